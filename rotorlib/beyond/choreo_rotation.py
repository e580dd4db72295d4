"""CG's rotation number and its resonances.

CG's reduced map ``P = g^-1 phi_{T/6}`` (``g = -C^2``, :func:`rotorlib.beyond.choreo.reduced_trace`)
has the multipliers ``1, 1, e^{+-2 pi i rho}`` while CG is stable: ``tr DP = 2 + 2 cos 2 pi
rho``. The rotation number ``rho`` (:func:`rotation_number`, :func:`rotation_curve`)
falls from ``1/3`` at G to 0 at the fold. Where it passes a rational ``p/q``
(:func:`resonance`: the root of ``tr DP - (2 + 2 cos 2 pi p/q)`` in CG's amplitude
``u``, by the engine's Illinois method), periodic points of period ``q`` of ``P`` branch
off; for ``q`` prime to 3 they are choreographies (:mod:`rotorlib.beyond.choreo_resonance`).
:func:`resonance_points` gives the resonances as special points of the family ``CG``
(kind ``resonance``, with ``rotation`` and ``families``).

Precision: float64 ``u`` to ``|du| < 1e-13`` (``E`` to ~1e-13); in the tier of ``digits``
``u`` to ``eps^(3/4)`` and ``E`` to ``digits - 10`` digits.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cache
from typing import Any

import numpy as np

from ..core.precision import FLOAT64, Tier, tier
from ..core.rounding import difference
from ..orbits.continuation import PALC, ContinuationOptions, continuation, member
from ..orbits.family import Branch, SpecialPoint
from ..orbits.shooting import solve
from .choreo import cg_problem, reduced_trace
from .choreo_family import ONCE, ChoreoMember, family, fold_energy, locate_member

__all__ = [
    "RESONANCES",
    "rotation_number",
    "rotation_curve",
    "Resonance",
    "resonance",
    "resonances",
    "resonance_points",
    "cg_family",
]

#: The resonances ``p/q`` of CG with ``q <= 8`` and ``3`` not dividing ``q`` (``rho``
#: runs over ``(0, 1/3)``), in the order CG meets them (rising energy).
RESONANCES = ((2, 7), (1, 4), (1, 5), (1, 7), (1, 8))


def rotation_number(trace_reduced: Any) -> float:
    """``rho = arccos((tr DP - 2)/2) / 2 pi`` in ``[0, 1/2]`` for ``0 <= tr DP <= 4``
    (``nan`` outside: the orbit is unstable and has no rotation number).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_rotation import rotation_number
    >>> [round(rotation_number(x), 12) for x in (1.0, 2.0, 4.0)]
    [0.333333333333, 0.25, 0.0]
    """
    x = float(trace_reduced)
    if not 0.0 <= x <= 4.0:
        return math.nan
    return math.acos(min(1.0, max(-1.0, x / 2 - 1))) / (2 * math.pi)


@cache
def rotation_curve() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(E, rho, T)`` (energy, rotation number, period) along CG from ``E = 0.02`` to the fold (float64, a continuation with
    steps about ten times smaller than :func:`rotorlib.beyond.choreo_family.follow`; ~1 s).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_rotation import rotation_curve
    >>> E, rho, T = rotation_curve()
    >>> bool(np.all(np.diff(rho) < 0)), round(float(rho[0]), 3)
    (True, 0.333)
    """
    p = cg_problem()
    start = []
    for E0 in (0.02, 0.024):
        start.append(member(p, solve(p, -math.sqrt(E0 / 6), E=E0).x, E0))
    b = continuation(
        p,
        PALC(ds=0.01, ds_max=0.02, E_ref=0.0),
        ContinuationOptions(max_steps=800, E_range=(0.01, 10.0), folds=False),
        start,
    )
    Es: list[float] = []
    rhos: list[float] = []
    Ts: list[float] = []
    for m in b.members:
        if Es and float(m.E) < Es[-1]:
            break  # past the fold: CT
        trp = float(reduced_trace(m.x0, 12 * m.t1)[0])
        Es.append(float(m.E))
        rhos.append(rotation_number(trp))
        Ts.append(float(12 * m.t1))
    return np.array(Es), np.array(rhos), np.array(Ts)


