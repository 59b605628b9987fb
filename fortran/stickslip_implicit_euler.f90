!> Backward (implicit) Euler method, order 1, L-stable, fixed step:
!! y1 = y + h f(t + h, y1), solved by Newton's method with the Jacobian once per step.
!!
!! Grid, output, Newton and statuses: see stickslip_fixed_implicit. Evaluations per step:
!! 1 + Newton iterations (+ n for a finite-difference Jacobian), and 1-2 more in steps that
!! contain a requested output time.
module stickslip_implicit_euler
    use stickslip_kinds, only: dp
    use stickslip_ode, only: ode_system, ode_stats, method_info
    use stickslip_fixed_implicit, only: newton_controls, NEWTON_CONTROL_NAMES, fixed_stepper, fixed_implicit_integrate, &
                                        solve_stage
    implicit none
    private

    public :: implicit_euler_options, implicit_euler_integrate

    !> Controls of backward Euler: h (> 0), max_steps, every_step and the Newton controls
    !! newton_rtol, newton_atol, newton_max_iter.
    type, extends(newton_controls) :: implicit_euler_options
    end type implicit_euler_options

    !> What implicit Euler is and which controls it reads (registry entry).
    type(method_info), parameter, public :: IMPLICIT_EULER_INFO = method_info(name='implicit_euler', &
        order=1, adaptive=.false., implicit=.true., controls='h max_steps every_step ' // NEWTON_CONTROL_NAMES, &
        doc='backward (implicit) Euler, fixed step')

    !> The method's state: the last stage derivative (the next Newton guess).
    type, extends(fixed_stepper) :: euler_stepper
        real(dp), allocatable :: k(:)   !! f(t, y) at the end of the last step [units of y / s]
    contains
        procedure :: start => euler_start
        procedure :: step => euler_step
    end type euler_stepper

contains

    !> Integrate y' = f(t, y) from t0 to t_end with backward Euler and fixed step opts%h.
    !!
    !! Grid mode: y_out(:, i) receives y(t_out(i)) (cubic Hermite inside a step). Every-step
    !! mode: (t_out, y_out) receive the initial state and each step. stats%status: SS_OK,
    !! SS_STEP_BUDGET, SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE, SS_NONFINITE,
    !! SS_OUTPUT_FULL or a bad-input code (SS_BAD_H, SS_BAD_MAX_STEPS, SS_BAD_NIT,
    !! SS_BAD_NEWTON_TOL, ...). On a run-time failure the rows up to stats%t_reached are valid.
    subroutine implicit_euler_integrate(sys, t0, y0, t_end, opts, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys          !! the right-hand side (and its Jacobian)
        real(dp), intent(in)    :: t0                    !! initial time [s]
        real(dp), intent(in)    :: y0(:)                 !! initial state
        real(dp), intent(in)    :: t_end                 !! final time, > t0 [s]
        type(implicit_euler_options), intent(in) :: opts !! controls
        real(dp), intent(inout) :: t_out(:)              !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)           !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats            !! counters and status
        type(euler_stepper) :: stepper
        call fixed_implicit_integrate(sys, stepper, t0, y0, t_end, opts, t_out, y_out, stats)
    end subroutine implicit_euler_integrate

    subroutine euler_start(self, f0)
        class(euler_stepper), intent(inout) :: self
        real(dp), intent(in) :: f0(:)       !! f(t0, y0)
        self%k = f0
    end subroutine euler_start

    !> y1 = y + h k with k = f(t + h, y + h k).
    subroutine euler_step(self, sys, t, h, y, y1, ctl, stats)
        class(euler_stepper), intent(inout) :: self
        class(ode_system), intent(inout) :: sys
        real(dp), intent(in)  :: t              !! time at the start of the step [s]
        real(dp), intent(in)  :: h              !! step size [s]
        real(dp), intent(in)  :: y(:)           !! state at t
        real(dp), intent(out) :: y1(:)          !! state at t + h
        class(newton_controls), intent(in) :: ctl   !! Newton controls
        type(ode_stats), intent(inout) :: stats     !! counters, status
        call solve_stage(sys, t + h, y, h, self%k, ctl, stats)
        y1 = y + h * self%k
    end subroutine euler_step

end module stickslip_implicit_euler
