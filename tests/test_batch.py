"""The batch entry: identical to single simulate calls, identical for 1 and 2 threads,
bounded output, clear errors."""
from __future__ import annotations

import numpy as np
import pytest

import stickslip

CASES = [("slope", "coulomb", "rk4"), ("slope", "recurdyn", "dopri5"), ("slope", "proposed", "rk4"),
         ("belt", "coulomb", "dopri5"), ("belt", "recurdyn", "rk4"), ("belt", "proposed", "dopri5")]


def _batch(threads: int, keep: bool = True) -> stickslip.BatchResult:
    return stickslip.simulate_batch([c[0] for c in CASES], [c[1] for c in CASES],
                                    method=[c[2] for c in CASES], t_end=5.0,
                                    h=[1e-3 if c[2] == "rk4" else np.nan for c in CASES],
                                    rtol=1e-8, atol=1e-11, n_grid=51, keep_grid=keep,
                                    threads=threads)


def test_batch_equals_single_simulate() -> None:
    b = _batch(2)
    for i, (scene, law, method) in enumerate(CASES):
        kw = {"h": 1e-3} if method == "rk4" else {"rtol": 1e-8, "atol": 1e-11}
        r = stickslip.simulate(scene, law, method=method, t_end=5.0, n_out=51, **kw)
        assert np.array_equal(b.t[i], r.t)
        assert np.array_equal(b.x[i], r.x) and np.array_equal(b.v[i], r.v)
        for k in ("nfev", "nstep", "naccept", "nreject", "nforced"):
            assert getattr(b, k)[i] == r.stats[k], k
        assert b.x_end[i] == r.x[-1] and b.v_end[i] == r.v[-1]
        assert b.v_max[i] == np.max(np.abs(r.v))
        assert b.status[i] == 0 and b.t_reached[i] == 5.0


def test_one_and_two_threads_identical() -> None:
    b1, b2 = _batch(1), _batch(2)
    for k in ("status", "nfev", "nstep", "x_end", "v_end", "v_max", "n_flip", "n_rev", "x", "v"):
        assert np.array_equal(getattr(b1, k), getattr(b2, k)), k
    assert b1.threads == 1 and b2.threads == 2


def test_summary_only_keeps_memory_bounded() -> None:
    b = _batch(2, keep=False)
    assert b.x is None and b.v is None and b.t is None
    assert len(b) == len(CASES) and b.x_end.shape == (len(CASES),)


