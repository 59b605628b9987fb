"""The engine-equivalent friction laws (stickslip.engines) against their published formulas,
engine_creep against the closed form of each law's balance on the slope, advise_engine's
budget, bad input, and (where the engine is installed) the prediction against the engine's
own run."""
from __future__ import annotations

import importlib.util
import math
import warnings

import numpy as np
import pytest

import stickslip as ss
from stickslip import engines as en

TH = math.radians(10.0)
TAN = math.tan(TH)
G, M = 9.81, 10.0


def quintic(x):
    """10 x^3 - 15 x^4 + 6 x^5, written out (Drake's step5)."""
    return 10 * x ** 3 - 15 * x ** 4 + 6 * x ** 5


# ---------------------------------------------------------------- the laws, as published
# The engines' laws are registered laws (Fortran); each against its published formula.
def mu(law, v, **p):
    return float(ss.friction_coefficient(law, v, **p))


@pytest.mark.parametrize("s", [0.0, 0.1, 0.37, 0.5, 0.99, 1.0, 1.4, 2.0, 2.9, 3.0, 7.0])
def test_drake_continuous_is_the_stribeck_model(s):
    vs, mu_s, mu_d = 2e-3, 0.5, 0.2
    got = mu("drake_continuous", s * vs, v_s=vs, mu_s=mu_s, mu_k=mu_d)
    if s < 1:
        want = mu_s * quintic(s)
    elif s < 3:
        want = mu_s - (mu_s - mu_d) * quintic((s - 1) / 2)
    else:
        want = mu_d
    assert got == pytest.approx(want, rel=1e-12, abs=1e-15)
    # odd in v (the force opposes the slip)
    assert mu("drake_continuous", -s * vs, v_s=vs, mu_s=mu_s, mu_k=mu_d) == pytest.approx(-got)


def test_drake_continuous_is_c2_at_its_knots():
    vs, mu_s, mu_d, eps = 1.0, 0.5, 0.2, 1e-4
    f = lambda v: mu("drake_continuous", v, v_s=vs, mu_s=mu_s, mu_k=mu_d)  # noqa: E731
    for knot in (1.0, 3.0):
        left = (f(knot) - f(knot - eps)) / eps
        right = (f(knot + eps) - f(knot)) / eps
        assert abs(left) < 1e-3 and abs(right) < 1e-3
    assert f(0.5) == pytest.approx(0.5 * mu_s)          # the step's midpoint


@pytest.mark.parametrize("s", [0.0, 0.25, 0.5, 0.9, 1.0, 4.0])
def test_tamsi_is_mu_s_2_minus_s(s):
    vs, mu_d = 1e-4, 0.3
    want = mu_d * s * (2 - s) if s < 1 else mu_d
    # mu_s is not read: discrete Drake has one coefficient (mu_k may exceed the default mu_s)
    assert mu("drake_tamsi", s * vs, v_s=vs, mu_k=mu_d) == pytest.approx(want, rel=1e-12, abs=1e-16)
    assert mu("drake_tamsi", s * vs, v_s=vs, mu_k=0.9) == pytest.approx(3 * want, rel=1e-12, abs=1e-16)


@pytest.mark.parametrize("v", [0.0, 1e-4, 2.4e-3, 2.5e-3, 0.01, 3.0])
def test_capped_viscous_is_newtons_min_kf_v_mu_fn(v):
    """Newton's semi-implicit contact: force min(k_f v, mu f_n), i.e. the law with
    v_s = mu f_n / k_f times f_n."""
    k_f, f_n, mu_c = 1000.0, 8.0, 0.3
    force = f_n * mu("capped_viscous", v, mu_k=mu_c, v_s=mu_c * f_n / k_f)
    assert force == pytest.approx(min(k_f * v, mu_c * f_n), rel=1e-12, abs=1e-15)


