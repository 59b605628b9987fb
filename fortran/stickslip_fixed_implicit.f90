!> What the fixed-step implicit methods (backward Euler, generalized-alpha) share: their
!! Newton controls, the step grid, the Newton solve of one implicit stage, and the driver
!! (output, counters, statuses). A method is a `fixed_stepper` extension with one `step`.
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
!! <= 1. After newton_max_iter iterations without convergence the stage is solved again from
!! the same guess by Newton's method with the Jacobian at every iterate and a backtracking line
!! search (at most 4 newton_max_iter iterations); if that fails too the run ends with
!! SS_NEWTON_FAILED (a fixed step is never reduced); a non-finite Jacobian gives
!! SS_JAC_NONFINITE, a singular matrix SS_SINGULAR, non-finite iterates SS_NEWTON_FAILED.
module stickslip_fixed_implicit
    use stickslip_kinds, only: dp, SS_INTERRUPTED, SS_OK, SS_BAD_H, SS_BAD_MAX_STEPS, SS_STEP_BUDGET, &
                               SS_NONFINITE, SS_OUTPUT_FULL, SS_NEWTON_FAILED, SS_SINGULAR, &
                               SS_JAC_NONFINITE, SS_BAD_NIT, SS_BAD_NEWTON_TOL
    use stickslip_ode, only: ode_system, ode_stats, step_controls, check_problem, output_start, step_count, stop_requested, &
                             all_finite, hermite
    use stickslip_linalg, only: lu_decompose, lu_solve
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: newton_controls, fixed_stepper, fixed_implicit_integrate, solve_stage

    !> Controls of a fixed-step implicit method: the shared ones (h, max_steps, every_step;
    !! h_min, h_max, h0, allow_forced are not read) and those of its Newton iteration.
    type, extends(step_controls) :: newton_controls
        real(dp) :: newton_rtol = 1.0e-10_dp    !! relative Newton tolerance on the stage state [-], >= 0
        real(dp) :: newton_atol = 1.0e-12_dp    !! absolute Newton tolerance on the stage state [units of y], > 0
        integer  :: newton_max_iter = 10        !! Newton iterations allowed per step, >= 1
    contains
        !> Set one control by name, then fall back to the parent types controls.
        procedure :: set => set_newton_control
    end type newton_controls

    !> Names of the Newton controls, for the methods' registry entries.
    character(len=*), parameter, public :: NEWTON_CONTROL_NAMES = 'newton_rtol newton_atol newton_max_iter'

    !> One method: advances (t, y) by h.
    type, abstract :: fixed_stepper
    contains
        !> Prepare the stepper from f(t0, y0).
        procedure(start_iface), deferred :: start
        !> Advance (t, y) by one step of size h.
        procedure(step_iface), deferred :: step
    end type fixed_stepper

    abstract interface
        !> Prepare the method's own state from f(t0, y0).
        subroutine start_iface(self, f0)
            import :: fixed_stepper, dp
            class(fixed_stepper), intent(inout) :: self
            real(dp), intent(in) :: f0(:)       !! f(t0, y0)
        end subroutine start_iface
        !> One step from (t, y) of size h into y1; stats counts, stats%status on failure.
        subroutine step_iface(self, sys, t, h, y, y1, ctl, stats)
            import :: fixed_stepper, ode_system, newton_controls, ode_stats, dp
            class(fixed_stepper), intent(inout) :: self
            class(ode_system), intent(inout) :: sys
            real(dp), intent(in)  :: t              !! time at the start of the step [s]
            real(dp), intent(in)  :: h              !! step size [s]
            real(dp), intent(in)  :: y(:)           !! state at t
            real(dp), intent(out) :: y1(:)          !! state at t + h
            class(newton_controls), intent(in) :: ctl   !! Newton controls
            type(ode_stats), intent(inout) :: stats     !! counters, status
        end subroutine step_iface
    end interface

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
        class(newton_controls), intent(in) :: ctl
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

    !> Solve k = f(tau, u + ch k) by Newton's method (Jacobian and LU once, at the guess).
    !! k: the starting guess on entry, the solution on exit. On failure stats%status is set.
    subroutine solve_stage(sys, tau, u, ch, k, ctl, stats)
        class(ode_system), intent(inout) :: sys     !! the right-hand side
        real(dp), intent(in)    :: tau              !! time of the stage [s]
        real(dp), intent(in)    :: u(:)             !! the stage state is u + ch k
        real(dp), intent(in)    :: ch               !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)             !! stage derivative: guess in, solution out
        class(newton_controls), intent(in) :: ctl   !! Newton controls
        type(ode_stats), intent(inout) :: stats     !! counters, status
        real(dp) :: ys(size(u)), fs(size(u)), dk(size(u)), a(size(u), size(u)), k0(size(u))
        integer :: ipiv(size(u)), iter
        real(dp) :: dnorm

        k0 = k
        ys = u + ch * k
        call sys%rhs(tau, ys, fs)
        stats%nfev = stats%nfev + 1
        if (.not. newton_matrix(sys, tau, ys, fs, ch, a, ipiv, stats)) return
        do iter = 1, ctl%newton_max_iter
            dk = fs - k
            call lu_solve(a, ipiv, dk)
            stats%nsol = stats%nsol + 1
            k = k + dk
            ys = u + ch * k
            dnorm = wnorm(ch * dk, ys)
            if (.not. ieee_is_finite(dnorm) .or. .not. all_finite(ys)) exit
            if (dnorm <= 1.0_dp) return
            call sys%rhs(tau, ys, fs)
            stats%nfev = stats%nfev + 1
        end do
        k = k0
        call damped_newton()

    contains

        !> The fallback of solve_stage when its simplified iteration fails (far from the solution,
        !! or where f is not Lipschitz, e.g. mu ~ |v|^(1/3) at rest): Newton's method from the same
        !! guess with the Jacobian at every iterate and a backtracking line search (halving, at most
        !! 30 times) on the weighted RMS norm of the residual ch (k - f(tau, u + ch k)) (weights of the
        !! convergence test at the current iterate, fixed during its line search), at most
        !! 4 newton_max_iter iterations, converged by the same test. A run that solve_stage's own
        !! iteration completes never gets here, so its counts are unchanged. On failure
        !! stats%status = SS_NEWTON_FAILED (or SS_JAC_NONFINITE, SS_SINGULAR).
        subroutine damped_newton()
            real(dp) :: kt(size(u)), yt(size(u)), ft(size(u))
            integer :: ls
            real(dp) :: rn, rtn, lam

            ys = u + ch * k
            call sys%rhs(tau, ys, fs)
            stats%nfev = stats%nfev + 1
            do iter = 1, 4 * ctl%newton_max_iter
                rn = wnorm(ch * (k - fs), ys)     ! weights fixed over the line search
                if (.not. newton_matrix(sys, tau, ys, fs, ch, a, ipiv, stats)) return
                dk = fs - k
                call lu_solve(a, ipiv, dk)
                stats%nsol = stats%nsol + 1
                lam = 1.0_dp
                do ls = 1, 30
                    kt = k + lam * dk
                    yt = u + ch * kt
                    call sys%rhs(tau, yt, ft)
                    stats%nfev = stats%nfev + 1
                    rtn = wnorm(ch * (kt - ft), ys)
                    if (ieee_is_finite(rtn) .and. rtn <= (1.0_dp - 1.0e-4_dp * lam) * rn) exit
                    lam = 0.5_dp * lam
                end do
                if (ls > 30) exit
                k = kt
                ys = yt
                fs = ft
                if (wnorm(lam * ch * dk, ys) <= 1.0_dp) return
            end do
            stats%status = SS_NEWTON_FAILED
        end subroutine damped_newton

        !> Weighted RMS norm of x with the convergence test's weights at state y.
        pure real(dp) function wnorm(x, y)
            real(dp), intent(in) :: x(:), y(:)
            wnorm = sqrt(sum((x / (ctl%newton_atol + ctl%newton_rtol * abs(y)))**2) / size(x))
        end function wnorm

    end subroutine solve_stage

    !> The Newton matrix I - ch J at (tau, ys), J = sys%jacobian, LU-factorised into (a, ipiv)
    !! and counted; .false. with stats%status = SS_JAC_NONFINITE or SS_SINGULAR.
    logical function newton_matrix(sys, tau, ys, fs, ch, a, ipiv, stats) result(ok)
        class(ode_system), intent(inout) :: sys     !! the right-hand side
        real(dp), intent(in)  :: tau                !! time of the stage [s]
        real(dp), intent(in)  :: ys(:)              !! stage state
        real(dp), intent(in)  :: fs(:)              !! f(tau, ys)
        real(dp), intent(in)  :: ch                 !! coefficient of k in the stage state [s]
        real(dp), intent(out) :: a(:, :)            !! LU factors of I - ch J
        integer, intent(out)  :: ipiv(:)            !! pivots
        type(ode_stats), intent(inout) :: stats     !! counters, status
        integer :: j, info
        ok = .false.
        stats%njac = stats%njac + 1
        call sys%jacobian(tau, ys, fs, a, stats%nfev)
        if (.not. all(ieee_is_finite(a))) then
            stats%status = SS_JAC_NONFINITE
            return
        end if
        a = -ch * a
        do j = 1, size(ys)
            a(j, j) = a(j, j) + 1.0_dp
        end do
        call lu_decompose(a, ipiv, info)
        stats%ndec = stats%ndec + 1
        if (info /= 0) then
            stats%status = SS_SINGULAR
            return
        end if
        ok = .true.
    end function newton_matrix

    !> Integrate with a fixed-step implicit method (the driver behind implicit_euler_integrate
    !! and galpha_integrate; see those for the arguments and statuses).
    subroutine fixed_implicit_integrate(sys, stepper, t0, y0, t_end, ctl, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys          !! the right-hand side (and its Jacobian)
        class(fixed_stepper), intent(inout) :: stepper   !! the method
        real(dp), intent(in)    :: t0                    !! initial time [s]
        real(dp), intent(in)    :: y0(:)                 !! initial state
        real(dp), intent(in)    :: t_end                 !! final time, > t0 [s]
        class(newton_controls), intent(in) :: ctl        !! controls (h, max_steps, every_step, Newton)
        real(dp), intent(inout) :: t_out(:)              !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)           !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats            !! counters and status

        real(dp) :: y(size(y0)), y1(size(y0)), f0(size(y0)), f1(size(y0))
        real(dp) :: t, t1, hs, nsteps_real
        integer(8) :: i, n_total, nsteps
        integer :: m, next
        logical :: f0_valid

        stats%status = check_problem(t0, y0, t_end, t_out, y_out, ctl%every_step)
        if (stats%status == SS_OK) stats%status = check_newton_controls(ctl)
        if (stats%status /= SS_OK) return

        m = size(t_out)
        nsteps_real = step_count(t0, t_end, ctl%h)
        n_total = huge(n_total)
        if (nsteps_real < 9.0e18_dp) n_total = int(nsteps_real, 8)
        nsteps = min(n_total, ctl%max_steps)

        t = t0
        y = y0
        call sys%rhs(t, y, f0)
        stats%nfev = 1
        f0_valid = .true.
        call stepper%start(f0)
        call output_start(t0, y0, t_out, y_out, ctl%every_step, next)
        stats%t_reached = t

        do i = 1, nsteps
            if (i == n_total) then
                t1 = t_end
            else
                t1 = t0 + real(i, dp) * ctl%h
            end if
            hs = t1 - t
            if (stop_requested(ctl, stats%nstep)) then
                stats%status = SS_INTERRUPTED
                exit
            end if
            stats%h_last = hs
            stats%nstep = stats%nstep + 1
            call stepper%step(sys, t, hs, y, y1, ctl, stats)
            if (stats%status /= SS_OK) exit
            if (.not. all_finite(y1)) then
                stats%status = SS_NONFINITE
                exit
            end if

            if (ctl%every_step) then
                if (next > m) then
                    stats%status = SS_OUTPUT_FULL
                    exit
                end if
                t_out(next) = t1
                y_out(:, next) = y1
                next = next + 1
                f0_valid = .false.
            else if (next <= m) then
                if (t_out(next) <= t1) then
                    if (.not. f0_valid) then
                        call sys%rhs(t, y, f0)
                        stats%nfev = stats%nfev + 1
                    end if
                    call sys%rhs(t1, y1, f1)
                    stats%nfev = stats%nfev + 1
                    do while (next <= m)
                        if (t_out(next) > t1) exit
                        if (t_out(next) == t1) then
                            y_out(:, next) = y1
                        else
                            y_out(:, next) = hermite(t, hs, y, f0, y1, f1, t_out(next))
                            if (.not. all_finite(y_out(:, next))) exit   ! interpolant overflow
                        end if
                        next = next + 1
                    end do
                    if (next <= m) then
                        if (t_out(next) <= t1) then
                            stats%status = SS_NONFINITE
                            exit
                        end if
                    end if
                    f0 = f1
                    f0_valid = .true.
                else
                    f0_valid = .false.
                end if
            end if
            stats%naccept = stats%naccept + 1   ! stored and committed
            y = y1
            t = t1
            stats%t_reached = t
        end do
        stats%n_written = next - 1
        if (stats%status == SS_OK .and. nsteps < n_total) stats%status = SS_STEP_BUDGET

    end subroutine fixed_implicit_integrate

end module stickslip_fixed_implicit
