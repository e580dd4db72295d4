"""``rotorlib catalogue``: the stored catalogue of periodic-orbit families.

Examples
--------
``rotorlib catalogue --E 5.45 --t-max 8 --json``: every family with a member at E = 5.45
(period <= 8), each of its members there (one per branch: two or more beside a fold)
solved to ``--digits`` from the interpolant of its stored members; a ``--t-max`` above
the census's period bound at that energy is refused (the list would be incomplete).
``rotorlib catalogue --family F001 --json``: one family's record.
``rotorlib catalogue --verify F001``: re-solve its stored members and compare.
"""

from __future__ import annotations

import argparse

from ..cli import add_digits_argument, emit
from ..core.energy import as_float

COLUMNS = ["id", "name", "E", "period", "trace", "stability", "symmetry"]


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "catalogue",
        help="the catalogue of symmetric periodic-orbit families",
        description="The stored catalogue of symmetric periodic-orbit families "
        "(rotorlib/data/catalogue): the families at an energy, one family, or a "
        "re-check of a family's stored members.",
    )
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--E", metavar="V", help="the families with a member at E = V")
    g.add_argument("--family", metavar="ID", help="one family's record (e.g. F001)")
    g.add_argument("--verify", metavar="ID", help="re-solve a family's stored members")
    p.add_argument(
        "--t-max",
        metavar="T",
        help="with --E: period <= T (at most the census's period bound at E, where "
        "the catalogue is complete)",
    )
    p.add_argument("--stable", action="store_true", help="with --E: stable there")
    p.add_argument("--path", default=None, help="another catalogue directory")
    add_digits_argument(p, "with --E: the member is solved in the tier that gives them")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..beyond.catalogue import catalogue, load, verify

    if args.verify:
        rec = verify(args.verify, args.path)
        if args.json:
            emit([rec], True, [])
        else:
            ok = "ok" if rec["ok"] else "FAILED"
            print(
                f"{rec['id']}: {rec['members']} members re-solved: {ok} (period "
                f"{rec['period']:.1e}, state0 {rec['state0']:.1e}, tr M "
                f"{rec['trace']:.1e} relative; closure {rec['closure']:.1e}; action "
                f"{rec['action']:.1e}; Maslov indices differing: {rec['maslov']})"
            )
        return 0 if rec["ok"] else 1
    if args.family:
        rec = load(args.path).family(args.family).to_dict()
        if args.json:
            emit([rec], True, [])
        else:
            print(
                f"{rec['id']} {rec['name'] or '-'}: E in {rec['E_range']}, "
                f"{len(rec['members'])} stored members, ends "
                + "; ".join(e["kind"] for e in rec["ends"])
            )
        return 0
    E = as_float(args.E, "--E")
    t_max = None if args.t_max is None else as_float(args.t_max, "--t-max")
    load(args.path).check_scope(E, t_max)
    recs = []
    for f in catalogue(E=E, path=args.path):
        if t_max is not None and not f.may_reach(t_max):
            continue  # no member anywhere below the bound: not solved
        try:
            ms = f.members_at(args.E, args.digits)
        except ValueError as exc:  # no shot from the interpolated members converged
            recs.append({"id": f.id, "name": f.name, "error": str(exc)})
            continue
        sy = f.symmetry
        kind = (
            "choreography"
            if sy["choreography"]
            else ("rotating" if sy["rotating"] else "librating")
        )
        for m in ms:
            if t_max is not None and float(m.period) > t_max:
                continue
            if args.stable and m.stability != "stable":
                continue
            recs.append({"id": f.id, "name": f.name, "symmetry": kind, **m.to_dict()})
    emit(recs, args.json, COLUMNS, one=False)
    return 0
