!> Viscous friction capped at Coulomb's level, the friction of a soft contact with one
!! coefficient inside a round cone,
!!
!!     mu = mu_k min(|v|/v_s, 1) sign(v),
!!
!! a damper of coefficient mu_k N/v_s [N s/m] until the force reaches mu_k N at v = v_s, then
!! Coulomb's kinetic level. There is no static level (its mu_s is mu_k; mu_s is not read). Two
!! physics engines use it, each with its own v_s:
!!
!! - Newton's (and warp.sim's) semi-implicit Euler solver, per contact point:
!!   min(k_f |v_t|, mu f_n), so v_s = mu f_n / k_f with k_f [N s/m] the mean of the two shapes'
!!   `kf` (default 1000 N s/m). Source: newton 1.8, newton/_src/solvers/semi_implicit/
!!   kernels_contact.py (`eval_body_contact`); warp.sim, `eval_rigid_contacts`.
!! - MuJoCo's soft contact with the elliptic cone, inside the cone: the friction rows give the
!!   force D (a_ref - a) with D = 1/R and a_ref = -B v, so a steady slip feels the damper
!!   B/R: B = 2/(d_max t_c) with t_c = max(solref(1), 2 timestep) (or -solref(2)/d_max in the
!!   direct format), R = (1 - d)/d A/impratio with d the impedance at the contact's
!!   penetration (solimp) and A the body's translational inverse weight (1/m for a free body):
!!   v_s = mu f_n (1 - d) A/(d B impratio). Source: mujoco, src/engine/engine_core_constraint.c
!!   (`mj_makeImpedance`, `mj_diagApprox`, `getimpedance`), mujoco 3.x and 4.0.0.
!!
!! `stickslip.engines` derives v_s from the engines' settings (`engine_mu`, `engine_creep`);
!! both were checked against the engines' own runs of the paper's slope box (MuJoCo 4.0.0 to
!! 1e-4, Newton 1.8.0 to 5e-4 at a stable step: `python -m cases.engines`). No internal state.
module stickslip_law_capped_viscous
    use stickslip_kinds, only: dp
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law
    implicit none
    private

    public :: capped_viscous_law, capped_viscous

    !> The capped viscous law; parameters mu_k, v_s (the speed at which the cap is reached).
    type, extends(friction_law) :: capped_viscous_law
    contains
        procedure :: init => capped_viscous_init
        !! validate and store the parameters
        procedure :: mu => capped_viscous_mu
        !! friction coefficient at a sliding velocity
        procedure :: dmu => capped_viscous_dmu
        !! its slope d mu / d v
    end type capped_viscous_law

contains

    function capped_viscous_init(self, p) result(status)
        class(capped_viscous_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_kinetic(p)
    end function capped_viscous_init

    elemental function capped_viscous_mu(self, v) result(mu)
        class(capped_viscous_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = capped_viscous(v, self%mu_k, self%v_s)
    end function capped_viscous_mu

    elemental function capped_viscous_dmu(self, v) result(d)
        class(capped_viscous_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m] (even in v)
        d = 0.0_dp
        if (abs(v) < self%v_s) d = self%mu_k / self%v_s
    end function capped_viscous_dmu

    !> mu_k min(|v|/v_s, 1) sign(v).
    elemental function capped_viscous(v, mu_k, v_s) result(mu)
        real(dp), intent(in) :: v      !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_k   !! kinetic coefficient, the cap [-]
        real(dp), intent(in) :: v_s    !! speed at which the cap is reached, > 0 [m/s]
        real(dp) :: mu                 !! friction coefficient [-]
        if (abs(v) >= v_s) then
            mu = mu_k
        else
            mu = mu_k * abs(v) / v_s   ! (a NaN v gets here and stays NaN)
        end if
        if (v < 0.0_dp) mu = -mu
    end function capped_viscous

end module stickslip_law_capped_viscous
