!> Many simulations in one call: a loop of `stickslip_simulate::simulate` over parameter
!! sets, in parallel with OpenMP (the thread count is an argument), each set reduced to a
!! compact summary so that memory stays bounded whatever the number of steps.
!!
!! Every set runs on a uniform monitor grid of n_grid times on [0, t_end] (grid mode of
!! the integrators: dense/Hermite output, no every-step storage). The summary holds the
!! status and counters of the run, the final state, and what the monitor grid shows:
!! max |v|, the number of sign changes of the relative sliding velocity, and the range of
!! the relative velocity over the second half of the run. The grid itself is kept only
!! when the caller passes y_grid.
!!
!! The grid is t_j = (j - 1) (t_end / (n_grid - 1)), j = 1 .. n_grid (t_end alone when
!! n_grid = 1): the same numbers numpy.linspace(0, t_end, n_grid) gives, so a set reproduces
!! a single `simulate` call on that grid bit for bit.
!!
!! Thread safety: `simulate` keeps its right-hand side in a local allocatable, and the core
!! has no mutable module variables, so sets share nothing but their read-only inputs.
module stickslip_batch
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_DIM, SS_BAD_N_OUT
    use stickslip_ode, only: ode_stats
    use stickslip_dopri5, only: dopri5_options
    use stickslip_scenes, only: SCENE_BELT
    use stickslip_simulate, only: scene_params, simulate
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    !$ use omp_lib, only: omp_get_max_threads
    implicit none
    private

    public :: batch_summary, simulate_batch, batch_threads_available

    !> The compact outcome of one parameter set.
    type :: batch_summary
        integer    :: status = SS_OK   !! SS_OK or a negative status code of the run
        integer(8) :: nfev = 0         !! right-hand-side evaluations
        integer(8) :: nstep = 0        !! attempted steps
        integer(8) :: naccept = 0      !! accepted steps (forced ones included)
        integer(8) :: nreject = 0      !! rejected steps
        integer(8) :: nforced = 0      !! steps forced at h_min (DOPRI5)
        integer(8) :: nstiff = 0       !! positive stiffness tests (DOPRI5)
        logical    :: stiff = .false.  !! DOPRI5 judged the problem stiff
        real(dp)   :: t_reached = 0.0_dp  !! time reached [s]
        real(dp)   :: h_last = 0.0_dp     !! last step size tried [s]
        real(dp)   :: t_last = 0.0_dp     !! last monitor-grid time written (t_end on success) [s]
        real(dp)   :: x_end = 0.0_dp      !! x at t_last [m]
        real(dp)   :: v_end = 0.0_dp      !! v at t_last [m/s]
        real(dp)   :: v_max = 0.0_dp      !! max |v| over the initial state and the monitor grid [m/s]
        integer    :: n_flip = 0          !! sign changes of the relative velocity on the monitor grid
        integer    :: n_flip_tail = 0     !! the same, over the grid times >= t_end / 2
        integer    :: n_rev = 0           !! reversals of the direction of v between grid points
                                          !! (successive differences of opposite sign, both above
                                          !! 64 eps max|v|): high-frequency content
        integer    :: n_rev_tail = 0      !! the same, over the grid times >= t_end / 2
        real(dp)   :: vrel_min_tail = 0.0_dp  !! min relative velocity over times >= t_end / 2 [m/s]
        real(dp)   :: vrel_max_tail = 0.0_dp  !! max relative velocity over times >= t_end / 2 [m/s]
        real(dp)   :: seconds = 0.0_dp    !! wall-clock time of this set (one thread) [s]
    end type batch_summary

