"""Measure a catalogue build that was stopped before it finished (outside CI; a minute).

``python scripts/catalogue_attempt.py --cache DIR --band 6.2 16 --band 8 8``
``  [--window 0.1 8] [--out book/data/catalogue_attempt.json]``

A build's tasks are stored as they finish (:mod:`rotorlib.beyond.catalogue_tasks`), so a
build stopped part-way has measured what it ran. This reads the store and reports, for
the tasks of the band's largest period bound ``T``:

* the censuses to ``T``: their energies, orbit counts and CPU seconds;
* the follows to ``T``: their number and CPU (speculative follows of a seed that a family
  already held included: they were run);
* the branch switching the first switch round asks for: the located ``IS`` / ``PD``
  points of those follows with ``n T_b`` within the bound at ``E_b`` (one task per
  distinct task key, :func:`rotorlib.beyond.catalogue_build.switch_jobs`), how many ran,
  their CPU, and how many orbits they found that lie on no followed family (the seeds of
  the next follows, each tested as the build tests it);

The follows counted are those of the build's own census grid (the most common ``energies``
in the follows' keys): a store shared by several builds holds others.

It writes the JSON that chapter 13 reads for the projected cost of the rest.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main(argv=None) -> int:
    sys.path.insert(0, str(ROOT))
    from rotorlib.beyond.catalogue_build import (
        is_new_daughter,
        special_points,
        switch_jobs,
    )
    from rotorlib.beyond.catalogue_paths import bands_of
    from rotorlib.beyond.catalogue_tasks import task_key

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cache", required=True)
    p.add_argument("--band", nargs=2, type=float, action="append", required=True)
    p.add_argument("--window", nargs=2, type=float, default=[0.1, 8.0])
    p.add_argument("--grid", type=int, default=300)
    p.add_argument("--out", default=None)
    a = p.parse_args(argv)
    lo, hi = a.window
    bands = bands_of([tuple(b) for b in a.band], hi)
    top = max(t for _, t in bands)
    rows = [json.loads(f.read_text()) for f in sorted(Path(a.cache).glob("*.json"))]
    by = {
        k: [r for r in rows if r["kind"] == k] for k in ("census", "follow", "switch")
    }
    census = sorted(
        (r["args"]["E"], len(r["result"]), r["cpu_s"])
        for r in by["census"]
        if r["args"]["t_max"] == top and r["args"].get("grid") == a.grid
    )
    mine = [
        r
        for r in by["follow"]
        if r["args"]["t_max"] == top and r["args"]["E_range"] == [lo, hi]
    ]
    grids = Counter(json.dumps(r["args"]["energies"]) for r in mine)
    grid_E = grids.most_common(1)[0][0] if grids else None
    fams = []
    follow_cpu = []
    for r in mine:
        if json.dumps(r["args"]["energies"]) == grid_E:
            f = dict(r["result"], t_max=top)
            f["special"] = special_points(f)
            fams.append(f)
            follow_cpu.append(r["cpu_s"])
    done = {task_key("switch", r["args"]): r for r in by["switch"]}
    jobs = {
        task_key("switch", j): j for j in switch_jobs(fams, bands, lo, hi, a.grid)[0]
    }
    ran = [done[k] for k in jobs if k in done]
    fresh = sum(
        is_new_daughter(dict(o, via=["switch"], t_max=r["args"]["t_max"]), fams)
        for r in ran
        for o in r["result"]
    )
    sw_cpu = [r["cpu_s"] for r in ran]
    out = {
        "bands": [list(b) for b in bands],
        "window": [lo, hi],
        "t_max": top,
        "census": {
            "energies": [c[0] for c in census],
            "orbits": [c[1] for c in census],
            "cpu_s": round(sum(c[2] for c in census), 1),
        },
        "follow": {
            "n": len(fams),
            "cpu_s": round(sum(follow_cpu), 1),
            "max_s": round(max(follow_cpu, default=0.0), 1),
        },
        "switch_round_1": {
            "tasks": len(jobs),
            "ran": len(ran),
            "cpu_s": round(sum(sw_cpu), 1),
            "mean_s": round(sum(sw_cpu) / len(sw_cpu), 2) if sw_cpu else 0.0,
            "orbits_found": sum(len(r["result"]) for r in ran),
            "orbits_on_no_family": fresh,
        },
    }
    text = json.dumps(out, indent=1)
    print(text)
    if a.out:
        Path(a.out).write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
