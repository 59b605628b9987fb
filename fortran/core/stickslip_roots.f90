!> A root of a continuous scalar function that may have an infinite slope (the proposed law's
!! mu ~ |w|^(1/3) at rest, where Newton's method cycles): bracketed from a start outwards,
!! then closed by Illinois regula falsi with bisection to rounding. Used by the scenes' own
!! stage solves (`scalar_stage`).
!!
!! By reverse communication: the search says where it wants the function next and the caller
!! evaluates it there, so that the function needs no procedure argument (an internal
!! procedure passed as one would need a trampoline, an executable stack, which recent C
!! libraries refuse to load):
!!
!!     call search%start(x0)
!!     do while (.not. search%done)
!!         call search%tell(phi(search%x))
!!     end do
!!     if (search%found) root = search%root
module stickslip_roots
    use stickslip_kinds, only: dp
    implicit none
    private

    !> A root search of phi from x0: a sign change bracketed from x0 outwards in steps of
    !! |phi(x0)| that double (in the direction where phi decreases in magnitude for an
    !! increasing phi), closed by Illinois regula falsi with bisection until the bracket is at
    !! rounding. found = .false. when no bracket lies within 1e6 (1 + |x0| + |phi(x0)|).
    type, public :: root_search
        real(dp) :: x = 0.0_dp           !! where the search wants phi next
        logical :: done = .true.         !! .true.: the search has ended
        logical :: found = .false.       !! .true. once ended: root is a root to rounding
        real(dp) :: root = 0.0_dp        !! the root (the bracket's end nearer a zero of phi)
        real(dp), private :: lo = 0.0_dp       !! the bracket's end where phi has phi(x0)'s sign
        real(dp), private :: hi = 0.0_dp       !! its other end
        real(dp), private :: plo = 0.0_dp      !! phi(lo) (halved by the Illinois rule)
        real(dp), private :: phi_hi = 0.0_dp   !! phi(hi) (halved by the Illinois rule)
        real(dp), private :: step = 0.0_dp     !! the bracketing step, doubled each time
        real(dp), private :: reach = 0.0_dp    !! the farthest step tried
        integer, private :: stage = 0          !! AT_START, BRACKETING or CLOSING
        integer, private :: it = 0             !! iterations of the stage
        integer, private :: side = 0           !! the end that moved last (Illinois rule)
    contains
        procedure :: start => root_start   !! begin from x0 (root_start)
        procedure :: tell => root_tell     !! phi at x: move on or end (root_tell)
    end type root_search

    integer, parameter :: AT_START = 0, BRACKETING = 1, CLOSING = 2
    integer, parameter :: MAX_BRACKET = 200, MAX_CLOSE = 400

contains

    !> Start a search from x0: it wants phi(x0) first.
    pure subroutine root_start(self, x0)
        class(root_search), intent(inout) :: self
        real(dp), intent(in) :: x0            !! the start
        self%x = x0
        self%root = x0
        self%done = .false.
        self%found = .false.
        self%stage = AT_START
    end subroutine root_start

    !> phi at self%x: the search moves on (a new self%x) or ends (done).
    pure subroutine root_tell(self, fx)
        class(root_search), intent(inout) :: self
        real(dp), intent(in) :: fx            !! phi(self%x)
        real(dp) :: vm
        select case (self%stage)
        case (AT_START)
            self%lo = self%x
            self%plo = fx
            if (fx == 0.0_dp) then
                call found_at(self, self%x)
                return
            end if
            ! a bracket, in steps of |phi(x0)| that double
            self%step = max(abs(fx), 1.0e-12_dp * (1.0_dp + abs(self%lo)))
            self%reach = 1.0e6_dp * (1.0_dp + abs(self%lo) + abs(fx))
            self%it = 1
            self%stage = BRACKETING
            self%x = self%lo - sign(self%step, self%plo)
        case (BRACKETING)
            self%hi = self%x
            self%phi_hi = fx
            if (fx == 0.0_dp) then
                call found_at(self, self%x)
            else if (sign(1.0_dp, fx) /= sign(1.0_dp, self%plo)) then
                self%side = 0
                self%it = 1
                self%stage = CLOSING
                call close_next(self)
            else
                self%step = 2.0_dp * self%step
                self%it = self%it + 1
                if (self%step > self%reach .or. self%it > MAX_BRACKET) then
                    self%done = .true.                    ! no bracket
                else
                    self%x = self%lo - sign(self%step, self%plo)
                end if
            end if
        case (CLOSING)
            vm = self%x
            if (fx == 0.0_dp) then
                self%lo = vm
                self%hi = vm
                call closed(self)
                return
            end if
            if (sign(1.0_dp, fx) == sign(1.0_dp, self%phi_hi)) then
                self%hi = vm
                self%phi_hi = fx
                if (self%side == 1) self%plo = 0.5_dp * self%plo
                self%side = 1
            else
                self%lo = vm
                self%plo = fx
                if (self%side == -1) self%phi_hi = 0.5_dp * self%phi_hi
                self%side = -1
            end if
            self%it = self%it + 1
            call close_next(self)
        end select
    end subroutine root_tell

    !> The next point of the closing bracket (Illinois regula falsi, bisection where it leaves
    !! the bracket), or the end where the bracket is at rounding or the iterations are spent.
    pure subroutine close_next(self)
        type(root_search), intent(inout) :: self
        real(dp) :: vm, lo, hi
        lo = self%lo
        hi = self%hi
        if (self%it > MAX_CLOSE) then
            call closed(self)
            return
        end if
        vm = hi - self%phi_hi * (hi - lo) / (self%phi_hi - self%plo)
        if (.not. (vm > min(lo, hi) .and. vm < max(lo, hi))) vm = 0.5_dp * (lo + hi)
        if (abs(hi - lo) <= 4.0_dp * epsilon(1.0_dp) * max(abs(lo), abs(hi)) .or. &
            vm == lo .or. vm == hi) then
            call closed(self)
        else
            self%x = vm
        end if
    end subroutine close_next

    !> The closed bracket's end nearer a zero of phi.
    pure subroutine closed(self)
        type(root_search), intent(inout) :: self
        call found_at(self, merge(self%lo, self%hi, abs(self%plo) < abs(self%phi_hi)))
    end subroutine closed

    pure subroutine found_at(self, x)
        type(root_search), intent(inout) :: self
        real(dp), intent(in) :: x
        self%root = x
        self%found = .true.
        self%done = .true.
    end subroutine found_at

end module stickslip_roots
