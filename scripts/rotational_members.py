"""The rotational newborn members of the scaling constants alpha^r, beta^r (a data product).

    .venv/bin/python scripts/rotational_members.py [--workers 2] [--out PATH]

Writes book/data/rotational_members.json: each member of a rotational newborn family
(IS^r_3..8, PD^r_3..8) that the paper's ratios alpha^r(n), beta^r(n) need for n = 3..6
(``rotorlib.paper.newborn_laws.rotational_members``: the family followed from its birth in the ``K``
chart to the bifurcation energy of the similar member two steps below it), as
``rotorlib.paper.newborn_laws.rotational_record`` (the member's JSON with ``E - 4``, its amplitudes
``a1_max``, ``a2dot_min`` and closure); or, for a family that ends below the energy
asked for, why. About 2 minutes of CPU (one minute on two cores): too long to run twice in
every CI run (book build and nbval), so chapter 06 reads this file, forms the ratios from
it, and recomputes some of the members itself to check it.
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from data_product import arguments, write_json  # noqa: E402

from rotorlib.paper import newborn_laws as laws  # noqa: E402

SPECS = [(k, n) for k in ("IS", "PD") for n in (3, 4, 5, 6)]
OUT = ROOT / "book" / "data" / "rotational_members.json"


def as_record(label, dE, m) -> dict:
    """A member (``rotorlib.paper.newborn_laws.rotational_record``), or the reason it does not exist."""
    key = "not_reached" if isinstance(m, str) else "member"
    return {"label": label, "dE_target": dE, key: m}


def main(argv=None) -> int:
    args = arguments("rotational_members", __doc__, OUT, argv)
    if args is None:
        return 2
    t0 = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        found = laws.rotational_members(SPECS, executor=pool)
    data = {
        "specs": [list(s) for s in SPECS],
        "precision": "members located to ~1e-15 (float64) or ~1e-30 (real128) in E - 4; "
        "a1max, a2'min to ~1e-8 (float64 members) or ~1e-15 (real128) relative; tr M "
        "to ~5e-4 relative at the deepest members (rotorlib.paper.newborn_laws.rotational_member)",
        "generated_by": "scripts/rotational_members.py",
        "members": [as_record(lab, dE, m) for (lab, dE), m in found.items()],
    }
    write_json("rotational_members", args.out, data, f"{len(found)} members", t0)
    return 0


if __name__ == "__main__":
    sys.exit(main())
