"""Stick fidelity of every friction law and method against exact answers::

    python -m cases.stick --outdir out/           # about 10 s
    python -m cases.stick --outdir out/ --quick   # the paper's middle step and tolerance only

Every law x method of the library at the paper's steps (h = 1e-2, 1e-3, 1e-4 s) and tolerances
(rtol = 1e-2, 1e-4, 1e-6, atol = 1e-3 rtol, h in [1e-6, 1e-2] s for the adaptive methods) on
three problems with exact answers (set-valued Coulomb friction, mu_s = 0.35, mu_k = 0.30):

(a) ``slope_rest``: the slope at 10 deg from rest for 20 s. Below the friction angle the box
    never moves: error |x(20 s)| [m].
(b) ``slope_stop``: the slope at 10 deg started at v0 = 2 m/s, 5 s. It slides with deceleration
    a = g (mu_k cos th - sin th) and stops for good at t_stop = v0/a, x_stop = v0^2/(2a):
    errors |x(5 s) - x_stop| [m] and |t_stop - v0/a| [s], with t_stop where v first reaches 0:
    the line through the two grid points (1 ms apart) before it, extended to v = 0 (exact for
    the linear deceleration); empty when v never reaches 0 (a creeping law).
(c) ``belt_stuck``: the belt (m = 10 kg, k = 300 N/m) slowed to v_b = 0.1 m/s so that a quarter
    of each cycle is stick, started stuck (x = 0, v = v_b), 5 s. The Coulomb cycle: centre
    x_k = mu_k m g/k, amplitude A = sqrt(((mu_s - mu_k) m g/k)^2 + (v_b/w)^2), w = sqrt(k/m),
    period (pi + 2 asin(v_b/(A w)))/w + 2 (mu_s - mu_k) m g/(k v_b): errors of the amplitude
    (half the range of x after the first slip, extremes refined by a parabola through three grid
    points), of the period (up-crossings of x_k), and max |x - x_exact| over the run [m].

The exact answers are those of set-valued Coulomb friction; a law with another slip curve
(Stribeck: mu above mu_k at low speeds, the bristle laws) differs from them physically as well
as numerically. Cost: right-hand-side (or force) evaluations, steps and CPU seconds of the library call.
Transitions: changes between |v_rel| < 1e-4 m/s and above on the output grid (event_driven
also reports its events). A run that fails (a step budget of 2e5 steps, a Newton failure) is a
row with its status and no error. Writes ``stick.csv``, ``stick.md`` (the tables of every run),
``stick_best.md`` (per problem and law, the method and setting with the smallest error, and
the methods that were exact), ``stick_best.png`` / ``.pdf`` (per problem and law, the smallest
error each method reached: exact, a number, or failed) and ``stick.png`` / ``.pdf`` (every run: error
against CPU time per problem, one colour per method, one marker per law).
"""
from __future__ import annotations

import math
import textwrap
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from harness import style

from . import _common as c
MU_S, MU_K, G = 0.35, 0.30, 9.81
THETA_DEG = 10.0
V0_SLOPE = 2.0                        # (b) initial speed [m/s]
BELT = {"m": 10.0, "k": 300.0, "v_b": 0.1}
T_END = {"slope_rest": 20.0, "slope_stop": 5.0, "belt_stuck": 5.0}
N_OUT = {"slope_rest": 2001, "slope_stop": 5001, "belt_stuck": 50001}
STEPS: tuple[float, ...] = (1e-2, 1e-3, 1e-4)       # [s]
RTOLS: tuple[float, ...] = (1e-2, 1e-4, 1e-6)       # atol = 1e-3 rtol
MAX_STEPS: int = 200_000
STUCK_SPEED: float = 1e-4             # |v_rel| below this counts as stuck [m/s]
FLOOR: float = 1e-16                  # exact zeros are drawn here on the log axes

HEADER = ["problem [-]", "law [-]", "method [-]", "h [s]", "rtol [-]", "status [-]", "nfev [-]",
          "nstep [-]", "cpu [s]", "transitions [-]", "nevents [-]", "err_x [m]", "err_t_stop [s]",
          "err_amplitude [m]", "err_period [s]", "err_path [m]"]


