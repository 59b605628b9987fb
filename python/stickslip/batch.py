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
                   STATUS_OK, _states, _shown,
                   UnstableStepWarning, UnusedParameterWarning, _FIRST_INPUT_CODE, _PARAM_ORDER,
                   _check_names, _choice, _count, _n_blocks, accepted_range, interruptible, rk4_stability_bound,
                   status_message)

#: Names of the integer and real summary fields, in the wrapper's order.
_BATCH_INT, _BATCH_REAL = (tuple(x.split()) for x in _ext.batch_names().decode().strip().split("|"))

#: Most values (doubles) of kept grids: rows x grid points x state components.
MAX_GRID_VALUES = 20_000_000
#: Most values (doubles) a batch allocates in all: initial and final states, each thread's grid
#: of its row, and the kept grids (2 GB).
MAX_BATCH_VALUES = 250_000_000
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
    range over t >= t_end/2. The velocity monitored is the body's, block 1's on the chain.
    y_end (n_sets, nmax): the state at t_last (the last grid time reached; t_end on success),
    n_state (a field) components per row and NaN beyond them (rows of several state sizes:
    laws with internal states, chains of several n_blocks); x_end and v_end: the monitored
    body's position and velocity (columns 0 and `v_column`). seconds: wall-clock time of the row
    on its thread. t, x, v: (n_sets, n_grid) grids of the monitored body when keep_grid was
    set, else None (y_grid: (n_sets, nmax, n_grid), the whole state, NaN-padded like y_end).

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
    def v_column(self) -> np.ndarray:
        """Each row's column of the monitored body's velocity in y_end and y_grid: 1, or
        n_blocks on the chain (its state is x_1..x_N, v_1..v_N, then the internal states)."""
        nb = self.params["n_blocks"].astype(np.int64)
        return np.where(self.scene == "chain", nb, 1)

    @property
    def x_end(self) -> np.ndarray:
        """The monitored body's final position [m] (block 1 on the chain)."""
        return self.y_end[:, 0]

    @property
    def v_end(self) -> np.ndarray:
        """The monitored body's final velocity [m/s] (block 1 on the chain)."""
        return self.y_end[np.arange(len(self)), self.v_column]

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
        raise ValueError(f"{name}: must be finite ({accepted}); row {bad} is {_shown(arr.reshape(-1)[bad])}")
    return arr


def _codes(name: str, value: str | Sequence[str], accepted: tuple[str, ...]) -> np.ndarray:
    names = [value] if isinstance(value, str) else list(value)
    for v in names:
        _choice(name, v, accepted)
    return np.array(names, dtype=object)


