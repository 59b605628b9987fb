"""Implicit Euler and generalized-alpha on the laws with jumps (Coulomb, Karnopp), whose stages
are solved as generalized equations over the law's modes (fortran/integrators/stickslip_fixed_implicit_body.inc,
docs/guide/implicit-nonsmooth.md), against closed forms of Coulomb friction: the slope below the
friction angle from rest (x = 0 exactly), the box sliding to a stop, and the belt's stick-slip
cycle, for parameter sets other than the paper's. Then every law x method pair on both scenes:
each succeeds, is refused before running (ValueError), or ends in exactly the IntegrationError
that the table below (and the same table in the doc page) predicts."""
from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pytest

import stickslip as ss

G = 9.81
FIXED = ("implicit_euler", "galpha")
# v_s (Coulomb's mu_s band) and dv (Karnopp's stick band) far below any velocity change of a
# step, so that the closed forms of plain Coulomb friction (mu_s in stick, mu_k in slip) apply.
NARROW = {"coulomb": {"v_s": 1e-10}, "karnopp": {"dv": 1e-10}}


@pytest.mark.parametrize("law", ["coulomb", "karnopp"])
@pytest.mark.parametrize("method", FIXED)
@pytest.mark.parametrize("h,t_end", [(1e-2, 20.0), (1e-3, 20.0), (1e-4, 2.0)])
def test_slope_from_rest_stays(law, method, h, t_end):
    """10 deg < atan(mu_s): the box never moves; the stick mode keeps v = 0 exactly, x = 0, at
    every step. On an output grid x stays 0 and v is the cubic Hermite of steps whose end
    derivatives hold g sin - mu g cos = 0 to rounding (1e-17 m/s^2): |v| < 1e-30 m/s."""
    r = ss.simulate("slope", law, method=method, h=h, t_end=t_end, every_step=True)
    assert r.t.size == round(t_end / h) + 1
    assert np.all(r.x == 0.0) and np.all(r.v == 0.0)
    r = ss.simulate("slope", law, method=method, h=h, t_end=t_end, n_out=101)
    assert np.all(r.x == 0.0) and np.all(np.abs(r.v) < 1e-30)


@pytest.mark.parametrize("method", FIXED)
@pytest.mark.parametrize("theta,mu_k,mu_s,v0", [(10.0, 0.3, 0.35, 1.0), (25.0, 0.6, 0.7, 2.0)])
@pytest.mark.parametrize("h", [1e-2, 1e-3, 1e-4])
def test_slope_slides_to_stop(method, theta, mu_k, mu_s, v0, h):
    """From v0 the box decelerates at a = g (mu_k cos th - sin th) and stops for good at
    t_stop = v0/a, x_stop = v0^2/(2a). Implicit Euler's x is off by v0 h/2 (its first-order
    error), generalized-alpha's less; the stop lands on the step after t_stop."""
    th = math.radians(theta)
    a = G * (mu_k * math.cos(th) - math.sin(th))
    t_stop, x_stop = v0 / a, v0 ** 2 / (2.0 * a)
    r = ss.simulate("slope", "coulomb", method=method, h=h, t_end=t_stop + 1.0, every_step=True, v0=v0,
                    theta_deg=theta, mu_k=mu_k, mu_s=mu_s, **NARROW["coulomb"])
    stopped = np.nonzero(r.v == 0.0)[0]
    assert stopped.size and np.all(r.v[stopped[0]:] == 0.0)           # stops, and stays
    assert abs(r.t[stopped[0]] - t_stop) <= 2.0 * h
    assert abs(r.x[-1] - x_stop) <= v0 * h
    assert np.all(r.x[stopped[0]:] == r.x[-1])


def _cycle(m, k, v_b, mu_s, mu_k):
    """Coulomb stick-slip on the belt: centre x_k, amplitude A, period P."""
    w = math.sqrt(k / m)
    x_k = mu_k * m * G / k
    amp = math.hypot((mu_s - mu_k) * m * G / k, v_b / w)
    period = (math.pi + 2.0 * math.asin(v_b / (amp * w))) / w + 2.0 * (mu_s - mu_k) * m * G / (k * v_b)
    return x_k, amp, period


@pytest.mark.parametrize("law", ["coulomb", "karnopp"])
@pytest.mark.parametrize("method", FIXED)
@pytest.mark.parametrize("par", [dict(m=2.0, k=50.0, v_b=0.2, mu_s=0.5, mu_k=0.3),
                                 dict(m=1.0, k=100.0, v_b=0.5, mu_s=0.6, mu_k=0.4)])
