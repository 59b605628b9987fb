"""Stability at the extremes: RK4 stability maps (step size h x v_s), DOPRI5 cost maps
(tolerance x v_s), maps of the fixed-step implicit methods on the slope (h up to 1e4 times
RK4's bound, `implicit_map`), and a list of extreme runs that must each end with a clear status::

    python -m cases.stability --outdir out/          # about a minute on 2 cores
    python -m cases.stability --outdir out/ --quick  # coarser maps, no 2e8-step run

Linear stability bound. Near the stick state the friction law is a stiff damper: for the slope,
x'' = g sin(theta) - mu(v) g cos(theta) linearised at the creep speed v* (mu(v*) = tan theta)
gives v' = lambda (v - v*) with lambda = -g cos(theta) mu'(v*); for the belt, linearised in the
stick state at v_rel (the state started in), lambda = -g mu'(v_rel) (the other eigenvalue,
about -k/(m g mu'), is tiny). RK4 is stable for h |lambda| <= 2.785 (its real-axis limit), so
h_lin = 2.785 / |lambda|. RecurDyn: mu' = mu_s pi/(2 v_s) sin(pi v/v_s); proposed:
mu' = beta mu / v; both scale as 1/v_s, so h_lin is proportional to v_s. Coulomb: mu' = 0
off its jumps and infinite at them: no bound, event-free stepping always chatters.

Scenarios. Slope: from rest (the paper's case). Belt: started in the stick state at its
stiffest point, x0 = mu_s m g / (2k), v0 = v_b - v_rel with mu(v_rel) = mu_s / 2 (the spring
then loads the contact through the rest of the stick phase, about 0.04 s). Each RK4 run
covers 2000 monitor intervals of an odd number of steps (so a period-2 oscillation shows as a
reversal at every monitor point; at least 20 intervals of one step for large h), aiming at
t_end = 1 s for the slope (at most 21 steps an interval) and 0.03 s for the belt (the stick
phase; at most 201 steps an interval).

Classification of a run (from the batch summary, second half of the run = its "tail"):
- unstable: status not 0 (non-finite), or max |v| beyond a physical bound (slope:
  |v0| + g (sin theta + mu_s cos theta) t_end; belt: 10 (|v_b| + mu_s g sqrt(m/k)));
- chattering: the relative velocity changes sign in the tail (the box moves uphill, the mass
  overtakes the belt), or the velocity reverses direction at >= 25% of the tail's monitor
  points (a numerical limit cycle);
- spurious (slope only): the tail stays more than 0.1% away from the creep speed v*, steady or
  not: beyond h_lin RK4 settles on a spurious fixed point of its map (a constant v != v*,
  with x'' != 0: Yee, Sweby & Griffiths 1991), which looks smooth but is wrong;
- stable otherwise.
"""
from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import _common as c

SCENES: tuple[str, ...] = ("slope", "belt")
LAWS: tuple[str, ...] = c.PAPER_LAWS
RK4_LIMIT: float = 2.785293563405282     # RK4 stability interval on the negative real axis
N_GRID: int = 2001
CLASSES: tuple[str, ...] = ("stable", "chattering", "spurious", "unstable")
MAP_HEADER: list[str] = ["scene [-]", "law [-]", "v_s [m/s]", "h [s]", "h_lin [s]", "t_end [s]",
                         "status [-]", "nfev [-]", "v_max [m/s]", "n_flip_tail [-]",
                         "n_rev_tail [-]", "class [-]"]
DOPRI_HEADER: list[str] = ["scene [-]", "law [-]", "v_s [m/s]", "rtol [-]", "t_end [s]",
                           "status [-]", "nfev [-]", "nstep [-]", "nreject [-]", "nforced [-]",
                           "stiff [-]", "v_max [m/s]", "n_flip_tail [-]", "n_rev_tail [-]",
                           "class [-]"]
EXTREME_HEADER: list[str] = ["case [-]", "scene [-]", "law [-]", "method [-]", "status [-]",
                             "outcome [-]", "t_reached [s]", "nfev [-]", "nforced [-]",
                             "x_end [m]", "v_end [m/s]", "v_max [m/s]", "finite [-]",
                             "seconds [s]"]


