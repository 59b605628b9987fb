"""Bad input gets a ValueError naming the parameter and its range; a run that cannot finish
raises an IntegrationError carrying the partial result: never a crash, hang or silent NaN."""
from __future__ import annotations

import re

import numpy as np
import pytest

import stickslip as ss

NAN, INF = float("nan"), float("inf")


def sim(**kw):
    args = {"scene": "slope", "law": "proposed", "method": "dopri5", "t_end": 1.0}
    args.update(kw)
    return ss.simulate(args.pop("scene"), args.pop("law"), **args)


@pytest.mark.parametrize("kw,name,range_text", [
    ({"method": "rk4", "h": 0.0}, "h", "> 0"),
    ({"method": "rk4", "h": -1e-3}, "h", "> 0"),
    ({"method": "rk4", "h": NAN}, "h", "finite"),
    ({"method": "rk4"}, "h", "required"),
    ({"h": 1e-3}, "h", "not a control of method 'dopri5'"),
    ({"t_end": 0.0}, "t_end", r"> 0 \[s\] \(the run starts at t = 0\), got t_end = 0"),
    ({"t_end": -5.0}, "t_end", r"> 0 \[s\] \(the run starts at t = 0\), got t_end = -5"),
    ({"t_end": INF}, "t_end", "finite"),
    ({"mu_k": 0.5}, "mu_k", r">= 0 and <= mu_s"),
    ({"v_s": 0.0}, "v_s", "> 0"),
    ({"law": "recurdyn", "v_d": 0.01}, "v_d", "> v_s"),
    ({"a": 1.0}, "a", "> 1"),
    ({"beta": -0.1}, "beta", "> 0"),
    ({"rtol": 1.0}, "rtol", r"1\)"),
    ({"rtol": 1e-16}, "rtol", "2.2e-14"),
    ({"rtol": -1e-6}, "rtol", "rtol"),
    ({"atol": -1e-9}, "atol", "> 0"),
    ({"rtol": 1e-6, "atol": 0.0}, "atol", "> 0"),
    ({"hmin": -1.0}, "hmin", ">= 0"),
    ({"t_end": 1e-7}, "hmin", r"<= t_end \[s\] \(got hmin = 1e-06, t_end = 1e-07\)"),
    ({"hmax": 1e-7}, "hmax", ">= hmin"),
    ({"hmax": -1.0}, "hmax", "> 0"),
    ({"h0": -1.0}, "h0", ">= 0"),
    ({"n_out": 0}, "n_out", "integer"),
    ({"n_out": 2.5}, "n_out", "integer"),
    ({"max_steps": 0}, "max_steps", ">= 1"),
    ({"x0": NAN}, "x0", "finite"),
    ({"v0": INF}, "v0", "finite"),
    ({"theta_deg": 95.0}, "theta_deg", r"\[-90, 90\]"),
    ({"scene": "belt", "m": 0.0}, "m", "> 0"),
    ({"scene": "belt", "k": -1.0}, "k", ">= 0"),
    ({"scene": "belt", "v_b": NAN}, "v_b", "finite"),
    ({"g": -9.81}, "g", ">= 0"),
    ({"scene": "ramp"}, "scene", "slope, belt"),
    ({"law": "bristle"}, "law", "coulomb, recurdyn, proposed"),
    ({"method": "euler"}, "method", "rk4, dopri5"),
    ({"mass": 1.0}, "mass", "unknown parameter"),
    ({"every_step": True, "n_out": 10}, "n_out", "not both"),
    ({"every_step": True, "max_steps": 10**9}, "max_steps", "rows"),
])
def test_bad_input_names_parameter(kw, name, range_text):
    with pytest.raises(ValueError) as err:
        sim(**kw)
    msg = str(err.value)
    assert msg.startswith(name) or f" {name}" in msg, msg
    assert re.search(range_text, msg), msg


def test_step_budget_exhausted_keeps_partial_result():
    with pytest.raises(ss.StepBudgetExhausted) as err:
        sim(scene="belt", t_end=20.0, max_steps=100)
    res = err.value.result
    assert res.stats["nstep"] == 100 and 0 < res.stats["t_reached"] < 20.0
    assert np.all(res.t <= res.stats["t_reached"]) and np.all(np.isfinite(res.x))
    assert "max_steps" in str(err.value)
    # a fixed-step run that cannot finish is refused before it starts, naming max_steps and the need
    with pytest.raises(ValueError, match=r"max_steps: rk4 with h = 0.001 s needs 1000 steps"):
        sim(method="rk4", h=1e-3, max_steps=10)


def test_forced_steps_can_be_an_error():
    # Coulomb's jump at v = 0 defeats the error test at any step: DOPRI5 steps at h_min
    res = sim(law="coulomb", t_end=0.01)
    assert res.stats["nforced"] > 0
    with pytest.raises(ss.StepSizeTooSmall) as err:
        sim(law="coulomb", t_end=0.01, allow_forced=False)
    assert "h_min" in str(err.value)


def test_stiffness_reported_and_optionally_fatal():
    # creeping on the slope is stiff: h |lambda| sits at the stability limit
    res = sim(law="recurdyn", t_end=20.0)
    assert res.stats["stiff"] and res.stats["nstiff"] >= 15
    with pytest.raises(ss.StiffnessDetected) as err:
        sim(law="recurdyn", t_end=20.0, stop_on_stiff=True)
    assert err.value.result.stats["t_reached"] < 20.0


def test_blow_up_is_reported_not_nan():
    # an absurd RK4 step on a stiff spring diverges: the run stops with a clear status
    with pytest.raises(ss.NonFiniteSolution) as err, \
            pytest.warns(ss.UnstableStepWarning, match="shortest period"):   # and it says so first
        sim(scene="belt", law="coulomb", method="rk4", h=0.5, t_end=1e4, k=1e6)
    assert np.all(np.isfinite(err.value.result.x))


def test_integration_error_pickles():
    import pickle
    with pytest.raises(ss.StepBudgetExhausted) as err:
        sim(max_steps=3)
    back = pickle.loads(pickle.dumps(err.value))
    assert type(back) is ss.StepBudgetExhausted and back.status == err.value.status
    assert str(back) == str(err.value) and back.result.stats["nstep"] == 3
