"""Gallery: steady states found directly (stickslip.periodic_orbit, continuation,
frequency_response, harmonic_balance) against closed forms (docs/gallery/steady-states.md)::

    python -m cases.gallery_steady --outdir out/            # about 20 s
    python -m cases.gallery_steady --outdir out/ --quick    # fewer points, about 8 s

Four systems:

**(a) The paper's belt** (m = 10 kg, k = 300 N/m, set-valued Coulomb, mu_s = 0.35,
mu_k = 0.3), its stick-slip cycle continued in the belt speed v_b by `continuation`, against
the closed form: a slip arc of amplitude A = hypot((mu_s - mu_k) m g / k, v_b / w) about
mu_k m g / k, then a stick phase carried by the belt over 2 (mu_s - mu_k) m g / k; period
(pi + 2 asin(v_b / (A w))) / w + 2 (mu_s - mu_k) m g / (k v_b), w = sqrt(k / m)
(`belt_closed_form`). Writes ``steady_belt.csv``.

**(b) Den Hartog's forced oscillator** (cases.gallery_denhartog's model, m = k = P0 = 1,
Coulomb friction F = r P0) by `frequency_response` below and above resonance, against his
non-stop closed form (`gallery_denhartog.amplitude`, where `gallery_denhartog.nonstop_valid`)
and, where the mass stops once each half period, the closed form with stops
(`gallery_denhartog.stop_motion`: the stick fraction). Writes ``steady_denhartog.csv`` and
``steady_denhartog_curves.csv`` (the closed-form lines).

**(c) The onset of stick-slip**: the paper's belt at v_b = 0.1 m/s with a falling set-valued
Stribeck law (mu_s = 0.4, mu_k = 0.3, v_s = 0.1 m/s, delta = 2) and a damper c to the wall.
Steady sliding is stable where c + N mu'(v_b) > 0 (N = m g): the linearisation's Hopf point is
c_H = -N mu'(v_b) (`hopf_linear`). The cycle born there is continued in c from 0.8 c_H up until
it shrinks to nothing; the branch's Hopf point is where the squared amplitude, linear in c
near a Hopf point, extrapolates to zero from the last two points with an amplitude above
HOPF_FLOOR. Writes ``steady_hopf.csv`` (the branch) and ``steady_hopf_point.csv`` (both Hopf
points, and the period there against 2 pi sqrt(m / k)).

**(d) A friction damper's response**: a forced mass-spring-damper (m = 1 kg, k = 4 N/m,
c = 0.4 N s/m, 10 N sin(2 pi f t)) with the regularised `proposed` law (N = 9.81 N,
mu_s = 0.4, mu_k = 0.3, v_s = 0.5 m/s) across the resonance, by shooting (`frequency_response`
with DOPRI5) and by harmonic balance (`harmonic_balance`) at HARMONICS harmonics, each
frequency started from the previous one's solution (time instants per period: `samples`). Writes ``steady_damper.csv``.

Figures (drawn from the CSV files alone by `plot`): ``steady_belt.png``,
``steady_denhartog.png``, ``steady_hopf.png``, ``steady_damper.png`` (each with a PDF copy).
"""
from __future__ import annotations

import math
import time
import warnings
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from harness import style

from . import _common as c
from . import _gallery
from . import gallery_denhartog as dh

G: float = 9.81
#: (a) The paper's belt (Table 1 of Yoo & Lee 2008) and the belt speeds of the branch.
BELT: dict[str, float] = dict(m=10.0, k=300.0, g=G, mu_s=0.35, mu_k=0.3)
V_B_RANGE: tuple[float, float] = (0.2, 2.0)
#: The branch's first arclength step. With continuation's default (0.02) the first step, which
#: has no guard against jumping (its tangent is v_b's axis), lands on one of the neutral
#: pure-slip orbits around steady sliding (no stick, multiplier 1) at v_b = 0.236 m/s.
BELT_STEP: float = 0.01
#: (b) Friction ratios F / P0, and frequency ratios below and above resonance.
RATIOS: tuple[float, ...] = (0.3, 0.5, 0.7)
QUICK_RATIOS: tuple[float, ...] = (0.5,)
BETAS_BELOW = np.round(np.linspace(0.3, 0.9, 13), 6)
BETAS_ABOVE = np.round(np.linspace(1.2, 3.0, 13), 6)
BETA_LINE = np.linspace(0.25, 3.05, 1200)
#: (c) The damped belt with a falling Stribeck law.
HOPF_VB: float = 0.1
HOPF_LAW: dict[str, float] = dict(mu_s=0.4, mu_k=0.3, v_s=0.1, delta=2.0)
HOPF_START: float = 0.8              # the branch starts at 0.8 c_H
HOPF_FLOOR: float = 1e-4             # [m]: smaller cycles are steady sliding (the branch's end)
#: (d) The friction damper.
DAMPER: dict[str, float] = dict(m=1.0, k=4.0, c=0.4, force=10.0, normal_force=G, mu_s=0.4, mu_k=0.3, v_s=0.5)
FREQUENCIES = np.round(np.linspace(0.15, 0.6, 16), 6)
HARMONICS: tuple[int, ...] = (1, 3, 9, 27)
QUICK_HARMONICS: tuple[int, ...] = (1, 3, 9)


