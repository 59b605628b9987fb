"""Shared helpers of the figure drivers: atomic file writing, the CSV contract (a header row
with units), common plot styling (Agg backend), argparse options and a parallel, de-duplicating
simulation runner with progress on stderr.

Every file a driver produces goes through `atomic_write`: it is written to a temporary file in
the target directory and moved into place with `os.replace`, so a file is there whole or not at
all (an interrupted run never leaves half a CSV or PNG behind).
"""
from __future__ import annotations

import argparse
import contextlib
import inspect
import math
import multiprocessing
import os
import queue
import sys
import textwrap
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator, Mapping, Sequence

import numpy as np
import stickslip.core

from harness import style as _style
from harness.cli import add_outdir, check_writable, cli_description, float_in, int_at_least
# the drivers write and read their files as c.write_csv, c.read_csv, ... (harness.files)
from harness.files import (FLOAT_FORMAT, atomic_write, markdown_table, read_csv, read_numeric_csv,  # noqa: F401
                           split_unit, write_columns, write_csv, write_text)
from harness.provenance import write_provenance
from harness.style import plt  # the Agg backend and the common style, set once

#: The three friction laws of the paper (Figs. 1-19 and Tables 2-3 are about these; the
#: library's full list is stickslip.LAWS).
PAPER_LAWS: tuple[str, ...] = ("coulomb", "recurdyn", "proposed")
#: Display names and colours of every friction law, shared by every plot (harness.style).
LAW_LABELS: dict[str, str] = _style.LAW_NAMES
LAW_COLORS: dict[str, str] = _style.LAW_COLORS
#: Colours and line styles for the variants (step sizes or tolerances) of one law.
VARIANT_COLORS: tuple[str, ...] = _style.VARIANT_COLORS
VARIANT_STYLES: tuple[str, ...] = _style.VARIANT_STYLES
#: Size [in] of a one-panel figure and resolution [dpi] of every PNG (a PDF copy beside it).
FIGSIZE: tuple[float, float] = _style.FIGSIZE
DPI: int = _style.DPI


# --------------------------------------------------------------------------------------------
# Plot styling
# --------------------------------------------------------------------------------------------
#: Width of a figure's first panel and of each further one [in]: one panel is a column wide
#: (harness.style.COLUMN_WIDTH), so its fonts are at their size there.
PANEL_WIDTHS: tuple[float, float] = (3.4, 2.7)


def figure_width(ncols: int) -> float:
    """The width [in] of a figure of `ncols` panels side by side (PANEL_WIDTHS)."""
    return PANEL_WIDTHS[0] + PANEL_WIDTHS[1] * (ncols - 1)


def new_figure(ncols: int = 1, *, nrows: int = 1, width: float | None = None,
               height: float | None = None, **kwargs: Any) -> tuple[Any, Any]:
    """A figure in the common style (harness.style) with `ncols` axes side by side (in `nrows`
    rows: then a 2-D array of axes), `width` inches wide (default figure_width(ncols)) and
    `height` high (default 0.62 of the width, at least 3 in), its fonts legible once scaled to a
    column (harness.style.column_fonts); `kwargs` go to plt.subplots (sharex, ...)."""
    w = width if width is not None else figure_width(ncols)
    _style.apply(w)
    h = height if height is not None else max(3.0, 0.62 * w)
    fig, axes = plt.subplots(nrows, ncols, figsize=(w, h), squeeze=False, **kwargs)
    if nrows > 1:
        return fig, axes
    return fig, axes[0] if ncols > 1 else axes[0][0]


def figure_legend(fig: Any, axes: Iterable[Any], ncol: int = 3, caption: str | None = None,
                  width: int = 150) -> Any:
    """One legend for the whole figure, below the axes (where it covers no data), with every
    distinct label of `axes` once: a marker shown in any panel is explained; in at most `ncol`
    columns, fewer when they would not fit the figure's width. `caption` (what the
    figure shows, how to read it) is set above the entries, wrapped at `width` characters."""
    handles: dict[str, Any] = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    title = textwrap.fill(caption, width=width) if caption else None
    n = min(ncol, max(len(handles), 1))
    while True:              # the most columns up to `ncol` with which it fits the figure's width
        legend = fig.legend(list(handles.values()), list(handles), loc="lower center", ncol=n,
                            frameon=False, title=title, alignment="left" if caption else "center")
        if n == 1 or legend.get_window_extent(fig.canvas.get_renderer()).width <= fig.bbox.width:
            return legend
        legend.remove()
        n -= 1


