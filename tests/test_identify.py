"""stickslip.fit_friction: parameters recovered from synthetic records of known parameters
(with noise) within their intervals, the intervals' coverage over many noise seeds against the
binomial distribution, BIC choosing the generating law, the force-level convention when the
normal force is not given, and bad input. The data loader on the repository's damper records."""
from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from scipy import stats

import stickslip
from stickslip import identify
from stickslip.identify import FitResult

pm = stickslip.prescribed_motion


def sine_record(duration: float = 4.0, n: int = 801, amplitude: float = 0.01, freq: float = 0.5,
                phase: float = 0.0):
    """A sine displacement [m] with its exact velocity [m/s]."""
    t = np.linspace(0.0, duration, n)
    w = 2.0 * np.pi * freq
    return t, amplitude * np.sin(w * t + phase), amplitude * w * np.cos(w * t + phase)


# ---------------------------------------------------------------------------------------------
# Static law: exact recovery, the force-level convention, coverage of the 95 % intervals
# ---------------------------------------------------------------------------------------------
STRIBECK = dict(mu_s=0.5, mu_k=0.4, v_s=0.004, delta=2.0, c_v=2.0, v_eps=0.001)
STRIBECK_FIXED = {"delta": 2.0, "v_eps": 0.001}
N_LOAD = 1000.0     # normal force of the synthetic records [N]


def test_noise_free_static_fit_recovers_parameters_and_force_levels():
    t, x, v = sine_record()
    f = pm("stribeck", t, x, v, normal_force=N_LOAD, **STRIBECK).force
    # normal force not given: force levels N mu (mu_s, mu_k in N, c_v in N s/m)
    fit = stickslip.fit_friction("stribeck", t, x, f, v=v, fixed=STRIBECK_FIXED)
    assert fit.force_levels
    assert fit.units["mu_k"] == "N" and fit.units["c_v"] == "N s/m" and fit.units["v_s"] == "m/s"
    for name in ("mu_s", "mu_k", "c_v"):
        assert fit.params[name] == pytest.approx(N_LOAD * STRIBECK[name], rel=1e-5)
    assert fit.params["v_s"] == pytest.approx(STRIBECK["v_s"], rel=1e-5)
    assert fit.rmse < 1e-6 * N_LOAD
    # given the normal force: coefficients
    fit_mu = stickslip.fit_friction("stribeck", t, x, f, v=v, normal_force=N_LOAD, fixed=STRIBECK_FIXED)
    assert not fit_mu.force_levels and fit_mu.units["mu_k"] == "-"
    assert fit_mu.params["mu_k"] == pytest.approx(STRIBECK["mu_k"], rel=1e-5)
    np.testing.assert_allclose(fit_mu.predict(t, x, v), f, atol=1e-6 * N_LOAD)


def test_force_scaled_parameters_are_those_proportional_to_mu():
    """The parameters the fit reports as force levels are exactly those by which N mu scales:
    scaling them by c and N by 1/c leaves the force of every law unchanged."""
    t, x, v = sine_record(n=401)
    from stickslip.identify import _force_scaled
    for law in stickslip.LAWS:
        names = stickslip.REGISTRY["law"][law]["params"]
        p = {k: stickslip.REGISTRY["param"][k]["default"] or 0.01 for k in names}
        scaled = {k: (7.0 * val if _force_scaled(k) else val) for k, val in p.items()}
        f1 = pm(law, t, x, v, normal_force=7.0, **p).force
        f2 = pm(law, t, x, v, normal_force=1.0, **scaled).force
        np.testing.assert_allclose(f2, f1, rtol=1e-6, atol=1e-9 * np.abs(f1).max(), err_msg=law)
        # and a parameter not in the list does change the force when scaled
        for k in names:
            if not _force_scaled(k):
                other = dict(p, **{k: p[k] * 1.3 if k != "n_elements" else 5.0})
                if law == "recurdyn" and k == "v_s":
                    other["v_d"] = 1.5 * other["v_s"]
                if k == "z_ba_ratio":
                    other[k] = 0.5
                f3 = pm(law, t, x, v, normal_force=1.0, **{q: (7.0 * val if _force_scaled(q) else val)
                                                           for q, val in other.items()}).force
                assert np.abs(f3 - f1).max() > 1e-6 * np.abs(f1).max() or law in ("coulomb", "karnopp"), (law, k)


# Coverage. A 95 % interval should hold the truth in 95 % of the noise draws. With S draws the
# count that do is Binomial(S, 0.95) when the intervals are right; the test accepts the central
# 99.8 % of that distribution (a right implementation fails with probability 0.2 % for a given
# set of seeds, and these seeds are fixed), and rejects intervals of true coverage 0.90 or 0.99
# with probability > 0.94 (checked below from the binomial distribution itself). 600 seeds of a
# static law (a fit costs about 10 ms) keep the test near 10 s.
COVERAGE_SEEDS = 600


def coverage_band(n: int, p: float = 0.95, mass: float = 0.998) -> tuple[int, int]:
    lo, hi = stats.binom.interval(mass, n, p)
    return int(lo), int(hi)


def test_coverage_band_has_power():
    lo, hi = coverage_band(COVERAGE_SEEDS)
    assert lo < 0.95 * COVERAGE_SEEDS < hi
    for wrong in (0.90, 0.99):
        inside = stats.binom.cdf(hi, COVERAGE_SEEDS, wrong) - stats.binom.cdf(lo - 1, COVERAGE_SEEDS, wrong)
        assert inside < 0.06, wrong


def test_confidence_intervals_cover_the_truth_95_percent():
    t, x, v = sine_record(duration=2.0, n=301)
    f = pm("stribeck", t, x, v, **STRIBECK).force
    noise = 0.01
    names = ("mu_s", "mu_k", "v_s", "c_v")
    hits = dict.fromkeys(names, 0)
    for seed in range(COVERAGE_SEEDS):
        fm = f + noise * np.random.default_rng(seed).standard_normal(f.size)
        fit = stickslip.fit_friction("stribeck", t, x, fm, v=v, normal_force=1.0, fixed=STRIBECK_FIXED,
                                     params0={k: STRIBECK[k] for k in names}, n_starts=1)
        for k in names:
            lo, hi = fit.ci95[k]
            hits[k] += lo <= STRIBECK[k] <= hi
    lo, hi = coverage_band(COVERAGE_SEEDS)
    for k in names:
        assert lo <= hits[k] <= hi, (k, hits[k], (lo, hi))


# ---------------------------------------------------------------------------------------------
# Laws with internal states: recovery within the intervals, several records jointly
# ---------------------------------------------------------------------------------------------
STATE_CASES = {
    "lugre": (dict(mu_s=1500.0, mu_k=1000.0, v_s=0.005, sigma0=4e5, sigma1=0.0, sigma2=3000.0),
              {"sigma1": 0.0}),
    "elastoplastic": (dict(mu_s=1500.0, mu_k=1000.0, v_s=0.005, sigma0=4e5, sigma1=0.0, sigma2=3000.0,
                           z_ba_ratio=0.5), {"sigma1": 0.0, "mu_s": 1500.0, "v_s": 0.005}),
    "dahl": (dict(mu_k=1000.0, sigma0=4e5, dahl_alpha=1.5), {}),
    "gms": (dict(mu_s=1500.0, mu_k=1000.0, v_s=0.005, sigma0=4e5, sigma1=0.0, sigma2=3000.0, n_elements=3,
                 gms_shape=1.0, gms_c=5e4),
            # gms_c (the sliding elements' attraction) changes the force by < 1e-4 N on sines: fixed
            {"sigma1": 0.0, "n_elements": 3, "gms_shape": 1.0, "gms_c": 5e4}),
}


def noisy_records(law: str, params: dict, noise: float, seed: int, n: int = 801, scale: float = 1.0, **opts):
    """Two records of different amplitude and frequency (states from 0 in each), with noise;
    `scale` multiplies both amplitudes."""
    rng = np.random.default_rng(seed)
    recs = [sine_record(4.0, n, 0.01 * scale, 0.5), sine_record(2.0, n, 0.004 * scale, 1.0, phase=0.3)]
    forces = [pm(law, t, x, v, **opts, **params).force + noise * rng.standard_normal(t.size)
              for t, x, v in recs]
    return [r[0] for r in recs], [r[1] for r in recs], forces, [r[2] for r in recs]


@pytest.mark.parametrize("law", sorted(STATE_CASES))
def test_state_law_recovered_within_intervals(law):
    truth, fixed = STATE_CASES[law]
    # elasto-plastic: its implicit state update costs 40x LuGre's, so fewer samples and
    # parameters (the Stribeck part is LuGre's, tested above)
    n = 801 if law != "elastoplastic" else 201
    t, x, f, v = noisy_records(law, truth, 10.0, seed=3, n=n)
    fit = stickslip.fit_friction(law, t, x, f, v=v, fixed=fixed, n_starts=3 if n > 201 else 1)
    assert fit.n_records == 2 and fit.n_samples == 2 * n
    assert fit.rmse == pytest.approx(10.0, rel=0.1)
    # each parameter within 3.29 standard errors (its 99.9 % interval: with 5-6 parameters
    # per fit, 95 % intervals would miss one in a quarter of the seeds); the coverage of the
    # 95 % intervals themselves is the coverage test's
    for k in fit.free:
        assert abs(fit.params[k] - truth[k]) <= 3.29 * fit.stderr[k], (k, fit.params[k], truth[k], fit.stderr[k])
        assert fit.stderr[k] < 0.2 * abs(truth[k]), k
        lo, hi = fit.ci95[k]
        assert lo < fit.params[k] < hi
    # correlation: symmetric, unit diagonal
    np.testing.assert_allclose(np.diag(fit.correlation), 1.0)
    np.testing.assert_allclose(fit.correlation, fit.correlation.T, atol=1e-12)


def test_backlash_and_asymmetry_fitted():
    truth, fixed = STATE_CASES["lugre"]
    opts = dict(backlash=0.001, asymmetry=1.3)
    t, x, f, v = noisy_records("lugre", truth, 10.0, seed=5, n=401, **opts)
    fit = stickslip.fit_friction("lugre", t, x, f, v=v, fixed=fixed, backlash="fit", asymmetry="fit", n_starts=1)
    for k, want in opts.items():
        assert abs(fit.params[k] - want) <= 3.29 * fit.stderr[k], (k, fit.params[k], fit.stderr[k])
    assert fit.units["backlash"] == "m"


