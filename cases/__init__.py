"""Figure drivers reproducing Yoo & Lee (2008) from the stickslip package.

Each driver module (`laws`, `slope`, `belt`) has `run(outdir, ...)` (simulate, write CSVs with a
header row of units), `plot(csv, outdir)` (render a PNG from that CSV alone, Agg backend) and
`main(argv=None)` (argparse; `python -m cases.<name> --outdir DIR`). `python -m cases` runs all
of them. What cases/, benchmarks/ and tools/ share (atomic writes, the CSV contract, the
rule for output paths, provenance, timing, the plot style) lives in the `harness` package;
the drivers' own helpers (figures, options, the parallel runner) in `cases._common`, the study
common to both scenes (figures and CPU table) in `cases._study`.
"""
