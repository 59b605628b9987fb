"""Tests of the command lines in cases/ that need no full simulation: file permissions, argument
validation before any simulation, fail-fast on the first failed run, the set-up script's
detection of a missing python3-venv."""
from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from cases import _common

ROOT = Path(__file__).resolve().parents[2]


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


# ---------------------------------------------------------------- arguments checked up front
@pytest.mark.parametrize("module,argv,named", [
    ("slope", ["--rtols", "1e-2", "1e-4", "1e-20"], "argument --rtols: must be finite and in [100 eps = 2.2e-14, 1)"),
    ("slope", ["--rtols", "1e-2", "1e-4", "1"], "argument --rtols: must be finite and in [100 eps"),
    ("belt", ["--workers", "0"], "argument --workers: must be an integer >= 1, got 0"),
    ("belt", ["--workers", "-3"], "argument --workers: must be an integer >= 1, got -3"),
    ("slope", ["--t-end", "inf"], "argument --t-end: must be finite and > 0"),
    ("slope", ["--t-end", "0"], "argument --t-end: must be finite and > 0"),
    ("slope", ["--t-end", "1e9"], "argument --t-end: must be <= 10000 s"),
    ("belt", ["--t-end", "2", "--max-steps", "1000"], "argument --t-end: must be <= 0.1 s"),
    ("belt", ["--points", "1"], "argument --points: must be an integer >= 2"),
    ("slope", ["--atol-ratio", "nan"], "argument --atol-ratio: must be finite and > 0"),
    ("slope", ["--theta-deg", "95"], "theta_deg: must be"),
    ("workprecision", ["--threads", "0"], "argument --threads: must be an integer >= 1"),
    ("stability", ["--threads", "-1"], "argument --threads: must be an integer >= 1"),
])
def test_bad_arguments_fail_before_any_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                           capsys: pytest.CaptureFixture[str], module: str,
                                           argv: list[str], named: str) -> None:
    """Each bad argument ends the command with a usage error (exit 2) naming the argument and
    its accepted range, before the runner starts and without writing a file."""
    import importlib
    driver = importlib.import_module(f"cases.{module}")

    def no_runs(*args: object, **kwargs: object) -> None:
        raise AssertionError("a simulation started")

    monkeypatch.setattr(_common, "run_all", no_runs)
    with pytest.raises(SystemExit) as exit_info:
        driver.main(["--outdir", str(tmp_path), *argv])
    assert exit_info.value.code == 2
    assert named in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_main_rejects_bad_counts(capsys: pytest.CaptureFixture[str]) -> None:
    from cases import __main__ as cases_main
    for argv in (["--workers", "0"], ["--threads", "0"], ["--jobs", "0"]):
        with pytest.raises(SystemExit):
            cases_main.main(argv)
        assert "must be an integer >= 1" in capsys.readouterr().err


# ---------------------------------------------------------------- the first failure ends it all
def test_first_failure_cancels_queued_and_running_runs() -> None:
    """A run that fails at once, started beside a long run (10^10 steps, hours) and ahead of
    another queued long run, ends run_all with its failure and leaves no worker process: had
    run_all waited for the long runs, it would not return for hours (no clock is read)."""
    import multiprocessing
    long_a = _common.Run("slope", "recurdyn", "rk4", 1e5, 11, h=1e-5, max_steps=10**11)     # 1e10 steps
    failing = _common.Run("slope", "coulomb", "dopri5", 5e3, 11, rtol=1e-6, atol=1e-9, max_steps=10)
    long_c = _common.Run("slope", "recurdyn", "rk4", 4e4, 11, h=1e-5, max_steps=10**11)     # 4e9 steps
    assert long_a.cost_hint() > failing.cost_hint() > long_c.cost_hint()        # start order
    with pytest.raises(_common.SimulationFailed, match="step budget"):
        _common.run_all([long_a, failing, long_c], workers=2, quiet=True)
    assert multiprocessing.active_children() == []


