!> Many simulations in one call: a loop over parameter sets, in parallel with OpenMP (the
!! thread count is an argument), each set a scene's (`stickslip_simulate::simulate`,
!! `simulate_batch`) or a user's model (`stickslip_user_model`, `simulate_model_batch`), run
!! and reduced to a compact summary by the same loop, so that memory stays bounded whatever
!! the number of steps.
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
!! has no mutable module variables, so sets share nothing but their read-only inputs; a
!! model row builds its own system from its own `stickslip_model` (one per set).
module stickslip_batch
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_DIM, SS_BAD_N_OUT
    use stickslip_params, only: NAME_LEN
    use stickslip_ode, only: ode_stats, stats_integers, stats_reals, STATS_INTEGER_NAMES, STATS_REAL_NAMES
    use stickslip_model_system, only: model_system
    use stickslip_simulate, only: simulate
    use stickslip_registry, only: METHOD_TABLE
    use stickslip_user_model, only: stickslip_model
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
    !$ use omp_lib, only: omp_get_max_threads
    implicit none
    private

    public :: batch_summary, simulate_batch, simulate_model_batch, batch_threads_available, batch_integers, batch_reals
    public :: batch_tables

    !> Names of the integer and real fields of a summary, in the order of `batch_integers`
    !! and `batch_reals`: the run's counters (ode_stats), then the monitor's.
    character(len=*), parameter, public :: BATCH_INTEGER_NAMES = STATS_INTEGER_NAMES // &
        ' n_flip n_flip_tail n_rev n_rev_tail'
    character(len=*), parameter, public :: BATCH_REAL_NAMES = STATS_REAL_NAMES // &
        ' t_last v_max vrel_min_tail vrel_max_tail seconds'
    !! names of the real fields of a summary, in the order of `batch_reals`

    !> The compact outcome of one parameter set.
    type :: batch_summary
        type(ode_stats) :: stats              !! counters and status of the run
        real(dp)   :: t_last = 0.0_dp         !! last monitor-grid time written (t_end on success) [s]
        real(dp), allocatable :: y_end(:)     !! state at t_last (y0 when nothing was written)
        !> max |v| of the monitored body (block 1 on the chain) over the initial state and the
        !! monitor grid [m/s]
        real(dp)   :: v_max = 0.0_dp
        integer    :: n_flip = 0              !! sign changes of the relative velocity on the monitor grid
        integer    :: n_flip_tail = 0         !! the same, over the grid times >= t_end / 2
        !> Reversals of the direction of v between grid points (successive differences of
        !! opposite sign, both above 64 eps max|v|): high-frequency content.
        integer    :: n_rev = 0
        integer    :: n_rev_tail = 0          !! the same, over the grid times >= t_end / 2
        real(dp)   :: vrel_min_tail = 0.0_dp  !! min relative velocity over times >= t_end / 2 [m/s]
        real(dp)   :: vrel_max_tail = 0.0_dp  !! max relative velocity over times >= t_end / 2 [m/s]
        real(dp)   :: seconds = 0.0_dp        !! wall-clock time of this set (one thread) [s]
        integer    :: elem_kind = 0           !! a model row's bad element: its kind (ELEM_*; 0: none)
        integer    :: elem_index = 0          !! and its index, from 1 (0: none)
    end type batch_summary

