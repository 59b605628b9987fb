!> Fortran tests of the integrators against independent truths:
!! Hairer's published DOPRI5 run on the Arenstorf orbit, Hairer's dop853.f run beside ours
!! (Arenstorf, Van der Pol, the belt), exactness on polynomials,
!! observed convergence orders on the harmonic oscillator, tableau consistency.
!! Prints one line per check; exits with status 1 if any check fails.
module test_problems
    use stickslip_kinds, only: dp
    use stickslip_ode, only: ode_system
    use stickslip_model_system, only: model_system
    implicit none
    private
    public :: arenstorf, oscillator, polynomial, van_der_pol, wrapped_scene

    !> The restricted three-body problem of Hairer's dr_dopri5 example.
    type, extends(ode_system) :: arenstorf
        real(dp) :: amu = 0.012277471_dp
    contains
        procedure :: rhs => arenstorf_rhs
    end type arenstorf

    !> y'' = -w^2 y as (y, y').
    type, extends(ode_system) :: oscillator
        real(dp) :: w = 1.0_dp
    contains
        procedure :: rhs => oscillator_rhs
    end type oscillator

    !> Van der Pol's equation y1' = y2, y2' = ((1 - y1^2) y2 - y1) / eps (Hairer's dr_dop853).
    type, extends(ode_system) :: van_der_pol
        real(dp) :: eps = 1.0e-3_dp
    contains
        procedure :: rhs => van_der_pol_rhs
    end type van_der_pol

    !> A built-in scene seen as a user's own system: it runs the integrators' generic kernel.
    type, extends(ode_system) :: wrapped_scene
        class(model_system), allocatable :: scene
    contains
        procedure :: rhs => wrapped_scene_rhs
    end type wrapped_scene

    !> y' = p t^(p-1): solved exactly by a method of order >= p.
    type, extends(ode_system) :: polynomial
        integer :: p = 4
    contains
        procedure :: rhs => polynomial_rhs
    end type polynomial

contains

    subroutine arenstorf_rhs(self, t, y, dydt)
        class(arenstorf), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        real(dp) :: amup, r1, r2
        amup = 1.0_dp - self%amu
        r1 = ((y(1) + self%amu)**2 + y(2)**2)**1.5_dp
        r2 = ((y(1) - amup)**2 + y(2)**2)**1.5_dp
        dydt(1) = y(3)
        dydt(2) = y(4)
        dydt(3) = y(1) + 2.0_dp * y(4) - amup * (y(1) + self%amu) / r1 - self%amu * (y(1) - amup) / r2
        dydt(4) = y(2) - 2.0_dp * y(3) - amup * y(2) / r1 - self%amu * y(2) / r2
    end subroutine arenstorf_rhs

    subroutine oscillator_rhs(self, t, y, dydt)
        class(oscillator), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt(1) = y(2)
        dydt(2) = -self%w**2 * y(1)
    end subroutine oscillator_rhs

    subroutine van_der_pol_rhs(self, t, y, dydt)
        class(van_der_pol), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt(1) = y(2)
        dydt(2) = ((1 - y(1)**2) * y(2) - y(1)) / self%eps
    end subroutine van_der_pol_rhs

    subroutine wrapped_scene_rhs(self, t, y, dydt)
        class(wrapped_scene), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        call self%scene%rhs(t, y, dydt)
    end subroutine wrapped_scene_rhs

    subroutine polynomial_rhs(self, t, y, dydt)
        class(polynomial), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = real(self%p, dp) * t**(self%p - 1)
    end subroutine polynomial_rhs

end module test_problems

program test_integrators
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK, SS_STEP_BUDGET, SS_BAD_H, SS_BAD_RTOL, SS_BAD_CONTROL, SS_STIFF
    use stickslip_registry, only: stickslip_message, code_of
    use stickslip_simulate, only: simulate
    use stickslip_ode, only: ode_stats
    use stickslip_rk4, only: rk4_integrate, rk4_b, rk4_c
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate, dp5_a, dp5_b, dp5_bhat, dp5_c
    use stickslip_dop853, only: dop853_options, dop853_integrate, dop853_a, dop853_b, dop853_c, dop853_er, &
                                dop853_bhh
    use stickslip_registry, only: new_system, HMIN_DEFAULT
    use stickslip_capi, only: ss_params, ss_dopri5_options, ss_stats, ss_params_default, &
                              ss_dopri5_options_default, ss_simulate
    use, intrinsic :: iso_c_binding, only: c_loc, c_int, c_double
    use stickslip_params, only: param_values, NAME_LEN
    use test_problems, only: arenstorf, oscillator, polynomial, van_der_pol, wrapped_scene
    implicit none


    call test_tableaus()
    call test_arenstorf()
    call test_belt_hairer()
    call test_polynomials()
    call test_orders()
    call test_dense_output()
    call test_status()
    call test_dop853_tableau()
    call test_dop853_arenstorf()
    call test_dop853_van_der_pol()
    call test_dop853_belt()
    call test_dop853_c_api()
    call test_dop853_kernels()
    call test_dop853_orders()
    call test_dop853_dense_output()
    call test_dop853_status()

    call finish('integrator')

