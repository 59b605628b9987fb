"""Which method and step reach a target error at the least cost, for your scene, law and
parameters (stickslip.advise: pilot runs, Richardson estimates, the explicit methods' stability
bound, one verifying run)::

    python -m cases.advise --scene belt --law stribeck --target 1e-6 --t-end 10 \\
        --param k=450 --param m=3 --param v_b=0.8

Prints the advice, then a table of the candidates (observed exponent, predicted setting, error
and cost of each method) and one of every run made. Writes no file.

With --brute-force it then checks the advice: every method on a grid of settings (h = t_end/N,
N = 16, 32, ..., 16 2^13, RK4 only within the advisor's stability bound, none beyond the scene's
shortest period; rtol = 10^(-k/2) from
1e-2 to 1e-12, atol = 1e-3 rtol), errors against RADAU5 and DOPRI5 at rtol = 1e-12 (which must
agree), the cheapest setting of each method that meets the target (it and every tighter one of
the grid: not a lucky cancellation), costs weighted by each method's measured seconds per
evaluation, and the advised run's cost over the cheapest.
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


def reference(scene: str, law: str, t_end: float, quantity: str = "x", **kw: float) -> float:
    """The quantity at t_end from RADAU5 at rtol = 1e-12 (atol 1e-15, no h_max), checked against
    DOPRI5 at the same tolerance: ValueError when they differ by more than 1e-9 max(1, |q|)."""
    import stickslip as ss
    q = {}
    for m in ("radau5", "dopri5"):
        r = ss.simulate(scene, law, method=m, t_end=t_end, n_out=2, rtol=1e-12, atol=1e-15, hmax=0.0, **kw)
        q[m] = float((r.x if quantity == "x" else r.v)[-1])
    if abs(q["radau5"] - q["dopri5"]) > 1e-9 * max(1.0, abs(q["radau5"])):
        raise ValueError(f"reference: RADAU5 and DOPRI5 at rtol = 1e-12 differ by "
                         f"{abs(q['radau5'] - q['dopri5']):.3g}: no trustworthy reference")
    return q["radau5"]


def brute_force(scene: str, law: str, t_end: float, target: float, ref: float, *,
                quantity: str = "x", bound: float | None = None,
                **kw: float) -> dict[str, dict[str, float]]:
    """The cheapest setting of each method that meets `target` against `ref` on the grid of the
    module's docstring: {method: {"setting", "nfev", "error", "weight" (seconds per evaluation
    over all of the method's grid runs), "cost" (nfev x weight)}}; a method without one is left
    out. kw: x0, v0 and physical parameters."""
    import stickslip as ss
    from stickslip.advise import controls_at, takes
    from stickslip.core import shortest_period
    period = shortest_period(scene, law, **kw)
    out: dict[str, dict[str, float]] = {}
    for m in ss.METHODS:
        if not takes(m, law):
            continue
        info = ss.REGISTRY["method"][m]
        if "h" in info["controls"]:
            grid = [dict(h=t_end / (16 * 2 ** k)) for k in range(14)]
            if not info["implicit"] and bound is not None:
                grid = [g for g in grid if g["h"] <= bound]
            if period is not None:       # simulate warns beyond it: not a setting to take
                grid = [g for g in grid if g["h"] <= period]
        else:
            grid = [controls_at(m, 10.0 ** (-k / 2), 1e-3) for k in range(4, 25)]
        rows: list[tuple[dict[str, float], bool, int, float]] = []
        nfev = secs = 0.0
        for g in grid:
            try:
                r = ss.simulate(scene, law, method=m, t_end=t_end, n_out=2, **g, **kw)
            except ss.IntegrationError:
                rows.append((g, False, 0, float("nan")))
                continue
            nfev += r.stats["nfev"]
            secs += r.stats["cpu_seconds"]
            err = abs(float((r.x if quantity == "x" else r.v)[-1]) - ref)
            rows.append((g, err <= target, r.stats["nfev"], err))
        for i, (g, _, n, err) in enumerate(rows):
            if all(ok for _, ok, _, _ in rows[i:]):
                w = secs / nfev if nfev else float("inf")
                out[m] = {"setting": next(iter(g.values())), "nfev": n, "error": err, "weight": w,
                          "cost": n * w}
                break
    return out


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
    p.add_argument("--scene", required=True, choices=[s for s in ss.SCENES if s != "chain"],
                   help="the scene (one body: the chain is not advised)")
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
    p.add_argument("--brute-force", action="store_true",
                   help="then check the advice against a grid search of every method (see above; "
                        "seconds to a minute)")
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
    if args.brute_force:
        print(check(advice))
    sys.stdout.flush()
    return advice


def compare(advice: "object") -> dict[str, object]:
    """The brute-force check of an Advice (module docstring): {"reference": the quantity at
    t_end from RADAU5 and DOPRI5 at rtol 1e-12, "found": brute_force's cheapest setting per
    method, "true_error": the advised run's error against the reference (None when nothing was
    advised), "cost_ratio": its cost over the cheapest grid setting's (None likewise)}."""
    import stickslip as ss
    a = advice
    kw = dict(x0=a.x0, v0=a.v0, **a.params)
    ref = reference(a.scene, a.law, a.t_end, a.quantity, **kw)
    found = brute_force(a.scene, a.law, a.t_end, a.target_error, ref, quantity=a.quantity,
                        bound=a.stability_bound, **kw)
    out: dict[str, object] = {"reference": ref, "found": found, "true_error": None, "cost_ratio": None}
    if a.feasible and found:
        r = ss.simulate(a.scene, a.law, method=a.method, t_end=a.t_end, n_out=2, **a.controls, **kw)
        out["true_error"] = abs(float((r.x if a.quantity == "x" else r.v)[-1]) - ref)
        best = min(found.values(), key=lambda f: f["cost"])
        mine = a.predicted_cost["nfev"] * found.get(a.method, {}).get("weight", float("nan"))
        out["cost_ratio"] = mine / best["cost"]
    return out


def check(advice: "object") -> str:
    """The --brute-force report of an Advice: true error of the advised run and cost against the
    cheapest setting of the grid search, as text."""
    from stickslip.advise import format_table
    a = advice
    cmp = compare(a)
    found = cmp["found"]
    unit = "m" if a.quantity == "x" else "m/s"
    rows = [[m, f"{f['setting']:.3g}", str(f["nfev"]), f"{f['error']:.2g}", f"{f['cost']:.3g}"]
            for m, f in sorted(found.items(), key=lambda kv: kv[1]["cost"])]
    lines = [f"brute force: reference {a.quantity}(t_end) = {cmp['reference']:.12g} {unit} "
             "(RADAU5 and DOPRI5 at rtol 1e-12)"]
    if cmp["true_error"] is not None:
        lines.append(f"advised run: true error {cmp['true_error']:.3g} {unit} (target {a.target_error:.3g}), cost "
                     f"{cmp['cost_ratio']:.2f} x the cheapest grid setting; all runs of the advisor "
                     f"{a.pilot_cost['ratio']:.1f} x the advised run")
    lines.append(format_table(["method", "setting (h [s] or rtol)", "nfev", f"error [{unit}]", "cost [s]"], rows))
    return "\n".join(lines)


if __name__ == "__main__":
    main()
