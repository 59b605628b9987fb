"""The figure checklist (docs/guide/extending.md), measured: figures drawn again from their
committed CSVs (docs/figures) and the CLI's --plot, each checked as saved.

What is measured, on the figure as laid out for saving (a print scales it as a whole, so that
what overlaps at its own size overlaps at a column's width and what does not, does not):

- the tick labels of an axis do not overlap (their window extents);
- the axis limits against the data drawn in data coordinates (and in the axes sharing them):
  at most a decade beyond the data on a log axis, 20 % of the data's span on a linear one;
- no legend's bounding box holds a data point;
- a log axis shows at least three tick labels.
"""
from __future__ import annotations

import itertools
import math
import sys
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
FIGURES = ROOT / "docs" / "figures"
sys.path.insert(0, str(ROOT))

import matplotlib  # noqa: E402
import matplotlib.text  # noqa: E402

matplotlib.use("Agg")
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

#: How far an axis may reach beyond its data: a factor on a log axis, a fraction of the data's
#: span on a linear one.
LOG_ROOM: float = 10.0
LINEAR_ROOM: float = 0.2


@pytest.fixture
def saved(monkeypatch: pytest.MonkeyPatch) -> Iterator[list[Figure]]:
    """The figures saved while the test runs (Figure.savefig recorded, each once)."""
    figures: list[Figure] = []
    original = Figure.savefig

    def record(self: Figure, *args: Any, **kwargs: Any) -> Any:
        if all(f is not self for f in figures):
            figures.append(self)
        return original(self, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", record)
    yield figures


def _renderer(fig: Figure) -> Any:
    """Draw `fig` (closed by pyplot once saved: given an Agg canvas again) and its renderer."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def _shown_ticks(axis: Any) -> list[Any]:
    """The tick labels of `axis` drawn: non-empty, visible, inside the axis' limits."""
    lo, hi = sorted(axis.get_view_interval())
    span = hi - lo
    out = []
    for tick in axis.get_major_ticks():
        loc = tick.get_loc()
        inside = lo - 1e-9 * span <= loc <= hi + 1e-9 * span
        if axis.get_scale() == "log":
            inside = lo * (1 - 1e-9) <= loc <= hi * (1 + 1e-9)
        for label in (tick.label1, tick.label2):
            if inside and label.get_visible() and label.get_text().strip():
                out.append(label)
    return out


def _data_points(ax: Any) -> np.ndarray:
    """The (x, y) data of `ax` drawn in its data coordinates: lines' vertices (legend proxies
    and lines at a fixed fraction of the axes excluded) and bars' corners."""
    pts = []
    for line in ax.get_lines():
        if line.get_transform() != ax.transData or not line.get_visible():
            continue
        xy = np.asarray(line.get_xydata(), dtype=float)
        if xy.size:
            pts.append(xy[np.all(np.isfinite(xy), axis=1)])
    for patch in ax.patches:
        if isinstance(patch, Rectangle) and patch.get_data_transform() == ax.transData:
            x, y, w, h = patch.get_x(), patch.get_y(), patch.get_width(), patch.get_height()
            if all(map(math.isfinite, (x, y, w, h))):
                pts.append(np.array([[x, y], [x + w, y + h]]))
    return np.vstack(pts) if pts else np.empty((0, 2))


def _siblings(ax: Any, which: str) -> list[Any]:
    group = ax.get_shared_y_axes() if which == "y" else ax.get_shared_x_axes()
    return group.get_siblings(ax)


def check_figure(fig: Figure, name: str, *, fitted: tuple[str, ...] = ("x", "y")) -> list[str]:
    """The checklist's measurable items on `fig`: a list of the failures, in words."""
    problems: list[str] = []
    renderer = _renderer(fig)
    for k, ax in enumerate(fig.axes):
        if not ax.get_visible() or ax.get_label() == "<colorbar>":
            continue
        where = f"{name}, axes {k} ({ax.get_title(loc='left') or ax.get_title()!r})"
        for which, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            labels = _shown_ticks(axis)
            boxes = [t.get_window_extent(renderer) for t in labels]
            for (a, ta), (b, tb) in itertools.combinations(zip(boxes, labels), 2):
                # overlapping by more than a pixel
                if a.x0 + 1 < b.x1 and b.x0 + 1 < a.x1 and a.y0 + 1 < b.y1 and b.y0 + 1 < a.y1:
                    problems.append(f"{where}: {which} tick labels {ta.get_text()!r} and "
                                    f"{tb.get_text()!r} overlap")
            # a log axis with its tick labels (shared axes may show them on one of the group)
            if axis.get_scale() == "log" and len(boxes) < 3:
                shown = {t.get_text() for s in _siblings(ax, which)
                         for t in _shown_ticks(s.yaxis if which == "y" else s.xaxis)}
                if len(shown) < 3:
                    problems.append(f"{where}: log {which} axis with {len(shown)} tick labels")
            if which not in fitted:
                continue
            column = 0 if which == "x" else 1
            data = np.concatenate([_data_points(s)[:, column] for s in _siblings(ax, which)])
            if axis.get_scale() == "log":
                data = data[data > 0]
            if data.size == 0:
                continue
            lo, hi = sorted(ax.get_xlim() if which == "x" else ax.get_ylim())
            dmin, dmax = float(data.min()), float(data.max())
            if which == "y":                 # room kept free at the top for in-panel notes
                notes = max(sum(t.get_window_extent(renderer).height for t in s.texts
                                if t.get_text().strip() and t.get_transform() == s.transAxes)
                            for s in _siblings(ax, "y"))
                if notes:
                    hi = float(ax.transData.inverted().transform(
                        (0.0, ax.transData.transform((1.0, hi))[1] - notes - 4.0))[1])
            if axis.get_scale() == "log":
                if lo * LOG_ROOM < dmin or hi > dmax * LOG_ROOM:
                    problems.append(f"{where}: log {which} axis {lo:.3g} .. {hi:.3g} for data "
                                    f"{dmin:.3g} .. {dmax:.3g} (more than a decade beyond)")
            else:
                room = LINEAR_ROOM * max(dmax - dmin, 1e-300)
                if lo < dmin - room or hi > dmax + room:
                    problems.append(f"{where}: {which} axis {lo:.3g} .. {hi:.3g} for data "
                                    f"{dmin:.3g} .. {dmax:.3g} (more than 20 % beyond)")
    # every text inside the figure (a label cut at the edge is not read)
    page = fig.bbox
    ticks = {id(label) for ax in fig.axes for axis in (ax.xaxis, ax.yaxis)
             for tick in axis.get_major_ticks() + axis.get_minor_ticks()
             for label in (tick.label1, tick.label2)}
    drawn = {id(label) for ax in fig.axes for axis in (ax.xaxis, ax.yaxis)
             for label in _shown_ticks(axis)}
    for text in fig.findobj(matplotlib.text.Text):
        if id(text) in ticks and id(text) not in drawn:
            continue
        if text.get_visible() and text.get_text().strip() and text.figure is fig:
            box = text.get_window_extent(renderer)
            if box.x0 < page.x0 - 1 or box.x1 > page.x1 + 1 or box.y0 < page.y0 - 1 or box.y1 > page.y1 + 1:
                problems.append(f"{name}: the text {text.get_text()!r} reaches beyond the figure")
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    for legend in legends:
        box = legend.get_window_extent(renderer)
        for k, ax in enumerate(fig.axes):
            pts = _data_points(ax)
            if not pts.size:
                continue
            shown = ax.transData.transform(pts)
            clip = ax.bbox
            inside = ((shown[:, 0] > box.x0) & (shown[:, 0] < box.x1) & (shown[:, 1] > box.y0)
                      & (shown[:, 1] < box.y1) & (shown[:, 0] >= clip.x0) & (shown[:, 0] <= clip.x1)
                      & (shown[:, 1] >= clip.y0) & (shown[:, 1] <= clip.y1))
            if inside.any():
                problems.append(f"{name}: the legend covers {int(inside.sum())} data points "
                                f"of axes {k}")
    return problems


def _render(saved: list[Figure], draw: Callable[[], Any]) -> list[Figure]:
    draw()
    assert saved, "nothing was drawn"
    return list(saved)


@pytest.mark.parametrize("kind", ["slope", "belt", "rest", "hmax"])
def test_laws_compare(kind: str, saved: list[Figure], tmp_path: Path) -> None:
    from cases import laws_compare
    csv = FIGURES / f"laws_compare_{kind}.csv"
    (fig,) = _render(saved, lambda: laws_compare.plot(csv, tmp_path))
    # the x axis is the laws' places (categories): its limits are the groups', not data's
    assert check_figure(fig, csv.stem, fitted=("y",)) == []


def test_identify_scores(saved: list[Figure], tmp_path: Path) -> None:
    from cases import identify
    (fig,) = _render(saved, lambda: identify.plot_scores(FIGURES / "identify_scores.csv", tmp_path))
    assert check_figure(fig, "identify_scores", fitted=("y",)) == []


def test_table2_slope_cpu(saved: list[Figure], tmp_path: Path) -> None:
    from cases import _study
    csv = FIGURES / "table2_slope_cpu.csv"
    (fig,) = _render(saved, lambda: _study.plot(csv, tmp_path))
    assert check_figure(fig, csv.stem, fitted=("x",)) == []
    # no marker cut by the frame: every point at least a marker's half-width inside
    ax = fig.axes[0]
    renderer = _renderer(fig)
    shown = ax.transData.transform(_data_points(ax))
    half = max(line.get_markersize() for line in ax.get_lines()) / 72 * fig.dpi / 2
    box = ax.get_window_extent(renderer)
    assert np.all(shown[:, 0] - half >= box.x0) and np.all(shown[:, 0] + half <= box.x1)


def test_workprecision_cpu_belt(saved: list[Figure], tmp_path: Path) -> None:
    from cases import workprecision
    paths: list[Path] = []
    figs = _render(saved, lambda: paths.extend(workprecision.plot(FIGURES / "workprecision.csv", tmp_path)))
    names = [p.stem for p in paths]
    problems = [p for fig, n in zip(figs, names) for p in check_figure(fig, n)]
    assert problems == []
    # each row states its reference (the Coulomb row: the exact motion for every method)
    texts = [t.get_text() for fig in figs for ax in fig.axes for t in ax.texts]
    refs = set(workprecision.REFERENCE_NAMES.values())
    assert sum(t.split("\n")[0] in refs for t in texts) == len(figs) * len(workprecision.LAWS)


def test_pareto_front_is_monotone() -> None:
    """The line of a CPU-time panel goes forward in cost and down in error."""
    from cases.workprecision import pareto_front
    cost = np.array([3.0, 1.0, 2.0, 5.0, 4.0])
    err = np.array([1e-6, 1e-3, 1e-2, 1e-8, 1e-5])
    front = pareto_front(cost, err)
    assert np.all(np.diff(cost[front]) > 0) and np.all(np.diff(err[front]) < 0)
    assert list(front) == [1, 0, 3]


def test_fig14_implicit(saved: list[Figure], tmp_path: Path) -> None:
    """The time series of fig*.csv are not committed (docs/figures/.gitignore: they come back
    in seconds): the ten runs of this one (about 2 s) are made again where it is absent."""
    from cases import implicit
    csv = FIGURES / "fig14_implicit.csv"
    if not csv.exists():
        csv = implicit.fig14(tmp_path, implicit.T_END_BELT, round(implicit.T_END_BELT / 0.01) + 1)[0]
    (fig,) = _render(saved, lambda: implicit.plot(csv, tmp_path))
    assert check_figure(fig, csv.stem) == []


def test_cli_plot(saved: list[Figure], tmp_path: Path) -> None:
    """python -m stickslip run MODEL.toml --plot: two bodies that stick together (a clutch)."""
    from stickslip.__main__ import main
    from test_model import clutch        # two bodies and a clutch between them
    m = clutch()
    path = tmp_path / "clutch.toml"
    m.to_toml(path)
    out = tmp_path / "clutch.csv"
    with matplotlib.rc_context():         # the CLI sets its fonts for its own process
        assert main(["run", str(path), "--method", "moreau", "--h", "1e-3", "--t-end", "1.5",
                     "--out", str(out), "--plot"]) == 0
    (fig,) = saved
    assert check_figure(fig, "cli plot") == []
    # a curve on another stays visible: the bodies' curves differ in line style and marker
    for ax in fig.axes:
        lines = [line for line in ax.get_lines() if line.get_label() in ("J1", "J2")]
        styles = {(line.get_linestyle(), line.get_marker()) for line in lines}
        assert len(styles) == len(lines) == 2
