"""Sweeps in chunks: on a Dask cluster, streamed to disk, with a progress bar.

`stickslip.simulate_batch(..., client=, chunk_rows=, out=, progress=)` comes here when any of
those is given. The rows (parameter sets) are cut into consecutive chunks of `chunk_rows`;
each chunk is one call of the local `simulate_batch` (one Fortran batch call, `threads`
OpenMP threads inside it), so a row's numbers do not depend on the chunking nor on where it
ran: the result is bit-identical to one local call (except the wall-clock `seconds`).

- client: a `dask.distributed.Client`. Each chunk is one task; the scheduler re-runs the
  chunks of a worker that dies, so a sweep survives a lost worker. Dask is imported only on
  this path (`pip install stickslip[dask]`).
- out: a directory. Each finished chunk is written as `chunk-NNNNNN.npz` (to a temporary
  file, then renamed: whole or absent) beside `manifest.json`, which names the sweep (a hash
  of its arguments) and its chunking. Rows are not kept in memory: the call returns a
  `SweepStore`, whose `load()` concatenates them (or `chunks()` reads them one at a time).
  Calling again with the same arguments and `out` resumes: chunks on disk are not recomputed.
- progress: a bar on stderr advancing per chunk (tqdm when installed, else plain lines).

Default chunk_rows (`default_chunk_rows`): about 4 chunks per worker (Dask) so that a slow
chunk does not leave the other workers idle, at most MAX_CHUNK_ROWS rows; locally 20 chunks
(for the progress bar and the files) of at most MAX_CHUNK_ROWS rows. A chunk costs the cluster
a few milliseconds (docs/guide/dask.md), so chunks should hold at least
a second of work.
"""
from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import re
import sys
from pathlib import Path
from typing import Any, Iterator

import numpy as np

from .batch import BatchResult, simulate_rows
from .outputs import atomic_write

#: Largest default chunk [rows].
MAX_CHUNK_ROWS = 10_000
#: Chunks per Dask worker by default (load balance against per-chunk overhead).
CHUNKS_PER_WORKER = 4
#: Chunks of a local chunked run by default.
LOCAL_CHUNKS = 20
MANIFEST = "manifest.json"
_FORMAT = "stickslip-sweep-1"


