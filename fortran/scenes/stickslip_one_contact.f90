!> A model's structure found once when it is built (`specialise`): a model of one body with
!! one contact, whose signals are all numbers, is a `one_contact_model`, its forces folded into
!! a few constants per unit mass, so that a step costs what a hand-written two-state system
!! costs. The integrators instantiate their specialised kernels for this type with each static
!! law (tools/gen_kernels.py), and the fixed-step implicit methods' one-contact step over a
!! law's modes (`nonsmooth_kernel`) runs on it.
!!
!! With x, v the body's position and velocity, the folded model reads
!!   x'' = f_c - k_m x - c_m v - mu(s) n_m dir,   s = dir (v - u),
!! where f_c [N/kg] is the forces' sum and k_m x_0 of the springs' rest lengths, k_m [1/s^2] and
!! c_m [1/s] the springs and dampers to the ground, n_m the normal force [N/kg], u the
!! surface's velocity [m/s] and dir = +1 where the body is the contact's side a (the law sees
!! the body's slip over the surface), -1 where it is side b (the law sees the surface's slip
!! under the body, as on the belt: s = u - v). Every number is the model's own, divided by the
!! mass once. The law's states follow s as in the model.
module stickslip_one_contact
    use stickslip_kinds, only: dp
    use stickslip_friction, only: friction_law
    use stickslip_ode, only: fd_jacobian
    use stickslip_model_system, only: model_system, model_contact
    use stickslip_contact, only: contact_system
    implicit none
    private

    public :: one_contact_model, one_contact_contact, specialise

    !> A model of one body with one contact and constant signals, folded (see the module notes).
    type, extends(model_system) :: one_contact_model
        class(friction_law), allocatable :: law   !! the contact's law (a copy of laws(1)%law)
        integer :: nz = 0                         !! the law's internal states
        logical :: static_law = .true.            !! the law depends on the slip alone
        real(dp) :: f_c = 0.0_dp                  !! constant force per unit mass [N/kg]
        real(dp) :: k_m = 0.0_dp                  !! springs to the ground over the mass [1/s^2]
        real(dp) :: c_m = 0.0_dp                  !! dampers to the ground over the mass [1/s]
        real(dp) :: n_m = 0.0_dp                  !! normal force over the mass, >= 0 [N/kg]
        real(dp) :: u = 0.0_dp                    !! the surface's velocity [m/s]
        real(dp) :: dir = 1.0_dp                  !! +1: s = v - u; -1: s = u - v
        !> the holding coefficient mu_hold = h_0 + h_x x + h_v v [-, 1/m, s/m] (0 without a
        !! normal force)
        real(dp) :: h_0 = 0.0_dp, h_x = 0.0_dp, h_v = 0.0_dp
        real(dp) :: dn_m = 0.0_dp                 !! dir n_m [N/kg]
        real(dp) :: du = 0.0_dp                   !! dir u [m/s]
        logical :: neg = .false.                  !! dir < 0
    contains
        procedure :: rhs => oc_rhs
        !! (x, v, z)' at (t, y)
        procedure :: jacobian => oc_jacobian
        !! analytic with a static law, finite differences otherwise
        procedure :: static_rhs => oc_static_rhs
        !! (x, v)' given the friction coefficient mu (affine in mu)
        procedure :: static_jacobian => oc_static_jacobian
        !! the analytic 2 x 2 Jacobian with a static law
        procedure :: relative_velocity => oc_vrel
        !! the slip s the law sees [m/s]
        procedure :: holding_coefficient => oc_mu_hold
        !! the coefficient that holds s [-]
        procedure :: set_relative_velocity => oc_set_vrel
        !! the velocity at which the slip is w
        procedure :: body_acceleration => oc_body_acceleration
        !! x'' with a static law, folded (the model's `scalar_stage` reads it)
        procedure :: condensed_components => oc_condensed_components
        !! the law's states, when the law solves their stage itself
        procedure :: condense_stage => oc_condense_stage
        !! their part of the stage from the law's stage_states
        procedure :: stage_rhs => oc_stage_rhs
        !! f at a stage state with the law's states moving at the stage's rates
        procedure :: contact_model => oc_contact_model
        !! the model as a `one_contact_contact`
        procedure :: error_size => oc_error_size
        !! the model's error sizes for its one body and contact (the same numbers)
    end type one_contact_model

    !> The contact model of a `one_contact_model` (moreau, event_driven): the model's own
    !! `model_contact`, its normal force, offset and solves with W = m + a c + b k written for
    !! its one body and one contact: the general model's operations in the same order (the
    !! same numbers, bit for bit), without its loops over contacts and signals; the normal
    !! force, the offset and the external forces, numbers, read once when it is built.
    type, extends(model_contact) :: one_contact_contact
        real(dp) :: c_w = 0.0_dp        !! the dampers' part of W, C(1, 1) [N s/m]
        real(dp) :: k_w = 0.0_dp        !! the springs' part of W, K(1, 1) [N/m]
        real(dp) :: n_fix = 0.0_dp      !! the normal force, clipped at 0 [N]
        real(dp) :: b_fix = 0.0_dp      !! the offset -w [m/s]
        real(dp), allocatable :: frc_fix(:)   !! the external forces' values, numbers [N]
    contains
        procedure :: force => occ_force
        !! springs, dampers and forces on the one body, the model's sums in its order
        procedure :: solve_w => occ_solve_w
        !! x / (m + a c + b k)
        procedure :: normal_forces => occ_normal
        !! the normal force (a number), clipped at 0 [N]
        procedure :: slip_offset => occ_offset
        !! -w, the surface's velocity (a number) [m/s]
        procedure :: offset_rate => occ_offset_rate
        !! -w' = -0 (the surface's velocity is a number)
    end type one_contact_contact

