"""Cost of stickslip.prescribed_motion per law (python -m benchmarks --prescribed), the table of
docs/guide/prescribed-motion.md: a 1 mm, 1 Hz sine over 2 s with 10^4 samples, the median and
minimum of the CPU times of `repeats` calls per law at rtol 1e-8 and 1e-6, the substeps of the state
integration, and scipy's solve_ivp on LuGre's state equation written in numpy along the same
motion (velocity interpolated linearly) as the reference the tests compare with; then LuGre's
error at rtol 1e-8 and 1e-6 against scipy's Radau at rtol 1e-11 on the sine's exact velocity.
"""
from __future__ import annotations

import time
from typing import Callable

import numpy as np

#: (law, parameters, label of the parameters) of the table's rows.
CASES: tuple[tuple[str, dict[str, float], str], ...] = (
    ("coulomb", {}, "defaults"),
    ("lugre", {"sigma0": 1e5}, "sigma0 = 1e5 1/m"),
    ("dahl", {"sigma0": 1e4}, "sigma0 = 1e4 1/m"),
    ("gms", {"sigma0": 1e4, "n_elements": 4}, "sigma0 = 1e4 1/m, N = 4"),
    ("gms", {"sigma0": 1e4, "n_elements": 16}, "sigma0 = 1e4 1/m, N = 16"),
    ("elastoplastic", {"sigma0": 1e5}, "sigma0 = 1e5 1/m"),
)


def _times(fn: Callable[[], object], repeats: int) -> tuple[float, float]:
    """(median, min) CPU time [s] of `repeats` calls (the machine is shared: a call's wall time
    grows with the other jobs' load, its CPU time much less)."""
    ts = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        ts.append(time.process_time() - t0)
    return float(np.median(ts)), float(np.min(ts))


def run_prescribed(log: Callable[[str], None], repeats: int = 15) -> str:
    """The markdown table (medians and minima of `repeats` calls)."""
    import stickslip as ss
    from scipy.integrate import solve_ivp
    from harness.provenance import machine

    t = np.linspace(0.0, 2.0, 10000)
    x = 1e-3 * np.sin(2.0 * np.pi * t)
    v = 2e-3 * np.pi * np.cos(2.0 * np.pi * t)
    lines = ["**prescribed_motion's cost** (`python -m benchmarks --prescribed`)", "",
             f"Machine: {machine()}. A 1 mm, 1 Hz sine over 2 s, 10^4 samples; CPU time of one call, median "
             f"and minimum of {repeats} calls (scipy: of {max(1, repeats // 5)}); substeps: `res.stats['n_advance']`.", "",
             "| law | parameters | ms per 10^4 samples, rtol 1e-8 (median / min) | substeps | "
             "rtol 1e-6 (median / min) | substeps |", "|---|---|---|---|---|---|"]
    for law, params, label in CASES:
        cells = []
        for rtol in (1e-8, 1e-6):
            res = ss.prescribed_motion(law, t, x, v, rtol=rtol, **params)
            med, low = _times(lambda: ss.prescribed_motion(law, t, x, v, rtol=rtol, **params), repeats)
            cells += [f"{1e3 * med:.3g} / {1e3 * low:.3g}", f"{res.stats['n_advance']:,}"]
        lines.append(f"| {law} | {label} | " + " | ".join(cells) + " |")
        log(lines[-1])
    p = {**ss.DEFAULTS, "sigma0": 1e5}
    p = {k: p[k] for k in ss.REGISTRY["law"]["lugre"]["params"]}

    def g(vel: float) -> float:
        return p["mu_k"] + (p["mu_s"] - p["mu_k"]) * np.exp(-(vel / p["v_s"]) ** 2)

    def rhs(tt: float, z: np.ndarray) -> list[float]:
        vel = float(np.interp(tt, t, v))
        return [vel - p["sigma0"] * abs(vel) * z[0] / g(vel)]

    for method in ("LSODA", "Radau"):
        med, low = _times(lambda: solve_ivp(rhs, (t[0], t[-1]), [0.0], method=method, t_eval=t, rtol=1e-8,
                                            atol=1e-14), max(1, repeats // 5))
        lines.append(f"| lugre, scipy solve_ivp {method} (numpy right-hand side) | sigma0 = 1e5 1/m | "
                     f"{1e3 * med:.3g} / {1e3 * low:.3g} | | | |")
        log(lines[-1])
    lines += ["", *_lugre_accuracy(ss, p, t, x, v, g)]
    log(lines[-1])
    return "\n".join(lines) + "\n"


def _lugre_accuracy(ss: object, p: dict[str, float], t: np.ndarray, x: np.ndarray, v: np.ndarray,
                    g: Callable[[float], float]) -> list[str]:
    """The table of LuGre's error at rtol 1e-8 and 1e-6 along the sine: against scipy's Radau at
    rtol 1e-11 on the sine's exact velocity (the cubic Hermite velocity that prescribed_motion
    follows differs from it by about 1e-14 of its amplitude at 10^4 samples)."""
    from scipy.integrate import solve_ivp

    def speed(tt: float) -> float:
        return 2e-3 * np.pi * np.cos(2.0 * np.pi * tt)

    def rate(vel: float, z: float) -> float:
        return vel - p["sigma0"] * abs(vel) * z / g(vel)

    sol = solve_ivp(lambda tt, z: [rate(speed(tt), z[0])], (t[0], t[-1]), [0.0], method="Radau", t_eval=t,
                    rtol=1e-11, atol=1e-16)
    if not sol.success:
        raise RuntimeError(f"prescribed_speed: scipy's reference failed: {sol.message}")
    z = sol.y[0]
    mu_ref = p["sigma0"] * z + p["sigma1"] * np.array([rate(vi, zi) for vi, zi in zip(v, z)]) + p["sigma2"] * v
    rows = ["LuGre (sigma0 = 1e5 1/m, the other parameters their defaults) against scipy's Radau at rtol 1e-11 "
            "on the same sine:", "", "| rtol | max abs(mu − mu_ref) [-] | max abs(mu_ref) [-] |", "|---|---|---|"]
    for rtol in (1e-8, 1e-6):
        mu = ss.prescribed_motion("lugre", t, x, v, rtol=rtol, sigma0=p["sigma0"]).mu
        rows.append(f"| {rtol:g} | {np.abs(mu - mu_ref).max():.2g} | {np.abs(mu_ref).max():.3g} |")
    return rows
