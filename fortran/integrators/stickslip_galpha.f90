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
!! On Coulomb and Karnopp (laws with modes) each stage is solved over the law's modes
!! instead of by Newton across the jump (stickslip_fixed_implicit).
!! Grid, output, Newton and statuses: see stickslip_fixed_implicit (the driver and the Newton
!! solve are stickslip_fixed_implicit_body.inc, instantiated here around stage_setup and
!! stage_finish).
module stickslip_galpha
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_RHO_INF, SS_STEP_BUDGET, SS_NONFINITE, SS_OUTPUT_FULL, &
                               SS_INTERRUPTED, SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE, SS_JUMP_MANY_CONTACTS
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
    !! SS_NONFINITE, SS_DIVERGED (a step left sys%state_bound), SS_OUTPUT_FULL or a bad-input
    !! code (SS_BAD_RHO_INF, SS_BAD_H, SS_BAD_NIT,
    !! SS_BAD_NEWTON_TOL, ...). On a run-time failure the rows up to stats%t_reached are valid.
    !! A built-in scene with a static law runs a specialised kernel (its analytic Jacobian,
    !! which is what its jacobian binding returns); any other system the generic one.
    subroutine galpha_integrate(sys, t0, y0, t_end, opts, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys          !! the right-hand side (and its Jacobian)
        real(dp), intent(in)    :: t0                    !! initial time [s]
        real(dp), intent(in)    :: y0(:)                 !! initial state
        real(dp), intent(in)    :: t_end                 !! final time, > t0 [s]
        type(galpha_options), intent(in) :: opts         !! controls
        real(dp), intent(inout) :: t_out(:)              !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)           !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats            !! counters and status
        real(dp) :: par(3)      ! alpha_m, alpha_f, gamma
        if (.not. ieee_is_finite(opts%rho_inf) .or. opts%rho_inf < 0.0_dp .or. opts%rho_inf > 1.0_dp) then
            stats%status = SS_BAD_RHO_INF
            return
        end if
        stats%status = check_problem(t0, y0, t_end, t_out, y_out, opts%every_step)
        if (stats%status == SS_OK) stats%status = check_newton_controls(opts)
        if (stats%status /= SS_OK) return
        call galpha_parameters(opts%rho_inf, par(1), par(2), par(3))

#define KERNEL_ARGS t0, y0, t_end, opts, par, t_out, y_out, stats
#define NONSMOOTH_KERNEL
#include "stickslip_kernel_dispatch.inc"
#undef NONSMOOTH_KERNEL
#undef KERNEL_ARGS
    end subroutine galpha_integrate

    ! The method's instances: generic_kernel for any ode_system (a user's own), and one for
    ! each built-in scene with each static law (its analytic Jacobian inlined).
#define KERNEL_BODY "stickslip_fixed_implicit_body.inc"
#define NONSMOOTH_KERNEL
#include "stickslip_kernel_instances.inc"
#undef NONSMOOTH_KERNEL
#undef KERNEL_BODY

    !> The stage of the step from (t, y) of size h: k = ydot_{n+alpha_m} solves
    !! k = f(t + alpha_f h, u + (alpha_f gamma / alpha_m) h k), u = y + alpha_f h (1 - gamma/alpha_m) ydot.
    pure subroutine stage_setup(par, t, h, y, ydot, tau, u, ch)
        real(dp), intent(in)  :: par(:)     !! alpha_m, alpha_f, gamma (galpha_parameters)
        real(dp), intent(in)  :: t          !! time at the start of the step [s]
        real(dp), intent(in)  :: h          !! step size [s]
        real(dp), intent(in)  :: y(:)       !! state at t, y_n
        real(dp), intent(in)  :: ydot(:)    !! ydot_n
        real(dp), intent(out) :: tau        !! time of the stage [s]
        real(dp), intent(out) :: u(:)       !! the stage state is u + ch k
        real(dp), intent(out) :: ch         !! coefficient of k in the stage state [s]
        associate (alpha_m => par(1), alpha_f => par(2), gamma => par(3))
            tau = t + alpha_f * h
            u = y + (alpha_f * h * (1.0_dp - gamma / alpha_m)) * ydot
            ch = alpha_f * gamma / alpha_m * h
        end associate
    end subroutine stage_setup

    !> From the stage's solution k: ydot_{n+1} and y_{n+1}.
    pure subroutine stage_finish(par, h, y, k, ydot, y1)
        real(dp), intent(in)    :: par(:)   !! alpha_m, alpha_f, gamma (galpha_parameters)
        real(dp), intent(in)    :: h        !! step size [s]
        real(dp), intent(in)    :: y(:)     !! y_n
        real(dp), intent(in)    :: k(:)     !! the stage's solution, ydot_{n+alpha_m}
        real(dp), intent(inout) :: ydot(:)  !! ydot_n on entry, ydot_{n+1} on exit
        real(dp), intent(out)   :: y1(:)    !! y_{n+1}
        real(dp) :: ydot1
        integer :: i
        associate (alpha_m => par(1), gamma => par(3))
            do i = 1, size(y)   ! (element by element: no temporary array)
                ydot1 = ydot(i) + (k(i) - ydot(i)) / alpha_m
                y1(i) = y(i) + h * ydot(i) + (gamma * h) * (ydot1 - ydot(i))
                ydot(i) = ydot1
            end do
        end associate
    end subroutine stage_finish

end module stickslip_galpha
