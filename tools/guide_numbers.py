"""The numbers the guides quote from runs that no study writes: each page's small measurements.

A study of `cases/` or a benchmark writes most of what the guides quote; a guide's own
illustration (a peak, a difference between two forms of one model, an advice) is measured
here, one function per page, and written into `docs/figures/guide_<page>.json`
(tools/docnumbers.py's format), with a page's tables as CSVs beside it (TABLES), and the
provenance sidecar; the page quotes the numbers with the {num} role and shows the tables as
generated tables (tools/doctables.py). Each page's runs take seconds.

    python tools/guide_numbers.py --outdir docs/figures [--page models]
"""
from __future__ import annotations

import argparse
import os
import warnings
import sys
import time
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from harness.files import write_text  # noqa: E402 - after the path above
from harness.provenance import write_provenance  # noqa: E402
from tools.docnumbers import numbers_json  # noqa: E402

Numbers = dict[str, tuple[float, str, str]]


def _page_example(page: str, marker: str) -> dict[str, object]:
    """The names a guide's Python example defines, run as the page writes it (its output
    discarded): the first fenced block of docs/guide/`page`.md that contains `marker`."""
    import contextlib
    import io
    import re
    text = (ROOT / "docs" / "guide" / f"{page}.md").read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"^```python\n(.*?)^```", text, re.S | re.M) if marker in b)
    names: dict[str, object] = {}
    with contextlib.redirect_stdout(io.StringIO()):
        exec(compile(block, f"docs/guide/{page}.md", "exec"), names)
    return names


def models() -> Numbers:
    """docs/guide/models.md: the clutch example's first stick, the driven drill string against
    its one-body form, the drill string on a turning surface, the rows on threads, the advice."""
    import stickslip as ss
    S = ss.signal
    out: Numbers = {}
    # the page's first example: J2 on a belt, a clutch engaged at 0.4 s
    res = _page_example("models", "m.add_damper(j1, j2")["res"]
    first = res.events[(res.events["contact"] == 1) & (res.events["kind"] == "stick")]["t"][0]
    out["example.j2_stick"] = (float(first), "s", "J2's first stick on the belt")

    # the driven drill string and its one-body form (as tests/test_model_drive.py builds them)
    def drill(law: str, driven: bool) -> ss.Model:
        d = ss.Model()
        if driven:
            top = d.add_body(50.0, name="top")
            bit = d.add_body(374.0, name="bit")
            d.add_spring(top, bit, 473.0)
            d.add_drive(top, velocity=5.0)
        else:
            bit = d.add_body(374.0, name="bit")
            d.add_spring(bit, None, 473.0)
            d.add_force(bit, 473.0 * S.ramp(0.0, 20.0, 100.0))
        d.add_contact(bit, None, law, 1000.0, mu_s=0.8, mu_k=0.5)
        return d

    for law in ("stribeck", "coulomb"):
        r2 = ss.simulate(drill(law, True), method="event_driven", t_end=20.0, n_out=401)
        r1 = ss.simulate(drill(law, False), method="event_driven", t_end=20.0, n_out=401)
        out[f"drive.{law}_dx"] = (float(np.max(np.abs(r2.x[1] - r1.x[0]))), "rad",
                                  f"largest |x| difference of the bit, two-body against one-body form, {law}")

    # the drill string's bit on a surface turning at 5 rad/s (as tests/test_model.py builds it)
    def surface() -> ss.Model:
        d = ss.Model()
        b = d.add_body(374.0, v0=5.0, name="bit")
        d.add_spring(b, None, 473.0)
        d.add_contact(b, None, "stribeck", 3669.0, 5.0, v_eps=1e-5, mu_s=0.8, mu_k=0.5)
        return d

    def peak(method: str, **controls: float) -> tuple[float, ss.Result]:
        r = ss.simulate(surface(), method=method, t_end=8.0, n_out=8001, **controls)
        return float(np.max(5.0 - r.v[0])), r

    out["surface.exact_peak"] = (peak("event_driven", rtol=1e-12, atol=1e-12)[0], "rad/s",
                                 "peak slip speed over 8 s, event_driven at rtol 1e-12")
    out["surface.converged_peak"] = (peak("radau5", rtol=1e-10, atol=1e-12)[0], "rad/s",
                                     "the same, radau5 at rtol 1e-10 (the regularised law)")
    for method in ("radau5", "dopri5", "dop853"):
        p, r = peak(method)
        out[f"surface.{method}_peak"] = (p, "rad/s", f"the same, {method} at its default tolerances")
        out[f"surface.{method}_nfev"] = (float(r.stats["nfev"]), "", f"{method}'s evaluations")

    # rows on threads: 8 RK4 rows of the page's two-body model (h = 1e-4 s, 20 s)
    m = _page_example("models", "ss.simulate_batch(")["m"]
    rows = {"contact 1.mu_k": [0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45]}
    for threads in (1, 2):
        wall = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ss.ConsistencyWarning)    # RK4 on Coulomb: timed, not judged
            batch = ss.simulate_batch(m, rows, method="rk4", h=1e-4, t_end=20.0, threads=threads)
        wall = time.perf_counter() - wall
        out[f"threads.{threads}.wall"] = (wall, "s", f"8 RK4 rows' wall time on {threads} thread(s)")
        out[f"threads.{threads}.rows_sum"] = (float(np.sum(batch.seconds)), "s",
                                              "the rows' own wall times, summed")
    out["threads.load_average"] = (os.getloadavg()[0], "", "the machine's load average after the runs")

    # the advice on the two-body model: the page's example, and the advice timed again
    example = _page_example("models", "ss.advise(")
    m, advice, r = example["m"], example["advice"], example["r"]
    wall = time.perf_counter()
    ss.advise(m, 1e-5, 1.0, body=1)
    wall = time.perf_counter() - wall
    exact = ss.simulate(m, method="event_driven", t_end=1.0, rtol=1e-11, atol=1e-13)
    out["advise.rtol"] = (float(advice.controls.get("rtol", np.nan)), "", f"the advised {advice.method}'s rtol")
    out["advise.estimated"] = (float(advice.predicted_error), "m", "the advice's estimated error")
    out["advise.true"] = (float(abs(r.x[1, -1] - exact.x[1, -1])), "m",
                          "the advised run's error at 1 s against event_driven at rtol 1e-11")
    out["advise.wall"] = (wall, "s", "the advice's wall time")
    out["advise.exact_x"] = (float(exact.x[1, -1]), "m", "body 1's x at 1 s, exact stick")
    for method in ("galpha", "dopri5", "dop853"):
        controls = dict(h=1e-4) if method == "galpha" else dict(rtol=1e-10, atol=1e-12)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ss.RegularisedLawWarning)     # the event-free form is the point
            r = ss.simulate(m, method=method, t_end=1.0, **controls)
        out[f"advise.{method}_x"] = (float(r.x[1, -1]), "m", f"the same under {method} (event-free law), tight")

    # RK4 beyond its stability bound on a spring (w = 100 rad/s, w h = 2.9), as tests/test_energy.py
    m = ss.Model()
    b = m.add_body(1.0, v0=1.0)
    m.add_spring(b, None, 1e4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ss.EnergyBoundWarning)
        r = ss.simulate(m, method="rk4", h=0.029, t_end=1.0, n_out=11)
    out["energy.rk4_growth"] = (float(np.hypot(100.0 * r.x[0, -1], r.v[0, -1])), "",
                                "RK4's amplitude at 1 s over the initial one, w h = 2.9")
    return out


