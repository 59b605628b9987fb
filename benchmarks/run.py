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
- ``overhead``: short runs (OVERHEAD) timed from Fortran and through ``stickslip.simulate``;
  the difference is what the Python facade and f2py add per call.

Times are medians of several samples; each sample repeats a run until it lasts long enough.
Nothing asserts an absolute time: the machine is shared. The compiled adaptive runs also get a
deterministic measure, ``instr_per_eval``: instructions per right-hand-side evaluation counted
by valgrind's callgrind (the difference between 3 runs and 1, so start-up cancels), when
valgrind is installed (not with --quick unless --callgrind).
"""
from __future__ import annotations

import argparse
import csv
import datetime as _dt
import math
import os
import platform
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from cases._common import atomic_write, write_text   # one way to write a file whole or not at all

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent

FIELDS: tuple[str, ...] = (
    "section", "impl", "method", "scene", "law", "t_end_s", "h_s", "tol", "target_err",
    "repeats", "median_s", "nstep", "nfev", "ns_per_step", "ns_per_eval", "instr_per_eval", "x_end_m",
    "v_end_m_s", "err", "reference", "ratio_step", "ratio_eval", "ratio_time",
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
    repeats=1, min_sample=0.0)


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
    t0 = time.perf_counter()
    result = fn()
    once = max(time.perf_counter() - t0, 1e-9)
    inner = max(1, math.ceil(cfg.min_sample / once))
    samples = []
    for _ in range(cfg.repeats):
        t0 = time.perf_counter()
        for _ in range(inner):
            result = fn()
        samples.append((time.perf_counter() - t0) / inner)
    return float(np.median(samples)), result


def machine() -> str:
    """lscpu's model name (or the platform's processor)."""
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                return line.split(":", 1)[1].strip()
    except (OSError, subprocess.CalledProcessError):
        pass
    return platform.processor() or platform.machine()


# -- the scenes in Python, for solve_ivp --------------------------------------------------------

PAPER = dict(mu_s=0.35, mu_k=0.30, v_s=0.01, v_d=0.015, beta=1.0 / 3.0, a=1.5, g=9.81, k_m=30.0,
             v_b=1.5, theta=math.radians(10.0))


def python_law(law: str) -> tuple[Callable[[float], float], Callable[[float], float]]:
    """mu(v) and d mu/dv of a law in plain Python (the paper's formulas, Table 1); d mu/dv of
    the proposed law is floored at |v| = 1e-6 v_s as in the library."""
    p = PAPER
    mu_s, mu_k, v_s, v_d, beta = p["mu_s"], p["mu_k"], p["v_s"], p["v_d"], p["beta"]
    ln_a = math.log(p["a"])
    b = -math.log(mu_s - mu_k) / ln_a - v_s

    def hav(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
        if x <= x0:
            return h0
        if x >= x1:
            return h1
        return h0 + (h1 - h0) * 0.5 * (1.0 - math.cos(math.pi * (x - x0) / (x1 - x0)))

    def dhav(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
        if x <= x0 or x >= x1:
            return 0.0
        return (h1 - h0) * 0.5 * math.pi / (x1 - x0) * math.sin(math.pi * (x - x0) / (x1 - x0))

    def mu(v: float) -> float:
        s = abs(v)
        if law == "coulomb":
            if v == 0.0:
                return 0.0
            m = mu_s if s < v_s else mu_k
        elif law == "recurdyn":
            m = hav(s, 0.0, 0.0, v_s, mu_s) if s < v_s else hav(s, v_s, mu_s, v_d, mu_k)
        else:
            m = mu_s * (s / v_s) ** beta if s <= v_s else math.exp(-ln_a * (s + b)) + mu_k
        return math.copysign(m, v)

    def dmu(v: float) -> float:
        s = abs(v)
        if law == "coulomb":
            return 0.0
        if law == "recurdyn":
            return dhav(s, 0.0, 0.0, v_s, mu_s) if s < v_s else dhav(s, v_s, mu_s, v_d, mu_k)
        if s <= v_s:
            s = max(s, 1e-6 * v_s)
            return mu_s * beta / v_s * (s / v_s) ** (beta - 1.0)
        return -ln_a * math.exp(-ln_a * (s + b))

    return mu, dmu


def python_rhs(scene: str, law: str) -> Callable[[float, np.ndarray], list[float]]:
    """The scene's right-hand side in plain Python (the paper's formulas), as a scipy user
    would write it; parameters of Table 1."""
    mu = python_law(law)[0]
    g, k_m, v_b, theta = PAPER["g"], PAPER["k_m"], PAPER["v_b"], PAPER["theta"]
    if scene == "belt":
        return lambda t, y: [y[1], -k_m * y[0] + mu(v_b - y[1]) * g]
    g_sin, g_cos = g * math.sin(theta), g * math.cos(theta)
    return lambda t, y: [y[1], g_sin - mu(y[1]) * g_cos]


def python_jac(scene: str, law: str) -> Callable[[float, np.ndarray], list[list[float]]]:
    """The Jacobian of python_rhs (analytic, as the library's scenes give it)."""
    dmu = python_law(law)[1]
    g, k_m, v_b, theta = PAPER["g"], PAPER["k_m"], PAPER["v_b"], PAPER["theta"]
    if scene == "belt":
        return lambda t, y: [[0.0, 1.0], [-k_m, -g * dmu(v_b - y[1])]]
    g_cos = g * math.cos(theta)
    return lambda t, y: [[0.0, 1.0], [0.0, -g_cos * dmu(y[1])]]


#: Short runs for the facade's per-call overhead: scene, law, method, t_end [s], h or tol.
OVERHEAD: tuple[tuple[str, str, str, float, float], ...] = (
    ("belt", "recurdyn", "dopri5", 20.0, 1e-4), ("belt", "proposed", "dopri5", 20.0, 1e-4),
    ("slope", "proposed", "radau5", 20.0, 1e-6), ("slope", "proposed", "rk4", 0.01, 1e-3))


# -- rows ---------------------------------------------------------------------------------------

def _row(section: str, impl: str, method: str, scene: str, law: str, t_end: float, *,
         h: float = float("nan"), tol: float = float("nan"), target: float = float("nan"),
         repeats: int = 0, median_s: float = float("nan"), nstep: int = 0, nfev: int = 0,
         x: float = float("nan"), v: float = float("nan"), err: float = float("nan")) -> dict:
    return {"section": section, "impl": impl, "method": method, "scene": scene, "law": law,
            "t_end_s": t_end, "h_s": h, "tol": tol, "target_err": target, "repeats": repeats,
            "median_s": median_s, "nstep": nstep, "nfev": nfev,
            "ns_per_step": 1e9 * median_s / nstep if nstep else float("nan"),
            "ns_per_eval": 1e9 * median_s / nfev if nfev else float("nan"), "instr_per_eval": float("nan"),
            "x_end_m": x, "v_end_m_s": v, "err": err, "reference": "",
            "ratio_step": float("nan"), "ratio_eval": float("nan"), "ratio_time": float("nan")}


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
            floor = float(np.max(np.abs(np.array([chk["x"], chk["v"]]) - yref)))
            rows.append(_row("reference", "gsl", "rk8pd", scene, law, t_end, tol=REFERENCE_TOL,
                             x=chk["x"], v=chk["v"], err=floor))
            log(f"reference {scene} {law}: stickslip dopri5 vs gsl rk8pd at 1e-13 differ by {floor:.2e}")

        def err_of(x: float, v: float) -> float:
            return max(float(np.max(np.abs(np.array([x, v]) - yref))), 1e-16)

        for tol in cfg.tols:
            group: list[dict] = []
            r = run_program(exes["bench_fortran"], scene, law, "dopri5", t_end, tol, cfg)
            group.append(_row("adaptive", "stickslip_fortran", "dopri5", scene, law, t_end, tol=tol,
                              repeats=cfg.repeats, median_s=r["median_s"], nstep=r["nstep"], nfev=r["nfev"],
                              x=r["x"], v=r["v"], err=err_of(r["x"], r["v"])))
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
                                  nfev=res.stats["nfev"], x=x, v=v, err=err_of(x, v)))
            if "bench_gsl" in exes:
                for m in ("rkf45", "rkck", "rk8pd"):
                    r = run_program(exes["bench_gsl"], scene, law, m, t_end, tol, cfg)
                    group.append(_row("adaptive", "gsl", m, scene, law, t_end, tol=tol, repeats=cfg.repeats,
                                      median_s=r["median_s"], nstep=r["nstep"], nfev=r["nfev"],
                                      x=r["x"], v=r["v"], err=err_of(r["x"], r["v"])))
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
                                  err=err_of(x, v) if sol.success else float("nan")))
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


