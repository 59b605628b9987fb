!> The friction problem of one step (or one instant) of a system with set-valued contacts,
!! for any number of contacts coupled through any Delassus matrix, and its solver: the one
!! place where the nonsmooth methods decide which contacts stick and which slip: moreau
!! (velocity level; on a chain `tridiagonal_rule`), event_driven (acceleration level,
!! `at_rest`), and implicit_euler and galpha over the laws' modes (the section at the end),
!! with one rule where the problem has several solutions.
!!
!! The problem. Relative velocities w = wf + D p (n contacts; D symmetric positive
!! semidefinite, [1/kg]: D = H W^-1 H^T of a time step, or H M^-1 H^T at the acceleration
!! level); each contact i with capacity c_i > 0 (h N_i [N s] for impulses, N_i [N] for
!! forces) obeys its set-valued law:
!!   stick: w_i = 0 and |p_i| <= mu_s,i c_i (1 + STICK_RTOL), or
!!   slip:  w_i /= 0 and p_i = -sign(w_i) c_i mu_i(|w_i|),
!! with mu_i the law's slip curve (`slip_mu`), or, at the acceleration level (`at_rest`),
!! the constant mu_i(0+) of a contact that starts to slip from rest. A contact with c_i = 0 or
!! mu_s,i = 0 is open: p_i = 0. |p_i| = mu_s c_i exactly counts as stuck (both nonsmooth
!! methods treat the limit the same way, within the relative tolerance STICK_RTOL).
!!
!! When the problem has several solutions (mu_s > mu_k: a contact held between mu_k c and
!! mu_s c could also slip; D singular: redundant contacts), the solver returns the one of
!! this rule, the same at every n and for every caller:
!!   1. Keep a slip: a contact that slipped in the previous step (mode in = +-1) and whose free
!!      velocity still goes that way faster than its own static limit could stop,
!!      mode_i wf_i > D_ii mu_s,i c_i, starts at its slip level, |p_i| <= c_i mu_i; every other
!!      contact starts at its static level, |p_i| <= mu_s,i c_i.
!!   2. Static first: with those levels as bounds the box problem (`stickslip_lcp`, the
!!      optimality condition of min 1/2 p^T D p + wf^T p over the box) is solved; its w is the
!!      same at every solution. A contact at its static level with w_i /= 0 cannot hold given
!!      the others and gives way: its bound drops to its slip level mu_i(|w_i|) c_i. A contact
!!      at its slip level whose w_i turns against its slip direction (its velocity crossed
!!      zero) is decided again from its static level, once. When no contact changes level,
!!      each contact that gave way (in order) is tried at its static level again with the
!!      others as they are: several can give way in one round, and one of them may hold once
!!      the others slip at their lower slip level. The first that holds there (w_i = 0) is
!!      raised back, once at most, and the rounds go on; a contact whose w_i exceeds
!!      D_ii (mu_s,i - mu_i) c_i cannot hold there (its static level moves its w by at most
!!      that) and is not tried. Rounds end when no contact changes level and none is raised
!!      (at most 5 n + 30). So only a contact whose static limit cannot hold given the others
!!      gives way, and a stuck contact never slips because another solution would allow it.
!!   3. Minimum norm: the stuck contacts' impulses are the ones that minimise
!!      sum p_i^2 / (mu_s,i c_i) among those that hold them (each loaded in proportion to its
!!      capacity), and the slip speeds solve the slip curves exactly (`solve_mode`).
!! Contacts on identical rows of H (the same row up to sign) have the same w, so the rule
!! treats them as one contact: splitting a contact into halves changes nothing (nothing is
!! counted). On one contact the rule is the closed form `local_solve` (stick when
!! |wf| <= D c mu_s). info%nonunique reports that another solution with at least as many
!! stuck contacts exists: for each slipping contact with |w_i| <= D_ii (mu_s,i + mu_i) c_i
!! (the others cannot let it stick otherwise) the mode with it stuck, that mode with the
!! stuck contacts it would overload slipping, and else that mode with one of the two stuck
!! contacts most coupled to it slipping (at most 4 such swaps a problem) are solved and
!! tested (a sufficient test: a tie it does not reach is not reported); a contact on the same
!! row as one held or let go in a trial (its other half) is held or let go with it.
!! `other_solution_exists` runs the same test on an answer found otherwise (event_driven's
!! modes, decided with its minimum-norm forces). At the acceleration level a mode may also be
!! consistent to first order only: a contact that starts to slip with zero relative
!! acceleration (mu_s = mu(0+) at its limit: only the derivative of the forces moves it);
!! `first_order_alternative` says whether a mode with a stuck contact coupled to it slipping
!! too is consistent strictly (another solution, with fewer stuck contacts, which only higher
!! derivatives tell apart).
!!
!! How. One active contact: its closed form (`local_solve`). More: the rounds of the rule,
!! each box problem by `box_solve` (an active-set Newton method, 1 to 4 linear solves from the
!! previous round's sets, with Lemke's method as the exact fallback), then the final mode
!! solved exactly (`solve_mode`). Cost: O(n^3) a linear solve, a few solves a round, a few
!! rounds a step; no enumeration of modes. On a chain (W tridiagonal, each contact on a
!! coordinate of its own) moreau runs `tridiagonal_rule` here: the same rounds, each box
!! problem by `tridiagonal_sweeps` (nonsmooth Gauss-Seidel on W itself, O(n) a sweep), and
!! `solve_contacts` on a step they do not solve (its own notes).
!! Projected Gauss-Seidel (`gauss_seidel`) is kept
!! for benchmarks and where a caller forces it (method = SOLVER_GAUSS_SEIDEL); its answer is a
!! solution when ok but follows no rule. The answer is checked against the problem itself
!! (`contact_residual`) whichever way it was found, and info%ok is .false. when the residual
!! exceeds the limit of the problem's scale (`residual_limit`) or no method found a solution:
!! the caller ends with a named status.
!!
!! The laws' modes (implicit_euler, galpha). Their step problem is the same, w = wf + D p with
!! p_i = c_i mu_i (c_i = h N_i), but each contact's graph is its regularised law's with its
!! jumps filled in (`friction_law%n_modes`, `mode`, `admits`: Coulomb with its band mu_s for
!! 0 < |v| < v_s and the set-valued point v_s, Karnopp with its band dv), a graph that is not
!! monotone, so that the box problems of the rounds do not apply. The same rule decides it
!! contact by contact (`modal_local_solve`): keep a slip (the current slip mode, where it still
!! holds and the contact cannot stick), else static first (the consistent mode whose velocity
!! is nearest zero: stuck where the static limit holds, else the slowest slip), and
!! `solve_modal_contacts` (dense D) or `modal_tridiagonal_sweeps` (W tridiagonal, each contact
!! on a coordinate of its own, O(n) a sweep) sweep it over the contacts (nonsmooth
!! Gauss-Seidel) until no mode changes, then check every contact on its mode and w = wf + D p.
!! nonunique there: some slipping contact, given the others' impulses, had another consistent
!! slip mode at another velocity (another solution with as many stuck contacts: exact on one
!! contact; on several, a tie of one contact's problem).
module stickslip_contact_solver
    use stickslip_kinds, only: dp
    use stickslip_contact, only: contact_law, contact_system, local_solve, CONTACT_COULOMB, STICK_RTOL
    use stickslip_linalg, only: psd_solve, lu_decompose, lu_solve
    use stickslip_lcp, only: box_solve
    use stickslip_friction, only: friction_law, MODE_MU, MODE_V
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: contact_solve_info, contact_workspace, solve_contacts, contact_residual, gauss_seidel
    public :: tridiagonal_sweeps, tridiagonal_rule, forces_at_rest, other_solution_exists, first_order_alternative
    public :: modal_law, modal_law_set, solve_modal_contacts, modal_tridiagonal_sweeps, modal_local_solve, modal_choose
    public :: STICK_RTOL   !! (from stickslip_contact) |p| <= mu_s c (1 + STICK_RTOL) sticks [-]

    integer, parameter, public :: MODE_STICK = 0    !! mode(i): stuck
    integer, parameter, public :: MODE_OPEN = 2     !! mode(i): open (no capacity), p_i = 0
    !! (slip is mode(i) = +1 or -1, the sign of w_i)

    integer, parameter, public :: SOLVER_LOCAL = 1          !! one active contact, closed form
    integer, parameter, public :: SOLVER_RULE = 2           !! the rule's rounds, box problems by active-set Newton
    integer, parameter, public :: SOLVER_GAUSS_SEIDEL = 3   !! projected Gauss-Seidel (forced only)
    integer, parameter, public :: SOLVER_PIVOTING = 4       !! the rule's rounds, box problems by Lemke alone

    !> Tolerance on the contact velocities of a step over the laws' modes, relative to the
    !! step's largest velocity (at least 1 m/s) [-].
    real(dp), parameter, public :: MODAL_TOL = 1.0e-12_dp
    !> Gauss-Seidel sweeps allowed a step over the laws' modes.
    integer, parameter, public :: MODAL_MAX_SWEEPS = 1000
    !> Sweeps after which each contact keeps its current mode wherever it holds (the rule's
    !! choices cycle where the contacts' ties feed each other: a band far narrower than a
    !! step's velocity change); such a step counts as nonunique.
    integer, parameter, public :: MODAL_SETTLE = 100

    !> The friction law of one contact, with modes (`friction_law%n_modes` > 0), for the step
    !! problem over the laws' modes.
    type :: modal_law
        class(friction_law), allocatable :: law   !! the contact's law
        integer, allocatable :: kind(:)           !! (modes) each mode's kind (`friction_law%mode`)
        real(dp), allocatable :: value(:)         !! (modes) its value: mu [-] or v [m/s]
        integer :: stick = 0                      !! the stuck mode (v = 0; 0: none)
    end type modal_law

    !> What the solver did and how well the answer satisfies the problem.
    type :: contact_solve_info
        logical :: ok = .true.          !! the answer satisfies the problem to tol
        integer :: method = 0           !! SOLVER_LOCAL, SOLVER_RULE, SOLVER_GAUSS_SEIDEL or SOLVER_PIVOTING
        integer :: sweeps = 0           !! Gauss-Seidel sweeps, or the rule's linear solves
        integer :: pivots = 0           !! Lemke pivots (0: not used)
        integer :: rounds = 0           !! box problems solved by the rule's rounds
        logical :: nonunique = .false.  !! another solution with as many stuck contacts exists
        real(dp) :: residual = 0.0_dp   !! complementarity residual (`contact_residual`) [m/s]
        integer :: worst = 0            !! the contact with the largest residual (0: none)
    end type contact_solve_info

    !> Work room of `solve_contacts`, `gauss_seidel` and `tridiagonal_rule`, for a caller that
    !! solves one problem after another (a time step each): passed to every call, it is sized on
    !! the first and then reused, so that a Gauss-Seidel solve and a step of the rule on a chain
    !! allocate nothing (without it each call allocates its own). One per caller and per thread:
    !! the solver keeps no state in it between calls.
    type :: contact_workspace
        real(dp), allocatable :: gap(:)  !! (n) Gauss-Seidel's gap, wf + D p - w at its answer [m/s]
        !> (n_dof, 4) `tridiagonal_rule`'s pivots from the top and from the bottom, and its
        !! sweeps' W uf and changes of a sweep
        real(dp), allocatable :: tri_dof(:, :)
        !> (n_c, 5) `tridiagonal_rule`'s free velocities, D_ii, levels, next levels and static
        !! limits of the contacts
        real(dp), allocatable :: tri_con(:, :)
        logical, allocatable :: tri_flag(:, :)      !! (n_c, 3) its kinetic, reset and active flags
        integer, allocatable :: tri_dir(:)          !! (n_c) its slip directions
        type(contact_law), allocatable :: tri_box(:)  !! (n_c) its box problem's laws
    end type contact_workspace

contains

    !> Solve the problem of the module notes. p: impulses out (a warm start for a forced
    !! Gauss-Seidel); mode: the previous mode in (rule step 1; any other value: none), the
    !! solution's out. method (tests and benchmarks): SOLVER_PIVOTING solves the rule's box
    !! problems by Lemke's method alone, SOLVER_GAUSS_SEIDEL runs projected Gauss-Seidel (up to
    !! max_iter sweeps; the rule where it fails). work: room reused from call to call. The
    !! arrays are declared contiguous (a strided section is passed as a copy).
    subroutine solve_contacts(laws, d, wf, cap, at_rest, tol, max_iter, p, w, mode, info, method, work)
        type(contact_law), intent(in), contiguous        :: laws(:)   !! (n) each contact's law
        real(dp), intent(in), contiguous                 :: d(:, :)   !! (n, n) Delassus matrix [1/kg]
        real(dp), intent(in), contiguous                 :: wf(:)     !! (n) velocities without friction [m/s]
        real(dp), intent(in), contiguous                 :: cap(:)    !! (n) capacities c_i >= 0 [N s] (or [N])
        logical, intent(in)                              :: at_rest   !! slip coefficient fixed at mu(0+)
        real(dp), intent(in)                             :: tol       !! tolerance on the residual [m/s]
        integer, intent(in)                              :: max_iter  !! Gauss-Seidel sweep limit (forced Gauss-Seidel)
        real(dp), intent(inout), contiguous              :: p(:)      !! (n) impulses [N s] (or forces [N])
        real(dp), intent(out), contiguous                :: w(:)      !! (n) velocities, exactly 0 when stuck [m/s]
        integer, intent(inout), contiguous               :: mode(:)   !! (n) MODE_STICK, +-1, MODE_OPEN
        type(contact_solve_info), intent(out)            :: info      !! how it was solved, residual, ok
        integer, intent(in), optional                    :: method    !! force SOLVER_PIVOTING or SOLVER_GAUSS_SEIDEL
        type(contact_workspace), intent(inout), optional :: work      !! room reused between calls
        integer :: n, na, i, ia, forced, worst
        real(dp) :: g, resid
        real(dp), allocatable :: gap(:)
        n = size(wf)
        ! the active contacts (capacity and a static limit), the others open
        na = 0
        ia = 0
        do i = 1, n
            if (is_active(laws(i), cap(i))) then
                na = na + 1
                ia = i
            else
                p(i) = 0.0_dp
                mode(i) = MODE_OPEN
            end if
        end do
        forced = 0
        if (present(method)) forced = method
        if (na == 0) then
            w = wf
        else if (na == 1) then
            info%method = SOLVER_LOCAL
            call local_solve(law_at(laws(ia), at_rest), wf(ia), d(ia, ia), cap(ia), w(ia), p(ia))
            mode(ia) = slip_sign(w(ia))
            call open_velocities(d, wf, p, mode, w)
        else if (forced == SOLVER_GAUSS_SEIDEL) then
            ! Gauss-Seidel (its updates and gap in the caller's room when given), then in one
            ! pass the modes of the answer, the open contacts' velocities (wf + D p, formed
            ! here) and the check (`contact_residual`, with the last sweep's wf + D p - w of
            ! each active contact)
            info%method = SOLVER_GAUSS_SEIDEL
            if (present(work)) call move_alloc(work%gap, gap)
            call reserve(gap, n)
            if (at_rest) then
                call gs_sweeps(law_at(laws, at_rest), d, wf, cap, tol, max_iter, p, w, info%sweeps, gap(:n))
            else
                call gs_sweeps(laws, d, wf, cap, tol, max_iter, p, w, info%sweeps, gap(:n))
            end if
            resid = 0.0_dp
            worst = 0
            do i = 1, n
                if (is_active(laws(i), cap(i))) then
                    mode(i) = slip_sign(w(i))
                    g = abs(gap(i))
                else
                    w(i) = wf(i) + dot_product(d(i, :), p)
                    g = 0.0_dp
                end if
                call keep_worst(residual_of(laws(i), d(i, i), cap(i), at_rest, p(i), w(i), mode(i), g), i, resid, worst)
            end do
            info%residual = resid
            info%worst = worst
            if (present(work)) call move_alloc(gap, work%gap)
            info%ok = info%residual <= residual_limit(tol, wf, d, p)
            if (info%ok) return
            forced = 0
            mode = -9           ! the rule from no previous mode
        end if
        if (na >= 2 .and. .not. (info%method == SOLVER_GAUSS_SEIDEL .and. info%ok)) then
            call rule_solve(laws, d, wf, cap, at_rest, tol, forced == SOLVER_PIVOTING, p, w, mode, info)
            if (.not. info%ok) return
            call find_other_solution(laws, d, wf, cap, at_rest, p, w, mode, info)
            return
        end if
        call contact_residual(laws, d, wf, cap, at_rest, p, w, mode, info%residual, info%worst)
        info%ok = info%residual <= residual_limit(tol, wf, d, p)
    end subroutine solve_contacts

    !> The contact forces r [N] of a system at (t, q, u) under its set-valued laws, as the
    !! event-driven method's mode gives them: a contact that slips (|w_i| > wtol_i) carries its
    !! slip force -sign(w_i) N_i mu_i(|w_i|); the contacts at rest (|w_i| <= wtol_i: stuck, or
    !! reversing) take the forces of the problem at rest, their relative accelerations
    !! a_C = af_C + D_CC r_C (D = H M^-1 H^T, the slip forces of the others in af, the offsets'
    !! rates db/dt included) decided by `solve_contacts` (its rule; slip at mu(0+) N). A stuck
    !! contact's holding force is thus the one that keeps its relative acceleration at zero,
    !! within its static limit. info: the solve's (info%ok .false.: r is not a solution).
    subroutine forces_at_rest(cs, t, q, u, wtol, r, info)
        class(contact_system), intent(in) :: cs   !! the system
        real(dp), intent(in)  :: t                !! time [s]
        real(dp), intent(in)  :: q(:)             !! (n_dof) coordinates [m]
        real(dp), intent(in)  :: u(:)             !! (n_dof) velocities [m/s]
        real(dp), intent(in)  :: wtol(:)          !! (n_c) |w_i| up to which contact i is at rest [m/s]
        real(dp), intent(out) :: r(:)             !! (n_c) each contact's force [N]
        type(contact_solve_info), intent(out) :: info   !! the solve's residual, rounds and status
        real(dp) :: w(cs%n_c), nn(cs%n_c), ha(cs%n_c), bd(cs%n_c), a(cs%n_dof), dall(cs%n_c, cs%n_c)
        integer, allocatable :: idx(:), mode(:)
        real(dp), allocatable :: p(:), wc(:)
        integer :: i
        call cs%relative_velocities(t, u, w)
        call cs%normal_forces(t, q, nn)
        r = 0.0_dp
        do i = 1, cs%n_c
            if (abs(w(i)) > wtol(i)) r(i) = -sign(1.0_dp, w(i)) * nn(i) * cs%laws(i)%slip_mu(abs(w(i)))
        end do
        idx = pack([(i, i = 1, cs%n_c)], abs(w) <= wtol)
        if (size(idx) == 0) return
        call cs%force(t, q, u, a)
        call cs%add_ht(r, a)
        call cs%solve_w(t, q, u, 0.0_dp, 0.0_dp, a)
        call cs%apply_h(a, ha)
        call cs%offset_rate(t, bd)
        call cs%delassus(t, q, u, 0.0_dp, 0.0_dp, dall)
        allocate(p(size(idx)), wc(size(idx)), mode(size(idx)))
        p = 0.0_dp
        mode = MODE_STICK
        call solve_contacts(cs%laws(idx), dall(idx, idx), ha(idx) + bd(idx), nn(idx), .true., &
                            1.0e-9_dp * max(maxval(abs(ha(idx) + bd(idx))), tiny(1.0_dp)), 1000, p, wc, mode, info)
        r(idx) = p
    end subroutine forces_at_rest

    !> The rule of the module notes (steps 1 to 3) on the active contacts, and its answer
    !! checked (`contact_residual`). info: method, rounds, linear solves, pivots, residual, ok.
    subroutine rule_solve(laws, d, wf, cap, at_rest, tol, lemke_only, p, w, mode, info)
        type(contact_law), intent(in) :: laws(:)
        real(dp), intent(in)    :: d(:, :), wf(:), cap(:), tol
        logical, intent(in)     :: at_rest, lemke_only
        real(dp), intent(inout) :: p(:)
        real(dp), intent(out)   :: w(:)
        integer, intent(inout)  :: mode(:)
        type(contact_solve_info), intent(inout) :: info
        logical :: active(size(wf))
        integer :: idx(count(is_active(laws, cap))), na, j, act(size(idx)), dir(size(idx)), s
        integer :: m_new(size(wf)), worst, rounds
        real(dp) :: da(size(idx), size(idx)), qa(size(idx)), bound(size(idx)), pa(size(idx)), ya(size(idx))
        real(dp) :: mu(size(idx)), mu_new(size(idx)), wts(size(idx)), ca(size(idx)), dg(size(idx))
        real(dp) :: wtol, pm(size(wf)), wm(size(wf)), r_box, r_mode
        type(contact_law) :: lw(size(idx))
        real(dp) :: pt(size(idx)), yt(size(idx)), bt(size(idx))
        integer :: act_t(size(idx))
        logical :: kin(size(idx)), reset(size(idx)), stuck(size(idx)), changed, ok
        logical :: dropped(size(idx)), raised(size(idx)), solved
        info%method = merge(SOLVER_PIVOTING, SOLVER_RULE, lemke_only)
        active = is_active(laws, cap)
        na = size(idx)
        idx = pack([(j, j = 1, size(wf))], active)
        lw = law_at(laws(idx), at_rest)
        da = d(idx, idx)
        qa = wf(idx)
        ca = cap(idx)
        do j = 1, na
            dg(j) = da(j, j)
        end do
        wts = lw%mu_s * ca
        ! step 1: a slip kept where its free velocity still goes its way past its static limit
        kin = .false.
        dir = 0
        do j = 1, na
            s = mode(idx(j))
            if (abs(s) == 1) then
                if (s * qa(j) > dg(j) * wts(j) * (1.0_dp + STICK_RTOL)) then
                    kin(j) = .true.
                    dir(j) = s
                end if
            end if
        end do
        reset = .false.
        mu = lw%mu_s
        where (kin) mu = lw%slip_mu(max(abs(qa) - dg * wts, tiny(1.0_dp)))
        act = -dir           ! a kept slip starts on its bound against its direction
        ! step 2: rounds of box problems, static first; a contact that gave way is tried at its
        ! static level again once the rounds settle, and raised back where it then holds
        dropped = .false.
        raised = .false.
        solved = .false.
        do rounds = 1, 5 * na + 30
            if (.not. solved) then
                bound = ca * mu
                call round_box(da, qa, wts, bound, lemke_only, pa, ya, act, ok, info)
                if (.not. ok) return
            end if
            solved = .false.
            wtol = 1.0e3_dp * epsilon(1.0_dp) * (maxval(abs(qa)) + maxval(dg) * maxval(abs(pa)))
            stuck = abs(ya) <= wtol
            changed = .false.
            mu_new = mu
            do j = 1, na
                if (stuck(j)) cycle
                s = slip_sign(ya(j))
                if (.not. kin(j)) then               ! gives way
                    kin(j) = .true.
                    dropped(j) = .true.
                    dir(j) = s
                    changed = .true.
                else if (s /= dir(j)) then
                    if (.not. reset(j)) then         ! crossed zero: decided again from rest
                        kin(j) = .false.
                        reset(j) = .true.
                        dir(j) = 0
                        mu_new(j) = lw(j)%mu_s
                        changed = .true.
                        cycle
                    end if
                    dir(j) = s
                end if
                mu_new(j) = lw(j)%slip_mu(abs(ya(j)))
            end do
            if (.not. changed .and. all(abs(mu_new - mu) <= 8.0_dp * epsilon(1.0_dp) * mu)) then
                ! settled: a contact that gave way while others gave way with it may hold now
                ! that they slip; the first (in order) that holds at its static level is raised
                ! back (once at most), and the rounds go on from that box problem's answer
                do j = 1, na
                    if (.not. (dropped(j) .and. kin(j)) .or. raised(j)) cycle
                    ! raising its bound by (mu_s - mu) c moves its w by at most D_jj times that
                    ! (the others' answer to it only lessens the change): no hold beyond reach
                    if (abs(ya(j)) > dg(j) * (lw(j)%mu_s - mu(j)) * ca(j) + wtol) cycle
                    bt = ca * mu
                    bt(j) = ca(j) * lw(j)%mu_s
                    act_t = act
                    call round_box(da, qa, wts, bt, lemke_only, pt, yt, act_t, ok, info)
                    if (.not. ok) return
                    if (abs(yt(j)) > 1.0e3_dp * epsilon(1.0_dp) * (maxval(abs(qa)) + maxval(dg) * maxval(abs(pt)))) &
                        cycle
                    raised(j) = .true.
                    kin(j) = .false.
                    dir(j) = 0
                    mu_new(j) = lw(j)%mu_s
                    bound = bt
                    pa = pt
                    ya = yt
                    act = act_t
                    solved = .true.
                    exit
                end do
                if (.not. solved) exit
            end if
            mu = mu_new
        end do
        if (solved) then     ! the rounds ran out on a raise: its box problem's answer
            wtol = 1.0e3_dp * epsilon(1.0_dp) * (maxval(abs(qa)) + maxval(dg) * maxval(abs(pa)))
            stuck = abs(ya) <= wtol
        end if
        ! the answer of the last round, slips exactly on their bounds
        p = 0.0_dp
        where (.not. stuck) pa = -sign(bound, ya)
        p(idx) = pa
        w = wf + matmul(d, p)
        mode(idx) = MODE_STICK
        do j = 1, na
            if (.not. stuck(j)) mode(idx(j)) = slip_sign(ya(j))
            if (stuck(j)) w(idx(j)) = 0.0_dp
        end do
        call contact_residual(laws, d, wf, cap, at_rest, p, w, mode, r_box, worst)
        ! step 3: the same mode solved exactly (weighted minimum-norm stuck impulses, slip speeds)
        m_new = mode
        call solve_mode(laws, d, wf, cap, at_rest, m_new, pm, wm, ok)
        info%sweeps = info%sweeps + 1
        if (ok) then
            call contact_residual(laws, d, wf, cap, at_rest, pm, wm, m_new, r_mode, worst)
            if (r_mode <= max(r_box, residual_limit(0.0_dp, wf, d, pm))) then
                p = pm
                w = wm
            end if
        end if
        call contact_residual(laws, d, wf, cap, at_rest, p, w, mode, info%residual, info%worst)
        info%ok = info%residual <= residual_limit(tol, wf, d, p)

    end subroutine rule_solve

    !> One box problem of `rule_solve`'s rounds: |p| <= bound on y = q + D p (act: its warm
    !! start in, sets out), its work counted in info; ok = .false. (info%ok too) where no
    !! method solved it.
    subroutine round_box(da, qa, wts, bound, lemke_only, pb, yb, actb, ok, info)
        real(dp), intent(in)   :: da(:, :), qa(:), wts(:), bound(:)
        logical, intent(in)    :: lemke_only
        real(dp), intent(out)  :: pb(:), yb(:)
        integer, intent(inout) :: actb(:)
        logical, intent(out)   :: ok
        type(contact_solve_info), intent(inout) :: info
        integer :: its, piv
        call box_solve(da, qa, -bound, bound, wts, pb, yb, actb, its, piv, ok, lemke_only)
        info%sweeps = info%sweeps + its
        info%pivots = info%pivots + piv
        info%rounds = info%rounds + 1
        if (.not. ok) then
            info%ok = .false.
            info%residual = huge(1.0_dp)
        end if
    end subroutine round_box

    !> info%nonunique: whether a solution with at least as many stuck contacts as the answer
    !! (p, w, mode) exists in the neighbourhood the module notes name: each slipping contact
    !! that could stick made stuck, with the stuck contacts it would overload slipping, or else
    !! with one of the two stuck contacts most coupled to it (|D_jk| / sqrt(D_jj D_kk)) slipping
    !! against its holding impulse (at most 4 such swaps a problem).
    subroutine find_other_solution(laws, d, wf, cap, at_rest, p, w, mode, info)
        type(contact_law), intent(in) :: laws(:)
        real(dp), intent(in) :: d(:, :), wf(:), cap(:), p(:), w(:)
        logical, intent(in)  :: at_rest
        integer, intent(in)  :: mode(:)
        type(contact_solve_info), intent(inout) :: info
        integer, parameter :: MAX_PAIR_TRIALS = 4   ! swaps tried in all (a bound on the work)
        integer :: j, k, kk, it, nst, npair, mt(size(wf))
        real(dp) :: pt(size(wf)), wt(size(wf)), reach
        logical :: ok, over(size(wf)), tried(size(wf))
        nst = count(mode == MODE_STICK)
        npair = 0
        do j = 1, size(wf)
            if (abs(mode(j)) /= 1) cycle
            reach = d(j, j) * (laws(j)%mu_s + slip_coefficient(laws(j), abs(w(j)), at_rest)) * cap(j)
            ! at rest (event_driven's decisions, a few an event) also what the stuck contacts'
            ! swings between their limits could change (a swap of j with one of them)
            if (at_rest) reach = reach + sum(abs(d(j, :)) * (laws%mu_s + slip_coefficient(laws, 0.0_dp, at_rest)) &
                                             * cap, mask=mode == MODE_STICK)
            if (abs(w(j)) > reach * (1.0_dp + 1.0e-9_dp)) cycle
            mt = mode
            call set_with_twins(d, wf, j, MODE_STICK, mt)      ! a contact split in halves: both held
            call solve_mode(laws, d, wf, cap, at_rest, mt, pt, wt, ok)
            info%sweeps = info%sweeps + 1
            if (.not. ok .and. all(pt /= huge(1.0_dp)) .and. all(ieee_is_finite(pt))) then
                ! the stuck contacts that j's hold overloads slip (j itself, and its halves, held:
                ! once the others slip it may be within its limit)
                over = mt == MODE_STICK .and. mode == MODE_STICK .and. abs(pt) > laws%mu_s * cap * (1.0_dp + STICK_RTOL)
                if (any(over) .and. count(mt == MODE_STICK) - count(over) >= nst) then
                    where (over) mt = -nint(sign(1.0_dp, pt))
                    call solve_mode(laws, d, wf, cap, at_rest, mt, pt, wt, ok)
                    info%sweeps = info%sweeps + 1
                end if
            end if
            if (.not. ok .and. npair < MAX_PAIR_TRIALS) then
                ! j held in place of one of the (two) stuck contacts most coupled to it (j
                ! itself overloaded, or the stuck set with j has no solution: rows that conflict)
                tried = .false.
                do it = 1, 2
                    k = 0
                    do kk = 1, size(wf)
                        if (mode(kk) /= MODE_STICK .or. tried(kk) .or. p(kk) == 0.0_dp .or. d(j, kk) == 0.0_dp) cycle
                        if (k == 0) then
                            k = kk
                        else if (d(j, kk)**2 * d(k, k) > d(j, k)**2 * d(kk, kk)) then
                            k = kk
                        end if
                    end do
                    if (k == 0 .or. npair >= MAX_PAIR_TRIALS) exit
                    tried(k) = .true.
                    npair = npair + 1
                    mt = mode
                    call set_with_twins(d, wf, j, MODE_STICK, mt)
                    call set_with_twins(d, wf, k, -nint(sign(1.0_dp, p(k))), mt)
                    call solve_mode(laws, d, wf, cap, at_rest, mt, pt, wt, ok)
                    info%sweeps = info%sweeps + 1
                    if (ok) exit
                end do
            end if
            if (ok) then
                info%nonunique = .true.
                return
            end if
        end do
    end subroutine find_other_solution

    !> nonunique: whether the problem (laws, d, wf, cap, at_rest) has another solution with at
    !! least as many stuck contacts as its solution (p, w, mode), by the sufficient test of
    !! `solve_contacts` (info%nonunique; the module notes). For a caller whose answer was not
    !! (only) the solver's: event_driven, where the mode's minimum-norm forces let a stuck
    !! contact of a closed loop go.
    subroutine other_solution_exists(laws, d, wf, cap, at_rest, p, w, mode, nonunique)
        type(contact_law), intent(in) :: laws(:)   !! (n) each contact's law
        real(dp), intent(in) :: d(:, :)            !! (n, n) Delassus matrix [1/kg]
        real(dp), intent(in) :: wf(:)              !! (n) velocities without friction [m/s] (or [m/s^2])
        real(dp), intent(in) :: cap(:)             !! (n) capacities [N s] (or [N])
        logical, intent(in)  :: at_rest            !! slip coefficient fixed at mu(0+)
        real(dp), intent(in) :: p(:)               !! (n) the solution's impulses (or forces)
        real(dp), intent(in) :: w(:)               !! (n) its velocities (or accelerations)
        integer, intent(in)  :: mode(:)            !! (n) its modes
        logical, intent(out) :: nonunique          !! another solution was found
        type(contact_solve_info) :: info
        call find_other_solution(laws, d, wf, cap, at_rest, p, w, mode, info)
        nonunique = info%nonunique
    end subroutine other_solution_exists

    !> found: at the acceleration level (event_driven's decisions, forces at rest), the mode
    !! (p, w, mode) is consistent to first order only, and another mode with fewer stuck
    !! contacts is consistent strictly. The first: a slipping contact j with |w_j| <= tol (it
    !! starts to slip with no relative acceleration: mu_s = mu(0+) at its limit, moved only by
    !! the derivative of the forces). The second: that mode with one stuck contact k coupled to
    !! j (D_jk /= 0; with its other half) slipping against its holding force, whose every
    !! slipping contact accelerates in its direction by more than tol and whose every stuck
    !! force is within its limit. Which continuation is right then depends on higher
    !! derivatives. A sufficient test (at most MAX_TRIALS modes solved); nothing is tried where
    !! no slipping contact is at |w_j| <= tol (an ordinary break-away, mu_s > mu_k).
    subroutine first_order_alternative(laws, d, wf, cap, tol, p, w, mode, found)
        type(contact_law), intent(in) :: laws(:)   !! (n) each contact's law
        real(dp), intent(in) :: d(:, :)            !! (n, n) Delassus matrix [1/kg]
        real(dp), intent(in) :: wf(:)              !! (n) accelerations without friction [m/s^2]
        real(dp), intent(in) :: cap(:)             !! (n) capacities (normal forces) [N]
        real(dp), intent(in) :: tol                !! a relative acceleration this small is zero [m/s^2]
        real(dp), intent(in) :: p(:)               !! (n) the mode's forces [N]
        real(dp), intent(in) :: w(:)               !! (n) its relative accelerations [m/s^2]
        integer, intent(in)  :: mode(:)            !! (n) its modes (MODE_STICK, +-1, MODE_OPEN)
        logical, intent(out) :: found              !! another mode is consistent strictly
        integer, parameter :: MAX_TRIALS = 16      ! modes solved in all (a bound on the work)
        integer :: j, k, ntr, mt(size(wf))
        real(dp) :: pt(size(wf)), wt(size(wf))
        logical :: ok
        found = .false.
        ntr = 0
        do j = 1, size(wf)
            if (abs(mode(j)) /= 1 .or. abs(w(j)) > tol) cycle
            do k = 1, size(wf)
                if (mode(k) /= MODE_STICK .or. p(k) == 0.0_dp .or. d(j, k) == 0.0_dp) cycle
                if (ntr >= MAX_TRIALS) return
                ntr = ntr + 1
                mt = mode
                call set_with_twins(d, wf, k, -nint(sign(1.0_dp, p(k))), mt)
                call solve_mode(laws, d, wf, cap, .true., mt, pt, wt, ok)
                found = ok .and. .not. any(abs(mt) == 1 .and. mt * wt <= tol)
                if (found) return
            end do
        end do
    end subroutine first_order_alternative

    !> mt(i) := m, and the same for every contact on the same row as i up to sign (the same
    !! free velocity and the same row of D, up to sign: a contact split in halves), whose slip
    !! direction is then m times that sign.
    subroutine set_with_twins(d, wf, i, m, mt)
        real(dp), intent(in)   :: d(:, :), wf(:)
        integer, intent(in)    :: i, m
        integer, intent(inout) :: mt(:)
        integer :: k
        real(dp) :: sg
        mt(i) = m
        do k = 1, size(wf)
            if (k == i .or. abs(mt(k)) /= 1 .and. mt(k) /= MODE_STICK) cycle
            sg = sign(1.0_dp, d(i, k))
            if (abs(d(k, k) - d(i, i)) > 1.0e-12_dp * d(i, i) .or. abs(d(i, k) - sg * d(i, i)) > 1.0e-12_dp * d(i, i)) &
                cycle
            if (abs(wf(k) - sg * wf(i)) > 1.0e-12_dp * max(maxval(abs(wf)), tiny(1.0_dp))) cycle
            if (any(abs(d(k, :) - sg * d(i, :)) > 1.0e-12_dp * d(i, i))) cycle
            mt(k) = nint(sg) * m
        end do
    end subroutine set_with_twins

    !> Velocities of open contacts from the impulses, wf + D p.
    subroutine open_velocities(d, wf, p, mode, w)
        real(dp), intent(in)    :: d(:, :), wf(:), p(:)
        integer, intent(in)     :: mode(:)
        real(dp), intent(inout) :: w(:)
        integer :: j
        do j = 1, size(wf)
            if (mode(j) == MODE_OPEN) w(j) = wf(j) + dot_product(d(j, :), p)
        end do
    end subroutine open_velocities

    !> A contact that can carry friction: capacity c > 0 and a static limit mu_s > 0.
    elemental logical function is_active(law, cap)
        type(contact_law), intent(in) :: law
        real(dp), intent(in) :: cap
        is_active = cap > 0.0_dp .and. law%mu_s > 0.0_dp
    end function is_active

    !> The residual an answer may have: tol, or the rounding of wf + D p where that is
    !! larger [m/s]. D is positive semidefinite (|D_ij| <= sqrt(D_ii D_jj)), so its largest
    !! entry is on its diagonal: read there, O(n) rather than a pass over D (a D that were not
    !! semidefinite would only get a smaller, stricter limit).
    pure real(dp) function residual_limit(tol, wf, d, p) result(lim)
        real(dp), intent(in) :: tol, wf(:), d(:, :), p(:)
        real(dp) :: dmax
        integer :: i
        dmax = 0.0_dp
        do i = 1, size(d, 1)
            dmax = max(dmax, abs(d(i, i)))
        end do
        lim = max(tol, 1.0e3_dp * epsilon(1.0_dp) * (maxval(abs(wf)) + dmax * maxval(abs(p))))
    end function residual_limit

    !> The law of a contact as the solver uses it: at rest, the Coulomb law with the slip
    !! coefficient mu(0+) (mu_k for Coulomb, mu_s for the Stribeck curve).
    elemental function law_at(law, at_rest) result(l)
        type(contact_law), intent(in) :: law
        logical, intent(in) :: at_rest
        type(contact_law) :: l
        l = law
        if (at_rest) l = contact_law(kind=CONTACT_COULOMB, mu_s=law%mu_s, mu_k=law%slip_mu(0.0_dp))
    end function law_at

    pure integer function slip_sign(w) result(s)
        real(dp), intent(in) :: w
        s = MODE_STICK
        if (w > 0.0_dp) s = 1
        if (w < 0.0_dp) s = -1
    end function slip_sign

    !> The complementarity residual of (p, w, mode) [m/s]: for every contact the largest of
    !! |wf + D p - w| (w = 0 if stuck), and, scaled by D_ii, the excess of a stuck impulse over
    !! mu_s c (1 + STICK_RTOL), the distance of a slipping impulse from -sign(w) c mu(|w|),
    !! and a slip whose direction disagrees with its mode. With gap, wf + D p - w is read from
    !! it (formed by the caller to rounding: Gauss-Seidel's last sweep) instead of formed here.
    subroutine contact_residual(laws, d, wf, cap, at_rest, p, w, mode, resid, worst, gap)
        type(contact_law), intent(in) :: laws(:)  !! (n) each contact's law
        real(dp), intent(in)  :: d(:, :)    !! (n, n) Delassus matrix [1/kg]
        real(dp), intent(in)  :: wf(:)      !! (n) velocities without friction [m/s]
        real(dp), intent(in)  :: cap(:)     !! (n) capacities [N s] (or [N])
        real(dp), intent(in)  :: p(:)       !! (n) impulses [N s] (or forces [N])
        real(dp), intent(in)  :: w(:)       !! (n) velocities [m/s]
        logical, intent(in)   :: at_rest    !! slip coefficient fixed at mu(0+)
        integer, intent(in)   :: mode(:)    !! (n) MODE_STICK, +-1 or MODE_OPEN
        real(dp), intent(out) :: resid      !! the largest residual [m/s]
        integer, intent(out)  :: worst      !! its contact (0: none)
        real(dp), intent(in), optional :: gap(:)  !! (n) wf + D p - w, formed to rounding [m/s]
        real(dp) :: g
        integer :: i
        resid = 0.0_dp
        worst = 0
        do i = 1, size(wf)
            if (present(gap)) then
                g = abs(gap(i))
            else
                g = abs(wf(i) + dot_product(d(i, :), p) - w(i))
            end if
            call keep_worst(residual_of(laws(i), d(i, i), cap(i), at_rest, p(i), w(i), mode(i), g), i, resid, worst)
        end do
    end subroutine contact_residual

    !> One contact's term of `contact_residual` [m/s], given g = |wf_i + (D p)_i - w_i| [m/s].
    pure real(dp) function residual_of(law, d_ii, cap, at_rest, p, w, mode, g) result(r)
        type(contact_law), intent(in) :: law
        real(dp), intent(in) :: d_ii, cap, p, w, g
        logical, intent(in)  :: at_rest
        integer, intent(in)  :: mode
        real(dp) :: dii
        dii = max(d_ii, tiny(1.0_dp))
        r = g
        select case (mode)
        case (MODE_OPEN)
            r = max(r, abs(p) * dii)
        case (MODE_STICK)
            r = max(r, abs(w), dii * max(0.0_dp, abs(p) - law%mu_s * cap * (1.0_dp + STICK_RTOL)))
        case default
            if (real(mode, dp) * w <= 0.0_dp) then
                r = huge(1.0_dp)
            else
                r = max(r, dii * abs(p + mode * cap * slip_coefficient(law, abs(w), at_rest)))
            end if
        end select
        if (.not. ieee_is_finite(r)) r = huge(1.0_dp)
    end function residual_of

    !> The largest residual so far and its contact: contact i's residual r taken where larger
    !! (or where none is yet).
    pure subroutine keep_worst(r, i, resid, worst)
        real(dp), intent(in)    :: r
        integer, intent(in)     :: i
        real(dp), intent(inout) :: resid
        integer, intent(inout)  :: worst
        if (r > resid .or. worst == 0) then
            resid = max(resid, r)
            worst = i
        end if
    end subroutine keep_worst

    elemental real(dp) function slip_coefficient(law, s, at_rest) result(mu)
        type(contact_law), intent(in) :: law
        real(dp), intent(in) :: s
        logical, intent(in) :: at_rest
        if (at_rest) then
            mu = law%slip_mu(0.0_dp)
        else
            mu = law%slip_mu(s)
        end if
    end function slip_coefficient

    !> The solution of one mode m (MODE_STICK, +-1 or MODE_OPEN per contact), if it has one:
    !! the stuck block's impulses by the weighted minimum-norm solve, the slip speeds in closed
    !! form (constant coefficients) or by a safeguarded Newton iteration (the Stribeck curve).
    !! ok: the mode's equations have a solution that satisfies its inequalities.
    subroutine solve_mode(laws, d, wf, cap, at_rest, m, p, w, ok)
        type(contact_law), intent(in) :: laws(:)
        real(dp), intent(in)  :: d(:, :), wf(:), cap(:)
        logical, intent(in)   :: at_rest
        integer, intent(in)   :: m(:)
        real(dp), intent(out) :: p(:), w(:)
        logical, intent(out)  :: ok
        integer :: is(count(m == MODE_STICK)), jf(count(abs(m) == 1)), ns, nf, i, it
        real(dp) :: ps(size(is), size(jf) + 1), g(size(jf), size(jf)), v0(size(jf)), sg(size(jf))
        real(dp) :: s(size(jf)), r(size(jf)), jac(size(jf), size(jf)), step(size(jf), 1), mu(size(jf))
        real(dp) :: cf(size(jf)), dmu(size(jf)), cs(size(is))
        logical :: constant
        p = huge(1.0_dp)      ! (no solution: every stuck impulse beyond its limit)
        w = 0.0_dp
        ns = size(is)
        nf = size(jf)
        is = pack([(i, i = 1, size(m))], m == MODE_STICK)
        jf = pack([(i, i = 1, size(m))], abs(m) == 1)
        sg = real(m(jf), dp)
        cf = cap(jf)
        cs = laws(is)%mu_s * cap(is)
        ! P [wf_S, D_SF]: the stuck block's response to the free velocities and to each
        ! slipping contact's unit impulse
        if (ns > 0) then
            ps(:, 1) = -wf(is)
            do i = 1, nf
                ps(:, i + 1) = -d(is, jf(i))
            end do
            call psd_solve(d(is, is), ps, cs, ok)
            if (.not. ok) return
        end if
        ! w_F = v0 + G p_F with the stuck block eliminated
        v0 = wf(jf)
        g = d(jf, jf)
        if (ns > 0) then
            v0 = v0 + matmul(d(jf, is), ps(:, 1))
            g = g + matmul(d(jf, is), ps(:, 2:))
        end if
        constant = at_rest
        if (.not. constant) constant = all(laws(jf)%kind == CONTACT_COULOMB)
        ! slip speeds s > 0: s = sg (v0 - G (sg c mu(s)))
        mu = slip_coefficient(laws(jf), 0.0_dp, .true.)
        if (.not. at_rest) mu = laws(jf)%mu_k
        s = sg * (v0 - matmul(g, sg * cf * mu))
        if (.not. constant) then
            s = max(s, 1.0e-3_dp * maxval(abs(v0)), tiny(1.0_dp))
            ok = .false.
            do it = 1, 100
                mu = laws(jf)%slip_mu(s)
                dmu = laws(jf)%slip_dmu(s)
                r = s - sg * (v0 - matmul(g, sg * cf * mu))
                if (all(abs(r) <= 8.0_dp * epsilon(1.0_dp) * max(s, maxval(abs(v0))))) then
                    ok = .true.
                    exit
                end if
                do i = 1, nf
                    jac(:, i) = sg * g(:, i) * sg(i) * cf(i) * dmu(i)
                    jac(i, i) = jac(i, i) + 1.0_dp
                end do
                step(:, 1) = -r
                call newton_solve(jac, step(:, 1), ok)
                if (.not. ok) return
                ok = .false.
                ! keep the speeds positive (halve towards zero instead of crossing it)
                s = max(s + step(:, 1), 0.5_dp * s)
            end do
            if (.not. ok) return
            mu = laws(jf)%slip_mu(s)
        end if
        if (any(.not. (s > 0.0_dp))) then
            ok = .false.
            return
        end if
        p = 0.0_dp
        w = 0.0_dp
        p(jf) = -sg * cf * mu
        if (ns > 0) p(is) = ps(:, 1) + matmul(ps(:, 2:), p(jf))
        w(jf) = sg * s
        ok = all(abs(p(is)) <= cs * (1.0_dp + STICK_RTOL))
        if (ok) ok = all(ieee_is_finite(p))
        ! open contacts see the others' impulses
        do i = 1, size(m)
            if (m(i) == MODE_OPEN) w(i) = wf(i) + dot_product(d(i, :), p)
        end do
    end subroutine solve_mode

    !> x := J^-1 x for the small Newton matrix of solve_mode (LU; ok = .false. if singular).
    subroutine newton_solve(jac, x, ok)
        real(dp), intent(in)    :: jac(:, :)
        real(dp), intent(inout) :: x(:)
        logical, intent(out)    :: ok
        real(dp) :: a(size(x), size(x))
        integer :: ipiv(size(x)), info
        a = jac
        call lu_decompose(a, ipiv, info)
        ok = info == 0
        if (ok) call lu_solve(a, ipiv, x)
    end subroutine newton_solve

    !> Projected Gauss-Seidel on w = wf + D p: each active contact's closed form given the
    !! others' impulses, sweep after sweep until the largest change that a sweep's later updates
    !! made to an earlier contact's velocity is <= tol [m/s] or max_iter sweeps are done.
    !! p: warm start in, impulses out [N s]; w: each contact's velocity from its last solve
    !! (exactly 0: stuck; open contacts: wf + D p).
    !! gap (optional): wf + D p - w of every active contact at the answer, from the last sweep's
    !! own sums, no extra pass over D: contact i's solve forms wf_i + sum_(j/=i) D_ij p_j in full
    !! with the impulses of that moment (a slipping contact's w_i is then that plus D_ii p_i, a
    !! stuck one's 0 with p_i = -that / D_ii, both to rounding), and the sweep's later updates add
    !! sum_(j>i) D_ij dp_j (the sums the stopping test forms anyway). Each is a dot product formed
    !! afresh, never an accumulation over sweeps, so gap is wf + D p - w to the rounding of one
    !! dot product, as if formed from the answer; 0 for open contacts, whose w the caller forms.
    !! work: room reused from call to call (without it, a call allocates its own). The arrays
    !! are declared contiguous, as in `solve_contacts` (a strided section is passed as a copy).
    subroutine gauss_seidel(laws, d, wf, cap, at_rest, tol, max_iter, p, w, sweeps, gap, work)
        type(contact_law), intent(in), contiguous        :: laws(:)   !! (n) each contact's law
        real(dp), intent(in), contiguous                 :: d(:, :)   !! (n, n) Delassus matrix [1/kg]
        real(dp), intent(in), contiguous                 :: wf(:)     !! (n) velocities without friction [m/s]
        real(dp), intent(in), contiguous                 :: cap(:)    !! (n) capacities [N s] (or [N])
        logical, intent(in)                              :: at_rest   !! slip coefficient fixed at mu(0+)
        real(dp), intent(in)                             :: tol       !! tolerance on the sweep residual [m/s]
        integer, intent(in)                              :: max_iter  !! sweep limit
        real(dp), intent(inout), contiguous              :: p(:)      !! (n) impulses: warm start in, answer out
        real(dp), intent(out), contiguous                :: w(:)      !! (n) velocities from the last solves [m/s]
        integer, intent(out)                             :: sweeps    !! sweeps done
        real(dp), intent(out), optional                  :: gap(:)    !! (n) wf + D p - w at the answer [m/s]
        type(contact_workspace), intent(inout), optional :: work      !! room reused between calls
        real(dp), allocatable :: upd(:)
        ! the sweeps' updates need room for n numbers, which end as the gap
        if (present(work)) call move_alloc(work%gap, upd)
        call reserve(upd, size(p))
        if (at_rest) then     ! (the laws as the solver uses them, `law_at`: at rest, a copy)
            call gs_sweeps(law_at(laws, at_rest), d, wf, cap, tol, max_iter, p, w, sweeps, upd(:size(p)))
        else
            call gs_sweeps(laws, d, wf, cap, tol, max_iter, p, w, sweeps, upd(:size(p)))
        end if
        if (present(gap)) then
            gap = upd(:size(p))
            where (.not. is_active(laws, cap)) gap = 0.0_dp     ! open contacts
        end if
        if (present(work)) call move_alloc(upd, work%gap)
    end subroutine gauss_seidel

    !> The sweeps of `gauss_seidel` with the laws as the solver uses them (`law_at`); upd: room
    !! for each sweep's updates, and out the gap of the active contacts (`gauss_seidel`'s notes;
    !! an open contact's entry is left as it is).
    subroutine gs_sweeps(lw, d, wf, cap, tol, max_iter, p, w, sweeps, upd)
        type(contact_law), intent(in) :: lw(:)
        real(dp), intent(in)    :: d(:, :), wf(:), cap(:), tol
        integer, intent(in)     :: max_iter
        real(dp), intent(inout) :: p(:)
        real(dp), intent(out)   :: w(:), upd(:)
        integer, intent(out)    :: sweeps
        real(dp) :: wfi, pnew, r, resid
        integer :: i, j, nc
        nc = size(p)
        w = wf
        do sweeps = 1, max_iter
            do i = 1, nc
                if (.not. is_active(lw(i), cap(i))) then
                    upd(i) = 0.0_dp
                    cycle
                end if
                wfi = wf(i)
                do j = 1, nc
                    if (j /= i) wfi = wfi + d(i, j) * p(j)
                end do
                call local_solve(lw(i), wfi, d(i, i), cap(i), w(i), pnew)
                ! a slip: its velocity from the impulses themselves (the law's root, to rounding)
                if (w(i) /= 0.0_dp) w(i) = wfi + d(i, i) * pnew
                upd(i) = pnew - p(i)
                p(i) = pnew
            end do
            resid = 0.0_dp
            do i = 1, nc - 1
                r = 0.0_dp
                do j = i + 1, nc
                    r = r + d(i, j) * upd(j)
                end do
                resid = max(resid, abs(r))
                upd(i) = r          ! (no longer needed as an update: rows below i are done)
            end do
            if (resid <= tol) exit
        end do
        sweeps = min(sweeps, max_iter)
        ! the gap of the active contacts: the last sweep's later updates (the last contact's: none)
        if (nc > 0) upd(nc) = 0.0_dp
    end subroutine gs_sweeps

    !> Nonsmooth Gauss-Seidel on W u1 = W uf + H^T p with W tridiagonal (l, d, r) and each
    !! contact on one coordinate of its own: coordinate by coordinate, u1_i from its row given
    !! the neighbours, through the contact's one-contact solution (`local_solve`) where it has
    !! one; a stuck contact gets w = 0 exactly. Sweeps until the residual (the largest change
    !! that the update of coordinate i + 1 made to coordinate i's velocity, [m/s]) is <= tol,
    !! and, where the sweeps contract it slowly (by rho >= 1/2 a sweep: W ill-conditioned, a
    !! stiff spring or a tiny mass), until the distance to the answer that this leaves, about
    !! resid rho / (1 - rho), is <= tol too; or max_iter sweeps are done, or (after 8 sweeps)
    !! the contraction seen would need more than the sweeps left. resid: that estimate (> tol:
    !! not converged).
    !! u1: starting guess in, velocities out [m/s].
    subroutine tridiagonal_sweeps(cs, l, d, r, uf, coord_contact, boff, hn, tol, max_iter, u1, wloc, sweeps, resid, &
                                  iworst, laws, room)
        class(contact_system), intent(in) :: cs  !! the system (its laws and H)
        real(dp), intent(in)    :: l(:)          !! W(i, i - 1) [-]
        real(dp), intent(in)    :: d(:)          !! W(i, i) [-]
        real(dp), intent(in)    :: r(:)          !! W(i, i + 1) [-]
        real(dp), intent(in)    :: uf(:)         !! velocities without friction [m/s]
        integer, intent(in)     :: coord_contact(:)  !! the contact on each coordinate (0: none)
        real(dp), intent(in)    :: boff(:)       !! offsets of the relative velocities [m/s]
        real(dp), intent(in)    :: hn(:)         !! step times normal force of each contact [N s]
        real(dp), intent(in)    :: tol           !! tolerance on the residual [m/s]
        integer, intent(in)     :: max_iter      !! sweep limit, >= 1
        real(dp), intent(inout) :: u1(:)         !! velocities [m/s]
        real(dp), intent(out)   :: wloc(:)       !! each contact's relative velocity (0: stuck) [m/s]
        integer, intent(out)    :: sweeps        !! sweeps done
        real(dp), intent(out)   :: resid         !! final residual [m/s]
        integer, intent(out)    :: iworst        !! the coordinate with the largest residual
        type(contact_law), intent(in), optional :: laws(:)  !! (n_c) the laws to use instead of cs%laws
        !> (n, 2) room for W uf and a sweep's changes, reused between calls (without it, its own)
        real(dp), intent(inout), optional, target, contiguous :: room(:, :)
        real(dp), allocatable, target :: own(:, :)
        real(dp), pointer, contiguous :: b(:), du(:)
        real(dp) :: s, ufree, hv, w, pnew, rho, resid_prev
        integer :: i, n, c
        n = size(u1)
        if (present(room)) then
            b => room(:n, 1)
            du => room(:n, 2)
        else
            allocate(own(n, 2))
            b => own(:, 1)
            du => own(:, 2)
        end if
        resid = 0.0_dp
        iworst = 1
        ! b = W uf
        do i = 1, n
            b(i) = d(i) * uf(i)
            if (i > 1) b(i) = b(i) + l(i) * uf(i - 1)
            if (i < n) b(i) = b(i) + r(i) * uf(i + 1)
        end do
        resid_prev = 0.0_dp
        do sweeps = 1, max_iter
            do i = 1, n
                s = b(i)
                if (i > 1) s = s - l(i) * u1(i - 1)
                if (i < n) s = s - r(i) * u1(i + 1)
                ufree = s / d(i)
                c = coord_contact(i)
                if (c > 0) then
                    hv = cs%h_val(cs%h_ptr(c))
                    if (present(laws)) then
                        call local_solve(laws(c), hv * ufree + boff(c), hv * hv / d(i), hn(c), w, pnew)
                    else
                        call local_solve(cs%laws(c), hv * ufree + boff(c), hv * hv / d(i), hn(c), w, pnew)
                    end if
                    wloc(c) = w
                    if (w == 0.0_dp) then
                        ufree = -boff(c) / hv
                    else
                        ufree = ufree + hv * pnew / d(i)
                    end if
                end if
                du(i) = ufree - u1(i)
                u1(i) = ufree
            end do
            resid = 0.0_dp
            iworst = 1
            do i = 1, n - 1
                if (abs(r(i) * du(i + 1) / d(i)) > resid) then
                    resid = abs(r(i) * du(i + 1) / d(i))
                    iworst = i
                end if
            end do
            ! the sweeps contract the residual by rho = resid / resid_prev a sweep: what remains
            ! to the answer is about resid rho / (1 - rho), which must be within tol too
            ! (rho >= 1: not contracting, no end)
            rho = 0.0_dp
            if (resid_prev > 0.0_dp) rho = resid / resid_prev
            resid_prev = resid
            if (rho >= 0.5_dp) resid = resid * rho / max(1.0_dp - rho, epsilon(1.0_dp))
            if (resid <= tol) exit
            ! contracting too slowly to reach tol within max_iter sweeps: stop (not converged)
            if (sweeps >= 8 .and. rho >= 0.5_dp) then
                if (rho >= 1.0_dp) exit
                if (log(tol / resid) / log(rho) > real(max_iter - sweeps, dp)) exit
            end if
        end do
        sweeps = min(sweeps, max_iter)
    end subroutine tridiagonal_sweeps

    !> The rule of the module notes among a contact's modes, each solved on its own: the
    !! current mode jcur kept where it is a slip that still holds and no stuck mode holds (keep
    !! a slip); otherwise the consistent mode whose velocity is nearest zero (static first:
    !! stuck where the static limit holds, else the slowest slip, the static level giving way
    !! only as far as it must), the current mode among equals, else a stuck one, else the
    !! first. other: another consistent mode as stuck as the chosen one (a slip where it slips)
    !! at another velocity (by more than tie) exists: another solution with as many stuck
    !! contacts, as `solve_contacts` counts them. What
    !! `modal_local_solve` and the one-contact kernel of the implicit methods decide with.
    pure subroutine modal_choose(jcur, adm, stick, v, tie, jnew, other)
        integer, intent(in)   :: jcur        !! current mode (0 or out of range: none)
        logical, intent(in)   :: adm(:)      !! (modes) each mode's solution lies on it
        logical, intent(in)   :: stick(:)    !! (modes) the mode is the stuck point (v = 0)
        real(dp), intent(in)  :: v(:)        !! (modes) each mode's relative velocity [m/s]
        real(dp), intent(in)  :: tie         !! velocities closer than this are one solution [m/s]
        integer, intent(out)  :: jnew        !! the mode chosen (0: none consistent)
        logical, intent(out)  :: other       !! another consistent solution exists
        integer :: j, nm
        logical :: cur
        nm = size(adm)
        jnew = 0
        other = .false.
        cur = jcur >= 1 .and. jcur <= nm
        if (cur) cur = adm(jcur)
        if (cur) then
            if (.not. stick(jcur) .and. .not. any(adm .and. stick)) jnew = jcur     ! keep a slip
        end if
        if (jnew == 0) then                  ! static first: the slowest consistent mode
            do j = 1, nm
                if (.not. adm(j)) cycle
                if (jnew == 0) then
                    jnew = j
                else if (abs(v(j)) < abs(v(jnew)) .or. (abs(v(j)) == abs(v(jnew)) .and. stick(j))) then
                    jnew = j
                end if
            end do
            if (jnew == 0) return
            if (cur) then
                if (abs(v(jcur)) <= abs(v(jnew))) jnew = jcur
            end if
        end if
        do j = 1, nm     ! (a slip where it sticks has fewer stuck contacts: not counted)
            if (adm(j) .and. (stick(j) .eqv. stick(jnew)) .and. abs(v(j) - v(jnew)) > tie) other = .true.
        end do
    end subroutine modal_choose

    ! ---- The step problem over the laws' modes (implicit_euler, galpha) -----------------------

    !> Nonsmooth Gauss-Seidel over the contacts' modes, on the dense Delassus matrix: contact i
    !! given the others' impulses has w_i = a_i + D_ii p_i, and its one-contact problem over its
    !! law's modes is decided by the rule (`modal_local_solve`; the current mode of its
    !! keep-a-slip is the contact's mode at the step's start in the first sweep, then the one
    !! the sweeps reached: the hysteresis that lets the sweeps settle where the band graph
    !! is not monotone). Sweeps repeat until no mode
    !! changes and the largest change of an impulse moves no velocity by more than MODAL_TOL
    !! (relative to the problem's velocities). The answer is then checked: every contact on its
    !! mode (`admits`) and w = wf + D p to 1e3 MODAL_TOL. p: warm start in, impulses out [N s];
    !! mode: each contact's law mode, in (0: none) and out (0: open, no normal force). ok:
    !! converged and checked, else worst is the contact that failed. nonunique: at the answer
    !! some contact had another consistent mode given the others' impulses.
    subroutine solve_modal_contacts(laws, d, wf, w0, c, p, w, mode, sweeps, ok, worst, resid, nonunique)
        type(modal_law), intent(in) :: laws(:)   !! (n) each contact's law (with modes)
        real(dp), intent(in)    :: d(:, :)       !! (n, n) Delassus matrix [1/kg]
        real(dp), intent(in)    :: wf(:)         !! (n) velocities without friction [m/s]
        real(dp), intent(in)    :: w0(:)         !! (n) velocities at the step's start [m/s]
        real(dp), intent(in)    :: c(:)          !! (n) capacities h N_i >= 0 [N s]
        real(dp), intent(inout) :: p(:)          !! (n) impulses [N s]
        real(dp), intent(out)   :: w(:)          !! (n) velocities after the impulses [m/s]
        integer, intent(inout)  :: mode(:)       !! (n) law modes
        integer, intent(out)    :: sweeps        !! sweeps done
        logical, intent(out)    :: ok            !! converged and checked
        integer, intent(out)    :: worst         !! the contact that failed (0: none)
        real(dp), intent(out)   :: resid         !! the largest |wf + D p - w| [m/s]
        logical, intent(out)    :: nonunique     !! another consistent mode existed
        integer :: i, nc, jnew
        real(dp) :: a, pnew, wnew, change, scale
        logical :: changed, other
        nc = size(wf)
        worst = 0
        ok = .false.
        nonunique = .false.
        resid = huge(1.0_dp)
        scale = max(maxval(abs(wf)), maxval(abs(w0)), 1.0_dp)
        do sweeps = 1, MODAL_MAX_SWEEPS
            changed = .false.
            change = 0.0_dp
            do i = 1, nc
                a = wf(i) + dot_product(d(i, :), p) - d(i, i) * p(i)
                call modal_local_solve(laws(i), a, d(i, i), c(i), w0(i), mode(i), jnew, pnew, wnew, ok, hold=sweeps > MODAL_SETTLE)
                if (.not. ok) then
                    worst = i
                    return
                end if
                if (jnew /= mode(i)) changed = .true.
                change = max(change, abs(pnew - p(i)) * maxval(abs(d(:, i))))
                mode(i) = jnew
                p(i) = pnew
                w(i) = wnew
            end do
            if (.not. changed .and. change <= MODAL_TOL * scale) exit
        end do
        sweeps = min(sweeps, MODAL_MAX_SWEEPS)
        nonunique = sweeps > MODAL_SETTLE     ! the rule's choices cycled: held (another solution)
        ! the check: every contact on its mode, w = wf + D p; and whether another mode was open
        ok = .true.
        resid = 0.0_dp
        do i = 1, nc
            a = wf(i) + dot_product(d(i, :), p) - d(i, i) * p(i)
            wnew = a + d(i, i) * p(i)
            resid = max(resid, abs(wnew - w(i)))
            if (abs(wnew - w(i)) > 1.0e3_dp * MODAL_TOL * scale) ok = .false.
            if (mode(i) > 0) then
                if (.not. laws(i)%law%admits(mode(i), -w(i), (w0(i) - a) / (d(i, i) * c(i)), p(i) / c(i))) ok = .false.
            end if
            if (.not. ok) then
                worst = i
                return
            end if
            call modal_local_solve(laws(i), a, d(i, i), c(i), w0(i), mode(i), jnew, pnew, wnew, ok, other)
            ok = .true.
            nonunique = nonunique .or. other
        end do
    end subroutine solve_modal_contacts

    !> The sweeps of `solve_modal_contacts` on W u1 = W uf + H^T p itself, W tridiagonal (l, dg,
    !! r) and each contact on one coordinate of its own (`step_layout`): coordinate by
    !! coordinate, u1_j from its row given its neighbours, through its contact's one-contact
    !! problem where it has one (w_i = h_i u1_j + b_i; the same rule, `modal_local_solve`), O(n)
    !! a sweep. u1: velocities out [m/s]; the rest as there, resid the largest residual of a row
    !! of W, divided by its diagonal [m/s].
    subroutine modal_tridiagonal_sweeps(laws, cs, l, dg, r, uf, coord_contact, b, c, w0, u1, p, w, mode, &
                                        sweeps, ok, worst, resid, nonunique)
        type(modal_law), intent(in) :: laws(:)       !! (n_c) each contact's law (with modes)
        class(contact_system), intent(in) :: cs      !! the system (its H)
        real(dp), intent(in)    :: l(:)              !! W(j, j - 1) [kg]
        real(dp), intent(in)    :: dg(:)             !! W(j, j) [kg]
        real(dp), intent(in)    :: r(:)              !! W(j, j + 1) [kg]
        real(dp), intent(in)    :: uf(:)             !! velocities without friction [m/s]
        integer, intent(in)     :: coord_contact(:)  !! the contact on each coordinate (0: none)
        real(dp), intent(in)    :: b(:)              !! offsets of the relative velocities [m/s]
        real(dp), intent(in)    :: c(:)              !! capacities h N_i >= 0 [N s]
        real(dp), intent(in)    :: w0(:)             !! relative velocities at the step's start [m/s]
        real(dp), intent(out)   :: u1(:)             !! velocities [m/s]
        real(dp), intent(inout) :: p(:)              !! impulses [N s]
        real(dp), intent(out)   :: w(:)              !! relative velocities [m/s]
        integer, intent(inout)  :: mode(:)           !! law modes (0: none / open)
        integer, intent(out)    :: sweeps            !! sweeps done
        logical, intent(out)    :: ok                !! converged and checked
        integer, intent(out)    :: worst             !! the contact that failed (0: none)
        real(dp), intent(out)   :: resid             !! the largest row residual [m/s]
        logical, intent(out)    :: nonunique         !! another consistent mode existed
        real(dp) :: rhs(size(uf)), s, a, dii, hv, unew, pnew, wnew, change, scale
        integer :: j, i, nd, jnew
        logical :: changed, other
        nd = size(uf)
        do j = 1, nd
            rhs(j) = dg(j) * uf(j) + off_diagonal(uf, j)
        end do
        resid = huge(1.0_dp)
        nonunique = .false.
        ok = .false.
        worst = 0
        scale = max(maxval(abs(uf)), maxval(abs(w0)), 1.0_dp)
        u1 = uf
        do sweeps = 1, MODAL_MAX_SWEEPS
            changed = .false.
            change = 0.0_dp
            do j = 1, nd
                s = rhs(j) - off_diagonal(u1, j)
                i = coord_contact(j)
                if (i == 0) then
                    unew = s / dg(j)
                else
                    hv = cs%h_val(cs%h_ptr(i))
                    a = hv * s / dg(j) + b(i)
                    dii = hv**2 / dg(j)
                    call modal_local_solve(laws(i), a, dii, c(i), w0(i), mode(i), jnew, pnew, wnew, ok, hold=sweeps > MODAL_SETTLE)
                    if (.not. ok) then
                        worst = i
                        return
                    end if
                    if (jnew /= mode(i)) changed = .true.
                    mode(i) = jnew
                    p(i) = pnew
                    w(i) = wnew
                    unew = (wnew - b(i)) / hv
                end if
                change = max(change, abs(unew - u1(j)))
                u1(j) = unew
            end do
            if (.not. changed .and. change <= MODAL_TOL * scale) exit
        end do
        sweeps = min(sweeps, MODAL_MAX_SWEEPS)
        nonunique = sweeps > MODAL_SETTLE     ! the rule's choices cycled: held (another solution)
        ! the check: every row of W u1 = W uf + H^T p, every contact on its mode; and whether
        ! another mode was open
        ok = .true.
        resid = 0.0_dp
        do j = 1, nd
            s = dg(j) * u1(j) + off_diagonal(u1, j) - rhs(j)
            i = coord_contact(j)
            if (i > 0) s = s - cs%h_val(cs%h_ptr(i)) * p(i)
            resid = max(resid, abs(s) / dg(j))
            if (abs(s) / dg(j) > 1.0e3_dp * MODAL_TOL * scale) ok = .false.
            if (i > 0 .and. ok) then
                hv = cs%h_val(cs%h_ptr(i))
                a = hv * (rhs(j) - off_diagonal(u1, j)) / dg(j) + b(i)
                dii = hv**2 / dg(j)
                if (mode(i) > 0) ok = laws(i)%law%admits(mode(i), -w(i), (w0(i) - a) / (dii * c(i)), p(i) / c(i))
                if (ok) then
                    call modal_local_solve(laws(i), a, dii, c(i), w0(i), mode(i), jnew, pnew, wnew, ok, other)
                    ok = .true.
                    nonunique = nonunique .or. other
                end if
            end if
            if (.not. ok) then
                worst = max(i, 1)
                return
            end if
        end do
    contains
        !> W(jj, jj-1) x(jj-1) + W(jj, jj+1) x(jj+1)
        real(dp) function off_diagonal(x, jj)
            real(dp), intent(in) :: x(:)
            integer, intent(in) :: jj
            off_diagonal = 0.0_dp
            if (jj > 1) off_diagonal = l(jj) * x(jj - 1)
            if (jj < nd) off_diagonal = off_diagonal + r(jj) * x(jj + 1)
        end function off_diagonal
    end subroutine modal_tridiagonal_sweeps

    !> One contact's problem over its law's modes, w = a + dii p, p = c mu with mu on the law's
    !! graph at v = -w (the laws' convention), decided by the rule (`modal_choose`): the stuck
    !! mode and the current one are solved first (static first, then keep a slip: the answer
    !! of most calls), every mode only where neither decides or other is asked for. A slip
    !! piece fixes mu, a point fixes w, the hold keeps w0. An open contact (c = 0) has p = 0,
    !! mode 0. other (optional): another consistent mode with another solution existed (a tie
    !! the rule broke).
    subroutine modal_local_solve(ml, a, dii, c, w0, jcur, jnew, p, w, ok, other, hold)
        type(modal_law), intent(in) :: ml        !! the contact's law (with modes)
        real(dp), intent(in)  :: a               !! velocity without this contact's impulse [m/s]
        real(dp), intent(in)  :: dii             !! w per unit impulse, > 0 [1/kg]
        real(dp), intent(in)  :: c               !! capacity h N >= 0 [N s]
        real(dp), intent(in)  :: w0              !! velocity at the step's start [m/s]
        integer, intent(in)   :: jcur            !! current mode (0: none)
        integer, intent(out)  :: jnew            !! the mode decided (0: open)
        real(dp), intent(out) :: p               !! impulse [N s]
        real(dp), intent(out) :: w               !! velocity after it [m/s]
        logical, intent(out)  :: ok              !! some mode is consistent
        logical, intent(out), optional :: other  !! another consistent solution existed
        logical, intent(in), optional :: hold    !! .true.: the current mode kept wherever it holds
        real(dp) :: mu_hold, pc, wc
        logical :: cur, adm_c
        integer :: nm
        ok = .true.
        if (present(other)) other = .false.
        jnew = 0
        p = 0.0_dp
        w = a
        if (.not. (c > 0.0_dp)) return
        nm = size(ml%kind)
        mu_hold = (w0 - a) / (dii * c)
        cur = jcur >= 1 .and. jcur <= nm .and. jcur /= ml%stick
        if (present(hold)) then
            if (hold .and. jcur >= 1 .and. jcur <= nm) then
                call mode_solution(jcur, p, w, ok)
                if (ok) then
                    jnew = jcur
                    return
                end if
            end if
        end if
        if (.not. present(other)) then
            if (ml%stick > 0) then
                call mode_solution(ml%stick, p, w, ok)
                if (ok) then                  ! static first (the current mode where it is the same point)
                    jnew = ml%stick
                    if (cur) then
                        call mode_solution(jcur, pc, wc, adm_c)
                        if (adm_c .and. wc == 0.0_dp) then
                            jnew = jcur
                            p = pc
                            w = wc
                        end if
                    end if
                    return
                end if
            end if
            if (cur) then
                call mode_solution(jcur, pc, wc, adm_c)
                if (adm_c) then               ! keep a slip
                    jnew = jcur
                    p = pc
                    w = wc
                    ok = .true.
                    return
                end if
            end if
        end if
        call every_mode(nm)
    contains
        !> Every mode solved, the rule's choice among them (`modal_choose`).
        subroutine every_mode(nmodes)
            integer, intent(in) :: nmodes
            real(dp) :: pj(nmodes), wj(nmodes)
            logical :: adm(nmodes), stick(nmodes), tie
            integer :: j
            do j = 1, nmodes
                call mode_solution(j, pj(j), wj(j), adm(j))
                stick(j) = j == ml%stick
            end do
            ok = any(adm)
            if (.not. ok) return
            call modal_choose(jcur, adm, stick, wj, 1.0e6_dp * epsilon(1.0_dp) * (abs(a) + maxval(abs(wj))), jnew, tie)
            if (present(other)) other = tie
            p = pj(jnew)
            w = wj(jnew)
        end subroutine every_mode

        !> Mode j's solution (pm, wm) and whether it lies on the mode.
        subroutine mode_solution(j, pm, wm, on)
            integer, intent(in)   :: j
            real(dp), intent(out) :: pm, wm
            logical, intent(out)  :: on
            select case (ml%kind(j))
            case (MODE_MU)
                pm = c * ml%value(j)
                wm = a + dii * pm
            case (MODE_V)
                wm = -ml%value(j)
                pm = (wm - a) / dii
            case default   ! MODE_KEEP
                wm = w0
                pm = (wm - a) / dii
            end select
            on = ml%law%admits(j, -wm, mu_hold, pm / c)
        end subroutine mode_solution
    end subroutine modal_local_solve

    !> A contact's law for the step problem over the laws' modes: a copy of law, its modes'
    !! table (`friction_law%mode`) and its stuck mode (the point v = 0 of its graph; 0: none).
    subroutine modal_law_set(ml, law)
        type(modal_law), intent(out) :: ml       !! the contact's law as the solver reads it
        class(friction_law), intent(in) :: law   !! a law with modes
        integer :: j
        allocate(ml%law, source=law)
        allocate(ml%kind(law%n_modes()), ml%value(law%n_modes()))
        ml%stick = 0
        do j = 1, law%n_modes()
            call law%mode(j, ml%kind(j), ml%value(j))
            if (ml%stick == 0 .and. ml%kind(j) == MODE_V .and. ml%value(j) == 0.0_dp) ml%stick = j
        end do
    end subroutine modal_law_set

    !> The rule of the module notes on a chain (W tridiagonal, each contact on one coordinate of
    !! its own; `tridiagonal_sweeps`' setting), O(n) a sweep: the rounds of `rule_solve`, each
    !! box problem (every contact between -c mu and c mu at its level mu) solved by the sweeps on
    !! W itself (`tridiagonal_sweeps` with Coulomb laws of mu_s = mu_k = the level). Step 1
    !! reads D_ii = h_i^2 (W^-1)_jj (the diagonal of W^-1, O(n)) and the free velocities; on
    !! a chain D is nonsingular, so the stuck impulses are unique (step 3 has nothing to choose).
    !! mode: the previous mode in (+-1 slip, 0 stuck, any other value: none), the answer's out.
    !! resid > tol: a round's sweeps did not converge (the caller solves the step otherwise).
    !! work: room reused from call to call (a step of the rule then allocates nothing).
    subroutine tridiagonal_rule(cs, l, d, r, uf, coord_contact, boff, hn, tol, max_iter, mode, u1, wloc, sweeps, &
                                resid, iworst, work)
        class(contact_system), intent(in) :: cs  !! the system (its laws and H)
        real(dp), intent(in)    :: l(:)          !! W(i, i - 1) [-]
        real(dp), intent(in)    :: d(:)          !! W(i, i) [-]
        real(dp), intent(in)    :: r(:)          !! W(i, i + 1) [-]
        real(dp), intent(in)    :: uf(:)         !! velocities without friction [m/s]
        integer, intent(in)     :: coord_contact(:)  !! the contact on each coordinate (0: none)
        real(dp), intent(in)    :: boff(:)       !! offsets of the relative velocities [m/s]
        real(dp), intent(in)    :: hn(:)         !! step times normal force of each contact [N s]
        real(dp), intent(in)    :: tol           !! tolerance on the sweeps' residual [m/s]
        integer, intent(in)     :: max_iter      !! sweep limit of a round, >= 1
        integer, intent(inout)  :: mode(:)       !! (n_c) previous mode in, the answer's out
        real(dp), intent(inout) :: u1(:)         !! velocities: starting guess in, answer out [m/s]
        real(dp), intent(out)   :: wloc(:)       !! each contact's relative velocity (0: stuck) [m/s]
        integer, intent(out)    :: sweeps        !! sweeps done over all rounds
        real(dp), intent(out)   :: resid         !! the last round's residual [m/s]
        integer, intent(out)    :: iworst        !! the coordinate with the largest residual
        type(contact_workspace), intent(inout), optional, target :: work  !! room reused between calls
        type(contact_workspace), target :: own
        type(contact_workspace), pointer :: ws
        logical :: changed
        integer :: n, nc, i, c, k, sw, rounds, sgn
        real(dp) :: hv
        n = size(d)
        nc = cs%n_c
        if (n == 1 .and. nc == 1) then
            call one_coordinate_rule(cs, d(1), uf(1), boff(1), hn(1), mode(1), u1(1), wloc(1))
            sweeps = 1
            resid = 0.0_dp
            iworst = 1
            return
        end if
        ws => own
        if (present(work)) ws => work
        if (allocated(ws%tri_dof)) then
            if (size(ws%tri_dof, 1) /= n) deallocate(ws%tri_dof)
        end if
        if (.not. allocated(ws%tri_dof)) allocate(ws%tri_dof(n, 4))
        if (allocated(ws%tri_con)) then
            if (size(ws%tri_con, 1) /= nc) deallocate(ws%tri_con, ws%tri_flag, ws%tri_dir, ws%tri_box)
        end if
        if (.not. allocated(ws%tri_con)) allocate(ws%tri_con(nc, 5), ws%tri_flag(nc, 3), ws%tri_dir(nc), &
                                                  ws%tri_box(nc))
        ! the room's columns: the pivots a, bb (the sweeps' W uf and changes in columns 3, 4); the
        ! contacts' free velocities, D_ii, levels, next levels and static limits; the flags
        associate (a => ws%tri_dof(:, 1), bb => ws%tri_dof(:, 2), wf => ws%tri_con(:, 1), dg => ws%tri_con(:, 2), &
                   mu => ws%tri_con(:, 3), mu_new => ws%tri_con(:, 4), wts => ws%tri_con(:, 5), box => ws%tri_box, &
                   kin => ws%tri_flag(:, 1), reset => ws%tri_flag(:, 2), act => ws%tri_flag(:, 3), dir => ws%tri_dir)
        act = is_active(cs%laws, hn)
        wts = cs%laws%mu_s * hn
        ! step 1: a slip kept where its free velocity still goes its way past its static limit
        ! (read only where a contact slipped before: the free velocities and D_ii)
        kin = .false.
        dir = 0
        if (any(act .and. abs(mode) == 1)) then
            ! pivots from the top (a) and from the bottom (bb): 1 / (W^-1)_ii = a_i + bb_i - d_i
            ! (the two recursions in one loop, so that their divisions overlap)
            a(1) = d(1)
            bb(n) = d(n)
            do i = 2, n
                a(i) = d(i) - l(i) * r(i - 1) / a(i - 1)
                k = n + 1 - i
                bb(k) = d(k) - r(k) * l(k + 1) / bb(k + 1)
            end do
            do i = 1, n
                c = coord_contact(i)
                if (c == 0) cycle
                hv = cs%h_val(cs%h_ptr(c))
                wf(c) = hv * uf(i) + boff(c)
                dg(c) = hv * hv / (a(i) + bb(i) - d(i))
            end do
            do c = 1, cs%n_c
                if (act(c) .and. abs(mode(c)) == 1) then
                    if (mode(c) * wf(c) > dg(c) * wts(c) * (1.0_dp + STICK_RTOL)) then
                        kin(c) = .true.
                        dir(c) = mode(c)
                    end if
                end if
            end do
        end if
        reset = .false.
        mu = cs%laws%mu_s
        where (kin) mu = cs%laws%slip_mu(max(abs(wf) - dg * wts, tiny(1.0_dp)))
        ! step 2: rounds of box problems, static first
        sweeps = 0
        do rounds = 1, 3 * cs%n_c + 30
            do c = 1, cs%n_c
                box(c) = contact_law(kind=CONTACT_COULOMB, mu_s=mu(c), mu_k=mu(c))
            end do
            call tridiagonal_sweeps(cs, l, d, r, uf, coord_contact, boff, hn, tol, max_iter, u1, wloc, sw, resid, &
                                    iworst, box, ws%tri_dof(:, 3:4))
            sweeps = sweeps + sw
            if (resid > tol) return
            changed = .false.
            mu_new = mu
            do c = 1, cs%n_c
                if (.not. act(c) .or. wloc(c) == 0.0_dp) cycle
                sgn = slip_sign(wloc(c))
                if (.not. kin(c)) then               ! gives way
                    kin(c) = .true.
                    dir(c) = sgn
                    changed = .true.
                else if (sgn /= dir(c)) then
                    if (.not. reset(c)) then         ! crossed zero: decided again from rest
                        kin(c) = .false.
                        reset(c) = .true.
                        dir(c) = 0
                        mu_new(c) = cs%laws(c)%mu_s
                        changed = .true.
                        cycle
                    end if
                    dir(c) = sgn
                end if
                mu_new(c) = cs%laws(c)%slip_mu(abs(wloc(c)))
            end do
            if (.not. changed .and. all(abs(mu_new - mu) <= 8.0_dp * epsilon(1.0_dp) * mu)) exit
            mu = mu_new
        end do
        do k = 1, cs%n_c
            mode(k) = merge(slip_sign(wloc(k)), MODE_OPEN, act(k))
        end do
        end associate
    end subroutine tridiagonal_rule

    !> `tridiagonal_rule` on one coordinate with its one contact (W = d, a 1 x 1 matrix): the
    !! rule on one contact is its closed form `local_solve` with the contact's own law (step 1
    !! keeps a slip exactly where local_solve slips; the rounds' levels converge to the slip
    !! speed that local_solve solves for), the same numbers as `solve_contacts` on the
    !! Delassus matrix D = h^2 / d and moreau's u1 = u_free + W^-1 H^T p there (a stuck
    !! contact's velocity set so that w = 0 exactly), without the rounds' sweeps.
    subroutine one_coordinate_rule(cs, d, uf, boff, hn, mode, u1, wloc)
        class(contact_system), intent(in) :: cs  !! the system (one contact on coordinate 1)
        real(dp), intent(in)    :: d             !! W(1, 1) [kg]
        real(dp), intent(in)    :: uf            !! velocity without friction [m/s]
        real(dp), intent(in)    :: boff          !! offset of the relative velocity [m/s]
        real(dp), intent(in)    :: hn            !! step times normal force [N s]
        integer, intent(inout)  :: mode          !! the answer's mode (+-1 slip, 0 stuck, open)
        real(dp), intent(out)   :: u1            !! velocity after the step [m/s]
        real(dp), intent(out)   :: wloc          !! relative velocity (0: stuck) [m/s]
        real(dp) :: hv, p
        hv = cs%h_val(cs%h_ptr(1))
        call local_solve(cs%laws(1), hv * uf + boff, hv * (hv / d), hn, wloc, p)
        if (wloc == 0.0_dp) then
            u1 = -boff / hv
        else
            u1 = uf + hv * p / d
        end if
        mode = merge(slip_sign(wloc), MODE_OPEN, is_active(cs%laws(1), hn))
    end subroutine one_coordinate_rule

    !> Room for n numbers in buf (kept where there is enough).
    subroutine reserve(buf, n)
        real(dp), allocatable, intent(inout) :: buf(:)
        integer, intent(in) :: n
        if (allocated(buf)) then
            if (size(buf) >= n) return
            deallocate(buf)
        end if
        allocate(buf(n))
    end subroutine reserve

end module stickslip_contact_solver
