"""The source layout: fortran/ in its layer folders, every module built by meson, and the
integrators' specialised kernels as tools/gen_kernels.py writes them from the registry."""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import gen_kernels  # noqa: E402

LAYERS = {"core", "laws", "integrators", "scenes", "api"}


def test_generated_kernels_are_current():
    """The committed kernel includes are what the generator writes from the registry now."""
    run = subprocess.run([sys.executable, str(ROOT / "tools" / "gen_kernels.py"), "--check"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def test_kernels_follow_the_registry_flags():
    """The kernels are those of the registry's kernel=.true. entries, no more: unmarking a law
    drops its kernels and its dispatch case; the generic kernel always stays."""
    source = gen_kernels.REGISTRY.read_text()
    assert gen_kernels.kernel_entries(source, "SCENE_TABLE") == ["slope", "belt"]
    assert gen_kernels.kernel_entries(source, "LAW_TABLE") == ["coulomb", "recurdyn", "proposed", "stribeck"]
    edited = re.sub(r"('stribeck'.*?), kernel=\.true\.\)", r"\1)", source, count=1, flags=re.S)
    laws = gen_kernels.kernel_entries(edited, "LAW_TABLE")
    assert laws == ["coulomb", "recurdyn", "proposed"]
    text = gen_kernels.instances(["slope", "belt"], laws) + gen_kernels.dispatch(["slope", "belt"], laws)
    assert "stribeck" not in text and "kernel_belt_proposed" in text and "generic_kernel" in text


def test_every_module_is_in_a_layer_and_built():
    """No Fortran source outside the layer folders, and meson.build compiles every module."""
    assert not list((ROOT / "fortran").glob("*.f90")) and not list((ROOT / "fortran").glob("*.inc"))
    assert {p.name for p in (ROOT / "fortran").iterdir() if p.is_dir()} == LAYERS
    meson = (ROOT / "meson.build").read_text()
    listed = set(re.findall(r"'(fortran/\w+/stickslip\w*\.f90)'", meson))
    on_disk = {str(p.relative_to(ROOT)) for p in (ROOT / "fortran").glob("*/*.f90")}
    assert listed == on_disk
