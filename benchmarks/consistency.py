"""The consistency check's numbers (python -m benchmarks.consistency), those that
docs/guide/results.md quotes, written to benchmarks/results/consistency.json (or --out) with
tools/docnumbers.py's numbers_json, and its provenance sidecar beside it.

- A brake (a model: 50 kg at v0 = 10 m/s, a normal force ramping from 0 to 1000 N over 0.5 s,
  `coulomb` with mu_s = mu_k = 0.4; closed form: it stops at T_STOP = 1.5 s at X_STOP = 26/3 m),
  run for 5 s with 1001 output points: under `dopri5` and `radau5` at the default tolerances
  (evaluations, steps forced at h_min, how far x ends past X_STOP), under `event_driven`
  (evaluations, |x(t_end) - X_STOP|), and under RK4 at h = 1e-2 s and 1e-3 s (x and v at t_end,
  x(t_end) - x(0) against the trapezoid integral of v computed here, and the first failure the
  ConsistencyWarning reports: its time, defect and allowance, read from the warning's sentence).
- The cost of the check (`stickslip.energy.check_result`, warnings silenced) on a scene's 1001
  points (the 10-step RK4 run of `coulomb` on the slope) and on the brake as a model (its RK4
  run at h = 1e-3 s); and whole calls of `stickslip.simulate`: that 10-step run of `coulomb`
  (simulate's checked path), the same run of `proposed` (its fast path, unchecked), and a 5 s
  RK4 run of `coulomb` on the belt at h = 1e-3 s. Each time is the best of --repeats samples of
  CPU time per call (`time.process_time`: the machine may be shared), each sample repeating the
  call for at least 0.05 s.
"""
from __future__ import annotations

import argparse
import math
import re
import time
import warnings
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

#: The brake's run: length [s] and output points.
T_END: float = 5.0
N_OUT: int = 1001
#: Its closed form: the stop [s] and the position it stops at [m] (a = mu N(t)/m = 16 t up to
#: 0.5 s, then 8 m/s^2: x = 5 - 1/3 + 4).
T_STOP: float = 1.5
X_STOP: float = 26.0 / 3.0
#: RK4's steps on the brake [s].
RK4_STEPS: tuple[float, ...] = (1e-2, 1e-3)
#: The first failure in a ConsistencyWarning's sentence (stickslip.energy): the end of the
#: span, the defect and the allowance.
FAILURE = re.compile(r"to (?P<t>\S+) s while the integral of v over that (?:time|interval) is \S+ m: "
                     r"a defect of (?P<defect>\S+) m, more than \S+ x its allowance (?P<allow>\S+) m")
#: Minimum length of a timing sample [s].
MIN_SAMPLE: float = 0.05


def brake() -> Any:
    """The brake as a stickslip Model (see the module's docstring)."""
    import stickslip as ss
    m = ss.Model()
    b = m.add_body(50.0, v0=10.0, name="brake")
    m.add_contact(b, None, "coulomb", ss.signal.ramp(0.0, 0.5, 1000.0), mu_s=0.4, mu_k=0.4)
    return m


def run_recorded(*args: Any, **kwargs: Any) -> tuple[Any, dict[str, list[str]]]:
    """stickslip.simulate with its warnings recorded: (result, messages by category name)."""
    import stickslip as ss
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = ss.simulate(*args, **kwargs)
    said: dict[str, list[str]] = {}
    for w in caught:
        said.setdefault(w.category.__name__, []).append(str(w.message))
    return r, said


