"""The catalogue's interpolant between stored members against 30-digit re-solves
(outside CI; ~5 minutes).

``python scripts/catalogue_midpoints.py [--path DIR] [--stride 8]``
``  [--out book/data/catalogue_midpoints.json]``

At the midpoint of every ``stride``-th pair of neighbouring stored members on each piece
(in ``E`` on the pieces parametrised by ``E``, in ``u`` on those parametrised by ``u``),
the interpolant's period and ``tr M`` against the member re-solved there at 30 digits
(:func:`rotorlib.beyond.catalogue_checks.midpoints`: a float64 shot is no reference for
``tr M``, good to ~1e-11 tr M^2 only). Writes, per class (``far``, ``near``: within 0.2
of E = 4 or 4.5 or 0.01 of a fold, ``u``: the pieces through folds;
:func:`rotorlib.beyond.catalogue_checks.midpoint_summary`), the number of midpoints, the
shots that failed, how many exceed 1e-8 in each quantity, and the largest errors and
where they are.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main(argv=None) -> int:
    sys.path.insert(0, str(ROOT))
    from rotorlib.beyond.catalogue_checks import midpoint_summary, midpoints
    from rotorlib.beyond.catalogue_tasks import write_json

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--path", default=None)
    p.add_argument("--stride", type=int, default=8)
    p.add_argument("--out", default=None)
    a = p.parse_args(argv)
    if a.stride < 1:
        p.error("--stride must be >= 1")
    rows = midpoints(a.path, a.stride, digits=30)
    out = {"stride": a.stride, **midpoint_summary(rows)}
    print(json.dumps(out, indent=1))
    if a.out:  # as the build writes its files (atomically)
        write_json(Path(a.out), out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
