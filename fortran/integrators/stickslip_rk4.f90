!> Classical fixed-step Runge-Kutta method of order 4, event-free.
!!
!! Steps are t_i = t0 + i h; the last one is shortened to end exactly at t_end.
!! Output at requested times uses the cubic Hermite interpolant through (y, f) at both
!! ends of the step (order 4, like the method), which costs no extra evaluation since
!! f at the end of a step is the first stage of the next one (first same as last).
!! Evaluations: 1 + 4 per step.
module stickslip_rk4
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_H, SS_BAD_MAX_STEPS, SS_STEP_BUDGET, &
                               SS_NONFINITE, SS_OUTPUT_FULL, SS_INTERRUPTED, SS_DIVERGED
    use stickslip_ode, only: ode_system, ode_stats, method_info, check_problem, output_start, hermite, fixed_steps, &
                             step_end, STOP_CHECK_MASK
    use stickslip_scenes, only: slope_scene, belt_scene
    ! every law's type, for the kernels of the laws marked kernel=.true. (stickslip_laws is written
    ! from the registry's LAW_TABLE by tools/gen_kernels.py, as the kernels are)
    use stickslip_laws
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: rk4_integrate

    !> What RK4 is and which controls it reads (registry entry).
    type(method_info), parameter, public :: RK4_INFO = method_info(name='rk4', order=4, &
        adaptive=.false., implicit=.false., controls='h max_steps every_step', &
        doc='classical Runge-Kutta, fixed step')

    !> Butcher tableau of the classical method (exact fractions).
    real(dp), parameter, public :: rk4_c(4) = [0.0_dp, 0.5_dp, 0.5_dp, 1.0_dp]
    real(dp), parameter, public :: rk4_b(4) = [1.0_dp/6.0_dp, 1.0_dp/3.0_dp, 1.0_dp/3.0_dp, 1.0_dp/6.0_dp]
    !! weights b of the classical tableau

contains

    !> Integrate y' = f(t, y) from t0 to t_end with fixed step h.
    !!
    !! Grid mode (every_step = .false.): y_out(:, i) receives y(t_out(i)).
    !! Every-step mode: (t_out, y_out) receive the initial state and each step.
    !! stats%status: SS_OK, SS_STEP_BUDGET (more than max_steps steps needed; output
    !! up to stats%t_reached is valid), SS_NONFINITE, SS_DIVERGED (a step left the system's
    !! `state_bound`), SS_OUTPUT_FULL or a bad-input code.
    subroutine rk4_integrate(sys, t0, y0, t_end, h, t_out, y_out, stats, every_step, max_steps, stop_flag)
        class(ode_system), intent(inout) :: sys  !! the right-hand side
        real(dp), intent(in)    :: t0            !! initial time [s]
        real(dp), intent(in)    :: y0(:)         !! initial state
        real(dp), intent(in)    :: t_end         !! final time, > t0 [s]
        real(dp), intent(in)    :: h             !! step size, > 0 [s]
        real(dp), intent(inout) :: t_out(:)      !! requested output times (grid) or step times (every step) [s]
        real(dp), intent(inout) :: y_out(:, :)   !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats    !! counters and status
        logical, intent(in), optional :: every_step     !! output every step (default .false.)
        integer(8), intent(in), optional :: max_steps   !! step budget (default: unlimited)
        !> Stop with SS_INTERRUPTED once another thread sets it nonzero (looked at every
        !! STOP_CHECK_MASK + 1 steps).
        integer, pointer, intent(in), optional :: stop_flag

#define KERNEL_ARGS t0, y0, t_end, h, t_out, y_out, stats, every_step, max_steps, stop_flag
#include "stickslip_kernel_dispatch.inc"
#undef KERNEL_ARGS
    end subroutine rk4_integrate

    ! The integrator's instances: generic_kernel for any ode_system (a user's own), and one
    ! for each built-in scene with each static law.
#define KERNEL_BODY "stickslip_rk4_body.inc"
#include "stickslip_kernel_instances.inc"
#undef KERNEL_BODY

end module stickslip_rk4
