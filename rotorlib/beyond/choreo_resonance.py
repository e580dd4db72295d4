"""The choreographies born from CG at its resonances ``p/q`` (``q <= 8``, ``3`` not
dividing ``q``).

At a resonance of CG's reduced map ``P = g^-1 phi_{T/6}`` (``g = -C^2``;
:mod:`rotorlib.beyond.choreo_rotation`) periodic points of period ``q`` of ``P`` branch
off: ``P^q y = y`` means ``phi_{qT/6}(y) = g^q y``, so the flow orbit through ``y`` has
``x(t + qT/6) = g^q x(t)``. With ``q`` prime to 3, ``g^{2q} = C^{q} = C^{+-1}``:
``x(t + T'/3) = C^{+-1} x(t)`` with ``T' = qT`` (``q`` odd; ``g^q`` of order 6, so
also ``x(t + T'/6) = g^{+-1} x(t)``) or ``T' = qT/2`` (``q`` even; ``g^q = C^{+-1}`` of
order 3): **a choreography**. With ``3 | q``, ``g^q = (-1)^{q/3}``: the orbit has
``x(t + qT/6) = +-x(t)``, not a choreography (CG's 1:6 touch and the 2/9 resonance).

The periodic orbits of ``P`` near a resonance are symmetric (``P`` is reversible), so each
new orbit starts on a mirror with its momentum normal to it, like CG: on CG's own
mirror ``Fix T(12)`` or on ``Fix T-(12)``, which CG crosses at ``3 T/12``; CG meets the
six mirrors in the order :data:`MIRRORS`, one every ``T/12``, and the new orbit meets
the mirror CG meets ``q`` twelfths later (``t1 ~ q T/12``; period ``12 t1`` for odd
``q``, ``6 t1`` for even ``q``). Each family is a :class:`~rotorlib.orbits.shooting.ShootingProblem`
(:func:`family_problem`) with a seed stored in the package data file
``beyond/data/choreo_resonance.json`` (found by ``scripts/choreo_resonance_seeds.py``),
followed by the engine (pseudo-arclength) from its birth at CG to where its period
exceeds :data:`T_BUDGET` or ``|tr DP|`` exceeds 1e10 (float64 shooting exhausted).

Names: ``CG<p>/<q>a`` is the family that is stable next to its birth (the elliptic
periodic orbit of ``P``), ``CG<p>/<q>b`` the unstable one (hyperbolic). For odd ``q``
the two are the two halves of one branch of the shooting problem through CG's
resonance point (on either side of CG's amplitude); for even ``q`` they start on the
two mirrors. At ``1/4`` they are the families found by the census: ``CG1/4a`` is
``CZ2``, ``CG1/4b`` is ``CZ1`` (:mod:`rotorlib.beyond.choreo_z3`, which serves them).

Precision: members ``|r| < 1e-8`` (typically 1e-14; the
float64 period to ~1e-13 relative); special points as in
:mod:`rotorlib.beyond.choreo_z3`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import replace
from functools import cache
from importlib import resources
from typing import Any

from ..core.flow import SectionNotReached
from ..core.precision import FLOAT64, Tier, tier
from ..core.rounding import difference
from ..orbits.continuation import PALC, ContinuationOptions, continuation, member
from ..orbits.family import Branch, SpecialPoint, energy_range
from ..orbits.periodic_orbit import PeriodicOrbit
from ..orbits.reversors import targets
from ..orbits.shooting import (
    NoConvergence,
    ShootingProblem,
    StartSet,
)
from .choreo import (
    cg_problem,
    choreo_branch,
    choreography_of,
    member_number,
    orbits_at_energy,
    reduced_trace,
)
from .choreo_family import ONCE, ChoreoMember, level_member
from .choreo_rotation import RESONANCES, Resonance, resonance

__all__ = [
    "MIRRORS",
    "T_BUDGET",
    "ALIASES",
    "START_B",
    "family_names",
    "family_spec",
    "family_problem",
    "resonance_problem",
    "resonance_range",
    "resonance_points_of",
    "resonance_orbits",
    "resonance_orbit",
    "resonance_family",
    "summary",
    "periods_at",
]

#: The mirrors CG meets, one every ``T/12``, from its start on ``Fix T(12)``.
MIRRORS = (
    "Fix T(12)",
    "Fix T-(13)",
    "Fix T(23)",
    "Fix T-(12)",
    "Fix T(13)",
    "Fix T-(23)",
)

#: The period budget: a family is followed until its period exceeds this.
T_BUDGET = 100.0

_TR_MAX = 1e10  # |tr DP| beyond which float64 shooting no longer resolves a member
_ENDS = {
    "period": f"the period exceeds the budget T = {T_BUDGET:g}",
    "float64": "|tr DP| exceeds 1e10 (float64 shooting exhausted)",
    "stuck": "the continuation step fell below 1e-10",
}

#: The families at ``1/4`` are the census's ``CZ2`` (``a``) and ``CZ1`` (``b``).
ALIASES = {"CG1/4a": "CZ2", "CG1/4b": "CZ1"}

#: The start line ``Fix T-(12)`` (``phi1 = -phi2 = u``), momentum normal to it.
START_B = StartSet("Fix T-(12)", a=(0.5, -0.5), b=(1.0, 1.0))
_DS = 0.0125  # pseudo-arclength step (as for the Z3 families)


# --------------------------------------------------------------------------- families


@cache
def _specs() -> dict[str, dict[str, Any]]:
    text = (
        resources.files("rotorlib.beyond")
        .joinpath("data/choreo_resonance.json")
        .read_text()
    )
    return {k: v for k, v in json.loads(text)["families"].items()}


def family_names() -> tuple[str, ...]:
    """The names of the families born from CG at :data:`RESONANCES` (the ``1/4`` ones
    included: :data:`ALIASES`).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import family_names
    >>> family_names()[:4]
    ('CG2/7a', 'CG2/7b', 'CG1/4a', 'CG1/4b')
    """
    return tuple(f"CG{p}/{q}{s}" for p, q in RESONANCES for s in "ab")


def _name(label: str) -> str:
    up = {k.upper(): k for k in family_names()}
    lab = str(label).strip().upper()
    if lab not in up:
        raise ValueError(
            f"unknown family born from CG {label!r} (known: {', '.join(family_names())})"
        )
    return up[lab]


def family_spec(label: str) -> dict[str, Any]:
    """The stored record of a family: ``p``, ``q``, ``start`` and ``target`` (mirrors),
    ``crossing``, ``factor``, ``order`` and ``power`` of its reduced map, the seed
    ``(u, E)`` and ``description`` (the ``1/4`` families: ``alias``).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import family_spec
    >>> s = family_spec("CG1/5a")
    >>> s["start"], s["target"], s["factor"], s["order"]
    ('Fix T(12)', 'Fix T-(23)', 12, 6)
    """
    return dict(_specs()[_name(label)])


def resonance_problem(q: int, start: int = 0, label: str = "") -> ShootingProblem:
    """The shooting problem of the symmetric periodic points of period ``q`` of CG's
    reduced map: from ``Fix T(12)`` (``start=0``, CG's start) or ``Fix T-(12)``
    (``start=3``, where CG is at ``3 T/12``) to the mirror CG meets ``q`` twelfths of a
    period later (:data:`MIRRORS`), at the crossing CG makes there; the period is
    ``2 ord(g^q) t1`` with ``ord(g^q) = 6 / gcd(q, 6)`` (``x(t + qT/6) = g^q x(t)``).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import resonance_problem
    >>> [resonance_problem(q).factor for q in (4, 5, 6, 9)]
    [6, 12, 2, 4]
    """
    if start not in (0, 3) or int(q) < 1:
        raise ValueError(f"start must be 0 or 3 and q >= 1, got {start!r}, {q!r}")
    q = int(q)
    i = (start + q) % 6
    (tg,) = [f for f in targets() if f.name == MIRRORS[i]]
    return ShootingProblem(
        label or f"period {q}",
        cg_problem().start if start == 0 else START_B,
        tg.section,
        tg.condition,
        1 + sum(1 for j in range(1, q) if (start + j) % 6 == i),
        2 * 6 // math.gcd(q, 6),
        (0.0, 0.0),
        None,
        None,
        T_BUDGET + 10,
    )


@cache
def family_problem(label: str) -> ShootingProblem:
    """The shooting problem of a family (period ``factor t1``).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import family_problem
    >>> family_problem("CG1/7a").crossing, family_problem("CG1/8b").start.name
    (2, 'Fix T-(12)')
    """
    lab = _name(label)
    if lab in ALIASES:
        from .choreo_z3 import z3_problem

        return replace(z3_problem(ALIASES[lab]), label=lab)
    s = _specs()[lab]
    p = resonance_problem(int(s["q"]), MIRRORS.index(s["start"]), lab)
    if (p.section.c, p.crossing, p.factor) != (
        [f for f in targets() if f.name == s["target"]][0].section.c,
        int(s["crossing"]),
        int(s["factor"]),
    ):
        raise RuntimeError(f"{lab}: the stored problem is not the one derived")
    return p


def _reduced(lab: str) -> tuple[int, int]:
    s = _specs()[lab]
    return int(s["order"]), int(s["power"])


def _member(lab: str, m) -> ChoreoMember:
    order, power = _reduced(lab)
    trp, trm = reduced_trace(m.x0, m.factor * m.t1, order=order, power=power)
    return ChoreoMember.from_member(m, float(trm), float(trp))


@cache
def _branch(lab: str) -> tuple[tuple[ChoreoMember, ...], str]:
    """``(members, why)``: the family from its birth at CG (the extremum of ``E`` at
    CG's resonance, where the engine passes onto the other half, is left out) to where its period exceeds
    :data:`T_BUDGET` or ``|tr DP|`` exceeds 1e10 (float64 shooting exhausted), float64,
    each member a ChoreoMember; ``why`` says which end was reached."""
    s, p = _specs()[lab], family_problem(lab)
    m0 = member(p, float(s["seed_u"]), float(s["seed_E"]))
    r = resonance(int(s["p"]), int(s["q"]))
    opts = ContinuationOptions(
        max_steps=600, E_range=(3.0, 6.0), t_max=T_BUDGET + 5, jump=0.05, folds=False
    )
    alg = PALC(ds=_DS, ds_max=_DS, ds_min=1e-10, u_floor=1.0)
    back = continuation(p, replace(alg, direction=-1), opts, [m0])
    fwd = continuation(p, alg, opts, [m0])
    runs = [(back.members, back.stop), (fwd.members, fwd.stop)]
    # the run that passes CG's resonance point (an extremum of E there) is cut at it
    out = None
    for (ms, _), (other, stop) in (runs, runs[::-1]):
        E = [float(m.E) for m in ms]
        ext = [
            j
            for j in range(1, len(E) - 1)
            if (E[j] - E[j - 1]) * (E[j + 1] - E[j]) <= 0 and abs(E[j] - r.E) < 1e-3
        ]
        if ext:
            j = ext[0]
            out = (list(ms[:j])[::-1] + list(other[1:]), stop)
            break
    if out is None:
        raise RuntimeError(f"{lab}: the continuation did not reach its birth at CG")
    kept: list[ChoreoMember] = []
    why = _ENDS.get(out[1], out[1])
    for m in out[0]:
        cm = _member(lab, m)
        if float(cm.period) > T_BUDGET:
            why = _ENDS["period"]
            break
        if abs(float(cm.trace_reduced)) > _TR_MAX:
            why = _ENDS["float64"]
            break
        kept.append(cm)
    return tuple(kept), why


def _born(lab: str, r: Resonance, m: ChoreoMember | None = None) -> ChoreoMember:
    """CG's member at the resonance as the family's member at its birth: CG's orbit run
    over ``q`` twelfths per ``t1`` (``tr DP`` of the new family's reduced map is that of
    ``DP^q``, 4 up to round-off)."""
    m = m or r.member
    s = _specs()[lab]
    th = math.acos(float(m.trace_reduced) / 2 - 1)
    with Tier(m.precision).context():
        t1 = int(s["q"]) * m.t1
    order = int(s["order"])
    return replace(
        m,
        label=lab,
        factor=int(s["factor"]),
        t1=t1,
        trace_reduced=2 + 2 * math.cos(r.q * th),
        trace=2 + 2 * math.cos(r.q * th * order),
    )


@cache
def resonance_points_of(
    label: str, digits: int | None = None
) -> tuple[SpecialPoint, ...]:
    """The special points of a family born from CG, by energy: its birth (kind ``fold``:
    ``E(u)`` has its extremum at CG's resonance; ``description`` ``born at CG ...``) and
    every change of stability (``tr DP`` of its reduced map through 4: ``IS`` or ``fold``,
    through 0: ``PD``), located by the engine's Illinois method in float64 and, with
    ``digits`` > 15, again in that tier.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import resonance_points_of
    >>> [(p.kind, round(p.member.E, 6)) for p in resonance_points_of("CG1/5a")]
    [('PD', 4.844816), ('fold', 5.139287)]
    """
    lab = _name(label)
    if lab in ALIASES:
        from .choreo_z3 import z3_points

        return tuple(
            replace(q, branch=lab, member=q.member and replace(q.member, label=lab))
            for q in z3_points(ALIASES[lab], digits)
        )
    s = _specs()[lab]
    t = tier(digits) if digits is not None and digits > 15 else FLOAT64
    r = resonance(int(s["p"]), int(s["q"]), digits)
    ms, _ = _branch(lab)
    out = [
        SpecialPoint(
            "fold",
            _born(lab, r) if r.refined is None else _born(lab, r, r.refined),
            0,
            "CG's resonance (rotorlib.beyond.choreo_rotation.resonance): "
            + (
                ONCE
                if r.refined is None
                else f"float64 and {t.name} agree to {difference(r.agreement)}"
            ),
            f"born at CG (CG's resonance {r.rotation}, tr DP = 2 + 2 cos 2 pi "
            f"{r.rotation})",
            branch=lab,
        )
    ]
    for i in range(1, len(ms) - 1):
        for lev, kind in ((4.0, "IS"), (0.0, "PD")):
            a, b = ms[i], ms[i + 1]
            if not (a.trace_reduced - lev) * (b.trace_reduced - lev) < 0:
                continue
            up = (b.trace_reduced > a.trace_reduced) == (b.E > a.E)
            into = (lev == 4.0) == up
            text = ("stable -> unstable" if into else "unstable -> stable") + (
                f" as E grows (tr DP = {lev:g})"
            )
            try:
                m = level_member(
                    family_problem(lab),
                    lev,
                    float(a.u),
                    float(b.u),
                    float(a.E),
                    FLOAT64,
                    *_reduced(lab),
                )
            except (NoConvergence, SectionNotReached, ValueError):
                out.append(SpecialPoint(kind, b, i, None, text, branch=lab))
                continue
            check = ONCE
            if t.extended:
                h = 1e-7 * max(1.0, abs(float(m.u)))
                refined = level_member(
                    family_problem(lab),
                    lev,
                    float(m.u) - h,
                    float(m.u) + h,
                    m.E,
                    t,
                    *_reduced(lab),
                )
                agree = abs(float(refined.E) - float(m.E))
                m = replace(refined, digits=max(10, int(digits or 0) - 10))
                check = f"float64 and {t.name} agree to {difference(agree)}"
            out.append(SpecialPoint(kind, m, i, check, text, branch=lab))
    return tuple(sorted(out, key=lambda q: q.E))


@cache
def resonance_range(label: str) -> tuple[float, float, str, str]:
    """``(E_min, E_max, why_min, why_max)``: the energies the family spans within the
    period budget and why it ends there (its birth at CG; the period budget).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import resonance_range
    >>> lo, hi, why_lo, why_hi = resonance_range("CG1/8a")
    >>> round(hi, 9), why_hi[:11]
    (5.296671491, "born at CG'")
    """
    lab = _name(label)
    if lab in ALIASES:
        from .choreo_z3 import z3_range

        return z3_range(ALIASES[lab])
    s = _specs()[lab]
    r = resonance(int(s["p"]), int(s["q"]))
    ms = _branch(lab)[0]
    born = f"born at CG's resonance {r.rotation} (E = {r.E:.10f})"
    budget = f"followed until {_branch(lab)[1]}, towards E -> 4.5 (the maxima T1, T2)"
    Es = [float(m.E) for m in ms]
    if max(Es) <= r.E + 1e-9:  # the family lies below its birth
        return min(Es), r.E, budget, born
    return min(r.E, min(Es)), max(Es), born, budget


def _check(lab: str, E: Any) -> float:
    lo, hi, why_lo, why_hi = resonance_range(lab)
    try:
        Ef = float(E)
    except (TypeError, ValueError):
        raise ValueError(f"E must be a number, got {E!r}") from None
    if not math.isfinite(Ef) or not lo <= Ef <= hi:
        raise ValueError(
            f"{lab} exists only for {lo:.10f} <= E <= {hi:.10f} (below: {why_lo}; "
            f"above: {why_hi}), not at E = {E}"
        )
    return Ef


@cache
def _orbits(lab: str, E: str, digits: int | None) -> tuple[PeriodicOrbit, ...]:
    order, power = _reduced(lab)
    return orbits_at_energy(
        family_problem(lab), _branch(lab)[0], E, digits, lab, order, power
    )


def resonance_orbits(
    label: str, E: float | str, digits: int | None = None
) -> tuple[PeriodicOrbit, ...]:
    """Every member of the family at energy ``E``, ordered by period
    (:class:`~rotorlib.orbits.periodic_orbit.PeriodicOrbit`; ``extra`` holds
    ``trace_reduced``, ``stable``, ``choreography``); each the root of ``E(u) = E``
    between two members of the followed family, re-solved at fixed ``E`` in the tier of
    ``digits``. Raises ValueError outside the family's range.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import resonance_orbits
    >>> [round(o.period, 6) for o in resonance_orbits("CG1/5a", 5.13)]
    [30.439073]
    """
    lab = _name(label)
    if lab in ALIASES:
        from .choreo_z3 import z3_orbits

        return tuple(replace(o, label=lab) for o in z3_orbits(ALIASES[lab], E, digits))
    _check(lab, E)
    return _orbits(lab, str(E), digits)


def resonance_orbit(
    label: str, E: float | str, digits: int | None = None, branch: int = 0
) -> PeriodicOrbit:
    """The member number ``branch`` (by period) of the family at ``E``
    (:func:`resonance_orbits`); ``extra`` adds ``branch`` and ``members_at_E``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import resonance_orbit
    >>> o = resonance_orbit("CG1/7a", 5.27)
    >>> o.extra["choreography"]["sixth"], o.extra["stable"]
    (True, True)
    """
    return member_number(
        _name(label),
        resonance_orbits(label, E, digits),
        E,
        branch,
        "none within the period budget",
    )


def resonance_family(
    label: str, E_range: Sequence[float], digits: int | None = None
) -> Branch:
    """The family ``label`` as a :class:`~rotorlib.orbits.family.Branch`: its members with
    ``E`` in ``E_range`` (from its birth at CG outwards; ChoreoMember, float64, ``trace``
    is ``tr M``, ``trace_reduced`` is ``tr DP`` of its reduced map, which decides
    ``stability``) and its special points there (:func:`resonance_points_of`). A range
    the family does not reach raises ValueError with the energies it spans.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import resonance_family
    >>> b = resonance_family("CG1/5a", (5.0, 5.2))
    >>> b.stop, b.special_points[-1].kind
    ('birth / period', 'fold')
    """
    lab = _name(label)
    lo, hi = energy_range(E_range)
    e0, e1, why0, why1 = resonance_range(lab)
    if hi < e0 or lo > e1:
        raise ValueError(
            f"{lab} spans {e0:.10f} <= E <= {e1:.10f} (below: {why0}; above: "
            f"{why1}): the range {lo:g}..{hi:g} misses it"
        )
    if lab in ALIASES:
        from .choreo_z3 import z3_family

        b = z3_family(ALIASES[lab], (lo, hi), digits)
        return replace(
            b,
            problem=family_problem(lab),
            members=tuple(replace(m, label=lab) for m in b.members),
            special_points=tuple(replace(q, branch=lab) for q in b.special_points),
            reason=f"{lab} is {ALIASES[lab]}: {b.reason}",
        )
    ms, why = _branch(lab)
    s = _specs()[lab]
    return choreo_branch(
        family_problem(lab),
        ms,
        resonance_points_of(lab, digits),
        (lo, hi),
        "birth / " + next(k for k, v in _ENDS.items() if v == why),
        f"{s['description']}; exists for {e0:.10f} <= E <= {e1:.10f} (below: {why0}; "
        f"above: {why1})",
    )


def summary(label: str) -> dict[str, Any]:
    """The record of a family for chapter 10a (JSON-serialisable): ``E_min``, ``E_max``
    and why it ends there, ``E_birth`` (CG's resonance), ``period_birth``, its special
    points (``kind``, ``E``, ``description``), ``stable_windows`` (energy intervals),
    ``enters_band`` (``E_max > 5.33``) and ``stable_in_band``, ``symmetry`` (the
    choreography record of a member 0.01 from its birth, with the ``T/3`` closure
    ``third_error``).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import summary
    >>> s = summary("CG1/7b")
    >>> s["enters_band"], s["stable_windows"], s["symmetry"]["power"]
    (False, [], 1)
    """
    lab = _name(label)
    lo, hi, why_lo, why_hi = resonance_range(lab)
    s = _specs()[lab]
    r = resonance(int(s["p"]), int(s["q"]))
    b = resonance_family(lab, (lo, hi))
    E_near = r.E + (0.01 if abs(lo - r.E) < 1e-6 else -0.01)
    o = resonance_orbit(lab, round(E_near, 6))
    c = choreography_of(o.state0, o.period)
    band = [w for w in b.stable_windows if w[1] > 5.33]
    return {
        "name": lab,
        "alias": ALIASES.get(lab),
        "rotation": r.rotation,
        "E_birth": r.E,
        "E_min": lo,
        "E_max": hi,
        "why_min": why_lo,
        "why_max": why_hi,
        "period_birth": float(r.member.period) * r.q / (1 if r.q % 2 else 2),
        "points": [
            {
                "kind": p.kind,
                "E": p.E,
                "description": p.description,
            }
            for p in b.special_points
        ],
        "stable_windows": [[float(a), float(z)] for a, z in b.stable_windows],
        "enters_band": hi > 5.33,
        "stable_in_band": bool(band),
        "symmetry": {
            "E": round(E_near, 6),
            "period": float(o.period),
            **(c.to_dict() if c else {}),
            "third_error": c.closure if c else None,
        },
    }


def periods_at(label: str, E: float) -> list[float]:
    """The periods of the family's members at ``E`` (float64; ``[]`` outside its range,
    and for ``CG1/4a``, ``CG1/4b``, which the census names ``CZ2``, ``CZ1``): how a
    census names the choreographies it finds.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_resonance import periods_at
    >>> [round(T, 4) for T in periods_at("CG1/8a", 5.29)], periods_at("CG1/8a", 5.4)
    ([27.6502], [])
    """
    lab = _name(label)
    if lab in ALIASES:
        return []
    lo, hi, _, _ = resonance_range(lab)
    if not lo <= float(E) <= hi:
        return []
    return [float(o.period) for o in resonance_orbits(lab, float(E))]