@pytest.mark.parametrize("h", [1e-3, 1e-4])
def test_belt_stick_slip_cycle(law, method, par, h):
    """Started stuck where the cycle re-sticks (x0 = 2 x_k - x_s, moving with the belt), the
    motion is the periodic Coulomb cycle from t = 0: x within x_k +- A, period P, both to O(h)
    (measured: about 5 h on the period, h on the extremes)."""
    x_k, amp, period = _cycle(**par)
    x_s = par["mu_s"] * par["m"] * G / par["k"]
    r = ss.simulate("belt", law, method=method, h=h, t_end=3.2 * period, every_step=True,
                    x0=2.0 * x_k - x_s, v0=par["v_b"], **par, **NARROW[law])
    stuck = np.abs(par["v_b"] - r.v) <= 2.0 * NARROW[law].get("dv", 0.0)
    onsets = r.t[1:][stuck[1:] & ~stuck[:-1]]
    assert len(onsets) >= 2
    assert np.all(np.abs(np.diff(onsets) - period) <= 10.0 * h), (np.diff(onsets), period)
    assert abs(r.x.max() - (x_k + amp)) <= 2.0 * h and abs(r.x.min() - (x_k - amp)) <= 2.0 * h
    if law == "coulomb":   # stick is exact: the relative velocity is 0 to rounding
        assert np.all(np.abs(par["v_b"] - r.v[stuck]) == 0.0)


@pytest.mark.parametrize("scene", ["slope", "belt"])
@pytest.mark.parametrize("law", ["coulomb", "karnopp"])
@pytest.mark.parametrize("method", FIXED)
def test_coarse_steps_never_fail(scene, law, method):
    """At any step the stage has a solution on the law's graph with its jumps filled in: from
    rest and from a speed, up to h = 0.5 s."""
    for h in (0.05, 0.5):
        for v0 in (0.0, 3.0):
            r = ss.simulate(scene, law, method=method, h=h, t_end=10.0, n_out=3, v0=v0)
            assert np.all(np.isfinite(r.x))


# The errors the documentation predicts (docs/guide/implicit-nonsmooth.md, same table):
# (scene, law, method, control) -> status name. Every other pair at these controls succeeds
# or is refused before running with a ValueError.
PREDICTED = {
    ("belt", "lugre", "rk4", "h=1e-3"): "DIVERGED",
    ("belt", "lugre", "rk4", "h=1e-4"): "DIVERGED",
    ("belt", "elastoplastic", "rk4", "h=1e-3"): "DIVERGED",
    ("belt", "dahl", "rk4", "h=1e-3"): "DIVERGED",
    ("belt", "dahl", "rk4", "h=1e-4"): "DIVERGED",
}
FIXED_CONTROLS = {"h=1e-3": {"h": 1e-3}, "h=1e-4": {"h": 1e-4}}
ADAPTIVE_CONTROLS = {"rtol=1e-4": {"rtol": 1e-4, "atol": 1e-7}, "rtol=1e-6": {"rtol": 1e-6, "atol": 1e-9}}


def _unexpected(scene: str, predicted: dict, **params) -> tuple[list, set]:
    """Run every law x method of the registry on `scene` for `params`; return the outcomes
    that differ from `predicted` (absent: "ok" or "refused") and the predicted keys seen."""
    seen, unexpected = set(), []
    for law in ss.LAWS:
        for method in ss.METHODS:
            adaptive = ss.REGISTRY["method"][method].get("adaptive", False)
            for label, ctl in (ADAPTIVE_CONTROLS if adaptive else FIXED_CONTROLS).items():
                key = (scene, law, method, label)
                try:
                    ss.simulate(scene, law, method=method, n_out=3, **ctl, **params)
                    outcome = "ok"
                except ValueError as exc:    # refused before running: must say why
                    assert str(exc), key
                    outcome = "refused"
                except ss.IntegrationError as exc:
                    outcome = next(n for n, c in ss.REGISTRY["status"].items() if c == exc.status)
                if key in predicted:
                    seen.add(key)
                    if outcome != predicted[key]:
                        unexpected.append((key, outcome))
                elif outcome not in ("ok", "refused"):
                    unexpected.append((key, outcome))
    return unexpected, seen


def test_every_pair():
    """Every law x method (from the registry, so new ones join) on both scenes for 1 s at the
    paper's steps (fixed-step methods) or tolerances (adaptive ones)."""
    unexpected, seen = [], set()
    for scene in ("slope", "belt"):
        u, s = _unexpected(scene, PREDICTED, t_end=1.0)
        unexpected += u
        seen |= s
    assert not unexpected, unexpected
    assert seen == set(PREDICTED)


