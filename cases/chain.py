"""Scaling of every method with the number of contacts on the chain scene::

    python -m cases.chain --outdir out/          # quick: t_end = 1 s, N = 1, 10, 100, 1000
    python -m cases.chain --outdir out/ --full   # t_end = 10 s, N up to 10,000 (LIMIT)

The chain (issue 23): N blocks of 10 kg on the belt (v_b = 1.5 m/s), block 1 tied to the wall
by k = 300 N/m, neighbours by k_c = k, normal forces spread by 1 % (perturbation = 0.01), all
blocks started stuck on the belt at rest length. Every method at one setting, the paper's
middle step and tolerance: h = 1e-3 s (rk4, implicit_euler, galpha, moreau), rtol = 1e-6,
atol = 1e-9 (dopri5, radau5, event_driven). The smooth methods run the regularised Stribeck law
(the smooth law whose set-valued counterpart the nonsmooth methods take), moreau and
event_driven set-valued Coulomb. The settings are fixed, not tuned to one accuracy: the
figure compares how the cost of each method grows with N, not the methods with each other.

Per run: CPU seconds of the library call, steps, CPU per step and per simulated second;
event_driven's events per simulated second. Fitted exponent: the slope of log(CPU per step)
against log(N) over the runs with N >= 100. Slip-event sizes (moreau, N = 100, t_end = 20 s
quick / 100 s full, output every step): the slipping set {(t, i): |v_i - v_b| > 1e-6 m/s}
split into connected pieces in (time step, block) (neighbours in time or along the chain);
the size of an event is the number of distinct blocks in its piece.

Writes ``chain.csv`` (one row per run), ``chain_events.csv`` (event sizes),
``chain.png``/``chain.pdf`` (CPU per step against N, log-log, with the exponents) and
``chain_events.png``/``chain_events.pdf`` (the distribution of event sizes).
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from . import _common as c
from . import _style as style

METHODS: dict[str, tuple[str, dict[str, float]]] = {
    "rk4": ("stribeck", {"h": 1e-3}),
    "dopri5": ("stribeck", {"rtol": 1e-6, "atol": 1e-9}),
    "radau5": ("stribeck", {"rtol": 1e-6, "atol": 1e-9}),
    "implicit_euler": ("stribeck", {"h": 1e-3}),
    "galpha": ("stribeck", {"h": 1e-3}),
    "moreau": ("coulomb", {"h": 1e-3}),
    "event_driven": ("coulomb", {"rtol": 1e-6, "atol": 1e-9}),
}
SIZES_QUICK = (1, 10, 100, 1000)
SIZES_FULL = (1, 10, 100, 1000, 10000)
#: The largest N each method is run at: event_driven's and DOPRI5's steps at N = 10,000 (the
#: --full study) add nothing the exponent does not show.
LIMIT = {"event_driven": 1000, "dopri5": 1000}
#: Okabe-Ito colours (colour-blind safe) and a marker per method.
STYLE = {"rk4": ("#000000", "o"), "dopri5": ("#E69F00", "s"), "radau5": ("#56B4E9", "^"),
         "implicit_euler": ("#009E73", "v"), "galpha": ("#CC79A7", "D"), "moreau": ("#0072B2", "P"),
         "event_driven": ("#D55E00", "X")}
SLIP_SPEED = 1e-6        # |v - v_b| above this is slipping [m/s]
EVENT_BLOCKS = 100

HEADER = ["method [-]", "law [-]", "n_blocks [-]", "t_end [s]", "status [-]", "nstep [-]", "nfev [-]",
          "nevents [-]", "cpu [s]", "cpu_per_step [s]", "cpu_per_simulated_second [-]",
          "events_per_second [1/s]"]


def measure(method: str, n_blocks: int, t_end: float) -> list[Any]:
    """One run of `method` on a chain of n_blocks (output: 11 points)."""
    import stickslip as ss
    law, ctl = METHODS[method]
    try:
        r = ss.simulate("chain", law, method=method, n_blocks=n_blocks, t_end=t_end, n_out=11, **ctl)
    except ss.IntegrationError as e:
        r = e.result
    s = r.stats
    cpu = s["cpu_seconds"]
    return [method, law, n_blocks, t_end, s["status"], s["nstep"], s["nfev"], s["nevents"], cpu,
            cpu / max(s["nstep"], 1), cpu / s["t_reached"] if s["t_reached"] > 0 else math.nan,
            s["nevents"] / t_end if method == "event_driven" else math.nan]


def event_sizes(t_end: float) -> np.ndarray:
    """Sizes of the slip events of a moreau run on EVENT_BLOCKS blocks (see the module notes)."""
    import stickslip as ss
    from scipy import ndimage
    r = ss.simulate("chain", "coulomb", method="moreau", h=1e-3, n_blocks=EVENT_BLOCKS, t_end=t_end,
                    every_step=True)
    slipping = np.abs(r.v - r.params["v_b"]) > SLIP_SPEED          # (blocks, steps)
    labels, count = ndimage.label(slipping)
    sizes = np.zeros(count, dtype=np.int64)
    for k, piece in enumerate(ndimage.find_objects(labels)):
        rows = np.any(labels[piece] == k + 1, axis=1)
        sizes[k] = int(rows.sum())
    return sizes


def fit_exponent(n: np.ndarray, cost: np.ndarray) -> float:
    """Slope of log(cost) against log(n) over n >= 100 (nan with fewer than 2 points)."""
    keep = (n >= 100) & np.isfinite(cost) & (cost > 0)
    if keep.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(n[keep]), np.log(cost[keep]), 1)[0])


def run(outdir: str | Path, *, full: bool = False, quiet: bool = False) -> list[Path]:
    """Run the study and write its CSV files and figures."""
    outdir = Path(outdir)
    t_end = 10.0 if full else 1.0
    rows = []
    for method in METHODS:
        for nb in SIZES_FULL if full else SIZES_QUICK:
            if nb > LIMIT.get(method, nb):
                continue
            c.log(f"cases.chain: {method}, N = {nb}", quiet)
            rows.append(measure(method, nb, t_end))
    csv_path = c.write_csv(outdir / "chain.csv", HEADER, rows)
    sizes = event_sizes(100.0 if full else 20.0)
    ev_path = c.write_csv(outdir / "chain_events.csv", ["event [-]", "size [blocks]"],
                          [[k, s] for k, s in enumerate(sizes)])
    return [csv_path, ev_path, *plot(csv_path, ev_path, outdir)]


def plot(csv_path: Path, ev_path: Path, outdir: Path) -> list[Path]:
    """The scaling figure and the event-size figure, from the CSV files alone."""
    cols = c.read_csv(csv_path)
    method = np.array(cols["method [-]"])
    n = np.array(cols["n_blocks [-]"], dtype=float)
    cost = np.array(cols["cpu_per_step [s]"], dtype=float)
    fig, ax = c.new_figure()
    for m in METHODS:
        sel = method == m
        if not sel.any():
            continue
        p = fit_exponent(n[sel], cost[sel])
        color, marker = STYLE[m]
        fit = f"exponent {p:.2f}" if math.isfinite(p) else "run to N = 100: no fit"
        ax.loglog(n[sel], cost[sel] * 1e6, marker=marker, color=color, label=f"{style.name(m)} ({fit})")
    ax.set_xlabel("number of blocks N [-]")
    ax.set_ylabel("CPU time per step [microseconds]")
    ax.set_title("Cost per step against the number of contacts (fit over N >= 100)")
    ax.legend()
    out = [c.save_figure(fig, outdir / "chain.png")]
    sizes = np.array(c.read_csv(ev_path)["size [blocks]"], dtype=int)
    fig, ax = c.new_figure()
    if sizes.size:
        edges = np.unique(np.round(np.logspace(0, math.log10(max(sizes.max(), 2)) + 0.01, 20)))
        counts, edges = np.histogram(sizes, bins=np.append(edges, edges[-1] + 1))
        centres = np.sqrt(edges[:-1] * edges[1:])
        widths = np.diff(edges)
        keep = counts > 0
        ax.loglog(centres[keep], counts[keep] / widths[keep], marker="o", linestyle="none",
                  color=STYLE["moreau"][0])
    ax.set_xlabel("event size: blocks that slip together [-]")
    ax.set_ylabel("events per unit size [-]")
    ax.set_title(f"Slip-event sizes, {EVENT_BLOCKS} blocks, moreau h = 1e-3 s ({sizes.size} events)")
    out.append(c.save_figure(fig, outdir / "chain_events.png"))
    return out


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.chain [--outdir DIR] [--full] [--threads N] [--quiet]."""
    parser = argparse.ArgumentParser(prog="python -m cases.chain", description=__doc__.split("\n\n")[0])
    parser.add_argument("--outdir", type=Path, default=Path("out"),
                        help="directory for CSV and figure files (default: out/)")
    parser.add_argument("--full", action="store_true",
                        help="t_end = 10 s and N up to 10,000 (default: t_end = 1 s, N up to 1,000)")
    parser.add_argument("--threads", type=c.count, default=1,
                        help="accepted for python -m cases; the runs are serial (default 1)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    args = parser.parse_args(argv)
    files = run(args.outdir, full=args.full, quiet=args.quiet)
    c.print_files(files)
    return files


if __name__ == "__main__":
    main()
