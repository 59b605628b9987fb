"""Measured numbers in the documentation's prose, each read from the results file that measured it.

A page writes a measured number as a MyST role that holds the number as the reader should see it
and, in angle brackets, where it comes from:

    the drivers' CPU times add up to {num}`31.9 s <docs/figures/cases.run.json:cpu_s>`

The source is a path relative to the top of the repository, a colon and a key:

- a named-numbers JSON file (written by `numbers_json`, below): the key is a name of its
  `numbers`, e.g. `docs/figures/cases.run.json:slope.cpu_s`;
- a CSV file with a header row, or a generated Markdown file of pipe tables (the first table
  with the named columns; a cell's first number is its value, "100 %" is 100): the key is a
  column as its header writes it and, in brackets, the cells that pick exactly one row, e.g.
  `docs/figures/table2_slope_cpu.csv:nfev [-][law [-]=coulomb,mode [-]=automatic]`; or several
  rows (a cell may list values, `method=implicit_euler|galpha`) and how to make one number of
  them, `@min`, `@max`, `@median` or `@sum` after the brackets
  (`ratio_step[section=fixed,impl=stickslip_fortran]@max`). A value with a comma is written in
  double quotes (`run="local, 1 thread"`).

A key may be the ratio of two keys of the same file, `A/B` (e.g. a run's CPU time over the
reference run's). A source may end with `*FACTOR` (the number shown is the value times FACTOR:
`*1e6` shows seconds as microseconds, `*100` a fraction as a percentage) and `~N` (rounded to N
significant digits first). The number keeps the form it is written in: as many decimals as
written (`0.1005`), or the exponent form (`8.5e-6`) with as many mantissa decimals. The words
around the number (a unit, "times") are the author's.

`python tools/doctables.py` rewrites every such number from its source (with the tables) and
`--check` lists those that disagree; the documentation site (docs/_ext/docnumbers_role.py) shows
the number read from the source, with the source and the run that wrote it (its provenance
sidecar) as the number's tooltip, and fails the -W build when the page's text disagrees. On
GitHub the role shows as written: the number and its source in code type.

A command that measures a number writes it with `numbers_json` into a results file beside its
other results (and names that file in its provenance sidecar, like every results file):

    write_text(outdir / "cases.run.json", numbers_json({"cpu_s": (31.9, "s", "CPU time ...")}))
"""
from __future__ import annotations

import csv
import json
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

ROOT: Path = Path(__file__).resolve().parent.parent

