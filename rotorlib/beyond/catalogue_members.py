"""The stored members of a catalogued family: which members are stored and their
re-solve to 30 digits (the ``polish`` task of :mod:`rotorlib.beyond.catalogue_tasks`).

**Which members.** :func:`stored_members` keeps the located special points (IS, PD,
folds), the seed, and the fewest members of the family's dense float64 path such that
the period and ``tr M`` of every path member are reproduced to :data:`TOL` (relative;
``tr M`` relative to ``max(1, |tr M|)``, i.e. absolute near ``tr M = 0``) by
:func:`local_interpolant` between stored members. The path is cut into pieces on which
one parameter, ``E`` or the shooting unknown ``u``, is strictly monotone and moves faster
than the other (:func:`pieces`: a fold in ``E`` lies inside a ``u`` piece, where ``E(u)``
is smooth); on each piece the other quantities are interpolated as functions of that
parameter. Members are inserted greedily where the error is largest.

**Precision.** Each stored member is re-solved at ``digits = 30`` (heyoka real128):
``state0_str`` and the period to 30 digits, ``tr M`` to 25 digits, the closure error
printed beside them. The action ``S = oint p.dq`` is
:func:`rotorlib.beyond.quantum_trace.orbit_action` on the float64 rounding of the
30-digit orbit (a spectrally accurate trapezoid sum: ~1e-13 relative); the Maslov index
:func:`rotorlib.beyond.quantum_trace.maslov_index` (an integer, exact in float64 unless the
orbit is marginal: ``null`` with the reason at ``tr M = 4``, IS points and folds).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

__all__ = [
    "TOL",
    "DEGREE",
    "member_record",
    "problem_of",
    "polish_task",
    "solved",
    "resolve_member",
    "member_strings",
    "phase_data",
    "pieces",
    "local_interpolant",
    "interpolation_errors",
    "left_out_errors",
    "stored_members",
    "DENSIFY_ROUNDS",
    "GAP_MIN",
    "coarse_gaps",
    "shoot_member",
    "densify_task",
    "insert_members",
]

#: The interpolation tolerance the stored members are chosen for (relative).
TOL = 1e-8
#: The degree of the local interpolating polynomials (``DEGREE + 1`` stored members).
DEGREE = 7
#: Rounds of path densification (:func:`coarse_gaps`; each may halve an interval).
DENSIFY_ROUNDS = 6
#: The shortest path interval (relative in ``E``) that densification splits.
GAP_MIN = 1e-10


def member_record(m, kind: str = "path") -> dict:
    """The float64 record of an engine member ``m`` (a path member of
    :func:`rotorlib.beyond.catalogue_tasks.follow_task`): ``kind``, ``E``, ``u``, ``w``,
    ``t1``, the period, ``tr M``, ``x0`` and the shooting residual ``r``."""
    return {
        "kind": kind,
        "E": float(m.E),
        "u": float(m.u),
        "w": float(m.w),
        "t1": float(m.t1),
        "period": float(m.period),
        "trace": float(m.trace),
        "x0": [float(v) for v in m.x0],
        "r": float(m.r),
    }


def problem_of(spec: dict):
    """The shooting problem of a census orbit from its names: ``start`` (a start set),
    ``target`` (a fixed set), ``crossing``, ``t_half``, ``E`` (and ``label``, ``factor``)."""
    from ..orbits.reversors import start_sets, targets
    from .atlas import shooting_problem

    si = [s.name for s in start_sets(spec["E"])].index(spec["start"])
    j = [t.name for t in targets()].index(spec["target"])
    prob = shooting_problem(si, j, spec["crossing"], spec["E"], spec["t_half"])
    if "factor" in spec:
        prob = replace(prob, label=spec["label"], factor=spec["factor"])
    return prob


def polish_task(args: dict) -> dict:
    """A stored member re-solved at ``args['digits']`` digits at the energy
    ``args['E_str']`` from ``args['u']``: the decimal strings of ``E``, the period,
    ``state0`` and ``tr M`` (5 digits fewer), the multipliers, the closure error, the
    action and the Maslov index (:func:`phase_data`); or ``{'failed': reason}`` when the
    re-solve does not converge."""
    return solved(resolve_member, args)


def solved(solve_member, args: dict) -> dict:
    """``solve_member(args)`` (a member's decimal strings) with its action and Maslov
    index (:func:`phase_data`), or ``{'failed': reason}`` when the solve fails."""
    from ..core.flow import SectionNotReached
    from ..orbits.shooting import NoConvergence

    try:
        out = solve_member(args)
    except (NoConvergence, SectionNotReached, ValueError, ZeroDivisionError) as exc:
        return {"failed": f"{type(exc).__name__}: {exc}"[:300]}
    return {**out, **phase_data(out["state0_str"], out["period_str"], out["trace_str"])}


def phase_data(state0, period, trace) -> dict:
    """The action and Maslov index of the orbit from ``state0`` of period ``period``
    (decimal strings or floats; ``trace``: its ``tr M``): ``{'action', 'maslov',
    'maslov_reason'}``. The index is ``None`` with the reason for a marginal orbit
    (``|tr M - 4| < 1e-6``: its index is undefined).

    Examples
    --------
    >>> import rotorlib
    >>> o = rotorlib.orbit("pendulum", 6.0)
    >>> d = phase_data(o.state0, o.period, o.trace)
    >>> from rotorlib.beyond.quantum_trace import pendulum_action
    >>> d["maslov"], d["maslov_reason"], abs(d["action"] - pendulum_action(6.0)) < 1e-11
    (1, None, True)
    """
    from .quantum_trace import maslov_index, orbit_action

    x = [float(v) for v in state0]
    T = float(period)
    out: dict = {"action": orbit_action(x, T), "maslov": None, "maslov_reason": None}
    if abs(float(trace) - 4.0) < 1e-6:
        out["maslov_reason"] = "marginal orbit (tr M = 4): no Maslov index"
        return out
    try:
        out["maslov"] = int(maslov_index(x, T, 1)[0])
    except ValueError as exc:
        out["maslov_reason"] = str(exc)[:200]
    return out


def resolve_member(args: dict) -> dict:
    """The decimal strings of a member re-solved at ``args['digits']`` digits at the
    energy ``args['E_str']`` from the shooting unknown ``args['u']`` (a secant in ``u``
    at fixed ``E``; :func:`member_strings` then): what :func:`polish_task` returns before
    its action and Maslov index. Raises :class:`rotorlib.orbits.shooting.NoConvergence`
    (or ValueError) when the secant does not converge."""
    from ..core.precision import tier
    from ..orbits.shooting import solve

    D = int(args["digits"])
    prob = problem_of(
        {**args["problem"], "label": "catalogue", "factor": args["factor"]}
    )
    t = tier(D)
    with t.context():
        u0 = t.num(repr(args["u"]))
        u1 = u0 * (1 + t.num("1e-12"))
        u = solve(prob, u0, u1, E=args["E_str"], digits=t, r_max=t.eps**0.6).x
        return member_strings(prob, u, args["E_str"], D)


def member_strings(prob, u, E_str: str, digits: int) -> dict:
    """The member of ``prob`` at the shooting unknown ``u`` (a number of the tier of
    ``digits``) and the energy ``E_str`` (a decimal string; the pair a root of the
    residual), as decimal strings to ``digits``: ``E_str`` as given, ``period_str``,
    ``state0_str``, ``trace_str`` (5 digits fewer), ``u_str``, with the multipliers,
    the closure error after one period (lattice reduced) and the residual."""
    from ..core.flow import monodromy_matrix
    from ..core.precision import tier
    from ..core.system import lattice_reduce
    from ..orbits.shooting import residual

    D = int(digits)
    t = tier(D)
    with t.context():
        sh = residual(prob, u, prob.w_at(u, E_str, t), t)
        # the factor as the small rational it is (Tier.scale)
        T = t.scale(prob.factor, sh.t1)
        M, xT, tr = monodromy_matrix(sh.x0, T, t)
        d = lattice_reduce([a - b for a, b in zip(xT, sh.x0)], D)
        mult = np.linalg.eigvals(np.array(M, dtype=float))
        return {
            "E_str": E_str,
            "period_str": t.text(T, D),
            "state0_str": [t.text(v, D) for v in sh.x0],
            "trace_str": t.text(tr, D - 5),
            "u_str": t.text(u, D),
            "multipliers": [[float(z.real), float(z.imag)] for z in mult],
            "closure": max(abs(float(v)) for v in d),
            "residual": abs(float(sh.r)),
            "digits": D,
        }


# ------------------------------------------------------------------ interpolation


def pieces(E, u) -> list[tuple[int, int, str]]:
    """The path (energies ``E``, shooting unknowns ``u`` in path order) cut into pieces
    ``(first, last, param)`` (indices inclusive; neighbours share their boundary member)
    on which ``param`` (``'E'`` or ``'u'``) is strictly monotone and moves at least as
    fast as the other one.

    Examples
    --------
    >>> s = np.linspace(-1, 1, 41)  # a fold in E at s = 0
    >>> pieces(1 - 4 * s**2, s)
    [(0, 18, 'E'), (18, 23, 'u'), (23, 40, 'E')]
    """
    E, u = np.asarray(E, float), np.asarray(u, float)
    if E.shape != u.shape or E.ndim != 1 or len(E) < 2:
        raise ValueError("E and u must be 1-d arrays of the same length >= 2")
    use = np.abs(np.gradient(E)) >= np.abs(np.gradient(u))
    cuts = [0]
    for i in range(1, len(E) - 1):
        x = E if use[cuts[-1]] else u
        turn = (x[i + 1] - x[i]) * (x[i] - x[i - 1]) < 0
        if use[i] != use[cuts[-1]] or turn:
            cuts.append(i)
    cuts.append(len(E) - 1)
    out = [(a, b, "E" if use[a] else "u") for a, b in zip(cuts, cuts[1:])]
    return out


def local_interpolant(xs, Y, x, degree: int = DEGREE) -> np.ndarray:
    """The values at ``x`` of the polynomials of degree ``degree`` through the
    ``degree + 1`` nodes of ``xs`` nearest each point (the window centred on the interval
    of ``xs`` that holds it; all nodes when fewer): ``Y`` has one row per node.

    ``xs`` must be strictly increasing. The interpolant is continuous (every window
    passes through its nodes) and exact on polynomials of degree ``<= degree``.

    Examples
    --------
    >>> xs = np.linspace(0, 1, 12)
    >>> y = local_interpolant(xs, xs[:, None] ** 5, np.array([0.33]))
    >>> round(float(y[0, 0]), 12) == round(0.33**5, 12)
    True
    """
    xs = np.asarray(xs, float)
    Y = np.asarray(Y, float)
    x = np.atleast_1d(np.asarray(x, float))
    if xs.ndim != 1 or len(xs) < 1 or np.any(np.diff(xs) <= 0):
        raise ValueError("xs must be strictly increasing with at least one node")
    m = min(degree + 1, len(xs))
    pos = np.searchsorted(xs, x)
    start = np.clip(pos - (m + 1) // 2, 0, len(xs) - m)
    idx = start[:, None] + np.arange(m)
    X = xs[idx]  # (q, m)
    L = np.ones_like(X)
    for j in range(m):
        d = X - X[:, [j]]
        d[:, j] = 1.0
        f = (x[:, None] - X[:, [j]]) / d
        f[:, j] = 1.0
        L *= f
    return np.einsum("qm,qm...->q...", L, Y[idx])


def _err(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(a - b) / np.maximum(1.0, np.abs(b))


def _errors(y: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Errors of ``y`` against ``Y`` by column: relative for the period (first column,
    ``> 0``), relative to ``max(1, |Y|)`` for the others."""
    e = _err(y, Y)
    e[:, 0] = np.abs(y[:, 0] - Y[:, 0]) / np.abs(Y[:, 0])
    return e


def interpolation_errors(x, Y, nodes, degree: int = DEGREE) -> np.ndarray:
    """The error at every point ``x`` (one piece, monotone) of the interpolant through
    ``nodes`` (indices into ``x``), columns as ``Y``'s: relative for the period (first
    column, ``> 0``), relative to ``max(1, |y|)`` for the others."""
    x, Y = np.asarray(x, float), np.asarray(Y, float)
    order = np.argsort(x[nodes])
    nd = np.asarray(nodes)[order]
    return _errors(local_interpolant(x[nd], Y[nd], x, degree), Y)


def left_out_errors(x, Y, degree: int = DEGREE) -> np.ndarray:
    """The error at each point of one piece (``x`` strictly monotone) of the interpolant
    through the others (the point left out: its ``degree + 1`` nearest neighbours),
    columns as :func:`interpolation_errors`'s; ``0`` at the piece's two ends, which
    would be extrapolated.

    Where it is below a tolerance the path is dense enough for the interpolant to hold
    *between* its members as well: leaving a member out widens one node interval, so the
    left-out error bounds the error at midpoints of the full path (for smooth data; the
    chapter on the catalogue measures it at shot midpoints).

    Examples
    --------
    >>> x = np.linspace(0, 1, 20)
    >>> e = left_out_errors(x, np.stack([1 + x**7, x**3], axis=1))
    >>> bool(e.max() < 1e-12), bool(left_out_errors(x, np.exp(9 * x)[:, None]).max() > 1e-3)
    (True, True)
    """
    x, Y = np.asarray(x, float), np.asarray(Y, float)
    n = len(x)
    order = np.argsort(x)
    xs, Ys = x[order], Y[order]
    e = np.zeros(Y.shape)
    for j in range(1, n - 1):
        keep = [
            k for k in range(max(0, j - degree - 1), min(n, j + degree + 2)) if k != j
        ]
        y = local_interpolant(xs[keep], Ys[keep], xs[j : j + 1], degree)
        e[order[j]] = _errors(y, Ys[j : j + 1])[0]
    return e


def _nodes(x, Y, tol: float, degree: int) -> tuple[list[int], float]:
    """Greedy: the piece's ends, then the point of largest error, until all are within
    ``tol``; returns the nodes and the largest error left."""
    nodes = [0, len(x) - 1] if x[-1] != x[0] else [0]
    while True:
        e = interpolation_errors(x, Y, nodes, degree).max(axis=1)
        e[nodes] = 0.0
        q = int(np.argmax(e))
        if e[q] <= tol:
            return sorted(nodes), float(e.max())
        nodes.append(q)


def stored_members(f: dict, tol: float = TOL, degree: int = DEGREE) -> list[dict]:
    """The members of a followed family ``f`` to store, in path order: its located IS,
    PD and fold points, its seed, and the path members chosen for interpolation (module
    docstring; each with ``pieces``, the indices of the pieces it is a node of). Sets
    ``f['interpolation']``: the pieces (``param``, first and last path index), ``degree``,
    ``tolerance`` and the largest error left on the path (``max_error``)."""
    path = f["path"]
    E = np.array([m["E"] for m in path])
    u = np.array([m["u"] for m in path])
    T = np.array([m["period"] for m in path])
    tr = np.array([m["trace"] for m in path])
    chosen: dict[int, list[int]] = {}
    info, worst = [], 0.0
    cut = pieces(E, u) if len(path) > 1 else [(0, 0, "E")]
    for k, (a, b, param) in enumerate(cut):
        x, other = (E, u) if param == "E" else (u, E)
        cols = [T, tr] if param == "E" else [T, tr, other]
        Y = np.stack([c[a : b + 1] for c in cols], axis=1)
        nodes, e = _nodes(x[a : b + 1], Y, tol, degree)
        worst = max(worst, e)
        for n in nodes:
            chosen.setdefault(a + n, []).append(k)
        info.append({"param": param, "path": [a, b]})
    f["interpolation"] = {
        "pieces": info,
        "degree": degree,
        "tolerance": tol,
        "max_error": worst,
    }
    seed = f["seed"]
    stored = [m for m in f["special"] if m["kind"] in ("IS", "PD", "fold")]
    seed_at = None
    for i, ks in sorted(chosen.items()):
        m = dict(path[i], kind="path", index=i, pieces=ks)
        if m["E"] == seed["E"] and m["u"] == seed["u"]:
            m["kind"], seed_at = "seed", i
            m = {**seed, **m}
        stored.append(m)
    if seed_at is None:
        at = [i for i, m in enumerate(path) if m["E"] == seed["E"]]
        stored.append(dict(seed, pieces=[], index=at[0] if at else 0))
    for m in stored:
        m.setdefault("pieces", [])
    return sorted(stored, key=lambda m: m.get("index", 0))


# ------------------------------------------------------------------ densification


def coarse_gaps(f: dict, tol: float = TOL, degree: int = DEGREE) -> list[tuple]:
    """The intervals of the followed family ``f``'s path where its interpolant is not
    shown to hold between path members: ``[(i, E, u, T, box)]``, the interval from
    ``path[i]`` to ``path[i + 1]`` on a piece (:func:`pieces`) beside a member that its
    neighbours do not reproduce to ``tol`` (:func:`left_out_errors` in the piece's
    parameter, period and ``tr M``). On a piece parametrised by ``E``, ``E`` is the
    interval's midpoint, ``u`` and ``T`` the interpolant's there, and ``box`` is None; on
    a piece parametrised by ``u`` (through a fold), ``u`` is the midpoint, ``E`` and
    ``T`` the interpolant's there, and ``box`` the interval in ``u``, inside which the
    member shot at ``E`` must land (:func:`densify_task`: at a fold's ``E`` two members
    exist). Intervals shorter than :data:`GAP_MIN` (relative) are not split.

    Each member tested is marked with its left-out error (``left_out``), and a member
    inserted in an interval (:func:`insert_members`) with the larger of its ends'
    (``parent``). A member whose error is not 4 times below that, its intervals having
    been split, is limited by the float64 accuracy of the path there, not by its
    spacing (``noise``: very unstable orbits, long passages near a separatrix's saddle):
    it is not split again. (Where the data are smooth a degree-7 interpolant's error
    falls by ~2^8 when the spacing halves.) An interval beside a member above ``tol``
    more than 4 times longer than a neighbouring interval is split all the same: the
    path is kept graded where the spacing hid a feature (an engine stop beside an
    unlocated fold, whose new members' errors are larger than their parents').

    Examples
    --------
    >>> E = np.linspace(1.0, 2.0, 12)
    >>> path = [{"E": e, "u": e, "period": 1 / (2.05 - e), "trace": 1.0} for e in E]
    >>> [i for i, *_ in coarse_gaps({"path": path})][-3:]
    [8, 9, 10]
    """
    path = f["path"]
    if len(path) < 3:
        return []
    E, u, T, tr = (
        np.array([m[k] for m in path]) for k in ("E", "u", "period", "trace")
    )
    out: list[tuple] = []
    for a, b, param in pieces(E, u):
        if b - a < 2:
            continue
        sl = slice(a, b + 1)
        x, other = (E, u) if param == "E" else (u, E)
        e = left_out_errors(x[sl], np.stack([T[sl], tr[sl]], axis=1), degree)
        err, bad = e.max(axis=1), set()
        for j in np.flatnonzero(err > tol):
            m = path[a + j]
            # split beside it (or born of a split), and no better
            if err[j] > 0.25 * m.get("left_out", m.get("parent", np.inf)):
                m["noise"] = True
            m["left_out"] = float(err[j])
            if not m.get("noise"):
                bad |= {a + j - 1, a + j}
        h = np.abs(np.diff(x[sl]))  # graded where the error is above tol
        nb = np.minimum(np.r_[np.inf, h[:-1]], np.r_[h[1:], np.inf])
        bad |= {
            a + i for i in np.flatnonzero((h > 4 * nb) & (err[:-1] + err[1:] > tol))
        }
        gaps = [
            i
            for i in sorted(bad)
            if a <= i < b and abs(x[i + 1] - x[i]) > GAP_MIN * max(1.0, abs(x[i]))
        ]
        if not gaps:
            continue
        order = np.argsort(x[sl])
        xs, Ys = x[sl][order], np.stack([other[sl], T[sl]], axis=1)[order]
        mid = 0.5 * (x[gaps] + x[np.array(gaps) + 1])
        Y = local_interpolant(xs, Ys, mid, degree)
        for i, m, y in zip(gaps, mid, Y):
            Ei, ui = (m, y[0]) if param == "E" else (y[0], m)
            # a u piece: the member shot at E(u) must land inside the interval in u
            box = None if param == "E" else sorted((float(u[i]), float(u[i + 1])))
            out.append((int(i), float(Ei), float(ui), float(y[1]), box))
    return out


def shoot_member(
    problem: Any,
    E: Any,
    u0: float,
    period: float | None = None,
    box: tuple[float, float] | None = None,
    digits: int | None = None,
) -> Any:
    """The member at ``E`` shot to ``digits`` from the guess ``u0`` of its shooting
    unknown (a :class:`~rotorlib.orbits.family.Member`, ``tr M`` computed).

    Raises :class:`~rotorlib.orbits.shooting.NoConvergence` when the shot fails, and
    ValueError when it lands on another orbit: its period more than 1e-4 (relative)
    from ``period``, or its ``u`` outside the open interval ``box`` (beside a fold two
    members share ``E``; the period does not tell them apart there).
    """
    from ..core.precision import tier
    from ..orbits.continuation import member
    from ..orbits.shooting import solve

    t = tier(digits)
    with t.context():
        x0 = t.num(repr(float(u0)))
        u = solve(problem, x0, x0 * (1 + t.num("1e-9")), E=E, digits=t).x
        m = member(problem, u, str(E) if t.extended else float(E), t, traces=True)
    if box is not None and not box[0] < float(m.u) < box[1]:
        raise ValueError(f"u = {float(m.u)!r} outside the interval {tuple(box)!r}")
    if period is not None and abs(float(m.period) / period - 1) > 1e-4:
        raise ValueError(f"period {float(m.period)!r}, guessed {period!r}")
    return m


def densify_task(args: dict) -> list[dict]:
    """Path members solved in float64 at the energies ``args['E']`` from the guesses
    ``args['u']`` (records as :func:`rotorlib.beyond.catalogue_tasks.follow_task`'s
    path: ``tr M`` computed), one per energy (:func:`shoot_member`); ``{'failed':
    reason}`` where the shot does not converge or lands on another orbit: on a piece
    parametrised by ``E``, more than 1e-4 (relative) from the guessed period
    ``args['period']``; on one parametrised by ``u`` (``args['box']``, :func:`coarse_gaps`),
    with its ``u`` outside the interval."""
    from ..core.flow import SectionNotReached
    from ..orbits.shooting import NoConvergence

    prob = problem_of(
        {**args["problem"], "label": "catalogue", "factor": args["factor"]}
    )
    out = []
    boxes = args.get("box", [None] * len(args["E"]))
    for E, u0, T0, box in zip(args["E"], args["u"], args["period"], boxes):
        try:
            # a u piece's box tells the branches apart; an E piece's guessed period
            m = shoot_member(prob, E, u0, None if box else T0, box)
            out.append(member_record(m))
        except (NoConvergence, SectionNotReached, ValueError, ZeroDivisionError) as exc:
            out.append({"failed": f"{type(exc).__name__}: {exc}"[:300]})
    return out


def insert_members(f: dict, gaps: list[tuple], found: list[dict]) -> int:
    """Insert into ``f``'s path the members ``found`` (:func:`densify_task`) of the
    intervals ``gaps`` (:func:`coarse_gaps`: after ``path[i]``), failures left out, and
    re-index its special points (``index``, ``index_end``) so that each still follows
    the path member before it. Returns how many were inserted.

    A special point between ``path[k]`` and ``path[k + 1]`` goes after a member inserted
    there when its projection on the chord from ``path[k]`` to ``path[k + 1]`` in the
    ``(E, period)`` plane is the farther along: through a fold ``E`` alone does not order
    them (it turns), the period does.

    Examples
    --------
    >>> path = [{"E": 1.0, "period": 3.0}, {"E": 2.0, "period": 5.0}]
    >>> f = {"path": path, "special": [{"E": 1.7, "period": 4.4, "index": 0}]}
    >>> insert_members(f, [(0, 1.5, 0.0, 4.0, None)], [{"E": 1.5, "period": 4.0}])
    1
    >>> [m["E"] for m in f["path"]], f["special"][0]["index"]
    ([1.0, 1.5, 2.0], 1)
    """
    path = f["path"]
    add = {
        g[0]: dict(m, parent=max(path[g[0] + d].get("left_out", 0.0) for d in (0, 1)))
        for g, m in zip(gaps, found)
        if "failed" not in m
    }
    if not add:
        return 0
    new: list[dict] = []
    where: list[int] = []
    for k, m in enumerate(path):
        where.append(len(new))
        new += [m, add[k]] if k in add else [m]

    def along(k: int, x: dict, coords: tuple[str, ...]) -> float:
        a, b = path[k], path[k + 1]
        d = [b[c] - a[c] for c in coords]
        n = sum(dc * dc for dc in d) or 1.0
        return sum((x[c] - a[c]) * dc for c, dc in zip(coords, d)) / n

    def moved(k: int, x: dict, coords: tuple[str, ...] = ("E", "period")) -> int:
        if not 0 <= k < len(path):
            return k if k < 0 else k + len(new) - len(path)
        m = add.get(k)
        return where[k] + int(
            m is not None and along(k, x, coords) > along(k, m, coords)
        )

    for p in f.get("special", []):
        p["index"] = moved(p["index"], p)
        if "index_end" in p:  # a marginal window's end: its period is not kept
            end = {"E": p.get("E_end", p["E"])}
            p["index_end"] = moved(p["index_end"], end, ("E",))
    f["path"] = new
    f.pop("_by_E", None)
    f.pop("_seg", None)
    return len(add)
