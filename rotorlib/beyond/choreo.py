"""Choreographies of the three rotors and the periodic orbits born at G.

A choreography is a periodic motion in which the three rotors run along one and the same
curve, a third of a period apart: ``theta_i(t + T/3) = theta_{i+1}(t)`` (indices mod 3,
angles mod 2 pi, the centre of mass free). In the relative angles ``phi1 = theta1 -
theta2``, ``phi2 = theta2 - theta3`` (``phi3 = theta3 - theta1 = -phi1 - phi2``) the
relabelling ``i -> i + 1`` is

``C (phi1, phi2) = (phi2, -phi1 - phi2)``,   ``C^3 = 1``,

so that a choreography is an orbit with ``x(t + T/3) = C x(t)`` modulo the configuration
lattice ``(2 pi Z)^2`` (``C`` acting on momenta by its cotangent lift ``C^-T``).
:data:`C_PHI`, :func:`relabelling` and :func:`choreography_of` (which tells whether a
periodic orbit is one, and with which lattice vector).

Near G the linearised motion is two copies of one frequency ``sqrt 3`` and the group
``S3 x Z2`` of the potential acts on the plane of normal modes as ``D6``, the symmetries of
a regular hexagon (``C`` the rotation by 120 degrees, ``phi -> -phi`` the rotation by
180 degrees). The equivariant Weinstein-Moser theorem (Montaldi, Roberts and Stewart) gives
one family for each isotropy subgroup of ``D6 x S^1`` with a two-dimensional fixed-point
space: two standing waves (on the mirrors of the transpositions, the breathers ``LG``, and
of the negated transpositions, the pendula) and one rotating wave with
``x(t + T/6) = -C^2 x(t)``: the choreography ``CG``. The quartic term of ``V`` is
``D6``-invariant hence isotropic, which fixes the first correction of each period:
``T = (2 pi / sqrt 3) (1 + E/16 + O(E^2))`` for the standing waves and
``(2 pi / sqrt 3) (1 + E/24 + O(E^2))`` for the choreography (:func:`lindstedt_period`).

The family ``CG`` is solved with the one shooting engine (:mod:`rotorlib.orbits.shooting`): the
orbit leaves the mirror ``Fix T(12)`` (``phi1 = phi2``) at right angles and meets
``Fix T-(13)`` at right angles a twelfth of a period later (``T = 12 t1``). Its stability
is that of the reduced map ``P = g^-1 phi_{T/6}`` with ``g = -C^2`` (:func:`reduced_trace`):
``M = DP^6``, so ``tr M = 4`` or ``0`` wherever the reduced multipliers ``e^{+-i theta}``
have ``6 theta = 0 mod pi`` without any change of stability; the orbit changes stability
only where ``tr DP`` leaves ``[0, 4]``. Families and their special points:
:mod:`rotorlib.beyond.choreo_family`.

Precision: float64 shooting to ``|r| < 1e-13`` (period to ~1e-14 relative, ``tr M`` to
~1e-13 |M|); ``digits=D`` re-solves the orbit in the tier of ``D`` digits.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from functools import cache
from typing import Any

import numpy as np

from ..core.flow import Section, flow
from ..core.precision import FLOAT64, Tier, tier
from ..orbits.family import Branch, Member, SpecialPoint
from ..orbits.floquet import stability_of
from ..orbits.periodic_orbit import PeriodicOrbit, periodic_orbit
from ..orbits.shooting import ShootingProblem, StartSet, residual, solve

__all__ = [
    "C_PHI",
    "relabelling",
    "sixth_map",
    "choreography_of",
    "choreography_label",
    "label_by_period",
    "Choreography",
    "cg_problem",
    "lindstedt_period",
    "reduced_trace",
    "reduced_orbit",
    "amplitude_at_energy",
    "choreo_branch",
    "orbits_at_energy",
    "member_number",
    "rotor_angles",
    "T0",
]

#: The cyclic relabelling ``theta_i -> theta_{i+1}`` on ``(phi1, phi2)``.
C_PHI = ((0, 1), (-1, -1))

#: The period of the small oscillations at G, ``2 pi / sqrt 3``.
T0 = 2 * math.pi / math.sqrt(3)

_A = np.array([[0.5, 0.0], [0.5, 1.0]])  # a = A phi (pendulum variables)
_AI = np.array([[2.0, 0.0], [-1.0, 1.0]])


def _lift(q):
    m = np.zeros((4, 4))
    m[:2, :2] = q
    m[2:, 2:] = np.linalg.inv(q).T
    return m


def relabelling(k: int = 1) -> np.ndarray:
    """``C^k`` on the state ``[a1, a2, p1, p2]`` (cotangent lift; exact entries).

    Examples
    --------
    >>> import numpy as np
    >>> from rotorlib.beyond.choreo import relabelling
    >>> np.allclose(np.linalg.matrix_power(relabelling(), 3), np.eye(4))
    True
    >>> relabelling()[:2, :2].tolist()
    [[-0.5, 0.5], [-1.5, -0.5]]
    """
    c = _A @ np.array(C_PHI, float) @ _AI
    return np.linalg.matrix_power(_lift(c), int(k) % 3)


def sixth_map() -> np.ndarray:
    """``g = -C^2`` on the state: the rotation by 60 degrees with ``x(t + T/6) = g x(t)``
    on the family ``CG`` (a rotating wave of ``D6``).

    Examples
    --------
    >>> import numpy as np
    >>> from rotorlib.beyond.choreo import sixth_map, relabelling
    >>> g = sixth_map()
    >>> np.allclose(g @ g, relabelling(1))
    True
    """
    return -relabelling(2)


@dataclass(frozen=True)
class Choreography:
    """How a periodic orbit is a choreography: ``x(t + T/3) = C^power x(t) + 2 pi lattice``
    (``lattice`` in ``phi``, integers, for the start state given); ``sixth`` whether also
    ``x(t + T/6) = -C^{2 power} x(t)`` modulo the lattice (the ``D6`` rotating-wave
    symmetry); ``rotating`` whether the lattice vector is not of the form ``(1 - C) m``
    (another translate of the start state): ``n1 - n2 != 0 mod 3``. Then each rotor takes
    the place of its neighbour displaced by ``2 pi/3`` about the centre of mass: the
    rotors go round the circle (about the maximum T1 of ``V``, a rigid rotation of three
    rotors ``2 pi/3`` apart).

    Examples
    --------
    >>> from rotorlib.beyond.choreo import choreography_of
    >>> from rotorlib.beyond.choreo_family import cg_orbit
    >>> o = cg_orbit(3)
    >>> choreography_of(o.state0, o.period).to_dict()["rotating"]
    False
    """

    power: int
    lattice: tuple
    sixth: bool
    rotating: bool
    closure: float

    def to_dict(self) -> dict:
        """The record of the atlas's ``choreography`` field (JSON-serialisable)."""
        return {
            "power": self.power,
            "lattice": list(self.lattice),
            "sixth": self.sixth,
            "rotating": self.rotating,
        }


