!> Your own system from Fortran (stickslip_user_model): a 2 kg box sliding at 3 m/s on the ground
!! under Coulomb friction, engaged only from t = 0.1 s (a step of its normal force), run by the
!! event-driven method. It must stop at t = 0.1 + v0 / (mu_k g) after v0 0.1 + v0^2 / (2 mu_k g):
!! the program checks both and exits with status 1 when either is off.
program model_stop
    use stickslip_kinds, only: dp
    use stickslip_ode, only: ode_stats
    use stickslip_user_model, only: stickslip_model
    implicit none
    real(dp), parameter :: g = 9.81_dp, mu_k = 0.4_dp, v0 = 3.0_dp, t_on = 0.1_dp
    type(stickslip_model) :: m
    type(ode_stats) :: st
    real(dp) :: t_out(2), y_out(2, 2), events(4, 10), t_stop, x_stop
    integer :: box, normal
    box = m%add_body(2.0_dp, v0=v0)
    normal = m%step(t_on, before=0.0_dp, after=2.0_dp * g)     ! the contact closes at t_on [N]
    call m%add_contact(box, 0, 'coulomb', normal, keys=['mu_s', 'mu_k'], vals=[0.5_dp, mu_k])
    t_out = [0.0_dp, 2.0_dp]
    call m%simulate('event_driven', 2.0_dp, t_out, y_out, st, rtol=[1.0e-12_dp], atol=[1.0e-14_dp], &
                    events=events)
    t_stop = t_on + v0 / (mu_k * g)
    x_stop = v0 * t_on + v0**2 / (2.0_dp * mu_k * g)
    print '(a, i0, a, i0)', 'status ', st%status, ', events ', st%nevents
    print '(a, es22.15, a, es22.15)', 'stop at t = ', events(1, 1), ' s, exact ', t_stop
    print '(a, es22.15, a, es22.15)', 'x(2 s)    = ', y_out(1, 2), ' m, exact ', x_stop
    if (st%status /= 0 .or. st%nevents /= 1 .or. abs(events(1, 1) - t_stop) > 1.0e-10_dp .or. &
        abs(y_out(1, 2) - x_stop) > 1.0e-10_dp) error stop 1
end program model_stop
