"""Den Hartog's forced oscillator with Coulomb friction, built as a `stickslip.Model` and run
with the event-driven method, against Den Hartog's closed form::

    python -m cases.gallery_denhartog --outdir out/            # about 30 s
    python -m cases.gallery_denhartog --outdir out/ --quick    # two friction ratios, about 15 s

The system (J. P. Den Hartog, "Forced vibrations with combined Coulomb and viscous friction",
Trans. ASME APM-53-9, 1931): a mass m on a spring k, on a floor with dry friction of force F
(mu_s = mu_k), driven by P0 cos(w t). With m = 1 kg, k = 1 N/m, P0 = 1 N the amplitude ratio
is X k / P0, beta = w / w_n the frequency ratio and r = F / P0 the friction ratio.

**Non-stop motion (closed form).** Den Hartog's steady motion without stops, one slip each way
per period: X k / P0 = sqrt(V^2 - r^2 U^2) with V = 1 / (1 - beta^2) and
U = tan(pi / (2 beta)) / beta (`amplitude`). It holds where its half-cycle moves one way
throughout and the mass does not stick at the turning point (net force k X beta^2 > F there):
`nonstop_valid` checks both on the closed-form path.

**Motion with stops.** Where those checks fail the mass stops twice per period. With one stop
per half period the motion is again in closed form within its slip (`stop_motion`): the mass
breaks away from -X when k X + P0 cos(theta) = F, slips for tau_s and stops at +X; the two
conditions x(tau_s) = X, x'(tau_s) = 0 are two equations in (theta, tau_s), solved by
scipy.optimize.fsolve. The stick fraction of the period is 1 - beta tau_s / pi (with w_n = 1).
The driver sets the event-driven run's stick fraction beside it and beside a converged
Moreau-Jean run (h = T / 2000, T the forcing period).

Each run starts from rest and lasts N_PERIODS forcing periods (N_PERIODS_LIGHT for
F/P0 < 0.2); amplitude and stick fraction are measured over the last N_AVG periods, and the
change from the N_AVG periods before says whether the transient has died out. The amplitude is
half the distance between the extreme turning points: the positions of the event-driven run's
reversal and stick events, which are exact (no output grid); the stick fraction is the time
between its stick and slip events. Writes ``denhartog.csv`` (one row per
(r, beta)), ``denhartog_curves.csv`` (the closed-form lines), ``denhartog_amplitude.md`` and
``denhartog_stops.md`` (the docs tables), ``denhartog_amplitude.png``/``.pdf`` (amplitude
ratio against frequency ratio: closed-form lines, simulated markers) and
``denhartog_regions.png``/``.pdf`` (the (beta, r) plane: where the closed form's non-stop
motion holds, and each run's stick fraction).
"""
from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import _common as c
from . import _gallery
from harness import style

#: Friction ratios F / P0 of the figure and the tables.
RATIOS: tuple[float, ...] = (0.1, 0.3, 0.5, 0.7)
QUICK_RATIOS: tuple[float, ...] = (0.3, 0.7)
#: Frequency ratios beta of the simulated markers (resonance, where the non-stop amplitude is
#: unbounded for r < pi / 4, is left out: near it the transient of light friction outlasts the runs).
BETAS: tuple[float, ...] = (0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1.3, 1.5, 2.0, 2.5, 3.0)
N_PERIODS: int = 60                   # forcing periods of each run ...
N_PERIODS_LIGHT: int = 150            # ... and with light friction (F/P0 < 0.2), whose transient lasts longer
N_AVG: int = 5                        # periods over which amplitude and stick are measured
RTOL: float = 1e-10                   # event_driven tolerances (atol = 1e-2 rtol)
MOREAU_STEPS: int = 2000              # Moreau-Jean steps per forcing period
BETA_LINE = np.linspace(0.15, 3.2, 1200)   # the closed-form lines

HEADER = ["r [-]", "beta [-]", "closed form X k/P0 [-]", "closed form holds [-]", "simulated X k/P0 [-]",
          "relative difference [-]", "settled change [-]", "stops per period [-]", "stick fraction [-]",
          "stick fraction moreau [-]", "stick fraction closed form [-]", "moreau h [s]", "cpu [s]"]


