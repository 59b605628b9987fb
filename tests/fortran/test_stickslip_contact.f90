!> Tests of the set-valued contact interface with more than one contact: two blocks on a
!! belt (block 1 tied to the wall by k1, block 2 to block 1 by kc, each with its own
!! Coulomb contact), written here as a user's own `contact_system`. Moreau-Jean (projected
!! Gauss-Seidel over a coupled 2 x 2 Delassus matrix) must converge to the event-driven
!! reference, hold stuck blocks at the belt speed exactly, and report its sweeps and
!! residual; the one-contact Stribeck solve must satisfy its equation to rounding.
!! Prints one line per check; exits with status 1 if any check fails.
module test_contact_chain
    use stickslip_kinds, only: dp
    use stickslip_contact, only: contact_system, contact_law
    implicit none
    private
    public :: two_blocks, make_two_blocks, two_blocks_tridiagonal

    !> Two blocks on a belt at v_b, springs k1 (wall - block 1) and kc (block 1 - block 2).
    type, extends(contact_system) :: two_blocks
        real(dp) :: m(2) = [1.0_dp, 1.5_dp]     !! masses [kg]
        real(dp) :: k1 = 100.0_dp               !! wall spring [N/m]
        real(dp) :: kc = 50.0_dp                !! coupling spring [N/m]
        real(dp) :: v_b = 0.5_dp                !! belt speed [m/s]
        real(dp) :: g = 9.81_dp                 !! gravity [m/s^2]
    contains
        procedure :: force => tb_force
        procedure :: solve_w => tb_solve_w
        procedure :: normal_forces => tb_normal
        procedure :: slip_offset => tb_offset
    end type two_blocks

    !> The same system saying that its W = M + a C + b K is tridiagonal (as the scene chain
    !! does), which lets event_driven take the holding forces from a diagonal Delassus matrix.
    type, extends(two_blocks) :: two_blocks_tridiagonal
    contains
        procedure :: w_tridiagonal => tb_w_tridiagonal
    end type two_blocks_tridiagonal

contains

    function make_two_blocks() result(s)
        type(two_blocks) :: s
        s%n_dof = 2
        s%n_c = 2
        ! gfortran -Wuninitialized on the components' descriptors: a false positive, each
        ! assignment below allocates its component
        s%h_ptr = [1, 2, 3]
        s%h_col = [1, 2]
        s%h_val = [1.0_dp, 1.0_dp]
        s%laws = [contact_law(mu_s=0.5_dp, mu_k=0.3_dp), contact_law(mu_s=0.45_dp, mu_k=0.25_dp)]
        s%w_constant = .true.
    end function make_two_blocks

    subroutine tb_force(self, t, q, u, f)
        class(two_blocks), intent(in) :: self
        real(dp), intent(in) :: t, q(:), u(:)
        real(dp), intent(out) :: f(:)
        f(1) = -self%k1 * q(1) + self%kc * (q(2) - q(1))
        f(2) = -self%kc * (q(2) - q(1))
    end subroutine tb_force

    subroutine tb_solve_w(self, t, q, u, a, b, x)
        class(two_blocks), intent(in) :: self
        real(dp), intent(in) :: t, q(:), u(:), a, b
        real(dp), intent(inout) :: x(:)
        real(dp) :: w11, w12, w22, det, x1
        w11 = self%m(1) + b * (self%k1 + self%kc)
        w12 = -b * self%kc
        w22 = self%m(2) + b * self%kc
        det = w11 * w22 - w12 * w12
        x1 = (w22 * x(1) - w12 * x(2)) / det
        x(2) = (w11 * x(2) - w12 * x(1)) / det
        x(1) = x1
    end subroutine tb_solve_w

    subroutine tb_normal(self, t, q, n)
        class(two_blocks), intent(in) :: self
        real(dp), intent(in) :: t, q(:)
        real(dp), intent(out) :: n(:)
        n = self%m * self%g
    end subroutine tb_normal

    subroutine tb_offset(self, t, b)
        class(two_blocks), intent(in) :: self
        real(dp), intent(in) :: t
        real(dp), intent(out) :: b(:)
        b = -self%v_b
    end subroutine tb_offset

    subroutine tb_w_tridiagonal(self, a, b, l, d, r, ok)
        class(two_blocks_tridiagonal), intent(in) :: self
        real(dp), intent(in)  :: a, b
        real(dp), intent(out) :: l(:), d(:), r(:)
        logical, intent(out)  :: ok
        d = [self%m(1) + b * (self%k1 + self%kc), self%m(2) + b * self%kc]
        l = -b * self%kc
        r = -b * self%kc
        ok = .true.
    end subroutine tb_w_tridiagonal

end module test_contact_chain

