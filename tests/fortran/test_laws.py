"""Friction laws against the paper's formulas at hand-computed points, continuity, symmetry."""
from __future__ import annotations

import math

import numpy as np
import pytest

import stickslip as ss

MU_S, MU_K, V_S = 0.35, 0.30, 0.01


def mu(law: str, v, **kw) -> np.ndarray:
    return ss.friction_coefficient(law, v, **kw)


def test_coulomb_points():
    got = mu("coulomb", [0.0, 0.005, -0.005, 0.01, 0.5, -0.5])
    np.testing.assert_array_equal(got, [0.0, MU_S, -MU_S, MU_K, MU_K, -MU_K])


def test_recurdyn_points():
    # haversine: half way up (v_s/2) gives mu_s/2; half way down (v_s + (v_d - v_s)/2) gives
    # (mu_s + mu_k)/2; v_d = 1.5 v_s by default.
    got = mu("recurdyn", [0.0, 0.005, 0.01, 0.0125, 0.015, 1.0])
    np.testing.assert_allclose(got, [0.0, MU_S / 2, MU_S, (MU_S + MU_K) / 2, MU_K, MU_K], rtol=1e-14)
    # a quarter of the way up: mu_s (1 - cos(pi/4)) / 2
    np.testing.assert_allclose(mu("recurdyn", 0.0025), MU_S * (1 - math.cos(math.pi / 4)) / 2, rtol=1e-14)
    # v_d is a parameter
    np.testing.assert_allclose(mu("recurdyn", 0.02, v_d=0.03), (MU_S + MU_K) / 2, rtol=1e-14)


def test_proposed_points():
    # inside v_s: mu_s (v/v_s)^(1/3); at v_s/8 that is mu_s/2
    np.testing.assert_allclose(mu("proposed", V_S / 8), MU_S / 2, rtol=1e-14)
    # outside: a^-(v + b) + mu_k with b = -ln(mu_s - mu_k)/ln a - v_s (a = 1.5)
    b = -math.log(MU_S - MU_K) / math.log(1.5) - V_S
    np.testing.assert_allclose(mu("proposed", 1.5), 1.5 ** (-(1.5 + b)) + MU_K, rtol=1e-14)
    # docs/paper.md's figure: mu(1.5 m/s) is about 0.327
    assert abs(float(mu("proposed", 1.5)) - 0.327) < 5e-4
    np.testing.assert_allclose(mu("proposed", 0.001, beta=1.0), MU_S * 0.1, rtol=1e-14)


@pytest.mark.parametrize("law", ss.LAWS)
def test_odd_symmetry(law):
    v = np.concatenate([np.linspace(0, 0.05, 501), np.geomspace(1e-9, 10, 200)])
    np.testing.assert_array_equal(mu(law, -v), -mu(law, v))


@pytest.mark.parametrize("law,points", [("recurdyn", [V_S, 1.5 * V_S]), ("proposed", [V_S])])
def test_continuity(law, points):
    for p in points:
        below, at, above = mu(law, [p * (1 - 1e-12), p, p * (1 + 1e-12)])
        assert abs(below - at) < 1e-9 and abs(above - at) < 1e-9


def test_recurdyn_is_c1_at_thresholds():
    # the haversine is flat at both ends: one-sided slopes vanish at v_s and v_d
    for p in (V_S, 1.5 * V_S):
        d = 1e-7
        left = (mu("recurdyn", p) - mu("recurdyn", p - d)) / d
        right = (mu("recurdyn", p + d) - mu("recurdyn", p)) / d
        assert abs(left) < 1e-3 and abs(right) < 1e-3


def test_coulomb_jumps_at_v_s():
    below, above = mu("coulomb", [V_S * (1 - 1e-12), V_S * (1 + 1e-12)])
    assert below - above == pytest.approx(MU_S - MU_K)


def test_shape_preserved():
    v = np.linspace(-1, 1, 12).reshape(3, 4)
    assert mu("proposed", v).shape == (3, 4)
    assert np.ndim(mu("proposed", 0.5)) == 0


@pytest.mark.parametrize("law,params,name", [
    ("coulomb", {"mu_k": 0.4}, "mu_k"),
    ("recurdyn", {"v_d": 0.01}, "v_d"),
    ("recurdyn", {"v_d": 0.005}, "v_d"),
    ("proposed", {"a": 1.0}, "a"),
    ("proposed", {"a": 0.5}, "a"),
    ("proposed", {"beta": 0.0}, "beta"),
    ("coulomb", {"v_s": 0.0}, "v_s"),
    ("coulomb", {"v_s": -1.0}, "v_s"),
    ("coulomb", {"mu_s": -0.1}, "mu_s"),
    ("proposed", {"mu_s": float("nan")}, "mu_s"),
    ("proposed", {"a": float("inf")}, "a"),
    ("proposed", {"gamma": 1.0}, "gamma"),
])
def test_bad_law_parameters(law, params, name):
    with pytest.raises(ValueError, match=name):
        mu(law, 0.1, **params)


def test_bad_law_name_and_velocity():
    with pytest.raises(ValueError, match="law"):
        mu("bristle", 0.1)
    with pytest.raises(ValueError, match="v"):
        mu("coulomb", [0.1, float("nan")])
