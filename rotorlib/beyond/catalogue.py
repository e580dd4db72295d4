"""The catalogue of symmetric periodic-orbit families: load, filter, re-solve, verify.

The files (built by ``scripts/build_catalogue.py`` with :mod:`rotorlib.beyond.catalogue_build`,
stored in ``rotorlib/data/catalogue/``): ``index.json`` (the build's scope: the energy
window, ``T_max``, ``bands`` ``[[E_hi, T_max], ...]``: the census's bound up to ``E_hi``,
the census energies and counts; one summary per family), ``F<nnn>.json`` per family,
``members.csv`` (every stored member, the decimal strings to 30 digits) and
``schema.json`` (:data:`SCHEMA`, the JSON Schema of a family file). Read them without rotorlib; in Python :func:`catalogue` returns
:class:`Family` objects, each with its :class:`~rotorlib.orbits.family.Branch`
(:meth:`Family.branch`) and its member at any energy of its range solved to any
``digits`` (:meth:`Family.at`); :func:`verify` re-solves the stored members.

A family record: ``id``, ``name`` (the atlas's name of its census orbits, e.g.
``pendulum``, ``breather R``, ``PD^b``, ``CG``; ``null`` for a family the book does not
name), ``symmetry`` (the pairs of fixed sets its census orbits meet half a period apart,
``choreography``, ``rotating`` with the net ``winding`` of the two angles over a period,
in turns), ``E_range`` (its path's energies and its located folds), ``ends`` (each
end's energy, period and why the record stops
there), ``special_points`` (``fold``, ``IS``: tr M = 4, ``PD``: tr M = 0, with their
``E_str`` to 30 digits and ``E_error``; ``touch``; ``marginal``), ``stable_windows``, ``parents`` / ``daughters``,
``fold_twins`` (the records holding the same family's other branch across a fold they
share, ``{id, E}``: a saddle-node family found from two census orbits is held as two
records),
``census_orbits`` (the census orbits it contains), ``members`` (the stored members:
``E_str``, ``period_str``, ``state0_str`` to 30 digits, ``trace_str`` to 25, the
multipliers, the action ``S = oint p.dq``, the Maslov index ``maslov``, ``null`` with
``maslov_reason`` at a marginal member, and ``pieces``, the interpolation pieces it is
a node of), ``interpolation`` (the pieces of the path, each with its parameter ``E`` or
``u`` and its nodes; ``degree``; ``max_error``: the interpolant's largest error over the
path members, ``<= tolerance = 1e-8``; ``path_accuracy``: the float64 path against the
30-digit members; ``left_out_error`` and ``densified``: the path made dense enough for
the interpolant to hold between its members) and ``branch`` (the float64 path ``[E, u,
t1, tr M, a1, a2, p1, p2]``, problem, factor). The stored members are chosen by need
(:mod:`rotorlib.beyond.catalogue_members`): the fewest path members from which the
period and ``tr M`` of every path member are interpolated to 1e-8, plus the special
points and the seed. :meth:`Family.members_at` solves every member from the interpolant.

Precision: stored members to 30 digits (real128, closure < 1e-28); path members float64
(residual < 1e-8; measured against the 30-digit members: ``path_accuracy``); the action
to ~1e-13 relative (:func:`rotorlib.beyond.quantum_trace.orbit_action`); the Maslov index
exact (an integer) away from marginal orbits.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from ..core.energy import as_float
from .catalogue_schema import SCHEMA

__all__ = [
    "DATA",
    "SCHEMA",
    "Family",
    "Catalogue",
    "catalogue",
    "load",
    "verify",
    "stable_fraction",
]

#: The stored catalogue (package data).
DATA = Path(__file__).resolve().parent.parent / "data" / "catalogue"


@dataclass(frozen=True)
class Family:
    """One catalogued family: its record (the family file's JSON) and accessors.

    Examples
    --------
    >>> from rotorlib.beyond.catalogue import catalogue
    >>> f = catalogue(name="pendulum")[0]
    >>> f.id, f.name, f.symmetry["rotating"]
    ('F001', 'pendulum', True)
    >>> b = f.branch()
    >>> b.label, len(b.members) == len(f.record["branch"]["path"])
    ('pendulum', True)
    """

    record: dict

    @property
    def id(self) -> str:
        return self.record["id"]

    @property
    def name(self) -> str | None:
        return self.record["name"]

    @property
    def symmetry(self) -> dict:
        return self.record["symmetry"]

    @property
    def E_range(self) -> tuple[float, float]:
        lo, hi = self.record["E_range"]
        return float(lo), float(hi)

    @property
    def stable_windows(self) -> list[tuple[float, float]]:
        return [(float(a), float(b)) for a, b in self.record["stable_windows"]]

    def exists_at(self, E: float) -> bool:
        """Whether the family has a member at ``E`` (within ``E_range``: its path's
        energies and its located folds)."""
        return self.E_range[0] <= E <= self.E_range[1]

    def may_reach(self, t_max: float) -> bool:
        """Whether a member may have ``T <= t_max`` (path minimum, 1e-6 relative)."""
        return self.record["period_range"][0] <= t_max * (1 + 1e-6)

    def stable_at(self, E: float) -> bool:
        return any(a <= E <= b for a, b in self.stable_windows)

    @cached_property
    def problem(self):
        from .catalogue_members import problem_of

        br = self.record["branch"]
        lab = self.name or self.id
        return problem_of({**br["problem"], "label": lab, "factor": br["factor"]})

    def branch(self):
        """The family as a :class:`~rotorlib.orbits.family.Branch` (float64 path
        members; special points as :class:`~rotorlib.orbits.family.SpecialPoint`)."""
        from ..core.precision import tier
        from ..orbits.family import Branch, Member, SpecialPoint

        prob = self.problem

        def mem(E, u, t1, tr, x0):
            return Member(u, E, E, t1, 0.0, tr, (), prob.label, prob.factor, tuple(x0))

        ms = tuple(mem(*row[:4], row[4:8]) for row in self.record["branch"]["path"])
        pts = []
        for p in self.record["special_points"]:
            x = (p["E"], 0.0, p["period"] / prob.factor, p["trace"], [math.nan] * 4)
            pts.append(SpecialPoint(p["kind"], mem(*x[:4], x[4]), int(p["index"])))
        ends = self.record["ends"]
        return Branch(
            prob,
            tier(None),
            ms,
            tuple(pts),
            " / ".join(e["stop"] for e in ends),
            "; ".join(f"{e['side']}: {e['kind']}" for e in ends),
            tuple(self.record["window"]),
        )

    def interpolate(self, E: Any) -> list[dict]:
        """The family's members at ``E`` read from the interpolant of its stored members
        (:func:`rotorlib.beyond.catalogue_members.local_interpolant`, piece by piece):
        ``[{'E', 'period', 'trace', 'u', 'piece'}]``, one per branch through ``E`` (two
        or more beside a fold), by period; ``[]`` outside the family's range.

        Precision: the interpolant runs through the stored members' 30-digit period and
        ``tr M``. On a piece parametrised by ``E``: 1e-8 (``max_error``) at held-out path
        members; at the midpoints between stored members, measured against 30-digit
        re-solves, 1e-8 away from folds and separatrices, ~4e-8 in T and ~2e-6 in tr M
        beside them. On a piece parametrised by ``u`` (through a fold, or a family
        whose ``u`` moves faster than ``E``) ``E(u) = E`` is solved on the interpolant;
        such pieces are densified in ``u`` as the others are in ``E``: measured at the
        midpoints in ``u`` of every fourth pair of stored members against float64
        shots, 2 of 1,409 above 1e-8 in T, the worst 8.5e-7 (F039 at E = 3.9996). Two
        branches closer to a fold than ~1/16 of a node interval in ``u`` are not
        resolved.

        Examples
        --------
        >>> from rotorlib.beyond.catalogue import catalogue
        >>> f = catalogue(name="pendulum")[0]
        >>> [m["piece"] for m in f.interpolate(5.6)], f.interpolate(9.0)
        ([0], [])
        """
        from scipy.optimize import brentq

        from .catalogue_members import local_interpolant

        Ef = as_float(E, "E")
        deg = int(self.record["interpolation"]["degree"])
        out: list[dict] = []
        for k, pc in enumerate(self.record["interpolation"]["pieces"]):
            key, xs, Y = self._piece(k)
            if key == "E":
                roots = [Ef] if xs[0] <= Ef <= xs[-1] else []
            else:
                g = np.concatenate(
                    [np.linspace(a, b, 17)[:-1] for a, b in zip(xs, xs[1:])] + [xs[-1:]]
                )
                val = local_interpolant(xs, Y[:, 2:], g, deg)[:, 0] - Ef

                def h(v):
                    return float(local_interpolant(xs, Y[:, 2:], [v], deg)[0, 0] - Ef)

                roots = [float(g[i]) for i in np.flatnonzero(val == 0)]
                roots += [
                    brentq(h, g[i], g[i + 1], xtol=1e-15, rtol=1e-15)
                    for i in np.flatnonzero(val[:-1] * val[1:] < 0)
                ]
            for x in roots:
                rec = dict(self.interpolate_piece(k, x), E=Ef)
                if not any(  # a member at a piece boundary is found twice
                    abs(r["period"] - rec["period"]) < 1e-9
                    and abs(r["u"] - rec["u"]) < 1e-7 * max(1.0, abs(rec["u"]))
                    for r in out
                ):
                    out.append(rec)
        return sorted(out, key=lambda r: r["period"])

    def _piece(self, k: int) -> tuple[str, np.ndarray, np.ndarray]:
        """Piece ``k``'s parameter (``'E'`` or ``'u'``), its nodes' values of it, and
        their rows ``[period, tr M, the other one]`` (the 30-digit values, rounded)."""
        pc = self.record["interpolation"]["pieces"][k]
        nodes = [self.record["members"][i] for i in pc["members"]]
        key, other = ("E", "u") if pc["param"] == "E" else ("u", "E")
        xs = np.array([m[key] for m in nodes], dtype=float)
        Y = np.array(
            [[float(m["period_str"]), float(m["trace_str"]), m[other]] for m in nodes]
        )
        return key, xs, Y

    def interpolate_piece(self, k: int, x: float) -> dict:
        """The member that piece ``k`` of the interpolant (:meth:`interpolate`) gives
        at the value ``x`` of its own parameter (``E`` or ``u``):
        ``{'E', 'period', 'trace', 'u', 'piece'}``. ValueError outside the piece.

        Examples
        --------
        >>> from rotorlib.beyond.catalogue import catalogue
        >>> f = catalogue(name="pendulum")[0]
        >>> r = f.interpolate_piece(0, 5.6)
        >>> r["period"] == f.interpolate(5.6)[0]["period"]
        True
        """
        from .catalogue_members import local_interpolant

        key, xs, Y = self._piece(k)
        if not xs[0] <= x <= xs[-1]:
            raise ValueError(
                f"{self.id}: {key} = {x!r} is outside piece {k} ({xs[0]}, {xs[-1]})"
            )
        deg = int(self.record["interpolation"]["degree"])
        y = local_interpolant(xs, Y, [x], deg)[0]
        E, u = (x, float(y[2])) if key == "E" else (float(y[2]), x)
        return {"E": E, "period": float(y[0]), "trace": float(y[1]), "u": u, "piece": k}

    def members_at(self, E: Any, digits: int | None = None) -> list:
        """Every member of the family at ``E`` (one per branch through ``E``:
        :meth:`interpolate`), each solved to ``digits`` from its interpolated ``u``
        (:class:`~rotorlib.orbits.family.Member`, ``tr M`` computed). A branch whose
        shot does not converge, or converges to a period more than 1e-4 (relative) from
        the interpolated one, is left out; so is a member with the period (1e-12) and
        ``tr M`` (1e-9) of one already found: one orbit met twice, by a path that passes
        an image of it again (as the census counts it: once). ValueError when none is
        left."""
        from ..orbits.shooting import NoConvergence
        from .catalogue_members import shoot_member

        found = self.interpolate(E)
        if not found:
            raise ValueError(
                f"{self.id} has no member at E = {E!r}: range {self.E_range}"
            )
        out: list[Any] = []
        errors: list[str] = []
        for r in found:
            try:
                m = shoot_member(self.problem, E, r["u"], r["period"], digits=digits)
            except (NoConvergence, ValueError) as exc:
                errors.append(str(exc))
                continue
            T, tr = float(m.period), float(m.trace)
            if any(  # one orbit met twice (its image: the path passes it again)
                abs(float(o.period) / T - 1) < 1e-12
                and abs(float(o.trace) - tr) < 1e-9 * max(1.0, abs(tr))
                for o in out
            ):
                continue
            out.append(m)
        if not out:
            raise ValueError(f"{self.id}: no member at E = {E!r} ({'; '.join(errors)})")
        return out

    def nearest(self, E: float) -> list:
        """The path member nearest in ``E`` (``[E, u, t1, tr M, a1, a2, p1, p2]``)."""
        path = self.record["branch"]["path"]
        return min(path, key=lambda r: abs(r[0] - E))

    def at(self, E: Any, digits: int | None = None):
        """The family's member at ``E`` solved from the nearest stored path member, to
        ``digits`` (a :class:`~rotorlib.orbits.family.Member`, ``tr M`` computed).

        Raises ValueError when ``E`` is outside the family's range or the shot does not
        converge to a member with the family's period (2e-3 relative)."""
        from ..core.energy import as_float
        from ..core.precision import tier
        from ..orbits.continuation import member
        from ..orbits.shooting import NoConvergence, solve

        Ef = as_float(E, "E")
        if not self.exists_at(Ef):
            raise ValueError(
                f"{self.id} has no member at E = {Ef!r}: range {self.E_range}"
            )
        # the path members on either side of E: the one with the nearest period
        path = self.record["branch"]["path"]
        i = int(np.argmin([abs(r[0] - Ef) for r in path]))
        row = path[i]
        t = tier(digits)
        with t.context():
            u0 = t.num(repr(row[1]))
            try:
                u = solve(self.problem, u0, u0 * (1 + t.num("1e-9")), E=E, digits=t).x
            except NoConvergence as exc:
                raise ValueError(
                    f"{self.id}: no member at E = {Ef!r} ({exc})"
                ) from None
            m = member(self.problem, u, str(E) if t.extended else Ef, t, traces=True)
        T0 = self.problem.factor * row[2]
        if abs(float(m.period) - T0) > 0.05 * T0:
            raise ValueError(f"{self.id}: the shot at E = {Ef!r} left the family")
        return m

    def to_dict(self) -> dict:
        return self.record


@dataclass(frozen=True)
class Catalogue:
    """The loaded catalogue: ``index`` (``index.json``) and ``families``."""

    index: dict
    families: tuple[Family, ...]

    def __iter__(self) -> Iterator[Family]:
        return iter(self.families)

    def __len__(self) -> int:
        return len(self.families)

    def period_bound(self, E: float) -> float:
        """The census's period bound at ``E`` (``index['bands']``): complete to it."""
        from .catalogue_paths import period_bound

        return float(period_bound(self.index["bands"], E))

    def check_scope(self, E: float, t_max: float | None = None) -> None:
        """``ValueError`` unless ``E`` is in the window, ``t_max`` in :meth:`period_bound`."""
        lo, hi = self.index["window"]
        if not lo <= as_float(E, "E") <= hi:
            raise ValueError(
                f"E = {E} lies outside the catalogue's built window {lo} <= E <= {hi}: "
                "it holds no family there (an empty list would say that none exists)"
            )
        if t_max is not None and as_float(t_max, "t_max") > (b := self.period_bound(E)):
            msg = f"at E = {E} the catalogue holds the families with T <= {b:g}"
            raise ValueError(f"{msg} (its census bound); t_max = {t_max} is beyond it")

    def family(self, fid: str) -> Family:
        for f in self.families:
            if f.id == fid:
                return f
        raise ValueError(
            f"no family {fid!r} in the catalogue (ids F001..F{len(self.families):03d})"
        )


def load(path: str | os.PathLike | None = None) -> Catalogue:
    """The catalogue stored in ``path`` (default :data:`DATA`)."""
    p = Path(path) if path is not None else DATA
    if not (p / "index.json").exists():
        raise ValueError(f"no catalogue in {p} (index.json missing)")
    index = json.loads((p / "index.json").read_text())
    fams = tuple(
        Family(json.loads((p / f"{r['id']}.json").read_text()))
        for r in index["families"]
    )
    return Catalogue(index, fams)


def catalogue(
    E: float | None = None,
    t_max: float | None = None,
    stable: bool | None = None,
    symmetry: str | None = None,
    name: str | None = None,
    path: str | os.PathLike | None = None,
) -> list[Family]:
    """The catalogued families, filtered.

    Parameters
    ----------
    E : float, optional
        Only families with a member at ``E``.
    t_max : float, optional
        Only families with a member of period ``<= t_max`` (at ``E`` if given, from
        the path members nearest it).
    stable : bool, optional
        Only families linearly stable (or unstable) at ``E`` (or somewhere, without ``E``).
    symmetry : str, optional
        ``choreography``, ``rotating``, ``librating`` or the name of a fixed set the
        family meets.
    name : str, optional
        The family's name (``pendulum``, ``breather R``, ...) or id (``F001``).
    path : path, optional
        Another catalogue directory.

    Raises
    ------
    ValueError
        ``E`` is not a number, or lies outside the built window (``index['window']``),
        or ``t_max`` exceeds the period bound of the census scope at ``E``
        (:meth:`Catalogue.period_bound`: beyond it the list would be incomplete).

    Examples
    --------
    >>> from rotorlib.beyond.catalogue import catalogue
    >>> fams = catalogue(E=5.45)
    >>> all(f.exists_at(5.45) for f in fams), len(fams) >= 5
    (True, True)
    >>> catalogue(E=9.0)
    Traceback (most recent call last):
    ...
    ValueError: E = 9.0 lies outside the catalogue's built window 0.1 <= E <= 8.0: ...
    """
    cat = load(path)
    if E is not None:
        cat.check_scope(E, t_max)
    out = []
    for f in cat:
        if E is not None and not f.exists_at(E):
            continue
        if t_max is not None:
            if E is None:
                T = f.record["period_range"][0]
            else:
                row = f.nearest(E)
                T = f.record["branch"]["factor"] * row[2]
            if T > t_max:
                continue
        if stable is not None:
            st = f.stable_at(E) if E is not None else bool(f.stable_windows)
            if st != stable:
                continue
        if symmetry is not None:
            sy = f.symmetry
            flags = {
                "choreography": sy["choreography"],
                "rotating": sy["rotating"],
                "librating": not sy["rotating"],
            }
            sets = {s for pair in sy["fixed_sets"] for s in pair}
            if not flags.get(symmetry, symmetry in sets):
                continue
        if name is not None and name not in (f.id, f.name, *f.record["names"]):
            continue
        out.append(f)
    return out


def verify(fid: str, path: str | os.PathLike | None = None, digits: int = 30) -> dict:
    """Re-solve every stored member of family ``fid`` at its ``E_str`` from its ``u``
    (:func:`rotorlib.beyond.catalogue_members.polish_task`) and compare: the largest
    relative difference of the period and of ``tr M``, the largest difference of
    ``state0``, the largest closure, the largest difference of the action (relative to
    max(1, |S|)) and the number of Maslov indices that differ; ``ok`` when they are
    below ``1e-20`` (period, state), ``1e-15 max(1, |tr M|)`` (trace), the closure
    below ``1e-20``, the action below ``1e-10`` and no index differs."""
    from mpmath import mp, mpf

    from .catalogue_members import polish_task

    f = load(path).family(fid)
    br = f.record["branch"]
    worst = {"period": 0.0, "state0": 0.0, "trace": 0.0, "closure": 0.0}
    worst |= {"action": 0.0, "maslov": 0}
    with mp.workdps(40):
        for m in f.record["members"]:
            r = polish_task(
                {
                    "problem": br["problem"],
                    "factor": br["factor"],
                    "u": m["u"],
                    "E_str": m["E_str"],
                    "digits": digits,
                }
            )
            dT = abs(mpf(r["period_str"]) / mpf(m["period_str"]) - 1)
            dx = max(
                abs(mpf(a) - mpf(b)) for a, b in zip(r["state0_str"], m["state0_str"])
            )
            dtr = abs(mpf(r["trace_str"]) - mpf(m["trace_str"])) / max(
                1, abs(mpf(m["trace_str"]))
            )
            worst["period"] = max(worst["period"], float(dT))
            worst["state0"] = max(worst["state0"], float(dx))
            worst["trace"] = max(worst["trace"], float(dtr))
            worst["closure"] = max(worst["closure"], r["closure"])
            dS = abs(r["action"] - m["action"]) / max(1.0, abs(m["action"]))
            worst["action"] = max(worst["action"], dS)
            worst["maslov"] += int(r["maslov"] != m["maslov"])
    ok = (
        worst["period"] < 1e-20
        and worst["state0"] < 1e-20
        and worst["trace"] < 1e-15
        and worst["closure"] < 1e-20
        and worst["action"] < 1e-10
        and worst["maslov"] == 0
    )
    return {"id": fid, "members": len(f.record["members"]), **worst, "ok": ok}


def stable_fraction(
    energies, path: str | os.PathLike | None = None, t_max: float | None = None
) -> list[dict]:
    """On a grid of energies: the number of catalogued families with a member there
    (``families``: ``E`` inside its ``E_range``), how many have a stable member there
    (``stable``: ``E`` inside one of its located ``stable_windows``) and their ratio
    (``fraction``; ``None`` where no family exists). Counts over the whole catalogue
    (not a sample: no sampling error); their precision is that of the located window
    ends (~1e-14 in ``E``, folds and IS/PD points; a window end that is a path end is
    the last path member, within ~0.01 of the family's true end). ``t_max``: count only
    families whose smallest period is ``<= t_max``.

    Examples
    --------
    >>> rows = stable_fraction([5.45, 5.9, 9.0])
    >>> [r["families"] > 0 for r in rows], rows[-1]["fraction"]
    ([True, True, False], None)
    """
    fams = list(load(path))
    if t_max is not None:
        fams = [f for f in fams if f.record["period_range"][0] <= t_max]
    out = []
    for E in energies:
        Ef = as_float(E, "E")
        here = [f for f in fams if f.exists_at(Ef)]
        st = sum(f.stable_at(Ef) for f in here)
        frac = st / len(here) if here else None
        out.append({"E": Ef, "families": len(here), "stable": st, "fraction": frac})
    return out
