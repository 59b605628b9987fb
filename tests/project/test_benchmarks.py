"""Smoke test of the benchmark driver: `python -m benchmarks --quick` into tmp_path writes a
complete CSV with finite, positive ratios, a PNG and a summary. No timing assertions."""
from __future__ import annotations

import csv
import math
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow     # builds and times the C, Fortran and GSL programs
@pytest.mark.xdist_group("build/bench")     # both build in benchmarks' build/bench: one worker
def test_quick_benchmarks(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if shutil.which("gfortran") is None or shutil.which("cc") is None:
        pytest.skip("compilers not found")
    monkeypatch.syspath_prepend(str(ROOT))
    monkeypatch.setenv("PATH", f"{Path(sys.executable).parent}:{__import__('os').environ['PATH']}")
    from benchmarks.run import FIELDS, QUICK, main

    assert main(["--quick", "--outdir", str(tmp_path)]) == 0
    with (tmp_path / "benchmarks.csv").open() as fh:
        reader = csv.DictReader(fh)
        assert tuple(reader.fieldnames) == FIELDS
        rows = list(reader)
    assert (tmp_path / "benchmarks.png").stat().st_size > 0
    text = (tmp_path / "summary.md").read_text()
    assert "python -m benchmarks --quick" in text

    fixed = [r for r in rows if r["section"] == "fixed"]
    impls = {r["impl"] for r in fixed}
    assert {"c_loop", "stickslip_fortran", "stickslip_python"} <= impls
    assert len(fixed) >= 3 * len(QUICK.fixed)
    for r in fixed:
        for key in ("ratio_step", "ratio_eval", "ratio_time", "ns_per_step", "ns_per_eval"):
            x = float(r[key])
            assert math.isfinite(x) and x > 0, (r["impl"], key, r[key])
        assert int(r["nfev"]) >= (4 if r["method"].startswith("rk4") else 1) * int(r["nstep"]) > 0
    assert {r["method"] for r in fixed} >= {"rk4", "implicit_euler", "galpha"}
    # Every implementation of RK4 in the fixed section reaches the same state (same h, same method).
    xs = [float(r["x_end_m"]) for r in fixed if r["impl"] != "gsl" and r["method"] == "rk4"]
    assert max(xs) - min(xs) < 1e-10

    adaptive = [r for r in rows if r["section"] == "adaptive"]
    methods = {(r["impl"], r["method"]) for r in adaptive}
    assert {("stickslip_fortran", "dopri5"), ("stickslip_python", "dopri5"), ("stickslip_python", "radau5")} <= methods
    assert {("scipy", m) for m in QUICK.scipy_methods} <= methods
    assert len(adaptive) == len(methods) * len(QUICK.tols) * len(QUICK.adaptive)
    for r in adaptive:
        for key in ("ratio_step", "ratio_eval", "ratio_time", "err", "err_x_m", "err_v_m_s"):
            x = float(r[key])
            assert math.isfinite(x) and x > 0, (r["impl"], r["method"], key, r[key])
    # The error by component: err the larger of err_x_m [m] and err_v_m_s [m/s]; the position's
    # error agrees with the end position's distance from GSL rk8pd's check of the reference,
    # within the two references' difference and the CSV's six digits.
    checks = {(r["scene"], r["law"]): r for r in rows if r["section"] == "reference"}
    for r in adaptive:
        ex, ev = float(r["err_x_m"]), float(r["err_v_m_s"])
        assert float(r["err"]) == pytest.approx(max(ex, ev), rel=1e-5)
        chk = checks.get((r["scene"], r["law"]))
        if chk is not None:
            x, x_chk = float(r["x_end_m"]), float(chk["x_end_m"])
            assert abs(abs(x - x_chk) - ex) <= float(chk["err"]) + 5e-6 * (abs(x) + abs(x_chk)), r

    # The facade's overhead: each short run through the bare f2py wrapper, then through simulate.
    over = [r for r in rows if r["section"] == "overhead"]
    assert [r["impl"] for r in over] == ["f2py_wrapper", "stickslip_python"] * (len(over) // 2) != []
    for f, p in zip(over[::2], over[1::2]):
        assert (f["method"], f["nstep"], f["nfev"]) == (p["method"], p["nstep"], p["nfev"])
        assert float(f["median_s"]) > 0 and float(p["median_s"]) > 0
        assert int(p["repeats"]) >= 2000 and math.isfinite(float(p["overhead_s"]))

    eq = [r for r in rows if r["section"] == "equal_accuracy"]
    assert any(r["impl"] == "stickslip_fortran" for r in eq)
    for r in eq:
        x = float(r["ratio_time"])
        assert math.isfinite(x) and x > 0

    # DOP853 against DOPRI5 and GSL rk8pd: every tolerance run by each, then at equal error
    # the interpolated costs as ratios to DOP853 (its own row 1).
    d8 = [r for r in rows if r["section"] == "dop853"]
    assert {r["method"] for r in d8} >= {"dop853", "dopri5"}
    assert len(d8) == len({r["method"] for r in d8}) * len(QUICK.dop853_tols)
    assert all(float(r["err"]) > 0 and int(r["nfev"]) > 0 for r in d8)
    d8eq = [r for r in rows if r["section"] == "dop853_equal_error"]
    assert [float(r["ratio_time"]) for r in d8eq if r["method"] == "dop853"] == [1.0] * len(QUICK.dop853_targets)
    assert all(math.isfinite(float(r["ratio_time"])) and float(r["ratio_time"]) > 0 for r in d8eq)
    assert "DOP853 at equal error" in text

    # The chain: every method of CHAIN_RUNS at every quick N it takes; RADAU5 banded and dense
    # take the same steps (a different path to the same Newton matrices), and the fitted
    # exponent recovers a known power law.
    from benchmarks.run import CHAIN_RUNS, fitted_exponent
    chain = [r for r in rows if r["section"] == "chain"]
    expected = {(m, n) for m, _, _, _, n_max in CHAIN_RUNS for n in QUICK.chain_sizes if n <= n_max}
    assert {(r["method"], int(r["n_blocks"])) for r in chain} == expected
    assert all(float(r["ns_per_step"]) > 0 and int(r["nstep"]) > 0 for r in chain)
    banded = [r for r in rows if r["section"] == "chain_banded"]
    assert [r["reference"] for r in banded] == ["banded", "dense"] * len(QUICK.chain_dense_sizes)
    for b, d in zip(banded[::2], banded[1::2]):
        assert (b["n_blocks"], b["nstep"], b["nfev"]) == (d["n_blocks"], d["nstep"], d["nfev"])
    assert "time per step against the number of blocks" in text
    assert fitted_exponent([10, 100, 1000], [3e-6, 3e-5, 3e-4]) == pytest.approx(1.0)
    assert math.isnan(fitted_exponent([10], [1.0]))


@pytest.mark.slow     # builds the contact benchmark's Fortran program (minutes on two busy cores)
@pytest.mark.xdist_group("build/bench")     # both build in benchmarks' build/bench: one worker
def test_quick_contact_benchmark(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """`python -m benchmarks --contact --quick`: a table row per n up to 8; the solver (its
    rule's rounds of box problems) and Lemke's method alone solve every random coupled problem;
    moreau runs the stack of 1 to 8 blocks to the end. No timing assertions. Slow (CI): the
    default run checks the same solver on random coupled problems of 2 to 9 contacts in
    tests/fortran/test_stickslip_contact.py::test_contact_solver_random_problems."""
    if shutil.which("gfortran") is None:
        pytest.skip("compilers not found")
    monkeypatch.syspath_prepend(str(ROOT))
    monkeypatch.setenv("PATH", f"{Path(sys.executable).parent}:{__import__('os').environ['PATH']}")
    from benchmarks.run import main

    assert main(["--contact", "--quick", "--outdir", str(tmp_path)]) == 0
    random_part, chain_part = (tmp_path / "contact.md").read_text().split("**The chain**")
    random_part, stack_part = random_part.split("**A stack of n blocks**")

    def table(text: str) -> list[list[str]]:
        return [line.split("|")[1:-1] for line in text.splitlines() if line.startswith("| ") and line[2].isdigit()]

    rows = table(random_part)
    assert [int(r[0]) for r in rows] == [2, 3, 4, 6, 8]
    for r in rows:
        assert r[2].strip() == "100 %" and r[7].strip() == "100 %"
        assert math.isfinite(float(r[1])) and float(r[1]) > 0
    rows = table(stack_part)
    assert [int(r[0]) for r in rows] == [1, 2, 3, 4, 6, 8]
    assert all(r[5].strip() == "0" and float(r[4]) <= 1e-12 for r in rows)     # status 0, residual
    # the chain (10 and 100 blocks in --quick): the tridiagonal path and the general solver
    # solve every step problem, to the same velocities; the sweeps alone are timed beside them
    rows = table(chain_part)
    assert [int(r[0]) for r in rows] == [10, 100]
    for r in rows:
        assert r[2].strip() == "100 %" and r[7].strip() == "100 %"
        assert float(r[4]) > 0 and abs(float(r[5]) - float(r[1]) / float(r[4])) <= 0.01 * float(r[5])
        assert float(r[12]) < 1e-10


def test_lmfit_benchmark_writes_the_same_fit(monkeypatch: pytest.MonkeyPatch) -> None:
    """benchmarks/lmfit_compare.py on one law (Dahl, the ten 36 lb damper records): the fit
    written with lmfit is the same fit, so both end at the same error and parameters within a
    standard error. No timing assertions."""
    pytest.importorskip("lmfit")
    monkeypatch.syspath_prepend(str(ROOT))
    from benchmarks.lmfit_compare import COLUMNS, run_lmfit

    rows, table = run_lmfit(lambda s: None, repeats=1, laws=("dahl",))
    (row,) = rows
    assert set(row) == set(COLUMNS)
    assert row["stickslip nrmse [-]"] == pytest.approx(row["lmfit nrmse [-]"], rel=1e-3)
    assert row["max |dp|/s.e. [-]"] < 1.0
    assert "| dahl | 5 |" in table


def test_prescribed_benchmark_has_a_row_per_case(monkeypatch: pytest.MonkeyPatch) -> None:
    """benchmarks/prescribed_speed.py with one call per case: a row per law and parameter set
    with positive times and the substep counts, and the two scipy rows; then LuGre's error
    against scipy's Radau at each rtol, within that rtol of its largest mu."""
    monkeypatch.syspath_prepend(str(ROOT))
    from benchmarks.prescribed_speed import CASES, run_prescribed

    cost, accuracy = run_prescribed(lambda s: None, repeats=1).split("| rtol |")
    body = [ln for ln in cost.splitlines() if ln.startswith("| ")][1:]    # after the header
    assert len(body) == len(CASES) + 2
    for (law, _, label), line in zip(CASES, body):
        cells = [c.strip() for c in line.split("|")[1:-1]]
        assert cells[:2] == [law, label]
        assert float(cells[2].split(" / ")[0]) > 0.0 and int(cells[3].replace(",", "")) >= 0
    rows = [[float(c) for c in ln.split("|")[1:-1]] for ln in accuracy.splitlines() if ln.startswith("| ")]
    assert [r[0] for r in rows] == [1e-8, 1e-6]
    assert all(0.0 < err <= rtol * mu_max for rtol, err, mu_max in rows), rows


def test_overhead_alone_replaces_its_block_and_rows(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """`python -m benchmarks --overhead`: the overhead block of summary.md and the overhead rows
    of benchmarks.csv are replaced in place, with the goal of issue 32 stated beside the
    measured time; every other line and row is left as the full run wrote it."""
    monkeypatch.syspath_prepend(str(ROOT))
    from benchmarks.run import FIELDS, OVERHEAD, OVERHEAD_HEAD, main

    before = ["Measured earlier.", "", "**Fixed-step RK4** (a section of the full run):", "", "| a |",
              "|---|", "| 1 |", "", f"{OVERHEAD_HEAD} (an old block):", "", "| old |", "|---|", "| 9 |", "",
              "After the block."]
    (tmp_path / "summary.md").write_text("\n".join(before) + "\n")
    kept = dict.fromkeys(FIELDS, "nan") | {"section": "fixed", "impl": "c_loop", "nstep": "2000000"}
    stale = dict.fromkeys(FIELDS, "nan") | {"section": "overhead", "impl": "f2py_wrapper"}
    with (tmp_path / "benchmarks.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        w.writerows([kept, stale])

    assert main(["--overhead", "--quick", "--outdir", str(tmp_path)]) == 0
    lines = (tmp_path / "summary.md").read_text().splitlines()
    assert lines[:8] == before[:8] and lines[-2:] == before[-2:]
    block = lines[8:-2]
    assert block[0].startswith(OVERHEAD_HEAD) and "Goal: " in block[0] and "at most 5 us" in block[0]
    assert "--overhead" in block[0] and "| old |" not in lines
    table = [line for line in block if line.startswith("| ") and not line.startswith("| scene")]
    assert len(table) == len(OVERHEAD)
    with (tmp_path / "benchmarks.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert rows[0] == kept                                   # as written, not reformatted
    over = rows[1:]
    assert [r["impl"] for r in over] == ["f2py_wrapper", "stickslip_python"] * len(OVERHEAD)
    assert all(float(r["median_s"]) > 0 for r in over)


def test_state_errors_keep_each_unit_apart() -> None:
    """A run's end-state error by component: err_x [m] and err_v [m/s] each against its own
    reference, err the larger (the norm atol = rtol controls), 1e-16 at the least (a log axis)."""
    sys.path.insert(0, str(ROOT))
    import numpy as np
    from benchmarks.run import state_errors
    assert state_errors(1.0, 2.0, np.array([1.5, 1.0])) == {"err": 1.0, "err_x": 0.5, "err_v": 1.0}
    assert state_errors(0.3, -0.2, np.array([0.3, -0.2 + 2e-9])) == pytest.approx(
        {"err": 2e-9, "err_x": 1e-16, "err_v": 2e-9})


def test_replot_draws_position_error_and_refuses_an_old_csv(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """--replot draws the figure from benchmarks.csv alone, its error axis the position's in
    metres (err_x_m), not the mixed err; a CSV without err_x_m in its adaptive rows (written
    before the column) is refused with a one-line error, not plotted with the mixed norm."""
    monkeypatch.syspath_prepend(str(ROOT))
    from benchmarks import run

    def row(section: str, impl: str, method: str, tol: float, t: float, ex: float, ev: float) -> dict:
        r = dict.fromkeys(run.FIELDS, "nan") | {"section": section, "impl": impl, "method": method,
                                               "scene": "belt", "law": "proposed", "tol": tol,
                                               "median_s": t, "h_s": 1e-5, "ns_per_eval": 20.0,
                                               "ratio_eval": 1.0, "err_x_m": ex, "err_v_m_s": ev,
                                               "err": max(ex, ev)}
        return r

    rows = [row("fixed", "c_loop", "rk4", float("nan"), 0.1, float("nan"), float("nan"))]
    rows += [row("adaptive", impl, "dopri5", tol, t, ex, 100 * ex)
             for impl in ("stickslip_fortran", "stickslip_python")
             for tol, t, ex in ((1e-4, 1e-3, 3e-5), (1e-8, 4e-3, 2e-9))]
    run.write_csv(rows, tmp_path / "benchmarks.csv")
    from harness import style as _style
    axes: list = []
    save = _style.save
    monkeypatch.setattr(_style, "save", lambda fig, path, write: (axes.extend(fig.axes), save(fig, path, write))[1])
    assert run.main(["--replot", "--outdir", str(tmp_path)]) == 0
    assert (tmp_path / "benchmarks.png").stat().st_size > 0
    panels = [ax for ax in axes if ax.get_yscale() == "log"]
    assert panels and all(ax.get_ylabel().endswith("[m]") for ax in panels)
    plotted = np.concatenate([line.get_ydata() for ax in panels for line in ax.get_lines()])
    assert set(plotted) == {3e-5, 2e-9}                      # err_x_m, not err (= err_v here)

    old = [{k: v for k, v in r.items() if k not in ("err_x_m", "err_v_m_s")} for r in rows]
    with (tmp_path / "benchmarks.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=[f for f in run.FIELDS if f not in ("err_x_m", "err_v_m_s")])
        w.writeheader()
        w.writerows(old)
    with pytest.raises(SystemExit):
        run.main(["--replot", "--outdir", str(tmp_path)])


def test_presets_benchmark_needs_a_base_build(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                             capsys: pytest.CaptureFixture) -> None:
    """`--presets` compares against a separate build of the package (--base SITE): without one
    it stops with a message naming --base; a worker of this tree reports every case once, each
    with its steps and a positive time per step."""
    import json
    monkeypatch.syspath_prepend(str(ROOT))
    from benchmarks import presets
    from benchmarks.run import main

    with pytest.raises(SystemExit):
        main(["--presets", "--outdir", str(tmp_path)])
    assert "--base" in capsys.readouterr().err
    monkeypatch.setattr(presets, "CASES", (("belt", "coulomb", "rk4", {"h": 1e-3}, {}, 0.1),
                                           ("chain", "proposed", "rk4", {"h": 1e-3}, {"n_blocks": 3}, 0.1)))
    presets._worker()
    runs = json.loads(capsys.readouterr().out)["runs"]
    assert [r["nstep"] for r in runs] == [100, 100]
    assert all(r["per_step"] > 0 and len(r["x"]) == n for r, n in zip(runs, (1, 3)))
