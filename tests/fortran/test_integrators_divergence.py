"""Divergence is an error: a run whose state leaves the bound that no motion of the scene can
reach ends with status DIVERGED (DivergedSolution), never with success.

The bound is checked here against this file's own statement of the scenes' energy bounds
(per unit mass, friction |mu| <= mu_max, T = t_end):
- slope: |v| <= V = |v0| + g (|sin theta| + mu_max cos theta) T, |x| <= |x0| + V T;
- belt: sqrt(v^2 + (k/m) x^2) <= R = sqrt(v0^2 + (k/m) x0^2) + g mu_max T (+ v_b), |v| <= R,
  |x| <= R sqrt(m/k);
- chain of N blocks: sqrt(sum v_i^2 + x^T K x) grows by at most sqrt(N) max g_i mu_max a second,
  so |v_i| <= R and |x_i| <= |x0_i| + R T;
with mu_max the larger of mu_s and the law's steady curve at the largest relative speed, and a
law's internal states moving at most twice as fast as the relative speed. A state beyond
MARGIN = 1000 times these has diverged. The fuzz test runs every law x method x scene over
aggressive settings (large steps, loose tolerances, fast starts): each run succeeds inside the
bound, or ends with a named error, or is refused before running."""
from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pytest

import stickslip as ss

MARGIN = 1e3
T_END = 5.0
N_CHAIN = 3
FIXED = {"rk4", "implicit_euler", "galpha", "moreau"}
# (v0 [m/s] or None for the scene's default, fixed step h [s], rtol, h_min [s] of the adaptive
# methods): far beyond what the bristle laws' stiffness allows an explicit step.
SETTINGS = [(None, 1e-2, 1e-2, 1e-3), (20.0, 1e-3, 1e-3, 1e-4), (5.0, 5e-2, 1e-1, 1e-2)]


def _mu_max(law: str, v_ref: float) -> float:
    p = ss.DEFAULTS
    steady = np.abs(ss.friction_coefficient(law, [v_ref, -v_ref]))
    return max(p["mu_s"], p["mu_k"], float(steady.max()))


def energy_bounds(scene: str, law: str, y0: np.ndarray, t_end: float) -> tuple[float, float, float]:
    """(bound on |x| [m], on |v| [m/s], on a law's state) before the margin, from y0."""
    p = ss.DEFAULTS
    g, mu0 = p["g"], max(p["mu_s"], p["mu_k"])
    n = N_CHAIN if scene == "chain" else 1
    x0, v0, z0 = y0[:n], y0[n:2 * n], y0[2 * n:]
    z_start = float(np.max(np.abs(z0))) if z0.size else 0.0
    if scene == "slope":
        th = math.radians(p["theta_deg"])
        gs, gc = g * abs(math.sin(th)), g * math.cos(th)
        a = gs + gc * _mu_max(law, abs(v0[0]) + (gs + gc * mu0) * t_end)
        v_max = abs(v0[0]) + a * t_end
        return abs(x0[0]) + v_max * t_end, v_max, z_start + 2.0 * v_max * t_end
    w2, v_b = p["k"] / p["m"], p["v_b"]
    # the chain's spring matrix per unit mass: eigenvalues below (k + k_p)/m + 4 k_c/m (k_c = k)
    lam = w2 if scene == "belt" else w2 + 4.0 * w2
    r0 = math.sqrt(float(np.sum(v0 ** 2) + lam * np.sum(x0 ** 2)))
    # normal forces per unit mass: g, and g (1 + 0.01 r_i) on the chain (perturbation 1 %)
    a_max = g * (1.0 + p["perturbation"]) * math.sqrt(n)
    r = r0 + a_max * _mu_max(law, v_b + r0 + a_max * mu0 * t_end) * t_end + v_b
    x_max = r / math.sqrt(w2) if scene == "belt" else float(np.max(np.abs(x0))) + r * t_end
    return x_max, r, z_start + 2.0 * (r + v_b) * t_end


def _run(scene, law, method, setting):
    v0, h, rtol, hmin = setting
    kw = {"t_end": T_END, "n_out": 201}
    if scene == "chain":
        kw["n_blocks"] = N_CHAIN
    if v0 is not None:
        kw["v0"] = v0
    if method in FIXED:
        kw["h"] = h
    else:
        kw.update(rtol=rtol, atol=1e-4)
        if method != "event_driven":
            kw["hmin"] = hmin
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ss.UnstableStepWarning)
        return ss.simulate(scene, law, method=method, **kw)


def test_issue_case_diverges():
    """The issue's run: GMS on the belt under RK4 at h = 1e-3 s from the belt's speed reached
    |x| = 2.2e11 m and reported success. Now it ends with DIVERGED, and the output it keeps
    (up to t_reached) lies inside the bound."""
    with pytest.raises(ss.DivergedSolution) as err:
        ss.simulate("belt", "gms", method="rk4", h=1e-3, v0=1.5, t_end=10.0)
    e = err.value
    assert e.status == ss.REGISTRY["status"]["DIVERGED"] == -11
    assert isinstance(e, ss.NonFiniteSolution)       # a blow-up, caught before the overflow
    assert "diverged" in str(e)
    res = e.result
    assert 0.0 < res.stats["t_reached"] < 10.0
    kept = res.t <= res.stats["t_reached"]
    x_max, v_max, z_max = energy_bounds("belt", "gms", res.y[:, 0], 10.0)
    assert np.all(np.isfinite(res.y[:, kept]))
    assert np.max(np.abs(res.x[kept])) <= MARGIN * x_max
    assert np.max(np.abs(res.v[kept])) <= MARGIN * v_max


