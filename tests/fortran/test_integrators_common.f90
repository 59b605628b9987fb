!> Fortran tests of what Python does not reach, beside the modules' own programs (the registry's
!! tables and messages: test_stickslip_registry.f90; the laws' derivatives: test_laws.f90; the
!! presets' Jacobians: test_stickslip_presets.f90; a model's band: test_stickslip_model_system.f90):
!! controls and dispatch by name, and regressions of the core's defects (zero-length RK4 steps,
!! counters on a full buffer, the state bounds of every method).
!! Prints one line per check; exits with status 1 if any check fails.
module test_core_problems
    use stickslip_kinds, only: dp
    use stickslip_ode, only: ode_system
    implicit none
    private
    public :: decay, growth, bounded_growth

    !> y' = -y.
    type, extends(ode_system) :: decay
    contains
        procedure :: rhs => decay_rhs
    end type decay

    !> y' = y, with the default bound (DEFAULT_BOUND_GROWTH max(1, |y0|)).
    type, extends(ode_system) :: growth
    contains
        procedure :: rhs => growth_rhs
    end type growth

    !> y' = y with its own bound: |y| <= 10.
    type, extends(growth) :: bounded_growth
    contains
        procedure :: state_bound => ten
    end type bounded_growth

contains

    subroutine decay_rhs(self, t, y, dydt)
        class(decay), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = -y
    end subroutine decay_rhs

    subroutine growth_rhs(self, t, y, dydt)
        class(growth), intent(inout) :: self
        real(dp), intent(in) :: t, y(:)
        real(dp), intent(out) :: dydt(:)
        dydt = y
    end subroutine growth_rhs

    function ten(self, t0, y0, t_end) result(bound)
        class(bounded_growth), intent(in) :: self
        real(dp), intent(in) :: t0, y0(:), t_end
        real(dp) :: bound(size(y0))
        bound = 10.0_dp
    end function ten

end module test_core_problems

program test_integrators_common
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK, SS_OUTPUT_FULL, SS_BAD_CONTROL_NAME, SS_BAD_DIM, SS_DIVERGED
    use stickslip_params, only: NAME_LEN
    use stickslip_ode, only: ode_stats, step_controls, step_count
    use stickslip_rk4, only: rk4_integrate
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate
    use stickslip_dop853, only: dop853_options, dop853_integrate
    use stickslip_radau5, only: radau5_options, radau5_integrate
    use stickslip_implicit_euler, only: implicit_euler_options, implicit_euler_integrate
    use stickslip_galpha, only: galpha_options, galpha_integrate
    use stickslip_registry, only: METHOD_TABLE, split_names, apply_controls, new_controls, HMIN_DEFAULT
    use stickslip_simulate, only: simulate
    use test_core_problems, only: decay, growth, bounded_growth
    implicit none

    call test_controls_by_name()
    call test_rk4_no_zero_step()
    call test_output_full_counters()
    call test_state_bounds()

    call finish('core')

