"""Stability at the extremes (issue 5): every extreme ends with a clear status (or a clear
exception) and finite output with bounded memory; observed orders on the smooth belt orbit;
the RK4 stability boundary of the RecurDyn law on the slope against the linear prediction."""
from __future__ import annotations

import math
import sys
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import stickslip

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from cases import stability  # noqa: E402

# (name, simulate_batch keyword arguments, expected status)
EXTREMES = [
    ("v_s=1e-6 rk4", dict(scene="slope", law="recurdyn", method="rk4", h=1e-3, v_s=1e-6), 0),
    ("v_s=1e-6 dopri5", dict(scene="slope", law="proposed", method="dopri5", v_s=1e-6), 0),
    ("beta=1e-3 rk4", dict(scene="slope", law="proposed", method="rk4", h=1e-3, beta=1e-3), 0),
    ("beta=1e-3 dopri5", dict(scene="belt", law="proposed", method="dopri5", beta=1e-3), 0),
    ("beta=1 dopri5", dict(scene="belt", law="proposed", method="dopri5", beta=1.0), 0),
    ("a=1.0001 rk4", dict(scene="belt", law="proposed", method="rk4", h=1e-3, a=1.0001), 0),
    ("a=100 dopri5", dict(scene="belt", law="proposed", method="dopri5", a=100.0), 0),
    ("t_end=1e4 rk4", dict(scene="belt", law="proposed", method="rk4", h=1e-3, t_end=1e4), 0),
    ("t_end=1e4 dopri5", dict(scene="belt", law="proposed", method="dopri5", t_end=1e4), 0),
    ("k=1e6 rk4 h=1e-3", dict(scene="belt", law="recurdyn", method="rk4", h=1e-3, k=1e6), 0),
    ("k=1e6 rk4 h=1e-2", dict(scene="belt", law="recurdyn", method="rk4", h=1e-2, k=1e6), -11),
    ("k=1e6 dopri5", dict(scene="belt", law="recurdyn", method="dopri5", k=1e6), 0),
    ("uphill v0=-1", dict(scene="slope", law="proposed", method="dopri5", v0=-1.0), 0),
    ("uphill v0=-1 coulomb", dict(scene="slope", law="coulomb", method="rk4", h=1e-3, v0=-1.0), 0),
    ("downhill v0=+1", dict(scene="slope", law="recurdyn", method="rk4", h=1e-3, v0=1.0), 0),
    ("budget rk4", dict(scene="belt", law="proposed", method="rk4", h=1e-3, max_steps=1000), -2),
    # the paper's hmax (simulate's default, the whole run, needs fewer than 1000 steps here)
    ("budget dopri5", dict(scene="belt", law="proposed", method="dopri5", max_steps=1000, hmax=1e-2), -2),
]


@pytest.fixture(scope="module")
def extremes() -> dict[str, tuple[stickslip.BatchResult, int, int]]:
    """All extremes, one batch per row (rows differ in which options they set), 2 threads."""
    out = {}
    for name, kw, expected in EXTREMES:
        kw = dict({"t_end": 20.0}, **kw)
        b = stickslip.simulate_batch(kw.pop("scene"), kw.pop("law"), n_grid=201, threads=1, **kw)
        out[name] = (b, 0, expected)
    return out


@pytest.mark.filterwarnings("ignore::stickslip.UnstableStepWarning")   # extreme on purpose
@pytest.mark.parametrize("name", [e[0] for e in EXTREMES])
def test_extreme_ends_with_clear_status_and_finite_output(extremes, name: str) -> None:
    b, i, expected = extremes[name]
    assert b.status[i] == expected, b.message(i)
    assert np.isfinite([b.x_end[i], b.v_end[i], b.v_max[i], b.t_reached[i]]).all()
    if expected == 0:
        assert b.t_reached[i] == b.t_end[i] and b.t_last[i] == b.t_end[i]
    else:
        assert 0.0 < b.t_reached[i] < b.t_end[i]


def test_box_started_uphill_or_downhill_stops_sliding(extremes) -> None:
    """Friction (mu_k > tan theta) stops the box whichever way it slides: it ends at creep
    speed, far below its 1 m/s start."""
    for name in ("uphill v0=-1", "downhill v0=+1"):
        b, i, _ = extremes[name]
        assert abs(b.v_end[i]) < 0.01, name


