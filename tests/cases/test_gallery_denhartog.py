"""The gallery's Den Hartog oscillator (cases.gallery_denhartog) against independent
references: Den Hartog's closed form and a scipy event-location integration of the oscillator
with stops."""
from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("scipy")
from scipy.integrate import solve_ivp  # noqa: E402

from cases import gallery_denhartog as dh  # noqa: E402


# ---------------------------------------------------------------------------------------------
# Den Hartog
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("beta, r", [(0.6, 0.1), (1.5, 0.3), (2.0, 0.5), (0.8, 0.3), (3.0, 0.1)])
def test_nonstop_amplitude_matches_den_hartog(beta: float, r: float) -> None:
    """Where Den Hartog's non-stop motion holds, the event-driven steady amplitude is his
    closed form to 1e-4 (relative), with no stops."""
    assert dh.nonstop_valid(beta, r)
    p = dh.simulate_point(beta, r)
    assert p["stops"] == 0
    assert abs(p["amplitude"] / dh.amplitude(beta, r) - 1.0) < 1e-4


def test_closed_form_path_solves_the_equation() -> None:
    """The closed form's half cycle satisfies x'' + x = cos(beta t + theta) - r (finite
    differences) and ends at +X at rest: an independent check of the formula's algebra."""
    beta, r = 1.5, 0.3
    x_amp = dh.amplitude(beta, r)
    v = 1.0 / (1.0 - beta ** 2)
    theta = math.atan2(r * math.tan(math.pi / (2 * beta)) / (v * beta), -x_amp / v)
    tau = np.linspace(0.0, math.pi / beta, 20001)
    x, xd = dh._half_cycle(beta, r, x_amp, theta, tau)
    h = tau[1] - tau[0]
    xdd = (x[2:] - 2 * x[1:-1] + x[:-2]) / h ** 2
    assert np.max(np.abs(xdd + x[1:-1] - np.cos(beta * tau[1:-1] + theta) + r)) < 1e-6
    assert abs(x[0] + x_amp) < 1e-12 and abs(x[-1] - x_amp) < 1e-12 and abs(xd[-1]) < 1e-12


def _scipy_stick_fraction(beta: float, r: float, periods: int, n_avg: int) -> float:
    """The oscillator x'' + x = cos(beta t) - r sgn(x') with stops, integrated mode by mode by
    scipy (solve_ivp with event location, rtol 1e-12): the stick fraction over the last
    n_avg periods."""
    period = 2 * math.pi / beta
    t_end = periods * period
    t, x, v, mode = 0.0, 0.0, 0.0, 0          # at rest, stuck (cos(0) = 1 > r breaks away at once)
    stuck: list[tuple[float, float]] = []
    while t < t_end:
        if mode == 0:
            net = -x + math.cos(beta * t)
            if abs(net) > r * (1 + 1e-12):
                mode = 1 if net > 0 else -1
                continue
            ev = lambda s, y, x=x: abs(-x + math.cos(beta * s)) - r  # noqa: E731
            ev.terminal, ev.direction = True, 1
            sol = solve_ivp(lambda s, y: [0.0], (t, t_end), [0.0], events=ev, rtol=1e-12, atol=1e-14,
                            max_step=period / 50)
            t1 = sol.t_events[0][0] if sol.t_events[0].size else t_end
            stuck.append((t, t1))
            t = t1
            net = -x + math.cos(beta * t)
            mode = 1 if net > 0 else -1
        else:
            s = mode
            ev = lambda _, y: y[1]  # noqa: E731
            ev.terminal, ev.direction = True, -s
            sol = solve_ivp(lambda tt, y: [y[1], -y[0] + math.cos(beta * tt) - r * s], (t, t_end), [x, v],
                            events=ev, rtol=1e-12, atol=1e-14, method="DOP853")
            if not sol.t_events[0].size:
                break
            t, x, v = sol.t_events[0][0], sol.y_events[0][0][0], 0.0
            net = -x + math.cos(beta * t)
            mode = 0 if abs(net) <= r else (1 if net > 0 else -1)
    t0 = t_end - n_avg * period
    return sum(max(0.0, min(b, t_end) - max(a, t0)) for a, b in stuck) / (n_avg * period)


