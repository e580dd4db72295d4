"""The classical regular fraction mu_reg(E) of the energy shell (a data product).

    .venv/bin/python scripts/regular_fraction.py [--workers 2] [--out PATH]

Writes book/data/regular_fraction.json: at 21 energies from 1 to 8, the fraction of 1000
microcanonical (Liouville) points of the shell whose finite-time Lyapunov exponent over
T = 300 is <= 0.05, with its binomial error and the systematic effect of the threshold
(0.03, 0.08) and of the time (T = 1000 on the first 200 points)
(``rotorlib.beyond.quantum_statistics.regular_fraction``). A few minutes; chapter 11
reads the file and recomputes one energy on fewer points.
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from data_product import arguments, write_json  # noqa: E402

from rotorlib.beyond.quantum_statistics import regular_fraction  # noqa: E402

ENERGIES = (
    1.0,
    1.5,
    2.0,
    2.5,
    3.0,
    3.5,
    3.9,
    4.25,
    4.5,
    4.75,
    5.0,
    5.2,
    5.33,
    5.45,
    5.6,
    5.8,
    6.0,
    6.5,
    7.0,
    7.5,
    8.0,
)
SETTINGS = dict(
    N=1000,
    T=300.0,
    threshold=0.05,
    thresholds=(0.03, 0.08),
    N_check=200,
    T_check=1000.0,
    seed=2026,
)
OUT = ROOT / "book" / "data" / "regular_fraction.json"


def main(argv=None) -> int:
    args = arguments("regular_fraction", __doc__, OUT, argv)
    if args is None:
        return 2
    t0 = time.perf_counter()
    ex = ProcessPoolExecutor(args.workers) if args.workers > 1 else None
    try:
        r = regular_fraction(ENERGIES, executor=ex, **SETTINGS)
    finally:
        if ex is not None:
            ex.shutdown()
    data = {
        "settings": {**SETTINGS, "thresholds": list(SETTINGS["thresholds"])},
        "seconds": round(time.perf_counter() - t0, 1),
        "regular_fraction": r.to_dict(),
    }
    write_json(
        "regular_fraction", args.out, data, f"mu_reg at {len(ENERGIES)} energies", t0
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
