!> The Dahl law (Dahl 1968, "A solid friction model", Aerospace Corp. TOR-0158(3107-18)-1;
!! Dahl 1976, AIAA J. 14(12)) in coefficient form, with the deflection z [m] as its one
!! internal state, mu = sigma0 z:
!!
!!     dmu/dx = sigma0 |1 - mu sgn(v)/mu_k|^alpha sgn(1 - mu sgn(v)/mu_k),
!!     z' = v |r|^alpha sgn(r),   r = 1 - sigma0 z sgn(v)/mu_k,
!!
!! a rate-independent hysteresis: mu depends on the path travelled, not on its speed. mu_k is
!! the Coulomb level F_c/N [-], sigma0 the stiffness at mu = 0 (dmu/dx there) [1/m], alpha
!! (`dahl_alpha`) Dahl's shape exponent: alpha = 1 gives the exponential approach
!! mu = mu_k (1 - exp(-sigma0 x/mu_k)) from rest under monotone motion (the LuGre equation with
!! g = mu_k and no damping), alpha > 1 a slower, algebraic approach, alpha < 1 reaches mu_k
!! after a finite travel. No Stribeck effect, no viscous term: the steady curve is
!! mu_k sign(v).
!!
!! The flow over a travel is exact (`advance`): with the travel s = |dx| and
!! kappa = sigma0/mu_k, r decays as r0 exp(-kappa s) (alpha = 1) or by
!! |r|^(1-alpha) = |r0|^(1-alpha) + (alpha - 1) kappa s (alpha /= 1; 0 once that is <= 0).
module stickslip_law_dahl
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law, MU_K_SPEC, SS_BAD_MU_K
    use stickslip_law_lugre, only: SIGMA0_SPEC
    implicit none
    private

    public :: dahl_law

    integer, parameter, public :: SS_BAD_DAHL_ALPHA = -171   !! dahl_alpha out of range

    !> Specification of the parameter dahl_alpha (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: DAHL_ALPHA_SPEC = param_spec(name='dahl_alpha', default=1.0_dp, &
        lo=0.0_dp, lo_open=.true., code=SS_BAD_DAHL_ALPHA, doc='Dahl shape exponent')

    !> The Dahl law; parameters mu_k, sigma0, dahl_alpha; state z [m].
    type, extends(friction_law) :: dahl_law
        real(dp) :: sigma0 = 1.0e5_dp / 9.81_dp   !! stiffness dmu/dx at mu = 0, > 0 [1/m]
        real(dp) :: alpha = 1.0_dp                !! shape exponent, > 0 [-]
    contains
        !> Read and check the parameters; SS_OK or the code naming the bad one.
        procedure :: init => dahl_init
        !> The steady curve mu_k sign(v) [-].
        procedure :: mu => dahl_mu
        !> Its slope, 0 [s/m].
        procedure :: dmu => dahl_dmu
        !> Number of internal states (1).
        procedure :: n_states => dahl_n_states
        !> Name and unit of the state.
        procedure :: state_label => dahl_label
        !> .false.: the law has a state.
        procedure :: is_static => dahl_is_static
        !> mu = sigma0 z and z'.
        procedure :: evaluate => dahl_evaluate
        !> Exact flow over a travel.
        procedure :: advance => dahl_advance
    end type dahl_law

contains

    function dahl_init(self, p) result(status)
        class(dahl_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = SS_OK
        call param_read(p, MU_K_SPEC, self%mu_k, status)
        call param_read(p, SIGMA0_SPEC, self%sigma0, status)
        call param_read(p, DAHL_ALPHA_SPEC, self%alpha, status)
        if (status == SS_OK .and. .not. self%mu_k > 0.0_dp) status = SS_BAD_MU_K
        self%mu_s = self%mu_k
    end function dahl_init

    elemental function dahl_mu(self, v) result(mu)
        class(dahl_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: mu                  !! friction coefficient [-]
        mu = 0.0_dp
        if (v /= 0.0_dp) mu = sign(self%mu_k, v)
    end function dahl_mu

    elemental function dahl_dmu(self, v) result(d)
        class(dahl_law), intent(in) :: self
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp) :: d                   !! d mu / d v [s/m]
        d = 0.0_dp
    end function dahl_dmu

    pure integer function dahl_n_states(self)
        class(dahl_law), intent(in) :: self
        dahl_n_states = 1
    end function dahl_n_states

    pure function dahl_label(self, i) result(label)
        class(dahl_law), intent(in) :: self
        integer, intent(in) :: i           !! state index (1)
        character(len=:), allocatable :: label
        label = 'z [m]'
    end function dahl_label

    pure logical function dahl_is_static(self)
        class(dahl_law), intent(in) :: self
        dahl_is_static = .false.
    end function dahl_is_static

    !> mu = sigma0 z, z' = v |r|^alpha sgn(r) with r = 1 - sigma0 z sgn(v)/mu_k.
    subroutine dahl_evaluate(self, v, z, mu_hold, mu, dz)
        class(dahl_law), intent(inout) :: self
        real(dp), intent(in)  :: v          !! relative sliding velocity [m/s]
        real(dp), intent(in)  :: z(:)       !! deflection (z(1)) [m]
        real(dp), intent(in)  :: mu_hold    !! holding coefficient [-] (unused)
        real(dp), intent(out) :: mu         !! friction coefficient [-]
        real(dp), intent(out) :: dz(:)      !! deflection rate (dz(1)) [m/s]
        real(dp) :: r
        mu = self%sigma0 * z(1)
        r = 1.0_dp - sign(1.0_dp, v) * mu / self%mu_k
        dz(1) = v * sign(abs(r)**self%alpha, r)
        if (r == 0.0_dp) dz(1) = 0.0_dp
    end subroutine dahl_evaluate

    !> The exact flow over a travel dx (module notes).
    subroutine dahl_advance(self, dx, h, v0, v1, z, status)
        class(dahl_law), intent(inout) :: self
        real(dp), intent(in)    :: dx       !! travel over the substep [m]
        real(dp), intent(in)    :: h        !! substep [s] (unused: the law is rate-independent)
        real(dp), intent(in)    :: v0       !! relative velocity at the start [m/s] (unused)
        real(dp), intent(in)    :: v1       !! relative velocity at the end [m/s] (unused)
        real(dp), intent(inout) :: z(:)     !! deflection (z(1)) at the start; at the end [m]
        integer, intent(out)    :: status   !! SS_OK
        real(dp) :: sg, r0, a, q, kappa_s
        status = SS_OK
        if (dx == 0.0_dp) return
        sg = sign(1.0_dp, dx)
        r0 = 1.0_dp - sg * self%sigma0 * z(1) / self%mu_k
        if (r0 == 0.0_dp) return
        kappa_s = self%sigma0 / self%mu_k * abs(dx)
        if (self%alpha == 1.0_dp) then
            a = abs(r0) * exp(-kappa_s)
        else
            q = abs(r0)**(1.0_dp - self%alpha) + (self%alpha - 1.0_dp) * kappa_s
            if (q > 0.0_dp) then
                a = q**(1.0_dp / (1.0_dp - self%alpha))
            else
                a = 0.0_dp
            end if
        end if
        z(1) = sg * self%mu_k * (1.0_dp - sign(a, r0)) / self%sigma0
    end subroutine dahl_advance

end module stickslip_law_dahl
