"""The gallery's CoupledClutches page (cases/gallery_clutches.py) against independent
references: Modelica's published result (data/coupled-clutches), closed forms, and the scipy
event-driven solver of cases/_scipy_events.py (numpy and scipy only, exhaustive mode search)."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from cases import gallery_clutches as cc  # noqa: E402

#: Modelica's reference came from DASSL at tolerance 1e-6: its speeds are good to about 1e-4
#: rad/s (the scipy solver at rtol 1e-10 and event_driven differ from it by 7e-5 rad/s at most).
MODELICA_SPEED_TOL = 2e-4
#: ... and its event times to about 1e-5 s (the largest difference, 4e-6 s, is the 0.79 s lock
#: of clutch 1).
MODELICA_EVENT_TOL = 2e-5


@pytest.fixture(scope="module")
def clutches():
    ref = cc.reference()
    res = cc.simulate(rtol=1e-10, atol=1e-12)
    on = np.isin(np.round(cc.GRID, 9), np.round(ref["t"], 9))
    return ref, res, on


def test_modelica_rows_are_what_the_readme_says():
    ref = cc.reference()
    assert ref["t"].size == 601 and ref["t"][0] == 0.0 and ref["t"][-1] == 1.5
    assert np.allclose(ref["w"][:, 0], [10.0, 0.0, 0.0, 0.0])
    # the torque on J1 and clutch 1 alone act until 0.4 s: J1 + J2 gain the torque's impulse
    w_sum = ref["w"][0] + ref["w"][1]
    k = np.searchsorted(ref["t"], 0.3)
    impulse = 10.0 * (1.0 - math.cos(2.0 * math.pi * 5.0 * ref["t"][k])) / (2.0 * math.pi * 5.0)
    assert abs(w_sum[k] - (10.0 + impulse)) < 1e-5


def test_closed_form_until_clutch_2_engages(clutches):
    """Until 0.4 s clutch 1 slides alone: J1's and J2's speeds have a closed form, which
    event_driven (rtol 1e-10) follows to 5e-8 rad/s and Modelica's rows to its tolerance."""
    ref, res, on = clutches
    early = ref["t"] <= 0.4
    exact = cc.closed_form(ref["t"][early])
    assert np.all(exact[0] > exact[1])                       # it does slide throughout
    assert np.abs(res.v[:2, on][:, early] - exact).max() < 5e-8
    assert np.abs(ref["w"][:2, early] - exact).max() < MODELICA_SPEED_TOL
    assert np.abs(ref["w"][2:, early]).max() < 1e-12         # J3 and J4 stay at rest (sums of rows)


def test_scipy_reference_agrees_with_modelica():
    ref = cc.reference()
    sysm = cc.scipy_system()
    _, v, events = sysm.run([10.0, 0.0, 0.0, 0.0], cc.T_END, ref["t"], rtol=1e-10, atol=1e-12)
    assert np.abs(v - ref["w"]).max() < MODELICA_SPEED_TOL
    # every transition of Modelica, at the same time, to the same clutch
    for tm, cl in zip(ref["event_t"], ref["event_clutch"]):
        assert any(c == cl and abs(t - tm) < MODELICA_EVENT_TOL for t, c, _ in events), (tm, cl)


def test_event_driven_agrees_with_modelica(clutches):
    ref, res, on = clutches
    assert res.v.shape == (4, cc.GRID.size)
    dev = np.abs(res.v[:, on] - ref["w"]).max(axis=1)
    assert dev.max() < MODELICA_SPEED_TOL, dev
    ours = [(float(e["t"]), int(e["contact"])) for e in res.events]
    # a clutch closing at its step (0.4 s, 0.9 s) or opening as its force falls through 0
    # (1.25 s) is no event of event_driven; every lock and break-away is, and nothing else
    compared = [(tm, cl) for tm, cl in zip(ref["event_t"], ref["event_clutch"])
                if min(abs(tm - corner) for corner in (0.4, 0.9, 1.25)) > 1e-9]
    assert len(compared) == len(ours) == 6
    for tm, cl in compared:
        assert any(c == cl and abs(t - tm) < MODELICA_EVENT_TOL for t, c in ours), (tm, cl, ours)


def test_event_driven_agrees_with_scipy_at_tight_tolerances(clutches):
    _, res, _ = clutches
    tight = cc.simulate(rtol=1e-12, atol=1e-14)
    _, v, events = cc.scipy_system().run([10.0, 0.0, 0.0, 0.0], cc.T_END, cc.GRID, rtol=1e-12, atol=1e-14)
    assert np.abs(tight.v - v).max() < 1e-8
    locks = [t for t, _, m in events if m == 0]
    ours = [float(e["t"]) for e in tight.events if e["kind"] == "stick"]
    assert len(locks) == len(ours) and np.abs(np.array(locks) - np.array(ours)).max() < 1e-8


def test_moreau_converges_to_event_driven_at_first_order(clutches):
    _, res, _ = clutches
    errs = [np.abs(cc.simulate("moreau", h=h).v - res.v).max() for h in (1e-3, 1e-4)]
    assert 5.0 < errs[0] / errs[1] < 20.0, errs
    assert errs[1] < 1e-2


def _quick(module, tmp_path):
    files = module.run(tmp_path, quick=True, quiet=True)
    assert all(Path(f).exists() for f in files)
    return files


@pytest.mark.slow      # the benchmark times 8 scipy runs and 3 of ours, 3 times each
def test_clutches_driver_writes_its_files(tmp_path):
    files = _quick(cc, tmp_path)
    names = {Path(f).name for f in files}
    assert {"gallery_clutches.csv", "gallery_clutches.png", "gallery_clutches_compare.md",
            "gallery_clutches_events.md", "gallery_clutches_bench.md"} <= names
    assert "times** faster than scipy" in (tmp_path / "gallery_clutches_bench.md").read_text()
