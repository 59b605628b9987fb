"""The scenes as presets against the scene code they replaced (python -m benchmarks --presets
--base SITE): the slope, the belt and the chain of 10, 100 and 1000 blocks, each run by
`stickslip.simulate(scene, ...)` in this tree (the preset: a model, its structure found once
when built) and in a build of the package before the presets (its own scene types and kernels),
installed into the directory SITE (for example
``git worktree add /tmp/base <commit> && pip install --no-build-isolation --no-deps --target SITE /tmp/base``).

Each side runs in its own process (`python -m benchmarks.presets --worker`), which runs every
case once untimed (warming up) and then once timed, and prints its CPU time per step (the
library's own, `stats["cpu_seconds"]`: the integration alone) and its end state; the two sides alternate `repeats` times, so that the
machine's drift falls on both alike. The ratio preset / scene is the median of the pairs'
ratios; both sides take the same steps (checked) and end in the same state (max |dx| reported).

With `--instructions` each side also runs every case once under valgrind's callgrind, which
counts the instructions the library executes inside its run (`run_prepared`, dumped after each
call): a cost that does not move with the machine's load or with where the linker happens to
place the code, which moves the CPU time of a short loop by up to a fifth between two builds
that execute the same instructions (the docs' benchmarks page shows a case).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any, Callable

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

#: (scene, law, method, controls, scene parameters, t_end [s]) of the table's rows.
CASES: tuple[tuple[str, str, str, dict[str, float], dict[str, float], float], ...] = (
    ("slope", "stribeck", "rk4", {"h": 1e-5}, {"v0": 1.0}, 2.0),
    ("slope", "coulomb", "implicit_euler", {"h": 1e-4}, {"v0": 1.0}, 2.0),
    ("belt", "stribeck", "rk4", {"h": 1e-5}, {}, 2.0),
    ("belt", "proposed", "dopri5", {"rtol": 1e-10, "atol": 1e-12}, {}, 20.0),
    ("belt", "recurdyn", "radau5", {"rtol": 1e-8, "atol": 1e-10}, {}, 20.0),
    ("belt", "recurdyn", "implicit_euler", {"h": 1e-4}, {}, 2.0),
    ("belt", "coulomb", "galpha", {"h": 1e-4}, {}, 2.0),
    ("belt", "lugre", "dopri5", {"rtol": 1e-6, "atol": 1e-8}, {}, 2.0),
    ("belt", "coulomb", "moreau", {"h": 1e-5}, {}, 2.0),
    ("belt", "coulomb", "event_driven", {"rtol": 1e-10, "atol": 1e-12}, {}, 50.0),
) + tuple(
    ("chain", law, method, ctl, {"n_blocks": n}, t_end)
    for n, t_end in ((10, 2.0), (100, 0.5), (1000, 0.1))
    for law, method, ctl in (("proposed", "rk4", {"h": 1e-4}),
                             ("lugre", "dopri5", {"rtol": 1e-6, "atol": 1e-8}),
                             ("recurdyn", "implicit_euler", {"h": 1e-3}),
                             ("coulomb", "moreau", {"h": 1e-4}))
)


def _worker(count: bool = False) -> None:
    """Run every case (once to warm up, then timed; `count`: once, under callgrind) with
    whatever `stickslip` this process imports; print JSON."""
    import warnings

    import stickslip as ss

    def run(case: tuple[str, str, str, dict[str, float], dict[str, float], float]) -> Any:
        scene, law, method, ctl, params, t_end = case
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ss.simulate(scene, law, method=method, t_end=t_end, n_out=2, **ctl, **params)

    # every case once untimed first: a fresh process's first runs are up to 2x slower (the
    # CPU's clock and caches warming; measured 1.1-2.1 us a step against 0.65-0.9 on the belt's
    # event_driven row), and the side that does more work on import would come out warmer
    for case in () if count else CASES:
        run(case)
    out = []
    for case in CASES:
        r = run(case)
        out.append({"per_step": r.stats["cpu_seconds"] / r.stats["nstep"], "nstep": int(r.stats["nstep"]),
                    "x": np.atleast_2d(r.x)[:, -1].tolist()})
    print(json.dumps({"file": ss.__file__, "runs": out}))


def _run_side(base_site: str | None, count_dir: Path | None = None) -> dict[str, Any]:
    """One worker process: this tree's package (base_site None) or the one in base_site; under
    callgrind when count_dir is given (each case's instructions in its run, as "instructions")."""
    env = dict(os.environ)
    cmd = [sys.executable, "-m", "benchmarks.presets", "--worker"] + (["--count"] if count_dir else [])
    if base_site is not None:
        env["PYTHONPATH"] = base_site
        # the editable install's finder comes before PYTHONPATH: run without it
        cmd = [sys.executable, "-c", "import sys; sys.meta_path = [f for f in sys.meta_path "
               "if 'editable' not in type(f).__module__]; sys.argv = ['presets', '--worker'"
               + (", '--count'" if count_dir else "") + "]; "
               "import runpy; runpy.run_module('benchmarks.presets', run_name='__main__')"]
    if count_dir is not None:
        for old in count_dir.glob("cg.out*"):
            old.unlink()
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={count_dir / 'cg.out'}",
               "--toggle-collect=run_prepared_", "--dump-after=run_prepared_"] + cmd
    run = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, check=True)
    side = json.loads(run.stdout.strip().splitlines()[-1])
    if count_dir is not None:
        # one dump per run, in the cases' order (cg.out.1, cg.out.2, ...)
        dumps = sorted(count_dir.glob("cg.out.*"), key=lambda f: int(f.suffix[1:]))
        if len(dumps) != len(side["runs"]):
            raise RuntimeError(f"callgrind wrote {len(dumps)} dumps for {len(side['runs'])} runs")
        for r, dump in zip(side["runs"], dumps):
            totals = [line for line in dump.read_text().splitlines() if line.startswith("totals:")]
            r["instructions"] = int(totals[0].split()[1])
    return side


