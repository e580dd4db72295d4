"""Which family holds an orbit, for the catalogue build (:mod:`rotorlib.beyond.catalogue_build`).

* :func:`covers`: a census orbit is a member of a followed family at its energy;
* :func:`on_family`: an orbit lies on a family's path between two members (the period
  and ``tr M`` interpolated);
* :func:`drop_contained`: the records whose paths lie on the others' (one family met
  from two seeds, a record stopped early, a bridge between two others);
* :func:`cut_at_critical`: a follow cut where the engine carried it across a critical
  energy onto another orbit;
* :func:`cut_at_reversal`: a follow cut where its path turns back in ``E`` with no
  located fold;
* :func:`cut_at_switch`: a follow cut at a fold where the engine turned onto another
  family's branch (a pitchfork);
* :func:`cut_untrusted`: a follow cut where its float64 members disagree with their
  30-digit re-solves;
* :func:`bands_of`, :func:`period_bound`: the build's scope, a period bound for each
  band of energies (``T <= 16`` up to ``E = 6.2``, ``T <= 8`` above, say).

Precision: the tolerances of each test (relative period, ``tr M``) are in its docstring;
the paths are float64 continuation members ~0.01 apart in ``E``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..core.system import BREATHER_SEPARATRIX_ENERGY, SEPARATRIX_ENERGY
from .catalogue_tasks import TRACE_TOL_SQ, near

__all__ = [
    "PATH_TOL",
    "TRUST",
    "bands_of",
    "period_bound",
    "covers",
    "same_orbit",
    "on_family",
    "drop_contained",
    "holds",
    "cut_at_critical",
    "seed_index",
    "cut_untrusted",
    "cut_at_switch",
    "cut_at_reversal",
    "beyond_jobs",
    "cut_beyond",
]


#: ``(rel_T, tol_tr)`` of :func:`on_family` for a point of one path tested on another
#: (both interpolated: looser than for a census orbit; see :func:`drop_contained`).
PATH_TOL = (2e-5, 5e-3)


def bands_of(
    t_max: float | Sequence[tuple[float, float]], hi: float
) -> tuple[tuple[float, float], ...]:
    """The build's scope as bands ``((E_hi, T_max), ...)``, ``E_hi`` increasing: the
    census at ``E`` seeks periods ``<= T_max`` of the first band with ``E <= E_hi``. A
    number is one band up to ``hi``.

    >>> bands_of(8, 8.0), bands_of([(8.0, 8), (6.2, 16)], 8.0)
    (((8.0, 8.0),), ((6.2, 16.0), (8.0, 8.0)))
    >>> bands_of([(6.2, 16)], 8.0)
    Traceback (most recent call last):
    ...
    ValueError: the bands ((6.2, 16.0),) must reach the highest energy 8.0
    """
    if isinstance(t_max, (int, float)):
        raw = [(float(hi), float(t_max))]
    else:
        raw = sorted((float(e), float(t)) for e, t in t_max)
    bands = tuple(raw)
    if not bands or any(not (t > 0 and math.isfinite(t)) for _, t in bands):
        raise ValueError(f"the period bounds must be positive numbers, got {t_max!r}")
    if bands[-1][0] < hi:
        raise ValueError(f"the bands {bands!r} must reach the highest energy {hi!r}")
    return bands


def period_bound(bands: Sequence[tuple[float, float]], E: float) -> float:
    """``T_max`` of the census at ``E`` (:func:`bands_of`; a band's ``E_hi`` belongs to it).

    >>> period_bound(((6.2, 16.0), (8.0, 8.0)), 6.2), period_bound(((6.2, 16.0),
    ...     (8.0, 8.0)), 6.25)
    (16.0, 8.0)
    """
    return next((t for e, t in bands if E <= e + 1e-12), bands[-1][1])


def covers(fam: dict, orb: dict) -> bool:
    """Whether a followed family has a member at the census orbit's energy with its
    period (1e-7 relative) and ``tr M`` (1e-5 relative, at least absolute). An orbit found
    by a ``switch`` task (off the census energies, key ``via``) is tested with
    :func:`on_family` instead. A seed marked with its census's bound (``t_max``) is
    covered only by a family followed as far (its ``t_max`` at least as large)."""
    if fam.get("t_max", math.inf) < orb.get("t_max", 0.0):
        return False
    if "via" in orb:
        if orb["via"] == ["speed"]:  # a census off the follows' energies (see build)
            return on_family(fam, orb, *PATH_TOL)
        return on_family(fam, orb)
    return any(
        same_orbit(m, orb) for m in _at_energies(fam).get(round(orb["E"], 9), ())
    )


def same_orbit(a: dict, b: dict) -> bool:
    """The same energy (1e-10), period (1e-7 relative) and ``tr M`` (1e-5 relative, at
    least absolute): one orbit up to the symmetries (a member and a census orbit, or two
    symmetric images).

    >>> same_orbit({"E": 5.0, "period": 6.0, "trace": 2.0},
    ...            {"E": 5.0, "period": 6.0 + 1e-9, "trace": 2.0})
    True
    """
    return (
        near(a["E"], b["E"], 1e-10)
        and near(a["period"], b["period"], 1e-7)
        and near(a["trace"], b["trace"], 1e-5)
    )


def _at_energies(fam: dict) -> dict:
    """The family's members by energy (rounded to 1e-9; cached in the record)."""
    idx = fam.get("_by_E")
    if idx is None:
        idx = {}
        for m in [fam["seed"], *fam["special"], *fam["path"]]:
            idx.setdefault(round(m["E"], 9), []).append(m)
        fam["_by_E"] = idx
    return idx


def _interp(pts: list[dict], i: int, E: float, key: str) -> float:
    """``key`` at ``E`` by the parabola through path members ``i-1, i, i+1`` (or ``i, i+1``
    as a line where ``E`` is not monotone across them: beside a fold)."""
    tri = pts[max(0, i - 1) : i + 2]
    Es = [m["E"] for m in tri]
    if len(tri) == 3 and (Es[0] - Es[1]) * (Es[1] - Es[2]) > 0:
        out = 0.0
        for j, m in enumerate(tri):
            w = 1.0
            for k, e in enumerate(Es):
                if k != j:
                    w *= (E - e) / (Es[j] - e)
            out += w * m[key]
        return out
    a, b = pts[i], pts[i + 1]
    t = (E - a["E"]) / (b["E"] - a["E"]) if b["E"] != a["E"] else 0.0
    return a[key] + t * (b[key] - a[key])


def _segments(fam: dict) -> tuple[np.ndarray, np.ndarray]:
    """The energy span ``(min, max)`` of each step of the family's path, as arrays
    (cached in the record with the path's length: a search over thousands of steps for
    each of thousands of orbits)."""
    seg = fam.get("_seg")
    if seg is None or seg[2] != len(fam["path"]):
        Es = np.array([m["E"] for m in fam["path"]], dtype=float)
        seg = (np.minimum(Es[:-1], Es[1:]), np.maximum(Es[:-1], Es[1:]), len(Es))
        fam["_seg"] = seg
    return seg[0], seg[1]


def on_family(fam: dict, orb: dict, rel_T: float = 2e-6, tol_tr: float = 2e-3) -> bool:
    """Whether the orbit lies on the family's path: between two members that bracket its
    energy, the period interpolated (a parabola in ``E``) agrees to ``rel_T`` and ``tr M`` to
    ``tol_tr`` (absolute, times ``max(1, |tr M|)``). With path steps of ~0.01 in ``E`` the
    interpolation error is ~1e-7 in ``T``; a daughter next to its parent (``|E - E_b| =
    dE``) differs by ~``dE`` in ``T`` and by ~``3 dE |d tr M / dE|`` in ``tr M``."""
    pts = fam["path"]
    E = orb["E"]
    lo, hi = _segments(fam)
    for i in np.flatnonzero((lo <= E) & (E <= hi)).tolist():
        T = _interp(pts, i, E, "period")
        tr = _interp(pts, i, E, "trace")
        if near(T, orb["period"], rel_T) and abs(tr - orb["trace"]) <= tol_tr * max(
            1.0, abs(tr)
        ):
            return True
    return False


def _probes(f: dict, samples: int) -> list[dict]:
    """The seed and ``samples`` members spread along the path (not its two ends: the
    first member past ``T_max`` or the window, which another path need not reach)."""
    pts = f["path"][1:-1]
    n = len(pts)
    idx = sorted({round(k * (n - 1) / max(1, samples - 1)) for k in range(samples)})
    return [f["seed"], *(pts[k] for k in idx)] if n else [f["seed"]]


def seed_index(f: dict) -> int | None:
    """The index of the seed of the followed family ``f`` in its path (the member with
    the seed's ``E`` and ``u``), or ``None``."""
    seed = (f["seed"]["E"], f["seed"]["u"])
    return next((i for i, m in enumerate(f["path"]) if (m["E"], m["u"]) == seed), None)


def _trim(f: dict, a: int, b: int, ends: list[dict]) -> dict:
    """The path of ``f`` cut to its members ``a .. b`` (inclusive), its special points
    there re-indexed (a marginal stretch's ``index_end`` too), with ``ends``."""
    special = [
        dict(p, index=p["index"] - a)
        | ({"index_end": p["index_end"] - a} if "index_end" in p else {})
        for p in f["special"]
        if a <= p["index"] and p.get("index_end", p["index"]) <= b
    ]
    return {"path": f["path"][a : b + 1], "special": special, "ends": ends}


def cut_at_critical(f: dict, ratio: float = 10.0) -> dict:
    """The follow ``f`` (a ``follow`` task's result) cut where its path crosses a
    critical energy (4 or 4.5, the saddles' levels) with a jump of the start state:
    a step whose ``state0`` moves (max norm) by more than ``ratio`` times the median of
    the ten steps beside it, and by more than 1e-3.

    At a critical energy the start sets change their shape (an arc of a mirror line
    splits or joins; the circle at D1 appears), so that the shooting unknown ``u``, which
    the engine continues smoothly, can name another orbit on the other side: the
    breather LD's path at ``T <= 16`` went on across ``E = 4`` with ``T`` smooth but its
    start jumping from ``(1.54, 4.62)`` to ``(2.36, 7.07)`` and ``tr M`` from 53,908 to
    9.04. The part of the path that holds the seed is kept; the end at the cut gets the
    stop ``'critical'`` with the jump in its reason; special points beyond it go.
    Returns ``f`` itself when nothing is cut.

    >>> path = [{"E": 3.9 + k / 100, "u": k / 100, "period": 6.0, "trace": 1.0,
    ...          "x0": [k / 1000 + (k > 10), 0.0, 0.0, 0.0]} for k in range(21)]
    >>> f = {"path": path, "seed": path[15], "special": [],
    ...      "ends": [{"side": "backward", "stop": "period", "reason": ""},
    ...               {"side": "forward", "stop": "period", "reason": ""}]}
    >>> g = cut_at_critical(f)
    >>> len(g["path"]), round(g["path"][0]["E"], 2), g["ends"][0]["stop"]
    (10, 4.01, 'critical')
    """
    path, s = f["path"], seed_index(f)
    if len(path) < 3 or s is None:
        return f
    E = np.array([m["E"] for m in path])
    dx = np.abs(np.diff(np.array([m["x0"] for m in path]), axis=0)).max(axis=1)
    cuts = {}
    for i, d in enumerate(dx):
        c = [
            c
            for c in (SEPARATRIX_ENERGY, BREATHER_SEPARATRIX_ENERGY)
            if (E[i] - c) * (E[i + 1] - c) <= 0
        ]
        beside = np.r_[dx[max(0, i - 5) : i], dx[i + 1 : i + 6]]
        if c and d > max(
            1e-3, ratio * float(np.median(beside)) if len(beside) else 0.0
        ):
            cuts[i] = (
                f"the start state jumps by {d:.3g} between the members at E = "
                f"{E[i]:.10g} and {E[i + 1]:.10g}, across the critical energy {c[0]:g}, "
                "where the start set changes: the path is cut there"
            )
    a = max((i + 1 for i in cuts if i < s), default=0)
    b = min((i for i in cuts if i >= s), default=len(path) - 1)
    if (a, b) == (0, len(path) - 1):
        return f
    ends = [dict(e) for e in f["ends"]]
    for side, i in ((0, a - 1), (1, b)):
        if i in cuts:
            ends[side] = {
                "side": ends[side]["side"],
                "stop": "critical",
                "reason": cuts[i],
            }
    return {**f, **_trim(f, a, b, ends)}


#: ``(rel_T, rel_tr)`` of :func:`cut_untrusted`: a float64 member that differs from its
#: 30-digit re-solve by more than ``rel_T`` in the period (relative) or ``rel_tr``
#: ``max(1, |tr M|)`` plus :data:`~rotorlib.beyond.catalogue_tasks.TRACE_TOL_SQ`
#: ``tr M^2`` (the float64 floor of a very unstable orbit's ``tr M``, as a match allows
#: it) in ``tr M`` is not the family's member. Loose: the float64 path's own accuracy,
#: which is finer (``interpolation.path_accuracy`` of each record), is measured and
#: recorded, not enforced here.
TRUST = (1e-6, 1e-2)


def cut_at_reversal(f: dict) -> dict:
    """The follow ``f`` cut where its path turns back in ``E`` with no located fold (each
    fold explains one turn, the nearest within two members): the stretch around the
    seed between such turns is kept, and
    an end there gets the stop ``'reversal'`` with the energy in its reason (and
    ``zigzag``: the build continues the family past it in ``u``, the ``beyond`` task of
    :mod:`rotorlib.beyond.catalogue_tasks`). Returns ``f`` itself when nothing is cut.

    Why: beside a fold of a very unstable family the engine's steps can zigzag (measured
    at ``T <= 16``: a family with ``|tr M| ~ 1e3`` visited E = 4.6785, 4.6766, 4.6763,
    4.6783, 4.6786, 4.6771 in that order, so that one piece of its path held members of
    both branches and the interpolant of one branch was off by 3e-3); a turn at a
    pitchfork the engine passed onto another branch looks the same.

    >>> path = [{"E": E, "u": k} for k, E in enumerate([1.0, 1.1, 1.2, 1.15, 1.3, 1.4])]
    >>> ends = [{}, {"side": "forward"}]
    >>> f = {"path": path, "seed": path[0], "special": [], "ends": ends}
    >>> g = cut_at_reversal(f)
    >>> [m["E"] for m in g["path"]], g["ends"][1]["stop"]
    ([1.0, 1.1, 1.2], 'reversal')
    """
    path, s = f["path"], seed_index(f)
    if len(path) < 3 or s is None:
        return f
    E = np.array([m["E"] for m in path])
    d = np.sign(np.diff(E))
    rev = [i for i in range(1, len(d)) if d[i] * d[i - 1] < 0]
    # each located fold explains one turn: the nearest, within two members
    explained = {
        min(rev, key=lambda i: abs(i - p["index"]))
        for p in f["special"]
        if p["kind"] == "fold" and rev and min(abs(i - p["index"]) for i in rev) <= 2
    }
    turns = [i for i in rev if i not in explained]
    a = max((i for i in turns if i < s), default=0)
    b = min((i for i in turns if i >= s), default=len(path) - 1)
    if (a, b) == (0, len(path) - 1):
        return f
    # a zigzag that starts within four members past a fold: cut at the fold
    fa = max((j for j in explained if a < j < s and j - a <= 4), default=None)
    fb = min((j for j in explained if s <= j < b and b - j <= 4), default=None)
    ends = [dict(e) for e in f["ends"]]
    for side, i, j in ((0, a, fa), (1, b, fb)):
        if i not in turns:
            continue
        side_name = ends[side].get("side", ("backward", "forward")[side])
        if j is None:
            ends[side] = {
                "side": side_name,
                "zigzag": True,
                "stop": "reversal",
                "reason": f"reversal: the path turns back in E at E = {E[i]:.10g} "
                "with no fold located there (the engine's steps zigzag): cut there",
            }
        else:
            ends[side] = {
                "side": side_name,
                "zigzag": True,
                "stop": "fold",
                "reason": f"fold at E = {E[j]:.10g}, past which the engine's steps "
                f"zigzag (the path turns back again at E = {E[i]:.10g}): cut at the fold",
            }
    a, b = fa if fa is not None else a, fb if fb is not None else b
    return {**f, **_trim(f, a, b, ends)}


def _disagreement(m: dict) -> str | None:
    """How a stored member's float64 values disagree with its 30-digit re-solve
    (``m['polish']``) beyond :data:`TRUST`, or ``None``. A fold is not tested (at fixed
    ``E`` its root in ``u`` is double: the re-solve is ill-conditioned), nor a re-solve
    that did not converge (listed among the failures)."""
    p = m.get("polish", {})
    if m["kind"] == "fold":
        return None
    if "failed" in p:
        return p["failed"] if "another orbit" in p["failed"] else None
    T, tr = float(p["period_str"]), float(p["trace_str"])
    rel_T, rel_tr = TRUST
    if (
        abs(T - m["period"]) <= rel_T * T
        and abs(tr - m["trace"]) <= rel_tr * max(1.0, abs(tr)) + TRACE_TOL_SQ * tr * tr
    ):
        return None
    return (
        f"its float64 member at E = {m['E']:.10g} has T = {m['period']:.12g}, "
        f"tr M = {m['trace']:.6g}; its 30-digit re-solve T = {T:.12g}, tr M = {tr:.6g}"
    )


def cut_untrusted(f: dict) -> bool:
    """Cut the path of the followed family ``f``, whose stored members carry their
    30-digit re-solves (``polish``), to the stretch around the seed where every stored
    member agrees with its re-solve to :data:`TRUST` (the period to 1e-6, ``tr M`` to
    1e-2 ``max(1, |tr M|)`` plus 1e-12 ``tr M^2``). The
    path then ends at the last agreeing stored member on each side; the end there gets
    the stop ``'untrusted'`` with the disagreement in its reason, and special points
    beyond it go. Returns whether it cut (the stored members must then be chosen again).

    Why: the float64 continuation loses the family close to a separatrix. Measured on
    the ``T <= 16`` record of ``IS^r_4``: at ``E - 4 = 1.7e-5`` its float64 ``tr M`` is
    2 % off, at ``E - 4 = 8e-7`` it is -3.46 against the re-solve's -6.22, and below
    ``2.4e-7`` the path's ``tr M`` jumps between -2,281 and 5,547 from member to
    member while the re-solves give 1.69. Nothing is cut when the seed itself disagrees.
    """
    path, s = f["path"], seed_index(f)
    if s is None:
        return False
    why = {m["index"]: w for m in f["stored"] if (w := _disagreement(m))}
    ok = sorted({m["index"] for m in f["stored"]} - set(why))
    if not why or s in why:
        return False
    below, above = [i for i in why if i < s], [i for i in why if i > s]
    a = min(i for i in ok if i > max(below)) if below else 0
    b = max(i for i in ok if i < min(above)) if above else len(path) - 1
    ends = [dict(e) for e in f["ends"]]
    for side, bad, keep in (
        (0, max(below, default=None), a),
        (1, min(above, default=None), b),
    ):
        if bad is not None:
            ends[side] = {
                "side": ends[side]["side"],
                "stop": "untrusted",
                "reason": f"untrusted: the float64 continuation is not trusted past "
                f"E = {path[keep]['E']:.10g}: {why[bad]}",
            }
    f.update(_trim(f, a, b, ends))
    f.pop("_by_E", None)
    f.pop("_seg", None)
    return True


def cut_at_switch(
    fams: Sequence[dict], samples: int = 24, share: float = 0.75
) -> list[tuple[Any, Any, float]]:
    """Cut each family whose path turns at a fold onto another family's branch: the
    side of the fold (not the seed's) whose members lie (``share`` of ``samples``
    probes, :data:`PATH_TOL`) on another record goes. Returns ``(task cut, task of the
    other, E of the fold)`` for each cut.

    At a pitchfork the parent's branch and the daughter's meet with ``tr M = 4``; the
    engine, coming down the parent, may go on up the daughter, and the path then shows
    a fold there (measured at ``T <= 16``: the pendulum's record turned at
    ``E = 4 + 1.7e-7`` onto ``IS^r_3``, whose census orbits made the record a family of
    its own, carrying the pendulum's stretch and special points a second time). The
    other record must have no fold of its own there (two halves of a saddle-node turn at
    the same fold: neither is the other's parent). The
    kept side ends at the fold with the stop ``'switch'``; the record gets
    ``switch_parent`` ``{task, E, period}`` (linked as a parent's ``IS`` point by
    :mod:`rotorlib.beyond.catalogue_files`). Special points on the cut side go."""
    out = []
    for f in fams:
        s = seed_index(f)
        for p in [p for p in f["special"] if p["kind"] == "fold"]:
            k, path = p["index"], f["path"]
            if s is None or not 2 < k < len(path) - 3:
                continue
            for side, part in ((0, path[: k - 2]), (1, path[k + 3 :])):
                if (s < k) == (side == 0) or len(part) < 4:
                    continue  # the seed's side is kept
                pr = part[:: max(1, len(part) // samples)]
                host = next(
                    (
                        g
                        for g in fams
                        if g is not f
                        # a parent goes on through its branch point: no fold there
                        and not any(
                            q["kind"] == "fold" and abs(q["E"] - p["E"]) < 1e-6
                            for q in g["special"]
                        )
                        and sum(on_family(g, m, *PATH_TOL) for m in pr)
                        >= share * len(pr)
                    ),
                    None,
                )
                if host is None:
                    continue
                a, b = (k, len(path) - 1) if side == 0 else (0, k)
                ends = [dict(e) for e in f["ends"]]
                ends[side] = {
                    "side": ends[side]["side"],
                    "stop": "switch",
                    "reason": f"switch: the path turned at E = {p['E']:.10g} (a fold "
                    "with tr M = 4) onto the branch of another record, which carries "
                    "the rest: a pitchfork, where this family is born",
                }
                f["switch_parent"] = {
                    "task": host.get("task"),
                    "E": p["E"],
                    "period": p["period"],
                }
                others = [q for q in f["special"] if q is not p]  # the fold: the end
                f.update(_trim({**f, "special": others}, a, b, ends))
                f.pop("_by_E", None)
                f.pop("_seg", None)
                out.append((f.get("task"), host.get("task"), p["E"]))
                break
            if "switch_parent" in f:
                break
    return out


def holds(fam: dict, orb: dict) -> bool:
    """Whether a census orbit can be assigned to the family: it :func:`covers` it, or
    the orbit lies on its path (:func:`on_family`, default tolerances)."""
    return covers(fam, orb) or on_family(fam, orb)


def drop_contained(
    fams: list[dict],
    samples: int = 24,
    rel_T: float = PATH_TOL[0],
    tol_tr: float = PATH_TOL[1],
    share: float = 0.75,
    orbits: Sequence[dict] = (),
) -> tuple[list[dict], list]:
    """The families with those removed whose path lies on the paths of the others: one
    family met from two seeds, one record carried only part of the way (the engine
    stopped early), or a record that bridges two others (the engine carried it across
    an energy where it stopped the other two).

    A family's probes are its seed and ``samples`` members spread along its path (not
    its two ends: the first member past ``T_max`` or the window, which the other path
    need not reach). A probe lies on a family when :func:`on_family` says so with the
    period to ``rel_T`` and ``tr M`` to ``tol_tr`` relative: looser than for a census
    orbit, because both paths are interpolated between steps of ~0.01 in ``E``, ~1e-6 in
    ``T`` where ``T(E)`` is steep, and more near a separatrix, where ``T`` diverges, and
    beside a fold, where ``E`` is not a parameter of the path (a quarter of the probes of
    the CG record that crosses its fold at E = 5.3153 fail there): hence ``share``, the
    fraction of probes that must lie on the others. Two different
    families agree that closely only at a point or along a short stretch (a bifurcation,
    a crossing), and such a family is kept.

    A record is held only by records followed to the same ``T_max`` or a larger one, or
    to one that its periods do not pass (a record followed to ``T <= 16`` may hold
    members that one followed to ``T <= 8`` lacks).
    A record is never dropped while one of ``orbits`` (the census orbits) that it
    :func:`holds` lies on none of the remaining others: the probes sample a path, and a
    stretch of it that no other record carries (a quarter of the probes may lie off the
    others) can hold census orbits.
    Repeatedly, of the families whose probes lie (``share`` of them) on the remaining
    others, the one that needs the most others to hold them (a bridge before a part),
    then the one with the shortest path, is dropped. Returns ``(kept, dropped)``,
    ``dropped`` as ``(task of the dropped, [tasks of the families that hold it])``.

    >>> a = {"task": "a", "seed": {"E": 1.5, "period": 3.0, "trace": 1.0},
    ...      "path": [{"E": 1 + k / 10, "period": 2 + k / 5, "trace": 1.0}
    ...               for k in range(11)]}
    >>> b = {"task": "b", "seed": {"E": 1.25, "period": 2.5, "trace": 1.0},
    ...      "path": [{"E": 1.2 + k / 20, "period": 2.4 + k / 10, "trace": 1.0}
    ...               for k in range(5)]}
    >>> kept, dropped = drop_contained([b, a])
    >>> [f["task"] for f in kept], dropped
    (['a'], [('b', ['a'])])
    """
    probes = [_probes(f, samples) for f in fams]
    top = [max((m["period"] for m in f["path"]), default=0.0) for f in fams]
    span = [
        (min(m["E"] for m in f["path"]), max(m["E"] for m in f["path"]))
        if f["path"]
        else (math.inf, -math.inf)
        for f in fams
    ]
    # on[i][j]: the probes of family i that lie on family j
    on: list[dict[int, frozenset[int]]] = []
    for i, pr in enumerate(probes):
        row = {}
        for j, g in enumerate(fams):
            if j == i or not g["path"]:
                continue
            if g.get("t_max", math.inf) < min(fams[i].get("t_max", math.inf), top[i]):
                continue  # a record followed to a lower T_max holds none that passes it
            lo, hi = span[j]
            hit = frozenset(
                k
                for k, m in enumerate(pr)
                if lo <= m["E"] <= hi and on_family(g, m, rel_T, tol_tr)
            )
            if hit:
                row[j] = hit
        on.append(row)
    # holders[k]: the families that hold census orbit k (tested once)
    holders = [{j for j, f in enumerate(fams) if holds(f, o)} for o in orbits]
    alive = set(range(len(fams)))
    dropped: list[tuple[Any, list]] = []
    while True:
        best = None
        for i in sorted(alive):
            hosts = {j: h for j, h in on[i].items() if j in alive}
            held = frozenset().union(*hosts.values()) if hosts else frozenset()
            if len(held) < share * len(probes[i]):
                continue
            if any(h & alive == {i} for h in holders):
                continue  # a census orbit only it holds
            cover, left = [], set(held)  # greedy: the others that hold its probes
            while left:
                j = max(hosts, key=lambda j: (len(hosts[j] & left), -j))
                cover.append(j)
                left -= hosts[j]
            key = (len(cover), -len(fams[i]["path"]), -i)
            if best is None or key > best[0]:
                best = (key, i, cover)
        if best is None:
            break
        _, i, cover = best
        alive.discard(i)
        dropped.append((fams[i].get("task"), [fams[j].get("task") for j in cover]))
    return [f for i, f in enumerate(fams) if i in alive], dropped


def beyond_jobs(
    fams: Sequence[dict], lo: float, hi: float
) -> tuple[list[dict], list[tuple[list, float]]]:
    """The ``beyond`` tasks of the ends of ``fams`` where the path was cut at a zigzag of
    the engine's steps (``zigzag``: :func:`cut_at_reversal`) and their owners
    ``([family task, 'beyond', E_end], T_max)``: the family walked on in its shooting
    unknown ``u`` from its end member, in steps of ``2e-5 max(1, |u|)`` the way its
    path went there."""
    jobs, owners = [], []
    for f in fams:
        path = f["path"]
        for side, end in enumerate(f["ends"]):
            if not end.get("zigzag") or len(path) < 2:
                continue
            m, prev = (path[-1], path[-2]) if side else (path[0], path[1])
            du = 2e-5 * max(1.0, abs(m["u"])) * (1 if m["u"] >= prev["u"] else -1)
            jobs.append(
                {
                    "problem": f["problem"],
                    "factor": f["factor"],
                    "u": m["u"],
                    "E": m["E"],
                    "du": du,
                    "t_max": f["t_max"],
                    "E_range": [lo, hi],
                }
            )
            owners.append(([f.get("task"), "beyond", m["E"]], f["t_max"]))
    return jobs, owners


def cut_beyond(f: dict, E: float) -> dict:
    """A record followed from a seed found past a zigzag end at ``E``
    (:func:`beyond_jobs`) cut at its turn in ``E`` nearest ``E`` (within 1e-3): the
    fold it crossed back onto the branch of the record it was found beyond, which that
    record carries. The seed's side is kept; its end there is a ``fold``. Returns ``f``
    itself when no such turn exists.

    Measured at ``T <= 16``: the record followed from past the zigzag of a family with
    ``|tr M| ~ 1e3`` at E = 4.6785 went up its own branch to the fold at E = 4.6786 and
    down the other record's branch to ``T = 16``, carrying that branch a second time.

    >>> path = [{"E": E, "u": k} for k, E in enumerate([1.0, 1.1, 1.2, 1.15, 1.1])]
    >>> f = {"path": path, "seed": path[0], "special": [], "ends": [{"side": "backward"},
    ...      {"side": "forward", "stop": "period"}]}
    >>> g = cut_beyond(f, 1.2005)
    >>> [m["E"] for m in g["path"]], g["ends"][1]["stop"]
    ([1.0, 1.1, 1.2], 'fold')
    """
    path, s = f["path"], seed_index(f)
    Es = np.array([m["E"] for m in path])
    d = np.sign(np.diff(Es))
    turns = [i for i in range(1, len(d)) if d[i] * d[i - 1] < 0 and i != s]
    turns = [i for i in turns if abs(Es[i] - E) < 1e-3]
    if s is None or not turns:
        return f
    k = min(turns, key=lambda i: abs(Es[i] - E))
    side = 1 if k > s else 0
    ends = [dict(e) for e in f["ends"]]
    ends[side] = {
        "side": ends[side].get("side", ("backward", "forward")[side]),
        "stop": "fold",
        "reason": f"fold at E = {Es[k]:.10g}, past which the path runs back along the "
        "branch of the record it was found beyond: cut at the fold",
    }
    a, b = (0, k) if side else (k, len(path) - 1)
    return {**f, **_trim(f, a, b, ends)}
