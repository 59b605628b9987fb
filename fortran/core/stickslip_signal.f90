!> Time signals of a model (`stickslip_model`): forces, normal forces and surface velocities
!! given as functions of time, evaluated in Fortran (never by a callback into Python).
!!
!! A set of signals is one program of postfix operations: signal i is the operations
!! op(start(i) : start(i + 1) - 1), evaluated on a stack of (value, rate) pairs, so that sums,
!! differences and products of signals and numbers need no tree. The primitives, with their
!! arguments arg(1:4) of the operation:
!!   - SIG_CONST (c): c;
!!   - SIG_STEP (time [s], before, after): before for t < time, after from t = time on;
!!   - SIG_RAMP (start [s], duration [s] > 0, height): 0 before start, rising linearly to
!!     height over the duration, height after;
!!   - SIG_SINE (amplitude, frequency [Hz], phase [rad], offset):
!!     amplitude sin(2 pi frequency t + phase) + offset;
!!   - SIG_TABLE (first, count): the table tab_t(first : first + count - 1) [s] (strictly
!!     increasing) with values tab_v(...), linear between its points, held constant outside.
!! and the operators SIG_ADD, SIG_SUB and SIG_MUL on the two top entries. Units are those of
!! what the signal drives (N for a force, m/s for a surface velocity).
!!
!! The rate of a signal is its time derivative (right-sided at a corner: a step's is 0, a
!! ramp's the slope after its start); the corners (a step's time, a ramp's start and end, a
!! table's points) are its breakpoints, where the methods with events restart.
module stickslip_signal
    use stickslip_kinds, only: dp, SS_OK
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: signal_set
    public :: signal_combine, signal_affine, signal_derivative, signal_integral

    integer, parameter, public :: SIG_CONST = 1   !! a number
    integer, parameter, public :: SIG_STEP = 2    !! a step at a time
    integer, parameter, public :: SIG_RAMP = 3    !! a linear ramp
    integer, parameter, public :: SIG_SINE = 4    !! a sine
    integer, parameter, public :: SIG_TABLE = 5   !! a table, linear between its points
    integer, parameter, public :: SIG_ADD = 6     !! the sum of the two top entries
    integer, parameter, public :: SIG_SUB = 7     !! their difference (lower minus top)
    integer, parameter, public :: SIG_MUL = 8     !! their product

    !> What is wrong with a signal program (`signal_set%check`).
    integer, parameter, public :: SIG_ERR_OP = 1        !! an unknown operation, or a program that leaves not one value
    integer, parameter, public :: SIG_ERR_ARG = 2       !! an argument not finite
    integer, parameter, public :: SIG_ERR_DURATION = 3  !! a ramp's duration <= 0
    integer, parameter, public :: SIG_ERR_TABLE = 4     !! a table empty, outside tab_t, or not strictly increasing

    real(dp), parameter :: two_pi = 2.0_dp * acos(-1.0_dp)

    !> The duration and height of a ramp that never ends in any run (`signal_integral`):
    !! 2^600 s (about 4e180 s), a power of 2 so that its value is t - start exactly.
    real(dp), parameter :: ENDLESS = 2.0_dp**600

    !> A postfix program (operations and their arguments), being built (`signal_combine`).
    type :: program_t
        integer, allocatable :: op(:)
        real(dp), allocatable :: arg(:, :)
    end type program_t

    !> Signals as one postfix program (see the module notes).
    type :: signal_set
        integer, allocatable :: op(:)           !! operation codes SIG_*
        real(dp), allocatable :: arg(:, :)      !! (4, size(op)) their arguments
        integer, allocatable :: start(:)        !! (n + 1) signal i is op(start(i) : start(i + 1) - 1)
        real(dp), allocatable :: tab_t(:)       !! the tables' times [s]
        real(dp), allocatable :: tab_v(:)       !! the tables' values
    contains
        !> Number of signals.
        procedure :: count => signal_count
        !> Value and rate of signal i at t.
        procedure :: eval => signal_eval
        !> The first breakpoint of signal i after t (huge when none) [s].
        procedure :: next_break => signal_next_break
        !> 0 when every signal is well formed; else the code SIG_ERR_* and the signal.
        procedure :: check => signal_check
        !> .true. when signal i is a number (a constant).
        procedure :: is_number => signal_is_number
        !> The value of signal i, a number (`is_number`).
        procedure :: number => signal_number
        !> The shortest period of any sine in the signals (huge when none) [s].
        procedure :: shortest_period => signal_shortest_period
        !> A bound on |signal i (t)| over all t.
        procedure :: sup => signal_sup
    end type signal_set

contains

    pure integer function signal_count(self) result(n)
        class(signal_set), intent(in) :: self
        n = 0
        if (allocated(self%start)) n = size(self%start) - 1
    end function signal_count

    pure real(dp) function signal_shortest_period(self) result(period)
        class(signal_set), intent(in) :: self
        integer :: k
        period = huge(1.0_dp)
        if (.not. allocated(self%op)) return
        do k = 1, size(self%op)
            if (self%op(k) == SIG_SINE .and. self%arg(2, k) /= 0.0_dp) &
                period = min(period, 1.0_dp / abs(self%arg(2, k)))
        end do
    end function signal_shortest_period

    !> A bound on |signal i (t)| over all times: each part's largest magnitude (a step's larger
    !! level, a ramp's height, a sine's amplitude plus its offset, a table's largest value),
    !! summed over + and -, multiplied over *.
    pure real(dp) function signal_sup(self, i) result(bound)
        class(signal_set), intent(in) :: self
        integer, intent(in) :: i            !! signal index, 1 .. count
        real(dp) :: st(self%start(i + 1) - self%start(i)), a(4)
        integer :: k, top, first
        top = 0
        do k = self%start(i), self%start(i + 1) - 1
            a = self%arg(:, k)
            select case (self%op(k))
            case (SIG_ADD, SIG_SUB)
                st(top - 1) = st(top - 1) + st(top)
                top = top - 1
            case (SIG_MUL)
                st(top - 1) = st(top - 1) * st(top)
                top = top - 1
            case default
                top = top + 1
                select case (self%op(k))
                case (SIG_CONST)
                    st(top) = abs(a(1))
                case (SIG_STEP)
                    st(top) = max(abs(a(2)), abs(a(3)))
                case (SIG_RAMP)
                    st(top) = abs(a(3))
                case (SIG_SINE)
                    st(top) = abs(a(1)) + abs(a(4))
                case default   ! SIG_TABLE
                    first = nint(a(1))
                    st(top) = maxval(abs(self%tab_v(first:first + nint(a(2)) - 1)))
                end select
            end select
        end do
        bound = st(1)
    end function signal_sup

    pure logical function signal_is_number(self, i) result(yes)
        class(signal_set), intent(in) :: self
        integer, intent(in) :: i            !! signal index, 1 .. count
        yes = self%start(i + 1) - self%start(i) == 1 .and. self%op(self%start(i)) == SIG_CONST
    end function signal_is_number

    pure real(dp) function signal_number(self, i) result(value)
        class(signal_set), intent(in) :: self
        integer, intent(in) :: i            !! signal index, 1 .. count, a number
        value = self%arg(1, self%start(i))
    end function signal_number

    !> Value and rate of signal i at time t (i in 1 .. count; a checked set).
    pure subroutine signal_eval(self, i, t, value, rate)
        class(signal_set), intent(in) :: self
        integer, intent(in) :: i            !! signal index, 1 .. count
        real(dp), intent(in) :: t           !! time [s]
        real(dp), intent(out) :: value      !! its value (units of what it drives)
        real(dp), intent(out) :: rate       !! its time derivative (per second)
        integer, parameter :: SHORT = 32    ! programs up to this length use a stack of fixed size
        real(dp) :: sv(SHORT), sr(SHORT)
        if (self%is_number(i)) then
            value = self%number(i)                  ! the common case
            rate = 0.0_dp
        else if (self%start(i + 1) - self%start(i) <= SHORT) then
            call run_program(self, i, t, sv, sr, value, rate)
        else
            call run_long_program(self, i, t, value, rate)
        end if
    end subroutine signal_eval

    !> signal_eval of a program longer than signal_eval's fixed stack.
    pure subroutine run_long_program(self, i, t, value, rate)
        class(signal_set), intent(in) :: self
        integer, intent(in) :: i
        real(dp), intent(in) :: t
        real(dp), intent(out) :: value, rate
        real(dp), allocatable :: lv(:), lr(:)
        allocate(lv(self%start(i + 1) - self%start(i)), lr(self%start(i + 1) - self%start(i)))
        call run_program(self, i, t, lv, lr, value, rate)
    end subroutine run_long_program

    !> Run signal i's program on the stack (sv, sr) of values and rates.
    pure subroutine run_program(self, i, t, sv, sr, value, rate)
        class(signal_set), intent(in) :: self
        integer, intent(in) :: i
        real(dp), intent(in) :: t
        real(dp), intent(inout) :: sv(:), sr(:)
        real(dp), intent(out) :: value, rate
        real(dp) :: a(4), u
        integer :: k, top, j, first, last, lo, hi
        top = 0
        do k = self%start(i), self%start(i + 1) - 1
            a = self%arg(:, k)
            select case (self%op(k))
            case (SIG_ADD, SIG_SUB, SIG_MUL)
                select case (self%op(k))
                case (SIG_ADD)
                    sv(top - 1) = sv(top - 1) + sv(top)
                    sr(top - 1) = sr(top - 1) + sr(top)
                case (SIG_SUB)
                    sv(top - 1) = sv(top - 1) - sv(top)
                    sr(top - 1) = sr(top - 1) - sr(top)
                case default
                    sr(top - 1) = sr(top - 1) * sv(top) + sv(top - 1) * sr(top)
                    sv(top - 1) = sv(top - 1) * sv(top)
                end select
                top = top - 1
                cycle
            end select
            top = top + 1
            sr(top) = 0.0_dp
            select case (self%op(k))
            case (SIG_CONST)
                sv(top) = a(1)
            case (SIG_STEP)
                sv(top) = merge(a(3), a(2), t >= a(1))
            case (SIG_RAMP)
                if (t < a(1)) then
                    sv(top) = 0.0_dp
                else if (t < a(1) + a(2)) then
                    sv(top) = a(3) * (t - a(1)) / a(2)
                    sr(top) = a(3) / a(2)
                else
                    sv(top) = a(3)
                end if
            case (SIG_SINE)
                u = two_pi * a(2) * t + a(3)
                sv(top) = a(1) * sin(u) + a(4)
                sr(top) = a(1) * two_pi * a(2) * cos(u)
            case (SIG_TABLE)
                first = nint(a(1))
                last = first + nint(a(2)) - 1
                if (t <= self%tab_t(first)) then
                    sv(top) = self%tab_v(first)
                    if (last > first .and. t == self%tab_t(first)) sr(top) = slope(first)
                else if (t >= self%tab_t(last)) then
                    sv(top) = self%tab_v(last)
                else
                    ! bisection: tab_t(lo) <= t < tab_t(hi), hi = lo + 1 at the end (a long
                    ! record, a ground acceleration, costs log2 of its length per evaluation)
                    lo = first
                    hi = last
                    do while (hi - lo > 1)
                        j = (lo + hi) / 2
                        if (self%tab_t(j) <= t) then
                            lo = j
                        else
                            hi = j
                        end if
                    end do
                    j = lo
                    sv(top) = self%tab_v(j) + slope(j) * (t - self%tab_t(j))
                    sr(top) = slope(j)
                end if
            end select
        end do
        value = sv(1)
        rate = sr(1)
    contains
        pure real(dp) function slope(j)
            integer, intent(in) :: j
            slope = (self%tab_v(j + 1) - self%tab_v(j)) / (self%tab_t(j + 1) - self%tab_t(j))
        end function slope
    end subroutine run_program

    !> The first corner of signal i strictly after t: a step's time, a ramp's start or end, a
    !! table's point; huge(1.0_dp) when there is none [s].
    pure real(dp) function signal_next_break(self, i, t) result(tb)
        class(signal_set), intent(in) :: self
        integer, intent(in) :: i            !! signal index, 1 .. count
        real(dp), intent(in) :: t           !! time [s]
        integer :: k, j
        tb = huge(1.0_dp)
        do k = self%start(i), self%start(i + 1) - 1
            select case (self%op(k))
            case (SIG_STEP)
                call consider(self%arg(1, k))
            case (SIG_RAMP)
                call consider(self%arg(1, k))
                call consider(self%arg(1, k) + self%arg(2, k))
            case (SIG_TABLE)
                do j = nint(self%arg(1, k)), nint(self%arg(1, k)) + nint(self%arg(2, k)) - 1
                    call consider(self%tab_t(j))
                end do
            end select
        end do
    contains
        pure subroutine consider(tc)
            real(dp), intent(in) :: tc
            if (tc > t) tb = min(tb, tc)
        end subroutine consider
    end function signal_next_break

    !> Check every signal: known operations leaving exactly one value, finite arguments, ramps
    !! of positive duration, tables inside tab_t with strictly increasing finite times and finite
    !! values. err = 0 (and which = 0) when all are well formed, else a SIG_ERR_* code and the
    !! first bad signal.
    pure subroutine signal_check(self, err, which)
        class(signal_set), intent(in) :: self
        integer, intent(out) :: err         !! 0 or SIG_ERR_OP, SIG_ERR_ARG, SIG_ERR_DURATION, SIG_ERR_TABLE
        integer, intent(out) :: which       !! the first bad signal, 1-based (0: none)
        integer :: i, k, depth, first, cnt
        err = 0
        which = 0
        if (.not. (allocated(self%op) .and. allocated(self%arg) .and. allocated(self%start) .and. &
                   allocated(self%tab_t) .and. allocated(self%tab_v))) then
            err = SIG_ERR_OP
            return
        end if
        if (size(self%start) < 1 .or. size(self%arg, 1) /= 4 .or. size(self%arg, 2) /= size(self%op) .or. &
            size(self%tab_t) /= size(self%tab_v)) then
            err = SIG_ERR_OP
            return
        end if
        do i = 1, self%count()
            which = i
            if (self%start(i) < 1 .or. self%start(i + 1) < self%start(i) .or. &
                self%start(i + 1) - 1 > size(self%op)) then
                err = SIG_ERR_OP
                return
            end if
            depth = 0
            do k = self%start(i), self%start(i + 1) - 1
                if (.not. all(ieee_is_finite(self%arg(:, k)))) err = SIG_ERR_ARG
                select case (self%op(k))
                case (SIG_ADD, SIG_SUB, SIG_MUL)
                    depth = depth - 1
                    if (depth < 1) err = SIG_ERR_OP
                case (SIG_CONST, SIG_STEP, SIG_SINE)
                    depth = depth + 1
                case (SIG_RAMP)
                    depth = depth + 1
                    if (err == 0 .and. .not. self%arg(2, k) > 0.0_dp) err = SIG_ERR_DURATION
                case (SIG_TABLE)
                    depth = depth + 1
                    if (err /= 0) exit
                    first = nint(self%arg(1, k))
                    cnt = nint(self%arg(2, k))
                    if (first < 1 .or. cnt < 1 .or. first + cnt - 1 > size(self%tab_t)) then
                        err = SIG_ERR_TABLE
                    else if (.not. (all(ieee_is_finite(self%tab_t(first:first + cnt - 1))) .and. &
                                    all(ieee_is_finite(self%tab_v(first:first + cnt - 1))))) then
                        err = SIG_ERR_TABLE
                    else if (any(self%tab_t(first + 1:first + cnt - 1) <= self%tab_t(first:first + cnt - 2))) then
                        err = SIG_ERR_TABLE
                    end if
                case default
                    err = SIG_ERR_OP
                end select
                if (err /= 0) exit
            end do
            if (err == 0 .and. depth /= 1) err = SIG_ERR_OP
            if (err /= 0) return
        end do
        which = 0
    end subroutine signal_check

    ! ---- Signals made from signals (the drives of `stickslip_user_model`): sums, affine maps,
    ! derivatives and integrals of a set's signal i, appended to the set as new signals. A
    ! function of time that grows without end, t - T after T, is a ramp that never ends in any
    ! run: ramp(T, ENDLESS, ENDLESS), whose value ENDLESS (t - T) / ENDLESS is t - T exactly
    ! (ENDLESS a power of 2).


    !> The signal s1 op s2 (op: SIG_ADD, SIG_SUB or SIG_MUL) appended to the set; its index.
    !! An s1 or s2 outside 1 .. count appends a malformed signal (`check` names it).
    integer function signal_combine(sig, s1, s2, op) result(index)
        type(signal_set), intent(inout) :: sig      !! the signals
        integer, intent(in) :: s1, s2               !! two of its signals
        integer, intent(in) :: op                   !! SIG_ADD, SIG_SUB or SIG_MUL
        integer :: n
        n = sig%count()
        if (s1 < 1 .or. s1 > n .or. s2 < 1 .or. s2 > n) then
            index = append(sig, leaf(SIG_ADD, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp]))
        else
            index = append(sig, join(span(sig, sig%start(s1), sig%start(s1 + 1) - 1), &
                                     span(sig, sig%start(s2), sig%start(s2 + 1) - 1), op))
        end if
    end function signal_combine

    !> scale * (signal s) + offset appended to the set; its index.
    integer function signal_affine(sig, s, scale, offset) result(index)
        type(signal_set), intent(inout) :: sig      !! the signals
        integer, intent(in) :: s                    !! one of its signals
        real(dp), intent(in) :: scale               !! the factor
        real(dp), intent(in) :: offset              !! the number added
        index = append(sig, affine(span(sig, sig%start(s), sig%start(s + 1) - 1), scale, offset))
    end function signal_affine

    !> The time derivative of signal s appended to the set (index in d); ok = .false. (and
    !! nothing appended) when s has a step, whose derivative is not a function.
    subroutine signal_derivative(sig, s, d, ok)
        type(signal_set), intent(inout) :: sig      !! the signals
        integer, intent(in) :: s                    !! one of its signals
        integer, intent(out) :: d                   !! the derivative's index (0 when not ok)
        logical, intent(out) :: ok                  !! .true. when s has a derivative
        call transform(sig, s, .false., d, ok)
    end subroutine signal_derivative

    !> The integral of signal s from t = 0, appended to the set (index in d): exact for sums,
    !! differences and multiples (a number times a signal) of constants, steps, ramps, sines
    !! and tables; ok = .false. (nothing appended) for other products.
    subroutine signal_integral(sig, s, d, ok)
        type(signal_set), intent(inout) :: sig      !! the signals
        integer, intent(in) :: s                    !! one of its signals
        integer, intent(out) :: d                   !! the integral's index (0 when not ok)
        logical, intent(out) :: ok                  !! .true. when it has a closed form here
        call transform(sig, s, .true., d, ok)
    end subroutine signal_integral

    !> Append the integral (integral = .true.) or the derivative of signal s; d its index.
    subroutine transform(sig, s, integral, d, ok)
        type(signal_set), intent(inout) :: sig
        integer, intent(in) :: s
        logical, intent(in) :: integral
        integer, intent(out) :: d
        logical, intent(out) :: ok
        type(program_t) :: p
        d = 0
        ok = .true.
        p = calculus(sig, sig%start(s + 1) - 1, integral, ok)
        if (ok) d = append(sig, p)
    end subroutine transform

    !> Append a program as a new signal; its index.
    integer function append(sig, p) result(index)
        type(signal_set), intent(inout) :: sig
        type(program_t), intent(in) :: p
        real(dp), allocatable :: a(:, :)
        integer :: n0
        n0 = size(sig%op)
        allocate(a(4, n0 + size(p%op)))
        a(:, :n0) = sig%arg
        a(:, n0 + 1:) = p%arg
        call move_alloc(a, sig%arg)
        sig%op = [sig%op, p%op]
        sig%start = [sig%start, size(sig%op) + 1]
        index = size(sig%start) - 1
    end function append

    pure function leaf(op, arg) result(p)
        integer, intent(in) :: op
        real(dp), intent(in) :: arg(4)
        type(program_t) :: p
        p%op = [op]
        p%arg = reshape(arg, [4, 1])
    end function leaf

    pure function number(c) result(p)
        real(dp), intent(in) :: c
        type(program_t) :: p
        p = leaf(SIG_CONST, [c, 0.0_dp, 0.0_dp, 0.0_dp])
    end function number

    !> p1 op p2.
    pure function join(p1, p2, op) result(p)
        type(program_t), intent(in) :: p1, p2
        integer, intent(in) :: op
        type(program_t) :: p
        p%op = [p1%op, p2%op, op]
        allocate(p%arg(4, size(p%op)))
        p%arg(:, :size(p1%op)) = p1%arg
        p%arg(:, size(p1%op) + 1:size(p%op) - 1) = p2%arg
        p%arg(:, size(p%op)) = 0.0_dp
    end function join

    !> scale * p + offset (the product and sum left out where they change nothing).
    pure function affine(p, scale, offset) result(q)
        type(program_t), intent(in) :: p
        real(dp), intent(in) :: scale, offset
        type(program_t) :: q
        q = p
        if (scale /= 1.0_dp) q = join(number(scale), q, SIG_MUL)
        if (offset /= 0.0_dp) q = join(q, number(offset), SIG_ADD)
    end function affine

    !> max(t - t_corner, 0)^power (power 1 or 2).
    pure function hinge(t_corner, power) result(p)
        real(dp), intent(in) :: t_corner
        integer, intent(in) :: power
        type(program_t) :: p
        p = leaf(SIG_RAMP, [t_corner, ENDLESS, ENDLESS, 0.0_dp])
        if (power == 2) p = join(p, p, SIG_MUL)
    end function hinge

    !> The operations first .. last of the set as a program.
    pure function span(sig, first, last) result(p)
        type(signal_set), intent(in) :: sig
        integer, intent(in) :: first, last
        type(program_t) :: p
        p%op = sig%op(first:last)
        p%arg = sig%arg(:, first:last)
    end function span

    !> The first operation of the operand that ends at operation last.
    pure integer function operand_start(sig, last) result(k)
        type(signal_set), intent(in) :: sig
        integer, intent(in) :: last
        integer :: need
        need = 1
        k = last
        do
            select case (sig%op(k))
            case (SIG_ADD, SIG_SUB, SIG_MUL)
                need = need + 1
            case default
                need = need - 1
            end select
            if (need == 0) return
            k = k - 1
        end do
    end function operand_start

    !> The derivative (integral = .false.; ok = .false. at a step) or the integral from t = 0
    !! (integral = .true.; ok = .false. at a product of two signals that are not numbers) of
    !! the operand ending at operation last.
    recursive function calculus(sig, last, integral, ok) result(p)
        type(signal_set), intent(in) :: sig
        integer, intent(in) :: last
        logical, intent(in) :: integral
        logical, intent(inout) :: ok
        type(program_t) :: p
        real(dp) :: a(4), w
        real(dp), allocatable :: corner(:), change(:)
        integer :: r, first, j
        a = sig%arg(:, last)
        r = 0
        first = 0
        if (any(sig%op(last) == [SIG_ADD, SIG_SUB, SIG_MUL])) then
            r = operand_start(sig, last - 1)            ! the operands: first .. r - 1, r .. last - 1
            first = operand_start(sig, r - 1)
        end if
        select case (sig%op(last))
        case (SIG_ADD, SIG_SUB)
            p = join(calculus(sig, r - 1, integral, ok), calculus(sig, last - 1, integral, ok), sig%op(last))
        case (SIG_MUL)
            if (.not. integral) then                    ! (u w)' = u' w + u w'
                p = join(join(calculus(sig, r - 1, integral, ok), span(sig, r, last - 1), SIG_MUL), &
                         join(span(sig, first, r - 1), calculus(sig, last - 1, integral, ok), SIG_MUL), SIG_ADD)
            else if (r - first == 1 .and. sig%op(first) == SIG_CONST) then    ! a number times a signal
                p = affine(calculus(sig, last - 1, integral, ok), sig%arg(1, first), 0.0_dp)
            else if (last - r == 1 .and. sig%op(r) == SIG_CONST) then
                p = affine(calculus(sig, r - 1, integral, ok), sig%arg(1, r), 0.0_dp)
            else
                ok = .false.
                p = number(0.0_dp)
            end if
        case (SIG_STEP)
            if (integral) then                          ! before t, then after (t - time) more
                p = join(affine(hinge(0.0_dp, 1), a(2), 0.0_dp), &
                         affine(hinge(max(a(1), 0.0_dp), 1), a(3) - a(2), 0.0_dp), SIG_ADD)
            else
                ok = .false.
                p = number(0.0_dp)
            end if
        case (SIG_RAMP)                                 ! slope h / d between start and start + d
            if (integral) then
                w = 0.5_dp * a(3) / a(2)
                p = affine(join(hinge(a(1), 2), hinge(a(1) + a(2), 2), SIG_SUB), w, &
                           -w * (max(-a(1), 0.0_dp)**2 - max(-a(1) - a(2), 0.0_dp)**2))
            else
                p = join(leaf(SIG_STEP, [a(1), 0.0_dp, a(3) / a(2), 0.0_dp]), &
                         leaf(SIG_STEP, [a(1) + a(2), 0.0_dp, -a(3) / a(2), 0.0_dp]), SIG_ADD)
            end if
        case (SIG_SINE)
            if (.not. integral) then
                p = leaf(SIG_SINE, [two_pi * a(2) * a(1), a(2), a(3) + 0.25_dp * two_pi, 0.0_dp])
            else if (a(2) == 0.0_dp) then
                p = affine(hinge(0.0_dp, 1), a(1) * sin(a(3)) + a(4), 0.0_dp)
            else
                w = a(1) / (two_pi * a(2))
                p = join(leaf(SIG_SINE, [w, a(2), a(3) - 0.25_dp * two_pi, w * cos(a(3))]), &
                         affine(hinge(0.0_dp, 1), a(4), 0.0_dp), SIG_ADD)
            end if
        case (SIG_TABLE)        ! at each point, a step (or, integrated, a quadratic) by the change of slope there
            call slope_changes(sig, nint(a(1)), nint(a(2)), corner, change)
            if (integral) then
                p = affine(hinge(0.0_dp, 1), sig%tab_v(nint(a(1))), 0.0_dp)
            else
                p = number(0.0_dp)
            end if
            do j = 1, size(corner)
                if (integral) then
                    w = 0.5_dp * change(j)
                    p = join(p, affine(hinge(corner(j), 2), w, -w * max(-corner(j), 0.0_dp)**2), SIG_ADD)
                else
                    p = join(p, leaf(SIG_STEP, [corner(j), 0.0_dp, change(j), 0.0_dp]), SIG_ADD)
                end if
            end do
        case default            ! SIG_CONST
            if (integral) then
                p = affine(hinge(0.0_dp, 1), a(1), 0.0_dp)
            else
                p = number(0.0_dp)
            end if
        end select
    end function calculus

    !> The points of the table tab(first : first + count - 1) where its slope changes (0 before
    !! its first point and after its last), and the change there.
    pure subroutine slope_changes(sig, first, count, corner, change)
        type(signal_set), intent(in) :: sig
        integer, intent(in) :: first, count
        real(dp), allocatable, intent(out) :: corner(:), change(:)
        real(dp) :: slope0, slope1
        integer :: j
        allocate(corner(0), change(0))
        slope0 = 0.0_dp
        do j = first, first + count - 1
            slope1 = 0.0_dp
            if (j < first + count - 1) slope1 = (sig%tab_v(j + 1) - sig%tab_v(j)) / (sig%tab_t(j + 1) - sig%tab_t(j))
            if (slope1 /= slope0) then
                corner = [corner, sig%tab_t(j)]
                change = [change, slope1 - slope0]
            end if
            slope0 = slope1
        end do
    end subroutine slope_changes

end module stickslip_signal
