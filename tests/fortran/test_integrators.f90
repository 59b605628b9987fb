!> Fortran tests of the integrators against independent truths:
!! Hairer's published DOPRI5 run on the Arenstorf orbit, exactness on polynomials,
!! observed convergence orders on the harmonic oscillator, tableau consistency.
!! Prints one line per check; exits with status 1 if any check fails.
module test_problems
    use stickslip_kinds, only: dp
    use stickslip_ode, only: ode_system
    implicit none
    private
    public :: arenstorf, oscillator, polynomial

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

    subroutine polynomial_rhs(self, t, y, dydt)
        class(polynomial), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = real(self%p, dp) * t**(self%p - 1)
    end subroutine polynomial_rhs

end module test_problems

program test_integrators
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK, SS_STEP_BUDGET, SS_BAD_H, SS_BAD_RTOL
    use stickslip_registry, only: stickslip_message, code_of
    use stickslip_simulate, only: simulate
    use stickslip_ode, only: ode_stats
    use stickslip_rk4, only: rk4_integrate, rk4_b, rk4_c
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate, dp5_a, dp5_b, dp5_bhat, dp5_c
    use test_problems, only: arenstorf, oscillator, polynomial
    implicit none


    call test_tableaus()
    call test_arenstorf()
    call test_belt_hairer()
    call test_polynomials()
    call test_orders()
    call test_dense_output()
    call test_status()

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

end program test_integrators
