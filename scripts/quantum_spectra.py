"""The quantum spectra too long for a chapter (data products).

    .venv/bin/python scripts/quantum_spectra.py [--hbar 0.03 0.02 0.014 0.01]
        [--workers 2] [--out DIR]
    .venv/bin/python scripts/quantum_spectra.py --legacy     # book/data/quantum_spectra.npz

Writes ``book/data/quantum/spectrum_hbar{h}.npz`` for each hbar: every level of every
symmetry sector below E = 8, with its change when the cut-off is lowered (``errors``),
its residual bound and the sector's cut-off and basis size
(``rotorlib.beyond.quantum.sector_spectrum``; read them with
``rotorlib.beyond.quantum_data.stored_spectrum``). Each sector runs in a fresh worker
process, so that its peak memory is its own; its wall time, CPU time and peak memory go
into ``book/data/quantum/cost.json``. CPU: 93 s at hbar = 0.03 (measured); the cost
grows like hbar^-4 (levels x block size), so ~2 hours at hbar = 0.01 (about 120,000
distinct levels; estimated). ``--legacy`` rewrites the older file
read by chapter 11 (hbar = 0.03 below 8 and hbar = 0.02 below 6.5, levels only).
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "book" / "data" / "quantum"
E_MAX = 8.0
HBARS = (0.03, 0.02, 0.014, 0.01)
LEGACY = ((0.03, 8.0), (0.02, 6.5))


def one(args):
    """One sector in its own process: the spectrum, seconds and peak memory."""
    from rotorlib.beyond import quantum

    hbar, sector = args
    t0, c0 = time.perf_counter(), time.process_time()
    s = quantum.sector_spectrum(hbar, sector, E_MAX)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # MiB (Linux)
    return s, wall, cpu, peak


def legacy(out: Path, workers: int) -> None:
    from rotorlib.beyond import quantum

    data = {}
    with ProcessPoolExecutor(workers) as ex:
        for hbar, E_max in LEGACY:
            s = quantum.spectrum(hbar, E_max, executor=ex)
            tag = f"h{hbar:g}"
            data[f"{tag}_meta"] = np.array([hbar, E_max])
            for x in s.sectors:
                data[f"{tag}_{x.sector}"] = x.levels
                data[f"{tag}_{x.sector}_info"] = np.array(
                    [x.convergence, x.cutoff, x.basis_size, x.plane_waves]
                )
    np.savez_compressed(out, **data)
    print(f"wrote {out}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hbar", type=float, nargs="+", default=list(HBARS))
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--legacy", action="store_true")
    args = ap.parse_args(argv)
    if args.workers < 1:
        print("quantum_spectra: --workers must be >= 1", file=sys.stderr)
        return 2
    if args.legacy:
        legacy(ROOT / "book" / "data" / "quantum_spectra.npz", args.workers)
        return 0
    from rotorlib.beyond import quantum

    args.out.mkdir(parents=True, exist_ok=True)
    cost_path = args.out / "cost.json"
    cost = json.loads(cost_path.read_text()) if cost_path.exists() else {}
    order = sorted(quantum.SECTORS, key=lambda s: -quantum.DIMENSIONS[s])
    for hbar in args.hbar:
        t0 = time.perf_counter()
        with ProcessPoolExecutor(args.workers, max_tasks_per_child=1) as ex:
            runs = dict(zip(order, ex.map(one, [(hbar, s) for s in order])))
        wall = time.perf_counter() - t0
        data = {"hbar": np.array(hbar), "E_max": np.array(E_MAX)}
        rec = {"hbar": hbar, "E_max": E_MAX, "workers": args.workers, "sectors": {}}
        for sec in quantum.SECTORS:
            s, w, c, peak = runs[sec]
            data[f"{sec}_levels"] = s.levels
            data[f"{sec}_errors"] = s.errors
            data[f"{sec}_residuals"] = s.residuals
            data[f"{sec}_info"] = np.array(
                [
                    s.cutoff,
                    quantum.cutoff_step(hbar),
                    s.basis_size,
                    s.plane_waves,
                    s.convergence,
                    s.top_check,
                ]
            )
            rec["sectors"][sec] = {
                "levels": len(s.levels),
                "basis_size": s.basis_size,
                "plane_waves": s.plane_waves,
                "wall_seconds": round(w, 1),
                "cpu_seconds": round(c, 1),
                "peak_MiB": round(peak),
                "convergence": s.convergence,
                "method": s.method,
            }
            print(
                f"hbar = {hbar:g} {sec}: {len(s.levels)} levels, block {s.basis_size},"
                f" {w:.0f} s wall, {c:.0f} s CPU, {peak:.0f} MiB, "
                f"convergence {s.convergence:.1e}",
                flush=True,
            )
        rec["wall_seconds"] = round(wall, 1)
        rec["cpu_seconds"] = round(sum(r[2] for r in runs.values()), 1)
        rec["levels_with_multiplicity"] = sum(
            len(runs[s][0].levels) * quantum.DIMENSIONS[s] for s in quantum.SECTORS
        )
        path = args.out / f"spectrum_hbar{hbar:g}.npz"
        np.savez_compressed(path, **data)
        cost[f"{hbar:g}"] = rec
        cost_path.write_text(json.dumps(cost, indent=1, sort_keys=True) + "\n")
        print(f"wrote {path} ({path.stat().st_size / 1e6:.2f} MB), {wall:.0f} s wall")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
