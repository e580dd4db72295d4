"""The period-doubling cascade in the stable window of the band (a data product).

    .venv/bin/python scripts/atlas_cascade.py [--workers 2] [--out PATH]

Writes book/data/atlas_cascade_E5.517.json: the cascade of chapter 09
(``atlas_families.cascade``, 4 generations) started at the IS point (pitchfork) of the
family whose stable window contains E = 5.517, the family of an orbit of the census at
E = 5.45 with T <= 12 (grid 300) followed across 5.33 <= E <= 5.6 in steps of at most 0.03,
as in the chapter. For each generation: its birth energy, its period at birth, and its
family (members' E and tr M, located points, why each end stopped). About 1.5 minutes on two
cores; chapter 09 reads this file and checks it by recomputing the first generations.
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from data_product import arguments, write_json  # noqa: E402

from rotorlib.beyond import atlas  # noqa: E402
from rotorlib.beyond import atlas_families as af  # noqa: E402

E, T_MAX, E_RANGE, STEP, E_WINDOW, GENERATIONS = 5.45, 12.0, (5.33, 5.6), 0.03, 5.517, 4
OUT = ROOT / "book" / "data" / "atlas_cascade_E5.517.json"


def start(executor=None):
    """``(orbit, fam, i_IS)``: the family whose stable window contains ``E_WINDOW`` (the
    first such family of the census, by period), its orbit of the census, and the index
    of the IS point at the lower end of that window (the pitchfork where the cascade
    starts)."""
    a = atlas.census(E, T_MAX, grid=300, executor=executor, name=False)
    fams = af.families(a, E_RANGE, step=STEP, executor=executor)
    o, fam, win = next(
        (o, f, w)
        for o, f in zip(a.orbits, fams)
        for w in f.stable_windows
        if w[0] < E_WINDOW < w[1]
    )
    (i_IS,) = [
        i
        for i, p in enumerate(fam.special_points)
        if p.kind == "IS" and abs(float(p.member.E) - win[0]) < 1e-12
    ]
    return o, fam, i_IS


def record(f) -> dict:
    return {
        "E": [float(x) for x in f.E],
        "trace": [float(x) for x in f.trace],
        "points": [[p.kind, float(p.member.E)] for p in f.special_points],
        "positions": [p.index + 0.5 * (p.kind != "fold") for p in f.special_points],
        "stops": f.stop.split(" / "),
    }


def main(argv=None) -> int:
    args = arguments("atlas_cascade", __doc__, OUT, argv)
    if args is None:
        return 2
    t0 = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        orbit, fam, i_IS = start(pool)
        cas = af.cascade(fam, i_IS, generations=GENERATIONS, executor=pool)
    data = {
        "E": E,
        "t_max": T_MAX,
        "E_range": list(E_RANGE),
        "step": STEP,
        "window_at": E_WINDOW,
        "parent_period": orbit.period,
        "start_point": i_IS,
        "generations": GENERATIONS,
        "precision": "float64 members; bifurcation energies to ~1e-13",
        "generated_by": "scripts/atlas_cascade.py",
        "births": list(cas.births),
        "periods": list(cas.periods),
        "families": [record(f) for f in cas.families[1:]],
    }
    write_json("atlas_cascade", args.out, data, f"{GENERATIONS} generations", t0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
