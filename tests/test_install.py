"""The installed library: `meson install` with -Dinstall_lib=true into a temporary prefix, then
the two programs of examples/ built OUTSIDE the meson tree with pkg-config, run, and checked
against expectations that do not come from the library (the paper's formulas evaluated here,
hand-computed values, a conserved quantity, exact solutions, counter identities)."""
from __future__ import annotations

import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


def _need(name: str) -> str:
    path = str(BIN / name) if (BIN / name).exists() else shutil.which(name)
    if path is None:
        pytest.skip(f"{name} not found")
    return path


def _run(cmd: list[str], **kw) -> str:
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120, **kw)
    assert proc.returncode == 0, f"{' '.join(cmd)}\nstdout:\n{proc.stdout}\nstderr:\n{proc.stderr}"
    return proc.stdout


def _keys(out: str) -> dict[str, str]:
    return dict(line.strip().split("=", 1) for line in out.splitlines() if "=" in line)


@pytest.fixture(scope="module")
def installed(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """Configure, build and install into a fresh prefix; return paths and an environment."""
    meson = _need("meson")
    pkgconf = _need("pkg-config")
    tmp = tmp_path_factory.mktemp("install")
    build, prefix = tmp / "build", tmp / "prefix"
    env = dict(os.environ, PATH=f"{BIN}{os.pathsep}{os.environ['PATH']}")
    _run([meson, "setup", str(build), str(ROOT), f"--prefix={prefix}", "-Dinstall_lib=true"], env=env)
    _run([meson, "install", "-C", str(build)], env=env)
    pcs = sorted(prefix.glob("lib*/**/pkgconfig/stickslip.pc"))
    assert pcs, f"no stickslip.pc under {prefix}"
    libdir = pcs[0].parent.parent
    assert (libdir / "libstickslip.a").exists()
    assert any(libdir.glob("libstickslip.so*"))
    inc = prefix / "include" / "stickslip"
    assert (inc / "stickslip.h").exists()
    for mod in ("kinds", "friction", "ode", "rk4", "dopri5", "scenes", "simulate", "capi"):
        assert (inc / f"stickslip_{mod}.mod").exists(), mod
    env = dict(env, PKG_CONFIG_PATH=str(pcs[0].parent),
               LD_LIBRARY_PATH=f"{libdir}{os.pathsep}{os.environ.get('LD_LIBRARY_PATH', '')}")
    flags = _run([pkgconf, "--cflags", "--libs", "stickslip"], env=env).split()
    return {"tmp": tmp, "env": env, "flags": flags, "libdir": libdir, "pkgconf": pkgconf}


def test_fortran_example(installed: dict) -> None:
    """Lotka-Volterra with the library's DOPRI5 and RK4: V is conserved, the two agree,
    and the counters obey DOPRI5's and RK4's evaluation counts."""
    fc = _need("gfortran")
    exe = installed["tmp"] / "lotka_volterra"
    work = installed["tmp"] / "fortran_example"
    work.mkdir()
    shutil.copy(ROOT / "examples" / "lotka_volterra.f90", work)   # outside the meson tree
    _run([fc, "lotka_volterra.f90", *installed["flags"], "-o", str(exe)], cwd=work, env=installed["env"])
    k = _keys(_run([str(exe)], env=installed["env"]))

    for m in ("dopri5", "rk4"):
        assert float(k[f"{m}_t_end"]) == 15.0
        assert int(k[f"{m}_nstep"]) > 0 and int(k[f"{m}_naccept"]) > 0
    # V = delta x - gamma ln x + beta y - alpha ln y is a first integral.
    assert float(k["dopri5_invariant_drift"]) < 1e-7
    assert float(k["rk4_invariant_drift"]) < 1e-8
    # Two methods, one answer (the orbit is periodic; the populations stay positive).
    x5, y5, x4, y4 = (float(k[n]) for n in ("dopri5_x", "dopri5_y", "rk4_x", "rk4_y"))
    assert x5 > 0 and y5 > 0
    assert abs(x5 - x4) < 1e-6 * max(1.0, abs(x4)) and abs(y5 - y4) < 1e-6
    # DOPRI5: 6 evaluations per attempted step, plus k1 and HINIT's one.
    nstep = int(k["dopri5_nstep"])
    assert int(k["dopri5_nfev"]) == 6 * nstep + 2
    assert int(k["dopri5_naccept"]) + int(k["dopri5_nreject"]) <= nstep
    # RK4, h = 1e-3 over 15: 15000 steps of 4 evaluations plus the first.
    assert int(k["rk4_nstep"]) == 15000 and int(k["rk4_nfev"]) == 4 * 15000 + 1


def _mu_paper(law: str, v: float) -> float:
    """Yoo & Lee (2008) eqs. 1, 2-3 and 5 with Table 1's parameters, written here from the paper."""
    mu_s, mu_k, v_s, v_d, beta, a = 0.35, 0.30, 0.01, 0.015, 1.0 / 3.0, 1.5
    s = abs(v)
    if s == 0.0:
        return 0.0
    if law == "coulomb":
        m = mu_s if s < v_s else mu_k
    elif law == "recurdyn":
        def hav(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
            if x <= x0:
                return h0
            if x >= x1:
                return h1
            return h0 + (h1 - h0) * (1.0 - math.cos(math.pi * (x - x0) / (x1 - x0))) / 2.0
        m = hav(s, 0.0, 0.0, v_s, mu_s) if s < v_s else hav(s, v_s, mu_s, v_d, mu_k)
    else:
        b = -math.log(mu_s - mu_k) / math.log(a) - v_s
        m = mu_s * (s / v_s) ** beta if s <= v_s else a ** (-(s + b)) + mu_k
    return math.copysign(m, v)


@pytest.mark.parametrize("link", ["shared", "static"])
def test_c_example(installed: dict, link: str) -> None:
    """Friction laws, scenes and a user's ODE through stickslip.h, linked both ways."""
    cc = _need("cc")
    work = installed["tmp"] / f"c_example_{link}"
    work.mkdir()
    shutil.copy(ROOT / "examples" / "friction_c.c", work)
    exe = work / "friction_c"
    if link == "shared":
        cmd = [cc, "friction_c.c", *installed["flags"], "-lm", "-o", str(exe)]
    else:
        cflags = _run([installed["pkgconf"], "--cflags", "stickslip"], env=installed["env"]).split()
        libs = _run([installed["pkgconf"], "--static", "--libs-only-l", "stickslip"],
                    env=installed["env"]).split()
        libs = [x for x in libs if x != "-lstickslip"]
        cmd = [cc, "friction_c.c", *cflags, str(installed["libdir"] / "libstickslip.a"), *libs, "-lm",
               "-o", str(exe)]
    _run(cmd, cwd=work, env=installed["env"])
    out = _run([str(exe)], env=installed["env"] if link == "shared" else None)
    k = _keys(out)

    rows = [line.split() for line in out.splitlines() if line.startswith("mu ")]
    assert len(rows) == 24
    for _, law, v, mu in rows:
        assert float(mu) == pytest.approx(_mu_paper(law, float(v)), rel=1e-13, abs=1e-15), (law, v)
    got = {(law, float(v)): float(mu) for _, law, v, mu in rows}
    # Hand-computed: haversine mid-points and the cube-root branch.
    assert got[("recurdyn", 0.005)] == pytest.approx(0.175, rel=1e-14)
    assert got[("recurdyn", 0.0125)] == pytest.approx(0.325, rel=1e-14)
    assert got[("proposed", 0.005)] == pytest.approx(0.35 * 0.5 ** (1.0 / 3.0), rel=1e-14)
    assert got[("proposed", -1.5)] == -got[("proposed", 1.5)]
    assert int(k["bad_status"]) == -102 and k["bad_message"].startswith("mu_k")

    # Belt, proposed law: DOPRI5 (rtol 1e-8) and RK4 (h = 1e-4) agree; counters consistent.
    for q in ("x_end", "v_end"):
        assert abs(float(k[f"belt_dopri5_{q}"]) - float(k[f"belt_rk4_{q}"])) < 1e-5
    nstep = int(k["belt_dopri5_nstep"])
    assert int(k["belt_dopri5_nfev"]) == 6 * nstep + 2
    assert int(k["belt_dopri5_naccept"]) + int(k["belt_dopri5_nreject"]) <= nstep
    assert int(k["belt_dopri5_naccept"]) >= 2000          # hmax = 1e-2 over 20 s
    assert int(k["belt_dopri5_n_written"]) == 201
    assert int(k["belt_rk4_nstep"]) == 200000 and int(k["belt_rk4_nfev"]) == 4 * 200000 + 1
    # The belt drives the mass into motion: it has moved well away from the wall.
    assert float(k["belt_dopri5_xmax_late"]) > 0.1
    # Slope: tan(10 deg) < mu_k, the box should not move; the proposed law creeps far less
    # than the paper's 0.1 m of the RecurDyn law.
    assert 0.0 <= float(k["slope_proposed_x_end"]) < 0.1
    # A user's ODE through a C function pointer: y' = -2 y, y(1) = exp(-2).
    assert abs(float(k["decay_y_end"]) - math.exp(-2.0)) < 1e-8
    assert int(k["decay_nfev"]) == 6 * int(k["decay_nstep"]) + 2
    # ... and with the library's RK4 at h = 0.01: 100 steps, 1 + 4 evaluations each,
    # global error lambda^5 h^4 t / 120 exp(-2 t), about 3.6e-10 at t = 1 (order h^4).
    assert int(k["decay_rk4_nstep"]) == 100 and int(k["decay_rk4_nfev"]) == 401
    assert 1e-10 < abs(float(k["decay_rk4_y_end"]) - math.exp(-2.0)) < 1e-9
