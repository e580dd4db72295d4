"""Benchmark (issue 3): time of ``python -m rotorlib bifurcations --n-max 20 --phase both --json``.

Requirement: under 60 s on the 2-core machine for the 80 transitions. Prints the wall time of the whole
command (interpreter start, heyoka JIT compilation, scan and root refinement) and of the library call alone.

Usage: ``.venv/bin/python benchmarks/bench_bifurcations.py``
"""

import json
import subprocess
import sys
import time


def main():
    t0 = time.perf_counter()
    cli = [sys.executable, "-m", "rotorlib", "bifurcations"]
    args = ["--n-max", "20", "--phase", "both", "--json"]
    p = subprocess.run(cli + args, capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    recs = json.loads(p.stdout)
    from rotorlib.paper.bifurcations import transitions

    t0 = time.perf_counter()
    trs = transitions(phase="both", n_max=20)
    lib = time.perf_counter() - t0
    print(
        f"bifurcations --n-max 20 --phase both: {len(recs)} transitions, {wall:.2f} s wall (CLI), "
        f"{lib:.2f} s in rotorlib.paper.bifurcations.transitions (requirement: < 60 s)"
    )
    assert len(recs) == len(trs) == 80
    return 0 if wall < 60 else 1


if __name__ == "__main__":
    sys.exit(main())