def test_backlash_near_its_bound_is_flagged():
    # no play in the data, backlash fitted: it ends at or near 0, within its own error of the
    # bound, and says so; its interval stays >= 0
    truth, fixed = STATE_CASES["lugre"]
    t, x, f, v = noisy_records("lugre", truth, 10.0, seed=7, n=401)
    fit = stickslip.fit_friction("lugre", t, x, f, v=v, fixed=fixed, backlash="fit", n_starts=1)
    assert fit.params["backlash"] < 1e-4
    assert "backlash" in fit.at_bound and fit.ci95["backlash"][0] >= 0.0
    assert "at a bound" in next(ln for ln in fit.report().splitlines() if ln.strip().startswith("backlash:"))


def test_bic_picks_the_generating_law():
    truth, fixed = STATE_CASES["lugre"]
    t, x, f, v = noisy_records("lugre", truth, 10.0, seed=7, n=401)
    fits = {"lugre": stickslip.fit_friction("lugre", t, x, f, v=v, fixed=fixed),
            "stribeck": stickslip.fit_friction("stribeck", t, x, f, v=v, fixed={"v_eps": 1e-3}),
            "recurdyn": stickslip.fit_friction("recurdyn", t, x, f, v=v)}
    assert min(fits, key=lambda k: fits[k].bic) == "lugre"
    # and from static data the static law wins over LuGre (one parameter fewer)
    fs = [pm("stribeck", ti, xi, vi, **{k: (1000.0 * val if k in ("mu_s", "mu_k", "c_v") else val)
                                        for k, val in STRIBECK.items()}).force for ti, xi, vi in zip(t, x, v)]
    rng = np.random.default_rng(8)
    fs = [fi + 10.0 * rng.standard_normal(fi.size) for fi in fs]
    static = stickslip.fit_friction("stribeck", t, x, fs, v=v, fixed=STRIBECK_FIXED)
    # LuGre imitates a static law by an ever stiffer bristle: bounded here, to keep it cheap
    lugre = stickslip.fit_friction("lugre", t, x, fs, v=v, fixed={"sigma1": 0.0}, n_starts=1,
                                   bounds={"sigma0": (1e4, 1e7)})
    assert static.bic < lugre.bic


def test_predict_and_score_on_a_held_out_record():
    truth, fixed = STATE_CASES["lugre"]
    t, x, f, v = noisy_records("lugre", truth, 10.0, seed=9)
    fit = stickslip.fit_friction("lugre", t[0], x[0], f[0], v=v[0], fixed=fixed)
    exact = pm("lugre", t[1], x[1], v[1], **truth).force
    np.testing.assert_allclose(fit.predict(t[1], x[1], v[1]), exact, atol=0.05 * np.ptp(exact))
    held = fit.score(t[1], x[1], f[1], v=v[1])
    assert held["rmse"] < 3.0 * fit.rmse and held["n_samples"] == t[1].size


# ---------------------------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def good():
    t, x, v = sine_record(n=101)
    return t, x, pm("stribeck", t, x, v, **STRIBECK).force


@pytest.mark.parametrize("change, match", [
    (lambda t, x, f: ("lugre2", t, x, f, {}), "law: unknown value 'lugre2'"),
    (lambda t, x, f: ("stribeck", t, x, np.where(np.arange(f.size) == 5, np.nan, f), {}), r"force: must be finite .* sample 5"),
    (lambda t, x, f: ("stribeck", t, x[:-1], f, {}), r"x: must be 101 values"),
    (lambda t, x, f: ("stribeck", t[::-1], x, f, {}), r"t: must be strictly increasing"),
    (lambda t, x, f: ("stribeck", t, x, f, {"fixed": {"sigma0": 1.0}}), r"fixed: unknown parameter\(s\) 'sigma0' of law 'stribeck'"),
    (lambda t, x, f: ("stribeck", t, x, f, {"params0": {"mu": 1.0}}), r"params0: unknown parameter\(s\) 'mu'"),
    (lambda t, x, f: ("stribeck", t, x, f, {"bounds": {"v_x": (0, 1)}}), r"bounds: unknown parameter\(s\) 'v_x'"),
    (lambda t, x, f: ("stribeck", t, x, f, {"bounds": {"v_s": (1.0, 0.5)}}), r"bounds\['v_s'\]: must have low < high"),
    (lambda t, x, f: ("stribeck", t, x, f, {"backlash": -1e-3}), r"backlash: must be >= 0"),
    (lambda t, x, f: ("stribeck", t, x, f, {"asymmetry": "yes"}), r"asymmetry: must be a number or 'fit'"),
    (lambda t, x, f: ("stribeck", t, x, f, {"normal_force": -2.0}), r"normal_force: must be > 0"),
    (lambda t, x, f: ("stribeck", t, x, f, {"n_starts": 0}), r"n_starts: must be an integer >= 1"),
    (lambda t, x, f: ("stribeck", [t, t], [x, x], f, {}), r"force: t is a list of 2 records"),
    (lambda t, x, f: ("stribeck", [t, t], [x, x[:-1]], [f, f], {}), r"x\[1\]: must be 101 values"),
    (lambda t, x, f: ("stribeck", t[:3], x[:3], f[:3], {}), r"t: 3 samples cannot determine"),
    (lambda t, x, f: ("stribeck", t, x, f, {"fixed": dict(STRIBECK)}), r"fixed: every parameter is fixed"),
    (lambda t, x, f: ("stribeck", t, x, np.zeros_like(f), {}), r"force: every sample is 0.0 N"),
    (lambda t, x, f: ("stribeck", t, x, np.full_like(f, 3.5), {}), r"force: every sample is 3.5 N"),
    (lambda t, x, f: ("lugre", t, x, f, {"fixed": {"sigma0": -1.0}}), r"fixed\['sigma0'\]: must be > 0 \[N/m\], got -1.0"),
    (lambda t, x, f: ("lugre", t, x, f, {"fixed": {"mu_s": 2.0, "mu_k": 3.0}}), r"fixed: mu_k = 3.0 must be <= mu_s = 2.0"),
    (lambda t, x, f: ("lugre", t, x, f, {"params0": {"sigma1": -5.0}}), r"params0\['sigma1'\]: must be >= 0 \[N s/m\], got -5.0"),
    (lambda t, x, f: ("gms", t, x, f, {"fixed": {"n_elements": 2.5}}), r"fixed\['n_elements'\]: must be an integer"),
    (lambda t, x, f: ("gms", t, x, f, {"fixed": {"n_elements": 99}}), r"fixed\['n_elements'\]: must be in \[1, 64\]"),
])
def test_bad_input_names_the_parameter(good, change, match):
    law, t, x, f, kw = change(*good)
    with pytest.raises(ValueError, match=match):
        stickslip.fit_friction(law, t, x, f, **kw)


def test_bad_input_is_refused_before_any_fitting(good, monkeypatch):
    # the constant force and the bad fixed value are refused without one model evaluation
    from stickslip import identify
    calls = []
    monkeypatch.setattr(identify, "_model", lambda *a, **k: calls.append(1))
    t, x, f = good
    for kw in ({"force": np.zeros_like(f)}, {"force": f, "fixed": {"sigma0": -1.0}}):
        with pytest.raises(ValueError):
            stickslip.fit_friction("lugre" if "fixed" in kw else "stribeck", t, x, **kw)
    assert calls == []


# ---------------------------------------------------------------------------------------------
# A failed fit says so
# ---------------------------------------------------------------------------------------------
def test_fit_out_of_budget_says_so(good):
    t, x, f = good
    with pytest.warns(RuntimeWarning, match="evaluation budget"):
        fit = stickslip.fit_friction("stribeck", t, x, f, n_starts=1, max_nfev=1,
                                     params0={"mu_k": 0.01, "mu_s": 0.02})
    assert not fit.success and "max_nfev" in fit.message


def test_fit_no_better_than_zero_says_so():
    # a force against the motion (a negative sliding level) is beyond every law: the best fit
    # lowers the sum of squares of the force by nothing
    t, x, v = sine_record(n=201)
    f = -pm("dahl", t, x, v, mu_k=0.3, sigma0=2e3).force
    with pytest.warns(RuntimeWarning, match="no better than predicting zero"):
        fit = stickslip.fit_friction("dahl", t, x, f, v=v)
    assert not fit.success


def test_fit_stopped_on_a_slope_says_so(monkeypatch):
    # an optimiser that never moves from its start reports success; the probe about its end
    # (a Gauss-Newton step, steps of two standard errors) finds lower points, the restarts from
    # them stop at once too, and with two restarts allowed the fit says it stopped far from a
    # minimum; with the default budget the probes' Gauss-Newton steps reach the truth (the data
    # are noise-free: to the integration's error), and the fit succeeds
    import scipy.optimize
    t, x, v = sine_record(n=201)
    f = pm("dahl", t, x, v, mu_k=0.3, sigma0=2e3).force
    real = scipy.optimize.least_squares

    def early(fun, x0, **kw):
        sol = real(fun, x0, **dict(kw, max_nfev=1))
        sol.status, sol.success, sol.message = 2, True, "`ftol` termination condition is satisfied."
        return sol
    monkeypatch.setattr(scipy.optimize, "least_squares", early)
    start = {"mu_k": 0.1, "sigma0": 300.0}
    with monkeypatch.context() as m:
        m.setattr(identify, "MAX_RESTARTS", 2)
        with pytest.warns(RuntimeWarning, match=r"far from a minimum: .* after 2 restart\(s\)"):
            fit = stickslip.fit_friction("dahl", t, x, f, v=v, n_starts=1, params0=start)
    assert not fit.success and fit.restarts == 2 and fit.probe_gain > 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fit = stickslip.fit_friction("dahl", t, x, f, v=v, n_starts=1, params0=start)
    assert fit.success and 2 < fit.restarts <= identify.MAX_RESTARTS
    for k, want in {"mu_k": 0.3, "sigma0": 2e3, "dahl_alpha": 1.0}.items():
        assert fit.params[k] == pytest.approx(want, rel=1e-5), k
    monkeypatch.setattr(scipy.optimize, "least_squares", real)
    fit = stickslip.fit_friction("dahl", t, x, f, v=v, n_starts=1, params0={"mu_k": 0.1, "sigma0": 300.0})
    assert fit.success and fit.message.startswith("`")


