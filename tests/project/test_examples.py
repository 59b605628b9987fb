"""The examples of README.md and the documentation run as written.

Every fenced block of README.md and docs/**/*.md whose language is `python` or `sh` is run on its
own, in an empty temporary directory, with the installed package (this interpreter, the venv's
bin first on PATH, nothing of the repository on the path): a Python block as a script file, a
shell block by `bash -e`. A block that is shown but not meant to run (a job of minutes, a
cluster it needs, files only a full regeneration writes) is written as a `{code-block}`
directive instead, which this test does not see. The shell blocks of the Fortran and C guide
are run by tests/project/test_install.py, which checks what their programs print.

Where the page shows what a block prints (a ```text or bare ``` block after it, introduced by a
sentence that says it "prints" or "printed"), every shown line must be printed, in that order, with the same words
and numbers: equal to the digits shown, except timings (a number with a unit of time on a line
about CPU or wall time, or per call), which only need the same order of magnitude (a factor
TIMING_FACTOR either way: the machine's speed varies, its results do not).
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: Pages whose blocks another test runs exactly as written (and checks more closely).
RUN_ELSEWHERE: dict[str, str] = {"docs/guide/fortran-c.md": "tests/project/test_install.py"}
BLOCK = re.compile(r"^```(python|sh)[ \t]*\n(.*?)^```[ \t]*$", re.S | re.M)
#: After a block: a short sentence that says it prints, then the ```text (or bare ```) block of
#: its output.
SHOWN = re.compile(r"\n(?P<intro>[^`]{0,300}?\b(?:prints?|printed)\b[^`]{0,300}?)\n```(?:text)?[ \t]*\n(?P<out>.*?)^```",
                   re.S | re.M)
NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d+)?|\.\d+)(?:[eE][+-]?\d+)?")
TIMING_LINE = re.compile(r"\b(CPU|cpu|wall|took|per call|elapsed)\b")
TIME_UNIT = r"\s?(?:s|ms|us|µs|ns)\b"
TIMING_FACTOR = 10.0
#: Pages whose shown output is not yet compared, and why: may only shrink.
OUTPUT_NOT_COMPARED: dict[str, str] = {}
#: Optional packages an example may import: without them the example is skipped, saying why.
OPTIONAL: dict[str, str] = {"distributed": "Dask's distributed (pip install '.[dask]')"}


def optional_missing(code: str) -> list[str]:
    """The optional packages `code` imports that this interpreter lacks."""
    import importlib.util
    imported = {m.split(".")[0] for m in re.findall(r"^\s*(?:import|from)\s+([\w.]+)", code, re.M)}
    return [OPTIONAL[m] for m in sorted(imported & OPTIONAL.keys()) if importlib.util.find_spec(m) is None]


def pages() -> list[Path]:
    docs = [p for p in sorted((ROOT / "docs").rglob("*.md"))
            if "figures" not in p.relative_to(ROOT / "docs").parts]
    return [ROOT / "README.md", *docs]


def blocks() -> list[tuple[str, int, str, str, str | None]]:
    """(page, line, language, code, the output the page shows or None) of every runnable block."""
    out = []
    for page in pages():
        rel = page.relative_to(ROOT).as_posix()
        if rel in RUN_ELSEWHERE:
            continue
        text = page.read_text()
        for m in BLOCK.finditer(text):
            shown = SHOWN.match(text, m.end())
            out.append((rel, text.count("\n", 0, m.start()) + 1, m.group(1), m.group(2),
                        shown.group("out") if shown else None))
    return out


BLOCKS = blocks()


def _timings(line: str) -> set[int]:
    """The positions of the numbers of `line` that are timings."""
    if not TIMING_LINE.search(line):
        return set()
    return {i for i, m in enumerate(NUMBER.finditer(line)) if re.match(TIME_UNIT, line[m.end():])}


def same_line(shown: str, printed: str) -> bool:
    """`printed` says what `shown` says: the same words, each number equal to the digits
    shown (a number the page cuts with "..." to its first digits; a timing within
    TIMING_FACTOR)."""
    cut = [shown[m.end():].startswith("...") for m in NUMBER.finditer(shown)]
    plain = re.sub(r"(\d)\.\.\.", r"\1", shown)
    if NUMBER.sub("#", plain).split() != NUMBER.sub("#", printed).split():
        return False
    timings = _timings(plain)
    for i, (a, b) in enumerate(zip(NUMBER.findall(plain), NUMBER.findall(printed))):
        x, y = float(a), float(b)
        if i in timings:
            if not (x == y or (x > 0 and y > 0 and 1 / TIMING_FACTOR <= y / x <= TIMING_FACTOR)):
                return False
        elif not (b.startswith(a) if cut[i] else a == b):
            return False
    return True


def unmatched(shown: str, printed: str) -> list[str]:
    """The shown lines not printed in that order (an empty list: the page shows the output)."""
    lines = [ln for ln in printed.splitlines() if ln.strip()]
    missing, k = [], 0
    for want in (ln for ln in shown.splitlines() if ln.strip()):
        j = next((j for j in range(k, len(lines)) if same_line(want, lines[j])), None)
        if j is None:
            missing.append(want)
        else:
            k = j + 1
    return missing


def test_the_output_checker() -> None:
    """Equal digits for results, the order of magnitude for a timing, lines in order."""
    printed = "x(2 s) = 1.00e-02 m   2066 evaluations\nCPU 4.1 us per call\ndone\n"
    assert unmatched("x(2 s) = 1.00e-02 m   2066 evaluations\ndone", printed) == []
    assert unmatched("CPU 9.5 us per call", printed) == []                  # a timing
    assert unmatched("CPU 95 us per call", printed) == ["CPU 95 us per call"]
    assert unmatched("x(2 s) = 1.01e-02 m   2066 evaluations", printed) != []
    assert unmatched("done\nx(2 s) = 1.00e-02 m   2066 evaluations", printed) != []    # order
    assert unmatched("x(2 s) = 1.00e-02 m   20... evaluations", printed) == []         # cut
    assert unmatched("x(2 s) = 1.00e-02 m   21... evaluations", printed) != []
    page = "```python\nprint(1)\n```\n\nIt prints:\n\n```text\n1\n```\n"
    m = BLOCK.search(page)
    assert SHOWN.match(page, m.end()).group("out") == "1\n"


def test_the_pages_left_uncompared_show_output() -> None:
    """OUTPUT_NOT_COMPARED names only pages with shown output (else it has to shrink)."""
    shown = {page for page, _, _, _, out in BLOCKS if out is not None}
    assert set(OUTPUT_NOT_COMPARED) <= shown, set(OUTPUT_NOT_COMPARED) - shown


def test_the_pages_have_examples() -> None:
    """README's example and the guide's are found (the reader is not silently empty)."""
    found = {(page, lang) for page, _, lang, _, _ in BLOCKS}
    assert ("README.md", "python") in found
    assert ("docs/guide/dask.md", "python") in found
    assert len(BLOCKS) >= 5


@pytest.mark.parametrize("page,line,lang,code,shown", BLOCKS,
                         ids=[f"{p}:{n}" for p, n, _, _, _ in BLOCKS])
def test_example_runs_as_written(tmp_path: Path, page: str, line: int, lang: str,
                                 code: str, shown: str | None) -> None:
    missing_packages = optional_missing(code)
    if missing_packages:
        pytest.skip(f"{page}:{line} needs the optional {', '.join(missing_packages)}, not installed")
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
    if shown is not None and page not in OUTPUT_NOT_COMPARED:
        missing = unmatched(shown, proc.stdout)
        assert not missing, (f"{page}:{line} does not print what the page shows: {missing}\n"
                             f"it printed:\n{proc.stdout}")
