"""The benchmark driver: build the compiled programs, time every tool on the same scenes and
laws, and write ``benchmarks.csv``, ``benchmarks.png`` and ``summary.md`` into --outdir.

Sections (the ``section`` column of the CSV):

- ``fixed``: classical RK4 with a fixed step, ns per step and per right-hand-side evaluation,
  as ratios to the plain C loop of the same scene and law. GSL's rk4 does step doubling (one
  step of h is two classical steps of h/2 plus an error estimate, 11-12 evaluations): compare
  it per evaluation.
- ``adaptive``: the adaptive methods at a few tolerances (rtol = atol = tol), ns per step and
  per evaluation, and the error at t_end against a tight reference (stickslip DOPRI5 at
  tol = 1e-13, cross-checked with GSL rk8pd at 1e-13), as ratios to stickslip DOPRI5 called
  from Fortran at the same tolerance.
- ``equal_accuracy``: for each method the time to reach an error target, interpolated in
  log-log along its work-precision curve, as a ratio to stickslip DOPRI5 (Fortran).
- ``overhead``: short runs (OVERHEAD) through ``stickslip.simulate`` and through a bare call
  of the f2py wrapper's run of the setting's handle (what simulate calls per run),
  interleaved; ``overhead_s`` is the median of the per-call differences, what the Python
  facade adds per call.
- ``exact_stick`` and ``exact_stick_equal``: set-valued Coulomb friction by ``moreau`` and
  ``event_driven`` against the smooth laws (RK4, DOPRI5) on two problems with exact answers
  (``cases.stick``: the slope sliding to a stop, error |x(t_end) - x_stop|; the belt started
  stuck, error max |x - x_exact| on the output grid); then, per error target, the time of each
  nonsmooth method as a ratio to the best smooth-law run that reaches it (none may).
- ``dop853`` and ``dop853_equal_error``: stickslip DOP853 against stickslip DOPRI5 and GSL
  rk8pd (all compiled, output at t_end) on the belt with the proposed law at the tolerances
  ``dop853_tols``, then at the error targets ``dop853_targets``: time, evaluations and
  instructions interpolated in log-log along each work-precision curve, as ratios to DOP853
  (``median_s``, ``nfev`` and ``instr_per_eval`` of those rows are the interpolated values).
- ``chain`` and ``chain_banded``: time per step on the chain of ``n_blocks`` blocks (CHAIN_RUNS,
  N in ``chain_sizes``) with the fitted exponent of time per step against N, and RADAU5 with
  its banded Jacobian and LU against the dense path (``banded=False``) at ``chain_dense_sizes``
  (``ratio_time`` = dense / banded).

Times are medians of several samples; each sample repeats a run until it lasts long enough.
Nothing asserts an absolute time: the machine is shared. The compiled adaptive runs also get a
deterministic measure, ``instr_per_eval``: instructions per right-hand-side evaluation counted
by valgrind's callgrind (the difference between 3 runs and 1, so start-up cancels), when
valgrind is installed (not with --quick unless --callgrind).

Single studies instead of the whole run: --identify (identify.md: two fits of the damper
records, prescribed_motion per sample), --lmfit (lmfit.md, lmfit.csv: every law fitted by
stickslip and by the same fit written with lmfit, benchmarks/lmfit_compare.py), --prescribed
(prescribed.md: prescribed_motion's CPU time per law, benchmarks/prescribed_speed.py),
--contact (contact.md: the contact solver), --modal-chain [--baseline PYTHON] (modal_chain.md:
implicit_euler, galpha and moreau on the chain, against another build where given,
benchmarks/modal_chain.py), --presets --base SITE [--instructions] (presets.md: the scenes as
presets against a build of the scene code they replaced, with valgrind's instruction counts
where asked, benchmarks/presets.py), --clutches (clutches.md: event_driven on Modelica's
CoupledClutches against a scipy event-driven solver at equal accuracy, cases/gallery_clutches.py),
--overhead (the ``overhead`` section alone, put in place of the old one in summary.md and
benchmarks.csv).
"""
from __future__ import annotations

import argparse
import csv
import datetime as _dt
import math
import os
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from harness.cli import add_outdir, check_writable, cli_description, int_at_least
from harness.files import atomic_write, write_text   # one way to write a file whole or not at all
from harness.provenance import machine, write_provenance
from harness.timing import median_time, python_jac, python_rhs, time_at_error

ROOT = Path(__file__).resolve().parents[1]
#: The tracked results the documentation quotes (written only with --results).
RESULTS_DIR = ROOT / "benchmarks" / "results"
BIN = Path(sys.executable).parent

FIELDS: tuple[str, ...] = (
    "section", "impl", "method", "scene", "law", "t_end_s", "h_s", "tol", "target_err",
    "repeats", "median_s", "nstep", "nfev", "ns_per_step", "ns_per_eval", "instr_per_eval", "x_end_m",
    "v_end_m_s", "err", "err_x_m", "err_v_m_s", "reference", "ratio_step", "ratio_eval", "ratio_time", "overhead_s", "n_blocks",
)
REFERENCE_TOL = 1e-13
#: Fixed-step implicit methods timed beside RK4 (from Python, default controls).
IMPLICIT_FIXED: tuple[str, ...] = ("implicit_euler", "galpha")
#: scipy methods that take the analytic Jacobian (python_jac).
SCIPY_IMPLICIT: tuple[str, ...] = ("Radau", "BDF", "LSODA")


@dataclass
class Config:
    """What to run; --quick shrinks everything to a few seconds."""

    fixed: list[tuple[str, str, float, float]]          # scene, law, t_end [s], h [s]
    adaptive: list[tuple[str, str]]                      # scene, law
    t_end_adaptive: float                                # [s]
    tols: list[float]
    targets: list[float]                                 # error targets for equal accuracy
    repeats: int
    min_sample: float                                    # [s]
    scipy_methods: list[str] = field(default_factory=lambda: ["RK45", "DOP853", "LSODA", "Radau"])
    callgrind: bool = False                              # count instructions of the compiled adaptive runs
    # exact_stick (run_exact_stick): t_end [s], RK4/moreau steps [s], DOPRI5/event_driven tolerances,
    # error targets [m]
    t_end_stick: float = 5.0
    stick_steps: tuple[float, ...] = (1e-2, 1e-3, 1e-4)
    stick_tols: tuple[float, ...] = (1e-4, 1e-6, 1e-8, 1e-10)
    stick_targets: tuple[float, ...] = (1e-2, 1e-3, 1e-5, 1e-8)
    dop853_tols: list[float] = field(default_factory=lambda: [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12,
                                                              1e-13])
    dop853_targets: list[float] = field(default_factory=lambda: [1e-7, 1e-8, 1e-9, 1e-10])
    # chain (run_chain): block counts of the per-step cost, those of RADAU5 banded against dense
    chain_sizes: tuple[int, ...] = (10, 100, 1000)
    chain_dense_sizes: tuple[int, ...] = (50, 100, 200)


FULL = Config(
    fixed=[("belt", "proposed", 20.0, 1e-5), ("belt", "recurdyn", 5.0, 1e-5),
           ("belt", "coulomb", 5.0, 1e-5), ("slope", "proposed", 5.0, 1e-5)],
    adaptive=[("belt", "proposed"), ("belt", "recurdyn"), ("slope", "proposed")],
    t_end_adaptive=20.0, tols=[1e-4, 1e-6, 1e-8, 1e-10], targets=[1e-5, 1e-7, 1e-9],
    repeats=5, min_sample=0.05)
QUICK = Config(
    fixed=[("belt", "proposed", 0.2, 1e-5)],
    adaptive=[("belt", "proposed")],
    t_end_adaptive=2.0, tols=[1e-4, 1e-7], targets=[1e-5],
    repeats=1, min_sample=0.0, t_end_stick=2.5, stick_steps=(1e-3, 1e-4), stick_tols=(1e-4, 1e-8),
    stick_targets=(1e-3, 1e-5), dop853_tols=[1e-6, 1e-9], dop853_targets=[1e-7], chain_sizes=(10, 100),
    chain_dense_sizes=(20, 40))


# -- helpers ----------------------------------------------------------------------------------

def _tool(name: str) -> str:
    path = BIN / name
    found = str(path) if path.exists() else shutil.which(name)
    if found is None:
        raise SystemExit(f"benchmarks: {name} not found (activate the venv)")
    return found


def _env() -> dict[str, str]:
    return dict(os.environ, PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}")


