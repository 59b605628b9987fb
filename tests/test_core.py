"""The facade's lean call: a setting validated once and cached must behave exactly as a first
call (same numbers, same errors, same warnings), and no Result shares memory with another."""
from __future__ import annotations

import math
import time
import warnings
from fractions import Fraction

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


@pytest.mark.parametrize("kind, kw", [
    ("grid", dict(method="rk4", t_end=1e-4, h=1e-5, n_out=3)),
    ("every step", dict(method="dopri5", t_end=0.05, every_step=True)),
    ("ended early", dict(method="dopri5", t_end=0.5, n_out=501, max_steps=100)),
])
@pytest.mark.parametrize("scene, law, extra", [
    ("belt", "gms", {}),                                   # several internal states: z is 2-d
    ("chain", "lugre", dict(n_blocks=3)),                  # rows per block
])
def test_no_two_results_of_one_setting_share_memory(kind, kw, scene, law, extra) -> None:
    """Every output array of a cached setting is new on each call, whatever its shape, also
    when the run ends early (the IntegrationError's result)."""
    def run() -> ss.Result:
        try:
            return ss.simulate(scene, law, **kw, **extra)
        except ss.IntegrationError as err:
            assert kind == "ended early"
            return err.result
    a, b = run(), run()
    assert a.t.size == b.t.size > 1 and a.stats == {**b.stats, "cpu_seconds": a.stats["cpu_seconds"]}
    for name in ("t", "x", "v", "z", "events"):
        x, y = getattr(a, name), getattr(b, name)
        assert np.array_equal(x, y), name
        assert x.size == 0 or not np.shares_memory(x, y), name
    assert a.stats is not b.stats and dict(a.stats) == a.stats and str(a.stats["message"]) in repr(a)


def test_cpu_seconds_is_the_cpu_time_of_the_library_call() -> None:
    """Read by the wrapper around the run on the process's CPU clock: positive, and within what
    time.process_time (the same clock) sees around the whole simulate call."""
    for _ in range(3):                                     # the first call validates, the others not
        before = time.process_time()
        r = ss.simulate("belt", "proposed", method="dopri5", t_end=20.0, rtol=1e-8, atol=1e-8)
        outer = time.process_time() - before
        assert 0.0 < r.stats["cpu_seconds"] <= outer


def test_cpu_seconds_of_a_long_run_on_a_worker_thread_is_on_the_cpu_clock() -> None:
    """A long run on another thread is not armed for Ctrl-C but still timed with the CPU clock:
    positive and within what time.process_time (the same clock) sees around the call."""
    import threading

    out: dict[str, float] = {}

    def work() -> None:
        before = time.process_time()
        r = ss.simulate("belt", "proposed", method="dopri5", t_end=20.0, rtol=1e-8, atol=1e-8)
        out["outer"], out["cpu"] = time.process_time() - before, r.stats["cpu_seconds"]

    worker = threading.Thread(target=work)
    worker.start()
    worker.join()
    assert 0.0 < out["cpu"] <= out["outer"]


def test_cpu_seconds_of_a_short_run_is_its_wall_time() -> None:
    """A fixed-step run too short to be armed is timed with the monotonic clock (two reads of
    the CPU clock cost more than the run): positive and within what time.perf_counter (the same
    clock) sees around the whole simulate call, on the main thread and on a worker thread."""
    import threading

    def run() -> tuple[float, float]:
        before = time.perf_counter()
        r = ss.simulate("slope", "proposed", method="rk4", t_end=0.01, h=1e-3, n_out=2)
        return time.perf_counter() - before, r.stats["cpu_seconds"]

    seen = [run() for _ in range(3)]                       # the first validates, the others not
    worker = threading.Thread(target=lambda: seen.append(run()))
    worker.start()
    worker.join()
    assert len(seen) == 4 and all(0.0 < cpu <= outer for outer, cpu in seen)


