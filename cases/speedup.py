"""The OpenMP speed-up of simulate_batch: one batch of 16 RK4 runs (belt, proposed law,
h = 1e-4 s, 20 s; v_s = 1e-2 and 1e-3 m/s) timed with 1 thread and with --threads (default 2),
median of 3, into stability_speedup.csv::

    python -m cases.speedup --outdir out/ [--threads N]

A timing, so `python -m cases` runs it alone, after the other drivers, with every core.
"""
from __future__ import annotations

import time
from pathlib import Path
from typing import Sequence

import numpy as np

from . import _common as c


def speedup(threads: int = 2, repeats: int = 3) -> tuple[float, float, float]:
    """(median seconds with 1 thread, with `threads`, ratio) of one batch of 16 RK4 runs."""
    import stickslip
    kw = dict(method="rk4", t_end=20.0, h=1e-4, v_s=np.repeat([1e-2, 1e-3], 8))
    times: dict[int, list[float]] = {1: [], threads: []}
    for _ in range(repeats):
        for n in (1, threads):
            t0 = time.perf_counter()
            stickslip.simulate_batch("belt", "proposed", threads=n, **kw)
            times[n].append(time.perf_counter() - t0)
    t1, tn = float(np.median(times[1])), float(np.median(times[threads]))
    return t1, tn, t1 / tn


def run(outdir: str | Path, *, quick: bool = False, threads: int = 2, quiet: bool = False) -> list[Path]:
    """Time the batch (--quick: one repeat) and write stability_speedup.csv."""
    t1, tn, ratio = speedup(threads, 1 if quick else 3)
    c.log(f"speedup: batch speed-up {ratio:.2f} ({t1:.3f} s with 1 thread, {tn:.3f} s with "
          f"{threads})", quiet)
    return [c.write_csv(Path(outdir) / "stability_speedup.csv",
                        ["threads [-]", "seconds [s]", "speedup [-]"],
                        [[1, t1, 1.0], [threads, tn, ratio]])]


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.speedup [--outdir DIR] [--quick] [--threads N]."""
    return c.study_main("cases.speedup", __doc__, "one repeat instead of three", run, argv)


if __name__ == "__main__":
    main()
