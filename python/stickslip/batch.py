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

import re
import warnings
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np

from . import _stickslip as _ext
from .core import CHATTER_FRACTION as _CHATTER_FRACTION
from .core import (CONTROL_DEFAULTS, CONTROLS, LAWS, METHODS, REGISTRY, SCENES, STATE_COUNT_PARAMS,
                   STATUS_OK, _states, _shown, RegularisedLawWarning, regularised_note,
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
#: grid's intervals over t >= t_end/2 (BatchResult); stickslip.core's, which the consistency
#: check reads too.
CHATTER_FRACTION = _CHATTER_FRACTION


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

    Rows of a model (`simulate_model_batch`: scene "model", law its contacts' laws joined by
    "+", params its overrides by address and n_blocks its number of bodies) monitor body 0, and
    their x and v hold every body: shape (n_sets, n_bodies, n_grid).

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
    #: What the rows' warnings and checks said, each sentence once with the rows it concerns
    #: ("rows 0, 2: ..."): the law a method computes (RegularisedLawWarning), and for a model's
    #: rows the failures of their consistency check (docs/guide/results.md).
    notes: list[str] = field(default_factory=list)

    def __getattr__(self, name: str) -> np.ndarray:
        fields = self.__dict__.get("fields", {})
        if name in fields:
            return fields[name]
        raise AttributeError(name)

    @property
    def v_column(self) -> np.ndarray:
        """Each row's column of the first body's velocity in y_end and y_grid: 1, or n_blocks
        on the chain and on a model (params["n_blocks"]: its bodies; the state is x_1..x_N,
        v_1..v_N, then the internal states)."""
        nb = self.params["n_blocks"].astype(np.int64)
        return np.where((self.scene == "chain") | (self.scene == "model"), nb, 1)

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


def _broadcast_rows(cols: dict[str, np.ndarray]) -> tuple[dict[str, np.ndarray], int]:
    """The per-set columns broadcast to one entry per row, and the number of rows; ValueError
    when their lengths differ or one is empty (keys "c:name", "o:name" are named "name")."""
    try:
        shape = np.broadcast_shapes(*(c.shape for c in cols.values()))
    except ValueError:
        lengths = {k.removeprefix("c:").removeprefix("o:"): c.size for k, c in cols.items()
                   if c.ndim == 1 and c.size != 1}
        raise ValueError(f"per-set arguments of different lengths: {lengths}") from None
    n = int(np.prod(shape)) if shape else 1
    if n < 1:
        raise ValueError("no parameter sets (a per-set argument is empty)")
    return {k: np.broadcast_to(c, (n,)).copy() for k, c in cols.items()}, n


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

    rows, n = _broadcast_rows(cols)

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
        rtol=tol["rtol"], atol=tol["atol"], status=sstatus, fields=fields, y_end=y_end, threads=int(threads),
        notes=_regularised_rows(rows, resolved))
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


def _grouped_notes(per_row: Sequence[Sequence[str]]) -> list[str]:
    """Each distinct sentence of the rows' notes once, prefixed with the rows that have it
    ("rows 0, 3 (2 of 5): ...", the first 10 rows named)."""
    rows_of: dict[str, list[int]] = {}
    for i, notes in enumerate(per_row):
        for note in notes:
            rows_of.setdefault(note, []).append(i)
    out = []
    for note, rows in rows_of.items():
        named = ", ".join(str(i) for i in rows[:10]) + (", ..." if len(rows) > 10 else "")
        out.append(f"row{'s' if len(rows) > 1 else ''} {named} ({len(rows)} of {len(per_row)}): {note}")
    return out


def _regularised_rows(rows: Mapping[str, np.ndarray], resolved: Mapping[str, np.ndarray]) -> list[str]:
    """The batch's notes on the law each row's method computes (`regularised_note`), grouped
    by rows, each warned once (RegularisedLawWarning)."""
    per_row = []
    for i, (law, method) in enumerate(zip(rows["law"], rows["method"])):
        params = {k: float(resolved[k][i]) for k in ("mu_s", "mu_k", "v_s", "v_eps") if k in resolved}
        note = regularised_note(str(law), params, str(method))
        per_row.append([] if note is None else [note])
    notes = _grouped_notes(per_row)
    for note in notes:
        warnings.warn(note, RegularisedLawWarning, stacklevel=3)
    return notes


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