# The belt started stuck (v0 = v_b, relative velocity 0), 1 s: the errors the documentation
# predicts (docs/guide/implicit-nonsmooth.md): the bristle laws' RK4 runs blow up as from rest.
# (The proposed law's infinite slope at v_rel = 0 defeated generalized-alpha's Newton iteration
# at h = 1e-4 s; the scene's bracketed scalar stage now solves it: test below.)
PREDICTED_STUCK = {
    ("belt", "lugre", "rk4", "h=1e-3"): "DIVERGED",
    ("belt", "elastoplastic", "rk4", "h=1e-3"): "DIVERGED",
    ("belt", "elastoplastic", "rk4", "h=1e-4"): "DIVERGED",
    ("belt", "dahl", "rk4", "h=1e-3"): "DIVERGED",
}


# The chain (3 blocks, started stuck on the belt, 0.2 s): the errors the documentation predicts
# (docs/guide/chain.md, same table). The fixed-step implicit methods solve Coulomb and Karnopp
# on the chain over every contact's modes (stickslip_modal_contacts); the proposed law's
# infinite slope at v_rel = 0 (where every block starts), which defeats their Newton iteration,
# is solved by the chain's own stage solve (Gauss-Seidel over the blocks' bracketed roots).
PREDICTED_CHAIN = {
    ("chain", "lugre", "rk4", "h=1e-3"): "DIVERGED",
    ("chain", "elastoplastic", "rk4", "h=1e-3"): "DIVERGED",
    ("chain", "dahl", "rk4", "h=1e-3"): "DIVERGED",
}


@pytest.mark.parametrize("scene, predicted, kw", [
    ("belt", PREDICTED_STUCK, dict(t_end=1.0, v0=ss.DEFAULTS["v_b"])),
    ("chain", PREDICTED_CHAIN, dict(t_end=0.2, n_blocks=3)),
], ids=["belt_started_stuck", "chain"])
def test_every_pair_started_stuck(scene, predicted, kw):
    """Every law x method started stuck on the belt (the relative velocity at the laws' kink):
    the belt, and a 3-block chain. Each completes, is refused before running, or ends in
    exactly the predicted error."""
    unexpected, seen = _unexpected(scene, predicted, **kw)
    assert not unexpected, unexpected
    assert seen == set(predicted)


def test_proposed_law_started_stuck_converges_at_the_methods_order():
    """The proposed law (mu ~ |v_rel|^(1/3) at rest) on the belt started stuck: Newton's
    method cycles at the cusp, the scene's bracketed scalar stage solves it; generalized-alpha
    converges at second order and implicit Euler at first against RADAU5 at rtol 1e-11."""
    kw = dict(t_end=1.0, v0=ss.DEFAULTS["v_b"], n_out=11)
    ref = ss.simulate("belt", "proposed", method="radau5", rtol=1e-11, atol=1e-13, **kw)
    for method, order in (("galpha", 2.0), ("implicit_euler", 1.0)):
        errs = [np.max(np.abs(ss.simulate("belt", "proposed", method=method, h=h, **kw).x - ref.x))
                for h in (1e-3, 1e-4)]
        assert 0.8 * order < np.log10(errs[0] / errs[1]) < 1.3 * order, (method, errs)


def test_proposed_law_on_the_chain_started_stuck():
    """The proposed law on a 3-block chain started stuck (every block at the law's cusp, where
    Newton's method fails and the chain's stage solve by Gauss-Seidel over the blocks' bracketed
    roots takes over): generalized-alpha converges at second order and implicit Euler at first
    against RADAU5 at rtol 1e-12, as on the belt. (Before: galpha's error grew as h shrank, 6.5e-6
    m at h = 1e-3 s, 6.7e-5 m at 1e-4 s: a stuck block's stage acceleration taken from f at its
    root, where the cusp makes f jump by ~1e-4 m/s^2 between neighbouring floats, and a damped
    Newton iteration declared converged on a step shortened by its line search.)"""
    kw = dict(n_blocks=3, t_end=1.0, v0=ss.DEFAULTS["v_b"], n_out=11)
    ref = ss.simulate("chain", "proposed", method="radau5", rtol=1e-12, atol=1e-14, **kw)
    for method, order in (("galpha", 2.0), ("implicit_euler", 1.0)):
        errs = [np.max(np.abs(ss.simulate("chain", "proposed", method=method, h=h, **kw).x - ref.x))
                for h in (1e-3, 1e-4)]
        assert 0.8 * order < np.log10(errs[0] / errs[1]) < 1.3 * order, (method, errs)


CHAIN5 = dict(n_blocks=5, t_end=10.0, n_out=1001)