def _shift_error(x0, xs, g):
    d = np.asarray(xs, float) - g @ np.asarray(x0, float)
    n = _AI @ d[:2] / (2 * math.pi)
    k = np.round(n)
    return max(
        float(np.max(np.abs(n - k))) * 2 * math.pi, float(np.max(np.abs(d[2:])))
    ), k


def choreography_of(
    state0: Sequence[float] | np.ndarray,
    period: float,
    tol: float = 1e-7,
    digits: int | None = None,
) -> Choreography | None:
    """Whether the periodic orbit through ``state0`` with period ``period`` is a
    choreography (:class:`Choreography`), else ``None``.

    The state after ``T/3`` (and ``T/6``) is compared with ``C^{+-1} x0`` (and
    ``-C^{-+1} x0``) modulo the lattice; it is one when the difference is below ``tol``
    (the orbit's own closure is ~1e-12 in float64). ``digits`` integrates in that tier.

    Examples
    --------
    >>> from rotorlib.beyond.choreo import choreography_of
    >>> from rotorlib.beyond.choreo_family import cg_orbit
    >>> o = cg_orbit(3)
    >>> c = choreography_of(o.state0, o.period)
    >>> c.sixth, c.rotating
    (True, False)
    """
    t = tier(digits)
    x0 = [float(v) for v in state0]
    x3 = [float(v) for v in flow(x0, float(period) / 3, t)]
    x6 = [float(v) for v in flow(x0, float(period) / 6, t)]
    for power in (1, 2):
        err, k = _shift_error(x0, x3, relabelling(power))
        if err < tol:
            err6, _ = _shift_error(x0, x6, -relabelling(2 * power))
            lat = tuple(int(v) for v in k)
            # n is defined modulo (1 - C^power) Z^2 (the start state's lattice translate),
            # a subgroup of index 3 on which n1 - n2 = 0 mod 3: the class is the invariant
            rot = (lat[0] - lat[1]) % 3 != 0
            return Choreography(power, lat, bool(err6 < tol), rot, err)
    return None


