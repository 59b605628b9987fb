"""Prescribed motion (stickslip.prescribed_motion) and the presliding-hysteresis laws (Dahl, the
generalized Maxwell-slip model), against independent references: the static laws' curves
(friction_coefficient, exactly), scipy's solve_ivp (Radau or LSODA, rtol 1e-10) on the same state
equations written here in numpy along the same motion (scipy's cubic Hermite interpolant),
Dahl's closed forms under monotone motion, a single elasto-slip element derived by hand, a play
operator written here, and the scenes run with the new laws."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicHermiteSpline
from scipy.optimize import brentq

import stickslip as ss

MU_S, MU_K, V_S = 0.35, 0.30, 0.01
STATIC = [law for law in ss.LAWS if ss.law_n_states(law) == 0]


def sine(n=4001, amp=1e-3, freq=1.0, periods=2.0):
    t = np.linspace(0.0, periods / freq, n)
    w = 2 * math.pi * freq
    return t, amp * np.sin(w * t), amp * w * np.cos(w * t)


def stribeck(v, mu_s=MU_S, mu_k=MU_K, v_s=V_S):
    return mu_k + (mu_s - mu_k) * np.exp(-(np.asarray(v) / v_s) ** 2)


# ---------------------------------------------------------------------------------------------
# The state equations, written again in numpy: rates dz(v, z) and the coefficient mu(v, z, dz)
# ---------------------------------------------------------------------------------------------
def lugre_rhs(p, alpha=None):
    s0, s1, s2 = p["sigma0"], p["sigma1"], p["sigma2"]

    def rates(v, z):
        g = stribeck(v, p["mu_s"], p["mu_k"], p["v_s"])
        a = 1.0 if alpha is None else alpha(z[0], v, g)
        return np.array([v - a * s0 * abs(v) * z[0] / g])

    def mu(v, z, dz):
        return s0 * z[0] + s1 * dz[0] + s2 * v
    return rates, mu


def dupont_alpha(p):
    z_ba = p["z_ba_ratio"] * p["mu_k"] / p["sigma0"]

    def alpha(z, v, g):
        z_ss = g / p["sigma0"]
        if not z * v > 0 or abs(z) <= z_ba:
            return 0.0
        if abs(z) >= z_ss:
            return 1.0
        return 0.5 * (1 + math.sin(math.pi * (abs(z) - 0.5 * (z_ss + z_ba)) / (z_ss - z_ba)))
    return alpha


def dahl_rhs(p):
    def rates(v, z):
        r = 1.0 - math.copysign(1.0, v) * p["sigma0"] * z[0] / p["mu_k"]
        return np.array([v * math.copysign(abs(r) ** p["dahl_alpha"], r)])

    def mu(v, z, dz):
        return p["sigma0"] * z[0]
    return rates, mu


def gms_fractions(n, m):
    u = (np.arange(1, n + 1) - 0.5) / n
    q = 1.0 - (1.0 - u) ** (1.0 / m)
    return q / q.sum()


def gms_rhs(p):
    n = int(p["n_elements"])
    k = p["sigma0"] / n
    frac = gms_fractions(n, p["gms_shape"])

    def rates(v, z):
        s = stribeck(v, p["mu_s"], p["mu_k"], p["v_s"])
        sg = math.copysign(1.0, v)
        level = frac * s
        slip = (v != 0.0) & (k * z * sg >= level)
        return np.where(slip, p["gms_c"] / k * (sg - k * z / level), v)

    def mu(v, z, dz):
        return k * z.sum() + p["sigma1"] / n * dz.sum() + p["sigma2"] * v
    return rates, mu


def reference(rhs, t, x, v, nz, method="Radau", **kw):
    """mu along the Hermite motion of (t, x, v), the states integrated by solve_ivp."""
    rates, mu = rhs
    dx = CubicHermiteSpline(t, x, v).derivative()
    sol = solve_ivp(lambda tt, z: rates(float(dx(tt)), z), (t[0], t[-1]), np.zeros(nz), method=method,
                    t_eval=t, rtol=1e-10, atol=1e-15, **kw)
    assert sol.success, sol.message
    return np.array([mu(vi, zi, rates(vi, zi)) for vi, zi in zip(v, sol.y.T)]), sol.y


# ---------------------------------------------------------------------------------------------
# Static laws: exactly their curves
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("law", STATIC)
def test_static_laws_are_their_curves(law):
    t, x, v = sine(n=1001, amp=0.05)
    r = ss.prescribed_motion(law, t, x, v, normal_force=250.0)
    np.testing.assert_array_equal(r.mu, ss.friction_coefficient(law, v))
    np.testing.assert_array_equal(r.force, 250.0 * ss.friction_coefficient(law, v))
    np.testing.assert_array_equal(r.v_contact, v)
    np.testing.assert_array_equal(r.x_contact, x)
    assert r.z.shape == (0, t.size) and r.stats["n_advance"] == 0


def test_normal_force_per_sample_and_asymmetry():
    t, x, v = sine(n=501, amp=0.05)
    nf = np.linspace(10.0, 20.0, t.size)
    r = ss.prescribed_motion("stribeck", t, x, v, normal_force=nf, asymmetry=1.25, delta=1.0)
    mu = ss.friction_coefficient("stribeck", v, delta=1.0)
    expect = np.where(mu < 0, 1.25 * mu, mu)
    np.testing.assert_array_equal(r.mu, expect)
    np.testing.assert_array_equal(r.force, expect * nf)


# ---------------------------------------------------------------------------------------------
# Laws with states against scipy
# ---------------------------------------------------------------------------------------------
LUGRE = dict(mu_s=MU_S, mu_k=MU_K, v_s=V_S, sigma0=1e5, sigma1=300.0, sigma2=0.05)
CASES = [
    ("lugre", LUGRE, lambda p: lugre_rhs(p), "Radau"),
    ("lugre", dict(LUGRE, sigma1=0.0, v_s=1e-3), lambda p: lugre_rhs(p), "Radau"),
    ("elastoplastic", dict(LUGRE, sigma0=2e4, z_ba_ratio=0.7), lambda p: lugre_rhs(p, dupont_alpha(p)), "Radau"),
    ("dahl", dict(mu_k=0.3, sigma0=2e3, dahl_alpha=1.0), dahl_rhs, "Radau"),
    ("dahl", dict(mu_k=0.3, sigma0=2e3, dahl_alpha=2.5), dahl_rhs, "Radau"),
    # alpha < 1: the rate is not Lipschitz at the bound, LSODA's reference takes minutes
    pytest.param("dahl", dict(mu_k=0.3, sigma0=2e3, dahl_alpha=0.6), dahl_rhs, "LSODA",
                 marks=pytest.mark.slow),
]


@pytest.mark.parametrize("law,p,rhs,method", CASES,
                         ids=[f"{(c.values if hasattr(c, 'values') else c)[0]}-{i}" for i, c in enumerate(CASES)])
def test_states_against_scipy(law, p, rhs, method):
    t, x, v = sine(n=2001, amp=1e-3, freq=1.0)
    r = ss.prescribed_motion(law, t, x, v, rtol=1e-10, **p)
    full = dict(ss.DEFAULTS, **p)
    mu, z = reference(rhs(full), t, x, v, 1, method=method)
    scale = np.abs(mu).max()
    assert r.stats["n_unconverged"] == 0
    np.testing.assert_allclose(r.mu, mu, rtol=0, atol=2e-7 * scale)
    np.testing.assert_allclose(r.z, z, rtol=0, atol=2e-7 * np.abs(z).max())


@pytest.mark.parametrize("n,shape", [(1, 1.0), (4, 1.0), (6, 3.0)])
def test_gms_against_scipy(n, shape):
    # Without a Stribeck drop (mu_s = mu_k) the levels are constant: the elements switch from
    # stick to slip once per stroke and then sit on their levels, a right-hand side an explicit
    # adaptive method follows through the switches (the Stribeck dynamics and C are checked by
    # the single-element test below)
    t, x, v = sine(n=401, amp=2e-3, freq=0.5)
    p = dict(mu_s=MU_K, mu_k=MU_K, v_s=V_S, sigma0=3e3, sigma1=0.0, sigma2=0.02, n_elements=n,
             gms_shape=shape, gms_c=100.0)
    r = ss.prescribed_motion("gms", t, x, v, rtol=1e-10, **p)
    mu, z = reference(gms_rhs(p), t, x, v, n, method="RK45", max_step=1e-3)
    assert r.z.shape == (n, t.size)
    np.testing.assert_allclose(r.mu, mu, rtol=0, atol=1e-7 * np.abs(mu).max())


# ---------------------------------------------------------------------------------------------
# Closed forms and hand derivations
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("alpha", [1.0, 2.0])
def test_dahl_virgin_curve_closed_form(alpha):
    # monotone motion from mu = 0: alpha = 1 gives mu_k (1 - exp(-sigma0 x/mu_k)),
    # alpha = 2 gives mu_k sigma0 x/(mu_k + sigma0 x) (integrate dmu/dx = sigma0 (1 - mu/mu_k)^2)
    t = np.linspace(0.0, 1.0, 201)
    x = 0.01 * t + 0.02 * t**2          # accelerating: the law is rate-independent
    v = 0.01 + 0.04 * t
    mu_k, s0 = 0.4, 300.0
    r = ss.prescribed_motion("dahl", t, x, v, mu_k=mu_k, sigma0=s0, dahl_alpha=alpha, normal_force=2.0)
    exact = mu_k * (1 - np.exp(-s0 * x / mu_k)) if alpha == 1.0 else mu_k * s0 * x / (mu_k + s0 * x)
    np.testing.assert_allclose(r.mu, exact, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(r.force, 2.0 * exact, rtol=1e-12, atol=1e-15)
    # and back: after a reversal the law retraces with the same shape from the turning point
    t2 = np.linspace(0.0, 2.0, 401)
    x2 = np.where(t2 <= 1.0, 0.01 * t2, 0.02 - 0.01 * t2)
    v2 = np.where(t2 <= 1.0, 0.01, -0.01)
    v2[200] = 0.0                         # the turning point
    r2 = ss.prescribed_motion("dahl", t2, x2, v2, mu_k=mu_k, sigma0=s0, dahl_alpha=1.0)
    m_top = mu_k * (1 - math.exp(-s0 * 0.01 / mu_k))
    back = 0.01 - x2[200:]                # travel since the reversal
    # d(mu)/dx' = sigma0 (1 + mu/mu_k) going back: mu = -mu_k + (mu_k + m_top) exp(-sigma0 x'/mu_k)
    np.testing.assert_allclose(r2.mu[200:], -mu_k + (mu_k + m_top) * np.exp(-s0 * back / mu_k),
                               rtol=0, atol=1e-12)


def test_gms_single_element_by_hand():
    # One elasto-slip element (N = 1: alpha_1 = 1, k = sigma0), no damping, along x = a t^2/2.
    # Stick: mu = k x until it reaches s(v) at t_b; then it slips: mu' = C (1 - mu/s(a t)), a
    # linear equation integrated here from t_b (hand-derived phases, the switch found by brentq).
    a, k, c = 0.02, 40.0, 5.0
    p = dict(mu_s=0.35, mu_k=0.25, v_s=0.01, sigma0=k, sigma1=0.0, sigma2=0.0, n_elements=1, gms_c=c)
    t = np.linspace(0.0, 2.0, 801)
    x, v = 0.5 * a * t**2, a * t
    r = ss.prescribed_motion("gms", t, x, v, rtol=1e-11, **p)
    s = lambda tt: stribeck(a * tt, 0.35, 0.25, 0.01)
    t_b = brentq(lambda tt: k * 0.5 * a * tt**2 - s(tt), 1e-9, 2.0)
    stick = t <= t_b
    np.testing.assert_allclose(r.mu[stick], k * x[stick], rtol=1e-12)
    sol = solve_ivp(lambda tt, m: c * (1 - m / s(tt)), (t_b, 2.0), [s(t_b)], t_eval=t[~stick],
                    rtol=1e-12, atol=1e-15)
    # (the substep where the element reaches its level caps it at the end level, an O(h) lag
    # error that step doubling bounds: a few 1e-7 next to the switch, decaying after it)
    np.testing.assert_allclose(r.mu[~stick], sol.y[0], rtol=0, atol=5e-7)
    # it lags behind the falling Stribeck level
    assert np.all(r.mu[~stick][5:] > s(t[~stick][5:]))


def test_gms_virgin_curve_at_constant_speed():
    # far above v_s the level is mu_k: mu(x) = sum_i min(k x, alpha_i mu_k) while loading
    n, m, s0 = 5, 2.0, 1e3
    t = np.linspace(0.0, 1.0, 501)
    vel = 1e-3
    p = dict(mu_s=0.3, mu_k=0.3, sigma0=s0, sigma1=0.0, sigma2=0.0, n_elements=n, gms_shape=m)
    r = ss.prescribed_motion("gms", t, vel * t, np.full(t.size, vel), **p)
    frac = gms_fractions(n, m)
    exact = np.minimum.outer(s0 / n * vel * t, frac * 0.3).sum(axis=1)
    np.testing.assert_allclose(r.mu, exact, rtol=1e-12, atol=1e-15)


def test_lugre_constant_speed_closed_form():
    # z' = v - sigma0 |v| z/g: z = z_ss (1 - exp(-sigma0 x/g)) at constant v
    t = np.linspace(0.0, 0.01, 101)
    vel = 0.05
    r = ss.prescribed_motion("lugre", t, vel * t, np.full(t.size, vel), **LUGRE)
    g = stribeck(vel)
    z = g / 1e5 * (1 - np.exp(-1e5 * vel * t / g))
    np.testing.assert_allclose(r.z[0], z, rtol=1e-12, atol=1e-20)


# ---------------------------------------------------------------------------------------------
# Backlash
# ---------------------------------------------------------------------------------------------
def play(x, b):
    out = np.empty_like(x)
    c = x[0]
    for i, xi in enumerate(x):
        c = min(max(c, xi - b / 2), xi + b / 2)
        out[i] = c
    return out


def test_backlash_is_a_play_operator():
    # samples at the extremes of the sine: x is monotone between samples
    t, x, v = sine(n=801, amp=1e-2, freq=1.0)
    b = 4e-3
    r = ss.prescribed_motion("coulomb", t, x, v, backlash=b, mu_k=0.3, mu_s=0.3)
    np.testing.assert_allclose(r.x_contact, play(x, b), rtol=0, atol=1e-15)
    engaged = np.abs(x - r.x_contact) >= b / 2 * (1 - 1e-12)
    moving_out = v * (x - r.x_contact) > 0
    np.testing.assert_array_equal(r.v_contact, np.where(engaged & moving_out, v, 0.0))
    # inside the band the Coulomb force is 0; outside it is +-mu_k
    assert np.all(r.mu[r.v_contact == 0.0] == 0.0)
    np.testing.assert_array_equal(np.abs(r.mu[r.v_contact != 0.0]), 0.3)
    # a dead band of travel b after each reversal: the reversal at t = 0.25 s
    i_rev = 100
    dead = (t > t[i_rev]) & (t < 0.75) & (x > x[i_rev] - b)
    assert np.all(r.v_contact[dead] == 0.0) and np.any(dead)


def test_backlash_with_states_matches_scipy():
    # LuGre behind a play: the contact rests inside the band, then follows x
    t, x, v = sine(n=2001, amp=2e-3, freq=1.0)
    b = 1e-3
    p = dict(LUGRE, sigma1=0.0)
    r = ss.prescribed_motion("lugre", t, x, v, backlash=b, rtol=1e-10, **p)
    H = CubicHermiteSpline(t, x, v)
    dH = H.derivative()
    rates, mu = lugre_rhs(dict(ss.DEFAULTS, **p))
    # the contact velocity along the dense motion: the play applied on a fine grid
    tf = np.linspace(t[0], t[-1], 400001)
    xc = play(H(tf), b)
    vcf = np.gradient(xc, tf)
    vcf[np.abs(np.diff(np.concatenate([[0.0], xc]))) == 0.0] = 0.0
    vc = lambda tt: float(np.interp(tt, tf, vcf))
    sol = solve_ivp(lambda tt, z: rates(vc(tt), z), (t[0], t[-1]), [0.0], t_eval=t, method="LSODA",
                    rtol=1e-10, atol=1e-15, max_step=1e-4)
    np.testing.assert_allclose(r.x_contact, play(x, b), rtol=0, atol=1e-15)
    # the first engaged sample after each reversal: the reference smears the engagement over a
    # grid step of its finite-difference contact velocity (1 % there); 1e-3 elsewhere
    first = np.flatnonzero((r.v_contact[1:] != 0.0) & (r.v_contact[:-1] == 0.0)) + 1
    rest = np.setdiff1d(np.arange(t.size), first)
    zmax = np.abs(sol.y[0]).max()
    np.testing.assert_allclose(r.z[0, rest], sol.y[0, rest], rtol=0, atol=1e-3 * zmax)
    np.testing.assert_allclose(r.z[0, first], sol.y[0, first], rtol=0, atol=2e-2 * zmax)


# ---------------------------------------------------------------------------------------------
# Velocity derived from x, states from z0
# ---------------------------------------------------------------------------------------------
def test_velocity_derived_from_x():
    t, x, v = sine(n=2001)
    r = ss.prescribed_motion("stribeck", t, x)
    np.testing.assert_array_equal(r.v_contact, np.gradient(x, t, edge_order=2))
    r1 = ss.prescribed_motion("lugre", t, x, **LUGRE)
    r2 = ss.prescribed_motion("lugre", t, x, np.gradient(x, t, edge_order=2), **LUGRE)
    np.testing.assert_array_equal(r1.mu, r2.mu)


def test_initial_states():
    t, x, v = sine(n=11)
    r = ss.prescribed_motion("gms", t, x, v, n_elements=3, z0=[1e-6, 2e-6, 3e-6])
    np.testing.assert_array_equal(r.z[:, 0], [1e-6, 2e-6, 3e-6])
    with pytest.raises(ValueError, match="z0"):
        ss.prescribed_motion("gms", t, x, v, n_elements=3, z0=[0.0, 0.0])


# ---------------------------------------------------------------------------------------------
# law_n_states, registry, bad input
# ---------------------------------------------------------------------------------------------
def test_law_n_states():
    assert ss.law_n_states("coulomb") == 0
    assert ss.law_n_states("lugre") == 1 and ss.law_n_states("dahl") == 1
    assert ss.law_n_states("gms") == int(ss.DEFAULTS["n_elements"])
    assert ss.law_n_states("gms", n_elements=7) == 7
    assert ss.law_state_labels("gms", n_elements=2) == ("z1 [m]", "z2 [m]")
    for bad in (0, 2.5, 65, math.nan):
        with pytest.raises(ValueError, match=r"^n_elements\b"):
            ss.law_n_states("gms", n_elements=bad)
    with pytest.raises(ValueError, match="sigma0"):
        ss.law_n_states("dahl", sigma0=-1.0)


@pytest.mark.parametrize("name,value", [("dahl_alpha", 0.0), ("dahl_alpha", -1.0), ("gms_shape", 0.0),
                                        ("gms_c", 0.0), ("gms_c", math.inf)])
def test_bad_law_parameter_named(name, value):
    law = "dahl" if name.startswith("dahl") else "gms"
    t, x, v = sine(n=11)
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        ss.prescribed_motion(law, t, x, v, **{name: value})
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        ss.simulate("slope", law, method="rk4", h=1e-3, t_end=0.01, **{name: value})


def test_bad_input_named():
    t, x, v = sine(n=11)
    cases = [
        (dict(law="nolaw"), "law"),
        (dict(sigma9=1.0), "sigma9"),
        (dict(dahl_alpha=1.0), "dahl_alpha"),           # not a parameter of lugre
        (dict(x=np.where(np.arange(11) == 3, np.nan, x)), "x"),
        (dict(v=v[:-1]), "v"),
        (dict(x=x[:-2]), "x"),
        (dict(t=t[::-1]), "t"),
        (dict(t=np.where(np.arange(11) == 4, t[3], t)), "t"),
        (dict(t=np.where(np.arange(11) == 4, np.inf, t)), "t"),
        (dict(backlash=-1e-3), "backlash"),
        (dict(backlash=math.nan), "backlash"),
        (dict(asymmetry=0.0), "asymmetry"),
        (dict(asymmetry=-2.0), "asymmetry"),
        (dict(normal_force=-1.0), "normal_force"),
        (dict(normal_force=np.ones(5)), "normal_force"),
        (dict(z0=[0.0, 0.0]), "z0"),
        (dict(sigma0=0.0), "sigma0"),
        (dict(rtol=2.0), "rtol"),
    ]
    for kw, name in cases:
        args = dict(law="lugre", t=t, x=x, v=v)
        args.update(kw)
        law = args.pop("law")
        with pytest.raises(ValueError, match=rf"(^|unknown parameter\(s\) ){name}\b") as err:
            ss.prescribed_motion(law, args.pop("t"), args.pop("x"), args.pop("v"), **args)
        assert "must" in str(err.value) or "accepted" in str(err.value), str(err.value)


def test_fortran_status_messages():
    # the library's own checks (for Fortran and C callers) name the input too
    for code, name in [(-175, "t"), (-176, "x, v"), (-177, "backlash"), (-178, "asymmetry"),
                       (-179, "normal_force"), (-171, "dahl_alpha"), (-172, "n_elements")]:
        assert ss.status_message(code).startswith(name + ":"), ss.status_message(code)


# ---------------------------------------------------------------------------------------------
# The new laws in the scenes
# ---------------------------------------------------------------------------------------------
def test_dahl_in_a_scene_is_lugre_without_stribeck_and_damping():
    # Dahl with alpha = 1 is LuGre with g = mu_k (mu_s = mu_k) and sigma1 = sigma2 = 0
    kw = dict(method="dopri5", t_end=0.5, n_out=501, rtol=1e-10, atol=1e-14)
    for scene, extra in [("slope", dict(theta_deg=20.0)), ("belt", {})]:
        d = ss.simulate(scene, "dahl", mu_k=0.3, sigma0=2e3, **extra, **kw)
        lg = ss.simulate(scene, "lugre", mu_s=0.3, mu_k=0.3, sigma0=2e3, sigma1=0.0, sigma2=0.0, **extra, **kw)
        assert d.state_labels == ("z [m]",) and d.z.shape == (501,)   # one state: the shape of x
        np.testing.assert_allclose(d.x, lg.x, rtol=0, atol=1e-8 * np.abs(lg.x).max())
        np.testing.assert_allclose(d.z, lg.z, rtol=0, atol=1e-8 * np.abs(lg.z).max())


@pytest.mark.parametrize("method,kw", [("rk4", dict(h=2e-5)), ("dopri5", dict(rtol=1e-8, atol=1e-12))])
def test_gms_on_the_slope_comes_to_rest_in_balance(method, kw):
    # 10 degrees, tan = 0.176 < mu_k: presliding only; at rest the elements hold the box,
    # sum k z_i = tan(theta) (the damping sigma1 brings it to rest)
    r = ss.simulate("slope", "gms", method=method, t_end=1.0, n_out=11, n_elements=6, **kw)
    assert r.z.shape == (6, 11) and r.state_labels == tuple(f"z{i} [m]" for i in range(1, 7))
    k = ss.DEFAULTS["sigma0"] / 6
    assert abs(r.v[-1]) < 1e-9
    np.testing.assert_allclose(k * r.z[:, -1].sum(), math.tan(math.radians(10.0)), rtol=1e-6)
    assert 0 < r.x[-1] < 3 * MU_S / ss.DEFAULTS["sigma0"]


def test_gms_batch_sizes_its_state():
    out = ss.simulate_batch("slope", "gms", method="rk4", h=2e-5, t_end=0.05, n_elements=[2.0, 5.0])
    assert out.status.tolist() == [0, 0]
    one = ss.simulate("slope", "gms", method="rk4", h=2e-5, t_end=0.05, n_elements=5)
    np.testing.assert_allclose(out.x_end[1], one.x[-1], rtol=1e-12)


# ---------------------------------------------------------------------------------------------
# GMS on measured motions: every element classified as the law defines it, at every tolerance
# ---------------------------------------------------------------------------------------------
GMS_DAMPER = dict(mu_s=13030.5, mu_k=11097.6, v_s=0.1726, sigma0=4.519e6, sigma1=22368.0, sigma2=534.5,
                  gms_shape=24.93, gms_c=1e6)     # force levels near a fit of the 36 lb records


def gms_rates_by_definition(p, t, x, v, z):
    """Each element's rate at each sample from the law's definition (numpy): below its level it
    sticks (z' = v); on it (within 1e-9, relative) while the level rises at L' it stays on it,
    z' = min(|v|, L'/k) sgn(v); above it, or on a falling level, the slip law. L' = alpha s'(v) a
    with a the acceleration of the Hermite cubic ending at the sample."""
    n = int(p.get("n_elements", 4))
    k = p["sigma0"] / n
    frac = gms_fractions(n, p["gms_shape"])[:, None]
    h = np.diff(t)
    c3 = 3 * np.diff(x) - h * (2 * v[:-1] + v[1:])
    c4 = -2 * np.diff(x) + h * (v[:-1] + v[1:])
    a = np.concatenate([[2 * c3[0] / h[0] ** 2], (2 * c3 + 6 * c4) / h**2])
    s = stribeck(v, p["mu_s"], p["mu_k"], p["v_s"])
    sdot = -(p["mu_s"] - p["mu_k"]) * 2 * v / p["v_s"] ** 2 * np.exp(-(v / p["v_s"]) ** 2) * a
    sg = np.sign(v)
    level = frac * s
    f = k * z * sg
    slip = p["gms_c"] / k * (sg - k * z / np.where(level > 0, level, 1.0))
    on_rising = (np.abs(f / level - 1) <= 1e-9) & (sdot > 0)
    rising = sg * np.minimum(np.abs(v), frac * np.where(sdot > 0, sdot, 0.0) / k)
    dz = np.where(f < level * (1 - 1e-9), v, np.where(on_rising, rising, slip))
    return np.where(v == 0, 0.0, dz)


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_gms_elements_classified_by_the_law_on_measured_motion(rtol):
    # The damper's measured motions (noisy velocity: the slip levels wander up and down from
    # sample to sample) with force levels near a fit: the force at every sample is the law's,
    # sum k z_i + sigma1/N sum z_i' + sigma2 v, with each element's rate from its definition
    # (an element on a rising level is on it, not stuck: it was classed stuck for one sample
    # when its level, recomputed at the sample's velocity, came out a few ulps above it,
    # giving one-sample spikes of sigma1 v/N)
    p = dict(GMS_DAMPER)
    n_on_rising = 0
    for f in ss.damper_files()[::4]:
        rec = ss.load_damper_record(f)
        v = np.gradient(rec.x, rec.t, edge_order=2)
        r = ss.prescribed_motion("gms", rec.t, rec.x, v, rtol=rtol, **p)
        dz = gms_rates_by_definition(p, rec.t, rec.x, v, r.z)
        expect = p["sigma0"] / 4 * r.z.sum(0) + p["sigma1"] / 4 * dz.sum(0) + p["sigma2"] * v
        np.testing.assert_allclose(r.force, expect, rtol=0, atol=1e-6 * np.ptp(expect))
        k = p["sigma0"] / 4
        level = gms_fractions(4, p["gms_shape"])[:, None] * stribeck(v, p["mu_s"], p["mu_k"], p["v_s"])
        n_on_rising += int((np.abs(k * r.z * np.sign(v) / level - 1) <= 1e-9).sum())
    assert n_on_rising > 100       # the case is exercised


def test_gms_force_continuous_in_its_parameters_on_measured_motion():
    # A relative change of 1e-7 in mu_s moves the force by about that much of its level (no
    # element toggles between stick and slip at any sample)
    p = dict(GMS_DAMPER)
    for f in ss.damper_files()[1::5]:
        rec = ss.load_damper_record(f)
        f0 = ss.prescribed_motion("gms", rec.t, rec.x, rtol=1e-6, **p).force
        f1 = ss.prescribed_motion("gms", rec.t, rec.x, rtol=1e-6, **dict(p, mu_s=p["mu_s"] * (1 + 1e-7))).force
        assert np.abs(f1 - f0).max() < 1e-4 * np.ptp(f0)


def test_elastoplastic_transition_step_is_fourth_order_at_constant_velocity():
    """At a constant velocity the steady deflection is constant over every substep, so the only
    error of the elasto-plastic flow is its step through the attachment's transition (z_ba <
    |z| < z_ss): on frozen substeps m = 1, 2, 4, 8 per sample interval (one Taylor step each) the
    deflection's error against scipy's Radau (rtol 1e-12) on the same equation falls by about
    2^4 per halving (measured 4.04-4.13). Parameters with z_ss = 1.06e-3 m, z_ba = 0.5e-3 m,
    0.1 mm of travel a sample."""
    from stickslip.prescribed import _run
    p = dict(mu_s=MU_S, mu_k=MU_K, v_s=V_S, sigma0=300.0, sigma1=0.0, sigma2=0.0, z_ba_ratio=0.5)
    vel = 0.01
    t = np.linspace(0.0, 0.3, 31)          # 3 mm of travel from rest: through the transition
    x = vel * t
    v = np.full_like(t, vel)
    rates, _ = lugre_rhs(p, dupont_alpha(p))
    ref = solve_ivp(lambda _, z: rates(vel, z), (0.0, t[-1]), [0.0], method="Radau", t_eval=t,
                    rtol=1e-12, atol=1e-16).y[0]
    code = ss.REGISTRY["law"]["elastoplastic"]["code"]
    errors = []
    for m in (1, 2, 4, 8):
        z = _run(code, tuple(p.items()), t, x, v, np.ones(1), np.zeros(1), 0.0, 1.0, 1e-8,
                 np.full(t.size - 1, m, dtype=np.int32))[2]
        errors.append(float(np.abs(np.asarray(z).ravel() - ref).max()))
    z_ss = float(stribeck(vel)) / p["sigma0"]
    assert ref[-1] > 0.9 * z_ss                     # the record crosses the transition
    assert errors[-1] < 5e-8 * z_ss                  # measured: 1.8e-8 z_ss at m = 8
    orders = [math.log2(a / b) for a, b in zip(errors, errors[1:])]
    assert all(3.5 < q < 4.5 for q in orders), (errors, orders)
