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
    use stickslip_simulate, only: scene_params, scene_params_from, simulate
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

    sp = scene_params_from(p)
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

!> Simulate nset parameter sets in one call (stickslip_batch), OpenMP over the sets.
!! Per set: codes scene/law/method, p(:, i) = (mu_s, mu_k, v_s, v_d, beta, a, m, g,
!! theta_deg, k, v_b), x0, v0, t_end, h (RK4), rtol, atol, hmin, hmax, h0, max_steps.
!! n_grid: monitor grid points per set; nkeep = n_grid to return y_grid, 0 not to.
!! istats(:, i) = (nfev, nstep, naccept, nreject, nforced, nstiff, stiff, n_flip, n_flip_tail,
!! n_rev, n_rev_tail);
!! rstats(:, i) = (t_reached, h_last, t_last, x_end, v_end, v_max, vrel_min_tail,
!! vrel_max_tail, seconds); sstatus(i) the status of set i; status the call's own.
subroutine run_batch(nset, scene, law, method, p, x0, v0, t_end, h, rtol, atol, hmin, hmax, h0, &
                     max_steps, allow_forced, stop_on_stiff, n_grid, nkeep, threads, &
                     sstatus, istats, rstats, y_grid, status)
    use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double
    use stickslip_dopri5, only: dopri5_options
    use stickslip_simulate, only: scene_params, scene_params_from
    use stickslip_batch, only: batch_summary, simulate_batch
    implicit none
    integer(c_int), intent(in) :: nset
    integer(c_int), intent(in) :: scene(nset), law(nset), method(nset)
    !f2py integer intent(hide), depend(scene) :: nset = len(scene)
    real(c_double), intent(in) :: p(11, nset)
    real(c_double), intent(in) :: x0(nset), v0(nset), t_end(nset), h(nset), rtol(nset), atol(nset)
    real(c_double), intent(in) :: hmin(nset), hmax(nset), h0(nset)
    integer(c_int64_t), intent(in) :: max_steps(nset)
    integer(c_int), intent(in) :: allow_forced, stop_on_stiff, n_grid, nkeep, threads
    integer(c_int), intent(out) :: sstatus(nset)
    integer(c_int64_t), intent(out) :: istats(11, nset)
    real(c_double), intent(out) :: rstats(9, nset)
    real(c_double), intent(out) :: y_grid(2, nkeep, nset)
    integer(c_int), intent(out) :: status
    type(scene_params), allocatable :: sp(:)
    type(dopri5_options), allocatable :: opts(:)
    type(batch_summary), allocatable :: s(:)
    integer :: i

    allocate(sp(nset), opts(nset), s(nset))
    do i = 1, nset
        sp(i) = scene_params_from(p(:, i))
        opts(i)%hmin = hmin(i)
        opts(i)%hmax = hmax(i)
        opts(i)%h0 = h0(i)
        opts(i)%max_steps = max_steps(i)
        opts(i)%allow_forced = allow_forced /= 0
        opts(i)%stop_on_stiff = stop_on_stiff /= 0
    end do
    y_grid = 0.0_c_double
    if (nkeep > 0) then
        call simulate_batch(scene, law, method, sp, x0, v0, t_end, h, rtol, atol, opts, &
                            n_grid, threads, s, status, y_grid)
    else
        call simulate_batch(scene, law, method, sp, x0, v0, t_end, h, rtol, atol, opts, &
                            n_grid, threads, s, status)
    end if
    do i = 1, nset
        sstatus(i) = s(i)%status
        istats(:, i) = [s(i)%nfev, s(i)%nstep, s(i)%naccept, s(i)%nreject, s(i)%nforced, &
                        s(i)%nstiff, merge(1_c_int64_t, 0_c_int64_t, s(i)%stiff), &
                        int(s(i)%n_flip, c_int64_t), int(s(i)%n_flip_tail, c_int64_t), &
                        int(s(i)%n_rev, c_int64_t), int(s(i)%n_rev_tail, c_int64_t)]
        rstats(:, i) = [s(i)%t_reached, s(i)%h_last, s(i)%t_last, s(i)%x_end, s(i)%v_end, &
                        s(i)%v_max, s(i)%vrel_min_tail, s(i)%vrel_max_tail, s(i)%seconds]
    end do
end subroutine run_batch
