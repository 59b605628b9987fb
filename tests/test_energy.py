"""The energy bound on results of models (stickslip.energy): exact for a free body pushed along
its velocity, a warning for an explicit run beyond its stability bound that returned success,
silence on correct runs with a moving surface (whose input the bound counts)."""
from __future__ import annotations

import warnings
from types import SimpleNamespace

import numpy as np
import pytest

import stickslip as ss
from stickslip.energy import _value, check_result, energy_bound

S = ss.signal


def run_quiet(model: ss.Model, **kw) -> tuple[ss.Result, list[warnings.WarningMessage]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = ss.simulate(model, **kw)
    return r, [w for w in caught if issubclass(w.category, ss.EnergyBoundWarning)]


def test_bound_is_exact_for_a_free_body_pushed_along_its_velocity():
    """E(t) = 1/2 m (v0 + F t/m)^2 is the bound's (sqrt(E0) + 1/2 |F| sqrt(2/m) t)^2."""
    m = ss.Model()
    b = m.add_body(2.0, v0=1.0)
    m.add_force(b, 3.0)
    r, caught = run_quiet(m, method="dopri5", t_end=2.0, n_out=11, rtol=1e-12, atol=1e-14)
    e, bound = energy_bound(m, r.t, r.x, r.v)
    exact = 0.5 * 2.0 * (1.0 + 3.0 * r.t / 2.0) ** 2
    np.testing.assert_allclose(e, exact, rtol=1e-10)
    np.testing.assert_allclose(bound, exact, rtol=3e-3)
    assert np.all(e <= bound) and not caught


@pytest.mark.parametrize("h, wrong", [(0.02, False), (0.029, True)])
def test_rk4_beyond_its_stability_bound_is_flagged(h, wrong):
    """A spring of 1e4 N/m (w = 100 rad/s): RK4 is stable for w h < 2 sqrt(2). At h = 0.029 s
    its amplitude grows 1.19 times a step, 380 times within 1 s: less than the model's
    divergence bound allows (BOUND_MARGIN = 1e3 times the energy bound's speed), so the run
    ends with status 0; the energy bound (no force: E <= E0) names it."""
    m = ss.Model()
    b = m.add_body(1.0, v0=1.0)
    m.add_spring(b, None, 1e4)
    r, caught = run_quiet(m, method="rk4", h=h, t_end=1.0, n_out=11)
    assert r.stats["status"] == 0 and np.isfinite(r.x).all()
    assert bool(caught) is wrong
    if wrong:
        assert "exceeds" in str(caught[0].message) and "rk4" in str(caught[0].message)


@pytest.mark.parametrize("method, ctl", [("rk4", dict(h=0.03)), ("dopri5", dict(rtol=1e-8, atol=1e-10)),
                                         ("moreau", dict(h=0.03, theta=0.5))])
def test_a_model_that_leaves_its_energy_bound_diverged(method, ctl):
    """The same spring at h = 0.03 s: RK4's amplitude grows 1.5 times a step, 6.6e5 times in
    1 s, beyond 1e3 times the speed the energy allows (|v| <= sqrt(2 E0 / m) = 1 m/s, no force
    puts energy in): DivergedSolution (SS_DIVERGED), not a result. A stable method on the
    same model stays within it."""
    m = ss.Model()
    b = m.add_body(1.0, v0=1.0)
    m.add_spring(b, None, 1e4)
    if method == "rk4":
        with pytest.raises(ss.DivergedSolution) as err:
            ss.simulate(m, method=method, t_end=1.0, n_out=11, **ctl)
        assert err.value.result.stats["status"] != 0
        assert np.abs(err.value.result.v).max() <= 1e3 * 1.5   # stopped at the step that left it
    else:
        r, caught = run_quiet(m, method=method, t_end=1.0, n_out=11, **ctl)
        assert r.stats["status"] == 0 and np.abs(r.v).max() <= 1.0 + 1e-6 and not caught


@pytest.mark.parametrize("law, method, ctl", [("coulomb", "event_driven", {}), ("stribeck", "moreau", dict(h=1e-3)),
                                              ("recurdyn", "dopri5", {})])
def test_moving_surface_input_is_counted(law, method, ctl):
    """A block at rest on a belt gains energy from the belt: E rises above E(0), within the
    bound, and correct runs raise no warning."""
    m = ss.Model.from_scene("belt", law)
    r, caught = run_quiet(m, method=method, t_end=10.0, n_out=201, **ctl)
    e, bound = energy_bound(m, r.t, r.x, r.v)
    assert e.max() > 10.0 * max(e[0], 1e-12) and np.all(e <= bound) and not caught


def test_laws_with_internal_states_are_not_checked():
    m = ss.Model.from_scene("belt", "lugre")
    r = ss.simulate(m, method="radau5", t_end=0.5, n_out=11)
    assert energy_bound(m, r.t, r.x, r.v) is None


def test_cached_bound_follows_a_changed_model():
    """The bounds are cached by the model's arrays, the grid and E(0): a model changed in
    place (a force's amplitude, a mass) gets the bound of a model built new with the change,
    and the same model on the same grid the same bound as before."""
    def pushed(force: float, mass: float) -> ss.Model:
        m = ss.Model()
        b = m.add_body(mass, v0=1.0)
        m.add_force(b, S.sine(force, 2.0))
        return m

    m = pushed(3.0, 2.0)
    t = np.linspace(0.0, 1.0, 21)
    x = np.zeros((1, t.size))
    v = np.ones((1, t.size))
    first = energy_bound(m, t, x, v)[1]
    np.testing.assert_array_equal(energy_bound(m, t, x, v)[1], first)
    m.forces[0] = (0, S.sine(6.0, 2.0))
    np.testing.assert_array_equal(energy_bound(m, t, x, v)[1], energy_bound(pushed(6.0, 2.0), t, x, v)[1])
    assert energy_bound(m, t, x, v)[1][-1] > first[-1]
    m.bodies[0].mass = 8.0
    np.testing.assert_array_equal(energy_bound(m, t, x, v)[1], energy_bound(pushed(6.0, 8.0), t, x, v)[1])


def test_normal_force_acting_between_two_samples_is_no_consistency_failure():
    """A normal force that rises above 0 and falls back between two output samples (a table
    at -5 N at both, 50 N between): friction acts there, and the check's bound on it takes N
    at its largest inside the interval, not at the samples (which gave 0 N and a false
    ConsistencyWarning). The run itself agrees with the independent event-driven reference."""
    from contact_reference import Reference
    tab = ([0.0, 0.501, 0.505, 0.509, 1.0], [-5.0, -5.0, 50.0, -5.0, -5.0])
    m = ss.Model()
    b = m.add_body(1.0, v0=0.5)
    m.add_spring(b, None, k=100.0)
    m.add_contact(b, None, "coulomb", normal_force=S.table(*tab), mu_s=0.5, mu_k=0.4)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = ss.simulate(m, method="event_driven", t_end=1.0, n_out=101, rtol=1e-10, atol=1e-12)
    assert not [w for w in caught if issubclass(w.category, ss.ConsistencyWarning)]
    ref = Reference(m=[1.0], k=[[100.0]], h=[[1.0]], b=[0.0], n=[10.0], mu_s=[0.5], mu_k=[0.4], normal_tables=[tab])
    y_ref, _ = ref.run([0.0], [0.5], 1.0, r.t)
    assert np.abs(r.x[0] - y_ref[0]).max() < 1e-7
    # the friction between the samples did act: without the pulse the motion differs
    m0 = ss.Model()
    b0 = m0.add_body(1.0, v0=0.5)
    m0.add_spring(b0, None, k=100.0)
    m0.add_contact(b0, None, "coulomb", normal_force=S.table(tab[0], [-5.0] * 5), mu_s=0.5, mu_k=0.4)
    r0 = ss.simulate(m0, method="event_driven", t_end=1.0, n_out=101, rtol=1e-10, atol=1e-12)
    assert np.abs(r.x[0] - r0.x[0]).max() > 1e-3


@pytest.mark.parametrize("sig", [S.table([0.0, 0.501, 0.505, 0.509, 1.0], [-5.0, -5.0, 50.0, -5.0, -5.0]),
                                 S.sine(3.0, 7.3, 0.4, 1.0), S.step(0.333, 1.0, -2.0) + S.ramp(0.1, 0.5, 4.0),
                                 S.ramp(0.0, 1.0, 2.0) * (S.constant(2.0) - S.ramp(0.0, 1.0, 2.3))])
def test_interval_max_against_dense_sampling(sig):
    """_interval_max: each output interval's largest value of the signal, against 20001 points
    an interval (the sine's sampled peak to 1.2e-3 of its amplitude, 64 points a period; a
    step's left limit, which dense sampling approaches from below)."""
    from stickslip.energy import _interval_max
    t = np.linspace(0.0, 1.0, 41)
    got = _interval_max(sig, t)
    dense = np.array([_value(sig, np.linspace(a, b, 20001)).max() for a, b in zip(t[:-1], t[1:])])
    assert got.shape == dense.shape
    assert np.all(got <= dense + 1e-4)
    assert np.allclose(got, dense, rtol=0.0, atol=1.3e-3 * 3.0)


# -- the check's cached parts (_Plan: per model content and output grid) -----------------------

def _decelerating(mass: float, normal: float) -> tuple[ss.Model, SimpleNamespace]:
    """A body of `mass` on a coulomb contact (mu 0.5, normal force `normal`), and a synthetic
    result in which it decelerates at 8 m/s^2 from 10 m/s (exact samples of x = 10 t - 4 t^2,
    v = 10 - 8 t): its friction is 8 mass N, which the check finds beyond 0.5 normal N."""
    m = ss.Model()
    b = m.add_body(mass, v0=10.0, name="slider")
    m.add_contact(b, None, "coulomb", normal, mu_s=0.5, mu_k=0.5)
    t = np.linspace(0.0, 1.0, 201)
    result = SimpleNamespace(t=t, x=(10.0 * t - 4.0 * t * t)[None, :], v=(10.0 - 8.0 * t)[None, :],
                             stats={"nstep": 100_000}, scene="model", law="coulomb", events=None)
    return m, result


def _check_quiet(result: SimpleNamespace, model: ss.Model, memo: list | None = None) -> list[str]:
    result.stats["notes"] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = check_result(result, "rk4", {"h": 1e-5}, model, memo=memo)
    assert [str(w.message) for w in caught] == found == result.stats["notes"]
    return found


def test_friction_excess_fires_again_from_the_memo():
    """A friction of 8 N against a limit of mu N = 5 N (a synthetic motion): the check fires on
    the first call and again on the second with the memo's plan reused (the same plan object,
    no second one), and not where the limit (N = 20 N: 10 N) exceeds the friction."""
    model, result = _decelerating(1.0, 10.0)
    memo: list = []
    first = _check_quiet(result, model, memo)
    assert len(first) == 1 and "slider: its mean friction force" in first[0] and "beyond the 5 N" in first[0]
    plan = memo[0]
    assert _check_quiet(result, model, memo) == first
    assert memo == [plan]
    strong, result = _decelerating(1.0, 20.0)
    assert _check_quiet(result, strong, []) == []


def test_friction_excess_follows_a_model_changed_in_place():
    """Without a memo the plan is found by the model's arrays: the silent model (8 N of friction
    within 10 N) made twice as heavy in place (16 N beyond 10 N) fires; the normal force then
    doubled in place (20 N) silences it again; each as a model built new with the change."""
    model, result = _decelerating(1.0, 20.0)
    assert _check_quiet(result, model) == _check_quiet(result, model) == []
    model.bodies[0].mass = 2.0
    fired = _check_quiet(result, model)
    assert len(fired) == 1 and "beyond the 10 N" in fired[0]
    assert fired == _check_quiet(result, _decelerating(2.0, 20.0)[0])
    model.contacts[0].normal_force = S.constant(40.0)
    assert _check_quiet(result, model) == []


def _spring_on_stribeck(amplitude: float) -> ss.Model:
    """The spring of 1e4 N/m (RK4 unstable at h = 0.029 s) with a stribeck contact of 100 N and
    a sine force of `amplitude` [N] at 1 Hz."""
    m = ss.Model()
    b = m.add_body(1.0, v0=1.0)
    m.add_spring(b, None, 1e4)
    m.add_contact(b, None, "stribeck", 100.0, mu_s=0.5, mu_k=0.4)
    m.add_force(b, S.sine(amplitude, 1.0))
    return m


def _simulate_recorded(model: ss.Model) -> tuple[ss.Result, list[tuple[type, str]]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = ss.simulate(model, method="rk4", h=0.029, t_end=2.0, n_out=101)
    return r, [(w.category, str(w.message)) for w in caught
               if issubclass(w.category, (ss.EnergyBoundWarning, ss.ConsistencyWarning))]


def test_energy_bound_fires_again_on_a_kept_run_and_after_a_change_in_place(monkeypatch):
    """simulate: RK4 at h = 0.029 s gains energy (0.568 J beyond the bound 0.5005 J of the
    force of 1e-6 N): warned on the first run, and on the second, whose check reuses the plan
    kept with the run (the signals integrated once); a force of 100 N loosens the bound (no
    warning); that model changed in place to the force of 1e-6 N warns as the model built new
    with it (its plan is not the 100 N model's)."""
    from stickslip import energy
    calls = []
    integrals = energy._signal_integrals
    monkeypatch.setattr(energy, "_signal_integrals", lambda *a: calls.append(1) or integrals(*a))
    weak = _spring_on_stribeck(1e-6)
    r1, said1 = _simulate_recorded(weak)
    assert [c for c, _ in said1] == [ss.EnergyBoundWarning] and "exceeds 0.5005 J" in said1[0][1]
    r2, said2 = _simulate_recorded(weak)
    assert said2 == said1 and r2.stats["notes"] == r1.stats["notes"] and len(calls) == 1
    loose = _spring_on_stribeck(100.0)
    assert _simulate_recorded(loose)[1] == []
    loose.forces[0] = (0, S.sine(1e-6, 1.0))
    r3, said3 = _simulate_recorded(loose)
    assert said3 == said1 and r3.stats["notes"] == r1.stats["notes"]


def test_kinematic_check_names_the_first_inconsistent_resolved_body():
    """Three bodies checked at once: body 0 chatters (v reverses every interval: not
    resolved, not checked, however wrong its x), body 1 is consistent, body 2's x runs 1 % ahead
    of the integral of its v: the check names body 2; with body 1 off too, body 1 (the first).
    (Their friction, with no contact and no force, is reported too.)"""
    m = ss.Model()
    for name in ("chatter", "good", "bad"):
        m.add_body(1.0, name=name)
    t = np.linspace(0.0, 1.0, 201)
    v = np.vstack([np.where(np.arange(t.size) % 2 == 0, 1.0, -1.0), np.cos(t), np.cos(t)])
    x = np.vstack([5.0 * t, np.sin(t), 1.01 * np.sin(t)])
    result = SimpleNamespace(t=t, x=x, v=v, stats={"nstep": 2000, "notes": []}, scene="model", law="", events=None)
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        found = [f for f in check_result(result, "rk4", {"h": 5e-4}, m) if "x changed" in f]
        assert len(found) == 1 and found[0].startswith("model (no contact, rk4): bad: x changed by")
        result.x[1] = 1.02 * np.sin(t)
        found = [f for f in check_result(result, "rk4", {"h": 5e-4}, m) if "x changed" in f]
    assert len(found) == 1 and found[0].startswith("model (no contact, rk4): good: x changed by")


@pytest.mark.parametrize("n, w", [(1, 0), (5, 2), (64, 3), (64, 63), (64, 100), (1000, 10)])
def test_window_sum_against_direct_sums(n, w):
    """_window_sum along each row: a[i - w] + ... + a[i + w] (the terms that exist), against
    the sums of the slices."""
    from stickslip.energy import _window_sum
    a = np.random.default_rng(n + w).random((3, n))
    direct = np.array([[row[max(i - w, 0):i + w + 1].sum() for i in range(n)] for row in a])
    np.testing.assert_allclose(_window_sum(a, w), direct, rtol=1e-12, atol=1e-12 * n)
    np.testing.assert_array_equal(_window_sum(a[1], w), _window_sum(a, w)[1])


def test_energy_of_springs_between_bodies_and_to_the_ground():
    """energy_bound's E: sum 1/2 m v^2 + sum 1/2 k (x_a - x_b - l0)^2 over springs between two
    bodies, to the ground and several on one body, against the sum written out here."""
    m = ss.Model()
    for mass in (1.0, 2.0, 3.0):
        m.add_body(mass)
    springs = [(0, None, 10.0, 0.1), (0, 1, 20.0, -0.2), (1, 2, 30.0, 0.0), (2, None, 40.0, 0.3), (2, 0, 50.0, 0.05)]
    for a, b, k, l0 in springs:
        m.add_spring(a, b, k, l0)
    m.add_damper(1, None, 2.0)
    t = np.linspace(0.0, 1.0, 11)
    rng = np.random.default_rng(7)
    x, v = rng.standard_normal((3, t.size)), rng.standard_normal((3, t.size))
    e, bound = energy_bound(m, t, x, v)
    want = sum(0.5 * mass * v[i] ** 2 for i, mass in enumerate((1.0, 2.0, 3.0)))
    want = want + sum(0.5 * k * (x[a] - (0.0 if b is None else x[b]) - l0) ** 2 for a, b, k, l0 in springs)
    np.testing.assert_allclose(e, want, rtol=1e-14)
    np.testing.assert_allclose(bound, e[0] * (1.0 + 1e-3) + 1e-14 * e[0], rtol=1e-14)   # nothing puts energy in
