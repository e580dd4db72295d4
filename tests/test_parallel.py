"""Sweeps through an executor: identical to serial; no progress bar in captured or notebook output.

The Dask tests run a ``distributed.LocalCluster`` (2 worker processes on 127.0.0.1, one per core) and
reach it through its scheduler address, as ``--scheduler`` does; one kills a worker mid-scan.
"""

import importlib.util
import io
import math
import os
import signal
import socket
import sys
import threading
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

from rotorlib.core import parallel
from rotorlib.core.closed_forms import pendulum
from rotorlib.core.parallel import executor_for, pmap
from rotorlib.orbits.floquet import monodromy

HAVE_DISTRIBUTED = importlib.util.find_spec("distributed") is not None
# Skipped only where dask[distributed] is missing; CI (CI=true) installs it from environment.txt and runs them.
requires_distributed = pytest.mark.skipif(
    not HAVE_DISTRIBUTED and os.environ.get("CI") != "true",
    reason="dask[distributed] not installed (pip install -r environment.txt)",
)

XS = [
    (-1.0, "lib"),
    (-5.0, "rot"),
    (-21.0012, "lib"),
    (-21.5, "rot"),
    (-60.0, "lib"),
    (-300.0, "rot"),
]


def trace_at(item):
    """Module level, so that process pools can pickle it."""
    x, phase = item
    M = monodromy(pendulum(log_abs_dE=x, phase=phase))
    return M.trace, M.precision, M.backend


def test_process_pool_identical_to_serial():
    serial = pmap(trace_at, XS)
    with ProcessPoolExecutor(max_workers=2) as ex:
        pooled = pmap(trace_at, XS, executor=ex, chunksize=2)
    assert pooled == serial  # bit-identical floats, same labels, same order
    assert all(np.isfinite(t) for t, _, _ in serial)


def test_thread_pool_identical_to_serial():
    serial = pmap(trace_at, XS[:3])
    with ThreadPoolExecutor(max_workers=2) as ex:
        assert pmap(trace_at, XS[:3], executor=ex) == serial


def test_progress_bar_off_when_not_a_terminal(capfd):
    pmap(trace_at, XS[:2], progress=True, desc="sweep")
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_progress_bar_off_under_tqdm_disable(monkeypatch, capfd):
    monkeypatch.setenv("TQDM_DISABLE", "1")
    pmap(trace_at, XS[:2], progress=True)
    assert capfd.readouterr() == ("", "")


def test_no_progress_bar_in_notebook_output():
    """Run pmap(progress=True) in a Jupyter kernel (as nbval does) without TQDM_DISABLE: no stream output."""
    jc = pytest.importorskip("jupyter_client")
    env = {
        k: v for k, v in os.environ.items() if k not in ("TQDM_DISABLE", "MPLBACKEND")
    }
    km, kc = jc.manager.start_new_kernel(kernel_name="python3", env=env)
    try:
        code = (
            "from rotorlib.core.closed_forms import pendulum\n"
            "from rotorlib.core.parallel import pmap\n"
            "from rotorlib.orbits.floquet import monodromy\n"
            "r = pmap(lambda x: monodromy(pendulum(E=x)).trace, [1.0, 2.0, 5.0], "
            "progress=True)\n"
            "len(r)"
        )
        msg_id = kc.execute(code)
        streams, result = [], None
        while True:
            msg = kc.get_iopub_msg(timeout=60)
            if msg["parent_header"].get("msg_id") != msg_id:
                continue
            kind = msg["msg_type"]
            if kind in (
                "stream",
                "display_data",
                "update_display_data",
            ):  # tqdm text or widget
                streams.append(msg["content"])
            elif kind == "execute_result":
                result = msg["content"]["data"]["text/plain"]
            elif kind == "error":
                raise AssertionError("\n".join(msg["content"]["traceback"]))
            elif kind == "status" and msg["content"]["execution_state"] == "idle":
                break
        assert result == "3"
        assert streams == []
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)


class _TTY(io.StringIO):
    def isatty(self):
        return True


@pytest.mark.parametrize("pool", [None, ThreadPoolExecutor])
def test_progress_bar_on_a_terminal(monkeypatch, pool):
    monkeypatch.delenv("TQDM_DISABLE", raising=False)
    monkeypatch.setattr(sys, "stderr", _TTY())
    xs = [-1, -2, -3, -4, -5]
    if pool is None:
        assert pmap(abs, xs, progress=True, desc="sweep") == [1, 2, 3, 4, 5]
    else:
        with pool(2) as ex:
            assert pmap(
                abs, xs, executor=ex, progress=True, desc="sweep", chunksize=2
            ) == [1, 2, 3, 4, 5]
    assert "sweep: 100%" in sys.stderr.getvalue() and "5/5" in sys.stderr.getvalue()


