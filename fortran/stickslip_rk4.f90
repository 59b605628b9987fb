!> Classical fixed-step Runge-Kutta method of order 4, event-free.
!!
!! Steps are t_i = t0 + i h; the last one is shortened to end exactly at t_end.
!! Output at requested times uses the cubic Hermite interpolant through (y, f) at both
!! ends of the step (order 4, like the method), which costs no extra evaluation since
!! f at the end of a step is the first stage of the next one (first same as last).
!! Evaluations: 1 + 4 per step.
module stickslip_rk4
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_H, SS_BAD_MAX_STEPS, SS_STEP_BUDGET, &
                               SS_NONFINITE, SS_OUTPUT_FULL, SS_INTERRUPTED
    use stickslip_ode, only: ode_system, ode_stats, method_info, check_problem, output_start, hermite, step_count, STOP_CHECK_MASK
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
    !! up to stats%t_reached is valid), SS_NONFINITE, SS_OUTPUT_FULL or a bad-input code.
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

        real(dp) :: y(size(y0)), y1(size(y0)), f0(size(y0)), f1(size(y0))
        real(dp) :: k2(size(y0)), k3(size(y0)), k4(size(y0)), ytmp(size(y0))
        real(dp) :: t, t1, hs, nsteps_real, t_next
        integer(8) :: i, nsteps, n_total, budget
        integer :: m, next
        logical :: steps_mode, watch

        steps_mode = .false.
        if (present(every_step)) steps_mode = every_step
        watch = present(stop_flag)
        if (watch) watch = associated(stop_flag)
        budget = huge(budget)
        if (present(max_steps)) budget = max_steps

        stats%status = check_problem(t0, y0, t_end, t_out, y_out, steps_mode)
        if (stats%status /= SS_OK) return
        if (.not. ieee_is_finite(h) .or. h <= 0.0_dp) then
            stats%status = SS_BAD_H
            return
        end if
        if (budget < 1) then
            stats%status = SS_BAD_MAX_STEPS
            return
        end if

        m = size(t_out)
        nsteps_real = step_count(t0, t_end, h)
        n_total = huge(n_total)       ! more steps than an integer(8) holds: never reached
        if (nsteps_real < 9.0e18_dp) n_total = int(nsteps_real, 8)
        nsteps = min(n_total, budget)

        y = y0
        t = t0
        call sys%rhs(t, y, f0)
        stats%nfev = 1
        call output_start(t0, y0, t_out, y_out, steps_mode, next)

        t_next = huge(1.0_dp)
        if (.not. steps_mode .and. next <= m) t_next = t_out(next)
        do i = 1, nsteps
            if (i == n_total) then
                t1 = t_end
            else
                t1 = t0 + real(i, dp) * h
            end if
            hs = t1 - t
            if (watch .and. iand(i, STOP_CHECK_MASK) == 0) then
                if (stop_flag /= 0) then
                    stats%status = SS_INTERRUPTED
                    exit
                end if
            end if
            ytmp = y + (0.5_dp * hs) * f0
            call sys%rhs(t + 0.5_dp * hs, ytmp, k2)
            ytmp = y + (0.5_dp * hs) * k2
            call sys%rhs(t + 0.5_dp * hs, ytmp, k3)
            ytmp = y + hs * k3
            call sys%rhs(t1, ytmp, k4)
            y1 = y + (hs / 6.0_dp) * (f0 + 2.0_dp * (k2 + k3) + k4)
            call sys%rhs(t1, y1, f1)
            stats%nfev = stats%nfev + 4
            stats%nstep = stats%nstep + 1
            stats%h_last = hs

            if (.not. all(ieee_is_finite(y1))) then   ! inline: no call in the hot loop
                stats%status = SS_NONFINITE
                exit
            end if

            if (steps_mode) then
                if (next > m) then
                    stats%status = SS_OUTPUT_FULL
                    exit
                end if
                t_out(next) = t1
                y_out(:, next) = y1
                next = next + 1
            else if (t1 >= t_next) then   ! an output time in this step (t_next = huge: none left)
                do while (next <= m)
                    if (t_out(next) > t1) exit
                    if (t_out(next) == t1) then
                        y_out(:, next) = y1
                    else
                        y_out(:, next) = hermite(t, hs, y, f0, y1, f1, t_out(next))
                        if (.not. all(ieee_is_finite(y_out(:, next)))) exit   ! interpolant overflow
                    end if
                    next = next + 1
                end do
                if (next <= m) then
                    if (t_out(next) <= t1) then
                        stats%status = SS_NONFINITE
                        exit
                    end if
                end if
                t_next = huge(1.0_dp)
                if (next <= m) t_next = t_out(next)
            end if

            stats%naccept = stats%naccept + 1   ! stored and committed
            y = y1
            f0 = f1
            t = t1
        end do

        stats%t_reached = t
        stats%n_written = next - 1
        if (stats%status == SS_OK .and. nsteps < n_total) stats%status = SS_STEP_BUDGET

    end subroutine rk4_integrate

end module stickslip_rk4
