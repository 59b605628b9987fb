"""The model path against the chain's own code (python -m benchmarks --model): a chain of 100
blocks on the belt built as a `stickslip.Model` (`Model.from_scene("chain", ...)`), run by the
general model code, and the same chain run by its specialised scene code, at equal settings.
Time per step from the library's own CPU time of each run (`stats["cpu_seconds"]`, the
integration alone: no Python), median of `repeats` runs each, interleaved; the ratio model /
scene is the median of the pairs' ratios (the machine's speed drifts between pairs); both
runs take the same steps (checked) and their motions agree (max |dx| reported).
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np

#: (law, method, controls) of the table's rows: every method family on the chain.
CASES: tuple[tuple[str, str, dict[str, Any]], ...] = (
    ("proposed", "rk4", {"h": 1e-4}),
    ("proposed", "dopri5", {"rtol": 1e-6, "atol": 1e-8}),
    ("lugre", "dopri5", {"rtol": 1e-6, "atol": 1e-8}),
    ("recurdyn", "radau5", {"rtol": 1e-6, "atol": 1e-8}),
    ("recurdyn", "implicit_euler", {"h": 1e-3}),
    ("coulomb", "moreau", {"h": 1e-4}),
    ("coulomb", "event_driven", {"rtol": 1e-8, "atol": 1e-10}),
)
N_BLOCKS: int = 100
T_END: float = 0.5


def run_model_chain(log: Callable[[str], None], repeats: int = 9, n_blocks: int = N_BLOCKS) -> str:
    """The markdown table (medians of `repeats` interleaved runs each)."""
    import stickslip as ss
    from harness.provenance import machine

    lines = ["**The model path against the chain's own code** (`python -m benchmarks --model`)", "",
             f"Machine: {machine()}. A chain of {n_blocks} blocks on the belt over {T_END:g} s, as a "
             "`Model` (`Model.from_scene`) and as the built-in scene; the library's CPU time per step, "
             f"median of {repeats} interleaved runs each; model / scene: the median of the pairs' ratios.", "",
             "| law | method | controls | steps | scene [us/step] | model [us/step] | model / scene | max abs dx [m] |",
             "|---|---|---|---|---|---|---|---|"]
    for law, method, ctl in CASES:
        model = ss.Model.from_scene("chain", law, n_blocks=n_blocks)
        per_scene, per_model = [], []
        for _ in range(repeats):
            rs = ss.simulate("chain", law, method=method, t_end=T_END, n_out=11, n_blocks=n_blocks, **ctl)
            rm = ss.simulate(model, method=method, t_end=T_END, n_out=11, **ctl)
            if rs.stats["nstep"] != rm.stats["nstep"]:
                raise RuntimeError(f"{law}/{method}: the model took {rm.stats['nstep']} steps, "
                                   f"the scene {rs.stats['nstep']}")
            per_scene.append(rs.stats["cpu_seconds"] / rs.stats["nstep"])
            per_model.append(rm.stats["cpu_seconds"] / rm.stats["nstep"])
        s, m = float(np.median(per_scene)), float(np.median(per_model))
        ratio = float(np.median(np.array(per_model) / np.array(per_scene)))
        controls = ", ".join(f"{k} = {v:g}" for k, v in ctl.items())
        lines.append(f"| {law} | {method} | {controls} | {rs.stats['nstep']:,} | {1e6 * s:.3g} | {1e6 * m:.3g} | "
                     f"{ratio:.2f} | {np.max(np.abs(rs.x - rm.x)):.1e} |")
        log(lines[-1])
    return "\n".join(lines) + "\n"