#: A number written through the role: {num}`TEXT <SOURCE>`.
ROLE = re.compile(r"\{num\}`(?P<text>[^`<]*?)\s*<(?P<source>[^`>]+)>`")
#: A fenced code block (kept whole by re.split).
FENCE = re.compile(r"(^(?:```|~~~).*?^(?:```|~~~)[ \t]*$)", re.S | re.M)
#: The number inside the role's text (the first one).
NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")
_SOURCE = re.compile(r"^(?P<path>[^:]+):(?P<key>.+?)(?:\*(?P<factor>[0-9.eE+-]+))?(?:~(?P<sig>\d+))?$")
#: How the cells of several rows become one number (`@min` after the row selection).
AGGREGATES = {"min": min, "max": max, "sum": sum, "median": lambda v: float(sorted(v)[len(v) // 2])
              if len(v) % 2 else 0.5 * (sorted(v)[len(v) // 2 - 1] + sorted(v)[len(v) // 2])}


class SourceError(ValueError):
    """A role's source cannot be read: no such file, key, column or row."""


@dataclass(frozen=True)
class Source:
    """What a role's source names."""

    path: Path           #: the results file
    key: str             #: the name (JSON) or column[row selection] (CSV, Markdown table)
    factor: float = 1.0  #: shown = value * factor
    sig: int | None = None   #: significant digits to round to first

    @property
    def relative(self) -> str:
        return self.path.relative_to(ROOT).as_posix() if self.path.is_relative_to(ROOT) else str(self.path)


def parse_source(text: str, root: Path = ROOT) -> Source:
    """The Source of `PATH:KEY[*FACTOR][~N]`."""
    m = _SOURCE.match(text.strip())
    if m is None:
        raise SourceError(f"source {text!r}: expected PATH:KEY, optionally *FACTOR and ~DIGITS")
    return Source(root / m["path"], m["key"].strip(), float(m["factor"]) if m["factor"] else 1.0,
                  int(m["sig"]) if m["sig"] else None)


def numbers_json(numbers: Mapping[str, float | tuple[float, str] | tuple[float, str, str]]) -> str:
    """The text of a named-numbers file: {"numbers": {name: {"value", "unit", "what"}}}.

    Parameters
    ----------
    numbers : mapping
        name -> value, (value, unit) or (value, unit, what it is); names sorted in the file.

    Returns
    -------
    str
        The JSON text, to be written by the caller's (atomic) writer.
    """
    out: dict[str, dict[str, object]] = {}
    for name, item in sorted(numbers.items()):
        value, unit, what = (item, "", "") if not isinstance(item, tuple) else (*item, "", "")[:3]
        if not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"numbers_json: {name} = {value!r}: expected a finite number")
        out[name] = {"value": value, "unit": unit, "what": what}
    return json.dumps({"numbers": out}, indent=1) + "\n"


def _table_key(key: str) -> dict[str, str | None] | None:
    """{column, where, how} of `COLUMN[NAME=VALUE,...][@HOW]` (names and columns may hold
    brackets, "x_end [m]"), or None."""
    body, _, how = key.rpartition("@") if re.search(r"\]@\w+$", key) else (key, "", None)
    if not body.endswith("]"):
        return None
    depth = 0
    for i in range(len(body) - 1, -1, -1):
        depth += {"]": 1, "[": -1}.get(body[i], 0)
        if depth == 0:
            where = body[i + 1:-1]
            return {"column": body[:i].strip(), "where": where, "how": how} if "=" in where else None
    return None


def _tables(path: Path) -> list[tuple[list[str], list[list[str]]]]:
    """The (header, rows) of every table of a results file: the CSV's one, or each Markdown
    pipe table of a generated `.md` (cells stripped)."""
    if path.suffix == ".csv":
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
        return [(rows[0], rows[1:])]
    tables, block = [], []
    for line in path.read_text(encoding="utf-8").splitlines() + [""]:
        if line.lstrip().startswith("|"):
            block.append([c.strip() for c in line.strip().strip("|").split("|")])
        elif block:
            if len(block) > 2:
                tables.append((block[0], block[2:]))     # the second line is |---|---|
            block = []
    return tables


def _cell(text: str, where: str) -> float:
    """The number of a cell: the cell itself, or the first number in it ("100 %"; "30,009" is
    30009, its thousands grouped)."""
    try:
        return float(text)
    except ValueError:
        m = re.search(r"(?<![\d.])\d{1,3}(?:,\d{3})+(?![\d,])", text)
        if m is not None and (n := NUMBER.search(text)) is not None and n.start() == m.start():
            return float(m.group(0).replace(",", ""))
        m = NUMBER.search(text)
        if m is None:
            raise SourceError(f"{where}: the cell {text!r} holds no number") from None
        return float(m.group(0))


def _table_value(source: Source) -> float:
    m = _table_key(source.key)
    if m is None:
        raise SourceError(f"{source.relative}: key {source.key!r}: expected COLUMN[NAME=VALUE,...]")
    # NAME=VALUE pairs split at commas outside double quotes (run="local, 1 thread")
    parts = [p for p in re.split(r',(?=(?:[^"]*"[^"]*")*[^"]*$)', m["where"]) if p.strip()]
    if not all("=" in p for p in parts):
        raise SourceError(f"{source.relative}: [{m['where']}]: expected NAME=VALUE, ...")
    where = [(n.strip(), v.strip().strip('"')) for n, v in (p.split("=", 1) for p in parts)]
    names = [m["column"], *(w[0].strip() for w in where)]
    tables = _tables(source.path)
    found = [(h, rows) for h, rows in tables if all(n in h for n in names)]
    if not found:
        heads = "; ".join(", ".join(h) for h, _ in tables)
        raise SourceError(f"{source.relative} has no table with the columns {', '.join(map(repr, names))} "
                          f"(it has: {heads})")
    header, data = found[0]
    col = header.index(m["column"])
    picked = [r for r in data
              if all(r[header.index(n.strip())] in {a.strip() for a in v.split("|")} for n, v in where)]
    if m["how"] is not None:
        if m["how"] not in AGGREGATES or not picked:
            raise SourceError(f"{source.relative}: @{m['how']} of {len(picked)} rows "
                              f"(one of {', '.join(AGGREGATES)}, over at least one row)")
        return float(AGGREGATES[m["how"]]([_cell(r[col], source.relative) for r in picked]))
    if len(picked) != 1:
        raise SourceError(f"{source.relative}: [{m['where']}] picks {len(picked)} rows, not one "
                          f"(add cells, or @{'/@'.join(AGGREGATES)})")
    return _cell(picked[0][col], source.relative)


def _split_ratio(key: str) -> tuple[str, str] | None:
    """(numerator, denominator) of a key `A[...]/B` (the slash outside brackets, right after a
    row selection or its aggregate: a column's own name may hold a slash), or None."""
    depth = 0
    for i, ch in enumerate(key):
        depth += {"[": 1, "]": -1}.get(ch, 0)
        if ch == "/" and depth == 0 and re.search(r"\](?:@\w+)?\s*$", key[:i]):
            return key[:i].strip(), key[i + 1:].strip()
    return None


def value_of(source: Source) -> float:
    """The number the source names (or the ratio of two, `A/B`), times its factor, rounded to
    its significant digits."""
    if not source.path.exists():
        raise SourceError(f"{source.relative} does not exist")
    ratio = _split_ratio(source.key)
    if ratio is not None:
        num, den = (value_of(Source(source.path, k)) for k in ratio)
        value = num / den
    elif source.path.suffix in (".csv", ".md"):
        value = _table_value(source)
    else:
        numbers = json.loads(source.path.read_text()).get("numbers", {})
        if source.key not in numbers:
            raise SourceError(f"{source.relative} has no number {source.key!r} (it has: {', '.join(numbers)})")
        value = float(numbers[source.key]["value"])
    value *= source.factor
    if source.sig is not None and value != 0:
        value = round(value, source.sig - 1 - math.floor(math.log10(abs(value))))
    return value


def format_like(written: str, value: float) -> str:
    """`value` in the form of the first number of `written` (its decimals, or its exponent form
    with as many mantissa decimals), with the words around it kept."""
    m = NUMBER.search(written)
    if m is None:
        raise SourceError(f"{written!r} holds no number to show the source's value in")
    literal = m.group(0)
    if "e" in literal.lower():
        mantissa = literal.lower().split("e")[0]
        decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
        mant, exp = f"{value:.{decimals}e}".split("e")
        shown = f"{mant}e{int(exp)}"
    else:
        decimals = len(literal.split(".")[1]) if "." in literal else 0
        shown = f"{value:.{decimals}f}"
    if shown.startswith("-") and float(shown) == 0:
        shown = shown[1:]
    return written[:m.start()] + shown + written[m.end():]


def shown(text: str, source_text: str, root: Path = ROOT) -> tuple[str, Source]:
    """What the role {num}`text <source_text>` shows: the text with the source's number."""
    source = parse_source(source_text, root)
    return format_like(text, value_of(source)), source


def refresh_text(text: str, root: Path = ROOT) -> tuple[str, list[tuple[int, str, str]]]:
    """`text` with every role's number rewritten from its source, and (line, written, shown) of
    each that changed."""
    changed: list[tuple[int, str, str]] = []
    out, line = [], 1

    def fill(m: re.Match[str]) -> str:
        new, _ = shown(m["text"], m["source"], root)
        if new != m["text"]:
            changed.append((line + m.string.count("\n", 0, m.start()), m["text"], new))
        return m.group(0).replace(f"`{m['text']}", f"`{new}", 1)

    # fenced code shows a role as text (an example of the syntax): only the prose is refreshed
    for part in FENCE.split(text):
        out.append(part if part.startswith(("```", "~~~")) else ROLE.sub(fill, part))
        line += part.count("\n")
    return "".join(out), changed