contains

    !> Number of threads OpenMP would use by default (1 without OpenMP).
    integer function batch_threads_available() result(n)
        n = 1
        !$ n = omp_get_max_threads()
    end function batch_threads_available

    !> The integer fields of s in the order of BATCH_INTEGER_NAMES.
    pure function batch_integers(s) result(v)
        type(batch_summary), intent(in) :: s
        !! the summary of one parameter set
        integer(8) :: v(size(stats_integers(s%stats)) + 4)
        v = [stats_integers(s%stats), int([s%n_flip, s%n_flip_tail, s%n_rev, s%n_rev_tail], 8)]
    end function batch_integers

    !> The real fields of s in the order of BATCH_REAL_NAMES.
    pure function batch_reals(s) result(v)
        type(batch_summary), intent(in) :: s
        !! the summary of one parameter set
        real(dp) :: v(size(stats_reals(s%stats)) + 5)
        v = [stats_reals(s%stats), s%t_last, s%v_max, s%vrel_min_tail, s%vrel_max_tail, s%seconds]
    end function batch_reals

    !> The summaries as tables, one column per set: the integer fields (as reals, exact below
    !! 2^53) and the real fields in the order of BATCH_INTEGER_NAMES and BATCH_REAL_NAMES, and
    !! the final states; SS_BAD_DIM when the tables' sizes do not fit the summaries.
    subroutine batch_tables(s, istats, rstats, yend, status)
        type(batch_summary), intent(in) :: s(:)     !! the summaries (with y_end)
        real(dp), intent(out) :: istats(:, :)       !! (number of integer fields, size(s))
        real(dp), intent(out) :: rstats(:, :)       !! (number of real fields, size(s))
        real(dp), intent(out) :: yend(:, :)         !! (nmax, size(s)) final states
        integer, intent(out) :: status              !! SS_OK or SS_BAD_DIM
        type(batch_summary) :: empty
        integer :: i
        istats = 0.0_dp
        rstats = 0.0_dp
        yend = 0.0_dp
        status = SS_OK
        if (size(istats, 1) /= size(batch_integers(empty)) .or. size(rstats, 1) /= size(batch_reals(empty)) .or. &
            size(istats, 2) /= size(s) .or. size(rstats, 2) /= size(s) .or. size(yend, 2) /= size(s)) then
            status = SS_BAD_DIM
            return
        end if
        do i = 1, size(s)
            istats(:, i) = real(batch_integers(s(i)), dp)
            rstats(:, i) = batch_reals(s(i))
            if (allocated(s(i)%y_end)) yend(:, i) = s(i)%y_end
        end do
    end subroutine batch_tables

    !> Run every parameter set i = 1 .. size(scene) through `simulate` and summarise it.
    !!
    !! Physical parameters and controls are named once (pkeys, ckeys) and valued per set
    !! (columns of pvals, cvals); a NaN value means "not given" (the default), so that rows
    !! of different methods can share one list of control names. y0(:, i) holds the initial
    !! state of set i in its first nstate(i) entries: 2 + (its law's internal states), times
    !! n_blocks on the chain (rows of several sizes share y0; the rest is not read).
    !! All per-set arrays must have the same number of sets; status = SS_BAD_DIM otherwise,
    !! and SS_BAD_N_OUT when n_grid < 1. A bad input in one set (a code <= -100) or a run
    !! that ends early is reported in that set's summary only.
    subroutine simulate_batch(scene, law, method, pkeys, pvals, nstate, y0, t_end, rtol, atol, ckeys, &
                              cvals, n_grid, threads, summary, status, y_grid, stop_flag)
        integer, intent(in) :: scene(:)                 !! scene code, per set
        integer, intent(in) :: law(:)                   !! friction law code, per set
        integer, intent(in) :: method(:)                !! method code, per set
        character(len=*), intent(in) :: pkeys(:)        !! physical parameter names
        real(dp), intent(in) :: pvals(:, :)             !! (size(pkeys), nset) values; NaN: default
        integer, intent(in) :: nstate(:)                !! state size of each set (n_blocks (2 + the law's states))
        real(dp), intent(in) :: y0(:, :)                !! (nmax, nset) initial states, first nstate(i) used
        real(dp), intent(in) :: t_end(:)                !! final time [s], per set
        real(dp), intent(in) :: rtol(:)                 !! relative tolerance, per set (adaptive methods)
        real(dp), intent(in) :: atol(:)                 !! absolute tolerance, per set (adaptive methods)
        character(len=*), intent(in) :: ckeys(:)        !! control names
        real(dp), intent(in) :: cvals(:, :)             !! (size(ckeys), nset) values; NaN: not given
        integer, intent(in) :: n_grid                   !! monitor grid points per set, >= 1
        integer, intent(in) :: threads                  !! OpenMP threads (< 1: OpenMP's default)
        type(batch_summary), intent(out) :: summary(:)  !! one summary per set
        integer, intent(out) :: status                  !! SS_OK, SS_BAD_DIM or SS_BAD_N_OUT
        real(dp), intent(out), optional :: y_grid(:, :, :)  !! (nmax, n_grid, nset) states on the grid
        !> A flag another thread may set nonzero to stop every run (SS_INTERRUPTED).
        integer, pointer, intent(in), optional :: stop_flag
        type(stickslip_model) :: no_models(0)
        real(dp) :: no_events(4, 0, 0)

        status = SS_OK
        if (size(scene) /= size(method) .or. size(law) /= size(method) .or. size(pvals, 2) /= size(method) .or. &
            size(pvals, 1) /= size(pkeys)) status = SS_BAD_DIM
        if (status /= SS_OK) return
        call run_rows(no_models, scene, law, method, pkeys, pvals, nstate, y0, t_end, rtol, atol, ckeys, &
                      cvals, n_grid, threads, summary, status, y_grid, stop_flag, no_events)
    end subroutine simulate_batch

    !> Run models (your own systems, `stickslip_user_model`), one per set, each from y0(1:nstate(i), i)
    !! with its method and controls, through the same loop, threads and summary as
    !! `simulate_batch`'s scene rows; body 1 is monitored, its velocity (relative to the ground)
    !! standing for the relative velocity of the summary. Every set's model is built (checked)
    !! before any set runs: a bad one leaves its status (<= -100) and (elem_kind, elem_index)
    !! naming the element in its summary, and nothing runs. Arguments and status otherwise as
    !! `simulate_batch`'s.
    subroutine simulate_model_batch(models, method, nstate, y0, t_end, rtol, atol, ckeys, cvals, n_grid, &
                                    threads, events, summary, status, y_grid, stop_flag)
        type(stickslip_model), intent(inout) :: models(:)  !! the model of each set (`model_from_arrays`)
        integer, intent(in) :: method(:)                !! method code, per set
        integer, intent(in) :: nstate(:)                !! state size of each set (every body's x, v, the law states)
        real(dp), intent(in) :: y0(:, :)                !! (nmax, nset) initial states, first nstate(i) used
        real(dp), intent(in) :: t_end(:)                !! final time [s], per set
        real(dp), intent(in) :: rtol(:)                 !! relative tolerance, per set (adaptive methods)
        real(dp), intent(in) :: atol(:)                 !! absolute tolerance, per set (adaptive methods)
        character(len=*), intent(in) :: ckeys(:)        !! control names
        real(dp), intent(in) :: cvals(:, :)             !! (size(ckeys), nset) values; NaN: not given
        integer, intent(in) :: n_grid                   !! monitor grid points per set, >= 1
        integer, intent(in) :: threads                  !! OpenMP threads (< 1: OpenMP's default)
        !> (4, room, nset): each set's stick/slip events under event_driven (t [s], kind, position
        !! [m], contact), as `stickslip_simulate`'s; room 0: none kept
        real(dp), intent(inout) :: events(:, :, :)
        type(batch_summary), intent(out) :: summary(:)  !! one summary per set
        integer, intent(out) :: status                  !! SS_OK, SS_BAD_DIM or SS_BAD_N_OUT
        real(dp), intent(out), optional :: y_grid(:, :, :)  !! (nmax, n_grid, nset) states on the grid
        !> A flag another thread may set nonzero to stop every run (SS_INTERRUPTED).
        integer, pointer, intent(in), optional :: stop_flag
        type(model_system) :: sys
        integer :: i

        status = SS_OK
        if (size(models) /= size(method) .or. size(summary) /= size(method) .or. size(events, 1) /= 4 .or. &
            size(events, 3) /= size(method)) then
            status = SS_BAD_DIM
            return
        end if
        do i = 1, size(models)
            call models(i)%build(sys, summary(i)%stats%status, summary(i)%elem_kind, summary(i)%elem_index)
        end do
        if (any(summary%stats%status /= SS_OK)) return
        call run_rows(models, [integer ::], [integer ::], method, [character(len=NAME_LEN) ::], &
                      reshape([real(dp) ::], [0, size(method)]), nstate, y0, t_end, rtol, atol, ckeys, cvals, &
                      n_grid, threads, summary, status, y_grid, stop_flag, events)
    end subroutine simulate_model_batch

    !> The loop of both batches over the sets, OpenMP-parallel: scene rows (scene, law, pkeys,
    !! pvals; models empty) or model rows (models; scene and law empty). Checks the sizes.
    subroutine run_rows(models, scene, law, method, pkeys, pvals, nstate, y0, t_end, rtol, atol, ckeys, &
                        cvals, n_grid, threads, summary, status, y_grid, stop_flag, events)
        type(stickslip_model), intent(inout) :: models(:)  !! the model of each set, or none
        integer, intent(in) :: scene(:), law(:)         !! scene and law codes, per set (scene rows)
        integer, intent(in) :: method(:)                !! method code, per set
        character(len=*), intent(in) :: pkeys(:)        !! physical parameter names (scene rows)
        real(dp), intent(in) :: pvals(:, :)             !! (size(pkeys), nset) values; NaN: default
        integer, intent(in) :: nstate(:)                !! state size of each set
        real(dp), intent(in) :: y0(:, :)                !! (nmax, nset) initial states
        real(dp), intent(in) :: t_end(:), rtol(:), atol(:)  !! final time [s], tolerances, per set
        character(len=*), intent(in) :: ckeys(:)        !! control names
        real(dp), intent(in) :: cvals(:, :)             !! (size(ckeys), nset) values; NaN: not given
        integer, intent(in) :: n_grid                   !! monitor grid points per set, >= 1
        integer, intent(in) :: threads                  !! OpenMP threads (< 1: OpenMP's default)
        type(batch_summary), intent(inout) :: summary(:)  !! one summary per set
        integer, intent(out) :: status                  !! SS_OK, SS_BAD_DIM or SS_BAD_N_OUT
        real(dp), intent(out), optional :: y_grid(:, :, :)  !! (nmax, n_grid, nset) states on the grid
        integer, pointer, intent(in), optional :: stop_flag  !! nonzero: stop every run
        real(dp), intent(inout) :: events(:, :, :)      !! (4, room, nset) a model row's events (none: size 0)
        integer :: nset, i, nthr
        logical :: keep

        nset = size(method)
        status = SS_OK
        if (size(y0, 2) /= nset .or. size(nstate) /= nset .or. size(t_end) /= nset .or. &
            size(rtol) /= nset .or. size(atol) /= nset .or. size(cvals, 2) /= nset .or. &
            size(cvals, 1) /= size(ckeys) .or. size(summary) /= nset) then
            status = SS_BAD_DIM
        else if (n_grid < 1) then
            status = SS_BAD_N_OUT
        else if (any(nstate < 2) .or. any(nstate > size(y0, 1))) then
            status = SS_BAD_DIM
        end if
        keep = present(y_grid)
        if (keep .and. status == SS_OK) then
            if (size(y_grid, 1) /= size(y0, 1) .or. size(y_grid, 2) /= n_grid .or. &
                size(y_grid, 3) /= nset) status = SS_BAD_DIM
        end if
        if (status /= SS_OK) return
        if (keep) y_grid = 0.0_dp

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
            real(dp), intent(inout), optional :: y_keep(:, :)
            real(dp), allocatable :: t_out(:), y_out(:, :)
            class(model_system), allocatable :: sys
            integer(8) :: c0, c1, rate
            integer :: j, n, n_ok
            logical :: pset(size(pkeys)), cset(size(ckeys))
            real(dp) :: dt

            allocate(t_out(n_grid))
            if (n_grid == 1) then
                t_out(1) = t_end(i)
            else
                dt = t_end(i) / real(n_grid - 1, dp)
                do j = 1, n_grid - 1
                    t_out(j) = real(j - 1, dp) * dt
                end do
                t_out(n_grid) = t_end(i)
            end if
            cset = .not. ieee_is_nan(cvals(:, i))

            n = nstate(i)
            allocate(y_out(n, n_grid))
            y_out = 0.0_dp
            call system_clock(c0, rate)
            if (size(models) > 0) then
                call models(i)%simulate(trim(METHOD_TABLE(method(i))%name), t_end(i), t_out, y_out, &
                                        summary(i)%stats, [rtol(i)], [atol(i)], pack(ckeys, cset), &
                                        pack(cvals(:, i), cset), summary(i)%elem_kind, summary(i)%elem_index, &
                                        stop_flag, events(:, :, i), y0=y0(1:n, i))
            else
                pset = .not. ieee_is_nan(pvals(:, i))
                call simulate(scene(i), law(i), method(i), pack(pkeys, pset), pack(pvals(:, i), pset), &
                              y0(1:n, i), t_end(i), [rtol(i)], [atol(i)], pack(ckeys, cset), &
                              pack(cvals(:, i), cset), t_out, y_out, summary(i)%stats, sys_out=sys, &
                              stop_flag=stop_flag)
            end if
            call system_clock(c1)
            summary(i)%seconds = real(c1 - c0, dp) / real(max(rate, 1_8), dp)

            n_ok = max(0, min(summary(i)%stats%n_written, n_grid))
            allocate(summary(i)%y_end(size(y0, 1)))
            summary(i)%y_end = 0.0_dp
            if (n_ok >= 1) then
                summary(i)%t_last = t_out(n_ok)
                summary(i)%y_end(1:n) = y_out(:, n_ok)
            else
                summary(i)%y_end(1:n) = y0(1:n, i)
            end if
            if (summary(i)%stats%status > -100) then
                if (size(models) > 0) then
                    call summarise(summary(i), size(models(i)%mass), t_end(i), y0(1:n, i), t_out(1:n_ok), &
                                   y_out(:, 1:n_ok))
                else if (allocated(sys)) then
                    call summarise(summary(i), sys%nb, t_end(i), y0(1:n, i), t_out(1:n_ok), y_out(:, 1:n_ok), sys)
                end if
            end if
            if (present(y_keep)) y_keep(1:n, :) = y_out
        end subroutine run_one

    end subroutine run_rows

    !> Fill the monitor part of s from the grid rows written (t(j), y(:, j)). The velocity
    !! monitored is body 1's (block 1 on the chain), the relative velocity contact 1's slip
    !! of the scene's system `sys`; without sys (a model's row), body 1's velocity itself.
    subroutine summarise(s, nb, t_end, y0, t, y, sys)
        type(batch_summary), intent(inout) :: s
        integer, intent(in) :: nb                  !! bodies in the state (velocity of body 1 at nb + 1)
        real(dp), intent(in) :: t_end              !! final time of the run [s]
        real(dp), intent(in) :: y0(:)              !! initial state
        real(dp), intent(in) :: t(:), y(:, :)      !! grid rows written
        class(model_system), intent(in), optional :: sys  !! the scene's system run (relative velocity)
        real(dp) :: vr, vr_prev, t_half, dv, dv_prev, vscale, v_prev, vr_b, v
        integer :: j
        logical :: have_prev, have_dv, in_tail

        s%v_max = abs(y0(nb + 1))
        s%vrel_min_tail = huge(1.0_dp)
        s%vrel_max_tail = -huge(1.0_dp)
        t_half = 0.5_dp * t_end
        have_prev = .false.
        have_dv = .false.
        vr_prev = 0.0_dp
        dv_prev = 0.0_dp
        v_prev = 0.0_dp
        vr_b = 0.0_dp                                 ! |v_ref|: belt speed or 0
        if (present(sys)) vr_b = abs(sys%slip(1, 0.0_dp, spread(0.0_dp, 1, size(y, 1))))
        do j = 1, size(t)
            v = y(nb + 1, j)
            if (.not. ieee_is_finite(v)) exit
            in_tail = t(j) >= t_half
            s%v_max = max(s%v_max, abs(v))
            if (j > 1) then
                dv = v - v_prev
                vscale = max(abs(v), abs(v_prev), vr_b)
                if (abs(dv) > 64.0_dp * epsilon(1.0_dp) * vscale) &
                    call count_sign_change(dv, in_tail, dv_prev, have_dv, s%n_rev, s%n_rev_tail)
            end if
            v_prev = v
            vr = v
            if (present(sys)) vr = sys%slip(1, t(j), y(:, j))
            if (in_tail) then
                s%vrel_min_tail = min(s%vrel_min_tail, vr)
                s%vrel_max_tail = max(s%vrel_max_tail, vr)
            end if
            if (abs(vr) > 0.0_dp) call count_sign_change(vr, in_tail, vr_prev, have_prev, s%n_flip, &
                                                         s%n_flip_tail)
        end do
        if (s%vrel_min_tail > s%vrel_max_tail) then   ! no row in the tail
            s%vrel_min_tail = 0.0_dp
            s%vrel_max_tail = 0.0_dp
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

end module stickslip_batch
