"""Periodic orbits, continuation and response curves (stickslip.steady) against closed forms,
scipy's variational equations and independent event-driven transients."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import stickslip as ss
from benchmarks.steady_bifurcations import JK_FS, JK_KT, LK_KAPPA, LK_VB, averaged_locking, caughey_amplitudes, \
    closed_form_bifurcation, damped_belt, forced_belt, jenkins_oscillator, locking_belt, locking_c_v, scipy_fold, \
    scipy_neimark_sacker, scipy_period_doubling, scipy_sliding_belt_multipliers, sliding_belt, stop_motion, \
    stop_oscillator
from cases import gallery_denhartog as dh

G = 9.81


def belt(v_b: float, mu_s: float = 0.4, mu_k: float = 0.3, m: float = 1.0, k: float = 4.0) -> ss.Model:
    """The paper's belt: mass m on a spring k to the wall, on a belt at v_b, Coulomb friction."""
    return ss.Model.from_scene("belt", "coulomb", m=m, k=k, v_b=v_b, g=G, mu_s=mu_s, mu_k=mu_k, v0=v_b)


def belt_closed_form(v_b: float, mu_s: float = 0.4, mu_k: float = 0.3, m: float = 1.0,
                     k: float = 4.0) -> tuple[float, float]:
    """Period and slip amplitude of the stick-slip cycle: the slip arc about mu_k m g / k
    starts at mu_s m g / k with velocity v_b (amplitude A), the stick phase covers the
    2 (mu_s - mu_k) m g / k between the arc's ends at v_b."""
    w = math.sqrt(k / m)
    amp = math.hypot((mu_s - mu_k) * m * G / k, v_b / w)
    period = (math.pi + 2.0 * math.asin(v_b / (amp * w))) / w + 2.0 * (mu_s - mu_k) * m * G / (k * v_b)
    return period, amp


@pytest.mark.parametrize("v_b", [0.1, 0.3, 0.8])
def test_belt_cycle_equals_closed_form(v_b: float) -> None:
    orb = ss.periodic_orbit(belt(v_b))
    period, amp = belt_closed_form(v_b)
    assert orb.autonomous and orb.monodromy_method == "saltation"
    assert orb.period == pytest.approx(period, rel=1e-8, abs=0)
    assert orb.amplitude[0] == pytest.approx(amp, rel=1e-8, abs=0)
    # one stick phase: the trivial multiplier 1, the other collapsed to 0
    assert abs(orb.multipliers[orb.trivial] - 1.0) < 1e-8
    assert abs(orb.nontrivial[0]) < 1e-10
    assert orb.stable
    stick = 2 * (0.4 - 0.3) * G / (4.0 * v_b)
    assert orb.stick_fraction[0] == pytest.approx(stick / period, rel=1e-8)
    assert sorted(set(orb.events["kind"])) == ["slip", "stick"]


def test_belt_continuation_in_belt_speed_follows_the_closed_form() -> None:
    br = ss.continuation(lambda p: belt(p), 0.2, 0.6, step=0.1, max_step=0.25)
    assert br.p[0] == 0.2 and br.p[-1] == 0.6 and len(br) >= 3
    for p, t, a, mult in zip(br.p, br.period, br.amplitude, br.multipliers):
        period, amp = belt_closed_form(float(p))
        assert t == pytest.approx(period, rel=1e-8, abs=0)
        assert a == pytest.approx(amp, rel=1e-8, abs=0)
        assert np.sort(np.abs(mult))[0] < 1e-10
    assert br.stable.all() and not br.bifurcations
    assert br.stop_reason.startswith("reached stop")


def test_default_first_step_stays_on_the_stick_slip_branch() -> None:
    """The paper's belt (m = 10 kg, k = 300 N/m, mu 0.35/0.30) continued in v_b from 0.2 m/s
    with the default first step: near steady sliding neutral pure-slip orbits surround the
    stick-slip cycle, and a first step along p's axis once landed on one (no stick, multiplier
    1) as an ordinary point. Every point must be the stick-slip cycle of the closed form."""
    def paper_belt(v_b: float) -> ss.Model:
        return ss.Model.from_scene("belt", "coulomb", v_b=v_b, mu_s=0.35, mu_k=0.30, v0=v_b)
    br = ss.continuation(paper_belt, 0.2, 2.0)
    assert br.stop_reason.startswith("reached stop") and len(br) >= 3
    for p, t in zip(br.p, br.period):
        period, _ = belt_closed_form(float(p), mu_s=0.35, mu_k=0.30, m=10.0, k=300.0)
        assert t == pytest.approx(period, rel=1e-8, abs=0)
    assert all(np.sort(np.abs(mult))[0] < 1e-10 for mult in br.multipliers)


def forced_linear(zeta: float = 0.05, f: float = 0.3) -> ss.Model:
    m = ss.Model()
    b = m.add_body(1.0)
    m.add_spring(b, None, k=4.0)
    m.add_damper(b, None, c=2 * zeta * 2.0)
    m.add_force(b, ss.signal.sine(1.0, f))
    return m


def test_forced_linear_oscillator_against_closed_form_and_scipy() -> None:
    f, zeta, wn = 0.3, 0.05, 2.0
    orb = ss.periodic_orbit(forced_linear(zeta, f), method="dopri5")
    w = 2 * math.pi * f
    amp = 1.0 / math.hypot(wn**2 - w**2, 2 * zeta * wn * w)
    assert orb.period == pytest.approx(1 / f, rel=1e-14)
    assert orb.amplitude[0] == pytest.approx(amp, rel=1e-8)
    # the monodromy is exp(A T) for x'' + 2 zeta wn x' + wn^2 x = 0: by scipy, independently
    from scipy.integrate import solve_ivp
    a = np.array([[0.0, 1.0], [-wn**2, -2 * zeta * wn]])
    sol = solve_ivp(lambda t, y: (a @ y.reshape(2, 2)).ravel(), (0, 1 / f), np.eye(2).ravel(),
                    method="DOP853", rtol=1e-12, atol=1e-14)
    ref = np.linalg.eigvals(sol.y[:, -1].reshape(2, 2))
    assert orb.monodromy_method == "finite differences"
    np.testing.assert_allclose(np.sort_complex(orb.multipliers), np.sort_complex(ref), rtol=0, atol=1e-6)
    assert orb.stable


