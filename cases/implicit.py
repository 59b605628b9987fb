"""The implicit integrators (RADAU5, implicit Euler, generalized-alpha) on the paper's scenes::

    python -m cases.implicit --outdir out/           # about 35 s on 2 cores
    python -m cases.implicit --outdir out/ --quick   # t_end shortened, fewer tolerances

Three studies, each a CSV (header with units) and a PNG rendered from it:

1. ``implicit_slope.csv``: the slope with the smooth laws (RecurDyn, proposed) over 20 s from
   rest, rtol = 1e-3 .. 1e-10 (atol = 1e-3 rtol): evaluations, Jacobians, LU decompositions,
   steps and CPU time of stickslip's RADAU5 (h_max unbounded, and at the paper's automatic
   h_max = 1e-2 s) and DOPRI5 against scipy's solve_ivp Radau, BDF and LSODA with a Python
   right-hand side and analytic Jacobian (`harness.timing.python_rhs`, `python_jac`). Error:
   |x(20 s) - x_ref| against DOPRI5 at rtol = 1e-13 (`cases.workprecision.references`). CPU:
   median wall time of the whole Python call (`harness.timing.median_time`).
   ``implicit_slope_equal.csv``: for each solver the time to reach |error| <= 1e-8 m and 1e-10 m,
   interpolated in log-log along its curve (`harness.timing.time_at_error`).
2. ``fig14_implicit.csv``, ``implicit_fig14_amplitude.csv``: Fig. 14 again (belt, RecurDyn law,
   h = 1e-3 and 1e-4 s, T_END_BELT) with implicit Euler and generalized-alpha (rho_inf = 0, 0.5,
   0.9, 1). On this orbit mu = mu_k throughout (v_rel > v_d), so the motion is the linear
   oscillator x'' = -w^2 (x - x_k), w = sqrt(k/m), x_k = mu_k m g / k, whose exact amplitude
   A = sqrt((x - x_k)^2 + (v/w)^2) stays x_k. A one-step method multiplies A each step by the
   modulus of its principal root r(i w h): implicit Euler |r| = (1 + (w h)^2)^(-1/2), so
   A(t) = x_k (1 + (w h)^2)^(-t/(2h)); generalized-alpha: the root of its amplification matrix
   (`galpha_root`) nearest exp(i w h). The table compares measured and predicted A(t_end).
3. ``implicit_auto.csv``: the "automatic" column of Tables 2-3 again, with RADAU5 (the
   facade's defaults: rtol = 1e-6, atol = 1e-9, h in [1e-6, 1e-2] s) and with DOPRI5 and RADAU5
   under position-only error control (rtol = [1e-6, 0.99], atol = [1e-9, 1e9]: the velocity's
   error is ignored), beside RK4 with h = 1e-3 s: evaluations and their ratio to RK4's (the paper
   found automatic as costly as h = 1e-3 s for Coulomb), and the creep x(t_end) on the slope
   (truth 0) or the amplitude of the last period on the belt.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import _common as c

T_END_SLOPE: float = 20.0
T_END_BELT: float = 30.0              # as cases.belt
RTOLS: tuple[float, ...] = tuple(10.0 ** -e for e in range(3, 11))
SMOOTH: tuple[str, ...] = ("recurdyn", "proposed")
TARGETS: tuple[float, ...] = (1e-8, 1e-10)   # equal-error targets on x(20 s) [m]
FIG14_H: tuple[float, ...] = (1e-3, 1e-4)    # the paper's step sizes [s]
RHO_INF: tuple[float, ...] = (0.0, 0.5, 0.9, 1.0)

SLOPE_HEADER = ["law [-]", "solver [-]", "rtol [-]", "atol [m]", "status [-]", "nfev [-]",
                "njac [-]", "ndec [-]", "nstep [-]", "nforced [-]", "cpu [s]", "x_end [m]",
                "x_ref [m]", "err [m]"]
EQUAL_HEADER = ["law [-]", "solver [-]", "target [m]", "cpu [s]", "cpu_ratio_to_radau5 [-]"]
AMP_HEADER = ["method [-]", "rho_inf [-]", "h [s]", "t_end [s]", "nfev [-]", "njac [-]",
              "amplitude [m]", "predicted [m]", "rel_diff [-]", "amplitude_over_x_k [-]",
              "root_modulus [-]"]
AUTO_HEADER = ["scene [-]", "law [-]", "mode [-]", "t_end [s]", "status [-]", "nfev [-]",
               "nstep [-]", "nforced [-]", "njac [-]", "cpu [s]", "nfev_ratio_to_h1e-3 [-]",
               "x_end [m]", "amplitude_last_period [m]"]


# --------------------------------------------------------------------------------------------
# Theory
# --------------------------------------------------------------------------------------------
def euler_root(wh: float) -> float:
    """|r(i w h)| of implicit Euler: (1 + (w h)^2)^(-1/2)."""
    return 1.0 / math.sqrt(1.0 + wh * wh)


def galpha_root(wh: float, rho_inf: float) -> float:
    """Modulus of the principal root of generalized-alpha (first-order form, the library's
    alpha_m, alpha_f, gamma of rho_inf) on y' = i w y with step h: the eigenvalue of the
    amplification matrix of (y, ydot) nearest exp(i w h)."""
    am = (3.0 - rho_inf) / (2.0 * (1.0 + rho_inf))
    af = 1.0 / (1.0 + rho_inf)
    ga = 0.5 + am - af
    z = 1j * wh                               # lambda h; ydot is scaled by h
    left = np.array([[1.0, -ga], [-z * af, am]])
    right = np.array([[1.0, 1.0 - ga], [z * (1.0 - af), -(1.0 - am)]])
    roots = np.linalg.eigvals(np.linalg.solve(left, right))
    return float(abs(roots[np.argmin(abs(roots - np.exp(z)))]))


def harmonic(params: dict[str, float]) -> tuple[float, float]:
    """(w [1/s], x_k [m]) of the belt under a constant mu = mu_k."""
    return math.sqrt(params["k"] / params["m"]), params["mu_k"] * params["m"] * params["g"] / params["k"]


def orbit_amplitude(x: np.ndarray, v: np.ndarray, params: dict[str, float]) -> np.ndarray:
    """sqrt((x - x_k)^2 + (v/w)^2) [m]: constant (x_k) on the exact harmonic orbit."""
    w, x_k = harmonic(params)
    return np.sqrt((x - x_k) ** 2 + (v / w) ** 2)


def _belt_params() -> dict[str, float]:
    import stickslip
    return {k: float(v) for k, v in stickslip.DEFAULTS.items() if v is not None}


# --------------------------------------------------------------------------------------------
# 1. Slope: RADAU5 and friends against scipy
# --------------------------------------------------------------------------------------------
def _stickslip_solver(name: str) -> tuple[str, dict[str, Any]]:
    return {"radau5": ("radau5", {"hmax": 0.0}), "radau5 hmax=1e-2": ("radau5", {"hmax": 1e-2}),
            "dopri5": ("dopri5", {"hmax": 0.0})}[name]


SOLVERS: tuple[str, ...] = ("radau5", "radau5 hmax=1e-2", "dopri5", "scipy Radau", "scipy BDF",
                            "scipy LSODA")


def slope_runs(rtols: Sequence[float], t_end: float, repeats: int, quiet: bool) -> list[list[Any]]:
    """One row per (law, solver, rtol) (SLOPE_HEADER)."""
    import stickslip
    from scipy.integrate import solve_ivp
    from . import workprecision
    from harness.timing import median_time, python_jac, python_rhs
    refs = workprecision.references(t_end, 1)
    rows = []
    for law in SMOOTH:
        x_ref = refs[("slope", law)]["x"]
        f, jac = python_rhs("slope", law), python_jac("slope", law)
        for solver in SOLVERS:
            for rtol in rtols:
                atol = 1e-3 * rtol
                if solver.startswith("scipy"):
                    m = solver.split()[1]
                    cpu, sol = median_time(lambda: solve_ivp(f, (0.0, t_end), [0.0, 0.0], method=m,
                                                             rtol=rtol, atol=atol, jac=jac),
                                           min(repeats, 3), 0.0)
                    status = int(sol.status)
                    st = {"nfev": sol.nfev, "njac": sol.njev, "ndec": sol.nlu,
                          "nstep": len(sol.t) - 1, "nforced": 0}
                    x = float(sol.y[0, -1])
                else:
                    method, kw = _stickslip_solver(solver)
                    cpu, res = median_time(lambda: stickslip.simulate(
                        "slope", law, method=method, t_end=t_end, rtol=rtol, atol=atol, n_out=2,
                        **kw), repeats, 0.02)
                    status, st, x = res.stats["status"], res.stats, float(res.x[-1])
                rows.append([law, solver, rtol, atol, status, int(st["nfev"]), int(st["njac"]),
                             int(st["ndec"]), int(st["nstep"]), int(st["nforced"]), cpu, x, x_ref,
                             abs(x - x_ref)])
            c.log(f"implicit: slope {law} {solver} done", quiet)
    return rows


def equal_error(rows: list[list[Any]]) -> list[list[Any]]:
    """Time to reach each target error, per law and solver, and its ratio to RADAU5's."""
    from harness.timing import time_at_error
    out = []
    for law in SMOOTH:
        for target in TARGETS:
            t = {s: time_at_error([(r[13], r[10]) for r in rows if r[0] == law and r[1] == s], target)
                 for s in SOLVERS}
            for s in SOLVERS:
                out.append([law, s, target, t[s], t[s] / t["radau5"]])
    return out