def test_cli_failure_exits_nonzero_quickly(tmp_path: Path) -> None:
    """python -m cases.slope whose Coulomb DOPRI5 run cannot finish within its step budget
    prints the failure and exits 1 without waiting for the other runs."""
    import subprocess
    import sys
    proc = subprocess.run([sys.executable, "-m", "cases.slope", "--outdir", str(tmp_path),
                           "--t-end", "100", "--max-steps", "2000000", "--quiet"],
                          cwd=ROOT, capture_output=True, text=True, timeout=20)
    assert proc.returncode == 1
    assert "simulation failed: slope coulomb dopri5" in proc.stderr
    assert "step budget exhausted" in proc.stderr


# ---------------------------------------------------------------- console output of the studies
def test_study_prints_every_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                 capsys: pytest.CaptureFixture[str]) -> None:
    from cases import stability, workprecision
    for module in (stability, workprecision):
        written = [tmp_path / "b.csv", tmp_path / "a.png"]
        monkeypatch.setattr(module, "run", lambda outdir, **kw: list(written))
        sidecar = tmp_path / f"{module.__name__}.provenance.json"     # command, date, machine
        assert module.main(["--outdir", str(tmp_path)]) == written + [sidecar]
        assert capsys.readouterr().out.split() == sorted(str(p) for p in written + [sidecar])


def test_fit_order_refuses_round_off() -> None:
    """An order is fitted only over >= 3 points above round-off: h^4 errors give 4, errors at
    round-off or zero give None (not 858.8 or nan)."""
    import numpy as np
    from cases import workprecision
    h = np.array([1e-2, 5e-3, 2.5e-3, 1.25e-3])
    order, n = workprecision.fit_order(h, 1e-3 * (h / 1e-2) ** 4, 1e-13)
    assert order == pytest.approx(4.0) and n == 4
    assert workprecision.fit_order(h, np.array([3e-13, 1e-14, 2e-14, 0.0]), 1e-13) == (None, 1)


def test_stability_boundary_is_bracketed() -> None:
    """boundary() gives the last stable h and the first non-stable one around h_lin."""
    from cases import stability
    rows = [["slope", "recurdyn", 1e-2, h, 5e-3, 1.0, 0, 0, 0.0, 0, 0, cls]
            for h, cls in ((2e-3, "stable"), (3.4e-3, "stable"), (5e-3, "spurious"),
                           (7e-3, "stable"), (1e-2, "unstable"))]
    rows.append(["slope", "coulomb", 1e-2, 1e-3, float("inf"), 1.0, 0, 0, 0.0, 0, 0, "chattering"])
    assert stability.boundary(rows) == [["slope", "recurdyn", 1e-2, 5e-3, 3.4e-3, 5e-3,
                                         pytest.approx(0.68), pytest.approx(1.0)]]


# ---------------------------------------------------------------- scripts/setup on a fresh Debian
@pytest.mark.parametrize("has_ensurepip", [True, False])
def test_setup_detects_missing_python3_venv(tmp_path: Path, has_ensurepip: bool) -> None:
    """scripts/setup asks apt-get for python3-venv exactly when `python3` cannot import
    ensurepip (Debian's Python without python3-venv), shown with a stand-in python3 on PATH;
    --print-missing installs nothing."""
    import shutil
    import subprocess
    import sys
    fake = tmp_path / "python3"
    fail = "" if has_ensurepip else 'case "$*" in *ensurepip*) exit 1;; esac\n'
    fake.write_text(f"#!/bin/sh\n{fail}exec {sys.executable} \"$@\"\n")
    fake.chmod(0o755)
    env = dict(os.environ, PATH=f"{tmp_path}{os.pathsep}{os.environ['PATH']}")
    assert shutil.which("python3", path=env["PATH"]) == str(fake)
    proc = subprocess.run([str(ROOT / "scripts" / "setup"), "--print-missing"], env=env,
                          capture_output=True, text=True, timeout=30)
    assert proc.returncode == 0, proc.stderr
    assert ("python3-venv" in proc.stdout.split()) == (not has_ensurepip)


