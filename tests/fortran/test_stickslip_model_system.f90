!> Fortran tests of a model's system (stickslip_model_system) that Python does not reach: the
!! band of its Jacobian in the body order against the dense Jacobian. Prints one line per check;
!! exits with status 1 if any check fails.
program test_stickslip_model_system
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_user_model, only: stickslip_model
    use stickslip_model_system, only: model_system
    implicit none

    call test_model_band()

    call finish('model system')

contains

    !> A model's band (body order) against its dense Jacobian, for a static law (analytic),
    !! laws with states and Karnopp (holding coefficient; grouped differences): every entry
    !! outside the band is exactly zero in the dense Jacobian (the structure misses none),
    !! every entry inside agrees with it, and the band is narrower than the matrix.
    subroutine test_model_band()
        character(len=16), parameter :: laws(4) = [character(len=16) :: 'stribeck', 'lugre', 'karnopp', 'dahl']
        type(stickslip_model) :: m
        type(model_system) :: sys
        real(dp), allocatable :: y(:), f(:), jd(:, :), jb(:, :)
        integer, allocatable :: perm(:)
        integer(8) :: nfev
        integer :: law, i, j, nb, n, ml, mu, status, ek, ei, body, sig_n
        real(dp) :: err_in, max_out
        nb = 12
        do law = 1, size(laws)
            m = stickslip_model()
            do i = 1, nb
                body = m%add_body(1.0_dp + 0.1_dp * i, 0.01_dp * i, 0.3_dp * sin(real(i, dp)))
            end do
            sig_n = m%constant(9.81_dp)
            do i = 1, nb
                call m%add_spring(i, i - 1, 80.0_dp, 0.0_dp)
                if (i > 2) call m%add_spring(i, i - 2, 15.0_dp, 0.0_dp)
                call m%add_damper(i, 0, 0.2_dp)
                call m%add_contact(i, 0, trim(laws(law)), sig_n, m%constant(0.2_dp))
                if (mod(i, 3) == 2) call m%add_contact(i, i - 1, trim(laws(law)), m%constant(2.0_dp))
            end do
            call m%build(sys, status, ek, ei)
            n = sys%n_states()
            y = m%initial_state(sys)
            allocate(f(n), jd(n, n), perm(n))
            call sys%rhs(0.1_dp, y, f)
            nfev = 0
            call sys%jacobian(0.1_dp, y, f, jd, nfev)
            call sys%bandwidth(perm, ml, mu)
            allocate(jb(max(ml + mu + 1, 1), n))
            if (ml >= 0) call sys%band_jacobian(0.1_dp, y, f, jb, nfev)
            err_in = 0.0_dp
            max_out = 0.0_dp
            do j = 1, n
                do i = 1, n
                    if (i - j > ml .or. j - i > mu) then
                        max_out = max(max_out, abs(jd(perm(i), perm(j))))
                    else
                        err_in = max(err_in, abs(jb(mu + 1 + i - j, j) - jd(perm(i), perm(j))) &
                                             / max(1.0_dp, abs(jd(perm(i), perm(j)))))
                    end if
                end do
            end do
            call check(status == SS_OK .and. ml >= 0 .and. 2 * ml + mu + 1 < n .and. max_out == 0.0_dp &
                       .and. err_in <= 1.0e-5_dp, 'model ' // trim(laws(law)) // &
                       ': band in the body order holds every nonzero of the dense Jacobian')
            deallocate(f, jd, jb, perm)
        end do
    end subroutine test_model_band

end program test_stickslip_model_system
