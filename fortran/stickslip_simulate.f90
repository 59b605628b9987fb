!> One entry point that runs a scene with a friction law and an integrator chosen by
!! integer codes: what the Python and C layers call, so that neither repeats the set-up.
module stickslip_simulate
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_SCENE, SS_BAD_METHOD
    use stickslip_friction, only: friction_law, friction_law_init
    use stickslip_scenes, only: slope_scene, belt_scene, slope_init, belt_init, SCENE_SLOPE, SCENE_BELT
    use stickslip_ode, only: ode_system, ode_stats
    use stickslip_rk4, only: rk4_integrate
    use stickslip_dopri5, only: dopri5_options, dopri5_integrate
    implicit none
    private

    public :: scene_params, scene_params_from, simulate, make_system

    integer, parameter, public :: METHOD_RK4 = 1      !! classical RK4, fixed step
    integer, parameter, public :: METHOD_DOPRI5 = 2   !! Dormand-Prince 5(4), adaptive

    !> Physical parameters of both scenes and all laws, with the paper's values (Table 1)
    !! and our defaults where the paper is silent (v_d = 1.5 v_s, theta = 10 deg).
    type :: scene_params
        real(dp) :: mu_s = 0.35_dp          !! static coefficient [-]
        real(dp) :: mu_k = 0.30_dp          !! kinetic coefficient [-]
        real(dp) :: v_s = 0.01_dp           !! static threshold velocity [m/s]
        real(dp) :: v_d = 0.015_dp          !! dynamic threshold velocity (recurdyn) [m/s]
        real(dp) :: beta = 1.0_dp / 3.0_dp  !! exponent of the proposed law [-]
        real(dp) :: a = 1.5_dp              !! base of the proposed law [-]
        real(dp) :: m = 10.0_dp             !! mass (belt) [kg]
        real(dp) :: g = 9.81_dp             !! gravity [m/s^2]
        real(dp) :: theta_deg = 10.0_dp     !! slope inclination [deg]
        real(dp) :: k = 300.0_dp            !! spring stiffness (belt) [N/m]
        real(dp) :: v_b = 1.5_dp            !! belt speed [m/s]
    end type scene_params

contains

    !> Parameters from an array in the order (mu_s, mu_k, v_s, v_d, beta, a, m, g, theta_deg,
    !! k, v_b): the layout the Python wrapper passes.
    pure function scene_params_from(p) result(sp)
        real(dp), intent(in) :: p(11)   !! parameters in the order above, SI units
        type(scene_params) :: sp
        sp = scene_params(mu_s=p(1), mu_k=p(2), v_s=p(3), v_d=p(4), beta=p(5), a=p(6), m=p(7), &
                          g=p(8), theta_deg=p(9), k=p(10), v_b=p(11))
    end function scene_params_from

    !> Build the right-hand side of a scene with a law; returns SS_OK or a bad-input code.
    function make_system(scene, law, p, sys) result(status)
        integer, intent(in) :: scene                       !! SCENE_SLOPE or SCENE_BELT
        integer, intent(in) :: law                         !! LAW_COULOMB, LAW_RECURDYN or LAW_PROPOSED
        type(scene_params), intent(in) :: p                !! parameters
        class(ode_system), allocatable, intent(out) :: sys !! the scene, ready to integrate
        integer :: status
        type(friction_law) :: fl
        type(slope_scene) :: slope
        type(belt_scene) :: belt

        if (scene /= SCENE_SLOPE .and. scene /= SCENE_BELT) then
            status = SS_BAD_SCENE
            return
        end if
        status = friction_law_init(fl, law, p%mu_s, p%mu_k, p%v_s, p%v_d, p%beta, p%a)
        if (status /= SS_OK) return
        if (scene == SCENE_SLOPE) then
            status = slope_init(slope, fl, p%g, p%theta_deg)
            if (status == SS_OK) allocate(sys, source=slope)
        else
            status = belt_init(belt, fl, p%m, p%g, p%k, p%v_b)
            if (status == SS_OK) allocate(sys, source=belt)
        end if
    end function make_system

    !> Simulate a scene from (x0, v0) at t = 0 to t_end.
    !! RK4 uses h, opts%max_steps and opts%every_step; DOPRI5 uses rtol, atol and opts.
    !! Output and status as for rk4_integrate / dopri5_integrate, in stats.
    subroutine simulate(scene, law, method, p, x0, v0, t_end, h, rtol, atol, opts, t_out, y_out, stats)
        integer, intent(in) :: scene                !! SCENE_SLOPE or SCENE_BELT
        integer, intent(in) :: law                  !! LAW_COULOMB, LAW_RECURDYN or LAW_PROPOSED
        integer, intent(in) :: method               !! METHOD_RK4 or METHOD_DOPRI5
        type(scene_params), intent(in) :: p         !! physical parameters
        real(dp), intent(in) :: x0                  !! initial displacement [m]
        real(dp), intent(in) :: v0                  !! initial velocity [m/s]
        real(dp), intent(in) :: t_end               !! final time [s]
        real(dp), intent(in) :: h                   !! RK4 step size [s]
        real(dp), intent(in) :: rtol(:)             !! DOPRI5 relative tolerance(s)
        real(dp), intent(in) :: atol(:)             !! DOPRI5 absolute tolerance(s)
        type(dopri5_options), intent(in) :: opts    !! DOPRI5 controls; max_steps, every_step for both
        real(dp), intent(inout) :: t_out(:)         !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)      !! (2, size(t_out)) states (x, v)
        type(ode_stats), intent(out) :: stats       !! counters and status
        class(ode_system), allocatable :: sys

        stats%status = make_system(scene, law, p, sys)
        if (stats%status /= SS_OK) return
        select case (method)
        case (METHOD_RK4)
            call rk4_integrate(sys, 0.0_dp, [x0, v0], t_end, h, t_out, y_out, stats, &
                               every_step=opts%every_step, max_steps=opts%max_steps)
        case (METHOD_DOPRI5)
            call dopri5_integrate(sys, 0.0_dp, [x0, v0], t_end, rtol, atol, opts, t_out, y_out, stats)
        case default
            stats%status = SS_BAD_METHOD
        end select
    end subroutine simulate

end module stickslip_simulate
