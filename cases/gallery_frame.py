"""A friction damper in a one-storey frame under the El Centro 1940 record, end to end: the
damper's law identified from its measured records, then the frame built as a
`stickslip.Model` and run with and without the damper::

    python -m cases.gallery_frame --outdir out/            # about 10 s
    python -m cases.gallery_frame --outdir out/ --quick    # the first 12 s of the record

**The law.** `python -m cases.identify` fits every law of the library to the 20 measured
records of data/friction-damper/ and its model selection (held-out error, then the fewest
parameters) picks Dahl's law at both band tensions. This driver fits Dahl's law again, to the
records at the 30 lb tension (the same checkerboard split of frequency x amplitude, 48 samples
per cycle), with backlash 0 and asymmetry 1 held fixed: the frame's contact is symmetric and
without play (the selection's fit finds a backlash of 0 and an asymmetry of 0.91 at 30 lb, the
tension closer to symmetric). The fit gives force levels (the normal force of the damper was
not measured): a sliding force F_d [N] and a stiffness sigma0 [N/m]. The contact of the model
takes the clamp force scale as its normal force, N = F_d, and the law's coefficients per unit
normal force: mu_k = 1, sigma0 / F_d [1/m], and the fitted exponent.

**The frame.** A storey of mass M (FRAME) on columns of lateral stiffness K (natural period
T_n = 0.5 s) with 2 % viscous damping, the damper between the storey and the ground. In
coordinates relative to the ground, the storey drift u obeys
M u'' + C u' + K u = -M a_g(t) + F_friction, the ground acceleration a_g of El Centro 1940 NS
(data/el-centro-1940/, public domain) as a table signal of the force -M a_g(t). Three runs:
no damper (DOPRI5, rtol 1e-10), the identified Dahl damper (DOPRI5, rtol 1e-9) and, for
comparison, an exact Coulomb damper of the same sliding force (mu_s = mu_k = 1 on N = F_d,
event-driven, rtol 1e-10), whose only difference from Dahl's is the presliding.

Measured: peak drift and its reduction, the drift at the end, the energy put in by the ground
and the share the damper dissipates, and the energy balance of each run (input = kinetic +
strain + viscous + damper work, by the trapezoidal rule on a 2 ms grid) as a check.

Writes ``frame_identified.md`` (the fit), ``frame_summary.md`` and ``frame_summary.csv`` (the
three runs), ``frame_series.csv`` (t, a_g, the drifts and damper forces, every 4 ms), ``frame_drift.png``/
``.pdf`` (ground acceleration and drift with and without the damper) and ``frame_loop.png``/
``.pdf`` (the damper's force against the drift over the strong motion, 0 to
8 s: Dahl and Coulomb).
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

ROOT: Path = Path(__file__).resolve().parent.parent
RECORD: Path = ROOT / "data" / "el-centro-1940" / "elcentro_1940_ns.csv"
G: float = 9.81                       # [m/s^2] per g of the record
TENSION: float = 30.0                 # [lb], the damper records fitted
#: The frame: storey mass [kg], natural period [s], viscous damping ratio [-].
FRAME: dict[str, float] = {"M": 2.0e4, "T_n": 0.5, "zeta": 0.02}
DT_OUT: float = 2e-3                  # output grid [s]
SERIES_EVERY: int = 2                 # frame_series.csv keeps every 2nd output point (4 ms)
QUICK_END: float = 12.0               # [s] of the record with --quick
RTOL_FIT: float = 1e-4                # the fit's state integration (as cases.identify)
LOOP_END: float = 8.0                 # [s]: the hysteresis figure shows the strong motion
RUNS: tuple[str, ...] = ("none", "dahl", "coulomb")
RUN_NAMES: dict[str, str] = {"none": "no damper", "dahl": "damper, Dahl (identified)",
                             "coulomb": "damper, Coulomb (same sliding force)"}
RUN_COLORS: dict[str, str] = {"none": "0.45", "dahl": style.LAW_COLORS["dahl"],
                              "coulomb": style.LAW_COLORS["coulomb"]}


def ground_record() -> tuple[np.ndarray, np.ndarray]:
    """El Centro 1940 NS: t [s] from 0 (a zero added at t = 0) and a_g [m/s^2]."""
    data = np.loadtxt(RECORD, delimiter=",", comments="#", skiprows=2)
    return np.concatenate([[0.0], data[:, 0]]), G * np.concatenate([[0.0], data[:, 1]])


def frame_constants() -> dict[str, float]:
    """M [kg], K [N/m], C [N s/m] of FRAME."""
    m = FRAME["M"]
    w = 2.0 * math.pi / FRAME["T_n"]
    return {"M": m, "K": m * w * w, "C": 2.0 * FRAME["zeta"] * m * w}


# --------------------------------------------------------------------------------------------
# Identification
# --------------------------------------------------------------------------------------------
def identify(quiet: bool = False) -> dict[str, Any]:
    """Fit Dahl's law to the 30 lb damper records (module notes); the fit, its held-out score
    and the records' counts."""
    import warnings

    import stickslip as ss
    from .identify import RTOL, DIFF_STEP, load_groups
    groups = load_groups(ss.damper_files(tension=TENSION))
    (recs,) = groups.values()
    train = [r for r, tr in recs if tr]
    held = [r for r, tr in recs if not tr]
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ss.fit_friction("dahl", train, backlash=0.0, asymmetry=1.0, n_starts=1, rtol=RTOL,
                              diff_step=DIFF_STEP)
    seconds = time.perf_counter() - t0
    c.log(f"cases.gallery_frame: Dahl fitted to {len(train)} records in {seconds:.1f} s", quiet)
    return {"fit": fit, "held": fit.score(held), "n_train": len(train), "n_held": len(held), "seconds": seconds}


