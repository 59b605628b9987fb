"""The advisor (stickslip.advise, issue 21): following its advice meets the target error on
parameter sets no study used, checked against closed forms or RADAU5 and DOPRI5 at rtol = 1e-12;
its cost is within a factor 3 of the cheapest setting the grid search of cases.advise.brute_force
finds; it says when no method can (Coulomb, a target below round-off); bad input is a clear
ValueError."""
from __future__ import annotations

import importlib
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import stickslip as ss
from stickslip.advise import jacobian_eigenvalues, stability_bound
from stickslip.core import rk4_stability_bound

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from cases import advise as advise_cli  # noqa: E402
from cases.advise import brute_force, reference  # noqa: E402
from cases.workprecision import harmonic_x  # noqa: E402

BELT = dict(k=450.0, m=3.0, v_b=0.8)                      # no study used these
STRIBECK = dict(mu_s=0.4, mu_k=0.25, v_s=0.05, delta=1.5, v_eps=2e-3)


def _q(scene: str, law: str, method: str, t_end: float, quantity: str, **kw: float) -> float:
    r = ss.simulate(scene, law, method=method, t_end=t_end, n_out=2, **kw)
    return float((r.x if quantity == "x" else r.v)[-1])


def _assert_near_cheapest(a: ss.Advice, ref: float, **kw: float) -> None:
    """The advised run costs at most 3x the cheapest setting of any method that meets the target
    in the grid search of cases.advise.brute_force (costs: evaluations weighted by each method's
    seconds per evaluation measured over its grid runs)."""
    found = brute_force(a.scene, a.law, a.t_end, a.target_error, ref, quantity=a.quantity,
                        bound=a.stability_bound, **kw)
    cheapest = min(f["cost"] for f in found.values())
    assert a.predicted_cost["nfev"] * found[a.method]["weight"] <= 3.0 * cheapest, (a, found)


def _follow(a: ss.Advice, t_end: float, quantity: str, **kw: float) -> float:
    """The quantity at t_end of simulate run as advised (controls straight from the advice)."""
    assert a.feasible, a
    return _q(a.scene, a.law, a.method, t_end, quantity, **a.controls, **kw)


# --------------------------------------------------------------------------------------------
# Following the advice meets the target, at near the least cost
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("target", [1e-6, 1e-9])
def test_belt_harmonic_orbit_unseen_parameters(target: float) -> None:
    """Belt with k = 450 N/m, m = 3 kg, v_b = 0.8 m/s from rest, a Stribeck law of its own: the
    mass never gets near the belt speed (max x' = x_k w = 0.21 m/s), mu = mu_k throughout and
    x(t) = x_k (1 - cos w t) exactly. The advice meets the target against that closed form at a
    cost within 3x of the cheapest setting of any method that meets it."""
    t_end = 10.0
    p = dict(BELT, **STRIBECK)
    a = ss.advise("belt", "stribeck", target, t_end, **p)
    exact = harmonic_x(t_end, dict(ss.DEFAULTS, **p))
    assert abs(_follow(a, t_end, "x", **p) - exact) <= target
    assert a.predicted_error <= target
    _assert_near_cheapest(a, exact, **p)


def test_belt_velocity_target() -> None:
    """quantity="v": v(t) = x_k w sin(w t) on the same orbit."""
    t_end, target = 7.0, 1e-7
    p = dict(BELT, **STRIBECK)
    a = ss.advise("belt", "stribeck", target, t_end, quantity="v", **p)
    w = math.sqrt(p["k"] / p["m"])
    exact = p["mu_k"] * p["m"] * ss.DEFAULTS["g"] / p["k"] * w * math.sin(w * t_end)
    assert abs(_follow(a, t_end, "v", **p) - exact) <= target
    assert "velocity" in str(a)


