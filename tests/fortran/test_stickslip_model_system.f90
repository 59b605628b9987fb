!> Fortran tests of a model's system (stickslip_model_system) that Python does not reach: the
!! band of its Jacobian in the body order against the dense Jacobian, and the runs of contacts
!! that share a law against the same model evaluated contact by contact. Prints one line per check;
!! exits with status 1 if any check fails.
program test_stickslip_model_system
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_user_model, only: stickslip_model
    use stickslip_model_system, only: model_system
    implicit none

    call test_model_band()
    call test_law_runs()

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

    !> The runs of contacts that share a law (`law_run`): contacts naming the same law with the
    !! same parameters, given alike, form one run, any other law or value starts a new one; and
    !! `rhs` with the runs equals `rhs` with every contact a run of its own, bit for bit.
    subroutine test_law_runs()
        character(len=8), parameter :: NOKEY(0) = [character(len=8) ::]
        real(dp), parameter :: NOVAL(0) = [real(dp) ::]
        type(stickslip_model) :: m
        type(model_system) :: sys, alone
        real(dp), allocatable :: y(:), f(:), f1(:)
        integer :: i, status, ek, ei, body, sig_n, sig_w
        m = stickslip_model()
        do i = 1, 6
            body = m%add_body(1.0_dp + 0.1_dp * i, 0.01_dp * i, 0.3_dp * sin(real(i, dp)))
            call m%add_spring(i, i - 1, 80.0_dp, 0.0_dp)
        end do
        sig_n = m%constant(9.81_dp)
        sig_w = m%constant(0.2_dp)
        call m%add_contact(1, 0, 'lugre', sig_n, sig_w)
        call m%add_contact(2, 0, 'lugre', sig_n, sig_w, keys=NOKEY, vals=NOVAL)
        call m%add_contact(3, 0, 'lugre', sig_n, sig_w, keys=['mu_s'], vals=[0.5_dp])
        call m%add_contact(4, 3, 'lugre', sig_n, 0, keys=['mu_s'], vals=[0.5_dp])
        call m%add_contact(5, 0, 'dahl', sig_n, sig_w)
        call m%add_contact(6, 0, 'lugre', sig_n, sig_w)
        call m%build(sys, status, ek, ei)
        call check(status == SS_OK .and. sys%fixed_contacts .and. size(sys%law_run) == 5, 'model: four runs of shared laws')
        if (size(sys%law_run) == 5) call check(all(sys%law_run == [1, 3, 5, 6, 7]), &
                                               'model: runs start at a new law or new values')
        y = m%initial_state(sys)
        y(2 * 6 + 1:) = [(1.0e-6_dp * real(i - 3, dp), i = 1, size(y) - 12)]
        allocate(f(size(y)), f1(size(y)))
        alone = sys
        alone%law_run = [(i, i = 1, 7)]
        call sys%rhs(0.1_dp, y, f)
        call alone%rhs(0.1_dp, y, f1)
        call check(all(f == f1), 'model: rhs with shared laws = rhs contact by contact, bit for bit')
    end subroutine test_law_runs

end program test_stickslip_model_system
