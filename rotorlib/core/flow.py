"""The nonlinear flow in pendulum variables, its variational equations and section events.

Hamilton's equations of ``H = p1^2/4 + 3 p2^2/4 + 3 - cos 2a1 - cos(a2 - a1) -
cos(a1 + a2)`` (:func:`rotorlib.core.system.rhs_alpha`) are integrated with heyoka's
Taylor method at the tolerance of the :class:`~rotorlib.core.precision.Tier`
(machine epsilon: 2.2e-16 float64, 1.9e-34 real128, ``2^(1-bits)`` for
``mp<bits>``). Integrators are compiled once per (tier, section, variational)
and thread, and reused.

A :class:`Section` is a hyperplane ``c . x = level`` of the state
``x = [a1, a2, p1, p2]``, or the family of parallel hyperplanes ``c . x = level
(mod period)`` (the lattice translates of a symmetry line); it is crossed in a
``direction``. :func:`to_section` integrates to its k-th crossing, located by
heyoka's event root finder to the working precision.

heyoka is required here: it is a dependency of rotorlib on Linux x86_64 and aarch64,
the extra ``rotorlib[fast]`` elsewhere. Without it every function below raises
:class:`~rotorlib.core.precision.HeyokaMissing` (an ``ImportError`` whose one-line
message names the extra; the command line prints it and exits with status 2): no
scipy fallback integrates the flow.

Precision: near the separatrix the flow amplifies round-off like ``1/|E - 4|``
(the book's *Numerical notes*, ``book/numerical_notes.md``, "Where extended
precision is needed"): a tier keeps about ``digits + log10|E - 4|`` digits.
"""

from __future__ import annotations

import threading
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .precision import Tier, load_heyoka, tier
from .system import rhs_alpha

#: A state ``[a1, a2, p1, p2]``: floats, tier numbers or decimal strings, or an array.
StateLike = Sequence[Any] | np.ndarray

__all__ = [
    "Section",
    "SectionNotReached",
    "equations_of_motion",
    "to_section",
    "crossings",
    "flow",
    "monodromy_matrix",
    "states_at",
    "sample",
    "extrema",
]


@dataclass(frozen=True)
class Section:
    """``c . x = level * pi (mod period * pi)``, crossed in ``direction``.

    Attributes
    ----------
    c : tuple of 4 floats
        Coefficients on ``[a1, a2, p1, p2]`` (small dyadic rationals: exact in every tier).
    level : float
        The level in units of pi.
    direction : {1, -1, 0}
        Crossing with ``c . x`` increasing, decreasing, or either.
    period : float, optional
        In units of pi: every ``level + k period`` is the same section (a symmetry
        line and its lattice translates). ``None``: one hyperplane.
    """

    c: tuple
    level: float = 0.0
    direction: int = 0
    period: float | None = None

    def value(self, x: Any) -> Any:
        """``c . x`` (exact for the zero coefficients)."""
        return sum(ci * xi for ci, xi in zip(self.c, x) if ci)


def equations_of_motion(hy: Any = None) -> list[tuple[Any, Any]]:
    """Hamilton's equations in pendulum variables as heyoka ``(variable, expression)``
    pairs (:func:`rotorlib.core.system.rhs_alpha` in numpy): the one builder every heyoka
    integrator of the nonlinear flow uses (``hy``: the heyoka module, default
    :func:`~rotorlib.core.precision.load_heyoka`)."""
    hy = hy or load_heyoka()
    a1, a2, p1, p2 = hy.make_vars("a1", "a2", "p1", "p2")
    s_m, s_p = hy.sin(a2 - a1), hy.sin(a1 + a2)
    two, half, three_halves = (hy.expression(v) for v in (2.0, 0.5, 1.5))
    return [
        (a1, half * p1),
        (a2, three_halves * p2),
        (p1, -(two * hy.sin(two * a1) - s_m + s_p)),
        (p2, -(s_m + s_p)),
    ]


_LOCAL = threading.local()


def _integrator(t: Tier, sections, variational: bool, terminal=True):
    cache = _LOCAL.__dict__.setdefault("integrators", {})
    key = (t.name, sections, variational, terminal)
    if key not in cache:
        cache[key] = _build(t, sections, variational, terminal)
    return cache[key]


def _event_expr(hy, section, k):
    """The event function of ``section`` with parameters ``par[2k]``, ``par[2k + 1]``."""
    lin = sum(
        (
            hy.expression(float(ci)) * v
            for ci, v in zip(section.c, hy.make_vars("a1", "a2", "p1", "p2"))
            if ci
        ),
        hy.expression(0.0),
    )
    if section.period is None:
        d = {1: hy.event_direction.positive, -1: hy.event_direction.negative}
        return lin - hy.par[2 * k], d.get(section.direction, hy.event_direction.any)
    return hy.sin(hy.par[2 * k + 1] * lin - hy.par[2 * k]), hy.event_direction.any


