"""The checks of a fixed step are written once, for every system: a scene and the Model built
from it (Model.from_scene) warn alike, and a model of one's own gets them too (issue 41 item 6).

The periods are checked against scipy's generalized symmetric eigenvalue solver on K x = w^2 M x,
assembled here from the springs independently of the package.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.linalg

import stickslip as ss
from stickslip.core import shortest_period
from stickslip.energy import EnergyBoundWarning


def said(run) -> list[tuple[type, str]]:
    """(category, message) of every warning `run()` issues (each one, none filtered), whether
    the run then succeeds or ends early."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            run()
        except ss.IntegrationError:
            pass
    return [(w.category, str(w.message)) for w in caught]


#: (scene, law, method, controls, parameters): each warns at least once.
SETTINGS = [
    ("belt", "coulomb", "moreau", dict(h=2.0, t_end=10.0), {}),                   # the issue's example
    ("belt", "coulomb", "moreau", dict(h=20.0, t_end=10.0), {}),                  # and beyond the run
    ("belt", "recurdyn", "rk4", dict(h=1.5, t_end=3.0), {}),
    ("belt", "stribeck", "implicit_euler", dict(h=0.2, t_end=0.5), dict(m=0.01, k=300.0)),
    ("slope", "recurdyn", "rk4", dict(h=1e-2, t_end=0.1), {}),                    # RK4's creep bound
    ("slope", "recurdyn", "rk4", dict(h=5.0, t_end=1.0), {}),
    ("chain", "coulomb", "moreau", dict(h=0.62, t_end=3.0), dict(n_blocks=4)),
    ("chain", "recurdyn", "galpha", dict(h=0.6, t_end=1.2), dict(n_blocks=300)),  # Gershgorin's bound
]


@pytest.mark.parametrize("scene, law, method, controls, params", SETTINGS)
def test_a_model_from_a_scene_warns_exactly_as_the_scene(scene, law, method, controls, params):
    """The same warnings, in the same order, with the same messages, but that a model's note on
    its law names the contact it is about ("contact 0 (body0-ground): ..."; a scene has one
    unnamed contact). The energy check after a model's run (stickslip.energy:
    EnergyBoundWarning) is left out: scenes do not have it yet, and it judges the result, not
    the setting."""
    from_scene = said(lambda: ss.simulate(scene, law, method=method, **controls, **params))
    model = ss.Model.from_scene(scene, law, **params)
    label = f"{model.contact_label(0)}: "
    from_model = [(w[0], w[1].removeprefix(label) if w[0] is ss.RegularisedLawWarning else w[1])
                  for w in said(lambda: ss.simulate(model, method=method, **controls))
                  if w[0] is not EnergyBoundWarning]
    assert from_scene, "the setting warns"
    assert from_model == from_scene


def test_the_issues_belt_warns_of_its_period():
    """h = 2 s on the belt (period 2 pi sqrt(m / k) = 1.147 s): the model warns too, at the
    caller's line."""
    model = ss.Model.from_scene("belt", "coulomb")
    with pytest.warns(ss.UnstableStepWarning, match=r"shortest period of oscillation 1\.15 s") as caught:
        ss.simulate(model, method="moreau", h=2.0, t_end=10.0)
    assert caught[0].filename == __file__


def drill_string() -> ss.Model:
    """A one-body drill string: bit inertia 374 kg m^2 on a torsional spring of 473 N m/rad,
    its contact on a surface turning at 5 rad/s."""
    m = ss.Model()
    bit = m.add_body(374.0, name="bit")
    m.add_spring(bit, None, k=473.0)
    m.add_contact(bit, None, "coulomb", normal_force=2000.0, surface_velocity=5.0, mu_s=0.4, mu_k=0.3)
    return m