def test_identify_driver_writes_scores_figures_and_report(tmp_path):
    """cases.identify on two 36 lb records (one fitted, one held out by the checkerboard) and two
    laws: every file is there, the CSV columns carry units, the report names a law to use."""
    from cases import _common as c
    from cases import identify
    d = stickslip.data.DAMPER_DIR
    files = identify.main(["--outdir", str(tmp_path), "--quiet", "--threads", "1", "--laws", "coulomb", "dahl",
                           "--data", str(d / "sine_1Hz_0.5in_36lb.csv.gz"), str(d / "sine_2Hz_0.5in_36lb.csv.gz")])
    names = {f.name for f in files}
    for stem in ("identify_loops_36lb", "identify_residuals_36lb", "identify_correlation_36lb", "identify_scores"):
        assert {stem + ".png", stem + ".pdf"} <= names
    scores = c.read_csv(tmp_path / "identify_scores.csv")
    assert scores["law [-]"] == ["coulomb", "dahl"]
    held = [float(x) for x in scores["nrmse held out [-]"]]
    assert held[1] < held[0]                       # presliding beats a jump, on the held-out record
    records = c.read_csv(tmp_path / "identify_records.csv")
    assert sorted(set(zip(records["record [-]"], records["split [-]"]))) == [
        ("sine_1Hz_0.5in_36lb", "fitted"), ("sine_2Hz_0.5in_36lb", "held out")]
    report = (tmp_path / "identify_report.md").read_text()
    assert "**Use Dahl** (`dahl`)" in report


# ---------------------------------------------------------------------------------------------
# select_friction_law: cross-validation over records
# ---------------------------------------------------------------------------------------------
def three_records(law, params, noise, seed, n=301):
    """Three sines of different amplitude and frequency (states from 0 in each), with noise."""
    rng = np.random.default_rng(seed)
    recs = [sine_record(4.0, n, 0.01, 0.5), sine_record(2.0, n, 0.004, 1.0, phase=0.3),
            sine_record(2.0, n, 0.02, 0.5, phase=1.0)]
    forces = [pm(law, t, x, v, **params).force + noise * rng.standard_normal(t.size) for t, x, v in recs]
    return [r[0] for r in recs], [r[1] for r in recs], forces, [r[2] for r in recs]


def test_select_prefers_the_simpler_law_that_predicts_as_well():
    # Dahl with alpha = 1 is LuGre with mu_s = mu_k and no damping: LuGre predicts as well with
    # three more parameters, so the one-standard-error rule keeps Dahl; Coulomb predicts worse
    truth = dict(mu_k=1000.0, sigma0=4e5, dahl_alpha=1.0)
    t, x, f, v = three_records("dahl", truth, 10.0, seed=5)
    sel = stickslip.select_friction_law(["coulomb", "dahl", "lugre"], t, x, f, v=v,
                                        fixed={"coulomb": {"v_s": 1e-3}, "lugre": {"sigma1": 0.0}})
    assert sel.best == "dahl" and sel.folds == "records"
    assert len(sel.fold_scores["dahl"]) == 3
    assert sel.scores["coulomb"][0] > 3 * sel.scores["dahl"][0]
    # the held-out error is near the noise (10 N over a 2000 N range)
    assert sel.scores["dahl"][0] < 3 * 10.0 / 2000.0
    assert sel.fits["dahl"].params["mu_k"] == pytest.approx(1000.0, rel=0.02)
    text = sel.table()
    assert "chosen" in text.splitlines()[2] and "dahl" in text.splitlines()[2]


def test_select_picks_the_law_that_predicts_better():
    # LuGre with a Stribeck drop and viscous friction: Dahl cannot follow the velocity dependence
    truth = dict(mu_s=1500.0, mu_k=1000.0, v_s=0.005, sigma0=4e5, sigma1=0.0, sigma2=20000.0)
    t, x, f, v = three_records("lugre", truth, 10.0, seed=6)
    sel = stickslip.select_friction_law(["dahl", "lugre"], t, x, f, v=v, fixed={"lugre": {"sigma1": 0.0}})
    assert sel.best == "lugre"
    lo_mean, lo_se = sel.scores["lugre"]
    assert sel.scores["dahl"][0] > lo_mean + lo_se


def test_select_on_one_record_uses_blocks():
    truth = dict(mu_k=1000.0, sigma0=4e5, dahl_alpha=1.0)
    t, x, v = sine_record(8.0, 801, 0.01, 0.5)
    f = pm("dahl", t, x, v, **truth).force + 10.0 * np.random.default_rng(2).standard_normal(t.size)
    sel = stickslip.select_friction_law(["coulomb", "dahl"], t, x, f, v=v, n_blocks=4,
                                        fixed={"coulomb": {"v_s": 1e-3}})
    assert sel.folds == "blocks" and len(sel.fold_scores["dahl"]) == 4
    assert sel.best == "dahl"
    # the fit on all the data has the default intervals (a static law: profiled), the folds'
    # fits, scored only, none profiled
    assert sel.fits["coulomb"].profiled and not sel.fits["dahl"].profiled


def test_select_profiles_only_the_fits_on_all_the_data(monkeypatch):
    t, x, v = sine_record(8.0, 401, 0.01, 0.5)
    f = pm("coulomb", t, x, v, mu_s=1000.0, mu_k=1000.0, v_s=1e-3).force
    f = f + 10.0 * np.random.default_rng(3).standard_normal(t.size)
    kinds = []
    real = identify.fit_friction

    def spy(*args, **kw):
        fit = real(*args, **kw)
        kinds.append((kw.get("interval"), set(fit.profiled), set(fit.free), set(fit.at_bound)))
        return fit

    monkeypatch.setattr(identify, "fit_friction", spy)
    stickslip.select_friction_law(["coulomb", "capped_viscous"], t, x, f, v=v, n_blocks=3,
                                  fixed={"coulomb": {"v_s": 1e-3}})
    # per law: the fit on all the data (every parameter profiled), then three folds (Wald,
    # but for a parameter near a bound, here Coulomb's mu_s = mu_k: profiled whatever the kind)
    assert [k[0] for k in kinds] == [None, "wald", "wald", "wald"] * 2
    for interval, profiled, free, at_bound in kinds:
        assert profiled == free if interval is None else profiled <= at_bound


@pytest.mark.parametrize("kw, match", [
    ({"laws": ["dahl"]}, "laws: give at least 2"),
    ({"laws": ["dahl", "dahl2"]}, "laws: unknown value 'dahl2'"),
    ({"laws": ["dahl", "dahl"]}, "laws: each law once"),
    ({"cv": "kfold"}, "cv: unknown value 'kfold'"),
    ({"n_blocks": 1}, "n_blocks: must be an integer >= 2"),
])
def test_select_bad_input(good, kw, match):
    t, x, f = good
    args = dict(laws=["coulomb", "dahl"], cv="records", n_blocks=5) | kw
    with pytest.raises(ValueError, match=match):
        stickslip.select_friction_law(args.pop("laws"), t, x, f, **args)


@pytest.mark.slow
def test_select_on_the_damper_records_held_out_by_record():
    # The ten 36 lb records, each held out in turn (subsampled to 48 samples per cycle as
    # cases.identify does): a law with presliding states predicts the held-out records better
    # than Coulomb (whose loops are rectangles) by a margin far beyond the folds' spread
    from cases import identify as ci
    recs = [r for r, _ in ci.load_groups(stickslip.damper_files(36))["36lb"]]
    sel = stickslip.select_friction_law(["coulomb", "dahl"], recs, backlash="fit", asymmetry="fit",
                                        fixed={"coulomb": ci.fixed_for("coulomb")}, rtol=1e-4, diff_step=1e-2)
    assert sel.folds == "records" and len(sel.fold_scores["dahl"]) == 10
    assert sel.best == "dahl"
    assert sel.scores["coulomb"][0] - sel.scores["dahl"][0] > 3 * sel.scores["coulomb"][1]


# ---------------------------------------------------------------------------------------------
# Honest uncertainty: prediction intervals, intervals inside the allowed range, the report
# ---------------------------------------------------------------------------------------------
def ar1_noise(rng, n, sd, rho):
    e = np.empty(n)
    e[0] = rng.standard_normal()
    for i in range(1, n):
        e[i] = rho * e[i - 1] + math.sqrt(1 - rho**2) * rng.standard_normal()
    return sd * e


@pytest.mark.parametrize("rho", [0.0, 0.8])
def test_prediction_interval_covers_held_out_measurements(rho):
    # fitted on one record, predicted on another of other amplitude and frequency: the 95 %
    # prediction interval holds 95 % of the held-out noisy samples (white or AR(1) noise)
    truth, fixed = STATE_CASES["dahl"]
    rng = np.random.default_rng(11)
    (t0, x0, v0), (t1, x1, v1) = sine_record(4.0, 801, 0.01, 0.5), sine_record(2.0, 801, 0.004, 1.0, phase=0.3)
    f0 = pm("dahl", t0, x0, v0, **truth).force + ar1_noise(rng, t0.size, 10.0, rho)
    exact1 = pm("dahl", t1, x1, v1, **truth).force
    fit = stickslip.fit_friction("dahl", t0, x0, f0, v=v0, fixed=fixed)
    assert fit.noise_correlation == pytest.approx(rho, abs=0.1)
    inside = []
    for seed in range(5):
        f1 = exact1 + ar1_noise(np.random.default_rng(100 + seed), t1.size, 10.0, rho)
        force, lower, upper = fit.predict(t1, x1, v1, interval=0.95)
        np.testing.assert_array_equal(force, fit.predict(t1, x1, v1))
        inside.append(np.mean((f1 >= lower) & (f1 <= upper)))
    assert 0.92 <= np.mean(inside) <= 0.98
    # the parameters' share of the width: a narrower interval than the residual scatter alone
    # cannot be (s is its floor)
    assert np.all(upper - force >= 1.959 * fit.residual_sd)


