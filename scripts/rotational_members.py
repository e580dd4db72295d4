"""The rotational newborn members of the scaling constants alpha^r, beta^r (a data product).

    .venv/bin/python scripts/rotational_members.py [--workers 2] [--out PATH]

Writes book/data/rotational_members.json: each member of a rotational newborn family
(IS^r_3..8, PD^r_3..8) that the paper's ratios alpha^r(n), beta^r(n) need for n = 3..6
(``rotorlib.laws.rotational_members``: the family followed from its birth in the ``K``
chart to the bifurcation energy of the similar member two steps below it), with its tier,
``E - 4``, amplitudes, trace and closure; or, for a family that ends below the energy
asked for, why. About 2 minutes of CPU (one minute on two cores): too long to run twice in
every CI run (book build and nbval), so chapter 06 reads this file, forms the ratios from
it, and recomputes some of the members itself to check it.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from rotorlib import laws  # noqa: E402

SPECS = [(k, n) for k in ("IS", "PD") for n in (3, 4, 5, 6)]
OUT = ROOT / "book" / "data" / "rotational_members.json"


def as_record(label, dE, m) -> dict:
    """A member (or the reason it does not exist) as a JSON record."""
    if isinstance(m, str):
        return {"label": label, "dE_target": dE, "not_reached": m}
    d = asdict(m)
    d["state0"] = [float(v) for v in m.state0]
    return {"label": label, "dE_target": dE, "member": d}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    if args.workers < 1:
        print("rotational_members: --workers must be >= 1", file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        found = laws.rotational_members(SPECS, executor=pool)
    data = {
        "specs": [list(s) for s in SPECS],
        "precision": "members located to ~1e-15 (float64) or ~1e-30 (real128) in E - 4; "
        "a1max, a2'min to ~1e-8 (float64 members) or ~1e-15 (real128) relative; tr M "
        "to ~5e-4 relative at the deepest members (rotorlib.laws.rotational_member)",
        "generated_by": "scripts/rotational_members.py",
        "members": [as_record(lab, dE, m) for (lab, dE), m in found.items()],
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(data, indent=1) + "\n")
    print(
        f"rotational_members: {len(found)} members written to {args.out} "
        f"in {time.perf_counter() - t0:.0f} s"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