@pytest.mark.parametrize("beta, r", [(0.4, 0.5), (2.0, 0.7)])
def test_stick_fraction_against_scipy_and_closed_form(beta: float, r: float) -> None:
    """With stops, the event-driven stick fraction agrees with a scipy event-location
    integration to 1e-6, with the closed form with one stop per half period to 1e-6, and with
    Moreau-Jean (h = T/2000, counted on its output grid) to 2e-3."""
    p = dh.simulate_point(beta, r)
    assert p["stops"] == 2
    ref = _scipy_stick_fraction(beta, r, dh.N_PERIODS, dh.N_AVG)
    assert abs(p["stick_fraction"] - ref) < 1e-6
    assert p["closed_stop"] is not None
    assert abs(p["stick_fraction"] - p["closed_stop"]["stick_fraction"]) < 1e-6
    assert abs(p["amplitude"] - p["closed_stop"]["amplitude"]) < 1e-6
    assert abs(p["moreau"] - p["stick_fraction"]) < 2e-3


def test_nonstop_region_boundary_is_where_stops_begin() -> None:
    """Just inside the closed form's non-stop region the simulation has no stops, just
    outside it has stops (at beta = 0.7, scanning r)."""
    beta = 0.7
    rs = np.linspace(0.05, 0.95, 181)
    holds = np.array([dh.nonstop_valid(beta, r) for r in rs])
    edge = int(np.flatnonzero(~holds)[0])
    assert edge > 0 and holds[:edge].all()
    assert dh.simulate_point(beta, float(rs[edge - 2]))["stops"] == 0
    assert dh.simulate_point(beta, float(rs[edge + 2]))["stops"] > 0


@pytest.mark.slow     # about 20 s
def test_denhartog_driver_quick(tmp_path) -> None:
    """The driver's quick run writes its tables and figures; every non-stop row within 1e-3."""
    files = dh.main(["--outdir", str(tmp_path), "--quick", "--quiet"])
    names = {f.name for f in files}
    for n in ("denhartog.csv", "denhartog_amplitude.md", "denhartog_stops.md", "denhartog_amplitude.png",
              "denhartog_amplitude.pdf", "denhartog_regions.png"):
        assert n in names
    rows = dh._rows(tmp_path / "quick" / "denhartog.csv")   # a --quick run writes into quick/
    diffs = [abs(r["relative difference [-]"]) for r in rows if r["closed form holds [-]"] == 1.0]
    assert diffs and max(diffs) < 1e-3


def test_event_driven_finds_every_breakaway_without_corners() -> None:
    """The oscillator at F/P0 = 0.3, beta = 0.3 from rest (the case event_driven once missed,
    its step growing while the mass was stuck): a mass stuck at x with |cos(beta t) - x| > F
    for part of every period must slip again, so there are slip events in the last 5 of 10
    periods; the same events and motion as the model with a zero force that has a corner
    every tenth of a period (each corner ends a mode: checked at least that often)."""
    import stickslip as ss
    beta, r = 0.3, 0.3
    period = 2 * math.pi / beta
    kw = dict(method="event_driven", t_end=10 * period, n_out=501, rtol=1e-10, atol=1e-12)
    res = ss.simulate(dh.model(beta, r), **kw)
    assert any(e["kind"] == "slip" and e["t"] > 5 * period for e in res.events)
    ref_model = dh.model(beta, r)
    corners = np.linspace(0.0, 10 * period, 101)
    ref_model.add_force(0, ss.signal.table(corners, np.zeros_like(corners)))
    ref = ss.simulate(ref_model, **kw)
    assert len(ref.events) == len(res.events)
    np.testing.assert_allclose(res.events["t"], ref.events["t"], rtol=0, atol=1e-8)
    np.testing.assert_allclose(res.x, ref.x, rtol=0, atol=1e-9)
