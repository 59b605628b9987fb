"""The chain scene (issue 23): N blocks on the belt coupled by springs.

Checked against: the belt scene (N = 1, bit for bit, every method), an independent Python
statement of the chain's equations integrated by scipy (N = 3; N = 4 with loading springs
k_p), the one-block chain with k_p as the belt with k + k_p (bit for bit), the banded and dense
linear algebra of the implicit methods (same steps), Moreau's solver residual on 1,000 blocks,
the energy balance of a Coulomb chain (with and without k_p), and bad input.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import stickslip as ss

CONTROLS = {"rk4": dict(h=1e-3), "dopri5": {}, "radau5": {}, "implicit_euler": dict(h=1e-3),
            "galpha": dict(h=1e-3), "moreau": dict(h=1e-3), "event_driven": {}}
SETVALUED = ("moreau", "event_driven")


def _run(scene: str, law: str, method: str, **kw) -> ss.Result:
    """A run, or the partial result of a run that ended early (the belt fails the same way)."""
    try:
        return ss.simulate(scene, law, method=method, **kw)
    except ss.IntegrationError as e:
        return e.result


@pytest.mark.parametrize("method", list(CONTROLS))
@pytest.mark.parametrize("law", ["coulomb", "stribeck", "proposed", "lugre"])
def test_one_block_is_the_belt_bit_for_bit(law, method):
    if method in SETVALUED and law not in ("coulomb", "stribeck"):
        pytest.skip("the set-valued methods take coulomb and stribeck only")
    kw = dict(t_end=4.0, n_out=161, x0=0.01, v0=0.2, **CONTROLS[method])
    a = _run("belt", law, method, **kw)
    b = _run("chain", law, method, n_blocks=1, k_c=1234.0, perturbation=0.3, **kw)
    assert a.x.shape == b.x.shape
    np.testing.assert_array_equal(b.x, a.x)
    np.testing.assert_array_equal(b.v, a.v)
    np.testing.assert_array_equal(b.z, a.z)
    np.testing.assert_array_equal(b.t, a.t)
    for key in ("nfev", "nstep", "naccept", "nreject", "njac", "ndec", "nsol", "nevents", "status"):
        assert b.stats[key] == a.stats[key], key


def _chain_rhs(n, m, g, k, kc, v_b, pert, law, params, kp=0.0):
    """The chain's equations as the issue states them, written independently of the library
    (the friction coefficient comes from ss.friction_coefficient)."""
    phi = (np.sqrt(5.0) - 1.0) / 2.0
    r = 2.0 * np.mod(0.5 + np.arange(n) * phi, 1.0) - 1.0
    normal = m * g * (1.0 + pert * r)

    def rhs(t, y):
        x, v = y[:n], y[n:]
        force = np.zeros(n)
        force[0] -= k * x[0]
        force[1:] -= kc * (x[1:] - x[:-1])
        force[:-1] -= kc * (x[:-1] - x[1:])
        force -= kp * x
        mu = ss.friction_coefficient(law, v_b - v, **params)
        return np.concatenate([v, (force + mu * normal) / m])
    return rhs


@pytest.mark.slow     # scipy's DOP853 at rtol 1e-11 on the proposed law's steep slope: minutes
def test_three_blocks_match_an_independent_statement_of_the_equations():
    """Slow (CI): the default run compares the chain with the same independent statement of its
    equations (_chain_rhs, scipy DOP853) in
    test_loading_springs_match_an_independent_statement_of_the_equations (four blocks, stribeck,
    k_p, DOPRI5 and RADAU5)."""
    n, m, g, k, kc, v_b, pert = 3, 2.0, 9.81, 300.0, 150.0, 0.4, 0.2
    params = dict(mu_s=0.4, mu_k=0.3, v_s=0.05)
    x0 = np.array([0.01, -0.02, 0.0])
    v0 = np.array([0.0, 0.1, 0.3])
    r = ss.simulate("chain", "proposed", method="dopri5", t_end=3.0, n_out=31, n_blocks=n, m=m, g=g, k=k,
                    k_c=kc, v_b=v_b, perturbation=pert, x0=x0, v0=v0, rtol=1e-10, atol=1e-12, **params)
    ref = solve_ivp(_chain_rhs(n, m, g, k, kc, v_b, pert, "proposed", params), (0.0, 3.0),
                    np.concatenate([x0, v0]), method="DOP853", t_eval=r.t, rtol=1e-11, atol=1e-13)
    assert r.x.shape == (n, 31)
    np.testing.assert_allclose(r.x, ref.y[:n], atol=2e-7)
    np.testing.assert_allclose(r.v, ref.y[n:], atol=2e-6)


def test_loading_springs_match_an_independent_statement_of_the_equations():
    n, m, g, k, kc, kp, v_b, pert = 4, 2.0, 9.81, 300.0, 150.0, 40.0, 0.4, 0.2
    params = dict(mu_s=0.4, mu_k=0.3, v_s=0.05)
    x0 = np.array([0.01, -0.02, 0.0, 0.03])
    v0 = np.array([0.0, 0.1, 0.3, 0.2])
    kw = dict(t_end=3.0, n_out=31, n_blocks=n, m=m, g=g, k=k, k_c=kc, k_p=kp, v_b=v_b, perturbation=pert,
              x0=x0, v0=v0, **params)
    ref = solve_ivp(_chain_rhs(n, m, g, k, kc, v_b, pert, "stribeck", params, kp), (0.0, 3.0),
                    np.concatenate([x0, v0]), method="DOP853", t_eval=np.linspace(0.0, 3.0, 31),
                    rtol=1e-11, atol=1e-13)
    r = ss.simulate("chain", "stribeck", method="dopri5", rtol=1e-10, atol=1e-12, **kw)
    np.testing.assert_allclose(r.x, ref.y[:n], atol=2e-7)
    np.testing.assert_allclose(r.v, ref.y[n:], atol=2e-6)
    # RADAU5 with the analytic band Jacobian, which carries k_p on its diagonal
    r = ss.simulate("chain", "stribeck", method="radau5", rtol=1e-9, atol=1e-12, **kw)
    np.testing.assert_allclose(r.x, ref.y[:n], atol=2e-6)
    # without k_p the motion differs by far more than these tolerances
    r0 = ss.simulate("chain", "stribeck", method="dopri5", rtol=1e-10, atol=1e-12, **(kw | {"k_p": 0.0}))
    assert np.abs(r0.x - ref.y[:n]).max() > 1e-3


@pytest.mark.parametrize("method", list(CONTROLS))
def test_one_block_with_loading_spring_is_the_belt_with_k_plus_k_p(method):
    law = "coulomb" if method in SETVALUED else "stribeck"
    kw = dict(t_end=4.0, n_out=161, x0=0.01, v0=0.2, **CONTROLS[method])
    a = _run("belt", law, method, k=300.0 + 125.0, **kw)
    b = _run("chain", law, method, n_blocks=1, k_p=125.0, **kw)
    np.testing.assert_array_equal(b.x, a.x)
    np.testing.assert_array_equal(b.v, a.v)
    assert b.stats["nfev"] == a.stats["nfev"] and b.stats["nstep"] == a.stats["nstep"]


def test_default_start_is_stuck_on_the_belt_at_rest_length():
    r = ss.simulate("chain", "coulomb", method="moreau", h=1e-3, t_end=0.01, n_out=2, n_blocks=4, v_b=0.3)
    np.testing.assert_array_equal(r.x[:, 0], 0.0)
    np.testing.assert_array_equal(r.v[:, 0], 0.3)
    # blocks 2..4 feel no spring yet: they ride the belt exactly
    np.testing.assert_array_equal(r.v[1:, 1], 0.3)


def test_law_states_block_by_block():
    z0 = np.array([1e-4, 2e-4, 3e-4])
    r = ss.simulate("chain", "lugre", method="radau5", t_end=0.01, n_out=2, n_blocks=3, z0=z0)
    np.testing.assert_array_equal(r.z[:, 0], z0)
    r1 = ss.simulate("chain", "lugre", method="radau5", t_end=0.01, n_out=2, n_blocks=3, z0=[5e-5])
    np.testing.assert_array_equal(r1.z[:, 0], 5e-5)


@pytest.mark.parametrize("bad", [0, -3, 1.5, 2_000_000, float("nan")])
def test_bad_n_blocks(bad):
    with pytest.raises(ValueError, match="n_blocks"):
        ss.simulate("chain", "coulomb", method="rk4", h=1e-3, t_end=1.0, n_blocks=bad)


def test_output_too_large_names_n_blocks():
    with pytest.raises(ValueError, match="n_blocks.*GB"):
        ss.simulate("chain", "coulomb", method="moreau", h=1e-3, t_end=1.0, n_blocks=1_000_000, n_out=200)


@pytest.mark.parametrize("method", ["implicit_euler", "galpha", "radau5"])
def test_dense_path_refuses_a_huge_chain_before_running(method):
    kw = dict(h=1e-3) if method != "radau5" else {}
    with pytest.raises(ValueError, match="n_blocks.*dense"):
        ss.simulate("chain", "coulomb", method=method, t_end=1.0, n_blocks=100_000, n_out=2, banded=False, **kw)


def test_bad_k_c_k_p_and_perturbation():
    with pytest.raises(ValueError, match="k_c"):
        ss.simulate("chain", "coulomb", method="rk4", h=1e-3, t_end=1.0, n_blocks=2, k_c=-1.0)
    with pytest.raises(ValueError, match=r"k_p: must be finite and >= 0 \[N/m\]"):
        ss.simulate("chain", "coulomb", method="moreau", h=1e-3, t_end=1.0, n_blocks=2, k_p=-5.0)
    with pytest.raises(ValueError, match="perturbation"):
        ss.simulate("chain", "coulomb", method="rk4", h=1e-3, t_end=1.0, n_blocks=2, perturbation=0.9)


def test_x0_array_must_have_one_value_per_block():
    with pytest.raises(ValueError, match="x0"):
        ss.simulate("chain", "coulomb", method="rk4", h=1e-3, t_end=1.0, n_blocks=3, x0=[0.0, 1.0])


@pytest.mark.parametrize("method", ["radau5", "implicit_euler", "galpha"])
@pytest.mark.parametrize("law", ["stribeck", "recurdyn"])
@pytest.mark.parametrize("n_blocks, kp", [(2, 0.0), (5, 0.0), (12, 0.0), (5, 30.0), (12, 30.0)])
def test_banded_and_dense_take_the_same_steps(method, law, n_blocks, kp):
    # Static laws: both paths use the analytic Jacobian, so only the linear algebra differs
    # (band LU in block order against dense LU in state order): same steps, states to rounding.
    kw = dict(t_end=3.0, n_out=31, n_blocks=n_blocks, perturbation=0.2, k_p=kp)
    # hmax = 1e-2 s: with the default hmax = 0 (the whole run) RADAU5's step and Jacobian
    # decisions come close enough to their thresholds that the rounding of the two
    # factorizations flips one (n_blocks = 5, stribeck: 1376 against 1373 evaluations, states
    # 3.6e-7 apart, within rtol), and "same steps" would no longer be a test of the algebra.
    kw.update(dict(rtol=1e-6, hmax=1e-2) if method == "radau5" else dict(h=2e-3))
    band = ss.simulate("chain", law, method=method, banded=True, **kw)
    dense = ss.simulate("chain", law, method=method, banded=False, **kw)
    for key in ("nfev", "nstep", "naccept", "nreject", "njac", "ndec", "nsol"):
        assert band.stats[key] == dense.stats[key], key
    assert band.stats["nstep"] > 100
    # Rounding (1e-16 a solve) carried through ~300 steps of a motion of order 1 m, and for
    # RADAU5 also through its Newton iteration, which stops once a correction is below a
    # fraction of the local tolerance (rtol = 1e-6): the two factorizations' rounding can
    # move the accepted iterate by more than rounding. Measured: fixed-step methods below
    # 1e-11 m; RADAU5 9.0e-10 m and 6.6e-9 m/s at most (recurdyn, N = 5, k_p = 30).
    tol = (1e-8, 1e-7) if method == "radau5" else (1e-10, 1e-9)
    np.testing.assert_allclose(band.x, dense.x, rtol=0, atol=tol[0])
    np.testing.assert_allclose(band.v, dense.v, rtol=0, atol=tol[1])


def test_radau5_banded_with_law_states_agrees_with_dense():
    # LuGre: the banded Jacobian comes from grouped differences (2 s + 1 evaluations instead of
    # n), so evaluation counts differ by design; the motion agrees to the tolerance.
    kw = dict(t_end=2.0, n_out=21, n_blocks=6, rtol=1e-8, atol=1e-11)
    band = ss.simulate("chain", "lugre", method="radau5", banded=True, **kw)
    dense = ss.simulate("chain", "lugre", method="radau5", banded=False, **kw)
    np.testing.assert_allclose(band.x, dense.x, rtol=0, atol=1e-7)


def test_moreau_solver_converges_on_a_thousand_blocks():
    r = ss.simulate("chain", "coulomb", method="moreau", h=1e-3, n_blocks=1000, t_end=1.0, n_out=11,
                    contact_tol=1e-12)
    assert r.stats["contact_residual"] <= 1e-12
    assert r.stats["ncontact_iter"] >= r.stats["nstep"] == 1000
    assert r.x.shape == (1000, 11)
    # stuck blocks ride the belt exactly: in 1 s the slip started at block 1 (when k x_1 =
    # mu_s m g) has not reached block 20
    np.testing.assert_array_equal(r.v[20:, :], r.params["v_b"])
    assert (r.v[0] != r.params["v_b"]).any()


def test_moreau_failed_solve_is_reported():
    with pytest.raises(ss.ContactSolverFailure):
        ss.simulate("chain", "coulomb", method="moreau", h=1e-2, n_blocks=2001, t_end=5.0, v_b=0.2,
                    x0=np.linspace(0.0, 0.05, 2001), contact_max_iter=1, contact_tol=1e-15)


CHAIN4 = dict(n_blocks=4, t_end=5.0, n_out=501, v_b=0.2, perturbation=0.1, x0=[0.0, 0.01, -0.01, 0.02])


def test_event_driven_cascades_through_the_chain():
    e = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-10, atol=1e-12, **CHAIN4)
    # slip starts at block 1 (pulled by the wall) and reaches the others through the springs
    assert e.events["contact"][0] == 0 and e.events["kind"][0] == "slip"
    assert set(e.events["contact"]) >= {0, 1, 2}
    assert {"slip", "stick"} <= set(e.events["kind"])


def test_moreau_converges_to_event_driven_at_first_order_on_a_chain():
    e = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-10, atol=1e-12, **CHAIN4)
    errs = [np.abs(ss.simulate("chain", "coulomb", method="moreau", h=h, **CHAIN4).x - e.x).max()
            for h in (1e-3, 1e-4)]
    assert errs[0] < 2e-4
    assert 5.0 < errs[0] / errs[1] < 20.0     # first order: about 10 for a tenfold step


@pytest.mark.parametrize("kp", [0.0, 80.0])
@pytest.mark.parametrize("method", ["moreau", "event_driven"])
def test_energy_balance_of_a_coulomb_chain(method, kp):
    """Work of the belt = change of spring and kinetic energy + heat, each from its own
    formula: the belt's work v_b * (friction impulse), the impulse from the momentum balance
    (m sum dv_i + k int x_1 dt + k_p sum int x_i dt: the coupling springs cancel in the sum),
    the heat from the law (mu_k m g_i |v_b - v_i| while slipping)."""
    n, m, g, k, kc, v_b, mu_k, pert = 5, 2.0, 9.81, 300.0, 200.0, 0.3, 0.3, 0.2
    kw = dict(n_blocks=n, m=m, g=g, k=k, k_c=kc, k_p=kp, v_b=v_b, mu_k=mu_k, perturbation=pert, t_end=4.0,
              x0=[0.0, 0.01, 0.0, -0.01, 0.02])
    if method == "moreau":
        r = ss.simulate("chain", "coulomb", method="moreau", h=2e-5, n_out=200001, **kw)
    else:
        r = ss.simulate("chain", "coulomb", method="event_driven", rtol=1e-11, atol=1e-13, n_out=200001, **kw)
    x, v, t = r.x, r.v, r.t
    phi = (np.sqrt(5.0) - 1.0) / 2.0
    gi = g * (1.0 + pert * (2.0 * np.mod(0.5 + np.arange(n) * phi, 1.0) - 1.0))

    def energy(j):
        return (0.5 * m * (v[:, j] ** 2).sum() + 0.5 * k * x[0, j] ** 2 + 0.5 * kp * (x[:, j] ** 2).sum()
                + 0.5 * kc * ((x[1:, j] - x[:-1, j]) ** 2).sum())

    slip = np.abs(v_b - v)
    heat = np.trapezoid((mu_k * m * gi[:, None] * slip).sum(axis=0), t)
    impulse = m * (v[:, -1] - v[:, 0]).sum() + k * np.trapezoid(x[0], t) + kp * np.trapezoid(x, t).sum()
    work = v_b * impulse
    d_energy = energy(-1) - energy(0)
    assert heat > 0.05 * abs(work)                          # the balance is not trivial
    # measured: 2.4e-10 (moreau), 3.3e-11 (event_driven) of the work (trapezoidal sums on 2e-5 s)
    assert abs(work - (d_energy + heat)) <= 1e-8 * abs(work)


def test_cases_chain_fits_the_exponent_and_plots_from_the_csv(tmp_path):
    from cases import _common, chain
    n = np.array([1.0, 10.0, 100.0, 300.0, 1000.0])
    assert chain.fit_exponent(n, 2e-7 * n**1.1) == pytest.approx(1.1, abs=1e-12)
    assert np.isnan(chain.fit_exponent(n[:3], n[:3]))          # one point with N >= 100
    rows = [[m, law, int(k), 0.5, "h", 1e-3, 1e-4 if k < 1000 else float("nan"), 1e-3, 0, 100, 400, 0,
             1e-6 * k, 1e-8 * k, 1e-6 * k, float("nan")] for m, law in chain.METHODS.items() for k in n]
    csv = _common.write_csv(tmp_path / "chain.csv", chain.HEADER, rows)
    ev = _common.write_csv(tmp_path / "chain_events.csv", ["event [-]", "size [blocks]", "start [s]"],
                           [[0, 1, 0.0], [1, 3, 1.0], [2, 3, 2.0], [3, 100, 3.0]])
    files = chain.derived(csv, ev, tmp_path)
    assert [f.name for f in files] == ["chain_exponents.md", "chain_events.md", "chain.png", "chain_events.png"]
    assert all(f.stat().st_size > 0 for f in files)
    assert all(f.with_suffix(".pdf").exists() for f in files if f.suffix == ".png")
    assert "| rk4 | 1000 | 1 | 1 |" in files[0].read_text()      # cost 1e-6 N and 1e-8 N


def test_cases_chain_events_summary_counts_by_size_class(tmp_path):
    from cases import _common, chain
    sizes = [1] * 40 + [2] * 10 + [3] * 5 + [7] * 2 + [50] + [100] * 3
    ev = _common.write_csv(tmp_path / "chain_events.csv", ["event [-]", "size [blocks]", "start [s]"],
                           [[k, s, float(k)] for k, s in enumerate(sizes)])
    text = chain.events_summary(ev)
    for row in ("| 1 | 40 |", "| 2-3 | 15 |", "| 4-10 | 2 |", "| 11-99 | 1 |", "| 100 | 3 |", "| all | 61 |"):
        assert row in text, row
    assert "size^-" in text


def test_cases_chain_slip_events_are_connected_pieces():
    from cases import chain
    slipping = np.zeros((6, 8), dtype=bool)      # (blocks, times)
    slipping[0, 1:3] = True                      # block 0 alone: size 1, starts at 1
    slipping[2:5, 4] = True                      # blocks 2-4 at once: size 3, starts at 4
    slipping[4, 5:7] = True                      # ... continued by block 4 in time: same event
    slipping[5, 0] = True                        # block 5 at time 0: size 1
    slipping[1, 6] = True                        # diagonal to nothing: size 1, starts at 6
    sizes, first = chain.slip_events(slipping)
    assert sorted(zip(first.tolist(), sizes.tolist())) == [(0, 1), (1, 1), (4, 3), (6, 1)]


def test_cases_chain_size_fit_recovers_a_known_power_law():
    from cases import chain
    s = np.arange(1, 11)
    sizes = np.repeat(s, np.round(5000.0 * s**-1.5).astype(int))
    b, a = chain.size_fit(np.concatenate([sizes, [100, 100]]))   # events above 10 do not count
    assert b == pytest.approx(1.5, abs=0.01) and a == pytest.approx(5000.0, rel=0.02)
    assert np.isnan(chain.size_fit(np.array([1, 1, 2]))[0])     # two sizes: no fit


def test_cases_chain_ladder_keeps_the_first_setting_confirmed_by_the_next(monkeypatch):
    """at_target keeps the coarsest setting whose error and the next finer one's meet the
    target (a lucky coarse setting followed by a failing one is not kept)."""
    from cases import chain

    class Fake:
        def __init__(self, h):
            self.h = h
            self.stats = dict(status=0, nstep=int(1 / h), nfev=int(4 / h), nevents=0, cpu_seconds=h,
                              t_reached=0.5)
    errors = {1e-2: 5e-3, 5e-3: 5e-4, 2e-3: 2e-3, 1e-3: 8e-4, 5e-4: 4e-4, 2e-4: 1e-4}
    monkeypatch.setattr(chain, "_run", lambda method, law, n, t, **ctl: Fake(ctl["h"]))
    monkeypatch.setattr(chain, "_error", lambda r, ref: errors.get(r.h, 1e-5))
    row = chain.at_target("rk4", 10, chain.QUICK, ref=object(), carried=None)
    assert row[4:7] == ["h", 1e-3, 8e-4]          # 5e-3 passes but 2e-3 does not
    row = chain.at_target("rk4", 10, chain.QUICK, ref=None, carried=5e-4)
    assert row[5] == 5e-4 and np.isnan(row[6])
