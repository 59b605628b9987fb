!> Adaptive explicit Runge-Kutta method of Dormand and Prince, order 5(4), event-free.
!!
!! The meaning of every control follows Hairer's DOPRI5 (Hairer, Norsett & Wanner,
!! Solving ODEs I, sec. II.4-II.6): RMS error norm with per-component scale
!! atol_i + rtol_i max(|y_i|, |y1_i|), PI (Lund) step control with beta = 0.04,
!! safety 0.9, step ratio in [0.2, 10], automatic initial step (HINIT), first same as
!! last, dense output of order 4 (Shampine), stiffness test h |lambda| > 3.25, and
!! counters counted as DOPRI5 counts them (6 evaluations per attempted step plus 2, or plus 1
!! when the initial step h0 is given;
!! no rejection counted before the first accepted step).
!!
!! One addition for non-smooth right-hand sides: a step size floor h_min. When the error
!! test still fails at h_min the step is taken anyway and counted as forced (event-free
!! stepping through a friction discontinuity); `allow_forced = .false.` makes that an
!! error (SS_STEP_TOO_SMALL) instead.
module stickslip_dopri5
    use stickslip_kinds, only: dp, SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_STIFF, &
                               SS_NONFINITE, SS_OUTPUT_FULL, SS_BAD_CONTROL_NAME, SS_INTERRUPTED, SS_BAD_DIM
    use stickslip_ode, only: ode_system, ode_stats, step_controls, method_info, check_problem, check_tolerances, &
                             check_step_controls, all_finite, diverged, output_start, RTOL_MIN, stop_requested, &
                             limit_after_forced, set_erk_constant, check_erk_constants
    use stickslip_scenes, only: slope_scene, belt_scene
    ! every law's type, for the kernels of the laws marked kernel=.true. (stickslip_laws is written
    ! from the registry's LAW_TABLE by tools/gen_kernels.py, as the kernels are)
    use stickslip_laws
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: dopri5_options, dopri5_integrate, dopri5_dense, DOPRI5_DENSE_ROWS

    !> Smallest accepted nonzero rtol: 100 units of round-off.
    real(dp), parameter, public :: DOPRI5_RTOL_MIN = RTOL_MIN

    ! Butcher tableau (exact fractions).
    real(dp), parameter, public :: dp5_c(7) = [0.0_dp, 1.0_dp/5.0_dp, 3.0_dp/10.0_dp, 4.0_dp/5.0_dp, &
                                               8.0_dp/9.0_dp, 1.0_dp, 1.0_dp]
    !! nodes c of the Dormand-Prince tableau
    real(dp), parameter :: a21 = 1.0_dp/5.0_dp
    real(dp), parameter :: a31 = 3.0_dp/40.0_dp, a32 = 9.0_dp/40.0_dp
    real(dp), parameter :: a41 = 44.0_dp/45.0_dp, a42 = -56.0_dp/15.0_dp, a43 = 32.0_dp/9.0_dp
    real(dp), parameter :: a51 = 19372.0_dp/6561.0_dp, a52 = -25360.0_dp/2187.0_dp, &
                           a53 = 64448.0_dp/6561.0_dp, a54 = -212.0_dp/729.0_dp
    real(dp), parameter :: a61 = 9017.0_dp/3168.0_dp, a62 = -355.0_dp/33.0_dp, a63 = 46732.0_dp/5247.0_dp, &
                           a64 = 49.0_dp/176.0_dp, a65 = -5103.0_dp/18656.0_dp
    real(dp), parameter :: a71 = 35.0_dp/384.0_dp, a73 = 500.0_dp/1113.0_dp, a74 = 125.0_dp/192.0_dp, &
                           a75 = -2187.0_dp/6784.0_dp, a76 = 11.0_dp/84.0_dp
    !> Weights of the 5th-order solution (= row 7 of A) and of the 4th-order one.
    real(dp), parameter, public :: dp5_b(7) = [a71, 0.0_dp, a73, a74, a75, a76, 0.0_dp]
    real(dp), parameter, public :: dp5_bhat(7) = [5179.0_dp/57600.0_dp, 0.0_dp, 7571.0_dp/16695.0_dp, &
                                                  393.0_dp/640.0_dp, -92097.0_dp/339200.0_dp, &
                                                  187.0_dp/2100.0_dp, 1.0_dp/40.0_dp]
    !! weights of the embedded 4th-order solution
    !> The full lower-triangular A, for tableau checks.
    real(dp), parameter, public :: dp5_a(7, 7) = reshape([ &
        0.0_dp, a21, a31, a41, a51, a61, a71, &
        0.0_dp, 0.0_dp, a32, a42, a52, a62, 0.0_dp, &
        0.0_dp, 0.0_dp, 0.0_dp, a43, a53, a63, a73, &
        0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a54, a64, a74, &
        0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a65, a75, &
        0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a76, &
        0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], [7, 7])
    ! Error weights e = b - bhat.
    real(dp), parameter :: e1 = 71.0_dp/57600.0_dp, e3 = -71.0_dp/16695.0_dp, e4 = 71.0_dp/1920.0_dp, &
                           e5 = -17253.0_dp/339200.0_dp, e6 = 22.0_dp/525.0_dp, e7 = -1.0_dp/40.0_dp
    ! Dense output of order 4 (Shampine 1986).
    real(dp), parameter :: d1 = -12715105075.0_dp/11282082432.0_dp, d3 = 87487479700.0_dp/32700410799.0_dp, &
                           d4 = -10690763975.0_dp/1880347072.0_dp, d5 = 701980252875.0_dp/199316789632.0_dp, &
                           d6 = -1453857185.0_dp/822651844.0_dp, d7 = 69997945.0_dp/29380423.0_dp

    !> Controls of DOPRI5: the shared ones (h_min, h_max, h0, max_steps, allow_forced,
    !! every_step; h is not read) and Hairer's step-control constants with his defaults.
    type, extends(step_controls) :: dopri5_options
        real(dp) :: safety = 0.9_dp     !! safety factor of the step control
        real(dp) :: fac1 = 0.2_dp       !! smallest step ratio h_new/h
        real(dp) :: fac2 = 10.0_dp      !! largest step ratio h_new/h
        real(dp) :: beta = 0.04_dp      !! PI (Lund) stabilisation exponent (0: plain I control)
        integer  :: nstiff = 1000       !! test stiffness every nstiff accepted steps
        logical  :: stop_on_stiff = .false. !! stop with SS_STIFF when the stiffness test fires
        !> Every-step mode only: when associated, column k >= 2 of this (DOPRI5_DENSE_ROWS n + 1,
        !! size(t_out)) array receives the continuous extension over [t_out(k-1), t_out(k)]:
        !! its coefficients r2..r5 (n each) and the step h [s]; `dopri5_dense` evaluates it.
        real(dp), pointer :: dense_rows(:, :) => null()
        !> Every-step mode only: call sys%step_accepted after each accepted step (the system
        !! sees the step's end, where the last evaluation was, and may end the run there)
        logical :: notify_steps = .false.
    contains
        procedure :: set => set_dopri5_option
        !! set a control by name (the step_controls ones and DOPRI5's own)
    end type dopri5_options

    !> Coefficient vectors per state component stored for a step's continuous extension.
    integer, parameter :: DOPRI5_DENSE_ROWS = 4

    !> What DOPRI5 is and which controls it reads (registry entry).
    type(method_info), parameter, public :: DOPRI5_INFO = method_info(name='dopri5', order=5, &
        adaptive=.true., implicit=.false., controls='rtol atol hmin hmax h0 max_steps allow_forced ' // &
        'every_step safety fac1 fac2 beta_pi nstiff stop_on_stiff fac_forced calm_steps', &
        doc='Dormand-Prince 5(4), adaptive, as Hairer''s DOPRI5')

contains

    !> Set one control by name: DOPRI5's own, then the shared ones.
    function set_dopri5_option(self, name, value) result(status)
        class(dopri5_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts and flags as reals)
        integer :: status
        status = set_erk_constant(name, value, self%safety, self%fac1, self%fac2, self%beta, self%nstiff, &
                                  self%stop_on_stiff)
        if (status == SS_BAD_CONTROL_NAME) status = self%step_controls%set(name, value)
    end function set_dopri5_option

    !> Integrate y' = f(t, y) from t0 to t_end with error control.
    !!
    !! rtol and atol have size 1 (scalar) or size(y0) (per component).
    !! Grid mode: y_out(:, i) receives y(t_out(i)) by dense output. Every-step mode:
    !! (t_out, y_out) receive the initial state and each accepted step.
    !! stats%status: SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_STIFF, SS_NONFINITE,
    !! SS_DIVERGED (a step left sys%state_bound), SS_OUTPUT_FULL or a bad-input code. On a run-time failure the output rows up to
    !! stats%t_reached are valid.
    subroutine dopri5_integrate(sys, t0, y0, t_end, rtol, atol, opts, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys  !! the right-hand side
        real(dp), intent(in)    :: t0            !! initial time [s]
        real(dp), intent(in)    :: y0(:)         !! initial state
        real(dp), intent(in)    :: t_end         !! final time, > t0 [s]
        real(dp), intent(in)    :: rtol(:)       !! relative tolerances, size 1 or size(y0)
        real(dp), intent(in)    :: atol(:)       !! absolute tolerances, size 1 or size(y0)
        type(dopri5_options), intent(in) :: opts !! controls
        real(dp), intent(inout) :: t_out(:)      !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats    !! counters and status

#define KERNEL_ARGS t0, y0, t_end, rtol, atol, opts, t_out, y_out, stats
#include "stickslip_kernel_dispatch.inc"
#undef KERNEL_ARGS
    end subroutine dopri5_integrate

    ! The integrator's instances: generic_kernel for any ode_system (a user's own), and one
    ! for each built-in scene with each static law.
#define KERNEL_BODY "stickslip_dopri5_body.inc"
#include "stickslip_kernel_instances.inc"
#undef KERNEL_BODY

    !> One component of the order-4 continuous extension at the step fraction s in [0, 1]:
    !! r1 is the component at the step's start, r2..r5 its coefficients.
    elemental real(dp) function dense_value(r1, r2, r3, r4, r5, s) result(yq)
        real(dp), intent(in) :: r1, r2, r3, r4, r5, s
        real(dp) :: s1
        s1 = 1.0_dp - s
        yq = r1 + s * (r2 + s1 * (r3 + s * (r4 + s1 * r5)))
    end function dense_value

    !> The state at time tq in a step stored by every-step mode with `dense_rows`: y_start is the
    !! state at the step's start t_start [s], coef the step's column of dense_rows.
    pure function dopri5_dense(y_start, coef, t_start, tq) result(yq)
        real(dp), intent(in) :: y_start(:)  !! state at the step's start
        real(dp), intent(in) :: coef(:)     !! the step's column of dense_rows (4 n + 1)
        real(dp), intent(in) :: t_start     !! the step's start [s]
        real(dp), intent(in) :: tq          !! the time wanted, in the step [s]
        real(dp) :: yq(size(y_start))
        integer :: n
        n = size(y_start)
        yq = dense_value(y_start, coef(1:n), coef(n + 1:2 * n), coef(2 * n + 1:3 * n), coef(3 * n + 1:4 * n), &
                         (tq - t_start) / coef(4 * n + 1))
    end function dopri5_dense

    !> Validate tolerances, the shared controls and DOPRI5's own.
    pure function check_options(n, m, t0, t_end, rtol, atol, opts) result(status)
        integer, intent(in) :: n, m   ! the state's size, the output's
        real(dp), intent(in) :: t0, t_end, rtol(:), atol(:)
        type(dopri5_options), intent(in) :: opts
        integer :: status
        status = check_tolerances(n, rtol, atol)
        if (status == SS_OK) status = check_step_controls(opts, t0, t_end)
        if (status == SS_OK) status = check_erk_constants(opts%safety, opts%fac1, opts%fac2, opts%beta, &
                                                          opts%nstiff)
        if (status == SS_OK .and. associated(opts%dense_rows)) then
            if (size(opts%dense_rows, 1) /= DOPRI5_DENSE_ROWS * n + 1 .or. size(opts%dense_rows, 2) < m) &
                status = SS_BAD_DIM
        end if
    end function check_options

end module stickslip_dopri5