def _level(p: int, q: int, t: Tier) -> Any:
    with t.context():
        return 2 + 2 * t.m.cos(2 * t.pi * p / t.num(q))


@dataclass(frozen=True)
class Resonance:
    """CG at its resonance ``p/q``: ``member`` (a :class:`~rotorlib.beyond.choreo_family.ChoreoMember`
    with ``tr DP = 2 + 2 cos 2 pi p/q``, float64), ``refined`` (the same located in the
    tier of ``digits``, or ``None``), ``agreement`` (the difference of the two energies),
    ``families`` (the names of the families born there; ``()`` when ``3 | q``: no
    choreography).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_rotation import resonance
    >>> r = resonance(1, 5)
    >>> r.rotation, round(r.E, 9), r.families
    ('1/5', 5.139286986, ('CG1/5a', 'CG1/5b'))
    """

    p: int
    q: int
    member: ChoreoMember
    refined: ChoreoMember | None = None
    agreement: float = math.nan

    @property
    def rotation(self) -> str:
        """``"p/q"``."""
        return f"{self.p}/{self.q}"

    @property
    def E(self) -> float:
        """The energy (float64)."""
        return float(self.member.E)

    @property
    def E_str(self) -> str:
        """The refined energy's verified digits, else the float64 one to 13 decimals."""
        if self.refined is not None:
            return self.refined.E_str
        return f"{self.E:.13f}"

    @property
    def families(self) -> tuple[str, ...]:
        """The families born here (none when ``3 | q``)."""
        if self.q % 3 == 0:
            return ()
        return tuple(f"CG{self.rotation}{s}" for s in "ab")


@cache
def _cg_members() -> tuple[ChoreoMember, ...]:
    return family("CG", (0.0, fold_energy())).members  # type: ignore[return-value]


@cache
def resonance(p: int, q: int, digits: int | None = None) -> Resonance:
    """CG's member at the resonance ``p/q`` (``0 < p/q < 1/3``): the root of ``tr DP -
    (2 + 2 cos 2 pi p/q)`` in CG's amplitude ``u`` between two members of
    :func:`rotorlib.beyond.choreo_family.follow`, by the engine's Illinois method
    (:func:`rotorlib.beyond.choreo_family.locate_member`), each ``u`` solved for ``E``;
    with ``digits`` > 15 located again in that tier (``refined``, ``E_str``).

    Precision: float64 ``u`` to 1e-13 (``E`` to ~1e-13: ``tr DP`` is monotone in ``E``);
    ``digits=D``: ``E`` to ``D - 10`` digits.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_rotation import resonance
    >>> round(resonance(1, 4).E, 9)  # tr M = 0 (theta = pi/2): where CZ1, CZ2 are born
    4.686903281
    """
    p, q = int(p), int(q)
    if not (q > 0 and 0 < 3 * p < q):
        raise ValueError(
            f"CG's rotation number runs over (0, 1/3): no resonance at {p}/{q}"
        )
    lev = float(_level(p, q, FLOAT64))
    ms = _cg_members()
    i = next(
        i
        for i in range(len(ms) - 1)
        if (ms[i].trace_reduced - lev) * (ms[i + 1].trace_reduced - lev) < 0
    )
    a, b = ms[i], ms[i + 1]
    m = locate_member(
        lambda m: m.trace_reduced - lev, float(a.u), float(b.u), float(a.E), FLOAT64
    )
    if digits is None or digits <= 15:
        return Resonance(p, q, m)
    t = tier(digits)
    with t.context():
        levt = _level(p, q, t)
        h = t.num(1e-7)
        r = locate_member(
            lambda m: m.trace_reduced - levt,
            t.num(float(m.u)) - h,
            t.num(float(m.u)) + h,
            float(m.E),
            t,
            t.num(t.eps) ** t.num(0.75),
        )
    r = replace(r, digits=max(10, int(digits) - 10))
    return Resonance(p, q, m, r, abs(float(r.E) - float(m.E)))