@pytest.mark.parametrize("name, good, bad", [
    ("t_end", 1, True), ("x0", 0, False), ("v0", 1, True), ("n_out", 1, True), ("max_steps", 10**4, True),
    ("h", 1e-3, "1e-3"), ("mu_s", 1, True), ("t_end", 1, np.True_), ("h", 1e-3, complex(1e-3, 0.0)),
    ("mu_s", 1, Fraction(1)),
])
def test_a_value_equal_to_a_cached_one_but_of_another_type_is_still_checked(name, good, bad) -> None:
    """True == 1 and hash(True) == hash(1): the cache must not let True through where 1 passed."""
    args = dict(method="rk4", t_end=1.0, h=1e-3, n_out=2)
    ss.simulate("slope", "recurdyn", **(args | {name: good}))
    with pytest.raises(ValueError, match=rf"^{name}: "):
        ss.simulate("slope", "recurdyn", **(args | {name: bad}))


def test_a_bad_value_after_a_cached_call_of_the_same_shape_raises_as_on_a_first_call() -> None:
    core._CALLS.clear()
    with pytest.raises(ValueError) as first:
        ss.simulate("slope", "proposed", method="rk4", t_end=1.0, h=-1e-3, n_out=2)
    core._CALLS.clear()
    ss.simulate("slope", "proposed", method="rk4", t_end=1.0, h=1e-3, n_out=2)    # cached
    with pytest.raises(ValueError) as again:
        ss.simulate("slope", "proposed", method="rk4", t_end=1.0, h=-1e-3, n_out=2)
    assert str(again.value) == str(first.value) and str(first.value).startswith("h: ")
    assert len(core._CALLS) == 1


def test_warnings_come_on_every_call_not_only_the_first() -> None:
    for _ in range(3):
        with pytest.warns(ss.UnstableStepWarning, match="stability bound"), \
                pytest.warns(UserWarning, match=r"h = 5 s is longer than the whole run"):
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
    bare = core.bare_call("belt", "proposed", **RK4)
    y, stats, status, cpu, drive_force = bare()
    r = ss.simulate("belt", "proposed", **RK4)
    assert status == 0 and np.array_equal(y[0], r.x) and np.array_equal(y[1], r.v)
    assert drive_force.shape == (0, r.t.size)          # a scene has no drives
    ni, nr = len(core._STATS_INT), len(core._STATS_REAL)
    assert stats.size == ni + nr
    assert stats[core._STATS_INT.index("nstep")] == r.stats["nstep"] == 10
    assert stats[ni:].tolist() == [r.stats[k] for k in core._STATS_REAL]
    # the one-call wrapper (run_simulation) gives the same numbers and the resolved parameters
    plan = core._plan("belt", "proposed", "rk4")
    vals = np.array([0.0, 0.0, 1.0, 1.0, 1e-5, 1e8])     # y0 (2), rtol, atol, h, max_steps
    y1, stats1, status1, _ = core._ext.run_simulation(*plan.codes, "|h,max_steps", vals, 0, 2, 1, 1, 1e-4,
                                                  np.linspace(0.0, 1e-4, 3), *core._SIZES,
                                                  np.zeros(1, dtype=np.int32), core._NO_EVENT_ROWS)
    assert status1 == 0 and np.array_equal(y1, y) and np.array_equal(stats1[:ni + nr], stats)
    resolved = dict(zip(core._PARAM_ORDER, stats1[ni + nr:].tolist()))
    assert r.params and all(resolved[k] == v for k, v in r.params.items())
    assert resolved["v_d"] == 1.5 * resolved["v_s"]                       # a derived default