def _params(**over: float) -> dict[str, float]:
    import stickslip
    p = {k: v for k, v in stickslip.DEFAULTS.items()}
    p.update(over)
    if p["v_d"] is None:
        p["v_d"] = 1.5 * p["v_s"]
    return p


def dmu_dv(law: str, v: float, p: dict[str, float]) -> float:
    """Slope of the friction law at relative velocity 0 < v < v_s [s/m]."""
    if law == "recurdyn":
        return p["mu_s"] * math.pi / (2.0 * p["v_s"]) * math.sin(math.pi * v / p["v_s"])
    if law == "proposed":
        return p["beta"] * p["mu_s"] * (v / p["v_s"]) ** p["beta"] / v
    return 0.0


def stick_velocity(law: str, mu: float, p: dict[str, float]) -> float:
    """Relative velocity in (0, v_s) where mu(v) = mu (< mu_s) [m/s]; 0 for Coulomb."""
    if law == "recurdyn":
        return p["v_s"] * math.acos(1.0 - 2.0 * mu / p["mu_s"]) / math.pi
    if law == "proposed":
        return p["v_s"] * (mu / p["mu_s"]) ** (1.0 / p["beta"])
    return 0.0


def linear_bound(scene: str, law: str, v_s: float, **over: float) -> tuple[float, float]:
    """(lambda [1/s], h_lin [s]) of the stick state of `scene` (module docstring); (0, inf)
    for Coulomb."""
    p = _params(v_s=v_s, **over)
    if law == "coulomb":
        return 0.0, math.inf
    if scene == "slope":
        th = math.radians(p["theta_deg"])
        v = stick_velocity(law, math.tan(th), p)
        lam = -p["g"] * math.cos(th) * dmu_dv(law, v, p)
    else:
        v = stick_velocity(law, 0.5 * p["mu_s"], p)
        lam = -p["g"] * dmu_dv(law, v, p)
    return lam, RK4_LIMIT / abs(lam)


def belt_stick_start(law: str, v_s: float) -> tuple[float, float]:
    """(x0 [m], v0 [m/s]) of the belt in the stick state where mu = mu_s / 2."""
    p = _params(v_s=v_s)
    x0 = 0.5 * p["mu_s"] * p["m"] * p["g"] / p["k"]
    return x0, p["v_b"] - stick_velocity(law, 0.5 * p["mu_s"], p)


def creep_speed(law: str, v_s: float) -> float:
    """Steady creep speed v* [m/s] of the box on the slope, mu(v*) = tan(theta); nan for
    Coulomb (it has none: mu jumps from 0 to mu_s)."""
    p = _params(v_s=v_s)
    if law == "coulomb":
        return math.nan
    return stick_velocity(law, math.tan(math.radians(p["theta_deg"])), p)


def classify(b: Any, i: int, v_bound: float, n_grid: int = N_GRID) -> str:
    """stable / chattering / spurious / unstable for row i of a BatchResult (module docstring)."""
    if b.status[i] != 0 or not math.isfinite(b.v_max[i]) or b.v_max[i] > v_bound:
        return "unstable"
    if b.n_flip_tail[i] > 0 or b.n_rev_tail[i] >= 0.25 * (n_grid - 1) / 2:
        return "chattering"
    if b.scene[i] == "slope":
        v_star = creep_speed(str(b.law[i]), float(b.params["v_s"][i]))
        if math.isfinite(v_star) and max(abs(b.vrel_min_tail[i] - v_star),
                                         abs(b.vrel_max_tail[i] - v_star)) > 1e-3 * v_star:
            return "spurious"
    return "stable"


def v_bound(scene: str, t_end: float, v0: float = 0.0) -> float:
    """Largest |v| [m/s] the exact dynamics can reach (module docstring)."""
    p = _params()
    if scene == "slope":
        th = math.radians(p["theta_deg"])
        return abs(v0) + p["g"] * (abs(math.sin(th)) + p["mu_s"] * math.cos(th)) * t_end
    return 10.0 * (abs(p["v_b"]) + p["mu_s"] * p["g"] * math.sqrt(p["m"] / p["k"]))


