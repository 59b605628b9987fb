!> Adaptive explicit Runge-Kutta method of Dormand and Prince, order 8(5,3), event-free.
!!
!! Hairer's DOP853 (Hairer, Norsett & Wanner, Solving ODEs I, 2nd ed., 1993), with the
!! meaning of every control kept: 12 stages a step plus one evaluation at the new point on
!! acceptance (its derivative starts the next step), an error estimate that combines the
!! 5th- and 3rd-order embedded solutions (err5^2 / sqrt(err5^2 + 0.01 err3^2), RMS over the
!! components with the scale atol_i + rtol_i max(|y_i|, |y1_i|)), step control with exponent
!! 1/8, safety 0.9 and step ratio in [0.333, 6], Lund stabilisation beta = 0 by default,
!! the automatic initial step (HINIT), the stiffness test h |lambda| > 6.1, and dense
!! output of order 7 (three more evaluations, made only for a step with an output time in
!! it). Counters as Hairer counts them (NFCN, NSTEP, NACCPT, NREJCT), except that a given
!! h0 saves the evaluation HINIT would have made and nfev counts only evaluations made.
!!
!! As DOPRI5 (stickslip_dopri5): a step size floor h_min where a failed error test forces
!! the step (event-free stepping through a friction discontinuity; `allow_forced = .false.`
!! makes that SS_STEP_TOO_SMALL), with the growth after a forced step limited by
!! `limit_after_forced`. Runs with h_min = 0 are Hairer's DOP853 step for step (a stop on
!! stiffness commits the step his code returns before).
!!
!! The coefficients are Hairer's, as published in his dop853.f (30-digit decimals).
module stickslip_dop853
    use stickslip_kinds, only: dp, SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_STIFF, &
                               SS_NONFINITE, SS_OUTPUT_FULL, SS_BAD_CONTROL_NAME, SS_INTERRUPTED
    use stickslip_ode, only: ode_system, ode_stats, step_controls, method_info, check_problem, check_tolerances, &
                             check_step_controls, all_finite, diverged, output_start, stop_requested, limit_after_forced, &
                             set_erk_constant, check_erk_constants
    use stickslip_scenes, only: slope_scene, belt_scene
    ! every law's type, for the kernels of the laws marked kernel=.true. (stickslip_laws is written
    ! from the registry's LAW_TABLE by tools/gen_kernels.py, as the kernels are)
    use stickslip_laws
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: dop853_options, dop853_integrate

    ! Hairer's coefficients: nodes c, 8th-order weights b, the 3rd-order weights bhh of the
    ! second error estimate, the error weights er (b minus the 5th-order weights), the
    ! stages' a, the three stages of the dense output (14-16) and its coefficients d.
    real(dp), parameter :: c2 = 0.526001519587677318785587544488e-01_dp, &
        c3 = 0.789002279381515978178381316732e-01_dp, &
        c4 = 0.118350341907227396726757197510e+00_dp, &
        c5 = 0.281649658092772603273242802490e+00_dp, &
        c6 = 0.333333333333333333333333333333e+00_dp, &
        c7 = 0.25e+00_dp, &
        c8 = 0.307692307692307692307692307692e+00_dp, &
        c9 = 0.651282051282051282051282051282e+00_dp, &
        c10 = 0.6e+00_dp, &
        c11 = 0.857142857142857142857142857142e+00_dp, &
        c14 = 0.1e+00_dp, &
        c15 = 0.2e+00_dp, &
        c16 = 0.777777777777777777777777777778e+00_dp
    real(dp), parameter :: b1 = 5.42937341165687622380535766363e-2_dp, &
        b6 = 4.45031289275240888144113950566e0_dp, &
        b7 = 1.89151789931450038304281599044e0_dp, &
        b8 = -5.8012039600105847814672114227e0_dp, &
        b9 = 3.1116436695781989440891606237e-1_dp, &
        b10 = -1.52160949662516078556178806805e-1_dp, &
        b11 = 2.01365400804030348374776537501e-1_dp, &
        b12 = 4.47106157277725905176885569043e-2_dp
    real(dp), parameter :: bhh1 = 0.244094488188976377952755905512e+00_dp, &
        bhh2 = 0.733846688281611857341361741547e+00_dp, &
        bhh3 = 0.220588235294117647058823529412e-01_dp
    real(dp), parameter :: er1 = 0.1312004499419488073250102996e-01_dp, &
        er6 = -0.1225156446376204440720569753e+01_dp, &
        er7 = -0.4957589496572501915214079952e+00_dp, &
        er8 = 0.1664377182454986536961530415e+01_dp, &
        er9 = -0.3503288487499736816886487290e+00_dp, &
        er10 = 0.3341791187130174790297318841e+00_dp, &
        er11 = 0.8192320648511571246570742613e-01_dp, &
        er12 = -0.2235530786388629525884427845e-01_dp
    real(dp), parameter :: a21 = 5.26001519587677318785587544488e-2_dp
    real(dp), parameter :: a31 = 1.97250569845378994544595329183e-2_dp, &
        a32 = 5.91751709536136983633785987549e-2_dp
    real(dp), parameter :: a41 = 2.95875854768068491816892993775e-2_dp, &
        a43 = 8.87627564304205475450678981324e-2_dp
    real(dp), parameter :: a51 = 2.41365134159266685502369798665e-1_dp, &
        a53 = -8.84549479328286085344864962717e-1_dp, &
        a54 = 9.24834003261792003115737966543e-1_dp
    real(dp), parameter :: a61 = 3.7037037037037037037037037037e-2_dp, &
        a64 = 1.70828608729473871279604482173e-1_dp, &
        a65 = 1.25467687566822425016691814123e-1_dp
    real(dp), parameter :: a71 = 3.7109375e-2_dp, &
        a74 = 1.70252211019544039314978060272e-1_dp, &
        a75 = 6.02165389804559606850219397283e-2_dp, &
        a76 = -1.7578125e-2_dp
    real(dp), parameter :: a81 = 3.70920001185047927108779319836e-2_dp, &
        a84 = 1.70383925712239993810214054705e-1_dp, &
        a85 = 1.07262030446373284651809199168e-1_dp, &
        a86 = -1.53194377486244017527936158236e-2_dp, &
        a87 = 8.27378916381402288758473766002e-3_dp
    real(dp), parameter :: a91 = 6.24110958716075717114429577812e-1_dp, &
        a94 = -3.36089262944694129406857109825e0_dp, &
        a95 = -8.68219346841726006818189891453e-1_dp, &
        a96 = 2.75920996994467083049415600797e1_dp, &
        a97 = 2.01540675504778934086186788979e1_dp, &
        a98 = -4.34898841810699588477366255144e1_dp
    real(dp), parameter :: a101 = 4.77662536438264365890433908527e-1_dp, &
        a104 = -2.48811461997166764192642586468e0_dp, &
        a105 = -5.90290826836842996371446475743e-1_dp, &
        a106 = 2.12300514481811942347288949897e1_dp, &
        a107 = 1.52792336328824235832596922938e1_dp, &
        a108 = -3.32882109689848629194453265587e1_dp, &
        a109 = -2.03312017085086261358222928593e-2_dp
    real(dp), parameter :: a111 = -9.3714243008598732571704021658e-1_dp, &
        a114 = 5.18637242884406370830023853209e0_dp, &
        a115 = 1.09143734899672957818500254654e0_dp, &
        a116 = -8.14978701074692612513997267357e0_dp, &
        a117 = -1.85200656599969598641566180701e1_dp, &
        a118 = 2.27394870993505042818970056734e1_dp, &
        a119 = 2.49360555267965238987089396762e0_dp, &
        a1110 = -3.0467644718982195003823669022e0_dp
    real(dp), parameter :: a121 = 2.27331014751653820792359768449e0_dp, &
        a124 = -1.05344954667372501984066689879e1_dp, &
        a125 = -2.00087205822486249909675718444e0_dp, &
        a126 = -1.79589318631187989172765950534e1_dp, &
        a127 = 2.79488845294199600508499808837e1_dp, &
        a128 = -2.85899827713502369474065508674e0_dp, &
        a129 = -8.87285693353062954433549289258e0_dp, &
        a1210 = 1.23605671757943030647266201528e1_dp, &
        a1211 = 6.43392746015763530355970484046e-1_dp
    real(dp), parameter :: a141 = 5.61675022830479523392909219681e-2_dp, &
        a147 = 2.53500210216624811088794765333e-1_dp, &
        a148 = -2.46239037470802489917441475441e-1_dp, &
        a149 = -1.24191423263816360469010140626e-1_dp, &
        a1410 = 1.5329179827876569731206322685e-1_dp, &
        a1411 = 8.20105229563468988491666602057e-3_dp, &
        a1412 = 7.56789766054569976138603589584e-3_dp, &
        a1413 = -8.298e-3_dp
    real(dp), parameter :: a151 = 3.18346481635021405060768473261e-2_dp, &
        a156 = 2.83009096723667755288322961402e-2_dp, &
        a157 = 5.35419883074385676223797384372e-2_dp, &
        a158 = -5.49237485713909884646569340306e-2_dp, &
        a1511 = -1.08347328697249322858509316994e-4_dp, &
        a1512 = 3.82571090835658412954920192323e-4_dp, &
        a1513 = -3.40465008687404560802977114492e-4_dp, &
        a1514 = 1.41312443674632500278074618366e-1_dp
    real(dp), parameter :: a161 = -4.28896301583791923408573538692e-1_dp, &
        a166 = -4.69762141536116384314449447206e0_dp, &
        a167 = 7.68342119606259904184240953878e0_dp, &
        a168 = 4.06898981839711007970213554331e0_dp, &
        a169 = 3.56727187455281109270669543021e-1_dp, &
        a1613 = -1.39902416515901462129418009734e-3_dp, &
        a1614 = 2.9475147891527723389556272149e0_dp, &
        a1615 = -9.15095847217987001081870187138e0_dp
    real(dp), parameter :: d41 = -0.84289382761090128651353491142e+01_dp, &
        d46 = 0.56671495351937776962531783590e+00_dp, &
        d47 = -0.30689499459498916912797304727e+01_dp, &
        d48 = 0.23846676565120698287728149680e+01_dp, &
        d49 = 0.21170345824450282767155149946e+01_dp, &
        d410 = -0.87139158377797299206789907490e+00_dp, &
        d411 = 0.22404374302607882758541771650e+01_dp, &
        d412 = 0.63157877876946881815570249290e+00_dp, &
        d413 = -0.88990336451333310820698117400e-01_dp, &
        d414 = 0.18148505520854727256656404962e+02_dp, &
        d415 = -0.91946323924783554000451984436e+01_dp, &
        d416 = -0.44360363875948939664310572000e+01_dp
    real(dp), parameter :: d51 = 0.10427508642579134603413151009e+02_dp, &
        d56 = 0.24228349177525818288430175319e+03_dp, &
        d57 = 0.16520045171727028198505394887e+03_dp, &
        d58 = -0.37454675472269020279518312152e+03_dp, &
        d59 = -0.22113666853125306036270938578e+02_dp, &
        d510 = 0.77334326684722638389603898808e+01_dp, &
        d511 = -0.30674084731089398182061213626e+02_dp, &
        d512 = -0.93321305264302278729567221706e+01_dp, &
        d513 = 0.15697238121770843886131091075e+02_dp, &
        d514 = -0.31139403219565177677282850411e+02_dp, &
        d515 = -0.93529243588444783865713862664e+01_dp, &
        d516 = 0.35816841486394083752465898540e+02_dp
    real(dp), parameter :: d61 = 0.19985053242002433820987653617e+02_dp, &
        d66 = -0.38703730874935176555105901742e+03_dp, &
        d67 = -0.18917813819516756882830838328e+03_dp, &
        d68 = 0.52780815920542364900561016686e+03_dp, &
        d69 = -0.11573902539959630126141871134e+02_dp, &
        d610 = 0.68812326946963000169666922661e+01_dp, &
        d611 = -0.10006050966910838403183860980e+01_dp, &
        d612 = 0.77771377980534432092869265740e+00_dp, &
        d613 = -0.27782057523535084065932004339e+01_dp, &
        d614 = -0.60196695231264120758267380846e+02_dp, &
        d615 = 0.84320405506677161018159903784e+02_dp, &
        d616 = 0.11992291136182789328035130030e+02_dp
    real(dp), parameter :: d71 = -0.25693933462703749003312586129e+02_dp, &
        d76 = -0.15418974869023643374053993627e+03_dp, &
        d77 = -0.23152937917604549567536039109e+03_dp, &
        d78 = 0.35763911791061412378285349910e+03_dp, &
        d79 = 0.93405324183624310003907691704e+02_dp, &
        d710 = -0.37458323136451633156875139351e+02_dp, &
        d711 = 0.10409964950896230045147246184e+03_dp, &
        d712 = 0.29840293426660503123344363579e+02_dp, &
        d713 = -0.43533456590011143754432175058e+02_dp, &
        d714 = 0.96324553959188282948394950600e+02_dp, &
        d715 = -0.39177261675615439165231486172e+02_dp, &
        d716 = -0.14972683625798562581422125276e+03_dp

    !> Nodes of the extended tableau: the 12 stages, the new point (13) and the three
    !! stages of the dense output (14-16).
    real(dp), parameter, public :: dop853_c(16) = [0.0_dp, c2, c3, c4, c5, c6, c7, c8, c9, c10, c11, &
                                                   1.0_dp, 1.0_dp, c14, c15, c16]
    !> Weights of the 8th-order solution over the 12 stages.
    real(dp), parameter, public :: dop853_b(12) = [b1, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, b6, b7, b8, b9, &
                                                   b10, b11, b12]
    !> Error weights over the 12 stages: 8th-order minus 5th-order weights.
    real(dp), parameter, public :: dop853_er(12) = [er1, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, er6, er7, er8, &
                                                    er9, er10, er11, er12]
    !> Weights of the 3rd-order solution (stages 1, 9 and 12) of the second error estimate.
    real(dp), parameter, public :: dop853_bhh(12) = [bhh1, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
                                                     0.0_dp, bhh2, 0.0_dp, 0.0_dp, bhh3]
    real(dp), parameter :: zeros(16) = 0.0_dp
    !> The extended tableau's A by rows (row 13 = b: the new point), for tableau checks.
    real(dp), parameter, public :: dop853_a(16, 16) = transpose(reshape([ &
        zeros(1:16), &
        a21, zeros(2:16), &
        a31, a32, zeros(3:16), &
        a41, 0.0_dp, a43, zeros(4:16), &
        a51, 0.0_dp, a53, a54, zeros(5:16), &
        a61, 0.0_dp, 0.0_dp, a64, a65, zeros(6:16), &
        a71, 0.0_dp, 0.0_dp, a74, a75, a76, zeros(7:16), &
        a81, 0.0_dp, 0.0_dp, a84, a85, a86, a87, zeros(8:16), &
        a91, 0.0_dp, 0.0_dp, a94, a95, a96, a97, a98, zeros(9:16), &
        a101, 0.0_dp, 0.0_dp, a104, a105, a106, a107, a108, a109, zeros(10:16), &
        a111, 0.0_dp, 0.0_dp, a114, a115, a116, a117, a118, a119, a1110, zeros(11:16), &
        a121, 0.0_dp, 0.0_dp, a124, a125, a126, a127, a128, a129, a1210, a1211, &
        zeros(12:16), &
        dop853_b, zeros(13:16), &
        a141, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a147, a148, a149, a1410, a1411, a1412, a1413, &
        zeros(14:16), &
        a151, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a156, a157, a158, 0.0_dp, 0.0_dp, a1511, a1512, a1513, &
        a1514, 0.0_dp, 0.0_dp, &
        a161, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, a166, a167, a168, a169, 0.0_dp, 0.0_dp, 0.0_dp, a1613, &
        a1614, a1615, 0.0_dp], [16, 16]))

    !> Controls of DOP853: the shared ones (h_min, h_max, h0, max_steps, allow_forced,
    !! every_step, fac_forced, calm_steps; h is not read) and Hairer's step-control
    !! constants with his defaults for DOP853.
    type, extends(step_controls) :: dop853_options
        real(dp) :: safety = 0.9_dp     !! safety factor of the step control
        real(dp) :: fac1 = 0.333_dp     !! smallest step ratio h_new/h
        real(dp) :: fac2 = 6.0_dp       !! largest step ratio h_new/h
        real(dp) :: beta = 0.0_dp       !! Lund stabilisation exponent (0: plain I control)
        integer  :: nstiff = 1000       !! test stiffness every nstiff accepted steps
        logical  :: stop_on_stiff = .false. !! stop with SS_STIFF when the stiffness test fires
    contains
        procedure :: set => set_dop853_option
        !! set a control by name (the step_controls ones and DOP853's own)
    end type dop853_options

    !> What DOP853 is and which controls it reads (registry entry).
    type(method_info), parameter, public :: DOP853_INFO = method_info(name='dop853', order=8, &
        adaptive=.true., implicit=.false., controls='rtol atol hmin hmax h0 max_steps allow_forced ' // &
        'every_step safety fac1 fac2 beta_pi nstiff stop_on_stiff fac_forced calm_steps', &
        doc='Dormand-Prince 8(5,3), adaptive, as Hairer''s DOP853')

contains

    !> Set one control by name: DOP853's own, then the shared ones.
    function set_dop853_option(self, name, value) result(status)
        class(dop853_options), intent(inout) :: self
        character(len=*), intent(in) :: name    !! control name
        real(dp), intent(in) :: value           !! its value (counts and flags as reals)
        integer :: status
        status = set_erk_constant(name, value, self%safety, self%fac1, self%fac2, self%beta, self%nstiff, &
                                  self%stop_on_stiff)
        if (status == SS_BAD_CONTROL_NAME) status = self%step_controls%set(name, value)
    end function set_dop853_option

    !> Integrate y' = f(t, y) from t0 to t_end with error control.
    !!
    !! rtol and atol have size 1 (scalar) or size(y0) (per component).
    !! Grid mode: y_out(:, i) receives y(t_out(i)) by dense output. Every-step mode:
    !! (t_out, y_out) receive the initial state and each accepted step.
    !! stats%status: SS_OK, SS_STEP_BUDGET, SS_STEP_TOO_SMALL, SS_STIFF, SS_NONFINITE,
    !! SS_DIVERGED (a step left sys%state_bound), SS_OUTPUT_FULL or a bad-input code. On a run-time failure the output rows up to
    !! stats%t_reached are valid.
    subroutine dop853_integrate(sys, t0, y0, t_end, rtol, atol, opts, t_out, y_out, stats)
        class(ode_system), intent(inout) :: sys  !! the right-hand side
        real(dp), intent(in)    :: t0            !! initial time [s]
        real(dp), intent(in)    :: y0(:)         !! initial state
        real(dp), intent(in)    :: t_end         !! final time, > t0 [s]
        real(dp), intent(in)    :: rtol(:)       !! relative tolerances, size 1 or size(y0)
        real(dp), intent(in)    :: atol(:)       !! absolute tolerances, size 1 or size(y0)
        type(dop853_options), intent(in) :: opts !! controls
        real(dp), intent(inout) :: t_out(:)      !! requested output times, or step times [s]
        real(dp), intent(inout) :: y_out(:, :)   !! (size(y0), size(t_out)) states at t_out
        type(ode_stats), intent(out) :: stats    !! counters and status

#define KERNEL_ARGS t0, y0, t_end, rtol, atol, opts, t_out, y_out, stats
#include "stickslip_kernel_dispatch.inc"
#undef KERNEL_ARGS
    end subroutine dop853_integrate

    ! The integrator's instances: generic_kernel for any ode_system (a user's own), and one
    ! for each built-in scene with each static law.
#define KERNEL_BODY "stickslip_dop853_body.inc"
#include "stickslip_kernel_instances.inc"
#undef KERNEL_BODY

    !> Validate tolerances, the shared controls and DOP853's own.
    pure function check_options(n, t0, t_end, rtol, atol, opts) result(status)
        integer, intent(in) :: n
        real(dp), intent(in) :: t0, t_end, rtol(:), atol(:)
        type(dop853_options), intent(in) :: opts
        integer :: status
        status = check_tolerances(n, rtol, atol)
        if (status == SS_OK) status = check_step_controls(opts, t0, t_end)
        if (status == SS_OK) status = check_erk_constants(opts%safety, opts%fac1, opts%fac2, opts%beta, &
                                                          opts%nstiff)
    end function check_options

end module stickslip_dop853
