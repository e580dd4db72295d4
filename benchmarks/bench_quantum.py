"""Cost of the quantum spectrum (rotorlib.beyond.quantum) against hbar, printed, never asserted.

For each hbar: every sector below ``E_max`` (default 8), each in a fresh worker process
(``max_tasks_per_child=1``) so that its peak resident memory is its own: plane waves,
block size, levels, wall and CPU seconds, peak memory (against
``quantum.memory_estimate``), convergence and the method. ``--cli`` instead times the
command ``python -m rotorlib spectrum --hbar H --sector S --E-max X --json`` as a
subprocess (wall, CPU and peak memory of the child; the issue's target at hbar = 0.01,
A1, E_max = 8 is 10 minutes and 6 GB on 2 cores) and can keep its JSON::

    .venv/bin/python benchmarks/bench_quantum.py                      # 0.1 0.05 0.03
    .venv/bin/python benchmarks/bench_quantum.py --hbar 0.02 --sectors A1 E1
    .venv/bin/python benchmarks/bench_quantum.py --cli --hbar 0.01 --sectors A1 \\
        --keep /tmp/a1.json

The figures of the stored spectra (every sector at hbar = 0.03, 0.02, 0.014, 0.01) are
measured by ``scripts/quantum_spectra.py`` and kept in ``book/data/quantum/cost.json``.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from rotorlib.beyond import quantum


def one(args):
    hbar, sector, E_max = args
    t0, c0 = time.perf_counter(), time.process_time()
    s = quantum.sector_spectrum(hbar, sector, E_max)
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # MiB (Linux: KiB)
    return s, dt, cpu, peak


def cli(hbar, sector, E_max, keep):
    cmd = [sys.executable, "-m", "rotorlib", "spectrum", "--hbar", str(hbar)]
    cmd += ["--sector", sector, "--E-max", str(E_max), "--json"]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode:
        print(p.stderr.strip())
        return
    rec = json.loads(p.stdout)
    if keep:
        Path(keep).write_text(p.stdout)
    print(
        f"{' '.join(cmd[1:])}\n  {rec['count']} levels, convergence "
        f"{rec['convergence']:.1e}; {wall:.0f} s wall, {ru.ru_utime + ru.ru_stime:.0f} s "
        f"CPU, peak {ru.ru_maxrss / 1024:.0f} MiB (estimate "
        f"{quantum.memory_estimate(hbar, E_max) / 2**20:.0f} MiB)"
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hbar", type=float, nargs="+", default=[0.1, 0.05, 0.03])
    ap.add_argument("--E-max", type=float, default=8.0, dest="E_max")
    ap.add_argument("--sectors", nargs="+", default=list(quantum.SECTORS))
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--cli", action="store_true", help="time the command instead")
    ap.add_argument("--keep", default=None, help="--cli: write its JSON here")
    args = ap.parse_args()
    if args.cli:
        for hbar in args.hbar:
            for sec in args.sectors:
                cli(hbar, sec, args.E_max, args.keep)
        return

    head = (
        f"{'hbar':>5} {'sector':>6} {'plane waves':>11} {'block':>6} {'levels':>6} "
        f"{'wall s':>7} {'CPU s':>7} {'peak MiB':>8} {'est MiB':>7} {'convergence':>11}"
        "  method"
    )
    print(f"sectors below E = {args.E_max:g}, one fresh process each")
    print(head)
    t_all = time.perf_counter()
    with ProcessPoolExecutor(args.workers, max_tasks_per_child=1) as ex:
        for hbar in args.hbar:
            jobs = [(hbar, s, args.E_max) for s in args.sectors]
            est = quantum.memory_estimate(hbar, args.E_max) / 2**20
            total, count = 0.0, 0
            for s, dt, cpu, peak in ex.map(one, jobs):
                total += cpu
                count += len(s.levels) * s.multiplicity
                print(
                    f"{hbar:5g} {s.sector:>6} {s.plane_waves:11d} {s.basis_size:6d} "
                    f"{len(s.levels):6d} {dt:7.1f} {cpu:7.1f} {peak:8.0f} {est:7.0f} "
                    f"{s.convergence:11.1e}  {s.method}"
                )
            print(f"{hbar:5g} {'sum':>6} {'':11} {'':6} {count:6d} {'':7} {total:7.1f}")
    print(
        f"wall time of the table on {args.workers} processes: "
        f"{time.perf_counter() - t_all:.0f} s"
    )


if __name__ == "__main__":
    main()
