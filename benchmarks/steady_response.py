"""Den Hartog's response curve at 50 frequencies: by `stickslip.frequency_response` (shooting,
natural-parameter continuation from the lowest frequency) against reading each amplitude from a
transient of the same accuracy::

    python -m benchmarks.steady_response [--ratio 0.3] [--n 50] [--quick]

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
from typing import Sequence

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


def main(argv: Sequence[str] | None = None) -> dict[str, float]:
    p = argparse.ArgumentParser(prog="python -m benchmarks.steady_response", description=__doc__.split("\n\n")[0])
    p.add_argument("--ratio", type=float, default=0.3, help="friction ratio F/P0 (default 0.3)")
    p.add_argument("--n", type=int, default=50, help="frequencies (default 50)")
    p.add_argument("--quick", action="store_true", help="5 frequencies")
    args = p.parse_args(argv)
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
