!> Small dense linear algebra for the implicit integrators: LU decomposition with partial
!! pivoting and the forward-backward substitution that uses it, for real and for complex
!! matrices (the complex one serves the complex n x n system of RADAU5).
!!
!! Written for the small systems of this library (n of a few to a few dozen), where a plain
!! column-oriented elimination is as fast as LAPACK's dgetrf/dgetrs (measured: see the
!! integrators' notes); any n works. A zero pivot (after pivoting) or a non-finite entry
!! makes the decomposition fail with info = the column where it happened, never a NaN
!! solution.
!!
!! `psd_solve` solves a symmetric positive semidefinite system that may be singular (the
!! Delassus matrix of redundant contacts): the weighted minimum-norm solution, by LU where
!! the matrix is safely regular and by a Jacobi eigendecomposition where it is not.
module stickslip_linalg
    use stickslip_kinds, only: dp
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
    implicit none
    private

    public :: lu_decompose, lu_solve, band_decompose, band_solve, psd_solve, tridiagonal_solve
    public :: psd_factors, psd_factor, real_eigenvalues

    !> The LU factors of a symmetric positive semidefinite matrix A for `psd_solve`, formed
    !! once (`psd_factor`) where A stays the same over many solves with other weights.
    type :: psd_factors
        real(dp), allocatable :: lu(:, :)   !! P L U of A, in place
        integer, allocatable :: ipiv(:)     !! the pivots
        integer :: info = -1                !! lu_decompose's info (-1: not formed)
    end type psd_factors

    !> A = P L U of a band matrix in LAPACK's band storage, in place (partial pivoting).
    interface band_decompose
        module procedure band_decompose_real, band_decompose_complex
    end interface band_decompose

    !> Solve A x = b with the factors of band_decompose; b is overwritten by x.
    interface band_solve
        module procedure band_solve_real, band_solve_complex
    end interface band_solve

    !> A = P L U in place; info = 0 on success, k > 0 when column k has no usable pivot.
    interface lu_decompose
        module procedure lu_decompose_real, lu_decompose_complex
    end interface lu_decompose

    !> Solve A x = b with the factors of lu_decompose; b is overwritten by x.
    interface lu_solve
        module procedure lu_solve_real, lu_solve_complex
    end interface lu_solve

contains

! One text for both kinds (stickslip_linalg_body.inc): LU_SCALAR is the element type, LU_MAG
! the pivot's size, LU_BAD a pivot that cannot be used.
#define LU_DECOMPOSE lu_decompose_real
#define LU_SOLVE lu_solve_real
#define LU_SCALAR real(dp)
#define LU_MAG(x) abs(x)
#define LU_BAD(p) (p == 0.0_dp .or. .not. ieee_is_finite(p))
#include "stickslip_linalg_body.inc"
#define BAND_DECOMPOSE band_decompose_real
#define BAND_SOLVE band_solve_real
#include "stickslip_linalg_band_body.inc"
#undef BAND_DECOMPOSE
#undef BAND_SOLVE
#undef LU_DECOMPOSE
#undef LU_SOLVE
#undef LU_SCALAR
#undef LU_MAG
#undef LU_BAD