def _build(t: Tier, sections, variational, terminal):
    """A heyoka integrator with terminal events (one per section) or, with
    ``terminal=False``, non-terminal events recording every crossing in ``ta.found``."""
    hy = load_heyoka()
    sys = equations_of_motion(hy)
    if variational:
        sys = hy.var_ode_sys(sys, hy.var_args.vars, order=1)
    ev_kw = {k: v for k, v in t.hy_kwargs.items() if k == "fp_type"}
    found = []
    events = []
    for k, section in enumerate(sections or ()):
        expr, d = _event_expr(hy, section, k)
        if terminal:
            events.append(hy.t_event(expr, direction=d, **ev_kw))
        else:

            def cb(ta, time, d_sgn, k=k):
                ta.update_d_output(time)
                found.append((k, time, ta.d_output[:4].copy()))

            events.append(hy.nt_event(expr, cb, direction=d, **ev_kw))
    ta = hy.taylor_adaptive(
        sys,
        t.hy_array([0.0] * 4),
        pars=t.hy_array(
            [0.0]
            * max(
                [
                    2 * k + (1 if s.period is None else 2)
                    for k, s in enumerate(sections or ())
                ]
                or [0]
            )
        ),
        compact_mode=variational or t.extended,
        **{"t_events" if terminal else "nt_events": events},
        **t.hy_kwargs,
    )
    return ta, found


def _set_levels(ta, t: Tier, sections):
    with t.context():
        for k, s in enumerate(sections):
            if s.period is None:
                ta.pars[2 * k] = t.to_hy(t.pi * s.level)
            else:
                ta.pars[2 * k] = t.to_hy(t.pi * s.level / s.period)
                ta.pars[2 * k + 1] = t.to_hy(1 / t.num(s.period))


def _start(ta, t: Tier, x0, variational):
    if ta.with_events:
        ta.reset_cooldowns()
    ta.time = t.to_hy(0.0)
    ta.state[:] = t.hy_array(
        list(x0) + (list(np.eye(4).ravel()) if variational else [])
    )


def _out(ta, t: Tier, variational):
    s = [t.from_hy(v) for v in ta.state]
    if not variational:
        return s
    return s[:4], [s[4 + 4 * i : 8 + 4 * i] for i in range(4)]


class SectionNotReached(RuntimeError):
    """The section was not crossed (``crossing`` times) before ``t_max``.

    Attributes
    ----------
    t_max : float
    crossings : int
        Crossings found before ``t_max``.
    """

    def __init__(self, t_max: Any, crossings: Any) -> None:
        super().__init__(
            f"section not reached before t = {float(t_max):g} ({crossings} crossings)"
        )
        self.t_max, self.crossings = t_max, crossings


def to_section(
    x0: StateLike,
    section: Section,
    digits: int | Tier | None = None,
    crossing: int = 1,
    t_max: float = 1e4,
    variational: bool = False,
    abort: Section | None = None,
) -> tuple[Any, ...]:
    """Integrate from ``x0`` at ``t = 0`` to the ``crossing``-th crossing of ``section``.

    Returns ``(t1, x1)`` or, with ``variational``, ``(t1, x1, Phi)`` where ``Phi`` is the
    4x4 fundamental matrix ``dx(t1)/dx0`` at fixed time (rows of tier numbers). Raises
    :class:`SectionNotReached` at ``t_max``, or as soon as ``abort`` is crossed first (e.g.
    ``a2`` turning back before it reaches the section of a rotation), or at once from an
    equilibrium (the vector field below ``1e-14`` in every component: a start set meets
    the saddle at ``E = 4``; heyoka's event at rest would fire again at every step). The
    tier is :func:`~rotorlib.core.precision.tier` of ``digits``.
    """
    if max(abs(float(v)) for v in rhs_alpha(0.0, [float(v) for v in x0])) < 1e-14:
        raise SectionNotReached(t_max, 0)
    t = tier(digits)
    secs = (section,) if abort is None else (section, abort)
    ta, _ = _integrator(t, secs, variational)
    _start(ta, t, x0, variational)
    _set_levels(ta, t, secs)
    found, tmax = 0, t.to_hy(t_max)
    while True:
        # -1: the terminal event of the section; anything else (the abort event, -2,
        # or heyoka's success, time limit and error outcomes): not reached
        if int(ta.propagate_until(tmax)[0]) != -1:
            raise SectionNotReached(t_max, found)
        if abs(float(ta.time)) < 1e-9 or not _right_way(
            section, [t.from_hy(v) for v in ta.state[:4]], t
        ):
            continue  # a start point on the section is not a crossing
        found += 1
        if found == crossing:
            out = _out(ta, t, variational)
            return (
                (t.from_hy(ta.time), *out) if variational else (t.from_hy(ta.time), out)
            )


def _right_way(section, x, t):
    """Whether a crossing at ``x`` goes in the section's direction (modular sections:
    heyoka's direction filter cannot tell the translates apart)."""
    if section.period is None or not section.direction:
        return True
    with t.context():
        return (section.value(rhs_alpha(0.0, x)) > 0) == (section.direction > 0)


