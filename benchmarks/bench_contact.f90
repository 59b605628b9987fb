!> The per-step contact solver (`stickslip_contact_solver`) on random coupled problems, against
!! projected Gauss-Seidel alone and static-first pivoting (Lemke) alone on the same problems. For each number of contacts n: problems
!! w = wf + D p with D = H W^-1 H^T (H: rows of one or two +-1 entries over n/2 + 1 coordinates,
!! so contacts are coupled; W symmetric positive definite), Coulomb laws with mu_s >= mu_k, and
!! capacities scaled like a step of 1 ms. Prints one line per n:
!!   n  us_per_solve  solved_fraction  gs_us_per_solve  gs_solved_fraction  modes_or_sweeps
!!   fallback_fraction  piv_us_per_solve  piv_solved_fraction  pivots
!! (fallback_fraction: problems where the solver fell back to pivoting; pivots: Lemke pivots a
!! solve of pivoting alone)
!! (microseconds a solve, the median of `repeats` passes over the problems; Gauss-Seidel alone
!! counts as solved where its answer meets the conditions to 1e-12 m/s).
!! Usage: bench_contact n_max repeats
program bench_contact
    use stickslip_kinds, only: dp
    use stickslip_contact, only: contact_law
    use stickslip_contact_solver, only: solve_contacts, contact_solve_info, gauss_seidel, contact_residual, &
                                        SOLVER_PIVOTING
    use stickslip_linalg, only: psd_solve
    implicit none
    integer, parameter :: nprob = 50
    character(len=32) :: arg
    integer :: n_max, repeats, n, k, r, nd, i, j, iseed
    integer, allocatable :: seed(:), mode(:)
    real(dp), allocatable :: d(:, :, :), wf(:, :), cap(:, :), p(:), w(:), hm(:, :), wm(:, :), winv(:, :), times(:), gtimes(:)
    real(dp), allocatable :: ptimes(:)
    type(contact_law), allocatable :: laws(:, :)
    type(contact_solve_info) :: info
    real(dp) :: u, t0, t1, resid, work
    integer :: nok, ngs, sweeps, worst, ns_list(10), nfall, npiv
    real(dp) :: pivots
    logical :: ok_inv

    call get_command_argument(1, arg)
    read (arg, *) n_max
    call get_command_argument(2, arg)
    read (arg, *) repeats
    call random_seed(size=iseed)
    allocate(seed(iseed), source=4242)
    call random_seed(put=seed)
    ns_list = [2, 3, 4, 5, 6, 8, 16, 32, 64, 128]
    do k = 1, size(ns_list)
        n = ns_list(k)
        if (n > n_max) exit
        nd = n / 2 + 1
        allocate(d(n, n, nprob), wf(n, nprob), cap(n, nprob), laws(n, nprob), p(n), w(n), mode(n))
        allocate(hm(n, nd), wm(nd, nd), winv(nd, nd), times(repeats), gtimes(repeats), ptimes(repeats))
        do j = 1, nprob
            hm = 0.0_dp
            do i = 1, n
                call random_number(u)
                hm(i, 1 + mod(i - 1, nd)) = 1.0_dp
                if (u < 0.5_dp) hm(i, 1 + mod(i, nd)) = -1.0_dp
            end do
            call random_number(wm)
            wm = 0.1_dp * matmul(transpose(wm), wm)
            do i = 1, nd
                wm(i, i) = wm(i, i) + 1.0_dp
            end do
            winv = 0.0_dp                      ! W^-1 by the library's psd_solve (LU: W is regular)
            do i = 1, nd
                winv(i, i) = 1.0_dp
            end do
            call psd_solve(wm, winv, [(1.0_dp, i = 1, nd)], ok_inv)
            d(:, :, j) = matmul(hm, matmul(winv, transpose(hm)))
            call random_number(wf(:, j))
            wf(:, j) = 0.02_dp * (wf(:, j) - 0.5_dp)
            call random_number(cap(:, j))
            cap(:, j) = 1.0e-3_dp * 9.81_dp * (0.5_dp + cap(:, j))
            do i = 1, n
                call random_number(u)
                laws(i, j) = contact_law(mu_s=0.3_dp + 0.4_dp * u, mu_k=0.3_dp)
            end do
        end do
        work = 0.0_dp
        pivots = 0.0_dp
        do r = 1, repeats
            nok = 0
            nfall = 0
            call cpu_time(t0)
            do j = 1, nprob
                p = 0.0_dp
                mode = -9
                call solve_contacts(laws(:, j), d(:, :, j), wf(:, j), cap(:, j), .false., 1.0e-12_dp, 1000, &
                                    p, w, mode, info)
                if (info%ok) nok = nok + 1
                if (info%method == SOLVER_PIVOTING) nfall = nfall + 1
                work = work + info%sweeps
            end do
            call cpu_time(t1)
            times(r) = (t1 - t0) / nprob
            ngs = 0
            call cpu_time(t0)
            do j = 1, nprob
                p = 0.0_dp
                call gauss_seidel(laws(:, j), d(:, :, j), wf(:, j), cap(:, j), .false., 1.0e-12_dp, 1000, p, w, sweeps)
                mode = merge(0, nint(sign(1.0_dp, w)), w == 0.0_dp)
                call contact_residual(laws(:, j), d(:, :, j), wf(:, j), cap(:, j), .false., p, w, mode, resid, worst)
                if (resid <= 1.0e-12_dp) ngs = ngs + 1
            end do
            call cpu_time(t1)
            gtimes(r) = (t1 - t0) / nprob
            npiv = 0
            call cpu_time(t0)
            do j = 1, nprob
                p = 0.0_dp
                mode = -9
                call solve_contacts(laws(:, j), d(:, :, j), wf(:, j), cap(:, j), .false., 1.0e-12_dp, 1000, &
                                    p, w, mode, info, method=SOLVER_PIVOTING)
                if (info%ok) npiv = npiv + 1
                pivots = pivots + info%pivots
            end do
            call cpu_time(t1)
            ptimes(r) = (t1 - t0) / nprob
        end do
        print '(i5, es12.4, f8.3, es12.4, f8.3, f10.1, f8.3, es12.4, f8.3, f10.1)', n, 1.0e6_dp * median(times), &
            real(nok, dp) / nprob, 1.0e6_dp * median(gtimes), real(ngs, dp) / nprob, work / (repeats * nprob), &
            real(nfall, dp) / nprob, 1.0e6_dp * median(ptimes), real(npiv, dp) / nprob, pivots / (repeats * nprob)
        deallocate(d, wf, cap, laws, p, w, mode, hm, wm, winv, times, gtimes, ptimes)
    end do

contains

    real(dp) function median(x)
        real(dp), intent(in) :: x(:)
        real(dp) :: s(size(x)), tmp
        integer :: i, j
        s = x
        do i = 2, size(s)
            tmp = s(i)
            j = i - 1
            do while (j >= 1)
                if (s(j) <= tmp) exit
                s(j + 1) = s(j)
                j = j - 1
            end do
            s(j + 1) = tmp
        end do
        median = 0.5_dp * (s((size(s) + 1) / 2) + s(size(s) / 2 + 1))
    end function median

end program bench_contact
