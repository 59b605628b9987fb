!> Implicit Runge-Kutta method Radau IIA of order 5 (3 stages) with step size control and
!! continuous output, for stiff systems y' = f(t, y).
!!
!! The meaning of every control follows Hairer & Wanner's RADAU5 (Solving ODEs II, 2nd ed.
!! 1996, sec. IV.8, code version of 1996/2002) for an explicit system with a full Jacobian:
!! - the stage equations are solved by simplified Newton iterations on the transformed
!!   system, one real n x n (gamma/h I - J) and one complex n x n ((alpha + i beta)/h I - J)
!!   linear system per iteration; starting values from the collocation polynomial of the
!!   previous step (zero on the first step or with `startn`);
!! - Newton stops after `nit` iterations or when its contraction rate theta >= 0.99 or
!!   predicts no convergence (then the step is shrunk and retried), and converges when
!!   faccon * |dz| <= fnewt;
!! - the Jacobian is reused for the next step when theta <= `thet`, and the factorisations
!!   too when in addition quot1 <= h_new/h <= quot2;
!! - the embedded error estimate needs one extra solve with the real matrix, and on the
!!   first step and after a rejection a second one ("filtered" estimate);
!! - Gustafsson's predictive step control (default) or the classical one, with safety 0.9
!!   (reduced when Newton needed many iterations) and h_new/h in [facl, facr];
!! - Hairer's tolerance transformation rtol' = 0.1 rtol^(2/3), atol' = rtol' atol/rtol;
!! - counters counted as RADAU5 counts them: nfev counts the right-hand sides of the
!!   stages, of the error estimate and of the step ends (not those of a finite-difference
!!   Jacobian, which `ode_system%jacobian` adds to nfev in this library: with the default
!!   Jacobian our nfev exceeds Hairer's NFCN by n njac), njac, ndec (one real and one complex
!!   decomposition count as one), nsol (Newton solves only), nstep, naccept, nreject
!!   (rejections after the first accepted step).
!!
!! As in DOPRI5 there is a step size floor h_min: when the error test fails at h_min the step
!! is accepted anyway and counted in nforced (`allow_forced = .false.`: SS_STEP_TOO_SMALL).
!! At h_min, where the step cannot shrink, Newton is not abandoned on the prediction that it
!! will converge too slowly (it iterates on up to `nit`); if it still fails (nit iterations,
!! or a contraction rate >= 0.99), the last iterate is taken as a forced step, counted in
!! nforced like a failed error test there (`allow_forced = .false.`: SS_NEWTON_FAILED).
!! This happens where the stage equations have no smooth solution: Coulomb's jump at v = 0,
!! and the proposed law's mu ~ |v|^beta from rest at tight tolerances. With h_min = 0
!! (Hairer's code has none) none of this is reached.
!!
!! Linear algebra: stickslip_linalg's own dense LU (for n <= 10 it was measured as fast as
!! LAPACK's dgetrf/dgetrs and zgetrf/zgetrs, and the library needs no LAPACK).
module stickslip_radau5
    use stickslip_kinds, only: dp, SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_OUTPUT_FULL, SS_NONFINITE, SS_INTERRUPTED, &
                               SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE, SS_BAD_NIT, &
                               SS_BAD_NEWTON_TOL, SS_BAD_RADAU5_CONTROL, SS_BAD_RTOL_POSITIVE, &
                               SS_BAD_RTOL
    use stickslip_ode, only: ode_system, ode_stats, step_controls, method_info, check_problem, check_tolerances, &
                             check_step_controls, all_finite, output_start, stop_requested, limit_after_forced
    use stickslip_linalg, only: lu_decompose, lu_solve
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: radau5_options, radau5_integrate

    !> Rounding unit of RADAU5's tests (Hairer's default WORK(1) = 1e-16).
    real(dp), parameter :: UROUND = 1.0e-16_dp

    ! Nodes of Radau IIA (order 5): c1, c2 = (4 -+ sqrt 6)/10, c3 = 1.
    real(dp), parameter :: SQ6 = sqrt(6.0_dp)
    !> Collocation nodes c of the 3-stage Radau IIA method (order 5) [-].
    real(dp), parameter, public :: radau5_c(3) = [(4.0_dp - SQ6) / 10.0_dp, (4.0_dp + SQ6) / 10.0_dp, 1.0_dp]
    real(dp), parameter :: C1 = radau5_c(1), C2 = radau5_c(2)
    real(dp), parameter :: C1M1 = C1 - 1.0_dp, C2M1 = C2 - 1.0_dp, C1MC2 = C1 - C2
    ! Weights of the embedded error estimate (Hairer & Wanner IV.8, (8.19)-(8.20)).
    real(dp), parameter :: DD1 = -(13.0_dp + 7.0_dp * SQ6) / 3.0_dp, DD2 = (-13.0_dp + 7.0_dp * SQ6) / 3.0_dp, &
                           DD3 = -1.0_dp / 3.0_dp
    ! Eigenvalues of A^-1: one real gamma = 1/u1 and the pair alpha +- i beta.
    real(dp), parameter :: CR81 = 81.0_dp**(1.0_dp / 3.0_dp), CR9 = 9.0_dp**(1.0_dp / 3.0_dp)
    real(dp), parameter :: GAM0 = 1.0_dp / ((6.0_dp + CR81 - CR9) / 30.0_dp)
    real(dp), parameter :: ALPH0 = (12.0_dp - CR81 + CR9) / 60.0_dp, &
                           BETA0 = (CR81 + CR9) * sqrt(3.0_dp) / 60.0_dp
    real(dp), parameter :: ALPH = ALPH0 / (ALPH0**2 + BETA0**2), BETA = BETA0 / (ALPH0**2 + BETA0**2)
    !> T with T^-1 A^-1 T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]] (rows of the
    !! published 20-digit values, Hairer & Wanner IV.8), and its inverse TI.
    real(dp), parameter, public :: radau5_t(3, 3) = reshape([ &
        9.1232394870892942792e-02_dp, 0.24171793270710701896_dp, 0.96604818261509293619_dp, &
        -0.14125529502095420843_dp, 0.20412935229379993199_dp, 1.0_dp, &
        -3.0029194105147424492e-02_dp, 0.38294211275726193779_dp, 0.0_dp], [3, 3])
    !> The inverse of radau5_t: the transformation to the real and complex systems [-].
    real(dp), parameter, public :: radau5_ti(3, 3) = reshape([ &
        4.3255798900631553510_dp, -4.1787185915519047273_dp, -0.50287263494578687595_dp, &
        0.33919925181580986954_dp, -0.32768282076106238708_dp, 2.5719269498556054292_dp, &
        0.54177053993587487119_dp, 0.47662355450055045196_dp, -0.59603920482822492497_dp], [3, 3])

    !> Controls of RADAU5: the shared ones (h_min, h_max, h0 = Hairer's initial H with 0
    !! meaning 1e-6, max_steps, allow_forced, fac_forced, calm_steps, every_step; h is not read) and Hairer's own,
    !! with his defaults (IWORK(3), IWORK(4), IWORK(8), WORK(2..9)).
    type, extends(step_controls) :: radau5_options
        integer  :: nit = 7              !! Newton iterations allowed per step (IWORK(3)), >= 1
        logical  :: startn = .false.     !! zero Newton starting values instead of extrapolation (IWORK(4))
        logical  :: pred = .true.        !! Gustafsson's predictive step control (IWORK(8) = 1); else classical
        real(dp) :: safety = 0.9_dp      !! safety factor of the step prediction (WORK(2)), in (0.001, 1)
        real(dp) :: thet = 0.001_dp      !! reuse the Jacobian when the Newton rate <= thet (WORK(3)), in [0, 1)
        real(dp) :: fnewt = 0.0_dp       !! Newton stopping criterion (WORK(4)); 0: max(10 uround/rtol', min(0.03, rtol'^0.5))
        real(dp) :: quot1 = 1.0_dp       !! keep h (and the factorisations) when quot1 <= h_new/h <= quot2 (WORK(5))
        real(dp) :: quot2 = 1.2_dp       !! see quot1 (WORK(6))
        real(dp) :: facl = 0.2_dp        !! smallest step ratio h_new/h (WORK(8))
        real(dp) :: facr = 8.0_dp        !! largest step ratio h_new/h (WORK(9))
    contains
        !> Set one control by name, then fall back to the parent types controls.
        procedure :: set => set_radau5_option
    end type radau5_options

    !> What RADAU5 is and which controls it reads (registry entry).
    type(method_info), parameter, public :: RADAU5_INFO = method_info(name='radau5', order=5, &
        adaptive=.true., implicit=.true., controls='rtol atol hmin hmax h0 max_steps allow_forced ' // &
        'fac_forced calm_steps every_step nit startn pred safety thet fnewt quot1 quot2 facl facr', &
        doc='Radau IIA order 5, adaptive, as Hairer''s RADAU5')

    ! What the main loop does next.
    integer, parameter :: DO_JAC = 1, DO_DEC = 2, DO_STEP = 3

