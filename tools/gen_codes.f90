!> Writes stickslip_codes.h, the C constants of the registry, to standard output; meson
!! runs it at build time so that the C header's codes come from the one registry.
!! Laws, scenes and methods: SS_LAW_<NAME>, SS_SCENE_<NAME>, SS_METHOD_<NAME> (their codes);
!! status codes: SS_<NAME>, and SS_BAD_<PARAMETER> for every physical parameter; for models,
!! SS_GROUND, SS_NO_SIGNAL, the element kinds SS_ELEM_*, the drive kinds SS_DRIVE_* and the
!! event kinds SS_EVENT_*.
program gen_codes
    use stickslip_kinds, only: STATUS_NAMES, STATUS_CODES
    use stickslip_registry, only: LAW_TABLE, SCENE_TABLE, METHOD_TABLE, PARAMS, split_names, &
                                  stickslip_message
    use stickslip_params, only: NAME_LEN
    use stickslip_user_model, only: ELEM_BODY, ELEM_SPRING, ELEM_DAMPER, ELEM_FORCE, ELEM_CONTACT, ELEM_SIGNAL, &
                                    ELEM_DRIVE, DRIVE_POSITION, DRIVE_VELOCITY
    use stickslip_event_driven, only: EVENT_STICK, EVENT_SLIP, EVENT_REVERSAL
    implicit none
    character(len=NAME_LEN), allocatable :: names(:)
    integer :: i

    print '(a)', '/* stickslip_codes.h: generated at build time from the registry (stickslip_registry.f90)'
    print '(a)', ' * by tools/gen_codes.f90. Do not edit; included by stickslip.h. */'
    print '(a)', '#ifndef STICKSLIP_CODES_H'
    print '(a)', '#define STICKSLIP_CODES_H'
    print '(a)', ''
    print '(a)', '/* Friction laws, scenes and integration methods (ss_code() finds them by name too). */'
    do i = 1, size(LAW_TABLE)
        call define('SS_LAW_' // upper(LAW_TABLE(i)%name), i, LAW_TABLE(i)%doc)
    end do
    do i = 1, size(SCENE_TABLE)
        call define('SS_SCENE_' // upper(SCENE_TABLE(i)%name), i, SCENE_TABLE(i)%doc)
    end do
    do i = 1, size(METHOD_TABLE)
        call define('SS_METHOD_' // upper(METHOD_TABLE(i)%name), i, METHOD_TABLE(i)%doc)
    end do
    print '(a)', ''
    print '(a)', '/* Status codes (ss_message() gives the text): 0 success, -1 .. -99 run-time outcomes,'
    print '(a)', ' * -100 and below bad input, naming the parameter. */'
    ! gfortran -Wuninitialized on names' descriptor: a false positive, the assignment allocates it
    names = split_names(STATUS_NAMES)
    do i = 1, size(STATUS_CODES)
        call define('SS_' // trim(names(i)), STATUS_CODES(i), stickslip_message(STATUS_CODES(i)))
    end do
    do i = 1, size(PARAMS)
        call define('SS_BAD_' // upper(PARAMS(i)%name), PARAMS(i)%code, stickslip_message(PARAMS(i)%code))
    end do
    print '(a)', ''
    print '(a)', '/* Models (ss_model_*): the ground and no signal as indices, the kinds of element that'
    print '(a)', ' * ss_model_error() names, and the kinds of event of ss_model_simulate(). */'
    call define('SS_GROUND', 0, 'the ground, as a body index')
    call define('SS_NO_SIGNAL', 0, 'no signal (a contact without a surface velocity)')
    call define('SS_ELEM_BODY', ELEM_BODY, 'a body')
    call define('SS_ELEM_SPRING', ELEM_SPRING, 'a spring')
    call define('SS_ELEM_DAMPER', ELEM_DAMPER, 'a damper')
    call define('SS_ELEM_FORCE', ELEM_FORCE, 'a force')
    call define('SS_ELEM_CONTACT', ELEM_CONTACT, 'a friction contact')
    call define('SS_ELEM_SIGNAL', ELEM_SIGNAL, 'a signal')
    call define('SS_ELEM_DRIVE', ELEM_DRIVE, 'a drive')
    call define('SS_DRIVE_POSITION', DRIVE_POSITION, 'a drive prescribes the position [m]')
    call define('SS_DRIVE_VELOCITY', DRIVE_VELOCITY, 'a drive prescribes the velocity [m/s]')
    call define('SS_EVENT_STICK', EVENT_STICK, 'slip -> stick')
    call define('SS_EVENT_SLIP', EVENT_SLIP, 'stick -> slip')
    call define('SS_EVENT_REVERSAL', EVENT_REVERSAL, 'the slip reached 0 and the contact could not hold')
    print '(a)', ''
    print '(a)', '#endif /* STICKSLIP_CODES_H */'

contains

    subroutine define(name, value, doc)
        character(len=*), intent(in) :: name, doc
        integer, intent(in) :: value
        character(len=16) :: v
        write (v, '(i0)') value
        if (value < 0) v = '(' // trim(v) // ')'
        print '(a)', '#define ' // name // repeat(' ', max(1, 32 - len(name))) // trim(v) // &
                     '  /* ' // trim(doc) // ' */'
    end subroutine define

    pure function upper(s) result(u)
        character(len=*), intent(in) :: s
        character(len=:), allocatable :: u
        integer :: k
        u = trim(s)
        do k = 1, len(u)
            if (u(k:k) >= 'a' .and. u(k:k) <= 'z') u(k:k) = achar(iachar(u(k:k)) - 32)
        end do
    end function upper

end program gen_codes
