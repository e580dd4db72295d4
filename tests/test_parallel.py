"""Sweeps through an executor: identical to serial; no progress bar in captured or notebook output."""
import os
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

import rotorlib as rl
from rotorlib.parallel import pmap

XS = [(-1.0, "lib"), (-5.0, "rot"), (-21.0012, "lib"), (-21.5, "rot"), (-60.0, "lib"), (-300.0, "rot")]


def trace_at(item):
    """Module level, so that process pools can pickle it."""
    x, phase = item
    M = rl.monodromy(rl.pendulum(log_abs_dE=x, phase=phase))
    return M.trace, M.precision, M.backend


def test_process_pool_identical_to_serial():
    serial = pmap(trace_at, XS)
    with ProcessPoolExecutor(max_workers=2) as ex:
        pooled = pmap(trace_at, XS, executor=ex, chunksize=2)
    assert pooled == serial                       # bit-identical floats, same labels, same order
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
    env = {k: v for k, v in os.environ.items() if k not in ("TQDM_DISABLE", "MPLBACKEND")}
    km, kc = jc.manager.start_new_kernel(kernel_name="python3", env=env)
    try:
        code = ("from rotorlib.parallel import pmap\nimport rotorlib as rl\n"
                "r = pmap(lambda x: rl.monodromy(rl.pendulum(E=x)).trace, [1.0, 2.0, 5.0], progress=True)\n"
                "len(r)")
        msg_id = kc.execute(code)
        streams, result = [], None
        while True:
            msg = kc.get_iopub_msg(timeout=60)
            if msg["parent_header"].get("msg_id") != msg_id:
                continue
            kind = msg["msg_type"]
            if kind in ("stream", "display_data", "update_display_data"):   # tqdm text or widget
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
