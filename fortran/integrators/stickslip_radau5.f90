!> Implicit Runge-Kutta method Radau IIA of order 5 (3 stages) with step size control and
!! continuous output, for stiff systems y' = f(t, y).
!!
!! The meaning of every control follows Hairer & Wanner's RADAU5 (Solving ODEs II, 2nd ed.
!! 1996, sec. IV.8, code version of 1996/2002) for an explicit system with a full Jacobian:
!! - the stage equations are solved by simplified Newton iterations on the transformed
!!   system, one real n x n (gamma/h I - J) and one complex n x n ((alpha + i beta)/h I - J)
!!   linear system per iteration; starting values from the collocation polynomial of the
!!   previous step (zero on the first step or with `startn`);
!! - Newton stops after `nit` iterations or when its contraction rate theta >= 0.99 or
!!   predicts no convergence (then the step is shrunk and retried), and converges when
!!   faccon * |dz| <= fnewt;
!! - the Jacobian is reused for the next step when theta <= `thet`, and the factorisations
!!   too when in addition quot1 <= h_new/h <= quot2;
!! - the embedded error estimate needs one extra solve with the real matrix, and on the
!!   first step and after a rejection a second one ("filtered" estimate);
!! - Gustafsson's predictive step control (default) or the classical one, with safety 0.9
!!   (reduced when Newton needed many iterations) and h_new/h in [facl, facr];
!! - Hairer's tolerance transformation rtol' = 0.1 rtol^(2/3), atol' = rtol' atol/rtol;
!! - counters counted as RADAU5 counts them: nfev counts the right-hand sides of the
!!   stages, of the error estimate and of the step ends (not those of a finite-difference
!!   Jacobian, which `ode_system%jacobian` adds to nfev in this library: with the default
!!   Jacobian our nfev exceeds Hairer's NFCN by n njac), njac, ndec (one real and one complex
!!   decomposition count as one), nsol (Newton solves only), nstep, naccept, nreject
!!   (rejections after the first accepted step).
!!
!! As in DOPRI5 there is a step size floor h_min: when the error test fails at h_min the step
!! is accepted anyway and counted in nforced (`allow_forced = .false.`: SS_STEP_TOO_SMALL).
!! At h_min, where the step cannot shrink, Newton is not abandoned on the prediction that it
!! will converge too slowly (it iterates on up to `nit`); if it still fails (nit iterations,
!! or a contraction rate >= 0.99), the last iterate is taken as a forced step, counted in
!! nforced like a failed error test there (`allow_forced = .false.`: SS_NEWTON_FAILED).
!! This happens where the stage equations have no smooth solution: Coulomb's jump at v = 0,
!! and the proposed law's mu ~ |v|^beta from rest at tight tolerances. With h_min = 0
!! (Hairer's code has none) none of this is reached.
!!
!! Banded systems (Hairer's MLJAC < N): when the system's `bandwidth` gives a band (ml lower,
!! mu upper diagonals in a state order of its choosing) and `banded` is set, the Jacobian
!! comes from `band_jacobian` and both matrices are factored as band matrices in that order
!! (storage and work O(n ml (ml + mu)) instead of O(n^2) and O(n^3)); the steps are those of
!! the dense path up to rounding.
!!
!! Linear algebra: stickslip_linalg's own dense LU (for n <= 10 it was measured as fast as
!! LAPACK's dgetrf/dgetrs and zgetrf/zgetrs, and the library needs no LAPACK).
module stickslip_radau5
    use stickslip_kinds, only: dp, SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_OUTPUT_FULL, SS_NONFINITE, SS_INTERRUPTED, &
                               SS_NEWTON_FAILED, SS_SINGULAR, SS_JAC_NONFINITE, SS_BAD_NIT, &
                               SS_BAD_NEWTON_TOL, SS_BAD_RADAU5_CONTROL, SS_BAD_RTOL_POSITIVE, &
                               SS_BAD_RTOL
    use stickslip_ode, only: ode_system, ode_stats, step_controls, method_info, check_problem, check_tolerances, &
                             check_step_controls, all_finite, diverged, output_start, stop_requested, limit_after_forced
    use stickslip_linalg, only: lu_decompose, lu_solve, band_decompose, band_solve
    use stickslip_scenes, only: slope_scene, belt_scene
    ! every law's type, for the kernels of the laws marked kernel=.true. (stickslip_laws is written
    ! from the registry's LAW_TABLE by tools/gen_kernels.py, as the kernels are)
    use stickslip_laws
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: radau5_options, radau5_integrate

    !> Rounding unit of RADAU5's tests (Hairer's default WORK(1) = 1e-16).
    real(dp), parameter :: UROUND = 1.0e-16_dp

    ! Nodes of Radau IIA (order 5): c1, c2 = (4 -+ sqrt 6)/10, c3 = 1.
    real(dp), parameter :: SQ6 = sqrt(6.0_dp)
    !> Collocation nodes c of the 3-stage Radau IIA method (order 5) [-].
    real(dp), parameter, public :: radau5_c(3) = [(4.0_dp - SQ6) / 10.0_dp, (4.0_dp + SQ6) / 10.0_dp, 1.0_dp]
    real(dp), parameter :: C1 = radau5_c(1), C2 = radau5_c(2)
    real(dp), parameter :: C1M1 = C1 - 1.0_dp, C2M1 = C2 - 1.0_dp, C1MC2 = C1 - C2
    ! Weights of the embedded error estimate (Hairer & Wanner IV.8, (8.19)-(8.20)).
    real(dp), parameter :: DD1 = -(13.0_dp + 7.0_dp * SQ6) / 3.0_dp, DD2 = (-13.0_dp + 7.0_dp * SQ6) / 3.0_dp, &
                           DD3 = -1.0_dp / 3.0_dp
    ! Eigenvalues of A^-1: one real gamma = 1/u1 and the pair alpha +- i beta.
    real(dp), parameter :: CR81 = 81.0_dp**(1.0_dp / 3.0_dp), CR9 = 9.0_dp**(1.0_dp / 3.0_dp)
    real(dp), parameter :: GAM0 = 1.0_dp / ((6.0_dp + CR81 - CR9) / 30.0_dp)
    real(dp), parameter :: ALPH0 = (12.0_dp - CR81 + CR9) / 60.0_dp, &
                           BETA0 = (CR81 + CR9) * sqrt(3.0_dp) / 60.0_dp
    real(dp), parameter :: ALPH = ALPH0 / (ALPH0**2 + BETA0**2), BETA = BETA0 / (ALPH0**2 + BETA0**2)
    !> T with T^-1 A^-1 T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]] (rows of the
    !! published 20-digit values, Hairer & Wanner IV.8), and its inverse TI.
    real(dp), parameter, public :: radau5_t(3, 3) = reshape([ &
        9.1232394870892942792e-02_dp, 0.24171793270710701896_dp, 0.96604818261509293619_dp, &
        -0.14125529502095420843_dp, 0.20412935229379993199_dp, 1.0_dp, &
        -3.0029194105147424492e-02_dp, 0.38294211275726193779_dp, 0.0_dp], [3, 3])
    !> The inverse of radau5_t: the transformation to the real and complex systems [-].
    real(dp), parameter, public :: radau5_ti(3, 3) = reshape([ &
        4.3255798900631553510_dp, -4.1787185915519047273_dp, -0.50287263494578687595_dp, &
        0.33919925181580986954_dp, -0.32768282076106238708_dp, 2.5719269498556054292_dp, &
        0.54177053993587487119_dp, 0.47662355450055045196_dp, -0.59603920482822492497_dp], [3, 3])

    !> Controls of RADAU5: the shared ones (h_min, h_max, h0 = Hairer's initial H with 0
    !! meaning 1e-6, max_steps, allow_forced, fac_forced, calm_steps, every_step; h is not read) and Hairer's own,
    !! with his defaults (IWORK(3), IWORK(4), IWORK(8), WORK(2..9)).
    type, extends(step_controls) :: radau5_options
        integer  :: nit = 7              !! Newton iterations allowed per step (IWORK(3)), >= 1
        logical  :: startn = .false.     !! zero Newton starting values instead of extrapolation (IWORK(4))
        logical  :: pred = .true.        !! Gustafsson's predictive step control (IWORK(8) = 1); else classical
        real(dp) :: safety = 0.9_dp      !! safety factor of the step prediction (WORK(2)), in (0.001, 1)
        real(dp) :: thet = 0.001_dp      !! reuse the Jacobian when the Newton rate <= thet (WORK(3)), in [0, 1)
        real(dp) :: fnewt = 0.0_dp       !! Newton stopping criterion (WORK(4)); 0: max(10 uround/rtol', min(0.03, rtol'^0.5))
        real(dp) :: quot1 = 1.0_dp       !! keep h (and the factorisations) when quot1 <= h_new/h <= quot2 (WORK(5))
        real(dp) :: quot2 = 1.2_dp       !! see quot1 (WORK(6))
        real(dp) :: facl = 0.2_dp        !! smallest step ratio h_new/h (WORK(8))
        real(dp) :: facr = 8.0_dp        !! largest step ratio h_new/h (WORK(9))
        !> Factor band matrices when the system says its Jacobian is banded (`bandwidth`:
        !! Hairer's MLJAC/MUJAC, with the system's own state order), O(n) a step; .false.:
        !! dense n x n matrices whatever the system says.
        logical  :: banded = .true.
    contains
        !> Set one control by name, then fall back to the parent types controls.
        procedure :: set => set_radau5_option
    end type radau5_options

    !> What RADAU5 is and which controls it reads (registry entry).
    type(method_info), parameter, public :: RADAU5_INFO = method_info(name='radau5', order=5, &
        adaptive=.true., implicit=.true., controls='rtol atol hmin hmax h0 max_steps allow_forced ' // &
        'fac_forced calm_steps every_step nit startn pred safety thet fnewt quot1 quot2 facl facr banded', &
        doc='Radau IIA order 5, adaptive, as Hairer''s RADAU5')

    ! What the main loop does next.
    integer, parameter :: DO_JAC = 1, DO_DEC = 2, DO_STEP = 3

