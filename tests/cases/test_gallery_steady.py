"""The gallery's steady states (cases.gallery_steady, docs/gallery/steady-states.md): the driver's
--quick run against closed forms written here (the belt's stick-slip cycle, the Stribeck law's
Hopf point), Den Hartog's closed forms (cases.gallery_denhartog), and, for the friction damper,
harmonic balance against shooting and shooting against a scipy integration of the same
equations run to its steady state."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from cases import _common as c  # noqa: E402
from cases import gallery_denhartog as dh  # noqa: E402
from cases import gallery_steady as gs  # noqa: E402


def _rows(path: Path) -> list[dict[str, float]]:
    cols = c.read_csv(path)
    return [{k: (float(v) if v not in ("", "belt") else v) for k, v in zip(cols, vals)}
            for vals in zip(*cols.values())]


@pytest.fixture(scope="module")
def out(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The driver's --quick run (a few seconds)."""
    d = tmp_path_factory.mktemp("steady")
    files = gs.main(["--outdir", str(d), "--quick", "--quiet"])
    assert {f.name for f in files} >= {"steady_belt.csv", "steady_denhartog.csv", "steady_hopf.csv",
                                       "steady_hopf_point.csv", "steady_damper.csv", "steady_belt.png",
                                       "steady_denhartog.png", "steady_hopf.png", "steady_damper.png",
                                       "cases.gallery_steady.provenance.json"}
    return Path(files[0]).parent          # --quick writes into a subdirectory of its own


def test_belt_cycle_equals_its_closed_form_along_the_branch(out: Path) -> None:
    """The paper's belt with set-valued Coulomb: slip arc of amplitude A = hypot(d, v_b/w)
    about x_k, d = (mu_s - mu_k) m g / k, then stuck over 2 d; the continuation's period,
    amplitude and stick fraction equal it to 1e-8 from v_b = 0.2 to 2 m/s, and the nontrivial
    multiplier is 0 (the stick phase)."""
    m, k, g, mu_s, mu_k = 10.0, 300.0, 9.81, 0.35, 0.3
    w, d = math.sqrt(k / m), (mu_s - mu_k) * m * g / k
    rows = _rows(out / "steady_belt.csv")
    assert rows[0]["v_b [m/s]"] == pytest.approx(0.2) and rows[-1]["v_b [m/s]"] == pytest.approx(2.0)
    assert len(rows) >= 10
    for r in rows:
        v_b = r["v_b [m/s]"]
        amp = math.hypot(d, v_b / w)
        stuck = 2.0 * d / v_b
        period = (math.pi + 2.0 * math.asin(v_b / (amp * w))) / w + stuck
        assert r["period [s]"] == pytest.approx(period, rel=1e-8)
        assert r["amplitude [m]"] == pytest.approx(amp, rel=1e-8)
        assert r["stick fraction [-]"] == pytest.approx(stuck / period, rel=1e-7)
        assert r["nontrivial multiplier [-]"] < 1e-10 and r["stable [-]"] == 1


def test_den_hartog_response_against_his_closed_forms(out: Path) -> None:
    """Where Den Hartog's non-stop motion holds the response curve's amplitude equals it to
    1e-8; where the mass stops once each half period the stick fraction equals the closed form
    with stops to 1e-8; both kinds occur."""
    rows = _rows(out / "steady_denhartog.csv")
    nonstop = [r for r in rows if r["closed form holds [-]"] == 1]
    stops = [r for r in rows if r["stops per period [-]"] == 2]
    assert len(nonstop) >= 5 and len(stops) >= 3
    for r in nonstop:
        assert r["X k/P0 [-]"] == pytest.approx(dh.amplitude(r["beta [-]"], r["r [-]"]), rel=1e-8)
    for r in stops:
        assert r["stick fraction closed form [-]"] != ""
        assert abs(r["stick fraction [-]"] - r["stick fraction closed form [-]"]) < 1e-8
        assert r["stick fraction [-]"] > 0.01
    assert all(r["stable [-]"] == 1 for r in rows)


