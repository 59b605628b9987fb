"""Chunked sweeps without Dask (stickslip.distributed): the rows of simulate_batch cut into
chunks are bit-identical to one call; out= writes each chunk whole or not at all and an
interrupted sweep resumes without recomputing what is on disk; nothing imports Dask."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import stickslip
import stickslip.distributed as sd

# The sweep's RK4 rows include small v_s, where h = 1e-3 s is beyond RK4's stability bound on
# purpose: chunked rows must equal the one-call rows whatever the rows do (the warning is
# tested in test_core_inputs.py).
pytestmark = pytest.mark.filterwarnings("ignore::stickslip.UnstableStepWarning")

N = 60
SWEEP = dict(scene=["slope", "belt", "belt"] * (N // 3),
             law=["recurdyn", "proposed", "coulomb", "proposed"] * (N // 4),
             method=["rk4", "dopri5"] * (N // 2), t_end=0.5, h=[1e-3, np.nan] * (N // 2),
             v_s=np.geomspace(1e-3, 1e-1, N), n_grid=11, keep_grid=True, threads=2)


#: A chain sweep whose chunks have states of different widths (n_blocks differs per row).
CHAIN_SWEEP = dict(scene="chain", law=["coulomb", "lugre", "stribeck"] * 4,
                   method=["moreau", "radau5", "dopri5"] * 4, h=[1e-3, np.nan, np.nan] * 4,
                   n_blocks=[1, 2, 3, 5, 8, 13, 2, 1, 4, 6, 3, 9], t_end=0.5, n_grid=11,
                   keep_grid=True, threads=2)


def assert_same_rows(a: stickslip.BatchResult, b: stickslip.BatchResult) -> None:
    """Every field equal (np.array_equal), but the wall-clock seconds."""
    for k in ("scene", "law", "method", "t_end", "h", "rtol", "atol", "status", "y_end",
              "t", "x", "v", "y_grid"):
        x, y = getattr(a, k), getattr(b, k)
        floats = x is not None and np.asarray(x).dtype.kind == "f"   # NaN pads rows of smaller states
        assert np.array_equal(x, y, equal_nan=floats), k
    assert a.fields.keys() == b.fields.keys() and a.params.keys() == b.params.keys()
    for k in a.fields:
        if k != "seconds":
            assert np.array_equal(a.fields[k], b.fields[k]), k
    for k in a.params:
        assert np.array_equal(a.params[k], b.params[k]), k
    assert a.threads == b.threads


@pytest.fixture(scope="module")
def local() -> stickslip.BatchResult:
    return stickslip.simulate_batch(**SWEEP)


def test_chunks_equal_one_call(local) -> None:
    assert_same_rows(local, stickslip.simulate_batch(**SWEEP, chunk_rows=7, progress=True))


def test_chain_chunks_equal_one_call() -> None:
    one = stickslip.simulate_batch(**CHAIN_SWEEP)
    parts = stickslip.simulate_batch(**CHAIN_SWEEP, chunk_rows=5)
    assert_same_rows(one, parts)
    assert one.y_end.shape[1] == one.n_state.max() == 13 * 2      # the 13-block Stribeck row
    assert np.isnan(parts.y_end[0, 2:]).all() and not np.isnan(parts.y_end[5]).any()


def test_row_numbers_of_errors_count_from_the_whole_sweep() -> None:
    a = [1.5] * 10
    a[8] = 0.5
    with pytest.raises(ValueError, match=r"row 8 .*a: must be finite and > 1"):
        stickslip.simulate_batch("slope", "proposed", method="rk4", t_end=0.1, h=1e-3, a=a,
                                 chunk_rows=3)
    with pytest.raises(ValueError, match="different lengths"):
        stickslip.simulate_batch("slope", "proposed", method="rk4", t_end=[0.1, 0.2], h=1e-3,
                                 a=[1.5] * 3, chunk_rows=2)
    with pytest.raises(ValueError, match="chunk_rows"):
        stickslip.simulate_batch("slope", "proposed", method="rk4", t_end=0.1, h=1e-3,
                                 chunk_rows=0)


def test_out_interrupted_then_resumed(local, tmp_path, monkeypatch) -> None:
    out = tmp_path / "sweep"
    calls = []
    real = sd.run_chunk

    def interrupted(args, start):
        if len(calls) == 3:
            raise KeyboardInterrupt
        calls.append(start)
        return real(args, start)

    monkeypatch.setattr(sd, "run_chunk", interrupted)
    with pytest.raises(KeyboardInterrupt):
        stickslip.simulate_batch(**SWEEP, chunk_rows=8, out=out)
    written = sorted(p.name for p in out.iterdir())
    assert written == ["chunk-000000.npz", "chunk-000001.npz", "chunk-000002.npz", "manifest.json"]
    stamps = {p: p.stat().st_mtime_ns for p in out.glob("chunk-*.npz")}

    calls.clear()
    monkeypatch.setattr(sd, "run_chunk", lambda args, start: (calls.append(start), real(args, start))[1])
    store = stickslip.simulate_batch(**SWEEP, out=out)     # chunk_rows from the manifest
    assert isinstance(store, sd.SweepStore) and store.complete() and len(store) == N
    assert calls == list(range(24, N, 8))                   # only the chunks not on disk
    assert all(p.stat().st_mtime_ns == t for p, t in stamps.items())
    assert not list(out.glob(".*.tmp"))
    assert_same_rows(local, store.load())
    assert sum(len(c) for c in store.chunks()) == N

    again = stickslip.simulate_batch(**SWEEP, out=out)      # complete: nothing runs
    assert again.complete() and calls == list(range(24, N, 8))
    other = dict(SWEEP, t_end=0.4)
    with pytest.raises(ValueError, match="different sweep"):
        stickslip.simulate_batch(**other, out=out)
    with pytest.raises(ValueError, match="chunks of 8 rows"):
        stickslip.simulate_batch(**SWEEP, out=out, chunk_rows=5)


def test_local_sweep_imports_no_dask() -> None:
    code = ("import sys, stickslip\n"
            "stickslip.simulate_batch('slope', 'proposed', method='rk4', t_end=0.1, h=1e-3,\n"
            "                         v_s=[1e-2, 1e-3], chunk_rows=1, progress=True)\n"
            "stickslip.simulate_batch('slope', 'proposed', method='rk4', t_end=0.1, h=1e-3)\n"
            "bad = [m for m in sys.modules if m.split('.')[0] in ('dask', 'distributed')]\n"
            "assert not bad, bad\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "2/2" in proc.stderr.replace(" ", "") or "2/2" in proc.stderr


@pytest.mark.parametrize("tqdm_installed", [True, False])
def test_progress_goes_to_stderr(capsys, monkeypatch, tqdm_installed) -> None:
    """Per chunk: a tqdm bar, or without tqdm plain 'k/n' lines, on a terminal; stdout stays
    empty."""
    from cases._progress import progress
    if not tqdm_installed:
        monkeypatch.setitem(sys.modules, "tqdm", None)      # import tqdm raises ImportError
    else:
        pytest.importorskip("tqdm")
    # the drivers' bars appear on a terminal only: none into a redirected stderr (a log)
    assert list(progress(["a", "b"], desc="runs")) == ["a", "b"]
    assert capsys.readouterr() == ("", "")
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    stickslip.simulate_batch("slope", "proposed", method="rk4", t_end=0.1, h=1e-3,
                             v_s=[1e-2, 1e-3, 1e-4], chunk_rows=1, progress=True)
    assert list(progress(["a", "b"], desc="runs")) == ["a", "b"]
    out, err = capsys.readouterr()
    assert out == ""
    if tqdm_installed:
        assert "3/3" in err and "2/2" in err and "|" in err
    else:
        assert err.splitlines() == ["simulate_batch 3 rows: 1/3", "simulate_batch 3 rows: 2/3",
                                    "simulate_batch 3 rows: 3/3", "runs: 1/2", "runs: 2/2"]
    list(progress(["a"], quiet=True))
    assert capsys.readouterr().err == ""


def test_study_drivers_take_scheduler() -> None:
    """--scheduler reaches the study's run (default: None, local)."""
    from cases import _common as c
    seen: list[dict] = []

    def run(outdir, *, scheduler=None, **kw):
        seen.append(dict(kw, scheduler=scheduler))
        return []

    c.study_main("cases.x", "doc", "quick", run, ["--scheduler", "tcp://127.0.0.1:8786"])
    c.study_main("cases.x", "doc", "quick", run, [])
    assert [kw.get("scheduler") for kw in seen] == ["tcp://127.0.0.1:8786", None]   # absent: local


def test_out_keeps_memory_to_one_chunk(tmp_path) -> None:
    """A sweep whose grids take 64 MB streams through out= with a peak of a few chunks. (DOPRI5:
    with RK4 each of the 2000 rows would have its stability bound worked out in Python, a
    tenfold cost under tracemalloc; the grids and the streaming are the same.)"""
    import tracemalloc
    kw = dict(scene="slope", law="recurdyn", method="dopri5", t_end=0.2,
              v_s=np.geomspace(1e-3, 1e-1, 2000), n_grid=2001, keep_grid=True)
    whole = 2000 * 2001 * 8 * 2                      # y_grid alone, bytes
    tracemalloc.start()
    try:
        store = stickslip.simulate_batch(**kw, out=tmp_path / "big", chunk_rows=100)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert store.complete() and store.n_chunks == 20
    assert peak < whole / 4, f"peak {peak / 1e6:.1f} MB for {whole / 1e6:.1f} MB of grids"
    last = list(store.chunks())[-1]
    ref = stickslip.simulate_batch(**{**kw, "v_s": kw["v_s"][1900:]})
    assert np.array_equal(last.y_grid, ref.y_grid) and np.array_equal(last.t, ref.t)
