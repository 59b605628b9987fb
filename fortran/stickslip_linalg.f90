!> Small dense linear algebra for the implicit integrators: LU decomposition with partial
!! pivoting and the forward-backward substitution that uses it, for real and for complex
!! matrices (the complex one serves the complex n x n system of RADAU5).
!!
!! Written for the small systems of this library (n of a few to a few dozen), where a plain
!! column-oriented elimination is as fast as LAPACK's dgetrf/dgetrs (measured: see the
!! integrators' notes); any n works. A zero pivot (after pivoting) or a non-finite entry
!! makes the decomposition fail with info = the column where it happened, never a NaN
!! solution.
module stickslip_linalg
    use stickslip_kinds, only: dp
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: lu_decompose, lu_solve

    !> A = P L U in place; info = 0 on success, k > 0 when column k has no usable pivot.
    interface lu_decompose
        module procedure lu_decompose_real, lu_decompose_complex
    end interface lu_decompose

    !> Solve A x = b with the factors of lu_decompose; b is overwritten by x.
    interface lu_solve
        module procedure lu_solve_real, lu_solve_complex
    end interface lu_solve

contains

    !> Real LU decomposition with partial pivoting (row interchanges recorded in ipiv).
    pure subroutine lu_decompose_real(a, ipiv, info)
        real(dp), intent(inout) :: a(:, :)   !! (n, n) matrix on entry, its L and U factors on exit
        integer, intent(out)    :: ipiv(:)   !! (n) row interchanged with row k at step k
        integer, intent(out)    :: info      !! 0: success; k: zero or non-finite pivot in column k
        integer :: n, k, p, j
        real(dp) :: piv, tmp
        n = size(a, 1)
        info = 0
        do k = 1, n
            p = k - 1 + maxloc(abs(a(k:n, k)), dim=1)
            ipiv(k) = p
            piv = a(p, k)
            if (piv == 0.0_dp .or. .not. ieee_is_finite(piv)) then
                info = k
                return
            end if
            if (p /= k) then   ! (element by element: no temporary array, which gfortran would allocate)
                do j = 1, size(a, 2)
                    tmp = a(k, j)
                    a(k, j) = a(p, j)
                    a(p, j) = tmp
                end do
            end if
            a(k+1:n, k) = a(k+1:n, k) / piv
            do j = k + 1, n
                a(k+1:n, j) = a(k+1:n, j) - a(k, j) * a(k+1:n, k)
            end do
        end do
    end subroutine lu_decompose_real

    !> Complex LU decomposition with partial pivoting (pivot by |re| + |im|).
    pure subroutine lu_decompose_complex(a, ipiv, info)
        complex(dp), intent(inout) :: a(:, :)  !! (n, n) matrix on entry, its L and U factors on exit
        integer, intent(out)       :: ipiv(:)  !! (n) row interchanged with row k at step k
        integer, intent(out)       :: info     !! 0: success; k: zero or non-finite pivot in column k
        integer :: n, k, p, j
        complex(dp) :: piv, tmp
        n = size(a, 1)
        info = 0
        do k = 1, n
            p = k - 1 + maxloc(abs(a(k:n, k)%re) + abs(a(k:n, k)%im), dim=1)
            ipiv(k) = p
            piv = a(p, k)
            if (piv == (0.0_dp, 0.0_dp) .or. .not. ieee_is_finite(piv%re) .or. &
                .not. ieee_is_finite(piv%im)) then
                info = k
                return
            end if
            if (p /= k) then   ! (element by element: no temporary array, which gfortran would allocate)
                do j = 1, size(a, 2)
                    tmp = a(k, j)
                    a(k, j) = a(p, j)
                    a(p, j) = tmp
                end do
            end if
            a(k+1:n, k) = a(k+1:n, k) / piv
            do j = k + 1, n
                a(k+1:n, j) = a(k+1:n, j) - a(k, j) * a(k+1:n, k)
            end do
        end do
    end subroutine lu_decompose_complex

    !> Forward-backward substitution with real factors.
    pure subroutine lu_solve_real(a, ipiv, b)
        real(dp), intent(in)    :: a(:, :)   !! (n, n) factors from lu_decompose
        integer, intent(in)     :: ipiv(:)   !! (n) interchanges from lu_decompose
        real(dp), intent(inout) :: b(:)      !! (n) right-hand side on entry, solution on exit
        integer :: n, k
        real(dp) :: tmp
        n = size(a, 1)
        do k = 1, n
            if (ipiv(k) /= k) then
                tmp = b(k)
                b(k) = b(ipiv(k))
                b(ipiv(k)) = tmp
            end if
            b(k+1:n) = b(k+1:n) - b(k) * a(k+1:n, k)
        end do
        do k = n, 1, -1
            b(k) = b(k) / a(k, k)
            b(1:k-1) = b(1:k-1) - b(k) * a(1:k-1, k)
        end do
    end subroutine lu_solve_real

    !> Forward-backward substitution with complex factors.
    pure subroutine lu_solve_complex(a, ipiv, b)
        complex(dp), intent(in)    :: a(:, :)  !! (n, n) factors from lu_decompose
        integer, intent(in)        :: ipiv(:)  !! (n) interchanges from lu_decompose
        complex(dp), intent(inout) :: b(:)     !! (n) right-hand side on entry, solution on exit
        integer :: n, k
        complex(dp) :: tmp
        n = size(a, 1)
        do k = 1, n
            if (ipiv(k) /= k) then
                tmp = b(k)
                b(k) = b(ipiv(k))
                b(ipiv(k)) = tmp
            end if
            b(k+1:n) = b(k+1:n) - b(k) * a(k+1:n, k)
        end do
        do k = n, 1, -1
            b(k) = b(k) / a(k, k)
            b(1:k-1) = b(1:k-1) - b(k) * a(1:k-1, k)
        end do
    end subroutine lu_solve_complex

end module stickslip_linalg