def test_correlated_residuals_widen_the_parameter_intervals():
    truth, fixed = STATE_CASES["dahl"]
    t, x, v = sine_record(4.0, 801, 0.01, 0.5)
    exact = pm("dahl", t, x, v, **truth).force
    white = stickslip.fit_friction("dahl", t, x, exact + ar1_noise(np.random.default_rng(1), t.size, 10.0, 0.0), v=v)
    red = stickslip.fit_friction("dahl", t, x, exact + ar1_noise(np.random.default_rng(1), t.size, 10.0, 0.8), v=v)
    assert white.variance_inflation < 1.3
    assert red.variance_inflation == pytest.approx(9.0, rel=0.4)      # (1 + 0.8)/(1 - 0.8)
    assert red.stderr["sigma0"] > 2.0 * white.stderr["sigma0"]


def test_intervals_stay_in_the_allowed_range():
    # LuGre data without damping, sigma1 fitted: its estimate sits near 0 with an error larger
    # than itself; the interval stays >= 0 (the log scale) and the report flags it
    truth, _ = STATE_CASES["lugre"]
    t, x, f, v = noisy_records("lugre", truth, 30.0, seed=4, n=401)
    fit = stickslip.fit_friction("lugre", t, x, f, v=v)
    from stickslip.identify import _range_of
    for name in fit.free:
        low, high = _range_of(name)[:2]
        lo, hi = fit.ci95[name]
        assert low <= lo <= fit.params[name] <= hi <= high, name
    assert fit.ci95["sigma1"][0] >= 0.0
    if fit.stderr["sigma1"] > fit.params["sigma1"]:
        assert "sigma1" in fit.undetermined


def test_ordered_pair_interval_on_the_log_of_the_excess():
    # mu_s fitted over mu_k ranges over (mu_k, inf): its Wald interval is mu_k + e exp(+-t sd / e),
    # e = mu_s - mu_k (closed form), inside the range, asymmetric (longer upwards); near the
    # bound (e < t sd) the plain interval cut at mu_k; an unknown error: (mu_k, inf)
    space = identify._Space(("mu_k", "mu_s", "v_s"), np.ones(3), {1: 0})
    pv, tq = np.array([1000.0, 1400.0, 0.005]), 1.96
    ci = identify._wald_intervals(space, pv, np.array([2.0, 100.0, 1e-3]), tq)
    e = 400.0
    np.testing.assert_allclose(ci["mu_s"], (1000.0 + e * math.exp(-tq * 100.0 / e), 1000.0 + e * math.exp(tq * 100.0 / e)))
    assert ci["mu_s"][1] - 1400.0 > 1400.0 - ci["mu_s"][0] > 0.0
    np.testing.assert_allclose(ci["v_s"], (0.005 * math.exp(-tq * 0.2), 0.005 * math.exp(tq * 0.2)))
    near = identify._wald_intervals(space, np.array([1000.0, 1100.0, 0.005]), np.array([2.0, 100.0, 1e-3]), tq)
    assert near["mu_s"] == (1000.0, 1100.0 + tq * 100.0)
    blind = identify._wald_intervals(space, pv, np.array([2.0, math.inf, 1e-3]), tq)
    assert blind["mu_s"] == (1000.0, math.inf)


def test_fit_report_is_complete():
    truth, fixed = STATE_CASES["lugre"]
    t, x, f, v = three_records("lugre", truth, 10.0, seed=8, n=201)
    sel = stickslip.select_friction_law(["dahl", "lugre"], t, x, f, v=v, fixed={"lugre": fixed})
    fit = sel.fits["lugre"]
    text = fit.report()
    for piece in ("[[Fit]]", "success", fit.message, f"model evaluations  = {fit.nfev}", "rmse", "nrmse",
                  "AIC", "BIC", "cross-validated", "lag-1 correlation", "[[Parameters]]", "[[Correlations]]",
                  "(fixed)", "95% intervals      = Wald, on the range's scale"):
        assert piece in text, piece
    for name in fit.free:
        line = next(ln for ln in text.splitlines() if ln.strip().startswith(name + ":"))
        assert f"{fit.params[name]:.7g}" in line and f"{fit.stderr[name]:.4g}" in line
        assert f"(start {fit.start[name]:.5g})" in line and "%" in line
    big = [(a, b) for i, a in enumerate(fit.free) for j, b in enumerate(fit.free)
           if i < j and abs(fit.correlation[i, j]) > 0.5]
    assert all(f"C({a}, {b})" in text for a, b in big)
    assert f"{sel.scores['lugre'][0]:.6g}" in text


@pytest.mark.parametrize("args, match", [
    (["--data", "{tmp}/absent.csv"], "argument --data: .*absent.csv: no such file"),
    (["--data", "{tmp}/bad.csv"], "argument --data: .*bad.csv: .*no column"),
    (["--outdir", "{tmp}/a_file/sub"], "argument --outdir: cannot write into"),
])
def test_identify_driver_refuses_bad_data_and_outdir_before_any_work(tmp_path, capsys, monkeypatch, args, match):
    from cases import identify
    (tmp_path / "bad.csv").write_text("garbage\n1,2\n")
    (tmp_path / "a_file").write_text("")
    monkeypatch.setattr(identify, "run", lambda *a, **k: pytest.fail("ran"))
    with pytest.raises(SystemExit) as exc:
        identify.main([a.format(tmp=tmp_path) for a in args] + ["--quiet"])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert re.search(match, err[-1]) and "Traceback" not in "\n".join(err)


# ---------------------------------------------------------------------------------------------
# Coverage of the 95 % intervals with a fitted backlash and asymmetry
# ---------------------------------------------------------------------------------------------
BACKLASH_OPTS = dict(backlash=0.001, asymmetry=1.3)


def linear_oracle(law: str, truth: dict, names: tuple[str, ...], n: int = 401, rel: float = 1e-4,
                  **opts) -> tuple[np.ndarray, np.ndarray]:
    """The linearised least-squares estimator at the truth, independent of fit_friction: the
    Jacobian of the noise-free records of `noisy_records` (prescribed_motion at rtol 1e-10,
    central differences of relative step `rel`) with respect to `names`; returns its
    pseudo-inverse P (the estimate's deviation is P @ noise) and the standard errors of that
    estimator for the generator's noise of 1 N (the rows' norms of P)."""
    recs = [sine_record(4.0, n, 0.01, 0.5), sine_record(2.0, n, 0.004, 1.0, phase=0.3)]
    full = dict(truth, **opts)

    def force(p: dict) -> np.ndarray:
        law_p = {k: v for k, v in p.items() if k not in opts}
        return np.concatenate([pm(law, t, x, v, rtol=1e-10, backlash=p["backlash"], asymmetry=p["asymmetry"],
                                  **law_p).force for t, x, v in recs])

    cols = []
    for k in names:
        h = rel * abs(full[k])
        cols.append((force({**full, k: full[k] + h}) - force({**full, k: full[k] - h})) / (2.0 * h))
    p_inv = np.linalg.pinv(np.array(cols).T)
    return p_inv, np.linalg.norm(p_inv, axis=1)


def backlash_coverage(draws: int, seed0: int = 1000) -> tuple[dict[str, int], dict[str, int], dict[str, np.ndarray]]:
    """Over `draws` noisy record pairs (10 N of white noise) of LuGre with a backlash and an
    asymmetry, all fitted: how many of each parameter's 95 % intervals hold the truth; how many
    intervals of the linearised estimator at the truth (`linear_oracle`, the same noise) hold
    it, the yardstick of what these draws allow; and per draw the fit's error and the
    oracle's in the oracle's standard errors."""
    truth, fixed = STATE_CASES["lugre"]
    full = dict(truth, **BACKLASH_OPTS)
    names = ("mu_s", "mu_k", "v_s", "sigma0", "sigma2", "backlash", "asymmetry")
    p_inv, sd = linear_oracle("lugre", truth, names, **BACKLASH_OPTS)
    noise_free = None
    hits, oracle = dict.fromkeys(names, 0), dict.fromkeys(names, 0)
    errors: dict[str, list] = {k: [] for k in names}
    tq = stats.t.ppf(0.975, 2 * 401 - len(names))
    for seed in range(seed0, seed0 + draws):
        t, x, f, v = noisy_records("lugre", truth, 10.0, seed=seed, n=401, **BACKLASH_OPTS)
        if noise_free is None:
            noise_free = np.concatenate([pm("lugre", *r, **BACKLASH_OPTS, **truth).force for r in zip(t, x, v)])
        z_lin = p_inv @ (np.concatenate(f) - noise_free) / (10.0 * sd)
        fit = stickslip.fit_friction("lugre", t, x, f, v=v, fixed=fixed, backlash="fit", asymmetry="fit",
                                     n_starts=1)
        assert fit.free == names
        for i, k in enumerate(names):
            lo, hi = fit.ci95[k]
            hits[k] += lo <= full[k] <= hi
            oracle[k] += int(abs(z_lin[i]) <= tq)
            errors[k].append(((fit.params[k] - full[k]) / (10.0 * sd[i]), z_lin[i], fit.stderr[k] / (10.0 * sd[i])))
    return hits, oracle, {k: np.array(e) for k, e in errors.items()}


def test_lugre_with_backlash_intervals_cover_a_few_draws():
    # (the finite-difference step of the standard errors used to measure the integrator's
    # step-doubling decisions: the backlash's interval was a few nanometres wide)
    hits, _, errors = backlash_coverage(4)
    assert hits["backlash"] >= 3 and min(hits.values()) >= 2, hits
    # the fit's errors are those of the linearised estimator at the truth on the same noise
    # (measured over 100 draws: within 0.65 of its standard errors, v_s 1.44; mu_s, the
    # Stribeck part's nonlinearity, not), and its standard errors are that estimator's on
    # average (per draw 0.79-1.31 times, the Jacobian at the estimate): standard errors 1.3
    # times too small, the suspicion of issue 31, would put the mean ratio near 0.77
    for k, e in errors.items():
        err, err_lin, ratio = e.T
        if k != "mu_s":
            assert np.abs(err - err_lin).max() <= 1.5, (k, err, err_lin)
            assert 0.85 <= ratio.mean() <= 1.2, (k, ratio)


