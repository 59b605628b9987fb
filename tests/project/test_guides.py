"""The guides name everything the library registers: a law, scene or method added to the
Fortran registry (stickslip.LAWS, SCENES, METHODS) without a word in the guides fails here."""
from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

import stickslip as ss

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide"

#: Which guide must name every entry of which registry list.
PAGES: dict[str, tuple[str, ...]] = {
    "friction-laws.md": ("law",),
    "python-api.md": ("law", "scene", "method"),
    "integrators.md": ("method",),
}


def registered(kind: str) -> tuple[str, ...]:
    """The names the library registers for one kind (law, scene, method)."""
    return {"law": ss.LAWS, "scene": ss.SCENES, "method": ss.METHODS}[kind]


def prose(text: str) -> str:
    """The page without its generated tables (a registry table names everything by
    construction; the prose must too)."""
    return re.sub(r"<!-- table: registry:.*?<!-- end table -->", "", text, flags=re.S)


def missing(names: tuple[str, ...], text: str) -> list[str]:
    """The names that the text never writes as code (`name` or "name")."""
    return [n for n in names if f"`{n}`" not in text and f'"{n}"' not in text]


def test_the_checker_notices_a_missing_name() -> None:
    text = "Use `rk4` or \"dopri5\"; RADAU5 is mentioned only in prose."
    assert missing(("rk4", "dopri5", "radau5"), text) == ["radau5"]
    assert prose("a\n<!-- table: registry:law -->\n`x`\n<!-- end table -->\nb") == "a\n\nb"


@pytest.mark.parametrize("page", sorted(PAGES))
def test_every_registered_name_is_in_its_guides(page: str) -> None:
    text = prose((GUIDE / page).read_text())
    gaps = {kind: missing(registered(kind), text) for kind in PAGES[page]}
    gaps = {k: v for k, v in gaps.items() if v}
    assert not gaps, f"docs/guide/{page} does not name the registered {gaps}"


def test_the_api_guide_has_the_registry_tables() -> None:
    text = (GUIDE / "python-api.md").read_text()
    for kind in ("law", "scene", "method", "param"):
        assert f"<!-- table: registry:{kind} -->" in text


API = ROOT / "docs" / "api.md"
DIRECTIVE = re.compile(r"^\.\. (?:auto(?:function|class|exception|data)|py:data):: "
                       r"(?:stickslip\.)?(?P<name>[\w.]+)\s*$", re.M)


def documented(text: str) -> list[str]:
    """The names the API reference documents, once per directive (module prefix dropped)."""
    return [m.group("name") for m in DIRECTIVE.finditer(text)]


def test_the_api_checker_counts_directives() -> None:
    text = ".. autofunction:: simulate\n.. py:data:: LAWS\n   :type: tuple\n.. autoclass:: stickslip.Result\n"
    assert documented(text) == ["simulate", "LAWS", "Result"]


def test_every_public_name_is_in_the_api_reference_once() -> None:
    """Each name of stickslip.__all__ has exactly one directive in docs/api.md (no catch-all
    automodule that would list it again), and nothing there names what the package lacks."""
    text = API.read_text()
    names = documented(text)
    twice = sorted({n for n in names if names.count(n) > 1})
    absent = sorted(set(ss.__all__) - set(names))
    unknown = sorted(n for n in names if "." not in n and not hasattr(ss, n))
    assert not twice and not absent and not unknown, (
        f"docs/api.md: documented twice {twice}, missing {absent}, not in the package {unknown}")
    assert ":undoc-members:" not in text and "automodule" not in text


@pytest.mark.parametrize("name", [n for n in ss.__all__ if callable(getattr(ss, n))
                                  and not isinstance(getattr(ss, n), type)])
def test_every_public_function_has_numpydoc_sections(name: str) -> None:
    """A public function's docstring has numpydoc Parameters and Returns sections."""
    doc = getattr(ss, name).__doc__ or ""
    assert "Parameters\n" in doc and "Returns\n" in doc, f"stickslip.{name}: no numpydoc sections"


