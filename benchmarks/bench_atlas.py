"""Wall time of one atlas census: serial, on a 2-process pool and on 2 Dask workers.

The census (``rotorlib.beyond.atlas.census``, by default at E = 5.45, T_max = 16, grid 300,
named: about 23 s of one core) is timed ``--repeat`` times on each executor, in turn
(serial, process pool, Dask), and every result is checked to be the serial one, orbit by
orbit and digit by digit (``to_dict()`` and start parameter). Each
executor first runs a census at ``T_max = 6`` (its workers compile heyoka's integrators
once); the Dask cluster is local (``distributed.LocalCluster``, 2 workers of one thread).

Printed, never asserted, for each run: the wall time, the load average, and the CPU path:
the CPU seconds of this process plus those of the busiest worker process (Dask's own work
in the worker included). On an idle machine the wall time is the CPU path plus the waits
between tasks; on a busy one it is longer, and the kernel's autogroup scheduling gives a
session's processes together one session's share of the cores, which hides the
speed-up. So the summary gives both speed-ups against serial, of the median wall time and
of the median CPU path (what two cores of our own would give, waits excluded)::

    .venv/bin/python benchmarks/bench_atlas.py [--E 5.45] [--t-max 16] [--repeat 3]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import time
from collections.abc import Iterator
from concurrent.futures import Executor, ProcessPoolExecutor

import psutil  # a dependency of distributed

from rotorlib.beyond.atlas import Atlas, census


def fingerprint(a: Atlas) -> list:
    """Everything a census reports, to compare runs exactly."""
    return [(o.to_dict(), o.extra["u"]) for o in a.orbits]


def worker_cpu() -> dict[int, float]:
    """CPU seconds so far of every process this one started (pool and Dask workers)."""
    out = {}
    for p in psutil.Process().children(recursive=True):
        with contextlib.suppress(psutil.Error):
            t = p.cpu_times()
            out[p.pid] = t.user + t.system
    return out


def timed(
    E: float, t_max: float, executor: Executor | None
) -> tuple[float, float, list]:
    """Wall seconds of one census on ``executor``, its CPU path (CPU seconds of this
    process plus those of the busiest worker) and its fingerprint."""
    w0, t0, c0 = worker_cpu(), time.perf_counter(), time.process_time()
    a = census(E, t_max, executor=executor)
    wall, cpu, w1 = time.perf_counter() - t0, time.process_time() - c0, worker_cpu()
    busy = [w1[p] - w0.get(p, 0.0) for p in w1] if executor is not None else []
    busiest = max(busy, default=0.0)  # serial: the idle workers do not count
    return wall, cpu + busiest, fingerprint(a)


@contextlib.contextmanager
def dask_executor() -> Iterator[Executor]:
    """The executor of a local Dask cluster with 2 single-threaded workers."""
    import distributed

    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, dashboard_address=None
        ) as cl,
        distributed.Client(cl) as client,
    ):
        yield client.get_executor()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--E", type=float, default=5.45)
    ap.add_argument("--t-max", type=float, default=16.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    E, t_max = args.E, args.t_max

    runs: dict[str, list[tuple[float, float]]] = {}
    ref = None
    with ProcessPoolExecutor(2) as pool, dask_executor() as dask:
        executors = {"serial": None, "process pool, 2": pool, "Dask, 2 workers": dask}
        for ex in executors.values():
            census(E, 6.0, executor=ex)  # warm-up: heyoka's JIT in every worker
        for _ in range(args.repeat):
            for label, ex in executors.items():
                wall, path, fp = timed(E, t_max, ex)
                ref = fp if ref is None else ref
                assert fp == ref, f"{label}: a different census"
                runs.setdefault(label, []).append((wall, path))
                load = os.getloadavg()[0]
                print(
                    f"  {label:<16} {wall:6.1f} s, CPU path {path:5.1f} s, load {load:.2f}"
                )
    print(
        f"\ncensus at E = {E:g}, T_max = {t_max:g}, grid 300: {len(ref)} orbits, "
        f"every run the same"
    )
    base = [statistics.median(v[k] for v in runs["serial"]) for k in (0, 1)]
    print(
        f"{'executor':<16} {'wall s':>7} {'speed-up':>9} {'CPU path s':>11} {'speed-up':>9}"
    )
    for label, rs in runs.items():
        wall, path = (statistics.median(v[k] for v in rs) for k in (0, 1))
        print(
            f"{label:<16} {wall:7.1f} {base[0] / wall:9.2f} {path:11.1f} "
            f"{base[1] / path:9.2f}   walls: " + " ".join(f"{v[0]:.1f}" for v in rs)
        )


if __name__ == "__main__":
    main()
