"""Where a results file came from: the command, the date and the machine that made it.

Every command that writes results (the drivers of cases/, python -m benchmarks) finishes with
`write_provenance(outdir, name, files)`, which writes the sidecar `<outdir>/<name>.provenance.json`
beside its files: the command line, the UTC date, the machine (CPU model, cores, operating
system), the Python and stickslip versions, the git commit of the sources, and the names of the
files that run wrote. The CSV files themselves keep their plain contract (one header row with
units), so every reader of them stays as it is. `provenance_of(path)` finds the sidecar that
names a file; the documentation's tables quote it (tools/doctables.py).

Paths inside the repository are recorded relative to its top, so a sidecar committed with
docs/figures/ names no path of the machine that made it.
"""
from __future__ import annotations

import datetime
import json
import os
import platform
import shlex
import subprocess
import sys
from pathlib import Path
from typing import Any, Iterable, Mapping, Sequence

ROOT: Path = Path(__file__).resolve().parent.parent
SUFFIX: str = ".provenance.json"


def machine() -> str:
    """The CPU model (lscpu's "Model name", else the platform's processor) and the cores this
    process may use, e.g. "AMD EPYC 7B13, 2 cores, Linux x86_64"."""
    model = ""
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
                break
    except (OSError, subprocess.CalledProcessError):
        pass
    model = model or platform.processor() or platform.machine()
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:                      # not on Linux
        cores = os.cpu_count() or 1
    return f"{model}, {cores} cores, {platform.system()} {platform.machine()}"


def _relative(word: str) -> str:
    """A path inside the repository, relative to its top; any other word unchanged."""
    try:
        p = Path(word)
        if p.is_absolute() and p.resolve().is_relative_to(ROOT):
            return p.resolve().relative_to(ROOT).as_posix() or "."
    except (OSError, ValueError):
        pass
    return word


def command_line(module: str, argv: Sequence[str] | None, shown: Mapping[str, str] | None = None) -> str:
    """The command as a user would type it: the command this process was started with when it
    is a module of this repository (python -m cases --all runs every driver as a child), else
    `python -m <module> <argv>` (a driver called from Python, e.g. by a test). A word that is a
    key of `shown` is written as its value (a path of this machine as its placeholder)."""
    start = Path(sys.argv[0]).resolve() if sys.argv and sys.argv[0] else None
    if start is not None and start.suffix == ".py" and start.is_relative_to(ROOT) \
            and start.parent != ROOT and start.parent.name in ("cases", "benchmarks"):
        parts = start.relative_to(ROOT).with_suffix("").parts
        mod = ".".join(parts[:-1] if parts[-1] == "__main__" else parts)
        words = sys.argv[1:]
    else:
        mod, words = module, list(argv if argv is not None else [])
    shown = shown or {}
    return shlex.join(["python", "-m", mod, *(shown.get(str(w), _relative(str(w))) for w in words)])


def _commit() -> str | None:
    """The git commit of the sources (with "+changes" when the work tree differs), or None."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=ROOT,
                              capture_output=True, text=True, check=True, timeout=10).stdout.strip()
        # the sources only: results being rewritten by this very command do not count
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--", ".",
                                ":(exclude)docs", ":(exclude)benchmarks/results"], cwd=ROOT,
                               capture_output=True, text=True, check=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return head + ("+changes" if dirty else "")


def provenance(module: str, argv: Sequence[str] | None = None,
               shown: Mapping[str, str] | None = None) -> dict[str, Any]:
    """The provenance record of a run of `module` with `argv` (no file list); `shown` as for
    `command_line`."""
    try:
        from stickslip import __version__ as version
    except ImportError:                         # benchmarks may run without the package
        version = None
    return {"command": command_line(module, argv, shown),
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "machine": machine(), "load_average": round(os.getloadavg()[0], 2),
            "python": platform.python_version(),
            "stickslip": version, "commit": _commit()}


def write_provenance(outdir: str | os.PathLike[str], module: str, files: Iterable[Path],
                     argv: Sequence[str] | None = None, shown: Mapping[str, str] | None = None) -> Path:
    """Write `<outdir>/<module>.provenance.json` naming `files` (those in outdir) and return
    its path. A sidecar left by an earlier run of the same module keeps the names of files this
    run did not write again (a --only or --quick run rewrites part of a directory), each with the
    record of the run that made it."""
    from .files import write_text                 # atomic, like every results file
    outdir = Path(outdir)
    path = outdir / f"{module}{SUFFIX}"
    record = provenance(module, argv, shown)
    names = sorted({Path(f).name for f in files if Path(f).parent.resolve() == outdir.resolve()})
    runs: list[dict[str, Any]] = [dict(record, files=names)]
    try:
        old = json.loads(path.read_text())
        for run in old.get("runs", []):
            kept = [n for n in run.get("files", []) if n not in names]
            if kept:
                runs.append(dict(run, files=kept))
    except (OSError, ValueError):
        pass
    return write_text(path, json.dumps({"runs": runs}, indent=1) + "\n")


def provenance_of(path: str | os.PathLike[str]) -> dict[str, Any] | None:
    """The record of the run that wrote `path` (from a sidecar beside it), or None."""
    path = Path(path)
    for sidecar in sorted(path.parent.glob(f"*{SUFFIX}")):
        try:
            runs = json.loads(sidecar.read_text()).get("runs", [])
        except (OSError, ValueError):
            continue
        for run in runs:
            if path.name in run.get("files", []):
                return run
    return None