def rk4_grid(scene: str, h: float) -> tuple[float, int]:
    """(t_end [s], n_grid) of an RK4 map run: up to 2000 monitor intervals of an odd number of
    steps each (module docstring), aiming at 1 s for the slope and 0.03 s for the belt."""
    target, k_max = (1.0, 21) if scene == "slope" else (0.03, 201)
    n_int = int(min(2000, max(20, round(target / h))))
    k = min(k_max, max(1, int(round(target / (n_int * h)))))
    k += 1 - k % 2
    return n_int * k * h, n_int + 1


def rk4_map(v_ss: Sequence[float], n_h: int, threads: int, client: Any = None) -> list[list[Any]]:
    """RK4 runs over h in [h_lin/20, 20 h_lin] (Coulomb: the RecurDyn window) for each v_s,
    one batch per monitor-grid size."""
    import stickslip
    rows: list[dict[str, Any]] = []
    for s in SCENES:
        for l in LAWS:
            for vs in v_ss:
                h_lin = linear_bound(s, l, vs)[1]
                centre = h_lin if math.isfinite(h_lin) else linear_bound(s, "recurdyn", vs)[1]
                for h in np.geomspace(centre / 20.0, centre * 20.0, n_h):
                    h = float(f"{h:.4g}")
                    x0, v0 = belt_stick_start(l, vs) if s == "belt" else (0.0, 0.0)
                    t_end, n_grid = rk4_grid(s, h)
                    rows.append({"scene": s, "law": l, "v_s": vs, "h": h, "h_lin": h_lin,
                                 "t_end": t_end, "n_grid": n_grid, "x0": x0, "v0": v0})
    out: list[list[Any]] = [[] for _ in rows]
    for n_grid in sorted({r["n_grid"] for r in rows}):
        idx = [i for i, r in enumerate(rows) if r["n_grid"] == n_grid]
        sub = [rows[i] for i in idx]
        with c.steps_beyond_stability():           # h spans [h_lin/20, 20 h_lin] on purpose
            b = stickslip.simulate_batch([r["scene"] for r in sub], [r["law"] for r in sub],
                                         method="rk4", t_end=[r["t_end"] for r in sub],
                                         h=[r["h"] for r in sub], v_s=[r["v_s"] for r in sub],
                                         x0=[r["x0"] for r in sub], v0=[r["v0"] for r in sub],
                                         n_grid=n_grid, threads=threads, client=client)
        for j, (i, r) in enumerate(zip(idx, sub)):
            cls = classify(b, j, v_bound(r["scene"], r["t_end"], r["v0"]), n_grid)
            out[i] = [r["scene"], r["law"], r["v_s"], r["h"], r["h_lin"], r["t_end"],
                      int(b.status[j]), int(b.nfev[j]), float(b.v_max[j]),
                      int(b.n_flip_tail[j]), int(b.n_rev_tail[j]), cls]
    return out


def dopri5_map(v_ss: Sequence[float], rtols: Sequence[float], threads: int,
               client: Any = None) -> list[list[Any]]:
    """DOPRI5 runs (paper's h_min = 1e-6 s, h_max = 1e-2 s, atol = 1e-3 rtol): slope from rest
    over 1 s, belt from the stick state over 0.5 s (stick, slip and the next stick)."""
    import stickslip
    rows = []
    for s in SCENES:
        for l in LAWS:
            for vs in v_ss:
                x0, v0 = belt_stick_start(l, vs) if s == "belt" else (0.0, 0.0)
                for rt in rtols:
                    rows.append({"scene": s, "law": l, "v_s": vs, "rtol": rt,
                                 "t_end": 1.0 if s == "slope" else 0.5, "x0": x0, "v0": v0})
    b = stickslip.simulate_batch([r["scene"] for r in rows], [r["law"] for r in rows],
                                 method="dopri5", t_end=[r["t_end"] for r in rows],
                                 rtol=[r["rtol"] for r in rows],
                                 atol=[1e-3 * r["rtol"] for r in rows], hmin=1e-6, hmax=1e-2,
                                 v_s=[r["v_s"] for r in rows], x0=[r["x0"] for r in rows],
                                 v0=[r["v0"] for r in rows], max_steps=10**7,
                                 n_grid=N_GRID, threads=threads, client=client)
    out = []
    for i, r in enumerate(rows):
        cls = classify(b, i, v_bound(r["scene"], r["t_end"], r["v0"]))
        out.append([r["scene"], r["law"], r["v_s"], r["rtol"], r["t_end"], int(b.status[i]),
                    int(b.nfev[i]), int(b.nstep[i]), int(b.nreject[i]), int(b.nforced[i]),
                    int(b.stiff[i]), float(b.v_max[i]), int(b.n_flip_tail[i]),
                    int(b.n_rev_tail[i]), cls])
    return out


