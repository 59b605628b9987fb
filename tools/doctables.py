"""Tables of measured numbers in the documentation, generated from the results files.

A page marks each such table with an HTML comment that names its source (a path relative to the
page), and the table sits between that comment and `<!-- end table -->`:

    <!-- table: figures/table2_slope_cpu.csv
    columns: law [-] = law; mode [-] = mode; nfev [-] = evaluations
    where: law [-] = recurdyn, proposed
    digits: 4
    -->
    | law | mode | evaluations |
    ...
    *Source: `docs/figures/table2_slope_cpu.csv`, written by `python -m cases --docs` ...*
    <!-- end table -->

A Markdown source (`.md`) is embedded whole. The source `registry:law`, `registry:scene`,
`registry:method` or `registry:param` is a table of what the compiled library registers
(`stickslip.REGISTRY`): every name with its parameters, states, order or controls and its
one-line description, so the guides cannot fall behind a law, scene or method added later. A CSV source is rendered as a table of the chosen
`columns` (the CSV header as written, then `= label` for the column's title in the page; all
columns when omitted), keeping the rows whose cells match every `where` line (any of the listed
values), numbers to `digits` significant digits (default 4; a column of integers whole). Under each table
a line names the file and, from its provenance sidecar (harness/provenance.py), the command,
date and machine that wrote it. HTML comments show in neither GitHub's rendering nor the site.

    python tools/doctables.py            # refresh every marked table of README.md and docs/
    python tools/doctables.py --check    # list the tables and numbers that disagree with their sources (exit 1)

A number in the prose is written as a role that names its source, {num}`0.1005 m <PATH:KEY>`
(tools/docnumbers.py); this command refreshes and checks those numbers too.

scripts/docs refreshes before it builds; tests/project/test_docs.py runs the check.
"""
from __future__ import annotations

import argparse
import csv
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
from harness.provenance import provenance_of  # noqa: E402 - after the path above
from tools.docnumbers import refresh_text as refresh_numbers  # noqa: E402

BLOCK = re.compile(r"(?P<open><!-- table: (?P<spec>.*?)-->\n)(?P<body>.*?)(?P<close><!-- end table -->)",
                   re.S)


@dataclass
class Spec:
    """What a marker asks for."""

    source: Path
    columns: list[tuple[str, str]] = field(default_factory=list)   # (CSV header, label)
    where: list[tuple[str, set[str]]] = field(default_factory=list)
    digits: int = 4


REGISTRY_PREFIX = "registry:"


def parse_spec(text: str, page: Path) -> Spec:
    lines = [ln.strip() for ln in text.strip().splitlines() if ln.strip()]
    source = Path(lines[0]) if lines[0].startswith(REGISTRY_PREFIX) else (page.parent / lines[0]).resolve()
    spec = Spec(source)
    for line in lines[1:]:
        key, _, value = line.partition(":")
        key = key.strip()
        if key == "columns":
            for item in value.split(";"):
                name, _, label = item.partition("=")
                spec.columns.append((name.strip(), (label or name).strip()))
        elif key == "where":
            name, _, values = value.partition("=")
            spec.where.append((name.strip(), {v.strip() for v in values.split(",")}))
        elif key == "digits":
            spec.digits = int(value)
        else:
            raise ValueError(f"{page}: unknown table option {key!r} (columns, where, digits)")
    return spec


def is_integer(text: str) -> bool:
    """The cell is an integer literal."""
    return re.fullmatch(r"[+-]?\d+", text.strip()) is not None


def cell(text: str, digits: int, whole: bool = True) -> str:
    """A CSV cell for the page: integers whole when `whole` (their column holds integers
    only), other numbers to `digits` significant digits."""
    text = text.strip()
    if whole and is_integer(text):
        return text
    try:
        value = float(text)
    except ValueError:
        return text.replace("|", "\\|")
    return f"{value:.{digits}g}"


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def render_csv(spec: Spec) -> str:
    with open(spec.source, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], rows[1:]
    index = {name: i for i, name in enumerate(header)}
    columns = spec.columns or [(h, h) for h in header]
    for name in [c for c, _ in columns] + [w for w, _ in spec.where]:
        if name not in index:
            raise ValueError(f"{spec.source.name} has no column {name!r} (it has: {', '.join(header)})")
    kept = [r for r in data if all(r[index[w]] in values for w, values in spec.where)]
    out = ["| " + " | ".join(label for _, label in columns) + " |",
           "|" + "---|" * len(columns)]
    # a column with a non-integer number shows all its numbers to `digits` (one format a column)
    whole = {c: all(is_integer(r[index[c]]) or not _is_number(r[index[c]]) for r in kept) for c, _ in columns}
    out += ["| " + " | ".join(cell(r[index[c]], spec.digits, whole[c]) for c, _ in columns) + " |"
            for r in kept]
    return "\n".join(out)


