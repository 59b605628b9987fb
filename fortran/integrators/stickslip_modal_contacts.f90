!> Backward Euler steps of a system with several frictional contacts whose laws jump
!! (`friction_law%n_modes` > 0: Coulomb with its v_s band, Karnopp), each step solved over the
!! laws' modes contact by contact. What `implicit_euler` and `galpha` run on such a system (the
!! chain with Coulomb or Karnopp); one contact keeps their own nonsmooth path
!! (stickslip_fixed_implicit), whose step this one equals for a single contact up to the
!! linearisation of the smooth forces.
!!
!! What it solves. The system is a `contact_system` (q, u; M u' = f(t, q, u) + H^T r) and each
!! contact i has its own friction law with modes; its friction force is r_i = N_i mu_i with mu_i
!! on the law's graph at the relative velocity v_i = -w_i (the laws' convention: the velocity of
!! the surface relative to the body, w = H u + b the body's relative to the surface). A step of
!! size h from (q, u) is the linearly implicit backward Euler step
!!   (M + h C + h^2 K) (u1 - u) = h f(t1, q + h u, u) + H^T p,   q1 = q + h u1,
!! (K = -df/dq, C = -df/du at the step's start: one Newton iteration on the smooth forces, exact
!! for a linear system such as the chain), with the impulses p_i = h N_i mu_i and mu_i on the
!! law's graph at v_i(t1): the catching-up scheme of the one-contact path, on all contacts
!! at once. The relative velocities after the impulses are w = wf + D p with D = H W^-1 H^T.
!! For Coulomb the graph is the smooth law's with its jumps filled in: mu_s (not mu_k) for
!! 0 < |v| < v_s, the point v_s where mu may take any value between mu_k and mu_s, stick at
!! v = 0 with |mu| <= mu_s. So this is not moreau with theta = 1 (which has no band): the two
!! differ where a contact slips slower than v_s, and agree as v_s -> 0.
!!
!! How. The step problem is solved by the contact module (`stickslip_contact_solver`, its
!! section on the laws' modes), the one that solves every nonsmooth method's contacts, with its
!! rule for several solutions: keep a slip (the current slip mode, where it still holds and
!! the contact cannot stick), else static first (the consistent mode whose velocity is nearest
!! zero), contact by contact in nonsmooth Gauss-Seidel sweeps (`solve_modal_contacts` on the
!! dense D, n_c solves with W a step; `modal_tridiagonal_sweeps` on W u1 = W u_free + H^T p
!! itself where W is tridiagonal and each contact lies on one coordinate of its own, the
!! chain, O(n) a sweep). A step whose sweeps do not converge or whose answer fails the check
!! ends the run with SS_CONTACT_FAILED, the step's time in t_reached and the contact in
!! contact_worst; a step where some contact had another consistent mode is counted in
!! stats%nonunique. Stuck contacts of one coordinate keep their relative velocity exactly.
!!
!! Generalized-alpha within slip phases. Where every contact is on a slip piece of its law
!! (MODE_MU: mu_i fixed) the system is smooth, and galpha takes its own step instead (par =
!! its alpha_m, alpha_f, gamma): the stage k = F(tau, U + ch k) of `stickslip_galpha` with
!! F(t, q, u) = (u, M^-1 (f(t, q, u) + H^T r)), r_i = N_i mu_i, solved as the backward Euler
!! step above is, linearly implicit: W = M + ch C + ch^2 K at the step's start, forces and
!! normal forces at the stage's base point (exact for linear forces, as the chain's; otherwise
!! one Newton iteration, whose O(h^2) error in k keeps second order). The step is kept if every
!! contact stays on its piece at the stage and at the step's end (`admits`) and none could
!! stick in the backward Euler step with the pieces' impulses (`may_stick`, a screen by
!! H_i M^-1 H_i^T: the rule's static first, where h N (mu_s - mu_k) / m exceeds v_s); otherwise the
!! step is the backward Euler step over the modes, and galpha's derivative restarts from that
!! step's stage derivative (u1, (u1 - u) / h), as on one contact (stickslip_fixed_implicit).
!!
!! Order: implicit_euler first. galpha second within a slip phase that no transition
!! interrupts (its first step from the initial state, whose modes are not yet known, is a
!! backward Euler step: one local error of O(h^2)), and first across transitions (the
!! backward Euler steps there), as on one contact.
module stickslip_modal_contacts
    use stickslip_kinds, only: dp, SS_OK, SS_NONFINITE, SS_OUTPUT_FULL, SS_STEP_BUDGET, SS_INTERRUPTED, &
                               SS_CONTACT_FAILED, SS_JUMP_MANY_CONTACTS
    use stickslip_ode, only: count_nonunique
    use stickslip_ode, only: ode_stats, step_controls, output_start, fixed_steps, step_end, stop_requested, all_finite, &
                             diverged, linear_output
    use stickslip_friction, only: MODE_MU
    use stickslip_contact, only: contact_system
    use stickslip_contact_solver, only: modal_law, modal_law_set, solve_modal_contacts, modal_tridiagonal_sweeps
    use stickslip_model_system, only: model_system
    implicit none
    private

    public :: modal_law, modal_contacts_integrate, model_modal_contacts

contains

    !> Backward Euler steps over the contacts' modes (module notes) from y0 = (q0, u0) to
    !! t_end on the grid of ctl%h (the last step ends at t_end exactly). Output at t_out by
    !! linear interpolation between steps (or every step with ctl%every_step). stats: nstep,
    !! naccept, nfev (2 force evaluations a step), ncontact_iter (sweeps), contact_residual,
    !! contact_worst; status SS_OK, SS_CONTACT_FAILED, SS_NONFINITE, SS_DIVERGED,
    !! SS_OUTPUT_FULL, SS_STEP_BUDGET or SS_INTERRUPTED (the input is checked by the caller).
    subroutine modal_contacts_integrate(cs, laws, t0, y0, t_end, ctl, t_out, y_out, stats, par)
        class(contact_system), intent(inout) :: cs   !! the system
        type(modal_law), intent(in) :: laws(:)       !! (n_c) each contact's law, with modes
        real(dp), intent(in)    :: t0                !! initial time [s]
        real(dp), intent(in)    :: y0(:)             !! initial state (q0, u0)
        real(dp), intent(in)    :: t_end             !! final time, > t0 [s]
        class(step_controls), intent(in) :: ctl      !! h, max_steps, every_step, y_bound
        real(dp), intent(inout) :: t_out(:)          !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)       !! (size(y0), size(t_out)) states
        type(ode_stats), intent(inout) :: stats      !! counters and status
        real(dp), intent(in), optional :: par(:)     !! galpha's alpha_m, alpha_f, gamma [-], or none

        real(dp), allocatable :: q(:), u(:), qp(:), f1(:), du(:), g(:), y(:), y1(:), ydot(:)
        real(dp), allocatable :: wf(:), w0(:), p(:), c(:), d(:, :), w(:), b(:), wl(:), wd(:), wr(:)
        real(dp), allocatable :: dm(:)     ! (n_c) H_i M^-1 H_i^T [1/kg] (galpha's stick screen)
        integer, allocatable :: mode(:), coord_contact(:)
        real(dp) :: t, t1, hs, t_next, resid
        integer(8) :: i, nsteps, n_total
        integer :: nd, nc, m, next, j, k, sweeps
        logical :: ok, tri, galpha, kept, other

        nd = cs%n_dof
        galpha = .false.
        if (present(par)) galpha = size(par) == 3
        allocate(ydot(2 * cs%n_dof))
        nc = cs%n_c
        allocate(q(nd), u(nd), qp(nd), f1(nd), du(nd), g(nd), y(2 * nd), y1(2 * nd))
        allocate(wf(nc), w0(nc), p(nc), c(nc), w(nc), b(nc), mode(nc), wl(nd), wd(nd), wr(nd))
        mode = 0    ! none yet
        ! W tridiagonal and each contact on one coordinate of its own (the chain): the sweeps on
        ! W itself, O(n) each; otherwise on the dense Delassus matrix
        allocate(coord_contact(nd))
        call cs%step_layout(ctl%h, ctl%h**2, wl, wd, wr, coord_contact, tri, d)
        m = size(t_out)
        call fixed_steps(t0, t_end, ctl%h, ctl%max_steps, n_total, nsteps)
        y = y0
        q = y0(:nd)
        u = y0(nd + 1:)
        t = t0
        p = 0.0_dp
        if (galpha) then
            allocate(dm(nc))
            do j = 1, nc
                w = 0.0_dp
                w(j) = 1.0_dp
                g = 0.0_dp
                call cs%add_ht(w, g)
                call cs%solve_w(t, q, u, 0.0_dp, 0.0_dp, g)
                call cs%apply_h(g, w)
                dm(j) = w(j)
            end do
        end if
        call output_start(t0, y0, t_out, y_out, ctl%every_step, next)
        t_next = huge(1.0_dp)
        if (.not. ctl%every_step .and. next <= m) t_next = t_out(next)

        do i = 1, nsteps
            if (stop_requested(ctl, stats%nstep)) then
                stats%status = SS_INTERRUPTED
                exit
            end if
            t1 = step_end(t0, t_end, ctl%h, i, n_total)
            hs = t1 - t
            stats%nstep = stats%nstep + 1
            stats%h_last = hs

            kept = .false.
            if (galpha) kept = galpha_slip_step()
            if (.not. kept) then
                ! the free step, with W = M + h C + h^2 K at the step's start
                qp = q + hs * u
                call cs%force(t1, qp, u, f1)
                stats%nfev = stats%nfev + 2
                du = hs * f1
                call cs%solve_w(t, q, u, hs, hs**2, du)
                du = u + du
                call cs%relative_velocities(t, u, w0)
                call cs%normal_forces(t1, qp, c)
                c = hs * c
                call cs%slip_offset(t1, b)
                if (tri) then
                    call cs%w_tridiagonal(hs, hs**2, wl, wd, wr, ok)   ! (structural: still tridiagonal)
                    call modal_tridiagonal_sweeps(laws, cs, wl, wd, wr, du, coord_contact, b, c, w0, g, p, w, &
                                                  mode, sweeps, ok, k, resid, other)
                else
                    call cs%relative_velocities(t1, du, wf)
                    call cs%delassus(t, q, u, hs, hs**2, d)
                    call solve_modal_contacts(laws, d, wf, w0, c, p, w, mode, sweeps, ok, k, resid, other)
                end if
                stats%ncontact_iter = stats%ncontact_iter + sweeps
                if (ok .and. other) call count_nonunique(stats, t1)
                stats%contact_residual = max(stats%contact_residual, resid)
                if (.not. ok) then
                    stats%status = SS_CONTACT_FAILED
                    stats%contact_worst = k
                    exit
                end if
                if (.not. tri) then
                    g = 0.0_dp
                    call cs%add_ht(p, g)
                    call cs%solve_w(t, q, u, hs, hs**2, g)
                    g = du + g
                    ! a contact of one coordinate whose mode fixes its velocity keeps it exactly
                    do j = 1, nc
                        k = cs%h_ptr(j)
                        if (cs%h_ptr(j + 1) - k == 1 .and. fixes_velocity(laws(j), mode(j))) &
                            g(cs%h_col(k)) = (w(j) - b(j)) / cs%h_val(k)
                    end do
                end if
                y1(:nd) = q + hs * g
                y1(nd + 1:) = g
                ydot(:nd) = g                   ! the stage derivative (galpha restarts from it)
                ydot(nd + 1:) = (g - u) / hs
            end if
            if (.not. all_finite(y1)) then
                stats%status = SS_NONFINITE
                exit
            end if
            if (diverged(y1, stats, ctl%y_bound)) exit
            call linear_output(t, y, t1, y1, ctl%every_step, t_out, y_out, next, t_next, stats%status)
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

        !> Generalized-alpha's own step from (t, y) to t1 where every contact slips on a piece
        !! of its law (module notes): .true. with y1 and ydot updated if every contact stays on
        !! its piece at the stage and at the step's end and none could stick in the backward
        !! Euler step (`may_stick`: static first, as the rule); .false. (nothing changed) otherwise.
        logical function galpha_slip_step() result(kept)
            real(dp) :: tau, ch, mu(nc), yu(2 * nd), k(2 * nd), ydot1(2 * nd)
            integer :: kind, jj
            kept = .false.
            do jj = 1, nc
                if (mode(jj) < 1) return
                call laws(jj)%law%mode(mode(jj), kind, mu(jj))
                if (kind /= MODE_MU) return
            end do
            associate (alpha_m => par(1), alpha_f => par(2), gamma => par(3))
                ! the stage k = F(tau, yu + ch k), linearly implicit about (qp, u) = yu + ch (yu_u, 0)
                tau = t + alpha_f * hs
                yu = y + (alpha_f * hs * (1.0_dp - gamma / alpha_m)) * ydot
                ch = alpha_f * gamma / alpha_m * hs
                qp = yu(:nd) + ch * yu(nd + 1:)
                call cs%force(tau, qp, yu(nd + 1:), f1)
                call cs%normal_forces(tau, qp, c)
                stats%nfev = stats%nfev + 1
                call cs%add_ht(c * mu, f1)
                call cs%solve_w(t, q, u, ch, ch**2, f1)
                k(nd + 1:) = f1
                k(:nd) = yu(nd + 1:) + ch * f1
                yu = yu + ch * k                                ! the stage state
                if (.not. on_pieces(tau, yu(nd + 1:))) return
                ydot1 = ydot + (k - ydot) / alpha_m
                y1 = y + hs * ydot + (gamma * hs) * (ydot1 - ydot)
            end associate
            if (.not. on_pieces(t1, y1(nd + 1:))) return
            if (may_stick(mu)) return
            ydot = ydot1
            kept = .true.
        end function galpha_slip_step

        !> Whether some contact could stick in the backward Euler step from (t, y) with every
        !! contact at its piece's coefficient mu (its impulse h N mu): contact i, given the
        !! others, sticks where |w_i| <= D_ii (mu_s,i - |mu_i|) h N_i at the velocities w after
        !! that step; screened with H_i M^-1 H_i^T >= D_ii (W = M + h C + h^2 K >= M for
        !! positive semidefinite C and K, as a model's dampers and springs), so that a step
        !! it passes is decided by the rule (the backward Euler step over the modes).
        logical function may_stick(mu)
            real(dp), intent(in) :: mu(:)    !! (n_c) each contact's coefficient [-]
            real(dp) :: qq(nd), cc(nc), wb(nc), gb(nd), mus(nc)
            integer :: jj
            qq = q + hs * u
            call cs%force(t1, qq, u, gb)
            call cs%normal_forces(t1, qq, cc)
            stats%nfev = stats%nfev + 1
            cc = hs * cc
            gb = hs * gb
            call cs%add_ht(cc * mu, gb)
            call cs%solve_w(t, q, u, hs, hs**2, gb)
            gb = u + gb
            call cs%relative_velocities(t1, gb, wb)
            do jj = 1, nc
                mus(jj) = laws(jj)%law%mu_s
            end do
            may_stick = any(cc > 0.0_dp .and. abs(wb) <= dm * (mus - abs(mu)) * cc * (1.0_dp + 1.0e-9_dp))
        end function may_stick

        !> Every contact on its slip piece (mode) at velocities uu at time tt.
        logical function on_pieces(tt, uu)
            real(dp), intent(in) :: tt, uu(:)
            integer :: jj, kind
            real(dp) :: value
            call cs%relative_velocities(tt, uu, w)
            on_pieces = .false.
            do jj = 1, nc
                call laws(jj)%law%mode(mode(jj), kind, value)
                if (.not. laws(jj)%law%admits(mode(jj), -w(jj), value, value)) return
            end do
            on_pieces = .true.
        end function on_pieces
    end subroutine modal_contacts_integrate

    !> A user's model (`stickslip_model_system`) whose contacts' laws jump, run by
    !! `modal_contacts_integrate` on its contact model with each contact's own law. Every law
    !! must have modes (a model mixing jump laws with smooth ones ends with
    !! SS_JUMP_MANY_CONTACTS: its smooth laws would need the Newton path); laws with internal
    !! states are not among the laws with modes. The laws read the model's slip s = -w, the
    !! opposite of the convention here, which for these odd laws gives the same force.
    subroutine model_modal_contacts(sys, t0, y0, t_end, ctl, par, t_out, y_out, stats)
        class(model_system), intent(inout) :: sys    !! the model; some law has modes
        real(dp), intent(in)    :: t0                !! initial time [s]
        real(dp), intent(in)    :: y0(:)             !! initial state (x, v)
        real(dp), intent(in)    :: t_end             !! final time, > t0 [s]
        class(step_controls), intent(in) :: ctl      !! h, max_steps, every_step, y_bound
        real(dp), intent(in)    :: par(:)            !! the method's parameters (galpha's: module notes)
        real(dp), intent(inout) :: t_out(:)          !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)       !! (size(y0), size(t_out)) states
        type(ode_stats), intent(out) :: stats        !! counters and status
        class(contact_system), allocatable :: cs
        type(modal_law), allocatable :: laws(:)
        integer :: status, i
        call sys%contact_model(cs, status)   ! (status: the set-valued counterparts, not needed)
        if (allocated(cs)) then
            allocate(laws(cs%n_c))
            do i = 1, cs%n_c
                if (sys%laws(i)%law%n_modes() > 0) call modal_law_set(laws(i), sys%laws(i)%law)
            end do
        end if
        call run_modal(cs, laws, t0, y0, t_end, ctl, par, t_out, y_out, stats)
    end subroutine model_modal_contacts

    !> `modal_contacts_integrate` on a system's contact model and its laws, or
    !! SS_JUMP_MANY_CONTACTS when there is no model, a contact has no law with modes, or y0 is
    !! not the model's (q, u).
    subroutine run_modal(cs, laws, t0, y0, t_end, ctl, par, t_out, y_out, stats)
        class(contact_system), allocatable, intent(inout) :: cs  !! the contact model (if any)
        type(modal_law), allocatable, intent(in) :: laws(:)      !! each contact's law with modes
        real(dp), intent(in)    :: t0                !! initial time [s]
        real(dp), intent(in)    :: y0(:)             !! initial state (q, u)
        real(dp), intent(in)    :: t_end             !! final time, > t0 [s]
        class(step_controls), intent(in) :: ctl      !! h, max_steps, every_step, y_bound
        real(dp), intent(in)    :: par(:)            !! the method's parameters (galpha's: module notes)
        real(dp), intent(inout) :: t_out(:)          !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)       !! (size(y0), size(t_out)) states
        type(ode_stats), intent(out) :: stats        !! counters and status
        integer :: i
        stats%status = SS_JUMP_MANY_CONTACTS
        if (.not. (allocated(cs) .and. allocated(laws))) return
        if (size(y0) /= 2 * cs%n_dof) return
        do i = 1, size(laws)
            if (.not. allocated(laws(i)%law)) return
        end do
        stats%status = SS_OK
        call modal_contacts_integrate(cs, laws, t0, y0, t_end, ctl, t_out, y_out, stats, par)
    end subroutine run_modal

    !> Whether mode j of a contact's law fixes its relative velocity (a point, or the hold).
    logical function fixes_velocity(ml, j)
        type(modal_law), intent(in) :: ml
        integer, intent(in) :: j
        integer :: kind
        real(dp) :: value
        fixes_velocity = .false.
        if (j < 1) return
        call ml%law%mode(j, kind, value)
        fixes_velocity = kind /= MODE_MU
    end function fixes_velocity

end module stickslip_modal_contacts