IMPLICIT_HEADER: list[str] = ["scene [-]", "law [-]", "method [-]", "rho_inf [-]", "v_s [m/s]", "h [s]",
                              "h_lin [s]", "t_end [s]", "status [-]", "nfev [-]", "v_max [m/s]",
                              "n_flip_tail [-]", "n_rev_tail [-]", "class [-]"]
#: The fixed-step implicit methods of the map: (method, rho_inf or None).
IMPLICIT_METHODS: tuple[tuple[str, float | None], ...] = (
    ("implicit_euler", None), ("galpha", 0.0), ("galpha", 0.5), ("galpha", 1.0))


def implicit_map(v_ss: Sequence[float], n_h: int, threads: int, client: Any = None) -> list[list[Any]]:
    """Implicit Euler and generalized-alpha on the slope from rest over h in
    [h_lin/10, 1e4 h_lin] (RK4's bound h_lin), with RK4's monitor grid (rk4_grid) and
    classification; a run whose Newton iteration fails is classed "newton failed"."""
    import stickslip
    rows: list[dict[str, Any]] = []
    for l in ("recurdyn", "proposed"):
        for vs in v_ss:
            h_lin = linear_bound("slope", l, vs)[1]
            for m, rho in IMPLICIT_METHODS:
                for h in np.geomspace(h_lin / 10.0, h_lin * 1e4, n_h):
                    h = float(f"{h:.4g}")
                    t_end, n_grid = rk4_grid("slope", h)
                    rows.append({"law": l, "v_s": vs, "method": m, "rho": rho, "h": h, "h_lin": h_lin,
                                 "t_end": t_end, "n_grid": n_grid})
    out: list[list[Any]] = [[] for _ in rows]
    failed = stickslip.REGISTRY["status"]["NEWTON_FAILED"]
    for n_grid in sorted({r["n_grid"] for r in rows}):
        idx = [i for i, r in enumerate(rows) if r["n_grid"] == n_grid]
        sub = [rows[i] for i in idx]
        b = stickslip.simulate_batch("slope", [r["law"] for r in sub], method=[r["method"] for r in sub],
                                     t_end=[r["t_end"] for r in sub], h=[r["h"] for r in sub],
                                     rho_inf=[np.nan if r["rho"] is None else r["rho"] for r in sub],
                                     v_s=[r["v_s"] for r in sub], n_grid=n_grid, threads=threads,
                                     client=client)
        for j, (i, r) in enumerate(zip(idx, sub)):
            cls = "newton failed" if b.status[j] == failed else classify(b, j, v_bound("slope", r["t_end"]),
                                                                          n_grid)
            out[i] = ["slope", r["law"], r["method"], r["rho"], r["v_s"], r["h"], r["h_lin"], r["t_end"],
                      int(b.status[j]), int(b.nfev[j]), float(b.v_max[j]), int(b.n_flip_tail[j]),
                      int(b.n_rev_tail[j]), cls]
    return out


#: Widths of the implicit methods' figure and of the maps [in]; their fonts are scaled to stay
#: legible at a column width (harness.style.apply).
IMPLICIT_WIDTH: float = 6.4
MAP_WIDTH: float = 6.4