def _pyramid_friction(q, load):
    """Friction / load of a MuJoCo pyramidal contact from its four edge rows written out: the
    rows along the slip push p - q and p + q, the two across it p, each clamped at 0; p from
    the normal balance (the clamped forces add up to the load), by bisection; the friction
    is mu (f+ - f-), returned over mu."""
    def edges(p):
        return max(p - q, 0.0), max(p + q, 0.0), max(p, 0.0)
    lo, hi = -2.0 * load - q, 2.0 * load + q
    for _ in range(200):
        p = 0.5 * (lo + hi)
        fm, fp, fa = edges(p)
        lo, hi = (p, hi) if fm + fp + 2 * fa < load else (lo, p)
    fm, fp, _ = edges(0.5 * (lo + hi))
    return min(fp - fm, load) / load


@pytest.mark.parametrize("s", [0.0, 0.2, 0.5, 0.8, 1.3, 2.0, 2.5, 10.0])
def test_mujoco_pyramidal_is_the_clamped_pyramid(s):
    """With the edge speed term q = s load / 2 (the viscous slope mu/v_s at rest), the law is
    the clamped four-row balance: all four rows push up to s = 1/2, then the row against the
    slip drops out, then the rows across it (s = 2): Coulomb's cap."""
    vs, mu_c, load = 3e-4, 0.3, 5.0
    want = mu_c * _pyramid_friction(0.5 * s * load, load)
    assert mu("mujoco_pyramidal", s * vs, mu_k=mu_c, v_s=vs) == pytest.approx(want, rel=1e-9,
                                                                              abs=1e-15)


def test_engine_contacts_carry_the_whole_load():
    N = M * G * math.cos(TH)
    for engine, extra in [("mujoco", {}), ("mujoco", {"cone": "elliptic"}),
                          ("newton_semi_implicit", {}), ("drake_tamsi", {}),
                          ("newton_semi_implicit", {"n_contacts": 3})]:
        contacts = en.engine_contacts(engine, **extra)
        assert sum(load for _, _, load in contacts) == pytest.approx(N, rel=1e-12)
        assert {law for law, _, _ in contacts} <= set(ss.LAWS)


@pytest.mark.parametrize("s", [0.0, 0.3, 1.0, 2.5, 40.0])
def test_drake_lagged_is_mu_s_over_sqrt_1_plus_s2(s):
    vs, mu_d = 1e-4, 0.3
    assert float(en.drake_lagged_mu(s * vs, vs, mu_d)) == pytest.approx(mu_d * s / math.hypot(1, s),
                                                                        rel=1e-12, abs=1e-16)


def test_mujoco_impedance_follows_solimp():
    imp = (0.9, 0.95, 0.001, 0.5, 2.0)
    assert en.mujoco_impedance(imp, 0.0) == 0.9
    assert en.mujoco_impedance(imp, 0.002) == 0.95
    assert en.mujoco_impedance(imp, 0.0005) == pytest.approx(0.925)       # midpoint
    # y = x^2 / mid below the midpoint, 1 - (1 - x)^2 / (1 - mid) above
    assert en.mujoco_impedance(imp, 0.0002) == pytest.approx(0.9 + 0.05 * 0.04 / 0.5)
    assert en.mujoco_impedance(imp, 0.0008) == pytest.approx(0.9 + 0.05 * (1 - 0.04 / 0.5))
    assert en.mujoco_impedance((0.8, 0.8, 0.001, 0.5, 2.0), 0.0003) == 0.8   # flat


# ---------------------------------------------------------------- creep, closed forms
def test_drake_continuous_creep_balances_the_slope():
    for vs in (1e-4, 1e-2):
        v = ss.engine_creep("drake_continuous", stiction_tolerance=vs)
        assert 0.35 * quintic(v / vs) == pytest.approx(TAN, rel=1e-10)
    # proportional to the stiction tolerance
    assert ss.engine_creep("drake_continuous", stiction_tolerance=1e-2) == pytest.approx(
        100 * ss.engine_creep("drake_continuous", stiction_tolerance=1e-4), rel=1e-12)