def build(build_dir: Path) -> dict[str, Path]:
    """Configure (once) and compile the benchmark programs; returns name -> executable."""
    meson = _tool("meson")
    if not (build_dir / "build.ninja").exists():
        subprocess.run([meson, "setup", str(build_dir), str(ROOT)], check=True, env=_env(),
                       capture_output=True, text=True)
    targets = ["bench_fortran", "bench_cloop"]
    intro = subprocess.run([meson, "introspect", "--targets", str(build_dir)], capture_output=True,
                           text=True, env=_env())
    if '"bench_gsl"' in intro.stdout:
        targets.append("bench_gsl")
    proc = subprocess.run([meson, "compile", "-C", str(build_dir), *targets], env=_env(),
                          capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"benchmarks: build failed\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return {t: build_dir / t for t in targets}


def run_program(exe: Path, scene: str, law: str, method: str, t_end: float, h_or_tol: float,
                cfg: Config) -> dict[str, float]:
    """One compiled benchmark: median seconds per integration, counters and final state."""
    out = subprocess.run([str(exe), scene, law, method, repr(t_end), repr(h_or_tol), str(cfg.repeats),
                          repr(cfg.min_sample)], check=True, capture_output=True, text=True).stdout
    med, nfev, nstep, x, v = out.split()
    return {"median_s": float(med), "nfev": int(nfev), "nstep": int(nstep), "x": float(x), "v": float(v)}


def count_instructions(exe: Path, scene: str, law: str, method: str, t_end: float, h_or_tol: float) -> float:
    """Instructions of one integration by a compiled benchmark, counted by callgrind: a program
    given MIN_SAMPLE_S = 0 runs 1 + REPEATS integrations, so (I(REPEATS=3) - I(REPEATS=1)) / 2 is
    one run without the start-up. Deterministic on a given build and machine."""
    counts = []
    for repeats in (1, 3):
        proc = subprocess.run([_tool("valgrind"), "--tool=callgrind", "--callgrind-out-file=/dev/null", str(exe),
                               scene, law, method, repr(t_end), repr(h_or_tol), str(repeats), "0"],
                              check=True, capture_output=True, text=True)
        found = [line for line in proc.stderr.splitlines() if "Collected :" in line]
        if not found:
            raise SystemExit(f"benchmarks: no callgrind count for {exe.name}\n{proc.stderr[-2000:]}")
        counts.append(int(found[-1].split(":")[-1]))
    return (counts[1] - counts[0]) / 2.0


def time_python(fn: Callable[[], object], cfg: Config) -> tuple[float, object]:
    """Median seconds of fn() over cfg.repeats samples of at least cfg.min_sample each."""
    return median_time(fn, cfg.repeats, cfg.min_sample)


#: Short runs for the facade's per-call overhead: scene, law, method, t_end [s], h or tol.
OVERHEAD: tuple[tuple[str, str, str, float, float], ...] = (
    ("belt", "recurdyn", "dopri5", 20.0, 1e-4), ("belt", "proposed", "dopri5", 20.0, 1e-4),
    ("slope", "proposed", "radau5", 20.0, 1e-6), ("slope", "proposed", "rk4", 0.01, 1e-3))


# -- rows ---------------------------------------------------------------------------------------

def _row(section: str, impl: str, method: str, scene: str, law: str, t_end: float, *,
         h: float = float("nan"), tol: float = float("nan"), target: float = float("nan"),
         repeats: int = 0, median_s: float = float("nan"), nstep: int = 0, nfev: int = 0,
         x: float = float("nan"), v: float = float("nan"), err: float = float("nan"),
         err_x: float = float("nan"), err_v: float = float("nan")) -> dict:
    return {"section": section, "impl": impl, "method": method, "scene": scene, "law": law,
            "t_end_s": t_end, "h_s": h, "tol": tol, "target_err": target, "repeats": repeats,
            "median_s": median_s, "nstep": nstep, "nfev": nfev,
            "ns_per_step": 1e9 * median_s / nstep if nstep else float("nan"),
            "ns_per_eval": 1e9 * median_s / nfev if nfev else float("nan"), "instr_per_eval": float("nan"),
            "x_end_m": x, "v_end_m_s": v, "err": err, "err_x_m": err_x, "err_v_m_s": err_v, "reference": "",
            "ratio_step": float("nan"), "ratio_eval": float("nan"), "ratio_time": float("nan"),
            "overhead_s": float("nan"), "n_blocks": 1}


def state_errors(x: float, v: float, yref: np.ndarray) -> dict[str, float]:
    """_row's error arguments for a run ending at position x [m] and speed v [m/s] against the
    reference state `yref` = (x, v): err_x [m] and err_v [m/s], each floored at 1e-16 (a log
    axis), and err, the larger of the two: the norm every tool's atol = rtol controls."""
    err_x, err_v = max(abs(x - float(yref[0])), 1e-16), max(abs(v - float(yref[1])), 1e-16)
    return {"err": max(err_x, err_v), "err_x": err_x, "err_v": err_v}


def run_fixed(cfg: Config, exes: dict[str, Path], log: Callable[[str], None]) -> list[dict]:
    import stickslip

    rows: list[dict] = []
    for scene, law, t_end, h in cfg.fixed:
        group: list[dict] = []
        r = run_program(exes["bench_cloop"], scene, law, "rk4", t_end, h, cfg)
        group.append(_row("fixed", "c_loop", "rk4", scene, law, t_end, h=h, repeats=cfg.repeats,
                          median_s=r["median_s"], nstep=r["nstep"], nfev=r["nfev"], x=r["x"], v=r["v"]))
        r = run_program(exes["bench_fortran"], scene, law, "rk4", t_end, h, cfg)
        group.append(_row("fixed", "stickslip_fortran", "rk4", scene, law, t_end, h=h, repeats=cfg.repeats,
                          median_s=r["median_s"], nstep=r["nstep"], nfev=r["nfev"], x=r["x"], v=r["v"]))
        med, res = time_python(lambda: stickslip.simulate(scene, law, method="rk4", t_end=t_end, h=h,
                                                          n_out=2), cfg)
        group.append(_row("fixed", "stickslip_python", "rk4", scene, law, t_end, h=h, repeats=cfg.repeats,
                          median_s=med, nstep=res.stats["nstep"], nfev=res.stats["nfev"],
                          x=float(res.x[-1]), v=float(res.v[-1])))
        for method in IMPLICIT_FIXED:     # per step: Newton with the analytic Jacobian and one LU
            med, res = time_python(lambda: stickslip.simulate(scene, law, method=method, t_end=t_end, h=h,
                                                              n_out=2), cfg)
            group.append(_row("fixed", "stickslip_python", method, scene, law, t_end, h=h, repeats=cfg.repeats,
                              median_s=med, nstep=res.stats["nstep"], nfev=res.stats["nfev"],
                              x=float(res.x[-1]), v=float(res.v[-1])))
        if "bench_gsl" in exes:
            r = run_program(exes["bench_gsl"], scene, law, "rk4", t_end, h, cfg)
            group.append(_row("fixed", "gsl", "rk4 (step doubling)", scene, law, t_end, h=h,
                              repeats=cfg.repeats, median_s=r["median_s"], nstep=r["nstep"],
                              nfev=r["nfev"], x=r["x"], v=r["v"]))
        ref = group[0]
        for row in group:
            row["reference"] = "c_loop"
            row["ratio_step"] = row["ns_per_step"] / ref["ns_per_step"]
            row["ratio_eval"] = row["ns_per_eval"] / ref["ns_per_eval"]
            row["ratio_time"] = row["median_s"] / ref["median_s"]
            log(f"fixed {scene:5s} {law:8s} {row['impl']:18s} {row['ns_per_step']:9.1f} ns/step "
                f"{row['ns_per_eval']:7.1f} ns/eval  x{row['ratio_step']:.2f}")
        rows += group
    return rows


def run_adaptive(cfg: Config, exes: dict[str, Path], log: Callable[[str], None]) -> list[dict]:
    import stickslip
    from scipy.integrate import solve_ivp

    rows: list[dict] = []
    t_end = cfg.t_end_adaptive
    for scene, law in cfg.adaptive:
        ref = run_program(exes["bench_fortran"], scene, law, "dopri5", t_end, REFERENCE_TOL,
                          Config(**{**cfg.__dict__, "repeats": 1, "min_sample": 0.0}))
        yref = np.array([ref["x"], ref["v"]])
        if "bench_gsl" in exes:
            chk = run_program(exes["bench_gsl"], scene, law, "rk8pd", t_end, REFERENCE_TOL,
                              Config(**{**cfg.__dict__, "repeats": 1, "min_sample": 0.0}))
            check = state_errors(chk["x"], chk["v"], yref)
            floor = check["err"]
            rows.append(_row("reference", "gsl", "rk8pd", scene, law, t_end, tol=REFERENCE_TOL,
                             x=chk["x"], v=chk["v"], **check))
            log(f"reference {scene} {law}: stickslip dopri5 vs gsl rk8pd at 1e-13 differ by {floor:.2e}")

        for tol in cfg.tols:
            group: list[dict] = []
            r = run_program(exes["bench_fortran"], scene, law, "dopri5", t_end, tol, cfg)
            group.append(_row("adaptive", "stickslip_fortran", "dopri5", scene, law, t_end, tol=tol,
                              repeats=cfg.repeats, median_s=r["median_s"], nstep=r["nstep"], nfev=r["nfev"],
                              x=r["x"], v=r["v"], **state_errors(r["x"], r["v"], yref)))
            if cfg.callgrind:
                group[-1]["instr_per_eval"] = count_instructions(exes["bench_fortran"], scene, law, "dopri5",
                                                                 t_end, tol) / r["nfev"]
            for method in ("dopri5", "radau5"):
                med, res = time_python(lambda: stickslip.simulate(
                    scene, law, method=method, t_end=t_end, rtol=tol, atol=tol, hmin=0.0, hmax=t_end,
                    n_out=2, max_steps=10**8), cfg)
                x, v = float(res.x[-1]), float(res.v[-1])
                group.append(_row("adaptive", "stickslip_python", method, scene, law, t_end, tol=tol,
                                  repeats=cfg.repeats, median_s=med, nstep=res.stats["nstep"],
                                  nfev=res.stats["nfev"], x=x, v=v, **state_errors(x, v, yref)))
            if "bench_gsl" in exes:
                for m in ("rkf45", "rkck", "rk8pd"):
                    r = run_program(exes["bench_gsl"], scene, law, m, t_end, tol, cfg)
                    group.append(_row("adaptive", "gsl", m, scene, law, t_end, tol=tol, repeats=cfg.repeats,
                                      median_s=r["median_s"], nstep=r["nstep"], nfev=r["nfev"],
                                      x=r["x"], v=r["v"], **state_errors(r["x"], r["v"], yref)))
                    if cfg.callgrind:
                        group[-1]["instr_per_eval"] = count_instructions(exes["bench_gsl"], scene, law, m,
                                                                         t_end, tol) / r["nfev"]
            f, jac = python_rhs(scene, law), python_jac(scene, law)
            for m in cfg.scipy_methods:
                sc = Config(**{**cfg.__dict__, "repeats": min(cfg.repeats, 3), "min_sample": 0.0})
                kw = {"jac": jac} if m in SCIPY_IMPLICIT else {}
                med, sol = time_python(lambda: solve_ivp(f, (0.0, t_end), [0.0, 0.0], method=m, rtol=tol,
                                                         atol=tol, **kw), sc)
                x, v = float(sol.y[0, -1]), float(sol.y[1, -1])
                nstep = len(sol.t) - 1
                group.append(_row("adaptive", "scipy", m, scene, law, t_end, tol=tol, repeats=sc.repeats,
                                  median_s=med, nstep=nstep, nfev=int(sol.nfev), x=x, v=v,
                                  **(state_errors(x, v, yref) if sol.success else {})))
            base = group[0]
            for row in group:
                row["reference"] = "stickslip_fortran dopri5"
                row["ratio_step"] = row["ns_per_step"] / base["ns_per_step"]
                row["ratio_eval"] = row["ns_per_eval"] / base["ns_per_eval"]
                row["ratio_time"] = row["median_s"] / base["median_s"]
                log(f"adaptive {scene:5s} {law:8s} tol={tol:.0e} {row['impl']:18s} {row['method']:7s} "
                    f"{1e6 * row['median_s']:10.1f} us  err={row['err']:.1e}  {row['ns_per_eval']:8.1f} ns/eval "
                    f"x{row['ratio_eval']:.2f}/eval")
            rows += group
    return rows


#: Calls of each OVERHEAD run, alternating with as many bare calls of the wrapper.
OVERHEAD_CALLS = 3000
#: The run of issue 32's goal (scene, law, method, steps) and the goal: simulate at most this
#: long per call on a quiet machine [s].
OVERHEAD_GOAL_RUN = ("slope", "proposed", "rk4", 10)
OVERHEAD_GOAL_S = 5e-6


def run_overhead(cfg: Config, exes: dict[str, Path], log: Callable[[str], None]) -> list[dict]:
    """Rows of the ``overhead`` section: for each OVERHEAD run (rtol = atol = tol, hmin = 0,
    hmax = t_end; output at t_end), OVERHEAD_CALLS calls of ``stickslip.simulate`` (its arguments
    written out in the call, as in a user's code) interleaved
    with as many bare calls of the f2py wrapper's run_prepared on the handle of the setting (the
    library call simulate makes per run, and nothing else: stickslip.core.bare_call; the
    wrapper reads the clock for stats["cpu_seconds"] itself), alternating which goes first.
    median_s: the median time of each; overhead_s (on the simulate row): the median of the
    per-pair differences, what the facade adds per call."""
    import stickslip
    from stickslip.core import bare_call

    rows: list[dict] = []
    clock = time.perf_counter
    for scene, law, method, t_end, hp in OVERHEAD:
        fixed = method == "rk4"
        kw = dict(h=hp) if fixed else dict(rtol=hp, atol=hp, hmin=0.0, hmax=t_end, max_steps=10**8)
        step = dict(h=hp) if fixed else dict(tol=hp)
        # the call as a user's code writes it, every argument written out (not unpacked from
        # a dict, which costs the call a dict of its own)
        written = ", ".join(f"{k}={v!r}" for k, v in kw.items())
        sim = eval(f"lambda: simulate({scene!r}, {law!r}, method={method!r}, t_end={t_end!r}, n_out=2, "
                   f"{written})", {"simulate": stickslip.simulate})
        bare = bare_call(scene, law, method=method, t_end=t_end, n_out=2, **kw)
        res = sim()
        t_bare, t_sim = np.empty(OVERHEAD_CALLS), np.empty(OVERHEAD_CALLS)
        for i in range(OVERHEAD_CALLS):
            if i % 2:
                t0 = clock(); bare(); t1 = clock(); sim(); t2 = clock()          # noqa: E702
                t_bare[i], t_sim[i] = t1 - t0, t2 - t1
            else:
                t0 = clock(); sim(); t1 = clock(); bare(); t2 = clock()          # noqa: E702
                t_sim[i], t_bare[i] = t1 - t0, t2 - t1
        over = float(np.median(t_sim - t_bare))
        base = _row("overhead", "f2py_wrapper", method, scene, law, t_end, **step, repeats=OVERHEAD_CALLS,
                    median_s=float(np.median(t_bare)), nstep=res.stats["nstep"], nfev=res.stats["nfev"],
                    x=float(res.x[-1]), v=float(res.v[-1]))
        row = _row("overhead", "stickslip_python", method, scene, law, t_end, **step, repeats=OVERHEAD_CALLS,
                   median_s=float(np.median(t_sim)), nstep=res.stats["nstep"], nfev=res.stats["nfev"],
                   x=float(res.x[-1]), v=float(res.v[-1]))
        row["overhead_s"] = over
        for x in (base, row):
            x["reference"] = "f2py_wrapper"
            x["ratio_time"] = x["median_s"] / base["median_s"]
        log(f"overhead {scene:5s} {law:8s} {method:7s} wrapper {1e6 * base['median_s']:7.1f} us, "
            f"simulate {1e6 * row['median_s']:7.1f} us: +{1e6 * over:.2f} us per call "
            f"(median of {OVERHEAD_CALLS} interleaved pairs)")
        rows += [base, row]
    return rows


def run_exact_stick(cfg: Config, log: Callable[[str], None]) -> tuple[list[dict], list[str]]:
    """Rows of the ``exact_stick`` sections (see the module notes) and notes on targets that
    no smooth-law run reached. Problems and exact answers from cases.stick."""
    import warnings

    import stickslip
    from cases import stick

    e = stick.exact()
    t_end = cfg.t_end_stick
    problems = {
        "slope": (dict(theta_deg=stick.THETA_DEG, v0=stick.V0_SLOPE, mu_s=stick.MU_S, mu_k=stick.MU_K),
                  lambda r: abs(float(r.x[-1]) - e["x_stop"])),
        "belt": (dict(stick.BELT, v0=stick.BELT["v_b"], mu_s=stick.MU_S, mu_k=stick.MU_K),
                 lambda r: float(np.max(np.abs(r.x - stick.belt_path(r.t)))))}
    steps, tols = cfg.stick_steps, cfg.stick_tols
    smooth = ("recurdyn", "proposed", "stribeck", "karnopp")
    runs = [(law, "rk4", {"h": h}) for law in smooth for h in steps]
    runs += [(law, "dopri5", {"rtol": tol, "atol": tol, "hmax": 1e-2}) for law in smooth for tol in tols]
    runs += [("coulomb", "moreau", {"h": h}) for h in steps]
    runs += [("coulomb", "event_driven", {"rtol": tol, "atol": tol}) for tol in tols]
    targets = cfg.stick_targets
    rows: list[dict] = []
    notes: list[str] = []
    for scene, (params, error) in problems.items():
        here: list[dict] = []
        for law, method, ctl in runs:
            def once(law=law, method=method, ctl=ctl):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", UserWarning)
                    return stickslip.simulate(scene, law, method=method, t_end=t_end, n_out=1001,
                                              max_steps=10**6, **params, **ctl)
            try:
                med, res = time_python(once, cfg)
            except stickslip.IntegrationError as exc:
                notes.append(f"{scene}/{law} {method} {ctl}: {type(exc).__name__}")
                continue
            err_x = max(error(res), 1e-16)           # both problems' errors are of the position [m]
            row = _row("exact_stick", "stickslip_python", method, scene, law, t_end, h=ctl.get("h", float("nan")),
                       tol=ctl.get("rtol", float("nan")), repeats=cfg.repeats, median_s=med,
                       nstep=res.stats["nstep"], nfev=res.stats["nfev"], x=float(res.x[-1]), v=float(res.v[-1]),
                       err=err_x, err_x=err_x)
            row["reference"] = "exact (cases.stick)"
            here.append(row)
            log(f"exact_stick {scene:5s} {law:8s} {method:12s} {ctl} {1e6 * med:9.0f} us  err={row['err']:.1e}")
        rows += here
        curves: dict[tuple[str, str], list[tuple[float, float]]] = {}
        for r in here:
            curves.setdefault((r["law"], r["method"]), []).append((r["err"], r["median_s"]))
        for target in targets:
            finite = [(time_at_error(c, target), key) for key, c in curves.items() if key[0] in smooth]
            finite = [f for f in finite if math.isfinite(f[0])]
            best_t, best_key = min(finite) if finite else (float("nan"), None)
            if best_key is None:
                notes.append(f"{scene}: no smooth-law run reached {target:.0e} m")
            for method in ("moreau", "event_driven"):
                t = time_at_error(curves.get(("coulomb", method), []), target)
                row = _row("exact_stick_equal", "stickslip_python", method, scene, "coulomb", t_end,
                           target=target, median_s=t)
                row["reference"] = f"best smooth: {best_key[0]} {best_key[1]}" if best_key else "no smooth run"
                row["ratio_time"] = t / best_t if best_key else float("nan")
                rows.append(row)
    return rows, notes
#: The runs of the dop853 section: implementation, benchmark program, method.
DOP853_RUNS: tuple[tuple[str, str, str], ...] = (
    ("stickslip_fortran", "bench_fortran", "dop853"), ("stickslip_fortran", "bench_fortran", "dopri5"),
    ("gsl", "bench_gsl", "rk8pd"))


def run_dop853(cfg: Config, exes: dict[str, Path], log: Callable[[str], None]) -> list[dict]:
    """Rows of the ``dop853`` and ``dop853_equal_error`` sections: the belt with the proposed law
    over cfg.t_end_adaptive, rtol = atol = tol (hmin = 0, hmax = t_end), error against the
    section adaptive's reference (stickslip DOPRI5 at REFERENCE_TOL)."""
    scene, law, t_end = "belt", "proposed", cfg.t_end_adaptive
    once = Config(**{**cfg.__dict__, "repeats": 1, "min_sample": 0.0})
    ref = run_program(exes["bench_fortran"], scene, law, "dopri5", t_end, REFERENCE_TOL, once)
    yref = np.array([ref["x"], ref["v"]])
    runs = [r for r in DOP853_RUNS if r[1] in exes]
    rows: list[dict] = []
    for tol in cfg.dop853_tols:
        for impl, exe, method in runs:
            r = run_program(exes[exe], scene, law, method, t_end, tol, cfg)
            errors = state_errors(r["x"], r["v"], yref)
            err = errors["err"]
            row = _row("dop853", impl, method, scene, law, t_end, tol=tol, repeats=cfg.repeats,
                       median_s=r["median_s"], nstep=r["nstep"], nfev=r["nfev"], x=r["x"], v=r["v"], **errors)
            if cfg.callgrind:
                row["instr_per_eval"] = count_instructions(exes[exe], scene, law, method, t_end, tol) / r["nfev"]
            row["reference"] = "stickslip_fortran dopri5 at 1e-13 (error)"
            log(f"dop853 {scene}/{law} tol={tol:.0e} {impl:18s} {method:7s} {1e6 * r['median_s']:8.1f} us "
                f"{r['nfev']:6d} evals  err={err:.1e}")
            rows.append(row)
    for target in cfg.dop853_targets:
        group: list[dict] = []
        for impl, _, method in runs:
            sel = [r for r in rows if (r["impl"], r["method"]) == (impl, method)]
            t = time_at_error([(r["err"], r["median_s"]) for r in sel], target)
            nfev = time_at_error([(r["err"], float(r["nfev"])) for r in sel], target)
            instr = time_at_error([(r["err"], r["instr_per_eval"] * r["nfev"]) for r in sel], target)
            if not math.isfinite(t):
                continue
            row = _row("dop853_equal_error", impl, method, scene, law, t_end, target=target, median_s=t,
                       nfev=round(nfev))
            row["instr_per_eval"] = instr / nfev
            group.append(row)
        base = next((r for r in group if r["method"] == "dop853"), None)
        for row in group if base else []:
            row["reference"] = "stickslip_fortran dop853"
            row["ratio_time"] = row["median_s"] / base["median_s"]
            row["ratio_eval"] = row["ns_per_eval"] / base["ns_per_eval"]
        rows += group
    return rows


#: The chain section's runs: method, law, controls, t_end [s], largest N.
CHAIN_RUNS: tuple[tuple[str, str, dict, float, int], ...] = (
    ("rk4", "stribeck", {"h": 1e-4}, 0.02, 10**6), ("dopri5", "stribeck", {"rtol": 1e-6, "atol": 1e-9}, 0.5, 10**6),
    ("dop853", "stribeck", {"rtol": 1e-6, "atol": 1e-9}, 0.5, 10**6),
    ("radau5", "stribeck", {"rtol": 1e-6, "atol": 1e-9}, 0.5, 10**6),
    ("implicit_euler", "stribeck", {"h": 1e-3}, 0.2, 10**6), ("galpha", "stribeck", {"h": 1e-3}, 0.2, 10**6),
    ("moreau", "coulomb", {"h": 1e-3}, 0.2, 10**6),
    ("event_driven", "coulomb", {"rtol": 1e-6, "atol": 1e-9}, 0.2, 10**6))


def fitted_exponent(n: Sequence[float], cost: Sequence[float]) -> float:
    """Least-squares slope of log(cost) against log(n) (nan with fewer than two points)."""
    pts = [(math.log(a), math.log(b)) for a, b in zip(n, cost) if a > 0 and b > 0 and math.isfinite(b)]
    if len(pts) < 2:
        return float("nan")
    x, y = np.array(pts).T
    return float(np.polyfit(x, y, 1)[0])


def run_chain(cfg: Config, log: Callable[[str], None]) -> list[dict]:
    """Rows of the ``chain`` section (time per step of every method on a chain of N blocks,
    stribeck for the smooth methods, coulomb for moreau and event_driven, started stuck) and of
    ``chain_banded`` (RADAU5 with the banded Jacobian and LU against banded=False, the dense
    path, same steps; ratio_time = dense / banded)."""
    import warnings

    import stickslip

    def timed(method: str, law: str, ctl: dict, t_end: float, n: int) -> tuple[float, object]:
        def once():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", UserWarning)
                return stickslip.simulate("chain", law, method=method, t_end=t_end, n_out=2, n_blocks=n, **ctl)
        return time_python(once, cfg)

    rows: list[dict] = []
    for method, law, ctl, t_end, n_max in CHAIN_RUNS:
        for n in (n for n in cfg.chain_sizes if n <= n_max):
            med, res = timed(method, law, ctl, t_end, n)
            row = _row("chain", "stickslip_python", method, "chain", law, t_end, h=ctl.get("h", float("nan")),
                       tol=ctl.get("rtol", float("nan")), repeats=cfg.repeats, median_s=med,
                       nstep=res.stats["nstep"], nfev=res.stats["nfev"])
            row["n_blocks"] = n
            rows.append(row)
            log(f"chain {method:14s} N={n:5d} {1e6 * med / max(res.stats['nstep'], 1):9.1f} us/step")
    ctl = {"rtol": 1e-6, "atol": 1e-9}
    for n in cfg.chain_dense_sizes:
        pair = []
        for banded in (True, False):
            med, res = timed("radau5", "stribeck", {**ctl, "banded": banded}, 0.5, n)
            row = _row("chain_banded", "stickslip_python", "radau5", "chain", "stribeck", 0.5, tol=1e-6,
                       repeats=cfg.repeats, median_s=med, nstep=res.stats["nstep"], nfev=res.stats["nfev"])
            row["n_blocks"] = n
            row["reference"] = "banded" if banded else "dense"
            pair.append(row)
        pair[1]["ratio_time"] = pair[1]["median_s"] / pair[0]["median_s"]
        rows += pair
        log(f"chain radau5 N={n:4d} dense/banded time {pair[1]['ratio_time']:.1f}")
    return rows


def equal_accuracy(adaptive: list[dict], cfg: Config) -> tuple[list[dict], list[str]]:
    """Rows of time-to-target ratios against stickslip DOPRI5 (Fortran); and notes on targets a
    method never reached."""
    rows: list[dict] = []
    notes: list[str] = []
    runs = [r for r in adaptive if r["section"] == "adaptive"]
    for scene, law in cfg.adaptive:
        here = [r for r in runs if r["scene"] == scene and r["law"] == law]
        methods = sorted({(r["impl"], r["method"]) for r in here},
                         key=lambda im: (im[0] != "stickslip_fortran", im[0] != "stickslip_python", im))
        curves = {im: [(r["err"], r["median_s"]) for r in here if (r["impl"], r["method"]) == im]
                  for im in methods}
        for target in cfg.targets:
            base = time_at_error(curves[("stickslip_fortran", "dopri5")], target)
            if not math.isfinite(base):
                notes.append(f"{scene}/{law}: stickslip DOPRI5 did not reach {target:.0e}")
                continue
            for impl, method in methods:
                t = time_at_error(curves[(impl, method)], target)
                if not math.isfinite(t):
                    notes.append(f"{scene}/{law}: {impl} {method} did not reach {target:.0e} "
                                 f"within the tolerances run")
                    continue
                row = _row("equal_accuracy", impl, method, scene, law, cfg.t_end_adaptive, target=target,
                           median_s=t)
                row["reference"] = "stickslip_fortran dopri5"
                row["ratio_time"] = t / base
                rows.append(row)
    return rows, notes


# -- output -------------------------------------------------------------------------------------

def write_csv(rows: list[dict], path: Path) -> None:
    def write(fh) -> None:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    atomic_write(path, write)


def read_rows(path: Path) -> list[dict]:
    """The rows of a benchmarks.csv (write_csv), numbers as floats."""
    def value(text: str) -> object:
        try:
            return float(text)
        except ValueError:
            return text

    with open(path, newline="", encoding="utf-8") as fh:
        return [{k: value(v) for k, v in row.items()} for row in csv.DictReader(fh)]


#: The line style of each tool in the work-precision panels (its colour is
#: harness.style.TOOL_COLORS', the same in every panel; the marker says the method).
TOOL_STYLE: dict[str, str] = {"stickslip_fortran": "-", "stickslip_python": "--", "gsl": ":",
                              "scipy": "-."}
#: Other tools' names of the library's methods (the same marker), and markers for the others.
SAME_METHOD: dict[str, str] = {"RK45": "dopri5", "DOP853": "dop853", "Radau": "radau5"}
OTHER_MARKERS: dict[str, str] = {"rkf45": "<", "rkck": ">", "rk8pd": "d", "LSODA": "h"}
#: The panels of adaptive methods: the library against one other tool each (at most six lines).
ADAPTIVE_PANELS: tuple[tuple[str, tuple[tuple[str, str], ...]], ...] = (
    ("stickslip and GSL", (("stickslip_fortran", "dopri5"), ("stickslip_python", "dopri5"),
                         ("gsl", "rkf45"), ("gsl", "rkck"), ("gsl", "rk8pd"))),
    ("stickslip and scipy", (("stickslip_python", "dopri5"), ("stickslip_python", "radau5"),
                                ("scipy", "RK45"), ("scipy", "DOP853"), ("scipy", "Radau"),
                                ("scipy", "LSODA"))))
#: The tools' names in the figure, short enough for a column ("Fortran", "Python": stickslip
#: called from Fortran or from Python).
TOOL_WORDS: dict[str, str] = {"c_loop": "C loop", "stickslip_fortran": "Fortran",
                              "stickslip_python": "Python", "gsl": "GSL", "scipy": "scipy"}
#: Width of the benchmark figure [in]; its fonts are scaled to stay legible at a column width.
FIGURE_WIDTH: float = 6.0


def method_marker(method: str) -> str:
    """The marker of a method in the benchmark figure: the library's own (harness.style) for its
    methods and the other tools' names of them, a fixed one for the others."""
    from harness import style as _style
    name = SAME_METHOD.get(method, method.split()[0])
    return _style.METHOD_MARKERS.get(name) or OTHER_MARKERS.get(method, "o")


def method_words(method: str) -> str:
    """A method's name as the figure shows it: "rk4 (step doubling)" -> "RK4 (step doubling)"."""
    from harness import style as _style
    head, _, rest = method.partition(" ")
    return f"{_style.name(head)} {rest}".strip()


def plot(rows: list[dict], path: Path) -> None:
    """The figure of a run (PNG at path, PDF beside it), one colour per tool in every panel
    (harness.style.TOOL_COLORS), three panels one above the other: (a) fixed-step time per
    evaluation of every tool on the first scene and law (bars on a linear axis); (b, c) the
    adaptive methods' error against time on the first adaptive scene and law, the library
    against GSL and against scipy (a marker per method, a line style per tool). The error is
    that of the position at t_end, |x - x_ref| [m] (the err_x_m column; one quantity an axis).
    A run that failed (no finite error) is a cross on the top edge."""
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter
    from matplotlib.transforms import blended_transform_factory
    from harness import style as _style

    _style.apply()
    plt.rcParams.update(_style.column_fonts(FIGURE_WIDTH))
    fixed = [r for r in rows if r["section"] == "fixed"]
    adaptive = [r for r in rows if r["section"] == "adaptive"]
    fig = plt.figure(figsize=(FIGURE_WIDTH, 12.0), layout="constrained")
    grid = fig.add_gridspec(3, 1, height_ratios=(1.0, 1.45, 1.45))
    if fixed:
        ax1 = fig.add_subplot(grid[0])
        scene, law = fixed[0]["scene"], fixed[0]["law"]
        sel = [r for r in fixed if r["scene"] == scene and r["law"] == law]
        ax1.barh(range(len(sel)), [r["ns_per_eval"] for r in sel],
                 color=[_style.TOOL_COLORS.get(r["impl"], "0.5") for r in sel])
        ax1.set_yticks(range(len(sel)), [f"{TOOL_WORDS.get(r['impl'], r['impl'])}: "
                                         f"{method_words(r['method'])}" for r in sel])
        for i, r in enumerate(sel):
            ax1.text(r["ns_per_eval"], i, f" {r['ratio_eval']:.2f}x", va="center")
        ax1.set_xlabel("time per right-hand-side evaluation [ns]")
        ax1.set_title(f"(a) fixed step h = {sel[0]['h_s']:g} s, ratio to C loop")
        ax1.set_xlim(0, 1.45 * max(r["ns_per_eval"] for r in sel))
        ax1.grid(True, axis="x", alpha=0.3)
        ax1.grid(False, axis="y")
    if adaptive:
        scene, law = adaptive[0]["scene"], adaptive[0]["law"]
        sel = [r for r in adaptive if r["scene"] == scene and r["law"] == law]
        for k, (title, series) in enumerate(ADAPTIVE_PANELS):
            ax = fig.add_subplot(grid[1 + k])
            top = blended_transform_factory(ax.transData, ax.transAxes)
            for impl, method in series:
                pts = sorted((r["median_s"], r["err_x_m"]) for r in sel
                             if (r["impl"], r["method"]) == (impl, method))
                if not pts:
                    continue
                t = np.array([p[0] for p in pts])
                err = np.array([p[1] for p in pts], dtype=float)
                ok = np.isfinite(err)
                look = {"color": _style.TOOL_COLORS.get(impl, "0.5"), "marker": method_marker(method),
                        "ms": 6, "markerfacecolor": "white"}
                ax.loglog(t[ok], err[ok], linestyle=TOOL_STYLE.get(impl, "-"), **look,
                          label=f"{TOOL_WORDS.get(impl, impl)}: {method_words(method)}")
                if (~ok).any():
                    ax.plot(t[~ok], np.full(int((~ok).sum()), 0.97), "x", transform=top,
                            clip_on=False, color=look["color"], ms=8, mew=1.5,
                            label=f"{TOOL_WORDS.get(impl, impl)}: {method_words(method)} failed")
            ax.set_title(f"({'bc'[k]}) adaptive, {title}")
            ax.set_xlabel("time per integration [s]")
            ax.set_ylabel("position error at t_end [m]")
            lo, hi = ax.get_xlim()
            if hi / lo < 20.0:                    # less than about a decade: label 3e-n too
                ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 3.0)))
                ax.xaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:.0e}"))
            ax.xaxis.set_minor_formatter(NullFormatter())
            ax.yaxis.set_major_locator(LogLocator(numticks=5))
            ax.yaxis.set_minor_formatter(NullFormatter())
            ax.grid(True, which="major", alpha=0.3)
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.25), ncol=2, frameon=False,
                      handlelength=2.2, labelspacing=0.25, columnspacing=1.0)
    cases = dict.fromkeys((r["scene"], r["law"]) for r in (fixed[:1] + adaptive[:1]))
    fig.suptitle("; ".join(f"{_style.name(sc)}, {_style.name(lw).split(' (')[0]} law"
                           for sc, lw in cases), fontsize=plt.rcParams["font.size"])
    _style.save(fig, path, atomic_write)


