!> The two scenes of Yoo & Lee (2008) as first-order systems with any friction law.
!! State y = (x [m], v [m/s], z...): position and velocity, then the law's internal
!! states, if it has any (none for a static law: the scene is then exactly 2 states).
!!
!! - `slope_scene`: a box on a plane inclined theta, x along the slope (down positive),
!!   x'' = g sin(theta) - mu(x') g cos(theta). The mass cancels, so the scene has none.
!!   Relative velocity v; holding coefficient tan(theta).
!! - `belt_scene`: a mass m on a belt moving at v_b, tied to a wall by a spring k,
!!   m x'' = -k x + mu(v_b - x') m g. Relative velocity v_b - v; holding coefficient
!!   k x / (m g).
!! Both supply the analytic Jacobian for static laws (finite differences otherwise).
!!
!! For the nonsmooth methods each scene also gives its contact model (`contact_model`, the
!! interface of `stickslip_contact`), modelling only what it needs: `slope_contact`, one
!! coordinate per unit mass (forces in N/kg), and `belt_contact`, the mass on the spring.
module stickslip_scenes
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law
    use stickslip_ode, only: ode_system, fd_jacobian, BOUND_MARGIN
    use stickslip_contact, only: contact_system, contact_law, contact_law_of
    use stickslip_roots, only: root_search
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: friction_scene, slope_scene, belt_scene, slope_contact, belt_contact

    integer, parameter, public :: SS_BAD_M = -111       !! m out of range
    integer, parameter, public :: SS_BAD_G = -112       !! g out of range
    integer, parameter, public :: SS_BAD_THETA = -113   !! theta_deg out of range
    integer, parameter, public :: SS_BAD_K = -114       !! k out of range
    integer, parameter, public :: SS_BAD_V_B = -115     !! v_b not finite

    !> The scenes' parameters with the paper's values (Table 1) and ours where it is silent.
    type(param_spec), parameter, public :: G_SPEC = param_spec(name='g', default=9.81_dp, &
        unit='m/s^2', lo=0.0_dp, code=SS_BAD_G, doc='gravity')
    type(param_spec), parameter, public :: THETA_SPEC = param_spec(name='theta_deg', default=10.0_dp, &
        unit='deg', lo=-90.0_dp, hi=90.0_dp, code=SS_BAD_THETA, doc='slope inclination')
    !! slope inclination theta_deg in [-90, 90] [deg]
    type(param_spec), parameter, public :: M_SPEC = param_spec(name='m', default=10.0_dp, &
        unit='kg', lo=0.0_dp, lo_open=.true., code=SS_BAD_M, doc='mass')
    !! mass m, > 0 [kg]
    type(param_spec), parameter, public :: K_SPEC = param_spec(name='k', default=300.0_dp, &
        unit='N/m', lo=0.0_dp, code=SS_BAD_K, doc='spring stiffness')
    !! spring stiffness k, >= 0 [N/m]
    type(param_spec), parameter, public :: V_B_SPEC = param_spec(name='v_b', default=1.5_dp, &
        unit='m/s', code=SS_BAD_V_B, doc='belt speed')
    !! belt speed v_b, finite [m/s]

    real(dp), parameter :: deg = acos(-1.0_dp) / 180.0_dp


    !> What both scenes share: the law, its number of internal states, and the
    !! relative velocity.
    type, abstract, extends(ode_system) :: friction_scene
        class(friction_law), allocatable :: law   !! friction between the body and its support
        integer :: nz = 0                         !! internal states of the law
        logical :: static_law = .true.            !! the law depends on v alone
    contains
        !> Dimension of the state: 2 + the law's internal states.
        procedure :: n_states => scene_n_states
        !> Relative sliding velocity [m/s] at state y.
        procedure(vrel_iface), deferred :: relative_velocity
        !> Position [m] and velocity [m/s] of the monitored body: the one whose contact
        !! `relative_velocity` reads (the only body; block 1 on the chain).
        procedure :: monitored_body => scene_monitored_body
        !> The law's internal states, when the law solves their stage itself (`stage_states`).
        procedure :: condensed_components => scene_condensed_components
        !> The internal states' part of a stage from the law's `stage_states` at the stage's
        !! relative velocity.
        procedure :: condense_stage => scene_condense_stage
        !> f at a stage state with the law's states moving at the stage's rates.
        procedure :: stage_rhs => scene_stage_rhs
        !> A static law's stage as one scalar equation in the stage velocity, bracketed.
        procedure :: scalar_stage => scene_scalar_stage
        !> The analytic 2 x 2 Jacobian of the scene with a static law.
        procedure(static_jacobian_iface), deferred :: static_jacobian
        !> The Jacobian: analytic for a static law, finite differences otherwise.
        procedure :: jacobian => scene_jacobian
        !> The scene as a system with a set-valued contact (`stickslip_contact`); SS_NOT_SETVALUED
        !! when its law has no set-valued counterpart.
        procedure(contact_model_iface), deferred :: contact_model
        !> (x, v)' given the friction coefficient mu (affine in mu).
        procedure(static_rhs_iface), deferred :: static_rhs
        !> Holding coefficient mu_hold [-] at state y (see `stickslip_friction`).
        procedure(mu_hold_iface), deferred :: holding_coefficient
        !> Set the velocity of state y so that its relative sliding velocity is w [m/s].
        procedure(set_vrel_iface), deferred :: set_relative_velocity
        !> A bound on |mu| [-] while the relative speed stays below v_ref: the static and
        !! kinetic levels and the law's steady curve at +-v_ref (its viscous part).
        procedure, non_overridable :: mu_bound => scene_mu_bound
    end type friction_scene

    !> The slope with a set-valued contact, per unit mass: q = x [m], u = v [m/s], M = 1,
    !! f = g sin(theta) [N/kg], N = g cos(theta) [N/kg], w = v.
    type, extends(contact_system) :: slope_contact
        real(dp) :: g_sin = 0.0_dp    !! g sin(theta) [m/s^2]
        real(dp) :: g_cos = 0.0_dp    !! g cos(theta) [m/s^2]
    contains
        procedure :: force => slope_contact_force
        !! f = g sin(theta)
        procedure :: solve_w => slope_contact_solve_w
        !! W = 1
        procedure :: normal_forces => slope_contact_normal
        !! N = g cos(theta)
    end type slope_contact

    !> The belt with a set-valued contact: q = x [m], u = v [m/s], M = m [kg], f = -k x [N],
    !! N = m g [N], w = v - v_b (the body's velocity relative to the belt).
    type, extends(contact_system) :: belt_contact
        real(dp) :: m = 10.0_dp       !! mass [kg]
        real(dp) :: k = 300.0_dp      !! spring stiffness [N/m]
        real(dp) :: mg = 98.1_dp      !! normal force m g [N]
        real(dp) :: v_b = 1.5_dp      !! belt speed [m/s]
    contains
        procedure :: force => belt_contact_force
        !! f = -k x
        procedure :: solve_w => belt_contact_solve_w
        !! W = m + b k
        procedure :: normal_forces => belt_contact_normal
        !! N = m g
        procedure :: slip_offset => belt_contact_offset
        !! b = -v_b
    end type belt_contact

    abstract interface
        pure function vrel_iface(self, y) result(vr)
            import :: friction_scene, dp
            class(friction_scene), intent(in) :: self
            real(dp), intent(in) :: y(:)    !! state (x, v, z...)
            real(dp) :: vr                  !! relative sliding velocity [m/s]
        end function vrel_iface

        subroutine contact_model_iface(self, cs, status)
            import :: friction_scene, contact_system
            class(friction_scene), intent(in) :: self
            class(contact_system), allocatable, intent(out) :: cs  !! the contact model
            integer, intent(out) :: status                         !! SS_OK or SS_NOT_SETVALUED
        end subroutine contact_model_iface
        pure subroutine static_rhs_iface(self, y, mu, dydt)
            import :: friction_scene, dp
            class(friction_scene), intent(in) :: self
            real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s])
            real(dp), intent(in)  :: mu         !! friction coefficient [-]
            real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2])
        end subroutine static_rhs_iface

        pure function mu_hold_iface(self, y) result(mu_hold)
            import :: friction_scene, dp
            class(friction_scene), intent(in) :: self
            real(dp), intent(in) :: y(:)    !! state (x, v, z...)
            real(dp) :: mu_hold             !! coefficient that would hold the relative velocity [-]
        end function mu_hold_iface

        pure subroutine set_vrel_iface(self, y, w)
            import :: friction_scene, dp
            class(friction_scene), intent(in) :: self
            real(dp), intent(inout) :: y(:) !! state (x, v, z...); v set on exit
            real(dp), intent(in) :: w       !! the relative sliding velocity wanted [m/s]
        end subroutine set_vrel_iface

        pure function static_jacobian_iface(self, y) result(j)
            import :: friction_scene, dp
            class(friction_scene), intent(in) :: self
            real(dp), intent(in) :: y(:)    !! state (x [m], v [m/s])
            real(dp) :: j(2, 2)             !! d(v, a)/d(x, v)
        end function static_jacobian_iface
    end interface

    !> Box on an inclined plane.
    type, extends(friction_scene) :: slope_scene
        real(dp) :: g_sin = 0.0_dp    !! g sin(theta) [m/s^2]
        real(dp) :: g_cos = 0.0_dp    !! g cos(theta) [m/s^2]
        real(dp) :: mu_hold = 0.0_dp  !! tan(theta) [-]
    contains
        procedure :: init => slope_init
        !! validate and store the parameters and the law
        procedure :: rhs => slope_rhs
        !! (x, v, law states)' at (t, y)
        procedure :: static_jacobian => slope_static_jacobian
        !! the analytic 2 x 2 Jacobian with a static law
        procedure :: static_rhs => slope_static_rhs
        !! (x, v)' for a static law, given its coefficient at the relative velocity
        procedure :: relative_velocity => slope_vrel
        !! the sliding velocity the law sees [m/s]
        procedure :: contact_model => slope_contact_model
        !! the slope as a `slope_contact`
        procedure :: holding_coefficient => slope_mu_hold
        !! tan(theta)
        procedure :: set_relative_velocity => slope_set_vrel
        !! v = w
        procedure :: state_bound => slope_state_bound
        !! BOUND_MARGIN times the speed and travel that gravity and friction allow
    end type slope_scene

    !> Spring-mass on a moving belt.
    type, extends(friction_scene) :: belt_scene
        real(dp) :: k_m = 0.0_dp      !! k / m [1/s^2]
        real(dp) :: g = 9.81_dp       !! gravity [m/s^2]
        real(dp) :: v_b = 1.5_dp      !! belt speed [m/s]
        real(dp) :: k_mg = 0.0_dp     !! k / (m g), holding coefficient per metre [1/m]
    contains
        procedure :: init => belt_init
        !! validate and store the parameters and the law
        procedure :: rhs => belt_rhs
        !! (x, v, law states)' at (t, y)
        procedure :: static_jacobian => belt_static_jacobian
        !! the analytic 2 x 2 Jacobian with a static law
        procedure :: static_rhs => belt_static_rhs
        !! (x, v)' for a static law, given its coefficient at the relative velocity
        procedure :: relative_velocity => belt_vrel
        !! the sliding velocity the law sees [m/s]
        procedure :: contact_model => belt_contact_model
        !! the belt as a `belt_contact`
        procedure :: holding_coefficient => belt_mu_hold
        !! k x / (m g)
        procedure :: set_relative_velocity => belt_set_vrel
        !! v = v_b - w
        procedure :: state_bound => belt_state_bound
        !! BOUND_MARGIN times the energy bound of the mass on its spring
    end type belt_scene

