!> Named physical parameters: the specification of one parameter (name, default, unit,
!! accepted range, the status code that names it) and a set of named values.
!!
!! Laws and scenes declare the parameters they read as `param_spec` constants in their own
!! modules; `stickslip_registry` collects them into one table, from which the defaults,
!! the range checks, the error messages, the Python facade and the C header all come.
!! A law or scene reads its values by name from a `param_values` set that the registry
!! has resolved (every given value range-checked, every missing one defaulted).
module stickslip_params
    use stickslip_kinds, only: dp, SS_OK
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: param_spec, param_values, param_ok, param_rule, param_get, param_read

    integer, parameter, public :: NAME_LEN = 16   !! longest parameter name

    !> One physical parameter.
    type :: param_spec
        character(len=NAME_LEN) :: name = ''   !! name, as Python and C users write it
        real(dp) :: default = 0.0_dp           !! default value [unit]
        character(len=12) :: unit = '-'        !! unit ('-' when dimensionless)
        real(dp) :: lo = -huge(1.0_dp)         !! lower bound of the accepted range [unit]
        real(dp) :: hi = huge(1.0_dp)          !! upper bound of the accepted range [unit]
        logical :: lo_open = .false.           !! the lower bound itself is excluded
        logical :: hi_open = .false.           !! the upper bound itself is excluded
        !> When not blank: the default is `scale` times this other parameter (v_d = 1.5 v_s).
        character(len=NAME_LEN) :: default_of = ''
        real(dp) :: scale = 1.0_dp             !! factor of `default_of`
        !> A constraint on other parameters that the law checks itself (blank: none),
        !! shown in the message, e.g. '<= mu_s'.
        character(len=24) :: relation = ''
        integer :: code = 0                    !! status code naming this parameter (<= -100)
        character(len=64) :: doc = ''          !! what it is
    end type param_spec

    !> A set of named values (all of one law and scene once resolved by the registry).
    type :: param_values
        character(len=NAME_LEN), allocatable :: names(:)   !! parameter names
        real(dp), allocatable :: values(:)                 !! their values [SI units]
    end type param_values

contains

    !> .true. when x is finite and inside the spec's simple range.
    elemental logical function param_ok(spec, x)
        type(param_spec), intent(in) :: spec   !! the parameter
        real(dp), intent(in) :: x              !! a value [unit]
        param_ok = ieee_is_finite(x)
        if (.not. param_ok) return
        if (spec%lo_open) then
            param_ok = x > spec%lo
        else
            param_ok = x >= spec%lo
        end if
        if (spec%hi_open) then
            param_ok = param_ok .and. x < spec%hi
        else
            param_ok = param_ok .and. x <= spec%hi
        end if
    end function param_ok

    !> 'name: must be finite and > 0 [m/s]': the message of the spec's status code.
    pure function param_rule(spec) result(msg)
        type(param_spec), intent(in) :: spec   !! the parameter
        character(len=:), allocatable :: msg
        character(len=:), allocatable :: lo, hi
        lo = fmt(spec%lo)
        hi = fmt(spec%hi)
        msg = trim(spec%name) // ': must be finite'
        if (spec%lo > -huge(1.0_dp) .and. spec%hi < huge(1.0_dp)) then
            msg = msg // ' and in ' // merge('(', '[', spec%lo_open) // lo // ', ' // hi // &
                  merge(')', ']', spec%hi_open)
        else if (spec%lo > -huge(1.0_dp)) then
            msg = msg // ' and ' // trim(merge('> ', '>=', spec%lo_open)) // ' ' // lo
        else if (spec%hi < huge(1.0_dp)) then
            msg = msg // ' and ' // trim(merge('< ', '<=', spec%hi_open)) // ' ' // hi
        end if
        if (len_trim(spec%relation) > 0) msg = msg // ' and ' // trim(spec%relation)
        if (trim(spec%unit) /= '-') msg = msg // ' [' // trim(spec%unit) // ']'
    contains
        !> x as written for a reader: an integer as one, else the fewest significant digits
        !! that read back as x, in plain decimals from 1e-4 to 1e7, else as 1.5e-14.
        pure function fmt(x) result(s)
            real(dp), intent(in) :: x
            character(len=:), allocatable :: s
            character(len=40) :: buf
            character(len=24) :: form
            real(dp) :: back
            integer :: digits, ios, e, at
            if (x == aint(x) .and. abs(x) < 1.0e9_dp) then
                write (buf, '(i0)') int(x, 8)
                s = trim(adjustl(buf))
                return
            end if
            do digits = 1, 17
                write (form, '(a,i0,a)') '(es40.', digits - 1, 'e4)'
                write (buf, form) x
                read (buf, *, iostat=ios) back
                if (ios == 0 .and. .not. (back < x .or. back > x)) exit
            end do
            at = index(buf, 'E')
            read (buf(at + 1:), *) e
            if (e >= -4 .and. e < 7) then
                write (form, '(a,i0,a)') '(f40.', max(digits - 1 - e, 1), ')'
                write (buf, form) x
                s = trim(adjustl(buf))
                if (s(1:1) == '.') s = '0' // s
                if (s(1:2) == '-.') s = '-0' // s(2:)
            else
                s = trim(adjustl(buf(:at - 1)))
                if (s(len(s):) == '.') s = s(:len(s) - 1)
                write (buf, '(i0)') e
                s = s // 'e' // trim(buf)
            end if
        end function fmt
    end function param_rule

    !> The value named like `spec` in p, or the spec's default when p has none.
    pure real(dp) function param_get(p, spec) result(x)
        type(param_values), intent(in) :: p    !! resolved values
        type(param_spec), intent(in) :: spec   !! the parameter to read
        integer :: i
        x = spec%default
        if (.not. allocated(p%names)) return
        do i = 1, size(p%names)
            if (p%names(i) == spec%name) then
                x = p%values(i)
                return
            end if
        end do
    end function param_get

    !> x = the value of `spec` in p (or its default); when status is still SS_OK and x is
    !! outside the spec's range, status becomes the spec's code.
    pure subroutine param_read(p, spec, x, status)
        type(param_values), intent(in) :: p    !! resolved values
        type(param_spec), intent(in) :: spec   !! the parameter to read
        real(dp), intent(out) :: x             !! its value [spec%unit]
        integer, intent(inout) :: status       !! the first failure is kept
        x = param_get(p, spec)
        if (status == SS_OK .and. .not. param_ok(spec, x)) status = spec%code
    end subroutine param_read

end module stickslip_params