def plot_implicit(csv: str | Path, outdir: str | Path) -> Path:
    """Render stability_implicit.csv: class over h / h_lin per method, one panel per law and v_s."""
    cols = c.read_csv(csv)
    keys = list(dict.fromkeys((cols["law [-]"][i], cols["v_s [m/s]"][i]) for i in range(len(cols["law [-]"]))))
    width = IMPLICIT_WIDTH
    c._style.apply(width)
    fig, axes = c.plt.subplots(len(keys), 1, figsize=(width, 2.4 + 1.5 * len(keys)), squeeze=False,
                               sharex=True)
    axes = axes.T
    colors = c._style.CLASS_COLORS
    labels = [m if rho is None else f"{m} {rho:g}" for m, rho in IMPLICIT_METHODS]
    shown = [c._style.name(m) if rho is None else f"{c._style.name(m)}, ρ∞ = {rho:g}"
             for m, rho in IMPLICIT_METHODS]
    for ax, (l, vs) in zip(axes[0], keys):
        seen = set()
        for i in range(len(cols["law [-]"])):
            if (cols["law [-]"][i], cols["v_s [m/s]"][i]) != (l, vs):
                continue
            rho = cols["rho_inf [-]"][i]
            lab = cols["method [-]"][i] + (f" {float(rho):g}" if rho else "")
            k = cols["class [-]"][i]
            ax.semilogx(float(cols["h [s]"][i]) / float(cols["h_lin [s]"][i]), labels.index(lab), "s",
                        color=colors[k], ms=5, label=None if k in seen else c._style.name(k))
            seen.add(k)
        ax.axvline(1.0, color="k", lw=0.8)
        ax.set_yticks(range(len(labels)), shown)
        ax.set_ylim(-0.6, len(labels) - 0.4)
        ax.set_title(f"{c.LAW_LABELS[l].split(' (')[0]}, v_s = {float(vs):g} m/s")
    axes[0][-1].set_xlabel("step h / RK4's bound h_lin [-]")
    fig.suptitle("Implicit methods on the slope (line: h = h_lin)")
    c.figure_legend(fig, axes.ravel(), ncol=3)
    return c.save_figure(fig, Path(outdir) / "stability_implicit.png")


