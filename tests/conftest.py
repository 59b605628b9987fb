"""Shared fixtures: a meson build of the native test programs (Fortran unit tests and
the GSL reference), made once per session in build/native next to the Python build."""
from __future__ import annotations

import contextlib
import fcntl
import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: The folders of tests/ beside this one (tests/README.md gives the layout): on sys.path, so that a
#: test file may import the references another file defines, wherever either lives.
for _folder in ("cases", "fortran", "project"):
    sys.path.insert(0, str(Path(__file__).resolve().parent / _folder))


def _tool(name: str) -> str:
    """A build tool from the running Python's environment, else from PATH."""
    here = Path(sys.executable).parent / name
    found = str(here) if here.exists() else shutil.which(name)
    if found is None:
        pytest.fail(f"{name} not found: run scripts/setup (README) first")
    return found


#: The native test build without link-time optimisation: with it, every test program's link
#: re-optimises the whole core (minutes per program on two cores; without, seconds). The code
#: and its arithmetic are the same (no -ffast-math, no FMA contraction on x86-64); the LTO build
#: is what the Python extension (every Python test) and the installed library (test_install,
#: slow) are built with.
NATIVE_OPTIONS: tuple[str, ...] = ("-Db_lto=false",)


def _configured_lto(build: Path) -> bool | None:
    """b_lto of a configured meson build directory (None when it cannot be read)."""
    info = build / "meson-info" / "intro-buildoptions.json"
    try:
        import json
        return next(o["value"] for o in json.loads(info.read_text()) if o["name"] == "b_lto")
    except (OSError, ValueError, StopIteration):
        return None


@contextlib.contextmanager
def build_lock(build: Path) -> Iterator[None]:
    """Hold the lock of a build directory shared by the test processes (pytest-xdist's workers
    each set up and compile build/native; meson and ninja must not run twice in one directory)."""
    build.parent.mkdir(parents=True, exist_ok=True)
    with open(build.parent / f".{build.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


@pytest.fixture(scope="session")
def native_build() -> Path:
    """build/native, configured (NATIVE_OPTIONS) and with the test programs compiled."""
    build = Path(os.environ.get("STICKSLIP_NATIVE_BUILD", ROOT / "build" / "native"))
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    with build_lock(build):
        if not (build / "build.ninja").exists():
            subprocess.run([_tool("meson"), "setup", str(build), str(ROOT), *NATIVE_OPTIONS], check=True,
                           env=env, capture_output=True, text=True)
        elif _configured_lto(build):          # a directory set up before NATIVE_OPTIONS: once
            subprocess.run([_tool("meson"), "configure", str(build), *NATIVE_OPTIONS], check=True,
                           env=env, capture_output=True, text=True)
    return build


def compile_target(build: Path, target: str) -> Path:
    """Compile one meson target of the native build and return the executable."""
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    with build_lock(build):
        proc = subprocess.run([_tool("meson"), "compile", "-C", str(build), target], env=env,
                              capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    exe = build / target
    assert exe.exists(), f"{exe} was not built"
    return exe


def xdist_group(item: pytest.Item) -> str | None:
    """The worker group of a test under pytest-xdist (--dist loadgroup, scripts/test): the tests
    of the native build on one worker (the others go on while it compiles), the tests sharing a
    module-scoped fixture on one worker per file (each worker would compute the fixture again);
    None for the rest, which go wherever a worker is free."""
    if "native_build" in item.fixturenames:
        return "native_build"
    info = getattr(item, "_fixtureinfo", None)
    defs = info.name2fixturedefs.values() if info is not None else ()
    if any(d and d[-1].scope in ("module", "package", "class") for d in defs):
        return item.nodeid.split("::", 1)[0]
    return None


def pytest_collection_modifyitems(config, items):
    """Tests marked slow run only with STICKSLIP_SLOW=1 in the environment; each test joins its
    xdist_group (a mark the tests set themselves is kept)."""
    for item in items:
        group = xdist_group(item)
        if group is not None and item.get_closest_marker("xdist_group") is None:
            item.add_marker(pytest.mark.xdist_group(group))
    if os.environ.get("STICKSLIP_SLOW") == "1":
        return
    skip = pytest.mark.skip(reason="slow: set STICKSLIP_SLOW=1 to run")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)


def pytest_configure(config):
    """Under pytest-xdist, the controlling process brings the editable build of stickslip up to
    date (importing it rebuilds what changed) before the workers start, so that they never
    rebuild it at once in one build directory."""
    if getattr(config.option, "numprocesses", None) and not hasattr(config, "workerinput"):
        import stickslip  # noqa: F401