def samples(h: int) -> int:
    """Instants per period of harmonic balance's time-domain evaluation with `h` harmonics:
    max(256, 16 (h + 1)). With harmonic_balance's default (4 (h + 1) + 1, at least 64) Newton's
    method stalled on this damper at 9 harmonics (0.21 Hz) and 27 (0.45 Hz), its residual 1e-8
    to 1e-3 N, most likely on the aliased higher harmonics of the friction force's steep turn."""
    return max(256, 16 * (h + 1))


# --------------------------------------------------------------------------------------------
# (a) The belt
# --------------------------------------------------------------------------------------------
def belt(v_b: float) -> Any:
    """The paper's belt at belt speed `v_b` [m/s] with set-valued Coulomb, started stuck."""
    import stickslip as ss
    return ss.Model.from_scene("belt", "coulomb", v_b=v_b, v0=v_b, **BELT)


def belt_closed_form(v_b: float) -> tuple[float, float]:
    """(period [s], amplitude [m]) of the belt's stick-slip cycle with Coulomb's law."""
    w = math.sqrt(BELT["k"] / BELT["m"])
    dx = (BELT["mu_s"] - BELT["mu_k"]) * BELT["m"] * BELT["g"] / BELT["k"]
    amp = math.hypot(dx, v_b / w)
    return (math.pi + 2.0 * math.asin(v_b / (amp * w))) / w + 2.0 * dx / v_b, amp


def belt_rows() -> tuple[list[list[Any]], str, float]:
    """The branch in v_b: rows of steady_belt.csv (the branch's CPU time repeated on each), its
    stop reason and CPU time."""
    import stickslip as ss
    t0 = time.process_time()
    br = ss.continuation(belt, *V_B_RANGE, step=BELT_STEP)
    cpu = time.process_time() - t0
    rows = []
    for p, period, amp, orb in zip(br.p, br.period, br.amplitude, br.orbits):
        t_cf, a_cf = belt_closed_form(float(p))
        rows.append([float(p), float(period), t_cf, abs(period / t_cf - 1.0), float(amp), a_cf, abs(amp / a_cf - 1.0),
                     float(np.max(np.abs(orb.nontrivial))), float(orb.stick_fraction[0]), int(orb.stable), cpu])
    return rows, br.stop_reason, cpu


BELT_HEADER = ["v_b [m/s]", "period [s]", "period closed form [s]", "period abs relative error [-]",
               "amplitude [m]", "amplitude closed form [m]", "amplitude abs relative error [-]",
               "nontrivial multiplier [-]", "stick fraction [-]", "stable [-]", "cpu [s]"]


# --------------------------------------------------------------------------------------------
# (b) Den Hartog
# --------------------------------------------------------------------------------------------
def _stop_closed_form(beta: float, r: float, orb: Any) -> float | None:
    """The stick fraction of Den Hartog's motion with one stop per half period
    (gallery_denhartog.stop_motion), started 0.1 rad and 10 % away from the orbit's upward
    breakaway and slip time; None where it has no such solution."""
    period = 2.0 * math.pi / beta
    ev = [(float(e["t"]), str(e["kind"]), float(e["x"])) for e in orb.events]
    ups = [t for t, kind, x in ev if kind == "slip" and x < 0.0]
    if not ups:
        return None
    s0 = ups[0]
    after = [t if t > s0 else t + period for t, kind, _ in ev if kind == "stick"]
    if not after:
        return None
    cs = dh.stop_motion(beta, r, ((beta * s0) % (2.0 * math.pi) + 0.1, 0.9 * (min(after) - s0)))
    return None if cs is None else cs["stick_fraction"]


