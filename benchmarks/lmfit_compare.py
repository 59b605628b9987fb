"""Identification against lmfit (python -m benchmarks --lmfit): every law fitted to the ten 36 lb
damper records by stickslip.fit_friction and by the same fit written with lmfit, for time and
parameters. lmfit is a reference only (a development requirement, never one of stickslip's).

The same fit: the same model (stickslip.prescribed_motion per record, backlash and asymmetry
fitted, cases.identify's fixed parameters, subsampling, rtol and finite-difference step), the
same start (the data-derived one stickslip reports in FitResult.start), the same bounds (those
the fit applied, FitResult.bounds: the library's ranges, a stiffness at most 1000 times its
start, z_ba_ratio at most 0.999; mu_s >= mu_k and v_d > v_s as excess parameters through lmfit
expressions), the same optimiser (lmfit's method
"least_squares", scipy's trust-region reflective, x_scale="jac", the same diff_step and
max_nfev). Parameters are compared in units of stickslip's standard error without the
correlation inflation (lmfit's covariance has none).
"""
from __future__ import annotations

import math
import time
import warnings
from pathlib import Path
from typing import Callable

import numpy as np

#: A fit of the ten records must take less than this [s] of wall time (issue 31).
BUDGET_S: float = 5.0
COLUMNS = ("law [-]", "k [-]", "stickslip wall [s]", "stickslip cpu [s]", "stickslip nfev [-]", "stickslip nrmse [-]",
           "lmfit wall [s]", "lmfit cpu [s]", "lmfit nfev [-]", "lmfit nrmse [-]", "time ratio [-]",
           "max |dp|/s.e. [-]", "s.e. ratio median [-]", "under budget [-]", "default rtol cpu [s]",
           "default rtol nrmse [-]")


def _lmfit_fit(law: str, recs: list, fit, rtol: float, diff_step: float):
    """The fit of `fit` (a stickslip FitResult) written with lmfit, from its start."""
    import lmfit
    from stickslip import identify as I

    data = I._records(recs, None, None, None, None)
    forces = np.concatenate([d.force for d in data])
    params = lmfit.Parameters()
    ordered = {b: a for a, b in I.ORDERED_PAIRS if a in fit.free and b in fit.free}
    for name in sorted(fit.free, key=lambda n: n in ordered):       # expressions after their terms
        low, high = fit.bounds[name]
        if name in ordered:
            params.add("excess_" + name, value=max(fit.start[name] - fit.start[ordered[name]], 1e-9 * fit.start[name]),
                       min=0.0)
            params.add(name, expr=f"{ordered[name]} + excess_{name}")
        else:
            params.add(name, value=fit.start[name], min=low, max=high)
    fixed = {k: v for k, v in fit.params.items() if k not in fit.free}

    def residual(p):
        q = dict(fixed, **{name: p[name].value for name in fit.free})
        try:
            return np.concatenate([I._model(law, d, q, rtol) for d in data]) - forces
        except (RuntimeError, ValueError):
            return np.full(forces.size, 100.0 * float(np.ptp(forces)) + 1.0)

    # BLAS on one thread, as inside fit_friction (when threadpoolctl is installed): the same
    # linear-algebra setting on both sides
    with warnings.catch_warnings(), I._one_blas_thread():
        warnings.simplefilter("ignore")
        out = lmfit.minimize(residual, params, method="least_squares", x_scale="jac", diff_step=diff_step,
                             max_nfev=30 * len(fit.free))
    return out, forces