def log_ticks(ax: Any, axis: str = "y", labels: int = 3) -> None:
    """Label a log axis of `ax` with at least `labels` ticks inside its limits (the figure
    checklist: at least three tick labels on a log axis), as few as that takes so that they do
    not overlap: every k-th decade; where the limits hold fewer decades, the limits widened to
    the decades around them (less than a decade beyond the data) and, if that is not enough,
    1, 2 and 5 of each decade. Call it once the limits are final."""
    from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter
    lo, hi = sorted(ax.get_ylim() if axis == "y" else ax.get_xlim())
    first, last = math.ceil(math.log10(lo) - 1e-9), math.floor(math.log10(hi) + 1e-9)
    if last - first < labels - 1:         # widen to the decades around the limits
        first, last = math.floor(math.log10(lo) + 1e-9), math.ceil(math.log10(hi) - 1e-9)
        lo, hi = 10.0 ** first, 10.0 ** last
        (ax.set_ylim if axis == "y" else ax.set_xlim)(lo, hi)
    decades = last - first
    if decades >= labels - 1:
        step = max(1, decades // (labels - 1))
        ticks = [10.0 ** e for e in range(first, last + 1, step)]
    else:
        ticks = [m * 10.0 ** e for e in range(first, last + 1) for m in (1, 2, 5)
                 if lo <= m * 10.0 ** e <= hi]

    def text(value: float, _: Any) -> str:
        e = math.floor(math.log10(value) + 1e-9)
        m = round(value / 10.0 ** e)
        return f"$10^{{{e}}}$" if m == 1 else f"${m}\\times10^{{{e}}}$"

    target = ax.yaxis if axis == "y" else ax.xaxis
    target.set_major_locator(FixedLocator(ticks))
    target.set_major_formatter(FuncFormatter(text))
    target.set_minor_formatter(NullFormatter())


def save_figure(fig: Any, path: str | os.PathLike[str]) -> Path:
    """Save `fig` as PNG (DPI dots per inch) and as a PDF beside it, each atomically, and close
    it; returns the PNG's path. A figure legend (figure_legend) keeps a strip of its own height
    below the axes."""
    bottom = 0.0
    if fig.legends:
        fig.canvas.draw()
        bottom = max(leg.get_window_extent().transformed(fig.transFigure.inverted()).y1
                     for leg in fig.legends)
    fig.tight_layout(rect=(0.0, bottom, 1.0, 1.0))
    return _style.save(fig, path, atomic_write)


def series_label(name: str) -> str:
    """The legend entry of a figure CSV's column, with units: "x coulomb [m]" -> "Coulomb",
    "x h=0.001 [m]" -> "RK4, h = 0.001 s", "x rtol=0.01 [m]" -> "DOPRI5, rtol = 0.01",
    "x automatic [m]" -> "DOPRI5 automatic (h in [1e-6, 1e-2] s)"."""
    key = split_unit(name)[0].split(" ", 1)[-1]
    if key in LAW_LABELS:
        return LAW_LABELS[key]
    if key.startswith("h="):
        return f"RK4, h = {key[2:]} s"
    if key.startswith("rtol="):
        return f"DOPRI5, rtol = {key[5:]}, atol = 1e-3 rtol"
    if key == "automatic":
        return "DOPRI5 automatic (h in [1e-6, 1e-2] s)"
    return key


def series_style(label: str, index: int) -> dict[str, Any]:
    """Line colour and style of a series: the law's colour when `label` names a law,
    else the index-th variant style."""
    for law, color in LAW_COLORS.items():
        if label.endswith(law):
            return {"color": color, "linestyle": VARIANT_STYLES[index % len(VARIANT_STYLES)]}
    return {"color": VARIANT_COLORS[index % len(VARIANT_COLORS)],
            "linestyle": VARIANT_STYLES[index % len(VARIANT_STYLES)]}


def plot_time_series(csv_path: str | os.PathLike[str], png_path: str | os.PathLike[str],
                     title: str) -> Path:
    """Render a CSV whose first column is time [s] and whose other columns are series of one
    quantity (e.g. "x coulomb [m]") as lines against time, with panels beside it when the
    lines alone would hide something:

    - when series lie on another one (within 2% of the largest range), their difference from
      it (the first series that has such company), so that a reader sees how close they are;
      when they are identical (difference exactly 0) the title says so instead of an empty
      panel;
    - when their final values span more than two decades, |x| on a log axis, so that every
      series is visible (without the distortion of a symmetric-log axis).

    The legend sits below the panels, where it covers no data."""
    cols = read_numeric_csv(csv_path)
    names = list(cols)
    t = cols[names[0]]
    series = names[1:]
    finals = [abs(cols[name][-1]) for name in series]
    positive = [f for f in finals if f > 0.0]
    wide = len(positive) > 1 and max(positive) / min(positive) > 100.0
    ys = np.array([cols[name] for name in series])
    scale = float(max(np.ptp(ys, axis=1).max(), np.abs(ys).max(), np.finfo(float).tiny))
    ref, close = 0, []
    for ref in range(len(series)):
        close = [k for k in range(ref + 1, len(series))
                 if np.abs(ys[k] - ys[ref]).max() < 0.02 * scale]
        if close:
            break
    # series identical to the reference (difference exactly 0) get a note, not an empty panel
    identical = [k for k in close if np.abs(ys[k] - ys[ref]).max() == 0.0]
    same_as = ""
    if close and len(identical) == len(close):
        same_as = ", ".join(series_label(series[k]).split(" (")[0] for k in close)
        close = []
    panels = 1 + wide + bool(close)
    # the panels one above the other, a column wide
    fig, axes = new_figure(1, nrows=panels, height=1.7 + 2.4 * panels, sharex=True)
    axes = list(axes[:, 0]) if panels > 1 else [axes]
    base, unit = split_unit(series[0])
    quantity = base.split()[0]
    first = series_label(series[ref]).split(" (")[0].split(", atol")[0]
    log_ax = axes[1] if wide else None
    diff_ax = axes[-1] if close else None
    for i, name in enumerate(series):
        key = split_unit(name)[0].split(" ", 1)[-1]
        style = series_style(key, i)
        axes[0].plot(t, cols[name], label=series_label(name), **style)
        if log_ax is not None:
            y = np.abs(cols[name])
            log_ax.semilogy(t[y > 0.0], y[y > 0.0], **style)
        if diff_ax is not None and i in close:
            diff_ax.plot(t, cols[name] - cols[series[ref]], **style)
    axes[0].set_ylabel(f"{quantity} [{unit}]")
    if log_ax is not None:
        axes[0].set_title(f"{quantity} on a linear axis")
        log_ax.set_ylabel(f"|{quantity}| [{unit}]")
        log_ax.set_title("the same on a log axis")
    if diff_ax is not None:
        spread = max(float(np.abs(ys[k] - ys[ref]).max()) for k in close)
        if log_ax is None:
            axes[0].set_title(f"{quantity}: curves that lie on each other")
        diff_ax.set_ylabel(f"difference in {quantity} [{unit}]")
        diff_ax.set_title(f"minus {first}: within {spread:.2g} {unit}" if spread > 0 else
                          f"minus {first}: identical (difference exactly 0)", pad=14)
        diff_ax.axhline(0.0, color="k", linewidth=0.6)
    if same_as:
        note = f"{same_as} identical to {first}"
        axes[0].set_title(f"{quantity}: {note}" if log_ax is None else f"{quantity} on a linear axis; {note}")
    if panels > 1 or same_as:
        fig.suptitle(title)
    else:
        axes[0].set_title(title)
    axes[-1].set_xlabel("time t [s]" if names[0] == "t [s]" else names[0])
    figure_legend(fig, axes)
    return save_figure(fig, png_path)


# --------------------------------------------------------------------------------------------
# Command line
# --------------------------------------------------------------------------------------------
#: Smallest relative tolerance the library accepts: 100 units of round-off (2.2e-14).
RTOL_MIN: float = stickslip.core.RTOL_MIN


#: argparse types: a finite float > 0; a relative tolerance in [100 eps, 1); a number of output
#: points (>= 2); a count of workers or threads (>= 1).
positive_float = float_in(0.0)
rtol_value = float_in(RTOL_MIN, 1.0, low_closed=True, what="100 eps = 2.2e-14")
positive_int = int_at_least(2)
count = int_at_least(1)


def add_common_options(parser: argparse.ArgumentParser) -> None:
    """--outdir, --workers and --quiet, shared by every driver."""
    add_outdir(parser)
    parser.add_argument("--workers", type=count, default=2,
                        help="simulations run in parallel, >= 1 (default 2: the machine has 2 "
                        "cores)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")


def changed_options(parser: argparse.ArgumentParser, args: argparse.Namespace,
                    ignore: Iterable[str] = ("outdir", "workers", "threads", "jobs", "quiet",
                                             "max_steps", "scheduler")) -> dict[str, Any]:
    """The options given a value other than their default, except those in `ignore` (where
    the files go and how the work is spread, which do not change a result)."""
    def same(a: Any, b: Any) -> bool:
        if isinstance(a, (list, tuple)) or isinstance(b, (list, tuple)):
            return list(a or []) == list(b or [])
        return a == b

    return {a.dest: getattr(args, a.dest) for a in parser._actions
            if a.dest not in ("help", *ignore) and a.default is not argparse.SUPPRESS
            and not same(getattr(args, a.dest), a.default)}


def parameter_outdir(outdir: Path, changed: Mapping[str, Any]) -> tuple[Path, str]:
    """Where a run with the non-default options `changed` writes, and the note its figure
    titles carry: `outdir` itself and "" for the paper's parameters; else a subdirectory
    named after them (e.g. out/theta_deg=90/, "theta_deg = 90"), so that such a run never
    overwrites the paper's figures and its files say what made them."""
    if not changed:
        return outdir, ""

    def text(v: Any) -> str:
        if isinstance(v, bool):
            return "yes" if v else "no"
        if isinstance(v, (list, tuple)):
            return "+".join(text(x) for x in v)
        return f"{v:g}" if isinstance(v, float) else str(v)

    parts = [(k, text(v)) for k, v in sorted(changed.items())]
    name = "_".join(k if v == "yes" else f"{k}={v}" for k, v in parts).replace("/", "-")
    return outdir / name, ", ".join(k if v == "yes" else f"{k} = {v}" for k, v in parts)


def study_main(module: str, doc: str, quick_help: str, run: Callable[..., list[Path]],
               argv: Sequence[str] | None) -> list[Path]:
    """The command line of a study driver (workprecision, stability): --outdir, --quick,
    --threads (OpenMP threads of simulate_batch) and --quiet, then run(outdir, quick=,
    threads=, quiet=)."""
    parser = argparse.ArgumentParser(prog=f"python -m {module}", description=cli_description(doc),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_outdir(parser, help="directory for CSV and PNG files (default: out/)")
    parser.add_argument("--quick", action="store_true", help=quick_help)
    parser.add_argument("--threads", type=count, default=2, help="OpenMP threads, >= 1 (default 2)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    sweeps = "scheduler" in inspect.signature(run).parameters   # the drivers built on sweeps
    if sweeps:
        parser.add_argument("--scheduler", metavar="ADDRESS", default=None,
                            help="run the sweeps on the Dask cluster at ADDRESS, e.g. "
                                 "tcp://127.0.0.1:8786 (default: locally)")
    args = parser.parse_args(argv)
    outdir, _ = parameter_outdir(args.outdir, changed_options(parser, args))
    check_writable(parser, outdir)
    where = {"scheduler": args.scheduler} if sweeps else {}
    files = run(outdir, quick=args.quick, threads=args.threads, quiet=args.quiet, **where)
    return finish(module, argv, files)


def print_files(files: Iterable[Path]) -> None:
    """Print where every file went (stdout, one path a line, sorted)."""
    for f in sorted(files):
        print(f)


def finish(module: str, argv: Sequence[str] | None, files: list[Path]) -> list[Path]:
    """The end of every driver: record the command, date and machine beside the files
    (`<dir>/<module>.provenance.json` in each directory written, harness.provenance), print
    where every file went, and return the files with their sidecars."""
    files = list(files)
    files += [f.with_suffix(".pdf") for f in files        # the vector copy of every figure
              if f.suffix == ".png" and f.with_suffix(".pdf").exists() and f.with_suffix(".pdf") not in files]
    dirs = sorted({Path(f).parent for f in files})
    files = list(files) + [write_provenance(d, module, files, argv) for d in dirs]
    print_files(files)
    return files


def add_law_options(parser: argparse.ArgumentParser) -> None:
    """The friction-law parameters (Table 1 defaults come from stickslip.DEFAULTS)."""
    from stickslip import DEFAULTS
    g = parser.add_argument_group("friction-law parameters (paper's Table 1)")
    g.add_argument("--mu-s", type=positive_float, default=DEFAULTS["mu_s"],
                   help="static coefficient [-] (default %(default)s)")
    g.add_argument("--mu-k", type=positive_float, default=DEFAULTS["mu_k"],
                   help="kinetic coefficient [-] (default %(default)s)")
    g.add_argument("--v-s", type=positive_float, default=DEFAULTS["v_s"],
                   help="static threshold velocity [m/s] (default %(default)s)")
    g.add_argument("--v-d", type=positive_float, default=None,
                   help="dynamic threshold velocity of the RecurDyn law [m/s] (default 1.5 v_s)")
    g.add_argument("--beta", type=positive_float, default=DEFAULTS["beta"],
                   help="exponent of the proposed law [-] (default 1/3)")
    g.add_argument("--a", type=positive_float, default=DEFAULTS["a"],
                   help="base of the proposed law [-] (> 1, default %(default)s)")


def law_params(args: argparse.Namespace) -> dict[str, float]:
    """The law parameters from parsed options, for stickslip.simulate/friction_coefficient."""
    p = {"mu_s": args.mu_s, "mu_k": args.mu_k, "v_s": args.v_s, "beta": args.beta, "a": args.a}
    if args.v_d is not None:
        p["v_d"] = args.v_d
    return p


def checked_law_params(parser: argparse.ArgumentParser,
                       args: argparse.Namespace) -> dict[str, float]:
    """law_params(args), validated by the library (each law evaluated once): a bad value ends
    the command with the library's message naming the parameter and its accepted range."""
    import stickslip
    params = law_params(args)
    try:
        for law in stickslip.LAWS:
            stickslip.friction_coefficient(law, 0.0, **params)
    except ValueError as exc:
        parser.error(str(exc))
    return params



@contextlib.contextmanager
def steps_beyond_stability() -> Iterator[None]:
    """Silence stickslip's UnstableStepWarning inside: for the studies that choose fixed steps
    beyond RK4's stability bound on purpose (a stability map, a step sweep), where the warning
    says nothing the study does not measure and report."""
    import stickslip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", stickslip.core.UnstableStepWarning)
        yield


def log(message: str, quiet: bool = False) -> None:
    """A progress line on stderr."""
    if not quiet:
        print(message, file=sys.stderr, flush=True)


def log_caption(text: str, quiet: bool = False) -> None:
    """The caption of a console table (units, what each column means), wrapped, on stderr."""
    log("\n".join(textwrap.fill(part, width=96) for part in text.split("\n")), quiet)


# --------------------------------------------------------------------------------------------
# Simulations: specification, de-duplication, parallel execution
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Run:
    """One simulation, hashable so that equal runs are simulated once.

    A fixed-step method (one whose controls include h, e.g. "rk4") uses h [s]; an adaptive one
    ("dopri5") uses rtol [-], atol [m or m/s], hmin, hmax [s]."""

    scene: str
    law: str
    method: str
    t_end: float
    n_out: int
    h: float | None = None
    rtol: float | None = None
    atol: float | None = None
    hmin: float = 1e-6
    hmax: float = 1e-2
    params: tuple[tuple[str, float], ...] = ()
    max_steps: int | None = None          # None: the library's default budget

    @property
    def fixed_step(self) -> bool:
        """The method steps with a fixed h (the registry lists h among its controls)."""
        from stickslip import REGISTRY
        return "h" in REGISTRY["method"][self.method]["controls"]

    def kwargs(self) -> dict[str, Any]:
        """Keyword arguments of stickslip.simulate."""
        # one parameter set serves every law of a figure: what a law does not read is ignored
        kw: dict[str, Any] = dict(method=self.method, t_end=self.t_end, n_out=self.n_out,
                                  ignore_unused=True, **dict(self.params))
        if self.fixed_step:
            kw["h"] = self.h
        else:
            kw.update(rtol=self.rtol, atol=self.atol, hmin=self.hmin, hmax=self.hmax)
        if self.max_steps is not None:
            kw["max_steps"] = self.max_steps
        return kw

    def label(self) -> str:
        """Short description for progress lines and tables."""
        how = f"h={self.h:g}" if self.fixed_step else f"rtol={self.rtol:g}"
        return f"{self.scene} {self.law} {self.method} {how}"

    def cost_hint(self) -> float:
        """A rough a-priori cost (larger first): Coulomb with an adaptive step is the one that
        can fall to h_min; fixed steps cost t_end/h."""
        if self.fixed_step:
            return self.t_end / float(self.h)
        return self.t_end / self.hmin if self.law == "coulomb" else self.t_end / self.hmax


@dataclass
class Outcome:
    """What a worker sends back: the output grid and the library's counters."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    stats: dict[str, Any] = field(default_factory=dict)
    wall_seconds: float = 0.0


class SimulationFailed(RuntimeError):
    """A run ended before t_end; the message names the run and the library's reason
    (without the partial Result, which the parent process has no use for)."""


def simulate_run(run: Run) -> Outcome:
    """Run one simulation (in a worker process); raises SimulationFailed if it ends early."""
    import stickslip
    t0 = time.perf_counter()
    try:
        r = stickslip.simulate(run.scene, run.law, **run.kwargs())
    except stickslip.IntegrationError as exc:
        raise SimulationFailed(f"{run.label()}, t_end = {run.t_end:g} s: {exc}") from None
    return Outcome(r.t, r.x, r.v, dict(r.stats), time.perf_counter() - t0)


def run_all(runs: Iterable[Run], *, workers: int = 2, quiet: bool = False,
            heartbeat: float = 3.0) -> dict[Run, Outcome]:
    """Simulate every distinct run once, `workers` at a time, the expensive ones first.
    Shows a progress bar on stderr (tqdm when installed; else one line per finished run and,
    every `heartbeat` seconds while runs are pending, a line with the elapsed time).

    The first failure ends everything at once: queued runs are dropped and running workers
    terminated (multiprocessing.Pool.terminate), then SimulationFailed is raised; so a hopeless
    command fails as soon as its first run does, not after every other run has finished."""
    from ._progress import bar
    unique = sorted(set(runs), key=lambda r: -r.cost_hint())
    results: dict[Run, Outcome] = {}
    start = time.perf_counter()
    with bar(len(unique), "  runs", quiet) as shown:
        if workers <= 1 or len(unique) <= 1:
            for run in unique:
                results[run] = simulate_run(run)
                shown.update(note=f"{run.label()}: {results[run].wall_seconds:.2f} s")
            return results
        return _run_pool(unique, results, workers, quiet, heartbeat, start, shown)


def _run_pool(unique: list[Run], results: dict[Run, Outcome], workers: int, quiet: bool,
              heartbeat: float, start: float, shown: Any) -> dict[Run, Outcome]:
    """run_all's parallel branch: a process pool, the first failure ends it."""
    ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods()
                                      else None)
    finished: queue.SimpleQueue[tuple[Run, Outcome | BaseException]] = queue.SimpleQueue()
    # Pool.__exit__ calls terminate(): on an error (or Ctrl-C) no worker outlives this block.
    with ctx.Pool(processes=min(workers, len(unique))) as pool:
        for run in unique:
            pool.apply_async(simulate_run, (run,),
                             callback=lambda o, run=run: finished.put((run, o)),
                             error_callback=lambda e, run=run: finished.put((run, e)))
        while len(results) < len(unique):
            try:
                run, outcome = finished.get(timeout=heartbeat)
            except queue.Empty:
                if shown._bar is None:     # tqdm shows the elapsed time itself
                    log(f"  ... {len(results)}/{len(unique)} done, "
                        f"{time.perf_counter() - start:.0f} s elapsed", quiet)
                continue
            if isinstance(outcome, BaseException):
                raise outcome
            results[run] = outcome
            shown.update(note=f"{run.label()}: {outcome.wall_seconds:.2f} s")
    return results
