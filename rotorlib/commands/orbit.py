"""``python -m rotorlib orbit LABEL --E V``: one periodic orbit (:func:`rotorlib.orbit`).

Examples
--------
``python -m rotorlib orbit pendulum --E 3.9 --digits 40``
``python -m rotorlib orbit IS^l_2 --E 4 --json``
``python -m rotorlib orbit PDr3 --E 4.0002``
``python -m rotorlib orbit PD^b --E 8.9 --json`` (the breather's period-doubled daughter)
``python -m rotorlib orbit CG --E 3 --digits 30`` (the choreography born at G; ``CT`` its
unstable partner beyond the fold, :mod:`rotorlib.beyond.choreo_family`)
``python -m rotorlib orbit CS --E 5.4`` (the third D6 choreography, :mod:`rotorlib.beyond.choreo_s`)
``python -m rotorlib orbit CR1 --E 5.6 --branch 1`` (a Z3 choreography, the second of its
members at that energy by period; ``CZ1``, ``CZ2`` likewise, :mod:`rotorlib.beyond.choreo_z3`)
"""

from __future__ import annotations

import argparse
from typing import Any

from ..cli import add_digits_argument, emit
from ..core.energy import as_float
from ..core.precision import check_digits


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "orbit",
        help="a periodic orbit: pendulum, breathers R/LG/LD, newborn IS^l_n, PD^l_n, "
        "IS^r_n, PD^r_n, PD^b, choreographies CG, CT, CZ1, CZ2, CR1, CS and those "
        "born from CG at its resonances (CG2/7a ... CG1/8b)",
        description="The periodic orbit LABEL at energy E (rotorlib.orbit): the pendulum or a "
        "breather (closed form, monodromy from the reduced problem), the member with energy "
        "E of the family of periodic orbits born at a pendulum bifurcation (symmetry-reduced shooting + continuation in energy; "
        "paper §6-7), of the breather's period-doubled daughter (PD^b), or of the "
        "choreographies born at G (CG, and CT beyond its fold) or of the Z3 "
        "choreographies CZ1, CZ2, CR1, the third D6 choreography CS, or a choreography "
        "born from CG at its resonance p/q (CG<p>/<q>a: stable next to its birth, b: "
        "unstable; q = 4, 5, 7, 8).",
    )
    p.add_argument(
        "label", help="pendulum, R, LG, LD, IS^l_2, ISl2, PD^r_3, PDr3, PD^b, CG ..."
    )
    p.add_argument("--E", required=True, metavar="V", help="energy (m = g = r = 1)")
    add_digits_argument(
        p,
        "for state, period and trace (real128 by default near E = 4); > 15: the tier that "
        "delivers them, with state0_str, period_str, trace_str; <= 15: plain float64, "
        "which loses log10(1/|E_n - 4|) digits near E = 4",
    )
    p.add_argument(
        "--branch",
        type=int,
        default=0,
        help="choreographies CZ1, CZ2, CR1, CS, CG<p>/<q>a|b: which member at E, "
        "numbered by period from 0 "
        "(a family that folds has several)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def record(label: str, E: Any, digits: int | None = None, branch: int = 0) -> dict:
    """The record the command prints for ``label`` at energy ``E`` (a decimal string keeps
    its digits): :meth:`rotorlib.orbit(label, E, digits=digits).to_dict()
    <rotorlib.orbits.periodic_orbit.PeriodicOrbit.to_dict>`, the choreographies with their
    ``choreography`` field."""
    from ..api import orbit

    as_float(E, "E")
    check_digits(digits, "--digits")
    return orbit(label, E, digits=digits, branch=branch).to_dict()


def run(args: argparse.Namespace) -> int:

    rec = record(args.label, args.E, args.digits, args.branch)
    cols = ["label", "E", "period", "trace", "alpha1_max", "alpha2_max", "precision"]
    if "trace_reduced" in rec:  # a choreography: its reduced map decides the stability
        cols[4:6] = ["trace_reduced", "stable"]
    emit([rec], args.json, cols)
    return 0
