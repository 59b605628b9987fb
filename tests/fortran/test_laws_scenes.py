"""The four laws of issue 14 (stribeck, karnopp, lugre, elastoplastic) against truths derived by
hand: their curves at hand-computed points, the slope from rest (exact hold, presliding at
sigma0 z = tan(theta), creep at mu(v*) = tan(theta)), the belt's exact Coulomb stick-slip cycle
(Karnopp as dv -> 0), the harmonic orbit from rest and its growth or decay rate -g mu'(v_b)/2,
LuGre's RK4 stability limit, and a named ValueError for every bad parameter value."""
from __future__ import annotations

import math

import numpy as np
import pytest

import stickslip as ss
from cases import _common
from cases import laws_compare as lc
from cases.laws_compare import coulomb_cycle, maxima

MU_S, MU_K, V_S, G = 0.35, 0.30, 0.01, 9.81
THETA = math.radians(10.0)
TAN = math.tan(THETA)
SIGMA0, SIGMA1, SIGMA2 = 1e5 / 9.81, math.sqrt(1e5) / 9.81, 0.4 / 9.81   # the 1995 paper / (1 kg g)
M, K, V_B = 10.0, 300.0, 1.5
OMEGA = math.sqrt(K / M)
X_S, X_K = MU_S * M * G / K, MU_K * M * G / K      # spring stretch at break-away, kinetic centre
NEW = ("stribeck", "karnopp", "lugre", "elastoplastic")


def mu(law, v, **kw):
    return ss.friction_coefficient(law, v, **kw)


def stribeck_g(s, delta=2.0):
    return MU_K + (MU_S - MU_K) * np.exp(-(np.abs(s) / V_S) ** delta)


# ---------------------------------------------------------------------------------------------
# Curves
# ---------------------------------------------------------------------------------------------
def test_stribeck_points():
    # default v_eps = v_s/10 = 1e-3 m/s, delta = 2, c_v = 0
    np.testing.assert_allclose(mu("stribeck", V_S), (MU_K + 0.05 / math.e) * math.tanh(10.0), rtol=1e-14)
    np.testing.assert_allclose(mu("stribeck", -1e-3), -(MU_K + 0.05 * math.exp(-0.01)) * math.tanh(1.0),
                               rtol=1e-14)
    # delta = 1, c_v = 0.1 s/m, v_eps = 2e-3 m/s at v = 0.02 m/s
    np.testing.assert_allclose(mu("stribeck", 0.02, delta=1.0, c_v=0.1, v_eps=2e-3),
                               (MU_K + 0.05 * math.exp(-2.0)) * math.tanh(10.0) + 0.002, rtol=1e-14)
    # far out: mu_k + c_v v
    np.testing.assert_allclose(mu("stribeck", 0.5, c_v=0.1), MU_K + 0.05, rtol=1e-14)
    # v_eps follows v_s (default v_s/10)
    np.testing.assert_allclose(mu("stribeck", 1e-2, v_s=0.1),
                               (MU_K + 0.05 * math.exp(-0.01)) * math.tanh(1.0), rtol=1e-14)


def test_stribeck_continuous_at_rest_and_peak_near_mu_s():
    v = np.linspace(-0.05, 0.05, 200001)            # step 5e-7 m/s
    m = mu("stribeck", v)
    # slope <= mu_s/v_eps: neighbours differ by at most 350 * 5e-7
    assert np.max(np.abs(np.diff(m))) <= MU_S / 1e-3 * 5e-7 * (1 + 1e-9)
    assert mu("stribeck", 0.0) == 0.0
    # the module's claim: the regularised curve still peaks within 2 % of mu_s
    assert 0.98 * MU_S <= m.max() < MU_S


def test_karnopp_curve_at_zero_holding_force():
    np.testing.assert_array_equal(mu("karnopp", [0.0, 5e-4, -9.9e-4, 1e-3, -0.5]), [0.0, 0.0, 0.0, MU_K, -MU_K])
    np.testing.assert_array_equal(mu("karnopp", [5e-4, 2e-3], dv=1e-2), [0.0, 0.0])


