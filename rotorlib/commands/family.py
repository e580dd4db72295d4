"""``python -m rotorlib family LABEL --E-range A B``: a family followed (:func:`rotorlib.family`).

Prints the members of the branch with energy in ``[A, B]`` and its special points there,
one path for every family (a :class:`~rotorlib.orbits.family.Branch`). A family born at a pendulum bifurcation (``IS^l_n``, ``PD^r_n``, ...): period, ``tr M``,
stability, and the folds and ``tr M = 4`` (IS) / ``0`` (PD) points located by the engine,
with why the branch stopped. A choreography: period, ``tr DP`` of the reduced map,
``tr M``, stability, the fold, the stability changes and the energies where ``tr M``
touches 4 or 0 without one (:mod:`rotorlib.beyond.choreo_family`).

Examples
--------
``python -m rotorlib family IS^l_1 --E-range 3.99 4.1``
``python -m rotorlib family PDr2 --E-range 4 4.01 --digits 20 --json``
``python -m rotorlib family CG --E-range 5 5.4``
``python -m rotorlib family CT --E-range 4.5 5.4 --json``
``python -m rotorlib family CG --E-range 5.3 5.4 --digits 30`` (the fold to 30 digits)
``python -m rotorlib family CR1 --E-range 5.6 5.8 --digits 30`` (a rotating Z3
choreography: :mod:`rotorlib.beyond.choreo_z3`, followed live from its seed, ~20 s; its PD and
fold located again in real128)
"""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING, cast

from ..cli import add_digits_argument

if TYPE_CHECKING:
    from ..orbits.family import Branch, Member


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "family",
        help="a family (IS^l_n, PD^l_n, IS^r_n, PD^r_n; choreographies CG, CT, CZ1, "
        "CZ2, CR1, CS, CG2/7a ... CG1/8b) over an energy range: members, folds, "
        "stability changes",
        description="Follow a family of periodic orbits with the continuation engine and "
        "print the members with E in the range and the special points (folds, the "
        "energies where tr M crosses 4 (IS) or 0 (PD), with their kind).",
    )
    p.add_argument(
        "label",
        help="a family born at a pendulum bifurcation (IS^l_2, PDr3, ...), CG (born at "
        "G), CT (its partner beyond the fold), a Z3 choreography CZ1, CZ2 "
        "(non-rotating), CR1 (rotating), CS (the third D6 choreography), or a "
        "choreography born from CG at its resonance p/q: CG<p>/<q>a (stable next to "
        "its birth) or b, q = 4, 5, 7, 8",
    )
    p.add_argument(
        "--E-range", nargs=2, required=True, metavar=("A", "B"), help="energies A < B"
    )
    add_digits_argument(
        p,
        "> 15: each special point located again in that tier (E_str, and its "
        "agreement with the float64 location)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def _print_branch(b: Branch, lo: float, hi: float) -> None:
    """Any family: its members and special points; a choreography's
    (:class:`~rotorlib.beyond.choreo_family.ChoreoMember`) also ``tr DP``, and each
    point's period, description, branch and how it was located."""
    from ..beyond.choreo_family import ChoreoMember

    d = max(12, min(30, b.members[0].digits)) if b.members else 12
    reduced = any(  # a choreography: a column of tr DP
        isinstance(m, ChoreoMember)
        for m in (*b.members, *(p.member for p in b.special_points))
    )
    print(f"{b.label}: {len(b.members)} members in {lo:g} <= E <= {hi:g}; {b.reason}")
    print(
        f"{'E':>{d + 4}}  {'period':>{d + 4}}  "
        + (f"{'tr DP':>16}  " if reduced else "")
        + f"{'tr M':>16}  stability"
    )
    for m in b.members:
        trp = (
            f"{float(m.trace_reduced):16.10g}  " if isinstance(m, ChoreoMember) else ""
        )
        print(
            f"{float(m.E):{d + 4}.{d}f}  {float(m.period):{d + 4}.{d}f}  {trp}"
            f"{float(m.trace):16.10g}  {m.stability}"
        )
    print(
        "special points:" if b.special_points else "special points: none in the range"
    )
    for p in b.special_points:
        m = cast("Member", p.member)  # a branch's points have their member
        what = f"({_WHAT.get(p.kind, p.kind)}{'' if p.located else ', not located'})"
        if isinstance(m, ChoreoMember):  # the best location, and how it was found
            what = (
                f"T = {float(m.period):.10f}  tr DP = {float(m.trace_reduced):.10f}  "
                f"({p.description})  [{p.branch}]  {p.located}"
            )
        E_p = m.E_str if m.precision != "float64" else f"{float(m.E):.{d}f}"
        print(f"  {p.kind:4s} E = {E_p}  {what}")


_WHAT = {"IS": "tr M = 4", "PD": "tr M = 0", "fold": "fold of E"}


def run(args: argparse.Namespace) -> int:
    from ..api import LABELS, family
    from ..core.energy import as_float

    lo, hi = (as_float(v, "--E-range") for v in args.E_range)
    if (args.digits or 0) > 60 and args.label.strip().upper() in LABELS["choreography"]:
        raise ValueError(
            f"--digits for a choreography is at most 60, got {args.digits}"
        )
    b = family(args.label, (lo, hi), digits=args.digits)
    if args.json:
        print(json.dumps(b.to_dict(), indent=2))
    else:
        _print_branch(b, lo, hi)
    return 0
