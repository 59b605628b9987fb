"""Drives (Model.add_drive): a body whose position or velocity is prescribed by a signal.

Checked against independent references: the drill string with a driven top against its
one-body form (the bit on a spring whose far end moves as Omega t); the driven body's
position and velocity against the closed forms of the signals' integrals and derivatives,
written here; the drive's force against Newton's law for the driven body, summed here from
the result with the law's coefficient (stickslip.friction_coefficient)."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import stickslip as ss

S = ss.signal
J_BIT, K, OMEGA, N_BIT, T = 374.0, 473.0, 5.0, 1000.0, 20.0
METHOD_CONTROLS = {"rk4": dict(h=1e-3), "dopri5": {}, "dop853": {}, "radau5": {},
                   "implicit_euler": dict(h=1e-3), "galpha": dict(h=1e-3), "moreau": dict(h=1e-3),
                   "event_driven": {}}


def drill_two_body(law: str, **law_params: float) -> ss.Model:
    """The drill string: a top driven at OMEGA through a torsional spring K to the bit, which
    has friction on the bottom."""
    m = ss.Model()
    top = m.add_body(50.0, name="top")
    bit = m.add_body(J_BIT, name="bit")
    m.add_spring(top, bit, K)
    m.add_contact(bit, None, law, N_BIT, **law_params)
    m.add_drive(top, velocity=OMEGA)
    return m


def drill_one_body(law: str, **law_params: float) -> ss.Model:
    """Its one-body form: the bit on a spring whose far end moves as OMEGA t (up to T)."""
    m = ss.Model()
    bit = m.add_body(J_BIT, name="bit")
    m.add_spring(bit, None, K)
    m.add_force(bit, K * S.ramp(0.0, T, OMEGA * T))
    m.add_contact(bit, None, law, N_BIT, **law_params)
    return m


@pytest.mark.parametrize("law,params", [("stribeck", dict(mu_s=0.8, mu_k=0.5)),
                                        ("coulomb", dict(mu_s=0.8, mu_k=0.5))])
def test_drill_string_driven_top_equals_one_body_form(law, params):
    """event_driven (default tolerances): the bit of the driven drill string equals the
    one-body form's to 1e-10 over several stick-slip cycles (measured 6e-12 for stribeck, 7e-14
    for coulomb: the two forms' forcings k Omega t differ in their last bit); the top follows
    OMEGA t exactly."""
    r2 = ss.simulate(drill_two_body(law, **params), method="event_driven", t_end=T, n_out=401)
    r1 = ss.simulate(drill_one_body(law, **params), method="event_driven", t_end=T, n_out=401)
    assert np.ptp(r1.v[0]) > 5.0                     # it does stick and slip
    assert np.max(np.abs(r2.x[1] - r1.x[0])) < 1e-10
    assert np.max(np.abs(r2.v[1] - r1.v[0])) < 1e-10
    assert np.array_equal(r2.v[0], np.full_like(r2.t, OMEGA))
    assert np.max(np.abs(r2.x[0] - OMEGA * r2.t)) <= 1e-12 * OMEGA * T
    assert r1.events.size == r2.events.size > 2
    assert np.max(np.abs(r1.events["t"] - r2.events["t"])) < 1e-10


def _ramp(t, start, dur, h):
    return np.clip((t - start) / dur, 0.0, 1.0) * h


@pytest.mark.parametrize("method", list(METHOD_CONTROLS))
def test_position_drive_follows_its_signal_exactly(method):
    """Under every method the driven body's position is its signal and its velocity the
    signal's derivative (closed forms written here) to 1e-12."""
    pos = 0.3 * S.sine(1.0, 0.7, 0.2) + S.ramp(0.5, 1.0, 2.0) + S.table([0.0, 1.0, 2.5], [0.0, 0.4, -0.1])
    m = ss.Model()
    d = m.add_body(2.0, name="sled")
    b = m.add_body(1.0, name="block")
    m.add_spring(b, d, 100.0, rest_length=0.1)
    m.add_contact(b, d, "stribeck" if method in ("moreau", "event_driven") else "recurdyn", 5.0)
    m.add_drive(d, position=pos)
    r = ss.simulate(m, method=method, t_end=3.0, n_out=61, **METHOD_CONTROLS[method])
    t = r.t
    w = 2.0 * math.pi * 0.7
    slope = np.where(t < 1.0, 0.4, np.where(t < 2.5, -0.5 / 1.5, 0.0))
    x = 0.3 * np.sin(w * t + 0.2) + _ramp(t, 0.5, 1.0, 2.0) + np.interp(t, [0.0, 1.0, 2.5], [0.0, 0.4, -0.1])
    v = 0.3 * w * np.cos(w * t + 0.2) + np.where((t >= 0.5) & (t < 1.5), 2.0, 0.0) + slope
    assert np.max(np.abs(r.x[0] - x)) < 1e-12
    assert np.max(np.abs(r.v[0] - v)) < 1e-12
    assert np.all(np.isfinite(r.x[1]))