def crossings(
    x0: StateLike,
    sections: Sequence[Section],
    t_max: float,
    digits: int | Tier | None = None,
) -> list[tuple[int, Any, list[Any]]]:
    """Every crossing of each of ``sections`` on ``0 < t < t_max`` from ``x0``.

    Returns a list of ``(index of the section, time, state)`` in time order (state as
    tier numbers), each located by heyoka's event root finder (non-terminal events).
    """
    t, sections = tier(digits), tuple(sections)
    ta, found = _integrator(t, sections, False, terminal=False)
    _start(ta, t, x0, False)
    _set_levels(ta, t, sections)
    found.clear()
    ta.propagate_until(t.to_hy(t_max))
    out = [
        (k, t.from_hy(tt), [t.from_hy(v) for v in x])
        for k, tt, x in found
        if abs(float(tt)) >= 1e-9
    ]  # a start point on a section: no crossing
    found.clear()
    return [c for c in out if _right_way(sections[c[0]], c[2], t)]


def flow(
    x0: StateLike,
    time: Any,
    digits: int | Tier | None = None,
    variational: bool = False,
) -> Any:
    """The state after ``time`` (and ``Phi`` with ``variational``), as tier numbers.

    Examples
    --------
    >>> from rotorlib.core.flow import flow
    >>> from rotorlib.core.system import energy_alpha
    >>> x0 = [0.0, 0.0, 0.0, 1.0]  # the pendulum: a1 = p1 = 0 is invariant
    >>> x = flow(x0, 5.0)
    >>> x[0], x[2], bool(abs(energy_alpha(x) - energy_alpha(x0)) < 1e-13)
    (0.0, 0.0, True)
    >>> x40 = flow(x0, 5.0, digits=40)  # mp tier: mpf numbers
    >>> bool(abs(x40[1] - x[1]) < 1e-13), type(x40[1]).__name__
    (True, 'mpf')
    """
    t = tier(digits)
    ta, _ = _integrator(t, None, variational)
    _start(ta, t, x0, variational)
    ta.propagate_until(t.to_hy(time))
    return _out(ta, t, variational)


def monodromy_matrix(
    x0: StateLike, period: Any, digits: int | Tier | None = None
) -> tuple[np.ndarray, list[Any], Any]:
    """``(M, x(T), tr M)``: the monodromy in state order as a float64 array, the end
    state (tier numbers) and the trace (a tier number, summed in the tier)."""
    t = tier(digits)
    x, Phi = flow(x0, period, t, variational=True)
    with t.context():
        tr = sum(Phi[i][i] for i in range(4))
    return np.array([[float(v) for v in row] for row in Phi]), x, tr


def states_at(
    x0: StateLike, times: ArrayLike, digits: int | Tier | None = None
) -> np.ndarray:
    """The states at ``times`` (increasing, the first 0: the start), shape
    ``(len(times), 4)``, float64, from one integration in the tier of ``digits``.

    Examples
    --------
    >>> from rotorlib.core.flow import states_at
    >>> x = states_at([0.0, 0.0, 0.0, 1.0], [0.0, 2.5, 5.0])  # the pendulum
    >>> x.shape, float(x[0, 3])
    ((3, 4), 1.0)
    """
    t = tier(digits)
    ta, _ = _integrator(t, None, False)
    _start(ta, t, x0, False)
    grid = np.asarray(times, dtype=float)
    states = ta.propagate_grid(t.hy_array(grid) if t.extended else grid)[-1]
    return np.array(states, dtype=float).reshape(len(grid), 4)


def sample(
    x0: StateLike,
    period: Any,
    n: int = 801,
    digits: int | Tier | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """States at ``n`` equally spaced times over ``[0, period]``: ``(states (n, 4), times)``,
    float64 (:func:`states_at`)."""
    grid = np.linspace(0.0, float(period), n)
    return states_at(x0, grid, digits), grid


def extrema(
    x0: StateLike, period: Any, digits: int | Tier | None = None
) -> tuple[float, float]:
    """``(max |a1|, largest excursion of a2)`` over ``[0, period]``, each located at its
    turning point (``p1 = 0`` or ``p2 = 0``) to the working precision.

    For a rotating ``a2`` (no turning point) the excursion is ``max |a2 - 2 pi k|``
    (nearest multiple) on 4001 samples. Returns floats.
    """
    hits = crossings(x0, (Section((0, 0, 1, 0)), Section((0, 0, 0, 1))), period, digits)
    a1m = max([abs(float(x0[0]))] + [abs(float(x[0])) for k, _, x in hits if k == 0])
    a2s = [abs(float(x[1])) for k, _, x in hits if k == 1]
    if a2s:
        return a1m, max(a2s)
    st, _ = sample(x0, period, 4001)
    return a1m, float(
        np.max(np.abs(st[:, 1] - 2 * np.pi * np.round(st[:, 1] / (2 * np.pi))))
    )
