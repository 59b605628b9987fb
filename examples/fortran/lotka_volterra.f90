!> Integrate your own ODE with stickslip's DOPRI5 and RK4: the Lotka-Volterra
!! predator-prey system
!!     x' = alpha x - beta x y,    y' = delta x y - gamma y,
!! whose first integral V = delta x - gamma ln x + beta y - alpha ln y is constant along
!! every solution: the change of V measures the integration error.
!!
!! Build against an installed stickslip:
!!     gfortran lotka_volterra.f90 $(pkg-config --cflags --libs stickslip)
!! Prints key=value lines: final state, relative drift of V, and the counters.
module lotka_volterra_model
    use stickslip_kinds, only: dp
    use stickslip_ode, only: ode_system
    implicit none
    private
    public :: lotka_volterra, invariant

    !> The model; its parameters travel in the extension of ode_system.
    type, extends(ode_system) :: lotka_volterra
        real(dp) :: alpha = 1.5_dp   !! prey growth rate [1/time]
        real(dp) :: beta = 1.0_dp    !! predation rate [1/(time prey)]
        real(dp) :: gamma = 3.0_dp   !! predator death rate [1/time]
        real(dp) :: delta = 1.0_dp   !! predator growth per prey [1/(time prey)]
    contains
        procedure :: rhs => lv_rhs
    end type lotka_volterra

contains

    subroutine lv_rhs(self, t, y, dydt)
        class(lotka_volterra), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time (unused: autonomous)
        real(dp), intent(in)  :: y(:)       !! (prey, predators)
        real(dp), intent(out) :: dydt(:)    !! their rates of change
        dydt(1) = self%alpha * y(1) - self%beta * y(1) * y(2)
        dydt(2) = self%delta * y(1) * y(2) - self%gamma * y(2)
    end subroutine lv_rhs

    !> The first integral V(x, y).
    pure function invariant(m, y) result(v)
        type(lotka_volterra), intent(in) :: m
        real(dp), intent(in) :: y(2)
        real(dp) :: v
        v = m%delta * y(1) - m%gamma * log(y(1)) + m%beta * y(2) - m%alpha * log(y(2))
    end function invariant

end module lotka_volterra_model

program lotka_volterra_example
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_registry, only: stickslip_message
    use stickslip_ode, only: ode_stats
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate
    use stickslip_rk4, only: rk4_integrate
    use lotka_volterra_model, only: lotka_volterra, invariant
    implicit none

    type(lotka_volterra) :: model
    type(dopri5_options) :: opts
    type(ode_stats) :: stats
    real(dp), parameter :: t_end = 15.0_dp, y0(2) = [10.0_dp, 5.0_dp]
    real(dp) :: t_out(1), y_out(2, 1), v0

    v0 = invariant(model, y0)
    t_out = t_end

    call dopri5_integrate(model, 0.0_dp, y0, t_end, [1.0e-10_dp], [1.0e-10_dp], opts, t_out, y_out, stats)
    if (stats%status /= SS_OK) then
        print '(a)', 'error: ' // stickslip_message(stats%status)
        error stop 1
    end if
    call report('dopri5')

    call rk4_integrate(model, 0.0_dp, y0, t_end, 1.0e-3_dp, t_out, y_out, stats)
    if (stats%status /= SS_OK) then
        print '(a)', 'error: ' // stickslip_message(stats%status)
        error stop 1
    end if
    call report('rk4')

contains

    subroutine report(method)
        character(len=*), intent(in) :: method
        print '(a,"_t_end=",es24.16)', method, t_out(1)
        print '(a,"_x=",es24.16)', method, y_out(1, 1)
        print '(a,"_y=",es24.16)', method, y_out(2, 1)
        print '(a,"_invariant_drift=",es12.4)', method, abs(invariant(model, y_out(:, 1)) - v0) / abs(v0)
        print '(a,"_nfev=",i0)', method, stats%nfev
        print '(a,"_nstep=",i0)', method, stats%nstep
        print '(a,"_naccept=",i0)', method, stats%naccept
        print '(a,"_nreject=",i0)', method, stats%nreject
    end subroutine report

end program lotka_volterra_example
