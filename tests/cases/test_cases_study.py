"""Tests of the figure drivers in cases/: each driver runs at reduced size into tmp_path and its
CSVs are checked against expectations computed here independently (our own numpy version of
the friction laws, closed-form creep speeds and harmonic solutions), never against files
generated earlier."""
from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import brentq

from cases import __main__ as cases_main
from cases import _common, _study, belt, laws, slope

MU_S, MU_K, V_S, BETA, A = 0.35, 0.30, 0.01, 1.0 / 3.0, 1.5
G, THETA_DEG, M, K, V_B = 9.81, 10.0, 10.0, 300.0, 1.5

SLOPE_T, SLOPE_POINTS = 2.0, 201
BELT_T, BELT_POINTS = 20.0, 2001
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


# ---------------------------------------------------------------- independent friction laws
def havsin(x: np.ndarray, x0: float, h0: float, x1: float, h1: float) -> np.ndarray:
    """The haversine step of the paper's eq. (3)."""
    s = np.clip((x - x0) / (x1 - x0), 0.0, 1.0)
    return h0 + (h1 - h0) * (1.0 - np.cos(np.pi * s)) / 2.0


def mu_ref(law: str, v: np.ndarray, v_d: float | None = None) -> np.ndarray:
    """Our own implementation of eqs. (1), (2)-(3) and (5), odd in v."""
    v = np.asarray(v, dtype=float)
    u = np.abs(v)
    if law == "coulomb":
        m = np.where(u < V_S, MU_S, MU_K)
    elif law == "recurdyn":
        vd = 1.5 * V_S if v_d is None else v_d
        m = np.where(u < V_S, havsin(u, 0.0, 0.0, V_S, MU_S), havsin(u, V_S, MU_S, vd, MU_K))
    else:
        b = -math.log(MU_S - MU_K) / math.log(A) - V_S
        m = np.where(u <= V_S, MU_S * (u / V_S) ** BETA, A ** (-(u + b)) + MU_K)
    return np.sign(v) * m


def creep_speed_ref(law: str) -> float:
    """v* solving mu(v*) = tan(theta), by brentq on mu_ref."""
    target = math.tan(math.radians(THETA_DEG))
    return brentq(lambda v: float(mu_ref(law, np.array(v))) - target, 1e-12, V_S, xtol=1e-15)


# ---------------------------------------------------------------- fixtures: run each driver once
@pytest.fixture(scope="module")
def slope_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("slope")
    files = slope.main(["--outdir", str(out), "--t-end", str(SLOPE_T), "--points", str(SLOPE_POINTS),
                        "--quiet"])
    return files[0].parent           # a subdirectory named after the non-default options


@pytest.fixture(scope="module")
def belt_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("belt")
    files = belt.main(["--outdir", str(out), "--t-end", str(BELT_T), "--points", str(BELT_POINTS),
                       "--quiet"])
    return files[0].parent           # a subdirectory named after the non-default options


@pytest.fixture(scope="module")
def laws_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("laws")
    files = laws.main(["--outdir", str(out), "--points", "301"])
    return files[0].parent           # a subdirectory named after the non-default options


def numeric(path: Path) -> dict[str, np.ndarray]:
    return _common.read_numeric_csv(path)


