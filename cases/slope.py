"""Scene 1 of the paper (section 3.1): a 10 kg box on a plane inclined 10 deg, starting at rest.

Regenerates Fig. 5 (the three laws, automatic step size), Figs. 6-8 (each law at the automatic
step size and RK4 with h = 1e-3 s, 1e-4 s), Figs. 9-11 (each law at three error tolerances) and
Table 2 (cost of 20 s of motion) as CSV + PNG (+ Markdown for the table)::

    python -m cases.slope --outdir out/

The physical truth: tan(10 deg) = 0.176 < mu_k = 0.30 < mu_s = 0.35, so the box never moves.
A smooth law with mu(0) = 0 instead creeps at the speed v* where mu(v*) = tan(theta).
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Sequence

from . import _common as c
from . import _study as s

PAPER_CPU: dict[str, tuple[float, float, float]] = {   # Table 2 [s]: automatic, 1e-3, 1e-4
    "recurdyn": (8.0, 66.0, 654.0), "proposed": (7.0, 64.0, 651.0), "coulomb": (65.0, 65.0, 656.0)}
T_END: float = 20.0       # [s], the paper's duration
N_OUT: int = 2001         # output every 10 ms


def creep_speed(law: str, params: dict[str, float]) -> float:
    """Steady creep speed v* [m/s] solving mu(v*) = tan(theta) on [0, v_s] by bisection on
    stickslip.friction_coefficient (0 for Coulomb, whose mu jumps from 0 to mu_s)."""
    import stickslip
    lawp = {k: params[k] for k in stickslip.LAW_PARAMS if k in params}
    target = math.tan(math.radians(params["theta_deg"]))
    lo, hi = 0.0, lawp.get("v_s", stickslip.DEFAULTS["v_s"])
    if float(stickslip.friction_coefficient(law, hi, **lawp)) < target:
        return float("nan")                 # no creep solution below v_s: the box slides
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if float(stickslip.friction_coefficient(law, mid, **lawp)) < target:
            lo = mid
        else:
            hi = mid
    return hi if hi > 1e-15 else 0.0


def metrics(run: c.Run, o: c.Outcome, params: dict[str, float]) -> dict[str, float | None]:
    """Final velocity [m/s], mean speed over the second half of the run [m/s], and the law's
    steady creep speed v* [m/s] with the distance v* t_end [m] it predicts."""
    half = len(o.t) // 2
    speed = (o.x[-1] - o.x[half]) / (o.t[-1] - o.t[half])
    v_star = creep_speed(run.law, params)
    return {"v_end [m/s]": float(o.v[-1]), "mean_speed_2nd_half [m/s]": float(speed),
            "v_star [m/s]": v_star, "v_star_t_end [m]": v_star * run.t_end}


SPEC = s.SceneSpec(scene="slope", fig_auto=5, fig_steps=6, fig_tol=9, table=2,
                   paper_cpu=PAPER_CPU, metrics=metrics,
                   metric_columns=("v_end [m/s]", "mean_speed_2nd_half [m/s]", "v_star [m/s]",
                                   "v_star_t_end [m]"))


def run(outdir: str | Path, *, t_end: float = T_END, n_out: int = N_OUT,
        params: dict[str, float] | None = None, rtols: Sequence[float] = s.TOLERANCES,
        atol_ratio: float = s.ATOL_RATIO, workers: int = 2, quiet: bool = False,
        max_steps: int | None = None) -> list[Path]:
    """Simulate and write every CSV (and the table's Markdown) of the slope into outdir."""
    params = dict(params or {})
    params.setdefault("theta_deg", 10.0)
    files = s.run(SPEC, outdir, t_end=t_end, n_out=n_out, params=params, rtols=rtols,
                  atol_ratio=atol_ratio, workers=workers, quiet=quiet, max_steps=max_steps)
    return files


def plot(csv: str | Path, outdir: str | Path) -> Path:
    """Render one of the slope's CSVs as PNG in outdir."""
    return s.plot(csv, outdir)


def _options(parser: argparse.ArgumentParser) -> None:
    g = parser.add_argument_group("scene")
    g.add_argument("--theta-deg", type=c.positive_float, default=10.0,
                   help="slope inclination [deg] (default %(default)s)")
    g.add_argument("--g", type=c.positive_float, default=9.81,
                   help="gravity [m/s^2] (default %(default)s)")


def _params(args: argparse.Namespace) -> dict[str, float]:
    return {"theta_deg": args.theta_deg, "g": args.g}


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.slope [--outdir DIR] [--t-end S] [law options]."""
    return s.main(SPEC, argv, description=c.cli_description(__doc__), t_end=T_END, n_out=N_OUT,
                  add_scene_options=_options, scene_params=_params, run_scene=run)


if __name__ == "__main__":
    main()
