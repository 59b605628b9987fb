"""DOP853 through the Python facade: the run Hairer's dop853.f makes (tests/fortran/
test_integrators.f90 compares every step), its own controls, bad input, and the batch path."""
from __future__ import annotations

import numpy as np
import pytest

import stickslip as ss


def test_registry_lists_dop853() -> None:
    info = ss.REGISTRY["method"]["dop853"]
    assert info["order"] == 8 and info["adaptive"] and not info["implicit"]
    assert {"rtol", "atol", "hmin", "hmax", "h0", "fac1", "fac2", "beta_pi", "nstiff"} <= set(info["controls"])


def test_belt_as_hairer() -> None:
    """Hairer's dop853.f on the belt with the proposed law, 30 s from rest, rtol = atol = 1e-7,
    WORK = 0 (his defaults: no step floor, hmax the whole interval): NFCN NSTEP NACCPT NREJCT =
    7578 648 448 200, x(30 s) = -8.78479513725508032e-02 m. Output at t_end only (no dense
    output)."""
    r = ss.simulate("belt", "proposed", method="dop853", t_end=30.0, rtol=1e-7, atol=1e-7, hmin=0.0,
                    hmax=0.0, n_out=2)
    st = r.stats
    assert (st["nfev"], st["nstep"], st["naccept"], st["nreject"]) == (7578, 648, 448, 200)
    assert r.x[-1] == pytest.approx(-8.78479513725508032e-02, abs=1e-13)
    assert r.v[-1] == pytest.approx(1.14447926107284248, abs=1e-13)


def test_dense_output_costs_three_evaluations_per_step_with_output() -> None:
    kw = dict(t_end=30.0, rtol=1e-7, atol=1e-7, hmin=0.0, hmax=0.0)
    end = ss.simulate("belt", "proposed", method="dop853", n_out=2, **kw)
    grid = ss.simulate("belt", "proposed", method="dop853", n_out=1001, **kw)
    assert grid.stats["nstep"] == end.stats["nstep"]
    extra = grid.stats["nfev"] - end.stats["nfev"]
    assert extra % 3 == 0 and 0 < extra // 3 <= end.stats["naccept"]
    assert grid.x[-1] == end.x[-1]


def test_own_controls_change_the_run() -> None:
    kw = dict(t_end=10.0, rtol=1e-8, atol=1e-8, hmin=0.0, hmax=0.0, n_out=2)
    base = ss.simulate("belt", "proposed", method="dop853", **kw)
    other = ss.simulate("belt", "proposed", method="dop853", fac2=3.0, safety=0.8, h0=1e-4, **kw)
    assert other.stats["nstep"] != base.stats["nstep"]
    # both meet the tolerance's accuracy: within 1e-5 m of each other at 10 s
    assert abs(other.x[-1] - base.x[-1]) < 1e-5


@pytest.mark.parametrize("name, value", [("fac1", 0.0), ("fac2", 0.5), ("safety", 1.5), ("beta_pi", 0.3),
                                         ("nstiff", 0)])
def test_bad_control(name: str, value: float) -> None:
    with pytest.raises(ValueError, match="fac1|safety|beta_pi|nstiff"):
        ss.simulate("belt", "proposed", method="dop853", t_end=1.0, **{name: value})


def test_not_a_control() -> None:
    with pytest.raises(ValueError, match="not a control of method"):
        ss.simulate("belt", "proposed", method="dop853", t_end=1.0, h=1e-3)


def test_batch_rows_equal_single_runs() -> None:
    ks = [200.0, 300.0, 400.0]
    b = ss.simulate_batch("belt", "proposed", method="dop853", t_end=5.0, rtol=1e-9, atol=1e-9, hmin=0.0,
                          hmax=0.0, k=ks)
    assert (b.status == 0).all()
    for i, k in enumerate(ks):
        r = ss.simulate("belt", "proposed", method="dop853", t_end=5.0, rtol=1e-9, atol=1e-9, hmin=0.0,
                        hmax=0.0, k=k, n_out=201)
        assert b.x_end[i] == r.x[-1] and b.v_end[i] == r.v[-1]
        assert b.nfev[i] == r.stats["nfev"]


def test_more_accurate_than_dopri5_for_fewer_evaluations() -> None:
    """At rtol = atol = 1e-10 on the belt, DOP853 is at least as accurate as DOPRI5 (against
    DOP853 at 1e-13) with fewer than half its evaluations."""
    kw = dict(t_end=20.0, hmin=0.0, hmax=0.0, n_out=2)
    ref = ss.simulate("belt", "proposed", method="dop853", rtol=1e-13, atol=1e-13, **kw)
    d8 = ss.simulate("belt", "proposed", method="dop853", rtol=1e-10, atol=1e-10, **kw)
    d5 = ss.simulate("belt", "proposed", method="dopri5", rtol=1e-10, atol=1e-10, **kw)
    err8 = np.max(np.abs([d8.x[-1] - ref.x[-1], d8.v[-1] - ref.v[-1]]))
    err5 = np.max(np.abs([d5.x[-1] - ref.x[-1], d5.v[-1] - ref.v[-1]]))
    assert err8 <= err5 and 2 * d8.stats["nfev"] < d5.stats["nfev"]