def extremes(quick: bool = False, threads: int = 2, client: Any = None) -> list[list[Any]]:
    """The extreme runs of issue 5, each with its status (or the ValueError it raises)."""
    import stickslip
    cases: list[tuple[str, dict[str, Any]]] = [
        ("v_s = 1e-6, RK4 h = 1e-3", dict(scene="slope", law="recurdyn", method="rk4", h=1e-3, v_s=1e-6)),
        ("v_s = 1e-6, RK4 h = 1e-3", dict(scene="slope", law="proposed", method="rk4", h=1e-3, v_s=1e-6)),
        ("v_s = 1e-6, DOPRI5", dict(scene="slope", law="recurdyn", method="dopri5", v_s=1e-6)),
        ("v_s = 1e-6, DOPRI5", dict(scene="belt", law="proposed", method="dopri5", v_s=1e-6)),
        ("beta = 1e-3", dict(scene="slope", law="proposed", method="rk4", h=1e-3, beta=1e-3)),
        ("beta = 1e-3", dict(scene="belt", law="proposed", method="dopri5", beta=1e-3)),
        ("beta = 1", dict(scene="slope", law="proposed", method="rk4", h=1e-3, beta=1.0)),
        ("beta = 1", dict(scene="belt", law="proposed", method="dopri5", beta=1.0)),
        ("a = 1.0001", dict(scene="belt", law="proposed", method="rk4", h=1e-3, a=1.0001)),
        ("a = 1.0001", dict(scene="belt", law="proposed", method="dopri5", a=1.0001)),
        ("a = 100", dict(scene="belt", law="proposed", method="rk4", h=1e-3, a=100.0)),
        ("a = 100", dict(scene="belt", law="proposed", method="dopri5", a=100.0)),
        ("t_end = 1e4 s", dict(scene="belt", law="proposed", method="rk4", h=1e-3, t_end=1e4)),
        ("t_end = 1e4 s", dict(scene="belt", law="proposed", method="dopri5", t_end=1e4)),
        ("k = 1e6 N/m, RK4 h = 1e-3", dict(scene="belt", law="recurdyn", method="rk4", h=1e-3, k=1e6)),
        ("k = 1e6 N/m, RK4 h = 1e-2", dict(scene="belt", law="recurdyn", method="rk4", h=1e-2, k=1e6)),
        ("k = 1e6 N/m, DOPRI5", dict(scene="belt", law="recurdyn", method="dopri5", k=1e6)),
        ("v0 = -1 m/s (uphill)", dict(scene="slope", law="proposed", method="dopri5", v0=-1.0)),
        ("v0 = -1 m/s (uphill)", dict(scene="slope", law="coulomb", method="rk4", h=1e-3, v0=-1.0)),
        ("v0 = +1 m/s (downhill)", dict(scene="slope", law="proposed", method="dopri5", v0=1.0)),
        ("v0 = +1 m/s (downhill)", dict(scene="slope", law="recurdyn", method="rk4", h=1e-3, v0=1.0)),
        ("max_steps = 1000", dict(scene="belt", law="proposed", method="rk4", h=1e-3, max_steps=1000)),
        ("max_steps = 1000", dict(scene="belt", law="proposed", method="dopri5", max_steps=1000)),
    ]
    if not quick:
        cases.append(("h = 1e-7 over 20 s", dict(scene="slope", law="recurdyn", method="rk4", h=1e-7)))
    out: list[list[Any]] = []
    # One batch per method keeps the per-row options simple; rows default to t_end = 20 s.
    for method in ("rk4", "dopri5"):
        sel = [(name, kw) for name, kw in cases if kw["method"] == method]
        rows = [dict({"t_end": 20.0, "max_steps": 3 * 10**8, "v0": 0.0}, **kw) for _, kw in sel]
        keys = sorted({k for r in rows for k in r} - {"scene", "law", "method"})
        cols: dict[str, Any] = {}
        for k in keys:
            cols[k] = [r.get(k, _params().get(k)) for r in rows]
        if method == "dopri5":
            cols.pop("h", None)
            cols.update(hmin=1e-6, hmax=1e-2)   # the paper's step range (simulate's hmax: t_end)
        with c.steps_beyond_stability():           # the extremes go beyond on purpose
            b = stickslip.simulate_batch([r["scene"] for r in rows], [r["law"] for r in rows],
                                         method=method, n_grid=201, threads=threads, client=client,
                                         **cols)
        for i, (name, kw) in enumerate(sel):
            outcome = "ok" if b.status[i] == 0 else b.message(i)
            finite = bool(np.isfinite([b.x_end[i], b.v_end[i], b.v_max[i]]).all())
            out.append([name, kw["scene"], kw["law"], method, int(b.status[i]), outcome,
                        float(b.t_reached[i]), int(b.nfev[i]), int(b.nforced[i]),
                        float(b.x_end[i]), float(b.v_end[i]), float(b.v_max[i]), int(finite),
                        float(b.seconds[i])])
    try:
        stickslip.simulate("slope", "recurdyn", method="dopri5", t_end=1.0, rtol=1e-14)
        out.append(["rtol = 1e-14", "slope", "recurdyn", "dopri5", 0, "accepted (!)",
                    1.0, 0, 0, 0.0, 0.0, 0.0, 1, 0.0])
    except ValueError as err:
        out.append(["rtol = 1e-14", "slope", "recurdyn", "dopri5", -123, f"ValueError: {err}",
                    0.0, 0, 0, 0.0, 0.0, 0.0, 1, 0.0])
    return out


def run(outdir: str | Path, *, quick: bool = False, threads: int = 2,
        quiet: bool = False, scheduler: str | None = None) -> list[Path]:
    """Maps and extremes; CSV files, then plots. They run on the Dask cluster at `scheduler`
    when given. (The batch speed-up is cases.speedup.)"""
    from stickslip.distributed import connect
    with connect(scheduler) as client:
        return _run(outdir, quick=quick, threads=threads, quiet=quiet, client=client)