def run_overhead(cfg: Config, exes: dict[str, Path], log: Callable[[str], None]) -> list[dict]:
    """Rows of the ``overhead`` section: each OVERHEAD run from Fortran and from Python (the
    controls of bench_fortran: rtol = atol = tol, hmin = 0, hmax = t_end; output at t_end)."""
    import stickslip

    rows: list[dict] = []
    for scene, law, method, t_end, hp in OVERHEAD:
        fixed = method == "rk4"
        kw = dict(h=hp) if fixed else dict(rtol=hp, atol=hp, hmin=0.0, hmax=t_end, max_steps=10**8)
        step = dict(h=hp) if fixed else dict(tol=hp)
        r = run_program(exes["bench_fortran"], scene, law, method, t_end, hp, cfg)
        base = _row("overhead", "stickslip_fortran", method, scene, law, t_end, **step, repeats=cfg.repeats,
                    median_s=r["median_s"], nstep=r["nstep"], nfev=r["nfev"], x=r["x"], v=r["v"])
        med, res = time_python(lambda: stickslip.simulate(scene, law, method=method, t_end=t_end, n_out=2,
                                                          **kw), cfg)
        row = _row("overhead", "stickslip_python", method, scene, law, t_end, **step, repeats=cfg.repeats,
                   median_s=med, nstep=res.stats["nstep"], nfev=res.stats["nfev"], x=float(res.x[-1]),
                   v=float(res.v[-1]))
        for x in (base, row):
            x["reference"] = "stickslip_fortran"
            x["ratio_time"] = x["median_s"] / base["median_s"]
        log(f"overhead {scene:5s} {law:8s} {method:7s} Fortran {1e6 * base['median_s']:7.1f} us, "
            f"Python {1e6 * med:7.1f} us: +{1e6 * (med - base['median_s']):.1f} us per call")
        rows += [base, row]
    return rows


