"""Input handling of the Python API: non-numbers rejected everywhere, every given value checked
against its range whatever the scene, hopeless runs refused before they start, warnings for
steps longer than the run, and no non-finite value in a result that reports success."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import stickslip as ss


@pytest.mark.parametrize("kw, name", [
    ({"t_end": "20"}, "t_end"),
    ({"method": "rk4", "h": "1e-3"}, "h"),
    ({"rtol": "1e-6"}, "rtol"),
    ({"x0": "0"}, "x0"),
    ({"mu_s": "0.3"}, "mu_s"),
    ({"max_steps": "100"}, "max_steps"),
    ({"t_end": True}, "t_end"),
])
def test_non_numbers_are_rejected_naming_the_parameter(kw, name):
    args = {"scene": "slope", "law": "recurdyn", "method": "dopri5", "t_end": 1.0} | kw
    with pytest.raises(ValueError, match=rf"^{name}: "):
        ss.simulate(**args)


def test_friction_coefficient_non_numbers_name_v():
    with pytest.raises(ValueError, match=r"^v: must be real numbers"):
        ss.friction_coefficient("coulomb", "abc")
    with pytest.raises(ValueError, match=r"^mu_s: "):
        ss.friction_coefficient("coulomb", 0.1, mu_s="x")


@pytest.mark.parametrize("kw, name", [
    ({"scene": "slope", "m": -1.0}, "m"),          # the slope has no mass, m is still checked
    ({"scene": "slope", "k": -5.0}, "k"),
    ({"scene": "belt", "theta_deg": 120.0}, "theta_deg"),
    ({"law": "coulomb", "a": 0.5}, "a"),            # a parameter of another law
])
def test_unused_parameters_are_range_checked(kw, name):
    args = {"scene": "slope", "law": "recurdyn", "method": "dopri5", "t_end": 1.0} | kw
    with pytest.raises(ValueError, match=rf"^{name}: must be finite"):
        ss.simulate(**args, ignore_unused=True)       # checked although unused, and not warned of


def test_step_longer_than_the_run_warns_naming_h():
    with pytest.warns(ss.UnstableStepWarning, match="stability bound"), \
            pytest.warns(UserWarning, match=r"h = 5 s is longer than the whole run"):
        ss.simulate("slope", "recurdyn", method="rk4", h=5.0, t_end=1.0)


def test_hopeless_fixed_step_run_is_refused_before_it_starts(monkeypatch):
    """Refused by the count of steps it needs, before any Fortran call: the call is replaced by
    one that fails the test."""
    def no_run(*args, **kwargs):
        raise AssertionError("the run started")

    monkeypatch.setattr(ss.core, "_execute", no_run)
    with pytest.raises(ValueError, match=r"^max_steps: rk4 with h = 1e-09 s needs 1e\+15 steps"):
        ss.simulate("slope", "recurdyn", method="rk4", h=1e-9, t_end=1e6)


@pytest.mark.parametrize("kw", [
    {"scene": "slope", "method": "dopri5", "v0": 1e308},
    {"scene": "belt", "method": "rk4", "h": 1e-3, "k": 1e308},
])
def test_overflow_near_the_limit_is_never_a_success(kw):
    """The issue's cases: each used to report success with infinite values on the grid."""
    with pytest.raises(ss.NonFiniteSolution) as err, warnings.catch_warnings():
        # k = 1e308 makes the belt's period 2e-153 s: the step warning is right and beside the point
        warnings.simplefilter("ignore", ss.UnstableStepWarning)
        ss.simulate(law="recurdyn", t_end=1.0, **kw)
    res = err.value.result
    assert np.all(np.isfinite(res.x)) and np.all(np.isfinite(res.v))


def test_rtol_and_atol_per_component():
    a = ss.simulate("belt", "proposed", method="dopri5", t_end=2.0, rtol=[1e-6, 1e-6], atol=[1e-9, 1e-9])
    b = ss.simulate("belt", "proposed", method="dopri5", t_end=2.0, rtol=1e-6, atol=1e-9)
    assert np.array_equal(a.x, b.x)
    with pytest.raises(ValueError, match=r"^atol: must be a real number or 2 of them"):
        ss.simulate("belt", "proposed", method="dopri5", t_end=2.0, atol=[1e-9, 1e-9, 1e-9])


