!> Timing of the stickslip core called directly from Fortran (no Python): one scene, law and
!! method through stickslip_simulate's `simulate`, output only at t_end.
!!
!! usage: bench_fortran SCENE LAW rk4|dopri5 T_END H_OR_TOL REPEATS MIN_SAMPLE_S
!! RK4 takes the step H; DOPRI5 takes rtol = atol = TOL, hmin = 0, hmax = t_end and no step
!! budget. Prints "median_s nfev nstep x_end v_end": the median over REPEATS samples of the
!! time of one integration [s]; each sample repeats it until it lasts MIN_SAMPLE_S.
program bench_fortran
    use, intrinsic :: iso_fortran_env, only: int64, error_unit
    use stickslip_kinds, only: dp, SS_OK, stickslip_message
    use stickslip_friction, only: LAW_COULOMB, LAW_RECURDYN, LAW_PROPOSED
    use stickslip_scenes, only: SCENE_SLOPE, SCENE_BELT
    use stickslip_simulate, only: scene_params, simulate, METHOD_RK4, METHOD_DOPRI5
    use stickslip_dopri5, only: dopri5_options
    use stickslip_ode, only: ode_stats
    implicit none

    character(len=32) :: arg(7)
    integer :: i, scene, law, method, repeats
    integer(int64) :: inner, j
    real(dp) :: t_end, hp, min_sample, once, t0
    real(dp), allocatable :: samples(:)
    type(scene_params) :: p
    type(dopri5_options) :: opts
    type(ode_stats) :: st
    real(dp) :: t_out(1), y_out(2, 1)

    if (command_argument_count() /= 7) then
        write (error_unit, '(a)') 'usage: bench_fortran SCENE LAW rk4|dopri5 T_END H_OR_TOL REPEATS MIN_SAMPLE_S'
        error stop 2
    end if
    do i = 1, 7
        call get_command_argument(i, arg(i))
    end do
    scene = merge(SCENE_BELT, SCENE_SLOPE, arg(1) == 'belt')
    law = LAW_PROPOSED
    if (arg(2) == 'coulomb') law = LAW_COULOMB
    if (arg(2) == 'recurdyn') law = LAW_RECURDYN
    method = merge(METHOD_RK4, METHOD_DOPRI5, arg(3) == 'rk4')
    read (arg(4), *) t_end
    read (arg(5), *) hp
    read (arg(6), *) repeats
    read (arg(7), *) min_sample
    opts%hmin = 0.0_dp
    opts%hmax = t_end
    opts%max_steps = huge(1_int64)
    allocate(samples(repeats))

    t0 = now()
    call run()
    once = now() - t0
    if (st%status /= SS_OK) then
        write (error_unit, '(a)') 'bench_fortran: ' // stickslip_message(st%status)
        error stop 1
    end if
    inner = max(1_int64, ceiling(min_sample / max(once, 1.0e-9_dp), int64))
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
        call simulate(scene, law, method, p, 0.0_dp, 0.0_dp, t_end, hp, [hp], [hp], opts, t_out, y_out, st)
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