def test_slope_sliding_at_constant_friction() -> None:
    """Slope at 25 deg (tan = 0.466 > mu_s), box started at 0.5 m/s: RecurDyn's mu = mu_k for
    v > v_d, so x = v0 t + g (sin - mu_k cos) t^2 / 2. Every method integrates a quadratic
    exactly: the advice is the cheapest pilot, its error round-off."""
    t_end, target, v0 = 4.0, 1e-8, 0.5
    a = ss.advise("slope", "recurdyn", target, t_end, v0=v0, theta_deg=25.0)
    th = math.radians(25.0)
    g, mu_k = ss.DEFAULTS["g"], ss.DEFAULTS["mu_k"]
    exact = v0 * t_end + 0.5 * g * (math.sin(th) - mu_k * math.cos(th)) * t_end ** 2
    assert abs(_follow(a, t_end, "x", v0=v0, theta_deg=25.0) - exact) <= target
    assert a.predicted_cost["nfev"] < 200


def test_slope_from_rest_stribeck_against_radau5() -> None:
    """Slope at 25 deg from rest with a Stribeck law of its own (the transition near v = 0 is
    crossed): against RADAU5 at rtol = 1e-12 (checked against DOPRI5 at the same tolerance), and
    within 3x of the brute-force cheapest."""
    t_end, target = 3.0, 1e-8
    p = dict(STRIBECK, theta_deg=25.0)
    a = ss.advise("slope", "stribeck", target, t_end, **p)
    ref = reference("slope", "stribeck", t_end, "x", **p)
    assert abs(_follow(a, t_end, "x", **p) - ref) <= target
    _assert_near_cheapest(a, ref, **p)


def test_slope_creep_unseen_parameters() -> None:
    """Slope at 8 deg with the RecurDyn law at v_s = 5 mm/s: the box creeps (stiff, |lambda| =
    g cos(theta) mu'(v*)). Implicit Euler's large steps look converged here (differences of
    3e-10 and 6e-10 m between h = 0.94, 0.47 and 0.23 s) but are 4.6e-7 m off: they skip the
    start-up transient. The cross-check against the other methods must refuse them."""
    t_end, target = 15.0, 1e-8
    p = dict(theta_deg=8.0, v_s=0.005)
    a = ss.advise("slope", "recurdyn", target, t_end, **p)
    assert a.method != "implicit_euler"
    ref = reference("slope", "recurdyn", t_end, "x", **p)
    assert abs(_follow(a, t_end, "x", **p) - ref) <= target
    _assert_near_cheapest(a, ref, **p)


def test_belt_stick_slip_proposed_against_tight_reference() -> None:
    """Belt started stuck (v0 = v_b) with the proposed law and unseen belt parameters: stick-slip,
    mu with an infinite slope at v = 0. The advice meets the target against RADAU5 and DOPRI5 at
    rtol = 1e-12; RK4 is never advised beyond its (tiny, in stick) stability bound."""
    t_end, target = 6.0, 1e-5
    a = ss.advise("belt", "proposed", target, t_end, v0=BELT["v_b"], **BELT)
    ref = reference("belt", "proposed", t_end, "x", v0=BELT["v_b"], **BELT)
    assert abs(_follow(a, t_end, "x", v0=BELT["v_b"], **BELT) - ref) <= target
    if a.method == "rk4":
        assert a.controls["h"] <= a.stability_bound


def test_methods_come_from_the_registry() -> None:
    """Every registered method is considered (a method added to the registry joins), and the
    candidates can be restricted."""
    a = ss.advise("belt", "stribeck", 1e-6, 5.0, **BELT)
    assert {c.method for c in a.candidates} == set(ss.METHODS)
    b = ss.advise("belt", "stribeck", 1e-6, 5.0, methods=["galpha"], **BELT)
    assert b.method == "galpha" and {c.method for c in b.candidates} == {"galpha"}
    assert set(b.controls) == {"h"}
    exact = harmonic_x(5.0, dict(ss.DEFAULTS, **BELT))
    assert abs(_follow(b, 5.0, "x", **BELT) - exact) <= 1e-6


def test_report_lists_runs_and_pilot_cost() -> None:
    a = ss.advise("belt", "recurdyn", 1e-6, 5.0, **BELT)
    assert a.runs and all(r.role in ("pilot", "verify", "survey", "check") for r in a.runs)
    assert a.pilot_cost["nfev"] == sum(r.nfev for r in a.runs)
    assert a.pilot_cost["ratio"] >= 1.0
    text = str(a)
    assert a.method in text and "pilot" in text and "evaluations" in text