def source_line(path: Path) -> str:
    where = path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else path.name
    run = provenance_of(path)
    if run is None:
        return f"*Source: `{where}`.*"
    load = f", load average {run['load_average']:g}" if run.get("load_average") is not None else ""
    return (f"*Source: `{where}`, written by `{run['command']}` on {run['date']}, "
            f"{run['machine']}{load}.*")


def _names(items: tuple[str, ...] | None) -> str:
    return ", ".join(f"`{i}`" for i in items) if items else ""


def render_registry(kind: str) -> str:
    """The table of one kind of registry entry (law, scene, method, param), from the library."""
    import stickslip as ss
    reg = ss.REGISTRY.get(kind)
    if kind not in ("law", "scene", "method", "param") or reg is None:
        raise ValueError(f"registry:{kind}: unknown kind (law, scene, method, param)")
    if kind == "law":
        rows = [["name", "parameters", "internal states", "description"]]
        rows += [[f"`{n}`", _names(e["params"]), ", ".join(e["states"]) or "none", e["doc"].strip()]
                 for n, e in reg.items()]
    elif kind == "scene":
        rows = [["name", "parameters", "description"]]
        rows += [[f"`{n}`", _names(e["params"]), e["doc"].strip()] for n, e in reg.items()]
    elif kind == "method":
        rows = [["name", "order", "step", "controls", "laws", "description"]]
        rows += [[f"`{n}`", str(e["order"]),
                  ("adaptive" if e["adaptive"] else "fixed") + (", implicit" if e["implicit"] else ""),
                  _names(e["controls"]), _names(e["laws"]) or "all", e["doc"].strip()]
                 for n, e in reg.items()]
    else:
        rows = [["name", "default", "unit", "accepted", "description"]]
        rows += [[f"`{n}`", (f"{e['scale']:g} {e['default_of']}" if e["default_of"] else f"{e['default']:g}"),
                  e["unit"], e["rule"].partition(": ")[2], e["doc"].strip()] for n, e in reg.items()]
    lines = ["| " + " | ".join(c.replace("|", "\\|") for c in r) + " |" for r in rows]
    lines.insert(1, "|" + "---|" * len(rows[0]))
    return "\n".join(lines)


def render(spec: Spec) -> str:
    if str(spec.source).startswith(REGISTRY_PREFIX):
        kind = str(spec.source)[len(REGISTRY_PREFIX):]
        return (f"{render_registry(kind)}\n\n*Source: `stickslip.REGISTRY[\"{kind}\"]`, read from the "
                "compiled library when the package is imported.*\n")
    if not spec.source.exists():
        raise FileNotFoundError(f"table source {spec.source} does not exist")
    table = spec.source.read_text().strip() if spec.source.suffix == ".md" else render_csv(spec)
    return f"{table}\n\n{source_line(spec.source)}\n"


def refresh(page: Path) -> tuple[str, list[int]]:
    """The page's text with every marked table regenerated and every {num} role's number
    rewritten from its source (tools/docnumbers.py), and the line numbers of what changed."""
    text = page.read_text()
    changed: list[int] = []

    def fill(m: re.Match[str]) -> str:
        body = render(parse_spec(m.group("spec"), page))
        if body != m.group("body"):
            changed.append(text.count("\n", 0, m.start()) + 1)
        return m.group("open") + body + m.group("close")

    text = BLOCK.sub(fill, text)
    text, numbers = refresh_numbers(text)
    return text, sorted(changed + [line for line, _, _ in numbers])


def pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python tools/doctables.py",
                                     description="Refresh (or --check) the documentation's "
                                                 "tables and numbers measured, from their results files.")
    parser.add_argument("--check", action="store_true",
                        help="change nothing; list the tables and numbers that disagree with their sources "
                             "and exit 1 if any does")
    args = parser.parse_args(argv)
    stale = []
    for page in pages():
        new, changed = refresh(page)
        rel = page.relative_to(ROOT).as_posix()
        stale += [f"{rel}:{line}" for line in changed]
        if changed and not args.check:
            page.write_text(new)
    if args.check and stale:
        print("tables and numbers that disagree with their results files (python tools/doctables.py "
              "refreshes them):\n" + "\n".join(stale), file=sys.stderr)
        return 1
    if stale:
        print("refreshed: " + ", ".join(stale))
    return 0


if __name__ == "__main__":
    sys.exit(main())