def _fmt(x: float, digits: int = 2) -> str:
    return "n/a" if not math.isfinite(x) else f"{x:.{digits}f}"


def summary(rows: list[dict], notes: list[str], cfg: Config, quick: bool, seconds: float) -> str:
    date = _dt.date.today().isoformat()
    cmd = "python -m benchmarks" + (" --quick" if quick else "")
    out = [f"Measured {date} on {machine()} (shared), `{cmd}` "
           f"({seconds:.0f} s); medians of {cfg.repeats} samples. Ratios > 1: slower than the reference.",
           ""]
    fixed = [r for r in rows if r["section"] == "fixed"]
    if fixed:
        out += ["**Fixed-step RK4** (reference: plain C loop, same scene and law):", "",
                "| scene / law | t_end, h | implementation | ns/step | ns/eval | ratio per step | ratio per eval |",
                "|---|---|---|---|---|---|---|"]
        for r in fixed:
            out.append(f"| {r['scene']} / {r['law']} | {r['t_end_s']:g} s, {r['h_s']:g} s | {r['impl']} "
                       f"{r['method']} | {r['ns_per_step']:.0f} | {r['ns_per_eval']:.1f} | "
                       f"{_fmt(r['ratio_step'])} | {_fmt(r['ratio_eval'])} |")
        out.append("")
    adaptive = [r for r in rows if r["section"] == "adaptive"]
    if adaptive:
        out += ["**Adaptive methods, cost per evaluation** (reference: stickslip DOPRI5 from Fortran, same "
                "tolerance; rtol = atol = tol; error = max |(x, v) - reference| at t_end):", "",
                "| scene / law | tol | implementation | steps | evals | us/run | ns/eval | error | "
                "ratio per eval |", "|---|---|---|---|---|---|---|---|---|"]
        for r in adaptive:
            out.append(f"| {r['scene']} / {r['law']} | {r['tol']:.0e} | {r['impl']} {r['method']} | "
                       f"{r['nstep']} | {r['nfev']} | {1e6 * r['median_s']:.0f} | {r['ns_per_eval']:.0f} | "
                       f"{r['err']:.1e} | {_fmt(r['ratio_eval'])} |")
        out.append("")
    counted = [r for r in adaptive if math.isfinite(r["instr_per_eval"])]
    if counted:
        others = [m for m in ("rkf45", "rkck", "rk8pd") if any(r["method"] == m for r in counted)]
        out += ["**Instructions per evaluation** (callgrind, deterministic: the same build on the same machine "
                "counts the same; everything a run executes, the right-hand side, libm and set-up included):", "",
                "| scene / law | tol | stickslip DOPRI5 | " + " | ".join(f"GSL {m}" for m in others)
                + " | DOPRI5 / " + " | DOPRI5 / ".join(others) + " |",
                "|---|---|---|" + "---|" * (2 * len(others))]
        for (scene, law, tol) in dict.fromkeys((r["scene"], r["law"], r["tol"]) for r in counted):
            here = {r["method"]: r["instr_per_eval"] for r in counted
                    if (r["scene"], r["law"], r["tol"]) == (scene, law, tol)}
            ours = here.get("dopri5", float("nan"))
            theirs = [here.get(m, float("nan")) for m in others]
            out.append(f"| {scene} / {law} | {tol:.0e} | {ours:.0f} | " + " | ".join(f"{x:.0f}" for x in theirs)
                       + " | " + " | ".join(_fmt(ours / x) for x in theirs) + " |")
        out.append("")
    eq = [r for r in rows if r["section"] == "equal_accuracy"]
    if eq:
        out += ["**Equal accuracy**: time to reach the error target, as a ratio to stickslip DOPRI5 "
                "(Fortran) (log-log interpolation between tolerances):", "",
                "| scene / law | target error | implementation | time ratio |", "|---|---|---|---|"]
        for r in eq:
            out.append(f"| {r['scene']} / {r['law']} | {r['target_err']:.0e} | {r['impl']} {r['method']} | "
                       f"{_fmt(r['ratio_time'])} |")
        out.append("")
    stick_eq = [r for r in rows if r["section"] == "exact_stick_equal"]
    if stick_eq:
        out += ["**Exact stick at equal error** (set-valued Coulomb by moreau and event_driven against the "
                "fastest smooth-law run, RK4 or DOPRI5, reaching the same error on the exact problems of "
                "cases.stick; n/a: not reached):", "",
                "| scene | target error [m] | method | time [us] | best smooth run | time ratio |",
                "|---|---|---|---|---|---|"]
        for r in stick_eq:
            out.append(f"| {r['scene']} | {r['target_err']:.0e} | {r['method']} | {_fmt(1e6 * r['median_s'], 0)} | "
                       f"{r['reference']} | {_fmt(r['ratio_time'], 3)} |")
        out.append("")
    if notes:
        out += ["Not reached: " + "; ".join(notes) + ".", ""]
    d8 = [r for r in rows if r["section"] == "dop853_equal_error"]
    if d8:
        out += [f"**DOP853 at equal error** ({d8[0]['scene']} / {d8[0]['law']}, {d8[0]['t_end_s']:g} s; "
                "error = max |(x, v) - reference| at t_end; time, evaluations and instructions "
                "interpolated in log-log between tolerances; reference: stickslip DOP853, ratios > 1: "
                "costlier than DOP853):", "",
                "| target error | implementation | us/run | evals | instructions | time ratio | "
                "evals ratio | instructions ratio |", "|---|---|---|---|---|---|---|---|"]
        for target in dict.fromkeys(r["target_err"] for r in d8):
            here = [r for r in d8 if r["target_err"] == target]
            base = next((r for r in here if r["method"] == "dop853"), None)
            if base is None:
                out.append(f"| {target:.0e} | stickslip_fortran dop853: not reached within the tolerances run "
                           "| | | | | | |")
                continue
            for r in here:
                instr, instr0 = r["instr_per_eval"] * r["nfev"], base["instr_per_eval"] * base["nfev"]
                out.append(f"| {target:.0e} | {r['impl']} {r['method']} | {1e6 * r['median_s']:.0f} | "
                           f"{r['nfev']} | {'n/a' if not math.isfinite(instr) else f'{instr:.3g}'} | "
                           f"{_fmt(r['ratio_time'])} | {_fmt(r['nfev'] / base['nfev'])} | "
                           f"{_fmt(instr / instr0)} |")
        out.append("")
    chain = [r for r in rows if r["section"] == "chain"]
    if chain:
        sizes = sorted({int(r["n_blocks"]) for r in chain})
        out += ["**The chain: time per step against the number of blocks N** (started stuck on the belt; "
                "stribeck for the smooth methods, coulomb for the set-valued ones; microseconds per step, "
                "median run time / steps; exponent: least-squares slope of log(time per step) over the N "
                "run from 100 on, or all N when fewer):", "",
                "| method (law) | " + " | ".join(f"N = {n}" for n in sizes) + " | exponent |",
                "|---|" + "---|" * (len(sizes) + 1)]
        for method in dict.fromkeys(r["method"] for r in chain):
            here = {int(r["n_blocks"]): r for r in chain if r["method"] == method}
            law = next(iter(here.values()))["law"]
            per = {n: r["ns_per_step"] / 1e3 for n, r in here.items()}
            fit = [n for n in per if n >= 100]
            fit = fit if len(fit) >= 2 else list(per)
            cells = [(f"{per[n]:.3g}" if n in per else "not run") for n in sizes]
            out.append(f"| {method} ({law}) | " + " | ".join(cells) + " | "
                       f"{_fmt(fitted_exponent(fit, [per[n] for n in fit]))} |")
        out.append("")
    banded = [r for r in rows if r["section"] == "chain_banded"]
    if banded:
        out += ["**RADAU5 on the chain: banded against dense Jacobian and LU** (stribeck, rtol = 1e-6, "
                "0.5 s; the same steps; ratio = dense time / banded time):", "",
                "| N | steps | banded us/step | dense us/step | ratio |", "|---|---|---|---|---|"]
        for b, d in zip(banded[::2], banded[1::2]):
            out.append(f"| {int(b['n_blocks'])} | {int(b['nstep'])} | {b['ns_per_step'] / 1e3:.3g} | "
                       f"{d['ns_per_step'] / 1e3:.3g} | {_fmt(d['ratio_time'])} |")
        out.append("")
    over = [r for r in rows if r["section"] == "overhead"]
    if over:
        out += overhead_markdown(over) + [""]
    return "\n".join(out)


