"""Figs. 1-3 of the paper: the three friction-coefficient laws mu(v) with Table 1's parameters.

Writes fig01_law_coulomb, fig02_law_recurdyn and fig03_law_proposed as CSV (v [m/s], v/v_s [-],
mu [-]) and PNG (full range, and a zoom on |v| <= 5 v_s)::

    python -m cases.laws --outdir out/
"""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Sequence

import numpy as np

from . import _common as c

FIGURES: dict[str, int] = {"coulomb": 1, "recurdyn": 2, "proposed": 3}
V_MAX: float = 2.0        # half-width of the plotted velocity range [m/s] (belt speed 1.5 m/s)
ZOOM: float = 5.0         # half-width of the zoom panel [v_s]
N_POINTS: int = 2001      # points on each of the two grids (full range and zoom)


def velocity_grid(v_max: float, v_s: float, n: int) -> np.ndarray:
    """Relative velocities [m/s], exactly symmetric about 0: n points on [0, v_max] merged
    with n points on [0, ZOOM v_s] (so that the transitions near v = 0 are resolved), mirrored."""
    pos = np.unique(np.concatenate([np.linspace(0.0, v_max, n), np.linspace(0.0, ZOOM * v_s, n)]))
    pos = pos[pos > 0.0]
    return np.concatenate([-pos[::-1], [0.0], pos])


def run(outdir: str | Path, *, params: dict[str, float] | None = None, v_max: float = V_MAX,
        n_points: int = N_POINTS) -> list[Path]:
    """Evaluate stickslip.friction_coefficient for each law and write one CSV per figure."""
    import stickslip
    params = dict(params or {})
    v_s = params.get("v_s", stickslip.DEFAULTS["v_s"])
    v = velocity_grid(v_max, v_s, n_points)
    files = []
    for law, number in FIGURES.items():
        mu = stickslip.friction_coefficient(law, v, **params)
        files.append(c.write_columns(Path(outdir) / f"fig{number:02d}_law_{law}.csv",
                                     {"v [m/s]": v, "v/v_s [-]": v / v_s, f"mu {law} [-]": mu}))
    return files


def plot(csv: str | Path, outdir: str | Path) -> Path:
    """Render a law's CSV: mu(v) over the full range and over |v| <= ZOOM v_s."""
    csv = Path(csv)
    cols = c.read_numeric_csv(csv)
    v, ratio = cols["v [m/s]"], cols["v/v_s [-]"]
    name = list(cols)[2]
    law = c.split_unit(name)[0].split()[-1]
    mu = cols[name]
    fig, (ax_full, ax_zoom) = c.new_figure(2)
    zoom = np.abs(ratio) <= ZOOM
    for ax, sel, title in ((ax_full, slice(None), "full range"),
                           (ax_zoom, zoom, f"|v| <= {ZOOM:g} v_s")):
        ax.plot(v[sel], mu[sel], color=c.LAW_COLORS[law])
        ax.axhline(0.0, color="k", linewidth=0.5)
        ax.axvline(0.0, color="k", linewidth=0.5)
        ax.set_xlabel("relative velocity v [m/s]")
        if ax is ax_full:
            ax.set_ylabel("friction coefficient μ [-]")
        ax.set_title(title)
    fig.suptitle(f"Fig. {FIGURES[law]}: {c.LAW_LABELS[law].split(' (')[0]} law, "
                 f"v_s = {v[np.argmax(ratio)] / ratio.max():g} m/s")
    return c.save_figure(fig, Path(outdir) / f"{csv.stem}.png")


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.laws [--outdir DIR] [--v-max V] [law options]."""
    parser = argparse.ArgumentParser(prog="python -m cases.laws",
                                     description=c.cli_description(__doc__),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    c.add_outdir(parser, help="directory for CSV and PNG files (default: out/)")
    parser.add_argument("--v-max", type=c.positive_float, default=V_MAX,
                        help="plotted range |v| <= v_max [m/s] (default %(default)s)")
    parser.add_argument("--points", type=c.positive_int, default=N_POINTS,
                        help="points per velocity grid (default %(default)s)")
    c.add_law_options(parser)
    args = parser.parse_args(argv)
    params = c.checked_law_params(parser, args)
    outdir, _ = c.parameter_outdir(args.outdir, c.changed_options(parser, args))
    c.check_writable(parser, outdir)
    files = run(outdir, params=params, v_max=args.v_max, n_points=args.points)
    files += [plot(f, outdir) for f in files]
    return c.finish("cases.laws", argv, files)


if __name__ == "__main__":
    main()
