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

    public :: lu_decompose, lu_solve, band_decompose, band_solve

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

end module stickslip_linalg
