"""Gallery: Modelica's CoupledClutches (docs/gallery/coupled-clutches.md), built with
`ss.Model` and compared with the Modelica Standard Library's published reference result::

    python -m cases.gallery_clutches --outdir docs/figures

Four inertias J1..J4 (1 kg m² each, J1 at 10 rad/s), a torque 10 sin(2 pi 5 t) N m on J1 and
three clutches between neighbours with normal forces 20 cos(2 pi 0.2 t) N, a step to 20 N at
0.4 s and one at 0.9 s (data/coupled-clutches/README.md). Modelica's clutch (mu_pos = [0, 0.5],
peak = 1.1, cgeo = 1) is set-valued Coulomb friction here: mu_k = 0.5, mu_s = peak mu_k = 0.55.

Writes gallery_clutches.csv (the four speeds of event_driven and of the reference, on the
reference's 2.5 ms grid), gallery_clutches.png (the speeds and the deviation from the
reference), gallery_clutches_compare.md (the largest deviations per inertia, for event_driven,
moreau and the scipy reference), gallery_clutches_events.md (the clutches' transitions in the
three results) and gallery_clutches_bench.md (event_driven against a scipy event-driven solver
at equal accuracy, CPU time in this run). --quick times fewer repeats.
"""
from __future__ import annotations

import csv
import math
import time
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from harness import style as _style

from . import _common as c
from . import _gallery

ROOT: Path = Path(__file__).resolve().parent.parent
DATA: Path = ROOT / "data" / "coupled-clutches" / "CoupledClutches.csv"
T_END: float = 1.5
#: Clutch data of the Modelica example: fn_max [N], mu_pos's single value, peak.
FN_MAX, MU_K, PEAK = 20.0, 0.5, 1.1
MU_S: float = PEAK * MU_K
#: The reference's output grid [s] (a row every 2.5 ms of data/coupled-clutches).
GRID: np.ndarray = np.linspace(0.0, T_END, 601)
NAMES: tuple[str, ...] = ("J1", "J2", "J3", "J4")
#: Modelica's mode codes.
MODE_WORDS: dict[int, str] = {-1: "slips", 0: "locked", 1: "slips", 2: "free"}


def model() -> Any:
    """CoupledClutches as an `ss.Model`: bodies J1..J4 (indices 0..3), contacts clutch1..3."""
    import stickslip as ss
    S = ss.signal
    m = ss.Model()
    j = [m.add_body(1.0, x0=0.0, v0=10.0 if i == 0 else 0.0, name=n) for i, n in enumerate(NAMES)]
    m.add_force(j[0], S.sine(10.0, 5.0))
    normal = (FN_MAX * S.sine(1.0, 0.2, phase=math.pi / 2),   # Modelica's sin2: amplitude 1, 0.2 Hz, phase pi/2
              FN_MAX * S.step(0.4), FN_MAX * S.step(0.9))
    for i, n in enumerate(normal):
        m.add_contact(j[i], j[i + 1], "coulomb", normal_force=n, mu_s=MU_S, mu_k=MU_K)
    return m


def scipy_system() -> Any:
    """The same system for the independent scipy event-driven solver (cases/_scipy_events.py)."""
    from cases._scipy_events import ScipyContacts

    def force(t: float, x: np.ndarray) -> np.ndarray:
        return np.array([10.0 * math.sin(2.0 * math.pi * 5.0 * t), 0.0, 0.0, 0.0])

    contacts = [(0, 1, lambda t: FN_MAX * math.cos(2.0 * math.pi * 0.2 * t)),
                (1, 2, lambda t: FN_MAX if t >= 0.4 else 0.0),
                (2, 3, lambda t: FN_MAX if t >= 0.9 else 0.0)]
    return ScipyContacts([1.0] * 4, force, contacts, MU_S, MU_K, breakpoints=(0.4, 0.9, 1.25))


