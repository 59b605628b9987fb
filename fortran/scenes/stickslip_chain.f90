!> The chain scene: N blocks on the belt (the Burridge-Knopoff model of stick-slip with a
!! belt as the driver). Block i (mass m) lies on the belt moving at v_b with its own contact
!! (normal force m g_i) and the chosen friction law; block 1 is tied to the wall by a spring
!! k, block i to block i - 1 by a coupling spring k_c, and every block to the wall by a
!! loading spring k_p (default 0; Burridge and Knopoff's leaf springs to the driver plate, here
!! fixed while the belt moves):
!!   m x_i'' = -k x_1 [i = 1] - k_p x_i - k_c (x_i - x_{i-1}) [i > 1] - k_c (x_i - x_{i+1}) [i < N]
!!             + mu(v_b - x_i') m g_i,
!! x_i measured from block i's rest position (all springs at rest length when every x_i = 0).
!! Block 1's two springs to the wall act as one of stiffness k + k_p, so a one-block chain is
!! the belt with k + k_p (bit for bit).
!! The blocks' normal forces carry a small deterministic perturbation so that they do not
!! move in lockstep: g_i = g (1 + perturbation r_i), r_i = 2 frac(1/2 + (i - 1) phi) - 1 in
!! [-1, 1) with phi the golden ratio's fractional part (an equidistributed sequence; r_1 = 0,
!! so block 1, and a one-block chain, has m g exactly).
!!
!! State y (size N (2 + nz)): x_1..x_N [m], v_1..v_N [m/s], then the law's internal states
!! block by block (z of block 1, then of block 2, ...). With N = 1 this is the belt scene's
!! (x, v, z), and every expression reduces to the belt's, operation for operation.
!!
!! The Jacobian: analytic for a static law, finite differences otherwise. In the state's
!! order it is not banded (x_i' = v_i couples i and N + i), but in the order of the blocks,
!! (x_1, v_1, z_1, x_2, v_2, z_2, ...), it is, with ml = s + 1 lower and mu = s - 1 upper
!! diagonals (s = 2 + nz states per block): `bandwidth` gives that order and
!! `band_jacobian` the Jacobian in band storage, so that an implicit method costs O(N) a step.
!!
!! For the nonsmooth methods the chain is a `contact_system` with q = x, u = v, M = m I,
!! f = -K x (K tridiagonal), N_i = m g_i, w_i = v_i - v_b (per unit mass, as the belt's).
module stickslip_chain
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law
    use stickslip_ode, only: fd_jacobian, fd_band_jacobian, BOUND_MARGIN
    use stickslip_scenes, only: friction_scene, M_SPEC, G_SPEC, K_SPEC, V_B_SPEC
    use stickslip_contact, only: contact_system, contact_law, contact_law_of
    use stickslip_linalg, only: tridiagonal_solve
    use stickslip_roots, only: root_search
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: chain_scene, chain_contact, chain_r

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

    !> The chain as a first-order system with any friction law.
    type, extends(friction_scene) :: chain_scene
        integer :: nb = 1                 !! number of blocks N
        real(dp) :: k_m = 0.0_dp          !! (k + k_p) / m: block 1's springs to the wall [1/s^2]
        real(dp) :: kp_m = 0.0_dp         !! k_p / m [1/s^2]
        real(dp) :: kc_m = 0.0_dp         !! k_c / m [1/s^2]
        real(dp) :: v_b = 1.5_dp          !! belt speed [m/s]
        real(dp), allocatable :: g(:)     !! (N) normal force per unit mass of each block [m/s^2]
        real(dp), allocatable :: k_mg(:)  !! (N) wall springs over m g_i: (k + k_p) / (m g_1), k_p / (m g_i) [1/m]
        real(dp), allocatable :: kc_mg(:) !! (N) k_c / (m g_i) [1/m]
    contains
        procedure :: init => chain_init
        !! validate and store the parameters and the law
        procedure :: n_states => chain_n_states
        !! N (2 + nz)
        procedure :: rhs => chain_rhs
        !! (x, v, z)' at (t, y)
        procedure :: jacobian => chain_jacobian
        !! dense Jacobian (analytic for a static law)
        procedure :: bandwidth => chain_bandwidth
        !! the block order and its band
        procedure :: band_jacobian => chain_band_jacobian
        !! the Jacobian in block order, band storage
        procedure :: static_jacobian => chain_static_jacobian
        !! block 1's 2 x 2 Jacobian with a static law (of the one-block chain)
        procedure :: relative_velocity => chain_vrel
        !! block 1's relative velocity v_b - v_1 [m/s]
        procedure :: monitored_body => chain_monitored_body
        !! block 1's position [m] and velocity [m/s]
        procedure :: condensed_components => chain_condensed_components
        !! every block's law states, when the law solves their stage itself
        procedure :: condense_stage => chain_condense_stage
        !! each block's law states from the law's stage_states at its relative velocity
        procedure :: stage_rhs => chain_stage_rhs
        !! f at a stage state with the law's states moving at the stage's rates
        procedure :: contact_model => chain_contact_model
        !! the chain as a `chain_contact`
        procedure :: static_rhs => chain_static_rhs
        !! (x_1, v_1)' of the one-block chain for a static law, given its coefficient
        procedure :: holding_coefficient => chain_mu_hold
        !! block 1's holding coefficient [-]
        procedure :: set_relative_velocity => chain_set_vrel
        !! v_1 = v_b - w
        procedure :: state_bound => chain_state_bound
        !! BOUND_MARGIN times the energy bound of the blocks on their springs
        procedure :: scalar_stage => chain_scalar_stage
        !! the stage of a static law by nonlinear Gauss-Seidel over the blocks, each a bracketed
        !! scalar equation (where Newton's method fails: the proposed law's cusp at rest)
    end type chain_scene

    !> The chain with set-valued contacts, per unit mass: q = x [m], u = v [m/s], M = I,
    !! f = -K x [N/kg], N_i = g_i [N/kg], w_i = v_i - v_b.
    type, extends(contact_system) :: chain_contact
        real(dp) :: k_m = 0.0_dp          !! (k + k_p) / m: block 1's springs to the wall [1/s^2]
        real(dp) :: kp_m = 0.0_dp         !! k_p / m [1/s^2]
        real(dp) :: kc_m = 0.0_dp         !! k_c / m [1/s^2]
        real(dp) :: v_b = 1.5_dp          !! belt speed [m/s]
        real(dp), allocatable :: g(:)     !! (N) normal force per unit mass [m/s^2]
    contains
        procedure :: force => chain_contact_force
        !! f = -K x
        procedure :: solve_w => chain_contact_solve_w
        !! W = I + b K, tridiagonal
        procedure :: normal_forces => chain_contact_normal
        !! N_i = g_i
        procedure :: slip_offset => chain_contact_offset
        !! b_i = -v_b
        procedure :: w_tridiagonal => chain_contact_w_tridiagonal
        !! W's three diagonals
    end type chain_contact

contains

    !> The perturbation sequence r_i in [-1, 1), r_1 = 0 [-].
    elemental real(dp) function chain_r(i) result(r)
        integer, intent(in) :: i    !! block index, >= 1
        real(dp), parameter :: PHI = 0.6180339887498948482_dp
        r = 0.5_dp + real(i - 1, dp) * PHI
        r = 2.0_dp * (r - aint(r)) - 1.0_dp
    end function chain_r

    !> Fill the chain from n_blocks, k_c, k_p, perturbation, m, g, k, v_b in p.
    function chain_init(self, law, p) result(status)
        class(chain_scene), intent(inout) :: self
        class(friction_law), intent(in) :: law  !! a validated friction law
        type(param_values), intent(in) :: p     !! resolved parameter values
        integer :: status
        real(dp) :: m, g, k, kc, kp, pert, nbr
        integer :: i
        status = SS_OK
        call param_read(p, N_BLOCKS_SPEC, nbr, status)
        call param_read(p, K_C_SPEC, kc, status)
        call param_read(p, K_P_SPEC, kp, status)
        call param_read(p, PERTURBATION_SPEC, pert, status)
        call param_read(p, M_SPEC, m, status)
        call param_read(p, G_SPEC, g, status)
        call param_read(p, K_SPEC, k, status)
        call param_read(p, V_B_SPEC, self%v_b, status)
        if (status == SS_OK .and. nbr /= aint(nbr)) status = SS_BAD_N_BLOCKS
        if (status /= SS_OK) return
        if (allocated(self%law)) deallocate(self%law)
        allocate(self%law, source=law)
        self%nz = law%n_states()
        self%static_law = law%is_static()
        self%nb = int(nbr)
        self%k_m = (k + kp) / m
        self%kp_m = kp / m
        self%kc_m = kc / m
        allocate(self%g(self%nb), self%k_mg(self%nb), self%kc_mg(self%nb))
        do i = 1, self%nb
            self%g(i) = g
            if (i > 1) self%g(i) = g * (1.0_dp + pert * chain_r(i))
        end do
        self%k_mg = 0.0_dp
        self%kc_mg = 0.0_dp
        where (self%g > 0.0_dp)
            self%k_mg = self%kp_m / self%g
            self%kc_mg = self%kc_m / self%g
        end where
        if (self%g(1) > 0.0_dp) self%k_mg(1) = self%k_m / self%g(1)
    end function chain_init

    !> The chain's bounds on |y| from the energy per unit mass E = (sum v_i^2 + x^T K x)/2 (K the
    !! springs' matrix per unit mass, its eigenvalues below lambda = (k + k_p)/m + 4 k_c/m by
    !! Gershgorin): friction (|mu| <= mu_max on every block) changes sqrt(2E) by at most
    !! sqrt(N) max g_i mu_max a second, so |v_i| <= R = sqrt(sum v0_i^2 + lambda sum x0_i^2)
    !! + sqrt(N) max g_i mu_max T over T = t_end - t0 (+ |v_b|), and |x_i| <= max |x0| + R T;
    !! a law's states move at most twice the relative speed, |z| <= max |z0| + 2 (R + |v_b|) T.
    !! BOUND_MARGIN times these.
    function chain_state_bound(self, t0, y0, t_end) result(bound)
        class(chain_scene), intent(in) :: self
        real(dp), intent(in) :: t0          !! initial time [s]
        real(dp), intent(in) :: y0(:)       !! initial state (x_1..x_N [m], v_1..v_N [m/s], z...)
        real(dp), intent(in) :: t_end       !! final time [s]
        real(dp) :: bound(size(y0))         !! bounds on |x_i| [m], |v_i| [m/s], |z| [m]
        real(dp) :: tt, r0, r, amax
        integer :: n
        n = self%nb
        bound = huge(1.0_dp)
        if (size(y0) < 2 * n) return     ! not this chain's state: the methods refuse it
        tt = max(t_end - t0, 0.0_dp)
        r0 = sqrt(sum(y0(n + 1:2 * n)**2) + (self%k_m + 4.0_dp * self%kc_m) * sum(y0(1:n)**2))
        amax = sqrt(real(n, dp)) * maxval(abs(self%g))
        r = abs(self%v_b) + r0 + amax * max(self%law%mu_s, self%law%mu_k) * tt
        r = r0 + amax * self%mu_bound(r) * tt + abs(self%v_b)
        bound(1:n) = BOUND_MARGIN * (maxval(abs(y0(1:n))) + r * tt)
        bound(n + 1:2 * n) = BOUND_MARGIN * r
        if (size(y0) > 2 * n) bound(2 * n + 1:) = BOUND_MARGIN * (maxval(abs(y0(2 * n + 1:))) + &
                                                                  2.0_dp * (r + abs(self%v_b)) * tt)
    end function chain_state_bound

    pure integer function chain_n_states(self)
        class(chain_scene), intent(in) :: self
        chain_n_states = self%nb * (2 + self%nz)
    end function chain_n_states

    !> Spring acceleration of block i [m/s^2] and the coefficient that would hold it [-].
    pure subroutine spring(self, x, i, a, mu_hold)
        class(chain_scene), intent(in) :: self
        real(dp), intent(in)  :: x(:)       !! positions x_1..x_N [m]
        integer, intent(in)   :: i          !! block
        real(dp), intent(out) :: a          !! spring force per unit mass on block i [m/s^2]
        real(dp), intent(out) :: mu_hold    !! its holding coefficient [-]
        ! Operation for operation the belt's (-k_m x, k_mg x) when N = 1.
        if (i == 1) then
            a = -self%k_m * x(1)
            mu_hold = self%k_mg(1) * x(1)
        else
            a = -self%kc_m * (x(i) - x(i - 1))
            mu_hold = self%kc_mg(i) * (x(i) - x(i - 1))
            if (self%kp_m /= 0.0_dp) then     ! without loading springs, the chain's own numbers
                a = a - self%kp_m * x(i)
                mu_hold = mu_hold + self%k_mg(i) * x(i)
            end if
        end if
        if (i < self%nb) then
            a = a - self%kc_m * (x(i) - x(i + 1))
            mu_hold = mu_hold + self%kc_mg(i) * (x(i) - x(i + 1))
        end if
    end subroutine spring

    !> The stage k = f(t, u + c k) of a static law, where Newton's method fails (the proposed
    !! law's infinite slope at v_rel = 0, where a chain started stuck has every block): nonlinear
    !! Gauss-Seidel over the blocks. Block i's stage velocity v_i solves
    !! phi_i(v_i) = v_i - u_v,i - c a_i(x_s, v_i) = 0 with x_s = u_x + c v_s and its neighbours'
    !! stage velocities fixed, by the bracketed root of the one-contact scenes (`root_search`);
    !! sweeps repeat until no stage velocity changes by more than 8 eps (1 + |v|). The coupling
    !! per sweep is c^2 k_c / m against 1 + c^2 (k + 2 k_c) / m where the law's slope is >= 0, so
    !! the sweeps contract for any step a stable explicit method would take, and far beyond.
    !! Each block starts from its velocity at the stage's start (so one block is the belt's
    !! `scalar_stage`, operation for operation). k returns f at the roots, except the
    !! accelerations, which are the roots' own, (v_s - u_v) / c: a block stuck at the cusp has
    !! its root between two floats, where f jumps by ~ g mu_s (2e-16 / v_s)^(1/3), and f there
    !! would feed that jump into the method's derivative each step. ok = .false. for a law that
    !! is not static, or when a block has no bracket or 1000 sweeps do not converge.
    subroutine chain_scalar_stage(self, t, u, c, k, nfev, ok)
        class(chain_scene), intent(inout) :: self
        real(dp), intent(in)    :: t        !! stage time [s]
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative: a guess in, the solution out
        integer(8), intent(inout) :: nfev   !! evaluations of f, counted
        logical, intent(out)    :: ok       !! .true.: k solves the stage
        real(dp) :: vs(self%nb), xs(self%nb), vnew, change
        integer :: i, n, sweep
        type(root_search) :: search
        ok = .false.
        n = self%nb
        if (self%nz /= 0 .or. .not. self%static_law .or. size(u) /= 2 * n) return
        vs = u(n + 1:2 * n)     ! from the stage's start, as the one-contact scenes
        xs = u(1:n) + c * vs
        do sweep = 1, 1000
            change = 0.0_dp
            do i = 1, n
                call search%start(vs(i))
                do while (.not. search%done)
                    call search%tell(phi(search%x))
                end do
                if (.not. search%found) return
                vnew = search%root
                change = max(change, abs(vnew - vs(i)) / (1.0_dp + abs(vnew)))
                vs(i) = vnew
                xs(i) = u(i) + c * vnew
            end do
            if (change <= 8.0_dp * epsilon(1.0_dp) .or. n == 1) exit   ! (one block: its root)
        end do
        if (change > 8.0_dp * epsilon(1.0_dp) .and. n > 1) return
        call self%rhs(t, [xs, vs], k)
        nfev = nfev + 1
        k(n + 1:2 * n) = (vs - u(n + 1:2 * n)) / c   ! the roots' own accelerations (notes)
        ok = all(ieee_is_finite(k))
    contains
        !> phi_i(v) [m/s] of the block i of the sweep
        real(dp) function phi(v)
            real(dp), intent(in) :: v
            real(dp) :: a, mu_hold
            xs(i) = u(i) + c * v
            call spring(self, xs, i, a, mu_hold)
            nfev = nfev + 1
            phi = v - u(n + i) - c * (a + self%law%mu(self%v_b - v) * self%g(i))
        end function phi
    end subroutine chain_scalar_stage

    subroutine chain_rhs(self, t, y, dydt)
        class(chain_scene), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s] (unused: autonomous)
        real(dp), intent(in)  :: y(:)       !! (x_1..x_N [m], v_1..v_N [m/s], z block by block)
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], accelerations [m/s^2], z rates)
        call chain_f(self, y, dydt)
    end subroutine chain_rhs

    !> The chain's f at y: the law's states at the rates of `evaluate`, or, given a stage
    !! derivative k, at k's rates with mu from the law's `stage_mu` (chain_stage_rhs).
    subroutine chain_f(self, y, dydt, k)
        class(chain_scene), intent(inout) :: self
        real(dp), intent(in)  :: y(:)       !! (x_1..x_N [m], v_1..v_N [m/s], z block by block)
        real(dp), intent(out) :: dydt(:)    !! (v [m/s], accelerations [m/s^2], z rates)
        real(dp), intent(in), optional :: k(:)   !! stage derivative (its law states' part read)
        real(dp) :: a, mu_hold, mu
        integer :: i, n, nz, iz
        n = self%nb
        nz = self%nz
        do i = 1, n
            call spring(self, y(1:n), i, a, mu_hold)
            iz = 2 * n + (i - 1) * nz
            if (present(k)) then
                dydt(iz + 1:iz + nz) = k(iz + 1:iz + nz)
                mu = self%law%stage_mu(self%v_b - y(n + i), y(iz + 1:iz + nz), dydt(iz + 1:iz + nz))
            else if (self%static_law) then
                mu = self%law%mu(self%v_b - y(n + i))
            else
                call self%law%evaluate(self%v_b - y(n + i), y(iz + 1:iz + nz), mu_hold, mu, dydt(iz + 1:iz + nz))
            end if
            dydt(i) = y(n + i)
            dydt(n + i) = a + mu * self%g(i)
        end do
    end subroutine chain_f

    !> The dense Jacobian: analytic for a static law, finite differences otherwise.
    subroutine chain_jacobian(self, t, y, f, dfdy, nfev)
        class(chain_scene), intent(inout) :: self
        real(dp), intent(in)    :: t             !! time [s]
        real(dp), intent(in)    :: y(:)          !! state
        real(dp), intent(in)    :: f(:)          !! f(t, y)
        real(dp), intent(out)   :: dfdy(:, :)    !! (n, n) Jacobian in the state's order
        integer(8), intent(inout) :: nfev        !! evaluation counter (+ n for finite differences)
        integer :: i, n
        if (.not. self%static_law) then
            call fd_jacobian(self, t, y, f, dfdy, nfev)
            return
        end if
        n = self%nb
        dfdy = 0.0_dp
        do i = 1, n
            dfdy(i, n + i) = 1.0_dp
            dfdy(n + i, i) = -merge(self%k_m, self%kp_m, i == 1) - merge(self%kc_m, 0.0_dp, i > 1) &
                             - merge(self%kc_m, 0.0_dp, i < n)
            ! gfortran -Wdo-subscript: a false positive, i - 1 >= 1 under the guard i > 1
            if (i > 1) dfdy(n + i, i - 1) = self%kc_m
            if (i < n) dfdy(n + i, i + 1) = self%kc_m
            dfdy(n + i, n + i) = -self%g(i) * self%law%dmu(self%v_b - y(n + i))
        end do
    end subroutine chain_jacobian

    !> The block order perm (state index of each position: x_1, v_1, z_1, x_2, ...) and the
    !! band of the Jacobian in that order: ml = s + 1, mu = s - 1 (s = 2 + nz).
    subroutine chain_bandwidth(self, perm, ml, mu)
        class(chain_scene), intent(in) :: self
        integer, intent(out) :: perm(:)     !! (n) state index at each position of the block order
        integer, intent(out) :: ml          !! lower bandwidth
        integer, intent(out) :: mu          !! upper bandwidth
        integer :: i, k, s, n
        n = self%nb
        s = 2 + self%nz
        do i = 1, n
            perm((i - 1) * s + 1) = i
            perm((i - 1) * s + 2) = n + i
            do k = 1, self%nz
                perm((i - 1) * s + 2 + k) = 2 * n + (i - 1) * self%nz + k
            end do
        end do
        ml = min(s + 1, n * s - 1)
        mu = min(s - 1, n * s - 1)
    end subroutine chain_bandwidth

    !> The Jacobian in block order in band storage, jb(mu + 1 + i - j, j) = J(perm(i), perm(j)):
    !! analytic for a static law; otherwise by finite differences that perturb every
    !! (ml + mu + 1)-th position of the block order together (Curtis, Powell and Reid):
    !! ml + mu + 1 = 2 s + 1 evaluations whatever N.
    subroutine chain_band_jacobian(self, t, y, f, jb, nfev)
        class(chain_scene), intent(inout) :: self
        real(dp), intent(in)    :: t             !! time [s]
        real(dp), intent(in)    :: y(:)          !! state
        real(dp), intent(in)    :: f(:)          !! f(t, y)
        real(dp), intent(out)   :: jb(:, :)      !! (ml + mu + 1, n) band of the reordered Jacobian
        integer(8), intent(inout) :: nfev        !! evaluation counter (+ evaluations made here)
        integer :: perm(size(y)), ml, mu, i, j, n, s
        call self%bandwidth(perm, ml, mu)
        n = self%nb
        s = 2 + self%nz
        jb = 0.0_dp
        if (self%static_law) then
            ! position (i-1) s + 1 is x_i, (i-1) s + 2 is v_i
            do i = 1, n
                j = (i - 1) * s
                jb(mu + 1 + (j + 1) - (j + 2), j + 2) = 1.0_dp                      ! d x_i' / d v_i
                jb(mu + 1 + 1, j + 1) = -merge(self%k_m, self%kp_m, i == 1) - merge(self%kc_m, 0.0_dp, i > 1) &
                                        - merge(self%kc_m, 0.0_dp, i < n)             ! d v_i' / d x_i
                if (i > 1) jb(mu + 1 + (j + 2) - (j + 1 - s), j + 1 - s) = self%kc_m   ! d v_i' / d x_{i-1}
                if (i < n) jb(mu + 1 + (j + 2) - (j + 1 + s), j + 1 + s) = self%kc_m   ! d v_i' / d x_{i+1}
                jb(mu + 1, j + 2) = -self%g(i) * self%law%dmu(self%v_b - y(n + i))     ! d v_i' / d v_i
            end do
            return
        end if
        call fd_band_jacobian(self, t, y, f, perm, ml, mu, jb, nfev)
    end subroutine chain_band_jacobian

    pure function chain_static_jacobian(self, y) result(j)
        class(chain_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)     !! state
        real(dp) :: j(2, 2)              !! d(v_1, a_1)/d(x_1, v_1) of the one-block chain
        j(1, 1) = 0.0_dp
        j(2, 1) = -self%k_m
        j(1, 2) = 1.0_dp
        j(2, 2) = -self%g(1) * self%law%dmu(self%v_b - y(self%nb + 1))
    end function chain_static_jacobian

    pure function chain_vrel(self, y) result(vr)
        class(chain_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)    !! state
        real(dp) :: vr                  !! block 1's relative sliding velocity v_b - v_1 [m/s]
        vr = self%v_b - y(self%nb + 1)
    end function chain_vrel

    pure function chain_monitored_body(self, y) result(xv)
        class(chain_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)    !! state (x_1..x_N [m], v_1..v_N [m/s], z)
        real(dp) :: xv(2)               !! (x_1 [m], v_1 [m/s])
        xv = [y(1), y(self%nb + 1)]
    end function chain_monitored_body

    subroutine chain_condensed_components(self, mask)
        class(chain_scene), intent(in) :: self
        logical, intent(out) :: mask(:)     !! (N (2 + nz)) .true. for the law's states
        mask = .false.
        if (self%law%condenses_states()) mask(2 * self%nb + 1:) = .true.
    end subroutine chain_condensed_components

    subroutine chain_condense_stage(self, u, c, k)
        class(chain_scene), intent(inout) :: self
        real(dp), intent(in)    :: u(:)     !! the stage state is u + c k
        real(dp), intent(in)    :: c        !! coefficient of k in the stage state [s]
        real(dp), intent(inout) :: k(:)     !! stage derivative; the law states' part on exit
        real(dp) :: z_s(self%nz)
        integer :: i, n, iz
        if (.not. self%law%condenses_states() .or. c <= 0.0_dp) return
        n = self%nb
        do i = 1, n
            iz = 2 * n + (i - 1) * self%nz
            call self%law%stage_states(self%v_b - (u(n + i) + c * k(n + i)), u(iz + 1:iz + self%nz), c, z_s)
            k(iz + 1:iz + self%nz) = (z_s - u(iz + 1:iz + self%nz)) / c
        end do
    end subroutine chain_condense_stage

    subroutine chain_stage_rhs(self, t, y, k, f)
        class(chain_scene), intent(inout) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: y(:)       !! stage state (x_1..x_N [m], v_1..v_N [m/s], z)
        real(dp), intent(in)  :: k(:)       !! stage derivative (the law states' part read)
        real(dp), intent(out) :: f(:)       !! (v [m/s], accelerations [m/s^2], z rates)
        if (self%law%condenses_states()) then
            call chain_f(self, y, f, k)
        else
            call chain_f(self, y, f)
        end if
    end subroutine chain_stage_rhs

    !> (x, v)' of the one-block chain (the belt) for a static law whose coefficient at the
    !! relative velocity is mu (as chain_static_jacobian: the modes' stage solve of the
    !! implicit methods reads it for a two-component state only).
    pure subroutine chain_static_rhs(self, y, mu, dydt)
        class(chain_scene), intent(in) :: self
        real(dp), intent(in)  :: y(:)       !! (x_1 [m], v_1 [m/s])
        real(dp), intent(in)  :: mu         !! the law's coefficient at the relative velocity [-]
        real(dp), intent(out) :: dydt(:)    !! (v_1 [m/s], acceleration [m/s^2])
        dydt(1) = y(2)
        dydt(2) = -self%k_m * y(1) + mu * self%g(1)
    end subroutine chain_static_rhs

    !> Block 1's holding coefficient: its spring force over its normal force [-].
    pure function chain_mu_hold(self, y) result(mu_hold)
        class(chain_scene), intent(in) :: self
        real(dp), intent(in) :: y(:)    !! state (x_1..x_N [m], v_1..v_N [m/s], z)
        real(dp) :: mu_hold             !! coefficient that would hold block 1 on the belt [-]
        real(dp) :: a
        call spring(self, y(1:self%nb), 1, a, mu_hold)
    end function chain_mu_hold

    !> Set block 1's velocity so that its relative sliding velocity is w: v_1 = v_b - w.
    pure subroutine chain_set_vrel(self, y, w)
        class(chain_scene), intent(in) :: self
        real(dp), intent(inout) :: y(:) !! state; y(N + 1) = v_b - w on exit
        real(dp), intent(in) :: w       !! relative sliding velocity [m/s]
        y(self%nb + 1) = self%v_b - w
    end subroutine chain_set_vrel

    subroutine chain_contact_model(self, cs, status)
        class(chain_scene), intent(in) :: self
        class(contact_system), allocatable, intent(out) :: cs  !! a chain_contact (also when
                                                               !! SS_NOT_SETVALUED: its laws then
                                                               !! the default, its structure the
                                                               !! chain's)
        integer, intent(out) :: status                         !! SS_OK or SS_NOT_SETVALUED
        type(chain_contact) :: cc
        type(contact_law) :: cl
        integer :: i
        call contact_law_of(self%law, cl, status)
        cc%n_dof = self%nb
        cc%n_c = self%nb
        cc%h_ptr = [(i, i = 1, self%nb + 1)]
        cc%h_col = [(i, i = 1, self%nb)]
        allocate(cc%h_val(self%nb), source=1.0_dp)
        allocate(cc%laws(self%nb), source=cl)
        cc%w_constant = .true.
        cc%k_m = self%k_m
        cc%kp_m = self%kp_m
        cc%kc_m = self%kc_m
        cc%v_b = self%v_b
        cc%g = self%g
        allocate(cs, source=cc)
    end subroutine chain_contact_model

    subroutine chain_contact_force(self, t, q, u, f)
        class(chain_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! positions [m]
        real(dp), intent(in)  :: u(:)       !! velocities [m/s]
        real(dp), intent(out) :: f(:)       !! spring forces per unit mass [N/kg]
        integer :: i, n
        n = self%n_dof
        do i = 1, n
            if (i == 1) then
                f(1) = -self%k_m * q(1)
            else
                ! gfortran -Wdo-subscript: a false positive, i >= 2 in this branch
                f(i) = -self%kc_m * (q(i) - q(i - 1))
                if (self%kp_m /= 0.0_dp) f(i) = f(i) - self%kp_m * q(i)
            end if
            if (i < n) f(i) = f(i) - self%kc_m * (q(i) - q(i + 1))
        end do
    end subroutine chain_contact_force

    !> W = I + b K: its diagonal d, sub-diagonal l (l(1) unused) and super-diagonal r (r(N)
    !! unused); ok = .true. for N > 1 (one block keeps Moreau's one-contact closed form,
    !! the belt's, result for result).
    subroutine chain_contact_w_tridiagonal(self, a, b, l, d, r, ok)
        class(chain_contact), intent(in) :: self
        real(dp), intent(in)  :: a          !! weight of C [s] (C = 0)
        real(dp), intent(in)  :: b          !! weight of K [s^2]
        real(dp), intent(out) :: l(:)       !! W(i, i - 1) [-]
        real(dp), intent(out) :: d(:)       !! W(i, i) [-]
        real(dp), intent(out) :: r(:)       !! W(i, i + 1) [-]
        logical, intent(out)  :: ok         !! .true.: W is tridiagonal
        integer :: i, n
        n = self%n_dof
        do i = 1, n
            d(i) = merge(self%k_m, self%kp_m, i == 1) + merge(self%kc_m, 0.0_dp, i > 1) &
                   + merge(self%kc_m, 0.0_dp, i < n)
            d(i) = 1.0_dp + b * d(i)
            l(i) = -b * self%kc_m
            r(i) = -b * self%kc_m
        end do
        ok = n > 1
    end subroutine chain_contact_w_tridiagonal

    !> x := W^-1 x by the Thomas algorithm (W = I + b K is symmetric positive definite and
    !! diagonally dominant: no pivoting needed), O(N).
    subroutine chain_contact_solve_w(self, t, q, u, a, b, x)
        class(chain_contact), intent(in) :: self
        real(dp), intent(in)    :: t        !! time [s]
        real(dp), intent(in)    :: q(:)     !! positions [m]
        real(dp), intent(in)    :: u(:)     !! velocities [m/s]
        real(dp), intent(in)    :: a        !! weight of C [s] (C = 0)
        real(dp), intent(in)    :: b        !! weight of K [s^2]
        real(dp), intent(inout) :: x(:)     !! right-hand side [N s/kg], then the solution [m/s]
        real(dp) :: l(self%n_dof), d(self%n_dof), r(self%n_dof)
        logical :: ok
        if (self%n_dof == 1) then    ! the belt's x / (m + b k) with m = 1
            x(1) = x(1) / (1.0_dp + b * self%k_m)
            return
        end if
        call self%w_tridiagonal(a, b, l, d, r, ok)
        call tridiagonal_solve(l, d, r, x)
    end subroutine chain_contact_solve_w

    subroutine chain_contact_normal(self, t, q, n)
        class(chain_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(in)  :: q(:)       !! positions [m]
        real(dp), intent(out) :: n(:)       !! g_i [N/kg]
        n = self%g
    end subroutine chain_contact_normal

    subroutine chain_contact_offset(self, t, b)
        class(chain_contact), intent(in) :: self
        real(dp), intent(in)  :: t          !! time [s]
        real(dp), intent(out) :: b(:)       !! -v_b [m/s]
        b = -self%v_b
    end subroutine chain_contact_offset

end module stickslip_chain