def denhartog_rows(ratios: Sequence[float], betas: Sequence[np.ndarray]) -> list[list[Any]]:
    """One row per (r, beta): the response curve's amplitude, stick fraction, stability and
    stops, beside Den Hartog's closed forms."""
    import stickslip as ss
    rows = []
    for r in ratios:
        for part in betas:
            t0 = time.process_time()
            resp = ss.frequency_response(lambda f, r=r: dh.model(2.0 * math.pi * f, r), part / (2.0 * math.pi),
                                         follow=False)
            cpu = (time.process_time() - t0) / len(part)
            for beta, amp, orb in zip(part, resp.amplitude, resp.orbits):
                beta = float(beta)
                cf, valid = dh.amplitude(beta, r), dh.nonstop_valid(beta, r)
                stops = int(sum(1 for e in orb.events if e["kind"] == "stick"))
                stick = float(orb.stick_fraction[0])
                cs = _stop_closed_form(beta, r, orb) if stops == 2 else None
                rows.append([r, beta, float(amp), cf if math.isfinite(cf) else None, int(valid),
                             abs(float(amp) / cf - 1.0) if valid else None, stops, stick, cs,
                             abs(stick - cs) if cs is not None else None, int(orb.stable), cpu])
    return rows


DH_HEADER = ["r [-]", "beta [-]", "X k/P0 [-]", "closed form X k/P0 [-]", "closed form holds [-]",
             "abs relative difference [-]", "stops per period [-]", "stick fraction [-]",
             "stick fraction closed form [-]", "stick fraction difference [-]", "stable [-]", "cpu per point [s]"]


# --------------------------------------------------------------------------------------------
# (c) The Hopf point
# --------------------------------------------------------------------------------------------
def damped_belt(c_damp: float) -> Any:
    """The paper's belt at v_b = HOPF_VB [m/s] with the falling Stribeck law and a damper
    `c_damp` [N s/m] to the wall, started sliding at rest."""
    import stickslip as ss
    m = ss.Model.from_scene("belt", "stribeck", v_b=HOPF_VB, v0=HOPF_VB, m=BELT["m"], k=BELT["k"], g=G, **HOPF_LAW)
    m.add_damper(0, None, c_damp)
    return m


def hopf_linear() -> tuple[float, float]:
    """(c_H [N s/m], x of steady sliding [m]): c_H = -N mu'(v_b) from the law's slope (central
    difference, step 1e-6 m/s), N = m g."""
    import stickslip as ss
    n = BELT["m"] * G
    mu = ss.friction_coefficient("stribeck", np.array([HOPF_VB - 1e-6, HOPF_VB, HOPF_VB + 1e-6]), **HOPF_LAW)
    return float(-n * (mu[2] - mu[0]) / 2e-6), float(n * mu[1] / BELT["k"])


def hopf_rows(quick: bool) -> tuple[list[list[Any]], list[Any], str]:
    """The branch of cycles in c (rows of steady_hopf.csv), the Hopf point's row
    (steady_hopf_point.csv) and the branch's stop reason."""
    import stickslip as ss
    c_h, x_slide = hopf_linear()
    t0 = time.process_time()
    w = math.sqrt(BELT["k"] / BELT["m"])
    with warnings.catch_warnings():     # where the cycle has shrunk to steady sliding (the branch's end)
        warnings.simplefilter("ignore", ss.MonodromyWarning)
        start = ss.periodic_orbit(damped_belt(HOPF_START * c_h), guess=[x_slide + 0.02, 0.0, 2.0 * math.pi / w])
        br = ss.continuation(damped_belt, HOPF_START * c_h, 1.05 * c_h, guess=start, step=0.2 if quick else 0.1,
                             max_step=0.2, max_points=30)
    cpu = time.process_time() - t0
    rows = [[float(p), float(p) / c_h, float(a), float(t), float(np.max(np.abs(o.nontrivial))), int(o.stable)]
            for p, a, t, o in zip(br.p, br.amplitude, br.period, br.orbits)]
    cycles = [row for row in rows if row[2] > HOPF_FLOOR]
    (c1, _, a1, t1, *_), (c2, _, a2, t2, *_) = cycles[-2], cycles[-1]
    c_branch = c2 + (c2 - c1) * a2 ** 2 / (a1 ** 2 - a2 ** 2)      # a^2 linear in c, zero at c_H
    t_branch = t2 + (t2 - t1) * (c_branch - c2) / (c2 - c1)
    point = ["belt", c_h, c_branch, c_branch / c_h - 1.0, t_branch, 2.0 * math.pi / w, len(rows), cpu]
    return rows, point, br.stop_reason