@pytest.mark.slow
def test_lugre_with_backlash_intervals_cover_the_truth_95_percent():
    # 400 draws (seeds 1000-1399): each parameter's count within the central 99.8 % of
    # Binomial(400, 0.95), 365-392 (a coverage of 0.90 falls outside with probability 0.82),
    # and within 5 % of the draws of the count of the linearised estimator at the truth on the
    # same noise, whose standard errors are exact. The 50-draw sets once used here had mu_k at
    # 84 % (seeds 1000-1049) and backlash at 84 % (3000-3049): that estimator covers as rarely
    # on those very draws (84 % and 84 %), and over 20000 draws 94.8-95.3 % for every
    # parameter; one 50-draw set in 40 has a parameter at 84 % or less. Measured (2026-11-26),
    # fit / linearised estimator: mu_s 386/386, mu_k 378/376, v_s 374/378, sigma0 385/380,
    # sigma2 382/380, backlash 376/377, asymmetry 385/385 (mu_s's interval on the log of
    # mu_s itself, before: 92.5 % over seeds 10000-10999, all misses low; now 95.2 %)
    draws = 400
    lo, hi = coverage_band(draws)
    hits, oracle, _ = backlash_coverage(draws)
    assert all(lo <= h <= hi for h in hits.values()), (hits, oracle, (lo, hi))
    # the fit misses where the exact linearisation misses (mu_s, whose interval follows its
    # standard error at the estimate, within 5 % of the draws)
    assert all(abs(hits[k] - oracle[k]) <= 0.05 * draws for k in hits), (hits, oracle)


# ---------------------------------------------------------------------------------------------
# Coverage of the 95 % intervals, law by law
# ---------------------------------------------------------------------------------------------
# truth, fixed parameters and the records' amplitude scale of each law (force levels, N = 1 N).
# The proposed law decays as a^-|v| with v in m/s: on the sines above (3 cm/s at most) and its
# default a = 1.5 the decay is 1 % of mu_s - mu_k, mu_k and a are then not determined (its
# intervals held mu_k in 35 of 50 draws, 21 fits said they had failed); ten times the
# amplitudes and a = 20 make the curve's shape visible.
TUNED_CASES: dict[str, tuple[dict, dict, float]] = {
    "coulomb": (dict(mu_s=1500.0, mu_k=1000.0, v_s=1e-3), {"v_s": 1e-3}, 1.0),
    "karnopp": (dict(mu_s=1500.0, mu_k=1000.0, dv=1e-3), {"dv": 1e-3}, 1.0),
    "recurdyn": (dict(mu_s=1500.0, mu_k=1000.0, v_s=0.003, v_d=0.006), {}, 1.0),
    "proposed": (dict(mu_s=1500.0, mu_k=1000.0, v_s=0.02, beta=1.0 / 3.0, a=20.0), {}, 10.0),
    "stribeck": (dict(mu_s=1500.0, mu_k=1000.0, v_s=0.004, delta=2.0, c_v=2000.0, v_eps=0.001), STRIBECK_FIXED, 1.0),
    **{law: (truth, fixed, 1.0) for law, (truth, fixed) in STATE_CASES.items()},
}
#: Force levels of a law without a tuned case (the physics engines' regularised laws have
#: theirs: v_s, the engine's regularisation speed); its other parameters at their defaults.
DEFAULT_LEVELS: dict[str, float] = dict(mu_s=1500.0, mu_k=1000.0, v_s=0.004)


def default_case(law: str) -> tuple[dict, dict, float]:
    """The coverage case of a law from the registry alone: its parameters at DEFAULT_LEVELS or
    their defaults, none fixed, the records at their own amplitude."""
    return ({k: DEFAULT_LEVELS.get(k, stickslip.REGISTRY["param"][k]["default"])
             for k in stickslip.REGISTRY["law"][law]["params"]}, {}, 1.0)


#: Every law of the registry: its tuned case, else the default one (a new law is covered with
#: no edit here).
COVERAGE_CASES: dict[str, tuple[dict, dict, float]] = {
    law: TUNED_CASES.get(law) or default_case(law) for law in stickslip.LAWS}


def law_coverage(law: str, draws: int, seed0: int = 2000) -> dict[str, int]:
    """How many of `draws` noisy record pairs (10 N of white noise) have each fitted
    parameter's 95 % interval holding the truth."""
    truth, fixed, scale = COVERAGE_CASES[law]
    n = 201 if law == "elastoplastic" else 401
    hits: dict[str, int] = {}
    for seed in range(seed0, seed0 + draws):
        t, x, f, v = noisy_records(law, truth, 10.0, seed=seed, n=n, scale=scale)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit = stickslip.fit_friction(law, t, x, f, v=v, fixed=fixed, n_starts=1)
        for k in fit.free:
            lo, hi = fit.ci95[k]
            hits[k] = hits.get(k, 0) + (lo <= truth[k] <= hi)
    return hits


def test_coverage_cases_follow_the_registry():
    """Every law has a case; a tuned case names a law of the registry and only its parameters;
    the default case of the engines' laws is the one they had by hand."""
    assert sorted(COVERAGE_CASES) == sorted(stickslip.LAWS)
    for law, (truth, fixed, _) in TUNED_CASES.items():
        assert set(truth) | set(fixed) <= set(stickslip.REGISTRY["law"][law]["params"]), law
    assert default_case("drake_tamsi") == (dict(mu_k=1000.0, v_s=0.004), {}, 1.0)
    assert default_case("drake_continuous") == (dict(mu_s=1500.0, mu_k=1000.0, v_s=0.004), {}, 1.0)


@pytest.mark.parametrize("law", sorted(COVERAGE_CASES))
def test_every_law_intervals_cover_a_few_draws(law):
    # three draws: at least 3/4 of the (parameter, draw) intervals hold the truth (a law with
    # five parameters and right intervals misses that with probability 0.5 %)
    hits = law_coverage(law, 3)
    assert sum(hits.values()) >= 0.75 * 3 * len(hits), hits


@pytest.mark.slow
@pytest.mark.parametrize("law", sorted(COVERAGE_CASES))
def test_every_law_intervals_cover_the_truth_95_percent(law):
    # 50 draws: each parameter's count within the central 99.8 % of Binomial(50, 0.95), i.e. at
    # least 42 (50 draws cannot tell a true coverage of 0.90 from 0.95; the 600-seed test of
    # the Stribeck law can). Measured (2026-11-25, seeds 2000-2049):
    # coulomb 48-49, karnopp 49-50, recurdyn 46-49, proposed 47-49, stribeck 47-49, lugre
    # 48-50, elastoplastic 48-49, dahl 48-49, gms 45-49 of 50
    lo, hi = coverage_band(50)
    hits = law_coverage(law, 50)
    assert all(lo <= h <= hi for h in hits.values()), (hits, (lo, hi))


# ---------------------------------------------------------------------------------------------
# The Jacobian on the frozen substep mesh against the adaptive model's
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("law", ["lugre", "gms", "elastoplastic"])
def test_frozen_mesh_jacobian_fits_as_the_adaptive_one(law, monkeypatch):
    # fit_friction differentiates the model on the substeps its state integration chose at the
    # point (one sweep a column); the same fit with every evaluation adaptive (the Jacobian the
    # forward difference of the step-doubling model, as scipy's own 2-point scheme took it)
    # must end at the same parameters, within a small fraction of their standard errors, with
    # the same force to the integration's tolerance
    truth, fixed = STATE_CASES[law]
    t, x, f, v = noisy_records(law, truth, 10.0, seed=5, n=201, backlash=2e-4)
    kw = dict(fixed=fixed, v=v, backlash="fit", n_starts=1)
    frozen = stickslip.fit_friction(law, t, x, f, **kw)
    original = identify._model_mesh
    calls = {"frozen": 0}

    def adaptive(law_, d, params, rtol=1e-8, substeps=None):
        calls["frozen"] += substeps is not None
        return original(law_, d, params, rtol)

    monkeypatch.setattr(identify, "_model_mesh", adaptive)
    plain = stickslip.fit_friction(law, t, x, f, **kw)
    monkeypatch.undo()
    assert calls["frozen"] > 0 and frozen.success and plain.success
    for k in frozen.free:
        assert abs(frozen.params[k] - plain.params[k]) <= 0.05 * frozen.stderr[k], (k, frozen.params[k], plain.params[k])
        assert frozen.stderr[k] == pytest.approx(plain.stderr[k], rel=0.05), k
    pf = np.concatenate(frozen.predict(t, x, v))
    pp = np.concatenate(plain.predict(t, x, v))
    assert np.abs(pf - pp).max() <= 0.01 * frozen.rmse


def test_frozen_substeps_reproduce_the_adaptive_force():
    # the substeps the step doubling chose, given back, give the same force bit for bit; a
    # parameter moved on them stays within the integration's tolerance of the adaptive force
    # and moves smoothly (the finite difference at 1e-7 and 1e-5 agree, a measure of the model)
    from stickslip.prescribed import _force_on
    t, x, v = sine_record(2.0, 401, 0.004, 1.0)
    nf = np.ones(1)
    p = dict(mu_s=1500.0, mu_k=1000.0, v_s=0.005, sigma0=4e5, sigma1=0.0, sigma2=3000.0)
    f, m = _force_on("lugre", p, t, x, v, nf, 2e-4, 1.2, 1e-6)
    f2, m2 = _force_on("lugre", p, t, x, v, nf, 2e-4, 1.2, 1e-6, m)
    assert np.array_equal(f, f2) and np.array_equal(m, m2) and m.size == t.size - 1 and (m >= 1).all()
    ref = pm("lugre", t, x, v, backlash=2e-4, asymmetry=1.2, rtol=1e-10, **dict(p, mu_k=1001.0)).force
    moved = _force_on("lugre", dict(p, mu_k=1001.0), t, x, v, nf, 2e-4, 1.2, 1e-6, m)[0]
    assert np.abs(moved - ref).max() <= 1e-4 * np.ptp(ref)
    d = [(_force_on("lugre", dict(p, mu_k=1000.0 + h), t, x, v, nf, 2e-4, 1.2, 1e-6, m)[0] -
          _force_on("lugre", dict(p, mu_k=1000.0 - h), t, x, v, nf, 2e-4, 1.2, 1e-6, m)[0]) / (2 * h)
         for h in (1e-4, 1e-2)]
    np.testing.assert_allclose(d[0], d[1], atol=1e-6 * np.abs(d[1]).max())
    with pytest.raises(ValueError, match=r"substeps: must be 400 integers in \[1, 65536\]"):
        _force_on("lugre", p, t, x, v, nf, 2e-4, 1.2, 1e-6, np.zeros(t.size - 1, dtype=np.int32))


