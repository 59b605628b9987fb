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

import warnings
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from . import _stickslip as _ext
from .core import (CONTROL_DEFAULTS, CONTROLS, LAWS, METHODS, REGISTRY, SCENES, STATE_COUNT_PARAMS,
                   STATUS_OK, _states,
                   UnstableStepWarning, UnusedParameterWarning, _FIRST_INPUT_CODE, _PARAM_ORDER,
                   _check_names, _choice, _count, accepted_range, interruptible, rk4_stability_bound,
                   status_message)

#: Names of the integer and real summary fields, in the wrapper's order.
_BATCH_INT, _BATCH_REAL = (tuple(x.split()) for x in _ext.batch_names().decode().strip().split("|"))

#: Largest n_sets * n_grid the facade allocates when the grid is kept (2 doubles each).
MAX_GRID_VALUES = 20_000_000
#: A row chattered when the velocity reversed between at least this fraction of the monitor
#: grid's intervals over t >= t_end/2 (BatchResult).
CHATTER_FRACTION = 0.25


@dataclass
class BatchResult:
    """One entry per parameter set (row). Times in s, x in m, velocities in m/s.

    status: library status code (0 = reached t_end; see `message`). The run's counters
    (nfev, nstep, naccept, nreject, nforced, nstiff, stiff, njac, ndec, nsol, t_reached, h_last)
    and the monitor's fields are in `fields` by name and as attributes. v_max: max abs(v) over the
    initial state and the monitor grid. n_flip / n_flip_tail: sign changes of the relative
    sliding velocity (v on the slope, v_b - v on the belt) between consecutive grid points, over
    the whole run / over t >= t_end/2. n_rev / n_rev_tail: reversals of the direction of v
    between grid points (successive differences of opposite sign, both above 64 eps max abs(v)), a
    count of high-frequency content. vrel_min_tail, vrel_max_tail: the relative velocity's
    range over t >= t_end/2. y_end (n_sets, nmax): the state at t_last (the last grid time
    reached; t_end on success), x_end and v_end its first two columns. seconds: wall-clock
    time of the row on its thread. t, x, v: (n_sets, n_grid) grids when keep_grid was set, else
    None (y_grid: (n_sets, nmax, n_grid) with the internal states).

    Flags (bool per row, in `fields` like the counters):

    - chattered: the velocity reversed its direction between at least CHATTER_FRACTION = 1/4
      of the monitor grid's intervals over t >= t_end/2 (n_rev_tail >= (n_grid - 1)/8): an
      oscillation at the grid's scale, which a motion the grid resolves does not have (a
      stick-slip cycle reverses twice a period). A run that chattered has a wrong velocity even
      where its mean motion looks right. Its value depends on n_grid.
    - forced: at least one step was taken at h_min although the error test failed there
      (nforced > 0): the tolerance was not met on those steps.

    `ok` is True where the row reached t_end (status 0), and nothing more: it says nothing of
    accuracy. A row can be ok and chattered, ok and forced, or ok and far from the exact
    solution (a fixed step beyond the stability bound that did not blow up, a loose tolerance).
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
    fields: dict[str, np.ndarray]
    y_end: np.ndarray
    threads: int
    t: np.ndarray | None = None
    x: np.ndarray | None = None
    v: np.ndarray | None = None
    y_grid: np.ndarray | None = None

    def __getattr__(self, name: str) -> np.ndarray:
        fields = self.__dict__.get("fields", {})
        if name in fields:
            return fields[name]
        raise AttributeError(name)

    @property
    def x_end(self) -> np.ndarray:
        return self.y_end[:, 0]

    @property
    def v_end(self) -> np.ndarray:
        return self.y_end[:, 1]

    def __len__(self) -> int:
        return int(self.status.size)

    @property
    def ok(self) -> np.ndarray:
        """True where the row reached t_end (status 0). Not a measure of accuracy: see the
        chattered and forced flags."""
        return self.status == STATUS_OK

    def message(self, i: int) -> str:
        """The library's message for row i's status."""
        return status_message(int(self.status[i]))


def _real(name: str, value: Any, accepted: str, allow_nan: bool = False) -> np.ndarray:
    """A scalar or 1-D array of finite reals (NaN too when allow_nan: "not given")."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: must be real numbers ({accepted})") from None
    if arr.ndim > 1:
        raise ValueError(f"{name}: must be a scalar or a 1-D sequence, got shape {arr.shape}")
    ok = np.isfinite(arr) | (np.isnan(arr) if allow_nan else False)
    if not np.all(ok):
        bad = int(np.flatnonzero(~ok.reshape(-1))[0])
        raise ValueError(f"{name}: must be finite ({accepted}); row {bad} is {arr.reshape(-1)[bad]!r}")
    return arr


