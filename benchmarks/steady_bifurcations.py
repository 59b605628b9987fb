"""Bifurcations found by `stickslip.continuation` against independent computations, the
numbers docs/guide/steady-states.md quotes::

    python -m benchmarks.steady_bifurcations                              # print them
    python -m benchmarks.steady_bifurcations --outdir benchmarks/results  # the guide's numbers

* Period doubling and folds of periodic orbits: a unit mass on a unit spring on a belt at
  0.1 m/s with a falling Stribeck law (regularised by its tanh ramp, so the flow is smooth),
  forced by F cos(W t) (`forced_belt`). Continued in W at F = 0.3 its period-1 orbit
  period-doubles twice (a bubble); continued down in F at W = 1 it turns at two saddle-node
  folds. Each located value is compared with a computation by scipy written here: shooting on
  solve_ivp (DOP853, rtol 1e-12) with the variational equations of the law written out, and a
  bracketing root (brentq) of mu_min + 1 over W for the period doubling, and of dF/dx(0) along
  the branch (Newton on (v(0), F) at fixed x(0), the implicit function theorem) for the fold.
* The Hopf point of steady sliding on the damped belt (m = 10 kg, k = 300 N/m, v_b = 1.5 m/s,
  the `proposed` law, a damper c), continued as equilibria in c: against c + N mu'(v_b) = 0.
* A LuGre stick-slip cycle (the belt at v_b = 0.1 m/s, radau5): its bristle state among the
  shooting unknowns; its period against a 60 s transient's.

No assertion here (the tests in tests/test_steady.py assert); CPU times are of this machine.
"""
from __future__ import annotations

import argparse
import math
import time
from typing import Any, Callable, Sequence

import numpy as np

#: the forced belt's law (stribeck) and belt speed [m/s]
MU_S, MU_K, V_S, DELTA, V_EPS, V_B = 0.4, 0.3, 0.1, 2.0, 0.01, 0.1


def forced_belt(w: float = 1.0, amp: float = 0.3) -> Any:
    """Unit mass and spring on a belt at V_B, stribeck friction (N = 1), forced by amp cos(w t)."""
    import stickslip as ss
    model = ss.Model()
    b = model.add_body(1.0)
    model.add_spring(b, None, k=1.0)
    model.add_force(b, ss.signal.sine(amp, w / (2 * math.pi), math.pi / 2))
    model.add_contact(b, None, "stribeck", normal_force=1.0, surface_velocity=V_B, mu_s=MU_S, mu_k=MU_K,
                      v_s=V_S, delta=DELTA, c_v=0.0, v_eps=V_EPS)
    return model


def _mu_and_slope(s: float) -> tuple[float, float]:
    """The stribeck law mu(s) = g(|s|) tanh(s / v_eps), g = mu_k + (mu_s - mu_k)
    exp(-(|s|/v_s)^delta) (c_v = 0), and its derivative, written out."""
    a = abs(s)
    e = math.exp(-(a / V_S) ** DELTA)
    g = MU_K + (MU_S - MU_K) * e
    dg = -(MU_S - MU_K) * e * DELTA * (a / V_S) ** (DELTA - 1) / V_S
    th = math.tanh(s / V_EPS)
    return g * th, dg * abs(th) + g / (V_EPS * math.cosh(s / V_EPS) ** 2)


