"""What the gallery's drivers (cases/gallery_*.py) share: figures one column (8.5 cm) wide made
by cases._common.new_figure (fonts of harness.style.column_fonts: 8 pt or more at that width),
two stacked panels, a legend kept clear of the data, and saving in the common style."""
from __future__ import annotations

from pathlib import Path
from typing import Any

from harness import style as _style

from . import _common as c

def figure(height: float, **kwargs: Any) -> tuple[Any, Any]:
    """A one-column figure `height` inches high with one panel: (fig, ax); `kwargs` go to
    plt.subplots (layout, ...)."""
    return c.new_figure(1, height=height, **kwargs)


def two_panels(height: float = 4.6, **kwargs: Any) -> tuple[Any, Any, Any]:
    """A one-column figure with two panels one above the other: (fig, top, bottom); `kwargs`
    go to plt.subplots (sharex, gridspec_kw, layout, ...)."""
    fig, axes = c.new_figure(1, nrows=2, height=height, **kwargs)
    return fig, axes[0, 0], axes[1, 0]


def legend_above_data(ax: Any, ncol: int, room: float = 0.35, **kwargs: Any) -> Any:
    """Raise the axes' upper limit by `room` of its range and put the legend there, in `ncol`
    columns, so that it covers no data."""
    low, high = ax.get_ylim()
    ax.set_ylim(low, high + room * (high - low))
    return ax.legend(loc="upper center", ncol=ncol, handlelength=1.5, columnspacing=0.8, **kwargs)


def save(fig: Any, path: Path) -> Path:
    """Lay the figure out (unless it has a layout engine of its own) and write it as PNG and
    PDF (harness.style.save); the PNG's path."""
    if fig.get_layout_engine() is None:
        fig.tight_layout()
    return _style.save(fig, path, c.atomic_write)
