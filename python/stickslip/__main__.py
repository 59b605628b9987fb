"""``python -m stickslip run MODEL.toml --method M --t-end T --out results.csv [--plot]``:
run a model file (docs/guide/models.md) and write its motion as CSV (and a figure)."""
from __future__ import annotations

import argparse
import io
import os
import sys
import warnings
from typing import Sequence

import numpy as np

EXAMPLES = """examples:
  python -m stickslip run clutch.toml --method event_driven --t-end 1.5 --out clutch.csv
  python -m stickslip run clutch.toml --method moreau --h 1e-3 --t-end 1.5 --out clutch.csv --plot
"""


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m stickslip", description="Run a stickslip model file.",
                                epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a model file (TOML) and write its motion as CSV",
                       epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("model", help="the model file (TOML; schema in docs/guide/models.md)")
    r.add_argument("--method", required=True, help="integration method (one of stickslip.METHODS)")
    r.add_argument("--t-end", type=float, required=True, help="end time [s]")
    r.add_argument("--out", required=True,
                   help="CSV file to write (t, then x and v of every body, then each drive's force)")
    r.add_argument("--n-out", type=int, default=1001, help="output points on [0, t_end] (default 1001)")
    r.add_argument("--h", type=float, help="step size of the fixed-step methods [s]")
    r.add_argument("--rtol", type=float, help="relative tolerance of the adaptive methods")
    r.add_argument("--atol", type=float, help="absolute tolerance of the adaptive methods")
    r.add_argument("--plot", action="store_true", help="also write a figure beside the CSV (.png)")
    r.add_argument("--force", action="store_true", help="overwrite an existing output file")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    import stickslip as ss
    from stickslip.model import write_whole
    from stickslip.outputs import output_problem

    def fail(message: str) -> int:
        print(f"python -m stickslip: error: {message}", file=sys.stderr)
        return 2
    if not os.path.isfile(args.model):
        return fail(f"model: no such file {args.model!r}")
    outs = [args.out] + ([os.path.splitext(args.out)[0] + ".png"] if args.plot else [])
    for out in outs:
        problem = output_problem(out, directory=False)      # the rule of every CLI (stickslip.outputs)
        if problem:
            return fail(f"--out: {problem}")
        if os.path.exists(out) and not args.force:
            return fail(f"--out: {out!r} exists (another result?); give --force to overwrite it")
    controls = {k: v for k, v in (("h", args.h), ("rtol", args.rtol), ("atol", args.atol)) if v is not None}
    try:
        model = ss.Model.from_toml(args.model)
        with warnings.catch_warnings():      # said once, as notes below
            warnings.simplefilter("ignore", ss.RegularisedLawWarning)
            warnings.simplefilter("ignore", ss.ConsistencyWarning)
            warnings.simplefilter("ignore", ss.EnergyBoundWarning)
            res = ss.simulate(model, method=args.method, t_end=args.t_end, n_out=args.n_out, **controls)
    except ValueError as err:
        return fail(str(err))
    except ss.IntegrationError as err:
        return fail(f"the run ended early: {err}")
    names = [b.name for b in model.bodies]
    driven = [f"F_drive_{names[d.body]}" for d in model.drives]       # the drives' forces [N]
    header = ",".join(["t"] + [f"x_{n}" for n in names] + [f"v_{n}" for n in names] + driven)
    rows = np.vstack([res.t, res.x, res.v, res.drive_force.T]).T
    lines = [header] + [",".join(repr(float(v)) for v in row) for row in rows]
    write_whole(args.out, "\n".join(lines) + "\n")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(6.0, 4.5))
        for i, n in enumerate(names):
            ax1.plot(res.t, res.x[i], label=n)
            ax2.plot(res.t, res.v[i], label=n)
        ax1.set_ylabel("position [m]")
        ax2.set_ylabel("velocity [m/s]")
        ax2.set_xlabel("time [s]")
        ax1.legend(loc="best", fontsize="small")
        fig.tight_layout()
        buffer = io.BytesIO()
        fig.savefig(buffer, format="png", dpi=150)
        write_whole(outs[1], buffer.getvalue())
        plt.close(fig)
    print(f"{args.out}: {res.t.size} rows, {len(names)} bodies, {res.stats['nfev']} evaluations, "
          f"{len(res.events)} events ({args.method})")
    for note in res.stats["notes"]:          # what the law computes here, failed consistency checks
        print(f"note: {note}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
