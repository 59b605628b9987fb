!> Adaptive explicit Runge-Kutta method of Dormand and Prince, order 5(4), event-free.
!!
!! The meaning of every control follows Hairer's DOPRI5 (Hairer, Norsett & Wanner,
!! Solving ODEs I, sec. II.4-II.6): RMS error norm with per-component scale
!! atol_i + rtol_i max(|y_i|, |y1_i|), PI (Lund) step control with beta = 0.04,
!! safety 0.9, step ratio in [0.2, 10], automatic initial step (HINIT), first same as
!! last, dense output of order 4 (Shampine), stiffness test h |lambda| > 3.25, and
!! counters counted as DOPRI5 counts them (6 evaluations per attempted step plus 2, or plus 1
!! when the initial step h0 is given;
!! no rejection counted before the first accepted step).
!!
!! One addition for non-smooth right-hand sides: a step size floor h_min. When the error
!! test still fails at h_min the step is taken anyway and counted as forced (event-free
!! stepping through a friction discontinuity); `allow_forced = .false.` makes that an
!! error (SS_STEP_TOO_SMALL) instead.
module stickslip_dopri5
    use stickslip_kinds, only: dp, SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_STIFF, &
                               SS_NONFINITE, SS_OUTPUT_FULL, SS_BAD_CONTROL, SS_INTERRUPTED
    use stickslip_ode, only: ode_system, ode_stats, step_controls, method_info, check_problem, check_tolerances, &
                             check_step_controls, all_finite, output_start, RTOL_MIN, stop_requested
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: dopri5_options, dopri5_integrate

    !> Smallest accepted nonzero rtol: 100 units of round-off.
    real(dp), parameter, public :: DOPRI5_RTOL_MIN = RTOL_MIN

    ! Butcher tableau (exact fractions).
    real(dp), parameter, public :: dp5_c(7) = [0.0_dp, 1.0_dp/5.0_dp, 3.0_dp/10.0_dp, 4.0_dp/5.0_dp, &
                                               8.0_dp/9.0_dp, 1.0_dp, 1.0_dp]
    !! nodes c of the Dormand-Prince tableau
    real(dp), parameter :: a21 = 1.0_dp/5.0_dp
    real(dp), parameter :: a31 = 3.0_dp/40.0_dp, a32 = 9.0_dp/40.0_dp
    real(dp), parameter :: a41 = 44.0_dp/45.0_dp, a42 = -56.0_dp/15.0_dp, a43 = 32.0_dp/9.0_dp
    real(dp), parameter :: a51 = 19372.0_dp/6561.0_dp, a52 = -25360.0_dp/2187.0_dp, &
                           a53 = 64448.0_dp/6561.0_dp, a54 = -212.0_dp/729.0_dp
    real(dp), parameter :: a61 = 9017.0_dp/3168.0_dp, a62 = -355.0_dp/33.0_dp, a63 = 46732.0_dp/5247.0_dp, &
                           a64 = 49.0_dp/176.0_dp, a65 = -5103.0_dp/18656.0_dp
    real(dp), parameter :: a71 = 35.0_dp/384.0_dp, a73 = 500.0_dp/1113.0_dp, a74 = 125.0_dp/192.0_dp, &
                           a75 = -2187.0_dp/6784.0_dp, a76 = 11.0_dp/84.0_dp
    !> Weights of the 5th-order solution (= row 7 of A) and of the 4th-order one.
    real(dp), parameter, public :: dp5_b(7) = [a71, 0.0_dp, a73, a74, a75, a76, 0.0_dp]
    real(dp), parameter, public :: dp5_bhat(7) = [5179.0_dp/57600.0_dp, 0.0_dp, 7571.0_dp/16695.0_dp, &
                                                  393.0_dp/640.0_dp, -92097.0_dp/339200.0_dp, &
                                                  187.0_dp/2100.0_dp, 1.0_dp/40.0_dp]
    !! weights of the embedded 4th-order solution
    !> The full lower-triangular A, for tableau checks.
    real(dp), parameter, public :: dp5_a(7, 7) = reshape([ &
        0.0_dp, a21, a31, a41, a51, a61, a71, &
        0.0_dp, 0.0_dp, a32, a42, a52, a62, 0.0_dp, &
        0.0_dp, 0.0_dp, 0.0_dp, a43, a53, a63, a73, &
        0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a54, a64, a74, &
        0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a65, a75, &
        0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a76, &
        0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], [7, 7])
    ! Error weights e = b - bhat.
    real(dp), parameter :: e1 = 71.0_dp/57600.0_dp, e3 = -71.0_dp/16695.0_dp, e4 = 71.0_dp/1920.0_dp, &
                           e5 = -17253.0_dp/339200.0_dp, e6 = 22.0_dp/525.0_dp, e7 = -1.0_dp/40.0_dp
    ! Dense output of order 4 (Shampine 1986).
    real(dp), parameter :: d1 = -12715105075.0_dp/11282082432.0_dp, d3 = 87487479700.0_dp/32700410799.0_dp, &
                           d4 = -10690763975.0_dp/1880347072.0_dp, d5 = 701980252875.0_dp/199316789632.0_dp, &
                           d6 = -1453857185.0_dp/822651844.0_dp, d7 = 69997945.0_dp/29380423.0_dp

    !> Controls of DOPRI5: the shared ones (h_min, h_max, h0, max_steps, allow_forced,
    !! every_step; h is not read) and Hairer's step-control constants with his defaults.
    type, extends(step_controls) :: dopri5_options
        real(dp) :: safety = 0.9_dp     !! safety factor of the step control
        real(dp) :: fac1 = 0.2_dp       !! smallest step ratio h_new/h
        real(dp) :: fac2 = 10.0_dp      !! largest step ratio h_new/h
        real(dp) :: beta = 0.04_dp      !! PI (Lund) stabilisation exponent (0: plain I control)
        integer  :: nstiff = 1000       !! test stiffness every nstiff accepted steps
        logical  :: stop_on_stiff = .false. !! stop with SS_STIFF when the stiffness test fires
    contains
        procedure :: set => set_dopri5_option
        !! set a control by name (the step_controls ones and DOPRI5's own)
    end type dopri5_options

    !> What DOPRI5 is and which controls it reads (registry entry).
    type(method_info), parameter, public :: DOPRI5_INFO = method_info(name='dopri5', order=5, &
        adaptive=.true., implicit=.false., controls='rtol atol hmin hmax h0 max_steps allow_forced ' // &
        'every_step safety fac1 fac2 beta_pi nstiff stop_on_stiff', &
        doc='Dormand-Prince 5(4), adaptive, as Hairer''s DOPRI5')

contains

    !> Set one control by name: DOPRI5's own, then the shared ones.
    function set_dopri5_option(self, name, value) result(status)
        class(dopri5_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts and flags as reals)
        integer :: status
        status = SS_OK
        select case (name)
        case ('safety');        self%safety = value
        case ('fac1');          self%fac1 = value
        case ('fac2');          self%fac2 = value
        case ('beta_pi');       self%beta = value
        case ('nstiff')
            if (value >= 1.0_dp .and. value <= real(huge(1), dp)) then
                self%nstiff = int(value)
            else
                status = SS_BAD_CONTROL
            end if
        case ('stop_on_stiff'); self%stop_on_stiff = value /= 0.0_dp
        case default;           status = self%step_controls%set(name, value)
        end select
    end function set_dopri5_option

    !> Integrate y' = f(t, y) from t0 to t_end with error control.
    !!
    !! rtol and atol have size 1 (scalar) or size(y0) (per component).
    !! Grid mode: y_out(:, i) receives y(t_out(i)) by dense output. Every-step mode:
    !! (t_out, y_out) receive the initial state and each accepted step.
    !! stats%status: SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_STIFF, SS_NONFINITE,
    !! SS_OUTPUT_FULL or a bad-input code. On a run-time failure the output rows up to
    !! stats%t_reached are valid.
    subroutine dopri5_integrate(sys, t0, y0, t_end, rtol, atol, opts, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys  !! the right-hand side
        real(dp), intent(in)    :: t0            !! initial time [s]
        real(dp), intent(in)    :: y0(:)         !! initial state
        real(dp), intent(in)    :: t_end         !! final time, > t0 [s]
        real(dp), intent(in)    :: rtol(:)       !! relative tolerances, size 1 or size(y0)
        real(dp), intent(in)    :: atol(:)       !! absolute tolerances, size 1 or size(y0)
        type(dopri5_options), intent(in) :: opts !! controls
        real(dp), intent(inout) :: t_out(:)      !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats    !! counters and status

        integer, parameter :: iord = 5
        real(dp) :: rt(size(y0)), at(size(y0)), sk(size(y0))
        real(dp) :: y(size(y0)), y1(size(y0)), ysti(size(y0)), yerr(size(y0))
        real(dp) :: k1(size(y0)), k2(size(y0)), k3(size(y0)), k4(size(y0)), k5(size(y0)), &
                    k6(size(y0)), k7(size(y0))
        real(dp) :: r1(size(y0)), r2(size(y0)), r3(size(y0)), r4(size(y0)), r5(size(y0))
        real(dp) :: t, tph, h, hnew, hmax, err, fac, fac11, facold, expo1, stnum, stden, hlamb
        integer :: n, m, next, iasti, nonsti
        logical :: last, reject, forced, dense_ready

        n = size(y0)
        stats%status = check_problem(t0, y0, t_end, t_out, y_out, opts%every_step)
        if (stats%status == SS_OK) stats%status = check_options(n, t0, t_end, rtol, atol, opts)
        if (stats%status /= SS_OK) return

        if (size(rtol) == 1) then   ! broadcast a scalar tolerance, or copy per component
            rt = rtol(1)
        else
            rt = rtol
        end if
        if (size(atol) == 1) then
            at = atol(1)
        else
            at = atol
        end if
        hmax = opts%hmax
        if (hmax == 0.0_dp) hmax = t_end - t0
        expo1 = 0.2_dp - opts%beta * 0.75_dp
        facold = 1.0e-4_dp
        iasti = 0
        nonsti = 0
        hlamb = 0.0_dp
        last = .false.
        reject = .false.
        m = size(t_out)

        t = t0
        y = y0
        call sys%rhs(t, y, k1)
        stats%nfev = 1
        h = opts%h0
        if (h == 0.0_dp) then
            h = initial_step()
            stats%nfev = 2
        end if
        h = min(max(h, opts%hmin), hmax)
        stats%t_reached = t

        call output_start(t0, y0, t_out, y_out, opts%every_step, next)

        do
            if (stats%nstep >= opts%max_steps) then
                stats%status = SS_STEP_BUDGET
                exit
            end if
            if (stop_requested(opts, stats%nstep)) then
                stats%status = SS_INTERRUPTED
                exit
            end if
            if (0.1_dp * abs(h) <= abs(t) * epsilon(1.0_dp)) then
                stats%status = SS_STEP_TOO_SMALL
                exit
            end if
            if (t + 1.01_dp * h > t_end) then
                h = t_end - t
                last = .true.
            end if
            stats%nstep = stats%nstep + 1
            stats%h_last = h

            y1 = y + h * a21 * k1
            call sys%rhs(t + dp5_c(2) * h, y1, k2)
            y1 = y + h * (a31 * k1 + a32 * k2)
            call sys%rhs(t + dp5_c(3) * h, y1, k3)
            y1 = y + h * (a41 * k1 + a42 * k2 + a43 * k3)
            call sys%rhs(t + dp5_c(4) * h, y1, k4)
            y1 = y + h * (a51 * k1 + a52 * k2 + a53 * k3 + a54 * k4)
            call sys%rhs(t + dp5_c(5) * h, y1, k5)
            ysti = y + h * (a61 * k1 + a62 * k2 + a63 * k3 + a64 * k4 + a65 * k5)
            tph = t + h
            if (last) tph = t_end
            call sys%rhs(tph, ysti, k6)
            y1 = y + h * (a71 * k1 + a73 * k3 + a74 * k4 + a75 * k5 + a76 * k6)
            call sys%rhs(tph, y1, k7)
            stats%nfev = stats%nfev + 6

            yerr = h * (e1 * k1 + e3 * k3 + e4 * k4 + e5 * k5 + e6 * k6 + e7 * k7)
            sk = at + rt * max(abs(y), abs(y1))
            err = sqrt(sum((yerr / sk)**2) / n)
            forced = .false.

            if (.not. ieee_is_finite(err) .or. .not. all_finite(y1)) then
                ! An overflow or NaN in the stages: shrink hard, or give up at the floor.
                if (h <= opts%hmin) then
                    stats%status = SS_NONFINITE
                    exit
                end if
                if (stats%naccept >= 1) stats%nreject = stats%nreject + 1
                reject = .true.
                last = .false.
                h = max(h * opts%fac1, opts%hmin)
                cycle
            end if

            ! PI control: fac = err^expo1 / facold^beta, limited to [1/fac2, 1/fac1] after safety.
            ! Hairer's two powers, bit for bit (exp/log of the same quantity moves the last bit).
            fac11 = err**expo1
            fac = fac11 / facold**opts%beta
            fac = max(1.0_dp / opts%fac2, min(1.0_dp / opts%fac1, fac / opts%safety))
            hnew = h / fac

            ! At the floor, or on a last step that the 1.01 stretch made slightly longer than
            ! the floor (rejecting it would only propose h_min and stretch it again).
            if (err > 1.0_dp .and. (h <= opts%hmin .or. (last .and. h <= 1.01_dp * opts%hmin))) then
                if (.not. opts%allow_forced) then
                    stats%status = SS_STEP_TOO_SMALL
                    exit
                end if
                forced = .true.
            end if

            if (err <= 1.0_dp .or. forced) then
                ! Output first: a step that cannot be stored is neither counted nor committed.
                dense_ready = .false.
                if (opts%every_step) then
                    if (next > m) then
                        stats%status = SS_OUTPUT_FULL
                        exit
                    end if
                    t_out(next) = tph
                    y_out(:, next) = y1
                    next = next + 1
                else
                    do while (next <= m)
                        if (t_out(next) > tph) exit
                        if (t_out(next) == tph) then
                            y_out(:, next) = y1
                        else
                            if (.not. dense_ready) call prepare_dense()
                            y_out(:, next) = dense(t_out(next))
                            if (.not. all_finite(y_out(:, next))) exit   ! dense output overflow
                        end if
                        next = next + 1
                    end do
                    if (next <= m) then
                        if (t_out(next) <= tph) then
                            stats%status = SS_NONFINITE
                            exit
                        end if
                    end if
                end if


                facold = max(err, 1.0e-4_dp)
                stats%naccept = stats%naccept + 1
                if (forced) stats%nforced = stats%nforced + 1

                if (mod(stats%naccept, int(opts%nstiff, 8)) == 0 .or. iasti > 0) then
                    stnum = sum((k7 - k6)**2)
                    stden = sum((y1 - ysti)**2)
                    if (stden > 0.0_dp) hlamb = h * sqrt(stnum / stden)
                    if (stden > 0.0_dp .and. hlamb > 3.25_dp) then
                        nonsti = 0
                        iasti = iasti + 1
                        stats%nstiff = stats%nstiff + 1
                        if (iasti == 15) stats%stiff = .true.
                    else
                        nonsti = nonsti + 1
                        if (nonsti == 6) iasti = 0
                    end if
                end if

                k1 = k7
                y = y1
                t = tph
                stats%t_reached = t
                if (stats%stiff .and. opts%stop_on_stiff) then
                    stats%status = SS_STIFF
                    exit
                end if
                if (last) exit
                if (abs(hnew) > hmax) hnew = hmax
                if (reject) hnew = min(abs(hnew), abs(h))
                reject = .false.
            else
                hnew = h / min(1.0_dp / opts%fac1, fac11 / opts%safety)
                reject = .true.
                if (stats%naccept >= 1) stats%nreject = stats%nreject + 1
                last = .false.
            end if
            h = max(hnew, opts%hmin)
        end do
        stats%n_written = next - 1

    contains

        !> Hairer's HINIT: a first step from the sizes of f and of its change.
        real(dp) function initial_step() result(h1)
            real(dp) :: dnf, dny, der2, der12, hh
            sk = at + rt * abs(y)
            dnf = sum((k1 / sk)**2)      ! Hairer's HINIT sums without dividing by n
            dny = sum((y / sk)**2)
            if (dnf <= 1.0e-10_dp .or. dny <= 1.0e-10_dp) then
                hh = 1.0e-6_dp
            else
                hh = sqrt(dny / dnf) * 0.01_dp
            end if
            hh = min(hh, hmax)
            y1 = y + hh * k1
            call sys%rhs(t + hh, y1, k2)
            der2 = sqrt(sum(((k2 - k1) / sk)**2)) / hh
            der12 = max(abs(der2), sqrt(dnf))
            if (der12 <= 1.0e-15_dp) then
                h1 = max(1.0e-6_dp, abs(hh) * 1.0e-3_dp)
            else
                h1 = (0.01_dp / der12)**(1.0_dp / iord)
            end if
            h1 = min(100.0_dp * abs(hh), h1, hmax)
        end function initial_step

        !> Coefficients of the order-4 continuous extension on [t, tph].
        subroutine prepare_dense()
            r1 = y
            r2 = y1 - y
            r3 = h * k1 - r2
            r4 = r2 - h * k7 - r3
            r5 = h * (d1 * k1 + d3 * k3 + d4 * k4 + d5 * k5 + d6 * k6 + d7 * k7)
            dense_ready = .true.
        end subroutine prepare_dense

        !> Dense output at time tq in [t, tph].
        function dense(tq) result(yq)
            real(dp), intent(in) :: tq
            real(dp) :: yq(n), s, s1
            s = (tq - t) / h
            s1 = 1.0_dp - s
            yq = r1 + s * (r2 + s1 * (r3 + s * (r4 + s1 * r5)))
        end function dense

    end subroutine dopri5_integrate

    !> Validate tolerances, the shared controls and DOPRI5's own.
    pure function check_options(n, t0, t_end, rtol, atol, opts) result(status)
        integer, intent(in) :: n
        real(dp), intent(in) :: t0, t_end, rtol(:), atol(:)
        type(dopri5_options), intent(in) :: opts
        integer :: status
        status = check_tolerances(n, rtol, atol)
        if (status == SS_OK) status = check_step_controls(opts, t0, t_end)
        if (status /= SS_OK) return
        if (.not. (opts%safety > 0.0_dp .and. opts%safety < 1.0_dp) .or. &
            .not. (opts%fac1 > 0.0_dp .and. opts%fac1 <= 1.0_dp) .or. &
            .not. (opts%fac2 >= 1.0_dp .and. ieee_is_finite(opts%fac2)) .or. &
            .not. (opts%beta >= 0.0_dp .and. opts%beta <= 0.2_dp) .or. opts%nstiff < 1) then
            status = SS_BAD_CONTROL
        end if
    end function check_options

end module stickslip_dopri5
