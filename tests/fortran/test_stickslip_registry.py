"""The registry drives the Python side (issue 41 item 7): the facade's constants are read from
the library (stickslip_registry's registry_text) rather than copied, one hmin default holds for
Python, Fortran and C (the Fortran and C halves: tests/fortran/test_integrators_common.f90 and
test_integrators.f90), and the figure style gives a law or method the registry adds a name,
a colour and a marker of its own with no edit."""
from __future__ import annotations

import numpy as np
import pytest

import stickslip as ss
from stickslip import core, model


def test_the_constants_are_the_registrys():
    const = ss.REGISTRY["const"]
    assert core._DEFAULT_MAX_EVENTS == const["max_events"]["value"] == 10000
    assert core._MAX_BLOCKS == const["max_blocks"]["value"] == 10**6
    assert core.RTOL_MIN == const["rtol_min"]["value"] == 100.0 * np.finfo(float).eps
    kinds = sorted(ss.REGISTRY["event"].items(), key=lambda kv: kv[1]["code"])
    assert core._EVENT_KINDS == tuple(k for k, _ in kinds) == ("stick", "slip", "reversal")
    assert [info["code"] for _, info in kinds] == [1, 2, 3]


def test_the_constants_act_as_the_library_does():
    """The limits read from the registry are where the library draws its lines."""
    ss.simulate("belt", "proposed", method="dopri5", t_end=0.1, n_out=2, rtol=core.RTOL_MIN)
    with pytest.raises(ValueError, match="rtol"):
        ss.simulate("belt", "proposed", method="dopri5", t_end=0.1, n_out=2, rtol=0.99 * core.RTOL_MIN)
    with pytest.raises(ValueError, match=rf"n_blocks: must be an integer in \[1, {core._MAX_BLOCKS}\]"):
        ss.simulate("chain", "coulomb", method="moreau", h=1e-3, t_end=0.01, n_blocks=core._MAX_BLOCKS + 1)


def test_one_hmin_default():
    """1e-6 s from the facade, as the library states it (HMIN_DEFAULT); Fortran's new_controls
    and C's option defaults are checked against the same constant in the Fortran suites."""
    assert core.CONTROL_DEFAULTS["hmin"] == ss.REGISTRY["const"]["hmin"]["value"] == 1e-6
    assert ss.REGISTRY["const"]["hmin"]["unit"] == "s"


def test_the_laws_that_jump_are_the_registrys():
    """The laws implicit_euler and galpha solve over their modes on a model: those with modes."""
    modes = {law: info["modes"] for law, info in ss.REGISTRY["law"].items()}
    assert model._JUMP_LAWS == tuple(law for law in ss.LAWS if modes[law] > 0) == ("coulomb", "karnopp")
    assert ss.REGISTRY["law"]["karnopp"]["doc"] == "Karnopp stick band |v| < dv, mu_k outside"   # a '|' kept


def test_the_style_is_keyed_from_the_registry():
    """Every registered law and method has a name, a colour and a marker, distinct within its
    kind; a list with a law the style has never seen gives it its own colour and a name."""
    from harness import style
    for names, colours in ((ss.LAWS, style.LAW_COLORS), (ss.METHODS, style.METHOD_COLORS)):
        assert list(colours) == list(names) and len(set(colours.values())) == len(names)
    assert list(style.METHOD_MARKERS) == list(ss.METHODS)
    assert set(ss.LAWS) <= set(style.LAW_NAMES) and set(ss.METHODS) <= set(style.METHOD_NAMES)
    laws = (*ss.LAWS, "toy_law", "another_law")
    colours = style.keyed(laws, style._LAW_COLORS, style.SPARE_COLORS)
    assert len(set(colours.values())) == len(laws)
    assert {k: colours[k] for k in ss.LAWS} == style.LAW_COLORS        # the others unchanged
    assert style.keyed(["toy_law"], style._LAW_NAMES, (), style._spaced) == {"toy_law": "toy law"}
    markers = style.keyed((*ss.METHODS, "toy_method"), style.METHOD_MARKERS, style.SPARE_MARKERS)
    assert len(set(markers.values())) == len(ss.METHODS) + 1


