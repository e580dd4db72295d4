"""Newborn families over an energy range: :func:`family` (the front door's
``rotorlib.family`` for IS/PD labels) and :func:`follow` (the engine's view), both one
pseudo-arclength continuation (:class:`~rotorlib.orbits.continuation.PALC`) from the family's
seed near its birth (:func:`rotorlib.paper.newborn.seed`).

Precision: the continuation's tier is float64 while ``|E_n - 4|`` exceeds
:attr:`Tier.separatrix_depth <rotorlib.core.precision.Tier.separatrix_depth>` (3e-8), real128
beyond, or the tier of ``digits``; members satisfy ``|r| < r_max`` (float64:
:attr:`Tier.r_max <rotorlib.core.precision.Tier.r_max>`, 1e-6 in the ``K`` chart; extended:
``max(eps^(2/3), 1e4 eps / |E_n - 4|)``); special points are located as in
:func:`rotorlib.orbits.continuation.continuation`.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

from ..core.flow import SectionNotReached
from ..core.precision import FLOAT64, REAL128, Tier, tier
from ..orbits.continuation import (
    PALC,
    Branch,
    ContinuationOptions,
    Member,
    SpecialPoint,
    continuation,
    member,
)
from ..orbits.shooting import NoConvergence, solve
from .newborn import (
    FAMILY_FLOAT64_DEPTH,
    FAMILY_REACH,
    FamilyRangeError,
    FamilySpec,
    branch_from_birth,
    family_range,
    family_spec,
    seed,
)

__all__ = ["family", "follow"]


def _default_tier(spec: FamilySpec, traces: bool) -> Tier:
    """float64 while ``|E_n - 4|`` exceeds the separatrix depth (with ``traces``:
    :data:`~rotorlib.paper.newborn.FAMILY_FLOAT64_DEPTH`, where float64 ``tr M`` is still
    right), else real128."""
    depth = FAMILY_FLOAT64_DEPTH if traces else Tier.separatrix_depth
    return FLOAT64 if spec.depth > depth else REAL128


def _branch(
    spec: FamilySpec,
    E_range: tuple[Any, Any],
    t: Tier,
    *,
    t_max: float,
    traces: bool,
    energies: tuple[Any, ...],
    chart: str,
    jump: float | None,
    ds: float,
    ds_max: float,
    max_steps: int,
    enter: bool,
    start: list[Member] | None = None,
) -> Branch:
    """The family of ``spec`` in pseudo-arclength from its seed (or from ``start``)."""
    prob = spec.problem if chart == "E" else spec.problem.chart(4.0)
    if start is None:
        m0 = seed(spec.label, t)[0]
        if chart == "K":
            m0 = member(prob, m0.u, prob.w_at(m0.u, m0.E, t), t)
        start = [m0]
    return continuation(
        prob,
        PALC(
            ds=ds,
            ds_max=ds_max,
            E_ref=spec.E_birth if chart == "E" else 4.0,
            u_floor=1e-3 * math.sqrt(spec.depth),
            w_floor=1e-3 * spec.depth,
        ),
        ContinuationOptions(
            max_steps=max_steps,
            E_range=E_range,
            t_max=t_max,
            jump=jump,
            traces=traces,
            energies=tuple(energies),
            r_max=_r_max(spec, t, chart),
            enter=enter,
        ),
        start,
        t,
    )


def _r_max(spec: FamilySpec, t: Tier, chart: str) -> float:
    """The accepted residual: the shooting amplifies round-off like 1/|E_n - 4| (the K
    chart's members sit in a channel where a2 barely passes the barrier: 1e-6 in float64,
    as measured)."""
    if t.extended:
        return max(t.r_max, 1e4 * t.eps / spec.depth)
    return 1e-6 if chart == "K" else t.r_max


def _t_max(spec: FamilySpec, t_max: float | None) -> float:
    """The largest full period ``t_max`` (default: 12 times the period at birth, beyond
    which the family runs into an orbit of infinite period)."""
    T_birth = spec.period_birth * (2 if spec.kind == "PD" else 1)
    return 12 * T_birth if t_max is None else t_max


def family(
    label: str,
    E_range: tuple[float | str, float | str],
    *,
    digits: int | Tier | None = None,
    steps: int | None = None,
    t_max: float | None = None,
    traces: bool = True,
    energies: tuple[float | str, ...] = (),
    chart: str = "E",
    jump: float | None = None,
    ds: float = 0.3,
    ds_max: float | None = None,
    max_steps: int = 2000,
) -> Branch:
    """The family born at ``label``, followed over ``E_range = (lo, hi)``.

    The family is followed in pseudo-arclength (it passes folds) from its seed near the
    birth energy ``E_n`` (:func:`seed`), through energies below ``lo`` if need be, and
    stops at the first member that leaves the range after entering it (or lands beyond
    it). The members returned all lie inside ``[lo, hi]``: the first and last are
    located exactly at ``lo`` and ``hi`` where the branch crosses them.

    Parameters
    ----------
    label : str
        ``IS^l_n``, ``PD^l_n``, ``IS^r_n``, ``PD^r_n`` (also ``ISl2``, ``PDr3``).
    E_range : (float or str, float or str)
        ``(lo, hi)`` with ``lo < hi``; it must reach above the birth energy ``E_n``.
    digits : int or Tier, optional
        Tier of the continuation (default float64 while ``|E_n - 4| > 1e-5``, where
        float64 ``tr M`` is still right, else real128; without ``traces``: 3e-8).
    steps : int, optional
        Instead of pseudo-arclength: ``steps`` energies from the seed to ``hi``, spaced
        equally in ``sqrt|E - E_n|`` (a natural continuation in ``E``, which stops at a
        fold: :class:`~rotorlib.orbits.continuation.FamilyEnd`); the members are the seed and
        one per step (plus one per halved step) that lie in ``E_range``, the last at
        ``hi``. ``hi`` must lie in :func:`~rotorlib.paper.newborn.family_range`.
    t_max : float, optional
        Stop once the period exceeds it (default: 12 times the period at birth): the
        family runs into an orbit of infinite period (through the maxima of V, E -> 4.5).
    traces : bool
        ``tr M`` of every member and the ``IS``/``PD`` points where it crosses 4 or 0
        (default; the stable windows are where ``0 < tr M < 4``).
    energies : tuple
        Energies at which members are located exactly (``E`` points).
    chart : {'E', 'K'}
        Second unknown: ``E``, or (rotational families) the energy ``q = K - 4`` of the
        ``a2`` motion above the barrier at the base point: ``E - 4 = q + T(u)`` without
        cancellation.
    jump : float, optional
        Refuse steps that change the period by more than this fraction.
    ds, ds_max, max_steps
        First and largest pseudo-arclength step (:class:`~rotorlib.orbits.continuation.PALC`;
        default ``ds_max``: 1 up to ``lo``, then the step that spaces about 24 members
        geometrically in ``E - E_n`` across the range), and the most members followed.

    Returns
    -------
    Branch
        Members inside ``E_range``; special points (``fold``, ``IS``: ``tr M = 4``,
        ``PD``: ``tr M = 0``, ``E``) located by the engine; ``stop`` and ``reason``: why
        it ended.

    Raises
    ------
    FamilyRangeError
        ``E_range`` lies below the birth, or above a fold where the family ends.

    Examples
    --------
    >>> from rotorlib.paper.newborn import family
    >>> b = family("IS^l_1", (3.991, 4.0))
    >>> float(b.E[0]), float(b.E[-1]), len(b.members), b.stop
    (3.991, 4.0, 14, 'E range')
    >>> b.special_points, [m.stability for m in b.members][-1]
    ((), 'stable')
    >>> g = family("IS^l_2", (3.99, 4.0), steps=4)  # the seed and 4 steps
    >>> len(g.members), float(g.E[-1]), round(float(g.trace[-1]), 4)
    (5, 4.0, 7.6664)
    >>> family("IS^l_1", (3.9, 3.99))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    rotorlib.paper.newborn.FamilyRangeError: ... exists for 3.99058822941... < E <= ...
    """
    spec = family_spec(label)
    t = _default_tier(spec, traces) if digits is None else tier(digits)
    with t.context():
        lo, hi = (t.num(str(v) if t.extended else v) for v in E_range)
    if not lo < hi:
        raise ValueError(f"E_range must be (lo, hi) with lo < hi, got {E_range!r}")
    top = family_range(spec)[1]
    if hi <= spec.E_birth or (FAMILY_REACH[spec.label][1] == "fold" and lo > top):
        raise FamilyRangeError(spec, E_range)
    r_max = _r_max(spec, t, chart)
    if steps is not None:
        if float(hi) > top:
            raise FamilyRangeError(spec, E_range)
        return _inside(branch_from_birth(spec, hi, t, steps, traces), lo, hi, r_max)
    kw: dict[str, Any] = dict(
        t_max=_t_max(spec, t_max), chart=chart, jump=jump, max_steps=max_steps
    )
    start, E0 = None, seed(spec.label, t)[0].E
    if E0 < lo:  # the approach, in long steps, to the member at lo
        a = _branch(spec, (-math.inf, lo), t, traces=False, energies=(lo,), ds=ds,
                    ds_max=ds_max or 1.0, enter=False, **kw)  # fmt: skip
        pts = [p for p in a.points("E") if p.located][-1:]
        at_lo = [m for p in pts for m in _at(a, p.member, lo, r_max)]
        if a.stop != "E range" or not at_lo:
            return _inside(a, lo, hi, r_max)
        start = [a.members[-2], at_lo[0]]
    # the steps across the range: about 24 members spaced geometrically in E - E_n
    with t.context():
        ratio = float((hi - spec.E_birth) / (max(lo, E0) - spec.E_birth))
    fine = ds_max or min(1.0, max(0.002, ratio ** (1 / 24) - 1))
    b = _branch(spec, (lo, hi), t, traces=traces, energies=(lo, hi) + tuple(energies),
                ds=min(ds, fine), ds_max=fine, enter=True, start=start, **kw)  # fmt: skip
    return _inside(b, lo, hi, r_max)


def _at(b: Branch, m: Member, E: Any, r_max: float) -> list[Member]:
    """The member of ``b``'s family at exactly ``E``, corrected from ``m`` (none if the
    corrector fails and ``m`` lies outside)."""
    p, t, traces = b.problem, b.tier, m.trace == m.trace
    try:
        with t.context():
            u = solve(p, m.u, E=E, digits=t, r_max=r_max).x
            return [member(p, u, p.w_at(u, E, t), t, traces)]
    except (NoConvergence, SectionNotReached, ValueError):
        return [m] if m.E == E else []


def _inside(b: Branch, lo: Any, hi: Any, r_max: float) -> Branch:
    """The members of ``b`` inside ``[lo, hi]``, with the members at ``lo`` and ``hi``
    where the branch crosses them, and the special points among them."""
    ms = b.members
    keep = [k for k, m in enumerate(ms) if lo <= m.E <= hi]
    first, last = (keep[0], keep[-1]) if keep else (len(ms), len(ms) - 1)

    def end(p: SpecialPoint, k: int) -> Any:  # the range end crossed after member k
        if p.kind != "E" or not p.located or p.index != k or not 0 <= k < len(ms) - 1:
            return None
        a, c = ms[k].E, ms[k + 1].E
        return next((v for v in (lo, hi) if (a - v) * (c - v) <= 0), None)

    ends = [p for p in b.special_points if end(p, first - 1) is not None]
    head = [m for p in ends[:1] for m in _at(b, p.member, end(p, first - 1), r_max)]
    tails = [p for p in b.special_points if end(p, last) is not None][-1:]
    tail = [m for p in tails for m in _at(b, p.member, end(p, last), r_max)]
    ends += tails
    members = head + list(ms[first : last + 1]) + tail
    pts = [
        replace(p, index=max(0, min(len(members) - 1, p.index - first + len(head))))
        for p in b.special_points
        if first - 1 <= p.index <= last and lo <= p.member.E <= hi and p not in ends
    ]
    n, (flo, fhi) = len(members), (float(lo), float(hi))
    why = (
        f"; {n} members lie inside E_range = ({flo:.12g}, {fhi:.12g})"
        if n
        else f"; no member lies inside E_range = ({flo:.12g}, {fhi:.12g})"
    )
    if not n and b.stop == "E range":
        why += " (the branch passed over it between two members)"
    return replace(
        b, members=tuple(members), special_points=tuple(pts), reason=b.reason + why
    )


def follow(
    label: str,
    *,
    E_range: tuple[float | None, float | None] = (None, None),
    t_max: float | None = None,
    digits: int | Tier | None = None,
    traces: bool = False,
    energies: tuple[float | str, ...] = (),
    chart: str = "E",
    jump: float | None = None,
    ds: float = 0.3,
    ds_max: float = 1.0,
    max_steps: int = 2000,
    clip: bool = True,
) -> Branch:
    """The engine's view of :func:`family` (the chapters' and the census's): the branch
    from the seed, stopped by the first member outside ``E_range = (lo, hi)`` (``None``
    for an end: ``lo = E_n - 2|E_n - 4|``; ``hi = 4.2`` for libration, ``E_n + 6`` for
    rotation), which is dropped with ``clip``; the seed is kept even when it lies
    outside. ``t_max`` bounds the period as in :func:`family`. Prefer :func:`family`,
    whose members all lie inside its range.

    Examples
    --------
    >>> from rotorlib.paper.newborn import follow
    >>> b = follow("IS^r_1", E_range=(5.8, 6.0))
    >>> b.stop, len(b.members)
    ('E range', 1)
    """
    spec = family_spec(label)
    t = _default_tier(spec, False) if digits is None else tier(digits)
    lo, hi = E_range
    hi = hi if hi is not None else 4.2 if spec.phase == "lib" else spec.E_birth + 6
    lo = lo if lo is not None else spec.E_birth - 2 * spec.depth
    b = _branch(
        spec,
        (lo, hi),
        t,
        t_max=_t_max(spec, t_max),
        traces=traces,
        energies=tuple(energies),
        chart=chart,
        jump=jump,
        ds=ds,
        ds_max=ds_max,
        max_steps=max_steps,
        enter=False,
    )
    if not clip or b.stop != "E range" or len(b.members) < 2:
        return b
    keep = b.members[:-1]
    pts = [
        p for p in b.special_points if p.index < len(keep) and lo <= p.member.E <= hi
    ]
    return replace(
        b,
        members=keep,
        special_points=tuple(pts),
        reason=b.reason + " (dropped: the branch ends with its last member inside)",
    )
