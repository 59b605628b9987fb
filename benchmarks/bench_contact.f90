!> The per-step contact solver (`stickslip_contact_solver`) on random coupled problems, against
!! projected Gauss-Seidel alone and the solver's rule with every box problem by Lemke's method
!! alone (SOLVER_PIVOTING) on the same problems. For each number of contacts n: problems
!! w = wf + D p with D = H W^-1 H^T (H: rows of one or two +-1 entries over n/2 + 1 coordinates,
!! so contacts are coupled; W symmetric positive definite), Coulomb laws with mu_s >= mu_k, and
!! capacities scaled like a step of 1 ms. Prints one line per n:
!!   n  us_per_solve  solved_fraction  gs_us_per_solve  gs_solved_fraction  linear_solves
!!   fallback_fraction  piv_us_per_solve  piv_solved_fraction  pivots
!! (linear_solves: the solver's a problem; fallback_fraction: problems where a box problem needed
!! Lemke's fallback; pivots: Lemke pivots a solve of Lemke alone)
!! (microseconds a solve, the median of `repeats` passes over the problems; Gauss-Seidel alone
!! counts as solved where its answer meets the conditions to 1e-12 m/s).
!!
!! Then the chain (when chain_n_max >= 10): the step problem of `moreau` on a chain of n = 10,
!! 100, 1000, 10000 blocks (Coulomb mu_s = 0.35, mu_k = 0.3, the scene's springs and masses,
!! h = 1 ms, theta = 1/2): five states of a run started stuck on the belt (moreau itself, at
!! t = 1, 2, 3, 4, 5 s), each giving the step's free velocities and capacities as moreau forms
!! them. Solved by the chain's own path (`tridiagonal_rule`: the contact solver's rule, each box
!! problem by nonsmooth Gauss-Seidel on the tridiagonal W, what moreau runs on a chain), and, up to 100 blocks, on the dense Delassus
!! matrix D = W^-1 by the general solver (`solve_contacts`) and by projected Gauss-Seidel alone
!! (`gauss_seidel`, the solver before its fallback); and by the sweeps alone
!! (`tridiagonal_sweeps` with the contacts' own laws, no rounds: moreau's chain path before the
!! rule). One line per n:
!!   chain  n  tri_us  tri_solved  tri_sweeps  sweeps_us  solver_us  solver_solved  gs_us
!!   gs_solved  gs_sweeps  both_solved  max_du
!! (microseconds a solve, medians of `repeats` passes; solver and Gauss-Seidel columns -1 beyond
!! 100 blocks; both_solved: problems that both dense solvers solved, over which their times
!! are taken; max_du: the largest difference of the step's velocities between the
!! tridiagonal path and the general solver [m/s]).
!!
!! Then the stack (`bench_stack`): moreau itself on a stack of n = 1 to min(n_max, 64) blocks on
!! a belt, every contact coupled to its neighbours, 2 s from rest at h = 1 ms: microseconds a
!! step, the contact solver's linear solves a step, the steps with another solution
!! (stats%nonunique), the largest residual and the status.
!! Usage: bench_contact n_max repeats [chain_n_max]
!> A stack of n blocks on a belt for the stack section of bench_contact: block 1 on the belt,
!! block i on block i - 1 (contact i: w_i = v_i - v_(i-1), a row of H with two entries, so
!! every contact is coupled to its neighbours), each block tied to the wall by a spring; normal
!! forces the weight of the blocks above and on the contact. W = M + b K is diagonal.
module bench_contact_stack
    use stickslip_kinds, only: dp
    use stickslip_contact, only: contact_system, contact_law
    implicit none
    private
    public :: stack_system, stack_of

    !> The stack (module notes).
    type, extends(contact_system) :: stack_system
        real(dp), allocatable :: m(:)       !! masses [kg]
        real(dp), allocatable :: k(:)       !! springs to the wall [N/m]
        real(dp), allocatable :: nf(:)      !! normal forces [N]
        real(dp) :: v_b = 0.3_dp            !! belt speed [m/s]
    contains
        procedure :: force => stack_force
        procedure :: solve_w => stack_solve_w
        procedure :: normal_forces => stack_normal
        procedure :: slip_offset => stack_offset
    end type stack_system

