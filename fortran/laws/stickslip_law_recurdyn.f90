!> The commercial (RecurDyn/ADAMS-style) law (Yoo & Lee 2008, eqs. 2-3): a C1-continuous
!! haversine step 0 -> mu_s on [0, v_s] and mu_s -> mu_k on [v_s, v_d]; mu -> 0 as v -> 0.
!! No internal state.
module stickslip_law_recurdyn
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law, havsin, havsin_slope
    implicit none
    private

    public :: recurdyn_law, recurdyn

    integer, parameter, public :: SS_BAD_V_D = -104    !! v_d out of range or <= v_s

    !> v_d; its default is 1.5 v_s (RecurDyn's threshold ratio; the paper gives none).
    type(param_spec), parameter, public :: V_D_SPEC = param_spec(name='v_d', default=0.015_dp, &
        unit='m/s', relation='> v_s', default_of='v_s', scale=1.5_dp, code=SS_BAD_V_D, &
        doc='dynamic threshold velocity')

    !> The RecurDyn law; parameters mu_s, mu_k, v_s, v_d.
    type, extends(friction_law) :: recurdyn_law
        real(dp) :: v_d = 0.015_dp      !! dynamic threshold velocity, > v_s [m/s]
    contains
        procedure :: init => recurdyn_init
        !! validate and store the parameters
        procedure :: mu => recurdyn_mu
        !! friction coefficient at a sliding velocity
        procedure :: dmu => recurdyn_dmu
        !! its slope d mu / d v
    end type recurdyn_law

contains

    function recurdyn_init(self, p) result(status)
        class(recurdyn_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_shared(p)
        call param_read(p, V_D_SPEC, self%v_d, status)
        if (status == SS_OK .and. .not. self%v_d > self%v_s) status = SS_BAD_V_D
    end function recurdyn_init

    elemental function recurdyn_mu(self, v) result(mu)
        class(recurdyn_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = recurdyn(v, self%mu_s, self%mu_k, self%v_s, self%v_d)
    end function recurdyn_mu

    elemental function recurdyn_dmu(self, v) result(d)
        class(recurdyn_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m] (even in v)
        real(dp) :: s
        s = abs(v)
        if (s < self%v_s) then
            d = havsin_slope(s, 0.0_dp, 0.0_dp, self%v_s, self%mu_s)
        else
            d = havsin_slope(s, self%v_s, self%mu_s, self%v_d, self%mu_k)
        end if
    end function recurdyn_dmu

    !> The RecurDyn law (eqs. 2-3).
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
        mu = abs(mu)                ! = sign(mu, v) but for a NaN v; see coulomb()
        if (v < 0.0_dp) mu = -mu
    end function recurdyn

end module stickslip_law_recurdyn