contains

    !> Set one control by name: RADAU5's own, then the shared ones.
    function set_radau5_option(self, name, value) result(status)
        class(radau5_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts and flags as reals)
        integer :: status
        status = SS_OK
        select case (name)
        case ('nit')
            if (value >= 1.0_dp .and. value <= 1.0e6_dp) then
                self%nit = int(value)
            else
                status = SS_BAD_NIT
            end if
        case ('startn'); self%startn = value /= 0.0_dp
        case ('pred');   self%pred = value /= 0.0_dp
        case ('safety'); self%safety = value
        case ('thet');   self%thet = value
        case ('fnewt');  self%fnewt = value
        case ('quot1');  self%quot1 = value
        case ('quot2');  self%quot2 = value
        case ('facl');   self%facl = value
        case ('facr');   self%facr = value
        case ('banded'); self%banded = value /= 0.0_dp
        case default;    status = self%step_controls%set(name, value)
        end select
    end function set_radau5_option

    !> Integrate y' = f(t, y) from t0 to t_end with Radau IIA (order 5) and error control.
    !!
    !! rtol and atol have size 1 (scalar) or size(y0) (per component); rtol must be > 0.
    !! The Jacobian comes from sys%jacobian (finite differences unless the system overrides it;
    !! a built-in scene with a static law runs a specialised kernel with its analytic Jacobian,
    !! which is what its jacobian binding returns).
    !! Grid mode: y_out(:, i) receives y(t_out(i)) from the collocation polynomial of the step
    !! containing it. Every-step mode: (t_out, y_out) receive the initial state and each
    !! accepted step. stats%status: SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_NEWTON_FAILED,
    !! SS_SINGULAR, SS_JAC_NONFINITE, SS_DIVERGED (a step left sys%state_bound), SS_OUTPUT_FULL
    !! or a bad-input code. On a run-time
    !! failure the output rows up to stats%t_reached are valid.
    subroutine radau5_integrate(sys, t0, y0, t_end, rtol, atol, opts, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys  !! the right-hand side (and its Jacobian)
        real(dp), intent(in)    :: t0            !! initial time [s]
        real(dp), intent(in)    :: y0(:)         !! initial state
        real(dp), intent(in)    :: t_end         !! final time, > t0 [s]
        real(dp), intent(in)    :: rtol(:)       !! relative tolerances, size 1 or size(y0), in [100 eps, 1)
        real(dp), intent(in)    :: atol(:)       !! absolute tolerances, size 1 or size(y0), > 0
        type(radau5_options), intent(in) :: opts !! controls
        real(dp), intent(inout) :: t_out(:)      !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats    !! counters and status
        real(dp) :: rt(size(y0)), at(size(y0))
        integer :: i

        stats%status = check_problem(t0, y0, t_end, t_out, y_out, opts%every_step)
        if (stats%status == SS_OK) stats%status = check_options(size(y0), t0, t_end, rtol, atol, opts)
        if (stats%status /= SS_OK) return

        ! Hairer's tolerance transformation (the error estimate is of lower order), done here
        ! for every kernel. rt**(2/3) is evaluated by the vectorised pow (libmvec; simd
        ! directive), as the compiler had always chosen for this loop: libmvec's pow and
        ! libm's differ in the last bit for some rtol (1e-4, 1e-8), and a loop of known size 2
        ! would otherwise be unrolled into libm's calls.
        if (size(rtol) == 1) then
            rt = rtol(1)
        else
            rt = rtol
        end if
        if (size(atol) == 1) then
            at = atol(1)
        else
            at = atol
        end if
        at = (at / rt)
        !$omp simd
        do i = 1, size(y0)
            rt(i) = 0.1_dp * rt(i)**(2.0_dp / 3.0_dp)
        end do
        at = rt * at

#define KERNEL_ARGS t0, y0, t_end, rt, at, opts, t_out, y_out, stats
#include "stickslip_kernel_dispatch.inc"
#undef KERNEL_ARGS
    end subroutine radau5_integrate

    ! The integrator's instances: generic_kernel for any ode_system (a user's own), and one
    ! for each built-in scene with each static law (its analytic Jacobian inlined).
