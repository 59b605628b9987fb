!> The one registry of the library: the friction laws, scenes and integration methods by
!! name and code, every physical parameter with its default, unit, range and status
!! code, and the dispatch from codes to objects and integrators.
!!
!! Everything that lists names comes from the tables here: the messages' "accepted: ..."
!! lists (`stickslip_message`), the Python facade's tuples and defaults (it reads
!! `registry_text` at import) and the C header's constants (generated from
!! `registry_text` at build time). Adding a law: one module extending `friction_law`
!! (fortran/laws/stickslip_law_NAME.f90, type NAME_law, its own parameters' specifications as
!! public param_spec constants), plus its entry in LAW_TABLE, then `python tools/gen_kernels.py`,
!! which writes the laws' dispatch from LAW_TABLE (stickslip_laws: the law modules' `use`, the
!! codes LAW_<NAME>, LAW_SPECS and `new_law`) and meson's list of law sources.
!! Adding a method: one module with its `method_info`, options type and
!! `<method>_integrate`, plus its entry in METHOD_TABLE, a case in `new_controls` (its
!! options type) and a `type is` in `integrate`.
!!
!! Codes are positions in the tables (1-based) and never change for a given name.
module stickslip_registry
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_LAW, SS_BAD_SCENE, SS_BAD_METHOD, &
                               SS_BAD_CONTROL_NAME, SS_BAD_PARAM_NAME, SS_BAD_DIM, status_text, &
                               STATUS_NAMES, STATUS_CODES
    use stickslip_params, only: param_spec, param_values, param_ok, param_rule, NAME_LEN
    use stickslip_ode, only: ode_stats, step_controls, method_info, STATS_INTEGER_NAMES, &
                             STATS_REAL_NAMES, RTOL_MIN
    use stickslip_friction, only: friction_law
    use stickslip_laws, only: new_law, LAW_SPECS
    use stickslip_rk4, only: rk4_integrate, RK4_INFO
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate, DOPRI5_INFO
    use stickslip_dop853, only: dop853_options, dop853_integrate, DOP853_INFO
    use stickslip_radau5, only: radau5_options, radau5_integrate, RADAU5_INFO
    use stickslip_implicit_euler, only: implicit_euler_options, implicit_euler_integrate, IMPLICIT_EULER_INFO
    use stickslip_galpha, only: galpha_options, galpha_integrate, GALPHA_INFO
    use stickslip_contact, only: contact_system
    use stickslip_model_system, only: model_system
    use stickslip_one_contact, only: specialise
    use stickslip_presets, only: slope_model, belt_model, chain_model, G_SPEC, THETA_SPEC, M_SPEC, K_SPEC, &
                                 V_B_SPEC, N_BLOCKS_SPEC, K_C_SPEC, K_P_SPEC, PERTURBATION_SPEC, MAX_BLOCKS
    use stickslip_moreau, only: moreau_options, moreau_integrate, MOREAU_INFO
    use stickslip_event_driven, only: event_driven_options, event_driven_integrate, EVENT_DRIVEN_INFO, &
                                      EVENT_STICK, EVENT_SLIP, EVENT_REVERSAL
    implicit none
    private

    public :: entry_info, stickslip_message, registry_text, code_of, split_names
    public :: resolve_params, new_law, make_law, new_system, preset_model, integrate, apply_controls
    public :: new_controls

    !> A law or scene: its name, the parameters it reads (space-separated), a line of doc, and
    !! whether the integrators have kernels specialised to it.
    type :: entry_info
        character(len=16) :: name = ''
        !! name, as the Python and C layers spell it
        character(len=120) :: params = ''
        !! the parameters it reads, space-separated
        character(len=80) :: doc = ''
        !! one line of documentation
        logical :: kernel = .false.
        !! .true. (laws only): every integrator has a kernel for this law (a static mu(v), type
        !! NAME_law) on a model of one body with one contact (`one_contact_model`, the slope's
        !! and the belt's presets). tools/gen_kernels.py writes them from LAW_TABLE into
        !! fortran/integrators/stickslip_kernel_instances.inc and _dispatch.inc.
    end type entry_info

    !> The friction laws; the code of a law is its position.
    type(entry_info), parameter, public :: LAW_TABLE(*) = [ &
        entry_info('coulomb', 'mu_s mu_k v_s', 'Coulomb (eq. 1), discontinuous', kernel=.true.), &
        entry_info('recurdyn', 'mu_s mu_k v_s v_d', 'RecurDyn/ADAMS haversine steps (eqs. 2-3)', kernel=.true.), &
        entry_info('proposed', 'mu_s mu_k v_s beta a', 'Roh & Yoo (2007) (eq. 5)', kernel=.true.), &
        entry_info('stribeck', 'mu_s mu_k v_s delta c_v v_eps', 'Stribeck curve + viscous, tanh ramp at rest', kernel=.true.), &
        entry_info('karnopp', 'mu_s mu_k dv', 'Karnopp stick band |v| < dv, mu_k outside'), &
        entry_info('lugre', 'mu_s mu_k v_s sigma0 sigma1 sigma2', 'LuGre bristle (Canudas de Wit et al. 1995)'), &
        entry_info('elastoplastic', 'mu_s mu_k v_s sigma0 sigma1 sigma2 z_ba_ratio', &
                   'elasto-plastic bristle (Dupont et al. 2002)'), &
        entry_info('dahl', 'mu_k sigma0 dahl_alpha', 'Dahl (1968, 1976), with its shape exponent'), &
        entry_info('gms', 'mu_s mu_k v_s sigma0 sigma1 sigma2 n_elements gms_shape gms_c', &
                   'generalized Maxwell-slip (Al-Bender, Lampaert & Swevers 2005)'), &
        entry_info('drake_continuous', 'mu_s mu_k v_s', 'Drake continuous mode: quintic steps to mu_s at v_s, to mu_k at 3 v_s'), &
        entry_info('drake_tamsi', 'mu_k v_s', 'Drake TAMSI: mu_k s (2 - s) below s = v/v_s = 1'), &
        entry_info('capped_viscous', 'mu_k v_s', 'mu_k min(v/v_s, 1): Newton semi-implicit, MuJoCo elliptic cone'), &
        entry_info('mujoco_pyramidal', 'mu_k v_s', 'MuJoCo pyramidal cone: viscous, slope bent at mu_k/2')]
    ! The codes LAW_<NAME> (positions in LAW_TABLE) are stickslip_laws', written from this table.

    !> The scenes, each a preset (`stickslip_presets`: the function that builds its model, run
    !! by `new_system`); the code of a scene is its position.
    type(entry_info), parameter, public :: SCENE_TABLE(*) = [ &
        entry_info('slope', 'g theta_deg', 'box on a plane inclined theta_deg'), &
        entry_info('belt', 'm g k v_b', 'mass on a belt moving at v_b, spring k to a wall'), &
        entry_info('chain', 'm g k v_b n_blocks k_c perturbation k_p', &
                   'n_blocks masses on the belt, springs k_c and k_p (Burridge-Knopoff)')]
    integer, parameter, public :: SCENE_SLOPE = 1, SCENE_BELT = 2
    !! scene codes: positions in SCENE_TABLE
    integer, parameter, public :: SCENE_CHAIN = 3   !! scene code of the chain

    !> The integration methods; the code of a method is its position.
    type(method_info), parameter, public :: METHOD_TABLE(*) = [RK4_INFO, DOPRI5_INFO, RADAU5_INFO, &
        IMPLICIT_EULER_INFO, GALPHA_INFO, MOREAU_INFO, EVENT_DRIVEN_INFO, DOP853_INFO]
    integer, parameter, public :: METHOD_RK4 = 1, METHOD_DOPRI5 = 2, METHOD_RADAU5 = 3, &
                                  METHOD_IMPLICIT_EULER = 4, METHOD_GALPHA = 5
    !! method codes: positions in METHOD_TABLE
    integer, parameter, public :: METHOD_MOREAU = 6   !! method code of moreau
    integer, parameter, public :: METHOD_EVENT_DRIVEN = 7   !! method code of event_driven
    integer, parameter, public :: METHOD_DOP853 = 8   !! method code of dop853

    !> Every physical parameter of every law and scene, each once.
    !! The laws' (LAW_SPECS, written from LAW_TABLE by tools/gen_kernels.py), then the scenes'.
    type(param_spec), parameter, public :: PARAMS(*) = [LAW_SPECS, &
        M_SPEC, G_SPEC, THETA_SPEC, K_SPEC, V_B_SPEC, N_BLOCKS_SPEC, K_C_SPEC, PERTURBATION_SPEC, &
        K_P_SPEC]
    !> The default step size floor of the adaptive methods [s], the same through every entry
    !! point: `new_controls` (Fortran and Python runs, models), the C API's option defaults
    !! (ss_dopri5_options_default, and NULL options) and the Python facade's CONTROL_DEFAULTS
    !! (read from `registry_text`). Where the error test fails at this step the step is taken
    !! anyway and counted (nforced), unless allow_forced is off. (The type step_controls keeps
    !! 0, no floor, for the integrators' internal runs, such as event_driven's modes.)
    real(dp), parameter, public :: HMIN_DEFAULT = 1.0e-6_dp
    integer, private :: jp   ! the implied-do index of DEFAULT_SOURCE's constructor only
    !> Position in PARAMS of the parameter each default is derived from (v_d's is v_s's), 0 for
    !! a plain default: worked out at compile time, so that resolving costs no string search.
    integer, parameter :: DEFAULT_SOURCE(size(PARAMS)) = &
        [(findloc(PARAMS%name, PARAMS(jp)%default_of, dim=1), jp = 1, size(PARAMS))]

contains

    !> A law with its parameters given by name (the others at their defaults), checked
    !! and ready; `p` returns every parameter as resolved.
    function make_law(code, keys, vals, law, p) result(status)
        integer, intent(in) :: code                           !! law code
        character(len=*), intent(in) :: keys(:)               !! given parameter names
        real(dp), intent(in) :: vals(:)                       !! their values [SI units]
        class(friction_law), allocatable, intent(out) :: law  !! the law
        type(param_values), intent(out) :: p                  !! every parameter, resolved
        integer :: status
        status = resolve_params(keys, vals, p)
        if (status == SS_OK) status = new_law(code, law)
        if (status == SS_OK) status = law%init(p)
    end function make_law

    !> Every parameter at its default, overridden by the given (name, value) pairs; each
    !! given value is checked against its range whatever the law and scene.
    function resolve_params(keys, vals, p) result(status)
        character(len=*), intent(in) :: keys(:)   !! given parameter names
        real(dp), intent(in) :: vals(:)           !! their values [SI units]
        type(param_values), intent(out) :: p      !! every parameter, resolved
        integer :: status
        logical :: given(size(PARAMS))
        integer :: i, j
        status = SS_OK
        p%names = PARAMS%name
        p%values = PARAMS%default
        given = .false.
        if (size(keys) /= size(vals)) then
            status = SS_BAD_DIM
            return
        end if
        do i = 1, size(keys)
            j = param_index(keys(i))
            if (j == 0) then
                status = SS_BAD_PARAM_NAME
                return
            end if
            if (.not. param_ok(PARAMS(j), vals(i))) then
                status = PARAMS(j)%code
                return
            end if
            p%values(j) = vals(i)
            given(j) = .true.
        end do
        do j = 1, size(PARAMS)
            if (.not. given(j) .and. DEFAULT_SOURCE(j) > 0) &
                p%values(j) = PARAMS(j)%scale * p%values(DEFAULT_SOURCE(j))
        end do
    end function resolve_params

    !> Build a scene's model (its preset, `stickslip_presets`) with a law from named parameters
    !! (the others at their defaults), its structure found (`specialise`, as for every model).
    !! `p` returns every parameter as resolved. SS_OK or the code of the bad input.
    function new_system(scene, law, keys, vals, sys, p) result(status)
        integer, intent(in) :: scene                            !! scene code
        integer, intent(in) :: law                              !! law code
        character(len=*), intent(in) :: keys(:)                 !! given parameter names
        real(dp), intent(in) :: vals(:)                         !! their values [SI units]
        !> the scene's model, ready to integrate (its structure found: `stickslip_one_contact`)
        class(model_system), allocatable, intent(out) :: sys
        type(param_values), intent(out) :: p                    !! every parameter, resolved
        integer :: status
        type(model_system) :: ms
        status = preset_model(scene, law, keys, vals, ms, p)
        if (status == SS_OK) call specialise(ms, sys)
    end function new_system

    !> A scene's model as its preset builds it (`stickslip_presets`), prepared and not yet
    !! specialised: what `new_system` runs, and what a user's model of the same arrays is
    !! (the Python `Model.from_scene` reads it). SS_OK or the code of the bad input.
    function preset_model(scene, law, keys, vals, ms, p) result(status)
        integer, intent(in) :: scene                            !! scene code
        integer, intent(in) :: law                              !! law code
        character(len=*), intent(in) :: keys(:)                 !! given parameter names
        real(dp), intent(in) :: vals(:)                         !! their values [SI units]
        type(model_system), intent(out) :: ms                   !! the scene's model, prepared
        type(param_values), intent(out) :: p                    !! every parameter, resolved
        integer :: status
        class(friction_law), allocatable :: fl

        if (scene < 1 .or. scene > size(SCENE_TABLE)) then
            status = resolve_params(keys, vals, p)
            if (status == SS_OK) status = SS_BAD_SCENE
            return
        end if
        status = make_law(law, keys, vals, fl, p)
        if (status /= SS_OK) return
        select case (scene)
        case (SCENE_SLOPE)
            status = slope_model(fl, p, ms)
        case (SCENE_BELT)
            status = belt_model(fl, p, ms)
        case (SCENE_CHAIN)
            status = chain_model(fl, p, ms)
        end select
    end function preset_model

    !> Set the named controls on ctl; each must be one the method reads.
    function apply_controls(ctl, info, keys, vals) result(status)
        class(step_controls), intent(inout) :: ctl  !! the method's options
        type(method_info), intent(in) :: info       !! the method
        character(len=*), intent(in) :: keys(:)     !! control names
        real(dp), intent(in) :: vals(:)             !! their values (counts and flags as reals)
        integer :: status
        integer :: i, n, last
        status = SS_OK
        if (size(keys) /= size(vals)) status = SS_BAD_DIM
        last = len_trim(info%controls)   ! once, not once per name
        do i = 1, size(keys)
            if (status /= SS_OK) exit
            n = len_trim(keys(i))
            if (.not. has_word(info%controls(1:last), keys(i)(1:n)) .or. is_tolerance(keys(i)(1:n))) then
                status = SS_BAD_CONTROL_NAME
            else
                status = ctl%set(keys(i)(1:n), vals(i))
            end if
        end do
    end function apply_controls

    !> Whether `name` (without blanks) is rtol or atol, which travel as arrays, not as controls:
    !! compared at equal lengths, without padding (apply_controls runs on every call).
    pure logical function is_tolerance(name)
        character(len=*), intent(in) :: name   !! a control name, without blanks
        is_tolerance = .false.
        if (len(name) == 4) is_tolerance = name == 'rtol' .or. name == 'atol'
    end function is_tolerance

    !> Whether `word` is one of the blank-separated words of `list` (a blank word is none);
    !! no temporary strings: apply_controls runs on every call. Trailing blanks of `list` are
    !! scanned like any other blank (the caller may cut them off).
    pure logical function has_word(list, word)
        character(len=*), intent(in) :: list   !! words separated by blanks
        character(len=*), intent(in) :: word   !! the word sought, without blanks
        integer :: i, n, last
        has_word = .false.
        n = len(word)
        last = len(list)
        if (n == 0) return
        do i = 1, last - n + 1
            if (list(i:i + n - 1) /= word) cycle
            if (i > 1) then
                if (list(i - 1:i - 1) /= ' ') cycle
            end if
            if (i + n <= last) then
                if (list(i + n:i + n) /= ' ') cycle
            end if
            has_word = .true.
            return
        end do
    end function has_word

    !> Integrate sys with the method of code `method` and its named controls (rtol and atol
    !! as arrays, read by the adaptive methods only), or with the options `controls` built by
    !! `new_controls` (keys and vals are then not read; a copy is run, so that `controls` may
    !! serve runs on several threads at once). Output and status as for the methods'
    !! `<method>_integrate`.
    subroutine integrate(method, sys, t0, y0, t_end, rtol, atol, keys, vals, t_out, y_out, stats, stop_flag, events, &
                         controls)
        use stickslip_ode, only: ode_system
        integer, intent(in) :: method                !! method code
        class(ode_system), intent(inout) :: sys      !! the right-hand side
        real(dp), intent(in) :: t0                   !! initial time [s]
        real(dp), intent(in) :: y0(:)                !! initial state
        real(dp), intent(in) :: t_end                !! final time [s]
        real(dp), intent(in) :: rtol(:)              !! relative tolerances, size 1 or size(y0)
        real(dp), intent(in) :: atol(:)              !! absolute tolerances, size 1 or size(y0)
        character(len=*), intent(in) :: keys(:)      !! control names
        real(dp), intent(in) :: vals(:)              !! their values
        real(dp), intent(inout) :: t_out(:)          !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)       !! (size(y0), size(t_out)) states
        type(ode_stats), intent(out) :: stats        !! counters and status
        !> A flag another thread may set nonzero to stop the run (SS_INTERRUPTED).
        integer, pointer, intent(in), optional :: stop_flag
        !> (4, room): the events of event_driven, (t [s], kind, position [m], contact)
        real(dp), intent(inout), optional :: events(:, :)
        !> The method's options from `new_controls` (for `method`), in place of keys and vals.
        class(step_controls), intent(in), optional :: controls
        class(step_controls), allocatable :: ctl
        class(contact_system), allocatable :: cs
        real(dp), allocatable :: no_events(:, :)

        if (present(controls)) then
            allocate(ctl, source=controls)
        else
            stats%status = new_controls(method, sys, keys, vals, ctl)
            if (stats%status /= SS_OK) return
        end if
        if (present(stop_flag)) ctl%stop_flag => stop_flag
        stats%status = SS_BAD_METHOD
        select type (ctl)
        type is (step_controls)
            ! rk4_integrate looks at the flag only when it is associated
            if (method == METHOD_RK4) call rk4_integrate(sys, t0, y0, t_end, ctl%h, t_out, y_out, &
                stats, every_step=ctl%every_step, max_steps=ctl%max_steps, stop_flag=ctl%stop_flag)
        type is (dopri5_options)
            call dopri5_integrate(sys, t0, y0, t_end, rtol, atol, ctl, t_out, y_out, stats)
        type is (radau5_options)
            call radau5_integrate(sys, t0, y0, t_end, rtol, atol, ctl, t_out, y_out, stats)
        type is (implicit_euler_options)
            call implicit_euler_integrate(sys, t0, y0, t_end, ctl, t_out, y_out, stats)
        type is (galpha_options)
            call galpha_integrate(sys, t0, y0, t_end, ctl, t_out, y_out, stats)
        type is (moreau_options)
            call contact_model_of(sys, cs, stats%status)
            ! moreau and event_driven see the contact model only: the system's bounds go with them
            ctl%y_bound = sys%state_bound(t0, y0, t_end)
            if (stats%status == SS_OK) call moreau_integrate(cs, t0, y0, t_end, ctl, t_out, y_out, stats)
        type is (event_driven_options)
            call contact_model_of(sys, cs, stats%status)
            ctl%y_bound = sys%state_bound(t0, y0, t_end)
            if (stats%status /= SS_OK) return
            if (present(events)) then
                call event_driven_integrate(cs, t0, y0, t_end, rtol, atol, ctl, t_out, y_out, stats, events)
            else
                allocate(no_events(4, 0))
                call event_driven_integrate(cs, t0, y0, t_end, rtol, atol, ctl, t_out, y_out, stats, no_events)
            end if
        type is (dop853_options)
            call dop853_integrate(sys, t0, y0, t_end, rtol, atol, ctl, t_out, y_out, stats)
        end select
    end subroutine integrate

    !> The options of the method of code `method` (its own options type) with the named
    !! controls set: SS_OK, SS_BAD_METHOD, or the code of the first bad control. For the
    !! nonsmooth methods a system without a set-valued contact model (SS_NOT_SETVALUED) is
    !! named before a bad control, as `integrate` would name it.
    function new_controls(method, sys, keys, vals, ctl) result(status)
        use stickslip_ode, only: ode_system
        integer, intent(in) :: method                          !! method code
        class(ode_system), intent(in) :: sys                   !! the system it will integrate
        character(len=*), intent(in) :: keys(:)                !! control names
        real(dp), intent(in) :: vals(:)                        !! their values (counts and flags as reals)
        class(step_controls), allocatable, intent(out) :: ctl  !! the method's options
        integer :: status
        class(contact_system), allocatable :: cs
        integer :: contact_status

        status = SS_OK
        select case (method)
        case (METHOD_RK4)
            allocate(step_controls :: ctl)
        case (METHOD_DOPRI5)
            allocate(dopri5_options :: ctl)
        case (METHOD_RADAU5)
            allocate(radau5_options :: ctl)
        case (METHOD_IMPLICIT_EULER)
            allocate(implicit_euler_options :: ctl)
        case (METHOD_GALPHA)
            allocate(galpha_options :: ctl)
        case (METHOD_MOREAU)
            allocate(moreau_options :: ctl)
        case (METHOD_EVENT_DRIVEN)
            allocate(event_driven_options :: ctl)
        case (METHOD_DOP853)
            allocate(dop853_options :: ctl)
        case default
            status = SS_BAD_METHOD
            return
        end select
        if (has_word(METHOD_TABLE(method)%controls, 'hmin')) ctl%hmin = HMIN_DEFAULT
        status = apply_controls(ctl, METHOD_TABLE(method), keys, vals)
        if (status /= SS_OK .and. (method == METHOD_MOREAU .or. method == METHOD_EVENT_DRIVEN)) then
            call contact_model_of(sys, cs, contact_status)
            if (contact_status /= SS_OK) status = contact_status
        end if
    end function new_controls


    !> The contact model of a system for the nonsmooth methods: a model's `contact_model` (the
    !! presets' too); SS_NOT_SETVALUED for a law without a set-valued counterpart or another system.
    subroutine contact_model_of(sys, cs, status)
        use stickslip_ode, only: ode_system
        use stickslip_kinds, only: SS_NOT_SETVALUED
        class(ode_system), intent(in) :: sys                   !! the system
        class(contact_system), allocatable, intent(out) :: cs  !! its contact model
        integer, intent(out) :: status                         !! SS_OK or SS_NOT_SETVALUED
        select type (sys)
        class is (model_system)
            call sys%contact_model(cs, status)
        class default
            status = SS_NOT_SETVALUED
        end select
    end subroutine contact_model_of

    !> Position of a parameter in PARAMS (0: none).
    pure integer function param_index(name) result(j)
        character(len=*), intent(in) :: name
        do j = 1, size(PARAMS)
            if (PARAMS(j)%name == name) return
        end do
        j = 0
    end function param_index

    !> Code of a law, scene or method by name (kind 'law', 'scene' or 'method'); 0 if none.
    pure integer function code_of(kind, name) result(code)
        character(len=*), intent(in) :: kind   !! 'law', 'scene' or 'method'
        character(len=*), intent(in) :: name   !! its name
        code = 0
        select case (kind)
        case ('law')
            code = findloc(LAW_TABLE%name, name, dim=1)
        case ('scene')
            code = findloc(SCENE_TABLE%name, name, dim=1)
        case ('method')
            code = findloc(METHOD_TABLE%name, name, dim=1)
        end select
    end function code_of

    !> Split 'a,b c' (commas or blanks) into names.
    pure function split_names(text) result(names)
        character(len=*), intent(in) :: text          !! names separated by commas or blanks
        character(len=NAME_LEN), allocatable :: names(:)
        integer :: i, start, k, pass
        ! two passes over the text: count the names, then fill an array of that size (one
        ! allocation: the wrapper splits on every call)
        do pass = 1, 2
            k = 0
            start = 0
            do i = 1, len(text) + 1
                if (i <= len(text)) then
                    if (text(i:i) /= ' ' .and. text(i:i) /= ',') then
                        if (start == 0) start = i
                        cycle
                    end if
                end if
                if (start > 0) then
                    k = k + 1
                    if (pass == 2) names(k) = text(start:i - 1)
                    start = 0
                end if
            end do
            if (pass == 1) allocate(names(k))
        end do
    end function split_names

    !> The full message of a status code: what happened, and for bad input the parameter
    !! and its accepted range, or the accepted names.
    pure function stickslip_message(status) result(msg)
        integer, intent(in) :: status   !! a status code returned by the library
        character(len=:), allocatable :: msg
        integer :: j
        select case (status)
        case (SS_BAD_LAW)
            msg = status_text(status) // ' (accepted: ' // joined(LAW_TABLE%name) // ')'
        case (SS_BAD_SCENE)
            msg = status_text(status) // ' (accepted: ' // joined(SCENE_TABLE%name) // ')'
        case (SS_BAD_METHOD)
            msg = status_text(status) // ' (accepted: ' // joined(METHOD_TABLE%name) // ')'
        case (SS_BAD_PARAM_NAME)
            msg = status_text(status) // ' (accepted: ' // joined(PARAMS%name) // ')'
        case default
            do j = 1, size(PARAMS)
                if (PARAMS(j)%code == status) then
                    msg = param_rule(PARAMS(j))
                    return
                end if
            end do
            msg = status_text(status)
        end select
    contains
        pure function joined(names) result(s)
            character(len=*), intent(in) :: names(:)
            character(len=:), allocatable :: s
            integer :: i
            s = trim(names(1))
            do i = 2, size(names)
                s = s // ', ' // trim(names(i))
            end do
        end function joined
    end function stickslip_message

    !> The registry as text, one record per line, fields separated by '|':
    !!   law|code|name|params|n_states|n_modes|state labels (';')|doc
    !!       (n_modes > 0: a law with jumps, solved over its modes by implicit_euler and galpha
    !!       on a model; a doc may hold '|', as the last field of every record)
    !!   scene|code|name|params|doc
    !!   method|code|name|order|adaptive|implicit|controls|doc|laws (empty: every law)
    !!   param|name|code|default|unit|default_of|scale|message|doc
    !!   stats|integer names|real names
    !!   status|name|code|message
    !!   event|code|kind|doc                 (event_driven's kinds of event)
    !!   const|name|value|unit|doc           (limits and defaults the layers above share)
    function registry_text() result(text)
        character(len=:), allocatable :: text
        character(len=32) :: a, b, c
        character(len=NAME_LEN), allocatable :: snames(:)
        class(friction_law), allocatable :: fl
        type(param_values) :: p
        integer :: i, k, status
        character(len=:), allocatable :: labels
        character(len=1), parameter :: nl = new_line('a')
        type(event_driven_options) :: edo

        text = ''
        status = resolve_params([character(len=NAME_LEN) ::], [real(dp) ::], p)
        do i = 1, size(LAW_TABLE)
            status = new_law(i, fl)
            status = fl%init(p)
            labels = ''
            do k = 1, fl%n_states()
                labels = labels // merge(';', ' ', k > 1) // fl%state_label(k)
            end do
            write (a, '(i0)') i
            write (b, '(i0)') fl%n_states()
            text = text // 'law|' // trim(a) // '|' // trim(LAW_TABLE(i)%name) // '|' // &
                   trim(LAW_TABLE(i)%params) // '|' // trim(b) // '|' // trim(num(real(fl%n_modes(), dp))) // &
                   '|' // trim(adjustl(labels)) // '|' // trim(LAW_TABLE(i)%doc) // nl
        end do
        do i = 1, size(SCENE_TABLE)
            write (a, '(i0)') i
            text = text // 'scene|' // trim(a) // '|' // trim(SCENE_TABLE(i)%name) // '|' // &
                   trim(SCENE_TABLE(i)%params) // '|' // trim(SCENE_TABLE(i)%doc) // nl
        end do
        do i = 1, size(METHOD_TABLE)
            write (a, '(i0)') i
            write (b, '(i0)') METHOD_TABLE(i)%order
            text = text // 'method|' // trim(a) // '|' // trim(METHOD_TABLE(i)%name) // '|' // trim(b) // &
                   '|' // merge('1', '0', METHOD_TABLE(i)%adaptive) // '|' // &
                   merge('1', '0', METHOD_TABLE(i)%implicit) // '|' // trim(METHOD_TABLE(i)%controls) // &
                   '|' // trim(METHOD_TABLE(i)%doc) // '|' // trim(METHOD_TABLE(i)%laws) // nl
        end do
        do i = 1, size(PARAMS)
            write (a, '(i0)') PARAMS(i)%code
            write (b, '(es24.17)') PARAMS(i)%default
            write (c, '(es24.17)') PARAMS(i)%scale
            text = text // 'param|' // trim(PARAMS(i)%name) // '|' // trim(a) // '|' // trim(adjustl(b)) // &
                   '|' // trim(PARAMS(i)%unit) // '|' // trim(PARAMS(i)%default_of) // '|' // &
                   trim(adjustl(c)) // '|' // param_rule(PARAMS(i)) // '|' // trim(PARAMS(i)%doc) // nl
        end do
        text = text // 'stats|' // STATS_INTEGER_NAMES // '|' // STATS_REAL_NAMES // nl
        allocate(snames, source=split_names(STATUS_NAMES))
        do i = 1, size(STATUS_CODES)
            write (a, '(i0)') STATUS_CODES(i)
            text = text // 'status|' // trim(snames(i)) // '|' // trim(a) // '|' // &
                   stickslip_message(STATUS_CODES(i)) // nl
        end do
        do i = 1, size(PARAMS)
            write (a, '(i0)') PARAMS(i)%code
            text = text // 'status|BAD_' // upper(trim(PARAMS(i)%name)) // '|' // trim(a) // '|' // &
                   param_rule(PARAMS(i)) // nl
        end do
        text = text // 'event|' // trim(num(real(EVENT_STICK, dp))) // '|stick|slip -> stick' // nl // &
               'event|' // trim(num(real(EVENT_SLIP, dp))) // '|slip|stick -> slip' // nl // &
               'event|' // trim(num(real(EVENT_REVERSAL, dp))) // &
               '|reversal|the relative velocity reached 0 and the contact could not be held' // nl
        text = text // 'const|max_events|' // trim(num(real(edo%max_events, dp))) // &
               '|-|event_driven: most events a run may have (default of its control max_events)' // nl // &
               'const|max_blocks|' // trim(num(real(MAX_BLOCKS, dp))) // '|-|most blocks of the chain' // nl // &
               'const|rtol_min|' // trim(num(RTOL_MIN)) // &
               '|-|smallest nonzero relative tolerance the adaptive methods accept (100 eps)' // nl // &
               'const|hmin|' // trim(num(HMIN_DEFAULT)) // &
               '|s|default step size floor of the adaptive methods (forced steps there; 0: none)' // nl
    contains
        !> A number as text: an integer exactly, else 17 significant digits.
        pure function num(x) result(t)
            real(dp), intent(in) :: x
            character(len=32) :: t
            if (x == aint(x) .and. abs(x) < 1.0e15_dp) then
                write (t, '(i0)') int(x, 8)
            else
                write (t, '(es24.17)') x
                t = adjustl(t)
            end if
        end function num

        pure function upper(s) result(u)
            character(len=*), intent(in) :: s
            character(len=len(s)) :: u
            integer :: k
            u = s
            do k = 1, len(s)
                if (s(k:k) >= 'a' .and. s(k:k) <= 'z') u(k:k) = achar(iachar(s(k:k)) - 32)
            end do
        end function upper
    end function registry_text

end module stickslip_registry