def test_velocity_drive_position_is_the_exact_integral():
    """A velocity drive's position is x0 plus the closed-form integral of its signal (a step,
    a ramp, a sine with offset and a table, with a number times a signal) to 1e-12."""
    vel = 2.0 * S.step(0.3, 1.0, -0.5) + S.ramp(0.2, 0.8, 1.5) + S.sine(0.6, 1.3, 0.4, 0.25) \
        - S.table([0.5, 1.0, 2.0], [1.0, 0.0, 2.0])
    m = ss.Model()
    d = m.add_body(1.0, x0=0.7, name="d")
    b = m.add_body(1.0, name="b")
    m.add_spring(b, d, 10.0)
    m.add_drive(d, velocity=vel)
    r = ss.simulate(m, method="dopri5", t_end=3.0, n_out=301)
    t = r.t
    w = 2.0 * math.pi * 1.3
    step_int = 2.0 * np.where(t < 0.3, t, 0.3 - 0.5 * (t - 0.3))
    ramp_int = np.where(t < 0.2, 0.0, np.where(t < 1.0, 1.5 / 0.8 * (t - 0.2) ** 2 / 2, 1.5 * (t - 1.0) + 0.6))
    sine_int = -0.6 / w * (np.cos(w * t + 0.4) - math.cos(0.4)) + 0.25 * t
    # the table's integral from 0: 1 up to 0.5, then the linear pieces, then 2 after 2.0
    tab_int = np.array([np.trapezoid(np.interp(np.linspace(0, ti, 20001), [0.5, 1.0, 2.0], [1.0, 0.0, 2.0]),
                                     np.linspace(0, ti, 20001)) for ti in t])
    x = 0.7 + step_int + ramp_int + sine_int - tab_int
    assert np.max(np.abs(r.x[0] - x)) < 1e-8        # the trapezoid sum of the table is the limit
    no_table = 2.0 * S.step(0.3, 1.0, -0.5) + S.ramp(0.2, 0.8, 1.5) + S.sine(0.6, 1.3, 0.4, 0.25)
    m.drives.clear()
    m.add_drive(d, velocity=no_table)
    r = ss.simulate(m, method="dopri5", t_end=3.0, n_out=301)
    assert np.max(np.abs(r.x[0] - (0.7 + step_int + ramp_int + sine_int))) < 1e-12


@pytest.mark.parametrize("driven_side", ["a", "b"])
def test_drive_force_is_newtons_law(driven_side):
    """res.drive_force = m_d a_d - (springs + dampers + forces + friction on d), each summed
    here from the result (friction from friction_coefficient at the slip), to 1e-9."""
    md, mb, k, l0, c, n = 3.0, 1.5, 80.0, 0.2, 4.0, 6.0
    params = dict(mu_s=0.5, mu_k=0.3)
    m = ss.Model()
    d = m.add_body(md, name="d")
    b = m.add_body(mb, v0=0.4, name="b")
    m.add_spring(d, b, k, rest_length=l0)
    m.add_damper(b, d, c)
    m.add_spring(b, None, 30.0)
    m.add_force(d, S.sine(2.0, 0.5))
    if driven_side == "a":
        m.add_contact(d, b, "stribeck", n, **params)
    else:
        m.add_contact(b, d, "stribeck", n, **params)
    amp, f = 0.5, 0.8
    w = 2.0 * math.pi * f
    m.add_drive(d, position=S.sine(amp, f))
    r = ss.simulate(m, method="dopri5", t_end=4.0, n_out=81, rtol=1e-10, atol=1e-12)
    xd, vd, xb, vb, t = r.x[0], r.v[0], r.x[1], r.v[1], r.t
    ad = -amp * w * w * np.sin(w * t)
    spring = -k * (xd - xb - l0)                       # on d, which is the spring's a
    damper = c * (vb - vd)                             # on d, the damper's b: -(-c (v_b - v_d))
    force = 2.0 * np.sin(2.0 * math.pi * 0.5 * t)
    if driven_side == "a":
        friction = -ss.friction_coefficient("stribeck", vd - vb, **params) * n
    else:
        friction = ss.friction_coefficient("stribeck", vb - vd, **params) * n
    expected = md * ad - spring - damper - force - friction
    assert r.drive_force.shape == (81, 1)
    assert np.max(np.abs(r.drive_force[:, 0] - expected)) < 1e-9