# ---------------------------------------------------------------------------------------------
# Profile-likelihood intervals
# ---------------------------------------------------------------------------------------------
def test_profile_interval_of_a_linear_model_is_the_t_interval():
    # capped viscous friction with v_s held and an offset fitted: the force is linear in mu_k
    # and the offset, so the profile of the sum of squares is exactly the parabola of linear
    # regression and the profile interval is estimate +- t(0.975, n - k) stderr (closed form)
    t, x, v = sine_record(4.0, 401, 0.01, 0.5)
    f = pm("capped_viscous", t, x, v, mu_k=1000.0, v_s=0.004).force + 20.0
    f = f + 10.0 * np.random.default_rng(11).standard_normal(t.size)
    fit = stickslip.fit_friction("capped_viscous", t, x, f, v=v, fixed={"v_s": 0.004}, offset="fit",
                                 interval="profile")
    assert fit.profiled == fit.free and fit.profile_evals > 0
    assert f"95% intervals      = profile likelihood for mu_k, offset ({fit.profile_evals} model evaluations)\n" \
        in fit.report()
    tq = stats.t.ppf(0.975, fit.n_samples - len(fit.free))
    for name in fit.free:
        half = tq * fit.stderr[name]
        lo, hi = fit.ci95[name]
        # within the search's tolerance on the statistic (3 % of the half-width)
        assert lo == pytest.approx(fit.params[name] - half, abs=0.04 * half), name
        assert hi == pytest.approx(fit.params[name] + half, abs=0.04 * half), name


def test_profile_interval_ends_where_a_full_refit_reaches_the_threshold():
    # the Stribeck law on one record: each end of v_s's and mu_k's profile intervals, held
    # fixed in a full refit of the other parameters (scipy's optimiser from the estimate), must
    # raise the sum of squares by t^2 s^2 (variance inflation included) within the tolerance
    t, x, v = sine_record(duration=2.0, n=301)
    f = pm("stribeck", t, x, v, **STRIBECK).force
    f = f + 0.01 * np.random.default_rng(5).standard_normal(f.size)
    names = ("mu_s", "mu_k", "v_s", "c_v")
    kw = dict(v=v, normal_force=1.0, n_starts=1)
    fit = stickslip.fit_friction("stribeck", t, x, f, fixed=STRIBECK_FIXED, interval="profile",
                                 params0={k: STRIBECK[k] for k in names}, **kw)
    ssr0 = fit.rmse ** 2 * fit.n_samples
    unit = fit.residual_sd ** 2 * fit.variance_inflation
    tq = stats.t.ppf(0.975, fit.n_samples - len(fit.free))
    for name in ("v_s", "mu_k"):
        for end in fit.ci95[name]:
            others = {k: fit.params[k] for k in names if k != name}
            others["mu_s"] = max(others["mu_s"], 1.001 * end) if name == "mu_k" else others["mu_s"]
            refit = stickslip.fit_friction("stribeck", t, x, f, fixed=dict(STRIBECK_FIXED, **{name: end}),
                                           params0=others, interval="wald", **kw)
            tau = math.sqrt(max(refit.rmse ** 2 * refit.n_samples - ssr0, 0.0) / unit)
            # the chord refit's sum of squares is an upper bound of the full refit's: the end
            # is at most a little inside the exact one
            assert tau == pytest.approx(tq, rel=0.08), (name, end, tau, tq)


def test_profile_interval_stops_at_a_bound_and_flags_it():
    # no play in the data, backlash fitted: the profile reaches the bound 0 below the
    # threshold; the interval starts at 0 and the parameter is flagged at its bound
    truth, fixed = STATE_CASES["lugre"]
    t, x, f, v = noisy_records("lugre", truth, 10.0, seed=7, n=401)
    fit = stickslip.fit_friction("lugre", t, x, f, v=v, fixed=fixed, backlash="fit", n_starts=1,
                                 interval="profile")
    assert fit.ci95["backlash"][0] == pytest.approx(0.0, abs=1e-12)
    assert "backlash" in fit.at_bound


def test_interval_option_is_checked():
    t, x, v = sine_record(2.0, 101)
    f = pm("coulomb", t, x, v, mu_s=1.0, mu_k=1.0, v_s=1e-3).force
    with pytest.raises(ValueError, match="interval: must be one of auto, wald, profile"):
        stickslip.fit_friction("coulomb", t, x, f, v=v, interval="bootstrap")


def test_fit_runs_blas_on_one_thread_and_restores_it():
    """Inside a fit the BLAS libraries loaded (numpy's, scipy's) run on one thread (their idle
    threads spun between the optimiser's small SVDs); after it they are as before (two threads
    set here). Checked by threadpoolctl's own report, from within the model's evaluations."""
    threadpoolctl = pytest.importorskip("threadpoolctl")
    import scipy.linalg  # noqa: F401  (loads scipy's BLAS too)

    def blas_threads() -> list[int]:
        return [d["num_threads"] for d in threadpoolctl.threadpool_info() if d["user_api"] == "blas"]

    t, x, _ = sine_record(n=201)
    f = stickslip.prescribed_motion("coulomb", t, x, normal_force=N_LOAD, mu_s=0.5, mu_k=0.4, v_s=0.001).force
    f = f + np.random.default_rng(3).normal(0.0, 5.0, f.size)
    seen: list[list[int]] = []
    model = identify._model_mesh

    def spy(*args, **kwargs):
        seen.append(blas_threads())
        return model(*args, **kwargs)

    with threadpoolctl.threadpool_limits(limits=2, user_api="blas"), pytest.MonkeyPatch.context() as mp:
        mp.setattr(identify, "_model_mesh", spy)
        identify.fit_friction("coulomb", t, x, f, fixed={"v_s": 0.001}, n_starts=1, interval="wald")
        after = blas_threads()
    assert after and all(n == 2 for n in after)
    # the start's evaluation comes before the optimiser; every one after it sees one thread
    assert len(seen) > 2 and all(n == 1 for counts in seen[1:] for n in counts)


def test_a_perfect_fit_has_unbounded_information_criteria():
    """Noise-free data that the model reproduces from the start (the sum of squares exactly 0):
    the fit ends with rmse 0 and AIC = BIC = -inf (the Gaussian likelihood is unbounded), not
    with a math domain error."""
    t, x, _ = sine_record(n=201)
    f = stickslip.prescribed_motion("coulomb", t, x, normal_force=N_LOAD, mu_s=0.5, mu_k=0.4, v_s=0.001).force
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = identify.fit_friction("coulomb", t, x, f, fixed={"v_s": 0.001}, normal_force=N_LOAD,
                                    params0={"mu_s": 0.5, "mu_k": 0.4}, n_starts=1, interval="wald")
    assert fit.rmse == 0.0 and fit.aic == -math.inf and fit.bic == -math.inf
    assert fit.params["mu_k"] == pytest.approx(0.4, rel=1e-12)


# ---------------------------------------------------------------------------------------------
# Identification at its edges: intervals at a bound and with mu_s = mu_k, calibrated prediction
# intervals, restarts from a lower point, backlash starts, nuisance terms per record, the report
# against lmfit's, refusals
# ---------------------------------------------------------------------------------------------
DAHL = STATE_CASES["dahl"][0]


def test_no_motion_is_refused_at_once():
    t, x, v = sine_record(n=201)
    f = pm("dahl", t, x, v, **DAHL).force
    with pytest.raises(ValueError, match=r"x: every sample is 0.0 m \(no motion\)"):
        stickslip.fit_friction("dahl", t, np.zeros_like(x), f)
    with pytest.raises(ValueError, match=r"x\[1\]: every sample is 0.0 m"):
        stickslip.fit_friction("dahl", [t, t], [x, np.zeros_like(x)], [f, f])


def test_messages_show_plain_numbers():
    t = np.array([0.0, 1.0, 1.0, 2.0])
    with pytest.raises(ValueError) as err:
        stickslip.fit_friction("coulomb", t, np.arange(4.0), np.arange(4.0))
    assert "np.float64" not in str(err.value) and "t[2] = 1.0" in str(err.value)


def test_prediction_interval_with_mu_s_equal_to_mu_k():
    # the delta method's step keeps mu_k <= mu_s: from mu_s = mu_k it steps mu_k down (and
    # mu_s up); the band is finite and as wide as the residual scatter or wider
    t, x, v = sine_record(n=401)
    f = pm("stribeck", t, x, v, **{k: 1000.0 * val if k in ("mu_s", "mu_k", "c_v") else val
                                   for k, val in STRIBECK.items()}).force
    f = f + 10.0 * np.random.default_rng(3).standard_normal(f.size)
    fit = stickslip.fit_friction("stribeck", t, x, f, v=v, fixed=STRIBECK_FIXED, interval="wald")
    import dataclasses
    same = dataclasses.replace(fit, params=dict(fit.params, mu_s=fit.params["mu_k"]))
    force, lower, upper = same.predict(t, x, v, interval=0.95)
    assert np.isfinite(lower).all() and np.isfinite(upper).all()
    assert np.all(upper - force >= 1.959 * fit.residual_sd)


