!> General contact configurations through the contact interface, written here as a user's
!! own `contact_system` (a linear system of bodies: diagonal mass, dense stiffness, a sparse
!! H with coupled and redundant rows, constant normal forces and belt offsets):
!!   - stacked: block A on a belt, block B on A (the contact B-A has the row [-1, 1] of H);
!!   - feet: one block on a belt standing on two feet (two identical rows of H, N/2 each).
!! Without arguments it checks the per-step contact solver on random problems (coupled and
!! redundant rows, mu_s >= mu_k, with and without a previous mode): the answer satisfies the
!! problem's conditions (checked here independently of the solver's own residual), it equals
!! the only solution where a brute force search written here finds exactly one, its modes are
!! those of the solver's rule as written here (`rule_reference`: the same rounds of box
!! problems, each solved by exhaustive search over the 3^n active sets), and where it reports
!! another solution (info%nonunique) the brute force finds one with as many stuck contacts. With the argument `dump` it prints the scenes' trajectories
!! under event_driven and moreau for tests/fortran/test_stickslip_contact.py, which compares them with
!! a scipy event-driven reference and the closed-form belt cycle.
module test_linear_contact
    use stickslip_kinds, only: dp
    use stickslip_contact, only: contact_system, contact_law
    use stickslip_linalg, only: lu_decompose, lu_solve, psd_solve
    implicit none
    private
    public :: linear_system, stacked_blocks, two_feet

    !> M u' = -K q + H^T r, w = H u + b, constant normal forces.
    type, extends(contact_system) :: linear_system
        real(dp), allocatable :: m(:)        !! masses [kg]
        real(dp), allocatable :: k(:, :)     !! stiffness [N/m]
        real(dp), allocatable :: boff(:)     !! offsets of w (minus the belt speed) [m/s]
        real(dp), allocatable :: nforce(:)   !! normal forces [N]
    contains
        procedure :: force => ls_force
        procedure :: solve_w => ls_solve_w
        procedure :: normal_forces => ls_normal
        procedure :: slip_offset => ls_offset
    end type linear_system

contains

    !> Block A (1 kg, spring 100 N/m to the wall) on a belt at 0.2 m/s, block B (0.5 kg,
    !! spring 150 N/m to the wall) on A. Contact 1: A on the belt, w1 = v_A - v_b, N1 = (m_A +
    !! m_B) g, mu_s 0.5, mu_k 0.3; contact 2: B on A, w2 = v_B - v_A, N2 = m_B g, mu_s 0.6,
    !! mu_k 0.4.
    function stacked_blocks() result(s)
        type(linear_system) :: s
        s%n_dof = 2
        s%n_c = 2
        s%m = [1.0_dp, 0.5_dp]
        s%k = reshape([100.0_dp, 0.0_dp, 0.0_dp, 150.0_dp], [2, 2])
        s%h_ptr = [1, 2, 4]
        s%h_col = [1, 1, 2]
        s%h_val = [1.0_dp, -1.0_dp, 1.0_dp]
        s%boff = [-0.2_dp, 0.0_dp]
        s%nforce = [1.5_dp * 9.81_dp, 0.5_dp * 9.81_dp]
        s%laws = [contact_law(mu_s=0.5_dp, mu_k=0.3_dp), contact_law(mu_s=0.6_dp, mu_k=0.4_dp)]
        s%w_constant = .true.
    end function stacked_blocks

    !> One block (2 kg, spring 500 N/m to the wall) on a belt at 0.3 m/s on two feet, each
    !! with half the weight, mu_s 0.6, mu_k 0.4: the belt scene's first parameter set of the
    !! closed-form tests, with its contact split in two.
    function two_feet() result(s)
        type(linear_system) :: s
        s%n_dof = 1
        s%n_c = 2
        s%m = [2.0_dp]
        s%k = reshape([500.0_dp], [1, 1])
        s%h_ptr = [1, 2, 3]
        s%h_col = [1, 1]
        s%h_val = [1.0_dp, 1.0_dp]
        s%boff = [-0.3_dp, -0.3_dp]
        s%nforce = [9.81_dp, 9.81_dp]
        s%laws = [contact_law(mu_s=0.6_dp, mu_k=0.4_dp), contact_law(mu_s=0.6_dp, mu_k=0.4_dp)]
        s%w_constant = .true.
    end function two_feet

    subroutine ls_force(self, t, q, u, f)
        class(linear_system), intent(in) :: self
        real(dp), intent(in) :: t, q(:), u(:)
        real(dp), intent(out) :: f(:)
        f = -matmul(self%k, q)
    end subroutine ls_force

    subroutine ls_solve_w(self, t, q, u, a, b, x)
        class(linear_system), intent(in) :: self
        real(dp), intent(in) :: t, q(:), u(:), a, b
        real(dp), intent(inout) :: x(:)
        real(dp) :: w(self%n_dof, self%n_dof)
        integer :: ipiv(self%n_dof), info, i
        w = b * self%k
        do i = 1, self%n_dof
            w(i, i) = w(i, i) + self%m(i)
        end do
        call lu_decompose(w, ipiv, info)
        call lu_solve(w, ipiv, x)
    end subroutine ls_solve_w

    subroutine ls_normal(self, t, q, n)
        class(linear_system), intent(in) :: self
        real(dp), intent(in) :: t, q(:)
        real(dp), intent(out) :: n(:)
        n = self%nforce
    end subroutine ls_normal

    subroutine ls_offset(self, t, b)
        class(linear_system), intent(in) :: self
        real(dp), intent(in) :: t
        real(dp), intent(out) :: b(:)
        b = self%boff
    end subroutine ls_offset

