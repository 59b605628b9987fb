"""Run the Fortran unit tests (meson test) and check Hairer's Arenstorf run from their output."""
from __future__ import annotations

import re
import subprocess

from conftest import compile_target


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


def test_fortran_law_suite(native_build):
    """tests/fortran/test_laws.f90: dmu, evaluate, alpha and the parameter table."""
    exe = compile_target(native_build, "test_laws")
    proc = subprocess.run([str(exe)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "FAIL" not in proc.stdout and "all law checks passed" in proc.stdout, proc.stdout


def test_meson_test_suite(native_build):
    """`meson test`: the two Fortran unit tests and both examples built in-tree from the core."""
    from conftest import _tool
    proc = subprocess.run([_tool("meson"), "test", "-C", str(native_build), "--print-errorlogs"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert re.search(r"Ok:\s+4\b", proc.stdout) and re.search(r"Fail:\s+0\b", proc.stdout), proc.stdout
