"""The choreographies with only the Z3 symmetry: CZ1, CZ2 (non-rotating) and CR1 (rotating).

Found by the census of symmetric orbits with ``T <= 16`` at ``E = 4.6`` and ``5.6``
(``scripts/choreo_census.py``, chapter 10). Each starts on a mirror of the torus with its
momentum normal to it and meets the mirror of the same class ``60`` degrees away (the
composition of the two reversing symmetries is ``C``, of order 3) at ``t1``, its
``crossing``-th crossing: ``T = 6 t1``. Each is given by that shooting problem (the
atlas's start sets and fixed sets, :mod:`rotorlib.reversors`) and one member found by the
census (a seed); :func:`z3_family` follows it with the engine (pseudo-arclength,
:func:`rotorlib.continuation.continuation`) through the energies asked for and reports the
members (``tr DP`` of the map over ``T/3``, :func:`rotorlib.choreo.reduced_trace` with
``order=3``) and the located folds, IS and PD points. For these families ``tr M = 2 +
lambda^3 + lambda^-3``: a crossing of 4 (IS) or 0 (PD) is a change of stability, and the
tangencies at ``tr DP = 1, 3`` are not. An IS and a PD located at one energy are a jump of
the computed ``tr M`` between two members (``|tr M|`` beyond ~1e10, where float64 loses
the monodromy), not a bifurcation: they are dropped.

Precision: members ``|r| < 1e-8``; folds to ~1e-15 in ``E`` along the branch, IS and PD
to ~1e-14 in the local parameter (chapter 10 checks the two ends of CZ1 and CZ2 at CG's
point ``tr M = 0`` to 1e-9).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cache

from .choreo import choreography_of, reduced_trace
from .continuation import PALC, ContinuationOptions, continuation, member
from .reversors import start_sets, targets
from .shooting import ShootingProblem

__all__ = ["Z3_FAMILIES", "z3_problem", "Z3Report", "z3_family"]

#: label: (start set, target fixed set, crossing, seed u, seed E, description).
Z3_FAMILIES = {
    "CZ1": (
        "Fix T-(12)",
        "Fix T-(13)",
        1,
        3.709588069893635,
        4.6,
        "non-rotating Z3 choreography born at CG's tr M = 0 point (E ~ 4.687)",
    ),
    "CZ2": (
        "Fix T(12)",
        "Fix T(13)",
        1,
        4.535761967849377,
        4.6,
        "non-rotating Z3 choreography born at CG's tr M = 0 point, stable in part",
    ),
    "CR1": (
        "Fix T(12)",
        "Fix T(13)",
        2,
        4.44083017832691,
        5.6,
        "rotating Z3 choreography, from E -> 4.5 across the band to a fold at E ~ 5.708",
    ),
}

_T_CAP = 40.0  # the continuation stops where the period exceeds this


def _label(label):
    up = {k.upper(): k for k in Z3_FAMILIES}
    lab = str(label).strip().upper()
    if lab not in up:
        raise ValueError(
            f"unknown Z3 choreography family {label!r} (known: {', '.join(Z3_FAMILIES)})"
        )
    return up[lab]


@cache
def z3_problem(label: str) -> ShootingProblem:
    """The shooting problem of a Z3 family (``T = 6 t1``).

    Examples
    --------
    >>> from rotorlib.choreo_z3 import z3_problem
    >>> z3_problem("CZ2").factor
    6
    """
    lab = _label(label)
    start, target, k, _, E0, _ = Z3_FAMILIES[lab]
    (st,) = [s for s in start_sets(E0) if s.name == start]
    (tg,) = [f for f in targets() if f.name == target]
    return ShootingProblem(
        lab, st, tg.section, tg.condition, k, 6, (0.0, 0.0), None, None, 50.0
    )


@dataclass(frozen=True)
class Z3Report:
    """``family CZ1 --E-range A B``: members ``(E, period, tr DP, tr M, stable)`` with
    ``E`` in the range, the located points ``(kind, E)`` there, the energies the
    continuation spanned and why it stopped each way."""

    label: str
    E_range: tuple
    members: tuple
    points: tuple
    span: tuple
    stops: tuple

    def to_record(self) -> dict:
        return {
            "label": self.label,
            "description": Z3_FAMILIES[self.label][5],
            "E_range": list(self.E_range),
            "span": list(self.span),
            "stops": list(self.stops),
            "members": [
                dict(zip(("E", "period", "trace_reduced", "trace", "stable"), m))
                for m in self.members
            ],
            "special_points": [{"kind": k, "E": e} for k, e in self.points],
        }


def _clean(points):
    out = []
    for k, e in points:
        if any(k2 == k and abs(e2 - e) < 1e-8 for k2, e2 in out):
            continue
        if k == "IS" and any(k2 == "fold" and abs(e2 - e) < 1e-8 for k2, e2 in points):
            continue  # tr M = 4 at a fold: the fold itself
        other = {"IS": "PD", "PD": "IS"}.get(k)
        if other and any(k2 == other and abs(e2 - e) < 1e-8 for k2, e2 in points):
            continue  # a jump of the computed tr M
        out.append((k, e))
    return sorted(out, key=lambda v: v[1])


@cache
def _follow(lab, lo, hi, step):
    p = z3_problem(lab)
    _, _, _, u0, E0, _ = Z3_FAMILIES[lab]
    m0 = member(p, u0, E0, traces=True)
    opts = ContinuationOptions(
        max_steps=300,
        E_range=(min(lo, E0) - step, max(hi, E0) + step),
        t1_max=_T_CAP / 6,
        jump=0.05,
        traces=True,
        folds=True,
    )
    ds = step / max(hi, 1.0)
    alg = PALC(ds=ds, ds_max=ds, ds_min=1e-10, u_floor=1.0)
    back = continuation(p, replace(alg, direction=-1), opts, [m0])
    fwd = continuation(p, alg, opts, [m0])
    ms = list(back.members[::-1]) + list(fwd.members[1:])
    pts = [
        (q.kind, float(q.member.E))
        for q in list(back.special_points) + list(fwd.special_points)
        if q.located and q.kind != "E"
    ]
    c = choreography_of(p.state(u0, E0), 6 * float(m0.t1))
    return p, tuple(ms), _clean(pts), (back.stop, fwd.stop), c.power


def z3_family(label: str, E_range, step: float = 0.02) -> Z3Report:
    """Follow the Z3 family ``label`` from its seed through ``E_range`` (and the energies
    between the seed and it) with steps of at most ``step`` in ``E``; a range the family
    does not reach raises ValueError with the energies it spans.

    Examples
    --------
    >>> from rotorlib.choreo_z3 import z3_family
    >>> r = z3_family("CR1", (5.65, 5.75))  # ~20 s
    >>> [(k, round(e, 6)) for k, e in r.points]
    [('PD', 5.706951), ('fold', 5.707703)]
    """
    lab = _label(label)
    lo, hi = (float(v) for v in E_range)
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"--E-range must be two finite energies A < B, got {E_range}")
    p, ms, pts, stops, power = _follow(lab, lo, hi, float(step))
    Es = [float(m.E) for m in ms]
    span = (min(Es), max(Es))
    if hi < span[0] or lo > span[1]:
        raise ValueError(
            f"{lab} was followed over {span[0]:.6f} <= E <= {span[1]:.6f} (ends: "
            f"{' / '.join(stops)}): the range {lo:g}..{hi:g} misses it"
        )
    rows = []
    for m in ms:
        if lo <= float(m.E) <= hi:
            T = float(6 * m.t1)
            trp = float(reduced_trace(p.state(m.u, m.w), T, order=3, power=power)[0])
            rows.append((float(m.E), T, trp, float(m.trace), bool(0 < trp < 4)))
    inside = tuple((k, e) for k, e in pts if lo <= e <= hi)
    return Z3Report(lab, (lo, hi), tuple(rows), inside, span, stops)
