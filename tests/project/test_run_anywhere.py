"""`python -m cases` and `python -m cases.<driver>` work from any directory, not only from the
top of the clone: the reproduction suite is installed beside stickslip (meson.build installs
the cases/ folder as the package `cases`; scripts/setup's editable install maps it to the
clone's files)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _run(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}   # nothing of the clone on the path
    return subprocess.run([sys.executable, *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=600)


def test_cases_is_found_outside_the_clone(tmp_path: Path) -> None:
    proc = _run(["-c", "import cases, cases.laws; print(cases.__file__)"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert Path(proc.stdout.strip()).resolve().is_relative_to(ROOT / "cases") or "site-packages" in proc.stdout


def test_python_m_cases_from_a_temporary_directory(tmp_path: Path) -> None:
    """The whole suite's entry point and one driver, each run from an empty directory, write
    their files under the relative --outdir there."""
    proc = _run(["-m", "cases", "--only", "laws", "--quiet", "--jobs", "1", "--outdir", "out"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "out" / "fig01_law_coulomb.png").is_file()
    proc = _run(["-m", "cases.laws", "--outdir", "one", "--points", "101"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "one").is_dir() and any((tmp_path / "one").rglob("fig02_law_recurdyn.csv"))


def test_help_from_a_temporary_directory(tmp_path: Path) -> None:
    proc = _run(["-m", "cases.advise", "--help"], tmp_path)
    assert proc.returncode == 0 and "--target" in proc.stdout, proc.stderr
