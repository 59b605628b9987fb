"""Run the Fortran unit tests (meson test) and check Hairer's Arenstorf run from their output."""
from __future__ import annotations

import re
import subprocess

import pytest

from conftest import compile_target


def run_program(native_build, target: str, name: str) -> str:
    """Build and run one Fortran test program; it passes when it exits 0, prints no FAIL line
    and ends with its verdict, "all <name> checks passed". Returns what it printed."""
    exe = compile_target(native_build, target)
    proc = subprocess.run([str(exe)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert not re.search(r"^FAIL", proc.stdout, re.M), proc.stdout
    assert f"all {name} checks passed" in proc.stdout, proc.stdout
    return proc.stdout


def test_fortran_integrator_suite(native_build):
    exe = compile_target(native_build, "test_integrators")
    proc = subprocess.run([str(exe)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "FAIL" not in proc.stdout
    # Hairer's published run (dr_dopri5, rtol = atol = 1e-7): fcn 1442, step 240,
    # accpt 216, rejct 22, y(xend) = (0.9940021016, 0.8911185692e-5).
    m = re.search(r"arenstorf: nfev nstep naccept nreject y1 y2 =\s+(\d+) (\d+) (\d+) (\d+)\s+(\S+)\s+(\S+)",
                  proc.stdout)
    assert m, proc.stdout
    assert tuple(int(g) for g in m.groups()[:4]) == (1442, 240, 216, 22)
    assert abs(float(m.group(5)) - 0.9940021016) < 1e-10
    assert abs(float(m.group(6)) - 0.8911185692e-5) < 1e-11


def test_fortran_implicit_suite(native_build):
    exe = compile_target(native_build, "test_integrators_implicit")
    proc = subprocess.run([str(exe)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert not re.search(r"^FAIL", proc.stdout, re.M), proc.stdout  # (labels name SS_NEWTON_FAILED)
    # Hairer's radau5.f (1996/2002) on Van der Pol (eps 1e-6, y0 = (2, -0.66), x_end = 2,
    # rtol = atol = 1e-4, analytic Jacobian): NFCN NJAC NSTEP NACCPT NREJCT NDEC NSOL
    # = 2218 161 275 238 8 248 660 (also the published output of his dr1_radau5 example).
    m = re.search(r"radau5 vdp tol 1.0E-04: nfev njac nstep naccept nreject ndec nsol y = ((?:\d+ ){6}\d+)\s+(\S+)",
                  proc.stdout)
    assert m, proc.stdout
    assert tuple(int(g) for g in m.group(1).split()) == (2218, 161, 275, 238, 8, 248, 660)
    assert abs(float(m.group(2)) - 1.70616110055875470) < 1e-9
    for method, lo, hi in (("radau5", 4.7, 5.3), ("galpha", 1.9, 2.1), ("implicit euler", 0.95, 1.05)):
        m = re.search(method + r" order: errors.*orders\s+(\S+)\s+(\S+)", proc.stdout)
        assert m, proc.stdout
        assert all(lo < float(g) < hi for g in m.groups()), m.group(0)


def test_fortran_registry_suite(native_build):
    """tests/fortran/test_stickslip_registry.f90: the registry's tables, messages and parameters."""
    run_program(native_build, "test_stickslip_registry", "registry")


def test_fortran_scene_suite(native_build):
    """tests/fortran/test_stickslip_presets.f90: every preset's analytic Jacobian."""
    run_program(native_build, "test_stickslip_presets", "scene")


def test_fortran_model_system_suite(native_build):
    """tests/fortran/test_stickslip_model_system.f90: a model's banded Jacobian."""
    run_program(native_build, "test_stickslip_model_system", "model system")


def test_fortran_core_suite(native_build):
    """tests/fortran/test_integrators_common.f90: controls by name, the integrators' regressions."""
    exe = compile_target(native_build, "test_integrators_common")
    proc = subprocess.run([str(exe)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert not re.search(r"^FAIL", proc.stdout, re.M), proc.stdout
    assert "all core checks passed" in proc.stdout


def test_fortran_law_suite(native_build):
    """tests/fortran/test_laws.f90: dmu, evaluate, alpha, the parameter table and every law's dmu."""
    exe = compile_target(native_build, "test_laws")
    proc = subprocess.run([str(exe)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "FAIL" not in proc.stdout and "all law checks passed" in proc.stdout, proc.stdout


@pytest.mark.slow     # every program again (the suites above run each), and the five examples
def test_meson_test_suite(native_build):
    """`meson test`: the Fortran unit tests (nine programs) and the five examples (Lotka-Volterra,
    the C friction example, the Fortran model that stops, the C clutch model and the C belt
    orbit, each as its closed form says) built in-tree."""
    from conftest import _tool, build_lock
    with build_lock(native_build):        # it compiles every target, as other workers may
        proc = subprocess.run([_tool("meson"), "test", "-C", str(native_build), "--print-errorlogs"],
                              capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert re.search(r"Ok:\s+14\b", proc.stdout) and re.search(r"Fail:\s+0\b", proc.stdout), proc.stdout
    assert "example_model_stop" in proc.stdout and "example_model_c" in proc.stdout


def test_fortran_contact_suite(native_build):
    """tests/fortran/test_stickslip_contact.f90: two blocks on a belt (two coupled contacts) under
    moreau and event_driven, and the one-contact Stribeck solve."""
    exe = compile_target(native_build, "test_stickslip_contact")
    proc = subprocess.run([str(exe)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert not re.search(r"^FAIL", proc.stdout, re.M), proc.stdout
    assert "all contact checks passed" in proc.stdout
