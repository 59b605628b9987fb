!> The elasto-plastic law (Dupont, Hayward, Armstrong & Altpeter, IEEE TAC 47(5), 2002): the
!! LuGre bristle (`stickslip_law_lugre`, same sigma0, sigma1, sigma2, g(v) and scaling) whose
!! relaxation term is switched on only past a break-away deflection z_ba,
!!
!!     z' = v - alpha(z, v) sigma0 |v| z / g(v),    mu = sigma0 z + sigma1 z' + sigma2 v,
!!
!! with z_ss(v) = g(v)/sigma0 the steady deflection and the published piecewise alpha:
!! alpha = 0 when sign(z) /= sign(v) or |z| <= z_ba (purely elastic: z' = v); alpha = 1 for
!! |z| >= z_ss(v); in between alpha = (1 + sin(pi (|z| - (z_ss + z_ba)/2) / (z_ss - z_ba)))/2.
!! Under any holding coefficient below sigma0 z_ba the bristle is elastic, so the body sticks
!! with no drift at all (LuGre drifts under such loads when they oscillate).
!!
!! z_ba must be below z_ss(v) for every v, i.e. below mu_k/sigma0; it is given as the ratio
!! z_ba_ratio = z_ba / (mu_k/sigma0) in (0, 1), default 0.8: z_ba = 2.35e-5 m with the
!! defaults, so holding coefficients up to 0.8 mu_k = 0.24 stick elastically (the 10 degree
!! slope, tan = 0.176, and its 17 % overshoot stay elastic).
module stickslip_law_elastoplastic
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_law_lugre, only: lugre_law
    implicit none
    private

    public :: elastoplastic_law

    integer, parameter, public :: SS_BAD_Z_BA_RATIO = -147   !! z_ba_ratio out of range

    !> Specification of the parameter z_ba_ratio (default, unit, accepted range, status code).
    type(param_spec), parameter, public :: Z_BA_RATIO_SPEC = param_spec(name='z_ba_ratio', default=0.8_dp, &
        lo=0.0_dp, hi=1.0_dp, lo_open=.true., hi_open=.true., code=SS_BAD_Z_BA_RATIO, &
        doc='break-away deflection z_ba in units of mu_k/sigma0')

    real(dp), parameter :: pi = acos(-1.0_dp)

    !> The elasto-plastic law; parameters mu_s, mu_k, v_s, sigma0, sigma1, sigma2, z_ba_ratio.
    type, extends(lugre_law) :: elastoplastic_law
        real(dp) :: z_ba = 0.0_dp   !! break-away deflection [m]
    contains
        !> Read and check the parameters; SS_OK or the code naming the bad one.
        procedure :: init => elastoplastic_init
        !> Duponts attachment function alpha(z, v) [-].
        procedure :: attachment => elastoplastic_attachment
        !> The flow over a substep in the travel: exact while elastic or fully sliding, a Taylor series between.
        procedure :: advance => elastoplastic_advance
    end type elastoplastic_law

contains

    function elastoplastic_init(self, p) result(status)
        class(elastoplastic_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        real(dp) :: ratio
        status = self%lugre_law%init(p)
        call param_read(p, Z_BA_RATIO_SPEC, ratio, status)
        if (status == SS_OK) self%z_ba = ratio * self%mu_k / self%sigma0
    end function elastoplastic_init

    !> The flow over a substep in the travel, with the steady deflection z_ss = g(v)/sigma0 at
    !! the substep's mean velocity. In w = z sgn(dx) the state equation is dw/dx' = f(w) = 1 -
    !! alpha(w) w/z_ss along the travel x' = |dx|: elastic (f = 1, exact; g is not needed) up
    !! to z_ba; above z_ss the exact exponential w = z_ss + (w - z_ss) exp(-x'/z_ss); between
    !! them (where w rises towards z_ss and never crosses it) the fourth-order Taylor series of
    !! the flow in the travel, its terms f, f f', f (f'^2 + f f''), ... from one sine and one
    !! cosine of the attachment's phase (the order of classical RK4 at a quarter of its
    !! trigonometry), in steps of at most z_ss/2 and a fifth of the attachment's width z_ss -
    !! z_ba; w = z_ss once the remaining travel exceeds 40 z_ss (exp(-40) ~ 4e-18). Its error
    !! (the mean g, the Taylor steps) vanishes with the substep; the step doubling of the
    !! prescribed motion keeps it within rtol.
    subroutine elastoplastic_advance(self, dx, h, v0, v1, z, status)
        class(elastoplastic_law), intent(inout) :: self
        real(dp), intent(in)    :: dx       !! travel over the substep [m]
        real(dp), intent(in)    :: h        !! substep [s]
        real(dp), intent(in)    :: v0       !! relative velocity at the start [m/s]
        real(dp), intent(in)    :: v1       !! relative velocity at the end [m/s]
        real(dp), intent(inout) :: z(:)     !! bristle deflection (z(1)) at the start; at the end [m]
        integer, intent(out)    :: status   !! SS_OK
        real(dp) :: sg, w, r, z_ss, q, k, mid, step, sn, cs, a0, a1, a2, a3, f, f1, f2, f3
        integer :: n, j
        status = SS_OK
        if (dx == 0.0_dp .or. h < 0.0_dp) return
        sg = sign(1.0_dp, dx)
        w = z(1) * sg
        r = abs(dx)
        ! elastic up to z_ba (and from any w of the other sign)
        if (w < self%z_ba) then
            if (w + r <= self%z_ba) then
                z(1) = (w + r) * sg
                return
            end if
            r = r - (self%z_ba - w)
            w = self%z_ba
        end if
        z_ss = self%g(0.5_dp * (v0 + v1)) / self%sigma0
        if (w >= z_ss) then
            w = z_ss + (w - z_ss) * exp(-r / z_ss)
        else if (r > 40.0_dp * z_ss) then
            w = z_ss
        else
            q = 1.0_dp / z_ss
            k = pi / (z_ss - self%z_ba)
            mid = 0.5_dp * (z_ss + self%z_ba)
            n = max(1, ceiling(r * max(2.0_dp * q, 5.0_dp * k / pi)))
            step = r / real(n, dp)
            do j = 1, n
                ! alpha = (1 + sin(k (w - mid)))/2 and its w-derivatives; f = 1 - q alpha w and its
                sn = sin(k * (w - mid))
                cs = cos(k * (w - mid))
                a0 = 0.5_dp * (1.0_dp + sn)
                a1 = 0.5_dp * k * cs
                a2 = -0.5_dp * k * k * sn
                a3 = -0.5_dp * k * k * k * cs
                f = 1.0_dp - q * a0 * w
                f1 = -q * (a1 * w + a0)
                f2 = -q * (a2 * w + 2.0_dp * a1)
                f3 = -q * (a3 * w + 3.0_dp * a2)
                ! w' = f, w'' = f f1, w''' = f (f1^2 + f f2), w'''' = f (f1^3 + 4 f f1 f2 + f^2 f3)
                w = min(w + step * (f + 0.5_dp * step * (f * f1 + step / 3.0_dp * (f * (f1 * f1 + f * f2) &
                        + 0.25_dp * step * f * (f1**3 + 4.0_dp * f * f1 * f2 + f * f * f3)))), z_ss)
            end do
        end if
        z(1) = w * sg
    end subroutine elastoplastic_advance

    !> Dupont et al.'s alpha(z, v) (see the module notes).
    pure function elastoplastic_attachment(self, z, v, g) result(alpha)
        class(elastoplastic_law), intent(in) :: self
        real(dp), intent(in) :: z       !! bristle deflection [m]
        real(dp), intent(in) :: v       !! relative sliding velocity [m/s]
        real(dp), intent(in) :: g       !! g(|v|) [-]
        real(dp) :: alpha               !! [-]
        real(dp) :: s, z_ss
        s = abs(z)
        z_ss = g / self%sigma0
        if (.not. z * v > 0.0_dp .or. s <= self%z_ba) then
            alpha = 0.0_dp
        else if (s >= z_ss) then
            alpha = 1.0_dp
        else
            alpha = 0.5_dp * (1.0_dp + sin(pi * (s - 0.5_dp * (z_ss + self%z_ba)) / (z_ss - self%z_ba)))
        end if
    end function elastoplastic_attachment

end module stickslip_law_elastoplastic