def lindstedt_period(E: float, family: str = "CG") -> float:
    """The period to first order in ``E`` at G: ``T0 (1 + E/24)`` for the choreography
    ``CG`` (circular motion in the plane of the normal modes), ``T0 (1 + E/16)`` for the
    standing waves (``pendulum``, ``breather LG``).

    The quartic part of ``V`` is ``-sum (theta_i - theta_j)^4/24``, ``D6``-invariant
    and hence a function of the radius alone in the plane of the modes:
    ``V = 3 r^2/2 - 3 r^4/16 + O(r^6)`` (unit kinetic metric). A line through G gives a
    Duffing oscillator, ``omega = sqrt 3 (1 - E/16)``; a circle of radius ``r`` turns
    at ``omega^2 = V'(r)/r``, ``omega = sqrt 3 (1 - E/24)`` with ``E = 3 r^2``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo import lindstedt_period, T0
    >>> round(lindstedt_period(0.24) / T0, 12)
    1.01
    """
    slope = {"CG": 1 / 24, "pendulum": 1 / 16, "breather LG": 1 / 16}
    if family not in slope:
        raise ValueError(f"unknown family {family!r} (CG, pendulum or breather LG)")
    return T0 * (1 + slope[family] * E)


@cache
def cg_problem() -> ShootingProblem:
    """The shooting problem of the choreography ``CG``: from ``Fix T(12)`` (``phi1 = phi2
    = u``, ``u < 0``, the momentum at right angles in the kinetic metric) to the first
    crossing of a translate of the mirror ``Fix T-(13)`` (``a2 = a1 mod 2 pi``), where the
    momentum must be at right angles again (``p1 + p2 = 0``); ``T = 12 t1``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo import cg_problem
    >>> cg_problem().factor
    12
    """
    return ShootingProblem(
        "CG",
        StartSet("Fix T(12)", a=(0.5, 1.5), b=(-3.0, 1.0)),
        Section((-1.0, 1.0, 0, 0), 0.0, 0, 2.0),
        Section((0, 0, -1.0, -1.0)),
        factor=12,
        t_max=50.0,
    )


def reduced_trace(
    state0: Sequence[float] | np.ndarray,
    period: float,
    digits: int | Tier | None = None,
    order: int = 6,
    power: int = 1,
) -> tuple:
    """``tr DP`` of the reduced map ``P = g^-1 phi_{T/order}`` and ``tr M`` (``M =
    DP^order``), as ``(tr DP, tr M)`` (tier numbers; ``digits``: the tier of
    :func:`rotorlib.core.precision.tier`).

    ``order=6``: ``g = -C^{2 power}`` (:func:`sixth_map`; the ``D6`` rotating waves such as
    ``CG``); ``order=3``: ``g = C^power`` (any choreography). ``DP`` has the multipliers
    ``1, 1, lambda, 1/lambda``: the orbit is stable when ``0 < tr DP < 4``;
    ``tr M = 2 + lambda^order + lambda^-order``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo import reduced_trace
    >>> from rotorlib.beyond.choreo_family import cg_orbit
    >>> o = cg_orbit(3)
    >>> trp, trm = reduced_trace(o.state0, o.period)
    >>> 0 < trp < 4, abs(trm - o.trace) < 1e-9
    (True, True)
    """
    return _reduced_trace(state0, period, tier(digits), order, power)


