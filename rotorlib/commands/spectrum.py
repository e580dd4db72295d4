"""``python -m rotorlib spectrum --hbar H --sector S --E-max X``: the quantum levels.

Examples
--------
``python -m rotorlib spectrum --hbar 0.1 --sector A1 --E-max 2``
``python -m rotorlib spectrum --hbar 0.5 --sector all --E-max 6.5 --json``
"""

from __future__ import annotations

import argparse
import math

from ..cli import add_executor_arguments, emit
from ..core.energy import as_float

_DESCRIPTION = """\
Levels of the quantum relative motion of the three rotors (the three-junction flux qubit with
equal junctions at zero flux) below E_max, in units g = m r^2 = 1 with a dimensionless hbar
(hbar^2 = 8 E_C / 3 E_J for the qubit). The sector is an irreducible representation of the
symmetry group S3 x Z2: A1 A2 B1 B2 (one-dimensional) or E1 E2 (two-dimensional: each level
is doubly degenerate), or `all` for the whole spectrum with multiplicities. The total angular
momentum is L = 0 mod 3 (a periodic relative wave function). Each level is printed with the
decimals its convergence estimate supports: the largest change of a level when the
plane-wave cut-off is lowered by 0.5 + 6 hbar."""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "spectrum",
        help="quantum levels of the relative motion (flux qubit), by symmetry sector",
        description=_DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--hbar", required=True, metavar="H", help="Planck constant (> 0)")
    p.add_argument(
        "--sector",
        required=True,
        metavar="S",
        help="A1, A2, B1, B2, E1, E2 or all",
    )
    p.add_argument(
        "--E-max", required=True, dest="E_max", metavar="X", help="highest energy"
    )
    p.add_argument(
        "--json",
        action="store_true",
        help="print one JSON object (levels, sectors, convergence, basis sizes)",
    )
    add_executor_arguments(p)
    p.set_defaults(func=run)


def decimals(convergence: float) -> int:
    """Decimals supported by a convergence estimate (at most 12: float64 eigenvalues
    carry ~1e-13 absolute error at these energies)."""
    if not math.isfinite(convergence):
        return 3
    return max(1, min(12, int(math.floor(-math.log10(max(convergence, 1e-13)))) - 1))


def run(args: argparse.Namespace) -> int:
    from ..beyond import quantum
    from ..core.parallel import executor_for

    hbar = as_float(args.hbar, "--hbar")
    E_max = as_float(args.E_max, "--E-max")
    if hbar <= 0:
        raise ValueError(f"--hbar must be > 0, got {args.hbar}")
    if E_max <= 0:
        raise ValueError(f"--E-max must be > 0, got {args.E_max}")
    if args.sector != "all" and args.sector not in quantum.SECTORS:
        raise ValueError(
            f"unknown sector {args.sector!r}: choose one of "
            f"{', '.join(quantum.SECTORS)} or all"
        )
    need = quantum.memory_estimate(hbar, E_max)
    have = quantum.available_memory()
    if need > have:
        K = quantum.default_cutoff(hbar, E_max) + quantum.cutoff_step(hbar)
        raise ValueError(
            f"the basis would not fit in memory: {quantum.basis_size(hbar, K):,} plane "
            f"waves, ~{need / 2**30:.3g} GiB needed, {have / 2**30:.3g} GiB available"
        )
    with executor_for(args.workers, args.scheduler) as ex:
        s = quantum.spectrum(hbar, E_max, args.sector, executor=ex, progress=True)
    d = decimals(s.convergence)
    rows = sorted(
        (float(E), x.sector, x.multiplicity) for x in s.sectors for E in x.levels
    )
    n_all = sum(m for _, _, m in rows)
    if args.json:
        record = {
            "hbar": hbar,
            "E_max": E_max,
            "sector": args.sector,
            "count": n_all,
            "levels": [round(E, d) for E, _, _ in rows],
            "sectors": [sec for _, sec, _ in rows],
            "multiplicities": [m for _, _, m in rows],
            "convergence": s.convergence,
            "decimals": d,
            "basis": {
                x.sector: {
                    "size": x.basis_size,
                    "plane_waves": x.plane_waves,
                    "cutoff": x.cutoff,
                    "convergence": x.convergence,
                    "method": x.method,
                }
                for x in s.sectors
            },
            "precision": "float64",
        }
        emit([record], True, [])
        return 0
    recs = [
        {"n": i + 1, "E": f"{E:.{d}f}", "sector": sec, "multiplicity": m}
        for i, (E, sec, m) in enumerate(rows)
    ]
    if recs:
        emit(recs, False, ["n", "E", "sector", "multiplicity"])
    print(
        f"# {len(rows)} distinct levels ({n_all} with multiplicity) below {E_max:g} "
        f"at hbar = {hbar:g}; convergence {s.convergence:.1e} "
        f"(largest change when the cut-off is lowered), float64"
    )
    return 0