def _rows(path: Path, law: str, methods: Sequence[str]) -> list[dict[str, str]]:
    """The rows of a laws_compare CSV of `law` under one of `methods`."""
    from harness.files import read_csv
    c = read_csv(path)
    keys = list(c)
    rows = [dict(zip(keys, r)) for r in zip(*c.values())]
    return [r for r in rows if r["law [-]"] == law and r["method [-]"] in methods]


def _absmax(rows: list[dict[str, str]], *columns: str) -> float:
    """The largest |cell| of `columns` over `rows` (empty cells skipped)."""
    return max(abs(float(r[c])) for r in rows for c in columns if r[c])


def friction_laws(figures: Path = ROOT / "docs" / "figures") -> Numbers:
    """docs/guide/friction-laws.md: the brake under Karnopp's and LuGre's laws (runs), and the
    largest deviations over RK4 and DOPRI5 runs of `python -m cases.laws_compare`'s CSVs."""
    import stickslip as ss
    S = ss.signal
    out: Numbers = {}
    x_stop = 26.0 / 3.0

    def brake(law: str, **params: float) -> ss.Model:
        m = ss.Model()
        b = m.add_body(50.0, v0=10.0, name="brake")
        m.add_contact(b, None, law, S.ramp(0.0, 0.5, 1000.0), **({"mu_s": 0.4, "mu_k": 0.4} | params))
        return m

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # the regularised law's and the consistency check's
        for method, controls in (("event_driven", {}), ("moreau", dict(h=1e-3)), ("implicit_euler", dict(h=1e-3)),
                                 ("galpha", dict(h=1e-3)), ("dopri5", {}), ("dop853", {}), ("radau5", {}),
                                 ("rk4", dict(h=1e-3))):
            r = ss.simulate(brake("karnopp", dv=1e-3), method=method, t_end=100.0, n_out=2001, **controls)
            out[f"karnopp_brake.{method}.dx"] = (float(abs(r.x[0, -1] - x_stop)), "m",
                                                 f"|x(100 s) - 26/3 m|, Karnopp's brake, {method}")
            out[f"karnopp_brake.{method}.v_end"] = (float(abs(r.v[0, -1])), "m/s", f"|v(100 s)|, {method}")
        for name, params in (("default", {}), ("sigma2_0", dict(sigma2=0.0))):
            r = ss.simulate(brake("lugre", **params), method="radau5", t_end=3.0, n_out=30001, rtol=1e-9,
                            atol=1e-12)
            out[f"lugre_brake.{name}.t_stop"] = (float(r.t[np.flatnonzero(r.v[0] <= 1e-6)[0]]), "s",
                                                 f"first output time (0.1 ms grid) with v <= 1e-6 m/s, LuGre "
                                                 f"({name}), radau5 at rtol 1e-9")
            out[f"lugre_brake.{name}.x_end"] = (float(r.x[0, -1]), "m", "x at 3 s, the same run")

    # the study's CSVs: largest deviations over its RK4 and DOPRI5 runs
    explicit = ("rk4", "dopri5")
    slope, belt = figures / "laws_compare_slope.csv", figures / "laws_compare_belt.csv"
    for law in ("elastoplastic", "lugre"):
        out[f"slope.{law}.rk4_vmax"] = (_absmax(_rows(slope, law, ("rk4",)), "v_20 [m/s]"), "m/s",
                                        f"largest |v(20 s)| of {law}'s RK4 runs on the slope")
        out[f"slope.{law}.dopri5_vmax"] = (_absmax(_rows(slope, law, ("dopri5",)), "v_20 [m/s]"), "m/s",
                                           f"|v(20 s)| of {law}'s DOPRI5 run on the slope")
    for law in ("coulomb", "recurdyn", "proposed", "stribeck", "karnopp", "lugre sigma2=0",
                "elastoplastic sigma2=0"):
        rows = _rows(belt, law, explicit)
        key = law.replace(" sigma2=0", "_sigma2_0")
        out[f"belt.{key}.err_x"] = (_absmax(rows, "err_x_max [m]", "err_x_min [m]"), "m",
                                    f"largest |error| of x_max and x_min, {law}, RK4 and DOPRI5 on the belt")
        out[f"belt.{key}.err_period"] = (_absmax(rows, "err_period [s]"), "s",
                                         f"largest |error| of the period, {law}, RK4 and DOPRI5 on the belt")
        out[f"belt.{key}.dopri5_err_x"] = (_absmax(_rows(belt, law, ("dopri5",)), "err_x_max [m]", "err_x_min [m]"),
                                           "m", f"the same, DOPRI5 alone")
    return out


