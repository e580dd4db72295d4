"""The census of symmetric periodic orbits with T <= 8 across 3.9 <= E <= 6.5 (a data product).

    .venv/bin/python scripts/atlas_sweep.py [--workers 2] [--out PATH]

Writes book/data/atlas_sweep_T8.json: for each of the 14 energies E = 3.9, 4.1, ..., 6.5 of
chapter 09's sweep, the census with T <= 8 (``atlas.census``, grid 150): every orbit's period,
trace, stability, fixed sets and start state. About 25 s on two cores; chapter 09 reads this
file and checks it by recomputing the censuses at three of its energies.
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

E_SWEEP = [round(3.9 + 0.2 * k, 1) for k in range(14)]  # 3.9, 4.1, ..., 6.5
T_MAX, GRID = 8.0, 150
OUT = ROOT / "book" / "data" / "atlas_sweep_T8.json"


def main(argv=None) -> int:
    args = arguments("atlas_sweep", __doc__, OUT, argv)
    if args is None:
        return 2
    t0 = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        sweep = [
            atlas.census(E, T_MAX, grid=GRID, executor=pool, name=False)
            for E in E_SWEEP
        ]
    data = {
        "t_max": T_MAX,
        "grid": GRID,
        "precision": "float64 (residual ~1e-13; tr M to ~1e-15 |tr M|)",
        "generated_by": "scripts/atlas_sweep.py",
        "censuses": [
            {
                "E": a.E,
                "orbits": [
                    {
                        "period": o.period,
                        "trace": o.trace,
                        "stable": o.stable,
                        "fixed_sets": list(o.extra["fixed_sets"]),
                        "state0_str": list(o.state0_str),
                    }
                    for o in a.orbits
                ],
            }
            for a in sweep
        ],
    }
    write_json("atlas_sweep", args.out, data, f"{len(sweep)} censuses", t0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