def test_progress_counts_items_as_they_complete(monkeypatch):
    """Item 0 finishes only once the bar has counted the three after it: the bar does not wait for input order."""
    counted, n = threading.Event(), [0]

    class Bar:
        def update(self, k=1):
            n[0] += k
            if n[0] >= 3:
                counted.set()

        def close(self):
            pass

    monkeypatch.setattr(parallel, "_bar", lambda total, desc, progress: Bar())
    with ThreadPoolExecutor(2) as ex:
        out = pmap(
            lambda x: counted.wait(10) if x == 0 else x,
            [0, 1, 2, 3],
            executor=ex,
            progress=True,
        )
    assert out == [True, 1, 2, 3] and n[0] == 4


def test_first_exception_is_raised():
    with ThreadPoolExecutor(2) as ex:
        with pytest.raises(ZeroDivisionError):
            pmap(lambda x: 1 / x, [1, 2, 0, 4], executor=ex)


# --- executor_for -------------------------------------------------------------------------------


def test_executor_for_serial_and_process_pool():
    for workers in (None, 1):
        with executor_for(workers) as ex:
            assert ex is None
    serial = pmap(trace_at, XS[:4])
    with executor_for(workers=2) as ex:
        assert isinstance(ex, ProcessPoolExecutor) and ex._max_workers == 2
        assert pmap(trace_at, XS[:4], executor=ex, chunksize=3) == serial
    with pytest.raises(RuntimeError):  # shut down on exit
        ex.submit(abs, 1)


@pytest.mark.parametrize(
    "kw",
    [{"workers": w} for w in (0, -3, 1.5, 2.0, "2", True)]
    + [{"workers": 2, "scheduler": "tcp://127.0.0.1:8786"}],
    ids=repr,
)
def test_executor_for_bad_workers(kw):
    with pytest.raises(ValueError) as err:
        with executor_for(**kw):
            pass
    msg = str(err.value)
    assert "\n" not in msg and "workers" in msg


def test_pmap_bad_chunksize():
    with pytest.raises(ValueError, match="chunksize"):
        pmap(abs, [1, 2], chunksize=0)


def test_executor_for_without_distributed(monkeypatch):
    monkeypatch.setitem(
        sys.modules, "distributed", None
    )  # import distributed -> ImportError
    with pytest.raises(ValueError, match=r"dask\[distributed\]"):
        with executor_for(scheduler="tcp://127.0.0.1:8786"):
            pass


@requires_distributed
@pytest.mark.parametrize(
    "address",
    [
        "foo://127.0.0.1:1",
        "tls://127.0.0.1:8786",
        "tcp://",
        "127.0.0.1",
        "tcp://host.invalid:8786",
        "free port",
    ],
)
def test_executor_for_bad_scheduler(address):
    if (
        address == "free port"
    ):  # nothing listens there: connection refused until timeout
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
    t = time.monotonic()
    with pytest.raises(ValueError) as err:
        with executor_for(scheduler=address, timeout=1):
            pass
    assert time.monotonic() - t < 10
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(
        f"cannot connect to Dask scheduler {address}: "
    )


@requires_distributed
def test_bad_scheduler_leaves_no_noise_at_exit(tmp_path):
    """What the CLI will print is the one-line error: nothing from a half-started Client at exit."""
    import subprocess

    code = (
        "from rotorlib.core.parallel import executor_for\n"
        "for a in ['foo://x:1', 'tcp://', 'tcp://127.0.0.1:9']:\n"
        "    try:\n"
        "        with executor_for(scheduler=a, timeout=1): pass\n"
        "    except ValueError as e: print(e)\n"
    )
    t = time.monotonic()
    res = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60
    )
    assert res.returncode == 0 and res.stderr == "", res.stderr
    assert len(res.stdout.splitlines()) == 3 and time.monotonic() - t < 30


@requires_distributed
def test_executor_for_scheduler_without_workers():
    from distributed import LocalCluster

    with LocalCluster(
        n_workers=0,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        address = cluster.scheduler_address
        with pytest.raises(
            ValueError, match=f"Dask scheduler {address} has no worker after 1 s"
        ):
            with executor_for(scheduler=address, timeout=1):
                pass


# --- Dask cluster -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def dask_cluster():
    """Two worker processes (one thread each) under nannies, which restart a worker that dies."""
    from distributed import LocalCluster

    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        host="127.0.0.1",
    ) as cluster:
        yield cluster


