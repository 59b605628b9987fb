!> A root of a continuous scalar function that may have an infinite slope (the proposed law's
!! mu ~ |w|^(1/3) at rest, where Newton's method cycles): bracketed from a start outwards,
!! then closed by Illinois regula falsi with bisection to rounding. Used by the scenes' own
!! stage solves (`scalar_stage`).
module stickslip_roots
    use stickslip_kinds, only: dp
    implicit none
    private

    public :: scalar_function, bracketed_root

    abstract interface
        !> A scalar function of one variable (it may count its evaluations through its host).
        real(dp) function scalar_function(x)
            import :: dp
            real(dp), intent(in) :: x     !! the variable
        end function scalar_function
    end interface

contains

    !> A root of phi near x0: a sign change bracketed from x0 outwards in steps of |phi(x0)|
    !! that double (in the direction where phi decreases in magnitude for an increasing phi),
    !! closed by Illinois regula falsi with bisection until the bracket is at rounding.
    !! found = .false. when no bracket lies within 1e6 (1 + |x0| + |phi(x0)|).
    subroutine bracketed_root(phi, x0, x, found)
        procedure(scalar_function) :: phi  !! the function, continuous
        real(dp), intent(in)  :: x0        !! the start
        real(dp), intent(out) :: x         !! the root (the bracket's end nearer a zero of phi)
        logical, intent(out)  :: found     !! .true.: x is a root to rounding
        real(dp) :: lo, hi, plo, phi_hi, step, vm, pm, reach
        integer :: it, side
        found = .false.
        lo = x0
        x = x0
        plo = phi(lo)
        if (plo == 0.0_dp) then
            found = .true.
            return
        end if
        ! a bracket, in steps of |phi(x0)| that double
        step = max(abs(plo), 1.0e-12_dp * (1.0_dp + abs(lo)))
        reach = 1.0e6_dp * (1.0_dp + abs(lo) + abs(plo))
        hi = lo
        phi_hi = plo
        do it = 1, 200
            hi = lo - sign(step, plo)
            phi_hi = phi(hi)
            if (phi_hi == 0.0_dp) then
                x = hi
                found = .true.
                return
            end if
            if (sign(1.0_dp, phi_hi) /= sign(1.0_dp, plo)) exit
            step = 2.0_dp * step
            if (step > reach) return
        end do
        if (sign(1.0_dp, phi_hi) == sign(1.0_dp, plo)) return
        side = 0
        do it = 1, 400
            vm = hi - phi_hi * (hi - lo) / (phi_hi - plo)
            if (.not. (vm > min(lo, hi) .and. vm < max(lo, hi))) vm = 0.5_dp * (lo + hi)
            if (abs(hi - lo) <= 4.0_dp * epsilon(1.0_dp) * max(abs(lo), abs(hi)) .or. &
                vm == lo .or. vm == hi) exit
            pm = phi(vm)
            if (pm == 0.0_dp) then
                lo = vm
                hi = vm
                exit
            end if
            if (sign(1.0_dp, pm) == sign(1.0_dp, phi_hi)) then
                hi = vm
                phi_hi = pm
                if (side == 1) plo = 0.5_dp * plo
                side = 1
            else
                lo = vm
                plo = pm
                if (side == -1) phi_hi = 0.5_dp * phi_hi
                side = -1
            end if
        end do
        x = merge(lo, hi, abs(plo) < abs(phi_hi))
        found = .true.
    end subroutine bracketed_root

end module stickslip_roots
