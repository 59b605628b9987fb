"""The installed library, exactly as the guide page "Using the library from Fortran and C"
(docs/guide/fortran-c.md) shows it: the page's shell commands, read from it, run in a copy of
the repository with a
temporary HOME (so `--prefix=$HOME/.local` is a temporary prefix) and an environment holding
only PATH and HOME. They install the library and build the two programs of examples/ against it
with pkg-config, shared and static; each program then runs in a clean environment (no
LD_LIBRARY_PATH, no PKG_CONFIG_PATH) and is checked against expectations that do not come from
the library (the paper's formulas evaluated here, hand-computed values, a conserved quantity,
exact solutions, counter identities)."""
from __future__ import annotations

import math
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

#: A copy of the repository, a fresh meson build and install, and four programs: minutes.
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "guide" / "fortran-c.md"
EXAMPLES = {"lotka_volterra.f90": "fortran", "friction_c.c": "c"}
CLEAN_PATH = "/usr/local/bin:/usr/bin:/bin"


def guide_commands(page: Path = GUIDE) -> list[str]:
    """The shell command lines of the guide page's sh blocks, in order."""
    blocks = re.findall(r"^```sh\n(.*?)^```", page.read_text(), re.S | re.M)
    assert blocks, f"no sh blocks in {page}"
    return [line for block in blocks for line in block.splitlines()
            if line.strip() and not line.lstrip().startswith("#")]


def _run(cmd: list[str], **kw) -> str:
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300, **kw)
    assert proc.returncode == 0, f"{' '.join(cmd)}\nstdout:\n{proc.stdout}\nstderr:\n{proc.stderr}"
    return proc.stdout


def _keys(out: str) -> dict[str, str]:
    return dict(line.strip().split("=", 1) for line in out.splitlines() if "=" in line)


def _needed(exe: Path) -> list[str]:
    """The shared libraries an executable names (DT_NEEDED)."""
    out = _run(["readelf", "-d", str(exe)])
    return re.findall(r"\(NEEDED\)\s+Shared library: \[(.*?)\]", out)