# --- A law added with one module and one registry row -------------------------------------------
#: The toy law's module, as a user would write it: mu = mu_k sign(v) + toy_c v, a constant level
#: plus a linear viscous term, with a parameter of its own (toy_c [s/m]) and its status code.
TOY_MODULE = """\
!> A toy law for the registry's test: mu = mu_k sign(v) + toy_c v.
module stickslip_law_toy_viscous
    use stickslip_kinds, only: dp, SS_OK
    use stickslip_params, only: param_spec, param_values, param_read
    use stickslip_friction, only: friction_law
    implicit none
    private

    public :: toy_viscous_law

    integer, parameter :: SS_BAD_TOY_C = -199   !! toy_c out of range
    type(param_spec), parameter, public :: TOY_C_SPEC = param_spec(name='toy_c', default=1.0_dp, &
        unit='s/m', lo=0.0_dp, code=SS_BAD_TOY_C, doc='viscous coefficient of the toy law')

    !> mu_k sign(v) + toy_c v.
    type, extends(friction_law) :: toy_viscous_law
        real(dp) :: c = 1.0_dp   !! viscous coefficient [s/m]
    contains
        procedure :: init => toy_init
        procedure :: mu => toy_mu
    end type toy_viscous_law

contains

    function toy_init(self, p) result(status)
        class(toy_viscous_law), intent(inout) :: self
        type(param_values), intent(in) :: p   !! resolved parameter values
        integer :: status
        status = self%read_kinetic(p)
        if (status == SS_OK) call param_read(p, TOY_C_SPEC, self%c, status)
    end function toy_init

    elemental function toy_mu(self, v) result(mu)
        class(toy_viscous_law), intent(in) :: self
        real(dp), intent(in) :: v   !! relative sliding velocity [m/s]
        real(dp) :: mu              !! friction coefficient [-]
        mu = sign(self%mu_k, v) + self%c * v
        if (v == 0.0_dp) mu = 0.0_dp
    end function toy_mu

end module stickslip_law_toy_viscous
"""
TOY_ROW = "entry_info('toy_viscous', 'mu_k toy_c', 'toy law: mu_k sign(v) + toy_c v')"

#: Run in the copy's package: the toy law on the slope and on a model of one body, printed as JSON.
TOY_RUN = """\
import json, sys
# the clone's editable install hooks `import stickslip`; this run must see the copy's package only
sys.meta_path[:] = [f for f in sys.meta_path if "editable" not in type(f).__module__.lower()]
import stickslip as ss
assert ss.__file__.startswith(sys.argv[1]), ss.__file__
out = {"laws": list(ss.LAWS), "params": list(ss.REGISTRY["law"]["toy_viscous"]["params"]),
       "default": ss.DEFAULTS["toy_c"]}
res = ss.simulate("slope", "toy_viscous", method="dopri5", mu_k=0.1, toy_c=2.0, theta_deg=10.0,
                  g=9.81, v0=0.5, t_end=0.8, n_out=17, rtol=1e-11, atol=1e-13)
out["slope"] = [res.t.tolist(), res.x.tolist(), res.v.tolist()]
m = ss.Model()
b = m.add_body(2.0, v0=0.5)
m.add_force(b, 3.0)
m.add_contact(b, None, "toy_viscous", normal_force=10.0, mu_k=0.1, toy_c=2.0)
res = ss.simulate(m, method="dopri5", t_end=0.8, n_out=17, rtol=1e-11, atol=1e-13)
out["model"] = [res.t.tolist(), res.x[0].tolist(), res.v[0].tolist()]   # (body, time)
try:
    ss.simulate("slope", "toy_viscous", method="rk4", h=1e-3, toy_c=-1.0, t_end=0.1)
except ValueError as e:
    out["error"] = str(e)
print(json.dumps(out))
"""


def _viscous_closed_form(t: np.ndarray, a0: float, lam: float, v0: float) -> tuple[np.ndarray, np.ndarray]:
    """x, v of x'' = a0 - lam x' from x = 0, v = v0: v -> a0/lam exponentially at rate lam."""
    v_inf = a0 / lam
    decay = np.exp(-lam * t)
    return v_inf * t + (v0 - v_inf) * (1.0 - decay) / lam, v_inf + (v0 - v_inf) * decay


