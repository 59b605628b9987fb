"""implicit_euler, galpha and moreau on the chain (python -m benchmarks --modal-chain [--baseline
PYTHON]): the cost per step of their contact problems, which the contact module solves with its
rule, over the laws' modes (implicit_euler, galpha) or set-valued (moreau: the rule's rounds),
by O(n) sweeps on the chain's tridiagonal W. With --baseline, the same runs by another
build's interpreter (a checkout of an earlier commit installed in its own environment), in
pairs interleaved with this build's: the ratio this / baseline is the median of the pairs'
ratios (the machine's speed drifts between pairs), and the two builds' motions are compared
(max |dx|). Time per step from the library's own CPU time (`stats["cpu_seconds"]`).

Run as a script (`python benchmarks/modal_chain.py --json N`) it prints one pass of timings
and final positions as JSON: what --baseline runs in the other interpreter.
"""
from __future__ import annotations

import json
import subprocess
import sys
import warnings
from pathlib import Path
from typing import Callable

import numpy as np

METHODS: tuple[str, ...] = ("implicit_euler", "galpha", "moreau")
#: blocks -> simulated time [s] (about 0.1 to 2 s of CPU a run)
SIZES: dict[int, float] = {10: 5.0, 100: 2.0, 1000: 0.5}


def one_pass(sizes: dict[int, float] = SIZES) -> dict[str, dict[str, object]]:
    """One run of every (method, blocks): CPU time per step [us], steps, final positions."""
    import stickslip as ss
    out: dict[str, dict[str, object]] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for method in METHODS:
            for n, t_end in sizes.items():
                r = ss.simulate("chain", "coulomb", method=method, h=1e-3, t_end=t_end, n_out=2, n_blocks=n)
                out[f"{method} {n}"] = {"us": 1e6 * r.stats["cpu_seconds"] / r.stats["nstep"],
                                        "nstep": int(r.stats["nstep"]), "x": np.asarray(r.x)[:, -1].tolist()}
    return out


def run_modal_chain(log: Callable[[str], None], repeats: int = 5, baseline: str | None = None,
                    sizes: dict[int, float] = SIZES) -> str:
    """The markdown table: medians of `repeats` passes (interleaved with the baseline's)."""
    from harness.provenance import machine

    ours: list[dict[str, dict[str, object]]] = []
    base: list[dict[str, dict[str, object]]] = []
    for _ in range(repeats):
        ours.append(one_pass(sizes))
        if baseline:
            text = subprocess.run([str(Path(baseline).absolute()), str(Path(__file__).resolve()), "--json",
                                   json.dumps(sizes)],
                                  check=True, capture_output=True, text=True, cwd="/").stdout
            base.append(json.loads(text))
    head = ["**implicit_euler, galpha and moreau on the chain** (`python -m benchmarks --modal-chain`)", "",
            f"Machine: {machine()}. The chain with Coulomb (its band v_s; h = 1 ms), started at rest on the belt; "
            f"the library's CPU time per step, median of {repeats} passes"
            + (f"; the baseline (`{baseline}`, another build's interpreter) in passes interleaved with these, "
               "this / baseline the median "
               "of the pairs' ratios, max |dx| the largest difference of the final positions." if baseline else "."),
            ""]
    cols = "| method | blocks | steps | [us/step] |" + (" baseline [us/step] | this / baseline | max abs dx [m] |"
                                                      if baseline else "")
    head += [cols, "|" + "---|" * (cols.count("|") - 1)]
    for key in ours[0]:
        method, n = key.split()
        t = np.array([p[key]["us"] for p in ours])
        row = f"| {method} | {n} | {ours[0][key]['nstep']:,} | {np.median(t):.3g} |"
        if baseline:
            tb = np.array([p[key]["us"] for p in base])
            dx = np.max(np.abs(np.array(ours[0][key]["x"]) - np.array(base[0][key]["x"])))
            row += f" {np.median(tb):.3g} | {np.median(t / tb):.2f} | {dx:.1e} |"
        head.append(row)
        log(row)
    return "\n".join(head) + "\n"


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--json":
        print(json.dumps(one_pass({int(k): v for k, v in json.loads(sys.argv[2]).items()})))
    else:
        raise SystemExit("usage: modal_chain.py --json SIZES (or python -m benchmarks --modal-chain)")