def test_contact_on_driven_body_is_a_moving_surface():
    """A contact between a free body and a body driven at a velocity equals the free body on
    a surface moving at that velocity, whichever side the driven body is, to rounding."""
    belt = S.ramp(0.0, 1.0, 0.4) + S.sine(0.1, 0.5)
    ref = ss.Model()
    b0 = ref.add_body(1.0, name="block")
    ref.add_spring(b0, None, 50.0)
    ref.add_contact(b0, None, "lugre", 9.81, belt)
    r0 = ss.simulate(ref, method="dopri5", t_end=5.0, n_out=101, rtol=1e-10, atol=1e-12)
    for side in "ab":
        m = ss.Model()
        b = m.add_body(1.0, name="block")
        d = m.add_body(10.0, name="belt")
        m.add_spring(b, None, 50.0)
        if side == "a":
            m.add_contact(b, d, "lugre", 9.81)
        else:
            m.add_contact(d, b, "lugre", 9.81)
        m.add_drive(d, velocity=belt)
        r = ss.simulate(m, method="dopri5", t_end=5.0, n_out=101, rtol=1e-10, atol=1e-12)
        assert np.max(np.abs(r.x[0] - r0.x[0])) < 1e-12
        assert np.max(np.abs(r.v[0] - r0.v[0])) < 1e-12
        assert np.max(np.abs(r.z - r0.z)) < 1e-12       # the law sees the free body's slip


@pytest.mark.parametrize("method,controls,tol_x,tol_f", [("event_driven", dict(rtol=1e-10, atol=1e-12), 1e-10, 1e-8),
                                                         ("moreau", dict(h=1e-3), 1e-6, 1e-4),
                                                         ("moreau", dict(h=1e-4), 1e-8, 1e-6)])
def test_drive_force_of_a_stuck_block_is_the_closed_form(method, controls, tol_x, tol_f):
    """A platform (md) driven at x_d = A sin(w t) carries a block (mb, spring k to the ground)
    that stays stuck on it (|k - mb w^2| A < mu_s N): the block moves as x_d, its friction is
    F = mb a_d + k x_d, and the drive supplies md a_d + F, in closed form. The holding force
    is set-valued; the contact solver's problem at rest gives it (before: NaN)."""
    md, mb, k, n, amp, f = 2.0, 1.0, 50.0, 9.81, 0.05, 0.5
    w = 2.0 * math.pi * f
    m = ss.Model()
    b = m.add_body(mb, v0=amp * w, name="block")
    d = m.add_body(md, name="platform")
    m.add_spring(b, None, k)
    m.add_contact(b, d, "coulomb", n, mu_s=0.6, mu_k=0.4)
    m.add_drive(d, position=S.sine(amp, f))
    r = ss.simulate(m, method=method, t_end=3.0, n_out=77, **controls)   # rows between moreau's steps
    assert abs(k - mb * w * w) * amp < 0.6 * n
    xd = amp * np.sin(w * r.t)
    expected = (k - (md + mb) * w * w) * xd
    assert np.max(np.abs(r.x[0] - xd)) < tol_x     # the block stays on the platform
    assert np.max(np.abs(r.drive_force[:, 0] - expected)) < tol_f


@pytest.mark.parametrize("method,controls", [("event_driven", dict(rtol=1e-10, atol=1e-12)),
                                             ("moreau", dict(h=1e-4))])
def test_drive_force_under_stick_slip_follows_the_mode(method, controls):
    """A block on a spring to the ground on a belt driven at 0.2 m/s sticks and slips: the
    drive's force is the block's friction, k x where it is stuck (|k x| <= mu_s N) and mu_k N
    against the slip where it slips (from rest at t = 0 too), everywhere finite."""
    k, n, mu_s, mu_k = 50.0, 9.81, 0.6, 0.4
    m = ss.Model()
    b = m.add_body(1.0, name="block")
    d = m.add_body(1.0, name="belt")
    m.add_spring(b, None, k)
    m.add_contact(b, d, "coulomb", n, mu_s=mu_s, mu_k=mu_k)
    m.add_drive(d, velocity=0.2)
    r = ss.simulate(m, method=method, t_end=4.0, n_out=401, **controls)
    slip = r.v[0] - 0.2
    stuck = np.abs(slip) < 1e-9
    assert 0 < stuck.sum() < stuck.size
    assert np.all(np.isfinite(r.drive_force))
    assert np.max(np.abs(r.drive_force[stuck, 0] - k * r.x[0, stuck])) < 1e-8
    assert np.all(np.abs(k * r.x[0, stuck]) <= mu_s * n * (1 + 1e-9))
    assert np.max(np.abs(r.drive_force[~stuck, 0] + mu_k * n * np.sign(slip[~stuck]))) < 1e-9


