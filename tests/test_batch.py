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