@pytest.mark.slow
def test_a_toy_law_needs_one_module_one_row_and_the_generator(tmp_path):
    """Copy the sources, add a law module and its LAW_TABLE row, run tools/gen_kernels.py (the
    one command of the extending guide), build the Python package there and run the law on the
    slope and on a user model: its motion is the closed form of a constant-plus-viscous drag.
    No other source file is edited: every file of the copy but the module, the registry and
    the generator's outputs is the clone's."""
    import filecmp
    import json
    import os
    import re
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    src = tmp_path / "src"
    listed = subprocess.run(["git", "ls-files", "-co", "--exclude-standard"], cwd=root, check=True,
                            capture_output=True, text=True).stdout.split("\n")
    files = [f for f in listed if f and (root / f).is_file()]
    for f in files:
        (src / f).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(root / f, src / f)
    (src / "fortran/laws/stickslip_law_toy_viscous.f90").write_text(TOY_MODULE)
    registry = src / "fortran/api/stickslip_registry.f90"
    text = registry.read_text()
    table = re.search(r"LAW_TABLE\(\*\) = \[.*?\)\]", text, re.S)
    registry.write_text(text[:table.end() - 1] + ", &\n        " + TOY_ROW + "]" + text[table.end():])

    gen = subprocess.run([sys.executable, "tools/gen_kernels.py"], cwd=src, capture_output=True, text=True)
    assert gen.returncode == 0, gen.stderr
    written = {line.split("wrote ", 1)[1] for line in gen.stdout.splitlines() if "wrote " in line}
    assert written == {"fortran/laws/stickslip_laws.f90", "fortran/laws/meson.build"}, gen.stdout
    changed = {f for f in files if not filecmp.cmp(root / f, src / f, shallow=False)}
    assert changed == written | {"fortran/api/stickslip_registry.f90"}, changed
    diff = subprocess.run(["git", "diff", "--no-index", "-U0", str(root / "fortran/api/stickslip_registry.f90"),
                           str(registry)], capture_output=True, text=True).stdout
    added = [line for line in diff.splitlines() if line.startswith("+") and not line.startswith("+++")]
    assert len(added) == 2 and "toy_viscous" in added[1], diff     # the table's last line, and the row

    # the Python extension built from the copy (no link-time optimisation: it only costs time here)
    bindir = Path(sys.executable).parent
    env = dict(os.environ, PATH=f"{bindir}{os.pathsep}{os.environ['PATH']}")
    meson = str(bindir / "meson") if (bindir / "meson").exists() else "meson"
    build = tmp_path / "build"
    for cmd in ([meson, "setup", str(build), str(src), "-Db_lto=false", "-Dbuildtype=debugoptimized"],
                [meson, "compile", "-C", str(build)]):          # the default targets: core, extensions
        run = subprocess.run(cmd, cwd=src, env=env, capture_output=True, text=True)
        assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    pkg = tmp_path / "pkg" / "stickslip"
    shutil.copytree(src / "python" / "stickslip", pkg)
    for ext in build.glob("_*.so"):
        shutil.copy2(ext, pkg)
    run = subprocess.run([sys.executable, "-c", TOY_RUN, str(pkg)], env=dict(env, PYTHONPATH=str(pkg.parent)),
                         cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout.splitlines()[-1])

    assert out["laws"][-1] == "toy_viscous" and out["params"] == ["mu_k", "toy_c"] and out["default"] == 1.0
    assert "toy_c" in out["error"] and "-1" in out["error"], out["error"]
    g, theta = 9.81, np.radians(10.0)
    # slope: x'' = g sin(theta) - (0.1 + 2 x') g cos(theta), while x' > 0
    t, x, v = map(np.asarray, out["slope"])
    want_x, want_v = _viscous_closed_form(t, g * np.sin(theta) - 0.1 * g * np.cos(theta), 2.0 * g * np.cos(theta), 0.5)
    np.testing.assert_allclose(x, want_x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(v, want_v, rtol=0, atol=1e-9)
    assert v.min() > 0
    # model: 2 x'' = 3 - 10 (0.1 + 2 x')
    t, x, v = map(np.asarray, out["model"])
    want_x, want_v = _viscous_closed_form(t, (3.0 - 10.0 * 0.1) / 2.0, 10.0 * 2.0 / 2.0, 0.5)
    np.testing.assert_allclose(x, want_x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(v, want_v, rtol=0, atol=1e-9)
    assert v.min() > 0


def test_the_checked_laws_are_the_set_valued_ones():
    """simulate checks x and v of the laws that jump or stick in a band, under the methods
    without stick/slip events: the laws the registry gives the set-valued methods."""
    set_valued = ss.REGISTRY["method"]["event_driven"]["laws"]
    assert set(set_valued) == {"coulomb", "stribeck", "karnopp"}
    assert {law for law in ss.LAWS if core._checked(law, "rk4")} == set(set_valued)
    assert not any(core._checked(law, "event_driven") for law in ss.LAWS)