# ------------------------------------------------------------------------------------------------
# Batches of a model (your own system): rows of parameter overrides
# ------------------------------------------------------------------------------------------------
#: The fields an override may address, per kind of element ("contact" also takes the
#: parameters of the contact's law). Signals (a force, a normal force, a surface velocity)
#: are replaced by a constant.
OVERRIDE_FIELDS: dict[str, tuple[str, ...]] = {
    "body": ("mass", "x0", "v0"),
    "spring": ("k", "rest_length"),
    "damper": ("c",),
    "force": ("force",),
    "contact": ("normal_force", "surface_velocity"),
}
_SECTIONS = {"body": "bodies", "spring": "springs", "damper": "dampers", "force": "forces", "contact": "contacts"}


def parse_override(model: Any, address: str) -> tuple[str, int, str]:
    """('kind', index, 'field') of an override address "kind index.field" on `model`
    (e.g. "contact 0.mu_k", "body 1.v0", "spring 0.k"), else ValueError naming it."""
    m = re.fullmatch(r"\s*([a-z]+)\s+(\d+)\s*\.\s*([A-Za-z_][A-Za-z0-9_]*)\s*", address) \
        if isinstance(address, str) else None
    if m is None or m.group(1) not in OVERRIDE_FIELDS:
        raise ValueError(f"overrides: {address!r} is not an address \"kind index.field\" (kinds: "
                         f"{', '.join(OVERRIDE_FIELDS)}; e.g. \"contact 0.mu_k\", \"body 1.v0\")")
    kind, index, name = m.group(1), int(m.group(2)), m.group(3)
    count = len(getattr(model, _SECTIONS[kind]))
    if index >= count:
        raise ValueError(f"overrides: {address!r}: the model has "
                         + (f"{kind}s 0 .. {count - 1}" if count else f"no {kind}"))
    accepted = OVERRIDE_FIELDS[kind]
    where = f"{kind} {index}"
    if kind == "contact":
        accepted = accepted + tuple(REGISTRY["law"][model.contacts[index].law]["params"])
        where = model.contact_label(index)
    if name not in accepted:
        raise ValueError(f"overrides: {address!r}: {where} has no field {name!r} (accepted: "
                         f"{', '.join(accepted)})")
    return kind, index, name


def _overridden(base: dict[str, Any], targets: list[tuple[str, int, str]], values: list[float]) -> dict[str, Any]:
    """The model's dict (Model.to_dict) with the fields of `targets` set to `values`: the
    entries overridden copied, the rest shared with `base` (which is not changed)."""
    data = dict(base)
    for (kind, index, name), value in zip(targets, values):
        if data[kind] is base[kind]:
            data[kind] = list(base[kind])
        entry = data[kind][index] = dict(data[kind][index])
        if kind == "contact" and name not in OVERRIDE_FIELDS["contact"]:
            entry["params"] = {**entry.get("params", {}), name: value}
        else:
            entry[name] = value
    return data


#: The arrays of a model (Model.arrays) in the order of the wrapper's offsets (run_model_batch).
_MODEL_ARRAYS = ("bodies", "springs", "dampers", "forces", "contacts", "con_ptr", "pvals", "signals", "sig_start",
                 "tables", "drives")
#: Most values (doubles) of the grids and event rows a model batch holds at once for its rows'
#: consistency check (32 MB): the rows run in chunks of that size, one Fortran call each.
MODEL_CHUNK_VALUES = 4_000_000


