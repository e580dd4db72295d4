"""Seeds of the choreography families born from CG at its resonances p/q (q <= 8, 3 not
dividing q): writes ``rotorlib/beyond/data/choreo_resonance.json`` (package data).

For each resonance (``rotorlib.beyond.choreo_resonance.resonance``) and each of the two
start mirrors (CG's ``Fix T(12)`` and ``Fix T-(12)``, which CG crosses at ``3 T/12``):
the shooting problem to the mirror CG meets ``q`` twelfths of its period later
(``MIRRORS[(i0 + q) % 6]``, at the crossing that CG's own orbit makes there), scanned at
``E_r -+ 0.01`` over ``u`` within 0.2 of CG's point on the mirror (201 points); the
roots of the residual nearest to CG's point on either side (CG's own root excluded:
``|du| > 0.01``; period within 5 % of ``q T`` or ``q T/2``) are solved at that energy and classified by the stability of their
reduced map next to the birth (``a``: stable, ``b``: unstable). Odd ``q``: both roots on
``Fix T(12)`` (the two halves of one branch); even ``q``: one root on each mirror.
The side of the resonance where roots exist is the side the families live on.
Run: ``.venv/bin/python scripts/choreo_resonance_seeds.py`` (~20 s).
"""

from __future__ import annotations

import json
import math
import pathlib

import numpy as np

from rotorlib.beyond import choreo_resonance as cr
from rotorlib.beyond.choreo import choreography_of, reduced_trace
from rotorlib.beyond.choreo_family import cg_orbit
from rotorlib.beyond.choreo_rotation import RESONANCES, resonance
from rotorlib.core.flow import flow
from rotorlib.orbits.shooting import NoConvergence, residual, solve

OUT = pathlib.Path(__file__).parents[1] / "rotorlib/beyond/data/choreo_resonance.json"


def problem(p, q, i0):
    pr = cr.resonance_problem(q, i0, f"CG{p}/{q}")
    return pr, cr.MIRRORS[(i0 + q) % 6], pr.crossing, pr.factor


def u_cg(E, i0):
    o = cg_orbit(E)
    if i0 == 0:
        return float(o.extra["u"])
    x = flow(list(o.state0), 3 * o.period / 12)  # on Fix T-(12): phi1 = -phi2 = u
    return 2 * float(x[0])


def roots(pr, E, uc):
    us = uc + np.linspace(-0.2, 0.2, 201)
    vals = []
    for u in us:
        try:
            vals.append(float(residual(pr, u, E).r))
        except Exception:
            vals.append(math.nan)
    out = []
    for i in range(len(us) - 1):
        if vals[i] * vals[i + 1] < 0 and abs((us[i] + us[i + 1]) / 2 - uc) > 0.01:
            try:  # a jump of the residual (another crossing) does not converge
                out.append(float(solve(pr, us[i], us[i + 1], E=E).x))
            except NoConvergence:
                continue
    below = [u for u in out if u < uc]
    above = [u for u in out if u > uc]
    return ([max(below)] if below else []) + ([min(above)] if above else [])


def main():
    fams = {}
    for p, q in RESONANCES:
        r = resonance(p, q)
        if (p, q) == (1, 4):
            for s, alias in (("a", "CZ2"), ("b", "CZ1")):
                fams[f"CG1/4{s}"] = {
                    "p": 1,
                    "q": 4,
                    "alias": alias,
                    "description": f"{alias}: born at CG's resonance 1/4",
                }
            continue
        found = []
        for i0 in (0,) if q % 2 else (0, 3):
            pr, tg, k, f = problem(p, q, i0)
            for dE in (-0.01, 0.01):
                E = r.E + dE
                us = roots(pr, E, u_cg(E, i0))
                if q % 2 == 0:
                    us = us[:1]  # both roots on one mirror are the same orbit
                for u in us:
                    s = residual(pr, u, E)
                    T = f * float(s.t1)
                    want = q * r.member.period / (1 if q % 2 else 2)  # q T or q T/2
                    if abs(T / float(want) - 1) > 0.05:
                        continue  # another orbit, not born here
                    c = choreography_of(s.x0, T)
                    assert c is not None, (p, q, u)
                    order = 6 if c.sixth else 3
                    trp = float(reduced_trace(s.x0, T, order=order, power=c.power)[0])
                    found.append(
                        dict(
                            p=p,
                            q=q,
                            start=cr.MIRRORS[i0],
                            target=tg,
                            crossing=k,
                            factor=f,
                            order=order,
                            power=c.power,
                            seed_u=u,
                            seed_E=E,
                            seed_period=T,
                            seed_trace_reduced=trp,
                        )
                    )
        assert len(found) == 2, (p, q, found)
        found.sort(key=lambda d: d["seed_trace_reduced"] > 4)
        assert found[0]["seed_trace_reduced"] < 4 < found[1]["seed_trace_reduced"]
        for s, d in zip("ab", found):
            kind = "stable" if s == "a" else "unstable"
            d["description"] = (
                f"choreography born at CG's resonance {p}/{q} ({kind} next to its "
                f"birth; period ~{d['seed_period']:.0f})"
            )
            fams[f"CG{p}/{q}{s}"] = d
        print(
            p,
            q,
            [
                (
                    d["start"],
                    round(d["seed_u"], 4),
                    round(d["seed_E"], 4),
                    round(d["seed_trace_reduced"], 6),
                )
                for d in found
            ],
        )
    OUT.parent.mkdir(exist_ok=True)
    OUT.write_text(
        json.dumps(
            {
                "about": "seeds of the choreographies born from CG at its resonances "
                "(scripts/choreo_resonance_seeds.py)",
                "families": fams,
            },
            indent=1,
        )
        + "\n"
    )


if __name__ == "__main__":
    main()
