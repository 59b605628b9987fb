!> The LuGre law (Canudas de Wit, Olsson, Astrom & Lischinsky, IEEE TAC 40(3), 1995) in
!! coefficient form, with the bristle deflection z [m] as its one internal state:
!!
!!     mu = sigma0 z + sigma1 z' + sigma2 v,    z' = v - sigma0 |v| z / g(v),
!!     g(v) = mu_k + (mu_s - mu_k) exp(-(v/v_s)^2)
!!
!! Velocities in m/s; sigma0 in 1/m, sigma1 and sigma2 in s/m (the paper's N/m and N s/m
!! divided by a normal force). Steady state (z' = 0): z = g(v) sign(v)/sigma0 and
!! mu = g(v) sign(v) + sigma2 v, the curve `mu` returns (0 at v = 0, where the steady
!! deflection is not defined). At rest under a holding coefficient |mu_hold| < mu_s the
!! bristle settles at sigma0 z = mu_hold.
!!
!! Scaling of the defaults. The paper's example is a unit mass, m = 1 kg, with sigma0 = 1e5
!! N/m, sigma1 = sqrt(1e5) N s/m, sigma2 = 0.4 N s/m, F_C = 1 N, F_S = 1.5 N, v_s = 1e-3 m/s.
!! We divide its forces by its normal force m g = 9.81 N: sigma0 = 1e5/9.81 = 1.0194e4 1/m,
!! sigma1 = sqrt(1e5)/9.81 = 32.24 s/m, sigma2 = 0.4/9.81 = 0.04077 s/m. This keeps the
!! paper's bristle dynamics in our scenes (whose friction force is mu m g): natural frequency
!! sqrt(g sigma0) = sqrt(1e5 / 1 kg) = 316 rad/s and damping ratio sigma1 sqrt(g/sigma0)/2 =
!! 0.5. mu_s, mu_k and v_s are the library's shared values (0.35, 0.30, 0.01 m/s), not the
!! paper's F_S/F_C = 1.5 and v_s = 1e-3 m/s (pass them to get the paper's curve).
!! Consequences for our scenes: presliding deflections are of order mu/sigma0 = 3e-5 m; at
!! the belt's 1.5 m/s the bristle relaxes at the rate sigma0 |v| / g = 5e4 1/s (stiff: RK4
!! needs h < 5e-5 s while sliding), and sigma2 adds 0.061 to mu there and damps the belt's
!! oscillation (no growth from rest into stick-slip).
!!
!! mu_k must be > 0 for this law (g(v) -> mu_k is a divisor; SS_BAD_MU_K otherwise).
!!
!! The elasto-plastic law (`stickslip_law_elastoplastic`) extends this one: it only replaces
!! `attachment`, the factor alpha of the relaxation term (1 here).
module stickslip_law_lugre
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law, SS_BAD_MU_K, relax_linear_target
    use stickslip_law_stribeck, only: stribeck_curve, stribeck_curve_slope
    implicit none
    private

    public :: lugre_law

    integer, parameter, public :: SS_BAD_SIGMA0 = -144   !! sigma0 out of range
    integer, parameter, public :: SS_BAD_SIGMA1 = -145   !! sigma1 out of range
    integer, parameter, public :: SS_BAD_SIGMA2 = -146   !! sigma2 out of range

    !> The paper's normal force (m = 1 kg, g = 9.81 m/s^2) that scales its values [N].
    real(dp), parameter :: N_PAPER = 9.81_dp

    !> Specification of the parameter sigma0 (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: SIGMA0_SPEC = param_spec(name='sigma0', &
        default=1.0e5_dp / N_PAPER, unit='1/m', lo=0.0_dp, lo_open=.true., code=SS_BAD_SIGMA0, &
        doc='bristle stiffness (mu per m of deflection)')
    !> Specification of the parameter sigma1 (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: SIGMA1_SPEC = param_spec(name='sigma1', &
        default=sqrt(1.0e5_dp) / N_PAPER, unit='s/m', lo=0.0_dp, code=SS_BAD_SIGMA1, &
        doc='bristle damping (mu per m/s of deflection rate)')
    !> Specification of the parameter sigma2 (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: SIGMA2_SPEC = param_spec(name='sigma2', &
        default=0.4_dp / N_PAPER, unit='s/m', lo=0.0_dp, code=SS_BAD_SIGMA2, &
        doc='viscous coefficient (mu per m/s of sliding)')

    !> Exponent of the Stribeck curve g(v) of the bristle laws (the 1995 paper's).
    real(dp), parameter :: STRIBECK_EXPONENT = 2.0_dp

    !> The LuGre law; parameters mu_s, mu_k, v_s, sigma0, sigma1, sigma2; state z [m].
    type, extends(friction_law) :: lugre_law
        real(dp) :: sigma0 = 1.0e5_dp / N_PAPER           !! bristle stiffness, > 0 [1/m]
        real(dp) :: sigma1 = sqrt(1.0e5_dp) / N_PAPER     !! bristle damping, >= 0 [s/m]
        real(dp) :: sigma2 = 0.4_dp / N_PAPER             !! viscous coefficient, >= 0 [s/m]
    contains
        !> Read and check the parameters; SS_OK or the code naming the bad one.
        procedure :: init => lugre_init
        !> mu(v) [-]; for a law with states, its steady-state curve.
        procedure :: mu => lugre_mu
        !> d mu / d v [s/m].
        procedure :: dmu => lugre_dmu
        !> Number of internal states.
        procedure :: n_states => lugre_n_states
        !> Name and unit of internal state i.
        procedure :: state_label => lugre_label
        !> .true. when mu depends on v alone.
        procedure :: is_static => lugre_is_static
        !> mu and the internal-state rates at (v, z, mu_hold).
        procedure :: evaluate => lugre_evaluate
        !> Exponential flow of z over a substep of prescribed motion (z' is linear in z).
        procedure :: advance => lugre_advance
        !> Factor alpha in [0, 1] of the relaxation term of z' (1 for LuGre).
        procedure :: attachment => lugre_attachment
        !> The Stribeck curve g(|v|) [-] of the steady state.
        procedure, non_overridable :: g => lugre_g
    end type lugre_law

contains

    function lugre_init(self, p) result(status)
        class(lugre_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_shared(p)
        call param_read(p, SIGMA0_SPEC, self%sigma0, status)
        call param_read(p, SIGMA1_SPEC, self%sigma1, status)
        call param_read(p, SIGMA2_SPEC, self%sigma2, status)
        if (status == SS_OK .and. .not. self%mu_k > 0.0_dp) status = SS_BAD_MU_K
    end function lugre_init

    elemental function lugre_g(self, v) result(g)
        class(lugre_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: g                   !! g(|v|) [-]
        g = stribeck_curve(abs(v), self%mu_s, self%mu_k, self%v_s, STRIBECK_EXPONENT)
    end function lugre_g

    !> The steady-state curve: g(|v|) sign(v) + sigma2 v (0 at v = 0).
    elemental function lugre_mu(self, v) result(mu)
        class(lugre_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = 0.0_dp
        if (v /= 0.0_dp) mu = sign(self%g(v) + self%sigma2 * abs(v), v)
    end function lugre_mu

    !> Slope of the steady-state curve, g'(|v|) + sigma2 (away from the jump at 0).
    elemental function lugre_dmu(self, v) result(d)
        class(lugre_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m]
        d = stribeck_curve_slope(abs(v), self%mu_s, self%mu_k, self%v_s, STRIBECK_EXPONENT) + self%sigma2
    end function lugre_dmu

    pure integer function lugre_n_states(self)
        class(lugre_law), intent(in) :: self
        lugre_n_states = 1
    end function lugre_n_states

    pure function lugre_label(self, i) result(label)
        class(lugre_law), intent(in) :: self
        integer, intent(in) :: i           !! state index (1)
        character(len=:), allocatable :: label
        label = 'z [m]'
    end function lugre_label

    pure logical function lugre_is_static(self)
        class(lugre_law), intent(in) :: self
        lugre_is_static = .false.
    end function lugre_is_static

    !> mu = sigma0 z + sigma1 z' + sigma2 v with z' = v - alpha sigma0 |v| z / g(v).
    subroutine lugre_evaluate(self, v, z, mu_hold, mu, dz)
        class(lugre_law), intent(inout) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in)  :: z(:)       !! bristle deflection (z(1)) [m]
        real(dp), intent(in)  :: mu_hold    !! holding coefficient [-] (unused)
        real(dp), intent(out) :: mu         !! friction coefficient [-]
        real(dp), intent(out) :: dz(:)      !! bristle deflection rate (dz(1)) [m/s]
        real(dp) :: g
        g = self%g(v)
        dz(1) = v - self%attachment(z(1), v, g) * self%sigma0 * abs(v) * z(1) / g
        mu = self%sigma0 * z(1) + self%sigma1 * dz(1) + self%sigma2 * v
    end subroutine lugre_evaluate

    !> In the travel u (du = |v| dt) the state equation is dz/du = sgn(v) - z/z_g(v), z_g =
    !! g(v)/sigma0: a relaxation over the length z_g to the steady deflection z_ss = z_g sgn(v).
    !! Over the substep: the rate 1/z_g at the mean of z_g(v0) and z_g(v1), the target
    !! z_ss linear in u from z_ss(v0) to z_ss(v1) (the first-order-hold exponential step: exact
    !! when g is constant, second order otherwise, and exact in the stiff limit, where z sits
    !! on z_ss(v1)). No travel, no change.
    subroutine lugre_advance(self, dx, h, v0, v1, z, status)
        class(lugre_law), intent(inout) :: self
        real(dp), intent(in)    :: dx       !! travel over the substep [m]
        real(dp), intent(in)    :: h        !! substep [s] (unused: the flow depends on the travel)
        real(dp), intent(in)    :: v0       !! relative velocity at the start [m/s]
        real(dp), intent(in)    :: v1       !! relative velocity at the end [m/s]
        real(dp), intent(inout) :: z(:)     !! bristle deflection (z(1)) at the start; at the end [m]
        integer, intent(out)    :: status   !! SS_OK
        real(dp) :: zg0, zg1, sg
        status = SS_OK
        if (dx == 0.0_dp) return
        sg = sign(1.0_dp, dx)
        zg0 = self%g(v0) / self%sigma0
        zg1 = self%g(v1) / self%sigma0
        z(1) = relax_linear_target(z(1), sg * zg0, sg * zg1, abs(dx) * 2.0_dp / (zg0 + zg1))
    end subroutine lugre_advance

    pure function lugre_attachment(self, z, v, g) result(alpha)
        class(lugre_law), intent(in) :: self
        real(dp), intent(in) :: z       !! bristle deflection [m]
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp), intent(in) :: g       !! g(|v|) [-]
        real(dp) :: alpha               !! [-]
        alpha = 1.0_dp
    end function lugre_attachment

end module stickslip_law_lugre
