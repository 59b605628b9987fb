"""Set-valued friction under method="moreau" and method="event_driven" against closed forms:
the box held on the slope, the box sliding to a stop, and the belt's Coulomb stick-slip cycle
(for several parameter sets, not only the paper's); moreau's observed order; events; bad input."""
from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pytest

import stickslip as ss

TIGHT = {"rtol": 1e-12, "atol": 1e-14}


def belt_cycle(t: np.ndarray, *, m: float, k: float, v_b: float, mu_s: float, mu_k: float,
               g: float = 9.81) -> tuple[np.ndarray, dict[str, float]]:
    """x(t) of the belt started stuck (x = 0, v = v_b) with set-valued Coulomb friction, and
    the cycle's constants: stuck until the spring reaches mu_s m g, then a slip arc of the
    oscillator about x_k = mu_k m g / k with amplitude A until v = v_b again at x_k - d
    (d = (mu_s - mu_k) m g / k), then stuck again; period (pi + 2 phi)/w + 2 d / v_b."""
    w = math.sqrt(k / m)
    x_k = mu_k * m * g / k
    d = (mu_s - mu_k) * m * g / k
    amp = math.hypot(d, v_b / w)
    phi = math.asin(v_b / (amp * w))
    t1 = (mu_s * m * g / k) / v_b
    t_slip = (math.pi + 2 * phi) / w
    period = t_slip + 2 * d / v_b
    tau = np.mod(t - t1, period)
    x = np.where(tau < t_slip, x_k + amp * np.cos(w * tau - phi), x_k - d + v_b * (tau - t_slip))
    x = np.where(t < t1, v_b * t, x)
    return x, {"x_k": x_k, "A": amp, "period": period, "t1": t1, "t_slip": t_slip, "d": d}


BELT_SETS = [
    {"m": 2.0, "k": 500.0, "v_b": 0.3, "mu_s": 0.6, "mu_k": 0.4},
    {"m": 1.0, "k": 50.0, "v_b": 0.8, "mu_s": 0.5, "mu_k": 0.2},
    {"m": 5.0, "k": 2000.0, "v_b": 0.1, "mu_s": 0.3, "mu_k": 0.29},
]


@pytest.mark.parametrize("method, controls", [("moreau", {"h": 1e-2}), ("event_driven", {})])
def test_slope_below_the_friction_angle_holds_exactly(method, controls):
    r = ss.simulate("slope", "coulomb", method=method, t_end=20, **controls)
    assert np.all(r.x == 0.0) and np.all(r.v == 0.0)
    r = ss.simulate("slope", "stribeck", method=method, t_end=20, theta_deg=15, mu_s=0.3, **controls)
    assert np.all(r.x == 0.0) and np.all(r.v == 0.0)


def _stop(theta_deg: float, mu_k: float, v0: float, g: float = 9.81) -> tuple[float, float]:
    th = math.radians(theta_deg)
    a = g * (mu_k * math.cos(th) - math.sin(th))
    return v0 / a, v0 ** 2 / (2 * a)


@pytest.mark.parametrize("theta_deg, mu_s, mu_k, v0", [(10.0, 0.35, 0.30, 2.0), (25.0, 0.7, 0.6, 0.7),
                                                     (-5.0, 0.2, 0.15, 1.3)])
def test_slope_slides_to_a_stop(theta_deg, mu_s, mu_k, v0):
    t_stop, x_stop = _stop(theta_deg, mu_k, v0)
    p = {"theta_deg": theta_deg, "mu_s": mu_s, "mu_k": mu_k}
    t_end = 1.5 * t_stop
    r = ss.simulate("slope", "coulomb", method="event_driven", t_end=t_end, v0=v0, **p, **TIGHT)
    assert r.stats["nevents"] == 1 and r.events["kind"][0] == "stick"
    assert abs(r.events["t"][0] - t_stop) <= 1e-13 * t_stop
    assert abs(r.events["x"][0] - x_stop) <= 1e-13 * x_stop
    assert abs(r.x[-1] - x_stop) <= 1e-13 * x_stop and r.v[-1] == 0.0
    # moreau: the stop falls inside a step; the position error is O(h) and the box then holds
    for h in (1e-2, 1e-3):
        r = ss.simulate("slope", "coulomb", method="moreau", h=h, t_end=t_end, v0=v0, **p)
        assert abs(r.x[-1] - x_stop) <= v0 * h
        stopped = r.t > t_stop + h
        assert np.all(r.v[stopped] == 0.0) and np.all(r.x[stopped] == r.x[-1])


