!> Your own system from Fortran: a `stickslip_model` collects bodies, springs, dampers,
!! forces, frictional contacts and time signals, checks them, and runs them with any method
!! (`simulate`). The physics is `stickslip_model_system`'s; the Python `Model` and the C API
!! (`ss_model_*`) fill the same arrays and call the same `build` and `simulate`.
!!
!!     type(stickslip_model) :: m
!!     integer :: j1, j2, s
!!     j1 = m%add_body(1.0_dp, v0=10.0_dp)            ! bodies are numbered from 1; 0 is the ground
!!     j2 = m%add_body(1.0_dp)
!!     call m%add_spring(j1, 0, 100.0_dp)
!!     s = m%times(m%constant(20.0_dp), m%step(0.4_dp))
!!     call m%add_contact(j1, j2, 'coulomb', s, keys=['mu_s', 'mu_k'], vals=[0.55_dp, 0.5_dp])
!!     call m%simulate('event_driven', 1.5_dp, t_out, y_out, stats)
!!
!! Signals are numbered from 1 as they are made (`constant`, `step`, `ramp`, `sine`,
!! `table`, and `plus`, `minus`, `times` of two signals); a contact without a surface
!! velocity passes 0. Errors are status codes: `build` (and so `simulate`) names the first bad
!! element by its kind (`ELEM_*`) and its index.
module stickslip_user_model
    use stickslip_kinds, only: dp, SS_OK, SS_BAD_MODEL_EMPTY, SS_BAD_BODY, SS_BAD_MASS, SS_BAD_SPRING, &
                               SS_BAD_DAMPER, SS_BAD_SIGNAL, SS_BAD_LAW, SS_BAD_DIM, SS_BAD_Y0, SS_BAD_METHOD
    use stickslip_params, only: param_values, NAME_LEN
    use stickslip_ode, only: ode_stats
    use stickslip_signal, only: signal_set, SIG_CONST, SIG_STEP, SIG_RAMP, SIG_SINE, SIG_TABLE, SIG_ADD, &
                                SIG_SUB, SIG_MUL, signal_combine, signal_affine, signal_derivative, &
                                signal_integral
    use stickslip_model_system, only: model_system
    use stickslip_one_contact, only: specialise
    use stickslip_registry, only: make_law, code_of, integrate
    use stickslip_contact, only: contact_system
    use stickslip_contact_solver, only: forces_at_rest, contact_solve_info
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
    implicit none
    private

    public :: stickslip_model, model_from_arrays, control_step

    !> Kinds of model element, as `build` names the bad one.
    integer, parameter, public :: ELEM_BODY = 1, ELEM_SPRING = 2, ELEM_DAMPER = 3, ELEM_FORCE = 4, &
                                  ELEM_CONTACT = 5, ELEM_SIGNAL = 6, ELEM_DRIVE = 7

    !> What a drive's signal prescribes (`add_drive`): the body's position [m] or its velocity [m/s].
    integer, parameter, public :: DRIVE_POSITION = 1, DRIVE_VELOCITY = 2

    !> How a model with drives maps onto its system (`build`): the driven bodies leave the
    !! state, and each drive's position and velocity are signals of the system.
    type, public :: drive_plan
        integer, allocatable :: free(:)            !! (nb_free) the model's index of each body of the system
        integer, allocatable :: pos(:), vel(:)     !! (nd) each drive's position [m] and velocity [m/s] signals in sys%sig
    end type drive_plan

    !> A model under construction: the arrays of `model_system`, plus the laws by code and
    !! their given parameters (made and checked by `build`).
    type :: stickslip_model
        real(dp), allocatable :: mass(:)           !! (nb) mass [kg] or inertia [kg m^2]
        real(dp), allocatable :: x0(:), v0(:)      !! (nb) initial position [m] and velocity [m/s]
        integer, allocatable :: spr_a(:), spr_b(:) !! springs' bodies (0: the ground)
        real(dp), allocatable :: spr_k(:)          !! stiffness [N/m]
        real(dp), allocatable :: spr_l0(:)         !! x_a - x_b at rest [m]
        integer, allocatable :: dmp_a(:), dmp_b(:) !! dampers' bodies
        real(dp), allocatable :: dmp_c(:)          !! damping [N s/m]
        integer, allocatable :: frc_body(:)        !! forces' bodies
        integer, allocatable :: frc_sig(:)         !! forces' signals
        integer, allocatable :: con_a(:), con_b(:) !! contacts' bodies
        integer, allocatable :: con_law(:)         !! contacts' law codes (registry)
        integer, allocatable :: con_n(:), con_w(:) !! contacts' normal-force and surface-velocity signals
        integer, allocatable :: con_ptr(:)         !! (nc + 1) contact i's parameters are keys/vals(con_ptr(i) : con_ptr(i + 1) - 1)
        character(len=NAME_LEN), allocatable :: keys(:)  !! given law parameter names
        real(dp), allocatable :: vals(:)           !! their values [SI units]
        integer, allocatable :: drv_body(:)        !! drives' bodies
        integer, allocatable :: drv_kind(:)        !! drives' kinds (DRIVE_POSITION, DRIVE_VELOCITY)
        integer, allocatable :: drv_sig(:)         !! drives' signals [m or m/s]
        type(signal_set) :: sig                    !! the signals
        !> .true.: the adaptive methods' relative tolerance acts on each contact's slip
        !! (`model_system`'s `error_size`); .false.: on |y|, as in the presets (a scene's model)
        logical :: slip_error_size = .true.
    contains
        !> Add a body of mass (inertia) m [kg] at x0 [m] moving at v0 [m/s]; its index (from 1).
        procedure :: add_body
        !> Add a spring k [N/m] between bodies a and b (0: the ground), relaxed at x_a - x_b = rest_length [m].
        procedure :: add_spring
        !> Add a damper c [N s/m] between bodies a and b (0: the ground).
        procedure :: add_damper
        !> Add the force of a signal on a body [N].
        procedure :: add_force
        !> Add a frictional contact between a and b (0: the ground) with a law by name.
        procedure :: add_contact
        !> Prescribe a body's position or velocity by a signal (a kinematic constraint).
        procedure :: add_drive
        !> A signal: the number c; its index.
        procedure :: constant
        !> A signal: before up to time [s], after from then on; its index.
        procedure :: step
        !> A signal: 0, rising linearly by height over duration [s] from start [s]; its index.
        procedure :: ramp
        !> A signal: amplitude sin(2 pi frequency t + phase) + offset; its index.
        procedure :: sine
        !> A signal: linear in a table (t [s] strictly increasing, values), constant outside; its index.
        procedure :: table
        !> A signal: the sum of two signals; its index.
        procedure :: plus
        !> A signal: the difference of two signals; its index.
        procedure :: minus
        !> A signal: the product of two signals; its index.
        procedure :: times
        !> Check the model and make its system; SS_OK or the code, with the bad element.
        procedure :: build
        !> `build`, then the system as its structure allows (`specialise`): what every run takes.
        procedure :: build_run
        !> The initial state (x0, v0, law states 0).
        procedure :: initial_state
        !> The size of the model's state (every body's x, v, then the law states).
        procedure :: state_size
        !> Each drive's force on its body at the output rows of a run [N].
        procedure :: drive_forces
        !> Every body's initial state from the free bodies' and the law states (`build`'s plan).
        procedure :: free_state
        !> Every body's output from a run of the free bodies, and each drive's force.
        procedure :: finish_drives
        !> Run the model with a method by name from t = 0 to t_end.
        procedure :: simulate => model_simulate
    end type stickslip_model

    !> What a prepared run of a model with drives (`stickslip_simulate`'s prepared_simulation)
    !! adds to its system's run: the model (its bodies, elements and drives), its system as
    !! built (unspecialised: `drive_forces` reads it), the plan mapping the free bodies onto
    !! every body, and the run's method, first tolerances and step, which the forces read.
    type, public :: drive_run
        type(stickslip_model) :: model              !! the model
        type(model_system) :: sys                   !! its system as built (`build`)
        type(drive_plan) :: plan                    !! its drives (`build`)
        character(len=NAME_LEN) :: method = ''      !! the run's method (registry name)
        real(dp) :: rtol = 0.0_dp                   !! the run's first relative tolerance [-]
        real(dp) :: atol = 0.0_dp                   !! the run's first absolute tolerance [m/s]
        real(dp) :: h = 0.0_dp                      !! the run's step h (0: none given) [s]
    end type drive_run

contains

    !> Empty arrays for a model that has none yet.
    subroutine ensure(self)
        class(stickslip_model), intent(inout) :: self
        if (allocated(self%mass)) return
        allocate(self%mass(0), self%x0(0), self%v0(0), self%spr_a(0), self%spr_b(0), self%spr_k(0), &
                 self%spr_l0(0), self%dmp_a(0), self%dmp_b(0), self%dmp_c(0), self%frc_body(0), &
                 self%frc_sig(0), self%con_a(0), self%con_b(0), self%con_law(0), self%con_n(0), &
                 self%con_w(0), self%keys(0), self%vals(0), self%drv_body(0), self%drv_kind(0), self%drv_sig(0))
        self%con_ptr = [1]
        allocate(self%sig%op(0), self%sig%arg(4, 0), self%sig%tab_t(0), self%sig%tab_v(0))
        self%sig%start = [1]
    end subroutine ensure

    integer function add_body(self, mass, x0, v0) result(index)
        class(stickslip_model), intent(inout) :: self
        real(dp), intent(in) :: mass                !! mass [kg] or inertia [kg m^2], > 0
        real(dp), intent(in), optional :: x0        !! initial position [m] (default 0)
        real(dp), intent(in), optional :: v0        !! initial velocity [m/s] (default 0)
        call ensure(self)
        self%mass = [self%mass, mass]
        self%x0 = [self%x0, 0.0_dp]
        self%v0 = [self%v0, 0.0_dp]
        index = size(self%mass)
        if (present(x0)) self%x0(index) = x0
        if (present(v0)) self%v0(index) = v0
    end function add_body

    subroutine add_spring(self, a, b, k, rest_length)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: a                    !! body, >= 1
        integer, intent(in) :: b                    !! body, or 0 for the ground
        real(dp), intent(in) :: k                   !! stiffness, >= 0 [N/m]
        real(dp), intent(in), optional :: rest_length  !! x_a - x_b at rest (default 0) [m]
        call ensure(self)
        self%spr_a = [self%spr_a, a]
        self%spr_b = [self%spr_b, b]
        self%spr_k = [self%spr_k, k]
        self%spr_l0 = [self%spr_l0, 0.0_dp]
        if (present(rest_length)) self%spr_l0(size(self%spr_l0)) = rest_length
    end subroutine add_spring

    subroutine add_damper(self, a, b, c)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: a                    !! body, >= 1
        integer, intent(in) :: b                    !! body, or 0 for the ground
        real(dp), intent(in) :: c                   !! damping, >= 0 [N s/m]
        call ensure(self)
        self%dmp_a = [self%dmp_a, a]
        self%dmp_b = [self%dmp_b, b]
        self%dmp_c = [self%dmp_c, c]
    end subroutine add_damper

    subroutine add_force(self, body, signal)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: body                 !! body, >= 1
        integer, intent(in) :: signal               !! the force's signal [N]
        call ensure(self)
        self%frc_body = [self%frc_body, body]
        self%frc_sig = [self%frc_sig, signal]
    end subroutine add_force

    subroutine add_contact(self, a, b, law, normal_force, surface_velocity, keys, vals)
        class(stickslip_model), intent(inout) :: self
        !> body, >= 1 (the friction force -mu N acts on it), or 0 for the ground when b is a
        !! body (the law then sees the ground's slip under b, -v_b - w: the belt preset's contact)
        integer, intent(in) :: a
        integer, intent(in) :: b                    !! body, or 0 for the ground (it gets +mu N)
        character(len=*), intent(in) :: law         !! the law's name (registry)
        integer, intent(in) :: normal_force         !! the normal force's signal [N] (<= 0: open)
        integer, intent(in), optional :: surface_velocity  !! the surface's velocity signal [m/s] (default none: 0)
        character(len=*), intent(in), optional :: keys(:)  !! the law's given parameters
        real(dp), intent(in), optional :: vals(:)          !! their values [SI units]
        call ensure(self)
        self%con_a = [self%con_a, a]
        self%con_b = [self%con_b, b]
        self%con_law = [self%con_law, code_of('law', law)]
        self%con_n = [self%con_n, normal_force]
        self%con_w = [self%con_w, 0]
        if (present(surface_velocity)) self%con_w(size(self%con_w)) = surface_velocity
        if (present(keys) .and. present(vals)) then
            self%keys = [character(len=NAME_LEN) :: self%keys, keys]
            self%vals = [self%vals, vals(:size(keys))]
        end if
        self%con_ptr = [self%con_ptr, size(self%keys) + 1]
    end subroutine add_contact

    !> Prescribe the motion of a body: its position (kind DRIVE_POSITION, a signal without
    !! steps [m]) or its velocity (DRIVE_VELOCITY, the position then x0 + its integral [m/s])
    !! follows the signal exactly under every method. The body leaves the state: each element
    !! joined to it acts on the other body as an element on the ground plus a signal.
    subroutine add_drive(self, body, signal, kind)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: body                 !! body, >= 1
        integer, intent(in) :: signal               !! the drive's signal
        integer, intent(in) :: kind                 !! DRIVE_POSITION or DRIVE_VELOCITY
        call ensure(self)
        self%drv_body = [self%drv_body, body]
        self%drv_sig = [self%drv_sig, signal]
        self%drv_kind = [self%drv_kind, kind]
    end subroutine add_drive

    !> Append one primitive operation as a new signal; its index.
    integer function primitive(self, op, arg) result(index)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: op
        real(dp), intent(in) :: arg(4)
        real(dp), allocatable :: a(:, :)
        call ensure(self)
        self%sig%op = [self%sig%op, op]
        allocate(a(4, size(self%sig%op)))
        a(:, :size(self%sig%op) - 1) = self%sig%arg
        a(:, size(self%sig%op)) = arg
        call move_alloc(a, self%sig%arg)
        self%sig%start = [self%sig%start, size(self%sig%op) + 1]
        index = size(self%sig%start) - 1
    end function primitive

    integer function constant(self, c) result(index)
        class(stickslip_model), intent(inout) :: self
        real(dp), intent(in) :: c                   !! the value
        index = primitive(self, SIG_CONST, [c, 0.0_dp, 0.0_dp, 0.0_dp])
    end function constant

    integer function step(self, time, before, after) result(index)
        class(stickslip_model), intent(inout) :: self
        real(dp), intent(in) :: time                !! the step's time [s]
        real(dp), intent(in), optional :: before    !! the value before it (default 0)
        real(dp), intent(in), optional :: after     !! the value from it on (default 1)
        real(dp) :: b, a
        b = 0.0_dp
        a = 1.0_dp
        if (present(before)) b = before
        if (present(after)) a = after
        index = primitive(self, SIG_STEP, [time, b, a, 0.0_dp])
    end function step

    integer function ramp(self, start, duration, height) result(index)
        class(stickslip_model), intent(inout) :: self
        real(dp), intent(in) :: start               !! when it starts rising [s]
        real(dp), intent(in) :: duration            !! how long it rises, > 0 [s]
        real(dp), intent(in) :: height              !! the value it reaches
        index = primitive(self, SIG_RAMP, [start, duration, height, 0.0_dp])
    end function ramp

    integer function sine(self, amplitude, frequency, phase, offset) result(index)
        class(stickslip_model), intent(inout) :: self
        real(dp), intent(in) :: amplitude           !! amplitude
        real(dp), intent(in) :: frequency           !! frequency [Hz]
        real(dp), intent(in), optional :: phase     !! phase (default 0) [rad]
        real(dp), intent(in), optional :: offset    !! offset (default 0)
        real(dp) :: p, o
        p = 0.0_dp
        o = 0.0_dp
        if (present(phase)) p = phase
        if (present(offset)) o = offset
        index = primitive(self, SIG_SINE, [amplitude, frequency, p, o])
    end function sine

    integer function table(self, t, values) result(index)
        class(stickslip_model), intent(inout) :: self
        real(dp), intent(in) :: t(:)                !! times, strictly increasing [s]
        real(dp), intent(in) :: values(:)           !! values at those times (same size)
        integer :: first
        call ensure(self)
        first = size(self%sig%tab_t) + 1
        self%sig%tab_t = [self%sig%tab_t, t]
        self%sig%tab_v = [self%sig%tab_v, values]
        index = primitive(self, SIG_TABLE, [real(first, dp), real(size(t), dp), 0.0_dp, 0.0_dp])
        if (size(values) /= size(t)) self%sig%arg(2, size(self%sig%op)) = 0.0_dp   ! malformed: build says so
    end function table

    !> Append s1 op s2 as a new signal (`signal_combine`); its index.
    integer function combine(self, s1, s2, op) result(index)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: s1, s2, op
        call ensure(self)
        index = signal_combine(self%sig, s1, s2, op)
    end function combine

    integer function plus(self, s1, s2) result(index)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: s1                   !! a signal
        integer, intent(in) :: s2                   !! another signal
        index = combine(self, s1, s2, SIG_ADD)
    end function plus

    integer function minus(self, s1, s2) result(index)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: s1                   !! a signal
        integer, intent(in) :: s2                   !! the signal subtracted
        index = combine(self, s1, s2, SIG_SUB)
    end function minus

    integer function times(self, s1, s2) result(index)
        class(stickslip_model), intent(inout) :: self
        integer, intent(in) :: s1                   !! a signal
        integer, intent(in) :: s2                   !! another signal
        index = combine(self, s1, s2, SIG_MUL)
    end function times

    !> Check every element and make the model's system (`stickslip_model_system`). On an error,
    !! status names what is wrong (SS_BAD_BODY, SS_BAD_MASS, SS_BAD_SPRING, SS_BAD_DAMPER,
    !! SS_BAD_SIGNAL, SS_BAD_LAW, a law parameter's code, ...) and elem_kind (ELEM_*) and
    !! elem_index (from 1) the first bad element.
    subroutine build(self, sys, status, elem_kind, elem_index, plan)
        class(stickslip_model), intent(inout) :: self
        type(model_system), intent(out) :: sys      !! the system
        integer, intent(out) :: status              !! SS_OK or the error's code
        integer, intent(out) :: elem_kind           !! ELEM_* of the bad element (0: none)
        integer, intent(out) :: elem_index          !! its index, from 1 (0: none)
        type(drive_plan), intent(out), optional :: plan  !! how the model maps onto sys (its drives)
        type(param_values) :: p
        type(drive_plan) :: dp_
        integer :: i, nb, nsig, err, nc, nd, a, b, da, db
        integer, allocatable :: driven(:)
        call ensure(self)
        status = SS_OK
        elem_kind = 0
        elem_index = 0
        nb = size(self%mass)
        nsig = self%sig%count()
        if (nb == 0) then
            status = SS_BAD_MODEL_EMPTY
            return
        end if
        do i = 1, nb
            if (.not. (ieee_is_finite(self%mass(i)) .and. self%mass(i) > 0.0_dp)) call fail(SS_BAD_MASS, ELEM_BODY, i)
            if (.not. (ieee_is_finite(self%x0(i)) .and. ieee_is_finite(self%v0(i)))) call fail(SS_BAD_Y0, ELEM_BODY, i)
            if (status /= SS_OK) return
        end do
        call self%sig%check(err, i)
        if (err /= 0) call fail(SS_BAD_SIGNAL, ELEM_SIGNAL, i)
        if (status /= SS_OK) return
        do i = 1, size(self%spr_k)
            if (.not. pair_ok(self%spr_a(i), self%spr_b(i))) call fail(SS_BAD_BODY, ELEM_SPRING, i)
            if (.not. (ieee_is_finite(self%spr_k(i)) .and. self%spr_k(i) >= 0.0_dp .and. &
                       ieee_is_finite(self%spr_l0(i)))) call fail(SS_BAD_SPRING, ELEM_SPRING, i)
            if (status /= SS_OK) return
        end do
        do i = 1, size(self%dmp_c)
            if (.not. pair_ok(self%dmp_a(i), self%dmp_b(i))) call fail(SS_BAD_BODY, ELEM_DAMPER, i)
            if (.not. (ieee_is_finite(self%dmp_c(i)) .and. self%dmp_c(i) >= 0.0_dp)) &
                call fail(SS_BAD_DAMPER, ELEM_DAMPER, i)
            if (status /= SS_OK) return
        end do
        do i = 1, size(self%frc_body)
            if (self%frc_body(i) < 1 .or. self%frc_body(i) > nb) call fail(SS_BAD_BODY, ELEM_FORCE, i)
            if (self%frc_sig(i) < 1 .or. self%frc_sig(i) > nsig) call fail(SS_BAD_SIGNAL, ELEM_FORCE, i)
            if (status /= SS_OK) return
        end do
        nd = size(self%drv_body)
        allocate(driven(0:nb))
        driven = 0                                  ! the drive of each body (0: none; the ground: none)
        do i = 1, nd
            if (self%drv_body(i) < 1 .or. self%drv_body(i) > nb) then
                call fail(SS_BAD_BODY, ELEM_DRIVE, i)
            else if (driven(self%drv_body(i)) /= 0) then
                call fail(SS_BAD_BODY, ELEM_DRIVE, i)
            end if
            if (self%drv_sig(i) < 1 .or. self%drv_sig(i) > nsig .or. &
                (self%drv_kind(i) /= DRIVE_POSITION .and. self%drv_kind(i) /= DRIVE_VELOCITY)) &
                call fail(SS_BAD_SIGNAL, ELEM_DRIVE, i)
            if (status /= SS_OK) return
            driven(self%drv_body(i)) = i
        end do
        if (nd > 0 .and. count(driven(1:) == 0) == 0) call fail(SS_BAD_MODEL_EMPTY, ELEM_DRIVE, nd)
        if (status /= SS_OK) return
        nc = size(self%con_a)
        if (size(self%con_ptr) /= nc + 1 .or. size(self%keys) /= size(self%vals)) then
            status = SS_BAD_DIM
            return
        end if
        allocate(sys%laws(nc), sys%z_first(nc + 1), sys%con_same_law(nc))
        sys%z_first(1) = 1
        sys%con_same_law = .false.
        do i = 1, nc
            ! a contact's side a may be the ground when its side b is a body (the presets'
            ! belt: the law sees the surface's slip under the body)
            if (.not. (pair_ok(self%con_a(i), self%con_b(i)) .or. &
                       (self%con_a(i) == 0 .and. pair_ok(self%con_b(i), 0)))) then
                call fail(SS_BAD_BODY, ELEM_CONTACT, i)
            else if (.not. (free(self%con_a(i)) .or. free(self%con_b(i)))) then
                call fail(SS_BAD_BODY, ELEM_CONTACT, i)     ! no free body: it moves nothing
            end if
            if (self%con_n(i) < 1 .or. self%con_n(i) > nsig .or. self%con_w(i) < 0 .or. self%con_w(i) > nsig) &
                call fail(SS_BAD_SIGNAL, ELEM_CONTACT, i)
            if (self%con_law(i) < 1) call fail(SS_BAD_LAW, ELEM_CONTACT, i)
            if (status /= SS_OK) return
            status = make_law(self%con_law(i), self%keys(self%con_ptr(i):self%con_ptr(i + 1) - 1), &
                              self%vals(self%con_ptr(i):self%con_ptr(i + 1) - 1), sys%laws(i)%law, p)
            if (status /= SS_OK) then
                elem_kind = ELEM_CONTACT
                elem_index = i
                return
            end if
            sys%z_first(i + 1) = sys%z_first(i) + sys%laws(i)%law%n_states()
            if (i > 1) sys%con_same_law(i) = same_law(self, i - 1, i)
            if (.not. sys%laws(i)%law%is_static()) sys%all_static = .false.
        end do
        call reduce(dp_)
        if (status /= SS_OK) return
        if (present(plan)) plan = dp_
        sys%slip_error_size = self%slip_error_size
        call sys%prepare()
    contains
        logical function pair_ok(a, b)
            integer, intent(in) :: a, b
            pair_ok = a >= 1 .and. a <= nb .and. b >= 0 .and. b <= nb .and. a /= b
        end function pair_ok

        !> Whether body j (0: the ground) is a body without a drive.
        logical function free(j)
            integer, intent(in) :: j
            free = j >= 1 .and. j <= nb
            if (free) free = driven(j) == 0
        end function free

        !> The system of the free bodies: each element joined to a driven body acts on the
        !! other body as an element on the ground plus a signal (a spring k to a body at x_d(t):
        !! a spring to the ground and the force k (x_d(t) + l0); a damper: c v_d(t); a contact:
        !! a surface moving at v_d(t)); a driven body's forces leave the system.
        subroutine reduce(plan)
            type(drive_plan), intent(out) :: plan
            integer :: red(0:nb), k, j
            logical :: ok
            sys%sig = self%sig
            allocate(plan%pos(nd), plan%vel(nd))
            do k = 1, nd
                if (self%drv_kind(k) == DRIVE_POSITION) then
                    plan%pos(k) = self%drv_sig(k)
                    call signal_derivative(sys%sig, self%drv_sig(k), plan%vel(k), ok)
                else
                    plan%vel(k) = self%drv_sig(k)
                    call signal_integral(sys%sig, self%drv_sig(k), j, ok)
                    if (ok) plan%pos(k) = signal_affine(sys%sig, j, 1.0_dp, self%x0(self%drv_body(k)))
                end if
                if (.not. ok) then
                    call fail(SS_BAD_SIGNAL, ELEM_DRIVE, k)
                    return
                end if
            end do
            plan%free = pack([(k, k = 1, nb)], driven(1:) == 0)
            red = 0
            red(plan%free) = [(k, k = 1, size(plan%free))]
            sys%nb = size(plan%free)
            sys%mass = self%mass(plan%free)
            allocate(sys%spr_a(0), sys%spr_b(0), sys%spr_k(0), sys%spr_l0(0), sys%dmp_a(0), sys%dmp_b(0), &
                     sys%dmp_c(0), sys%frc_body(0), sys%frc_sig(0))
            do k = 1, size(self%spr_k)
                call ends(self%spr_a(k), self%spr_b(k))
                if (da == 0 .and. db == 0) then
                    call spring(red(a), red(b), self%spr_k(k), self%spr_l0(k), 0)
                else if (da == 0) then
                    call spring(red(a), 0, self%spr_k(k), 0.0_dp, &
                                signal_affine(sys%sig, plan%pos(db), self%spr_k(k), self%spr_k(k) * self%spr_l0(k)))
                else if (b > 0 .and. db == 0) then
                    call spring(red(b), 0, self%spr_k(k), 0.0_dp, &
                                signal_affine(sys%sig, plan%pos(da), self%spr_k(k), -self%spr_k(k) * self%spr_l0(k)))
                end if
            end do
            do k = 1, size(self%dmp_c)
                call ends(self%dmp_a(k), self%dmp_b(k))
                if (da == 0 .and. db == 0) then
                    call damper(red(a), red(b), self%dmp_c(k), 0)
                else if (da == 0) then
                    call damper(red(a), 0, self%dmp_c(k), signal_affine(sys%sig, plan%vel(db), self%dmp_c(k), 0.0_dp))
                else if (b > 0 .and. db == 0) then
                    call damper(red(b), 0, self%dmp_c(k), signal_affine(sys%sig, plan%vel(da), self%dmp_c(k), 0.0_dp))
                end if
            end do
            do k = 1, size(self%frc_body)
                if (driven(self%frc_body(k)) /= 0) cycle
                sys%frc_body = [sys%frc_body, red(self%frc_body(k))]
                sys%frc_sig = [sys%frc_sig, self%frc_sig(k)]
            end do
            sys%con_a = self%con_a
            sys%con_b = self%con_b
            sys%con_n = self%con_n
            sys%con_w = self%con_w
            do k = 1, nc       ! a contact keeps its index; its free body becomes its side a
                call ends(self%con_a(k), self%con_b(k))
                if (da == 0 .and. db == 0) then
                    sys%con_a(k) = red(a)
                    sys%con_b(k) = red(b)
                else if (da == 0) then          ! slip v_a - (v_d + w)
                    sys%con_a(k) = red(a)
                    sys%con_b(k) = 0
                    sys%con_w(k) = plan%vel(db)
                    if (self%con_w(k) > 0) sys%con_w(k) = signal_combine(sys%sig, plan%vel(db), self%con_w(k), SIG_ADD)
                else                            ! slip v_b - (v_d - w): the opposite of v_d - v_b - w
                    sys%con_a(k) = red(b)
                    sys%con_b(k) = 0
                    sys%con_w(k) = plan%vel(da)
                    if (self%con_w(k) > 0) sys%con_w(k) = signal_combine(sys%sig, plan%vel(da), self%con_w(k), SIG_SUB)
                end if
            end do
        end subroutine reduce

        !> An element's bodies a, b and their drives da, db (0: free or the ground).
        subroutine ends(ea, eb)
            integer, intent(in) :: ea, eb
            a = ea
            b = eb
            da = driven(a)
            db = driven(b)
        end subroutine ends

        !> A spring of the system and, for a signal f > 0, the force f on body a.
        subroutine spring(a, b, k, l0, f)
            integer, intent(in) :: a, b, f
            real(dp), intent(in) :: k, l0
            sys%spr_a = [sys%spr_a, a]
            sys%spr_b = [sys%spr_b, b]
            sys%spr_k = [sys%spr_k, k]
            sys%spr_l0 = [sys%spr_l0, l0]
            if (f > 0) call force(a, f)
        end subroutine spring

        !> A damper of the system and, for a signal f > 0, the force f on body a.
        subroutine damper(a, b, c, f)
            integer, intent(in) :: a, b, f
            real(dp), intent(in) :: c
            sys%dmp_a = [sys%dmp_a, a]
            sys%dmp_b = [sys%dmp_b, b]
            sys%dmp_c = [sys%dmp_c, c]
            if (f > 0) call force(a, f)
        end subroutine damper

        subroutine force(a, f)
            integer, intent(in) :: a, f
            sys%frc_body = [sys%frc_body, a]
            sys%frc_sig = [sys%frc_sig, f]
        end subroutine force
        subroutine fail(code, kind, index)
            integer, intent(in) :: code, kind, index
            if (status /= SS_OK) return
            status = code
            elem_kind = kind
            elem_index = index
        end subroutine fail
    end subroutine build

    !> Contacts i and j name the same law with the same parameters, given alike (so their
    !! laws are equal; `model_system%con_same_law`).
    pure logical function same_law(self, i, j)
        class(stickslip_model), intent(in) :: self
        integer, intent(in) :: i, j          !! contacts, from 1
        integer :: i0, j0, ni
        i0 = self%con_ptr(i)
        j0 = self%con_ptr(j)
        ni = self%con_ptr(i + 1) - i0
        same_law = self%con_law(i) == self%con_law(j) .and. ni == self%con_ptr(j + 1) - j0
        if (.not. same_law .or. ni == 0) return
        same_law = all(self%keys(i0:i0 + ni - 1) == self%keys(j0:j0 + ni - 1)) .and. &
                   all(self%vals(i0:i0 + ni - 1) == self%vals(j0:j0 + ni - 1))
    end function same_law

    !> `build`, then the system with its structure found once (`stickslip_one_contact`'s
    !! `specialise`, as for a scene's preset): a model of one body with one contact with the
    !! ground and only numbers as signals runs the integrators' kernels for that structure.
    subroutine build_run(self, sys, run, status, elem_kind, elem_index, plan)
        class(stickslip_model), intent(inout) :: self
        type(model_system), intent(out) :: sys                   !! the system as built
        class(model_system), allocatable, intent(out) :: run     !! the same, specialised (on SS_OK)
        integer, intent(out) :: status              !! SS_OK or the error's code
        integer, intent(out) :: elem_kind           !! ELEM_* of the bad element (0: none)
        integer, intent(out) :: elem_index          !! its index, from 1 (0: none)
        type(drive_plan), intent(out), optional :: plan  !! how the model maps onto sys (its drives)
        call self%build(sys, status, elem_kind, elem_index, plan)
        if (status == SS_OK) call specialise(sys, run)
    end subroutine build_run

    !> (x0, v0, 0 for every law state) of a built system.
    function initial_state(self, sys) result(y0)
        class(stickslip_model), intent(in) :: self
        type(model_system), intent(in) :: sys       !! the model's system (`build`)
        real(dp), allocatable :: y0(:)              !! the initial state
        integer :: nb
        nb = size(self%mass)
        allocate(y0(self%state_size(sys)))
        y0 = 0.0_dp
        y0(:nb) = self%x0
        y0(nb + 1:2 * nb) = self%v0
    end function initial_state

    !> Every body's position and velocity (the driven ones' too), then the law states of a
    !! built system.
    pure integer function state_size(self, sys) result(n)
        class(stickslip_model), intent(in) :: self
        type(model_system), intent(in) :: sys       !! the model's system (`build`)
        n = 2 * size(self%mass) + sys%n_states() - 2 * sys%nb
    end function state_size

    !> The force each drive applies to its body at the rows (t(j), y(:, j)) of a run of the
    !! model: m_d a_d minus the other forces on the driven body (springs, dampers, forces,
    !! and the friction of its contacts as their laws give it at that state). Under the
    !! set-valued methods (event_driven, moreau) the friction is the set-valued laws': a
    !! contact at rest (|w| <= tol: event_driven's atol + rtol times the largest velocity,
    !! moreau's MOREAU_REST_TOL times it, at least 1 m/s) holds
    !! with the force that keeps its relative acceleration at zero, from the contact solver's
    !! problem at rest (`forces_at_rest`); NaN where that problem has no solution. NaN where a
    !! contact joins the driven body under implicit_euler or galpha with coulomb or karnopp
    !! (the force of a law's band or jump is not a function of the state there).
    subroutine drive_forces(self, sys, plan, method, t, y, force, rtol, atol, h)
        class(stickslip_model), intent(in) :: self
        type(model_system), intent(inout) :: sys    !! the model's system (`build`)
        type(drive_plan), intent(in) :: plan        !! its drives (`build`)
        character(len=*), intent(in) :: method      !! the run's method
        real(dp), intent(in) :: t(:)                !! output times [s]
        real(dp), intent(in) :: y(:, :)             !! (state_size, size(t)) every body's state [m, m/s, ...]
        real(dp), intent(out) :: force(:, :)        !! (number of drives, size(t)) [N]
        real(dp), intent(in) :: rtol                !! the run's relative tolerance (event_driven) [-]
        real(dp), intent(in) :: atol                !! the run's absolute tolerance (event_driven) [m/s]
        real(dp), intent(in) :: h                   !! the run's step (moreau; 0: none) [s]
        real(dp) :: fric(size(self%con_a)), x(size(self%mass)), v(size(self%mass)), yr(sys%n_states())
        real(dp) :: f, fe, rate, pos, acc, ta, tb
        real(dp) :: wtol(size(self%con_a)), bt(size(self%con_a)), ba(size(self%con_a)), bb(size(self%con_a))
        integer :: j, k, i, d, nb, nf, status
        logical :: set_valued, jumps
        class(contact_system), allocatable :: cs
        type(contact_solve_info) :: info
        !> |w| at rest relative to the largest velocity under moreau, whose stuck contacts
        !! have w = 0 at the steps to rounding (and output rows between steps to O(h^2)) [-]
        real(dp), parameter :: MOREAU_REST_TOL = 1.0e-8_dp
        nb = size(self%mass)
        nf = sys%nb
        set_valued = method == 'event_driven' .or. method == 'moreau'
        jumps = (method == 'implicit_euler' .or. method == 'galpha') .and. sys%has_jumps()
        if (set_valued) call sys%contact_model(cs, status)
        do j = 1, size(t)
            x = y(1:nb, j)
            v = y(nb + 1:2 * nb, j)
            yr(1:nf) = x(plan%free)
            yr(nf + 1:2 * nf) = v(plan%free)
            yr(2 * nf + 1:) = y(2 * nb + 1:, j)
            if (set_valued) then
                ! at rest: w within the integration's tolerance (event_driven), or within
                ! MOREAU_REST_TOL of the largest velocity plus what the output's linear
                ! interpolation between moreau's steps (of size h) leaves of a stuck contact's
                ! w = 0: its offset b(t) less b interpolated (rtol, atol are not moreau's)
                wtol = MOREAU_REST_TOL * max(maxval(abs(v)), 1.0_dp)
                if (method == 'event_driven') then
                    wtol = atol + rtol * max(maxval(abs(v)), 1.0_dp)
                else if (h > 0.0_dp) then
                    ta = h * aint(t(j) / h)
                    tb = min(ta + h, t(size(t)))
                    if (tb > ta .and. t(j) > ta) then
                        call cs%slip_offset(t(j), bt)
                        call cs%slip_offset(ta, ba)
                        call cs%slip_offset(tb, bb)
                        wtol = wtol + abs(bt - (ba * (tb - t(j)) + bb * (t(j) - ta)) / (tb - ta))
                    end if
                end if
                call forces_at_rest(cs, t(j), yr(1:nf), yr(nf + 1:2 * nf), wtol, fric, info)
                if (.not. info%ok) fric = ieee_value(f, ieee_quiet_nan)
            else
                call sys%friction(t(j), yr, fric)
            end if
            do k = 1, size(self%drv_body)
                d = self%drv_body(k)
                call sys%sig%eval(plan%vel(k), t(j), pos, acc)
                f = self%mass(d) * acc
                do i = 1, size(self%spr_k)
                    if (self%spr_a(i) /= d .and. self%spr_b(i) /= d) cycle
                    pos = 0.0_dp
                    if (self%spr_b(i) > 0) pos = x(self%spr_b(i))
                    fe = -self%spr_k(i) * (x(self%spr_a(i)) - pos - self%spr_l0(i))
                    f = f - merge(fe, -fe, self%spr_a(i) == d)
                end do
                do i = 1, size(self%dmp_c)
                    if (self%dmp_a(i) /= d .and. self%dmp_b(i) /= d) cycle
                    pos = 0.0_dp
                    if (self%dmp_b(i) > 0) pos = v(self%dmp_b(i))
                    fe = -self%dmp_c(i) * (v(self%dmp_a(i)) - pos)
                    f = f - merge(fe, -fe, self%dmp_a(i) == d)
                end do
                do i = 1, size(self%frc_body)
                    if (self%frc_body(i) /= d) cycle
                    call self%sig%eval(self%frc_sig(i), t(j), fe, rate)
                    f = f - fe
                end do
                do i = 1, size(self%con_a)     ! the friction on d is the opposite of that on its free side
                    if (self%con_a(i) /= d .and. self%con_b(i) /= d) cycle
                    f = f + fric(i)
                    if (jumps) f = ieee_value(f, ieee_quiet_nan)
                end do
                force(k, j) = f
            end do
        end do
    end subroutine drive_forces

    !> The state a run of the free bodies starts from (`build`'s plan): the free bodies' x
    !! and v of y, then the law states.
    pure function free_state(self, plan, y) result(y_free)
        class(stickslip_model), intent(in) :: self
        type(drive_plan), intent(in) :: plan        !! its drives (`build`)
        real(dp), intent(in) :: y(:)                !! every body's x [m], v [m/s], then the law states
        real(dp), allocatable :: y_free(:)          !! the free bodies' x, v, then the law states
        integer :: nb
        nb = size(self%mass)
        y_free = [y(plan%free), y(nb + plan%free), y(2 * nb + 1:)]
    end function free_state

    !> Every body's output rows from a run of the free bodies (the driven ones' x and v from
    !! their signals) and, when asked, each drive's force (`drive_forces`): what a run of a
    !! model with drives ends with, one call or prepared.
    subroutine finish_drives(self, sys, plan, method, rtol, atol, h, t_out, y_free, y_out, drive_force)
        class(stickslip_model), intent(in) :: self
        type(model_system), intent(inout) :: sys    !! the model's system (`build`)
        type(drive_plan), intent(in) :: plan        !! its drives (`build`)
        character(len=*), intent(in) :: method      !! the run's method
        real(dp), intent(in) :: rtol                !! the run's relative tolerance [-]
        real(dp), intent(in) :: atol                !! the run's absolute tolerance [m/s]
        real(dp), intent(in) :: h                   !! the run's step (0: none) [s]
        real(dp), intent(in) :: t_out(:)            !! output times [s]
        real(dp), intent(in) :: y_free(:, :)        !! (sys%n_states(), size(t_out)) the free bodies' run
        real(dp), intent(inout) :: y_out(:, :)      !! (state_size, size(t_out)) every body's state
        !> (number of drives, size(t_out)): each drive's force on its body [N]
        real(dp), intent(out), optional :: drive_force(:, :)
        real(dp) :: rate
        integer :: nb, nf, j, k
        nb = size(self%mass)
        nf = sys%nb
        y_out(plan%free, :) = y_free(1:nf, :)
        y_out(nb + plan%free, :) = y_free(nf + 1:2 * nf, :)
        y_out(2 * nb + 1:, :) = y_free(2 * nf + 1:, :)
        do j = 1, size(t_out)
            do k = 1, size(self%drv_body)
                call sys%sig%eval(plan%pos(k), t_out(j), y_out(self%drv_body(k), j), rate)
                call sys%sig%eval(plan%vel(k), t_out(j), y_out(nb + self%drv_body(k), j), rate)
            end do
        end do
        if (present(drive_force)) call self%drive_forces(sys, plan, method, t_out, y_out, drive_force, rtol, atol, h)
    end subroutine finish_drives

    !> The step h among named controls (the value of the last named 'h'; 0 when none) [s].
    pure real(dp) function control_step(ckeys, cvals) result(h)
        character(len=*), intent(in) :: ckeys(:)    !! names of the controls
        real(dp), intent(in) :: cvals(:)            !! their values
        integer :: j
        h = 0.0_dp
        do j = 1, size(ckeys)
            if (ckeys(j) == 'h') h = cvals(j)
        end do
    end function control_step

    !> Run the model from t = 0 (its bodies' x0, v0; law states 0) to t_end with a method by
    !! name and its controls by name; output as `stickslip_simulate`'s. implicit_euler and
    !! galpha take laws with jumps (coulomb, karnopp) through `stickslip_modal_contacts` (all
    !! contacts' laws must then have jumps: SS_JUMP_MANY_CONTACTS otherwise); moreau and
    !! event_driven end with SS_NOT_SETVALUED when a contact's law has no set-valued form.
    subroutine model_simulate(self, method, t_end, t_out, y_out, stats, rtol, atol, ckeys, cvals, &
                              elem_kind, elem_index, stop_flag, events, y0, drive_force)
        class(stickslip_model), intent(inout) :: self
        character(len=*), intent(in) :: method      !! the method's name (registry)
        real(dp), intent(in) :: t_end               !! final time [s]
        real(dp), intent(inout) :: t_out(:)         !! requested output times, or room for every step [s]
        real(dp), intent(inout) :: y_out(:, :)      !! (n_states, size(t_out)) states
        type(ode_stats), intent(out) :: stats       !! counters and status
        real(dp), intent(in), optional :: rtol(:)   !! relative tolerance(s) (default 1e-6)
        real(dp), intent(in), optional :: atol(:)   !! absolute tolerance(s) (default 1e-9)
        character(len=*), intent(in), optional :: ckeys(:)  !! names of the given controls
        real(dp), intent(in), optional :: cvals(:)          !! their values
        integer, intent(out), optional :: elem_kind         !! ELEM_* of a bad element (0: none)
        integer, intent(out), optional :: elem_index        !! its index (0: none)
        !> A flag another thread may set nonzero to stop the run (SS_INTERRUPTED).
        integer, pointer, intent(in), optional :: stop_flag
        !> (4, room): the stick/slip events of event_driven, (t [s], kind, position [m], contact)
        real(dp), intent(inout), optional :: events(:, :)
        real(dp), intent(in), optional :: y0(:)     !! an initial state other than the bodies' (with law states)
        !> (number of drives, size(t_out)): each drive's force on its body [N] (`drive_forces`)
        real(dp), intent(out), optional :: drive_force(:, :)
        type(model_system) :: sys
        class(model_system), allocatable :: run   ! sys with its structure found (`specialise`)
        type(drive_plan) :: plan
        real(dp), allocatable :: rt(:), at(:), y_init(:), y_free(:, :)
        character(len=NAME_LEN), allocatable :: ck(:)
        real(dp), allocatable :: cv(:)
        integer :: ek, ei, code
        call self%build_run(sys, run, stats%status, ek, ei, plan)
        if (present(elem_kind)) elem_kind = ek
        if (present(elem_index)) elem_index = ei
        if (stats%status /= SS_OK) return
        code = code_of('method', method)
        if (code == 0) then
            stats%status = SS_BAD_METHOD
            return
        end if
        rt = [1.0e-6_dp]
        at = [1.0e-9_dp]
        if (present(rtol)) rt = rtol
        if (present(atol)) at = atol
        allocate(ck(0), cv(0))
        if (present(ckeys) .and. present(cvals)) then
            ck = ckeys
            cv = cvals
        end if
        if (present(y0)) then
            y_init = y0
        else
            y_init = self%initial_state(sys)
        end if
        if (size(y_init) /= self%state_size(sys) .or. size(y_out, 1) /= size(y_init) .or. &
            size(y_out, 2) /= size(t_out)) then
            stats%status = SS_BAD_DIM
            return
        end if
        if (present(drive_force)) then
            if (size(drive_force, 1) /= size(self%drv_body) .or. size(drive_force, 2) /= size(t_out)) then
                stats%status = SS_BAD_DIM
                return
            end if
        end if
        if (size(self%drv_body) == 0) then
            call integrate(code, run, 0.0_dp, y_init, t_end, rt, at, ck, cv, t_out, y_out, stats, stop_flag, events)
            return
        end if
        ! the free bodies' state; then every body's, the driven ones' from their signals
        allocate(y_free(sys%n_states(), size(t_out)))
        y_free = 0.0_dp
        call integrate(code, run, 0.0_dp, self%free_state(plan, y_init), t_end, rt, at, ck, cv, t_out, y_free, &
                       stats, stop_flag, events)
        call self%finish_drives(sys, plan, method, rt(1), at(1), control_step(ck, cv), t_out, y_free, y_out, &
                                drive_force)
    end subroutine model_simulate

    !> A model from arrays, one per kind of element (body indices as reals, from 1, 0 the
    !! ground), as the Python layer passes it: bodies(3, nb) = (mass, x0, v0), springs(4, ns) =
    !! (a, b, k, rest length), dampers(3, nd) = (a, b, c), forces(2, nf) = (body, signal),
    !! contacts(5, nc) = (a, b, law code, normal-force signal, surface-velocity signal or 0),
    !! their law parameters (names keys, values vals; contact i's from con_ptr(i) to
    !! con_ptr(i+1)-1), signals(5, nop) = (operation, its 4 arguments) with sig_start and
    !! tables(2, ntab) = (t, value) (stickslip_signal), drives(3, ndr) = (body, kind, signal).
    !! Checked by `build`, not here.
    subroutine model_from_arrays(m, bodies, springs, dampers, forces, contacts, con_ptr, keys, vals, signals, &
                                 sig_start, tables, drives, slip_error_size)
        type(stickslip_model), intent(out) :: m   !! the model
        real(dp), intent(in) :: bodies(:, :)      !! (3, nb) mass [kg], x0 [m], v0 [m/s] of each body
        real(dp), intent(in) :: springs(:, :)     !! (4, ns) a, b, k [N/m], rest length [m]
        real(dp), intent(in) :: dampers(:, :)     !! (3, nd) a, b, c [N s/m]
        real(dp), intent(in) :: forces(:, :)      !! (2, nf) body, signal
        real(dp), intent(in) :: contacts(:, :)    !! (5, nc) a, b, law code, normal force, surface velocity
        integer, intent(in) :: con_ptr(:)         !! (nc + 1) first parameter of each contact
        character(len=*), intent(in) :: keys(:)   !! the contacts' parameter names
        real(dp), intent(in) :: vals(:)           !! their values [SI units]
        real(dp), intent(in) :: signals(:, :)     !! (5, nop) the signals' operations
        integer, intent(in) :: sig_start(:)       !! first operation of each signal
        real(dp), intent(in) :: tables(:, :)      !! (2, ntab) the tables' points
        real(dp), intent(in) :: drives(:, :)      !! (3, ndr) the drives
        !> the adaptive methods' error size: on the contacts' slips (default) or on |y| (a
        !! scene's model: `stickslip_model`'s slip_error_size)
        logical, intent(in), optional :: slip_error_size
        if (present(slip_error_size)) m%slip_error_size = slip_error_size
        m%mass = bodies(1, :)
        m%x0 = bodies(2, :)
        m%v0 = bodies(3, :)
        m%spr_a = nint(springs(1, :))
        m%spr_b = nint(springs(2, :))
        m%spr_k = springs(3, :)
        m%spr_l0 = springs(4, :)
        m%dmp_a = nint(dampers(1, :))
        m%dmp_b = nint(dampers(2, :))
        m%dmp_c = dampers(3, :)
        m%frc_body = nint(forces(1, :))
        m%frc_sig = nint(forces(2, :))
        m%con_a = nint(contacts(1, :))
        m%con_b = nint(contacts(2, :))
        m%con_law = nint(contacts(3, :))
        m%con_n = nint(contacts(4, :))
        m%con_w = nint(contacts(5, :))
        m%con_ptr = con_ptr
        m%keys = keys
        m%vals = vals
        m%sig%op = nint(signals(1, :))
        m%sig%arg = signals(2:5, :)
        m%sig%start = sig_start
        m%sig%tab_t = tables(1, :)
        m%sig%tab_v = tables(2, :)
        m%drv_body = nint(drives(1, :))
        m%drv_kind = nint(drives(2, :))
        m%drv_sig = nint(drives(3, :))
    end subroutine model_from_arrays

end module stickslip_user_model
