!> Friction-coefficient laws mu(v) of Yoo & Lee (2008), as elemental pure functions.
!!
!! v is the relative sliding velocity [m/s]; every law is odd in v, mu(-v) = -mu(v),
!! so the friction force is mu(v_rel) * N with the sign already applied. The
!! coefficients are dimensionless.
!!
!! Laws:
!! - `coulomb`   (eq. 1): mu_s sign(v) for 0 < |v| < v_s, mu_k sign(v) beyond, 0 at v = 0.
!! - `recurdyn`  (eqs. 2-3): haversine step 0 -> mu_s on [0, v_s], mu_s -> mu_k on [v_s, v_d].
!! - `proposed`  (eq. 5, Roh & Yoo 2007): mu_s (|v|/v_s)^beta inside v_s,
!!               a^-(|v|+b) + mu_k outside, b = -ln(mu_s - mu_k)/ln(a) - v_s (continuity).
!!
!! `friction_law` holds the parameters of one law with the derived constants cached
!! (ln a and b of the proposed law), and `friction_mu` evaluates it.
module stickslip_friction
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_LAW, SS_BAD_MU_S, SS_BAD_MU_K, SS_BAD_V_S, &
                               SS_BAD_V_D, SS_BAD_BETA, SS_BAD_A
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: friction_law, friction_law_init, friction_mu
    public :: coulomb, recurdyn, proposed, havsin, proposed_b

    integer, parameter, public :: LAW_COULOMB = 1     !! code of the Coulomb law
    integer, parameter, public :: LAW_RECURDYN = 2    !! code of the commercial (RecurDyn/ADAMS) law
    integer, parameter, public :: LAW_PROPOSED = 3    !! code of the Roh & Yoo (2007) law

    real(dp), parameter :: pi = acos(-1.0_dp)

    !> One friction law with its parameters and cached derived constants.
    type :: friction_law
        integer  :: law = LAW_PROPOSED  !! LAW_COULOMB, LAW_RECURDYN or LAW_PROPOSED
        real(dp) :: mu_s = 0.35_dp      !! static coefficient [-]
        real(dp) :: mu_k = 0.30_dp      !! kinetic coefficient [-]
        real(dp) :: v_s = 0.01_dp       !! static threshold velocity [m/s]
        real(dp) :: v_d = 0.015_dp      !! dynamic threshold velocity of the recurdyn law [m/s]
        real(dp) :: beta = 1.0_dp/3.0_dp  !! exponent of the proposed law inside v_s [-]
        real(dp) :: a = 1.5_dp          !! base of the proposed law outside v_s (> 1) [-]
        real(dp) :: ln_a = 0.0_dp       !! cached ln(a)
        real(dp) :: b = 0.0_dp          !! cached continuity offset b of the proposed law [m/s]
    end type friction_law