def test_every_law_and_method_has_its_own_colour_and_name() -> None:
    """The figure checklist (docs/guide/extending.md): a law or a method has one colour in
    every figure, distinct from the others of its kind, and a display name."""
    sys.path.insert(0, str(ROOT))
    from harness import style as _style
    for kind, names, colours, labels in (("law", ss.LAWS, _style.LAW_COLORS, _style.LAW_NAMES),
                                         ("method", ss.METHODS, _style.METHOD_COLORS, _style.METHOD_NAMES)):
        missing_colour = [n for n in names if n not in colours]
        missing_name = [n for n in names if n not in labels]
        assert not missing_colour and not missing_name, (kind, missing_colour, missing_name)
        used = [colours[n].lower() for n in names]
        assert len(set(used)) == len(used), f"two {kind}s share a colour: {used}"


#: The sources that draw the figures of docs/figures, docs/gallery and benchmarks/results.
FIGURE_SOURCES: tuple[Path, ...] = tuple(
    p for p in sorted((ROOT / "cases").glob("*.py")) + sorted((ROOT / "benchmarks").glob("*.py")))


def test_every_method_has_its_own_marker() -> None:
    """The figure checklist, point 2: where colour alone would not separate series, a method's
    marker does; every registered method has one, distinct from the others'."""
    sys.path.insert(0, str(ROOT))
    from harness import style as _style
    markers = [_style.METHOD_MARKERS.get(m) for m in ss.METHODS]
    assert None not in markers, [m for m in ss.METHODS if m not in _style.METHOD_MARKERS]
    assert len(set(markers)) == len(markers), f"two methods share a marker: {markers}"


def test_figure_colours_come_from_the_style() -> None:
    """The figure checklist, point 2: no driver spells a colour of its own as a hex code (a law,
    method or tool takes its colour from harness/style.py, the only place that names them), and
    the drivers that draw import the style (directly or through cases._common)."""
    hex_colour = re.compile(r"[\"']#[0-9A-Fa-f]{6}[\"']")
    for path in FIGURE_SOURCES:
        text = path.read_text()
        assert not hex_colour.search(text), f"{path.name}: a colour outside harness/style.py"
        if re.search(r"\.(plot|loglog|semilogy|bar|barh|scatter)\(", text):
            assert "_style" in text or "_common" in text, f"{path.name}: draws without harness.style"


def test_no_caption_in_the_image_and_one_line_titles() -> None:
    """The figure checklist, point 4: no caption set into a figure (figure_legend's caption),
    and no title of more than one line (a title with a line break is a caption)."""
    call = re.compile(r"(set_title|suptitle)\((?:[^()]|\([^()]*\))*\)", re.S)
    for path in FIGURE_SOURCES:
        text = path.read_text()
        assert not re.search(r"figure_legend\([^)]*caption\s*=", text), \
            f"{path.name}: a caption set into the image (the page's text says how to read it)"
        for match in call.finditer(text):
            assert "\\n" not in match.group(0), f"{path.name}: a title of two lines: {match.group(0)}"


#: The drivers whose figures are drawn with column-width fonts (issue 32 item 5): every figure
#: they make comes from new_figure or follows _style.apply(width) / column_fonts(width).
COLUMN_FONT_DRIVERS: tuple[str, ...] = (
    "cases/_common.py", "cases/_study.py", "cases/laws.py", "cases/laws_compare.py",
    "cases/stability.py", "cases/identify.py", "cases/chain.py", "cases/engines.py",
    "cases/implicit.py", "cases/workprecision.py", "cases/stick.py", "benchmarks/run.py",
    "cases/_gallery.py", *(f"cases/{p.name}" for p in sorted((ROOT / "cases").glob("gallery_*.py"))))
