!> What the integrators share: the right-hand side of y' = f(t, y) as an abstract type,
!! the counters of a run, and checks on output grids and states.
!!
!! Output convention of every integrator: arrays t_out(m) and y_out(n, m) owned by the
!! caller. In grid mode t_out holds requested times (non-decreasing, in [t0, t_end]) and
!! the integrator fills y_out at them by its dense output; in every-step mode it writes
!! (t, y) of the initial state and of each accepted step, up to m rows.
!!
!! A user integrates their own ODE by extending `ode_system` and implementing `rhs`;
!! their data travels in the extension, not through globals.
module stickslip_ode
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_N_OUT, SS_BAD_DIM, SS_BAD_Y0, SS_BAD_T_END
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: ode_system, ode_stats, check_problem, all_finite, output_start

    !> A first-order system y' = f(t, y).
    type, abstract :: ode_system
    contains
        procedure(rhs_iface), deferred :: rhs
    end type ode_system

    abstract interface
        !> Evaluate f(t, y) into dydt (same size as y).
        subroutine rhs_iface(self, t, y, dydt)
            import :: ode_system, dp
            class(ode_system), intent(inout) :: self
            real(dp), intent(in)  :: t          !! time [s]
            real(dp), intent(in)  :: y(:)       !! state
            real(dp), intent(out) :: dydt(:)    !! derivative of the state
        end subroutine rhs_iface
    end interface

    !> Counters and outcome of one integration (names after Hairer's DOPRI5).
    type :: ode_stats
        integer(8) :: nfev = 0      !! right-hand-side evaluations (NFCN)
        integer(8) :: nstep = 0     !! attempted steps (NSTEP)
        integer(8) :: naccept = 0   !! accepted steps, forced ones included (NACCPT)
        integer(8) :: nreject = 0   !! rejected steps after the first accepted one (NREJCT)
        integer(8) :: nforced = 0   !! steps taken at h_min although the error test failed
        integer(8) :: nstiff = 0    !! stiffness tests with h*|lambda| > 3.25 (DOPRI5)
        logical    :: stiff = .false.   !! 15 such tests in a row: the problem is probably stiff
        integer    :: n_written = 0     !! output rows written
        real(dp)   :: t_reached = 0.0_dp  !! time reached when the run ended [s]
        real(dp)   :: h_last = 0.0_dp     !! last step size tried [s]
        integer    :: status = SS_OK      !! SS_OK or a negative status code
    end type ode_stats

contains

    !> Check what every integration needs: a finite y0, t_end > t0, and the output
    !! arrays (grid mode: requested times finite, non-decreasing, in [t0, t_end]).
    pure function check_problem(t0, y0, t_end, t_out, y_out, every_step) result(status)
        real(dp), intent(in) :: t0          !! initial time [s]
        real(dp), intent(in) :: y0(:)       !! initial state
        real(dp), intent(in) :: t_end       !! final time [s]
        real(dp), intent(in) :: t_out(:)    !! output times (requested, or room for every step) [s]
        real(dp), intent(in) :: y_out(:, :) !! (size(y0), size(t_out)) output states
        logical, intent(in)  :: every_step  !! every-step mode
        integer :: status
        integer :: i
        status = SS_OK
        if (.not. all_finite(y0)) then
            status = SS_BAD_Y0
        else if (.not. ieee_is_finite(t0) .or. .not. ieee_is_finite(t_end) .or. t_end <= t0) then
            status = SS_BAD_T_END
        else if (size(t_out) < 1) then
            status = SS_BAD_N_OUT
        else if (size(y_out, 1) /= size(y0) .or. size(y_out, 2) /= size(t_out)) then
            status = SS_BAD_DIM
        else if (.not. every_step) then
            do i = 1, size(t_out)
                if (.not. ieee_is_finite(t_out(i))) then
                    status = SS_BAD_N_OUT
                else if (t_out(i) < t0 .or. t_out(i) > t_end) then
                    status = SS_BAD_N_OUT
                else if (i > 1) then
                    if (t_out(i) < t_out(i - 1)) status = SS_BAD_N_OUT
                end if
            end do
        end if
    end function check_problem

    !> Write the rows due at t0: in every-step mode row 1 = (t0, y0); in grid mode y0 at every
    !! requested time equal to t0. `next` is the index of the next row to write.
    pure subroutine output_start(t0, y0, t_out, y_out, every_step, next)
        real(dp), intent(in)    :: t0           !! initial time [s]
        real(dp), intent(in)    :: y0(:)        !! initial state
        real(dp), intent(inout) :: t_out(:)     !! output times (checked by check_problem) [s]
        real(dp), intent(inout) :: y_out(:, :)  !! (size(y0), size(t_out)) output states
        logical, intent(in)     :: every_step   !! every-step mode
        integer, intent(out)    :: next         !! next row to write
        next = 1
        if (every_step) then
            t_out(1) = t0
            y_out(:, 1) = y0
            next = 2
        else
            do while (next <= size(t_out))
                if (t_out(next) > t0) exit
                y_out(:, next) = y0
                next = next + 1
            end do
        end if
    end subroutine output_start

    !> .true. when every component of y is finite.
    pure logical function all_finite(y)
        real(dp), intent(in) :: y(:)
        all_finite = all(ieee_is_finite(y))
    end function all_finite

end module stickslip_ode