def test_regularised_multipliers_against_scipy_variational_equations() -> None:
    """A forced oscillator with a regularised law (proposed, smooth): the monodromy by finite
    differences of DOPRI5's flow against the variational equations integrated by scipy."""
    model = ss.Model()
    b = model.add_body(1.0)
    model.add_spring(b, None, k=4.0)
    model.add_force(b, ss.signal.sine(10.0, 0.25))
    model.add_contact(b, None, "proposed", normal_force=G, mu_s=0.4, mu_k=0.3, v_s=0.5)
    orb = ss.periodic_orbit(model, method="dopri5")
    from scipy.integrate import solve_ivp

    def mu(s: np.ndarray) -> np.ndarray:
        return ss.friction_coefficient("proposed", s, mu_s=0.4, mu_k=0.3, v_s=0.5)

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        x, v = z[0], z[1]
        phi = z[2:].reshape(2, 2)
        h = 1e-7
        dmu = (mu(np.array([v + h]))[0] - mu(np.array([v - h]))[0]) / (2 * h)
        jac = np.array([[0.0, 1.0], [-4.0, -G * dmu]])
        acc = -4.0 * x + 10.0 * math.sin(2 * math.pi * 0.25 * t) - G * mu(np.array([v]))[0]
        return np.concatenate([[v, acc], (jac @ phi).ravel()])
    sol = solve_ivp(rhs, (0, 4.0), np.concatenate([orb.y0, np.eye(2).ravel()]), method="DOP853",
                    rtol=1e-11, atol=1e-13)
    assert np.max(np.abs(sol.y[:2, -1] - orb.y0)) < 1e-7         # the orbit closes under scipy too
    ref = np.linalg.eigvals(sol.y[2:, -1].reshape(2, 2))
    np.testing.assert_allclose(np.sort_complex(orb.multipliers), np.sort_complex(ref), rtol=0, atol=3e-5)


def test_saltation_against_finite_differences_on_den_hartog_without_stops() -> None:
    """The exact route and the finite-difference route agree on an orbit with reversals."""
    beta, r = 2.0, 0.3
    model = dh.model(beta, r)
    orb = ss.periodic_orbit(model)
    assert orb.monodromy_method == "saltation"
    assert set(orb.events["kind"]) == {"reversal"}
    from stickslip import steady
    fd = steady._fd_monodromy(steady._Runner(model, "event_driven", {"rtol": 1e-12, "atol": 1e-14}),
                              orb.y0, orb.period)
    np.testing.assert_allclose(orb.monodromy, fd, rtol=0, atol=1e-5)


def test_den_hartog_response_equals_closed_form() -> None:
    r = 0.3
    betas = [b for b in (0.6, 0.7, 0.8, 1.3, 1.5, 2.0, 2.5) if dh.nonstop_valid(b, r)]
    assert len(betas) >= 5
    freqs = [b / (2 * math.pi) for b in betas]
    br = ss.frequency_response(lambda f: dh.model(2 * math.pi * f, r), freqs, follow=False)
    np.testing.assert_array_equal(br.p, freqs)
    for b, a in zip(betas, br.amplitude):
        assert a == pytest.approx(dh.amplitude(b, r), rel=1e-8, abs=0)
    assert (br.stick_fraction == 0).all()


def test_den_hartog_with_stops_against_an_event_driven_transient() -> None:
    beta, r = 0.5, 0.7
    assert not dh.nonstop_valid(beta, r)
    orb = ss.periodic_orbit(dh.model(beta, r))
    assert orb.stick_fraction[0] > 0.05
    # a stop collapses the velocity direction (multiplier 0); the position held during the
    # stop sets the breakaway time, so the other multiplier is not 0: against finite differences
    assert np.abs(orb.multipliers).min() < 1e-10
    from stickslip import steady
    fd = steady._fd_monodromy(steady._Runner(dh.model(beta, r), "event_driven",
                                             {"rtol": 1e-12, "atol": 1e-14}), orb.y0, orb.period)
    assert np.abs(orb.multipliers).max() == pytest.approx(np.abs(np.linalg.eigvals(fd)).max(), abs=1e-5)
    # the independent check: 80 periods from rest, amplitude from the last turning points
    T = 2 * math.pi / beta
    res = ss.simulate(dh.model(beta, r), method="event_driven", t_end=80 * T, n_out=3, rtol=1e-12, atol=1e-14)
    xs = [e["x"] for e in res.events if e["t"] > 78 * T and e["kind"] in ("stick", "reversal")]
    assert orb.amplitude[0] == pytest.approx(0.5 * (max(xs) - min(xs)), rel=1e-8)
    stick, _ = dh._stick_intervals(res.events, 78 * T, 80 * T)
    assert orb.stick_fraction[0] == pytest.approx(stick / (2 * T), rel=1e-8)


def test_non_periodic_forcing_is_a_named_failure() -> None:
    m = forced_linear()
    m.add_force(0, ss.signal.ramp(1.0, 2.0, 1.0))
    with pytest.raises(ss.NonPeriodicForcing, match="ramp"):
        ss.periodic_orbit(m, method="dopri5")
    with pytest.raises(ss.NonPeriodicForcing, match="does not repeat"):
        ss.periodic_orbit(forced_linear(f=0.3), period=2.0, method="dopri5")


def test_guess_of_the_wrong_shape_is_a_named_failure() -> None:
    with pytest.raises(ss.GuessShapeError, match="got shape"):
        ss.periodic_orbit(forced_linear(), guess=[0.0, 0.0, 0.0], method="dopri5")
    with pytest.raises(ss.GuessShapeError, match="period"):
        ss.periodic_orbit(belt(0.3), guess=[0.0, 0.3])


def test_no_convergence_is_a_named_failure_not_an_orbit() -> None:
    # an undamped forced oscillator at resonance has no periodic orbit
    m = ss.Model()
    b = m.add_body(1.0)
    m.add_spring(b, None, k=4.0)
    m.add_force(b, ss.signal.sine(1.0, 1.0 / math.pi))
    with pytest.raises(ss.NoConvergence) as err:
        ss.periodic_orbit(m, method="dopri5", max_iter=5)
    assert err.value.residual > 1e-10


@pytest.mark.filterwarnings("ignore::stickslip.ConsistencyWarning")
def test_lugre_belt_cycle_against_a_long_transient() -> None:
    """LuGre's bristle state is an unknown of the shooting: the stick-slip cycle on the belt
    at v_b = 0.1 m/s equals the last periods of a 60 s transient (radau5, rtol 1e-12): its
    period from the transient's upward crossings of the mid position, its amplitude and the
    bristle deflection z at that crossing."""
    m = ss.Model.from_scene("belt", "lugre", v_b=0.1)
    orb = ss.periodic_orbit(m, method="radau5")
    assert orb.z0.shape == (1,) and orb.y0.shape == (3,) and orb.multipliers.shape == (3,)
    assert orb.trivial_error < 1e-5 and orb.stable
    # from a guess off the cycle, the bristle deflected the other way: Newton moves z too (z = 0
    # exactly gives the orbit solver's differences a step of 1e-9 times fd_newton in z, below
    # rounding: stickslip_orbit's orbit_scales)
    off = ss.periodic_orbit(m, guess=[orb.x0[0], orb.v0[0], -orb.z0[0], 1.05 * orb.period], method="radau5")
    assert off.iterations > 0 and off.period == pytest.approx(orb.period, rel=1e-9)
    r = ss.simulate(m, method="radau5", t_end=60.0, n_out=600001, rtol=1e-12, atol=1e-14)
    last = r.t >= 60.0 - 10 * orb.period
    x, t = r.x[0, last], r.t[last]
    level = 0.5 * (x.max() + x.min())
    up = np.flatnonzero((x[:-1] < level) & (x[1:] >= level))
    crossings = t[up] + (level - x[up]) * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    assert np.diff(crossings) == pytest.approx(orb.period, rel=1e-6)
    assert 0.5 * (x.max() - x.min()) == pytest.approx(orb.amplitude[0], rel=1e-6)
    # the bristle deflection where x rises through the level, on either grid (interpolated)
    def z_at_level(xs: np.ndarray, zs: np.ndarray) -> float:
        k = np.flatnonzero((xs[:-1] < level) & (xs[1:] >= level))[-1]
        return float(zs[k] + (level - xs[k]) * (zs[k + 1] - zs[k]) / (xs[k + 1] - xs[k]))
    z_orbit = z_at_level(orb.result.x[0], orb.result.z.reshape(-1, orb.result.t.size)[0])
    assert z_at_level(x, r.z.reshape(-1, r.t.size)[0, last]) == pytest.approx(z_orbit, rel=1e-6)
    assert orb.result.z.min() <= orb.z0[0] <= orb.result.z.max()


