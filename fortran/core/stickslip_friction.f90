!> The abstract friction law that every law of the library extends, one law per module
!! (`stickslip_law_coulomb`, `stickslip_law_recurdyn`, `stickslip_law_proposed`, ...).
!!
!! Conventions. v is the relative sliding velocity [m/s]; a law returns the friction
!! coefficient mu [-], odd in v, so that the friction force is mu(v) N with the sign
!! already applied. A scene writes the rate of its relative velocity as
!! dv/dt = c (mu_hold - mu), c > 0: `mu_hold` [-] is the coefficient that would hold the
!! relative velocity constant (the non-friction force in units of the normal force). Laws
!! with a stick band (Karnopp) need it; the others ignore it.
!!
!! A law with internal states (a bristle deflection z, ...) reports how many it has,
!! their names and units, and their rates; the scene appends them to its state vector
!! (x, v, z...). A law without states adds nothing.
!!
!! A law whose graph mu(v) jumps (Coulomb's at v = 0 and v_s, Karnopp's at the band edges)
!! can describe it as finitely many modes (`n_modes`, `mode`, `admits`): each a slip piece
!! with a constant coefficient, or a point of the velocity axis where mu may take any value of
!! an interval (the jump filled in: set-valued), or Karnopp's hold (mu = mu_hold, the relative
!! velocity kept). The fixed-step implicit methods then solve each stage as a generalized
!! equation over those modes instead of by Newton across the jump (see
!! `stickslip_fixed_implicit`). A law with a Lipschitz graph has no modes (the default).
!!
!! A law may also have a set-valued counterpart (`set_valued`, a `contact_law`): its graph with
!! the static set at rest exact (stick up to mu_s, no regularisation) and a slip curve mu(s) for
!! s = |v| > 0, which the nonsmooth methods' contact solver (`stickslip_contact_solver`) reads.
!! Coulomb and Karnopp give set-valued Coulomb (mu_s, mu_k), Stribeck its curve without the tanh
!! ramp; a law without one (the default) gives SS_NOT_SETVALUED. So each law describes itself
!! once, here: regularised (`mu`), set-valued (`set_valued`) and its modes (`mode`, `admits`).
!!
!! A law reads its parameters by name from a resolved `param_values` set (see
!! `stickslip_params`); the parameters every law shares (mu_s, mu_k, v_s) are declared
!! here once.
module stickslip_friction
    use stickslip_kinds, only: dp, SS_OK, SS_NEWTON_FAILED, SS_SINGULAR, SS_NOT_SETVALUED
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_linalg, only: lu_decompose, lu_solve
    implicit none
    private

    public :: friction_law, havsin, havsin_slope, between, tr_bdf2_advance, relax_linear_target
    public :: contact_law, stribeck_curve, stribeck_curve_slope

    !> Relative slack of a mode's bounds in `between` [-] (a million units of round-off: the
    !! stage is solved to rounding, and a velocity or coefficient on a bound must count as on it).
    real(dp), parameter, public :: MODE_SLACK = 1.0e6_dp * epsilon(1.0_dp)

    real(dp), parameter :: pi = acos(-1.0_dp)

    !> Parameter codes of the shared friction parameters (stable: the C header lists them).
    integer, parameter, public :: SS_BAD_MU_S = -101   !! mu_s out of range
    integer, parameter, public :: SS_BAD_MU_K = -102   !! mu_k out of range or > mu_s
    integer, parameter, public :: SS_BAD_V_S = -103    !! v_s out of range

    integer, parameter, public :: CONTACT_COULOMB = 1    !! set-valued Coulomb (mu_s, mu_k)
    integer, parameter, public :: CONTACT_STRIBECK = 2   !! set-valued Stribeck curve

    !> Kinds of a law's mode (see `mode`).
    integer, parameter, public :: MODE_MU = 1     !! slip piece: mu = the mode's value
    integer, parameter, public :: MODE_V = 2      !! set-valued point: v = the mode's value, mu in an interval
    integer, parameter, public :: MODE_KEEP = 3   !! hold: the relative velocity kept, mu = mu_hold

    !> The parameters every law shares, with the paper's values (Table 1).
    type(param_spec), parameter, public :: MU_S_SPEC = param_spec(name='mu_s', default=0.35_dp, &
        lo=0.0_dp, code=SS_BAD_MU_S, doc='static friction coefficient')
    type(param_spec), parameter, public :: MU_K_SPEC = param_spec(name='mu_k', default=0.30_dp, &
        lo=0.0_dp, relation='<= mu_s', code=SS_BAD_MU_K, doc='kinetic friction coefficient')
    !! kinetic friction coefficient mu_k, <= mu_s [-]
    type(param_spec), parameter, public :: V_S_SPEC = param_spec(name='v_s', default=0.01_dp, &
        unit='m/s', lo=0.0_dp, lo_open=.true., code=SS_BAD_V_S, doc='static threshold velocity')
    !! static threshold velocity v_s, > 0 [m/s]

    !> The set-valued counterpart of a friction law (module notes): stick at rest with
    !! |mu| <= mu_s, slip at speed s > 0 with the coefficient `slip_mu`: Coulomb (mu_k at any
    !! speed) or the Stribeck curve mu(s) = mu_k + (mu_s - mu_k) exp(-(s/v_s)^delta) + c_v s
    !! (continuous at s = 0+ with the static limit mu_s, no tanh regularisation). The band of the
    !! paper's Coulomb law (mu_s for 0 < |v| < v_s) is a stand-in for the static set and has no
    !! counterpart here: v_s is not read by the set-valued Coulomb.
    type :: contact_law
        integer :: kind = CONTACT_COULOMB   !! CONTACT_COULOMB or CONTACT_STRIBECK
        real(dp) :: mu_s = 0.35_dp          !! static coefficient: stick up to mu_s N [-]
        real(dp) :: mu_k = 0.30_dp          !! kinetic coefficient [-]
        real(dp) :: v_s = 0.01_dp           !! Stribeck velocity (Stribeck only) [m/s]
        real(dp) :: delta = 2.0_dp          !! Stribeck shape exponent (Stribeck only) [-]
        real(dp) :: c_v = 0.0_dp            !! viscous coefficient (Stribeck only) [s/m]
    contains
        !> Coefficient in slip at speed s > 0 [-].
        procedure :: slip_mu
        !> d(slip_mu)/ds at s > 0 [s/m].
        procedure :: slip_dmu
    end type contact_law

    !> A friction law: mu as a function of the relative velocity (and of its internal
    !! states, if it has any).
    type, abstract :: friction_law
        real(dp) :: mu_s = 0.35_dp      !! static coefficient [-]
        real(dp) :: mu_k = 0.30_dp      !! kinetic coefficient [-]
        real(dp) :: v_s = 0.01_dp       !! static threshold velocity [m/s]
    contains
        !> Read and check the parameters; SS_OK or the code naming the bad one.
        procedure(init_iface), deferred :: init
        !> Read and check the shared parameters (for `init`).
        procedure, non_overridable :: read_shared
        !> Read and check mu_k and v_s of a law with one coefficient (for `init`; mu_s = mu_k).
        procedure, non_overridable :: read_kinetic
        !> mu(v) [-] for a law without states; the steady-state curve of a law with states.
        procedure(mu_iface), deferred :: mu
        !> d mu / d v [s/m] (the default is a central difference of `mu`).
        procedure :: dmu => central_dmu
        !> Number of internal states (0: a static law).
        procedure :: n_states => no_states
        !> Name and unit of internal state i, as 'z [m]'.
        procedure :: state_label => no_label
        !> .true. when mu depends on v alone, so scenes may call `mu` instead of `evaluate`.
        procedure :: is_static => static_law
        !> mu and the rates of the internal states at (v, z) with the holding coefficient.
        procedure :: evaluate => static_evaluate
        !> Number of modes of a law with a discontinuous graph (0: none, the default).
        procedure :: n_modes => no_modes
        !> Kind (MODE_MU, MODE_V, MODE_KEEP) and value (mu [-] or v [m/s]) of mode i.
        procedure :: mode => no_mode
        !> .true. when (v, mu_hold, mu) lies on mode i (the law's graph, jumps filled in).
        procedure :: admits => no_admits
        !> The law's set-valued counterpart (module notes): SS_OK, or SS_NOT_SETVALUED (the
        !! default: the law has none).
        procedure :: set_valued => kind_set_valued
        !> The kind of the law's set-valued counterpart (CONTACT_COULOMB: `set_valued` builds it
        !! from mu_s, mu_k); 0, the default: none.
        procedure :: set_valued_kind => no_set_valued_kind
        !> The coefficient the law selects at v given the holding coefficient: the element of
        !! its (filled-in) set at v nearest mu_hold (mu(v) where the law is single-valued).
        procedure :: mu_select => static_select
        !> Advance the internal states over a substep of prescribed motion: travel dx in a time
        !! h, the relative velocity going from v0 to v1 (same sign as dx, or 0): exact or
        !! exponential where a law overrides it, one TR-BDF2 step otherwise (`tr_bdf2_advance`).
        procedure :: advance => tr_bdf2_advance
        !> .true. when `stage_states` solves the states' stage equation (a law whose rates
        !! jump with the state, where Newton's method across the jump has no solution).
        procedure :: condenses_states => no_condensed_states
        !> The internal states' part of an implicit stage, z_s = z_u + c dz(v, z_s), solved for
        !! a given relative velocity v (the Filippov solution where the rate jumps); only for
        !! a law whose condenses_states is .true. (the default leaves z_s = z_u).
        procedure :: stage_states => no_stage_states
        !> mu [-] at v with states z moving at the rates dz (a condensed stage's rates, in
        !! place of `evaluate`'s, which jump); only for a law whose condenses_states is .true.
        !! (the default is mu(v)).
        procedure :: stage_mu => plain_stage_mu
        !> mu [-] at a sample of a prescribed motion, where the acceleration is known too: a
        !! law whose rates depend on how its thresholds move (GMS: an element on a rising slip
        !! level) classifies its states with it; the default is `evaluate`'s mu.
        procedure :: motion_mu => plain_motion_mu
    end type friction_law

    abstract interface
        function init_iface(self, p) result(status)
            import :: friction_law, param_values
            class(friction_law), intent(inout) :: self
            type(param_values), intent(in) :: p  !! resolved parameter values
            integer :: status
        end function init_iface

        elemental function mu_iface(self, v) result(mu)
            import :: friction_law, dp
            class(friction_law), intent(in) :: self
            real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
            real(dp) :: mu                      !! friction coefficient, odd in v [-]
        end function mu_iface
    end interface

contains

    !> Read and check mu_s, mu_k (<= mu_s) and v_s; extensions call it first from `init`.
    function read_shared(self, p) result(status)
        class(friction_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = SS_OK
        call param_read(p, MU_S_SPEC, self%mu_s, status)
        call param_read(p, MU_K_SPEC, self%mu_k, status)
        call param_read(p, V_S_SPEC, self%v_s, status)
        if (status == SS_OK .and. self%mu_k > self%mu_s) status = SS_BAD_MU_K
    end function read_shared

    !> Read and check mu_k and v_s of a law with one friction coefficient, whose static
    !! level is its kinetic one (mu_s is not read; the law's mu_s becomes mu_k, so that bounds
    !! taken from max(mu_s, mu_k) stay right); extensions call it first from `init`.
    function read_kinetic(self, p) result(status)
        class(friction_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = SS_OK
        call param_read(p, MU_K_SPEC, self%mu_k, status)
        call param_read(p, V_S_SPEC, self%v_s, status)
        self%mu_s = self%mu_k
    end function read_kinetic

    elemental function central_dmu(self, v) result(d)
        class(friction_law), intent(in) :: self
        real(dp), intent(in) :: v          !! relative sliding velocity [m/s]
        real(dp) :: d                      !! d mu / d v [s/m]
        real(dp) :: dv
        dv = 1.0e-6_dp * max(abs(v), self%v_s)
        d = (self%mu(v + dv) - self%mu(v - dv)) / (2.0_dp * dv)
    end function central_dmu

    pure integer function no_states(self)
        class(friction_law), intent(in) :: self
        no_states = 0
    end function no_states

    pure function no_label(self, i) result(label)
        class(friction_law), intent(in) :: self
        integer, intent(in) :: i           !! state index, 1 .. n_states
        character(len=:), allocatable :: label
        label = ''
    end function no_label

    pure logical function static_law(self)
        class(friction_law), intent(in) :: self
        static_law = .true.
    end function static_law

    pure logical function no_condensed_states(self)
        class(friction_law), intent(in) :: self
        no_condensed_states = .false.
    end function no_condensed_states

    pure real(dp) function plain_stage_mu(self, v, z, dz) result(mu)
        class(friction_law), intent(in) :: self
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: z(:)        !! internal states
        real(dp), intent(in) :: dz(:)       !! their rates
        mu = self%mu(v)
    end function plain_stage_mu

    pure subroutine no_stage_states(self, v, z_u, c, z_s)
        class(friction_law), intent(in) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity at the stage [m/s]
        real(dp), intent(in)  :: z_u(:)     !! the stage's base states (z_s = z_u + c dz)
        real(dp), intent(in)  :: c          !! coefficient of the rate [s]
        real(dp), intent(out) :: z_s(:)     !! the stage's states
        z_s = z_u
    end subroutine no_stage_states

    !> A static law: mu = mu(v), no states.
    subroutine plain_motion_mu(self, v, a, z, mu)
        class(friction_law), intent(inout) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in)  :: a          !! its rate [m/s^2] (unused)
        real(dp), intent(in)  :: z(:)       !! internal states (size n_states)
        real(dp), intent(out) :: mu         !! friction coefficient [-]
        real(dp) :: dz(size(z))
        call self%evaluate(v, z, 0.0_dp, mu, dz)
    end subroutine plain_motion_mu

    subroutine static_evaluate(self, v, z, mu_hold, mu, dz)
        class(friction_law), intent(inout) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in)  :: z(:)       !! internal states (size n_states)
        real(dp), intent(in)  :: mu_hold    !! coefficient that would hold v constant [-]
        real(dp), intent(out) :: mu         !! friction coefficient [-]
        real(dp), intent(out) :: dz(:)      !! rates of the internal states
        mu = self%mu(v)
    end subroutine static_evaluate

    pure integer function no_modes(self)
        class(friction_law), intent(in) :: self
        no_modes = 0
    end function no_modes

    pure subroutine no_mode(self, i, kind, value)
        class(friction_law), intent(in) :: self
        integer, intent(in) :: i            !! mode index, 1 .. n_modes
        integer, intent(out) :: kind        !! MODE_MU, MODE_V or MODE_KEEP
        real(dp), intent(out) :: value      !! mu [-] (MODE_MU), v [m/s] (MODE_V), 0 (MODE_KEEP)
        kind = MODE_MU
        value = 0.0_dp
    end subroutine no_mode

    pure logical function no_admits(self, i, v, mu_hold, mu)
        class(friction_law), intent(in) :: self
        integer, intent(in) :: i            !! mode index, 1 .. n_modes
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_hold     !! coefficient that would hold v constant [-]
        real(dp), intent(in) :: mu          !! friction coefficient [-]
        no_admits = .false.
    end function no_admits

    !> The set-valued counterpart of kind `set_valued_kind` with the law's mu_s, mu_k and v_s
    !! (Coulomb's: a law with more parameters, Stribeck, overrides this); SS_NOT_SETVALUED where
    !! the kind is 0 (cl then the default Coulomb).
    pure subroutine kind_set_valued(self, cl, status)
        class(friction_law), intent(in) :: self
        type(contact_law), intent(out) :: cl    !! the set-valued counterpart
        integer, intent(out) :: status          !! SS_OK or SS_NOT_SETVALUED
        status = SS_NOT_SETVALUED
        if (self%set_valued_kind() == 0) return
        cl = contact_law(kind=self%set_valued_kind(), mu_s=self%mu_s, mu_k=self%mu_k, v_s=self%v_s)
        status = SS_OK
    end subroutine kind_set_valued

    pure integer function no_set_valued_kind(self) result(kind)
        class(friction_law), intent(in) :: self
        kind = 0
    end function no_set_valued_kind

    elemental function slip_mu(self, s) result(mu)
        class(contact_law), intent(in) :: self
        real(dp), intent(in) :: s           !! sliding speed |w| > 0 [m/s]
        real(dp) :: mu                      !! friction coefficient in slip [-]
        if (self%kind == CONTACT_STRIBECK) then
            mu = stribeck_curve(s, self%mu_s, self%mu_k, self%v_s, self%delta) + self%c_v * s
        else
            mu = self%mu_k
        end if
    end function slip_mu

    elemental function slip_dmu(self, s) result(d)
        class(contact_law), intent(in) :: self
        real(dp), intent(in) :: s           !! sliding speed |w| > 0 [m/s]
        real(dp) :: d                       !! d mu / d s [s/m]
        if (self%kind == CONTACT_STRIBECK) then
            d = stribeck_curve_slope(s, self%mu_s, self%mu_k, self%v_s, self%delta) + self%c_v
        else
            d = 0.0_dp
        end if
    end function slip_dmu

    !> The Stribeck curve g(s) = mu_k + (mu_s - mu_k) exp(-(s/v_s)^delta) [-] at speed s >= 0.
    elemental function stribeck_curve(s, mu_s, mu_k, v_s, delta) result(g)
        real(dp), intent(in) :: s       !! sliding speed |v| [m/s]
        real(dp), intent(in) :: mu_s    !! static coefficient [-]
        real(dp), intent(in) :: mu_k    !! kinetic coefficient [-]
        real(dp), intent(in) :: v_s     !! Stribeck velocity [m/s]
        real(dp), intent(in) :: delta   !! shape exponent [-]
        real(dp) :: g
        g = mu_k + (mu_s - mu_k) * exp(-(s / v_s)**delta)
    end function stribeck_curve

    !> dg/ds [s/m] for s > 0 (infinite at s = 0 when delta < 1).
    elemental function stribeck_curve_slope(s, mu_s, mu_k, v_s, delta) result(d)
        real(dp), intent(in) :: s       !! sliding speed |v| > 0 [m/s]
        real(dp), intent(in) :: mu_s    !! static coefficient [-]
        real(dp), intent(in) :: mu_k    !! kinetic coefficient [-]
        real(dp), intent(in) :: v_s     !! Stribeck velocity [m/s]
        real(dp), intent(in) :: delta   !! shape exponent [-]
        real(dp) :: d                   !! dg/ds [s/m]
        d = -(mu_s - mu_k) * delta / v_s * (s / v_s)**(delta - 1.0_dp) * exp(-(s / v_s)**delta)
    end function stribeck_curve_slope

    pure function static_select(self, v, mu_hold) result(mu)
        class(friction_law), intent(in) :: self
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_hold     !! coefficient that would hold v constant [-]
        real(dp) :: mu                      !! friction coefficient [-]
        mu = self%mu(v)
    end function static_select

    !> .true. when x lies in the closed interval between a and b (either order), widened by
    !! MODE_SLACK: the test of a law's `admits` (a stage solved to rounding lands on a mode's
    !! edge to rounding).
    elemental logical function between(x, a, b)
        real(dp), intent(in) :: x, a, b
        !! x: the value; a, b: the ends of the interval, either order
        between = x >= min(a, b) - MODE_SLACK * (1.0_dp + abs(a)) .and. &
                  x <= max(a, b) + MODE_SLACK * (1.0_dp + abs(b))
    end function between

    !> One step of TR-BDF2 (Bank et al. 1985; Hosea & Shampine 1996: a trapezoidal stage to
    !! t + gamma h, gamma = 2 - sqrt(2), then BDF2; L-stable, order 2) on the internal states
    !! z' = f(v(t), z), f from `evaluate` (holding coefficient 0), with the velocity linear
    !! from v0 to v1 over the step (dx is not used). Each stage is solved by Newton iterations
    !! with a forward-difference Jacobian at every iterate (n evaluations each: the laws' rates
    !! may bend sharply, as the elasto-plastic attachment does). A law without states returns
    !! at once.
    subroutine tr_bdf2_advance(self, dx, h, v0, v1, z, status)
        class(friction_law), intent(inout) :: self   !! the law (its `evaluate` gives the rates)
        real(dp), intent(in)    :: dx       !! travel over the step [m] (unused)
        real(dp), intent(in)    :: h        !! step [s], >= 0
        real(dp), intent(in)    :: v0       !! relative velocity at the start [m/s]
        real(dp), intent(in)    :: v1       !! relative velocity at the end [m/s]
        real(dp), intent(inout) :: z(:)     !! internal states at the start; at the end on return
        integer, intent(out)    :: status   !! SS_OK, SS_NEWTON_FAILED or SS_SINGULAR
        real(dp), parameter :: gam = 2.0_dp - sqrt(2.0_dp), d = 0.5_dp * gam
        real(dp), parameter :: a_g = 1.0_dp / (gam * (2.0_dp - gam)), &
                               a_0 = (1.0_dp - gam)**2 / (gam * (2.0_dp - gam))
        integer, parameter :: max_iter = 20
        real(dp) :: f0(size(z)), f1(size(z)), fp(size(z)), zg(size(z)), w(size(z)), dz(size(z)), &
                    jac(size(z), size(z)), zp(size(z)), delta, mu, v
        integer :: ipiv(size(z)), n, j, it, info
        n = size(z)
        status = SS_OK
        if (n == 0 .or. h <= 0.0_dp) return
        call self%evaluate(v0, z, 0.0_dp, mu, f0)
        ! trapezoidal stage: zg = z + d h (f(z) + f(zg)), from the explicit Euler guess
        w = z + gam * h * f0
        v = v0 + gam * (v1 - v0)
        call solve_stage(z + d * h * f0)
        if (status /= SS_OK) return
        zg = w
        ! BDF2 stage: z1 = a_g zg - a_0 z + d h f(z1)
        v = v1
        call solve_stage(a_g * zg - a_0 * z)
        if (status /= SS_OK) return
        z = w
    contains
        !> w = rhs + d h f(v, w) by Newton from the current w.
        subroutine solve_stage(rhs)
            real(dp), intent(in) :: rhs(:)
            do it = 1, max_iter
                call self%evaluate(v, w, 0.0_dp, mu, f1)
                do j = 1, n
                    zp = w
                    delta = sqrt(epsilon(1.0_dp) * max(1.0e-5_dp, abs(w(j))))
                    zp(j) = w(j) + delta
                    call self%evaluate(v, zp, 0.0_dp, mu, fp)
                    jac(:, j) = -d * h * (fp - f1) / delta
                    jac(j, j) = jac(j, j) + 1.0_dp
                end do
                call lu_decompose(jac, ipiv, info)
                if (info /= 0) then
                    status = SS_SINGULAR
                    return
                end if
                dz = rhs + d * h * f1 - w
                call lu_solve(jac, ipiv, dz)
                w = w + dz
                if (all(abs(dz) <= 1.0e-12_dp * max(abs(w), abs(rhs), h * abs(f0)))) return
            end do
            status = SS_NEWTON_FAILED
        end subroutine solve_stage
    end subroutine tr_bdf2_advance

    !> y(1) of y' = lambda (L(t) - y) from y(0) = y0 with the target L linear from L0 to L1
    !! over the step and x = lambda h >= 0: L1 + (y0 - L0) e^-x - (L1 - L0)(1 - e^-x)/x (the
    !! first-order-hold exponential step; y0 at x = 0, L1 as x -> infinity).
    elemental function relax_linear_target(y0, l0, l1, x) result(y)
        real(dp), intent(in) :: y0      !! initial value
        real(dp), intent(in) :: l0      !! target at the start
        real(dp), intent(in) :: l1      !! target at the end
        real(dp), intent(in) :: x       !! lambda h, >= 0 [-]
        real(dp) :: y                   !! value at the end
        real(dp) :: e, phi
        e = exp(-x)
        if (x < 1.0e-4_dp) then
            phi = 1.0_dp - x * (0.5_dp - x / 6.0_dp)     ! (1 - e^-x)/x, without cancellation
        else
            phi = (1.0_dp - e) / x
        end if
        y = l1 + (y0 - l0) * e - (l1 - l0) * phi
    end function relax_linear_target

    !> Haversine step: h0 for x <= x0, h1 for x >= x1, and
    !! h0 + (h1 - h0) (1 - cos(pi (x - x0)/(x1 - x0)))/2 in between (needs x1 > x0).
    elemental function havsin(x, x0, h0, x1, h1) result(h)
        real(dp), intent(in) :: x, x0, h0, x1, h1
        !! x: abscissa; the step goes from h0 at x0 to h1 at x1 (x1 > x0)
        real(dp) :: h
        if (x <= x0) then
            h = h0
        else if (x >= x1) then
            h = h1
        else
            h = h0 + (h1 - h0) * 0.5_dp * (1.0_dp - cos(pi * (x - x0) / (x1 - x0)))
        end if
    end function havsin

    !> d havsin / d x.
    elemental function havsin_slope(x, x0, h0, x1, h1) result(d)
        real(dp), intent(in) :: x, x0, h0, x1, h1
        !! x: abscissa; the step goes from h0 at x0 to h1 at x1 (x1 > x0)
        real(dp) :: d
        if (x <= x0 .or. x >= x1) then
            d = 0.0_dp
        else
            d = (h1 - h0) * 0.5_dp * sin(pi * (x - x0) / (x1 - x0)) * pi / (x1 - x0)
        end if
    end function havsin_slope

end module stickslip_friction
