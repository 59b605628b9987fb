!> What the integrators share: the right-hand side of y' = f(t, y) as an abstract type
!! (with a Jacobian that defaults to finite differences), the controls every method reads,
!! the counters of a run, and checks on output grids, states, tolerances and controls.
!!
!! Output convention of every integrator: arrays t_out(m) and y_out(n, m) owned by the
!! caller. In grid mode t_out holds requested times (non-decreasing, in [t0, t_end]) and
!! the integrator fills y_out at them by its dense output; in every-step mode it writes
!! (t, y) of the initial state and of each accepted step, up to m rows.
!!
!! A user integrates their own ODE by extending `ode_system` and implementing `rhs`
!! (and, for the implicit methods, optionally `jacobian`); their data travels in the
!! extension, not through globals.
module stickslip_ode
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_N_OUT, SS_BAD_DIM, SS_BAD_Y0, SS_BAD_T_END, &
                               SS_BAD_RTOL, SS_BAD_ATOL, SS_BAD_HMIN, SS_BAD_HMAX, SS_BAD_H0, &
                               SS_BAD_MAX_STEPS, SS_BAD_CONTROL_NAME, SS_BAD_FORCED_GROWTH, SS_BAD_CONTROL, &
                               SS_NONFINITE, SS_DIVERGED, SS_OUTPUT_FULL
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: ode_system, ode_stats, step_controls, method_info, check_problem, check_tolerances, fd_jacobian, fd_band_jacobian, &
              check_step_controls, all_finite, output_start, stats_integers, stats_reals, count_nonunique, hermite, &
              step_count, fixed_steps, step_end, stop_requested, limit_after_forced, set_erk_constant, check_erk_constants, &
              diverged, default_state_bound, linear_output

    !> Steps between two looks at a stop flag (a power of 2 minus 1, as a mask).
    integer(8), parameter, public :: STOP_CHECK_MASK = 4095_8

    !> Smallest accepted nonzero rtol of the adaptive methods: 100 units of round-off.
    real(dp), parameter, public :: RTOL_MIN = 100.0_dp * epsilon(1.0_dp)

    !> Growth of the default bound on |y_i| (`default_state_bound`) over max(1, |y0|) [-]: no
    !! system of the library's kind grows by 30 orders of magnitude; one that does overrides
    !! `state_bound`.
    real(dp), parameter, public :: DEFAULT_BOUND_GROWTH = 1.0e30_dp

    !> Margin of a system's energy-based `state_bound` over its energy bound [-]: a state
    !! beyond it has diverged (SS_DIVERGED), whatever the step size or the method's own errors.
    real(dp), parameter, public :: BOUND_MARGIN = 1.0e3_dp

    !> A first-order system y' = f(t, y).
    type, abstract :: ode_system
    contains
        procedure(rhs_iface), deferred :: rhs
        !! the right-hand side f(t, y)
        !> df/dy; the default is forward differences (override it with the analytic one).
        procedure :: jacobian => fd_jacobian
        !> The state order perm in which df/dy is banded, and its band (ml lower, mu upper
        !! diagonals); the default ml = mu = -1 says "dense" (the implicit methods then factor
        !! n x n matrices). A banded system lets RADAU5 factor band matrices: O(n) a step.
        procedure :: bandwidth => dense_bandwidth
        !> df/dy in the order of `bandwidth`, in band storage; the default packs `jacobian`.
        procedure :: band_jacobian => packed_band_jacobian
        !> The components (mask) whose part of a stage equation k = f(t, u + c k) the system
        !! solves itself (`condense_stage`), where a rate that jumps with the state leaves
        !! Newton's method without a solution; the default: none (mask all .false.).
        procedure :: condensed_components => no_condensed_components
        !> Overwrite the condensed components of the stage derivative k so that they solve
        !! their part of k = f(t, u + c k) given the others; the default: nothing to do.
        procedure :: condense_stage => no_condense_stage
        !> f at a stage state y whose condensed components move at the rates k holds (their
        !! part of the stage, set by condense_stage); the default: rhs.
        procedure :: stage_rhs => plain_stage_rhs
        !> Solve the whole stage k = f(t, u + c k) itself, where Newton's method cannot (a law
        !! with an infinite slope at rest); ok = .false. by default: the system has no such
        !! solve (the one-contact scenes with a static law have a bracketed scalar one).
        procedure :: scalar_stage => no_scalar_stage
        !> Bounds on each |y_i| that no solution from y0 over [t0, t_end] reaches: a step that
        !! leaves them ends the run with SS_DIVERGED. The default, DEFAULT_BOUND_GROWTH max(1,
        !! max |y0|), is conservative; the scenes give theirs from their energy.
        procedure :: state_bound => default_state_bound
        !> Called by DOPRI5's every-step mode after each accepted step when its option
        !! notify_steps is set, with the step's end: the integrator's last evaluation of the
        !! right-hand side was there (its FSAL stage), so the system may keep what that
        !! evaluation found; halt = .true. ends the run after this step (status SS_OK,
        !! t_reached the step's end). The default: nothing kept, no halt.
        procedure :: step_accepted => no_step_accepted
        !> The size of each component that the relative tolerance scales, read by the error
        !! norms of dopri5, dop853 and radau5 (weights atol + rtol size): |y_i| by default. A
        !! system overrides it where what matters is smaller than |y_i|: a model gives a
        !! velocity's size as the slip its friction law sees (`stickslip_model_system`).
        procedure :: error_size => plain_error_size
    end type ode_system

    !> The controls every integrator shares; each method reads those its registry entry
    !! lists and ignores the rest. Method-specific controls extend this type
    !! (`dopri5_options`, ...).
    type :: step_controls
        real(dp) :: h = 0.0_dp          !! step size of the fixed-step methods [s]
        real(dp) :: hmin = 0.0_dp       !! step size floor of the adaptive methods; forced steps happen there (0: none) [s]
        real(dp) :: hmax = 0.0_dp       !! largest step of the adaptive methods (0: t_end - t0) [s]
        real(dp) :: h0 = 0.0_dp         !! initial step of the adaptive methods (0: automatic) [s]
        !> Budget of attempted steps (Hairer's NMAX, 1e5; ours is 1e8 because event-free
        !! runs through a friction jump take up to (t_end - t0)/h_min steps).
        integer(8) :: max_steps = 100000000_8
        logical  :: allow_forced = .true.   !! take steps at h_min when the error test fails there
        !> Largest step ratio h_new/h after a forced step, until the controller itself asks
        !! for less (ours: Hairer has no forced steps). 2 doubles the step back up from h_min
        !! instead of jumping by fac2 (DOPRI5: 10 h_min) into the discontinuity, which only
        !! rejects it again. Must exceed 1 (1 would never grow again).
        real(dp) :: fac_forced = 2.0_dp
        !> After a forced step, h is held until this many steps in a row have passed the
        !! error test unforced; only then may it grow (by fac_forced). In a chatter at h_min
        !! the passes come singly between forced steps and each growth was rejected: 2
        !! removes those rejections and costs one step where the motion turns smooth
        !! (0: grow at once).
        integer  :: calm_steps = 2
        logical  :: every_step = .false.    !! output every accepted step instead of a grid
        !> When associated and nonzero (set by another thread: a Ctrl-C), the run stops
        !! with SS_INTERRUPTED; checked every STOP_CHECK_STEPS steps.
        integer, pointer :: stop_flag => null()
        !> Bounds on each |y_i| of an accepted state (SS_DIVERGED beyond them), for the methods
        !! that see a system's contact model only (moreau, event_driven): the caller sets them
        !! from the system's `state_bound` (unallocated: only finiteness is checked). The
        !! methods given the ode_system itself ask its `state_bound`.
        real(dp), allocatable :: y_bound(:)
    contains
        !> Set one control by name (flags: value /= 0); SS_OK or SS_BAD_CONTROL_NAME.
        !! Method-specific options types override it and fall back to this one.
        procedure :: set => set_step_control
    end type step_controls

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
        integer(8) :: njac = 0      !! Jacobian evaluations (NJAC; implicit methods)
        integer(8) :: ndec = 0      !! LU decompositions (NDEC; implicit methods)
        integer(8) :: nsol = 0      !! forward-backward substitutions (NSOL; implicit methods)
        integer(8) :: nevents = 0   !! stick/slip transitions (event_driven)
        integer(8) :: ncontact_iter = 0  !! sweeps of the contact solver, all steps together (moreau)
        real(dp)   :: contact_residual = 0.0_dp  !! largest final residual of a step's contact solve (moreau) [m/s]
        integer    :: contact_worst = 0  !! the contact (1-based) whose solve failed (SS_CONTACT_FAILED), else 0
        integer(8) :: nonunique = 0      !! steps (moreau, implicit_euler, galpha) or mode decisions
                                         !! (event_driven) whose contact problem had another solution
                                         !! (`stickslip_contact_solver`'s notes say which each finds)
        real(dp)   :: t_nonunique = 0.0_dp  !! the time of the first of them (`count_nonunique`; 0 where none) [s]
        logical    :: stiff = .false.   !! 15 such tests in a row: the problem is probably stiff
        integer    :: n_written = 0     !! output rows written
        real(dp)   :: t_reached = 0.0_dp  !! time reached when the run ended [s]
        real(dp)   :: h_last = 0.0_dp     !! last step size tried [s]
        integer    :: status = SS_OK      !! SS_OK or a negative status code
    end type ode_stats

    !> What a method is, for the registry: name, order, kind, and the controls it reads
    !! (space-separated names; rtol and atol are passed as arrays beside the others).
    type :: method_info
        character(len=16) :: name = ''        !! method name, as users write it
        integer :: order = 0                  !! order of convergence
        logical :: adaptive = .false.         !! error-controlled step (else fixed step h)
        logical :: implicit = .false.         !! implicit method (uses the Jacobian)
        character(len=160) :: controls = ''   !! the controls it reads
        character(len=64) :: doc = ''         !! one line on what it is
        character(len=64) :: laws = ''        !! the laws it takes, space-separated (empty: every law)
    end type method_info

    !> Names of the integer and real counters of ode_stats, in the order of
    !! `stats_integers` and `stats_reals`: the Python and C layers read them by name.
    character(len=*), parameter, public :: STATS_INTEGER_NAMES = &
        'nfev nstep naccept nreject nforced nstiff stiff njac ndec nsol n_written status nevents ncontact_iter' // &
        ' contact_worst nonunique'
    character(len=*), parameter, public :: STATS_REAL_NAMES = 't_reached h_last contact_residual t_nonunique'
    !! names of the real counters, in the order of `stats_reals`

contains

    !> |y_i| (the default `error_size`).
    subroutine plain_error_size(self, t, y, size_y)
        class(ode_system), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! state
        real(dp), intent(out) :: size_y(:)  !! the size of each component
        size_y = abs(y)
    end subroutine plain_error_size

    !> .true. when the caller has asked the run to stop: the flag is looked at only every
    !! STOP_CHECK_MASK + 1 steps, so that the check costs nothing in the hot loop.
    logical function stop_requested(ctl, nstep)
        class(step_controls), intent(in) :: ctl   !! controls holding the optional flag
        integer(8), intent(in) :: nstep           !! steps attempted so far
        stop_requested = .false.
        if (iand(nstep, STOP_CHECK_MASK) /= 0) return
        if (.not. associated(ctl%stop_flag)) return
        stop_requested = ctl%stop_flag /= 0
    end function stop_requested

    !> The integer counters of st in the order of STATS_INTEGER_NAMES.
    pure function stats_integers(st) result(v)
        type(ode_stats), intent(in) :: st   !! counters of a run
        integer(8) :: v(16)
        v = [st%nfev, st%nstep, st%naccept, st%nreject, st%nforced, st%nstiff, &
             merge(1_8, 0_8, st%stiff), st%njac, st%ndec, st%nsol, int(st%n_written, 8), &
             int(st%status, 8), st%nevents, st%ncontact_iter, int(st%contact_worst, 8), st%nonunique]
    end function stats_integers

    !> The real counters of st in the order of STATS_REAL_NAMES.
    pure function stats_reals(st) result(v)
        type(ode_stats), intent(in) :: st   !! counters of a run
        real(dp) :: v(4)
        v = [st%t_reached, st%h_last, st%contact_residual, st%t_nonunique]
    end function stats_reals

    !> Count a step or decision at time t whose contact problem had another solution
    !! (st%nonunique), the first one's time kept in st%t_nonunique.
    pure subroutine count_nonunique(st, t)
        type(ode_stats), intent(inout) :: st   !! counters of a run
        real(dp), intent(in) :: t              !! the step's or decision's time [s]
        if (st%nonunique == 0) st%t_nonunique = t
        st%nonunique = st%nonunique + 1
    end subroutine count_nonunique

    function set_step_control(self, name, value) result(status)
        class(step_controls), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts and flags as reals)
        integer :: status
        status = SS_OK
        select case (name)
        case ('h');            self%h = value
        case ('hmin');         self%hmin = value
        case ('hmax');         self%hmax = value
        case ('h0');           self%h0 = value
        case ('max_steps')
            if (value >= 1.0_dp .and. value <= 9.0e18_dp) then
                self%max_steps = int(value, 8)
            else
                status = SS_BAD_MAX_STEPS
            end if
        case ('allow_forced'); self%allow_forced = value /= 0.0_dp
        case ('fac_forced');   self%fac_forced = value
        case ('calm_steps')
            if (value >= 0.0_dp .and. value <= real(huge(1), dp)) then
                self%calm_steps = int(value)
            else
                status = SS_BAD_FORCED_GROWTH
            end if
        case ('every_step');   self%every_step = value /= 0.0_dp
        case default;          status = SS_BAD_CONTROL_NAME
        end select
    end function set_step_control

    !> Number of steps of the grid t0 + i h with the last step ending at t_end (never of
    !! zero length), as a real number so that it cannot overflow.
    pure function step_count(t0, t_end, h) result(nsteps)
        real(dp), intent(in) :: t0, t_end, h    !! interval and step size [s]
        real(dp) :: nsteps
        ! A relative slack of 1e-12 keeps (t_end - t0)/h = 20000.000000001 at 20000 steps.
        nsteps = max(1.0_dp, (t_end - t0) / h * (1.0_dp - 1.0e-12_dp))
        if (nsteps >= 9.0e18_dp) return
        nsteps = real(ceiling(nsteps, kind=8), dp)
        ! The last grid point before t_end must lie strictly before it (cancellation in
        ! t_end - t0 can make the quotient one too large).
        do while (nsteps > 1.0_dp)
            if (t0 + (nsteps - 1.0_dp) * h < t_end) exit
            nsteps = nsteps - 1.0_dp
        end do
    end function step_count

    !> The steps of a fixed-step run from t0 to t_end with step h (`step_count`): n_total
    !! steps reach t_end (huge(n_total) when more than an integer(8) holds: never reached),
    !! and the run takes nsteps = min(n_total, budget) of them.
    pure subroutine fixed_steps(t0, t_end, h, budget, n_total, nsteps)
        real(dp), intent(in) :: t0, t_end, h    !! interval and step size [s]
        integer(8), intent(in) :: budget        !! most steps the run may take
        integer(8), intent(out) :: n_total      !! steps to t_end
        integer(8), intent(out) :: nsteps       !! steps to take
        real(dp) :: nsteps_real
        nsteps_real = step_count(t0, t_end, h)
        n_total = huge(n_total)
        if (nsteps_real < 9.0e18_dp) n_total = int(nsteps_real, 8)
        nsteps = min(n_total, budget)
    end subroutine fixed_steps

    !> The end of step i of a fixed-step run (`fixed_steps`): t0 + i h, t_end exactly at the
    !! last step n_total [s].
    pure real(dp) function step_end(t0, t_end, h, i, n_total) result(t1)
        real(dp), intent(in) :: t0, t_end, h    !! interval and step size [s]
        integer(8), intent(in) :: i, n_total    !! the step, and the steps to t_end
        if (i == n_total) then
            t1 = t_end
        else
            t1 = t0 + real(i, dp) * h
        end if
    end function step_end

    !> The default bound on |y_i|: DEFAULT_BOUND_GROWTH max(1, max_j |y0_j|) for every i.
    function default_state_bound(self, t0, y0, t_end) result(bound)
        class(ode_system), intent(in) :: self
        !! the system
        real(dp), intent(in) :: t0          !! initial time [s]
        real(dp), intent(in) :: y0(:)       !! initial state
        real(dp), intent(in) :: t_end       !! final time [s]
        real(dp) :: bound(size(y0))         !! bound on each |y_i| [units of y_i]
        bound = DEFAULT_BOUND_GROWTH * max(1.0_dp, maxval(abs(y0)))
    end function default_state_bound

    !> .true. when the accepted state y has left its bound (a component with |y_i| > bound_i)
    !! or is not finite; stats%status is then SS_DIVERGED (or SS_NONFINITE). Without a bound
    !! (absent, or an unallocated array) only finiteness is checked. One comparison per
    !! component: the methods call it once per accepted step, and a run that stays inside is
    !! unchanged.
    logical function diverged(y, stats, bound)
        real(dp), intent(in) :: y(:)                !! the accepted state
        type(ode_stats), intent(inout) :: stats     !! status set when diverged
        real(dp), intent(in), optional :: bound(:)  !! bound on each |y_i| [units of y_i]
        if (present(bound)) then
            diverged = .not. all(abs(y) <= bound)   ! .true. for a NaN too
        else
            diverged = .not. all(ieee_is_finite(y))
        end if
        if (.not. diverged) return
        stats%status = merge(SS_DIVERGED, SS_NONFINITE, all(ieee_is_finite(y)))
    end function diverged

    !> The default: no component is condensed.
    subroutine no_condensed_components(self, mask)
        class(ode_system), intent(in) :: self
        !! the system
        logical, intent(out) :: mask(:)     !! (n) .true. for a component condense_stage solves
        mask = .false.
    end subroutine no_condensed_components

    !> The default: nothing is condensed, k is left as it is.
    subroutine no_condense_stage(self, u, c, k)
        class(ode_system), intent(inout) :: self
        !! the system
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative; its condensed components on exit
    end subroutine no_condense_stage

    !> The default: no stage solve of the system's own.
    subroutine no_scalar_stage(self, t, u, c, k, nfev, ok)
        class(ode_system), intent(inout) :: self
        !! the system
        real(dp), intent(in)    :: t        !! stage time [s]
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative: a guess in, the solution out
        integer(8), intent(inout) :: nfev   !! evaluations of f, counted
        logical, intent(out)    :: ok       !! .true.: k solves the stage
        ok = .false.
    end subroutine no_scalar_stage

    !> The default: nothing to keep, never halt.
    subroutine no_step_accepted(self, t, h, y, dydt, halt)
        class(ode_system), intent(inout) :: self
        !! the system
        real(dp), intent(in)  :: t          !! the step's end [s]
        real(dp), intent(in)  :: h          !! the step's length [s]
        real(dp), intent(in)  :: y(:)       !! the state at t
        real(dp), intent(in)  :: dydt(:)    !! f(t, y), the integrator's last evaluation
        logical, intent(out)  :: halt       !! .true.: end the run after this step
        halt = .false.
    end subroutine no_step_accepted

    !> The default: f(t, y), nothing condensed.
    subroutine plain_stage_rhs(self, t, y, k, f)
        class(ode_system), intent(inout) :: self
        !! the system
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! stage state
        real(dp), intent(in)  :: k(:)       !! stage derivative (its condensed components read)
        real(dp), intent(out) :: f(:)       !! f(t, y)
        call self%rhs(t, y, f)
    end subroutine plain_stage_rhs

    !> The default band: none (ml = mu = -1, perm the identity).
    subroutine dense_bandwidth(self, perm, ml, mu)
        class(ode_system), intent(in) :: self
        !! the system
        integer, intent(out) :: perm(:)     !! (n) state index at each position of the banded order
        integer, intent(out) :: ml          !! lower bandwidth (-1: dense)
        integer, intent(out) :: mu          !! upper bandwidth (-1: dense)
        integer :: i
        perm = [(i, i = 1, size(perm))]
        ml = -1
        mu = -1
    end subroutine dense_bandwidth

    !> df/dy in the order of `bandwidth` in band storage, jb(mu + 1 + i - j, j) =
    !! J(perm(i), perm(j)) for max(1, j - mu) <= i <= min(n, j + ml), from the dense
    !! `jacobian` (a banded system overrides it with an O(n) one).
    subroutine packed_band_jacobian(self, t, y, f, jb, nfev)
        class(ode_system), intent(inout) :: self
        !! the system
        real(dp), intent(in)    :: t             !! time [s]
        real(dp), intent(in)    :: y(:)          !! state
        real(dp), intent(in)    :: f(:)          !! f(t, y), already evaluated
        real(dp), intent(out)   :: jb(:, :)      !! (ml + mu + 1, n) band of the reordered Jacobian
        integer(8), intent(inout) :: nfev        !! evaluation counter
        real(dp), allocatable :: dfdy(:, :)
        integer :: perm(size(y)), ml, mu, i, j, n
        n = size(y)
        call self%bandwidth(perm, ml, mu)
        allocate(dfdy(n, n))
        call self%jacobian(t, y, f, dfdy, nfev)
        jb = 0.0_dp
        do j = 1, n
            do i = max(1, j - mu), min(n, j + ml)
                jb(mu + 1 + i - j, j) = dfdy(perm(i), perm(j))
            end do
        end do
    end subroutine packed_band_jacobian

    !> Forward-difference Jacobian df/dy(t, y) with Hairer's increments
    !! sqrt(eps max(1e-5, |y_j|)): n evaluations of f, added to nfev.
    subroutine fd_jacobian(self, t, y, f, dfdy, nfev)
        class(ode_system), intent(inout) :: self
        !! the system (its rhs is evaluated)
        real(dp), intent(in)    :: t             !! time [s]
        real(dp), intent(in)    :: y(:)          !! state
        real(dp), intent(in)    :: f(:)          !! f(t, y), already evaluated
        real(dp), intent(out)   :: dfdy(:, :)    !! (n, n) Jacobian, dfdy(i, j) = d f_i / d y_j
        integer(8), intent(inout) :: nfev        !! evaluation counter (+ n here; + 0 when analytic)
        real(dp) :: yy(size(y)), f1(size(y)), delt
        integer :: j
        yy = y
        do j = 1, size(y)
            delt = sqrt(epsilon(1.0_dp) * max(1.0e-5_dp, abs(y(j))))
            yy(j) = y(j) + delt
            call self%rhs(t, yy, f1)
            dfdy(:, j) = (f1 - f) / delt
            yy(j) = y(j)
        end do
        nfev = nfev + size(y)
    end subroutine fd_jacobian

    !> df/dy in the order perm, band storage jb(mu + 1 + i - j, j) = J(perm(i), perm(j)), by
    !! forward differences that perturb every (ml + mu + 1)-th position together (Curtis,
    !! Powell and Reid): positions of one group lie more than ml + mu apart, so their columns
    !! share no row of the band. ml + mu + 1 evaluations of f whatever n, Hairer's increments.
    subroutine fd_band_jacobian(self, t, y, f, perm, ml, mu, jb, nfev)
        class(ode_system), intent(inout) :: self
        !! the system (its rhs is evaluated)
        real(dp), intent(in)    :: t             !! time [s]
        real(dp), intent(in)    :: y(:)          !! state
        real(dp), intent(in)    :: f(:)          !! f(t, y), already evaluated
        integer, intent(in)     :: perm(:)       !! (n) state index at each position of the banded order
        integer, intent(in)     :: ml            !! lower bandwidth, >= 0
        integer, intent(in)     :: mu            !! upper bandwidth, >= 0
        real(dp), intent(out)   :: jb(:, :)      !! (ml + mu + 1, n) band of the reordered Jacobian
        integer(8), intent(inout) :: nfev        !! evaluation counter (+ the evaluations made here)
        real(dp) :: yy(size(y)), f1(size(y)), delt(size(y))
        integer :: i, j, nn, grp
        nn = size(y)
        jb = 0.0_dp
        do grp = 1, min(ml + mu + 1, nn)
            yy = y
            do j = grp, nn, ml + mu + 1
                delt(j) = sqrt(epsilon(1.0_dp) * max(1.0e-5_dp, abs(y(perm(j)))))
                yy(perm(j)) = y(perm(j)) + delt(j)
            end do
            call self%rhs(t, yy, f1)
            nfev = nfev + 1
            do j = grp, nn, ml + mu + 1
                do i = max(1, j - mu), min(nn, j + ml)
                    jb(mu + 1 + i - j, j) = (f1(perm(i)) - f(perm(i))) / delt(j)
                end do
            end do
        end do
    end subroutine fd_band_jacobian

    !> Check tolerances of the adaptive methods: size 1 or n each, rtol 0 or in
    !! [RTOL_MIN, 1), atol > 0 (a zero atol makes the error scale 0/0 for a component
    !! that is exactly 0 at both ends of a step, such as a body at rest).
    pure function check_tolerances(n, rtol, atol) result(status)
        integer, intent(in)  :: n           !! dimension of the state
        real(dp), intent(in) :: rtol(:)     !! relative tolerances, size 1 or n [-]
        real(dp), intent(in) :: atol(:)     !! absolute tolerances, size 1 or n [units of y]
        integer :: status
        status = SS_OK
        if ((size(rtol) /= 1 .and. size(rtol) /= n) .or. (size(atol) /= 1 .and. size(atol) /= n)) then
            status = SS_BAD_DIM
        else if (.not. all(ieee_is_finite(rtol)) .or. any(rtol < 0.0_dp) .or. any(rtol >= 1.0_dp) &
                 .or. any(rtol > 0.0_dp .and. rtol < RTOL_MIN)) then
            status = SS_BAD_RTOL
        else if (.not. all(ieee_is_finite(atol)) .or. any(atol <= 0.0_dp)) then
            status = SS_BAD_ATOL
        end if
    end function check_tolerances

    !> Check the shared controls an adaptive method reads: h_min, h_max, h0, max_steps.
    pure function check_step_controls(ctl, t0, t_end) result(status)
        class(step_controls), intent(in) :: ctl  !! the controls
        real(dp), intent(in) :: t0, t_end       !! the interval [s]
        integer :: status
        status = SS_OK
        if (.not. ieee_is_finite(ctl%hmin) .or. ctl%hmin < 0.0_dp .or. ctl%hmin > t_end - t0) then
            status = SS_BAD_HMIN
        else if (.not. ieee_is_finite(ctl%hmax) .or. ctl%hmax < 0.0_dp .or. &
                 (ctl%hmax > 0.0_dp .and. ctl%hmax < ctl%hmin)) then
            status = SS_BAD_HMAX
        else if (.not. ieee_is_finite(ctl%h0) .or. ctl%h0 < 0.0_dp) then
            status = SS_BAD_H0
        else if (ctl%max_steps < 1) then
            status = SS_BAD_MAX_STEPS
        else if (.not. (ctl%fac_forced > 1.0_dp .and. ieee_is_finite(ctl%fac_forced)) .or. &
                 ctl%calm_steps < 0) then
            status = SS_BAD_FORCED_GROWTH
        end if
    end function check_step_controls

    !> The step-size proposal hnew after an accepted step of size h, for the adaptive
    !! methods' forced steps (controls fac_forced, calm_steps). Call it after a forced step
    !! and while `slow` is set; slow and calm start .false. and 0.
    pure subroutine limit_after_forced(ctl, forced, reject, h, slow, calm, hnew)
        class(step_controls), intent(in) :: ctl  !! the controls
        logical, intent(in)     :: forced        !! the step just taken was forced
        logical, intent(in)     :: reject        !! the attempt before it was rejected
        real(dp), intent(in)    :: h             !! its size [s]
        logical, intent(inout)  :: slow          !! growth limited since the last forced step
        integer, intent(inout)  :: calm          !! unforced steps in a row since then
        real(dp), intent(inout) :: hnew          !! the controller's proposal, limited here [s]
        if (forced) then
            slow = .true.
            calm = 0
        else if (calm < huge(calm)) then
            calm = calm + 1
        end if
        if (.not. slow) return
        if (calm < ctl%calm_steps) then
            hnew = min(abs(hnew), abs(h))
        else if (abs(hnew) > ctl%fac_forced * abs(h)) then
            hnew = ctl%fac_forced * abs(h)
        else if (.not. (forced .or. reject)) then
            slow = .false.
        end if
    end subroutine limit_after_forced

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
                end if
            end do
            if (any(t_out(2:) < t_out(:size(t_out) - 1))) status = SS_BAD_N_OUT
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

    !> Record a fixed step from (t, y) to (t1, y1) on the output: the step itself with
    !! every_step (SS_OUTPUT_FULL when t_out has no room left), else every requested time up to
    !! t1 by linear interpolation (t1 itself exactly). next and t_next advance (t_next: the next
    !! requested time, huge when none is left).
    subroutine linear_output(t, y, t1, y1, every_step, t_out, y_out, next, t_next, status)
        real(dp), intent(in)    :: t            !! start of the step [s]
        real(dp), intent(in)    :: y(:)         !! state at t
        real(dp), intent(in)    :: t1           !! end of the step [s]
        real(dp), intent(in)    :: y1(:)        !! state at t1
        logical, intent(in)     :: every_step   !! record every step instead of t_out
        real(dp), intent(inout) :: t_out(:)     !! output times [s]
        real(dp), intent(inout) :: y_out(:, :)  !! (size(y), size(t_out)) states
        integer, intent(inout)  :: next         !! the next column of y_out to fill
        real(dp), intent(inout) :: t_next       !! the next requested time [s]
        integer, intent(inout)  :: status       !! SS_OUTPUT_FULL set when full
        integer :: m
        m = size(t_out)
        if (every_step) then
            if (next > m) then
                status = SS_OUTPUT_FULL
                return
            end if
            t_out(next) = t1
            y_out(:, next) = y1
            next = next + 1
        else
            do while (t_next <= t1)
                y_out(:, next) = y + (t_next - t) / (t1 - t) * (y1 - y)
                if (t_next == t1) y_out(:, next) = y1
                next = next + 1
                t_next = huge(1.0_dp)
                if (next <= m) t_next = t_out(next)
            end do
        end if
    end subroutine linear_output

    !> Cubic Hermite interpolant through (y0, f0) at t and (y1, f1) at t + hs, at time tq
    !! (the dense output of the fixed-step methods).
    pure function hermite(t, hs, y0, f0, y1, f1, tq) result(yq)
        real(dp), intent(in) :: t           !! start of the step [s]
        real(dp), intent(in) :: hs          !! step size [s]
        real(dp), intent(in) :: y0(:)       !! state at t
        real(dp), intent(in) :: f0(:)       !! f(t, y0)
        real(dp), intent(in) :: y1(:)       !! state at t + hs
        real(dp), intent(in) :: f1(:)       !! f(t + hs, y1)
        real(dp), intent(in) :: tq          !! interpolation time, in [t, t + hs] [s]
        real(dp) :: yq(size(y0)), s, s2, s3
        s = (tq - t) / hs
        s2 = s * s
        s3 = s2 * s
        yq = (2.0_dp*s3 - 3.0_dp*s2 + 1.0_dp) * y0 + (s3 - 2.0_dp*s2 + s) * hs * f0 &
           + (3.0_dp*s2 - 2.0_dp*s3) * y1 + (s3 - s2) * hs * f1
    end function hermite

    !> .true. when every component of y is finite.
    pure logical function all_finite(y)
        real(dp), intent(in) :: y(:)
        !! the array to test
        all_finite = all(ieee_is_finite(y))
    end function all_finite

    !> Set one of the step-control constants of Hairer's explicit codes (DOPRI5, DOP853) by
    !! name; SS_BAD_CONTROL_NAME for any other name (the caller then tries the shared ones).
    function set_erk_constant(name, value, safety, fac1, fac2, beta, nstiff, stop_on_stiff) result(status)
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts and flags as reals)
        real(dp), intent(inout) :: safety       !! safety factor of the step control
        real(dp), intent(inout) :: fac1         !! smallest step ratio h_new/h
        real(dp), intent(inout) :: fac2         !! largest step ratio h_new/h
        real(dp), intent(inout) :: beta         !! Lund stabilisation exponent (control 'beta_pi')
        integer, intent(inout) :: nstiff        !! stiffness test every nstiff accepted steps
        logical, intent(inout) :: stop_on_stiff !! stop with SS_STIFF when the test fires
        integer :: status
        status = SS_OK
        select case (name)
        case ('safety');        safety = value
        case ('fac1');          fac1 = value
        case ('fac2');          fac2 = value
        case ('beta_pi');       beta = value
        case ('nstiff')
            if (value >= 1.0_dp .and. value <= real(huge(1), dp)) then
                nstiff = int(value)
            else
                status = SS_BAD_CONTROL
            end if
        case ('stop_on_stiff'); stop_on_stiff = value /= 0.0_dp
        case default;           status = SS_BAD_CONTROL_NAME
        end select
    end function set_erk_constant

    !> Check the step-control constants of Hairer's explicit codes: 0 < safety < 1,
    !! 0 < fac1 <= 1 <= fac2 (finite), 0 <= beta <= 0.2, nstiff >= 1; SS_OK or SS_BAD_CONTROL.
    pure function check_erk_constants(safety, fac1, fac2, beta, nstiff) result(status)
        real(dp), intent(in) :: safety      !! safety factor of the step control
        real(dp), intent(in) :: fac1        !! smallest step ratio h_new/h
        real(dp), intent(in) :: fac2        !! largest step ratio h_new/h
        real(dp), intent(in) :: beta        !! Lund stabilisation exponent
        integer, intent(in)  :: nstiff      !! stiffness test every nstiff accepted steps
        integer :: status
        status = SS_OK
        if (.not. (safety > 0.0_dp .and. safety < 1.0_dp) .or. &
            .not. (fac1 > 0.0_dp .and. fac1 <= 1.0_dp) .or. &
            .not. (fac2 >= 1.0_dp .and. ieee_is_finite(fac2)) .or. &
            .not. (beta >= 0.0_dp .and. beta <= 0.2_dp) .or. nstiff < 1) then
            status = SS_BAD_CONTROL
        end if
    end function check_erk_constants

end module stickslip_ode