def backlash_at_zero_draws(draws: int, seed0: int = 4000) -> tuple[float, float, float, float]:
    """Dahl records with no play (backlash 0, at its bound), backlash fitted: the fraction of
    the parameters' 95 % intervals holding the truth (all draws and parameters but the
    backlash), the backlash's own, the mean coverage of the 95 % prediction interval on a
    held-out record's new measurements, and the largest median half-width of that band over
    the noise's standard deviation."""
    rng = np.random.default_rng(seed0)
    held_t, held_x, held_v = sine_record(2.0, 401, 0.007, 0.75, phase=0.5)
    exact = pm("dahl", held_t, held_x, held_v, **DAHL).force
    hits, n_int, back, cover, widest = 0, 0, 0, [], 0.0
    for seed in range(seed0, seed0 + draws):
        t, x, f, v = noisy_records("dahl", DAHL, 10.0, seed=seed, n=401)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit = stickslip.fit_friction("dahl", t, x, f, v=v, backlash="fit")
        for k in fit.free:
            lo, hi = fit.ci95[k]
            if k == "backlash":
                back += lo <= 0.0 <= hi
            else:
                hits += lo <= DAHL[k] <= hi
                n_int += 1
        force, lower, upper = fit.predict(held_t, held_x, held_v, interval=0.95)
        new = exact + 10.0 * rng.standard_normal(exact.size)
        cover.append(np.mean((new >= lower) & (new <= upper)))
        widest = max(widest, float(np.median(upper - force)) / 10.0)
    return hits / n_int, back / draws, float(np.mean(cover)), widest


def test_intervals_at_a_bound_cover_95_percent():
    # 50 draws (3.4 s of CPU): with the backlash at its bound, the other parameters' intervals
    # and the prediction band on a held-out record each cover between 0.90 and 0.99, and the
    # band stays within a few noise deviations (the delta method's tangent at the bound, times
    # a standard error as large as the amplitude, gave bands of meganewtons on a 2 kN force).
    # Measured: parameters 0.973, band 0.948, widest median half-width 2.05 noise deviations
    params, back, cover, widest = backlash_at_zero_draws(50)
    assert 0.90 <= params <= 0.99 and back >= 0.9, (params, back)
    assert 0.90 <= cover <= 0.99 and widest < 3.0, (cover, widest)


def test_calibrated_prediction_intervals_cover_as_stated():
    # four training records, AR(1) noise (lag-1 0.8): the intervals calibrated on the held-out
    # records' residuals (leave one record out) cover 50 % and 95 % of new records' samples
    rng = np.random.default_rng(21)
    shapes = [(4.0, 0.01, 0.5, 0.0), (2.0, 0.004, 1.0, 0.3), (3.0, 0.007, 0.75, 0.9), (2.0, 0.012, 0.6, 1.7)]
    recs = [sine_record(d, 401, a, fr, ph) for d, a, fr, ph in shapes]
    t, x, v = [r[0] for r in recs], [r[1] for r in recs], [r[2] for r in recs]
    f = [pm("dahl", *r, **DAHL).force + ar1_noise(rng, r[0].size, 10.0, 0.8) for r in recs]
    fit = stickslip.fit_friction("dahl", t, x, f, v=v, calibrate=True)
    assert fit.heldout_residuals.size == sum(ti.size for ti in t)
    new_t, new_x, new_v = sine_record(3.0, 401, 0.009, 0.8, phase=0.4)
    exact = pm("dahl", new_t, new_x, new_v, **DAHL).force
    for q in (0.5, 0.95):
        force, lower, upper = fit.predict(new_t, new_x, new_v, interval=q)
        np.testing.assert_allclose(upper - force, np.quantile(np.abs(fit.heldout_residuals), q))
        inside = [np.mean(np.abs(exact + ar1_noise(np.random.default_rng(500 + s), exact.size, 10.0, 0.8)
                                 - force) <= upper - force) for s in range(40)]
        assert abs(np.mean(inside) - q) <= 0.05, (q, np.mean(inside))
    with pytest.raises(ValueError, match="calibrate: needs several records"):
        stickslip.fit_friction("dahl", t[0], x[0], f[0], v=v[0], calibrate=True)


def test_select_calibrates_its_fits_by_the_held_out_records():
    t, x, f, v = three_records("dahl", DAHL, 10.0, seed=8, n=201)
    sel = stickslip.select_friction_law(["coulomb", "dahl"], t, x, f, v=v, groups=["a", "a", "b"])
    assert sel.folds == "groups" and all(len(s) == 2 for s in sel.fold_scores.values())
    assert sel.fits["dahl"].heldout_residuals.size == sum(ti.size for ti in t)
    for kw, match in (({"groups": ["a", "a"]}, "one label per record"), ({"groups": ["a"] * 3}, "2 distinct"),
                      ({"groups": ["a", "b", "c"], "cv": "blocks"}, "only with cv='groups'")):
        with pytest.raises(ValueError, match=match):
            stickslip.select_friction_law(["coulomb", "dahl"], t, x, f, v=v, **kw)


def first_search_cut_short(monkeypatch) -> None:
    """The first local search of the fits that follow stops after two evaluations and reports
    success, as on a tolerance; the later ones run to their end."""
    import scipy.optimize
    real = scipy.optimize.least_squares
    calls = []

    def first_short(fun, x0, **kw):
        calls.append(1)
        sol = real(fun, x0, **(dict(kw, max_nfev=2) if len(calls) == 1 else kw))
        sol.status, sol.success = 2, True
        return sol
    monkeypatch.setattr(scipy.optimize, "least_squares", first_short)


def test_a_fit_stopped_short_restarts_from_the_probes_lower_point(monkeypatch):
    # the first local search stops after two evaluations, as on a tolerance: the probe about
    # its end finds a lower point, a second search from it reaches the minimum
    t, x, v = sine_record(n=201)
    f = pm("dahl", t, x, v, **DAHL).force + 10.0 * np.random.default_rng(2).standard_normal(t.size)
    ref = stickslip.fit_friction("dahl", t, x, f, v=v)
    first_search_cut_short(monkeypatch)
    fit = stickslip.fit_friction("dahl", t, x, f, v=v, params0={"mu_k": 500.0, "sigma0": 1e5, "dahl_alpha": 1.0})
    assert fit.restarts >= 1 and fit.success and fit.probe_gain <= fit.redchi
    assert fit.chisqr == pytest.approx(ref.chisqr, rel=1e-4)


def test_a_profiles_lower_point_counts_only_where_the_model_is_lower(monkeypatch):
    # the profiles refit on the optimum's frozen substeps; a lower sum of squares they report
    # is checked with the model itself. A claimed point far off (mu_k doubled), where the
    # model is far higher, is no lower point: the fit succeeds without a restart. The true
    # lower point of a search cut short (the probe disabled, every parameter profiled) starts
    # a restart that reaches the uncut fit's minimum.
    t, x, v = sine_record(n=201)
    f = pm("dahl", t, x, v, **DAHL).force + 10.0 * np.random.default_rng(2).standard_normal(t.size)
    ref = stickslip.fit_friction("dahl", t, x, f, v=v, interval="profile")
    real_profiles = identify._profile_intervals

    def claims_lower(*args, **kw):
        out = real_profiles(*args, **kw)
        p_far = args[6].copy()
        p_far[0] *= 2.0                        # mu_k
        return out[:4] + ((out[4][0] - 100.0 * ref.chisqr, "mu_k", float(p_far[0]), p_far),)
    monkeypatch.setattr(identify, "_profile_intervals", claims_lower)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fit = stickslip.fit_friction("dahl", t, x, f, v=v, interval="profile")
    assert fit.success and fit.restarts == 0 and fit.chisqr == pytest.approx(ref.chisqr, rel=1e-6)
    monkeypatch.setattr(identify, "_profile_intervals", real_profiles)
    first_search_cut_short(monkeypatch)
    monkeypatch.setattr(identify, "_probe", lambda res, u, *a: (0.0, u, ""))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fit = stickslip.fit_friction("dahl", t, x, f, v=v, interval="profile",
                                     params0={"mu_k": 500.0, "sigma0": 1e5, "dahl_alpha": 1.0})
    assert fit.restarts >= 1 and fit.success
    assert fit.chisqr == pytest.approx(ref.chisqr, rel=1e-4)


def test_lugre_on_the_damper_holds_its_backlash_at_the_lower_bound():
    # On the ten 36 lb records the cost of LuGre jumps between a backlash of exactly 0 and one
    # just above (136-174 reduced chi-squares higher at 1e-12 to 1e-7 m, the other parameters
    # held): a search moved strictly inside the bounds cannot start from the profile's lower
    # point at 0. The restart searches on that face: the fit ends at backlash 0 with success,
    # as low as the fit with the backlash fixed at 0 (to a reduced chi-square)
    from cases import identify as ci
    recs = [r for r, _ in ci.load_groups(stickslip.damper_files(36))["36lb"]]
    kw = dict(fixed=ci.fixed_for("lugre"), asymmetry="fit", rtol=ci.RTOL, diff_step=ci.DIFF_STEP, interval="wald")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fit = stickslip.fit_friction("lugre", recs, backlash="fit", **kw)
    at_zero = stickslip.fit_friction("lugre", recs, backlash=0.0, **kw)
    assert fit.success and fit.restarts >= 1 and fit.params["backlash"] == 0.0 and "backlash" in fit.at_bound
    assert fit.chisqr <= at_zero.chisqr + fit.redchi
    data = identify._records(recs, None, None, None, None)
    forces = np.concatenate([d.force for d in data])

    def ssr(backlash: float) -> float:
        p = dict(fit.params, backlash=backlash)
        r = np.concatenate([identify._model("lugre", d, identify._record_params(p, i), ci.RTOL)
                            for i, d in enumerate(data)]) - forces
        return float(r @ r)
    assert ssr(1e-9) - ssr(0.0) > 10.0 * fit.redchi


@pytest.mark.parametrize("law", ["lugre", "gms"])
def test_laws_with_states_on_the_damper_reach_lmfits_minimum(law):
    # LuGre and GMS on the ten 36 lb records (backlash and asymmetry fitted, as the lmfit
    # benchmark): success, and a sum of squares at most a reduced chi-square above that of the
    # same fit written with lmfit from the same start (they used to stop with success=False,
    # a profile finding a point 1.7 and 3.8 reduced chi-squares lower)
    pytest.importorskip("lmfit")
    from benchmarks.lmfit_compare import _lmfit_fit
    from cases import identify as ci
    recs = [r for r, _ in ci.load_groups(stickslip.damper_files(36))["36lb"]]
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        fit = stickslip.fit_friction(law, recs, fixed=ci.fixed_for(law), backlash="fit", asymmetry="fit",
                                     rtol=ci.RTOL, diff_step=ci.DIFF_STEP, interval="wald")
    out, _ = _lmfit_fit(law, recs, fit, ci.RTOL, ci.DIFF_STEP)
    assert fit.success and fit.chisqr <= float(out.residual @ out.residual) + fit.redchi


