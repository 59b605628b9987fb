!> The two scenes of Yoo & Lee (2008) as first-order systems, state y = (x [m], v [m/s]).
!!
!! - `slope_scene`: a box on a plane inclined theta, x along the slope (down positive),
!!   x'' = g sin(theta) - mu(x') g cos(theta). The mass cancels, so the scene has none.
!! - `belt_scene`: a mass m on a belt moving at v_b, tied to a wall by a spring k,
!!   m x'' = -k x + mu(v_b - x') m g.
module stickslip_scenes
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_M, SS_BAD_G, SS_BAD_THETA, SS_BAD_K, SS_BAD_V_B
    use stickslip_friction, only: friction_law, friction_mu
    use stickslip_ode, only: ode_system
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: slope_scene, belt_scene, slope_init, belt_init

    integer, parameter, public :: SCENE_SLOPE = 1   !! code of the box on a slope
    integer, parameter, public :: SCENE_BELT = 2    !! code of the spring-mass on a belt

    real(dp), parameter :: deg = acos(-1.0_dp) / 180.0_dp

    !> Box on an inclined plane.
    type, extends(ode_system) :: slope_scene
        type(friction_law) :: law     !! friction between box and plane
        real(dp) :: g_sin = 0.0_dp    !! g sin(theta) [m/s^2]
        real(dp) :: g_cos = 0.0_dp    !! g cos(theta) [m/s^2]
    contains
        procedure :: rhs => slope_rhs
    end type slope_scene

    !> Spring-mass on a moving belt.
    type, extends(ode_system) :: belt_scene
        type(friction_law) :: law     !! friction between mass and belt
        real(dp) :: k_m = 0.0_dp      !! k / m [1/s^2]
        real(dp) :: g = 9.81_dp       !! gravity [m/s^2]
        real(dp) :: v_b = 1.5_dp      !! belt speed [m/s]
    contains
        procedure :: rhs => belt_rhs
    end type belt_scene

contains

    !> Fill a slope scene; returns SS_OK or the code of the bad parameter.
    function slope_init(self, law, g, theta_deg) result(status)
        type(slope_scene), intent(out) :: self
        type(friction_law), intent(in) :: law   !! a validated friction law
        real(dp), intent(in) :: g               !! gravity, >= 0 [m/s^2]
        real(dp), intent(in) :: theta_deg       !! inclination, in [-90, 90] [deg]
        integer :: status
        status = SS_OK
        if (.not. ieee_is_finite(g) .or. g < 0.0_dp) then
            status = SS_BAD_G
        else if (.not. ieee_is_finite(theta_deg) .or. abs(theta_deg) > 90.0_dp) then
            status = SS_BAD_THETA
        end if
        if (status /= SS_OK) return
        self%law = law
        self%g_sin = g * sin(theta_deg * deg)
        self%g_cos = g * cos(theta_deg * deg)
    end function slope_init

    !> Fill a belt scene; returns SS_OK or the code of the bad parameter.
    function belt_init(self, law, m, g, k, v_b) result(status)
        type(belt_scene), intent(out) :: self
        type(friction_law), intent(in) :: law   !! a validated friction law
        real(dp), intent(in) :: m               !! mass, > 0 [kg]
        real(dp), intent(in) :: g               !! gravity, >= 0 [m/s^2]
        real(dp), intent(in) :: k               !! spring stiffness, >= 0 [N/m]
        real(dp), intent(in) :: v_b             !! belt speed [m/s]
        integer :: status
        status = SS_OK
        if (.not. ieee_is_finite(m) .or. m <= 0.0_dp) then
            status = SS_BAD_M
        else if (.not. ieee_is_finite(g) .or. g < 0.0_dp) then
            status = SS_BAD_G
        else if (.not. ieee_is_finite(k) .or. k < 0.0_dp) then
            status = SS_BAD_K
        else if (.not. ieee_is_finite(v_b)) then
            status = SS_BAD_V_B
        end if
        if (status /= SS_OK) return
        self%law = law
        self%k_m = k / m
        self%g = g
        self%v_b = v_b
    end function belt_init

    subroutine slope_rhs(self, t, y, dydt)
        class(slope_scene), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s] (unused: autonomous)
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s])
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2])
        dydt(1) = y(2)
        dydt(2) = self%g_sin - friction_mu(self%law, y(2)) * self%g_cos
    end subroutine slope_rhs

    subroutine belt_rhs(self, t, y, dydt)
        class(belt_scene), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s] (unused: autonomous)
        real(dp), intent(in)  :: y(:)       !! (x [m], v [m/s])
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], acceleration [m/s^2])
        dydt(1) = y(2)
        dydt(2) = -self%k_m * y(1) + friction_mu(self%law, self%v_b - y(2)) * self%g
    end subroutine belt_rhs

end module stickslip_scenes
