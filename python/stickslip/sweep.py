"""`stickslip.simulate_batch`: many parameter sets in one Fortran batch call
(`stickslip.batch`), or, for large sweeps, in chunks on a Dask cluster or streamed to disk
(`stickslip.distributed`).

This module sits above both, so that the dependencies run one way: sweep -> distributed ->
batch -> core (tests/project/test_imports.py checks that the package has no import cycle).
"""
from __future__ import annotations

import os
from typing import Any, Sequence

from . import batch
from .model import Model
from .distributed import SweepStore, run_chunked

__all__ = ["simulate_batch"]


def simulate_batch(scene: str | Sequence[str] | Model, law: str | Sequence[str] | dict[str, Any] | None = None, *,
                   method: str | Sequence[str], t_end: Any, x0: Any = 0.0, v0: Any = None,
                   n_grid: int = 201, keep_grid: bool = False, threads: int = 1,
                   ignore_unused: bool = False, client: Any = None, chunk_rows: int | None = None,
                   out: str | os.PathLike[str] | None = None, progress: bool = False,
                   **params: Any) -> batch.BatchResult | SweepStore:
    """Simulate many parameter sets: one row per set, OpenMP threads over the rows, in one
    Fortran call or, for large sweeps, in chunks (on a Dask cluster or streamed to disk).

    Every argument but `n_grid`, `keep_grid`, `threads`, `ignore_unused`, `client`,
    `chunk_rows`, `out` and `progress` is a scalar or a 1-D sequence, broadcast to one row per
    parameter set, with the meaning it has in `simulate`.

    A model (your own system) takes rows of parameter overrides instead:
    ``simulate_batch(model, {"contact 0.mu_k": [...], "body 1.v0": [...]}, method=...,
    t_end=..., **controls)`` (`stickslip.batch.simulate_model_batch`: the addresses, the
    summary, x and v per body), run by the same Fortran batch as a scene's rows; the model goes
    to Dask workers as its dict (TOML) form.

    Parameters
    ----------
    scene, law, method : str or sequence of str
        Names from SCENES, LAWS and METHODS, one for all rows or one per row; or a
        `stickslip.Model` and a dict of overrides ("kind index.field": values).
    t_end : float or sequence of float
        End of each run [s], > 0.
    x0, v0 : float or sequence of float, optional
        Initial position [m] and velocity [m/s]; v0 None or NaN: 0, or on the chain every block
        stuck on the belt (v0 = v_b). On the chain they apply to every block. Internal states
        of a law start at 0.
    n_grid : int
        Points of each row's output grid numpy.linspace(0, t_end, n_grid), >= 1 (default 201).
    keep_grid : bool
        Keep every row's grid (`BatchResult.y_grid`); row i then equals
        ``simulate(..., n_out=n_grid)`` bit for bit.
    threads : int
        OpenMP threads over the rows (>= 1); inside each chunk when chunked.
    ignore_unused : bool
        Do not warn about a physical parameter that no row's scene or law reads.
    client : dask.distributed.Client, optional
        Run the rows in chunks on this Dask cluster, one task per chunk; the scheduler reruns
        the chunks of a worker that dies.
    chunk_rows : int, optional
        Rows per chunk (>= 1). Default: about 4 chunks per worker on a cluster, 20 chunks
        locally, at most 10,000 rows.
    out : path, optional
        A directory: each finished chunk is written there (whole or absent) beside
        ``manifest.json``, rows are not kept in memory, and the call returns a `SweepStore`.
        The same call again resumes: chunks on disk are not recomputed.
    progress : bool
        Show a bar on stderr advancing per chunk (tqdm when installed, else plain lines).
    **params
        Physical parameters (DEFAULTS; v_d None meaning 1.5 v_s) and the methods' controls
        (CONTROLS: h [s] for fixed-step rows, rtol, atol, hmin, hmax, h0 [s], max_steps,
        allow_forced, ... for adaptive ones), each a scalar or a 1-D sequence. A control is
        passed only to the rows whose method reads it (h may be None or NaN on adaptive rows);
        a name no method reads is an error.

    Returns
    -------
    BatchResult or SweepStore
        One row per parameter set, in order: status, counters, final state, max |v|, velocity
        reversals (a chatter detector) and, with `keep_grid`, the grids; the same bit for bit
        however the rows were chunked, on how many threads or where they ran (every field but
        the wall-clock ``seconds``). A `SweepStore` when `out` is given. Run-time failures are
        per-row status codes, not exceptions.

    Raises
    ------
    ValueError
        Bad input, naming the parameter (and the row when the library finds it), before
        anything runs; a batch that would allocate more than
        ``stickslip.batch.MAX_BATCH_VALUES`` doubles.

    Warns
    -----
    UnusedParameterWarning
        A physical parameter that no row's scene or law reads (unless `ignore_unused`).
    UnstableStepWarning
        RK4 rows with h beyond RK4's linear stability bound.

    Examples
    --------
    >>> import stickslip as ss
    >>> b = ss.simulate_batch("belt", "stribeck", method="rk4", t_end=1.0, h=1e-3,
    ...                       k=[200.0, 300.0, 400.0])
    >>> b.status.tolist()
    [0, 0, 0]
    """
    local = client is None and chunk_rows is None and out is None and not progress
    if isinstance(scene, Model):
        if x0 != 0.0 or v0 is not None or ignore_unused:
            raise ValueError("x0, v0, ignore_unused: not for a model (override \"body i.x0\", "
                             "\"body i.v0\" instead)")
        if law is not None and not isinstance(law, dict):
            raise ValueError(f"overrides: must be a dict of \"kind index.field\" -> values (e.g. "
                             f"{{\"contact 0.mu_k\": [0.2, 0.3]}}), got {type(law).__name__}")
        # chunks take the model as its dict (TOML) form, as Dask workers and the sweep's
        # fingerprint need it
        args: dict[str, Any] = dict(model=scene if local else scene.to_dict(), overrides=dict(law or {}),
                                    method=method, t_end=t_end, n_grid=n_grid, keep_grid=keep_grid,
                                    threads=threads, **params)
    elif law is None:
        raise ValueError("law: required for a scene (a name of LAWS, or one per row); a model takes "
                         "its overrides there instead")
    else:
        # every argument of the local call, defaults included (the sweep's fingerprint names them)
        args = dict(scene=scene, law=law, method=method, t_end=t_end, x0=x0, v0=v0, n_grid=n_grid,
                    keep_grid=keep_grid, threads=threads, **params)
        if ignore_unused:
            args["ignore_unused"] = True     # the sweep's fingerprint as before that option
    if local:
        return batch.simulate_rows(args)
    return run_chunked(args, client=client, chunk_rows=chunk_rows, out=out, progress=progress)