def test_the_drill_string_warns_at_a_step_of_its_period():
    period = 2.0 * math.pi * math.sqrt(374.0 / 473.0)          # 5.587 s
    assert shortest_period(drill_string()) == pytest.approx(period, rel=1e-12)
    with pytest.warns(ss.UnstableStepWarning, match=rf"shortest period of oscillation {period:.3g} s"):
        ss.simulate(drill_string(), method="moreau", h=6.0, t_end=60.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ss.simulate(drill_string(), method="moreau", h=0.5, t_end=5.0)


def test_a_model_warns_of_a_step_longer_than_its_run():
    with pytest.warns(UserWarning, match=r"h = 2 s is longer than the whole run \(t_end = 1 s\)"):
        ss.simulate(drill_string(), method="moreau", h=2.0, t_end=1.0)


def stiffness(n: int, springs: list[tuple[int, int | None, float]]) -> np.ndarray:
    k = np.zeros((n, n))
    for a, b, ks in springs:
        k[a, a] += ks
        if b is not None:
            k[b, b] += ks
            k[a, b] -= ks
            k[b, a] -= ks
    return k


def random_model(rng: np.random.Generator) -> tuple[ss.Model, np.ndarray, np.ndarray]:
    """1-6 bodies (masses over four decades), springs to the ground and between bodies."""
    n = int(rng.integers(1, 7))
    masses = 10.0 ** rng.uniform(-2, 2, n)
    springs: list[tuple[int, int | None, float]] = []
    for _ in range(int(rng.integers(1, 2 * n + 1))):
        a = int(rng.integers(n))
        b = None if rng.random() < 0.4 or n == 1 else int(rng.choice([i for i in range(n) if i != a]))
        springs.append((a, b, float(10.0 ** rng.uniform(0, 4))))
    m = ss.Model()
    for mass in masses:
        m.add_body(float(mass))
    for a, b, k in springs:
        m.add_spring(a, b, k)
    m.add_contact(0, None, "coulomb", normal_force=1.0)
    return m, masses, stiffness(n, springs)


def stuck_basis(n: int, ground: np.ndarray, pairs: list[tuple[int, int]]) -> np.ndarray:
    """The motions left when the bodies of `ground` are held (stuck on the ground) and each
    pair of `pairs` moves together (a stuck contact between two bodies): columns of P, x = P q."""
    group = list(range(n))

    def root(i: int) -> int:
        while group[i] != i:
            i = group[i]
        return i
    for a, b in pairs:
        group[root(a)] = root(b)
    held = {root(i) for i in np.flatnonzero(ground)}
    free = sorted({root(i) for i in range(n)} - held)
    return np.array([[1.0 if root(i) == g else 0.0 for g in free] for i in range(n)]).reshape(n, len(free))


def test_the_period_is_the_generalized_eigenproblems_and_sticking_never_shortens_it():
    """On random models: the period equals 2 pi / sqrt(max eig(K, M)) from scipy; and with any
    contacts stuck (bodies held on the ground, pairs of bodies moving together: K and M
    projected on the motions left) the largest eigenvalue is never larger, so the free system
    has the shortest period (as core._period_of says, and why it leaves the contacts out)."""
    rng = np.random.default_rng(41)
    for _ in range(60):
        model, masses, k = random_model(rng)
        lam = scipy.linalg.eigh(k, np.diag(masses), eigvals_only=True)[-1]
        got = shortest_period(model)
        if not lam > 1e-12 * np.abs(k).max():
            assert got is None or got > 1e6
            continue
        assert got == pytest.approx(2.0 * math.pi / math.sqrt(lam), rel=1e-9)
        n = masses.size
        for _ in range(4):
            pairs = [(int(a), int(b)) for a, b in rng.integers(n, size=(int(rng.integers(0, n)), 2)) if a != b]
            p = stuck_basis(n, rng.random(n) < 0.3, pairs)
            if p.shape[1]:
                sub = scipy.linalg.eigh(p.T @ k @ p, p.T @ np.diag(masses) @ p, eigvals_only=True)[-1]
                assert sub <= lam * (1.0 + 1e-10)


def test_a_long_chain_takes_gershgorins_bound_below_the_exact_period():
    """Beyond 200 bodies the period is Gershgorin's bound: at most the exact one (scipy on the
    chain's tridiagonal M^-1/2 K M^-1/2), and within 1e-3 of it on a uniform chain."""
    n, m, k, k_c, k_p = 300, 1.0, 300.0, 300.0, 0.0
    diag = np.full(n, (k_p + 2 * k_c) / m)
    diag[0] = (k + k_p + k_c) / m
    diag[-1] = (k_p + k_c) / m
    lam = scipy.linalg.eigvalsh_tridiagonal(diag, np.full(n - 1, -k_c / m))[-1]
    exact = 2.0 * math.pi / math.sqrt(lam)
    bound = shortest_period("chain", n_blocks=n, m=m, k=k, k_c=k_c, k_p=k_p)
    assert bound <= exact and bound == pytest.approx(exact, rel=1e-3)
    with pytest.warns(ss.UnstableStepWarning, match="Gershgorin"):
        ss.simulate("chain", "recurdyn", method="galpha", h=0.6, t_end=1.2, n_blocks=n)
