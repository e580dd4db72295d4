"""Seconds per energy of the atlas census (issue 12), printed, never asserted.

1. Against ``T_max`` (8, 12, 16) at E = 5.45 (the band of global chaos), grid 300, on a
   ``ProcessPoolExecutor(2)``.
2. Against the workers at ``T_max = 16``: serial, a 2-process pool, and a local Dask
   cluster (``distributed.LocalCluster``, one thread per worker) with 1 and 2 workers.

Each census is timed once after a warm-up census at ``T_max = 6`` on the same executor
(heyoka's JIT compilation in every worker excluded)::

    .venv/bin/python benchmarks/bench_atlas.py [--E 5.45] [--t-max 16]
"""

from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor

from rotorlib.atlas import census


def timed(E, t_max, executor):
    census(E, 6.0, grid=100, executor=executor, name=False)  # warm-up
    t0 = time.perf_counter()
    a = census(E, t_max, executor=executor, name=False)
    return time.perf_counter() - t0, len(a.orbits), len(a.stable)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--E", type=float, default=5.45)
    ap.add_argument("--t-max", type=float, default=16.0)
    args = ap.parse_args()

    print(f"census at E = {args.E}, grid 300, 2-process pool")
    print(f"{'T_max':>6} {'seconds':>8} {'orbits':>7} {'stable':>7}")
    with ProcessPoolExecutor(2) as ex:
        for t_max in (8.0, 12.0, 16.0):
            s, n, k = timed(args.E, t_max, ex)
            print(f"{t_max:6.0f} {s:8.1f} {n:7d} {k:7d}")

    print(f"\ncensus at E = {args.E}, T_max = {args.t_max:g}: workers")
    rows = [("serial", *timed(args.E, args.t_max, None))]
    with ProcessPoolExecutor(2) as ex:
        rows.append(("process pool, 2", *timed(args.E, args.t_max, ex)))
    try:
        import distributed
    except ImportError:
        distributed = None
    if distributed is not None:
        for n in (1, 2):
            with (
                distributed.LocalCluster(
                    n_workers=n, threads_per_worker=1, dashboard_address=None
                ) as cl,
                distributed.Client(cl) as client,
            ):
                rows.append(
                    (
                        f"Dask, {n} worker(s)",
                        *timed(args.E, args.t_max, client.get_executor()),
                    )
                )
    base = rows[0][1]
    print(f"{'executor':<20} {'seconds':>8} {'speed-up':>9} {'orbits':>7}")
    for name, s, n, _ in rows:
        print(f"{name:<20} {s:8.1f} {base / s:9.2f} {n:7d}")


if __name__ == "__main__":
    main()
