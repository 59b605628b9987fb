"""Sphinx configuration of stickslip's documentation site (built by scripts/docs).

The pages are MyST Markdown: index.md, the user guide (guide/*.md, every page in that folder
joins the guide's table of contents by itself), the reproduction report, the benchmarks and the
Python API reference (autodoc with numpydoc). scripts/docs writes the Fortran API (FORD) into
fortran/ beside this site's HTML; the page fortran-api.md links to it.
"""
from __future__ import annotations

import datetime
import logging
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))

project = "stickslip"
author = "the stickslip authors"
copyright = f"{datetime.date.today().year}, {author}"   # noqa: A001 - Sphinx's name

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "numpydoc",
    "docnumbers_role",   # {num}`TEXT <SOURCE>`: a measured number read from its results file
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
# figures/*.md are results tables the pages embed (tools/doctables.py), not pages of their own
exclude_patterns = ["_build", "_ext", "figures/*.md", "**/.ipynb_checkpoints"]

myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
myst_heading_anchors = 3

autodoc_member_order = "bysource"
autodoc_typehints = "none"          # numpydoc's Parameters sections carry the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

html_theme = "pydata_sphinx_theme"
html_title = "stickslip"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 4,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_show_sourcelink = False
html_static_path: list[str] = []


class _NoEmptyGuideGlob(logging.Filter):
    """The guide's toctree (guide/index.md) ends with a glob, so that a page added to docs/guide/ joins
    the guide by itself; when every page there is listed by name the glob matches nothing, which
    is no fault. (Sphinx gives this warning no type, so suppress_warnings cannot name it.)"""

    def filter(self, record: logging.LogRecord) -> bool:
        return getattr(record, "subtype", None) != "empty_glob"


_ABS = re.compile(r"(?<![\\|`])\|([A-Za-z_][\w.*()/^+-]*)\|(?![|`])")


def _plain_absolute_values(app, what, name, obj, options, lines: list[str]) -> None:
    """Docstrings write absolute values as plain text (|v|, |lambda|), as help() shows them;
    reStructuredText would read |name| as a substitution, so the bars are escaped here."""
    lines[:] = [_ABS.sub(r"\\|\1\\|", line) for line in lines]


def setup(app) -> dict:
    logging.getLogger("sphinx.sphinx.directives.other").addFilter(_NoEmptyGuideGlob())
    app.connect("autodoc-process-docstring", _plain_absolute_values, priority=400)
    return {"parallel_read_safe": True}
