"""`stickslip.simulate_batch`: many parameter sets in one Fortran batch call
(`stickslip.batch`), or, for large sweeps, in chunks on a Dask cluster or streamed to disk
(`stickslip.distributed`).

This module sits above both, so that the dependencies run one way: sweep -> distributed ->
batch -> core (tests/test_imports.py checks that the package has no import cycle).
"""
from __future__ import annotations

import inspect
import os
from typing import Any

from . import batch
from .distributed import SweepStore, run_chunked

__all__ = ["simulate_batch"]


def simulate_batch(scene: Any, law: Any, *, client: Any = None, chunk_rows: int | None = None,
                   out: str | os.PathLike[str] | None = None, progress: bool = False,
                   **kwargs: Any) -> batch.BatchResult | SweepStore:
    """Simulate many parameter sets, in one Fortran batch call or in chunks.

    Parameters
    ----------
    scene, law
        A name or a 1-D sequence of names, one per row, as in `stickslip.batch.simulate_batch`.
    client : dask.distributed.Client, optional
        Run the rows in chunks on this Dask cluster, one task per chunk (`threads` OpenMP
        threads inside each); the scheduler reruns the chunks of a worker that dies.
    chunk_rows : int, optional
        Rows per chunk (>= 1). Default: about 4 chunks per worker on a cluster, 20 chunks
        locally, at most 10,000 rows.
    out : path, optional
        A directory: each finished chunk is written there (whole or absent) beside
        ``manifest.json``, rows are not kept in memory, and the call returns a `SweepStore`.
        The same call again resumes: chunks on disk are not recomputed.
    progress : bool
        Show a bar on stderr advancing per chunk (tqdm when installed, else plain lines).
    **kwargs
        method, t_end, x0, v0, n_grid, keep_grid, threads, ignore_unused, the physical
        parameters and the controls: as in `stickslip.batch.simulate_batch`, each a scalar or a
        1-D sequence.

    Returns
    -------
    BatchResult or SweepStore
        One row per parameter set, in order, the same bit for bit however the rows were
        chunked or where they ran (every field but the wall-clock ``seconds``); a `SweepStore`
        when `out` is given.

    Raises
    ------
    ValueError
        Bad input, naming the parameter (and the row when the library finds it), before
        anything runs; ``chunk_rows`` that is not an integer >= 1.
    """
    if client is None and chunk_rows is None and out is None and not progress:
        return batch.simulate_batch(scene, law, **kwargs)
    # every argument of the local call, defaults included (the sweep's fingerprint names them)
    bound = inspect.signature(batch.simulate_batch).bind(scene, law, **kwargs)
    bound.apply_defaults()
    args = {k: v for k, v in bound.arguments.items() if k != "kwargs"}
    args.update(bound.arguments.get("kwargs", {}))
    if not args.get("ignore_unused"):
        args.pop("ignore_unused", None)       # the sweep's fingerprint as before that option
    return run_chunked(args, client=client, chunk_rows=chunk_rows, out=out, progress=progress)