def exact() -> dict[str, float]:
    """The exact answers of (b) and (c)."""
    th = math.radians(THETA_DEG)
    a = G * (MU_K * math.cos(th) - math.sin(th))
    m, k, v_b = BELT["m"], BELT["k"], BELT["v_b"]
    w = math.sqrt(k / m)
    d = (MU_S - MU_K) * m * G / k
    amp = math.hypot(d, v_b / w)
    phi = math.asin(v_b / (amp * w))
    return {"t_stop": V0_SLOPE / a, "x_stop": V0_SLOPE ** 2 / (2 * a), "x_k": MU_K * m * G / k,
            "d": d, "A": amp, "w": w, "phi": phi, "t_slip": (math.pi + 2 * phi) / w,
            "period": (math.pi + 2 * phi) / w + 2 * d / v_b, "t1": MU_S * m * G / k / v_b}


def belt_path(t: np.ndarray) -> np.ndarray:
    """The exact x(t) of (c): stuck until the spring holds mu_s m g, then the cycle."""
    e = exact()
    tau = np.mod(t - e["t1"], e["period"])
    x = np.where(tau < e["t_slip"], e["x_k"] + e["A"] * np.cos(e["w"] * tau - e["phi"]),
                 e["x_k"] - e["d"] + BELT["v_b"] * (tau - e["t_slip"]))
    return np.where(t < e["t1"], BELT["v_b"] * t, x)


def jobs(quick: bool = False) -> list[dict[str, Any]]:
    """Every (problem, law, method, setting) as keyword arguments of stickslip.simulate."""
    import stickslip as ss
    steps, rtols = ((1e-3,), (1e-4,)) if quick else (STEPS, RTOLS)
    out = []
    for problem in T_END:
        scene = "belt" if problem == "belt_stuck" else "slope"
        start = {"v0": BELT["v_b"], **BELT} if scene == "belt" else \
            {"theta_deg": THETA_DEG, "v0": V0_SLOPE if problem == "slope_stop" else 0.0}
        for law in ss.LAWS:
            for method in ss.METHODS:
                controls = ss.REGISTRY["method"][method]["controls"]
                settings = [{"h": h} for h in steps] if "h" in controls else \
                    [{"rtol": r, "atol": 1e-3 * r, **({"hmin": 1e-6, "hmax": 1e-2} if "hmin" in controls else {})}
                     for r in rtols]
                for s in settings:
                    out.append({"problem": problem, "scene": scene, "law": law, "method": method,
                                "t_end": T_END[problem], "n_out": N_OUT[problem], "max_steps": MAX_STEPS,
                                "mu_s": MU_S, "mu_k": MU_K, **start, **s})
    return out


def simulate_job(job: dict[str, Any]) -> dict[str, Any]:
    """Run one job; the outcome with its status (a refusal or a run-time failure is a status,
    not an exception)."""
    import warnings

    import stickslip as ss
    kw = {k: v for k, v in job.items() if k not in ("problem", "scene", "law")}
    out = {"job": job, "status": "ok"}
    try:
        with warnings.catch_warnings():     # RK4's stability warnings: the errors show it
            warnings.simplefilter("ignore", UserWarning)
            r = ss.simulate(job["scene"], job["law"], **kw)
    except ss.IntegrationError as exc:
        out["status"] = type(exc).__name__
        r = exc.result
    except ValueError as exc:
        out["status"] = "refused"
        out["reason"] = str(exc)
        return out
    out.update(t=r.t, x=r.x, v=r.v, stats=r.stats, nevents=len(r.events))
    return out


def _transitions(v_rel: np.ndarray) -> int:
    stuck = np.abs(v_rel) < STUCK_SPEED
    return int(np.count_nonzero(stuck[1:] != stuck[:-1]))


def _extremes(t: np.ndarray, x: np.ndarray, sign: float) -> np.ndarray:
    """Local maxima (sign 1) or minima (-1) of x on the grid, refined by a parabola."""
    y = sign * x
    i = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1
    a, b, cc = y[i - 1], y[i], y[i + 1]
    den = a - 2 * b + cc
    with np.errstate(divide="ignore", invalid="ignore"):
        peak = np.where(den < 0, b - 0.125 * (a - cc) ** 2 / den, b)
    return sign * peak


