"""What the gallery's drivers (cases/gallery_*.py) share: two stacked panels sized for a column
of 8.5 cm, a legend kept clear of the data, and saving in the common style (cases._style)."""
from __future__ import annotations

from pathlib import Path
from typing import Any

from . import _common as c
from . import _style

#: Width of a gallery figure [in]: one column of 8.5 cm, fonts at their size.
WIDTH: float = 3.4


def two_panels(height: float = 4.6, **kwargs: Any) -> tuple[Any, Any, Any]:
    """A figure with two panels one above the other: (fig, top, bottom)."""
    import matplotlib.pyplot as plt
    _style.apply()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(WIDTH, height), **kwargs)
    return fig, top, bottom


def legend_above_data(ax: Any, ncol: int, room: float = 0.35, **kwargs: Any) -> Any:
    """Raise the axes' upper limit by `room` of its range and put the legend there, in `ncol`
    columns, so that it covers no data."""
    low, high = ax.get_ylim()
    ax.set_ylim(low, high + room * (high - low))
    return ax.legend(fontsize=7, loc="upper center", ncol=ncol, handlelength=1.5, columnspacing=0.8, **kwargs)


def save(fig: Any, path: Path) -> Path:
    """Lay the figure out and write it as PNG and PDF (cases._style.save); the PNG's path."""
    fig.tight_layout()
    return _style.save(fig, path, c.atomic_write)
