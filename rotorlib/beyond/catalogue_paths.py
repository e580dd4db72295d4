"""Which family holds an orbit, for the catalogue build (:mod:`rotorlib.beyond.catalogue_build`).

* :func:`covers`: a census orbit is a member of a followed family at its energy;
* :func:`on_family`: an orbit lies on a family's path between two members (the period
  and ``tr M`` interpolated);
* :func:`drop_contained`: the records whose paths lie on the others' (one family met
  from two seeds, a record stopped early, a bridge between two others);
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

from .catalogue_tasks import near

__all__ = [
    "PATH_TOL",
    "bands_of",
    "period_bound",
    "covers",
    "same_orbit",
    "on_family",
    "drop_contained",
    "holds",
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