program test_stickslip_contact
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK, SS_DIVERGED
    use stickslip_ode, only: ode_stats
    use stickslip_contact, only: contact_law, local_solve, CONTACT_STRIBECK
    use stickslip_moreau, only: moreau_options, moreau_integrate
    use stickslip_event_driven, only: event_driven_options, event_driven_integrate
    use test_contact_chain, only: two_blocks, make_two_blocks, two_blocks_tridiagonal
    implicit none

    call test_two_blocks()
    call test_diagonal_delassus()
    call test_stribeck_local_solve()
    call test_state_bounds()
    call finish('contact')

contains

    subroutine test_two_blocks()
        type(two_blocks) :: sys
        type(moreau_options) :: mo
        type(event_driven_options) :: eo
        type(ode_stats) :: st, sr
        integer, parameter :: nout = 201
        real(dp) :: t_ref(nout), y_ref(4, nout), t_m(nout), y_m(4, nout), ev(4, 1000)
        real(dp) :: y0(4), err(3), hs(3)
        integer :: i, j, nstuck, nslip(2)
        character(len=160) :: line

        sys = make_two_blocks()
        y0 = [0.0_dp, 0.0_dp, sys%v_b, sys%v_b]     ! both stuck at rest length
        t_ref = [(5.0_dp * (i - 1) / (nout - 1), i = 1, nout)]
        eo%max_steps = 10000000_8
        call event_driven_integrate(sys, 0.0_dp, y0, 5.0_dp, [1.0e-11_dp], [1.0e-13_dp], eo, t_ref, y_ref, sr, ev)
        call check(sr%status == SS_OK, 'two blocks: event_driven runs')
        nslip = 0
        do i = 1, int(min(sr%nevents, 1000_8))
            if (nint(ev(2, i)) == 2) nslip(nint(ev(4, i))) = nslip(nint(ev(4, i))) + 1
        end do
        write (line, '(a, i0, a, 2(i0, 1x))') 'two blocks: events ', sr%nevents, ', stick->slip per block ', nslip
        call check(all(nslip >= 2), trim(line))

        hs = [2.0e-3_dp, 1.0e-3_dp, 5.0e-4_dp]
        do j = 1, 3
            mo%h = hs(j)
            t_m = t_ref
            call moreau_integrate(sys, 0.0_dp, y0, 5.0_dp, mo, t_m, y_m, st)
            call check(st%status == SS_OK, 'two blocks: moreau runs')
            err(j) = maxval(abs(y_m(1:2, :) - y_ref(1:2, :)))
            write (line, '(a, es9.2, a, i0, a, i0, a, es9.2)') 'two blocks: moreau h = ', hs(j), ' sweeps ', &
                st%ncontact_iter, ' steps ', st%nstep, ' residual ', st%contact_residual
            call check(st%contact_residual <= mo%contact_tol .and. st%ncontact_iter > st%nstep, trim(line))
            ! stuck blocks move with the belt exactly
            nstuck = count(abs(y_m(3:4, 2:) - sys%v_b) < 1.0e-9_dp)
            call check(nstuck > 0 .and. count(abs(y_m(3:4, 2:) - sys%v_b) < 1.0e-9_dp .and. &
                       y_m(3:4, 2:) /= sys%v_b) == 0, 'two blocks: stuck velocities are v_b exactly')
        end do
        write (line, '(a, 3es10.2)') 'two blocks: moreau position errors against event_driven ', err
        call check(err(3) < 2.0e-3_dp .and. err(1) / err(3) > 2.5_dp, trim(line))
    end subroutine test_two_blocks

    !> The bounds a caller gives moreau and event_driven (y_bound of their options; the
    !! registry sets them from the scene's state_bound): a run that stays inside them is the
    !! run without them, bit for bit; with block 1's bound at half its largest excursion the
    !! run ends with SS_DIVERGED before t_end.
    subroutine test_state_bounds()
        type(two_blocks) :: sys
        type(moreau_options) :: mo, mb
        type(event_driven_options) :: eo, eb
        type(ode_stats) :: s0, s1
        integer, parameter :: nout = 101
        real(dp) :: t0(nout), y0r(4, nout), t1(nout), y1r(4, nout), ev(4, 1000), y0(4), xmax, big
        integer :: i
        sys = make_two_blocks()
        y0 = [0.0_dp, 0.0_dp, sys%v_b, sys%v_b]
        big = huge(1.0_dp)
        t0 = [(2.0_dp * (i - 1) / (nout - 1), i = 1, nout)]
        mo%h = 1.0e-3_dp
        call moreau_integrate(sys, 0.0_dp, y0, 2.0_dp, mo, t0, y0r, s0)
        xmax = maxval(abs(y0r(1, :)))
        mb = mo
        mb%y_bound = [10.0_dp * xmax, big, big, big]
        t1 = t0
        call moreau_integrate(sys, 0.0_dp, y0, 2.0_dp, mb, t1, y1r, s1)
        call check(s0%status == SS_OK .and. s1%status == SS_OK .and. all(y1r == y0r) .and. &
                   s1%nstep == s0%nstep, 'moreau: inside its bounds, the run without them bit for bit')
        mb%y_bound(1) = 0.5_dp * xmax
        call moreau_integrate(sys, 0.0_dp, y0, 2.0_dp, mb, t1, y1r, s1)
        call check(s1%status == SS_DIVERGED .and. s1%t_reached < 2.0_dp .and. &
                   all(abs(y1r(1, :s1%n_written)) <= 0.5_dp * xmax), 'moreau: beyond its bound: SS_DIVERGED')
        call event_driven_integrate(sys, 0.0_dp, y0, 2.0_dp, [1.0e-9_dp], [1.0e-11_dp], eo, t0, y0r, s0, ev)
        eb = eo
        eb%y_bound = [10.0_dp * xmax, big, big, big]
        call event_driven_integrate(sys, 0.0_dp, y0, 2.0_dp, [1.0e-9_dp], [1.0e-11_dp], eb, t1, y1r, s1, ev)
        call check(s0%status == SS_OK .and. s1%status == SS_OK .and. all(y1r == y0r) .and. &
                   s1%nstep == s0%nstep, 'event_driven: inside its bounds, the run without them bit for bit')
        eb%y_bound(1) = 0.5_dp * xmax
        call event_driven_integrate(sys, 0.0_dp, y0, 2.0_dp, [1.0e-9_dp], [1.0e-11_dp], eb, t1, y1r, s1, ev)
        call check(s1%status == SS_DIVERGED .and. s1%t_reached < 2.0_dp, 'event_driven: beyond its bound: SS_DIVERGED')
    end subroutine test_state_bounds

    !> event_driven's holding forces from the diagonal of the Delassus matrix (a system whose
    !! mass matrix is diagonal, contacts on coordinates of their own: O(n)) equal those of
    !! the dense solve bit for bit: the same run, every output value and counter.
    subroutine test_diagonal_delassus()
        type(two_blocks) :: dense
        type(two_blocks_tridiagonal) :: diag
        type(event_driven_options) :: eo
        type(ode_stats) :: s1, s2
        integer, parameter :: nout = 101
        real(dp) :: t1(nout), y1(4, nout), t2(nout), y2(4, nout), e1(4, 1000), e2(4, 1000), y0(4)
        integer :: i
        dense = make_two_blocks()
        diag%two_blocks = make_two_blocks()
        y0 = [0.0_dp, 0.0_dp, dense%v_b, dense%v_b]
        t1 = [(5.0_dp * (i - 1) / (nout - 1), i = 1, nout)]
        t2 = t1
        call event_driven_integrate(dense, 0.0_dp, y0, 5.0_dp, [1.0e-9_dp], [1.0e-11_dp], eo, t1, y1, s1, e1)
        call event_driven_integrate(diag, 0.0_dp, y0, 5.0_dp, [1.0e-9_dp], [1.0e-11_dp], eo, t2, y2, s2, e2)
        call check(s1%status == SS_OK .and. s2%status == SS_OK .and. s1%nevents > 4, &
                   'diagonal Delassus: both runs complete, with events')
        call check(all(y1 == y2) .and. s1%nfev == s2%nfev .and. s1%nstep == s2%nstep .and. &
                   s1%nevents == s2%nevents, 'diagonal Delassus: the same run as the dense solve, bit for bit')
    end subroutine test_diagonal_delassus

    subroutine test_stribeck_local_solve()
        type(contact_law) :: cl
        real(dp) :: w, p, wf, d, hn
        integer :: i
        logical :: ok
        cl = contact_law(kind=CONTACT_STRIBECK, mu_s=0.5_dp, mu_k=0.3_dp, v_s=0.01_dp, delta=2.0_dp, c_v=0.02_dp)
        ok = .true.
        do i = 1, 50
            wf = -2.0_dp + 4.0_dp * (i - 0.5_dp) / 50.0_dp
            d = 0.7_dp
            hn = 1.0e-2_dp * 9.81_dp
            call local_solve(cl, wf, d, hn, w, p)
            if (abs(wf) <= d * hn * cl%mu_s) then
                ok = ok .and. w == 0.0_dp .and. abs(wf + d * p) <= 4.0_dp * epsilon(1.0_dp) * abs(wf)
            else
                ! w = wf + d p, p = -sign(w) hn mu(|w|), sign(w) = sign(wf)
                ok = ok .and. sign(1.0_dp, w) == sign(1.0_dp, wf) .and. &
                     abs(w - (wf + d * p)) <= 8.0_dp * epsilon(1.0_dp) * abs(wf) .and. &
                     abs(p + sign(hn * cl%slip_mu(abs(w)), w)) <= 8.0_dp * epsilon(1.0_dp) * hn
            end if
        end do
        call check(ok, 'stribeck one-contact solve: stick inside the cone, slip equation to rounding')
    end subroutine test_stribeck_local_solve

end program test_stickslip_contact
