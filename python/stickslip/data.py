"""Measured records: read the friction-damper tests shipped in the repository's
`data/friction-damper/` (CC BY-SA 4.0, see the README there) into SI arrays.

A record file is a CSV (optionally gzip-compressed) with comment lines starting with `#`, a
header row, then the columns `t [s], x [m], F [N]` and optionally `v [m/s]`. The damper files
are named `sine_<f>Hz_<a>in_<T>lb.csv.gz`: the name gives the test's frequency, nominal
amplitude and band tension, kept as metadata.
"""
from __future__ import annotations

import gzip
import io
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

#: Inch in metres (exact).
INCH = 0.0254

#: The repository's damper records, when this package runs from a source checkout (an
#: editable install); None when the folder is not there (an installed wheel carries no data).
_SOURCE_DATA = Path(__file__).resolve().parents[2] / "data" / "friction-damper"
DAMPER_DIR: Path | None = _SOURCE_DATA if _SOURCE_DATA.is_dir() else None

_NAME = re.compile(r"sine_(?P<f>[0-9.]+)Hz_(?P<a>[0-9.]+)in_(?P<T>[0-9.]+)lb")
_COLUMNS = {"t": "t [s]", "x": "x [m]", "force": "F [N]", "v": "v [m/s]"}


@dataclass
class Record:
    """One measured record in SI units: time t [s], imposed displacement x [m], measured
    friction force [N] and, when the file has it, the measured velocity v [m/s] (else None).

    Metadata from a damper file's name (None when the name does not follow the pattern):
    frequency [Hz], amplitude (nominal) [m], tension (band tension, which sets the unmeasured
    normal force) [lb]; `source` is the file's first comment line (its provenance)."""

    name: str
    t: np.ndarray
    x: np.ndarray
    force: np.ndarray
    v: np.ndarray | None = None
    frequency: float | None = None
    amplitude: float | None = None
    tension: float | None = None
    source: str = ""
    meta: dict[str, Any] = field(default_factory=dict)

    def __len__(self) -> int:
        return int(self.t.size)

    def subsample(self, step: int) -> "Record":
        """Every `step`-th sample (a new Record with the same metadata)."""
        if not (isinstance(step, (int, np.integer)) and step >= 1):
            raise ValueError(f"step: must be an integer >= 1, got {step!r}")
        cut = slice(None, None, int(step))
        return Record(self.name, self.t[cut].copy(), self.x[cut].copy(), self.force[cut].copy(),
                      None if self.v is None else self.v[cut].copy(), self.frequency,
                      self.amplitude, self.tension, self.source, dict(self.meta, subsample=int(step)))

    def decimate(self, step: int) -> "Record":
        """Every `step`-th sample after an anti-aliasing low-pass filter (`decimate`: an order-8
        Butterworth filter at 0.8 times the new Nyquist frequency, zero phase): a new Record
        with the same metadata."""
        t, (x, force, v) = decimate(self.t, [self.x, self.force, self.v], step)
        return Record(self.name, t, x, force, v, self.frequency, self.amplitude, self.tension, self.source,
                      dict(self.meta, decimate=int(step)))


#: Order of the Butterworth anti-aliasing filter of `decimate`.
FILTER_ORDER: int = 8
#: Its cut-off frequency as a fraction of the decimated record's Nyquist frequency.
FILTER_CUTOFF: float = 0.8


def decimate(t: np.ndarray, columns: list[np.ndarray | None], step: int) -> tuple[np.ndarray, list]:
    """Every `step`-th sample of t, and of each column after an anti-aliasing low-pass filter:
    a Butterworth filter of order FILTER_ORDER (8) with its cut-off at FILTER_CUTOFF (0.8)
    times the new Nyquist frequency, run forward and backward (scipy.signal.sosfiltfilt: zero
    phase, no delay, the gain squared; maximally flat, so a component at a tenth of the
    cut-off keeps its amplitude to 1e-16). A column None stays None."""
    from scipy import signal
    if not (isinstance(step, (int, np.integer)) and step >= 1):
        raise ValueError(f"step: must be an integer >= 1, got {step!r}")
    tt = np.ascontiguousarray(np.asarray(t)[::int(step)])
    if step == 1:
        return tt, [None if c is None else np.asarray(c, dtype=float) for c in columns]
    sos = signal.butter(FILTER_ORDER, FILTER_CUTOFF / int(step), output="sos")
    return tt, [None if c is None else np.ascontiguousarray(signal.sosfiltfilt(sos, np.asarray(c, dtype=float))[::int(step)])
                for c in columns]


