!> The built-in systems of the registry's SCENE_TABLE as models: each preset builds the
!! `model_system` (`stickslip_model_system`) of its scene from the scene's parameters and a
!! friction law, and every method runs it like any user's model.
!!
!! - `slope_model`: one body of unit mass (the slope's mass cancels) on the ground, pulled
!!   down the slope by the force g sin(theta) [N/kg], normal force g cos(theta) [N/kg]; x along
!!   the slope, down positive; the law sees v.
!! - `belt_model`: a mass on a spring k to the wall (the ground), on a belt moving at v_b,
!!   normal force m g, per unit mass (mass 1, spring k / m, normal force g: the motion is the
!!   same, and every number the scene's own); the law sees the belt's slip under the mass, v_b - v (the mass is the
!!   contact's side b, the ground side a with the surface velocity -v_b).
!! - `chain_model`: n_blocks such masses (Burridge-Knopoff), per unit mass as the belt: block
!!   1 on a spring k + k_p to the wall, block i > 1 on a loading spring k_p to the wall (where
!!   k_p > 0) and a coupling spring k_c to block i - 1; every block on the belt with normal
!!   force m g_i,
!!   g_i = g (1 + perturbation r_i) (`chain_r`: a deterministic equidistributed spread in
!!   [-1, 1), r_1 = 0, so a one-block chain is the belt with k + k_p).
!!
!! State y = (x_1..x_N [m], v_1..v_N [m/s], then the law's states block by block), as every
!! model's. The adaptive methods' error norm weighs |y| (`slip_error_size` off), as it did
!! before the scenes became models. A law's internal states follow the slip the law sees (v on the slope, v_b - v_i
!! on the belt and the chain).
module stickslip_presets
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law
    use stickslip_signal, only: SIG_CONST
    use stickslip_model_system, only: model_system
    implicit none
    private

    public :: slope_model, belt_model, chain_model, chain_r

    integer, parameter, public :: SS_BAD_M = -111       !! m out of range
    integer, parameter, public :: SS_BAD_G = -112       !! g out of range
    integer, parameter, public :: SS_BAD_THETA = -113   !! theta_deg out of range
    integer, parameter, public :: SS_BAD_K = -114       !! k out of range
    integer, parameter, public :: SS_BAD_V_B = -115     !! v_b not finite

    !> The scenes' parameters with the paper's values (Table 1) and ours where it is silent.
    type(param_spec), parameter, public :: G_SPEC = param_spec(name='g', default=9.81_dp, &
        unit='m/s^2', lo=0.0_dp, code=SS_BAD_G, doc='gravity')
    type(param_spec), parameter, public :: THETA_SPEC = param_spec(name='theta_deg', default=10.0_dp, &
        unit='deg', lo=-90.0_dp, hi=90.0_dp, code=SS_BAD_THETA, doc='slope inclination')
    !! slope inclination theta_deg in [-90, 90] [deg]
    type(param_spec), parameter, public :: M_SPEC = param_spec(name='m', default=10.0_dp, &
        unit='kg', lo=0.0_dp, lo_open=.true., code=SS_BAD_M, doc='mass')
    !! mass m, > 0 [kg]
    type(param_spec), parameter, public :: K_SPEC = param_spec(name='k', default=300.0_dp, &
        unit='N/m', lo=0.0_dp, code=SS_BAD_K, doc='spring stiffness')
    !! spring stiffness k, >= 0 [N/m]
    type(param_spec), parameter, public :: V_B_SPEC = param_spec(name='v_b', default=1.5_dp, &
        unit='m/s', code=SS_BAD_V_B, doc='belt speed')
    !! belt speed v_b, finite [m/s]


    integer, parameter, public :: SS_BAD_N_BLOCKS = -116      !! n_blocks not an integer in range
    integer, parameter, public :: SS_BAD_K_C = -117           !! k_c out of range
    integer, parameter, public :: SS_BAD_PERTURBATION = -118  !! perturbation out of range
    integer, parameter, public :: SS_BAD_K_P = -119           !! k_p out of range

    !> Largest number of blocks: the state (N (2 + nz) values) and the work arrays of every
    !! method grow linearly in N; 10^6 blocks keep one state under 50 MB for the largest law.
    integer, parameter, public :: MAX_BLOCKS = 1000000

    type(param_spec), parameter, public :: N_BLOCKS_SPEC = param_spec(name='n_blocks', default=1.0_dp, &
        unit='-', lo=1.0_dp, hi=real(MAX_BLOCKS, dp), relation='an integer', code=SS_BAD_N_BLOCKS, &
        doc='number of blocks of the chain')
    !! number of blocks N, an integer in [1, MAX_BLOCKS] [-]
    type(param_spec), parameter, public :: K_C_SPEC = param_spec(name='k_c', default=300.0_dp, &
        unit='N/m', lo=0.0_dp, default_of='k', code=SS_BAD_K_C, doc='coupling spring between blocks')
    !! coupling spring stiffness k_c, >= 0, default k [N/m]
    type(param_spec), parameter, public :: PERTURBATION_SPEC = param_spec(name='perturbation', &
        default=0.01_dp, unit='-', lo=0.0_dp, hi=0.5_dp, code=SS_BAD_PERTURBATION, &
        doc='relative spread of the blocks'' normal forces')
    !! amplitude of the deterministic spread of the normal forces, in [0, 0.5] [-]
    type(param_spec), parameter, public :: K_P_SPEC = param_spec(name='k_p', default=0.0_dp, &
        unit='N/m', lo=0.0_dp, code=SS_BAD_K_P, doc='loading spring from each block to the wall')
    !! loading spring stiffness k_p from every block to the wall, >= 0 [N/m]

    real(dp), parameter :: deg = acos(-1.0_dp) / 180.0_dp

contains

    !> The perturbation sequence r_i in [-1, 1), r_1 = 0 [-].
    elemental real(dp) function chain_r(i) result(r)
        integer, intent(in) :: i    !! block index, >= 1
        real(dp), parameter :: PHI = 0.6180339887498948482_dp
        r = 0.5_dp + real(i - 1, dp) * PHI
        r = 2.0_dp * (r - aint(r)) - 1.0_dp
    end function chain_r

    !> The slope (g, theta_deg in p) with `law` as a model; SS_OK or the code of the bad
    !! parameter.
    function slope_model(law, p, sys) result(status)
        class(friction_law), intent(in) :: law  !! a validated friction law
        type(param_values), intent(in) :: p     !! resolved parameter values
        type(model_system), intent(out) :: sys  !! the model, prepared
        integer :: status
        real(dp) :: g, theta_deg
        status = SS_OK
        call param_read(p, G_SPEC, g, status)
        call param_read(p, THETA_SPEC, theta_deg, status)
        if (status /= SS_OK) return
        call start(sys, [1.0_dp], [g * sin(theta_deg * deg), g * cos(theta_deg * deg)])
        sys%frc_body = [1]
        sys%frc_sig = [1]
        call contacts(sys, law, [1], [2], [0], .false.)
    end function slope_model

    !> The belt (m, g, k, v_b in p) with `law` as a model; SS_OK or the code of the bad parameter.
    function belt_model(law, p, sys) result(status)
        class(friction_law), intent(in) :: law  !! a validated friction law
        type(param_values), intent(in) :: p     !! resolved parameter values
        type(model_system), intent(out) :: sys  !! the model, prepared
        integer :: status
        real(dp) :: m, g, k, v_b
        status = SS_OK
        call param_read(p, M_SPEC, m, status)
        call param_read(p, G_SPEC, g, status)
        call param_read(p, K_SPEC, k, status)
        call param_read(p, V_B_SPEC, v_b, status)
        if (status /= SS_OK) return
        call start(sys, [1.0_dp], [g, -v_b])
        sys%spr_a = [1]
        sys%spr_b = [0]
        sys%spr_k = [k / m]
        sys%spr_l0 = [0.0_dp]
        call contacts(sys, law, [1], [1], [2], .true.)
    end function belt_model

    !> The chain (n_blocks, k_c, k_p, perturbation, m, g, k, v_b in p) with `law` as a model;
    !! SS_OK or the code of the bad parameter.
    function chain_model(law, p, sys) result(status)
        class(friction_law), intent(in) :: law  !! a validated friction law
        type(param_values), intent(in) :: p     !! resolved parameter values
        type(model_system), intent(out) :: sys  !! the model, prepared
        integer :: status
        real(dp) :: m, g, k, kc, kp, pert, v_b, nbr
        integer :: i, nb, ns
        status = SS_OK
        call param_read(p, N_BLOCKS_SPEC, nbr, status)
        call param_read(p, K_C_SPEC, kc, status)
        call param_read(p, K_P_SPEC, kp, status)
        call param_read(p, PERTURBATION_SPEC, pert, status)
        call param_read(p, M_SPEC, m, status)
        call param_read(p, G_SPEC, g, status)
        call param_read(p, K_SPEC, k, status)
        call param_read(p, V_B_SPEC, v_b, status)
        if (status == SS_OK .and. nbr /= aint(nbr)) status = SS_BAD_N_BLOCKS
        if (status /= SS_OK) return
        nb = int(nbr)
        ! signals: -v_b, then each block's normal force
        call start(sys, [(1.0_dp, i = 1, nb)], [-v_b, g, (g * (1.0_dp + pert * chain_r(i)), i = 2, nb)])
        ns = nb + merge(nb - 1, 0, kp > 0.0_dp)
        deallocate(sys%spr_a, sys%spr_b, sys%spr_k, sys%spr_l0)
        allocate(sys%spr_a(ns), sys%spr_b(ns), sys%spr_k(ns), sys%spr_l0(ns))
        sys%spr_l0 = 0.0_dp
        sys%spr_a(1) = 1
        sys%spr_b(1) = 0
        sys%spr_k(1) = (k + kp) / m
        ns = 1
        do i = 2, nb
            if (kp > 0.0_dp) then
                ns = ns + 1
                sys%spr_a(ns) = i
                sys%spr_b(ns) = 0
                sys%spr_k(ns) = kp / m
            end if
            ns = ns + 1
            sys%spr_a(ns) = i
            sys%spr_b(ns) = i - 1
            sys%spr_k(ns) = kc / m
        end do
        call contacts(sys, law, [(i, i = 1, nb)], [(i + 1, i = 1, nb)], [(1, i = 1, nb)], .true.)
    end function chain_model

    !> The bodies' masses [kg] and constant signals (numbers), and no element yet.
    subroutine start(sys, mass, numbers)
        type(model_system), intent(inout) :: sys
        real(dp), intent(in) :: mass(:), numbers(:)
        integer :: i, n
        n = size(numbers)
        sys%nb = size(mass)
        sys%mass = mass
        allocate(sys%spr_a(0), sys%spr_b(0), sys%spr_k(0), sys%spr_l0(0), sys%dmp_a(0), sys%dmp_b(0), &
                 sys%dmp_c(0), sys%frc_body(0), sys%frc_sig(0))
        sys%sig%op = [(SIG_CONST, i = 1, n)]
        allocate(sys%sig%arg(4, n))
        sys%sig%arg = 0.0_dp
        sys%sig%arg(1, :) = numbers
        sys%sig%start = [(i, i = 1, n + 1)]
        allocate(sys%sig%tab_t(0), sys%sig%tab_v(0))
    end subroutine start

    !> One contact per body of `bodies` with the ground, each with a copy of `law`, its normal
    !! force signal and its surface-velocity signal (0: none), the body on side a (the law sees
    !! its slip over the ground) or on side b (the law sees the ground's slip under it); then
    !! the model is prepared.
    subroutine contacts(sys, law, bodies, normal, surface, side_b)
        type(model_system), intent(inout) :: sys
        class(friction_law), intent(in) :: law
        integer, intent(in) :: bodies(:), normal(:), surface(:)
        logical, intent(in) :: side_b
        integer :: i, nc
        nc = size(bodies)
        if (side_b) then
            sys%con_a = [(0, i = 1, nc)]
            sys%con_b = bodies
        else
            sys%con_a = bodies
            sys%con_b = [(0, i = 1, nc)]
        end if
        sys%con_n = normal
        sys%con_w = surface
        allocate(sys%laws(nc), sys%z_first(nc + 1))
        sys%z_first = [(1 + (i - 1) * law%n_states(), i = 1, nc + 1)]
        do i = 1, nc
            allocate(sys%laws(i)%law, source=law)
        end do
        sys%con_same_law = [(i > 1, i = 1, nc)]
        sys%all_static = law%is_static()
        sys%slip_error_size = .false.
        call sys%prepare()
    end subroutine contacts

end module stickslip_presets