# --------------------------------------------------------------------------------------------
# The stability bound from the Jacobian
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("law", ["recurdyn", "proposed"])
def test_jacobian_bound_matches_the_analytic_creep_bound(law: str) -> None:
    """At the creep speed on the slope the finite-difference Jacobian of the right-hand side
    gives RK4's bound 2.785/|lambda| as rk4_stability_bound does from mu' (within 1%)."""
    r = ss.simulate("slope", law, method="radau5", t_end=20.0, rtol=1e-10, atol=1e-13, hmax=0.0, n_out=2)
    state = np.array([[r.x[-1]], [r.v[-1]]])
    eig = jacobian_eigenvalues("slope", law, state, {})
    assert stability_bound(4, eig) == pytest.approx(rk4_stability_bound(law), rel=1e-2)


def test_stability_bound_on_the_imaginary_axis() -> None:
    """An undamped oscillation lambda = +-i w: RK4 is stable for h w <= 2 sqrt(2)."""
    w = 12.0
    assert stability_bound(4, np.array([1j * w, -1j * w])) == pytest.approx(2 * math.sqrt(2) / w, rel=1e-9)
    assert stability_bound(4, np.array([-100.0 + 0j])) == pytest.approx(2.785293563405282 / 100, rel=1e-9)


# --------------------------------------------------------------------------------------------
# When no method can
# --------------------------------------------------------------------------------------------
def test_coulomb_cannot_and_says_what_can() -> None:
    """Coulomb on the slope (the box should stick): event-free stepping converges at order 1 with
    chatter, DOPRI5 and RADAU5 are pinned at h_min; none of them reaches 1e-6 m, and the advice
    names the set-valued methods."""
    a = ss.advise("slope", "coulomb", 1e-6, 5.0, methods=("rk4", "dopri5", "radau5"))
    assert not a.feasible and a.method is None and a.controls == {}
    assert "jumps at v = 0" in a.message and "stribeck" in a.message
    for m in ("moreau", "event_driven"):
        if m in ss.METHODS:
            assert f"method={m!r}" in a.message


@pytest.mark.skipif("moreau" not in ss.METHODS, reason="no set-valued method registered")
def test_coulomb_with_every_method_finds_one_that_holds() -> None:
    """With every method that takes Coulomb (the set-valued ones, and the implicit fixed-step
    methods, which solve each stage over the law's modes), the advice is feasible and following
    it holds the box (the truth: x = 0) within the target; the event-free explicit and adaptive
    methods are not advised."""
    a = ss.advise("slope", "coulomb", 1e-6, 5.0)
    assert a.feasible and a.method in ("moreau", "event_driven", "implicit_euler", "galpha")
    r = ss.simulate("slope", "coulomb", method=a.method, t_end=5.0, **a.controls)
    assert abs(r.x[-1]) <= 1e-6


@pytest.mark.skipif("moreau" not in ss.METHODS, reason="no set-valued method registered")
def test_a_held_body_has_error_exactly_zero_and_nothing_below_round_off_is_printed() -> None:
    """The held box (x = 0 in every run): its error is exactly 0 and printed so, never as a
    number below what a double can represent (2.2e-314 m before); every printed error of the
    report is either "exactly 0", "round-off (...)" or at least the round-off level."""
    a = ss.advise("slope", "coulomb", 1e-6, 5.0)
    assert a.feasible and a.predicted_error == 0.0 and a.roundoff == 0.0
    text = str(a)
    assert "estimated error exactly 0," in text
    import re
    numbers = [float(x) for x in re.findall(r"(?<![\w.])\d\.?\d*e-\d+", text)]
    assert all(x >= 1e-300 for x in numbers), numbers
    from stickslip.advise import error_text
    assert error_text(0.0, 0.0) == "exactly 0"
    assert error_text(1e-17, 2e-14).startswith("round-off")
    assert error_text(3e-9, 2e-14) == "3e-09"


