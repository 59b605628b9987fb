!> Linear complementarity problems by Lemke's complementary pivoting, and the box-constrained
!! problem of a friction step written as one.
!!
!! LCP(M, q): find z >= 0 with y = M z + q >= 0 and z^T y = 0 (m unknowns). `lemke` runs
!! Lemke's algorithm with the covering vector e = (1, ..., 1) on a dense tableau, with the
!! lexicographic ratio test, so that degenerate problems (ties, which identical or redundant
!! contacts make common) cannot cycle. For a copositive-plus M (every positive semidefinite
!! M is one) the algorithm ends, in exact arithmetic, with a solution whenever the problem is
!! feasible (Cottle, Pang and Stone, The Linear Complementarity Problem, 1992, section 4.4).
!! Each pivot costs O(m^2); a problem typically needs O(m) pivots.
!!
!! The box problem (`box_lcp`): find p with lo <= p <= hi and y = D p + q such that y_i >= 0
!! where p_i = lo_i, y_i <= 0 where p_i = hi_i and y_i = 0 in between (D symmetric positive
!! semidefinite, n unknowns). It is the optimality condition of min 1/2 p^T D p + q^T p over
!! the box, so it always has a solution. Written as LCP(M, q') of size 2n with
!! z = (p - lo, nu), M = [[D, I], [-I, 0]] (positive semidefinite), q' = (q + D lo, hi - lo):
!! the first block of y is the positive part of D p + q, nu its negative part.
!!
!! `box_solve` solves the same box problem by a primal-dual active-set method (a semismooth
!! Newton method on the problem's projection form, Hintermueller, Ito and Kunisch, SIAM J.
!! Optim. 13, 2003): each iteration fixes the contacts at a bound, solves the free block by LU
!! and moves contacts between the sets where the bounds or the signs of y are violated. It
!! ends, typically after 1 to 4 linear solves from a warm start, when no set changes; where it
!! does not within 2 m + 10 iterations (it may cycle where D is not an M-matrix) or a free
!! block is singular (redundant contacts), Lemke's method (`box_lcp`) is the exact fallback. y = D p + q is the same at every
!! solution of the box problem (D p is constant on the minimisers of a convex quadratic), so
!! which contacts end with y_i /= 0 does not depend on the method that solved it.
module stickslip_lcp
    use stickslip_kinds, only: dp
    use stickslip_linalg, only: psd_solve
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: lemke, box_lcp, box_solve

    integer, parameter, public :: LCP_SOLVED = 0     !! a solution was found
    integer, parameter, public :: LCP_RAY = 1        !! ended on a secondary ray (no solution found)
    integer, parameter, public :: LCP_BUDGET = 2     !! the pivot budget ran out
    integer, parameter, public :: LCP_BAD = 3        !! non-finite data or pivot

contains

    !> Lemke's algorithm for LCP(M, q) (module notes). status LCP_SOLVED: z, y solve the
    !! problem up to the rounding of the pivots; otherwise z, y are zero.
    subroutine lemke(mat, q, z, y, max_pivots, pivots, status)
        real(dp), intent(in)  :: mat(:, :)     !! (m, m) the matrix M
        real(dp), intent(in)  :: q(:)          !! (m) the vector q
        real(dp), intent(out) :: z(:)          !! (m) the solution z >= 0
        real(dp), intent(out) :: y(:)          !! (m) y = M z + q >= 0, complementary to z
        integer, intent(in)   :: max_pivots    !! pivot budget, >= 1
        integer, intent(out)  :: pivots        !! pivots done
        integer, intent(out)  :: status        !! LCP_SOLVED, LCP_RAY, LCP_BUDGET or LCP_BAD
        ! tableau columns: 1..m the y's (B^-1 of the start), m+1..2m the z's, 2m+1 the
        ! artificial z0; rhs the values of the basic variables
        real(dp) :: t(size(q), 2 * size(q) + 1), rhs(size(q)), col(size(q)), ratio, best, tie
        integer :: basis(size(q)), m, i, r, entering, leaving, z0
        m = size(q)
        z = 0.0_dp
        y = 0.0_dp
        pivots = 0
        status = LCP_SOLVED
        if (m == 0) return
        if (.not. (all(ieee_is_finite(q)) .and. all(ieee_is_finite(mat)))) then
            status = LCP_BAD
            return
        end if
        if (all(q >= 0.0_dp)) then
            y = q
            return
        end if
        z0 = 2 * m + 1
        t = 0.0_dp
        do i = 1, m
            t(i, i) = 1.0_dp
        end do
        t(:, m + 1:2 * m) = -mat
        t(:, z0) = -1.0_dp
        rhs = q
        basis = [(i, i = 1, m)]
        ! z0 enters where q is most negative; of tied rows the last keeps the tableau
        ! lexicographically positive
        best = minval(q)
        r = 0
        do i = 1, m
            if (q(i) == best) r = i
        end do
        call pivot(r, z0)
        leaving = r
        do
            entering = complement(leaving)
            if (pivots >= max_pivots) then
                status = LCP_BUDGET
                exit
            end if
            col = t(:, entering)
            tie = 1.0e-12_dp * maxval(abs(col))
            ! minimum ratio over rows whose basic variable decreases; ties: z0's row if it is
            ! one (the end), else the lexicographic minimum of the rows of B^-1 / col
            r = 0
            best = huge(1.0_dp)
            do i = 1, m
                if (col(i) <= tie) cycle
                ratio = max(rhs(i), 0.0_dp) / col(i)
                if (ratio < best) then
                    best = ratio
                    r = i
                end if
            end do
            if (r == 0) then
                status = LCP_RAY
                exit
            end if
            r = tie_break(best, tie)
            leaving = basis(r)
            call pivot(r, entering)
            if (status /= LCP_SOLVED) exit
            if (leaving == z0) exit
        end do
        if (status /= LCP_SOLVED) return
        do i = 1, m
            if (basis(i) <= m) then
                y(basis(i)) = max(rhs(i), 0.0_dp)
            else if (basis(i) <= 2 * m) then
                z(basis(i) - m) = max(rhs(i), 0.0_dp)
            end if
        end do
    contains

        !> The complement of a variable (y_i <-> z_i); z0's has none (not called for it).
        pure integer function complement(k) result(c)
            integer, intent(in) :: k
            if (k <= m) then
                c = k + m
            else
                c = k - m
            end if
        end function complement

        !> Among the rows tied at the minimum ratio best: z0's row, else the lexicographic
        !! minimum of (rhs_i, B^-1 row i) / col_i.
        integer function tie_break(best, tiny_col) result(r)
            real(dp), intent(in) :: best, tiny_col
            integer :: i, k, cand(m), nc
            real(dp) :: slack, a, b
            slack = 1.0e-12_dp * max(best, 1.0e-300_dp) + 1.0e-15_dp * maxval(abs(rhs)) / maxval(abs(col))
            nc = 0
            do i = 1, m
                if (col(i) <= tiny_col) cycle
                if (max(rhs(i), 0.0_dp) / col(i) <= best + slack) then
                    nc = nc + 1
                    cand(nc) = i
                end if
            end do
            r = cand(1)
            do i = 1, nc
                if (basis(cand(i)) == z0) then
                    r = cand(i)
                    return
                end if
            end do
            do i = 2, nc
                do k = 1, m
                    a = t(cand(i), k) / col(cand(i))
                    b = t(r, k) / col(r)
                    if (a < b) then
                        r = cand(i)
                        exit
                    else if (a > b) then
                        exit
                    end if
                end do
            end do
        end function tie_break

        !> Gauss-Jordan pivot on t(r, c): variable c becomes basic in row r.
        subroutine pivot(r, c)
            integer, intent(in) :: r, c
            real(dp) :: piv, f, colc(m)
            integer :: j
            piv = t(r, c)
            if (.not. (abs(piv) > 0.0_dp .and. ieee_is_finite(piv))) then
                status = LCP_BAD
                return
            end if
            ! column by column (contiguous): t := t - (t(:, c) - e_r) t(r, :) / piv (row r divided by piv)
            colc = t(:, c)
            colc(r) = colc(r) - 1.0_dp
            colc = colc / piv
            do j = 1, size(t, 2)
                f = t(r, j)
                if (f == 0.0_dp) cycle
                t(:, j) = t(:, j) - f * colc
            end do
            f = rhs(r)
            rhs = rhs - f * colc
            t(:, c) = 0.0_dp
            t(r, c) = 1.0_dp
            basis(r) = c
            pivots = pivots + 1
        end subroutine pivot
    end subroutine lemke

    !> The box problem of the module notes, by `lemke` on its LCP form.
    !! ok: solved; then p is in the box and y = D p + q.
    subroutine box_lcp(d, q, lo, hi, p, y, pivots, ok)
        real(dp), intent(in)  :: d(:, :)   !! (n, n) symmetric positive semidefinite matrix [1/kg]
        real(dp), intent(in)  :: q(:)      !! (n) the free term [m/s]
        real(dp), intent(in)  :: lo(:)     !! (n) lower bounds [N s]
        real(dp), intent(in)  :: hi(:)     !! (n) upper bounds, > lo [N s]
        real(dp), intent(out) :: p(:)      !! (n) the solution [N s]
        real(dp), intent(out) :: y(:)      !! (n) D p + q [m/s]
        integer, intent(out)  :: pivots    !! pivots done
        logical, intent(out)  :: ok        !! a solution was found
        real(dp) :: mat(2 * size(q), 2 * size(q)), qq(2 * size(q)), z(2 * size(q)), yy(2 * size(q))
        integer :: n, i, status
        n = size(q)
        mat = 0.0_dp
        mat(:n, :n) = d
        do i = 1, n
            mat(i, n + i) = 1.0_dp
            mat(n + i, i) = -1.0_dp
        end do
        qq(:n) = q + matmul(d, lo)
        qq(n + 1:) = hi - lo
        call lemke(mat, qq, z, yy, 50 * (2 * n + 1), pivots, status)
        ok = status == LCP_SOLVED
        p = min(max(lo + z(:n), lo), hi)
        y = q + matmul(d, p)
    end subroutine box_lcp

    !> The box problem of the module notes by the active-set Newton method, Lemke's method
    !! (`box_lcp`) where that does not end (module notes). act: the set of each unknown in
    !! (a warm start: -1 at lo, +1 at hi, 0 free) and out. ok: solved; then p is in the box
    !! and y = D p + q.
    subroutine box_solve(d, q, lo, hi, wts, p, y, act, its, pivots, ok, lemke_only)
        real(dp), intent(in)    :: d(:, :)   !! (n, n) symmetric positive semidefinite matrix [1/kg]
        real(dp), intent(in)    :: q(:)      !! (n) the free term [m/s]
        real(dp), intent(in)    :: lo(:)     !! (n) lower bounds [N s]
        real(dp), intent(in)    :: hi(:)     !! (n) upper bounds, > lo [N s]
        real(dp), intent(in)    :: wts(:)    !! (n) weights of the minimum norm of a singular free block, > 0
        real(dp), intent(out)   :: p(:)      !! (n) the solution [N s]
        real(dp), intent(out)   :: y(:)      !! (n) D p + q [m/s]
        integer, intent(inout)  :: act(:)    !! (n) -1 at lo, +1 at hi, 0 free: warm start in, sets out
        integer, intent(out)    :: its       !! active-set iterations (linear solves) done
        integer, intent(out)    :: pivots    !! Lemke pivots (0: not needed)
        logical, intent(out)    :: ok        !! a solution was found
        logical, intent(in), optional :: lemke_only  !! skip the Newton method (tests, benchmarks)
        integer :: n, nf, i, j, k, fr(size(q))
        real(dp) :: rhs(size(q), 1), a(size(q), size(q)), ytol, ptol(size(q)), dmax
        logical :: changed
        n = size(q)
        pivots = 0
        its = 0
        ok = .true.
        dmax = 0.0_dp
        do i = 1, n
            dmax = max(dmax, d(i, i))
        end do
        ptol = 1.0e-12_dp * (hi - lo)
        if (present(lemke_only)) then
            if (lemke_only) ok = .false.
        end if
        do while (ok .and. its < 2 * n + 10)
            its = its + 1
            nf = 0
            do i = 1, n
                if (act(i) > 0) then
                    p(i) = hi(i)
                else if (act(i) < 0) then
                    p(i) = lo(i)
                else
                    p(i) = 0.0_dp
                    nf = nf + 1
                    fr(nf) = i
                end if
            end do
            if (nf > 0) then
                ! D_FF p_F = -(q_F + D_FB p_B)
                do k = 1, nf
                    i = fr(k)
                    rhs(k, 1) = -q(i)
                    do j = 1, n
                        if (act(j) /= 0) rhs(k, 1) = rhs(k, 1) - d(i, j) * p(j)
                    end do
                    a(:nf, k) = d(fr(:nf), i)
                end do
                call psd_solve(a(:nf, :nf), rhs(:nf, :), wts(fr(:nf)), ok, regular_only=.true.)
                if (.not. ok) exit
                p(fr(:nf)) = rhs(:nf, 1)
            end if
            y = q + matmul(d, p)
            ytol = 1.0e3_dp * epsilon(1.0_dp) * (maxval(abs(q)) + dmax * maxval(abs(p)))
            changed = .false.
            do i = 1, n
                select case (act(i))
                case (0)
                    if (p(i) > hi(i) + ptol(i)) then
                        act(i) = 1
                        changed = .true.
                    else if (p(i) < lo(i) - ptol(i)) then
                        act(i) = -1
                        changed = .true.
                    end if
                case (1)
                    if (y(i) > ytol) then
                        act(i) = 0
                        changed = .true.
                    end if
                case default
                    if (y(i) < -ytol) then
                        act(i) = 0
                        changed = .true.
                    end if
                end select
            end do
            if (.not. changed) then
                p = min(max(p, lo), hi)
                return
            end if
        end do
        ! the exact fallback
        call box_lcp(d, q, lo, hi, p, y, pivots, ok)
        do i = 1, n
            act(i) = 0
            if (p(i) >= hi(i) .and. y(i) < 0.0_dp) act(i) = 1
            if (p(i) <= lo(i) .and. y(i) > 0.0_dp) act(i) = -1
        end do
    end subroutine box_solve

end module stickslip_lcp