#: Figures of those drivers not yet redrawn, and why (each an exception with its reason).
NOT_YET_AT_COLUMN_FONTS: dict[str, str] = {}


def test_column_fonts_are_legible_at_a_column_width() -> None:
    """The figure checklist, point 7: the fonts column_fonts gives a figure read at least
    MIN_FONT_AT_COLUMN points once it is scaled to a column (8.5 cm), at any width, and
    apply(width) sets them (apply() the plain sizes again); new_figure's figures have them; and
    the drivers of COLUMN_FONT_DRIVERS make every figure that way, with no font size set by a
    number of points (which would not scale with the figure)."""
    sys.path.insert(0, str(ROOT))
    from harness import style as _style
    from cases import _common
    assert _style.COLUMN_WIDTH == pytest.approx(8.5 / 2.54)
    for width in (2.0, _style.COLUMN_WIDTH, 5.6, 12.0):
        fonts = _style.column_fonts(width)
        scaled = min(fonts.values()) * min(_style.COLUMN_WIDTH / width, 1.0)
        assert scaled >= _style.MIN_FONT_AT_COLUMN - 1e-9, (width, fonts)
    from matplotlib.font_manager import FontProperties
    for ncols in (1, 2, 3):
        fig, _ = _common.new_figure(ncols)
        width = fig.get_figwidth()
        for key in ("xtick.labelsize", "ytick.labelsize", "legend.fontsize", "axes.titlesize",
                    "axes.labelsize"):
            size = FontProperties(size=_style.plt.rcParams[key]).get_size_in_points()
            assert size * min(_style.COLUMN_WIDTH / width, 1.0) >= _style.MIN_FONT_AT_COLUMN - 1e-9, \
                (ncols, key, size)
        _style.plt.close(fig)
    _style.apply()
    assert _style.plt.rcParams["font.size"] == 9
    make = re.compile(r"plt\.(subplots|figure)\(")
    scaled_here = re.compile(r"apply\([^)]|column_fonts\(")
    for name in COLUMN_FONT_DRIVERS:
        text = (ROOT / name).read_text()
        assert not re.search(r"fontsize\s*=\s*[0-9]", text), f"{name}: a font size in points"
        for match in make.finditer(text):
            start = text.rfind("\ndef ", 0, match.start())
            function = re.match(r"\ndef (\w+)", text[start:]).group(1)
            if function in NOT_YET_AT_COLUMN_FONTS or function == "new_figure":
                continue
            assert scaled_here.search(text, start, match.start()), \
                f"{name}: {function} makes a figure without column-width fonts"


def test_work_precision_shows_every_method_or_says_why_not() -> None:
    """Issue 32: the work-precision figure shows every method of stickslip.METHODS; where a
    method has no curve (refused by the law, or not run) the figure names it and the reason,
    and the library does refuse the pairs said to be refused."""
    sys.path.insert(0, str(ROOT))
    from cases import workprecision as wp
    assert set(wp.METHODS) == set(ss.METHODS)
    assert {m for _, group in wp.GROUPS for m in group} == set(ss.METHODS)
    assert all(len(group) <= 6 for _, group in wp.GROUPS)
    for scene in wp.SCENES:
        for law in wp.LAWS:
            for method in wp.METHODS:
                why = wp.refusal(scene, law, method)
                assert wp.applies(scene, law, method) == (why is None), (scene, law, method)
                if why is not None and why.startswith("refused"):
                    with pytest.raises(ValueError):
                        ss.simulate(scene, law, method=method, t_end=0.01,
                                    **({"h": 1e-3} if method in wp.FIXED_STEP else {}))


