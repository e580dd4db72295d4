"""Checks of the stored catalogue (:mod:`rotorlib.beyond.catalogue`) against independent
computations: the script ``scripts/catalogue_check.py`` runs them all, the tests one each.

* :func:`held_back`: an independent census (:func:`rotorlib.beyond.atlas.census`, its own
  grid) at an energy off the build's census grid; every reference orbit must be a member
  of a catalogued family at that energy (the member solved from the interpolant of the
  stored members, :meth:`~rotorlib.beyond.catalogue.Family.members_at`): the period to
  ``1e-8`` relative and ``tr M`` to ``1e-6`` relative to ``max(1, |tr M|)`` plus
  ``3e-11 tr M^2`` (:func:`rotorlib.beyond.catalogue_tasks.matches`).
* :func:`named_special_points`: every special point (IS, PD, fold) of a named family
  against the one :func:`rotorlib.family` locates (passed in) over the family's energy range (``E``
  to ``1e-8``), and the points it locates there that the record lacks.
* :func:`validate`: every family file against the schema, the links both ways.
* :func:`midpoints`: the interpolant between stored members (the one the stored
  members serve, :meth:`~rotorlib.beyond.catalogue.Family.interpolate`) against members
  re-solved there, in float64 or at 30 digits; :func:`midpoint_summary` its table.

The real128 closure of ``rotorlib catalogue --E V --json`` is in the script and in
``tests/test_catalogue.py`` (it integrates with the tests' independent rotor equations).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable

from ..core.system import BREATHER_SEPARATRIX_ENERGY, SEPARATRIX_ENERGY
from .catalogue_tasks import matches

__all__ = [
    "beside_separatrix_or_fold",
    "held_back",
    "midpoint_summary",
    "midpoints",
    "named_special_points",
    "validate",
]


def held_back(
    E: float,
    t_max: float | None = None,
    grid: int = 400,
    path: str | os.PathLike | None = None,
    census=None,
) -> dict:
    """Every orbit of an independent census at ``E`` (``T <= t_max``, default the
    catalogue's period bound at ``E``) matched against the catalogue's members at ``E``.

    Returns ``{'E', 't_max', 'on_grid', 'in_window', 'reference', 'matched',
    'unmatched', 'errors'}``: ``matched`` holds ``(period, family id)``, ``unmatched``
    the reference orbits no family contains (``(period, tr M)``), ``errors`` the
    families whose member could not be solved. ``census``: a census already computed
    (an :class:`~rotorlib.beyond.atlas.Atlas`) instead of a new one.
    """
    from ..core.energy import as_float
    from .atlas import census as run_census
    from .catalogue import load

    Ef = as_float(E, "E")
    cat = load(path)
    T_max = cat.period_bound(Ef) if t_max is None else float(t_max)
    lo, hi = cat.index["window"]
    a = census if census is not None else run_census(Ef, T_max, grid, name=False)
    members: list[tuple[str, float, float]] = []
    errors = []
    for f in cat:
        if not (f.exists_at(Ef) and f.may_reach(T_max)):
            continue  # (no member below the bound anywhere: none to match)
        try:
            ms = f.members_at(repr(Ef))
        except ValueError as exc:
            errors.append((f.id, str(exc)))
            continue
        members += [(f.id, float(m.period), float(m.trace)) for m in ms]
    matched: list[tuple] = []
    unmatched: list[tuple] = []
    for o in a.orbits:
        T, tr = float(o.period), float(o.trace)
        if T > T_max:
            continue
        hit = [fid for fid, Tm, trm in members if matches(T, tr, Tm, trm)]
        (matched if hit else unmatched).append((T, hit[0]) if hit else (T, tr))
    return {
        "E": Ef,
        "t_max": T_max,
        "on_grid": any(abs(Ef - e) < 1e-12 for e in cat.index["census_energies"]),
        "in_window": lo <= Ef <= hi,
        "reference": len(matched) + len(unmatched),
        "matched": matched,
        "unmatched": unmatched,
        "errors": errors,
    }


def named_special_points(
    family: Callable, path: str | os.PathLike | None = None, names=None
) -> list[dict]:
    """For each named family (or those in ``names``) that ``family`` serves
    (:func:`rotorlib.family`, passed in: this layer does not import the front door; a
    name it does not serve raises ValueError and is skipped; ``breather X`` is asked
    as ``X``), over the record's energy range (widened to its special points, and by
    1e-8): the
    special points (IS, PD, folds) ``family`` locates against the record's.

    Returns ``[{'id', 'name', 'label', 'points', 'located', 'worst', 'missing',
    'not_located', 'not_compared', 'reason'}]``: ``points`` the record's, ``located`` those ``family``
    locates, ``worst`` the largest ``|dE|`` between a located point and the record's
    point of the same kind nearest it, ``missing`` the located points the record lacks
    (no point of the kind within ``1e-8``: a failure), ``not_located`` the record's
    points ``family`` does not locate (its branch stops before them, or does not pass
    a fold: ``reason`` says why it stopped). A point counts as the record's when any
    record of the same name has it (the census may give two records one name).
    ``not_compared``: the points ``family`` locates where the record cannot have them,
    ``(kind, E, period, tr M)``: above the record's ``T_max``, or not a root at all
    (``tr M`` far from its level: a sign change through a pole, as ``family("PD^r_2")``
    gives within 5e-8 of the separatrix E = 4.5, where ``tr M ~ 1e14`` and ``T > 30``)."""
    from .catalogue import load

    out = []
    cat = load(path)
    for f in cat:
        if not f.name or (names is not None and f.name not in names):
            continue
        pts = f.record["special_points"]
        # widened by the comparison's 1e-8: a fold at an end, located at 30 digits, may
        # lie just inside the float64 fold that family() locates
        lo = min([f.E_range[0]] + [p["E"] for p in pts]) - 1e-8
        hi = max([f.E_range[1]] + [p["E"] for p in pts]) + 1e-8
        b, lab = None, f.name
        for lab in (f.name, f.name.removeprefix("breather ")):
            try:
                b = family(lab, (lo, hi))
                break
            except ValueError:
                continue
        if b is None:
            continue
        kinds = ("IS", "PD", "fold")
        level = {"IS": 4.0, "fold": 4.0, "PD": 0.0}
        t_max = float(f.record["t_max"])  # how far the record was followed
        located = [
            p
            for p in b.special_points
            if p.member is not None and p.located and p.kind in kinds
        ]
        # the record stops at T_max, and a sign change of tr M - 4 through a pole (the
        # family running into a separatrix, tr M ~ 1e14) is not a special point
        theirs = [
            (p.kind, float(p.member.E))
            for p in located
            if float(p.member.period) <= t_max
            and abs(float(p.member.trace) - level[p.kind]) < 1e-3
        ]
        beyond = [
            (p.kind, float(p.member.E), float(p.member.period), float(p.member.trace))
            for p in located
            if (p.kind, float(p.member.E)) not in theirs
        ]
        # the records the census names alike (one family the engine carried in two
        # records, or twin branches of a pitchfork) share their points
        ours = [
            (p["kind"], float(p["E"]))
            for g in cat
            if g.name == f.name
            for p in g.record["special_points"]
            if p["kind"] in kinds
        ]

        def gap(k, E, others):
            # an IS that ``family`` locates at a fold of the record: the record calls
            # it a fold (tr M = 4 there), so a fold of the record matches it
            same = ("IS", "fold") if k == "IS" else (k,)
            return min((abs(E - e) for kk, e in others if kk in same), default=math.inf)

        d = [gap(k, E, ours) for k, E in theirs]
        out.append(
            {
                "id": f.id,
                "name": f.name,
                "label": lab,
                "points": len(ours),
                "located": len(theirs),
                "worst": max([x for x in d if x <= 1e-8], default=0.0),
                "missing": [(k, E, x) for (k, E), x in zip(theirs, d) if x > 1e-8],
                "not_located": [(k, E) for k, E in ours if gap(k, E, theirs) > 1e-8],
                "not_compared": beyond,
                "reason": b.reason,
            }
        )
    return out


def validate(path: str | os.PathLike | None = None) -> list[str]:
    """The problems of the stored files: a family file that fails the schema
    (:data:`rotorlib.beyond.catalogue_schema.SCHEMA`, with ``jsonschema``), a stored
    ``schema.json`` that differs from it, a parent/daughter link without its converse,
    a ``fold_twins`` link that the other record does not return. ``[]`` when there is
    none."""
    import json

    import jsonschema

    from .catalogue import DATA, SCHEMA, load

    cat = load(path)
    p = DATA if path is None else path
    bad = []
    with open(os.path.join(p, "schema.json")) as fh:
        stored = json.load(fh)
    if stored != SCHEMA:
        bad.append("schema.json differs from rotorlib.beyond.catalogue.SCHEMA")
    v = jsonschema.Draft202012Validator(SCHEMA)
    by = {f.id: f.record for f in cat}
    for r in by.values():
        for e in v.iter_errors(r):
            bad.append(f"{r['id']}: {e.message[:200]}")
        for d in r["daughters"]:
            back = {"id": r["id"], "kind": d["kind"], "E": d["E"]}
            if d["id"] not in by or back not in by[d["id"]]["parents"]:
                bad.append(f"{r['id']}: daughter {d} has no parent link back")
        for q in r["parents"]:
            back = {"id": r["id"], "kind": q["kind"], "E": q["E"]}
            if q["id"] not in by or back not in by[q["id"]]["daughters"]:
                bad.append(f"{r['id']}: parent {q} has no daughter link back")
        for t in r["fold_twins"]:  # both records name each other, at one fold
            if t["id"] not in by or not any(
                b["id"] == r["id"] and abs(b["E"] - t["E"]) <= 1e-6 * abs(t["E"])
                for b in by[t["id"]]["fold_twins"]
            ):
                bad.append(f"{r['id']}: fold twin {t} does not name it back")
    return bad


def beside_separatrix_or_fold(E: float, special: list[dict]) -> bool:
    """Whether ``E`` lies within 0.2 of a separatrix energy (4 or 4.5) or within 0.01
    of a fold among the record's special points ``special``: the ``near`` class of
    :func:`midpoints`, where the interpolant is measured apart.

    Examples
    --------
    >>> beside_separatrix_or_fold(4.15, []), beside_separatrix_or_fold(5.3, [])
    (True, False)
    >>> beside_separatrix_or_fold(5.3, [{"kind": "fold", "E": 5.305}])
    True
    """
    sep = min(abs(E - SEPARATRIX_ENERGY), abs(E - BREATHER_SEPARATRIX_ENERGY))
    return sep < 0.2 or any(
        p["kind"] == "fold" and abs(E - p["E"]) < 0.01 for p in special
    )


def midpoints(
    path: str | os.PathLike | None = None,
    stride: int = 1,
    digits: int | None = None,
    ids: list[str] | None = None,
) -> list[dict]:
    """The catalogue's interpolant at the midpoints between neighbouring stored members
    against the members re-solved there.

    On each piece of each family (of ``ids``, default all), at every ``stride``-th
    pair of neighbouring stored members, the midpoint in the piece's parameter: in
    ``E`` on a piece parametrised by ``E``; in ``u`` on one parametrised by ``u``
    (through a fold), at the ``E`` the interpolant gives there. The member is shot
    in float64 at that ``E`` from the interpolated ``u``
    (:func:`~rotorlib.beyond.catalogue_members.shoot_member`); on a ``u`` piece the
    shot must land between the pair's ``u`` (beside a fold two members share ``E``),
    and the interpolant is read at the ``u`` it lands on
    (:meth:`~rotorlib.beyond.catalogue.Family.interpolate_piece`). With ``digits``
    (30), the member is then re-solved at ``digits``
    (:func:`~rotorlib.beyond.catalogue_members.polish_task`): the reference for
    ``tr M``, whose float64 value is good to ~1e-11 ``tr M^2`` only.

    Returns one row per midpoint: ``{'id', 'param', 'E', 'near', 'period_error',
    'trace_error'}``, the period's error relative, ``tr M``'s relative to
    ``max(1, |tr M|)`` (``None`` in float64); ``near``:
    :func:`beside_separatrix_or_fold`. A midpoint whose shot fails or leaves the interval has
    ``'failed'`` (its reason) in place of the errors.
    """
    from ..orbits.shooting import NoConvergence
    from .catalogue import load
    from .catalogue_members import polish_task, shoot_member

    if stride < 1:
        raise ValueError(f"stride must be >= 1, got {stride!r}")
    rows: list[dict] = []
    for f in load(path):
        if ids is not None and f.id not in ids:
            continue
        rec = f.record
        br = rec["branch"]
        for k, pc in enumerate(rec["interpolation"]["pieces"]):
            nodes = [rec["members"][i] for i in pc["members"]]
            key = pc["param"]
            for a, b in list(zip(nodes, nodes[1:]))[::stride]:
                r = f.interpolate_piece(k, 0.5 * (a[key] + b[key]))
                row: dict = {"id": f.id, "param": key, "E": r["E"]}
                row["near"] = beside_separatrix_or_fold(r["E"], rec["special_points"])
                rows.append(row)
                box = (min(a["u"], b["u"]), max(a["u"], b["u"])) if key == "u" else None
                try:
                    m = shoot_member(f.problem, r["E"], r["u"], r["period"], box)
                except (NoConvergence, ValueError) as exc:
                    row["failed"] = f"{type(exc).__name__}: {exc}"[:200]
                    continue
                u = float(m.u)
                if key == "u":  # the interpolant where the shot landed
                    r = dict(f.interpolate_piece(k, u), E=r["E"])
                if digits is None:
                    T, tr = float(m.period), None
                else:
                    args = {"problem": br["problem"], "factor": br["factor"], "u": u}
                    s = polish_task({**args, "E_str": repr(r["E"]), "digits": digits})
                    if "failed" in s:
                        row["failed"] = s["failed"]
                        continue
                    T, tr = float(s["period_str"]), float(s["trace_str"])
                row["period_error"] = abs(r["period"] / T - 1)
                row["trace_error"] = (
                    None if tr is None else abs(r["trace"] - tr) / max(1.0, abs(tr))
                )
    return rows


def midpoint_summary(rows: list[dict], tol: float = 1e-8) -> dict:
    """The rows of :func:`midpoints` by class: ``far`` and ``near`` (pieces
    parametrised by ``E``), ``u`` (pieces parametrised by ``u``). Each class:
    ``{'n', 'failed', 'period_above', 'trace_above', 'period_max', 'period_max_at',
    'trace_max', 'trace_max_at', 'above'}`` (``_above``: how many exceed ``tol``;
    ``_at``: ``[id, E]``; the ``tr M`` entries ``None`` for float64 rows; ``above``:
    ``[id, E, period error, tr M error]`` of the rows above ``tol``, the worst 20).

    Examples
    --------
    >>> rows = [{"id": "F001", "param": "E", "E": 5.0, "near": False,
    ...          "period_error": 2e-9, "trace_error": None}]
    >>> s = midpoint_summary(rows)
    >>> s["far"]["n"], s["far"]["period_above"], s["near"]["n"]
    (1, 0, 0)
    """
    out: dict = {}
    for cls in ("far", "near", "u"):
        rs = [
            r
            for r in rows
            if (r["param"] == "u") == (cls == "u")
            and (cls == "u" or r["near"] == (cls == "near"))
        ]
        ok = [r for r in rs if "failed" not in r]
        c: dict = {"n": len(ok), "failed": len(rs) - len(ok)}
        for q in ("period", "trace"):
            e = [r for r in ok if r[f"{q}_error"] is not None]
            w = max(e, key=lambda r: r[f"{q}_error"], default=None)
            c[f"{q}_above"] = sum(r[f"{q}_error"] > tol for r in e) if e else None
            c[f"{q}_max"] = None if w is None else w[f"{q}_error"]
            c[f"{q}_max_at"] = None if w is None else [w["id"], w["E"]]
        bad = [
            r for r in ok if r["period_error"] > tol or (r["trace_error"] or 0.0) > tol
        ]
        c["above"] = [  # where (at most 20, the worst first)
            [r["id"], r["E"], r["period_error"], r["trace_error"]]
            for r in sorted(
                bad, key=lambda r: -max(r["period_error"], r["trace_error"] or 0)
            )
        ][:20]
        out[cls] = c
    return out
