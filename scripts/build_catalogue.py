"""Build the catalogue of periodic-orbit families (outside CI; resumable).

``python scripts/build_catalogue.py --E 5.40 5.45 5.50 --t-max 16 --workers 2``
``  --cache build/catalogue-cache --out book/data/catalogue``
``python scripts/build_catalogue.py --E-grid 0.1 8 0.1 --band 6.2 16 --band 8 8 --workers 2``

``--band 6.2 16 --band 8 8``: the census seeks T <= 16 up to E = 6.2 and T <= 8 above
(each census orbit followed over the whole window to its census's bound).

``--E-grid LO HI STEP``: census energies LO, LO + STEP, ... up to HI (rounded to 12
decimals; with ``--E`` the union).

Every task's result is stored in ``--cache`` as it finishes: run the same command again
after a kill and the finished tasks are read back, not redone. Prints the measured cost
(wall, task CPU per kind: total, number run, mean and largest, and the CPU of each
family) as JSON on the last line and writes it to ``OUT/build.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

from rotorlib.beyond.catalogue import DATA, SCHEMA
from rotorlib.beyond.catalogue_build import build
from rotorlib.beyond.catalogue_files import write
from rotorlib.beyond.catalogue_ids import previous_census
from rotorlib.core.parallel import executor_for


def name_choreographies(cat: dict) -> int:
    """Name the census's choreographies after the library's families (the front door's
    :func:`rotorlib.api.name_choreography`, which the beyond layer cannot call: the
    census tasks label them ``choreography``); returns how many were named."""
    from rotorlib.api import name_choreography
    from rotorlib.beyond.choreo import choreography_of

    named = 0
    for orbits in cat["censuses"].values():
        for o in orbits:
            if o["label"] != "choreography":
                continue
            c = choreography_of(o["state0"], o["period"])
            if c is not None:
                o["label"] = name_choreography(o["E"], c, o["period"])
                named += o["label"] != "choreography"
    return named


def rest_censuses(cat: dict, base: list[float], a, ex) -> dict | None:
    """With bands, the censuses to the largest bound at the base energies where the
    build's bound is lower (stored tasks: the measure of what the rest of the scope
    holds, for the projection of its cost), and the same count on the base energies
    the largest bound covers: ``{'t_max', 'energies', 'census_orbits', 'cpu_s',
    'band_energies', 'band_census_orbits'}``; ``None`` with one bound."""
    from rotorlib.beyond.catalogue_paths import period_bound
    from rotorlib.beyond.catalogue_tasks import run_tasks

    bands, top = cat["bands"], cat["t_max"]
    if len({t for _, t in bands}) == 1:
        return None
    rest = [E for E in base if period_bound(bands, E) < top]
    extra = {"name": False} if a.no_names else {}
    jobs = [("census", {"E": E, "t_max": top, "grid": a.grid, **extra}) for E in rest]
    cpu: dict[str, float] = {}
    got, _ = run_tasks(jobs, a.cache, ex, sys.stderr.isatty(), "rest", cpu)
    band = [E for E in base if period_bound(bands, E) == top]
    return {
        "t_max": top,
        "energies": rest,
        "census_orbits": [len(r) for r in got],
        "cpu_s": round(sum(cpu.values()), 1),
        "band_energies": band,
        "band_census_orbits": [len(cat["censuses"][E]) for E in band],
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--E", nargs="+", type=float, default=[])
    p.add_argument("--E-grid", nargs=3, type=float, metavar=("LO", "HI", "STEP"))
    p.add_argument("--t-max", type=float, default=16.0)
    p.add_argument(
        "--band",
        nargs=2,
        type=float,
        action="append",
        metavar=("E_HI", "T_MAX"),
        help="census bound T_MAX up to E_HI (repeat; replaces --t-max)",
    )
    p.add_argument("--grid", type=int, default=300)
    p.add_argument("--step", type=float, default=0.01)
    p.add_argument("--refine", type=int, default=1)
    p.add_argument("--digits", type=int, default=30)
    p.add_argument("--cache", default="build/catalogue-cache")
    p.add_argument("--out", default="book/data/catalogue")
    p.add_argument("--workers", type=int, default=None)
    p.add_argument("--scheduler", default=None)
    p.add_argument("--no-write", action="store_true")
    p.add_argument(
        "--max-steps", type=int, default=None, help="default: the whole window"
    )
    p.add_argument("--switch", type=int, default=2, help="branch-switching rounds")
    p.add_argument("--no-names", action="store_true", help="unnamed censuses (tests)")
    p.add_argument(
        "--ids-from",
        default=str(DATA),
        help="keep the record ids of this earlier catalogue (default: the library's; "
        "'none': number afresh)",
    )
    a = p.parse_args(argv)
    energies = set(a.E)
    if a.E_grid:
        lo, hi, st = a.E_grid
        if not (st > 0 and lo <= hi):
            p.error("--E-grid needs LO <= HI and STEP > 0")
        n = int(math.floor((hi - lo) / st + 1e-9))
        energies |= {round(lo + k * st, 12) for k in range(n + 1)}
    if not energies:
        p.error("give --E or --E-grid")
    t0, c0 = time.time(), time.process_time()
    with executor_for(a.workers, a.scheduler) as ex:
        cat = build(
            sorted(energies),
            [tuple(b) for b in a.band] if a.band else a.t_max,
            a.cache,
            grid=a.grid,
            step=a.step,
            refine=a.refine,
            digits=a.digits,
            name=not a.no_names,
            max_steps=a.max_steps,
            switch=a.switch,
            executor=ex,
            progress=sys.stderr.isatty(),
            log=lambda s: print(s, file=sys.stderr, flush=True),
        )
        rest = rest_censuses(cat, sorted(energies), a, ex)
    cost = {
        "wall_s": round(time.time() - t0, 1),
        "client_cpu_s": round(time.process_time() - c0, 1),
        "workers": a.workers or 1,
        "load_average": round(os.getloadavg()[0], 1),
        "max_steps": cat["max_steps"],
        "tasks": {
            k: {
                "n": n,
                "run": r,
                "cpu_s": round(cat["cpu"][k], 1),
                "mean_s": round(cat["cpu"][k] / n, 2) if n else 0.0,
                "max_s": round(cat["cpu_max"][k], 1),
            }
            for k, (n, r) in cat["tasks"].items()
        },
        "families": len(cat["families"]),
        "bands": cat["bands"],
        "switch_rounds": cat["switch_rounds"],
        "beyond_rounds": cat["beyond_rounds"],
        "densify_rounds": cat["densify_rounds"],
    }
    if rest:
        cost["rest"] = rest
    cost["task_cpu_s"] = round(sum(v["cpu_s"] for v in cost["tasks"].values()), 1)
    if any(n > r for n, r in cat["tasks"].values()):
        # resumed: some results were read from the cache, so the wall time and the
        # load of this invocation say nothing about the build's cost (its task CPU does)
        for k in ("wall_s", "client_cpu_s", "load_average"):
            cost.pop(k)
        cost["resumed"] = True
    if not a.no_write:
        if not a.no_names:
            name_choreographies(cat)
        previous = {} if a.ids_from == "none" else previous_census(a.ids_from)
        write(cat, a.out, SCHEMA, previous)  # gives each family its id
        cost["per_family"] = [
            {
                "id": f["id"],
                "E_range": [
                    min(m["E"] for m in f["path"]),
                    max(m["E"] for m in f["path"]),
                ],
                "members": len(f["path"]),
                "t_max": f["t_max"],
                "cpu_s": {k: round(v, 2) for k, v in f["cpu_s"].items()},
            }
            for f in sorted(cat["families"], key=lambda f: f["id"])
        ]
        Path(a.out, "build.json").write_text(json.dumps(cost, indent=1))
    for k, v in cost["tasks"].items():
        print(
            f"{k}: {v['n']} tasks ({v['run']} run), CPU {v['cpu_s']} s, "
            f"mean {v['mean_s']} s, largest {v['max_s']} s",
            file=sys.stderr,
        )
    print(json.dumps({k: v for k, v in cost.items() if k != "per_family"}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
