"""The gallery's two-block belt page (cases/gallery_belt2dof.py) against the scipy event-driven
solver of cases/_scipy_events.py (numpy and scipy only, exhaustive mode search)."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from cases._scipy_events import ScipyContacts  # noqa: E402
from cases import gallery_belt2dof as belt  # noqa: E402

import stickslip as ss  # noqa: E402
from test_gallery_clutches import _quick  # noqa: E402  (each gallery driver's quick run)


def _stribeck_curve(w: float) -> float:
    p = belt.LAW
    return p["mu_k"] + (p["mu_s"] - p["mu_k"]) * math.exp(-(w / p["v_s"]) ** p["delta"])


def test_two_block_belt_exact_motion_agrees_with_scipy():
    """event_driven with the set-valued Stribeck law against the scipy solver with the same
    Stribeck curve, over 3 s."""
    t = np.linspace(0.0, 3.0, 601)
    res = ss.simulate(belt.model(**belt.LAW), method="event_driven", t_end=3.0, n_out=t.size,
                      rtol=1e-12, atol=1e-14)

    def force(_t: float, x: np.ndarray) -> np.ndarray:
        return np.array([-belt.K1 * x[0] - belt.K12 * (x[0] - x[1]), -belt.K2 * x[1] - belt.K12 * (x[1] - x[0])])

    contacts = [(0, None, lambda _t: belt.M1 * belt.G, belt.V_BELT),
                (1, None, lambda _t: belt.M2 * belt.G, belt.V_BELT)]
    sysm = ScipyContacts([belt.M1, belt.M2], force, contacts, belt.LAW["mu_s"], belt.LAW["mu_k"],
                         mu_slip=_stribeck_curve)
    x, v, events = sysm.run([0.0, 0.0], 3.0, t, rtol=1e-12, atol=1e-14)
    assert sum(1 for e in events if e[2] == 0) >= 4                  # both blocks stick, again and again
    assert np.abs(res.x - x).max() < 1e-8


def test_two_block_belt_regularised_measures_approach_the_exact_ones():
    exact = ss.simulate(belt.model(**belt.LAW), method="event_driven", t_end=belt.T_END, n_out=belt.N_OUT,
                        rtol=1e-10, atol=1e-12)
    m_exact = belt.measures(exact.t, exact.x[0], exact.v[0])
    assert m_exact["stick"] > 0.1 and 0.1 < m_exact["period"] < 2.0
    errs = []
    for w in (1e-2, 1e-3):
        r = ss.simulate(belt.model(**belt.LAW, v_eps=w), method="dopri5", t_end=belt.T_END, n_out=belt.N_OUT,
                        rtol=1e-9, atol=1e-12)
        mm = belt.measures(r.t, r.x[0], r.v[0])
        errs.append(abs(mm["period"] - m_exact["period"]) / m_exact["period"])
    assert errs[1] < errs[0]



def test_belt2dof_driver_writes_its_files(tmp_path):
    _quick(belt, tmp_path)
    text = (tmp_path / "gallery_belt2dof.md").read_text()
    assert "exact (event_driven)" in text