def test_runtime_failure_is_a_row_status_not_an_exception() -> None:
    b = stickslip.simulate_batch("belt", "proposed", method="rk4", t_end=20.0, h=1e-3,
                                 max_steps=[100, 10**8])
    assert list(b.status) == [-2, 0]
    assert b.t_reached[0] == pytest.approx(0.1) and "step budget" in b.message(0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(method="rk4", t_end=1.0), "h: required"),
    (dict(method="rk4", t_end=1.0, h=1e-3, a=[1.5, 0.5]), "row 1 .*a: must be finite and > 1"),
    (dict(method="dopri5", t_end=1.0, rtol=1e-14), "rtol"),
    (dict(method="rk4", t_end=[1.0, 2.0, 3.0], h=[1e-3, 1e-3]), "different lengths"),
    (dict(method="rk4", t_end=1.0, h=1e-3, threads=0), "threads"),
    (dict(method="euler", t_end=1.0), "method"),
])
def test_bad_input_raises_value_error(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        stickslip.simulate_batch("slope", "proposed", **kwargs)


# --------------------------------------------------------------------------------------------
# The chain in a batch: rows of several n_blocks, laws and methods
# --------------------------------------------------------------------------------------------
CHAIN_ROWS = [(1, "coulomb", "moreau"), (5, "coulomb", "event_driven"), (7, "stribeck", "dopri5"),
              (2, "lugre", "radau5"), (4, "karnopp", "rk4")]


def _chain_batch(threads: int) -> stickslip.BatchResult:
    return stickslip.simulate_batch(
        "chain", [r[1] for r in CHAIN_ROWS], method=[r[2] for r in CHAIN_ROWS], t_end=1.5,
        n_blocks=[r[0] for r in CHAIN_ROWS],
        h=[1e-3 if r[2] in ("moreau", "rk4") else np.nan for r in CHAIN_ROWS],
        n_grid=31, keep_grid=True, threads=threads)


def test_chain_rows_equal_single_simulate() -> None:
    b = _chain_batch(2)
    widest = max(n * (2 + stickslip.REGISTRY["law"][l]["n_states"]) for n, l, _ in CHAIN_ROWS)
    assert b.y_end.shape == (len(CHAIN_ROWS), widest)
    for i, (nb, law, method) in enumerate(CHAIN_ROWS):
        kw = {"h": 1e-3} if method in ("moreau", "rk4") else {}
        r = stickslip.simulate("chain", law, method=method, t_end=1.5, n_blocks=nb, n_out=31, **kw)
        state = np.vstack([np.atleast_2d(r.x), np.atleast_2d(r.v)] + ([r.z] if r.z is not None else []))
        assert b.status[i] == 0 and b.n_state[i] == state.shape[0]
        assert np.array_equal(b.y_grid[i, :state.shape[0]], state), law
        assert np.isnan(b.y_grid[i, state.shape[0]:]).all() and np.isnan(b.y_end[i, state.shape[0]:]).all()
        assert np.array_equal(b.y_end[i, :state.shape[0]], state[:, -1])
        x1, v1 = state[0], state[nb]                      # block 1, the monitored body
        assert np.array_equal(b.x[i], x1) and np.array_equal(b.v[i], v1)
        assert b.x_end[i] == x1[-1] and b.v_end[i] == v1[-1]
        assert b.v_max[i] == np.max(np.abs(v1))
        assert b.nstep[i] == r.stats["nstep"]


def test_chain_rows_one_and_two_threads_identical() -> None:
    b1, b2 = _chain_batch(1), _chain_batch(2)
    for k in ("status", "nfev", "nstep", "v_max", "n_flip", "n_rev"):
        assert np.array_equal(getattr(b1, k), getattr(b2, k)), k
    for k in ("y_end", "y_grid"):
        assert np.array_equal(getattr(b1, k), getattr(b2, k), equal_nan=True), k


def test_one_block_chain_row_is_the_belt_row() -> None:
    """N = 1 with every block stuck on the belt (v0 not given) is the belt started at v0 = v_b."""
    kw = dict(method="dopri5", t_end=3.0, n_grid=41, keep_grid=True, v_b=0.2)
    chain = stickslip.simulate_batch("chain", "stribeck", **kw)
    belt = stickslip.simulate_batch("belt", "stribeck", v0=0.2, **kw)
    assert np.array_equal(chain.y_grid, belt.y_grid) and chain.nfev[0] == belt.nfev[0]
    assert chain.n_flip[0] == belt.n_flip[0] and chain.vrel_min_tail[0] == belt.vrel_min_tail[0]
    # v0 not given on the belt is 0, not v_b: another motion
    assert not np.array_equal(stickslip.simulate_batch("belt", "stribeck", **kw).y_grid, belt.y_grid)


@pytest.mark.parametrize("kwargs, match", [
    (dict(n_blocks=[3, 0]), r"row 1 \(chain, coulomb, moreau\): n_blocks: must be an integer in \[1, 1000000\], got 0"),
    (dict(n_blocks=2.5), r"row 0 \(chain, coulomb, moreau\): n_blocks: must be an integer"),
    (dict(n_blocks=10**6, n_grid=1001), r"n_blocks: the batch needs .* GB.*lower n_blocks"),
    (dict(n_blocks=300, n_grid=201, keep_grid=True, t_end=[1.0] * 200), r"keep_grid: 200 rows x 201"),
])
def test_chain_bad_input_raises_value_error(kwargs: dict, match: str) -> None:
    kw = dict(method="moreau", h=1e-3, t_end=1.0) | kwargs
    with pytest.raises(ValueError, match=match):
        stickslip.simulate_batch("chain", "coulomb", **kw)
