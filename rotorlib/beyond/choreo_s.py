"""The family ``CS``: the third ``D6``-symmetric, non-rotating choreography.

Besides ``CG`` and its partner ``CT`` (:mod:`rotorlib.beyond.choreo_family`), the shooting
problem of the ``D6`` rotating waves (:func:`rotorlib.beyond.choreo.cg_problem`: from the
mirror ``Fix T(12)``, ``phi1 = phi2 = u``, at right angles to the first translate of
``Fix T-(13)``, at right angles, ``T = 12 t1``) has a second family of roots at ``u > 0``:
orbits that pass close to the maxima ``T1``, ``T2`` of the potential. Its members satisfy
``x(t + T/6) = -C^2 x(t)`` and ``x(t + T/3) = C x(t)`` (non-rotating). The engine
(pseudo-arclength, :func:`rotorlib.orbits.continuation.continuation`) follows it from a
seed at ``E = 5.45`` (``T ~ 16.52``) both ways until the period exceeds 100: it leaves
``E -> 4.5`` (``T -> infinity``, the separatrix of the maxima), crosses the band of
global chaos unstable with ``tr DP < 0``, becomes stable at a pitchfork
(``tr DP = 0``) below ``E = 6.47``, turns at a fold (``tr DP = 4``) near ``E = 6.87``
and comes back down to ``E -> 4.5`` unstable (``tr DP > 4``) with a longer period.

Stability is that of the reduced map ``P = g^-1 phi_{T/6}``, ``g = -C^2``
(:func:`rotorlib.beyond.choreo.reduced_trace`, order 6): ``tr M = 2 + lambda^6 +
lambda^-6``. Where ``tr DP`` passes 0 the map over ``T/3``, ``P^2``, has the multiplier
``+1`` with an eigenvector odd under ``g``: a pitchfork of the ``Z3`` quotient in which
two ``Z3`` choreographies of the same period leave ``CS`` (``D6 -> Z3``), kind
``pitchfork``. Where it passes 4 at the extremum of ``E`` the family folds.

:func:`cs_points` (the fold and the pitchfork, located as roots of ``tr DP - 4`` and
``tr DP`` in the amplitude ``u`` by the engine's Illinois method, in float64 and again in
the tier of ``digits``, with their agreement; the fold also as the extremum of ``E(u)``),
:func:`cs_range`, :func:`cs_orbits`, :func:`cs_orbit` (``orbit CS --E V``),
:func:`cs_family` (``family CS --E-range A B``).

Precision: members ``|r| < 1e-8`` (typically 1e-14); special points ``E`` to ~1e-13 in
float64 (the measured agreement with the extended tier is each point's ``agreement``),
to ``~eps^(3/4)`` in an extended tier (the fold, an extremum, to ``~eps``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from functools import cache

from ..core.precision import FLOAT64, tier
from ..core.rounding import difference
from ..orbits.continuation import PALC, ContinuationOptions, continuation, member
from ..orbits.family import Branch, SpecialPoint, energy_range
from ..orbits.periodic_orbit import PeriodicOrbit
from ..orbits.shooting import ShootingProblem, residual, solve
from .choreo import (
    amplitude_at_energy,
    cg_problem,
    choreo_branch,
    reduced_orbit,
    reduced_trace,
)
from .choreo_family import ONCE, ChoreoMember, level_member

__all__ = [
    "CS_LABEL",
    "CS_SEED",
    "CS_DESCRIPTION",
    "cs_problem",
    "cs_members",
    "cs_points",
    "cs_range",
    "cs_orbits",
    "cs_periods",
    "cs_orbit",
    "cs_family",
]

CS_LABEL = "CS"
#: ``(u, E)`` of the seed: the member at ``E = 5.45`` with ``T ~ 16.52`` (found by the
#: scan of the choreography census, ``scripts/choreo_census.py``).
CS_SEED = (2.2553545926, 5.45)
CS_DESCRIPTION = (
    "D6 non-rotating choreography: from E -> 4.5 across the band unstable, a "
    "pitchfork D6 -> Z3 (stable above), a fold near E = 6.87, back to E -> 4.5"
)
_T_CAP = 100.0  # the continuation stops where the period exceeds this
_DS = 0.0125


@cache
def cs_problem() -> ShootingProblem:
    """CG's shooting problem (:func:`rotorlib.beyond.choreo.cg_problem`) labelled ``CS``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_s import cs_problem
    >>> cs_problem().label, cs_problem().factor
    ('CS', 12)
    """
    return replace(cg_problem(), label=CS_LABEL)


@cache
def cs_members() -> tuple:
    """``(members, stops)``: the family along the continuation (float64), from the
    short-period end (``E -> 4.5``, ``tr DP < 0``) over the fold to the long-period end,
    each a :class:`~rotorlib.beyond.choreo_family.ChoreoMember` with ``tr M`` and ``tr DP``
    (over ``T/6``).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_s import cs_members
    >>> ms, stops = cs_members()
    >>> stops, len(ms) > 100
    (('period', 'period'), True)
    """
    p = cs_problem()
    opts = ContinuationOptions(
        max_steps=400, E_range=(4.4, 8.0), t_max=_T_CAP, jump=0.05, folds=False
    )
    alg = PALC(ds=_DS, ds_max=_DS, ds_min=1e-10, u_floor=1.0)
    m0 = member(p, CS_SEED[0], CS_SEED[1])
    # the seed's u grows towards the short-period end: direction +1 in u is "back"
    back = continuation(p, alg, opts, [m0])
    fwd = continuation(p, replace(alg, direction=-1), opts, [m0])
    first, last = back.members, fwd.members
    if float(first[-1].u) < float(last[-1].u):
        first, last = last, first
        back, fwd = fwd, back
    ms = []
    for m in list(first[::-1]) + list(last[1:]):
        trp, trm = reduced_trace(p.state(m.u, m.w), 12 * m.t1)
        ms.append(ChoreoMember.from_member(m, float(trm), float(trp)))
    return tuple(ms), (back.stop, fwd.stop)


def _extremum(j: int) -> float:
    """``E`` at the extremum of ``E(u)`` next to the member ``j`` (bounded Brent on
    ``(u_{j-1}, u_{j+1})``, each ``u`` solved for ``E``; float64)."""
    from scipy.optimize import minimize_scalar

    p, ms = cs_problem(), cs_members()[0]
    a, m, b = ms[j - 1], ms[j], ms[j + 1]
    guess = [float(m.E)]

    def f(u):
        guess[0] = float(solve(p, guess[0], u=u).x)
        return -guess[0]

    lo, hi = sorted((float(a.u), float(b.u)))
    res = minimize_scalar(f, method="bounded", bounds=(lo, hi), options={"xatol": 1e-9})
    return -float(f(res.x))


@cache
def cs_points(digits: int | None = None) -> tuple[SpecialPoint, ...]:
    """The special points of ``CS`` ordered by energy
    (:class:`~rotorlib.orbits.family.SpecialPoint`, ``branch`` ``CS``): every root of
    ``tr DP - 4`` (the fold, where ``E(u)`` turns) and of ``tr DP`` (the pitchfork
    ``D6 -> Z3``, kind ``pitchfork``) between consecutive members, located in float64 and,
    with ``digits`` > 15, again in that tier (then ``member`` and ``E_str`` are the
    tier's, and ``located`` gives the agreement of the two); the fold's ``located`` also
    gives its distance to the extremum of ``E(u)``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_s import cs_points
    >>> [(p.kind, round(p.E, 6)) for p in cs_points()]
    [('pitchfork', 6.469685), ('fold', 6.867887)]
    """
    t = tier(digits) if digits is not None and digits > 15 else FLOAT64
    ms = cs_members()[0]
    E = [float(m.E) for m in ms]
    ext = {j for j in range(1, len(E) - 1) if (E[j] - E[j - 1]) * (E[j + 1] - E[j]) < 0}
    out = []
    for i, (a, b) in enumerate(zip(ms, ms[1:])):
        for lev in (4.0, 0.0):
            if not (a.trace_reduced - lev) * (b.trace_reduced - lev) < 0:
                continue
            m = level_member(
                cs_problem(), lev, float(a.u), float(b.u), float(a.E), FLOAT64
            )
            up = (b.trace_reduced > a.trace_reduced) == (b.E > a.E)  # tr DP up with E
            into = (lev == 4.0) == up  # leaves [0, 4] as E grows
            change = "stable -> unstable" if into else "unstable -> stable"
            fold = lev == 4.0 and bool(ext & {i, i + 1})
            if fold:
                kind, text = "fold", "fold (saddle-node, tr DP = 4)"
            elif lev == 4.0:
                kind, text = "IS", f"{change} (tr DP = 4)"
            else:
                kind = "pitchfork"
                text = (
                    f"{change} (tr DP = 0): pitchfork D6 -> Z3, two Z3 choreographies of "
                    "the same period branch off"
                )
            best, check = m, ONCE
            if t.extended:
                h = 1e-7 * max(1.0, abs(float(m.u)))
                r = level_member(
                    cs_problem(), lev, float(m.u) - h, float(m.u) + h, float(m.E), t
                )
                best = replace(r, digits=max(10, int(digits or 0) - 10))
                agree = abs(float(r.E) - float(m.E))
                check = (
                    f"root of tr DP = {lev:g} in float64 and {t.name} agree to "
                    f"{difference(agree)}"
                )
            if fold:
                j = min((i, i + 1), key=lambda k: abs(float(ms[k].u) - float(m.u)))
                d = abs(_extremum(j) - float(m.E))
                check += f"; extremum of E(u) {difference(d)} away"
            out.append(SpecialPoint(kind, best, i, check, text, branch=CS_LABEL))
    return tuple(sorted(out, key=lambda q: q.E))


@cache
def cs_range() -> tuple:
    """``(E_min, E_max, why_min, why_max)``: the energies ``CS`` spans (the lower end is
    the lowest member followed, ``T <= 100``; the upper end its fold).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_s import cs_range
    >>> lo, hi, why_lo, why_hi = cs_range()
    >>> round(lo, 4), round(hi, 6), why_hi
    (4.5, 6.867887, 'a fold (saddle-node)')
    """
    ms = cs_members()[0]
    (f,) = [q for q in cs_points() if q.kind == "fold"]
    lo = min(float(m.E) for m in ms)
    why = "the period exceeds 100 (E -> 4.5: the maxima T1, T2)"
    return lo, f.E, why, "a fold (saddle-node)"


@cache
def _orbits(E: str, digits: int | None) -> tuple:
    p, ms = cs_problem(), list(cs_members()[0])
    (f,) = [q for q in cs_points() if q.kind == "fold"]
    ms.insert(f.index + 1, f.member)  # the fold itself: brackets up to E_f
    t = tier(digits) if digits is not None and digits > 15 else FLOAT64
    Ef = float(E)
    found: list = []
    for a, b in zip(ms, ms[1:]):
        if not (float(a.E) - Ef) * (float(b.E) - Ef) <= 0 or a.E == b.E:
            continue
        u = amplitude_at_energy(p, float(a.u), float(b.u), float(a.E), float(b.E), Ef)
        with t.context():
            w = t.num(E) if t.extended else Ef
            if t.extended:
                ut = t.num(u)
                u = solve(p, ut, ut * (1 + t.num("1e-12")), E=w, digits=t).x
            T = float(12 * residual(p, u, w, t).t1)
        if not any(abs(T - T2) < 1e-8 * T for T2, _ in found):
            found.append((T, u))
    with t.context():
        w = t.num(E) if t.extended else Ef
    return tuple(
        reduced_orbit(p, u, w, t, CS_LABEL, digits)
        for _, u in sorted(found, key=lambda v: v[0])
    )


def cs_orbits(E: float | str, digits: int | None = None) -> tuple:
    """Every member of ``CS`` at energy ``E`` ordered by period (two below the fold: the
    short one with ``tr DP < 4``, the long one with ``tr DP > 4``), each a
    :class:`~rotorlib.orbits.periodic_orbit.PeriodicOrbit` whose ``extra`` holds
    ``trace_reduced``, ``stable`` and ``choreography``; empty outside the range. Each is
    the root of ``E(u) = E`` between two members followed, re-solved at fixed ``E`` in
    the tier of ``digits`` (a decimal string keeps its digits).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_s import cs_orbits
    >>> [round(o.period, 6) for o in cs_orbits(5.45)]
    [16.524918, 27.750819]
    """
    return _orbits(str(E), digits)


def cs_periods(E: float) -> list[float]:
    """The periods of the members of ``CS`` at ``E`` (empty outside :func:`cs_range`):
    how the front door names a census's choreography (:func:`rotorlib.api.name_choreography`).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_s import cs_periods
    >>> [round(T, 4) for T in cs_periods(5.6)], cs_periods(7.0)
    ([16.1171, 25.8245], [])
    """
    lo, hi = cs_range()[:2]
    E = float(E)
    return [float(o.period) for o in cs_orbits(E)] if lo <= E <= hi else []


def cs_orbit(
    E: float | str, digits: int | None = None, branch: int = 0
) -> PeriodicOrbit:
    """The member number ``branch`` (by period) of ``CS`` at ``E`` (:func:`cs_orbits`);
    ``extra`` adds ``branch`` and ``members_at_E``. Raises ValueError outside
    :func:`cs_range` (with the range and why it ends there) or without that member.

    Precision: float64, period to ~1e-13 relative; ``digits=D`` re-solves the orbit in
    the tier of ``D`` digits.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_s import cs_orbit
    >>> o = cs_orbit(5.4)
    >>> round(o.period, 6), o.extra["stability"]
    (16.679805, 'unstable')
    """
    try:
        Ef = float(E)
    except (TypeError, ValueError):
        raise ValueError(f"E must be a number, got {E!r}") from None
    lo, hi, why_lo, why_hi = cs_range()
    if not math.isfinite(Ef) or not lo <= Ef <= hi:
        raise ValueError(
            f"CS exists only for {lo:.10f} <= E <= {hi:.10f} (below: {why_lo}; above: "
            f"{why_hi}), not at E = {E}"
        )
    os_ = cs_orbits(E, digits)
    if not 0 <= int(branch) < len(os_):
        raise ValueError(
            f"CS has {len(os_)} member(s) at E = {E} (branch 0 to {len(os_) - 1}, by "
            f"period), not branch {branch}"
        )
    o = os_[int(branch)]
    return replace(
        o, extra={**o.extra, "branch": int(branch), "members_at_E": len(os_)}
    )


def cs_family(E_range: Sequence[float], digits: int | None = None) -> Branch:
    """``CS`` as a :class:`~rotorlib.orbits.family.Branch`: its members with ``E`` in
    ``E_range`` (in order along the continuation, short-period end first;
    :class:`~rotorlib.beyond.choreo_family.ChoreoMember`, float64) and its special points
    there (:func:`cs_points`, re-located in the tier of ``digits`` > 15). A range the
    family does not reach raises ValueError.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_s import cs_family
    >>> b = cs_family((4.6, 6.9))
    >>> [p.kind for p in b.special_points]
    ['pitchfork', 'fold']
    """
    lo, hi = energy_range(E_range)
    ms, stops = cs_members()
    e0, e1, why0, why1 = cs_range()
    if hi < e0 or lo > e1:
        raise ValueError(
            f"CS was followed over {e0:.10f} <= E <= {e1:.10f}: the range "
            f"{lo:g}..{hi:g} misses it"
        )
    return choreo_branch(
        cs_problem(),
        ms,
        cs_points(digits),
        (lo, hi),
        " / ".join(stops),
        f"{CS_DESCRIPTION}; exists for {e0:.10f} <= E <= {e1:.10f} (below: {why0}; "
        f"above: {why1})",
    )