# ---------------------------------------------------------------- output directories
DRIVERS = ("laws", "slope", "belt", "workprecision", "stability", "laws_compare", "implicit",
           "speedup")


@pytest.mark.parametrize("module", [*DRIVERS, "__main__"])
def test_unwritable_outdir_fails_before_any_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                capsys: pytest.CaptureFixture[str],
                                                module: str) -> None:
    """An --outdir that cannot be written (here: below a plain file, which stops root too)
    ends the command with a usage error naming it, exit 2, before any simulation."""
    import importlib
    driver = importlib.import_module(f"cases.{module}")

    def no_runs(*args: object, **kwargs: object) -> None:
        raise AssertionError("a simulation started")

    monkeypatch.setattr(_common, "run_all", no_runs)
    monkeypatch.setattr(driver, "run", no_runs, raising=False)
    monkeypatch.setattr(driver, "run_jobs", no_runs, raising=False)
    monkeypatch.setattr(driver, "_run_driver", no_runs, raising=False)
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    with pytest.raises(SystemExit) as exit_info:
        driver.main(["--outdir", str(blocker / "out")])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert f"argument --outdir: cannot write into {blocker / 'out'}" in err
    assert "Traceback" not in err


def test_unwritable_outdir_from_the_shell(tmp_path: Path) -> None:
    """The same as a user sees it: one line on stderr, exit status 2, no traceback."""
    import subprocess
    import sys
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    proc = subprocess.run([sys.executable, "-m", "cases.slope", "--outdir", str(blocker / "x")],
                          cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert "cannot write into" in proc.stderr and "Traceback" not in proc.stderr


def test_non_default_parameters_never_overwrite_the_papers_figures(tmp_path: Path) -> None:
    """A run with other parameters writes into a subdirectory named after them, records its
    command beside its files, and leaves the paper's own files alone."""
    import json
    from cases import laws
    paper = laws.main(["--outdir", str(tmp_path)])
    assert {f.parent for f in paper} == {tmp_path}
    before = {f: f.read_bytes() for f in paper if f.suffix == ".csv"}
    other = laws.main(["--outdir", str(tmp_path), "--mu-s", "0.5", "--v-max", "1"])
    assert {f.parent for f in other} == {tmp_path / "mu_s=0.5_v_max=1"}
    assert all(f.read_bytes() == data for f, data in before.items())
    sidecar = json.loads((tmp_path / "mu_s=0.5_v_max=1" / "cases.laws.provenance.json").read_text())
    assert "--mu-s 0.5" in sidecar["runs"][0]["command"]
    assert "fig01_law_coulomb.csv" in sidecar["runs"][0]["files"]


def test_parameter_outdir_names() -> None:
    """The subdirectory and the title note say which options differ from the paper's."""
    import argparse
    parser = argparse.ArgumentParser()
    parser.add_argument("--outdir", type=Path, default=Path("out"))
    parser.add_argument("--theta-deg", type=float, default=10.0)
    parser.add_argument("--rtols", type=float, nargs="+", default=(1e-2, 1e-4))
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--workers", type=int, default=2)
    same = parser.parse_args(["--outdir", "o", "--theta-deg", "10", "--rtols", "0.01", "0.0001",
                              "--workers", "1"])
    assert _common.changed_options(parser, same) == {}
    assert _common.parameter_outdir(Path("o"), {}) == (Path("o"), "")
    args = parser.parse_args(["--theta-deg", "30", "--rtols", "1e-3", "--quick"])
    changed = _common.changed_options(parser, args)
    assert changed == {"theta_deg": 30.0, "rtols": [1e-3], "quick": True}
    assert _common.parameter_outdir(Path("out"), changed) == (
        Path("out") / "quick_rtols=0.001_theta_deg=30", "quick, rtols = 0.001, theta_deg = 30")


def test_quick_benchmarks_leave_the_tracked_results_alone(tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    """python -m benchmarks (and --quick) writes into out/benchmarks/; only --results writes
    the tracked benchmarks/results/, and not with --quick."""
    from benchmarks import run

    class Stop(Exception):
        pass

    def stop(build_dir: Path) -> None:
        raise Stop

    monkeypatch.setattr(run, "build", stop)
    monkeypatch.chdir(tmp_path)
    tracked = {p: p.stat().st_mtime_ns for p in run.RESULTS_DIR.iterdir()}
    with pytest.raises(Stop):
        run.main(["--quick"])
    assert (tmp_path / "out" / "benchmarks").is_dir()
    with pytest.raises(SystemExit) as exit_info:
        run.main(["--quick", "--results"])
    assert exit_info.value.code == 2
    assert "argument --results: not with --quick" in capsys.readouterr().err
    assert {p: p.stat().st_mtime_ns for p in run.RESULTS_DIR.iterdir()} == tracked


# ---------------------------------------------------------------- --help
@pytest.mark.parametrize("module", [*(f"cases.{d}" for d in DRIVERS), "cases", "benchmarks",
                                    "benchmarks.sweep_dask"])
def test_help_is_complete(module: str) -> None:
    """`python -m MODULE --help` exits 0 and shows the description whole: it ends a sentence
    (or a usage block), and every option has its help text."""
    import subprocess
    import sys
    proc = subprocess.run([sys.executable, "-m", module, "--help"], cwd=ROOT, capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    text = proc.stdout
    description = text.split("\n\n", 1)[1].split("\noptions:")[0].strip()
    assert description and not description.endswith((":", ",")), description[-200:]
    assert "::" not in description
    options = text.split("\noptions:", 1)[1]
    for line in options.splitlines():
        if line.startswith("  -") and "  " not in line.strip():     # option alone on its line
            nxt = options.splitlines()[options.splitlines().index(line) + 1]
            assert nxt.startswith(" " * 10), f"{module}: {line.strip()} has no help"


def test_step_search_runs_beyond_the_bound_without_warnings() -> None:
    """laws_compare probes RK4 beyond its stability bound on purpose: the facade's warning,
    which tells a user calling simulate() directly, is handled there and not printed; any other
    warning still is."""
    import warnings
    import stickslip
    from cases import laws_compare
    with pytest.warns(UserWarning, match="beyond RK4's stability bound"):
        stickslip.simulate("slope", "recurdyn", method="rk4", h=0.01, t_end=0.1, n_out=11)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r, status = laws_compare.simulate("slope", "recurdyn", "rk4", 0.01, 0.1, 11)
    assert status == 0 and len(r.x) == 11


def test_benchmarks_replot_draws_from_the_csv_alone(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """python -m benchmarks --replot runs nothing and draws the figure (PNG and PDF) from the
    benchmarks.csv in the output directory; without one it is a usage error, and so is a CSV
    written before the position error err_x_m (the tracked one until the next --results run:
    its figure's error axis would mix m and m/s)."""
    import shutil
    from benchmarks import run
    with pytest.raises(SystemExit) as exit_info:
        run.main(["--replot", "--outdir", str(tmp_path)])
    assert exit_info.value.code == 2
    shutil.copy(run.RESULTS_DIR / "benchmarks.csv", tmp_path / "benchmarks.csv")
    if "err_x_m" not in (tmp_path / "benchmarks.csv").read_text().splitlines()[0].split(","):
        with pytest.raises(SystemExit) as exit_info:
            run.main(["--replot", "--outdir", str(tmp_path)])
        assert exit_info.value.code == 2 and "no position error err_x_m" in capsys.readouterr().err
        pytest.skip("benchmarks/results/benchmarks.csv predates err_x_m: run python -m benchmarks --results")
    assert run.main(["--replot", "--outdir", str(tmp_path)]) == 0
    assert (tmp_path / "benchmarks.png").stat().st_size > 0
    assert (tmp_path / "benchmarks.pdf").read_bytes().startswith(b"%PDF")


# ---------------------------------------------------------------- benchmarks' counts refused
@pytest.mark.parametrize("module,argv,named", [
    ("benchmarks.run", ["--repeats", "-1"], "argument --repeats: must be an integer >= 1, got -1"),
    ("benchmarks.run", ["--repeats", "0"], "argument --repeats: must be an integer >= 1, got 0"),
    ("benchmarks.sweep_dask", ["--repeats", "-1"], "argument --repeats: must be an integer >= 1, got -1"),
    ("benchmarks.sweep_dask", ["--rows", "0"], "argument --rows: must be an integer >= 1, got 0"),
    ("benchmarks.sweep_dask", ["--chunk-rows", "100", "-5"], "argument --chunk-rows: must be an integer >= 1"),
    ("benchmarks.sweep_dask", ["--overhead-chunks", "0"], "argument --overhead-chunks: must be an integer >= 1"),
])
def test_benchmarks_refuse_bad_counts(tmp_path: Path, capsys: pytest.CaptureFixture[str], module: str,
                                      argv: list[str], named: str) -> None:
    """A negative or zero count is a usage error naming the argument (exit 2), before anything
    is built or run and without a traceback; --repeats -1 used to be clamped to 1 silently."""
    import importlib
    mod = importlib.import_module(module)
    with pytest.raises(SystemExit) as exit_info:
        mod.main(["--outdir", str(tmp_path), *argv])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert named in err and "Traceback" not in err
    assert not list(tmp_path.iterdir())


# ---------------------------------------------------------------- numbers shown as numbers
@pytest.mark.parametrize("call,named", [
    (lambda ss, np: ss.simulate("belt", "proposed", method="rk4", h=np.float64("nan"), t_end=1.0),
     "h: must be finite"),
    (lambda ss, np: ss.simulate("belt", "proposed", method="rk4", h=1e-3, t_end=np.float64("inf")),
     "t_end: must be finite"),
    (lambda ss, np: ss.simulate("belt", "proposed", method="dopri5", t_end=1.0, max_steps=np.float64(2.5)),
     "max_steps: must be an integer"),
    (lambda ss, np: ss.simulate_batch("belt", "proposed", method="rk4", h=1e-3, t_end=1.0,
                                      mu_s=np.array([0.3, np.nan])),
     "mu_s: must be finite"),
])
def test_error_messages_show_numbers_as_numbers(call, named) -> None:
    """A numpy scalar in a bad argument is shown as the number it is (nan, inf, 2.5), never
    as np.float64(nan): the facade's messages format the value, not numpy's repr of it."""
    import numpy as np

    import stickslip as ss
    with pytest.raises(ValueError) as err:
        call(ss, np)
    text = str(err.value)
    assert named in text, text
    assert "np.float64" not in text and "np.int64" not in text and "array(" not in text, text


# ---------------------------------------------------------------- progress only on a terminal
def test_progress_bars_only_on_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    """Off a terminal (stderr a file or a pipe) the drivers draw no bar and print no progress
    lines; on one they do unless quiet."""
    import io
    import sys

    from cases import _progress

    class Stream(io.StringIO):
        def __init__(self, tty: bool) -> None:
            super().__init__()
            self.tty = tty

        def isatty(self) -> bool:
            return self.tty

    for tty, quiet, expected in [(False, False, False), (True, False, True), (True, True, False)]:
        err = Stream(tty)
        monkeypatch.setattr(sys, "stderr", err)
        assert _progress.shown(quiet) is expected
        for _ in _progress.progress(range(3), "runs", quiet):
            pass
        assert bool(err.getvalue()) is expected, (tty, quiet, err.getvalue())
