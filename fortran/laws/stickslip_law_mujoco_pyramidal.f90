!> MuJoCo's soft-contact friction with its default pyramidal cone, inside the cone: viscous,
!! with its slope bent where one edge of the pyramid stops pushing,
!!
!!     mu = mu_k s                  for s = |v|/v_s <= 1/2,
!!     mu = mu_k (1 + s)/3          for 1/2 < s <= 2,
!!     mu = mu_k                    for s > 2,
!!
!! odd in v (continuous, its slope mu_k/v_s at rest falling to a third beyond s = 1/2). One
!! coefficient mu_k (its mu_s is mu_k; mu_s is not read).
!!
!! Derivation. A contact of condim 3 has four pyramid edges n +- mu t1, n +- mu t2, each a
!! constraint row whose force is D (a_ref - a) clamped at 0, D = 1/R, a_ref = -B (edge speed)
!! - K d (penetration). In a steady slip along t1 at speed v under the normal load f_n, the
!! edges along t1 carry p -+ q with q = B mu v/R; while q <= p all four push: f_n = 4 p and the
!! friction is 2 mu q (mu_k s with s = 2 q/f_n). Beyond (s > 1/2) the edge against the slip
!! drops out: f_n = 3 p + q, friction mu (p + q) = mu f_n (1 + s)/3, up to s = 2 where only
!! the leading edge is left and the friction is mu f_n. The edge rows' R is
!! 2 (mu^2/impratio) (1 - d)/d (1 + mu^2) A (MuJoCo's diagonal approximation of an edge of
!! the pyramid), B = 2/(d_max t_c), t_c = max(solref(1), 2 timestep), so
!! v_s = mu f_n (1 - d)(1 + mu^2) A/(d B impratio) with d the impedance at the penetration
!! (solimp) and A the body's translational inverse weight (1/m for a free body). The law
!! takes d at the penetration of the four-edge regime; beyond s = 1/2 the penetration changes
!! by a few parts per million of solimp's width and with it d, which the law neglects (it
!! moves mu by less than 3e-5 mu_k at MuJoCo's defaults on the paper's box).
!!
!! Source: mujoco, src/engine/engine_core_constraint.c (`mj_makeImpedance`, `mj_diagApprox`,
!! `getimpedance`, the pyramidal rows of `mj_instantiateContact`), mujoco 3.x and 4.0.0;
!! `stickslip.engines` derives v_s from the settings. Checked against mujoco 4.0.0's own runs
!! of the paper's slope box (`python -m cases.engines`). No internal state.
module stickslip_law_mujoco_pyramidal
    use stickslip_kinds, only: dp
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law
    implicit none
    private

    public :: mujoco_pyramidal_law, mujoco_pyramidal

    !> The MuJoCo pyramidal-cone law; parameters mu_k, v_s (twice the speed of the bend).
    type, extends(friction_law) :: mujoco_pyramidal_law
    contains
        procedure :: init => mujoco_pyramidal_init
        !! validate and store the parameters
        procedure :: mu => mujoco_pyramidal_mu
        !! friction coefficient at a sliding velocity
        procedure :: dmu => mujoco_pyramidal_dmu
        !! its slope d mu / d v
    end type mujoco_pyramidal_law

contains

    function mujoco_pyramidal_init(self, p) result(status)
        class(mujoco_pyramidal_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_kinetic(p)
    end function mujoco_pyramidal_init

    elemental function mujoco_pyramidal_mu(self, v) result(mu)
        class(mujoco_pyramidal_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = mujoco_pyramidal(v, self%mu_k, self%v_s)
    end function mujoco_pyramidal_mu

    elemental function mujoco_pyramidal_dmu(self, v) result(d)
        class(mujoco_pyramidal_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m] (even in v)
        real(dp) :: s
        s = abs(v) / self%v_s
        if (s <= 0.5_dp) then
            d = self%mu_k / self%v_s
        else if (s <= 2.0_dp) then
            d = self%mu_k / (3.0_dp * self%v_s)
        else
            d = 0.0_dp
        end if
    end function mujoco_pyramidal_dmu

    !> MuJoCo's pyramidal-cone coefficient at v (see the module).
    elemental function mujoco_pyramidal(v, mu_k, v_s) result(mu)
        real(dp), intent(in) :: v      !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_k   !! the contact's friction coefficient [-]
        real(dp), intent(in) :: v_s    !! twice the speed at which the slope bends, > 0 [m/s]
        real(dp) :: mu                 !! friction coefficient [-]
        real(dp) :: s
        s = abs(v) / v_s
        if (s > 2.0_dp) then
            mu = mu_k
        else if (s > 0.5_dp) then
            mu = mu_k * (1.0_dp + s) / 3.0_dp
        else
            mu = mu_k * s              ! (a NaN v gets here and stays NaN)
        end if
        if (v < 0.0_dp) mu = -mu
    end function mujoco_pyramidal

end module stickslip_law_mujoco_pyramidal