def test_coulomb_chain_converges_to_event_driven_at_first_order():
    """Coulomb on a 5-block chain (several contacts: each step over every contact's modes,
    stickslip_modal_contacts): implicit_euler converges at first order to event_driven
    (rtol 1e-11). galpha (backward Euler steps where a mode changes, its own steps within slip
    phases) converges at first order across the transitions too, with a smaller error, where
    v_s is small enough (1e-4 m/s) for the band's own effect (about 3.5e-3 m at the default
    v_s = 1e-2 m/s, where both methods level off) to stay below its error. It is not moreau
    with theta = 1: the smooth law's band (mu_s for 0 < |v_rel| < v_s) keeps them apart by a
    distance that does not vanish with h, and shrinks with v_s."""
    ref = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-11, atol=1e-13, **CHAIN5)
    assert ref.stats["nevents"] >= 4
    hs = [2e-3, 1e-3, 5e-4, 2.5e-4]
    errs, gaps = [], {}
    for h in hs:
        r = ss.simulate("chain", "coulomb", method="implicit_euler", h=h, **CHAIN5)
        errs.append(np.max(np.abs(r.x - ref.x)))
        assert r.stats["contact_residual"] < 1e-12
    order = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    assert 0.8 < order < 1.3 and errs[-1] < 1e-2, errs
    ref = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-11, atol=1e-13, v_s=1e-4, **CHAIN5)
    errs, gerrs = [], []
    for h in hs[1:]:
        g = ss.simulate("chain", "coulomb", method="galpha", h=h, v_s=1e-4, **CHAIN5)
        gerrs.append(np.max(np.abs(g.x - ref.x)))
        assert g.stats["contact_residual"] < 1e-12
        r = ss.simulate("chain", "coulomb", method="implicit_euler", h=h, v_s=1e-4, **CHAIN5)
        errs.append(np.max(np.abs(r.x - ref.x)))
    order = np.polyfit(np.log(hs[1:]), np.log(gerrs), 1)[0]
    assert 0.8 < order < 1.3 and np.all(np.array(gerrs) < 0.5 * np.array(errs)), (gerrs, errs)
    for v_s in (1e-2, 1e-4):
        r = ss.simulate("chain", "coulomb", method="implicit_euler", h=5e-4, v_s=v_s, **CHAIN5)
        m = ss.simulate("chain", "coulomb", method="moreau", theta=1.0, h=5e-4, **CHAIN5)
        gaps[v_s] = np.max(np.abs(r.x - m.x))
    assert 1e-5 < gaps[1e-4] < gaps[1e-2] < 5e-3, gaps


@pytest.mark.parametrize("rho_inf", [0.0, 0.5, 1.0])
def test_galpha_chain_in_slip_converges_at_second_order(rho_inf):
    """A 5-block Coulomb chain started at rest with the belt moving, over an interval in which every
    block slips faster than v_s (no transition: event_driven records no event): galpha takes
    its own steps there (stickslip_modal_contacts; only its first step, before the modes are
    known, is backward Euler) and converges at second order to event_driven (rtol 1e-12);
    implicit_euler at first order."""
    kw = dict(n_blocks=5, t_end=0.3, n_out=31, v0=0.0)
    ref = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-12, atol=1e-14, **kw)
    assert ref.stats["nevents"] == 0
    assert np.min(ss.DEFAULTS["v_b"] - ref.v) > 10.0 * ss.DEFAULTS["v_s"]     # all slip, beyond v_s
    hs = [2e-3, 1e-3, 5e-4, 2.5e-4]
    for method, order, opts in (("galpha", 2.0, {"rho_inf": rho_inf}), ("implicit_euler", 1.0, {})):
        errs = [np.max(np.abs(ss.simulate("chain", "coulomb", method=method, h=h, **opts, **kw).x - ref.x))
                for h in hs]
        fitted = np.polyfit(np.log(hs), np.log(errs), 1)[0]
        assert 0.85 * order < fitted < 1.2 * order, (method, errs)


