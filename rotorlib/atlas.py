"""An atlas of symmetric periodic orbits: every one with period ``<= T_max`` at energy ``E``.

The grid search for reversible systems (Markellos and coworkers; Tsirogiannis, Perdios and
Markellos, Celest. Mech. Dyn. Astr. 103, 49 (2009)): a symmetric periodic orbit meets the
fixed sets of two reversing symmetries half a period apart (:mod:`rotorlib.reversors`).
For each class of fixed set (:func:`rotorlib.reversors.start_sets`) the start points are
sampled on a grid of ``grid`` points along the curve; each is integrated for
``T_max / 2`` and every crossing of every fixed set is recorded with the residual of its
condition; a sign change between neighbouring start points, at the same crossing of the
same fixed set, brackets an orbit, which the engine refines (a :class:`ShootingProblem`,
Brent's method in the start parameter). Each root is verified: the orbit must close,
modulo the configuration lattice, after ``2 t1`` times the order of the symmetry relating
the two fixed sets; its primitive period is found; orbits related by the symmetry group
or by time reversal are merged (same period and action ``2 (E T - int V dt)``); each is
polished in real128 (state, period and trace to ~30 digits), its ``tr M`` computed and it
is named after the known family it belongs to (pendulum, breathers, the IS/PD daughters,
PD^b) or ``new``. :func:`census` runs the scan through :func:`rotorlib.parallel.pmap`
(process pool or Dask cluster).

Precision: float64 scan and refinement (residual to ~1e-13), real128 polish; the listed
``trace`` is the real128 one (``~30 - log10|tr M|`` digits).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from .flow import Section, SectionNotReached, crossings, flow, monodromy_matrix, sample
from .parallel import pmap
from .precision import FLOAT64, REAL128
from .reversors import start_sets, targets
from .shooting import ShootingProblem, residual, solve

__all__ = ["AtlasOrbit", "Atlas", "census", "atlas", "budget_seconds", "BUDGET"]

#: Largest accepted cost of one census, in seconds of one core (estimated; see budget_seconds).
BUDGET = 3600.0


@dataclass(frozen=True)
class AtlasOrbit:
    """One symmetric periodic orbit of the atlas.

    Attributes
    ----------
    label : str
        The known family (``pendulum``, ``breather R``/``LG``/``LD``, ``IS^l_3``, ``PD^b``...)
        or ``new``.
    family : str
        Family id (orbits of one family at other energies share it; see :func:`atlas`).
    E, period, trace : float
    stable : bool
        ``0 < tr M < 4``.
    state0 : tuple
        ``[a1, a2, p1, p2]`` (float64) on the start fixed set.
    state0_str, period_str, trace_str : tuple, str, str
        The real128 polish (~30 significant digits).
    fixed_sets : tuple of str
        The two fixed sets the orbit meets half a period apart.
    action : float
        ``oint p dq = 2 (E T - int V dt)``.
    closure : float
        ``max |x(T) - x(0) - lattice|`` of the real128 orbit.
    u : float
        The start parameter on its fixed set.
    """

    label: str
    family: str
    E: float
    period: float
    trace: float
    stable: bool
    state0: tuple
    state0_str: tuple
    period_str: str
    trace_str: str
    fixed_sets: tuple
    action: float
    closure: float
    u: float
    problem: ShootingProblem = field(repr=False, default=None)

    def to_record(self) -> dict:
        return {"label": self.label, "family": self.family, "E": self.E,
                "period": self.period, "trace": self.trace, "stable": self.stable,
                "state0_str": list(self.state0_str), "period_str": self.period_str,
                "trace_str": self.trace_str, "fixed_sets": list(self.fixed_sets),
                "action": self.action, "closure": self.closure}


@dataclass(frozen=True)
class Atlas:
    """The census at one energy: ``orbits`` sorted by period; ``grid``, the number of
    candidate brackets refined, and the wall time."""

    E: float
    t_max: float
    grid: int
    orbits: tuple
    candidates: int
    seconds: float

    @property
    def stable(self) -> tuple:
        return tuple(o for o in self.orbits if o.stable)


def budget_seconds(E_values, t_max, grid=600) -> float:
    """An estimate of a census's cost (core seconds): the scan integrates ``5 grid`` start
    points for ``T_max / 2`` per energy (measured ~0.15 ms per unit of time with the
    fixed-set events), the refinement ~50 shots per bracket, brackets growing like
    ``T_max^2``."""
    n = len(list(E_values))
    return n * (5 * grid * 1.5e-4 * t_max / 2 * 12 + 3e-3 * (t_max ** 2) * 2)


def _check(E_values, t_max, grid):
    for E in E_values:
        if not (isinstance(E, (int, float)) and math.isfinite(E) and E > 0):
            raise ValueError(f"E must be a finite energy > 0, got {E!r}")
    if not (math.isfinite(t_max) and t_max > 0):
        raise ValueError(f"T_max must be > 0, got {t_max!r}")
    if not (isinstance(grid, int) and grid >= 20):
        raise ValueError(f"grid must be an integer >= 20, got {grid!r}")
    cost = budget_seconds(E_values, t_max, grid)
    if cost > BUDGET:
        raise ValueError(f"a census to T_max = {t_max:g} at {len(E_values)} energies would take "
                         f"~{cost / 60:.0f} min of one core (budget {BUDGET / 60:.0f} min): "
                         f"lower T_max or the number of energies")


# --------------------------------------------------------------------------- the scan

def _scan_one(args):
    """Crossings of every fixed set from one start point: ``[(target, k, t, residual)]``."""
    si, u, E, t_half = args
    start = start_sets(E)[si]
    try:
        x0 = start.at(u, E)
    except ValueError:
        return None
    tg = targets()
    hits = crossings(x0, [f.section for f in tg], t_half)
    count = [0] * len(tg)
    out = []
    for j, tt, x in hits:
        count[j] += 1
        r = _condition(tg[j].condition, x)
        out.append((j, count[j], float(tt), float(r)))
    return out


def _condition(c: Section, x):
    y = c.value(x) - c.level * math.pi
    if c.period is None:
        return y
    k = 1 / c.period
    return math.sin(k * y) / k


def _brackets(us, rows):
    """Sign changes of the residual between neighbouring start points, same fixed set and
    crossing (and crossing times close: the same crossing, not the next)."""
    out = []
    for i in range(len(us) - 1):
        a, b = rows[i], rows[i + 1]
        if a is None or b is None:
            continue
        db = {(j, k): (tt, r) for j, k, tt, r in b}
        for j, k, ta, ra in a:
            if (j, k) not in db:
                continue
            tb, rb = db[(j, k)]
            if ra * rb < 0 and abs(ta - tb) < 0.2 * max(ta, tb) and abs(ra) + abs(rb) < 1.0:
                out.append((i, j, k))
    return out


# --------------------------------------------------------------------------- orbits

def _problem(si, j, k, E, t_half):
    start, tg = start_sets(E)[si], targets()[j]
    return ShootingProblem(f"{start.name} -> {tg.name} ({k})", start, tg.section,
                           tg.condition, k, 2, (0.0, 0.0), None, None, 2 * t_half + 1)


def _lattice_shift(d):
    """``d`` reduced modulo the configuration lattice (generated by (0, 2 pi), (pi, pi))."""
    d = list(d)
    n1 = round(d[0] / math.pi)
    d[0] -= n1 * math.pi
    d[1] -= n1 * math.pi
    d[1] -= 2 * math.pi * round(d[1] / (2 * math.pi))
    return d


def _closure(x0, T):
    xT = flow(x0, T)
    return max(abs(v) for v in _lattice_shift([a - b for a, b in zip(xT, x0)]))


def _period(x0, t1, t_max, tol=1e-7):
    """The primitive period: the smallest ``2 n t1 / m`` that closes (``n`` the order of the
    symmetry relating the fixed sets, 1..6; ``m`` a divisor revealing extra symmetry)."""
    for n in (1, 2, 3, 4, 6):
        T = 2 * n * t1
        if T > t_max * 1.05 or _closure(x0, T) > tol:
            continue
        for m in (6, 5, 4, 3, 2):
            if T / m > 1e-3 and _closure(x0, T / m) < tol:
                return T / m
        return T
    return None


def _invariants(x0, T, E):
    """``(period, action)``: the action ``oint p dq = 2 (E T - int V dt)`` (Simpson on 801
    samples) is the same for every image of the orbit under the group and time reversal."""
    from scipy.integrate import simpson

    from .system import potential_alpha

    st, ts = sample(x0, T, 801)
    return T, 2 * (E * T - simpson(potential_alpha(st[:, 0], st[:, 1]), x=ts))


def _refine(args):
    """One bracket: the root in ``u`` (Brent), its verification and invariants, or ``None``."""
    from scipy.optimize import brentq

    si, j, k, E, t_half, ua, ub = args
    prob = _problem(si, j, k, E, t_half)

    def f(u):
        return float(residual(prob, u, E).r)

    try:
        u = brentq(f, ua, ub, xtol=1e-15, rtol=4e-16, maxiter=200)
        s = residual(prob, u, E)
    except (ValueError, SectionNotReached, RuntimeError):
        return None
    if abs(s.r) > 1e-9:
        return None
    x0 = [float(v) for v in s.x0]
    T = _period(x0, float(s.t1), 2 * t_half)
    if T is None:
        return None
    return (si, j, k, u, x0, T, *_invariants(x0, T, E)[1:])


def _polish(prob, u, E, T):
    """The orbit in real128: ``u`` re-solved at ``E``, state, period, trace, closure."""
    t = REAL128
    with t.context():
        u = solve(prob, t.num(u), t.num(u) * (1 + t.num("1e-12")), E=str(E), t=t,
                  r_max=1e-20).x
        s = residual(prob, u, str(E), t)
        n = round(T / (2 * float(s.t1)) * 6) / 6             # T = 2 t1 n (n may be n/m)
        Tm = 2 * s.t1 * t.num(n)
        M, xT, tr = monodromy_matrix(s.x0, Tm, t)
        d = _lattice_shift([float(a - b) for a, b in zip(xT, s.x0)])
        return s.x0, Tm, tr, max(abs(v) for v in d)


# --------------------------------------------------------------------------- known families

def _known(E, t_max):
    """``[(label, period, action)]`` of the known families at ``E`` with period ``<= t_max``."""
    from . import newborn as nb
    from .breathers import DAUGHTER_E_MIN, breather_daughter
    from .orbits import breather, pendulum

    out = []

    def add(label, x0, T):
        if T <= t_max * 1.001:
            out.append((label, T, _invariants(list(x0), T, E)[1]))

    if E != 4.0:
        p = pendulum(E)
        add("pendulum", p.state0, p.period)
    for fam in ("LG", "LD", "R"):
        try:
            b = breather(E, fam)
        except ValueError:
            continue
        add(f"breather {fam}", b.state0, b.period)
    for lab in nb.FAMILIES:
        spec = nb.family_spec(lab)
        if spec.depth < 3e-8 or not spec.E_birth < E:
            continue
        try:
            b = nb.follow(lab, E_max=max(E, nb.family_range(spec)[1]) + 0.05, energies=(E,),
                          max_steps=600)
        except (ValueError, SectionNotReached):
            continue
        for pt in b.points("E"):
            if pt.located:
                m = pt.member
                add(spec.label, b.state(m), float(b.problem.factor * m.t1))
    if DAUGHTER_E_MIN <= E < 8.968:
        o = breather_daughter(E)
        add("PD^b", o.state0, o.period)
    return out


def _name(T, S, known):
    for label, Tk, Sk in known:
        if abs(T - Tk) < 1e-6 * Tk and abs(S - Sk) < 1e-6 * max(1.0, abs(Sk)):
            return label
    return "new"


# --------------------------------------------------------------------------- front end

def census(E, t_max=16.0, grid=600, executor=None, progress=False, name=True) -> Atlas:
    """Every symmetric periodic orbit with period ``<= t_max`` at energy ``E``.

    Parameters
    ----------
    E : float
    t_max : float
        Largest period.
    grid : int
        Start points per fixed-set class (refine until the census no longer changes).
    executor : concurrent.futures.Executor, optional
        For the scan and the refinement (:func:`rotorlib.parallel.pmap`).
    progress : bool
        A progress bar on a terminal (never in notebooks).
    name : bool
        Name the orbits after the known families (follows every daughter family to ``E``).

    Returns
    -------
    Atlas
    """
    E, t_max = float(E), float(t_max)
    _check([E], t_max, grid)
    t0 = time.perf_counter()
    t_half = t_max / 2 * 1.02
    tasks, index = [], []
    for si, st in enumerate(start_sets(E)):
        lo, hi = st.span(E)
        us = np.linspace(lo, hi, grid + 1)[:-1] + (hi - lo) / (2 * grid)
        index.append((si, us))
        tasks += [(si, float(u), E, t_half) for u in us]
    rows = pmap(_scan_one, tasks, executor=executor, progress=progress, desc=f"scan E={E:g}",
                chunksize=max(1, grid // 8))
    jobs, pos = [], 0
    for si, us in index:
        r = rows[pos:pos + len(us)]
        pos += len(us)
        jobs += [(si, j, k, E, t_half, float(us[i]), float(us[i + 1]))
                 for i, j, k in _brackets(us, r)]
    found = [f for f in pmap(_refine, jobs, executor=executor, progress=progress,
                             desc="refine", chunksize=8) if f is not None]
    unique = []
    for f in sorted(found, key=lambda f: (f[5], f[0], f[1], f[2])):
        T, S = f[5], f[6]
        if T > t_max or any(abs(T - g[5]) < 1e-7 * T and abs(S - g[6]) < 1e-6 * max(1, abs(S))
                            for g in unique):
            continue
        unique.append(f)
    known = _known(E, t_max) if name else []
    tg = targets()
    orbits = []
    for n, (si, j, k, u, x0, T, S) in enumerate(unique):
        prob = _problem(si, j, k, E, t_half)
        x128, T128, tr128, clo = _polish(prob, u, E, T)
        with REAL128.context():
            tr = float(tr128)
            orbits.append(AtlasOrbit(
                _name(T, S, known), "", E, float(T128), tr, bool(0 < tr < 4), tuple(x0),
                tuple(REAL128.text(v, 30) for v in x128), REAL128.text(T128, 30),
                REAL128.text(tr128, 25), (start_sets(E)[si].name, tg[j].name), float(S), clo,
                float(u), prob))
    orbits = [_with_family(o, i) for i, o in enumerate(orbits)]
    return Atlas(E, t_max, grid, tuple(orbits), len(jobs), time.perf_counter() - t0)


def _with_family(o, i):
    from dataclasses import replace

    return replace(o, family=o.label if o.label != "new" else f"N{i + 1}")


def atlas(energies, t_max=16.0, grid=600, executor=None, progress=False) -> list:
    """:func:`census` at each energy (a list of :class:`Atlas`)."""
    energies = [float(E) for E in energies]
    _check(energies, t_max, grid)
    return [census(E, t_max, grid, executor, progress) for E in energies]