@pytest.mark.parametrize("p", BELT_SETS)
def test_event_driven_belt_matches_the_closed_form_cycle(p):
    t_end = 6.0
    r = ss.simulate("belt", "coulomb", method="event_driven", t_end=t_end, v0=p["v_b"], n_out=3001, **p,
                    **TIGHT)
    x, c = belt_cycle(r.t, **p)
    assert np.max(np.abs(r.x - x)) < 1e-9
    ev = r.events
    assert len(ev) >= 4 and set(ev["kind"]) == {"slip", "stick"}
    assert np.all(ev["kind"][::2] == "slip") and np.all(ev["kind"][1::2] == "stick")
    slips = ev["t"][ev["kind"] == "slip"]
    assert np.max(np.abs(np.diff(slips) - c["period"])) < 1e-11
    assert np.max(np.abs(ev["x"][ev["kind"] == "slip"] - p["mu_s"] * p["m"] * 9.81 / p["k"])) < 1e-12
    assert np.max(np.abs(ev["x"][ev["kind"] == "stick"] - (c["x_k"] - c["d"]))) < 1e-9
    # stick is exact: between a stick event and the next slip the body moves with the belt
    for t_on, t_off in zip(ev["t"][1::2], ev["t"][2::2]):
        inside = (r.t > t_on) & (r.t < t_off)
        assert np.all(np.abs(r.v[inside] - p["v_b"]) <= 4 * np.finfo(float).eps * p["v_b"])


@pytest.mark.parametrize("p", BELT_SETS[:2])
def test_moreau_belt_cycle_and_exact_stick(p):
    r = ss.simulate("belt", "coulomb", method="moreau", h=1e-4, t_end=4.0, v0=p["v_b"], n_out=4001, **p)
    x, c = belt_cycle(r.t, **p)
    assert np.max(np.abs(r.x - x)) < 20 * p["v_b"] * 1e-4
    assert abs(r.x.max() - (c["x_k"] + c["A"])) < 1e-3 * c["A"]
    held = np.abs(r.v - p["v_b"]) < 1e-6
    assert held.sum() > 100 and np.all(r.v[held] == p["v_b"])


def test_moreau_observed_order_in_position():
    """First order in position through the stick-slip transitions, on a grid of the steps."""
    p = BELT_SETS[1]
    errs = []
    hs = [4e-3, 2e-3, 1e-3, 5e-4]
    for h in hs:
        r = ss.simulate("belt", "coulomb", method="moreau", h=h, t_end=4.0, v0=p["v_b"], n_out=401, **p)
        errs.append(np.max(np.abs(r.x - belt_cycle(r.t, **p)[0])))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(errs[-1] < np.array(errs[:-1]))
    assert 0.8 < np.mean(orders) < 1.5, (errs, orders)


@pytest.mark.parametrize("p", [{"m": 10.0, "k": 300.0, "v_b": 1.5, "mu_s": 0.35, "mu_k": 0.30}] + BELT_SETS[:2])
def test_moreau_theta_one_damps_the_slip_arc_more_than_the_default(p):
    """theta = 1/2 (default) keeps the slip oscillation's amplitude; theta = 1 shrinks it."""
    err = {}
    for theta in (0.5, 1.0):
        r = ss.simulate("belt", "coulomb", method="moreau", h=1e-3, t_end=4.0, v0=p["v_b"], theta=theta,
                        n_out=4001, **p)
        c = belt_cycle(r.t, **p)[1]
        err[theta] = abs(r.x.max() - (c["x_k"] + c["A"]))
    assert err[0.5] < 0.5 * err[1.0], err


def test_stribeck_moreau_converges_to_event_driven():
    p = {"v_b": 0.4, "c_v": 0.02, "mu_s": 0.5, "mu_k": 0.3, "v_s": 0.05}
    ref = ss.simulate("belt", "stribeck", method="event_driven", t_end=3.0, v0=0.4, n_out=301, **p, **TIGHT)
    assert ref.stats["nevents"] >= 2
    errs = [np.max(np.abs(ss.simulate("belt", "stribeck", method="moreau", h=h, t_end=3.0, v0=0.4,
                                      n_out=301, **p).x - ref.x)) for h in (2e-3, 5e-4)]
    assert errs[1] < 0.5 * errs[0] and errs[1] < 1e-3


