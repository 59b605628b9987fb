!> Periodic orbits of any system the registry integrates (a scene with its law, a user's
!! model, a C user's ODE) by single shooting, with their Floquet multipliers: what
!! `stickslip.periodic_orbit` does on its finite-difference route, for Fortran and C users
!! (`ss_periodic_orbit`, `ss_model_periodic_orbit`) and for the Python facade itself.
!!
!! The unknowns are the state y0 at the section and, for an autonomous system, the period T.
!! The residual is flow(y0, T) - y0, each flow one run of `integrate` with the chosen method
!! from the section's time t0 to t0 + T (`orbit_options%t0`, default 0: a forced system's
!! section is t = t0, y0 the state there; an autonomous system's signals are constant, so t0
!! changes nothing there), plus for an autonomous system the phase
!! condition (y0 - g) . f / |f|_inf = 0, with g the guess and f the flow's direction at the
!! guess, (flow(g, 1e-6 T) - g) / (1e-6 T) (the start state orthogonal to the flow at the
!! reference, as AUTO and COCO fix the section).
!!
!! Newton's method: the Jacobian by forward differences of the residual, the increment of
!! unknown j `fd_newton` times its scale; the step solved by LU; step control by halving
!! (up to 12 halvings) until the residual's infinity norm decreases. Converged when that norm
!! is at most tol max(1, |u_guess|_inf). The scale of a component: positions (the first
!! n_bodies components) share max(|x|_inf, 1e-3), velocities (the next n_bodies) share
!! max(|v|_inf, 1e-3), the laws' states (the rest) share max(|z|_inf, 1e-9); the period's
!! scale is its guess. A system without bodies (n_bodies = 0): each component its own
!! max(|y_j|, 1e-3).
!!
!! The monodromy matrix M = d flow(y0, T) / d y0 by central differences of the same method's
!! flow: column j is (flow(y0 + h e_j, T) - flow(y0 - h e_j, T)) / (2 h) with h = `fd_monodromy`
!! times component j's scale at the answer (default 1e-4: an adaptive method's flow jitters
!! with its step-size choices at smaller increments). The multipliers are M's eigenvalues
!! (`real_eigenvalues`: Hessenberg QR; the build links no LAPACK), largest modulus first; an
!! autonomous orbit's trivial multiplier (the flow direction's, 1 up to the differences'
!! error) is the one closest to 1. A stick phase under a set-valued method collapses
!! directions: their multipliers are 0 up to the differences' error (about fd_monodromy).
!!
!! Failures are status codes: SS_BAD_PERIOD, SS_BAD_GUESS, SS_BAD_ORBIT_OPTION for bad input,
!! the method's and the registry's own codes for a bad method, control or tolerance, a run's
!! status when a run at the guess fails, SS_NO_ORBIT (the residual returned) and
!! SS_ORBIT_COLLAPSED (the period fell below 1e-3 of its guess: an equilibrium).
module stickslip_orbit
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_PERIOD, SS_BAD_GUESS, SS_BAD_ORBIT_OPTION, &
                               SS_NO_ORBIT, SS_ORBIT_COLLAPSED
    use stickslip_params, only: NAME_LEN
    use stickslip_ode, only: ode_system, ode_stats, step_controls
    use stickslip_registry, only: integrate, new_controls
    use stickslip_linalg, only: lu_decompose, lu_solve, real_eigenvalues
    use stickslip_model_system, only: model_system
    use stickslip_user_model, only: stickslip_model
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: periodic_orbit, scene_periodic_orbit, model_periodic_orbit, orbit_scales

    !> The solver's options (defaults as `stickslip.periodic_orbit`'s).
    type, public :: orbit_options
        real(dp) :: tol = 1.0e-9_dp
        !! Newton's tolerance on the residual's infinity norm, relative to max(1, |u_guess|_inf)
        integer :: max_iter = 30
        !! Newton iterations at most; 0: no iteration, the residual and the monodromy at the guess
        real(dp) :: fd_newton = 1.0e-5_dp
        !! forward-difference increment of the shooting Jacobian, relative to each unknown's scale
        real(dp) :: fd_monodromy = 1.0e-4_dp
        !! central-difference increment of the monodromy, relative to each component's scale
        logical :: monodromy = .true.
        !! compute the monodromy and the multipliers
        real(dp) :: t0 = 0.0_dp
        !! the section's time [s]: y0 is the state at t0, each run from t0 over the period
    end type orbit_options

    !> A periodic orbit, or how the search for one ended (`status`).
    type, public :: orbit_result
        integer :: status = SS_OK
        !! SS_OK, or the code of the failure (see the module)
        real(dp), allocatable :: y0(:)
        !! the state at the section (t = opts%t0) [m, m/s, law states]; the last iterate on failure
        real(dp) :: period = 0.0_dp
        !! the period [s]
        real(dp) :: residual = huge(1.0_dp)
        !! the residual's infinity norm at y0 [state units; the phase condition in its units]
        integer :: iterations = 0
        !! Newton iterations made
        integer :: runs = 0
        !! runs of the method (flows) made
        real(dp), allocatable :: monodromy(:, :)
        !! (n, n) d flow(y0, T) / d y0 (empty when not computed)
        real(dp), allocatable :: mult_re(:), mult_im(:)
        !! (n) the Floquet multipliers, largest modulus first (real and imaginary parts)
        integer :: trivial = 0
        !! index in the multipliers of the trivial one (autonomous; 0 when forced)
        logical :: stable = .false.
        !! every nontrivial multiplier inside the unit circle
    end type orbit_result

    !> The residual's fixed data: the system, the method and its options, the kind of orbit.
    type :: shooting
        integer :: method = 0
        class(step_controls), allocatable :: ctl
        real(dp), allocatable :: rtol(:), atol(:)
        logical :: autonomous = .false.
        real(dp) :: period = 0.0_dp                   ! the forcing period [s] (forced)
        real(dp) :: t0 = 0.0_dp                       ! the section's time [s]: each run starts there
        real(dp), allocatable :: ref(:), dir(:)       ! the phase condition's reference and direction
        integer :: runs = 0
    end type shooting