def test_hopf_point_against_the_linearisation(out: Path) -> None:
    """Stribeck's mu = mu_k + (mu_s - mu_k) exp(-(v/v_s)^delta): steady sliding on the damped
    belt loses stability at c_H = -m g mu'(v_b). The branch of cycles shrinks to nothing there
    (its squared amplitude extrapolated to zero within 1e-4 of c_H), with the period 2 pi
    sqrt(m/k) of the undamped oscillation, and its cycles are stable (supercritical)."""
    law = gs.HOPF_LAW
    v, vs, delta = gs.HOPF_VB, law["v_s"], law["delta"]
    slope = -(law["mu_s"] - law["mu_k"]) * delta * v ** (delta - 1) / vs ** delta * math.exp(-(v / vs) ** delta)
    c_h = -10.0 * 9.81 * slope
    point = _rows(out / "steady_hopf_point.csv")[0]
    assert point["c_H linearisation [N s/m]"] == pytest.approx(c_h, rel=1e-5)
    assert point["c_H branch [N s/m]"] == pytest.approx(c_h, rel=1e-4)
    assert point["period at c_H branch [s]"] == pytest.approx(2 * math.pi * math.sqrt(10.0 / 300.0), rel=1e-4)
    cycles = [r for r in _rows(out / "steady_hopf.csv") if r["amplitude [m]"] > gs.HOPF_FLOOR]
    assert len(cycles) >= 3
    assert all(r["c [N s/m]"] < c_h and r["stable [-]"] == 1 for r in cycles)
    amps = [r["amplitude [m]"] for r in cycles]
    assert amps == sorted(amps, reverse=True)         # shrinking towards c_H


def test_friction_damper_harmonic_balance_approaches_shooting(out: Path) -> None:
    """Harmonic balance's amplitude approaches shooting's as the harmonics grow: within 15 % at
    one harmonic, 1 % at the most, each count better than the one before over the curve."""
    d = c.read_numeric_csv(out / "steady_damper.csv")
    worst = [float(np.max(d[f"HB{h} abs relative difference [-]"])) for h in gs.QUICK_HARMONICS]
    assert worst[0] < 0.15 and worst[-1] < 1e-2
    assert all(b < a for a, b in zip(worst, worst[1:]))


def test_friction_damper_shooting_against_scipy() -> None:
    """The shooting orbit at the lowest frequency against scipy's DOP853 run of the same
    equations (m x'' = F sin(2 pi f t) - k x - c x' - N mu(x')) for 15 periods (100 s; the
    viscous damper alone decays as exp(-c t / (2 m)), e^-20 over it) from rest: the amplitude
    over its last period within 1e-5."""
    import stickslip as ss
    from scipy.integrate import solve_ivp
    p, f = gs.DAMPER, float(gs.FREQUENCIES[0])

    def rhs(t: float, y: np.ndarray) -> list[float]:
        mu = float(ss.friction_coefficient("proposed", np.array([y[1]]), mu_s=p["mu_s"], mu_k=p["mu_k"],
                                           v_s=p["v_s"])[0])
        force = p["force"] * math.sin(2 * math.pi * f * t) - p["k"] * y[0] - p["c"] * y[1] - p["normal_force"] * mu
        return [y[1], force / p["m"]]
    period = 1.0 / f
    t_last = np.linspace(14 * period, 15 * period, 4001)
    sol = solve_ivp(rhs, (0.0, 15 * period), [0.0, 0.0], method="DOP853", rtol=1e-10, atol=1e-12, t_eval=t_last)
    amp_scipy = 0.5 * (sol.y[0].max() - sol.y[0].min())
    orb = ss.periodic_orbit(gs.damper(f), method="dopri5")
    assert orb.amplitude[0] == pytest.approx(amp_scipy, rel=1e-5)
