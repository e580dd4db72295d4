"""Wall time of a small catalogue build on 1 and 2 worker processes, and projections.

A slice (E = 5.3 .. 5.65 by 0.05, T_max = 6, grid 60, unnamed censuses, at most 30
continuation steps each way: many families of comparable cost, as a full build has, members polished to 20 digits, no branch switching) is built
from an empty cache, serially and on a process pool of 2
(``rotorlib.core.parallel.executor_for``; the pool's processes are started and their
integrators compiled before the clock starts). Printed, never asserted: the load average,
the wall times, the speed-up, the sum of the tasks' CPU seconds (stored with each task)
and its ratio to the wall time (the parallelism obtained: on a loaded machine the
speed-up is bounded by the CPU the build gets, which this ratio shows); then the projected
wall time of a build whose task CPU total is ``--cpu`` seconds on 64 workers (the largest
task bounds it)::

    .venv/bin/python benchmarks/bench_catalogue.py [--cpu SECONDS] [--max-task SECONDS]
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

ENERGIES = [5.3, 5.35, 5.4, 5.45, 5.5, 5.55, 5.6, 5.65]


def _warm(_: int) -> int:
    """A small census in a worker: heyoka's integrators compiled there."""
    from rotorlib.beyond.atlas import census

    return len(census(4.3, 3.0, 20, name=False).orbits)


def schedule(tasks: list[tuple[str, float]], workers: int) -> float:
    """The wall time of the build's stages (census, follow and switch, polish) run one
    after the other, the tasks ``(kind, CPU seconds)`` of each stage list-scheduled in
    order on ``workers`` that are never preempted: the speed-up the build's schedule
    allows, whatever the machine's load."""
    wall = 0.0
    for stage in (("census",), ("follow", "switch"), ("polish",)):
        load = [0.0] * workers
        for k, c in tasks:
            if k in stage:
                load[load.index(min(load))] += c
        wall += max(load)
    return wall


def run(workers: int) -> tuple[float, dict[str, tuple[str, float]], float]:
    """``(wall, {task file: (kind, CPU s)} in the order they finished, load)``."""
    with tempfile.TemporaryDirectory() as d, executor_for(workers) as ex:
        if ex is not None:
            list(ex.map(_warm, range(4 * workers)))
        else:
            _warm(0)
        t0, l0 = time.time(), os.getloadavg()[0]
        build(
            ENERGIES,
            6.0,
            d,
            grid=60,
            refine=0,
            digits=20,
            name=False,
            max_steps=30,
            executor=ex,
            switch=0,
        )
        wall = time.time() - t0
        load = (l0 + os.getloadavg()[0]) / 2
        cpu: dict[str, tuple[str, float]] = {}
        for p in sorted(Path(d).glob("*.json"), key=lambda p: p.stat().st_mtime_ns):
            rec = json.loads(p.read_text())
            cpu[p.name] = (rec["kind"], rec["cpu_s"])
    return wall, cpu, load


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument(
        "--cpu",
        type=float,
        default=None,
        help="task CPU total of a full build to project (s)",
    )
    ap.add_argument(
        "--max-task", type=float, default=0.0, help="its largest task's CPU (s)"
    )
    a = ap.parse_args()
    w1, k1, l1 = run(1)
    w2, k2, l2 = run(2)
    c1, c2 = (sum(c for _, c in k.values()) for k in (k1, k2))
    print(
        f"load average {l1:.1f} (1 worker), {l2:.1f} (2 workers) on {os.cpu_count()} CPUs"
    )
    print(
        f"1 worker: {w1:.1f} s wall; {len(k1)} tasks, CPU {c1:.1f} s "
        f"(CPU / wall {c1 / w1:.2f})"
    )
    print(
        f"2 workers: {w2:.1f} s wall; {len(k2)} tasks, CPU {c2:.1f} s "
        f"(CPU / wall {c2 / w2:.2f}); speed-up {w1 / w2:.2f}x"
    )
    # one set of costs (the 2-worker run's: a task's CPU seconds vary between runs on a
    # loaded machine): serially the tasks of the serial run (keys are the inputs' hash),
    # on 2 workers all of them (the speculative follows included)
    t1 = [k2[n] for n in k1 if n in k2]
    s1, s2 = schedule(t1, 1), schedule(list(k2.values()), 2)
    print(
        f"schedule of the measured task costs: {s1:.1f} s on 1 worker, {s2:.1f} s on 2 "
        f"({len(k2) - len(k1)} speculative follows): speed-up {s1 / s2:.2f}x on an "
        "idle machine"
    )
    if a.cpu:
        print(
            f"projected on 64 workers: >= {max(a.cpu / 64, a.max_task):.0f} s "
            f"(CPU {a.cpu:.0f} s / 64, or the largest task {a.max_task:.0f} s)"
        )


if __name__ == "__main__":
    main()