contains

    !> The model as the type its structure allows: a `one_contact_model` when it has one body,
    !! one contact (with the ground) and only numbers as signals, the model itself otherwise.
    !! Found once, when the model is built and prepared.
    subroutine specialise(ms, sys)
        type(model_system), intent(in) :: ms                    !! the model, prepared
        class(model_system), allocatable, intent(out) :: sys    !! the same model, specialised
        type(one_contact_model), allocatable :: oc
        integer :: i
        real(dp) :: f
        logical :: fits
        fits = ms%nb == 1 .and. size(ms%con_a) == 1
        if (fits) fits = ms%con_a(1) == 0 .or. ms%con_b(1) == 0
        do i = 1, ms%sig%count()
            if (fits) fits = ms%sig%is_number(i)
        end do
        if (.not. fits) then
            allocate(sys, source=ms)
            return
        end if
        allocate(oc)
        oc%model_system = ms
        allocate(oc%law, source=ms%laws(1)%law)
        oc%nz = oc%law%n_states()
        oc%static_law = oc%law%is_static()
        f = 0.0_dp
        do i = 1, size(ms%frc_body)
            f = f + ms%sig%number(ms%frc_sig(i))
        end do
        do i = 1, size(ms%spr_k)
            oc%k_m = oc%k_m + ms%spr_k(i)
            f = f + ms%spr_k(i) * ms%spr_l0(i)      ! -k (x - l0): a is the body, b the ground
        end do
        do i = 1, size(ms%dmp_c)
            oc%c_m = oc%c_m + ms%dmp_c(i)
        end do
        oc%f_c = f / ms%mass(1)
        oc%k_m = oc%k_m / ms%mass(1)
        oc%c_m = oc%c_m / ms%mass(1)
        oc%n_m = ms%con_fixed(1, 1) / ms%mass(1)
        oc%u = ms%con_fixed(2, 1)
        oc%dir = merge(1.0_dp, -1.0_dp, ms%con_a(1) == 1)
        if (oc%dir < 0.0_dp) oc%u = -oc%u     ! side b: s = -w - v = u - v with u = -w
        oc%dn_m = oc%dir * oc%n_m
        oc%du = oc%dir * oc%u
        oc%neg = oc%dir < 0.0_dp
        if (oc%n_m > 0.0_dp) then
            oc%h_0 = oc%dir * oc%f_c / oc%n_m
            oc%h_x = -oc%dir * oc%k_m / oc%n_m
            oc%h_v = -oc%dir * oc%c_m / oc%n_m
        end if
        call move_alloc(oc, sys)
    end subroutine specialise

    pure subroutine oc_static_rhs(self, y, mu, dydt)
        class(one_contact_model), intent(in) :: self
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s])
        real(dp), intent(in)  :: mu         !! the law's coefficient at the slip [-]
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2])
        dydt(1) = y(2)
        dydt(2) = self%f_c - self%k_m * y(1) - mu * self%dn_m
        if (self%c_m /= 0.0_dp) dydt(2) = dydt(2) - self%c_m * y(2)     ! (no damper: skipped)
    end subroutine oc_static_rhs

    pure real(dp) function oc_vrel(self, y) result(s)
        class(one_contact_model), intent(in) :: self
        real(dp), intent(in) :: y(:)        !! state (x, v, z...)
        ! dir v - dir u: v - u, or (-v) - (-u), which rounds as u - v does (zero included: x - x
        ! is +0); dir v as a sign flip (a branch taken alike at every call), not a product on the
        ! stages' chain of dependences
        s = merge(-y(2), y(2), self%neg) - self%du
    end function oc_vrel

    pure real(dp) function oc_mu_hold(self, y) result(mu_hold)
        class(one_contact_model), intent(in) :: self
        real(dp), intent(in) :: y(:)        !! state (x, v, z...)
        mu_hold = self%h_0 + self%h_x * y(1) + self%h_v * y(2)
    end function oc_mu_hold

    pure subroutine oc_set_vrel(self, y, w)
        class(one_contact_model), intent(in) :: self
        real(dp), intent(inout) :: y(:)     !! state; its velocity set on exit
        real(dp), intent(in) :: w           !! the slip wanted [m/s]
        if (self%dir > 0.0_dp) then
            y(2) = self%u + w
        else
            y(2) = self%u - w
        end if
    end subroutine oc_set_vrel

    pure function oc_static_jacobian(self, y) result(j)
        class(one_contact_model), intent(in) :: self
        real(dp), intent(in) :: y(:)        !! state (x [m], v [m/s])
        real(dp) :: j(2, 2)                 !! d(v, a)/d(x, v)
        j(1, 1) = 0.0_dp
        j(2, 1) = -self%k_m
        j(1, 2) = 1.0_dp
        j(2, 2) = -self%c_m - self%n_m * self%law%dmu(oc_vrel(self, y))   ! (its own slip, inlined)
    end function oc_static_jacobian

    subroutine oc_rhs(self, t, y, dydt)
        class(one_contact_model), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s], z...)
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2], z rates)
        real(dp) :: mu
        if (self%static_law) then
            call self%static_rhs(y, self%law%mu(self%relative_velocity(y)), dydt)
        else
            call self%law%evaluate(self%relative_velocity(y), y(3:), self%holding_coefficient(y), mu, dydt(3:))
            if (self%k_m == 0.0_dp .and. self%c_m == 0.0_dp .and. self%n_m > 0.0_dp) then
                ! a constant force alone: dir n_m (mu_hold - mu), so that mu = mu_hold (a stick
                ! band) holds v exactly, not to rounding
                dydt(1) = y(2)
                dydt(2) = self%dir * self%n_m * (self%h_0 - mu)
            else
                call self%static_rhs(y, mu, dydt)
            end if
        end if
    end subroutine oc_rhs

    subroutine oc_jacobian(self, t, y, f, dfdy, nfev)
        class(one_contact_model), intent(inout) :: self
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
    end subroutine oc_jacobian

    !> x'' at (x, v) with a static law, what the model's `scalar_stage` solves for [m/s^2].
    real(dp) function oc_body_acceleration(self, i, t, x, v) result(a)
        class(one_contact_model), intent(in) :: self
        integer, intent(in) :: i            !! the body (1)
        real(dp), intent(in) :: t           !! time [s]
        real(dp), intent(in) :: x(:)        !! (1) position [m]
        real(dp), intent(in) :: v(:)        !! (1) velocity [m/s]
        real(dp) :: f(2)
        call self%static_rhs([x(1), v(1)], self%law%mu(self%relative_velocity([x(1), v(1)])), f)
        a = f(2)
    end function oc_body_acceleration

    !> The law's states z (components 3 ..), when the law condenses them.
    subroutine oc_condensed_components(self, mask)
        class(one_contact_model), intent(in) :: self
        logical, intent(out) :: mask(:)     !! (2 + nz) .true. for the law's states
        mask = .false.
        if (self%law%condenses_states()) mask(3:) = .true.
    end subroutine oc_condensed_components

    !> k(3:) = (z_s - u(3:)) / c with z_s the law's stage states at the slip of the stage
    !! state u + c k (its x and v read from k(1:2)).
    subroutine oc_condense_stage(self, u, c, k)
        class(one_contact_model), intent(inout) :: self
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative; its states' part on exit
        real(dp) :: ys(size(u)), z_s(size(u) - 2)
        if (.not. self%law%condenses_states() .or. c <= 0.0_dp) return
        ys = u + c * k
        call self%law%stage_states(self%relative_velocity(ys), u(3:), c, z_s)
        k(3:) = (z_s - u(3:)) / c
    end subroutine oc_condense_stage

    !> f at the stage state y: the law's states move at the rates k(3:) of the stage
    !! (condense_stage), and mu is the law's at those rates (`stage_mu`).
    subroutine oc_stage_rhs(self, t, y, k, f)
        class(one_contact_model), intent(inout) :: self
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
    end subroutine oc_stage_rhs

    !> The model's `error_size` (|y|; the body's velocity sized by its contact's slip where
    !! `slip_error_size`) for its one body and contact, the same numbers without the loop over
    !! contacts: a call the specialised kernels resolve and can inline.
    pure subroutine oc_error_size(self, t, y, size_y)
        class(one_contact_model), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s], z)
        real(dp), intent(out) :: size_y(:)  !! the size of each component
        size_y = abs(y)
        if (.not. self%slip_error_size) return
        size_y(2) = min(size_y(2), max(abs(self%relative_velocity(y)), self%con_band(1)))
    end subroutine oc_error_size

    !> The model's `model_contact` as a `one_contact_contact` (see the type).
    subroutine oc_contact_model(self, cs, status)
        class(one_contact_model), intent(in) :: self
        class(contact_system), allocatable, intent(out) :: cs   !! the contact model
        integer, intent(out) :: status                          !! SS_OK or SS_NOT_SETVALUED
        class(contact_system), allocatable :: general
        type(one_contact_contact), allocatable :: occ
        real(dp) :: nb(1), bb(1)
        integer :: i
        call self%model_system%contact_model(general, status)
        select type (general)
        type is (model_contact)
            allocate(occ)
            occ%model_contact = general
            occ%c_w = general%ctri(2, 1)    ! (one body: W is its diagonal, tridiagonal)
            occ%k_w = general%ktri(2, 1)
            call general%normal_forces(0.0_dp, [0.0_dp], nb)      ! (numbers: any t, q)
            call general%slip_offset(0.0_dp, bb)
            occ%n_fix = nb(1)
            occ%b_fix = bb(1)
            occ%frc_fix = [(self%sig%number(self%frc_sig(i)), i = 1, size(self%frc_sig))]
            call move_alloc(occ, cs)
        class default
            call move_alloc(general, cs)
        end select
    end subroutine oc_contact_model

    !> The springs, dampers and forces on the one body [N]: `model_free_forces`' terms and sums
    !! in its order (each element joins the body, side a, to the ground), the forces' signals
    !! read as the numbers they are.
    subroutine occ_force(self, t, q, u, f)
        class(one_contact_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! (1) position [m]
        real(dp), intent(in)  :: u(:)       !! (1) velocity [m/s]
        real(dp), intent(out) :: f(:)       !! (1) springs, dampers and forces [N]
        real(dp) :: xb, vb
        integer :: i
        xb = 0.0_dp
        vb = 0.0_dp
        f(1) = 0.0_dp
        associate (m => self%m)
            do i = 1, size(m%spr_k)
                f(1) = f(1) + (-m%spr_k(i) * (q(1) - xb - m%spr_l0(i)))
            end do
            do i = 1, size(m%dmp_c)
                f(1) = f(1) + (-m%dmp_c(i) * (u(1) - vb))
            end do
        end associate
        do i = 1, size(self%frc_fix)
            f(1) = f(1) + self%frc_fix(i)
        end do
    end subroutine occ_force

    !> x / W with W = m + a c + b k, as the model's tridiagonal solve of one row (x / M where
    !! a = b = 0).
    subroutine occ_solve_w(self, t, q, u, a, b, x)
        class(one_contact_contact), intent(in) :: self
        real(dp), intent(in)    :: t        !! time [s]
        real(dp), intent(in)    :: q(:)     !! position [m]
        real(dp), intent(in)    :: u(:)     !! velocity [m/s]
        real(dp), intent(in)    :: a        !! weight of C [s]
        real(dp), intent(in)    :: b        !! weight of K [s^2]
        real(dp), intent(inout) :: x(:)     !! (1) right-hand side [N s], then the solution [m/s]
        if (a == 0.0_dp .and. b == 0.0_dp) then
            x(1) = x(1) / self%m%mass(1)
        else
            x(1) = x(1) / (self%m%mass(1) + a * self%c_w + b * self%k_w)
        end if
    end subroutine occ_solve_w

    subroutine occ_normal(self, t, q, n)
        class(one_contact_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! position [m]
        real(dp), intent(out) :: n(:)       !! (1) normal force, >= 0 [N]
        n(1) = self%n_fix
    end subroutine occ_normal

    subroutine occ_offset(self, t, b)
        class(one_contact_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(out) :: b(:)       !! (1) -w of the contact [m/s]
        b(1) = self%b_fix
    end subroutine occ_offset

    subroutine occ_offset_rate(self, t, b)
        class(one_contact_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(out) :: b(:)       !! (1) -w' of the contact [m/s^2]
        b(1) = -0.0_dp      ! (the model's -w' of a number: w' = 0)
    end subroutine occ_offset_rate

end module stickslip_one_contact