def _run(outdir: str | Path, *, quick: bool, threads: int, quiet: bool,
         client: Any) -> list[Path]:
    outdir = Path(outdir)
    v_ss = [float(f"{v:.3g}") for v in np.geomspace(1e-1, 1e-6, 6 if quick else 11)]
    t0 = time.perf_counter()
    rk4 = rk4_map(v_ss, 9 if quick else 17, threads, client)
    c.log(f"stability: RK4 map, {len(rk4)} runs, {time.perf_counter() - t0:.1f} s", quiet)
    p_rk4 = c.write_csv(outdir / "stability_rk4.csv", MAP_HEADER, rk4)
    t0 = time.perf_counter()
    rtols = [10.0 ** -e for e in (range(2, 11, 2) if quick else range(2, 11))]
    dop = dopri5_map(v_ss, rtols, threads, client)
    c.log(f"stability: DOPRI5 map, {len(dop)} runs, {time.perf_counter() - t0:.1f} s", quiet)
    p_dop = c.write_csv(outdir / "stability_dopri5.csv", DOPRI_HEADER, dop)
    t0 = time.perf_counter()
    imp = implicit_map([1e-2, 1e-4], 7 if quick else 11, threads, client)
    c.log(f"stability: implicit map, {len(imp)} runs, {time.perf_counter() - t0:.1f} s", quiet)
    p_imp = c.write_csv(outdir / "stability_implicit.csv", IMPLICIT_HEADER, imp)
    t0 = time.perf_counter()
    ext = extremes(quick, threads, client)
    c.log(f"stability: extremes, {time.perf_counter() - t0:.1f} s", quiet)
    p_ext = c.write_csv(outdir / "stability_extremes.csv", EXTREME_HEADER, ext)
    c.log_caption("Extreme runs (stability_extremes.csv, with t_reached [s], nfev, x_end [m], "
                  "v_end and v_max [m/s]): status [-] is the library's status code, 0 = reached "
                  "t_end, negative = the error named in outcome (a ValueError is raised before "
                  "any step).", quiet)
    c.log(c.markdown_table(["case", "scene", "law", "method", "status [-]", "outcome"],
                           [r[:6] for r in ext]), quiet)
    # The RK4 boundary against the linear bound, bracketed by the map's grid.
    c.log_caption(boundary_caption(9 if quick else 17), quiet)
    c.log(c.markdown_table(["scene", "law", "v_s [m/s]", "h_lin [s]", "h_obs [s]", "h_next [s]",
                            "h_obs/h_lin", "h_next/h_lin"], boundary(rk4)), quiet)
    return [p_rk4, p_dop, p_imp, p_ext] + plot(p_rk4, outdir) + plot(p_dop, outdir) \
        + [plot_implicit(p_imp, outdir)]


def boundary_caption(n_h: int) -> str:
    """What the boundary table's columns mean and how finely the map resolves them."""
    step = 400.0 ** (1.0 / (n_h - 1))
    return (f"RK4 stability boundary on the map's grid: {n_h} step sizes from h_lin/20 to "
            f"20 h_lin, a factor {step:.3g} apart.\n"
            "h_lin = 2.785/|lambda| [s], the linear bound; h_obs [s] = the largest stable h below "
            "the first non-stable one, h_next [s] = that first non-stable h (empty: none in the "
            "window). The true boundary lies between h_obs and h_next, so h_obs/h_lin = "
            f"{1 / step:.2f} with h_next/h_lin = 1 means a boundary in [{1 / step:.2f}, 1] h_lin: the grid's resolution, "
            "not a miss of the bound (a 2%-step scan, tests/fortran/test_integrators_extremes.py, finds the RecurDyn slope "
            "boundary within 2% of h_lin). Belt runs cover only the 0.03 s stick phase, so larger "
            "steps may leave it before an instability shows. Coulomb has no linear bound (mu' = 0 "
            "off its jump) and is left out.")


def boundary(rk4_rows: list[list[Any]]) -> list[list[Any]]:
    """Per (scene, law, v_s) with a linear bound: h_lin, the largest stable h below the first
    non-stable one (h_obs), that first non-stable h (h_next, None if every h was stable), and
    both as ratios to h_lin."""
    out = []
    keys = sorted({(r[0], r[1], r[2]) for r in rk4_rows if math.isfinite(r[4])},
                  key=lambda k: (k[0], k[1], -k[2]))
    for s, l, vs in keys:
        rows = sorted([r for r in rk4_rows if (r[0], r[1], r[2]) == (s, l, vs)], key=lambda r: r[3])
        h_obs = h_next = None
        for r in rows:
            if r[11] != "stable":
                h_next = r[3]
                break
            h_obs = r[3]
        h_lin = rows[0][4]
        out.append([s, l, vs, h_lin, h_obs, h_next, None if h_obs is None else h_obs / h_lin,
                    None if h_next is None else h_next / h_lin])
    return out