def gallery_figures(monkeypatch: pytest.MonkeyPatch) -> dict[str, object]:
    """Every gallery figure drawn again from the CSVs the gallery's drivers committed to
    docs/figures (each driver's plot reads its CSVs alone): {name: the matplotlib figure}."""
    sys.path.insert(0, str(ROOT))
    from harness import style as _style
    from cases import _common, gallery_belt2dof, gallery_clutches, gallery_denhartog
    from cases import gallery_frame, gallery_stacked, gallery_steady
    drawn: dict[str, object] = {}
    monkeypatch.setattr(_style, "save", lambda fig, path, atomic_write: drawn.setdefault(Path(path).stem, fig))
    figures = ROOT / "docs" / "figures"
    gallery_denhartog.plot(figures)
    gallery_frame.plot(figures)
    gallery_steady.plot(figures)
    gallery_clutches.plot(_common.read_numeric_csv(figures / "gallery_clutches.csv"), Path("gallery_clutches.png"))
    gallery_belt2dof.plot(figures / "gallery_belt2dof.csv", figures / "gallery_belt2dof_errors.csv",
                          Path("gallery_belt2dof.png"))
    gallery_stacked.plot(figures / "gallery_stacked.csv", figures / "gallery_stacked_convergence.csv",
                         Path("gallery_stacked.png"))
    return drawn


def test_gallery_figures_are_legible_at_a_column_width(monkeypatch: pytest.MonkeyPatch) -> None:
    """The figure checklist, point 7, on the drawn gallery figures: every piece of text
    (ticks, labels, titles, legends, colour bars) reads at least MIN_FONT_AT_COLUMN points once
    the figure is scaled to a column of 8.5 cm, and no figure is wider than a column needs."""
    from matplotlib.text import Text
    from harness import style as _style
    drawn = gallery_figures(monkeypatch)
    assert set(drawn) == {"denhartog_amplitude", "denhartog_regions", "frame_drift", "frame_loop",
                          "gallery_clutches", "gallery_belt2dof", "gallery_stacked",
                          "steady_belt", "steady_denhartog", "steady_hopf", "steady_damper"}
    for name, fig in drawn.items():
        fig.canvas.draw()
        scale = min(_style.COLUMN_WIDTH / fig.get_figwidth(), 1.0)
        small = [(t.get_text(), t.get_fontsize()) for t in fig.findobj(Text)
                 if t.get_visible() and t.get_text().strip()
                 and t.get_fontsize() * scale < _style.MIN_FONT_AT_COLUMN - 1e-9]
        assert not small, f"{name}: text below {_style.MIN_FONT_AT_COLUMN} pt at a column width: {small[:5]}"
        _style.plt.close(fig)


def test_belt_engines_and_presliding_figures_have_at_most_six_series_a_panel(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The figure checklist, point 7 (at most about six series a panel), on the two figures
    that had seven in one: engines_belt and laws_compare_presliding, drawn again from their
    committed CSVs, keep every series of the CSV and put at most six in a panel."""
    sys.path.insert(0, str(ROOT))
    from harness import style as _style
    from cases import _common, engines, laws_compare
    drawn: dict[str, object] = {}
    monkeypatch.setattr(_style, "save", lambda fig, path, atomic_write: drawn.setdefault(Path(path).stem, fig))
    figures = ROOT / "docs" / "figures"
    engines.plot(figures)
    laws_compare.plot(figures / "laws_compare_presliding.csv", figures)
    panels = {name: [[line for line in ax.get_lines() if not line.get_label().startswith("_")]
                     for ax in drawn[name].axes] for name in ("engines_belt", "laws_compare_presliding")}
    for name, lines in panels.items():
        assert len(lines) >= 3 and all(0 < len(p) <= 6 for p in lines), (name, [len(p) for p in lines])
    runs = [k[2:].split(" [")[0] for k in _common.read_csv(figures / "engines_belt_series.csv") if k.startswith("v_")]
    assert {line.get_label() for p in panels["engines_belt"] for line in p} == {engines.label(r) for r in runs}
    states = list(_common.read_csv(figures / "laws_compare_presliding.csv"))[1:]
    assert sum(len(p) for p in panels["laws_compare_presliding"]) == len(states)
    _style.plt.close("all")