def reference() -> dict[str, np.ndarray]:
    """Modelica's result: t [s] (unique times, the 2.5 ms grid), w (4, n_t) [rad/s], and the
    transitions: event_t [s], event_clutch (0-based), event_mode (Modelica's codes)."""
    with open(DATA, newline="") as f:
        rows = list(csv.reader(f))
    head, d = rows[0], np.array([[float(v) for v in r] for r in rows[1:]])
    col = {h: d[:, i] for i, h in enumerate(head)}
    w1 = col["J1.w"]
    w2 = w1 + col["clutch1.w_rel"]
    w3 = w2 + col["clutch2.w_rel"]
    w4 = w3 + col["clutch3.w_rel"]
    t = col["time"]
    on_grid = np.isclose(t / 0.0025, np.round(t / 0.0025), rtol=0.0, atol=1e-7)
    _, first = np.unique(t, return_index=True)     # an event's time is written twice: keep the first
    keep = np.zeros(t.size, bool)
    keep[first] = True
    keep &= on_grid
    ev_t, ev_c, ev_m = [], [], []
    for k in range(3):
        mode = col[f"clutch{k + 1}.mode"]
        for i in np.flatnonzero(np.diff(mode) != 0):
            ev_t.append(t[i + 1])
            ev_c.append(k)
            ev_m.append(int(mode[i + 1]))
    order = np.argsort(ev_t, kind="stable")
    return {"t": t[keep], "w": np.vstack([w1, w2, w3, w4])[:, keep],
            "event_t": np.asarray(ev_t)[order], "event_clutch": np.asarray(ev_c)[order],
            "event_mode": np.asarray(ev_m)[order]}


def closed_form(t: np.ndarray) -> np.ndarray:
    """J1's and J2's speeds (2, n_t) [rad/s] while clutch 1 slides alone (t <= 0.4 s): J1 gets the
    torque 10 sin(2 pi 5 t) minus the clutch's mu_k fn_max cos(2 pi 0.2 t), J2 the clutch's."""
    clutch = MU_K * FN_MAX / (2.0 * math.pi * 0.2) * np.sin(2.0 * math.pi * 0.2 * t)
    drive = 10.0 / (2.0 * math.pi * 5.0) * (1.0 - np.cos(2.0 * math.pi * 5.0 * t))
    return np.vstack([10.0 + drive - clutch, clutch])


def simulate(method: str = "event_driven", built: Any = None, **controls: Any) -> Any:
    """Our run of the model (`built`, or a new `model()`) on the reference's grid."""
    import stickslip as ss
    return ss.simulate(model() if built is None else built, method=method, t_end=T_END, n_out=GRID.size,
                       **controls)


def _cpu(fn: Callable[[], object], repeats: int) -> float:
    """The smallest CPU time of `repeats` calls [s] (the machine is shared)."""
    best = math.inf
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        best = min(best, time.process_time() - t0)
    return best


#: scipy's integrators and the tolerances each is run at in the benchmark.
SCIPY_RUNS: dict[str, tuple[float, ...]] = {"DOP853": (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11),
                                             "RK45": (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)}


