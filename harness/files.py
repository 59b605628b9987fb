"""Results files of cases/, benchmarks/ and tools/: written whole or not at all, and the CSV
contract (one header row, each column with its unit in brackets).

Every file goes through `atomic_write` (stickslip.outputs: a temporary file beside it, renamed
over it once complete), so an interrupted run never leaves half a CSV or PNG behind.
"""
from __future__ import annotations

import csv
import os
from pathlib import Path
from typing import Any, Iterable, Mapping, Sequence

import numpy as np
from stickslip.outputs import atomic_write

__all__ = ["atomic_write", "write_text", "write_csv", "write_columns", "read_csv", "read_numeric_csv",
           "split_unit", "markdown_table", "FLOAT_FORMAT"]

#: Float format of every CSV: 10 significant digits.
FLOAT_FORMAT: str = "%.10g"


def write_text(path: str | os.PathLike[str], text: str) -> Path:
    """Write `text` to `path` atomically."""
    return atomic_write(path, lambda f: f.write(text))


def write_csv(path: str | os.PathLike[str], header: Sequence[str],
              rows: Iterable[Sequence[Any]]) -> Path:
    """Write a CSV atomically: `header` (each name with its unit in brackets, e.g. "t [s]"),
    then `rows`; floats are written with FLOAT_FORMAT, None as an empty cell."""
    for name in header:
        if "[" not in name or not name.endswith("]"):
            raise ValueError(f"CSV column {name!r} has no unit in brackets")

    def cell(value: Any) -> str:
        if value is None:
            return ""
        if isinstance(value, (float, np.floating)):
            return FLOAT_FORMAT % value
        return str(value)

    def write(f: Any) -> None:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        for row in rows:
            if len(row) != len(header):
                raise ValueError(f"CSV row of {len(row)} cells for {len(header)} columns")
            w.writerow([cell(v) for v in row])

    return atomic_write(path, write)


def write_columns(path: str | os.PathLike[str], columns: Mapping[str, np.ndarray]) -> Path:
    """Write equal-length numeric columns {"name [unit]": array} as a CSV atomically."""
    arrays = [np.asarray(a, dtype=float) for a in columns.values()]
    if len({a.shape for a in arrays}) != 1:
        raise ValueError("columns of different lengths")
    return write_csv(path, list(columns), zip(*arrays))


def read_csv(path: str | os.PathLike[str]) -> dict[str, list[str]]:
    """Read a CSV into {header: list of cell strings} (in column order)."""
    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.reader(f)
        header = next(reader)
        cols: dict[str, list[str]] = {name: [] for name in header}
        for row in reader:
            for name, value in zip(header, row):
                cols[name].append(value)
    return cols


def read_numeric_csv(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """Read an all-numeric CSV into {header: float array}."""
    return {k: np.array(v, dtype=float) for k, v in read_csv(path).items()}


def split_unit(name: str) -> tuple[str, str]:
    """Split "x coulomb [m]" into ("x coulomb", "m")."""
    base, _, unit = name.rpartition("[")
    return base.strip(), unit.rstrip("]").strip()



def markdown_table(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """A Markdown (GitHub) table of `rows` under `header`; None renders as an empty cell."""
    def cell(v: Any) -> str:
        if v is None or v == "":
            return ""
        if isinstance(v, (float, np.floating)):
            return f"{v:.4g}"
        return str(v)

    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"
