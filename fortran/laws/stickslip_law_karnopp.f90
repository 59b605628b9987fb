!> Karnopp's stick band (Karnopp, ASME J. Dyn. Sys. Meas. Control 107, 1985): inside the band
!! |v| < dv the friction balances the other forces up to the static limit,
!!
!!     mu = clamp(mu_hold, -mu_s, mu_s)            for |v| < dv,
!!     mu = mu_k sign(v)                           for |v| >= dv (Coulomb's kinetic level),
!!
!! so that while |mu_hold| <= mu_s the relative velocity is held constant (at zero if it
!! entered the band at zero: true stick, no creep). Velocities in m/s. The kinetic law outside
!! the band is the constant mu_k (not a Stribeck curve): with it a small band reproduces the
!! exact piecewise Coulomb stick-slip solution.
!!
!! The law needs the holding coefficient mu_hold, so it is not static (`is_static` is
!! .false.) although it has no internal state: a scene must call `evaluate` with mu_hold =
!! its non-friction force in units of the normal force, writing dv/dt = c (mu_hold - mu),
!! c > 0. The library's slope and belt do; a user's own scene can use the law the same way
!! (e.g. a mass m pushed by a force F on a table: mu_hold = F / (m g), c = g).
!!
!! Its modes (for the implicit methods' generalized equation, see `stickslip_friction`): the
!! band as a static set, Coulomb's graph with its band v_s replaced by dv (`band_mode`): slip
!! at -mu_k (v <= -dv), the band edge -dv, slip at -mu_s inside the band, stick at v = 0 with
!! |mu| <= mu_s, slip at mu_s, the edge dv, slip at mu_k. Inside the band the stick force
!! (up to mu_s) brings the relative velocity to exactly zero within a step and holds it there,
!! where `evaluate` (the explicit methods' right-hand side) can only hold the velocity it
!! entered the band with. The set-valued methods (moreau, event_driven) take the law as
!! set-valued Coulomb (mu_s, mu_k; `stickslip_contact`'s contact_law_of): dv is the band of
!! a regularisation they do not need and is not read there.
!!
!! `mu(v)` alone is the curve at zero holding force: 0 inside the band, mu_k sign(v) outside.
!! dv defaults to 1e-3 m/s: the band must catch the relative velocity in one step, so dv must
!! exceed half the velocity change of a step, |a| h / 2 (2.5e-4 m/s on the belt re-sticking
!! with a = g (mu_k - mu_hold) = 0.49 m/s^2 at the paper's coarser step h = 1e-3 s), while the
!! stick velocity it allows (up to dv) perturbs the stick-slip cycle by O(dv / v_b).
module stickslip_law_karnopp
    use stickslip_kinds, only: dp
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law, CONTACT_COULOMB
    use stickslip_law_coulomb, only: band_mode, band_admits
    implicit none
    private

    public :: karnopp_law

    integer, parameter, public :: SS_BAD_DV = -143   !! dv out of range

    !> Specification of the parameter dv (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: DV_SPEC = param_spec(name='dv', default=0.001_dp, &
        unit='m/s', lo=0.0_dp, lo_open=.true., code=SS_BAD_DV, doc='half-width of the stick band')

    !> The Karnopp law; parameters mu_s, mu_k, dv.
    type, extends(friction_law) :: karnopp_law
        real(dp) :: dv = 0.001_dp   !! half-width of the stick band, > 0 [m/s]
    contains
        !> Read and check the parameters; SS_OK or the code naming the bad one.
        procedure :: init => karnopp_init
        !> mu(v) [-]; for a law with states, its steady-state curve.
        procedure :: mu => karnopp_mu
        !> d mu / d v [s/m].
        procedure :: dmu => karnopp_dmu
        !> .true. when mu depends on v alone.
        procedure :: is_static => karnopp_is_static
        !> mu and the internal-state rates at (v, z, mu_hold).
        procedure :: evaluate => karnopp_evaluate
        !> Seven modes: Coulomb's with the band dv (`band_mode`).
        procedure :: n_modes => karnopp_n_modes
        !> Kind and value of a mode.
        procedure :: mode => karnopp_mode
        !> Whether (v, mu_hold, mu) lies on a mode.
        procedure :: admits => karnopp_admits
        !> The law itself (it is single-valued given mu_hold).
        procedure :: mu_select => karnopp_select
        procedure :: set_valued_kind => karnopp_set_valued_kind
        !! its set-valued counterpart: Coulomb (mu_s, mu_k), the band not read
    end type karnopp_law

contains

    function karnopp_init(self, p) result(status)
        class(karnopp_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_shared(p)
        call param_read(p, DV_SPEC, self%dv, status)
    end function karnopp_init

    !> The curve at zero holding force: 0 inside the band, mu_k sign(v) outside.
    elemental function karnopp_mu(self, v) result(mu)
        class(karnopp_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = karnopp(v, 0.0_dp, self%mu_s, self%mu_k, self%dv)
    end function karnopp_mu

    !> Zero: for a given mu_hold the law is piecewise constant in v.
    elemental function karnopp_dmu(self, v) result(d)
        class(karnopp_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m]
        d = 0.0_dp
    end function karnopp_dmu

    pure logical function karnopp_is_static(self)
        class(karnopp_law), intent(in) :: self
        karnopp_is_static = .false.
    end function karnopp_is_static

    subroutine karnopp_evaluate(self, v, z, mu_hold, mu, dz)
        class(karnopp_law), intent(inout) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in)  :: z(:)       !! internal states (none)
        real(dp), intent(in)  :: mu_hold    !! coefficient that would hold v constant [-]
        real(dp), intent(out) :: mu         !! friction coefficient [-]
        real(dp), intent(out) :: dz(:)      !! rates of the internal states (none)
        mu = karnopp(v, mu_hold, self%mu_s, self%mu_k, self%dv)
    end subroutine karnopp_evaluate

    pure integer function karnopp_n_modes(self)
        class(karnopp_law), intent(in) :: self
        karnopp_n_modes = 7
    end function karnopp_n_modes

    !> Modes 1 .. 7 (`band_mode` with edge dv): slip at -mu_k, the edge -dv, slip at -mu_s, stick
    !! at v = 0, slip at mu_s, the edge dv, slip at mu_k.
    pure subroutine karnopp_mode(self, i, kind, value)
        class(karnopp_law), intent(in) :: self
        integer, intent(in) :: i            !! mode index, 1 .. 7
        integer, intent(out) :: kind        !! MODE_MU or MODE_V
        real(dp), intent(out) :: value      !! mu [-] (MODE_MU) or v [m/s] (MODE_V)
        call band_mode(i, self%mu_s, self%mu_k, self%dv, kind, value)
    end subroutine karnopp_mode

    pure logical function karnopp_admits(self, i, v, mu_hold, mu)
        class(karnopp_law), intent(in) :: self
        integer, intent(in) :: i            !! mode index, 1 .. 7
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_hold     !! coefficient that would hold v constant [-] (not read)
        real(dp), intent(in) :: mu          !! friction coefficient [-]
        karnopp_admits = band_admits(i, v, mu, self%mu_s, self%mu_k, self%dv)
    end function karnopp_admits

    pure function karnopp_select(self, v, mu_hold) result(mu)
        class(karnopp_law), intent(in) :: self
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_hold     !! coefficient that would hold v constant [-]
        real(dp) :: mu                      !! friction coefficient [-]
        mu = karnopp(v, mu_hold, self%mu_s, self%mu_k, self%dv)
    end function karnopp_select

    !> Karnopp's law at v with holding coefficient mu_hold.
    elemental function karnopp(v, mu_hold, mu_s, mu_k, dv) result(mu)
        real(dp), intent(in) :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_hold    !! coefficient that would hold v constant [-]
        real(dp), intent(in) :: mu_s       !! static coefficient [-]
        real(dp), intent(in) :: mu_k       !! kinetic coefficient [-]
        real(dp), intent(in) :: dv         !! half-width of the stick band [m/s]
        real(dp) :: mu                     !! friction coefficient [-]
        if (abs(v) < dv) then
            mu = max(-mu_s, min(mu_s, mu_hold))
        else
            mu = sign(mu_k, v)
        end if
    end function karnopp

    !> Set-valued Coulomb (stick up to mu_s, slip at mu_k at any speed; the band not read).
    pure integer function karnopp_set_valued_kind(self) result(kind)
        class(karnopp_law), intent(in) :: self
        kind = CONTACT_COULOMB
    end function karnopp_set_valued_kind

end module stickslip_law_karnopp