@pytest.fixture(scope="module")
def guide_builds(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """Run the guide's install and build commands in a copy of the repository; return the
    program run lines by (example, "shared" or "static") and what the clean runs need."""
    venv = Path(sys.prefix)
    if not (venv / "bin" / "activate").exists() or shutil.which("readelf") is None:
        pytest.skip("needs the scripts/setup venv (the guide activates it) and readelf")
    tmp = tmp_path_factory.mktemp("install")
    repo, home = tmp / "repo", tmp / "home"
    shutil.copytree(ROOT, repo, ignore=shutil.ignore_patterns(
        ".git", ".venv", "build", "build-*", "out", "__pycache__", ".pytest_cache", "*.mod", "*.o"))
    (repo / ".venv").symlink_to(venv, target_is_directory=True)
    home.mkdir()
    env = {"PATH": CLEAN_PATH, "HOME": str(home)}

    lines = guide_commands()
    outputs = {}                                    # -o target -> example
    for line in lines:
        words = shlex.split(line, posix=True)
        if words[0] in ("gfortran", "cc") and "-o" in words:
            src = Path(words[1]).name
            assert src in EXAMPLES, line
            outputs[words[words.index("-o") + 1]] = EXAMPLES[src]
    runs = [line for line in lines if line.split()[0] in outputs]
    script = "\n".join(line for line in lines if line not in runs)
    # No set -u: the guide's export reads PKG_CONFIG_PATH, which a new user's shell may not set.
    _run(["bash", "-e", "-o", "pipefail", "-c", script], cwd=repo, env=env)

    prefix = home / ".local"
    installed = sorted(str(p.relative_to(prefix)) for p in prefix.rglob("*") if not p.is_dir())
    programs = {}
    for line in runs:
        exe = repo / line.split()[0]
        link = "shared" if any(n.startswith("libstickslip.so") for n in _needed(exe)) else "static"
        assert (outputs[line.split()[0]], link) not in programs, line
        programs[outputs[line.split()[0]], link] = line
    return {"repo": repo, "env": env, "programs": programs, "installed": installed}


def _run_program(builds: dict, example: str, link: str) -> str:
    """Run the guide's line for one program, as the guide shows it, in a clean environment."""
    line = builds["programs"].get((example, link))
    assert line is not None, f"the guide builds and runs no {link} {example} example"
    return _run(["bash", "-c", line], cwd=builds["repo"], env=builds["env"])


def test_readme_installs_the_library_alone(guide_builds: dict) -> None:
    """The static and shared library, header, module files and .pc file; no Python."""
    files = guide_builds["installed"]
    for want in ("libstickslip.a", "libstickslip.so", "pkgconfig/stickslip.pc"):
        assert any(f.startswith("lib") and f.endswith(want) for f in files), (want, files)
    assert "include/stickslip/stickslip.h" in files and "include/stickslip/stickslip_codes.h" in files
    for mod in ("kinds", "friction", "ode", "rk4", "dopri5", "radau5", "presets", "registry", "simulate", "capi"):
        assert f"include/stickslip/stickslip_{mod}.mod" in files, mod
    library = re.compile(r"include/stickslip/stickslip(_\w+\.mod|_codes\.h|\.h)"
                         r"|lib[^/]*/([^/]+/)?(libstickslip\.(a|so[.\d]*)|pkgconfig/stickslip\.pc)")
    others = [f for f in files if not library.fullmatch(f)]
    assert not others, f"installed besides the library: {others}"


def test_static_libs_name_every_runtime(guide_builds: dict) -> None:
    """`pkg-config --static --libs` names each runtime libstickslip.a calls into, also those the
    examples do not reach (OpenMP is only in the batch module)."""
    files = guide_builds["installed"]
    pc = next(f for f in files if f.endswith("pkgconfig/stickslip.pc"))
    prefix = Path(guide_builds["env"]["HOME"]) / ".local"
    env = dict(guide_builds["env"], PKG_CONFIG_PATH=str((prefix / pc).parent))
    libs = _run(["pkg-config", "--static", "--libs", "stickslip"], env=env).split()
    archive = prefix / next(f for f in files if f.endswith("libstickslip.a"))
    undefined = set(_run(["nm", "-u", "--format=just-symbols", str(archive)]).split())
    runtimes = {"-lgfortran": r"_gfortran_\w+", "-lgomp": r"GOMP_\w+|omp_\w+",
                "-lm": r"(exp|log|pow|sqrt|sin|cos|tan|atan2?|cbrt|hypot)f?"}
    for flag, pattern in runtimes.items():
        if any(re.fullmatch(pattern, sym) for sym in undefined):
            assert flag in libs[libs.index("-lstickslip"):], (flag, libs)


@pytest.mark.parametrize("link", ["shared", "static"])
def test_fortran_example(guide_builds: dict, link: str) -> None:
    """Lotka-Volterra with the library's DOPRI5 and RK4: V is conserved, the two agree,
    and the counters obey DOPRI5's and RK4's evaluation counts."""
    k = _keys(_run_program(guide_builds, "fortran", link))

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
def test_c_example(guide_builds: dict, link: str) -> None:
    """Friction laws, scenes and a user's ODE through stickslip.h, linked both ways."""
    out = _run_program(guide_builds, "c", link)
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
    # by name (ss_code, ss_run): the same run bit for bit; RADAU5 creeps at v* with
    # mu(v*) = tan 10 deg, on the haversine's first branch: v* = (v_s/pi) acos(1 - 2 tan/mu_s)
    assert int(k["slope_proposed_by_name_equal"]) == 1 and int(k["unknown_law_code"]) == 0
    v_star = 0.02 / math.pi * math.acos(1.0 - 2.0 * math.tan(math.radians(10.0)) / 0.35)
    assert float(k["slope_recurdyn_radau5_v_end"]) == pytest.approx(v_star, rel=1e-5)
    assert int(k["slope_recurdyn_radau5_njac"]) >= 1
    # A user's ODE through a C function pointer: y' = -2 y, y(1) = exp(-2).
    assert abs(float(k["decay_y_end"]) - math.exp(-2.0)) < 1e-8
    assert int(k["decay_nfev"]) == 6 * int(k["decay_nstep"]) + 2
    # ... and with the library's DOP853: Hairer's count, 12 evaluations a step (11 stages and
    # f at the new point, the next step's first stage) + 2 (the first f and HINIT's); a struct filled with
    # DOP853's defaults gives the same run as NULL.
    assert abs(float(k["decay_dop853_y_end"]) - math.exp(-2.0)) < 1e-9
    assert int(k["decay_dop853_nfev"]) == 12 * int(k["decay_dop853_nstep"]) + 2
    assert int(k["decay_dop853_nstep"]) < int(k["decay_nstep"])
    assert int(k["decay_dop853_opts_equal"]) == 1
    # ... and with the library's RK4 at h = 0.01: 100 steps, 1 + 4 evaluations each,
    # global error lambda^5 h^4 t / 120 exp(-2 t), about 3.6e-10 at t = 1 (order h^4).
    assert int(k["decay_rk4_nstep"]) == 100 and int(k["decay_rk4_nfev"]) == 401
    assert 1e-10 < abs(float(k["decay_rk4_y_end"]) - math.exp(-2.0)) < 1e-9
