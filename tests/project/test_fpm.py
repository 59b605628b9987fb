"""fpm builds the library from the same sources as meson (fpm.toml), runs the Fortran unit
tests and the Fortran example: what a Fortran user without meson or Python does. fpm writes
into build/ (build/gfortran_*, fpm's debug profile: bounds and array checks on)."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow     # a whole second build of the library by fpm
def test_fpm_build_test_and_example() -> None:
    here = Path(sys.executable).parent / "fpm"
    fpm = str(here) if here.exists() else shutil.which("fpm")
    if fpm is None:
        pytest.skip("fpm is not installed (scripts/setup installs it)")
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")

    def run(*args: str) -> str:
        proc = subprocess.run([fpm, *args], cwd=ROOT, env=env, capture_output=True, text=True)
        assert proc.returncode == 0, f"fpm {' '.join(args)}:\n{proc.stdout}\n{proc.stderr}"
        return proc.stdout

    run("build")
    out = run("test")
    assert "all integrator checks passed" in out and not re.search(r"^FAIL", out, re.M), out
    assert all(f"all {s} checks passed" in out for s in ("core", "law")), out
    # Hairer's Arenstorf counts, as the meson build's test checks them
    assert re.search(r"arenstorf: nfev nstep naccept nreject y1 y2 =\s+1442 240 216 22\b", out), out
    out = run("run", "--example", "lotka_volterra")
    drift = {m.group(1): float(m.group(2)) for m in re.finditer(r"(\w+)_invariant_drift=\s*(\S+)", out)}
    assert drift.keys() == {"dopri5", "rk4"} and max(drift.values()) < 1e-8, out
