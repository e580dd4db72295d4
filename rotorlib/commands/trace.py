"""``python -m rotorlib trace``: tr M of pendula and breathers.

Examples
--------
``python -m rotorlib trace pendulum --E 1 3.9 5 --json``
``python -m rotorlib trace pendulum --log-dE -60 --phase rot --digits 30``
``python -m rotorlib trace breather --E 9 20`` (rotational breather R)
``python -m rotorlib trace breather --E 4.3 --family LD``
"""
from __future__ import annotations

import math

from ..cli import emit
from ..energy import as_float
from ..monodromy import monodromy
from ..orbits import breather, pendulum


def register(sub):
    p = sub.add_parser("trace", help="trace of the monodromy matrix of pendula or breathers",
                       description="tr M (full 4x4) of pendula or isosceles breathers. For breathers, "
                                   "--log-dE is log|E - 4.5| (distance to the breather separatrix).")
    p.add_argument("family", choices=["pendulum", "breather"])
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--E", nargs="+", metavar="V", help="energies (m = g = r = 1)")
    g.add_argument("--log-dE", nargs="+", metavar="V", dest="log_dE",
                   help="natural log of the distance to the separatrix (needs --phase or --family)")
    p.add_argument("--phase", choices=["lib", "rot"], help="libration or rotation")
    p.add_argument("--family", dest="breather_family", choices=["LG", "LD", "R"],
                   help="breather family (default LG below 4.5, R above)")
    p.add_argument("--digits", type=int, default=None,
                   help="significant digits (default float64; > 15 uses heyoka real128/multiprecision)")
    p.add_argument("--backend", choices=["heyoka", "scipy", "mpmath"], default=None)
    p.add_argument("--json", action="store_true", help="print JSON (one object per energy, a list when several)")
    p.set_defaults(func=run)


def _record(M, digits):
    ext = M.precision != "float64"
    en = M.energy
    if M.family == "pendulum":
        rec = {"family": "pendulum", "phase": en.phase, "E": en.decimal_E(max(17, digits or 0)),
               "log_abs_dE": repr(en.log_abs_dE) if en.given[0] == "E" else en.given[1]}
    else:
        rec = {"family": "breather", "breather_family": en.family, "phase": en.phase, "E": repr(en.E),
               "log_abs_dE_4.5": repr(math.log(en.eps))}
    rec.update({
        "trace": M.trace_str if ext else M.trace,
        "trace_transverse": M.trace_transverse,
        "period": M.period_str if ext else M.period,
        "stable": M.stable,
        "multipliers": [[float(complex(z).real), float(complex(z).imag)] for z in M.multipliers],
        "precision": M.precision,
        "backend": M.backend,
        "residual": M.residual,
    })
    return rec


def run(args):
    values = args.E if args.E is not None else args.log_dE
    by_log = args.E is None
    if args.family == "pendulum" and args.breather_family:
        raise ValueError("--family applies to breathers only")
    if by_log and args.family == "pendulum" and args.phase is None:
        raise ValueError("--log-dE needs --phase lib or rot")
    records = []
    for text in values:
        v = as_float(text, "log|E-4|" if by_log else "E")
        if args.family == "pendulum":
            orb = pendulum(log_abs_dE=v, phase=args.phase) if by_log else pendulum(E=v, phase=args.phase)
        else:
            fam = args.breather_family or {"lib": "LG", "rot": "R", None: None}[args.phase]
            if by_log:
                if fam is None:
                    raise ValueError("--log-dE for breathers needs --phase or --family")
                orb = breather(log_abs_dE=v, family=fam)
            else:
                orb = breather(E=v, family=fam)
        records.append(_record(monodromy(orb, digits=args.digits, backend=args.backend), args.digits))
    emit(records, args.json, ["family", "phase", "E", "trace", "period", "stable", "precision"])
    return 0
