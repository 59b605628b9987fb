"""Experiment workflows (stickslip.experiments): the steady friction of constant-velocity steps
against the law's steady curve (friction_coefficient), a Stribeck curve fitted to them with
parameters recovered within their intervals (coverage over noise draws against the binomial
distribution in the slow run), the two-step LuGre identification, and fit_friction's offset and
drift terms, all on synthetic records of known parameters (stickslip.prescribed_motion)."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy import stats

import stickslip

pm = stickslip.prescribed_motion
# LuGre in force levels (N = 1 N): a 1.5 kN static level falling to 1 kN, viscous 3 kN s/m;
# presliding length g/sigma0 = 0.5-0.75 mm
LUGRE = dict(mu_s=1500.0, mu_k=1000.0, v_s=0.005, sigma0=2e6, sigma1=3000.0, sigma2=3000.0)
SPEEDS = [s * d for s in (0.001, 0.002, 0.004, 0.008, 0.016, 0.032, 0.064) for d in (1, -1)]


def staircase(speeds, travel=0.02, n_step=100, n_ramp=5, t_min=0.5):
    """t [s], x [m], v [m/s] of constant-velocity steps (each `travel` long, at least t_min
    seconds, n_step samples) joined by linear ramps of n_ramp samples."""
    ts, vs = [np.array([0.0])], [np.array([0.0])]
    t_now, v_now = 0.0, 0.0
    for s in speeds:
        dur = max(travel / abs(s), t_min)
        tr = t_now + np.linspace(0.0, 0.02 * dur, n_ramp + 1)[1:]
        vr = v_now + (s - v_now) * np.linspace(0.0, 1.0, n_ramp + 1)[1:]
        tc = tr[-1] + np.linspace(0.0, dur, n_step + 1)[1:]
        ts += [tr, tc]
        vs += [vr, np.full(n_step, s)]
        t_now, v_now = tc[-1], s
    t, v = np.concatenate(ts), np.concatenate(vs)
    x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    return t, x, v


@pytest.fixture(scope="module")
def stairs():
    t, x, v = staircase(SPEEDS)
    return t, x, v, pm("lugre", t, x, v, **LUGRE).force


def test_steady_points_are_the_laws_steady_curve(stairs):
    t, x, v, f = stairs
    pts = stickslip.steady_friction(t, x, f, v=v)
    # every step found once, ramps and the start at rest dropped
    np.testing.assert_allclose(pts.speed, SPEEDS, rtol=1e-12)
    assert (pts.n_samples == 50).all() and pts.force_levels
    # settled: within 0.01 N of the steady curve g(v) + sigma2 v (a 1-3 kN force)
    exact = stickslip.friction_coefficient("lugre", pts.speed, **LUGRE)
    np.testing.assert_allclose(pts.force, exact, atol=0.01)
    # with no settling the transient's first samples pull the slow steps' means off
    raw = stickslip.steady_friction(t, x, f, v=v, settle=0.0)
    assert np.abs(raw.force - exact).max() > 10.0
    # the normal force divides out: coefficients
    coef = stickslip.steady_friction(t, x, 2.0 * f, v=v, normal_force=2.0)
    assert not coef.force_levels and (coef.normal_force == 2.0).all()
    assert "speed [m/s]" in pts.table().splitlines()[0] and len(pts.table().splitlines()) == len(SPEEDS) + 1


def test_steady_curve_params():
    assert stickslip.experiments.steady_curve_params("lugre") == ("mu_s", "mu_k", "v_s", "sigma2")
    assert stickslip.experiments.steady_curve_params("dahl") == ("mu_k",)
    assert stickslip.experiments.steady_curve_params("stribeck") == ("mu_s", "mu_k", "v_s", "delta", "c_v",
                                                                     "v_eps")


def noisy_curve(stairs, seed, noise=5.0, law="lugre"):
    t, x, v, f = stairs
    fm = f + noise * np.random.default_rng(seed).standard_normal(f.size)
    return stickslip.fit_stribeck_curve(stickslip.steady_friction(t, x, fm, v=v), law)


def test_stribeck_curve_recovers_lugre_static_parameters(stairs):
    curve = noisy_curve(stairs, seed=1)
    assert curve.free == ("mu_s", "mu_k", "v_s", "sigma2") and curve.success
    for k in curve.free:
        # within its 99.9 % interval (four parameters: the 95 % coverage is the slow test's)
        assert abs(curve.params[k] - LUGRE[k]) <= 3.29 * curve.stderr[k], (k, curve.params[k], curve.stderr[k])
        assert curve.ci95[k][0] < curve.params[k] < curve.ci95[k][1]
    # the points' standard errors are right: chi-square of 10 dof within its 99.8 % band
    lo, hi = stats.chi2.ppf([0.001, 0.999], curve.dof) / curve.dof
    assert lo < curve.reduced_chi2 < hi
    np.testing.assert_allclose(curve.mu(curve.points.speed), curve.points.force, atol=4 * curve.points.stderr.max())
    assert "sigma2" in curve.summary() and curve.units["sigma2"] == "N s/m"


@pytest.mark.slow
def test_stribeck_curve_intervals_cover_the_truth_95_percent(stairs):
    # 200 noise draws of the staircase: each parameter's 95 % interval holds the truth in a
    # count within the central 99.8 % of Binomial(200, 0.95). Measured (2026-11-25):
    # mu_s 187, mu_k 190, v_s 188, sigma2 189 of 200
    draws = 200
    hits = dict.fromkeys(("mu_s", "mu_k", "v_s", "sigma2"), 0)
    for seed in range(draws):
        curve = noisy_curve(stairs, seed=100 + seed)
        for k in hits:
            hits[k] += curve.ci95[k][0] <= LUGRE[k] <= curve.ci95[k][1]
    lo, hi = stats.binom.interval(0.998, draws, 0.95)
    assert all(lo <= h <= hi for h in hits.values()), hits


def presliding_records(noise, seed, params=LUGRE):
    """Two small back-and-forth motions inside the presliding range (0.2 mm at 5 Hz, 0.5 mm at
    2 Hz; the presliding length is 0.5-0.75 mm), with noise."""
    rng = np.random.default_rng(seed)
    ts, xs, vs, fs = [], [], [], []
    for amp, hz in ((2e-4, 5.0), (5e-4, 2.0)):
        t = np.linspace(0.0, 2.0 / hz, 401)
        w = 2.0 * np.pi * hz
        x, v = amp * np.sin(w * t), amp * w * np.cos(w * t)
        ts.append(t), xs.append(x), vs.append(v)
        fs.append(pm("lugre", t, x, v, **params).force + noise * rng.standard_normal(t.size))
    return ts, xs, fs, vs


def test_two_step_lugre_recovers_static_then_dynamic_parameters(stairs):
    curve = noisy_curve(stairs, seed=2)
    t, x, f, v = presliding_records(2.0, seed=3)
    two = stickslip.fit_two_step(curve, t, x, f, v=v)
    assert two.dynamic.free == ("sigma0", "sigma1") and two.dynamic.success
    assert set(two.params) >= set(LUGRE) and set(two.ci95) == set(LUGRE)
    for k in LUGRE:
        assert abs(two.params[k] - LUGRE[k]) <= 3.29 * two.stderr[k], (k, two.params[k], two.stderr[k])
    # step 2 holds step 1's values
    for k in curve.free:
        assert two.params[k] == curve.params[k]
    # the model predicts the noise-free presliding force
    np.testing.assert_allclose(two.predict(t[0], x[0], v[0]), pm("lugre", t[0], x[0], v[0], **LUGRE).force,
                               atol=0.02 * np.ptp(f[0]))
    assert "step 1" in two.summary() and "step 2" in two.summary()


def test_offset_and_drift_fitted_beside_the_law():
    # Dahl records measured through a load cell 40 N off zero, with a friction level that
    # rises 2 % per second over each record
    truth = dict(mu_k=1000.0, sigma0=4e5, dahl_alpha=1.5)
    rng = np.random.default_rng(4)
    ts, xs, vs, fs = [], [], [], []
    for dur, amp, hz in ((4.0, 0.01, 0.5), (2.0, 0.004, 1.0)):
        t = np.linspace(0.0, dur, 401)
        w = 2.0 * np.pi * hz
        x, v = amp * np.sin(w * t), amp * w * np.cos(w * t)
        level = 1.0 + 0.02 * (t - 0.5 * dur)
        ts.append(t), xs.append(x), vs.append(v)
        fs.append(pm("dahl", t, x, v, **truth).force * level + 40.0 + 10.0 * rng.standard_normal(t.size))
    fit = stickslip.fit_friction("dahl", ts, xs, fs, v=vs, offset="fit", drift="fit")
    want = dict(truth, offset=40.0, drift=0.02)
    assert fit.units["offset"] == "N" and fit.units["drift"] == "1/s"
    for k in fit.free:
        assert abs(fit.params[k] - want[k]) <= 3.29 * fit.stderr[k], (k, fit.params[k], fit.stderr[k])
    assert fit.rmse == pytest.approx(10.0, rel=0.1)
    assert "offset:" in fit.report() and "drift:" in fit.report()
    # without them the fit is worse by far more than the noise
    plain = stickslip.fit_friction("dahl", ts, xs, fs, v=vs)
    assert plain.rmse > 2.0 * fit.rmse
    assert "offset" not in plain.report()
    # a fixed offset is applied, not fitted
    held = stickslip.fit_friction("dahl", ts, xs, fs, v=vs, offset=40.0, drift=0.02)
    assert "offset" not in held.free and abs(held.params["mu_k"] - 1000.0) <= 3.29 * held.stderr["mu_k"]


@pytest.mark.parametrize("call, match", [
    (lambda s: stickslip.steady_friction(*s[:2], s[3], v=s[2], v_tol=0.0), r"v_tol: must be in \(0, 1\)"),
    (lambda s: stickslip.steady_friction(*s[:2], s[3], v=s[2], settle=1.0), r"settle: must be in \[0, 1\)"),
    (lambda s: stickslip.steady_friction(*s[:2], s[3], v=s[2], min_samples=2), "min_samples: must be an integer >= 4"),
    (lambda s: stickslip.steady_friction(*s[:2], s[3], v=s[2], v_floor=-1.0), r"v_floor: must be >= 0"),
    (lambda s: stickslip.steady_friction(s[0], np.zeros_like(s[0]), s[3]), r"x: every sample is 0.0 m \(no motion\)"),
    (lambda s: stickslip.fit_stribeck_curve(([0.01, 0.02], [1.0, 1.1]), "lugre"), "points: 2 steps cannot determine 4"),
    (lambda s: stickslip.fit_stribeck_curve(([0.01, 0.02], [1.0]), "lugre"), "points: speed, force"),
    (lambda s: stickslip.fit_stribeck_curve(([0.01, 0.02], [1.0, 1.1]), "lugre", fixed={"sigma0": 1.0}),
     r"fixed: unknown parameter\(s\) 'sigma0'"),
    (lambda s: stickslip.fit_stribeck_curve(([0.01, 0.02], [1.0, 1.1]), "lugre2"), "law: unknown value 'lugre2'"),
    (lambda s: stickslip.fit_two_step("lugre", [0.0, 1.0], [0.0, 1.0], [0.0, 1.0]), "steady: must be a SteadyCurve"),
])
def test_bad_input_names_the_parameter(stairs, call, match):
    with pytest.raises(ValueError, match=match):
        call(stairs)


def test_two_step_refuses_mixed_units_and_fixed_static_parameters(stairs):
    curve = noisy_curve(stairs, seed=1)
    t, x, f, v = presliding_records(2.0, seed=3)
    with pytest.raises(ValueError, match="normal_force: step 1 was fitted without"):
        stickslip.fit_two_step(curve, t, x, f, v=v, normal_force=1.0)
    with pytest.raises(ValueError, match="fixed: 'mu_k' come"):
        stickslip.fit_two_step(curve, t, x, f, v=v, fixed={"mu_k": 1000.0})


def test_two_step_sensitivity_is_the_refit_change(stairs):
    # the delta method's S = d(step 2 estimates)/d(step 1 values), against refitting step 2 with
    # one step-1 value moved by twice its standard error (the refit is the independent check)
    curve = noisy_curve(stairs, seed=2, noise=50.0)
    t, x, f, v = presliding_records(2.0, seed=3)
    two = stickslip.fit_two_step(curve, t, x, f, v=v)
    assert two.sensitivity.shape == (2, 4) and two.covariance.shape == (2, 2)
    for j, name in enumerate(curve.free):
        delta = 2.0 * curve.stderr[name]
        moved = dataclasses.replace(curve, params=dict(curve.params, **{name: curve.params[name] + delta}))
        refit = stickslip.fit_two_step(moved, t, x, f, v=v, params0={k: two.params[k] for k in ("sigma0", "sigma1")})
        for i, k in enumerate(two.dynamic.free):
            change = refit.params[k] - two.params[k]
            # linear to within a fifth of the change, or of step 2's own standard error
            assert abs(change - two.sensitivity[i, j] * delta) <= 0.2 * max(abs(change), two.dynamic.stderr[k]), \
                (name, k, change, two.sensitivity[i, j] * delta)
    # step 2's standard errors: its own (conditional) ones with step 1's carried in
    for i, k in enumerate(two.dynamic.free):
        extra = (two.sensitivity @ curve.covariance @ two.sensitivity.T)[i, i]
        np.testing.assert_allclose(two.stderr[k] ** 2, two.dynamic.stderr[k] ** 2 + extra, rtol=1e-9)
        assert two.ci95[k][0] < two.params[k] < two.ci95[k][1]


def test_two_step_intervals_carry_step_one_uncertainty():
    # 20 draws with a noisy staircase (50 N) and quiet presliding records (2 N): step 1's
    # uncertainty dominates sigma0's and sigma1's. Measured (40 draws, seeds 500-539): the
    # estimates scatter by 2420 N/m and 158 N s/m; step 2's conditional standard errors say 455
    # and 19 (their 95 % intervals held the truth in 15 % of the draws), the carried ones 2200
    # and 155 (90 %)
    t, x, v = staircase(SPEEDS)
    f0 = pm("lugre", t, x, v, **LUGRE).force
    names = ("sigma0", "sigma1")
    est, own, carried, hits = [], [], [], np.zeros(2)
    for seed in range(20):
        rng = np.random.default_rng(500 + seed)
        curve = stickslip.fit_stribeck_curve(
            stickslip.steady_friction(t, x, f0 + 50.0 * rng.standard_normal(f0.size), v=v), "lugre")
        ts, xs, fs, vs = presliding_records(2.0, seed=900 + seed)
        two = stickslip.fit_two_step(curve, ts, xs, fs, v=vs)
        est.append([two.params[k] for k in names])
        own.append([two.dynamic.stderr[k] for k in names])
        carried.append([two.stderr[k] for k in names])
        hits += [two.ci95[k][0] <= LUGRE[k] <= two.ci95[k][1] for k in names]
    scatter = np.std(est, axis=0, ddof=1)
    # the carried standard errors match the scatter (20 draws: a sample sd within about +-30 %)
    ratio = scatter / np.mean(carried, axis=0)
    assert ((ratio > 0.7) & (ratio < 1.4)).all(), ratio
    # the conditional ones are far too small here
    assert (np.mean(own, axis=0) < 0.4 * scatter).all(), (np.mean(own, axis=0), scatter)
    # at least 15 of 20 intervals hold the truth (probability 0.3 % to miss that at 95 %)
    assert (hits >= 15).all(), hits


def test_steady_friction_refuses_a_record_without_plateaus():
    # a sine has runs within v_tol of their mean about its velocity peaks (short, a small part
    # of the moving time): not steady sliding, refused with what was found; a staircase joined
    # by long ramps too, below min_fraction
    t = np.linspace(0.0, 8.0, 4001)
    x = 0.02 * np.sin(np.pi * t)
    v = 0.02 * np.pi * np.cos(np.pi * t)
    f = pm("lugre", t, x, v, **LUGRE).force
    with pytest.raises(ValueError, match=r"t: not a velocity staircase: \d+ run\(s\) within v_tol 0.05 of their mean "
                                         r"velocity \([0-9.]+-[0-9.]+ ms\), 0 of them at a constant velocity .* "
                                         r"covering 0 % of the record's moving time"):
        stickslip.steady_friction(t, x, f, v=v)
    with pytest.raises(ValueError, match="not a velocity staircase"):
        stickslip.steady_friction([t, t], [x, x], [f, f], v=[v, v])
    ts, xs, vs = staircase(SPEEDS[:4], n_ramp=100)
    fs = pm("lugre", ts, xs, vs, **LUGRE).force
    assert len(stickslip.steady_friction(ts, xs, fs, v=vs, min_fraction=0.3)) == 4
    with pytest.raises(ValueError, match=r"min_fraction: must be in \(0, 1\]"):
        stickslip.steady_friction(ts, xs, fs, v=vs, min_fraction=0.0)