def _model_rows(model: Any, addresses: list[str], targets: list[tuple[str, int, str]],
                rows: Mapping[str, np.ndarray], n: int, controls: Sequence[str]) -> list[dict[str, Any]]:
    """Each row's model (`model` with the row's overrides) and what `simulate_model` would pass
    the library for it: its arrays, initial state, controls and tolerances, and its notes; the
    warnings of that call issued. ValueError naming the row for a bad row, before anything runs."""
    from .core import _end_time, _physical, friction_coefficient, \
        model_notes, _warn_model_steps
    from .model import Model, check_method, event_room, initial_state, run_controls
    base = model.to_dict()
    out = []
    for i in range(n):
        meth = str(rows["method"][i])
        kw: dict[str, Any] = {}
        for k in controls:
            val = float(rows["c:" + k][i])
            if k in REGISTRY["method"][meth]["controls"] and not np.isnan(val):
                kw[k] = int(val) if k == "max_steps" else val
        try:
            m_i = Model.from_dict(_overridden(base, targets, [float(rows["o:" + a][i]) for a in addresses])) \
                if targets else model
            for j, c in enumerate(m_i.contacts):
                try:
                    friction_coefficient(c.law, 0.0, **_physical(dict(c.params)))
                except ValueError as exc:
                    raise ValueError(f"{m_i.contact_label(j)}: {exc}") from None
            m_i.n_states()
            check_method(m_i, meth)
            notes = model_notes(m_i, meth, stacklevel=5)
            t_end = _end_time(float(rows["t_end"][i]))
            _warn_model_steps(m_i, meth, t_end, kw, stacklevel=6)
            ctl, rtol, atol = run_controls(m_i, meth, {k: v for k, v in kw.items() if k != "max_steps"},
                                           kw.get("max_steps"))
            arrays = m_i.arrays()
        except ValueError as exc:
            raise ValueError(f"row {i} ({meth}): {exc}") from None
        out.append(dict(model=m_i, arrays=arrays, y0=initial_state(m_i, arrays), ctl=ctl, rtol=rtol, atol=atol,
                        room=event_room(meth, ctl), notes=notes, given=kw))
    return out


def _run_model_rows(prep: list[dict[str, Any]], method: np.ndarray, t_end: np.ndarray, n_grid: int,
                    threads: int, stop: np.ndarray) -> tuple[Any, ...]:
    """One call of the Fortran model batch (run_model_batch) on the rows `prep`: their arrays
    concatenated with their offsets, controls by name (NaN where a row has none). Returns its
    outputs (istats, rstats, yend, y_grid: always kept, for the check; elem, status) and the
    rows' event buffer."""
    n = len(prep)
    offsets = np.ones((len(_MODEL_ARRAYS), n + 1), dtype=np.int32, order="F")
    cat = {}
    for k, name in enumerate(_MODEL_ARRAYS):
        parts = [p["arrays"][name] for p in prep]
        offsets[k, 1:] = 1 + np.cumsum([a.shape[-1] for a in parts])
        cat[name] = np.asfortranarray(np.concatenate(parts, axis=-1))
    pkeys = " ".join(p["arrays"]["pkeys"] for p in prep if p["arrays"]["pkeys"])
    nstate = np.array([p["y0"].size for p in prep], dtype=np.int32)
    y0 = np.zeros((int(nstate.max()), n), order="F")
    for i, p in enumerate(prep):
        y0[:nstate[i], i] = p["y0"]
    cnames = list(dict.fromkeys(k for p in prep for k in p["ctl"]))
    cvals = np.full((len(cnames), n), np.nan, order="F")
    for i, p in enumerate(prep):
        for j, k in enumerate(cnames):
            cvals[j, i] = p["ctl"].get(k, np.nan)
    tol = {k: np.array([float(np.max(p[k])) for p in prep]) for k in ("rtol", "atol")}
    events = np.zeros((4, max(p["room"] for p in prep), n), order="F")
    codes = np.array([REGISTRY["method"][m]["code"] for m in method], dtype=np.int32)
    slip_size = np.array([int(p["model"].slip_error_size) for p in prep], dtype=np.int32)
    out = _ext.run_model_batch(codes, *(cat[k] for k in _MODEL_ARRAYS[:6]), pkeys,
                               *(cat[k] for k in _MODEL_ARRAYS[6:]), offsets, slip_size, nstate, y0, t_end,
                               tol["rtol"], tol["atol"], ",".join(cnames), cvals, int(n_grid), int(n_grid),
                               int(threads), events, len(_BATCH_INT), len(_BATCH_REAL), stop)
    return (*out, events)