#define KERNEL_BODY "stickslip_radau5_body.inc"
#include "stickslip_kernel_instances.inc"
#undef KERNEL_BODY

    !> (b1, b2, b3) = M (a1, a2, a3) componentwise, for the 3 x 3 transformations T and TI.
    pure subroutine transform(mat, a1, a2, a3, b1, b2, b3)
        real(dp), intent(in)  :: mat(3, 3)
        real(dp), intent(in)  :: a1(:), a2(:), a3(:)
        real(dp), intent(out) :: b1(:), b2(:), b3(:)
        b1 = mat(1, 1) * a1 + mat(1, 2) * a2 + mat(1, 3) * a3
        b2 = mat(2, 1) * a1 + mat(2, 2) * a2 + mat(2, 3) * a3
        b3 = mat(3, 1) * a1 + mat(3, 2) * a2 + mat(3, 3) * a3
    end subroutine transform

    !> Validate tolerances, the shared controls and RADAU5's own.
    pure function check_options(n, t0, t_end, rtol, atol, opts) result(status)
        integer, intent(in) :: n
        real(dp), intent(in) :: t0, t_end, rtol(:), atol(:)
        type(radau5_options), intent(in) :: opts
        integer :: status
        status = check_tolerances(n, rtol, atol)
        if (status == SS_BAD_RTOL .or. (status == SS_OK .and. any(rtol <= 0.0_dp))) status = SS_BAD_RTOL_POSITIVE
        if (status == SS_OK) status = check_step_controls(opts, t0, t_end)
        if (status /= SS_OK) return
        if (opts%nit < 1) then
            status = SS_BAD_NIT
        else if (.not. ieee_is_finite(opts%fnewt) .or. opts%fnewt < 0.0_dp .or. &
                 (opts%fnewt > 0.0_dp .and. opts%fnewt <= UROUND / (0.1_dp * rtol(1)**(2.0_dp / 3.0_dp)))) then
            status = SS_BAD_NEWTON_TOL
        else if (.not. (opts%safety > 0.001_dp .and. opts%safety < 1.0_dp) .or. &
                 .not. (opts%thet >= 0.0_dp .and. opts%thet < 1.0_dp) .or. &
                 .not. (opts%quot1 > 0.0_dp .and. opts%quot1 <= 1.0_dp) .or. &
                 .not. (opts%quot2 >= 1.0_dp .and. ieee_is_finite(opts%quot2)) .or. &
                 .not. (opts%facl > 0.0_dp .and. opts%facl <= 1.0_dp) .or. &
                 .not. (opts%facr >= 1.0_dp .and. ieee_is_finite(opts%facr))) then
            status = SS_BAD_RADAU5_CONTROL
        end if
    end function check_options

end module stickslip_radau5
