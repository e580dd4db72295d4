"""An atlas of symmetric periodic orbits: every one with period ``<= T_max`` at energy ``E``.

The grid search for reversible systems (Markellos and coworkers; Tsirogiannis, Perdios and
Markellos, Celest. Mech. Dyn. Astr. 103, 49 (2009)): a symmetric periodic orbit meets the
fixed sets of two reversing symmetries half a period apart (:mod:`rotorlib.orbits.reversors`).
A grid of ``grid`` start points on each class of fixed set (``start_sets``) is integrated
for ``T_max / 2``, every crossing of every fixed set recorded with the residual of its
condition; a sign change between neighbours brackets an orbit, refined by the engine
(:func:`symmetric_roots`) and verified: it must close, modulo the lattice, after ``2 t1``
times the order of the symmetry relating the two fixed sets; its primitive period is
found; a root closing only to ~1e-4 (beside a very unstable orbit) is dropped; orbits
related by symmetry or time reversal are merged (same period and action, an image of one
start state on the other within ``SAME_ORBIT``); it is named after its known family
(pendulum, breathers, IS/PD daughters, PD^b, choreographies) or ``new``. :func:`census`
runs in two rounds of tasks of similar cost through :func:`rotorlib.core.parallel.pmap`.

Precision: float64 scan and refinement (residual ~1e-13; ``tr M`` to ~1e-15 |tr M|); with
``digits=D`` every orbit is re-solved and given to ``D`` digits (``tr M`` to ``D - 5``).
Tested against an independent real128 integration and census (``tests/test_atlas.py``).
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import math
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numpy.typing import ArrayLike

from ..core.energy import as_float
from ..core.flow import SectionNotReached, crossings, monodromy_matrix, sample
from ..core.parallel import pmap
from ..core.precision import FLOAT64, json_number, load_heyoka, tier
from ..core.system import lattice_reduce
from ..orbits.periodic_orbit import PeriodicOrbit
from ..orbits.reversors import images, start_sets, targets
from ..orbits.shooting import ShootingProblem, residual, solve
from .choreo import Choreography, choreography_label

__all__ = [
    "Atlas",
    "census",
    "budget_seconds",
    "check_census",
    "BUDGET",
    "E_DOMAIN",
    "BUDGET_MODEL",
    "SAME_ORBIT",
    "symmetric_roots",
    "finish_orbit",
    "atlas_orbit",
    "distinct_orbits",
    "orbit_samples",
    "distance_to_orbit",
    "shooting_problem",
    "orbit_action",
]

#: Energies where the census is validated (``tests/test_atlas.py``): below 0.1 the normal
#: modes at G differ by less than the closure test resolves; above 100 the rotors are free.
E_DOMAIN = (0.1, 100.0)

#: Largest accepted cost of one census in CPU seconds (:func:`budget_seconds`, whose
#: model, fitted to ``census(5.45, T)``, is ``BUDGET_MODEL``).
BUDGET = 3600.0
BUDGET_MODEL = {"BASE": 2.2, "GROWTH": 23.0, "RATE": 0.36}


@dataclass(frozen=True)
class Atlas:
    """The census at one energy (:func:`census`): its ``orbits`` sorted by period, and the
    ``grid`` of start points.

    Examples
    --------
    >>> from rotorlib.beyond.atlas import census
    >>> a = census(4.3, 7, grid=40, name=False)
    >>> [(round(o.period, 4), o.stability) for o in a.orbits]
    [(3.0612, 'stable'), (4.9378, 'stable'), (5.8151, 'unstable'), (6.8829, 'unstable')]
    >>> len(a.stable), a.orbits[0].extra["fixed_sets"]
    (2, ('Fix T(12)', 'Fix T(12)'))
    >>> [a.to_dict()[k] for k in ("E", "t_max", "grid")], len(a.to_dict()["orbits"])
    ([4.3, 7.0, 40], 4)
    """

    E: float
    t_max: float
    grid: int
    orbits: tuple[PeriodicOrbit, ...]

    @property
    def stable(self) -> tuple[PeriodicOrbit, ...]:
        """The linearly stable orbits (``0 < tr M < 4``)."""
        return tuple(o for o in self.orbits if o.stable)

    def to_dict(self) -> dict:
        """The census as JSON: ``E``, ``t_max``, ``grid``, ``orbits`` (each as the
        ``orbit`` command prints it)."""
        return {
            **json_number("E", self.E),
            **json_number("t_max", self.t_max),
            "grid": self.grid,
            "orbits": [o.to_dict() for o in self.orbits],
        }


def budget_seconds(E_values: Iterable[float], t_max: float, grid: int = 300) -> float:
    """A census's cost in seconds of one core (CPU time): per energy ``(BASE + GROWTH
    exp(RATE (T_max - 16)) grid / 300) max(1, E / 5.45)`` (``BUDGET_MODEL``, fitted
    to the CPU time of ``census(5.45, T)``, 3.5, 7.7 and 25.3 s at T = 8, 12, 16, serial,
    ``nice -n 10`` on the 2-core CI machine). Measured accuracy: within 2% of that fit;
    1.2-1.25x over at ``E = 8`` (T = 8, 12); over below the band (1.2-1.7x at
    ``E = 4.3``, 3.7x at ``E = 2``, ``T = 8``); 0.7x at ``T = 4`` (a first run compiles
    heyoka's integrators).

    >>> round(budget_seconds([5.45], 8), 1), round(budget_seconds([5.45], 16), 1)
    (3.5, 25.2)
    """
    m = BUDGET_MODEL
    return sum(
        (m["BASE"] + m["GROWTH"] * (grid / 300) * math.exp(m["RATE"] * (t_max - 16)))
        * max(1.0, E / 5.45)
        for E in E_values
    )


def check_census(E_values: Sequence[float], t_max: float, grid: int = 300) -> None:
    """Refuse a census request before any work is done (ValueError, saying why): every
    energy in :data:`E_DOMAIN`, ``t_max > 0`` finite, ``grid`` an integer ``>= 20``, and
    the predicted cost (:func:`budget_seconds`) within :data:`BUDGET`.

    Examples
    --------
    >>> from rotorlib.beyond.atlas import check_census
    >>> check_census([4.3], 7.0)
    >>> check_census([0.05], 7.0)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: E = 0.05 is outside the atlas's domain 0.1 <= E <= 100.0 (nearly ...
    """
    for E in E_values:  # floats (as_float); outside the domain: also E <= 0 and nan
        if not E_DOMAIN[0] <= E <= E_DOMAIN[1]:
            raise ValueError(
                f"E = {E!r} is outside the atlas's domain {E_DOMAIN[0]} <= E <= "
                f"{E_DOMAIN[1]} (nearly integrable: the normal modes, or the free "
                f"rotations, are too close to degenerate for the census to tell "
                f"the orbits apart)"
            )
    if not (math.isfinite(t_max) and t_max > 0):
        raise ValueError(f"T_max must be > 0, got {t_max!r}")
    if not (isinstance(grid, int) and grid >= 20):
        raise ValueError(f"grid must be an integer >= 20, got {grid!r}")
    cost = budget_seconds(E_values, t_max, grid)
    if cost > BUDGET:
        raise ValueError(
            f"a census to T_max = {t_max:g} at {len(E_values)} energies would take "
            f"~{cost / 60:.0f} min of one core (budget {BUDGET / 60:.0f} min): "
            f"lower T_max or the number of energies"
        )


def _scan_one(si, u, E, t_half):
    """Crossings of every fixed set from one start point: ``[(target, k, t, residual)]``."""
    try:
        x0 = start_sets(E)[si].at(u, E)
    except ValueError:
        return None
    tg, count, out = targets(), [0] * len(targets()), []
    for j, tt, x in crossings(x0, [f.section for f in tg], t_half):
        c, count[j] = tg[j].condition, count[j] + 1
        y, k = c.value(x) - c.level * math.pi, c.period and 1 / c.period
        out.append(
            (j, count[j], float(tt), float(y if k is None else math.sin(k * y) / k))
        )
    return out


def _pairs(a: list, b: list, t_half: float) -> list:
    """``[(j, k, ra, rb)]``: the crossings of the rows ``a``, ``b`` of two start points
    (:func:`_scan_one`) that correspond: the ``k``-th crossing of a fixed set ``j`` crossed
    as often from both, at times within ``0.05 t_half``, with its residual on each side."""
    na, nb = ({j: k for j, k, _, _ in r} for r in (a, b))
    db = {(j, k): (tt, r) for j, k, tt, r in b}
    return [
        (j, k, ra, db[j, k][1])
        for j, k, ta, ra in a
        if na[j] == nb.get(j) and abs(ta - db[j, k][0]) < 0.05 * t_half
    ]


def _needs_split(a, b, t_half):
    """Whether the crossings change between two start points (a crossing appears or
    vanishes, or moves by ``0.05 t_half`` or more): the pairing by index breaks."""
    if a is None or b is None:
        return a is not b
    return len(_pairs(a, b, t_half)) < max(len(a), len(b))


def symmetric_roots(
    si: int,
    E: float,
    t_half: float,
    grid: int,
    window: tuple[float, float],
    executor: Executor | None = None,
) -> list[tuple]:
    """The symmetric orbits of the census's scan (:func:`census`) started on ``window =
    (lo, hi)`` of start set ``si``: ``grid`` start points, bisected 8 times at most where
    their crossings change, each sign change refined and verified, in 8 tasks through
    :func:`rotorlib.core.parallel.pmap`. Returns the roots ``(si, j, k, u, x0, T, action)``
    (float64, residual ~1e-13), for :func:`distinct_orbits`."""
    jobs = _scan_jobs(si, E, t_half, grid, 8, 8, window)
    return _gather(jobs[0], pmap(_segments, jobs, executor=executor))


def _scan_jobs(si, E, t_half, grid, depth, parts, window=None) -> list:
    """The tasks of one class's scan: its grid (cell midpoints and both ends of the span,
    where a mirror's turning points sit) cut into ``parts`` runs of neighbours."""
    lo, hi = window or start_sets(E)[si].span(E)
    us = [lo, *(np.linspace(lo, hi, grid + 1)[:-1] + (hi - lo) / (2 * grid)), hi]
    n = -(-(len(us) - 1) // parts)
    return [
        (si, us[i : i + n + 1], E, t_half, (hi - lo) / grid, depth)
        for i in range(0, len(us) - 1, n)
    ]


def _bisect(si, E, t_half, a, ra, b, rb, width, depth) -> list:
    """The points in ``(a, b]`` with their rows: the interval halved while its crossing
    structure changes, ``depth`` times at most, not when narrower than 1.5 x ``width / 2``."""
    width /= 2
    if depth < 1 or b - a <= 1.5 * width or not _needs_split(ra, rb, t_half):
        return [(b, rb)]
    m = 0.5 * (a + b)
    rm = _scan_one(si, m, E, t_half)
    return _bisect(si, E, t_half, a, ra, m, rm, width, depth - 1) + _bisect(
        si, E, t_half, m, rm, b, rb, width, depth - 1
    )


def _segments(args) -> tuple[bool, list]:
    """One task of a scan: neighbours ``us`` on the grid of class ``si``, each interval
    between them bisected (:func:`_bisect`) and its roots found (:func:`_roots`) but an
    end of the span (half a cell, left to :func:`_gather`): ``(split, [(a, ra, b, rb,
    roots)])``, ``roots`` None and the rows ``ra``, ``rb`` kept for an end only."""
    si, us, E, t_half, width, depth = args
    rows = [_scan_one(si, u, E, t_half) for u in us]
    split, out = False, []  # type: bool, list
    for a, b, ra, rb in zip(us, us[1:], rows, rows[1:]):
        if b - a > 1.5 * (width / 2):
            split = split or _needs_split(ra, rb, t_half)
            out.append(
                (a, None, b, None, _roots(si, E, t_half, a, ra, b, rb, width, depth))
            )
        else:
            out.append((a, ra, b, rb, None))
    return split, out


def _gather(job, results) -> list:
    """The roots of a class's tasks in order, its ends bisected from the second level on
    if another interval was at the first."""
    si, _, E, t_half, width, depth = job
    split = any(s for s, _ in results)
    out = []
    for a, ra, b, rb, roots in (seg for _, segs in results for seg in segs):
        if roots is None:
            # an end: bisected only if another interval was at the first level
            roots = _roots(si, E, t_half, a, ra, b, rb, width / 2, (depth - 1) * split)
        out += roots
    return out


def _roots(si, E, t_half, a, ra, b, rb, width, depth) -> list:
    """The roots between the start points ``a`` and ``b`` (rows ``ra``, ``rb``): the
    interval bisected (:func:`_bisect`), the sign changes of the residual between
    neighbours at the same crossing of the same fixed set (:func:`_pairs`; other fixed sets
    may change their crossings in between) refined (:func:`_refine_bracket`)."""
    pts = [(a, ra), *_bisect(si, E, t_half, a, ra, b, rb, width, depth)]
    roots = [
        _refine_bracket(si, j, k, E, t_half, float(u0), float(u1))
        for (u0, row0), (u1, row1) in zip(pts, pts[1:])
        if row0 is not None and row1 is not None
        for j, k, r0, r1 in _pairs(row0, row1, t_half)
        if r0 * r1 < 0
    ]
    return [r for r in roots if r is not None]


def shooting_problem(si, j, k, E, t_half):
    """The census's shooting problem from start set ``si`` to target ``j`` at its
    ``k``-th crossing, energy ``E``, half period about ``t_half`` (float64 or a tier)."""
    start, tg = start_sets(E)[si], targets()[j]
    name, sec, cond = f"{start.name} -> {tg.name} ({k})", tg.section, tg.condition
    return ShootingProblem(
        name, start, sec, cond, k, 2, (0.0, 0.0), None, None, 2 * t_half + 1
    )


def _closure_at(x0, times):
    """``max |x(t) - x(0)|`` modulo the lattice at each of ``times`` (one integration)."""
    from ..core.flow import states_at

    ts = sorted(set(times))
    states = states_at(x0, [0.0] + ts)[1:]
    res = {
        t: lattice_reduce([a - b for a, b in zip(x, x0)]) for t, x in zip(ts, states)
    }
    return [max(map(abs, res[t])) for t in times]


def _period(x0, t1, t_max):
    """The primitive period. The symmetry relating the two fixed sets has order ``n`` in
    (1, 2, 3, 4, 6): the orbit closes after ``2 n t1``, the ``n`` whose closure is smallest
    (at most 1e-3: float64 closure grows with the orbit's instability, the real128 polish
    checks it again) and far below the others'; then the smallest ``T / m`` (``m <= 24``)
    that closes too (a multiple cover, or extra symmetry)."""
    ns = [n for n in (1, 2, 3, 4, 6) if 2 * n * t1 <= t_max]
    if not ns:
        return None
    cl = _closure_at(x0, [2 * n * t1 for n in ns])
    k = int(np.argmin(cl))
    n, c = ns[k], cl[k]
    if c > 1e-3 or any(o < 100 * c for m, o in zip(ns, cl) if m != n and n % m):
        return None
    T = 2 * n * t1
    ms = list(range(24, 1, -1))  # a multiple cover of a shorter orbit
    for m, cm in zip(ms, _closure_at(x0, [T / m for m in ms])):
        if cm < max(1e-9, 10 * c):
            return T / m
    return T


def orbit_action(x0, T, E=None):
    """The action ``oint p dq = 2 (E T - int V dt)`` of the orbit from ``x0`` of period
    ``T``: the same for every image of the orbit under the group and time reversal.

    :func:`rotorlib.beyond.quantum_trace.orbit_action` on 800 equal steps (a trapezoid
    sum of a smooth periodic integrand; the cost of the 801 samples this function once
    summed by Simpson's rule). Against 800 T steps, on the catalogue's members and their
    doubles: < 1e-15 relative for ``T < 8``, < 2e-14 for ``T < 12``, < 2e-12 for
    ``T < 17`` (the census compares actions to 1e-6). ``E`` (the orbit's energy) is not
    needed: it is read from ``x0``."""
    from .quantum_trace import orbit_action as action

    return action(x0, T, 800)


#: An orbit is kept if it closes after one period to ``max(1e6, 100 |tr M|) 10^-D`` (``D``
#: digits; genuine orbits close to ``~1e-15 |tr M|`` in float64, ``~1e-33 |tr M|`` in
#: real128; a near-periodic trajectory beside an orbit with ``|tr M| > 1e7``, 1e-4). Two
#: orbits with the same period and action are the same orbit when an image of one's start
#: state under the group (and time reversal) lies within this distance of the other orbit
#: (float64 states from Brent to 1e-15; a pair born at a pitchfork closer than this in
#: phase space, ``|tr M - 4| < ~1e-10``, would count once).
SAME_ORBIT = 1e-6


def orbit_samples(x0: ArrayLike, T: float) -> np.ndarray:
    """The states of the orbit from ``x0`` of period ``T`` at 4000 times, for
    :func:`distance_to_orbit`."""
    return sample(np.asarray(x0, dtype=float), T, 4000)[0]


def distance_to_orbit(states: np.ndarray, y0: ArrayLike) -> float:
    """The phase-space distance (configuration modulo the lattice) from the nearest image of
    ``y0`` under the group to the orbit sampled at ``states`` (:func:`orbit_samples`):
    every local minimum of the distance to the samples below 0.05 refined by Newton on the
    time along the orbit (short integrations)."""
    from ..core.flow import flow
    from ..core.system import rhs_alpha

    def gap(y, x):
        return lattice_reduce(np.array(y) - x)

    best = math.inf
    for y in images(y0):
        dist = np.max(np.abs(lattice_reduce(states - y)), axis=1)
        best = min(best, float(dist.min()))
        near = (dist < 0.05) & (dist <= np.roll(dist, 1)) & (dist <= np.roll(dist, -1))
        for x in states[near]:  # each local minimum below 0.05
            for _ in range(4):
                v = np.asarray(rhs_alpha(0.0, x), float)
                x = np.array(flow(list(x), float(gap(y, x) @ v / (v @ v))), float)
            best = min(best, float(np.max(np.abs(gap(y, x)))))
    return best


def _refine_bracket(si, j, k, E, t_half, ua, ub) -> tuple | None:
    """One bracket: the root in ``u`` (Brent), its verification and invariants, or ``None``."""
    from scipy.optimize import brentq

    prob = shooting_problem(si, j, k, E, t_half)

    try:
        f = lambda u: float(residual(prob, u, E).r)  # noqa: E731
        u = brentq(f, ua, ub, xtol=1e-15, rtol=1e-15, maxiter=200)
        s = residual(prob, u, E)
    except (ValueError, SectionNotReached, RuntimeError):
        return None
    if abs(s.r) > 1e-9:
        return None
    x0 = [float(v) for v in s.x0]
    T = _period(x0, float(s.t1), 2 * t_half)
    return None if T is None else (si, j, k, u, x0, T, orbit_action(x0, T, E))


def finish_orbit(args: tuple) -> tuple:
    """One orbit's trace and closure, and its state/period/trace as strings: float64 from the
    scan (``digits=None``), or re-solved at ``E`` in the tier that delivers ``digits``."""
    si, j, k, E, t_half, u, x0, T, digits = args
    if digits is None:
        M, _, tr = monodromy_matrix(x0, T)
        return (
            tuple(map(repr, x0)),
            repr(T),
            repr(tr),
            float(tr),
            float(T),
            _closure_at(x0, [T])[0],
            M,
            None,
        )
    t, prob = tier(int(digits)), shooting_problem(si, j, k, E, t_half)
    with t.context():
        u0, u1 = t.num(u), t.num(u) * (1 + t.num("1e-12"))
        u = solve(prob, u0, u1, E=str(E), digits=t, r_max=t.eps**0.6).x
        sh = residual(prob, u, str(E), t)
        n = Fraction(T / (2 * float(sh.t1))).limit_denominator(24)  # T = 2 t1 n/m
        Tm = 2 * sh.t1 * n.numerator / n.denominator
        M, xT, tr = monodromy_matrix(sh.x0, Tm, t)
        d = lattice_reduce([a - b for a, b in zip(xT, sh.x0)], digits)  # closure
        return (
            tuple(t.text(v, digits) for v in sh.x0),
            t.text(Tm, digits),
            t.text(tr, digits - 5),
            float(tr),
            float(Tm),
            max(abs(float(v)) for v in d),
            [[float(v) for v in row] for row in M],
            digits,
        )


def atlas_orbit(
    label: str,
    family: str,
    E: float,
    t_half: float,
    root: tuple,
    fin: tuple,
    choreography: dict | None = None,
) -> PeriodicOrbit:
    """The :class:`~rotorlib.orbits.periodic_orbit.PeriodicOrbit` of a verified root
    ``(si, j, k, u, x0, T, S)`` of :func:`symmetric_roots` and its :func:`finish_orbit`
    ``(xs, Ts, trs, tr, Tf, closure, M, digits)``. ``extra`` holds the census's data:
    ``fixed_sets`` (the two fixed sets met half a period apart), ``action``
    (``oint p dq = 2 (E T - int V dt)``), ``u`` (the start parameter), ``problem`` (its
    shooting problem) and ``choreography`` (how it is one, from :func:`census`); ``residual`` is the
    closure ``max |x(T) - x(0) - lattice|`` in the working precision. ``alpha1_max`` and
    ``alpha2_max`` are not computed by a census (nan)."""
    from ..core.system import energy_alpha

    si, j, k, u, x0, T, S = root
    xs, Ts, trs, tr, Tf, clo, M, digits = fin
    extra = {
        "fixed_sets": (start_sets(E)[si].name, targets()[j].name),
        "action": float(S),
        "u": float(u),
        "problem": shooting_problem(si, j, k, E, t_half),
        "choreography": choreography,
    }
    x = np.array(x0, dtype=float)
    return PeriodicOrbit(
        label,
        float(E),
        float(Tf),
        x,
        np.array(M, dtype=float),
        float(tr),
        float(clo),
        abs(float(energy_alpha(x)) - float(E)),
        tier(digits).name,
        math.nan,
        math.nan,
        math.log(abs(E - 4)) if E != 4 else math.nan,
        extra,
        digits=digits or 15,
        period_str=Ts,
        trace_str=trs,
        state0_str=tuple(xs),
        family=family,
    )


# --------------------------------------------------------------------------- known families


def _known_family(args):
    """``(label, period, action)`` of one daughter family at ``E`` (where it is located
    last along the family), or ``None``."""
    from ..paper import newborn as nb

    lab, E = args
    spec = nb.family_spec(lab)
    try:
        E_max = max(E, nb.family_range(spec)[1]) + 0.05  # beyond E and the range
        b = nb.follow(lab, E_range=(None, E_max), energies=(E,), max_steps=600)
    except (ValueError, SectionNotReached):
        return None
    located = [pt.member for pt in b.points("E") if pt.located]
    if not located:
        return None
    T = float(b.problem.factor * located[-1].t1)
    return spec.label, T, orbit_action(list(b.state(located[-1])), T, E)


def _known_tasks(E) -> list:
    """The daughter families to follow (:func:`_known_family`) to ``E``."""
    from ..paper import newborn as nb

    return [
        (s.label, E)
        for s in map(nb.family_spec, nb.FAMILIES)
        if s.E_birth < E and s.depth >= FLOAT64.separatrix_depth
    ]


def _known(E, t_max, followed) -> list:
    """``[(label, period, action)]``: the known families at ``E`` with period ``<= t_max``,
    the daughters ``followed`` (:func:`_known_tasks`) last."""
    from ..core.closed_forms import breather, pendulum
    from ..paper.breathers import DAUGHTER_E_MIN, breather_daughter

    closed: list = [("pendulum", pendulum(E))] if E != 4.0 else []
    for fam in ("LG", "LD", "R"):
        with contextlib.suppress(ValueError):
            closed.append((f"breather {fam}", breather(E, fam)))
    if DAUGHTER_E_MIN <= E < 8.968:
        closed.append(("PD^b", breather_daughter(E)))
    return [
        (lab, o.period, orbit_action(list(o.state0), o.period, E))
        for lab, o in closed
        if o.period <= t_max * 1.001
    ] + [f for f in followed if f is not None and f[1] <= t_max * 1.001]


def _name(T, S, known):
    """The label of the known family with the period ``T`` and action ``S``, or ``new``."""
    return next(
        (
            lab
            for lab, Tk, Sk in known
            if abs(T - Tk) < 1e-6 * Tk and abs(S - Sk) < 1e-6 * Sk
        ),
        "new",
    )


def _run(job):
    """``f(args)`` for ``job = (f, args)``: tasks of several kinds in one :func:`pmap`."""
    return job[0](job[1])


def distinct_orbits(args: tuple) -> list:
    """A group of roots of :func:`census` (periods within 1e-7 of a neighbour's) without its
    repeats (the same period and action, and an image of the start state within
    ``SAME_ORBIT`` of an earlier root's orbit), finished (:func:`finish_orbit`):
    ``[(root, finish)]``."""
    group, E, t_half, digits = args
    unique: list = []
    curve = functools.cache(lambda i: orbit_samples(unique[i][4], unique[i][5]))
    for f in group:
        T, S = f[5], f[6]
        if not any(
            abs(T - g[5]) < 1e-7 * T
            and abs(S - g[6]) < 1e-6 * S
            and distance_to_orbit(curve(i), f[4]) < SAME_ORBIT
            for i, g in enumerate(unique)
        ):
            unique.append(f)
    return [(f, finish_orbit((*f[:3], E, t_half, *f[3:6], digits))) for f in unique]


# --------------------------------------------------------------------------- front end


def census(
    E: float,
    t_max: float = 16.0,
    grid: int = 300,
    depth: int = 10,
    executor: Executor | None = None,
    progress: bool = False,
    name: bool = True,
    digits: int | None = None,
    known: list | None = None,
    name_choreography: Callable[[float, Choreography, float], str] | None = None,
) -> Atlas:
    """Every symmetric periodic orbit with period ``<= t_max`` at energy ``E``.

    Two rounds of tasks through :func:`rotorlib.core.parallel.pmap`, of ~0.25 s each by
    :func:`budget_seconds`: runs of neighbouring start points, each scanned, bisected and its
    brackets refined (and the daughter families followed, to name the orbits); then groups of
    roots of nearly equal period, deduplicated and finished. The executor changes no digit.

    Parameters
    ----------
    E : float
    t_max : float
        Largest period.
    grid : int
        Start points per fixed-set class on the first pass (raise it until nothing changes).
    depth : int
        Intervals whose crossing structure changes are bisected up to ``depth`` times (an
        orbit with ``|tr M| ~ 1e7`` hides within ``~1e-3`` of the spacing beside a change of
        structure: depth 6 misses some at ``T_max = 16``).
    executor : concurrent.futures.Executor, optional
        A process pool or a Dask client's executor (:func:`rotorlib.core.parallel.pmap`).
    progress : bool
        A progress bar on a terminal (never in notebooks).
    name : bool
        Name the orbits after the known families (follows every daughter family to ``E``).
    digits : int, optional
        ``None``: float64 results (traces from the float64 variational equations). ``D``:
        every orbit re-solved at ``E`` in the tier that delivers ``D`` digits (real128 for
        ``D <= 31``) and its state, period and trace given to ``D`` digits.
    known : list, optional
        The known families at ``E``, ``(label, period, action)`` (default: the closed-form
        orbits and the daughter families, followed to ``E`` when ``name``).
    name_choreography : callable, optional
        Names a choreography of no known family (the front door's: ``CG``, ``CT``, ...).

    Returns
    -------
    Atlas

    Examples
    --------
    >>> from rotorlib.beyond.atlas import census
    >>> a = census(4.3, 7, grid=40, name=False)  # a coarse grid: the 4 orbits with T <= 7
    >>> o = a.orbits[0]
    >>> o.extra["fixed_sets"], round(o.period, 4), round(o.trace, 3)
    (('Fix T(12)', 'Fix T(12)'), 3.0612, 0.358)
    """
    E, t_max = as_float(E, "E"), as_float(t_max, "T_max")
    check_census([E], t_max, grid)
    load_heyoka()  # the scan integrates the flow: without heyoka, refuse at once
    t_half = t_max / 2 * 1.02
    classes = range(len(start_sets(E)))
    parts = max(4, round(budget_seconds([E], t_max, grid) / 0.25 / len(classes)))
    scans = [_scan_jobs(si, E, t_half, grid, depth, parts) for si in classes]
    follow = _known_tasks(E) if known is None and name else []
    jobs = [(_known_family, a) for a in follow] + [
        (_segments, a) for s in scans for a in s
    ]
    res = pmap(_run, jobs, executor=executor, progress=progress, desc=f"census E={E:g}")
    if known is None:
        known = _known(E, t_max, res[: len(follow)]) if name else []
    rest = iter(res[len(follow) :])  # each class's tasks in turn
    found = [
        f for s in scans for f in _gather(s[0], list(itertools.islice(rest, len(s))))
    ]
    groups: list = []  # roots by period; a root is compared with its group only
    for f in sorted(
        (f for f in found if f[5] <= t_max), key=lambda f: (f[5], f[0], f[1], f[2])
    ):
        if groups and f[5] - groups[-1][-1][5] < 1e-7 * f[5]:
            groups[-1].append(f)
        else:
            groups.append([f])
    done = pmap(
        distinct_orbits,
        [(g, E, t_half, digits) for g in groups],
        executor=executor,
        progress=progress,
        desc="orbits",
        chunksize=len(groups) // len(jobs) + 1,  # as many tasks as in the first round
    )
    orbits = []
    D = 15 if digits is None else int(digits)
    for i, (f, fin_i) in enumerate(x for d in done for x in d):
        x0, T, S = f[4:]
        tr, clo = fin_i[3], fin_i[5]
        if not clo <= max(1e6, 1e2 * abs(tr)) * 10.0**-D:
            continue  # a near-periodic trajectory beside a very unstable orbit, not an orbit
        label, chor = choreography_label(
            _name(T, S, known), E, x0, T, name_choreography if name else None, name
        )
        family = label if label != "new" else f"N{i + 1}"
        orbits.append(atlas_orbit(label, family, E, t_half, f, fin_i, chor))
    return Atlas(E, t_max, grid, tuple(orbits))
