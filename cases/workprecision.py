"""Work-precision: error against a reference versus CPU time and function evaluations, for each
scene x law x method, RK4 with h = 1e-2 .. 1e-6 s, DOPRI5 and RADAU5 with rtol = 1e-2 .. 1e-12
(RADAU5 not on the Coulomb slope, where it forces about 1e7 steps at h_min per run)::

    python -m cases.workprecision --outdir out/          # about 30 s on 2 cores
    python -m cases.workprecision --outdir out/ --quick  # t_end = 2 s, h >= 1e-5, rtol >= 1e-10

Two errors, kept apart (both at t_end, on x, in m):

- discretisation error: against a converged solution of the *same* law. Analytic where one
  exists: on the belt from rest with v_b > v_d the mass never gets near the belt speed
  (max x' = x_k w = 0.54 m/s < v_b), so Coulomb and RecurDyn give mu = mu_k throughout and the
  harmonic orbit x(t) = x_k (1 - cos w t), x_k = mu_k m g / k, w = sqrt(k/m). Coulomb on the
  slope: the limit of event-free stepping as h -> 0 is the sticking (Filippov) solution x = 0.
  Otherwise (RecurDyn and proposed on the slope, proposed on the belt): DOPRI5 at rtol = 1e-13,
  atol = 1e-16, h_min = 0, h_max = 1e-2 s, whose convergence is shown by the difference to the
  same run at rtol = 1e-12 (column ref_uncertainty).
- model error: against the physical truth: the box on the slope does not move (x = 0); the
  mass on the belt follows the Coulomb cycle (here the harmonic orbit above).

DOPRI5 and RADAU5 runs use atol = 1e-3 rtol, the paper's h_min = 1e-6 s (forced steps there) and no h_max
(so that loose tolerances cost little). t_end = 20 s (the paper's duration) for both scenes.
Observed orders are least-squares slopes of log(discretisation error) against log(h) (RK4) and
against -log(nfev) (DOPRI5, RADAU5), over the points whose error lies between 100x the reference's
uncertainty (or 1e-13 m) and 1e-2 m, up to the smallest error (beyond it round-off rules);
nfev_ratio is max/min nfev over the sweep (near 1: the cost is set by stability, not accuracy,
and an order against nfev means nothing) and tol_slope the slope of log(error) against
log(rtol) (1 = tolerance proportionality).
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import _common as c
from . import _progress

SCENES: tuple[str, ...] = ("slope", "belt")
LAWS: tuple[str, ...] = c.PAPER_LAWS
METHODS: tuple[str, ...] = ("rk4", "dopri5", "radau5")
T_END: float = 20.0
T_END_QUICK: float = 2.0
HS: tuple[float, ...] = tuple(float(f"{10.0 ** e:.3g}") for e in np.arange(-2.0, -6.01, -0.5))
RTOLS: tuple[float, ...] = tuple(10.0 ** -e for e in range(2, 13))
HMIN: float = 1e-6                 # the paper's automatic range, lower end [s]
REF_RTOL: tuple[float, float] = (1e-13, 1e-12)
ERR_FLOOR: float = 1e-13           # below this an error is round-off [m]
#: DOPRI5's order against nfev is reported only when the sweep's cost varies at least this
#: much (max/min nfev): where stability sets the step, the cost hardly moves with the
#: tolerance and the slope of error against nfev is a division by almost zero (858.8).
MIN_COST_SPREAD: float = 2.0
ORDERS_CAPTION: str = (
    "Observed orders (workprecision_orders.csv). order [-]: slope of log(discretisation error) "
    "against log(h) (RK4) or -log(nfev) (DOPRI5), fitted where the error lies between "
    "max(1e-13 m, 100 x the reference's uncertainty) and 1e-2 m; expected [-]: the method's order "
    "on smooth motion; points [-]: points in the fit; nfev_ratio [-]: max/min function "
    "evaluations over the sweep; tol_slope [-]: slope of log(error) against log(rtol) "
    "(1 = proportional to the tolerance); err_min, err_max [m]: errors in the fitted range. "
    "Empty: not meaningful: fewer than 3 points above round-off and before the error stops "
    "falling (Coulomb on the slope with DOPRI5: pinned at h_min, the error is 8.4e-6 m at every "
    "rtol <= 1e-4), or a DOPRI5 cost that barely moves with rtol "
    f"(nfev_ratio < {MIN_COST_SPREAD:g}: stability, not accuracy, sets the step).")

HEADER: list[str] = [
    "scene [-]", "law [-]", "method [-]", "h [s]", "rtol [-]", "atol [-]", "t_end [s]",
    "status [-]", "nfev [-]", "nstep [-]", "nforced [-]", "cpu [s]", "x_end [m]",
    "x_ref [m]", "ref_kind [-]", "ref_uncertainty [m]", "err_disc [m]", "x_truth [m]",
    "err_model [m]"]
ORDER_HEADER: list[str] = ["scene [-]", "law [-]", "method [-]", "order [-]", "expected [-]",
                           "points [-]", "nfev_ratio [-]", "tol_slope [-]", "err_min [m]",
                           "err_max [m]"]


def harmonic_x(t: float, params: dict[str, float]) -> float:
    """x(t) [m] of the belt from rest under a constant mu = mu_k: x_k (1 - cos w t)."""
    w = math.sqrt(params["k"] / params["m"])
    x_k = params["mu_k"] * params["m"] * params["g"] / params["k"]
    return x_k * (1.0 - math.cos(w * t))


def references(t_end: float, threads: int,
               client: Any = None) -> dict[tuple[str, str], dict[str, Any]]:
    """The converged solution of each (scene, law) at t_end, and the physical truth."""
    import stickslip
    p = dict(stickslip.DEFAULTS)
    p["v_d"] = 1.5 * p["v_s"]
    out: dict[tuple[str, str], dict[str, Any]] = {}
    truth_belt = harmonic_x(t_end, p)
    need = [(s, l) for s in SCENES for l in LAWS
            if not (l == "coulomb" or (s == "belt" and l == "recurdyn"))]
    r = stickslip.simulate_batch([s for s, _ in need for _ in REF_RTOL],
                                 [l for _, l in need for _ in REF_RTOL], method="dopri5",
                                 t_end=t_end, rtol=list(REF_RTOL) * len(need),
                                 atol=[1e-16, 1e-15] * len(need), hmin=0.0, hmax=1e-2,
                                 max_steps=10**7, n_grid=2, threads=threads, client=client)
    if not np.all(r.ok):
        raise RuntimeError("a reference run failed: " + r.message(int(np.flatnonzero(~r.ok)[0])))
    for i, (s, l) in enumerate(need):
        a, b = r.x_end[2 * i], r.x_end[2 * i + 1]
        out[(s, l)] = {"x": float(a), "kind": "dopri5 rtol 1e-13", "unc": float(abs(a - b))}
    out[("slope", "coulomb")] = {"x": 0.0, "kind": "sticking (Filippov) x = 0", "unc": 0.0}
    for l in ("coulomb", "recurdyn"):
        out[("belt", l)] = {"x": truth_belt, "kind": "analytic harmonic orbit", "unc": 0.0}
    for (s, l), ref in out.items():
        ref["truth"] = 0.0 if s == "slope" else truth_belt
    return out


def fit_order(x: np.ndarray, err: np.ndarray, lo: float,
              hi: float = 1e-2) -> tuple[float | None, int]:
    """Least-squares slope of log(err) against log(x), x decreasing (h, or 1/nfev), over the
    asymptotic range: the points with lo < err < hi up to the one of smallest error (beyond it
    round-off or the reference's uncertainty dominates). None when fewer than 3 points are
    left: an order fitted to errors at round-off or zero means nothing."""
    order = np.argsort(-x)
    x, err = x[order], err[order]
    finite = np.isfinite(err) & (x > 0)
    if not finite.any():
        return None, 0
    stop = int(np.nanargmin(np.where(finite, err, np.nan)))
    sel = finite & (err > lo) & (err < hi) & (np.arange(x.size) <= stop)
    if sel.sum() < 3:
        return None, int(sel.sum())
    slope = np.polyfit(np.log(x[sel]), np.log(err[sel]), 1)[0]
    return float(slope), int(sel.sum())


def run(outdir: str | Path, *, quick: bool = False, threads: int = 2,
        quiet: bool = False, scheduler: str | None = None) -> list[Path]:
    """Run the sweeps, write workprecision.csv and workprecision_orders.csv, then plot; on the
    Dask cluster at `scheduler` when given."""
    from stickslip.distributed import connect
    with connect(scheduler) as client:
        return _run(outdir, quick=quick, threads=threads, quiet=quiet, client=client)


def _run(outdir: str | Path, *, quick: bool, threads: int, quiet: bool,
         client: Any) -> list[Path]:
    import stickslip
    outdir = Path(outdir)
    t_end = T_END_QUICK if quick else T_END
    hs = [h for h in HS if h >= (1e-5 if quick else 1e-6)]
    rtols = [r for r in RTOLS if r >= (1e-10 if quick else 1e-12)]

    c.log(f"workprecision: references (t_end = {t_end} s)", quiet)
    refs = references(t_end, threads, client)

    rows: list[dict[str, Any]] = []
    for s in SCENES:
        for l in LAWS:
            rows += [{"scene": s, "law": l, "method": "rk4", "h": h, "rtol": 0.0, "atol": 0.0}
                     for h in hs]
            rows += [{"scene": s, "law": l, "method": "dopri5", "h": float("nan"), "rtol": r,
                      "atol": 1e-3 * r} for r in rtols]
            if (s, l) != ("slope", "coulomb"):     # RADAU5 forces 1e7 steps there: 20 s a run
                rows += [{"scene": s, "law": l, "method": "radau5", "h": float("nan"), "rtol": r,
                          "atol": 1e-3 * r} for r in rtols]
    c.log(f"workprecision: {len(rows)} runs in one batch, {threads} thread(s)", quiet)
    with c.steps_beyond_stability():               # the step sweep crosses RK4's bound on purpose
        r = stickslip.simulate_batch(
            [q["scene"] for q in rows], [q["law"] for q in rows], method=[q["method"] for q in rows],
            t_end=t_end, h=[q["h"] for q in rows], rtol=[q["rtol"] or 1e-6 for q in rows],
            atol=[q["atol"] or 1e-9 for q in rows], hmin=HMIN, hmax=0.0, max_steps=10**8,
            n_grid=2, threads=threads, client=client, progress=_progress.shown(quiet))

    table = []
    for i, q in enumerate(rows):
        ref = refs[(q["scene"], q["law"])]
        ok = r.status[i] == 0
        x = float(r.x_end[i]) if ok else float("nan")
        table.append([q["scene"], q["law"], q["method"], q["h"] if q["method"] == "rk4" else None,
                      q["rtol"] or None, q["atol"] or None, t_end, int(r.status[i]),
                      int(r.nfev[i]), int(r.nstep[i]), int(r.nforced[i]), float(r.seconds[i]),
                      x, ref["x"], ref["kind"], ref["unc"], abs(x - ref["x"]), ref["truth"],
                      abs(x - ref["truth"])])
    csv_path = c.write_csv(outdir / "workprecision.csv", HEADER, table)

    orders = []
    for s in SCENES:
        for l in LAWS:
            ref = refs[(s, l)]
            lo = max(ERR_FLOOR, 100.0 * ref["unc"])
            for m, expected in (("rk4", 4.0), ("dopri5", 5.0), ("radau5", 5.0)):
                sel = [row for row in table if row[0] == s and row[1] == l and row[2] == m]
                if not sel:
                    continue
                err = np.array([row[16] for row in sel], dtype=float)
                nfev = np.array([row[8] for row in sel], dtype=float)
                tol_slope = None
                if m == "rk4":
                    order, npts = fit_order(np.array([row[3] for row in sel], float), err, lo)
                else:
                    order, npts = fit_order(1.0 / nfev, err, lo)
                    tol_slope, _ = fit_order(np.array([row[4] for row in sel], float), err, lo)
                ratio = float(nfev.max() / nfev.min())
                if m == "dopri5" and ratio < MIN_COST_SPREAD:
                    order = None              # the cost does not follow the tolerance
                good = err[(err > lo) & (err < 1e-2)]
                orders.append([s, l, m, order, expected, npts, ratio, tol_slope,
                               float(good.min()) if good.size else None,
                               float(good.max()) if good.size else None])
    orders_path = c.write_csv(outdir / "workprecision_orders.csv", ORDER_HEADER, orders)
    c.log_caption(ORDERS_CAPTION, quiet)
    c.log(c.markdown_table(ORDER_HEADER, orders), quiet)
    return [csv_path, orders_path] + plot(csv_path, outdir)


#: Errors below this are drawn at it (exact zeros cannot be shown on a log axis) [m].
ERR_DRAWN: float = 1e-16
#: What the work-precision figures show and why a curve need not fall monotonically.
CAPTION: str = (
    "Discretisation error (solid): distance of x(t_end) from a converged solution of the same "
    "law (exact where one is known, else DOPRI5 at rtol = 1e-13): what a smaller step or "
    "tolerance removes. Model error (dashed): distance of x(t_end) from the physical truth (the "
    "box does not move; the mass on the belt follows the Coulomb orbit): what the friction law "
    "itself gets wrong, which no step or tolerance removes. A curve is not monotone where the "
    "signed error crosses zero (a dip), where round-off (about 1e-12 m over 20 s) sets a floor, "
    "or, for the proposed law on the belt, where the error is set by when each slip onset "
    f"happens, which moves unevenly with the tolerance. Errors below {1e-16:g} m are drawn at "
    f"{1e-16:g} m; the Coulomb slope has no RADAU5 run (it would force about 1e7 steps at h_min).")


def plot(csv: str | Path, outdir: str | Path) -> list[Path]:
    """Render workprecision.csv: error vs function evaluations and error vs CPU time, one panel
    per scene and law (log-log); solid = discretisation error, dashed = model error."""
    cols = c.read_csv(csv)
    num = {k: np.array([float(v) if v != "" else np.nan for v in vals])
           for k, vals in cols.items() if k.split(" [")[0] not in ("scene", "law", "method", "ref_kind")}
    paths = []
    runs = "RK4 with h = 1e-2 .. 1e-6 s; DOPRI5 and RADAU5 with rtol = 1e-2 .. 1e-12, atol = 1e-3 rtol"
    t_end = float(num["t_end [s]"][0])
    for xkey, fname, xlabel in (("nfev [-]", "workprecision_nfev.png", "function evaluations [-]"),
                                ("cpu [s]", "workprecision_cpu.png", "CPU time per run [s]")):
        c._style.apply()
        fig, axes = c.plt.subplots(len(SCENES), len(LAWS), figsize=(11.0, 6.6), squeeze=False)
        for a, s in enumerate(SCENES):
            for b, l in enumerate(LAWS):
                ax = axes[a][b]
                for m in METHODS:
                    sel = np.array([cols["scene [-]"][i] == s and cols["law [-]"][i] == l and
                                    cols["method [-]"][i] == m for i in range(len(cols["law [-]"]))])
                    x = num[xkey][sel]
                    for key, style, lab in (("err_disc [m]", "o-", "discretisation error"),
                                            ("err_model [m]", "x--", "model error")):
                        y = np.maximum(num[key][sel], ERR_DRAWN)
                        ax.loglog(x, y, style, color=c._style.color(m), ms=3, lw=1.0,
                                  label=f"{c._style.name(m)}: {lab}")
                ax.set_title(f"{c._style.name(s)}, {c.LAW_LABELS[l]} law")
                ax.grid(True, which="both", alpha=0.3)
                if a == len(SCENES) - 1:
                    ax.set_xlabel(xlabel)
                if b == 0:
                    ax.set_ylabel(f"error in x({t_end:g} s) [m]")
        fig.suptitle(f"Error against cost, {t_end:g} s of motion: {runs}")
        # how to read it (CAPTION) is the page's text, not the image's: docs/guide/choosing-h.md
        c.figure_legend(fig, axes.ravel(), ncol=3)
        paths.append(c.save_figure(fig, Path(outdir) / fname))
    return paths


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.workprecision [--outdir DIR] [--quick] [--threads N]
    [--scheduler ADDRESS]."""
    return c.study_main("cases.workprecision", __doc__,
                        f"t_end = {T_END_QUICK} s, h >= 1e-5 s, rtol >= 1e-10 (a few seconds)",
                        run, argv)


if __name__ == "__main__":
    main()