def resonances(digits: int | None = None) -> tuple[Resonance, ...]:
    """Every resonance of :data:`RESONANCES` (:func:`resonance`), by energy.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_rotation import resonances
    >>> [r.rotation for r in resonances()]
    ['2/7', '1/4', '1/5', '1/7', '1/8']
    """
    return tuple(resonance(p, q, digits) for p, q in RESONANCES)


def resonance_points(
    E_range: tuple[float, float] | None = None, digits: int | None = None
) -> tuple[SpecialPoint, ...]:
    """The resonances of :data:`RESONANCES` with ``E`` in ``E_range`` as special points
    of ``CG`` (:class:`~rotorlib.orbits.family.SpecialPoint` of kind ``resonance``, with
    ``rotation`` and ``families``; ``index`` counts the members of CG's branch,
    :func:`rotorlib.beyond.choreo_family.family`).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_rotation import resonance_points
    >>> [(p.kind, p.rotation) for p in resonance_points((5.2, 5.3))]
    [('resonance', '1/7'), ('resonance', '1/8')]
    """
    lo, hi = (-math.inf, math.inf) if E_range is None else map(float, E_range)
    ms = _cg_members()
    out = []
    for r in resonances(digits):
        if not lo <= r.E <= hi:
            continue
        i = sum(float(m.E) <= r.E for m in ms) - 1
        th = f"2 pi {r.rotation}"
        out.append(
            SpecialPoint(
                "resonance",
                r.member if r.refined is None else r.refined,
                i,
                ONCE
                if r.refined is None
                else f"root of tr DP = 2 + 2 cos {th} in float64 and "
                f"{r.refined.precision} agree to {difference(r.agreement)}",
                f"rotation number {r.rotation} (tr DP = 2 + 2 cos {th}; no change of "
                f"stability): {' and '.join(r.families)} are born here",
                rotation=r.rotation,
                families=tuple(r.families),
                branch="CG",
            )
        )
    return tuple(out)


def cg_family(E_range: Sequence[float], digits: int | None = None) -> Branch:
    """The branch ``CG`` of :func:`rotorlib.beyond.choreo_family.family` with CG's
    resonances in ``E_range`` added to its special points (:func:`resonance_points`,
    kind ``resonance``; ``index`` counted among the branch's members). The touch of
    ``tr M = 0`` at ``theta = pi/2`` is the resonance ``1/4`` and is listed once, as
    the resonance (its description says both).

    Examples
    --------
    >>> from rotorlib.beyond.choreo_rotation import cg_family
    >>> b = cg_family((4.0, 5.2))
    >>> [(p.kind, getattr(p, "rotation", "")) for p in b.special_points]
    [('resonance', '1/4'), ('resonance', '1/5')]
    """
    b = family("CG", E_range, digits)
    lo, hi = b.E_range
    Es = [float(m.E) for m in b.members]
    pts = list(resonance_points((lo, hi), digits))
    others = []
    for q in b.special_points:  # a touch at a resonance (1/4: tr M = 0) is that point
        same = [k for k, r in enumerate(pts) if abs(r.E - q.E) < 1e-9]
        if q.kind == "fold" or not same:
            others.append(q)
            continue
        r = pts[same[0]]
        text = f"{r.description}; {q.description}"
        pts[same[0]] = replace(r, description=text)
    pts = [replace(p, index=sum(E <= p.E for E in Es) - 1) for p in pts]
    return replace(
        b,
        special_points=tuple(sorted([*others, *pts], key=lambda p: p.E)),
    )