def scipy_period(y0: np.ndarray, w: float, amp: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The forced belt's state after one forcing period from y0 at t = 0, its derivative in y0
    (2 x 2) and in amp, by scipy's DOP853 on the equations and their variations."""
    from scipy.integrate import solve_ivp

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        mu, dmu = _mu_and_slope(z[1] - V_B)
        jac = np.array([[0.0, 1.0], [-1.0, -dmu]])
        return np.concatenate([[z[1], amp * math.cos(w * t) - z[0] - mu], (jac @ z[2:6].reshape(2, 2)).ravel(),
                               jac @ z[6:] + [0.0, math.cos(w * t)]])
    z = solve_ivp(rhs, (0.0, 2 * math.pi / w), np.concatenate([y0, np.eye(2).ravel(), [0.0, 0.0]]),
                  method="DOP853", rtol=1e-12, atol=1e-13).y[:, -1]
    return z[:2], z[2:6].reshape(2, 2), z[6:]


def scipy_period_doubling(w_lo: float, w_hi: float, y0: np.ndarray, amp: float = 0.3) -> float:
    """The forcing frequency in [w_lo, w_hi] where the period-1 orbit's smallest multiplier is
    -1: brentq (to 1e-12) on mu_min + 1, each orbit by Newton on the scipy flow from the last."""
    from scipy.optimize import brentq
    y = np.array(y0, dtype=float)

    def test_function(w: float) -> float:
        nonlocal y
        for _ in range(30):
            y1, m, _ = scipy_period(y, w, amp)
            dy = np.linalg.solve(m - np.eye(2), y - y1)
            y = y + dy
            if np.max(np.abs(dy)) < 1e-12:
                break
        return float(np.min(np.linalg.eigvals(scipy_period(y, w, amp)[1]).real)) + 1.0
    return float(brentq(test_function, w_lo, w_hi, xtol=1e-12))


def scipy_fold(x_lo: float, x_hi: float, v0: float, amp: float, w: float = 1.0) -> float:
    """The forcing amplitude at the fold of the period-1 orbits at forcing frequency w, the
    branch parametrised by x(0) in [x_lo, x_hi]: each point by Newton on (v(0), F), dF/dx(0) by
    the implicit function theorem, its root by brentq (to 1e-12); (v0, amp) a start on it."""
    from scipy.optimize import brentq
    state = {"v0": v0, "amp": amp}

    def slope(x0: float) -> float:
        v, a = state["v0"], state["amp"]
        for _ in range(40):
            y1, m, da = scipy_period(np.array([x0, v]), w, a)
            d = np.linalg.solve(np.column_stack([m[:, 1] - [0.0, 1.0], da]), [x0, v] - y1)
            v, a = v + d[0], a + d[1]
            if np.max(np.abs(d)) < 1e-13:
                break
        _, m, da = scipy_period(np.array([x0, v]), w, a)
        state.update(v0=v, amp=a)
        return float(np.linalg.solve(np.column_stack([m[:, 1] - [0.0, 1.0], da]), -(m[:, 0] - [1.0, 0.0]))[1])
    slope(brentq(slope, x_lo, x_hi, xtol=1e-12))
    return float(state["amp"])


def damped_belt(c: float) -> Any:
    """The paper's belt (m = 10 kg, k = 300 N/m, v_b = 1.5 m/s), `proposed` law, a damper c."""
    import stickslip as ss
    m = ss.Model.from_scene("belt", "proposed", v0=1.5)
    m.add_damper(0, None, c / ss.DEFAULTS["m"])      # the preset is per unit mass (mass 1)
    return m


def _cpu(fn: Callable[[], Any]) -> tuple[Any, float]:
    t0 = time.process_time()
    out = fn()
    return out, time.process_time() - t0


def guide_numbers() -> dict[str, tuple[float, str, str]]:
    """Each (value, unit, what)."""
    import stickslip as ss
    out: dict[str, tuple[float, str, str]] = {}
    br, cpu = _cpu(lambda: ss.continuation(forced_belt, 0.85, 1.65, method="dopri5", step=0.05, max_step=0.1))
    pd = [b for b in br.bifurcations if b["kind"] == "period doubling"]
    out["pd.points"] = (len(br), "", "points of the branch in W from 0.85 to 1.65")
    out["pd.cpu"] = (cpu, "s", "its CPU time, the two period doublings located included")
    for k, b in enumerate(pd, 1):
        i = b["index"]
        exact = scipy_period_doubling(br.p[i - 1], br.p[i], br.orbits[i].y0)
        out[f"pd.w{k}"] = (b["p"], "rad/s", f"period doubling {k}")
        out[f"pd.err{k}"] = (abs(b["p"] / exact - 1), "", "relative distance to scipy's")
    br, cpu = _cpu(lambda: ss.continuation(lambda a: forced_belt(1.0, a), 0.06, 0.02, method="dopri5", step=0.05,
                                           max_step=0.1))
    folds = [b for b in br.bifurcations if b["kind"] == "fold"]
    out["fold.points"] = (len(br), "", "points of the branch in F from 0.06 to 0.02")
    out["fold.cpu"] = (cpu, "s", "its CPU time, the two folds located included")
    for k, b in enumerate(folds, 1):
        out[f"fold.f{k}"] = (b["p"], "", f"fold {k}: the forcing amplitude")
    i = folds[0]["index"]
    exact = scipy_fold(float(br.orbits[i - 1].x0[0]), float(br.orbits[i + 1].x0[0]), float(br.orbits[i].v0[0]),
                       float(br.p[i]))
    out["fold.err1"] = (abs(folds[0]["p"] / exact - 1), "", "relative distance of fold 1 to scipy's")
    rough = ss.continuation(lambda a: forced_belt(1.0, a), 0.06, 0.02, method="dopri5", step=0.05, max_step=0.1,
                            locate_bifurcations=False)
    out["fold.rough_err1"] = (abs(rough.bifurcations[0]["p"] / exact - 1), "", "the same, at the turning point")
    # the Hopf point of steady sliding, as equilibria in c
    eq, cpu = _cpu(lambda: ss.continuation(damped_belt, 0.5, 1.5, kind="equilibrium", step=0.1))
    slope = float(np.diff(ss.friction_coefficient("proposed", np.array([1.5 - 1e-6, 1.5 + 1e-6])))[0] / 2e-6)
    c_hopf = -10.0 * 9.81 * slope
    out["eq.cpu"] = (cpu, "s", "CPU time of 11 equilibria and the Hopf point located")
    out["eq.hopf"] = (eq.bifurcations[0]["p"], "N s/m", "Hopf point of the equilibria")
    out["eq.err"] = (abs(eq.bifurcations[0]["p"] / c_hopf - 1), "", "relative distance to -N mu'(v_b)")
    # LuGre
    lugre = ss.Model.from_scene("belt", "lugre", v_b=0.1)
    orb, cpu = _cpu(lambda: ss.periodic_orbit(lugre, method="radau5"))
    out["lugre.cpu"] = (cpu, "s", "CPU time of the LuGre cycle")
    out["lugre.period"] = (orb.period, "s", "its period")
    out["lugre.z0"] = (float(orb.z0[0]), "m", "the bristle deflection at the section")
    out["lugre.multiplier"] = (float(np.abs(orb.nontrivial).max()), "", "largest nontrivial multiplier")
    return out


def main(argv: Sequence[str] | None = None) -> dict[str, tuple[float, str, str]]:
    p = argparse.ArgumentParser(prog="python -m benchmarks.steady_bifurcations", description=__doc__.split("\n\n")[0])
    p.add_argument("--outdir", help="write the numbers into OUTDIR/steady_bifurcations.json (with its provenance)")
    args = p.parse_args(argv)
    numbers = guide_numbers()
    if args.outdir:
        import sys
        from pathlib import Path
        root = Path(__file__).resolve().parent.parent
        if str(root) not in sys.path:
            sys.path.insert(0, str(root))
        from harness.files import write_text
        from harness.provenance import write_provenance
        from tools.docnumbers import numbers_json
        path = write_text(Path(args.outdir) / "steady_bifurcations.json", numbers_json(numbers))
        write_provenance(args.outdir, "benchmarks.steady_bifurcations", [path], argv)
        print(path)
    else:
        for key, (value, unit, what) in numbers.items():
            print(f"{key:20s} {value:.10g} {unit:6s} {what}")
    return numbers


if __name__ == "__main__":
    main()