def test_stiff_spring_blows_up_rk4_beyond_its_bound_only(extremes) -> None:
    """k = 1e6 N/m: w = 316 rad/s; RK4's imaginary-axis limit is h w < 2.83: h = 1e-3 is
    inside, h = 1e-2 (h w = 3.2) outside and ends with SS_DIVERGED (its state leaves the
    belt's energy bound long before it would overflow), not NaN output."""
    assert extremes["k=1e6 rk4 h=1e-3"][0].v_max[0] < 10.0
    assert "diverged" in extremes["k=1e6 rk4 h=1e-2"][0].message(0)


def test_rtol_below_roundoff_is_a_clear_value_error() -> None:
    with pytest.raises(ValueError, match=r"rtol.*100 eps"):
        stickslip.simulate("slope", "recurdyn", method="dopri5", t_end=1.0, rtol=1e-14)
    with pytest.raises(ValueError, match="rtol"):
        stickslip.simulate_batch("slope", "recurdyn", method="dopri5", t_end=1.0, rtol=1e-14)
    r = stickslip.simulate("slope", "recurdyn", method="dopri5", t_end=1.0, rtol=3e-14, atol=1e-16)
    assert r.stats["status"] == 0 and np.isfinite(r.x).all()


def test_tiny_step_over_20_s_has_bounded_memory() -> None:
    """h = 1e-6 over 20 s: 2e7 RK4 steps (320 MB if each step's state were kept) on a
    201-point grid; Python-side allocations stay under 1 MB and the result is the converged
    creep (x = 20 s * v* - transient)."""
    tracemalloc.start()
    r = stickslip.simulate("slope", "recurdyn", method="rk4", t_end=20.0, h=1e-6, n_out=201,
                           max_steps=3 * 10**7)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert r.stats["status"] == 0 and r.stats["nstep"] == 20_000_000
    assert r.x.size == 201 and peak < 1_000_000
    ref = stickslip.simulate("slope", "recurdyn", method="rk4", t_end=20.0, h=1e-4, n_out=2)
    assert r.x[-1] == pytest.approx(ref.x[-1], rel=1e-8)


def _harmonic(t: float) -> float:
    p = stickslip.DEFAULTS
    w = math.sqrt(p["k"] / p["m"])
    return p["mu_k"] * p["m"] * p["g"] / p["k"] * (1.0 - math.cos(w * t))


def test_rk4_order_4_on_the_belt_harmonic_orbit() -> None:
    hs = np.array([1e-2, 5e-3, 2.5e-3, 1.25e-3])
    b = stickslip.simulate_batch("belt", "recurdyn", method="rk4", t_end=5.0, h=hs, n_grid=2)
    err = np.abs(b.x_end - _harmonic(5.0))
    order = np.polyfit(np.log(hs), np.log(err), 1)[0]
    assert 3.8 < order < 4.2, (order, err)


def test_dopri5_order_5_on_the_belt_harmonic_orbit() -> None:
    rtols = 10.0 ** -np.arange(5.0, 11.0)
    b = stickslip.simulate_batch("belt", "coulomb", method="dopri5", t_end=5.0, rtol=rtols,
                                 atol=1e-3 * rtols, hmin=0.0, hmax=0.0, n_grid=2)
    err = np.abs(b.x_end - _harmonic(5.0))
    order = -np.polyfit(np.log(b.nfev.astype(float)), np.log(err), 1)[0]
    assert 4.3 < order < 6.0, (order, err, b.nfev)


@pytest.mark.filterwarnings("ignore::stickslip.UnstableStepWarning")   # a scan across the bound
@pytest.mark.parametrize("v_s", [1e-2, 1e-4])
def test_rk4_boundary_recurdyn_slope_within_10_percent_of_linear(v_s: float) -> None:
    """The largest stable h of a scan 0.7 .. 1.3 h_lin in 2% steps lies within 10% of
    h_lin = 2.785 / (g cos(theta) mu'(v*))."""
    h_lin = stability.linear_bound("slope", "recurdyn", v_s)[1]
    hs = h_lin * np.arange(0.70, 1.31, 0.02)
    cls = []
    for h in hs:
        t_end, n_grid = stability.rk4_grid("slope", float(h))
        b = stickslip.simulate_batch("slope", "recurdyn", method="rk4", t_end=t_end, h=float(h),
                                     v_s=v_s, n_grid=n_grid, threads=1)
        cls.append(stability.classify(b, 0, stability.v_bound("slope", t_end), n_grid))
    assert cls[0] == "stable" and cls[-1] != "stable", cls
    first_bad = hs[[c != "stable" for c in cls].index(True)]
    assert abs(first_bad / h_lin - 1.0) < 0.10, (first_bad / h_lin, cls)