def _reduced_trace(state0, period, t: Tier, order: int = 6, power: int = 1) -> tuple:
    if order not in (3, 6):
        raise ValueError(f"order must be 3 or 6, got {order!r}")
    g = -relabelling(2 * power) if order == 6 else relabelling(power)
    with t.context():
        x, phi = flow([t.num(v) for v in state0], t.num(period) / order, t, True)
        gi = np.rint(np.linalg.inv(g) * 2) / 2  # entries 0, +-1/2, +-1, +-3/2, +-2
        dp = [
            [sum(t.num(gi[i][k]) * phi[k][j] for k in range(4)) for j in range(4)]
            for i in range(4)
        ]
        trp = sum(dp[i][i] for i in range(4))
        m = dp
        for _ in range(order - 1):
            m = [
                [sum(m[i][k] * dp[k][j] for k in range(4)) for j in range(4)]
                for i in range(4)
            ]
        return trp, sum(m[i][i] for i in range(4))


def reduced_orbit(
    p: ShootingProblem,
    u: Any,
    w: Any,
    t: Tier,
    label: str,
    digits: int | None,
    order: int = 6,
    power: int = 1,
) -> PeriodicOrbit:
    """The :class:`~rotorlib.orbits.periodic_orbit.PeriodicOrbit` of the choreography problem ``p`` at
    ``(u, w)`` in the tier ``t``, with ``extra`` holding ``trace_reduced`` (``tr DP`` of
    the reduced map of ``order`` and ``power``, :func:`rotorlib.beyond.choreo.reduced_trace`),
    ``stable``, ``stability`` (of ``tr DP``), ``choreography`` and, in an extended tier,
    ``trace_reduced_str`` to ``digits - 8`` digits. Shared by :func:`rotorlib.beyond.choreo_family.cg_orbit` and
    :func:`rotorlib.beyond.choreo_z3.z3_orbits`.

    Examples
    --------
    >>> from rotorlib.beyond.choreo import cg_problem
    >>> from rotorlib.beyond.choreo_family import cg_orbit
    >>> from rotorlib.core.precision import FLOAT64
    >>> o = cg_orbit(3)
    >>> r = reduced_orbit(cg_problem(), o.extra["u"], 3.0, FLOAT64, "CG", None)
    >>> r.extra["stability"], abs(r.period - o.period) < 1e-12
    ('stable', True)
    """
    with t.context():
        o = periodic_orbit(p, u, w, t, label, shown=digits if t.extended else None)
        s = residual(p, u, w, t)
        trp = reduced_trace(s.x0, p.factor * s.t1, t, order, power)[0]
    c = choreography_of(o.state0, o.period)
    extra = dict(o.extra)
    extra.update(
        trace_reduced=float(trp),
        stable=bool(0 < float(trp) < 4),
        stability=stability_of(float(trp), o.digits),
        choreography=c.to_dict() if c else None,
    )
    if t.extended and digits is not None:
        extra["trace_reduced_str"] = t.text(trp, int(digits) - 8)
    return replace(o, extra=extra)