contains

    !> Set one control by name: RADAU5's own, then the shared ones.
    function set_radau5_option(self, name, value) result(status)
        class(radau5_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts and flags as reals)
        integer :: status
        status = SS_OK
        select case (name)
        case ('nit')
            if (value >= 1.0_dp .and. value <= 1.0e6_dp) then
                self%nit = int(value)
            else
                status = SS_BAD_NIT
            end if
        case ('startn'); self%startn = value /= 0.0_dp
        case ('pred');   self%pred = value /= 0.0_dp
        case ('safety'); self%safety = value
        case ('thet');   self%thet = value
        case ('fnewt');  self%fnewt = value
        case ('quot1');  self%quot1 = value
        case ('quot2');  self%quot2 = value
        case ('facl');   self%facl = value
        case ('facr');   self%facr = value
        case default;    status = self%step_controls%set(name, value)
        end select
    end function set_radau5_option

    !> Integrate y' = f(t, y) from t0 to t_end with Radau IIA (order 5) and error control.
    !!
    !! rtol and atol have size 1 (scalar) or size(y0) (per component); rtol must be > 0.
    !! The Jacobian comes from sys%jacobian (finite differences unless the system overrides it).
    !! Grid mode: y_out(:, i) receives y(t_out(i)) from the collocation polynomial of the step
    !! containing it. Every-step mode: (t_out, y_out) receive the initial state and each
    !! accepted step. stats%status: SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_NEWTON_FAILED,
    !! SS_SINGULAR, SS_JAC_NONFINITE, SS_OUTPUT_FULL or a bad-input code. On a run-time
    !! failure the output rows up to stats%t_reached are valid.
    subroutine radau5_integrate(sys, t0, y0, t_end, rtol, atol, opts, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys  !! the right-hand side (and its Jacobian)
        real(dp), intent(in)    :: t0            !! initial time [s]
        real(dp), intent(in)    :: y0(:)         !! initial state
        real(dp), intent(in)    :: t_end         !! final time, > t0 [s]
        real(dp), intent(in)    :: rtol(:)       !! relative tolerances, size 1 or size(y0), in [100 eps, 1)
        real(dp), intent(in)    :: atol(:)       !! absolute tolerances, size 1 or size(y0), > 0
        type(radau5_options), intent(in) :: opts !! controls
        real(dp), intent(inout) :: t_out(:)      !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats    !! counters and status

        real(dp) :: rt(size(y0)), at(size(y0)), scal(size(y0)), y(size(y0)), f0(size(y0))
        real(dp) :: z1(size(y0)), z2(size(y0)), z3(size(y0)), w1(size(y0)), w2(size(y0)), w3(size(y0))
        real(dp) :: ytmp(size(y0)), ferr(size(y0)), cont(size(y0), 3)
        real(dp) :: fjac(size(y0), size(y0)), e1(size(y0), size(y0))
        complex(dp) :: e2(size(y0), size(y0)), zc(size(y0))
        integer :: ip1(size(y0)), ip2(size(y0))
        real(dp) :: t, tph, told, h, hold, hnew, hmaxn, hacc, erracc, err, fac, quot, facgus, qt
        real(dp) :: faccon, theta, thq, thqold, dyno, dynold, dyth, qnewt, fnewt, cfac, fac1
        real(dp) :: ffacl, ffacr
        integer :: n, m, next, action, newt, nsing, ier, i, calm
        logical :: first, reject, last, caljac, forced, newton_ok, newton_forced, slow

        n = size(y0)
        stats%status = check_problem(t0, y0, t_end, t_out, y_out, opts%every_step)
        if (stats%status == SS_OK) stats%status = check_options(n, t0, t_end, rtol, atol, opts)
        if (stats%status /= SS_OK) return

        ! Hairer's tolerance transformation (the error estimate is of lower order).
        if (size(rtol) == 1) then
            rt = rtol(1)
        else
            rt = rtol
        end if
        if (size(atol) == 1) then
            at = atol(1)
        else
            at = atol
        end if
        at = (at / rt)
        rt = 0.1_dp * rt**(2.0_dp / 3.0_dp)
        at = rt * at
        fnewt = opts%fnewt
        if (fnewt == 0.0_dp) fnewt = max(10.0_dp * UROUND / rt(1), min(0.03_dp, sqrt(rt(1))))
        ffacl = 1.0_dp / opts%facl    ! largest h/h_new
        ffacr = 1.0_dp / opts%facr    ! smallest h/h_new

        m = size(t_out)
        hmaxn = t_end - t0
        if (opts%hmax > 0.0_dp) hmaxn = min(opts%hmax, hmaxn)
        h = opts%h0
        if (h <= 10.0_dp * UROUND) h = 1.0e-6_dp
        h = max(min(h, hmaxn), opts%hmin)
        hold = h
        hacc = h
        erracc = 1.0_dp
        reject = .false.
        slow = .false.
        calm = 0
        first = .true.
        last = .false.
        t = t0
        told = t0
        y = y0
        if (t + h * 1.0001_dp >= t_end) then
            h = t_end - t
            last = .true.
        end if
        faccon = 1.0_dp
        theta = abs(opts%thet)
        thqold = 1.0_dp
        dynold = 1.0_dp
        newt = 0
        cfac = opts%safety * (1 + 2 * opts%nit)
        nsing = 0
        ier = 0
        caljac = .false.
        cont = 0.0_dp
        scal = at + rt * abs(y)
        stats%t_reached = t
        call output_start(t0, y0, t_out, y_out, opts%every_step, next)

        call sys%rhs(t, y, f0)
        stats%nfev = 1
        action = DO_JAC

        steps: do
            if (action == DO_JAC) then
                stats%njac = stats%njac + 1
                call sys%jacobian(t, y, f0, fjac, stats%nfev)
                if (.not. all(ieee_is_finite(fjac))) then
                    stats%status = SS_JAC_NONFINITE
                    exit steps
                end if
                caljac = .true.
                action = DO_DEC
            end if
            if (action == DO_DEC) then
                call decompose(ier)
                if (ier /= 0) then
                    call unexpected_rejection()
                    if (stats%status /= SS_OK) exit steps
                    cycle steps
                end if
                stats%ndec = stats%ndec + 1
            end if
            action = DO_STEP

            if (stats%nstep >= opts%max_steps) then
                stats%status = SS_STEP_BUDGET
                exit steps
            end if
            if (stop_requested(opts, stats%nstep)) then
                stats%status = SS_INTERRUPTED
                exit steps
            end if
            stats%nstep = stats%nstep + 1
            if (0.1_dp * abs(h) <= abs(t) * UROUND) then
                stats%status = SS_STEP_TOO_SMALL
                exit steps
            end if
            stats%h_last = h
            tph = t + h

            call starting_values()
            call newton(newton_ok)
            if (.not. newton_ok) then
                if (stats%status /= SS_OK) exit steps
                cycle steps
            end if

            call error_estimate()
            fac = min(opts%safety, cfac / (newt + 2 * opts%nit))
            quot = max(ffacr, min(ffacl, err**0.25_dp / fac))
            hnew = h / quot

            forced = .false.
            if ((err >= 1.0_dp .or. newton_forced) .and. (h <= opts%hmin .or. (last .and. h <= 1.0001_dp * opts%hmin))) then
                if (.not. opts%allow_forced) then
                    stats%status = SS_STEP_TOO_SMALL
                    exit steps
                end if
                forced = .true.
            end if

            if (err < 1.0_dp .or. forced) then
                first = .false.
                stats%naccept = stats%naccept + 1
                if (forced) stats%nforced = stats%nforced + 1
                if (opts%pred) then   ! Gustafsson's predictive controller
                    if (stats%naccept > 1) then
                        facgus = (hacc / h) * (err**2 / erracc)**0.25_dp / opts%safety
                        facgus = max(ffacr, min(ffacl, facgus))
                        quot = max(quot, facgus)
                        hnew = h / quot
                    end if
                    hacc = h
                    erracc = max(1.0e-2_dp, err)
                end if
                told = t
                hold = h
                t = tph
                if (last) t = t_end
                y = y + z3
                ! Collocation polynomial on [told, t] in s = (tq - t)/hold, s in [-1, 0]:
                ! y + s (cont1 + (s - c2 + 1) (cont2 + (s - c1 + 1) cont3)).
                cont(:, 1) = (z2 - z3) / C2M1
                ytmp = (z1 - z2) / C1MC2
                cont(:, 2) = (ytmp - cont(:, 1)) / C1M1
                cont(:, 3) = cont(:, 2) - (ytmp - z1 / C1) / C2
                scal = at + rt * abs(y)
                stats%t_reached = t
                if (.not. write_output()) exit steps
                caljac = .false.
                if (last) exit steps
                call sys%rhs(t, y, f0)
                stats%nfev = stats%nfev + 1
                hnew = min(hnew, hmaxn)
                if (reject) hnew = min(hnew, h)
                ! After a forced step: hold, then grow gradually (limit_after_forced).
                if (forced .or. slow) call limit_after_forced(opts, forced, reject, h, slow, calm, hnew)
                reject = .false.
                if (t + hnew / opts%quot1 >= t_end) then
                    h = t_end - t
                    last = .true.
                else
                    qt = hnew / h
                    if (theta <= opts%thet .and. qt >= opts%quot1 .and. qt <= opts%quot2) cycle steps
                    h = max(hnew, opts%hmin)
                    call clip_to_end()
                end if
                if (theta <= opts%thet) then
                    action = DO_DEC
                else
                    action = DO_JAC
                end if
            else
                reject = .true.
                last = .false.
                if (first) then
                    h = h * 0.1_dp
                else
                    h = hnew
                end if
                h = max(h, opts%hmin)
                call clip_to_end()
                if (stats%naccept >= 1) stats%nreject = stats%nreject + 1
                action = merge(DO_DEC, DO_JAC, caljac)
            end if
        end do steps
        stats%n_written = next - 1

    contains

        !> E1 = gamma/h I - J (real) and E2 = (alpha + i beta)/h I - J (complex), factorised.
        subroutine decompose(info)
            integer, intent(out) :: info
            fac1 = GAM0 / h
            e1 = -fjac
            e2 = cmplx(-fjac, 0.0_dp, kind=dp)
            do i = 1, n
                e1(i, i) = e1(i, i) + fac1
                e2(i, i) = e2(i, i) + cmplx(ALPH / h, BETA / h, kind=dp)
            end do
            call lu_decompose(e1, ip1, info)
            if (info == 0) call lu_decompose(e2, ip2, info)
        end subroutine decompose

        !> A step raised to h_min must not pass t_end (Hairer's own h never does).
        subroutine clip_to_end()
            if (t + h >= t_end) then
                h = t_end - t
                last = .true.
            end if
        end subroutine clip_to_end

        !> Newton failed or a matrix was singular: halve h and retry (Hairer's label 78),
        !! or end the run (stats%status set) after 5 singular matrices or at h_min.
        subroutine unexpected_rejection()
            if (ier /= 0) then
                nsing = nsing + 1
                if (nsing >= 5) then
                    stats%status = SS_SINGULAR
                    return
                end if
            end if
            if (h <= opts%hmin) then
                stats%status = merge(SS_SINGULAR, SS_NEWTON_FAILED, ier /= 0)
                return
            end if
            h = max(0.5_dp * h, opts%hmin)
            reject = .true.
            last = .false.
            call clip_to_end()
            action = merge(DO_DEC, DO_JAC, caljac)
        end subroutine unexpected_rejection

        !> Starting values of the stage increments z (and of w = TI z).
        subroutine starting_values()
            real(dp) :: c3q, c1q, c2q
            if (first .or. opts%startn) then
                z1 = 0.0_dp; z2 = 0.0_dp; z3 = 0.0_dp
                w1 = 0.0_dp; w2 = 0.0_dp; w3 = 0.0_dp
            else
                c3q = h / hold
                c1q = C1 * c3q
                c2q = C2 * c3q
                z1 = c1q * (cont(:, 1) + (c1q - C2M1) * (cont(:, 2) + (c1q - C1M1) * cont(:, 3)))
                z2 = c2q * (cont(:, 1) + (c2q - C2M1) * (cont(:, 2) + (c2q - C1M1) * cont(:, 3)))
                z3 = c3q * (cont(:, 1) + (c3q - C2M1) * (cont(:, 2) + (c3q - C1M1) * cont(:, 3)))
                call transform(radau5_ti, z1, z2, z3, w1, w2, w3)
            end if
        end subroutine starting_values

        !> Simplified Newton iterations on the transformed stage system. ok = .false.: the step
        !! was shrunk for a retry (or the run must end, then stats%status is set).
        subroutine newton(ok)
            logical, intent(out) :: ok
            real(dp) :: a1(n), a2(n), a3(n)
            ok = .false.
            newton_forced = .false.
            newt = 0
            faccon = max(faccon, UROUND)**0.8_dp
            theta = abs(opts%thet)
            do
                if (newt >= opts%nit) then
                    if (force_newton()) exit
                    ier = 0
                    call unexpected_rejection()
                    return
                end if
                ytmp = y + z1
                call sys%rhs(t + C1 * h, ytmp, a1)
                ytmp = y + z2
                call sys%rhs(t + C2 * h, ytmp, a2)
                ytmp = y + z3
                call sys%rhs(tph, ytmp, a3)
                stats%nfev = stats%nfev + 3
                call transform(radau5_ti, a1, a2, a3, z1, z2, z3)
                ! Right-hand sides of the real and the complex system, then the solves.
                z1 = z1 - fac1 * w1
                zc = cmplx(z2 - (ALPH / h) * w2 + (BETA / h) * w3, z3 - (ALPH / h) * w3 - (BETA / h) * w2, kind=dp)
                call lu_solve(e1, ip1, z1)
                call lu_solve(e2, ip2, zc)
                z2 = zc%re
                z3 = zc%im
                stats%nsol = stats%nsol + 1
                newt = newt + 1
                dyno = sqrt(sum((z1 / scal)**2 + (z2 / scal)**2 + (z3 / scal)**2) / (3 * n))
                if (.not. ieee_is_finite(dyno)) then   ! overflow in the stages: as divergence
                    ier = 0
                    call unexpected_rejection()
                    return
                end if
                if (newt > 1 .and. newt < opts%nit) then
                    thq = dyno / dynold
                    if (newt == 2) then
                        theta = thq
                    else
                        theta = sqrt(thq * thqold)
                    end if
                    thqold = thq
                    if (theta < 0.99_dp) then
                        faccon = theta / (1.0_dp - theta)
                        dyth = faccon * dyno * theta**(opts%nit - 1 - newt) / fnewt
                        ! Predicted not to converge in time: shrink h. At h_min, where h cannot
                        ! shrink, iterate on instead (the prediction is only a guess; Newton
                        ! can still converge, e.g. from rest under mu ~ |v|^(1/3)).
                        if (dyth >= 1.0_dp .and. h > opts%hmin) then
                            qnewt = max(1.0e-4_dp, min(20.0_dp, dyth))
                            h = max(0.8_dp * qnewt**(-1.0_dp / (4.0_dp + opts%nit - 1 - newt)) * h, opts%hmin)
                            reject = .true.
                            last = .false.
                            call clip_to_end()
                            action = merge(DO_DEC, DO_JAC, caljac)
                            return
                        end if
                    else
                        if (force_newton()) exit
                        ier = 0
                        call unexpected_rejection()
                        return
                    end if
                end if
                dynold = max(dyno, UROUND)
                w1 = w1 + z1
                w2 = w2 + z2
                w3 = w3 + z3
                call transform(radau5_t, w1, w2, w3, z1, z2, z3)
                if (faccon * dyno <= fnewt) exit
            end do
            ok = .true.
        end subroutine newton

        !> Newton failed at h_min (no smaller step to retry with): with allow_forced, take
        !! the last iterate as the stage values of a forced step (as DOPRI5 forces a step
        !! whose error test fails at h_min); .false. otherwise.
        logical function force_newton() result(force)
            force = h <= opts%hmin .and. opts%allow_forced
            if (.not. force) return
            call transform(radau5_t, w1, w2, w3, z1, z2, z3)
            newton_forced = .true.
        end function force_newton

        !> Embedded error estimate (with the filtered second solve on a first or rejected step).
        subroutine error_estimate()
            ferr = (DD1 / h) * z1 + (DD2 / h) * z2 + (DD3 / h) * z3
            ytmp = ferr + f0
            call lu_solve(e1, ip1, ytmp)
            err = max(sqrt(sum((ytmp / scal)**2) / n), 1.0e-10_dp)
            if (err >= 1.0_dp .and. (first .or. reject)) then
                ytmp = y + ytmp
                call sys%rhs(t, ytmp, w1)   ! w (transformed increments) is no longer needed
                stats%nfev = stats%nfev + 1
                ytmp = w1 + ferr
                call lu_solve(e1, ip1, ytmp)
                err = max(sqrt(sum((ytmp / scal)**2) / n), 1.0e-10_dp)
            end if
            if (.not. ieee_is_finite(err)) err = huge(1.0_dp)
        end subroutine error_estimate

        !> Write the output due after an accepted step; .false. when the buffer is full.
        logical function write_output() result(ok)
            real(dp) :: s
            ok = .true.
            if (opts%every_step) then
                if (next > m) then   ! the step cannot be stored: neither count nor commit it
                    stats%status = SS_OUTPUT_FULL
                    stats%naccept = stats%naccept - 1
                    if (forced) stats%nforced = stats%nforced - 1
                    stats%t_reached = told
                    ok = .false.
                    return
                end if
                t_out(next) = t
                y_out(:, next) = y
                next = next + 1
            else
                do while (next <= m)
                    if (t_out(next) > t) exit
                    if (t_out(next) == t) then
                        y_out(:, next) = y
                    else
                        s = (t_out(next) - t) / hold
                        y_out(:, next) = y + s * (cont(:, 1) + (s - C2M1) * (cont(:, 2) + (s - C1M1) * cont(:, 3)))
                        if (.not. all_finite(y_out(:, next))) then   ! collocation polynomial overflow
                            stats%status = SS_NONFINITE
                            ok = .false.
                            return
                        end if
                    end if
                    next = next + 1
                end do
            end if
        end function write_output

    end subroutine radau5_integrate

    !> (b1, b2, b3) = M (a1, a2, a3) componentwise, for the 3 x 3 transformations T and TI.
    pure subroutine transform(mat, a1, a2, a3, b1, b2, b3)
        real(dp), intent(in)  :: mat(3, 3)
        real(dp), intent(in)  :: a1(:), a2(:), a3(:)
        real(dp), intent(out) :: b1(:), b2(:), b3(:)
        b1 = mat(1, 1) * a1 + mat(1, 2) * a2 + mat(1, 3) * a3
        b2 = mat(2, 1) * a1 + mat(2, 2) * a2 + mat(2, 3) * a3
        b3 = mat(3, 1) * a1 + mat(3, 2) * a2 + mat(3, 3) * a3
    end subroutine transform

    !> Validate tolerances, the shared controls and RADAU5's own.
    pure function check_options(n, t0, t_end, rtol, atol, opts) result(status)
        integer, intent(in) :: n
        real(dp), intent(in) :: t0, t_end, rtol(:), atol(:)
        type(radau5_options), intent(in) :: opts
        integer :: status
        status = check_tolerances(n, rtol, atol)
        if (status == SS_BAD_RTOL .or. (status == SS_OK .and. any(rtol <= 0.0_dp))) status = SS_BAD_RTOL_POSITIVE
        if (status == SS_OK) status = check_step_controls(opts, t0, t_end)
        if (status /= SS_OK) return
        if (opts%nit < 1) then
            status = SS_BAD_NIT
        else if (.not. ieee_is_finite(opts%fnewt) .or. opts%fnewt < 0.0_dp .or. &
                 (opts%fnewt > 0.0_dp .and. opts%fnewt <= UROUND / (0.1_dp * rtol(1)**(2.0_dp / 3.0_dp)))) then
            status = SS_BAD_NEWTON_TOL
        else if (.not. (opts%safety > 0.001_dp .and. opts%safety < 1.0_dp) .or. &
                 .not. (opts%thet >= 0.0_dp .and. opts%thet < 1.0_dp) .or. &
                 .not. (opts%quot1 > 0.0_dp .and. opts%quot1 <= 1.0_dp) .or. &
                 .not. (opts%quot2 >= 1.0_dp .and. ieee_is_finite(opts%quot2)) .or. &
                 .not. (opts%facl > 0.0_dp .and. opts%facl <= 1.0_dp) .or. &
                 .not. (opts%facr >= 1.0_dp .and. ieee_is_finite(opts%facr))) then
            status = SS_BAD_RADAU5_CONTROL
        end if
    end function check_options

end module stickslip_radau5
