"""CG's stable island on the Poincaré section against the chaotic fraction (a data product).

Writes book/data/choreo_island.json: for each energy of ENERGIES (from 5.2 up to just
below CG's fold E_f ~ 5.3153) the area of CG's island on the section phi1 = 0 of chapter
8 (``rotorlib.beyond.choreo_island.island_area``: FTLE over T = 300 on a grid, the
connected regular set about CG's fixed point) and the fraction of the section both
islands fill; and, at FRACTION_ENERGIES, chapter 8's chaotic fraction of the energy shell
with chapter 8's parameters (``rotorlib.paper.chaos.chaotic_fraction``, N = 400, T = 300,
threshold 0.05, seed 1). A few minutes of one core: python scripts/choreo_island.py
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from rotorlib.beyond.choreo_family import fold_energy
from rotorlib.beyond.choreo_island import island_area
from rotorlib.paper.chaos import chaotic_fraction

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "book" / "data" / "choreo_island.json"
ENERGIES = (5.2, 5.25, 5.28, 5.3, 5.31, 5.314, 5.3152)
FRACTION_ENERGIES = (5.2, 5.25, 5.3, 5.3152, 5.33)
N_GRID = 49


def main():
    t0 = time.perf_counter()
    islands = []
    for E in ENERGIES:
        t = time.perf_counter()
        r = island_area(E, N_GRID)
        rec = {**r.to_dict(), "seconds": round(time.perf_counter() - t, 1)}
        islands.append(rec)
        print(
            f"E = {E}: area {r.area:.4g} +- {r.area_err:.2g}, fraction "
            f"{r.fraction:.4g} +- {r.fraction_err:.2g} ({rec['seconds']} s)",
            flush=True,
        )
    cf = chaotic_fraction(FRACTION_ENERGIES, N=400, T=300.0, threshold=0.05, seed=1)
    data = {
        "E_fold": fold_energy(),
        "islands": islands,
        "chaotic_fraction": {
            "E": list(FRACTION_ENERGIES),
            "fraction": [float(v) for v in cf.fraction],
            "stderr": [float(v) for v in cf.stderr],
            "N": cf.N,
            "T": cf.T,
            "threshold": cf.threshold,
            "seed": 1,
        },
        "seconds": round(time.perf_counter() - t0),
    }
    OUT.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