def test_drake_tamsi_creep_closed_form():
    v = ss.engine_creep("drake_tamsi", stiction_tolerance=1e-3, mu_k=0.25, theta_deg=12.0)
    t = math.tan(math.radians(12.0))
    assert v == pytest.approx(1e-3 * (1 - math.sqrt(1 - t / 0.25)), rel=1e-12)
    assert 0.25 * (v / 1e-3) * (2 - v / 1e-3) == pytest.approx(t, rel=1e-12)


def test_drake_lagged_creep_closed_form():
    v = ss.engine_creep("drake_lagged", stiction_tolerance=2e-4)
    s = v / 2e-4
    assert 0.30 * s / math.sqrt(1 + s * s) == pytest.approx(TAN, rel=1e-12)


def test_newton_creep_is_viscous():
    v = ss.engine_creep("newton_semi_implicit", k_f=500.0, n_contacts=4)
    assert v == pytest.approx(M * G * math.sin(TH) / (4 * 500.0), rel=1e-12)
    # a weak k_f saturates every contact: mu >= tan(theta) still holds the box at some speed
    assert math.isfinite(ss.engine_creep("newton_semi_implicit", k_f=1e-3, n_contacts=4))
    assert ss.engine_creep("newton_semi_implicit", k_f=100.0, mu=0.1) == math.inf


def _mujoco_kb(tc, dmax):
    """MuJoCo's damping of a constraint from solref = (timeconst, dampratio = 1), as its
    documentation gives it: b = 2 / (dmax timeconst)."""
    return 2 / (dmax * tc)


def _mujoco_elliptic_steps(d: float, ir: float, h: float = 2e-3, n: int = 20000) -> float:
    """The box's speed after n steps of MuJoCo's soft-constraint update, written from its
    documentation rather than from a closed form: four contacts of one body of mass M, one
    friction row each along the slope (elliptic cone, inside it), A = J M^-1 J^T (all 1/M),
    R = (1 - d)/d diag(A) / impratio, the reference acceleration -b v; each step solves
    (A + R) f = a_ref - a0 for the row forces and advances v by h (a0 + sum f / M)."""
    import numpy as np
    a0 = G * math.sin(TH)                      # the unconstrained acceleration down the slope
    A = np.full((4, 4), 1 / M)
    R = np.diag(np.full(4, (1 - d) / d / M / ir))
    b, v = _mujoco_kb(0.02, d), 0.0
    for _ in range(n):
        f = np.linalg.solve(A + R, np.full(4, -b * v - a0))
        v += h * (a0 + f.sum() / M)
    return v


@pytest.mark.parametrize("ir", [1.0, 10.0])
def test_mujoco_elliptic_creep_is_the_steady_state_of_its_steps(ir):
    """Flat impedance d: engine_creep is where MuJoCo's own step update (simulated here, a
    different route from the closed form) settles."""
    d = 0.9
    v = ss.engine_creep("mujoco", cone="elliptic", impratio=ir, solimp=(d, d, 0.001, 0.5, 2),
                        aspect=0.0)
    assert v == pytest.approx(_mujoco_elliptic_steps(d, ir), rel=1e-6)


def test_mujoco_timestep_enters_only_below_twice_timeconst():
    base = ss.engine_creep("mujoco", timestep=0.002)
    assert ss.engine_creep("mujoco", timestep=0.0005) == base
    assert ss.engine_creep("mujoco", timestep=0.02) > 1.5 * base      # t_c = 2 h = 0.04 s


@pytest.mark.parametrize("engine,extra", [("drake_continuous", {}), ("drake_tamsi", {}),
                                          ("drake_lagged", {}),
                                          ("mujoco", {"cone": "elliptic"}),
                                          ("mujoco", {"cone": "pyramidal"}),
                                          ("newton_semi_implicit", {"n_contacts": 4})])