contains

    !> n blocks: masses 2, 1, 0.5, 2, 1, ... kg, springs 200, 60, 30, ... N/m, Coulomb
    !! (mu_s, mu_k) = (0.5, 0.35), (0.4, 0.3), (0.3, 0.2), ... from the belt up.
    function stack_of(n) result(s)
        integer, intent(in) :: n
        type(stack_system) :: s
        integer :: i, j
        real(dp), parameter :: ms(3) = [2.0_dp, 1.0_dp, 0.5_dp], ks(3) = [200.0_dp, 60.0_dp, 30.0_dp]
        real(dp), parameter :: mus(3) = [0.5_dp, 0.4_dp, 0.3_dp], muk(3) = [0.35_dp, 0.3_dp, 0.2_dp]
        s%n_dof = n
        s%n_c = n
        allocate(s%m(n), s%k(n), s%nf(n), s%laws(n), s%h_ptr(n + 1))
        allocate(s%h_col(2 * n - 1), s%h_val(2 * n - 1))
        s%h_ptr(1) = 1
        s%h_col(1) = 1
        s%h_val(1) = 1.0_dp
        do i = 1, n
            j = 1 + mod(i - 1, 3)
            s%m(i) = ms(j)
            s%k(i) = ks(j)
            s%laws(i) = contact_law(mu_s=mus(j), mu_k=muk(j))
            if (i > 1) then
                s%h_col(2 * i - 2:2 * i - 1) = [i - 1, i]
                s%h_val(2 * i - 2:2 * i - 1) = [-1.0_dp, 1.0_dp]
            end if
            s%h_ptr(i + 1) = 2 * i
        end do
        do i = 1, n
            s%nf(i) = 9.81_dp * sum(s%m(i:))
        end do
        s%w_constant = .true.
    end function stack_of

    subroutine stack_force(self, t, q, u, f)
        class(stack_system), intent(in) :: self
        real(dp), intent(in)  :: t, q(:), u(:)
        real(dp), intent(out) :: f(:)
        f = -self%k * q
    end subroutine stack_force

    subroutine stack_solve_w(self, t, q, u, a, b, x)
        class(stack_system), intent(in) :: self
        real(dp), intent(in)    :: t, q(:), u(:), a, b
        real(dp), intent(inout) :: x(:)
        x = x / (self%m + b * self%k)
    end subroutine stack_solve_w

    subroutine stack_normal(self, t, q, n)
        class(stack_system), intent(in) :: self
        real(dp), intent(in)  :: t, q(:)
        real(dp), intent(out) :: n(:)
        n = self%nf
    end subroutine stack_normal

    subroutine stack_offset(self, t, b)
        class(stack_system), intent(in) :: self
        real(dp), intent(in)  :: t
        real(dp), intent(out) :: b(:)
        b = 0.0_dp
        b(1) = -self%v_b
    end subroutine stack_offset

end module bench_contact_stack

