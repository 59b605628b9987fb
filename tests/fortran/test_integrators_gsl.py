"""Our integrators against GSL's gsl_odeiv2, an independent implementation of the same
scenes (tests/gsl/gsl_reference.c re-implements the laws and scenes in C)."""
from __future__ import annotations

import subprocess

import numpy as np
import pytest

import stickslip as ss
from conftest import compile_target


@pytest.fixture(scope="module")
def gsl_reference(native_build):
    return compile_target(native_build, "gsl_reference")


def run_gsl(exe, stepper: str, scene: str, law: str, t_end: float, h_or_tol: float, n_out: int):
    proc = subprocess.run([str(exe), stepper, scene, law, repr(t_end), repr(h_or_tol), str(n_out)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    data = np.array([[float(x) for x in line.split()] for line in lines if not line.startswith("#")])
    counts = dict(kv.split("=") for kv in lines[-1][2:].split())
    return data, {k: int(v) for k, v in counts.items()}


@pytest.mark.parametrize("scene,law,t_end", [
    ("slope", "recurdyn", 20.0), ("slope", "proposed", 20.0),
    ("belt", "coulomb", 20.0), ("belt", "proposed", 5.0),
])
def test_rk4_matches_gsl_rk4(gsl_reference, scene, law, t_end):
    # GSL's rk4 stepper does step doubling: one GSL step of h is two classical steps of h/2.
    h = 1e-3
    data, counts = run_gsl(gsl_reference, "rk4", scene, law, t_end, 2 * h, 101)
    ours = ss.simulate(scene, law, method="rk4", h=h, t_end=t_end, n_out=101)
    np.testing.assert_allclose(ours.t, data[:, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(ours.x, data[:, 1], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(ours.v, data[:, 2], rtol=1e-9, atol=1e-12)
    # GSL spends 11-12 evaluations a step (doubling); we spend 4 per classical step
    assert 11 <= counts["nfev"] / counts["nstep"] <= 12
    assert ours.stats["nfev"] == 1 + 4 * ours.stats["nstep"]


@pytest.mark.parametrize("scene,law", [("slope", "recurdyn"), ("slope", "proposed"),
                                       ("belt", "recurdyn"), ("belt", "proposed")])
def test_dopri5_matches_gsl_rk8pd(gsl_reference, scene, law):
    t_end = 20.0 if scene == "slope" else 8.0
    data, _ = run_gsl(gsl_reference, "rk8pd", scene, law, t_end, 1e-12, 41)
    ours = ss.simulate(scene, law, method="dopri5", t_end=t_end, rtol=1e-11, atol=1e-13,
                       hmin=0.0, n_out=41)
    np.testing.assert_allclose(ours.x, data[:, 1], rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(ours.v, data[:, 2], rtol=1e-5, atol=1e-8)