def exact_stick() -> Numbers:
    """docs/guide/exact-stick.md: moreau's theta on the paper's belt, its observed order on a
    belt cycle, event_driven against the closed-form cycle on three other belts."""
    import stickslip as ss
    from cases.laws_compare import coulomb_cycle
    out: Numbers = {}
    paper = {"m": 10.0, "k": 300.0, "v_b": 1.5, "mu_s": 0.35, "mu_k": 0.30}
    x_max = coulomb_cycle(paper["mu_s"], paper["mu_k"], paper["m"], paper["k"], paper["v_b"])[0]
    for theta in (0.5, 1.0):
        r = ss.simulate("belt", "coulomb", method="moreau", h=1e-3, t_end=4.0, v0=paper["v_b"], theta=theta,
                        n_out=4001, **paper)
        out[f"theta.{theta:g}.amplitude_error"] = (float(abs(r.x.max() - x_max)), "m",
                                                   f"|largest x - the cycle's x_max|, moreau theta = {theta:g}, "
                                                   "h = 1e-3 s, the paper's belt started stuck, 4 s")
    hs = (4e-3, 2e-3, 1e-3, 5e-4)
    errs = []
    cycle = {"m": 1.0, "k": 50.0, "v_b": 0.8, "mu_s": 0.5, "mu_k": 0.2}     # tests/fortran/test_integrators_exact_stick.py's second
    ref = ss.simulate("belt", "coulomb", method="event_driven", t_end=4.0, v0=cycle["v_b"], n_out=401,
                      rtol=1e-12, atol=1e-14, **cycle)
    for h in hs:
        r = ss.simulate("belt", "coulomb", method="moreau", h=h, t_end=4.0, v0=cycle["v_b"], n_out=401, **cycle)
        errs.append(float(np.max(np.abs(r.x - ref.x))))
        out[f"order.err.{h:g}"] = (errs[-1], "m", f"largest |x - event_driven's x| (rtol 1e-12), moreau h = {h:g} s, "
                                   "m = 1 kg, k = 50 N/m, v_b = 0.8 m/s, mu_s = 0.5, mu_k = 0.2, 4 s, 401 points")
    for i in range(len(hs) - 1):
        out[f"order.{i + 1}"] = (float(np.log2(errs[i] / errs[i + 1])), "", f"observed order, h = {hs[i]:g} "
                                 f"to {hs[i + 1]:g} s")
    sets = [{"m": 2.0, "k": 500.0, "v_b": 0.3, "mu_s": 0.6, "mu_k": 0.4},
            {"m": 1.0, "k": 50.0, "v_b": 0.8, "mu_s": 0.5, "mu_k": 0.2},
            {"m": 5.0, "k": 2000.0, "v_b": 0.1, "mu_s": 0.3, "mu_k": 0.29}]     # tests/fortran/test_integrators_exact_stick.py's
    dx = dt = 0.0
    for p in sets:
        r = ss.simulate("belt", "coulomb", method="event_driven", t_end=6.0, v0=p["v_b"], n_out=3001,
                        rtol=1e-12, atol=1e-14, **p)
        period = coulomb_cycle(p["mu_s"], p["mu_k"], p["m"], p["k"], p["v_b"])[2]
        slips = r.events["t"][r.events["kind"] == "slip"]
        ev_x = r.events["x"][r.events["kind"] == "stick"]
        x_k = p["mu_k"] * p["m"] * 9.81 / p["k"]
        dx = max(dx, float(np.max(np.abs(ev_x - (2 * x_k - p["mu_s"] * p["m"] * 9.81 / p["k"])))))
        dt = max(dt, float(np.max(np.abs(np.diff(slips) - period))))
    out["event_driven.stick_x"] = (dx, "m", "largest |x at a stick event - x_k + d| over three belts, event_driven "
                                   "at rtol 1e-12, 6 s")
    out["event_driven.period"] = (dt, "s", "largest |time between slips - the closed-form period|, the same")
    return out


def exact_stick_stacked(outdir: Path) -> Path:
    """docs/guide/exact-stick.md's stacked blocks: for each friction set, moreau's largest
    position difference from event_driven (rtol 1e-12) over 5 s at h = 1e-3, 1e-4, 1e-5 s,
    and its `nonunique` count, into guide_exact_stick_stacked.csv."""
    import stickslip as ss
    from harness.files import write_csv
    g = 9.81
    sets = {"base": [(0.5, 0.35), (0.4, 0.3), (0.3, 0.2)],          # (mu_s, mu_k) belt-A, A-B, B-C
            "C-B at (0.32, 0.2)": [(0.5, 0.35), (0.4, 0.3), (0.32, 0.2)],
            "A-B at (0.4, 0.25)": [(0.5, 0.35), (0.4, 0.25), (0.3, 0.2)],
            "belt-A at (0.45, 0.35)": [(0.45, 0.35), (0.4, 0.3), (0.3, 0.2)],
            "B-C at (0.3, 0.3)": [(0.5, 0.35), (0.4, 0.3), (0.3, 0.3)]}
    hs = (1e-3, 1e-4, 1e-5)
    rows = []
    for name, friction in sets.items():
        m = ss.Model()
        a, b, c = m.add_body(2.0), m.add_body(1.0), m.add_body(0.5)
        for body, k in zip((a, b, c), (200.0, 60.0, 30.0)):
            m.add_spring(body, None, k)
        for (lower, upper, n, w), (mu_s, mu_k) in zip(((a, None, 3.5, 0.3), (b, a, 1.5, 0.0), (c, b, 0.5, 0.0)),
                                                      friction):
            m.add_contact(lower, upper, "coulomb", n * g, surface_velocity=w, mu_s=mu_s, mu_k=mu_k)
        ref = ss.simulate(m, method="event_driven", t_end=5.0, n_out=501, rtol=1e-12)
        errs, counts = [], []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)       # the nonunique count: counted here
            for h in hs:
                r = ss.simulate(m, method="moreau", h=h, t_end=5.0, n_out=501)
                errs.append(float(np.abs(r.x - ref.x).max()))
                counts.append(int(r.stats["nonunique"]))
        rows.append([name, *errs, *counts])
    header = ["set [-]", *(f"dx at h {h:g} s [m]" for h in hs), *(f"nonunique at h {h:g} s [-]" for h in hs)]
    return write_csv(outdir / "guide_exact_stick_stacked.csv", header, rows)


