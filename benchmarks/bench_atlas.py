"""Wall time of one atlas census: serial, on a 2-process pool and on 2 Dask workers.

The census (``rotorlib.atlas.census``, by default at E = 5.45, T_max = 16, grid 300,
named: about 20 s of one core) is timed ``--repeat`` times on each executor, in turn
(serial, process pool, Dask), and every result is checked to be the serial one, orbit by
orbit and digit by digit (``to_dict()``, start parameter, number of brackets). Each
executor first runs a census at ``T_max = 6`` (its workers compile heyoka's integrators
once); the Dask cluster is local (``distributed.LocalCluster``, 2 workers of one thread).
Printed, never asserted: seconds of each run (and the CPU seconds of this process: for the
serial run, below its wall time when other work shares the core), the speed-up of the
median against the serial median, and the load average. Other work on the machine hides
the speed-up (with the kernel's autogroup scheduling, a session's processes share one
session's slice of the CPU): measure on an idle machine::

    .venv/bin/python benchmarks/bench_atlas.py [--E 5.45] [--t-max 16] [--repeat 3]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import time
from concurrent.futures import Executor, ProcessPoolExecutor

from rotorlib.atlas import Atlas, census


def fingerprint(a: Atlas) -> list:
    """Everything a census reports, to compare runs exactly."""
    return [a.candidates] + [(o.to_dict(), o.u) for o in a.orbits]


def timed(
    E: float, t_max: float, executor: Executor | None
) -> tuple[float, float, list]:
    """Wall and CPU seconds (of this process) of one census on ``executor``, and its
    fingerprint."""
    t0, c0 = time.perf_counter(), time.process_time()
    a = census(E, t_max, executor=executor)
    return time.perf_counter() - t0, time.process_time() - c0, fingerprint(a)


@contextlib.contextmanager
def dask_executor():
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

    runs: dict[str, list[float]] = {}
    ref = None
    with (
        ProcessPoolExecutor(2) as pool,
        dask_executor() as dask,
    ):
        executors = {"serial": None, "process pool, 2": pool, "Dask, 2 workers": dask}
        for ex in executors.values():
            census(E, 6.0, executor=ex)  # warm-up: heyoka's JIT in every worker
        for _ in range(args.repeat):
            for label, ex in executors.items():
                s, cpu, fp = timed(E, t_max, ex)
                ref = fp if ref is None else ref
                assert fp == ref, f"{label}: a different census"
                runs.setdefault(label, []).append(s)
                load = os.getloadavg()[0]
                print(
                    f"  {label:<16} {s:6.1f} s (CPU here {cpu:5.1f} s), load {load:.2f}"
                )
    base = statistics.median(runs["serial"])
    n = len(ref) - 1
    print(
        f"\ncensus at E = {E:g}, T_max = {t_max:g}, grid 300: {n} orbits, all runs equal"
    )
    print(f"{'executor':<16} {'median s':>9} {'speed-up':>9}  runs (s)")
    for label, ss in runs.items():
        m = statistics.median(ss)
        each = " ".join(f"{s:.1f}" for s in ss)
        print(f"{label:<16} {m:9.1f} {base / m:9.2f}  {each}")


if __name__ == "__main__":
    main()
