"""Benchmarks of stickslip against the tools users would pick instead.

Run from the repository root: ``python -m benchmarks [--quick] [--outdir DIR]``.

Side by side in one run, on the same scenes and laws, reported as ratios against a reference
measured in the same run (never absolute times): stickslip's RK4 and DOPRI5 called from Python
and from Fortran directly (``benchmarks/bench_fortran.f90``), scipy's ``solve_ivp`` (RK45,
DOP853, LSODA) with a Python right-hand side, GSL's ``gsl_odeiv2`` (rk4, rkf45, rkck, rk8pd;
``benchmarks/bench_gsl.c``), and a plain C RK4 loop (``benchmarks/bench_cloop.c``), the
practical limit. The compiled programs are built by meson in ``build/bench``.
"""
