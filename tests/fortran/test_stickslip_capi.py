"""The C API for models (ss_model_* in stickslip.h) against the Python Model.

tests/c/capi_model_cases.c builds two models through the C API and runs them (dopri5, rk4,
dopri5 with every step, event_driven), then feeds it bad handles, bad elements and bad
arguments; here the same models are built with `stickslip.Model` and run with
`stickslip.simulate`, and the C results must agree to 1e-12, the statuses must be the
registry's codes for each bad input, and the messages must name the element.
examples/model_c.c (a clutch, also a meson test) is checked against its closed form here too.
"""
from __future__ import annotations

import subprocess
from collections import defaultdict

import numpy as np
import pytest

import stickslip as ss
from conftest import compile_target

S = ss.signal
STATUS = ss.REGISTRY["status"]
#: stickslip_user_model's ELEM_* (SS_ELEM_* in C).
BODY, SPRING, DAMPER, FORCE, CONTACT, SIGNAL, DRIVE = 1, 2, 3, 4, 5, 6, 7
EVENT_KINDS = {1: "stick", 2: "slip", 3: "reversal"}


@pytest.fixture(scope="module")
def cases(native_build) -> dict:
    """What capi_model_cases prints: runs (rows, events, stats) and cases (status, kind, index, message)."""
    exe = compile_target(native_build, "capi_model_cases")
    proc = subprocess.run([str(exe)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    rows, events, stats, out, drives = defaultdict(list), defaultdict(list), {}, {}, defaultdict(list)
    for line in proc.stdout.splitlines():
        kind, name, *rest = line.split(" ")
        if kind == "row":
            rows[name].append([float(f) for f in rest[1:]])
        elif kind == "event":
            events[name].append([float(f) for f in rest[1:]])
        elif kind == "drive":
            drives[name].append([float(f) for f in rest[1:]])
        elif kind == "stats":
            stats[name] = [int(f) for f in rest]
        elif kind == "case":
            status, ekind, eindex = (int(f) for f in rest[:3])
            out[name] = (status, ekind, eindex, line.split(" | ", 1)[1])
    return {"rows": {k: np.array(v) for k, v in rows.items()}, "events": events, "stats": stats, "cases": out,
            "drives": {k: np.array(v) for k, v in drives.items()}}


def model_a() -> ss.Model:
    """capi_model_cases.c's model A, in Python."""
    m = ss.Model()
    b1 = m.add_body(1.5, x0=0.02, v0=0.3)
    b2 = m.add_body(0.8, x0=-0.01, v0=0.0)
    m.add_spring(b1, None, k=120.0, rest_length=0.05)
    m.add_spring(b1, b2, k=60.0, rest_length=0.0)
    m.add_damper(b2, None, c=0.7)
    m.add_force(b1, S.sine(3.0, 2.0, 0.3, 0.5) + S.ramp(0.2, 0.3, 4.0))
    m.add_force(b2, S.table([0.0, 0.3, 0.6, 1.0], [0.0, 2.0, -1.0, 0.5]) - S.constant(0.25))
    m.add_contact(b1, b2, "lugre", normal_force=S.constant(15.0), mu_s=0.5, mu_k=0.4, v_s=0.02)
    m.add_contact(b2, None, "stribeck", normal_force=S.step(0.3, 10.0, 20.0) * S.constant(1.0),
                  surface_velocity=S.sine(0.5, 1.0, 0.0, 1.0), mu_s=0.6, mu_k=0.45, v_s=0.05)
    return m


def model_b() -> ss.Model:
    """capi_model_cases.c's model B: the example of issue 29."""
    m = ss.Model()
    j1 = m.add_body(1.0, x0=0.0, v0=10.0)
    j2 = m.add_body(1.0)
    m.add_spring(j1, None, k=100.0, rest_length=0.0)
    m.add_damper(j1, j2, c=2.0)
    m.add_force(j1, S.sine(10.0, 5.0))
    m.add_contact(j1, j2, "coulomb", normal_force=S.constant(20.0) * S.step(0.4), mu_s=0.55, mu_k=0.5)
    m.add_contact(j2, None, "stribeck", normal_force=S.constant(98.1), surface_velocity=S.constant(1.5))
    return m


def model_c() -> ss.Model:
    """capi_model_cases.c's model C: a drill string with its top driven at 5 rad/s."""
    m = ss.Model()
    top = m.add_body(50.0)
    bit = m.add_body(374.0)
    m.add_spring(top, bit, k=473.0)
    m.add_contact(bit, None, "stribeck", normal_force=1000.0, mu_s=0.8, mu_k=0.5)
    m.add_drive(top, velocity=5.0)
    return m


#: The same runs in Python (the facade's hmin defaults to 1e-6, the library's to 0: given here).
RUNS = {
    "a_dopri5": (model_a, dict(method="dopri5", t_end=1.0, n_out=21, rtol=1e-9, atol=1e-11, hmin=1e-6,
                               hmax=0.05)),
    "a_rk4": (model_a, dict(method="rk4", t_end=1.0, n_out=21, h=2e-5)),
    "a_dopri5_every": (model_a, dict(method="dopri5", t_end=0.5, every_step=True, rtol=1e-6, atol=1e-8,
                                     hmin=0.0)),
    "b_event_driven": (model_b, dict(method="event_driven", t_end=1.5, n_out=301, rtol=1e-10, atol=1e-12)),
    "c_drive_dopri5": (model_c, dict(method="dopri5", t_end=4.0, n_out=41, rtol=1e-9, atol=1e-11, hmin=1e-6)),
    "c_drive_event_driven": (model_c, dict(method="event_driven", t_end=10.0, n_out=41, rtol=1e-10, atol=1e-12)),
}


@pytest.mark.parametrize("run", list(RUNS))
def test_c_model_runs_as_the_python_model(cases: dict, run: str) -> None:
    make, kw = RUNS[run]
    res = ss.simulate(make(), **kw)
    rows = cases["rows"][run]
    status, n_written, nfev, n_events = cases["stats"][run]
    assert status == STATUS["OK"]
    assert n_written == len(res.t) == len(rows)
    assert nfev == res.stats["nfev"]
    np.testing.assert_allclose(rows[:, 0], res.t, rtol=1e-14, atol=1e-15)
    # x, v (n_bodies x n_t) in C and in Python: 1e-12 relative to each state's scale
    for c_cols, py in ((rows[:, 1:3].T, res.x), (rows[:, 3:5].T, res.v)):
        scale = np.maximum(1.0, np.abs(py).max(axis=1, keepdims=True))
        assert np.abs(c_cols - py).max() / scale.min() < 1e-12, np.abs(c_cols - py).max()
    assert n_events == len(res.events)
    for (t, kind, pos, contact), ev in zip(cases["events"][run], res.events):
        assert abs(t - ev["t"]) < 1e-12 and abs(pos - ev["x"]) < 1e-12
        assert EVENT_KINDS[int(kind)] == ev["kind"] and int(contact) - 1 == ev["contact"]
    if res.drive_force.shape[1]:
        np.testing.assert_allclose(cases["drives"][run], res.drive_force, rtol=1e-12, atol=1e-9)


def test_event_driven_run_has_events(cases: dict) -> None:
    """The comparison above is not empty: the clutch and the belt stick and slip."""
    kinds = {int(e[1]) for e in cases["events"]["b_event_driven"]}
    assert len(cases["events"]["b_event_driven"]) >= 3 and {1, 3} <= kinds


def test_bad_handles_are_refused_by_every_function(cases: dict) -> None:
    handles = {k: v for k, v in cases["cases"].items() if "_handle_" in k}
    assert len(handles) == 36
    for name, (status, *_, message) in handles.items():
        assert status == STATUS["BAD_HANDLE"], name
        assert message.startswith("model: not a live handle"), name


@pytest.mark.parametrize("case,code,kind,index,prefix", [
    ("empty", "BAD_MODEL_EMPTY", 0, 0, "model: has no bodies"),
    ("spring_body", "BAD_BODY", SPRING, 1, "spring 1 (body 1 - body 2): body:"),
    ("damper_self", "BAD_BODY", DAMPER, 1, "damper 1 (body 1 - body 1): body:"),
    ("drive_body", "BAD_BODY", DRIVE, 1, "drive 1 (body 5): body:"),
    ("drive_step", "BAD_SIGNAL", DRIVE, 1, "drive 1 (body 2): signal:"),
    ("negative_mass", "BAD_MASS", BODY, 2, "body 2: mass: must be finite and > 0"),
    ("negative_k", "BAD_SPRING", SPRING, 1, "spring 1 (body 1 - ground): k:"),
    ("negative_c", "BAD_DAMPER", DAMPER, 2, "damper 2 (body 1 - ground): c:"),
    ("ramp_duration", "BAD_SIGNAL", SIGNAL, 1, "signal 1: signal: malformed"),
    ("unknown_signal", "BAD_SIGNAL", FORCE, 2, "force 2 (body 1): signal:"),
    ("unknown_law", "BAD_LAW", CONTACT, 1, "contact 1 (body 1 - ground): law: unknown friction law"),
    ("unnamed_law", "BAD_LAW", CONTACT, 2, "contact 2 (body 2 - ground): law:"),
    ("negative_mu_k", None, CONTACT, 1, "contact 1 (body 1 - ground): mu_k:"),
    ("unknown_param", "BAD_PARAM_NAME", CONTACT, 1, "contact 1 (body 1 - ground): parameter:"),
    ("x_null", "BAD_DIM", 0, 0, ""),
    ("events_null", "BAD_DIM", 0, 0, ""),
    ("controls_not_values", "BAD_DIM", 0, 0, ""),
    ("n_out_0", "BAD_N_OUT", 0, 0, "n_out:"),
    ("method_0", "BAD_METHOD", 0, 0, "method:"),
    ("method_99", "BAD_METHOD", 0, 0, "method:"),
    ("control_of_another_method", "BAD_CONTROL_NAME", 0, 0, "control:"),
    ("rk4_h_0", "BAD_H", 0, 0, "h:"),
    ("event_driven_lugre", "NOT_SETVALUED", 0, 0, "law:"),
    ("t_end_negative", "BAD_T_END", 0, 0, "t_end:"),
    ("good_after_bad", "OK", 0, 0, "success"),
])
def test_bad_model_input_returns_its_code(cases: dict, case: str, code: str | None, kind: int, index: int,
                                          prefix: str) -> None:
    status, ekind, eindex, message = cases["cases"][case]
    expected = ss.REGISTRY["param"]["mu_k"]["code"] if code is None else STATUS[code]
    assert (status, ekind, eindex) == (expected, kind, index), message
    assert message.startswith(prefix), message


@pytest.mark.parametrize("case", ["keys_not_values", "values_null", "table_negative_n", "table_null"])
def test_unreadable_arrays_are_refused_when_added(cases: dict, case: str) -> None:
    """An element whose arrays cannot be read is not added: SS_BAD_DIM from the add call."""
    assert cases["cases"][case][0] == STATUS["BAD_DIM"]


def test_python_refuses_the_same_models() -> None:
    """The Python Model refuses, as it is built, what the C API's check refuses."""
    m = ss.Model()
    m.add_body(1.0)
    with pytest.raises(ValueError, match="mass"):
        m.add_body(-2.0)
    with pytest.raises(ValueError, match="body"):
        m.add_spring(0, 1, k=10.0)
    with pytest.raises(ValueError, match="law"):
        m.add_contact(0, None, "no_such_law", normal_force=1.0)


def test_clutch_example_matches_its_closed_form(native_build) -> None:
    """examples/model_c.c: lock time, angles and speeds of the clutch, recomputed here."""
    exe = compile_target(native_build, "model_c")
    proc = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = dict(line.split("=", 1) for line in proc.stdout.splitlines())
    j1, j2, w0, mu_k, n, t_on, t_end = 1.0, 2.0, 10.0, 0.4, 50.0, 0.1, 1.0
    torque = mu_k * n
    t_lock = t_on + w0 / (torque * (1 / j1 + 1 / j2))
    w_c = j1 * w0 / (j1 + j2)
    slip = t_lock - t_on
    x1 = w0 * t_lock - 0.5 * torque / j1 * slip**2 + w_c * (t_end - t_lock)
    x2 = 0.5 * torque / j2 * slip**2 + w_c * (t_end - t_lock)
    assert int(out["n_events"]) == 1 and float(out["event_kind"]) == 1 and float(out["event_contact"]) == 1
    assert abs(float(out["t_lock"]) - t_lock) < 1e-12
    assert abs(float(out["flywheel_angle"]) - x1) < 1e-12
    assert abs(float(out["drum_angle"]) - x2) < 1e-12
    assert all(abs(float(s) - w_c) < 1e-12 for s in out["speeds"].split(","))
    assert int(out["bad_status"]) == STATUS["BAD_BODY"]
    assert out["bad_message"].startswith("spring 1 (body 2 - body 3): body:")
