"""Many simulations in one call into Fortran: `simulate_batch`.

Each parameter set (one row) is integrated by the same core routine as `stickslip.simulate`,
OpenMP-parallel over the sets (`threads`), and reduced to a compact summary: status, counters,
final state, max |v|, sign changes of the relative sliding velocity and its range over the
second half of the run, on a uniform monitor grid of `n_grid` points (kept only on request).
Memory is O(n_sets * n_grid) at most, whatever the number of steps.

Run-time outcomes (step budget, non-finite solution, ...) are per-row status codes, not
exceptions: a stability map wants to see them. Bad input raises ValueError naming the row.
Units are SI: m, s, kg, m/s; angles in degrees.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from . import _stickslip as _ext
from .core import (DEFAULTS, LAWS, METHODS, SCENES, STATUS_OK, _CODES, _FIRST_INPUT_CODE,
                   _PARAM_ORDER, _check_names, _choice, _count, status_message)

#: Largest n_sets * n_grid the facade allocates when the grid is kept (2 doubles each).
MAX_GRID_VALUES = 20_000_000


@dataclass
class BatchResult:
    """One entry per parameter set (row). Times in s, x in m, velocities in m/s.

    status: library status code (0 = reached t_end; see `message`). v_max: max |v| over the
    initial state and the monitor grid. n_flip / n_flip_tail: sign changes of the relative
    sliding velocity (v on the slope, v_b - v on the belt) between consecutive grid points,
    over the whole run / over t >= t_end/2. n_rev / n_rev_tail: reversals of the direction of v
    between grid points (successive differences of opposite sign, both above 64 eps max|v|),
    a count of high-frequency content (a period-2 chatter sampled every odd number of steps
    reverses at every grid point). vrel_min_tail, vrel_max_tail: its range over
    t >= t_end/2. x_end, v_end: state at t_last (the last grid time reached; t_end on success).
    seconds: wall-clock time of the row on its thread. t, x, v: (n_sets, n_grid) grids when
    keep_grid was set, else None.
    """

    scene: np.ndarray
    law: np.ndarray
    method: np.ndarray
    params: dict[str, np.ndarray]
    t_end: np.ndarray
    h: np.ndarray
    rtol: np.ndarray
    atol: np.ndarray
    status: np.ndarray
    nfev: np.ndarray
    nstep: np.ndarray
    naccept: np.ndarray
    nreject: np.ndarray
    nforced: np.ndarray
    nstiff: np.ndarray
    stiff: np.ndarray
    n_flip: np.ndarray
    n_flip_tail: np.ndarray
    n_rev: np.ndarray
    n_rev_tail: np.ndarray
    t_reached: np.ndarray
    h_last: np.ndarray
    t_last: np.ndarray
    x_end: np.ndarray
    v_end: np.ndarray
    v_max: np.ndarray
    vrel_min_tail: np.ndarray
    vrel_max_tail: np.ndarray
    seconds: np.ndarray
    threads: int
    t: np.ndarray | None = None
    x: np.ndarray | None = None
    v: np.ndarray | None = None

    def __len__(self) -> int:
        return int(self.status.size)

    @property
    def ok(self) -> np.ndarray:
        """True where the row reached t_end."""
        return self.status == STATUS_OK

    def message(self, i: int) -> str:
        """The library's message for row i's status."""
        return status_message(int(self.status[i]))


def _real(name: str, value: Any, accepted: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: must be real numbers ({accepted})") from None
    if arr.ndim > 1:
        raise ValueError(f"{name}: must be a scalar or a 1-D sequence, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero(~np.isfinite(arr.reshape(-1)))[0])
        raise ValueError(f"{name}: must be finite ({accepted}); row {bad} is {arr.reshape(-1)[bad]!r}")
    return arr


def _codes(name: str, value: str | Sequence[str], accepted: tuple[str, ...]) -> np.ndarray:
    names = [value] if isinstance(value, str) else list(value)
    for v in names:
        _choice(name, v, accepted)
    return np.array(names, dtype=object)


def simulate_batch(scene: str | Sequence[str], law: str | Sequence[str], *,
                   method: str | Sequence[str], t_end: Any, h: Any = None,
                   rtol: Any = 1e-6, atol: Any = 1e-9, hmin: Any = 1e-6, hmax: Any = 1e-2,
                   h0: Any = 0.0, max_steps: Any = 10**8, allow_forced: bool = True,
                   stop_on_stiff: bool = False, x0: Any = 0.0, v0: Any = 0.0,
                   n_grid: int = 201, keep_grid: bool = False, threads: int = 1,
                   **params: Any) -> BatchResult:
    """Simulate many parameter sets in one Fortran call, `threads` OpenMP threads over the sets.

    Every argument but allow_forced, stop_on_stiff, n_grid, keep_grid and threads is a scalar
    or a 1-D sequence; they are broadcast to one row per parameter set. The meaning of each is
    that of `stickslip.simulate` (scene, law, method names; t_end, h [s] for RK4 rows; rtol,
    atol, hmin, hmax, h0 [s] for DOPRI5 rows; max_steps; x0 [m], v0 [m/s]; the physical
    parameters of DEFAULTS, v_d = None meaning 1.5 v_s). h may be None or NaN on DOPRI5 rows.

    Each row is integrated on the grid numpy.linspace(0, t_end, n_grid), so with
    keep_grid=True row i reproduces `simulate(..., n_out=n_grid)` exactly. The summary
    (BatchResult) is always returned; run-time failures are per-row status codes.

    Raises ValueError for bad input (the message names the parameter, and the row when the
    library finds it).
    """
    threads = _count("threads", threads)
    n_grid = _count("n_grid", n_grid)
    _check_names(params, _PARAM_ORDER)

    cols: dict[str, np.ndarray] = {
        "scene": _codes("scene", scene, SCENES),
        "law": _codes("law", law, LAWS),
        "method": _codes("method", method, METHODS),
        "t_end": _real("t_end", t_end, "> 0 [s]"),
        "rtol": _real("rtol", rtol, "0 or in [100 eps, 1)"),
        "atol": _real("atol", atol, ">= 0"),
        "hmin": _real("hmin", hmin, ">= 0 [s]"),
        "hmax": _real("hmax", hmax, "> 0 [s]"),
        "h0": _real("h0", h0, ">= 0 [s]"),
        "x0": _real("x0", x0, "[m]"),
        "v0": _real("v0", v0, "[m/s]"),
    }
    h_arr = np.asarray(np.nan if h is None else h, dtype=np.float64)
    if h_arr.ndim > 1:
        raise ValueError(f"h: must be a scalar or a 1-D sequence, got shape {h_arr.shape}")
    cols["h"] = h_arr
    ms = np.asarray(max_steps)
    if ms.dtype.kind not in "iu" or ms.ndim > 1 or np.any(ms < 1):
        raise ValueError(f"max_steps: must be integers >= 1, got {max_steps!r}")
    cols["max_steps"] = ms.astype(np.int64)
    v_d_auto = params.get("v_d", DEFAULTS["v_d"]) is None
    for name in _PARAM_ORDER:
        if name == "v_d" and v_d_auto:
            continue
        cols[name] = _real(name, params.get(name, DEFAULTS[name]), "see stickslip.DEFAULTS")

    try:
        shape = np.broadcast_shapes(*(c.shape for c in cols.values()))
    except ValueError:
        lengths = {k: c.size for k, c in cols.items() if c.ndim == 1 and c.size != 1}
        raise ValueError(f"per-set arguments of different lengths: {lengths}") from None
    n = int(np.prod(shape)) if shape else 1
    if n < 1:
        raise ValueError("no parameter sets (a per-set argument is empty)")
    rows = {k: np.broadcast_to(c, (n,)).copy() for k, c in cols.items()}
    if v_d_auto:
        rows["v_d"] = 1.5 * rows["v_s"]

    is_rk4 = rows["method"] == "rk4"
    bad_h = is_rk4 & ~(np.isfinite(rows["h"]) & (rows["h"] > 0.0))
    if np.any(bad_h):
        i = int(np.flatnonzero(bad_h)[0])
        raise ValueError(f"h: required for method 'rk4' rows (finite, > 0 [s]); row {i} has {rows['h'][i]!r}")
    rows["h"] = np.where(is_rk4, rows["h"], 0.0)

    keep = bool(keep_grid)
    if keep and 2 * n * int(n_grid) > MAX_GRID_VALUES:
        raise ValueError(f"keep_grid: {n} rows x {n_grid} grid points exceed {MAX_GRID_VALUES // 2} "
                         "states; lower n_grid or drop keep_grid")

    def codes(key: str) -> np.ndarray:
        return np.array([_CODES[s] for s in rows[key]], dtype=np.int32)

    p = np.asfortranarray(np.array([rows[k] for k in _PARAM_ORDER], dtype=np.float64))
    sstatus, istats, rstats, y_grid, status = _ext.run_batch(
        codes("scene"), codes("law"), codes("method"), p, rows["x0"], rows["v0"], rows["t_end"],
        rows["h"], rows["rtol"], rows["atol"], rows["hmin"], rows["hmax"], rows["h0"],
        rows["max_steps"], int(bool(allow_forced)), int(bool(stop_on_stiff)), int(n_grid),
        int(n_grid) if keep else 0, int(threads))
    status = int(status)
    if status != STATUS_OK:
        raise ValueError(status_message(status))
    sstatus = np.asarray(sstatus, dtype=np.int64)
    bad = np.flatnonzero(sstatus <= _FIRST_INPUT_CODE)
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"row {i} ({rows['scene'][i]}, {rows['law'][i]}, {rows['method'][i]}): "
                         f"{status_message(int(sstatus[i]))}")

    istats = np.asarray(istats)
    rstats = np.asarray(rstats)
    result = BatchResult(
        scene=rows["scene"].astype(str), law=rows["law"].astype(str), method=rows["method"].astype(str),
        params={k: rows[k] for k in _PARAM_ORDER}, t_end=rows["t_end"], h=rows["h"],
        rtol=rows["rtol"], atol=rows["atol"], status=sstatus,
        nfev=istats[0].copy(), nstep=istats[1].copy(), naccept=istats[2].copy(),
        nreject=istats[3].copy(), nforced=istats[4].copy(), nstiff=istats[5].copy(),
        stiff=istats[6].astype(bool), n_flip=istats[7].copy(), n_flip_tail=istats[8].copy(),
        n_rev=istats[9].copy(), n_rev_tail=istats[10].copy(),
        t_reached=rstats[0].copy(), h_last=rstats[1].copy(), t_last=rstats[2].copy(),
        x_end=rstats[3].copy(), v_end=rstats[4].copy(), v_max=rstats[5].copy(),
        vrel_min_tail=rstats[6].copy(), vrel_max_tail=rstats[7].copy(), seconds=rstats[8].copy(),
        threads=int(threads))
    if keep:
        y = np.asarray(y_grid)
        t = np.empty((n, int(n_grid)))
        for i in range(n):   # the grid the Fortran side used (numpy.linspace's numbers)
            t[i] = np.linspace(0.0, rows["t_end"][i], int(n_grid)) if n_grid > 1 else rows["t_end"][i]
        result.t, result.x, result.v = t, y[0].T.copy(), y[1].T.copy()
    return result


__all__ = ["BatchResult", "simulate_batch", "MAX_GRID_VALUES"]