def _open_text(path: Path) -> io.TextIOBase:
    with open(path, "rb") as f:
        gzipped = f.read(2) == b"\x1f\x8b"
    return gzip.open(path, "rt", encoding="utf-8") if gzipped else open(path, encoding="utf-8")


def load_damper_record(path: str | os.PathLike[str]) -> Record:
    """Read one record file (CSV or gzip-compressed CSV) into a Record in SI units.

    Parameters
    ----------
    path
        The file, e.g. ``data/friction-damper/sine_1Hz_1in_36lb.csv.gz``.

    Returns
    -------
    Record
        t [s], x [m], force [N], v [m/s] (None without a `v [m/s]` column) and, for a name
        ``sine_<f>Hz_<a>in_<T>lb``, frequency [Hz], amplitude [m] and tension [lb].

    Raises
    ------
    ValueError
        A missing column, a non-numeric or non-finite value, fewer than 2 samples, or times
        that do not increase strictly; the message names the file and the column.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"path: no such file {str(path)!r}")
    source = ""
    with _open_text(path) as f:
        line = f.readline()
        while line.startswith("#"):
            source = source or line.lstrip("# ").rstrip()
            line = f.readline()
        header = [h.strip() for h in line.rstrip("\n").split(",")]
        try:
            table = np.loadtxt(f, delimiter=",", ndmin=2)
        except ValueError as exc:
            raise ValueError(f"{path.name}: not a numeric table after the header ({exc})") from None
    cols: dict[str, np.ndarray] = {}
    for key, label in _COLUMNS.items():
        if label in header:
            cols[key] = np.ascontiguousarray(table[:, header.index(label)], dtype=np.float64)
        elif key != "v":
            raise ValueError(f"{path.name}: no column {label!r} (header: {', '.join(header)})")
    for key, values in cols.items():
        if not np.isfinite(values).all():
            raise ValueError(f"{path.name}: column {_COLUMNS[key]!r} holds non-finite values")
    if cols["t"].size < 2 or not (np.diff(cols["t"]) > 0.0).all():
        raise ValueError(f"{path.name}: column 't [s]' must increase strictly (>= 2 samples)")
    m = _NAME.search(path.name)
    meta = dict(frequency=float(m["f"]), amplitude=float(m["a"]) * INCH, tension=float(m["T"])) if m else {}
    name = path.name.split(".csv")[0]
    return Record(name=name, t=cols["t"], x=cols["x"], force=cols["force"], v=cols.get("v"),
                  source=source, **meta)


def damper_files(tension: float | None = None, directory: str | os.PathLike[str] | None = None) -> list[Path]:
    """The damper record files, all of them or those of one band tension.

    Parameters
    ----------
    tension : float, optional
        Only the records at this band tension [lb] (30 or 36); default: all.
    directory : path, optional
        The folder of the records (default: ``data/friction-damper/`` of a source checkout).

    Returns
    -------
    list of pathlib.Path
        The ``*.csv.gz`` files, sorted by tension, frequency and amplitude.

    Raises
    ------
    ValueError
        When the folder does not exist (not a source checkout and no `directory`).
    """
    where = Path(directory) if directory is not None else DAMPER_DIR
    if where is None or not where.is_dir():
        raise ValueError("directory: the damper records are not here; give the folder that holds "
                         "data/friction-damper/*.csv.gz (a source checkout of stickslip)")

    def key(p: Path) -> tuple[float, float, float]:
        m = _NAME.search(p.name)
        return (float(m["T"]), float(m["f"]), float(m["a"])) if m else (np.inf, np.inf, np.inf)

    files = sorted((p for p in where.glob("*.csv*") if _NAME.search(p.name)), key=key)
    if tension is not None:
        files = [p for p in files if key(p)[0] == float(tension)]
    return files
