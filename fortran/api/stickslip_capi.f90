!> The C interface of the library: `bind(C)` entry points over the Fortran core.
!!
!! Declared for C in `stickslip.h` (beside this file). Every function returns an
!! integer status (`SS_OK` = 0, negative on failure; `ss_message` explains a code).
!! Nothing here re-implements the physics or the integrators: laws, scenes and methods
!! come from `stickslip_registry` by code, with parameters and controls by name
!! (`ss_run`, `ss_mu`: any law, scene or method the registry lists, with no change here
!! when one is added); `ss_simulate` and `ss_friction` are the fixed-struct entry points
!! for the paper's laws, kept for existing C programs; a C user's own ODE is integrated by
!! `stickslip_dopri5`, `stickslip_dop853` or `stickslip_rk4` through a thin `ode_system` extension that calls
!! a C function pointer.
!!
!! A user's own system (`stickslip_user_model`) is an opaque `ss_model *`: `ss_model_new`,
!! `ss_model_add_*`, `ss_signal_*`, `ss_model_check`, `ss_model_simulate`, `ss_model_free`;
!! the handle points to a Fortran `model_handle` whose tag tells a live model from NULL or a
!! stray pointer (SS_BAD_HANDLE), and which keeps the element its last check named
!! (`ss_model_error`, `ss_model_message`).
!!
!! Array layout: states are stored as C arrays `y_out[n_out][n]` (row i holds the state
!! at t_out[i]), which is the Fortran array y_out(n, n_out); a model's positions and
!! velocities are `x[n_bodies][n_out]`, the Fortran array x(n_out, n_bodies).
module stickslip_capi
    use, intrinsic :: iso_c_binding, only: c_int, c_int64_t, c_double, c_char, c_size_t, &
                                           c_ptr, c_funptr, c_null_char, c_associated, c_f_procpointer, c_f_pointer, &
                                           c_null_ptr, c_loc
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_DIM, SS_BAD_N_OUT, SS_BAD_METHOD, SS_BAD_HANDLE
    use stickslip_params, only: param_values, NAME_LEN
    use stickslip_friction, only: friction_law
    use stickslip_ode, only: ode_system, ode_stats, step_controls
    use stickslip_rk4, only: rk4_integrate
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate
    use stickslip_dop853, only: dop853_options, dop853_integrate
    use stickslip_registry, only: stickslip_message, registry_text, make_law, split_names, code_of, HMIN_DEFAULT, &
                                  PARAMS, METHOD_TABLE, METHOD_RK4, METHOD_DOPRI5, METHOD_DOP853, LAW_TABLE
    use stickslip_simulate, only: simulate
    use stickslip_model_system, only: model_system
    use stickslip_user_model, only: stickslip_model, ELEM_SPRING, ELEM_DAMPER, ELEM_FORCE, ELEM_CONTACT, &
                                    ELEM_DRIVE
    use stickslip_orbit, only: orbit_options, orbit_result, scene_periodic_orbit, model_periodic_orbit
    implicit none
    private

    public :: ss_params, ss_dopri5_options, ss_stats
    public :: ss_params_default, ss_dopri5_options_default, ss_dop853_options_default, ss_message, &
              ss_friction, ss_simulate, ss_dopri5, ss_dop853, ss_rk4, ss_run, ss_mu, ss_code, ss_registry
    public :: ss_model_new, ss_model_free, ss_model_add_body, ss_model_add_spring, ss_model_add_damper, &
              ss_model_add_force, ss_model_add_contact, ss_signal_constant, ss_signal_step, ss_signal_ramp, &
              ss_signal_sine, ss_signal_table, ss_signal_add, ss_signal_sub, ss_signal_mul, ss_model_check, &
              ss_model_error, ss_model_message, ss_model_simulate, ss_model_add_drive, ss_model_drive_forces
    public :: ss_orbit_options, ss_orbit_info, ss_orbit_options_default, ss_periodic_orbit, ss_model_periodic_orbit

    !> Physical parameters of both scenes and all laws (C struct `ss_params`).
    type, bind(C) :: ss_params
        real(c_double) :: mu_s       !! static coefficient [-]
        real(c_double) :: mu_k       !! kinetic coefficient [-]
        real(c_double) :: v_s        !! static threshold velocity [m/s]
        real(c_double) :: v_d        !! dynamic threshold velocity (recurdyn) [m/s]
        real(c_double) :: beta       !! exponent of the proposed law [-]
        real(c_double) :: a          !! base of the proposed law [-]
        real(c_double) :: m          !! mass (belt) [kg]
        real(c_double) :: g          !! gravity [m/s^2]
        real(c_double) :: theta_deg  !! slope inclination [deg]
        real(c_double) :: k          !! spring stiffness (belt) [N/m]
        real(c_double) :: v_b        !! belt speed [m/s]
    end type ss_params

    !> Integration controls (C struct `ss_dopri5_options`); flags are 0/1.
    type, bind(C) :: ss_dopri5_options
        real(c_double) :: hmin          !! step size floor, forced steps there (default 1e-6; 0: none) [s]
        real(c_double) :: hmax          !! largest step (0: t_end - t0) [s]
        real(c_double) :: h0            !! initial step (0: automatic) [s]
        real(c_double) :: safety        !! safety factor of the step control
        real(c_double) :: fac1          !! smallest step ratio h_new/h
        real(c_double) :: fac2          !! largest step ratio h_new/h
        real(c_double) :: beta          !! PI (Lund) stabilisation exponent
        integer(c_int64_t) :: max_steps !! budget of attempted steps (RK4 and DOPRI5)
        integer(c_int) :: nstiff        !! stiffness test every nstiff accepted steps
        integer(c_int) :: allow_forced  !! take steps at hmin when the error test fails there
        integer(c_int) :: stop_on_stiff !! stop with SS_STIFF when the stiffness test fires
        integer(c_int) :: every_step    !! output every step instead of at the given times
    end type ss_dopri5_options

    !> Counters and outcome of one integration (C struct `ss_stats`).
    type, bind(C) :: ss_stats
        integer(c_int64_t) :: nfev      !! right-hand-side evaluations
        integer(c_int64_t) :: nstep     !! attempted steps
        integer(c_int64_t) :: naccept   !! accepted steps (forced ones included)
        integer(c_int64_t) :: nreject   !! rejected steps after the first accepted one
        integer(c_int64_t) :: nforced   !! steps forced at hmin
        integer(c_int64_t) :: nstiff    !! stiffness tests that fired
        integer(c_int) :: stiff         !! 1 when the problem was judged stiff
        integer(c_int) :: n_written     !! output rows written
        real(c_double) :: t_reached     !! time reached [s]
        real(c_double) :: h_last        !! last step size tried [s]
        integer(c_int) :: status        !! SS_OK or a negative status code
        integer(c_int64_t) :: njac      !! Jacobian evaluations (implicit methods)
        integer(c_int64_t) :: ndec      !! LU decompositions (implicit methods)
        integer(c_int64_t) :: nsol      !! forward-backward substitutions (implicit methods)
    end type ss_stats

    !> The periodic-orbit solver's options (C struct `ss_orbit_options`; stickslip_orbit's
    !! orbit_options).
    type, bind(C) :: ss_orbit_options
        real(c_double) :: tol            !! Newton's tolerance, relative to max(1, |guess|_inf)
        integer(c_int) :: max_iter       !! Newton iterations at most (0: the monodromy at the guess)
        real(c_double) :: fd_newton      !! forward-difference increment of the Jacobian, relative
        real(c_double) :: fd_monodromy   !! central-difference increment of the monodromy, relative
        real(c_double) :: t0             !! the section's time [s]: y0 is the state at t0 (default 0)
    end type ss_orbit_options

    !> What the periodic-orbit solver found (C struct `ss_orbit_info`).
    type, bind(C) :: ss_orbit_info
        real(c_double) :: period         !! the period [s]
        real(c_double) :: residual       !! the shooting residual's infinity norm at the answer
        integer(c_int) :: iterations     !! Newton iterations made
        integer(c_int) :: runs           !! runs of the method made
        integer(c_int) :: trivial        !! index (from 0) of the trivial multiplier; -1 when forced
        integer(c_int) :: stable         !! 1: every nontrivial multiplier inside the unit circle
    end type ss_orbit_info

    !> A C user's ODE: dydt = f(t, y) through `void f(double t, const double *y,
    !! double *dydt, int n, void *data)`.
    type, extends(ode_system) :: c_system
        type(c_funptr) :: f            !! the C function
        type(c_ptr) :: data            !! the user's data, passed back unchanged
        integer(c_int) :: n = 0        !! dimension of the state
    contains
        procedure :: rhs => c_system_rhs
    end type c_system

    !> The tag of a live model handle (an arbitrary number a stray pointer is unlikely to hold).
    integer, parameter :: LIVE_TAG = 1936943469
    !> What an `ss_model *` points to: a model, a tag that tells a live handle from another
    !! pointer, and the outcome of the model's last check or run.
    type :: model_handle
        integer :: tag = LIVE_TAG                !! LIVE_TAG while the handle is live, 0 once freed
        type(stickslip_model) :: model           !! the model
        integer :: status = SS_OK                !! status of its last check or run
        integer :: elem_kind = 0                 !! ELEM_* of the element that status names (0: none)
        integer :: elem_index = 0                !! its index, from 1 (0: none)
        !> (number of drives, n_out) the drives' forces of its last run [N] (ss_model_drive_forces)
        real(dp), allocatable :: drive_force(:, :)
    end type model_handle

    !> The values of an empty C array.
    real(c_double), target :: no_values(0)

    interface
        !> The C library's strlen.
        function c_strlen(s) result(n) bind(C, name='strlen')
            import :: c_ptr, c_size_t
            type(c_ptr), value :: s             !! a NUL-terminated string
            integer(c_size_t) :: n
        end function c_strlen
    end interface

    abstract interface
        !> The C right-hand side.
        subroutine c_rhs(t, y, dydt, n, data) bind(C)
            import :: c_double, c_int, c_ptr
            real(c_double), value :: t          !! time
            real(c_double), intent(in) :: y(*)  !! state (n)
            real(c_double), intent(out) :: dydt(*)  !! derivative (n)
            integer(c_int), value :: n          !! dimension
            type(c_ptr), value :: data          !! user data
        end subroutine c_rhs
    end interface

contains

    !> Fill `p` with the paper's parameters (Table 1) and our defaults.
    subroutine ss_params_default(p) bind(C, name='ss_params_default')
        type(ss_params), intent(out) :: p   !! parameters to fill
        real(c_double) :: v(size(PARAMS))
        v = PARAMS%default
        p = transfer(v(param_order()), p)
    end subroutine ss_params_default

    !> Fill `o` with DOPRI5's default controls (Hairer's: safety 0.9, fac1 0.2, fac2 10,
    !! beta 0.04; h_min = HMIN_DEFAULT = 1e-6 s, the registry's, max_steps = 10^8).
    subroutine ss_dopri5_options_default(o) bind(C, name='ss_dopri5_options_default')
        type(ss_dopri5_options), intent(out) :: o   !! controls to fill
        type(dopri5_options) :: d
        d%hmin = HMIN_DEFAULT
        call from_f_options(d%step_controls, d%safety, d%fac1, d%fac2, d%beta, d%nstiff, d%stop_on_stiff, o)
    end subroutine ss_dopri5_options_default

    !> Fill `o` with DOP853's default controls (Hairer's: safety 0.9, fac1 0.333, fac2 6,
    !! beta 0; h_min = HMIN_DEFAULT = 1e-6 s, max_steps = 10^8), for `ss_dop853`.
    subroutine ss_dop853_options_default(o) bind(C, name='ss_dop853_options_default')
        type(ss_dopri5_options), intent(out) :: o   !! controls to fill
        type(dop853_options) :: d
        d%hmin = HMIN_DEFAULT
        call from_f_options(d%step_controls, d%safety, d%fac1, d%fac2, d%beta, d%nstiff, d%stop_on_stiff, o)
    end subroutine ss_dop853_options_default

    !> Copy the message of a status code into buf (NUL-terminated, truncated to len - 1
    !! characters). Returns the full length of the message (without the NUL).
    function ss_message(status, buf, buflen) result(full) bind(C, name='ss_message')
        integer(c_int), value :: status                !! a status code
        character(kind=c_char), intent(out) :: buf(*)  !! room for len characters
        integer(c_size_t), value :: buflen             !! size of buf [chars]
        integer(c_int) :: full
        full = copy_out(stickslip_message(status), buf, buflen)
    end function ss_message

    !> Friction coefficient mu(v) [-] of one law at n relative velocities v [m/s].
    !! law: SS_LAW_COULOMB (1), SS_LAW_RECURDYN (2), SS_LAW_PROPOSED (3). Returns SS_OK
    !! or the code of the bad parameter (mu is then left untouched).
    function ss_friction(law, n, v, mu_s, mu_k, v_s, v_d, beta, a, mu) result(status) &
            bind(C, name='ss_friction')
        integer(c_int), value :: law           !! law code
        integer(c_int64_t), value :: n         !! number of velocities, >= 0
        real(c_double), intent(in) :: v(*)     !! relative velocities (n) [m/s]
        real(c_double), value :: mu_s          !! static coefficient [-]
        real(c_double), value :: mu_k          !! kinetic coefficient [-]
        real(c_double), value :: v_s           !! static threshold velocity [m/s]
        real(c_double), value :: v_d           !! dynamic threshold velocity (recurdyn) [m/s]
        real(c_double), value :: beta          !! exponent (proposed) [-]
        real(c_double), value :: a             !! base (proposed) [-]
        real(c_double), intent(inout) :: mu(*) !! friction coefficients (n) [-]
        integer(c_int) :: status
        if (n < 0) then
            status = SS_BAD_DIM
            return
        end if
        status = mu_named(law, 'mu_s,mu_k,v_s,v_d,beta,a', [mu_s, mu_k, v_s, v_d, beta, a], n, v, mu)
    end function ss_friction

    !> Simulate a scene from (x0, v0) at t = 0 to t_end; a wrapper of stickslip_simulate's
    !! `simulate`. scene: SS_SCENE_SLOPE (1) / SS_SCENE_BELT (2); method: SS_METHOD_RK4 (1,
    !! fixed step h) / SS_METHOD_DOPRI5 (2, rtol, atol and opts) / any other method of the
    !! registry (SS_METHOD_DOP853 reads opts but not its safety, fac1, fac2 and beta, which are
    !! DOPRI5's). opts may be NULL (defaults);
    !! opts->max_steps and opts->every_step apply to both methods.
    !! t_out(n_out): requested output times, or room for every step (overwritten);
    !! y_out: n_out rows of (x [m], v [m/s]). stats may be NULL. Returns stats->status.
    function ss_simulate(scene, law, method, p, x0, v0, t_end, h, rtol, atol, opts, n_out, &
                         t_out, y_out, stats) result(status) bind(C, name='ss_simulate')
        integer(c_int), value :: scene, law, method       !! scene, law and method codes
        type(ss_params), intent(in) :: p                  !! physical parameters
        real(c_double), value :: x0                       !! initial displacement [m]
        real(c_double), value :: v0                       !! initial velocity [m/s]
        real(c_double), value :: t_end                    !! final time [s]
        real(c_double), value :: h                        !! RK4 step [s]
        real(c_double), value :: rtol                     !! DOPRI5 relative tolerance
        real(c_double), value :: atol                     !! DOPRI5 absolute tolerance
        type(c_ptr), value :: opts                    !! const ss_dopri5_options * (NULL: defaults)
        integer(c_int), value :: n_out                    !! rows of t_out and y_out, >= 1
        real(c_double), intent(inout) :: t_out(*)         !! output times [s]
        real(c_double), intent(inout) :: y_out(2, *)      !! output states
        type(c_ptr), value :: stats                   !! ss_stats * (NULL: not returned)
        integer(c_int) :: status
        type(dopri5_options) :: fo
        type(ode_stats) :: st
        character(len=NAME_LEN), allocatable :: ckeys(:)
        real(dp), allocatable :: cvals(:)
        logical, allocatable :: keep(:)
        if (n_out < 1) then
            status = SS_BAD_N_OUT
            call put_stats(st, status, stats)
            return
        end if
        call get_options(opts, fo%step_controls, fo%safety, fo%fac1, fo%fac2, fo%beta, fo%nstiff, &
                         fo%stop_on_stiff)
        fo%h = h
        if (method < 1 .or. method > size(METHOD_TABLE)) then
            st%status = SS_BAD_METHOD
        else
            call struct_controls(fo, METHOD_TABLE(method)%controls, ckeys, cvals)
            ! The struct's safety, fac1, fac2 and beta are DOPRI5's constants: DOP853 keeps
            ! its own (Hairer's 0.9, 0.333, 6, 0; ss_run sets them by name).
            keep = .not. (method == METHOD_DOP853 .and. (ckeys == 'safety' .or. ckeys == 'fac1' .or. &
                                                          ckeys == 'fac2' .or. ckeys == 'beta_pi'))
            ckeys = pack(ckeys, keep)
            cvals = pack(cvals, keep)
            call simulate(int(scene), int(law), int(method), PARAMS(param_order())%name, transfer(p, [0.0_dp]), &
                          [x0, v0], t_end, [rtol], [atol], ckeys, cvals, t_out(1:n_out), y_out(:, 1:n_out), st)
        end if
        status = int(st%status, c_int)
        call put_stats(st, status, stats)
    end function ss_simulate

    !> Integrate a C user's ODE y' = f(t, y) (dimension n) from t0 to t_end with the
    !! library's DOPRI5. rtol, atol: ntol = 1 (scalar) or n values. opts may be NULL.
    !! t_out(n_out), y_out(n_out rows of n): as for ss_simulate. stats may be NULL.
    function ss_dopri5(f, data, n, t0, y0, t_end, ntol, rtol, atol, opts, n_out, t_out, y_out, stats) &
            result(status) bind(C, name='ss_dopri5')
        type(c_funptr), value :: f                    !! void f(double t, const double *y, double *dydt, int n, void *data)
        type(c_ptr), value :: data                    !! passed to f unchanged (may be NULL)
        integer(c_int), value :: n                    !! dimension of the state, >= 1
        real(c_double), value :: t0                   !! initial time
        real(c_double), intent(in) :: y0(*)           !! initial state (n)
        real(c_double), value :: t_end                !! final time, > t0
        integer(c_int), value :: ntol                 !! 1 or n
        real(c_double), intent(in) :: rtol(*)         !! relative tolerances (ntol)
        real(c_double), intent(in) :: atol(*)         !! absolute tolerances (ntol)
        type(c_ptr), value :: opts                    !! const ss_dopri5_options * (NULL: defaults)
        integer(c_int), value :: n_out                !! rows of t_out and y_out, >= 1
        real(c_double), intent(inout) :: t_out(*)     !! output times
        real(c_double), intent(inout) :: y_out(*)     !! output states (n_out * n)
        type(c_ptr), value :: stats                   !! ss_stats * (NULL: not returned)
        integer(c_int) :: status
        status = integrate_user(METHOD_DOPRI5, f, data, n, t0, y0, t_end, 0.0_c_double, ntol, rtol, &
                                atol, opts, n_out, t_out, y_out, stats)
    end function ss_dopri5

    !> Integrate a C user's ODE with the library's DOP853 (Hairer's 8(5,3) pair); the
    !! arguments are those of ss_dopri5. opts may be NULL (DOP853's defaults); fill a struct
    !! with ss_dop853_options_default before changing some of its fields.
    function ss_dop853(f, data, n, t0, y0, t_end, ntol, rtol, atol, opts, n_out, t_out, y_out, stats) &
            result(status) bind(C, name='ss_dop853')
        type(c_funptr), value :: f                    !! the C right-hand side (see ss_dopri5)
        type(c_ptr), value :: data                    !! passed to f unchanged (may be NULL)
        integer(c_int), value :: n                    !! dimension of the state, >= 1
        real(c_double), value :: t0                   !! initial time
        real(c_double), intent(in) :: y0(*)           !! initial state (n)
        real(c_double), value :: t_end                !! final time, > t0
        integer(c_int), value :: ntol                 !! 1 or n
        real(c_double), intent(in) :: rtol(*)         !! relative tolerances (ntol)
        real(c_double), intent(in) :: atol(*)         !! absolute tolerances (ntol)
        type(c_ptr), value :: opts                    !! const ss_dopri5_options * (NULL: DOP853's defaults)
        integer(c_int), value :: n_out                !! rows of t_out and y_out, >= 1
        real(c_double), intent(inout) :: t_out(*)     !! output times
        real(c_double), intent(inout) :: y_out(*)     !! output states (n_out * n)
        type(c_ptr), value :: stats                   !! ss_stats * (NULL: not returned)
        integer(c_int) :: status
        status = integrate_user(METHOD_DOP853, f, data, n, t0, y0, t_end, 0.0_c_double, ntol, rtol, &
                                atol, opts, n_out, t_out, y_out, stats)
    end function ss_dop853

    !> Integrate a C user's ODE with the library's classical RK4, fixed step h.
    !! opts may be NULL; only opts->max_steps and opts->every_step are used.
    function ss_rk4(f, data, n, t0, y0, t_end, h, opts, n_out, t_out, y_out, stats) &
            result(status) bind(C, name='ss_rk4')
        type(c_funptr), value :: f                    !! the C right-hand side (see ss_dopri5)
        type(c_ptr), value :: data                    !! passed to f unchanged
        integer(c_int), value :: n                    !! dimension, >= 1
        real(c_double), value :: t0                   !! initial time
        real(c_double), intent(in) :: y0(*)           !! initial state (n)
        real(c_double), value :: t_end                !! final time, > t0
        real(c_double), value :: h                    !! step size, > 0
        type(c_ptr), value :: opts                    !! const ss_dopri5_options * (NULL: defaults)
        integer(c_int), value :: n_out                !! rows of t_out and y_out, >= 1
        real(c_double), intent(inout) :: t_out(*)     !! output times
        real(c_double), intent(inout) :: y_out(*)     !! output states (n_out * n)
        type(c_ptr), value :: stats                   !! ss_stats * (NULL: not returned)
        integer(c_int) :: status
        status = integrate_user(METHOD_RK4, f, data, n, t0, y0, t_end, h, 1_c_int, [0.0_c_double], &
                                [0.0_c_double], opts, n_out, t_out, y_out, stats)
    end function ss_rk4

    !> Simulate a scene with a law and a method, all by code (`ss_code`), with the
    !! physical parameters and controls by name: pkeys and ckeys are comma-separated names
    !! (NULL or "" for none) valued by pvals[np] and cvals[nc] (flags and counts as
    !! doubles); the others take their defaults. y0[n]: (x0 [m], v0 [m/s], then the law's
    !! internal states). rtol, atol: ntol = 1 or n values (adaptive methods).
    !! t_out[n_out], y_out[n_out][n], stats: as for ss_simulate. Returns stats->status.
    function ss_run(scene, law, method, pkeys, np, pvals, n, y0, t_end, ntol, rtol, atol, ckeys, nc, &
                    cvals, n_out, t_out, y_out, stats) result(status) bind(C, name='ss_run')
        integer(c_int), value :: scene, law, method       !! codes
        character(kind=c_char), intent(in) :: pkeys(*)    !! parameter names, NUL-terminated
        integer(c_int), value :: np                       !! number of parameter values
        real(c_double), intent(in) :: pvals(*)            !! parameter values (np) [SI units]
        integer(c_int), value :: n                        !! state size
        real(c_double), intent(in) :: y0(*)               !! initial state (n)
        real(c_double), value :: t_end                    !! final time [s]
        integer(c_int), value :: ntol                     !! 1 or n
        real(c_double), intent(in) :: rtol(*), atol(*)    !! tolerances (ntol)
        character(kind=c_char), intent(in) :: ckeys(*)    !! control names, NUL-terminated
        integer(c_int), value :: nc                       !! number of control values
        real(c_double), intent(in) :: cvals(*)            !! control values (nc)
        integer(c_int), value :: n_out                    !! rows of t_out and y_out, >= 1
        real(c_double), intent(inout) :: t_out(*)         !! output times [s]
        real(c_double), intent(inout) :: y_out(*)         !! output states (n_out * n)
        type(c_ptr), value :: stats                       !! ss_stats * (NULL: not returned)
        integer(c_int) :: status
        type(ode_stats) :: st
        if (n < 1 .or. np < 0 .or. nc < 0 .or. (ntol /= 1 .and. ntol /= n)) then
            st%status = SS_BAD_DIM
        else if (n_out < 1) then
            st%status = SS_BAD_N_OUT
        else
            call run(y_out)
        end if
        status = int(st%status, c_int)
        call put_stats(st, status, stats)
    contains
        subroutine run(yo)
            real(c_double), intent(inout) :: yo(n, *)
            call simulate(int(scene), int(law), int(method), split_names(c_string(pkeys)), pvals(1:np), &
                          y0(1:n), t_end, rtol(1:ntol), atol(1:ntol), split_names(c_string(ckeys)), &
                          cvals(1:nc), t_out(1:n_out), yo(:, 1:n_out), st)
        end subroutine run
    end function ss_run

    !> mu[i] = friction coefficient [-] of law `law` (a code) at v[i] [m/s], i < n, with its
    !! parameters by name as in ss_run. Returns SS_OK or the code of the bad input.
    function ss_mu(law, pkeys, np, pvals, n, v, mu) result(status) bind(C, name='ss_mu')
        integer(c_int), value :: law                     !! law code
        character(kind=c_char), intent(in) :: pkeys(*)   !! parameter names, NUL-terminated
        integer(c_int), value :: np                      !! number of parameter values
        real(c_double), intent(in) :: pvals(*)           !! parameter values (np)
        integer(c_int64_t), value :: n                   !! number of velocities, >= 0
        real(c_double), intent(in) :: v(*)               !! relative velocities (n) [m/s]
        real(c_double), intent(inout) :: mu(*)           !! friction coefficients (n) [-]
        integer(c_int) :: status
        if (n < 0 .or. np < 0) then
            status = SS_BAD_DIM
            return
        end if
        status = mu_named(law, c_string(pkeys), pvals(1:np), n, v, mu)
    end function ss_mu

    !> The code of a law, scene or method by name: kind is "law", "scene" or "method".
    !! Returns 0 for an unknown name.
    function ss_code(kind, name) result(code) bind(C, name='ss_code')
        character(kind=c_char), intent(in) :: kind(*)   !! NUL-terminated
        character(kind=c_char), intent(in) :: name(*)   !! NUL-terminated
        integer(c_int) :: code
        code = int(code_of(c_string(kind), c_string(name)), c_int)
    end function ss_code

    !> Copy the registry (laws, scenes, methods, parameters, status codes; one record per
    !! line, fields separated by '|') into buf as ss_message does. Returns its full length.
    function ss_registry(buf, buflen) result(full) bind(C, name='ss_registry')
        character(kind=c_char), intent(out) :: buf(*)  !! room for buflen characters
        integer(c_size_t), value :: buflen             !! size of buf [chars]
        integer(c_int) :: full
        full = copy_out(registry_text(), buf, buflen)
    end function ss_registry

    ! -- a user's model (stickslip_user_model) through an opaque handle ---------------

    !> A new, empty model: its handle (`ss_model *`), or NULL when there is no memory for it.
    !! Add bodies, elements and signals to it, run it with ss_model_simulate, and free it with
    !! ss_model_free.
    function ss_model_new() result(model) bind(C, name='ss_model_new')
        type(c_ptr) :: model                  !! the handle (NULL: out of memory)
        type(model_handle), pointer :: box
        integer :: err
        model = c_null_ptr
        allocate(box, stat=err)
        if (err == 0) model = c_loc(box)
    end function ss_model_new

    !> Free a model of ss_model_new (NULL: nothing). The handle is dead afterwards.
    subroutine ss_model_free(model) bind(C, name='ss_model_free')
        type(c_ptr), value :: model           !! the handle, or NULL
        type(model_handle), pointer :: box
        if (handle(model, box) /= SS_OK) return
        box%tag = 0
        deallocate(box)
    end subroutine ss_model_free

    !> Add a body of mass (or inertia) mass [kg or kg m^2] at x0 [m] moving at v0 [m/s].
    !! Returns its index (bodies are numbered from 1; 0 is the ground) or SS_BAD_HANDLE. The
    !! values are checked by ss_model_check and ss_model_simulate.
    function ss_model_add_body(model, mass, x0, v0) result(index) bind(C, name='ss_model_add_body')
        type(c_ptr), value :: model           !! the model's handle
        real(c_double), value :: mass         !! mass or inertia, finite and > 0 [kg or kg m^2]
        real(c_double), value :: x0           !! initial position [m]
        real(c_double), value :: v0           !! initial velocity [m/s]
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index == SS_OK) index = int(box%model%add_body(mass, x0=x0, v0=v0), c_int)
    end function ss_model_add_body

    !> Add a spring of stiffness k [N/m] between bodies a and b (b = 0: the ground), relaxed
    !! at x_a - x_b = rest_length [m]. Returns its index (from 1) or SS_BAD_HANDLE.
    function ss_model_add_spring(model, a, b, k, rest_length) result(index) bind(C, name='ss_model_add_spring')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: a            !! a body, 1 .. n_bodies
        integer(c_int), value :: b            !! another body, or 0 for the ground
        real(c_double), value :: k            !! stiffness, finite and >= 0 [N/m]
        real(c_double), value :: rest_length  !! x_a - x_b at rest [m]
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index /= SS_OK) return
        call box%model%add_spring(int(a), int(b), k, rest_length)
        index = int(size(box%model%spr_k), c_int)
    end function ss_model_add_spring

    !> Add a damper c [N s/m] between bodies a and b (b = 0: the ground). Returns its index
    !! (from 1) or SS_BAD_HANDLE.
    function ss_model_add_damper(model, a, b, c) result(index) bind(C, name='ss_model_add_damper')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: a            !! a body, 1 .. n_bodies
        integer(c_int), value :: b            !! another body, or 0 for the ground
        real(c_double), value :: c            !! damping, finite and >= 0 [N s/m]
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index /= SS_OK) return
        call box%model%add_damper(int(a), int(b), c)
        index = int(size(box%model%dmp_c), c_int)
    end function ss_model_add_damper

    !> Add the force of a signal [N] (ss_signal_*) on a body. Returns its index (from 1) or
    !! SS_BAD_HANDLE.
    function ss_model_add_force(model, body, signal) result(index) bind(C, name='ss_model_add_force')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: body         !! the body, 1 .. n_bodies
        integer(c_int), value :: signal       !! the force's signal [N], from ss_signal_*
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index /= SS_OK) return
        call box%model%add_force(int(body), int(signal))
        index = int(size(box%model%frc_body), c_int)
    end function ss_model_add_force

    !> Prescribe the motion of a body by a signal: its position [m] (kind SS_DRIVE_POSITION;
    !! a signal without steps) or its velocity [m/s] (SS_DRIVE_VELOCITY; the position is then
    !! x0 plus its integral), exactly under every method (`stickslip_model%add_drive`). Returns
    !! the drive's index (from 1) or SS_BAD_HANDLE.
    function ss_model_add_drive(model, body, kind, signal) result(index) bind(C, name='ss_model_add_drive')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: body         !! the driven body, 1 .. n_bodies
        integer(c_int), value :: kind         !! SS_DRIVE_POSITION or SS_DRIVE_VELOCITY
        integer(c_int), value :: signal       !! the drive's signal [m or m/s], from ss_signal_*
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index /= SS_OK) return
        call box%model%add_drive(int(body), int(signal), int(kind))
        index = int(size(box%model%drv_body), c_int)
    end function ss_model_add_drive

    !> Copy the drives' forces on their bodies [N] of the model's last ss_model_simulate into
    !! force[n_drives * n_out] (force[(d - 1) * n_out + i] = drive d at t_out[i]; NaN where a
    !! contact joins the driven body under event_driven or moreau, see
    !! `stickslip_model%drive_forces`). Returns SS_OK, SS_BAD_HANDLE, or SS_BAD_DIM when n
    !! is not n_drives times the last run's n_out or force is NULL.
    function ss_model_drive_forces(model, n, force) result(status) bind(C, name='ss_model_drive_forces')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: n            !! room in force [values]
        type(c_ptr), value :: force           !! double *: the forces (n)
        integer(c_int) :: status
        type(model_handle), pointer :: box
        real(c_double), pointer :: out(:, :)
        status = handle(model, box)
        if (status /= SS_OK) return
        status = SS_BAD_DIM
        if (.not. (allocated(box%drive_force) .and. c_associated(force))) return
        if (n /= size(box%drive_force)) return
        call c_f_pointer(force, out, [size(box%drive_force, 2), size(box%drive_force, 1)])
        out = transpose(box%drive_force)
        status = SS_OK
    end function ss_model_drive_forces

    !> Add a frictional contact between bodies a and b (b = 0: the ground): the friction force
    !! on a opposes the slip v_a - v_b - w (w the surface velocity's signal, 0 for none), b gets
    !! the opposite force; a normal force <= 0 opens the contact. The law by code (SS_LAW_*,
    !! or ss_code("law", name)) with its parameters by name as in ss_run (pkeys
    !! comma-separated, NULL or "" for none, valued by pvals[np]; the others take their
    !! defaults). Returns the contact's index (from 1), SS_BAD_HANDLE, or SS_BAD_DIM when
    !! pkeys does not name np parameters or pvals is NULL with np > 0. The law and its values
    !! are checked by ss_model_check and ss_model_simulate.
    function ss_model_add_contact(model, a, b, law, normal_force, surface_velocity, pkeys, np, pvals) &
            result(index) bind(C, name='ss_model_add_contact')
        type(c_ptr), value :: model             !! the model's handle
        integer(c_int), value :: a              !! a body, 1 .. n_bodies (the friction force -mu N acts on it)
        integer(c_int), value :: b              !! another body, or 0 for the ground (it gets +mu N)
        integer(c_int), value :: law            !! the law's code (SS_LAW_*)
        integer(c_int), value :: normal_force   !! the normal force's signal [N] (<= 0: open)
        integer(c_int), value :: surface_velocity  !! the surface velocity's signal [m/s], or 0 for none
        type(c_ptr), value :: pkeys             !! const char *: the law's parameter names, comma-separated (NULL: none)
        integer(c_int), value :: np             !! number of parameter values, >= 0
        type(c_ptr), value :: pvals             !! const double *: their values (np) [SI units]
        integer(c_int) :: index
        type(model_handle), pointer :: box
        character(len=NAME_LEN), allocatable :: keys(:)
        real(c_double), pointer :: vals(:)
        character(len=:), allocatable :: name
        index = handle(model, box)
        if (index == SS_OK) index = c_array(pvals, np, vals)
        if (index /= SS_OK) return
        keys = split_names(c_string_at(pkeys))
        if (size(keys) /= np) then
            index = SS_BAD_DIM
            return
        end if
        name = ''          ! an unknown code: build says SS_BAD_LAW for this contact
        if (law >= 1 .and. law <= size(LAW_TABLE)) name = trim(LAW_TABLE(law)%name)
        call box%model%add_contact(int(a), int(b), name, int(normal_force), int(surface_velocity), keys, vals)
        index = int(size(box%model%con_a), c_int)
    end function ss_model_add_contact

    !> A signal of the model: the number c. Returns its index (signals are numbered from 1)
    !! or SS_BAD_HANDLE.
    function ss_signal_constant(model, c) result(index) bind(C, name='ss_signal_constant')
        type(c_ptr), value :: model           !! the model's handle
        real(c_double), value :: c            !! the value [unit of what it drives]
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index == SS_OK) index = int(box%model%constant(c), c_int)
    end function ss_signal_constant

    !> A signal: before for t < time, after from t = time on (a time event for the methods
    !! with events). Returns its index or SS_BAD_HANDLE.
    function ss_signal_step(model, time, before, after) result(index) bind(C, name='ss_signal_step')
        type(c_ptr), value :: model           !! the model's handle
        real(c_double), value :: time         !! the step's time [s]
        real(c_double), value :: before       !! the value before it
        real(c_double), value :: after        !! the value from it on
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index == SS_OK) index = int(box%model%step(time, before, after), c_int)
    end function ss_signal_step

    !> A signal: 0 up to start, rising linearly by height over duration, then height.
    !! Returns its index or SS_BAD_HANDLE.
    function ss_signal_ramp(model, start, duration, height) result(index) bind(C, name='ss_signal_ramp')
        type(c_ptr), value :: model           !! the model's handle
        real(c_double), value :: start        !! when it starts rising [s]
        real(c_double), value :: duration     !! how long it rises, > 0 [s]
        real(c_double), value :: height       !! the value it reaches
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index == SS_OK) index = int(box%model%ramp(start, duration, height), c_int)
    end function ss_signal_ramp

    !> A signal: amplitude sin(2 pi frequency t + phase) + offset. Returns its index or
    !! SS_BAD_HANDLE.
    function ss_signal_sine(model, amplitude, frequency, phase, offset) result(index) bind(C, name='ss_signal_sine')
        type(c_ptr), value :: model           !! the model's handle
        real(c_double), value :: amplitude    !! amplitude
        real(c_double), value :: frequency    !! frequency [Hz]
        real(c_double), value :: phase        !! phase [rad]
        real(c_double), value :: offset       !! offset
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index == SS_OK) index = int(box%model%sine(amplitude, frequency, phase, offset), c_int)
    end function ss_signal_sine

    !> A signal: linear between the points (t[i], values[i]), i < n, held constant outside
    !! (its points are time events). Returns its index, SS_BAD_HANDLE, or SS_BAD_DIM when n < 0
    !! or an array is NULL with n > 0.
    function ss_signal_table(model, n, t, values) result(index) bind(C, name='ss_signal_table')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: n            !! number of points, >= 1
        type(c_ptr), value :: t               !! const double *: times, strictly increasing (n) [s]
        type(c_ptr), value :: values          !! const double *: values at those times (n)
        integer(c_int) :: index
        type(model_handle), pointer :: box
        real(c_double), pointer :: tt(:), vv(:)
        index = handle(model, box)
        if (index == SS_OK) index = c_array(t, n, tt)
        if (index == SS_OK) index = c_array(values, n, vv)
        if (index == SS_OK) index = int(box%model%table(tt, vv), c_int)
    end function ss_signal_table

    !> A signal: s1 + s2. Returns its index or SS_BAD_HANDLE (an unknown signal makes a
    !! malformed one, which ss_model_check reports).
    function ss_signal_add(model, s1, s2) result(index) bind(C, name='ss_signal_add')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: s1           !! a signal
        integer(c_int), value :: s2           !! another signal
        integer(c_int) :: index
        index = two_signals(model, s1, s2, '+')
    end function ss_signal_add

    !> A signal: s1 - s2. Returns its index or SS_BAD_HANDLE.
    function ss_signal_sub(model, s1, s2) result(index) bind(C, name='ss_signal_sub')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: s1           !! a signal
        integer(c_int), value :: s2           !! the signal subtracted
        integer(c_int) :: index
        index = two_signals(model, s1, s2, '-')
    end function ss_signal_sub

    !> A signal: s1 * s2. Returns its index or SS_BAD_HANDLE.
    function ss_signal_mul(model, s1, s2) result(index) bind(C, name='ss_signal_mul')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: s1           !! a signal
        integer(c_int), value :: s2           !! another signal
        integer(c_int) :: index
        index = two_signals(model, s1, s2, '*')
    end function ss_signal_mul

    !> Check every element of the model (what ss_model_simulate does first). Returns SS_OK or
    !! the code of the first bad element (SS_BAD_MODEL_EMPTY, SS_BAD_BODY, SS_BAD_MASS,
    !! SS_BAD_SPRING, SS_BAD_DAMPER, SS_BAD_SIGNAL, SS_BAD_LAW, a law parameter's SS_BAD_*,
    !! ...), which ss_model_error and ss_model_message then name.
    function ss_model_check(model) result(status) bind(C, name='ss_model_check')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int) :: status
        type(model_handle), pointer :: box
        type(model_system) :: sys
        status = handle(model, box)
        if (status /= SS_OK) return
        call box%model%build(sys, box%status, box%elem_kind, box%elem_index)
        status = int(box%status, c_int)
    end function ss_model_check

    !> The status of the model's last ss_model_check or ss_model_simulate (SS_BAD_HANDLE for a
    !! bad handle), with the kind (SS_ELEM_BODY, ..., SS_ELEM_SIGNAL; 0 for none) and index
    !! (from 1; 0 for none) of the element it names in *elem_kind and *elem_index (each may be NULL).
    function ss_model_error(model, elem_kind, elem_index) result(status) bind(C, name='ss_model_error')
        type(c_ptr), value :: model           !! the model's handle
        type(c_ptr), value :: elem_kind       !! int *: the bad element's kind, SS_ELEM_* (NULL: not returned)
        type(c_ptr), value :: elem_index      !! int *: its index, from 1 (NULL: not returned)
        integer(c_int) :: status
        type(model_handle), pointer :: box
        status = handle(model, box)
        if (status /= SS_OK) return
        status = int(box%status, c_int)
        call put_int(elem_kind, box%elem_kind)
        call put_int(elem_index, box%elem_index)
    end function ss_model_error

    !> Copy the message of the model's last status, naming the element ("contact 2 (body 1 -
    !! ground): mu_k: ..."), into buf as ss_message does. Returns the message's full length.
    function ss_model_message(model, buf, buflen) result(full) bind(C, name='ss_model_message')
        type(c_ptr), value :: model                    !! the model's handle
        character(kind=c_char), intent(out) :: buf(*)  !! room for buflen characters
        integer(c_size_t), value :: buflen             !! size of buf [chars]
        integer(c_int) :: full
        type(model_handle), pointer :: box
        if (handle(model, box) /= SS_OK) then
            full = copy_out(stickslip_message(SS_BAD_HANDLE), buf, buflen)
        else
            full = copy_out(element_message(box), buf, buflen)
        end if
    end function ss_model_message

    !> Run the model from t = 0 (its bodies' x0, v0; law states 0) to t_end with a method by
    !! code (SS_METHOD_*). h: the step of the fixed-step methods [s] (ignored by the others;
    !! an h in ckeys wins); rtol, atol: the tolerances of the adaptive methods; other controls
    !! by name as in ss_run (ckeys comma-separated, NULL or "" for none, valued by cvals[nc]).
    !! t_out[n_out]: the output times (non-decreasing, in [0, t_end]), or with the control
    !! every_step room for every step (overwritten with the step times). x and v: the
    !! n_bodies x n_out positions [m] and velocities [m/s], x[(j - 1) * n_out + i] = body j at
    !! t_out[i]. events: room for events_room rows of (t [s], kind SS_EVENT_*, position [m] of
    !! the contact, contact index from 1) of event_driven (NULL with events_room = 0: none);
    !! *n_events: how many there were (may exceed events_room; NULL: not returned). stats may be
    !! NULL. Returns stats->status: SS_OK, a run's outcome, or the code of the first bad input
    !! (a bad element: see ss_model_check; SS_BAD_DIM for a NULL output array or a count that
    !! does not match; SS_BAD_METHOD; SS_NOT_SETVALUED for moreau or event_driven with a
    !! smooth law).
    function ss_model_simulate(model, method, t_end, h, rtol, atol, ckeys, nc, cvals, n_out, t_out, x, v, &
                               stats, events_room, events, n_events) result(status) bind(C, name='ss_model_simulate')
        type(c_ptr), value :: model           !! the model's handle
        integer(c_int), value :: method       !! the method's code (SS_METHOD_*)
        real(c_double), value :: t_end        !! final time, > 0 [s]
        real(c_double), value :: h            !! step of the fixed-step methods [s]
        real(c_double), value :: rtol         !! relative tolerance of the adaptive methods
        real(c_double), value :: atol         !! absolute tolerance of the adaptive methods
        type(c_ptr), value :: ckeys           !! const char *: control names, comma-separated (NULL: none)
        integer(c_int), value :: nc           !! number of control values, >= 0
        type(c_ptr), value :: cvals           !! const double *: their values (nc; flags and counts as doubles)
        integer(c_int), value :: n_out        !! output times, >= 1
        type(c_ptr), value :: t_out           !! double *: output times (n_out) [s]
        type(c_ptr), value :: x               !! double *: positions (n_bodies * n_out) [m]
        type(c_ptr), value :: v               !! double *: velocities (n_bodies * n_out) [m/s]
        type(c_ptr), value :: stats           !! ss_stats * (NULL: not returned)
        integer(c_int), value :: events_room  !! rows of events, >= 0
        type(c_ptr), value :: events          !! double *: events (4 * events_room), or NULL for none
        type(c_ptr), value :: n_events        !! int64_t *: number of events of the run (NULL: not returned)
        integer(c_int) :: status
        type(model_handle), pointer :: box
        type(model_system) :: sys
        type(ode_stats) :: st
        real(c_double), pointer :: t(:), xo(:, :), vo(:, :), ev(:, :)
        real(c_double), allocatable, target :: no_events(:, :)
        real(dp), allocatable :: y(:, :), vals(:)
        character(len=NAME_LEN), allocatable :: keys(:)
        integer(c_int64_t), pointer :: count
        integer :: nb
        count => null()
        if (c_associated(n_events)) then
            call c_f_pointer(n_events, count)
            count = 0_c_int64_t
        end if
        status = handle(model, box)
        if (status == SS_OK) then
            call box%model%build(sys, box%status, box%elem_kind, box%elem_index)
            status = int(box%status, c_int)
        end if
        if (status == SS_OK .and. n_out < 1) status = SS_BAD_N_OUT
        if (status == SS_OK .and. .not. (c_associated(t_out) .and. c_associated(x) .and. c_associated(v) .and. &
                                         events_room >= 0 .and. (events_room == 0 .or. c_associated(events)))) &
            status = SS_BAD_DIM
        if (status == SS_OK) status = model_controls(method, h, ckeys, nc, cvals, keys, vals)
        if (status == SS_OK) then
            nb = size(box%model%mass)
            call c_f_pointer(t_out, t, [n_out])
            call c_f_pointer(x, xo, [n_out, nb])
            call c_f_pointer(v, vo, [n_out, nb])
            if (events_room > 0) then
                call c_f_pointer(events, ev, [4, events_room])
            else
                allocate(no_events(4, 0))
                ev => no_events
            end if
            allocate(y(box%model%state_size(sys), n_out))
            y = 0.0_dp
            if (allocated(box%drive_force)) deallocate(box%drive_force)
            allocate(box%drive_force(size(box%model%drv_body), n_out))
            call box%model%simulate(trim(METHOD_TABLE(method)%name), t_end, t, y, st, [rtol], [atol], keys, vals, &
                                    box%elem_kind, box%elem_index, events=ev, drive_force=box%drive_force)
            status = int(st%status, c_int)
            xo = transpose(y(:nb, :))
            vo = transpose(y(nb + 1:2 * nb, :))
            if (associated(count)) count = int(st%nevents, c_int64_t)
        end if
        if (associated(box)) box%status = status
        call put_stats(st, status, stats)
    end function ss_model_simulate

    ! -- periodic orbits (stickslip_orbit) --------------------------------------------

    !> The periodic-orbit solver's defaults: tol 1e-9, max_iter 30, fd_newton 1e-5,
    !! fd_monodromy 1e-4 (those of stickslip.periodic_orbit), the section at t0 = 0.
    subroutine ss_orbit_options_default(o) bind(C, name='ss_orbit_options_default')
        type(ss_orbit_options), intent(out) :: o   !! the options
        type(orbit_options) :: f
        o = ss_orbit_options(f%tol, int(f%max_iter, c_int), f%fd_newton, f%fd_monodromy, f%t0)
    end subroutine ss_orbit_options_default

    !> A periodic orbit of a scene with a law (codes, parameters by name as in ss_run) by
    !! single shooting with a method (code) and its controls by name: y0[n] the guess of the
    !! state at the section on entry, the orbit's state on return (the last iterate when
    !! Newton did not converge; untouched for bad input); period: the forcing period
    !! (autonomous = 0) or the guess of the period (autonomous = 1) [s]. opts NULL: defaults.
    !! monodromy[n * n] (row i: d y_i(T) / d y0_j, j < n), mult_re[n], mult_im[n] (the
    !! multipliers, largest modulus first) and info may each be NULL; when the three arrays
    !! are NULL no monodromy is computed.
    function ss_periodic_orbit(scene, law, method, pkeys, np, pvals, n, y0, period, autonomous, ntol, rtol, atol, &
                               ckeys, nc, cvals, opts, monodromy, mult_re, mult_im, info) result(status) &
                               bind(C, name='ss_periodic_orbit')
        integer(c_int), value :: scene, law, method       !! codes
        character(kind=c_char), intent(in) :: pkeys(*)    !! parameter names, NUL-terminated
        integer(c_int), value :: np                       !! number of parameter values
        real(c_double), intent(in) :: pvals(*)            !! parameter values (np) [SI units]
        integer(c_int), value :: n                        !! state size
        real(c_double), intent(inout) :: y0(*)            !! guess in, orbit's state out (n)
        real(c_double), value :: period                   !! forcing period or its guess [s]
        integer(c_int), value :: autonomous               !! 1: the period is an unknown
        integer(c_int), value :: ntol                     !! 1 or n
        real(c_double), intent(in) :: rtol(*), atol(*)    !! tolerances (ntol)
        character(kind=c_char), intent(in) :: ckeys(*)    !! control names, NUL-terminated
        integer(c_int), value :: nc                       !! number of control values
        real(c_double), intent(in) :: cvals(*)            !! control values (nc)
        type(c_ptr), value :: opts                        !! const ss_orbit_options * (NULL: defaults)
        type(c_ptr), value :: monodromy                   !! double *: n * n, or NULL
        type(c_ptr), value :: mult_re, mult_im            !! double *: n each, or NULL
        type(c_ptr), value :: info                        !! ss_orbit_info *, or NULL
        integer(c_int) :: status
        type(orbit_options) :: o
        type(orbit_result) :: orb
        if (n < 1 .or. np < 0 .or. nc < 0 .or. (ntol /= 1 .and. ntol /= n)) then
            status = SS_BAD_DIM
            return
        end if
        o = orbit_options_of(opts, monodromy, mult_re, mult_im)
        call scene_periodic_orbit(int(scene), int(law), split_names(c_string(pkeys)), pvals(1:np), int(method), &
                                  y0(1:n), period, autonomous /= 0, rtol(1:ntol), atol(1:ntol), &
                                  split_names(c_string(ckeys)), cvals(1:nc), o, orb)
        status = put_orbit(orb, y0, monodromy, mult_re, mult_im, info)
    end function ss_periodic_orbit

    !> A periodic orbit of a model (its handle) by single shooting with a method (code):
    !! y0[n] = (x of every body, v of every body) the guess on entry and the orbit's state on
    !! return (as ss_periodic_orbit); h, rtol, atol, ckeys, nc, cvals as for ss_model_simulate;
    !! period, autonomous, opts, monodromy, mult_re, mult_im, info as for ss_periodic_orbit.
    !! A bad element is named as by ss_model_check (ss_model_error, ss_model_message).
    function ss_model_periodic_orbit(model, method, n, y0, period, autonomous, h, rtol, atol, ckeys, nc, cvals, &
                                     opts, monodromy, mult_re, mult_im, info) result(status) &
                                     bind(C, name='ss_model_periodic_orbit')
        type(c_ptr), value :: model                       !! the model's handle
        integer(c_int), value :: method                   !! the method's code (SS_METHOD_*)
        integer(c_int), value :: n                        !! state size
        real(c_double), intent(inout) :: y0(*)            !! guess in, orbit's state out (n)
        real(c_double), value :: period                   !! forcing period or its guess [s]
        integer(c_int), value :: autonomous               !! 1: the period is an unknown
        real(c_double), value :: h                        !! step of the fixed-step methods [s]
        real(c_double), value :: rtol, atol               !! tolerances of the adaptive methods
        type(c_ptr), value :: ckeys                       !! const char *: control names (NULL: none)
        integer(c_int), value :: nc                       !! number of control values
        type(c_ptr), value :: cvals                       !! const double *: their values (nc)
        type(c_ptr), value :: opts                        !! const ss_orbit_options * (NULL: defaults)
        type(c_ptr), value :: monodromy                   !! double *: n * n, or NULL
        type(c_ptr), value :: mult_re, mult_im            !! double *: n each, or NULL
        type(c_ptr), value :: info                        !! ss_orbit_info *, or NULL
        integer(c_int) :: status
        type(model_handle), pointer :: box
        type(orbit_options) :: o
        type(orbit_result) :: orb
        real(dp), allocatable :: vals(:)
        character(len=NAME_LEN), allocatable :: keys(:)
        status = handle(model, box)
        if (status == SS_OK .and. n < 1) status = SS_BAD_DIM
        if (status == SS_OK) status = model_controls(method, h, ckeys, nc, cvals, keys, vals)
        if (status == SS_OK) then
            o = orbit_options_of(opts, monodromy, mult_re, mult_im)
            call model_periodic_orbit(box%model, trim(METHOD_TABLE(method)%name), y0(1:n), period, autonomous /= 0, &
                                      [rtol], [atol], keys, vals, o, orb, box%elem_kind, box%elem_index)
            status = put_orbit(orb, y0, monodromy, mult_re, mult_im, info)
        end if
        if (associated(box)) box%status = status
    end function ss_model_periodic_orbit

    ! -- helpers -------------------------------------------------------------------

    !> The model behind a handle: SS_OK, or SS_BAD_HANDLE (box null) for NULL or a pointer
    !! that does not hold a live model (one never made by ss_model_new, or freed; a freed
    !! handle is told apart only while its memory has not been reused).
    function handle(model, box) result(status)
        type(c_ptr), intent(in) :: model
        type(model_handle), pointer, intent(out) :: box
        integer(c_int) :: status
        status = SS_BAD_HANDLE
        box => null()
        if (.not. c_associated(model)) return
        call c_f_pointer(model, box)
        if (box%tag /= LIVE_TAG) then
            box => null()
            return
        end if
        status = SS_OK
    end function handle

    !> A signal of two signals of a model: s1 + s2, s1 - s2 or s1 * s2 (op '+', '-' or '*');
    !! its index or SS_BAD_HANDLE.
    function two_signals(model, s1, s2, op) result(index)
        type(c_ptr), intent(in) :: model
        integer(c_int), intent(in) :: s1, s2
        character, intent(in) :: op
        integer(c_int) :: index
        type(model_handle), pointer :: box
        index = handle(model, box)
        if (index /= SS_OK) return
        select case (op)
        case ('+')
            index = int(box%model%plus(int(s1), int(s2)), c_int)
        case ('-')
            index = int(box%model%minus(int(s1), int(s2)), c_int)
        case default
            index = int(box%model%times(int(s1), int(s2)), c_int)
        end select
    end function two_signals

    !> A C array of n doubles as a Fortran pointer (zero-size for n = 0, NULL or not):
    !! SS_OK, or SS_BAD_DIM for n < 0 or NULL with n > 0.
    function c_array(p, n, a) result(status)
        type(c_ptr), intent(in) :: p
        integer(c_int), intent(in) :: n
        real(c_double), pointer, intent(out) :: a(:)
        integer(c_int) :: status
        status = SS_OK
        if (n < 0 .or. (n > 0 .and. .not. c_associated(p))) then
            status = SS_BAD_DIM
            a => null()
        else if (n == 0) then
            a => no_values
        else
            call c_f_pointer(p, a, [n])
        end if
    end function c_array

    !> The NUL-terminated C string at p as a Fortran string ('' for NULL).
    function c_string_at(p) result(f)
        type(c_ptr), intent(in) :: p
        character(len=:), allocatable :: f
        character(kind=c_char), pointer :: s(:)
        integer :: n
        if (.not. c_associated(p)) then
            f = ''
            return
        end if
        n = int(c_strlen(p))
        call c_f_pointer(p, s, [n])
        allocate(character(len=n) :: f)
        f = transfer(s, f)
    end function c_string_at

    !> The solver's options from a C struct (NULL: the defaults); no monodromy when no array
    !! would receive it.
    function orbit_options_of(opts, monodromy, mult_re, mult_im) result(o)
        type(c_ptr), intent(in) :: opts, monodromy, mult_re, mult_im
        type(orbit_options) :: o
        type(ss_orbit_options), pointer :: c
        if (c_associated(opts)) then
            call c_f_pointer(opts, c)
            o%tol = c%tol
            o%max_iter = int(c%max_iter)
            o%fd_newton = c%fd_newton
            o%fd_monodromy = c%fd_monodromy
            o%t0 = c%t0
        end if
        o%monodromy = c_associated(monodromy) .or. c_associated(mult_re) .or. c_associated(mult_im)
    end function orbit_options_of

    !> An orbit's results into the C arrays and struct that are not NULL; its status.
    function put_orbit(orb, y0, monodromy, mult_re, mult_im, info) result(status)
        type(orbit_result), intent(in) :: orb
        real(c_double), intent(inout) :: y0(*)
        type(c_ptr), intent(in) :: monodromy, mult_re, mult_im, info
        integer(c_int) :: status
        real(c_double), pointer :: a(:, :), w(:)
        type(ss_orbit_info), pointer :: s
        integer :: n
        status = int(orb%status, c_int)
        if (.not. allocated(orb%y0)) return          ! the system could not be built
        n = size(orb%y0)
        if (status > -100) y0(1:n) = orb%y0
        if (size(orb%monodromy, 1) == n .and. n > 0 .and. allocated(orb%mult_re)) then
            if (c_associated(monodromy)) then
                call c_f_pointer(monodromy, a, [n, n])
                a = transpose(orb%monodromy)          ! C row i: d y_i(T) / d y0_j
            end if
            if (c_associated(mult_re)) then
                call c_f_pointer(mult_re, w, [n])
                w = orb%mult_re
            end if
            if (c_associated(mult_im)) then
                call c_f_pointer(mult_im, w, [n])
                w = orb%mult_im
            end if
        end if
        if (c_associated(info)) then
            call c_f_pointer(info, s)
            s = ss_orbit_info(orb%period, orb%residual, int(orb%iterations, c_int), int(orb%runs, c_int), &
                              int(orb%trivial - 1, c_int), merge(1_c_int, 0_c_int, orb%stable))
        end if
    end function put_orbit

    !> A model call's controls from C: the method's code checked, ckeys split and valued by
    !! cvals (nc values), and the step h as the control "h" of a fixed-step method unless
    !! ckeys names it. SS_OK, SS_BAD_METHOD or SS_BAD_DIM.
    function model_controls(method, h, ckeys, nc, cvals, keys, vals) result(status)
        integer(c_int), intent(in) :: method, nc
        real(c_double), intent(in) :: h
        type(c_ptr), intent(in) :: ckeys, cvals
        character(len=NAME_LEN), allocatable, intent(out) :: keys(:)
        real(dp), allocatable, intent(out) :: vals(:)
        integer(c_int) :: status
        real(c_double), pointer :: cv(:)
        status = c_array(cvals, nc, cv)
        if (status == SS_OK .and. (method < 1 .or. method > size(METHOD_TABLE))) status = SS_BAD_METHOD
        if (status /= SS_OK) return
        keys = split_names(c_string_at(ckeys))
        if (size(keys) /= nc) then
            status = SS_BAD_DIM
            return
        end if
        vals = cv
        if (any(split_names(METHOD_TABLE(method)%controls) == 'h') .and. .not. any(keys == 'h')) then
            keys = [character(len=NAME_LEN) :: 'h', keys]
            vals = [h, vals]
        end if
    end function model_controls

    !> *p = value for a C int pointer (NULL: nothing).
    subroutine put_int(p, value)
        type(c_ptr), intent(in) :: p
        integer, intent(in) :: value
        integer(c_int), pointer :: target_int
        if (.not. c_associated(p)) return
        call c_f_pointer(p, target_int)
        target_int = int(value, c_int)
    end subroutine put_int

    !> The message of a model's last status, prefixed by the element it names:
    !! "contact 2 (body 1 - ground): ...".
    function element_message(box) result(msg)
        type(model_handle), intent(in) :: box
        character(len=:), allocatable :: msg
        character(len=*), parameter :: KINDS(7) = [character(len=7) :: 'body', 'spring', 'damper', 'force', &
                                                    'contact', 'signal', 'drive']
        integer :: i
        msg = stickslip_message(box%status)
        if (box%elem_kind < 1 .or. box%elem_kind > size(KINDS) .or. box%elem_index < 1) return
        i = box%elem_index
        select case (box%elem_kind)
        case (ELEM_SPRING)
            msg = pair(box%model%spr_a(i), box%model%spr_b(i)) // msg
        case (ELEM_DAMPER)
            msg = pair(box%model%dmp_a(i), box%model%dmp_b(i)) // msg
        case (ELEM_CONTACT)
            msg = pair(box%model%con_a(i), box%model%con_b(i)) // msg
        case (ELEM_FORCE)
            msg = ' (' // body_name(box%model%frc_body(i)) // '): ' // msg
        case (ELEM_DRIVE)
            msg = ' (' // body_name(box%model%drv_body(i)) // '): ' // msg
        case default
            msg = ': ' // msg
        end select
        msg = trim(KINDS(box%elem_kind)) // ' ' // number(i) // msg
    contains
        function pair(a, b) result(s)
            integer, intent(in) :: a, b
            character(len=:), allocatable :: s
            s = ' (' // body_name(a) // ' - ' // body_name(b) // '): '
        end function pair
        function body_name(j) result(s)
            integer, intent(in) :: j
            character(len=:), allocatable :: s
            s = 'body ' // number(j)
            if (j == 0) s = 'ground'
        end function body_name
        function number(j) result(s)
            integer, intent(in) :: j
            character(len=:), allocatable :: s
            character(len=12) :: buf
            write (buf, '(i0)') j
            s = trim(buf)
        end function number
    end function element_message

    !> Evaluate a law given by code with named parameters at n velocities.
    function mu_named(law, keys, vals, n, v, mu) result(status)
        integer(c_int), intent(in) :: law
        character(len=*), intent(in) :: keys
        real(dp), intent(in) :: vals(:)
        integer(c_int64_t), intent(in) :: n
        real(c_double), intent(in) :: v(*)
        real(c_double), intent(inout) :: mu(*)
        integer(c_int) :: status
        class(friction_law), allocatable :: fl
        type(param_values) :: p
        status = int(make_law(int(law), split_names(keys), vals, fl, p), c_int)
        if (status == SS_OK) mu(1:n) = fl%mu(v(1:n))
    end function mu_named

    !> A NUL-terminated C string as a Fortran string.
    function c_string(s) result(f)
        character(kind=c_char), intent(in) :: s(*)
        character(len=:), allocatable :: f
        integer :: i
        i = 0
        do
            if (s(i + 1) == c_null_char) exit
            i = i + 1
        end do
        allocate(character(len=i) :: f)
        f = transfer(s(1:i), f)
    end function c_string

    !> Copy msg into buf (NUL-terminated, truncated to buflen - 1); its full length.
    function copy_out(msg, buf, buflen) result(full)
        character(len=*), intent(in) :: msg
        character(kind=c_char), intent(out) :: buf(*)
        integer(c_size_t), intent(in) :: buflen
        integer(c_int) :: full
        integer :: i, ncopy
        full = int(len_trim(msg), c_int)
        if (buflen < 1) return
        ncopy = int(min(int(full, c_size_t), buflen - 1))
        do i = 1, ncopy
            buf(i) = msg(i:i)
        end do
        buf(ncopy + 1) = c_null_char
    end function copy_out

    !> Positions in PARAMS of the fields of ss_params, in the struct's order.
    pure function param_order() result(idx)
        integer :: idx(11)
        character(len=NAME_LEN), parameter :: fields(11) = [character(len=NAME_LEN) :: 'mu_s', 'mu_k', &
            'v_s', 'v_d', 'beta', 'a', 'm', 'g', 'theta_deg', 'k', 'v_b']
        integer :: i
        do i = 1, 11
            idx(i) = findloc(PARAMS%name, fields(i), dim=1)
        end do
    end function param_order

    !> The controls `names` (a method's list) valued from the options struct.
    subroutine struct_controls(o, names, keys, vals)
        type(dopri5_options), intent(in) :: o
        character(len=*), intent(in) :: names
        character(len=NAME_LEN), allocatable, intent(out) :: keys(:)
        real(dp), allocatable, intent(out) :: vals(:)
        character(len=NAME_LEN), allocatable :: all(:)
        real(dp) :: x
        integer :: i, k
        allocate(all, source=split_names(names))
        allocate(keys(size(all)), vals(size(all)))
        k = 0
        do i = 1, size(all)
            select case (all(i))
            case ('h');             x = o%h
            case ('hmin');          x = o%hmin
            case ('hmax');          x = o%hmax
            case ('h0');            x = o%h0
            case ('max_steps');     x = real(o%max_steps, dp)
            case ('allow_forced');  x = merge(1.0_dp, 0.0_dp, o%allow_forced)
            case ('every_step');    x = merge(1.0_dp, 0.0_dp, o%every_step)
            case ('safety');        x = o%safety
            case ('fac1');          x = o%fac1
            case ('fac2');          x = o%fac2
            case ('beta_pi');       x = o%beta
            case ('nstiff');        x = real(o%nstiff, dp)
            case ('stop_on_stiff'); x = merge(1.0_dp, 0.0_dp, o%stop_on_stiff)
            case default;           cycle     ! rtol, atol, and controls the struct has not
            end select
            k = k + 1
            keys(k) = all(i)
            vals(k) = x
        end do
        keys = keys(:k)
        vals = vals(:k)
    end subroutine struct_controls

    !> What ss_dopri5, ss_dop853 and ss_rk4 share: check the problem, wrap the C function as an
    !! ode_system, run the integrator, report stats.
    function integrate_user(method, f, data, n, t0, y0, t_end, h, ntol, rtol, atol, opts, n_out, &
                            t_out, y_out, stats) result(status)
        integer, intent(in) :: method                 !! METHOD_RK4, METHOD_DOPRI5 or METHOD_DOP853
        type(c_funptr), intent(in) :: f               !! the C right-hand side
        type(c_ptr), intent(in) :: data               !! passed to f unchanged
        integer(c_int), intent(in) :: n               !! dimension, >= 1
        real(c_double), intent(in) :: t0, t_end       !! interval [time unit of f]
        real(c_double), intent(in) :: y0(*)           !! initial state (n)
        real(c_double), intent(in) :: h               !! RK4 step size
        integer(c_int), intent(in) :: ntol            !! 1 or n (DOPRI5)
        real(c_double), intent(in) :: rtol(*), atol(*)  !! tolerances of the adaptive methods (ntol)
        type(c_ptr), intent(in) :: opts               !! const ss_dopri5_options * (NULL: defaults)
        integer(c_int), intent(in) :: n_out           !! rows of t_out and y_out, >= 1
        real(c_double), intent(inout) :: t_out(*)     !! output times
        real(c_double), intent(inout) :: y_out(*)     !! output states (n_out * n)
        type(c_ptr), intent(in) :: stats              !! ss_stats * (NULL: not returned)
        integer(c_int) :: status
        type(c_system) :: sys
        type(dopri5_options) :: fo
        type(dop853_options) :: fo8
        type(ode_stats) :: st
        status = check_user(f, n, ntol, n_out)
        if (status == SS_OK) then
            sys = c_system(f=f, data=data, n=n)
            ! NULL keeps each method's own defaults
            call get_options(opts, fo%step_controls, fo%safety, fo%fac1, fo%fac2, fo%beta, fo%nstiff, &
                             fo%stop_on_stiff)
            call get_options(opts, fo8%step_controls, fo8%safety, fo8%fac1, fo8%fac2, fo8%beta, fo8%nstiff, &
                             fo8%stop_on_stiff)
            call run(y_out)
            status = int(st%status, c_int)
        end if
        call put_stats(st, status, stats)
    contains
        subroutine run(yo)
            real(c_double), intent(inout) :: yo(n, *)
            if (method == METHOD_RK4) then
                call rk4_integrate(sys, t0, y0(1:n), t_end, h, t_out(1:n_out), yo(:, 1:n_out), st, &
                                   every_step=fo%every_step, max_steps=fo%max_steps)
            else if (method == METHOD_DOP853) then
                call dop853_integrate(sys, t0, y0(1:n), t_end, rtol(1:ntol), atol(1:ntol), fo8, &
                                      t_out(1:n_out), yo(:, 1:n_out), st)
            else
                call dopri5_integrate(sys, t0, y0(1:n), t_end, rtol(1:ntol), atol(1:ntol), fo, &
                                      t_out(1:n_out), yo(:, 1:n_out), st)
            end if
        end subroutine run
    end function integrate_user

    !> Dimensions and function pointer of a user problem.
    pure function check_user(f, n, ntol, n_out) result(status)
        type(c_funptr), intent(in) :: f
        integer(c_int), intent(in) :: n, ntol, n_out
        integer(c_int) :: status
        status = SS_OK
        if (.not. c_associated(f) .or. n < 1 .or. (ntol /= 1 .and. ntol /= n)) then
            status = SS_BAD_DIM
        else if (n_out < 1) then
            status = SS_BAD_N_OUT
        end if
    end function check_user

    !> Call the C right-hand side.
    subroutine c_system_rhs(self, t, y, dydt)
        class(c_system), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time
        real(dp), intent(in)  :: y(:)       !! state
        real(dp), intent(out) :: dydt(:)    !! derivative
        procedure(c_rhs), pointer :: fp
        call c_f_procpointer(self%f, fp)
        call fp(t, y, dydt, self%n, self%data)
    end subroutine c_system_rhs

    !> Options from a C pointer (NULL: the defaults).
    subroutine get_options(opts, c, safety, fac1, fac2, beta, nstiff, stop_on_stiff)
        type(c_ptr), intent(in) :: opts
        type(step_controls), intent(inout) :: c             !! the shared controls
        real(dp), intent(inout) :: safety, fac1, fac2, beta  !! the method's constants
        integer, intent(inout) :: nstiff
        logical, intent(inout) :: stop_on_stiff
        type(ss_dopri5_options), pointer :: o
        if (c_associated(opts)) then
            call c_f_pointer(opts, o)
            call to_f_options(o, c, safety, fac1, fac2, beta, nstiff, stop_on_stiff)
        else
            c%hmin = HMIN_DEFAULT                           ! NULL: the defaults of every entry point
        end if
    end subroutine get_options

    !> Stats to a C pointer (NULL: nothing).
    subroutine put_stats(st, status, stats)
        type(ode_stats), intent(in) :: st
        integer(c_int), intent(in) :: status
        type(c_ptr), intent(in) :: stats
        type(ss_stats), pointer :: s
        if (.not. c_associated(stats)) return
        call c_f_pointer(stats, s)
        call to_c_stats(st, status, s)
    end subroutine put_stats

    !> A C struct from the shared controls and an explicit method's constants.
    pure subroutine from_f_options(c, safety, fac1, fac2, beta, nstiff, stop_on_stiff, o)
        type(step_controls), intent(in) :: c
        real(dp), intent(in) :: safety, fac1, fac2, beta
        integer, intent(in) :: nstiff
        logical, intent(in) :: stop_on_stiff
        type(ss_dopri5_options), intent(out) :: o
        o%hmin = c%hmin
        o%hmax = c%hmax
        o%h0 = c%h0
        o%safety = safety
        o%fac1 = fac1
        o%fac2 = fac2
        o%beta = beta
        o%max_steps = c%max_steps
        o%nstiff = int(nstiff, c_int)
        o%allow_forced = merge(1_c_int, 0_c_int, c%allow_forced)
        o%stop_on_stiff = merge(1_c_int, 0_c_int, stop_on_stiff)
        o%every_step = merge(1_c_int, 0_c_int, c%every_step)
    end subroutine from_f_options

    !> The shared controls and an explicit method's constants from a C struct (the inverse of
    !! from_f_options).
    pure subroutine to_f_options(o, c, safety, fac1, fac2, beta, nstiff, stop_on_stiff)
        type(ss_dopri5_options), intent(in) :: o
        type(step_controls), intent(inout) :: c
        real(dp), intent(out) :: safety, fac1, fac2, beta
        integer, intent(out) :: nstiff
        logical, intent(out) :: stop_on_stiff
        c%hmin = o%hmin
        c%hmax = o%hmax
        c%h0 = o%h0
        safety = o%safety
        fac1 = o%fac1
        fac2 = o%fac2
        beta = o%beta
        c%max_steps = o%max_steps
        nstiff = int(o%nstiff)
        c%allow_forced = o%allow_forced /= 0
        stop_on_stiff = o%stop_on_stiff /= 0
        c%every_step = o%every_step /= 0
    end subroutine to_f_options

    pure subroutine to_c_stats(st, status, s)
        type(ode_stats), intent(in) :: st
        integer(c_int), intent(in) :: status
        type(ss_stats), intent(out) :: s
        s%nfev = st%nfev
        s%nstep = st%nstep
        s%naccept = st%naccept
        s%nreject = st%nreject
        s%nforced = st%nforced
        s%nstiff = st%nstiff
        s%stiff = merge(1_c_int, 0_c_int, st%stiff)
        s%n_written = int(st%n_written, c_int)
        s%t_reached = st%t_reached
        s%h_last = st%h_last
        s%status = status
        s%njac = st%njac
        s%ndec = st%ndec
        s%nsol = st%nsol
    end subroutine to_c_stats

end module stickslip_capi
