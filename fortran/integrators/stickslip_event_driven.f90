!> Event-driven integration of a system with set-valued friction (`stickslip_contact`): the
!! exact reference. Each mode (every contact either stuck or slipping in a known direction)
!! is a smooth ODE integrated by DOPRI5 (`stickslip_dopri5`, unchanged); the transitions
!! are located by root-finding and the mode is switched there.
!!
!! In a mode, slipping contacts carry r_i = -sigma_i N_i mu_i(sigma_i w_i) (sigma_i = +-1 the
!! slip direction) and stuck contacts the holding forces that keep their relative
!! acceleration at zero: H_S M^-1 (f + H^T r) + db_S/dt = 0, a linear system of the size of
!! the stuck set (LU). A stuck contact's velocity is set to w = 0 when it sticks (exactly for
!! a contact with one entry in its row of H) and then stays there to rounding.
!!
!! Event functions: sigma_i w_i for a slipping contact (slip -> stick when it reaches 0) and
!! mu_s N_i - |r_i| for a stuck one (stick -> slip when the holding force reaches mu_s N_i).
!! They are evaluated at the end of every accepted step (one more force evaluation a step);
!! where one has reached 0, the crossing time is found by bracketing (Illinois regula falsi
!! with bisection) to within 4 units of round-off in t. The state at a trial time t is
!! integrated afresh from the start of the step (a DOPRI5 run from the step's start to t,
!! as accurate as the steps themselves). An event function that touches zero and returns
!! within one step is not seen (as with any event location that looks at signs).
!!
!! At an event the mode is switched and made consistent: contacts that reach w = 0 stick,
!! and any stuck contact whose holding force exceeds mu_s N is released, the worst first,
!! sliding against its holding force (one that reaches w = 0 and cannot be held reverses:
!! kind 3). Events are recorded as (t [s], kind: 1 slip -> stick, 2 stick -> slip, 3 reversal,
!! position of the contact's coordinate q [m], contact index). The initial mode (contacts
!! with w = 0 at t0 stuck if they can be held) is not an event.
!!
!! Output on the grid: DOPRI5's dense output, from a second DOPRI5 run over each stretch
!! between events that holds grid points (the same steps as the first until the event).
!! Counters: nstep/naccept/nreject of the mode integration; nfev counts every evaluation
!! (the event checks, the root-finding runs and the output runs included); nevents the
!! transitions.
!!
!! Accumulating events (Zeno, chatter) end the run with SS_EVENT_ZENO: more than
!! max_events events, or 10 in a row less than zeno_gap apart.
module stickslip_event_driven
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_DIM, SS_OUTPUT_FULL, SS_STEP_BUDGET, SS_EVENT_ZENO, &
                               SS_BAD_EVENT_CTL, SS_SINGULAR, SS_BAD_MAX_STEPS
    use stickslip_ode, only: ode_system, ode_stats, step_controls, method_info, check_problem, &
                             check_tolerances, output_start
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate
    use stickslip_contact, only: contact_system
    use stickslip_linalg, only: lu_decompose, lu_solve
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use stickslip_ode, only: diverged
    implicit none
    private

    public :: event_driven_options, event_driven_integrate

    integer, parameter, public :: EVENT_STICK = 1      !! slip -> stick
    integer, parameter, public :: EVENT_SLIP = 2       !! stick -> slip
    integer, parameter, public :: EVENT_REVERSAL = 3   !! w reached 0 and the contact could not be held

    !> What the event-driven method is and which controls it reads (registry entry).
    type(method_info), parameter, public :: EVENT_DRIVEN_INFO = method_info(name='event_driven', order=5, &
        adaptive=.true., implicit=.false., controls='rtol atol max_steps max_events zeno_gap', &
        doc='event-driven stick/slip switching, DOPRI5 in each mode', laws='coulomb stribeck')

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
    contains
        procedure :: rhs => mode_rhs
        !! (u, acceleration) in the current mode
    end type mode_system

    integer, parameter :: ZENO_ROW = 10