def benchmark(repeats: int, quiet: bool) -> tuple[list[list[Any]], dict[str, float]]:
    """event_driven against the scipy event-driven solver (DOP853 and RK45) at equal accuracy.
    The error of a run: its largest deviation in the four speeds over the 601-point grid from
    scipy's DOP853 run at rtol 1e-13 (atol 1e-15). Each of our runs is matched with each scipy
    integrator's CPU time at the same error, interpolated (log-log) between its runs. Rows and
    a summary (the agreement of the two tightest runs, the smallest and largest ratio for each
    integrator)."""
    sysm = scipy_system()
    v0 = [10.0, 0.0, 0.0, 0.0]
    _, v_ref, _ = sysm.run(v0, T_END, GRID, rtol=1e-13, atol=1e-15)
    tight = simulate(rtol=1e-12, atol=1e-14)
    summary = {"agree": float(np.abs(tight.v - v_ref).max())}
    curves: dict[str, list[tuple[float, float, float, int]]] = {}
    for method, rtols in SCIPY_RUNS.items():
        pts = []
        for rtol in rtols:
            sysm.nfev = 0
            _, v, _ = sysm.run(v0, T_END, GRID, rtol=rtol, atol=rtol * 1e-2, method=method)
            nfev = sysm.nfev
            cpu = _cpu(lambda: sysm.run(v0, T_END, GRID, rtol=rtol, atol=rtol * 1e-2, method=method),
                       max(1, repeats // 5))
            pts.append((rtol, float(np.abs(v - v_ref).max()), cpu, nfev))
            c.log(f"gallery_clutches: scipy {method} rtol {rtol:g}: error {pts[-1][1]:.2e} rad/s, "
                  f"{1e3 * cpu:.1f} ms", quiet)
        curves[method] = pts
    rows = []
    built = model()          # built once, as scipy's system is
    for rtol in (1e-6, 1e-8, 1e-10):
        res = simulate(built=built, rtol=rtol, atol=rtol * 1e-2)
        err = float(np.abs(res.v - v_ref).max())
        cpu = _cpu(lambda: simulate(built=built, rtol=rtol, atol=rtol * 1e-2), repeats)
        row = ["event_driven (stickslip)", f"{rtol:g}", f"{err:.2g}", f"{1e3 * cpu:.3g}",
               f"{res.stats['nfev']}", f"{res.stats['nevents']}"]
        for method, pts in curves.items():
            log_err = np.log([p[1] for p in pts])
            log_cpu = np.log([p[2] for p in pts])
            order = np.argsort(log_err)
            inside = log_err.min() <= math.log(err) <= log_err.max()
            if inside:
                other = float(np.exp(np.interp(math.log(err), log_err[order], log_cpu[order])))
                ratio = other / cpu
                summary[f"{method}_min"] = min(summary.get(f"{method}_min", math.inf), ratio)
                summary[f"{method}_max"] = max(summary.get(f"{method}_max", 0.0), ratio)
                row += [f"{1e3 * other:.3g}", f"{ratio:.0f}"]
            else:
                row += ["outside its range", ""]
        rows.append(row)
        c.log(f"gallery_clutches: event_driven rtol {rtol:g}: error {err:.2e} rad/s, {1e3 * cpu:.3f} ms; "
              + ", ".join(f"{m} / ours {r}" for m, r in zip(curves, row[7::2])), quiet)
    for method, pts in curves.items():
        for rtol, err, cpu, nfev in pts:
            rows.append([f"scipy solve_ivp {method}, event-driven (numpy)", f"{rtol:g}", f"{err:.2g}",
                         f"{1e3 * cpu:.3g}", f"{nfev}", "", "", "", "", ""])
    return rows, summary


def _span(summary: dict[str, float], method: str) -> str:
    """"7 to 16" (the smallest and largest ratio against `method`, rounded), or one number."""
    low, high = (f"{summary.get(f'{method}_{k}', math.nan):.0f}" for k in ("min", "max"))
    return low if low == high else f"{low} to {high}"


def bench_markdown(repeats: int, quiet: bool = True) -> str:
    """The benchmark as Markdown: a paragraph (machine, what is measured, the ratios) and the
    table of `benchmark` (`repeats` timed runs of ours, repeats // 5 of scipy's)."""
    from harness.provenance import machine
    c.log("gallery_clutches: benchmark against scipy", quiet)
    bench, summary = benchmark(repeats, quiet)
    text = (f"Machine: {machine()}. CPU time of one run to t = 1.5 s with 601 output points, the smallest of "
            f"{repeats} runs (scipy: of {max(1, repeats // 5)}); error: the largest deviation of the four speeds "
            f"from scipy's DOP853 run at rtol 1e-13 (which agrees with event_driven at rtol 1e-12 to "
            f"{summary['agree']:.1g} rad/s); atol = rtol/100 throughout. At equal error event_driven is "
            f"**{_span(summary, 'DOP853')} times** faster than scipy's DOP853 and {_span(summary, 'RK45')} times "
            f"faster than its RK45 (where RK45 reaches that error).\n\n")
    return text + c.markdown_table(
        ["solver", "rtol [-]", "error [rad/s]", "CPU [ms]", "right-hand sides [-]", "events [-]",
         "DOP853 CPU at equal error [ms]", "DOP853 / event_driven [-]", "RK45 CPU at equal error [ms]",
         "RK45 / event_driven [-]"], bench)


def _events_ours(res: Any) -> list[tuple[float, int, str]]:
    return [(float(e["t"]), int(e["contact"]), str(e["kind"])) for e in res.events]


def plot(cols: dict[str, np.ndarray], path: Path) -> Path:
    """The four speeds (lines: event_driven; dots: Modelica) and |ours - Modelica| per inertia,
    from the columns of gallery_clutches.csv alone (`cols`, as c.read_numeric_csv reads them)."""
    fig, top, bottom = _gallery.two_panels(4.4, sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    t = cols["time t [s]"]
    for i, n in enumerate(NAMES):
        col = _style.SEQUENCE[i]
        ours, theirs = cols[f"omega {n} event_driven [rad/s]"], cols[f"omega {n} Modelica [rad/s]"]
        on = np.isfinite(theirs)                  # the reference's grid points
        top.plot(t, ours, color=col, label=n)
        top.plot(t[on][::16], theirs[on][::16], "o", ms=2.5, mfc="none", color=col)
        bottom.semilogy(t[on], np.maximum(np.abs(ours[on] - theirs[on]), 1e-12), color=col, lw=0.9)
    top.plot([], [], "o", ms=2.5, mfc="none", color="0.3", label="Modelica")
    top.set_ylabel("speed ω [rad/s]")
    top.set_title("CoupledClutches: event-driven vs Modelica")
    top.legend(ncol=3, loc="upper right", handlelength=1.2, columnspacing=0.8)
    bottom.set_ylabel("|ω − ω_Modelica| [rad/s]")
    bottom.set_xlabel("time t [s]")
    bottom.set_ylim(1e-10, 1e-2)
    return _gallery.save(fig, path)


def run(outdir: str | Path, *, quick: bool = False, threads: int = 2, quiet: bool = False) -> list[Path]:
    """Run the comparison and the benchmark; write the files of the module's docstring."""
    outdir = Path(outdir)
    ref = reference()
    c.log("gallery_clutches: event_driven, moreau and the scipy reference against Modelica", quiet)
    res = simulate(rtol=1e-10, atol=1e-12)
    sysm = scipy_system()
    _, v_sp, ev_sp = sysm.run([10.0, 0.0, 0.0, 0.0], T_END, GRID, rtol=1e-10, atol=1e-12)
    on = np.isin(np.round(GRID, 9), np.round(ref["t"], 9))
    assert on.sum() == ref["t"].size, "the reference's grid is not the 2.5 ms grid"
    runs = [("event_driven, rtol 1e-10", res.v[:, on]), ("scipy event-driven (DOP853, rtol 1e-10)", v_sp[:, on])]
    for h in (1e-3, 1e-4, 1e-5):
        r = simulate("moreau", h=h)
        runs.append((f"moreau, h = {h:g} s", r.v[:, on]))
    rows = [[label] + [f"{np.abs(v[i] - ref['w'][i]).max():.2g}" for i in range(4)]
            + [f"{np.abs(v - res.v[:, on]).max():.2g}"] for label, v in runs]
    early = ref["t"] <= 0.4
    exact = closed_form(ref["t"][early])
    first = [[label] + [f"{np.abs(v[i, early] - exact[i]).max():.2g}" for i in range(2)]
             for label, v in (("Modelica (Dymola, DASSL, tolerance 1e-6)", ref["w"]),
                              ("event_driven, rtol 1e-10", res.v[:, on]), runs[1])]
    files = [c.write_text(outdir / "gallery_clutches_compare.md", c.markdown_table(
        ["run", "J1: max abs(ω − ω_Modelica) [rad/s]", "J2 [rad/s]", "J3 [rad/s]", "J4 [rad/s]",
         "max abs(ω − ω_event_driven) [rad/s]"], rows)
        + "\nUntil 0.4 s, while clutch 1 slides alone, against the closed form:\n\n"
        + c.markdown_table(["run", "J1: max abs(ω − ω_exact) [rad/s]", "J2 [rad/s]"], first))]
    # the transitions: Modelica's, ours, scipy's
    ours = _events_ours(res)
    ev_rows = []
    for k, (tm, cl, mode) in enumerate(zip(ref["event_t"], ref["event_clutch"], ref["event_mode"])):
        word = MODE_WORDS[int(mode)]
        mine = [e for e in ours if e[1] == cl and abs(e[0] - tm) < 5e-3]
        sp = [e for e in ev_sp if e[1] == cl and abs(e[0] - tm) < 5e-3]
        ev_rows.append([f"clutch {cl + 1}", word, f"{tm:.7f}",
                        f"{mine[0][0]:.7f} ({mine[0][2]})" if mine else "none",
                        f"{sp[0][0]:.7f}" if sp else "none",
                        f"{abs(mine[0][0] - tm):.1e}" if mine else ""])
    extra = [e for e in ours if not any(abs(e[0] - tm) < 5e-3 and e[1] == cl
                                        for tm, cl in zip(ref["event_t"], ref["event_clutch"]))]
    for e in extra:
        ev_rows.append([f"clutch {e[1] + 1}", e[2], "none", f"{e[0]:.7f} ({e[2]})", "", ""])
    files.append(c.write_text(outdir / "gallery_clutches_events.md", c.markdown_table(
        ["clutch", "becomes", "Modelica t [s]", "event_driven t [s] (kind)", "scipy t [s]",
         "abs(event_driven − Modelica) [s]"], ev_rows)))
    cols = {"time t [s]": GRID}
    for i, n in enumerate(NAMES):
        cols[f"omega {n} event_driven [rad/s]"] = res.v[i]
    for i, n in enumerate(NAMES):
        cols[f"omega {n} Modelica [rad/s]"] = np.where(on, np.interp(GRID, ref["t"], ref["w"][i]), np.nan)
    files.append(c.write_columns(outdir / "gallery_clutches.csv", cols))
    files.append(plot(cols, outdir / "gallery_clutches.png"))
    files.append(c.write_text(outdir / "gallery_clutches_bench.md", bench_markdown(3 if quick else 15, quiet)))
    return files


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.gallery_clutches [--outdir DIR] [--quick] [--threads N] [--quiet]."""
    return c.study_main("cases.gallery_clutches", __doc__, "time 3 repeats instead of 15", run, argv)


if __name__ == "__main__":
    main()
