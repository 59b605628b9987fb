!> The law proposed by Roh & Yoo (2007) (Yoo & Lee 2008, eq. 5): mu_s (|v|/v_s)^beta
!! inside v_s, a^-(|v| + b) + mu_k outside, with b = -ln(mu_s - mu_k)/ln(a) - v_s so that
!! the two branches meet at v_s. Velocities in m/s. No internal state.
!!
!! Derivative at rest: with beta < 1 the slope of mu is infinite at v = 0. `dmu` returns
!! the slope at |v| = max(|v|, 1e-6 v_s) instead, a finite value (about 1e4 mu_s/v_s at
!! beta = 1/3) that keeps a Newton iteration's matrix finite while still making the law
!! the stiffest term of the Jacobian near rest.
module stickslip_law_proposed
    use stickslip_kinds, only: dp
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law
    implicit none
    private

    public :: proposed_law, proposed, proposed_b

    integer, parameter, public :: SS_BAD_BETA = -105   !! beta out of range
    integer, parameter, public :: SS_BAD_A = -106      !! a out of range

    type(param_spec), parameter, public :: BETA_SPEC = param_spec(name='beta', default=1.0_dp/3.0_dp, &
        lo=0.0_dp, lo_open=.true., code=SS_BAD_BETA, doc='exponent inside v_s')
    !! exponent beta of the proposed law, > 0 [-]
    type(param_spec), parameter, public :: A_SPEC = param_spec(name='a', default=1.5_dp, &
        lo=1.0_dp, lo_open=.true., code=SS_BAD_A, doc='base of the decay outside v_s')
    !! base a of the proposed law's decay, > 1 [-]

    !> Smallest |v| / v_s at which `dmu` evaluates the slope (see the module notes).
    real(dp), parameter :: DMU_FLOOR = 1.0e-6_dp

    !> The proposed law; parameters mu_s, mu_k, v_s, beta, a; ln a and b cached.
    type, extends(friction_law) :: proposed_law
        real(dp) :: beta = 1.0_dp / 3.0_dp  !! exponent inside v_s, > 0 [-]
        real(dp) :: a = 1.5_dp              !! base outside v_s, > 1 [-]
        real(dp) :: ln_a = 0.0_dp           !! cached ln(a)
        real(dp) :: b = 0.0_dp              !! cached continuity offset [m/s]
    contains
        procedure :: init => proposed_init
        !! validate and store the parameters (caches ln a and b)
        procedure :: mu => proposed_mu
        !! friction coefficient at a sliding velocity
        procedure :: dmu => proposed_dmu
        !! its slope d mu / d v
    end type proposed_law

contains

    function proposed_init(self, p) result(status)
        class(proposed_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_shared(p)
        call param_read(p, BETA_SPEC, self%beta, status)
        call param_read(p, A_SPEC, self%a, status)
        self%ln_a = log(max(self%a, tiny(1.0_dp)))
        self%b = proposed_b(self%mu_s, self%mu_k, self%v_s, self%a)
    end function proposed_init

    elemental function proposed_mu(self, v) result(mu)
        class(proposed_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = proposed_cached(v, self%mu_s, self%mu_k, self%v_s, self%beta, self%ln_a, self%b)
    end function proposed_mu

    elemental function proposed_dmu(self, v) result(d)
        class(proposed_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m] (even in v), finite at 0
        real(dp) :: s
        s = abs(v)
        if (s <= self%v_s) then
            s = max(s, DMU_FLOOR * self%v_s)
            d = self%mu_s * self%beta / self%v_s * (s / self%v_s)**(self%beta - 1.0_dp)
        else
            d = -self%ln_a * exp(-self%ln_a * (s + self%b))
        end if
    end function proposed_dmu

    !> Continuity offset b of the proposed law: a^-(v_s + b) = mu_s - mu_k [m/s].
    !! For mu_s = mu_k the offset is +huge (the outer branch is mu_k).
    elemental function proposed_b(mu_s, mu_k, v_s, a) result(b)
        real(dp), intent(in) :: mu_s, mu_k, v_s, a
        !! static and kinetic coefficients [-], v_s [m/s], base a [-]
        real(dp) :: b
        if (mu_s > mu_k .and. a > 1.0_dp) then
            b = -log(mu_s - mu_k) / log(a) - v_s
        else
            b = huge(1.0_dp)
        end if
    end function proposed_b

    !> The proposed law (eq. 5).
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

end module stickslip_law_proposed
