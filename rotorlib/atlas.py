"""An atlas of symmetric periodic orbits: every one with period ``<= T_max`` at energy ``E``.

The grid search for reversible systems (Markellos and coworkers; Tsirogiannis, Perdios and
Markellos, Celest. Mech. Dyn. Astr. 103, 49 (2009)): a symmetric periodic orbit meets the
fixed sets of two reversing symmetries half a period apart (:mod:`rotorlib.reversors`).
The start points of each class of fixed set (:func:`rotorlib.reversors.start_sets`), a
grid of ``grid`` points, are integrated for ``T_max / 2`` and every crossing of every
fixed set is recorded with the residual of its condition (:func:`scan`); a sign change
between neighbours at the same crossing brackets an orbit (:func:`brackets`), refined by
the engine (:func:`refine_bracket`: Brent's method in the start parameter) and verified:
it must close, modulo the configuration lattice, after ``2 t1`` times the order of the
symmetry relating the two fixed sets; its primitive period is found; a root closing only
to ~1e-4 (beside a very unstable orbit) is dropped; orbits related by the symmetry group
or time reversal are merged (same period and action ``2 (E T - int V dt)``, and an image
of one start state on the other orbit within ``SAME_ORBIT``); it is named after its known
family (pendulum, breathers, IS/PD daughters, PD^b, choreographies) or ``new``.
:func:`census` runs the scan through :func:`rotorlib.parallel.pmap`.

Precision: float64 scan and refinement (residual ~1e-13; ``tr M`` to ~1e-15 |tr M|); with
``digits=D`` every orbit is re-solved and given to ``D`` digits (``tr M`` to ``D - 5``).
Tested against an independent real128 integration and census (``tests/test_atlas.py``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from fractions import Fraction

import numpy as np

from .choreo import atlas_name
from .flow import Section, SectionNotReached, crossings, monodromy_matrix, sample
from .parallel import pmap
from .precision import FLOAT64
from .reversors import _group_images, start_sets, targets
from .shooting import ShootingProblem, residual, solve

__all__ = ["AtlasOrbit", "Atlas", "census", "atlas", "budget_seconds", "BUDGET"]
__all__ += ["E_DOMAIN", "BUDGET_MODEL", "SAME_ORBIT", "scan", "brackets"]
__all__ += ["refine_bracket", "finish_orbit", "atlas_orbit", "lattice_shift"]
__all__ += ["SampledOrbit", "distance_to_orbit"]

#: Energies where the census is validated (``tests/test_atlas.py``). Below ``E = 0.1`` the
#: normal modes at G (pendulum, breather LG) differ by less than the closure test resolves;
#: above ``E = 100`` the rotors are nearly free, every resonant torus nearly degenerate.
E_DOMAIN = (0.1, 100.0)

#: Largest accepted cost of one census in CPU seconds (:func:`budget_seconds`, whose
#: model, fitted to ``atlas([5.45], T)``, is ``BUDGET_MODEL``).
BUDGET = 3600.0
BUDGET_MODEL = {"BASE": 2.2, "GROWTH": 23.0, "RATE": 0.36}


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
        With every digit the census computed (float64 reprs, or ``digits`` digits).
    fixed_sets : tuple of str
        The two fixed sets the orbit meets half a period apart.
    action : float
        ``oint p dq = 2 (E T - int V dt)``.
    closure : float
        ``max |x(T) - x(0) - lattice|`` in the working precision.
    u : float
        The start parameter on its fixed set.
    choreography : dict or None
        How it is a choreography (``rotorlib.choreo.atlas_name``; named censuses only).
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
    problem: ShootingProblem | None = field(repr=False, default=None)
    choreography: dict | None = None

    def to_record(self) -> dict:
        """The fields printed by ``python -m rotorlib atlas --json``."""
        keys = "label family E period trace stable state0_str period_str trace_str"
        out = {k: getattr(self, k) for k in keys.split()}
        out["state0"] = [float(v) for v in self.state0]
        out["state0_str"] = list(self.state0_str)
        out.update(
            fixed_sets=list(self.fixed_sets), action=self.action, closure=self.closure
        )
        out["choreography"] = self.choreography
        return out


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


def budget_seconds(E_values, t_max, grid=300) -> float:
    """A census's cost in seconds of one core (CPU time): per energy ``(BASE + GROWTH
    exp(RATE (T_max - 16)) grid / 300) max(1, E / 5.45)`` (``BUDGET_MODEL``, fitted
    to the CPU time of ``atlas([5.45], T)``, 3.5, 7.7 and 25.3 s at T = 8, 12, 16, serial,
    ``nice -n 10`` on the 2-core CI machine). Measured accuracy: within 2% of that fit;
    1.2-1.25x over at ``E = 8`` (T = 8, 12); over below the band (1.2-1.7x at
    ``E = 4.3``, 3.7x at ``E = 2``, ``T = 8``); 0.7x at ``T = 4`` (a first run compiles
    heyoka's integrators). Wall time on a loaded machine is longer (17.5 s at T = 8).

    >>> round(budget_seconds([5.45], 8), 1), round(budget_seconds([5.45], 16), 1)
    (3.5, 25.2)
    """
    m = BUDGET_MODEL
    return sum(
        (m["BASE"] + m["GROWTH"] * (grid / 300) * math.exp(m["RATE"] * (t_max - 16)))
        * max(1.0, E / 5.45)
        for E in E_values
    )


def _check(E_values, t_max, grid):
    for E in E_values:
        if not (isinstance(E, (int, float)) and math.isfinite(E) and E > 0):
            raise ValueError(f"E must be a finite energy > 0, got {E!r}")
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


def _structure(row):
    """The number of crossings of each fixed set: a change between neighbours means a
    crossing appeared or vanished in between (where the pairing by index breaks)."""
    counts = {}
    for j, k, _, _ in row:
        counts[j] = k
    return counts


def _needs_split(a, b, t_half):
    if a is None or b is None:
        return a is not b
    if _structure(a) != _structure(b):
        return True
    db = {(j, k): (tt, r) for j, k, tt, r in b}
    return any(
        abs(ta - db[(j, k)][0]) > 0.05 * t_half for j, k, ta, _ in a if (j, k) in db
    )


def brackets(us, rows, t_half):
    """Sign changes of the residual between neighbouring start points at the same crossing of
    the same fixed set, where that fixed set's crossings correspond on both sides (same
    number, times close); other fixed sets may change their crossings in between."""
    out = []
    for i in range(len(us) - 1):
        a, b = rows[i], rows[i + 1]
        if a is None or b is None:
            continue
        sa, sb = _structure(a), _structure(b)
        db = {(j, k): (tt, r) for j, k, tt, r in b}
        for j, k, ta, ra in a:
            if sa.get(j) != sb.get(j) or (j, k) not in db:
                continue
            tb, rb = db[(j, k)]
            if ra * rb < 0 and abs(ta - tb) < 0.05 * t_half:
                out.append((i, j, k))
    return out


def scan(si, E, t_half, grid, depth, executor, progress, window=None):
    """The start points of one class (on ``window = (lo, hi)``, default the whole span): a
    uniform grid, then every interval whose crossing structure changes bisected (up to
    ``depth`` times): ``(us, rows)``."""
    lo, hi = window or start_sets(E)[si].span(E)
    # cell midpoints, and both ends of the span (a mirror's turning points sit at the ends)
    us = [lo, *(np.linspace(lo, hi, grid + 1)[:-1] + (hi - lo) / (2 * grid)), hi]
    rows = pmap(
        _scan_one,
        [(si, u, E, t_half) for u in us],
        executor=executor,
        progress=progress,
        desc=f"scan E={E:g}",
        chunksize=max(1, grid // 8),
    )
    width = (hi - lo) / grid
    for level in range(depth):
        width /= 2
        mids = [
            (i, 0.5 * (us[i] + us[i + 1]))
            for i in range(len(us) - 1)
            if us[i + 1] - us[i] > 1.5 * width
            and _needs_split(rows[i], rows[i + 1], t_half)
        ]
        if not mids:
            break
        new = pmap(
            _scan_one,
            [(si, u, E, t_half) for _, u in mids],
            executor=executor,
            chunksize=max(1, len(mids) // 16),
        )
        for (i, u), r in sorted(zip(mids, new), key=lambda v: -v[0][0]):
            us.insert(i + 1, u)
            rows.insert(i + 1, r)
    return us, rows


def _problem(si, j, k, E, t_half):
    start, tg = start_sets(E)[si], targets()[j]
    return ShootingProblem(
        f"{start.name} -> {tg.name} ({k})",
        start,
        tg.section,
        tg.condition,
        k,
        2,
        (0.0, 0.0),
        None,
        None,
        2 * t_half + 1,
    )


def lattice_shift(d, t=FLOAT64):
    """``d`` reduced modulo the configuration lattice (generated by (0, 2 pi), (pi, pi)), in
    the tier ``t``."""
    with t.context():
        d, pi = list(d), t.pi
        n1 = round(float(d[0] / pi))
        d[0] -= n1 * pi
        d[1] -= n1 * pi
        d[1] -= 2 * pi * round(float(d[1] / (2 * pi)))
        return d


def _closure_at(x0, times):
    """``max |x(t) - x(0)|`` modulo the lattice at each of ``times`` (one integration)."""
    from .flow import _integrator, _start

    ts = sorted(set(times))
    ta, _ = _integrator(FLOAT64, None, False)
    _start(ta, FLOAT64, x0, False)
    out = ta.propagate_grid(np.array([0.0] + ts))[-1]
    res = {
        t: max(abs(v) for v in lattice_shift([a - b for a, b in zip(x, x0)]))
        for t, x in zip(ts, out[1:])
    }
    return [res[t] for t in times]


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


def _invariants(x0, T, E):
    """``(period, action)``: the action ``oint p dq = 2 (E T - int V dt)`` (Simpson on 801
    samples) is the same for every image of the orbit under the group and time reversal."""
    from scipy.integrate import simpson

    from .system import potential_alpha

    st, ts = sample(x0, T, 801)
    return T, 2 * (E * T - simpson(potential_alpha(st[:, 0], st[:, 1]), x=ts))


#: An orbit is kept when its closure after one period, in the tier of ``D`` digits, is at
#: most ``max(1e6, 100 |tr M|) 10^-D``: genuine orbits close to ``~1e-15 |tr M|`` (float64)
#: or ``~1e-33 |tr M|`` (real128); a root of the residual that closes only to 1e-4 (a
#: near-periodic trajectory beside an orbit with ``|tr M| > 1e7``) is dropped.
#: Two orbits with the same period and action are the same orbit when an image of one's start
#: state under the group (and time reversal) lies within this distance of the other orbit
#: (float64 states from Brent to 1e-15; a pair born at a pitchfork closer than this in phase
#: space, ``|tr M - 4| < ~1e-10``, would count once).
SAME_ORBIT = 1e-6


class SampledOrbit:
    """An orbit sampled densely, for :func:`distance_to_orbit`."""

    def __init__(self, x0, T, n=4000):
        self.x0 = list(x0)
        self.states, self.ts = sample(x0, T, n)


def distance_to_orbit(c: SampledOrbit, y0) -> float:
    """The phase-space distance (configuration modulo the lattice) from the nearest image of
    ``y0`` under the group to the orbit ``c``: every local minimum of the distance to the
    samples below 0.05 refined by Newton on the time along the orbit (short integrations)."""
    from .flow import _integrator, _start
    from .system import rhs_alpha

    def gap(y, x):
        d = np.array(y) - x
        d[:2] = lattice_shift(d[:2])
        return d

    ta, _ = _integrator(FLOAT64, None, False)
    best = math.inf
    for y in _group_images() @ np.asarray(y0, float):
        d = c.states - y
        n1 = np.round(d[:, 0] / math.pi)
        d[:, 0] -= n1 * math.pi
        d[:, 1] -= n1 * math.pi
        d[:, 1] -= 2 * math.pi * np.round(d[:, 1] / (2 * math.pi))
        dist = np.max(np.abs(d), axis=1)
        best = min(best, float(dist.min()))
        near = np.flatnonzero(
            (dist < 0.05) & (dist <= np.roll(dist, 1)) & (dist <= np.roll(dist, -1))
        )
        for i in near:
            x = c.states[i]
            for _ in range(4):
                v = np.asarray(rhs_alpha(0.0, x), float)
                _start(ta, FLOAT64, list(x), False)
                ta.propagate_for(float(gap(y, x) @ v / (v @ v)))
                x = np.array(ta.state, float)
            best = min(best, float(np.max(np.abs(gap(y, x)))))
    return best


def refine_bracket(args):
    """One bracket: the root in ``u`` (Brent), its verification and invariants, or ``None``."""
    from scipy.optimize import brentq

    si, j, k, E, t_half, ua, ub = args
    prob = _problem(si, j, k, E, t_half)

    def f(u):
        return float(residual(prob, u, E).r)

    try:
        u = brentq(f, ua, ub, xtol=1e-15, rtol=1e-15, maxiter=200)
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


def finish_orbit(args):
    """One orbit's trace and closure, and its state/period/trace as strings: float64 from the
    scan (``digits=None``), or re-solved at ``E`` in the tier that delivers ``digits``."""
    si, j, k, E, t_half, u, x0, T, digits = args
    if digits is None:
        M, xT, tr = monodromy_matrix(x0, T)
        clo = _closure_at(x0, [T])[0]
        return (
            tuple(repr(v) for v in x0),
            repr(T),
            repr(float(tr)),
            float(tr),
            float(T),
            clo,
        )
    from .precision import tier

    t, prob = tier(int(digits)), _problem(si, j, k, E, t_half)
    with t.context():
        u = solve(
            prob,
            t.num(u),
            t.num(u) * (1 + t.num("1e-12")),
            E=str(E),
            t=t,
            r_max=t.eps**0.6,
        ).x
        sh = residual(prob, u, str(E), t)
        n = Fraction(T / (2 * float(sh.t1))).limit_denominator(24)  # T = 2 t1 n/m
        Tm = 2 * sh.t1 * n.numerator / n.denominator
        M, xT, tr = monodromy_matrix(sh.x0, Tm, t)
        clo = max(
            abs(float(v)) for v in lattice_shift([a - b for a, b in zip(xT, sh.x0)], t)
        )
        return (
            tuple(t.text(v, digits) for v in sh.x0),
            t.text(Tm, digits),
            t.text(tr, digits - 5),
            float(tr),
            float(Tm),
            clo,
        )


def atlas_orbit(label, family, E, t_half, root, fin) -> AtlasOrbit:
    """The :class:`AtlasOrbit` of a verified root ``(si, j, k, u, x0, T, S)`` of
    :func:`refine_bracket` and its :func:`finish_orbit` ``(xs, Ts, trs, tr, Tf, closure)``."""
    si, j, k, u, x0, T, S = root
    xs, Ts, trs, tr, Tf, clo = fin
    head = (label, family, E, Tf, tr, bool(0 < tr < 4), tuple(x0), xs, Ts, trs)
    fixed, prob = (
        (start_sets(E)[si].name, targets()[j].name),
        _problem(si, j, k, E, t_half),
    )
    return AtlasOrbit(*head, fixed, float(S), clo, float(u), prob)


# --------------------------------------------------------------------------- known families


def _known_family(args):
    """``{E: (label, period, action)}`` of one daughter family at each of ``energies``."""
    from . import newborn as nb

    lab, energies = args
    spec = nb.family_spec(lab)
    try:
        b = nb.follow(
            lab,
            E_max=max(max(energies), nb.family_range(spec)[1]) + 0.05,
            energies=tuple(energies),
            max_steps=600,
        )
    except (ValueError, SectionNotReached):
        return {}
    out = {}
    for pt in b.points("E"):
        if pt.located:
            m = pt.member
            E = min(energies, key=lambda e: abs(e - float(m.E)))
            T = float(b.problem.factor * m.t1)
            out[E] = (spec.label, T, _invariants(list(b.state(m)), T, E)[1])
    return out


def _known(energies, t_max, executor=None):
    """``{E: [(label, period, action)]}``: the known families at each energy with period
    ``<= t_max`` (each daughter family followed once through all the energies)."""
    from . import newborn as nb
    from .breathers import DAUGHTER_E_MIN, breather_daughter
    from .orbits import breather, pendulum

    out = {E: [] for E in energies}

    def add(E, label, x0, T):
        if T <= t_max * 1.001:
            out[E].append((label, T, _invariants(list(x0), T, E)[1]))

    for E in energies:
        if E != 4.0:
            p = pendulum(E)
            add(E, "pendulum", p.state0, p.period)
        for fam in ("LG", "LD", "R"):
            try:
                b = breather(E, fam)
            except ValueError:
                continue
            add(E, f"breather {fam}", b.state0, b.period)
        if DAUGHTER_E_MIN <= E < 8.968:
            o = breather_daughter(E)
            add(E, "PD^b", o.state0, o.period)
    tasks = []
    for lab in nb.FAMILIES:
        spec = nb.family_spec(lab)
        es = [E for E in energies if spec.E_birth < E]
        if spec.depth >= 3e-8 and es:
            tasks.append((lab, es))
    for found in pmap(_known_family, tasks, executor=executor, desc="known families"):
        for E, (label, T, S) in found.items():
            if T <= t_max * 1.001:
                out[E].append((label, T, S))
    return out


def _name(T, S, known):
    for label, Tk, Sk in known:
        if abs(T - Tk) < 1e-6 * Tk and abs(S - Sk) < 1e-6 * Sk:
            return label
    return "new"


# --------------------------------------------------------------------------- front end


def census(
    E,
    t_max=16.0,
    grid=300,
    depth=10,
    executor=None,
    progress=False,
    name=True,
    digits=None,
    known=None,
) -> Atlas:
    """Every symmetric periodic orbit with period ``<= t_max`` at energy ``E``.

    Parameters
    ----------
    E : float
    t_max : float
        Largest period.
    grid : int
        Start points per fixed-set class on the first pass (refine until the census no longer
        changes).
    depth : int
        Intervals whose crossing structure changes are bisected up to ``depth`` times (the
        residual of an orbit with ``|tr M| ~ 1e7`` changes sign within ``~1e-3`` of the grid
        spacing, beside a change of structure: depth 6 misses some at ``T_max = 16``).
    executor : concurrent.futures.Executor, optional
        For the scan and the refinement (:func:`rotorlib.parallel.pmap`).
    progress : bool
        A progress bar on a terminal (never in notebooks).
    name : bool
        Name the orbits after the known families (follows every daughter family to ``E``).
    digits : int, optional
        ``None``: float64 results (traces from the float64 variational equations). ``D``:
        every orbit re-solved at ``E`` in the tier that delivers ``D`` digits (real128 for
        ``D <= 31``) and its state, period and trace given to ``D`` digits.
    known : list, optional
        The known families at ``E`` (computed by :func:`atlas` for all its energies at once).

    Returns
    -------
    Atlas
    """
    E, t_max = float(E), float(t_max)
    _check([E], t_max, grid)
    t0 = time.perf_counter()
    t_half = t_max / 2 * 1.02
    jobs = []
    for si in range(len(start_sets(E))):
        us, rows = scan(si, E, t_half, grid, depth, executor, progress)
        jobs += [
            (si, j, k, E, t_half, float(us[i]), float(us[i + 1]))
            for i, j, k in brackets(us, rows, t_half)
        ]
    found = [
        f
        for f in pmap(
            refine_bracket,
            jobs,
            executor=executor,
            progress=progress,
            desc="refine",
            chunksize=8,
        )
        if f is not None
    ]
    unique: list = []
    curves: list = []
    for f in sorted(found, key=lambda f: (f[5], f[0], f[1], f[2])):
        T, S = f[5], f[6]
        if T > t_max or any(
            abs(T - g[5]) < 1e-7 * T
            and abs(S - g[6]) < 1e-6 * S
            and distance_to_orbit(c, f[4]) < SAME_ORBIT
            for g, c in zip(unique, curves)
        ):
            continue
        unique.append(f)
        curves.append(SampledOrbit(f[4], T))
    if known is None:
        known = _known([E], t_max, executor)[E] if name else []
    fin = pmap(
        finish_orbit,
        [(si, j, k, E, t_half, u, x0, T, digits) for si, j, k, u, x0, T, S in unique],
        executor=executor,
        progress=progress,
        desc="orbits",
    )
    orbits = []
    D = 15 if digits is None else int(digits)
    for i, ((si, j, k, u, x0, T, S), fin_i) in enumerate(zip(unique, fin)):
        tr, clo = fin_i[3], fin_i[5]
        if not clo <= max(1e6, 1e2 * abs(tr)) * 10.0**-D:
            continue  # a near-periodic trajectory beside a very unstable orbit, not an orbit
        label, chor = atlas_name(_name(T, S, known), E, x0, T, name)
        family = label if label != "new" else f"N{i + 1}"
        o = atlas_orbit(label, family, E, t_half, (si, j, k, u, x0, T, S), fin_i)
        orbits.append(replace(o, choreography=chor))
    return Atlas(E, t_max, grid, tuple(orbits), len(jobs), time.perf_counter() - t0)


def atlas(
    energies,
    t_max=16.0,
    grid=300,
    executor=None,
    progress=False,
    digits=None,
    name=True,
) -> list:
    """:func:`census` at each energy (a list of :class:`Atlas`); the known families are
    followed once through all the energies."""
    energies = [float(E) for E in energies]
    _check(energies, t_max, grid)
    known = _known(energies, t_max, executor) if name else {E: [] for E in energies}
    return [
        census(
            E,
            t_max,
            grid,
            executor=executor,
            progress=progress,
            digits=digits,
            known=known[E],
        )
        for E in energies
    ]
