"""Tests of the command lines in cases/ that need no full simulation: file permissions, argument
validation before any simulation, fail-fast on the first failed run, the set-up script's
detection of a missing python3-venv."""
from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from cases import _common

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("umask,expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_written_files_follow_umask(tmp_path: Path, umask: int, expected: int) -> None:
    """CSV, text and PNG files get 0666 less the umask, like any new file (not mkstemp's 0600),
    also when they replace an existing file."""
    old = os.umask(umask)
    try:
        paths = [_common.write_csv(tmp_path / "a.csv", ["x [m]"], [[1.0]]),
                 _common.write_text(tmp_path / "a.md", "text\n"),
                 _common.atomic_write(tmp_path / "a.png", lambda f: f.write(b"\x89PNG"),
                                      binary=True),
                 _common.write_text(tmp_path / "a.md", "again\n")]
    finally:
        os.umask(old)
    for p in paths:
        assert stat.S_IMODE(p.stat().st_mode) == expected, p
    assert (tmp_path / "a.md").read_text() == "again\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "a.md", "a.png"]
