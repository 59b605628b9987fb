"""Den Hartog's response curve at 50 frequencies: by `stickslip.frequency_response` (shooting,
natural-parameter continuation from the lowest frequency) against reading each amplitude from a
transient of the same accuracy::

    python -m benchmarks.steady_response [--ratio 0.3] [--n 50] [--quick]
    python -m benchmarks.steady_response --outdir benchmarks/results   # the guide's numbers

The system is cases/gallery_denhartog.py's (m = k = P0 = 1, Coulomb friction F = r P0),
frequency ratios beta from 1.3 to 3.0 where Den Hartog's non-stop closed form holds, so both
answers are compared with it. The transient starts from rest and is run for as many forcing
periods as it takes its amplitude (half the spread of the turning points over the last period,
from event_driven's exact events) to settle within the tolerance reached by shooting (its
largest relative error against the closed form): the periods are doubled from 25 until the
error against the closed form is below that. Prints the CPU times and their ratio (no
assertion: speed is a ratio measured here, not a test).
"""
from __future__ import annotations

import argparse
import math
import time
from typing import Any, Callable, Sequence

import numpy as np


def _transient_amplitude(beta: float, r: float, periods: int) -> float:
    import stickslip as ss
    from cases import gallery_denhartog as dh
    period = 2 * math.pi / beta
    res = ss.simulate(dh.model(beta, r), method="event_driven", t_end=periods * period, n_out=2,
                      rtol=1e-12, atol=1e-14)
    xs = [e["x"] for e in res.events if e["t"] >= (periods - 1) * period and e["kind"] in ("reversal", "stick")]
    return 0.5 * (max(xs) - min(xs)) if xs else math.nan


def run(ratio: float = 0.3, n: int = 50) -> dict[str, float]:
    """CPU seconds and errors of both ways over `n` frequency ratios from 1.3 to 3.0."""
    import stickslip as ss
    from cases import gallery_denhartog as dh
    betas = np.linspace(1.3, 3.0, n)
    exact = np.array([dh.amplitude(b, ratio) for b in betas])
    assert all(dh.nonstop_valid(b, ratio) for b in betas)
    t0 = time.process_time()
    br = ss.frequency_response(lambda f: dh.model(2 * math.pi * f, ratio), betas / (2 * math.pi), follow=False)
    cpu_shoot = time.process_time() - t0
    err_shoot = float(np.max(np.abs(br.amplitude / exact - 1.0)))
    target = max(err_shoot, 1e-12)
    t0 = time.process_time()
    periods_used = []
    err_tr = 0.0
    for b, x in zip(betas, exact):
        periods = 25
        while True:
            amp = _transient_amplitude(float(b), ratio, periods)
            if abs(amp / x - 1.0) <= target or periods >= 25 * 2**9:
                break
            periods *= 2
        periods_used.append(periods)
        err_tr = max(err_tr, abs(amp / x - 1.0))
    cpu_tr = time.process_time() - t0
    return {"n": n, "ratio": ratio, "cpu_shooting": cpu_shoot, "err_shooting": err_shoot, "cpu_transient": cpu_tr,
            "err_transient": err_tr, "periods_max": max(periods_used), "periods_median": float(np.median(periods_used))}


def _cpu(fn: Callable[[], Any]) -> tuple[Any, float]:
    t0 = time.process_time()
    out = fn()
    return out, time.process_time() - t0


