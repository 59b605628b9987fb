"""Work-precision: error against a reference versus CPU time and function evaluations, for each
scene x law x method of the library: the fixed-step methods (RK4, implicit Euler,
generalized-alpha, Moreau-Jean) with h = 1e-2 .. 1e-6 s, the adaptive ones (DOPRI5, DOP853,
RADAU5, event-driven) with rtol = 1e-2 .. 1e-12; the set-valued methods (Moreau-Jean,
event-driven) on the Coulomb law only (the library refuses the smooth laws), RADAU5 not on the
Coulomb slope, where it forces about 1e7 steps at h_min per run::

    python -m cases.workprecision --outdir out/          # 7 min on 2 busy cores (load 12)
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

The adaptive runs use atol = 1e-3 rtol, the paper's h_min = 1e-6 s (forced steps there) and no h_max
(so that loose tolerances cost little). t_end = 20 s (the paper's duration) for both scenes.
Observed orders are least-squares slopes of log(discretisation error) against log(h) (fixed
step) and against -log(nfev) (adaptive), over the points whose error lies between 100x the reference's
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
from matplotlib.ticker import FuncFormatter

from . import _common as c
from . import _progress

SCENES: tuple[str, ...] = ("slope", "belt")
LAWS: tuple[str, ...] = c.PAPER_LAWS
#: Every method of the library (stickslip.METHODS), fixed-step ones first.
METHODS: tuple[str, ...] = ("rk4", "implicit_euler", "galpha", "moreau",
                            "dopri5", "dop853", "radau5", "event_driven")
#: The methods swept over the step h (the others over rtol, with atol = 1e-3 rtol).
FIXED_STEP: tuple[str, ...] = ("rk4", "implicit_euler", "galpha", "moreau")
#: The set-valued methods and the laws they take (the library refuses the others).
SET_VALUED: tuple[str, ...] = ("moreau", "event_driven")
SET_VALUED_LAWS: tuple[str, ...] = ("coulomb", "stribeck")
#: Order of each method on smooth motion [-] (against h for the fixed-step ones, against
#: function evaluations for the adaptive ones; moreau: theta = 0.5, the trapezoidal rule
#: between events, first order across them; event_driven: DOPRI5 between the events).
EXPECTED_ORDER: dict[str, float] = {"rk4": 4.0, "implicit_euler": 1.0, "galpha": 2.0,
                                    "moreau": 2.0, "dopri5": 5.0, "dop853": 8.0,
                                    "radau5": 5.0, "event_driven": 5.0}
#: Pairs not run although the library takes them, and why (shown in the figure).
NOT_RUN: dict[tuple[str, str, str], str] = {
    ("slope", "coulomb", "radau5"): "not run: about 1e7 forced steps at h_min (20 s a run)"}
T_END: float = 20.0
T_END_QUICK: float = 2.0
HS: tuple[float, ...] = tuple(float(f"{10.0 ** e:.3g}") for e in np.arange(-2.0, -6.01, -0.5))
RTOLS: tuple[float, ...] = tuple(10.0 ** -e for e in range(2, 13))
HMIN: float = 1e-6                 # the paper's automatic range, lower end [s]
REF_RTOL: tuple[float, float] = (1e-13, 1e-12)
ERR_FLOOR: float = 1e-13           # below this an error is round-off [m]
#: The order of an explicit adaptive method (DOPRI5, DOP853, event-driven) against nfev is reported only when the sweep's cost varies at least this
#: much (max/min nfev): where stability sets the step, the cost hardly moves with the
#: tolerance and the slope of error against nfev is a division by almost zero (858.8).
MIN_COST_SPREAD: float = 2.0
ORDERS_CAPTION: str = (
    "Observed orders (workprecision_orders.csv). order [-]: slope of log(discretisation error) "
    "against log(h) (fixed step) or -log(nfev) (adaptive), fitted where the error lies between "
    "max(1e-13 m, 100 x the reference's uncertainty) and 1e-2 m; expected [-]: the method's order "
    "on smooth motion; points [-]: points in the fit; nfev_ratio [-]: max/min function "
    "evaluations over the sweep; tol_slope [-]: slope of log(error) against log(rtol) "
    "(1 = proportional to the tolerance); err_min, err_max [m]: errors in the fitted range. "
    "Empty: not meaningful: fewer than 3 points above round-off and before the error stops "
    "falling (Coulomb on the slope with DOPRI5: pinned at h_min, the error is 8.4e-6 m at every "
    "rtol <= 1e-4), or an explicit adaptive method's cost that barely moves with rtol "
    f"(nfev_ratio < {MIN_COST_SPREAD:g}: stability, not accuracy, sets the step).")

HEADER: list[str] = [
    "scene [-]", "law [-]", "method [-]", "h [s]", "rtol [-]", "atol [-]", "t_end [s]",
    "status [-]", "nfev [-]", "nstep [-]", "nforced [-]", "cpu [s]", "x_end [m]",
    "x_ref [m]", "ref_kind [-]", "ref_uncertainty [m]", "err_disc [m]", "x_truth [m]",
    "err_model [m]"]
ORDER_HEADER: list[str] = ["scene [-]", "law [-]", "method [-]", "order [-]", "expected [-]",
                           "points [-]", "nfev_ratio [-]", "tol_slope [-]", "err_min [m]",
                           "err_max [m]"]


def applies(scene: str, law: str, method: str) -> bool:
    """Whether the sweep runs `method` on (`scene`, `law`): not where the library refuses the
    law (a set-valued method on a smooth law) nor where NOT_RUN says why not."""
    if method in SET_VALUED and law not in SET_VALUED_LAWS:
        return False
    return (scene, law, method) not in NOT_RUN


def refusal(scene: str, law: str, method: str) -> str | None:
    """Why `method` has no curve on (`scene`, `law`), in words; None when it was run."""
    if method in SET_VALUED and law not in SET_VALUED_LAWS:
        return "refused: takes Coulomb and Stribeck only"
    return NOT_RUN.get((scene, law, method))


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
            for m in METHODS:
                if not applies(s, l, m):
                    continue
                if m in FIXED_STEP:
                    rows += [{"scene": s, "law": l, "method": m, "h": h, "rtol": 0.0,
                              "atol": 0.0} for h in hs]
                else:
                    rows += [{"scene": s, "law": l, "method": m, "h": float("nan"), "rtol": r,
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
        table.append([q["scene"], q["law"], q["method"], q["h"] if q["method"] in FIXED_STEP else None,
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
            for m, expected in EXPECTED_ORDER.items():
                sel = [row for row in table if row[0] == s and row[1] == l and row[2] == m]
                if not sel:
                    continue
                err = np.array([row[16] for row in sel], dtype=float)
                nfev = np.array([row[8] for row in sel], dtype=float)
                tol_slope = None
                if m in FIXED_STEP:
                    order, npts = fit_order(np.array([row[3] for row in sel], float), err, lo)
                else:
                    order, npts = fit_order(1.0 / nfev, err, lo)
                    tol_slope, _ = fit_order(np.array([row[4] for row in sel], float), err, lo)
                ratio = float(nfev.max() / nfev.min())
                if m in ("dopri5", "dop853", "event_driven") and ratio < MIN_COST_SPREAD:
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
#: Width of a work-precision figure [in]; its fonts are scaled to stay legible at a column
#: width (harness.style.column_fonts).
WIDTH: float = 5.6
#: The two panels of each law: the methods swept over h, and those swept over rtol.
GROUPS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("fixed step (h)", FIXED_STEP),
    ("adaptive (rtol)", tuple(m for m in METHODS if m not in FIXED_STEP)))
#: What the work-precision figures show and why a curve need not fall monotonically (the
#: page's text: docs/guide/choosing-h.md).
CAPTION: str = (
    "Discretisation error (lines): distance of x(t_end) from a converged solution of the same "
    "law (exact where one is known, else DOPRI5 at rtol = 1e-13): what a smaller step or "
    "tolerance removes. Model error (grey band): distance of the converged solution from the "
    "physical truth (the box does not move; the mass on the belt follows the Coulomb orbit): "
    "what the friction law itself gets wrong, which no step or tolerance removes. Errors below "
    f"{ERR_DRAWN:g} m (exact zeros included) are drawn at {ERR_DRAWN:g} m; a failed run is a "
    "cross at the top of its panel; a method without a curve is named in the panel with the "
    "reason (refused by the library, or not run). Each row names its one reference at its top "
    "left: \"vs exact motion\" (the set-valued motion, for every method of the row, the "
    "regularised ones included) or \"vs converged run\" (the law's own DOPRI5 solution at rtol "
    "= 1e-13). Against CPU time, which is measured and not monotone in the tolerance, every "
    "run is a marker and the line joins the runs that no cheaper run beats.")


#: Height of a line of a panel's note, as a fraction of the panel's height [-].
NOTE_LINE: float = 0.12



def _reserve_top(axes_row: Sequence[Any], values: list[float], lines: int) -> None:
    """Set the shared log y-range of a row of panels so that the data (`values` [m]) leave a
    strip at the top free for `lines` lines of notes: a note then hides no point."""
    lo, hi = math.log10(min(values)), math.log10(max(values))
    lo, hi = lo - 0.3, max(hi, lo + 1.0) + 0.3
    strip = min(NOTE_LINE * lines + 0.03, 0.5) if lines else 0.0
    axes_row[0].set_ylim(10.0 ** lo, 10.0 ** (lo + (hi - lo) / (1.0 - strip)))
    top = 10.0 ** (hi + 0.5)
    for ax in axes_row:                   # no tick labels in the strip: no data up there
        ax.yaxis.set_major_formatter(FuncFormatter(
            lambda value, _: "" if value > top or value <= 0.0
            else f"$10^{{{round(math.log10(value))}}}$"))


#: Short names of the references of workprecision.csv (its ref_kind), shown in each row.
#: "vs exact motion": against the set-valued (physical) motion for every method of the row;
#: "vs converged run": against the same law's DOPRI5 solution at rtol = 1e-13 (CAPTION).
REFERENCE_NAMES: dict[str, str] = {
    "analytic harmonic orbit": "vs exact motion",
    "sticking (Filippov) x = 0": "vs exact motion",
    "dopri5 rtol 1e-13": "vs converged run"}


def pareto_front(cost: np.ndarray, err: np.ndarray) -> np.ndarray:
    """Indices of the runs no cheaper run beats in error, by increasing `cost`: the line of a
    work-precision diagram whose cost is measured (CPU time), which is not monotone in the
    tolerance."""
    order = np.argsort(cost, kind="stable")
    keep, best = [], math.inf
    for i in order:
        if err[i] < best:
            keep.append(i)
            best = err[i]
    return np.array(keep, dtype=int)


def plot(csv: str | Path, outdir: str | Path) -> list[Path]:
    """Render workprecision.csv: error against function evaluations and against CPU time, one
    figure per scene and cost (workprecision_<cost>_<scene>.png), a row per law and two panels
    a row (fixed-step methods, adaptive methods; at most four methods a panel, each with its
    colour and marker of harness.style), log-log. Lines: discretisation error; grey dashed line:
    the law's model error (its converged solution against the physical truth); grey dotted
    line: ERR_DRAWN, where exact zeros are drawn; a cross at the top: a failed run. Against CPU
    time (measured, not monotone in the tolerance) every run is a marker and the line joins the
    front (pareto_front). The left panel of a row names its reference. A note in
    the panel names the methods refused or not run there, and those whose error is exactly 0
    at every point (their markers lie on each other at ERR_DRAWN)."""
    from matplotlib.lines import Line2D
    from matplotlib.ticker import LogLocator
    from matplotlib.transforms import blended_transform_factory
    cols = c.read_csv(csv)
    num = {k: np.array([float(v) if v != "" else np.nan for v in vals])
           for k, vals in cols.items() if k.split(" [")[0] not in ("scene", "law", "method", "ref_kind")}
    scene_of, law_of, method_of = (np.array(cols[k]) for k in ("scene [-]", "law [-]", "method [-]"))
    paths = []
    t_end = float(num["t_end [s]"][0])
    short = {m: c._style.name(m).split(" (")[0] for m in METHODS}
    for xkey, stem, xlabel in (("nfev [-]", "workprecision_nfev", "evaluations [-]"),
                               ("cpu [s]", "workprecision_cpu", "CPU time per run [s]")):
        for s in SCENES:
            c._style.apply(WIDTH)
            fig, axes = c.plt.subplots(len(LAWS), len(GROUPS), figsize=(WIDTH, 8.2),
                                       squeeze=False, sharex="col", sharey="row", layout="constrained")
            legend: dict[str, Any] = {}
            for a, l in enumerate(LAWS):
                row_values: list[float] = []
                row_notes: list[tuple[Any, list[str]]] = []
                here = (scene_of == s) & (law_of == l)
                model = np.abs(num["x_ref [m]"][here] - num["x_truth [m]"][here])
                for b, (group, methods) in enumerate(GROUPS):
                    ax = axes[a][b]
                    top = blended_transform_factory(ax.transData, ax.transAxes)
                    if model.size and model[0] > 0.0:
                        row_values.append(max(float(model[0]), ERR_DRAWN))
                        legend["model error of the law"] = ax.axhline(
                            max(float(model[0]), ERR_DRAWN), color="0.45", ls="--", lw=1.0)
                    notes, zeros = [], []
                    for m in methods:
                        why = refusal(s, l, m)
                        if why is not None:
                            notes.append(f"{short[m]}: {why.split(':')[0]}")   # the page says why
                            continue
                        sel = here & (method_of == m)
                        x = num[xkey][sel]
                        y = num["err_disc [m]"][sel]
                        ok = num["status [-]"][sel] == 0
                        look = {"color": c._style.color(m), "marker": c._style.METHOD_MARKERS[m],
                                "ms": 5, "lw": 1.2, "mec": "black" if m == "event_driven" else None,
                                "mew": 0.5}
                        yd = np.maximum(y[ok], ERR_DRAWN)
                        if xkey == "cpu [s]":  # a timed sweep is not monotone in CPU time:
                            # every run a marker, the line through the front (cheapest error)
                            ax.loglog(x[ok], yd, linestyle="none", **look)
                            front = pareto_front(x[ok], yd)
                            legend[short[m]] = ax.loglog(x[ok][front], yd[front], "-", **look)[0]
                        else:
                            legend[short[m]] = ax.loglog(x[ok], yd, "-", **look)[0]
                        row_values += [max(float(yi), ERR_DRAWN) for yi in y[ok]]
                        if ok.any() and np.all(y[ok] == 0.0):
                            zeros.append(short[m])
                        if (~ok).any():
                            legend["failed run"] = ax.plot(
                                x[~ok], np.full(int((~ok).sum()), 0.96), "x", transform=top,
                                color=c._style.color(m), ms=7, mew=1.5, clip_on=False)[0]
                    if zeros:
                        legend[f"error 0 (drawn at {ERR_DRAWN:g} m)"] = ax.axhline(
                            ERR_DRAWN, color="0.45", ls=":", lw=1.0)
                        notes += [f"error 0: {zeros[0]}"] + [f"  {z}" for z in zeros[1:]]
                    ax.grid(True, which="major", alpha=0.3)
                    ax.yaxis.set_major_locator(LogLocator(numticks=5))
                    row_notes.append((ax, notes))
                    if a == 0:
                        ax.set_title(group)
                    if b == 0:                # the row's one reference, stated in it
                        kinds = sorted(set(np.array(cols["ref_kind [-]"])[here]))
                        notes.insert(0, " or ".join(REFERENCE_NAMES.get(k, k) for k in kinds))
                        ax.set_ylabel(f"{c._style.name(l).split(' (')[0]}: error [m]")
                _reserve_top(axes[a], row_values or [ERR_DRAWN, 1.0],
                             max(len(n) for _, n in row_notes))
                for ax, notes in row_notes:       # in the strip the data leave free at the top
                    ax.text(0.03, 0.97, "\n".join(notes), transform=ax.transAxes, ha="left",
                            va="top", color="0.25", linespacing=1.1, in_layout=False)
            for ax in axes[-1]:
                ax.set_xlabel(xlabel)
                c.log_ticks(ax, "x")
            fig.suptitle(f"{c._style.name(s)}: error in x({t_end:g} s)")
            order = [short[m] for m in METHODS] + [k for k in legend if k not in short.values()]
            keys = [k for k in order if k in legend]
            fig.legend([legend[k] for k in keys], keys, loc="outside lower center", ncol=2,
                       frameon=False, handlelength=2.0, columnspacing=1.0, labelspacing=0.3)
            paths.append(c._style.save(fig, Path(outdir) / f"{stem}_{s}.png", c.atomic_write))
    return paths


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.workprecision [--outdir DIR] [--quick] [--threads N]
    [--scheduler ADDRESS]."""
    return c.study_main("cases.workprecision", __doc__,
                        f"t_end = {T_END_QUICK} s, h >= 1e-5 s, rtol >= 1e-10 (about 30 s)",
                        run, argv)


if __name__ == "__main__":
    main()