def test_engine_mu_balances_at_the_creep(engine, extra):
    if engine == "newton_semi_implicit":
        extra = {**extra, "k_f": 300.0}
    v = ss.engine_creep(engine, **extra)
    assert float(en.engine_mu(engine, v, **extra)) == pytest.approx(TAN, rel=1e-6)


# ---------------------------------------------------------------- advice
@pytest.mark.parametrize("engine,extra", [("drake_continuous", {}), ("drake_tamsi", {}),
                                          ("drake_lagged", {}),
                                          ("mujoco", {"cone": "elliptic"}),
                                          ("mujoco", {"cone": "pyramidal"}),
                                          ("newton_semi_implicit", {})])
@pytest.mark.parametrize("budget", [1e-4, 1e-2])
def test_advise_engine_meets_the_budget_within_2x(engine, extra, budget):
    a = ss.advise_engine(engine, budget, 20.0, settle=0.0, **extra)
    name = en.ADVISED_SETTING[engine]
    creep = ss.engine_creep(engine, **extra, **{name: a[name]}) * 20.0
    assert creep <= budget * (1 + 1e-9)
    assert creep >= budget / 2
    assert a["creep"] == pytest.approx(creep)
    if engine in ("drake_tamsi", "drake_lagged"):
        assert a["timestep"] is None
    else:
        assert a["steps_per_second"] == pytest.approx(1 / a["timestep"])


def test_advise_engine_cost_of_drake_continuous_is_its_stability_bound():
    a = ss.advise_engine("drake_continuous", 1e-3, 20.0, settle=0.0)
    N = M * G * math.cos(TH)
    slope = 0.35 * 1.875 * N / a["stiction_tolerance"]     # steepest dF/dv: step5'(1/2) = 15/8
    # the box's yaw on its four corners: I_z = m (0.2^2 + 0.2^2) / 12, lever^2 = 0.1^2 + 0.1^2
    lam = slope * (0.1 ** 2 + 0.1 ** 2) / (M * (0.2 ** 2 + 0.2 ** 2) / 12)
    assert a["timestep"] == pytest.approx(2 / lam)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("call,match", [
    (lambda: ss.engine_creep("havok"), "unknown engine 'havok'; accepted: drake_continuous"),
    (lambda: ss.engine_creep("bullet"), "no smooth law"),
    (lambda: ss.engine_creep("drake_sap"), "no smooth law"),
    (lambda: ss.engine_creep("mujoco", stiction_tolerance=1e-3), "mujoco has no setting "
     "'stiction_tolerance'; accepted: cone, impratio"),
    (lambda: ss.engine_creep("drake_tamsi", impratio=3), "accepted: stiction_tolerance"),
    (lambda: ss.engine_creep("mujoco", cone="round"), "accepted: pyramidal, elliptic"),
    (lambda: ss.engine_creep("newton_semi_implicit", k_f=-1.0), "k_f must be a finite number > 0, got -1"),
    (lambda: ss.engine_creep("drake_tamsi", stiction_tolerance=0), "must be a finite number > 0, got 0"),
    (lambda: ss.engine_creep("mujoco", n_contacts=2.5), "n_contacts must be an integer"),
    (lambda: ss.engine_creep("mujoco", solref=(0.02, -1)), "solref must be"),
    (lambda: ss.advise_engine("mujoco", 0.0, 20.0), "max_creep must be a finite number > 0"),
    (lambda: ss.advise_engine("mujoco", -1e-3, 20.0), "max_creep must be"),
    (lambda: ss.advise_engine("mujoco", 1e-3, 0.0), "t_end must be"),
    (lambda: ss.advise_engine("mujoco", 1e-3, 20.0, impratio=2), "chooses impratio"),
    (lambda: ss.advise_engine("ode", 1e-3, 20.0), "unknown engine 'ode'"),
    (lambda: ss.advise_engine("drake_tamsi", 1e-3, 20.0, mu_k=0.1), "cannot hold the box"),
    (lambda: ss.advise_engine("mujoco", 1e-3, 20.0, mu=0.1), "cannot hold the box"),
])
def test_bad_input_one_line(call, match):
    with pytest.raises(ValueError, match=match) as err:
        call()
    assert "\n" not in str(err.value)


