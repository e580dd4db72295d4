"""The periodic orbits of the trace-formula section, with their semiclassical data (a data product).

    .venv/bin/python scripts/trace_orbits.py [--workers 2] [--out PATH]

Writes book/data/trace_orbits.json: at each energy E0 of ``ENERGIES``, every symmetric
orbit of the census with period <= ``T_MAX`` (``rotorlib.census``) and every named family
of chapters 5, 7 and 10 that exists there with period <= ``T_NAMED`` (pendulum, the
breathers LG/LD/R, PD^b, the newborn IS/PD families n <= 3, the choreographies CG, CT,
CZ1, CZ2, CR1), each with its action, Maslov indices (r = 1, 2, 3), trace, stabiliser,
copies and, for orbits lying in a mirror, the mirror's relative orbit
(``rotorlib.beyond.quantum_trace.orbit_term``), and for the named ones dT/dE by a
central difference of +-1e-4 in E (null where unknown). About 7 minutes on 2 busy cores
(mostly the named families at E0 +- 1e-4); book/11a_trace_formula reads the file and
recomputes the orbits of E0 = 3.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from data_product import arguments, write_json  # noqa: E402

import rotorlib  # noqa: E402
from rotorlib.beyond import quantum_trace as qt  # noqa: E402

ENERGIES = (3.0, 4.3, 5.45, 7.0)
T_MAX, T_NAMED = 10.0, 14.0
NAMED = ["pendulum", "LG", "LD", "R", "PD^b", "CG", "CT", "CZ1", "CZ2", "CR1"] + [
    f"{k}^{s}_{n}" for k in ("IS", "PD") for s in ("l", "r") for n in (1, 2, 3)
]
DE = 1e-4


def named_orbits(E0: float) -> list:
    out = []
    for lab in NAMED:
        try:
            o = rotorlib.orbit(lab, E0)
        except ValueError:
            continue
        if o.period > T_NAMED:
            continue
        try:
            dT = (
                rotorlib.orbit(lab, E0 + DE).period
                - rotorlib.orbit(lab, E0 - DE).period
            ) / (2 * DE)
        except ValueError:
            dT = float("nan")
        out.append((lab, o, dT))
    return out


def main(argv=None) -> int:
    args = arguments(
        "trace_orbits", __doc__, ROOT / "book" / "data" / "trace_orbits.json", argv
    )
    if args is None:
        return 2
    t0 = time.perf_counter()
    record: dict = {
        "what": "periodic orbits with action, Maslov indices (r = 1..3), trace, copies",
        "T_max_census": T_MAX,
        "T_max_named": T_NAMED,
        "energies": {},
    }
    for E0 in ENERGIES:
        census = rotorlib.census(E0, T_MAX, workers=args.workers).orbits
        named = named_orbits(E0)
        rows = []
        used = set()
        for o in census:
            label, slope = o.label, float("nan")
            for lab, p, dT in named:
                if abs(p.period - o.period) < 1e-6 and abs(p.trace - o.trace) < 1e-4 * (
                    1 + abs(o.trace)
                ):
                    label, slope = lab, dT
                    used.add(lab)
            rows.append((label, o, slope, "census"))
        rows += [(lab, p, dT, "named") for lab, p, dT in named if lab not in used]
        terms = []
        for label, o, slope, src in rows:
            tm = qt.orbit_term(label, E0, o.period, o.state0, o.trace, 3)
            d = tm.to_dict()
            d["period_slope"] = slope if slope == slope else None  # JSON has no NaN
            d["extra"] = {"source": src, "state0": [float(v) for v in o.state0]}
            terms.append(d)
        terms.sort(key=lambda d: d["period"])
        record["energies"][f"{E0:g}"] = terms
        print(f"E0 = {E0:g}: {len(terms)} orbits", flush=True)
    write_json("trace_orbits", args.out, record, "orbit data", t0)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
