"""Overhead per task of rotorlib.core.parallel.pmap on a process pool and on a Dask cluster.

Maps a function that does nothing over N items with 2 workers: serially, on a
``ProcessPoolExecutor(2)`` (``executor_for(workers=2)``) and on a local Dask
cluster of 2 worker processes with one thread each, reached through its
scheduler address (``executor_for(scheduler=...)``, as ``--scheduler`` does; or on the
running cluster given by ``--scheduler``),
at ``chunksize`` 1 (one task per item) and 50. Prints the wall time per item
(minimum over repeats; pool and cluster start-up excluded). For reference it
also times Dask's own ``executor.map`` (which ignores ``chunksize``)::

    .venv/bin/python benchmarks/bench_executors.py [--n 2000] [--repeat 3] [--scheduler tcp://127.0.0.1:8786]
"""

from __future__ import annotations

import argparse
import contextlib
import time

from rotorlib.core.parallel import executor_for, pmap


def noop(x):
    return x


def per_item(run, n, repeat):
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - t)
        assert out == list(range(n))
    return best / n


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument(
        "--scheduler", help="time this running Dask cluster instead of a LocalCluster"
    )
    args = ap.parse_args()
    n, rep = args.n, args.repeat
    items = range(n)
    rows = [("serial", per_item(lambda: pmap(noop, items), n, rep))]
    t = time.perf_counter()
    with executor_for(workers=2) as ex:
        pmap(noop, range(4), executor=ex)  # start the processes
        start_pool = time.perf_counter() - t
        for cs in (1, 50):
            rows.append(
                (
                    f"ProcessPoolExecutor(2), chunksize={cs}",
                    per_item(
                        lambda: pmap(noop, items, executor=ex, chunksize=cs), n, rep
                    ),
                )
            )
    t = time.perf_counter()
    with contextlib.ExitStack() as stack:
        if args.scheduler:
            address, name = args.scheduler, "Dask " + args.scheduler
        else:
            from distributed import LocalCluster

            cluster = stack.enter_context(
                LocalCluster(
                    n_workers=2,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                )
            )
            address, name = cluster.scheduler_address, "Dask LocalCluster(2x1)"
        ex = stack.enter_context(executor_for(scheduler=address))
        pmap(noop, range(4), executor=ex)
        start_dask = time.perf_counter() - t
        for cs in (1, 50):
            rows.append(
                (
                    f"{name}, chunksize={cs}",
                    per_item(
                        lambda: pmap(noop, items, executor=ex, chunksize=cs), n, rep
                    ),
                )
            )
        rows.append(
            (
                f"{name}, executor.map",
                per_item(lambda: list(ex.map(noop, items)), n, rep),
            )
        )
    print(
        f"{n} items of a function that returns its argument; 2 workers; min of {rep} repeats"
    )
    print(
        f"start-up: process pool {start_pool:.2f} s, Dask (cluster and) client {start_dask:.2f} s"
    )
    for label, dt in rows:
        print(f"{label:48s} {dt * 1e6:9.1f} us per item")


if __name__ == "__main__":
    main()