def table(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def row(rows: list[dict[str, str]], law: str, mode: str) -> dict[str, str]:
    (found,) = [r for r in rows if r["law [-]"] == law and r["mode [-]"] == mode]
    return found


# ---------------------------------------------------------------- file contract
@pytest.mark.parametrize("fixture", ["slope_dir", "belt_dir", "laws_dir"])
def test_files_complete_with_units(fixture: str, request: pytest.FixtureRequest) -> None:
    """Every CSV has a unit on each header, equal-length complete rows, and a PNG beside it;
    no temporary file is left behind."""
    out: Path = request.getfixturevalue(fixture)
    csvs = sorted(out.glob("*.csv"))
    expected = {"slope_dir": 8, "belt_dir": 8, "laws_dir": 3}[fixture]
    assert len(csvs) == expected
    for path in csvs:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        header, body = rows[0], rows[1:]
        assert all(re.fullmatch(r".+ \[[^\]]*\]", name) for name in header), header
        assert body and all(len(r) == len(header) for r in body)
        png = path.with_suffix(".png")
        assert png.read_bytes()[:8] == PNG_MAGIC and png.stat().st_size > 2000
    assert not list(out.glob(".*.tmp"))


def test_time_series_rows(slope_dir: Path, belt_dir: Path) -> None:
    """Figure CSVs hold exactly --points rows on [0, --t-end]."""
    for path, n, t_end in ((slope_dir / "fig05_slope_automatic.csv", SLOPE_POINTS, SLOPE_T),
                           (belt_dir / "fig13_belt_automatic.csv", BELT_POINTS, BELT_T)):
        t = numeric(path)["t [s]"]
        assert len(t) == n and t[0] == 0.0 and t[-1] == pytest.approx(t_end)


def test_plot_from_csv_alone(slope_dir: Path, tmp_path: Path) -> None:
    """plot() re-renders a PNG from a copied CSV, with nothing else in its directory."""
    src = slope_dir / "fig08_slope_steps_coulomb.csv"
    copy = tmp_path / src.name
    copy.write_bytes(src.read_bytes())
    png = slope.plot(copy, tmp_path)
    assert png.read_bytes()[:8] == PNG_MAGIC


def test_atomic_write_keeps_old_file(tmp_path: Path) -> None:
    """A failing writer leaves the previous file intact and no temporary file."""
    target = tmp_path / "a.csv"
    _common.write_csv(target, ["x [m]"], [[1.0]])
    before = target.read_text()

    def bad_rows():
        yield [2.0]
        raise RuntimeError("interrupted")

    with pytest.raises(RuntimeError):
        _common.write_csv(target, ["x [m]"], bad_rows())
    assert target.read_text() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]
    with pytest.raises(ValueError, match="unit"):
        _common.write_csv(tmp_path / "b.csv", ["x"], [[1.0]])


# ---------------------------------------------------------------- laws (Figs. 1-3)
@pytest.mark.parametrize("law,number", [("coulomb", 1), ("recurdyn", 2), ("proposed", 3)])
def test_law_curves(laws_dir: Path, law: str, number: int) -> None:
    cols = numeric(laws_dir / f"fig{number:02d}_law_{law}.csv")
    v, mu = cols["v [m/s]"], cols[f"mu {law} [-]"]
    keep = ~np.isclose(np.abs(v), V_S, rtol=0.0, atol=1e-12)    # Coulomb's jump at v_s
    assert_allclose(mu[keep], mu_ref(law, v[keep]), atol=1e-12)
    assert_allclose(mu, -mu[::-1], atol=1e-12)                    # odd (grid is symmetric)


# ---------------------------------------------------------------- slope (Figs. 5-11, Table 2)
@pytest.mark.parametrize("law", ["recurdyn", "proposed"])
def test_slope_creep_speed(slope_dir: Path, law: str) -> None:
    """The smooth laws creep at v* with mu(v*) = tan(theta), at every step size."""
    v_star = creep_speed_ref(law)
    number = {"recurdyn": 6, "proposed": 7}[law]
    cols = numeric(slope_dir / f"fig{number:02d}_slope_steps_{law}.csv")
    t = cols.pop("t [s]")
    half = len(t) // 2
    assert len(cols) == 3
    for name, x in cols.items():
        speed = (x[-1] - x[half]) / (t[-1] - t[half])
        assert speed == pytest.approx(v_star, rel=1e-5), name
    rows = table(slope_dir / "table2_slope_cpu.csv")
    assert float(row(rows, law, "automatic")["v_star [m/s]"]) == pytest.approx(v_star, rel=1e-9)


