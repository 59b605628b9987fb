!> What the Fortran test programs share: one line per check ("ok" or "FAIL" and what was
!! checked), and the verdict at the end (exit status 1 if any check failed).
module test_support
    implicit none
    private
    public :: check, finish

    integer :: nfail = 0   !! checks failed so far in this program

contains

    !> Print the outcome of one check.
    subroutine check(ok, what)
        logical, intent(in) :: ok              !! the check passed
        character(*), intent(in) :: what       !! what was checked
        if (ok) then
            print '(a, a)', 'ok    ', what
        else
            print '(a, a)', 'FAIL  ', what
            nfail = nfail + 1
        end if
    end subroutine check

    !> 'all NAME checks passed', or the number of failures and exit status 1.
    subroutine finish(name)
        character(*), intent(in) :: name       !! the suite, as in 'all integrator checks passed'
        if (nfail > 0) then
            print '(a, i0, a)', 'FAILED: ', nfail, ' check(s)'
            error stop 1
        end if
        print '(a)', 'all ' // name // ' checks passed'
    end subroutine finish

end module test_support
