"""The examples of README.md and the documentation run as written.

Every fenced block of README.md and docs/**/*.md whose language is `python` or `sh` is run on its
own, in an empty temporary directory, with the installed package (this interpreter, the venv's
bin first on PATH, nothing of the repository on the path): a Python block as a script file, a
shell block by `bash -e`. A block that is shown but not meant to run (a job of minutes, a
cluster it needs, files only a full regeneration writes) is written as a `{code-block}`
directive instead, which this test does not see. The shell blocks of the Fortran and C guide
are run by tests/test_install.py, which checks what their programs print.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Pages whose blocks another test runs exactly as written (and checks more closely).
RUN_ELSEWHERE: dict[str, str] = {"docs/guide/fortran-c.md": "tests/test_install.py"}
BLOCK = re.compile(r"^```(python|sh)[ \t]*\n(.*?)^```[ \t]*$", re.S | re.M)


def pages() -> list[Path]:
    docs = [p for p in sorted((ROOT / "docs").rglob("*.md"))
            if "figures" not in p.relative_to(ROOT / "docs").parts]
    return [ROOT / "README.md", *docs]


def blocks() -> list[tuple[str, int, str, str]]:
    """(page, line, language, code) of every runnable block."""
    out = []
    for page in pages():
        rel = page.relative_to(ROOT).as_posix()
        if rel in RUN_ELSEWHERE:
            continue
        text = page.read_text()
        for m in BLOCK.finditer(text):
            out.append((rel, text.count("\n", 0, m.start()) + 1, m.group(1), m.group(2)))
    return out


BLOCKS = blocks()


def test_the_pages_have_examples() -> None:
    """README's example and the guide's are found (the reader is not silently empty)."""
    found = {(page, lang) for page, _, lang, _ in BLOCKS}
    assert ("README.md", "python") in found
    assert ("docs/guide/dask.md", "python") in found
    assert len(BLOCKS) >= 5


@pytest.mark.parametrize("page,line,lang,code", BLOCKS,
                         ids=[f"{p}:{n}" for p, n, _, _ in BLOCKS])
def test_example_runs_as_written(tmp_path: Path, page: str, line: int, lang: str,
                                 code: str) -> None:
    env = {"PATH": f"{Path(sys.executable).parent}{os.pathsep}/usr/local/bin:/usr/bin:/bin",
           "HOME": str(tmp_path), "MPLBACKEND": "Agg", "LANG": "C.UTF-8",
           "OPENBLAS_NUM_THREADS": "1"}
    if lang == "python":
        script = tmp_path / "example.py"
        script.write_text(code)
        cmd = [sys.executable, str(script)]
    else:
        cmd = ["bash", "-e", "-c", code]
    proc = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"{page}:{line} failed\nstdout:\n{proc.stdout}\nstderr:\n{proc.stderr}"
    assert "Traceback" not in proc.stderr, proc.stderr