def simulate_batch(scene: str | Sequence[str], law: str | Sequence[str], *,
                   method: str | Sequence[str], t_end: Any, x0: Any = 0.0, v0: Any = None,
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

    Chain rows (scene "chain") may have different n_blocks: a row's x0 and v0 apply to every
    block, and v0 not given (None or NaN) means every block stuck on the belt (v0 = v_b), as in
    `simulate`; elsewhere v0 not given is 0. The summary's velocity is block 1's (the block
    whose contact `relative_velocity` reads); y_end and y_grid hold each row's whole state
    (n_state columns: x_1..x_N, v_1..v_N, then the internal states block by block), padded with
    NaN to the widest row. A batch that would allocate more than MAX_BATCH_VALUES doubles
    (states, each thread's grid, kept grids) is refused before running.

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

    cols: dict[str, np.ndarray] = {
        "scene": _codes("scene", scene, SCENES),
        "law": _codes("law", law, LAWS),
        "method": _codes("method", method, METHODS),
        "t_end": _real("t_end", t_end, "> 0 [s]"),
        "x0": _real("x0", x0, "[m]"),
        "v0": _real("v0", np.nan if v0 is None else v0, "[m/s]; NaN: the scene's default", allow_nan=True),
    }
    pnames = [k for k in _PARAM_ORDER if k in kwargs and kwargs[k] is not None]
    for k in pnames:
        cols[k] = _real(k, kwargs[k], accepted_range(k))
    given_ctl = {k: v for k, v in kwargs.items() if k in CONTROLS}
    if "max_steps" in given_ctl:
        ms = np.asarray(given_ctl["max_steps"])
        if ms.dtype.kind not in "iu" or ms.ndim > 1 or np.any(ms < 1):
            raise ValueError(f"max_steps: must be integers >= 1, got {_shown(given_ctl['max_steps'])}")
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
                             f"row {i} has {_shown(hrow[i])}")
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
    nstate, n_blocks = _state_sizes(rows, cvals, cnames)
    nmax = int(nstate.max())
    _check_memory(nstate, n, int(n_grid), keep, threads)
    # the initial states: x0 and v0 for every block (v0 not given: 0, every block stuck on the
    # belt on the chain), the internal states 0
    chain = rows["scene"] == "chain"
    v_b = rows["v_b"] if "v_b" in rows else np.full(n, float(REGISTRY["param"]["v_b"]["default"]))
    v0_row = np.where(np.isnan(rows["v0"]), np.where(chain, v_b, 0.0), rows["v0"])
    y0 = np.zeros((nmax, n), order="F")
    for i in range(n):
        nb = n_blocks[i]
        y0[:nb, i], y0[nb:2 * nb, i] = rows["x0"][i], v0_row[i]

    def codes(key: str, kind: str) -> np.ndarray:
        return np.array([REGISTRY[kind][s]["code"] for s in rows[key]], dtype=np.int32)

    pvals = np.asfortranarray(np.array([rows[k] for k in pnames], dtype=np.float64).reshape(len(pnames), n))
    istats, rstats, yend, y_grid, status = interruptible(lambda stop: _ext.run_batch(
        codes("scene", "scene"), codes("law", "law"), codes("method", "method"), ",".join(pnames), pvals,
        nstate.astype(np.int32), y0, rows["t_end"], tol["rtol"], tol["atol"], ",".join(cnames), np.asfortranarray(cvals),
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
        _warn_unstable_rk4(rows, v0_row, pnames, cvals[cnames.index("h")])

    resolved = {k: rows[k] for k in pnames}
    for k in _PARAM_ORDER:
        if k not in resolved:
            info = REGISTRY["param"][k]
            resolved[k] = (info["scale"] * resolved[info["default_of"]] if info["default_of"]
                           else np.full(n, info["default"]))
    fields["n_state"] = nstate.astype(np.int64)
    resolved["n_blocks"] = n_blocks.astype(np.float64)
    padding = np.arange(nmax)[None, :] >= nstate[:, None]          # (n, nmax): beyond a row's state
    y_end = np.asarray(yend).T.copy()
    y_end[padding] = np.nan
    h_col = cvals[cnames.index("h")] if "h" in cnames else np.full(n, np.nan)
    result = BatchResult(
        scene=rows["scene"].astype(str), law=rows["law"].astype(str), method=rows["method"].astype(str),
        params=resolved, t_end=rows["t_end"], h=np.where(np.isfinite(h_col), h_col, 0.0),
        rtol=tol["rtol"], atol=tol["atol"], status=sstatus, fields=fields, y_end=y_end, threads=int(threads))
    if keep:
        y_grid_rows = np.transpose(np.asarray(y_grid), (2, 0, 1)).copy()   # (n, nmax, n_grid)
        y_grid_rows[padding] = np.nan
        t = np.empty((n, int(n_grid)))
        for i in range(n):   # the grid the Fortran side used (numpy.linspace's numbers)
            t[i] = np.linspace(0.0, rows["t_end"][i], int(n_grid)) if n_grid > 1 else rows["t_end"][i]
        rows_i = np.arange(n)
        result.t, result.y_grid = t, y_grid_rows
        result.x, result.v = y_grid_rows[rows_i, 0], y_grid_rows[rows_i, result.v_column]
    return result


def _state_sizes(rows: dict[str, np.ndarray], cvals: np.ndarray, cnames: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Each row's state size and number of blocks (1 off the chain), n_blocks checked as in
    `stickslip.simulate`."""
    n = rows["law"].size
    nstate = np.array([2 + REGISTRY["law"][l]["n_states"] for l in rows["law"]], dtype=np.int64)
    for k in STATE_COUNT_PARAMS:            # laws whose state count is a parameter (gms: n_elements)
        if k in rows:
            for i, (l, val) in enumerate(zip(rows["law"], rows[k])):
                if k in REGISTRY["law"][l]["params"] and np.isfinite(val):
                    nstate[i] = 2 + _states(str(l), ((k, float(val)),))[0]
    n_blocks = np.ones(n, dtype=np.int64)
    banded = cvals[cnames.index("banded")] if "banded" in cnames else np.full(n, np.nan)
    for i in np.flatnonzero(rows["scene"] == "chain"):
        given = {"n_blocks": float(rows["n_blocks"][i])} if "n_blocks" in rows else {}
        method = str(rows["method"][i])
        try:
            n_blocks[i] = _n_blocks(given, method, int(nstate[i]), banded[i] == 0.0)
        except ValueError as exc:
            raise ValueError(f"row {i} (chain, {rows['law'][i]}, {method}): {exc}") from None
    return nstate * n_blocks, n_blocks


def _check_memory(nstate: np.ndarray, n: int, n_grid: int, keep: bool, threads: int) -> None:
    """Refuse a batch whose arrays would exceed MAX_BATCH_VALUES doubles: the initial and final
    states (n rows of the widest state; the final ones in the library, its wrapper and here),
    each thread's grid of its row, and the kept grids."""
    nmax = int(nstate.max())
    values = 4 * nmax * n + min(threads, n) * nmax * n_grid + (nmax * n * n_grid if keep else 0)
    if keep and nmax * n * n_grid > MAX_GRID_VALUES:
        raise ValueError(f"keep_grid: {n} rows x {n_grid} grid points x {nmax} state components exceed "
                         f"{MAX_GRID_VALUES} values; lower n_grid or drop keep_grid")
    if values > MAX_BATCH_VALUES:
        raise ValueError(f"n_blocks: the batch needs {values:.3g} values ({8 * values / 1e9:.3g} GB: rows of up "
                         f"to {nmax} state components, {n} rows, {n_grid} grid points), more than "
                         f"{MAX_BATCH_VALUES:.3g}; lower n_blocks, the rows or n_grid, or split the sweep "
                         "(stickslip.simulate_batch with chunk_rows)")


def _warn_unstable_rk4(rows: dict[str, np.ndarray], v0: np.ndarray, pnames: list[str], h: np.ndarray) -> None:
    """One UnstableStepWarning for the RK4 rows whose h lies beyond rk4_stability_bound (the
    chain's rows are not checked)."""
    beyond = []
    for i in np.flatnonzero((rows["method"] == "rk4") & (rows["scene"] != "chain")):
        params = tuple(sorted((k, float(rows[k][i])) for k in pnames))
        bound = rk4_stability_bound(str(rows["law"][i]), params, str(rows["scene"][i]), float(v0[i]))
        if bound is not None and h[i] > bound:
            beyond.append((int(i), float(h[i]), bound))
    if beyond:
        i, hi, bound = beyond[0]
        warnings.warn(f"{len(beyond)} RK4 row(s) with h beyond RK4's stability bound (row {i}: h = {hi:g} s > "
                      f"{bound:.3g} s, for {rows['law'][i]!r} on the {rows['scene'][i]}): they may chatter, "
                      "settle on a wrong state or blow up (see the chattered column)", UnstableStepWarning,
                      stacklevel=3)


__all__ = ["BatchResult", "simulate_batch", "MAX_GRID_VALUES", "MAX_BATCH_VALUES", "CHATTER_FRACTION"]
