"""Families of periodic orbits: one continuation engine for every :class:`ShootingProblem`.

``continuation(problem, algorithm, options, start)`` follows the curve ``r(u, w) = 0``
of :func:`rotorlib.orbits.shooting.residual` from known members and returns a :class:`Branch`:
members and special points. :class:`Natural` steps ``u`` or ``E`` through given values
(secant corrector, failed steps halved; it cannot pass a fold of its parameter);
:class:`PALC` (pseudo-arclength, steps relative to the current member, Newton on
``[r = 0, tangent . (X - X_k) = ds]``) passes folds. Both honour the stopping rules of
:class:`ContinuationOptions`. Events (:class:`SpecialPoint`): ``fold``, ``E`` (a
requested energy), ``IS`` / ``PD`` (``tr M`` crosses 4 / 0, with ``options.traces``),
located between members by :func:`illinois`. ``Branch.stop`` says why it ended (``values``,
``steps``, ``E range``, ``period``: the period exceeds ``t_max``, ``event``, ``stuck``); ``reason`` too. Members satisfy ``|r| < options.r_max`` (default
1e-8 float64, ``eps^(2/3)`` extended); located events are solved to the tier's precision.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

from ..core.flow import SectionNotReached, monodromy_matrix
from ..core.precision import Tier, tier
from .family import Branch, Member, SpecialPoint
from .shooting import NoConvergence, ShootingProblem, residual, solve

__all__ = [
    "Member",
    "SpecialPoint",
    "Branch",
    "Natural",
    "PALC",
    "ContinuationOptions",
    "continuation",
    "member",
    "switch",
    "FamilyEnd",
    "illinois",
]


class FamilyEnd(ValueError):
    """Natural continuation stopped: ``label, members, E_asked`` (nan: u)."""

    def __init__(self, label: str, members: Any, E_asked: float, par: str):
        self.label, self.members, self.E_asked = label, members, E_asked
        E = float(members[-1].E)
        ask = f"; asked for E = {E_asked!r}" if E_asked == E_asked else ""
        super().__init__(
            f"{label}: the family was not found beyond E = {E!r} (a fold "
            f"in {par}, or the orbit stops reaching its section){ask}"
        )


@dataclass(frozen=True)
class Natural:
    """Natural-parameter continuation through ``values`` of ``parameter`` (``u`` or ``E``).

    The predictor extrapolates the other unknown with a polynomial of degree ``order``
    through the last members in the coordinate ``s``: ``u^2`` for ``parameter='u'``
    (a fork is even in ``u``), ``sqrt|E - origin|`` for ``'E'`` (a fork has
    ``u ~ sqrt|E - E_n|``; ``E`` itself without ``origin``). ``origin`` (with
    ``origin_other``) is a virtual member at the bifurcation used by the first predictions.
    A failed step is halved in ``s`` (at most 12 times).
    """

    parameter: str
    values: tuple[Any, ...]
    order: int = 1
    origin: Any = None
    origin_other: Any = None


@dataclass(frozen=True)
class PALC:
    """Pseudo-arclength continuation.

    ``ds`` is the first step, ``ds_max``/``ds_min`` its bounds, in the plane
    ``((u - u_k) / |u_k|, (w - w_k) / |E_k - E_ref|)`` rescaled at every member ``k``
    (floors ``u_floor``, ``w_floor``); ``direction`` is the sign of ``du`` of the first
    step. The predictor is the quadratic through the last three members (in ``u^2`` when
    the step holds ``u``; along the tangent at the first step). ``scales = (su, sw)``
    fixes the scales instead: a step moves ``u`` by at most ``ds su`` and ``w`` by at most
    ``2 ds sw`` (for a family that crosses a narrow window of energy with large changes of
    ``u``).
    """

    ds: float = 0.3
    ds_max: float = 1.0
    ds_min: float = 1e-7
    E_ref: float = 0.0
    u_floor: float = 1e-12
    w_floor: float = 1e-12
    direction: int = 1
    scales: tuple[float, float] | None = None


@dataclass(frozen=True)
class ContinuationOptions:
    """Stopping rules and events (honoured by :class:`Natural` and :class:`PALC` alike).

    Attributes
    ----------
    max_steps : int
        Stop (``steps``) after this many members are added.
    E_range : (float, float)
        Stop (``E range``) once a member leaves it.
    t_max : float
        Stop (``period``) once the period (the full period, ``factor t1``) exceeds it.
    jump : float or None
        Refuse a step that changes ``t1`` by more than this fraction (a long step can
        land on another family whose members are close in ``(u, w)``).
    traces : bool
        ``tr M`` of every member; detect and locate ``IS`` and ``PD`` points.
    energies : tuple
        Locate a member at each of these energies (``E`` points; decimal strings keep
        their digits in extended tiers).
    folds : bool
        Locate the folds of ``E``.
    r_max : float or None
        Accepted residual (default 1e-8 float64, ``eps^(2/3)`` extended).
    stop_on : tuple
        Stop (``event``) once ``tr M`` crosses the level of one of these kinds (``IS``: 4,
        ``PD``: 0; needs ``traces``).
    enter : bool
        Members before the first one inside ``E_range`` approach it and do not stop the
        branch, unless one lands beyond the range's far end (:func:`rotorlib.paper.newborn_families.family`
        from a seed below the range).
    """

    max_steps: int = 400
    E_range: tuple[Any, Any] = (-math.inf, math.inf)
    t_max: float = math.inf
    jump: float | None = None
    traces: bool = False
    energies: tuple[Any, ...] = ()
    folds: bool = True
    r_max: float | None = None
    stop_on: tuple[str, ...] = ()
    enter: bool = False


def member(
    problem: ShootingProblem,
    u: Any,
    w: Any,
    digits: int | Tier | None = None,
    traces: bool = False,
) -> Member:
    """The :class:`Member` at ``(u, w)`` (``tr M`` over the full period with ``traces``)."""
    t = tier(digits)
    with t.context():
        s = residual(problem, u, w, t)
        tr = monodromy_matrix(s.x0, problem.factor * s.t1, t)[2] if traces else math.nan
        r = abs(float(s.r))
        d = min(t.dps - 8, int(-math.log10(r))) if r > 0 else t.dps - 8
        return Member(
            t.num(u),
            t.num(w),
            problem.energy(u, w, t),
            s.t1,
            s.r,
            tr,
            tuple(s.x1),
            problem.label,
            problem.factor,
            tuple(s.x0),
            max(1, d) if t.extended else 15,
            t.name,
        )


def switch(
    problem: ShootingProblem,
    u: Any,
    E_birth: Any,
    dE: Any,
    digits: int | Tier | None = None,
    tol: Any = None,
    r_max: float | None = None,
) -> tuple[Member, int]:
    """The member of ``problem`` (a daughter family whose parent is its ``trivial`` root,
    divided out of the residual) with amplitude ``u``, by a secant in ``w`` from the
    bifurcation energy ``E_birth`` and ``E_birth + dE`` (the paper's "adjust one quantity").
    Returns ``(member, secant iterations)``."""
    t = tier(digits)
    with t.context():
        E0 = t.num(E_birth)
        w0, w1 = problem.w_at(u, E0, t), problem.w_at(u, E0 + t.num(dE), t)
        root = solve(problem, w0, w1, u=u, digits=t, tol=tol, r_max=r_max)
        return replace(member(problem, u, root.x, t), r=root.residual), root.iterations


# --------------------------------------------------------------------------- natural


def _extrapolate(xs, ys, x, order, t: Tier):
    """Lagrange extrapolation through the last ``order + 1`` points (duplicates dropped)."""
    pts = list(zip(xs, ys))[-(order + 1) :]
    while len(pts) > 1 and len({p[0] for p in pts}) < len(pts):
        pts = pts[1:]
    with t.context():
        out = 0
        for i, (xi, yi) in enumerate(pts):
            term = yi
            for xj, _ in pts[:i] + pts[i + 1 :]:
                term = term * (x - xj) / (xi - xj)
            out = out + term
        return out


def _natural(problem, alg: Natural, opts, start, t: Tier, on_member):
    par = alg.parameter
    if par not in ("u", "E"):
        raise ValueError(f"Natural: parameter must be 'u' or 'E', got {par!r}")

    def s_of(v):  # the predictor's coordinate
        if par == "u":
            return v * v
        return v if alg.origin is None else t.m.sqrt(abs(v - alg.origin))

    members = list(start)
    with t.context():
        xs = [s_of(mb.u if par == "u" else mb.E) for mb in members]
        ys = [mb.w if par == "u" else mb.u for mb in members]
        if alg.origin is not None:
            xs.insert(0, s_of(t.num(alg.origin)) if par == "u" else t.num(0))
            ys.insert(0, t.num(alg.origin_other))
        targets = [t.num(v) for v in alg.values]
        halvings = 0
        while targets:
            if len(members) - len(start) >= opts.max_steps:
                return members, "steps"
            v = targets[0]
            guess = _extrapolate(xs, ys, s_of(v), alg.order, t)
            try:
                x = solve(problem, guess, digits=t, r_max=opts.r_max, **{par: v}).x
                u, w = (v, x) if par == "u" else (x, problem.w_at(x, v, t))
                new = member(problem, u, w, t, opts.traces)
                if (
                    opts.jump is not None
                    and abs(new.t1 / members[-1].t1 - 1) > opts.jump
                ):
                    raise NoConvergence(problem.label, {par: v}, None, "t1 jumped")
            except (NoConvergence, SectionNotReached):
                if halvings >= 12:
                    raise FamilyEnd(
                        problem.label,
                        members,
                        float(v) if par == "E" else math.nan,
                        par,
                    ) from None
                halvings += 1
                prev = members[-1].u if par == "u" else members[-1].E
                if par == "u":
                    targets.insert(0, (prev + v) / 2)
                else:
                    sm = (s_of(prev) + s_of(v)) / 2
                    targets.insert(
                        0,
                        sm
                        if alg.origin is None
                        else alg.origin + (1 if v > alg.origin else -1) * sm * sm,
                    )
                continue
            members.append(new)
            xs.append(s_of(v))
            ys.append(new.w if par == "u" else new.u)
            targets.pop(0)
            why = on_member(members)
            if why:
                return members, why
    return members, "values"


def _crossed(opts, members):
    """Whether ``tr M`` of the last two members crosses a level of ``opts.stop_on``."""
    a, b = members[-2].trace, members[-1].trace
    levels = {"IS": 4, "PD": 0}
    return any((a - levels[k]) * (b - levels[k]) < 0 for k in opts.stop_on)


class _Local:
    """Coordinates centred on a reference member and scaled by it,
    ``X = ((u - u_k) / su, (w - w_k) / sw)`` with ``su = |u_k|``, ``sw = |E_k - E_ref|``
    (floors ``u_floor``, ``w_floor``), and the local-parametrization corrector."""

    def __init__(self, problem, t, alg, ref: Member, opts):
        self.p, self.t, self.ref, self.opts = problem, t, ref, opts
        with t.context():
            self.su, self.sw = (
                (t.num(v) for v in alg.scales)
                if alg.scales is not None
                else (
                    max(abs(ref.u), t.num(alg.u_floor)),
                    max(abs(ref.E - t.num(alg.E_ref)), t.num(alg.w_floor)),
                )
            )

    def X(self, m: Member):
        return ((m.u - self.ref.u) / self.su, (m.w - self.ref.w) / self.sw)

    def tangent(self):
        """The unit tangent at the reference (kernel of the variational gradient of ``r``)."""
        s = residual(self.p, self.ref.u, self.ref.w, self.t, derivative=True)
        g = (s.grad[0] * self.su, s.grad[1] * self.sw)
        n = self.t.m.sqrt(g[0] ** 2 + g[1] ** 2)
        return (-g[1] / n, g[0] / n)

    def correct(self, k, value, guess, change):
        """The member with coordinate ``k`` (``0``: ``u``, ``1``: ``w``) at ``value``, the
        other solved by the secant from ``guess`` (first step ``1e-4`` of the predicted
        ``change``). Raises NoConvergence or SectionNotReached."""
        t, floor = self.t, (self.sw, self.su)[k]  # the scale of the other coordinate
        tol = 1e-13 if not t.extended else t.num(t.eps) * 8
        x1 = guess + max(
            abs(change) * t.num("1e-4"),
            abs(guess) * t.num(t.eps) ** t.num(0.5),
            floor * tol,
        )
        x = solve(
            self.p,
            guess,
            x1,
            digits=t,
            tol=tol,
            floor=floor,
            r_max=self.opts.r_max,
            **{"uw"[k]: value},  # the held coordinate
        ).x
        u, w = (value, x) if k == 0 else (x, value)
        return member(self.p, u, w, t, self.opts.traces)


def _held(d):
    """The coordinate held fixed for a step along ``d`` (scaled): ``u`` unless it is nearly
    stationary (a turning point of ``u``); near a fork ``E - E_n ~ u^2`` changes twice as
    fast as ``u`` in relative terms, and ``w(u^2)`` is the smooth prediction."""
    return 0 if abs(d[0]) >= abs(d[1]) / 5 else 1


def _predict(members, k, value, order, t):
    """The other coordinate at ``value`` of coordinate ``k``: Lagrange extrapolation through
    the last members, in ``u^2`` when stepping ``u`` (a fork is even in ``u``)."""
    xs = [m.u * m.u if k == 0 else m.w for m in members]
    ys = [m.w if k == 0 else m.u for m in members]
    return _extrapolate(xs, ys, value * value if k == 0 else value, order, t)


def _palc(problem, alg: PALC, opts, start, t: Tier, on_member):
    members = list(start)
    ds, stop = t.num(alg.ds), "steps"
    with t.context():
        for _ in range(opts.max_steps):
            ref = members[-1]
            loc = _Local(problem, t, alg, ref, opts)
            if len(members) >= 2:
                d = tuple(-x for x in loc.X(members[-2]))
            else:
                try:
                    d = loc.tangent()
                except (SectionNotReached, ValueError):
                    stop = "section lost"
                    break
                if (d[0] > 0) != (alg.direction > 0):
                    d = (-d[0], -d[1])
            k = _held(d)
            j, sign = 1 - k, (1 if d[k] > 0 else -1)  # j: the coordinate solved for
            at, sc = (ref.u, ref.w), (loc.su, loc.sw)  # the reference and the scales
            new = None
            while ds >= alg.ds_min:
                value = at[k] + sign * ds * sc[k]
                if len(members) >= 2:
                    guess = _predict(members, k, value, 2, t)
                else:  # along the tangent
                    guess = at[j] + (d[j] / d[k]) * (value - at[k]) / sc[k] * sc[j]
                change = guess - at[j]
                try:
                    mb = loc.correct(k, value, guess, change)
                except (SectionNotReached, ValueError):
                    ds = ds / 2
                    continue
                # a correction far beyond the predicted change may be another family (they
                # lie close in (u, w) near E = 4), unless t1 moved continuously
                got, dt1 = (mb.u, mb.w)[j], abs(mb.t1 - ref.t1) / abs(ref.t1)
                far = (
                    abs(got - guess) > abs(change) / 5 + abs(got) * 1e-10 and dt1 > 0.01
                )
                jump = opts.jump is not None and dt1 > opts.jump
                if alg.scales is not None:  # fixed scales bound both coordinates
                    jump = jump or abs(got - at[j]) > 2 * ds * sc[j]
                if not far and not jump:
                    new = mb
                    break
                ds = ds / 2
            if new is None:
                stop = "stuck"
                break
            members.append(new)
            ds = min(ds * t.num(1.5), t.num(alg.ds_max))
            why = on_member(members)
            if why:
                stop = why
                break
    return members, stop


# --------------------------------------------------------------------------- events


def _between(problem, t, alg, members, i, j, opts):
    """``(at, vb)``: members between ``members[i]`` and ``members[j]``, parametrised by the
    coordinate held by the step (:func:`_held`), ``v`` from 0 at ``i`` to ``vb`` at ``j``,
    the other interpolated through the neighbouring members and corrected."""
    a, b = members[i], members[j]
    loc = _Local(problem, t, alg, a, opts)
    Xb = loc.X(b)
    k = _held(Xb)
    known = members[max(0, i - 1) : j + 2]  # i, j and their neighbours

    def at(v):
        value = a.u + v * loc.su if k == 0 else a.w + v * loc.sw
        guess = _predict(known, k, value, len(known) - 1, t)
        return loc.correct(k, value, guess, (b.w - a.w) if k == 0 else (b.u - a.u))

    return at, Xb[k]


def illinois(
    g: Callable[[Any], Any],
    at: Callable[[Any], Any],
    vb: Any,
    ga: Any,
    gb: Any,
    tol: Any,
    maxiter: int = 100,
) -> Any:
    """The member ``at(v)`` where ``g`` vanishes for ``v`` in ``(0, vb)`` (``g`` of opposite
    signs ``ga``, ``gb`` at the ends): the Illinois variant of regula falsi, a bracketing
    superlinear method that works on floats and mpf alike."""
    a, b, side, last = 0 * vb, vb, 0, None
    for _ in range(maxiter):
        c = (a * gb - b * ga) / (gb - ga)
        m = at(c)
        gc = g(m)
        if gc == 0 or (last is not None and abs(c - last) <= tol * abs(vb)):
            return m
        last = c
        if (gc > 0) == (gb > 0):  # the end kept twice running is halved (Illinois)
            b, gb, ga, side = c, gc, ga / 2 if side == -1 else ga, -1
        else:
            a, ga, gb, side = c, gc, gb / 2 if side == 1 else gb, 1
    return m


def _events(problem, t, branch_members, opts, alg):
    """Special points between consecutive members: a secant on the local parameter for the
    zeros of ``E - E_target`` and ``tr M - 4``, ``tr M``; bounded Brent for the folds of
    ``E`` (``E`` to ~1e-15: the extremum is quadratic). A point that cannot be located (the
    orbit stops reaching its section there) is kept unlocated; a sign change where the
    located ``|g|`` exceeds 1 and ``1e-6`` of its values at the two members (a root's is
    ~1e-14 of them) is a pole of ``tr M`` (``~1e14`` beside a separatrix), not a root,
    and is dropped."""
    from scipy.optimize import minimize_scalar

    pal = alg if isinstance(alg, PALC) else PALC()
    out = []
    with t.context():
        tol = 1e-14 if not t.extended else t.num(t.eps) * 4
        tol_tr = tol if not t.extended else t.num(t.eps) ** t.num(0.5)  # ~d - log10|M|
        checks = [("E", lambda m, e=t.num(e): m.E - e, tol) for e in opts.energies]
        if opts.traces:
            checks += [
                ("IS", lambda m: m.trace - 4, tol_tr),
                ("PD", lambda m: m.trace, tol_tr),
            ]
        for k in range(1, len(branch_members)):
            a, b = branch_members[k - 1], branch_members[k]
            for kind, g, tol in checks:
                if not g(a) * g(b) < 0:
                    continue
                try:
                    at, vb = _between(problem, t, pal, branch_members, k - 1, k, opts)
                    m = illinois(g, at, vb, g(a), g(b), tol)
                    if abs(g(m)) <= max(1, 1e-6 * max(abs(g(a)), abs(g(b)))):
                        why = "Illinois between two members" + (
                            f" (to {float(tol):.0e}, {t.name})"
                        )
                        out.append(SpecialPoint(kind, m, k - 1, why))  # else a pole
                except (SectionNotReached, ValueError):
                    out.append(SpecialPoint(kind, b, k - 1, None))
            if opts.folds and k < len(branch_members) - 1:
                c = branch_members[k + 1]
                if not (b.E - a.E) * (c.E - b.E) < 0:
                    continue
                try:
                    at, vc = _between(
                        problem, t, pal, branch_members, k - 1, k + 1, opts
                    )
                    sign = 1 if b.E > a.E else -1
                    res = minimize_scalar(
                        lambda v: -sign * float(at(v).E),
                        method="bounded",
                        bounds=sorted((0.0, float(vc))),
                        options={"xatol": 1e-10 * abs(float(vc))},
                    )
                    out.append(
                        SpecialPoint(
                            "fold",
                            at(t.num(res.x)),
                            k,
                            f"bounded Brent: the extremum of E between members ({t.name})",
                        )
                    )
                except (SectionNotReached, ValueError):
                    out.append(SpecialPoint("fold", b, k, None))
    return sorted(out, key=lambda p: p.index)


# --------------------------------------------------------------------------- front end


def continuation(
    problem: ShootingProblem,
    algorithm: Natural | PALC,
    options: ContinuationOptions | None = None,
    start: Sequence[Member] = (),
    digits: int | Tier | None = None,
) -> Branch:
    """Follow the family of ``problem`` from the members ``start`` (see the module docstring).

    Parameters
    ----------
    problem : ShootingProblem
    algorithm : Natural or PALC
    options : ContinuationOptions, optional
    start : sequence of Member
        Known members, in order along the branch (at least one).
    digits : int or Tier, optional
        Working precision of every shot (:func:`~rotorlib.core.precision.tier`; float64).

    Returns
    -------
    Branch

    Examples
    --------
    >>> from rotorlib.orbits.continuation import Natural, continuation
    >>> from rotorlib.paper.newborn import family_spec, seed
    >>> spec, (m0, _) = family_spec("IS^l_2"), seed("IS^l_2")
    >>> alg = Natural("E", (3.998, 3.999, 4.0), origin=spec.E_birth, origin_other=0.0)
    >>> b = continuation(spec.problem, alg, start=[m0])
    >>> b.stop, [round(float(E), 4) for E in b.E], round(float(b.u[2]), 6)
    ('values', [3.9969, 3.998, 3.999, 4.0], 0.12372)
    """
    t = tier(digits)
    opts = options or ContinuationOptions()
    if not start:
        raise ValueError("continuation needs at least one starting member")
    start = [
        m
        if not opts.traces or m.trace == m.trace
        else member(problem, m.u, m.w, t, True)
        for m in start
    ]

    lo, hi = opts.E_range
    entered = [not opts.enter or lo <= start[-1].E <= hi]

    def on_member(members):
        m = members[-1]
        if lo <= m.E <= hi:
            entered[0] = True
        elif entered[0] or (m.E < lo if members[0].E > hi else m.E > hi):
            return "E range"
        if float(m.period) > opts.t_max:
            return "period"
        return "event" if _crossed(opts, members) else ""

    runs: dict[type, Callable[..., Any]] = {Natural: _natural, PALC: _palc}
    run = runs.get(type(algorithm))
    if run is None:
        raise ValueError(f"algorithm must be Natural or PALC, got {algorithm!r}")
    members, stop = run(problem, algorithm, opts, start, t, on_member)
    return Branch(
        problem,
        t,
        tuple(members),
        tuple(_events(problem, t, members, opts, algorithm)),
        stop,
        _reason(stop, members, opts),
        tuple(opts.E_range),
    )


def _reason(stop: str, members, opts) -> str:
    """One sentence saying why a continuation ended (:attr:`Branch.reason`)."""
    m, n, (lo, hi) = members[-1], len(members), map(float, opts.E_range)
    why = {
        "values": "every value asked for was reached",
        "steps": f"max_steps = {opts.max_steps} members were added",
        "period": f"the period {float(m.period):.6g} exceeds t_max = {opts.t_max:.6g} "
        "(the family runs into an orbit of infinite period)",
        "event": f"tr M crossed a level of stop_on = {opts.stop_on}",
        "stuck": "the step fell below its minimum (the family ends or turns sharply)",
        "section lost": "the orbit no longer reaches its section",
        "E range": f"it is the first member outside E_range = ({lo:g}, {hi:g})",
    }.get(stop, stop)
    if stop == "E range" and not lo <= members[0].E <= hi:
        why += f"; the first member, E = {float(members[0].E):.6g}, is outside it too"
    return f"{stop}: ended after {n} members, the last at E = {float(m.E):.6g}: {why}"