contains

    subroutine test_tableaus()
        integer :: i
        call check(abs(sum(rk4_b) - 1.0_dp) < 1e-15_dp, 'rk4: sum of b = 1')
        call check(abs(sum(dp5_b) - 1.0_dp) < 1e-15_dp, 'dopri5: sum of b = 1')
        call check(abs(sum(dp5_bhat) - 1.0_dp) < 1e-15_dp, 'dopri5: sum of bhat = 1')
        do i = 1, 7
            call check(abs(sum(dp5_a(i, :)) - dp5_c(i)) < 1e-14_dp, 'dopri5: row sum of A = c')
        end do
        call check(all(abs(dp5_a(7, :) - dp5_b) < 1e-16_dp), 'dopri5: last row of A = b (FSAL)')
        ! Order conditions up to 4 for the 4th-order embedded weights (sum bhat c^3 = 1/4).
        call check(abs(sum(dp5_bhat * dp5_c**3) - 0.25_dp) < 1e-14_dp, 'dopri5: sum bhat c^3 = 1/4')
        call check(abs(sum(dp5_b * dp5_c**4) - 0.2_dp) < 1e-14_dp, 'dopri5: sum b c^4 = 1/5')
        call check(abs(sum(rk4_b * rk4_c**3) - 0.25_dp) < 1e-15_dp, 'rk4: sum b c^3 = 1/4')
    end subroutine test_tableaus

    !> Hairer's dr_dopri5.f: rtol = atol = 1e-7, default controls, automatic initial step.
    !! Published: fcn = 1442, step = 240, accpt = 216, rejct = 22,
    !! y(xend) = (0.9940021016, 0.8911185692e-5).
    subroutine test_arenstorf()
        type(arenstorf) :: sys
        type(dopri5_options) :: opts
        type(ode_stats) :: st
        real(dp), parameter :: xend = 17.0652165601579625588917206249_dp
        real(dp) :: y0(4), t_out(1), y_out(4, 1)
        y0 = [0.994_dp, 0.0_dp, 0.0_dp, -2.00158510637908252240537862224_dp]
        t_out = [xend]
        call dopri5_integrate(sys, 0.0_dp, y0, xend, [1.0e-7_dp], [1.0e-7_dp], opts, t_out, y_out, st)
        print '(a, 4(1x, i0), 2(1x, es18.10))', 'arenstorf: nfev nstep naccept nreject y1 y2 =', &
            st%nfev, st%nstep, st%naccept, st%nreject, y_out(1, 1), y_out(2, 1)
        call check(st%status == SS_OK, 'arenstorf: status ok')
        call check(st%nfev == 1442, 'arenstorf: 1442 function evaluations (Hairer)')
        call check(st%nstep == 240, 'arenstorf: 240 steps (Hairer)')
        call check(st%naccept == 216, 'arenstorf: 216 accepted (Hairer)')
        call check(st%nreject == 22, 'arenstorf: 22 rejected (Hairer)')
        call check(abs(y_out(1, 1) - 0.9940021016_dp) < 1.0e-10_dp, 'arenstorf: x(xend) = 0.9940021016')
        ! Published to 10 digits; we agree to 7e-13 absolute, far below the run's global error
        ! (~1e-5 at rtol 1e-7): the last digits depend on the machine's rounding.
        call check(abs(y_out(2, 1) - 0.8911185692e-5_dp) < 1.0e-11_dp, 'arenstorf: y(xend) = 0.8911185692e-5')
    end subroutine test_arenstorf

    !> The belt with the proposed law as the studies run it automatically (30 s, rtol 1e-6,
    !! atol 1e-9, h_max 1e-2, h_min 1e-6, never reached): Hairer's dopri5.f, built beside
    !! ours and given the same right-hand side, takes 19670 evaluations, 3278 steps, 59
    !! rejected, every accepted step bitwise equal to ours, and ends at x = -0.08784676205023.
    !! An exp/log form of the PI factor (equal in exact arithmetic) moved the last bit of
    !! step sizes: 19688 evaluations, 61 rejected, x = -0.0878572.
    subroutine test_belt_hairer()
        type(ode_stats) :: st
        real(dp) :: t_out(1), y_out(2, 1)
        t_out = [30.0_dp]
        call simulate(code_of('scene', 'belt'), code_of('law', 'proposed'), code_of('method', 'dopri5'), &
                      [character(len=16) ::], [real(dp) ::], [0.0_dp, 0.0_dp], 30.0_dp, [1.0e-6_dp], &
                      [1.0e-9_dp], [character(len=16) :: 'hmin', 'hmax'], [1.0e-6_dp, 1.0e-2_dp], &
                      t_out, y_out, st)
        print '(a, 4(1x, i0), 1x, es24.16)', 'belt/proposed: nfev nstep naccept nreject x =', &
            st%nfev, st%nstep, st%naccept, st%nreject, y_out(1, 1)
        call check(st%status == SS_OK, 'belt/proposed dopri5: status ok')
        call check(st%nfev == 19670, 'belt/proposed dopri5: 19670 evaluations (Hairer)')
        call check(st%nstep == 3278, 'belt/proposed dopri5: 3278 steps (Hairer)')
        call check(st%naccept == 3219, 'belt/proposed dopri5: 3219 accepted (Hairer)')
        call check(st%nreject == 59, 'belt/proposed dopri5: 59 rejected (Hairer)')
        call check(abs(y_out(1, 1) - (-8.7846762050233257e-2_dp)) < 1.0e-12_dp, &
                   'belt/proposed dopri5: x(30 s) = -0.08784676205023 (Hairer)')
    end subroutine test_belt_hairer

    !> RK4 integrates y' = 4 t^3 exactly, DOPRI5 y' = 5 t^4; neither y' = (p+1) t^p.
    subroutine test_polynomials()
        type(polynomial) :: sys
        type(dopri5_options) :: opts
        type(ode_stats) :: st
        real(dp) :: t_out(1), y_out(1, 1)
        t_out = [2.0_dp]
        sys%p = 4
        call rk4_integrate(sys, 0.0_dp, [0.0_dp], 2.0_dp, 0.25_dp, t_out, y_out, st)
        call check(abs(y_out(1, 1) - 16.0_dp) < 1e-12_dp, 'rk4: exact on y'' = 4 t^3')
        sys%p = 5
        call rk4_integrate(sys, 0.0_dp, [0.0_dp], 2.0_dp, 0.25_dp, t_out, y_out, st)
        call check(abs(y_out(1, 1) - 32.0_dp) > 1e-6_dp, 'rk4: not exact on y'' = 5 t^4')
        ! DOPRI5 at a fixed step: h_min = h_max = h0 (every step at h, forced if need be).
        opts%hmin = 0.25_dp; opts%hmax = 0.25_dp; opts%h0 = 0.25_dp
        call dopri5_integrate(sys, 0.0_dp, [0.0_dp], 2.0_dp, [1e-10_dp], [1e-10_dp], opts, t_out, y_out, st)
        call check(abs(y_out(1, 1) - 32.0_dp) < 1e-11_dp .and. st%nstep == 8, 'dopri5: exact on y'' = 5 t^4')
        sys%p = 6
        call dopri5_integrate(sys, 0.0_dp, [0.0_dp], 2.0_dp, [1e-10_dp], [1e-10_dp], opts, t_out, y_out, st)
        call check(abs(y_out(1, 1) - 64.0_dp) > 1e-6_dp, 'dopri5: not exact on y'' = 6 t^5')
    end subroutine test_polynomials

    !> Observed order from errors at h and h/2 on the oscillator over one period.
    subroutine test_orders()
        type(oscillator) :: sys
        type(dopri5_options) :: opts
        type(ode_stats) :: st
        real(dp), parameter :: tau = 2.0_dp * acos(-1.0_dp)
        real(dp) :: t_out(1), y_out(2, 1), err(2), p
        integer :: i
        t_out = [tau]
        do i = 1, 2
            call rk4_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], tau, tau / (50 * i), t_out, y_out, st)
            err(i) = norm2(y_out(:, 1) - [1.0_dp, 0.0_dp])
        end do
        p = log(err(1) / err(2)) / log(2.0_dp)
        print '(a, f6.3)', 'rk4 observed order: ', p
        call check(abs(p - 4.0_dp) < 0.1_dp, 'rk4: observed order 4')
        do i = 1, 2
            opts%h0 = tau / (20 * i); opts%hmin = opts%h0; opts%hmax = opts%h0
            call dopri5_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], tau, [1e-13_dp], [1e-13_dp], opts, &
                                  t_out, y_out, st)
            err(i) = norm2(y_out(:, 1) - [1.0_dp, 0.0_dp])
        end do
        p = log(err(1) / err(2)) / log(2.0_dp)
        print '(a, f6.3)', 'dopri5 observed order: ', p
        call check(abs(p - 5.0_dp) < 0.15_dp, 'dopri5: observed order 5')
    end subroutine test_orders

    !> Dense output (DOPRI5, order 4) and Hermite output (RK4) between steps.
    subroutine test_dense_output()
        type(oscillator) :: sys
        type(dopri5_options) :: opts
        type(ode_stats) :: st
        real(dp) :: t_out(1001), y_out(2, 1001)
        integer :: i
        t_out = [(0.01_dp * i, i = 0, 1000)]
        call dopri5_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 10.0_dp, [1e-8_dp], [1e-8_dp], opts, &
                              t_out, y_out, st)
        print '(a, i0, a, es10.3)', 'dopri5 dense output: steps ', st%nstep, ', max error ', &
            maxval(abs(y_out(1, :) - cos(t_out)))
        call check(st%n_written == 1001, 'dopri5: all 1001 grid points written')
        call check(maxval(abs(y_out(1, :) - cos(t_out))) < 1e-6_dp, 'dopri5: dense output within 1e-6 of cos t')
        call check(st%nstep < 1001, 'dopri5: fewer steps than output points (output is interpolated)')
        call rk4_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 10.0_dp, 0.013_dp, t_out, y_out, st)
        call check(maxval(abs(y_out(1, :) - cos(t_out))) < 1e-7_dp, 'rk4: Hermite output within 1e-7 of cos t')
        call check(st%nfev == 1 + 4 * st%nstep, 'rk4: 1 + 4 evaluations per step')
    end subroutine test_dense_output

    subroutine test_status()
        type(oscillator) :: sys
        type(dopri5_options) :: opts
        type(ode_stats) :: st
        real(dp) :: t_out(1), y_out(2, 1)
        t_out = [1.0_dp]
        call rk4_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 1.0_dp, -0.1_dp, t_out, y_out, st)
        call check(st%status == SS_BAD_H, 'rk4: h < 0 gives SS_BAD_H: ' // stickslip_message(st%status))
        call rk4_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 1.0_dp, 1e-3_dp, t_out, y_out, st, max_steps=10_8)
        call check(st%status == SS_STEP_BUDGET .and. st%nstep == 10, 'rk4: budget of 10 steps stops')
        call dopri5_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 1.0_dp, [1e-16_dp], [0.0_dp], opts, t_out, y_out, st)
        call check(st%status == SS_BAD_RTOL, 'dopri5: rtol 1e-16 gives SS_BAD_RTOL')
        opts%max_steps = 5
        call dopri5_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 100.0_dp, [1e-8_dp], [1e-8_dp], opts, t_out, &
                              y_out, st)
        call check(st%status == SS_STEP_BUDGET .and. st%nstep == 5, 'dopri5: budget of 5 steps stops')
    end subroutine test_status

    ! DOP853 against Hairer's dop853.f (version of October 11, 2009, minor modification of
    ! August 4, 2025, the copy carried by github.com/djps/homoclinic-orbits), built with
    ! gfortran 12.2 -O2 beside our library in a temporary directory, called with
    ! WORK = IWORK = 0 (his defaults) apart from the settings each test names, and given the
    ! same right-hand side (for the belt: our scene's rhs binding). Every accepted step (t and
    ! y, printed to 17 digits) and every dense output value agreed bit for bit with ours on
    ! all the runs below; the tests record his counters and end values.

    !> Tableau checks: row sums of A = c (all 16 rows: every coefficient enters one),
    !! the order conditions sum b c^(q-1) = 1/q up to q = 8, the 3rd-order weights of the
    !! second estimate up to q = 3, and the error weights (b minus 5th-order weights)
    !! orthogonal to c^(q-1) up to q = 5.
    subroutine test_dop853_tableau()
        integer :: i, q
        logical :: ok
        ok = .true.
        do i = 1, 16
            ok = ok .and. abs(sum(dop853_a(i, :)) - dop853_c(i)) < 1.0e-14_dp
        end do
        call check(ok, 'dop853: row sums of A = c (16 rows)')
        ok = .true.
        do q = 1, 8
            ok = ok .and. abs(sum(dop853_b * dop853_c(:12)**(q - 1)) - 1.0_dp / q) < 1.0e-14_dp
        end do
        call check(ok, 'dop853: sum b c^(q-1) = 1/q for q = 1..8')
        call check(abs(sum(dop853_b * dop853_c(:12)**8) - 1.0_dp / 9) > 1.0e-8_dp, &
                   'dop853: sum b c^8 /= 1/9 (order 8, not 9)')
        ok = .true.
        do q = 1, 3
            ok = ok .and. abs(sum(dop853_bhh * dop853_c(:12)**(q - 1)) - 1.0_dp / q) < 1.0e-14_dp
        end do
        call check(ok, 'dop853: 3rd-order weights, sum bhh c^(q-1) = 1/q for q = 1..3')
        ok = .true.
        do q = 1, 5
            ok = ok .and. abs(sum(dop853_er * dop853_c(:12)**(q - 1))) < 1.0e-13_dp
        end do
        call check(ok, 'dop853: error weights, sum er c^(q-1) = 0 for q = 1..5')
    end subroutine test_dop853_tableau

    !> Arenstorf (as dr_dopri5), rtol = atol = 1e-7 and 1e-10, output at x_end only.
    !! Hairer: NFCN NSTEP NACCPT NREJCT = 1361 116 83 32 and 2785 237 176 59.
    subroutine test_dop853_arenstorf()
        type(arenstorf) :: sys
        type(dop853_options) :: opts
        type(ode_stats) :: st
        real(dp), parameter :: xend = 17.0652165601579625588917206249_dp
        real(dp) :: y0(4), t_out(1), y_out(4, 1)
        y0 = [0.994_dp, 0.0_dp, 0.0_dp, -2.00158510637908252240537862224_dp]
        t_out = [xend]
        call dop853_integrate(sys, 0.0_dp, y0, xend, [1.0e-7_dp], [1.0e-7_dp], opts, t_out, y_out, st)
        print '(a, 4(1x, i0), 2(1x, es24.16))', 'dop853 arenstorf 1e-7: nfev nstep naccept nreject y1 y2 =', &
            st%nfev, st%nstep, st%naccept, st%nreject, y_out(1, 1), y_out(2, 1)
        call check(st%status == SS_OK .and. st%nfev == 1361 .and. st%nstep == 116 .and. st%naccept == 83 &
                   .and. st%nreject == 32, 'dop853 arenstorf 1e-7: counters 1361 116 83 32 (Hairer)')
        call check(all(abs(y_out(:, 1) - [9.94001611588659406e-01_dp, 4.09771015244357606e-06_dp, &
                   6.71446520589480400e-04_dp, -2.00133379096372899e+00_dp]) < 1.0e-13_dp), &
                   'dop853 arenstorf 1e-7: y(x_end) as Hairer''s')
        call dop853_integrate(sys, 0.0_dp, y0, xend, [1.0e-10_dp], [1.0e-10_dp], opts, t_out, y_out, st)
        print '(a, 4(1x, i0), 2(1x, es24.16))', 'dop853 arenstorf 1e-10: nfev nstep naccept nreject y1 y2 =', &
            st%nfev, st%nstep, st%naccept, st%nreject, y_out(1, 1), y_out(2, 1)
        call check(st%status == SS_OK .and. st%nfev == 2785 .and. st%nstep == 237 .and. st%naccept == 176 &
                   .and. st%nreject == 59, 'dop853 arenstorf 1e-10: counters 2785 237 176 59 (Hairer)')
        call check(all(abs(y_out(:, 1) - [9.94000001523297816e-01_dp, 5.27160683069230127e-09_dp, &
                   8.55194923016222575e-07_dp, -2.00158486910229572e+00_dp]) < 1.0e-13_dp), &
                   'dop853 arenstorf 1e-10: y(x_end) as Hairer''s')
        ! The orbit is closed: at 1e-10 the end state is within 1e-8 of the start (1e-3 at 1e-7).
        call check(norm2(y_out(:, 1) - y0) < 1.0e-6_dp, 'dop853 arenstorf 1e-10: orbit closes to 1e-6')
    end subroutine test_dop853_arenstorf

    !> Van der Pol as Hairer's dr_dop853: eps = 1e-3, y0 = (2, 0), x_end = 2,
    !! rtol = atol = 1e-9, dense output at 0.1, 0.2, ..., 1.9 (his IOUT = 3: the three
    !! extra evaluations only in steps with an output point, as ours). Hairer:
    !! NFCN NSTEP NACCPT NREJCT = 17552 1468 1345 122 (with IOUT = 2, dense output prepared
    !! on every step: NFCN 17552 + 3 (1345 - 19); with no output: 17495), and his CONTD8
    !! values at 0.5 and 1.9.
    subroutine test_dop853_van_der_pol()
        type(van_der_pol) :: sys
        type(dop853_options) :: opts
        type(ode_stats) :: st
        real(dp) :: t_out(20), y_out(2, 20)
        integer :: i
        t_out = [(0.1_dp * i, i = 1, 19), 2.0_dp]
        call dop853_integrate(sys, 0.0_dp, [2.0_dp, 0.0_dp], 2.0_dp, [1.0e-9_dp], [1.0e-9_dp], opts, &
                              t_out, y_out, st)
        print '(a, 4(1x, i0), 2(1x, es24.16))', 'dop853 vdp 1e-9: nfev nstep naccept nreject y1 y2 =', &
            st%nfev, st%nstep, st%naccept, st%nreject, y_out(:, 20)
        call check(st%status == SS_OK .and. st%nfev == 17552 .and. st%nstep == 1468 .and. st%naccept == 1345 &
                   .and. st%nreject == 122, 'dop853 vdp 1e-9: counters 17552 1468 1345 122 (Hairer)')
        call check(all(abs(y_out(:, 20) - [1.76323454018891024e+00_dp, -8.35688681914662057e-01_dp]) &
                   < 1.0e-13_dp), 'dop853 vdp 1e-9: y(2) as Hairer''s')
        call check(all(abs(y_out(:, 5) - [1.59732368458998653e+00_dp, -1.02859902045780527e+00_dp]) &
                   < 1.0e-13_dp) .and. all(abs(y_out(:, 19) - [1.84329293618653223e+00_dp, &
                   -7.68521470158742837e-01_dp]) < 1.0e-13_dp), 'dop853 vdp 1e-9: dense output as CONTD8''s')
        ! The stiffness test (h |lambda| > 6.1 fifteen times in a row), tested on every
        ! step: Hairer (IWORK(4) = 1, no printing) stops with IDID = -4 after 23 steps,
        ! 20 accepted, 275 evaluations; ours stops there too, after committing the step.
        opts%nstiff = 1
        opts%stop_on_stiff = .true.
        call dop853_integrate(sys, 0.0_dp, [2.0_dp, 0.0_dp], 2.0_dp, [1.0e-3_dp], [1.0e-3_dp], opts, &
                              t_out, y_out, st)
        call check(st%status == SS_STIFF .and. st%stiff .and. st%nfev == 275 .and. st%nstep == 23 .and. &
                   st%naccept == 20 .and. st%nreject == 3, 'dop853 vdp 1e-3: stiff after 23 steps (Hairer)')
    end subroutine test_dop853_van_der_pol

    !> The belt with the proposed law (the registry's defaults, 30 s from rest) through
    !! simulate, rtol = atol = 1e-7, h_max and h_min left at their defaults (whole interval,
    !! none). Hairer: NFCN NSTEP NACCPT NREJCT = 7578 648 448 200, and at 1e-10
    !! 15997 1358 1057 301.
    subroutine test_dop853_belt()
        type(ode_stats) :: st
        real(dp) :: t_out(1), y_out(2, 1)
        t_out = [30.0_dp]
        call simulate(code_of('scene', 'belt'), code_of('law', 'proposed'), code_of('method', 'dop853'), &
                      [character(len=16) ::], [real(dp) ::], [0.0_dp, 0.0_dp], 30.0_dp, [1.0e-7_dp], &
                      [1.0e-7_dp], [character(len=16) ::], [real(dp) ::], t_out, y_out, st)
        print '(a, 4(1x, i0), 2(1x, es24.16))', 'dop853 belt/proposed 1e-7: nfev nstep naccept nreject x v =', &
            st%nfev, st%nstep, st%naccept, st%nreject, y_out(:, 1)
        call check(st%status == SS_OK .and. st%nfev == 7578 .and. st%nstep == 648 .and. st%naccept == 448 &
                   .and. st%nreject == 200, 'dop853 belt/proposed 1e-7: counters 7578 648 448 200 (Hairer)')
        call check(all(abs(y_out(:, 1) - [-8.78479513725508032e-02_dp, 1.14447926107284248e+00_dp]) &
                   < 1.0e-13_dp), 'dop853 belt/proposed 1e-7: y(30 s) as Hairer''s')
        call simulate(code_of('scene', 'belt'), code_of('law', 'proposed'), code_of('method', 'dop853'), &
                      [character(len=16) ::], [real(dp) ::], [0.0_dp, 0.0_dp], 30.0_dp, [1.0e-10_dp], &
                      [1.0e-10_dp], [character(len=16) ::], [real(dp) ::], t_out, y_out, st)
        call check(st%status == SS_OK .and. st%nfev == 15997 .and. st%nstep == 1358 .and. st%naccept == 1057 &
                   .and. st%nreject == 301, 'dop853 belt/proposed 1e-10: counters 15997 1358 1057 301 (Hairer)')
        call check(all(abs(y_out(:, 1) - [-8.78474311799994356e-02_dp, 1.14448241604422152e+00_dp]) &
                   < 1.0e-13_dp), 'dop853 belt/proposed 1e-10: y(30 s) as Hairer''s')
    end subroutine test_dop853_belt

    !> The C API's ss_simulate with the default options struct (DOPRI5's constants in it):
    !! DOP853 keeps its own and runs as Hairer's.
    subroutine test_dop853_c_api()
        type(ss_params), target :: p
        type(ss_dopri5_options), target :: o
        type(ss_stats), target :: s
        real(c_double) :: tc(1), yc(2, 1)
        integer(c_int) :: status
        call ss_params_default(p)
        call ss_dopri5_options_default(o)
        call check(o%hmin == HMIN_DEFAULT, 'C API: ss_dopri5_options_default gives hmin = HMIN_DEFAULT (as Fortran, Python)')
        tc = 30.0_dp
        status = ss_simulate(int(code_of('scene', 'belt'), c_int), int(code_of('law', 'proposed'), c_int), &
                             int(code_of('method', 'dop853'), c_int), p, 0.0_dp, 0.0_dp, 30.0_dp, 0.0_dp, &
                             1.0e-7_dp, 1.0e-7_dp, c_loc(o), 1_c_int, tc, yc, c_loc(s))
        call check(status == SS_OK .and. s%nfev == 7578 .and. s%nstep == 648 .and. s%naccept == 448 .and. &
                   s%nreject == 200, 'dop853 through ss_simulate (C API): counters 7578 648 448 200 (Hairer)')
    end subroutine test_dop853_c_api

    !> The specialised kernels (scene and static law known at compile time) against the
    !! generic one (the same scene wrapped as a user's system): every accepted step and
    !! every counter identical, for both scenes and the four static laws, with h_min so
    !! that Coulomb's jumps force steps.
    subroutine test_dop853_kernels()
        character(len=16), parameter :: laws(4) = [character(len=16) :: 'coulomb', 'recurdyn', 'proposed', &
                                                   'stribeck']
        character(len=16), parameter :: scenes(2) = [character(len=16) :: 'slope', 'belt']
        type(wrapped_scene) :: wrapped
        type(dop853_options) :: opts
        type(ode_stats) :: st1, st2
        type(param_values) :: p
        ! save: arrays this large live in static storage anyway (-Wsurprising); run once
        real(dp), save :: t1(5000), y1(2, 5000), t2(5000), y2(2, 5000)
        real(dp) :: y0(2)
        integer :: i, j, status
        logical :: same
        opts%every_step = .true.
        opts%hmin = 1.0e-6_dp
        do i = 1, 2
            do j = 1, 4
                status = new_system(code_of('scene', scenes(i)), code_of('law', laws(j)), &
                                    [character(len=NAME_LEN) ::], [real(dp) ::], wrapped%scene, p)
                y0 = [0.0_dp, merge(0.5_dp, 0.0_dp, i == 1)]
                call dop853_integrate(wrapped%scene, 0.0_dp, y0, 20.0_dp, [1.0e-7_dp], [1.0e-7_dp], opts, &
                                      t1, y1, st1)
                call dop853_integrate(wrapped, 0.0_dp, y0, 20.0_dp, [1.0e-7_dp], [1.0e-7_dp], opts, t2, y2, st2)
                ! (Coulomb on the slope chatters at h_min once the box stops: both fill the
                ! 5000 rows and stop with SS_OUTPUT_FULL.)
                same = status == SS_OK .and. st1%status == st2%status .and. st1%n_written > 20 .and. &
                       st1%n_written == st2%n_written .and. st1%nfev == st2%nfev .and. &
                       st1%nforced == st2%nforced .and. st1%nreject == st2%nreject
                if (same) same = all(t1(:st1%n_written) == t2(:st1%n_written)) .and. &
                                 all(y1(:, :st1%n_written) == y2(:, :st1%n_written))
                print '(a, 3(1x, i0))', 'dop853 kernels: status rows nforced', st1%status, st1%n_written, st1%nforced
                call check(same, 'dop853 ' // trim(scenes(i)) // '/' // trim(laws(j)) // &
                           ': specialised kernel = generic kernel, bit for bit')
            end do
        end do
    end subroutine test_dop853_kernels

    !> Exact on y' = 8 t^7, not on y' = 9 t^8, at a fixed step h = 1 (h_min = h_max = h0:
    !! every step at h, forced if need be); observed order 8 on the oscillator at fixed steps.
    subroutine test_dop853_orders()
        type(polynomial) :: poly
        type(oscillator) :: osc
        type(dop853_options) :: opts
        type(ode_stats) :: st
        real(dp), parameter :: tau = 2.0_dp * acos(-1.0_dp)
        real(dp) :: t_out(1), y_out(1, 1), y2(2, 1), err(2), p
        integer :: i
        opts%hmin = 1.0_dp; opts%hmax = 1.0_dp; opts%h0 = 1.0_dp
        t_out = [2.0_dp]
        poly%p = 8
        call dop853_integrate(poly, 0.0_dp, [0.0_dp], 2.0_dp, [1e-12_dp], [1e-12_dp], opts, t_out, y_out, st)
        call check(abs(y_out(1, 1) - 256.0_dp) < 1e-11_dp .and. st%nstep == 2, 'dop853: exact on y'' = 8 t^7')
        poly%p = 9
        call dop853_integrate(poly, 0.0_dp, [0.0_dp], 2.0_dp, [1e-12_dp], [1e-12_dp], opts, t_out, y_out, st)
        call check(abs(y_out(1, 1) - 512.0_dp) > 1e-6_dp, 'dop853: not exact on y'' = 9 t^8')
        t_out = [tau]
        do i = 1, 2
            opts%h0 = tau / (4 * i); opts%hmin = opts%h0; opts%hmax = opts%h0
            call dop853_integrate(osc, 0.0_dp, [1.0_dp, 0.0_dp], tau, [1e-13_dp], [1e-13_dp], opts, &
                                  t_out, y2, st)
            err(i) = norm2(y2(:, 1) - [1.0_dp, 0.0_dp])
        end do
        p = log(err(1) / err(2)) / log(2.0_dp)
        print '(a, 2es10.3, a, f6.3)', 'dop853 errors at h = tau/4, tau/8:', err, ', observed order: ', p
        call check(abs(p - 8.0_dp) < 0.3_dp, 'dop853: observed order 8')
    end subroutine test_dop853_orders

    !> Dense output of order 7 between steps, and its cost: three evaluations for each step
    !! with an output time inside it, none for the others.
    subroutine test_dop853_dense_output()
        type(oscillator) :: sys
        type(dop853_options) :: opts
        type(ode_stats) :: st, st_end
        real(dp) :: t_out(1001), y_out(2, 1001), t1(1), y1(2, 1)
        integer :: i
        t_out = [(0.01_dp * i, i = 0, 1000)]
        call dop853_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 10.0_dp, [1e-10_dp], [1e-10_dp], opts, &
                              t_out, y_out, st)
        print '(a, i0, a, es10.3)', 'dop853 dense output: steps ', st%nstep, ', max error ', &
            maxval(abs(y_out(1, :) - cos(t_out)))
        call check(st%n_written == 1001 .and. maxval(abs(y_out(1, :) - cos(t_out))) < 1e-8_dp, &
                   'dop853: dense output within 1e-8 of cos t')
        t1 = [10.0_dp]
        call dop853_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 10.0_dp, [1e-10_dp], [1e-10_dp], opts, &
                              t1, y1, st_end)
        ! Every step is longer than the output spacing (0.01 s): each has output times inside.
        call check(st%nstep == st_end%nstep .and. st%nfev == st_end%nfev + 3 * st%naccept, &
                   'dop853: 3 evaluations per step with dense output')
    end subroutine test_dop853_dense_output

    subroutine test_dop853_status()
        type(oscillator) :: sys
        type(dop853_options) :: opts
        type(ode_stats) :: st
        real(dp) :: t_out(1), y_out(2, 1)
        integer :: status, status2
        t_out = [1.0_dp]
        opts%fac1 = 0.0_dp
        call dop853_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 1.0_dp, [1e-8_dp], [1e-8_dp], opts, t_out, y_out, st)
        call check(st%status == SS_BAD_CONTROL, 'dop853: fac1 = 0 gives SS_BAD_CONTROL: ' // &
                   stickslip_message(st%status))
        opts = dop853_options()
        ! each set evaluated on its own: in one .and. expression the compiler may skip the
        ! second call (-Wfunction-elimination)
        status = opts%set('fac2', 8.0_dp)
        status2 = opts%set('hmin', 1.0e-3_dp)
        call check(status == SS_OK .and. opts%fac2 == 8.0_dp .and. &
                   status2 == SS_OK .and. opts%hmin == 1.0e-3_dp, &
                   'dop853: controls set by name, its own and the shared ones')
        opts = dop853_options()
        opts%max_steps = 5
        call dop853_integrate(sys, 0.0_dp, [1.0_dp, 0.0_dp], 100.0_dp, [1e-8_dp], [1e-8_dp], opts, t_out, &
                              y_out, st)
        call check(st%status == SS_STEP_BUDGET .and. st%nstep == 5, 'dop853: budget of 5 steps stops')
    end subroutine test_dop853_status

end program test_integrators