# --------------------------------------------------------------------------------------------
# The frame
# --------------------------------------------------------------------------------------------
def frame_model(damper: str, f_d: float = 0.0, sigma0: float = 0.0, alpha: float = 1.0) -> Any:
    """The frame as a stickslip.Model: the storey (body 0, drift u relative to the ground)
    on a spring K and a damper C, loaded by -M a_g(t) (a table signal); with `damper` "dahl" or
    "coulomb" a contact with the ground of normal force `f_d` [N] (Dahl: mu_k = 1,
    sigma0 / f_d [1/m], exponent `alpha`; Coulomb: mu_s = mu_k = 1)."""
    import stickslip as ss
    k = frame_constants()
    t, a_g = ground_record()
    m = ss.Model()
    s = m.add_body(k["M"], name="storey")
    m.add_spring(s, None, k["K"])
    m.add_damper(s, None, k["C"])
    m.add_force(s, ss.signal.table(t, -k["M"] * a_g))
    if damper == "dahl":
        m.add_contact(s, None, "dahl", normal_force=f_d, mu_k=1.0, sigma0=sigma0 / f_d, dahl_alpha=alpha)
    elif damper == "coulomb":
        m.add_contact(s, None, "coulomb", normal_force=f_d, mu_s=1.0, mu_k=1.0)
    elif damper != "none":
        raise ValueError(f"damper: must be 'none', 'dahl' or 'coulomb', got {damper!r}")
    return m


def simulate_frame(damper: str, t_end: float, f_d: float = 0.0, sigma0: float = 0.0,
                   alpha: float = 1.0) -> dict[str, Any]:
    """Run one frame (module notes); t, drift u, velocity, the damper's force R resisting the
    drift (R = -friction force on the storey) and the CPU time of the library call."""
    import stickslip as ss
    m = frame_model(damper, f_d, sigma0, alpha)
    n_out = int(round(t_end / DT_OUT)) + 1
    if damper == "coulomb":
        res = ss.simulate(m, method="event_driven", t_end=t_end, n_out=n_out, rtol=1e-10, atol=1e-13)
    else:
        rtol = 1e-10 if damper == "none" else 1e-9
        res = ss.simulate(m, method="dopri5", t_end=t_end, n_out=n_out, rtol=rtol, atol=1e-3 * rtol)
    u, v = res.x[0], res.v[0]
    k = frame_constants()
    t_rec, a_rec = ground_record()
    a_g = np.interp(res.t, t_rec, a_rec)
    if damper == "dahl":
        force = sigma0 * res.z[0]                       # mu N = (sigma0 / f_d) z f_d
    elif damper == "coulomb":
        # slipping: f_d sign(v); stuck (v = 0, u'' = 0): the force that holds the storey
        force = np.where(v != 0.0, f_d * np.sign(v), -k["K"] * u - k["M"] * a_g)
    else:
        force = np.zeros_like(u)
    return {"t": res.t, "u": u, "v": v, "a_g": a_g, "force": force, "cpu": res.stats["cpu_seconds"],
            "nfev": res.stats["nfev"], "events": len(res.events)}