@pytest.mark.parametrize("law", ["lugre", "elastoplastic"])
def test_bristle_steady_curves(law):
    v = np.array([1e-3, 0.01, 0.02, 1.5])
    np.testing.assert_allclose(mu(law, v), stribeck_g(v) + SIGMA2 * v, rtol=1e-14)
    np.testing.assert_allclose(mu(law, -v), -(stribeck_g(v) + SIGMA2 * v), rtol=1e-14)
    np.testing.assert_allclose(mu(law, 0.01, sigma2=0.0), MU_K + 0.05 / math.e, rtol=1e-14)
    assert mu(law, 0.0) == 0.0


@pytest.mark.parametrize("law,kw", [("stribeck", {"delta": 0.5, "c_v": 0.2}), ("karnopp", {"dv": 0.1}),
                                    ("lugre", {"sigma2": 1.0}), ("elastoplastic", {"v_s": 0.1})])
def test_odd_with_other_parameters(law, kw):
    v = np.concatenate([np.geomspace(1e-9, 10, 300), np.linspace(0, 0.2, 301)])
    np.testing.assert_array_equal(mu(law, -v, **kw), -mu(law, v, **kw))


def test_registry_names_states():
    for law in ("stribeck", "karnopp"):
        assert ss.REGISTRY["law"][law]["n_states"] == 0
    for law in ("lugre", "elastoplastic"):
        assert ss.REGISTRY["law"][law]["states"] == ("z [m]",)
    r = ss.simulate("slope", "lugre", method="rk4", h=1e-3, t_end=0.01, n_out=3, z0=1e-6)
    assert r.state_labels == ("z [m]",) and r.z.shape == (3,) and r.z[0] == 1e-6
    with pytest.raises(ValueError, match="z0"):
        ss.simulate("slope", "lugre", method="rk4", h=1e-3, t_end=0.01, z0=[0.0, 1.0])


def test_parameter_codes_and_names_unique():
    text = ss.core._ext.registry().decode().rstrip("\x00 \n")
    rows = [line.split("|") for line in text.splitlines() if line.startswith("param|")]
    names, codes = [r[1] for r in rows], [int(r[2]) for r in rows]
    assert len(set(names)) == len(names) and len(set(codes)) == len(codes)
    new = {"delta", "c_v", "v_eps", "dv", "sigma0", "sigma1", "sigma2", "z_ba_ratio"}
    assert new <= set(names)
    assert all(-199 <= c <= -140 for n, c in zip(names, codes) if n in new)


# ---------------------------------------------------------------------------------------------
# Bad values: a ValueError naming the parameter, from both entry points
# ---------------------------------------------------------------------------------------------
BAD = [("stribeck", "delta", 0.0), ("stribeck", "delta", -1.0), ("stribeck", "delta", math.nan),
       ("stribeck", "c_v", -0.1), ("stribeck", "c_v", math.inf), ("stribeck", "v_eps", 0.0),
       ("stribeck", "v_eps", -1e-3), ("karnopp", "dv", 0.0), ("karnopp", "dv", -1e-3),
       ("karnopp", "dv", math.inf), ("lugre", "sigma0", 0.0), ("lugre", "sigma0", -1.0),
       ("lugre", "sigma1", -1.0), ("lugre", "sigma2", -0.1), ("lugre", "mu_k", 0.0),
       ("elastoplastic", "sigma0", math.nan), ("elastoplastic", "z_ba_ratio", 0.0),
       ("elastoplastic", "z_ba_ratio", 1.0), ("elastoplastic", "z_ba_ratio", 1.5)]


@pytest.mark.parametrize("law,name,value", BAD)
def test_bad_parameter_named(law, name, value):
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        mu(law, 0.1, **{name: value})
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        ss.simulate("slope", law, method="rk4", h=1e-3, t_end=0.01, **{name: value})


# ---------------------------------------------------------------------------------------------
# Slope, 10 degrees, from rest
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("method,kw", [("rk4", {"h": 1e-3}), ("rk4", {"h": 1e-4}), ("dopri5", {})])
def test_karnopp_holds_the_box_exactly(method, kw):
    r = ss.simulate("slope", "karnopp", method=method, t_end=20.0, **kw)
    assert np.all(r.x == 0.0) and np.all(r.v == 0.0)