# ---------------------------------------------------------------- against the engines
needs_mujoco = pytest.mark.skipif(importlib.util.find_spec("mujoco") is None,
                                  reason="mujoco is not installed (pip install .[engines])")
needs_bullet = pytest.mark.skipif(importlib.util.find_spec("pybullet") is None,
                                  reason="pybullet is not installed (pip install .[engines])")


@needs_mujoco
@pytest.mark.parametrize("cone,ir,h,tol", [("elliptic", 1.0, 0.002, 1e-4),
                                           ("elliptic", 10.0, 0.001, 1e-4),
                                           ("pyramidal", 1.0, 0.002, 1e-4),
                                           ("pyramidal", 30.0, 0.002, 1e-4)])
def test_mujoco_creep_matches_the_engine(cone, ir, h, tol):
    from cases import engines as ce
    out = ce.mujoco_slope(timestep=h, cone=cone, impratio=ir, t_end=2.0)
    assert out["n_contacts"] == 4
    pred = ss.engine_creep("mujoco", cone=cone, impratio=ir, timestep=h, mu=ce.MU,
                           aspect=ce.HALF[2] / ce.HALF[0])
    assert out["creep"] == pytest.approx(pred, rel=tol)


@needs_mujoco
@pytest.mark.parametrize("cone,mu", [("pyramidal", 0.5), ("pyramidal", 0.3), ("elliptic", 0.3)])
def test_mujoco_flat_impedance_creep_is_the_engines(cone, mu):
    """Flat impedance d = 0.9, both pyramid regimes (mu = 0.5 >= 2 tan(theta): all four edges
    push; mu = 0.3: the edge against the slip drops out) and the elliptic cone: engine_creep
    against MuJoCo's own run of the same settings (`mujoco_slope_xml`), not against its closed
    form typed again."""
    import mujoco
    import numpy as np
    from cases import engines as ce
    settings = dict(cone=cone, mu=mu, solimp=(0.9, 0.9, 0.001, 0.5, 2), aspect=ce.HALF[2] / ce.HALF[0])
    m = mujoco.MjModel.from_xml_string(en.mujoco_slope_xml(**settings))
    d = mujoco.MjData(m)
    t, x = [0.0], [0.0]
    for _ in range(1000):                                   # 2 s at the default 2 ms step
        mujoco.mj_step(m, d)
        t.append(d.time)
        x.append(float(d.qpos[0]))
    assert d.ncon == 4
    assert ce._creep_of(np.array(t), np.array(x)) == pytest.approx(ss.engine_creep("mujoco", **settings),
                                                                   rel=1e-6)


@needs_mujoco
def test_mujoco_inverse_weight_is_one_over_m():
    """engine_creep takes a free box's translational inverse weight as 1 / m: MuJoCo's own."""
    import mujoco
    from cases import engines as ce
    m = mujoco.MjModel.from_xml_string(en.mujoco_slope_xml(cone="elliptic", m=ce.MASS))
    assert m.body_invweight0[1, 0] == pytest.approx(1 / ce.MASS, rel=1e-9)


@needs_bullet
def test_bullet_holds_the_box_to_a_tiny_creep():
    """Bullet has no smooth law; its box creeps far less than MuJoCo's at the
    engines' defaults (measured, not predicted)."""
    from cases import engines as ce
    out = ce.bullet_slope(t_end=2.0)
    assert abs(out["creep"]) < 0.1 * ss.engine_creep("mujoco")


needs_newton = pytest.mark.skipif(importlib.util.find_spec("newton") is None,
                                  reason="newton is not installed (pip install newton warp-lang; "
                                         "not part of the extras: its CPU path compiles kernels "
                                         "for minutes on first use)")