def test_chain_steps_solve_the_law_graph_with_its_band():
    """What implicit_euler solves on several contacts, checked step by step from its output:
    each block's backward Euler step (v1 - v0)/h = -(K x1)_i/m + mu_i g_i has mu_i on the
    smooth Coulomb law's graph at the step's end (|mu| = mu_k beyond v_s, mu_s inside the band
    0 < |v_rel| < v_s, between at |v_rel| = v_s, |mu| <= mu_s stuck), written out here."""
    d = ss.DEFAULTS
    nb, h, v_s = 4, 1e-3, 0.05
    r = ss.simulate("chain", "coulomb", method="implicit_euler", h=h, t_end=3.0, n_blocks=nb, v_s=v_s,
                    every_step=True)
    m, k, kc, g0 = d["m"], d["k"], d["k"], d["g"]
    phi = (np.sqrt(5.0) - 1.0) / 2.0
    rr = 0.5 + np.arange(nb) * phi
    gi = g0 * (1.0 + d["perturbation"] * (2.0 * (rr - np.floor(rr)) - 1.0))
    x, v = r.x, r.v
    kx = np.zeros_like(x)
    kx[0] += k * x[0]
    kx[1:] += kc * (x[1:] - x[:-1])
    kx[:-1] += kc * (x[:-1] - x[1:])
    mu = ((v[:, 1:] - v[:, :-1]) / h + kx[:, 1:] / m) / gi[:, None]
    w = d["v_b"] - v[:, 1:]                       # the law's relative velocity at the step's end
    tol = 1e-9
    band = (np.abs(w) > tol) & (np.abs(w) < v_s - tol)
    slip = np.abs(w) > v_s + tol
    edge = np.abs(np.abs(w) - v_s) <= tol
    stuck = np.abs(w) <= tol
    assert band.any() and slip.any() and stuck.any()
    np.testing.assert_allclose(mu[band], d["mu_s"] * np.sign(w[band]), atol=1e-6)
    np.testing.assert_allclose(mu[slip], d["mu_k"] * np.sign(w[slip]), atol=1e-6)
    assert np.all(np.abs(mu[stuck]) <= d["mu_s"] + 1e-6)
    assert np.all((np.abs(mu[edge]) >= d["mu_k"] - 1e-6) & (np.abs(mu[edge]) <= d["mu_s"] + 1e-6))
    assert np.all(w[stuck] == 0.0)                 # a stuck block keeps v = v_b exactly


@pytest.mark.parametrize("method", FIXED)
def test_karnopp_chain_converges_at_first_order(method):
    """Karnopp on a 5-block chain under the fixed-step implicit methods (over its modes:
    slip, band edges, hold, saturated band): every step size completes, and the differences
    between successive halvings of h halve (first order)."""
    kw = dict(n_blocks=5, t_end=3.0, n_out=301)
    xs = [ss.simulate("chain", "karnopp", method=method, h=h, **kw).x for h in (1e-3, 5e-4, 2.5e-4, 1.25e-4)]
    diffs = [np.max(np.abs(a - b)) for a, b in zip(xs[:-1], xs[1:])]
    rates = np.log2(np.array(diffs[:-1]) / np.array(diffs[1:]))
    assert np.all(np.abs(rates - 1.0) < 0.2) and diffs[-1] < 2e-3, (diffs, rates)


@pytest.mark.parametrize("method, order", [("implicit_euler", 1), ("galpha", 2)])
def test_lugre_belt_from_rest_converges(method, order):
    """LuGre on the belt from rest: the first stage's guess carries the bristle rate
    v_rel = 1.5 m/s, and Newton from it is drawn onto the kink of |v_rel| (the rest-guess
    fallback solves it). Every step size completes and the velocity at t = 2 s converges at the
    method's order to RADAU5 at rtol = 1e-11."""
    ref = ss.simulate("belt", "lugre", method="radau5", rtol=1e-11, atol=1e-13, t_end=2.0, n_out=3)
    steps = [1e-2, 5e-3, 2.5e-3, 1.25e-3] if order == 1 else [5e-3, 2.5e-3, 1.25e-3]
    err = [abs(ss.simulate("belt", "lugre", method=method, h=h, t_end=2.0, n_out=3).v[-1] - ref.v[-1])
           for h in steps]
    rates = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(rates - order) < 0.3), (err, rates)