def measure(o: dict[str, Any]) -> list[Any]:
    """One CSV row from an outcome."""
    job = o["job"]
    row: list[Any] = [job["problem"], job["law"], job["method"], job.get("h"), job.get("rtol"), o["status"]]
    if "t" not in o:
        return row + [None] * (len(HEADER) - len(row))
    st, t, x, v = o["stats"], o["t"], o["x"], o["v"]
    e = exact()
    v_rel = v - BELT["v_b"] if job["scene"] == "belt" else v
    row += [st["nfev"], st["nstep"], st["cpu_seconds"], _transitions(v_rel), o["nevents"]]
    err_x = err_t = err_a = err_p = err_path = None
    complete = o["status"] == "ok"
    if job["problem"] == "slope_rest" and complete:
        err_x = abs(x[-1])
    elif job["problem"] == "slope_stop" and complete:
        err_x = abs(x[-1] - e["x_stop"])
        k = np.flatnonzero((v[:-1] > 0) & (v[1:] <= 0))
        if k.size and k[0] >= 1 and v[k[0] - 1] > v[k[0]]:
            i = k[0]
            err_t = abs(t[i] + v[i] / (v[i - 1] - v[i]) * (t[i] - t[i - 1]) - e["t_stop"])
    elif job["problem"] == "belt_stuck" and complete:
        after = t > e["t1"] + 0.05
        hi, lo = _extremes(t[after], x[after], 1.0), _extremes(t[after], x[after], -1.0)
        if hi.size and lo.size:
            err_a = abs(0.5 * (hi.max() - lo.min()) - e["A"])
        up = np.flatnonzero((x[:-1] < e["x_k"]) & (x[1:] >= e["x_k"]))
        if up.size >= 2:
            tc = t[up] + (e["x_k"] - x[up]) / (x[up + 1] - x[up]) * (t[up + 1] - t[up])
            err_p = abs(np.mean(np.diff(tc)) - e["period"])
        err_path = float(np.max(np.abs(x - belt_path(t))))
    return row + [err_x, err_t, err_a, err_p, err_path]


def run(outdir: str | Path, *, quick: bool = False, threads: int = 1, quiet: bool = False) -> list[Path]:
    """Simulate every job and write the CSV, tables and figure. The runs are serial (the whole
    study takes seconds, less than a process pool costs to start): `threads` is accepted for
    `python -m cases` and not used."""
    outdir = Path(outdir)
    todo = jobs(quick)
    c.log(f"cases.stick: {len(todo)} runs", quiet)
    start = time.perf_counter()
    rows = [measure(simulate_job(job)) for job in todo]
    c.log(f"cases.stick: {time.perf_counter() - start:.1f} s", quiet)
    csv_path = c.write_csv(outdir / "stick.csv", HEADER, rows)
    return [csv_path, write_tables(csv_path, outdir), write_best(csv_path, outdir),
            *plot_best(csv_path, outdir), *plot(csv_path, outdir)]


def _rows(csv_path: Path) -> list[dict[str, str]]:
    cols = c.read_csv(csv_path)
    return [dict(zip(cols, vals)) for vals in zip(*cols.values())]


def _num(s: str) -> float | None:
    return float(s) if s not in ("", None) else None


ERRORS = {"slope_rest": ("err_x [m]",), "slope_stop": ("err_x [m]", "err_t_stop [s]"),
          "belt_stuck": ("err_amplitude [m]", "err_period [s]", "err_path [m]")}
TITLES = {"slope_rest": "(a) slope at 10 deg from rest, 20 s: |x(20 s)|",
          "slope_stop": "(b) slope, v0 = 2 m/s, sliding to a stop: |x(5 s) - x_stop|",
          "belt_stuck": "(c) belt started stuck, v_b = 0.1 m/s: |amplitude - A|"}


SHORT_TITLES = {"slope_rest": "(a) slope, at rest", "slope_stop": "(b) slope, sliding to a stop",
                "belt_stuck": "(c) belt, started stuck"}


