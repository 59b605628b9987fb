"""The facade's lean call: a setting validated once and cached must behave exactly as a first
call (same numbers, same errors, same warnings), and no Result shares memory with another."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import stickslip as ss
from stickslip import core

RK4 = dict(method="rk4", t_end=1e-4, h=1e-5, n_out=3)


def test_a_repeated_call_gives_the_same_numbers_in_arrays_of_its_own() -> None:
    core._CALLS.clear()
    a = ss.simulate("belt", "lugre", **RK4)                   # validated, then cached
    b = ss.simulate("belt", "lugre", **RK4)                   # from the cache
    assert len(core._CALLS) == 1
    for name in ("t", "x", "v", "z"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
        assert not np.shares_memory(getattr(a, name), getattr(b, name)), name
    same = lambda st: {k: v for k, v in st.items() if k != "cpu_seconds"}      # noqa: E731
    assert same(a.stats) == same(b.stats) and a.stats["nstep"] == 10 and a.params == b.params
    a.x[:] = 1.0
    a.t[:] = 1.0
    c = ss.simulate("belt", "lugre", **RK4)
    assert np.array_equal(c.x, b.x) and np.array_equal(c.t, b.t) and c.t[-1] == 1e-4


@pytest.mark.parametrize("name, good, bad", [
    ("t_end", 1, True), ("x0", 0, False), ("v0", 1, True), ("n_out", 1, True), ("max_steps", 10**4, True),
    ("h", 1e-3, "1e-3"), ("mu_s", 1, True),
])
def test_a_value_equal_to_a_cached_one_but_of_another_type_is_still_checked(name, good, bad) -> None:
    """True == 1 and hash(True) == hash(1): the cache must not let True through where 1 passed."""
    args = dict(method="rk4", t_end=1.0, h=1e-3, n_out=2)
    ss.simulate("slope", "recurdyn", **(args | {name: good}))
    with pytest.raises(ValueError, match=rf"^{name}: "):
        ss.simulate("slope", "recurdyn", **(args | {name: bad}))


def test_warnings_come_on_every_call_not_only_the_first() -> None:
    for _ in range(3):
        with pytest.warns(UserWarning, match=r"h = 5 s is longer than the whole run"):
            ss.simulate("slope", "recurdyn", method="rk4", h=5.0, t_end=1.0)


def test_an_input_the_library_rejects_is_never_cached() -> None:
    core._CALLS.clear()
    for _ in range(2):
        with pytest.raises(ValueError, match=r"^mu_k: "):
            ss.simulate("slope", "proposed", method="rk4", h=1e-3, t_end=0.01, mu_k=0.5)
    assert not core._CALLS


def test_a_run_that_ends_early_raises_on_every_call() -> None:
    for _ in range(2):
        with pytest.raises(ss.StepBudgetExhausted) as err:
            ss.simulate("belt", "proposed", method="dopri5", t_end=20.0, max_steps=50)
        assert err.value.result.stats["nstep"] == 50 and err.value.result.t.size < 1001


def test_every_step_output_is_trimmed_to_the_steps_taken() -> None:
    for _ in range(2):
        r = ss.simulate("belt", "proposed", method="dopri5", t_end=1.0, every_step=True)
        assert r.t.size == r.stats["naccept"] + 1 and r.x.size == r.t.size and r.t[-1] == 1.0


def test_calls_from_another_thread_work_and_match() -> None:
    from concurrent.futures import ThreadPoolExecutor
    ref = ss.simulate("belt", "recurdyn", **RK4)
    with ThreadPoolExecutor(2) as pool:
        out = list(pool.map(lambda _: ss.simulate("belt", "recurdyn", **RK4), range(4)))
    assert all(np.array_equal(r.x, ref.x) for r in out)


def test_bare_call_is_the_call_simulate_makes() -> None:
    """The benchmarks' reference: the same arguments, hence the same numbers."""
    bare = core._bare_call("belt", "proposed", **RK4)
    y, istats, rstats, resolved, status = bare()
    r = ss.simulate("belt", "proposed", **RK4)
    assert status == 0 and np.array_equal(y[0], r.x) and np.array_equal(y[1], r.v)


def test_result_pickles_whole() -> None:
    import pickle
    r = ss.simulate("belt", "lugre", **RK4)
    back = pickle.loads(pickle.dumps(r))
    assert np.array_equal(back.x, r.x) and back.stats == r.stats and back.params == r.params
    assert back.state_labels == r.state_labels and back.law == "lugre"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        repr(back)
