"""Scene 2 of the paper (section 3.2): a 10 kg mass tied to a wall by a spring k = 300 N/m on a
belt moving at v_b = 1.5 m/s (Thomson's stick-slip example), starting at rest (x = 0, x' = 0).

Regenerates Fig. 13 (the three laws, automatic step size), Figs. 14-16 (each law at the automatic
step size and RK4 with h = 1e-3 s, 1e-4 s), Figs. 17-19 (each law at three error tolerances) and
Table 3 (cost) as CSV + PNG (+ Markdown for the table)::

    python -m cases.belt --outdir out/

The paper gives no duration. The proposed law's self-excited vibration grows from rest and
first sticks (v_rel = v_b - x' < v_s) at t = 17.45 s, after which its peaks repeat to 1e-4 m;
T_END = 30 s shows the growth and about eleven stick-slip cycles. Coulomb and RecurDyn laws
see v_rel > v_d throughout, i.e. a constant mu_k: a harmonic oscillation of amplitude
x_k = mu_k m g / k about x_k, period 2 pi sqrt(m/k).
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Sequence

import numpy as np

from . import _common as c
from . import _study as s

PAPER_CPU: dict[str, tuple[float, float, float]] = {   # Table 3 [s]: automatic, 1e-3, 1e-4
    "recurdyn": (18.0, 167.0, 1709.0), "proposed": (159.0, 167.0, 1701.0),
    "coulomb": (225.0, 223.0, 1674.0)}
T_END: float = 30.0       # [s]: the proposed law first sticks at t = 17.45 s
N_OUT: int = 3001         # output every 10 ms
SCENE_DEFAULTS: dict[str, float] = {"m": 10.0, "k": 300.0, "v_b": 1.5, "g": 9.81}


def metrics(run: c.Run, o: c.Outcome, params: dict[str, float]) -> dict[str, float | None]:
    """First time the mass sticks (v_rel < v_s on the output grid) [s], and the half
    peak-to-peak amplitude [m] and the smallest v_rel [m/s] over the last natural period."""
    p = {**SCENE_DEFAULTS, **params}
    v_s = p.get("v_s", 0.01)
    v_rel = p["v_b"] - o.v
    stuck = np.flatnonzero(v_rel < v_s)
    period = 2.0 * math.pi * math.sqrt(p["m"] / p["k"])
    last = o.t >= o.t[-1] - period
    return {"t_first_stick [s]": float(o.t[stuck[0]]) if stuck.size else None,
            "amplitude_last_period [m]": float(np.ptp(o.x[last]) / 2.0),
            "min_v_rel_last_period [m/s]": float(v_rel[last].min())}


SPEC = s.SceneSpec(scene="belt", fig_auto=13, fig_steps=14, fig_tol=17, table=3,
                   paper_cpu=PAPER_CPU, metrics=metrics,
                   metric_columns=("t_first_stick [s]", "amplitude_last_period [m]",
                                   "min_v_rel_last_period [m/s]"))


def run(outdir: str | Path, *, t_end: float = T_END, n_out: int = N_OUT,
        params: dict[str, float] | None = None, rtols: Sequence[float] = s.TOLERANCES,
        atol_ratio: float = s.ATOL_RATIO, workers: int = 2, quiet: bool = False,
        max_steps: int | None = None) -> list[Path]:
    """Simulate and write every CSV (and the table's Markdown) of the belt into outdir."""
    params = {**SCENE_DEFAULTS, **(params or {})}
    return s.run(SPEC, outdir, t_end=t_end, n_out=n_out, params=params, rtols=rtols,
                 atol_ratio=atol_ratio, workers=workers, quiet=quiet, max_steps=max_steps)


def plot(csv: str | Path, outdir: str | Path) -> Path:
    """Render one of the belt's CSVs as PNG in outdir."""
    return s.plot(csv, outdir)


def _options(parser: argparse.ArgumentParser) -> None:
    g = parser.add_argument_group("scene")
    g.add_argument("--m", type=c.positive_float, default=SCENE_DEFAULTS["m"],
                   help="mass [kg] (default %(default)s)")
    g.add_argument("--k", type=c.positive_float, default=SCENE_DEFAULTS["k"],
                   help="spring stiffness [N/m] (default %(default)s)")
    g.add_argument("--v-b", type=c.positive_float, default=SCENE_DEFAULTS["v_b"],
                   help="belt speed [m/s] (default %(default)s)")
    g.add_argument("--g", type=c.positive_float, default=SCENE_DEFAULTS["g"],
                   help="gravity [m/s^2] (default %(default)s)")


def _params(args: argparse.Namespace) -> dict[str, float]:
    return {"m": args.m, "k": args.k, "v_b": args.v_b, "g": args.g}


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.belt [--outdir DIR] [--t-end S] [scene and law options]."""
    return s.main(SPEC, argv, description=c.cli_description(__doc__), t_end=T_END, n_out=N_OUT,
                  add_scene_options=_options, scene_params=_params, run_scene=run)


if __name__ == "__main__":
    main()
