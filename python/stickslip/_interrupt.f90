! Compiled into the extension beside _wrap.f90, but not read by f2py.

!> Ctrl-C while a call runs (_interrupt.c): arm sets the stop flag on SIGINT, disarm puts the
!! previous handler back. Only the main thread arms (stop(1) = -1 asks for it). cpu_seconds:
!! the process's CPU clock that times a long call; wall_seconds: the monotonic clock that
!! times a short one. prepare_setting: a setting of the wrapper's run_simulation built from
!! its one string of names and one array of values; timed_run: a prepared setting run between
!! two reads of a clock (the one way the wrapper's entry points build and run a scene).
module stickslip_wrap_interrupt
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    implicit none
    private
    public :: arm, disarm, cpu_seconds, wall_seconds, timed_run, prepare_setting
    interface
        !> The process's CPU time [s] (CLOCK_PROCESS_CPUTIME_ID, as time.process_time).
        function cpu_seconds() bind(C, name='ss_py_cpu_seconds')
            import :: c_double
            real(c_double) :: cpu_seconds
        end function cpu_seconds
        !> A monotonic wall clock [s] (CLOCK_MONOTONIC), read without a system call on Linux.
        function wall_seconds() bind(C, name='ss_py_wall_seconds')
            import :: c_double
            real(c_double) :: wall_seconds
        end function wall_seconds
        subroutine ss_py_arm(flag) bind(C, name='ss_py_arm')
            import :: c_int
            integer(c_int), intent(inout) :: flag
        end subroutine ss_py_arm
        subroutine ss_py_disarm() bind(C, name='ss_py_disarm')
        end subroutine ss_py_disarm
    end interface
contains
    !> Arm when asked (flag = -1 on entry), leaving the flag at 0.
    subroutine arm(flag, armed)
        integer(c_int), intent(inout) :: flag   !! -1: arm; becomes 0, then 1 on SIGINT
        logical, intent(out) :: armed           !! whether disarm must follow
        armed = flag == -1
        flag = 0
        if (armed) call ss_py_arm(flag)
    end subroutine arm
    !> Put the previous SIGINT handler back.
    subroutine disarm(armed)
        logical, intent(in) :: armed            !! as returned by arm
        if (armed) call ss_py_disarm()
    end subroutine disarm

    !> The setting of run_simulation's arguments (_wrap.f90): keys = 'pkeys|ckeys', vals =
    !! [pvals(np), y0(n), rtol(nrt), atol(nat), cvals], built by stickslip_simulate's
    !! prepare_simulation; resolved: every parameter as resolved (registry order). status: SS_OK,
    !! the bad input's code, or SS_BAD_DIM for counts that overrun vals, names without the '|'
    !! or a size of resolved that is not the registry's.
    subroutine prepare_setting(scene, law, method, keys, vals, np, n, nrt, nat, t_end, prep, resolved, status)
        use stickslip_kinds, only: SS_OK, SS_BAD_DIM
        use stickslip_params, only: param_values
        use stickslip_registry, only: split_names
        use stickslip_simulate, only: prepared_simulation, prepare_simulation
        integer(c_int), intent(in) :: scene, law, method   !! codes (registry)
        character(len=*), intent(in) :: keys               !! 'pkeys|ckeys'
        real(c_double), intent(in) :: vals(:)              !! [pvals, y0, rtol, atol, cvals]
        integer(c_int), intent(in) :: np, n, nrt, nat      !! counts of the first four parts of vals
        real(c_double), intent(in) :: t_end                !! final time [s]
        type(prepared_simulation), intent(out) :: prep     !! the setting
        real(c_double), intent(out) :: resolved(:)         !! every parameter, resolved
        integer(c_int), intent(out) :: status              !! SS_OK or the bad input's code
        type(param_values) :: p
        integer :: bar, o
        resolved = 0.0_c_double
        bar = index(keys, '|')
        o = np + n + nrt + nat          ! cvals start after o
        if (bar == 0 .or. min(np, n, nrt, nat) < 0 .or. o > size(vals)) then
            status = SS_BAD_DIM
            return
        end if
        status = prepare_simulation(scene, law, split_names(keys(:bar - 1)), vals(1:np), method, &
                                    split_names(keys(bar + 1:)), vals(o + 1:), vals(np + 1:np + n), t_end, &
                                    vals(np + n + 1:np + n + nrt), vals(np + n + nrt + 1:o), prep, p_out=p)
        if (.not. allocated(p%values)) return
        if (size(resolved) /= size(p%values)) then
            if (status == SS_OK) status = SS_BAD_DIM
            return
        end if
        resolved = p%values
    end subroutine prepare_setting

    !> Run a prepared setting (stickslip_simulate's run_prepared) with the stop flag `stop`:
    !! on entry -1 a long run on the main thread (the SIGINT handler is armed), -2 a long run
    !! elsewhere, 0 a run too short for the integrators to look at the flag. cpu: the run's
    !! time [s], the process's CPU time for a long run, the monotonic wall time for a short one
    !! (two reads of the CPU clock are system calls that cost more than such a run). stats:
    !! the integer counters (as reals, exact below 2^53), then the real counters; status
    !! SS_BAD_DIM when its size is not theirs. drive_force: a model's drives' forces, when given.
    subroutine timed_run(prep, t_out, y_out, stop, events, stats, status, cpu, drive_force)
        use stickslip_kinds, only: SS_BAD_DIM
        use stickslip_ode, only: ode_stats, stats_integers, stats_reals
        use stickslip_simulate, only: prepared_simulation, run_prepared
        type(prepared_simulation), intent(in) :: prep   !! the setting
        real(c_double), intent(inout) :: t_out(:)       !! output times, or room for every step [s]
        real(c_double), intent(inout) :: y_out(:, :)    !! (states, rows) output
        integer(c_int), intent(inout), target :: stop   !! the stop flag (see above)
        real(c_double), intent(inout) :: events(:, :)   !! (4, room) event_driven's events
        real(c_double), intent(out) :: stats(:)         !! the counters (see above)
        integer(c_int), intent(out) :: status           !! the run's status
        real(c_double), intent(out) :: cpu              !! the run's time [s]
        real(c_double), intent(out), optional :: drive_force(:, :)  !! (drives, rows) their forces [N]
        type(ode_stats) :: st
        integer, pointer :: flag
        logical :: armed, long_run
        integer :: ni
        flag => stop
        long_run = stop < 0
        call arm(stop, armed)
        if (long_run) then
            cpu = cpu_seconds()
        else
            cpu = wall_seconds()
        end if
        call run_prepared(prep, t_out, y_out, st, stop_flag=flag, events=events, drive_force=drive_force)
        if (long_run) then
            cpu = cpu_seconds() - cpu
        else
            cpu = wall_seconds() - cpu
        end if
        call disarm(armed)
        status = st%status
        ni = size(stats_integers(st))
        if (size(stats) /= ni + size(stats_reals(st))) then
            status = SS_BAD_DIM
            return
        end if
        stats(1:ni) = real(stats_integers(st), c_double)
        stats(ni + 1:) = stats_reals(st)
    end subroutine timed_run
end module stickslip_wrap_interrupt

