"""The quantum spectra too long for a chapter (a data product).

    .venv/bin/python scripts/quantum_spectra.py [--workers 2] [--out PATH]

Writes book/data/quantum_spectra.npz: every level of every symmetry sector at
hbar = 0.03 below E = 8 (about 20,000 levels with multiplicity) and at hbar = 0.02 below
E = 6.5 (about 30,000), with each sector's convergence estimate and cut-off
(``rotorlib.beyond.quantum.spectrum``). Several minutes: chapter 11 reads the file and checks it
against levels it recomputes itself (the A1 sector at hbar = 0.03 below E = 4).
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from data_product import arguments  # noqa: E402

from rotorlib.beyond import quantum  # noqa: E402

RUNS = ((0.03, 8.0), (0.02, 6.5))
OUT = ROOT / "book" / "data" / "quantum_spectra.npz"


def main(argv=None) -> int:
    args = arguments("quantum_spectra", __doc__, OUT, argv)
    if args is None:
        return 2
    data = {}
    ex = ProcessPoolExecutor(args.workers) if args.workers > 1 else None
    try:
        for hbar, E_max in RUNS:
            t0 = time.perf_counter()
            s = quantum.spectrum(hbar, E_max, executor=ex)
            tag = f"h{hbar:g}"
            data[f"{tag}_meta"] = np.array([hbar, E_max])
            for x in s.sectors:
                data[f"{tag}_{x.sector}"] = x.levels
                data[f"{tag}_{x.sector}_info"] = np.array(
                    [x.convergence, x.cutoff, x.basis_size, x.plane_waves]
                )
            print(
                f"hbar = {hbar:g}, E <= {E_max:g}: {len(s.levels)} levels, "
                f"convergence {s.convergence:.1e}, {time.perf_counter() - t0:.0f} s",
                flush=True,
            )
    finally:
        if ex is not None:
            ex.shutdown()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(args.out, **data)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