def test_static_law_with_backlash_fitted_finds_it():
    # Coulomb with a 1 mm play: the cost is a staircase in the backlash; the starts from the
    # scan of backlash widths find the play within its interval
    truth = dict(mu_s=1500.0, mu_k=1000.0, v_s=1e-3)
    t, x, f, v = noisy_records("coulomb", truth, 10.0, seed=5, n=801, backlash=0.001)
    fit = stickslip.fit_friction("coulomb", t, x, f, v=v, fixed={"v_s": 1e-3}, backlash="fit")
    assert fit.success and fit.n_starts == 1 + identify.BACKLASH_STARTS
    lo, hi = fit.ci95["backlash"]
    assert lo <= 0.001 <= hi and hi - lo < 0.0005


def test_offsets_per_record_are_not_carried_over():
    # two records read through load cells 40 N and -25 N off zero: fitted per record, each
    # offset is recovered and a new record (no offset) is predicted without one; one common
    # offset would carry their compromise over
    t, x, f, v = noisy_records("dahl", DAHL, 10.0, seed=12, n=401)
    f = [f[0] + 40.0, f[1] - 25.0]
    fit = stickslip.fit_friction("dahl", t, x, f, v=v, offset="per_record")
    assert fit.free[-2:] == ("offset[0]", "offset[1]") and fit.params["offset"] == 0.0
    for i, want in enumerate((40.0, -25.0)):
        lo, hi = fit.ci95[f"offset[{i}]"]
        assert lo <= want <= hi, (i, lo, hi)
    new_t, new_x, new_v = sine_record(3.0, 401, 0.009, 0.8, phase=0.4)
    exact = pm("dahl", new_t, new_x, new_v, **DAHL).force
    assert abs(np.mean(fit.predict(new_t, new_x, new_v) - exact)) < 3.0
    common = stickslip.fit_friction("dahl", t, x, f, v=v, offset="fit")
    assert abs(np.mean(common.predict(new_t, new_x, new_v) - exact)) > 5.0
    with pytest.raises(ValueError, match="backlash: must be a number or 'fit', got 'per_record'"):
        stickslip.fit_friction("dahl", t, x, f, v=v, backlash="per_record")


def test_asymmetry_and_drift_per_record():
    # two records of different asymmetry (1.2, 1.4): fitted per record, each is recovered within
    # its interval and a new record is predicted symmetric (the default), not at their mean
    t, x, v = [], [], []
    f = []
    rng = np.random.default_rng(13)
    for (dur, amp, hz, ph), asym in zip(((4.0, 0.01, 0.5, 0.0), (2.0, 0.004, 1.0, 0.3)), (1.2, 1.4)):
        ti, xi, vi = sine_record(dur, 401, amp, hz, ph)
        t.append(ti), x.append(xi), v.append(vi)
        f.append(pm("dahl", ti, xi, vi, asymmetry=asym, **DAHL).force + 10.0 * rng.standard_normal(ti.size))
    fit = stickslip.fit_friction("dahl", t, x, f, v=v, asymmetry="per_record", drift="per_record")
    assert set(fit.free) >= {"asymmetry[0]", "asymmetry[1]", "drift[0]", "drift[1]"}
    assert fit.params["asymmetry"] == 1.0 and fit.units["asymmetry[1]"] == "-" and fit.units["drift[0]"] == "1/s"
    for i, want in enumerate((1.2, 1.4)):
        lo, hi = fit.ci95[f"asymmetry[{i}]"]
        assert lo <= want <= hi, (i, lo, hi)
        assert fit.ci95[f"drift[{i}]"][0] <= 0.0 <= fit.ci95[f"drift[{i}]"][1]
    new_t, new_x, new_v = sine_record(3.0, 401, 0.009, 0.8, phase=0.4)
    exact = pm("dahl", new_t, new_x, new_v, **DAHL).force
    assert np.sqrt(np.mean((fit.predict(new_t, new_x, new_v) - exact) ** 2)) < 10.0
    assert set(fit.law_params) == set(DAHL)


def test_report_matches_lmfit_on_the_same_fit():
    lmfit = pytest.importorskip("lmfit")
    t, x, v = sine_record(n=401)
    f = pm("dahl", t, x, v, **DAHL).force + 10.0 * np.random.default_rng(4).standard_normal(t.size)
    fit = stickslip.fit_friction("dahl", t, x, f, v=v)
    params = lmfit.Parameters()
    for name in fit.free:
        params.add(name, value=fit.params[name], min=fit.bounds[name][0], max=fit.bounds[name][1])

    def residual(p):
        return pm("dahl", t, x, v, rtol=fit.rtol, **{k: p[k].value for k in fit.free}).force - f
    out = lmfit.minimize(residual, params, method="least_squares")
    assert fit.chisqr == pytest.approx(out.chisqr, rel=1e-6)
    assert fit.redchi == pytest.approx(out.redchi, rel=1e-6)
    assert fit.aic_lmfit == pytest.approx(out.aic, abs=1e-3)
    assert fit.bic_lmfit == pytest.approx(out.bic, abs=1e-3)
    # the full-likelihood AIC is lmfit's plus n (1 + ln 2 pi) + 2 (the noise variance counted)
    assert fit.aic - fit.aic_lmfit == pytest.approx(t.size * (1.0 + math.log(2.0 * math.pi)) + 2.0)
    text = fit.report()
    for piece in ("optimiser          = scipy.optimize.least_squares", "chi-square", "reduced chi-square",
                  "AIC (lmfit)", "BIC (lmfit)", f"{fit.n_evaluations} in all", "bounds [",
                  "[[Correlations]] (|c| > 0.1)"):
        assert piece in text, piece
    assert fit.n_evaluations > fit.nfev
    big = [(a, b) for i, a in enumerate(fit.free) for j, b in enumerate(fit.free)
           if i < j and abs(fit.correlation[i, j]) > 0.1]
    assert all(f"C({a}, {b})" in text for a, b in big)
    assert "(|c| > 0.9)" in fit.report(min_correl=0.9)
    with pytest.raises(ValueError, match=r"min_correl: must be in \[0, 1\), got 1.5"):
        fit.report(min_correl=1.5)


def test_decimate_filters_what_the_new_rate_cannot_hold():
    # a 0.5 Hz sine sampled at 200 Hz, plus a 90 Hz tone (above the Nyquist frequency of every
    # 8th sample, 12.5 Hz): decimated by 8 the sine is kept to 1e-4 of its amplitude away from
    # the ends and the tone removed (plain subsampling folds it onto 10 Hz at full amplitude)
    from stickslip.data import Record, decimate
    t = np.arange(0.0, 8.0, 0.005)
    slow, tone = np.sin(np.pi * t), 0.3 * np.sin(2 * np.pi * 90.0 * t)
    rec = Record("r", t, slow + tone, 2.0 * (slow + tone))
    dec = rec.decimate(8)
    np.testing.assert_array_equal(dec.t, t[::8])
    inner = slice(20, -20)
    assert np.abs(dec.x - slow[::8])[inner].max() < 1e-4
    assert np.abs(rec.subsample(8).x - slow[::8]).max() > 0.25
    np.testing.assert_allclose(dec.force, 2.0 * dec.x)
    assert dec.v is None and dec.meta["decimate"] == 8
    with pytest.raises(ValueError, match="step: must be an integer >= 1, got 0"):
        decimate(t, [slow], 0)


def test_select_with_screening_chooses_as_at_full_rate():
    # three Dahl records at 200 samples a cycle: screened at 48 a cycle, the same law is
    # chosen, the folds are scored on the full-rate records, the chosen law refitted at full rate
    t, x, f, v = three_records("dahl", DAHL, 10.0, seed=8, n=401)
    kw = dict(fixed={"coulomb": {"v_s": 1e-3}})
    full = stickslip.select_friction_law(["coulomb", "dahl"], t, x, f, v=v, **kw)
    screened = stickslip.select_friction_law(["coulomb", "dahl"], t, x, f, v=v, screen=48, **kw)
    assert screened.best == full.best == "dahl" and screened.screen == 48
    assert screened.fits["dahl"].n_samples == sum(ti.size for ti in t)
    assert screened.screen_fits["dahl"].n_samples < 0.4 * screened.fits["dahl"].n_samples
    assert screened.fits["dahl"].heldout_residuals.size == sum(ti.size for ti in t)
    for law in ("coulomb", "dahl"):
        assert screened.scores[law][0] == pytest.approx(full.scores[law][0], rel=0.05), law
    assert "screening: fits to the records decimated to 48 samples per cycle" in screened.table()
    with pytest.raises(ValueError, match="screen: must be an integer >= 8"):
        stickslip.select_friction_law(["coulomb", "dahl"], t, x, f, v=v, screen=4, **kw)
    with pytest.raises(ValueError, match="screen: screening decimates whole records"):
        stickslip.select_friction_law(["coulomb", "dahl"], t[0], x[0], f[0], v=v[0], screen=48, **kw)


def test_elastoplastic_z_ba_ratio_is_fitted_up_to_its_cap():
    # the transition between z_ba and the steady deflection narrows as z_ba_ratio nears 1 and
    # its integration costs in proportion: the fit's range stops at Z_BA_RATIO_MAX
    truth, fixed = STATE_CASES["elastoplastic"]
    t, x, f, v = noisy_records("elastoplastic", truth, 10.0, seed=3, n=201)
    fit = stickslip.fit_friction("elastoplastic", t, x, f, v=v, fixed=fixed)
    assert fit.bounds["z_ba_ratio"][1] == pytest.approx(identify.Z_BA_RATIO_MAX, rel=1e-12)
    assert fit.params["z_ba_ratio"] <= identify.Z_BA_RATIO_MAX