def implicit_nonsmooth() -> Numbers:
    """docs/guide/implicit-nonsmooth.md: the fixed-step implicit methods on a 5-block Coulomb
    chain and a 3-block proposed-law chain against references, and RADAU5's forced steps."""
    import stickslip as ss
    out: Numbers = {}

    def err(method: str, ref: ss.Result, **kw: float) -> float:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ss.RegularisedLawWarning)     # the band is what is measured
            return float(np.max(np.abs(ss.simulate("chain", "coulomb", method=method, **kw).x - ref.x)))

    chain5 = dict(n_blocks=5, t_end=10.0, n_out=1001)          # as tests/fortran/test_stickslip_fixed_implicit.py
    ref = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-11, atol=1e-13, **chain5)
    for h in (2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4):
        out[f"chain5.ie.{h:g}"] = (err("implicit_euler", ref, h=h, **chain5), "m",
                                   f"implicit_euler's largest |x - event_driven| on the 5-block chain, 10 s, h = {h:g} s")
    for h in (2.5e-4, 1.25e-4):
        out[f"chain5.galpha.{h:g}"] = (err("galpha", ref, h=h, **chain5), "m", f"the same, galpha, h = {h:g} s")
    for v_s in (1e-2, 1e-4):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ss.RegularisedLawWarning)
            r = ss.simulate("chain", "coulomb", method="implicit_euler", h=5e-4, v_s=v_s, **chain5)
        m = ss.simulate("chain", "coulomb", method="moreau", theta=1.0, h=5e-4, **chain5)
        out[f"chain5.gap.{v_s:g}"] = (float(np.max(np.abs(r.x - m.x))), "m", f"implicit_euler (v_s = {v_s:g} m/s) "
                                      "against moreau with theta = 1, h = 5e-4 s")
    ref = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-11, atol=1e-13, v_s=1e-4, **chain5)
    for h in (1e-3, 5e-4, 2.5e-4, 1.25e-4):
        out[f"chain5_vs1e-4.galpha.{h:g}"] = (err("galpha", ref, h=h, v_s=1e-4, **chain5), "m",
                                              f"galpha, v_s = 1e-4 m/s, h = {h:g} s")
        out[f"chain5_vs1e-4.ie.{h:g}"] = (err("implicit_euler", ref, h=h, v_s=1e-4, **chain5), "m",
                                          f"implicit_euler, v_s = 1e-4 m/s, h = {h:g} s")
    slip = dict(n_blocks=5, t_end=0.3, n_out=31, v0=0.0)
    ref = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-12, atol=1e-14, **slip)
    for h in (2e-3, 1e-3, 5e-4, 2.5e-4):
        out[f"slip.galpha.{h:g}"] = (err("galpha", ref, h=h, rho_inf=0.5, **slip), "m",
                                     f"galpha (rho_inf 0.5), 5-block chain in slip, 0.3 s, h = {h:g} s")
        out[f"slip.ie.{h:g}"] = (err("implicit_euler", ref, h=h, **slip), "m", f"the same, implicit_euler")
    stuck = dict(n_blocks=3, t_end=1.0, v0=ss.DEFAULTS["v_b"], n_out=11)
    ref = ss.simulate("chain", "proposed", method="radau5", rtol=1e-12, atol=1e-14, **stuck)
    for method, hs in (("galpha", (1e-2, 1e-3, 1e-4)), ("implicit_euler", (1e-3, 1e-4))):
        for h in hs:
            x = ss.simulate("chain", "proposed", method=method, h=h, **stuck).x
            out[f"stuck3.{method}.{h:g}"] = (float(np.max(np.abs(x - ref.x))), "m",
                                             f"{method}, 3-block proposed chain started stuck, 1 s, h = {h:g} s")
    # RADAU5 on Coulomb
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # the regularised law's warning: the point here
        for name, kw in (("auto", {}), ("hmax", dict(hmax=1e-2))):
            r = ss.simulate("belt", "coulomb", method="radau5", t_end=2.0, rtol=1e-6, **kw)
            out[f"radau5.belt.{name}.nfev"] = (float(r.stats["nfev"]), "", f"RADAU5, the paper's belt from rest, 2 s ({name})")
            out[f"radau5.belt.{name}.nstep"] = (float(r.stats["nstep"]), "", "its steps")
            out[f"radau5.belt.{name}.nforced"] = (float(r.stats["nforced"]), "", "its forced steps")
        cpu = time.process_time()
        r = ss.simulate("slope", "coulomb", method="radau5", t_end=2.0, rtol=1e-6, atol=1e-9)
        cpu = time.process_time() - cpu
        out["radau5.slope.nstep"] = (float(r.stats["nstep"]), "", "RADAU5, slope at rest, 2 s: steps")
        out["radau5.slope.nforced"] = (float(r.stats["nforced"]), "", "its forced steps")
        out["radau5.slope.nfev"] = (float(r.stats["nfev"]), "", "its evaluations")
        out["radau5.slope.cpu"] = (cpu, "s", "its CPU time")
        out["radau5.slope.x_end"] = (float(abs(r.x[-1])), "m", "its creep at 2 s")
        for name, kw in (("grid", {}), ("every_step", dict(every_step=True))):
            cpu = time.process_time()
            r = ss.simulate("slope", "coulomb", method="implicit_euler", h=1e-3, t_end=2.0, **kw)
            cpu = time.process_time() - cpu
            out[f"ie.slope.{name}.nfev"] = (float(r.stats["nfev"]), "", f"implicit Euler, slope at rest, 2 s ({name})")
            out[f"ie.slope.{name}.cpu"] = (cpu, "s", "its CPU time")
        for name, kw in (("auto", {}), ("hmax", dict(hmax=1e-2))):
            r = ss.simulate("slope", "karnopp", method="radau5", t_end=2.0, rtol=1e-6, atol=1e-9, **kw)
            out[f"radau5.karnopp.{name}.nfev"] = (float(r.stats["nfev"]), "", f"RADAU5, Karnopp, slope at rest ({name})")
    return out


