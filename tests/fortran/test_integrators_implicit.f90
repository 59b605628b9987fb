!> Fortran tests of the implicit integrators (RADAU5, generalized-alpha, backward Euler)
!! against independent truths: Hairer's radau5.f (1996 version, corrections of 2002) run on
!! Van der Pol and Robertson, observed convergence orders, A-stability, the exact numerical
!! damping of backward Euler and the amplification matrix of generalized-alpha, bad inputs
!! and run-time failures. Prints one line per check; exits with status 1 if any check fails.
module implicit_problems
    use stickslip_kinds, only: dp
    use stickslip_ode, only: ode_system
    implicit none
    private
    public :: vdp, robertson, linear, oscillator2, signum, nanjac, tjump, wrapped, prothero

    !> Prothero-Robinson's y' = -lambda (y - cos t) - sin t, exact solution
    !! y = cos t + (y0 - 1) exp(-lambda t): a stiff linear system whose slow manifold is cos t.
    type, extends(ode_system) :: prothero
        real(dp) :: lambda = 1.0_dp
    contains
        procedure :: rhs => prothero_rhs
        procedure :: jacobian => prothero_jac
    end type prothero

    !> Van der Pol, eps y2' = (1 - y1^2) y2 - y1, with its analytic Jacobian (Hairer's dr1_radau5).
    type, extends(ode_system) :: vdp
        real(dp) :: eps = 1.0e-6_dp
    contains
        procedure :: rhs => vdp_rhs
        procedure :: jacobian => vdp_jac
    end type vdp

    !> Robertson's chemical kinetics, with its analytic Jacobian.
    type, extends(ode_system) :: robertson
    contains
        procedure :: rhs => rob_rhs
        procedure :: jacobian => rob_jac
    end type robertson

    !> y' = lambda y (scalar), analytic Jacobian.
    type, extends(ode_system) :: linear
        real(dp) :: lambda = -1.0_dp
    contains
        procedure :: rhs => linear_rhs
        procedure :: jacobian => linear_jac
    end type linear

    !> x'' = -w^2 x as (x, v), analytic Jacobian.
    type, extends(ode_system) :: oscillator2
        real(dp) :: w = 1.0_dp
    contains
        procedure :: rhs => osc_rhs
        procedure :: jacobian => osc_jac
    end type oscillator2

    !> y' = -sign(y): no backward-Euler solution for large h (Newton cannot converge).
    type, extends(ode_system) :: signum
    contains
        procedure :: rhs => signum_rhs
    end type signum

    !> y' = -y with a Jacobian full of NaN.
    type, extends(ode_system) :: nanjac
    contains
        procedure :: rhs => nanjac_rhs
        procedure :: jacobian => nanjac_jac
    end type nanjac

    !> y' = 0 before t = 0.5 and 1000 after (a jump the error control cannot resolve).
    type, extends(ode_system) :: tjump
    contains
        procedure :: rhs => tjump_rhs
    end type tjump

    !> Another system's right-hand side and Jacobian through its bindings: a built-in scene
    !! wrapped so that the integrators run their generic kernel on it.
    type, extends(ode_system) :: wrapped
        class(ode_system), allocatable :: inner
    contains
        procedure :: rhs => wrapped_rhs
        procedure :: jacobian => wrapped_jac
    end type wrapped

contains

    subroutine vdp_rhs(self, t, y, dydt)
        class(vdp), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt(1) = y(2)
        dydt(2) = ((1.0_dp - y(1)**2) * y(2) - y(1)) / self%eps
    end subroutine vdp_rhs

    subroutine vdp_jac(self, t, y, f, dfdy, nfev)
        class(vdp), intent(inout) :: self
        real(dp), intent(in) :: t, y(:), f(:)
        real(dp), intent(out) :: dfdy(:, :)
        integer(8), intent(inout) :: nfev
        dfdy(1, :) = [0.0_dp, 1.0_dp]
        dfdy(2, :) = [(-2.0_dp * y(1) * y(2) - 1.0_dp) / self%eps, (1.0_dp - y(1)**2) / self%eps]
    end subroutine vdp_jac

    subroutine rob_rhs(self, t, y, dydt)
        class(robertson), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt(1) = -0.04_dp * y(1) + 1.0e4_dp * y(2) * y(3)
        dydt(3) = 3.0e7_dp * y(2)**2
        dydt(2) = -dydt(1) - dydt(3)
    end subroutine rob_rhs

    subroutine rob_jac(self, t, y, f, dfdy, nfev)
        class(robertson), intent(inout) :: self
        real(dp), intent(in) :: t, y(:), f(:)
        real(dp), intent(out) :: dfdy(:, :)
        integer(8), intent(inout) :: nfev
        dfdy(1, :) = [-0.04_dp, 1.0e4_dp * y(3), 1.0e4_dp * y(2)]
        dfdy(3, :) = [0.0_dp, 6.0e7_dp * y(2), 0.0_dp]
        dfdy(2, :) = -dfdy(1, :) - dfdy(3, :)
    end subroutine rob_jac

    subroutine linear_rhs(self, t, y, dydt)
        class(linear), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = self%lambda * y
    end subroutine linear_rhs

    subroutine linear_jac(self, t, y, f, dfdy, nfev)
        class(linear), intent(inout) :: self
        real(dp), intent(in) :: t, y(:), f(:)
        real(dp), intent(out) :: dfdy(:, :)
        integer(8), intent(inout) :: nfev
        dfdy = self%lambda
    end subroutine linear_jac

    subroutine osc_rhs(self, t, y, dydt)
        class(oscillator2), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt(1) = y(2)
        dydt(2) = -self%w**2 * y(1)
    end subroutine osc_rhs

    subroutine osc_jac(self, t, y, f, dfdy, nfev)
        class(oscillator2), intent(inout) :: self
        real(dp), intent(in) :: t, y(:), f(:)
        real(dp), intent(out) :: dfdy(:, :)
        integer(8), intent(inout) :: nfev
        dfdy(1, :) = [0.0_dp, 1.0_dp]
        dfdy(2, :) = [-self%w**2, 0.0_dp]
    end subroutine osc_jac

    subroutine signum_rhs(self, t, y, dydt)
        class(signum), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = -sign(1.0_dp, y)
    end subroutine signum_rhs

    subroutine nanjac_rhs(self, t, y, dydt)
        class(nanjac), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = -y
    end subroutine nanjac_rhs

    subroutine nanjac_jac(self, t, y, f, dfdy, nfev)
        use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
        class(nanjac), intent(inout) :: self
        real(dp), intent(in) :: t, y(:), f(:)
        real(dp), intent(out) :: dfdy(:, :)
        integer(8), intent(inout) :: nfev
        dfdy = ieee_value(1.0_dp, ieee_quiet_nan)
    end subroutine nanjac_jac

    subroutine tjump_rhs(self, t, y, dydt)
        class(tjump), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = merge(1000.0_dp, 0.0_dp, t > 0.5_dp)
    end subroutine tjump_rhs

    subroutine wrapped_rhs(self, t, y, dydt)
        class(wrapped), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        call self%inner%rhs(t, y, dydt)
    end subroutine wrapped_rhs

    subroutine wrapped_jac(self, t, y, f, dfdy, nfev)
        class(wrapped), intent(inout) :: self
        real(dp), intent(in) :: t, y(:), f(:)
        real(dp), intent(out) :: dfdy(:, :)
        integer(8), intent(inout) :: nfev
        call self%inner%jacobian(t, y, f, dfdy, nfev)
    end subroutine wrapped_jac

    subroutine prothero_rhs(self, t, y, dydt)
        class(prothero), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = -self%lambda * (y - cos(t)) - sin(t)
    end subroutine prothero_rhs

    subroutine prothero_jac(self, t, y, f, dfdy, nfev)
        class(prothero), intent(inout) :: self
        real(dp), intent(in) :: t, y(:), f(:)
        real(dp), intent(out) :: dfdy(:, :)
        integer(8), intent(inout) :: nfev
        dfdy = -self%lambda
    end subroutine prothero_jac

