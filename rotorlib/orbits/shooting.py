"""Symmetric shooting for periodic orbits (paper §6): the problem, its residual, its corrector.

The flow is reversible: with ``T`` the reversal of time (``p -> -p``) and ``g`` a
symmetry of V, ``R = T g`` maps orbits to orbits run backwards. An orbit through a
point of ``Fix R1`` that meets ``Fix R2`` at ``t1`` is periodic: ``x(t + 2 t1) =
R2 R1 x(t)``, so its period is ``2 t1`` times the order of ``R2 R1`` (``factor``).
A :class:`ShootingProblem` says where the orbit starts (:class:`StartSet`, one
parameter ``u`` at given energy), which fixed set it must meet (a
:class:`~rotorlib.core.flow.Section` crossed as an event, and a ``condition`` that
vanishes on the fixed set), at which crossing, and the lattice vector it closes
on. Its residual :func:`residual` is one number of two unknowns ``(u, w)``; ``w``
is the energy ``E`` or, with ``K_ref``, the free kinetic energy ``K - K_ref`` at
the start (the chart of the rotational families, where ``E - 4`` is formed without
cancellation). The energy shell is exact by construction: no unfolding term.

Correctors: :func:`secant` in one unknown (:func:`solve`), and Newton with the
variational equations (the gradient of the residual, corrected for the moving
event time) in :mod:`rotorlib.orbits.continuation`.

Precision: every quantity is computed in the :class:`~rotorlib.core.precision.Tier`
asked for; the residual carries ``~eps / |E - 4|`` round-off near the separatrix.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

from ..core.flow import Section, SectionNotReached, to_section
from ..core.precision import Tier, tier
from ..core.system import rhs_alpha

__all__ = [
    "StartSet",
    "ShootingProblem",
    "Shot",
    "Root",
    "NoConvergence",
    "residual",
    "secant",
    "solve",
]


def _kin(p):
    """Kinetic energy ``p1^2/4 + 3 p2^2/4``."""
    return p[0] * p[0] / 4 + 3 * p[1] * p[1] / 4


@dataclass(frozen=True)
class StartSet:
    """Initial states on a fixed set of a reversing symmetry, one parameter ``u``.

    ``q = q0 pi + u a`` and ``p = u c + sqrt(K / K(b)) b`` (``c`` and ``b``
    orthogonal in the kinetic metric), so ``E = K + V(q) + u^2 K(c)``: ``K`` is the
    kinetic energy left for the direction ``b``.

    Attributes
    ----------
    name : str
    q0, a, c, b : tuple of 2 floats
        Base point (units of pi), configuration direction, momentum directions.
    """

    name: str
    q0: tuple[float, float] = (0.0, 0.0)
    a: tuple[float, float] = (0.0, 0.0)
    c: tuple[float, float] = (0.0, 0.0)
    b: tuple[float, float] = (0.0, 1.0)

    def __post_init__(self):
        if self.c[0] * self.b[0] / 4 + 3 * self.c[1] * self.b[1] / 4:
            raise ValueError(
                f"{self.name}: c and b must be orthogonal in the kinetic metric"
            )

    def _q(self, u, t: Tier):
        return [
            q0 * t.pi + u * a if q0 or t.extended else u * a  # exact zeros in float64
            for q0, a in zip(self.q0, self.a)
        ]

    def _v(self, q, t: Tier):
        if t.extended:
            return 3 - t.m.cos(2 * q[0]) - t.m.cos(q[1] - q[0]) - t.m.cos(q[0] + q[1])
        from ..core.system import potential_alpha

        return float(potential_alpha(q[0], q[1]))

    def bound(self, u: Any, digits: int | Tier | None = None) -> Any:
        """``V(q(u)) + u^2 K(c)``: the energy at ``u`` with ``K = 0``."""
        t = tier(digits)
        with t.context():
            return self._v(self._q(u, t), t) + u * u * _kin(self.c)

    def at(self, u: Any, E: Any, digits: int | Tier | None = None) -> list[Any]:
        """The state at ``u`` on the energy shell ``E`` (the protocol every start set keeps)."""
        t = tier(digits)
        with t.context():
            u = t.num(u)
            return self.state(u, t.num(E) - self.bound(u, t), t)

    def state(self, u: Any, K: Any, digits: int | Tier | None = None) -> list[Any]:
        """``[a1, a2, p1, p2]`` at ``(u, K)`` (tier numbers). ``K < 0`` raises ValueError."""
        t = tier(digits)
        with t.context():
            u, K = t.num(u), t.num(K)
            if K < 0:
                raise ValueError(
                    f"{self.name}: u = {float(u)!r} is outside the energy shell"
                )
            s = t.m.sqrt(K / _kin(self.b))
            return self._q(u, t) + [
                u * c + s * b if b or c else t.num(0) for c, b in zip(self.c, self.b)
            ]


@dataclass(frozen=True)
class ShootingProblem:
    """A symmetric periodic orbit as a root of one residual (see the module docstring).

    Attributes
    ----------
    label : str
    start : StartSet
    section : Section
        The event: the orbit's ``crossing``-th crossing of it is the symmetric point.
    condition : Section
        Vanishes on the target fixed set (its ``level`` and ``period`` are used, its
        ``direction`` is not); the residual is its value at the event.
    crossing : int
    factor : int
        Period = ``factor * t1``.
    lattice : tuple
        ``(a1, a2)`` displacement over one period, in units of pi.
    trivial : float or None
        A known root ``u = trivial`` of the condition for every ``w`` (the parent orbit,
        e.g. the pendulum at ``u = 0``), divided out of the residual.
    K_ref : float or None
        Chart: ``None``, the second unknown is ``E``; else it is ``K - K_ref``.
    t_max : float
        Integration limit of one shot.
    abort : Section or None
        A shot that crosses it before ``section`` has failed (ends at once).
    """

    label: str
    start: StartSet
    section: Section
    condition: Section
    crossing: int = 1
    factor: int = 2
    lattice: tuple[float, float] = (0.0, 0.0)
    trivial: float | None = None
    K_ref: float | None = None
    t_max: float = 1e3
    abort: Section | None = None

    def chart(self, K_ref: float | None = None) -> ShootingProblem:
        """The same problem with the second unknown ``E`` (``K_ref=None``) or ``K - K_ref``."""
        return replace(self, K_ref=K_ref)

    def energy(self, u: Any, w: Any, digits: int | Tier | None = None) -> Any:
        """``E`` at ``(u, w)``."""
        t = tier(digits)
        if self.K_ref is None:
            return t.num(w)
        with t.context():
            return t.num(self.K_ref) + t.num(w) + self.start.bound(t.num(u), t)

    def w_at(self, u: Any, E: Any, digits: int | Tier | None = None) -> Any:
        """The second unknown at amplitude ``u`` and energy ``E``."""
        t = tier(digits)
        if self.K_ref is None:
            return t.num(E)
        with t.context():
            return t.num(E) - t.num(self.K_ref) - self.start.bound(t.num(u), t)

    def state(self, u: Any, w: Any, digits: int | Tier | None = None) -> list[Any]:
        """Initial state ``[a1, a2, p1, p2]`` at ``(u, w)``."""
        t = tier(digits)
        if self.K_ref is None:
            return self.start.at(u, w, t)
        with t.context():
            return self.start.state(t.num(u), t.num(self.K_ref) + t.num(w), t)


@dataclass(frozen=True)
class Shot:
    """One evaluation of the residual.

    Attributes
    ----------
    r : float or mpf
        The residual (deflated by ``u - trivial``).
    t1 : float or mpf
        Time of the symmetric point (period = ``factor * t1``).
    x0, x1 : list
        Initial state and state at ``t1``.
    grad : tuple or None
        ``(dr/du, dr/dw)`` (with ``derivative=True``).
    """

    r: Any
    t1: Any
    x0: list
    x1: list
    grad: tuple | None = None


def _cond(section: Section, x, t: Tier):
    """The condition's value (modular conditions as ``(P/pi) sin(pi (c.x - L)/P)``: a unit
    slope at every translate) and its derivative factor."""
    y = section.value(x) - section.level * t.pi if section.level else section.value(x)
    if section.period is None:
        return y, 1
    k = t.pi / (section.period * t.pi)
    return t.m.sin(k * y) / k, t.m.cos(k * y)


def residual(
    problem: ShootingProblem,
    u: Any,
    w: Any,
    digits: int | Tier | None = None,
    derivative: bool = False,
) -> Shot:
    """The residual at ``(u, w)`` in the tier of ``digits``; raises SectionNotReached
    or ValueError.

    With ``derivative``, the variational equations give ``dx1/dx0 = (I - f s^T/(s.f)) Phi``
    (``Phi`` at fixed time, ``s`` the section's normal, ``f`` the vector field at the
    event), hence ``dr/du`` and ``dr/dw``.
    """
    t = tier(digits)
    with t.context():
        u, w = t.num(u), t.num(w)
        x0 = problem.state(u, w, t)
        t1, x1, *Phi = to_section(  # Phi: [the fundamental matrix] with derivative
            x0,
            problem.section,
            t,
            problem.crossing,
            problem.t_max,
            derivative,
            problem.abort,
        )
        g, dg = _cond(problem.condition, x1, t)
        d = 1 if problem.trivial is None else u - t.num(problem.trivial)
        if problem.trivial is not None and d == 0:
            raise ValueError(
                f"{problem.label}: u = {problem.trivial} is the parent orbit"
            )
        r = g / d
        if not derivative:
            return Shot(r, t1, x0, x1)
        c = [ci * dg for ci in problem.condition.c]
        grad = _gradient(problem, u, w, x0, Phi[0], x1, t)  # (dx1/du, dx1/dw)
        dr = [sum(ci * gi for ci, gi in zip(c, col)) / d for col in grad]
        if problem.trivial is not None:
            dr[0] -= r / d
        return Shot(r, t1, x0, x1, tuple(dr))


def _gradient(problem, u, w, x0, Phi, x1, t: Tier):
    """``(dx1/du, dx1/dw)``: the start set differentiated (in closed
    form for a :class:`StartSet`, by central differences of its ``at`` otherwise), the flow
    by its fundamental matrix, the event time by implicit differentiation of the section."""
    st = problem.start
    if isinstance(st, StartSet):
        K = (x0[2] * x0[2] / 4 + 3 * x0[3] * x0[3] / 4) - u * u * _kin(st.c)
        dp_dK = (
            [bi / (2 * t.m.sqrt(K * _kin(st.b))) for bi in st.b] if K > 0 else [0, 0]
        )
        f0 = rhs_alpha(0.0, x0)
        dK_du = (
            0
            if problem.K_ref is not None
            # K = E - V(q(u)) - u^2 K(c)
            else ((f0[2] * st.a[0] + f0[3] * st.a[1]) - 2 * u * _kin(st.c))
        )
        cols = [
            [st.a[0], st.a[1], st.c[0] + dp_dK[0] * dK_du, st.c[1] + dp_dK[1] * dK_du],
            [0, 0, dp_dK[0], dp_dK[1]],
        ]
    else:
        h = t.num(t.eps) ** (t.num(1) / 3)
        cols = [
            [
                (a - b) / (2 * h)
                for a, b in zip(problem.state(u + h, w, t), problem.state(u - h, w, t))
            ],
            [
                (a - b) / (2 * h)
                for a, b in zip(problem.state(u, w + h, t), problem.state(u, w - h, t))
            ],
        ]
    f = rhs_alpha(0.0, x1)
    s = problem.section.c
    sf = sum(si * fi for si, fi in zip(s, f))
    out = []
    for v in cols:
        y = [sum(Phi[i][j] * v[j] for j in range(4)) for i in range(4)]
        dt = -sum(si * yi for si, yi in zip(s, y)) / sf  # the event time moves
        out.append([yi + fi * dt for yi, fi in zip(y, f)])
    return out


@dataclass(frozen=True)
class Root:
    """Result of :func:`secant`: ``x``, ``|f(x)|``, iterations and whether the step converged."""

    x: Any
    residual: Any
    iterations: int
    converged: bool


class NoConvergence(ValueError):
    """A corrector failed.

    Attributes
    ----------
    label : str
    fixed : dict
        The fixed coordinate (``{"E": ...}`` or ``{"u": ...}``) as floats.
    best : Root or None
    """

    def __init__(self, label: str, fixed: Any, best: Any = None, why: str = ""):
        where = ", ".join(f"{k} = {float(v)!r}" for k, v in fixed.items())
        super().__init__(
            f"{label}: the shooting did not converge at {where}"
            + (f" ({why})" if why else "")
        )
        self.label, self.fixed, self.best = (
            label,
            {k: float(v) for k, v in fixed.items()},
            best,
        )


# --------------------------------------------------------------------------- PALC


def _reachable(f, x, good, shrink):
    """``(x, f(x))`` with ``x`` moved back towards ``good`` (the step divided by ``shrink``,
    at most 30 times) while ``f`` raises SectionNotReached or ValueError."""
    for _ in range(30):
        try:
            return x, f(x)
        except (SectionNotReached, ValueError):
            x = good + (x - good) / shrink
    raise SectionNotReached(0.0, 0)


def secant(
    f: Callable[[Any], Any],
    x0: Any,
    x1: Any,
    tol: Any,
    floor: Any = 0.0,
    maxiter: int = 40,
) -> Root:
    """Secant iteration on a scalar ``f``.

    A point beyond the section's reach (``f`` raises SectionNotReached or ValueError)
    is moved back towards the last good one. Stops when the step falls below
    ``tol * max(|x|, floor)`` (converged) or stops shrinking after 3 iterations (the
    round-off floor of ``f``); returns the iterate with the smallest ``|f|`` then.
    """
    fx0 = f(x0)
    x1, fx1 = _reachable(f, x1, x0, 8)
    best = (abs(fx1), x1) if abs(fx1) < abs(fx0) else (abs(fx0), x0)
    last = None
    it = 0
    for it in range(maxiter):
        if fx1 == fx0:
            break
        x2, fx2 = _reachable(f, x1 - fx1 * (x1 - x0) / (fx1 - fx0), x1, 2)
        dx = abs(x2 - x1)
        x0, fx0, x1, fx1 = x1, fx1, x2, fx2
        if abs(fx1) < best[0]:
            best = (abs(fx1), x1)
        if dx <= tol * max(abs(x1), floor) or fx1 == 0:
            return Root(x1, abs(fx1), it + 1, True)
        if last is not None and it >= 3 and dx >= last:
            break
        last = dx
    return Root(best[1], best[0], it + 1, False)


def solve(
    problem: ShootingProblem,
    x0: Any,
    x1: Any = None,
    *,
    u: Any = None,
    w: Any = None,
    E: Any = None,
    digits: int | Tier | None = None,
    tol: Any = None,
    floor: Any = 0.0,
    r_max: float | None = None,
) -> Root:
    """The member with amplitude ``u`` (solving for ``w``), or with second unknown ``w`` or
    energy ``E`` (solving for ``u``).

    A :func:`secant` from ``x0`` and ``x1`` to a step of ``tol * max(|x|, floor)`` (default
    tol :attr:`Tier.step_tol <rotorlib.core.precision.Tier.step_tol>`: 4e-15 float64, ``8 eps``
    extended). ``x1`` defaults to ``x0 (1 + 1e-4)`` in float64,
    ``x0 (1 + 1e-9)`` extended. Raises :class:`NoConvergence` unless
    ``|r| < r_max`` at the end (default :attr:`Tier.r_max
    <rotorlib.core.precision.Tier.r_max>`: 1e-8 float64, ``eps^(2/3)`` extended; ``math.inf``
    accepts any end).

    Examples
    --------
    >>> from rotorlib.paper.newborn import family_spec
    >>> from rotorlib.orbits.shooting import residual, solve
    >>> p = family_spec("IS^l_2").problem
    >>> root = solve(p, 0.1, E=3.999)  # the amplitude u of the member at E = 3.999
    >>> round(root.x, 8), bool(abs(residual(p, root.x, 3.999).r) < 1e-12)
    (0.12372003, True)
    """
    if sum(v is not None for v in (u, w, E)) != 1:
        raise ValueError("give exactly one of u, w and E")
    t = tier(digits)
    with t.context():
        tol = tol if tol is not None else t.step_tol
        r_max = r_max if r_max is not None else t.r_max
        x0 = t.num(x0)
        key, held = next(
            (k, t.num(v)) for k, v in zip("uwE", (u, w, E)) if v is not None
        )

        def f(x):  # the residual as a function of the other unknown
            if key == "u":
                return residual(problem, held, x, t).r
            return residual(
                problem, x, held if key == "w" else problem.w_at(x, held, t), t
            ).r

        if x1 is None:
            x1 = x0 * (1 + (1e-4 if not t.extended else t.num("1e-9")))
        root = secant(f, x0, t.num(x1), tol, floor)
        if not root.residual < r_max:
            raise NoConvergence(problem.label, {key: held}, root)
        return root
