"""The gallery's stacked-block page (cases/gallery_stacked.py) against independent references:
closed forms and the scipy event-driven solver of cases/_scipy_events.py (numpy and scipy only,
exhaustive mode search)."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from cases._scipy_events import ScipyContacts  # noqa: E402
from cases import gallery_stacked as st  # noqa: E402

import stickslip as ss  # noqa: E402
from test_gallery_clutches import _quick  # noqa: E402  (each gallery driver's quick run)


def test_closed_form_agrees_with_scipy():
    """The stick-slip closed form of one block on a belt against the scipy solver (both
    independent of stickslip)."""
    t = np.linspace(0.0, 3.0, 301)
    sysm = ScipyContacts([1.0], lambda _t, x: np.array([-100.0 * x[0]]),
                         [(0, None, lambda _t: 9.81, st.V_BELT)], st.MU_S, st.MU_K)
    x, _, events = sysm.run([0.0], 3.0, t, rtol=1e-12, atol=1e-14)
    assert len(events) >= 6
    assert np.abs(x[0] - st.closed_form(t, 1.0, 100.0, 9.81)).max() < 1e-10


def test_closed_form_refuses_a_first_slip_that_never_sticks():
    with pytest.raises(ValueError, match="belt's speed"):
        st.closed_form(np.array([0.0, 1.0]), 1.0, 100.0, 9.81, v_b=5.0)


@pytest.mark.parametrize("n_feet", [1, 2, 3])
def test_block_on_feet_follows_the_closed_form(n_feet):
    t = np.linspace(0.0, st.T_END, st.N_OUT)
    res = ss.simulate(st.feet(n_feet), method="event_driven", t_end=st.T_END, n_out=st.N_OUT,
                      rtol=1e-12, atol=1e-14)
    assert np.abs(res.x[0] - st.closed_form(t, st.M_A, st.K_A, st.M_A * st.G)).max() < 1e-9


def test_stacked_blocks_held_move_as_one_block():
    t = np.linspace(0.0, st.T_END, st.N_OUT)
    res = ss.simulate(st.stacked(st.B_HELD), method="event_driven", t_end=st.T_END, n_out=st.N_OUT,
                      rtol=1e-12, atol=1e-14)
    one = st.closed_form(t, st.M_A + st.M_B, st.K_A + st.K_B, (st.M_A + st.M_B) * st.G)
    assert np.abs(res.x - one).max() < 1e-9


def test_stacked_blocks_slipping_agree_with_scipy():
    t = np.linspace(0.0, st.T_END, st.N_OUT)
    res = ss.simulate(st.stacked(st.B_SLIPS), method="event_driven", t_end=st.T_END, n_out=st.N_OUT,
                      rtol=1e-12, atol=1e-14)
    ref = st.scipy_stacked(st.B_SLIPS, t)
    assert np.abs(res.x[0] - res.x[1]).max() > 1e-2          # B does slip on A
    assert np.abs(res.x - ref).max() < 1e-8


@pytest.mark.parametrize("model", ["feet", "held"])
def test_moreau_converges_on_the_stacked_systems(model):
    t = np.linspace(0.0, st.T_END, st.N_OUT)
    if model == "feet":
        m, ref = st.feet(2), st.closed_form(t, st.M_A, st.K_A, st.M_A * st.G)
    else:
        m = st.stacked(st.B_HELD)
        ref = st.closed_form(t, st.M_A + st.M_B, st.K_A + st.K_B, (st.M_A + st.M_B) * st.G)
    errs = [np.abs(ss.simulate(m, method="moreau", h=h, t_end=st.T_END, n_out=st.N_OUT).x - ref).max()
            for h in (1e-3, 1e-5)]
    # first order over two decades (a stick-slip error's size depends on where the events fall
    # between steps, so a single decade can show 5x or 40x)
    assert 0.7 < math.log10(errs[0] / errs[1]) / 2.0 < 1.5, errs



def test_stacked_driver_writes_its_files(tmp_path):
    _quick(st, tmp_path)
    text = (tmp_path / "gallery_stacked.md").read_text()
    assert text.count("\n| ") == 3           # a row for each of the three systems