! Complex pivots by their size |re| + |im|.
#define LU_DECOMPOSE lu_decompose_complex
#define LU_SOLVE lu_solve_complex
#define LU_SCALAR complex(dp)
#define LU_MAG(x) abs(x%re) + abs(x%im)
#define LU_BAD(p) (p == (0.0_dp, 0.0_dp) .or. .not. ieee_is_finite(p%re) .or. .not. ieee_is_finite(p%im))
#include "stickslip_linalg_body.inc"
#define BAND_DECOMPOSE band_decompose_complex
#define BAND_SOLVE band_solve_complex
#include "stickslip_linalg_band_body.inc"
#undef BAND_DECOMPOSE
#undef BAND_SOLVE
#undef LU_DECOMPOSE
#undef LU_SOLVE
#undef LU_SCALAR
#undef LU_MAG
#undef LU_BAD

    !> Solve a tridiagonal system by elimination without pivoting (Thomas), for a matrix that is
    !! diagonally dominant or symmetric positive definite (no pivot vanishes).
    pure subroutine tridiagonal_solve(l, d, r, x)
        real(dp), intent(in)    :: l(:)     !! (n) sub-diagonal, l(i) = A(i, i - 1) (l(1) unused)
        real(dp), intent(in)    :: d(:)     !! (n) diagonal, A(i, i)
        real(dp), intent(in)    :: r(:)     !! (n) super-diagonal, r(i) = A(i, i + 1) (r(n) unused)
        real(dp), intent(inout) :: x(:)     !! (n) right-hand side on entry, solution on exit
        real(dp) :: c(size(d)), w
        integer :: i, n
        n = size(d)
        if (n == 1) then
            x(1) = x(1) / d(1)
            return
        end if
        c(1) = r(1) / d(1)
        x(1) = x(1) / d(1)
        do i = 2, n
            w = d(i) - l(i) * c(i - 1)
            c(i) = r(i) / w
            x(i) = (x(i) - l(i) * x(i - 1)) / w
        end do
        do i = n - 1, 1, -1
            x(i) = x(i) - c(i) * x(i + 1)
        end do
    end subroutine tridiagonal_solve

    !> x = C^(1/2) (C^(1/2) A C^(1/2))^+ C^(1/2) b for a symmetric positive semidefinite A
    !! (m x m) and weights C = diag(wts) > 0: among the solutions of A x = b the one that
    !! minimises sum x_i^2 / wts_i (the unique solution when A is regular). Columns of b are
    !! solved together. A regular matrix (every LU pivot, scaled as the weights scale A, above
    !! 1e-12 of the largest scaled diagonal entry) is solved by LU of A; otherwise by the
    !! eigendecomposition of the scaled
    !! matrix (cyclic Jacobi), eigenvalues below 1e-12 of the largest taken as 0. ok is
    !! .false. when b is not in the range of A (relative residual above 1e-9) or an entry is
    !! not finite; x is then not a solution. With `factors` (A's LU from `psd_factor`, where A
    !! serves many solves) A is not factored again. With regular_only, a singular A gives
    !! ok = .false. at once (no eigendecomposition: for a caller with another way on).
    subroutine psd_solve(a, b, wts, ok, factors, regular_only)
        real(dp), intent(in)    :: a(:, :)   !! (m, m) symmetric positive semidefinite matrix
        real(dp), intent(inout) :: b(:, :)   !! (m, k) right-hand sides, solutions on exit
        real(dp), intent(in)    :: wts(:)    !! (m) weights of the norm, > 0
        logical, intent(out)    :: ok        !! .true.: b was in the range of A
        type(psd_factors), intent(in), optional :: factors  !! A's LU (`psd_factor`), if formed
        logical, intent(in), optional :: regular_only       !! a singular A: ok = .false., b untouched
        type(psd_factors) :: own
        real(dp) :: big
        integer :: info, m, j
        m = size(wts)
        ok = .true.
        if (m == 0) return
        big = 0.0_dp
        do j = 1, m
            big = max(big, abs(sqrt(wts(j)) * a(j, j) * sqrt(wts(j))))   ! the scaled diagonal
        end do
        if (.not. (big > 0.0_dp .and. ieee_is_finite(big))) then
            ok = all(b == 0.0_dp)
            b = 0.0_dp
            return
        end if
        ! regular: the unique solution, by LU of A itself (no scaling: a diagonal A gives b / a)
        if (present(factors)) then
            call lu_path(factors)
        else
            call psd_factor(a, own)
            call lu_path(own)
        end if
        if (info == 0) then
            ok = all(ieee_is_finite(b))
            return
        end if
        if (present(regular_only)) then
            if (regular_only) then
                ok = .false.
                return
            end if
        end if
        call psd_pseudo_solve(a, b, wts, ok)
    contains
        !> info = 0 and b solved when f's every pivot, scaled as the weights scale A, is above
        !! 1e-12 of big (A regular); info /= 0 and b untouched otherwise.
        subroutine lu_path(f)
            type(psd_factors), intent(in) :: f
            integer :: jj
            info = f%info
            do jj = 1, m
                if (info /= 0) return
                if (abs(f%lu(jj, jj)) * sqrt(wts(jj))**2 <= 1.0e-12_dp * big) info = 1
            end do
            if (info /= 0) return          ! the last pivot too small: b stays for the pseudo-solve
            do jj = 1, size(b, 2)
                call lu_solve(f%lu, f%ipiv, b(:, jj))
            end do
        end subroutine lu_path
    end subroutine psd_solve

    !> The LU factors of A for `psd_solve` (f%info: lu_decompose's info).
    subroutine psd_factor(a, f)
        real(dp), intent(in) :: a(:, :)          !! (m, m) symmetric positive semidefinite matrix
        type(psd_factors), intent(inout) :: f   !! its factors
        f%lu = a
        if (allocated(f%ipiv)) then
            if (size(f%ipiv) /= size(a, 1)) deallocate(f%ipiv)
        end if
        if (.not. allocated(f%ipiv)) allocate(f%ipiv(size(a, 1)))
        call lu_decompose(f%lu, f%ipiv, f%info)
    end subroutine psd_factor

    !> `psd_solve` where A is singular, or close to it: by the eigendecomposition of the
    !! scaled matrix.
    subroutine psd_pseudo_solve(a, b, wts, ok)
        real(dp), intent(in)    :: a(:, :), wts(:)
        real(dp), intent(inout) :: b(:, :)
        logical, intent(out)    :: ok
        real(dp) :: s(size(wts)), as(size(wts), size(wts))
        real(dp) :: v(size(wts), size(wts)), lam(size(wts)), y(size(wts)), rhs(size(wts)), big
        integer :: j, k
        ok = .true.
        s = sqrt(wts)
        do j = 1, size(wts)
            as(:, j) = s * a(:, j) * s(j)
        end do
        call jacobi_eigen(as, lam, v)
        big = maxval(abs(lam))
        do k = 1, size(b, 2)
            rhs = s * b(:, k)
            y = matmul(rhs, v)
            where (lam > 1.0e-12_dp * big)
                y = y / lam
            elsewhere
                y = 0.0_dp
            end where
            y = matmul(v, y)
            ! consistency: the scaled system's residual against its size
            if (norm2(matmul(as, y) - rhs) > 1.0e-9_dp * (big * norm2(y) + norm2(rhs))) ok = .false.
            b(:, k) = s * y
        end do
        if (.not. all(ieee_is_finite(b))) ok = .false.
    end subroutine psd_pseudo_solve

    !> Eigenvalues lam and orthonormal eigenvectors v (columns) of a symmetric matrix a, by
    !! cyclic Jacobi rotations until the off-diagonal part is below rounding (at most 100 sweeps).
    pure subroutine jacobi_eigen(a, lam, v)
        real(dp), intent(in)  :: a(:, :)     !! (m, m) symmetric matrix
        real(dp), intent(out) :: lam(:)      !! (m) eigenvalues
        real(dp), intent(out) :: v(:, :)     !! (m, m) eigenvectors, by columns
        real(dp) :: b(size(lam), size(lam)), off, tot, theta, t, c, sn, bpp, bqq, bpq, tmp
        integer :: m, p, q, sweep, i
        m = size(lam)
        b = a
        v = 0.0_dp
        do i = 1, m
            v(i, i) = 1.0_dp
        end do
        do sweep = 1, 100
            off = 0.0_dp
            tot = 0.0_dp
            do q = 1, m
                do p = 1, m
                    tot = tot + b(p, q)**2
                    if (p /= q) off = off + b(p, q)**2
                end do
            end do
            if (off <= (epsilon(1.0_dp)**2) * tot) exit
            do p = 1, m - 1
                do q = p + 1, m
                    bpq = b(p, q)
                    if (bpq == 0.0_dp) cycle
                    bpp = b(p, p)
                    bqq = b(q, q)
                    theta = (bqq - bpp) / (2.0_dp * bpq)
                    t = sign(1.0_dp, theta) / (abs(theta) + sqrt(theta**2 + 1.0_dp))
                    c = 1.0_dp / sqrt(t**2 + 1.0_dp)
                    sn = t * c
                    do i = 1, m       ! columns p, q of b
                        tmp = b(i, p)
                        b(i, p) = c * tmp - sn * b(i, q)
                        b(i, q) = sn * tmp + c * b(i, q)
                    end do
                    do i = 1, m       ! rows p, q of b
                        tmp = b(p, i)
                        b(p, i) = c * tmp - sn * b(q, i)
                        b(q, i) = sn * tmp + c * b(q, i)
                    end do
                    do i = 1, m
                        tmp = v(i, p)
                        v(i, p) = c * tmp - sn * v(i, q)
                        v(i, q) = sn * tmp + c * v(i, q)
                    end do
                end do
            end do
        end do
        lam = [(b(i, i), i = 1, m)]
    end subroutine jacobi_eigen

    !> The eigenvalues of a real n x n matrix (wr + i wi; a complex pair adjacent, the one
    !! with wi > 0 first), for the small matrices of this library (the orbit solver's
    !! monodromy; the build links no LAPACK): reduction to upper Hessenberg form by
    !! elimination with partial pivoting (EISPACK's ELMHES), then Francis' double-shift QR
    !! iteration on it (EISPACK's HQR, Wilkinson and Reinsch 1971, with its exceptional
    !! shifts after 10 and 20 iterations), without balancing. info = 0 on success; k > 0
    !! when the k-th eigenvalue (counted from the last) did not converge within 30 n
    !! iterations, or the matrix has a NaN or infinite entry (info = n, wr and wi NaN).
    pure subroutine real_eigenvalues(a, wr, wi, info)
        real(dp), intent(in) :: a(:, :)     !! (n, n) the matrix
        real(dp), intent(out) :: wr(:)      !! (n) real parts of the eigenvalues
        real(dp), intent(out) :: wi(:)      !! (n) imaginary parts
        integer, intent(out) :: info        !! 0, or the eigenvalue that did not converge
        real(dp) :: h(size(a, 1), size(a, 1)), x, y, w, s, t, p, q, r, zz, norm, tst1, tst2
        real(dp) :: row(size(a, 1))
        integer :: n, m, i, j, k, l, en, na, enm2, its, itn, mp2
        logical :: notlas

        n = size(a, 1)
        info = 0
        wr = 0.0_dp
        wi = 0.0_dp
        if (n == 0) return
        if (.not. all(ieee_is_finite(a))) then
            info = n
            wr = ieee_value(0.0_dp, ieee_quiet_nan)
            wi = wr
            return
        end if
        h = a
        ! ELMHES: eliminate below the subdiagonal, column m - 1, pivot of largest size
        do m = 2, n - 1
            x = 0.0_dp
            i = m
            do j = m, n
                if (abs(h(j, m - 1)) > abs(x)) then
                    x = h(j, m - 1)
                    i = j
                end if
            end do
            if (i /= m) then
                row(m - 1:n) = h(i, m - 1:n)
                h(i, m - 1:n) = h(m, m - 1:n)
                h(m, m - 1:n) = row(m - 1:n)
                row = h(:, i)
                h(:, i) = h(:, m)
                h(:, m) = row
            end if
            if (x == 0.0_dp) cycle
            do i = m + 1, n
                y = h(i, m - 1)
                if (y == 0.0_dp) cycle
                y = y / x
                h(i, m - 1) = 0.0_dp
                h(i, m:n) = h(i, m:n) - y * h(m, m:n)
                h(:, m) = h(:, m) + y * h(:, i)
            end do
        end do
        norm = 0.0_dp
        do i = 1, n
            norm = norm + sum(abs(h(i, max(i - 1, 1):n)))
        end do
        ! HQR: deflate from the bottom, one real root or a pair at a time
        en = n
        t = 0.0_dp
        itn = 30 * n
        do while (en >= 1)
            its = 0
            na = en - 1
            enm2 = na - 1
            do
                ! a small subdiagonal element h(l, l - 1) splits the matrix
                do l = en, 2, -1
                    s = abs(h(l - 1, l - 1)) + abs(h(l, l))
                    if (s == 0.0_dp) s = norm
                    tst1 = s
                    tst2 = tst1 + abs(h(l, l - 1))
                    if (tst2 == tst1) exit
                end do
                l = max(l, 1)
                x = h(en, en)
                if (l == en) then                    ! one real root
                    wr(en) = x + t
                    wi(en) = 0.0_dp
                    en = na
                    exit
                end if
                y = h(na, na)
                w = h(en, na) * h(na, en)
                if (l == na) then                    ! two roots
                    p = (y - x) / 2.0_dp
                    q = p * p + w
                    zz = sqrt(abs(q))
                    x = x + t
                    if (q >= 0.0_dp) then
                        zz = p + sign(zz, p)
                        wr(na) = x + zz
                        wr(en) = wr(na)
                        if (zz /= 0.0_dp) wr(en) = x - w / zz
                        wi(na) = 0.0_dp
                        wi(en) = 0.0_dp
                    else
                        wr(na) = x + p
                        wr(en) = x + p
                        wi(na) = zz
                        wi(en) = -zz
                    end if
                    en = enm2
                    exit
                end if
                if (itn == 0) then
                    info = en
                    return
                end if
                if (its == 10 .or. its == 20) then   ! exceptional shift
                    t = t + x
                    do i = 1, en
                        h(i, i) = h(i, i) - x
                    end do
                    s = abs(h(en, na)) + abs(h(na, enm2))
                    x = 0.75_dp * s
                    y = x
                    w = -0.4375_dp * s * s
                end if
                its = its + 1
                itn = itn - 1
                ! two consecutive small subdiagonal elements: where the double step starts
                do m = enm2, l, -1
                    zz = h(m, m)
                    r = x - zz
                    s = y - zz
                    p = (r * s - w) / h(m + 1, m) + h(m, m + 1)
                    q = h(m + 1, m + 1) - zz - r - s
                    r = h(m + 2, m + 1)
                    s = abs(p) + abs(q) + abs(r)
                    p = p / s
                    q = q / s
                    r = r / s
                    if (m == l) exit
                    tst1 = abs(p) * (abs(h(m - 1, m - 1)) + abs(zz) + abs(h(m + 1, m + 1)))
                    tst2 = tst1 + abs(h(m, m - 1)) * (abs(q) + abs(r))
                    if (tst2 == tst1) exit
                end do
                mp2 = m + 2
                do i = mp2, en
                    h(i, i - 2) = 0.0_dp
                    if (i /= mp2) h(i, i - 3) = 0.0_dp
                end do
                ! the double QR step on rows l .. en and columns m .. en
                do k = m, na
                    notlas = k /= na
                    if (k /= m) then
                        p = h(k, k - 1)
                        q = h(k + 1, k - 1)
                        r = 0.0_dp
                        if (notlas) r = h(k + 2, k - 1)
                        x = abs(p) + abs(q) + abs(r)
                        if (x == 0.0_dp) cycle
                        p = p / x
                        q = q / x
                        r = r / x
                    end if
                    s = sign(sqrt(p * p + q * q + r * r), p)
                    if (k /= m) then
                        h(k, k - 1) = -s * x
                    else if (l /= m) then
                        h(k, k - 1) = -h(k, k - 1)
                    end if
                    p = p + s
                    x = p / s
                    y = q / s
                    zz = r / s
                    q = q / p
                    r = r / p
                    if (notlas) then
                        do j = k, en
                            p = h(k, j) + q * h(k + 1, j) + r * h(k + 2, j)
                            h(k, j) = h(k, j) - p * x
                            h(k + 1, j) = h(k + 1, j) - p * y
                            h(k + 2, j) = h(k + 2, j) - p * zz
                        end do
                        do i = l, min(en, k + 3)
                            p = x * h(i, k) + y * h(i, k + 1) + zz * h(i, k + 2)
                            h(i, k) = h(i, k) - p
                            h(i, k + 1) = h(i, k + 1) - p * q
                            h(i, k + 2) = h(i, k + 2) - p * r
                        end do
                    else
                        do j = k, en
                            p = h(k, j) + q * h(k + 1, j)
                            h(k, j) = h(k, j) - p * x
                            h(k + 1, j) = h(k + 1, j) - p * y
                        end do
                        do i = l, min(en, k + 3)
                            p = x * h(i, k) + y * h(i, k + 1)
                            h(i, k) = h(i, k) - p
                            h(i, k + 1) = h(i, k + 1) - p * q
                        end do
                    end if
                end do
            end do
        end do
    end subroutine real_eigenvalues

end module stickslip_linalg