end module implicit_problems

program test_integrators_implicit
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_H, SS_BAD_RHO_INF, SS_BAD_NIT, SS_BAD_NEWTON_TOL, &
                               SS_BAD_RADAU5_CONTROL, SS_BAD_RTOL_POSITIVE, SS_BAD_ATOL, SS_BAD_HMIN, &
                               SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE, SS_STEP_BUDGET, SS_DIVERGED, &
                               SS_STEP_TOO_SMALL, SS_OUTPUT_FULL
    use stickslip_registry, only: stickslip_message, new_system, SCENE_TABLE
    use stickslip_laws, only: LAW_COULOMB, LAW_STRIBECK
    use stickslip_params, only: param_values, NAME_LEN
    use stickslip_model_system, only: model_system
    use stickslip_ode, only: ode_stats
    use stickslip_radau5, only: radau5_options, radau5_integrate, radau5_t, radau5_ti
    use stickslip_galpha, only: galpha_options, galpha_integrate, galpha_parameters
    use stickslip_implicit_euler, only: implicit_euler_options, implicit_euler_integrate
    use stickslip_ode, only: step_count
    use implicit_problems
    implicit none


    call test_radau5_hairer()
    call test_orders()
    call test_a_stability()
    call test_damping()
    call test_bad_inputs()
    call test_failures()
    call test_output_and_budget()
    call test_kernels_match_generic()
    call test_band_lu()
    call test_lu_two_rows()
    call test_stiff_newton()

    call finish('implicit')

