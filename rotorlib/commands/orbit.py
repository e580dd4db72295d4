"""``python -m rotorlib orbit LABEL --E V``: a periodic orbit born at a pendulum bifurcation.

Examples
--------
``python -m rotorlib orbit IS^l_2 --E 4 --json``
``python -m rotorlib orbit PDr3 --E 4.0002``
``python -m rotorlib orbit PD^b --E 8.9 --json`` (the breather's period-doubled daughter)
"""
from __future__ import annotations

import re

from ..cli import emit
from ..energy import as_float

_BREATHER = re.compile(r"^PD\^?b$", re.IGNORECASE)


def register(sub):
    p = sub.add_parser("orbit", help="a newborn periodic orbit (families IS^l_n, PD^l_n, IS^r_n, PD^r_n, PD^b)",
                       description="Find the member with energy E of the family of periodic orbits born at a "
                                   "pendulum bifurcation (symmetry-reduced shooting + continuation in energy; "
                                   "paper §6-7), or of the breather's period-doubled daughter (PD^b).")
    p.add_argument("label", help="family label: IS^l_2, ISl2, PD^r_3, PDr3, PD^b ...")
    p.add_argument("--E", required=True, metavar="V", help="energy (m = g = r = 1)")
    p.add_argument("--digits", type=int, default=None,
                   help="<= 15: float64 search; 16..31: real128 (default: real128 polish near E = 4)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args):
    E = as_float(args.E, "E")
    if args.digits is not None and not 1 <= args.digits <= 31:
        raise ValueError(f"--digits must be from 1 to 31, got {args.digits}")
    if _BREATHER.match(args.label.strip()):
        try:
            from ..breathers import breather_daughter
        except ImportError:
            raise ValueError("the breather daughter (PD^b) needs rotorlib.breathers, which is not available") from None
        orbit = breather_daughter(E) if args.digits is None else breather_daughter(E, digits=args.digits)
        rec = orbit.to_record()
    else:
        from ..newborn import newborn_orbit

        prec = None if args.digits is None else ("float64" if args.digits <= 15 else "real128")
        orbit = newborn_orbit(args.label, args.E if prec != "float64" else E, precision=prec)
        rec = orbit.to_record()
        for key in ("state0_str", "period_str", "trace_str", "start", "section", "condition", "t1"):
            if key in orbit.extra:
                rec[key] = orbit.extra[key]
    emit([rec], args.json, ["label", "E", "period", "trace", "alpha1_max", "alpha2_max", "precision"])
    return 0