def simulate_model_batch(model: Any, overrides: Mapping[str, Any] | None = None, *, method: Any,
                         t_end: Any, n_grid: int = 201, keep_grid: bool = False, threads: int = 1,
                         **controls: Any) -> BatchResult:
    """Simulate a model (`stickslip.Model`) under rows of parameter overrides.

    `overrides` maps addresses "kind index.field" (parse_override: "body 1.v0", "spring 0.k",
    "damper 0.c", "force 0.force", "contact 0.mu_k", "contact 1.normal_force"; kinds and fields
    in OVERRIDE_FIELDS, a contact also taking its law's parameters) to a number or a 1-D
    sequence of numbers; `method`, `t_end` and the controls (h, rtol, atol, ..., max_steps; a
    control is passed only to the rows whose method reads it, NaN or None: not given) are a
    scalar or a 1-D sequence too, all broadcast to one row each. Row i runs the model with its
    overrides (a force, normal force or surface velocity becomes that constant) with what
    `stickslip.simulate(model_i, method=..., t_end=..., n_out=n_grid, ...)` passes the library,
    so its grid equals that run's bit for bit. The rows run in the Fortran batch of the scene
    rows (`simulate_batch`: the same loop, `threads` OpenMP threads, the same summary), in
    chunks of at most MODEL_CHUNK_VALUES grid and event values, whose grids the consistency
    check reads.

    Every row's model, law parameters and controls are checked before any row runs (a
    ValueError naming the row and the element), with the warnings `simulate` gives for it;
    run-time failures are per-row status codes. A row that reached t_end gets `simulate`'s
    consistency check (its failures in `notes`, warned). The summary is that of the scene
    batches with body 0 monitored: x_end, v_end, v_max, n_rev are body 0's, and n_flip,
    vrel_min_tail, vrel_max_tail count and bound body 0's velocity (relative to the ground; a
    model has no single relative velocity). With keep_grid: x and v are (n_sets, n_bodies,
    n_grid), one row per body, and y_grid the whole state.
    """
    from .core import _FIRST_INPUT_CODE as first_input, _events
    from .energy import check_result
    from .model import Model, _input_error
    if not isinstance(model, Model):
        raise ValueError(f"model: must be a stickslip.Model, got {type(model).__name__}")
    threads = _count("threads", threads)
    n_grid = _count("n_grid", n_grid)
    overrides = dict(overrides or {})
    targets = [parse_override(model, a) for a in overrides]
    if len(set(targets)) < len(targets):
        raise ValueError("overrides: the same field is given twice (" + ", ".join(overrides) + ")")
    cols: dict[str, np.ndarray] = {"method": _codes("method", method, METHODS),
                                   "t_end": _real("t_end", t_end, "> 0 [s]")}
    for a, value in overrides.items():
        cols["o:" + a] = _real(f"overrides[{a!r}]", value, "a number per row")
    unknown = sorted(set(controls) - set(CONTROLS))
    if unknown:
        _check_names({k: None for k in unknown}, CONTROLS)
    for k, value in controls.items():
        arr = np.asarray(np.nan if value is None else value)
        cols["c:" + k] = _real(k, arr.astype(np.float64) if arr.dtype == bool else arr,
                               "see stickslip.simulate; NaN: not given", allow_nan=True)
    rows, n = _broadcast_rows(cols)
    methods = sorted(set(rows["method"]))
    for k in controls:
        if not any(k in REGISTRY["method"][m]["controls"] for m in methods):
            raise ValueError(f"{k}: not a control of any row's method ({', '.join(methods)})")

    prep = _model_rows(model, list(overrides), targets, rows, n, list(controls))
    nstate = np.array([p["y0"].size for p in prep], dtype=np.int64)
    nmax = int(nstate.max())
    nb = model.n_bodies
    _check_memory(nstate, n, int(n_grid), bool(keep_grid), threads)
    laws = "+".join(dict.fromkeys(c.law for c in model.contacts))
    int_names = [k for k in _BATCH_INT if k not in ("status", "n_written")]
    fields: dict[str, Any] = {k: np.zeros(n, dtype=np.int64) for k in int_names}
    fields.update({k: np.zeros(n) for k in _BATCH_REAL})
    status = np.zeros(n, dtype=np.int64)
    y_end = np.full((n, nmax), np.nan)
    y_grid = np.full((n, nmax, int(n_grid)), np.nan) if keep_grid else None
    notes: list[list[str]] = [[] for _ in range(n)]
    per_row = nmax * int(n_grid) + 4 * max(p["room"] for p in prep)
    chunk = max(1, MODEL_CHUNK_VALUES // per_row)
    for start in range(0, n, chunk):
        part = slice(start, min(n, start + chunk))
        istats, rstats, yend, grid, elem, call_status, events = interruptible(lambda stop: _run_model_rows(
            prep[part], rows["method"][part], rows["t_end"][part], int(n_grid), threads, stop))
        if int(call_status) != STATUS_OK:
            raise ValueError(status_message(int(call_status)))
        bad = np.flatnonzero(istats[_BATCH_INT.index("status")] <= first_input)
        if bad.size:
            j = int(bad[0])
            i = start + j
            err = _input_error(prep[i]["model"], int(istats[_BATCH_INT.index("status"), j]), int(elem[0, j]),
                               int(elem[1, j]))
            raise ValueError(f"row {i} ({rows['method'][i]}): {err}")
        for j in range(part.stop - start):
            i = start + j
            st = {k: istats[m, j] for m, k in enumerate(_BATCH_INT)}
            st.update({k: rstats[m, j] for m, k in enumerate(_BATCH_REAL)})
            status[i] = int(st["status"])
            for k in int_names:
                fields[k][i] = int(st[k])
            for k in _BATCH_REAL:
                fields[k][i] = st[k]
            y_end[i, :nstate[i]] = yend[:nstate[i], j]
            written = int(st["n_written"]) if status[i] != STATUS_OK else int(n_grid)
            y_i = grid[:nstate[i], :written, j]
            if y_grid is not None:
                y_grid[i, :nstate[i], :written] = y_i
            if status[i] != STATUS_OK:
                continue
            t_i = np.linspace(0.0, rows["t_end"][i], int(n_grid)) if n_grid > 1 else rows["t_end"][i:i + 1]
            run = _Row(t=t_i, x=y_i[:nb], v=y_i[nb:2 * nb], law=laws, stats={"nstep": int(st["nstep"]), "notes": []},
                       events=_events(events[:, :, j], int(st["nevents"])) if prep[i]["room"] else None)
            p = prep[i]
            check_result(run, str(rows["method"][i]), {**p["ctl"], "rtol": p["rtol"], "atol": p["atol"]},
                         p["model"], p["arrays"], stacklevel=4)
            notes[i] = p["notes"] + run.stats["notes"]
    fields["stiff"] = fields["stiff"].astype(bool)
    fields["chattered"] = fields["n_rev_tail"] >= CHATTER_FRACTION * (int(n_grid) - 1) / 2
    fields["forced"] = fields["nforced"] > 0
    fields["n_state"] = nstate
    params = {a: rows["o:" + a] for a in overrides}
    params["n_blocks"] = np.full(n, float(nb))
    h = np.array([p["given"].get("h", 0.0) for p in prep])
    tol = {k: np.array([p["given"].get(k, float(CONTROL_DEFAULTS[k])) if k in REGISTRY["method"][m]["controls"]
                        else 1.0 for p, m in zip(prep, rows["method"])]) for k in ("rtol", "atol")}
    result = BatchResult(
        scene=np.full(n, "model"), law=np.full(n, laws), method=rows["method"].astype(str), params=params,
        t_end=rows["t_end"], h=h, rtol=tol["rtol"], atol=tol["atol"], status=status, fields=fields,
        y_end=y_end, threads=int(threads), notes=_grouped_notes(notes))
    if y_grid is not None:
        result.t = np.array([np.linspace(0.0, te, int(n_grid)) if n_grid > 1 else np.array([te])
                             for te in rows["t_end"]])
        result.y_grid = y_grid
        result.x, result.v = y_grid[:, :nb], y_grid[:, nb:2 * nb]
    return result


def simulate_rows(args: Mapping[str, Any]) -> BatchResult:
    """The local batch of a sweep's arguments (what `stickslip.simulate_batch` and each chunk of
    `stickslip.distributed` run): a model's rows when args has "model" (a Model or its dict,
    Model.to_dict, with "overrides": `simulate_model_batch`), else a scene's (`simulate_batch`)."""
    if "model" not in args:
        return simulate_batch(**args)
    from .model import Model
    rest = {k: v for k, v in args.items() if k != "model"}
    model = args["model"]
    return simulate_model_batch(model if isinstance(model, Model) else Model.from_dict(model), **rest)


@dataclass
class _Row:
    """A model row's run as the consistency check (stickslip.energy.check_result) reads it."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    law: str
    stats: dict[str, Any]
    events: np.ndarray | None
    scene: str = "model"


__all__ = ["BatchResult", "simulate_batch", "simulate_model_batch", "simulate_rows", "parse_override", "OVERRIDE_FIELDS",
           "MAX_GRID_VALUES", "MAX_BATCH_VALUES", "MODEL_CHUNK_VALUES", "CHATTER_FRACTION"]
