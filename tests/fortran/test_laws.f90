!> Fortran tests of the friction laws' behaviour that Python cannot reach: the analytic
!! derivatives `dmu` against central differences of `mu`, `evaluate` with a holding
!! coefficient and internal states at hand-computed points, the elasto-plastic alpha, the
!! law metadata (states, labels, static or not), the registry's parameter table (names
!! and status codes unique; the new laws' codes in -140 .. -199), and `evaluate_run` and
!! `mu_run` against `evaluate` and `mu` contact by contact.
!! Prints one line per check; exits with status 1 if any check fails.
program test_laws
    use test_support, only: check, finish
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_values, NAME_LEN
    use stickslip_friction, only: friction_law
    use stickslip_registry, only: PARAMS, LAW_TABLE, make_law, code_of, resolve_params
    implicit none

    real(dp), parameter :: MU_S = 0.35_dp, MU_K = 0.30_dp

    call test_param_table()
    call test_derivatives()
    call test_karnopp()
    call test_lugre()
    call test_elastoplastic()
    call test_law_derivatives()
    call test_runs()

    call finish('law')

contains

    !> A law by name with the given parameters (the others at their defaults).
    function law(name, keys, vals) result(fl)
        character(len=*), intent(in) :: name, keys(:)
        real(dp), intent(in) :: vals(:)
        class(friction_law), allocatable :: fl
        type(param_values) :: p
        integer :: status
        status = make_law(code_of('law', name), keys, vals, fl, p)
        call check(status == SS_OK, 'make_law ' // name)
    end function law

    subroutine test_param_table()
        integer :: i, j
        logical :: unique_names, unique_codes, new_in_range
        unique_names = .true.
        unique_codes = .true.
        do i = 1, size(PARAMS)
            do j = i + 1, size(PARAMS)
                if (PARAMS(i)%name == PARAMS(j)%name) unique_names = .false.
                if (PARAMS(i)%code == PARAMS(j)%code) unique_codes = .false.
            end do
        end do
        call check(unique_names, 'PARAMS: names unique')
        call check(unique_codes, 'PARAMS: status codes unique')
        new_in_range = .true.
        do i = 1, size(PARAMS)
            select case (trim(PARAMS(i)%name))
            case ('delta', 'c_v', 'v_eps', 'dv', 'sigma0', 'sigma1', 'sigma2', 'z_ba_ratio')
                if (PARAMS(i)%code > -140 .or. PARAMS(i)%code < -199) new_in_range = .false.
            end select
        end do
        call check(new_in_range, 'PARAMS: the new laws'' codes in -140 .. -199')
        call check(all([(code_of('law', LAW_TABLE(i)%name) == i, i = 1, size(LAW_TABLE))]) .and. &
                   code_of('law', 'elastoplastic') == 7 .and. &
                   code_of('law', 'dahl') == 8 .and. code_of('law', 'gms') == 9 .and. &
                   code_of('law', 'drake_continuous') == 10 .and. code_of('law', 'drake_tamsi') == 11 .and. &
                   code_of('law', 'capped_viscous') == 12 .and. code_of('law', 'mujoco_pyramidal') == 13, &
                   'LAW_TABLE: a law''s code is its position, and the codes given never change')
    end subroutine test_param_table

    !> dmu against a central difference of mu (relative 1e-6) away from kinks and jumps.
    subroutine test_derivatives()
        character(len=16), parameter :: names(4) = [character(len=16) :: 'stribeck', 'lugre', &
                                                     'elastoplastic', 'karnopp']
        real(dp), parameter :: vs(6) = [-0.7_dp, -0.004_dp, 0.0003_dp, 0.002_dp, 0.013_dp, 1.5_dp]
        class(friction_law), allocatable :: fl
        real(dp) :: d, fd, h
        integer :: i, k
        logical :: ok
        character(len=64) :: what
        do i = 1, size(names)
            fl = law(trim(names(i)), [character(len=16) :: 'c_v'], [0.05_dp])
            ok = .true.
            do k = 1, size(vs)
                h = 1.0e-7_dp * max(abs(vs(k)), 1.0e-3_dp)
                fd = (fl%mu(vs(k) + h) - fl%mu(vs(k) - h)) / (2.0_dp * h)
                d = fl%dmu(vs(k))
                if (abs(d - fd) > 1.0e-6_dp * max(1.0_dp, abs(fd))) then
                    ok = .false.
                    print '(a, a, 3es14.6)', '      ', trim(names(i)), vs(k), d, fd
                end if
            end do
            write (what, '(a, a)') 'dmu = central difference of mu: ', trim(names(i))
            call check(ok, trim(what))
        end do
        ! Stribeck at rest: g(0)/v_eps + c_v (the tanh ramp's slope), finite even for delta < 1
        fl = law('stribeck', [character(len=16) :: 'delta', 'c_v', 'v_eps'], [0.5_dp, 0.05_dp, 2.0e-3_dp])
        call check(abs(fl%dmu(0.0_dp) - (MU_S / 2.0e-3_dp + 0.05_dp)) < 1.0e-12_dp, &
                   'stribeck dmu(0) = mu_s/v_eps + c_v (delta = 0.5)')
    end subroutine test_derivatives

    !> Inside the band mu = clamp(mu_hold, -mu_s, mu_s); outside mu_k sign(v) whatever mu_hold.
    subroutine test_karnopp()
        class(friction_law), allocatable :: fl
        real(dp) :: mu, z(0), dz(0)
        fl = law('karnopp', [character(len=16) :: 'dv'], [1.0e-3_dp])
        call check(.not. fl%is_static() .and. fl%n_states() == 0, 'karnopp: not static, no states')
        call fl%evaluate(5.0e-4_dp, z, 0.2_dp, mu, dz)
        call check(mu == 0.2_dp, 'karnopp: in band, mu = mu_hold = 0.2')
        call fl%evaluate(-9.0e-4_dp, z, 0.5_dp, mu, dz)
        call check(mu == MU_S, 'karnopp: in band, mu_hold = 0.5 clamped to mu_s')
        call fl%evaluate(0.0_dp, z, -0.5_dp, mu, dz)
        call check(mu == -MU_S, 'karnopp: in band, mu_hold = -0.5 clamped to -mu_s')
        call fl%evaluate(1.0e-3_dp, z, 0.2_dp, mu, dz)
        call check(mu == MU_K, 'karnopp: at the band edge, mu_k')
        call fl%evaluate(-0.3_dp, z, 0.2_dp, mu, dz)
        call check(mu == -MU_K, 'karnopp: outside, -mu_k for v < 0')
    end subroutine test_karnopp

    !> mu = sigma0 z + sigma1 z' + sigma2 v, z' = v - sigma0 |v| z / g(v), by hand.
    subroutine test_lugre()
        class(friction_law), allocatable :: fl
        real(dp) :: mu, dz(1), g, s0, s1, s2, dz_hand, v, z
        s0 = 1.0e5_dp / 9.81_dp
        s1 = sqrt(1.0e5_dp) / 9.81_dp
        s2 = 0.4_dp / 9.81_dp
        fl = law('lugre', [character(len=16) ::], [real(dp) ::])
        call check(fl%n_states() == 1 .and. fl%state_label(1) == 'z [m]' .and. .not. fl%is_static(), &
                   'lugre: one state z [m], not static')
        v = -0.01_dp
        z = -2.0e-5_dp
        g = MU_K + (MU_S - MU_K) * exp(-1.0_dp)
        call fl%evaluate(v, [z], 0.0_dp, mu, dz)
        dz_hand = v - s0 * abs(v) * z / g
        call check(abs(dz(1) - dz_hand) < 1.0e-15_dp, 'lugre: z'' at v = -0.01, z = -2e-5')
        call check(abs(mu - (s0 * z + s1 * dz_hand + s2 * v)) < 1.0e-13_dp, 'lugre: mu at the same point')
        ! steady state z = g/sigma0: z' = 0 and mu equals the steady curve
        call fl%evaluate(0.01_dp, [g / s0], 0.0_dp, mu, dz)
        call check(abs(dz(1)) < 1.0e-15_dp .and. abs(mu - fl%mu(0.01_dp)) < 1.0e-13_dp, &
                   'lugre: steady deflection g/sigma0 gives z'' = 0 and mu = mu(v)')
    end subroutine test_lugre

    !> Dupont's alpha: 0 below z_ba or against the motion, 1 past z_ss, 1/2 half way.
    subroutine test_elastoplastic()
        class(friction_law), allocatable :: fl
        real(dp) :: mu, dz(1), s0, z_ba, z_ss, g, v
        s0 = 1.0e5_dp / 9.81_dp
        fl = law('elastoplastic', [character(len=16) :: 'z_ba_ratio'], [0.5_dp])
        z_ba = 0.5_dp * MU_K / s0
        v = 0.02_dp
        g = MU_K + (MU_S - MU_K) * exp(-4.0_dp)
        z_ss = g / s0
        call fl%evaluate(v, [0.99_dp * z_ba], 0.0_dp, mu, dz)
        call check(dz(1) == v, 'elastoplastic: |z| < z_ba is elastic, z'' = v')
        call fl%evaluate(-v, [1.5_dp * z_ss], 0.0_dp, mu, dz)
        call check(dz(1) == -v, 'elastoplastic: z against the motion is elastic, z'' = v')
        call fl%evaluate(v, [1.5_dp * z_ss], 0.0_dp, mu, dz)
        call check(abs(dz(1) - (v - s0 * v * 1.5_dp * z_ss / g)) < 1.0e-15_dp, &
                   'elastoplastic: |z| > z_ss is LuGre (alpha = 1)')
        call fl%evaluate(-v, [-0.5_dp * (z_ss + z_ba)], 0.0_dp, mu, dz)
        ! z' = v - alpha sigma0 |v| z / g with v = -0.02, z = -(z_ss + z_ba)/2, alpha = 1/2
        call check(abs(dz(1) - (-v + 0.5_dp * s0 * v * 0.5_dp * (z_ss + z_ba) / g)) < 1.0e-15_dp, &
                   'elastoplastic: alpha = 1/2 half way between z_ba and z_ss (v < 0)')
    end subroutine test_elastoplastic

    !> Each law's dmu against a central difference of its mu, away from its kinks.
    subroutine test_law_derivatives()
        class(friction_law), allocatable :: fl
        type(param_values) :: p
        real(dp), parameter :: v(6) = [-0.3_dp, -0.012_dp, -0.004_dp, 0.003_dp, 0.0125_dp, 0.7_dp]
        real(dp) :: d, fd, dv
        integer :: law, i, status
        logical :: ok
        do law = 1, size(LAW_TABLE)
            status = make_law(law, [character(len=NAME_LEN) ::], [real(dp) ::], fl, p)
            ok = status == SS_OK
            do i = 1, size(v)
                dv = 1.0e-7_dp
                fd = (fl%mu(v(i) + dv) - fl%mu(v(i) - dv)) / (2.0_dp * dv)
                d = fl%dmu(v(i))
                ok = ok .and. abs(d - fd) <= 1.0e-5_dp * max(1.0_dp, abs(fd))
                ok = ok .and. fl%mu(-v(i)) == -fl%mu(v(i))
            end do
            call check(ok, 'law ' // trim(LAW_TABLE(law)%name) // ': dmu = central difference, mu odd')
        end do
        status = make_law(3, [character(len=NAME_LEN) ::], [real(dp) ::], fl, p)
        call check(fl%dmu(0.0_dp) > 0.0_dp .and. fl%dmu(0.0_dp) < huge(1.0_dp) .and. &
                   fl%dmu(0.0_dp) == fl%dmu(1.0e-12_dp), 'law proposed: dmu finite at rest (floor at 1e-6 v_s)')
    end subroutine test_law_derivatives

    !> Each law's `evaluate_run` over five contacts (slips on both sides of rest and in the
    !! law's band, states away from 0, holding coefficients inside and outside mu_s) gives
    !! `evaluate`'s numbers at each contact, bit for bit, and `mu_run` gives `mu`'s: GMS too,
    !! which extends LuGre and evaluates its own way; and `mu_run` at 4000 slips spread over
    !! the band and beyond gives `mu`'s numbers.
    subroutine test_runs()
        use stickslip_laws, only: evaluate_run, mu_run
        class(friction_law), allocatable :: fl
        type(param_values) :: p
        real(dp), parameter :: v(5) = [-0.2_dp, -0.004_dp, 0.0_dp, 0.003_dp, 0.5_dp]
        real(dp), parameter :: hold(5) = [0.1_dp, -0.5_dp, 0.2_dp, 0.34_dp, 0.0_dp]
        real(dp), allocatable :: z(:), dz(:), dz1(:)
        real(dp) :: mu(5), mus(5), mu1, vs(4000), mus_many(4000)
        integer :: law, i, nz, status
        logical :: ok
        do law = 1, size(LAW_TABLE)
            status = make_law(law, [character(len=NAME_LEN) ::], [real(dp) ::], fl, p)
            nz = fl%n_states()
            z = [(1.0e-6_dp * real(modulo(7 * i, 11) - 5, dp), i = 1, 5 * nz)]
            allocate(dz(5 * nz), dz1(nz))
            call evaluate_run(fl, v, z, hold, mu, dz)
            call mu_run(fl, v, mus)
            ok = status == SS_OK
            do i = 1, 5
                call fl%evaluate(v(i), z((i - 1) * nz + 1:i * nz), hold(i), mu1, dz1)
                ok = ok .and. mu1 == mu(i) .and. all(dz1 == dz((i - 1) * nz + 1:i * nz)) .and. mus(i) == fl%mu(v(i))
            end do
            call check(ok, 'law ' // trim(LAW_TABLE(law)%name) // ': evaluate_run and mu_run = evaluate and mu at each contact')
            call random_number(vs)
            vs = 0.05_dp * (vs - 0.5_dp)
            call mu_run(fl, vs, mus_many)
            ok = .true.
            do i = 1, size(vs)
                ok = ok .and. mus_many(i) == fl%mu(vs(i))
            end do
            call check(ok, 'law ' // trim(LAW_TABLE(law)%name) // ': mu_run = mu at 4000 slips, bit for bit')
            deallocate(dz, dz1)
        end do
    end subroutine test_runs

end program test_laws
