"""Build the catalogue of periodic-orbit families (outside CI; resumable).

``python scripts/build_catalogue.py --E 5.40 5.45 5.50 --t-max 16 --workers 2``
``  --cache build/catalogue-cache --out book/data/catalogue``

Every task's result is stored in ``--cache`` as it finishes: run the same command again
after a kill and the finished tasks are read back, not redone. Prints the measured cost
(wall and per task kind) as JSON on the last line and writes it to ``OUT/build.json``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from rotorlib.beyond.catalogue import SCHEMA
from rotorlib.beyond.catalogue_build import build
from rotorlib.beyond.catalogue_files import write
from rotorlib.core.parallel import executor_for


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--E", nargs="+", type=float, required=True)
    p.add_argument("--t-max", type=float, default=16.0)
    p.add_argument("--grid", type=int, default=300)
    p.add_argument("--step", type=float, default=0.01)
    p.add_argument("--refine", type=int, default=1)
    p.add_argument("--digits", type=int, default=30)
    p.add_argument("--cache", default="build/catalogue-cache")
    p.add_argument("--out", default="book/data/catalogue")
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--scheduler", default=None)
    p.add_argument("--no-write", action="store_true")
    p.add_argument("--max-steps", type=int, default=600)
    p.add_argument("--no-names", action="store_true", help="unnamed censuses (tests)")
    a = p.parse_args(argv)
    t0, c0 = time.time(), time.process_time()
    with executor_for(a.workers, a.scheduler) as ex:
        cat = build(
            a.E,
            a.t_max,
            a.cache,
            grid=a.grid,
            step=a.step,
            refine=a.refine,
            digits=a.digits,
            name=not a.no_names,
            max_steps=a.max_steps,
            executor=ex,
            progress=sys.stderr.isatty(),
            log=lambda s: print(s, file=sys.stderr, flush=True),
        )
    cost = {
        "wall_s": round(time.time() - t0, 1),
        "client_cpu_s": round(time.process_time() - c0, 1),
        "workers": a.workers or 1,
        "tasks": cat["tasks"],
        "families": len(cat["families"]),
    }
    if not a.no_write:
        write(cat, a.out, SCHEMA)
        Path(a.out, "build.json").write_text(json.dumps(cost, indent=1))
    print(json.dumps(cost))
    return 0


if __name__ == "__main__":
    sys.exit(main())
