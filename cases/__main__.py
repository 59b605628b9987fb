"""Regenerate every figure and table:

    python -m cases [--outdir out/] [--only slope belt ...]   # the paper: Figs. 1-19, Tables 2-3
    python -m cases --all                                     # and the work-precision and stability studies
    python -m cases --docs        # the committed copies in docs/figures/ (the documentation's figures)

Runs the drivers of DRIVERS, --jobs at a time (default: one per core, at most 2), each in its
own process, the costliest first, then the timings of parallel speed alone; prints where every
file went and the total wall time. Each driver's report (stdout) is printed whole when it
finishes. The paper's drivers parallelise their simulations over --workers processes, the
studies over --threads OpenMP threads; both default to the cores left per job (1 on 2 cores
with 2 jobs; every core for a driver that runs alone). With --jobs 1 the drivers run in turn
in this process and show their progress bars.

To add a driver, append a Driver(module name, kind, cost, alone) to DRIVERS: the module needs
`main(argv)` accepting `--outdir`, plus `--workers` and `--quiet` for kind "paper" or
`--threads` and `--quiet` for kind "study"; cost (CPU seconds of a full run) only orders the
jobs.
"""
from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import multiprocessing
import os
import queue
import sys
import time
import traceback
from pathlib import Path
from typing import Any, NamedTuple, Sequence

# numpy's OpenBLAS keeps worker threads spinning after each (tiny) BLAS call of the drivers,
# on the core the other job needs: one BLAS thread, set before numpy is first imported.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from harness.cli import add_outdir, check_writable, cli_description  # noqa: E402 - after the environment above
from ._common import count  # noqa: E402
from ._progress import bar  # noqa: E402

class Driver(NamedTuple):
    """A driver module run by `python -m cases`."""

    name: str       #: module cases.<name>
    kind: str       #: "laws" (no simulation), "paper" (a figure set of the paper,
                    #: --workers/--quiet) or "study" (--all only, --threads/--quiet)
    cost: float     #: CPU seconds of one full run on one core (measured 2026-11-23): only
                    #: starts the costliest jobs first
    alone: bool     #: a timing of parallel speed: runs after the others, every core its own


DRIVERS: tuple[Driver, ...] = (
    Driver("laws", "laws", 0.7, False), Driver("slope", "paper", 5.5, False),
    Driver("belt", "paper", 1.6, False), Driver("workprecision", "study", 25.0, False),
    Driver("stability", "study", 37.6, False), Driver("laws_compare", "study", 18.0, False),
    Driver("implicit", "study", 15.1, False), Driver("speedup", "study", 1.1, True),
    Driver("stick", "study", 12.0, False), Driver("identify", "study", 35.0, False),
    Driver("chain", "study", 31.0, False), Driver("advise_examples", "study", 60.0, False),
    Driver("engines", "study", 64.0, False), Driver("gallery_clutches", "study", 13.0, False),
    Driver("gallery_belt2dof", "study", 6.0, False), Driver("gallery_stacked", "study", 12.0, False),
    Driver("gallery_denhartog", "study", 28.0, False), Driver("gallery_frame", "study", 9.0, False),
    Driver("model_pairs", "study", 13.0, False), Driver("gallery_steady", "study", 10.0, False))
DOCS_DIR: Path = Path(__file__).resolve().parent.parent / "docs" / "figures"


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:          # not on Linux
        return os.cpu_count() or 1


