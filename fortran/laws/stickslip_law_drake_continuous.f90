!> Drake's friction law in continuous mode (MultibodyPlant with a continuous time step, point
!! contact): the Stribeck approximation of Coulomb friction,
!!
!!     mu = mu_s step5(s)                                 for s = |v|/v_s < 1,
!!     mu = mu_s - (mu_s - mu_k) step5((s - 1)/2)          for 1 <= s < 3,
!!     mu = mu_k                                          for s >= 3,
!!
!! odd in v, with step5(x) = x^3 (10 - 15 x + 6 x^2), the quintic step from 0 at x = 0 to 1 at
!! x = 1 with zero first and second derivatives at both ends. v_s is Drake's stiction
!! tolerance (`MultibodyPlant::set_stiction_tolerance`, default 1e-4 m/s there; the library's
!! v_s default, 0.01 m/s, applies here unless given), mu_s and mu_k Drake's static and dynamic
!! coefficients. This is the paper's haversine family (`recurdyn`) with a C2 quintic step in
!! place of the half cosine, and the fall to mu_k over [v_s, 3 v_s].
!!
!! Source: drake, multibody/plant/multibody_plant.cc, `StribeckModel::ComputeFrictionCoefficient`
!! and `step5` (the law is unchanged from 2019 to drake 1.51.1), and Drake's documentation of
!! contact, "Stribeck approximation" (multibody/plant/contact_model_doxygen.h). Checked against
!! drake 1.51.1's own runs of the paper's slope box: creep within 0.03 % of this law's balance
!! (`python -m cases.engines`). No internal state.
module stickslip_law_drake_continuous
    use stickslip_kinds, only: dp
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law
    implicit none
    private

    public :: drake_continuous_law, drake_continuous, step5

    !> The Drake continuous-mode law; parameters mu_s, mu_k, v_s (the stiction tolerance).
    type, extends(friction_law) :: drake_continuous_law
    contains
        procedure :: init => drake_continuous_init
        !! validate and store the parameters
        procedure :: mu => drake_continuous_mu
        !! friction coefficient at a sliding velocity
        procedure :: dmu => drake_continuous_dmu
        !! its slope d mu / d v
    end type drake_continuous_law

contains

    function drake_continuous_init(self, p) result(status)
        class(drake_continuous_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_shared(p)
    end function drake_continuous_init

    elemental function drake_continuous_mu(self, v) result(mu)
        class(drake_continuous_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = drake_continuous(v, self%mu_s, self%mu_k, self%v_s)
    end function drake_continuous_mu

    elemental function drake_continuous_dmu(self, v) result(d)
        class(drake_continuous_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m] (even in v)
        real(dp) :: s
        s = abs(v) / self%v_s
        if (s < 1.0_dp) then
            d = self%mu_s * step5_slope(s) / self%v_s
        else if (s < 3.0_dp) then
            d = -(self%mu_s - self%mu_k) * step5_slope(0.5_dp * (s - 1.0_dp)) / (2.0_dp * self%v_s)
        else
            d = 0.0_dp
        end if
    end function drake_continuous_dmu

    !> Drake's continuous-mode coefficient at v (see the module).
    elemental function drake_continuous(v, mu_s, mu_k, v_s) result(mu)
        real(dp), intent(in) :: v      !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_s   !! static coefficient [-]
        real(dp), intent(in) :: mu_k   !! dynamic (kinetic) coefficient [-]
        real(dp), intent(in) :: v_s    !! stiction tolerance, > 0 [m/s]
        real(dp) :: mu                 !! friction coefficient [-]
        real(dp) :: s
        s = abs(v) / v_s
        if (s >= 3.0_dp) then
            mu = mu_k
        else if (s >= 1.0_dp) then
            mu = mu_s - (mu_s - mu_k) * step5(0.5_dp * (s - 1.0_dp))
        else
            mu = mu_s * step5(s)     ! (a NaN v gets here and stays NaN)
        end if
        mu = abs(mu)                ! = sign(mu, v) but for a NaN v; see coulomb()
        if (v < 0.0_dp) mu = -mu
    end function drake_continuous

    !> Drake's quintic step x^3 (10 - 15 x + 6 x^2) on [0, 1]: 0 at 0, 1 at 1, zero first and
    !! second derivatives at both ends (the argument must lie in [0, 1]).
    elemental function step5(x) result(y)
        real(dp), intent(in) :: x      !! abscissa in [0, 1] [-]
        real(dp) :: y                  !! step value [-]
        y = x**3 * (10.0_dp + x * (6.0_dp * x - 15.0_dp))
    end function step5

    !> d step5 / dx = 30 x^2 (1 - x)^2.
    elemental function step5_slope(x) result(d)
        real(dp), intent(in) :: x      !! abscissa in [0, 1] [-]
        real(dp) :: d                  !! slope [-]
        d = 30.0_dp * (x * (1.0_dp - x))**2
    end function step5_slope

end module stickslip_law_drake_continuous
