"""Selection at the records' full rate (python -m benchmarks.select_speed): the law chosen by
`stickslip.select_friction_law` over the ten 36 lb damper records (each held out in turn;
backlash and asymmetry fitted, cases.identify's fixed parameters, rtol and finite-difference
step) at the records' full rate with a screening pass (`screen=48`: every law's fits on the
records decimated to about 48 samples per cycle through an anti-aliasing filter, the folds'
fits scored on the held-out records at full rate, the chosen law refitted at full rate),
against the same selection on the records subsampled to 48 samples per cycle as
cases.identify does. CPU time of this process (`time.process_time`); the two choices must be
the same. Writes a markdown row per run to benchmarks/results/select_speed.md (or --out).
"""
from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path
from typing import Callable, Sequence

#: The laws of the identification guide's selection example (Coulomb, Dahl, LuGre).
LAWS: tuple[str, ...] = ("coulomb", "dahl", "lugre")
#: Samples per cycle of the screening pass and of the subsampled selection.
PER_CYCLE: int = 48
#: The selection at full rate must take less CPU time than this [s].
BUDGET_CPU_S: float = 60.0


def run_select_speed(log: Callable[[str], None], laws: Sequence[str] = LAWS) -> tuple[list[dict], str]:
    """Rows (full rate with screening; subsampled) and the markdown table."""
    import stickslip
    from cases import identify as ci
    from harness.provenance import machine

    files = stickslip.damper_files(36)
    full = [stickslip.load_damper_record(f) for f in files]
    sub = [r for r, _ in ci.load_groups(files)["36lb"]]
    kw = dict(backlash="fit", asymmetry="fit", fixed={law: ci.fixed_for(law) for law in laws},
              rtol=ci.RTOL, diff_step=ci.DIFF_STEP)
    rows = []
    for label, recs, extra in (("full rate, screen=48", full, {"screen": PER_CYCLE}),
                               ("subsampled to 48 a cycle", sub, {})):
        w0, c0 = time.perf_counter(), time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sel = stickslip.select_friction_law(list(laws), recs, **kw, **extra)
        row = {"run": label, "samples": sum(len(r) for r in recs), "wall [s]": time.perf_counter() - w0,
               "cpu [s]": time.process_time() - c0, "best": sel.best,
               "scores": {law: sel.scores[law] for law in laws}}
        rows.append(row)
        log(f"{label}: {row['cpu [s]']:.1f} s CPU ({row['wall [s]']:.1f} s wall), chose {sel.best}; "
            + ", ".join(f"{law} {m:.4f} +- {se:.4f}" for law, (m, se) in row["scores"].items()))
    same = rows[0]["best"] == rows[1]["best"]
    lines = ["**Selection at the records' full rate** (`python -m benchmarks.select_speed`)", "",
             f"Machine: {machine()}. `select_friction_law({list(laws)!r}, ...)` over the ten 36 lb damper records "
             "(each held out in turn; backlash and asymmetry fitted; cases.identify's fixed parameters, rtol "
             f"{ci.RTOL:g}, diff_step {ci.DIFF_STEP:g}). Full rate with a screening pass (screen={PER_CYCLE}: the "
             "fits on the records decimated through an order-8 Butterworth anti-aliasing filter, zero phase, the "
             "folds scored on the held-out records at full rate, the chosen law refitted at full rate), and the "
             f"records subsampled to {PER_CYCLE} samples per cycle (cases.identify's). CPU time of the process "
             f"(budget {BUDGET_CPU_S:g} s at full rate); the same choice: {'yes' if same else 'NO'}.", "",
             "| run | samples | CPU [s] | wall [s] | chosen | "
             + " | ".join(f"{law} CV NRMSE | {law} s.e." for law in laws) + " |",
             "|---|---|---|---|---|" + "---|---|" * len(laws)]
    lines += [f"| {r['run']} | {r['samples']} | {r['cpu [s]']:.1f} | {r['wall [s]']:.1f} | {r['best']} | "
              + " | ".join(f"{m:.4f} | {se:.4f}" for m, se in r["scores"].values()) + " |" for r in rows]
    return rows, "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "select_speed.md",
                        help="markdown file to write (default: benchmarks/results/select_speed.md)")
    args = parser.parse_args(argv)
    from harness.files import write_text
    from harness.provenance import write_provenance
    _, table = run_select_speed(print)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_text(args.out, table)
    write_provenance(args.out.parent, "benchmarks.select_speed", [args.out], argv)
    print(table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
