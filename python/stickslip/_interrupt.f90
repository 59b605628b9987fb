! Compiled into the extension beside _wrap.f90, but not read by f2py.

!> Ctrl-C while a call runs (_interrupt.c): arm sets the stop flag on SIGINT, disarm puts the
!! previous handler back. Only the main thread arms (stop(1) = -1 asks for it). cpu_seconds:
!! the process's CPU clock that times a long call; wall_seconds: the monotonic clock that
!! times a short one.
module stickslip_wrap_interrupt
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    implicit none
    private
    public :: arm, disarm, cpu_seconds, wall_seconds
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
end module stickslip_wrap_interrupt

