"""Wall time of a small catalogue build on 1 and 2 worker processes, and projections.

A slice (default E = 4.3 .. 4.55 by 0.05, T_max = 5, grid 60, unnamed censuses,
max 60 continuation steps, members polished to 20 digits) is built from an empty cache,
serially and on a process pool of 2 (``rotorlib.core.parallel.executor_for``). Printed,
never asserted: the wall times, the speed-up, the sum of the tasks' CPU seconds (stored
with each task) and the load average; then the projected wall time of a build whose
task CPU total is ``--cpu`` seconds on 64 workers (the largest task bounds it)::

    .venv/bin/python benchmarks/bench_catalogue.py [--cpu SECONDS]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

from rotorlib.beyond.catalogue_build import build
from rotorlib.core.parallel import executor_for

ENERGIES = [4.3, 4.35, 4.4, 4.45, 4.5, 4.55]


def run(workers: int) -> tuple[float, list[float]]:
    with tempfile.TemporaryDirectory() as d, executor_for(workers) as ex:
        t0 = time.time()
        build(
            ENERGIES,
            5.0,
            d,
            grid=60,
            refine=0,
            digits=20,
            name=False,
            max_steps=60,
            executor=ex,
        )
        wall = time.time() - t0
        cpu = [json.loads(p.read_text())["cpu_s"] for p in Path(d).glob("*.json")]
    return wall, cpu


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument(
        "--cpu",
        type=float,
        default=None,
        help="task CPU total of a full build to project (s)",
    )
    a = ap.parse_args()
    run(1)  # compile heyoka's integrators once
    w1, c1 = run(1)
    w2, c2 = run(2)
    print(f"load average {os.getloadavg()[0]:.1f}")
    print(f"1 worker: {w1:.1f} s wall; tasks {len(c1)}, CPU {sum(c1):.1f} s")
    print(f"2 workers: {w2:.1f} s wall; CPU {sum(c2):.1f} s; speed-up {w1 / w2:.2f}x")
    if a.cpu:
        print(f"projected on 64 workers: >= {a.cpu / 64:.0f} s (+ the longest task)")


if __name__ == "__main__":
    main()
