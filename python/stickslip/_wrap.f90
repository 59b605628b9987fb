! The thin layer f2py reads: plain subroutines with C kinds, names mapped to integer
! codes, everything else delegated to the core modules. Never call these directly:
! the Python facade (stickslip/core.py) validates input and raises on bad status.

!> The integer codes of laws, scenes and methods, and the status codes, in one array:
!! (coulomb, recurdyn, proposed, slope, belt, rk4, dopri5).
subroutine codes(c)
    use, intrinsic :: iso_c_binding, only: c_int
    use stickslip_friction, only: LAW_COULOMB, LAW_RECURDYN, LAW_PROPOSED
    use stickslip_scenes, only: SCENE_SLOPE, SCENE_BELT
    use stickslip_simulate, only: METHOD_RK4, METHOD_DOPRI5
    implicit none
    integer(c_int), intent(out) :: c(7)
    c = [LAW_COULOMB, LAW_RECURDYN, LAW_PROPOSED, SCENE_SLOPE, SCENE_BELT, METHOD_RK4, METHOD_DOPRI5]
end subroutine codes

!> The library's message for a status code.
subroutine message(status, msg)
    use, intrinsic :: iso_c_binding, only: c_int
    use stickslip_kinds, only: stickslip_message
    implicit none
    integer(c_int), intent(in) :: status
    character(len=200), intent(out) :: msg
    msg = stickslip_message(status)
end subroutine message

!> Friction coefficient mu(v) of one law at n velocities [m/s].
subroutine friction(law, v, n, mu_s, mu_k, v_s, v_d, beta, a, mu, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_double
    use stickslip_kinds, only: SS_OK
    use stickslip_friction, only: friction_law, friction_law_init, friction_mu
    implicit none
    integer(c_int), intent(in) :: law
    integer(c_int), intent(in) :: n
    real(c_double), intent(in) :: v(n)
    !f2py integer intent(hide), depend(v) :: n = len(v)
    real(c_double), intent(in) :: mu_s, mu_k, v_s, v_d, beta, a
    real(c_double), intent(out) :: mu(n)
    integer(c_int), intent(out) :: status
    type(friction_law) :: fl
    status = friction_law_init(fl, law, mu_s, mu_k, v_s, v_d, beta, a)
    if (status == SS_OK) then
        mu = friction_mu(fl, v)
    else
        mu = 0.0_c_double
    end if
end subroutine friction

!> Simulate a scene. p = (mu_s, mu_k, v_s, v_d, beta, a, m, g, theta_deg, k, v_b).
!! t_out: requested times (grid mode) or room for every step (overwritten with step times).
!! istats = (nfev, nstep, naccept, nreject, nforced, nstiff, stiff, n_written);
!! rstats = (t_reached, h_last).
subroutine run_simulation(scene, law, method, p, x0, v0, t_end, h, rtol, atol, hmin, hmax, h0, &
                    max_steps, every_step, allow_forced, stop_on_stiff, nrow, t_out, y_out, &
                    istats, rstats, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double
    use stickslip_ode, only: ode_stats
    use stickslip_dopri5, only: dopri5_options
    use stickslip_simulate, only: scene_params, simulate
    implicit none
    integer(c_int), intent(in) :: scene, law, method
    real(c_double), intent(in) :: p(11)
    real(c_double), intent(in) :: x0, v0, t_end, h, rtol, atol, hmin, hmax, h0
    integer(c_int64_t), intent(in) :: max_steps
    integer(c_int), intent(in) :: every_step, allow_forced, stop_on_stiff
    integer(c_int), intent(in) :: nrow
    real(c_double), intent(inout) :: t_out(nrow)
    !f2py integer intent(hide), depend(t_out) :: nrow = len(t_out)
    real(c_double), intent(out) :: y_out(2, nrow)
    integer(c_int64_t), intent(out) :: istats(8)
    real(c_double), intent(out) :: rstats(2)
    integer(c_int), intent(out) :: status
    type(scene_params) :: sp
    type(dopri5_options) :: opts
    type(ode_stats) :: st

    sp = scene_params(mu_s=p(1), mu_k=p(2), v_s=p(3), v_d=p(4), beta=p(5), a=p(6), m=p(7), &
                      g=p(8), theta_deg=p(9), k=p(10), v_b=p(11))
    opts%hmin = hmin
    opts%hmax = hmax
    opts%h0 = h0
    opts%max_steps = max_steps
    opts%every_step = every_step /= 0
    opts%allow_forced = allow_forced /= 0
    opts%stop_on_stiff = stop_on_stiff /= 0
    y_out = 0.0_c_double
    call simulate(scene, law, method, sp, x0, v0, t_end, h, [rtol], [atol], opts, t_out, y_out, st)
    istats = [st%nfev, st%nstep, st%naccept, st%nreject, st%nforced, st%nstiff, &
              merge(1_c_int64_t, 0_c_int64_t, st%stiff), int(st%n_written, c_int64_t)]
    rstats = [st%t_reached, st%h_last]
    status = st%status
end subroutine run_simulation