# --------------------------------------------------------------------------------------------
# 2. Fig. 14 with implicit integrators
# --------------------------------------------------------------------------------------------
def fig14_variants() -> list[tuple[str, str, float | None, float]]:
    """(label, method, rho_inf, h) of every run."""
    out = []
    for h in FIG14_H:
        out.append((f"implicit_euler h={h:g}", "implicit_euler", None, h))
        out += [(f"galpha rho={r:g} h={h:g}", "galpha", r, h) for r in RHO_INF]
    return out


def fig14(outdir: Path, t_end: float, n_out: int) -> list[Path]:
    import stickslip
    p = _belt_params()
    w, x_k = harmonic(p)
    cols: dict[str, np.ndarray] = {}
    rows = []
    for label, method, rho, h in fig14_variants():
        kw = {} if rho is None else {"rho_inf": rho}
        r = stickslip.simulate("belt", "recurdyn", method=method, h=h, t_end=t_end, n_out=n_out, **kw)
        cols.setdefault("t [s]", r.t)
        cols[f"x {label} [m]"] = r.x
        amp = float(orbit_amplitude(r.x[-1:], r.v[-1:], p)[0])
        root = euler_root(w * h) if rho is None else galpha_root(w * h, rho)
        steps = round(t_end / h)
        pred = x_k * root ** steps
        rows.append([method, rho, h, t_end, r.stats["nfev"], r.stats["njac"], amp, pred,
                     amp / pred - 1.0, amp / x_k, root])
    return [c.write_columns(outdir / "fig14_implicit.csv", cols),
            c.write_csv(outdir / "implicit_fig14_amplitude.csv", AMP_HEADER, rows)]