def test_the_wrapper_refuses_values_that_do_not_match_their_counts() -> None:
    """run_simulation takes every name in one string and every number in one array: counts
    that overrun the array, or names without the '|' between parameters and controls, are
    SS_BAD_DIM, never a read beyond the array."""
    bad_dim = core.REGISTRY["status"]["BAD_DIM"]
    codes = core._plan("slope", "proposed", "rk4").codes
    vals = np.array([0.0, 0.0, 1.0, 1.0, 1e-3])           # y0 (2), rtol, atol, h
    grid = np.array([0.0, 1e-2])

    def run(keys: str, counts: tuple[int, int, int, int]) -> int:
        stop = np.zeros(1, dtype=np.int32)
        return int(core._ext.run_simulation(*codes, keys, vals, *counts, 1e-2, grid, *core._SIZES, stop,
                                        core._NO_EVENT_ROWS)[2])
    assert run("|h", (0, 2, 1, 1)) == 0
    assert run("h", (0, 2, 1, 1)) == bad_dim
    assert run("|h", (0, 2, 2, 2)) == bad_dim                  # 6 values counted, 5 given
    assert run("|h", (-1, 2, 1, 1)) == bad_dim


def test_only_runs_long_enough_to_look_at_the_stop_flag_arm_the_sigint_handler() -> None:
    """The integrators look at the stop flag as a run starts, then every STOP_CHECK_MASK + 1
    steps (fortran/core/stickslip_ode.f90): a fixed-step run of fewer steps is not armed (two
    system calls per call saved), a longer one and every adaptive run are."""
    import re
    from pathlib import Path
    ode = (Path(__file__).resolve().parents[1] / "fortran" / "core" / "stickslip_ode.f90").read_text()
    mask = int(re.search(r"STOP_CHECK_MASK\s*=\s*(\d+)", ode).group(1))
    assert core._STOP_CHECK_STEPS == mask + 1

    def arm(law: str = "proposed", **kw) -> bool:
        core._CALLS.clear()
        ss.simulate("slope", law, n_out=2, **kw)
        (call,) = core._CALLS.values()
        return call.arm
    assert not arm(method="rk4", h=1e-3, t_end=1e-2)                  # 10 steps
    assert not arm("coulomb", method="moreau", h=1e-3, t_end=1.0)     # 1000 steps
    assert arm(method="rk4", h=1e-4, t_end=1.0)                       # 10^4 steps
    assert arm(method="dopri5", t_end=1e-2)                           # adaptive: steps unknown


def test_result_pickles_whole() -> None:
    import pickle
    r = ss.simulate("belt", "lugre", **RK4)
    back = pickle.loads(pickle.dumps(r))
    assert np.array_equal(back.x, r.x) and back.stats == r.stats and back.params == r.params
    assert back.state_labels == r.state_labels and back.law == "lugre"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        repr(back)


def test_a_driven_models_result_pickles_with_its_drive_force() -> None:
    """The drive's force (Result.drive_force) survives pickling; a Result without drives keeps
    its (n_t, 0) array."""
    import pickle
    m = ss.Model()
    d = m.add_body(1.0, name="platform")
    b = m.add_body(2.0, name="block")
    m.add_spring(b, d, 10.0)
    m.add_drive(d, position=ss.signal.sine(0.01, 2.0))
    r = ss.simulate(m, method="rk4", h=1e-3, t_end=0.5, n_out=11)
    assert r.drive_force.shape == (11, 1) and np.any(r.drive_force != 0.0)
    back = pickle.loads(pickle.dumps(r))
    assert np.array_equal(back.drive_force, r.drive_force) and np.array_equal(back.x, r.x)
    plain = pickle.loads(pickle.dumps(ss.simulate("belt", "lugre", **RK4)))
    assert plain.drive_force.shape == (plain.t.size, 0)


# -- the API's shapes, warnings and messages --------------------------------------------------

def test_z_has_the_shape_of_x_for_one_state_and_y_stacks_every_component() -> None:
    one = ss.simulate("belt", "lugre", **RK4)
    assert one.z.shape == one.x.shape == (3,) and one.y.shape == (3, 3)
    assert np.array_equal(one.y[2], one.z) and np.array_equal(one.y[0], one.x)
    none = ss.simulate("belt", "recurdyn", **RK4)
    assert none.z.shape == (0, 3) and none.y.shape == (2, 3)


