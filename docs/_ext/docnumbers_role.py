"""The role {num}`TEXT <SOURCE>`: a measured number shown from the results file that measured it.

The number is read from SOURCE (tools/docnumbers.py describes the syntax), shown in the form TEXT
writes it, with the source and the run that wrote it (its provenance sidecar) as a tooltip. When
TEXT disagrees with the source the build warns (an error under -W): `python tools/doctables.py`
rewrites the page from its sources.
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from docutils import nodes

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
from harness.provenance import provenance_of  # noqa: E402 - after the path above
from tools.docnumbers import ROLE, Source, SourceError, shown  # noqa: E402


def _tooltip(source: Source) -> str:
    """The file and key, and the run that wrote the file (its provenance), for the tooltip."""
    run = provenance_of(source.path)
    where = f"{source.relative}: {source.key}"
    if run is None:
        return where
    return f"{where}; written by {run['command']} on {run['date']}, {run['machine']}"


def num_role(name: str, rawtext: str, text: str, lineno: int, inliner: Any,
             options: dict | None = None, content: list[str] | None = None) -> tuple[list, list]:
    """The role's nodes: the number of `text` ("TEXT <SOURCE>") read from its source, as an
    abbreviation whose title names the source; a warning when TEXT disagrees with it."""
    m = ROLE.fullmatch(f"{{num}}`{text}`")
    if m is None:
        msg = inliner.reporter.error(f"{{num}}`{text}`: expected TEXT <PATH:KEY>", line=lineno)
        return [inliner.problematic(rawtext, rawtext, msg)], [msg]
    try:
        value, source = shown(m["text"], m["source"])
    except (SourceError, OSError, ValueError) as exc:
        msg = inliner.reporter.error(f"{{num}}`{text}`: {exc}", line=lineno)
        return [inliner.problematic(rawtext, rawtext, msg)], [msg]
    messages = []
    if value != m["text"]:
        messages.append(inliner.reporter.warning(
            f"the page says {m['text']!r}, {source.relative} gives {value!r} "
            "(python tools/doctables.py rewrites it)", line=lineno))
    return [nodes.abbreviation(value, value, explanation=_tooltip(source))], messages


def setup(app: Any) -> dict[str, bool]:
    app.add_role("num", num_role)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