contains

    !> Every control a method lists is accepted by its options; others are refused.
    subroutine test_controls_by_name()
        type(dopri5_options) :: d5
        type(step_controls) :: c
        character(len=NAME_LEN), allocatable :: names(:)
        real(dp) :: t_out(1), y_out(2, 1)
        type(ode_stats) :: st
        integer :: i, status
        logical :: ok
        ok = .true.
        ! gfortran -Wuninitialized on names' descriptor: a false positive, the assignment allocates it
        names = split_names(METHOD_TABLE(2)%controls)
        do i = 1, size(names)
            if (names(i) == 'rtol' .or. names(i) == 'atol') cycle
            status = apply_controls(d5, METHOD_TABLE(2), names(i:i), [1.0_dp])
            if (status /= SS_OK) ok = .false.
        end do
        call check(ok, 'controls: every control dopri5 lists is accepted by name')
        call check(apply_controls(c, METHOD_TABLE(1), [character(len=NAME_LEN) :: 'hmin'], [1.0_dp]) == &
                   SS_BAD_CONTROL_NAME, 'controls: rk4 refuses hmin (not one of its controls)')
        block
            class(step_controls), allocatable :: ctl
            type(decay) :: sys
            call check(new_controls(2, sys, [character(len=NAME_LEN) ::], [real(dp) ::], ctl) == SS_OK .and. &
                       ctl%hmin == HMIN_DEFAULT .and. HMIN_DEFAULT == 1.0e-6_dp, &
                       'controls: a run without hmin gets HMIN_DEFAULT = 1e-6 s (as C and Python)')
        end block
        call check(apply_controls(d5, METHOD_TABLE(2), [character(len=NAME_LEN) :: 'beta_pi'], [0.1_dp]) == SS_OK &
                   .and. d5%beta == 0.1_dp, 'controls: beta_pi sets DOPRI5''s PI exponent')
        t_out = 1.0_dp
        call simulate(1, 2, 2, [character(len=NAME_LEN) ::], [real(dp) ::], [0.0_dp, 0.0_dp], 1.0_dp, &
                      [1.0e-6_dp], [1.0e-9_dp], [character(len=NAME_LEN) :: 'hmin', 'hmax'], &
                      [0.0_dp, 1.0_dp], t_out, y_out, st)
        call check(st%status == SS_OK .and. y_out(1, 1) > 0.0_dp, 'simulate: slope/recurdyn/dopri5 by code and name')
        call simulate(1, 2, 2, [character(len=NAME_LEN) ::], [real(dp) ::], [0.0_dp, 0.0_dp, 0.0_dp], 1.0_dp, &
                      [1.0e-6_dp], [1.0e-9_dp], [character(len=NAME_LEN) ::], [real(dp) ::], t_out, y_out, st)
        call check(st%status == SS_BAD_DIM, 'simulate: a state of the wrong size is refused')
    end subroutine test_controls_by_name

    !> RK4 from t0 /= 0: no zero-length last step (the count rounded up when t0 + n h == t_end).
    subroutine test_rk4_no_zero_step()
        type(decay) :: sys
        type(ode_stats) :: st
        real(dp) :: t_out(10), y_out(1, 10), t0
        t0 = 1.0e6_dp
        call rk4_integrate(sys, t0, [1.0_dp], t0 + 0.3_dp, 0.1_dp, t_out, y_out, st, every_step=.true.)
        call check(st%status == SS_OK .and. st%nstep == 3 .and. st%n_written == 4 .and. &
                   st%h_last > 0.05_dp .and. step_count(t0, t0 + 0.3_dp, 0.1_dp) == 3.0_dp, &
                   'rk4: t0 = 1e6, 0.3 s at h = 0.1: 3 steps, no zero-length last step')
    end subroutine test_rk4_no_zero_step

    !> A full every-step buffer: the step that could not be stored is not counted accepted.
    subroutine test_output_full_counters()
        type(decay) :: sys
        type(ode_stats) :: st
        type(dopri5_options) :: o
        real(dp) :: t_out(4), y_out(1, 4)
        call rk4_integrate(sys, 0.0_dp, [1.0_dp], 1.0_dp, 0.1_dp, t_out, y_out, st, every_step=.true.)
        call check(st%status == SS_OUTPUT_FULL .and. st%naccept == st%n_written - 1 .and. &
                   st%t_reached == t_out(st%n_written), 'rk4: on OUTPUT_FULL naccept = rows stored - 1')
        o%every_step = .true.
        o%hmax = 0.05_dp
        call dopri5_integrate(sys, 0.0_dp, [1.0_dp], 1.0_dp, [1.0e-6_dp], [1.0e-9_dp], o, t_out, y_out, st)
        call check(st%status == SS_OUTPUT_FULL .and. st%naccept == st%n_written - 1 .and. &
                   st%t_reached == t_out(st%n_written), 'dopri5: on OUTPUT_FULL naccept = rows stored - 1')
    end subroutine test_output_full_counters

    !> y' = y from y(0) = 1 crosses the bound 10 at t = ln 10: every method given the system
    !! ends with SS_DIVERGED at its first accepted step beyond it (the rows written before stay
    !! inside it); with the default bound (1e30) the same run to t = 20 succeeds and ends at
    !! e^20 as it did (the check changes nothing inside the bound), and a run to t = 80 stops
    !! where e^t passes 1e30 (t = 69.08).
    subroutine test_state_bounds()
        type(growth) :: free
        type(bounded_growth) :: capped
        type(ode_stats) :: st
        type(dopri5_options) :: o5
        type(dop853_options) :: o8
        type(radau5_options) :: orad
        type(implicit_euler_options) :: oie
        type(galpha_options) :: oga
        real(dp) :: t_out(2000), y_out(1, 2000), h
        real(dp), parameter :: t_cross = log(10.0_dp)
        integer :: k
        character(len=*), parameter :: names(6) = ['rk4           ', 'dopri5        ', 'dop853        ', &
                                                   'radau5        ', 'implicit_euler', 'galpha        ']
        h = 0.01_dp
        o5%every_step = .true.
        o8%every_step = .true.
        orad%every_step = .true.
        oie%every_step = .true.
        oie%h = h
        oga%every_step = .true.
        oga%h = h
        do k = 1, 6
            t_out = 0.0_dp
            y_out = 0.0_dp
            select case (k)
            case (1)
                call rk4_integrate(capped, 0.0_dp, [1.0_dp], 5.0_dp, h, t_out, y_out, st, every_step=.true.)
            case (2)
                call dopri5_integrate(capped, 0.0_dp, [1.0_dp], 5.0_dp, [1.0e-8_dp], [1.0e-8_dp], o5, t_out, y_out, st)
            case (3)
                call dop853_integrate(capped, 0.0_dp, [1.0_dp], 5.0_dp, [1.0e-8_dp], [1.0e-8_dp], o8, t_out, y_out, st)
            case (4)
                call radau5_integrate(capped, 0.0_dp, [1.0_dp], 5.0_dp, [1.0e-8_dp], [1.0e-8_dp], orad, t_out, y_out, st)
            case (5)
                call implicit_euler_integrate(capped, 0.0_dp, [1.0_dp], 5.0_dp, oie, t_out, y_out, st)
            case (6)
                call galpha_integrate(capped, 0.0_dp, [1.0_dp], 5.0_dp, oga, t_out, y_out, st)
            end select
            ! the last row written is the last state inside; the next accepted one was beyond
            call check(st%status == SS_DIVERGED .and. st%n_written >= 2 .and. &
                       all(abs(y_out(1, :st%n_written)) <= 10.0_dp) .and. st%t_reached < t_cross .and. &
                       st%t_reached == t_out(st%n_written) .and. &
                       st%t_reached > merge(t_cross - 0.1_dp, 1.0_dp, k == 1 .or. k >= 5), &
                       trim(names(k)) // ': y'' = y ends SS_DIVERGED where it passes its bound 10 (t = ln 10)')
        end do
        t_out(1) = 20.0_dp
        call rk4_integrate(free, 0.0_dp, [1.0_dp], 20.0_dp, h, t_out(1:1), y_out(:, 1:1), st)
        call check(st%status == SS_OK .and. abs(y_out(1, 1) / exp(20.0_dp) - 1.0_dp) < 1.0e-6_dp, &
                   'rk4: y'' = y to t = 20 inside the default bound: e^20')
        t_out(1) = 80.0_dp
        call rk4_integrate(free, 0.0_dp, [1.0_dp], 80.0_dp, h, t_out(1:1), y_out(:, 1:1), st)
        call check(st%status == SS_DIVERGED .and. abs(st%t_reached - 30.0_dp * log(10.0_dp)) < 2.0_dp * h, &
                   'rk4: y'' = y to t = 80 stops where it passes the default bound 1e30 (t = 69.08)')
    end subroutine test_state_bounds

end program test_integrators_common