program bench_contact
    use stickslip_kinds, only: dp
    use stickslip_contact, only: contact_law
    use stickslip_contact_solver, only: solve_contacts, contact_solve_info, contact_workspace, gauss_seidel, &
                                        contact_residual, SOLVER_PIVOTING, tridiagonal_rule, &
                                        tridiagonal_sweeps
    use stickslip_linalg, only: psd_solve
    use stickslip_params, only: param_values, NAME_LEN
    use stickslip_contact, only: contact_system
    use stickslip_model_system, only: model_system
    use stickslip_registry, only: new_system, code_of
    use stickslip_moreau, only: moreau_options, moreau_integrate
    use stickslip_ode, only: ode_stats
    use bench_contact_stack, only: stack_system, stack_of
    implicit none
    integer, parameter :: nprob = 50
    character(len=32) :: arg
    integer :: n_max, repeats, n, k, r, nd, i, j, iseed
    integer, allocatable :: seed(:), mode(:)
    real(dp), allocatable :: d(:, :, :), wf(:, :), cap(:, :), p(:), w(:), hm(:, :), wm(:, :), winv(:, :), times(:), gtimes(:)
    real(dp), allocatable :: ptimes(:)
    type(contact_law), allocatable :: laws(:, :)
    type(contact_solve_info) :: info
    type(contact_workspace) :: cw     ! the solvers' room, reused from solve to solve as moreau does
    real(dp) :: u, t0, t1, resid, work
    integer :: nok, ngs, sweeps, worst, ns_list(12), nfall, npiv
    real(dp) :: pivots
    logical :: ok_inv
    integer :: chain_n_max

    call get_command_argument(1, arg)
    read (arg, *) n_max
    call get_command_argument(2, arg)
    read (arg, *) repeats
    chain_n_max = 0
    if (command_argument_count() >= 3) then
        call get_command_argument(3, arg)
        read (arg, *) chain_n_max
    end if
    call random_seed(size=iseed)
    allocate(seed(iseed), source=4242)
    call random_seed(put=seed)
    ns_list = [2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 128]
    do k = 1, size(ns_list)
        n = ns_list(k)
        if (n > n_max) exit
        nd = n / 2 + 1
        allocate(d(n, n, nprob), wf(n, nprob), cap(n, nprob), laws(n, nprob), p(n), w(n), mode(n))
        allocate(hm(n, nd), wm(nd, nd), winv(nd, nd), times(repeats), gtimes(repeats), ptimes(repeats))
        do j = 1, nprob
            hm = 0.0_dp
            do i = 1, n
                call random_number(u)
                hm(i, 1 + mod(i - 1, nd)) = 1.0_dp
                if (u < 0.5_dp) hm(i, 1 + mod(i, nd)) = -1.0_dp
            end do
            call random_number(wm)
            wm = 0.1_dp * matmul(transpose(wm), wm)
            do i = 1, nd
                wm(i, i) = wm(i, i) + 1.0_dp
            end do
            winv = 0.0_dp                      ! W^-1 by the library's psd_solve (LU: W is regular)
            do i = 1, nd
                winv(i, i) = 1.0_dp
            end do
            call psd_solve(wm, winv, [(1.0_dp, i = 1, nd)], ok_inv)
            d(:, :, j) = matmul(hm, matmul(winv, transpose(hm)))
            call random_number(wf(:, j))
            wf(:, j) = 0.02_dp * (wf(:, j) - 0.5_dp)
            call random_number(cap(:, j))
            cap(:, j) = 1.0e-3_dp * 9.81_dp * (0.5_dp + cap(:, j))
            do i = 1, n
                call random_number(u)
                laws(i, j) = contact_law(mu_s=0.3_dp + 0.4_dp * u, mu_k=0.3_dp)
            end do
        end do
        work = 0.0_dp
        pivots = 0.0_dp
        do r = 1, repeats
            nok = 0
            nfall = 0
            call cpu_time(t0)
            do j = 1, nprob
                p = 0.0_dp
                mode = -9
                call solve_contacts(laws(:, j), d(:, :, j), wf(:, j), cap(:, j), .false., 1.0e-12_dp, 1000, &
                                    p, w, mode, info, work=cw)
                if (info%ok) nok = nok + 1
                if (info%pivots > 0) nfall = nfall + 1      ! Lemke's fallback was needed
                work = work + info%sweeps
            end do
            call cpu_time(t1)
            times(r) = (t1 - t0) / nprob
            ngs = 0
            call cpu_time(t0)
            do j = 1, nprob
                p = 0.0_dp
                call gauss_seidel(laws(:, j), d(:, :, j), wf(:, j), cap(:, j), .false., 1.0e-12_dp, 1000, p, w, &
                                  sweeps, work=cw)
                mode = merge(0, nint(sign(1.0_dp, w)), w == 0.0_dp)
                call contact_residual(laws(:, j), d(:, :, j), wf(:, j), cap(:, j), .false., p, w, mode, resid, worst)
                if (resid <= 1.0e-12_dp) ngs = ngs + 1
            end do
            call cpu_time(t1)
            gtimes(r) = (t1 - t0) / nprob
            npiv = 0
            call cpu_time(t0)
            do j = 1, nprob
                p = 0.0_dp
                mode = -9
                call solve_contacts(laws(:, j), d(:, :, j), wf(:, j), cap(:, j), .false., 1.0e-12_dp, 1000, &
                                    p, w, mode, info, method=SOLVER_PIVOTING, work=cw)
                if (info%ok) npiv = npiv + 1
                pivots = pivots + info%pivots
            end do
            call cpu_time(t1)
            ptimes(r) = (t1 - t0) / nprob
        end do
        print '(i5, es12.4, f8.3, es12.4, f8.3, f10.1, f8.3, es12.4, f8.3, f10.1)', n, 1.0e6_dp * median(times), &
            real(nok, dp) / nprob, 1.0e6_dp * median(gtimes), real(ngs, dp) / nprob, work / (repeats * nprob), &
            real(nfall, dp) / nprob, 1.0e6_dp * median(ptimes), real(npiv, dp) / nprob, pivots / (repeats * nprob)
        deallocate(d, wf, cap, laws, p, w, mode, hm, wm, winv, times, gtimes, ptimes)
    end do

    do k = 1, size(ns_list)
        if (ns_list(k) > min(n_max, 64)) exit
        if (k == 1) call bench_stack(1)
        call bench_stack(ns_list(k))
    end do

    n = 10
    do while (n <= chain_n_max)
        call bench_chain(n)
        n = 10 * n
    end do