def test_laws_with_states_are_refused_where_not_handled() -> None:
    """Equilibria refuse laws with states by name, before any run; harmonic balance those on a
    moving surface (the belt)."""
    from stickslip.harmonic import harmonic_balance
    m = ss.Model.from_scene("belt", "lugre")
    with pytest.raises(ss.LawStatesUnsupported, match="internal states"):
        ss.equilibrium(m)
    forced = ss.Model.from_scene("belt", "lugre")
    forced.add_force(0, ss.signal.sine(1.0, 1.0))
    with pytest.raises(ss.LawStatesUnsupported, match="internal states"):
        harmonic_balance(forced, 3)


def test_den_hartog_curve_followed_by_pseudo_arclength() -> None:
    r = 0.3
    betas = np.linspace(1.3, 3.0, 4)
    br = ss.frequency_response(lambda f: dh.model(2 * math.pi * f, r), betas[::-1] / (2 * math.pi))
    np.testing.assert_array_equal(br.p, betas[::-1] / (2 * math.pi))      # rows in the order given
    for b, a in zip(betas[::-1], br.amplitude):
        assert a == pytest.approx(dh.amplitude(b, r), rel=1e-8, abs=0)
    curve = br.curve
    assert curve is not None and len(curve) > 4 and curve.stop_reason.startswith("reached stop")
    assert np.all(np.diff(curve.p) > 0) and not [b for b in curve.bifurcations if b["kind"] == "fold"]
    exact = np.array([dh.amplitude(2 * math.pi * f, r) for f in curve.p])
    np.testing.assert_allclose(curve.amplitude, exact, rtol=1e-8)


