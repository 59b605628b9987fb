!> The generalized Maxwell-slip model (Al-Bender, Lampaert & Swevers, IEEE TAC 50(11):1883-1887,
!! 2005) in coefficient form: N elementary slip blocks in parallel, element i a spring of
!! stiffness k_i [1/m] (mu per m) with deflection z_i [m] (its state) and slip level
!! alpha_i s(v), s(v) = mu_k + (mu_s - mu_k) exp(-(v/v_s)^2) the Stribeck curve of the
!! bristle laws:
!!
!!     mu = sum_i (k_i z_i + sigma1/N z_i') + sigma2 v,
!!     stick:  z_i' = v,                                   while k_i z_i sgn(v) < alpha_i s(v),
!!     slip:   k_i z_i' = C (sgn(v) - k_i z_i/(alpha_i s(v)))    otherwise,
!!
!! the slip equation being the paper's dF_i/dt = sgn(v) C (1 - F_i/(alpha_i s(v))) with s
!! signed like v (it draws the element's force to alpha_i s(v) sgn(v) at the rate C [1/s],
!! the attraction constant that sets the frictional lag in sliding). An element slips while its
!! spring force, in the direction of motion, is at or above its slip level and sticks
!! otherwise (at v = 0 every element sticks): the mode is a function of the state, as the
!! scenes' integrators need. (The paper keeps a slipping element slipping until the velocity
!! reverses; the two differ only while s(v) rises during sliding, where ours re-sticks and
!! follows alpha_i s(v).)
!!
!! Parameterisation for identification, with few parameters: sigma0 is the total stiffness
!! K = sum k_i (the slope of the force after every reversal), the elements share it equally,
!! k_i = K/N, and their fractions alpha_i (sum 1) come from one shape parameter m
!! (`gms_shape`): alpha_i = q_i / sum q, q_i = 1 - (1 - u_i)^(1/m), u_i = (i - 1/2)/N, the
!! quantiles of a break-away deflection distributed as P(Delta > d) = (1 - d/d_max)^m. The
!! virgin curve (monotone loading from rest at constant s) is mu(x) = sum_i min(k_i x, alpha_i
!! s), whose slope for large N tends to K (1 - x/d_max)^m: m -> 0 one sharp elasto-slip
!! corner, m = 1 a parabola, m large an exponential approach like Dahl's alpha = 1. N = 1 is
!! a single elasto-slip element. sigma1 damps every element in proportion to its stiffness
!! (sigma_i = sigma1 k_i/K), sigma2 is the viscous term; the steady curve is s(v) sgn(v) +
!! sigma2 v, as LuGre's.
!!
!! At a constant velocity the flow is exact (`advance`): a sticking element moves with v until
!! it reaches its slip level and then stays there; a slipping one relaxes to it as
!! exp(-C h/(alpha_i s)).
!!
!! An element on its slip level (within LEVEL_TOL, relative) while the level moves: on a
!! falling level it slips (the slip law draws it down); on a rising level it sticks, so its
!! force rises at k |v| at most, and while the level rises slower than that the element stays
!! on it (the Filippov solution: z_i' = sgn(v) L_i'/k). Along a prescribed motion, whose
!! acceleration is known, `motion_mu` uses that rate, min(|v|, L_i'/k) sgn(v); `advance` keeps
!! such an element stuck, capped at the new level. (`evaluate`, which knows no acceleration,
!! gives an element on its level the slip rate, ~0.)
module stickslip_law_gms
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_law_lugre, only: lugre_law
    use stickslip_friction, only: relax_linear_target
    implicit none
    private

    public :: gms_law

    integer, parameter, public :: SS_BAD_N_ELEMENTS = -172   !! n_elements out of range or not an integer
    integer, parameter, public :: SS_BAD_GMS_SHAPE = -173    !! gms_shape out of range
    integer, parameter, public :: SS_BAD_GMS_C = -174        !! gms_c out of range

    !> Relative band around an element's slip level within which the element is on it: far
    !! above rounding of the level (recomputed from a velocity interpolated two ways), far
    !! below any force of interest [-].
    real(dp), parameter :: LEVEL_TOL = 1.0e-9_dp

    !> Largest number of elements.
    integer, parameter, public :: GMS_MAX_ELEMENTS = 64

    !> Specification of the parameter n_elements (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: N_ELEMENTS_SPEC = param_spec(name='n_elements', default=4.0_dp, &
        lo=1.0_dp, hi=real(GMS_MAX_ELEMENTS, dp), relation='an integer', code=SS_BAD_N_ELEMENTS, &
        doc='number of Maxwell-slip elements')
    !> Specification of the parameter gms_shape (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: GMS_SHAPE_SPEC = param_spec(name='gms_shape', default=1.0_dp, &
        lo=0.0_dp, lo_open=.true., code=SS_BAD_GMS_SHAPE, &
        doc='shape m of the elements'' break-away distribution')
    !> Specification of the parameter gms_c (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: GMS_C_SPEC = param_spec(name='gms_c', default=100.0_dp, &
        unit='1/s', lo=0.0_dp, lo_open=.true., code=SS_BAD_GMS_C, &
        doc='attraction constant C of sliding elements (mu per s)')

    !> The generalized Maxwell-slip model; parameters mu_s, mu_k, v_s, sigma0 (total
    !! stiffness), sigma1, sigma2, n_elements, gms_shape, gms_c; states z_1..z_N [m].
    type, extends(lugre_law) :: gms_law
        integer :: n = 4                       !! number of elements N
        real(dp) :: c = 100.0_dp               !! attraction constant C [1/s]
        real(dp) :: shape = 1.0_dp             !! shape m of the break-away distribution [-]
        real(dp) :: k = 0.0_dp                 !! stiffness of each element, sigma0/N [1/m]
        real(dp), allocatable :: frac(:)       !! fractions alpha_i of the slip level, sum 1 [-]
    contains
        !> Read and check the parameters; SS_OK or the code naming the bad one.
        procedure :: init => gms_init
        !> Number of internal states: N.
        procedure :: n_states => gms_n_states
        !> Name and unit of state i, 'z<i> [m]'.
        procedure :: state_label => gms_label
        !> mu and the element rates at (v, z).
        procedure :: evaluate => gms_evaluate
        !> Flow over a substep of prescribed motion (exact at a constant velocity).
        procedure :: advance => gms_advance
        procedure :: condenses_states => gms_condenses
        !! .true.: gms_stage_states solves the elements' stage
        procedure :: stage_states => gms_stage_states
        !! each element's implicit stage in closed form (stick, relax, or on its slip level)
        procedure :: stage_mu => gms_stage_mu
        !! mu = sum (k z_i + sigma1/N z_i') + sigma2 v with the stage's rates z_i'
        procedure :: motion_mu => gms_motion_mu
        !! mu at a sample of prescribed motion: elements on a moving level classified with its rate
    end type gms_law

contains

    function gms_init(self, p) result(status)
        class(gms_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        real(dp) :: n, q(GMS_MAX_ELEMENTS)
        integer :: i
        status = self%lugre_law%init(p)
        call param_read(p, N_ELEMENTS_SPEC, n, status)
        call param_read(p, GMS_SHAPE_SPEC, self%shape, status)
        call param_read(p, GMS_C_SPEC, self%c, status)
        if (status == SS_OK .and. n /= aint(n)) status = SS_BAD_N_ELEMENTS
        if (status /= SS_OK) return
        self%n = int(n)
        self%k = self%sigma0 / real(self%n, dp)
        do i = 1, self%n
            q(i) = 1.0_dp - (1.0_dp - (real(i, dp) - 0.5_dp) / real(self%n, dp))**(1.0_dp / self%shape)
        end do
        ! a tiny shape underflows the small quantiles to 0: every element then at the mean
        if (.not. sum(q(1:self%n)) > 0.0_dp .or. any(q(1:self%n) <= 0.0_dp)) q(1:self%n) = 1.0_dp
        self%frac = q(1:self%n) / sum(q(1:self%n))
    end function gms_init

    pure integer function gms_n_states(self)
        class(gms_law), intent(in) :: self
        gms_n_states = self%n
    end function gms_n_states

    pure function gms_label(self, i) result(label)
        class(gms_law), intent(in) :: self
        integer, intent(in) :: i           !! state index, 1 .. N
        character(len=:), allocatable :: label
        character(len=12) :: buf
        write (buf, '(i0)') i
        label = 'z' // trim(buf) // ' [m]'
    end function gms_label

    !> mu = sum (k z_i + sigma1/N z_i') + sigma2 v with the stick and slip rates (module notes).
    subroutine gms_evaluate(self, v, z, mu_hold, mu, dz)
        class(gms_law), intent(inout) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in)  :: z(:)       !! element deflections [m]
        real(dp), intent(in)  :: mu_hold    !! holding coefficient [-] (unused)
        real(dp), intent(out) :: mu         !! friction coefficient [-]
        real(dp), intent(out) :: dz(:)      !! element deflection rates [m/s]
        real(dp) :: s, sg, level
        integer :: i
        s = self%g(v)
        sg = sign(1.0_dp, v)
        do i = 1, self%n
            level = self%frac(i) * s
            ! (to rounding: `advance` leaves a element that reached its level at level/k)
            if (v /= 0.0_dp .and. self%k * z(i) * sg >= level * (1.0_dp - 4.0_dp * epsilon(1.0_dp))) then
                dz(i) = self%c / self%k * (sg - self%k * z(i) / level)
            else
                dz(i) = v
            end if
        end do
        mu = self%k * sum(z(1:self%n)) + self%sigma1 / real(self%n, dp) * sum(dz(1:self%n)) + self%sigma2 * v
    end subroutine gms_evaluate

    !> mu = sum (k z_i + sigma1/N z_i') + sigma2 v at a sample of prescribed motion, each
    !! element's rate from the law's definition with the level's rate L_i' = alpha_i s'(v) a:
    !! below its level (by more than LEVEL_TOL) it sticks, z_i' = v; above, it slips; on it,
    !! z_i' = min(|v|, L_i'/k) sgn(v) while the level rises and the slip rate (~0) otherwise
    !! (module notes). Continuous in the states where `evaluate`'s rate jumps from v to 0 at
    !! the level.
    subroutine gms_motion_mu(self, v, a, z, mu)
        class(gms_law), intent(inout) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in)  :: a          !! its rate [m/s^2]
        real(dp), intent(in)  :: z(:)       !! element deflections [m]
        real(dp), intent(out) :: mu         !! friction coefficient [-]
        real(dp) :: s, sdot, sg, level, f, hv, dz(self%n)
        integer :: i
        if (v == 0.0_dp) then
            mu = self%k * sum(z(1:self%n))
            return
        end if
        s = self%g(v)
        ! ds/dt = s'(v) a, s' by a central difference (s is smooth away from v = 0)
        hv = 1.0e-6_dp * abs(v)
        sdot = (self%g(v + hv) - self%g(v - hv)) / (2.0_dp * hv) * a
        sg = sign(1.0_dp, v)
        do i = 1, self%n
            level = self%frac(i) * s
            f = self%k * z(i) * sg
            if (f < level * (1.0_dp - LEVEL_TOL)) then
                dz(i) = v
            else if (f <= level * (1.0_dp + LEVEL_TOL) .and. sdot > 0.0_dp) then
                dz(i) = sg * min(abs(v), self%frac(i) * sdot / self%k)
            else
                dz(i) = self%c / self%k * (sg - self%k * z(i) / level)
            end if
        end do
        mu = self%k * sum(z(1:self%n)) + self%sigma1 / real(self%n, dp) * sum(dz) + self%sigma2 * v
    end subroutine gms_motion_mu

    pure real(dp) function gms_stage_mu(self, v, z, dz) result(mu)
        class(gms_law), intent(in) :: self
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: z(:)        !! element deflections [m]
        real(dp), intent(in) :: dz(:)       !! their rates [m/s]
        mu = self%k * sum(z(1:self%n)) + self%sigma1 / real(self%n, dp) * sum(dz(1:self%n)) + self%sigma2 * v
    end function gms_stage_mu

    pure logical function gms_condenses(self)
        class(gms_law), intent(in) :: self
        gms_condenses = .true.
    end function gms_condenses

    !> The stage z_s = z_u + c dz(v, z_s) of every element at the relative velocity v. In the
    !! element force p = k z sgn(v) and its level L = alpha_i s(v) the rate is k |v| below L,
    !! C (1 - p/L) above it and anything between at L, so p - c dp/dt is increasing and the
    !! stage has one solution: p_u + c k |v| if that is below L (the element sticks through
    !! the stage), (p_u + c C)/(1 + c C/L) if p_u is above L (it relaxes: backward Euler of the
    !! linear slip law), L otherwise (it reaches its level and stays on it: the Filippov
    !! solution, where the equation with `evaluate`'s rates has none). At v = 0 every element
    !! sticks: z_s = z_u.
    pure subroutine gms_stage_states(self, v, z_u, c, z_s)
        class(gms_law), intent(in) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity at the stage [m/s]
        real(dp), intent(in)  :: z_u(:)     !! the stage's base deflections [m]
        real(dp), intent(in)  :: c          !! coefficient of the rate [s]
        real(dp), intent(out) :: z_s(:)     !! the stage's deflections [m]
        real(dp) :: s, sg, level, p_u, p_s
        integer :: i
        if (v == 0.0_dp) then
            z_s = z_u
            return
        end if
        s = self%g(v)
        sg = sign(1.0_dp, v)
        do i = 1, self%n
            level = self%frac(i) * s
            p_u = self%k * z_u(i) * sg
            if (p_u + c * self%k * abs(v) < level) then
                z_s(i) = z_u(i) + c * v
                cycle
            else if (p_u > level) then
                p_s = (p_u + c * self%c) / (1.0_dp + c * self%c / level)
            else
                p_s = level
            end if
            z_s(i) = p_s * sg / self%k
        end do
    end subroutine gms_stage_states

    !> The flow over a substep of prescribed motion (module notes), in the element forces
    !! f_i = k z_i sgn(dx) with the levels L_i = alpha_i s(v) going from L_i(v0) to L_i(v1):
    !! a sticking element, or one on its level (within LEVEL_TOL) while the level does not fall,
    !! gains k |dx| and is capped at L_i(v1) (it reached its level and follows it); one above
    !! its level, or on a falling level, slips: it relaxes, df/dt = (C/L)(L - f), by the
    !! first-order-hold exponential step with C/L at the mean level, and re-sticks at L_i(v1)
    !! if that leaves it below. Exact at a constant velocity; at a varying one the error is of the order of the
    !! level's change over the substep where C h/L is neither small nor large.
    subroutine gms_advance(self, dx, h, v0, v1, z, status)
        class(gms_law), intent(inout) :: self
        real(dp), intent(in)    :: dx       !! travel over the substep [m]
        real(dp), intent(in)    :: h        !! substep [s]
        real(dp), intent(in)    :: v0       !! relative velocity at the start [m/s]
        real(dp), intent(in)    :: v1       !! relative velocity at the end [m/s]
        real(dp), intent(inout) :: z(:)     !! element deflections at the start; at the end [m]
        integer, intent(out)    :: status   !! SS_OK
        real(dp) :: s0, s1, sg, l0, l1, f
        integer :: i
        status = SS_OK
        if (dx == 0.0_dp) return
        s0 = self%g(v0)
        s1 = self%g(v1)
        sg = sign(1.0_dp, dx)
        do i = 1, self%n
            l0 = self%frac(i) * s0
            l1 = self%frac(i) * s1
            f = self%k * z(i) * sg
            if (f < l0 * (1.0_dp - LEVEL_TOL) .or. (f <= l0 * (1.0_dp + LEVEL_TOL) .and. l1 >= l0)) then
                f = min(f + self%k * abs(dx), l1)
            else
                f = max(relax_linear_target(f, l0, l1, self%c * h * 2.0_dp / (l0 + l1)), l1)
            end if
            z(i) = sg * f / self%k
        end do
    end subroutine gms_advance

end module stickslip_law_gms