contains

    !> max(mu_s, mu_k, |mu(v_ref)|, |mu(-v_ref)|) [-] of the scene's law.
    function scene_mu_bound(self, v_ref) result(mu_max)
        class(friction_scene), intent(in) :: self
        real(dp), intent(in) :: v_ref       !! largest relative speed [m/s]
        real(dp) :: mu_max                  !! bound on |mu| [-]
        mu_max = max(self%law%mu_s, self%law%mu_k, abs(self%law%mu(v_ref)), abs(self%law%mu(-v_ref)))
    end function scene_mu_bound

    !> The slope's bounds on |y|: with |mu| <= mu_max the acceleration is at most
    !! a = g (|sin theta| + mu_max cos theta), so |v| <= V = |v0| + a T and
    !! |x| <= |x0| + V T over T = t_end - t0; a law's states (bristle deflections) move at
    !! most twice the sliding speed, |z| <= max |z0| + 2 V T. BOUND_MARGIN times these.
    function slope_state_bound(self, t0, y0, t_end) result(bound)
        class(slope_scene), intent(in) :: self
        real(dp), intent(in) :: t0          !! initial time [s]
        real(dp), intent(in) :: y0(:)       !! initial state (x [m], v [m/s], z...)
        real(dp), intent(in) :: t_end       !! final time [s]
        real(dp) :: bound(size(y0))         !! bounds on |x| [m], |v| [m/s], |z| [m]
        real(dp) :: tt, a, vmax
        bound = huge(1.0_dp)
        if (size(y0) < 2) return     ! not this scene's state: the methods refuse it
        tt = max(t_end - t0, 0.0_dp)
        a = abs(self%g_sin) + self%g_cos * max(self%law%mu_s, self%law%mu_k)
        a = abs(self%g_sin) + self%g_cos * self%mu_bound(abs(y0(2)) + a * tt)
        vmax = abs(y0(2)) + a * tt
        bound(1) = BOUND_MARGIN * (abs(y0(1)) + vmax * tt)
        bound(2) = BOUND_MARGIN * vmax
        if (size(y0) > 2) bound(3:) = BOUND_MARGIN * (maxval(abs(y0(3:))) + 2.0_dp * vmax * tt)
    end function slope_state_bound

    !> The belt's bounds on |y| from the energy per unit mass E = (v^2 + (k/m) x^2)/2: friction
    !! (|mu| <= mu_max) changes sqrt(2E) by at most g mu_max a second, so sqrt(2E) <= R =
    !! sqrt(v0^2 + (k/m) x0^2) + g mu_max T over T = t_end - t0, |v| <= R (+ |v_b|) and
    !! |x| <= R / sqrt(k/m) (|x0| + R T without a spring); a law's states move at most twice
    !! the relative speed, |z| <= max |z0| + 2 (R + |v_b|) T. BOUND_MARGIN times these.
    function belt_state_bound(self, t0, y0, t_end) result(bound)
        class(belt_scene), intent(in) :: self
        real(dp), intent(in) :: t0          !! initial time [s]
        real(dp), intent(in) :: y0(:)       !! initial state (x [m], v [m/s], z...)
        real(dp), intent(in) :: t_end       !! final time [s]
        real(dp) :: bound(size(y0))         !! bounds on |x| [m], |v| [m/s], |z| [m]
        real(dp) :: tt, r0, r
        bound = huge(1.0_dp)
        if (size(y0) < 2) return     ! not this scene's state: the methods refuse it
        tt = max(t_end - t0, 0.0_dp)
        r0 = sqrt(y0(2)**2 + self%k_m * y0(1)**2)
        r = abs(self%v_b) + r0 + self%g * max(self%law%mu_s, self%law%mu_k) * tt
        r = r0 + self%g * self%mu_bound(r) * tt
        if (self%k_m > 0.0_dp) then
            bound(1) = BOUND_MARGIN * r / sqrt(self%k_m)
        else
            bound(1) = BOUND_MARGIN * (abs(y0(1)) + (r + abs(self%v_b)) * tt)
        end if
        bound(2) = BOUND_MARGIN * (r + abs(self%v_b))
        if (size(y0) > 2) bound(3:) = BOUND_MARGIN * (maxval(abs(y0(3:))) + 2.0_dp * (r + abs(self%v_b)) * tt)
    end function belt_state_bound

    pure integer function scene_n_states(self)
        class(friction_scene), intent(in) :: self
        scene_n_states = 2 + self%nz
    end function scene_n_states

    !> The stage k = f(t, u + c k) of a static law (state (x, v), x' = v) as one equation in
    !! the stage velocity v_s: x_s = u_x + c v_s and phi(v_s) = v_s - u_v - c a(t, x_s, v_s) = 0.
    !! phi is continuous where f is (the proposed law's mu ~ |w|^(1/3) has an infinite slope at
    !! w = 0, where Newton's method cycles), so a sign change is bracketed, from v_s = u_v
    !! outwards in steps that double, and closed by Illinois regula falsi with bisection to
    !! rounding. k = (v_s, (v_s - u_v) / c): the root's own acceleration, not f at the root,
    !! which at the cusp jumps between the two floats that hold the root. ok = .false. for a
    !! law with internal states, or when no bracket is found within 1e6 (1 + |u_v| + |phi(u_v)|).
    subroutine scene_scalar_stage(self, t, u, c, k, nfev, ok)
        class(friction_scene), intent(inout) :: self
        real(dp), intent(in)    :: t        !! stage time [s]
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative: a guess in, the solution out
        integer(8), intent(inout) :: nfev   !! evaluations of f, counted
        logical, intent(out)    :: ok       !! .true.: k solves the stage
        type(root_search) :: search
        ok = .false.
        if (self%nz /= 0 .or. size(u) /= 2) return
        call search%start(u(2))
        do while (.not. search%done)
            call search%tell(phi(search%x))
        end do
        if (search%found) call finish(search%root)
    contains
        !> phi(v_s) [m/s]
        real(dp) function phi(vs)
            real(dp), intent(in) :: vs
            real(dp) :: ys(2), f(2)
            ys = [u(1) + c * vs, vs]
            call self%rhs(t, ys, f)
            nfev = nfev + 1
            phi = vs - u(2) - c * f(2)
        end function phi
        subroutine finish(vs)
            real(dp), intent(in) :: vs
            real(dp) :: ys(2), f(2)
            ys = [u(1) + c * vs, vs]
            call self%rhs(t, ys, f)
            nfev = nfev + 1
            k = [f(1), (vs - u(2)) / c]   ! the root's own acceleration (notes)
            ok = all(ieee_is_finite(k))
        end subroutine finish
    end subroutine scene_scalar_stage

    !> The states z (components 3 ..) of a one-contact scene whose law condenses them.
    subroutine scene_condensed_components(self, mask)
        class(friction_scene), intent(in) :: self
        logical, intent(out) :: mask(:)     !! (2 + nz) .true. for the law's states
        mask = .false.
        if (self%law%condenses_states()) mask(3:) = .true.
    end subroutine scene_condensed_components

    !> k(3:) = (z_s - u(3:)) / c with z_s the law's stage states at the relative velocity of
    !! the stage state u + c k (its x and v read from k(1:2)).
    subroutine scene_condense_stage(self, u, c, k)
        class(friction_scene), intent(inout) :: self
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative; its states' part on exit
        real(dp) :: ys(size(u)), z_s(size(u) - 2)
        if (.not. self%law%condenses_states() .or. c <= 0.0_dp) return
        ys = u + c * k
        call self%law%stage_states(self%relative_velocity(ys), u(3:), c, z_s)
        k(3:) = (z_s - u(3:)) / c
    end subroutine scene_condense_stage

    !> f at the stage state y of a one-contact scene: the law's states move at the rates k(3:)
    !! of the stage (condense_stage), and mu is the law's at those rates (`stage_mu`).
    subroutine scene_stage_rhs(self, t, y, k, f)
        class(friction_scene), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! stage state (x [m], v [m/s], z)
        real(dp), intent(in)  :: k(:)       !! stage derivative (k(3:) read)
        real(dp), intent(out) :: f(:)       !! (v [m/s], acceleration [m/s^2], z rates)
        if (.not. self%law%condenses_states()) then
            call self%rhs(t, y, f)
            return
        end if
        call self%static_rhs(y, self%law%stage_mu(self%relative_velocity(y), y(3:), k(3:)), f)
        f(3:) = k(3:)
    end subroutine scene_stage_rhs

    pure function scene_monitored_body(self, y) result(xv)
        class(friction_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)    !! state (x [m], v [m/s], internal states)
        real(dp) :: xv(2)               !! (x [m], v [m/s]) of the body
        xv = y(1:2)
    end function scene_monitored_body

    !> Take the law (a validated one) and record its states.
    subroutine set_law(self, law)
        class(friction_scene), intent(inout) :: self
        class(friction_law), intent(in) :: law
        if (allocated(self%law)) deallocate(self%law)
        allocate(self%law, source=law)
        self%nz = law%n_states()
        self%static_law = law%is_static()
    end subroutine set_law

    !> Fill a slope scene from g and theta_deg in p; SS_OK or the code of the bad parameter.
    function slope_init(self, law, p) result(status)
        class(slope_scene), intent(inout) :: self
        class(friction_law), intent(in) :: law  !! a validated friction law
        type(param_values), intent(in) :: p     !! resolved parameter values
        integer :: status
        real(dp) :: g, theta_deg
        status = SS_OK
        call param_read(p, G_SPEC, g, status)
        call param_read(p, THETA_SPEC, theta_deg, status)
        if (status /= SS_OK) return
        call set_law(self, law)
        self%g_sin = g * sin(theta_deg * deg)
        self%g_cos = g * cos(theta_deg * deg)
        self%mu_hold = 0.0_dp
        if (self%g_cos > 0.0_dp) self%mu_hold = self%g_sin / self%g_cos
    end function slope_init

    !> Fill a belt scene from m, g, k, v_b in p; SS_OK or the code of the bad parameter.
    function belt_init(self, law, p) result(status)
        class(belt_scene), intent(inout) :: self
        class(friction_law), intent(in) :: law  !! a validated friction law
        type(param_values), intent(in) :: p     !! resolved parameter values
        integer :: status
        real(dp) :: m, k
        status = SS_OK
        call param_read(p, M_SPEC, m, status)
        call param_read(p, G_SPEC, self%g, status)
        call param_read(p, K_SPEC, k, status)
        call param_read(p, V_B_SPEC, self%v_b, status)
        if (status /= SS_OK) return
        call set_law(self, law)
        self%k_m = k / m
        self%k_mg = 0.0_dp
        if (self%g > 0.0_dp) self%k_mg = self%k_m / self%g
    end function belt_init

    subroutine slope_rhs(self, t, y, dydt)
        class(slope_scene), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s] (unused: autonomous)
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s], z...)
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2], z rates)
        real(dp) :: mu
        if (self%static_law) then
            call self%static_rhs(y, self%law%mu(self%relative_velocity(y)), dydt)
        else
            dydt(1) = y(2)
            call law_with_states(self, y(2), self%holding_coefficient(y), y, dydt, mu)
            ! c (mu_hold - mu), so that mu = mu_hold (a stick band) holds v exactly, not to rounding
            dydt(2) = merge(self%g_cos * (self%mu_hold - mu), self%g_sin - mu * self%g_cos, self%g_cos > 0.0_dp)
        end if
    end subroutine slope_rhs

    subroutine belt_rhs(self, t, y, dydt)
        class(belt_scene), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s] (unused: autonomous)
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s], z...)
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2], z rates)
        real(dp) :: mu
        if (self%static_law) then
            call self%static_rhs(y, self%law%mu(self%relative_velocity(y)), dydt)
        else
            call law_with_states(self, self%v_b - y(2), self%holding_coefficient(y), y, dydt, mu)
            dydt(1) = y(2)
            dydt(2) = -self%k_m * y(1) + mu * self%g
        end if
    end subroutine belt_rhs

    !> The slope's (x, v)' for a static law: the one place of its physics that the
    !! integrators' specialised kernels share with `rhs`.
    pure subroutine slope_static_rhs(self, y, mu, dydt)
        class(slope_scene), intent(in) :: self
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s])
        real(dp), intent(in)  :: mu         !! the law's coefficient at the relative velocity [-]
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2])
        dydt(1) = y(2)
        dydt(2) = self%g_sin - mu * self%g_cos
    end subroutine slope_static_rhs

    !> The belt's (x, v)' for a static law: the one place of its physics that the
    !! integrators' specialised kernels share with `rhs`.
    pure subroutine belt_static_rhs(self, y, mu, dydt)
        class(belt_scene), intent(in) :: self
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s])
        real(dp), intent(in)  :: mu         !! the law's coefficient at the relative velocity [-]
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2])
        dydt(1) = y(2)
        dydt(2) = -self%k_m * y(1) + mu * self%g
    end subroutine belt_static_rhs

    !> mu and the internal-state rates dydt(3:) of a law that is not static (kept out of
    !! the right-hand sides so that their static path stays short).
    subroutine law_with_states(self, v, mu_hold, y, dydt, mu)
        class(friction_scene), intent(inout) :: self
        real(dp), intent(in)    :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in)    :: mu_hold    !! coefficient that would hold v constant [-]
        real(dp), intent(in)    :: y(:)       !! state (x, v, z...)
        real(dp), intent(inout) :: dydt(:)    !! derivative; dydt(3:) set here
        real(dp), intent(out)   :: mu         !! friction coefficient [-]
        call self%law%evaluate(v, y(3:), mu_hold, mu, dydt(3:))
    end subroutine law_with_states

    !> The analytic Jacobian for a static law (the scene's `static_jacobian`), finite
    !! differences otherwise (a law with states or a stick band).
    subroutine scene_jacobian(self, t, y, f, dfdy, nfev)
        class(friction_scene), intent(inout) :: self
        real(dp), intent(in)    :: t             !! time [s]
        real(dp), intent(in)    :: y(:)          !! state
        real(dp), intent(in)    :: f(:)          !! f(t, y)
        real(dp), intent(out)   :: dfdy(:, :)    !! (n, n) Jacobian
        integer(8), intent(inout) :: nfev        !! evaluation counter (+ n for finite differences)
        if (self%static_law) then
            dfdy = self%static_jacobian(y)
        else
            call fd_jacobian(self, t, y, f, dfdy, nfev)
        end if
    end subroutine scene_jacobian

    pure function slope_static_jacobian(self, y) result(j)
        class(slope_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)     !! state (x [m], v [m/s])
        real(dp) :: j(2, 2)              !! d(v, a)/d(x, v)
        j(:, 1) = 0.0_dp
        j(1, 2) = 1.0_dp
        j(2, 2) = -self%g_cos * self%law%dmu(y(2))
    end function slope_static_jacobian

    pure function belt_static_jacobian(self, y) result(j)
        class(belt_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)     !! state (x [m], v [m/s])
        real(dp) :: j(2, 2)              !! d(v, a)/d(x, v)
        j(1, 1) = 0.0_dp
        j(2, 1) = -self%k_m
        j(1, 2) = 1.0_dp
        j(2, 2) = -self%g * self%law%dmu(self%v_b - y(2))
    end function belt_static_jacobian

    pure function slope_vrel(self, y) result(vr)
        class(slope_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)    !! state (x, v, z...)
        real(dp) :: vr                  !! relative sliding velocity v [m/s]
        vr = y(2)
    end function slope_vrel

    pure function belt_vrel(self, y) result(vr)
        class(belt_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)    !! state (x, v, z...)
        real(dp) :: vr                  !! relative sliding velocity v_b - v [m/s]
        vr = self%v_b - y(2)
    end function belt_vrel

    !> One contact on coordinate 1 with H = [1] and the scene law's set-valued counterpart.
    subroutine one_contact(cs, law, status)
        class(contact_system), intent(inout) :: cs  !! the model being built
        class(friction_law), intent(in) :: law      !! the scene's law
        integer, intent(out) :: status              !! SS_OK or SS_NOT_SETVALUED
        type(contact_law) :: cl
        call contact_law_of(law, cl, status)
        cs%n_dof = 1
        cs%n_c = 1
        cs%h_ptr = [1, 2]
        cs%h_col = [1]
        cs%h_val = [1.0_dp]
        cs%laws = [cl]
        cs%w_constant = .true.
    end subroutine one_contact

    subroutine slope_contact_model(self, cs, status)
        class(slope_scene), intent(in) :: self
        class(contact_system), allocatable, intent(out) :: cs  !! a slope_contact
        integer, intent(out) :: status                         !! SS_OK or SS_NOT_SETVALUED
        type(slope_contact) :: sc
        sc%g_sin = self%g_sin
        sc%g_cos = self%g_cos
        call one_contact(sc, self%law, status)
        if (status == SS_OK) allocate(cs, source=sc)
    end subroutine slope_contact_model

    subroutine belt_contact_model(self, cs, status)
        class(belt_scene), intent(in) :: self
        class(contact_system), allocatable, intent(out) :: cs  !! a belt_contact
        integer, intent(out) :: status                         !! SS_OK or SS_NOT_SETVALUED
        type(belt_contact) :: bc
        ! The scene keeps k/m and g; with the mass set to 1 the model is per unit mass
        ! (forces in N/kg), which changes nothing in the motion.
        bc%m = 1.0_dp
        bc%k = self%k_m
        bc%mg = self%g
        bc%v_b = self%v_b
        call one_contact(bc, self%law, status)
        if (status == SS_OK) allocate(cs, source=bc)
    end subroutine belt_contact_model

    subroutine slope_contact_force(self, t, q, u, f)
        class(slope_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! position x [m]
        real(dp), intent(in)  :: u(:)       !! velocity v [m/s]
        real(dp), intent(out) :: f(:)       !! g sin(theta) [N/kg]
        f(1) = self%g_sin
    end subroutine slope_contact_force

    subroutine slope_contact_solve_w(self, t, q, u, a, b, x)
        class(slope_contact), intent(in) :: self
        real(dp), intent(in)    :: t        !! time [s]
        real(dp), intent(in)    :: q(:)     !! position [m]
        real(dp), intent(in)    :: u(:)     !! velocity [m/s]
        real(dp), intent(in)    :: a        !! weight of C [s] (C = 0)
        real(dp), intent(in)    :: b        !! weight of K [s^2] (K = 0)
        real(dp), intent(inout) :: x(:)     !! unchanged: W = M = 1
    end subroutine slope_contact_solve_w

    subroutine slope_contact_normal(self, t, q, n)
        class(slope_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! position [m]
        real(dp), intent(out) :: n(:)       !! g cos(theta) [N/kg]
        n(1) = max(self%g_cos, 0.0_dp)
    end subroutine slope_contact_normal

    subroutine belt_contact_force(self, t, q, u, f)
        class(belt_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! position x [m]
        real(dp), intent(in)  :: u(:)       !! velocity v [m/s]
        real(dp), intent(out) :: f(:)       !! spring force -k x [N]
        f(1) = -self%k * q(1)
    end subroutine belt_contact_force

    subroutine belt_contact_solve_w(self, t, q, u, a, b, x)
        class(belt_contact), intent(in) :: self
        real(dp), intent(in)    :: t        !! time [s]
        real(dp), intent(in)    :: q(:)     !! position [m]
        real(dp), intent(in)    :: u(:)     !! velocity [m/s]
        real(dp), intent(in)    :: a        !! weight of C [s] (C = 0)
        real(dp), intent(in)    :: b        !! weight of K = k [s^2]
        real(dp), intent(inout) :: x(:)     !! right-hand side [N s], then x / (m + b k) [m/s]
        x(1) = x(1) / (self%m + b * self%k)
    end subroutine belt_contact_solve_w

    subroutine belt_contact_normal(self, t, q, n)
        class(belt_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! position [m]
        real(dp), intent(out) :: n(:)       !! m g [N]
        n(1) = self%mg
    end subroutine belt_contact_normal

    subroutine belt_contact_offset(self, t, b)
        class(belt_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(out) :: b(:)       !! -v_b [m/s]
        b(1) = -self%v_b
    end subroutine belt_contact_offset
    pure function slope_mu_hold(self, y) result(mu_hold)
        class(slope_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)    !! state (x, v, z...) (not read)
        real(dp) :: mu_hold             !! tan(theta) [-]
        mu_hold = self%mu_hold
    end function slope_mu_hold

    pure function belt_mu_hold(self, y) result(mu_hold)
        class(belt_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)    !! state (x, v, z...)
        real(dp) :: mu_hold             !! k x / (m g) [-]
        mu_hold = self%k_mg * y(1)
    end function belt_mu_hold

    pure subroutine slope_set_vrel(self, y, w)
        class(slope_scene), intent(in) :: self
        real(dp), intent(inout) :: y(:) !! state; y(2) = w on exit
        real(dp), intent(in) :: w       !! relative sliding velocity [m/s]
        y(2) = w
    end subroutine slope_set_vrel

    pure subroutine belt_set_vrel(self, y, w)
        class(belt_scene), intent(in) :: self
        real(dp), intent(inout) :: y(:) !! state; y(2) = v_b - w on exit
        real(dp), intent(in) :: w       !! relative sliding velocity [m/s]
        y(2) = self%v_b - w
    end subroutine belt_set_vrel

end module stickslip_scenes
