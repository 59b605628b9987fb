!> Timing of the stickslip core called directly from Fortran (no Python): one scene, law and
!! method through stickslip_simulate's `simulate`, output only at t_end.
!!
!! usage: bench_fortran SCENE LAW METHOD T_END H_OR_TOL REPEATS MIN_SAMPLE_S
!! METHOD rk4 takes the step H; an adaptive method (dopri5, dop853, ...) takes
!! rtol = atol = TOL, hmin = 0, hmax = t_end and no step budget. Prints "median_s nfev nstep
!! x_end v_end": the median over REPEATS samples of the time of one integration [s]; each
!! sample repeats it until it lasts MIN_SAMPLE_S (with MIN_SAMPLE_S = 0: exactly 1 + REPEATS
!! runs, for instruction counts under callgrind).
program bench_fortran
    use, intrinsic :: iso_fortran_env, only: int64, error_unit
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_registry, only: stickslip_message, code_of
    use stickslip_simulate, only: simulate
    use stickslip_ode, only: ode_stats
    implicit none

    character(len=32) :: arg(7)
    integer :: i, scene, law, method, repeats
    integer(int64) :: inner, j
    real(dp) :: t_end, hp, min_sample, once, t0
    real(dp), allocatable :: samples(:)
    type(ode_stats) :: st
    character(len=16), allocatable :: ckeys(:)
    real(dp), allocatable :: cvals(:)
    real(dp) :: t_out(1), y_out(2, 1)

    if (command_argument_count() /= 7) then
        write (error_unit, '(a)') 'usage: bench_fortran SCENE LAW METHOD T_END H_OR_TOL REPEATS MIN_SAMPLE_S'
        error stop 2
    end if
    do i = 1, 7
        call get_command_argument(i, arg(i))
    end do
    scene = code_of('scene', trim(arg(1)))
    law = code_of('law', trim(arg(2)))
    method = code_of('method', trim(arg(3)))
    read (arg(4), *) t_end
    read (arg(5), *) hp
    read (arg(6), *) repeats
    read (arg(7), *) min_sample
    if (arg(3) == 'rk4') then
        ckeys = [character(len=16) :: 'h', 'max_steps']
        cvals = [hp, 9.0e18_dp]
    else
        ckeys = [character(len=16) :: 'hmin', 'hmax', 'max_steps']
        cvals = [0.0_dp, t_end, 9.0e18_dp]
    end if
    allocate(samples(repeats))

    t0 = now()
    call run()
    once = now() - t0
    if (st%status /= SS_OK) then
        write (error_unit, '(a)') 'bench_fortran: ' // stickslip_message(st%status)
        error stop 1
    end if
    ! Runs per sample: the first run is cold (page faults, lazy binding) and would make the
    ! samples too short, so a warm batch of about a tenth of a sample times one run again.
    ! MIN_SAMPLE_S = 0 (counting instructions): exactly 1 + REPEATS runs.
    inner = 1
    if (min_sample > 0.0_dp) then
        inner = max(1_int64, ceiling(0.1_dp * min_sample / max(once, 1.0e-9_dp), int64))
        t0 = now()
        do j = 1, inner
            call run()
        end do
        once = (now() - t0) / real(inner, dp)
        inner = max(1_int64, ceiling(min_sample / max(once, 1.0e-9_dp), int64))
    end if
    do i = 1, repeats
        t0 = now()
        do j = 1, inner
            call run()
        end do
        samples(i) = (now() - t0) / real(inner, dp)
    end do
    print '(es16.9, 2(1x, i0), 2(1x, es24.16))', median(samples), st%nfev, st%nstep, y_out(1, 1), y_out(2, 1)

contains

    subroutine run()
        t_out(1) = t_end
        call simulate(scene, law, method, [character(len=16) ::], [real(dp) ::], [0.0_dp, 0.0_dp], t_end, &
                      [hp], [hp], ckeys, cvals, t_out, y_out, st)
    end subroutine run

    !> Monotonic wall-clock time [s].
    real(dp) function now()
        integer(int64) :: count, rate
        call system_clock(count, rate)
        now = real(count, dp) / real(rate, dp)
    end function now

    real(dp) function median(x)
        real(dp), intent(inout) :: x(:)
        integer :: a, b
        real(dp) :: tmp
        do a = 2, size(x)          ! insertion sort: a handful of samples
            tmp = x(a)
            b = a - 1
            do while (b >= 1)
                if (x(b) <= tmp) exit
                x(b + 1) = x(b)
                b = b - 1
            end do
            x(b + 1) = tmp
        end do
        if (mod(size(x), 2) == 1) then
            median = x(size(x) / 2 + 1)
        else
            median = 0.5_dp * (x(size(x) / 2) + x(size(x) / 2 + 1))
        end if
    end function median

end program bench_fortran