def test_event_budget_and_accumulation_are_distinct_named_errors():
    p = BELT_SETS[0]
    with pytest.raises(ss.EventBudgetExhausted) as e:
        ss.simulate("belt", "coulomb", method="event_driven", t_end=6.0, v0=p["v_b"], max_events=3, **p)
    assert len(e.value.result.events) == 3 and "max_events" in str(e.value)
    assert not isinstance(e.value, ss.EventAccumulation)
    with pytest.raises(ss.EventAccumulation) as e:
        ss.simulate("belt", "coulomb", method="event_driven", t_end=30.0, v0=p["v_b"], zeno_gap=100.0, **p)


@pytest.mark.parametrize("kwargs, words", [
    ({"method": "moreau", "h": 1e-2, "theta": 0.3}, ["theta", "[0.5, 1]"]),
    ({"method": "moreau", "h": 1e-2, "theta": 1.2}, ["theta", "[0.5, 1]"]),
    ({"method": "moreau", "h": 0.0}, ["h", "> 0"]),
    ({"method": "moreau", "h": -1e-3}, ["h", "> 0"]),
    ({"method": "moreau", "h": 1e-2, "contact_tol": 0.0}, ["contact_tol", "> 0"]),
    ({"method": "moreau", "h": 1e-2, "contact_max_iter": 0}, ["contact_max_iter", ">= 1"]),
    ({"method": "moreau", "h": 1e-2, "contact_max_iter": 2.7}, ["contact_max_iter", "integer"]),
    ({"method": "event_driven", "max_events": 2.5}, ["max_events", "integer"]),
    ({"method": "event_driven", "max_events": 0}, ["max_events", ">= 1"]),
    ({"method": "event_driven", "zeno_gap": -1.0}, ["zeno_gap", ">= 0"]),
])
def test_bad_controls_name_the_parameter_and_range(kwargs, words):
    with pytest.raises(ValueError) as e:
        ss.simulate("slope", "coulomb", t_end=1.0, **kwargs)
    assert all(w in str(e.value) for w in words), str(e.value)


@pytest.mark.parametrize("law", [law for law in ss.LAWS if law not in ("coulomb", "stribeck", "karnopp")])
@pytest.mark.parametrize("method, controls", [("moreau", {"h": 1e-2}), ("event_driven", {})])
def test_other_laws_are_refused_before_running(law, method, controls):
    assert ss.REGISTRY["method"][method]["laws"] == ("coulomb", "stribeck", "karnopp")
    with pytest.raises(ValueError, match="coulomb, stribeck, karnopp"):
        ss.simulate("belt", law, method=method, t_end=1.0, **controls)


def test_stick_best_runs_picks_the_smallest_error():
    """The summary figure's cell: the smallest error over the settings (ties: the cheaper run), a
    failure only where no setting finished."""
    from cases.stick import best_runs

    def row(law, method, err, cpu, status="ok"):
        return {"problem [-]": "slope_rest", "law [-]": law, "method [-]": method, "err_x [m]": err,
                "cpu [s]": cpu, "status [-]": status}
    rows = [row("coulomb", "rk4", "0.2", "0.001"), row("coulomb", "rk4", "0.002", "0.01"),
            row("coulomb", "rk4", "", "", "NewtonFailure"), row("coulomb", "rk4", "0.002", "0.005"),
            row("lugre", "rk4", "", "", "NonFiniteSolution"), row("lugre", "moreau", "", "", "refused"),
            row("coulomb", "moreau", "0", "0.02"), row("coulomb", "moreau", "1e-3", "0.001"),
            {**row("coulomb", "rk4", "1e-9", "0.1"), "problem [-]": "slope_stop"}]
    best = best_runs(rows, "slope_rest")
    assert best["coulomb", "rk4"]["err_x [m]"] == "0.002" and best["coulomb", "rk4"]["cpu [s]"] == "0.005"
    assert best["coulomb", "moreau"]["err_x [m]"] == "0"
    assert best["lugre", "rk4"]["status [-]"] == "NonFiniteSolution"
    assert best["lugre", "moreau"]["status [-]"] == "refused"
    assert set(best) == {("coulomb", "rk4"), ("lugre", "rk4"), ("lugre", "moreau"), ("coulomb", "moreau")}