def test_elastoplastic_presliding_is_the_linear_oscillator():
    # |z| stays below z_ba = 0.8 mu_k/sigma0, so z' = v and z = x: x'' = g cos (tan - sigma0 x
    # - (sigma1 + sigma2) x'), a damped oscillator settling exactly at x = tan/sigma0.
    r = ss.simulate("slope", "elastoplastic", method="dopri5", t_end=20.0, n_out=2001, rtol=1e-10, atol=1e-16)
    gc = G * math.cos(THETA)
    w0 = math.sqrt(gc * SIGMA0)
    zeta = gc * (SIGMA1 + SIGMA2) / (2 * w0)
    wd = w0 * math.sqrt(1 - zeta**2)
    xs = TAN / SIGMA0
    t = r.t
    exact = xs * (1 - np.exp(-zeta * w0 * t) * (np.cos(wd * t) + zeta / math.sqrt(1 - zeta**2) * np.sin(wd * t)))
    np.testing.assert_allclose(r.x, exact, rtol=0, atol=1e-9 * xs)
    np.testing.assert_array_equal(r.z, r.x)            # elastic: z' = v exactly
    assert abs(r.x[-1] - xs) < 1e-12 * xs and abs(r.v[-1]) < 1e-15
    assert r.x.max() < 0.8 * MU_K / SIGMA0                 # the overshoot stayed below z_ba


@pytest.mark.parametrize("method,kw", [("rk4", {"h": 1e-3}), ("dopri5", {"rtol": 1e-10, "atol": 1e-16})])
def test_lugre_settles_at_presliding_and_does_not_drift(method, kw):
    r = ss.simulate("slope", "lugre", method=method, t_end=20.0, n_out=201, **kw)
    zs = TAN / SIGMA0                                    # sigma0 z = tan(theta) at v = 0
    np.testing.assert_allclose(r.z[-1], zs, rtol=1e-9)
    # x - z grows by sigma0 |v| z / g >= 0 while z >= 0: x ends at or beyond z
    assert np.all(r.z >= 0) and r.x[-1] >= zs
    assert r.x[-1] < 3 * zs
    # near rest the bristle is a damped oscillator (decay rate >= 70 1/s): after 10 s nothing moves
    half = r.t >= 10.0
    assert np.max(np.abs(r.v[half])) < 1e-12
    assert np.ptp(r.x[half]) < 1e-15


def stribeck_creep_speed():
    """v* with mu(v*) = tan(theta) for the default Stribeck law, by bisection on the formula."""
    lo, hi = 0.0, 0.01
    for _ in range(200):
        v = 0.5 * (lo + hi)
        if stribeck_g(v) * math.tanh(v / 1e-3) < TAN:
            lo = v
        else:
            hi = v
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("method,kw,tol", [("rk4", {"h": 1e-4}, 1e-6), ("dopri5", {}, 1e-5)])
def test_stribeck_creeps_at_the_predicted_speed(method, kw, tol):
    # tol: RK4's error at h = 1e-4 s is far below 1e-6; DOPRI5's is a few atol = 1e-9 m/s
    v_star = stribeck_creep_speed()
    assert 5.5e-4 < v_star < 5.6e-4
    r = ss.simulate("slope", "stribeck", method=method, t_end=20.0, n_out=201, **kw)
    np.testing.assert_allclose(r.v[100:], v_star, rtol=tol)
    # after a transient of a few ms the box creeps at v*
    np.testing.assert_allclose(r.x[-1] - r.x[100], 10.0 * v_star, rtol=tol)


# ---------------------------------------------------------------------------------------------
# Belt
# ---------------------------------------------------------------------------------------------
def test_coulomb_cycle_numbers():
    x_max, x_min, period, t_break = coulomb_cycle()
    assert (round(x_max, 6), round(x_min, 6), round(period, 6), round(t_break, 4)) == \
        (0.372449, -0.176249, 1.147173, 0.0763)