def time_at_error(points: Sequence[tuple[float, float]], target: float) -> float:
    """Time to reach error <= target along a work-precision curve [(err, time)], interpolated
    linearly in log-log between the runs that bracket the target; NaN if never reached."""
    pts = sorted((t, e) for e, t in points if math.isfinite(e) and math.isfinite(t) and t > 0)
    env: list[tuple[float, float]] = []          # lower envelope: error only decreases with time
    for t, e in pts:
        if not env or e < env[-1][1]:
            env.append((t, e))
    for i, (t, e) in enumerate(env):
        if e <= target:
            if i == 0:
                return t
            t0, e0 = env[i - 1]
            w = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(t0) + w * (math.log(t) - math.log(t0)))
    return float("nan")


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


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fixed = [r for r in rows if r["section"] == "fixed"]
    adaptive = [r for r in rows if r["section"] == "adaptive"]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    if fixed:
        scene, law = fixed[0]["scene"], fixed[0]["law"]
        sel = [r for r in fixed if r["scene"] == scene and r["law"] == law]
        ax1.barh([f"{r['impl']}\n{r['method']}" for r in sel], [r["ns_per_eval"] for r in sel], color="C0")
        for i, r in enumerate(sel):
            ax1.text(r["ns_per_eval"], i, f" {r['ns_per_eval']:.0f} ns/eval, x{r['ratio_eval']:.2f}",
                     va="center", fontsize=8)
        ax1.set_xlabel("ns per right-hand-side evaluation")
        ax1.set_title(f"RK4, h = {sel[0]['h_s']:g} s, {scene}/{law}, {sel[0]['t_end_s']:g} s")
        ax1.set_xlim(0, 1.4 * max(r["ns_per_eval"] for r in sel))
    if adaptive:
        scene, law = adaptive[0]["scene"], adaptive[0]["law"]
        sel = [r for r in adaptive if r["scene"] == scene and r["law"] == law]
        for i, im in enumerate(dict.fromkeys((r["impl"], r["method"]) for r in sel)):
            pts = sorted((r["err"], r["median_s"]) for r in sel if (r["impl"], r["method"]) == im)
            ax2.loglog([p[1] for p in pts], [p[0] for p in pts], "o-", color=f"C{i}",
                       label=f"{im[0]} {im[1]}")
        ax2.set_xlabel("time per integration [s]")
        ax2.set_ylabel("max error of (x, v) at t_end")
        ax2.set_title(f"work-precision, {scene}/{law}, {sel[0]['t_end_s']:g} s")
        ax2.legend(fontsize=7)
        ax2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    try:
        atomic_write(path, lambda fh: fig.savefig(fh, format="png", dpi=110), binary=True)
    finally:
        plt.close(fig)


def _fmt(x: float, digits: int = 2) -> str:
    return "n/a" if not math.isfinite(x) else f"{x:.{digits}f}"


