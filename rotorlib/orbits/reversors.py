"""Reversing symmetries of the 3-rotor Hamiltonian and their fixed sets (for the atlas).

In the relative angles ``phi = (phi1, phi2)`` on the torus ``(2 pi Z)^2`` the potential
``V = 3 - cos phi1 - cos phi2 - cos phi3`` (``phi3 = -phi1 - phi2``) and the kinetic metric
``(phi1'^2 + phi2'^2 + phi1' phi2') / 3`` are invariant under the permutations of
``(phi1, phi2, phi3)`` (relabelling the rotors) and ``phi -> -phi``: the dihedral group
``D6`` of the hexagonal torus, found here by enumerating the integer matrices that preserve
both (:func:`symmetry_group`). With time reversal ``T: (q, p, t) -> (q, -p, -t)``, every
``g`` with ``g^2 = 1`` gives a reversing symmetry ``R = T g`` (``g`` acting on momenta by its
cotangent lift ``g^-T``): ``g = 1`` (pure time reversal), ``g = -1`` and the six reflections.
Their fixed sets ``Fix R = {x : R x = x}`` on the energy shell are one-parameter curves:

* ``T``: ``p = 0`` on the equipotential ``V = E`` (brake points; ``E < 4.5`` only);
* ``T (-1)``: a point with ``2 phi = 0 mod 2 pi`` (G, or a saddle D1..D3 for ``E > 4``) and any
  momentum of kinetic energy ``E - V``: a circle;
* ``T g`` for a reflection ``g``: ``phi`` on the mirror (a closed geodesic of the torus) and
  ``p`` in the ``-1`` eigenspace of ``g^-T``.

:func:`targets` lists them (in the pendulum variables of the engine,
``a1 = phi1/2``, ``a2 = phi1/2 + phi2``): every fixed set is a target. Up to the group
the start sets reduce to five classes (brake, G, D, mirror of a transposition, mirror of a
negated transposition): :func:`start_sets`.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.flow import Section
from ..core.precision import Tier, tier
from .shooting import StartSet

__all__ = [
    "symmetry_group",
    "Reversor",
    "reversors",
    "FixedSet",
    "start_sets",
    "targets",
    "CircleSet",
    "BrakeSet",
    "MirrorSet",
    "images",
]

#: ``a = A phi`` (pendulum variables); momenta transform with ``A^-T``.
A = np.array([[0.5, 0.0], [0.5, 1.0]])
_G = np.array([[1.0, 0.5], [0.5, 1.0]]) / 3.0  # kinetic metric of phi'


def _V(phi):
    f1, f2 = phi
    return 3 - math.cos(f1) - math.cos(f2) - math.cos(f1 + f2)


@functools.cache
def symmetry_group() -> tuple[np.ndarray, ...]:
    """The integer 2x2 matrices ``g`` (acting on ``phi``) that preserve V and the metric.

    Examples
    --------
    >>> from rotorlib.orbits.reversors import symmetry_group
    >>> len(symmetry_group())  # D6: the permutations of (phi1, phi2, phi3) and -1
    12
    """
    pts = np.random.default_rng(1).uniform(0, 2 * math.pi, (20, 2))
    candidates = (
        np.array(e, float).reshape(2, 2)
        for e in itertools.product((-1, 0, 1), repeat=4)
    )
    return tuple(
        g
        for g in candidates
        if abs(np.linalg.det(g)) == 1
        and np.allclose(g.T @ _G @ g, _G)
        and all(abs(_V(g @ p) - _V(p)) < 1e-12 for p in pts)
    )


@dataclass(frozen=True)
class Reversor:
    """``R = T g`` for an involution ``g`` of the group: ``name``, the matrix ``g`` (on phi)."""

    name: str
    g: tuple

    @property
    def kind(self) -> str:
        tr = self.g[0][0] + self.g[1][1]
        return "time reversal" if tr == 2 else "point" if tr == -2 else "mirror"


#: The involutions ``g`` (entries row by row) named by what they do to ``(phi1, phi2, phi3)``.
_INVOLUTIONS = {
    (1, 0, 0, 1): "1",
    (-1, 0, 0, -1): "-1",
    (0, 1, 1, 0): "(12)",
    (-1, -1, 0, 1): "(13)",
    (1, 0, -1, -1): "(23)",
    (0, -1, -1, 0): "-(12)",
    (1, 1, 0, -1): "-(13)",
    (-1, 0, 1, 1): "-(23)",
}


@functools.cache
def reversors() -> tuple[Reversor, ...]:
    """The eight reversing symmetries ``T g``, ``g^2 = 1``, named by what ``g`` does to
    ``(phi1, phi2, phi3)`` (``1``, ``-1``, ``(12)``, ``(13)``, ``(23)``, ``-(12)`` ...): the
    involutions of :func:`symmetry_group`.

    Examples
    --------
    >>> from rotorlib.orbits.reversors import reversors
    >>> [(r.name, r.kind) for r in reversors()][:3]
    [('1', 'time reversal'), ('-1', 'point'), ('(12)', 'mirror')]
    """
    found = {
        tuple(int(v) for v in g.ravel())
        for g in symmetry_group()
        if np.allclose(g @ g, np.eye(2))
    }
    assert found == set(_INVOLUTIONS), found
    return tuple(Reversor(name, (g[:2], g[2:])) for g, name in _INVOLUTIONS.items())


@dataclass(frozen=True)
class FixedSet:
    """One component of ``Fix R`` on the energy shell.

    Attributes
    ----------
    name : str
        ``Fix T``, ``Fix T(-1) at G``, ``Fix T(12)`` ...
    reversor : Reversor
    section, condition : Section
        The event that crosses the fixed set (a configuration line, or ``p2 = 0`` for brake
        points) and the residual that vanishes on it, in the engine's variables.
    """

    name: str
    reversor: Reversor
    section: Section
    condition: Section


def _alpha_form(n_phi):
    """A linear form ``n . phi`` written on the pendulum variables: ``n . A^-1 a``."""
    return tuple(float(v) for v in np.array(n_phi) @ np.linalg.inv(A))


def _integers(v: np.ndarray) -> np.ndarray:
    """``v`` scaled so that its smallest nonzero entry is ``+-1``: integers here, so exact in
    every tier."""
    v = v / np.min(np.abs(v[np.abs(v) > 1e-9]))
    assert np.allclose(v, np.round(v)), v
    return np.round(v)


def _reversed_momentum(g: np.ndarray) -> np.ndarray:
    """The momentum (in ``phi``) that ``T g`` fixes: the ``-1`` eigenvector of ``g^-T``."""
    w, vec = np.linalg.eig(np.linalg.inv(g).T)
    return vec[:, int(np.argmin(w))]


def _mirror(g):
    """``(e, n, g_v)``: the mirror's direction ``e`` and normal form ``n`` (integers) and the
    number of its components ``g_v``: ``Fix g = {n . phi = 0 mod 2 pi / g_v}``."""
    gm = np.array(g, float)
    w, vec = np.linalg.eig(gm)
    e = _integers(vec[:, int(np.argmax(w))]).astype(int)
    n = np.array([-e[1], e[0]])
    d = gm - np.eye(2)  # rank one: d = v n^T
    k = 0 if n[0] else 1
    v = d[:, k] / n[k]
    return e, n, math.gcd(int(round(abs(v[0]))), int(round(abs(v[1]))))


@functools.cache
def targets() -> tuple:
    """Every fixed-set component of the eight reversors (:class:`FixedSet`): every symmetric
    orbit meets two of them half a period apart."""
    out = []
    for r in reversors():
        if r.kind == "time reversal":
            out.append(
                FixedSet("Fix T", r, Section((0, 0, 0, 1)), Section((0, 0, 1, 0)))
            )
        elif r.kind == "point":
            for name, q in (
                ("G", (0, 0)),
                ("D1", (1, 1)),
                ("D2", (1, 0)),
                ("D3", (0, 1)),
            ):
                out.append(
                    FixedSet(
                        f"Fix T(-1) at {name}",
                        r,
                        Section(_alpha_form((1, 0)) + (0, 0), q[0], 0, 2.0),
                        Section(_alpha_form((0, 1)) + (0, 0), q[1], 0, 2.0),
                    )
                )
        else:
            g = np.array(r.g, float)
            e, n, gv = _mirror(g)
            b = _reversed_momentum(g)
            # m . P = 0 on the fixed set, m = (-b2, b1); P_phi = A^T p_alpha
            m_alpha = _integers(A @ np.array([-b[1], b[0]]))
            out.append(
                FixedSet(
                    f"Fix T{r.name}",
                    r,
                    Section(_alpha_form(n) + (0, 0), 0.0, 0, 2.0 / gv),
                    Section((0, 0) + tuple(float(v) for v in m_alpha)),
                )
            )
    return tuple(out)


# --------------------------------------------------------------------------- start sets


@dataclass(frozen=True)
class _Curve:
    """A one-parameter start set named ``name``: :meth:`at` gives the state at parameter
    ``u`` on the shell ``E``, for ``u`` in :meth:`span` (a closed curve: ``0 <= u < 2 pi``)."""

    name: str

    def span(self, E: Any) -> Any:
        return (0.0, 2 * math.pi)


@dataclass(frozen=True)
class CircleSet(_Curve):
    """``Fix T(-1)`` at a point: ``q = q0`` and ``p = sqrt(K) (sin u c + cos u b)`` with ``c``,
    ``b`` of unit kinetic energy, ``-pi/2 < u < pi/2`` (the other half is the image under -1)."""

    q0: tuple

    def bound(self, u: Any, digits: int | Tier | None = None) -> Any:
        t = tier(digits)
        with t.context():
            q, c = [self.q0[0] * t.pi, self.q0[1] * t.pi], t.m.cos
            return 3 - c(2 * q[0]) - c(q[1] - q[0]) - c(q[0] + q[1])

    def at(self, u: Any, E: Any, digits: int | Tier | None = None) -> Any:
        t = tier(digits)
        with t.context():
            u, K = t.num(u), t.num(E) - self.bound(u, t)
            if K < 0:
                raise ValueError(f"{self.name}: E below V there")
            s = t.m.sqrt(K)
            return [
                self.q0[0] * t.pi,
                self.q0[1] * t.pi,
                2 * s * t.m.sin(u),
                2 * s * t.m.cos(u) / t.m.sqrt(3),
            ]

    def span(self, E: Any) -> Any:
        return (-math.pi / 2, math.pi / 2)


@dataclass(frozen=True)
class BrakeSet(_Curve):
    """``Fix T``: ``p = 0`` on the equipotential ``V = E`` around ``centre`` (``phi``, units of
    pi: G for ``E < 4``, the maximum T1 for ``4 < E < 4.5``), parametrised by the polar angle
    ``u`` in the ``phi`` plane; the radius is solved from ``V = E`` (Brent in float64, then
    Newton in the tier)."""

    centre: tuple

    def _radius(self, u, E, t):
        from scipy.optimize import brentq

        c = (self.centre[0] * math.pi, self.centre[1] * math.pi)
        d = (math.cos(float(u)), math.sin(float(u)))

        def f(r):
            return _V((c[0] + r * d[0], c[1] + r * d[1])) - float(E)

        hi = 0.05
        while f(hi) * f(0.0) > 0 and hi < 4.0:
            hi *= 1.5
        r = brentq(f, 0.0, hi, xtol=1e-15)
        if not t.extended:
            return r
        m = t.m
        with t.context():
            u, E, r = t.num(u), t.num(E), t.num(r)
            cu, su = m.cos(u), m.sin(u)
            for _ in range(8):
                f1, f2 = self.centre[0] * t.pi + r * cu, self.centre[1] * t.pi + r * su
                V = 3 - m.cos(f1) - m.cos(f2) - m.cos(f1 + f2)
                dV = (m.sin(f1) + m.sin(f1 + f2)) * cu + (
                    m.sin(f2) + m.sin(f1 + f2)
                ) * su
                r = r - (V - E) / dV
            return r

    def at(self, u: Any, E: Any, digits: int | Tier | None = None) -> Any:
        t = tier(digits)
        with t.context():
            r = self._radius(u, E, t)
            f1 = self.centre[0] * t.pi + r * t.m.cos(t.num(u))
            f2 = self.centre[1] * t.pi + r * t.m.sin(t.num(u))
            return [f1 / 2, f1 / 2 + f2, t.num(0), t.num(0)]


@functools.lru_cache(maxsize=256)
def _arcs(line: StartSet, E: float):
    """The allowed arcs ``(x_a, x_b)`` (``V < E``, ``x_a < x_b``, positions along ``line``
    within one period ``2 pi``) between turning points, or ``None`` when ``V < E`` on the whole
    line. Turning points by Brent in float64, moved inward by ``1e-13`` so that ``K > 0`` at
    the ends in every tier (the momentum left out, ``~3e-7``, is that of a brake point)."""
    from scipy.optimize import brentq

    def f(x):
        return line.bound(x) - E

    xs = np.linspace(0.0, 2 * math.pi, 4001)
    fs = np.array([f(x) for x in xs])
    roots = [
        brentq(f, xs[i], xs[i + 1], xtol=1e-15, rtol=1e-15)
        for i in range(len(xs) - 1)
        if fs[i] * fs[i + 1] < 0
    ]
    if not roots:
        return None if fs[0] < 0 else ()
    if fs[0] > 0:  # arcs between roots 0-1, 2-3, ...
        pairs = list(zip(roots[0::2], roots[1::2]))
    else:  # the arc through x = 0 wraps around
        pairs = list(zip(roots[1::2], roots[2::2])) + [
            (roots[-1], roots[0] + 2 * math.pi)
        ]
    return tuple((a + 1e-13, b - 1e-13) for a, b in pairs)


@dataclass(frozen=True)
class MirrorSet(_Curve):
    """``Fix T g`` for a reflection: ``phi`` on the mirror, ``p`` along the ``-1`` eigenvector of
    ``g^-T``, over one closed geodesic of the torus, ``0 <= u < 2 pi``.

    Where the whole mirror is allowed (``V < E`` on it) ``u`` is the position along it. Below
    the mirror's highest potential it is cut into arcs ending at turning points, where the
    momentum grows like the square root of the distance: ``u`` is then split among the arcs in
    proportion to their lengths and each share maps to its arc as
    ``x = x_a + (x_b - x_a) sin^2(theta / 2)``, ``0 <= theta <= pi``, so that the momentum
    is smooth in ``u`` at the turning points (on a uniform grid in position a start ``1e-8``
    from a turning point is resolved only after ~20 bisections), and ``K = E - V`` is taken
    from the nearer end as a sum of products of sines (no cancellation near a turning point:
    float64 starts there are smooth in ``u`` to ~1e-16, not ~1e-9).
    """

    line: StartSet

    def at(self, u: Any, E: Any, digits: int | Tier | None = None) -> Any:
        t = tier(digits)
        arcs = _arcs(self.line, float(E))
        if arcs is None:
            return self.line.at(u, E, t)
        if not arcs:
            raise ValueError(f"{self.name}: E below V on the whole mirror")
        L = [b - a for a, b in arcs]
        shares = np.cumsum([0.0] + [2 * math.pi * v / sum(L) for v in L])
        turns = math.floor(float(u) / (2 * math.pi))
        v = float(u) - 2 * math.pi * turns
        i = min(int(np.searchsorted(shares, v, "right")) - 1, len(L) - 1)
        a, b = arcs[i]
        with t.context():
            v = t.num(u) - 2 * turns * t.pi - t.num(shares[i])
            half = v * t.pi / t.num(shares[i + 1] - shares[i]) / 2  # theta / 2
            # the arc's length from its ends in the tier: a float enters a tier as its
            # shortest decimal (Tier.num), so num(b - a) differs from num(b) - num(a)
            # by ~1e-16, and the two forms would not meet at the arc's middle
            span = t.num(b) - t.num(a)
            end, s = (
                (a, span * t.m.sin(half) ** 2)
                if float(half) < math.pi / 4
                else (b, -span * t.m.cos(half) ** 2)
            )
            K = t.num(E) - self.line.bound(t.num(end), t) - self._rise(end, s, t)
            return self.line.state(t.num(end) + s, K, t)

    def _rise(self, x, s, t: Tier):
        """``V(x + s) - V(x)`` along the mirror as a sum of products of sines (relative
        precision also for small ``s``)."""
        m, q, d = t.m, self.line._q(t.num(x), t), self.line.a
        terms = (
            (2 * q[0], 2 * d[0]),
            (q[1] - q[0], d[1] - d[0]),
            (q[0] + q[1], d[0] + d[1]),
        )
        return sum(2 * m.sin(c + s * k / 2) * m.sin(s * k / 2) for c, k in terms if k)


def start_sets(E: Any) -> tuple:
    """One start set per class of fixed sets under the group (every symmetric orbit meets one
    of them, up to a symmetry): brake points (``E < 4.5``), the circle at G, the circle at D1
    (``E > 4``), the mirror of (12) (the breathers' line ``phi1 = phi2``) and of -(12)."""
    E = float(E)
    return _start_sets(0 if E < 4.0 else 1 if E < 4.5 else 2)


@functools.cache
def _start_sets(regime) -> tuple:
    out: list = []
    if regime == 0:
        out.append(BrakeSet("Fix T (around G)", (0.0, 0.0)))
    elif regime == 1:
        out.append(BrakeSet("Fix T (around T1)", (2 / 3, 2 / 3)))
    out.append(CircleSet("Fix T(-1) at G", (0.0, 0.0)))
    if regime > 0:
        out.append(CircleSet("Fix T(-1) at D1", tuple(A @ np.array([1.0, 1.0]))))
    for r in reversors():
        if r.name in ("(12)", "-(12)"):
            g = np.array(r.g, float)
            e, _, _ = _mirror(g)
            b = _integers(np.linalg.inv(A).T @ _reversed_momentum(g))  # A^-T P_phi
            ae = A @ e.astype(float)
            out.append(
                MirrorSet(
                    f"Fix T{r.name}",
                    StartSet(
                        f"Fix T{r.name}",
                        a=(float(ae[0]), float(ae[1])),
                        b=(float(b[0]), float(b[1])),
                    ),
                )
            )
    return tuple(out)


def _group_images() -> np.ndarray:
    """The 24 linear maps of the state ``(a1, a2, p1, p2)``: the group (12) and time reversal
    (``q = A g A^-1`` on the angles, ``+-q^-T`` on the momenta)."""
    from scipy.linalg import block_diag

    qs = [A @ g @ np.linalg.inv(A) for g in symmetry_group()]
    return np.array(
        [block_diag(q, s * np.linalg.inv(q).T) for q in qs for s in (1, -1)]
    )


def images(state: Any) -> np.ndarray:
    """The 24 images of a state ``[a1, a2, p1, p2]`` under the symmetry group and time
    reversal (the same orbit seen by relabelled rotors, or run backwards): shape ``(24, 4)``,
    the identity first."""
    maps = _group_images()
    identity_first = np.argsort(
        [not np.allclose(m, np.eye(4)) for m in maps], kind="stable"
    )
    return maps[identity_first] @ np.asarray(state, float)