def test_a_parameter_nothing_reads_warns_and_ignore_unused_silences_it() -> None:
    with pytest.warns(ss.UnusedParameterWarning, match=r"^a, k: not read by scene 'slope' with law 'coulomb'"):
        r = ss.simulate("slope", "coulomb", method="rk4", h=1e-3, t_end=0.01, a=2.0, k=5.0)
    assert "a" not in r.params
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        # (coulomb under rk4 is the regularised law, and chatters at rest: said by warnings of their own)
        warnings.simplefilter("ignore", ss.RegularisedLawWarning)
        warnings.simplefilter("ignore", ss.ConsistencyWarning)
        ss.simulate("slope", "coulomb", method="rk4", h=1e-3, t_end=0.01, a=2.0, ignore_unused=True)
        ss.simulate("slope", "proposed", method="rk4", h=1e-3, t_end=0.01, a=2.0)    # read: no warning
        # a batch warns only about a parameter that no row reads
        ss.simulate_batch("slope", ["coulomb", "proposed"], method="rk4", h=1e-3, t_end=0.01, a=2.0)
    with pytest.warns(ss.UnusedParameterWarning, match=r"^k: not read by any row"):
        ss.simulate_batch("slope", ["coulomb", "proposed"], method="rk4", h=1e-3, t_end=0.01, k=5.0)


@pytest.mark.parametrize("kw, shown", [
    (dict(mu_k=0.5), "(got mu_k = 0.5, mu_s = 0.35)"),
    (dict(mu_k=0.5, mu_s=0.4), "(got mu_k = 0.5, mu_s = 0.4)"),
    (dict(law="recurdyn", v_d=0.01), "(got v_d = 0.01, v_s = 0.01)"),
    (dict(t_end=1e-7), "(got hmin = 1e-06, t_end = 1e-07)"),
    (dict(hmin=1e-3, hmax=1e-4), "(got hmax = 0.0001, hmin = 0.001)"),
])
def test_a_range_error_shows_the_values_it_compares(kw, shown) -> None:
    args = dict(law="proposed", method="dopri5", t_end=1.0) | kw
    with pytest.raises(ValueError) as err:
        ss.simulate("slope", args.pop("law"), **args)
    assert str(err.value).endswith(shown), str(err.value)


def test_rtol_zero_is_a_purely_absolute_error_test_for_dopri5_and_refused_by_radau5() -> None:
    """From rest the Karnopp law's belt motion is x = x_k (1 - cos w t) exactly
    (test_laws_scenes.test_constant_kinetic_from_rest_is_harmonic)."""
    w, x_k = math.sqrt(300.0 / 10.0), 0.3 * 9.81 * 10.0 / 300.0
    r = ss.simulate("belt", "karnopp", method="dopri5", t_end=10.0, rtol=0.0, atol=1e-10)
    assert np.max(np.abs(r.x - x_k * (1 - np.cos(w * r.t)))) < 1e-8
    relative = ss.simulate("belt", "karnopp", method="dopri5", t_end=10.0, rtol=1e-6, atol=1e-10)
    assert r.stats["nfev"] != relative.stats["nfev"]               # 0 is not replaced by a default
    b = ss.simulate_batch("belt", "karnopp", method="dopri5", t_end=10.0, rtol=0.0, atol=1e-10)
    assert b.nfev[0] == r.stats["nfev"] and b.x_end[0] == r.x[-1]
    with pytest.raises(ValueError, match=r"^rtol: RADAU5 needs rtol finite and in \[100 eps"):
        ss.simulate("belt", "karnopp", method="radau5", t_end=1.0, rtol=0.0)


def test_help_of_simulate_documents_every_key_of_stats_and_every_section() -> None:
    doc = ss.simulate.__doc__
    for section in ("Parameters\n    ----------", "Returns\n    -------", "Raises\n    ------",
                    "Examples\n    --------"):
        assert section in doc, section
    for method in ("rk4", "dopri5"):
        kw = dict(h=1e-3) if method == "rk4" else {}
        for key in ss.simulate("belt", "proposed", method=method, t_end=0.01, **kw).stats:
            assert f"``{key}``" in doc, key