def test_slope_coulomb_depends_on_step(slope_dir: Path) -> None:
    """Coulomb's chattering creep differs with h (RK4: smaller h, less creep; truth: 0)."""
    cols = numeric(slope_dir / "fig08_slope_steps_coulomb.csv")
    x3, x4 = cols["x h=0.001 [m]"][-1], cols["x h=0.0001 [m]"][-1]
    assert x3 > 3.0 * x4 > 0.0
    assert cols["x automatic [m]"][-1] < x4


@pytest.mark.parametrize("law,number", [("recurdyn", 9), ("proposed", 10)])
def test_slope_smooth_laws_ignore_tolerance(slope_dir: Path, law: str, number: int) -> None:
    cols = numeric(slope_dir / f"fig{number:02d}_slope_tolerances_{law}.csv")
    finals = [x[-1] for name, x in cols.items() if name != "t [s]"]
    assert len(finals) == 3
    assert max(finals) - min(finals) < 1e-3 * max(finals)


def test_slope_table(slope_dir: Path) -> None:
    """RK4 takes t_end/h steps; the paper's CPU seconds sit in the three paper modes only;
    Coulomb in automatic mode is forced down to h_min."""
    rows = table(slope_dir / "table2_slope_cpu.csv")
    assert len(rows) == 15
    for r in rows:
        if r["method [-]"] == "rk4":
            assert int(r["nstep [-]"]) == round(SLOPE_T / float(r["h [s]"]))
        has_paper = r["mode [-]"] in ("automatic", "h=0.001", "h=0.0001")
        assert (r["paper_cpu_seconds [s]"] != "") == has_paper
    coulomb = row(rows, "coulomb", "automatic")
    assert int(coulomb["nforced [-]"]) > 0.3 * SLOPE_T / 1e-6
    assert int(row(rows, "recurdyn", "automatic")["nforced [-]"]) == 0
    md = (slope_dir / "table2_slope_cpu.md").read_text()
    assert md.count("\n") == 17 and "| coulomb | automatic |" in md


def test_runs_are_not_duplicated() -> None:
    """Fig. 5, the automatic panel of Figs. 6-8 and the rtol = 1e-6 curve of Figs. 9-11 are one
    run: 3 laws x (automatic + 2 fixed steps + 2 other tolerances) distinct runs."""
    plan = _study.build_runs(slope.SPEC, t_end=1.0, n_out=11, params={},
                             rtols=_study.TOLERANCES)
    runs = _study.all_runs(plan)
    assert len(runs) == 3 * (1 + 3 + 3) and len(set(runs)) == 15


# ---------------------------------------------------------------- belt (Figs. 13-19, Table 3)
def harmonic(t: np.ndarray) -> np.ndarray:
    """Constant mu_k from rest: x = x_k (1 - cos(w t)), x_k = mu_k m g / k, w = sqrt(k/m)."""
    return MU_K * M * G / K * (1.0 - np.cos(math.sqrt(K / M) * t))


@pytest.mark.parametrize("law,number", [("recurdyn", 14), ("coulomb", 16)])
def test_belt_constant_amplitude(belt_dir: Path, law: str, number: int) -> None:
    cols = numeric(belt_dir / f"fig{number:02d}_belt_steps_{law}.csv")
    t = cols.pop("t [s]")
    assert len(cols) == 3
    for name, x in cols.items():
        assert_allclose(x, harmonic(t), atol=1e-6, err_msg=name)
    auto = numeric(belt_dir / "fig13_belt_automatic.csv")[f"x {law} [m]"]
    assert_allclose(auto, harmonic(t), atol=1e-6)


