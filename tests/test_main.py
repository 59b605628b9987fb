"""The command line (python -m stickslip, stickslip.__main__): `run` writes the run's numbers,
keeps an existing file without --force and refuses a bad method in one line."""
from __future__ import annotations

import numpy as np

import stickslip as ss
from test_model import clutch


def test_command_line_run(tmp_path, capsys):
    """python -m stickslip run: the CSV holds the run's numbers; an existing file is kept
    without --force; a bad method is one line, exit status 2."""
    from stickslip.__main__ import main
    clutch().to_toml(tmp_path / "c.toml")
    out = tmp_path / "c.csv"
    assert main(["run", str(tmp_path / "c.toml"), "--method", "moreau", "--h", "1e-3", "--t-end", "1.0",
                 "--n-out", "11", "--out", str(out)]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    res = ss.simulate(clutch(), method="moreau", h=1e-3, t_end=1.0, n_out=11)
    assert np.array_equal(data[:, 1:3].T, res.x) and out.read_text().startswith("t,x_J1,x_J2,v_J1,v_J2")
    before = out.read_text()
    assert main(["run", str(tmp_path / "c.toml"), "--method", "moreau", "--h", "1e-3", "--t-end", "1.0",
                 "--out", str(out)]) == 2
    assert out.read_text() == before and "exists" in capsys.readouterr().err
    assert main(["run", str(tmp_path / "c.toml"), "--method", "euler", "--t-end", "1.0",
                 "--out", str(tmp_path / "d.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "method" in err and not (tmp_path / "d.csv").exists()