def test_the_controls_page_lists_every_control_with_its_default() -> None:
    from pathlib import Path
    page = (Path(__file__).resolve().parents[1] / "docs" / "guide" / "controls.md").read_text()
    rows = {line.split("|")[1].strip().strip("`") for line in page.splitlines() if line.startswith("| `")}
    assert set(ss.CONTROLS) <= rows, set(ss.CONTROLS) - rows
    for name, value in ss.CONTROL_DEFAULTS.items():
        assert f"| `{name}` |" in page, name


# -- honest batch rows ------------------------------------------------------------------------

def test_rk4_bound_on_the_belt_matches_the_closed_forms() -> None:
    """Sliding with Coulomb friction (mu' = 0) the belt is an undamped oscillator, lambda = i w:
    RK4's bound is 2 sqrt(2) / w. Stuck (v0 = v_b - w0) with the RecurDyn law the stiff real
    eigenvalue is about -g mu'(w0), the haversine's slope: the bound tends to 2.785 / (g mu')."""
    w = math.sqrt(300.0 / 10.0)
    assert core.rk4_stability_bound("coulomb", scene="belt", v0=0.0) == pytest.approx(2 * math.sqrt(2) / w, rel=1e-9)
    assert core.rk4_stability_bound("coulomb", scene="belt", v0=1.5) is None          # mu jumps at rest
    v_s, mu_s, w0 = 1e-3, 0.35, 2e-4
    dmu = mu_s * 0.5 * math.pi / v_s * math.sin(math.pi * w0 / v_s)
    bound = core.rk4_stability_bound("recurdyn", (("v_s", v_s),), scene="belt", v0=1.5 - w0)
    assert bound == pytest.approx(2.785293563405282 / (9.81 * dmu), rel=1e-3)
    assert core.rk4_stability_bound("lugre", scene="belt") is None                     # not derived


def test_batch_warns_for_rk4_rows_beyond_the_bound_and_flags_chatter() -> None:
    with pytest.warns(ss.core.UnstableStepWarning, match=r"^2 RK4 row\(s\) with h beyond"):
        b = ss.simulate_batch("slope", "recurdyn", method="rk4", t_end=1.0, h=[1e-3, 1e-2, 2e-2])
    assert list(b.ok) == [True, True, True]             # reached t_end, all of them ...
    assert list(b.chattered) == [False, True, True]     # ... but two chattered
    assert not b.forced.any()
    # a reference the flag must agree with: the RK4 slope creeping at h = 1e-3 is smooth, the
    # monitor grid of h = 1e-2 shows the velocity reversing on most intervals of the tail
    assert b.n_rev_tail[0] == 0 and b.n_rev_tail[1] >= 0.25 * 200 / 2
    c = ss.simulate_batch("slope", "coulomb", method="dopri5", t_end=1.0)
    assert c.ok[0] and c.forced[0] and c.nforced[0] > 0


