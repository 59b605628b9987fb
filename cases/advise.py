"""Which method and step reach a target error at the least cost, for your scene, law and
parameters (stickslip.advise: pilot runs, Richardson estimates, the explicit methods' stability
bound, one verifying run)::

    python -m cases.advise --scene belt --law stribeck --target 1e-6 --t-end 10 \\
        --param k=450 --param m=3 --param v_b=0.8

Prints the advice, then a table of the candidates (observed order, predicted setting, error and
cost of each method) and one of every run made. Writes no file.
"""
from __future__ import annotations

import argparse
import sys
from typing import Sequence

from . import _common as c


def _param(text: str) -> tuple[str, float]:
    """argparse type of --param: NAME=VALUE."""
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"must be NAME=VALUE (e.g. k=450), got {text!r}")
    try:
        return name.strip(), float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{name}: not a number: {value!r}") from None


def parser() -> argparse.ArgumentParser:
    """The command line of python -m cases.advise."""
    import stickslip as ss
    def default(name: str) -> str:
        info = ss.REGISTRY["param"][name]
        if info["default_of"]:
            return f"{info['scale']:g} {info['default_of']}"
        return f"{info['default']:g} {info['unit']}"

    names = ", ".join(f"{k} ({default(k)})" for k in ss.DEFAULTS)
    p = argparse.ArgumentParser(prog="python -m cases.advise",
                                description=__doc__.split("\n\n")[0].rstrip(":") + ".",
                                epilog=f"Physical parameters (NAME, default and unit): {names}. "
                                       "Each is passed to every run and range-checked by the library.")
    p.add_argument("--scene", required=True, choices=ss.SCENES, help="the scene")
    p.add_argument("--law", required=True, choices=ss.LAWS, help="the friction law")
    p.add_argument("--target", required=True, type=c.positive_float,
                   help="largest acceptable absolute error of the quantity at t_end [m or m/s], > 0")
    p.add_argument("--t-end", type=c.positive_float, default=20.0,
                   help="end of the run [s] (default %(default)s)")
    p.add_argument("--quantity", choices=("x", "v"), default="x",
                   help="x: position [m], v: velocity [m/s], both at t_end (default %(default)s)")
    p.add_argument("--x0", type=c.float_in(-float("inf")), default=0.0,
                   help="initial position [m] (default %(default)s)")
    p.add_argument("--v0", type=c.float_in(-float("inf")), default=0.0,
                   help="initial velocity [m/s] (default %(default)s)")
    p.add_argument("--methods", nargs="+", choices=ss.METHODS, default=None, metavar="METHOD",
                   help=f"candidate methods (default: all of {', '.join(ss.METHODS)})")
    p.add_argument("--param", type=_param, action="append", default=[], metavar="NAME=VALUE",
                   help="a physical parameter, repeatable (names and defaults below)")
    return p


def main(argv: Sequence[str] | None = None) -> "object":
    """Command line: python -m cases.advise --scene S --law L --target E [--t-end T]
    [--quantity x|v] [--x0 X] [--v0 V] [--methods M ...] [--param NAME=VALUE ...]. Prints the
    advice and returns it."""
    import stickslip as ss
    p = parser()
    args = p.parse_args(argv)
    try:
        advice = ss.advise(args.scene, args.law, args.target, args.t_end, quantity=args.quantity,
                           x0=args.x0, v0=args.v0, methods=args.methods, **dict(args.param))
    except ValueError as exc:
        p.error(str(exc))
    print(advice)
    sys.stdout.flush()
    return advice


if __name__ == "__main__":
    main()