# --------------------------------------------------------------------------------------------
# 3. Tables 2-3, automatic column
# --------------------------------------------------------------------------------------------
#: The paper's step range of the automatic runs (stickslip.simulate's default hmax is t_end).
PAPER_STEPS: dict[str, float] = {"hmin": 1e-6, "hmax": 1e-2}
AUTO_MODES: dict[str, dict[str, Any]] = {
    "rk4 h=1e-3": {"method": "rk4", "h": 1e-3},
    "radau5 automatic": {"method": "radau5", **PAPER_STEPS},
    "dopri5 automatic": {"method": "dopri5", **PAPER_STEPS},
    "dopri5 position-only": {"method": "dopri5", "rtol": [1e-6, 0.99], "atol": [1e-9, 1e9], **PAPER_STEPS},
    "radau5 position-only": {"method": "radau5", "rtol": [1e-6, 0.99], "atol": [1e-9, 1e9], **PAPER_STEPS},
}


def auto_column(t_slope: float, t_belt: float, quiet: bool) -> list[list[Any]]:
    import stickslip
    from .belt import metrics
    p = _belt_params()
    rows = []
    for scene, t_end in (("slope", t_slope), ("belt", t_belt)):
        for law in ("coulomb", "recurdyn", "proposed"):
            base = None
            for mode, kw in AUTO_MODES.items():
                r = stickslip.simulate(scene, law, t_end=t_end, n_out=int(round(t_end / 0.01)) + 1, **kw)
                st = r.stats
                base = base or st["nfev"]
                amp = None
                if scene == "belt":
                    amp = metrics(None, r, p)["amplitude_last_period [m]"]   # type: ignore[arg-type]
                rows.append([scene, law, mode, t_end, st["status"], st["nfev"], st["nstep"],
                             st["nforced"], st["njac"], st["cpu_seconds"], st["nfev"] / base,
                             float(r.x[-1]), amp])
                c.log(f"implicit: {scene} {law} {mode}: nfev {st['nfev']}, {st['cpu_seconds']:.2f} s", quiet)
    return rows


