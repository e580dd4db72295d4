"""``python -m rotorlib trace``: tr M of pendula and breathers.

Examples
--------
``python -m rotorlib trace pendulum --E 1 3.9 5 --json``
``python -m rotorlib trace pendulum --log-dE -60 --phase rot --digits 30``
``python -m rotorlib trace pendulum --E 3.99999999999999999999 --digits 30`` (4 - 1e-20, read exactly)
``python -m rotorlib trace pendulum --log-dE -1e4 --phase lib --digits 30`` (beyond float64)
``python -m rotorlib trace breather --E 9 20`` (rotational breather R)
``python -m rotorlib trace breather --log-dE -40 --family R --digits 30``
"""

from __future__ import annotations

import argparse
from typing import Any

from ..cli import add_digits_argument, emit
from ..core.closed_forms import BreatherOrbit, PendulumOrbit, breather, pendulum
from ..core.precision import json_number
from ..orbits.floquet import monodromy

_DESCRIPTION = """\
tr M (full 4x4) of pendula or isosceles breathers, with the precision that produced it.

Energies are decimals read exactly: --E 3.99999999999999999999 is 4 - 1e-20 in every tier (the
distance to the separatrix is carried, never E itself); only E equal to the separatrix (4, or
4.5 for breathers) is refused. --log-dE is log|E - 4| (pendula) or log|E - 4.5| (breathers), any
notation (-60, -1e4, -.5). Float64 covers |E - sep| >= 1.8e-307 (log >= -706.3); deeper energies
need --digits > 15 (heyoka real128 to log|E - sep| ~ -11000, multiprecision beyond; the run time
grows like |log|E - sep||: -1e4 takes ~1 s). Breather traces grow like |E - 4.5|^-2 and overflow
float64 below log|E - 4.5| ~ -350 (JSON: trace null, trace_str the value).

stability is stable (0 < tr M < 4), unstable, or marginal: tr M within the accuracy of the tier
(1e-12 in float64, 10^(2 - digits) above) of 0 or 4, where the computed value cannot decide. E = 0
is the equilibrium G: both normal modes have frequency sqrt(3) (1:1 resonance), M is the identity,
tr M = 4: marginal (neutrally stable), with a note. For small E > 0 the pendulum has
4 - tr M = pi^2 E^3/3456 (1 + O(E)) > 0 (stable), unresolved in float64 below E ~ 7e-4 (e.g.
E = 1e-300): marginal, and the note gives the series value."""


def register(sub: Any) -> None:
    p = sub.add_parser(
        "trace",
        help="trace of the monodromy matrix of pendula or breathers",
        description=_DESCRIPTION,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("family", choices=["pendulum", "breather"])
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument(
        "--E",
        nargs="+",
        metavar="V",
        help="energies (m = g = r = 1), decimals read exactly",
    )
    g.add_argument(
        "--log-dE",
        nargs="+",
        metavar="V",
        dest="log_dE",
        help="natural log of the distance to the separatrix (needs --phase or --family)",
    )
    p.add_argument("--phase", choices=["lib", "rot"], help="libration or rotation")
    p.add_argument(
        "--family",
        dest="breather_family",
        choices=["LG", "LD", "R"],
        help="breather family (default LG below 4.5, R above)",
    )
    add_digits_argument(p, "> 15 uses heyoka real128/multiprecision")
    p.add_argument(
        "--json",
        action="store_true",
        help="print JSON (one object per energy, a list when several)",
    )
    p.set_defaults(func=run)


def _record(M, digits: int | None) -> dict[str, Any]:
    """The JSON record of one monodromy (the rule of :func:`rotorlib.core.precision.json_number`:
    numbers are float64 values, the digits beyond them in ``*_str`` decimal strings)."""
    ext = M.precision != "float64"
    en = M.energy
    given_log = en.given[1] if en.given[0] == "log_abs_dE" else None
    return {
        **(
            {"family": "pendulum"}
            if M.family == "pendulum"
            else {"family": "breather", "breather_family": en.family}
        ),
        "phase": en.phase,
        **json_number("E", en.E, en.E_text(max(17, digits or 0))),
        **json_number("log_abs_dE", en.log_abs_dE, given_log),  # to E = 4 or 4.5
        # trace_str also where float64 overflows
        **json_number(
            "trace",
            M.trace,
            M.trace_str if ext or M.trace_str != repr(M.trace) else None,
        ),
        **json_number(
            "trace_transverse", M.trace_transverse, note="beyond float64: see trace_str"
        ),
        **json_number("period", M.period, M.period_str if ext else None),
        "stable": M.stable,
        "stability": M.stability,
        "stability_note": M.stability_note,
        "multipliers": [
            [float(complex(z).real), float(complex(z).imag)] for z in M.multipliers
        ],
        "precision": M.precision,
        "backend": M.backend,
        **json_number("residual", M.residual),
    }


def run(args: argparse.Namespace) -> int:
    values = args.E if args.E is not None else args.log_dE
    by_log = args.E is None
    if args.family == "pendulum" and args.breather_family:
        raise ValueError("--family applies to breathers only")
    if by_log and args.family == "pendulum" and args.phase is None:
        raise ValueError("--log-dE needs --phase lib or rot")
    records = []
    for text in values:
        at = {"log_abs_dE": text} if by_log else {"E": text}
        if args.family == "pendulum":
            orb: PendulumOrbit | BreatherOrbit = pendulum(**at, phase=args.phase)
        else:
            fam = (
                args.breather_family
                or {"lib": "LG", "rot": "R", None: None}[args.phase]
            )
            if by_log and fam is None:
                raise ValueError("--log-dE for breathers needs --phase or --family")
            orb = breather(**at, family=fam)
        records.append(_record(monodromy(orb, digits=args.digits), args.digits))
    emit(
        records,
        args.json,
        ["family", "phase", "E", "trace", "period", "stability", "precision"],
    )
    return 0
