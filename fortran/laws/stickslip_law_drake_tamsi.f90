!> Drake's friction law under its discrete TAMSI solver (Transition-Aware Modified Semi-Implicit,
!! Castro et al. 2019), the regularised Coulomb law of one coefficient,
!!
!!     mu = mu_k s (2 - s)     for s = |v|/v_s < 1,
!!     mu = mu_k               for s >= 1,
!!
!! odd in v: a parabola from 0 with slope 2 mu_k/v_s at rest to mu_k at the stiction tolerance
!! v_s, C1 there. mu_k is Drake's dynamic coefficient: discrete Drake uses no static one, so
!! this law reads mu_k and v_s only (its mu_s is mu_k). The time step does not enter the law.
!!
!! Source: drake, multibody/plant/multibody_plant.cc, `StribeckModel::ModifiedStribeck`
!! (drake 1.x; used by TamsiSolver through the stiction tolerance of MultibodyPlant), and
!! Castro, Qu, Kuppuswamy, Alspach and Sherman, "A Transition-Aware Method for the Simulation
!! of Compliant Contact with Regularized Friction", IEEE RA-L 5(2), 2020. Checked against
!! drake 1.51.1's own runs of the paper's slope box: creep within 0.01 % of this law's balance
!! (`python -m cases.engines`). No internal state.
module stickslip_law_drake_tamsi
    use stickslip_kinds, only: dp
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law
    implicit none
    private

    public :: drake_tamsi_law, drake_tamsi

    !> The Drake TAMSI law; parameters mu_k, v_s (the stiction tolerance).
    type, extends(friction_law) :: drake_tamsi_law
    contains
        procedure :: init => drake_tamsi_init
        !! validate and store the parameters
        procedure :: mu => drake_tamsi_mu
        !! friction coefficient at a sliding velocity
        procedure :: dmu => drake_tamsi_dmu
        !! its slope d mu / d v
    end type drake_tamsi_law

contains

    function drake_tamsi_init(self, p) result(status)
        class(drake_tamsi_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_kinetic(p)
    end function drake_tamsi_init

    elemental function drake_tamsi_mu(self, v) result(mu)
        class(drake_tamsi_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = drake_tamsi(v, self%mu_k, self%v_s)
    end function drake_tamsi_mu

    elemental function drake_tamsi_dmu(self, v) result(d)
        class(drake_tamsi_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m] (even in v)
        real(dp) :: s
        s = abs(v) / self%v_s
        d = 0.0_dp
        if (s < 1.0_dp) d = 2.0_dp * self%mu_k * (1.0_dp - s) / self%v_s
    end function drake_tamsi_dmu

    !> TAMSI's coefficient at v (see the module).
    elemental function drake_tamsi(v, mu_k, v_s) result(mu)
        real(dp), intent(in) :: v      !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_k   !! dynamic (kinetic) coefficient [-]
        real(dp), intent(in) :: v_s    !! stiction tolerance, > 0 [m/s]
        real(dp) :: mu                 !! friction coefficient [-]
        real(dp) :: s
        s = abs(v) / v_s
        if (s >= 1.0_dp) then
            mu = mu_k
        else
            mu = mu_k * s * (2.0_dp - s)   ! (a NaN v gets here and stays NaN)
        end if
        mu = abs(mu)
        if (v < 0.0_dp) mu = -mu
    end function drake_tamsi

end module stickslip_law_drake_tamsi
