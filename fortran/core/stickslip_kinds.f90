!> Kinds, status codes and their messages for the stickslip library.
!!
!! Every routine of the library that can fail returns an integer status:
!! `SS_OK` (zero) on success, a negative code on failure. Codes from -100
!! downwards name one bad input each (the physical parameters' codes are declared
!! beside their specifications, in the law and scene modules); codes -1 .. -99 are
!! run-time outcomes of an integration (in the spirit of Hairer's IDID).
module stickslip_kinds
    use, intrinsic :: iso_fortran_env, only: dp => real64
    implicit none
    private

    public :: dp, status_text

    ! -- success ----------------------------------------------------------------
    integer, parameter, public :: SS_OK = 0                 !! finished normally

    ! -- run-time outcomes of an integration ------------------------------------
    integer, parameter, public :: SS_STEP_BUDGET = -2       !! step budget (max_steps) exhausted
    integer, parameter, public :: SS_STEP_TOO_SMALL = -3    !! error test failed at h_min and forced steps are off
    integer, parameter, public :: SS_STIFF = -4             !! problem judged stiff and stop_on_stiff is set
    integer, parameter, public :: SS_NONFINITE = -5         !! the solution became NaN or infinite
    integer, parameter, public :: SS_OUTPUT_FULL = -6       !! every-step output buffer is full
    integer, parameter, public :: SS_NEWTON_FAILED = -7     !! Newton iteration did not converge
    integer, parameter, public :: SS_SINGULAR = -8          !! the Newton matrix is singular
    integer, parameter, public :: SS_JAC_NONFINITE = -9     !! the Jacobian has a NaN or infinite entry
    integer, parameter, public :: SS_INTERRUPTED = -10      !! the caller set the stop flag
    !> the solution left the system's bound on |y| (`ode_system%state_bound`): it diverged
    integer, parameter, public :: SS_DIVERGED = -11
    integer, parameter, public :: SS_CONTACT_FAILED = -21 !! moreau's contact solver missed contact_tol
    integer, parameter, public :: SS_EVENT_ZENO = -22    !! event_driven: events accumulate (Zeno, chatter)
    integer, parameter, public :: SS_EVENT_BUDGET = -23  !! event_driven: more than max_events events
    !> periodic orbit (stickslip_orbit): Newton's method did not reach its tolerance (the residual returned)
    integer, parameter, public :: SS_NO_ORBIT = -31
    !> periodic orbit: the period collapsed below 1e-3 of its guess (an equilibrium, not an orbit)
    integer, parameter, public :: SS_ORBIT_COLLAPSED = -32

    ! -- bad input, one code per parameter ---------------------------------------
    integer, parameter, public :: SS_BAD_LAW = -100         !! unknown friction law code
    integer, parameter, public :: SS_BAD_SCENE = -110       !! unknown scene code
    integer, parameter, public :: SS_BAD_METHOD = -120      !! unknown integration method code
    integer, parameter, public :: SS_BAD_H = -121           !! h not finite or <= 0
    integer, parameter, public :: SS_BAD_T_END = -122       !! t_end not finite or <= t0
    integer, parameter, public :: SS_BAD_RTOL = -123        !! rtol not finite, outside [0, 1), or in (0, 100 eps)
    integer, parameter, public :: SS_BAD_ATOL = -124        !! atol not finite or <= 0
    integer, parameter, public :: SS_BAD_HMIN = -125        !! h_min not finite, < 0 or > t_end - t0
    integer, parameter, public :: SS_BAD_HMAX = -126        !! h_max not finite, <= 0 or < h_min
    integer, parameter, public :: SS_BAD_N_OUT = -127       !! output grid empty, unsorted or outside [t0, t_end]
    integer, parameter, public :: SS_BAD_MAX_STEPS = -128   !! max_steps < 1
    integer, parameter, public :: SS_BAD_Y0 = -129          !! initial state not finite
    integer, parameter, public :: SS_BAD_H0 = -130          !! initial step h0 not finite or < 0
    integer, parameter, public :: SS_BAD_CONTROL = -131     !! safety, fac1, fac2, beta_pi or nstiff out of range
    integer, parameter, public :: SS_BAD_DIM = -132         !! array sizes do not agree
    integer, parameter, public :: SS_BAD_RHO_INF = -133     !! rho_inf not finite or outside [0, 1]
    integer, parameter, public :: SS_BAD_NIT = -134         !! Newton iteration limit (nit, newton_max_iter) < 1
    integer, parameter, public :: SS_BAD_NEWTON_TOL = -135  !! newton_rtol, newton_atol or fnewt out of range
    integer, parameter, public :: SS_BAD_RADAU5_CONTROL = -136 !! safety, thet, quot1/quot2 or facl/facr of RADAU5 out of range
    integer, parameter, public :: SS_BAD_RTOL_POSITIVE = -137  !! rtol not in [100 eps, 1) where 0 is not allowed (RADAU5)
    integer, parameter, public :: SS_BAD_CONTROL_NAME = -138  !! a control the method does not read
    integer, parameter, public :: SS_BAD_PARAM_NAME = -139  !! a parameter no law or scene has
    integer, parameter, public :: SS_BAD_FORCED_GROWTH = -148 !! fac_forced not finite or <= 1, or calm_steps < 0
    integer, parameter, public :: SS_BAD_THETA_MJ = -160    !! moreau's theta outside [1/2, 1]
    integer, parameter, public :: SS_BAD_CONTACT_CTL = -161 !! contact_tol or contact_max_iter out of range
    integer, parameter, public :: SS_BAD_EVENT_CTL = -162   !! max_events or zeno_gap out of range
    integer, parameter, public :: SS_NOT_SETVALUED = -163   !! the law (or system) has no set-valued contact
    !> implicit_euler/galpha and a law with jumps (modes) on a system of several contacts
    !! without a contact model
    integer, parameter, public :: SS_JUMP_MANY_CONTACTS = -164
    ! prescribed motion (stickslip_prescribed)
    integer, parameter, public :: SS_BAD_TIMES = -175       !! sample times not finite or not strictly increasing
    integer, parameter, public :: SS_BAD_MOTION = -176      !! displacement or velocity samples not finite
    integer, parameter, public :: SS_BAD_BACKLASH = -177    !! backlash not finite or < 0
    integer, parameter, public :: SS_BAD_ASYMMETRY = -178   !! asymmetry not finite or <= 0
    integer, parameter, public :: SS_BAD_NORMAL_FORCE = -179 !! normal force not finite or < 0
    ! a user's model (stickslip_model)
    integer, parameter, public :: SS_BAD_MODEL_EMPTY = -185 !! a model without bodies
    integer, parameter, public :: SS_BAD_BODY = -186        !! a body index outside the model, or an element joining a body to itself
    integer, parameter, public :: SS_BAD_MASS = -187        !! a mass not finite or <= 0
    integer, parameter, public :: SS_BAD_SPRING = -188      !! a stiffness not finite or < 0, or a rest length not finite
    integer, parameter, public :: SS_BAD_DAMPER = -189      !! a damping coefficient not finite or < 0
    integer, parameter, public :: SS_BAD_SIGNAL = -190      !! a signal malformed (see stickslip_signal)
    integer, parameter, public :: SS_BAD_HANDLE = -191      !! a C model handle that is NULL or not one of ss_model_new
    ! periodic orbits (stickslip_orbit)
    integer, parameter, public :: SS_BAD_PERIOD = -201      !! a period not finite or <= 0
    integer, parameter, public :: SS_BAD_GUESS = -202       !! a guess of the wrong size (not the system's state) or not finite
    integer, parameter, public :: SS_BAD_ORBIT_OPTION = -203 !! tol, max_iter, fd_newton or fd_monodromy out of range

    !> Names of the status codes above, for the generated C header (`SS_` + name).
    character(len=*), parameter, public :: STATUS_NAMES = 'OK STEP_BUDGET STEP_TOO_SMALL STIFF ' // &
        'NONFINITE OUTPUT_FULL BAD_LAW BAD_SCENE BAD_METHOD BAD_H BAD_T_END BAD_RTOL BAD_ATOL ' // &
        'BAD_HMIN BAD_HMAX BAD_N_OUT BAD_MAX_STEPS BAD_Y0 BAD_H0 BAD_CONTROL BAD_DIM ' // &
        'BAD_CONTROL_NAME BAD_PARAM_NAME NEWTON_FAILED SINGULAR JAC_NONFINITE BAD_RHO_INF ' // &
        'BAD_NIT BAD_NEWTON_TOL BAD_RADAU5_CONTROL BAD_RTOL_POSITIVE INTERRUPTED BAD_FORCED_GROWTH' // &
        ' CONTACT_FAILED EVENT_ZENO EVENT_BUDGET BAD_THETA_MJ BAD_CONTACT_CTL BAD_EVENT_CTL' // &
        ' NOT_SETVALUED JUMP_MANY_CONTACTS BAD_TIMES BAD_MOTION BAD_BACKLASH BAD_ASYMMETRY BAD_NORMAL_FORCE' // &
        ' DIVERGED BAD_MODEL_EMPTY BAD_BODY BAD_MASS BAD_SPRING BAD_DAMPER BAD_SIGNAL BAD_HANDLE' // &
        ' NO_ORBIT ORBIT_COLLAPSED BAD_PERIOD BAD_GUESS BAD_ORBIT_OPTION'
    !> Their values, in the same order.
    integer, parameter, public :: STATUS_CODES(59) = [SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, &
        SS_STIFF, SS_NONFINITE, SS_OUTPUT_FULL, SS_BAD_LAW, SS_BAD_SCENE, SS_BAD_METHOD, SS_BAD_H, &
        SS_BAD_T_END, SS_BAD_RTOL, SS_BAD_ATOL, SS_BAD_HMIN, SS_BAD_HMAX, SS_BAD_N_OUT, &
        SS_BAD_MAX_STEPS, SS_BAD_Y0, SS_BAD_H0, SS_BAD_CONTROL, SS_BAD_DIM, SS_BAD_CONTROL_NAME, &
        SS_BAD_PARAM_NAME, SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE, SS_BAD_RHO_INF, SS_BAD_NIT, &
        SS_BAD_NEWTON_TOL, SS_BAD_RADAU5_CONTROL, SS_BAD_RTOL_POSITIVE, SS_INTERRUPTED, &
        SS_BAD_FORCED_GROWTH, SS_CONTACT_FAILED, SS_EVENT_ZENO, SS_EVENT_BUDGET, SS_BAD_THETA_MJ, &
        SS_BAD_CONTACT_CTL, SS_BAD_EVENT_CTL, SS_NOT_SETVALUED, SS_JUMP_MANY_CONTACTS, SS_BAD_TIMES, &
        SS_BAD_MOTION, &
        SS_BAD_BACKLASH, SS_BAD_ASYMMETRY, SS_BAD_NORMAL_FORCE, SS_DIVERGED, SS_BAD_MODEL_EMPTY, SS_BAD_BODY, &
        SS_BAD_MASS, SS_BAD_SPRING, SS_BAD_DAMPER, SS_BAD_SIGNAL, SS_BAD_HANDLE, SS_NO_ORBIT, &
        SS_ORBIT_COLLAPSED, SS_BAD_PERIOD, SS_BAD_GUESS, SS_BAD_ORBIT_OPTION]

contains

    !> The text of a run-time or generic input status code. The full message of any code,
    !! with the parameters' ranges and the accepted names, is `stickslip_registry`'s
    !! `stickslip_message`.
    pure function status_text(status) result(msg)
        integer, intent(in) :: status   !! a status code returned by the library
        character(len=:), allocatable :: msg
        select case (status)
        case (SS_OK);             msg = 'success'
        case (SS_STEP_BUDGET);    msg = 'step budget exhausted: max_steps attempted steps did not reach t_end'
        case (SS_STEP_TOO_SMALL); msg = 'step size too small: the error test failed at h_min (or h underflowed)' // &
                                        ' and forced steps are disabled'
        case (SS_STIFF);          msg = 'problem judged stiff (DOPRI5 stiffness test) and stop_on_stiff is set'
        case (SS_NONFINITE);      msg = 'the solution became NaN or infinite'
        case (SS_DIVERGED);       msg = 'the solution diverged: the state left the bounds that no motion of' // &
                                        ' the system reaches (a scene''s energy bounds with a margin of 1000;' // &
                                        ' another system''s state_bound, by default 1e30 max(1, |y0|))'
        case (SS_OUTPUT_FULL);    msg = 'the every-step output buffer is full'
        case (SS_NEWTON_FAILED);  msg = 'Newton iteration did not converge (fixed-step method: within' // &
                                        ' newton_max_iter iterations; RADAU5: at h_min)'
        case (SS_SINGULAR);       msg = 'the Newton matrix is singular (RADAU5: 5 times, step halved in between)'
        case (SS_INTERRUPTED);    msg = 'interrupted: the caller set the stop flag (Ctrl-C)'
        case (SS_JAC_NONFINITE);  msg = 'the Jacobian df/dy has a NaN or infinite entry'
        case (SS_BAD_LAW);        msg = 'law: unknown friction law'
        case (SS_BAD_SCENE);      msg = 'scene: unknown scene'
        case (SS_BAD_METHOD);     msg = 'method: unknown integration method'
        case (SS_BAD_H);          msg = 'h: must be finite and > 0 [s]'
        case (SS_BAD_T_END);      msg = 't_end: must be finite and > t0 [s]'
        case (SS_BAD_RTOL);       msg = 'rtol: must be finite and 0 or in [100 eps = 2.2e-14, 1)'
        case (SS_BAD_ATOL);       msg = 'atol: must be finite and > 0 (0 would make the error scale 0/0 at a state component 0)'
        case (SS_BAD_HMIN);       msg = 'hmin: must be finite, >= 0 and <= t_end - t0 [s]'
        case (SS_BAD_HMAX);       msg = 'hmax: must be finite, > 0 and >= hmin [s]'
        case (SS_BAD_N_OUT);      msg = 'n_out: output times must be finite, non-decreasing and in [t0, t_end]' // &
                                        ' (n_out >= 1)'
        case (SS_BAD_MAX_STEPS);  msg = 'max_steps: must be >= 1'
        case (SS_BAD_Y0);         msg = 'x0, v0: the initial state must be finite'
        case (SS_BAD_H0);         msg = 'h0: must be finite and >= 0 (0 = automatic initial step) [s]'
        case (SS_BAD_CONTROL);    msg = 'step control: need 0 < safety < 1, 0 < fac1 <= 1 <= fac2,' // &
                                        ' 0 <= beta_pi <= 0.2, nstiff >= 1'
        case (SS_BAD_DIM);        msg = 'array sizes do not agree'
        case (SS_BAD_FORCED_GROWTH); msg = 'fac_forced: must be finite and > 1; calm_steps: an integer >= 0'
        case (SS_BAD_CONTROL_NAME); msg = 'control: not a control of the chosen method' // &
                                          ' (each method lists its controls in the registry)'
        case (SS_BAD_PARAM_NAME); msg = 'parameter: not a parameter of any friction law or scene'
        case (SS_BAD_RHO_INF);    msg = 'rho_inf: must be finite and in [0, 1]'
        case (SS_BAD_NIT);        msg = 'nit, newton_max_iter: the Newton iteration limit must be >= 1'
        case (SS_BAD_NEWTON_TOL); msg = 'newton_rtol, newton_atol: must be finite, newton_rtol >= 0, newton_atol > 0;' // &
                                        ' fnewt: 0 (automatic) or > eps / rtol'
        case (SS_BAD_RADAU5_CONTROL); msg = 'RADAU5 control: need 0.001 < safety < 1, 0 <= thet < 1,' // &
                                        ' 0 < quot1 <= 1 <= quot2, 0 < facl <= 1 <= facr'
        case (SS_BAD_RTOL_POSITIVE); msg = 'rtol: RADAU5 needs rtol finite and in [100 eps = 2.2e-14, 1)' // &
                                        ' (its tolerance transformation divides by rtol; 0 is not allowed)'
        case (SS_CONTACT_FAILED); msg = 'contact solver: a step''s (moreau) or an event''s (event_driven)' // &
                                        ' friction problem has no solution within contact_tol and' // &
                                        ' contact_max_iter (see stats contact_worst and t_reached)'
        case (SS_EVENT_ZENO); msg = 'events accumulate (Zeno or chatter, event_driven): 10 instants' // &
                                        ' with events in a row closer than zeno_gap, or more than 4 n_c + 8' // &
                                        ' events at one instant'
        case (SS_EVENT_BUDGET); msg = 'event budget exhausted (event_driven): more than max_events' // &
                                        ' stick/slip transitions; raise max_events to go on'
        case (SS_BAD_THETA_MJ);   msg = 'theta: must be in [0.5, 1] (the Moreau-Jean theta-method)'
        case (SS_BAD_CONTACT_CTL); msg = 'contact_tol: must be finite and > 0 [m/s]; contact_max_iter:' // &
                                        ' an integer >= 1'
        case (SS_BAD_EVENT_CTL); msg = 'max_events: an integer >= 1; zeno_gap: finite and >= 0 [s]'
        case (SS_NOT_SETVALUED);  msg = 'law: the methods moreau and event_driven take only the set-valued' // &
                                        ' laws coulomb, stribeck, karnopp (and a system with the contact interface)'
        case (SS_JUMP_MANY_CONTACTS); msg = 'law: implicit_euler and galpha solve a law with jumps' // &
                                        ' (coulomb, karnopp) on several contacts only through the' // &
                                        ' system''s contact model, which this system does not give'
        case (SS_BAD_TIMES);      msg = 't: must be finite and strictly increasing, one time per sample [s]'
        case (SS_BAD_MOTION);     msg = 'x, v: must be finite, one value per sample [m, m/s]'
        case (SS_BAD_BACKLASH);   msg = 'backlash: must be finite and >= 0 [m]'
        case (SS_BAD_ASYMMETRY);  msg = 'asymmetry: must be finite and > 0 (negative-direction level / positive one) [-]'
        case (SS_BAD_NORMAL_FORCE); msg = 'normal_force: must be finite and >= 0, a scalar or one value per sample [N]'
        case (SS_BAD_MODEL_EMPTY); msg = 'model: has no bodies (add_body first)'
        case (SS_BAD_BODY);       msg = 'body: an index outside 0 .. n_bodies (0 the ground), or an element' // &
                                        ' joining a body to itself'
        case (SS_BAD_MASS);       msg = 'mass: must be finite and > 0 [kg, or kg m^2 for an inertia]'
        case (SS_BAD_SPRING);     msg = 'k: must be finite and >= 0 [N/m]; rest_length: finite [m]'
        case (SS_BAD_DAMPER);     msg = 'c: must be finite and >= 0 [N s/m]'
        case (SS_BAD_SIGNAL);     msg = 'signal: malformed (a ramp''s duration must be > 0, a table''s times' // &
                                        ' finite and strictly increasing, every number finite)'
        case (SS_BAD_HANDLE);     msg = 'model: not a live handle of ss_model_new (NULL, freed, or another pointer)'
        case (SS_NO_ORBIT); msg = 'periodic orbit: Newton''s method did not reach its tolerance' // &
                                        ' within max_iter iterations (or a step halved 12 times did not lower' // &
                                        ' the residual, or the Jacobian was singular); the residual is returned:' // &
                                        ' give a better guess or looser tolerances'
        case (SS_ORBIT_COLLAPSED); msg = 'periodic orbit: the period collapsed below 1e-3 of its guess' // &
                                        ' (an equilibrium, not an orbit); give a guess on the orbit'
        case (SS_BAD_PERIOD);     msg = 'period: must be finite and > 0 [s]'
        case (SS_BAD_GUESS);      msg = 'guess: must be finite, one value per state component of the system' // &
                                        ' (x then v of every body, then the laws'' states)'
        case (SS_BAD_ORBIT_OPTION); msg = 'orbit options: tol must be finite and > 0, max_iter >= 0,' // &
                                        ' fd_newton and fd_monodromy in (0, 0.1], t0 finite'
        case default;             msg = 'unknown status code'
        end select
    end function status_text

end module stickslip_kinds
