!> Fortran tests of the registry (stickslip_registry) that Python does not reach: its tables
!! (names and codes unique, every law's and scene's parameter specified), its messages (the
!! parameter, its range, the accepted names) and the resolution of parameters (defaults, derived
!! defaults, ranges, unknown names). Prints one line per check; exits with status 1 if any fails.
program test_stickslip_registry
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_LAW, SS_BAD_METHOD, SS_BAD_PARAM_NAME, SS_BAD_DIM, STATUS_CODES
    use stickslip_params, only: param_values, param_rule, NAME_LEN
    use stickslip_friction, only: SS_BAD_MU_K
    use stickslip_law_recurdyn, only: SS_BAD_V_D
    use stickslip_presets, only: SS_BAD_M
    use stickslip_registry, only: PARAMS, LAW_TABLE, SCENE_TABLE, stickslip_message, code_of, split_names, &
                                  resolve_params
    implicit none

    call test_tables()
    call test_messages()
    call test_params()

    call finish('registry')

contains

    !> Names and codes are unique; every law and scene parameter is in PARAMS.
    subroutine test_tables()
        integer :: i, j
        logical :: unique, listed
        character(len=NAME_LEN), allocatable :: names(:)
        unique = .true.
        do i = 1, size(PARAMS)
            do j = i + 1, size(PARAMS)
                if (PARAMS(i)%name == PARAMS(j)%name .or. PARAMS(i)%code == PARAMS(j)%code) unique = .false.
            end do
            if (any(STATUS_CODES == PARAMS(i)%code) .or. PARAMS(i)%code > -100) unique = .false.
        end do
        call check(unique, 'registry: parameter names and codes unique, <= -100, apart from the status codes')
        listed = .true.
        do i = 1, size(LAW_TABLE)
            names = split_names(LAW_TABLE(i)%params)
            do j = 1, size(names)
                if (findloc(PARAMS%name, names(j), dim=1) == 0) listed = .false.
            end do
        end do
        do i = 1, size(SCENE_TABLE)
            names = split_names(SCENE_TABLE(i)%params)
            do j = 1, size(names)
                if (findloc(PARAMS%name, names(j), dim=1) == 0) listed = .false.
            end do
        end do
        call check(listed, 'registry: every law and scene parameter has a specification')
        call check(code_of('law', 'proposed') == 3 .and. code_of('method', 'dopri5') == 2 .and. &
                   code_of('scene', 'belt') == 2 .and. code_of('law', 'nope') == 0, 'registry: codes by name')
        names = split_names('a, b,,c  d')
        call check(size(names) == 4 .and. names(4) == 'd', 'registry: split_names on commas and blanks')
    end subroutine test_tables

    !> Messages name the parameter, its range, and the accepted names.
    subroutine test_messages()
        block
            integer :: i
            logical :: ok
            ok = index(stickslip_message(SS_BAD_LAW), 'law: unknown friction law (accepted: coulomb, ' // &
                       'recurdyn, proposed') == 1
            do i = 1, size(LAW_TABLE)
                ok = ok .and. index(stickslip_message(SS_BAD_LAW), trim(LAW_TABLE(i)%name)) > 0
            end do
            call check(ok, 'message: law list, every law of the registry')
        end block
        call check(index(stickslip_message(SS_BAD_METHOD), 'rk4, dopri5, radau5') > 0, 'message: method list')
        call check(stickslip_message(SS_BAD_MU_K) == 'mu_k: must be finite and >= 0 and <= mu_s', &
                   'message: mu_k range and relation')
        call check(stickslip_message(SS_BAD_V_D) == 'v_d: must be finite and > v_s [m/s]', 'message: v_d')
        call check(stickslip_message(SS_BAD_M) == 'm: must be finite and > 0 [kg]', 'message: m with unit')
        call check(param_rule(PARAMS(findloc(PARAMS%name, 'theta_deg', dim=1))) == &
                   'theta_deg: must be finite and in [-90, 90] [deg]', 'message: closed interval')
    end subroutine test_messages

    !> Defaults, derived defaults, range checks of unused parameters, unknown names.
    subroutine test_params()
        type(param_values) :: p
        integer :: status, iv
        status = resolve_params([character(len=NAME_LEN) :: 'v_s'], [0.02_dp], p)
        iv = findloc(p%names, 'v_d', dim=1)
        call check(status == SS_OK .and. abs(p%values(iv) - 0.03_dp) < 1e-17_dp, 'params: v_d defaults to 1.5 v_s')
        status = resolve_params([character(len=NAME_LEN) :: 'm'], [-1.0_dp], p)
        call check(status == SS_BAD_M, 'params: m = -1 rejected whatever the scene')
        status = resolve_params([character(len=NAME_LEN) :: 'mass'], [1.0_dp], p)
        call check(status == SS_BAD_PARAM_NAME, 'params: unknown name')
        status = resolve_params([character(len=NAME_LEN) :: 'mu_s', 'mu_k'], [0.3_dp], p)
        call check(status == SS_BAD_DIM, 'params: names and values of different sizes')
    end subroutine test_params

end program test_stickslip_registry
