"""``python -m rotorlib bifurcations``: stability transitions of pendula (paper §5, Tables I and II).

Examples
--------
``python -m rotorlib bifurcations --phase both --n-max 20 --json``
``python -m rotorlib bifurcations --phase lib --kind PD --n-max 6``
``python -m rotorlib bifurcations --family breather --json``
"""

from __future__ import annotations

import argparse
from typing import Any

from ..cli import add_digits_argument, emit

#: Largest --n-max accepted on the command line (float64 reaches n ~ 125 in every sequence).
N_MAX_LIMIT = 200


def register(sub: Any) -> None:
    p = sub.add_parser(
        "bifurcations",
        help="stability transitions (IS/PD bifurcations) of pendula or breathers",
        description="Energies and periods of the stability transitions of librational and "
        "rotational pendula (roots of the transverse discriminant), or of the "
        "isosceles breathers (--family breather).",
    )
    p.add_argument("--phase", default="both", help="lib, rot or both (default both)")
    p.add_argument(
        "--n-max",
        dest="n_max",
        type=int,
        default=6,
        help=f"largest index n in each sequence (1..{N_MAX_LIMIT}; default 6)",
    )
    p.add_argument("--kind", default=None, help="IS or PD (default both)")
    p.add_argument("--family", default="pendulum", choices=["pendulum", "breather"])
    add_digits_argument(
        p,
        "float64 gives ~13 in log|E-4|; > 15 re-locates every root with heyoka "
        "real128 / multiprecision",
    )
    p.add_argument("--json", action="store_true", help="print a JSON list of records")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.family == "breather":
        from ..paper.breathers import breather_transitions

        emit(
            [t.to_dict() for t in breather_transitions(digits=args.digits)],
            args.json,
            ["kind", "E", "period", "transition"],
            one=False,
        )
        return 0
    from ..paper.bifurcations import transition, transitions

    if args.phase not in ("lib", "rot", "both"):
        raise ValueError(f"--phase must be lib, rot or both, got {args.phase!r}")
    if not 1 <= args.n_max <= N_MAX_LIMIT:
        raise ValueError(
            f"--n-max must be between 1 and {N_MAX_LIMIT}, got {args.n_max}"
        )
    kinds = ("IS", "PD") if args.kind is None else (args.kind.upper(),)
    if not set(kinds) <= {"IS", "PD"}:
        raise ValueError(f"--kind must be IS or PD, got {args.kind!r}")
    trs = transitions(phase=args.phase, n_max=args.n_max, kinds=kinds)
    if args.digits is not None and args.digits > 15:
        trs = [transition(t.label, digits=args.digits) for t in trs]
    emit(
        [t.to_dict() for t in trs],
        args.json,
        ["label", "log_abs_dE", "E", "period", "transition", "precision"],
        one=False,  # JSON: a list, even for one record
    )
    return 0
