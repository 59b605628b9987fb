"""simulate_batch on a real Dask cluster: a LocalCluster of 2 worker processes on loopback.
The rows come back in order and bit-identical to the local run, a failing row keeps its
status, and a worker process killed mid-sweep costs nothing but time."""
from __future__ import annotations

import logging
import os
import signal
import threading
import time

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")

import stickslip  # noqa: E402
from test_distributed import CHAIN_SWEEP, SWEEP, assert_same_rows  # noqa: E402

# The sweep's RK4 rows include some beyond RK4's stability bound on purpose: the cluster's rows
# must equal the local ones whatever the rows do (the warning itself: test_core_inputs.py).
pytestmark = pytest.mark.filterwarnings("ignore::stickslip.UnstableStepWarning")


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  host="127.0.0.1", dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as c:
        c.wait_for_workers(2)
        yield c


def test_cluster_rows_equal_local(client, tmp_path) -> None:
    local = stickslip.simulate_batch(**SWEEP)
    assert_same_rows(local, stickslip.simulate_batch(**SWEEP, client=client, chunk_rows=7))
    assert_same_rows(local, stickslip.simulate_batch(**SWEEP, client=client))   # default chunks
    store = stickslip.simulate_batch(**SWEEP, client=client, chunk_rows=9, out=tmp_path / "s",
                                     progress=True)
    assert_same_rows(local, store.load())


def test_chain_rows_on_the_cluster(client) -> None:
    """Chains of different n_blocks in chunks of different state widths: as the local run."""
    local = stickslip.simulate_batch(**CHAIN_SWEEP)
    assert_same_rows(local, stickslip.simulate_batch(**CHAIN_SWEEP, client=client, chunk_rows=4))


def test_failing_row_keeps_its_status(client) -> None:
    kw = dict(method="rk4", t_end=20.0, h=1e-3, max_steps=[10**8] * 5 + [100] + [10**8] * 4)
    local = stickslip.simulate_batch("belt", "proposed", **kw)
    b = stickslip.simulate_batch("belt", "proposed", **kw, client=client, chunk_rows=3)
    assert list(b.status) == [0] * 5 + [-2] + [0] * 4
    assert "step budget" in b.message(5) and b.t_reached[5] == pytest.approx(0.1)
    assert_same_rows(local, b)
    with pytest.raises(ValueError, match=r"row 7 .*a: must be finite and > 1"):
        stickslip.simulate_batch("slope", "proposed", method="rk4", t_end=0.1, h=1e-3,
                                 a=[1.5] * 7 + [0.5], client=client, chunk_rows=2)


def test_worker_killed_mid_sweep(client, caplog) -> None:
    """SIGKILL one worker process while chunks run: the scheduler reruns its chunks on the
    other worker (and on the one its nanny restarts); the sweep returns every row."""
    kw = dict(scene="belt", law="proposed", method="rk4", t_end=10.0, h=1e-3,
              v_s=np.geomspace(1e-3, 1e-1, 400), n_grid=51, threads=1)   # about 2 s of work
    local = stickslip.simulate_batch(**kw)
    caplog.set_level(logging.INFO, logger="distributed.scheduler")
    pids = client.run(os.getpid)                       # {worker address: pid}
    victim, pid = sorted(pids.items())[0]
    killed: dict[str, float] = {}

    def kill_when_busy() -> None:
        deadline = time.monotonic() + 20.0
        while time.monotonic() < deadline:             # the victim is running a chunk
            if client.processing(workers=[victim]).get(victim):
                time.sleep(0.1)
                os.kill(pid, signal.SIGKILL)
                killed["at"] = time.monotonic()
                return
            time.sleep(0.02)

    killer = threading.Thread(target=kill_when_busy)
    killer.start()
    b = stickslip.simulate_batch(**kw, client=client, chunk_rows=10)
    done = time.monotonic()
    killer.join()
    assert "at" in killed and killed["at"] < done, "the worker was not killed during the sweep"
    assert any(victim in r.getMessage() and "emov" in r.getMessage() for r in caplog.records), \
        "the scheduler did not see the worker go"
    assert len(b) == 400
    assert_same_rows(local, b)
    client.wait_for_workers(2, timeout=30)             # the nanny restarted it
    assert pid not in client.run(os.getpid).values()


def test_study_rows_on_the_cluster(client) -> None:
    """cases.stability's RK4 and DOPRI5 maps through connect(ADDRESS) (what --scheduler does)
    equal the local ones."""
    from cases import stability
    from stickslip.distributed import connect
    v_ss = [1e-2, 1e-4]
    with connect(client.scheduler.address) as remote:
        assert remote is not None
        assert stability.rk4_map(v_ss, 3, 1, remote) == stability.rk4_map(v_ss, 3, 1)
        assert stability.dopri5_map(v_ss, [1e-3, 1e-6], 1, remote) == \
            stability.dopri5_map(v_ss, [1e-3, 1e-6], 1)


def test_model_rows_on_the_cluster(client) -> None:
    """A model's batch (the model sent to the workers as its dict) equals the local one, and
    each row the single run of the overridden model; a bad override names the whole sweep's row."""
    from test_sweep import ROWS, by_hand, two_body
    kw = dict(method="event_driven", t_end=1.0, n_grid=21, keep_grid=True, rtol=1e-10, atol=1e-12)
    local = stickslip.simulate_batch(two_body(), ROWS, **kw)
    b = stickslip.simulate_batch(two_body(), ROWS, **kw, client=client, chunk_rows=1)
    assert_same_rows(local, b)
    np.testing.assert_array_equal(b.x, local.x)
    for i in range(len(b)):
        r = stickslip.simulate(by_hand(i), n_out=21, **{k: v for k, v in kw.items()
                                                         if k not in ("n_grid", "keep_grid")})
        np.testing.assert_array_equal(b.v[i], r.v)
    with pytest.raises(ValueError, match=r"row 3 \(moreau\): body 0: mass must be > 0"):
        stickslip.simulate_batch(two_body(), {"body 0.mass": [1.0, 1.0, 2.0, -1.0]}, method="moreau",
                                 t_end=0.1, h=1e-3, client=client, chunk_rows=2)