HOPF_HEADER = ["c [N s/m]", "c/c_H [-]", "amplitude [m]", "period [s]", "nontrivial multiplier [-]", "stable [-]"]
POINT_HEADER = ["system [-]", "c_H linearisation [N s/m]", "c_H branch [N s/m]", "relative difference [-]",
                "period at c_H branch [s]", "2 pi sqrt(m/k) [s]", "points [-]", "cpu [s]"]


# --------------------------------------------------------------------------------------------
# (d) The friction damper
# --------------------------------------------------------------------------------------------
def damper(f: float) -> Any:
    """The friction-damped oscillator forced at `f` [Hz]."""
    import stickslip as ss
    d = DAMPER
    m = ss.Model()
    b = m.add_body(d["m"], name="mass")
    m.add_spring(b, None, k=d["k"])
    m.add_damper(b, None, d["c"])
    m.add_force(b, ss.signal.sine(d["force"], f))
    m.add_contact(b, None, "proposed", normal_force=d["normal_force"], mu_s=d["mu_s"], mu_k=d["mu_k"], v_s=d["v_s"])
    return m


def damper_rows(freqs: np.ndarray, harmonics: Sequence[int]) -> tuple[list[str], list[list[Any]]]:
    """Header and rows of steady_damper.csv: per frequency the shooting amplitude and, per
    number of harmonics, harmonic balance's amplitude and its relative difference from
    shooting's; the CPU time of each method over the whole curve (columns `... cpu [s]`: the
    curve's total, repeated on every row)."""
    import stickslip as ss
    from stickslip.harmonic import harmonic_balance
    t0 = time.process_time()
    resp = ss.frequency_response(damper, freqs, method="dopri5", follow=False)
    cpu_shoot = time.process_time() - t0
    amps = {}
    cpus = {}
    for h in harmonics:
        t0, prev, out = time.process_time(), None, []
        for f in freqs:
            prev = harmonic_balance(damper(float(f)), h, guess=prev, n_samples=samples(h))
            out.append(float(prev.amplitude[0]))
        cpus[h], amps[h] = time.process_time() - t0, np.array(out)
    header = ["f [Hz]", "shooting amplitude [m]", "shooting stable [-]", "shooting cpu [s]"]
    for h in harmonics:
        header += [f"HB{h} amplitude [m]", f"HB{h} abs relative difference [-]", f"HB{h} cpu [s]"]
    rows = []
    for i, f in enumerate(freqs):
        row: list[Any] = [float(f), float(resp.amplitude[i]), int(resp.stable[i]), cpu_shoot]
        for h in harmonics:
            row += [amps[h][i], abs(amps[h][i] / resp.amplitude[i] - 1.0), cpus[h]]
        rows.append(row)
    return header, rows


# --------------------------------------------------------------------------------------------
# The run
# --------------------------------------------------------------------------------------------
def run(outdir: str | Path, *, quick: bool = False, threads: int = 1, quiet: bool = False) -> list[Path]:
    """Compute the four systems and write the CSV files and figures (`threads` is accepted
    for `python -m cases` and not used: each part is serial)."""
    outdir = Path(outdir)
    files = []
    start = time.perf_counter()
    rows, reason, cpu = belt_rows()
    c.log(f"cases.gallery_steady: belt branch, {len(rows)} points in {cpu:.2f} s CPU ({reason})", quiet)
    files.append(c.write_csv(outdir / "steady_belt.csv", BELT_HEADER, rows))
    ratios = QUICK_RATIOS if quick else RATIOS
    betas = (BETAS_BELOW[::2], BETAS_ABOVE[::2]) if quick else (BETAS_BELOW, BETAS_ABOVE)
    rows = denhartog_rows(ratios, betas)
    c.log(f"cases.gallery_steady: Den Hartog, {len(rows)} orbits", quiet)
    files.append(c.write_csv(outdir / "steady_denhartog.csv", DH_HEADER, rows))
    curves = {"beta [-]": BETA_LINE}
    for r in ratios:
        curves[f"X k/P0 r={r:g} [-]"] = np.array([dh.amplitude(b, r) for b in BETA_LINE])
        curves[f"holds r={r:g} [-]"] = np.array([float(dh.nonstop_valid(b, r)) for b in BETA_LINE])
    files.append(c.write_columns(outdir / "steady_denhartog_curves.csv", curves))
    rows, point, reason = hopf_rows(quick)
    c.log(f"cases.gallery_steady: Hopf branch, {len(rows)} points ({reason}); c_H {point[1]:.6g} (linear), "
          f"{point[2]:.6g} (branch)", quiet)
    files.append(c.write_csv(outdir / "steady_hopf.csv", HOPF_HEADER, rows))
    files.append(c.write_csv(outdir / "steady_hopf_point.csv", POINT_HEADER, [point]))
    header, rows = damper_rows(FREQUENCIES[::2] if quick else FREQUENCIES, QUICK_HARMONICS if quick else HARMONICS)
    files.append(c.write_csv(outdir / "steady_damper.csv", header, rows))
    c.log(f"cases.gallery_steady: done in {time.perf_counter() - start:.1f} s", quiet)
    files += plot(outdir)
    return files


