"""The implicit integrators (RADAU5, implicit Euler, generalized-alpha) on the paper's scenes,
against independent truths: the slope's creep speed v* (mu(v*) = tan theta, by brentq on our
own numpy law), the belt's harmonic orbit (mu stays at mu_k) with each method's predicted
damping, and RADAU5 from rest under the proposed law (mu ~ |v|^(1/3), infinite slope at 0)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import stickslip as ss
from cases import implicit
from test_cases_study import G, K, M, MU_K, creep_speed_ref

FIXED = [("implicit_euler", {}), ("galpha", {"rho_inf": 0.0}), ("galpha", {"rho_inf": 0.5}),
         ("galpha", {"rho_inf": 1.0})]


@pytest.mark.parametrize("law", ["recurdyn", "proposed"])
@pytest.mark.parametrize("method,kw", [("radau5", {"rtol": 1e-8, "atol": 1e-11})]
                         + [(m, {**k, "h": h}) for m, k in FIXED for h in (1e-3, 1e-4)])
def test_slope_creep_speed(law, method, kw):
    """Near v* the motion is v' = lambda (v - v*) with lambda = -g cos(theta) mu'(v*), about
    -540 1/s (RecurDyn) and -450 1/s (proposed): after 2 s the transient is below e^-900. v*
    is a fixed point of every method (f(v*) = 0 solves each stage equation exactly), so what
    is left is the Newton tolerance (newton_rtol = 1e-10) or RADAU5's rtol = 1e-8 on a step
    that starts at rest: 1e-7 relative bounds both."""
    v_star = creep_speed_ref(law)
    r = ss.simulate("slope", law, method=method, t_end=2.0, n_out=3, **kw)
    assert abs(r.v[-1] / v_star - 1.0) < 1e-7, (r.v[-1], v_star)


@pytest.mark.parametrize("law", ["recurdyn", "proposed"])
@pytest.mark.parametrize("h", [1e-2, 0.1, 1.0])
def test_slope_implicit_euler_any_h(law, h):
    """Implicit Euler is L-stable: from rest it reaches v* (to the Newton tolerance, as above)
    at any step, up to h = 1 s = 540 / |lambda|, where RK4 needs h < 5e-3 s. From rest at
    h >= 1e-2 the simplified Newton iteration fails and the damped Newton fallback
    (damped_newton in fortran/integrators/stickslip_fixed_implicit_body.inc) solves the first steps."""
    v_star = creep_speed_ref(law)
    r = ss.simulate("slope", law, method="implicit_euler", h=h, t_end=20.0, n_out=3)
    assert abs(r.v[-1] / v_star - 1.0) < 1e-7, (r.v[-1], v_star)


def _amplitude(r) -> float:
    w = math.sqrt(K / M)
    x_k = MU_K * M * G / K
    return math.hypot(r.x[-1] - x_k, r.v[-1] / w)


@pytest.mark.parametrize("law", ["coulomb", "recurdyn"])
@pytest.mark.parametrize("h", [1e-3, 1e-2])
def test_belt_implicit_euler_damping(law, h):
    """On the belt from rest v_rel >= v_b - x_k w = 0.96 m/s > v_d: mu = mu_k, a linear
    oscillator about x_k = mu_k m g / k. Implicit Euler multiplies A = |(x - x_k, v/w)| by
    (1 + (w h)^2)^(-1/2) each step (I - h A is a scaled rotation), so after t_end = N h:
    A = x_k (1 + (w h)^2)^(-N/2), from rest A(0) = x_k."""
    t_end = 10.0
    w = math.sqrt(K / M)
    x_k = MU_K * M * G / K
    r = ss.simulate("belt", law, method="implicit_euler", h=h, t_end=t_end, n_out=1001)
    predicted = x_k * (1.0 + (w * h) ** 2) ** (-round(t_end / h) / 2.0)
    assert predicted < 0.99 * x_k                     # the damping is visible
    assert abs(_amplitude(r) / predicted - 1.0) < 0.01
    assert np.min(1.5 - r.v) > 1.5 * 0.01                 # v_rel stayed beyond v_d = 1.5 v_s


@pytest.mark.parametrize("rho_inf", [0.0, 0.5, 1.0])
def test_belt_galpha_root(rho_inf):
    """Generalized-alpha keeps the orbit within its principal root's damping: the modulus
    from implicit.galpha_root (an eigenvalue of the amplification matrix) is 1 - c (w h)^4
    and at h = 1e-2 the amplitude stays within 1% of x_k |r|^N; rho_inf = 1 conserves it."""
    h, t_end = 1e-2, 10.0
    w = math.sqrt(K / M)
    x_k = MU_K * M * G / K
    root = implicit.galpha_root(w * h, rho_inf)
    assert root <= 1.0 + 1e-12
    r = ss.simulate("belt", "recurdyn", method="galpha", rho_inf=rho_inf, h=h, t_end=t_end, n_out=3)
    assert abs(_amplitude(r) / (x_k * root ** round(t_end / h)) - 1.0) < 0.01


def test_radau5_proposed_from_rest():
    """The proposed law from rest (the reported failure: NEWTON_FAILED at t = 0): RADAU5
    completes at every tolerance and creeps as DOPRI5 does; at rtol = 1e-8 the first step's
    Newton cannot converge at h_min (nforced > 0), and without forced steps that is an error."""
    ref = ss.simulate("slope", "proposed", method="dopri5", t_end=20.0, rtol=1e-10, atol=1e-13, n_out=2)
    for rtol in (1e-4, 1e-6, 1e-8):
        r = ss.simulate("slope", "proposed", method="radau5", t_end=20.0, rtol=rtol, atol=1e-3 * rtol,
                        n_out=2)
        assert abs(r.x[-1] - ref.x[-1]) < 1e-3 * rtol * 20.0
    assert r.stats["nforced"] >= 1
    with pytest.raises(ss.IntegrationError) as exc:
        ss.simulate("slope", "proposed", method="radau5", t_end=1.0, rtol=1e-8, atol=1e-11,
                    allow_forced=False)
    assert exc.value.status == ss.REGISTRY["status"]["NEWTON_FAILED"]


def test_radau5_coulomb_slope_completes():
    """Coulomb's jump has no smooth stage solution at v = 0: RADAU5 forces steps at h_min and
    stays near the sticking solution (x of the order of h_min times the speeds involved)."""
    r = ss.simulate("slope", "coulomb", method="radau5", t_end=0.01, n_out=2)
    assert r.stats["nforced"] > 0
    assert abs(r.x[-1]) < 1e-6


def test_implicit_driver_quick(tmp_path):
    """python -m cases.implicit --quick writes its CSVs and PNGs; RK4 with h = 1e-3 s makes
    4 evaluations a step plus the first (the automatic column's reference), every run
    reaches t_end, and RADAU5 unbounded is the cheapest stickslip solver on the slope."""
    files = implicit.main(["--outdir", str(tmp_path), "--quick", "--threads", "1", "--quiet"])
    assert {f.parent for f in files} == {tmp_path / "quick"}     # not the full run's files
    tmp_path = tmp_path / "quick"
    names = {f.name for f in files}
    assert {"implicit_slope.csv", "implicit_slope_equal.csv", "fig14_implicit.csv",
            "implicit_fig14_amplitude.csv", "implicit_auto.csv", "implicit_slope.png",
            "fig14_implicit.png"} <= names
    from cases._common import read_csv
    auto = read_csv(tmp_path / "implicit_auto.csv")
    for i, mode in enumerate(auto["mode [-]"]):
        assert auto["status [-]"][i] == "0"
        if mode == "rk4 h=1e-3":
            assert int(auto["nfev [-]"][i]) == 4 * round(float(auto["t_end [s]"][i]) / 1e-3) + 1
    slope = read_csv(tmp_path / "implicit_slope.csv")
    for law in ("recurdyn", "proposed"):
        nfev = {s: int(n) for l, s, r, n in zip(slope["law [-]"], slope["solver [-]"], slope["rtol [-]"],
                                               slope["nfev [-]"]) if l == law and float(r) == 1e-4}
        assert nfev["radau5"] < min(nfev["dopri5"], nfev["radau5 hmax=1e-2"])
