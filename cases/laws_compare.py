"""Which friction law? Every law of the registry on both scenes, with every method of the
registry (fixed-step methods at the paper's steps h = 1e-3 s and 1e-4 s, adaptive ones at the
facade's default tolerances), against exact answers::

    python -m cases.laws_compare --outdir out/       # about 20 s

Four tables (CSV with units, a PNG each, and laws_compare.md with all of them), and the
presliding transients of the laws with internal states:

- laws_compare_slope.csv: the box on the 10 degree slope from rest, 20 s. Truth: a box held by
  static friction (tan 10 deg = 0.176 < mu_s = 0.35) does not move, x(20 s) = 0. Regularised
  laws creep at v* with mu(v*) = tan(theta); bristle laws settle at a presliding displacement
  of order tan(theta)/sigma0 (2e-5 m) and stop.
- laws_compare_belt.csv: the mass on the belt started stuck (x0 = 0, v0 = v_b), 10 s, against
  the exact Coulomb stick-slip cycle (`coulomb_cycle`: stick until k x = mu_s m g, harmonic slip
  about x_k = mu_k m g / k at w = sqrt(k/m) until the mass is back at belt speed, stick again):
  extremes and period of the last cycle, and the time from which every maximum is within 1 mm
  of the exact one ("reached the Coulomb cycle"), with the cost (right-hand-side evaluations,
  CPU seconds).
- laws_compare_rest.csv: the belt from rest, 30 s, adaptive method: the growth rate of the
  oscillation, measured from its peaks, against -g mu'(v_b)/2 (the linearisation
  m x'' + m g mu'(v_b) x' + k x = const), and the first time the mass sticks (v_rel < 1e-3 m/s).
  Only a law whose steady curve falls at the belt speed (mu' < 0) grows from rest into stick-slip.
- laws_compare_hmax.csv: the largest RK4 step (bisection in log h over [1e-6, 1e-2] s; for the
  implicit methods over [1e-5, 1e-2] s,
  assuming one boundary; slope 2 s from rest, belt 3 s from stuck) by two criteria:
  "bounded" (finite, |v| within the scene's physical bound, and for bristle laws
  |z| <= mu_s/sigma0, an invariant of the exact solution: RK4's stability in the strict sense)
  and "1 %" (bounded, and v within 1 % of its largest value, + 1e-6 m/s, of a DOPRI5 run at
  rtol = 1e-9 over the second half: a step that also gets the answer right). 1e-2 means "not
  limited in the range", 0 "no step in the range".
- laws_compare_presliding.csv: x and the internal states (named from Result.state_labels,
  e.g. "z lugre [m]") of every law with states on the slope over the first 50 ms, DOPRI5 at
  rtol = 1e-10: the bristle settles at sigma0 z = tan(theta).

The bristle laws run with the 1995 paper's viscous term sigma2 (their defaults) and again
with sigma2 = 0 on the belt ("lugre sigma2=0"): the viscous term damps the belt's
oscillation at g sigma2 / 2 = 0.2 1/s, which ends its stick-slip.

Methods come from stickslip.METHODS, so methods added to the registry (implicit ones) join
the study without a change here; a method that takes only some laws (the set-valued moreau and
event_driven: REGISTRY["method"][m]["laws"]) runs those only. --threads is accepted for `python -m cases`; the runs are
serial (about 400 short simulations).
"""
from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import _common as c

STEPS: tuple[float, ...] = (1e-3, 1e-4)      # the paper's RK4 steps [s]
SLOPE_T: float = 20.0                        # [s]
BELT_T: float = 10.0                         # [s]
REST_T: float = 30.0                         # [s]
BELT_N: int = 20001                          # output every 0.5 ms
CYCLE_TOL: float = 1e-3                      # [m]: "reached the Coulomb cycle"
STICK_V: float = 1e-3                        # [m/s]: v_rel below which the mass counts as stuck
RK4_LIMIT: float = 2.785293563405282         # RK4 stability interval on the negative real axis
P: dict[str, float] = {"m": 10.0, "k": 300.0, "v_b": 1.5, "g": 9.81, "theta_deg": 10.0}
#: Extra configurations of the belt studies: (label, law, parameters).
EXTRA: tuple[tuple[str, str, dict[str, float]], ...] = (
    ("lugre sigma2=0", "lugre", {"sigma2": 0.0}),
    ("elastoplastic sigma2=0", "elastoplastic", {"sigma2": 0.0}))