def plot(csv: str | Path, outdir: str | Path) -> list[Path]:
    """Render stability_rk4.csv (class over h x v_s with h_lin) or stability_dopri5.csv
    (nfev over rtol x v_s, forced steps and stiffness marked): one panel per scene and law."""
    from matplotlib.colors import LogNorm
    cols = c.read_csv(csv)
    is_rk4 = "h [s]" in cols
    c._style.apply(MAP_WIDTH)
    # a row per law, a column per scene
    fig, axes = c.plt.subplots(len(LAWS), len(SCENES), figsize=(MAP_WIDTH, 2.8 + 2.4 * len(LAWS)),
                               squeeze=False, sharex=True)
    colors = c._style.CLASS_COLORS
    for a, s in enumerate(SCENES):
        for b, l in enumerate(LAWS):
            ax = axes[b][a]
            sel = [i for i in range(len(cols["law [-]"]))
                   if cols["scene [-]"][i] == s and cols["law [-]"][i] == l]
            vs = np.array([float(cols["v_s [m/s]"][i]) for i in sel])
            if is_rk4:
                h = np.array([float(cols["h [s]"][i]) for i in sel])
                cls = [cols["class [-]"][i] for i in sel]
                for k in CLASSES:
                    m = np.array([q == k for q in cls])
                    if m.any():
                        ax.loglog(vs[m], h[m], "s", color=colors[k], ms=4, label=f"RK4: {c._style.name(k)}")
                v_line = np.geomspace(vs.min(), vs.max(), 50)
                if l != "coulomb":
                    ax.loglog(v_line, [linear_bound(s, l, v)[1] for v in v_line], "k-", lw=1.2,
                              label="linear stability bound h_lin = 2.785/|λ| [s]")
                if a == 0:
                    ax.set_ylabel("RK4 step h [s]")
            else:
                rt = np.array([float(cols["rtol [-]"][i]) for i in sel])
                nfev = np.array([float(cols["nfev [-]"][i]) for i in sel])
                forced = np.array([float(cols["nforced [-]"][i]) for i in sel])
                stiff = np.array([cols["stiff [-]"][i] == "1" for i in sel])
                sc = ax.scatter(vs, rt, c=nfev, norm=LogNorm(), cmap="viridis", marker="s", s=30)
                ax.set_xscale("log")
                ax.set_yscale("log")
                fig.colorbar(sc, ax=ax, label="nfev [-]")
                ax.scatter(vs[forced > 0], rt[forced > 0], marker="x", color=c._style.OKABE_ITO["vermillion"], s=14,
                           label="forced steps at h_min (nforced > 0)")
                ax.scatter(vs[stiff], rt[stiff], marker="o", facecolors="none",
                           edgecolors=c._style.OKABE_ITO["sky blue"], s=40, label="stiffness detected (stiff flag)")
                if a == 0:
                    ax.set_ylabel("rtol [-]")
            ax.set_title(f"{s}, {c.LAW_LABELS[l].split(' (')[0]}")
            if b == len(LAWS) - 1:
                ax.set_xlabel("v_s [m/s]")
    fig.suptitle("RK4 from rest: outcome over h and v_s" if is_rk4 else
                 "DOPRI5 from rest: cost over rtol and v_s")
    c.figure_legend(fig, axes.ravel(), ncol=2)
    name = "stability_rk4.png" if is_rk4 else "stability_dopri5.png"
    return [c.save_figure(fig, Path(outdir) / name)]


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.stability [--outdir DIR] [--quick] [--threads N]
    [--scheduler ADDRESS]."""
    return c.study_main("cases.stability", __doc__,
                        "coarser maps and no 2e8-step run (a few seconds)", run, argv)


if __name__ == "__main__":
    main()