def _codes(name: str, value: str | Sequence[str], accepted: tuple[str, ...]) -> np.ndarray:
    names = [value] if isinstance(value, str) else list(value)
    for v in names:
        _choice(name, v, accepted)
    return np.array(names, dtype=object)


def simulate_batch(scene: str | Sequence[str], law: str | Sequence[str], *,
                   method: str | Sequence[str], t_end: Any, x0: Any = 0.0, v0: Any = 0.0,
                   n_grid: int = 201, keep_grid: bool = False, threads: int = 1,
                   ignore_unused: bool = False, **kwargs: Any) -> Any:
    """Simulate many parameter sets in one Fortran call, `threads` OpenMP threads over the sets.

    scene, law, method, t_end, x0, v0 and every keyword argument (physical parameters of
    DEFAULTS, v_d = None meaning 1.5 v_s; controls of the methods, e.g. h [s] for fixed-step
    rows, rtol, atol, hmin, hmax, h0 [s] and max_steps for adaptive rows, allow_forced) are a
    scalar or a 1-D sequence, broadcast to one row per parameter set, with the meaning they have
    in `stickslip.simulate`. A control is passed only to the rows whose method reads it (so one
    hmin can serve the adaptive rows of a sweep that also has RK4 rows; h may be None or NaN on
    adaptive rows); a name no method reads is an error. Internal states of a law start at 0.

    Each row is integrated on the grid numpy.linspace(0, t_end, n_grid), so with
    keep_grid=True row i reproduces `simulate(..., n_out=n_grid)` exactly. The summary
    (BatchResult) is always returned; run-time failures are per-row status codes.

    Raises ValueError for bad input (the message names the parameter, and the row when the
    library finds it). Warns (UnusedParameterWarning) about a physical parameter that no row's
    scene or law reads, unless ignore_unused; and (UnstableStepWarning) when RK4 rows have h
    beyond RK4's linear stability bound (stickslip.core.rk4_stability_bound: at the creep speed
    on the slope, at the start on the belt; laws with internal states and the implicit methods
    are not checked). Each row says whether it chattered or took forced steps (BatchResult).

    This is the local batch: one call, all rows in memory. `stickslip.simulate_batch` (module
    stickslip.sweep) adds client, chunk_rows, out and progress for large sweeps in chunks, on a
    Dask cluster or streamed to disk (stickslip.distributed), with the same rows bit for bit.
    """
    threads = _count("threads", threads)
    n_grid = _count("n_grid", n_grid)
    unknown = sorted(set(kwargs) - set(_PARAM_ORDER) - set(CONTROLS))
    if unknown:
        _check_names({k: None for k in unknown}, _PARAM_ORDER + CONTROLS)

    if "chain" in np.atleast_1d(np.asarray(scene, dtype=object)).tolist():
        raise ValueError("scene: simulate_batch takes the one-body scenes (slope, belt); the chain's state "
                         "size varies with n_blocks: run each chain with stickslip.simulate")
    cols: dict[str, np.ndarray] = {
        "scene": _codes("scene", scene, SCENES),
        "law": _codes("law", law, LAWS),
        "method": _codes("method", method, METHODS),
        "t_end": _real("t_end", t_end, "> 0 [s]"),
        "x0": _real("x0", x0, "[m]"),
        "v0": _real("v0", v0, "[m/s]"),
    }
    pnames = [k for k in _PARAM_ORDER if k in kwargs and kwargs[k] is not None]
    for k in pnames:
        cols[k] = _real(k, kwargs[k], accepted_range(k))
    given_ctl = {k: v for k, v in kwargs.items() if k in CONTROLS}
    if "max_steps" in given_ctl:
        ms = np.asarray(given_ctl["max_steps"])
        if ms.dtype.kind not in "iu" or ms.ndim > 1 or np.any(ms < 1):
            raise ValueError(f"max_steps: must be integers >= 1, got {given_ctl['max_steps']!r}")
    for k, value in given_ctl.items():
        arr = np.asarray(np.nan if value is None else value)
        if arr.dtype == bool:
            arr = arr.astype(np.float64)
        cols["c:" + k] = _real(k, arr, "see stickslip.simulate; NaN: not given", allow_nan=True)

    try:
        shape = np.broadcast_shapes(*(c.shape for c in cols.values()))
    except ValueError:
        lengths = {k.removeprefix("c:"): c.size for k, c in cols.items() if c.ndim == 1 and c.size != 1}
        raise ValueError(f"per-set arguments of different lengths: {lengths}") from None
    n = int(np.prod(shape)) if shape else 1
    if n < 1:
        raise ValueError("no parameter sets (a per-set argument is empty)")
    rows = {k: np.broadcast_to(c, (n,)).copy() for k, c in cols.items()}

    # Controls: one column per control any row's method reads; NaN where a row's method does not.
    methods = sorted(set(rows["method"]))
    cnames = [c for c in CONTROLS if c not in ("rtol", "atol")
              and any(c in REGISTRY["method"][m]["controls"] for m in methods)]
    reads = {c: np.array([c in REGISTRY["method"][m]["controls"] for m in rows["method"]]) for c in CONTROLS}
    cvals = np.full((len(cnames), n), np.nan)
    for j, c in enumerate(cnames):
        if "c:" + c in rows:
            cvals[j] = np.where(reads[c], rows["c:" + c], np.nan)   # rows of other methods ignore it
        elif c in CONTROL_DEFAULTS:
            cvals[j] = np.where(reads[c], float(CONTROL_DEFAULTS[c]), np.nan)
        elif c == "max_steps":
            cvals[j] = np.where(reads[c], 1e8, np.nan)
    if "h" in cnames:
        hrow = cvals[cnames.index("h")]
        bad_h = reads["h"] & ~(np.isfinite(hrow) & (hrow > 0.0))
        if np.any(bad_h):
            i = int(np.flatnonzero(bad_h)[0])
            raise ValueError(f"h: required for method {rows['method'][i]!r} rows (finite, > 0 [s]); "
                             f"row {i} has {hrow[i]!r}")
    tol = {}
    for k in ("rtol", "atol"):
        tol[k] = rows["c:" + k] if "c:" + k in rows else np.full(n, float(CONTROL_DEFAULTS[k]))
        tol[k] = np.where(reads[k], tol[k], 1.0)   # unread: any valid value

    if not ignore_unused:
        read = {k for s, l in set(zip(rows["scene"], rows["law"]))
                for k in REGISTRY["law"][l]["params"] + REGISTRY["scene"][s]["params"]}
        unused = [k for k in pnames if k not in read]
        if unused:
            warnings.warn(f"{', '.join(unused)}: not read by any row's scene and law, ignored (range-checked "
                          "only; ignore_unused=True silences this)", UnusedParameterWarning, stacklevel=2)
    keep = bool(keep_grid)
    nstate = np.array([2 + REGISTRY["law"][l]["n_states"] for l in rows["law"]], dtype=np.int32)
    for k in STATE_COUNT_PARAMS:            # laws whose state count is a parameter (gms: n_elements)
        if k in rows:
            for i, (l, val) in enumerate(zip(rows["law"], rows[k])):
                if k in REGISTRY["law"][l]["params"] and np.isfinite(val):
                    nstate[i] = 2 + _states(str(l), ((k, float(val)),))[0]
    nmax = int(nstate.max())
    if keep and nmax * n * int(n_grid) > MAX_GRID_VALUES:
        raise ValueError(f"keep_grid: {n} rows x {n_grid} grid points exceed {MAX_GRID_VALUES // 2} "
                         "states; lower n_grid or drop keep_grid")
    y0 = np.zeros((nmax, n), order="F")
    y0[0], y0[1] = rows["x0"], rows["v0"]

    def codes(key: str, kind: str) -> np.ndarray:
        return np.array([REGISTRY[kind][s]["code"] for s in rows[key]], dtype=np.int32)

    pvals = np.asfortranarray(np.array([rows[k] for k in pnames], dtype=np.float64).reshape(len(pnames), n))
    istats, rstats, yend, y_grid, status = interruptible(lambda stop: _ext.run_batch(
        codes("scene", "scene"), codes("law", "law"), codes("method", "method"), ",".join(pnames), pvals,
        nstate, y0, rows["t_end"], tol["rtol"], tol["atol"], ",".join(cnames), np.asfortranarray(cvals),
        int(n_grid), int(n_grid) if keep else 0, int(threads), len(_BATCH_INT), len(_BATCH_REAL), stop))
    status = int(status)
    if status != STATUS_OK:
        raise ValueError(status_message(status))
    fields = {k: istats[j].astype(np.int64) for j, k in enumerate(_BATCH_INT)}
    fields.update({k: rstats[j].copy() for j, k in enumerate(_BATCH_REAL)})
    sstatus = fields.pop("status")
    fields.pop("n_written")
    fields["stiff"] = fields["stiff"].astype(bool)
    fields["chattered"] = fields["n_rev_tail"] >= CHATTER_FRACTION * (int(n_grid) - 1) / 2
    fields["forced"] = fields["nforced"] > 0
    bad = np.flatnonzero(sstatus <= _FIRST_INPUT_CODE)
    if bad.size:
        i = int(bad[0])
        raise ValueError(f"row {i} ({rows['scene'][i]}, {rows['law'][i]}, {rows['method'][i]}): "
                         f"{status_message(int(sstatus[i]))}")
    if "h" in cnames:                       # the rows are valid: their bounds can be computed
        _warn_unstable_rk4(rows, pnames, cvals[cnames.index("h")])

    resolved = {k: rows[k] for k in pnames}
    for k in _PARAM_ORDER:
        if k not in resolved:
            info = REGISTRY["param"][k]
            resolved[k] = (info["scale"] * resolved[info["default_of"]] if info["default_of"]
                           else np.full(n, info["default"]))
    h_col = cvals[cnames.index("h")] if "h" in cnames else np.full(n, np.nan)
    result = BatchResult(
        scene=rows["scene"].astype(str), law=rows["law"].astype(str), method=rows["method"].astype(str),
        params=resolved, t_end=rows["t_end"], h=np.where(np.isfinite(h_col), h_col, 0.0),
        rtol=tol["rtol"], atol=tol["atol"], status=sstatus, fields=fields,
        y_end=np.asarray(yend).T.copy(), threads=int(threads))
    if keep:
        y = np.asarray(y_grid)
        t = np.empty((n, int(n_grid)))
        for i in range(n):   # the grid the Fortran side used (numpy.linspace's numbers)
            t[i] = np.linspace(0.0, rows["t_end"][i], int(n_grid)) if n_grid > 1 else rows["t_end"][i]
        result.t, result.x, result.v = t, y[0].T.copy(), y[1].T.copy()
        result.y_grid = np.transpose(y, (2, 0, 1)).copy()
    return result


def _warn_unstable_rk4(rows: dict[str, np.ndarray], pnames: list[str], h: np.ndarray) -> None:
    """One UnstableStepWarning for the RK4 rows whose h lies beyond rk4_stability_bound."""
    beyond = []
    for i in np.flatnonzero(rows["method"] == "rk4"):
        params = tuple(sorted((k, float(rows[k][i])) for k in pnames))
        bound = rk4_stability_bound(str(rows["law"][i]), params, str(rows["scene"][i]), float(rows["v0"][i]))
        if bound is not None and h[i] > bound:
            beyond.append((int(i), float(h[i]), bound))
    if beyond:
        i, hi, bound = beyond[0]
        warnings.warn(f"{len(beyond)} RK4 row(s) with h beyond RK4's stability bound (row {i}: h = {hi:g} s > "
                      f"{bound:.3g} s, for {rows['law'][i]!r} on the {rows['scene'][i]}): they may chatter, "
                      "settle on a wrong state or blow up (see the chattered column)", UnstableStepWarning,
                      stacklevel=3)


__all__ = ["BatchResult", "simulate_batch", "MAX_GRID_VALUES", "CHATTER_FRACTION"]