# --------------------------------------------------------------------------------------------
# Driver and plots
# --------------------------------------------------------------------------------------------
def run(outdir: str | Path, *, quick: bool = False, threads: int = 2, quiet: bool = False) -> list[Path]:
    """All three studies; returns the CSV and PNG paths."""
    outdir = Path(outdir)
    t_slope = 2.0 if quick else T_END_SLOPE
    t_belt = 3.0 if quick else T_END_BELT
    rtols = RTOLS[1::2] if quick else RTOLS
    c.log("implicit: slope, RADAU5 / DOPRI5 / scipy", quiet)
    rows = slope_runs(rtols, t_slope, 1 if quick else 5, quiet)
    files = [c.write_csv(outdir / "implicit_slope.csv", SLOPE_HEADER, rows),
             c.write_csv(outdir / "implicit_slope_equal.csv", EQUAL_HEADER, equal_error(rows))]
    c.log("implicit: Fig. 14 with implicit Euler and generalized-alpha", quiet)
    files += fig14(outdir, t_belt, int(round(t_belt / 0.01)) + 1)
    c.log("implicit: automatic column of Tables 2-3", quiet)
    files.append(c.write_csv(outdir / "implicit_auto.csv", AUTO_HEADER, auto_column(t_slope, t_belt, quiet)))
    pngs = [plot(f, outdir) for f in files if f.stem in ("implicit_slope", "fig14_implicit")]
    return files + pngs


#: Colours of generalized-alpha's rho_inf variants (implicit Euler keeps its method colour).
GALPHA_COLORS: tuple[str, ...] = (c._style.OKABE_ITO["blue"], c._style.OKABE_ITO["vermillion"],
                                  c._style.OKABE_ITO["bluish green"], c._style.OKABE_ITO["reddish purple"])
#: Legend names of the solvers of implicit_slope.csv.
SOLVER_NAMES: dict[str, str] = {"radau5": "stickslip RADAU5 (h_max unbounded)",
                                "radau5 hmax=1e-2": "stickslip RADAU5, h_max = 1e-2 s",
                                "dopri5": "stickslip DOPRI5", "scipy Radau": "scipy Radau",
                                "scipy BDF": "scipy BDF", "scipy LSODA": "scipy LSODA"}


#: Colour (the tool's, harness.style.TOOL_COLORS), marker (the method's) and line style of each
#: solver of implicit_slope.csv: the same method has the same marker whatever the tool.
SOLVER_STYLE: dict[str, tuple[str, str, str]] = {
    "radau5": ("stickslip_python", c._style.METHOD_MARKERS["radau5"], "-"),
    "radau5 hmax=1e-2": ("stickslip_python", c._style.METHOD_MARKERS["radau5"], "--"),
    "dopri5": ("stickslip_python", c._style.METHOD_MARKERS["dopri5"], ":"),
    "scipy Radau": ("scipy", c._style.METHOD_MARKERS["radau5"], "-."),
    "scipy BDF": ("scipy", "h", "-."), "scipy LSODA": ("scipy", "p", "-.")}


def plot(csv: str | Path, outdir: str | Path) -> Path:
    """implicit_slope.csv: error against evaluations and CPU per law and solver;
    fig14_implicit.csv: x(t) of every variant."""
    csv = Path(csv)
    if csv.stem == "fig14_implicit":
        return plot_fig14(csv, outdir)
    cols = c.read_csv(csv)
    fig, axes = c.new_figure(1, nrows=len(SMOOTH), height=7.6, sharex=True)
    axes = axes[:, 0]
    for b, law in enumerate(SMOOTH):
        ax = axes[b]
        for k, s in enumerate(SOLVERS):
            sel = [i for i in range(len(cols["law [-]"])) if cols["law [-]"][i] == law and cols["solver [-]"][i] == s]
            x = [float(cols["cpu [s]"][i]) for i in sel]
            y = [max(float(cols["err [m]"][i]), 1e-16) for i in sel]
            tool, marker, line = SOLVER_STYLE.get(s, ("", "o", "-"))
            ax.loglog(x, y, marker=marker, linestyle=line, ms=4, mfc="white",
                      color=c._style.TOOL_COLORS.get(tool, c._style.SEQUENCE[k]),
                      label=SOLVER_NAMES.get(s, s))
        ax.set_title(f"{c.LAW_LABELS[law].split(' (')[0]} law")
        ax.set_ylabel("|x(20 s) - reference| [m]")
    axes[-1].set_xlabel("median wall time of a run [s]")
    # the runs (rtol = 1e-3 .. 1e-10, atol = 1e-3 rtol), the reference (DOPRI5 at rtol = 1e-13)
    # and errors below 1e-16 m drawn at 1e-16 m: the page's text (docs/reproduction.md)
    fig.suptitle("Box on a 10° slope: stickslip and scipy")
    c.figure_legend(fig, axes, ncol=3)
    return c.save_figure(fig, Path(outdir) / "implicit_slope.png")