def test_retuned_and_the_cli(tmp_path) -> None:
    from stickslip.__main__ import main
    from stickslip.steady import retuned
    model = dh.model(2.0, 0.3)
    assert ss.steady.forcing_period(retuned(model, 0.5)) == pytest.approx(2.0)
    path = tmp_path / "dh.toml"
    model.to_toml(path)
    out = tmp_path / "orbit.csv"
    assert main(["orbit", str(path), "--out", str(out), "--plot"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data[-1, 0] == pytest.approx(math.pi)
    assert (tmp_path / "orbit.png").stat().st_size > 1000
    out = tmp_path / "response.csv"
    assert main(["response", str(path), "--frequencies", "0.25,0.4", "--out", str(out)]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 1], [dh.amplitude(2 * math.pi * f, 0.3) for f in (0.25, 0.4)], rtol=1e-8)
    assert main(["response", str(path), "--frequencies", "0.25", "--out", str(out)]) == 2   # exists


def test_module_examples() -> None:
    import doctest
    from stickslip import harmonic, steady
    for mod in (steady, harmonic):
        result = doctest.testmod(mod, optionflags=doctest.ELLIPSIS)
        assert result.attempted >= 3 and result.failed == 0


def test_multiple_shooting_finds_the_same_orbits() -> None:
    beta, r = 0.5, 0.7                                  # forced, with stops: segments start at k T / 3
    one = ss.periodic_orbit(dh.model(beta, r))
    three = ss.periodic_orbit(dh.model(beta, r), segments=3, guess=one.y0 + 0.01)
    np.testing.assert_allclose(three.y0, one.y0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(three.amplitude, one.amplitude, rtol=1e-9)
    orb = ss.periodic_orbit(belt(0.3), segments=4)      # autonomous
    period, amp = belt_closed_form(0.3)
    assert orb.period == pytest.approx(period, rel=1e-8) and orb.amplitude[0] == pytest.approx(amp, rel=1e-8)
    with pytest.raises(ValueError, match="segments"):
        ss.periodic_orbit(belt(0.3), segments=0)


def test_shifted_signals_are_the_signals_later() -> None:
    from stickslip.steady import _shifted, _signal
    s = ss.signal.sine(2.0, 0.7, 0.3, 0.1) * ss.signal.step(1.0) + ss.signal.ramp(0.5, 1.0, 3.0) \
        + ss.signal.table([0.0, 1.0, 2.0], [0.0, 2.0, 1.0])
    m = ss.Model()
    b = m.add_body(1.0)
    m.add_force(b, s)
    later = _shifted(m, 0.8).forces[0][1]
    t = np.linspace(0.0, 3.0, 31)
    np.testing.assert_allclose(_signal(later, t)[0], _signal(s, t + 0.8)[0], rtol=0, atol=1e-13)




def test_hopf_point_of_steady_sliding_against_the_linearisation() -> None:
    """Steady sliding on the belt loses stability where c + N mu'(v_b) = 0 (the linearised
    damping vanishes). The Hopf is subcritical: unstable cycles exist for c above it; followed
    down in c, the branch shrinks to the equilibrium at the Hopf point and turns back."""
    mass, k, n = 10.0, 300.0, 10.0 * 9.81
    slope = np.diff(ss.friction_coefficient("proposed", np.array([1.5 - 1e-6, 1.5 + 1e-6])))[0] / 2e-6
    c_hopf = -n * slope
    w = math.sqrt(k / mass)
    x_slide = n * ss.friction_coefficient("proposed", np.array([1.5]))[0] / k
    start = ss.periodic_orbit(damped_belt(1.11), guess=[x_slide + 0.18, 0.0, 2 * math.pi / w], method="dopri5")
    assert not start.stable
    br = ss.continuation(damped_belt, 1.11, 1.0, guess=start, method="dopri5", step=0.05, max_points=20)
    hopf = [b for b in br.bifurcations if b["kind"] == "Hopf"]
    assert len(hopf) == 1 and not [b for b in br.bifurcations if b["kind"] == "fold"]
    i = hopf[0]["index"]
    assert br.p[i] == pytest.approx(c_hopf, rel=1e-4)
    assert br.period[i] == pytest.approx(2 * math.pi / w, rel=1e-6)
    assert not br.stable.any()


def test_continuation_through_the_end_of_den_hartogs_stops() -> None:
    """From motion with stops into non-stop motion (r = 0.5): the branch marks where the stick
    phases vanish (an "events" bifurcation) at the border of his closed form's validity, and
    beyond it equals the closed form."""
    r = 0.5
    br = ss.continuation(lambda f: dh.model(2 * math.pi * f, r), 0.5 / (2 * math.pi), 0.7 / (2 * math.pi))
    assert br.stop_reason.startswith("reached stop")
    events = [b for b in br.bifurcations if b["kind"] == "events"]
    assert len(events) == 1
    i = events[0]["index"]
    assert dict(events[0]["before"]) == {"slip@0": 2, "stick@0": 2}
    assert dict(events[0]["after"]) == {"reversal@0": 2}
    beta = 2 * math.pi * br.p
    assert not dh.nonstop_valid(beta[i - 1], r) and dh.nonstop_valid(beta[i], r)
    assert (br.stick_fraction[:i, 0] > 0).all() and (br.stick_fraction[i:, 0] == 0).all()
    exact = np.array([dh.amplitude(b, r) for b in beta[i:]])
    np.testing.assert_allclose(br.amplitude[i:], exact, rtol=1e-8)


def test_two_blocks_saltation_against_finite_differences() -> None:
    """The gallery's two coupled blocks on a belt with Coulomb friction: a cycle where block 2
    sticks while block 1 slips; the saltation monodromy (the stuck contact's holding force
    coupling the modes) against central differences of event_driven's flow."""
    from cases import gallery_belt2dof as g2
    from stickslip import steady
    model = g2.model("coulomb", mu_s=0.4, mu_k=0.25)
    orb = ss.periodic_orbit(model, transient=60)
    assert orb.monodromy_method == "saltation" and orb.stick_fraction[0] == 0 and orb.stick_fraction[1] > 0.1
    fd = steady._fd_monodromy(steady._Runner(model, "event_driven", {"rtol": 1e-12, "atol": 1e-14}),
                              orb.y0, orb.period)
    np.testing.assert_allclose(orb.monodromy, fd, rtol=0, atol=1e-6)
    assert abs(orb.multipliers[orb.trivial] - 1) < 1e-9 and np.abs(orb.multipliers).min() < 1e-12
    # started stuck on the belt, Newton shrinks the period to nothing: refused, not an orbit
    for b in model.bodies:
        b.v0 = 0.2
    with pytest.raises(ss.NoConvergence, match="collapsed"):
        ss.periodic_orbit(model, transient=60)


def test_an_untrustworthy_monodromy_warns() -> None:
    """Moreau-Jean's fixed steps put the belt's stick-slip transitions inside steps: the flow
    map jumps, no multiplier is near 1, and the orbit says so (the period is still first-order
    close to the closed form)."""
    with pytest.warns(ss.MonodromyWarning, match="not to be trusted"):
        orb = ss.periodic_orbit(belt(0.3), method="moreau", h=1e-3)
    assert orb.trivial_error > 1e-3
    assert orb.period == pytest.approx(belt_closed_form(0.3)[0], rel=1e-4)
    assert orb.stick_fraction[0] == pytest.approx(0.4355, abs=1e-3)


def test_branch_plot_and_progress(capsys) -> None:
    import matplotlib
    matplotlib.use("Agg")
    br = ss.continuation(belt, 0.3, 0.4, progress=True)
    assert capsys.readouterr().err.rstrip().endswith("] p = 0.4")
    ax = br.plot()
    assert ax.get_ylabel() == "amplitude [m]" and len(ax.lines) >= 2


@pytest.mark.parametrize("beta", [0.6, 1.5, 2.0, 3.0, 5.0])
def test_den_hartog_multipliers_product_in_closed_form(beta: float) -> None:
    """Without viscous damping the flow between events keeps volume (det 1), and a reversal at
    the turning point X, where the spring and the force pull back with k X beta^2 (m = k = 1)
    and friction F = r flips, has a saltation matrix of determinant (k X beta^2 - F) /
    (k X beta^2 + F): two per period give det M = ((X beta^2 - r) / (X beta^2 + r))^2."""
    r = 0.3
    assert dh.nonstop_valid(beta, r)
    orb = ss.periodic_orbit(dh.model(beta, r))
    x = dh.amplitude(beta, r)
    expected = ((x * beta**2 - r) / (x * beta**2 + r)) ** 2
    assert abs(np.prod(orb.multipliers)) == pytest.approx(expected, rel=1e-9)
    assert np.all(np.abs(orb.multipliers) < 1) and orb.stable


def test_stribeck_cycle_saltation_with_integrated_variations() -> None:
    """Set-valued Stribeck on the belt under event_driven: the variational equation of the slip
    mode integrated by scipy, saltation at the events; the stick phase's multiplier is 0, the
    trivial one 1, and the monodromy equals central differences of the flow."""
    from stickslip import steady
    model = ss.Model.from_scene("belt", "stribeck", m=1.0, k=4.0, v_b=0.3, g=G, mu_s=0.4, mu_k=0.3, v_s=0.1,
                                delta=2.0, v0=0.3)
    orb = ss.periodic_orbit(model)
    assert orb.monodromy_method == "saltation" and orb.stick_fraction[0] > 0.4
    assert abs(orb.multipliers[orb.trivial] - 1) < 1e-8 and abs(orb.nontrivial[0]) < 1e-12
    fd = steady._fd_monodromy(steady._Runner(model, "event_driven", {"rtol": 1e-12, "atol": 1e-14}),
                              orb.y0, orb.period)
    np.testing.assert_allclose(orb.monodromy, fd, rtol=0, atol=1e-6)


@pytest.mark.parametrize("kwargs,match", [(dict(tol=0.0), "tol"), (dict(max_iter=0), "max_iter"),
                                          (dict(n_out=1), "n_out"), (dict(segments=1.5), "segments"),
                                          (dict(period=-1.0), "period"), (dict(transient=True), "transient")])
def test_bad_options_name_the_parameter(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        ss.periodic_orbit(forced_linear(), method="dopri5", **kwargs)


def test_equilibria_continued_to_the_hopf_point_of_steady_sliding() -> None:
    """Steady sliding on the damped belt continued in the damper c: its eigenvalues equal
    numpy's of the linearisation x'' = -(k x + (c + N mu'(v_b)) x') / m written here, and the
    Hopf point is located where c + N mu'(v_b) = 0, at the frequency sqrt(k/m)."""
    mass, k, n, v_b = 10.0, 300.0, 10.0 * 9.81, 1.5
    h = 1e-6
    slope = float(np.diff(ss.friction_coefficient("proposed", np.array([v_b - h, v_b + h])))[0] / (2 * h))
    c_hopf = -n * slope
    br = ss.continuation(damped_belt, 0.5, 1.5, kind="equilibrium", step=0.1)
    assert br.kind == "equilibrium" and len(br) == 11 and br.stop_reason.startswith("reached stop")
    x_slide = n * float(ss.friction_coefficient("proposed", np.array([v_b]))[0]) / k
    for c, eq, eig in zip(br.p, br.orbits, br.eigenvalues):
        assert eq.x0[0] == pytest.approx(x_slide, rel=1e-12) and eq.v0[0] == 0.0 and eq.residual < 1e-12
        lin = np.array([[0.0, 1.0], [-k / mass, -(c + n * slope) / mass]])
        exact = np.linalg.eigvals(lin)
        key = lambda z: (round(float(np.real(z)), 9), float(np.imag(z)))     # noqa: E731
        np.testing.assert_allclose(sorted(eig.astype(complex), key=key), sorted(exact, key=key),
                                   rtol=0, atol=1e-8)
        assert eq.stable == (c > c_hopf)
    hopf = br.bifurcations
    assert [b["kind"] for b in hopf] == ["Hopf"]
    assert hopf[0]["p"] == pytest.approx(c_hopf, rel=1e-9)
    assert hopf[0]["frequency"] == pytest.approx(math.sqrt(k / mass), rel=1e-9)
    assert np.all(np.isnan(br.period)) and br.multipliers.shape == (11, 0)


def test_two_blocks_equilibrium_eigenvalues_against_the_linearisation() -> None:
    """The gallery's two blocks on the belt (stribeck with v_s = 0.2 m/s: falling at the belt
    speed) with a damper c on block 1: equilibrium x = K^-1 (N mu(v_b)), eigenvalues of
    [[0, I], [-M^-1 K, -M^-1 (C + N mu'(v_b) I)]] by numpy, and one Hopf point (one mode
    damped out of its instability by c, the other not) where a pair of those crosses."""
    from cases import gallery_belt2dof as g2

    def build(c: float) -> ss.Model:
        m = g2.model("stribeck", **law)
        m.add_damper(0, None, c)
        return m
    law = {**g2.LAW, "v_s": 0.2}
    v, h = g2.V_BELT, 1e-6
    mu = float(ss.friction_coefficient("stribeck", np.array([v]), **law)[0])
    slope = float(np.diff(ss.friction_coefficient("stribeck", np.array([v - h, v + h]), **law))[0] / (2 * h))
    k = np.array([[g2.K1 + g2.K12, -g2.K12], [-g2.K12, g2.K2 + g2.K12]])
    normal = np.array([g2.M1, g2.M2]) * g2.G
    mass = np.array([g2.M1, g2.M2])

    def linear(c: float) -> np.ndarray:
        damping = np.diag([c, 0.0]) + np.diag(normal * slope)
        return np.block([[np.zeros((2, 2)), np.eye(2)], [-k / mass[:, None], -damping / mass[:, None]]])
    br = ss.continuation(build, 0.0, 60.0, kind="equilibrium", step=0.05)
    key = lambda z: (round(float(np.real(z)), 7), float(np.imag(z)))     # noqa: E731
    for c, eq in zip(br.p, br.orbits):
        np.testing.assert_allclose(eq.x0, np.linalg.solve(k, normal * mu), rtol=1e-12)
        np.testing.assert_allclose(sorted(eq.eigenvalues.astype(complex), key=key),
                                   sorted(np.linalg.eigvals(linear(c)), key=key), rtol=0, atol=1e-7)
    assert [(b["kind"], b["located"]) for b in br.bifurcations] == [("Hopf", True)]
    ev = np.linalg.eigvals(linear(br.bifurcations[0]["p"]))
    crit = ev[np.argmin(np.abs(ev.real))]
    assert abs(crit.real) < 1e-8 and br.bifurcations[0]["frequency"] == pytest.approx(abs(crit.imag), rel=1e-9)


def test_equilibrium_refusals_are_named() -> None:
    """A forced model has no equilibrium; a set-valued contact at rest on its surface has a set
    of them; both refused by name."""
    with pytest.raises(ss.NonPeriodicForcing, match="no equilibrium"):
        ss.equilibrium(forced_linear())
    at_rest = ss.Model.from_scene("belt", "coulomb", v_b=0.0)
    with pytest.raises(ss.SteadyStateError, match="set of equilibria|are a set"):
        ss.equilibrium(at_rest)
    with pytest.raises(ValueError, match="kind"):
        ss.continuation(damped_belt, 0.5, 1.5, kind="equilibria")


# ------------------------------------------------------------------------------------------
# Folds and period doubling, against independent scipy computations
# ------------------------------------------------------------------------------------------
# The system (benchmarks/steady_bifurcations.py): a unit mass on a unit spring on a belt at
# 0.1 m/s with a falling Stribeck law (regularised by its tanh ramp, so the flow is smooth and
# every bifurcation a classical one), forced by F cos(W t). Self-excited near the belt's sliding
# equilibrium and forced, it locks to the forcing: the period-1 orbit period-doubles as W
# passes the 1:2 locking region, and at small F it ends in saddle-node folds. No published
# friction system with tabulated fold or period-doubling values could be read from this
# project's sources (the papers found, e.g. Leine, van Campen & van de Vrande 2000, Nonlinear
# Dynamics 23, and Leine & van Campen 2002, Math. Comput. Modelling 36, give theirs only in
# figures), so each value is checked against its own computation with scipy there: shooting on
# solve_ivp (DOP853, rtol 1e-12) with the variational equations of the law written out, and a
# bracketing root (brentq). A period doubling and a pitchfork of a system whose bifurcations
# are published (Shaw 1986) are checked against closed forms further below, and the folds at
# the edge of frequency locking of a weakly self-excited belt against the first-order averaged
# equations and Adler's (1946) locking edge right after the scipy fold.


def test_period_doublings_against_scipy_shooting() -> None:
    """Continued in W from 0.85 to 1.65 at F = 0.3, the period-1 orbit's multiplier passes -1
    twice (a period-doubling bubble); each located W equals the root of mu_min(W) + 1 of
    scipy shooting with the variational equations, to 1e-8 (measured: 3e-10)."""
    br = ss.continuation(forced_belt, 0.85, 1.65, method="dopri5", step=0.05, max_step=0.1)
    assert br.stop_reason.startswith("reached stop")
    pd = [b for b in br.bifurcations if b["kind"] == "period doubling"]
    assert [b["located"] for b in pd] == [True, True] and len(br.bifurcations) == 2
    for b in pd:
        i = b["index"]
        assert br.p[i - 1] < b["p"] < br.p[i]
        before, after = np.min(br.multipliers[i - 1].real), np.min(br.multipliers[i].real)
        assert before < 0 and after < 0 and (abs(before) - 1) * (abs(after) - 1) < 0
        assert b["p"] == pytest.approx(scipy_period_doubling(br.p[i - 1], br.p[i], br.orbits[i].y0), rel=1e-8)
    assert not br.stable[(br.p > pd[0]["p"]) & (br.p < pd[1]["p"])].any()
    assert br.stable[(br.p < pd[0]["p"]) | (br.p > pd[1]["p"])].all()


def test_fold_against_scipy_extremum_of_the_branch() -> None:
    """Continued down in the forcing amplitude F at W = 1, the locked orbit turns back at a
    saddle-node fold (a multiplier through +1) and again further on; the first fold's F equals
    the minimum of F along the branch computed with scipy: the branch parametrised by x(0), each
    point by Newton on (v(0), F), dF/dx(0) by the implicit function theorem, and its root
    bracketed (to 1e-9; measured 1e-12)."""
    br = ss.continuation(lambda amp: forced_belt(1.0, amp), 0.06, 0.02, method="dopri5", step=0.05, max_step=0.1)
    folds = [b for b in br.bifurcations if b["kind"] == "fold"]
    assert len(folds) == 2 and all(b["located"] for b in folds)
    i = folds[0]["index"]
    exact = scipy_fold(float(br.orbits[i - 1].x0[0]), float(br.orbits[i + 1].x0[0]), float(br.orbits[i].v0[0]),
                       float(br.p[i]))
    assert folds[0]["p"] == pytest.approx(exact, rel=1e-9)
    assert br.stable[:i].all() and not br.stable[i + 1:].any()


def test_folds_at_the_edge_of_frequency_locking_tend_to_the_averaged_equations_and_adlers_edge() -> None:
    """A weakly self-excited belt (growth rate eps: D'(0) = -2 eps, no quadratic term in D)
    forced by F cos(W t) at W = 1 + sigma, sigma = eps / 4, continued down in F: the locked
    orbit turns at a saddle-node fold (the edge of 1:1 locking) and again at a second fold
    (where the saddle meets the small-amplitude orbit). To first order in eps (Krylov-Bogoliubov
    averaging, or multiple scales as Nayfeh & Mook, Nonlinear Oscillations, Wiley 1979, do for
    the forced van der Pol oscillator), locked orbits of amplitude a satisfy F^2 = Q(a)^2 +
    4 sigma^2 a^2, Q(a) = (1/pi) int D(-a sin t) sin t dt (`averaged_locking`), and the folds
    are its extrema in a: each continued fold tends to the averaged one at the first-order
    rate (the relative gap halves with eps; measured 0.45 and 0.49 for the lower fold, 0.48
    and 0.50 for the upper). The lower fold of the averaged equations tends to Adler's
    locking edge F = 2 a0 |sigma| (R. Adler, Proc. IRE 34, 351-357, 1946; a0 the free cycle's
    amplitude, Q(a0) = 0) as sigma / eps -> 0, the gap quartering as sigma halves (measured
    0.246 and 0.249). The first fold also equals scipy's minimum of F along the branch at
    eps = 0.01 to 1e-8 (measured 3e-10)."""
    gaps = []
    for eps in (0.02, 0.01, 0.005):
        a0, f_min, f_max = averaged_locking(eps, LK_KAPPA * eps)
        br = ss.continuation(lambda f: locking_belt(f, eps), 2.5 * f_min, 0.5 * f_min, method="dopri5", step=0.05,
                             max_step=0.1)
        folds = [b for b in br.bifurcations if b["kind"] == "fold"]
        assert [b["located"] for b in folds] == [True, True] and len(br.bifurcations) == 2
        i = folds[0]["index"]
        assert br.stable[:i].all() and not br.stable[i + 1:].any()
        gaps.append([folds[0]["p"] / f_min - 1, folds[1]["p"] / f_max - 1])
        assert np.all(np.abs(gaps[-1]) < 1.2 * eps)
        if eps == 0.01:
            exact = scipy_fold(float(br.orbits[i - 1].x0[0]), float(br.orbits[i + 1].x0[0]),
                               float(br.orbits[i].v0[0]), float(br.p[i]), 1.0 + LK_KAPPA * eps, locking_c_v(eps),
                               LK_VB)
            assert folds[0]["p"] == pytest.approx(exact, rel=1e-8)
    ratios = np.array(gaps[1:]) / np.array(gaps[:-1])
    assert np.all((ratios > 0.4) & (ratios < 0.6)), ratios
    adler = []
    for kappa in (0.2, 0.1, 0.05):
        a0, f_min, _ = averaged_locking(0.01, kappa * 0.01)
        adler.append(f_min / (2.0 * a0 * kappa * 0.01) - 1.0)
    assert adler[0] < 0 and abs(adler[0]) < 0.2 ** 2
    assert np.all((np.array(adler[1:]) / adler[:-1] > 0.2) & (np.array(adler[1:]) / adler[:-1] < 0.3)), adler


def test_bilinear_hysteresis_response_against_caugheys_one_harmonic_closed_form() -> None:
    """A mass on a spring k and a Jenkins element (spring k_t in series with a slider of limit
    F_s: bilinear hysteresis), lightly damped and forced by P cos(w t): Caughey (1960,
    "Sinusoidal excitation of a system with bilinear hysteresis", J. Appl. Mech. 27(4)
    640-643) gives its one-harmonic response in closed form; with x_y = F_s / k_t and
    cos(beta) = 1 - 2 x_y / a the element's describing function is C = k_t a (beta - sin(2
    beta) / 2) / pi in phase and S = 4 F_s (1 - x_y / a) / pi in quadrature, and
    (k a + C - m w^2 a)^2 + (S + c w a)^2 = P^2 (benchmarks/steady_bifurcations.py,
    `caughey_residual`). That curve has one amplitude at every frequency, checked here on a
    grid (it bends to lower frequency but never folds; the jump phenomenon Iwan, J. Appl. Mech.
    32(4) 921-925, 1965, reports is that of his double bilinear model), and the exact curve,
    continued by shooting, has no fold either. Where the motion stays elastic (a <= x_y) it is linear and the closed form is
    exact: equal to 1e-8 (measured 1.5e-9); where the slider slips the exact amplitude departs
    from the one-harmonic one by at most 4 % (measured 3.3 % at 0.7 rad/s, where slip sets
    in) and by 3e-3 from 0.8 rad/s on (measured 2.2e-3). The Jenkins element is the
    elastoplastic law in its limit z_ba -> F_s / k_t (z_ba_ratio 0.999 against 0.9999: 8.6e-7)."""
    ws = np.linspace(0.3, 1.6, 14)
    one = [caughey_amplitudes(float(w)) for w in np.linspace(0.3, 1.6, 131)]
    assert all(len(r) == 1 for r in one)
    br = ss.frequency_response(lambda f: jenkins_oscillator(2 * math.pi * f), ws / (2 * math.pi), method="radau5")
    assert br.stop_reason == "every frequency solved"
    assert np.all(np.diff(br.curve.p) > 0) and not [b for b in br.curve.bifurcations if b["kind"] == "fold"]
    a1 = np.array([caughey_amplitudes(float(w))[0] for w in ws])
    gap = br.amplitude / a1 - 1.0
    yielding = a1 > JK_FS / JK_KT
    assert yielding.sum() >= 5 and (~yielding).sum() >= 5
    assert np.max(np.abs(gap[~yielding])) < 1e-8
    assert np.max(np.abs(gap[yielding])) < 0.04
    assert np.max(np.abs(gap[yielding & (ws >= 0.8)])) < 3e-3
    # slipping: asymptotically stable; elastic: the slider's rest position is free, a multiplier
    # 1 (the monodromy by finite differences of radau5 runs: to 1e-3, measured 3.4e-4)
    assert br.stable[yielding].all()
    for o in np.array(br.orbits, dtype=object)[~yielding]:
        assert o.monodromy_method == "finite differences" and np.min(np.abs(o.multipliers - 1.0)) < 1e-3
    limit = [ss.periodic_orbit(jenkins_oscillator(0.8, r), method="radau5").amplitude[0] for r in (0.999, 0.9999)]
    assert limit[0] == pytest.approx(limit[1], rel=1e-5)


def test_a_light_slider_on_coulomb_converges_to_the_jenkins_limit() -> None:
    """The Jenkins element of `jenkins_oscillator` built instead from a light body eps (the
    slider, on set-valued coulomb) on the spring k_t, shot event-driven with the saltation
    monodromy: its amplitude at 0.8 rad/s tends to the elastoplastic law's limit linearly in
    eps (measured -8.2e-3 at eps = 1e-3, -7.5e-2 at 1e-2). At eps = 1e-3 the slider sticks
    within 1e-9 of a period after the section, which the saltation monodromy once ran to a
    negative end time."""
    from benchmarks.steady_bifurcations import JK_C, JK_K, JK_P

    def light_slider(eps: float) -> ss.Model:
        m = ss.Model()
        b, s = m.add_body(1.0), m.add_body(eps)
        m.add_spring(b, None, k=JK_K)
        m.add_spring(b, s, k=JK_KT)
        m.add_damper(b, None, c=JK_C)
        m.add_force(b, ss.signal.sine(JK_P, 0.8 / (2 * math.pi), math.pi / 2))
        m.add_contact(s, None, "coulomb", normal_force=1.0, mu_s=JK_FS, mu_k=JK_FS)
        return m
    limit = ss.periodic_orbit(jenkins_oscillator(0.8, 0.9999), method="radau5").amplitude[0]
    gaps = []
    for eps in (1e-2, 1e-3):
        orb = ss.periodic_orbit(light_slider(eps))
        assert orb.monodromy_method == "saltation" and orb.stable
        gaps.append(orb.amplitude[0] / limit - 1.0)
    assert -1e-2 < gaps[1] < 0 and 5 < gaps[0] / gaps[1] < 15


def test_neimark_sacker_and_period_doubling_from_synthetic_multipliers() -> None:
    """The classifier on orbits whose multipliers are set by hand (known truth): a complex pair
    r exp(+-0.7i) with r = 0.9, 0.95, 1.05, 1.1 at p = 0, 1, 2, 3 is a Neimark-Sacker at
    p = 1.5 (|mu| - 1 interpolated), a real pair -0.8, -0.9, -1.1 and 0.5 a period doubling at
    p = 1.5; `locate`, when given, decides p; 0.8, 0.9, 1.1, 1.2 is a branch point where its
    test function is located at a root, a stability change otherwise, or a fold where p turns
    back at the crossing."""
    from stickslip.steady import _bifurcations
    base = ss.periodic_orbit(forced_linear(), method="dopri5")

    def with_multipliers(mult: list[complex]) -> ss.Orbit:
        m = np.array(mult)
        return dataclasses.replace(base, multipliers=m, stable=bool(np.all(np.abs(m) < 1)))
    ps = [0.0, 1.0, 2.0, 3.0]
    torus = [with_multipliers([r * np.exp(0.7j), r * np.exp(-0.7j)]) for r in (0.9, 0.95, 1.05, 1.1)]
    found = _bifurcations(ps, torus, [1.0] * 4)
    assert [(b["kind"], b["index"], b["located"]) for b in found] == [("Neimark-Sacker", 2, False)]
    assert found[0]["p"] == pytest.approx(1.5, rel=1e-12)
    flip = [with_multipliers([m, 0.5]) for m in (-0.8, -0.9, -1.1, -1.2)]
    found = _bifurcations(ps, flip, [1.0] * 4, locate=lambda i, g: (1.25, 0.0))
    assert [(b["kind"], b["index"], b["p"], b["located"]) for b in found] == [("period doubling", 2, 1.25, True)]
    # a real multiplier through +1: a branch point where p goes on, a fold where p turns back
    plus = [with_multipliers([m, 0.5]) for m in (0.8, 0.9, 1.1, 1.2)]
    found = _bifurcations(ps, plus, [1.0] * 4, locate=lambda i, g: (1.4, 1e-9))
    assert [(b["kind"], b["index"], b["p"], b["located"]) for b in found] == [("branch point", 2, 1.4, True)]
    # ... unless prod(mu - 1) only jumps across 0 there (not located, not near 0 where located,
    # or far from where the points predict it): a multiplier jumping across, a stability change
    for locate in (None, lambda i, g: (1.4, 0.03), lambda i, g: (1.9, 1e-9)):
        found = _bifurcations(ps, plus, [1.0] * 4, locate=locate)
        assert [(b["kind"], b["index"], b["located"]) for b in found] == [("stability change", 2, False)]
    found = _bifurcations([0.0, 1.0, 2.0, 1.0], plus, [1.0, 1.0, 1.0, -1.0])
    assert [(b["kind"], b["index"]) for b in found] == [("fold", 2)]


def test_guess_with_law_states_reads_the_period_last() -> None:
    """An autonomous LuGre model takes x, v, (z,) then the period: [x, v, T] is the state and
    period with the bristle at 0, not a bristle deflection of T."""
    from stickslip.steady import _as_guess
    y, t = _as_guess([0.1, -0.1, 1.2], 1, True, 1)
    assert t == 1.2 and y.tolist() == [0.1, -0.1, 0.0]
    y, t = _as_guess([0.1, -0.1, 3e-5, 1.2], 1, True, 1)
    assert t == 1.2 and y.tolist() == [0.1, -0.1, 3e-5]
    y, t = _as_guess([0.1, -0.1, 3e-5], 1, False, 1)
    assert t is None and y.tolist() == [0.1, -0.1, 3e-5]
    with pytest.raises(ss.GuessShapeError, match="law states"):
        _as_guess([0.1, -0.1, 3e-5, 1.2, 1.0], 1, True, 1)


# ------------------------------------------------------------------------------------------
# Neimark-Sacker on a mechanical model, against a brute-force multiplier scan with scipy
# ------------------------------------------------------------------------------------------
# benchmarks/steady_bifurcations.py: `sliding_belt(F)`, a unit mass on a unit spring on a belt
# at 0.1 m/s with a falling stribeck law and a viscous term c_v (self-excited steady sliding
# that saturates before the mass sticks), forced by F cos(1.3 t); scipy's multipliers of its
# period-1 orbit with the law written out.
def test_neimark_sacker_of_a_forced_self_excited_belt_against_a_multiplier_scan() -> None:
    """Continued down in F from 0.06 to 0.02, the branch has one bifurcation, a Neimark-Sacker
    point located by `continuation`; a brute-force scan of scipy's multipliers on a grid of F
    (step 5e-4) brackets the crossing of |mu| = 1 by the complex pair, the located F lies in
    that bracket, and equals the root of |mu|(F) - 1 (brentq on scipy's multipliers) to 1e-6
    relative (the continuation's multipliers are finite differences, good to about 1e-5;
    measured 1e-7)."""
    br = ss.continuation(sliding_belt, 0.06, 0.02, method="dopri5", step=0.05, max_step=0.1)
    assert br.stop_reason.startswith("reached stop")
    assert [b["kind"] for b in br.bifurcations] == ["Neimark-Sacker"] and br.bifurcations[0]["located"]
    f_ns = br.bifurcations[0]["p"]
    i = br.bifurcations[0]["index"]
    assert np.all(np.abs(np.imag(br.multipliers[i - 1:i + 1])) > 1e-3)      # a complex pair either side
    assert br.stable[br.p > f_ns].all() and not br.stable[br.p < f_ns].any()
    y = br.orbits[i].y0
    grid = np.arange(0.030, 0.0501, 5e-4)
    radius = []
    for f in grid:
        y, mu = scipy_sliding_belt_multipliers(f, y)
        assert np.all(np.abs(np.imag(mu)) > 1e-3)
        radius.append(np.max(np.abs(mu)))
    k = int(np.flatnonzero(np.diff(np.array(radius) < 1.0))[0])      # one crossing: outside below, inside above
    assert radius[k] > 1.0 > radius[k + 1] and np.sum(np.diff(np.array(radius) < 1.0)) == 1
    assert grid[k] < f_ns < grid[k + 1]
    assert f_ns == pytest.approx(scipy_neimark_sacker(grid[k], grid[k + 1], y), rel=1e-6)


# ------------------------------------------------------------------------------------------
# A pitchfork and a period doubling of the forced Coulomb oscillator with static friction
# ------------------------------------------------------------------------------------------
# benchmarks/steady_bifurcations.py: `stop_oscillator(beta)`, Den Hartog's oscillator with
# kinetic friction r = 0.3 P0 and static r_s = 0.9 P0, where Shaw (J. Sound Vib. 108(2),
# 305-325, 1986, abstract) showed that the symmetric motions with two stops per period can lose
# stability with pairs of asymmetric motions born there; `stop_motion` gives the stop position
# and the multiplier of the symmetric motion and of the motion with one stop and one reversal
# from their maps in closed form, derived there.
def test_pitchfork_of_the_symmetric_stop_motion_against_its_closed_form() -> None:
    """r = 0.3, r_s = 0.9, continued in beta from 0.3 to 0.48 on the symmetric two-stop motion:
    every point's stop position and nontrivial multiplier equal the closed form's X and g'(X)^2
    (saltation route, exact: 1e-9), the one bifurcation is a located "branch point" at the
    closed form's root of g'(X) = -1 (brentq, 1e-14) to 3e-8 (measured 8e-9), stable before
    and unstable after; and beyond it the transient settles on an asymmetric motion (one of
    the pair born there)."""
    br = ss.continuation(stop_oscillator, 0.3, 0.48, step=0.05, max_step=0.1)
    assert br.stop_reason.startswith("reached stop")
    for beta, orb in zip(br.p, br.orbits):
        x_stop, slope = stop_motion(beta, reversal=False)
        assert orb.amplitude[0] == pytest.approx(x_stop, rel=1e-9)
        assert np.sort(np.abs(orb.multipliers)) == pytest.approx([0.0, slope ** 2], abs=1e-9)
    exact = closed_form_bifurcation(0.44, 0.47, reversal=False)
    assert [(b["kind"], b["located"]) for b in br.bifurcations] == [("branch point", True)]
    bp = br.bifurcations[0]["p"]
    assert bp == pytest.approx(exact, rel=3e-8)
    assert br.stable[br.p < bp].all() and not br.stable[br.p > bp].any()
    beyond = ss.periodic_orbit(stop_oscillator(0.47))
    assert beyond.stable and abs(np.max(beyond.result.x) + np.min(beyond.result.x)) > 1e-2


def test_period_doubling_of_the_one_stop_motion_against_its_closed_form() -> None:
    """r = 0.3, r_s = 0.9, continued in beta from 0.56 to 0.68 on the motion with one stop and
    one reversal: every point's stop position and nontrivial multiplier equal the closed form's
    X (1e-9) and F'(X) (1e-8: the orbits are found to 1e-9; measured 2e-9), and the one
    bifurcation is a located period doubling at the closed form's root of F'(X) = -1 (brentq,
    1e-14) to 1e-9 (measured 1e-10)."""
    br = ss.continuation(stop_oscillator, 0.56, 0.68, step=0.05, max_step=0.1)
    assert br.stop_reason.startswith("reached stop")
    for beta, orb in zip(br.p, br.orbits):
        x_stop, slope = stop_motion(beta, reversal=True)
        assert sorted(orb.events["kind"]) == ["reversal", "slip", "stick"]
        assert abs(orb.events["x"][orb.events["kind"] == "stick"][0]) == pytest.approx(x_stop, rel=1e-9)
        assert np.sort(orb.multipliers.real) == pytest.approx([slope, 0.0], abs=1e-8)
    exact = closed_form_bifurcation(0.63, 0.65, reversal=True)
    assert [(b["kind"], b["located"]) for b in br.bifurcations] == [("period doubling", True)]
    assert br.bifurcations[0]["p"] == pytest.approx(exact, rel=1e-9)
    assert br.stable[br.p < exact].all() and not br.stable[br.p > exact].any()


@pytest.mark.parametrize("beta", [0.45, 0.55, 1.5, 2.5])
def test_den_hartog_multipliers_in_closed_form(beta: float) -> None:
    """Each multiplier of Den Hartog's non-stop motion (m = k = 1, r = 0.05), not only their
    product: by the x -> -x symmetry the period is twice the same half: the free flow over
    T / 2 = pi / beta rotates (x, v) by theta = pi / beta, and the reversal's saltation matrix is
    diag(1, rho), rho = (X beta^2 - r) / (X beta^2 + r) (see the product's test), so the
    multipliers are the squares of the roots of lambda^2 - (1 + rho) cos(theta) lambda + rho.
    Where cos(theta) = 1, beta = 1 / (2n), a root is 1: the marginally stable non-sticking
    motions Csernak, Stepan & Shaw published at Omega = 1 / (2n) (G. Csernak, G. Stepan, S. W.
    Shaw, "Sub-harmonic resonant solutions of a harmonically excited dry friction oscillator",
    Nonlinear Dyn. 50, 93-109, 2007, abstract): see the next test."""
    r = 0.05
    assert dh.nonstop_valid(beta, r)
    orb = ss.periodic_orbit(dh.model(beta, r))
    x = dh.amplitude(beta, r)
    rho = (x * beta ** 2 - r) / (x * beta ** 2 + r)
    lam = np.roots([1.0, -(1.0 + rho) * math.cos(math.pi / beta), rho])
    np.testing.assert_allclose(np.sort_complex(orb.multipliers), np.sort_complex(lam ** 2), rtol=0, atol=1e-9)


@pytest.mark.parametrize("n", [1, 2])
def test_den_hartog_is_marginally_stable_at_half_the_natural_frequency(n: int) -> None:
    """At beta = 1/(2n) (Csernak, Stepan & Shaw 2007, above) the orbit is one of a family and a
    multiplier is 1: the solver's largest is 1 to 1e-4 (its Newton meets a singular Jacobian
    there; measured 6e-6 and 3e-5), at Den Hartog's amplitude X = 1 / (1 - beta^2) (friction
    free there, U = 0). The member of the family it lands on comes to rest for an instant at
    one turn (a stick event), which collapses the other multiplier to 0."""
    beta = 1.0 / (2 * n)
    orb = ss.periodic_orbit(dh.model(beta, 0.05))
    assert orb.amplitude[0] == pytest.approx(1.0 / (1.0 - beta ** 2), rel=1e-9)
    assert np.sort(np.abs(orb.multipliers)) == pytest.approx([0.0, 1.0], abs=1e-4)
