!> Backward (implicit) Euler method, order 1, L-stable, fixed step:
!! y1 = y + h f(t + h, y1), solved by Newton's method with the Jacobian once per step.
!!
!! On Coulomb and Karnopp (laws with modes) each stage is solved over the law's modes
!! instead of by Newton across the jump (stickslip_fixed_implicit).
!! Grid, output, Newton and statuses: see stickslip_fixed_implicit (the driver and the Newton
!! solve are stickslip_fixed_implicit_body.inc, instantiated here around stage_setup and
!! stage_finish). Evaluations per step: 1 + Newton iterations (+ n for a finite-difference
!! Jacobian), and 1-2 more in steps that contain a requested output time.
module stickslip_implicit_euler
    use stickslip_kinds, only: dp, SS_OK, SS_STEP_BUDGET, SS_NONFINITE, SS_OUTPUT_FULL, SS_INTERRUPTED, &
                               SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE, SS_JUMP_MANY_CONTACTS
    use stickslip_ode, only: ode_system, ode_stats, method_info, check_problem, output_start, fixed_steps, step_end, &
                             stop_requested, all_finite, diverged, hermite, count_nonunique
    use stickslip_fixed_implicit, only: newton_controls, NEWTON_CONTROL_NAMES, check_newton_controls, ROUNDING_FLOOR
    use stickslip_linalg, only: lu_decompose, lu_solve, band_decompose, band_solve
    use stickslip_one_contact, only: one_contact_model
    use stickslip_modal_contacts, only: model_modal_contacts
    use stickslip_model_system, only: model_system
    use stickslip_friction, only: MODE_MU, MODE_V, between
    ! every law's type, for the kernels of the laws marked kernel=.true. (stickslip_laws is written
    ! from the registry's LAW_TABLE by tools/gen_kernels.py, as the kernels are)
    use stickslip_laws
    use stickslip_contact_solver, only: modal_choose
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
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

contains

    !> Integrate y' = f(t, y) from t0 to t_end with backward Euler and fixed step opts%h.
    !!
    !! A built-in scene with a static law runs a specialised kernel (its analytic Jacobian,
    !! which is what its jacobian binding returns); any other system the generic one.
    !! Grid mode: y_out(:, i) receives y(t_out(i)) (cubic Hermite inside a step). Every-step
    !! mode: (t_out, y_out) receive the initial state and each step. stats%status: SS_OK,
    !! SS_STEP_BUDGET, SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE, SS_NONFINITE,
    !! SS_DIVERGED (a step left sys%state_bound), SS_OUTPUT_FULL or a bad-input code (SS_BAD_H, SS_BAD_MAX_STEPS, SS_BAD_NIT,
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
        real(dp), parameter :: par(1) = [0.0_dp]         ! backward Euler has no parameter

        stats%status = check_problem(t0, y0, t_end, t_out, y_out, opts%every_step)
        if (stats%status == SS_OK) stats%status = check_newton_controls(opts)
        if (stats%status /= SS_OK) return

#define KERNEL_ARGS t0, y0, t_end, opts, par, t_out, y_out, stats
#define NONSMOOTH_KERNEL
#include "stickslip_kernel_dispatch.inc"
#undef NONSMOOTH_KERNEL
#undef KERNEL_ARGS
    end subroutine implicit_euler_integrate

    ! The method's instances: generic_kernel for any ode_system (a user's own), and one for
    ! each built-in scene with each static law (its analytic Jacobian inlined).
#define KERNEL_BODY "stickslip_fixed_implicit_body.inc"
#define NONSMOOTH_KERNEL
#include "stickslip_kernel_instances.inc"
#undef NONSMOOTH_KERNEL
#undef KERNEL_BODY

    !> The stage of the step from (t, y) of size h: k = f(t + h, y + h k) (ydot not read:
    !! it is the Newton guess, f at the end of the last step).
    pure subroutine stage_setup(par, t, h, y, ydot, tau, u, ch)
        real(dp), intent(in)  :: par(:)     !! (none)
        real(dp), intent(in)  :: t          !! time at the start of the step [s]
        real(dp), intent(in)  :: h          !! step size [s]
        real(dp), intent(in)  :: y(:)       !! state at t
        real(dp), intent(in)  :: ydot(:)    !! the last stage derivative
        real(dp), intent(out) :: tau        !! time of the stage [s]
        real(dp), intent(out) :: u(:)       !! the stage state is u + ch k
        real(dp), intent(out) :: ch         !! coefficient of k in the stage state [s]
        tau = t + h
        u = y
        ch = h
    end subroutine stage_setup

    !> y1 = y + h k; the next guess ydot = k.
    pure subroutine stage_finish(par, h, y, k, ydot, y1)
        real(dp), intent(in)    :: par(:)   !! (none)
        real(dp), intent(in)    :: h        !! step size [s]
        real(dp), intent(in)    :: y(:)     !! state at the start of the step
        real(dp), intent(in)    :: k(:)     !! the stage's solution, f(t + h, y1)
        real(dp), intent(inout) :: ydot(:)  !! k on exit
        real(dp), intent(out)   :: y1(:)    !! state at the end of the step
        y1 = y + h * k
        ydot = k
    end subroutine stage_finish

end module stickslip_implicit_euler
