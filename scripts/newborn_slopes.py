"""The slope-theorem fits of fourteen newborn families (a data product).

    .venv/bin/python scripts/newborn_slopes.py [--workers 2] [--out PATH]

Writes book/data/newborn_slopes.json: for IS^l_1..4, IS^r_1..4 and PD^r_1..6, the fork fit
of the newborn family at birth (``rotorlib.paper.newborn_laws.newborn_slope``: five members at
``E_n + r |E_n - 4|``, ``r = 2e-4 ... 4e-3``) with the pendulum's slope by two routes. About
a minute of CPU, the largest part of chapter 06's run time: chapter 06 reads this file and
recomputes four of the fits itself to check it.
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from data_product import arguments, write_json  # noqa: E402

from rotorlib.core.parallel import pmap  # noqa: E402
from rotorlib.paper import newborn_laws as laws  # noqa: E402

LABELS = [f"IS^{p}_{n}" for p in "lr" for n in range(1, 5)]
LABELS += [f"PD^r_{n}" for n in range(1, 7)]
OUT = ROOT / "book" / "data" / "newborn_slopes.json"


def main(argv=None) -> int:
    args = arguments("newborn_slopes", __doc__, OUT, argv)
    if args is None:
        return 2
    t0 = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        fits = pmap(laws.newborn_slope, LABELS, executor=pool)
    records = []
    for s in fits:
        d = asdict(s)
        for k in ("E", "trace", "u"):
            d[k] = [float(v) for v in d[k]]
        records.append(d)
    data = {
        "precision": "pendulum slope: two routes agree to < 1e-9 relative; newborn "
        "slope: fork fit of members at the tier's precision (rotorlib.paper.newborn_laws.newborn_slope)",
        "generated_by": "scripts/newborn_slopes.py",
        "slopes": records,
    }
    write_json("newborn_slopes", args.out, data, f"{len(records)} fits", t0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