def rotor_angles(
    state0: Sequence[float] | np.ndarray, period: float, n: int = 601
) -> np.ndarray:
    """The rotor angles ``theta (n, 3)`` over one period (centre of mass at rest at 0),
    from the orbit in pendulum variables (float64).

    Examples
    --------
    >>> from rotorlib.beyond.choreo import rotor_angles
    >>> from rotorlib.beyond.choreo_family import cg_orbit
    >>> o = cg_orbit(1)
    >>> th = rotor_angles(o.state0, o.period, 7)
    >>> bool(abs(th.sum(axis=1)).max() < 1e-12)
    True
    """
    from ..core.flow import sample

    st, _ = sample([float(v) for v in state0], float(period), n)
    phi1 = 2 * st[:, 0]
    phi2 = st[:, 1] - st[:, 0]
    return np.stack(
        [(2 * phi1 + phi2) / 3, (phi2 - phi1) / 3, -(phi1 + 2 * phi2) / 3], axis=1
    )


def label_by_period(
    E: float,
    chor: Choreography,
    period: float,
    families: Sequence[tuple[str, Callable[[str, float, Choreography], list[float]]]],
) -> str:
    """The first of ``families`` (``(label, periods)``, ``periods(label, E, chor)`` the
    periods of its members at ``E`` that rotate as ``chor`` does) with a member of this
    ``period`` (to 1e-7), else ``choreography``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import cg_orbit
    >>> o = cg_orbit(5.3)
    >>> c = choreography_of(o.state0, o.period)
    >>> label_by_period(5.3, c, o.period, [("CX", lambda lab, E, c: [1.0])])
    'choreography'
    >>> label_by_period(5.3, c, o.period, [("CG", lambda lab, E, c: [o.period])])
    'CG'
    """
    T = float(period)
    for lab, periods in families:
        if any(abs(Tk - T) < 1e-7 * T for Tk in periods(lab, E, chor)):
            return lab
    return "choreography"


def choreography_label(
    label: str,
    E: float,
    state0: Sequence[float],
    period: float,
    name_choreography: Callable[[float, Choreography, float], str] | None,
    test: bool = True,
) -> tuple[str, dict | None]:
    """``(label, record)`` of a census orbit: whether it is a choreography
    (:func:`choreography_of`; ``record`` its :meth:`Choreography.to_dict`, else
    ``None``), and its label: ``label`` if it is not ``new``, else what
    ``name_choreography(E, choreography, period)`` calls it (the front door's
    :func:`rotorlib.api.name_choreography`: ``CG``, ``CT``, ``CZ1``, ...), else
    ``choreography``. With ``test=False`` nothing is tested: ``(label, None)``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_family import cg_orbit
    >>> o = cg_orbit(5.3)
    >>> choreography_label("new", 5.3, o.state0, o.period, None)[0]
    'choreography'
    """
    c = choreography_of(state0, period) if test else None
    if c is None or label != "new":
        return label, None if c is None else c.to_dict()
    named = name_choreography(E, c, period) if name_choreography else "choreography"
    return named, c.to_dict()


def amplitude_at_energy(
    p: ShootingProblem, a: float, b: float, Ea: float, Eb: float, E: float
) -> float:
    """The amplitude ``u`` in ``(a, b)`` where the member of the problem ``p`` has energy
    ``E`` (``E(u)`` monotone there, ``E(a) = Ea``, ``E(b) = Eb``), float64: the engine's
    Illinois method (:func:`rotorlib.orbits.continuation.illinois`) on ``E(u) - E`` to
    ``2e-16 E``, each ``u`` solved for its energy by the engine (robust beside a fold,
    where a secant at fixed ``E`` is not).

    Examples
    --------
    >>> from rotorlib.beyond.choreo import amplitude_at_energy, cg_problem
    >>> from rotorlib.beyond.choreo_family import follow
    >>> a, b = follow().members[10:12]
    >>> u = amplitude_at_energy(cg_problem(), a.u, b.u, a.E, b.E, (a.E + b.E) / 2)
    >>> bool(min(a.u, b.u) < u < max(a.u, b.u))
    True
    """
    from ..orbits.continuation import illinois

    def at(v: float) -> tuple[float, float]:  # (u, E(u) - E)
        return a + v, float(solve(p, E, u=a + v).x) - E

    def g(m: tuple[float, float]) -> float:  # zero once E(u) is E to 2e-16 E
        return 0.0 if abs(m[1]) < 2e-16 * E else m[1]

    return illinois(g, at, b - a, Ea - E, Eb - E, 0.0, maxiter=200)[0]