@requires_distributed
def test_dask_identical_to_serial(dask_cluster, monkeypatch):
    serial = pmap(trace_at, XS)
    monkeypatch.delenv("TQDM_DISABLE", raising=False)
    monkeypatch.setattr(sys, "stderr", _TTY())
    with executor_for(scheduler=dask_cluster.scheduler_address) as ex:
        assert type(ex).__name__ == "ClientExecutor"
        assert pmap(trace_at, XS, executor=ex) == serial  # one task per item
        assert (
            pmap(trace_at, XS, executor=ex, chunksize=4, progress=True, desc="dask")
            == serial
        )
    assert "dask: 100%" in sys.stderr.getvalue() and "6/6" in sys.stderr.getvalue()


KILL_ITEM = 8


def scan_task(item):
    """Deterministic in i. With a log directory: marks its completion, and the first run of item KILL_ITEM
    claims the file ``victim`` (writing its worker's pid) and then waits to be killed."""
    i, delay, logdir = item
    if logdir is not None:
        if i == KILL_ITEM:
            tmp = os.path.join(logdir, f"pid-{os.getpid()}")
            with open(tmp, "w") as f:
                f.write(str(os.getpid()))
            try:
                os.link(
                    tmp, os.path.join(logdir, "victim")
                )  # atomic: only the first run claims it
            except FileExistsError:
                pass
            else:
                time.sleep(60)  # SIGKILLed here
        time.sleep(delay)
        open(os.path.join(logdir, f"done-{i}-{os.getpid()}"), "w").close()
    return i, math.fsum(math.sin(k * i) / k for k in range(1, 100))


@requires_distributed
@pytest.mark.parametrize("allowed_failures", [3, 0])
def test_dask_worker_killed_mid_scan(dask_cluster, tmp_path, allowed_failures):
    """A worker is killed while it runs item 8 of 40: Dask reruns it elsewhere and the scan is unchanged.

    With ``allowed-failures`` 3 (Dask's default) the result equals the serial one; with 0, the same kill
    makes Dask give the task up (KilledWorker), which shows that this test sees a lost task.
    """
    from distributed.scheduler import KilledWorker

    cluster = dask_cluster
    cluster.wait_for_workers(2, timeout=30)
    n = 40
    expected = pmap(scan_task, [(i, 0.0, None) for i in range(n)])
    items = [(i, 0.1, str(tmp_path)) for i in range(n)]
    before = set(cluster.scheduler.workers)
    worker_pids = {w.process.process.pid for w in cluster.workers.values()}
    saved, cluster.scheduler.allowed_failures = (
        cluster.scheduler.allowed_failures,
        allowed_failures,
    )

    def scan():
        with executor_for(scheduler=cluster.scheduler_address) as ex:
            return pmap(scan_task, items, executor=ex)

    t0 = time.monotonic()
    try:
        with ThreadPoolExecutor(1) as runner:
            fut = runner.submit(scan)
            victim = tmp_path / "victim"
            while not (victim.exists() and victim.read_text()):
                assert time.monotonic() - t0 < 30 and not fut.done(), (
                    "item 8 never started"
                )
                time.sleep(0.01)
            pid = int(victim.read_text())
            assert pid in worker_pids
            done_before_kill = len(list(tmp_path.glob("done-*")))
            os.kill(pid, signal.SIGKILL)
            if allowed_failures:
                assert (
                    fut.result(timeout=45) == expected
                )  # every task, in order, same values
            else:
                with pytest.raises(KilledWorker):
                    fut.result(timeout=45)
        cluster.wait_for_workers(2, timeout=30)  # the nanny restarted the worker
    finally:
        cluster.scheduler.allowed_failures = saved
    assert done_before_kill >= 4  # killed after a few tasks completed
    assert (
        len(before - set(cluster.scheduler.workers)) == 1
    )  # the killed worker left the cluster
    if allowed_failures:
        done = {tuple(map(int, p.name.split("-")[1:])) for p in tmp_path.glob("done-*")}
        assert {i for i, _ in done} == set(range(n))
        assert (KILL_ITEM, pid) not in done and any(
            i == KILL_ITEM for i, _ in done
        )  # rerun on another worker
    assert time.monotonic() - t0 < 50