def test_belt_proposed_grows_into_stick_slip(belt_dir: Path) -> None:
    """The proposed law's oscillation grows (self-excited) until the mass sticks to the belt."""
    t = numeric(belt_dir / "fig15_belt_steps_proposed.csv")["t [s]"]
    x = numeric(belt_dir / "fig15_belt_steps_proposed.csv")["x automatic [m]"]
    period = 2.0 * math.pi * math.sqrt(M / K)
    first = x[t <= period]
    later = x[(t >= 12.0) & (t <= 12.0 + period)]
    assert np.ptp(later) > 1.5 * np.ptp(first)
    rows = table(belt_dir / "table3_belt_cpu.csv")
    stick = float(row(rows, "proposed", "automatic")["t_first_stick [s]"])
    assert 10.0 < stick < BELT_T
    assert float(row(rows, "proposed", "automatic")["min_v_rel_last_period [m/s]"]) < V_S
    x_k, w = MU_K * M * G / K, math.sqrt(K / M)
    for law in ("coulomb", "recurdyn"):
        r = row(rows, law, "automatic")
        assert r["t_first_stick [s]"] == ""
        assert float(r["min_v_rel_last_period [m/s]"]) == pytest.approx(V_B - x_k * w, abs=1e-3)


def test_failed_run_is_reported_across_processes() -> None:
    """A run that exhausts its step budget in a worker surfaces as SimulationFailed naming it."""
    ok = _common.Run("slope", "recurdyn", "rk4", 0.1, 11, h=1e-3)
    bad = _common.Run("slope", "coulomb", "dopri5", 0.1, 11, rtol=1e-6, atol=1e-9, max_steps=10)
    with pytest.raises(_common.SimulationFailed, match="slope coulomb dopri5 rtol=1e-06"):
        _common.run_all([ok, bad], workers=2, quiet=True)


