!> Event-driven integration of a system with set-valued friction (`stickslip_contact`): the
!! exact reference. Each mode (every contact either stuck or slipping in a known direction)
!! is a smooth ODE integrated by DOPRI5 (`stickslip_dopri5`, unchanged); the transitions
!! are located by root-finding and the mode is switched there.
!!
!! In a mode, slipping contacts carry r_i = -sigma_i N_i mu_i(sigma_i w_i) (sigma_i = +-1 the
!! slip direction) and stuck contacts the holding forces that keep their relative
!! acceleration at zero: H_S M^-1 (f + H^T r) + db_S/dt = 0, a linear system of the size of
!! the stuck set. It is solved by `psd_solve`: LU where it is regular, and where it is
!! singular (redundant contacts: a body on two feet) the weighted minimum-norm forces, which
!! load each stuck contact in proportion to its capacity mu_s N (contacts on identical rows of
!! H reach their limits together). When the mass matrix is diagonal and each contact acts on
!! a coordinate of its own, the Delassus matrix is diagonal and the forces come from its
!! diagonal in O(n). A stuck contact's velocity is set to w = 0 when it sticks (exactly for
!! a contact with one entry in its row of H) and then stays there to rounding.
!!
!! Event functions: sigma_i w_i for a slipping contact (slip -> stick when it reaches 0) and
!! mu_s N_i (1 + 2 STICK_RTOL) - |r_i| for a stuck one (stick -> slip when the holding force
!! exceeds the static limit; |r| = mu_s N exactly is stuck, as in moreau, and the margin
!! 2 STICK_RTOL keeps rounding from undoing the release at the located instant). They are
!! evaluated at the end of every accepted step from DOPRI5's own last evaluation there (its
!! FSAL stage: `ode_system%step_accepted`, no evaluation of their own), and DOPRI5 stops
!! after the first step in which one crosses or may dip to 0, so no step past an event is
!! integrated and thrown away. Where one has crossed, the crossing time is found by
!! bracketing (Illinois regula falsi with bisection) to within 4 units of round-off in t. A
!! slipping contact whose w turns back within a step (its rate sigma dw/dt changes sign from
!! - to + and the cubic Hermite interpolant of sigma w dips below half its end values) is
!! searched for its minimum (`dips`, then `graze`; DOPRI5 starts the mode again after that
!! step where it does not touch): a grazing touch of w = 0 inside one step is found, and a
!! minimum within the integration's tolerance of 0 (atol + rtol |u| over the contact's row
!! of H) counts as touching. The
!! state at a trial time t comes from the step's continuous extension (DOPRI5's dense output
!! of order 4, kept for every step of the mode's run: `dopri5_options%dense_rows`), so a
!! trial costs one force evaluation, not a DOPRI5 run.
!!
!! At an event the modes are decided together: every stuck contact and every contact that
!! has reached w = 0 is a candidate, and the problem at rest (their relative accelerations
!! a_C = af_C + H_C M^-1 H_C^T r_C, with slip at mu(0+) N, the other contacts' slip forces
!! fixed) is solved by `stickslip_contact_solver` (its one rule where several modes are
!! consistent, as for moreau's steps; the contacts one by one when the Delassus matrix is
!! diagonal). A decision where another solution existed is counted once in stats%nonunique:
!! (a) the solver's test finds another mode set with as many stuck contacts, or (b) a stuck
!! contact let go because the mode's minimum-norm forces exceed its limit, in a stuck set with
!! a singular Delassus block, that the solver's answer held by other forces within every limit
!! (`held_otherwise`) or that another mode set with as many stuck contacts holds (`loop_tie`,
!! by the solver's test `other_solution_exists`), or (c) the mode decided is consistent to
!! first order only (a contact that starts to slip with zero relative acceleration: mu_s =
!! mu(0+) at its limit) where a mode with a stuck contact coupled to it slipping too is
!! consistent strictly (`first_order_tie`, by the solver's `first_order_alternative`): which
!! continuation is right depends on higher derivatives. Where a
!! slipping contact reaches w = 0, every other slipping contact at w = 0 to the integration's
!! tolerance there (bodies that stop together) is decided with it. Where the stuck contacts
!! form a closed loop (their holding forces are not unique), the solver's answer may hold
!! them by a distribution other than the mode's weighted minimum-norm forces: a contact
!! that these exceed slips against its holding force and the others are decided again, so
!! that the decision and the mode's break-away test use the same forces. A contact not stuck
!! whose row of H is a combination of the stuck ones' rows (`locked_contacts`) keeps w = 0
!! while they hold: it carries its slip force and has no event of its own (rounding of its
!! w would otherwise reverse it at every step). Every change of mode is an event, recorded as
!! (t [s], kind: 1 slip -> stick, 2 stick -> slip, 3 reversal (reached w = 0 and slips
!! back), the contact's slip displacement H_i q [m], contact index). A contact that touches
!! w = 0 and slips on in the same direction changes no mode and records nothing. The
!! initial mode (contacts with w = 0 at t0 decided the same way) is not an event.
!!
!! Corners of the forces in time (`contact_system%next_time_event`: a model's signal steps,
!! ramp ends and table points) end a mode's integration exactly there: a stuck contact whose
!! w jumped away from 0 (its surface's speed stepped) slips in the direction of w, and every
!! stuck contact and every contact at w = 0 is decided afresh (a normal force that stepped
!! down releases what it can no longer hold). An open contact (N = 0: a disengaged clutch)
!! has no events while it is open; its slip direction is taken from its w at the corner where
!! it closes. A normal force that crosses 0 between corners (a table or ramp through 0, a
!! sine) is an event too: each step's end compares every contact's N > 0 with its state where
!! the mode's run started (`closed`), and the crossing is located by bisection on the step's
!! continuous extension to 4 units of round-off in t (`locate_normal`). There a contact that
!! closes slips the way it moves (at w = 0 to the integration's tolerance, `w_tolerance`: a
!! body held by other contacts, it is decided with the others), and every stuck
!! contact is decided afresh. While a contact is open, the steps are kept to 1/16 of the
!! forces' shortest period as for a stuck one (its normal force does not limit them).
!!
!! Where forces vary smoothly in time (a sine, `contact_system%time_scale`), a mode with a
!! stuck contact keeps its steps to 1/16 of their shortest period: while a body is stuck its
!! state does not move, DOPRI5's error estimate is zero and its steps would otherwise grow
!! past a whole period, over a breakaway that the check at the step's end no longer sees. (A
!! holding force that exceeds the limit only within one such step, by less than about 2 % of
!! the sine's amplitude, can still pass unseen.)
!!
!! Output on the grid: the same continuous extension of the mode's steps up to the event
!! (a grid time on a step's end takes the step's state).
!! Counters: nstep/naccept/nreject of the mode integration; nfev counts every evaluation
!! (the event checks and the root-finding's included); nevents the transitions.
!!
!! Ends: SS_EVENT_BUDGET after more than max_events events; SS_EVENT_ZENO when events
!! accumulate: 10 instants with events in a row closer than zeno_gap (events at one instant
!! count once: a row of identical blocks switching together is not Zeno), or more than
!! 4 n_c + 8 events at one instant, or more than 4 n_c + 8 switches of mode in a row each within
!! zeno_gap of the last (changing a mode or not: nothing turns at one instant for ever);
!! SS_CONTACT_FAILED when an event's problem has no solution, or a stuck set's holding forces
!! have none (contact_worst names the contact); SS_STEP_BUDGET and SS_INTERRUPTED (the stop
!! flag), looked at before every mode's run as well as in DOPRI5's. A failed run keeps its
!! output rows and t_reached up to the last step it trusts.
module stickslip_event_driven
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_DIM, SS_OUTPUT_FULL, SS_STEP_BUDGET, SS_EVENT_ZENO, &
                               SS_BAD_EVENT_CTL, SS_BAD_MAX_STEPS, SS_EVENT_BUDGET, &
                               SS_CONTACT_FAILED, SS_INTERRUPTED
    use stickslip_ode, only: ode_system, ode_stats, step_controls, method_info, check_problem, &
                             check_tolerances, output_start
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate, dopri5_dense, DOPRI5_DENSE_ROWS
    use stickslip_contact, only: contact_system
    use stickslip_linalg, only: psd_solve, psd_factors, psd_factor
    use stickslip_contact_solver, only: solve_contacts, contact_solve_info, STICK_RTOL, MODE_STICK, MODE_OPEN, &
                                        other_solution_exists, first_order_alternative
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use stickslip_ode, only: diverged, stop_requested, count_nonunique
    implicit none
    private

    public :: event_driven_options, event_driven_integrate

    integer, parameter, public :: EVENT_STICK = 1      !! slip -> stick
    integer, parameter, public :: EVENT_SLIP = 2       !! stick -> slip
    integer, parameter, public :: EVENT_REVERSAL = 3   !! w reached 0 and the contact could not be held

    !> What the event-driven method is and which controls it reads (registry entry).
    type(method_info), parameter, public :: EVENT_DRIVEN_INFO = method_info(name='event_driven', order=5, &
        adaptive=.true., implicit=.false., controls='rtol atol max_steps max_events zeno_gap', &
        doc='event-driven stick/slip switching, DOPRI5 in each mode', laws='coulomb stribeck karnopp')

    !> Controls of the event-driven method.
    type, extends(step_controls) :: event_driven_options
        integer  :: max_events = 10000      !! most events a run may have, >= 1
        real(dp) :: zeno_gap = 1.0e-10_dp   !! 10 events in a row closer than this: accumulation [s]
    contains
        procedure :: set => set_event_option
        !! set a control by name (max_steps and the method's own)
    end type event_driven_options

    !> One mode of a contact system as an ODE y = (q, u), y' = (u, M^-1 (f + H^T r)).
    type, extends(ode_system) :: mode_system
        class(contact_system), allocatable :: cs   !! the system
        logical, allocatable :: stuck(:)           !! (n_c) contact i is stuck
        real(dp), allocatable :: sig(:)            !! (n_c) slip direction of a slipping contact, +-1
        integer :: nfev = 0                        !! evaluations outside DOPRI5 (event checks)
        logical :: singular = .false.              !! the stuck set's matrix was singular
        !> H M^-1 H^T is diagonal (diagonal_delassus over every contact): the holding forces of
        !! any stuck set come from its diagonal
        logical :: diagonal = .false.
        !> The time functions (forces, normal forces, offsets) are read at min(t, t_cap): just
        !! below a corner that ends the current stretch, so that the stretch sees their left
        !! limits up to its end [s]
        real(dp) :: t_cap = huge(1.0_dp)
        !> The stuck set of `idx` (`stuck_set`); where W at a = b = 0 is constant
        !! (`w_constant`), the set's Delassus block (`amat` and its factors `fac`, or its
        !! diagonal `dgl`) too: formed once a set, not at every right-hand side
        logical, allocatable :: cached(:)
        integer, allocatable :: idx(:)             !! the stuck contacts
        real(dp), allocatable :: amat(:, :)        !! their Delassus block [1/kg]
        real(dp), allocatable :: dgl(:)            !! its diagonal, where it is diagonal [1/kg]
        type(psd_factors) :: fac                   !! amat's LU
        !> Work arrays of mode_forces (n_dof: wf, wg; n_c: the others; rhs2: (n_c, 1)) and of
        !! mode_rhs (wr, n_c), allocated with the mode (no allocation at an evaluation)
        real(dp), allocatable :: wf(:), wg(:), wn(:), ww(:), wb(:), wh(:), wc(:), wcap(:), rhs2(:, :), wr(:)
        !> The event functions and their rates (`event_values`) at the last two step ends
        !! (ga, dga: the one before; gb, dgb: the last), kept by `mode_step_accepted`
        real(dp), allocatable :: ga(:), dga(:), gb(:), dgb(:)
        logical :: halted = .false.   !! mode_step_accepted ended DOPRI5's run after its last step
        !> (n_c) contact i carried a normal force (N_i > 0) where the mode's run started
        logical, allocatable :: closed(:)
        !> (n_c) its normal force has crossed 0 since (`closed` differs at the last step's end)
        logical, allocatable :: flip(:)
        integer :: singular_contact = 0   !! a contact of the stuck set found singular
        !> (n_c) a contact not stuck whose row of H is a combination of the stuck contacts'
        !! rows (a closed loop of contacts): its w stays 0 while they hold (`stuck_set`)
        logical, allocatable :: locked(:)
        real(dp) :: t_prev = 0.0_dp   !! the time of ga, dga [s]
    contains
        procedure :: rhs => mode_rhs
        !! (u, acceleration) in the current mode
        procedure :: step_accepted => mode_step_accepted
        !! the event functions at each step's end, from DOPRI5's last evaluation there
    end type mode_system

    integer, parameter :: ZENO_ROW = 10
    !> Least steps per period of the forces' fastest sine of a mode with a stuck contact
    real(dp), parameter :: STEPS_PER_PERIOD = 16.0_dp
    !> Rows of a mode's run kept at a time (DOPRI5 ends with SS_OUTPUT_FULL when they are full)
    integer, parameter :: CHUNK = 512

    !> One run of `event_driven_integrate`: the mode, the controls, the counters and the
    !! variables its procedures share (the mode's steps, the step being searched, the event
    !! bookkeeping). The run's procedures take it as their first argument.
    type :: ed_run
        type(mode_system) :: ms                    !! the current mode
        type(dopri5_options) :: d5                 !! DOPRI5's controls of a mode's run
        type(event_driven_options) :: opts         !! the run's controls
        type(ode_stats) :: stats                   !! counters and status
        real(dp), allocatable :: rtol(:), atol(:)  !! tolerances, size 1 or 2 n_dof
        real(dp), allocatable :: tb(:)             !! the times of the mode's steps [s]
        real(dp), allocatable :: yb(:, :)          !! (n, CHUNK) the states there
        real(dp), allocatable :: cb(:, :)          !! their continuous extensions (DOPRI5's dense rows)
        real(dp), allocatable :: y(:)              !! the state (q, u) at t
        real(dp), allocatable :: ya(:), ystar(:)   !! the states at ta and tstar
        real(dp), allocatable :: r(:)              !! contact forces at a mode's start [N]
        real(dp), allocatable :: ev(:, :)          !! (4, grown as needed) the events recorded
        integer :: room = 0                        !! columns of the caller's events array
        logical, allocatable :: cand_now(:)        !! the contacts being decided (`decide`)
        logical, allocatable :: touch(:)           !! contacts whose w came within tolerance of 0 at t_touch
        real(dp), allocatable :: p_dec(:)          !! (n_c) the contact solver's forces at the last decision [N]
        !> the decision under way had another solution (`decide`: counted once in stats%nonunique)
        logical :: tie = .false.
        real(dp) :: t = 0.0_dp                     !! time [s]
        real(dp) :: ta = 0.0_dp                    !! the start of the step being searched [s]
        real(dp) :: tstar = 0.0_dp                 !! the earliest crossing found in it so far [s]
        real(dp) :: h_carry = 0.0_dp               !! DOPRI5's first step of the next mode's run [s]
        real(dp) :: t_last_event = 0.0_dp          !! time of the last event [s]
        real(dp) :: t_touch = 0.0_dp               !! time where `touch` holds [s]
        real(dp) :: t_seg = 0.0_dp                 !! the end of the mode's run (a corner or t_end) [s]
        integer :: nd = 0                          !! degrees of freedom
        integer :: nc = 0                          !! contacts
        integer :: n = 0                           !! states, 2 nd
        integer :: next = 1                        !! the next output row
        integer :: k = 0                           !! the step being searched (of tb)
        integer :: nrows = 0                       !! steps of the mode's run in tb
        integer :: zeno_run = 0                    !! instants with events in a row closer than zeno_gap
        integer :: ievent = 0                      !! events so far
        integer :: same_instant = 0                !! events at the current instant
        real(dp) :: t_last_switch = 0.0_dp         !! time of the last switch of mode (`switch_mode`) [s]
        integer :: close_switches = 0              !! switches in a row closer than zeno_gap
    end type ed_run

contains

    function set_event_option(self, name, value) result(status)
        class(event_driven_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts as reals)
        integer :: status
        status = SS_OK
        select case (name)
        case ('max_events')
            if (value >= 1.0_dp .and. value <= real(huge(1), dp) .and. value == aint(value)) then
                self%max_events = int(value)
            else
                status = SS_BAD_EVENT_CTL
            end if
        case ('zeno_gap'); self%zeno_gap = value
        case default;      status = self%step_controls%set(name, value)
        end select
    end function set_event_option

    !> Acceleration a and contact forces r [N] of the mode at (t, y); the system's time
    !! functions are read at min(t, t_cap) (the left limit at a corner that ends the mode).
    subroutine mode_forces(self, t_in, y, a, r)
        class(mode_system), intent(inout) :: self
        real(dp), intent(in)  :: t_in       !! time [s]
        real(dp), intent(in)  :: y(:)       !! (q, u)
        real(dp), intent(out) :: a(:)       !! acceleration u' [m/s^2]
        real(dp), intent(out) :: r(:)       !! contact forces [N]
        integer :: nd, nc, i, j, ns
        logical :: ok
        real(dp) :: t
        t = min(t_in, self%t_cap)
        nd = self%cs%n_dof
        nc = self%cs%n_c
        associate (cs => self%cs, f => self%wf, g => self%wg, nn => self%wn, w => self%ww, bd => self%wb, &
                   ha => self%wh, col => self%wc, cap => self%wcap, rs => self%rhs2)
            call cs%force(t, y(:nd), y(nd + 1:), f)
            call cs%normal_forces(t, y(:nd), nn)
            call cs%relative_velocities(t, y(nd + 1:), w)
            r = 0.0_dp
            do i = 1, nc
                if (.not. self%stuck(i)) r(i) = -self%sig(i) * nn(i) * cs%laws(i)%slip_mu(max(self%sig(i) * w(i), 0.0_dp))
            end do
            a = f
            call cs%add_ht(r, a)
            call cs%solve_w(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, a)
            if (.not. any(self%stuck)) then
                self%locked = .false.
                return
            end if
            call stuck_set(self, t, y)
            ns = size(self%idx)
            call cs%apply_h(a, ha)
            call cs%offset_rate(t, bd)
            do j = 1, ns
                i = self%idx(j)
                rs(j, 1) = -(ha(i) + bd(i))
                cap(j) = max(cs%laws(i)%mu_s * nn(i), tiny(1.0_dp))
            end do
            call holding_forces(self, cap(:ns), rs(:ns, :), ok)
            if (.not. ok) then
                if (.not. self%singular) self%singular_contact = self%idx(1)
                self%singular = .true.
                return
            end if
            col = 0.0_dp
            do j = 1, ns
                col(self%idx(j)) = rs(j, 1)
                r(self%idx(j)) = rs(j, 1)
            end do
            g = 0.0_dp
            call cs%add_ht(col, g)
            call cs%solve_w(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, g)
            a = a + g
        end associate
    end subroutine mode_forces

    !> self%idx := the stuck contacts and the set's Delassus block (its diagonal `dgl` where
    !! it is diagonal, otherwise `amat` and its LU `fac`) at (t, y). Where W at a = b = 0 is
    !! constant (`w_constant`) both are formed again only when the stuck set changes.
    subroutine stuck_set(self, t, y)
        class(mode_system), intent(inout) :: self
        real(dp), intent(in) :: t           !! time [s]
        real(dp), intent(in) :: y(:)        !! (q, u)
        integer :: i, ns
        logical :: same
        same = .false.
        if (allocated(self%cached)) same = all(self%cached .eqv. self%stuck)
        if (same .and. self%cs%w_constant) return
        if (.not. same) then
            self%cached = self%stuck
            self%idx = pack([(i, i = 1, self%cs%n_c)], self%stuck)
        end if
        ns = size(self%idx)
        if (self%diagonal) then
            if (allocated(self%dgl)) deallocate(self%dgl)
            allocate(self%dgl(ns))
            call delassus_diagonal(self, t, y, self%idx, self%dgl)
        else
            if (allocated(self%amat)) deallocate(self%amat)
            allocate(self%amat(ns, ns))
            call delassus_block(self, t, y, self%idx, self%amat)
            call psd_factor(self%amat, self%fac)
            if (.not. same) call locked_contacts(self, t, y)
        end if
    end subroutine stuck_set

    !> self%locked: each contact i not stuck whose row of H lies in the span of the stuck
    !! contacts' rows, D_ii - D_iS D_SS^+ D_Si = 0 (to 1e-10 D_ii) with D = H M^-1 H^T at
    !! (t, y) and the stuck set's block formed (`stuck_set`). Its w cannot leave 0 (nor
    !! reach it) while the stuck set holds: a slipping contact there carries its slip force
    !! at w = 0 and has no event of its own (rounding of w would make one at every step).
    subroutine locked_contacts(self, t, y)
        class(mode_system), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp) :: dall(self%cs%n_c, self%cs%n_c), x(size(self%idx), 1)
        integer :: i, nd, ns_i
        logical :: ok
        nd = self%cs%n_dof
        call self%cs%delassus(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, dall)
        self%locked = .false.
        do i = 1, self%cs%n_c
            if (self%stuck(i)) cycle
            x(:, 1) = dall(self%idx, i)
            call psd_solve(self%amat, x, [(1.0_dp, ns_i = 1, size(self%idx))], ok, self%fac)
            if (.not. ok) cycle
            self%locked(i) = dall(i, i) - dot_product(dall(self%idx, i), x(:, 1)) <= 1.0e-10_dp * dall(i, i)
        end do
    end subroutine locked_contacts

    !> x := the forces r_S of the stuck contacts (self%idx) that give them the relative
    !! accelerations H_S M^-1 H_S^T r_S = x, with the block `stuck_set` formed: from its
    !! diagonal when it is diagonal (O(n)), otherwise by `psd_solve`, whose weighted
    !! minimum-norm solution shares a redundant stuck set's load in proportion to the
    !! capacities cap (mu_s N). ok = .false. when no forces give x (inconsistent, or not
    !! finite).
    subroutine holding_forces(self, cap, x, ok)
        class(mode_system), intent(in) :: self
        real(dp), intent(in)    :: cap(:)      !! the capacities mu_s N, at least tiny [N]
        real(dp), intent(inout) :: x(:, :)     !! (n_s, 1) relative accelerations in, forces out
        logical, intent(out)    :: ok
        if (self%diagonal) then
            ok = all(self%dgl /= 0.0_dp)
            if (ok) x(:, 1) = x(:, 1) / self%dgl
        else
            call psd_solve(self%amat, x, cap, ok, self%fac)
        end if
    end subroutine holding_forces

    !> The diagonal of the Delassus matrix [1/kg] at the contacts idx when it is diagonal: one
    !! solve with H^T 1_S (the contacts' columns do not mix).
    subroutine delassus_diagonal(self, t, y, idx, dg)
        class(mode_system), intent(in) :: self
        real(dp), intent(in)  :: t, y(:)
        integer, intent(in)   :: idx(:)
        real(dp), intent(out) :: dg(:)
        real(dp) :: col(self%cs%n_c), g(self%cs%n_dof)
        integer :: nd
        nd = self%cs%n_dof
        col = 0.0_dp
        col(idx) = 1.0_dp
        g = 0.0_dp
        call self%cs%add_ht(col, g)
        call self%cs%solve_w(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, g)
        call self%cs%apply_h(g, col)
        dg = col(idx)
    end subroutine delassus_diagonal

    !> The Delassus block H_S M^-1 H_S^T [1/kg] of the contacts idx at (t, y): n_s columns,
    !! each a solve with M.
    subroutine delassus_block(self, t, y, idx, amat)
        class(mode_system), intent(in) :: self
        real(dp), intent(in)  :: t, y(:)
        integer, intent(in)   :: idx(:)
        real(dp), intent(out) :: amat(:, :)
        real(dp) :: col(self%cs%n_c), g(self%cs%n_dof)
        integer :: j, nd
        nd = self%cs%n_dof
        do j = 1, size(idx)
            col = 0.0_dp
            col(idx(j)) = 1.0_dp
            g = 0.0_dp
            call self%cs%add_ht(col, g)
            call self%cs%solve_w(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, g)
            call self%cs%apply_h(g, col)
            amat(:, j) = col(idx)
        end do
    end subroutine delassus_block

    !> .true. when H M^-1 H^T is diagonal: the system's mass matrix is diagonal (w_tridiagonal
    !! with a = b = 0 has no off-diagonal), and each contact has one entry of H, on a coordinate
    !! of its own. Then so is its restriction to any stuck set.
    function diagonal_delassus(cs) result(diag)
        class(contact_system), intent(in) :: cs
        logical :: diag
        real(dp) :: wl(cs%n_dof), wd(cs%n_dof), wr(cs%n_dof)
        logical :: taken(cs%n_dof)
        integer :: i, k
        call cs%w_tridiagonal(0.0_dp, 0.0_dp, wl, wd, wr, diag)
        if (.not. diag) return
        diag = all(wl(2:) == 0.0_dp) .and. all(wr(:cs%n_dof - 1) == 0.0_dp)
        taken = .false.
        do i = 1, cs%n_c
            if (.not. diag) return
            k = cs%h_ptr(i)
            diag = cs%h_ptr(i + 1) - k == 1
            if (diag) diag = .not. taken(cs%h_col(k))
            if (diag) taken(cs%h_col(k)) = .true.
        end do
    end function diagonal_delassus

    subroutine mode_rhs(self, t, y, dydt)
        class(mode_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (q, u)
        real(dp), intent(out) :: dydt(:)    !! (u, acceleration)
        integer :: nd
        nd = self%cs%n_dof
        dydt(:nd) = y(nd + 1:)
        call mode_forces(self, t, y, dydt(nd + 1:), self%wr)
    end subroutine mode_rhs

    !> The event functions of the mode at (t, y): sigma_i w_i (slipping) and
    !! mu_s N_i (1 + 2 STICK_RTOL) - |r_i| (stuck); their rates dg (slipping contacts:
    !! sigma_i dw_i/dt [m/s^2]; 0 for stuck ones); r returns the contact forces [N].
    subroutine event_values(ms, t_in, y, gv, r, dg)
        class(mode_system), intent(inout) :: ms
        real(dp), intent(in)  :: t_in, y(:)
        real(dp), intent(out) :: gv(:), r(:), dg(:)
        real(dp) :: a(ms%cs%n_dof)
        call mode_forces(ms, t_in, y, a, r)
        ms%nfev = ms%nfev + 1
        call values_from_forces(ms, min(t_in, ms%t_cap), a, r, gv, dg)
    end subroutine event_values

    !> The event functions gv and their rates dg (as `event_values`) from an evaluation of
    !! `mode_forces` at time t just made: its acceleration a and contact forces r, and the
    !! normal forces and relative velocities it left in wn and ww.
    subroutine values_from_forces(ms, t, a, r, gv, dg)
        class(mode_system), intent(inout) :: ms
        real(dp), intent(in)  :: t          !! time, at most t_cap [s]
        real(dp), intent(in)  :: a(:)       !! acceleration [m/s^2]
        real(dp), intent(in)  :: r(:)       !! contact forces [N]
        real(dp), intent(out) :: gv(:)      !! event functions
        real(dp), intent(out) :: dg(:)      !! their rates (slipping contacts) [m/s^2]
        call ms%cs%apply_h(a, dg)
        call ms%cs%offset_rate(t, ms%wb)
        where (ms%stuck)
            gv = ms%cs%laws%mu_s * ms%wn * (1.0_dp + 2.0_dp * STICK_RTOL) - abs(r)
            dg = 0.0_dp
        elsewhere (ms%wn > 0.0_dp .and. .not. ms%locked)
            gv = ms%sig * ms%ww
            dg = ms%sig * (dg + ms%wb)
        elsewhere     ! an open contact (N = 0) carries no force: no event until it closes
            gv = 1.0_dp
            dg = 0.0_dp
        end where
    end subroutine values_from_forces

    !> After each accepted DOPRI5 step: the event functions at its end from DOPRI5's last
    !! evaluation there (the FSAL stage at (t, y), which left its forces in wr, wn, ww; no
    !! evaluation of its own), the previous end's moved to ga, dga. DOPRI5 halts after a step
    !! in which an event function crossed (`crossed`) or a slipping contact's may dip to 0
    !! (`dips`), or when the stuck set was singular: event_driven_integrate takes it from there.
    subroutine mode_step_accepted(self, t, h, y, dydt, halt)
        class(mode_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! the step's end [s]
        real(dp), intent(in)  :: h          !! the step's length [s]
        real(dp), intent(in)  :: y(:)       !! (q, u) at t
        real(dp), intent(in)  :: dydt(:)    !! (u, acceleration) at t
        logical, intent(out)  :: halt       !! .true.: an event (or a dip) in the step
        integer :: nd
        real(dp) :: step
        nd = self%cs%n_dof
        self%ga = self%gb
        self%dga = self%dgb
        call values_from_forces(self, min(t, self%t_cap), dydt(nd + 1:), self%wr, self%gb, self%dgb)
        step = t - self%t_prev      ! as event_driven_integrate's scan takes it (not h: rounding)
        self%t_prev = t
        self%flip = (self%wn > 0.0_dp) .neqv. self%closed
        halt = self%singular .or. any(crossed(self%stuck, self%gb)) .or. any(self%flip) .or. &
               any(dips(self%stuck, self%ga, self%gb, step * self%dga, step * self%dgb))
        self%halted = halt
    end subroutine mode_step_accepted

    !> Has contact i's event function crossed? A slipping contact when sigma w <= 0 (it
    !! reached w = 0), a stuck one when its holding force exceeds the static limit (g < 0).
    elemental logical function crossed(stuck, g)
        logical, intent(in) :: stuck
        real(dp), intent(in) :: g
        if (stuck) then
            crossed = g < 0.0_dp
        else
            crossed = g <= 0.0_dp
        end if
    end function crossed

    !> May a slipping contact's event function sigma w, positive at both ends of a step
    !! (ga, gb) with slopes in the step's fraction sa, sb (its rate times the step), dip to 0
    !! inside it? When it falls at the start, rises at the end and its cubic Hermite
    !! interpolant's minimum is below half the smaller end value (`graze` then searches it).
    elemental logical function dips(stuck, ga, gb, sa, sb)
        logical, intent(in) :: stuck
        real(dp), intent(in) :: ga, gb, sa, sb
        dips = .not. stuck .and. .not. crossed(stuck, gb)
        if (dips) dips = ga > 0.0_dp .and. sa < 0.0_dp .and. sb > 0.0_dp
        if (dips) dips = .not. (hermite_min(ga, gb, sa, sb) >= 0.5_dp * min(ga, gb))
    end function dips

    !> The minimum over theta in [0, 1] of the cubic Hermite interpolant of g with values
    !! ga, gb and slopes (in theta) sa, sb at the ends: at the ends or where its derivative,
    !! a quadratic, vanishes.
    pure real(dp) function hermite_min(ga, gb, sa, sb) result(gmin)
        real(dp), intent(in) :: ga, gb, sa, sb
        real(dp) :: c1, c2, c3, disc, th(2)
        integer :: k
        ! g(th) = ga + sa th + c2 th^2 + c3 th^3
        c3 = 2.0_dp * (ga - gb) + sa + sb
        c2 = 3.0_dp * (gb - ga) - 2.0_dp * sa - sb
        c1 = sa
        gmin = min(ga, gb)
        ! g'(th) = c1 + 2 c2 th + 3 c3 th^2 = 0
        if (c3 == 0.0_dp) then
            if (c2 == 0.0_dp) return
            th = -c1 / (2.0_dp * c2)
        else
            disc = c2**2 - 3.0_dp * c3 * c1
            if (disc < 0.0_dp) return
            th(1) = (-c2 + sqrt(disc)) / (3.0_dp * c3)
            th(2) = (-c2 - sqrt(disc)) / (3.0_dp * c3)
        end if
        do k = 1, 2
            if (th(k) > 0.0_dp .and. th(k) < 1.0_dp) &
                gmin = min(gmin, ga + th(k) * (c1 + th(k) * (c2 + th(k) * c3)))
        end do
    end function hermite_min

    !> Integrate with stick/slip switching from t0 to t_end. y0 = (q0, u0), size 2 n_dof.
    !! events(:, k) = (t [s], kind, position [m], contact) of the k-th event, for as many as
    !! there are columns. Status: SS_OK, SS_EVENT_ZENO, SS_EVENT_BUDGET, SS_STEP_BUDGET,
    !! SS_INTERRUPTED, SS_CONTACT_FAILED, DOPRI5's run-time codes, or a bad-input code.
    subroutine event_driven_integrate(cs, t0, y0, t_end, rtol, atol, opts, t_out, y_out, stats, events)
        class(contact_system), intent(in) :: cs   !! the system
        real(dp), intent(in)    :: t0            !! initial time [s]
        real(dp), intent(in)    :: y0(:)         !! initial state (q0, u0)
        real(dp), intent(in)    :: t_end         !! final time, > t0 [s]
        real(dp), intent(in)    :: rtol(:)       !! relative tolerances, size 1 or size(y0)
        real(dp), intent(in)    :: atol(:)       !! absolute tolerances, size 1 or size(y0)
        type(event_driven_options), intent(in) :: opts  !! controls
        real(dp), intent(inout) :: t_out(:)      !! requested output times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! (size(y0), size(t_out)) states
        type(ode_stats), intent(out) :: stats    !! counters and status
        real(dp), intent(inout) :: events(:, :)  !! (4, room) events (t, kind, position, contact)
        type(ed_run), target :: s
        integer :: nw

        stats%status = check_problem(t0, y0, t_end, t_out, y_out, .false.)
        if (stats%status == SS_OK) stats%status = check_tolerances(size(y0), rtol, atol)
        if (stats%status /= SS_OK) return
        if (size(y0) /= 2 * cs%n_dof .or. size(events, 1) /= 4) then
            stats%status = SS_BAD_DIM
        else if (.not. (ieee_is_finite(opts%zeno_gap) .and. opts%zeno_gap >= 0.0_dp) .or. opts%max_events < 1) then
            stats%status = SS_BAD_EVENT_CTL
        else if (opts%max_steps < 1) then
            stats%status = SS_BAD_MAX_STEPS
        end if
        if (stats%status /= SS_OK) return

        call run_start(s, cs, t0, y0, rtol, atol, opts, size(events, 2))
        s%d5%dense_rows => s%cb
        call output_start(t0, y0, t_out, y_out, .false., s%next)
        call initial_mode(s)
        do
            if (s%stats%status /= SS_OK) exit
            if (.not. run_mode(s, t_end, t_out, y_out)) exit
        end do

        stats = s%stats
        stats%nfev = stats%nfev + s%ms%nfev
        stats%t_reached = s%t
        stats%n_written = s%next - 1
        nw = min(s%ievent, s%room)
        if (nw > 0) events(:, :nw) = s%ev(:, :nw)
    end subroutine event_driven_integrate

    !> The run's state at t0: the mode system (a copy of cs, its work arrays), the step
    !! buffers, DOPRI5's controls (every step, dense rows, step notification, the stop flag);
    !! every contact slipping forward until `initial_mode` decides.
    subroutine run_start(s, cs, t0, y0, rtol, atol, opts, room)
        type(ed_run), intent(inout) :: s
        class(contact_system), intent(in) :: cs   !! the system
        real(dp), intent(in) :: t0               !! initial time [s]
        real(dp), intent(in) :: y0(:)            !! initial state (q0, u0)
        real(dp), intent(in) :: rtol(:), atol(:) !! tolerances
        type(event_driven_options), intent(in) :: opts  !! controls
        integer, intent(in) :: room              !! columns of the caller's events array
        integer :: nd, nc, n
        nd = cs%n_dof
        nc = cs%n_c
        n = 2 * nd
        s%nd = nd
        s%nc = nc
        s%n = n
        s%opts = opts
        s%rtol = rtol
        s%atol = atol
        s%room = room
        allocate(s%ev(4, min(room, 64)))
        allocate(s%ms%cs, source=cs)
        s%ms%diagonal = diagonal_delassus(cs)
        allocate(s%ms%wf(nd), s%ms%wg(nd), s%ms%wn(nc), s%ms%ww(nc), s%ms%wb(nc), s%ms%wh(nc), s%ms%wc(nc), &
                 s%ms%wcap(nc), s%ms%rhs2(nc, 1), s%ms%wr(nc))
        allocate(s%ms%stuck(nc), s%ms%sig(nc), s%r(nc))
        allocate(s%ms%ga(nc), s%ms%dga(nc), s%ms%gb(nc), s%ms%dgb(nc))
        allocate(s%ms%closed(nc), s%ms%flip(nc), s%ms%locked(nc), source=.false.)
        allocate(s%cand_now(nc), s%touch(nc), source=.false.)
        allocate(s%p_dec(nc), source=0.0_dp)
        s%t_touch = -huge(1.0_dp)
        allocate(s%tb(CHUNK), s%yb(n, CHUNK), s%y(n), s%ya(n), s%ystar(n), s%cb(DOPRI5_DENSE_ROWS * n + 1, CHUNK))
        s%d5%every_step = .true.
        s%d5%notify_steps = .true.
        s%d5%stop_flag => opts%stop_flag
        s%t = t0
        s%y = y0
        s%ms%stuck = .false.
        s%ms%sig = 1.0_dp
        s%h_carry = 0.0_dp
        s%t_last_event = -huge(1.0_dp)
        s%t_last_switch = -huge(1.0_dp)
        s%close_switches = 0
        s%zeno_run = 0
        s%ievent = 0
        s%same_instant = 0
    end subroutine run_start

    !> One run of DOPRI5 in the current mode from t, up to the first step with an event (or a
    !! dip), a corner of the forces (`next_time_event`) or t_end; then the event located and
    !! the mode switched, or the corner's `time_event`. .false. when the run is over (t_end,
    !! or a status set).
    logical function run_mode(s, t_end, t_out, y_out) result(more)
        type(ed_run), intent(inout) :: s
        real(dp), intent(in)    :: t_end         !! final time [s]
        real(dp), intent(in)    :: t_out(:)      !! output times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! output states
        type(ode_stats) :: st
        real(dp) :: g_a(s%nc), g_b(s%nc), dg_a(s%nc), dg_b(s%nc)
        logical :: cand(s%nc), flip(s%nc), hit
        integer :: i, k, nrows
        more = .false.
        flip = .false.
        ! the budgets and the stop flag, before every mode's run (DOPRI5 takes at least a step)
        if (s%stats%nstep >= s%opts%max_steps) then
            s%stats%status = SS_STEP_BUDGET
            return
        end if
        if (stop_requested(s%opts, 0_8)) then
            s%stats%status = SS_INTERRUPTED
            return
        end if
        associate (ms => s%ms, cs => s%ms%cs, d5 => s%d5)
            ! Pass 1: the mode's steps, CHUNK rows at a time, looking for an event.
            d5%h0 = s%h_carry
            d5%max_steps = max(1_8, s%opts%max_steps - s%stats%nstep)
            ! A stuck contact's state barely moves, so DOPRI5's error estimate does not limit
            ! the step, while the forces may follow a sine: keep the steps, at whose ends the
            ! holding forces are checked, to 1/STEPS_PER_PERIOD of the shortest period.
            s%t_seg = min(t_end, cs%next_time_event(s%t))   ! a corner of the forces: the mode ends there
            ms%t_cap = huge(1.0_dp)
            if (s%t_seg < t_end) ms%t_cap = nearest(s%t_seg, -1.0_dp)
            ! the event functions at the start; mode_step_accepted takes them at each step's end
            ! and halts DOPRI5 after a step with an event (or a dip) in it
            call event_values(ms, s%t, s%y, ms%gb, s%r, ms%dgb)
            ms%closed = ms%wn > 0.0_dp
            ms%flip = .false.
            ! So does an open contact's normal force, which the state does not follow while it
            ! is open: it is sampled at the same density, to see where it closes.
            d5%hmax = 0.0_dp
            if ((any(ms%stuck) .or. .not. all(ms%closed)) .and. cs%time_scale() < huge(1.0_dp)) &
                d5%hmax = cs%time_scale() / STEPS_PER_PERIOD
            ms%t_prev = s%t
            ms%halted = .false.
            call dopri5_integrate(ms, s%t, s%y, s%t_seg, s%rtol, s%atol, d5, s%tb, s%yb, st)
            s%stats%nfev = s%stats%nfev + st%nfev
            s%stats%nstep = s%stats%nstep + st%nstep
            s%stats%naccept = s%stats%naccept + st%naccept
            s%stats%nreject = s%stats%nreject + st%nreject
            s%h_carry = st%h_last
            nrows = st%n_written
            s%nrows = nrows
            if (st%status /= SS_OK .and. st%status /= SS_OUTPUT_FULL) then
                s%stats%status = st%status
                if (s%stats%status == SS_STEP_BUDGET .or. s%stats%nstep >= s%opts%max_steps) &
                    s%stats%status = SS_STEP_BUDGET
                call keep_rows(s, nrows, t_out, y_out)
                return
            end if
            if (ms%singular) then
                ! the stuck set's holding forces have no solution: the run's friction problem
                ! failed (not a Newton matrix: there is none); its last step is not kept
                s%stats%status = SS_CONTACT_FAILED
                s%stats%contact_worst = ms%singular_contact
                call keep_rows(s, nrows - 1, t_out, y_out)
                return
            end if
            if (diverged(s%yb(:, nrows), s%stats, s%opts%y_bound)) return   ! left the bound: SS_DIVERGED
            ! The run ends after the first step with an event or a dip (ms%halted): only its last
            ! step is searched, from the event functions mode_step_accepted kept at its ends.
            hit = .false.
            k = nrows
            s%k = k
            if (ms%halted) then
                s%ta = s%tb(k - 1)
                s%ya = s%yb(:, k - 1)
                s%tstar = s%tb(k)
                s%ystar = s%yb(:, k)
                g_a = ms%ga
                dg_a = ms%dga
                g_b = ms%gb
                dg_b = ms%dgb
                cand = crossed(ms%stuck, g_b)
                flip = ms%flip
                hit = any(cand) .or. any(flip)
                ! a slipping contact whose w turns back within the step: its minimum
                do i = 1, s%nc
                    if (.not. dips(ms%stuck(i), g_a(i), g_b(i), (s%tb(k) - s%ta) * dg_a(i), &
                                   (s%tb(k) - s%ta) * dg_b(i))) cycle
                    call graze(s, i, dg_a(i), dg_b(i), cand(i))
                    hit = hit .or. cand(i)
                end do
            end if
            if (.not. hit) then
                call output_to(s, s%tb(nrows), t_out, y_out)
                s%t = s%tb(nrows)
                s%y = s%yb(:, nrows)
                more = .true.
                if (st%status == SS_OK .and. s%t < s%t_seg) return          ! a dip that did not touch
                if (st%status == SS_OK .and. s%t_seg >= t_end) more = .false.  ! reached t_end
                if (st%status == SS_OK .and. more) then                       ! reached a corner
                    s%t = s%t_seg                  ! exactly: the next corner is the one after it
                    ms%t_cap = huge(1.0_dp)        ! from here on, the values after the corner
                    call time_event(s)
                end if
                return
            end if

            ! An event in step (ta, tb(k)] (or before a grazing minimum): the earliest crossing.
            s%h_carry = s%tb(k) - s%ta
            do i = 1, s%nc
                if (cand(i)) call locate(s, i, g_a(i))
            end do
            do i = 1, s%nc
                if (flip(i)) call locate_normal(s, i)
            end do
            call output_to(s, s%tstar, t_out, y_out)
            s%t = s%tstar
            s%y = s%ystar
            call switch_mode(s)
            more = s%stats%status == SS_OK .and. s%t < t_end
        end associate
    end function run_mode

    !> Contacts with w = 0 at t0 take the modes of the problem at rest (`decide`); the
    !! others slip in the direction of w. Not recorded as events.
    subroutine initial_mode(s)
        type(ed_run), intent(inout) :: s
        real(dp) :: w(s%nc)
        logical :: at_zero(s%nc)
        call s%ms%cs%relative_velocities(s%t, s%y(s%nd + 1:), w)
        at_zero = w == 0.0_dp
        where (.not. at_zero) s%ms%sig = sign(1.0_dp, w)
        if (any(at_zero)) call decide(s, at_zero, .false.)
    end subroutine initial_mode

    !> At a corner of the forces (`next_time_event`: a step of a normal force, a table's
    !! point): a stuck contact whose w has jumped away from 0 (a surface's speed stepped)
    !! slips in the direction of w (recorded); every stuck contact and every contact at w = 0
    !! is decided afresh, as at an event; DOPRI5 starts again with its automatic step.
    subroutine time_event(s)
        type(ed_run), intent(inout) :: s
        real(dp) :: w(s%nc)
        integer :: j, nchanged
        logical :: again(s%nc)
        associate (ms => s%ms)
            call ms%cs%relative_velocities(s%t, s%y(s%nd + 1:), w)
            do j = 1, s%nc
                if (ms%stuck(j) .and. abs(w(j)) > w_tolerance(s, j, s%y)) then
                    ms%stuck(j) = .false.
                    ms%sig(j) = sign(1.0_dp, w(j))
                    call record(s, j, EVENT_SLIP)
                else if (.not. ms%stuck(j) .and. w(j) /= 0.0_dp) then
                    ms%sig(j) = sign(1.0_dp, w(j))   ! a contact that was open slips the way it moves
                end if
            end do
            again = ms%stuck .or. w == 0.0_dp
            if (any(again) .and. s%stats%status == SS_OK) call decide(s, again, .true., nchanged)
            s%h_carry = 0.0_dp
        end associate
    end subroutine time_event

    !> The modes of the contacts cand (each at w = 0: stuck, or just reached) from the
    !! problem at rest (`decide_set`), and then from the mode itself: a stuck set whose holding
    !! forces are not unique (a closed loop of contacts) holds in the mode with its weighted
    !! minimum-norm forces (`mode_forces`), which may exceed a limit where the solver's box
    !! answer held it by another distribution; such a contact slips against its holding force
    !! and the others are decided again (at most once each), so that the stick test here and
    !! the break-away test of the mode use the same forces. With record, every change of mode
    !! is an event (kind 1 stick, 2 slip, 3 reversal).
    subroutine decide(s, cand, record_events, nchanged)
        type(ed_run), intent(inout) :: s
        logical, intent(in) :: cand(:)             !! (n_c) the contacts to decide
        logical, intent(in) :: record_events       !! record the changes as events
        integer, intent(out), optional :: nchanged !! contacts whose mode changed
        logical :: was_stuck(s%nc), c(s%nc), over(s%nc), let_go(s%nc)
        real(dp) :: old_sig(s%nc), a(s%nd), r(s%nc), nn(s%nc)
        integer :: j, round
        associate (ms => s%ms)
            was_stuck = ms%stuck
            old_sig = ms%sig
            c = cand
            s%tie = .false.
            let_go = .false.
            do round = 1, count(cand)
                call decide_set(s, c)
                if (s%stats%status /= SS_OK) then
                    ms%stuck = was_stuck
                    return
                end if
                if (.not. any(c .and. ms%stuck)) exit
                call mode_forces(ms, s%t, s%y, a, r)
                if (ms%singular) exit
                call ms%cs%normal_forces(min(s%t, ms%t_cap), s%y(:s%nd), nn)
                over = c .and. ms%stuck .and. abs(r) > ms%cs%laws%mu_s * nn * (1.0_dp + 2.0_dp * STICK_RTOL)
                if (.not. any(over)) exit
                s%tie = s%tie .or. held_otherwise(s, c .and. ms%stuck, r, nn)
                let_go = let_go .or. over
                where (over)
                    ms%stuck = .false.
                    ms%sig = -sign(1.0_dp, r)
                    c = .false.
                end where
                if (.not. any(c)) exit
            end do
            if (.not. s%tie) s%tie = other_decision(s, cand, let_go)
            if (s%tie) call count_nonunique(s%stats, s%t)
            if (present(nchanged)) nchanged = count(cand .and. ((ms%stuck .neqv. was_stuck) .or. &
                                                                 (.not. ms%stuck .and. ms%sig /= old_sig)))
            if (.not. record_events) return
            do j = 1, s%nc
                if (.not. cand(j)) cycle
                if (was_stuck(j) .and. .not. ms%stuck(j)) then
                    call record(s, j, EVENT_SLIP)
                else if (.not. was_stuck(j) .and. ms%stuck(j)) then
                    call record(s, j, EVENT_STICK)
                else if (.not. ms%stuck(j) .and. ms%sig(j) /= old_sig(j)) then
                    call record(s, j, EVENT_REVERSAL)
                end if
            end do
        end associate
    end subroutine decide

    !> The modes of the contacts cand (each at w = 0: stuck, or just reached) from the
    !! problem at rest: their relative accelerations a_C = af_C + A_CC r_C with the other
    !! contacts' slip forces fixed, solved jointly by `solve_contacts` (stick preferred).
    subroutine decide_set(s, cand)
        type(ed_run), intent(inout) :: s
        logical, intent(in) :: cand(:)             !! (n_c) the contacts to decide
        integer, allocatable :: idx(:), cmode(:)
        real(dp), allocatable :: amat(:, :), af(:), cap(:), p(:), wv(:), dgl(:)
        real(dp) :: a(s%nd), rr(s%nc), nn(s%nc), ha(s%nc), bd(s%nc), scale
        logical :: was_stuck(s%nc)
        type(contact_solve_info) :: info
        integer :: j, c, nn_c, nd
        nd = s%nd
        associate (ms => s%ms, cs => s%ms%cs, t => s%t, y => s%y)
            was_stuck = ms%stuck
            s%cand_now = cand
            idx = pack([(j, j = 1, s%nc)], cand)
            nn_c = size(idx)
            ! the free problem: the candidates carry no force
            ms%stuck(idx) = .false.
            call free_acceleration(s, a, rr)
            call cs%apply_h(a, ha)
            call cs%offset_rate(t, bd)
            call cs%normal_forces(t, y(:nd), nn)
            allocate(af(nn_c), cap(nn_c), p(nn_c), wv(nn_c), cmode(nn_c), dgl(nn_c))
            if (.not. ms%diagonal) allocate(amat(nn_c, nn_c))
            af = ha(idx) + bd(idx)
            cap = nn(idx)
            p = 0.0_dp
            cmode = MODE_STICK     ! the guess: every candidate held (see stickslip_contact_solver)
            scale = 1.0e-9_dp * max(maxval(abs(af)), tiny(1.0_dp))
            if (ms%diagonal) then
                ! uncoupled: one closed form per contact
                call delassus_diagonal(ms, t, y, idx, dgl)
                do j = 1, nn_c
                    call solve_contacts(cs%laws(idx(j):idx(j)), reshape([dgl(j)], [1, 1]), af(j:j), cap(j:j), &
                                        .true., scale, 1, p(j:j), wv(j:j), cmode(j:j), info)
                    if (.not. info%ok) exit
                end do
            else
                call delassus_block(ms, t, y, idx, amat)
                call solve_contacts(cs%laws(idx), amat, af, cap, .true., scale, 1000, p, wv, cmode, info)
                s%tie = s%tie .or. info%nonunique
            end if
            s%cand_now = .false.
            if (.not. info%ok) then
                s%stats%status = SS_CONTACT_FAILED
                s%stats%contact_worst = idx(max(info%worst, 1))
                ms%stuck = was_stuck
                return
            end if
            s%p_dec(idx) = p
            do j = 1, nn_c
                c = idx(j)
                ms%stuck(c) = cmode(j) == MODE_STICK
                if (abs(cmode(j)) == 1) ms%sig(c) = real(cmode(j), dp)
            end do
        end associate
    end subroutine decide_set

    !> Did the contact solver's answer at the decision under way (s%p_dec) hold the stuck
    !! contacts `held` by other forces than the mode's weighted minimum-norm ones r, within
    !! every static limit? Then a contact that r takes beyond its limit, and that therefore
    !! slips, could have been held (another solution, as many stuck contacts or more): the
    !! set's holding forces are not unique (a singular Delassus block: a closed loop of
    !! contacts, or redundant rows) and the choice decides. Forces that differ by no more than
    !! 1e-9 of the largest static limit are the same forces to rounding (a unique set at its
    !! limit), and are not counted.
    logical function held_otherwise(s, held, r, nn) result(other)
        type(ed_run), intent(in) :: s
        logical, intent(in)  :: held(:)     !! (n_c) the stuck contacts compared
        real(dp), intent(in) :: r(:)        !! (n_c) the mode's forces [N]
        real(dp), intent(in) :: nn(:)       !! (n_c) the normal forces [N]
        real(dp) :: lim(s%nc), gap
        lim = s%ms%cs%laws%mu_s * nn
        gap = 1.0e-9_dp * maxval(lim, mask=held, dim=1)
        other = any(held .and. abs(s%p_dec - r) > gap) .and. &
                all(abs(s%p_dec) <= lim * (1.0_dp + 2.0_dp * STICK_RTOL) .or. .not. held)
    end function held_otherwise

    !> Had the decision just made for the candidates cand another solution? Where it let
    !! stuck contacts go against their holding forces (let_go), one with as many stuck contacts
    !! that holds one of them (`loop_tie`); else, or if not, a mode consistent to first order
    !! only with a strict alternative (`first_order_tie`). The one test of `decide` and
    !! `switch_mode`.
    logical function other_decision(s, cand, let_go) result(other)
        type(ed_run), intent(inout) :: s
        logical, intent(in) :: cand(:)      !! (n_c) the contacts decided
        logical, intent(in) :: let_go(:)    !! (n_c) the ones let go against their holding forces
        other = .false.
        if (any(let_go)) other = loop_tie(s, cand, let_go)
        if (.not. other) other = first_order_tie(s, cand)
    end function other_decision

    !> The candidates cand's indices and their Delassus block [1/kg].
    subroutine candidates_block(s, cand, idx, amat)
        type(ed_run), intent(inout) :: s
        logical, intent(in) :: cand(:)                    !! (n_c) the candidates
        integer, allocatable, intent(out) :: idx(:)       !! their indices
        real(dp), allocatable, intent(out) :: amat(:, :)  !! their Delassus block [1/kg]
        integer :: j
        idx = pack([(j, j = 1, s%nc)], cand)
        allocate(amat(size(idx), size(idx)))
        call delassus_block(s%ms, s%t, s%y, idx, amat)
    end subroutine candidates_block

    !> Where a decision let stuck contacts go (let_go) because the mode's weighted minimum-norm
    !! forces took them beyond their limits, and the stuck set with them has a singular Delassus
    !! block (their holding forces are not unique: a closed loop of contacts): has the problem
    !! at rest of the candidates cand another solution with as many stuck contacts, one that
    !! holds a contact let go (`other_solution_exists`: the solver's test, on the modes decided)?
    logical function loop_tie(s, cand, let_go) result(other)
        type(ed_run), intent(inout) :: s
        logical, intent(in) :: cand(:)      !! (n_c) the contacts decided
        logical, intent(in) :: let_go(:)    !! (n_c) the ones let go against their holding forces
        integer, allocatable :: idx(:), cm(:), js(:)
        real(dp), allocatable :: amat(:, :), af(:), cap(:), p(:), wv(:), x(:, :)
        logical :: ok
        integer :: j
        other = .false.
        if (s%ms%diagonal) return
        call candidates_block(s, cand, idx, amat)
        js = pack([(j, j = 1, size(idx))], s%ms%stuck(idx) .or. let_go(idx))
        allocate(x(size(js), 1), source=1.0_dp)
        call psd_solve(amat(js, js), x, [(1.0_dp, j = 1, size(js))], ok, regular_only=.true.)
        if (ok) return                     ! regular: the holding forces are unique
        call problem_at_rest(s, cand, idx, amat, af, cap, p, wv, cm, ok)
        if (ok) call other_solution_exists(s%ms%cs%laws(idx), amat, af, cap, .true., p, wv, cm, other)
    end function loop_tie

    !> Is the mode just decided for the candidates cand consistent to first order only, with
    !! another mode (fewer stuck contacts) consistent strictly? A slipping candidate whose
    !! relative acceleration is 0 to the decision's tolerance (1e-9 of the largest free one, as
    !! `decide_set`) starts to slip only through the derivative of its forces (mu_s = mu(0+) at
    !! its limit), and where a stuck contact coupled to it slipping too gives a strict mode
    !! (`first_order_alternative`), which continuation is right depends on higher derivatives:
    !! a decision with another solution. Not tried where the Delassus matrix is diagonal (no
    !! coupling) or no candidate slips.
    logical function first_order_tie(s, cand) result(other)
        type(ed_run), intent(inout) :: s
        logical, intent(in) :: cand(:)      !! (n_c) the contacts decided
        integer, allocatable :: idx(:), cm(:)
        real(dp), allocatable :: amat(:, :), af(:), cap(:), p(:), wv(:)
        logical :: ok
        other = .false.
        if (s%ms%diagonal .or. .not. any(cand .and. .not. s%ms%stuck)) return
        call candidates_block(s, cand, idx, amat)
        call problem_at_rest(s, cand, idx, amat, af, cap, p, wv, cm, ok)
        if (ok) call first_order_alternative(s%ms%cs%laws(idx), amat, af, cap, &
                                             1.0e-9_dp * max(maxval(abs(af)), tiny(1.0_dp)), p, wv, cm, other)
    end function first_order_tie

    !> The problem at rest of the candidates idx (with their Delassus block amat) as
    !! `decide_set` poses it, with the current mode's forces (`mode_forces`) as its answer:
    !! af their free relative accelerations, cap their normal forces, p the mode's forces, cm
    !! its modes and wv = af + amat p (0 where stuck). ok: the mode's holding forces exist. A
    !! check: its evaluations are not counted as the run's.
    subroutine problem_at_rest(s, cand, idx, amat, af, cap, p, wv, cm, ok)
        type(ed_run), intent(inout) :: s
        logical, intent(in) :: cand(:)                    !! (n_c) the candidates
        integer, intent(in) :: idx(:)                     !! their indices
        real(dp), intent(in) :: amat(:, :)                !! their Delassus block [1/kg]
        real(dp), allocatable, intent(out) :: af(:)       !! free relative accelerations [m/s^2]
        real(dp), allocatable, intent(out) :: cap(:)      !! normal forces [N]
        real(dp), allocatable, intent(out) :: p(:)        !! the mode's forces [N]
        real(dp), allocatable, intent(out) :: wv(:)       !! the mode's relative accelerations [m/s^2]
        integer, allocatable, intent(out) :: cm(:)        !! the mode (MODE_STICK, +-1, MODE_OPEN)
        logical, intent(out) :: ok                        !! the mode's holding forces exist
        real(dp) :: a(s%nd), r(s%nc), rr(s%nc), ha(s%nc), bd(s%nc), nn(s%nc)
        logical :: stuck(s%nc)
        integer :: nfev
        associate (ms => s%ms, cs => s%ms%cs)
            call mode_forces(ms, s%t, s%y, a, r)
            ok = .not. ms%singular
            if (.not. ok) return
            nfev = ms%nfev
            stuck = ms%stuck
            s%cand_now = cand
            ms%stuck(idx) = .false.
            call free_acceleration(s, a, rr)
            ms%stuck = stuck
            s%cand_now = .false.
            ms%nfev = nfev
            call cs%apply_h(a, ha)
            call cs%offset_rate(s%t, bd)
            call cs%normal_forces(min(s%t, ms%t_cap), s%y(:s%nd), nn)
            af = ha(idx) + bd(idx)
            cap = nn(idx)
            p = r(idx)
            cm = merge(MODE_STICK, nint(ms%sig(idx)), ms%stuck(idx))
            where (.not. cap > 0.0_dp) cm = MODE_OPEN
            wv = af + matmul(amat, p)
            where (cm == MODE_STICK) wv = 0.0_dp
        end associate
    end subroutine problem_at_rest

    !> The acceleration a and forces rr with the current mode's slip forces and without the
    !! forces of stuck contacts (used with the candidates marked as not stuck and carrying
    !! no force: w = 0 gives them the slip force of speed 0, which is removed here).
    subroutine free_acceleration(s, a, rr)
        type(ed_run), intent(inout) :: s
        real(dp), intent(out) :: a(:)   !! acceleration [m/s^2]
        real(dp), intent(out) :: rr(:)  !! the slip forces [N]
        real(dp) :: f(s%nd), w(s%nc), nn(s%nc)
        integer :: j, nd
        nd = s%nd
        associate (ms => s%ms, cs => s%ms%cs, t => s%t, y => s%y)
            call cs%force(t, y(:nd), y(nd + 1:), f)
            call cs%normal_forces(t, y(:nd), nn)
            call cs%relative_velocities(t, y(nd + 1:), w)
            ms%nfev = ms%nfev + 1
            rr = 0.0_dp
            do j = 1, s%nc
                if (.not. ms%stuck(j) .and. .not. s%cand_now(j)) &
                    rr(j) = -ms%sig(j) * nn(j) * cs%laws(j)%slip_mu(max(ms%sig(j) * w(j), 0.0_dp))
            end do
            a = f
            call cs%add_ht(rr, a)
            call cs%solve_w(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, a)
        end associate
    end subroutine free_acceleration

    !> The minimum of a slipping contact i's sigma w in (ta, tstar) (where its rate changes
    !! sign), by Illinois regula falsi on the rate. If sigma w reaches 0 there, tstar and
    !! ystar move to that point (a crossing lies in (ta, tstar]) and hit_i is set; if its
    !! minimum comes within the integration's tolerance of 0 (`w_tolerance`) without
    !! crossing, the contact touches: tstar moves to the minimum and it is decided there.
    subroutine graze(s, i, da, db, hit_i)
        type(ed_run), intent(inout) :: s
        integer, intent(in) :: i              !! the contact
        real(dp), intent(in) :: da, db        !! its rates at ta and tstar [m/s^2]
        logical, intent(inout) :: hit_i       !! set when it reaches or touches w = 0
        real(dp) :: lo, hi, dlo, dhi, tm, gv(s%nc), rr(s%nc), dgv(s%nc), yq(s%n), gbest, tbest, ybest(s%n)
        integer :: it, side
        lo = s%ta
        hi = s%tstar
        dlo = da
        dhi = db
        side = 0
        gbest = huge(1.0_dp)
        tbest = s%tstar
        ybest = s%ystar
        do it = 1, 100
            tm = lo - dlo * (hi - lo) / (dhi - dlo)
            if (.not. (tm > lo .and. tm < hi)) tm = 0.5_dp * (lo + hi)
            if (tm <= lo .or. tm >= hi) exit
            call advance(s, tm, yq)
            call event_values(s%ms, tm, yq, gv, rr, dgv)
            if (gv(i) <= 0.0_dp) then
                s%tstar = tm
                s%ystar = yq
                hit_i = .true.
                return
            end if
            if (gv(i) < gbest) then
                gbest = gv(i)
                tbest = tm
                ybest = yq
            end if
            if (dgv(i) < 0.0_dp) then
                lo = tm
                dlo = dgv(i)
                if (side == 1) dhi = 0.5_dp * dhi
                side = 1
            else
                hi = tm
                dhi = dgv(i)
                if (side == -1) dlo = 0.5_dp * dlo
                side = -1
            end if
            if (hi - lo <= 1.0e-10_dp * (s%tstar - s%ta)) exit
        end do
        if (gbest <= w_tolerance(s, i, ybest)) then
            s%tstar = tbest
            s%ystar = ybest
            s%touch(i) = .true.
            s%t_touch = tbest
            hit_i = .true.
        end if
    end subroutine graze

    !> The integration's tolerance on contact i's relative velocity at the state yq [m/s]:
    !! sum over its row of H of |H_ij| (atol_j + rtol_j |u_j|).
    real(dp) function w_tolerance(s, i, yq) result(tol)
        type(ed_run), intent(in) :: s
        integer, intent(in) :: i          !! the contact
        real(dp), intent(in) :: yq(:)     !! the state (q, u)
        integer :: kk, j
        tol = 0.0_dp
        associate (cs => s%ms%cs)
            do kk = cs%h_ptr(i), cs%h_ptr(i + 1) - 1
                j = s%nd + cs%h_col(kk)
                tol = tol + abs(cs%h_val(kk)) * (s%atol(min(j, size(s%atol))) + &
                                                 s%rtol(min(j, size(s%rtol))) * abs(yq(j)))
            end do
        end associate
    end function w_tolerance

    !> The state at time tq in [ta, tb(k)]: the continuous extension of the step k searched.
    subroutine advance(s, tq, yq)
        type(ed_run), intent(in) :: s
        real(dp), intent(in)  :: tq       !! time [s]
        real(dp), intent(out) :: yq(:)    !! the state there
        if (tq <= s%ta) then
            yq = s%ya
        else
            yq = dopri5_dense(s%ya, s%cb(:, s%k), s%ta, tq)
        end if
    end subroutine advance

    !> Earliest crossing of contact i's event function in (ta, tstar]: shrink tstar.
    subroutine locate(s, i, ga)
        type(ed_run), intent(inout) :: s
        integer, intent(in) :: i          !! the contact
        real(dp), intent(in) :: ga        !! its event function at ta
        real(dp) :: lo, hi, glo, ghi, tm, gm, gv(s%nc), rr(s%nc), dgv(s%nc), yq(s%n)
        integer :: it, side
        lo = s%ta
        hi = s%tstar
        glo = max(ga, 0.0_dp)
        ! g_i at the current tstar (it may already have been shrunk by another contact)
        call event_values(s%ms, s%tstar, s%ystar, gv, rr, dgv)
        ghi = gv(i)
        if (.not. crossed(s%ms%stuck(i), ghi)) return     ! crosses after an earlier event: not now
        side = 0
        do it = 1, 200
            if (hi - lo <= 4.0_dp * epsilon(1.0_dp) * max(abs(lo), abs(hi), 1.0e-300_dp)) exit
            if (glo > 0.0_dp .and. ghi < 0.0_dp) then
                tm = hi - ghi * (hi - lo) / (ghi - glo)
            else
                tm = 0.5_dp * (lo + hi)
            end if
            if (.not. (tm > lo .and. tm < hi)) tm = 0.5_dp * (lo + hi)
            if (tm <= lo .or. tm >= hi) exit
            call advance(s, tm, yq)
            call event_values(s%ms, tm, yq, gv, rr, dgv)
            gm = gv(i)
            if (crossed(s%ms%stuck(i), gm)) then
                hi = tm
                ghi = gm
                s%tstar = tm
                s%ystar = yq
                if (gm == 0.0_dp) exit
                if (side == -1) glo = 0.5_dp * glo   ! Illinois
                side = -1
            else
                lo = tm
                glo = gm
                if (side == 1) ghi = 0.5_dp * ghi
                side = 1
            end if
        end do
    end subroutine locate

    !> After a failed mode's run: the output rows and the state up to its step `last` (none
    !! when last < 1), so that t_reached and the rows written say how far the motion is known.
    subroutine keep_rows(s, last, t_out, y_out)
        type(ed_run), intent(inout) :: s
        integer, intent(in)     :: last          !! the last step of the run to keep
        real(dp), intent(in)    :: t_out(:)      !! output times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! output states
        if (last < 2) return                     ! tb(1) is the run's start: nothing new
        call output_to(s, s%tb(last), t_out, y_out)
        s%t = s%tb(last)
        s%y = s%yb(:, last)
    end subroutine keep_rows

    !> Earliest crossing of 0 by contact i's normal force in (ta, tstar] (it closes where the
    !! run started open, or opens where it started closed: `closed`), by bisection on the
    !! state's continuous extension to 4 units of round-off in t: shrink tstar.
    subroutine locate_normal(s, i)
        type(ed_run), intent(inout) :: s
        integer, intent(in) :: i          !! the contact
        real(dp) :: lo, hi, tm, yq(s%n)
        integer :: it
        if (.not. normal_flipped(s, i, s%tstar, s%ystar)) return   ! after an earlier event: not now
        lo = s%ta
        hi = s%tstar
        do it = 1, 200
            if (hi - lo <= 4.0_dp * epsilon(1.0_dp) * max(abs(lo), abs(hi), 1.0e-300_dp)) exit
            tm = 0.5_dp * (lo + hi)
            if (tm <= lo .or. tm >= hi) exit
            call advance(s, tm, yq)
            if (normal_flipped(s, i, tm, yq)) then
                hi = tm
                s%tstar = tm
                s%ystar = yq
            else
                lo = tm
            end if
        end do
    end subroutine locate_normal

    !> Has contact i's normal force at (tq, yq) crossed 0 since the mode's run started?
    logical function normal_flipped(s, i, tq, yq) result(flipped)
        type(ed_run), intent(inout) :: s
        integer, intent(in) :: i          !! the contact
        real(dp), intent(in) :: tq        !! time [s]
        real(dp), intent(in) :: yq(:)     !! the state (q, u) there
        real(dp) :: nn(s%nc)
        call s%ms%cs%normal_forces(min(tq, s%ms%t_cap), yq(:s%nd), nn)
        flipped = (nn(i) > 0.0_dp) .neqv. s%ms%closed(i)
    end function normal_flipped

    !> Switch the mode at (t, y): the contacts whose event functions have crossed and every
    !! stuck contact are decided together (`decide`); a contact that reached w = 0 and has
    !! one entry in H gets w = 0 exactly. A contact whose normal force rose above 0 (it was
    !! open where the mode's run started) slips the way it moves, and is decided with the
    !! others where it closes at w = 0 to the integration's tolerance (not slipped on the
    !! sign of rounding). If that changes no mode although a holding force
    !! exceeds its limit here (rounding at the limit), that contact gives way. More than
    !! 4 n_c + 8 switches in a row each within zeno_gap of the last (with or without a change
    !! of mode) end the run with SS_EVENT_ZENO: no input turns at one instant for ever.
    subroutine switch_mode(s)
        type(ed_run), intent(inout) :: s
        real(dp) :: gv(s%nc), rr(s%nc), dgv(s%nc), b(s%nc), nn(s%nc), w(s%nc)
        integer :: j, kk, nchanged
        logical :: now(s%nc), over(s%nc), closing(s%nc), cand(s%nc), tie
        if (s%t - s%t_last_switch <= s%opts%zeno_gap) then
            s%close_switches = s%close_switches + 1
            if (s%close_switches > 4 * s%nc + 8) then
                s%stats%status = SS_EVENT_ZENO
                return
            end if
        else
            s%close_switches = 0
        end if
        s%t_last_switch = s%t
        associate (ms => s%ms, cs => s%ms%cs)
            closing = .false.
            if (.not. all(ms%closed)) then
                call cs%normal_forces(min(s%t, ms%t_cap), s%y(:s%nd), nn)
                call cs%relative_velocities(s%t, s%y(s%nd + 1:), w)
                closing = nn > 0.0_dp .and. .not. ms%closed .and. .not. ms%stuck
                ! at w = 0 to the integration's tolerance (a body held by other contacts: its
                ! w is rounding) it is decided with the others; else it slips the way it moves
                do j = 1, s%nc
                    if (.not. closing(j)) cycle
                    closing(j) = abs(w(j)) <= w_tolerance(s, j, s%y)
                    if (.not. closing(j)) ms%sig(j) = sign(1.0_dp, w(j))
                end do
            end if
            call event_values(ms, s%t, s%y, gv, rr, dgv)
            call cs%slip_offset(s%t, b)
            now = crossed(ms%stuck, gv) .or. closing
            if (s%t == s%t_touch) now = now .or. s%touch
            s%touch = .false.
            ! every other slipping contact at w = 0 to the integration's tolerance goes with them
            ! (bodies that stop together: w_i and w_j reach 0 at one instant, and the crossing
            ! located on one leaves the other's at rounding): decided with the others, not left
            ! slipping at w = 0 with its slip force
            if (any(now .and. .not. ms%stuck)) then
                call cs%normal_forces(min(s%t, ms%t_cap), s%y(:s%nd), nn)
                call cs%relative_velocities(s%t, s%y(s%nd + 1:), w)
                do j = 1, s%nc
                    if (ms%stuck(j) .or. now(j) .or. .not. nn(j) > 0.0_dp) cycle
                    now(j) = abs(w(j)) <= w_tolerance(s, j, s%y)
                end do
            end if
            over = now .and. ms%stuck
            do j = 1, s%nc
                if (.not. now(j) .or. ms%stuck(j)) cycle
                kk = cs%h_ptr(j)
                if (cs%h_ptr(j + 1) - kk == 1) s%y(s%nd + cs%h_col(kk)) = -b(j) / cs%h_val(kk)
            end do
            call decide(s, now .or. ms%stuck, .true., nchanged)
            if (s%stats%status /= SS_OK .or. nchanged > 0) return
            ! nothing changed although a holding force exceeded its limit: rounding at the
            ! limit (or, where the solver held the set by other forces, a choice of forces:
            ! counted as another solution); the contact gives way against its holding force
            over = over .and. ms%stuck
            if (.not. any(over)) return
            cand = now .or. ms%stuck
            tie = .false.
            if (.not. s%tie) then           ! (a decision with another solution is counted once)
                call cs%normal_forces(min(s%t, ms%t_cap), s%y(:s%nd), nn)
                tie = held_otherwise(s, ms%stuck, rr, nn)
            end if
            do j = 1, s%nc
                if (over(j)) then
                    ms%stuck(j) = .false.
                    ms%sig(j) = -sign(1.0_dp, rr(j))
                    call record(s, j, EVENT_SLIP)
                end if
            end do
            if (.not. (s%tie .or. tie)) tie = other_decision(s, cand, over)
            if (tie) then
                s%tie = .true.
                call count_nonunique(s%stats, s%t)
            end if
        end associate
    end subroutine switch_mode

    !> Record an event of contact j at (t, y). Events at one instant count once towards the
    !! Zeno test (10 instants in a row closer than zeno_gap); more events at one instant than
    !! 4 n_c + 8 is chatter; more than max_events in all ends with SS_EVENT_BUDGET.
    subroutine record(s, j, kind)
        type(ed_run), intent(inout) :: s
        integer, intent(in) :: j          !! the contact
        integer, intent(in) :: kind       !! EVENT_STICK, EVENT_SLIP or EVENT_REVERSAL
        real(dp), allocatable :: grown(:, :)
        s%ievent = s%ievent + 1
        s%stats%nevents = s%ievent
        if (s%ievent <= s%room) then
            if (s%ievent > size(s%ev, 2)) then
                allocate(grown(4, min(s%room, 2 * size(s%ev, 2) + 64)))
                grown(:, :size(s%ev, 2)) = s%ev
                call move_alloc(grown, s%ev)
            end if
            s%ev(:, s%ievent) = [s%t, real(kind, dp), s%ms%cs%contact_displacement(j, s%y(:s%nd)), real(j, dp)]
        end if
        if (s%t == s%t_last_event) then
            s%same_instant = s%same_instant + 1
            if (s%same_instant > 4 * s%nc + 8) s%stats%status = SS_EVENT_ZENO
        else
            s%same_instant = 1
            if (s%t - s%t_last_event < s%opts%zeno_gap) then
                s%zeno_run = s%zeno_run + 1
            else
                s%zeno_run = 0
            end if
        end if
        s%t_last_event = s%t
        if (s%zeno_run >= ZENO_ROW) s%stats%status = SS_EVENT_ZENO
        if (s%ievent > s%opts%max_events .and. s%stats%status == SS_OK) s%stats%status = SS_EVENT_BUDGET
    end subroutine record

    !> Grid rows with times in (t, t_to], from the mode's steps (tb(1) = t, t_to <= tb(nrows)):
    !! a step's end state where a grid time falls on it, its continuous extension between.
    subroutine output_to(s, t_to, t_out, y_out)
        type(ed_run), intent(inout) :: s
        real(dp), intent(in)    :: t_to          !! the last time to write [s]
        real(dp), intent(in)    :: t_out(:)      !! output times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! output states
        integer :: j
        j = 2
        do while (s%next <= size(t_out))
            if (t_out(s%next) > t_to) exit
            do while (s%tb(j) < t_out(s%next))
                j = j + 1
            end do
            if (t_out(s%next) == s%tb(j)) then
                y_out(:, s%next) = s%yb(:, j)
            else
                y_out(:, s%next) = dopri5_dense(s%yb(:, j - 1), s%cb(:, j), s%tb(j - 1), t_out(s%next))
            end if
            s%next = s%next + 1
        end do
    end subroutine output_to

end module stickslip_event_driven
