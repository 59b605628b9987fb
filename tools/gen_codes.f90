!> Writes stickslip_codes.h, the C constants of the registry, to standard output; meson
!! runs it at build time so that the C header's codes come from the one registry.
!! Laws, scenes and methods: SS_LAW_<NAME>, SS_SCENE_<NAME>, SS_METHOD_<NAME> (their codes);
!! status codes: SS_<NAME>, and SS_BAD_<PARAMETER> for every physical parameter.
program gen_codes
    use stickslip_kinds, only: STATUS_NAMES, STATUS_CODES
    use stickslip_registry, only: LAW_TABLE, SCENE_TABLE, METHOD_TABLE, PARAMS, split_names, &
                                  stickslip_message
    use stickslip_params, only: NAME_LEN
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