def _script_times(page: str, marker: str) -> tuple[float, float]:
    """The wall and CPU time [s] of a guide's Python example (the first fenced block of
    docs/guide/`page`.md that contains `marker`) run as a script in a fresh interpreter, as a
    reader runs it: its imports included, BLAS on one thread."""
    import re
    import resource
    import subprocess
    import tempfile
    text = (ROOT / "docs" / "guide" / f"{page}.md").read_text(encoding="utf-8")
    block = next(b for b in re.findall(r"^```python\n(.*?)^```", text, re.S | re.M) if marker in b)
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "example.py"
        script.write_text(block, encoding="utf-8")
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        wall = time.perf_counter()
        subprocess.run([sys.executable, str(script)], cwd=tmp, check=True, capture_output=True,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg"))
        wall = time.perf_counter() - wall
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


def _timed(run: Callable[[], object]) -> tuple[object, float, float]:
    """run()'s value, its wall time and the process's CPU time [s]."""
    wall, cpu = time.perf_counter(), time.process_time()
    value = run()
    return value, time.perf_counter() - wall, time.process_time() - cpu


def identification() -> Numbers:
    """docs/guide/identification.md: its examples' own numbers (times, intervals, bands), the
    staircase and two-step workflows over noise draws, and the small fits on the damper's
    records (cases.identify's split and settings) that the page quotes."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")           # the fits' warnings about bounds: the page reads them
        return _identification_examples() | _identification_workflows() | _identification_damper()


def _identification_examples() -> Numbers:
    """The identification guide's examples: times as a script, and what the page reads of them."""
    out: Numbers = {}
    # the first example: Dahl and LuGre on one record, the other record predicted
    marker = 'dahl = stickslip.fit_friction("dahl", rec'
    ex = _page_example("identification", marker)
    dahl, lugre, rec, other = ex["dahl"], ex["lugre"], ex["rec"], ex["other"]
    wall, cpu = _script_times("identification", marker)
    out["ex1.wall"] = (wall, "s", "the first example's wall time, run as a script")
    out["ex1.cpu"] = (cpu, "s", "the first example's CPU time, run as a script")
    out["ex1.dbic"] = (lugre.bic - dahl.bic, "", "LuGre's BIC minus Dahl's")
    for fit in (dahl, lugre):
        out[f"ex1.{fit.law}.heldout_rmse"] = (fit.score(other)["rmse"], "N", f"{fit.law}'s rmse on the 1 Hz record")
    out["ex1.dahl.rho"] = (dahl.noise_correlation, "", "Dahl's residuals' lag-1 correlation")
    out["ex1.dahl.inflation"] = (dahl.variance_inflation, "", "(1 + rho)/(1 - rho)")
    out["ex1.dahl.widening"] = (dahl.variance_inflation ** 0.5, "", "sqrt of the inflation: the intervals' widening")
    out["ex1.range"] = (float(np.ptp(rec.force)), "N", "the 0.5 Hz record's force range")
    for name, r in (("rec", rec), ("other", other)):
        f, lo, hi = lugre.predict(r, interval=0.95)
        half = 0.5 * (hi - lo)
        out[f"ex1.lugre_band.{name}.median"] = (float(np.median(half)), "N", f"LuGre's 95 % band's median half-width, {name}")
        out[f"ex1.lugre_band.{name}.max"] = (float(np.max(half)), "N", f"its largest half-width, {name}")
        out[f"ex1.lugre_band.{name}.held"] = (float(np.mean((r.force >= lo) & (r.force <= hi))), "",
                                              f"the fraction of {name}'s samples inside it")

    wall, cpu = _script_times("identification", "fit_two_step(curve")
    out["ex2.wall"] = (wall, "s", "the two-step example's wall time, run as a script")
    out["ex2.cpu"] = (cpu, "s", "its CPU time, run as a script")
    # the offset and drift example
    ex = _page_example("identification", 'offset="fit", drift="fit"')
    out["ex3.plain.rmse"] = (ex["plain"].rmse, "N", "the fit without offset and drift: rmse")
    out["ex3.plain.mu_k_low"] = (1000.0 - ex["plain"].params["mu_k"], "N", "its mu_k below the truth")
    # the selection example: Dahl's calibrated 95 % half-width
    ex = _page_example("identification", "select_friction_law([")
    sel, t3, x3, v3 = ex["sel"], ex["t"], ex["x"], ex["v"]
    f, lo, hi = sel.fits["dahl"].predict(t3[1], x3[1], v=v3[1], interval=0.95)
    out["ex4.calibrated_half"] = (float(np.median(0.5 * (hi - lo))), "N", "Dahl's calibrated 95 % half-width")
    return out


def _identification_workflows() -> Numbers:
    """The experiment workflows on the two-step example's staircase (its truth and motion):
    the settling, the Stribeck curve's and the two steps' intervals over noise draws, and the
    refusal of a sine."""
    import re

    import stickslip as ss
    out: Numbers = {}
    ex = _page_example("identification", "fit_two_step(curve")
    truth, t, x, v = ex["truth"], ex["t"], ex["x"], ex["v"]
    exact = ss.prescribed_motion("lugre", t, x, v, **truth).force
    steady = ss.friction_coefficient("lugre", ss.steady_friction(t, x, exact, v=v).speed, **truth)
    raw = ss.steady_friction(t, x, exact, v=v, settle=0.0)
    out["stairs.unsettled"] = (float(np.max(np.abs(raw.force - steady))), "N",
                               "largest |step mean - steady force| with settle=0, noise-free")
    curve_names = ("mu_s", "mu_k", "v_s", "sigma2")
    hits = dict.fromkeys(curve_names, 0)
    draws = 200
    for seed in range(draws):
        rng = np.random.default_rng(100 + seed)
        curve = ss.fit_stribeck_curve(ss.steady_friction(t, x, exact + 5.0 * rng.standard_normal(t.size), v=v), "lugre")
        for k in curve_names:
            hits[k] += curve.ci95[k][0] <= truth[k] <= curve.ci95[k][1]
    out["stairs.draws"] = (float(draws), "", "noise draws of the staircase (5 N)")
    out["stairs.held.min"] = (float(min(hits.values())), "", "fewest intervals holding the truth, over the parameters")
    out["stairs.held.max"] = (float(max(hits.values())), "", "most")
    names = ("sigma0", "sigma1")
    est, own, carried, held_own, held = [], [], [], np.zeros(2), np.zeros(2)
    draws = 40
    for seed in range(draws):
        rng = np.random.default_rng(500 + seed)
        curve = ss.fit_stribeck_curve(ss.steady_friction(t, x, exact + 50.0 * rng.standard_normal(t.size), v=v), "lugre")
        rng = np.random.default_rng(900 + seed)
        ts, xs, vs, fs = [], [], [], []
        for amp, hz in ((2e-4, 5.0), (5e-4, 2.0)):          # the example's presliding records
            ti = np.linspace(0.0, 2.0 / hz, 401)
            ts.append(ti)
            xs.append(amp * np.sin(2 * np.pi * hz * ti))
            vs.append(amp * 2 * np.pi * hz * np.cos(2 * np.pi * hz * ti))
            fs.append(ss.prescribed_motion("lugre", ti, xs[-1], vs[-1], **truth).force
                      + 2.0 * rng.standard_normal(ti.size))
        two = ss.fit_two_step(curve, ts, xs, fs, v=vs)
        est.append([two.params[k] for k in names])
        own.append([two.dynamic.stderr[k] for k in names])
        carried.append([two.stderr[k] for k in names])
        held_own += [two.dynamic.ci95[k][0] <= truth[k] <= two.dynamic.ci95[k][1] for k in names]
        held += [two.ci95[k][0] <= truth[k] <= two.ci95[k][1] for k in names]
    out["two_step.draws"] = (float(draws), "", "noise draws (50 N on the staircase, 2 N on the presliding records)")
    for i, k in enumerate(names):
        out[f"two_step.{k}.scatter"] = (float(np.std(np.array(est)[:, i], ddof=1)), "", f"{k}'s estimates' sd")
        out[f"two_step.{k}.own_se"] = (float(np.mean(np.array(own)[:, i])), "", f"{k}'s conditional standard error, mean")
        out[f"two_step.{k}.carried_se"] = (float(np.mean(np.array(carried)[:, i])), "",
                                           f"{k}'s standard error with step 1's carried, mean")
    out["two_step.own_held"] = (float(held_own.mean() / draws), "", "fraction of conditional intervals holding the truth")
    out["two_step.carried_held"] = (float(held.mean() / draws), "", "fraction of carried intervals holding the truth")

    # a sine is not a staircase: the refusal's numbers on the damper's 0.5 Hz record
    sine = ss.load_damper_record(ss.data.DAMPER_DIR / "sine_0.5Hz_1in_36lb.csv.gz")
    try:
        ss.steady_friction(sine)
        raise RuntimeError("steady_friction accepted a sine")
    except ValueError as err:
        m = re.search(r"(\d+) run\(s\) .*?\(([0-9.]+)-([0-9.]+) ms\), (\d+) of them .*?covering ([0-9.]+) % of the "
                      r"record's moving time \(([0-9.]+) s\)", str(err))
        for key, g in zip(("runs", "shortest_ms", "longest_ms", "constant", "percent", "moving_s"), m.groups()):
            out[f"sine_refused.{key}"] = (float(g), "", f"the refusal's {key}")
    return out


def _identification_damper() -> Numbers:
    """Small fits on the damper's records with cases.identify's split and settings: offset and
    drift, calibrated bands, several starts, LuGre's cost off a zero backlash, GMS's standard
    errors against the step, the elasto-plastic law's cost against z_ba_ratio."""
    import dataclasses

    import stickslip as ss
    from cases import identify as ci
    from harness.files import read_csv
    from stickslip import identify as I
    out: Numbers = {}
    groups = ci.load_groups(ss.damper_files())
    kw = dict(backlash="fit", asymmetry="fit", n_starts=1, rtol=ci.RTOL, diff_step=ci.DIFF_STEP)
    for group in ("30lb", "36lb"):
        train = [r for r, tr in groups[group] if tr]
        held_recs = [r for r, tr in groups[group] if not tr]
        plain = ss.fit_friction("dahl", train, **kw)
        fit = ss.fit_friction("dahl", train, offset="fit", drift="fit", **kw)
        out[f"damper.{group}.offset"] = (fit.params["offset"], "N", "Dahl's fitted offset")
        out[f"damper.{group}.offset_se"] = (fit.stderr["offset"], "N", "its standard error")
        out[f"damper.{group}.drift_pct"] = (-100.0 * fit.params["drift"], "%/s", "the level's fall a second")
        out[f"damper.{group}.drift_se_pct"] = (100.0 * fit.stderr["drift"], "%/s", "its standard error")
        for name, f_ in (("plain", plain), ("drift", fit)):
            out[f"damper.{group}.{name}.nrmse_pct"] = (100.0 * f_.nrmse, "%", f"fitted nrmse, {name}")
            out[f"damper.{group}.{name}.heldout_pct"] = (100.0 * f_.score(held_recs)["nrmse"], "%",
                                                         f"held-out nrmse, {name}")
    # the calibrated prediction intervals at 36 lb
    train = [r for r, tr in groups["36lb"] if tr]
    held_recs = [r for r, tr in groups["36lb"] if not tr]
    fit, _, cpu = _timed(lambda: ss.fit_friction("dahl", train, calibrate=True, **kw))
    out["calibrated.cpu"] = (cpu, "s", "Dahl's fit with calibrate=True on five records: CPU")
    plain = dataclasses.replace(fit, heldout_residuals=None)
    forces = np.concatenate([r.force for r in held_recs])
    for name, f_ in (("calibrated", fit), ("alone", plain)):
        for q in (0.5, 0.95):
            bands = [f_.predict(r, interval=q) for r in held_recs]
            lo_, hi_ = np.concatenate([b[1] for b in bands]), np.concatenate([b[2] for b in bands])
            out[f"calibrated.{name}.{q:g}.held_pct"] = (100.0 * float(np.mean((forces >= lo_) & (forces <= hi_))),
                                                        "%", f"{name} {q:g} band: held-out samples inside")
            out[f"calibrated.{name}.{q:g}.half_kN"] = (float(np.median(0.5 * (hi_ - lo_))) / 1e3, "kN",
                                                       f"{name} {q:g} band: median half-width")
    out["calibrated.fit_sd_kN"] = (fit.residual_sd / 1e3, "kN", "the fit's residual standard deviation")
    out["calibrated.heldout_rms_kN"] = (fit.score(held_recs)["rmse"] / 1e3, "kN", "the held-out records' rmse")

    # the ten 36 lb records
    ten = [r for r, _ in groups["36lb"]]
    dahl10 = ss.fit_friction("dahl", ten, **kw)
    out["ten.dahl.aic"] = (dahl10.aic, "", "Dahl's AIC on the ten 36 lb records")
    out["ten.dahl.bic"] = (dahl10.bic, "", "its BIC")
    out["ten.dahl.bic_lmfit"] = (dahl10.bic_lmfit, "", "its BIC in lmfit's definition")
    # several starts (default rtol and diff_step): each start's cost, the CPU time of one and of three
    for law in ("lugre", "dahl", "gms"):
        for n in (1, 3):
            fit, _, cpu = _timed(lambda: ss.fit_friction(law, ten, backlash="fit", asymmetry="fit", n_starts=n,
                                                         fixed=ci.fixed_for(law)))
            out[f"starts.{law}.{n}.cpu"] = (cpu, "s", f"{law}'s CPU time, {n} start(s), default rtol")
            out[f"starts.{law}.{n}.cost"] = (fit.cost, "N^2", f"{law}'s final cost (half the sum of squares), "
                                              f"{n} start(s)")
        for i, cost in enumerate(fit.start_costs):
            out[f"starts.{law}.start{i + 1}"] = (float(cost), "N^2", f"{law}: the cost start {i + 1} ended at")
    lugre10 = ss.fit_friction("lugre", ten, **dict(kw, fixed=ci.fixed_for("lugre")))
    # LuGre's cost just off a backlash of 0, in reduced chi-squares
    data = I._records(ten, None, None, None, None)
    forces = np.concatenate([d.force for d in data])

    def ssr(backlash: float) -> float:
        p = dict(lugre10.params, backlash=backlash)
        r = np.concatenate([I._model("lugre", d, I._record_params(p, i), ci.RTOL) for i, d in enumerate(data)])
        return float((r - forces) @ (r - forces))
    jumps = [(ssr(b) - ssr(0.0)) / lugre10.redchi for b in (1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7)]
    out["lugre_backlash.at_zero"] = (float(lugre10.params["backlash"]), "m", "LuGre's fitted backlash, ten records")
    out["lugre_backlash.jump_min"] = (min(jumps), "s^2", "the cost's rise at 1e-12 to 1e-7 m, least")
    out["lugre_backlash.jump_max"] = (max(jumps), "s^2", "the most")
    # GMS's mu_s standard error against the finite-difference step, five fitted records
    for step in (1e-2, 3e-3, 1e-3):
        fit = ss.fit_friction("gms", train, **dict(kw, diff_step=step, fixed=ci.fixed_for("gms")))
        out[f"gms_se.{step:g}"] = (fit.stderr["mu_s"], "N", f"GMS's mu_s standard error at diff_step {step:g}")
    # the elasto-plastic law's transition: one evaluation along a record against z_ba_ratio
    sine = ss.load_damper_record(ss.data.DAMPER_DIR / "sine_0.5Hz_1in_36lb.csv.gz")
    c = read_csv(ROOT / "docs" / "figures" / "identify_params.csv")
    p = {name: float(value) for group, law, name, value in zip(c["group [-]"], c["law [-]"], c["parameter [-]"],
                                                                c["value [unit]"])
         if group == "36lb" and law == "elastoplastic"}
    law_p = {k: p[k] for k in ss.REGISTRY["law"]["elastoplastic"]["params"] if k in p}
    for ratio in (0.999, 0.999999):
        _, _, cpu = _timed(lambda: ss.prescribed_motion("elastoplastic", sine.t, sine.x, sine.v, rtol=1e-6,
                                                        backlash=p["backlash"], asymmetry=p["asymmetry"],
                                                        **dict(law_p, z_ba_ratio=ratio)))
        out[f"z_ba.{ratio:g}.cpu"] = (cpu, "s", f"one evaluation along the full-rate 0.5 Hz 36 lb record at "
                                      f"z_ba_ratio {ratio:g} (cases.identify's 36 lb fit otherwise)")
    return out


PAGES: dict[str, Callable[[], Numbers]] = {"models": models, "friction-laws": friction_laws,
                                           "exact-stick": exact_stick, "implicit-nonsmooth": implicit_nonsmooth,
                                           "identification": identification}

def implicit_nonsmooth_slope(outdir: Path) -> Path:
    """docs/guide/implicit-nonsmooth.md's slope table: the box on a 25 deg slope (mu_k = 0.6,
    mu_s = 0.7, v0 = 2 m/s, v_s = 1e-10 m/s) sliding to its closed-form stop, under the
    fixed-step implicit methods: errors of x and of the stop time, evaluations per step."""
    import math

    import stickslip as ss
    from harness.files import write_csv
    th, mu_k, mu_s, v0 = math.radians(25.0), 0.6, 0.7, 2.0
    a = 9.81 * (mu_k * math.cos(th) - math.sin(th))
    t_stop, x_stop = v0 / a, v0 ** 2 / (2.0 * a)
    rows = []
    for method in ("implicit_euler", "galpha"):
        for h in (1e-2, 1e-3, 1e-4):
            r = ss.simulate("slope", "coulomb", method=method, h=h, t_end=t_stop + 1.0, every_step=True, v0=v0,
                            theta_deg=25.0, mu_k=mu_k, mu_s=mu_s, v_s=1e-10)
            stop = r.t[np.flatnonzero(r.v == 0.0)[0]]
            rows.append([method, h, float(r.x[-1] - x_stop), float(stop - t_stop),
                         r.stats["nfev"] / r.stats["nstep"]])
    return write_csv(outdir / "guide_implicit_nonsmooth_slope.csv",
                     ["method [-]", "h [s]", "x_end - x_stop [m]", "t_stop error [s]", "nfev/step [-]"], rows)


def implicit_nonsmooth_belt(outdir: Path) -> Path:
    """docs/guide/implicit-nonsmooth.md's belt table: the Coulomb cycle (m = 2 kg, k = 50 N/m,
    v_b = 0.2 m/s, mu_s = 0.5, mu_k = 0.3, v_s = dv = 1e-10 m/s) started stuck at its re-stick
    point, over 3.2 periods: largest errors of the periods between stick onsets and of the
    extremes against the closed form, Coulomb and Karnopp."""
    import math

    import stickslip as ss
    from harness.files import write_csv
    g, par = 9.81, dict(m=2.0, k=50.0, v_b=0.2, mu_s=0.5, mu_k=0.3)
    w = math.sqrt(par["k"] / par["m"])
    x_k, x_s = par["mu_k"] * par["m"] * g / par["k"], par["mu_s"] * par["m"] * g / par["k"]
    amp = math.hypot(x_s - x_k, par["v_b"] / w)
    period = (math.pi + 2 * math.asin(par["v_b"] / (amp * w))) / w + 2 * (x_s - x_k) / par["v_b"]
    rows = []
    for law, narrow in (("coulomb", dict(v_s=1e-10)), ("karnopp", dict(dv=1e-10))):
        for method in ("implicit_euler", "galpha"):
            for h in (1e-2, 1e-3, 1e-4):
                r = ss.simulate("belt", law, method=method, h=h, t_end=3.2 * period, every_step=True,
                                x0=2 * x_k - x_s, v0=par["v_b"], **par, **narrow)
                stuck = np.abs(par["v_b"] - r.v) <= 2.0 * narrow.get("dv", 0.0)
                onsets = r.t[1:][stuck[1:] & ~stuck[:-1]]
                rows.append([law, method, h, float(np.abs(np.diff(onsets) - period).max()),
                             float(r.x.max() - (x_k + amp)), float(r.x.min() - (x_k - amp)),
                             r.stats["nfev"] / r.stats["nstep"]])
    return write_csv(outdir / "guide_implicit_nonsmooth_belt.csv",
                     ["law [-]", "method [-]", "h [s]", "period [s]", "max x [m]", "min x [m]", "nfev/step [-]"], rows)


def implicit_nonsmooth_gms(outdir: Path) -> Path:
    """docs/guide/implicit-nonsmooth.md's GMS table: the largest position error of the
    fixed-step implicit methods at h = 1e-3 and 1e-4 s against RADAU5 at rtol = 1e-10 (0.5 s)."""
    import stickslip as ss
    from harness.files import write_csv
    rows = []
    for name, scene, kw in (("slope", "slope", {}), ("belt, from rest", "belt", {}),
                            ("belt, started stuck (through break-away)", "belt", {"v0": 1.5}),
                            ("chain of 3 blocks", "chain", {"n_blocks": 3})):
        ref = ss.simulate(scene, "gms", method="radau5", rtol=1e-10, atol=1e-13, t_end=0.5, n_out=21, **kw)
        rows.append([name, *(float(np.abs(ss.simulate(scene, "gms", method=method, h=h, t_end=0.5, n_out=21,
                                                      **kw).x - ref.x).max())
                             for method in ("implicit_euler", "galpha") for h in (1e-3, 1e-4))])
    return write_csv(outdir / "guide_implicit_nonsmooth_gms.csv",
                     ["scene [-]", "implicit_euler h 1e-3 [m]", "implicit_euler h 1e-4 [m]", "galpha h 1e-3 [m]",
                      "galpha h 1e-4 [m]"], rows)


#: The tables a page's measurements also write (page -> writers of outdir).
TABLES: dict[str, list[Callable[[Path], Path]]] = {
    "exact-stick": [exact_stick_stacked],
    "implicit-nonsmooth": [implicit_nonsmooth_slope, implicit_nonsmooth_belt, implicit_nonsmooth_gms]}


def main(argv: Sequence[str] | None = None) -> list[Path]:
    p = argparse.ArgumentParser(prog="python tools/guide_numbers.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--outdir", type=Path, required=True, help="where to write guide_<page>.json")
    p.add_argument("--page", choices=sorted(PAGES), action="append",
                   help="a page's numbers only (repeatable; default: every page)")
    args = p.parse_args(argv)
    import stickslip as ss
    # the guides measure the regularised laws' bands on purpose: their warnings are expected
    warnings.filterwarnings("ignore", category=ss.RegularisedLawWarning)
    paths = []
    for page in args.page or sorted(PAGES):
        paths.append(write_text(args.outdir / f"guide_{page.replace('-', '_')}.json", numbers_json(PAGES[page]())))
        paths += [write(args.outdir) for write in TABLES.get(page, [])]
        print("\n".join(map(str, paths)))
    write_provenance(args.outdir, "tools.guide_numbers", paths, argv if argv is not None else sys.argv[1:])
    return paths


if __name__ == "__main__":
    main()
