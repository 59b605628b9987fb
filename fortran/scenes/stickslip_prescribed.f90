!> Prescribed motion: the friction force of any law along a given displacement record, its
!! internal states integrated with the motion known (friction identification fits this to
!! measured forces, thousands of times per fit).
!!
!! The motion. Samples (t_i, x_i, v_i), t strictly increasing: between two samples x(t) is
!! the cubic Hermite interpolant of (x, v) at both ends, so its velocity is the quadratic
!! dx/dt, equal to v_i at the samples (a caller without a velocity signal derives v_i from x).
!! The contact sees x through a play (backlash) of total width b >= 0: its displacement x_c
!! follows x only when x pushes at either end of the band, x_c = min(max(x_c, x - b/2),
!! x + b/2), starting centred (x_c = x_1); inside the band the contact does not move. The
!! contact velocity v_c at a sample is v_i when the play is engaged (b = 0, or x at an end
!! of the band and moving outwards) and 0 otherwise.
!!
!! The states. Each sample interval is cut at the reversals of x (the roots of the quadratic
!! velocity) into pieces where x is monotone, each piece into m equal substeps. Over a
!! substep the contact travels dx_c (the play applied to x at the substep's end) while its
!! velocity goes from v0 to v1 (the interpolant's, 0 while the play is open), and the law
!! advances its states (its `advance`: exact in the travel for Dahl, an exponential step with
!! a target linear over the substep for LuGre and the generalized Maxwell-slip model, exact
!! for both at a constant velocity and in the stiff limit; for the elasto-plastic law its own
!! flow in the travel (exact while elastic or fully sliding, a fourth-order Taylor step
!! between); one L-stable TR-BDF2 step with the velocity linear from v0 to v1 otherwise). The error of a substep is of second order in its
!! length where the states are smooth, larger across a stick-slip switch of GMS or a kink of
!! the elasto-plastic attachment; the step doubling below takes care of it.
!! m is chosen per interval by step doubling: the coefficient the states give at rest
!! (`evaluate` at v = 0: sigma0 z for the bristle laws, sum k_i z_i for GMS; continuous in
!! the states, unlike the rate terms that switch with a stick-slip mode), computed at the
!! interval's end with m and with 2m substeps, must agree within rtol (|mu| + mu_ref), mu_ref
!! the law's steady level at the record's largest speed; the 2m result is kept and m doubles
!! until it passes (at most 2^16; an interval that still fails is kept and counted in
!! `n_unconverged`). The next interval starts from m/2. A caller may instead give the substeps
!! of every interval (`substeps_in`, e.g. those `substeps_out` returned at a nearby parameter
!! set): one sweep each, no test, so that the result is a smooth function of the law's
!! parameters (finite differences of it measure the model, not the step choices; a fit's
!! Jacobian uses it).
!!
!! The force at a sample: mu = the law's `motion_mu` at (v_c, z) and the acceleration of the
!! Hermite cubic ending there (`evaluate` with holding coefficient 0 for every law but GMS,
!! which classifies an element on a moving slip level with the level's rate; static laws:
!! mu(v_c), exactly `friction` of the registry); a negative mu is multiplied by
!! `asymmetry` (the ratio of the negative-direction sliding level to the positive one; for a
!! static law the same as scaling mu for v < 0, for laws with states it keeps the force
!! continuous through reversals); force = mu N with N the normal force. Sign convention (the
!! laws'): in steady sliding mu has the sign of the velocity, so `force` is the force that
!! drives the motion against friction (what a load cell between actuator and body reads); the
!! friction force acting on the sliding body is -force.
module stickslip_prescribed
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_DIM, SS_BAD_RTOL, SS_BAD_Y0, SS_BAD_TIMES, SS_BAD_MOTION, &
                               SS_BAD_BACKLASH, SS_BAD_ASYMMETRY, SS_BAD_NORMAL_FORCE
    use stickslip_friction, only: friction_law
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: prescribed_motion, prescribed_stats

    !> Largest number of substeps per monotone piece of a sample interval.
    integer, parameter, public :: MAX_SUBSTEPS = 65536

    !> Relative slack of the play's engagement: a gap within it of half the backlash counts as
    !! engaged (the contact was set to x -+ half, to rounding).
    real(dp), parameter :: ENGAGED_SLACK = 1.0e-12_dp

    !> Counters of one prescribed-motion evaluation.
    type :: prescribed_stats
        integer(8) :: n_advance = 0      !! calls of the law's `advance` (substeps, both halves of each doubling test)
        integer(8) :: n_unconverged = 0  !! intervals kept at MAX_SUBSTEPS without passing the rtol test
        integer :: max_substeps = 0      !! largest substep count used in one piece
        integer :: status = SS_OK        !! SS_OK or the code of the bad input or failed step
    end type prescribed_stats

contains

    !> The friction force of `law` (initialised) along the sampled motion (t, x, v); see the
    !! module notes for the motion, the backlash, the integration and the sign convention.
    subroutine prescribed_motion(law, t, x, v, normal_force, z0, backlash, asymmetry, rtol, &
                                 force, mu, z, x_c, v_c, stats, substeps_in, substeps_out)
        class(friction_law), intent(inout) :: law   !! the friction law, initialised
        real(dp), intent(in) :: t(:)                !! sample times, strictly increasing [s]
        real(dp), intent(in) :: x(:)                !! displacement of the sliding body at t [m]
        real(dp), intent(in) :: v(:)                !! its velocity at t [m/s]
        real(dp), intent(in) :: normal_force(:)     !! normal force: 1 value or one per sample [N]
        real(dp), intent(in) :: z0(:)               !! initial internal states (size n_states)
        real(dp), intent(in) :: backlash            !! total width of the play, >= 0 [m]
        real(dp), intent(in) :: asymmetry           !! negative-direction level / positive one, > 0 [-]
        !> relative tolerance of the step-doubling test, 0 (= 100 eps) or in [100 eps, 1) [-]
        real(dp), intent(in) :: rtol
        real(dp), intent(out) :: force(:)           !! friction force mu N at t [N]
        real(dp), intent(out) :: mu(:)              !! friction coefficient at t (asymmetry applied) [-]
        real(dp), intent(out) :: z(:, :)            !! (n_states, size(t)) internal states at t
        real(dp), intent(out) :: x_c(:)             !! contact displacement at t [m]
        real(dp), intent(out) :: v_c(:)             !! contact velocity at t [m/s]
        type(prescribed_stats), intent(out) :: stats   !! counters; stats%status: SS_OK or the bad input
        !> substeps per monotone piece of each sample interval (size(t) - 1 values, each >= 1)
        !! instead of the step-doubling choice: a frozen mesh, on which the result is a smooth
        !! function of the law's parameters (finite differences of it measure the model, not
        !! the step choices); rtol is then unused
        integer, intent(in), optional :: substeps_in(:)
        !> the substeps per piece that each sample interval used (size(t) - 1 values; the
        !! count of the kept half of the doubling test, or substeps_in)
        integer, intent(out), optional :: substeps_out(:)
        integer :: n, nz, i, m, status
        real(dp) :: half, tol, mu_ref, xc
        ! the current interval [t(kk), t(kk+1)]: Hermite coefficients, breakpoints, length
        integer :: kk, np
        real(dp) :: c(4), tau(4), dt

        n = size(t)
        nz = law%n_states()
        force = 0.0_dp
        mu = 0.0_dp
        z = 0.0_dp
        x_c = 0.0_dp
        v_c = 0.0_dp
        status = check_input()
        if (status == SS_OK .and. present(substeps_in)) then
            if (size(substeps_in) < n - 1) then
                status = SS_BAD_DIM
            else if (n > 1) then
                if (any(substeps_in(1:n - 1) < 1 .or. substeps_in(1:n - 1) > MAX_SUBSTEPS)) status = SS_BAD_DIM
            end if
        end if
        if (status == SS_OK .and. present(substeps_out)) then
            if (size(substeps_out) < n - 1) status = SS_BAD_DIM
        end if
        if (present(substeps_out)) substeps_out = 0
        stats%status = status
        if (status /= SS_OK) return

        half = 0.5_dp * backlash
        tol = max(rtol, 100.0_dp * epsilon(1.0_dp))
        mu_ref = abs(law%mu(maxval(abs(v))))
        if (.not. mu_ref > 0.0_dp) mu_ref = 1.0_dp
        xc = x(1)
        z(:, 1) = z0
        call output(1, xc, z(:, 1))
        m = 1
        do i = 1, n - 1
            call interval(i, xc, z(:, i), z(:, i + 1), m)
            if (stats%status /= SS_OK) return
            call output(i + 1, xc, z(:, i + 1))
        end do

    contains

        integer function check_input() result(st)
            integer :: k
            st = SS_OK
            if (size(x) /= n .or. size(v) /= n .or. size(force) /= n .or. size(mu) /= n .or. &
                size(x_c) /= n .or. size(v_c) /= n .or. size(z, 1) /= nz .or. size(z, 2) /= n .or. &
                size(z0) /= nz .or. n < 1 .or. .not. (size(normal_force) == 1 .or. size(normal_force) == n)) then
                st = SS_BAD_DIM
            else if (.not. all(ieee_is_finite(t))) then
                st = SS_BAD_TIMES
            else if (.not. all(ieee_is_finite(x)) .or. .not. all(ieee_is_finite(v))) then
                st = SS_BAD_MOTION
            else if (.not. all(ieee_is_finite(normal_force))) then
                st = SS_BAD_NORMAL_FORCE
            else if (any(normal_force < 0.0_dp)) then
                st = SS_BAD_NORMAL_FORCE
            else if (.not. all(ieee_is_finite(z0))) then
                st = SS_BAD_Y0
            else if (.not. (ieee_is_finite(backlash) .and. backlash >= 0.0_dp)) then
                st = SS_BAD_BACKLASH
            else if (.not. (ieee_is_finite(asymmetry) .and. asymmetry > 0.0_dp)) then
                st = SS_BAD_ASYMMETRY
            else if (.not. (ieee_is_finite(rtol) .and. rtol < 1.0_dp .and. &
                            (rtol == 0.0_dp .or. rtol >= 100.0_dp * epsilon(1.0_dp)))) then
                st = SS_BAD_RTOL
            end if
            if (st /= SS_OK) return
            do k = 1, n - 1
                if (.not. t(k + 1) > t(k)) then
                    st = SS_BAD_TIMES
                    return
                end if
            end do
        end function check_input

        !> Contact velocity, coefficient and force at sample k.
        subroutine output(k, xck, zk)
            integer, intent(in) :: k
            real(dp), intent(in) :: xck, zk(:)
            x_c(k) = xck
            v_c(k) = contact_velocity(k, xck)
            if (nz == 0) then
                mu(k) = law%mu(v_c(k))
            else
                call law%motion_mu(v_c(k), merge(acceleration(k), 0.0_dp, v_c(k) /= 0.0_dp), zk, mu(k))
            end if
            if (mu(k) < 0.0_dp) mu(k) = asymmetry * mu(k)
            force(k) = mu(k) * normal_force(merge(1, k, size(normal_force) == 1))
        end subroutine output

        !> Advance the contact and the states over [t(k), t(k+1)], m substeps per piece to start
        !! with (updated to the count used, halved for the next interval).
        subroutine interval(k, xck, za, zb, m)
            integer, intent(in) :: k
            real(dp), intent(inout) :: xck
            real(dp), intent(in) :: za(:)
            real(dp), intent(out) :: zb(:)
            integer, intent(inout) :: m
            real(dp) :: xc1, xc2, z1(nz), z2(nz), mu1, mu2
            integer :: st
            kk = k
            dt = t(k + 1) - t(k)
            ! Hermite: x(s) = c1 + c2 s + c3 s^2 + c4 s^3 on s in [0, 1]
            c(1) = x(k)
            c(2) = dt * v(k)
            c(3) = 3.0_dp * (x(k + 1) - x(k)) - dt * (2.0_dp * v(k) + v(k + 1))
            c(4) = -2.0_dp * (x(k + 1) - x(k)) + dt * (v(k) + v(k + 1))
            call pieces(c, tau, np)
            if (nz == 0) then
                call sweep(1, xck, za, xc1, z1, st)
                xck = xc1
                if (present(substeps_out)) substeps_out(k) = 1
                return
            end if
            if (present(substeps_in)) then
                ! the frozen mesh: one sweep with the given substeps
                call sweep(substeps_in(k), xck, za, xc2, zb, st)
                if (st /= SS_OK) then
                    stats%status = st
                    return
                end if
                stats%max_substeps = max(stats%max_substeps, substeps_in(k))
                if (present(substeps_out)) substeps_out(k) = substeps_in(k)
                xck = xc2
                return
            end if
            call sweep(m, xck, za, xc1, z1, st)
            if (st /= SS_OK) z1 = huge(1.0_dp)
            do
                call sweep(2 * m, xck, za, xc2, z2, st)
                if (st /= SS_OK) then
                    if (2 * m >= MAX_SUBSTEPS) then
                        stats%status = st
                        return
                    end if
                    m = 2 * m
                    z1 = huge(1.0_dp)
                    cycle
                end if
                call end_mu(z1, mu1)
                call end_mu(z2, mu2)
                if (abs(mu2 - mu1) <= tol * (abs(mu2) + mu_ref)) exit
                if (2 * m >= MAX_SUBSTEPS) then
                    stats%n_unconverged = stats%n_unconverged + 1
                    exit
                end if
                m = 2 * m
                xc1 = xc2
                z1 = z2
            end do
            stats%max_substeps = max(stats%max_substeps, 2 * m)
            if (present(substeps_out)) substeps_out(k) = 2 * m
            xck = xc2
            zb = z2
            m = max(1, m / 2)
        end subroutine interval

        !> States and contact at t(kk+1) from (xca, za) at t(kk), ms substeps per piece.
        !> States and contact at t(kk+1) from (xca, za) at t(kk), ms substeps per piece. A
        !! substep in which the play engages is cut where it does (bisection on the monotone
        !! x): the contact rests before, moves at its mean velocity after.
        subroutine sweep(ms, xca, za, xce, ze, st)
            integer, intent(in) :: ms
            real(dp), intent(in) :: xca, za(:)
            real(dp), intent(out) :: xce, ze(:)
            integer, intent(out) :: st
            integer :: p, j, it
            real(dp) :: s0, s1, sa, s, h, xs, xa, xnew, lo, hi, mid
            st = SS_OK
            xce = xca
            ze = za
            xa = x(kk)
            do p = 1, np - 1
                s0 = tau(p)
                s1 = tau(p + 1)
                do j = 1, ms
                    sa = s0 + (s1 - s0) * real(j - 1, dp) / real(ms, dp)
                    s = s0 + (s1 - s0) * real(j, dp) / real(ms, dp)
                    if (nz == 0) s = s1
                    xs = hermite(s)
                    if (j == ms .and. p == np - 1 .or. nz == 0 .and. p == np - 1) xs = x(kk + 1)
                    xnew = min(max(xce, xs - half), xs + half)
                    if (nz > 0) then
                        ! (engaged already when the gap is half to rounding: the contact
                        ! was set to x -+ half at the substep's start; a bisection there
                        ! would only find the start again, at the cost of 60 x evaluations)
                        if (xnew /= xce .and. abs(xa - xce) < half * (1.0_dp - ENGAGED_SLACK)) then
                            ! the play engages inside the substep: at |x(s) - xce| = half
                            lo = sa
                            hi = s
                            do it = 1, 60
                                mid = 0.5_dp * (lo + hi)
                                if (abs(hermite(mid) - xce) < half) then
                                    lo = mid
                                else
                                    hi = mid
                                end if
                            end do
                            call law%advance(0.0_dp, (hi - sa) * dt, 0.0_dp, 0.0_dp, ze, st)
                            if (st /= SS_OK) return
                            sa = hi
                            stats%n_advance = stats%n_advance + 1
                        end if
                        h = (s - sa) * dt
                        if (h > 0.0_dp) then
                            call law%advance(xnew - xce, h, merge(velocity(sa), 0.0_dp, xnew /= xce), &
                                             merge(velocity(s), 0.0_dp, xnew /= xce), ze, st)
                            stats%n_advance = stats%n_advance + 1
                            if (st /= SS_OK) return
                        end if
                    end if
                    xce = xnew
                    xa = xs
                    if (nz == 0) exit
                end do
            end do
        end subroutine sweep

        !> The coefficient the states ze would give at rest (the error test's measure: a
        !! continuous function of the states, free of the rate terms that switch with a
        !! stick-slip mode).
        subroutine end_mu(ze, mue)
            real(dp), intent(in) :: ze(:)
            real(dp), intent(out) :: mue
            real(dp) :: dz(nz)
            call law%evaluate(0.0_dp, ze, 0.0_dp, mue, dz)
        end subroutine end_mu

        !> The acceleration at sample k: the second derivative of the Hermite cubic of the
        !! interval that ends there (of the first interval at sample 1; 0 for one sample).
        real(dp) function acceleration(k) result(a)
            integer, intent(in) :: k
            real(dp) :: h, c3, c4
            a = 0.0_dp
            if (n < 2) return
            if (k == 1) then
                h = t(2) - t(1)
                c3 = 3.0_dp * (x(2) - x(1)) - h * (2.0_dp * v(1) + v(2))
                a = 2.0_dp * c3 / h**2
            else
                h = t(k) - t(k - 1)
                c3 = 3.0_dp * (x(k) - x(k - 1)) - h * (2.0_dp * v(k - 1) + v(k))
                c4 = -2.0_dp * (x(k) - x(k - 1)) + h * (v(k - 1) + v(k))
                a = (2.0_dp * c3 + 6.0_dp * c4) / h**2
            end if
        end function acceleration

        !> x at the fraction s of the current interval (its Hermite cubic).
        pure real(dp) function hermite(s) result(xs)
            real(dp), intent(in) :: s
            xs = c(1) + s * (c(2) + s * (c(3) + s * c(4)))
        end function hermite

        !> dx/dt at the fraction s of the current interval (the Hermite cubic's derivative).
        pure real(dp) function velocity(s) result(vs)
            real(dp), intent(in) :: s
            vs = (c(2) + s * (2.0_dp * c(3) + s * 3.0_dp * c(4))) / dt
        end function velocity

        !> The contact velocity at sample k with the contact at xck: v(k) when the play is
        !! engaged, 0 inside the band.
        real(dp) function contact_velocity(k, xck) result(vc)
            integer, intent(in) :: k
            real(dp), intent(in) :: xck
            real(dp) :: gap
            gap = x(k) - xck
            vc = v(k)
            if (backlash > 0.0_dp .and. .not. (abs(gap) >= half * (1.0_dp - ENGAGED_SLACK) .and. &
                                               v(k) * gap > 0.0_dp)) vc = 0.0_dp
        end function contact_velocity

    end subroutine prescribed_motion

    !> The breakpoints 0 = tau(1) < ... < tau(np) = 1 of [0, 1] at the roots of the velocity
    !! c2 + 2 c3 s + 3 c4 s^2 of the cubic x(s) = c1 + c2 s + c3 s^2 + c4 s^3 inside (0, 1).
    pure subroutine pieces(c, tau, np)
        real(dp), intent(in) :: c(4)        !! coefficients of x(s) [m]
        real(dp), intent(out) :: tau(4)     !! breakpoints in [0, 1]
        integer, intent(out) :: np          !! number of breakpoints (2 to 4)
        real(dp) :: a, b, cc, disc, q, r1, r2
        a = 3.0_dp * c(4)
        b = 2.0_dp * c(3)
        cc = c(2)
        tau(1) = 0.0_dp
        np = 1
        r1 = -1.0_dp
        r2 = -1.0_dp
        if (a == 0.0_dp) then
            if (b /= 0.0_dp) r1 = -cc / b
        else
            disc = b * b - 4.0_dp * a * cc
            if (disc > 0.0_dp) then
                q = -0.5_dp * (b + sign(sqrt(disc), b))
                r1 = q / a
                if (q /= 0.0_dp) r2 = cc / q
                if (r2 < r1) then
                    q = r1
                    r1 = r2
                    r2 = q
                end if
            end if
        end if
        if (r1 > 0.0_dp .and. r1 < 1.0_dp) then
            np = np + 1
            tau(np) = r1
        end if
        if (r2 > 0.0_dp .and. r2 < 1.0_dp .and. r2 > tau(np)) then
            np = np + 1
            tau(np) = r2
        end if
        np = np + 1
        tau(np) = 1.0_dp
    end subroutine pieces

end module stickslip_prescribed