contains

    !> The chain section (program notes) for n blocks.
    subroutine bench_chain(n)
        integer, intent(in) :: n    !! blocks (and contacts)
        integer, parameter :: nst = 5               ! states (problems)
        real(dp), parameter :: h = 1.0e-3_dp, th = 0.5_dp, tol = 1.0e-12_dp
        class(model_system), allocatable :: sys
        class(contact_system), allocatable :: cc
        type(param_values) :: p
        integer :: status
        type(moreau_options) :: mo
        type(ode_stats) :: st
        type(contact_solve_info) :: inf
        type(contact_workspace) :: cwk      ! the solvers' room, reused from solve to solve as moreau does
        real(dp) :: t_out(nst + 1), y_out(2 * n, nst + 1), y0(2 * n)
        real(dp) :: uf(n, nst), wf(n, nst), hn(n), boff(n), wl(n), wd(n), wr(n), f0(n), f1(n), qp(n)
        real(dp) :: ut(n, nst), ud(n), pp(n), ww(n), wl2(n), res, du_max, tm
        real(dp) :: tt(repeats), ts(repeats), tg(repeats), ta(repeats), ut2(n)
        real(dp), allocatable :: dm(:, :), dlay(:, :)   ! dlay: step_layout's room for D (none on the chain)
        integer :: cmap(n), i, j, r, sw, iw, nin, k, ntri, nsol, ngs, nboth, cm(n), pm(n, nst)
        integer :: tri_sweeps, gs_sweeps
        logical :: dense, ok, both(nst)
        ! The chain preset's contact system (its model's contact_model), Coulomb, k_p = 0.
        status = new_system(code_of('scene', 'chain'), code_of('law', 'coulomb'), &
                            [character(len=NAME_LEN) :: 'n_blocks', 'mu_s', 'mu_k', 'm', 'k', 'k_c', 'v_b'], &
                            [real(n, dp), 0.35_dp, 0.3_dp, 10.0_dp, 300.0_dp, 300.0_dp, 1.5_dp], sys, p)
        if (status == 0) call sys%contact_model(cc, status)
        if (status /= 0) error stop 'bench_contact: the chain preset failed'
        ! States of a run started stuck on the belt.
        mo%h = h
        mo%theta = th
        y0 = 0.0_dp
        y0(n + 1:) = 1.5_dp
        t_out = [(real(i, dp), i = 0, nst)]
        call moreau_integrate(cc, 0.0_dp, y0, real(nst, dp), mo, t_out, y_out, st)
        if (st%status /= 0) error stop 'bench_contact: the chain run failed'
        ! The step problems, as moreau forms them.
        call cc%step_layout(h * th, (h * th)**2, wl, wd, wr, cmap, ok, dlay)
        call cc%slip_offset(0.0_dp, boff)
        call cc%normal_forces(0.0_dp, y0(:n), hn)
        hn = h * hn
        do j = 1, nst
            associate (q => y_out(:n, j + 1), u => y_out(n + 1:, j + 1))
                call cc%force(0.0_dp, q, u, f0)
                qp = q + h * u
                call cc%force(h, qp, u, f1)
                uf(:, j) = h * ((1.0_dp - th) * f0 + th * f1)
                call cc%solve_w(0.0_dp, q, u, h * th, (h * th)**2, uf(:, j))
                uf(:, j) = u + uf(:, j)
                call cc%relative_velocities(h, uf(:, j), wf(:, j))
                call cc%relative_velocities(0.0_dp, u, ww)     ! moreau's previous mode: the step start's
                pm(:, j) = merge(0, nint(sign(1.0_dp, ww)), ww == 0.0_dp)
            end associate
        end do
        dense = n <= 100     ! the general solver on D: O(n^3) a linear solve
        if (dense) then
            allocate(dm(n, n))
            call cc%delassus(0.0_dp, y0(:n), y0(n + 1:), h * th, (h * th)**2, dm)
        end if
        nin = max(1, 20000 / n)     ! solves per timing, for a measurable time
        du_max = 0.0_dp
        ntri = 0
        nsol = 0
        ngs = 0
        tri_sweeps = 0
        gs_sweeps = 0
        both = .true.
        do r = 1, repeats
            ! the chain's own path, warm-started at the step's start as moreau does
            tt(r) = 0.0_dp
            do j = 1, nst
                call cpu_time(t0)
                do k = 1, nin
                    ut(:, j) = y_out(n + 1:, j + 1)
                    cm = pm(:, j)
                    call tridiagonal_rule(cc, wl, wd, wr, uf(:, j), cmap, boff, hn, tol, 1000, cm, ut(:, j), wl2, sw, &
                                          res, iw, work=cwk)
                end do
                call cpu_time(t1)
                tt(r) = tt(r) + (t1 - t0) / (nin * nst)
                if (r == 1 .and. res <= tol) ntri = ntri + 1
                if (r == 1) tri_sweeps = tri_sweeps + sw
            end do
            ! the sweeps alone (moreau's chain path before the rule: one set of sweeps with the
            ! contacts' own laws, no rounds), warm-started the same way
            ta(r) = 0.0_dp
            do j = 1, nst
                call cpu_time(t0)
                do k = 1, nin
                    ut2 = y_out(n + 1:, j + 1)
                    call tridiagonal_sweeps(cc, wl, wd, wr, uf(:, j), cmap, boff, hn, tol, 1000, ut2, wl2, sw, res, iw)
                end do
                call cpu_time(t1)
                ta(r) = ta(r) + (t1 - t0) / (nin * nst)
            end do
            if (.not. dense) cycle
            ! the general solver and Gauss-Seidel alone on D, from p = 0
            ts(r) = 0.0_dp
            tg(r) = 0.0_dp
            do j = 1, nst
                call cpu_time(t0)
                do k = 1, nin
                    pp = 0.0_dp
                    cm = -9
                    call solve_contacts(cc%laws, dm, wf(:, j), hn, .false., tol, 1000, pp, ww, cm, inf, work=cwk)
                end do
                call cpu_time(t1)
                tm = (t1 - t0) / nin
                if (r == 1) then
                    if (inf%ok) nsol = nsol + 1
                    both(j) = both(j) .and. inf%ok
                    ud = 0.0_dp
                    call cc%add_ht(pp, ud)
                    call cc%solve_w(0.0_dp, y0(:n), y0(n + 1:), h * th, (h * th)**2, ud)
                    ud = uf(:, j) + ud
                    du_max = max(du_max, maxval(abs(ud - ut(:, j))))
                end if
                if (both(j)) ts(r) = ts(r) + tm
                call cpu_time(t0)
                do k = 1, nin
                    pp = 0.0_dp
                    call gauss_seidel(cc%laws, dm, wf(:, j), hn, .false., tol, 1000, pp, ww, sw, work=cwk)
                end do
                call cpu_time(t1)
                tm = (t1 - t0) / nin
                if (r == 1) then
                    cm = merge(0, nint(sign(1.0_dp, ww)), ww == 0.0_dp)
                    call contact_residual(cc%laws, dm, wf(:, j), hn, .false., pp, ww, cm, res, iw)
                    if (res <= tol) ngs = ngs + 1
                    both(j) = both(j) .and. res <= tol
                    gs_sweeps = gs_sweeps + sw
                end if
                if (both(j)) tg(r) = tg(r) + tm
            end do
        end do
        nboth = count(both)
        if (dense) then
            print '(a, i7, es12.4, f8.3, f8.1, es12.4, es12.4, f8.3, es12.4, f8.3, f8.1, f8.3, es12.4)', 'chain', n, &
                1.0e6_dp * median(tt), real(ntri, dp) / nst, real(tri_sweeps, dp) / nst, 1.0e6_dp * median(ta), &
                1.0e6_dp * median(ts) / max(nboth, 1), real(nsol, dp) / nst, 1.0e6_dp * median(tg) / max(nboth, 1), &
                real(ngs, dp) / nst, real(gs_sweeps, dp) / nst, real(nboth, dp) / nst, du_max
        else
            print '(a, i7, es12.4, f8.3, f8.1, es12.4, a)', 'chain', n, 1.0e6_dp * median(tt), real(ntri, dp) / nst, &
                real(tri_sweeps, dp) / nst, 1.0e6_dp * median(ta), '  -1  -1  -1  -1  -1  -1  -1'
        end if
    end subroutine bench_chain

    !> The stack section: moreau (h = 1 ms, theta = 1/2) on a stack of n blocks on a belt
    !! (`bench_contact_stack`) for 2 s from rest, `repeats` times: one line
    !!   stack  n  us_per_step  linear_solves_per_step  nonunique_steps  largest_residual  status
    subroutine bench_stack(n)
        integer, intent(in) :: n        !! blocks (and contacts)
        type(stack_system) :: s
        type(moreau_options) :: mo
        type(ode_stats) :: st
        real(dp) :: t_out(2), y_out(2 * n, 2), y0(2 * n), tm(repeats), c0, c1
        integer :: r
        s = stack_of(n)
        mo%h = 1.0e-3_dp
        y0 = 0.0_dp
        do r = 1, repeats
            t_out = [0.0_dp, 2.0_dp]
            call cpu_time(c0)
            call moreau_integrate(s, 0.0_dp, y0, 2.0_dp, mo, t_out, y_out, st)
            call cpu_time(c1)
            tm(r) = (c1 - c0) / max(st%nstep, 1_8)
        end do
        print '(a, i5, es12.4, f10.2, i8, es12.4, i5)', 'stack', n, 1.0e6_dp * median(tm), &
            real(st%ncontact_iter, dp) / max(st%nstep, 1_8), st%nonunique, st%contact_residual, st%status
    end subroutine bench_stack

    real(dp) function median(x)
        real(dp), intent(in) :: x(:)
        real(dp) :: s(size(x)), tmp
        integer :: i, j
        s = x
        do i = 2, size(s)
            tmp = s(i)
            j = i - 1
            do while (j >= 1)
                if (s(j) <= tmp) exit
                s(j + 1) = s(j)
                j = j - 1
            end do
            s(j + 1) = tmp
        end do
        median = 0.5_dp * (s((size(s) + 1) / 2) + s(size(s) / 2 + 1))
    end function median

end program bench_contact