# --------------------------------------------------------------------------------------------
# Den Hartog's closed form
# --------------------------------------------------------------------------------------------
def amplitude(beta: float, r: float) -> float:
    """Den Hartog's non-stop amplitude ratio X k / P0 at frequency ratio `beta` and friction
    ratio `r` = F / P0 (NaN where V^2 < r^2 U^2: no such motion)."""
    v = 1.0 / (1.0 - beta ** 2)
    u = math.tan(math.pi / (2.0 * beta)) / beta
    d = v * v - (r * u) ** 2
    return math.sqrt(d) if d > 0.0 else math.nan


def _half_cycle(beta: float, r: float, x_amp: float, theta: float, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """x and x' of the upward slip from rest at -x_amp, forcing cos(beta tau + theta), m = k = 1."""
    v = 1.0 / (1.0 - beta ** 2)
    a = -x_amp + r - v * math.cos(theta)
    b = v * beta * math.sin(theta)
    x = a * np.cos(tau) + b * np.sin(tau) + v * np.cos(beta * tau + theta) - r
    xd = -a * np.sin(tau) + b * np.cos(tau) - v * beta * np.sin(beta * tau + theta)
    return x, xd


def nonstop_valid(beta: float, r: float) -> bool:
    """Whether Den Hartog's non-stop motion exists at (beta, r) and is the motion: its
    half-cycle moves one way throughout, and at the turning point the net force (k X beta^2)
    exceeds the friction force, so the mass does not stick."""
    x_amp = amplitude(beta, r)
    if not math.isfinite(x_amp):
        return False
    v = 1.0 / (1.0 - beta ** 2)
    # the phase at the start of the upward half-cycle: V cos(theta) = -X,
    # V beta sin(theta) = r tan(pi / (2 beta))
    theta = math.atan2(r * math.tan(math.pi / (2.0 * beta)) / (v * beta), -x_amp / v)
    tau = np.linspace(0.0, math.pi / beta, 2001)[1:-1]
    _, xd = _half_cycle(beta, r, x_amp, theta, tau)
    return bool(np.all(xd > 0.0)) and x_amp * beta ** 2 > r


def stop_motion(beta: float, r: float, guess: tuple[float, float]) -> dict[str, float] | None:
    """The motion with one stop per half period in closed form: breakaway phase theta and slip
    time tau_s from x(tau_s) = X, x'(tau_s) = 0 (fsolve from `guess` = (theta, tau_s)), with
    X = F/k - P0 cos(theta)/k; its amplitude ratio and stick fraction 1 - beta tau_s / pi.
    None when the solution fails its checks (converged, one-way slip, the stop holds, the mass
    stays stuck until the symmetric breakaway)."""
    from scipy.optimize import fsolve

    def eqs(p: np.ndarray) -> list[float]:
        theta, ts = p
        x_amp = r - math.cos(theta)
        x, xd = _half_cycle(beta, r, x_amp, theta, np.array([ts]))
        return [x[0] - x_amp, xd[0]]
    sol, info, ok, _ = fsolve(eqs, np.asarray(guess, dtype=float), full_output=True, xtol=1e-13)
    theta, ts = float(sol[0]), float(sol[1])
    x_amp = r - math.cos(theta)
    if ok != 1 or max(abs(e) for e in eqs(sol)) > 1e-10 or not (0.0 < ts < math.pi / beta) or x_amp <= 0.0:
        return None
    tau = np.linspace(0.0, ts, 2001)[1:-1]
    _, xd = _half_cycle(beta, r, x_amp, theta, tau)
    # stuck at +X from phase theta + beta ts to theta + pi: |-X + cos(phase)| <= r throughout
    phases = np.linspace(theta + beta * ts, theta + math.pi, 2001)
    held = np.all(np.abs(-x_amp + np.cos(phases)) <= r * (1.0 + 1e-9))
    if not (np.all(xd > 0.0) and held and math.sin(theta) < 0.0):
        return None
    return {"theta": theta, "tau_s": ts, "amplitude": x_amp, "stick_fraction": 1.0 - beta * ts / math.pi}


# --------------------------------------------------------------------------------------------
# Simulation
# --------------------------------------------------------------------------------------------
def model(beta: float, r: float) -> Any:
    """The oscillator as a stickslip.Model: m = 1 kg, k = 1 N/m, P0 cos(beta t) with P0 = 1 N,
    Coulomb friction F = r P0 (mu_s = mu_k = 1 on a normal force r)."""
    import stickslip as ss
    m = ss.Model()
    b = m.add_body(1.0, name="mass")
    m.add_spring(b, None, k=1.0)
    m.add_force(b, ss.signal.sine(1.0, beta / (2.0 * math.pi), math.pi / 2.0))   # cos(beta t)
    m.add_contact(b, None, "coulomb", normal_force=r, mu_s=1.0, mu_k=1.0)
    return m


def _stick_intervals(events: list[dict[str, Any]], t0: float, t1: float) -> tuple[float, int]:
    """Total stick time within [t0, t1] and the number of stops that begin there, from the
    event-driven run's events (a stick event to the next slip event)."""
    total, stops, since = 0.0, 0, None
    for e in events:
        if e["kind"] == "stick":
            since = e["t"]
            if t0 <= e["t"] <= t1:
                stops += 1
        elif e["kind"] == "slip" and since is not None:
            total += max(0.0, min(e["t"], t1) - max(since, t0))
            since = None
    if since is not None:
        total += max(0.0, t1 - max(since, t0))
    return total, stops


def simulate_point(beta: float, r: float) -> dict[str, Any]:
    """Event-driven run at (beta, r) from rest: amplitude, its change over the last two windows,
    stops and stick fraction per period; where it stops, the Moreau-Jean run and the closed form
    with stops beside it."""
    import stickslip as ss
    period = 2.0 * math.pi / beta
    n_periods = N_PERIODS_LIGHT if r < 0.2 else N_PERIODS
    t_end = n_periods * period
    t0 = time.process_time()
    res = ss.simulate(model(beta, r), method="event_driven", t_end=t_end, n_out=n_periods + 1,
                      rtol=RTOL, atol=1e-2 * RTOL)
    cpu = time.process_time() - t0
    turning = [(e["t"], e["x"]) for e in res.events if e["kind"] in ("reversal", "stick")]

    def half_range(t0: float, t1: float) -> float:
        xs = [x for t, x in turning if t0 <= t <= t1]
        return 0.5 * (max(xs) - min(xs)) if xs else 0.0
    amp = half_range(t_end - N_AVG * period, t_end)
    settled = abs(amp - half_range(t_end - 2 * N_AVG * period, t_end - N_AVG * period)) / amp if amp else math.inf
    stick, stops = _stick_intervals(res.events, t_end - N_AVG * period, t_end)
    out = {"beta": beta, "r": r, "amplitude": amp, "settled": settled, "stops": stops / N_AVG,
           "stick_fraction": stick / (N_AVG * period), "cpu": cpu, "moreau": None, "closed_stop": None,
           "moreau_h": None}
    if stops:
        h = period / MOREAU_STEPS
        rm = ss.simulate(model(beta, r), method="moreau", h=h, t_end=t_end, n_out=n_periods * MOREAU_STEPS + 1)
        sel = rm.t >= t_end - N_AVG * period - 1e-9
        out["moreau"] = float(np.mean(rm.v[0][sel] == 0.0))
        out["moreau_h"] = h
        if stops == 2 * N_AVG:         # one stop per half period: the closed form with stops
            # the guess: the last breakaway upwards (a slip event from the lowest position)
            ups = [e["t"] for e in res.events
                   if e["kind"] == "slip" and e["t"] > t_end - 2 * period and e["x"] < 0.0]
            if ups:
                s0 = ups[0]
                nxt = [e["t"] for e in res.events if e["kind"] == "stick" and e["t"] > s0]
                if nxt:
                    # started 0.1 rad and 10 % away, so that fsolve converges on its own
                    out["closed_stop"] = stop_motion(beta, r, ((beta * s0) % (2 * math.pi) + 0.1, 0.9 * (nxt[0] - s0)))
    return out


def run(outdir: str | Path, *, quick: bool = False, threads: int = 1, quiet: bool = False) -> list[Path]:
    """Simulate the grid, write the CSV files, tables and figures. The runs are serial (each
    takes milliseconds): `threads` is accepted for `python -m cases` and not used."""
    outdir = Path(outdir)
    ratios = QUICK_RATIOS if quick else RATIOS
    start = time.perf_counter()
    rows = []
    for r in ratios:
        for beta in BETAS:
            p = simulate_point(beta, r)
            cf = amplitude(beta, r)
            valid = nonstop_valid(beta, r)
            cs = p["closed_stop"]
            rows.append([r, beta, cf, int(valid), p["amplitude"],
                         (p["amplitude"] - cf) / cf if valid else None, p["settled"], p["stops"],
                         p["stick_fraction"], p["moreau"], None if cs is None else cs["stick_fraction"],
                         p["moreau_h"], p["cpu"]])
    c.log(f"cases.gallery_denhartog: {len(rows)} runs, {time.perf_counter() - start:.1f} s", quiet)
    files = [c.write_csv(outdir / "denhartog.csv", HEADER, rows)]
    curves = {"beta [-]": BETA_LINE}
    for r in ratios:
        curves[f"X k/P0 r={r:g} [-]"] = np.array([amplitude(b, r) for b in BETA_LINE])
        curves[f"holds r={r:g} [-]"] = np.array([float(nonstop_valid(b, r)) for b in BETA_LINE])
    files.append(c.write_columns(outdir / "denhartog_curves.csv", curves))
    files += tables(outdir)
    files += plot(outdir)
    return files


# --------------------------------------------------------------------------------------------
# Tables and figures (from the CSV files alone)
# --------------------------------------------------------------------------------------------
def _rows(path: Path) -> list[dict[str, float | None]]:
    cols = c.read_csv(path)
    return [{k: (float(v) if v != "" else None) for k, v in zip(cols, vals)} for vals in zip(*cols.values())]


def _below(value: float, floor: float) -> str:
    """`value` as 1.2e-05, or '< floor' under it (the CSV keeps 10 significant digits)."""
    return f"< {floor:.0e}" if value < floor else f"{value:.1e}"


def tables(outdir: Path) -> list[Path]:
    """denhartog_amplitude.md (the non-stop points: closed form against event-driven) and
    denhartog_stops.md (the points with stops: stick fraction three ways)."""
    rows = _rows(outdir / "denhartog.csv")
    nonstop = [r for r in rows if r["closed form holds [-]"] == 1.0]
    body = [[f"{r['r [-]']:g}", f"{r['beta [-]']:g}", f"{r['closed form X k/P0 [-]']:.5f}",
             f"{r['simulated X k/P0 [-]']:.5f}", f"{r['relative difference [-]']:.1e}",
             f"{r['settled change [-]']:.0e}", f"{r['stops per period [-]']:g}"] for r in nonstop]
    both = [r for r in nonstop if not r["stops per period [-]"]]
    worst = max(abs(r["relative difference [-]"]) for r in both) if both else math.nan
    amp = (c.markdown_table(["F/P0", "beta", "X k/P0 closed form", "X k/P0 event-driven", "relative difference",
                             "change over the 5 periods before", "stops per period (event-driven)"], body)
           + f"\nLargest relative difference over the {len(both)} points where the closed form holds and the "
           f"event-driven run has no stops: {worst:.1e}.\n")
    stops = [r for r in rows if r["stops per period [-]"]]
    body = []
    for r in stops:
        cf = r["stick fraction closed form [-]"]
        body.append([f"{r['r [-]']:g}", f"{r['beta [-]']:g}", f"{r['stops per period [-]']:g}",
                     f"{r['stick fraction [-]']:.5f}", f"{r['stick fraction moreau [-]']:.5f}",
                     "" if cf is None else f"{cf:.5f}",
                     "" if cf is None else _below(abs(r['stick fraction [-]'] - cf), 1e-9),
                     f"{r['simulated X k/P0 [-]']:.4f}"])
    st = c.markdown_table(["F/P0", "beta", "stops per period", "stick fraction event-driven",
                           "stick fraction Moreau-Jean", "stick fraction closed form", "|event-driven - closed form|",
                           "X k/P0 event-driven"], body)
    return [c.write_text(outdir / "denhartog_amplitude.md", amp), c.write_text(outdir / "denhartog_stops.md", st)]


def plot(outdir: Path) -> list[Path]:
    """denhartog_amplitude.png/.pdf and denhartog_regions.png/.pdf."""
    import matplotlib.pyplot as plt
    rows = _rows(outdir / "denhartog.csv")
    cur = c.read_numeric_csv(outdir / "denhartog_curves.csv")
    ratios = list(dict.fromkeys(r["r [-]"] for r in rows))
    fig, ax = _gallery.figure(4.4, layout="constrained")
    for i, r in enumerate(ratios):
        col = style.SEQUENCE[i]
        y = cur[f"X k/P0 r={r:g} [-]"]
        ok = cur[f"holds r={r:g} [-]"] == 1.0
        ax.plot(cur["beta [-]"], np.where(ok, y, np.nan), color=col, lw=1.1, label=f"F/P0 = {r:g}")
        # not the motion: dotted, above beta = 0.45 only (below, tan(pi / (2 beta)) has poles)
        ax.plot(cur["beta [-]"], np.where(ok | (cur["beta [-]"] < 0.45), np.nan, y), color=col, lw=0.8, ls=":")
        mine = [p for p in rows if p["r [-]"] == r]
        for p in mine:
            stop = bool(p["stops per period [-]"])
            ax.plot(p["beta [-]"], p["simulated X k/P0 [-]"], "o" if not stop else "s", ms=3.5, color=col,
                    mfc=col if not stop else "white", mew=0.9)
    lines, _ = ax.get_legend_handles_labels()
    lines.append(plt.Line2D([], [], color="k", lw=0.8, ls=":", label="not the motion"))
    # the legends below the axes, where they cover no data
    fig.legend(handles=lines, loc="outside lower left", handlelength=1.4, title="closed form", frameon=False)
    marks = [plt.Line2D([], [], color="k", marker="o", ms=3.5, ls="none", label="no stops"),
             plt.Line2D([], [], color="k", marker="s", ms=3.5, mfc="white", ls="none", label="with stops")]
    fig.legend(handles=marks, loc="outside lower right", title="event-driven", handlelength=1.4, frameon=False)
    ax.set_yscale("log")
    ax.set_ylim(0.02, 30.0)
    ax.set_xlim(0.15, 3.2)
    ax.set_xlabel("frequency ratio ω/ω$_n$ [-]")
    ax.set_ylabel("amplitude ratio X k/P$_0$ [-]")
    files = [_gallery.save(fig, outdir / "denhartog_amplitude.png")]
    # the (beta, r) plane
    fig, ax = _gallery.figure(3.8, layout="constrained")
    bb = np.linspace(0.15, 3.2, 160)
    rr = np.linspace(0.01, 1.0, 100)
    holds = np.array([[nonstop_valid(b, r) for b in bb] for r in rr])
    ax.contourf(bb, rr, holds.astype(float), levels=[-0.5, 0.5, 1.5], colors=["0.85", "white"])
    ax.contour(bb, rr, holds.astype(float), levels=[0.5], colors="0.3", linewidths=0.8)
    stop = [p for p in rows if p["stops per period [-]"]]
    free = [p for p in rows if not p["stops per period [-]"]]
    ax.plot([p["beta [-]"] for p in free], [p["r [-]"] for p in free], "o", color=style.SEQUENCE[0], ms=3.5,
            label="event-driven: no stops")
    sc = ax.scatter([p["beta [-]"] for p in stop], [p["r [-]"] for p in stop],
                    c=[p["stick fraction [-]"] for p in stop], cmap="viridis", vmin=0.0, vmax=0.6, marker="s",
                    s=16, edgecolors="k", linewidths=0.4, label="event-driven: stops", zorder=3)
    fig.colorbar(sc, ax=ax, label="stick fraction of the period [-]", pad=0.02)
    ax.set_xlabel("frequency ratio ω/ω$_n$ [-]")
    ax.set_ylabel("friction ratio F/P$_0$ [-]")
    ax.set_ylim(0.0, 1.0)
    from matplotlib.patches import Patch
    handles, _ = ax.get_legend_handles_labels()
    handles.append(Patch(facecolor="0.85", edgecolor="0.3", label="non-stop closed form fails"))
    fig.legend(handles=handles, loc="outside lower center", frameon=False)
    files.append(_gallery.save(fig, outdir / "denhartog_regions.png"))
    return files


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.gallery_denhartog [--outdir DIR] [--quick] [--threads N] [--quiet]."""
    return c.study_main("cases.gallery_denhartog", __doc__, "two friction ratios (0.3 and 0.7)", run, argv)


if __name__ == "__main__":
    main()