#: The first line of the overhead block of summary.md (--overhead replaces the block in place).
OVERHEAD_HEAD = "**Facade overhead per call**"


def overhead_markdown(over: list[dict], measured: str = "") -> list[str]:
    """The ``overhead`` rows as summary.md's block: a paragraph (what is measured, the goal of the
    10-step RK4 run and whether this run met it; `measured` names the run when the block is
    written alone), then the table."""
    goal = ""
    for p in over[1::2]:
        if (p["scene"], p["law"], p["method"], p["nstep"]) == OVERHEAD_GOAL_RUN:
            met = "met" if p["median_s"] <= OVERHEAD_GOAL_S else "not met"
            goal = (f" Goal: the {p['nstep']}-step RK4 run ({p['scene']} / {p['law']}, h = "
                    f"{p['h_s']:g} s) through simulate in at most {1e6 * OVERHEAD_GOAL_S:g} us on a quiet "
                    f"machine; this run: {1e6 * p['median_s']:.1f} us ({met} here).")
    lines = [f"{OVERHEAD_HEAD} (short runs, output at t_end: stickslip.simulate, its arguments "
             "written out in the call as in a user's code, against "
             "a bare call of the f2py wrapper's run of the setting simulate built and keeps (its "
             "handle: the library copies the built scene and options and integrates; simulate "
             "calls the same routine from C, without f2py's conversion of its arguments), which "
             "includes its timing of "
             "the run for `stats['cpu_seconds']` (two reads of the CPU clock for runs long enough to "
             "look at the stop flag, of the monotonic clock for shorter ones) and, for the long runs, "
             "the SIGINT handler simulate arms; medians of "
             f"{int(over[0]['repeats'])} interleaved calls each, overhead = median of the differences)."
             + goal + (f" {measured}" if measured else ""), "",
             "| scene / law | method | h or tol | steps | wrapper us | simulate us | overhead us | ratio |",
             "|---|---|---|---|---|---|---|---|"]
    for f, p in zip(over[::2], over[1::2]):
        hp = f["h_s"] if math.isfinite(f["h_s"]) else f["tol"]
        lines.append(f"| {f['scene']} / {f['law']} | {f['method']} | {hp:g} | {int(p['nstep'])} | "
                     f"{1e6 * f['median_s']:.1f} | {1e6 * p['median_s']:.1f} | "
                     f"{1e6 * p['overhead_s']:.2f} | {_fmt(p['ratio_time'])} |")
    return lines


