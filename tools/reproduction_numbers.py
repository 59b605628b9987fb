"""The numbers the reproduction report derives from the paper's figure CSVs (its **(D)** marks).

The figure CSVs of `python -m cases` (time series, not committed) hold more than the tables:
how close the harmonic belt runs stay to the exact solution, the proposed law's peaks, its
limit cycle's range and period, and how far apart the curves of one figure lie. This command
reads them from the directory a run wrote and writes those numbers, named, into
`reproduction_derived.json` (tools/docnumbers.py's format) with its provenance sidecar, with
the proposed law's stick time on the belt from a run on a finer grid (0.1 ms); the
report quotes them with the {num} role.

    python -m cases --outdir out && python tools/reproduction_numbers.py out --outdir docs/figures
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Sequence

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from harness.files import read_csv, read_numeric_csv, write_text  # noqa: E402 - after the path above
from harness.provenance import write_provenance  # noqa: E402
from tools.docnumbers import numbers_json  # noqa: E402

#: The paper's belt (Table 1): x_k = mu_k m g / k about which Coulomb and RecurDyn oscillate, w.
X_K, OMEGA = 0.30 * 10 * 9.81 / 300, math.sqrt(300 / 10)
#: The belt's figures with harmonic runs (every curve but the proposed law's).
HARMONIC = ("fig13_belt_automatic", "fig14_belt_steps_recurdyn", "fig16_belt_steps_coulomb",
            "fig17_belt_tolerances_recurdyn", "fig19_belt_tolerances_coulomb")
#: The figures whose curves (one law, several steps or tolerances) should coincide.
SPREAD = ("fig06_slope_steps_recurdyn", "fig07_slope_steps_proposed", "fig09_slope_tolerances_recurdyn",
          "fig10_slope_tolerances_proposed", "fig14_belt_steps_recurdyn", "fig15_belt_steps_proposed",
          "fig16_belt_steps_coulomb", "fig17_belt_tolerances_recurdyn", "fig18_belt_tolerances_proposed")
#: The limit cycle's stretch of the belt run [s]: from here on (the proposed law first sticks at
#: table3's t_first_stick; the peaks before it grow, those after it repeat).
LATE = 20.0


def derived(figures: Path) -> dict[str, tuple[float, str, str]]:
    """The named numbers, from the figure CSVs in `figures`."""
    out: dict[str, tuple[float, str, str]] = {}
    dev = 0.0
    for name in HARMONIC:
        c = read_numeric_csv(figures / f"{name}.csv")
        t = c.pop("t [s]")
        for key, x in c.items():
            if "proposed" not in key:
                dev = max(dev, float(np.abs(x - X_K * (1 - np.cos(OMEGA * t))).max()))
    out["belt.harmonic_deviation"] = (dev, "m", "largest |x - x_k (1 - cos wt)| of the Coulomb and "
                                      "RecurDyn belt runs (Figs. 13, 14, 16, 17, 19)")
    c = read_numeric_csv(figures / "fig13_belt_automatic.csv")
    t, x = c["t [s]"], c["x proposed [m]"]
    peaks = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:])) + 1
    table3 = read_csv(figures / "table3_belt_cpu.csv")
    first_stick = float(next(s for law, mode, s in zip(table3["law [-]"], table3["mode [-]"],
                                                        table3["t_first_stick [s]"])
                             if law == "proposed" and mode == "automatic"))
    growing = [k for k in peaks if t[k] < first_stick]          # before the first stick
    repeating = [k for k in peaks if t[k] >= first_stick]
    out["proposed.peaks_growing"] = (len(growing), "", "peaks of the proposed law's growth (Fig. 13)")
    out["proposed.first_peak_t"] = (float(t[peaks[0]]), "s", "time of the first peak")
    out["proposed.first_peak_x"] = (float(x[peaks[0]]), "m", "the first peak")
    out["proposed.last_growing_peak_t"] = (float(t[growing[-1]]), "s", "time of the growth's last peak")
    out["proposed.last_growing_peak_x"] = (float(x[growing[-1]]), "m", "the growth's last peak")
    out["proposed.first_cycle_peak_t"] = (float(t[repeating[0]]), "s", "time of the cycle's first peak")
    out["proposed.cycle_peak_min"] = (float(x[repeating].min()), "m", "the cycle's lowest peak")
    out["proposed.cycle_peak_max"] = (float(x[repeating].max()), "m", "the cycle's highest peak")
    late = t >= LATE
    out["proposed.late_x_min"] = (float(x[late].min()), "m", f"smallest x for t >= {LATE:g} s")
    out["proposed.late_x_max"] = (float(x[late].max()), "m", f"largest x for t >= {LATE:g} s")
    out["proposed.late_period"] = (float(np.diff(t[peaks][t[peaks] > LATE]).mean()), "s",
                                   f"mean time between peaks after {LATE:g} s")
    # a finer output grid than the figures' (0.1 ms): how long the proposed law sticks
    import stickslip as ss
    r = ss.simulate("belt", "proposed", method="dopri5", t_end=30.0, n_out=300001)
    v_rel, tt = 1.5 - r.v, r.t
    stuck = float(((v_rel < 0.01) & (tt > 25)).sum() * (tt[1] - tt[0]))
    out["proposed.stuck_25_30"] = (stuck, "s", "time with v_rel < v_s between 25 and 30 s (0.1 ms grid)")
    out["proposed.stuck_per_cycle"] = (stuck / (5.0 / out["proposed.late_period"][0]), "s",
                                       "that time per cycle of the limit cycle")
    out["proposed.first_stick_fine"] = (float(tt[np.argmax(v_rel < 0.01)]), "s",
                                        "first v_rel < v_s on the 0.1 ms grid")
    for name in SPREAD:
        c = read_numeric_csv(figures / f"{name}.csv")
        c.pop("t [s]")
        spread = float(np.ptp(np.array(list(c.values())), axis=0).max())
        out[f"{name}.spread"] = (spread, "m", f"largest distance between the curves of {name}")
    return out


def main(argv: Sequence[str] | None = None) -> list[Path]:
    parser = argparse.ArgumentParser(prog="python tools/reproduction_numbers.py", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("figures", type=Path, help="the directory of a python -m cases run")
    parser.add_argument("--outdir", type=Path, default=ROOT / "docs" / "figures",
                        help="where reproduction_derived.json goes (default: docs/figures)")
    argv = sys.argv[1:] if argv is None else list(argv)
    args = parser.parse_args(argv)
    missing = [n for n in (*HARMONIC, *SPREAD) if not (args.figures / f"{n}.csv").is_file()]
    if missing:
        parser.error(f"figures: {args.figures} lacks {', '.join(missing)}.csv (run python -m cases "
                     f"--outdir {args.figures} first)")
    path = write_text(args.outdir / "reproduction_derived.json", numbers_json(derived(args.figures)))
    files = [path, write_provenance(args.outdir, "tools.reproduction_numbers", [path], argv)]
    print(f"wrote {path}")
    return files


if __name__ == "__main__":
    main()
