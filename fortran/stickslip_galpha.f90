!> Generalized-alpha method for first-order systems (Jansen, Whiting & Hulbert 2000),
!! order 2, fixed step, with numerical damping controlled by rho_inf (the spectral radius
!! of its amplification factor as h |lambda| -> infinity):
!!
!!   alpha_m = (3 - rho_inf) / (2 (1 + rho_inf)),  alpha_f = 1 / (1 + rho_inf),
!!   gamma = 1/2 + alpha_m - alpha_f,
!!   y_{n+1} = y_n + h ydot_n + gamma h (ydot_{n+1} - ydot_n),
!!   ydot_n + alpha_m (ydot_{n+1} - ydot_n) = f(t_n + alpha_f h, y_n + alpha_f (y_{n+1} - y_n)),
!!
!! with ydot_0 = f(t0, y0). With k = ydot_{n+alpha_m} as unknown the equation is
!! k = f(t_n + alpha_f h, u + (alpha_f gamma / alpha_m) h k), u = y_n + alpha_f h (1 - gamma/alpha_m) ydot_n,
!! solved by Newton's method with the Jacobian once per step.
!! Grid, output, Newton and statuses: see stickslip_fixed_implicit.
module stickslip_galpha
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_RHO_INF
    use stickslip_ode, only: ode_system, ode_stats, method_info
    use stickslip_fixed_implicit, only: newton_controls, NEWTON_CONTROL_NAMES, fixed_stepper, fixed_implicit_integrate, &
                                        solve_stage
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: galpha_options, galpha_integrate, galpha_parameters

    !> Controls of generalized-alpha: h (> 0), max_steps, every_step, the Newton controls
    !! (newton_rtol, newton_atol, newton_max_iter) and rho_inf.
    type, extends(newton_controls) :: galpha_options
        real(dp) :: rho_inf = 0.5_dp    !! spectral radius at h |lambda| -> infinity, in [0, 1] [-]
    contains
        !> Set one control by name, then fall back to the parent types controls.
        procedure :: set => set_galpha_option
    end type galpha_options

    !> What generalized-alpha is and which controls it reads (registry entry).
    type(method_info), parameter, public :: GALPHA_INFO = method_info(name='galpha', order=2, &
        adaptive=.false., implicit=.true., controls='h max_steps every_step rho_inf ' // NEWTON_CONTROL_NAMES, &
        doc='generalized-alpha (Jansen, Whiting & Hulbert 2000), fixed step')

    !> The method's state: its derivative variable ydot_n and its parameters.
    type, extends(fixed_stepper) :: galpha_stepper
        real(dp), allocatable :: ydot(:)    !! ydot_n [units of y / s]
        real(dp) :: alpha_m = 0.0_dp, alpha_f = 0.0_dp, gamma = 0.0_dp
    contains
        procedure :: start => galpha_start
        procedure :: step => galpha_step
    end type galpha_stepper

contains

    !> Set one control by name: rho_inf, then the Newton and shared ones.
    function set_galpha_option(self, name, value) result(status)
        class(galpha_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value
        integer :: status
        if (name == 'rho_inf') then
            self%rho_inf = value
            status = SS_OK
        else
            status = self%newton_controls%set(name, value)
        end if
    end function set_galpha_option

    !> alpha_m, alpha_f and gamma of rho_inf (second order, unconditionally stable).
    pure subroutine galpha_parameters(rho_inf, alpha_m, alpha_f, gamma)
        real(dp), intent(in)  :: rho_inf    !! spectral radius at infinity, in [0, 1] [-]
        real(dp), intent(out) :: alpha_m    !! weight of ydot_{n+1} in the derivative [-]
        real(dp), intent(out) :: alpha_f    !! weight of y_{n+1} in the state [-]
        real(dp), intent(out) :: gamma      !! weight of ydot_{n+1} in the update [-]
        alpha_m = (3.0_dp - rho_inf) / (2.0_dp * (1.0_dp + rho_inf))
        alpha_f = 1.0_dp / (1.0_dp + rho_inf)
        gamma = 0.5_dp + alpha_m - alpha_f
    end subroutine galpha_parameters

    !> Integrate y' = f(t, y) from t0 to t_end with generalized-alpha and fixed step opts%h.
    !!
    !! Grid mode: y_out(:, i) receives y(t_out(i)) (cubic Hermite with f at both ends inside a
    !! step). Every-step mode: (t_out, y_out) receive the initial state and each step.
    !! stats%status: SS_OK, SS_STEP_BUDGET, SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE,
    !! SS_NONFINITE, SS_OUTPUT_FULL or a bad-input code (SS_BAD_RHO_INF, SS_BAD_H, SS_BAD_NIT,
    !! SS_BAD_NEWTON_TOL, ...). On a run-time failure the rows up to stats%t_reached are valid.
    subroutine galpha_integrate(sys, t0, y0, t_end, opts, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys          !! the right-hand side (and its Jacobian)
        real(dp), intent(in)    :: t0                    !! initial time [s]
        real(dp), intent(in)    :: y0(:)                 !! initial state
        real(dp), intent(in)    :: t_end                 !! final time, > t0 [s]
        type(galpha_options), intent(in) :: opts         !! controls
        real(dp), intent(inout) :: t_out(:)              !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)           !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats            !! counters and status
        type(galpha_stepper) :: stepper
        if (.not. ieee_is_finite(opts%rho_inf) .or. opts%rho_inf < 0.0_dp .or. opts%rho_inf > 1.0_dp) then
            stats%status = SS_BAD_RHO_INF
            return
        end if
        call galpha_parameters(opts%rho_inf, stepper%alpha_m, stepper%alpha_f, stepper%gamma)
        call fixed_implicit_integrate(sys, stepper, t0, y0, t_end, opts, t_out, y_out, stats)
    end subroutine galpha_integrate

    subroutine galpha_start(self, f0)
        class(galpha_stepper), intent(inout) :: self
        real(dp), intent(in) :: f0(:)       !! f(t0, y0)
        self%ydot = f0
    end subroutine galpha_start

    !> One step: solve for k = ydot_{n+alpha_m}, then ydot_{n+1} and y_{n+1}.
    subroutine galpha_step(self, sys, t, h, y, y1, ctl, stats)
        class(galpha_stepper), intent(inout) :: self
        class(ode_system), intent(inout) :: sys
        real(dp), intent(in)  :: t              !! time at the start of the step [s]
        real(dp), intent(in)  :: h              !! step size [s]
        real(dp), intent(in)  :: y(:)           !! state at t
        real(dp), intent(out) :: y1(:)          !! state at t + h
        class(newton_controls), intent(in) :: ctl   !! Newton controls
        type(ode_stats), intent(inout) :: stats     !! counters, status
        real(dp) :: k(size(y)), ydot1(size(y))
        k = self%ydot
        call solve_stage(sys, t + self%alpha_f * h, &
                         y + (self%alpha_f * h * (1.0_dp - self%gamma / self%alpha_m)) * self%ydot, &
                         self%alpha_f * self%gamma / self%alpha_m * h, k, ctl, stats)
        if (stats%status /= SS_OK) then
            y1 = y
            return
        end if
        ydot1 = self%ydot + (k - self%ydot) / self%alpha_m
        y1 = y + h * self%ydot + (self%gamma * h) * (ydot1 - self%ydot)
        self%ydot = ydot1
    end subroutine galpha_step

end module stickslip_galpha
