"""The library's periodic-orbit solver (fortran/api/stickslip_orbit.f90) through its C entry
points (ss_periodic_orbit, ss_model_periodic_orbit): tests/c/capi_orbit_cases.c finds the
belt's stick-slip cycle, Den Hartog's forced orbit, a smooth forced oscillator's orbit (the
last two also with the section at t0 > 0) and a linear three-body chain's, and feeds it bad
input; here they are checked against the closed
form of the belt's cycle, stickslip.periodic_orbit's saltation route, scipy's variational
equations and the matrix exponential, and the multipliers against numpy's eigenvalues of the
printed monodromy (the Hessenberg QR of stickslip_linalg)."""
from __future__ import annotations

import math
import subprocess

import numpy as np
import pytest

import stickslip as ss
from cases import gallery_denhartog as dh
from conftest import compile_target

G = 9.81
STATUS = ss.REGISTRY["status"]


@pytest.fixture(scope="module")
def cases(native_build) -> dict:
    """What capi_orbit_cases prints: orbits by name (a dict each) and cases (status, residual, message)."""
    exe = compile_target(native_build, "capi_orbit_cases")
    proc = subprocess.run([str(exe)], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    orbits, out = {}, {}
    for line in proc.stdout.splitlines():
        kind, name, *rest = line.split(" ")
        if kind == "orbit":
            n = int(rest[7])
            v = np.array([float(f) for f in rest[8:]])
            orbits[name] = {"status": int(rest[0]), "period": float(rest[1]), "residual": float(rest[2]),
                            "iterations": int(rest[3]), "runs": int(rest[4]), "trivial": int(rest[5]),
                            "stable": bool(int(rest[6])), "y0": v[:n], "mult": v[n:2 * n] + 1j * v[2 * n:3 * n],
                            "monodromy": v[3 * n:].reshape(n, n)}
        elif kind == "case":
            out[name] = (int(rest[0]), float(rest[1]), line.split(" | ", 1)[1])
    return {"orbits": orbits, "cases": out}


def test_belt_cycle_equals_the_closed_form(cases) -> None:
    """Set-valued Coulomb on the belt (m = 1, k = 4, v_b = 0.3, mu 0.4/0.3) under event_driven:
    the period (pi + 2 asin(v_b/(A w)))/w + 2 (mu_s - mu_k) m g/(k v_b); the trivial multiplier
    1 and the stick phase's 0, both to the finite differences' error."""
    o = cases["orbits"]["belt"]
    m, k, v_b, mu_s, mu_k = 1.0, 4.0, 0.3, 0.4, 0.3
    w = math.sqrt(k / m)
    amp = math.hypot((mu_s - mu_k) * m * G / k, v_b / w)
    period = (math.pi + 2.0 * math.asin(v_b / (amp * w))) / w + 2.0 * (mu_s - mu_k) * m * G / (k * v_b)
    assert o["status"] == 0 and o["residual"] <= 1e-9 * 3.3
    assert o["period"] == pytest.approx(period, rel=1e-8, abs=0)
    assert o["trivial"] >= 0 and abs(o["mult"][o["trivial"]] - 1.0) < 1e-4
    assert abs(np.delete(o["mult"], o["trivial"])[0]) < 1e-4
    assert o["stable"]
    # the state is on the cycle: stuck (v = v_b, x below mu_s m g / k), or slipping on the arc of
    # radius A about mu_k m g / k
    x, v = o["y0"]
    on_arc = math.hypot(x - mu_k * m * G / k, (v - v_b) / w)
    stuck = v == pytest.approx(v_b, abs=1e-9) and x <= mu_s * m * G / k + 1e-9
    assert stuck or on_arc == pytest.approx(amp, rel=1e-7)


def test_den_hartog_matches_periodic_orbit(cases) -> None:
    """Den Hartog's oscillator (beta = 2, r = 0.3, no stops) forced, under event_driven: the C
    solver's state at t = 0 and monodromy (finite differences) against stickslip.periodic_orbit's
    exact saltation route, an independent computation of the monodromy."""
    o = cases["orbits"]["den_hartog"]
    ref = ss.periodic_orbit(dh.model(2.0, 0.3))
    assert ref.monodromy_method == "saltation"
    assert o["status"] == 0 and o["period"] == pytest.approx(math.pi, rel=1e-15)
    np.testing.assert_allclose(o["y0"], ref.y0, rtol=0, atol=1e-8)
    np.testing.assert_allclose(o["monodromy"], ref.monodromy, rtol=0, atol=1e-5)
    np.testing.assert_allclose(np.sort_complex(o["mult"]), np.sort_complex(ref.multipliers), rtol=0, atol=1e-5)
    assert o["trivial"] == -1 and o["stable"] == ref.stable


@pytest.mark.parametrize("name,t0,method,atol", [("den_hartog_t0", 0.7, "event_driven", 1e-8),
                                                 ("smooth_t0", 1.3, "dopri5", 5e-8)])
def test_section_at_t0_against_periodic_orbit_of_the_shifted_model(cases, name: str, t0: float, method: str,
                                                                   atol: float) -> None:
    """ss_orbit_options.t0: the C solver's state with the section at t0 equals
    stickslip.periodic_orbit's at t = 0 on the model whose signals are advanced by t0
    (steady._shifted: s(t + t0)), and the state the t = 0 orbit reaches at t0, to `atol`
    (both orbits are found to a residual of 1e-9 max(1, |guess|); measured 2e-14 and 8e-9);
    the multipliers do not depend on the section."""
    from stickslip import steady
    o = cases["orbits"][name]
    base = dh.model(2.0, 0.3) if name == "den_hartog_t0" else _smooth_model()
    ref = ss.periodic_orbit(steady._shifted(base, t0), method=method)
    assert o["status"] == 0 and o["trivial"] == -1
    np.testing.assert_allclose(o["y0"], ref.y0, rtol=0, atol=atol)
    at_zero = ss.periodic_orbit(base, method=method)
    later = ss.simulate(steady._with_state(base, at_zero.y0), method=method, t_end=t0, n_out=2, rtol=1e-12,
                        atol=1e-14)
    np.testing.assert_allclose(o["y0"], [later.x[0, -1], later.v[0, -1]], rtol=0, atol=atol)
    np.testing.assert_allclose(np.sort_complex(o["mult"]), np.sort_complex(at_zero.multipliers), rtol=0, atol=3e-5)
    assert np.max(np.abs(o["y0"] - at_zero.y0)) > 0.1        # the section did move


def _smooth_model() -> ss.Model:
    """tests/c/capi_orbit_cases.c's smooth oscillator: m = 1, k = 4, 10 sin(2 pi 0.25 t), the
    `proposed` law on N = 9.81."""
    m = ss.Model()
    b = m.add_body(1.0)
    m.add_spring(b, None, k=4.0)
    m.add_force(b, ss.signal.sine(10.0, 0.25))
    m.add_contact(b, None, "proposed", normal_force=9.81, mu_s=0.4, mu_k=0.3, v_s=0.5)
    return m


def test_smooth_multipliers_against_scipy_variational_equations(cases) -> None:
    """The forced oscillator with the smooth `proposed` law under dopri5: the orbit closes under
    scipy, and the multipliers (finite differences of DOPRI5's flow) equal those of the
    variational equations integrated by scipy."""
    from scipy.integrate import solve_ivp
    o = cases["orbits"]["smooth"]
    assert o["status"] == 0

    def mu(s: float) -> float:
        return float(ss.friction_coefficient("proposed", np.array([s]), mu_s=0.4, mu_k=0.3, v_s=0.5)[0])

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        x, v = z[0], z[1]
        h = 1e-7
        dmu = (mu(v + h) - mu(v - h)) / (2 * h)
        jac = np.array([[0.0, 1.0], [-4.0, -G * dmu]])
        acc = -4.0 * x + 10.0 * math.sin(2 * math.pi * 0.25 * t) - G * mu(v)
        return np.concatenate([[v, acc], (jac @ z[2:].reshape(2, 2)).ravel()])
    sol = solve_ivp(rhs, (0, 4.0), np.concatenate([o["y0"], np.eye(2).ravel()]), method="DOP853",
                    rtol=1e-11, atol=1e-13)
    assert np.max(np.abs(sol.y[:2, -1] - o["y0"])) < 1e-7
    ref = np.linalg.eigvals(sol.y[2:, -1].reshape(2, 2))
    np.testing.assert_allclose(np.sort_complex(o["mult"]), np.sort_complex(ref), rtol=0, atol=3e-5)


def test_six_multipliers_of_a_linear_chain(cases) -> None:
    """Three bodies, springs and dampers, forced: the monodromy is exp(A T) (scipy's expm), and
    the multipliers (Hessenberg QR) equal numpy's eigenvalues of the printed monodromy."""
    from scipy.linalg import expm
    o = cases["orbits"]["chain3"]
    assert o["status"] == 0 and o["period"] == 2.5
    mass = np.diag([1.0, 2.0, 0.5])
    k = np.array([[5.0, -2.0, 0.0], [-2.0, 7.0, -5.0], [0.0, -5.0, 5.0]])
    c = np.array([[0.3, 0.0, 0.0], [0.0, 0.2, -0.2], [0.0, -0.2, 0.2]])
    a = np.block([[np.zeros((3, 3)), np.eye(3)], [-np.linalg.solve(mass, k), -np.linalg.solve(mass, c)]])
    exact = expm(a * 2.5)
    np.testing.assert_allclose(o["monodromy"], exact, rtol=0, atol=1e-6)
    np.testing.assert_allclose(np.sort_complex(o["mult"]), np.sort_complex(np.linalg.eigvals(o["monodromy"])),
                               rtol=0, atol=1e-12)
    assert np.all(np.diff(np.abs(o["mult"])) <= 1e-15)          # largest modulus first
    assert o["stable"] == bool(np.all(np.abs(np.linalg.eigvals(exact)) < 1))


@pytest.mark.parametrize("name,code,word", [("period", "BAD_PERIOD", "period"), ("guess", "BAD_GUESS", "guess"),
                                            ("options", "BAD_ORBIT_OPTION", "orbit options: tol"),
                                            ("options_t0", "BAD_ORBIT_OPTION", "orbit options: tol"),
                                            ("scene_period", "BAD_PERIOD", "period"),
                                            ("scene_guess", "BAD_GUESS", "guess")])
def test_bad_input_is_named(cases, name: str, code: str, word: str) -> None:
    status, _, message = cases["cases"][name]
    assert status == STATUS[code] and message.startswith(word)


def test_no_orbit_is_a_named_failure_with_its_residual(cases) -> None:
    """An undamped oscillator forced at resonance has no periodic orbit: SS_NO_ORBIT, never an
    orbit with SS_OK, and the residual says how far it got."""
    status, residual, message = cases["cases"]["resonance"]
    assert status == STATUS["NO_ORBIT"] and residual > 1e-10 and "did not" in message


def test_the_guide_example(native_build) -> None:
    """examples/orbit_c.c (docs/guide/fortran-c.md): the belt's cycle against its closed form,
    checked by the program itself (exit 0), and the numbers it prints agree."""
    exe = compile_target(native_build, "orbit_c")
    proc = subprocess.run([str(exe)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    lines = proc.stdout.splitlines()
    found = float(lines[0].split()[1])
    closed = float(lines[-1].split()[2])
    assert found == pytest.approx(closed, rel=1e-8, abs=0)
