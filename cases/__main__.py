"""Regenerate every figure and table of the reproduction:

    python -m cases [--outdir out/] [--only slope belt ...]
    python -m cases --docs        # the committed copies in docs/figures/ (used by REPRODUCTION.md)

Runs each driver of DRIVERS in turn (each parallelises its own simulations over --workers
processes), prints where every file went and the total wall time. To add a driver, append its
module name to DRIVERS: the module needs `main(argv)` accepting `--outdir` (and, if it runs
simulations, `--workers` and `--quiet`).
"""
from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path
from typing import Sequence

#: Driver modules run by `python -m cases`, in order; (name, accepts --workers/--quiet).
DRIVERS: tuple[tuple[str, bool], ...] = (("laws", False), ("slope", True), ("belt", True))
DOCS_DIR: Path = Path(__file__).resolve().parent.parent / "docs" / "figures"


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run the drivers; returns every file written."""
    parser = argparse.ArgumentParser(prog="python -m cases", description=__doc__.split("\n\n")[0])
    parser.add_argument("--outdir", type=Path, default=Path("out"),
                        help="directory for all files (default: out/)")
    parser.add_argument("--docs", action="store_true",
                        help=f"write into {DOCS_DIR} (the figures REPRODUCTION.md embeds)")
    parser.add_argument("--only", nargs="+", choices=[name for name, _ in DRIVERS],
                        help="run only these drivers")
    parser.add_argument("--workers", type=int, default=2,
                        help="parallel simulations per driver (default 2)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    args = parser.parse_args(argv)
    outdir = DOCS_DIR if args.docs else args.outdir
    start = time.perf_counter()
    files: list[Path] = []
    for name, simulates in DRIVERS:
        if args.only and name not in args.only:
            continue
        t0 = time.perf_counter()
        if not args.quiet:
            print(f"== cases.{name} -> {outdir}", file=sys.stderr, flush=True)
        driver = importlib.import_module(f"cases.{name}")
        extra = ["--workers", str(args.workers)] + (["--quiet"] if args.quiet else []) \
            if simulates else []
        files += driver.main(["--outdir", str(outdir), *extra])
        if not args.quiet:
            print(f"== cases.{name}: {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    print(f"{len(files)} files in {outdir}; wall time {time.perf_counter() - start:.1f} s")
    return files


if __name__ == "__main__":
    main()
