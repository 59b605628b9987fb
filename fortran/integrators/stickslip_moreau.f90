!> Moreau-Jean time-stepping (velocity level, theta-method) for a system with set-valued
!! friction (`stickslip_contact`). Fixed step h; each step solves its friction problem
!! exactly, so a contact that should stick has relative velocity 0 and does not creep.
!!
!! One step from (t, q, u) to t1 = t + h, with f the non-friction forces:
!!   W (u1 - u) = h [(1 - theta) f(t, q, u) + theta f(t1, q + h u, u)] + H^T p
!!   q1 = q + h [(1 - theta) u + theta u1]
!! with W = M + h theta C + (h theta)^2 K (C = -df/du, K = -df/dq; `solve_w`) and the
!! friction impulses p (one per contact, [N s]) from the set-valued law at the end of the
!! step: p_i in -h N_i F_i(w_i), w = H u1 + b(t1), with N_i at (t1, q + h u). For a linear f this is exactly the
!! theta-method; otherwise it is its linearly implicit form (one Newton iteration).
!!
!! The friction problem w = w_free + D p, D = H W^-1 H^T (the Delassus matrix, n_c x n_c),
!! is solved by `stickslip_contact_solver` (`solve_contacts`): one contact in closed form
!! (`local_solve`), more by its rule for problems with several solutions (a slip kept while
!! its free velocity goes its way, static first, minimum-norm impulses; the solver's notes),
!! at a cost polynomial in n_c. The previous step's modes are the rule's previous mode (the
!! first step's: each contact's initial relative velocity, slipping where it moves); a step
!! whose problem had another solution with as many stuck contacts is counted in
!! stats%nonunique. Every answer is checked against the step's problem: a residual above
!! contact_tol [m/s] (or the rounding of the problem's own numbers, where larger) ends the
!! run with SS_CONTACT_FAILED, the step's time in t_reached and the worst contact in
!! contact_worst. When `w_constant` is set, D is formed once per step size (n_c solves with
!! W), otherwise every step. Dense D: fine for a few hundred contacts.
!!
!! When W is tridiagonal (`w_tridiagonal`, e.g. a chain of blocks) and every contact acts on
!! one coordinate of its own, the same problem is solved on W itself by the same rule
!! (`tridiagonal_rule` of `stickslip_contact_solver`): the rule's rounds, each box problem by
!! sweeps on W u1 = W u_free + H^T p, coordinate by coordinate, each contact's one-contact
!! problem in closed form at its level given its neighbours' velocities (nonsmooth
!! Gauss-Seidel; W is symmetric positive definite, so the sweeps converge). A sweep costs O(n)
!! instead of O(n_c^2), and D is never formed. Its residual is the same quantity: the largest change that a sweep's
!! later update of coordinate i + 1 makes to coordinate i's velocity, |W(i, i+1) du_{i+1} /
!! W(i, i)| [m/s], enlarged where the sweeps contract slowly to the distance to the answer it
!! leaves. A step whose sweeps do not reach contact_tol within contact_max_iter in a round (W
!! ill-conditioned: two blocks joined by a spring with k h^2 >> m, a mass ratio of 1e-9) is
!! solved again by `solve_contacts` on D, formed for it (up to DENSE_FALLBACK_MAX contacts).
!!
!! A stuck contact whose row of H has a single entry has its coordinate's velocity set so
!! that w = 0 exactly (the solve gives it to rounding otherwise).
!!
!! theta: 1/2 is the default. In slip the scheme is then the trapezoidal rule, second order
!! and free of numerical damping, so the spring-mass oscillation of a slip phase keeps its
!! amplitude; theta = 1 (backward Euler) damps its amplitude by 1/sqrt(1 + (h w)^2) a step
!! (its energy by the square of that), which
!! shortens the slip phases of the stick-slip cycle. At a stick-slip transition every theta
!! is first order in position (the transition falls inside a step). theta > 1/2 adds
!! dissipation where an energy-growing system needs it.
!!
!! Output: in grid mode linear interpolation between steps (q is piecewise linear in time
!! in the scheme), in every-step mode the steps themselves. The state is y = (q, u).
module stickslip_moreau
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_H, SS_BAD_MAX_STEPS, SS_BAD_DIM, SS_NONFINITE, &
                               SS_OUTPUT_FULL, SS_STEP_BUDGET, SS_INTERRUPTED, SS_BAD_THETA_MJ, &
                               SS_BAD_CONTACT_CTL, SS_CONTACT_FAILED
    use stickslip_ode, only: ode_stats, step_controls, method_info, check_problem, output_start, &
                             fixed_steps, step_end, stop_requested, all_finite
    use stickslip_contact, only: contact_system
    use stickslip_contact_solver, only: solve_contacts, contact_solve_info, contact_workspace, tridiagonal_rule
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use stickslip_ode, only: diverged, linear_output, count_nonunique
    implicit none
    private

    public :: moreau_options, moreau_integrate

    !> Most contacts for which a step whose tridiagonal sweeps do not converge is solved again
    !! on the dense Delassus matrix (n_c^2 numbers); beyond, the step fails (SS_CONTACT_FAILED).
    integer, parameter, public :: DENSE_FALLBACK_MAX = 2000

    !> What the Moreau-Jean method is and which controls it reads (registry entry).
    type(method_info), parameter, public :: MOREAU_INFO = method_info(name='moreau', order=1, &
        adaptive=.false., implicit=.true., controls='h theta contact_tol contact_max_iter max_steps every_step', &
        doc='Moreau-Jean theta time-stepping, set-valued friction', laws='coulomb stribeck karnopp')

    !> Controls of the Moreau-Jean method: h, max_steps, every_step (shared) and its own.
    type, extends(step_controls) :: moreau_options
        real(dp) :: theta = 0.5_dp          !! theta of the theta-method, in [1/2, 1] [-]
        real(dp) :: contact_tol = 1.0e-12_dp  !! tolerance of the contact solve [m/s]
        integer  :: contact_max_iter = 1000   !! Gauss-Seidel sweeps per box problem on a chain (W tridiagonal), >= 1
    contains
        procedure :: set => set_moreau_option
        !! set a control by name (the step_controls ones and the method's own)
    end type moreau_options

contains

    function set_moreau_option(self, name, value) result(status)
        class(moreau_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts as reals)
        integer :: status
        status = SS_OK
        select case (name)
        case ('theta');       self%theta = value
        case ('contact_tol'); self%contact_tol = value
        case ('contact_max_iter')
            if (value >= 1.0_dp .and. value <= real(huge(1), dp) .and. value == aint(value)) then
                self%contact_max_iter = int(value)
            else
                status = SS_BAD_CONTACT_CTL
            end if
        case default;         status = self%step_controls%set(name, value)
        end select
    end function set_moreau_option

    !> Integrate M u' = f + H^T r, q' = u with set-valued friction from t0 to t_end.
    !! y0 = (q0, u0) of size 2 n_dof. Output as for the other fixed-step methods.
    !! stats: nfev counts force evaluations (2 a step), ncontact_iter the contact sweeps (or
    !! the contact solver's linear solves), nonunique the steps whose problem had another
    !! solution with as many stuck contacts, contact_residual the largest final residual of a
    !! step [m/s],
    !! contact_worst the contact whose residual failed (SS_CONTACT_FAILED). Status: SS_OK,
    !! SS_CONTACT_FAILED, SS_NONFINITE, SS_OUTPUT_FULL, SS_STEP_BUDGET,
    !! SS_INTERRUPTED or a bad-input code.
    subroutine moreau_integrate(cs, t0, y0, t_end, opts, t_out, y_out, stats)
        class(contact_system), intent(inout) :: cs   !! the system
        real(dp), intent(in)    :: t0            !! initial time [s]
        real(dp), intent(in)    :: y0(:)         !! initial state (q0, u0)
        real(dp), intent(in)    :: t_end         !! final time, > t0 [s]
        type(moreau_options), intent(in) :: opts !! controls
        real(dp), intent(inout) :: t_out(:)      !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! (size(y0), size(t_out)) states
        type(ode_stats), intent(out) :: stats    !! counters and status

        real(dp), allocatable :: q(:), u(:), qp(:), f0(:), f1(:), du(:), g(:), y1(:), y(:)
        real(dp), allocatable :: wfree(:), p(:), hn(:), dmat(:, :), wloc(:)
        real(dp), allocatable :: wl(:), wd(:), wr(:), boff(:)
        integer, allocatable :: coord_contact(:), cmode(:)
        type(contact_solve_info) :: cinfo
        type(contact_workspace) :: cwork   ! the contact solver's room, reused from step to step
        logical :: tri, dense
        real(dp) :: t, t1, hs, th, h_d, h_w, resid, t_next
        integer(8) :: i, nsteps, n_total
        integer :: nd, nc, m, next, sweeps, c, k, iworst

        stats%status = check_problem(t0, y0, t_end, t_out, y_out, opts%every_step)
        if (stats%status /= SS_OK) return
        nd = cs%n_dof
        nc = cs%n_c
        if (size(y0) /= 2 * nd) then
            stats%status = SS_BAD_DIM
        else if (.not. ieee_is_finite(opts%h) .or. opts%h <= 0.0_dp) then
            stats%status = SS_BAD_H
        else if (.not. (opts%theta >= 0.5_dp .and. opts%theta <= 1.0_dp)) then
            stats%status = SS_BAD_THETA_MJ
        else if (.not. (ieee_is_finite(opts%contact_tol) .and. opts%contact_tol > 0.0_dp) .or. &
                 opts%contact_max_iter < 1) then
            stats%status = SS_BAD_CONTACT_CTL
        else if (opts%max_steps < 1) then
            stats%status = SS_BAD_MAX_STEPS
        end if
        if (stats%status /= SS_OK) return

        allocate(q(nd), u(nd), qp(nd), f0(nd), f1(nd), du(nd), g(nd), y(2 * nd), y1(2 * nd))
        th = opts%theta
        allocate(wfree(nc), p(nc), hn(nc), wloc(nc), wl(nd), wd(nd), wr(nd), boff(nc), coord_contact(nd))
        ! the previous mode of the first step: each contact's from its initial relative velocity
        ! (slipping where it moves, stuck where it rests: the contact solver's rule, step 1)
        allocate(cmode(nc))
        call cs%relative_velocities(t0, y0(nd + 1:), wloc)
        cmode = merge(0, nint(sign(1.0_dp, wloc)), wloc == 0.0_dp)
        call cs%step_layout(opts%h * th, (opts%h * th)**2, wl, wd, wr, coord_contact, tri, dmat)
        m = size(t_out)
        call fixed_steps(t0, t_end, opts%h, opts%max_steps, n_total, nsteps)

        y = y0
        q = y0(:nd)
        u = y0(nd + 1:)
        t = t0
        p = 0.0_dp
        h_d = -1.0_dp      ! step size D was formed for (none yet)
        h_w = -1.0_dp      ! step size W's diagonals were formed for (none yet)
        call output_start(t0, y0, t_out, y_out, opts%every_step, next)
        t_next = huge(1.0_dp)
        if (.not. opts%every_step .and. next <= m) t_next = t_out(next)

        do i = 1, nsteps
            if (stop_requested(opts, i)) then
                stats%status = SS_INTERRUPTED
                exit
            end if
            t1 = step_end(t0, t_end, opts%h, i, n_total)
            hs = t1 - t
            stats%nstep = stats%nstep + 1
            stats%h_last = hs

            ! The free step: no friction.
            call cs%force(t, q, u, f0)
            qp = q + hs * u
            call cs%force(t1, qp, u, f1)
            stats%nfev = stats%nfev + 2
            du = hs * ((1.0_dp - th) * f0 + th * f1)
            call cs%solve_w(t, q, u, hs * th, (hs * th)**2, du)
            du = u + du
            call cs%relative_velocities(t1, du, wfree)

            ! The friction problem, with D formed where it may have changed.
            call cs%normal_forces(t1, qp, hn)
            hn = hs * hn
            dense = .not. tri
            if (tri) then   ! on W itself: u1 from W u1 = W u_free + H^T p
                if (hs /= h_w) then     ! W's diagonals: once per step size
                    call cs%w_tridiagonal(hs * th, (hs * th)**2, wl, wd, wr, tri)
                    h_w = hs
                end if
                call cs%slip_offset(t1, boff)
                g = u
                call tridiagonal_rule(cs, wl, wd, wr, du, coord_contact, boff, hn, opts%contact_tol, &
                                      opts%contact_max_iter, cmode, g, wloc, sweeps, resid, iworst, work=cwork)
                stats%ncontact_iter = stats%ncontact_iter + sweeps
                if (resid <= opts%contact_tol) then
                    stats%contact_residual = max(stats%contact_residual, resid)
                    y1(:nd) = q + hs * ((1.0_dp - th) * u + th * g)
                    y1(nd + 1:) = g
                else if (nc <= DENSE_FALLBACK_MAX) then
                    ! the sweeps did not converge (W ill-conditioned: a stiff spring, a tiny mass):
                    ! this step by the contact solver on the Delassus matrix, formed for it
                    dense = .true.
                    if (size(dmat, 1) /= nc) then
                        deallocate(dmat)
                        allocate(dmat(nc, nc))
                        h_d = -1.0_dp
                    end if
                else
                    stats%contact_worst = coord_contact(iworst)
                    stats%contact_residual = max(stats%contact_residual, resid)
                end if
            end if
            if (dense) then
                if (.not. (cs%w_constant .and. hs == h_d)) then
                    call cs%delassus(t, q, u, hs * th, (hs * th)**2, dmat)
                    h_d = hs
                end if
                call solve_contacts(cs%laws, dmat, wfree, hn, .false., opts%contact_tol, opts%contact_max_iter, &
                                    p, wloc, cmode, cinfo, work=cwork)
                stats%ncontact_iter = stats%ncontact_iter + cinfo%sweeps
                if (cinfo%nonunique) call count_nonunique(stats, t1)
                stats%contact_residual = max(stats%contact_residual, cinfo%residual)
                resid = 0.0_dp
                if (.not. cinfo%ok) then
                    resid = huge(1.0_dp)
                    stats%contact_worst = cinfo%worst
                end if

                ! u1 = u_free + W^-1 H^T p, and the exact stick of single-coordinate contacts.
                g = 0.0_dp
                call cs%add_ht(p, g)
                call cs%solve_w(t, q, u, hs * th, (hs * th)**2, g)
                g = du + g
                call snap_stuck(g)
                y1(:nd) = q + hs * ((1.0_dp - th) * u + th * g)
                y1(nd + 1:) = g
            end if

            if (.not. all_finite(y1)) then
                stats%status = SS_NONFINITE
                exit
            end if
            if (resid > opts%contact_tol) then
                stats%status = SS_CONTACT_FAILED
                exit
            end if
            if (diverged(y1, stats, opts%y_bound)) exit   ! left the system's bound: SS_DIVERGED
            call linear_output(t, y, t1, y1, opts%every_step, t_out, y_out, next, t_next, stats%status)
            if (stats%status /= SS_OK) exit
            stats%naccept = stats%naccept + 1
            y = y1
            q = y1(:nd)
            u = y1(nd + 1:)
            t = t1
        end do
        stats%t_reached = t
        stats%n_written = next - 1
        if (stats%status == SS_OK .and. nsteps < n_total) stats%status = SS_STEP_BUDGET

    contains

        !> Velocities ui of stuck contacts (their one-contact solve gave w = 0) with a single
        !! entry in H: w = 0 exactly.
        subroutine snap_stuck(ui)
            real(dp), intent(inout) :: ui(:)
            real(dp) :: b(nc)
            call cs%slip_offset(t1, b)
            do c = 1, nc
                k = cs%h_ptr(c)
                if (cs%h_ptr(c + 1) - k == 1 .and. wloc(c) == 0.0_dp) ui(cs%h_col(k)) = -b(c) / cs%h_val(k)
            end do
        end subroutine snap_stuck

    end subroutine moreau_integrate

end module stickslip_moreau
