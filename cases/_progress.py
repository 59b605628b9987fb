"""Progress bars for the drivers, on stderr (stdout stays the report): tqdm when it is
installed (pip install stickslip[progress]), else one plain line per step, nothing when quiet.
The bar itself is stickslip.distributed.ProgressBar, the one simulate_batch(progress=True)
shows, so the package and the drivers look alike.

Where it plugs in: `_common.run_all` (one bar over the distinct runs of a paper driver) and
the study drivers' `simulate_batch(..., progress=shown(quiet))` (per chunk). Bars appear only
on a terminal.
"""
from __future__ import annotations

import sys
from typing import Iterable, Iterator, TypeVar

from stickslip.distributed import ProgressBar

T = TypeVar("T")


def shown(quiet: bool = False) -> bool:
    """Whether to show progress: not when quiet, and only on a terminal (stderr redirected to a
    file or a pipe, a log, gets no bar redrawn line after line)."""
    return not quiet and sys.stderr.isatty()


def bar(total: int, desc: str = "", quiet: bool = False, unit: str = "run") -> ProgressBar:
    """A bar of `total` steps; `.update()` per step, `.close()` (or a with-block) at the end.
    Shown only on a terminal (`shown`)."""
    return ProgressBar(total, desc, unit=unit, enabled=shown(quiet))


def progress(items: Iterable[T], desc: str = "", quiet: bool = False, unit: str = "run",
             total: int | None = None) -> Iterator[T]:
    """Yield the items, advancing a bar after each one."""
    items = list(items) if total is None and not hasattr(items, "__len__") else items
    with bar(len(items) if total is None else total, desc, quiet, unit) as b:  # type: ignore[arg-type]
        for item in items:
            yield item
            b.update()