def test_issue_case_siblings():
    """The same call with LuGre, Dahl and the elasto-plastic law, which raised
    NonFiniteSolution before, now stops earlier with DivergedSolution (still a
    NonFiniteSolution for callers that catch that)."""
    for law in ("lugre", "dahl", "elastoplastic"):
        with pytest.raises(ss.NonFiniteSolution) as err:
            ss.simulate("belt", law, method="rk4", h=1e-3, v0=1.5, t_end=10.0)
        assert type(err.value) is ss.DivergedSolution


def test_every_pair_succeeds_inside_the_bound_or_fails_by_name():
    """Every scene x law x method over the aggressive settings: a success ends with a finite
    state inside MARGIN times the energy bounds at every output row; an error is one of the
    named subclasses (never the bare IntegrationError); and the grid does reach divergence
    (so that the check is exercised), with at least one DivergedSolution on every scene."""
    outcomes = {}
    for scene, law, method, setting in itertools.product(ss.SCENES, ss.LAWS, ss.METHODS, SETTINGS):
        key = (scene, law, method, setting)
        try:
            res = _run(scene, law, method, setting)
        except ValueError:
            outcomes[key] = "refused"
            continue
        except ss.IntegrationError as e:
            assert type(e) is not ss.IntegrationError, (key, str(e))
            outcomes[key] = type(e).__name__
            continue
        outcomes[key] = "ok"
        n = N_CHAIN if scene == "chain" else 1
        x_max, v_max, z_max = energy_bounds(scene, law, res.y[:, 0], T_END)
        assert np.all(np.isfinite(res.y)), key
        assert np.max(np.abs(res.y[:n])) <= MARGIN * x_max, key
        assert np.max(np.abs(res.y[n:2 * n])) <= MARGIN * v_max, key
        if res.y.shape[0] > 2 * n:
            assert np.max(np.abs(res.y[2 * n:])) <= MARGIN * z_max, key
    for scene in ss.SCENES:
        assert any(o == "DivergedSolution" for k, o in outcomes.items() if k[0] == scene), scene
    assert sum(o == "ok" for o in outcomes.values()) > len(outcomes) // 3


@pytest.mark.parametrize("method", ["rk4", "dopri5", "dop853", "radau5", "implicit_euler", "galpha"])
def test_diverged_run_keeps_its_output(method):
    """GMS on the slope from 20 m/s at a large step diverges under every event-free method or
    ends with another named error; when it diverges, the rows before t_reached are finite and
    inside the bound, and the rows after it were never written (NaN-free zeros are not
    reported as motion)."""
    setting = (20.0, 5e-2, 1e-1, 1e-2)
    try:
        res = _run("slope", "gms", method, setting)
    except ss.DivergedSolution as e:
        res = e.result
        kept = res.t <= res.stats["t_reached"]
        x_max, v_max, _ = energy_bounds("slope", "gms", res.y[:, 0], T_END)
        assert np.all(np.isfinite(res.y[:2, kept]))
        assert np.max(np.abs(res.x[kept])) <= MARGIN * x_max
        assert res.stats["t_reached"] < T_END
    except ss.IntegrationError as e:
        assert type(e) is not ss.IntegrationError
    else:
        x_max, v_max, _ = energy_bounds("slope", "gms", res.y[:, 0], T_END)
        assert np.max(np.abs(res.x)) <= MARGIN * x_max


def test_committed_study_rows_are_inside_the_energy_bound():
    """docs/figures/laws_compare_{belt,slope}.csv (python -m cases --docs --only laws_compare):
    every row that reports success lies inside the scene's energy bound itself (no margin);
    the RK4 run of the generalized Maxwell-slip model at h = 1e-3 s, which used to report
    success at x_max = 9.3e10 m, is a DIVERGED row."""
    import csv
    from pathlib import Path

    figures = Path(__file__).resolve().parents[2] / "docs" / "figures"
    diverged = ss.REGISTRY["status"]["DIVERGED"]
    with open(figures / "laws_compare_belt.csv", newline="") as f:
        belt = list(csv.DictReader(f))
    with open(figures / "laws_compare_slope.csv", newline="") as f:
        slope = list(csv.DictReader(f))
    v_b = ss.DEFAULTS["v_b"]
    for row in belt:
        law = row["law [-]"].split()[0]
        if int(row["status [-]"]) != 0:
            continue
        x_max, _, _ = energy_bounds("belt", law, np.array([0.0, v_b]), 10.0)   # started stuck, 10 s
        assert abs(float(row["x_max [m]"])) <= x_max and abs(float(row["x_min [m]"])) <= x_max, row
    for row in slope:
        if int(row["status [-]"]) != 0:
            continue
        x_max, v_max, _ = energy_bounds("slope", row["law [-]"], np.array([0.0, 0.0]), 20.0)  # rest, 20 s
        assert abs(float(row["x_20 [m]"])) <= x_max and abs(float(row["v_20 [m/s]"])) <= v_max, row
    gms = [r for r in belt if (r["law [-]"], r["method [-]"], r["h [s]"]) == ("gms", "rk4", "0.001")]
    assert len(gms) == 1 and int(gms[0]["status [-]"]) == diverged