def energies(run: dict[str, Any]) -> dict[str, float]:
    """Input energy -int M a_g u' dt, the energy left (kinetic + strain), the viscous and the
    damper's dissipated work (trapezoidal rule on the output grid) and the balance's residual
    over the input [J, -]."""
    k = frame_constants()
    t, u, v, a_g, f = run["t"], run["u"], run["v"], run["a_g"], run["force"]

    def integral(y: np.ndarray) -> float:
        return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t)))
    e_in = integral(-k["M"] * a_g * v)
    left = 0.5 * k["M"] * v[-1] ** 2 + 0.5 * k["K"] * u[-1] ** 2
    visc = integral(k["C"] * v * v)
    damp = integral(f * v)
    return {"input": e_in, "left": left, "viscous": visc, "damper": damp,
            "residual": (e_in - left - visc - damp) / e_in}


def run(outdir: str | Path, *, quick: bool = False, threads: int = 1, quiet: bool = False) -> list[Path]:
    """Identify, simulate, write the files of the module notes. `threads` is accepted for
    `python -m cases` and not used (three runs, one after the other)."""
    outdir = Path(outdir)
    ident = identify(quiet)
    fit = ident["fit"]
    f_d, sigma0, alpha = fit.params["mu_k"], fit.params["sigma0"], fit.params["dahl_alpha"]
    t_rec, _ = ground_record()
    t_end = QUICK_END if quick else float(t_rec[-1])
    runs = {}
    for name in RUNS:
        runs[name] = simulate_frame(name, t_end, f_d, sigma0, alpha)
        c.log(f"cases.gallery_frame: {RUN_NAMES[name]}: peak drift {1e3 * np.max(np.abs(runs[name]['u'])):.2f} mm, "
              f"CPU {runs[name]['cpu']:.3f} s", quiet)
    files = [write_identified(outdir, ident)]
    k = frame_constants()
    peak0 = float(np.max(np.abs(runs["none"]["u"])))
    rows = []
    for name in RUNS:
        r = runs[name]
        e = energies(r)
        i = int(np.argmax(np.abs(r["u"])))
        peak = float(abs(r["u"][i]))
        rows.append([name, 1e3 * peak, float(r["t"][i]), 100.0 * (1.0 - peak / peak0), 1e3 * float(r["u"][-1]),
                     1e-3 * float(np.max(np.abs(r["force"]))), 1e-3 * e["input"],
                     100.0 * e["damper"] / e["input"], 100.0 * e["viscous"] / e["input"], e["residual"],
                     r["cpu"], r["nfev"], r["events"]])
    files.append(c.write_csv(outdir / "frame_summary.csv",
                             ["run [-]", "peak drift [mm]", "at t [s]", "reduction [%]", "drift at end [mm]",
                              "peak damper force [kN]", "input energy [kJ]", "damper share [%]",
                              "viscous share [%]", "energy residual [-]", "cpu [s]", "nfev [-]", "events [-]"], rows))
    every = slice(None, None, SERIES_EVERY)
    files.append(c.write_columns(outdir / "frame_series.csv", {
        "t [s]": runs["none"]["t"][every], "a_g [m/s^2]": runs["none"]["a_g"][every],
        **{f"u {n} [m]": runs[n]["u"][every] for n in RUNS},
        **{f"R {n} [N]": runs[n]["force"][every] for n in ("dahl", "coulomb")}}))
    files.append(write_summary(outdir, k, f_d, t_end))
    files += plot(outdir)
    return files


def write_identified(outdir: Path, ident: dict[str, Any]) -> Path:
    """frame_identified.md: the fitted parameters with intervals, and the errors."""
    fit = ident["fit"]
    rows = []
    for name in ("mu_k", "sigma0", "dahl_alpha"):
        lo, hi = fit.ci95.get(name, (None, None))
        label = {"mu_k": "sliding force F_d (mu_k at N = 1 N)", "sigma0": "presliding stiffness sigma0",
                 "dahl_alpha": "shape exponent alpha"}[name]
        rows.append([label, f"{fit.params[name]:.4g}", fit.units[name],
                     "" if lo is None else f"[{lo:.4g}, {hi:.4g}]"])
    text = c.markdown_table(["parameter", "value", "unit", "95 % interval"], rows)
    text += (f"\nDahl's law fitted to {ident['n_train']} records at {TENSION:g} lb ({fit.n_samples} samples) "
             f"in {ident['seconds']:.1f} s: RMS error {1e-3 * fit.rmse:.2f} kN ({100 * fit.nrmse:.1f} % of the force "
             f"range) on them, {1e-3 * ident['held']['rmse']:.2f} kN ({100 * ident['held']['nrmse']:.1f} %) on the "
             f"{ident['n_held']} held-out records. Presliding displacement F_d / sigma0 = "
             f"{1e3 * fit.params['mu_k'] / fit.params['sigma0']:.2f} mm.\n")
    return c.write_text(outdir / "frame_identified.md", text)


