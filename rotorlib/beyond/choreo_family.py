"""The family of choreographies born at G, followed to the end: ``CG`` and ``CT``.

The engine (:func:`rotorlib.orbits.continuation.continuation`, pseudo-arclength) follows the
shooting problem :func:`rotorlib.beyond.choreo.cg_problem` from small ``E``. The family leaves G
with ``T -> 2 pi / sqrt 3``, its period grows with ``E``, and at ``E_f ~ 5.3153`` (just
below the band of global chaos) it folds back: a saddle-node (the reduced multipliers meet
at ``+1``, ``tr DP = 4``) in which the stable branch ``CG`` meets an unstable branch,
labelled ``CT``. ``CT`` comes back down in energy and ends at ``E -> 4.5`` with
``T -> infinity``: its orbits spend longer and longer near the maxima ``T1``, ``T2`` of the
potential (three rotors ``2 pi/3`` apart). Beyond ``E_f`` the family does not exist.

:func:`follow` (the branch, cached), :func:`fold_energy`, :func:`branch_range`,
:func:`cg_orbit` (one member, any precision), :func:`special_points` (folds, stability
changes of the reduced map, and the energies where ``tr M`` touches 4 or 0 without a
change of stability), :func:`family` (``CG`` or ``CT`` over an energy range as a
:class:`~rotorlib.orbits.family.Branch` of :class:`ChoreoMember` with its
special points).

Precision: members ``|r| < 1e-8`` (typically 1e-15); special points located by the
Illinois method on the amplitude ``u`` (each value solved for ``E``) to ``|du| < 1e-13``,
``E`` to ~1e-14 (the fold: an extremum, ``E`` to ~1e-15); with ``digits`` each is
re-solved in the tier.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import cache
from typing import Any, cast

import numpy as np

from ..core.precision import FLOAT64, Tier, tier
from ..core.rounding import difference
from ..orbits.continuation import (
    PALC,
    ContinuationOptions,
    FamilyEnd,
    Natural,
    continuation,
    illinois,
    member,
)
from ..orbits.family import Branch, Member, SpecialPoint, energy_range
from ..orbits.floquet import stability_of
from ..orbits.periodic_orbit import PeriodicOrbit
from ..orbits.shooting import ShootingProblem, solve
from .choreo import (
    amplitude_at_energy,
    cg_problem,
    choreo_branch,
    reduced_orbit,
    reduced_trace,
)

__all__ = [
    "LABELS",
    "follow",
    "fold",
    "fold_energy",
    "branch_range",
    "cg_orbit",
    "periods_at",
    "ChoreoMember",
    "locate_member",
    "special_points",
    "family",
]

#: The two branches of the family, with a one-line description.
LABELS = {
    "CG": "choreography born at G (stable, up to the fold)",
    "CT": "its unstable partner, from the fold down to E -> 4.5 (T -> infinity at T1, T2)",
}

_E_START = 0.02  # the first members (u ~ -0.06)
#: A bracket of the fold's amplitude (checked: tr DP - 4 changes sign).
_U_FOLD = (-1.46, -1.50)
_T_MAX = 90.0  # the continuation stops at T = 90 (E - 4.5 ~ 1e-7)


def _label(label: str) -> str:
    lab = str(label).strip()
    up = {k.upper(): k for k in LABELS}
    if lab.upper() not in up:
        raise ValueError(
            f"unknown choreography family {label!r} (known: {', '.join(LABELS)})"
        )
    return up[lab.upper()]


@cache
def follow() -> Branch:
    """The branch ``CG`` + ``CT`` (a :class:`~rotorlib.orbits.continuation.Branch`, float64, with
    its fold located), from ``E = 0.02`` to ``T = 400``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import follow
    >>> b = follow()
    >>> b.stop, len(b.points("fold"))
    ('period', 1)
    """
    p = cg_problem()
    start = []
    for E in (_E_START, 1.2 * _E_START):
        root = solve(p, -math.sqrt(E / 6), E=E)
        start.append(member(p, root.x, E))
    return continuation(
        p,
        PALC(ds=0.1, ds_max=0.25, E_ref=0.0),
        ContinuationOptions(max_steps=400, E_range=(0.01, 10.0), t_max=_T_MAX),
        start,
    )


@cache
def _fold(digits: int | None = None) -> ChoreoMember:
    t = tier(digits) if digits is not None and digits > 15 else FLOAT64
    with t.context():
        tol = 1e-14 if not t.extended else t.num(t.eps) ** t.num(0.75)
        return locate_member(
            lambda m: m.trace_reduced - 4,
            t.num(_U_FOLD[0]),
            t.num(_U_FOLD[1]),
            5.3,
            t,
            tol=tol,
        )


def fold(digits: int | None = None) -> tuple:
    """The fold of the family as the root of ``tr DP = 4`` (the reduced multipliers meet
    at +1), by the Illinois method in the amplitude ``u`` on ``-1.50 < u < -1.46``, each
    ``u`` solved for ``E`` by the engine: ``(u, E, T, tr DP, tr M)`` (tier numbers;
    ``digits`` > 15 in that tier). Independent of the engine's own location of the fold
    as the maximum of ``E`` along :func:`follow` (they agree to ~1e-13).

    Precision: ``u`` to ~1e-14 relative in float64, so ``E`` (an extremum) to ~1e-15;
    ``digits=D``: ``u`` to ``eps^(3/4)``, ``E`` to ``~eps``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import fold
    >>> u, E, T, trp, trm = fold()
    >>> round(float(E), 9), round(float(T), 6)
    (5.315323913, 7.396377)
    """
    m = _fold(digits)
    return m.u, m.E, m.period, m.trace_reduced, m.trace


def fold_energy() -> float:
    """The energy of the fold where ``CG`` and ``CT`` meet (float64, :func:`fold`).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import fold_energy
    >>> round(fold_energy(), 6)
    5.315324
    """
    return float(fold()[1])


def _fold_index() -> int:
    (f,) = [p for p in follow().points("fold") if p.located]
    return f.index


def branch_range(label: str) -> tuple:
    """``(E_min, E_max)`` of a branch (open at ``E_min``: G at 0 for ``CG``, the maxima
    of ``V`` at 4.5 for ``CT``; closed at the fold).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import branch_range
    >>> branch_range("CT")[0]
    4.5
    """
    lab = _label(label)
    return (0.0 if lab == "CG" else 4.5, fold_energy())


def periods_at(label: str, E: float) -> list[float]:
    """The period of the member of ``CG`` or ``CT`` at ``E`` (a list: empty where the
    branch has none, or its member is not found).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import periods_at
    >>> [round(T, 9) for T in periods_at("CG", 3.0)], periods_at("CT", 4.4)
    ([4.29745632], [])
    """
    lo, hi = branch_range(label)
    try:
        return [float(cg_orbit(E, label=label).period)] if lo < E <= hi else []
    except ValueError:
        return []


def _check_E(label, E):
    lab = _label(label)
    try:
        Ef = float(E)
    except (TypeError, ValueError):
        raise ValueError(f"E must be a number, got {E!r}") from None
    lo, hi = branch_range(lab)
    if not math.isfinite(Ef):
        raise ValueError(f"E must be finite, got {E!r}")
    if Ef > hi:
        raise ValueError(
            f"{lab} does not exist at E = {E}: the family ends at the fold E = {hi:.10f} "
            f"(a saddle-node where CG and CT meet; beyond it neither exists)"
        )
    if Ef <= lo:
        why = (
            "G is the equilibrium itself (E = 0)"
            if lab == "CG"
            else "CT ends at E -> 4.5, where its period diverges (the maxima T1, T2)"
        )
        raise ValueError(f"{lab} needs E > {lo:g}, got E = {E}: {why}")
    if lab == "CG" and Ef < 1e-6:
        raise ValueError(
            f"CG at E = {E} is within 1e-6 of G: the orbit is the normal mode "
            f"(T = 2 pi / sqrt 3 (1 + E/24)); the shooting resolves E >= 1e-6"
        )
    if lab == "CT" and Ef < 4.5 + 1e-9:
        raise ValueError(
            f"CT at E = {E} is within 1e-9 of 4.5: the period exceeds ~150, beyond the "
            f"range followed"
        )
    return lab, Ef


def _solve_u(lab, E, t: Tier):
    """The root ``u`` of the branch ``lab`` at energy ``E`` (a tier number), followed by
    the engine's natural continuation in ``E``: ``CG`` below ``E = 4`` from its first
    members near G; ``CG`` above 4 and ``CT`` from the fold, stepping in
    ``sqrt(E_f - E)`` (:class:`~rotorlib.orbits.continuation.Natural` with ``origin`` at the
    fold, where ``u - u_f ~ +-sqrt(E_f - E)``); then re-solved in the tier."""
    Ef = float(E)
    p = cg_problem()
    uf, Efold = (float(v) for v in fold()[:2])
    if Efold - Ef < 1e-13:
        u = uf
    elif lab == "CG" and Ef <= 4.0:
        E0 = min(Ef, _E_START)
        m0 = member(p, solve(p, -math.sqrt(E0 / 6), E=E0).x, E0)
        vals = tuple(np.geomspace(E0, Ef, 12)[1:]) if Ef > E0 else ()
        u = float(_natural_last(p, Natural("E", vals), m0)) if vals else float(m0.u)
    else:
        side = 1 if lab == "CG" else -1
        h = 1e-3
        E1 = solve(p, Efold, u=uf + side * h).x
        m1 = member(p, uf + side * h, E1)
        if Ef >= E1:  # between the fold and uf +- h: E(u) monotone
            u = amplitude_at_energy(p, uf + side * h, uf, E1, Efold, Ef)
        elif lab == "CG":
            d = np.geomspace(Efold - E1, Efold - Ef, 14)[1:]
            vals = tuple(Efold - d)
            u = float(
                _natural_last(p, Natural("E", vals, origin=Efold, origin_other=uf), m1)
            )
        else:  # CT: step in u towards the maximum (u = -2 pi/3), solving for E
            uT = -2 * math.pi / 3
            us = uT + np.geomspace(uf - h - uT, 1e-7, 80)[1:]
            try:
                ms = continuation(
                    p,
                    Natural("u", tuple(us)),
                    ContinuationOptions(folds=False, jump=0.5),
                    [m1],
                ).members
            except FamilyEnd as end:  # the shots fail at E - 4.5 ~ 1e-8
                ms = end.members
            Es = [float(m.E) for m in ms]
            k = next((i for i in range(len(Es) - 1) if Es[i + 1] <= Ef), None)
            if k is None:
                raise ValueError(
                    f"CT at E = {E}: below the energies followed (E - 4.5 >= "
                    f"{Es[-1] - 4.5:.1e}, T <= {float(12 * ms[-1].t1):.0f})"
                )
            a_, b_ = ms[k], ms[k + 1]
            u = amplitude_at_energy(
                p, float(a_.u), float(b_.u), float(a_.E), float(b_.E), Ef
            )
    if not t.extended:
        return u
    with t.context():
        u = t.num(u)
        return solve(
            p, u, u * (1 + t.num("1e-12")), E=str(E), digits=t, r_max=t.eps**0.6
        ).x


def _natural_last(p, alg, m0):
    b = continuation(p, alg, ContinuationOptions(folds=False), [m0])
    return b.members[-1].u


def cg_orbit(
    E: float | str, digits: int | None = None, label: str = "CG"
) -> PeriodicOrbit:
    """The member of ``CG`` (or ``CT``) with energy ``E`` (a decimal string keeps its
    digits), as a :class:`~rotorlib.orbits.periodic_orbit.PeriodicOrbit` whose ``extra`` holds the
    reduced trace ``trace_reduced`` (``tr DP``), ``stable`` and the choreography's
    symmetry.

    Raises ValueError beyond the family's range (:func:`branch_range`), with the reason.

    Precision: float64, period to ~1e-14 relative; ``digits=D`` re-solves the orbit in
    the tier of ``D`` digits and gives ``period_str`` etc. to ``D`` digits.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import cg_orbit
    >>> o = cg_orbit(3)
    >>> round(o.period, 9), o.extra["stable"]
    (4.29745632, True)
    """
    lab, Ef = _check_E(label, E)
    t = tier(digits) if digits is not None and digits > 15 else FLOAT64
    with t.context():
        u = _solve_u(lab, E, t)
        w = t.num(E) if not t.extended else t.num(str(E))
    return reduced_orbit(cg_problem(), u, w, t, lab, digits)


@dataclass(frozen=True)
class ChoreoMember(Member):
    """A member of a choreography family (a :class:`~rotorlib.orbits.family.Member`): ``trace`` is
    ``tr M`` over the full period, as for every member, and ``trace_reduced`` is ``tr DP``
    of the reduced map (:func:`rotorlib.beyond.choreo.reduced_trace`: over ``T/6`` for ``CG`` and
    ``CT``, over ``T/3`` for the Z3 families), which decides ``stability``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import family
    >>> m = family("CG", (5.0, 5.2)).members[0]
    >>> round(float(m.trace_reduced), 4), round(float(m.trace), 4), m.stability
    (2.7186, 3.1855, 'stable')
    """

    trace_reduced: Any = math.nan

    @property
    def stability(self) -> str:
        """:func:`~rotorlib.orbits.floquet.stability_of` applied to ``tr DP``."""
        return stability_of(float(self.trace_reduced), self.digits)

    @classmethod
    def from_member(
        cls, m: Member, trace: Any, trace_reduced: Any, **changes: Any
    ) -> ChoreoMember:
        """The branch member ``m`` with its ``trace`` (``tr M``) and ``trace_reduced``
        (``tr DP``), and any other field in ``changes``."""
        return cls(
            **{**vars(m), "trace": trace, "trace_reduced": trace_reduced, **changes}
        )

    def to_dict(self) -> dict[str, Any]:
        """:meth:`Member.to_dict <rotorlib.orbits.family.Member.to_dict>` and ``trace_reduced``."""
        return {**super().to_dict(), "trace_reduced": float(self.trace_reduced)}


#: How a choreography's special point was located without ``digits`` (its ``located``).
ONCE = "located once, in float64 (digits > 15 locates it again)"


def _at_u(
    u: Any,
    E_guess: Any,
    t: Tier = FLOAT64,
    p: ShootingProblem | None = None,
    order: int = 6,
    power: int = 1,
) -> ChoreoMember:
    """The member with amplitude ``u`` (of ``CG``, or of the problem ``p`` with its reduced
    map of ``order``, ``power``), with ``tr M`` and ``tr DP``."""
    p = p or cg_problem()
    with t.context():
        w = solve(p, t.num(E_guess), u=t.num(u), digits=t).x
        m = member(p, u, w, t)
        trp, trm = reduced_trace(m.x0, p.factor * m.t1, t, order, power)
        return ChoreoMember.from_member(m, trm, trp)


def locate_member(
    g: Callable[..., Any],
    ua: Any,
    ub: Any,
    Ea: Any,
    digits: int | Tier | None = None,
    tol: Any = 1e-13,
    p: ShootingProblem | None = None,
    order: int = 6,
    power: int = 1,
) -> ChoreoMember:
    """The member with amplitude ``u`` in ``(ua, ub)`` where ``g(member) = 0`` (``g``
    changes sign there), by the engine's Illinois method
    (:func:`rotorlib.orbits.continuation.illinois`) to ``|du| < tol``, in the tier of ``digits``.

    The members are those of the family born at G (``p`` None) or of the problem ``p``,
    with ``tr DP`` of the reduced map over ``1/order`` of the period, raised to ``power``
    (:func:`rotorlib.beyond.choreo.reduced_trace`); ``Ea`` is the energy near ``ua`` (the first
    guess of the corrector).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import locate_member
    >>> m = locate_member(lambda m: m.trace_reduced - 4, -1.46, -1.50, 5.3)
    >>> round(float(m.E), 9)  # the fold: tr DP = 4
    5.315323913
    """
    t = tier(digits)
    E_last = [Ea]

    def at(v):
        m = _at_u(ua + v, E_last[0], t, p, order, power)
        E_last[0] = m.E
        return m

    fa, fb = g(at(0 * (ub - ua))), g(at(ub - ua))
    return illinois(g, at, ub - ua, fa, fb, tol)


def level_member(
    p: ShootingProblem | None,
    level: float,
    ua: Any,
    ub: Any,
    Ea: Any,
    digits: int | Tier | None = None,
    order: int = 6,
    power: int = 1,
) -> ChoreoMember:
    """The member with ``u`` in ``(ua, ub)`` where ``tr DP`` (of the reduced map over
    ``1/order`` of the period, raised to ``power``) equals ``level`` (4: IS or fold, 0: PD),
    by :func:`locate_member` to ``|du| < 1e-13`` in float64 and ``eps**0.75`` in an
    extended tier.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import level_member
    >>> round(float(level_member(None, 4.0, -1.46, -1.50, 5.3).E), 9)  # CG's fold
    5.315323913
    """
    t = tier(digits)
    tol = 1e-13 if not t.extended else t.num(t.eps) ** t.num(0.75)
    with t.context():
        lev = t.num(level)
        return locate_member(
            lambda m: m.trace_reduced - lev,
            t.num(ua),
            t.num(ub),
            Ea,
            t,
            tol,
            p,
            order,
            power,
        )


@cache
def _members() -> tuple[ChoreoMember, ...]:
    """The members of :func:`follow` with ``tr M`` and ``tr DP``."""
    b = follow()
    out = []
    for m in b.members:
        trp, trm = reduced_trace(b.state(m), 12 * m.t1, FLOAT64)
        out.append(ChoreoMember.from_member(m, trm, trp))
    return tuple(out)


#: ``(level of tr DP = 2 + 2 cos theta, kind, description)``: leaving ``[0, 4]`` changes
#: the stability; ``6 theta = 0 mod 2 pi`` (``tr M = 4``) and ``6 theta = pi mod 2 pi``
#: (``tr M = 0``) do not: kind ``touch``.
_LEVELS = (
    (4.0, "IS", " (tr DP = 4)"),
    (0.0, "PD", " (tr DP = 0)"),
    (3.0, "touch", "tr M = 4 (no change: theta = pi/3)"),
    (1.0, "touch", "tr M = 4 (no change: theta = 2 pi/3)"),
    (2.0 + math.sqrt(3), "touch", "tr M = 0 (no change: theta = pi/6)"),
    (
        2.0,
        "touch",
        "tr M = 0 (no change: theta = pi/2; the map over T/3 has multipliers -1)",
    ),
    (2.0 - math.sqrt(3), "touch", "tr M = 0 (no change: theta = 5 pi/6)"),
)


@cache
def _special_float() -> tuple[SpecialPoint, ...]:
    """Every special point of :func:`follow`, ``index`` that of its members."""
    k_fold = _fold_index()
    ms = _members()
    out = [
        SpecialPoint(
            "fold", _fold(), k_fold, ONCE, "fold (saddle-node)", branch="CG/CT"
        )
    ]
    for i, (a, b) in enumerate(zip(ms, ms[1:])):
        if i == k_fold:
            continue
        for lev, kind, text in _LEVELS:
            if not (a.trace_reduced - lev) * (b.trace_reduced - lev) < 0:
                continue
            m = locate_member(
                lambda m, lev=lev: m.trace_reduced - lev,
                float(a.u),
                float(b.u),
                float(a.E),
                FLOAT64,
            )
            if lev in (0.0, 4.0):
                up = (b.trace_reduced > a.trace_reduced) == (b.E > a.E)  # tr DP up, E
                into = (lev == 4.0) == up  # leaves [0, 4] as E grows
                text = ("stable -> unstable" if into else "unstable -> stable") + text
            branch = "CG" if i < k_fold else "CT"
            out.append(SpecialPoint(kind, m, i, ONCE, text, branch=branch))
    return tuple(out)


def special_points(
    label: str = "CG",
    E_range: tuple[float, float] | None = None,
    digits: int | None = None,
) -> tuple[SpecialPoint, ...]:
    """The special points of a branch (``CG`` or ``CT``) within ``E_range``, ordered by
    energy: the fold, the stability changes (``tr DP`` through 4 or 0, ``DP`` the reduced
    map of :func:`rotorlib.beyond.choreo.reduced_trace`: kind ``IS``, ``PD``) and the energies
    where ``tr M`` touches 4 or 0 without one (kind ``touch``; ``6 theta = 0 mod pi`` for
    the reduced multipliers ``e^{+-i theta}``). With ``digits`` (> 15) each is located again in that tier as the
    root of ``tr DP`` = its level (``member``; ``located`` gives the difference from the
    float64 location, and for the fold the engine's own location as the maximum of ``E``
    along :func:`follow`). ``index`` counts the members of :func:`follow`.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import special_points
    >>> [(p.kind, p.description[:8]) for p in special_points("CG")][-2:]
    [('touch', 'tr M = 0'), ('fold', 'fold (sa')]
    """
    lab = _label(label)
    pts = [p for p in _special_float() if lab in p.branch.split("/")]
    if E_range is not None:
        lo, hi = (float(v) for v in E_range)
        pts = [p for p in pts if lo <= p.E <= hi]
    if digits is not None and digits > 15:
        pts = [_refine(p, int(digits)) for p in pts]
    return tuple(sorted(pts, key=lambda p: p.E))


@cache
def _refine(p: SpecialPoint, digits: int) -> SpecialPoint:
    """``p`` located again in the tier of ``digits``: ``E`` to ``D - 10`` digits."""
    t = tier(digits)
    d = max(10, digits - 10)  # u to eps^(3/4); E to the same or, at the fold, ~eps
    m0 = cast(ChoreoMember, p.member)
    E0, trp0 = float(m0.E), float(m0.trace_reduced)
    if p.kind == "fold":
        m = _fold(digits)
        agree = abs(float(m.E) - E0)
        engine_fold = follow().fold
        assert engine_fold is not None  # CG's branch always passes its fold
        check = (
            f"root of tr DP = 4 in float64 and {t.name} agree to {difference(agree)}; the "
            f"engine's maximum of E along the branch is {difference(abs(engine_fold.E - E0))}"
            " away"
        )
    else:
        lev = next(v for v, _, _ in _LEVELS if abs(trp0 - v) < 1e-6)
        u0 = float(m0.u)
        with t.context():
            r3 = t.m.sqrt(3)
            levt = {2 + math.sqrt(3): 2 + r3, 2 - math.sqrt(3): 2 - r3}.get(
                lev, t.num(lev)
            )
            h = t.num(1e-7 * max(1.0, abs(u0)))
            tol = t.num(t.eps) ** t.num(0.75)
            m = locate_member(
                lambda m: m.trace_reduced - levt,
                t.num(u0) - h,
                t.num(u0) + h,
                E0,
                t,
                tol,
            )
        agree = abs(float(m.E) - E0)
        check = f"root of tr DP = {lev:.6g} in float64 and {t.name} agree to {difference(agree)}"
    return replace(p, member=replace(m, digits=d), located=check)


def family(label: str, E_range: Sequence[float], digits: int | None = None) -> Branch:
    """The branch ``label`` (``CG`` or ``CT``) with its members in ``E_range`` (in order
    along the family: ``CG`` up from G to the fold, ``CT`` down from the fold to
    ``E -> 4.5``; :class:`ChoreoMember`, float64) and its special points there
    (:func:`special_points`, re-located in the tier of ``digits`` > 15). ``stop`` names
    the two ends (``G / fold``, ``period / fold``: the period exceeds 90 at
    ``E - 4.5 ~ 1e-7``), ``reason`` says where the branch exists. A range entirely outside
    the branch raises ValueError.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import family
    >>> b = family("CG", (5.0, 5.4))
    >>> b.label, b.stop, b.special_points[-1].kind, round(float(b.fold.E), 9)
    ('CG', 'G / fold', 'fold', 5.315323913)
    """
    lab = _label(label)
    lo, hi = energy_range(E_range)
    e0, e1 = branch_range(lab)
    if lo > e1 or hi <= e0:
        raise ValueError(
            f"{lab} exists only for {e0:g} < E <= {e1:.10f} (G or the maxima T1, T2 at "
            f"the low end, the fold at the top): the range {lo:g}..{hi:g} misses it"
        )
    k = _fold_index() + 1  # CG: the members before the fold; CT: after it
    ms = _members()[:k] if lab == "CG" else _members()[k:]
    off = 0 if lab == "CG" else k
    pts = [
        replace(p, index=p.index - off) for p in special_points(lab, (lo, hi), digits)
    ]
    return choreo_branch(
        cg_problem() if lab == "CG" else replace(cg_problem(), label="CT"),
        [replace(m, label=lab) for m in ms],
        pts,
        (lo, hi),
        "G / fold" if lab == "CG" else "period / fold",
        f"{LABELS[lab]}; exists for {e0:g} < E <= {e1:.12f}",
    )