contains

    !> The band LU (stickslip_linalg band_decompose/band_solve) against the dense LU on band
    !! matrices with small diagonals, so that partial pivoting swaps rows and fills in: real
    !! and complex, the residual |A x - b| and the dense solution.
    subroutine test_band_lu()
        use stickslip_linalg, only: lu_decompose, lu_solve, band_decompose, band_solve
        integer, parameter :: n = 17, ml = 3, mu = 2
        real(dp) :: a(n, n), ab(2 * ml + mu + 1, n), b(n), xd(n), xb(n), r(n, n)
        complex(dp) :: ca(n, n), cab(2 * ml + mu + 1, n), cb(n), cxd(n), cxb(n)
        integer :: ipd(n), ipb(n), info_d, info_b, i, j
        call random_seed(put=[(12345 + i, i = 1, 64)])
        call random_number(r)
        a = 0.0_dp
        do j = 1, n
            do i = max(1, j - mu), min(n, j + ml)
                a(i, j) = r(i, j) - 0.5_dp
                if (i == j) a(i, j) = 0.1_dp * a(i, j)   ! small pivots: rows must swap
            end do
        end do
        b = [(sin(real(i, dp)), i = 1, n)]
        ab = 0.0_dp
        do j = 1, n
            do i = max(1, j - mu), min(n, j + ml)
                ab(ml + mu + 1 + i - j, j) = a(i, j)
            end do
        end do
        call band_decompose(ab, ml, mu, ipb, info_b)
        xb = b
        call band_solve(ab, ml, mu, ipb, xb)
        r = a
        call lu_decompose(r, ipd, info_d)
        xd = b
        call lu_solve(r, ipd, xd)
        call check(info_b == 0 .and. info_d == 0, 'band lu: decompositions succeed')
        call check(any(ipb /= [(i, i = 1, n)]), 'band lu: rows were interchanged')
        call check(maxval(abs(matmul(a, xb) - b)) < 1.0e-11_dp, 'band lu: residual of the real solve')
        ! the dense LU once swapped the multipliers of earlier columns as well, which its
        ! interleaved substitution does not expect: residual 3.5 on this matrix
        call check(maxval(abs(matmul(a, xd) - b)) < 1.0e-11_dp, 'dense lu: residual with interchanges after column 1')
        call check(maxval(abs(xb - xd)) < 1.0e-10_dp * maxval(abs(xd)), 'band lu: real solve = dense solve')
        ca = cmplx(a, 0.3_dp * transpose(a), kind=dp)
        do j = 1, n
            do i = 1, n
                if (i < j - mu .or. i > j + ml) ca(i, j) = (0.0_dp, 0.0_dp)
            end do
        end do
        cb = cmplx(b, cos(b), kind=dp)
        cab = (0.0_dp, 0.0_dp)
        do j = 1, n
            do i = max(1, j - mu), min(n, j + ml)
                cab(ml + mu + 1 + i - j, j) = ca(i, j)
            end do
        end do
        call band_decompose(cab, ml, mu, ipb, info_b)
        cxb = cb
        call band_solve(cab, ml, mu, ipb, cxb)
        call lu_decompose(ca, ipd, info_d)
        cxd = cb
        call lu_solve(ca, ipd, cxd)
        call check(info_b == 0 .and. info_d == 0, 'band lu: complex decompositions succeed')
        call check(maxval(abs(cxb - cxd)) < 1.0e-10_dp * maxval(abs(cxd)), 'band lu: complex solve = dense solve')
        ! a singular band matrix: a zero column is reported, not solved
        ab = 0.0_dp
        ab(ml + mu + 1, :) = 1.0_dp
        ab(ml + mu + 1, 5) = 0.0_dp
        call band_decompose(ab, ml, mu, ipb, info_b)
        call check(info_b == 5, 'band lu: a zero column is reported (info = its index)')
    end subroutine test_band_lu

    !> The dense LU's two-row path (unrolled) against its loop: A embedded as the leading block
    !! of diag(A, 1), which the loop factorises with the same operations on that block (the third
    !! row and column only add zeros), so that its factors, interchanges and solution must
    !! equal the two-row path's bit for bit: real and complex, with and without an interchange,
    !! and the failures (a zero first column: info 1; a singular matrix: info 2).
    subroutine test_lu_two_rows()
        use stickslip_linalg, only: lu_decompose, lu_solve
        real(dp) :: a2(2, 2), a3(3, 3), b2(2), b3(3), r(2, 2)
        complex(dp) :: c2(2, 2), c3(3, 3), d2(2), d3(3)
        integer :: ip2(2), ip3(3), info2, info3, trial, i
        logical :: same, swapped
        call random_seed(put=[(777 + i, i = 1, 64)])
        same = .true.
        swapped = .false.
        do trial = 1, 200
            call random_number(r)
            a2 = r - 0.5_dp
            if (mod(trial, 3) == 0) a2(1, 1) = 1.0e-3_dp * a2(1, 1)     ! an interchange
            a3 = 0.0_dp
            a3(1:2, 1:2) = a2
            a3(3, 3) = 1.0_dp
            b2 = [sin(real(trial, dp)), cos(real(trial, dp))]
            b3 = [b2, 0.0_dp]
            call lu_decompose(a2, ip2, info2)
            call lu_decompose(a3, ip3, info3)
            call lu_solve(a2, ip2, b2)
            call lu_solve(a3, ip3, b3)
            same = same .and. info2 == 0 .and. info3 == 0 .and. all(ip2 == ip3(1:2)) .and. &
                   all(a2 == a3(1:2, 1:2)) .and. all(b2 == b3(1:2))
            swapped = swapped .or. ip2(1) == 2
            c2 = cmplx(r - 0.5_dp, transpose(r) - 0.25_dp, kind=dp)
            c3 = (0.0_dp, 0.0_dp)
            c3(1:2, 1:2) = c2
            c3(3, 3) = (1.0_dp, 0.0_dp)
            d2 = cmplx(b2, 1.0_dp, kind=dp)
            d3 = [d2, (0.0_dp, 0.0_dp)]
            call lu_decompose(c2, ip2, info2)
            call lu_decompose(c3, ip3, info3)
            call lu_solve(c2, ip2, d2)
            call lu_solve(c3, ip3, d3)
            same = same .and. info2 == 0 .and. info3 == 0 .and. all(ip2 == ip3(1:2)) .and. &
                   all(c2 == c3(1:2, 1:2)) .and. all(d2 == d3(1:2))
        end do
        call check(same .and. swapped, 'dense lu: two rows unrolled = the loop on diag(A, 1), bit for bit')
        a2 = reshape([0.0_dp, 0.0_dp, 1.0_dp, 2.0_dp], [2, 2])
        call lu_decompose(a2, ip2, info2)
        call check(info2 == 1, 'dense lu: two rows, a zero first column is reported (info 1)')
        a2 = reshape([1.0_dp, 2.0_dp, 2.0_dp, 4.0_dp], [2, 2])
        call lu_decompose(a2, ip2, info2)
        call check(info2 == 2 .and. ip2(1) == 2, 'dense lu: two rows, a singular matrix is reported (info 2)')
    end subroutine test_lu_two_rows

    !> Hairer's radau5.f (version of July 9, 1996, latest correction January 18, 2002;
    !! decsol.f and dc_decsol.f as distributed with it), built with gfortran 12 -O2 and run
    !! with an analytic Jacobian, full matrices, default WORK/IWORK (NIT = 7, THET = 0.001,
    !! QUOT1 = 1, QUOT2 = 1.2, FACL/FACR 5 and 1/8, Gustafsson control) and H = 1e-6.
    !! Counters IWORK(14..20): NFCN NJAC NSTEP NACCPT NREJCT NDEC NSOL, and y(x_end).
    !! The first row is also the published output of Hairer's dr1_radau5 example.
    subroutine test_radau5_hairer()
        type(vdp) :: v
        type(robertson) :: r
        type(radau5_options) :: o
        type(ode_stats) :: st
        real(dp) :: to(1), y2(2, 1), y3(3, 1), eye(3, 3)
        integer :: i
        ! Van der Pol, eps = 1e-6, y0 = (2, -0.66), x in [0, 2], rtol = atol = tol (ITOL = 0).
        real(dp), parameter :: vtol(2) = [1.0e-4_dp, 1.0e-7_dp]
        integer(8), parameter :: vcnt(7, 2) = reshape([2218_8, 161_8, 275_8, 238_8, 8_8, 248_8, 660_8, &
                                                       5647_8, 431_8, 702_8, 693_8, 8_8, 582_8, 1651_8], [7, 2])
        real(dp), parameter :: vy(2, 2) = reshape([1.70616110055875470_dp, -8.92807477681565320e-1_dp, &
                                                   1.70616742146845524_dp, -8.92810031799688097e-1_dp], [2, 2])
        ! Robertson, y0 = (1, 0, 0), rtol = (1e-6, 1e-5, 1e-6), atol = (1e-8, 1e-12, 1e-8) (ITOL = 1),
        ! x_end = 1e5 and 1e11.
        real(dp), parameter :: rtend(2) = [1.0e5_dp, 1.0e11_dp]
        real(dp), parameter :: ratol(3) = [1.0e-8_dp, 1.0e-12_dp, 1.0e-8_dp]
        integer(8), parameter :: rcnt(7, 2) = reshape([808_8, 97_8, 107_8, 106_8, 1_8, 106_8, 234_8, &
                                                       1306_8, 157_8, 170_8, 166_8, 1_8, 169_8, 380_8], [7, 2])
        real(dp), parameter :: ry(3, 2) = reshape([1.78659221745263927e-2_dp, 7.27475189687370855e-8_dp, &
                                                   9.82134005077954675e-1_dp, &
                                                   2.07910404297521749e-8_dp, 8.31641634274826492e-14_dp, &
                                                   9.99999979208876733e-1_dp], [3, 2])
        character(len=80) :: label

        eye = 0.0_dp
        do i = 1, 3
            eye(i, i) = 1.0_dp
        end do
        call check(maxval(abs(matmul(radau5_t, radau5_ti) - eye)) < 1.0e-14_dp, 'radau5: T TI = I')

        do i = 1, 2
            to = 2.0_dp
            call radau5_integrate(v, 0.0_dp, [2.0_dp, -0.66_dp], 2.0_dp, [vtol(i)], [vtol(i)], o, to, y2, st)
            write (label, '(a, es8.1)') 'radau5 vdp tol', vtol(i)
            print '(a, a, 7(1x, i0), 2es24.15)', trim(label), ': nfev njac nstep naccept nreject ndec nsol y =', &
                st%nfev, st%njac, st%nstep, st%naccept, st%nreject, st%ndec, st%nsol, y2(:, 1)
            call check(st%status == SS_OK .and. all([st%nfev, st%njac, st%nstep, st%naccept, st%nreject, &
                       st%ndec, st%nsol] == vcnt(:, i)), trim(label) // ': counters equal to radau5.f')
            ! 1e-10 relative: rounding in the LU and the 20-digit constants differ from Hairer's.
            call check(all(abs(y2(:, 1) - vy(:, i)) <= 1.0e-10_dp * abs(vy(:, i))), &
                       trim(label) // ': y(2) equal to radau5.f within 1e-10 relative')
        end do
        do i = 1, 2
            to = rtend(i)
            call radau5_integrate(r, 0.0_dp, [1.0_dp, 0.0_dp, 0.0_dp], rtend(i), [1.0e-6_dp, 1.0e-5_dp, 1.0e-6_dp], &
                                  ratol, o, to, y3, st)
            write (label, '(a, es8.1)') 'radau5 robertson t_end', rtend(i)
            print '(a, a, 7(1x, i0), 3es24.15)', trim(label), ': nfev njac nstep naccept nreject ndec nsol y =', &
                st%nfev, st%njac, st%nstep, st%naccept, st%nreject, st%ndec, st%nsol, y3(:, 1)
            call check(st%status == SS_OK .and. all([st%nfev, st%njac, st%nstep, st%naccept, st%nreject, &
                       st%ndec, st%nsol] == rcnt(:, i)), trim(label) // ': counters equal to radau5.f')
            ! 1e-10 relative, or a millionth of atol for the tiny components after 170 steps to 1e11.
            call check(all(abs(y3(:, 1) - ry(:, i)) <= 1.0e-10_dp * abs(ry(:, i)) + 1.0e-6_dp * ratol), &
                       trim(label) // ': y equal to radau5.f within 1e-10 relative (or 1e-6 atol)')
        end do
    end subroutine test_radau5_hairer

    !> Observed orders on x'' = -x, x(0) = 1, x'(0) = 0, at t = 2 (exact: cos, -sin).
    subroutine test_orders()
        type(oscillator2) :: s
        type(radau5_options) :: ro
        type(galpha_options) :: go
        type(implicit_euler_options) :: eo
        type(ode_stats) :: st
        real(dp) :: to(1), yo(2, 1), err(3), hs(3), p1, p2
        integer :: i
        logical :: fixed
        real(dp), parameter :: tend = 2.0_dp

        ! RADAU5 held at fixed steps (h0 = hmax = h, loose tolerances so no step is rejected;
        ! on a linear problem one simplified Newton iteration with the exact Jacobian is exact).
        hs = [0.25_dp, 0.125_dp, 0.0625_dp]   ! binary fractions: t reaches t_end exactly
        fixed = .true.
        do i = 1, 3
            ro%h0 = hs(i)
            ro%hmax = hs(i)
            to = tend
            call radau5_integrate(s, 0.0_dp, [1.0_dp, 0.0_dp], tend, [0.5_dp], [0.5_dp], ro, to, yo, st)
            if (st%status /= SS_OK) print '(a, i0)', 'radau5 order run status ', st%status
            fixed = fixed .and. st%status == SS_OK .and. st%naccept == nint(tend / hs(i)) .and. st%nstep == st%naccept
            err(i) = norm2(yo(:, 1) - [cos(tend), -sin(tend)])
        end do
        p1 = log(err(1) / err(2)) / log(2.0_dp)
        p2 = log(err(2) / err(3)) / log(2.0_dp)
        print '(a, 3es10.2, a, 2f6.2)', 'radau5 order: errors', err, '  orders', p1, p2
        call check(fixed, 'radau5 order test: every step at h (no rejection)')
        call check(abs(p1 - 5.0_dp) < 0.3_dp .and. abs(p2 - 5.0_dp) < 0.3_dp, 'radau5: observed order 5')

        hs = [0.1_dp, 0.05_dp, 0.025_dp]
        do i = 1, 3
            go%h = hs(i)
            to = tend
            call galpha_integrate(s, 0.0_dp, [1.0_dp, 0.0_dp], tend, go, to, yo, st)
            err(i) = norm2(yo(:, 1) - [cos(tend), -sin(tend)])
        end do
        p1 = log(err(1) / err(2)) / log(2.0_dp)
        p2 = log(err(2) / err(3)) / log(2.0_dp)
        print '(a, 3es10.2, a, 2f6.2)', 'galpha order: errors', err, '  orders', p1, p2
        call check(st%status == SS_OK .and. abs(p1 - 2.0_dp) < 0.1_dp .and. abs(p2 - 2.0_dp) < 0.1_dp, &
                   'galpha (rho_inf 0.5): observed order 2')

        hs = [0.01_dp, 0.005_dp, 0.0025_dp]
        do i = 1, 3
            eo%h = hs(i)
            to = tend
            call implicit_euler_integrate(s, 0.0_dp, [1.0_dp, 0.0_dp], tend, eo, to, yo, st)
            err(i) = norm2(yo(:, 1) - [cos(tend), -sin(tend)])
        end do
        p1 = log(err(1) / err(2)) / log(2.0_dp)
        p2 = log(err(2) / err(3)) / log(2.0_dp)
        print '(a, 3es10.2, a, 2f6.2)', 'implicit euler order: errors', err, '  orders', p1, p2
        call check(st%status == SS_OK .and. abs(p1 - 1.0_dp) < 0.05_dp .and. abs(p2 - 1.0_dp) < 0.05_dp, &
                   'implicit euler: observed order 1')
    end subroutine test_orders

    !> y' = -1e6 y, y(0) = 1, h = 1e-2 (h lambda = -1e4) on [0, 1]: bounded and decaying.
    subroutine test_a_stability()
        type(linear) :: s
        type(radau5_options) :: ro
        type(galpha_options) :: go
        type(implicit_euler_options) :: eo
        type(ode_stats) :: st
        real(dp) :: to(200), yo(1, 200)
        s%lambda = -1.0e6_dp
        ro%h0 = 1.0e-2_dp
        ro%hmax = 1.0e-2_dp
        ro%every_step = .true.
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, [1.0e-6_dp], [1.0e-6_dp], ro, to, yo, st)
        call check(st%status == SS_OK .and. maxval(abs(yo(1, :st%n_written))) <= 1.0_dp .and. &
                   abs(yo(1, st%n_written)) < 1.0e-12_dp, 'radau5: A-stable at h lambda = -1e4 (bounded, decays)')
        go%h = 1.0e-2_dp
        go%every_step = .true.
        call galpha_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, go, to, yo, st)
        print '(a, es10.2, a, es10.2)', 'galpha stiff decay: max |y|', maxval(abs(yo(1, :st%n_written))), &
            '  |y(1)|', abs(yo(1, st%n_written))
        call check(st%status == SS_OK .and. st%n_written == 101 .and. maxval(abs(yo(1, :st%n_written))) <= 1.0_dp &
                   .and. abs(yo(1, st%n_written)) < 1.0e-12_dp, 'galpha: A-stable at h lambda = -1e4 (bounded, decays)')
        eo%h = 1.0e-2_dp
        eo%every_step = .true.
        call implicit_euler_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, eo, to, yo, st)
        call check(st%status == SS_OK .and. st%n_written == 101 .and. maxval(abs(yo(1, :st%n_written))) <= 1.0_dp &
                   .and. abs(yo(1, st%n_written)) < 1.0e-12_dp, 'implicit euler: A-stable at h lambda = -1e4')
    end subroutine test_a_stability

    !> Numerical damping on x'' = -w^2 x.
    subroutine test_damping()
        type(oscillator2) :: s
        type(implicit_euler_options) :: eo
        type(galpha_options) :: go
        type(ode_stats) :: st
        real(dp) :: to(1), yo(2, 1), amp, expect, h, rho_num, rho_mat, tend
        real(dp) :: tw(2), yw(2, 2)
        integer :: k
        real(dp), parameter :: whs(2) = [1.0_dp, 1.0e6_dp]

        ! Backward Euler: amplitude sqrt(x^2 + (v/w)^2) = A0 (1 + (w h)^2)^(-t/(2h)).
        s%w = 2.0_dp
        h = 0.05_dp
        tend = 10.0_dp
        eo%h = h
        to = tend
        call implicit_euler_integrate(s, 0.0_dp, [1.0_dp, 0.0_dp], tend, eo, to, yo, st)
        amp = sqrt(yo(1, 1)**2 + (yo(2, 1) / s%w)**2)
        expect = (1.0_dp + (s%w * h)**2)**(-tend / (2.0_dp * h))
        print '(a, 2es14.6)', 'implicit euler amplitude (measured, A0 (1+(wh)^2)^(-t/2h)):', amp, expect
        call check(st%status == SS_OK .and. abs(amp / expect - 1.0_dp) < 0.01_dp, &
                   'implicit euler: amplitude decay (1 + (w h)^2)^(-t/(2h)) within 1%')

        ! Generalized-alpha: decay per step, measured over steps 200..300, against the spectral
        ! radius of the amplification matrix at z = i w h. (At w h -> infinity both eigenvalues
        ! tend to -rho_inf, a near-Jordan pair: the n rho^n growth factor contributes
        ! (300/200)^(1/100) = 1.004, inside the 1%.) At w h = 1e6 the Newton tolerance is 1e-8:
        ! the residual of the second component is ~ eps (w h)^2 |x|, beyond 1e-10 relative.
        go%rho_inf = 0.5_dp
        go%h = 1.0_dp
        do k = 1, 2
            s%w = whs(k)
            tw = [200.0_dp, 300.0_dp]
            go%newton_rtol = merge(1.0e-8_dp, 1.0e-10_dp, k == 2)
            call galpha_integrate(s, 0.0_dp, [1.0_dp, 0.0_dp], 300.0_dp, go, tw, yw, st)
            rho_num = (sqrt(yw(1, 2)**2 + (yw(2, 2) / s%w)**2) / sqrt(yw(1, 1)**2 + (yw(2, 1) / s%w)**2))**(1.0_dp / 100.0_dp)
            rho_mat = spectral_radius(go%rho_inf, cmplx(0.0_dp, whs(k) * go%h, kind=dp))
            if (st%status /= SS_OK) print '(a, i0)', 'galpha damping run status ', st%status
            print '(a, es9.1, a, 2f12.8)', 'galpha w h =', whs(k), ': rho measured, from amplification matrix', &
                rho_num, rho_mat
            call check(st%status == SS_OK .and. abs(rho_num / rho_mat - 1.0_dp) < 0.01_dp, &
                       'galpha: measured damping per step = spectral radius of the amplification matrix (1%)')
        end do
        call check(abs(spectral_radius(0.5_dp, cmplx(0.0_dp, 1.0e10_dp, kind=dp)) - 0.5_dp) < 1.0e-3_dp .and. &
                   abs(spectral_radius(0.0_dp, cmplx(0.0_dp, 1.0e10_dp, kind=dp))) < 1.0e-3_dp .and. &
                   abs(spectral_radius(1.0_dp, cmplx(0.0_dp, 1.0e10_dp, kind=dp)) - 1.0_dp) < 1.0e-3_dp, &
                   'galpha: spectral radius -> rho_inf as w h -> infinity (rho_inf = 0, 0.5, 1)')
    end subroutine test_damping

    !> Spectral radius of the amplification matrix G of generalized-alpha on y' = lambda y,
    !! z = h lambda, acting on (y_n, h ydot_n). From the two equations of a step,
    !!   y1 - gamma w1 = y + (1 - gamma) w,
    !!   -z alpha_f y1 + alpha_m w1 = z (1 - alpha_f) y - (1 - alpha_m) w   (w = h ydot),
    !! G = L^-1 R with L = [[1, -gamma], [-z alpha_f, alpha_m]], R = [[1, 1 - gamma],
    !! [z (1 - alpha_f), alpha_m - 1]]; eigenvalues from trace and determinant.
    function spectral_radius(rho_inf, z) result(rho)
        real(dp), intent(in) :: rho_inf
        complex(dp), intent(in) :: z
        real(dp) :: rho, am, af, ga
        complex(dp) :: l(2, 2), r(2, 2), li(2, 2), g(2, 2), tr, det, disc
        call galpha_parameters(rho_inf, am, af, ga)
        l = reshape([(1.0_dp, 0.0_dp), -z * af, cmplx(-ga, 0.0_dp, dp), cmplx(am, 0.0_dp, dp)], [2, 2])
        r = reshape([(1.0_dp, 0.0_dp), z * (1.0_dp - af), cmplx(1.0_dp - ga, 0.0_dp, dp), cmplx(am - 1.0_dp, 0.0_dp, dp)], &
                    [2, 2])
        det = l(1, 1) * l(2, 2) - l(1, 2) * l(2, 1)
        li = reshape([l(2, 2), -l(2, 1), -l(1, 2), l(1, 1)], [2, 2]) / det
        g = matmul(li, r)
        tr = g(1, 1) + g(2, 2)
        det = g(1, 1) * g(2, 2) - g(1, 2) * g(2, 1)
        disc = sqrt(tr**2 - 4.0_dp * det)
        rho = max(abs((tr + disc) / 2.0_dp), abs((tr - disc) / 2.0_dp))
    end function spectral_radius

    subroutine test_bad_inputs()
        type(linear) :: s
        type(radau5_options) :: ro
        type(galpha_options) :: go
        type(implicit_euler_options) :: eo
        type(ode_stats) :: st
        real(dp) :: to(1), yo(1, 1)
        to = 1.0_dp
        eo%h = 0.0_dp
        call implicit_euler_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, eo, to, yo, st)
        call check(st%status == SS_BAD_H, 'implicit euler: h = 0 -> SS_BAD_H')
        eo%h = 0.1_dp
        eo%newton_max_iter = 0
        call implicit_euler_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, eo, to, yo, st)
        call check(st%status == SS_BAD_NIT, 'implicit euler: newton_max_iter = 0 -> SS_BAD_NIT')
        go%h = -1.0_dp
        call galpha_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, go, to, yo, st)
        call check(st%status == SS_BAD_H, 'galpha: h < 0 -> SS_BAD_H')
        go%h = 0.1_dp
        go%rho_inf = 1.5_dp
        call galpha_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, go, to, yo, st)
        call check(st%status == SS_BAD_RHO_INF, 'galpha: rho_inf = 1.5 -> SS_BAD_RHO_INF')
        go%rho_inf = -0.1_dp
        call galpha_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, go, to, yo, st)
        call check(st%status == SS_BAD_RHO_INF, 'galpha: rho_inf = -0.1 -> SS_BAD_RHO_INF')
        go%rho_inf = 0.5_dp
        go%newton_atol = 0.0_dp
        call galpha_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, go, to, yo, st)
        call check(st%status == SS_BAD_NEWTON_TOL, 'galpha: newton_atol = 0 -> SS_BAD_NEWTON_TOL')
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, [0.0_dp], [1.0e-6_dp], ro, to, yo, st)
        call check(st%status == SS_BAD_RTOL_POSITIVE, 'radau5: rtol = 0 -> SS_BAD_RTOL_POSITIVE')
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, [1.0_dp], [1.0e-6_dp], ro, to, yo, st)
        call check(st%status == SS_BAD_RTOL_POSITIVE, 'radau5: rtol = 1 -> SS_BAD_RTOL_POSITIVE')
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, [1.0e-6_dp], [0.0_dp], ro, to, yo, st)
        call check(st%status == SS_BAD_ATOL, 'radau5: atol = 0 -> SS_BAD_ATOL')
        ro%nit = 0
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, [1.0e-6_dp], [1.0e-6_dp], ro, to, yo, st)
        call check(st%status == SS_BAD_NIT, 'radau5: nit = 0 -> SS_BAD_NIT')
        ro%nit = 7
        ro%safety = 1.5_dp
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, [1.0e-6_dp], [1.0e-6_dp], ro, to, yo, st)
        call check(st%status == SS_BAD_RADAU5_CONTROL, 'radau5: safety = 1.5 -> SS_BAD_RADAU5_CONTROL')
        ro%safety = 0.9_dp
        ro%quot2 = 0.5_dp
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, [1.0e-6_dp], [1.0e-6_dp], ro, to, yo, st)
        call check(st%status == SS_BAD_RADAU5_CONTROL, 'radau5: quot2 = 0.5 -> SS_BAD_RADAU5_CONTROL')
        ro%quot2 = 1.2_dp
        ro%hmin = -1.0_dp
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, [1.0e-6_dp], [1.0e-6_dp], ro, to, yo, st)
        call check(st%status == SS_BAD_HMIN, 'radau5: hmin < 0 -> SS_BAD_HMIN')
        call check(index(stickslip_message(SS_BAD_RHO_INF), 'rho_inf') > 0 .and. &
                   index(stickslip_message(SS_BAD_RTOL_POSITIVE), 'rtol') > 0 .and. &
                   index(stickslip_message(SS_NEWTON_FAILED), 'Newton') > 0, 'messages name the parameter')
    end subroutine test_bad_inputs

    !> Run-time failures end with a clear status, never a hang or a NaN.
    subroutine test_failures()
        type(signum) :: sg
        type(nanjac) :: nj
        type(linear) :: s
        type(vdp) :: v
        type(radau5_options) :: ro
        type(galpha_options) :: go
        type(implicit_euler_options) :: eo
        type(ode_stats) :: st
        real(dp) :: to(1), yo(1, 1), y2(2, 1)
        to = 100.0_dp
        ! y' = -sign(y), y(0) = 1, h = 10: y1 = 1 - 10 sign(y1) has no solution.
        eo%h = 10.0_dp
        call implicit_euler_integrate(sg, 0.0_dp, [1.0_dp], 100.0_dp, eo, to, yo, st)
        call check(st%status == SS_NEWTON_FAILED .and. st%t_reached == 0.0_dp, &
                   'implicit euler: sign(y) at h = 10 -> SS_NEWTON_FAILED')
        go%h = 10.0_dp
        call galpha_integrate(sg, 0.0_dp, [1.0_dp], 100.0_dp, go, to, yo, st)
        call check(st%status == SS_NEWTON_FAILED, 'galpha: sign(y) at h = 10 -> SS_NEWTON_FAILED')
        call implicit_euler_integrate(nj, 0.0_dp, [1.0_dp], 100.0_dp, eo, to, yo, st)
        call check(st%status == SS_JAC_NONFINITE, 'implicit euler: NaN Jacobian -> SS_JAC_NONFINITE')
        call galpha_integrate(nj, 0.0_dp, [1.0_dp], 100.0_dp, go, to, yo, st)
        call check(st%status == SS_JAC_NONFINITE, 'galpha: NaN Jacobian -> SS_JAC_NONFINITE')
        call radau5_integrate(nj, 0.0_dp, [1.0_dp], 100.0_dp, [1.0e-6_dp], [1.0e-6_dp], ro, to, yo, st)
        call check(st%status == SS_JAC_NONFINITE, 'radau5: NaN Jacobian -> SS_JAC_NONFINITE')
        ! y' = 2 y with h = 0.5: I - h J = 0.
        s%lambda = 2.0_dp
        eo%h = 0.5_dp
        to = 1.0_dp
        call implicit_euler_integrate(s, 0.0_dp, [1.0_dp], 1.0_dp, eo, to, yo, st)
        call check(st%status == SS_SINGULAR, 'implicit euler: I - h J singular -> SS_SINGULAR')
        ! RADAU5 on sign(y) with a floor h_min: must end (any status), never hang.
        ro%hmin = 1.0e-3_dp
        to = 3.0_dp
        call radau5_integrate(sg, 0.0_dp, [1.0_dp], 3.0_dp, [1.0e-6_dp], [1.0e-6_dp], ro, to, yo, st)
        print '(a, i0, a, i0, a, es10.2)', 'radau5 sign(y), hmin 1e-3: status ', st%status, ' nstep ', st%nstep, &
            ' t_reached', st%t_reached
        call check(st%nstep < 100000 .and. (st%status == SS_OK .or. st%status == SS_NEWTON_FAILED), &
                   'radau5: sign(y) with h_min ends (OK or SS_NEWTON_FAILED)')
        ! Newton failure at h_min (VdP's fast transition needs steps far below 1e-2).
        ro%hmin = 1.0e-2_dp
        ro%nit = 1
        to = 2.0_dp
        call radau5_integrate(v, 0.0_dp, [2.0_dp, -0.66_dp], 2.0_dp, [1.0e-4_dp], [1.0e-4_dp], ro, to, y2, st)
        print '(a, i0, a, i0, a, es10.2, a, 2es10.2)', 'radau5 vdp nit 1, hmin 1e-2: status ', st%status, &
            ' nstep ', st%nstep, ' t_reached', st%t_reached, ' y', y2(:, 1)
        ! forced steps at h_min whose Newton iteration did not converge may leave the solution's
        ! bound (the default, 1e30 times |y0|): SS_DIVERGED is then the honest end
        call check(st%status == SS_NEWTON_FAILED .or. st%status == SS_OK .or. st%status == SS_DIVERGED, &
                   'radau5: nit = 1, h_min = 1e-2 ends (OK, SS_NEWTON_FAILED or SS_DIVERGED)')
    end subroutine test_failures

    subroutine test_output_and_budget()
        type(linear) :: s
        type(tjump) :: tj
        type(radau5_options) :: ro
        type(implicit_euler_options) :: eo
        type(galpha_options) :: go
        type(ode_stats) :: st
        real(dp) :: tg(5), yg(1, 5), te(20), ye(1, 20)
        integer :: i
        logical :: ok
        ! Grid output of RADAU5 by its collocation polynomial: y' = -y against exp(-t).
        s%lambda = -1.0_dp
        tg = [0.0_dp, 0.3_dp, 0.77_dp, 1.5_dp, 2.0_dp]
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 2.0_dp, [1.0e-9_dp], [1.0e-9_dp], ro, tg, yg, st)
        call check(st%status == SS_OK .and. st%n_written == 5 .and. maxval(abs(yg(1, :) - exp(-tg))) < 1.0e-7_dp, &
                   'radau5: grid output by dense output within 1e-7 of exp(-t)')
        ! Every-step output, and a full buffer.
        ro%every_step = .true.
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 2.0_dp, [1.0e-4_dp], [1.0e-4_dp], ro, te, ye, st)
        ok = st%status == SS_OK .and. st%n_written == st%naccept + 1 .and. te(st%n_written) == 2.0_dp
        do i = 2, st%n_written
            ok = ok .and. te(i) > te(i - 1) .and. abs(ye(1, i) - exp(-te(i))) < 1.0e-4_dp
        end do
        call check(ok, 'radau5: every-step output, last row at t_end')
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 2.0_dp, [1.0e-4_dp], [1.0e-4_dp], ro, te(1:3), ye(:, 1:3), st)
        call check(st%status == SS_OUTPUT_FULL .and. st%n_written == 3, 'radau5: full buffer -> SS_OUTPUT_FULL')
        ro%every_step = .false.
        ro%max_steps = 3
        call radau5_integrate(s, 0.0_dp, [1.0_dp], 2.0_dp, [1.0e-9_dp], [1.0e-9_dp], ro, tg, yg, st)
        call check(st%status == SS_STEP_BUDGET .and. st%nstep == 3, 'radau5: max_steps = 3 -> SS_STEP_BUDGET')
        ro%max_steps = 100000000_8
        ! A jump in f at t = 0.5 with h_min = 1e-2: forced steps, or SS_STEP_TOO_SMALL.
        ro%hmin = 1.0e-2_dp
        tg(1) = 1.0_dp
        call radau5_integrate(tj, 0.0_dp, [0.0_dp], 1.0_dp, [1.0e-8_dp], [1.0e-8_dp], ro, tg(1:1), yg(:, 1:1), st)
        print '(a, i0, a, i0, a, es12.4)', 'radau5 jump, hmin 1e-2, forced allowed: status ', st%status, &
            ' nforced ', st%nforced, ' y(1) ', yg(1, 1)
        call check(st%status == SS_OK .and. st%nforced >= 1 .and. abs(yg(1, 1) - 500.0_dp) < 10.0_dp, &
                   'radau5: forced steps at h_min through a jump (counted)')
        ro%allow_forced = .false.
        call radau5_integrate(tj, 0.0_dp, [0.0_dp], 1.0_dp, [1.0e-8_dp], [1.0e-8_dp], ro, tg(1:1), yg(:, 1:1), st)
        call check(st%status == SS_STEP_TOO_SMALL .and. st%t_reached < 0.5_dp + 1.0e-2_dp, &
                   'radau5: allow_forced = .false. -> SS_STEP_TOO_SMALL')

        ! Fixed-step grid: t0 = 1e6, t_end = t0 + 0.3, h = 0.1 is 3 steps, none of zero length.
        call check(step_count(1.0e6_dp, 1.0e6_dp + 0.3_dp, 0.1_dp) == 3.0_dp .and. &
                   step_count(0.0_dp, 1.0_dp, 0.3_dp) == 4.0_dp .and. &
                   step_count(0.0_dp, 1.0_dp, 2.0_dp) == 1.0_dp, 'fixed step count (no zero-length last step)')
        eo%h = 0.1_dp
        eo%every_step = .true.
        call implicit_euler_integrate(s, 1.0e6_dp, [1.0_dp], 1.0e6_dp + 0.3_dp, eo, te, ye, st)
        ok = st%status == SS_OK .and. st%n_written == 4 .and. te(4) == 1.0e6_dp + 0.3_dp
        do i = 2, st%n_written
            ok = ok .and. te(i) > te(i - 1)
        end do
        call check(ok, 'implicit euler: every step from t0 = 1e6, last row at t_end, no zero-length step')
        ! Grid output by cubic Hermite (y' = -y, h = 1e-3): within the method's error.
        eo%every_step = .false.
        eo%h = 1.0e-3_dp
        tg = [0.0_dp, 0.3005_dp, 0.77_dp, 1.5_dp, 2.0_dp]
        call implicit_euler_integrate(s, 0.0_dp, [1.0_dp], 2.0_dp, eo, tg, yg, st)
        call check(st%status == SS_OK .and. st%n_written == 5 .and. maxval(abs(yg(1, :) - exp(-tg))) < 1.0e-3_dp, &
                   'implicit euler: grid output within 1e-3 of exp(-t) at h = 1e-3')
        go%h = 1.0e-2_dp
        call galpha_integrate(s, 0.0_dp, [1.0_dp], 2.0_dp, go, tg, yg, st)
        call check(st%status == SS_OK .and. st%n_written == 5 .and. maxval(abs(yg(1, :) - exp(-tg))) < 1.0e-4_dp, &
                   'galpha: grid output within 1e-4 of exp(-t) at h = 1e-2')
        go%max_steps = 5
        call galpha_integrate(s, 0.0_dp, [1.0_dp], 2.0_dp, go, tg, yg, st)
        call check(st%status == SS_STEP_BUDGET .and. st%nstep == 5 .and. abs(st%t_reached - 0.05_dp) < 1.0e-15_dp, &
                   'galpha: max_steps = 5 -> SS_STEP_BUDGET at t = 5 h')
    end subroutine test_output_and_budget

    !> The specialised kernels of backward Euler and generalized-alpha (a built-in scene with a
    !! static law) give what the generic kernel gives on the same scene behind its bindings:
    !! every output value and every counter identical, in grid and every-step mode. (A law with
    !! modes, Coulomb, runs nonsmooth_kernel on a scene: see test_nonsmooth.)
    subroutine test_kernels_match_generic()
        class(model_system), allocatable :: scene
        type(wrapped) :: wrap
        type(param_values) :: p
        type(implicit_euler_options) :: eo
        type(galpha_options) :: go
        type(ode_stats) :: s1, s2
        real(dp) :: t1(301), y1(2, 301), t2(301), y2(2, 301), y0(2)
        integer :: isc, law, mode, meth, status, i
        logical :: ok
        ok = .true.
        do isc = 1, size(SCENE_TABLE)
            do law = LAW_COULOMB, LAW_STRIBECK
                status = new_system(isc, law, [character(len=NAME_LEN) ::], [real(dp) ::], scene, p)
                if (status /= SS_OK) ok = .false.
                if (scene%has_jumps()) cycle   ! (Coulomb: solved over its modes, no Newton kernel)
                if (allocated(wrap%inner)) deallocate(wrap%inner)
                allocate(wrap%inner, source=scene)
                y0 = [0.0_dp, 0.2_dp]
                do mode = 1, 2
                    do meth = 1, 2
                        eo%h = 1.0e-3_dp
                        go%h = 1.0e-3_dp
                        eo%every_step = mode == 2
                        go%every_step = mode == 2
                        t1 = [(real(i, dp), i = 0, 300)] / 1000.0_dp
                        t2 = t1
                        y1 = 0.0_dp
                        y2 = 0.0_dp
                        if (meth == 1) then
                            call implicit_euler_integrate(scene, 0.0_dp, y0, 0.3_dp, eo, t1, y1, s1)
                            call implicit_euler_integrate(wrap, 0.0_dp, y0, 0.3_dp, eo, t2, y2, s2)
                        else
                            call galpha_integrate(scene, 0.0_dp, y0, 0.3_dp, go, t1, y1, s1)
                            call galpha_integrate(wrap, 0.0_dp, y0, 0.3_dp, go, t2, y2, s2)
                        end if
                        if (.not. (all(t1 == t2) .and. all(y1 == y2) .and. s1%nfev == s2%nfev .and. &
                                   s1%njac == s2%njac .and. s1%ndec == s2%ndec .and. s1%nsol == s2%nsol .and. &
                                   s1%nstep == s2%nstep .and. s1%status == s2%status .and. &
                                   s1%n_written == s2%n_written .and. s1%t_reached == s2%t_reached .and. &
                                   s1%nstep > 0)) then
                            ok = .false.
                            print '(a, 3i3)', '  differs: scene, law, method ', isc, law, meth
                        end if
                    end do
                end do
            end do
        end do
        call check(ok, 'implicit_euler, galpha: specialised kernels = generic kernel (every value and counter)')
    end subroutine test_kernels_match_generic

    !> The Newton convergence test on y' = -lambda (y - cos t) - sin t from y0 = 2 (off the slow
    !! manifold), lambda = 1 .. 1e12, against the exact y = cos t + (y0 - 1) exp(-lambda t), for
    !! both fixed-step methods at h = 1e-2, 1e-3, 1e-4 on [0, 1]: every run completes, and its
    !! error at t = 1 is what the method's own error is (the bounds below), never a Newton
    !! failure. generalized-alpha's stage state is u + c h k with u ~ h ydot_n ~ h lambda: its
    !! rounding, eps h lambda, is what the convergence test must accept.
    subroutine test_stiff_newton()
        type(prothero) :: s
        type(galpha_options) :: go
        type(implicit_euler_options) :: eo
        type(ode_stats) :: st
        real(dp) :: to(1), yo(1, 1), exact, err(3, 2), h
        integer :: il, ih, meth
        logical :: ok, err_ok(3, 2)
        real(dp), parameter :: hs(3) = [1.0e-2_dp, 1.0e-3_dp, 1.0e-4_dp]
        character(len=16), parameter :: names(2) = [character(len=16) :: 'implicit euler', 'galpha']
        err_ok = .true.
        do meth = 1, 2
            ok = .true.
            do il = 0, 12, 2
                s%lambda = 10.0_dp**il
                exact = cos(1.0_dp) + exp(-s%lambda)
                do ih = 1, 3
                    h = hs(ih)
                    to = 1.0_dp
                    if (meth == 1) then
                        eo%h = h
                        call implicit_euler_integrate(s, 0.0_dp, [2.0_dp], 1.0_dp, eo, to, yo, st)
                    else
                        go%h = h
                        call galpha_integrate(s, 0.0_dp, [2.0_dp], 1.0_dp, go, to, yo, st)
                    end if
                    err(ih, meth) = abs(yo(1, 1) - exact)
                    ! implicit Euler's global error is at most h/10 here, generalized-alpha's h^2/10.
                    err_ok(ih, meth) = err_ok(ih, meth) .and. err(ih, meth) <= 0.1_dp * h**meth
                    if (st%status /= SS_OK) then
                        ok = .false.
                        print '(a, a, es8.1, a, es8.1, a, i0)', trim(names(meth)), ' lambda', s%lambda, ' h', h, &
                            ': status ', st%status
                    end if
                end do
                print '(a, a, es8.1, a, 3es10.2, a, 2f6.2)', trim(names(meth)), ' prothero lambda', s%lambda, &
                    ': errors at h = 1e-2, 1e-3, 1e-4', err(:, meth), '  orders', &
                    log10(err(1, meth) / err(2, meth)), log10(err(2, meth) / err(3, meth))
                ! The observed order (1, 2) where the errors are well above rounding (1e-13).
                if (err(3, meth) > 1.0e-13_dp) err_ok(:, meth) = err_ok(:, meth) .and. &
                    abs(log10(err(1, meth) / err(2, meth)) - meth) < 0.05_dp .and. &
                    abs(log10(err(2, meth) / err(3, meth)) - meth) < 0.05_dp
            end do
            call check(ok, trim(names(meth)) // ': y'' = -lambda (y - cos t) - sin t, lambda = 1 .. 1e12, completes')
            call check(all(err_ok(:, meth)), trim(names(meth)) // ': prothero errors within the bound, ' // &
                       'observed order where above rounding')
        end do
    end subroutine test_stiff_newton

end program test_integrators_implicit