@needs_newton
def test_newton_creep_matches_the_engine():
    from cases import engines as ce
    out = ce.newton_slope(t_end=1.0)
    assert out["n_contacts"] == 4
    assert out["creep"] == pytest.approx(ss.engine_creep("newton_semi_implicit", mu=ce.MU),
                                         rel=0.02)


needs_drake = pytest.mark.skipif(importlib.util.find_spec("pydrake") is None,
                                 reason="drake is not installed (pip install .[drake]; "
                                        "scripts/setup leaves it out: it is large)")


@needs_drake
@pytest.mark.parametrize("mode,vs,theta", [("tamsi", 1e-4, 10.0), ("tamsi", 1e-2, 10.0),
                                           ("continuous", 1e-2, 10.0), ("lagged", 1e-4, 10.0),
                                           ("lagged", 1e-3, 10.0), ("lagged", 1e-4, 5.0),
                                           ("lagged", 1e-4, 15.0)])
def test_drake_creep_matches_the_engine(mode, vs, theta):
    """Drake's own runs creep as the laws predict; for the lagged model, whose form was
    identified on the 10-degree slope, the other angles test the form itself."""
    from cases import engines as ce
    out = ce.drake_slope(mode=mode, stiction_tolerance=vs, timestep=1e-3, t_end=2.0,
                         theta_deg=theta)
    pred = ss.engine_creep(f"drake_{mode}", stiction_tolerance=vs, theta_deg=theta)
    assert out["creep"] == pytest.approx(pred, rel=0.02)


def test_engines_driver_quick(tmp_path):
    """python -m cases.engines --quick writes its tables and figures, the exact methods'
    creep is zero, every predicted creep sits within 2 % of the measured one, and the
    versions file names every engine that ran."""
    from cases import _common as c
    from cases import engines as ce
    ce.main(["--quick", "--outdir", str(tmp_path)])
    rows = c.read_csv(tmp_path / "engines_slope.csv")
    for i, eng in enumerate(rows["engine [-]"]):
        meas = float(rows["creep_speed [m/s]"][i])
        pred = rows["predicted_creep_speed [m/s]"][i]
        if eng in ("event_driven", "moreau"):
            assert meas == 0.0
        elif pred:
            assert meas == pytest.approx(float(pred), rel=0.02), (eng, rows["setting [-]"][i])
    versions = c.read_csv(tmp_path / "engines_versions.csv")["engine [-]"]
    assert set(ce.versions()) <= set(versions)
    b = c.read_csv(tmp_path / "engines_belt.csv")
    exact = b["run [-]"].index("event_driven")
    assert float(b["stick_fraction [-]"][exact]) > 0.2       # the paper's law sticks
    for f in ("engines_slope_creep.png", "engines_belt.png", "engines_slope.md"):
        assert (tmp_path / f).stat().st_size > 0


def test_engines_replot_without_results_is_a_usage_error(tmp_path, capsys):
    from cases import engines as ce
    with pytest.raises(SystemExit) as err:
        ce.main(["--replot", "--outdir", str(tmp_path)])
    assert err.value.code == 2
    msg = capsys.readouterr().err.strip().splitlines()[-1]
    assert "has no engines_slope.csv" in msg


def test_engines_driver_keeps_results_of_engines_not_installed(tmp_path, monkeypatch, capsys):
    """Run into a directory whose results were made with an engine absent here (the committed
    docs/figures and Drake), the driver writes nothing and says why; --force would."""
    from cases import _common as c
    from cases import engines as ce
    c.write_csv(tmp_path / "engines_versions.csv", ["engine [-]", "version [-]"],
                [["mujoco", "4.0.0"], ["drake", "1.51.1"]])
    monkeypatch.setattr(ce, "versions", lambda: {"mujoco": "4.0.0"})
    assert ce.main(["--outdir", str(tmp_path)]) == []
    err = capsys.readouterr().err
    assert "holds results of drake" in err and "pip install .[drake]" in err and "--force" in err
    assert [p.name for p in tmp_path.iterdir()] == ["engines_versions.csv"]


