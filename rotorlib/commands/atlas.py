"""``python -m rotorlib atlas --E V [V ...] --t-max T``: every symmetric periodic orbit.

Examples
--------
``python -m rotorlib atlas --E 4.3 --t-max 8``
``python -m rotorlib atlas --E 5.45 --t-max 16 --workers 2 --json``
``python -m rotorlib atlas --E 5.4 5.5 --t-max 12 --scheduler tcp://127.0.0.1:8786``
"""

from __future__ import annotations

import argparse
import sys

from ..cli import add_digits_argument, add_executor_arguments, emit
from ..core.energy import as_float

COLUMNS = [
    "E",
    "label",
    "family",
    "period",
    "trace",
    "stability",
    "fixed_sets",
    "state0",
]


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "atlas",
        help="every symmetric periodic orbit with period <= T_max at energy E",
        description="The census of symmetric periodic orbits (symmetry-line grid search on "
        "the fixed sets of the reversing symmetries, refined with the shooting engine, "
        "deduplicated up to the symmetry group, named after the known families).",
    )
    p.add_argument("--E", required=True, nargs="+", metavar="V", help="energies (> 0)")
    p.add_argument("--t-max", required=True, metavar="T", help="largest period (> 0)")
    p.add_argument(
        "--grid",
        type=int,
        default=300,
        help="start points per fixed-set class before bisection (default 300)",
    )
    add_digits_argument(p, "re-solve every orbit in the tier that delivers them")
    p.add_argument("--json", action="store_true", help="print a JSON list of records")
    add_executor_arguments(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..api import name_choreography
    from ..beyond.atlas import census, check_census
    from ..core.parallel import executor_for

    energies = [as_float(v, "E") for v in args.E]
    t_max = as_float(args.t_max, "--t-max")
    check_census(energies, t_max, args.grid)  # refuses before any work is done
    with executor_for(args.workers, args.scheduler) as ex:
        recs: list = [  # one per orbit, in order of energy and period
            o.to_dict()
            for E in energies
            for o in census(
                E,
                t_max,
                args.grid,
                executor=ex,
                progress=sys.stderr.isatty() and not args.json,
                digits=args.digits,
                name_choreography=name_choreography,  # CG, CT, CZ1, ... (the registry)
            ).orbits
        ]
    if args.json:
        emit(recs if len(recs) != 1 else [recs], True, COLUMNS)
    else:  # one line per orbit
        emit(
            [
                dict(
                    {
                        k: v
                        for k, v in r.items()
                        if k not in ("period_str", "trace_str")
                    },
                    fixed_sets=" / ".join(r["fixed_sets"]),
                    state0=" ".join(r.get("state0_str") or map(repr, r["state0"])),
                    period=f"{r['period']:.10g}",
                    trace=f"{r['trace']:.8g}",
                )
                for r in recs
            ],
            False,
            COLUMNS,
        )
    return 0