@pytest.mark.parametrize("law", ["coulomb", "karnopp"])
@pytest.mark.parametrize("method", FIXED)
def test_no_normal_force_moves_freely(law, method):
    """g = 0: no normal force, so friction has no effect whatever mu the modes pick: the box
    keeps its speed (x = v0 t), from rest it stays (no mode is left without a solution)."""
    for v0 in (0.0, 1.0, -0.5):
        r = ss.simulate("slope", law, method=method, h=1e-2, t_end=2.0, n_out=5, g=0.0, v0=v0)
        np.testing.assert_allclose(r.x, v0 * r.t, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(r.v, v0, rtol=1e-12, atol=0.0)


# GMS under the fixed-step implicit methods: each element's stage is solved in closed form
# (stick, relax, or pinned on its slip level: the Filippov solution, where Newton's method on
# the law's rates has none), mu takes the stage's rates, and Newton runs on the condensed
# stage with its own matrix. Checked against RADAU5 at rtol = 1e-10 (which agrees with DOP853
# at rtol = 1e-11 to 1.2e-10 m on the slope, 6e-6 m on the belt): implicit Euler converges at
# first order, and so does every run started stuck on the belt through its break-away.
GMS_CASES = [("slope", {}), ("belt", {}), ("belt", {"v0": 1.5}), ("chain", {"n_blocks": 3})]


def _gms_errors(scene: str, method: str, kw: dict) -> list[float]:
    """Largest position error at h = 1e-3 and 1e-4 s against RADAU5 at rtol = 1e-10 (0.5 s)."""
    ref = ss.simulate(scene, "gms", method="radau5", rtol=1e-10, atol=1e-13, t_end=0.5, n_out=21, **kw)
    return [np.abs(ss.simulate(scene, "gms", method=method, h=h, t_end=0.5, n_out=21, **kw).x - ref.x).max()
            for h in (1e-3, 1e-4)]


@pytest.mark.parametrize("scene, kw", GMS_CASES, ids=["slope", "belt", "belt-stuck", "chain"])
def test_gms_under_implicit_euler_converges_at_first_order(scene, kw):
    errs = _gms_errors(scene, "implicit_euler", kw)
    assert 5.0 < errs[0] / errs[1] < 20.0, errs       # first order: about 10 for a tenfold step


@pytest.mark.parametrize("scene, kw", GMS_CASES, ids=["slope", "belt", "belt-stuck", "chain"])
def test_gms_under_galpha_converges(scene, kw):
    errs = _gms_errors(scene, "galpha", kw)
    assert errs[1] < errs[0] < 5e-3, errs


@pytest.mark.parametrize("method", ["implicit_euler", "galpha"])
def test_gms_chain_banded_equals_dense(method):
    kw = dict(method=method, h=1e-3, t_end=0.5, n_out=21, n_blocks=12)
    band = ss.simulate("chain", "gms", banded=True, **kw)
    dense = ss.simulate("chain", "gms", banded=False, **kw)
    np.testing.assert_allclose(band.x, dense.x, rtol=0, atol=1e-10)
    assert band.stats["nstep"] == dense.stats["nstep"] == 500
    assert band.stats["nfev"] < dense.stats["nfev"]          # grouped differences: fewer evaluations


# --- The step problem over the laws' modes, against an exhaustive reference -----------------------
#: Modes of the Coulomb law with its band (fortran/laws/stickslip_law_coulomb.f90's band_mode),
#: written out here: (kind, value), kind "mu" a slip piece, "v" a point of the velocity axis.
def _band_modes(mu_s: float, mu_k: float, v_s: float) -> list[tuple[str, float]]:
    return [("mu", -mu_k), ("v", -v_s), ("mu", -mu_s), ("v", 0.0), ("mu", mu_s), ("v", v_s), ("mu", mu_k)]


def _on_mode(j: int, v: float, mu: float, mu_s: float, mu_k: float, v_s: float, tol: float) -> bool:
    """(v, mu) on mode j (0-based) of the band graph, to tol (relative to 1)."""
    lo_hi = [(-np.inf, -v_s), (-mu_s, -mu_k), (-v_s, 0.0), (-mu_s, mu_s), (0.0, v_s), (mu_k, mu_s), (v_s, np.inf)]
    lo, hi = lo_hi[j]
    x = v if j % 2 == 0 else mu
    return lo - tol <= x <= hi + tol


def _local_modes(a: float, dii: float, c: float, law: tuple[float, float, float], tol: float):
    """Contact i's one-contact problem w = a + dii p, p = c mu(v = -w) on the band graph: the
    velocity w of each consistent mode (None where the mode is not consistent)."""
    out = []
    for j, (kind, val) in enumerate(_band_modes(*law)):
        if kind == "mu":
            p = c * val
            w = a + dii * p
        else:
            w = -val
            p = (w - a) / dii
        out.append(w if _on_mode(j, -w, p / c, *law, tol) else None)
    return out


def _check_modal_steps(r, mass, kmat, hmat, b, normal, laws, h):
    """Every backward Euler step of `r` (every_step) on the linear system M u' = -K q + H^T r:
    its impulses p from the output, (a) on the band graph, (b) among the solutions that an
    exhaustive search over all 7^n mode combinations finds, equal to it where it is the only
    one, (c) each contact stuck where its own problem given the others' impulses lets it stick
    (static first) and otherwise on a consistent slip; and the steps where some slipping
    contact's own problem had another consistent slip counted as stats['nonunique'], the first
    of them at stats['t_nonunique']. Returns the count."""
    n_dof = len(mass)
    m = np.diag(mass)
    w_mat = m + h * h * kmat
    winv = np.linalg.inv(w_mat)
    dmat = hmat @ winv @ hmat.T
    c = h * np.asarray(normal)
    y = np.vstack([r.x, r.v]) if r.x.ndim == 2 else np.vstack([r.x[None], r.v[None]])
    q, u = y[:n_dof], y[n_dof:]
    ties = 0
    unique_steps = 0
    for s in range(q.shape[1] - 1):
        uf = u[:, s] + winv @ (h * (-kmat @ (q[:, s] + h * u[:, s])))
        wf = hmat @ uf + b
        p = np.linalg.lstsq(hmat.T, w_mat @ (u[:, s + 1] - uf), rcond=None)[0]
        w = hmat @ u[:, s + 1] + b
        scale = max(1.0, np.max(np.abs(wf)))
        tol = 1e-9 * scale
        # (a) the graph
        for i, law in enumerate(laws):
            assert any(_on_mode(j, -w[i], p[i] / c[i], *law, 1e-7) for j in range(7)), (s, i, w[i], p[i] / c[i])
        # (b) exhaustive search over the modes of all contacts
        sols = []
        for combo in itertools.product(range(7), repeat=len(c)):
            pp = np.zeros(len(c))
            fixed = [i for i, j in enumerate(combo) if j % 2 == 1]          # points: w fixed
            for i, j in enumerate(combo):
                if j % 2 == 0:
                    pp[i] = c[i] * _band_modes(*laws[i])[j][1]
            if fixed:
                wt = np.array([-_band_modes(*laws[i])[combo[i]][1] for i in fixed])
                free = [i for i in range(len(c)) if i not in fixed]
                rhs = wt - wf[fixed] - dmat[np.ix_(fixed, free)] @ pp[free]
                pp[fixed] = np.linalg.solve(dmat[np.ix_(fixed, fixed)], rhs)
            ww = wf + dmat @ pp
            if all(_on_mode(j, -ww[i], pp[i] / c[i], *laws[i], 1e-9) for i, j in enumerate(combo)):
                if not any(np.max(np.abs(ww - x)) <= tol for x in sols):
                    sols.append(ww)
        assert any(np.max(np.abs(w - x)) <= 1e-7 * scale for x in sols), (s, w, sols)
        unique_steps += len(sols) == 1
        # (c) the rule, contact by contact given the others
        other = False
        for i, law in enumerate(laws):
            a = w[i] - dmat[i, i] * p[i]
            ws = _local_modes(a, dmat[i, i], c[i], law, 1e-9)
            if ws[3] is not None:                       # it can stick: it sticks
                assert abs(w[i]) <= 1e-9 * scale, (s, i, ws, w[i])
            assert any(x is not None and abs(x - w[i]) <= 1e-7 * scale for x in ws), (s, i, ws, w[i])
            if abs(w[i]) > 1e-9 * scale:                # another slip: as many stuck contacts
                other |= any(x is not None and j != 3 and abs(x - w[i]) > 1e-7 * scale for j, x in enumerate(ws))
        if other and not ties:
            assert abs(r.stats["t_nonunique"] - r.t[s + 1]) <= 1e-12 * max(1.0, r.t[-1]), (r.stats["t_nonunique"], s)
        ties += other
    assert unique_steps > 0
    return ties


@pytest.mark.parametrize("h", [1e-3, 2e-2])
def test_modal_steps_of_coupled_contacts_follow_the_rule(h):
    """Two coupled contacts with the band (block A on a belt, block B on A: the dense Delassus
    path of the contact module's modal solve) under implicit_euler, step by step against the
    exhaustive reference above; the steps with another consistent mode are stats['nonunique']."""
    v_b, v_s, g = 0.2, 0.05, 9.81
    laws = [(0.5, 0.3, v_s), (0.25, 0.2, v_s)]
    model = ss.Model()
    a = model.add_body(1.0)
    bb = model.add_body(0.5)
    model.add_spring(a, None, k=100.0)
    model.add_spring(bb, None, k=40.0)
    model.add_contact(a, None, "coulomb", normal_force=1.5 * g, surface_velocity=v_b, mu_s=0.5, mu_k=0.3, v_s=v_s)
    model.add_contact(bb, a, "coulomb", normal_force=0.5 * g, mu_s=0.25, mu_k=0.2, v_s=v_s)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = ss.simulate(model, method="implicit_euler", h=h, t_end=3.0, every_step=True)
    ties = _check_modal_steps(r, [1.0, 0.5], np.diag([100.0, 40.0]), np.array([[1.0, 0.0], [-1.0, 1.0]]),
                              np.array([-v_b, 0.0]), [1.5 * g, 0.5 * g], laws, h)
    assert r.stats["nonunique"] == ties


def test_modal_steps_of_a_chain_follow_the_rule():
    """Three blocks on a belt joined by springs (W tridiagonal, one contact on each coordinate:
    the contact module's O(n) sweeps on W) under implicit_euler, against the same reference."""
    v_b, v_s, g, k, kc = 0.3, 0.02, 9.81, 50.0, 30.0
    laws = [(0.4, 0.3, v_s), (0.35, 0.3, v_s), (0.45, 0.25, v_s)]
    masses = [1.0, 0.7, 1.3]
    model = ss.Model()
    bodies = [model.add_body(mi) for mi in masses]
    model.add_spring(bodies[0], None, k=k)
    for i in range(2):
        model.add_spring(bodies[i], bodies[i + 1], k=kc)
    for bi, mi, (mu_s, mu_k, vs) in zip(bodies, masses, laws):
        model.add_contact(bi, None, "coulomb", normal_force=mi * g, surface_velocity=v_b, mu_s=mu_s, mu_k=mu_k, v_s=vs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = ss.simulate(model, method="implicit_euler", h=2e-3, t_end=3.0, every_step=True)
    kmat = np.array([[k + kc, -kc, 0.0], [-kc, 2 * kc, -kc], [0.0, -kc, kc]])
    ties = _check_modal_steps(r, masses, kmat, np.eye(3), np.full(3, -v_b), [mi * g for mi in masses], laws, 2e-3)
    assert r.stats["nonunique"] == ties


@pytest.mark.parametrize("method", FIXED)
@pytest.mark.parametrize("h", [1e-2, 3e-3])
def test_one_contact_steps_stick_first_where_both_hold(method, h):
    """The slope with Coulomb's band far narrower than a step's velocity change under static
    friction (h g (mu_s - mu_k) cos th > v_s): near the stop, a step could end stuck or still
    slipping at mu_k. The contact module's rule (static first, then keep a slip) sticks there;
    each step is checked against it from the output alone: where the backward Euler step could
    end stuck, |v/h + g sin th| <= mu_s g cos th, it ends stuck (v = 0, x unchanged); otherwise
    it keeps slipping. (Before, the kept slip mode of the one-contact path slid on for three
    steps past that point, from 0.044 m/s at h = 1e-2.)"""
    theta, mu_s, mu_k, v_s, v0 = 10.0, 0.7, 0.3, 1e-3, 1.0
    th = math.radians(theta)
    assert h * G * (mu_s - mu_k) * math.cos(th) > v_s
    r = ss.simulate("slope", "coulomb", method=method, h=h, t_end=1.0, every_step=True, v0=v0,
                    theta_deg=theta, mu_k=mu_k, mu_s=mu_s, v_s=v_s)
    holds = np.abs(r.v[:-1] / h + G * math.sin(th)) <= mu_s * G * math.cos(th) * (1.0 + 1e-12)
    first = int(np.argmax(holds))
    assert holds.any() and r.v[first] > v_s            # it could stick while still slipping
    assert np.all(r.v[first + 1:] == 0.0) and np.all(r.x[first + 1:] == r.x[first])
    assert np.all(r.v[1:first + 1] > v_s)               # and slipped until then


@pytest.mark.parametrize("h", [1e-2, 3e-3])
def test_galpha_slip_steps_of_several_contacts_stick_first(h):
    """Generalized-alpha's own steps while every contact slips (stickslip_modal_contacts) are
    kept only where no contact could stick in the backward Euler step: two bodies sliding down
    slopes (force g sin th, normal force g cos th, Coulomb's band far narrower than a step's
    velocity change), from 1.0 and 0.6 m/s. Each body is checked step by step from the output:
    where its backward Euler step could end stuck, |v/h + g sin th| <= mu_s g cos th, the step
    ends stuck and it stays there; until then it slips."""
    theta, mu_s, mu_k, v_s = 10.0, 0.7, 0.3, 1e-3
    th = math.radians(theta)
    m = ss.Model()
    for v0 in (1.0, 0.6):
        b = m.add_body(1.0, v0=v0)
        m.add_force(b, G * math.sin(th))
        m.add_contact(b, None, "coulomb", normal_force=G * math.cos(th), mu_s=mu_s, mu_k=mu_k, v_s=v_s)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = ss.simulate(m, method="galpha", h=h, t_end=1.0, every_step=True)
    for x, v in zip(r.x, r.v):
        holds = np.abs(v[:-1] / h + G * math.sin(th)) <= mu_s * G * math.cos(th) * (1.0 + 1e-12)
        first = int(np.argmax(holds))
        assert holds.any() and v[first] > v_s
        assert np.all(v[first + 1:] == 0.0) and np.all(x[first + 1:] == x[first])
        assert np.all(v[1:first + 1] > v_s)