def write_tables(csv_path: Path, outdir: Path) -> Path:
    """stick.md: one table per problem, a row per law x method x setting that ran."""
    parts = ["# Stick fidelity: every law and method against exact answers\n",
             "Made by `python -m cases.stick` (see its docstring for the problems). Errors in m "
             "and s; 0 means exactly zero; CPU in ms; a failed run shows its status.\n"]
    rows = _rows(csv_path)
    for problem, errs in ERRORS.items():
        parts.append(f"\n## {TITLES[problem]}\n\n")
        header = ["law", "method", "h or rtol", "status", *[e.split(" ")[0] for e in errs],
                  "nfev", "steps", "CPU [ms]", "transitions"]
        body = []
        for r in rows:
            if r["problem [-]"] != problem or r["status [-]"] == "refused":
                continue
            setting = f"h = {r['h [s]']}" if r["h [s]"] else f"rtol = {r['rtol [-]']}"
            cpu = _num(r["cpu [s]"])
            body.append([r["law [-]"], r["method [-]"], setting, r["status [-]"],
                         *[_num(r[e]) for e in errs], r["nfev [-]"], r["nstep [-]"],
                         None if cpu is None else 1e3 * cpu, r["transitions [-]"]])
        parts.append(c.markdown_table(header, body))
    refused = sorted({(r["law [-]"], r["method [-]"]) for r in rows if r["status [-]"] == "refused"})
    parts.append("\nRefused before running (the nonsmooth methods take the set-valued laws only): "
                 + ", ".join(f"{law}/{m}" for law, m in refused) + ".\n")
    return c.write_text(outdir / "stick.md", "".join(parts))


#: The laws of stick.png: the two with a set-valued counterpart, where every method runs (the
#: best error of every law is stick_best.png's).
PLOT_LAWS: tuple[str, ...] = ("coulomb", "stribeck")
#: Width of stick.png [in]; its fonts are scaled to stay legible at a column width.
PLOT_WIDTH: float = 5.6
#: Short panel titles of stick.png.
SHORT_TITLES: dict[str, str] = {"slope_rest": "slope, from rest", "slope_stop": "slope, to a stop",
                                "belt_stuck": "belt, started stuck"}


def plot(csv_path: str | Path, outdir: str | Path) -> list[Path]:
    """stick.png and stick.pdf: for each problem (a row) and each of PLOT_LAWS (a column) its
    first error against CPU time, a line per method through its settings (the method's colour
    and marker of harness.style); exact results (error 0) on the dotted line at FLOOR; a run
    that failed (status other than ok, e.g. its step budget) a cross at the top of its panel;
    the methods refused by a law named in the panel."""
    import matplotlib.pyplot as plt
    from matplotlib.transforms import blended_transform_factory
    rows = _rows(Path(csv_path))
    methods = list(dict.fromkeys(r["method [-]"] for r in rows))
    style.apply(PLOT_WIDTH)
    fig, axes = plt.subplots(len(ERRORS), len(PLOT_LAWS), figsize=(PLOT_WIDTH, 8.4), squeeze=False,
                             sharey="row", layout="constrained")
    handles: dict[str, Any] = {}
    for i, (problem, errs) in enumerate(ERRORS.items()):
        for j, law in enumerate(PLOT_LAWS):
            ax = axes[i][j]
            top = blended_transform_factory(ax.transData, ax.transAxes)
            refused = []
            for method in methods:
                mine = [r for r in rows if r["problem [-]"] == problem and r["method [-]"] == method
                        and r["law [-]"] == law]
                if mine and all(r["status [-]"] == "refused" for r in mine):
                    refused.append(style.name(method).split(" (")[0])
                look = {"color": style.color(method), "marker": style.METHOD_MARKERS.get(method, "o"),
                        "mec": "black" if method == "event_driven" else None, "mew": 0.5}
                pts = [(_num(r["cpu [s]"]), _num(r[errs[0]])) for r in mine
                       if r["status [-]"] == "ok" and _num(r[errs[0]]) is not None]
                if pts:
                    cpu, err = zip(*sorted(pts))
                    handles[style.name(method).split(" (")[0]] = ax.plot(
                        cpu, np.maximum(err, FLOOR), ms=5, lw=1.0, **look)[0]
                failed = [_num(r["cpu [s]"]) for r in mine if r["status [-]"] not in ("ok", "refused")
                          and _num(r["cpu [s]"]) is not None]
                if failed:
                    ax.plot(failed, [0.96] * len(failed), "x", transform=top, clip_on=False, ms=7,
                            mew=1.5, color=look["color"])
                    handles["failed run (its method's colour)"] = plt.Line2D(
                        [], [], color="0.3", marker="x", ms=7, mew=1.5, linestyle="none")
            ax.set_xscale("log")
            ax.set_yscale("log")
            handles[f"error 0 (at {FLOOR:g})"] = ax.axhline(FLOOR, color="0.5", lw=0.8, ls=":")
            if refused:
                ax.text(0.03, 0.04, "refused: " + ", ".join(refused), transform=ax.transAxes,
                        color="0.25", in_layout=False)
            if i == 0:
                ax.set_title(style.name(law).split(" (")[0])
            if i == len(ERRORS) - 1:
                ax.set_xlabel("CPU time of a run [s]")
            if j == 0:
                unit = errs[0].split("[")[1].rstrip("]")
                ax.set_ylabel(f"{SHORT_TITLES[problem]}\nerror [{unit}]")
        lo, hi = (np.log10(v) for v in axes[i][0].get_ylim())
        axes[i][0].set_ylim(10.0 ** lo, 10.0 ** (hi + 0.15 * (hi - lo)))   # the crosses' strip
    order = [style.name(m).split(" (")[0] for m in methods] + ["failed run (its method's colour)",
                                                                 f"error 0 (at {FLOOR:g})"]
    keys = [k for k in order if k in handles]
    fig.legend([handles[k] for k in keys], keys, loc="outside lower center", ncol=2,
               frameon=False, handlelength=1.8, columnspacing=1.0, labelspacing=0.3)
    fig.suptitle("Error against CPU time, every setting")
    outdir = Path(outdir)
    png = c.atomic_write(outdir / "stick.png", lambda f: fig.savefig(f, format="png", dpi=200), binary=True)
    pdf = c.atomic_write(outdir / "stick.pdf", lambda f: fig.savefig(f, format="pdf"), binary=True)
    plt.close(fig)
    return [png, pdf]


