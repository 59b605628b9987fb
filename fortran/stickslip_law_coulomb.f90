!> Coulomb's law (Yoo & Lee 2008, eq. 1): mu_s sign(v) for 0 < |v| < v_s, mu_k sign(v)
!! beyond, 0 at v = 0. Discontinuous at 0 and at v_s; no internal state.
module stickslip_law_coulomb
    use stickslip_kinds, only: dp
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law
    implicit none
    private

    public :: coulomb_law, coulomb

    !> The Coulomb law; parameters mu_s, mu_k, v_s.
    type, extends(friction_law) :: coulomb_law
    contains
        procedure :: init => coulomb_init
        !! validate and store the parameters
        procedure :: mu => coulomb_mu
        !! friction coefficient at a sliding velocity
        procedure :: dmu => coulomb_dmu
        !! its slope d mu / d v
    end type coulomb_law

contains

    function coulomb_init(self, p) result(status)
        class(coulomb_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_shared(p)
    end function coulomb_init

    elemental function coulomb_mu(self, v) result(mu)
        class(coulomb_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = coulomb(v, self%mu_s, self%mu_k, self%v_s)
    end function coulomb_mu

    !> Zero: the law is piecewise constant (its jumps have no derivative).
    elemental function coulomb_dmu(self, v) result(d)
        class(coulomb_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m]
        d = 0.0_dp
    end function coulomb_dmu

    !> Coulomb's law (eq. 1).
    elemental function coulomb(v, mu_s, mu_k, v_s) result(mu)
        real(dp), intent(in) :: v      !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_s   !! static coefficient [-]
        real(dp), intent(in) :: mu_k   !! kinetic coefficient [-]
        real(dp), intent(in) :: v_s    !! static threshold velocity [m/s]
        real(dp) :: mu                 !! friction coefficient [-]
        if (v == 0.0_dp) then
            mu = 0.0_dp
        else
            ! = sign(mu_s or mu_k, v) for v /= 0, written without sign(): gfortran spills the
            ! operand of an inlined sign() and reloads it wider (a store-forwarding stall
            ! that cost a third of an RK4 step on the belt).
            mu = abs(mu_k)
            if (abs(v) < v_s) mu = abs(mu_s)
            if (v < 0.0_dp) mu = -mu
        end if
    end function coulomb

end module stickslip_law_coulomb