def test_fixed_steps_stay_within_the_scene_period() -> None:
    """No fixed step beyond a tenth of the belt's period 2 pi sqrt(m/k) (0.513 s at k = 450 N/m,
    m = 3 kg), even when the pilots' Jacobian shows no oscillation (omega = 0: a held body, or
    no adaptive survey reached t_end), where the ladders used to start at t_end/16 = 0.625 s."""
    adv = importlib.import_module("stickslip.advise")   # the module (stickslip.advise is the function)
    p = dict(BELT)
    period = 2 * math.pi * math.sqrt(p["m"] / p["k"])
    prob = adv._Problem("belt", "stribeck", 10.0, "x", 0.0, 0.0, adv._physical(p))
    lad = adv._pilot(prob, "implicit_euler", 1e-4, None, 0.0, math.inf, 0.0)
    hs = [r.controls["h"] for r in lad.runs + lad.failed]
    assert hs and max(hs) <= adv.PERIOD_FRACTION * period
    a = ss.advise("belt", "stribeck", 1e-4, 10.0, methods=["implicit_euler", "galpha"], **p)
    assert all(r.controls["h"] <= adv.PERIOD_FRACTION * period for r in a.runs if "h" in r.controls)


def test_order_one_method_alone_cannot_reach_a_tight_target() -> None:
    """Implicit Euler alone cannot reach 1e-12 m on the belt within max_steps (order 1): the
    advice says so and names the methods left out."""
    a = ss.advise("belt", "stribeck", 1e-12, 5.0, methods=["implicit_euler"], **BELT)
    assert not a.feasible and "dopri5" in a.message and "jumps" not in a.message


def test_target_below_roundoff_cannot() -> None:
    a = ss.advise("slope", "recurdyn", 1e-16, 4.0, v0=0.5, theta_deg=25.0)
    assert not a.feasible and "round-off" in a.message


