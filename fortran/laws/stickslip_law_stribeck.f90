!> The Stribeck law: a static peak mu_s decaying to the kinetic level mu_k with the shape
!! exponent delta, plus viscous friction, made continuous at rest by a tanh ramp:
!!
!!     mu(v) = g(|v|) tanh(v / v_eps) + c_v v,   g(s) = mu_k + (mu_s - mu_k) exp(-(s/v_s)^delta)
!!
!! Velocities in m/s, c_v in s/m. The regularisation multiplies the Stribeck curve g by
!! tanh(v/v_eps): smooth and exactly odd, with a finite slope g(0)/v_eps + c_v at rest.
!! It is a regularised (creeping) law: under any holding coefficient 0 < mu_hold < mu_s it
!! slides at the speed v* where mu(v*) = mu_hold (on the 10 degree slope with the defaults,
!! v* = 0.55 mm/s, about v_eps atanh(mu_hold/mu_s)). v_eps defaults to v_s/10: the
!! regularised curve still peaks within 2 % of mu_s (0.344 at 3.1 v_eps), and the creep stays
!! below that of the paper's laws on the slope (proposed 1.3 mm/s, RecurDyn 5.0 mm/s). A smaller
!! v_eps creeps proportionally less but stiffens the law at rest (slope mu_s/v_eps): RK4 on the
!! slope is accurate only for h below about 2.785 / (g cos(theta) mu'(v*)) = 1.1e-3 s at the
!! default, proportional to v_eps.
!! No internal state.
!!
!! `stribeck_curve` (g above, kept in `stickslip_friction` with the set-valued laws) is public: the bristle laws (`stickslip_law_lugre`,
!! `stickslip_law_elastoplastic`) use it with delta = 2 as their steady-state force.
module stickslip_law_stribeck
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law, contact_law, CONTACT_STRIBECK, stribeck_curve, stribeck_curve_slope
    implicit none
    private

    public :: stribeck_law, stribeck_curve, stribeck_curve_slope

    integer, parameter, public :: SS_BAD_DELTA = -140   !! delta out of range
    integer, parameter, public :: SS_BAD_C_V = -141     !! c_v out of range
    integer, parameter, public :: SS_BAD_V_EPS = -142   !! v_eps out of range

    !> Specification of the parameter delta (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: DELTA_SPEC = param_spec(name='delta', default=2.0_dp, &
        lo=0.0_dp, lo_open=.true., code=SS_BAD_DELTA, doc='Stribeck shape exponent')
    !> Specification of the parameter c_v (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: C_V_SPEC = param_spec(name='c_v', default=0.0_dp, &
        unit='s/m', lo=0.0_dp, code=SS_BAD_C_V, doc='viscous coefficient (mu per m/s)')
    !> v_eps defaults to v_s/10 (see the module notes).
    type(param_spec), parameter, public :: V_EPS_SPEC = param_spec(name='v_eps', default=0.001_dp, &
        unit='m/s', lo=0.0_dp, lo_open=.true., default_of='v_s', scale=0.1_dp, code=SS_BAD_V_EPS, &
        doc='regularisation velocity of the tanh ramp at rest')

    !> The Stribeck law; parameters mu_s, mu_k, v_s, delta, c_v, v_eps.
    type, extends(friction_law) :: stribeck_law
        real(dp) :: delta = 2.0_dp      !! shape exponent, > 0 [-]
        real(dp) :: c_v = 0.0_dp        !! viscous coefficient, >= 0 [s/m]
        real(dp) :: v_eps = 0.001_dp    !! regularisation velocity, > 0 [m/s]
    contains
        !> Read and check the parameters; SS_OK or the code naming the bad one.
        procedure :: init => stribeck_init
        !> mu(v) [-]; for a law with states, its steady-state curve.
        procedure :: mu => stribeck_mu
        !> d mu / d v [s/m].
        procedure :: dmu => stribeck_dmu
        !> Its set-valued counterpart: the curve g without the ramp (`contact_law`).
        procedure :: set_valued => stribeck_set_valued
    end type stribeck_law

contains

    function stribeck_init(self, p) result(status)
        class(stribeck_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_shared(p)
        call param_read(p, DELTA_SPEC, self%delta, status)
        call param_read(p, C_V_SPEC, self%c_v, status)
        call param_read(p, V_EPS_SPEC, self%v_eps, status)
    end function stribeck_init

    elemental function stribeck_mu(self, v) result(mu)
        class(stribeck_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        real(dp) :: s
        s = abs(v)
        mu = stribeck_curve(s, self%mu_s, self%mu_k, self%v_s, self%delta) * tanh(s / self%v_eps) + &
             self%c_v * s
        mu = sign(mu, v)
    end function stribeck_mu

    !> d mu/d v = g'(|v|) tanh(|v|/v_eps) + g(|v|) / (v_eps cosh^2(v/v_eps)) + c_v, even in v,
    !! finite everywhere (g' tanh -> 0 at rest even for delta < 1).
    elemental function stribeck_dmu(self, v) result(d)
        class(stribeck_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m]
        real(dp) :: s, th
        s = abs(v)
        th = tanh(s / self%v_eps)
        d = stribeck_curve(s, self%mu_s, self%mu_k, self%v_s, self%delta) * (1.0_dp - th**2) / self%v_eps &
            + self%c_v
        if (s > 0.0_dp) d = d + stribeck_curve_slope(s, self%mu_s, self%mu_k, self%v_s, self%delta) * th
    end function stribeck_dmu

    !> The set-valued counterpart: the Stribeck curve without the tanh ramp, plus c_v s.
    pure subroutine stribeck_set_valued(self, cl, status)
        class(stribeck_law), intent(in) :: self
        type(contact_law), intent(out) :: cl    !! kind CONTACT_STRIBECK
        integer, intent(out) :: status          !! SS_OK
        cl = contact_law(kind=CONTACT_STRIBECK, mu_s=self%mu_s, mu_k=self%mu_k, v_s=self%v_s, &
                         delta=self%delta, c_v=self%c_v)
        status = SS_OK
    end subroutine stribeck_set_valued

end module stickslip_law_stribeck