@pytest.mark.parametrize("dv,method,kw", [(1e-3, "dopri5", {"rtol": 1e-10, "atol": 1e-12}),
                                          (1e-4, "dopri5", {"rtol": 1e-10, "atol": 1e-12}),
                                          (1e-6, "dopri5", {"rtol": 1e-10, "atol": 1e-12}),
                                          (1e-3, "rk4", {"h": 1e-4})])
def test_karnopp_reproduces_the_coulomb_cycle(dv, method, kw):
    """Starting stuck (x0 = 0, v0 = v_b). Derived error of the band: at break-away the friction
    stays mu_s until v_rel = v_b (1 - cos w tau) reaches dv, so the spring over-stretches by at
    most v_b tau = sqrt(2 v_b dv)/w, which moves the extremes by (x_s - x_k)/A times that; the
    slip starts up to dv slower, which moves them by at most (v_b/w)(dv/w)/A < dv/w. The period
    moves by at most tau + 2 (x_s - x_k) dv / v_b^2 plus the slip-time change."""
    x_max, x_min, period, t_break = coulomb_cycle()
    r = ss.simulate("belt", "karnopp", method=method, t_end=6.0, n_out=60001, v0=V_B, dv=dv, **kw)
    # stick at exactly the belt speed until the spring holds mu_s m g
    before = r.t < t_break - 1e-3
    np.testing.assert_allclose(r.v[before], V_B, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r.x[before], V_B * r.t[before], rtol=0, atol=1e-12)
    amp = x_max - X_K
    tau = math.sqrt(2 * dv / V_B) / OMEGA                 # v_b (1 - cos w tau) = dv
    bound = (X_S - X_K) / amp * V_B * tau + dv / OMEGA + 1e-6   # 2.0e-5 m at dv = 1e-6 m/s
    tm, xm = maxima(r.t, r.x)
    tn, xn = maxima(r.t, -r.x)
    assert len(tm) >= 5
    assert np.max(np.abs(xm - x_max)) < bound and np.max(np.abs(-xn - x_min)) < bound
    t_bound = tau + 2 * (X_S - X_K) * dv / V_B**2 + 2 * bound / (amp * OMEGA) + 1e-5
    assert np.max(np.abs(np.diff(tm) - period)) < t_bound