# ---------------------------------------------------------------- edges of the domain
def test_solimp_takes_three_to_five_numbers_as_mujoco_does():
    """MuJoCo fills solimp's midpoint and power with 0.5 and 2 where they are not given."""
    full = ss.engine_creep("mujoco", solimp=(0.8, 0.9, 0.002, 0.5, 2.0))
    assert ss.engine_creep("mujoco", solimp=(0.8, 0.9, 0.002)) == full
    assert ss.engine_creep("mujoco", solimp=[0.8, 0.9, 0.002, 0.5]) == full
    with pytest.raises(ValueError, match="solimp must be 3 to 5 numbers"):
        ss.engine_creep("mujoco", solimp=(0.8, 0.9))


def test_numpy_scalars_are_numbers():
    assert ss.engine_creep("mujoco", impratio=np.float32(3)) == ss.engine_creep("mujoco", impratio=3.0)
    assert ss.engine_creep("newton_semi_implicit", n_contacts=np.int64(4), k_f=np.float64(500)) \
        == ss.engine_creep("newton_semi_implicit", n_contacts=4, k_f=500.0)
    a = ss.advise_engine("drake_tamsi", np.float32(1e-3), np.int32(20), settle=np.float64(0.0))
    assert a == ss.advise_engine("drake_tamsi", float(np.float32(1e-3)), 20.0, settle=0.0)
    with pytest.raises(ValueError, match="max_creep must be a real number, got '1e-3'"):
        ss.advise_engine("drake_tamsi", "1e-3", 20.0)


def test_drake_continuous_between_mu_d_and_mu_s_slides():
    """With mu_d < tan(theta) < mu_s the law has a creep below v_s, but past 3 v_s it gives
    mu_d < tan(theta): metastable, so infinite with the named warning; below mu_d finite."""
    th = math.degrees(math.atan(0.32))                      # mu_d 0.30 < 0.32 < mu_s 0.35
    with pytest.warns(en.EngineDomainWarning, match="between mu_d = 0.3 and mu_s = 0.35"):
        assert ss.engine_creep("drake_continuous", theta_deg=th) == math.inf
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert math.isfinite(ss.engine_creep("drake_continuous", theta_deg=16.0))  # tan 0.287


@pytest.mark.parametrize("cone,zeta,warns", [("pyramidal", 1.0, False), ("pyramidal", 0.75, False),
                                             ("pyramidal", 0.6, True), ("elliptic", 0.6, False),
                                             ("elliptic", 0.4, True)])
def test_mujoco_rocking_threshold_warns(cone, zeta, warns):
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        v = ss.engine_creep("mujoco", cone=cone, solref=(0.02, zeta))
    rocking = [w for w in got if issubclass(w.category, en.EngineDomainWarning)]
    assert bool(rocking) == warns and math.isfinite(v)
    # the direct format (-stiffness, -damping) has the same damping ratio B / (2 sqrt(K))
    own = en._split("mujoco", {"cone": cone, "solref": (0.02, zeta)})[1]
    K, B = en._mujoco_kb(own)
    assert en.mujoco_dampratio({**own, "solref": (-K * 0.95 ** 2, -B * 0.95)}) == pytest.approx(zeta)


def test_mujoco_rocking_threshold_rises_with_impratio():
    values = [en.rocking_dampratio("pyramidal", ir) for ir in (1, 2, 10, 50, 1e4)]
    assert values == sorted(values) and values[0] == 0.72 and values[-1] == 0.85


def test_noslip_iterations():
    assert ss.engine_creep("mujoco", noslip_iterations=10) == ss.engine_creep("mujoco")
    with pytest.raises(ValueError, match="noslip_iterations > 0 with the elliptic cone has no "
                                         "equivalent law"):
        ss.engine_creep("mujoco", cone="elliptic", noslip_iterations=1)
    with pytest.raises(ValueError, match="noslip_iterations must be an integer >= 0, got 1.5"):
        ss.engine_creep("mujoco", noslip_iterations=1.5)


