"""Cost of every method against the number of contacts, at one accuracy, on a Burridge-Knopoff
chain; and the sizes of its slip events::

    python -m cases.chain --outdir out/          # quick: t_end = 0.5 s, N up to 1,000, 1e-3 m
    python -m cases.chain --outdir out/ --full   # t_end = 1 s, N up to 10,000, 1e-4 m

The chain (`SCENE`): N blocks of 10 kg on a slow belt (v_b = 0.01 m/s), block 1 tied to the
wall by k = 300 N/m, neighbours by k_c = 300 N/m, every block to the wall by a loading spring
k_p = 10 N/m (Burridge and Knopoff's leaf springs), normal forces spread by 20 %
(perturbation = 0.2), Coulomb mu_s = 0.35, mu_k = 0.3. Every block starts stuck on the belt
with its wall springs preloaded (`preload`) between the kinetic and the static level, so that
slip starts everywhere at once and the number of stick-slip events grows with N.

**Scaling at one accuracy.** For each method and N the study walks the method's ladder of
settings (`FIXED_STEPS` h [s] for the fixed-step methods, `TOLERANCES` rtol, with atol = 1e-3
rtol [m, m/s], for the adaptive ones) from coarse to fine and keeps the first setting whose
position error, and that of the next finer setting, are at most the target (max over blocks
and the 51 output times of |x_i - x_i,ref|). The references: RADAU5 at rtol = 1e-10 for the
smooth methods (regularised Stribeck law), event_driven at rtol = 1e-10 for moreau and
event_driven (set-valued Coulomb). Where N is beyond a reference's reach (`REFERENCE_LIMIT`)
the method runs at the setting kept for the largest N that had one, and its error is not
measured (hollow markers). The cost is the CPU time of the kept run's library call.

**Slip events** (N = 100, 1,000 s quick, 5,000 s full, the first 10 % dropped): the slipping set
{(t, i): |v_i - v_b| > 1e-6 m/s} of a moreau run (h = 1e-3 s) on a 0.05 s output grid, split
into connected pieces in (time, block); the size of an event is the number of blocks in its
piece.

Writes ``chain.csv`` (one row per method and N), ``chain_events.csv`` (event sizes and start
times), ``chain_exponents.md`` (the fitted exponents), ``chain_events.md`` (the events by size
class), ``chain.png``/``.pdf`` (cost per simulated second at the target and cost per step
against N, log-log, with fitted exponents) and ``chain_events.png``/``.pdf``; with ``--full``
the same files named ``chain_full*``. ``--replot`` redraws the figures and tables from the CSV
files alone.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any, NamedTuple, Sequence

import numpy as np

from harness import style

from . import _common as c
#: The study's chain: the scene's parameters that differ from the defaults.
SCENE: dict[str, float] = {"k_p": 10.0, "k_c": 300.0, "perturbation": 0.2, "v_b": 0.01}
#: Law of each method: the smooth ones take the regularised Stribeck law, the set-valued ones
#: its set-valued counterpart, Coulomb.
METHODS: dict[str, str] = {"rk4": "stribeck", "dopri5": "stribeck", "dop853": "stribeck",
                           "radau5": "stribeck", "implicit_euler": "stribeck", "galpha": "stribeck",
                           "moreau": "coulomb", "event_driven": "coulomb"}
FIXED_STEPS = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5)    # h [s]
TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)                       # rtol [-]
#: The reference of each law's family.
REFERENCE: dict[str, tuple[str, dict[str, float]]] = {
    "stribeck": ("radau5", {"rtol": 1e-10, "atol": 1e-13}),
    "coulomb": ("event_driven", {"rtol": 1e-10, "atol": 1e-13})}


class Plan(NamedTuple):
    """What one version of the study runs."""

    t_end: float                   #: simulated time of each scaling run [s]
    sizes: tuple[int, ...]         #: numbers of blocks N
    target: float                  #: position error the settings must meet [m]
    limit: dict[str, int]          #: largest N each method runs at (default: every N)
    reference_limit: dict[str, int]   #: largest N each law's reference runs at
    events_t_end: float            #: simulated time of the slip-event run [s]


#: event_driven's events, and so its cost, grow with N on this chain (its cost per simulated
#: second goes as N^2): it stops at 100 blocks in the quick study, 1,000 in the full one.
#: Implicit Euler needs h <= 1e-5 s for 1e-4 m (first order, a large error constant): it stops
#: at 1,000 blocks in the full study.
QUICK = Plan(0.5, (1, 10, 100, 1000), 1e-3, {"event_driven": 100}, {"stribeck": 1000, "coulomb": 100},
             1000.0)
FULL = Plan(1.0, (1, 10, 100, 1000, 10000), 1e-4, {"event_driven": 1000, "implicit_euler": 1000},
            {"stribeck": 10000, "coulomb": 1000}, 5000.0)
N_OUT = 51
MARKERS: dict[str, str] = style.METHOD_MARKERS
SLIP_SPEED = 1e-6        # |v - v_b| above this is slipping [m/s]
EVENT_BLOCKS = 100
EVENT_DT = 0.05          # output grid of the slip-event run [s]

HEADER = ["method [-]", "law [-]", "n_blocks [-]", "t_end [s]", "control [-]", "setting [-]",
          "error [m]", "target [m]", "status [-]", "nstep [-]", "nfev [-]", "nevents [-]", "cpu [s]",
          "cpu_per_step [s]", "cpu_per_simulated_second [-]", "events_per_second [1/s]"]


def preload(n_blocks: int) -> np.ndarray:
    """Initial positions [m]: block i's springs to the wall hold mu_i m g, mu_i = mu_k + (mu_s -
    mu_k) u_i between the kinetic and the static level, u_i = frac(i (sqrt 2 - 1)) (a sequence
    unrelated to the normal forces' spread; m, g, k, mu_s, mu_k at their defaults)."""
    import stickslip as ss
    d = ss.DEFAULTS
    u = np.mod(np.arange(n_blocks) * (math.sqrt(2.0) - 1.0), 1.0)
    wall = np.full(n_blocks, SCENE["k_p"])
    wall[0] += d["k"]
    return (d["mu_k"] + (d["mu_s"] - d["mu_k"]) * u) * d["m"] * d["g"] / wall


def _run(method: str, law: str, n_blocks: int, t_end: float, **ctl: float) -> Any:
    """The chain run (a Result; the partial one of a run that ended early)."""
    import stickslip as ss
    try:
        return ss.simulate("chain", law, method=method, n_blocks=n_blocks, t_end=t_end, n_out=N_OUT,
                           x0=preload(n_blocks), **SCENE, **ctl)
    except ss.IntegrationError as e:
        return e.result


def _controls(method: str, setting: float) -> tuple[str, dict[str, float]]:
    import stickslip as ss
    if "h" in ss.REGISTRY["method"][method]["controls"]:
        return "h", {"h": setting}
    return "rtol", {"rtol": setting, "atol": 1e-3 * setting}


def _error(r: Any, ref: Any) -> float:
    """Max over blocks and output times of |x - x_ref| [m]; inf for a run that ended early."""
    if r.stats["status"] != 0:
        return math.inf
    return float(np.max(np.abs(np.atleast_2d(r.x) - np.atleast_2d(ref.x))))


def ladder(method: str) -> tuple[float, ...]:
    """The method's settings from coarse to fine: FIXED_STEPS or TOLERANCES."""
    return FIXED_STEPS if _controls(method, 1.0)[0] == "h" else TOLERANCES


def at_target(method: str, n_blocks: int, plan: Plan, ref: Any | None,
              carried: float | None) -> list[Any]:
    """The CSV row of `method` on N blocks at the plan's target (see the module notes). With a
    reference the ladder starts one setting coarser than `carried` (the setting kept at the
    previous N; a larger chain rarely allows a coarser one); without, `carried` is run."""
    law = METHODS[method]
    kind = _controls(method, 1.0)[0]
    settings = ladder(method)
    if ref is None:                               # no reference here: the setting carried over
        setting = carried if carried is not None else settings[-1]
        r, err = _run(method, law, n_blocks, plan.t_end, **_controls(method, setting)[1]), math.nan
    else:
        first = max(0, settings.index(carried) - 1) if carried is not None else 0
        tried: list[tuple[float, Any, float]] = []
        chosen = None
        for setting in settings[first:]:
            r = _run(method, law, n_blocks, plan.t_end, **_controls(method, setting)[1])
            tried.append((setting, r, _error(r, ref)))
            if len(tried) >= 2 and tried[-2][2] <= plan.target and tried[-1][2] <= plan.target:
                chosen = tried[-2]
                break
        if chosen is None:                        # not met, or met only by the finest setting
            chosen = tried[-1]
        setting, r, err = chosen
    s = r.stats
    cpu = s["cpu_seconds"]
    return [method, law, n_blocks, plan.t_end, kind, setting, err, plan.target, s["status"], s["nstep"],
            s["nfev"], s["nevents"], cpu, cpu / max(s["nstep"], 1),
            cpu / s["t_reached"] if s["t_reached"] > 0 else math.nan,
            s["nevents"] / plan.t_end if method == "event_driven" else math.nan]


def scaling(plan: Plan, quiet: bool = False) -> list[list[Any]]:
    """Every method at every N of the plan (the rows of chain.csv)."""
    rows: list[list[Any]] = []
    carried: dict[str, float] = {}
    for n_blocks in plan.sizes:
        refs = {}
        for law, (method, ctl) in REFERENCE.items():
            if n_blocks <= plan.reference_limit[law]:
                c.log(f"cases.chain: reference {method} ({law}), N = {n_blocks}", quiet)
                refs[law] = _run(method, law, n_blocks, plan.t_end, **ctl)
        for method, law in METHODS.items():
            if n_blocks > plan.limit.get(method, n_blocks):
                continue
            c.log(f"cases.chain: {method}, N = {n_blocks}", quiet)
            row = at_target(method, n_blocks, plan, refs.get(law), carried.get(method))
            if law in refs and row[6] <= plan.target:
                carried[method] = row[5]
            rows.append(row)
    return rows


def slip_events(slipping: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The connected pieces of a (blocks, times) boolean array, neighbours along the chain or
    in time (not diagonal): each piece's number of distinct blocks and its first time index,
    in the order of their first element (block-major)."""
    from scipy import ndimage
    labels, _ = ndimage.label(slipping)
    sizes, starts = [], []
    for k, piece in enumerate(ndimage.find_objects(labels)):
        mine = labels[piece] == k + 1
        sizes.append(int(np.any(mine, axis=1).sum()))
        starts.append(int(piece[1].start + np.flatnonzero(np.any(mine, axis=0))[0]))
    return np.array(sizes, dtype=np.int64), np.array(starts, dtype=np.int64)


def event_sizes(t_end: float) -> tuple[np.ndarray, np.ndarray]:
    """Sizes [blocks] and start times [s] of the slip events of a moreau run on EVENT_BLOCKS
    blocks (see the module notes)."""
    import stickslip as ss
    n_out = int(round(t_end / EVENT_DT)) + 1
    r = ss.simulate("chain", "coulomb", method="moreau", h=1e-3, n_blocks=EVENT_BLOCKS, t_end=t_end,
                    n_out=n_out, x0=preload(EVENT_BLOCKS), **SCENE)
    skip = n_out // 10
    sizes, first = slip_events(np.abs(r.v[:, skip:] - SCENE["v_b"]) > SLIP_SPEED)
    return sizes, r.t[skip + first]


def fit_exponent(n: np.ndarray, cost: np.ndarray) -> float:
    """Slope of log(cost) against log(n) over n >= 100 (nan with fewer than 2 points)."""
    keep = (n >= 100) & np.isfinite(cost) & (cost > 0)
    if keep.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(n[keep]), np.log(cost[keep]), 1)[0])


def size_fit(sizes: np.ndarray, largest: int = 10) -> tuple[float, float]:
    """(b, a) of counts = a size^-b fitted (least squares in log-log) to the counts of sizes
    1 .. `largest` that occur (nan, nan with fewer than 3 such sizes): a description of the
    small events, not a claim of a power law."""
    counts = np.bincount(sizes, minlength=largest + 1)[1:largest + 1]
    s = np.arange(1, largest + 1)
    keep = counts > 0
    if keep.sum() < 3:
        return math.nan, math.nan
    slope, log_a = np.polyfit(np.log(s[keep]), np.log(counts[keep]), 1)
    return float(-slope), float(math.exp(log_a))


def run(outdir: str | Path, *, full: bool = False, quiet: bool = False) -> list[Path]:
    """Run the study and write its CSV files and figures (named chain_full* with `full`, so
    that both versions can sit in one directory)."""
    outdir = Path(outdir)
    plan, stem = (FULL, "chain_full") if full else (QUICK, "chain")
    csv_path = c.write_csv(outdir / f"{stem}.csv", HEADER, scaling(plan, quiet))
    c.log(f"cases.chain: slip events, N = {EVENT_BLOCKS}, {plan.events_t_end:g} s", quiet)
    sizes, starts = event_sizes(plan.events_t_end)
    ev_path = c.write_csv(outdir / f"{stem}_events.csv", ["event [-]", "size [blocks]", "start [s]"],
                          [[k, s, t] for k, (s, t) in enumerate(zip(sizes, starts))])
    return [csv_path, ev_path, *derived(csv_path, ev_path, outdir)]


def derived(csv_path: Path, ev_path: Path, outdir: Path) -> list[Path]:
    """What the CSV files give: <stem>_exponents.md, <stem>_events.md and the figures."""
    return [c.write_text(outdir / f"{csv_path.stem}_exponents.md", exponents_summary(csv_path)),
            c.write_text(outdir / f"{ev_path.stem}.md", events_summary(ev_path)),
            *plot(csv_path, ev_path, outdir)]


def exponents_summary(csv_path: Path) -> str:
    """A Markdown table of each method's fitted exponents (fit_exponent) and its largest N,
    from the scaling CSV alone."""
    cols = c.read_csv(csv_path)
    method = np.array(cols["method [-]"])
    n = np.array(cols["n_blocks [-]"], dtype=float)
    rows = []
    for m in METHODS:
        sel = method == m
        if sel.any():
            fits = [fit_exponent(n[sel], np.array(cols[k], dtype=float)[sel])
                    for k in ("cpu_per_simulated_second [-]", "cpu_per_step [s]")]
            rows.append([m, int(n[sel].max()), *(round(f, 2) if math.isfinite(f) else "" for f in fits)])
    return c.markdown_table(["method", "largest N", "exponent at the target", "exponent per step"], rows)


#: Size classes of the event summary [blocks], (smallest, largest).
SIZE_CLASSES = ((1, 1), (2, 3), (4, 10), (11, EVENT_BLOCKS - 1), (EVENT_BLOCKS, EVENT_BLOCKS))


def events_summary(ev_path: Path) -> str:
    """A Markdown table of the events by size class and the fit to the small ones, from the
    events CSV alone."""
    sizes = np.array(c.read_csv(ev_path)["size [blocks]"], dtype=int)
    rows = [[f"{lo}" if lo == hi else f"{lo}-{hi}", int(((sizes >= lo) & (sizes <= hi)).sum())]
            for lo, hi in SIZE_CLASSES]
    rows.append(["all", int(sizes.size)])
    b, a = size_fit(sizes)
    return (c.markdown_table(["event size [blocks]", "events"], rows) + "\n"
            + f"Sizes 1-10: counts = {a:.3g} size^-{b:.3g} (least squares in log-log).\n")


#: The rows of the scaling figure: groups of methods, at most five lines a panel.
PLOT_GROUPS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("explicit, set-valued", ("rk4", "dopri5", "dop853", "moreau", "event_driven")),
    ("implicit", ("radau5", "implicit_euler", "galpha")))


def plot(csv_path: Path, ev_path: Path, outdir: Path) -> list[Path]:
    """The scaling figure and the event-size figure, from the CSV files alone (named after
    them: <stem>.png and <stem>_events.png)."""
    cols = c.read_csv(csv_path)
    method = np.array(cols["method [-]"])
    n = np.array(cols["n_blocks [-]"], dtype=float)
    per_second = np.array(cols["cpu_per_simulated_second [-]"], dtype=float)
    per_step = np.array(cols["cpu_per_step [s]"], dtype=float)
    error = np.array(cols["error [m]"], dtype=float)
    target = float(cols["target [m]"][0]) if len(cols["target [m]"]) else math.nan
    # a row per group of methods (at most five lines a panel); the fitted exponents are the
    # table's (chain_exponents.md), not the legend's
    fig, axes = c.new_figure(2, nrows=len(PLOT_GROUPS), height=8.0, sharex=True)
    for row, (group, members) in enumerate(PLOT_GROUPS):
        ax_t, ax_s = axes[row]
        for m in members:
            sel = method == m
            if not sel.any():
                continue
            color, marker = style.METHOD_COLORS.get(m, "black"), MARKERS[m]
            kw = dict(color=color, marker=marker, markeredgecolor="black", markeredgewidth=0.4)
            ax_t.loglog(n[sel], per_second[sel], label=style.name(m).split(" (")[0], **kw)
            hollow = sel & ~np.isfinite(error)
            if hollow.any():
                ax_t.loglog(n[hollow], per_second[hollow], linestyle="none", marker=marker, markersize=9,
                            markerfacecolor="white", markeredgecolor=color)
            missed = sel & np.isfinite(error) & (error > target)
            if missed.any():
                ax_t.loglog(n[missed], per_second[missed], linestyle="none", marker="o", markersize=14,
                            markerfacecolor="none", markeredgecolor=style.OKABE_ITO["vermillion"],
                            markeredgewidth=1.5, label="target not met")
            ax_s.loglog(n[sel], per_step[sel] * 1e6, **kw)
        ax_t.set_ylabel("CPU s / simulated s")
        ax_s.set_ylabel("CPU per step [µs]")
        ax_t.set_title(group)
        ax_s.set_title("per step")
        if row == len(PLOT_GROUPS) - 1:
            ax_t.set_xlabel("number of blocks N [-]")
            ax_s.set_xlabel("number of blocks N [-]")
    # how to read it (exponents fitted over N >= 100, hollow markers) is the page's text:
    # docs/guide/chain.md
    fig.suptitle(f"Runs at position error <= {target:g} m")
    c.figure_legend(fig, axes[:, 0], ncol=2)
    out = [c.save_figure(fig, outdir / f"{csv_path.stem}.png")]

    sizes = np.array(c.read_csv(ev_path)["size [blocks]"], dtype=int)
    fig, ax = c.new_figure()
    if sizes.size:
        # integer bins [lo, hi): one size each up to 10, then logarithmic; a bin is drawn at the
        # geometric mean of its smallest and largest size
        edges = np.unique(np.round(np.logspace(0, math.log10(max(sizes.max(), 2)) + 0.01, 20)))
        counts, edges = np.histogram(sizes, bins=np.append(edges, edges[-1] + 1))
        centres = np.sqrt(edges[:-1] * (edges[1:] - 1))
        keep = counts > 0
        ax.loglog(centres[keep], counts[keep] / np.diff(edges)[keep], marker="o", linestyle="none",
                  color=style.METHOD_COLORS["moreau"], label="events per unit size")
        b, a = size_fit(sizes)
        if math.isfinite(b):
            s = np.arange(1, 11)
            ax.loglog(s, a * s ** -b, color=style.OKABE_ITO["vermillion"], linestyle="--",
                      label=f"{a:.0f} size^-{b:.2f}, fitted to sizes 1-10")
        whole = int((sizes >= EVENT_BLOCKS).sum())
        ax.set_title(f"{EVENT_BLOCKS} blocks: {sizes.size} events, {whole} whole")
        c.figure_legend(fig, [ax], ncol=1)
    ax.set_xlabel("event size: blocks slipping together [-]")
    ax.set_ylabel("events per unit size [-]")
    out.append(c.save_figure(fig, outdir / f"{ev_path.stem}.png"))
    return out


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.chain [--outdir DIR] [--full] [--threads N] [--quiet]."""
    parser = argparse.ArgumentParser(prog="python -m cases.chain", description=__doc__.split("\n\n")[0])
    c.add_outdir(parser, help="directory for CSV and figure files (default: out/)")
    parser.add_argument("--full", action="store_true",
                        help="t_end = 1 s, N up to 10,000, target 1e-4 m, 5,000 s of slip events "
                             "(default: 0.5 s, N up to 1,000, 1e-3 m, 1,000 s)")
    parser.add_argument("--threads", type=c.count, default=1,
                        help="accepted for python -m cases; the runs are serial (default 1)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    parser.add_argument("--replot", action="store_true",
                        help="only redraw the figures and Markdown tables from the CSV files in --outdir "
                             "(chain_full* with --full)")
    args = parser.parse_args(argv)
    if args.replot:
        stem = "chain_full" if args.full else "chain"
        files = derived(args.outdir / f"{stem}.csv", args.outdir / f"{stem}_events.csv", args.outdir)
    else:
        files = run(args.outdir, full=args.full, quiet=args.quiet)
    return c.finish("cases.chain", argv, files)


if __name__ == "__main__":
    main()