def best_runs(rows: list[dict[str, str]], problem: str) -> dict[tuple[str, str], dict[str, str]]:
    """For each (law, method) of `problem`: its run with the smallest first error (ties: the
    cheaper), or, when no setting finished, one of its failed or refused rows."""
    err_col = ERRORS[problem][0]
    best: dict[tuple[str, str], dict[str, str]] = {}
    for r in rows:
        if r["problem [-]"] != problem:
            continue
        key = (r["law [-]"], r["method [-]"])
        err = _num(r[err_col])
        old = best.get(key)
        if old is None:
            best[key] = r
            continue
        old_err = _num(old[err_col])
        if err is not None and (old_err is None or (err, _num(r["cpu [s]"]) or 0.0)
                                < (old_err, _num(old["cpu [s]"]) or 0.0)):
            best[key] = r
    return best


def write_best(csv_path: str | Path, outdir: str | Path) -> Path:
    """stick_best.md: per problem one row per law: the method and setting with the smallest
    error (ties: the cheaper), that error and its CPU time, and the methods that were exact
    (error 0) at some setting."""
    rows = _rows(Path(csv_path))
    laws = list(dict.fromkeys(r["law [-]"] for r in rows))
    parts = []
    for problem, errs in ERRORS.items():
        best = best_runs(rows, problem)
        exact_by = {law: sorted({r["method [-]"] for r in rows if r["problem [-]"] == problem
                                 and r["law [-]"] == law and _num(r[errs[0]]) == 0.0},
                                key=lambda m: list(best).index((law, m)) if (law, m) in best else 0)
                    for law in laws}
        body = []
        for law in laws:
            cands = [r for (lw, _), r in best.items() if lw == law and _num(r[errs[0]]) is not None]
            if not cands:
                body.append([style.name(law), "none finished", "", None, None, ""])
                continue
            r = min(cands, key=lambda r: (_num(r[errs[0]]), _num(r["cpu [s]"]) or 0.0))
            setting = f"h = {r['h [s]']} s" if r["h [s]"] else f"rtol = {r['rtol [-]']}"
            cpu = _num(r["cpu [s]"])
            body.append([style.name(law), style.name(r["method [-]"]), setting, _num(r[errs[0]]),
                         None if cpu is None else 1e3 * cpu,
                         ", ".join(style.name(m) for m in exact_by[law]) or "none"])
        unit = errs[0].split("[")[1].rstrip("]")
        parts.append(f"{TITLES[problem]}\n\n" + c.markdown_table(
            ["law", "best method", "its setting", f"error [{unit}]", "CPU [ms]", "exact (error 0) with"],
            body))
    return c.write_text(Path(outdir) / "stick_best.md", "\n".join(parts))