# --------------------------------------------------------------------------------------------
# Figures (from the CSV files alone)
# --------------------------------------------------------------------------------------------
def _numeric(path: Path) -> dict[str, np.ndarray]:
    """A CSV's columns as floats, an empty cell (no value) as NaN."""
    return {k: np.array([float(x) if x != "" else math.nan for x in v]) for k, v in c.read_csv(path).items()}


def plot(outdir: Path) -> list[Path]:
    """steady_belt.png, steady_denhartog.png, steady_hopf.png and steady_damper.png (and
    PDFs) from the CSV files in `outdir`."""
    return [plot_belt(outdir), plot_denhartog(outdir), plot_hopf(outdir), plot_damper(outdir)]


def plot_belt(outdir: Path) -> Path:
    """Period and amplitude of the belt's cycle against v_b: closed form (lines) and the
    continuation's points (markers)."""
    d = c.read_numeric_csv(outdir / "steady_belt.csv")
    fig, top, bottom = _gallery.two_panels(4.6, sharex=True)
    v = np.linspace(d["v_b [m/s]"].min(), d["v_b [m/s]"].max(), 400)
    cf = np.array([belt_closed_form(x) for x in v])
    for ax, col, k, label in ((top, "period [s]", 0, "period T [s]"), (bottom, "amplitude [m]", 1, "amplitude A [m]")):
        ax.plot(v, cf[:, k], color=style.SEQUENCE[0], lw=1.1, label="closed form")
        ax.plot(d["v_b [m/s]"], d[col], "o", ms=3.5, mfc="white", color=style.SEQUENCE[1], mew=0.9,
                label="continuation")
        ax.set_ylabel(label)
    bottom.set_xlabel("belt speed v$_b$ [m/s]")
    top.legend(loc="upper right")
    return _gallery.save(fig, outdir / "steady_belt.png")


def plot_denhartog(outdir: Path) -> Path:
    """Amplitude ratio against frequency ratio (closed form lines, frequency_response markers,
    hollow where the mass stops) and the stick fraction in the stop region."""
    import matplotlib.pyplot as plt
    d = _numeric(outdir / "steady_denhartog.csv")
    cur = c.read_numeric_csv(outdir / "steady_denhartog_curves.csv")
    ratios = list(dict.fromkeys(d["r [-]"].tolist()))
    fig, top, bottom = _gallery.two_panels(5.8, sharex=True, gridspec_kw={"height_ratios": [2.2, 1.0]},
                                           layout="constrained")
    for i, r in enumerate(ratios):
        col = style.SEQUENCE[i]
        y, ok = cur[f"X k/P0 r={r:g} [-]"], cur[f"holds r={r:g} [-]"] == 1.0
        top.plot(cur["beta [-]"], np.where(ok, y, np.nan), color=col, lw=1.1, label=f"F/P$_0$ = {r:g}")
        top.plot(cur["beta [-]"], np.where(ok | (cur["beta [-]"] < 0.45), np.nan, y), color=col, lw=0.8, ls=":")
        sel = d["r [-]"] == r
        stop = sel & (d["stops per period [-]"] > 0)
        free = sel & ~(d["stops per period [-]"] > 0)
        top.plot(d["beta [-]"][free], d["X k/P0 [-]"][free], "o", ms=3.5, color=col)
        top.plot(d["beta [-]"][stop], d["X k/P0 [-]"][stop], "s", ms=3.5, color=col, mfc="white", mew=0.9)
        bottom.plot(d["beta [-]"][sel], d["stick fraction [-]"][sel], "s-", ms=3, color=col, mfc="white", lw=0.8)
        cf = d["stick fraction closed form [-]"]
        has = sel & np.isfinite(cf)
        bottom.plot(d["beta [-]"][has], cf[has], "x", ms=4, color="k", mew=0.8)
    top.set_yscale("log")
    top.set_ylim(0.02, 100.0)
    top.set_ylabel("X k/P$_0$ [-]")
    bottom.set_ylabel("stick fraction [-]")
    bottom.set_xlabel("frequency ratio ω/ω$_n$ [-]")
    handles, _ = top.get_legend_handles_labels()
    handles += [plt.Line2D([], [], color="k", lw=0.8, ls=":", label="not the motion"),
                plt.Line2D([], [], color="k", marker="o", ms=3.5, ls="none", label="orbit, no stops"),
                plt.Line2D([], [], color="k", marker="s", ms=3.5, mfc="white", ls="none", label="orbit with stops"),
                plt.Line2D([], [], color="k", marker="x", ms=4, ls="none", label="closed form with stops")]
    # below the axes, where it covers no data
    fig.legend(handles=handles, loc="outside lower center", ncol=2, handlelength=1.4, columnspacing=0.8,
               frameon=False)
    return _gallery.save(fig, outdir / "steady_denhartog.png")