def run_lmfit(log: Callable[[str], None], repeats: int = 3, laws: tuple[str, ...] | None = None) -> tuple[list[dict], str]:
    """Rows (one per law) and the markdown table: medians of `repeats` timings of each fit."""
    import lmfit
    import scipy
    import stickslip
    from cases import identify as ci
    from harness.provenance import machine

    recs = [r for r, _ in ci.load_groups(stickslip.damper_files(36))["36lb"]]
    try:
        import threadpoolctl
        blas = f"Both fits run with BLAS on one thread (threadpoolctl {threadpoolctl.__version__}). "
    except ImportError:
        blas = "BLAS threads as the environment sets them, for both fits (threadpoolctl not installed). "
    rows = []
    for law in laws or stickslip.LAWS:
        # Wald intervals, as lmfit's (its conf_interval is a separate, much costlier call)
        kw = dict(fixed=ci.fixed_for(law), backlash="fit", asymmetry="fit", n_starts=1, rtol=ci.RTOL,
                  diff_step=ci.DIFF_STEP, interval="wald")
        walls, cpus, fit = [], [], None
        for _ in range(repeats):
            w0, c0 = time.perf_counter(), time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fit = stickslip.fit_friction(law, recs, **kw)
            walls.append(time.perf_counter() - w0)
            cpus.append(time.process_time() - c0)
        # once more at fit_friction's default rtol (1e-6) and diff_step (1e-4), one start
        c0 = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit_default = stickslip.fit_friction(law, recs, fixed=ci.fixed_for(law), backlash="fit",
                                                 asymmetry="fit", n_starts=1)
        cpu_default = time.process_time() - c0
        lwalls, lcpus, out = [], [], None
        for _ in range(repeats):
            w0, c0 = time.perf_counter(), time.process_time()
            out, forces = _lmfit_fit(law, recs, fit, ci.RTOL, ci.DIFF_STEP)
            lwalls.append(time.perf_counter() - w0)
            lcpus.append(time.process_time() - c0)
        infl = math.sqrt(fit.variance_inflation)
        dev, ratios = [], []
        for name in fit.free:
            se = fit.stderr[name] / infl
            dev.append(abs(out.params[name].value - fit.params[name]) / se if se > 0 and math.isfinite(se) else math.nan)
            lse = out.params[name].stderr
            if lse and math.isfinite(se) and se > 0:
                ratios.append(lse / se)
        rmse_l = math.sqrt(float(np.mean(out.residual ** 2)))
        row = {"law [-]": law, "k [-]": len(fit.free), "stickslip wall [s]": float(np.median(walls)),
               "stickslip cpu [s]": float(np.median(cpus)), "stickslip nfev [-]": fit.nfev,
               "stickslip nrmse [-]": fit.nrmse, "lmfit wall [s]": float(np.median(lwalls)),
               "lmfit cpu [s]": float(np.median(lcpus)), "lmfit nfev [-]": int(out.nfev),
               "lmfit nrmse [-]": rmse_l / float(np.ptp(forces)),
               "time ratio [-]": float(np.median(cpus)) / float(np.median(lcpus)),
               "max |dp|/s.e. [-]": float(np.nanmax(dev)) if dev else math.nan,
               "s.e. ratio median [-]": float(np.median(ratios)) if ratios else math.nan,
               "under budget [-]": "yes" if float(np.median(cpus)) < BUDGET_S else "no",
               "default rtol cpu [s]": cpu_default, "default rtol nrmse [-]": fit_default.nrmse}
        rows.append(row)
        log(f"{law}: stickslip {row['stickslip wall [s]']:.2f} s ({row['stickslip cpu [s]']:.2f} s CPU), "
            f"lmfit {row['lmfit wall [s]']:.2f} s ({row['lmfit cpu [s]']:.2f} s CPU), "
            f"max |dp|/se {row['max |dp|/s.e. [-]']:.3g}; default rtol {cpu_default:.2f} s CPU")
    lines = ["**Identification against lmfit** (`python -m benchmarks --lmfit`)", "",
             f"Machine: {machine()}. lmfit {lmfit.__version__}, scipy {scipy.__version__}. Each law fitted to "
             f"the ten 36 lb damper records ({sum(len(r) for r in recs)} samples, {ci.SAMPLES_PER_CYCLE} per "
             f"cycle; backlash and asymmetry fitted; rtol {ci.RTOL:g}, diff_step {ci.DIFF_STEP:g}, one start) by "
             "`stickslip.fit_friction` and by the same fit written with lmfit (same model, start, bounds, "
             f"optimiser; `benchmarks/lmfit_compare.py`), medians of {repeats}. Time ratio: stickslip's CPU time "
             "over lmfit's (stickslip's includes its standard errors, Wald intervals as lmfit's, and checks). max |dp|/s.e.: the largest "
             "difference of a parameter between the two fits in stickslip's standard errors (without the "
             "correlation inflation); s.e. ratio: lmfit's standard error over that one, median over the "
             "parameters (blank where lmfit gives none: a parameter at a bound makes its covariance singular). "
             "lmfit's nfev counts the Jacobian's evaluations, stickslip's does not. " + blas + "Wall times are of a machine "
             f"shared with other jobs; the budget, a fit in under {BUDGET_S:g} s, is checked on CPU time. Last "
             "column: stickslip once more at fit_friction's default rtol 1e-6 and diff_step 1e-4 (one start; "
             "default intervals: profile likelihood for the laws without states), CPU time.", "",
             "| law | k | stickslip [s] (CPU) | lmfit [s] (CPU) | time ratio | nfev stickslip / lmfit | "
             "nrmse stickslip / lmfit | max dp/s.e. | s.e. ratio | under 5 s CPU | default rtol [s CPU] |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['law [-]']} | {r['k [-]']} | {r['stickslip wall [s]']:.2f} ({r['stickslip cpu [s]']:.2f}) | "
                     f"{r['lmfit wall [s]']:.2f} ({r['lmfit cpu [s]']:.2f}) | {r['time ratio [-]']:.2f} | "
                     f"{r['stickslip nfev [-]']} / {r['lmfit nfev [-]']} | {r['stickslip nrmse [-]']:.4f} / "
                     f"{r['lmfit nrmse [-]']:.4f} | {r['max |dp|/s.e. [-]']:.2g} | {_blank(r['s.e. ratio median [-]'], '.2f')} | "
                     f"{r['under budget [-]']} | {r['default rtol cpu [s]']:.2f} |")
    return rows, "\n".join(lines) + "\n"


def _blank(value: float, fmt: str) -> str:
    return "" if not math.isfinite(value) else format(value, fmt)


def write_rows(rows: list[dict], path: Path) -> None:
    """The rows as a CSV with units in the header."""
    from harness.files import write_csv
    write_csv(path, COLUMNS, ([f"{r[c]:.6g}" if isinstance(r[c], float) else r[c] for c in COLUMNS] for r in rows))