def cpu_seconds() -> float:
    """CPU time of this process (every thread) and of its children that ended [s]: a driver's
    worker processes count."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def write_run_times(outdir: Path, name: str, times: dict[str, tuple[float, float]], wall: float,
                    n_jobs: int, argv: Sequence[str] | None) -> list[Path]:
    """Write each driver's wall and CPU time, the run's wall time and the sum of the CPU times
    into `<outdir>/<name>.json` (a named-numbers file, tools/docnumbers.py, which the
    documentation quotes) with its provenance; nothing from a copy without tools/ beside it."""
    root = Path(__file__).resolve().parent.parent
    if not (root / "tools" / "docnumbers.py").is_file():
        return []
    if str(root) not in sys.path:
        sys.path.insert(0, str(root))
    from tools.docnumbers import numbers_json
    from ._common import write_text
    from harness.provenance import write_provenance
    numbers: dict[str, tuple[float, str, str]] = {
        "wall_s": (round(wall, 1), "s", "wall time of the run"),
        "cpu_s": (round(sum(c for _, c in times.values()), 1), "s", "sum of the drivers' CPU times"),
        "jobs": (n_jobs, "", "drivers run at once")}
    for driver, (seconds, cpu) in times.items():
        numbers[f"{driver}.wall_s"] = (round(seconds, 1), "s", f"wall time of cases.{driver}")
        numbers[f"{driver}.cpu_s"] = (round(cpu, 1), "s", f"CPU time of cases.{driver} and its workers")
    path = write_text(outdir / f"{name}.json", numbers_json(numbers))
    return [path, write_provenance(outdir, name, [path], argv)]


def _run_driver(name: str, argv: list[str]) -> list[Path]:
    return importlib.import_module(f"cases.{name}").main(argv)


def _job(index: int, name: str, argv: list[str], results: Any) -> None:
    """A job process: run one driver with its stdout captured; send (index, ok, payload)."""
    out = io.StringIO()
    t0, cpu0 = time.perf_counter(), cpu_seconds()
    try:
        with contextlib.redirect_stdout(out):
            files = _run_driver(name, argv)
        results.put((index, True, (files, out.getvalue(), time.perf_counter() - t0,
                                   cpu_seconds() - cpu0)))
    except BaseException as exc:    # noqa: BLE001 - reported to the parent, which raises it
        text = f"cases.{name} failed:\n{out.getvalue()}{traceback.format_exc()}"
        results.put((index, False, (type(exc).__name__, str(exc), text)))


class DriverFailed(RuntimeError):
    """A driver of a parallel `python -m cases` run failed; the message holds its traceback."""


def run_jobs(jobs: list[tuple[str, list[str]]], n_jobs: int, quiet: bool,
             costs: Sequence[float], times: dict[str, tuple[float, float]] | None = None) -> list[list[Path]]:
    """Run the drivers `jobs` ((name, argv)) in up to n_jobs processes, the costliest first;
    returns each one's files, in the order of `jobs`, and puts each one's (wall, CPU) seconds
    into `times`. The first failure ends the run: the other jobs are terminated and
    DriverFailed raised."""
    ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods()
                                      else None)
    results = ctx.Queue()
    running: dict[int, Any] = {}
    done: dict[int, list[Path]] = {}
    pending = sorted(range(len(jobs)), key=lambda i: -costs[i])
    shown = bar(len(jobs), "drivers", quiet, unit="driver")   # its clock ticks every second

    def say(line: str) -> None:                   # a line above the bar, not through it
        if shown._bar is not None:
            shown._bar.write(line, file=sys.stderr)
        else:
            print(line, file=sys.stderr, flush=True)
    try:
        while pending or running:
            while pending and len(running) < n_jobs:
                i = pending.pop(0)
                # not a Pool: a Pool's workers are daemons, and the paper drivers start their own
                running[i] = ctx.Process(target=_job, args=(i, *jobs[i], results), name=jobs[i][0])
                running[i].start()
                if not quiet:
                    say(f"== cases.{jobs[i][0]} started")
            try:
                i, ok, payload = results.get(timeout=1.0)
            except queue.Empty:
                if shown._bar is not None:
                    shown._bar.refresh()
                for j, proc in running.items():
                    if not proc.is_alive():
                        proc.join(0.5)      # its last message may still be in the pipe
                        if results.empty():
                            raise DriverFailed(f"cases.{jobs[j][0]} died (exit code {proc.exitcode})")
                continue
            running.pop(i).join()
            if not ok:
                kind, message, text = payload
                raise DriverFailed(f"{kind}: {message}\n{text}")
            files, report, seconds, cpu = payload
            done[i] = files
            if times is not None:
                times[jobs[i][0]] = (seconds, cpu)
            sys.stdout.write(report)
            sys.stdout.flush()
            if not quiet:
                say(f"== cases.{jobs[i][0]}: {seconds:.1f} s (CPU {cpu:.1f} s)")
            shown.update()
    finally:
        shown.close()
        for proc in running.values():
            proc.terminate()
            proc.join()
    return [done[i] for i in range(len(jobs))]


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run the drivers; returns every file written."""
    parser = argparse.ArgumentParser(prog="python -m cases", description=cli_description(__doc__),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_outdir(parser, help="directory for all files (default: out/)")
    parser.add_argument("--docs", action="store_true",
                        help="write into docs/figures/ (the figures and tables the documentation shows)")
    parser.add_argument("--only", nargs="+", choices=[d.name for d in DRIVERS],
                        help="run only these drivers")
    parser.add_argument("--all", action="store_true",
                        help="also run the studies (work-precision, stability, laws_compare, implicit, stick, "
                        "identify, chain, advise_examples, engines, the gallery's gallery_denhartog, gallery_frame and "
                        "gallery_steady)")
    parser.add_argument("--jobs", type=count, default=min(2, _cores()),
                        help="drivers run at once, each in its own process, >= 1 (default: cores, at most 2)")
    parser.add_argument("--workers", type=count, default=None,
                        help="parallel simulations per paper driver, >= 1 (default: cores / jobs)")
    parser.add_argument("--threads", type=count, default=None,
                        help="OpenMP threads per study driver, >= 1 (default: cores / jobs)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    args = parser.parse_args(argv)
    if args.docs and not DOCS_DIR.parent.is_dir():
        parser.error(f"--docs: writes into the docs/figures/ of a source checkout, and this copy of "
                     f"cases ({Path(__file__).resolve().parent}) has none beside it; use --outdir")
    outdir = DOCS_DIR if args.docs else args.outdir
    check_writable(parser, outdir)
    chosen = [d for d in DRIVERS if (d.name in args.only if args.only else (d.kind != "study" or args.all))]
    together = [d for d in chosen if not d.alone]
    n_jobs = max(1, min(args.jobs, len(together)))

    def driver_argv(kind: str, cores: int, quiet: bool) -> list[str]:
        flags = ["--quiet"] if quiet else []
        return {"laws": [], "paper": ["--workers", str(args.workers or cores), *flags],
                "study": ["--threads", str(args.threads or cores), *flags]}[kind]

    start = time.perf_counter()
    by_driver: dict[str, list[Path]] = {}
    times: dict[str, tuple[float, float]] = {}
    if n_jobs > 1:
        # in parallel, the reports are printed whole at the end of each driver: no bars
        jobs = [(d.name, ["--outdir", str(outdir), *driver_argv(d.kind, max(1, _cores() // n_jobs), True)])
                for d in together]
        found = run_jobs(jobs, n_jobs, args.quiet, [d.cost for d in together], times)
        by_driver.update(zip([d.name for d in together], found))
    for name, kind, _, _ in chosen:        # with --jobs 1 all of them, else the "alone" ones
        if name in by_driver:
            continue
        t0, cpu0 = time.perf_counter(), cpu_seconds()
        if not args.quiet:
            print(f"== cases.{name} -> {outdir}", file=sys.stderr, flush=True)
        by_driver[name] = _run_driver(name, ["--outdir", str(outdir), *driver_argv(kind, _cores(), args.quiet)])
        times[name] = (time.perf_counter() - t0, cpu_seconds() - cpu0)
        if not args.quiet:
            print(f"== cases.{name}: {times[name][0]:.1f} s (CPU {times[name][1]:.1f} s)",
                  file=sys.stderr, flush=True)
    files = [f for d in chosen for f in by_driver[d.name]]
    wall = time.perf_counter() - start
    if not args.only:       # a whole run (the paper's part, or --all): its times for the docs
        files += write_run_times(outdir, "cases.run_all" if args.all else "cases.run", times, wall,
                                 n_jobs, argv)
    print(f"{len(files)} files in {outdir}; wall time {wall:.1f} s, the drivers' CPU time "
          f"{sum(c for _, c in times.values()):.1f} s")
    return files


if __name__ == "__main__":
    try:
        main()
    except DriverFailed as exc:
        sys.exit(f"python -m cases: {exc}")
