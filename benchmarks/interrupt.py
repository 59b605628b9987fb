"""How promptly Ctrl-C stops a long Fortran call (python -m benchmarks.interrupt).

Each case runs in a fresh interpreter: SIGINT is sent `--delay` seconds into the call, and the
time from the signal to the KeyboardInterrupt is printed, with its ratio to the delay. The
integrators look at a stop flag every 4096 steps, so the latency should be a small fraction of
the delay. The last case is a setting kept from a first call run whole, which the facade runs
from C (stickslip._runner's fast path); its first call's duration is printed too, and the
ratio of the latency to it. tests/test_core_inputs.py checks that every case is interrupted; the
times live here, since a test reads no clock.
"""
from __future__ import annotations

import argparse
import subprocess
import sys
from typing import Sequence

#: (label, code run before the call, the call): the long calls of tests/test_core_inputs.py.
CASES: tuple[tuple[str, str, str], ...] = (
    ("simulate, Coulomb DOPRI5", "", 'ss.simulate("slope", "coulomb", method="dopri5", t_end=1e6, '
                                     "max_steps=10**12)"),
    ("simulate, RK4", "", 'ss.simulate("slope", "recurdyn", method="rk4", h=1e-6, t_end=1e5, '
                          "max_steps=10**12)"),
    ("simulate_batch, 2 rows", "", 'ss.simulate_batch("slope", "coulomb", method="dopri5", '
                                   "t_end=[1e6, 1e6], max_steps=10**12)"),
    ("simulate, kept setting",
     "kw = dict(method='rk4', h=1e-6, t_end=20.0, n_out=2)\n"
     "t0 = time.perf_counter(); ss.simulate('slope', 'recurdyn', **kw)\n"
     "print('whole %.4f' % (time.perf_counter() - t0))\n",
     "ss.simulate('slope', 'recurdyn', **kw)"),
)


def latency(before: str, call: str, delay: float) -> tuple[float, float | None]:
    """(seconds from SIGINT to KeyboardInterrupt, the first whole call's seconds or None)."""
    code = ("import os, signal, threading, time\nimport stickslip as ss\n" + before +
            f"sent = []\n"
            f"def fire():\n    sent.append(time.perf_counter()); os.kill(os.getpid(), signal.SIGINT)\n"
            f"threading.Timer({delay!r}, fire).start()\n"
            f"try:\n    {call}\n    print('finished')\n"
            f"except KeyboardInterrupt:\n    print('latency %.4f' % (time.perf_counter() - sent[0]))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                         check=True).stdout.split()
    if "latency" not in out:
        raise RuntimeError(f"the call was not interrupted: {' '.join(out)}")
    whole = float(out[out.index("whole") + 1]) if "whole" in out else None
    return float(out[out.index("latency") + 1]), whole


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.interrupt", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--delay", type=float, default=0.5, help="seconds into the call (default 0.5)")
    args = parser.parse_args(argv)
    if not args.delay > 0:
        parser.error(f"--delay: must be > 0 [s], got {args.delay}")
    print(f"{'case':26s} {'latency [ms]':>12s} {'/ delay':>8s} {'/ whole call':>12s}")
    for label, before, call in CASES:
        lat, whole = latency(before, call, args.delay)
        ratio = f"{lat / whole:12.2g}" if whole else f"{'':12s}"
        print(f"{label:26s} {1e3 * lat:12.2f} {lat / args.delay:8.2g} {ratio}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
