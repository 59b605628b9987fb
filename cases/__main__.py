"""Regenerate every figure and table:

    python -m cases [--outdir out/] [--only slope belt ...]   # the paper: Figs. 1-19, Tables 2-3
    python -m cases --all                                     # and the work-precision and stability studies
    python -m cases --docs        # the committed copies in docs/figures/ (used by REPRODUCTION.md)

Runs each driver of DRIVERS in turn (the paper's drivers parallelise their simulations over
--workers processes, the studies over --threads OpenMP threads), prints where every file went
and the total wall time. To add a driver, append (module name, kind) to DRIVERS: the module
needs `main(argv)` accepting `--outdir`, plus `--workers` and `--quiet` for kind "paper" or
`--threads` and `--quiet` for kind "study".
"""
from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path
from typing import Sequence

from ._common import count

#: Driver modules run by `python -m cases`, in order, and their kind: "laws" (no simulation),
#: "paper" (a figure set of the paper, --workers/--quiet) or "study" (--all only, --threads/--quiet).
DRIVERS: tuple[tuple[str, str], ...] = (("laws", "laws"), ("slope", "paper"), ("belt", "paper"),
                                        ("workprecision", "study"), ("stability", "study"),
                                        ("laws_compare", "study"), ("implicit", "study"))
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
    parser.add_argument("--all", action="store_true",
                        help="also run the studies (work-precision, stability, laws_compare, implicit): about 2.5 min more on "
                        "2 cores (README)")
    parser.add_argument("--workers", type=count, default=2,
                        help="parallel simulations per paper driver, >= 1 (default 2)")
    parser.add_argument("--threads", type=count, default=2,
                        help="OpenMP threads per study driver, >= 1 (default 2)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    args = parser.parse_args(argv)
    outdir = DOCS_DIR if args.docs else args.outdir
    quiet = ["--quiet"] if args.quiet else []
    extra = {"laws": [], "paper": ["--workers", str(args.workers), *quiet],
             "study": ["--threads", str(args.threads), *quiet]}
    start = time.perf_counter()
    files: list[Path] = []
    for name, kind in DRIVERS:
        wanted = name in args.only if args.only else (kind != "study" or args.all)
        if not wanted:
            continue
        t0 = time.perf_counter()
        if not args.quiet:
            print(f"== cases.{name} -> {outdir}", file=sys.stderr, flush=True)
        driver = importlib.import_module(f"cases.{name}")
        files += driver.main(["--outdir", str(outdir), *extra[kind]])
        if not args.quiet:
            print(f"== cases.{name}: {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    print(f"{len(files)} files in {outdir}; wall time {time.perf_counter() - start:.1f} s")
    return files


if __name__ == "__main__":
    main()