def test_stick_best_table_names_the_best_method_per_law(tmp_path):
    """stick_best.md: one row per law and problem, the method with the smallest error (ties: the
    cheaper), and the methods exact at some setting; a law with no finished run says so."""
    from cases import stick
    from cases._common import write_csv
    rows = []
    for problem, errs in stick.ERRORS.items():
        for law, method, err, cpu, status in (("coulomb", "rk4", "0.2", "0.001", "ok"),
                                               ("coulomb", "moreau", "0", "0.02", "ok"),
                                               ("coulomb", "event_driven", "0", "0.01", "ok"),
                                               ("lugre", "rk4", "", "", "NonFiniteSolution")):
            r = {h: "" for h in stick.HEADER}
            r.update({"problem [-]": problem, "law [-]": law, "method [-]": method, "h [s]": "0.001",
                      "cpu [s]": cpu, "status [-]": status, errs[0]: err})
            rows.append([r[h] for h in stick.HEADER])
    csv = write_csv(tmp_path / "stick.csv", stick.HEADER, rows)
    text = stick.write_best(csv, tmp_path).read_text()
    assert text.count("| Coulomb | event-driven (set-valued) |") == 3     # exact and cheaper than moreau
    assert "Moreau-Jean (set-valued), event-driven (set-valued)" in text or \
        "event-driven (set-valued), Moreau-Jean (set-valued)" in text
    assert text.count("| LuGre | none finished |") == 3


def test_stick_study_quick(tmp_path):
    """python -m cases.stick --quick writes the CSV, the tables and the figure; the set-valued
    methods hold the slope exactly and a creeping law does not."""
    from cases import stick
    from cases._common import read_csv
    files = stick.main(["--outdir", str(tmp_path), "--quick", "--threads", "1", "--quiet"])
    # --quick writes into its own subdirectory, beside the run's provenance record
    assert {f.name for f in files} == {"stick.csv", "stick.md", "stick_best.md", "stick.png", "stick.pdf", "stick_best.png",
                                       "stick_best.pdf", "cases.stick.provenance.json"}
    out = files[0].parent
    assert out == tmp_path / "quick" and all(f.parent == out for f in files)
    cols = read_csv(out / "stick.csv")
    rows = [dict(zip(cols, v)) for v in zip(*cols.values())]
    rest = {(r["law [-]"], r["method [-]"]): r for r in rows if r["problem [-]"] == "slope_rest"}
    for law in ("coulomb", "stribeck"):
        for method in ("moreau", "event_driven"):
            assert float(rest[law, method]["err_x [m]"]) == 0.0
    assert float(rest["recurdyn", "rk4"]["err_x [m]"]) > 1e-3        # RecurDyn creeps
    assert rest["lugre", "moreau"]["status [-]"] == "refused"
    belt = {(r["law [-]"], r["method [-]"]): r for r in rows if r["problem [-]"] == "belt_stuck"}
    assert float(belt["coulomb", "event_driven"]["err_path [m]"]) < 1e-4
    assert "## (c)" in (out / "stick.md").read_text()


# --- moreau on a chain: the contact solver's rule on W itself, against the rule written here -------
def _box(dmat, q, bound):
    """The box problem w = q + D p, -b <= p <= b, each w_i = 0 inside or of the sign that pushes
    p_i to its bound (w_i <= 0 at +b, >= 0 at -b), by exhaustive search over the 3^n sets."""
    n = len(q)
    for sets in itertools.product((0, 1, -1), repeat=n):
        p = np.zeros(n)
        free = [i for i in range(n) if sets[i] == 0]
        for i in range(n):
            if sets[i]:
                p[i] = sets[i] * bound[i]
        if free:
            rest = [i for i in range(n) if sets[i]]
            p[free] = np.linalg.solve(dmat[np.ix_(free, free)], -(q[free] + dmat[np.ix_(free, rest)] @ p[rest]))
        w = q + dmat @ p
        tol = 1e-11 * (1.0 + np.max(np.abs(q)))
        if all(abs(p[i]) <= bound[i] * (1 + 1e-12) if sets[i] == 0 else sets[i] * w[i] <= tol for i in range(n)):
            w[free] = 0.0
            return w
    raise AssertionError("no box solution")


