!> What the fixed-step implicit methods (backward Euler, generalized-alpha) share: their
!! Newton controls and their checks here; the driver (step grid, output, counters, statuses)
!! and the Newton solve of one implicit stage in stickslip_fixed_implicit_body.inc, which each
!! method's module instantiates (one kernel for any ode_system, one per built-in scene and
!! static law) around its own stage_setup and stage_finish. What follows describes that body.
!!
!! Step grid: t_i = t0 + i h, i = 1 .. N - 1, and t_N = t_end exactly, where N is the smallest
!! count whose grid point t0 + (N - 1) h lies strictly before t_end (so there is never a
!! zero-length last step, also when t0 + (N - 1) h rounds onto t_end).
!! Output at requested times: cubic Hermite interpolation with f at both ends of the step
!! (evaluated only for steps that contain a requested time; counted in nfev).
!!
!! The stage equation of both methods is k = f(tau, u + c h k) for a stage derivative k; it
!! is solved by Newton's method with the Jacobian evaluated once per step (at the starting
!! guess) and the matrix I - c h J factorised once per step. Convergence: the weighted RMS
!! norm of the change of u + c h k, with weights newton_atol + newton_rtol |u + c h k|, is
!! <= 1, or every component of that change is at the rounding level of the sum u + c h k
!! (newton_atol + ROUNDING_FLOOR (|u| + |c h k|)): on a stiff system started off its slow
!! manifold the terms of the sum are far larger than the state and its rounding far larger
!! than newton_rtol |u + c h k| (generalized-alpha on y' = -lambda (y - cos t) - sin t,
!! lambda h = 1e10, needed that to converge at all). After newton_max_iter iterations without
!! convergence the stage is solved again from the same guess by Newton's method with the
!! Jacobian at every iterate and a backtracking line search (at most 4 newton_max_iter
!! iterations, converged only on a full step), and if that fails, by the same from the rest guess k = 0 (a guess carrying a
!! large rate, LuGre's bristle from rest on the belt, can draw the iteration onto a kink of
!! |v_rel| where no descent direction is left); if that fails too, by the system's own solve
!! of the stage where it has one (`scalar_stage`: a one-contact scene with a static law solves
!! its stage as one bracketed scalar equation in the stage velocity, which the proposed law's
!! infinite slope at rest needs), and otherwise the run ends with SS_NEWTON_FAILED (a fixed step is never reduced); a non-finite Jacobian gives
!! SS_JAC_NONFINITE, a singular matrix SS_SINGULAR, non-finite iterates SS_NEWTON_FAILED.
!!
!! Laws with jumps. On a friction scene (x, v) whose law has modes (`friction_law%n_modes`
!! > 0: Coulomb, Karnopp) the methods run their nonsmooth instance instead: no Newton across
!! a jump, the stage is a generalized equation on the law's graph with its jumps filled in,
!! decided by the contact module's rule (static first, then keep a slip, then the slowest
!! consistent slip: `modal_choose`). A step keeps the current mode when the rule would: the
!! stick mode where it still holds; any other mode where it holds and the backward Euler step
!! could not end stuck (its stick mode is tried first, two evaluations of f: where
!! h g (mu_s - mu_k) > v_s a body can be stopped within a step while its slip would still
!! hold). It is then the method's own stage in the current slip mode (mu fixed, Newton as
!! above) when that mode still holds at the stage and at the step's end, or a backward Euler
!! step in the current stick mode or band point when the friction it needs is admissible;
!! otherwise a backward Euler step (Moreau's catching-up scheme) solved in every mode, the
!! rule choosing among the admissible solutions. A slip mode is
!! solved with mu fixed; a set-valued point or Karnopp's hold fixes the stage's relative
!! velocity (v from it, x = u_x + c h v) and takes mu from the scene's force (affine in mu),
!! so that a stuck body keeps its relative velocity exactly. Generalized-alpha's derivative
!! restarts from the stage of a backward Euler step (order 2 within a slip phase, a
!! first-order step at each switch and through stick). No admissible mode at all (not seen:
!! the filled-in graph always has one) ends the run with SS_NEWTON_FAILED.
module stickslip_fixed_implicit
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_H, SS_BAD_MAX_STEPS, SS_BAD_NIT, SS_BAD_NEWTON_TOL
    use stickslip_ode, only: step_controls
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: newton_controls, check_newton_controls

    !> Relative size of the rounding of a sum u + ch k that the Newton convergence test accepts
    !! as converged (in units of |u| + |ch k|): 64 units of round-off, a few times what
    !! forming the sum, evaluating f there and one substitution with the LU factors leave.
    real(dp), parameter, public :: ROUNDING_FLOOR = 64.0_dp * epsilon(1.0_dp)

    !> Controls of a fixed-step implicit method: the shared ones (h, max_steps, every_step;
    !! h_min, h_max, h0, allow_forced are not read) and those of its Newton iteration.
    type, extends(step_controls) :: newton_controls
        real(dp) :: newton_rtol = 1.0e-10_dp    !! relative Newton tolerance on the stage state [-], >= 0
        real(dp) :: newton_atol = 1.0e-12_dp    !! absolute Newton tolerance on the stage state [units of y], > 0
        integer  :: newton_max_iter = 10        !! Newton iterations allowed per step, >= 1
        !> Factor a band matrix when the system says its Jacobian is banded (`bandwidth`), O(n)
        !! a step; .false.: the dense n x n matrix whatever the system says.
        logical  :: banded = .true.
    contains
        !> Set one control by name, then fall back to the parent types controls.
        procedure :: set => set_newton_control
    end type newton_controls

    !> Names of the Newton controls, for the methods' registry entries.
    character(len=*), parameter, public :: NEWTON_CONTROL_NAMES = 'newton_rtol newton_atol newton_max_iter banded'

contains

    !> Set one control by name: the Newton controls, then the shared ones.
    function set_newton_control(self, name, value) result(status)
        class(newton_controls), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts as reals)
        integer :: status
        status = SS_OK
        select case (name)
        case ('newton_rtol'); self%newton_rtol = value
        case ('newton_atol'); self%newton_atol = value
        case ('banded');      self%banded = value /= 0.0_dp
        case ('newton_max_iter')
            if (value >= 1.0_dp .and. value <= 1.0e6_dp) then
                self%newton_max_iter = int(value)
            else
                status = SS_BAD_NIT
            end if
        case default; status = self%step_controls%set(name, value)
        end select
    end function set_newton_control

    !> Check the controls of a fixed-step implicit method.
    pure function check_newton_controls(ctl) result(status)
        class(newton_controls), intent(in) :: ctl   !! the controls to check
        integer :: status
        status = SS_OK
        if (.not. ieee_is_finite(ctl%h) .or. ctl%h <= 0.0_dp) then
            status = SS_BAD_H
        else if (ctl%max_steps < 1) then
            status = SS_BAD_MAX_STEPS
        else if (ctl%newton_max_iter < 1) then
            status = SS_BAD_NIT
        else if (.not. ieee_is_finite(ctl%newton_rtol) .or. ctl%newton_rtol < 0.0_dp .or. &
                 .not. ieee_is_finite(ctl%newton_atol) .or. ctl%newton_atol <= 0.0_dp) then
            status = SS_BAD_NEWTON_TOL
        end if
    end function check_newton_controls

end module stickslip_fixed_implicit
