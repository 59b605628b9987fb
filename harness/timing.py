"""What the benchmarks and the studies of cases/ both need for timing: a median of repeated
runs, the time to reach an error target along a work-precision curve, and the paper's scenes
written in plain Python (the right-hand side and Jacobian a scipy user would write), the
reference for solve_ivp.

benchmarks/ imports this module; nothing in cases/ imports benchmarks/ (one-way dependencies,
tests/project/test_imports.py).
"""
from __future__ import annotations

import math
import time
from typing import Callable, Sequence

import numpy as np


def median_time(fn: Callable[[], object], repeats: int, min_sample: float) -> tuple[float, object]:
    """Median seconds of fn() over `repeats` samples, each repeating fn until it lasts at least
    `min_sample` seconds; returns it with fn's last result."""
    t0 = time.perf_counter()
    result = fn()
    once = max(time.perf_counter() - t0, 1e-9)
    inner = max(1, math.ceil(min_sample / once))
    samples = []
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        for _ in range(inner):
            result = fn()
        samples.append((time.perf_counter() - t0) / inner)
    return float(np.median(samples)), result


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


# -- the scenes in Python, for solve_ivp -------------------------------------------------------

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