# --------------------------------------------------------------------------------------------
# Progress
# --------------------------------------------------------------------------------------------
class ProgressBar:
    """A progress bar on stderr: tqdm when it is installed, else one plain line per update
    ("desc: k/total"). `update(n)` advances it; use as a context manager."""

    def __init__(self, total: int, desc: str = "", unit: str = "chunk", enabled: bool = True):
        self.total, self.desc, self.done, self.enabled = int(total), desc, 0, enabled
        self._bar = None
        if enabled:
            try:
                from tqdm import tqdm
            except ImportError:
                tqdm = None
            if tqdm is not None:
                self._bar = tqdm(total=self.total, desc=desc, unit=unit, file=sys.stderr)

    def update(self, n: int = 1, note: str = "") -> None:
        """Advance by n; `note` (what just finished) is shown beside the count."""
        self.done += n
        if self._bar is not None:
            if note:
                self._bar.set_postfix_str(note, refresh=False)
            self._bar.update(n)
        elif self.enabled:
            print(f"{self.desc}: {self.done}/{self.total}" + (f" {note}" if note else ""),
                  file=sys.stderr, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> "ProgressBar":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


# --------------------------------------------------------------------------------------------
# Rows and chunks
# --------------------------------------------------------------------------------------------
def _is_sequence(value: Any) -> bool:
    return not isinstance(value, (str, bytes)) and value is not None and np.ndim(value) == 1


def _per_set(args: dict[str, Any]) -> Iterator[Any]:
    """The per-set arguments' values, those of a model's overrides (a dict) among them."""
    for k, v in args.items():
        if k == "overrides" and isinstance(v, dict):
            yield from v.values()
        else:
            yield v


def count_rows(args: dict[str, Any]) -> int | None:
    """Rows of a sweep (per-set arguments broadcast), or None when their lengths differ or
    one is empty (the local simulate_batch then raises the usual ValueError)."""
    lengths = {len(v) for v in _per_set(args) if _is_sequence(v)} - {1}
    if len(lengths) > 1 or 0 in lengths:
        return None
    return lengths.pop() if lengths else 1


def _slice(args: dict[str, Any], start: int, stop: int) -> dict[str, Any]:
    """The arguments of rows start .. stop-1 (length-1 sequences and scalars broadcast)."""
    out = {}
    for k, v in args.items():
        if k == "overrides" and isinstance(v, dict):
            v = _slice(v, start, stop)
        elif _is_sequence(v) and len(v) != 1:
            v = v[start:stop] if hasattr(v, "__getitem__") else list(v)[start:stop]
        out[k] = v
    return out


def default_chunk_rows(n_rows: int, workers: int | None = None) -> int:
    """The default chunk size: CHUNKS_PER_WORKER chunks per Dask worker (workers given) or
    LOCAL_CHUNKS chunks locally, at most MAX_CHUNK_ROWS rows."""
    parts = CHUNKS_PER_WORKER * max(1, workers) if workers else LOCAL_CHUNKS
    return max(1, min(MAX_CHUNK_ROWS, math.ceil(n_rows / parts)))


def run_chunk(args: dict[str, Any], start: int) -> BatchResult:
    """One chunk through the local simulate_batch (what a Dask task runs). A ValueError names
    rows by their number in the whole sweep (start + the row in the chunk). A model's rows
    (args["model"]: the model as Model.to_dict) or a scene's: `stickslip.batch.simulate_rows`."""
    try:
        return simulate_rows(args)
    except ValueError as exc:
        msg = re.sub(r"\brow (\d+)", lambda m: f"row {int(m.group(1)) + start}", str(exc))
        raise ValueError(msg) from None


def concat(parts: list[BatchResult]) -> BatchResult:
    """Rows of several results in order; y_end and y_grid padded with NaN to the widest
    state (as one batch call pads them)."""
    first = parts[0]
    nmax = max(p.y_end.shape[1] for p in parts)

    def pad(a: np.ndarray) -> np.ndarray:
        width = [(0, 0)] * a.ndim
        width[1] = (0, nmax - a.shape[1])
        return np.pad(a, width, constant_values=np.nan)

    def cat(get: Any) -> np.ndarray:
        return np.concatenate([get(p) for p in parts])

    out = BatchResult(
        scene=cat(lambda p: p.scene), law=cat(lambda p: p.law), method=cat(lambda p: p.method),
        params={k: cat(lambda p, k=k: p.params[k]) for k in first.params},
        t_end=cat(lambda p: p.t_end), h=cat(lambda p: p.h), rtol=cat(lambda p: p.rtol),
        atol=cat(lambda p: p.atol), status=cat(lambda p: p.status),
        fields={k: cat(lambda p, k=k: p.fields[k]) for k in first.fields},
        y_end=cat(lambda p: pad(p.y_end)), threads=first.threads)
    if first.t is not None:
        out.t, out.x, out.v = cat(lambda p: p.t), cat(lambda p: p.x), cat(lambda p: p.v)
        out.y_grid = cat(lambda p: pad(p.y_grid))
    return out


# --------------------------------------------------------------------------------------------
# Chunks on disk
# --------------------------------------------------------------------------------------------
_ARRAYS = ("scene", "law", "method", "t_end", "h", "rtol", "atol", "status", "y_end",
           "t", "x", "v", "y_grid")


def save_chunk(path: Path, result: BatchResult) -> Path:
    """Write a chunk's rows as .npz: to a temporary file beside `path`, then rename."""
    arrays = {k: getattr(result, k) for k in _ARRAYS if getattr(result, k) is not None}
    arrays.update({f"p:{k}": v for k, v in result.params.items()})
    arrays.update({f"f:{k}": v for k, v in result.fields.items()})
    arrays["threads"] = np.array(result.threads)
    atomic_write(path, lambda f: np.savez(f, **arrays), binary=True)
    return path


def load_chunk(path: Path) -> BatchResult:
    """A chunk written by save_chunk."""
    with np.load(path, allow_pickle=False) as z:
        data = {k: z[k] for k in z.files}
    kw = {k: data[k] for k in _ARRAYS if k in data}
    return BatchResult(params={k[2:]: v for k, v in data.items() if k.startswith("p:")},
                       fields={k[2:]: v for k, v in data.items() if k.startswith("f:")},
                       threads=int(data["threads"]), **kw)


def fingerprint(args: dict[str, Any]) -> str:
    """A hash of a sweep's arguments (what its rows are), to recognise it on resume."""
    def plain(v: Any) -> Any:
        return v if isinstance(v, str) or v is None else np.asarray(v).tolist()
    text = json.dumps({k: plain(v) for k, v in sorted(args.items()) if k != "threads"},
                      default=repr, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


class SweepStore:
    """A sweep on disk (simulate_batch(out=...)): `manifest.json` and one .npz per chunk."""

    def __init__(self, path: str | os.PathLike[str]):
        self.path = Path(path)
        self.manifest = json.loads((self.path / MANIFEST).read_text())
        self.n_rows: int = self.manifest["n_rows"]
        self.chunk_rows: int = self.manifest["chunk_rows"]
        self.n_chunks: int = self.manifest["n_chunks"]

    def chunk_path(self, k: int) -> Path:
        return self.path / f"chunk-{k:06d}.npz"

    def missing(self) -> list[int]:
        """Chunks not (yet) on disk."""
        return [k for k in range(self.n_chunks) if not self.chunk_path(k).exists()]

    def complete(self) -> bool:
        return not self.missing()

    def chunks(self) -> Iterator[BatchResult]:
        """Each chunk's rows, in order, one in memory at a time."""
        for k in range(self.n_chunks):
            yield load_chunk(self.chunk_path(k))

    def load(self) -> BatchResult:
        """All rows in one BatchResult (needs them to fit in memory)."""
        if not self.complete():
            raise FileNotFoundError(f"{self.path}: chunks {self.missing()} not written yet")
        return concat(list(self.chunks()))

    def __len__(self) -> int:
        return self.n_rows

    @classmethod
    def create(cls, path: str | os.PathLike[str], n_rows: int, chunk_rows: int | None,
               sweep: str) -> "SweepStore":
        """Open the sweep at `path` if it is this sweep (resume), else start it there."""
        path = Path(path)
        mf = path / MANIFEST
        if mf.exists():
            old = json.loads(mf.read_text())
            if old.get("sweep") != sweep or old.get("n_rows") != n_rows:
                raise ValueError(f"out: {path} holds a different sweep (other arguments); "
                                 "choose another directory or remove it")
            if chunk_rows is not None and chunk_rows != old["chunk_rows"]:
                raise ValueError(f"out: {path} was cut into chunks of {old['chunk_rows']} rows, "
                                 f"not {chunk_rows}: resume with chunk_rows={old['chunk_rows']}")
            return cls(path)
        path.mkdir(parents=True, exist_ok=True)
        manifest = {"format": _FORMAT, "sweep": sweep, "n_rows": n_rows, "chunk_rows": chunk_rows,
                    "n_chunks": math.ceil(n_rows / chunk_rows),
                    "files": "chunk-NNNNNN.npz, rows NNNNNN*chunk_rows onwards"}
        atomic_write(mf, lambda f: json.dump(manifest, f, indent=1))
        return cls(path)


# --------------------------------------------------------------------------------------------
# The sweep
# --------------------------------------------------------------------------------------------
def run_chunked(args: dict[str, Any], *, client: Any = None, chunk_rows: int | None = None,
                out: str | os.PathLike[str] | None = None,
                progress: bool = False) -> BatchResult | SweepStore:
    """simulate_batch(**args) in chunks (see the module's docstring)."""
    n = count_rows(args)
    if n is None:
        return run_chunk(args, 0)              # raises the ValueError for the lengths
    if chunk_rows is not None:
        if isinstance(chunk_rows, bool) or int(chunk_rows) != chunk_rows or chunk_rows < 1:
            raise ValueError(f"chunk_rows: must be an integer >= 1, got {chunk_rows!r}")
        chunk_rows = int(chunk_rows)
    workers = len(client.scheduler_info()["workers"]) if client is not None else None
    store = None
    if out is not None:
        wanted = chunk_rows if chunk_rows is not None or (Path(out) / MANIFEST).exists() \
            else default_chunk_rows(n, workers)
        store = SweepStore.create(out, n, wanted, fingerprint(args))
        chunk_rows = store.chunk_rows
    elif chunk_rows is None:
        chunk_rows = default_chunk_rows(n, workers)
    starts = list(range(0, n, chunk_rows))
    todo = store.missing() if store is not None else list(range(len(starts)))
    results: dict[int, BatchResult] = {}

    def finish(k: int, res: BatchResult) -> None:
        if store is not None:
            save_chunk(store.chunk_path(k), res)
        else:
            results[k] = res
        bar.update(1)

    desc = f"simulate_batch {n} rows"
    with ProgressBar(len(starts), desc, enabled=bool(progress)) as bar:
        if len(todo) < len(starts):
            bar.update(len(starts) - len(todo))
        chunk_args = {k: _slice(args, starts[k], min(starts[k] + chunk_rows, n)) for k in todo}
        if client is None:
            for k in todo:
                finish(k, run_chunk(chunk_args[k], starts[k]))
        else:
            from distributed import as_completed
            futures = {client.submit(run_chunk, chunk_args[k], starts[k], pure=False): k
                       for k in todo}
            try:
                for fut in as_completed(list(futures)):
                    finish(futures[fut], fut.result())
                    fut.release()
            finally:
                left = [f for f in futures if not f.done()]
                if left:                       # an error or an interrupt: stop the rest
                    client.cancel(left)
    if store is not None:
        return store
    return concat([results[k] for k in range(len(starts))])


@contextlib.contextmanager
def connect(scheduler: str | None) -> Iterator[Any]:
    """A dask.distributed Client of the scheduler at `scheduler` (e.g. 'tcp://127.0.0.1:8786'),
    closed on exit; None (run locally) when scheduler is None or empty."""
    if not scheduler:
        yield None
        return
    try:
        from distributed import Client
    except ImportError:
        raise RuntimeError("--scheduler needs dask.distributed: pip install 'stickslip[dask]'") from None
    with Client(scheduler) as client:
        yield client


__all__ = ["SweepStore", "connect", "default_chunk_rows", "ProgressBar", "run_chunked",
           "MAX_CHUNK_ROWS", "CHUNKS_PER_WORKER", "LOCAL_CHUNKS"]
