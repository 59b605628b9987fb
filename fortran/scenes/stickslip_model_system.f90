!> A user's own system, assembled from arrays: bodies on one axis (a mass or an inertia each),
!! linear springs and dampers between two bodies or a body and the ground, external forces and
!! frictional contacts, each contact with its own friction law, and time signals
!! (`stickslip_signal`) for the forces, the normal forces and the surfaces' velocities. Built
!! by `stickslip_model` (which validates it); every method runs it.
!!
!! Bodies 1 .. nb, index 0 is the ground. With positions x and velocities v [m, m/s; or rad,
!! rad/s for inertias]:
!!   - spring (a, b, k, l0): force -k (x_a - x_b - l0) on a and the opposite on b (x_0 = 0);
!!   - damper (a, b, c): force -c (v_a - v_b) on a and the opposite on b;
!!   - force (a, s): signal s on body a [N];
!!   - contact (a, b, law, N, w): the slip s = v_a - v_b - w(t) (w a signal, the velocity of
!!     a surface driven under a, a belt; 0 by default) and the normal force N(t) (a signal;
!!     N <= 0 opens the contact: no friction); the law's coefficient mu at s gives the force
!!     -mu N on a and +mu N on b. The law sees s as its relative velocity, and its internal
!!     states (a bristle deflection) follow s.
!! m_a x_a'' = the sum of the forces on a.
!!
!! State y = (x_1 .. x_nb, v_1 .. v_nb, then the contacts' law states, contact by contact).
!! A law that reads a holding coefficient (Karnopp) gets, for contact i,
!! mu_hold = (f_a / m_a - f_b / m_b - w') / (N (1 / m_a + 1 / m_b)) with f the forces other
!! than friction: the coefficient that holds s constant when no other contact acts on a or b
!! (where another does, its friction is not counted).
!!
!! For the nonsmooth methods the model is a `contact_system` (`model_contact`) with q = x,
!! u = v, M = diag(m), f = springs + dampers + forces, H with +1 at a and -1 at b per contact
!! (coupled rows where a contact joins two bodies), N_i(t) and b_i(t) = -w_i(t); every
!! contact's law must then have a set-valued form (Coulomb, Stribeck). W = M + a C + b K is
!! tridiagonal when every spring and damper joins neighbours (|a - b| = 1) or the ground, and
!! then solved in O(nb); otherwise by dense LU.
!!
!! Divergence: `state_bound` bounds each |y_i| by BOUND_MARGIN times what the energy allows
!! (`model_state_bound`): every force and friction force is bounded over all times (the
!! signals' `sup`, the laws' largest |mu|), so a state beyond it has diverged (SS_DIVERGED).
module stickslip_model_system
    use stickslip_kinds, only: dp, SS_OK, SS_NOT_SETVALUED
    use stickslip_friction, only: friction_law
    use stickslip_laws, only: evaluate_run, mu_run
    use stickslip_ode, only: ode_system, fd_jacobian, fd_band_jacobian, BOUND_MARGIN
    use stickslip_contact, only: contact_system, contact_law_of
    use stickslip_signal, only: signal_set
    use stickslip_linalg, only: lu_decompose, lu_solve, tridiagonal_solve
    use stickslip_roots, only: root_search
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: model_system, model_contact, law_slot

    !> One contact's friction law (an array of polymorphic laws).
    type :: law_slot
        class(friction_law), allocatable :: law   !! a validated law
    end type law_slot

    !> The model as a first-order system (see the module notes).
    type, extends(ode_system) :: model_system
        integer :: nb = 0                          !! bodies
        real(dp), allocatable :: mass(:)           !! (nb) mass [kg] or inertia [kg m^2], > 0
        integer, allocatable :: spr_a(:), spr_b(:) !! springs' bodies (0: the ground)
        real(dp), allocatable :: spr_k(:)          !! stiffness [N/m], >= 0
        real(dp), allocatable :: spr_l0(:)         !! x_a - x_b at rest [m]
        integer, allocatable :: dmp_a(:), dmp_b(:) !! dampers' bodies (0: the ground)
        real(dp), allocatable :: dmp_c(:)          !! damping [N s/m], >= 0
        integer, allocatable :: frc_body(:)        !! forces' bodies
        integer, allocatable :: frc_sig(:)         !! forces' signals
        integer, allocatable :: con_a(:), con_b(:) !! contacts' bodies (0: the ground, on one side at most)
        integer, allocatable :: con_n(:)           !! contacts' normal-force signals
        integer, allocatable :: con_w(:)           !! contacts' surface-velocity signals (0: none)
        type(law_slot), allocatable :: laws(:)     !! contacts' laws
        integer, allocatable :: z_first(:)         !! (nc + 1) contact i's states are z(z_first(i) : z_first(i + 1) - 1)
        logical :: all_static = .true.             !! every law is static (no states)
        type(signal_set) :: sig                    !! the signals
        integer, allocatable :: band_perm(:)       !! (n) state at each position of the body order (`prepare`)
        integer, allocatable :: band_pos(:)        !! (n) the position of each state in that order (`prepare`)
        integer :: band_ml = -1                    !! lower bandwidth in that order (-1: dense)
        integer :: band_mu = -1                    !! upper bandwidth in that order (-1: dense)
        real(dp), allocatable :: work(:, :)        !! (nb, 2) the forces of `rhs`, kept between calls (no allocation a call)
        !> the static Jacobian's constant part (x' = v, springs, dampers) as `static_jacobian`
        !! assembles it, in the layout of lower bandwidth jac_fixed_ml (-1: dense); formed on its
        !! first use after `prepare` and copied then, the contacts' part added each call
        real(dp), allocatable :: jac_fixed(:, :)
        integer :: jac_fixed_ml = -2               !! the layout jac_fixed holds (-2: none)
        !> (2, nc) contact i's normal force [N] and surface velocity [m/s] where their signals
        !! are numbers (`prepare`), read without evaluating the signal
        real(dp), allocatable :: con_fixed(:, :)
        logical, allocatable :: con_is_fixed(:, :) !! (2, nc) which of them are numbers
        !> (nc) the slip speed over which each contact's law turns, max |mu| / |mu'(0)| (its v_eps
        !! or v_s) [m/s]; huge where mu'(0) is 0 (`prepare`; read by `error_size`)
        real(dp), allocatable :: con_band(:)
        !> .true.: `error_size` sizes a body's velocity by its contacts' slips; .false.: |y| (the
        !! presets, whose steps are those the scenes took before they became models)
        logical :: slip_error_size = .true.
        !> (nb + 1) body i's springs, dampers and contacts are elem_of(elem_ptr(i) : elem_ptr(i + 1) - 1)
        !! (`prepare`): a spring's index, nspr + a damper's, nspr + ndmp + a contact's
        integer, allocatable :: elem_ptr(:)
        integer, allocatable :: elem_of(:)         !! the elements of each body, in index order (`elem_ptr`)
        !> every contact's normal force and surface velocity a number (`prepare`): `rhs` then
        !! takes its short path (`fixed_static_rhs`, or `fixed_rhs` for laws with states),
        !! reading them as found
        logical :: fixed_contacts = .false.
        logical :: unit_mass = .false.             !! every mass is 1 (`prepare`): no division
        real(dp), allocatable :: con_im(:)         !! (nc) 1 / m_a + 1 / m_b of each contact [1/kg] (`prepare`)
        !> (nc) contact i's law is contact i - 1's: the same law with the same parameters, as
        !! the model's builder made it (unallocated: no two contacts share a law)
        logical, allocatable :: con_same_law(:)
        !> (runs + 1) the runs of contacts that share a law (`prepare`): contacts
        !! law_run(r) .. law_run(r + 1) - 1 share contact law_run(r)'s law, which `evaluate_run`
        !! and `mu_run` evaluate for them all in one call (`fixed_rhs`, `fixed_static_rhs`)
        integer, allocatable :: law_run(:)
        !> (nc, 3) each contact's slip [m/s], holding coefficient and mu [-] (`fixed_rhs`'s
        !! workspace, allocated by `prepare`)
        real(dp), allocatable :: con_work(:, :)
    contains
        procedure :: rhs => model_rhs
        !! (x, v, z)' at (t, y)
        procedure :: jacobian => model_jacobian
        !! analytic with static laws, finite differences otherwise
        procedure :: prepare => model_prepare
        !! find the body order and its band, and the contacts' constant signals (once, when
        !! the model is built)
        procedure :: bandwidth => model_bandwidth
        !! the body order and its band, or dense
        procedure :: band_jacobian => model_band_jacobian
        !! the Jacobian in the body order, band storage
        procedure :: n_states => model_n_states
        !! 2 nb + the laws' states
        procedure :: free_forces => model_free_forces
        !! springs, dampers and forces on each body [N]
        procedure :: friction => model_friction
        !! each contact's friction force on its body a at (t, y) [N]
        procedure :: slip => model_slip
        !! contact i's slip s at (t, y), what its law sees [m/s]
        procedure :: error_size => model_error_size
        !! a body's velocity sized by the smallest slip of its contacts (what the laws see)
        procedure :: contact_model => model_contact_model
        !! the model as a `model_contact`
        procedure :: next_break => model_next_break
        !! the first corner of any signal after t [s]
        procedure :: has_jumps => model_has_jumps
        !! .true. when a contact's law has a jump (modes)
        procedure :: state_bound => model_state_bound
        !! BOUND_MARGIN times the energy bound on each |y_i|
        procedure :: condensed_components => model_condensed_components
        !! the states of the contacts whose law solves their stage itself (`condensed`)
        procedure :: condense_stage => model_condense_stage
        !! their part of the stage from each law's stage_states at its slip
        procedure :: stage_rhs => model_stage_rhs
        !! f at a stage state with those states moving at the stage's rates
        procedure :: scalar_stage => model_scalar_stage
        !! a stage of static laws by nonlinear Gauss-Seidel over the bodies, each a bracketed
        !! scalar equation (where Newton's method fails: the proposed law's cusp at rest)
        procedure :: body_acceleration => model_body_acceleration
        !! body i's acceleration at (t, x, v) with static laws [m/s^2] (read by `scalar_stage`)
    end type model_system

    !> The model with set-valued contacts (see the module notes).
    type, extends(contact_system) :: model_contact
        type(model_system) :: m                   !! the model
        real(dp), allocatable :: kmat(:, :)       !! (nb, nb) K = -df/dx [N/m], when not tridiagonal
        real(dp), allocatable :: cmat(:, :)       !! (nb, nb) C = -df/dv [N s/m], when not tridiagonal
        real(dp), allocatable :: ktri(:, :)       !! (3, nb) K's diagonals (i, i - 1), (i, i), (i, i + 1), when tridiagonal
        real(dp), allocatable :: ctri(:, :)       !! (3, nb) C's diagonals, when tridiagonal
        logical :: tri = .false.                  !! K and C are tridiagonal
    contains
        procedure :: force => mc_force
        !! springs, dampers and forces
        procedure :: solve_w => mc_solve_w
        !! W = M + a C + b K, tridiagonal or dense
        procedure :: normal_forces => mc_normal
        !! the normal-force signals, clipped at 0
        procedure :: slip_offset => mc_offset
        !! -w(t)
        procedure :: offset_rate => mc_offset_rate
        !! -w'(t)
        procedure :: w_tridiagonal => mc_w_tridiagonal
        !! W's three diagonals when K and C are tridiagonal
        procedure :: next_time_event => mc_next_time_event
        !! the first corner of any signal after t
        procedure :: time_scale => mc_time_scale
        !! the shortest period of any sine in the signals
    end type model_contact

