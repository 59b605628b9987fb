"""Where results go (stickslip.outputs): one rule for the output paths of every command line
(python -m stickslip run --out, python -m cases.* and python -m benchmarks --outdir): a missing
directory is created with its parents, an unwritable one is refused before any work."""
from __future__ import annotations

from pathlib import Path

import pytest

from cases import _common

ROOT = Path(__file__).resolve().parents[1]


# ------------------------------------------------ one rule for output paths, every command line
def _outdir_commands() -> list[str]:
    """Every command that takes --outdir: the drivers of cases/ (python -m cases.<name>),
    python -m cases, and the benchmarks' commands."""
    found = [f"cases.{p.stem}" for p in sorted((ROOT / "cases").glob("*.py"))
             if not p.stem.startswith("_") and "def main(" in (text := p.read_text())
             and ("--outdir" in text or "study_main(" in text or "s.main(" in text)]
    return [*found, "cases.__main__", "benchmarks.run", "benchmarks.sweep_dask"]


OUTDIR_COMMANDS = _outdir_commands()


def test_the_outdir_commands_are_found() -> None:
    assert {"cases.chain", "cases.identify", "cases.slope", "cases.gallery_frame", "cases.engines"} \
        <= set(OUTDIR_COMMANDS)
    assert "cases.advise" not in OUTDIR_COMMANDS                 # prints, writes nothing


@pytest.mark.parametrize("where", ["proc", "file"])
@pytest.mark.parametrize("module", OUTDIR_COMMANDS)
def test_every_command_refuses_an_unwritable_outdir_before_any_work(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
        module: str, where: str) -> None:
    """The rule of stickslip.outputs on every --outdir: a directory that cannot be made (below
    /proc, or below a plain file, which stops root too) ends the command while its arguments are
    parsed, exit 2, naming the path and the reason; no simulation starts (each is replaced by a
    failure here)."""
    import importlib
    import stickslip as ss
    import stickslip.core

    def no_runs(*args: object, **kwargs: object) -> None:
        raise AssertionError("a simulation started")

    for owner in (ss, stickslip.core):
        for name in ("simulate", "simulate_batch", "sweep"):
            monkeypatch.setattr(owner, name, no_runs, raising=False)
    monkeypatch.setattr(_common, "run_all", no_runs)
    if where == "proc":
        bad, reason = Path("/proc/nowhere/deep"), "No such file or directory"
    else:
        (tmp_path / "a-file").write_text("")
        bad, reason = tmp_path / "a-file" / "out", "Not a directory"
    driver = importlib.import_module(module)
    with pytest.raises(SystemExit) as exit_info:
        driver.main(["--outdir", str(bad)])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert f"argument --outdir: cannot write into {bad}: {reason}" in err, err
    assert "Traceback" not in err


def test_a_missing_outdir_is_created_with_its_parents(tmp_path: Path) -> None:
    """The other half of the rule: --outdir a/b/c that does not exist is made, parents
    included, as the arguments are parsed."""
    import argparse
    from harness.cli import add_outdir
    parser = argparse.ArgumentParser()
    add_outdir(parser)
    deep = tmp_path / "a" / "b" / "c"
    assert parser.parse_args(["--outdir", str(deep)]).outdir == deep and deep.is_dir()


def test_stickslip_run_follows_the_same_rule(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """python -m stickslip run --out: a missing directory is created; an unwritable one is
    refused before the run, naming it and why."""
    import stickslip as ss
    from stickslip.__main__ import main
    m = ss.Model()
    m.add_spring(m.add_body(1.0, v0=1.0), None, k=100.0)
    m.to_toml(tmp_path / "m.toml")
    run = ["run", str(tmp_path / "m.toml"), "--method", "rk4", "--h", "1e-2", "--t-end", "0.1", "--n-out", "3"]
    out = tmp_path / "new" / "deep" / "m.csv"
    assert main([*run, "--out", str(out)]) == 0 and out.is_file()
    capsys.readouterr()
    assert main([*run, "--out", "/proc/nowhere/m.csv"]) == 2
    assert "--out: cannot write into /proc/nowhere: No such file or directory" in capsys.readouterr().err
    (tmp_path / "a-file").write_text("")
    assert main([*run, "--out", str(tmp_path / "a-file" / "m.csv")]) == 2
    assert f"cannot write into {tmp_path / 'a-file'}: " in capsys.readouterr().err