def run_presets(log: Callable[[str], None], base_site: str, repeats: int = 5, instructions: bool = False) -> str:
    """The markdown table: preset / scene per case, medians of `repeats` interleaved pairs (and,
    with `instructions`, each side's instructions a step under callgrind and their ratio)."""
    import shutil
    import tempfile

    from harness.provenance import machine

    if instructions and shutil.which("valgrind") is None:
        raise RuntimeError("--instructions needs valgrind (apt-get install valgrind)")
    new, old = [], []
    for i in range(repeats):
        old.append(_run_side(base_site))
        new.append(_run_side(None))
        log(f"presets: pair {i + 1}/{repeats}")
    if old[0]["file"] == new[0]["file"]:
        raise RuntimeError(f"both sides imported {new[0]['file']}: is --base a separate build?")
    counted: list[dict[str, Any]] = []
    if instructions:
        with tempfile.TemporaryDirectory() as tmp:
            for site in (base_site, None):
                counted.append(_run_side(site, Path(tmp)))
                log(f"presets: instructions counted ({'scene' if site else 'preset'} side)")
    count_head = " scene [instr/step] | preset [instr/step] | instructions preset / scene |" if instructions else ""
    lines = ["**The scenes as presets against the scene code they replaced** (`python -m benchmarks "
             "--presets --base SITE`)", "",
             f"Machine: {machine()}. Each scene run by `simulate(scene, ...)` in this tree (a preset: "
             "the scene's model, its structure found when built) and in a build of the package before "
             "the presets (the scene types and their kernels); the library's CPU time per step, median "
             f"of {repeats} runs each, the two alternating in separate processes; preset / scene: the "
             "median of the pairs' ratios."
             + (" Instructions: those the library executes in the run, counted by valgrind's callgrind "
                "(one run a side), per step." if instructions else ""), "",
             "| scene | law | method | controls | steps | scene [us/step] | preset [us/step] | preset / scene |"
             + count_head + " max abs dx [m] |",
             "|---|---|---|---|---|---|---|---|" + ("---|---|---|" if instructions else "") + "---|"]
    for k, (scene, law, method, ctl, params, _) in enumerate(CASES):
        steps = {run["runs"][k]["nstep"] for run in old + new + counted}
        if len(steps) != 1:
            raise RuntimeError(f"{scene}/{law}/{method}: the two builds took {sorted(steps)} steps")
        nstep = steps.pop()
        s = np.array([o["runs"][k]["per_step"] for o in old])
        p = np.array([n["runs"][k]["per_step"] for n in new])
        dx = float(np.max(np.abs(np.array(old[0]["runs"][k]["x"]) - np.array(new[0]["runs"][k]["x"]))))
        name = scene if scene != "chain" else f"chain {params['n_blocks']}"
        controls = ", ".join(f"{key} = {v:g}" for key, v in ctl.items())
        count_cells = ""
        if instructions:
            si, pi = (c["runs"][k]["instructions"] / nstep for c in counted)
            count_cells = f" {si:,.0f} | {pi:,.0f} | {pi / si:.3f} |"
        lines.append(f"| {name} | {law} | {method} | {controls} | {nstep:,} | {1e6 * np.median(s):.3g} | "
                     f"{1e6 * np.median(p):.3g} | {np.median(p / s):.3f} |{count_cells} {dx:.1e} |")
        log(lines[-1])
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    """`--worker`: one side's runs (JSON on stdout)."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worker", action="store_true", help="run every case once and print JSON")
    parser.add_argument("--count", action="store_true", help="with --worker: no warm-up pass (under callgrind)")
    args = parser.parse_args(argv)
    if args.worker:
        _worker(args.count)
    return 0


if __name__ == "__main__":
    sys.exit(main())