def test_drive_errors_name_the_drive_and_value():
    m = ss.Model()
    a = m.add_body(1.0, name="top")
    b = m.add_body(1.0, name="bit")
    with pytest.raises(ValueError, match=r"drive 0: give exactly one of position= and velocity=, got both"):
        m.add_drive(a, position=1.0, velocity=1.0)
    with pytest.raises(ValueError, match=r"drive 0: give exactly one .* got neither"):
        m.add_drive(a)
    with pytest.raises(ValueError, match=r"drive 0: body must be a body index \(0 \.\. 1\), got 5"):
        m.add_drive(5, velocity=1.0)
    with pytest.raises(ValueError, match=r"drive 0 \(top\): position has a step"):
        m.add_drive(a, position=S.step(1.0))
    with pytest.raises(ValueError, match=r"drive 0 \(top\): velocity multiplies two signals"):
        m.add_drive(a, velocity=S.sine(1.0, 1.0) * S.ramp(0.0, 1.0, 1.0))
    m.add_drive(a, velocity=2.0 * S.ramp(0.0, 1.0, 1.0))
    with pytest.raises(ValueError, match=r"drive 1 \(top\): body 'top' already has a drive"):
        m.add_drive(a, position=0.0)
    m.add_contact(a, None, "coulomb", 1.0)
    with pytest.raises(ValueError, match=r"contact 0 \(top-ground\): each side is driven or the ground"):
        ss.simulate(m, method="dopri5", t_end=1.0)
    m.contacts.clear()
    m.add_drive(b, position=0.0)
    with pytest.raises(ValueError, match=r"model: every body has a drive \(top, bit\)"):
        ss.simulate(m, method="dopri5", t_end=1.0)


def test_drive_toml_round_trip(tmp_path):
    """[[drive]] tables: written and read back to the same model and result; a drive table
    with both or neither signal is refused in TOML's words."""
    m = drill_two_body("stribeck", mu_s=0.8, mu_k=0.5)
    path = tmp_path / "drill.toml"
    m.to_toml(path)
    text = path.read_text()
    assert "[[drive]]" in text and 'body = "top"' in text
    m2 = ss.Model.from_toml(path)
    assert m2.to_dict() == m.to_dict()
    r1 = ss.simulate(m, method="dopri5", t_end=2.0, n_out=11)
    r2 = ss.simulate(m2, method="dopri5", t_end=2.0, n_out=11)
    assert np.array_equal(r1.y if hasattr(r1, "y") else r1.x, r2.y if hasattr(r2, "y") else r2.x)
    path.write_text(text.replace("velocity = ", "position = 1.0\nvelocity = "))
    with pytest.raises(ValueError, match=r"drive 0: give exactly one of position and velocity, got position, "
                                         r"velocity"):
        ss.Model.from_toml(path)


@pytest.mark.parametrize("method", list(METHOD_CONTROLS))
def test_velocity_drive_under_every_method(method):
    """A velocity drive (a ramp and a sine) under every method: the driven body's position is
    x0 plus the closed-form integral, written here, to 1e-12, and the run ends in success."""
    m = ss.Model()
    d = m.add_body(2.0, x0=0.3, name="sled")
    b = m.add_body(1.0, name="block")
    m.add_spring(b, d, 100.0)
    m.add_contact(b, None, "stribeck" if method in ("moreau", "event_driven") else "recurdyn", 5.0)
    m.add_drive(d, velocity=S.ramp(0.0, 1.0, 2.0) + S.sine(0.5, 1.0))
    r = ss.simulate(m, method=method, t_end=3.0, n_out=31, **METHOD_CONTROLS[method])
    t = r.t
    x = 0.3 + np.where(t < 1.0, t**2, 1.0 + 2.0 * (t - 1.0)) + 0.5 / (2 * np.pi) * (1.0 - np.cos(2 * np.pi * t))
    assert r.stats["status"] == 0 and np.all(np.isfinite(r.x[1]))
    assert np.max(np.abs(r.x[0] - x)) < 1e-12
    assert np.max(np.abs(r.v[0] - (np.clip(t, 0.0, 1.0) * 2.0 + 0.5 * np.sin(2 * np.pi * t)))) < 1e-12


def test_command_line_writes_the_drive_force(tmp_path):
    """python -m stickslip run on a model file with a [[drive]]: the CSV's last column is the
    drive's force, equal to the Python run's."""
    from stickslip.__main__ import main
    m = drill_two_body("stribeck", mu_s=0.8, mu_k=0.5)
    m.to_toml(tmp_path / "drill.toml")
    out = tmp_path / "drill.csv"
    assert main(["run", str(tmp_path / "drill.toml"), "--method", "dopri5", "--t-end", "2.0", "--n-out", "21",
                 "--out", str(out)]) == 0
    assert out.read_text().startswith("t,x_top,x_bit,v_top,v_bit,F_drive_top\n")
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    res = ss.simulate(m, method="dopri5", t_end=2.0, n_out=21)
    assert np.array_equal(data[:, 5], res.drive_force[:, 0]) and np.ptp(data[:, 5]) > 0.0