def guide_numbers() -> dict[str, tuple[float, str, str]]:
    """The measured numbers docs/guide/steady-states.md quotes (besides its tables' rows, which
    the tests check): each (value, unit, what)."""
    import stickslip as ss
    from stickslip import steady
    from cases import gallery_denhartog as dh
    g = 9.81
    out: dict[str, tuple[float, str, str]] = {}

    def belt(v_b: float, law: str = "coulomb", **kw: float) -> Any:
        return ss.Model.from_scene("belt", law, m=1.0, k=4.0, v_b=v_b, g=g, mu_s=0.4, mu_k=0.3, v0=v_b, **kw)
    neutral = ss.periodic_orbit(ss.Model.from_scene("belt", "coulomb"))
    out["neutral.amplitude"] = (float(neutral.amplitude[0]), "m", "pure-slip orbit of the default belt from rest")
    out["neutral.period"] = (neutral.period, "s", "its period")
    cpus = [_cpu(lambda: ss.periodic_orbit(belt(v, "stribeck", v_s=0.1, delta=2.0)))[1] for v in (0.3, 0.1)]
    out["stribeck.cpu_min"], out["stribeck.cpu_max"] = ((min(cpus), "s", "CPU of a Stribeck belt orbit, least"),
                                                        (max(cpus), "s", "and most of two"))
    # the finite-difference step: a forced oscillator with the proposed law
    model = ss.Model()
    b = model.add_body(1.0)
    model.add_spring(b, None, k=4.0)
    model.add_force(b, ss.signal.sine(10.0, 0.25))
    model.add_contact(b, None, "proposed", normal_force=g, mu_s=0.4, mu_k=0.3, v_s=0.5)
    orb, cpu = _cpu(lambda: ss.periodic_orbit(model, method="dopri5"))
    out["hb.shooting_amplitude"] = (float(orb.amplitude[0]), "m", "shooting amplitude of the proposed oscillator")
    out["hb.shooting_cpu"] = (cpu, "s", "its CPU time")
    runner = steady._Runner(model, "dopri5", {"rtol": 1e-12, "atol": 1e-14})
    eig = {}
    for h in (1e-4, 1e-5, 1e-6):
        steady._FD_MONODROMY = h
        eig[h] = np.sort_complex(np.linalg.eigvals(steady._fd_monodromy(runner, orb.y0, 4.0)))
    steady._FD_MONODROMY = 1e-4
    out["fd.jitter"] = (float(max(np.abs(eig[1e-5] - eig[1e-4]).max(), np.abs(eig[1e-6] - eig[1e-4]).max())), "",
                        "largest change of the multipliers with steps 1e-5, 1e-6 against 1e-4")
    # continuation of the belt in v_b against the closed form
    br, cpu = _cpu(lambda: ss.continuation(belt, 0.1, 1.0))
    w = 2.0

    def closed(v_b: float) -> tuple[float, float]:
        amp = math.hypot(0.1 * g / 4.0, v_b / w)
        return (math.pi + 2 * math.asin(v_b / (amp * w))) / w + 2 * 0.1 * g / (4.0 * v_b), amp
    out["belt_branch.points"] = (len(br), "", "points from v_b = 0.1 to 1")
    out["belt_branch.cpu"] = (cpu, "s", "CPU time")
    out["belt_branch.worst"] = (max(max(abs(t / closed(p)[0] - 1), abs(a / closed(p)[1] - 1))
                                    for p, t, a in zip(br.p, br.period, br.amplitude)), "", "worst relative error")
    out["belt_branch.nontrivial"] = (max(float(np.abs(o.nontrivial).max()) for o in br.orbits), "",
                                     "largest nontrivial multiplier")
    # Den Hartog from stops to non-stop motion
    br, cpu = _cpu(lambda: ss.continuation(lambda f: dh.model(2 * math.pi * f, 0.5), 0.4 / (2 * math.pi),
                                           0.9 / (2 * math.pi)))
    i = [x for x in br.bifurcations if x["kind"] == "events"][0]["index"]
    out["stops_branch.points"] = (len(br), "", "points from beta = 0.4 to 0.9 at F/P0 = 0.5")
    out["stops_branch.cpu"] = (cpu, "s", "CPU time")
    out["stops_branch.before"] = (2 * math.pi * br.p[i - 1], "", "last beta with stops")
    out["stops_branch.after"] = (2 * math.pi * br.p[i], "", "first beta without")
    # the Hopf point of steady sliding on the damped belt with the proposed law
    def damped(c: float) -> Any:
        m = ss.Model.from_scene("belt", "proposed", v0=1.5)
        m.add_damper(0, None, c)
        return m
    n = 10.0 * g
    slope = np.diff(ss.friction_coefficient("proposed", np.array([1.5 - 1e-6, 1.5 + 1e-6])))[0] / 2e-6
    c_hopf = float(-n * slope)
    x_slide = n * float(ss.friction_coefficient("proposed", np.array([1.5]))[0]) / 300.0
    start = ss.periodic_orbit(damped(1.11), guess=[x_slide + 0.18, 0.0, 2 * math.pi / math.sqrt(30.0)],
                              method="dopri5")
    down = ss.continuation(damped, 1.11, 1.0, guess=start, method="dopri5", step=0.05, max_points=20)
    j = [x for x in down.bifurcations if x["kind"] == "Hopf"][0]["index"]
    out["hopf.linear"] = (c_hopf, "N s/m", "c_H = -N mu'(v_b)")
    out["hopf.start_multiplier"] = (float(np.abs(start.nontrivial).max()), "", "unstable cycle at c = 1.11")
    out["hopf.amplitude"] = (float(down.amplitude[j]), "m", "amplitude where the branch turns")
    out["hopf.c"] = (float(down.p[j]), "N s/m", "c where it turns")
    out["hopf.error"] = (abs(down.p[j] / c_hopf - 1), "", "relative distance to c_H")
    out["hopf.period"] = (float(down.period[j]), "s", "period there")
    up = ss.continuation(damped, 1.11, 1.2, guess=start, method="dopri5", step=0.05, max_points=60)
    stable = np.flatnonzero(up.stable)
    k = int(stable[0]) if stable.size else len(up) - 1
    out["grazing.c"] = (float(up.p[-1]), "N s/m", "where the continuation stops")
    out["grazing.amplitude"] = (float(up.amplitude[k]), "m", "amplitude of the stable orbit there")
    out["grazing.from"] = (max(float(np.abs(o.nontrivial).max()) for o in up.orbits[:k]), "",
                           "largest nontrivial multiplier on the unstable side")
    out["grazing.to"] = (float(np.abs(up.orbits[k].nontrivial).max()), "", "on the stable side")
    # the cost of the response curve
    cost = run(0.3, 50)
    out["cost.shooting_cpu"] = (cost["cpu_shooting"], "s", "50 frequencies by frequency_response")
    out["cost.shooting_err"] = (cost["err_shooting"], "", "its largest relative error")
    out["cost.transient_cpu"] = (cost["cpu_transient"], "s", "transients to the same error")
    out["cost.ratio"] = (cost["cpu_transient"] / cost["cpu_shooting"], "", "transients over shooting")
    out["cost.periods_median"] = (cost["periods_median"], "", "periods per transient, median")
    out["cost.periods_max"] = (cost["periods_max"], "", "and most")
    return out