contains

    !> Validate the parameters of a law and fill `self`, caching ln a and b.
    !! Only the parameters the chosen law uses are checked (v_d for recurdyn,
    !! beta and a for proposed). Returns SS_OK or the code naming the bad parameter.
    function friction_law_init(self, law, mu_s, mu_k, v_s, v_d, beta, a) result(status)
        type(friction_law), intent(out) :: self
        integer, intent(in)  :: law       !! LAW_COULOMB, LAW_RECURDYN or LAW_PROPOSED
        real(dp), intent(in) :: mu_s      !! static coefficient, >= 0 [-]
        real(dp), intent(in) :: mu_k      !! kinetic coefficient, 0 <= mu_k <= mu_s [-]
        real(dp), intent(in) :: v_s       !! static threshold velocity, > 0 [m/s]
        real(dp), intent(in) :: v_d       !! dynamic threshold velocity, > v_s (recurdyn) [m/s]
        real(dp), intent(in) :: beta      !! exponent, > 0 (proposed) [-]
        real(dp), intent(in) :: a         !! base, > 1 (proposed) [-]
        integer :: status

        status = SS_OK
        if (law < LAW_COULOMB .or. law > LAW_PROPOSED) then
            status = SS_BAD_LAW
        else if (.not. ieee_is_finite(mu_s) .or. mu_s < 0.0_dp) then
            status = SS_BAD_MU_S
        else if (.not. ieee_is_finite(mu_k) .or. mu_k < 0.0_dp .or. mu_k > mu_s) then
            status = SS_BAD_MU_K
        else if (.not. ieee_is_finite(v_s) .or. v_s <= 0.0_dp) then
            status = SS_BAD_V_S
        else if (law == LAW_RECURDYN .and. (.not. ieee_is_finite(v_d) .or. v_d <= v_s)) then
            status = SS_BAD_V_D
        else if (law == LAW_PROPOSED .and. (.not. ieee_is_finite(beta) .or. beta <= 0.0_dp)) then
            status = SS_BAD_BETA
        else if (law == LAW_PROPOSED .and. (.not. ieee_is_finite(a) .or. a <= 1.0_dp)) then
            status = SS_BAD_A
        end if
        if (status /= SS_OK) return

        self%law = law
        self%mu_s = mu_s
        self%mu_k = mu_k
        self%v_s = v_s
        self%v_d = v_d
        self%beta = beta
        self%a = a
        if (law == LAW_PROPOSED) then
            self%ln_a = log(a)
            self%b = proposed_b(mu_s, mu_k, v_s, a)
        end if
    end function friction_law_init

    !> Friction coefficient of a validated law at relative velocity v [m/s].
    elemental function friction_mu(self, v) result(mu)
        type(friction_law), intent(in) :: self  !! a law filled by friction_law_init
        real(dp), intent(in) :: v               !! relative sliding velocity [m/s]
        real(dp) :: mu                          !! friction coefficient, odd in v [-]
        select case (self%law)
        case (LAW_COULOMB)
            mu = coulomb(v, self%mu_s, self%mu_k, self%v_s)
        case (LAW_RECURDYN)
            mu = recurdyn(v, self%mu_s, self%mu_k, self%v_s, self%v_d)
        case default
            mu = proposed_cached(v, self%mu_s, self%mu_k, self%v_s, self%beta, self%ln_a, self%b)
        end select
    end function friction_mu

    !> Haversine step: h0 for x <= x0, h1 for x >= x1, and
    !! h0 + (h1 - h0) (1 - cos(pi (x - x0)/(x1 - x0)))/2 in between (needs x1 > x0).
    elemental function havsin(x, x0, h0, x1, h1) result(h)
        real(dp), intent(in) :: x, x0, h0, x1, h1
        real(dp) :: h
        if (x <= x0) then
            h = h0
        else if (x >= x1) then
            h = h1
        else
            h = h0 + (h1 - h0) * 0.5_dp * (1.0_dp - cos(pi * (x - x0) / (x1 - x0)))
        end if
    end function havsin

    !> Coulomb's law (eq. 1): discontinuous at 0 and at v_s.
    elemental function coulomb(v, mu_s, mu_k, v_s) result(mu)
        real(dp), intent(in) :: v      !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_s   !! static coefficient [-]
        real(dp), intent(in) :: mu_k   !! kinetic coefficient [-]
        real(dp), intent(in) :: v_s    !! static threshold velocity [m/s]
        real(dp) :: mu
        if (v == 0.0_dp) then
            mu = 0.0_dp
        else if (abs(v) < v_s) then
            mu = sign(mu_s, v)
        else
            mu = sign(mu_k, v)
        end if
    end function coulomb

    !> The commercial (RecurDyn/ADAMS-style) law (eqs. 2-3): C1-continuous haversine
    !! steps, mu -> 0 as v -> 0.
    elemental function recurdyn(v, mu_s, mu_k, v_s, v_d) result(mu)
        real(dp), intent(in) :: v      !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_s   !! static coefficient [-]
        real(dp), intent(in) :: mu_k   !! kinetic coefficient [-]
        real(dp), intent(in) :: v_s    !! static threshold velocity [m/s]
        real(dp), intent(in) :: v_d    !! dynamic threshold velocity, > v_s [m/s]
        real(dp) :: mu, s
        s = abs(v)
        if (s < v_s) then
            mu = havsin(s, 0.0_dp, 0.0_dp, v_s, mu_s)
        else
            mu = havsin(s, v_s, mu_s, v_d, mu_k)
        end if
        mu = sign(mu, v)
    end function recurdyn

    !> Continuity offset b of the proposed law: a^-(v_s + b) = mu_s - mu_k [m/s].
    !! For mu_s = mu_k the offset is +huge (the outer branch is mu_k).
    elemental function proposed_b(mu_s, mu_k, v_s, a) result(b)
        real(dp), intent(in) :: mu_s, mu_k, v_s, a
        real(dp) :: b
        if (mu_s > mu_k) then
            b = -log(mu_s - mu_k) / log(a) - v_s
        else
            b = huge(1.0_dp)
        end if
    end function proposed_b

    !> The proposed law of Roh & Yoo (2007) (eq. 5), velocities in m/s.
    elemental function proposed(v, mu_s, mu_k, v_s, beta, a) result(mu)
        real(dp), intent(in) :: v      !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_s   !! static coefficient [-]
        real(dp), intent(in) :: mu_k   !! kinetic coefficient [-]
        real(dp), intent(in) :: v_s    !! static threshold velocity [m/s]
        real(dp), intent(in) :: beta   !! exponent inside v_s, > 0 [-]
        real(dp), intent(in) :: a      !! base outside v_s, > 1 [-]
        real(dp) :: mu
        mu = proposed_cached(v, mu_s, mu_k, v_s, beta, log(a), proposed_b(mu_s, mu_k, v_s, a))
    end function proposed

    !> The proposed law with ln a and b precomputed.
    elemental function proposed_cached(v, mu_s, mu_k, v_s, beta, ln_a, b) result(mu)
        real(dp), intent(in) :: v, mu_s, mu_k, v_s, beta, ln_a, b
        real(dp) :: mu, s
        s = abs(v)
        if (s <= v_s) then
            mu = mu_s * (s / v_s)**beta
        else
            mu = exp(-ln_a * (s + b)) + mu_k
        end if
        mu = sign(mu, v)
    end function proposed_cached

end module stickslip_friction