def test_controls_of_another_method_are_refused():
    with pytest.raises(ValueError, match=r"^rho_inf: not a control of method 'rk4'"):
        ss.simulate("slope", "recurdyn", method="rk4", h=1e-3, t_end=1.0, rho_inf=0.5)
    with pytest.raises(ValueError, match=r"unknown parameter\(s\) bogus"):
        ss.simulate("slope", "recurdyn", method="rk4", h=1e-3, t_end=1.0, bogus=1.0)


def test_registry_is_the_source_of_names():
    assert ss.LAWS == tuple(ss.REGISTRY["law"]) and "radau5" in ss.METHODS
    assert ss.DEFAULTS["v_d"] is None and ss.REGISTRY["param"]["v_d"]["default_of"] == "v_s"
    r = ss.simulate("slope", "recurdyn", method="rk4", h=1e-3, t_end=0.01, v_s=0.02)
    assert r.params["v_d"] == pytest.approx(0.03) and "m" not in r.params


# A setting kept from a first call (about 2 s, run whole) runs in C on its second call
# (stickslip._runner's fast path), which arms the SIGINT handler itself.
_KEPT = ("kw = dict(method='rk4', h=1e-6, t_end=20.0, n_out=2)\n"
         "ss.simulate('slope', 'recurdyn', **kw)\n"
         "assert len(ss.core._CALLS) == 1\n")


@pytest.mark.parametrize("before, call", [
    ("", 'ss.simulate("slope", "coulomb", method="dopri5", t_end=1e6, max_steps=10**12)'),
    ("", 'ss.simulate("slope", "recurdyn", method="rk4", h=1e-6, t_end=1e5, max_steps=10**12)'),
    ("", 'ss.simulate_batch("slope", "coulomb", method="dopri5", t_end=[1e6, 1e6], max_steps=10**12)'),
    (_KEPT, "ss.simulate('slope', 'recurdyn', **kw)"),
])
def test_ctrl_c_stops_a_long_fortran_call(before, call):
    """SIGINT half a second into a run raises KeyboardInterrupt. The first three runs take hours
    whole: had the signal not stopped them, the subprocess' timeout would end the test first.
    The kept setting (its first call run whole) is as long as its first call, so here only the
    exception is checked; how promptly each call stops is measured by
    `python -m benchmarks.interrupt` (no clock is read in a test)."""
    import subprocess
    import sys
    code = ("import os, signal, threading\n"
            "import stickslip as ss\n"
            f"{before}"
            "threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()\n"
            "try:\n"
            f"    {call}\n"
            "    print('finished')\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted')\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.stdout.split() == ["interrupted"], proc.stdout + proc.stderr


def test_rk4_beyond_its_stability_bound_on_the_slope_warns():
    """The bound docs/guide/choosing-h.md derives, 2.785/(g cos(theta) mu'(v*)) with mu(v*) = tan(theta), computed
    here independently from the haversine's derivative on its first branch."""
    import math
    g_cos, tan = 9.81 * math.cos(math.radians(10.0)), math.tan(math.radians(10.0))
    v_s, mu_s = 0.01, 0.35
    v_star = v_s / math.pi * math.acos(1.0 - 2.0 * tan / mu_s)
    dmu = mu_s * 0.5 * math.pi / v_s * math.sin(math.pi * v_star / v_s)
    assert ss.core.rk4_stability_bound("recurdyn") == pytest.approx(2.785293563405282 / (g_cos * dmu), rel=1e-6)
    assert ss.core.rk4_stability_bound("coulomb") is None        # a jump: no linear bound
    with pytest.warns(UserWarning, match=r"h = 0.01 s is beyond RK4's stability bound 2.785/\|lambda\| = 0.00524 s"):
        ss.simulate("slope", "recurdyn", method="rk4", h=1e-2, t_end=0.1)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ss.simulate("slope", "recurdyn", method="rk4", h=1e-3, t_end=0.1)


def test_ranges_in_messages_are_written_as_a_reader_writes_them():
    """The library writes a bound in the fewest digits that read back as it (0.5, not
    0.50000000000000000), in the error and in every rule of the registry."""
    with pytest.raises(ValueError, match=r"perturbation: must be finite and in \[0, 0\.5\] \(got perturbation = 0\.7\)"):
        ss.simulate("chain", "coulomb", method="moreau", h=1e-3, t_end=0.01, perturbation=0.7)
    import re
    rules = [v["rule"] for v in ss.REGISTRY["param"].values()]
    assert ss.REGISTRY["param"]["perturbation"]["rule"].endswith("in [0, 0.5]")
    assert not [r for r in rules if re.search(r"\d\.\d*0{4,}|\d{10,}", r)]