# ---------------------------------------------------------------- python -m cases, CLI errors
def test_main_runs_listed_drivers(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    files = cases_main.main(["--outdir", str(tmp_path), "--only", "laws", "--quiet"])
    assert {f.name for f in files} >= {"fig01_law_coulomb.png", "fig03_law_proposed.csv"}
    assert all(f.exists() for f in files)
    assert str(tmp_path) in capsys.readouterr().out


@pytest.mark.parametrize("argv,expected", [
    ([], ["laws", "slope", "belt"]),
    (["--all", "--threads", "1"], ["laws", "slope", "belt", "workprecision", "stability", "laws_compare",
                                   "implicit", "speedup", "stick", "identify", "chain",
                                   "advise_examples", "engines", "gallery_clutches", "gallery_belt2dof",
                                   "gallery_stacked", "gallery_denhartog", "gallery_frame", "model_pairs",
                                   "gallery_steady"]),
    (["--only", "stability"], ["stability"]),
])
def test_main_selects_drivers(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                              argv: list[str], expected: list[str]) -> None:
    """The paper's drivers by default, the studies only with --all, each with its options
    (--jobs 1: in turn, in this process)."""
    argv = ["--jobs", "1", *argv]
    calls: list[tuple[str, list[str]]] = []

    class Fake:
        def __init__(self, name: str) -> None:
            self.name = name

        def main(self, args: list[str]) -> list[Path]:
            calls.append((self.name, args))
            return []

    monkeypatch.setattr(cases_main.importlib, "import_module",
                        lambda mod: Fake(mod.removeprefix("cases.")))
    cases_main.main(["--outdir", str(tmp_path), "--quiet", *argv])
    assert [name for name, _ in calls] == expected
    for name, args in calls:
        assert args[:2] == ["--outdir", str(tmp_path)]
        if name in ("workprecision", "stability", "laws_compare", "implicit", "speedup", "stick", "identify", "chain",
                    "advise_examples", "engines") or name.startswith("gallery_") or name == "model_pairs":
            assert "--threads" in args and "--workers" not in args
        elif name != "laws":
            assert "--workers" in args


class _FakeDriver:
    """Stands in for a driver module in a job process: prints a report and writes one file
    (or fails, or sleeps, by name)."""

    def __init__(self, name: str) -> None:
        self.name = name

    def main(self, args: list[str]) -> list[Path]:
        import time
        out = Path(args[args.index("--outdir") + 1])
        if self.name == "implicit":
            raise RuntimeError("implicit broke")
        if self.name == "stability" and out.name == "fail":
            time.sleep(60)          # must be terminated, not waited for
        print(f"report of {self.name} {' '.join(args[2:])}")
        path = out / f"{self.name}.txt"
        path.write_text(self.name)
        return [path]


def test_main_runs_drivers_in_parallel_jobs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    """--jobs 2: each driver in its own process, the costliest first, one core each; the files
    come back in DRIVERS order and every report is printed whole."""
    monkeypatch.setattr(cases_main.importlib, "import_module",
                        lambda mod: _FakeDriver(mod.removeprefix("cases.")))
    monkeypatch.setattr(cases_main, "_cores", lambda: 2)
    files = cases_main.main(["--outdir", str(tmp_path), "--jobs", "2", "--only", "laws", "belt",
                             "workprecision", "stability", "speedup"])
    assert [f.name for f in files] == ["laws.txt", "belt.txt", "workprecision.txt", "stability.txt",
                                       "speedup.txt"]
    assert all(f.read_text() + ".txt" == f.name for f in files)
    captured = capsys.readouterr()
    assert "report of belt --workers 1 --quiet\n" in captured.out
    assert "report of stability --threads 1 --quiet\n" in captured.out
    assert "report of speedup --threads 2\n" in captured.out          # alone: every core
    started = re.findall(r"== cases\.(\w+) (?:started|->)", captured.err)
    assert started[:2] == ["stability", "workprecision"]      # the costliest first (DRIVERS)
    assert started[-1] == "speedup"                           # after every other job


def test_main_first_failed_job_ends_the_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A driver that fails ends `python -m cases` at once: the job still running is
    terminated (it would sleep a minute), and the error names the exception and its message."""
    import time
    monkeypatch.setattr(cases_main.importlib, "import_module",
                        lambda mod: _FakeDriver(mod.removeprefix("cases.")))
    out = tmp_path / "fail"
    out.mkdir()
    t0 = time.perf_counter()
    with pytest.raises(cases_main.DriverFailed, match="RuntimeError: implicit broke"):
        cases_main.main(["--outdir", str(out), "--jobs", "2", "--quiet", "--only", "stability",
                         "implicit"])
    assert time.perf_counter() - t0 < 10.0
    assert not list(out.iterdir())


@pytest.mark.parametrize("driver,argv,named", [(slope, ["--t-end", "-1"], "--t-end"),
                                               (laws, ["--a", "0.5"], "a: must be"),
                                               (belt, ["--mu-k", "0.5"], "mu_k: must be"),
                                               (slope, ["--theta-deg", "95"], "theta_deg: must be")])
def test_cli_rejects_bad_input(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                               driver, argv: list[str], named: str) -> None:
    """Bad values end the command with a usage error naming the parameter (exit 2) and write
    nothing."""
    with pytest.raises(SystemExit) as exit_info:
        driver.main(["--outdir", str(tmp_path), *argv])
    assert exit_info.value.code == 2
    assert named in capsys.readouterr().err
    assert not list(tmp_path.glob("*.csv"))


def test_laws_compare_bounds_a_maxwell_slip_element_by_its_own_level():
    """A GMS element holds up to its level over its stiffness, n_elements mu_s/sigma0 at most,
    beyond the bristle's mu_s/sigma0: a converged belt run is bounded, one that blew up is not."""
    import stickslip as ss
    from cases import laws_compare as lc
    ok = ss.simulate("belt", "gms", method="rk4", h=1e-4, t_end=3.0, n_out=301, v0=lc.P["v_b"])
    assert np.abs(ok.z).max() > 0.35 / ss.DEFAULTS["sigma0"]        # beyond the bristle's bound
    assert lc.bounded("belt", "gms", ok, 0, 3.0)
    bad = ss.simulate("belt", "gms", method="rk4", h=1e-3, t_end=3.0, n_out=301, v0=lc.P["v_b"])
    assert not lc.bounded("belt", "gms", bad, 0, 3.0)
