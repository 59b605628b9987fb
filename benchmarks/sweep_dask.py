"""Rows per second of a large simulate_batch sweep, locally and on a Dask LocalCluster, and
the cost of one chunk on the cluster:

    python -m benchmarks.sweep_dask [--rows 100000] [--repeats 3] [--chunk-rows 1000 2000 50000]

The sweep: the slope with the RecurDyn law, RK4, h = 1e-3 s, t_end = 0.2 s, n_grid = 11,
v_s over [1e-3, 1e-1] m/s (one value per row). Local: one call, 1 and 2 OpenMP threads.
Cluster: LocalCluster(n_workers=2, processes=True, threads_per_worker=1) on loopback, 1 OpenMP
thread per chunk, for each chunk size (and the default). Wall time, and CPU time (this process,
which holds the scheduler, plus the workers): on a shared machine the wall time depends on the
load, the CPU time much less. Per-chunk overhead: wall time of
--overhead-chunks chunks of one 1-step row each on the same cluster, less the same rows in one
local call, divided by their number (both workers busy: the cost a chunk adds to a sweep).
Times are medians of --repeats runs, interleaved so that a change of load (the machine may be
shared) hits every configuration alike;
every cluster run is checked equal to the local one. Prints a Markdown table; also writes it to
out/benchmarks/sweep_dask.md (with --results: the tracked
benchmarks/results/sweep_dask.md).
"""
from __future__ import annotations

import argparse
import os
import time
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from harness.cli import add_outdir, check_writable, cli_description, int_at_least
from harness.files import markdown_table, write_text
from harness.provenance import machine, write_provenance

#: The tracked results the documentation quotes (written only with --results).
RESULTS_DIR = Path(__file__).resolve().parent / "results"


def sweep(rows: int) -> dict[str, Any]:
    """The benchmark's simulate_batch arguments."""
    return dict(scene="slope", law="recurdyn", method="rk4", t_end=0.2, h=1e-3, n_grid=11,
                v_s=np.geomspace(1e-3, 1e-1, rows))


def main(argv: Sequence[str] | None = None) -> str:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.sweep_dask",
                                     description=cli_description(__doc__),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rows", type=int_at_least(1), default=100_000, help="rows of the sweep, >= 1")
    parser.add_argument("--repeats", type=int_at_least(1), default=3, help="runs per timing (median), >= 1")
    parser.add_argument("--chunk-rows", type=int_at_least(1), nargs="+", default=[1000, 2000, 50_000],
                        help="chunk sizes to time on the cluster (besides the default)")
    parser.add_argument("--overhead-chunks", type=int_at_least(1), default=200,
                        help="one-row chunks timed for the per-chunk overhead")
    add_outdir(parser, default="out/benchmarks", help="where sweep_dask.md goes (default: out/benchmarks/)")
    parser.add_argument("--results", action="store_true",
                        help="write into the tracked benchmarks/results/ instead, the table the "
                             "documentation quotes")
    args = parser.parse_args(argv)
    outdir = RESULTS_DIR if args.results else args.outdir
    check_writable(parser, outdir)
    import stickslip
    from distributed import Client, LocalCluster
    from stickslip.distributed import default_chunk_rows

    kw = sweep(args.rows)
    load0 = os.getloadavg()[0]
    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        client.wait_for_workers(2)
        stickslip.simulate_batch(**sweep(10), client=client)          # workers import stickslip
        ref = stickslip.simulate_batch(**kw, threads=1)
        sizes = [default_chunk_rows(args.rows, 2)] + sorted(set(args.chunk_rows))
        runs: dict[str, Callable[[], Any]] = {
            "local, 1 thread": lambda: stickslip.simulate_batch(**kw, threads=1),
            "local, 2 OpenMP threads": lambda: stickslip.simulate_batch(**kw, threads=2)}
        for cr in sizes:
            label = f"2-worker LocalCluster, chunk_rows {cr}" + (" (default)" if cr == sizes[0] else "")
            runs[label] = lambda cr=cr: stickslip.simulate_batch(**kw, threads=1, client=client,
                                                                 chunk_rows=cr)
        tiny = dict(sweep(args.overhead_chunks), t_end=1e-3, n_grid=2)
        runs["tiny local"] = lambda: stickslip.simulate_batch(**tiny)
        runs["tiny chunks"] = lambda: stickslip.simulate_batch(**tiny, client=client, chunk_rows=1)

        def cpu() -> float:                    # this process (and the scheduler) + workers
            return time.process_time() + sum(client.run(time.process_time).values())

        times: dict[str, list[float]] = {k: [] for k in runs}
        cpus: dict[str, list[float]] = {k: [] for k in runs}
        for _ in range(args.repeats):          # interleaved: a change of load hits every run
            for label, run in runs.items():
                c0, t0 = cpu(), time.perf_counter()
                out = run()
                times[label].append(time.perf_counter() - t0)
                cpus[label].append(cpu() - c0)
                if not label.startswith("tiny"):
                    assert np.array_equal(out.x_end, ref.x_end) and np.array_equal(out.nfev, ref.nfev)
    med = {k: float(np.median(v)) for k, v in times.items()}
    table: list[list[Any]] = []
    for label in runs:
        if label.startswith("tiny"):
            continue
        cr = int(label.split("chunk_rows ")[1].split()[0]) if "chunk_rows" in label else args.rows
        c = float(np.median(cpus[label]))
        table.append([label, -(-args.rows // cr), med[label], args.rows / med[label], c, args.rows / c])
    t_loc, t_chunks = med["tiny local"], med["tiny chunks"]
    per_chunk_ms = 1e3 * (t_chunks - t_loc) / args.overhead_chunks
    cpu_ms = 1e3 * (float(np.median(cpus["tiny chunks"])) - float(np.median(cpus["tiny local"]))) \
        / args.overhead_chunks
    header = ["run", "chunks", "wall [s]", "rows/s", "CPU [s]", "rows per CPU-s"]
    text = (f"{args.rows} rows ({kw['scene']}, {kw['law']}, RK4 h = {kw['h']} s, t_end = "
            f"{kw['t_end']} s, n_grid = {kw['n_grid']}), median of {args.repeats} interleaved runs; "
            f"{machine()}, load average {load0:.2f} before and "
            f"{os.getloadavg()[0]:.2f} after\n\n"
            + markdown_table(header, table)
            + f"\nper-chunk overhead on the 2-worker cluster: {per_chunk_ms:.2f} ms wall, "
              f"{cpu_ms:.2f} ms CPU ({args.overhead_chunks} one-row chunks in {t_chunks:.3f} s)\n")
    print(text)
    path = write_text(outdir / "sweep_dask.md", text)
    write_provenance(outdir, "benchmarks.sweep_dask", [path], argv)
    return text


if __name__ == "__main__":
    main()