SLOPE_HEADER = ["law [-]", "method [-]", "h [s]", "status [-]", "x_20 [m]", "v_20 [m/s]",
                "z_20 [m]", "nfev [-]", "cpu [s]"]
BELT_HEADER = ["law [-]", "method [-]", "h [s]", "status [-]", "x_max [m]", "x_min [m]",
               "period [s]", "err_x_max [m]", "err_x_min [m]", "err_period [s]",
               "t_coulomb [s]", "nfev [-]", "cpu [s]"]
REST_HEADER = ["law [-]", "method [-]", "dmu_dv_at_v_b [s/m]", "rate_predicted [1/s]",
               "rate_measured [1/s]", "t_first_stick [s]", "nfev [-]", "cpu [s]"]
HMAX_HEADER = ["law [-]", "scene [-]", "h_bounded [s]", "h_1pct [s]", "runs [-]"]


# --------------------------------------------------------------------------------------------
# Exact answers and measurements
# --------------------------------------------------------------------------------------------
def coulomb_cycle(mu_s: float = 0.35, mu_k: float = 0.30, m: float = P["m"], k: float = P["k"],
                  v_b: float = P["v_b"], g: float = P["g"]) -> tuple[float, float, float, float]:
    """The belt's exact Coulomb stick-slip cycle: (x_max [m], x_min [m], period [s], first
    break-away time from x0 = 0 stuck [s]). The slip starts at x_s = mu_s m g / k with the belt's
    speed and is harmonic about x_k = mu_k m g / k, amplitude A = hypot(x_s - x_k, v_b/w); it
    ends at belt speed at x_k - (x_s - x_k), after the phase 2 pi - 2 phi0 (tan phi0 =
    (x_s - x_k) w / v_b); the stick then carries the mass back to x_s in 2 (x_s - x_k)/v_b."""
    w = math.sqrt(k / m)
    x_s, x_k = mu_s * m * g / k, mu_k * m * g / k
    d = x_s - x_k
    amp = math.hypot(d, v_b / w)
    phi0 = math.atan2(d, v_b / w)
    return x_k + amp, x_k - amp, (2 * math.pi - 2 * phi0) / w + 2 * d / v_b, x_s / v_b


