"""The batch entry: identical to single simulate calls, identical for 1 and 2 threads,
bounded output, clear errors."""
from __future__ import annotations

import numpy as np
import pytest

import stickslip

CASES = [("slope", "coulomb", "rk4"), ("slope", "recurdyn", "dopri5"), ("slope", "proposed", "rk4"),
         ("belt", "coulomb", "dopri5"), ("belt", "recurdyn", "rk4"), ("belt", "proposed", "dopri5")]


def _batch(threads: int, keep: bool = True) -> stickslip.BatchResult:
    return stickslip.simulate_batch([c[0] for c in CASES], [c[1] for c in CASES],
                                    method=[c[2] for c in CASES], t_end=5.0,
                                    h=[1e-3 if c[2] == "rk4" else np.nan for c in CASES],
                                    rtol=1e-8, atol=1e-11, n_grid=51, keep_grid=keep,
                                    threads=threads)


def test_batch_equals_single_simulate() -> None:
    b = _batch(2)
    for i, (scene, law, method) in enumerate(CASES):
        kw = {"h": 1e-3} if method == "rk4" else {"rtol": 1e-8, "atol": 1e-11}
        r = stickslip.simulate(scene, law, method=method, t_end=5.0, n_out=51, **kw)
        assert np.array_equal(b.t[i], r.t)
        assert np.array_equal(b.x[i], r.x) and np.array_equal(b.v[i], r.v)
        for k in ("nfev", "nstep", "naccept", "nreject", "nforced"):
            assert getattr(b, k)[i] == r.stats[k], k
        assert b.x_end[i] == r.x[-1] and b.v_end[i] == r.v[-1]
        assert b.v_max[i] == np.max(np.abs(r.v))
        assert b.status[i] == 0 and b.t_reached[i] == 5.0


def test_one_and_two_threads_identical() -> None:
    b1, b2 = _batch(1), _batch(2)
    for k in ("status", "nfev", "nstep", "x_end", "v_end", "v_max", "n_flip", "n_rev", "x", "v"):
        assert np.array_equal(getattr(b1, k), getattr(b2, k)), k
    assert b1.threads == 1 and b2.threads == 2


def test_summary_only_keeps_memory_bounded() -> None:
    b = _batch(2, keep=False)
    assert b.x is None and b.v is None and b.t is None
    assert len(b) == len(CASES) and b.x_end.shape == (len(CASES),)