def _rule(dmat, wf, cap, mu_s, mu_k, prev):
    """The rule of docs/guide/exact-stick.md (set-valued Coulomb), written out: keep a slip
    whose free velocity still drives it past its static limit, else static first, rounds of
    box problems until no contact changes level."""
    n = len(wf)
    dg = np.diag(dmat)
    kin = [abs(prev[i]) == 1 and prev[i] * wf[i] > dg[i] * mu_s[i] * cap[i] * (1 + 1e-12) for i in range(n)]
    direction = [prev[i] if kin[i] else 0 for i in range(n)]
    reset = [False] * n
    mu = np.where(kin, mu_k, mu_s)
    for _ in range(3 * n + 30):
        w = _box(dmat, wf, cap * mu)
        changed, mu_new = False, mu.copy()
        for j in range(n):
            if w[j] == 0.0:
                continue
            s = int(np.sign(w[j]))
            if not kin[j]:
                kin[j], direction[j], changed = True, s, True
            elif s != direction[j]:
                if not reset[j]:
                    kin[j], reset[j], direction[j], changed = False, True, 0, True
                    mu_new[j] = mu_s[j]
                    continue
                direction[j] = s
            mu_new[j] = mu_k[j]
        if not changed and np.all(mu_new == mu):
            return w
        mu = mu_new
    raise AssertionError("rounds did not settle")


#: (h, k_c, mu_s, mu_k, masses): a chain with stick-slip at h = 1 ms, and one at h = 20 ms with
#: stiff couplings where a step has several solutions (the former plain sweeps took another one);
#: one block alone (the rule's one-contact closed form, `one_coordinate_rule`).
RULE_CHAINS = [
    (1e-3, 30.0, [0.5, 0.45, 0.6], [0.3, 0.3, 0.25], [1.0, 0.7, 1.3]),
    (2e-2, 3000.0, [0.72, 0.803, 0.882], [0.281, 0.473, 0.738], [1.134, 1.384, 0.537]),
    (1e-3, 0.0, [0.5], [0.3], [1.0]),
]


@pytest.mark.parametrize("h, kc, mu_s, mu_k, masses", RULE_CHAINS)
def test_moreau_chain_follows_the_rule_step_by_step(h, kc, mu_s, mu_k, masses):
    """Blocks on a belt joined by springs (W tridiagonal, one contact on each block: the
    contact solver's `tridiagonal_rule`; one block: its one-contact closed form), mu_s > mu_k:
    every step's relative velocities equal those of the rule written out above on the step's
    own problem (Delassus matrix formed here, box problems by exhaustive search)."""
    v_b, g, k, th = 0.3, 9.81, 50.0, 0.5
    mu_s, mu_k, masses = np.array(mu_s), np.array(mu_k), np.array(masses)
    n = len(masses)
    model = ss.Model()
    bodies = [model.add_body(mi) for mi in masses]
    model.add_spring(bodies[0], None, k=k)
    for i in range(n - 1):
        model.add_spring(bodies[i], bodies[i + 1], k=kc)
    for bi, mi, ms, mk in zip(bodies, masses, mu_s, mu_k):
        model.add_contact(bi, None, "coulomb", normal_force=mi * g, surface_velocity=v_b, mu_s=ms, mu_k=mk)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = ss.simulate(model, method="moreau", h=h, t_end=3.0, every_step=True)
    kmat = np.zeros((n, n))
    kmat[0, 0] = k
    for i in range(n - 1):
        kmat[i:i + 2, i:i + 2] += kc * np.array([[1.0, -1.0], [-1.0, 1.0]])
    w_mat = np.diag(masses) + (h * th) ** 2 * kmat
    winv = np.linalg.inv(w_mat)
    cap = h * masses * g
    q, u = r.x, r.v
    prev = [0 if w == 0.0 else int(np.sign(w)) for w in u[:, 0] - v_b]
    slips = 0
    for s in range(q.shape[1] - 1):
        f0, f1 = -kmat @ q[:, s], -kmat @ (q[:, s] + h * u[:, s])
        uf = u[:, s] + winv @ (h * ((1 - th) * f0 + th * f1))
        w_rule = _rule(winv, uf - v_b, cap, mu_s, mu_k, prev)
        w = u[:, s + 1] - v_b
        np.testing.assert_allclose(w, w_rule, atol=1e-9, err_msg=f"step {s}")
        prev = [0 if x == 0.0 else int(np.sign(x)) for x in w]
        slips += any(x != 0.0 for x in w)
    assert slips > 0