end module test_linear_contact

program test_stickslip_contact_general
    use test_support, only: check, finish
    use stickslip_kinds, only: dp
    use stickslip_ode, only: ode_stats
    use stickslip_contact, only: contact_law, CONTACT_STRIBECK
    use stickslip_contact_solver, only: solve_contacts, contact_solve_info, SOLVER_PIVOTING, SOLVER_GAUSS_SEIDEL, &
                                        gauss_seidel, first_order_alternative, MODE_STICK
    use stickslip_linalg, only: lu_decompose, lu_solve, psd_solve
    use stickslip_moreau, only: moreau_options, moreau_integrate
    use stickslip_event_driven, only: event_driven_options, event_driven_integrate
    use test_linear_contact, only: linear_system, stacked_blocks, two_feet
    implicit none
    character(len=16) :: arg
    integer, parameter :: NMAX = 128   ! most contacts of a random problem
    integer, parameter :: NBRUTE = 9   ! most contacts searched by brute force (3^9 modes)
    ! the current random problem (random_problems, conditions, brute_force)
    real(dp) :: d(NMAX, NMAX), wf(NMAX), cap(NMAX)
    type(contact_law) :: laws(NMAX)
    integer :: mode(NMAX)

    arg = ''
    if (command_argument_count() >= 1) call get_command_argument(1, arg)
    if (arg == 'dump') then
        call dump('stacked', stacked_blocks(), [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], 4.0_dp)
        call dump('feet', two_feet(), [0.0_dp, 0.3_dp], 4.0_dp)
    else
        ! the solver as it runs (the rule's rounds, active-set Newton with Lemke's fallback)
        call random_problems('random problems', 2, 6, 4, 400, 0, .true.)
        ! the same rounds with every box problem by Lemke's method, against brute force
        call random_problems('pivoting', 2, NBRUTE, 5, 300, SOLVER_PIVOTING, .true.)
        ! large strongly coupled sets (the benchmark's kind), where Gauss-Seidel alone fails
        ! 7 to 12 contacts (beyond brute force): the rule's modes by both box solvers
        call random_problems('random problems of 7-12', 7, 12, 7, 200, 0, .false.)
        call random_problems('large sets', 8, NMAX, NMAX / 2 + 1, 40, 0, .false.)
        ! the same with Stribeck curves (slip speeds by Newton's method in every mode)
        call random_problems('large Stribeck sets', 8, 32, 17, 40, 0, .false., stribeck=.true.)
        call first_order_cases()
        call finish('general contact')
    end if

contains

    !> `first_order_alternative` on two coupled contacts at rest, written out by hand (Coulomb,
    !! mu_s 0.5, mu_k 0.3, normal forces 10 N: static limits 5 N, slip forces 3 N; accelerations
    !! w = wf + D p): contact 1 slips (+1) at w_1 = 0, so that its mode holds to first order
    !! only; contact 2 is stuck with the force p_2. Released against its holding force, contact
    !! 2 slips (-1) with the force +3 N: with D = [2 -1; -1 2] and p_2 = 4 N (above its slip
    !! force) the accelerations become w = (1, -2), both strictly in their slip directions, so
    !! another mode is consistent strictly (found); with p_2 = 2 N (below it) they become
    !! (-1, 2), inconsistent; uncoupled (D_12 = 0), or with contact 1 accelerating (w_1 = 0.5,
    !! an ordinary slip), nothing is tried.
    subroutine first_order_cases()
        type(contact_law) :: two(2)
        real(dp) :: dd(2, 2), pp(2)
        logical :: found
        integer, parameter :: STICK_SLIP(2) = [1, MODE_STICK]   ! contact 1 slipping (+1), 2 held
        two = contact_law(mu_s=0.5_dp, mu_k=0.3_dp)
        dd = reshape([2.0_dp, -1.0_dp, -1.0_dp, 2.0_dp], [2, 2])
        ! p_2 = 4 N: wf = -D p with p = (-3, 4) -> (10, -11)
        pp = [-3.0_dp, 4.0_dp]
        call first_order_alternative(two, dd, -matmul(dd, pp), [10.0_dp, 10.0_dp], 1.0e-9_dp, pp, &
                                     [0.0_dp, 0.0_dp], STICK_SLIP, found)
        call check(found, 'first-order mode: a stuck contact above its slip force released is a strict mode')
        pp = [-3.0_dp, 2.0_dp]
        call first_order_alternative(two, dd, -matmul(dd, pp), [10.0_dp, 10.0_dp], 1.0e-9_dp, pp, &
                                     [0.0_dp, 0.0_dp], STICK_SLIP, found)
        call check(.not. found, 'first-order mode: a stuck contact below its slip force released is not')
        pp = [-3.0_dp, 4.0_dp]
        call first_order_alternative(two, reshape([2.0_dp, 0.0_dp, 0.0_dp, 2.0_dp], [2, 2]), &
                                     -matmul(reshape([2.0_dp, 0.0_dp, 0.0_dp, 2.0_dp], [2, 2]), pp), &
                                     [10.0_dp, 10.0_dp], 1.0e-9_dp, pp, [0.0_dp, 0.0_dp], STICK_SLIP, found)
        call check(.not. found, 'first-order mode: uncoupled contacts have no alternative')
        call first_order_alternative(two, dd, [0.5_dp, 0.0_dp] - matmul(dd, pp), [10.0_dp, 10.0_dp], 1.0e-9_dp, &
                                     pp, [0.5_dp, 0.0_dp], STICK_SLIP, found)
        call check(.not. found, 'first-order mode: an ordinary slip (w_1 > tol) tries nothing')
    end subroutine first_order_cases

    !> Trajectories of one scene on a grid of 401 points: event_driven (rtol 1e-11) and moreau
    !! at h = 4e-3, 2e-3, 1e-3, 5e-4, as lines 'TRAJ scene method h status t q.. u..', and the
    !! events as 'EVENT scene t kind position contact'.
    subroutine dump(name, sys, y0, t_end)
        character(*), intent(in) :: name
        type(linear_system), intent(in) :: sys
        real(dp), intent(in) :: y0(:), t_end
        integer, parameter :: nout = 401
        type(moreau_options) :: mo
        type(event_driven_options) :: eo
        type(ode_stats) :: st
        real(dp) :: t(nout), y(size(y0), nout), hs(4)
        real(dp), allocatable :: ev(:, :)
        type(linear_system) :: s
        integer :: i, j
        allocate(ev(4, 10000))
        s = sys
        t = [(t_end * (i - 1) / (nout - 1), i = 1, nout)]
        eo%max_steps = 10000000_8
        call event_driven_integrate(s, 0.0_dp, y0, t_end, [1.0e-11_dp], [1.0e-13_dp], eo, t, y, st, ev)
        do i = 1, st%n_written
            print '(a, 1x, a, 1x, a, es12.4, i6, 99es24.16)', 'TRAJ', name, 'event_driven', 0.0_dp, st%status, t(i), y(:, i)
        end do
        do i = 1, int(min(st%nevents, 10000_8))
            print '(a, 1x, a, es24.16, i3, es24.16, i3)', 'EVENT', name, ev(1, i), nint(ev(2, i)), ev(3, i), nint(ev(4, i))
        end do
        hs = [4.0e-3_dp, 2.0e-3_dp, 1.0e-3_dp, 5.0e-4_dp]
        do j = 1, size(hs)
            mo%h = hs(j)
            t = [(t_end * (i - 1) / (nout - 1), i = 1, nout)]
            call moreau_integrate(s, 0.0_dp, y0, t_end, mo, t, y, st)
            do i = 1, st%n_written
                print '(a, 1x, a, 1x, a, es12.4, i6, 99es24.16)', 'TRAJ', name, 'moreau', hs(j), st%status, t(i), y(:, i)
            end do
        end do
    end subroutine dump

    !> Random problems w = wf + D p, D = H W^-1 H^T with H of nlo..nhi rows over 1..ndmax
    !! coordinates, some rows repeated (redundant) and some with two entries (coupled),
    !! mu_s >= mu_k, Coulomb laws. forced: 0 (the solver as it chooses) or a method to force;
    !! brute: compare with brute force (up to NBRUTE contacts).
    subroutine random_problems(label, nlo, nhi, ndmax, ntrial, forced, brute, stribeck)
        character(*), intent(in) :: label
        integer, intent(in) :: nlo, nhi, ndmax, ntrial, forced
        logical, intent(in) :: brute
        logical, intent(in), optional :: stribeck   ! Stribeck curves instead of Coulomb
        integer :: trial, n, nd, i, j, nsol, nbetter, nbad, nuniq, ndiff, nfail, nseed, nfewer, nforced
        integer :: nrule, nflag, nfalse, ntie, mprev(nhi), mref(nhi), solves(ntrial), nsolved
        real(dp) :: hm(nhi, ndmax), wmat(ndmax, ndmax), winv(ndmax, ndmax), p(nhi), w(nhi), worst_res, u
        logical :: ok_inv
        real(dp) :: pb(nhi), wb(nhi), res
        type(contact_solve_info) :: info
        integer :: msol(nhi)
        integer, allocatable :: seed(:)
        real(dp) :: worst_gap
        call random_seed(size=nseed)
        allocate(seed(nseed), source=12345 + nhi - 6)
        call random_seed(put=seed)
        nbad = 0; nuniq = 0; ndiff = 0; nbetter = 0; nfail = 0; nfewer = 0; nforced = 0
        nrule = 0; nflag = 0; nfalse = 0; ntie = 0; nsolved = 0
        worst_res = 0.0_dp
        worst_gap = 0.0_dp
        do trial = 1, ntrial
            call random_number(u)
            n = nlo + int(u * (nhi - nlo + 1))          ! nlo .. nhi contacts
            call random_number(u)
            nd = 1 + int(u * ndmax)                     ! 1 .. ndmax coordinates
            if (.not. brute) nd = n / 2 + 1             ! large sets: strongly coupled
            hm = 0.0_dp
            do i = 1, n
                call random_number(u)
                if (i > 1 .and. u < 0.2_dp) then        ! redundant: a copy of an earlier row
                    hm(i, :) = hm(1 + int(u * 5.0_dp * (i - 1)), :)
                    cycle
                end if
                call random_number(u)
                j = 1 + int(u * nd)
                hm(i, j) = 1.0_dp
                call random_number(u)
                if (nd > 1 .and. u < 0.5_dp) hm(i, 1 + mod(j, nd)) = -1.0_dp   ! coupled
            end do
            ! W = M + b K: random symmetric positive definite
            call random_number(wmat)
            wmat(:nd, :nd) = matmul(transpose(wmat(:nd, :nd)), wmat(:nd, :nd))
            do i = 1, nd
                wmat(i, i) = wmat(i, i) + 0.5_dp
            end do
            winv = 0.0_dp                      ! W^-1 by the library's psd_solve (LU: W is regular)
            do i = 1, nd
                winv(i, i) = 1.0_dp
            end do
            call psd_solve(wmat(:nd, :nd), winv(:nd, :nd), [(1.0_dp, i = 1, nd)], ok_inv)
            d(:n, :n) = matmul(hm(:n, :nd), matmul(winv(:nd, :nd), transpose(hm(:n, :nd))))
            call random_number(wf(:n))
            wf(:n) = 4.0_dp * (wf(:n) - 0.5_dp)
            call random_number(cap(:n))
            cap(:n) = 0.2_dp + 2.0_dp * cap(:n)
            do i = 1, n
                call random_number(u)
                laws(i) = contact_law(mu_s=0.3_dp + 0.4_dp * u, mu_k=0.0_dp)
                call random_number(u)
                laws(i)%mu_k = laws(i)%mu_s * (0.5_dp + 0.5_dp * u)
                if (present(stribeck)) then
                    if (stribeck) then
                        laws(i)%kind = CONTACT_STRIBECK
                        laws(i)%v_s = 0.05_dp + 0.5_dp * u
                    end if
                end if
            end do
            p(:n) = 0.0_dp
            mode(:n) = -9
            if (mod(trial, 2) == 0) then                ! a previous mode: stuck or slipping
                do i = 1, n
                    call random_number(u)
                    mode(i) = int(3.0_dp * u) - 1
                end do
            end if
            mprev(:n) = mode(:n)
            if (forced > 0) then
                call solve_contacts(laws(:n), d(:n, :n), wf(:n), cap(:n), .false., 1.0e-12_dp, 1000, p(:n), &
                                    w(:n), mode(:n), info, method=forced)
                if (info%method == forced) nforced = nforced + 1
            else
                call solve_contacts(laws(:n), d(:n, :n), wf(:n), cap(:n), .false., 1.0e-12_dp, 1000, p(:n), &
                                    w(:n), mode(:n), info)
                if (info%method == SOLVER_PIVOTING) nforced = nforced + 1
            end if
            if (.not. brute) call check_gap(n, worst_gap)
            if (.not. info%ok) then
                nfail = nfail + 1
                cycle
            end if
            nsolved = nsolved + 1
            solves(nsolved) = info%sweeps
            res = conditions(n, p, w)
            worst_res = max(worst_res, res)
            if (res > 1.0e-12_dp * (1.0_dp + maxval(abs(wf(:n))))) nbad = nbad + 1
            if (.not. brute) then
                ! the rule's modes the same with every box problem by Lemke's method (each box
                ! problem's w is unique, so the modes do not depend on how it is solved)
                if (forced == 0) then
                    mref(:n) = mprev(:n)
                    pb(:n) = 0.0_dp
                    call solve_contacts(laws(:n), d(:n, :n), wf(:n), cap(:n), .false., 1.0e-12_dp, 1000, pb(:n), &
                                        wb(:n), mref(:n), info, method=SOLVER_PIVOTING)
                    if (info%ok .and. all(mref(:n) == mode(:n))) nrule = nrule + 1
                end if
                cycle
            end if
            ! brute force over all 3^n modes (regular stuck blocks only): solutions, and whether
            ! one has more stuck contacts than the solver's
            call brute_force(n, nsol, msol, pb, wb, nbetter_out=i, ntie_out=j)
            if (i > 0) nfewer = nfewer + 1
            nbetter = nbetter + i
            ! the rule, as written here
            call rule_reference(n, mprev(:n), mref(:n))
            if (all(mref(:n) == mode(:n))) nrule = nrule + 1
            ! another solution with as many stuck contacts: reported, and never falsely
            if (i + j > 0) ntie = ntie + 1
            if (info%nonunique) nflag = nflag + 1
            if (info%nonunique .and. i + j == 0) nfalse = nfalse + 1
            if (nsol == 1) then
                nuniq = nuniq + 1
                if (maxval(abs(pb(:n) - p(:n))) > 1.0e-9_dp * (1.0_dp + maxval(abs(pb(:n)))) .or. &
                    maxval(abs(wb(:n) - w(:n))) > 1.0e-9_dp * (1.0_dp + maxval(abs(wf(:n))))) ndiff = ndiff + 1
            end if
        end do
        block
            character(len=200) :: line
            write (line, '(a, a, i0, a, i0, a, es9.2)') label, ': ', ntrial - nfail, ' of ', ntrial, &
                ' solved, largest condition residual ', worst_res
            call check(nfail == 0 .and. nbad == 0, trim(line))
            if (forced > 0) then
                write (line, '(a, a, i0, a, i0)') label, ': solved by the forced method in ', nforced, ' of ', ntrial
                call check(nforced == ntrial, trim(line))
            end if
            if (nsolved > 0) then
                ! the work: linear solves of a problem (no enumeration of modes)
                ! the median: the smallest count with half the problems at or below it
                write (line, '(a, a, i0, a, i0)') label, ': linear solves a problem, median ', &
                    minval(solves(:nsolved), mask=[(count(solves(:nsolved) <= solves(i)) >= (nsolved + 1) / 2, &
                                                    i = 1, nsolved)]), ', largest ', maxval(solves(:nsolved))
                call check(maxval(solves(:nsolved)) <= 60 * nhi, trim(line))
            end if
            if (.not. brute .and. forced == 0) then
                write (line, '(a, a, i0, a, i0)') label, ': the same modes with Lemke''s method for every box '// &
                    'problem in ', nrule, ' of ', ntrial
                call check(nrule == ntrial, trim(line))
            end if
            if (.not. brute) then
                ! Gauss-Seidel's gap (the solver's check reads it instead of forming wf + D p)
                write (line, '(a, a, es9.2, a)') label, ': Gauss-Seidel''s gap against wf + D p - w formed '// &
                    'here, largest difference ', worst_gap, ' of max|wf| + max|D| max|p| (after 1, 2, 3, 1000 sweeps)'
                call check(worst_gap <= 1.0e-13_dp, trim(line))
            end if
            if (brute) then
                write (line, '(a, a, i0, a, i0, a)') label, ': the only solution (brute force) in ', nuniq - ndiff, &
                    ' of ', nuniq, ' problems with one'
                call check(ndiff == 0 .and. nuniq > 50, trim(line))
                write (line, '(a, a, i0, a, i0)') label, ': the rule''s modes (reference written here) in ', nrule, &
                    ' of ', ntrial
                call check(nrule == ntrial, trim(line))
                ! static first prefers stick contact by contact, not globally: stated, counted
                write (line, '(a, a, i0, a, i0)') label, ': problems where another solution has more stuck '// &
                    'contacts: ', nfewer, ' of ', ntrial
                call check(nfewer < ntrial / 4, trim(line))
                write (line, '(a, a, i0, a, i0, a, i0)') label, ': another solution with as many stuck contacts '// &
                    'in ', ntie, ', reported in ', nflag, ', falsely in ', nfalse
                call check(nfalse == 0 .and. (nflag > 0 .or. ntie == 0), trim(line))
            end if
        end block
    end subroutine random_problems

        !> Gauss-Seidel's gap (wf + D p - w from its last sweep) against wf + D p - w formed
        !! here from its answer, on active contacts, after 1, 2, 3 and up to 1000 sweeps (converged
        !! or not): the largest difference, relative to max |wf| + max |D| max |p|, in worst_gap.
        subroutine check_gap(n, worst_gap)
            integer, intent(in) :: n
            real(dp), intent(inout) :: worst_gap
            real(dp) :: pg(n), wg(n), gap(n), scale
            integer :: k, it, sweeps, i
            do k = 1, 4
                it = merge(1000, k, k == 4)
                pg = 0.0_dp
                call gauss_seidel(laws(:n), d(:n, :n), wf(:n), cap(:n), .false., 1.0e-12_dp, it, pg, wg, sweeps, gap)
                scale = maxval(abs(wf(:n))) + maxval(abs(d(:n, :n))) * maxval(abs(pg))
                do i = 1, n
                    if (cap(i) > 0.0_dp .and. laws(i)%mu_s > 0.0_dp) worst_gap = max(worst_gap, &
                        abs(gap(i) - (wf(i) + dot_product(d(i, :n), pg) - wg(i))) / scale)
                end do
            end do
        end subroutine check_gap

        !> The largest violation of the problem's conditions by (p, w), written here: w = wf + D p
        !! (w = 0 if stuck), |p| <= mu_s c (stuck), p = -sign(w) mu_k c (slip) [m/s].
        real(dp) function conditions(n, p, w) result(v)
            integer, intent(in) :: n
            real(dp), intent(in) :: p(:), w(:)
            integer :: i
            v = 0.0_dp
            do i = 1, n
                v = max(v, abs(wf(i) + dot_product(d(i, :n), p(:n)) - w(i)))
                if (w(i) == 0.0_dp) then
                    v = max(v, d(i, i) * max(0.0_dp, abs(p(i)) - laws(i)%mu_s * cap(i) * (1.0_dp + 1.0e-12_dp)))
                else
                    ! the slip curve (mu_k for Coulomb; for Stribeck written out here)
                    v = max(v, d(i, i) * abs(p(i) + sign(slip_mu_here(laws(i), abs(w(i))) * cap(i), w(i))))
                end if
            end do
        end function conditions

        !> The slip coefficient at speed s: mu_k, or the Stribeck curve
        !! mu_k + (mu_s - mu_k) exp(-(s/v_s)^delta) + c_v s [-].
        real(dp) function slip_mu_here(law, s) result(mu)
            type(contact_law), intent(in) :: law
            real(dp), intent(in) :: s
            mu = law%mu_k
            if (law%kind == CONTACT_STRIBECK) &
                mu = law%mu_k + (law%mu_s - law%mu_k) * exp(-(s / law%v_s)**law%delta) + law%c_v * s
        end function slip_mu_here

        !> Every mode (stick, slip +, slip -) whose stuck block is regular, solved by LU: the
        !! number of solutions nsol (one returned in pb, wb), and how many have more stuck
        !! contacts than the solver's answer.
        subroutine brute_force(n, nsol, msol, pb, wb, nbetter_out, ntie_out)
            integer, intent(in) :: n
            integer, intent(out) :: nsol, msol(:), nbetter_out, ntie_out
            real(dp), intent(out) :: pb(:), wb(:)
            integer :: code, i, m(NBRUTE), c, ns
            real(dp) :: pp(NBRUTE), ww(NBRUTE)
            logical :: ok
            nsol = 0
            nbetter_out = 0
            ntie_out = 0
            do code = 0, 3**n - 1
                c = code
                do i = 1, n
                    m(i) = mod(c, 3) - 1          ! -1, 0 (stuck), +1
                    c = c / 3
                end do
                pp = 0.0_dp
                do i = 1, n
                    if (m(i) /= 0) pp(i) = -m(i) * laws(i)%mu_k * cap(i)
                end do
                ns = count(m(:n) == 0)
                call solve_free(n, m(:n) == 0, pp, ww, ok)
                if (.not. ok) cycle
                ok = .true.
                do i = 1, n
                    if (m(i) == 0) then
                        ok = ok .and. abs(pp(i)) <= laws(i)%mu_s * cap(i) * (1.0_dp + 1.0e-12_dp)
                        ww(i) = 0.0_dp
                    else
                        ok = ok .and. m(i) * ww(i) > 0.0_dp
                    end if
                end do
                if (.not. ok) cycle
                nsol = nsol + 1
                msol(:n) = m(:n)
                pb(:n) = pp(:n)
                wb(:n) = ww(:n)
                if (ns > count(mode(:n) == 0)) nbetter_out = nbetter_out + 1
                if (ns == count(mode(:n) == 0) .and. any(m(:n) /= mode(:n))) ntie_out = ntie_out + 1
            end do
        end subroutine brute_force

        !> The solver's rule (stickslip_contact_solver's notes), written here: a slip kept where
        !! mprev_i wf_i > D_ii mu_s c_i, every other contact at its static level; rounds of box
        !! problems (`box_brute`), a contact at its static level with w /= 0 giving way to mu_k,
        !! a kept slip whose w turns against it decided again from its static level (once); when
        !! no contact changes, each contact that gave way (and has not been raised back before) in
        !! turn at its static level with the others as they are: the first that holds there is
        !! raised back and the rounds go on. The modes in mref (0 stuck, +-1 slip).
        subroutine rule_reference(n, mprev, mref)
            integer, intent(in) :: n, mprev(:)
            integer, intent(out) :: mref(:)
            real(dp) :: bound(n), pp(n), yy(n), wtol, bt(n), pt(n), yt(n)
            logical :: kin(n), reset(n), changed, gave(n), tried(n)   ! tried: raised back once
            integer :: dir(n), i, round, sg
            kin = .false.
            reset = .false.
            gave = .false.
            tried = .false.
            dir = 0
            do i = 1, n
                if (abs(mprev(i)) == 1) then
                    if (mprev(i) * wf(i) > d(i, i) * laws(i)%mu_s * cap(i) * (1.0_dp + 1.0e-12_dp)) then
                        kin(i) = .true.
                        dir(i) = mprev(i)
                    end if
                end if
            end do
            do round = 1, 5 * n + 30
                do i = 1, n
                    bound(i) = cap(i) * merge(laws(i)%mu_k, laws(i)%mu_s, kin(i))
                end do
                call box_brute(n, bound, pp, yy)
                wtol = 1.0e-9_dp * (maxval(abs(wf(:n))) + maxval(abs(d(:n, :n))) * maxval(abs(pp)))
                changed = .false.
                do i = 1, n
                    if (abs(yy(i)) <= wtol) cycle
                    sg = nint(sign(1.0_dp, yy(i)))
                    if (.not. kin(i)) then
                        kin(i) = .true.
                        gave(i) = .true.
                        dir(i) = sg
                        changed = .true.
                    else if (sg /= dir(i)) then
                        if (.not. reset(i)) then
                            kin(i) = .false.
                            reset(i) = .true.
                            changed = .true.
                        else
                            dir(i) = sg
                        end if
                    end if
                end do
                if (changed) cycle
                do i = 1, n
                    if (.not. (gave(i) .and. kin(i)) .or. tried(i)) cycle
                    bt = bound
                    bt(i) = cap(i) * laws(i)%mu_s
                    call box_brute(n, bt, pt, yt)
                    if (abs(yt(i)) > 1.0e-9_dp * (maxval(abs(wf(:n))) + maxval(abs(d(:n, :n))) * maxval(abs(pt)))) &
                        cycle
                    tried(i) = .true.
                    kin(i) = .false.
                    dir(i) = 0
                    changed = .true.
                    exit
                end do
                if (.not. changed) exit
            end do
            do i = 1, n
                mref(i) = 0
                if (abs(yy(i)) > wtol) mref(i) = nint(sign(1.0_dp, yy(i)))
            end do
        end subroutine rule_reference

        !> The box problem |p_i| <= bound_i, y = wf + D p (y_i >= 0 at -bound, <= 0 at +bound,
        !! 0 between) by exhaustive search over the 3^n active sets (a regular free block solved
        !! by LU): the first set whose solution meets the conditions. Its y is the same at every
        !! solution.
        subroutine box_brute(n, bound, pp, yy)
            integer, intent(in) :: n
            real(dp), intent(in) :: bound(:)
            real(dp), intent(out) :: pp(:), yy(:)
            integer :: code, c, i, st(NBRUTE)
            real(dp) :: tl
            logical :: ok
            do code = 0, 3**n - 1
                c = code
                do i = 1, n
                    st(i) = mod(c, 3) - 1              ! -1 at -bound, 0 free, +1 at +bound
                    c = c / 3
                    pp(i) = st(i) * bound(i)
                end do
                call solve_free(n, st(:n) == 0, pp, yy, ok)
                if (.not. ok) cycle
                tl = 1.0e-10_dp * (maxval(abs(wf(:n))) + maxval(abs(d(:n, :n))) * maxval(abs(pp(:n))))
                ok = .true.
                do i = 1, n
                    select case (st(i))
                    case (0)
                        ok = ok .and. abs(pp(i)) <= bound(i) * (1.0_dp + 1.0e-12_dp)
                    case (1)
                        ok = ok .and. yy(i) <= tl
                    case default
                        ok = ok .and. yy(i) >= -tl
                    end select
                end do
                if (ok) return
            end do
            pp = huge(1.0_dp)          ! (not reached: the box problem always has a solution)
            yy = huge(1.0_dp)
        end subroutine box_brute

        !> With the entries of pp outside free fixed, the free ones from D_FF p_F = -(wf_F + D_FB p_B)
        !! by LU, and yy = wf + D pp. regular: .false. (pp, yy not formed) where D_FF has a pivot
        !! below 1e-10 of max|D|.
        subroutine solve_free(n, free, pp, yy, regular)
            integer, intent(in) :: n
            logical, intent(in) :: free(:)
            real(dp), intent(inout) :: pp(:)
            real(dp), intent(out) :: yy(:)
            logical, intent(out) :: regular
            integer :: fr(NBRUTE), nf, i, ipiv(NBRUTE), info
            real(dp) :: a(NBRUTE, NBRUTE), rhs(NBRUTE)
            nf = count(free(:n))
            fr(:nf) = pack([(i, i = 1, n)], free(:n))
            regular = .true.
            if (nf > 0) then
                where (free(:n)) pp(:n) = 0.0_dp
                a(:nf, :nf) = d(fr(:nf), fr(:nf))
                rhs(:nf) = -(wf(fr(:nf)) + matmul(d(fr(:nf), :n), pp(:n)))
                call lu_decompose(a(:nf, :nf), ipiv(:nf), info)
                regular = info == 0
                if (regular) regular = minval([(abs(a(i, i)), i = 1, nf)]) >= 1.0e-10_dp * maxval(abs(d(:n, :n)))
                if (.not. regular) return
                call lu_solve(a(:nf, :nf), ipiv(:nf), rhs(:nf))
                pp(fr(:nf)) = rhs(:nf)
            end if
            yy(:n) = wf(:n) + matmul(d(:n, :n), pp(:n))
        end subroutine solve_free

end program test_stickslip_contact_general