contains

    function set_event_option(self, name, value) result(status)
        class(event_driven_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts as reals)
        integer :: status
        status = SS_OK
        select case (name)
        case ('max_events')
            if (value >= 1.0_dp .and. value <= real(huge(1), dp)) then
                self%max_events = int(value)
            else
                status = SS_BAD_EVENT_CTL
            end if
        case ('zeno_gap'); self%zeno_gap = value
        case default;      status = self%step_controls%set(name, value)
        end select
    end function set_event_option

    !> Acceleration a and contact forces r [N] of the mode at (t, y).
    subroutine mode_forces(self, t, y, a, r)
        class(mode_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! (q, u)
        real(dp), intent(out) :: a(:)       !! acceleration u' [m/s^2]
        real(dp), intent(out) :: r(:)       !! contact forces [N]
        real(dp) :: f(size(a)), g(size(a)), nn(size(r)), w(size(r)), bd(size(r)), ha(size(r)), col(size(r))
        real(dp), allocatable :: amat(:, :), rs(:)
        integer, allocatable :: idx(:), ipiv(:)
        integer :: nd, nc, i, j, ns, info
        associate (cs => self%cs)
            nd = cs%n_dof
            nc = cs%n_c
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
            ns = count(self%stuck)
            if (ns == 0) return
            idx = pack([(i, i = 1, nc)], self%stuck)
            call cs%apply_h(a, ha)
            call cs%offset_rate(t, bd)
            if (self%diagonal) then
                ! H M^-1 H^T is diagonal on the stuck set: its diagonal from one solve with
                ! H^T 1_S (the stuck contacts' columns do not mix), the same arithmetic as the
                ! dense columns below and so the same forces, bit for bit, in O(n).
                col = 0.0_dp
                col(idx) = 1.0_dp
                g = 0.0_dp
                call cs%add_ht(col, g)
                call cs%solve_w(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, g)
                call cs%apply_h(g, col)
                if (any(col(idx) == 0.0_dp)) then
                    self%singular = .true.
                    return
                end if
                rs = -(ha(idx) + bd(idx)) / col(idx)
            else
                call dense_holding_forces()
                if (self%singular) return
            end if
            col = 0.0_dp
            col(idx) = rs
            r(idx) = rs
            g = 0.0_dp
            call cs%add_ht(col, g)
            call cs%solve_w(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, g)
            a = a + g
        end associate
    contains
        !> rs: the holding forces of the stuck set from the dense Delassus matrix (n_s columns,
        !! each a solve with W, and an LU: O(n n_s + n_s^3)).
        subroutine dense_holding_forces()
            associate (cs => self%cs)
            allocate(amat(ns, ns), ipiv(ns))
            do j = 1, ns
                col = 0.0_dp
                col(idx(j)) = 1.0_dp
                g = 0.0_dp
                call cs%add_ht(col, g)
                call cs%solve_w(t, y(:nd), y(nd + 1:), 0.0_dp, 0.0_dp, g)
                call cs%apply_h(g, col)
                amat(:, j) = col(idx)
            end do
            rs = -(ha(idx) + bd(idx))
            call lu_decompose(amat, ipiv, info)
            if (info /= 0) then
                self%singular = .true.
                return
            end if
            call lu_solve(amat, ipiv, rs)
            end associate
        end subroutine dense_holding_forces
    end subroutine mode_forces

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
        real(dp) :: r(self%cs%n_c)
        integer :: nd
        nd = self%cs%n_dof
        dydt(:nd) = y(nd + 1:)
        call mode_forces(self, t, y, dydt(nd + 1:), r)
    end subroutine mode_rhs

    !> The event functions of the mode at (t, y): sigma_i w_i (slipping), mu_s N_i - |r_i|
    !! (stuck); r returns the contact forces [N].
    subroutine event_values(ms, t, y, gv, r)
        class(mode_system), intent(inout) :: ms
        real(dp), intent(in)  :: t, y(:)
        real(dp), intent(out) :: gv(:), r(:)
        real(dp) :: a(ms%cs%n_dof), w(ms%cs%n_c), nn(ms%cs%n_c)
        integer :: nd
        nd = ms%cs%n_dof
        call mode_forces(ms, t, y, a, r)
        ms%nfev = ms%nfev + 1
        call ms%cs%relative_velocities(t, y(nd + 1:), w)
        call ms%cs%normal_forces(t, y(:nd), nn)
        where (ms%stuck)
            gv = ms%cs%laws%mu_s * nn - abs(r)
        elsewhere
            gv = ms%sig * w
        end where
    end subroutine event_values

    !> Integrate with stick/slip switching from t0 to t_end. y0 = (q0, u0), size 2 n_dof.
    !! events(:, k) = (t [s], kind, position [m], contact) of the k-th event, for as many as
    !! there are columns. Status: SS_OK, SS_EVENT_ZENO, SS_STEP_BUDGET, SS_SINGULAR,
    !! DOPRI5's run-time codes, or a bad-input code.
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

        integer, parameter :: CHUNK = 512
        type(mode_system) :: ms
        type(dopri5_options) :: d5
        type(ode_stats) :: st
        real(dp), allocatable :: tb(:), yb(:, :), y(:), ya(:), ystar(:), g_a(:), g_b(:), r(:)
        real(dp) :: t, ta, tstar, h_carry, t_last_event
        integer :: nd, nc, n, next, m, k, nrows, i, zeno_run, ievent
        logical :: hit

        stats%status = check_problem(t0, y0, t_end, t_out, y_out, .false.)
        if (stats%status == SS_OK) stats%status = check_tolerances(size(y0), rtol, atol)
        if (stats%status /= SS_OK) return
        nd = cs%n_dof
        nc = cs%n_c
        n = 2 * nd
        if (size(y0) /= n .or. size(events, 1) /= 4) then
            stats%status = SS_BAD_DIM
        else if (.not. (ieee_is_finite(opts%zeno_gap) .and. opts%zeno_gap >= 0.0_dp) .or. opts%max_events < 1) then
            stats%status = SS_BAD_EVENT_CTL
        else if (opts%max_steps < 1) then
            stats%status = SS_BAD_MAX_STEPS
        end if
        if (stats%status /= SS_OK) return

        allocate(ms%cs, source=cs)
        ms%diagonal = diagonal_delassus(cs)
        allocate(ms%stuck(nc), ms%sig(nc), g_a(nc), g_b(nc), r(nc))
        allocate(tb(CHUNK), yb(n, CHUNK), y(n), ya(n), ystar(n))
        d5%every_step = .true.
        d5%stop_flag => opts%stop_flag
        m = size(t_out)
        call output_start(t0, y0, t_out, y_out, .false., next)

        t = t0
        y = y0
        ms%stuck = .false.
        ms%sig = 1.0_dp
        call initial_mode()
        h_carry = 0.0_dp
        t_last_event = -huge(1.0_dp)
        zeno_run = 0
        ievent = 0

        segment: do
            ! Pass 1: the mode's steps, CHUNK rows at a time, looking for an event.
            d5%h0 = h_carry
            d5%max_steps = max(1_8, opts%max_steps - stats%nstep)
            call dopri5_integrate(ms, t, y, t_end, rtol, atol, d5, tb, yb, st)
            stats%nfev = stats%nfev + st%nfev
            stats%nstep = stats%nstep + st%nstep
            stats%naccept = stats%naccept + st%naccept
            stats%nreject = stats%nreject + st%nreject
            h_carry = st%h_last
            nrows = st%n_written
            if (st%status /= SS_OK .and. st%status /= SS_OUTPUT_FULL) then
                stats%status = st%status
                if (stats%status == SS_STEP_BUDGET .or. stats%nstep >= opts%max_steps) stats%status = SS_STEP_BUDGET
                if (nrows >= 1) call output_to(tb(nrows))
                exit segment
            end if
            if (ms%singular) then
                stats%status = SS_SINGULAR
                exit segment
            end if
            if (diverged(yb(:, nrows), stats, opts%y_bound)) exit segment   ! left the bound: SS_DIVERGED
            hit = .false.
            call event_values(ms, tb(1), yb(:, 1), g_a, r)
            do k = 2, nrows
                call event_values(ms, tb(k), yb(:, k), g_b, r)
                if (any(g_b <= 0.0_dp)) then
                    hit = .true.
                    exit
                end if
                g_a = g_b
            end do
            if (.not. hit) then
                call output_to(tb(nrows))
                if (stats%status /= SS_OK) exit segment
                t = tb(nrows)
                y = yb(:, nrows)
                if (st%status == SS_OK) exit segment     ! reached t_end
                cycle segment
            end if

            ! An event in step (tb(k-1), tb(k)]: the earliest crossing.
            ta = tb(k - 1)
            ya = yb(:, k - 1)
            h_carry = tb(k) - ta
            tstar = tb(k)
            ystar = yb(:, k)
            do i = 1, nc
                if (g_b(i) <= 0.0_dp) call locate(i, g_a(i), g_b(i))
            end do
            if (stats%status /= SS_OK) exit segment
            call output_to(tstar)
            if (stats%status /= SS_OK) exit segment
            t = tstar
            y = ystar
            call switch_mode()
            if (stats%status /= SS_OK) exit segment
            if (t >= t_end) exit segment
        end do segment

        stats%nfev = stats%nfev + ms%nfev
        stats%t_reached = t
        stats%n_written = next - 1

    contains

        !> Contacts with w = 0 at t0 stuck, then released until the mode is consistent.
        subroutine initial_mode()
            real(dp) :: w(nc)
            call cs%relative_velocities(t, y(nd + 1:), w)
            ms%stuck = w == 0.0_dp
            where (.not. ms%stuck) ms%sig = sign(1.0_dp, w)
            call release(0)
        end subroutine initial_mode

        !> Release stuck contacts that cannot be held, the worst first. A contact released
        !! here that has just stuck (index just_stuck) is a reversal. Returns the kind.
        subroutine release(just_stuck, kind_out)
            integer, intent(in) :: just_stuck
            integer, intent(inout), optional :: kind_out
            real(dp) :: a(nd), rr(nc), nn(nc), excess
            integer :: j, worst
            do
                if (.not. any(ms%stuck)) return
                call mode_forces(ms, t, y, a, rr)
                ms%nfev = ms%nfev + 1
                call cs%normal_forces(t, y(:nd), nn)
                worst = 0
                excess = 0.0_dp
                do j = 1, nc
                    if (.not. ms%stuck(j)) cycle
                    if (abs(rr(j)) - cs%laws(j)%mu_s * nn(j) > excess) then
                        excess = abs(rr(j)) - cs%laws(j)%mu_s * nn(j)
                        worst = j
                    end if
                end do
                if (worst == 0) return
                ms%stuck(worst) = .false.
                ms%sig(worst) = -sign(1.0_dp, rr(worst))
                if (worst == just_stuck .and. present(kind_out)) kind_out = 3
            end do
        end subroutine release

        !> The state at time tq in [ta, tb(k)] from (ta, ya); a failed run sets stats%status.
        subroutine advance(tq, yq)
            real(dp), intent(in)  :: tq
            real(dp), intent(out) :: yq(:)
            type(dopri5_options) :: o
            type(ode_stats) :: s1
            real(dp) :: tt(1), yy(n, 1)
            if (tq <= ta) then
                yq = ya
                return
            end if
            o%h0 = tq - ta
            o%max_steps = 100000_8
            tt(1) = tq
            call dopri5_integrate(ms, ta, ya, tq, rtol, atol, o, tt, yy, s1)
            stats%nfev = stats%nfev + s1%nfev
            yq = yy(:, 1)
            if (s1%status /= SS_OK) stats%status = s1%status
        end subroutine advance

        !> Earliest crossing of contact i's event function in (ta, tstar]: shrink tstar.
        subroutine locate(i, ga, gb)
            integer, intent(in) :: i
            real(dp), intent(in) :: ga, gb
            real(dp) :: lo, hi, glo, ghi, tm, gm, gv(nc), rr(nc), yq(n)
            integer :: it, side
            lo = ta
            hi = tstar
            glo = max(ga, 0.0_dp)
            ! g_i at the current tstar (it may already have been shrunk by another contact)
            call event_values(ms, tstar, ystar, gv, rr)
            ghi = gv(i)
            if (ghi > 0.0_dp) return     ! crosses after an earlier event: not now
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
                call advance(tm, yq)
                if (stats%status /= SS_OK) return
                call event_values(ms, tm, yq, gv, rr)
                gm = gv(i)
                if (gm <= 0.0_dp) then
                    hi = tm
                    ghi = gm
                    tstar = tm
                    ystar = yq
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

        !> Switch the mode at (t, y) for the contacts whose event functions are <= 0.
        subroutine switch_mode()
            real(dp) :: gv(nc), rr(nc), b(nc)
            integer :: j, kind, kk
            call event_values(ms, t, y, gv, rr)
            call cs%slip_offset(t, b)
            do j = 1, nc
                if (gv(j) > 0.0_dp) cycle
                if (ms%stuck(j)) then
                    kind = 2
                    ms%stuck(j) = .false.
                    ms%sig(j) = -sign(1.0_dp, rr(j))
                else
                    kind = 1
                    ms%stuck(j) = .true.
                    kk = cs%h_ptr(j)
                    if (cs%h_ptr(j + 1) - kk == 1) y(nd + cs%h_col(kk)) = -b(j) / cs%h_val(kk)
                end if
                if (kind == 1) call release(j, kind)
                call record(j, kind)
                if (stats%status /= SS_OK) return
            end do
            call release(0)
        end subroutine switch_mode

        subroutine record(j, kind)
            integer, intent(in) :: j, kind
            ievent = ievent + 1
            stats%nevents = ievent
            if (ievent <= size(events, 2)) events(:, ievent) = [t, real(kind, dp), &
                y(cs%contact_coordinate(j)), real(j, dp)]
            if (t - t_last_event < opts%zeno_gap) then
                zeno_run = zeno_run + 1
            else
                zeno_run = 0
            end if
            t_last_event = t
            if (ievent > opts%max_events .or. zeno_run >= ZENO_ROW) stats%status = SS_EVENT_ZENO
        end subroutine record

        !> Grid rows with times in (t, t_to], by DOPRI5's dense output over the stretch
        !! (a second run from (t, y) with the first run's initial step); a failed run sets
        !! stats%status.
        subroutine output_to(t_to)
            real(dp), intent(in) :: t_to
            integer :: last
            type(dopri5_options) :: o
            type(ode_stats) :: s2
            if (next > m .or. t_to <= t) return
            last = next
            do while (last + 1 <= m)
                if (t_out(last + 1) > t_to) exit
                last = last + 1
            end do
            if (t_out(next) > t_to) return
            o%h0 = d5%h0
            o%max_steps = opts%max_steps
            call dopri5_integrate(ms, t, y, t_to, rtol, atol, o, t_out(next:last), y_out(:, next:last), s2)
            stats%nfev = stats%nfev + s2%nfev
            next = next + s2%n_written
            if (s2%status /= SS_OK) stats%status = s2%status
        end subroutine output_to

    end subroutine event_driven_integrate

end module stickslip_event_driven