contains

    !> The model's bounds on |y|. With E = sum m_i v_i^2 / 2 + the springs' energy (dampers
    !! only take energy out), each body's force beyond its springs and dampers is at most
    !! P_i = sum of sup |F| over its forces + sum of mu_max sup N over its contacts (mu_max:
    !! the law's largest |mu| up to the largest relative speed, `contact_speed_bound`), so
    !! E' <= sum P_i |v_i| <= a sqrt(E) with a = sum P_i sqrt(2 / m_i), and
    !! sqrt(E) <= R = sqrt(E0) + a T / 2 over T = t_end - t0: |v_i| <= V_i = R sqrt(2 / m_i),
    !! |x_i| <= |x0_i| + V_i T, and |x_a| <= |l0| + R sqrt(2 / k) for a spring k from body a to
    !! the ground (its energy is at most E); a law's states move at most twice their relative speed,
    !! |z| <= max |z0| + 2 S T (S the largest relative speed: V_a + V_b + sup |w|).
    !! BOUND_MARGIN times these.
    function model_state_bound(self, t0, y0, t_end) result(bound)
        class(model_system), intent(in) :: self
        real(dp), intent(in) :: t0          !! initial time [s]
        real(dp), intent(in) :: y0(:)       !! initial state (x [m], v [m/s], z...)
        real(dp), intent(in) :: t_end       !! final time [s]
        real(dp) :: bound(size(y0))         !! bounds on |x_i| [m], |v_i| [m/s], |z| [m]
        real(dp) :: tt, e0, d, vb(self%nb), speed, root_e
        integer :: i, nb
        nb = self%nb
        bound = huge(1.0_dp)
        if (size(y0) /= self%n_states()) return     ! not this model's state: the methods refuse it
        tt = max(t_end - t0, 0.0_dp)
        e0 = 0.5_dp * sum(self%mass * y0(nb + 1:2 * nb)**2)
        do i = 1, size(self%spr_k)
            d = y0(self%spr_a(i)) - self%spr_l0(i)
            if (self%spr_b(i) > 0) d = d - y0(self%spr_b(i))
            e0 = e0 + 0.5_dp * self%spr_k(i) * d * d
        end do
        ! first with mu_s and mu_k, then with each law's |mu| up to the speeds that allows
        call body_speeds(-1.0_dp, vb, speed, root_e)
        call body_speeds(speed, vb, speed, root_e)
        bound(1:nb) = BOUND_MARGIN * (abs(y0(1:nb)) + vb * tt)
        ! a spring to the ground holds its body: k (x_a - l0)^2 / 2 <= E <= R^2
        do i = 1, size(self%spr_k)
            if (self%spr_b(i) == 0 .and. self%spr_k(i) > 0.0_dp) bound(self%spr_a(i)) = &
                min(bound(self%spr_a(i)), BOUND_MARGIN * (abs(self%spr_l0(i)) + root_e * sqrt(2.0_dp / self%spr_k(i))))
        end do
        bound(nb + 1:2 * nb) = BOUND_MARGIN * vb
        if (size(y0) > 2 * nb) bound(2 * nb + 1:) = BOUND_MARGIN * (maxval(abs(y0(2 * nb + 1:))) + 2.0_dp * speed * tt)
    contains
        !> vb: each body's speed bound V_i [m/s] with each law's |mu| bounded at relative speeds up
        !! to v_ref (< 0: by mu_s and mu_k alone); speed: the largest relative speed of a
        !! contact that allows [m/s]; root_e: R, the bound on sqrt(E) [sqrt(J)].
        subroutine body_speeds(v_ref, vb, speed, root_e)
            real(dp), intent(in)  :: v_ref
            real(dp), intent(out) :: vb(:), speed, root_e
            real(dp) :: push(nb), mu_max, r
            integer :: j, c
            push = 0.0_dp
            do j = 1, size(self%frc_body)
                push(self%frc_body(j)) = push(self%frc_body(j)) + self%sig%sup(self%frc_sig(j))
            end do
            do c = 1, size(self%con_a)
                associate (law => self%laws(c)%law)
                    mu_max = max(law%mu_s, law%mu_k)
                    if (v_ref >= 0.0_dp) mu_max = max(mu_max, abs(law%mu(v_ref)), abs(law%mu(-v_ref)))
                end associate
                if (self%con_a(c) > 0) push(self%con_a(c)) = push(self%con_a(c)) + mu_max * self%sig%sup(self%con_n(c))
                if (self%con_b(c) > 0) push(self%con_b(c)) = push(self%con_b(c)) + mu_max * self%sig%sup(self%con_n(c))
            end do
            r = sqrt(e0) + 0.5_dp * tt * sum(push * sqrt(2.0_dp / self%mass))
            root_e = r
            vb = r * sqrt(2.0_dp / self%mass)
            speed = 0.0_dp
            do c = 1, size(self%con_a)
                r = 0.0_dp
                if (self%con_a(c) > 0) r = vb(self%con_a(c))
                if (self%con_b(c) > 0) r = r + vb(self%con_b(c))
                if (self%con_w(c) > 0) r = r + self%sig%sup(self%con_w(c))
                speed = max(speed, r)
            end do
        end subroutine body_speeds
    end function model_state_bound

    pure integer function model_n_states(self) result(n)
        class(model_system), intent(in) :: self
        n = 2 * self%nb + self%z_first(size(self%z_first)) - 1
    end function model_n_states

    !> Springs, dampers and external forces on each body at (t, x, v) [N].
    subroutine model_free_forces(self, t, x, v, f)
        class(model_system), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: x(:)       !! (nb) positions [m]
        real(dp), intent(in)  :: v(:)       !! (nb) velocities [m/s]
        real(dp), intent(out) :: f(:)       !! (nb) forces [N]
        real(dp) :: fe, xb, vb, rate
        integer :: i, a, b
        f = 0.0_dp
        do i = 1, size(self%spr_k)
            a = self%spr_a(i)
            b = self%spr_b(i)
            xb = 0.0_dp
            if (b > 0) xb = x(b)
            fe = -self%spr_k(i) * (x(a) - xb - self%spr_l0(i))
            f(a) = f(a) + fe
            if (b > 0) f(b) = f(b) - fe
        end do
        do i = 1, size(self%dmp_c)
            a = self%dmp_a(i)
            b = self%dmp_b(i)
            vb = 0.0_dp
            if (b > 0) vb = v(b)
            fe = -self%dmp_c(i) * (v(a) - vb)
            f(a) = f(a) + fe
            if (b > 0) f(b) = f(b) - fe
        end do
        do i = 1, size(self%frc_body)
            call self%sig%eval(self%frc_sig(i), t, fe, rate)
            f(self%frc_body(i)) = f(self%frc_body(i)) + fe
        end do
    end subroutine model_free_forces

    !> Contact i's slip s [m/s], its normal force N >= 0 [N] and the surface's acceleration
    !! w' [m/s^2] at (t, v).
    subroutine contact_state(self, i, t, v, s, n, wdot)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i
        real(dp), intent(in) :: t, v(:)
        real(dp), intent(out) :: s, n, wdot
        real(dp) :: w
        n = normal_force(self, i, t)
        call surface(self, i, t, w, wdot)
        s = -w
        if (self%con_a(i) > 0) s = v(self%con_a(i)) - w
        if (self%con_b(i) > 0) s = s - v(self%con_b(i))
    end subroutine contact_state

    !> Contact i's normal force at t, clipped at 0 [N].
    pure real(dp) function normal_force(self, i, t) result(n)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i
        real(dp), intent(in) :: t
        real(dp) :: rate
        if (self%con_is_fixed(1, i)) then
            n = self%con_fixed(1, i)
        else
            call self%sig%eval(self%con_n(i), t, n, rate)
        end if
        n = max(n, 0.0_dp)
    end function normal_force

    !> Contact i's surface velocity w [m/s] and its rate w' [m/s^2] at t (0 where it has none).
    pure subroutine surface(self, i, t, w, wdot)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i
        real(dp), intent(in) :: t
        real(dp), intent(out) :: w, wdot
        if (self%con_is_fixed(2, i)) then
            w = self%con_fixed(2, i)
            wdot = 0.0_dp
        else
            call self%sig%eval(self%con_w(i), t, w, wdot)
        end if
    end subroutine surface

    !> 1 / m_a + 1 / m_b of contact i [1/kg] (the ground: infinite mass).
    pure real(dp) function inverse_mass(self, i) result(im)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i
        im = 0.0_dp
        if (self%con_a(i) > 0) im = 1.0_dp / self%mass(self%con_a(i))
        if (self%con_b(i) > 0) im = im + 1.0_dp / self%mass(self%con_b(i))
    end function inverse_mass

    subroutine model_rhs(self, t, y, dydt)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s], z)
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2], z rates)
        integer :: nb
        nb = self%nb
        if (self%fixed_contacts .and. self%all_static) then
            call fixed_static_rhs(self, t, y, dydt)
            return
        else if (self%fixed_contacts) then
            call fixed_rhs(self, t, y, dydt)
            return
        end if
        if (.not. allocated(self%work)) allocate(self%work(nb, 2))
        associate (f => self%work(:, 1), f0 => self%work(:, 2))
        call self%free_forces(t, y(1:nb), y(nb + 1:2 * nb), f0)
        call contact_forces(self, t, y, f0, f, dydt)
        dydt(1:nb) = y(nb + 1:2 * nb)
        if (self%unit_mass) then
            dydt(nb + 1:2 * nb) = f
        else
            dydt(nb + 1:2 * nb) = f / self%mass
        end if
        end associate
    end subroutine model_rhs

    !> `rhs` of a model whose laws are all static and whose contacts' signals are numbers
    !! (`fixed_contacts`): the same operations in the same order (the same numbers, bit for
    !! bit), the numbers read as they were found by `prepare`: every contact's slip first, then
    !! each run of contacts that share a law (`law_run`) in one call (`mu_run`), then the
    !! forces summed in contact order.
    subroutine fixed_static_rhs(self, t, y, dydt)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s])
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2])
        integer :: i, r, nb
        nb = self%nb
        call self%free_forces(t, y(1:nb), y(nb + 1:2 * nb), dydt(nb + 1:2 * nb))
        associate (f => dydt(nb + 1:2 * nb), s => self%con_work(:, 1), mu => self%con_work(:, 3))
        call fixed_slips(self, y(nb + 1:2 * nb), s)
        do r = 1, size(self%law_run) - 1
            i = self%law_run(r)
            call mu_run(self%laws(i)%law, s(i:self%law_run(r + 1) - 1), mu(i:self%law_run(r + 1) - 1))
        end do
        call add_friction(self, mu, f)
        if (.not. self%unit_mass) f = f / self%mass
        end associate
        dydt(1:nb) = y(nb + 1:2 * nb)
    end subroutine fixed_static_rhs

    !> `rhs` of a model whose contacts' signals are numbers (`fixed_contacts`) and whose laws
    !! have states: `contact_forces`' numbers in the same order (the same, bit for bit), the
    !! numbers read as `prepare` found them (a surface's acceleration 0). Every contact's slip
    !! and holding coefficient (from the free forces alone, before any friction is added) are
    !! formed first; then each run of contacts that share a law (`law_run`) is evaluated in one
    !! call (`evaluate_run`), and the friction forces are summed in contact order.
    subroutine fixed_rhs(self, t, y, dydt)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s], z)
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2], z rates)
        integer :: i, r, nb, z0, z1
        nb = self%nb
        associate (v => y(nb + 1:2 * nb), f => dydt(nb + 1:2 * nb), s => self%con_work(:, 1), &
                   hold => self%con_work(:, 2), mu => self%con_work(:, 3))
        call self%free_forces(t, y(1:nb), v, f)
        call fixed_slips(self, v, s)
        do i = 1, size(self%con_a)
            hold(i) = holding(self, i, max(self%con_fixed(1, i), 0.0_dp), f, 0.0_dp)
        end do
        do r = 1, size(self%law_run) - 1
            i = self%law_run(r)
            z0 = 2 * nb + self%z_first(i)
            z1 = 2 * nb + self%z_first(self%law_run(r + 1)) - 1
            call evaluate_run(self%laws(i)%law, s(i:self%law_run(r + 1) - 1), y(z0:z1), &
                              hold(i:self%law_run(r + 1) - 1), mu(i:self%law_run(r + 1) - 1), dydt(z0:z1))
        end do
        call add_friction(self, mu, f)
        if (.not. self%unit_mass) f = f / self%mass
        end associate
        dydt(1:nb) = y(nb + 1:2 * nb)
    end subroutine fixed_rhs

    !> Every contact's slip s = v_a - v_b - w [m/s] of a model whose surface velocities are
    !! numbers (`fixed_contacts`, read as `prepare` found them).
    pure subroutine fixed_slips(self, v, s)
        class(model_system), intent(in) :: self
        real(dp), intent(in)  :: v(:)       !! (nb) velocities [m/s]
        real(dp), intent(out) :: s(:)       !! (nc) slips [m/s]
        integer :: i
        do i = 1, size(self%con_a)
            s(i) = -self%con_fixed(2, i)
            if (self%con_a(i) > 0) s(i) = v(self%con_a(i)) - self%con_fixed(2, i)
            if (self%con_b(i) > 0) s(i) = s(i) - v(self%con_b(i))
        end do
    end subroutine fixed_slips

    !> f += each contact's friction -mu N on its body a and +mu N on b, in contact order, the
    !! normal forces numbers (`fixed_contacts`) [N].
    pure subroutine add_friction(self, mu, f)
        class(model_system), intent(in) :: self
        real(dp), intent(in)    :: mu(:)    !! (nc) friction coefficients [-]
        real(dp), intent(inout) :: f(:)     !! (nb) forces [N]
        real(dp) :: fn
        integer :: i
        do i = 1, size(self%con_a)
            fn = mu(i) * max(self%con_fixed(1, i), 0.0_dp)
            if (self%con_a(i) > 0) f(self%con_a(i)) = f(self%con_a(i)) - fn
            if (self%con_b(i) > 0) f(self%con_b(i)) = f(self%con_b(i)) + fn
        end do
    end subroutine add_friction

    !> The sizes the adaptive methods' relative tolerance scales (`ode_system%error_size`):
    !! |y_i|, except that a body's velocity counts as the smallest max(|s|, band) of its
    !! contacts when that is smaller: on a moving surface, or against another moving body, the
    !! law sees the slip s = v_a - v_b - w, not v_a, and an error of rtol |v_a| in v_a may
    !! exceed the law's band (v_eps, v_s: `con_band`) where s is small. The tolerance then acts
    !! on the slip, as it does on the same system written in the surface's frame, down to the
    !! band's width, within which the law is resolved at rtol of its band (a law flat at rest,
    !! Karnopp's, keeps |v|).
    subroutine model_error_size(self, t, y, size_y)
        class(model_system), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s], z)
        real(dp), intent(out) :: size_y(:)  !! the size of each component
        real(dp) :: s, w, wdot
        integer :: i, nb, a, b
        nb = self%nb
        size_y = abs(y)
        if (.not. self%slip_error_size) return
        do i = 1, size(self%con_a)
            a = self%con_a(i)
            b = self%con_b(i)
            call surface(self, i, t, w, wdot)
            s = -w
            if (a > 0) s = y(nb + a) - w
            if (b > 0) s = s - y(nb + b)
            s = max(abs(s), self%con_band(i))
            if (a > 0) size_y(nb + a) = min(size_y(nb + a), s)
            if (b > 0) size_y(nb + b) = min(size_y(nb + b), s)
        end do
    end subroutine model_error_size

    !> Contact i's slip s = v_a - v_b - w(t) at (t, y) [m/s] (v_0 = 0: the ground).
    real(dp) function model_slip(self, i, t, y) result(s)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i            !! the contact, from 1
        real(dp), intent(in) :: t           !! time [s]
        real(dp), intent(in) :: y(:)        !! (x [m], v [m/s], z)
        real(dp) :: n, wdot
        call contact_state(self, i, t, y(self%nb + 1:2 * self%nb), s, n, wdot)
    end function model_slip

    !> Each contact's friction force on its body a at (t, y), -mu N [N] (b gets the opposite).
    subroutine model_friction(self, t, y, fric)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s], z)
        real(dp), intent(out) :: fric(:)    !! (number of contacts) [N]
        real(dp) :: f0(self%nb), f(self%nb), dydt(size(y))
        call self%free_forces(t, y(1:self%nb), y(self%nb + 1:2 * self%nb), f0)
        call contact_forces(self, t, y, f0, f, dydt, fric)
    end subroutine model_friction

    !> The forces f on each body [N]: f0 (springs, dampers, forces) and every contact's
    !! friction (each also in fric when present); the law states' rates into dydt.
    subroutine contact_forces(self, t, y, f0, f, dydt, fric, k)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)  :: t, y(:), f0(:)
        real(dp), intent(out) :: f(:)
        real(dp), intent(inout) :: dydt(:)
        real(dp), intent(out), optional :: fric(:)
        !> a stage derivative: the condensed contacts' states move at its rates, their mu the
        !! law's `stage_mu` (`stage_rhs`)
        real(dp), intent(in), optional :: k(:)
        real(dp) :: s, n, wdot, mu, mu_hold
        integer :: i, nb, a, b, z0, z1
        nb = self%nb
        f = f0
        do i = 1, size(self%con_a)
            a = self%con_a(i)
            b = self%con_b(i)
            call contact_state(self, i, t, y(nb + 1:2 * nb), s, n, wdot)
            if (self%all_static) then
                mu = self%laws(i)%law%mu(s)
            else if (present(k) .and. condensed(self, i)) then
                z0 = 2 * nb + self%z_first(i)
                z1 = 2 * nb + self%z_first(i + 1) - 1
                dydt(z0:z1) = k(z0:z1)
                mu = self%laws(i)%law%stage_mu(s, y(z0:z1), dydt(z0:z1))
            else
                z0 = 2 * nb + self%z_first(i)
                z1 = 2 * nb + self%z_first(i + 1) - 1
                mu_hold = holding(self, i, n, f0, wdot)
                call self%laws(i)%law%evaluate(s, y(z0:z1), mu_hold, mu, dydt(z0:z1))
            end if
            if (a > 0) f(a) = f(a) - mu * n
            if (b > 0) f(b) = f(b) + mu * n
            if (present(fric)) fric(i) = -mu * n
        end do
    end subroutine contact_forces

    !> Contact i's holding coefficient given the free forces f0 [N] on the bodies, its normal
    !! force n [N] and its surface's acceleration wdot [m/s^2]: the mu that keeps its slip
    !! constant, (f0_a / m_a - f0_b / m_b - w') / (n (1 / m_a + 1 / m_b)) (0 without a normal force).
    pure real(dp) function holding(self, i, n, f0, wdot) result(mu_hold)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i
        real(dp), intent(in) :: n, f0(:), wdot
        real(dp) :: c, fa, fb
        integer :: a, b
        mu_hold = 0.0_dp
        c = n * self%con_im(i)
        if (.not. c > 0.0_dp) return
        a = self%con_a(i)
        b = self%con_b(i)
        fa = 0.0_dp
        fb = 0.0_dp
        if (self%unit_mass) then
            if (a > 0) fa = f0(a)
            if (b > 0) fb = f0(b)
        else
            if (a > 0) fa = f0(a) / self%mass(a)
            if (b > 0) fb = f0(b) / self%mass(b)
        end if
        mu_hold = (fa - fb - wdot) / c
    end function holding

    !> Whether contact i's law solves its states' stage itself (`condenses_states`) where its
    !! surface moves at a constant velocity (the stage's slip needs no time).
    pure logical function condensed(self, i)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i
        condensed = self%laws(i)%law%condenses_states() .and. self%con_is_fixed(2, i)
    end function condensed

    subroutine model_condensed_components(self, mask)
        class(model_system), intent(in) :: self
        logical, intent(out) :: mask(:)     !! (n) .true. for the condensed contacts' states
        integer :: i
        mask = .false.
        if (self%all_static) return
        do i = 1, size(self%con_a)
            if (condensed(self, i)) mask(2 * self%nb + self%z_first(i):2 * self%nb + self%z_first(i + 1) - 1) = .true.
        end do
    end subroutine model_condensed_components

    !> k(z) = (z_s - u(z)) / c for each condensed contact, z_s its law's stage states at the
    !! slip of the stage velocities u_v + c k_v.
    subroutine model_condense_stage(self, u, c, k)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative; the condensed states' part on exit
        real(dp) :: s, n, wdot, vs(self%nb)
        integer :: i, nb, z0, z1
        if (self%all_static .or. c <= 0.0_dp) return
        nb = self%nb
        vs = u(nb + 1:2 * nb) + c * k(nb + 1:2 * nb)
        do i = 1, size(self%con_a)
            if (.not. condensed(self, i)) cycle
            z0 = 2 * nb + self%z_first(i)
            z1 = 2 * nb + self%z_first(i + 1) - 1
            call contact_state(self, i, 0.0_dp, vs, s, n, wdot)     ! (a constant surface: no time read)
            block
                real(dp) :: z_s(z1 - z0 + 1)
                call self%laws(i)%law%stage_states(s, u(z0:z1), c, z_s)
                k(z0:z1) = (z_s - u(z0:z1)) / c
            end block
        end do
    end subroutine model_condense_stage

    !> f at the stage state y, the condensed contacts' states moving at the rates of the stage
    !! derivative k and their mu the law's `stage_mu` there.
    subroutine model_stage_rhs(self, t, y, k, f)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! stage state
        real(dp), intent(in)  :: k(:)       !! stage derivative (the condensed states' part read)
        real(dp), intent(out) :: f(:)       !! f at y
        integer :: nb
        nb = self%nb
        if (.not. allocated(self%work)) allocate(self%work(nb, 2))
        associate (fb => self%work(:, 1), f0 => self%work(:, 2))
        call self%free_forces(t, y(1:nb), y(nb + 1:2 * nb), f0)
        call contact_forces(self, t, y, f0, fb, f, k=k)
        f(1:nb) = y(nb + 1:2 * nb)
        f(nb + 1:2 * nb) = fb / self%mass
        end associate
    end subroutine model_stage_rhs

    !> df/dy: analytic when every law is static (springs, dampers, and each contact's
    !! d mu/ds N on the velocities of its bodies), finite differences otherwise.
    subroutine model_jacobian(self, t, y, f, dfdy, nfev)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)    :: t             !! time [s]
        real(dp), intent(in)    :: y(:)          !! state
        real(dp), intent(in)    :: f(:)          !! f(t, y), already evaluated
        real(dp), intent(out)   :: dfdy(:, :)    !! (n, n) Jacobian
        integer(8), intent(inout) :: nfev        !! evaluation counter (+ 0: analytic)
        if (.not. self%all_static) then
            call fd_jacobian(self, t, y, f, dfdy, nfev)
            return
        end if
        call static_jacobian(self, t, y, -1, -1, dfdy)
    end subroutine model_jacobian

    !> The contacts' signals that are numbers (read without evaluating them), and the body
    !! order (x_1, v_1, the states of the contacts whose first body is 1, x_2, ...) and the band of the Jacobian in it, from the model's structure: x_i' reads v_i; a
    !! body's acceleration reads the positions and velocities of the bodies joined to it by a
    !! spring or a damper, and the velocities and states of its contacts; a contact's states
    !! read its bodies' velocities, and, for a law that is not static and holds (it has modes:
    !! it reads its holding coefficient), the positions of its bodies and of the bodies joined
    !! to them by a spring, and the velocities of those joined by a damper. Banded
    !! when the band LU's storage (2 ml + mu + 1 rows) is smaller than the dense matrix's (n);
    !! dense (-1) otherwise, as for one or two bodies.
    subroutine model_prepare(self)
        class(model_system), intent(inout) :: self
        !! the model, built
        integer, allocatable :: pos(:), first(:), owned(:)
        integer :: nb, nc, n, i, k, p, c, q, ends(2), ml, mu
        nb = self%nb
        nc = size(self%con_a)
        n = self%n_states()
        ! the contacts' signals that are numbers
        allocate(self%con_fixed(2, nc), self%con_is_fixed(2, nc), self%con_band(nc))
        do c = 1, nc
            associate (law => self%laws(c)%law)
                self%con_band(c) = huge(1.0_dp)
                if (abs(law%dmu(0.0_dp)) > 0.0_dp) self%con_band(c) = max(law%mu_s, law%mu_k) / abs(law%dmu(0.0_dp))
                if (.not. self%con_band(c) < huge(1.0_dp)) self%con_band(c) = huge(1.0_dp)
            end associate
            self%con_is_fixed(1, c) = self%sig%is_number(self%con_n(c))
            self%con_is_fixed(2, c) = self%con_w(c) == 0
            if (.not. self%con_is_fixed(2, c)) self%con_is_fixed(2, c) = self%sig%is_number(self%con_w(c))
            self%con_fixed(:, c) = 0.0_dp
            if (self%con_is_fixed(1, c)) self%con_fixed(1, c) = self%sig%number(self%con_n(c))
            if (self%con_w(c) > 0 .and. self%con_is_fixed(2, c)) self%con_fixed(2, c) = self%sig%number(self%con_w(c))
        end do
        call index_elements(self)
        if (allocated(self%jac_fixed)) deallocate(self%jac_fixed)   ! (formed again on first use)
        self%jac_fixed_ml = -2
        self%fixed_contacts = all(self%con_is_fixed)
        self%unit_mass = all(self%mass == 1.0_dp)
        self%con_im = [(inverse_mass(self, c), c = 1, nc)]
        call find_law_runs(self)
        if (allocated(self%con_work)) deallocate(self%con_work)
        allocate(self%con_work(nc, 3))
        allocate(pos(n), self%band_perm(n))
        ! each body's contacts in their order (a contact's states follow its body a, or b
        ! when a is the ground), bucketed once: O(nb + nc)
        allocate(first(nb + 2), owned(nc))
        first = 0
        do c = 1, nc
            i = owner(c)
            first(i + 2) = first(i + 2) + 1
        end do
        first(1) = 1
        first(2) = 1
        do i = 3, nb + 2
            first(i) = first(i) + first(i - 1)
        end do
        do c = 1, nc
            i = owner(c)
            owned(first(i + 1)) = c
            first(i + 1) = first(i + 1) + 1
        end do
        ! positions in the body order
        p = 0
        do i = 1, nb
            call place(i)
            call place(nb + i)
            do q = first(i), first(i + 1) - 1
                c = owned(q)
                do k = 2 * nb + self%z_first(c), 2 * nb + self%z_first(c + 1) - 1
                    call place(k)
                end do
            end do
        end do
        ml = 0
        mu = 0
        do i = 1, nb
            call touch(i, nb + i)
            call touch(nb + i, i)
            call touch(nb + i, nb + i)
            call joined(nb + i, i)
        end do
        do c = 1, nc
            ends = [self%con_a(c), self%con_b(c)]
            do k = 1, 2
                if (ends(k) == 0) cycle
                call reads(nb + ends(k), c)
            end do
            do k = 2 * nb + self%z_first(c), 2 * nb + self%z_first(c + 1) - 1
                call reads(k, c)
            end do
        end do
        if (2 * ml + mu + 1 < n) then
            self%band_ml = ml
            self%band_mu = mu
            self%band_pos = pos
        else
            self%band_ml = -1
            self%band_mu = -1
            self%band_perm = [(i, i = 1, n)]
            self%band_pos = self%band_perm
        end if
    contains
        !> The body whose states a contact's states follow: a, or b where a is the ground.
        pure integer function owner(c)
            integer, intent(in) :: c
            owner = max(self%con_a(c), merge(self%con_b(c), 0, self%con_a(c) == 0))
        end function owner

        subroutine place(state)
            integer, intent(in) :: state
            p = p + 1
            self%band_perm(p) = state
            pos(state) = p
        end subroutine place

        !> df(row)/dy(col) may be nonzero: widen the band.
        subroutine touch(row, col)
            integer, intent(in) :: row, col
            ml = max(ml, pos(row) - pos(col))
            mu = max(mu, pos(col) - pos(row))
        end subroutine touch

        !> The state row reads the forces of body's springs and dampers: the positions of the
        !! bodies joined to it by a spring, the velocities of those joined by a damper.
        subroutine joined(row, body)
            integer, intent(in) :: row, body
            integer :: q, e, other, nspr, ndmp
            nspr = size(self%spr_a)
            ndmp = size(self%dmp_a)
            do q = self%elem_ptr(body), self%elem_ptr(body + 1) - 1
                e = self%elem_of(q)
                if (e > nspr + ndmp) exit
                if (e <= nspr) then
                    other = self%spr_a(e) + self%spr_b(e) - body
                    if (other > 0) call touch(row, other)
                else
                    other = self%dmp_a(e - nspr) + self%dmp_b(e - nspr) - body
                    if (other > 0) call touch(row, nb + other)
                end if
            end do
        end subroutine joined

        !> The state row reads contact c: its bodies' velocities, its states, and for a law that
        !! holds (modes, not static) what its holding coefficient reads.
        subroutine reads(row, c)
            integer, intent(in) :: row, c
            integer :: j, q, body
            do j = 1, 2
                body = merge(self%con_a(c), self%con_b(c), j == 1)
                if (body == 0) cycle
                call touch(row, nb + body)
                ! the holding coefficient, read by a law that holds (a mode: Karnopp's band)
                if (self%laws(c)%law%is_static() .or. self%laws(c)%law%n_modes() == 0) cycle
                call touch(row, body)
                call joined(row, body)      ! the holding coefficient
            end do
            do q = 2 * nb + self%z_first(c), 2 * nb + self%z_first(c + 1) - 1
                call touch(row, q)
            end do
        end subroutine reads
    end subroutine model_prepare

    !> The runs of contacts that share a law (`law_run`), from `con_same_law`.
    subroutine find_law_runs(self)
        class(model_system), intent(inout) :: self
        logical :: starts(size(self%con_a))
        integer :: c, nc
        nc = size(self%con_a)
        starts = .true.
        if (allocated(self%con_same_law)) starts(2:) = .not. self%con_same_law(2:)
        self%law_run = [pack([(c, c = 1, nc)], starts), nc + 1]
    end subroutine find_law_runs

    !> Each body's springs, dampers and contacts (elem_ptr, elem_of), in index order.
    subroutine index_elements(self)
        class(model_system), intent(inout) :: self
        integer :: nspr, ndmp, nel, e, j, a, b, nb
        integer, allocatable :: fill(:)
        nb = self%nb
        nspr = size(self%spr_a)
        ndmp = size(self%dmp_a)
        nel = nspr + ndmp + size(self%con_a)
        allocate(self%elem_ptr(nb + 1), fill(nb + 1))
        fill = 0
        do e = 1, nel
            call ends(e, a, b)
            if (a > 0) fill(a) = fill(a) + 1
            if (b > 0) fill(b) = fill(b) + 1
        end do
        self%elem_ptr(1) = 1
        do j = 1, nb
            self%elem_ptr(j + 1) = self%elem_ptr(j) + fill(j)
        end do
        allocate(self%elem_of(self%elem_ptr(nb + 1) - 1))
        fill(1:nb) = self%elem_ptr(1:nb)
        do e = 1, nel
            call ends(e, a, b)
            if (a > 0) call put(a, e)
            if (b > 0) call put(b, e)
        end do
    contains
        subroutine ends(e, a, b)
            integer, intent(in) :: e
            integer, intent(out) :: a, b
            if (e <= nspr) then
                a = self%spr_a(e)
                b = self%spr_b(e)
            else if (e <= nspr + ndmp) then
                a = self%dmp_a(e - nspr)
                b = self%dmp_b(e - nspr)
            else
                a = self%con_a(e - nspr - ndmp)
                b = self%con_b(e - nspr - ndmp)
            end if
        end subroutine ends
        subroutine put(body, e)
            integer, intent(in) :: body, e
            self%elem_of(fill(body)) = e
            fill(body) = fill(body) + 1
        end subroutine put
    end subroutine index_elements

    !> The force on body i at (t, x, v) [N] with static laws: its springs, dampers, forces and
    !! contacts, summed in the order of `rhs` (the same number, bit for bit).
    real(dp) function body_force(self, i, t, x, v) result(f)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i
        real(dp), intent(in) :: t, x(:), v(:)
        real(dp) :: fe, rate, s, n, wdot
        integer :: q, e, a, b, nspr, ndmp
        nspr = size(self%spr_a)
        ndmp = size(self%dmp_a)
        f = 0.0_dp
        do q = self%elem_ptr(i), self%elem_ptr(i + 1) - 1
            e = self%elem_of(q)
            if (e > nspr + ndmp) exit               ! the contacts come last
            if (e <= nspr) then
                a = self%spr_a(e)
                b = self%spr_b(e)
                fe = -self%spr_k(e) * (x(a) - merge(x(max(b, 1)), 0.0_dp, b > 0) - self%spr_l0(e))
            else
                a = self%dmp_a(e - nspr)
                b = self%dmp_b(e - nspr)
                fe = -self%dmp_c(e - nspr) * (v(a) - merge(v(max(b, 1)), 0.0_dp, b > 0))
            end if
            f = f + merge(fe, -fe, a == i)
        end do
        do e = 1, size(self%frc_body)
            if (self%frc_body(e) /= i) cycle
            call self%sig%eval(self%frc_sig(e), t, fe, rate)
            f = f + fe
        end do
        do q = self%elem_ptr(i), self%elem_ptr(i + 1) - 1
            e = self%elem_of(q) - nspr - ndmp
            if (e < 1) cycle
            call contact_state(self, e, t, v, s, n, wdot)
            fe = self%laws(e)%law%mu(s) * n
            f = merge(f - fe, f + fe, self%con_a(e) == i)
        end do
    end function body_force

    !> Body i's force over its mass at (t, x, v), the laws static [m/s^2].
    real(dp) function model_body_acceleration(self, i, t, x, v) result(a)
        class(model_system), intent(in) :: self
        integer, intent(in) :: i            !! the body
        real(dp), intent(in) :: t           !! time [s]
        real(dp), intent(in) :: x(:)        !! (nb) positions [m]
        real(dp), intent(in) :: v(:)        !! (nb) velocities [m/s]
        a = body_force(self, i, t, x, v) / self%mass(i)
    end function model_body_acceleration

    !> The stage k = f(t, u + c k) of a model whose laws are all static, where Newton's method
    !! fails (the proposed law's infinite slope at rest, where a chain started stuck has every
    !! block): nonlinear Gauss-Seidel over the bodies. Body i's stage velocity v_i solves
    !! phi_i(v_i) = v_i - u_v,i - c F_i(x_s, v_s) / m_i = 0 with x_s = u_x + c v_s and the other
    !! bodies' stage velocities fixed, by a bracketed root (`root_search`); sweeps repeat until
    !! no stage velocity changes by more than 8 eps (1 + |v|). Where the springs' and dampers'
    !! coupling per sweep is below the diagonal (c^2 k_c / m against 1 + c^2 (k + 2 k_c) / m on
    !! the chain, the law's slope >= 0), the sweeps contract. Each body starts from its velocity
    !! at the stage's start. k returns f at the roots, except the accelerations, which are the
    !! roots' own, (v_s - u_v) / c: a body stuck at the cusp has its root between two floats,
    !! where f jumps. ok = .false. for a law with states, a missing bracket or no convergence in
    !! 1000 sweeps. One evaluation of a body's force counts as one of f (nfev).
    subroutine model_scalar_stage(self, t, u, c, k, nfev, ok)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)    :: t        !! stage time [s]
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative: a guess in, the solution out
        integer(8), intent(inout) :: nfev   !! evaluations of f, counted
        logical, intent(out)    :: ok       !! .true.: k solves the stage
        real(dp) :: vs(self%nb), xs(self%nb), vnew, change
        integer :: i, n, sweep
        type(root_search) :: search
        ok = .false.
        n = self%nb
        if (.not. self%all_static .or. size(u) /= 2 * n .or. .not. allocated(self%elem_ptr)) return
        vs = u(n + 1:2 * n)     ! from the stage's start
        xs = u(1:n) + c * vs
        do sweep = 1, 1000
            change = 0.0_dp
            do i = 1, n
                call search%start(vs(i))
                do while (.not. search%done)
                    call search%tell(phi(search%x))
                end do
                if (.not. search%found) return
                vnew = search%root
                change = max(change, abs(vnew - vs(i)) / (1.0_dp + abs(vnew)))
                vs(i) = vnew
                xs(i) = u(i) + c * vnew
            end do
            if (change <= 8.0_dp * epsilon(1.0_dp) .or. n == 1) exit   ! (one body: its root)
        end do
        if (change > 8.0_dp * epsilon(1.0_dp) .and. n > 1) return
        call self%rhs(t, [xs, vs], k)
        nfev = nfev + 1
        k(n + 1:2 * n) = (vs - u(n + 1:2 * n)) / c   ! the roots' own accelerations (notes)
        ok = all(ieee_is_finite(k))
    contains
        !> phi_i(v) [m/s] of the body i of the sweep
        real(dp) function phi(v)
            real(dp), intent(in) :: v
            real(dp) :: v_keep
            xs(i) = u(i) + c * v
            v_keep = vs(i)
            vs(i) = v
            nfev = nfev + 1
            phi = v - u(n + i) - c * self%body_acceleration(i, t, xs, vs)
            vs(i) = v_keep
        end function phi
    end subroutine model_scalar_stage

    !> The body order and its band (`prepare`), or dense (ml = mu = -1).
    subroutine model_bandwidth(self, perm, ml, mu)
        class(model_system), intent(in) :: self
        integer, intent(out) :: perm(:)     !! (n) state index at each position of the body order
        integer, intent(out) :: ml          !! lower bandwidth (-1: dense)
        integer, intent(out) :: mu          !! upper bandwidth (-1: dense)
        integer :: i
        if (allocated(self%band_perm)) then
            perm = self%band_perm
        else
            perm = [(i, i = 1, size(perm))]
        end if
        ml = self%band_ml
        mu = self%band_mu
    end subroutine model_bandwidth

    !> The Jacobian in the body order in band storage, jb(mu + 1 + i - j, j) =
    !! J(perm(i), perm(j)): analytic with static laws (O(n)), grouped finite differences
    !! (`fd_band_jacobian`: ml + mu + 1 evaluations) otherwise.
    subroutine model_band_jacobian(self, t, y, f, jb, nfev)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)    :: t             !! time [s]
        real(dp), intent(in)    :: y(:)          !! state
        real(dp), intent(in)    :: f(:)          !! f(t, y), already evaluated
        real(dp), intent(out)   :: jb(:, :)      !! (ml + mu + 1, n) band of the reordered Jacobian
        integer(8), intent(inout) :: nfev        !! evaluation counter
        integer :: perm(size(y)), ml, mu
        if (self%all_static) then
            call static_jacobian(self, t, y, self%band_ml, self%band_mu, jb)
        else
            call self%bandwidth(perm, ml, mu)
            call fd_band_jacobian(self, t, y, f, perm, ml, mu, jb, nfev)
        end if
    end subroutine model_band_jacobian

    !> df/dy of a model whose laws are all static, dense (ml < 0: jm(i, j) = J(i, j)) or in
    !! band storage in the body order (jm(mu + 1 + i - j, j) = J(perm(i), perm(j)), perm the
    !! model's `band_perm`, ml and mu its band).
    !! The constant part (x' = v, springs, dampers) is assembled once per layout (`jac_fixed`)
    !! and copied; the contacts' terms are added to it in the same order as before (the same
    !! sums, bit for bit).
    subroutine static_jacobian(self, t, y, ml, mu, jm)
        class(model_system), intent(inout) :: self
        real(dp), intent(in)  :: t, y(:)
        integer, intent(in)   :: ml, mu
        real(dp), intent(out) :: jm(:, :)
        integer :: i, nb
        real(dp) :: s, n, wdot
        logical :: formed
        nb = self%nb
        formed = allocated(self%jac_fixed) .and. self%jac_fixed_ml == ml
        if (formed) formed = all(shape(self%jac_fixed) == shape(jm))
        if (formed) then
            jm = self%jac_fixed
        else
            jm = 0.0_dp
            do i = 1, nb
                call put(i, nb + i, 1.0_dp)
            end do
            do i = 1, size(self%spr_k)
                call pair(self%spr_a(i), self%spr_b(i), 0, self%spr_k(i))
            end do
            do i = 1, size(self%dmp_c)
                call pair(self%dmp_a(i), self%dmp_b(i), nb, self%dmp_c(i))
            end do
            self%jac_fixed = jm
            self%jac_fixed_ml = ml
        end if
        do i = 1, size(self%con_a)
            call contact_state(self, i, t, y(nb + 1:2 * nb), s, n, wdot)
            if (self%con_a(i) > 0) then
                call pair(self%con_a(i), self%con_b(i), nb, self%laws(i)%law%dmu(s) * n)
            else        ! the same force on b alone: -g (0 - u_b) on the ground, the opposite on b
                call pair(self%con_b(i), 0, nb, self%laws(i)%law%dmu(s) * n)
            end if
        end do
    contains
        subroutine put(row, col, val)
            integer, intent(in) :: row, col
            real(dp), intent(in) :: val
            integer :: i, j
            if (ml < 0) then
                jm(row, col) = jm(row, col) + val
            else
                i = self%band_pos(row)
                j = self%band_pos(col)
                jm(mu + 1 + i - j, j) = jm(mu + 1 + i - j, j) + val
            end if
        end subroutine put

        !> A force -g (u_a - u_b) on a and the opposite on b, u the positions (off = 0) or the
        !! velocities (off = nb).
        subroutine pair(a, b, off, g)
            integer, intent(in) :: a, b, off
            real(dp), intent(in) :: g
            call put(nb + a, off + a, per_mass(-g, a))
            if (b == 0) return
            call put(nb + a, off + b, per_mass(g, a))
            call put(nb + b, off + b, per_mass(-g, b))
            call put(nb + b, off + a, per_mass(g, b))
        end subroutine pair

        !> x / m_body (x itself where every mass is 1: the same number, without a division).
        pure real(dp) function per_mass(x, body)
            real(dp), intent(in) :: x
            integer, intent(in) :: body
            per_mass = x
            if (.not. self%unit_mass) per_mass = x / self%mass(body)
        end function per_mass
    end subroutine static_jacobian

    !> K = -df/dx [N/m] and C = -df/dv [N s/m] of the springs and dampers (dense).
    pure subroutine stiffness_damping(self, kmat, cmat)
        class(model_system), intent(in) :: self
        real(dp), intent(out) :: kmat(:, :), cmat(:, :)
        integer :: i
        kmat = 0.0_dp
        cmat = 0.0_dp
        do i = 1, size(self%spr_k)
            call couple(kmat, self%spr_a(i), self%spr_b(i), self%spr_k(i))
        end do
        do i = 1, size(self%dmp_c)
            call couple(cmat, self%dmp_a(i), self%dmp_b(i), self%dmp_c(i))
        end do
    contains
        pure subroutine couple(mat, a, b, k)
            real(dp), intent(inout) :: mat(:, :)
            integer, intent(in) :: a, b
            real(dp), intent(in) :: k
            mat(a, a) = mat(a, a) + k
            if (b > 0) then
                mat(b, b) = mat(b, b) + k
                mat(a, b) = mat(a, b) - k
                mat(b, a) = mat(b, a) - k
            end if
        end subroutine couple
    end subroutine stiffness_damping

    pure real(dp) function model_next_break(self, t) result(tb)
        class(model_system), intent(in) :: self
        real(dp), intent(in) :: t           !! time [s]
        integer :: i
        tb = huge(1.0_dp)
        do i = 1, self%sig%count()
            tb = min(tb, self%sig%next_break(i, t))
        end do
    end function model_next_break

    pure logical function model_has_jumps(self) result(jumps)
        class(model_system), intent(in) :: self
        integer :: i
        jumps = .false.
        do i = 1, size(self%laws)
            jumps = jumps .or. self%laws(i)%law%n_modes() > 0
        end do
    end function model_has_jumps

    !> The model with set-valued contacts; SS_NOT_SETVALUED when a contact's law has no
    !! set-valued form (the structure is built all the same: the implicit methods' modal steps
    !! use it with the laws themselves).
    subroutine model_contact_model(self, cs, status)
        class(model_system), intent(in) :: self
        class(contact_system), allocatable, intent(out) :: cs   !! the contact model
        integer, intent(out) :: status                          !! SS_OK or SS_NOT_SETVALUED
        type(model_contact), allocatable :: mc
        integer :: i, nc, nb, k, law_status
        nb = self%nb
        nc = size(self%con_a)
        allocate(mc)
        allocate(mc%laws(nc))
        status = SS_OK
        do i = 1, nc
            call contact_law_of(self%laws(i)%law, mc%laws(i), law_status)
            if (law_status /= SS_OK) status = law_status
        end do
        mc%m = self
        mc%n_dof = nb
        mc%n_c = nc
        allocate(mc%h_ptr(nc + 1), mc%h_col(2 * nc), mc%h_val(2 * nc))
        k = 0
        do i = 1, nc
            mc%h_ptr(i) = k + 1
            if (self%con_a(i) > 0) then
                k = k + 1
                mc%h_col(k) = self%con_a(i)
                mc%h_val(k) = 1.0_dp
            end if
            if (self%con_b(i) > 0) then
                k = k + 1
                mc%h_col(k) = self%con_b(i)
                mc%h_val(k) = -1.0_dp
            end if
        end do
        mc%h_ptr(nc + 1) = k + 1
        mc%h_col = mc%h_col(:k)
        mc%h_val = mc%h_val(:k)
        mc%w_constant = .true.
        mc%tri = .true.
        do i = 1, size(self%spr_k)
            if (self%spr_b(i) > 0 .and. abs(self%spr_a(i) - self%spr_b(i)) > 1) mc%tri = .false.
        end do
        do i = 1, size(self%dmp_c)
            if (self%dmp_b(i) > 0 .and. abs(self%dmp_a(i) - self%dmp_b(i)) > 1) mc%tri = .false.
        end do
        if (mc%tri) then      ! three diagonals: O(nb) memory and solves, whatever nb
            allocate(mc%ktri(3, nb), mc%ctri(3, nb))
            mc%ktri = 0.0_dp
            mc%ctri = 0.0_dp
            do i = 1, size(self%spr_k)
                call couple_tri(mc%ktri, self%spr_a(i), self%spr_b(i), self%spr_k(i))
            end do
            do i = 1, size(self%dmp_c)
                call couple_tri(mc%ctri, self%dmp_a(i), self%dmp_b(i), self%dmp_c(i))
            end do
        else
            allocate(mc%kmat(nb, nb), mc%cmat(nb, nb))
            call stiffness_damping(self, mc%kmat, mc%cmat)
        end if
        call move_alloc(mc, cs)
    contains
        !> g between a and b = a +- 1 (or the ground) into three diagonals.
        pure subroutine couple_tri(tri, a, b, g)
            real(dp), intent(inout) :: tri(:, :)
            integer, intent(in) :: a, b
            real(dp), intent(in) :: g
            tri(2, a) = tri(2, a) + g
            if (b == 0) return
            tri(2, b) = tri(2, b) + g
            tri(2 + (b - a), a) = tri(2 + (b - a), a) - g     ! W(a, b): row a, diagonal of b - a
            tri(2 + (a - b), b) = tri(2 + (a - b), b) - g
        end subroutine couple_tri
    end subroutine model_contact_model

    subroutine mc_force(self, t, q, u, f)
        class(model_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! positions [m]
        real(dp), intent(in)  :: u(:)       !! velocities [m/s]
        real(dp), intent(out) :: f(:)       !! springs, dampers and forces [N]
        call self%m%free_forces(t, q, u, f)
    end subroutine mc_force

    subroutine mc_w_tridiagonal(self, a, b, l, d, r, ok)
        class(model_contact), intent(in) :: self
        real(dp), intent(in)  :: a          !! weight of C [s]
        real(dp), intent(in)  :: b          !! weight of K [s^2]
        real(dp), intent(out) :: l(:)       !! W(i, i - 1)
        real(dp), intent(out) :: d(:)       !! W(i, i)
        real(dp), intent(out) :: r(:)       !! W(i, i + 1)
        logical, intent(out)  :: ok         !! .true.: W is tridiagonal
        ok = self%tri
        if (.not. ok) return
        l = a * self%ctri(1, :) + b * self%ktri(1, :)
        d = self%m%mass + a * self%ctri(2, :) + b * self%ktri(2, :)
        r = a * self%ctri(3, :) + b * self%ktri(3, :)
    end subroutine mc_w_tridiagonal

    subroutine mc_solve_w(self, t, q, u, a, b, x)
        class(model_contact), intent(in) :: self
        real(dp), intent(in)    :: t        !! time [s]
        real(dp), intent(in)    :: q(:)     !! positions [m]
        real(dp), intent(in)    :: u(:)     !! velocities [m/s]
        real(dp), intent(in)    :: a        !! weight of C [s]
        real(dp), intent(in)    :: b        !! weight of K [s^2]
        real(dp), intent(inout) :: x(:)     !! right-hand side [N s], then the solution [m/s]
        if (a == 0.0_dp .and. b == 0.0_dp) then   ! W = M, diagonal (what the solves below give)
            x = x / self%m%mass
        else
            call solve_w_general(self, a, b, x)
        end if
    end subroutine mc_solve_w

    !> mc_solve_w with C or K: tridiagonal where the springs and dampers join neighbours,
    !! dense LU otherwise.
    subroutine solve_w_general(self, a, b, x)
        class(model_contact), intent(in) :: self
        real(dp), intent(in)    :: a        !! weight of C [s]
        real(dp), intent(in)    :: b        !! weight of K [s^2]
        real(dp), intent(inout) :: x(:)     !! right-hand side [N s], then the solution [m/s]
        real(dp), allocatable :: w(:, :)
        real(dp) :: l(self%n_dof), d(self%n_dof), r(self%n_dof)
        integer :: ipiv(self%n_dof), info, i
        logical :: ok
        call self%w_tridiagonal(a, b, l, d, r, ok)
        if (ok) then
            call tridiagonal_solve(l, d, r, x)
            return
        end if
        w = a * self%cmat + b * self%kmat     ! dense (a spring or damper joins distant bodies)
        do i = 1, self%n_dof
            w(i, i) = w(i, i) + self%m%mass(i)
        end do
        call lu_decompose(w, ipiv, info)   ! M + a C + b K is symmetric positive definite: info = 0
        call lu_solve(w, ipiv, x)
    end subroutine solve_w_general

    subroutine mc_normal(self, t, q, n)
        class(model_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! positions [m]
        real(dp), intent(out) :: n(:)       !! normal forces, >= 0 [N]
        integer :: i
        do i = 1, self%n_c
            n(i) = normal_force(self%m, i, t)
        end do
    end subroutine mc_normal

    subroutine mc_offset(self, t, b)
        class(model_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(out) :: b(:)       !! -w(t) of each contact [m/s]
        real(dp) :: rate
        integer :: i
        do i = 1, self%n_c
            call surface(self%m, i, t, b(i), rate)
            b(i) = -b(i)
        end do
    end subroutine mc_offset

    subroutine mc_offset_rate(self, t, b)
        class(model_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(out) :: b(:)       !! -w'(t) of each contact [m/s^2]
        real(dp) :: w
        integer :: i
        do i = 1, self%n_c
            call surface(self%m, i, t, w, b(i))
            b(i) = -b(i)
        end do
    end subroutine mc_offset_rate

    pure real(dp) function mc_next_time_event(self, t) result(tb)
        class(model_contact), intent(in) :: self
        real(dp), intent(in) :: t           !! time [s]
        tb = self%m%next_break(t)
    end function mc_next_time_event

    pure real(dp) function mc_time_scale(self) result(ts)
        class(model_contact), intent(in) :: self
        ts = self%m%sig%shortest_period()
    end function mc_time_scale

end module stickslip_model_system
