"""Scenes against analytic solutions: the slope's creep speed, the belt's harmonic orbit."""
from __future__ import annotations

import math

import numpy as np
import pytest

import stickslip as ss

G, THETA = 9.81, math.radians(10.0)
MU_S, MU_K, V_S, M, K, V_B = 0.35, 0.30, 0.01, 10.0, 300.0, 1.5


def creep_speed(law: str) -> float:
    """v* with mu(v*) = tan(theta), inverted by hand from the paper's formulas."""
    r = math.tan(THETA) / MU_S
    if law == "recurdyn":      # mu_s (1 - cos(pi v/v_s)) / 2 = tan(theta)
        return V_S / math.pi * math.acos(1.0 - 2.0 * r)
    return V_S * r ** 3        # proposed: mu_s (v/v_s)^(1/3) = tan(theta)


@pytest.mark.parametrize("method,opts", [("dopri5", {}), ("rk4", {"h": 1e-3})])
@pytest.mark.parametrize("law", ["recurdyn", "proposed"])
def test_slope_creeps_at_v_star(law, method, opts):
    res = ss.simulate("slope", law, method=method, t_end=20.0, **opts)
    v_star = creep_speed(law)
    late = res.t >= 5.0
    np.testing.assert_allclose(res.v[late], v_star, rtol=1e-5)
    # x grows linearly at v*: the slope of x over [10, 20] s is v*
    i10, i20 = np.searchsorted(res.t, 10.0), len(res.t) - 1
    assert (res.x[i20] - res.x[i10]) / (res.t[i20] - res.t[i10]) == pytest.approx(v_star, rel=1e-5)


def test_slope_recurdyn_slides_about_a_tenth_of_a_metre():
    # the paper: "with the RecurDyn law the box slides about 0.1 m in 20 s"
    res = ss.simulate("slope", "recurdyn", method="dopri5", t_end=20.0)
    assert res.x[-1] == pytest.approx(20.0 * creep_speed("recurdyn"), rel=1e-3)
    assert 0.09 < res.x[-1] < 0.11


def test_slope_steeper_than_friction_accelerates():
    # theta = 30 deg: tan > mu_s, the box accelerates at g (sin - mu_k cos) once past v_d
    th = math.radians(30.0)
    res = ss.simulate("slope", "coulomb", method="rk4", h=1e-4, t_end=2.0, theta_deg=30.0, v0=1.0)
    acc = G * (math.sin(th) - MU_K * math.cos(th))
    np.testing.assert_allclose(res.v, 1.0 + acc * res.t, rtol=1e-12, atol=1e-12)


def harmonic(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Belt from rest under constant mu_k (v_rel > v_d throughout): x = x_k (1 - cos w t)."""
    w = math.sqrt(K / M)
    x_k = MU_K * M * G / K
    return x_k * (1.0 - np.cos(w * t)), x_k * w * np.sin(w * t)


@pytest.mark.parametrize("law", ["coulomb", "recurdyn"])
def test_belt_is_harmonic_about_x_k(law):
    res = ss.simulate("belt", law, method="dopri5", t_end=20.0, rtol=1e-10, atol=1e-12, n_out=4001)
    x, v = harmonic(res.t)
    np.testing.assert_allclose(res.x, x, atol=1e-8)
    np.testing.assert_allclose(res.v, v, atol=1e-7)
    # amplitude and period measured from the trajectory itself
    x_k = MU_K * M * G / K
    assert res.x.max() == pytest.approx(2.0 * x_k, rel=1e-6)
    up = np.flatnonzero((res.v[:-1] < 0) & (res.v[1:] >= 0))
    t_cross = res.t[up] - res.v[up] * (res.t[up + 1] - res.t[up]) / (res.v[up + 1] - res.v[up])
    assert np.diff(t_cross).mean() == pytest.approx(2 * math.pi * math.sqrt(M / K), rel=1e-5)


def test_belt_rk4_error_is_fourth_order():
    errs = []
    for h in (4e-3, 2e-3):
        res = ss.simulate("belt", "coulomb", method="rk4", h=h, t_end=20.0)
        errs.append(np.abs(res.x - harmonic(res.t)[0]).max())
    assert math.log2(errs[0] / errs[1]) == pytest.approx(4.0, abs=0.1)


def test_belt_proposed_grows_into_stick_slip():
    res = ss.simulate("belt", "proposed", method="dopri5", t_end=40.0, n_out=8001)
    x_k = MU_K * M * G / K
    early = np.abs(res.x[res.t < 2] - x_k).max()
    late = np.abs(res.x[res.t > 30] - x_k).max()
    assert late > 2.0 * early
    # stick phases: the mass moves with the belt (v close to v_b) for a while in each cycle
    assert np.mean(np.abs(res.v[res.t > 30] - V_B) < 0.02) > 0.05


def test_output_grid_is_bounded_by_n_out():
    res = ss.simulate("belt", "proposed", method="rk4", h=1e-5, t_end=2.0, n_out=11)
    assert res.t.shape == res.x.shape == res.v.shape == (11,)
    np.testing.assert_allclose(res.t, np.linspace(0, 2, 11))
    assert res.stats["nstep"] == 200000 and res.stats["nfev"] == 1 + 4 * 200000


def test_every_step_output():
    res = ss.simulate("slope", "proposed", method="dopri5", t_end=1.0, every_step=True)
    assert len(res.t) == res.stats["naccept"] + 1
    assert res.t[0] == 0.0 and res.t[-1] == 1.0 and np.all(np.diff(res.t) > 0)
    rk = ss.simulate("slope", "proposed", method="rk4", h=0.005, t_end=1.0, every_step=True)   # within its bound
    np.testing.assert_allclose(rk.t, np.linspace(0, 1, 201), atol=1e-15)
