"""One style for every figure of cases/ and benchmarks/: the colour-blind-safe palette of Okabe
& Ito (2008), the plain-language names of the library's codes, and how figures are saved.

- `name(code)` turns a law, method or scene code ("recurdyn", "implicit_euler", "belt") into
  the words a figure shows ("RecurDyn (haversine)", "implicit Euler", "mass on a moving
  belt"); a code it does not know is shown as it is, so a new law still plots.
- `LAW_COLORS`, `METHOD_COLORS`, `SEQUENCE`: colours by code, and the default colour cycle.
  The tables of laws and methods are keyed from the library's registry (stickslip.LAWS,
  stickslip.METHODS): a law or method added there gets a display name (its code, spaced), a
  colour of its own from SPARE_COLORS and a marker from SPARE_MARKERS with no edit here; the
  choices below only replace those defaults.
- `apply(width)` sets matplotlib's parameters (Agg backend, fonts legible at a column width of
  8.5 cm for a figure `width` inches wide, the colour cycle); `save(fig,
  path)` writes a PNG at `DPI` (>= 200) and a vector PDF beside it, each whole or not at all.

Use it through `cases._common` (`new_figure`, `save_figure`, `LAW_LABELS`, ...) or directly.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the backend)
from cycler import cycler  # noqa: E402
from stickslip import LAWS, METHODS  # noqa: E402

#: Okabe & Ito's eight colours, named (https://jfly.uni-koeln.de/color/).
OKABE_ITO: dict[str, str] = {"black": "#000000", "orange": "#E69F00", "sky blue": "#56B4E9",
                             "bluish green": "#009E73", "yellow": "#F0E442", "blue": "#0072B2",
                             "vermillion": "#D55E00", "reddish purple": "#CC79A7"}
_C = OKABE_ITO
#: Paul Tol's "wine": a dark colour for the eighth series, where Okabe & Ito's yellow would be
#: faint on white (the figure checklist: markers visible on white).
WINE: str = "#882255"
#: The colour cycle of every axes (no yellow: it is faint on white).
SEQUENCE: tuple[str, ...] = (_C["blue"], _C["vermillion"], _C["bluish green"], _C["orange"],
                             _C["reddish purple"], _C["sky blue"], _C["black"], WINE)

#: Colours and markers a law or method the choices below do not name takes, in this order,
#: skipping those already taken: Paul Tol's colour-blind-safe "muted" colours not chosen below,
#: then his "light" ones.
SPARE_COLORS: tuple[str, ...] = ("#CC6677", "#88CCEE", "#117733", "#44BB99", "#EE8866", "#BBCC33",
                                 "#77AADD", "#EEDD88", "#FFAABB", "#DDDDDD")
SPARE_MARKERS: tuple[str, ...] = ("*", "h", "p", "d", ">", "8", "H", "1", "2", "3", "4")


def keyed(codes: Iterable[str], chosen: Mapping[str, str], spare: Iterable[str],
          default: Callable[[str], str] | None = None) -> dict[str, str]:
    """A value for every code of `codes` (a registry list): `chosen`'s where it names one, else
    `default(code)` or, without `default`, the first of `spare` no code has yet."""
    used = set(chosen.values())
    free = iter([v for v in spare if v not in used])
    return {c: chosen[c] if c in chosen else (default(c) if default else next(free)) for c in codes}


def _spaced(code: str) -> str:
    return code.replace("_", " ")


#: Display names of the library's codes, in one place.
_LAW_NAMES: dict[str, str] = {
    "coulomb": "Coulomb", "recurdyn": "RecurDyn (haversine)", "proposed": "proposed (Roh & Yoo)",
    "stribeck": "Stribeck", "karnopp": "Karnopp", "lugre": "LuGre", "elastoplastic": "elasto-plastic",
    "dahl": "Dahl", "gms": "generalized Maxwell-slip",
    "drake_continuous": "Drake continuous", "drake_tamsi": "Drake TAMSI",
    "capped_viscous": "capped viscous (MuJoCo elliptic, Newton)", "mujoco_pyramidal": "MuJoCo pyramidal"}
LAW_NAMES: dict[str, str] = keyed(LAWS, _LAW_NAMES, (), _spaced)
_METHOD_NAMES: dict[str, str] = {
    "rk4": "RK4", "dopri5": "DOPRI5", "dop853": "DOP853", "radau5": "RADAU5",
    "implicit_euler": "implicit Euler", "galpha": "generalized-α",
    "moreau": "Moreau-Jean (set-valued)", "event_driven": "event-driven (set-valued)"}
METHOD_NAMES: dict[str, str] = {
    **keyed(METHODS, _METHOD_NAMES, (), _spaced),
    # other tools of the comparisons
    "c_loop": "plain C loop", "stickslip_fortran": "stickslip from Fortran",
    "stickslip_python": "stickslip from Python", "gsl": "GSL", "scipy": "scipy"}
SCENE_NAMES: dict[str, str] = {"slope": "box on a 10° slope", "belt": "mass on a moving belt"}
#: Status words of the stability maps and the law comparison.
CLASS_NAMES: dict[str, str] = {"stable": "stable", "chattering": "chattering",
                               "spurious": "spurious (smooth but wrong)", "unstable": "unstable",
                               "newton failed": "Newton failed"}

_LAW_COLORS: dict[str, str] = {
    "coulomb": _C["vermillion"], "recurdyn": _C["blue"], "proposed": _C["bluish green"],
    "stribeck": _C["orange"], "karnopp": _C["reddish purple"], "lugre": _C["sky blue"],
    "elastoplastic": _C["black"],
    # beyond Okabe & Ito's eight: Paul Tol's colour-blind-safe "muted" scheme
    "dahl": "#882255", "gms": "#999933", "drake_continuous": "#44AA99", "drake_tamsi": "#332288",
    "capped_viscous": "#DDCC77", "mujoco_pyramidal": "#AA4499"}
LAW_COLORS: dict[str, str] = keyed(LAWS, _LAW_COLORS, SPARE_COLORS)
_METHOD_COLORS: dict[str, str] = {
    "rk4": _C["blue"], "dopri5": _C["vermillion"], "radau5": _C["bluish green"],
    "implicit_euler": _C["orange"], "galpha": _C["reddish purple"], "dop853": _C["sky blue"],
    "moreau": _C["black"], "event_driven": WINE}
METHOD_COLORS: dict[str, str] = keyed(METHODS, _METHOD_COLORS, SPARE_COLORS)
CLASS_COLORS: dict[str, str] = {
    "stable": _C["bluish green"], "chattering": _C["orange"], "spurious": _C["reddish purple"],
    "unstable": _C["vermillion"], "newton failed": "0.45"}
#: Colours and line styles of the variants (step sizes, tolerances) of one law.
VARIANT_COLORS: tuple[str, ...] = (_C["black"], _C["orange"], _C["sky blue"], _C["reddish purple"],
                                   _C["bluish green"])
VARIANT_STYLES: tuple[str, ...] = ("-", "--", ":", "-.")

#: Resolution of every PNG [dots per inch]; a PDF copy is written beside it.
DPI: int = 200
#: Size of a one-panel figure [in].
FIGSIZE: tuple[float, float] = (6.4, 3.9)
#: A journal's column width (8.5 cm) [in]: the checklist's "legible at a column width".
COLUMN_WIDTH: float = 8.5 / 2.54
#: The smallest font a figure may show once scaled to COLUMN_WIDTH [pt].
MIN_FONT_AT_COLUMN: float = 8.0
#: Colours of the tools of the benchmark figure (one per tool in every panel; the library's
#: two interfaces in two blues, the other tools in colours no method of the figure needs).
TOOL_COLORS: dict[str, str] = {"c_loop": _C["black"], "stickslip_fortran": _C["blue"],
                               "stickslip_python": _C["sky blue"], "gsl": _C["orange"],
                               "scipy": _C["vermillion"], "f2py_wrapper": _C["reddish purple"]}
#: Markers of the methods, so that a series is told apart without its colour.
METHOD_MARKERS: dict[str, str] = keyed(METHODS, {
    "rk4": "o", "dopri5": "s", "dop853": "<", "radau5": "^", "implicit_euler": "v",
    "galpha": "D", "moreau": "P", "event_driven": "X"}, SPARE_MARKERS)


def name(code: str) -> str:
    """The display name of a law, method, scene or status code (the code itself if unknown)."""
    for table in (LAW_NAMES, METHOD_NAMES, SCENE_NAMES, CLASS_NAMES):
        if code in table:
            return table[code]
    return code


def color(code: str, index: int = 0) -> str:
    """The colour of a law, method or status code; else the index-th colour of the cycle."""
    for table in (LAW_COLORS, METHOD_COLORS, CLASS_COLORS):
        if code in table:
            return table[code]
    return SEQUENCE[index % len(SEQUENCE)]


def column_fonts(width: float) -> dict[str, float]:
    """matplotlib's font sizes [pt] for a figure `width` inches wide that is legible when
    scaled to COLUMN_WIDTH: its smallest font (ticks, legend) reads MIN_FONT_AT_COLUMN there.
    apply(width) sets them."""
    small = MIN_FONT_AT_COLUMN * max(width / COLUMN_WIDTH, 1.0)
    return {"font.size": small, "axes.titlesize": small, "axes.labelsize": small,
            "xtick.labelsize": small, "ytick.labelsize": small, "legend.fontsize": small,
            "legend.title_fontsize": small, "figure.titlesize": small * 1.1}


def apply(width: float | None = None) -> None:
    """matplotlib's parameters for every figure: fonts, grid, the Okabe-Ito colour cycle; given
    the figure's `width` [in], fonts legible once it is scaled to a column (column_fonts)."""
    plt.rcParams.update({"font.size": 9, "axes.grid": True, "grid.alpha": 0.3,
                         "legend.fontsize": 8, "axes.titlesize": 9, "figure.titlesize": 10,
                         "legend.title_fontsize": None, "xtick.labelsize": "medium",
                         "ytick.labelsize": "medium", "axes.labelsize": "medium",
                         "lines.linewidth": 1.2, "axes.prop_cycle": cycler(color=list(SEQUENCE)),
                         "savefig.dpi": DPI, "pdf.fonttype": 42})
    if width is not None:
        plt.rcParams.update(column_fonts(width))


def save(fig: Any, path: str | os.PathLike[str],
         atomic_write: Callable[..., Path]) -> Path:
    """Write `fig` as `path` (PNG, DPI dots per inch) and as the same name with .pdf, each
    through `atomic_write` (whole or not at all); close it; return the PNG's path."""
    path = Path(path)
    try:
        atomic_write(path.with_suffix(".pdf"), lambda f: fig.savefig(f, format="pdf"), binary=True)
        return atomic_write(path, lambda f: fig.savefig(f, format="png", dpi=DPI), binary=True)
    finally:
        plt.close(fig)


apply()