def main(argv: Sequence[str] | None = None) -> dict[str, float]:
    p = argparse.ArgumentParser(prog="python -m benchmarks.steady_response", description=__doc__.split("\n\n")[0])
    p.add_argument("--ratio", type=float, default=0.3, help="friction ratio F/P0 (default 0.3)")
    p.add_argument("--n", type=int, default=50, help="frequencies (default 50)")
    p.add_argument("--quick", action="store_true", help="5 frequencies")
    p.add_argument("--outdir", help="write the guide's numbers into OUTDIR/steady.json (with its provenance) "
                                    "instead of timing the response curve alone")
    args = p.parse_args(argv)
    if args.outdir:
        import sys
        from pathlib import Path
        root = Path(__file__).resolve().parent.parent
        if str(root) not in sys.path:
            sys.path.insert(0, str(root))
        from harness.files import write_text
        from harness.provenance import write_provenance
        from tools.docnumbers import numbers_json
        path = write_text(Path(args.outdir) / "steady.json", numbers_json(guide_numbers()))
        write_provenance(args.outdir, "benchmarks.steady_response", [path], argv)
        print(path)
        return {}
    out = run(args.ratio, 5 if args.quick else args.n)
    print(f"Den Hartog's response, F/P0 = {out['ratio']:g}, {out['n']} frequencies (beta 1.3 .. 3.0):")
    print(f"  shooting (frequency_response): {out['cpu_shooting']:.3f} s CPU, largest relative error "
          f"{out['err_shooting']:.1e}")
    print(f"  transients to the same error:  {out['cpu_transient']:.3f} s CPU, largest relative error "
          f"{out['err_transient']:.1e}, periods per frequency median {out['periods_median']:g}, "
          f"max {out['periods_max']}")
    print(f"  ratio transient / shooting: {out['cpu_transient'] / out['cpu_shooting']:.1f}")
    return out


if __name__ == "__main__":
    main()