def test_the_examples_of_the_docstrings_run_as_written() -> None:
    import doctest
    result = doctest.testmod(core, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 5 and result.failed == 0


#: Settings across scenes, laws (static, with states, several states) and methods (fixed step,
#: adaptive, implicit, set-valued), for the interleaving test below.
_MIXED = [
    ("slope", "proposed", dict(method="rk4", t_end=0.05, h=1e-3, n_out=5)),
    ("belt", "lugre", dict(method="dopri5", t_end=0.5, rtol=1e-7, atol=1e-9, n_out=7)),
    ("belt", "gms", dict(method="radau5", t_end=0.2, n_elements=3, n_out=4)),
    ("slope", "stribeck", dict(method="dop853", t_end=0.3, every_step=True, theta_deg=25.0)),
    ("belt", "coulomb", dict(method="moreau", t_end=0.1, h=1e-3, n_out=3)),
    ("belt", "stribeck", dict(method="event_driven", t_end=2.0, n_out=3)),
    ("chain", "recurdyn", dict(method="implicit_euler", t_end=0.02, h=1e-3, n_blocks=3, n_out=3)),
    ("belt", "elastoplastic", dict(method="galpha", t_end=0.02, h=1e-4, n_out=3, v0=0.2)),
]


def _numbers(r: ss.Result) -> tuple:
    """Everything a Result holds except the measured CPU time, as bytes and plain values."""
    stats = {k: v for k, v in r.stats.items() if k != "cpu_seconds"}
    return (r.t.tobytes(), r.y.tobytes(), r.events.tobytes(), sorted(stats.items()), sorted(r.params.items()),
            r.state_labels)


def test_interleaved_settings_give_bitwise_the_numbers_of_their_first_calls() -> None:
    """Nothing a call leaves behind (in the facade's cache or in the library) changes another
    call: each setting, validated on its first call, gives bitwise the same output when called
    again from the cache after every other setting ran, in both orders, and with another
    parameter value of the same names in between."""
    core._CALLS.clear()
    first = [_numbers(ss.simulate(scene, law, **kw)) for scene, law, kw in _MIXED]
    assert len(core._CALLS) == len(_MIXED)
    for order in (range(len(_MIXED)), reversed(range(len(_MIXED)))):
        for i in order:
            scene, law, kw = _MIXED[i]
            other = ss.simulate(scene, law, **{**kw, "x0": 1e-3})      # same names, another value
            assert _numbers(other) != first[i]
            assert _numbers(ss.simulate(scene, law, **kw)) == first[i], (scene, law, kw["method"])


@pytest.mark.parametrize("scene, law, kw", [
    (scene, law, {k: v for k, v in kw.items() if k not in ("n_out", "every_step")}) for scene, law, kw in _MIXED
    if "every_step" not in kw])
def test_a_setting_run_from_its_handle_matches_the_library_building_it_anew(scene, law, kw) -> None:
    """simulate runs a cached setting from the library's handle (prepare_run once, run_prepared
    on a copy of the scene and options per call); the batch path builds the scene, its law
    and the options from names on every row (stickslip_simulate's simulate, no copy): the
    same numbers bit for bit, on the first call and from the cache, on 1 and 2 threads."""
    from concurrent.futures import ThreadPoolExecutor
    core._CALLS.clear()
    runs = [ss.simulate(scene, law, n_out=21, **kw) for _ in range(2)]
    with ThreadPoolExecutor(2) as pool:
        runs += list(pool.map(lambda _: ss.simulate(scene, law, n_out=21, **kw), range(4)))
    assert len(core._CALLS) == 1
    ref = ss.simulate_batch(scene, law, n_grid=21, keep_grid=True, **kw)
    n = runs[0].y.shape[0]
    for r in runs:
        assert r.y.tobytes() == ref.y_grid[0, :n].tobytes() and r.stats["nfev"] == ref.nfev[0]


def _python_calls(fn) -> int:
    """How many times a call of fn() enters the Python function simulate stands for."""
    import sys
    code, count = ss.simulate.__wrapped__.__code__, [0]

    def profile(frame, event, arg):
        if event == "call" and frame.f_code is code:
            count[0] += 1
    sys.setprofile(profile)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return count[0]


@pytest.mark.parametrize("kw", [
    dict(method="rk4", t_end=1e-4, h=1e-5, n_out=3),                     # short: not armed
    dict(method="dopri5", t_end=0.05, n_out=5),                          # adaptive: armed
    dict(method="dopri5", t_end=0.05, every_step=True),                  # every step
    dict(method="rk4", t_end=1e-4, h=1e-5, n_out=5000),                  # a grid not kept
])
def test_a_kept_setting_is_run_without_entering_python_and_gives_the_same_numbers(kw) -> None:
    """simulate is stickslip._runner's FastPath: a setting kept in _CALLS (no warnings to
    repeat; a kept grid or every step) runs in C, bit for bit as its first call, which went
    through the Python function; a grid too long to keep goes through Python every time."""
    core._CALLS.clear()
    first = []
    assert _python_calls(lambda: first.append(ss.simulate("belt", "lugre", **kw))) == 1
    again = []
    entered = _python_calls(lambda: again.append(ss.simulate("belt", "lugre", **kw)))
    assert entered == (1 if kw.get("n_out") == 5000 else 0)
    a, b = first[0], again[0]
    assert a.y.tobytes() == b.y.tobytes() and a.t.tobytes() == b.t.tobytes()
    same = lambda st: {k: v for k, v in st.items() if k != "cpu_seconds"}      # noqa: E731
    assert same(a.stats) == same(b.stats) and a.params == b.params and a.state_labels == b.state_labels


def test_a_setting_with_warnings_goes_through_python_and_warns_each_time() -> None:
    core._CALLS.clear()
    kw = dict(method="rk4", h=1e-3, t_end=1e-2, n_out=3, k=5.0)           # k: not on the slope
    for _ in range(2):
        with pytest.warns(ss.UnusedParameterWarning, match="k: not read by scene 'slope'"):
            assert _python_calls(lambda: ss.simulate("slope", "proposed", **kw)) == 1
    assert len(core._CALLS) == 1


def test_simulate_binds_its_arguments_as_the_function_it_stands_for() -> None:
    """The fast path binds positional and keyword arguments to the function's parameters itself:
    by name or by position, the same setting; whatever Python would refuse, the function
    refuses (the fast path passes it on)."""
    core._CALLS.clear()
    ref = ss.simulate("belt", "lugre", **RK4)
    by_name = ss.simulate(scene="belt", law="lugre", **RK4)
    built = {"".join(["met", "hod"]): "rk4", "".join(["h"]) + "": 1e-5}   # keyword names not interned
    odd = ss.simulate("belt", "lugre", t_end=1e-4, n_out=3, **built)
    assert len(core._CALLS) <= 2 and by_name.y.tobytes() == ref.y.tobytes() == odd.y.tobytes()
    fn = ss.simulate.__wrapped__
    bad_calls = [
        lambda f: f("belt", "lugre", "rk4", t_end=1e-4, h=1e-5),            # method is keyword-only
        lambda f: f("belt", "lugre", t_end=1e-4, h=1e-5),                   # method missing
        lambda f: f("belt", "lugre", law="lugre", **RK4),                   # law twice
        lambda f: f(law="lugre", **RK4),                                    # scene missing
    ]
    for bad in bad_calls:
        with pytest.raises(TypeError) as fast:
            bad(ss.simulate)
        with pytest.raises(TypeError) as slow:
            bad(fn)
        assert str(fast.value) == str(slow.value)


def test_simulate_pickles_by_name_and_reads_as_its_function() -> None:
    import inspect
    import pickle
    assert pickle.loads(pickle.dumps(ss.simulate)) is ss.simulate
    assert ss.simulate.__name__ == "simulate" and ss.simulate.__module__ == "stickslip.core"
    assert inspect.signature(ss.simulate) == inspect.signature(ss.simulate.__wrapped__)
    assert ss.simulate.__doc__ == ss.simulate.__wrapped__.__doc__ and "Parameters" in ss.simulate.__doc__


def test_the_extensions_do_not_need_an_executable_stack() -> None:
    """An internal procedure passed as an argument makes gfortran build a trampoline on the
    stack, and the linker then marks the extension as needing an executable stack, which
    recent C libraries (glibc 2.41) refuse to load. The ELF program header PT_GNU_STACK of
    each compiled module must not have the execute flag."""
    import struct
    import sys
    from stickslip import _runner, _stickslip
    if not sys.platform.startswith("linux"):
        pytest.skip("ELF only")
    for module in (_stickslip, _runner):
        data = open(module.__file__, "rb").read()
        assert data[:4] == b"\x7fELF" and data[4] == 2, module.__file__            # ELF64
        phoff, = struct.unpack_from("<Q", data, 0x20)
        phentsize, phnum = struct.unpack_from("<HH", data, 0x36)
        flags = {}
        for i in range(phnum):
            p_type, p_flags = struct.unpack_from("<II", data, phoff + i * phentsize)
            flags[p_type] = p_flags
        assert 0x6474E551 in flags, "no PT_GNU_STACK header"
        assert not flags[0x6474E551] & 1, f"{module.__file__} asks for an executable stack"