#: Width of stick_best.png [in]; its fonts are scaled to stay legible at a column width.
BEST_WIDTH: float = 6.4
#: Its panels' titles (the problems of ERRORS, short enough for a third of its width).
BEST_TITLES: dict[str, str] = {"slope_rest": "(a) rest", "slope_stop": "(b) stop", "belt_stuck": "(c) belt"}


def plot_best(csv_path: str | Path, outdir: str | Path) -> list[Path]:
    """stick_best.png and .pdf: per problem, for each law (a row) the smallest error each method
    reached over its settings, a marker per method in the method's colour on a log axis; "exact"
    (error 0) at the left edge, "failed" (no setting finished) at the right edge, a hollow marker
    where some other setting failed (the error shown is then that of a looser setting); a method
    that refuses the law has no marker."""
    import matplotlib.pyplot as plt
    rows = _rows(Path(csv_path))
    methods = list(dict.fromkeys(r["method [-]"] for r in rows))
    laws = list(dict.fromkeys(r["law [-]"] for r in rows))
    style.apply(BEST_WIDTH)
    lo, hi = 1e-12, 10.0                 # the error axis; exact drawn at exact_at, failures at fail_at
    exact_at, fail_at = 1e-14, 1e3
    fig, axes = plt.subplots(1, len(ERRORS), figsize=(BEST_WIDTH, 0.42 * len(laws) + 4.0), sharey=True,
                             layout="constrained")
    for ax, (problem, errs) in zip(axes, ERRORS.items()):
        best = best_runs(rows, problem)
        partly = {(r["law [-]"], r["method [-]"]) for r in rows            # some setting failed
                  if r["problem [-]"] == problem and r["status [-]"] not in ("ok", "refused")}
        for mi, method in enumerate(methods):
            dy = (mi - (len(methods) - 1) / 2) * 0.09
            for li, law in enumerate(laws):
                r = best.get((law, method))
                if r is None or r["status [-]"] == "refused":
                    continue
                err = _num(r[errs[0]])
                x = fail_at if err is None else (exact_at if err == 0.0 else min(max(err, lo), hi))
                colour = style.METHOD_COLORS.get(method, "0.3")
                ax.plot([x], [li + dy], linestyle="none", color=colour,
                        marker="x" if err is None else "o", markersize=3.2 if err is None else 3.0,
                        markerfacecolor="white" if (law, method) in partly and err is not None else colour)
        ax.set_xscale("log")
        ax.set_xlim(exact_at / 4, fail_at * 4)
        ticks = [exact_at, 1e-10, 1e-5, 1.0, fail_at]
        ax.set_xticks(ticks, ["exact", "1e-10", "1e-5", "1", "failed"], rotation=90)
        ax.minorticks_off()
        for edge in (exact_at * 10 ** 0.5, fail_at / 10 ** 0.5):
            ax.axvline(edge, color="0.6", linewidth=0.6)
        unit = errs[0].split("[")[1].rstrip("]")
        ax.set_xlabel(f"error [{unit}]")
        ax.set_title(BEST_TITLES[problem])
        ax.set_ylim(len(laws) - 0.5, -0.5)
        ax.grid(axis="y", visible=False)
        for li in range(len(laws) - 1):
            ax.axhline(li + 0.5, color="0.9", linewidth=0.5)
    axes[0].set_yticks(range(len(laws)), [textwrap.fill(style.name(law).split(" (")[0], 14) for law in laws])
    handles = [plt.Line2D([], [], color=style.METHOD_COLORS.get(m, "0.3"), marker="o", linestyle="none",
                          markersize=4, label=style.name(m)) for m in methods]
    handles += [plt.Line2D([], [], color="0.3", marker="o", markerfacecolor="white", linestyle="none",
                           markersize=4, label="other settings failed"),
                plt.Line2D([], [], color="0.3", marker="x", linestyle="none", markersize=4,
                           label="no setting finished")]
    fig.legend(handles=handles, loc="outside lower center", ncol=2, frameon=False)
    png = style.save(fig, Path(outdir) / "stick_best.png", c.atomic_write)
    return [png, png.with_suffix(".pdf")]


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.stick [--outdir DIR] [--quick] [--threads N] [--quiet]."""
    return c.study_main("cases.stick", __doc__, "one step size and one tolerance (h = 1e-3 s, rtol = 1e-4)",
                        run, argv)


if __name__ == "__main__":
    main()