def test_runtime_failure_is_a_row_status_not_an_exception() -> None:
    b = stickslip.simulate_batch("belt", "proposed", method="rk4", t_end=20.0, h=1e-3,
                                 max_steps=[100, 10**8])
    assert list(b.status) == [-2, 0]
    assert b.t_reached[0] == pytest.approx(0.1) and "step budget" in b.message(0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(method="rk4", t_end=1.0), "h: required"),
    (dict(method="rk4", t_end=1.0, h=1e-3, a=[1.5, 0.5]), "row 1 .*a: must be finite and > 1"),
    (dict(method="dopri5", t_end=1.0, rtol=1e-14), "rtol"),
    (dict(method="rk4", t_end=[1.0, 2.0, 3.0], h=[1e-3, 1e-3]), "different lengths"),
    (dict(method="rk4", t_end=1.0, h=1e-3, threads=0), "threads"),
    (dict(method="euler", t_end=1.0), "method"),
])
def test_bad_input_raises_value_error(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        stickslip.simulate_batch("slope", "proposed", **kwargs)


# --------------------------------------------------------------------------------------------
# The chain in a batch: rows of several n_blocks, laws and methods
# --------------------------------------------------------------------------------------------
CHAIN_ROWS = [(1, "coulomb", "moreau"), (5, "coulomb", "event_driven"), (7, "stribeck", "dopri5"),
              (2, "lugre", "radau5"), (4, "karnopp", "rk4")]


def _chain_batch(threads: int) -> stickslip.BatchResult:
    return stickslip.simulate_batch(
        "chain", [r[1] for r in CHAIN_ROWS], method=[r[2] for r in CHAIN_ROWS], t_end=1.5,
        n_blocks=[r[0] for r in CHAIN_ROWS],
        h=[1e-3 if r[2] in ("moreau", "rk4") else np.nan for r in CHAIN_ROWS],
        n_grid=31, keep_grid=True, threads=threads)


def test_chain_rows_equal_single_simulate() -> None:
    b = _chain_batch(2)
    widest = max(n * (2 + stickslip.REGISTRY["law"][l]["n_states"]) for n, l, _ in CHAIN_ROWS)
    assert b.y_end.shape == (len(CHAIN_ROWS), widest)
    for i, (nb, law, method) in enumerate(CHAIN_ROWS):
        kw = {"h": 1e-3} if method in ("moreau", "rk4") else {}
        r = stickslip.simulate("chain", law, method=method, t_end=1.5, n_blocks=nb, n_out=31, **kw)
        state = np.vstack([np.atleast_2d(r.x), np.atleast_2d(r.v)] + ([r.z] if r.z is not None else []))
        assert b.status[i] == 0 and b.n_state[i] == state.shape[0]
        assert np.array_equal(b.y_grid[i, :state.shape[0]], state), law
        assert np.isnan(b.y_grid[i, state.shape[0]:]).all() and np.isnan(b.y_end[i, state.shape[0]:]).all()
        assert np.array_equal(b.y_end[i, :state.shape[0]], state[:, -1])
        x1, v1 = state[0], state[nb]                      # block 1, the monitored body
        assert np.array_equal(b.x[i], x1) and np.array_equal(b.v[i], v1)
        assert b.x_end[i] == x1[-1] and b.v_end[i] == v1[-1]
        assert b.v_max[i] == np.max(np.abs(v1))
        assert b.nstep[i] == r.stats["nstep"]


def test_chain_rows_one_and_two_threads_identical() -> None:
    b1, b2 = _chain_batch(1), _chain_batch(2)
    for k in ("status", "nfev", "nstep", "v_max", "n_flip", "n_rev"):
        assert np.array_equal(getattr(b1, k), getattr(b2, k)), k
    for k in ("y_end", "y_grid"):
        assert np.array_equal(getattr(b1, k), getattr(b2, k), equal_nan=True), k


def test_one_block_chain_row_is_the_belt_row() -> None:
    """N = 1 with every block stuck on the belt (v0 not given) is the belt started at v0 = v_b."""
    kw = dict(method="dopri5", t_end=3.0, n_grid=41, keep_grid=True, v_b=0.2)
    chain = stickslip.simulate_batch("chain", "stribeck", **kw)
    belt = stickslip.simulate_batch("belt", "stribeck", v0=0.2, **kw)
    assert np.array_equal(chain.y_grid, belt.y_grid) and chain.nfev[0] == belt.nfev[0]
    assert chain.n_flip[0] == belt.n_flip[0] and chain.vrel_min_tail[0] == belt.vrel_min_tail[0]
    # v0 not given on the belt is 0, not v_b: another motion
    assert not np.array_equal(stickslip.simulate_batch("belt", "stribeck", **kw).y_grid, belt.y_grid)


@pytest.mark.parametrize("kwargs, match", [
    (dict(n_blocks=[3, 0]), r"row 1 \(chain, coulomb, moreau\): n_blocks: must be an integer in \[1, 1000000\], got 0"),
    (dict(n_blocks=2.5), r"row 0 \(chain, coulomb, moreau\): n_blocks: must be an integer"),
    (dict(n_blocks=10**6, n_grid=1001), r"n_blocks: the batch needs .* GB.*lower n_blocks"),
    (dict(n_blocks=300, n_grid=201, keep_grid=True, t_end=[1.0] * 200), r"keep_grid: 200 rows x 201"),
])
def test_chain_bad_input_raises_value_error(kwargs: dict, match: str) -> None:
    kw = dict(method="moreau", h=1e-3, t_end=1.0) | kwargs
    with pytest.raises(ValueError, match=match):
        stickslip.simulate_batch("chain", "coulomb", **kw)


# -- rows of a model: the same Fortran batch ------------------------------------------------------
def _brake() -> stickslip.Model:
    """A 50 kg brake at 10 m/s whose normal force ramps to 1000 N over 0.5 s (coulomb, mu 0.4):
    under RK4 at h = 1e-3 .. 1e-2 s its x leaves the integral of v (tests/test_energy_consistency.py)."""
    m = stickslip.Model()
    b = m.add_body(50.0, v0=10.0, name="brake")
    m.add_contact(b, None, "coulomb", stickslip.signal.ramp(0.0, 0.5, 1000.0), mu_s=0.4, mu_k=0.4)
    return m


def test_model_rows_of_a_scene_equal_the_scene_rows() -> None:
    """The slope as a model (Model.from_scene) in the model batch is the scene batch's system
    run by the same loop: every grid value and every field but the wall clock equal, bit for bit
    (its relative velocity is the body's velocity, which a model row monitors). The belt's preset
    (per_unit_mass=True, its error sized on |y| as the scene's) gives the scene rows' states and
    steps bit for bit (its monitor counts the body's velocity, the scene's the belt's slip)."""
    v0 = [0.5, 1.0, 2.0]
    for law, method, ctl in (("stribeck", "dopri5", dict(rtol=1e-8, atol=1e-10)), ("recurdyn", "rk4", dict(h=1e-3))):
        scene = stickslip.simulate_batch("slope", law, method=method, t_end=3.0, n_grid=101, keep_grid=True,
                                         v0=v0, threads=2, **ctl)
        model = stickslip.simulate_batch(stickslip.Model.from_scene("slope", law), {"body 0.v0": v0},
                                         method=method, t_end=3.0, n_grid=101, keep_grid=True, threads=2, **ctl)
        assert np.array_equal(scene.y_grid, model.y_grid) and np.array_equal(scene.y_end, model.y_end)
        for k in scene.fields:
            if k != "seconds":
                assert np.array_equal(scene.fields[k], model.fields[k]), (law, method, k)
    for method, ctl in (("dopri5", dict(rtol=1e-8, atol=1e-10)), ("radau5", dict(rtol=1e-8, atol=1e-10))):
        scene = stickslip.simulate_batch("belt", "stribeck", method=method, t_end=2.0, n_grid=51, keep_grid=True,
                                         v0=[0.0, 0.1], **ctl)
        model = stickslip.simulate_batch(stickslip.Model.from_scene("belt", "stribeck", per_unit_mass=True),
                                         {"body 0.v0": [0.0, 0.1]}, method=method, t_end=2.0, n_grid=51,
                                         keep_grid=True, **ctl)
        assert np.array_equal(scene.y_grid, model.y_grid) and np.array_equal(scene.nstep, model.nstep), method


def _notes_by_rows(notes: list[str]) -> list[tuple[set[int], str]]:
    """A batch's notes ("rows 0, 2 (2 of 3): sentence") as (the rows, the sentence)."""
    out = []
    for n in notes:
        head, sentence = n.split(": ", 1)
        out.append(({int(k) for k in head.split("(")[0].replace("rows", "").replace("row", "").split(",")}, sentence))
    return out


def test_model_rows_are_checked_as_single_runs() -> None:
    """Each model row that reached t_end gets simulate's consistency check: the sentences its
    single run puts in stats["notes"] are the batch's notes for that row (the brake under RK4
    at two steps, and a step that leaves it consistent)."""
    hs = [1e-2, 1e-3, 1e-4]
    with pytest.warns(UserWarning):
        b = stickslip.simulate_batch(_brake(), {}, method="rk4", t_end=5.0, n_grid=1001, h=hs)
    assert b.status.tolist() == [0, 0, 0]
    for i, h in enumerate(hs):
        with pytest.warns(UserWarning):
            r = stickslip.simulate(_brake(), method="rk4", t_end=5.0, n_out=1001, h=h)
        mine = {note for rows, note in _notes_by_rows(b.notes) if i in rows}
        assert mine == set(r.stats["notes"]), (h, mine, r.stats["notes"])
        assert b.x_end[i] == r.x[0, -1] and b.v_end[i] == r.v[0, -1]
    assert any("integral of v" in n for n in b.notes)


def test_model_rows_in_chunks_equal_one_call(monkeypatch: pytest.MonkeyPatch) -> None:
    """Rows run in chunks of MODEL_CHUNK_VALUES grid and event values (event_driven's events kept
    for the check): one row per chunk gives the rows and notes of one call, bit for bit."""
    from stickslip import batch
    m = stickslip.Model()
    a = m.add_body(1.0, v0=0.5)
    m.add_spring(a, None, 50.0)
    m.add_contact(a, None, "coulomb", 9.81, surface_velocity=0.3, mu_s=0.4, mu_k=0.3)
    kw = dict(method="event_driven", t_end=2.0, n_grid=41, keep_grid=True, rtol=1e-10, atol=1e-12)
    rows = {"spring 0.k": [20.0, 50.0, 200.0, 400.0]}
    one = batch.simulate_model_batch(m, rows, threads=2, **kw)
    monkeypatch.setattr(batch, "MODEL_CHUNK_VALUES", 1)
    chunked = batch.simulate_model_batch(m, rows, threads=2, **kw)
    assert np.array_equal(one.y_grid, chunked.y_grid) and one.notes == chunked.notes
    for k in one.fields:
        if k != "seconds":
            assert np.array_equal(one.fields[k], chunked.fields[k]), k
    assert one.nevents.min() > 0
    for i, k in enumerate(rows["spring 0.k"]):
        m_i = stickslip.Model.from_dict(m.to_dict())
        m_i.springs[0] = (0, None, k, 0.0)
        r = stickslip.simulate(m_i, t_end=2.0, n_out=41, method="event_driven", rtol=1e-10, atol=1e-12)
        assert np.array_equal(one.x[i], r.x) and one.nevents[i] == r.stats["nevents"]


def test_a_bad_model_row_stops_the_batch_before_any_row_runs() -> None:
    """The Fortran model batch builds every row's model before running any: a row whose model
    the library refuses (a mass of -1 kg, past the Python checks) names its element (body 1,
    kind 1 = ELEM_BODY) and no row runs (no steps anywhere)."""
    from stickslip import batch
    from stickslip.core import status_message
    m = _brake()
    rows = [dict(model=m, arrays=m.arrays(), y0=np.array([0.0, 10.0]), ctl={"h": 1e-3, "max_steps": 1e8},
                 rtol=np.array([1.0]), atol=np.array([1.0]), room=0) for _ in range(3)]
    rows[1]["arrays"] = dict(rows[1]["arrays"], bodies=np.asfortranarray([[-1.0], [0.0], [10.0]]))
    istats, _, _, _, elem, status, _ = batch._run_model_rows(
        rows, np.array(["rk4"] * 3), np.full(3, 1.0), 11, 2, np.zeros(1, dtype=np.int32))
    row_status = istats[batch._BATCH_INT.index("status")]
    assert int(status) == 0 and row_status[0] == 0 and row_status[2] == 0
    assert "mass" in status_message(int(row_status[1])) and elem[:, 1].tolist() == [1, 1]
    assert istats[batch._BATCH_INT.index("nstep")].tolist() == [0, 0, 0]


def test_model_rows_on_a_one_point_grid() -> None:
    """n_grid = 1 (t_end alone, nothing for the consistency check to compare) on a model without
    contacts: each row's final state is its single run's, which the closed form of the damped
    oscillator confirms."""
    m = stickslip.Model()
    a = m.add_body(1.0, v0=1.0)
    m.add_spring(a, None, 10.0)
    m.add_damper(a, None, 0.5)
    b = stickslip.simulate_batch(m, {"body 0.v0": [1.0, 2.0]}, method="dopri5", t_end=1.0, n_grid=1,
                                 rtol=1e-10, atol=1e-12)
    assert b.status.tolist() == [0, 0] and b.notes == [] and b.law.tolist() == ["", ""]
    wd = np.sqrt(10.0 - 0.25 ** 2)
    for i, v0 in enumerate([1.0, 2.0]):
        r = stickslip.simulate(m if i == 0 else stickslip.Model.from_dict(
            {**m.to_dict(), "body": [dict(m.to_dict()["body"][0], v0=v0)]}), method="dopri5", t_end=1.0, n_out=1,
            rtol=1e-10, atol=1e-12)
        assert b.x_end[i] == r.x[0, -1] and b.v_end[i] == r.v[0, -1]
        assert b.x_end[i] == pytest.approx(v0 / wd * np.exp(-0.25) * np.sin(wd), abs=1e-8)