contains

    !> A periodic orbit of `sys` by single shooting with the method of code `method` and its
    !! controls by name, from the guess (y_guess, period): a forced orbit of that period
    !! (autonomous = .false.), or an autonomous one whose period is an unknown (period its
    !! guess). See the module for the method and the statuses.
    subroutine periodic_orbit(sys, method, y_guess, period, autonomous, rtol, atol, ckeys, cvals, opts, orb, &
                              n_bodies, n_states)
        class(ode_system), intent(inout) :: sys       !! the system (a scene, a model's system, ...)
        integer, intent(in) :: method                 !! method code (registry)
        real(dp), intent(in) :: y_guess(:)            !! (n) the guess of the state at the section
        real(dp), intent(in) :: period                !! the forcing period, or the period's guess [s], > 0
        logical, intent(in) :: autonomous             !! .true.: the period is an unknown
        real(dp), intent(in) :: rtol(:)               !! relative tolerance(s) of the runs, size 1 or n
        real(dp), intent(in) :: atol(:)               !! absolute tolerance(s) of the runs, size 1 or n
        character(len=*), intent(in) :: ckeys(:)      !! names of the method's controls
        real(dp), intent(in) :: cvals(:)              !! their values
        type(orbit_options), intent(in) :: opts       !! the solver's options
        type(orbit_result), intent(out) :: orb        !! the orbit, or the failure's status
        integer, intent(in) :: n_bodies               !! bodies whose positions, then velocities, lead the state (0: none)
        integer, intent(in) :: n_states               !! the system's state size (the guess's, checked)
        type(shooting) :: sh
        real(dp), allocatable :: u(:), r(:), du(:), trial(:), rt(:), jac(:, :), scale(:), e(:)
        real(dp) :: norm, nn, tol_abs, lam, h
        integer :: n, nu, it, j, halving, status, info
        integer, allocatable :: ipiv(:)

        n = size(y_guess)
        orb%y0 = y_guess
        orb%period = period
        allocate(orb%monodromy(0, 0), orb%mult_re(0), orb%mult_im(0))
        orb%status = check_input(y_guess, period, opts, n_states)
        if (orb%status /= SS_OK) return
        orb%status = new_controls(method, sys, ckeys, cvals, sh%ctl)
        if (orb%status /= SS_OK) return
        sh%method = method
        sh%rtol = rtol
        sh%atol = atol
        sh%autonomous = autonomous
        sh%period = period
        sh%t0 = opts%t0
        if (autonomous) then
            h = 1.0e-6_dp * period
            call flow(sys, sh, y_guess, h, e, status)
            if (status /= SS_OK) then
                call finish(status)
                return
            end if
            sh%ref = y_guess
            sh%dir = (e - y_guess) / h
        end if
        nu = n + merge(1, 0, autonomous)
        u = y_guess
        if (autonomous) u = [u, period]
        scale = orbit_scales(y_guess, n_bodies)
        if (autonomous) scale = [scale, period]
        allocate(jac(nu, nu), ipiv(nu), du(nu))
        tol_abs = opts%tol * max(1.0_dp, maxval(abs(u)))
        call residual(sys, sh, u, r, status)
        if (status /= SS_OK) then
            call finish(status)
            return
        end if
        norm = maxval(abs(r))
        it = 0
        do while (norm > tol_abs .and. opts%max_iter > 0)
            if (it == opts%max_iter) exit
            do j = 1, nu
                h = opts%fd_newton * scale(j)
                trial = u
                trial(j) = trial(j) + h
                call residual(sys, sh, trial, rt, status)
                if (status /= SS_OK) exit
                jac(:, j) = (rt - r) / h
            end do
            if (status /= SS_OK) exit
            call lu_decompose(jac, ipiv, info)
            if (info /= 0) exit
            du = -r
            call lu_solve(jac, ipiv, du)
            lam = 1.0_dp
            do halving = 1, 12
                trial = u + lam * du
                call residual(sys, sh, trial, rt, status)
                nn = huge(1.0_dp)
                if (status == SS_OK) nn = maxval(abs(rt))
                if (nn < norm .or. nn <= tol_abs) exit
                lam = 0.5_dp * lam
            end do
            status = SS_OK
            if (.not. (nn < norm .or. nn <= tol_abs)) exit
            u = trial
            r = rt
            norm = nn
            it = it + 1
        end do
        orb%y0 = u(1:n)
        if (autonomous) orb%period = u(nu)
        orb%residual = norm
        orb%iterations = it
        if (status /= SS_OK) then
            call finish(status)
            return
        end if
        if (norm > tol_abs .and. opts%max_iter > 0) then
            call finish(SS_NO_ORBIT)
            return
        end if
        if (.not. orb%period > 1.0e-3_dp * period) then
            call finish(SS_ORBIT_COLLAPSED)
            return
        end if
        if (opts%monodromy) call monodromy(sys, sh, orb, opts%fd_monodromy * orbit_scales(orb%y0, n_bodies), status)
        call finish(status)
    contains
        subroutine finish(code)
            integer, intent(in) :: code
            orb%status = code
            orb%runs = sh%runs
        end subroutine finish
    end subroutine periodic_orbit

    !> SS_OK, or the code of the first bad input of `periodic_orbit`.
    pure integer function check_input(y_guess, period, opts, n_states) result(status)
        real(dp), intent(in) :: y_guess(:), period
        type(orbit_options), intent(in) :: opts
        integer, intent(in) :: n_states
        status = SS_OK
        if (.not. (ieee_is_finite(period) .and. period > 0.0_dp)) then
            status = SS_BAD_PERIOD
        else if (size(y_guess) /= n_states .or. .not. all(ieee_is_finite(y_guess))) then
            status = SS_BAD_GUESS
        else if (.not. (ieee_is_finite(opts%tol) .and. opts%tol > 0.0_dp) .or. opts%max_iter < 0 .or. &
                 .not. ieee_is_finite(opts%t0) .or. &
                 .not. (opts%fd_newton > 0.0_dp .and. opts%fd_newton <= 0.1_dp) .or. &
                 .not. (opts%fd_monodromy > 0.0_dp .and. opts%fd_monodromy <= 0.1_dp)) then
            status = SS_BAD_ORBIT_OPTION
        end if
    end function check_input

    !> A scale per state component (see the module): positions, velocities and law states
    !! each share their group's largest magnitude (at least 1e-3, 1e-3, 1e-9).
    pure function orbit_scales(y, n_bodies) result(s)
        real(dp), intent(in) :: y(:)         !! the state
        integer, intent(in) :: n_bodies      !! bodies leading the state (0: every component alone)
        real(dp) :: s(size(y))
        integer :: nb
        nb = min(n_bodies, size(y) / 2)
        if (nb <= 0) then
            s = max(abs(y), 1.0e-3_dp)
            return
        end if
        s(1:nb) = max(maxval(abs(y(1:nb))), 1.0e-3_dp)
        s(nb + 1:2 * nb) = max(maxval(abs(y(nb + 1:2 * nb))), 1.0e-3_dp)
        if (size(y) > 2 * nb) s(2 * nb + 1:) = max(maxval(abs(y(2 * nb + 1:))), 1.0e-9_dp)
    end function orbit_scales

    !> The state after t_len seconds from y at the section's time sh%t0: one run of the method.
    subroutine flow(sys, sh, y, t_len, y_end, status)
        class(ode_system), intent(inout) :: sys
        type(shooting), intent(inout) :: sh
        real(dp), intent(in) :: y(:), t_len
        real(dp), allocatable, intent(out) :: y_end(:)
        integer, intent(out) :: status
        real(dp) :: t_out(2), y_out(size(y), 2)
        type(ode_stats) :: stats
        t_out = [sh%t0, sh%t0 + t_len]
        y_out = 0.0_dp
        sh%runs = sh%runs + 1
        call integrate(sh%method, sys, sh%t0, y, sh%t0 + t_len, sh%rtol, sh%atol, [character(len=NAME_LEN) ::], &
                       [real(dp) ::], t_out, y_out, stats, controls=sh%ctl)
        status = stats%status
        y_end = y_out(:, 2)
    end subroutine flow

    !> The shooting residual at the unknowns u = (y0[, T]).
    subroutine residual(sys, sh, u, r, status)
        class(ode_system), intent(inout) :: sys
        type(shooting), intent(inout) :: sh
        real(dp), intent(in) :: u(:)
        real(dp), allocatable, intent(out) :: r(:)
        integer, intent(out) :: status
        real(dp), allocatable :: y_end(:)
        real(dp) :: t
        integer :: n
        n = size(u) - merge(1, 0, sh%autonomous)
        t = sh%period
        if (sh%autonomous) t = u(n + 1)
        if (.not. t > 0.0_dp) then            ! the period went negative: no run
            status = SS_NO_ORBIT
            allocate(r(size(u)))
            r = huge(1.0_dp)
            return
        end if
        call flow(sys, sh, u(1:n), t, y_end, status)
        r = y_end - u(1:n)
        if (sh%autonomous) r = [r, dot_product(u(1:n) - sh%ref, sh%dir) / max(maxval(abs(sh%dir)), 1.0e-300_dp)]
    end subroutine residual

    !> The monodromy at orb's state and period by central differences of increments h(j),
    !! and its eigenvalues (largest modulus first), the trivial one and the stability.
    subroutine monodromy(sys, sh, orb, h, status)
        class(ode_system), intent(inout) :: sys
        type(shooting), intent(inout) :: sh
        type(orbit_result), intent(inout) :: orb
        real(dp), intent(in) :: h(:)
        integer, intent(out) :: status
        real(dp), allocatable :: yp(:), ym(:), e(:)
        real(dp) :: wr(size(h)), wi(size(h)), key(size(h))
        integer :: n, j, k, order(size(h)), info
        logical :: inside
        n = size(h)
        deallocate(orb%monodromy)
        allocate(orb%monodromy(n, n), e(n))
        status = SS_OK
        do j = 1, n
            e = 0.0_dp
            e(j) = h(j)
            call flow(sys, sh, orb%y0 + e, orb%period, yp, status)
            if (status == SS_OK) call flow(sys, sh, orb%y0 - e, orb%period, ym, status)
            if (status /= SS_OK) return
            orb%monodromy(:, j) = (yp - ym) / (2.0_dp * h(j))
        end do
        call real_eigenvalues(orb%monodromy, wr, wi, info)
        if (info /= 0) then
            status = SS_NO_ORBIT
            return
        end if
        ! largest modulus first, ties in the order found (insertion sort: n is small)
        key = hypot(wr, wi)
        order = [(j, j = 1, n)]
        do j = 2, n
            k = j
            do while (k > 1)
                if (.not. key(order(k)) > key(order(k - 1))) exit
                order([k - 1, k]) = order([k, k - 1])
                k = k - 1
            end do
        end do
        orb%mult_re = wr(order)
        orb%mult_im = wi(order)
        orb%trivial = 0
        if (sh%autonomous) orb%trivial = minloc(hypot(orb%mult_re - 1.0_dp, orb%mult_im), dim=1)
        inside = .true.
        do j = 1, n
            if (j /= orb%trivial .and. .not. hypot(orb%mult_re(j), orb%mult_im(j)) < 1.0_dp) inside = .false.
        end do
        orb%stable = inside
    end subroutine monodromy

    !> A periodic orbit of a scene (code) with a law (code) and its parameters by name, the
    !! others at their defaults (as `stickslip_simulate`): the scene built by `new_system`
    !! (a bad parameter's code on failure) and solved by `periodic_orbit`; its bodies are
    !! the preset model's (the chain's blocks, or the one body of the slope and the belt).
    subroutine scene_periodic_orbit(scene, law, pkeys, pvals, method, y_guess, period, autonomous, rtol, atol, &
                                    ckeys, cvals, opts, orb)
        use stickslip_registry, only: new_system
        use stickslip_model_system, only: model_system
        use stickslip_params, only: param_values
        integer, intent(in) :: scene                  !! scene code (registry)
        integer, intent(in) :: law                    !! law code (registry)
        character(len=*), intent(in) :: pkeys(:)      !! names of the given physical parameters
        real(dp), intent(in) :: pvals(:)              !! their values [SI units]
        integer, intent(in) :: method                 !! method code (registry)
        real(dp), intent(in) :: y_guess(:)            !! the guess of the state at the section
        real(dp), intent(in) :: period                !! the forcing period, or the period's guess [s]
        logical, intent(in) :: autonomous             !! .true.: the period is an unknown
        real(dp), intent(in) :: rtol(:), atol(:)      !! tolerances of the runs (size 1 or n)
        character(len=*), intent(in) :: ckeys(:)      !! names of the method's controls
        real(dp), intent(in) :: cvals(:)              !! their values
        type(orbit_options), intent(in) :: opts       !! the solver's options
        type(orbit_result), intent(out) :: orb        !! the orbit, or the failure's status
        class(model_system), allocatable :: sys
        type(param_values) :: p
        orb%status = new_system(scene, law, pkeys, pvals, sys, p)
        if (orb%status /= SS_OK) return
        call periodic_orbit(sys, method, y_guess, period, autonomous, rtol, atol, ckeys, cvals, opts, orb, sys%nb, &
                            sys%n_states())
    end subroutine scene_periodic_orbit

    !> A periodic orbit of a user's model (`stickslip_model`) with a method by name: its
    !! system built (`build`: a bad element named by elem_kind, elem_index) and solved by
    !! `periodic_orbit`, the state (x of every body, v of every body, the laws' states). A model
    !! with drives: SS_BAD_GUESS unless the guess has the free bodies' state only (a driven
    !! body's motion is prescribed, not an unknown), in the system's order.
    subroutine model_periodic_orbit(model, method, y_guess, period, autonomous, rtol, atol, ckeys, cvals, opts, &
                                    orb, elem_kind, elem_index)
        use stickslip_registry, only: code_of
        use stickslip_kinds, only: SS_BAD_METHOD
        use stickslip_user_model, only: drive_plan
        type(stickslip_model), intent(in) :: model   !! the model
        character(len=*), intent(in) :: method       !! the method's name (registry)
        real(dp), intent(in) :: y_guess(:)           !! the guess of the state at the section
        real(dp), intent(in) :: period               !! the forcing period, or the period's guess [s]
        logical, intent(in) :: autonomous            !! .true.: the period is an unknown
        real(dp), intent(in) :: rtol(:), atol(:)     !! tolerances of the runs (size 1 or n)
        character(len=*), intent(in) :: ckeys(:)     !! names of the method's controls
        real(dp), intent(in) :: cvals(:)             !! their values
        type(orbit_options), intent(in) :: opts      !! the solver's options
        type(orbit_result), intent(out) :: orb       !! the orbit, or the failure's status
        integer, intent(out) :: elem_kind            !! ELEM_* of a bad element (0: none)
        integer, intent(out) :: elem_index           !! its index (0: none)
        type(stickslip_model) :: m
        type(model_system) :: sys
        class(model_system), allocatable :: run     ! sys with its structure found (`build_run`)
        type(drive_plan) :: plan
        integer :: code
        m = model
        call m%build_run(sys, run, orb%status, elem_kind, elem_index, plan)
        if (orb%status /= SS_OK) return
        code = code_of('method', method)
        if (code == 0) then
            orb%status = SS_BAD_METHOD
            return
        end if
        call periodic_orbit(run, code, y_guess, period, autonomous, rtol, atol, ckeys, cvals, opts, orb, sys%nb, &
                            sys%n_states())
    end subroutine model_periodic_orbit

end module stickslip_orbit
