"""Forced steps at h_min (Coulomb's jumps) and the step growth after them: the controls
fac_forced and calm_steps shared by DOPRI5 and RADAU5."""
from __future__ import annotations

import math

import pytest

import stickslip as ss


def test_chatter_at_hmin_takes_every_step_there_without_rejections():
    # Coulomb holds the box on the 10 degree slope; event-free, v chatters about 0 and every
    # step sits at h_min = 1e-6 s: exactly t_end / h_min accepted steps. Before calm_steps
    # each single pass of the error test grew h, and the next step was rejected.
    t_end, hmin = 0.5, 1e-6
    r = ss.simulate("slope", "coulomb", method="dopri5", t_end=t_end, hmin=hmin)
    assert r.stats["naccept"] == round(t_end / hmin)
    assert r.stats["nreject"] == 0 and r.stats["nforced"] > 0.5 * t_end / hmin
    old = ss.simulate("slope", "coulomb", method="dopri5", t_end=t_end, hmin=hmin, calm_steps=0)
    assert old.stats["nreject"] > 0.2 * t_end / hmin
    assert old.stats["naccept"] == r.stats["naccept"]
    # RADAU5 also forces steps where Newton fails at h_min: fewer steps, not none rejected
    a = ss.simulate("slope", "coulomb", method="radau5", t_end=t_end, hmin=hmin)
    b = ss.simulate("slope", "coulomb", method="radau5", t_end=t_end, hmin=hmin, calm_steps=0)
    assert a.stats["nfev"] < 0.9 * b.stats["nfev"]


@pytest.mark.parametrize("method", ["dopri5", "radau5"])
def test_step_grows_again_after_the_jump(method: str) -> None:
    # On a 25 degree slope (tan 25 deg > mu_s) the box slides from rest; Coulomb's jump from
    # mu_s to mu_k at v_s forces a step, after which the motion is smooth again. Exact:
    # a1 = g (sin - mu_s cos) up to v_s, then a2 = g (sin - mu_k cos).
    p = ss.DEFAULTS
    th, t_end = math.radians(25.0), 2.0
    a1 = p["g"] * (math.sin(th) - p["mu_s"] * math.cos(th))
    a2 = p["g"] * (math.sin(th) - p["mu_k"] * math.cos(th))
    t1 = p["v_s"] / a1
    exact = p["v_s"] ** 2 / (2 * a1) + p["v_s"] * (t_end - t1) + a2 * (t_end - t1) ** 2 / 2
    kw = dict(t_end=t_end, theta_deg=25.0, rtol=1e-8, atol=1e-11)
    r = ss.simulate("slope", "coulomb", method=method, **kw)
    plain = ss.simulate("slope", "coulomb", method=method, calm_steps=0, **kw)
    assert r.stats["nforced"] >= 1
    assert abs(r.x[-1] - exact) < 1e-5
    # the wait costs a step or two, not a run at h_min (which would be 2e6 steps)
    assert r.stats["nstep"] <= plain.stats["nstep"] + 2


@pytest.mark.parametrize("control, value", [("fac_forced", 1.0), ("fac_forced", math.inf),
                                            ("calm_steps", -1.0), ("fac_forced", 0.5)])
def test_bad_forced_growth_controls_are_named(control: str, value: float) -> None:
    # the facade refuses inf itself, the library the rest; both name the control
    with pytest.raises(ValueError, match=r"^fac_forced: must be finite|calm_steps: an integer >= 0"):
        ss.simulate("slope", "coulomb", method="dopri5", t_end=0.01, **{control: value})