def maxima(t: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Times and values of the local maxima of x on a uniform grid t (parabolic interpolation
    through each maximum and its neighbours)."""
    i = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:])) + 1
    a, b, cc = x[i - 1], x[i], x[i + 1]
    den = a - 2 * b + cc
    shift = np.where(den != 0, 0.5 * (a - cc) / np.where(den != 0, den, 1.0), 0.0)
    return t[i] + shift * (t[1] - t[0]), b - 0.25 * (a - cc) * shift


def takes(method: str, law: str) -> bool:
    """The method takes the law (the set-valued methods take only some: REGISTRY's "laws")."""
    import stickslip
    laws = stickslip.REGISTRY["method"][method]["laws"]
    return laws is None or law in laws


def variants(law: str | None = None) -> list[tuple[str, float | None]]:
    """(method, h) for every registered method (that takes `law`, if given): fixed-step ones at
    STEPS, adaptive ones once."""
    import stickslip
    out: list[tuple[str, float | None]] = []
    for name in stickslip.METHODS:
        if law is not None and not takes(name, law):
            continue
        if "h" in stickslip.REGISTRY["method"][name]["controls"]:
            out += [(name, h) for h in STEPS]
        else:
            out.append((name, None))
    return out


def configs(belt: bool, laws: Sequence[str] | None = None) -> list[tuple[str, str, dict[str, float]]]:
    """(label, law, parameters): every registered law (or those of `laws`) at its defaults,
    plus the EXTRA configurations of those laws on the belt."""
    import stickslip
    chosen = tuple(stickslip.LAWS if laws is None else laws)
    return [(law, law, {}) for law in chosen] + [e for e in EXTRA if belt and e[1] in chosen]


def simulate(scene: str, law: str, method: str, h: float | None, t_end: float, n_out: int,
             **kw: Any) -> tuple[Any, int]:
    """One run: (Result or the partial Result of a run that ended early, status)."""
    import stickslip
    extra = {"h": h} if h is not None else {}
    if "hmax" in stickslip.REGISTRY["method"][method]["controls"]:
        extra.update(hmin=1e-6, hmax=1e-2)      # the paper's step range (simulate's hmax: t_end)
    try:
        with c.steps_beyond_stability():       # the RK4 step sweeps and bisections cross it on purpose
            r = stickslip.simulate(scene, law, method=method, t_end=t_end, n_out=n_out, ignore_unused=True,
                                   **extra,
                                   **{**{k: v for k, v in P.items() if k != "theta_deg" or scene == "slope"},
                                      **kw})
        return r, 0
    except stickslip.IntegrationError as exc:
        return exc.result, exc.status


def bounded(scene: str, law: str, r: Any, status: int, t_end: float) -> bool:
    """Finite, |v| within the scene's physical bound, bristle deflection within mu_s/sigma0
    (a Maxwell-slip element's within mu_s/k_i = n_elements mu_s/sigma0: its level is a
    fraction of mu_s, its stiffness sigma0/n_elements)."""
    import stickslip
    if status != 0 or not np.all(np.isfinite(r.v)):
        return False
    mu_s = 0.35
    if scene == "slope":
        th = math.radians(P["theta_deg"])
        v_lim = P["g"] * (math.sin(th) + mu_s * math.cos(th)) * t_end
    else:
        v_lim = 10 * (P["v_b"] + mu_s * P["g"] * math.sqrt(P["m"] / P["k"]))
    ok = float(np.max(np.abs(r.v))) <= v_lim
    if "sigma0" in stickslip.REGISTRY["law"][law]["params"] and r.z.size:
        per_element = r.z.shape[0] if "n_elements" in stickslip.REGISTRY["law"][law]["params"] else 1
        ok = ok and float(np.max(np.abs(r.z))) <= per_element * mu_s / stickslip.DEFAULTS["sigma0"] * (1 + 1e-9)
    return ok


# --------------------------------------------------------------------------------------------
# The four studies
# --------------------------------------------------------------------------------------------
def slope_rows(quiet: bool, laws: Sequence[str] | None = None) -> list[list[Any]]:
    rows = []
    for _, law, _ in configs(belt=False, laws=laws):
        for method, h in variants(law):
            r, status = simulate("slope", law, method, h, SLOPE_T, 201)
            done = status == 0
            rows.append([law, method, h, status, float(r.x[-1]) if done else None,
                         float(r.v[-1]) if done else None,
                         float(r.y[2, -1]) if done and r.z.size else None,
                         r.stats["nfev"], r.stats["cpu_seconds"]])
        c.log(f"laws_compare: slope {law}", quiet)
    return rows


def belt_rows(quiet: bool, laws: Sequence[str] | None = None) -> list[list[Any]]:
    x_max, x_min, period, _ = coulomb_cycle()
    rows = []
    for label, law, par in configs(belt=True, laws=laws):
        for method, h in variants(law):
            r, status = simulate("belt", law, method, h, BELT_T, BELT_N, v0=P["v_b"], **par)
            row: list[Any] = [label, method, h, status] + [None] * 7
            if status == 0:
                tm, xm = maxima(r.t, r.x)
                tn, xn = maxima(r.t, -r.x)
                if len(tm) >= 3 and len(tn) >= 1:
                    per = float(np.mean(np.diff(tm[-3:])))
                    near = np.flatnonzero(np.abs(xm - x_max) <= CYCLE_TOL)
                    # from this maximum on, every one stays within CYCLE_TOL of the exact one
                    reached = None
                    for i in near:
                        if np.all(np.abs(xm[i:] - x_max) <= CYCLE_TOL):
                            reached = float(tm[i])
                            break
                    row[4:11] = [float(xm[-1]), float(-xn[-1]), per, float(xm[-1] - x_max),
                                 float(-xn[-1] - x_min), per - period, reached]
            rows.append(row + [r.stats["nfev"], r.stats["cpu_seconds"]])
        c.log(f"laws_compare: belt {label}", quiet)
    return rows


def rest_rows(quiet: bool, laws: Sequence[str] | None = None) -> list[list[Any]]:
    import stickslip
    adaptive = [m for m in stickslip.METHODS if stickslip.REGISTRY["method"][m]["adaptive"]]
    method = adaptive[0]
    rows = []
    eps = 1e-6
    for label, law, par in configs(belt=True, laws=laws):
        slope = float((stickslip.friction_coefficient(law, P["v_b"] + eps, **par)
                       - stickslip.friction_coefficient(law, P["v_b"] - eps, **par)) / (2 * eps))
        r, status = simulate("belt", law, method, None, REST_T, 30001, rtol=1e-9, atol=1e-12, **par)
        measured = stick = None
        if status == 0:
            tm, xm = maxima(r.t, r.x)
            tn, xn = maxima(r.t, -r.x)
            first = np.flatnonzero(P["v_b"] - r.v < STICK_V)
            stick = float(r.t[first[0]]) if first.size else None
            # the growth before any sticking: peaks 2 .. 9 (or up to the first stick)
            n = min(len(tm), len(tn), 9)
            if stick is not None:
                n = min(n, int(np.sum(tm < stick)), int(np.sum(tn < stick)))
            if n >= 4:
                amp = (xm[:n] + xn[:n]) / 2
                measured = math.log(amp[n - 1] / amp[1]) / (tm[n - 1] - tm[1])
        rows.append([label, method, slope, -P["g"] * slope / 2, measured, stick, r.stats["nfev"],
                     r.stats["cpu_seconds"]])
        c.log(f"laws_compare: rest {label}", quiet)
    return rows


def largest_step(ok: Any, lo: float = 1e-6, hi: float = 1e-2, iterations: int = 8) -> tuple[float, int]:
    """(largest h in [lo, hi] with ok(h) found by bisection in log h [s] (hi if ok(hi), 0 if
    not ok(lo)), runs). Assumes ok holds below one boundary and fails above it."""
    if ok(hi):
        return hi, 1
    if not ok(lo):
        return 0.0, 2
    for _ in range(iterations):
        mid = math.sqrt(lo * hi)
        if ok(mid):
            lo = mid
        else:
            hi = mid
    return lo, 2 + iterations


def step_limits(scene: str, law: str, method: str = "rk4") -> tuple[float, float, int]:
    """(largest bounded h, largest h within 1 % of the reference [s], simulations run)."""
    t_end, n_out = (2.0, 201) if scene == "slope" else (3.0, 301)
    kw = {} if scene == "slope" else {"v0": P["v_b"]}
    ref, status = simulate(scene, law, "dopri5", None, t_end, n_out, rtol=1e-9, atol=1e-12, **kw)
    tail = ref.t >= t_end / 2
    tol = 0.01 * float(np.max(np.abs(ref.v))) + 1e-6

    done: dict[float, tuple[Any, bool]] = {}

    def run_h(h: float) -> tuple[Any, bool]:
        # the second search starts at the first one's ends: each h is simulated once
        if h not in done:
            r, st = simulate(scene, law, method, h, t_end, n_out, **kw)
            done[h] = r, bounded(scene, law, r, st, t_end)
        return done[h]

    def is_bounded(h: float) -> bool:
        return run_h(h)[1]

    def is_close(h: float) -> bool:
        r, ok = run_h(h)
        return ok and status == 0 and float(np.max(np.abs(r.v[tail] - ref.v[tail]))) <= tol

    import stickslip
    # implicit methods: down to 1e-5 s only. (Chosen when every step on Coulomb's slope ran the
    # damped Newton fallback, about 140 evaluations a step; their stages on Coulomb are now
    # solved over the law's modes at 2 evaluations a step, and the floor is kept so that the
    # study's bisection, and its other rows, stay as they were.)
    lo = 1e-5 if stickslip.REGISTRY["method"][method]["implicit"] else 1e-6
    h_b, _ = largest_step(is_bounded, lo=lo)
    h_c, _ = largest_step(is_close, lo=lo, hi=h_b if h_b > 0 else lo)
    return h_b, h_c, 1 + len(done)


def hmax_rows(quiet: bool, laws: Sequence[str] | None = None) -> list[list[Any]]:
    import stickslip
    fixed = [m for m in stickslip.METHODS if "h" in stickslip.REGISTRY["method"][m]["controls"]]
    rows = []
    for _, law, _ in configs(belt=False, laws=laws):
        for scene in ("slope", "belt"):
            for method in (m for m in fixed if takes(m, law)):
                h_b, h_c, runs = step_limits(scene, law, method)
                rows.append([law, scene + ("" if method == "rk4" else f" {method}"), h_b, h_c, runs])
        c.log(f"laws_compare: h_max {law}", quiet)
    return rows


def presliding(laws: Sequence[str] | None = None) -> dict[str, np.ndarray]:
    """Columns {"t [s]", "x <law> [m]", "<state> <law> [unit]"...} of the slope's first 50 ms
    for every law with internal states."""
    import stickslip
    cols: dict[str, np.ndarray] = {}
    for _, law, _ in configs(belt=False, laws=laws):
        if stickslip.REGISTRY["law"][law]["n_states"] == 0:
            continue
        r, _ = simulate("slope", law, "dopri5", None, 0.05, 501, rtol=1e-10, atol=1e-15)
        cols["t [s]"] = r.t
        cols[f"x {law} [m]"] = r.x
        for label, z in zip(r.state_labels, r.y[2:]):
            name, unit = c.split_unit(label)
            cols[f"{name} {law} [{unit}]"] = z
    return cols


# --------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------
def run(outdir: str | Path, *, quick: bool = False, threads: int = 2, quiet: bool = False,
        laws: Sequence[str] | None = None, scheduler: str | None = None) -> list[Path]:
    """All four tables as CSV, a PNG each, and laws_compare.md, for every law (or `laws`).
    `quick` skips the h search. `scheduler` is accepted for the common study command line
    (c.study_main passes it) and unused: these runs are single simulations, always local."""
    outdir = Path(outdir)
    t0 = time.perf_counter()
    tables = {"slope": (SLOPE_HEADER, slope_rows(quiet, laws)), "belt": (BELT_HEADER, belt_rows(quiet, laws)),
              "rest": (REST_HEADER, rest_rows(quiet, laws))}
    if not quick:
        tables["hmax"] = (HMAX_HEADER, hmax_rows(quiet, laws))
    files: list[Path] = []
    md = [f"# Which friction law? (python -m cases.laws_compare; {time.perf_counter() - t0:.1f} s)\n"]
    for name, (header, rows) in tables.items():
        csv = c.write_csv(outdir / f"laws_compare_{name}.csv", header, rows)
        files += [csv, plot(csv, outdir)]
        md += [f"\n## {name}\n\n", c.markdown_table(header, rows)]
    cols = presliding(laws)
    if cols:
        csv = c.write_columns(outdir / "laws_compare_presliding.csv", cols)
        files += [csv, plot(csv, outdir)]
    files.append(c.write_text(outdir / "laws_compare.md", "".join(md)))
    c.log(f"laws_compare: {time.perf_counter() - t0:.1f} s", quiet)
    return files


#: What each CSV's figure shows: (column, log scale of its absolute value, y label, title).
FIGURES: dict[str, tuple[str, bool, str, str]] = {
    "slope": ("x_20 [m]", True, "distance slid |x(20 s)| [m] (truth: 0)",
              "Box on a 10° slope from rest: distance slid in 20 s"),
    "belt": ("err_x_max [m]", True, "|x_max - exact Coulomb x_max| [m]",
             "Belt, started stuck: error of the largest excursion"),
    "rest": ("rate_measured [1/s]", False, "growth rate of the oscillation [1/s]",
             "Belt from rest: growth rates"),
    "hmax": ("h_bounded [s]", True, "largest step h [s]",
             "Largest step h with a bounded motion"),
}


def series_name(tag: str) -> str:
    """A legend entry from a row's method (and step) or scene (and method): "rk4 h=0.001" ->
    "RK4, h = 0.001 s", "slope implicit_euler" -> "slope: implicit Euler"."""
    words = tag.split()
    if words and words[0] in c._style.SCENE_NAMES:
        return f"{words[0]}: {c._style.name(words[1]) if len(words) > 1 else 'RK4'}"
    text = c._style.name(words[0]) if words else tag
    return text + "".join(f", h = {w[2:]} s" for w in words[1:] if w.startswith("h="))


def legend_name(tag: str) -> str:
    """A method's legend entry without its step (the panel says "set-valued"; the legend says
    which step is hollow): "moreau h=0.001" -> "Moreau-Jean", "slope rk4" -> "RK4"."""
    words = tag.split()
    if words and words[0] in c._style.SCENE_NAMES:
        words = words[1:] or ["rk4"]
    return c._style.name(words[0]).removesuffix(" (set-valued)")


#: Width of the figures of runs grouped by law [in]; their fonts are scaled to stay legible at a
#: column width (harness.style.apply).
WIDTH: float = 6.4


def plot(csv: str | Path, outdir: str | Path) -> Path:
    """Render one laws_compare CSV grouped by law (PNG and PDF, from the CSV alone): a point per
    run on a log axis (a bar's length from an arbitrary baseline would mean nothing there), bars
    on a linear one; each method in its colour (harness.style), its second step hollow or
    hatched. A run that failed (status != 0, or no value) is marked with a cross at the foot of
    its place, a value of exactly 0 on a log axis with a circle there, a law a method has no row
    for (it refuses the law) with a grey dash; on a log axis of every method, a panel per family
    (FAMILIES), so that a law's group holds at most five points a panel."""
    csv = Path(csv)
    kind = csv.stem.removeprefix("laws_compare_")
    if kind == "presliding":
        data = c.read_numeric_csv(csv)
        names = list(data)
        # a panel per quantity and message: the body's position; the one bristle of each law
        # that has one; the elements of each law with several (generalized Maxwell-slip), in
        # line styles of the law's colour
        panels: dict[str, list[tuple[str, str, int | None]]] = {"x": []}
        for name in names[1:]:
            what, law = c.split_unit(name)[0].split()
            element = int(what[1:]) - 1 if what[1:].isdigit() else None
            key = "x" if what == "x" else "z" if element is None else law
            panels.setdefault(key, []).append((name, law, element))
        fig, _ = c.new_figure(1, nrows=len(panels), height=2.6 * len(panels) + 1.4, sharex=True)
        for a, (key, series) in zip(fig.axes, panels.items()):
            for name, law, element in series:
                # elements that stick move together: staggered markers keep each one visible
                marks = {} if element is None else {
                    "marker": "osv^"[element % 4], "markevery": (12 * element, 48), "ms": 4,
                    "mfc": "white"}
                a.plot(data[names[0]] * 1e3, data[name] * 1e6, color=c._style.color(law),
                       linestyle=c.VARIANT_STYLES[(element or 0) % len(c.VARIANT_STYLES)],
                       label=c._style.name(law) + ("" if element is None else f", element {element + 1}"),
                       **marks)
            a.set_title("position of the box" if key == "x" else "one bristle per law" if key == "z"
                        else f"{c._style.name(key)}: its elements")
            a.set_ylabel("position x [µm]" if key == "x" else "bristle deflection z [µm]")
        fig.axes[-1].set_xlabel("time t [ms]")
        fig.suptitle("Box on a 10° slope from rest: presliding")
        c.figure_legend(fig, fig.axes, ncol=2)
        return c.save_figure(fig, Path(outdir) / f"{csv.stem}.png")
    column, log, ylabel, title = FIGURES[kind]
    cols = c.read_csv(csv)
    laws = list(dict.fromkeys(cols["law [-]"]))
    second = "scene [-]" if kind == "hmax" else "method [-]"
    tags = [f"{m}" + (f" h={h}" if h else "")
            for m, h in zip(cols[second], cols.get("h [s]", [""] * len(cols[second])))]
    series = list(dict.fromkeys(tags))
    # a log figure of every method: a panel per family (per scene for "hmax"), so that a
    # law's group holds a few points a panel and no marker hides another
    if kind == "hmax":
        families = [(c._style.name(scene), [t for t in series if t.partition(" ")[0] == scene])
                    for scene in ("slope", "belt")]
    elif log:
        families = [(name, [t for t in series if t.partition(" h=")[0] in members])
                    for name, members in FAMILIES]
    else:
        families = [("", series)]
    families = [(name, group) for name, group in families if group]
    others = [t for t in series if not any(t in group for _, group in families)]
    if others:
        families.append(("other", others))
    c._style.apply(WIDTH)
    fig, axes = c.plt.subplots(len(families), 1, figsize=(WIDTH, 3.6 + 2.3 * max(len(families), 2)),
                               squeeze=False, sharex=True, sharey=True)
    lowest = math.inf                     # the smallest value drawn on a log axis
    marks = False
    for (family, members), ax in zip(families, axes[:, 0]):
        low, marked = _draw_group(ax, kind, log, cols, laws, tags, members, column)
        lowest, marks = min(lowest, low), marks or marked
        if family:
            ax.set_title(family, loc="left")
    # one y label, beside the panels (not beside the legend below them)
    middle = axes[len(families) // 2, 0]
    middle.set_ylabel(ylabel)
    if len(families) % 2 == 0:            # centred between the two middle panels
        middle.yaxis.set_label_coords(-0.14, 1.0 + 0.5 * fig.subplotpars.hspace)
    if kind == "hmax":                    # the step search's upper end: a value there is ">= cap"
        for ax in axes[:, 0]:
            ax.axhline(HMAX_CAP, color="0.4", linestyle=":", linewidth=0.9,
                       label=f"upper end of the search ({HMAX_CAP * 1e3:g} ms)")
        axes[0, 0].set_ylim(top=HMAX_CAP * 2.5)
    if log and marks and math.isfinite(lowest):   # the foot's marks below every value
        axes[0, 0].set_ylim(bottom=lowest / 8.0)
    if log:
        for ax in axes[:, 0]:
            c.log_ticks(ax, "y")

    axes[-1, 0].set_xticks(range(len(laws)))
    axes[-1, 0].set_xticklabels([tick_label(law) for law in laws], rotation=90)
    axes[-1, 0].set_xlim(-0.6, len(laws) - 0.4)
    if len(families) > 1:
        fig.suptitle(title)
    else:
        axes[0, 0].set_title(title)
    c.figure_legend(fig, axes[:, 0], ncol=3)
    return c.save_figure(fig, Path(outdir) / f"{csv.stem}.png")


#: The upper end of the largest-step search (largest_step's `hi`) [s].
HMAX_CAP: float = 1e-2
#: Tick labels of the laws, on one line each (two lines side by side would overlap their
#: neighbours at the printed size).
SHORT_NAMES: dict[str, str] = {"gms": "gen. Maxwell-slip"}


def tick_label(law: str) -> str:
    """A law's tick label on one line: "lugre sigma2=0" -> "LuGre, σ2 = 0"."""
    base, _, variant = law.partition(" ")
    name = SHORT_NAMES.get(base, c._style.name(base).split(" (")[0])
    return name + (", " + variant.replace("sigma", "σ").replace("=", " = ") if variant else "")


#: The panels of a log figure of laws_compare: the methods grouped by family.
FAMILIES: tuple[tuple[str, frozenset[str]], ...] = (
    ("explicit", frozenset({"rk4", "dopri5", "dop853"})),
    ("implicit", frozenset({"implicit_euler", "galpha", "radau5"})),
    ("set-valued (other laws refused)", frozenset({"moreau", "event_driven"})))


def _draw_group(ax: Any, kind: str, log: bool, cols: dict[str, list[str]], laws: list[str],
                tags: list[str], members: list[str], column: str) -> tuple[float, bool]:
    """Draw the series `members` of one laws_compare CSV on `ax`, grouped by law: points on a
    log axis, bars on a linear one; a cross at the foot for a failed run, a circle for exactly
    0 on a log axis, a grey dash for a law the method has no row for (refused or not run).
    Returns the smallest value drawn and whether any foot mark was drawn."""
    from matplotlib.transforms import blended_transform_factory
    foot = blended_transform_factory(ax.transData, ax.transAxes)
    width = 0.8 / max(len(members), 1)
    failed, zero, missing = [], [], []
    lowest = math.inf
    steps_drawn: dict[str, set[float]] = {"filled": set(), "hollow": set()}

    def bar_style(s: str, j: int) -> dict[str, Any]:
        """A method's own colour (harness.style), its second step hatched; on "hmax" (series
        "scene method") the method's colour too, the belt's marked by a square."""
        if kind == "hmax":
            method = s.partition(" ")[2] or "rk4"
            return {"color": c._style.METHOD_COLORS.get(method, "0.3"),
                    "marker": c._style.METHOD_MARKERS.get(method, "o")}
        method = s.partition(" h=")[0]
        if method not in c._style.METHOD_COLORS:
            return {"color": c._style.SEQUENCE[j % len(c._style.SEQUENCE)]}
        steps = [t for t in members if t.partition(" h=")[0] == method]
        return {"color": c._style.METHOD_COLORS[method], "edgecolor": "0.5", "linewidth": 0.3,
                "hatch": "////" if steps.index(s) > 0 else None,
                "marker": c._style.METHOD_MARKERS.get(method, "o")}

    for j, s in enumerate(members):
        xs, ys = [], []
        seen = set()
        for i, (law, tag) in enumerate(zip(cols["law [-]"], tags)):
            if tag != s:
                continue
            seen.add(law)
            x = laws.index(law) + (j - (len(members) - 1) / 2) * width
            status = cols.get("status [-]", ["0"] * len(tags))[i]
            if cols[column][i] == "" or status not in ("", "0") or (kind == "hmax" and float(cols[column][i]) == 0):
                failed.append(x)
                continue
            value = float(cols[column][i])
            if log and value == 0.0:
                zero.append(x)
                continue
            xs.append(x)
            ys.append(abs(value) if log else value)
        if kind != "hmax":
            missing += [laws.index(law) + (j - (len(members) - 1) / 2) * width
                        for law in laws if law not in seen]
        if log:                           # points: no bars on a log axis
            lowest = min([lowest, *ys])
            st = bar_style(s, j)
            # one legend entry a method (its second step hollow, explained once: STEP_NOTE)
            ax.plot(xs, ys, linestyle="none", marker=st.get("marker", "o"), markersize=5,
                    label="_" if st.get("hatch") else legend_name(s),
                    color=st["color"], markeredgewidth=1.0,
                    markerfacecolor="white" if st.get("hatch") else st["color"])
            if " h=" in s:
                steps_drawn["hollow" if st.get("hatch") else "filled"].add(float(s.partition(" h=")[2]))
        else:
            st = {k: v for k, v in bar_style(s, j).items() if k != "marker"}
            ax.bar(xs, ys, width=width, label=series_name(s), **st)
    if steps_drawn["hollow"]:             # which step is which, once
        for key, face in (("filled", "0.3"), ("hollow", "white")):
            hs = " or ".join(f"{h:g}" for h in sorted(steps_drawn[key], reverse=True))
            ax.plot([], [], "o", color="0.3", mfc=face, ms=5, label=f"{key}: h = {hs} s")
    if failed:
        ax.plot(failed, [0.04] * len(failed), "x", color="k", ms=6, mew=1.5, transform=foot,
                label="failed run" if kind != "hmax" else "no bounded step")
    if zero:
        ax.plot(zero, [0.04] * len(zero), "o", mfc="none", color="k", ms=6, transform=foot,
                label="exactly 0")
    if missing and log:
        ax.plot(missing, [0.04] * len(missing), "_", color="0.55", ms=6, mew=1.5, transform=foot,
                label="refused by the method")
    if kind == "rest":
        ax.plot(range(len(laws)), [float(v) for v in cols["rate_predicted [1/s]"]], "o",
                color="k", label="predicted: -g μ'(v_b)/2")
        ax.axhline(0.0, color="k", linewidth=0.6)
    if kind == "hmax":
        for j, s in enumerate(members):
            pts = [(laws.index(law) + (j - (len(members) - 1) / 2) * width, float(v))
                   for law, tag, v in zip(cols["law [-]"], tags, cols["h_1pct [s]"]) if tag == s and float(v) > 0]
            if pts:
                ax.plot(*zip(*pts), "_", color=bar_style(s, j)["color"], ms=9, mew=1.5,
                        label="within 1 % of the reference" if j == 0 else None)
    if log:
        ax.set_yscale("log")
        for i in range(len(laws) - 1):   # the groups' borders
            ax.axvline(i + 0.5, color="0.85", linewidth=0.6)
        ax.grid(axis="x", visible=False)
    return lowest, bool(failed or zero or (missing and log))


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.laws_compare [--outdir DIR] [--quick] [--quiet]."""
    return c.study_main("cases.laws_compare", __doc__, "skip the RK4 step search (a few seconds)",
                        run, argv)


if __name__ == "__main__":
    main()