@pytest.mark.parametrize("law", ["karnopp", "stribeck"])
def test_constant_kinetic_from_rest_is_harmonic(law):
    """From rest the relative velocity stays in [v_b - x_k w, v_b + x_k w] = [0.96, 2.04] m/s,
    where both laws give exactly mu_k: x = x_k (1 - cos w t), never reaching belt speed."""
    r = ss.simulate("belt", law, method="dopri5", t_end=10.0, n_out=1001, rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(r.x, X_K * (1 - np.cos(OMEGA * r.t)), rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.v, X_K * OMEGA * np.sin(OMEGA * r.t), rtol=0, atol=1e-9)
    assert X_K * OMEGA < V_B                               # 0.537 < 1.5 m/s


@pytest.mark.parametrize("law", ["proposed", "lugre", "elastoplastic", "stribeck"])
def test_growth_from_rest_follows_the_slope_at_belt_speed(law):
    """m x'' + m g mu'(v_b) x' + k x = ... near steady sliding: the oscillation from rest grows
    (mu' < 0: the proposed law) or decays (mu' > 0: LuGre's sigma2) at the rate -g mu'(v_b)/2."""
    eps = 1e-6
    slope = float((mu(law, V_B + eps) - mu(law, V_B - eps)) / (2 * eps))
    rate = -G * slope / 2
    r = ss.simulate("belt", law, method="dopri5", t_end=12.0, n_out=24001, rtol=1e-9, atol=1e-12)
    tm, xm = maxima(r.t, r.x)
    tn, xn = maxima(r.t, -r.x)
    n = min(len(tm), len(tn), 9)
    amp = (xm[:n] + xn[:n]) / 2
    measured = math.log(amp[n - 1] / amp[1]) / (tm[n - 1] - tm[1])
    assert measured == pytest.approx(rate, abs=0.02 * abs(rate) + 1e-6)
    assert np.max(r.v) < V_B                               # none sticks within 12 s


def test_lugre_rk4_stability_limit_on_the_belt():
    """Sliding at v_rel the bristle relaxes at the rate sigma0 v_rel / mu_k (g = mu_k there);
    from rest v_rel reaches v_b + x_k w = 2.04 m/s, so RK4 (real stability interval 2.785)
    needs h < 2.785 mu_k / (sigma0 2.04) = 4.0e-5 s. An unstable RK4 need not overflow here
    (the relaxation term saturates): it breaks the exact solution's invariant
    |z| <= mu_s/sigma0 instead."""
    h_max = 2.785 * MU_K / (SIGMA0 * (V_B + X_K * OMEGA))
    assert 3.9e-5 < h_max < 4.1e-5
    z_lim = MU_S / SIGMA0
    ok = ss.simulate("belt", "lugre", method="rk4", h=0.9 * h_max, t_end=4.0, n_out=4001)
    assert np.max(np.abs(ok.z)) <= z_lim
    bad = ss.simulate("belt", "lugre", method="rk4", h=1.25 * h_max, t_end=4.0, n_out=4001)
    assert np.max(np.abs(bad.z)) > 2 * z_lim
    with pytest.raises(ss.NonFiniteSolution):           # the paper's steps overflow
        ss.simulate("belt", "lugre", method="rk4", h=1e-4, t_end=1.0)


# ---------------------------------------------------------------------------------------------
# The study driver (reduced to three laws, no step search)
# ---------------------------------------------------------------------------------------------
def test_laws_compare_driver(tmp_path):
    files = lc.run(tmp_path, quick=True, quiet=True, laws=("karnopp", "stribeck", "lugre"))
    names = {f.name for f in files}
    assert {"laws_compare_slope.csv", "laws_compare_belt.png", "laws_compare.md"} <= names
    assert all(f.stat().st_size > 0 for f in files)
    slope = _common.read_csv(tmp_path / "laws_compare_slope.csv")
    assert all("[" in h for h in slope)
    rows = list(zip(*slope.values()))
    assert {r[1] for r in rows} == set(ss.METHODS)
    assert all(r[3] == "0" for r in rows if r[1] in ("rk4", "dopri5"))
    for r in (r for r in rows if r[3] == "0"):     # a failed run (status < 0) has no state
        if r[0] == "karnopp":
            assert float(r[4]) == 0.0 and float(r[5]) == 0.0          # truth: no creep
        if r[0] == "stribeck" and ss.REGISTRY["method"][r[1]]["laws"] is None:
            assert float(r[5]) == pytest.approx(stribeck_creep_speed(), rel=1e-5)
        elif r[0] == "stribeck":         # moreau, event_driven: set-valued, held exactly
            assert float(r[4]) == 0.0 and float(r[5]) == 0.0
    belt = _common.read_csv(tmp_path / "laws_compare_belt.csv")
    x_max = coulomb_cycle()[0]
    brows = {(r[0], r[1], r[2]): r for r in zip(*belt.values())}
    k = brows[("karnopp", "dopri5", "")]
    # dv = 1e-3 m/s: the derived bound of test_karnopp_reproduces_the_coulomb_cycle, 7.6e-4 m
    assert abs(float(k[4]) - x_max) < 7.6e-4 and abs(float(k[7])) < 7.6e-4
    # RK4 at the paper's step leaves the belt's energy bound: DIVERGED, not a row of numbers
    assert int(brows[("lugre", "rk4", "0.001")][3]) == ss.REGISTRY["status"]["DIVERGED"]
    assert abs(float(brows[("lugre sigma2=0", "dopri5", "")][7])) < 1e-4
    rest = {r[0]: r for r in zip(*_common.read_csv(tmp_path / "laws_compare_rest.csv").values())}
    assert float(rest["lugre"][4]) == pytest.approx(-G * SIGMA2 / 2, rel=1e-3)
    pre = _common.read_numeric_csv(tmp_path / "laws_compare_presliding.csv")
    assert list(pre) == ["t [s]", "x lugre [m]", "z lugre [m]"]          # named from state_labels
    assert pre["z lugre [m]"][-1] == pytest.approx(TAN / SIGMA0, rel=2e-3)   # settling after 50 ms
    again = lc.plot(tmp_path / "laws_compare_rest.csv", tmp_path / "again")
    assert again.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