contains

    !> Number of threads OpenMP would use by default (1 without OpenMP).
    integer function batch_threads_available() result(n)
        n = 1
        !$ n = omp_get_max_threads()
    end function batch_threads_available

    !> Run every parameter set i = 1 .. size(scene) through `simulate` and summarise it.
    !!
    !! All per-set arrays must have the same size; status = SS_BAD_DIM otherwise, and
    !! SS_BAD_N_OUT when n_grid < 1. A bad input in one set (a negative code <= -100) or a
    !! run that ends early is reported in that set's summary only.
    !! Relative velocity: v for the slope, v_b - v for the belt.
    subroutine simulate_batch(scene, law, method, p, x0, v0, t_end, h, rtol, atol, opts, &
                              n_grid, threads, summary, status, y_grid)
        integer, intent(in) :: scene(:)                 !! SCENE_SLOPE or SCENE_BELT, per set
        integer, intent(in) :: law(:)                   !! friction law code, per set
        integer, intent(in) :: method(:)                !! METHOD_RK4 or METHOD_DOPRI5, per set
        type(scene_params), intent(in) :: p(:)          !! physical parameters, per set
        real(dp), intent(in) :: x0(:)                   !! initial displacement [m], per set
        real(dp), intent(in) :: v0(:)                   !! initial velocity [m/s], per set
        real(dp), intent(in) :: t_end(:)                !! final time [s], per set
        real(dp), intent(in) :: h(:)                    !! RK4 step size [s], per set
        real(dp), intent(in) :: rtol(:)                 !! DOPRI5 relative tolerance, per set
        real(dp), intent(in) :: atol(:)                 !! DOPRI5 absolute tolerance [m, m/s], per set
        type(dopri5_options), intent(in) :: opts(:)     !! controls (max_steps for both methods), per set
        integer, intent(in) :: n_grid                   !! monitor grid points per set, >= 1
        integer, intent(in) :: threads                  !! OpenMP threads (< 1: OpenMP's default)
        type(batch_summary), intent(out) :: summary(:)  !! one summary per set
        integer, intent(out) :: status                  !! SS_OK, SS_BAD_DIM or SS_BAD_N_OUT
        real(dp), intent(out), optional :: y_grid(:, :, :)  !! (2, n_grid, nset) states on the grid

        integer :: nset, i, nthr
        logical :: keep

        nset = size(scene)
        status = SS_OK
        if (size(law) /= nset .or. size(method) /= nset .or. size(p) /= nset .or. &
            size(x0) /= nset .or. size(v0) /= nset .or. size(t_end) /= nset .or. &
            size(h) /= nset .or. size(rtol) /= nset .or. size(atol) /= nset .or. &
            size(opts) /= nset .or. size(summary) /= nset) then
            status = SS_BAD_DIM
        else if (n_grid < 1) then
            status = SS_BAD_N_OUT
        end if
        keep = present(y_grid)
        if (keep .and. status == SS_OK) then
            if (size(y_grid, 1) /= 2 .or. size(y_grid, 2) /= n_grid .or. size(y_grid, 3) /= nset) &
                status = SS_BAD_DIM
        end if
        if (status /= SS_OK) return

        nthr = threads
        if (nthr < 1) nthr = batch_threads_available()

        !$omp parallel do schedule(dynamic, 1) num_threads(nthr) default(shared) private(i)
        do i = 1, nset
            if (keep) then
                call run_one(i, y_grid(:, :, i))
            else
                call run_one(i)
            end if
        end do
        !$omp end parallel do

    contains

        !> One set: simulate on the monitor grid, then summarise.
        subroutine run_one(i, y_keep)
            integer, intent(in) :: i
            real(dp), intent(out), optional :: y_keep(:, :)
            real(dp), allocatable :: t_out(:), y_out(:, :)
            type(ode_stats) :: st
            integer(8) :: c0, c1, rate
            integer :: j, n_ok
            real(dp) :: dt, v_ref, sgn

            allocate(t_out(n_grid), y_out(2, n_grid))
            if (n_grid == 1) then
                t_out(1) = t_end(i)
            else
                dt = t_end(i) / real(n_grid - 1, dp)
                do j = 1, n_grid - 1
                    t_out(j) = real(j - 1, dp) * dt
                end do
                t_out(n_grid) = t_end(i)
            end if
            y_out = 0.0_dp

            call system_clock(c0, rate)
            call simulate(scene(i), law(i), method(i), p(i), x0(i), v0(i), t_end(i), h(i), &
                          [rtol(i)], [atol(i)], opts(i), t_out, y_out, st)
            call system_clock(c1)

            summary(i)%status = st%status
            summary(i)%nfev = st%nfev
            summary(i)%nstep = st%nstep
            summary(i)%naccept = st%naccept
            summary(i)%nreject = st%nreject
            summary(i)%nforced = st%nforced
            summary(i)%nstiff = st%nstiff
            summary(i)%stiff = st%stiff
            summary(i)%t_reached = st%t_reached
            summary(i)%h_last = st%h_last
            summary(i)%seconds = real(c1 - c0, dp) / real(max(rate, 1_8), dp)

            ! Rows written are valid; the state at t_reached is the last of them, except
            ! on an early stop between grid times, where the last written row is earlier.
            n_ok = max(0, min(st%n_written, n_grid))
            v_ref = 0.0_dp
            sgn = 1.0_dp
            if (scene(i) == SCENE_BELT) then
                v_ref = p(i)%v_b
                sgn = -1.0_dp
            end if
            call summarise(i, n_ok, t_out, y_out, v_ref, sgn)
            if (present(y_keep)) y_keep = y_out
        end subroutine run_one

        !> Fill the monitor part of summary(i) from the first n_ok grid rows.
        subroutine summarise(i, n_ok, t_out, y_out, v_ref, sgn)
            integer, intent(in) :: i, n_ok
            real(dp), intent(in) :: t_out(:), y_out(:, :)
            real(dp), intent(in) :: v_ref   !! relative velocity = sgn * (v - v_ref) [m/s]
            real(dp), intent(in) :: sgn     !! +1 (slope) or -1 (belt)
            real(dp) :: vr, vr_prev, t_half, dv, dv_prev, vscale
            integer :: j
            logical :: have_prev, have_dv

            if (n_ok >= 1) then
                summary(i)%t_last = t_out(n_ok)
                summary(i)%x_end = y_out(1, n_ok)
                summary(i)%v_end = y_out(2, n_ok)
            else
                summary(i)%x_end = x0(i)
                summary(i)%v_end = v0(i)
            end if
            if (summary(i)%status <= -100) return      ! bad input: nothing ran

            summary(i)%v_max = abs(v0(i))
            summary(i)%n_flip = 0
            summary(i)%n_flip_tail = 0
            summary(i)%vrel_min_tail = huge(1.0_dp)
            summary(i)%vrel_max_tail = -huge(1.0_dp)
            t_half = 0.5_dp * t_end(i)
            summary(i)%n_rev = 0
            summary(i)%n_rev_tail = 0
            have_prev = .false.
            have_dv = .false.
            vr_prev = 0.0_dp
            dv_prev = 0.0_dp
            do j = 1, n_ok
                if (.not. ieee_is_finite(y_out(2, j))) exit
                summary(i)%v_max = max(summary(i)%v_max, abs(y_out(2, j)))
                if (j > 1) then
                    dv = y_out(2, j) - y_out(2, j - 1)
                    vscale = max(abs(y_out(2, j)), abs(y_out(2, j - 1)), abs(v_ref))
                    if (abs(dv) > 64.0_dp * epsilon(1.0_dp) * vscale) &
                        call count_sign_change(dv, t_out(j) >= t_half, dv_prev, have_dv, &
                                               summary(i)%n_rev, summary(i)%n_rev_tail)
                end if
                vr = sgn * (y_out(2, j) - v_ref)
                if (t_out(j) >= t_half) then
                    summary(i)%vrel_min_tail = min(summary(i)%vrel_min_tail, vr)
                    summary(i)%vrel_max_tail = max(summary(i)%vrel_max_tail, vr)
                end if
                if (vr /= 0.0_dp) call count_sign_change(vr, t_out(j) >= t_half, vr_prev, have_prev, &
                                                         summary(i)%n_flip, summary(i)%n_flip_tail)
            end do
            if (summary(i)%vrel_min_tail > summary(i)%vrel_max_tail) then   ! no row in the tail
                summary(i)%vrel_min_tail = 0.0_dp
                summary(i)%vrel_max_tail = 0.0_dp
            end if
        end subroutine summarise

        !> Count a change of sign of x against the previous nonzero value (in the tail too).
        pure subroutine count_sign_change(x, in_tail, prev, have_prev, n, n_tail)
            real(dp), intent(in) :: x           !! the new nonzero value
            logical, intent(in) :: in_tail      !! its time is in the second half of the run
            real(dp), intent(inout) :: prev     !! the previous value counted
            logical, intent(inout) :: have_prev !! prev holds a value
            integer, intent(inout) :: n, n_tail !! sign changes, overall and in the tail
            if (have_prev .and. (x > 0.0_dp .neqv. prev > 0.0_dp)) then
                n = n + 1
                if (in_tail) n_tail = n_tail + 1
            end if
            prev = x
            have_prev = .true.
        end subroutine count_sign_change

    end subroutine simulate_batch

end module stickslip_batch