def plot_hopf(outdir: Path) -> Path:
    """The cycle's amplitude and its nontrivial multiplier against c / c_H, with the
    linearisation's Hopf point and the branch's."""
    d = c.read_numeric_csv(outdir / "steady_hopf.csv")
    pt = c.read_csv(outdir / "steady_hopf_point.csv")
    ratio = float(pt["c_H branch [N s/m]"][0]) / float(pt["c_H linearisation [N s/m]"][0])
    fig, top, bottom = _gallery.two_panels(4.6, sharex=True)
    cyc = d["amplitude [m]"] > HOPF_FLOOR
    top.plot(d["c/c_H [-]"][cyc], 1e3 * d["amplitude [m]"][cyc], "o-", ms=3.5, lw=0.9, color=style.SEQUENCE[0],
             label="continuation (stable cycles)")
    top.plot(d["c/c_H [-]"][~cyc], 1e3 * d["amplitude [m]"][~cyc], "o", ms=3.5, mfc="white",
             color=style.SEQUENCE[0], label="shrunk to steady sliding")
    top.plot([ratio], [0.0], "x", ms=6, mew=1.2, color=style.SEQUENCE[1], label="branch's Hopf point")
    for ax in (top, bottom):
        ax.axvline(1.0, color="0.4", lw=0.8, ls="--", label="c$_H$ = -N μ'(v$_b$)" if ax is top else None)
    top.set_ylabel("amplitude [mm]")
    top.legend(loc="lower left")
    bottom.plot(d["c/c_H [-]"][cyc], d["nontrivial multiplier [-]"][cyc], "o-", ms=3.5, lw=0.9,
                color=style.SEQUENCE[2])
    bottom.set_ylabel("nontrivial |multiplier| [-]")
    bottom.set_xlabel("damper c / c$_H$ [-]")
    return _gallery.save(fig, outdir / "steady_hopf.png")


def plot_damper(outdir: Path) -> Path:
    """Amplitude against frequency (shooting markers, harmonic balance lines) and harmonic
    balance's relative difference from shooting."""
    d = c.read_numeric_csv(outdir / "steady_damper.csv")
    hs = [int(k[2:].split(" ")[0]) for k in d if k.startswith("HB") and k.endswith("amplitude [m]")]
    fig, top, bottom = _gallery.two_panels(4.8, sharex=True)
    f = d["f [Hz]"]
    top.plot(f, d["shooting amplitude [m]"], "o", ms=4, color="k", mfc="white", mew=0.9, label="shooting")
    for i, h in enumerate(hs):
        col = style.SEQUENCE[i]
        top.plot(f, d[f"HB{h} amplitude [m]"], "-", lw=1.0, color=col, label=f"HB, {h} harmonic{'s' if h > 1 else ''}")
        bottom.semilogy(f, d[f"HB{h} abs relative difference [-]"], "-", marker=".", lw=1.0, color=col)
    top.set_ylabel("amplitude [m]")
    _gallery.legend_above_data(top, ncol=2, room=0.45)
    bottom.set_ylabel("|HB / shooting - 1| [-]")
    bottom.set_xlabel("forcing frequency f [Hz]")
    return _gallery.save(fig, outdir / "steady_damper.png")


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.gallery_steady [--outdir DIR] [--quick] [--threads N] [--quiet]."""
    return c.study_main("cases.gallery_steady", __doc__, "fewer points: one friction ratio, every other frequency",
                        run, argv)


if __name__ == "__main__":
    main()