# --------------------------------------------------------------------------------------------
# Bad input
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, match", [
    (dict(target_error=0.0), "target_error: must be a finite number > 0"),
    (dict(target_error=-1e-6), "target_error: must be a finite number > 0"),
    (dict(target_error=float("nan")), "target_error"),
    (dict(target_error="1e-6"), "target_error"),
    (dict(quantity="a"), "quantity: unknown value 'a'"),
    (dict(t_end=0.0), "t_end: must be a finite number > 0"),
    (dict(methods=["rk5"]), "method: unknown value 'rk5'"),
    (dict(methods=[]), "methods: give at least one"),
    (dict(h=1e-3), "h: controls are what advise chooses"),
    (dict(k=-1.0), "k"),
    (dict(spring=1.0), "unknown parameter"),
])
def test_bad_input_is_a_clear_value_error(kwargs: dict, match: str) -> None:
    args = dict(scene="belt", law="stribeck", target_error=1e-6, t_end=1.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        ss.advise(args.pop("scene"), args.pop("law"), args.pop("target_error"), args.pop("t_end"), **args)


def test_bad_scene_or_law() -> None:
    with pytest.raises(ValueError, match="scene: unknown value"):
        ss.advise("ramp", "stribeck", 1e-6, 1.0)
    with pytest.raises(ValueError, match="law: unknown value"):
        ss.advise("belt", "viscous", 1e-6, 1.0)
    with pytest.raises(ValueError, match="scene: advise takes the one-body scenes"):
        ss.advise("chain", "stribeck", 1e-6, 1.0)


# --------------------------------------------------------------------------------------------
# Command line
# --------------------------------------------------------------------------------------------
def test_cli_prints_the_table(capsys: pytest.CaptureFixture[str]) -> None:
    advise_cli.main(["--scene", "belt", "--law", "stribeck", "--target", "1e-6", "--t-end", "5",
                     "--param", "k=450", "--param", "m=3", "--param", "v_b=0.8"])
    out = capsys.readouterr().out
    assert "use method=" in out and "role" in out and "pilot" in out


def test_cli_brute_force_check(capsys: pytest.CaptureFixture[str]) -> None:
    """--brute-force reports the advised run's true error and its cost against the grid."""
    advise_cli.main(["--scene", "slope", "--law", "stribeck", "--target", "1e-7", "--t-end", "2",
                     "--param", "theta_deg=25", "--brute-force"])
    out = capsys.readouterr().out
    assert "brute force: reference" in out and "x the cheapest grid setting" in out


def test_cli_bad_input(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        advise_cli.main(["--scene", "belt", "--law", "stribeck", "--target", "0"])
    assert "--target" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        advise_cli.main(["--scene", "belt", "--law", "stribeck", "--target", "1e-6", "--param", "k"])
    assert "NAME=VALUE" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        advise_cli.main(["--scene", "belt", "--law", "stribeck", "--target", "1e-6", "--param", "k=-3"])
    assert "k" in capsys.readouterr().err


# -- a model (your own system) -------------------------------------------------------------------
def _two_body_model(law: str, **law_params: float) -> "ss.Model":
    """Two bodies, a spring between them and one to the ground, a force that steps at 0.3 s, a
    contact on a moving surface and one between the bodies (cases.model_pairs)."""
    from cases.model_pairs import general_model
    return general_model(law, **law_params)


def test_advise_on_a_two_body_model_with_exact_stick() -> None:
    """Coulomb contacts with stiction: the set-valued methods are candidates, the advice is
    feasible and its run lands within the target of event_driven at rtol = 1e-12 (exact stick;
    the event-free methods integrate mu_k sign(v), another motion, and are not the reference)."""
    import stickslip
    m = _two_body_model("coulomb", mu_s=0.4, mu_k=0.3)
    a = stickslip.advise(m, 1e-5, 1.0, body=1)
    assert a.feasible and a.scene == "model" and a.law == "coulomb" and a.model is m and a.body == 1
    assert {"moreau", "event_driven"} <= {c.method for c in a.candidates}
    r = stickslip.simulate(a.model, method=a.method, t_end=a.t_end, **a.controls)
    ref = stickslip.simulate(m, method="event_driven", t_end=1.0, rtol=1e-12, atol=1e-14)
    assert abs(r.x[1, -1] - ref.x[1, -1]) <= 1e-5
    assert "advise: model, coulomb" in str(a)
    assert any(r.role == "reference" and r.method == "event_driven" for r in a.runs)


def test_event_free_advice_on_a_model_is_checked_against_exact_stick() -> None:
    """Generalized-alpha integrates Coulomb's event-free form (mu_s within v_s of v = 0) and
    converges to another motion, 1.7e-3 m from the exact one: whether its own ladder verifies
    (then the reference refuses it) or not (then the note says how far its last run is from the
    reference), the advice is infeasible and names the exact-stick reference."""
    import stickslip
    m = _two_body_model("coulomb", mu_s=0.4, mu_k=0.3)
    a = stickslip.advise(m, 1e-5, 1.0, body=1, methods=["galpha"])
    assert not a.feasible
    assert "differs from the exact-stick reference event_driven" in a.candidates[0].note


def test_advise_on_a_two_body_model_with_smooth_laws() -> None:
    """Smooth laws: the set-valued methods are not candidates; the advised run's velocity of
    body 1 at t_end is within the target of RADAU5 at rtol = 1e-12."""
    import stickslip
    m = _two_body_model("recurdyn")
    a = stickslip.advise(m, 1e-6, 1.0, body=1, quantity="v")
    assert a.feasible and not {"moreau", "event_driven"} & {c.method for c in a.candidates}
    r = stickslip.simulate(a.model, method=a.method, t_end=a.t_end, **a.controls)
    ref = stickslip.simulate(m, method="radau5", t_end=1.0, rtol=1e-12, atol=1e-14)
    assert abs(r.v[1, -1] - ref.v[1, -1]) <= 1e-6
    assert a.stability_bound is not None and a.stability_bound > 0.0


def test_advise_on_a_model_refuses_scene_arguments() -> None:
    import stickslip
    m = _two_body_model("coulomb")
    with pytest.raises(ValueError, match=r"law, x0, v0, parameters: not for a model"):
        stickslip.advise(m, "coulomb", 1e-5, 1.0)
    with pytest.raises(ValueError, match=r"law, x0, v0, parameters: not for a model"):
        stickslip.advise(m, 1e-5, 1.0, mu_k=0.2)
    with pytest.raises(ValueError, match=r"body: must be a body index of the model \(0 \.\. 1\), got 2"):
        stickslip.advise(m, 1e-5, 1.0, body=2)
    with pytest.raises(ValueError, match=r"target_error: must be a finite number > 0"):
        stickslip.advise(m, -1.0, 1.0)