#: Periods of the harmonic orbit the top panels of fig14_implicit show, at the end of the run:
#: 30 s of oscillation at a column's width is a block of colour; the last periods show where
#: each method has drifted to.
FIG14_PERIODS: float = 2.0


def plot_fig14(csv: Path, outdir: str | Path) -> Path:
    """fig14_implicit.csv: for each step size, x(t) of implicit Euler and generalized-alpha
    beside the exact harmonic solution x_k (1 - cos w t) over the last FIG14_PERIODS periods
    (top), and each method's largest distance from it so far on a log axis over the whole run
    (bottom), where the variants that lie on each other on top separate; staggered markers keep
    a curve on another visible."""
    cols = c.read_numeric_csv(csv)
    t = cols["t [s]"]
    w, x_k = harmonic(_belt_params())
    exact = x_k * (1.0 - np.cos(w * t))
    last = t >= t[-1] - FIG14_PERIODS * 2.0 * np.pi / w
    width = c.figure_width(len(FIG14_H))
    c._style.apply(width)
    fig, axes = c.plt.subplots(2, len(FIG14_H), figsize=(width, 7.8), squeeze=False,
                               sharey="row")
    palette = (c._style.color("implicit_euler"), *GALPHA_COLORS)
    for col, h in enumerate(FIG14_H):
        top, bottom = axes[0][col], axes[1][col]
        top.plot(t[last], exact[last], color="0.6", lw=3.0, label="exact: x_k (1 - cos ωt)")
        variants = [v for v in fig14_variants() if v[3] == h]
        for j, (label, method, rho, hh) in enumerate(variants):
            x = cols[f"x {label} [m]"]
            name = c._style.name(method) + ("" if rho is None else f", ρ∞ = {rho:g}")
            marker = c._style.METHOD_MARKERS[method] if rho is None else "osD^"[j % 4]
            style = dict(color=palette[j], linestyle=c.VARIANT_STYLES[j % 4], lw=1.2,
                         marker=marker, ms=4, mfc="white")
            if rho is None or rho == 0.0:          # the other rho_inf lie on this one on top
                n = int(last.sum())
                top.plot(t[last], x[last], label=name, markevery=(j * n // 12, n // 6), **style)
            worst = np.maximum.accumulate(np.abs(x - exact))
            pos = worst > 0
            n = int(pos.sum())
            bottom.semilogy(t[pos], worst[pos], label=name,
                            markevery=(j * n // (6 * len(variants)), n // 6), **style)
        # generalized-alpha with rho_inf = 0.5, 0.9, 1 lies on rho_inf = 0 on top: drawn below only
        top.set_title(f"h = {h:g} s")
        top.set_xlabel("time t [s]")
        top.set_xlim(t[last][0], t[-1])
        bottom.set_xlabel("time t [s]")
        bottom.set_xlim(0.0, t[-1])
    axes[0][0].set_ylabel("x [m]")
    axes[1][0].set_ylabel("max |x - exact| so far [m]")
    for ax in axes[1]:
        c.log_ticks(ax, "y")
    fig.suptitle("Fig. 14 again: belt, RecurDyn law (μ = μ_k)")
    c.figure_legend(fig, [ax for row in axes for ax in row], ncol=2)
    return c.save_figure(fig, Path(outdir) / "fig14_implicit.png")


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.implicit [--outdir DIR] [--quick] [--threads N] [--quiet]."""
    return c.study_main("cases.implicit", __doc__, "t_end = 2 s (slope), 3 s (belt), 4 tolerances",
                        run, argv)


if __name__ == "__main__":
    main()
