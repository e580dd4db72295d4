"""``python -m rotorlib family LABEL --E-range A B``: a family followed (:func:`rotorlib.family`).

Prints the members of the branch with energy in ``[A, B]`` and its special points there.
A family born at a pendulum bifurcation (``IS^l_n``, ``PD^r_n``, ...): period, ``tr M``,
stability, and the folds and ``tr M = 4`` (IS) / ``0`` (PD) points located by the engine,
with why the branch stopped. A choreography: period, ``tr DP`` of the reduced map,
``tr M``, stability, the fold, the stability changes and the energies where ``tr M``
touches 4 or 0 without one (:mod:`rotorlib.choreo_family`).

Examples
--------
``python -m rotorlib family IS^l_1 --E-range 3.99 4.1``
``python -m rotorlib family PDr2 --E-range 4 4.01 --digits 20 --json``
``python -m rotorlib family CG --E-range 5 5.4``
``python -m rotorlib family CT --E-range 4.5 5.4 --json``
``python -m rotorlib family CG --E-range 5.3 5.4 --digits 30`` (the fold to 30 digits)
``python -m rotorlib family CR1 --E-range 5.6 5.8 --digits 30`` (a rotating Z3
choreography: :mod:`rotorlib.choreo_z3`, followed live from its seed, ~20 s; its PD and
fold located again in real128)
"""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..branch import Branch


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "family",
        help="a family (IS^l_n, PD^l_n, IS^r_n, PD^r_n; choreographies CG, CT, CZ1, "
        "CZ2, CR1) over an energy range: members, folds, stability changes",
        description="Follow a family of periodic orbits with the continuation engine and "
        "print the members with E in the range and the special points (folds, the "
        "energies where tr M crosses 4 (IS) or 0 (PD), with their kind).",
    )
    p.add_argument(
        "label",
        help="a family born at a pendulum bifurcation (IS^l_2, PDr3, ...), CG (born at "
        "G), CT (its partner beyond the fold), or a Z3 choreography CZ1, CZ2 "
        "(non-rotating), CR1 (rotating)",
    )
    p.add_argument(
        "--E-range", nargs=2, required=True, metavar=("A", "B"), help="energies A < B"
    )
    p.add_argument(
        "--digits",
        type=int,
        default=None,
        help="> 15: each special point located again in the tier of that many digits "
        "(E_str, and its agreement with the float64 location)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def _num(v, name):
    from ..energy import as_float

    return as_float(v, name)


def _table(rec):
    print(f"{'E':>18}  {'period':>18}  {'tr DP':>14}  {'tr M':>14}  stable")
    for m in rec["members"]:
        print(
            f"{m['E']:18.12f}  {m['period']:18.12f}  {m['trace_reduced']:14.8g}  "
            f"{m['trace']:14.8g}  {'yes' if m['stable'] else 'no'}"
        )
    print("special points:")
    if not rec["special_points"]:
        print("  none in the range")
    for p in rec["special_points"]:
        e = p["E_str"] if p["E_str"] != repr(p["E"]) else f"{p['E']:.13f}"
        check = f"  ({p['check']})" if p["check"] else ""
        print(
            f"  E = {e}  T = {p['period']:.10f}  tr DP = {p['trace_reduced']:.10f}  "
            f"{p['kind']}  [{p['branch']}]{check}"
        )


def _print_branch(b: Branch, lo: float, hi: float) -> None:
    """A family born at a pendulum bifurcation: its members and special points."""
    d = max(12, min(30, b.members[0].digits)) if b.members else 12
    print(f"{b.label}: {len(b.members)} members in {lo:g} <= E <= {hi:g}; {b.reason}")
    print(f"{'E':>{d + 4}}  {'period':>{d + 4}}  {'tr M':>16}  stability")
    for m in b.members:
        print(
            f"{float(m.E):{d + 4}.{d}f}  {float(m.period):{d + 4}.{d}f}  "
            f"{float(m.trace):16.10g}  {m.stability}"
        )
    print(
        "special points:" if b.special_points else "special points: none in the range"
    )
    for p in b.special_points:
        what = {"IS": "tr M = 4", "PD": "tr M = 0", "fold": "fold of E"}.get(
            p.kind, p.kind
        )
        E_p = p.member.E_str if p.member.digits > 15 else f"{float(p.member.E):.{d}f}"
        print(
            f"  {p.kind:4s} E = {E_p}  ({what}{'' if p.located else ', not located'})"
        )


def run(args: argparse.Namespace) -> int:
    from ..api import LABELS, family
    from ..branch import Branch
    from ..precision import check_digits

    check_digits(args.digits, "--digits")
    lo, hi = (_num(v, "--E-range") for v in args.E_range)
    choreo = str(args.label).strip().upper() in LABELS["choreography"]
    if choreo and args.digits is not None and args.digits > 60:
        raise ValueError(
            f"--digits for a choreography is at most 60, got {args.digits}"
        )
    res = family(args.label, (lo, hi), digits=args.digits)
    rec = res.to_dict()
    if args.json:
        print(json.dumps(rec, indent=2))
    elif isinstance(res, Branch):
        _print_branch(res, lo, hi)
    else:
        ends = (
            f"exists for {rec['span'][0]:.10f} <= E <= {rec['span'][1]:.10f} "
            f"(continuation ends: {' / '.join(rec['stops'])})"
            if "span" in rec  # a Z3 family
            else f"exists for {rec['E_min']:g} < E <= {rec['E_max']:.12f}"
        )
        print(f"{rec['label']}: {rec['description']}; {ends}")
        _table(rec)
    return 0
