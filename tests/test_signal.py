"""Time signals (stickslip.signal): the bounds of a signal enclose its values, and the library
evaluates every kind of signal as Python does (stickslip.energy's _value)."""
from __future__ import annotations

import math

import numpy as np

import stickslip as ss
from stickslip.energy import _value

S = ss.signal


def test_signal_bounds_contain_the_signal():
    """Signal.bounds encloses the signal's values, sampled here, and is exact for primitives."""
    t = np.linspace(-1.0, 4.0, 5001)
    sig = 2.0 * S.sine(1.5, 0.7, 0.3, -0.5) - S.table([0.0, 1.0, 2.0], [1.0, -3.0, 2.0]) * S.step(1.0, 0.5, 2.0) \
        + S.ramp(0.5, 1.0, -4.0)
    low, high = sig.bounds()
    values = (2.0 * (1.5 * np.sin(2 * np.pi * 0.7 * t + 0.3) - 0.5)
              - np.interp(t, [0.0, 1.0, 2.0], [1.0, -3.0, 2.0]) * np.where(t >= 1.0, 2.0, 0.5)
              - 4.0 * np.clip(t - 0.5, 0.0, 1.0))
    assert low <= values.min() and values.max() <= high
    assert S.sine(1.5, 0.7, 0.3, -0.5).bounds() == (-2.0, 1.0)
    assert S.table([0.0, 1.0], [3.0, -1.0]).bounds() == (-1.0, 3.0)


def test_signals_evaluate_as_the_library_does():
    """A free body under a force made of every kind of signal: the library's velocity equals
    v0 + int F/m with F evaluated here (_value, integrated by the midpoint rule on a fine grid
    through the corners)."""
    force = (2.0 * S.step(0.2, -1.0, 3.0) + S.ramp(0.1, 0.3, 4.0) - S.sine(1.5, 3.0, 0.4, 0.2)
             + S.table([0.0, 0.5, 0.7], [1.0, -2.0, 0.5]) * S.constant(0.5))
    m = ss.Model()
    b = m.add_body(2.0, v0=0.3)
    m.add_force(b, force)
    r = ss.simulate(m, method="event_driven", t_end=1.0, n_out=11, rtol=1e-12, atol=1e-14)   # restarts at the corners
    fine = np.union1d(np.linspace(0.0, 1.0, 400_001), [0.1, 0.2, 0.4, 0.5, 0.7])
    mid = 0.5 * (fine[1:] + fine[:-1])            # the midpoint rule: no point on a corner
    cum = np.concatenate([[0.0], np.cumsum(_value(force, mid) * np.diff(fine))])
    np.testing.assert_allclose(r.v[0], 0.3 + np.interp(r.t, fine, cum) / 2.0, rtol=0, atol=1e-10)
    assert math.isclose(float(_value(S.step(0.2), np.array([0.2]))[0]), 1.0)   # right-continuous
