!> Coulomb's law (Yoo & Lee 2008, eq. 1): mu_s sign(v) for 0 < |v| < v_s, mu_k sign(v)
!! beyond, 0 at v = 0. Discontinuous at 0 and at v_s; no internal state.
!!
!! Its modes (for the implicit methods' generalized equation): the graph with its jumps filled
!! in, so set-valued at v = 0 (any mu in [-mu_s, mu_s]: stick) and at v = +-v_s (mu between
!! mu_k and mu_s): seven modes, -mu_k (v <= -v_s), the point -v_s, -mu_s (-v_s <= v <= 0),
!! the point 0, mu_s (0 <= v <= v_s), the point v_s, mu_k (v >= v_s).
module stickslip_law_coulomb
    use stickslip_kinds, only: dp
    use stickslip_params, only: param_values
    use stickslip_friction, only: friction_law, CONTACT_COULOMB, MODE_MU, MODE_V, between
    implicit none
    private

    public :: coulomb_law, coulomb, band_mode, band_admits

    !> The Coulomb law; parameters mu_s, mu_k, v_s.
    type, extends(friction_law) :: coulomb_law
    contains
        procedure :: init => coulomb_init
        !! validate and store the parameters
        procedure :: mu => coulomb_mu
        !! friction coefficient at a sliding velocity
        procedure :: dmu => coulomb_dmu
        !! its slope d mu / d v
        procedure :: n_modes => coulomb_n_modes
        !! seven modes: four slip pieces and three set-valued points
        procedure :: mode => coulomb_mode
        !! kind and value of a mode
        procedure :: admits => coulomb_admits
        !! whether (v, mu) lies on a mode
        procedure :: mu_select => coulomb_select
        !! mu(v), and at v = 0 mu_hold clamped to [-mu_s, mu_s]
        procedure :: set_valued_kind => coulomb_set_valued_kind
        !! its set-valued counterpart: Coulomb (mu_s, mu_k), the band not read
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

    pure integer function coulomb_n_modes(self)
        class(coulomb_law), intent(in) :: self
        coulomb_n_modes = 7
    end function coulomb_n_modes

    !> Modes 1 .. 7 from v = -infinity to +infinity: slip at -mu_k, the point -v_s, slip at
    !! -mu_s, the point 0 (stick), slip at mu_s, the point v_s, slip at mu_k.
    pure subroutine coulomb_mode(self, i, kind, value)
        class(coulomb_law), intent(in) :: self
        integer, intent(in) :: i            !! mode index, 1 .. 7
        integer, intent(out) :: kind        !! MODE_MU or MODE_V
        real(dp), intent(out) :: value      !! mu [-] (MODE_MU) or v [m/s] (MODE_V)
        call band_mode(i, self%mu_s, self%mu_k, self%v_s, kind, value)
    end subroutine coulomb_mode

    pure logical function coulomb_admits(self, i, v, mu_hold, mu)
        class(coulomb_law), intent(in) :: self
        integer, intent(in) :: i            !! mode index, 1 .. 7
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_hold     !! coefficient that would hold v constant [-] (not read)
        real(dp), intent(in) :: mu          !! friction coefficient [-]
        coulomb_admits = band_admits(i, v, mu, self%mu_s, self%mu_k, self%v_s)
    end function coulomb_admits

    !> mu(v); at v = 0, the stick force: mu_hold clamped to [-mu_s, mu_s].
    pure function coulomb_select(self, v, mu_hold) result(mu)
        class(coulomb_law), intent(in) :: self
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu_hold     !! coefficient that would hold v constant [-]
        real(dp) :: mu                      !! friction coefficient [-]
        if (v == 0.0_dp) then
            mu = max(-self%mu_s, min(self%mu_s, mu_hold))
        else
            mu = coulomb(v, self%mu_s, self%mu_k, self%v_s)
        end if
    end function coulomb_select

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

    !> Mode i (1 .. 7) of the graph with a static band: slip at -mu_k (v <= -edge), the point
    !! -edge, slip at -mu_s (-edge <= v <= 0), the point 0 (stick), slip at mu_s, the point
    !! edge, slip at mu_k (v >= edge). Coulomb's modes (edge = v_s) and Karnopp's (edge = dv).
    pure subroutine band_mode(i, mu_s, mu_k, edge, kind, value)
        integer, intent(in) :: i            !! mode index, 1 .. 7
        real(dp), intent(in) :: mu_s        !! static coefficient [-]
        real(dp), intent(in) :: mu_k        !! kinetic coefficient [-]
        real(dp), intent(in) :: edge        !! half-width of the band [m/s]
        integer, intent(out) :: kind        !! MODE_MU or MODE_V
        real(dp), intent(out) :: value      !! mu [-] (MODE_MU) or v [m/s] (MODE_V)
        real(dp) :: values(7)
        values = [-mu_k, -edge, -mu_s, 0.0_dp, mu_s, edge, mu_k]
        kind = merge(MODE_V, MODE_MU, mod(i, 2) == 0)
        value = values(i)
    end subroutine band_mode

    !> Whether (v, mu) lies on mode i of `band_mode`'s graph.
    pure logical function band_admits(i, v, mu, mu_s, mu_k, edge) result(ok)
        integer, intent(in) :: i            !! mode index, 1 .. 7
        real(dp), intent(in) :: v           !! relative sliding velocity [m/s]
        real(dp), intent(in) :: mu          !! friction coefficient [-]
        real(dp), intent(in) :: mu_s        !! static coefficient [-]
        real(dp), intent(in) :: mu_k        !! kinetic coefficient [-]
        real(dp), intent(in) :: edge        !! half-width of the band [m/s]
        real(dp), parameter :: inf = 0.25_dp * huge(1.0_dp)   ! (an open end; room for the slack)
        select case (i)
        case (1); ok = between(v, -inf, -edge)
        case (2); ok = between(mu, -mu_s, -mu_k)
        case (3); ok = between(v, -edge, 0.0_dp)
        case (4); ok = between(mu, -mu_s, mu_s)
        case (5); ok = between(v, 0.0_dp, edge)
        case (6); ok = between(mu, mu_k, mu_s)
        case (7); ok = between(v, edge, inf)
        case default; ok = .false.
        end select
    end function band_admits

    !> Set-valued Coulomb (stick up to mu_s, slip at mu_k at any speed; the band not read).
    pure integer function coulomb_set_valued_kind(self) result(kind)
        class(coulomb_law), intent(in) :: self
        kind = CONTACT_COULOMB
    end function coulomb_set_valued_kind

end module stickslip_law_coulomb
