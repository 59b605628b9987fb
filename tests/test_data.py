"""The repository's data (stickslip.data): the damper records load in SI units with the
README's levels, and bad files are refused naming the file and the column."""
from __future__ import annotations

import numpy as np
import pytest

import stickslip


# ---------------------------------------------------------------------------------------------
# The damper records
# ---------------------------------------------------------------------------------------------
def test_damper_records_load_in_si_units():
    files = stickslip.damper_files()
    assert len(files) == 20 and len(stickslip.damper_files(36)) == 10
    rec = stickslip.load_damper_record(files[-1])
    assert (rec.name, rec.frequency, rec.tension) == ("sine_2Hz_0.5in_36lb", 2.0, 36.0)
    assert rec.amplitude == pytest.approx(0.5 * 0.0254)
    assert rec.t.size == rec.x.size == rec.force.size == rec.v.size == 897
    assert np.all(np.diff(rec.t) > 0) and rec.t[1] - rec.t[0] == pytest.approx(1.0 / 256.0, rel=1e-3)
    sub = rec.subsample(4)
    assert len(sub) == 225 and sub.meta["subsample"] == 4
    rec = stickslip.load_damper_record(stickslip.data.DAMPER_DIR / "sine_1Hz_1in_36lb.csv.gz")
    # the displacement's amplitude is the nominal one, the rig's velocity is dx/dt
    assert np.abs(rec.x).max() == pytest.approx(rec.amplitude, rel=0.05)
    assert np.corrcoef(rec.v, np.gradient(rec.x, rec.t))[0, 1] > 0.99
    # sliding levels of the README (about +15 kN and -20 kN at 36 lb), past mid-stroke
    assert 12e3 < np.median(rec.force[(rec.v > 0) & (rec.x > 0)]) < 18e3
    assert -23e3 < np.median(rec.force[(rec.v < 0) & (rec.x < 0)]) < -16e3


def test_damper_loader_rejects_bad_files(tmp_path):
    bad = tmp_path / "r.csv"
    bad.write_text("t [s],x [m]\n0,0\n1,0\n")
    with pytest.raises(ValueError, match=r"r.csv: no column 'F \[N\]'"):
        stickslip.load_damper_record(bad)
    bad.write_text("t [s],x [m],F [N]\n0,0,1\n0,0,nan\n")
    with pytest.raises(ValueError, match=r"column 'F \[N\]' holds non-finite"):
        stickslip.load_damper_record(bad)
    with pytest.raises(ValueError, match="no such file"):
        stickslip.load_damper_record(tmp_path / "none.csv")
