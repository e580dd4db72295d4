"""The choreographies with only the Z3 symmetry: CZ1, CZ2 (non-rotating) and CR1 (rotating).

Found by the census of symmetric orbits with ``T <= 16`` at ``E = 4.6`` and ``5.6``
(``scripts/choreo_census.py``, chapter 10). Each starts on a mirror of the torus with its
momentum normal to it and meets the mirror of the same class ``60`` degrees away (the
composition of the two reversing symmetries is ``C``, of order 3) at ``t1``, its
``crossing``-th crossing: ``T = 6 t1``. Each is given by that shooting problem (the
atlas's start sets and fixed sets, :mod:`rotorlib.orbits.reversors`) and one member found by the
census (a seed). The engine (pseudo-arclength, :func:`rotorlib.orbits.continuation.continuation`)
follows the whole family from the seed both ways until its period exceeds 40 (once per
process, 15-25 s a family): :func:`z3_range`, :func:`z3_orbits` and :func:`z3_orbit`
(the members at one energy), :func:`z3_points` and :func:`z3_family` (the Branch of
``family CZ1 --E-range A B``). Their examples are not run as doctests (each first
follows a family, ~20 s); ``tests/test_choreo.py`` checks the same values.

Stability is that of the map over a third of the period, ``P = C^-k phi_{T/3}``
(:func:`rotorlib.beyond.choreo.reduced_trace` with ``order=3``): ``tr M = 2 + lambda^3 +
lambda^-3``, so ``tr DP`` leaving ``[0, 4]`` changes the stability (through 0: ``PD``;
through 4: a fold, or ``IS`` where ``E`` has no extremum) and the tangencies of ``tr M``
at ``tr DP = 1, 3`` do not. The special points are the roots of ``tr DP - 4`` and ``tr
DP`` along the family, located by the engine's Illinois method in the amplitude ``u``
(each ``u`` solved for ``E``). Their check: each is located twice, in float64 and in
the tier of ``digits`` (real128 for ``digits=30``), and a fold also as the extremum of
``E(u)`` (bounded Brent, float64). CZ1 and CZ2 are born at CG's point ``tr M = 0``
(``theta = pi/2``, where the map over CG's ``T/3`` has multipliers ``-1``): that end is
given by CG's problem (:func:`rotorlib.beyond.choreo_family.special_points`) and checked against
the Z3 family's own extremum of ``E`` (which the degenerate shooting there resolves only
to ~1e-8). The two halves of CZ1 and CZ2 on either side of that point are images of each
other under a symmetry (same ``E`` and period): each of their points is found twice.

Precision: members ``|r| < 1e-8``; special points ``E`` to ~1e-13 in float64 (the
measured agreement with the real128 location is in each point's ``located``), to
``~eps^(3/4)`` in an extended tier (the fold, an extremum, to ``~eps``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from functools import cache
from typing import cast

from ..core.precision import FLOAT64, Tier, tier
from ..core.rounding import difference
from ..orbits.continuation import PALC, ContinuationOptions, continuation, member
from ..orbits.family import Branch, energy_range
from ..orbits.periodic_orbit import PeriodicOrbit
from ..orbits.reversors import start_sets, targets
from ..orbits.shooting import ShootingProblem, residual, solve
from .choreo import (
    Choreography,
    choreo_branch,
    choreography_of,
    member_number,
    orbits_at_energy,
    reduced_trace,
)
from .choreo_family import (
    ONCE,
    ChoreoMember,
    SpecialPoint,
    level_member,
    special_points,
)

__all__ = [
    "Z3_FAMILIES",
    "z3_problem",
    "seed_choreography",
    "z3_range",
    "z3_orbits",
    "z3_orbit",
    "periods_at",
    "z3_points",
    "z3_family",
]

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
_DS = (
    0.0125  # pseudo-arclength step (twice that of the census, scripts/choreo_census.py)
)

#: The description of the end where CZ1 and CZ2 are born (a ``fold`` of ``E``).
_BORN = "born at CG (CG's tr M = 0, theta = pi/2)"


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
    >>> from rotorlib.beyond.choreo_z3 import z3_problem
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


@cache
def seed_choreography(label: str) -> Choreography:
    """How the family's seed is a choreography (power, lattice, rotating), one shot.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_z3 import seed_choreography
    >>> seed_choreography("CR1").rotating, seed_choreography("CZ1").rotating
    (True, False)
    """
    lab = _label(label)
    p, (_, _, _, u0, E0, _) = z3_problem(lab), Z3_FAMILIES[lab]
    s = residual(p, u0, E0)
    c = choreography_of(s.x0, 6 * float(s.t1))
    if c is None:
        raise RuntimeError(
            f"{lab}: the seed is no choreography (shooting problem changed?)"
        )
    return c


@cache
def _branch(lab: str) -> tuple:
    """``(members, stops)``: the whole family along the continuation, float64, each member
    a :class:`~rotorlib.beyond.choreo_family.ChoreoMember` (``tr M`` and ``tr DP``)."""
    p = z3_problem(lab)
    _, _, _, u0, E0, _ = Z3_FAMILIES[lab]
    opts = ContinuationOptions(
        max_steps=300, E_range=(4.0, 6.0), t_max=_T_CAP, jump=0.05, folds=False
    )
    alg = PALC(ds=_DS, ds_max=_DS, ds_min=1e-10, u_floor=1.0)
    m0 = member(p, u0, E0)
    back = continuation(p, replace(alg, direction=-1), opts, [m0])
    fwd = continuation(p, alg, opts, [m0])
    k = seed_choreography(lab).power
    ms = []
    for m in back.members[::-1] + fwd.members[1:]:
        trp, trm = reduced_trace(p.state(m.u, m.w), 6 * m.t1, order=3, power=k)
        ms.append(ChoreoMember.from_member(m, float(trm), float(trp)))
    return tuple(ms), (back.stop, fwd.stop)


def _extremum(lab: str, j: int) -> float:
    """``E`` at the extremum of ``E(u)`` next to the member ``j`` of the branch (bounded
    Brent on ``(u_{j-1}, u_{j+1})``, each ``u`` solved for ``E``; float64)."""
    from scipy.optimize import minimize_scalar

    p, ms = z3_problem(lab), _branch(lab)[0]
    a, m, b = ms[j - 1], ms[j], ms[j + 1]
    sign = 1 if float(m.E) > float(a.E) else -1  # a maximum: minimise -E
    guess = [float(m.E)]

    def f(u):
        guess[0] = float(solve(p, guess[0], u=u).x)
        return -sign * guess[0]

    lo, hi = sorted((float(a.u), float(b.u)))
    res = minimize_scalar(f, method="bounded", bounds=(lo, hi), options={"xatol": 1e-9})
    return -sign * float(f(res.x))


@cache
def _raw_points(lab: str) -> list:
    """``(kind, level, index)`` of every crossing of ``tr DP`` through 4 or 0 between the
    members ``index`` and ``index + 1``, and the extrema of ``E`` without one."""
    ms = _branch(lab)[0]
    E = [float(m.E) for m in ms]
    trp = [m.trace_reduced for m in ms]
    ext = [j for j in range(1, len(E) - 1) if (E[j] - E[j - 1]) * (E[j + 1] - E[j]) < 0]
    out: list[tuple[str, float | None, int]] = []
    for i in range(len(ms) - 1):
        for lev in (4.0, 0.0):
            if (trp[i] - lev) * (trp[i + 1] - lev) < 0:
                fold = lev == 4.0 and any(j in (i, i + 1) for j in ext)
                out.append(("fold" if fold else "IS" if lev == 4.0 else "PD", lev, i))
    used = {i + d for k, _, i in out if k == "fold" for d in (0, 1)}
    out += [(_BORN, None, j) for j in ext if j not in used]
    return out


def _born(lab: str, m: ChoreoMember) -> ChoreoMember:
    """CG's member ``m`` at its point ``tr M = 0`` (``theta = pi/2``) as the Z3 family's:
    CG's orbit run twice (``T = 6 t1``; ``P`` over ``T/3`` is CG's ``P^4``)."""
    th = math.acos(float(m.trace_reduced) / 2 - 1)  # CG's reduced angle, pi/2
    with Tier(m.precision).context():
        t1 = 4 * m.t1
    return replace(
        m,
        label=lab,
        factor=6,
        t1=t1,
        trace_reduced=2 + 2 * math.cos(4 * th),
        trace=2 + 2 * math.cos(12 * th),
    )


@cache
def z3_points(label: str, digits: int | None = None) -> tuple[SpecialPoint, ...]:
    """The special points of a Z3 family, ordered by energy
    (:class:`~rotorlib.orbits.family.SpecialPoint`, ``branch`` the label, ``index`` that
    of the family's members): folds, ``IS`` and ``PD`` (the stability changes: ``tr DP``
    through 4 or 0) and the end where the family is born at CG (a ``fold``: ``E(u)`` has
    its extremum there, ``tr DP = 4``; ``description`` ``born at CG ...``; its member is
    CG's orbit run twice, with CG's amplitude ``u``). Each is located in float64 and,
    with ``digits`` > 15, again in that tier (then ``member`` is that location, and
    ``located`` gives the agreement of the two); a fold's ``located`` also gives its
    distance to the extremum of ``E(u)``. Points found on both symmetric halves of a
    family are listed once (``located`` says so).

    Precision: float64 ``E`` to ~1e-13 (the agreement measures it), a tier's to
    ``~eps^(3/4)``; ``born at CG`` as CG's point
    (:func:`rotorlib.beyond.choreo_family.special_points`).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_z3 import z3_points
    >>> [(p.kind, round(p.member.E, 8)) for p in z3_points("CR1")]  # doctest: +SKIP
    [('PD', 5.70695054), ('fold', 5.70770316)]
    """
    lab = _label(label)
    t = tier(digits) if digits is not None and digits > 15 else FLOAT64
    ms = _branch(lab)[0]
    out = []
    for kind, lev, i in _raw_points(lab):
        if kind == _BORN:
            (q,) = [
                p
                for p in special_points("CG", digits=digits)
                if "pi/2" in p.description
            ]
            Ez = _extremum(lab, i)
            out.append(
                replace(
                    q,
                    kind="fold",
                    member=_born(lab, cast(ChoreoMember, q.member)),
                    index=i,
                    description=kind,
                    branch=lab,
                    located=f"{q.located}; period, tr DP, tr M: CG's orbit run twice; "
                    "the family's own extremum of E differs by "
                    f"{difference(abs(Ez - float(q.E)))}",
                )
            )
            continue
        k = seed_choreography(lab).power
        m = level_member(
            z3_problem(lab),
            lev,
            float(ms[i].u),
            float(ms[i + 1].u),
            float(ms[i].E),
            FLOAT64,
            3,
            k,
        )
        u, E = float(m.u), float(m.E)
        refined, check = None, ONCE
        if t.extended:
            h = 1e-7 * max(1.0, abs(u))
            refined = level_member(z3_problem(lab), lev, u - h, u + h, E, t, 3, k)
            refined = replace(refined, digits=max(10, int(digits or 0) - 10))
            agree = abs(float(refined.E) - E)
            check = f"float64 and {t.name} agree to {difference(agree)}"
        if kind == "fold":
            j = i if abs(float(ms[i].u) - u) < abs(float(ms[i + 1].u) - u) else i + 1
            Eb = _extremum(lab, j)
            check += (
                "; " if check else ""
            ) + f"extremum of E(u) {difference(abs(Eb - E))} away"
        out.append(SpecialPoint(kind, refined or m, i, check, kind, branch=lab))
    uniq: list[SpecialPoint] = []
    for q in sorted(out, key=lambda q: q.E):
        if (
            uniq
            and uniq[-1].description == q.description
            and abs(uniq[-1].E - q.E) < 1e-9
        ):
            note = "found on both symmetric halves"
            uniq[-1] = replace(uniq[-1], located=f"{uniq[-1].located}; {note}")
            continue
        uniq.append(q)
    return tuple(uniq)


@cache
def z3_range(label: str) -> tuple:
    """``(E_min, E_max, why_min, why_max)``: the energies the family spans (its folds and
    its birth at CG from :func:`z3_points` in float64; an end where the period exceeds
    40 at the last member followed) and why it ends there.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_z3 import z3_range
    >>> lo, hi, why_lo, why_hi = z3_range("CR1")  # doctest: +SKIP
    >>> round(hi, 8), why_hi  # doctest: +SKIP
    (5.70770316, 'a fold (saddle-node)')
    """
    lab = _label(label)
    ms = _branch(lab)[0]
    why = "the period exceeds 40 (E -> 4.5: the maxima T1, T2)"
    ends = [(float(ms[0].E), why), (float(ms[-1].E), why)]
    for q in z3_points(lab):
        if q.kind == "fold":
            born = q.description == _BORN
            ends.append(
                (
                    q.E,
                    "CG's point tr M = 0, where the family is born"
                    if born
                    else "a fold (saddle-node)",
                )
            )
    lo, hi = min(ends), max(ends)
    return lo[0], hi[0], lo[1], hi[1]


@cache
def _orbits(lab, E, digits):
    k = seed_choreography(lab).power
    return orbits_at_energy(z3_problem(lab), _branch(lab)[0], E, digits, lab, 3, k)


def z3_orbits(label: str, E: float | str, digits: int | None = None) -> tuple:
    """Every member of the family at energy ``E``, distinct up to symmetry, ordered by
    period (:class:`~rotorlib.orbits.periodic_orbit.PeriodicOrbit`; ``extra`` holds ``trace_reduced``,
    ``stable``, ``choreography``); empty outside the family's range.

    Each is the root of ``E(u) = E`` between two members of the followed family
    (Illinois in ``u``, each ``u`` solved for ``E``), re-solved at fixed ``E`` in the
    tier of ``digits``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_z3 import z3_orbits
    >>> [round(o.period, 6) for o in z3_orbits("CR1", 5.6)]  # doctest: +SKIP
    [13.125659, 15.777029]
    """
    return _orbits(_label(label), str(E), digits)


def periods_at(label: str, E: float, chor: Choreography | None = None) -> list[float]:
    """The periods of the family's members at ``E`` (:func:`z3_orbits`); none if its
    orbits do not rotate as ``chor`` does.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_z3 import periods_at
    >>> [round(T, 6) for T in periods_at("CR1", 5.6)]  # doctest: +SKIP
    [13.125659, 15.777029]
    """
    if chor is not None and seed_choreography(label).rotating != chor.rotating:
        return []
    return [float(o.period) for o in z3_orbits(label, E)]


def z3_orbit(
    label: str, E: float | str, digits: int | None = None, branch: int = 0
) -> PeriodicOrbit:
    """The member number ``branch`` (by period) of the family at energy ``E``
    (:func:`z3_orbits`); ``extra`` adds ``branch`` and ``members_at_E``. Raises
    ValueError outside the family's range (:func:`z3_range`) with the range and why it
    ends there, or when there is no member number ``branch``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_z3 import z3_orbit
    >>> o = z3_orbit("CR1", 5.6, branch=1)  # doctest: +SKIP
    >>> round(o.period, 6), o.extra["stable"]  # doctest: +SKIP
    (15.777029, False)
    """
    lab = _label(label)
    Ef = float(E)
    lo, hi, why_lo, why_hi = z3_range(lab)
    if not math.isfinite(Ef) or not lo <= Ef <= hi:
        raise ValueError(
            f"{lab} exists only for {lo:.10f} <= E <= {hi:.10f} (below: {why_lo}; "
            f"above: {why_hi}), not at E = {E}"
        )
    return member_number(
        lab, z3_orbits(lab, E, digits), E, branch, "its ends are followed up to T = 40"
    )


def z3_family(
    label: str, E_range: Sequence[float], digits: int | None = None
) -> Branch:
    """The Z3 family ``label`` as a :class:`~rotorlib.orbits.family.Branch`: its members with
    ``E`` in ``E_range`` (in order along the continuation;
    :class:`~rotorlib.beyond.choreo_family.ChoreoMember`, float64, ``trace`` is ``tr M``,
    ``trace_reduced`` is ``tr DP`` over ``T/3``, which decides ``stability``) and its
    special points there (:func:`z3_points`, re-located in the tier of ``digits`` > 15).
    ``stop`` is why the continuation stopped each way (``period``: ``T > 40``),
    ``reason`` the energies the family spans and why it ends there (:func:`z3_range`).
    A range the family does not reach raises ValueError with the energies it spans.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_z3 import z3_family
    >>> b = z3_family("CR1", (5.65, 5.75))  # doctest: +SKIP
    >>> [(p.kind, round(p.member.E, 10)) for p in b.special_points]  # doctest: +SKIP
    [('PD', 5.706950538), ('fold', 5.7077031647)]
    """
    lab = _label(label)
    lo, hi = energy_range(E_range)
    ms, stops = _branch(lab)
    e0, e1, why0, why1 = z3_range(lab)
    if hi < e0 or lo > e1:
        raise ValueError(
            f"{lab} was followed over {e0:.10f} <= E <= {e1:.10f} (ends: "
            f"{' / '.join(stops)}): the range {lo:g}..{hi:g} misses it"
        )
    return choreo_branch(
        z3_problem(lab),
        ms,
        z3_points(lab, digits),
        (lo, hi),
        " / ".join(stops),
        f"{Z3_FAMILIES[lab][5]}; exists for {e0:.10f} <= E <= {e1:.10f} (below: "
        f"{why0}; above: {why1}; continuation ends: {' / '.join(stops)})",
    )