def best_cpu(fn: Callable[[], object], repeats: int) -> float:
    """The best of `repeats` samples of CPU seconds per call of fn (warnings silenced), each
    sample repeating fn for at least MIN_SAMPLE seconds."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.process_time()
        fn()
        inner = max(1, math.ceil(MIN_SAMPLE / max(time.process_time() - t0, 1e-6)))
        samples = []
        for _ in range(repeats):
            t0 = time.process_time()
            for _ in range(inner):
                fn()
            samples.append((time.process_time() - t0) / inner)
    return min(samples)


def measure_brake(log: Callable[[str], None]) -> dict[str, tuple[float, str, str]]:
    """The brake's numbers: name -> (value, unit, what)."""
    out: dict[str, tuple[float, str, str]] = {}
    for method in ("dopri5", "radau5", "event_driven"):
        r, said = run_recorded(brake(), method=method, t_end=T_END, n_out=N_OUT)
        if r.stats["status"] != 0:
            raise RuntimeError(f"the brake under {method} did not reach t_end: {r.stats['message']}")
        x_end = float(r.x[0, -1])
        out[f"brake.{method}.nfev"] = (int(r.stats["nfev"]), "-", f"right-hand-side evaluations, {method}")
        out[f"brake.{method}.nforced"] = (int(r.stats["nforced"]), "-", f"steps forced at h_min, {method}")
        out[f"brake.{method}.x_past_stop_m"] = (x_end - X_STOP, "m", f"x(t_end) - 26/3 m, {method}")
        out[f"brake.{method}.x_error_m"] = (abs(x_end - X_STOP), "m", f"|x(t_end) - 26/3 m|, {method}")
        out[f"brake.{method}.warnings"] = (sum(map(len, said.values())), "-",
                                           f"warnings of the {method} run (all categories)")
        log(f"brake, {method}: nfev {r.stats['nfev']}, nforced {r.stats['nforced']}, "
            f"x(t_end) - 26/3 = {x_end - X_STOP:.3g} m; warned: {sorted(said)}")
    for h in RK4_STEPS:
        r, said = run_recorded(brake(), method="rk4", h=h, t_end=T_END, n_out=N_OUT)
        t, x, v = r.t, r.x[0], r.v[0]
        name = f"brake.rk4_h{h:.0e}".replace("e-0", "e-")
        defect = float(x[-1] - x[0] - np.sum(np.diff(t) * 0.5 * (v[1:] + v[:-1])))
        found = [FAILURE.search(m) for m in said.get("ConsistencyWarning", [])]
        if not found or found[0] is None:
            raise RuntimeError(f"the brake under RK4 at h = {h:g} s: no ConsistencyWarning with a defect "
                               f"(warned: {said})")
        first = found[0]
        after = t > T_STOP
        out |= {
            f"{name}.x_end_m": (float(x[-1]), "m", f"x at t_end, RK4 at h = {h:g} s"),
            f"{name}.v_end_m_s": (float(v[-1]), "m/s", f"v at t_end, RK4 at h = {h:g} s"),
            f"{name}.x_back_m": (float(np.max(x) - x[-1]), "m", f"max x - x(t_end), RK4 at h = {h:g} s"),
            f"{name}.v_max_after_stop_m_s": (float(np.max(np.abs(v[after]))), "m/s",
                                             f"max |v| at the output points after 1.5 s, RK4 at h = {h:g} s"),
            f"{name}.defect_m": (abs(defect), "m", "|x(t_end) - x(0) - trapezoid integral of v|, computed "
                                                   f"here, RK4 at h = {h:g} s"),
            f"{name}.first_t_s": (float(first["t"]), "s", "end of the first span the ConsistencyWarning "
                                                          f"reports, RK4 at h = {h:g} s"),
            f"{name}.first_defect_m": (abs(float(first["defect"])), "m", "its defect (|.|, from the warning)"),
            f"{name}.first_allowance_m": (float(first["allow"]), "m", "its allowance (from the warning)"),
        }
        log(f"brake, RK4 h = {h:g} s: x(t_end) {x[-1]:.6g} m, v(t_end) {v[-1]:.3g} m/s, defect {defect:.3g} m; "
            f"first failure at {first['t']} s: {first['defect']} m against {first['allow']} m")
    return out


def measure_cost(log: Callable[[str], None], repeats: int) -> dict[str, tuple[float, str, str]]:
    """The check's cost and whole calls of simulate [s]: name -> (value, unit, what)."""
    import stickslip as ss
    from stickslip.energy import check_result

    def checked(r: Any, *args: Any) -> Callable[[], object]:
        notes = list(r.stats["notes"])

        def fn() -> object:
            found = check_result(r, *args)
            r.stats["notes"][:] = notes             # the check appends its sentences
            return found
        return fn

    slope = dict(method="rk4", h=1e-3, t_end=0.01)
    belt = dict(method="rk4", h=1e-3, t_end=T_END)
    rk4 = {**ss.CONTROL_DEFAULTS, "h": 1e-3}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r_scene = ss.simulate("slope", "coulomb", **slope)
        model = brake()
        r_model = ss.simulate(model, method="rk4", h=1e-3, t_end=T_END, n_out=N_OUT)
    timed = {
        "cost.check_scene_s": (checked(r_scene, "rk4", rk4), f"check_result on the slope's 10-step RK4 run of "
                                                             f"coulomb ({r_scene.t.size} points)"),
        "cost.check_model_s": (checked(r_model, "rk4", rk4, model, model.arrays()),
                               f"check_result on the brake's RK4 run at h = 1e-3 s ({r_model.t.size} points)"),
        "cost.slope_coulomb_s": (lambda: ss.simulate("slope", "coulomb", **slope),
                                 "simulate, slope, coulomb, RK4, 10 steps of 1e-3 s (checked path)"),
        "cost.slope_proposed_s": (lambda: ss.simulate("slope", "proposed", **slope),
                                  "simulate, slope, proposed, RK4, 10 steps of 1e-3 s (fast path)"),
        "cost.belt_coulomb_s": (lambda: ss.simulate("belt", "coulomb", **belt),
                                "simulate, belt, coulomb, RK4, 5 s at h = 1e-3 s (checked path)"),
    }
    out = {}
    for name, (fn, what) in timed.items():
        out[name] = (best_cpu(fn, repeats), "s", f"{what}: best of {repeats} samples of CPU time per call")
        log(f"{name}: {1e3 * out[name][0]:.4g} ms")
    return out


def main(argv: Sequence[str] | None = None) -> int:
    from harness.cli import int_at_least
    parser = argparse.ArgumentParser(prog="python -m benchmarks.consistency", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "consistency.json",
                        help="named-numbers file to write (default: benchmarks/results/consistency.json)")
    parser.add_argument("--repeats", type=int_at_least(1), default=7,
                        help="timing samples, the best kept, >= 1 (default 7)")
    args = parser.parse_args(argv)
    from harness.files import write_text
    from harness.provenance import write_provenance
    from tools.docnumbers import numbers_json
    numbers = measure_brake(print) | measure_cost(print, args.repeats)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_text(args.out, numbers_json(numbers))
    write_provenance(args.out.parent, "benchmarks.consistency", [args.out], argv)
    print(args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