def summary(rows: list[dict], notes: list[str], cfg: Config, quick: bool, seconds: float) -> str:
    date = _dt.date.today().isoformat()
    cmd = "python -m benchmarks" + (" --quick" if quick else "")
    out = [f"Measured {date} on {machine()} ({os.cpu_count()} cores, shared), `{cmd}` "
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
    if notes:
        out += ["Not reached: " + "; ".join(notes) + ".", ""]
    over = [r for r in rows if r["section"] == "overhead"]
    if over:
        out += ["**Facade overhead per call** (short runs, output at t_end: stickslip.simulate against "
                "the same run from Fortran):", "",
                "| scene / law | method | h or tol | steps | Fortran us | Python us | overhead us | ratio |",
                "|---|---|---|---|---|---|---|---|"]
        for f, p in zip(over[::2], over[1::2]):
            hp = f["h_s"] if math.isfinite(f["h_s"]) else f["tol"]
            out.append(f"| {f['scene']} / {f['law']} | {f['method']} | {hp:g} | {p['nstep']} | "
                       f"{1e6 * f['median_s']:.1f} | {1e6 * p['median_s']:.1f} | "
                       f"{1e6 * (p['median_s'] - f['median_s']):.1f} | {_fmt(p['ratio_time'])} |")
        out.append("")
    return "\n".join(out)


def run_identify(log: Callable[[str], None], repeats: int = 3) -> str:
    """Identification (issue 20): wall time of a LuGre and a GMS fit on the ten 36 lb damper
    records (cases.identify's subsampling, backlash and asymmetry fitted, one start), and
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
             f"({ci.SAMPLES_PER_CYCLE} per cycle), rtol {ci.RTOL:g}.", "",
             "| what | median wall time | notes |", "|---|---|---|"]
    for law in ("lugre", "gms"):
        times, fit = [], None
        for _ in range(repeats):
            t0 = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                fit = stickslip.fit_friction(law, recs, fixed=ci.fixed_for(law), backlash="fit", asymmetry="fit",
                                             n_starts=1, rtol=ci.RTOL, diff_step=ci.DIFF_STEP)
            times.append(time.perf_counter() - t0)
        lines.append(f"| {law} fit | {np.median(times):.2f} s | {fit.nfev} evaluations of the model "
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
            t0 = time.perf_counter()
            ref[name] = fn()
            times.append(time.perf_counter() - t0)
        ref[name + " time"] = float(np.median(times))
    base = ref["stickslip.prescribed_motion (Fortran, rtol 1e-8) time"]
    first = ref["stickslip.prescribed_motion (Fortran, rtol 1e-8)"]
    for name in [k for k in ref if not k.endswith(" time")]:
        dt = ref[name + " time"]
        dev = float(np.abs(ref[name] - first).max())
        lines.append(f"| LuGre along {rec.name}, {name} | {1e6 * dt / rec.t.size:.2f} us/sample | "
                     f"{dt / base:.3g} x the time of the first row; max force difference from it {dev:.3g} N |")
        log(lines[-1])
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n\n")[0])
    parser.add_argument("--outdir", type=Path, default=ROOT / "benchmarks" / "results",
                        help="where benchmarks.csv, benchmarks.png and summary.md go")
    parser.add_argument("--build-dir", type=Path, default=ROOT / "build" / "bench",
                        help="meson build directory of the compiled benchmarks")
    parser.add_argument("--quick", action="store_true", help="a few seconds: tiny problems, one sample")
    parser.add_argument("--repeats", type=int, default=None, help="samples per median")
    parser.add_argument("--no-scipy", action="store_true", help="leave out solve_ivp")
    parser.add_argument("--identify", action="store_true",
                        help="only the identification benchmark (LuGre and GMS fits on the 36 lb damper "
                             "records, prescribed motion per sample): writes identify.md")
    parser.add_argument("--callgrind", action=argparse.BooleanOptionalAction, default=None,
                        help="count instructions per evaluation of the compiled adaptive runs with valgrind "
                             "(default: on when valgrind is installed, off with --quick)")
    args = parser.parse_args(argv)

    cfg = QUICK if args.quick else FULL
    if args.repeats is not None:
        cfg = Config(**{**cfg.__dict__, "repeats": max(1, args.repeats)})
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
    write_csv(rows, args.outdir / "benchmarks.csv")
    plot(rows, args.outdir / "benchmarks.png")
    text = summary(rows, notes, cfg, args.quick, time.perf_counter() - t0)
    write_text(args.outdir / "summary.md", text + "\n")
    print(text)
    return 0
