"""Cost of the quantum spectrum (rotorlib.beyond.quantum) against hbar, printed, never asserted.

For each hbar: every sector below ``E_max`` (default 6.5), each in a fresh worker process
(``max_tasks_per_child=1``) so that its peak resident memory is its own: plane waves, block
size, levels, seconds, peak memory, convergence and the method. Then the whole spectrum at
the smallest hbar through ``rotorlib.core.parallel.pmap`` on the pool (wall time)::

    .venv/bin/python benchmarks/bench_quantum.py                   # hbar 0.2 0.1 0.05 (~2 min)
    .venv/bin/python benchmarks/bench_quantum.py --hbar 0.02 --no-whole  # ~31,700 levels
"""

from __future__ import annotations

import argparse
import resource
import time
from concurrent.futures import ProcessPoolExecutor

from rotorlib.beyond import quantum


def one(args):
    hbar, sector, E_max = args
    t0 = time.perf_counter()
    s = quantum.sector_spectrum(hbar, sector, E_max)
    dt = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # MiB (Linux: KiB)
    return s, dt, peak


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hbar", type=float, nargs="+", default=[0.2, 0.1, 0.05])
    ap.add_argument("--E-max", type=float, default=6.5, dest="E_max")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument(
        "--no-whole",
        action="store_true",
        help="skip the whole-spectrum run through pmap",
    )
    args = ap.parse_args()

    head = (
        f"{'hbar':>5} {'sector':>6} {'plane waves':>11} {'block':>6} {'levels':>6} "
        f"{'seconds':>8} {'peak MiB':>8} {'convergence':>11}  method"
    )
    print(f"every sector below E = {args.E_max:g}, one fresh process each")
    print(head)
    t_all = time.perf_counter()
    with ProcessPoolExecutor(args.workers, max_tasks_per_child=1) as ex:
        for hbar in args.hbar:
            jobs = [(hbar, s, args.E_max) for s in quantum.SECTORS]
            total, count = 0.0, 0
            for s, dt, peak in ex.map(one, jobs):
                total += dt
                count += len(s.levels) * s.multiplicity
                print(
                    f"{hbar:5g} {s.sector:>6} {s.plane_waves:11d} {s.basis_size:6d} "
                    f"{len(s.levels):6d} {dt:8.1f} {peak:8.0f} {s.convergence:11.1e}"
                    f"  {s.method}"
                )
            print(
                f"{hbar:5g} {'all':>6} {'':11} {'':6} {count:6d} {total:8.1f} "
                "(sum over sectors, one core)"
            )
    print(
        f"wall time of the table on {args.workers} processes: "
        f"{time.perf_counter() - t_all:.0f} s"
    )
    if args.no_whole:
        return
    h = min(args.hbar)
    with ProcessPoolExecutor(args.workers) as ex:
        t0 = time.perf_counter()
        s = quantum.spectrum(h, args.E_max, executor=ex)
        wall = time.perf_counter() - t0
    print(
        f"\nwhole spectrum at hbar = {h:g} below {args.E_max:g} through pmap on "
        f"{args.workers} processes: {len(s.levels)} levels, {wall:.0f} s wall, "
        f"convergence {s.convergence:.1e}"
    )


if __name__ == "__main__":
    main()
