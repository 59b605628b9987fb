"""``python -m stickslip run MODEL.toml --method M --t-end T --out results.csv [--plot]``:
run a model file (docs/guide/models.md) and write its motion as CSV (and a figure)."""
from __future__ import annotations

import argparse
import io
import os
import sys
import warnings
from typing import Any, Callable, Sequence

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
    _steady_parsers(sub)
    return p


STEADY_EXAMPLES = """examples:
  python -m stickslip orbit belt.toml --out orbit.csv --plot
  python -m stickslip response oscillator.toml --frequencies 0.2:0.5:50 --out response.csv --plot
"""


def _steady_parsers(sub: argparse._SubParsersAction) -> None:
    """The subcommands orbit and response (stickslip.steady)."""
    for name, text in (("orbit", "the periodic orbit of a model file: one period as CSV, multipliers printed"),
                       ("response", "the forced response curve of a model file: amplitude per frequency as CSV")):
        q = sub.add_parser(name, help=text, epilog=STEADY_EXAMPLES,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        q.add_argument("model", help="the model file (TOML; schema in docs/guide/models.md)")
        if name == "orbit":
            q.add_argument("--period", type=float, help="forcing period [s] (default: its sines'; none: autonomous)")
        else:
            q.add_argument("--frequencies", required=True,
                           help="START:STOP:N (N frequencies [Hz], evenly spaced) or a comma-separated list; "
                                "every sine of the model is retuned to each")
        q.add_argument("--method", default="event_driven", help="integration method (default event_driven)")
        q.add_argument("--out", required=True, help="CSV file to write")
        q.add_argument("--h", type=float, help="step size of the fixed-step methods [s]")
        q.add_argument("--rtol", type=float, help="relative tolerance of the adaptive methods (default 1e-12)")
        q.add_argument("--atol", type=float, help="absolute tolerance of the adaptive methods (default 1e-14)")
        q.add_argument("--plot", action="store_true", help="also write a figure beside the CSV (.png)")
        q.add_argument("--force", action="store_true", help="overwrite an existing output file")


def _frequencies(text: str) -> list[float]:
    """--frequencies: START:STOP:N or a comma-separated list [Hz]."""
    if ":" in text:
        a, b, n = text.split(":")
        return np.linspace(float(a), float(b), int(n)).tolist()
    return [float(f) for f in text.split(",")]


def _steady(args: argparse.Namespace, fail: "Callable[[str], int]") -> int:
    """python -m stickslip orbit / response."""
    import stickslip as ss
    from stickslip.model import write_whole
    from stickslip.steady import retuned
    controls = {k: v for k, v in (("h", args.h), ("rtol", args.rtol), ("atol", args.atol)) if v is not None}
    try:
        model = ss.Model.from_toml(args.model)
        if args.command == "orbit":
            orb = ss.periodic_orbit(model, period=args.period, method=args.method, **controls)
            names = [b.name for b in model.bodies]
            header = ",".join(["t [s]"] + [f"x_{n} [m]" for n in names] + [f"v_{n} [m/s]" for n in names])
            rows = np.vstack([orb.result.t, orb.result.x, orb.result.v]).T
            summary = (f"period {orb.period!r} s, amplitude {orb.amplitude.tolist()} m, multipliers "
                       f"{np.round(orb.multipliers, 12).tolist()} ({orb.monodromy_method}), "
                       f"{'stable' if orb.stable else 'unstable'}")
        else:
            try:
                freqs = _frequencies(args.frequencies)
            except ValueError:
                return fail("--frequencies: START:STOP:N or a comma-separated list of numbers, "
                            f"got {args.frequencies!r}")
            br = ss.frequency_response(lambda f: retuned(model, f), freqs, follow=False, method=args.method,
                                       **controls)
            amp = br.amplitude.reshape(len(br), -1)
            names = [b.name for b in model.bodies]
            header = ",".join(["frequency [Hz]"] + [f"amplitude_{n} [m]" for n in names] + ["stable [-]"])
            rows = np.column_stack([br.p, amp, br.stable.astype(float)])
            summary = f"{len(br)} frequencies, amplitude {amp.min():.6g} .. {amp.max():.6g} m"
    except (ValueError, ss.SteadyStateError) as err:
        return fail(f"{type(err).__name__}: {err}")
    except ss.IntegrationError as err:
        return fail(f"a run ended early: {err}")
    lines = [header] + [",".join(repr(float(v)) for v in row) for row in rows]
    write_whole(args.out, "\n".join(lines) + "\n")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        plt.rcParams.update(_PLOT_FONTS)
        fig, ax = plt.subplots(figsize=(_PLOT_WIDTH, 3.4), layout="constrained")
        if args.command == "orbit":
            for i, n in enumerate(names):
                ax.plot(orb.result.x[i], orb.result.v[i], label=n,
                        **_series_style(i, len(names), orb.result.x[i].size))
            ax.set_xlabel("position [m]")
            ax.set_ylabel("velocity [m/s]")
            ax.set_title(f"period {orb.period:.6g} s")
            _legend_below(fig, ax)
        else:
            br.plot(ax)
            ax.set_yscale("log")
            ax.set_xlabel("frequency [Hz]")
        buffer = io.BytesIO()
        fig.savefig(buffer, format="png", dpi=150)
        write_whole(os.path.splitext(args.out)[0] + ".png", buffer.getvalue())
        plt.close(fig)
    print(f"{args.out}: {summary}")
    return 0


#: Width of the --plot figures [in] and their font size [pt]: 8 pt once scaled to a journal's
#: column (8.5 cm), the figure checklist of docs/guide/extending.md.
_PLOT_WIDTH: float = 4.5
_PLOT_FONTS: dict[str, float] = {"font.size": 8.0 * _PLOT_WIDTH / (8.5 / 2.54)}
#: Line styles of the bodies' curves, so that a curve on another (bodies that stick together)
#: stays visible: the later drawn dashed over the earlier.
_LINE_STYLES: tuple[str, ...] = ("-", "--", ":", "-.")
_MARKERS: str = "osv^D<>p"


def _series_style(i: int, n: int, points: int) -> dict[str, Any]:
    """Matplotlib keywords of the i-th of n curves of `points` points: its own line style, a
    marker every 1/8 of the curve, staggered so that markers of curves on each other alternate."""
    every = max(points // 8, 1)
    return {"linestyle": _LINE_STYLES[i % len(_LINE_STYLES)], "linewidth": 1.6 if i == 0 else 1.2,
            "marker": _MARKERS[i % len(_MARKERS)], "markersize": 4, "markerfacecolor": "white",
            "markevery": ((i * every) // max(n, 1), every)}


def _legend_below(fig: Any, ax: Any) -> None:
    """One legend for the figure, below the axes, where it covers no curve."""
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=min(len(labels), 4),
               frameon=False)


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
    if args.command in ("orbit", "response"):
        return _steady(args, fail)
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
        plt.rcParams.update(_PLOT_FONTS)
        fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(_PLOT_WIDTH, 4.4), layout="constrained")
        for i, n in enumerate(names):
            ax1.plot(res.t, res.x[i], label=n, **_series_style(i, len(names), res.t.size))
            ax2.plot(res.t, res.v[i], label=n, **_series_style(i, len(names), res.t.size))
        ax1.set_ylabel("position [m]")
        ax2.set_ylabel("velocity [m/s]")
        ax2.set_xlabel("time [s]")
        _legend_below(fig, ax1)
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