@pytest.mark.parametrize("engine", ["drake_continuous", "drake_tamsi", "newton_semi_implicit"])
def test_advise_engine_budgets_settle_and_margin(engine):
    """The steady creep gets max_creep / (1 + margin) - settle; nothing budgeted without settle
    (for engines the package cannot run), with a warning that says so."""
    a = ss.advise_engine(engine, 1e-3, 20.0, settle=2e-4, margin=0.25)
    assert a["budget"] == pytest.approx(8e-4) and a["settle"] == 2e-4
    assert a["total"] == pytest.approx(a["creep"] + 2e-4)
    assert 3e-4 <= a["creep"] <= 6e-4 * (1 + 1e-9)
    with pytest.warns(UserWarning, match="settling slip from rest is not budgeted"):
        b = ss.advise_engine(engine, 1e-3, 20.0)
    assert b["settle"] is None
    with pytest.raises(ValueError, match="the settling slip 0.002 m alone exceeds the budget"):
        ss.advise_engine(engine, 1e-3, 20.0, settle=2e-3)


@needs_mujoco
@pytest.mark.parametrize("cone", ["pyramidal", "elliptic"])
def test_advise_engine_holds_mujoco_from_rest(cone):
    """MuJoCo's own run from rest at the advised impratio stays within the budget, and the
    advice's total (settling slip measured with MuJoCo plus the steady creep) is what the
    engine does."""
    import mujoco
    a = ss.advise_engine("mujoco", 1e-3, 20.0, cone=cone)
    assert a["settle"] > 0
    model = mujoco.MjModel.from_xml_string(en.mujoco_slope_xml(cone=cone, impratio=a["impratio"]))
    data = mujoco.MjData(model)
    for _ in range(int(round(20.0 / model.opt.timestep))):
        mujoco.mj_step(model, data)
    assert data.qpos[0] <= 1e-3
    assert data.qpos[0] == pytest.approx(a["total"], rel=1e-6)
    assert data.qpos[0] > 0.5e-3


@needs_mujoco
def test_mujoco_rocks_where_engine_creep_warns():
    """The warning's threshold against MuJoCo itself: below it the box loses contacts and
    creeps faster than the law; above it all four hold and the law is exact."""
    from cases import engines as ce
    for zeta, rocks in ((0.6, True), (0.8, False)):
        out = ce.mujoco_slope(solref=(0.02, zeta), t_end=10.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", en.EngineDomainWarning)
            pred = ss.engine_creep("mujoco", solref=(0.02, zeta), mu=ce.MU)
        assert (out["fewest_contacts"] < 4 and out["creep"] > 1.5 * pred) == rocks
        assert rocks or out["creep"] == pytest.approx(pred, rel=1e-4)


def test_rocking_thresholds_cover_the_measured_runs():
    """`ROCKING_DAMPRATIO` against MuJoCo's own runs (engines_rocking.csv, committed; written by
    python -m cases.engines --rocking): at every setting measured, the warning's threshold is at
    or above the damping ratio where the box first holds, and within 0.01 of the largest such
    ratio at its impratio (pyramidal) or overall (elliptic)."""
    import csv
    from pathlib import Path
    path = Path(__file__).resolve().parents[1] / "docs" / "figures" / "engines_rocking.csv"
    rows = list(csv.DictReader(path.open()))
    assert len(rows) >= 20
    worst: dict[tuple[str, float], float] = {}
    for r in rows:
        cone, ir, holds = r["cone [-]"], float(r["impratio [-]"]), float(r["holds_at_dampratio [-]"])
        assert en.rocking_dampratio(cone, ir) >= holds
        key = (cone, ir if cone == "pyramidal" else 0.0)
        worst[key] = max(worst.get(key, 0.0), holds)
    for (cone, ir), holds in worst.items():
        assert en.rocking_dampratio(cone, ir or 1.0) - holds <= 0.01