def replace_overhead(outdir: Path, over: list[dict], quick: bool) -> None:
    """--overhead: put the new ``overhead`` rows in place of the old ones in benchmarks.csv and
    the new block (which names its run: date, machine, load) in place of the old one in
    summary.md (each added when absent), leaving every other section as the full run wrote it."""
    csv_path, md_path = outdir / "benchmarks.csv", outdir / "summary.md"
    rows: list[dict] = []
    if csv_path.exists():                     # the other rows as written (text: no reformatting)
        with open(csv_path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
    at = next((i for i, r in enumerate(rows) if r["section"] == "overhead"), len(rows))
    rows = [r for r in rows if r["section"] != "overhead"]
    write_csv(rows[:at] + over + rows[at:], csv_path)
    cmd = "python -m benchmarks --overhead" + (" --quick" if quick else "")
    load = f", load average {os.getloadavg()[0]:.1f}" if hasattr(os, "getloadavg") else ""
    block = overhead_markdown(over, f"Measured {_dt.date.today().isoformat()} on {machine()} (shared{load}), "
                                    f"`{cmd}`.")
    lines = md_path.read_text().splitlines() if md_path.exists() else []
    start = next((i for i, line in enumerate(lines) if line.startswith(OVERHEAD_HEAD)), None)
    if start is None:
        lines += ([""] if lines and lines[-1] else []) + block
    else:
        end = start + 1
        while end < len(lines) and not lines[end].startswith("|"):
            end += 1                          # the blank line between paragraph and table
        while end < len(lines) and lines[end].startswith("|"):
            end += 1
        lines[start:end] = block
    write_text(md_path, "\n".join(lines) + "\n")
    # no provenance record: the files' other sections are still the full run's (the sidecar
    # says so and the documentation's captions quote it); the block names its own run


def run_contact(build_dir: Path, log: Callable[[str], None], n_max: int = 64, repeats: int = 3,
                chain_n_max: int = 10000) -> str:
    """The per-step contact solver (stickslip_contact_solver) on random coupled problems of n
    contacts (bench_contact: 50 problems per n, rows of H with one or two +-1 entries over
    n/2 + 1 coordinates, Coulomb mu_s in [0.3, 0.7] against mu_k = 0.3, capacities of a 1 ms
    step), against projected Gauss-Seidel alone and Lemke's method alone on the same
    problems: microseconds a solve (medians of `repeats` passes), the fraction solved to
    1e-12 m/s, the fraction that needed Lemke's fallback. Then moreau on a stack of 1 to 64
    blocks (every contact coupled): microseconds a step. Then moreau's step problem on a chain of
    10 to `chain_n_max` blocks (bench_contact's chain section): the chain's tridiagonal path, and
    the general solver against Gauss-Seidel alone on the dense Delassus
    matrix (up to 100 blocks), with their ratio over the problems both solve. Returns contact.md."""
    meson = _tool("meson")
    if not (build_dir / "build.ninja").exists():
        subprocess.run([meson, "setup", str(build_dir), str(ROOT)], check=True, env=_env(),
                       capture_output=True, text=True)
    proc = subprocess.run([meson, "compile", "-C", str(build_dir), "bench_contact"], env=_env(),
                          capture_output=True, text=True)
    if proc.returncode != 0 and "target not found" in proc.stdout + proc.stderr:
        # a build directory configured before bench_contact existed
        subprocess.run([meson, "setup", "--reconfigure", str(build_dir), str(ROOT)], check=True, env=_env(),
                       capture_output=True, text=True)
        proc = subprocess.run([meson, "compile", "-C", str(build_dir), "bench_contact"], env=_env(),
                              capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"benchmarks: build failed\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    out = subprocess.run([str(build_dir / "bench_contact"), str(n_max), str(repeats), str(chain_n_max)],
                         check=True, capture_output=True, text=True).stdout
    chain = [line.split()[1:] for line in out.split("\n") if line.startswith("chain")]
    stack = [line.split()[1:] for line in out.split("\n") if line.startswith("stack")]
    out = "\n".join(line for line in out.split("\n") if not line.startswith(("chain", "stack")))
    lines = ["**The contact solver** (`python -m benchmarks --contact`)", "",
             f"Machine: {machine()}. 50 random coupled problems per number of contacts n (rows of H "
             "with one or two +-1 entries over n/2 + 1 coordinates, so contacts share bodies; Coulomb "
             "mu_s in [0.3, 0.7], mu_k = 0.3; impulses of a 1 ms step), medians of "
             f"{repeats} passes. The solver follows its rule at every n (static first: rounds of box "
             "problems, each by an active-set Newton method with Lemke's algorithm as the exact fallback, "
             "then the final mode solved exactly; no enumeration of modes); \"Gauss-Seidel alone\" is "
             "projected Gauss-Seidel (up to 1000 sweeps, no rule), \"Lemke alone\" the rule with every box "
             "problem by Lemke's algorithm. Solved: the answer meets the problem's conditions to 1e-12 m/s "
             "(the solver says so itself; a miss ends a run with ContactSolverFailure).", "",
             "| n | solver [us/solve] | solved | needed Lemke | Gauss-Seidel alone [us/solve] | solved "
             "| Lemke alone [us/solve] | solved | linear solves | Lemke pivots |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for line in out.split("\n"):
        if not line.strip():
            continue
        n, us, ok, gus, gok, work, fall, pus, pok, piv = line.split()
        lines.append(f"| {n} | {float(us):.3g} | {100 * float(ok):.0f} % | {100 * float(fall):.0f} % | "
                     f"{float(gus):.3g} | {100 * float(gok):.0f} % | {float(pus):.3g} | {100 * float(pok):.0f} % | "
                     f"{float(work):.0f} | {float(piv):.0f} |")
        log(f"contact n={n}: {float(us):.3g} us, {100 * float(ok):.0f} % solved")
    if stack:
        lines += ["", "**A stack of n blocks** (moreau itself, h = 1 ms, theta = 1/2, 2 s from rest): block 1 on "
                  "a belt at 0.3 m/s, block i on block i - 1, so every contact is coupled to its neighbours; "
                  "masses 2, 1, 0.5 kg, springs 200, 60, 30 N/m to the wall and (mu_s, mu_k) = (0.5, 0.35), "
                  "(0.4, 0.3), (0.3, 0.2) repeated up the stack; normal forces the weight above each contact. "
                  f"Medians of {repeats} runs.", "",
                  "| n | moreau [us/step] | linear solves a step | steps with another solution | "
                  "largest residual [m/s] | status |", "|---|---|---|---|---|---|"]
        for n, us, solves, nonu, res, status in stack:
            lines.append(f"| {n} | {float(us):.3g} | {float(solves):.2f} | {nonu} | {float(res):.2g} | {status} |")
            log(f"contact stack n={n}: {float(us):.3g} us a step")
    if chain:
        lines += ["", "**The chain** (moreau's step problem, h = 1 ms, theta = 1/2; Coulomb mu_s = 0.35, "
                  "mu_k = 0.3): five states of a run of the chain started stuck on the belt (t = 1 to 5 s), "
                  f"medians of {repeats} passes. \"Tridiagonal\" is what moreau runs on a chain: the contact "
                  "solver's rule on W itself (its rounds, each box problem by nonsmooth Gauss-Seidel, O(n) a "
                  "sweep), warm-started at the step's start velocities and modes; \"sweeps alone\" the same "
                  "problems by one set of those sweeps with the contacts' own laws and no rounds (moreau's "
                  "chain path before the rule), warm-started alike, and the rule's cost over theirs. Up to "
                  "100 blocks the same problems on the dense Delassus matrix D = W^-1, from p = 0: the general "
                  "solver (its rule: rounds of box problems) against Gauss-Seidel alone; their times over the problems both solve, and the "
                  "ratio. Largest velocity difference: tridiagonal against the general solver.", "",
                  "| n | tridiagonal [us/solve] | solved | sweeps | sweeps alone [us/solve] | rule / sweeps alone "
                  "| general solver on D [us/solve] | solved "
                  "| Gauss-Seidel alone on D [us/solve] | solved | sweeps | solver / Gauss-Seidel "
                  "| largest velocity difference [m/s] |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for n, tus, tok, tsw, aus, sus, sok, gus, gok, gsw, both, du in chain:
            head = (f"| {n} | {float(tus):.3g} | {100 * float(tok):.0f} % | {float(tsw):.1f} "
                    f"| {float(aus):.3g} | {float(tus) / float(aus):.2f} ")
            if float(sus) < 0:
                lines.append(head + "| (dense D not formed) | | | | | | |")
            else:
                lines.append(head + f"| {float(sus):.3g} | {100 * float(sok):.0f} % | {float(gus):.3g} "
                             f"| {100 * float(gok):.0f} % | {float(gsw):.1f} | {float(sus) / float(gus):.2f} "
                             f"| {float(du):.2g} |")
            log(f"contact chain n={n}: tridiagonal {float(tus):.3g} us")
    return "\n".join(lines) + "\n"


def run_identify(log: Callable[[str], None], repeats: int = 3) -> str:
    """Identification: CPU time of the process (robust on a shared machine) of a LuGre and a GMS
    fit on the ten 36 lb damper records (cases.identify's subsampling, backlash and asymmetry
    fitted, one start), and
    stickslip.prescribed_motion's cost per sample for LuGre against two plain implementations
    of the same law along the same record: a Python loop of the exact flow at each interval's
    mean velocity (one substep per interval), and scipy's solve_ivp (LSODA, rtol 1e-8) on
    dz/dt = v - sigma0 |v| z / g(v) with v interpolated linearly. Both plain versions move
    along a coarser motion than prescribed_motion's cubic Hermite one: their forces differ from
    it by under 1 %. Medians of `repeats`."""
    import warnings
    from scipy.integrate import solve_ivp
    import stickslip
    sys.path.insert(0, str(ROOT))
    from cases import identify as ci
    recs = [r for r, _ in ci.load_groups(stickslip.damper_files(36))["36lb"]]
    lines = ["## Identification (python -m benchmarks --identify)", "",
             f"Machine: {machine()}. Ten 36 lb damper records, {sum(len(r) for r in recs)} samples "
             f"({ci.SAMPLES_PER_CYCLE} per cycle), rtol {ci.RTOL:g}. CPU time of the process, BLAS on one thread "
             "in the fits.", "",
             "| what | median CPU time | time / first row | max force difference from it [N] | notes |",
             "|---|---|---|---|---|"]
    for law in ("lugre", "gms"):
        times, fit = [], None
        for _ in range(repeats):
            t0 = time.process_time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fit = stickslip.fit_friction(law, recs, fixed=ci.fixed_for(law), backlash="fit", asymmetry="fit",
                                             n_starts=1, rtol=ci.RTOL, diff_step=ci.DIFF_STEP)
            times.append(time.process_time() - t0)
        lines.append(f"| {law} fit | {np.median(times):.2f} s |  |  | {fit.nfev} evaluations of the model "
                     f"(Jacobians not counted), nrmse {fit.nrmse:.3f} |")
        log(lines[-1])
    rec = max(recs, key=len)
    p = dict(mu_s=14500.0, mu_k=11600.0, v_s=0.096, sigma0=2.6e6, sigma1=0.0, sigma2=2100.0)

    def g(v: np.ndarray) -> np.ndarray:
        return p["mu_k"] + (p["mu_s"] - p["mu_k"]) * np.exp(-(v / p["v_s"]) ** 2)

    def numpy_loop() -> np.ndarray:
        z = np.zeros(rec.t.size)
        dx, vm = np.diff(rec.x), 0.5 * (rec.v[1:] + rec.v[:-1])
        gv = g(vm)
        for k in range(dx.size):
            zss = np.sign(dx[k]) * gv[k] / p["sigma0"]
            z[k + 1] = zss + (z[k] - zss) * math.exp(-p["sigma0"] * abs(dx[k]) / gv[k])
        return p["sigma0"] * z + p["sigma2"] * rec.v

    def scipy_ivp() -> np.ndarray:
        def rhs(t: float, z: np.ndarray) -> list[float]:
            v = float(np.interp(t, rec.t, rec.v))
            return [v - p["sigma0"] * abs(v) * z[0] / float(g(np.array(v)))]
        sol = solve_ivp(rhs, (rec.t[0], rec.t[-1]), [0.0], method="LSODA", t_eval=rec.t, rtol=1e-8, atol=1e-12)
        return p["sigma0"] * sol.y[0] + p["sigma2"] * rec.v

    ref = {}
    for name, fn in (("stickslip.prescribed_motion (Fortran, rtol 1e-8)",
                      lambda: stickslip.prescribed_motion("lugre", rec.t, rec.x, rec.v, **p).force),
                     (f"stickslip.prescribed_motion (Fortran, rtol {ci.RTOL:g})",
                      lambda: stickslip.prescribed_motion("lugre", rec.t, rec.x, rec.v, rtol=ci.RTOL, **p).force),
                     ("numpy loop, exact flow, 1 substep/interval", numpy_loop),
                     ("scipy solve_ivp LSODA, rtol 1e-8", scipy_ivp)):
        times = []
        for _ in range(repeats):
            t0 = time.process_time()
            ref[name] = fn()
            times.append(time.process_time() - t0)
        ref[name + " time"] = float(np.median(times))
    base = ref["stickslip.prescribed_motion (Fortran, rtol 1e-8) time"]
    first = ref["stickslip.prescribed_motion (Fortran, rtol 1e-8)"]
    for name in [k for k in ref if not k.endswith(" time")]:
        dt = ref[name + " time"]
        dev = float(np.abs(ref[name] - first).max())
        lines.append(f"| LuGre along {rec.name}, {name} | {1e6 * dt / rec.t.size:.2f} us/sample | "
                     f"{dt / base:.3g} | {dev:.3g} | the first row: prescribed_motion at rtol 1e-8 |")
        log(lines[-1])
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=cli_description(__doc__),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_outdir(parser, default=None, help="where benchmarks.csv, benchmarks.png and summary.md go "
                                          "(default: out/benchmarks/)")
    parser.add_argument("--results", action="store_true",
                        help=f"write into the tracked {RESULTS_DIR.relative_to(ROOT)}/ instead, the "
                             "tables the documentation quotes (not with --quick)")
    parser.add_argument("--build-dir", type=Path, default=ROOT / "build" / "bench",
                        help="meson build directory of the compiled benchmarks")
    parser.add_argument("--quick", action="store_true", help="a few seconds: tiny problems, one sample")
    parser.add_argument("--replot", action="store_true",
                        help="run nothing: draw benchmarks.png and .pdf again from the "
                             "benchmarks.csv already in the output directory")
    parser.add_argument("--repeats", type=int_at_least(1), default=None,
                        help="samples per median (with --presets: the interleaved pairs, 5 by default), >= 1")
    parser.add_argument("--no-scipy", action="store_true", help="leave out solve_ivp")
    parser.add_argument("--identify", action="store_true",
                        help="only the identification benchmark (LuGre and GMS fits on the 36 lb damper "
                             "records, prescribed motion per sample): writes identify.md")
    parser.add_argument("--lmfit", action="store_true",
                        help="only the identification benchmark against lmfit (every law on the 36 lb damper "
                             "records, time and parameters; needs lmfit): writes lmfit.md and lmfit.csv")
    parser.add_argument("--prescribed", action="store_true",
                        help="only prescribed_motion's cost per law (a sine of 10^4 samples): writes prescribed.md")
    parser.add_argument("--contact", action="store_true",
                        help="only the contact-solver benchmark (random coupled problems of 2 to 64 "
                             "contacts, against Gauss-Seidel alone; moreau on a stack of 1 to 64 blocks; "
                             "the chain): writes contact.md")
    parser.add_argument("--modal-chain", action="store_true",
                        help="only implicit_euler, galpha and moreau on the chain of 10, 100 and 1000 blocks "
                             "(their contact problems): writes modal_chain.md")
    parser.add_argument("--baseline", metavar="PYTHON", default=None,
                        help="with --modal-chain: also time another build's interpreter, interleaved, "
                             "and give the ratio")
    parser.add_argument("--instructions", action="store_true",
                        help="with --presets: also count each side's instructions a step under valgrind's "
                             "callgrind (needs valgrind)")
    parser.add_argument("--presets", action="store_true",
                        help="only the scenes as presets against the scene code they replaced (slope, belt, "
                             "chain of 10, 100 and 1000 blocks; needs --base): writes presets.md")
    parser.add_argument("--base", metavar="SITE",
                        help="with --presets: a directory holding a build of the package before the presets "
                             "(pip install --target SITE <checkout>)")
    parser.add_argument("--clutches", action="store_true",
                        help="only event_driven on Modelica's CoupledClutches against a scipy event-driven "
                             "solver at equal accuracy: writes clutches.md")
    parser.add_argument("--overhead", action="store_true",
                        help="only the facade's overhead per call (short runs through simulate against the "
                             "bare f2py call): replaces that block of summary.md and those rows of "
                             "benchmarks.csv in the output directory, leaving the other sections")
    parser.add_argument("--callgrind", action=argparse.BooleanOptionalAction, default=None,
                        help="count instructions per evaluation of the compiled adaptive runs with valgrind "
                             "(default: on when valgrind is installed, off with --quick)")
    args = parser.parse_args(argv)
    if args.results and (args.quick or args.outdir is not None):
        parser.error("argument --results: not with --quick or --outdir (the tracked tables are "
                     "those of a full run)")
    args.outdir = RESULTS_DIR if args.results else (args.outdir or Path("out") / "benchmarks")
    check_writable(parser, args.outdir)
    if args.replot:
        if not (args.outdir / "benchmarks.csv").exists():
            parser.error(f"argument --replot: no benchmarks.csv in {args.outdir}")
        rows = read_rows(args.outdir / "benchmarks.csv")
        if any(not isinstance(r.get("err_x_m"), float) for r in rows if r["section"] == "adaptive"):
            parser.error(f"argument --replot: {args.outdir}/benchmarks.csv has no position error "
                         f"err_x_m in its adaptive rows (written before that column): run python -m "
                         f"benchmarks again")
        png = args.outdir / "benchmarks.png"
        plot(rows, png)
        write_provenance(args.outdir, "benchmarks", [png, png.with_suffix(".pdf")], argv)
        print(png)
        return 0

    cfg = QUICK if args.quick else FULL
    if args.repeats is not None:
        cfg = Config(**{**cfg.__dict__, "repeats": args.repeats})
    if args.no_scipy:
        cfg = Config(**{**cfg.__dict__, "scipy_methods": []})
    callgrind = args.callgrind if args.callgrind is not None else (not args.quick and shutil.which("valgrind") is not None)
    if callgrind and shutil.which("valgrind") is None:
        raise SystemExit("benchmarks: --callgrind needs valgrind")
    cfg = Config(**{**cfg.__dict__, "callgrind": callgrind})
    args.outdir.mkdir(parents=True, exist_ok=True)
    log = (lambda s: print(s, flush=True))
    if args.identify:
        write_text(args.outdir / "identify.md", run_identify(log, 1 if args.quick else 3))
        write_provenance(args.outdir, "identify", [args.outdir / "identify.md"], argv)
        return 0
    if args.prescribed:
        from .prescribed_speed import run_prescribed
        write_text(args.outdir / "prescribed.md", run_prescribed(log, 3 if args.quick else 15))
        write_provenance(args.outdir, "prescribed", [args.outdir / "prescribed.md"], argv)
        return 0
    if args.modal_chain:
        from .modal_chain import SIZES, run_modal_chain
        write_text(args.outdir / "modal_chain.md",
                   run_modal_chain(log, 1 if args.quick else 5, args.baseline,
                                   {10: 0.5, 100: 0.1} if args.quick else SIZES))
        write_provenance(args.outdir, "modal_chain", [args.outdir / "modal_chain.md"], argv)
    if args.instructions and not args.presets:
        parser.error("argument --instructions: only with --presets")
    if args.presets:
        from .presets import run_presets
        if not args.base:
            parser.error("argument --presets: needs --base SITE (a build of the package before the presets)")
        write_text(args.outdir / "presets.md", run_presets(log, args.base, args.repeats or (2 if args.quick else 5),
                                                           args.instructions))
        # the command as run, the base build's directory (a path of this machine) written SITE
        write_provenance(args.outdir, "presets", [args.outdir / "presets.md"], argv, shown={str(args.base): "SITE"})
        return 0
    if args.clutches:
        from cases.gallery_clutches import bench_markdown
        write_text(args.outdir / "clutches.md", bench_markdown(3 if args.quick else 15, quiet=False))
        write_provenance(args.outdir, "clutches", [args.outdir / "clutches.md"], argv)
        return 0
    if args.lmfit:
        from .lmfit_compare import run_lmfit, write_rows
        rows, table = run_lmfit(log, 1 if args.quick else 3)
        write_rows(rows, args.outdir / "lmfit.csv")
        write_text(args.outdir / "lmfit.md", table)
        write_provenance(args.outdir, "lmfit", [args.outdir / "lmfit.md", args.outdir / "lmfit.csv"], argv)
        return 0
    if args.overhead:
        replace_overhead(args.outdir, run_overhead(cfg, {}, log), args.quick)
        print(args.outdir / "summary.md")
        return 0
    if args.contact:
        write_text(args.outdir / "contact.md",
                   run_contact(args.build_dir, log, 8 if args.quick else 64, 1 if args.quick else 3,
                               100 if args.quick else 10000))
        write_provenance(args.outdir, "contact", [args.outdir / "contact.md"], argv)
        return 0
    t0 = time.perf_counter()
    exes = build(args.build_dir)
    if "bench_gsl" not in exes:
        log("GSL not found: its rows are left out")
    rows = run_fixed(cfg, exes, log)
    adaptive = run_adaptive(cfg, exes, log)
    eq, notes = equal_accuracy(adaptive, cfg)
    rows += adaptive + eq
    rows += run_overhead(cfg, exes, log)
    stick_rows, stick_notes = run_exact_stick(cfg, log)
    rows += stick_rows
    notes += stick_notes
    rows += run_dop853(cfg, exes, log)
    rows += run_chain(cfg, log)
    write_csv(rows, args.outdir / "benchmarks.csv")
    plot(rows, args.outdir / "benchmarks.png")
    text = summary(rows, notes, cfg, args.quick, time.perf_counter() - t0)
    write_text(args.outdir / "summary.md", text + "\n")
    names = ["benchmarks.csv", "benchmarks.png", "benchmarks.pdf", "summary.md"]
    write_provenance(args.outdir, "benchmarks", [args.outdir / n for n in names], argv)
    print(text)
    return 0