def write_summary(outdir: Path, k: dict[str, float], f_d: float, t_end: float) -> Path:
    """frame_summary.md: the frame's constants and the three runs (from frame_summary.csv)."""
    cols = c.read_csv(outdir / "frame_summary.csv")
    rows = [dict(zip(cols, vals)) for vals in zip(*cols.values())]
    method = {"none": "DOPRI5, rtol 1e-10", "dahl": "DOPRI5, rtol 1e-9", "coulomb": "event-driven, rtol 1e-10"}
    body = [[RUN_NAMES[r["run [-]"]], method[r["run [-]"]], f"{float(r['peak drift [mm]']):.2f}",
             f"{float(r['at t [s]']):.2f}", f"{float(r['reduction [%]']):.1f}", f"{float(r['drift at end [mm]']):.2f}",
             f"{float(r['peak damper force [kN]']):.2f}", f"{float(r['damper share [%]']):.1f}",
             f"{float(r['energy residual [-]']):.1e}", f"{1e3 * float(r['cpu [s]']):.0f}"] for r in rows]
    head = (f"Storey mass {k['M'] / 1e3:g} t, stiffness {k['K'] / 1e6:.3f} MN/m (T_n = {FRAME['T_n']:g} s), "
            f"damping {100 * FRAME['zeta']:g} % ({k['C'] / 1e3:.1f} kN s/m); damper sliding force "
            f"F_d = {f_d / 1e3:.2f} kN ({100 * f_d / (k['M'] * G):.1f} % of the storey weight); El Centro 1940 NS, "
            f"0 to {t_end:g} s.\n\n")
    text = head + c.markdown_table(["run", "method", "peak drift [mm]", "at t [s]", "reduction [%]",
                                    "drift at the end [mm]", "peak damper force [kN]",
                                    "damper's share of the input energy [%]", "energy balance residual [-]",
                                    "CPU [ms]"], body)
    return c.write_text(outdir / "frame_summary.md", text)


def plot(outdir: Path) -> list[Path]:
    """frame_drift.png/.pdf and frame_loop.png/.pdf from frame_series.csv."""
    s = c.read_numeric_csv(outdir / "frame_series.csv")
    t = s["t [s]"]
    fig, ax0, ax1 = _gallery.two_panels(3.6, sharex=True, layout="constrained",
                                        gridspec_kw={"height_ratios": [1, 2.2]})
    ax0.plot(t, s["a_g [m/s^2]"] / G, color="k", lw=0.6)
    ax0.set_ylabel("a$_g$ [g]")
    for n in RUNS:
        ax1.plot(t, 1e3 * s[f"u {n} [m]"], color=RUN_COLORS[n], lw=0.7 if n == "none" else 0.9,
                 label=RUN_NAMES[n].replace("damper, ", "").replace(" (same sliding force)", ""))
    ax1.set_ylabel("storey drift u [mm]")
    ax1.set_xlabel("time t [s]")
    ax1.legend(ncol=3, loc="upper center", bbox_to_anchor=(0.5, 1.17), frameon=False,
               handlelength=1.4, columnspacing=0.8)
    ax1.set_xlim(0.0, t[-1])
    files = [_gallery.save(fig, outdir / "frame_drift.png")]
    fig, ax = _gallery.figure(3.4, layout="constrained")
    strong = t <= LOOP_END
    for n in ("coulomb", "dahl"):
        ax.plot(1e3 * s[f"u {n} [m]"][strong], 1e-3 * s[f"R {n} [N]"][strong], color=RUN_COLORS[n], lw=0.6,
                label=RUN_NAMES[n].replace("damper, ", ""))
    ax.set_xlabel("storey drift u [mm]")
    ax.set_ylabel("damper force [kN]")
    ax.set_ylim(-14.0, 14.0)
    ax.set_title(f"the strong motion, 0 to {LOOP_END:g} s")
    fig.legend(loc="outside lower center", handlelength=1.4, frameon=False)   # below: covers no loop
    files.append(_gallery.save(fig, outdir / "frame_loop.png"))
    return files


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.gallery_frame [--outdir DIR] [--quick] [--threads N] [--quiet]."""
    return c.study_main("cases.gallery_frame", __doc__, f"the first {QUICK_END:g} s of the record", run, argv)


if __name__ == "__main__":
    main()