def choreo_branch(
    problem: ShootingProblem,
    members: Sequence[Member],
    points: Sequence[SpecialPoint],
    E_range: tuple[float, float],
    stop: str,
    reason: str,
) -> Branch:
    """The :class:`~rotorlib.orbits.family.Branch` of a choreography family: the ``members`` (in
    order along the family) with ``E`` in ``E_range`` and the ``points`` there, each
    ``index`` (counted in ``members``) counted again among those kept (-1: before the
    first); ``stop`` names the two ends, ``reason`` says where the family exists."""
    lo, hi = E_range
    keep = [i for i, m in enumerate(members) if lo <= float(m.E) <= hi]
    pts = [
        replace(p, index=sum(k <= p.index for k in keep) - 1)
        for p in points
        if lo <= p.E <= hi
    ]
    return Branch(
        problem,
        FLOAT64,
        tuple(members[i] for i in keep),
        tuple(sorted(pts, key=lambda p: p.E)),
        stop,
        reason,
        (lo, hi),
    )


def orbits_at_energy(
    p: ShootingProblem,
    members: Sequence[Member],
    E: str,
    digits: int | None,
    label: str,
    order: int = 6,
    power: int = 1,
) -> tuple[PeriodicOrbit, ...]:
    """Every member at energy ``E`` (a decimal string) of the family of the problem ``p``
    followed as ``members`` (in order along it), distinct up to symmetry, ordered by
    period: each the root of ``E(u) = E`` between two members (:func:`amplitude_at_energy`),
    re-solved at fixed ``E`` in the tier of ``digits`` (> 15), as
    :func:`reduced_orbit` (``order``, ``power``). Shared by the Z3 families
    (:mod:`rotorlib.beyond.choreo_z3`) and those born from CG
    (:mod:`rotorlib.beyond.choreo_resonance`)."""
    t = tier(digits) if digits is not None and digits > 15 else FLOAT64
    Ef = float(E)
    found: list[tuple[float, Any]] = []
    for a, b in zip(members, members[1:]):
        if not (float(a.E) - Ef) * (float(b.E) - Ef) <= 0 or a.E == b.E:
            continue
        u = amplitude_at_energy(p, float(a.u), float(b.u), float(a.E), float(b.E), Ef)
        with t.context():
            w = t.num(str(E)) if t.extended else Ef
            if t.extended:
                ut = t.num(u)
                u = solve(p, ut, ut * (1 + t.num("1e-12")), E=w, digits=t).x
            T = float(p.factor * residual(p, u, w, t).t1)
        if any(abs(T - T2) < 1e-8 * T for T2, _ in found):
            continue  # the same orbit on the other symmetric half
        found.append((T, u))
    with t.context():
        w = t.num(str(E)) if t.extended else Ef
    return tuple(
        reduced_orbit(p, u, w, t, label, digits, order=order, power=power)
        for _, u in sorted(found, key=lambda v: v[0])
    )


def member_number(
    label: str, orbits: Sequence[PeriodicOrbit], E: Any, branch: int, why_none: str
) -> PeriodicOrbit:
    """The member number ``branch`` (by period) of ``orbits``, the members of ``label`` at
    ``E``; ``extra`` adds ``branch`` and ``members_at_E``. ValueError when there is none
    (``why_none`` says why) or no member number ``branch``."""
    if not orbits:
        raise ValueError(f"{label} has no member at E = {E}: {why_none}")
    if not 0 <= int(branch) < len(orbits):
        raise ValueError(
            f"{label} has {len(orbits)} member(s) at E = {E} (branch 0 to "
            f"{len(orbits) - 1}, by period), not branch {branch}"
        )
    o = orbits[int(branch)]
    return replace(
        o, extra={**o.extra, "branch": int(branch), "members_at_E": len(orbits)}
    )
