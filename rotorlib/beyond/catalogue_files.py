"""The catalogue's files: one JSON per family, the index, the schema and the flat
table of members, written from a build (:func:`rotorlib.beyond.catalogue_build.build`);
the parent/daughter links, stability windows and ends of each family.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from ..core.system import BREATHER_SEPARATRIX_ENERGY, SEPARATRIX_ENERGY
from .catalogue_ids import assign_ids
from .catalogue_links import link_families
from .catalogue_members import (
    DEGREE,
    TOL,
    interpolation_errors,
    left_out_errors,
    phase_data,
)
from .catalogue_paths import seed_index
from .catalogue_tasks import VERSION, write_json

__all__ = ["END_KINDS", "COLUMNS", "write", "write_parquet"]

#: Why a family's record ends, from the engine's stop code (``E range``: see ``_end``).
END_KINDS = {
    "period": "leaves T <= T_max",
    "stuck": "engine stopped",
    "section lost": "engine stopped",
    "steps": "engine stopped",
    "fold": "fold",
    "parent": "bifurcation from a parent",
    "separatrix": "collision with a separatrix",
    "critical": "a critical point",
    "untrusted": "engine stopped",
    "reversal": "engine stopped",
    "axis": "E = 0 or E = 8",
    "window": "end of the built window",
}

#: The separatrix energies (the saddles of the potential: the pendulum's E = 4, the
#: breather's E = 4.5) and the critical energies (the equilibria: 0, 4, 4.5).
SEPARATRICES = (SEPARATRIX_ENERGY, BREATHER_SEPARATRIX_ENERGY)


def _extreme(f: dict, side: int) -> int:
    """The path member where the family's energy is lowest (``side`` 0) or highest (1)."""
    Es = [m["E"] for m in f["path"]]
    return (min if side == 0 else max)(range(len(Es)), key=lambda i: Es[i])


def _end(f: dict, side: int, lo: float, hi: float) -> dict:
    """The record of the family's low-energy (``side`` 0) or high-energy (1) end: where
    and why its energy range stops.

    At an interior member of the path (the engine went on): a ``fold``, or, where the fold
    lies on a parent's located IS/PD point (within 1e-4 in ``E``, as the path's turning
    member is where the engine did not locate the fold; the links of
    :func:`~rotorlib.beyond.catalogue_links.link_families`), a
    ``bifurcation from a parent``. At an end of the path: a ``bifurcation from a parent``
    too where the engine stopped (``stuck``, ``section lost``) within 1e-3 in ``E`` of a
    parent's point (the distance is given: the engine may stop short of a pitchfork's
    point on the daughter's side); otherwise, from the engine's stop: ``E = 0 or E = 8``, or ``end of the built window`` (``E range``);
    ``collision with a separatrix`` (the period grows past ``T_max`` as ``E`` approaches
    4 or 4.5, within 0.05, the period rising over the last members) or ``leaves T <=
    T_max`` (``period``); ``a critical point`` (the engine stops within 0.05 of
    ``E = 0``, or of 4 or 4.5 with the momenta of ``state0`` below 0.05: the orbit shrinks
    to an equilibrium; or the path was cut where the engine carried it across a critical
    energy onto another orbit, :func:`~rotorlib.beyond.catalogue_paths.cut_at_critical`);
    ``bifurcation from a parent`` where the path was cut at a fold onto its parent's
    branch (:func:`~rotorlib.beyond.catalogue_paths.cut_at_switch`); ``engine stopped``
    where it was cut because its float64 members disagree with their 30-digit re-solves
    (:func:`~rotorlib.beyond.catalogue_paths.cut_untrusted`: the reason gives the
    disagreement) or where its steps zigzag (``reversal``,
    :func:`~rotorlib.beyond.catalogue_paths.cut_at_reversal`; ``fold`` when the zigzag
    starts just past one), or with the engine's reason (``stuck``,
    ``section lost``, ``steps``; where another family goes on from the same orbit,
    :func:`_joins`, it is named). ``side`` names the path's direction
    (``backward``/``forward`` from the seed) where the end lies."""
    path = f["path"]
    i = _extreme(f, side)
    m = path[i]
    seed = seed_index(f) or 0
    direction = "backward" if i < seed or (i == seed and seed == 0) else "forward"
    e = f["ends"][0 if direction == "backward" else 1]
    stop, reason = e["stop"], e["reason"]
    if 0 < i < len(path) - 1 or stop == "fold":  # at a fold: the located one
        at = [p for p in f.get("special", ()) if p["kind"] == "fold"]
        at = [p for p in at if abs(p["E"] - m["E"]) < 1e-4 * max(1.0, m["E"])]
        m = dict(m, E=at[0]["E"], period=at[0]["period"]) if at else m
    near_sep = [s for s in (0.0, *SEPARATRICES) if abs(m["E"] - s) < 0.05]
    if 0 < i < len(path) - 1:
        stop = "fold"
        parent = next(
            (
                p
                for p in f.get("parents", ())
                if abs(p["E"] - m["E"]) < 1e-4 * max(1.0, abs(m["E"]))
            ),
            None,
        )
        if parent is not None:
            kind = END_KINDS["parent"]
            reason = f"born at the {parent['kind']} point of {parent['id']} at E = {parent['E']:.10g}"
        else:  # the record of the branch beyond it is named (fold_twins, link_families)
            kind = END_KINDS["fold"]
            reason = f"fold at E = {m['E']:.10g} (the engine went on past it)"
            twin = [
                t["id"] for t in f.get("fold_twins", ()) if abs(t["E"] - m["E"]) < 1e-4
            ]
            if twin:  # the record of the fold's other branch
                reason += f"; the branch beyond the fold is the record {twin[0]}"
    elif stop in ("critical", "untrusted"):  # cut_at_critical, cut_untrusted
        kind = END_KINDS[stop]
    elif stop == "switch":  # cut_at_switch: born at the parent's branch point
        kind = END_KINDS["parent"]
        ps = [p for p in f.get("parents", ()) if abs(p["E"] - m["E"]) < 1e-6]
        if ps:
            reason = f"born at the IS point of {ps[0]['id']} at E = {ps[0]['E']:.10g}; {reason}"
    elif stop == "E range":
        at_axis = (m["E"] <= 0.01 and lo <= 0.01) or (m["E"] >= 8 and hi >= 8)
        kind = END_KINDS["axis"] if at_axis else END_KINDS["window"]
    elif stop == "period":
        k = max(0, i - 3) if i > 0 else min(len(path) - 1, 3)
        rising = m["period"] > path[k]["period"]
        sep = [s for s in near_sep if s > 0]
        if sep and rising:
            kind = END_KINDS["separatrix"]
            reason = (
                f"T -> infinity as E -> {sep[0]:g} (the separatrix energy); {reason}"
            )
        else:
            kind = END_KINDS["period"]
    elif stop in ("stuck", "section lost", "reversal", "fold") and (
        born := [p for p in f.get("parents", ()) if abs(p["E"] - m["E"]) < 1e-3]
    ):
        kind = END_KINDS["parent"]
        reason = (
            f"born at the {born[0]['kind']} point of {born[0]['id']} at E = "
            f"{born[0]['E']:.10g}; the engine stopped {abs(born[0]['E'] - m['E']):.1e} "
            f"from it ({reason})"
        )
    elif stop in ("reversal", "fold"):  # cut_at_reversal, away from a parent's point
        kind = END_KINDS[stop]
        on = [j for j in f.get("joins", ()) if j.get("beyond") and j["side"] == (i > 0)]
        for j in on[:1]:  # walked on in u past the zigzag (the build's beyond task)
            reason += f"; past the zigzag the family goes on as the record {j['id']}"
    elif joined := [j for j in f.get("joins", ()) if j["side"] == (0 if i == 0 else 1)]:
        kind = END_KINDS["stuck"]
        j = joined[0]
        reason = f"{reason}; the family goes on as {j['id']} " + (
            f"(the same orbit at E = {m['E']:.10g}: the engine does not carry it "
            "across this energy)"
            if "gap" not in j
            else f"(whose record stops {j['gap']:.1e} away in E, with the same "
            "period to 1e-3 and tr M to 1e-2: the engine crossed the gap from "
            "neither side)"
        )
    elif near_sep and (
        m["E"] < 0.05 or max(abs(v) for v in m.get("x0", [1.0] * 4)[2:]) < 0.05
    ):
        kind = END_KINDS["critical"]
        reason = f"E -> {near_sep[0]:g}, momenta -> 0 (an equilibrium); {reason}"
    else:
        kind = END_KINDS.get(stop, "engine stopped")
    return {
        "side": direction,
        "E": m["E"],
        "period": m["period"],
        "kind": kind,
        "stop": stop,
        "reason": reason,
    }


def _symmetry(f: dict) -> dict:
    sets = sorted({tuple(o["fixed_sets"]) for o in f["census"]}) or [  # none: the
        (f["problem"]["start"], f["problem"]["target"])  # shooting problem's
    ]
    return {
        "fixed_sets": [list(s) for s in sets],
        "choreography": any(o["choreography"] for o in f["census"]),
        "rotating": any(abs(w) > 1e-6 for w in f["winding"]),
        "winding": [round(w, 9) for w in f["winding"]],
    }


def _stable_windows(f: dict) -> list[list[float]]:
    """Runs of stable path members, bounded by the located IS/PD/fold points beside them.
    A member inside a ``marginal`` stretch (``tr M`` within 1e-6 of 4 or 0, its side
    not resolved: :func:`rotorlib.beyond.catalogue_build.special_points`) is in none."""
    path = f["path"]
    marks = [p for p in f["special"] if p["kind"] != "marginal"]
    out, i = [], 0
    unresolved = {
        k
        for p in f["special"]
        if p["kind"] == "marginal"
        for k in range(p["index"], p["index_end"] + 2)
    }
    st = [0 < m["trace"] < 4 and k not in unresolved for k, m in enumerate(path)]
    while i < len(st):
        j = i
        while j < len(st) and st[j] == st[i]:
            j += 1
        if st[i]:
            ends = [m["E"] for m in path[i:j]] + [
                p["E"] for p in marks if p["kind"] != "E" and i - 1 <= p["index"] < j
            ]
            out.append([min(ends), max(ends)])
        i = j
    merged: list[list[float]] = []  # overlapping windows (through a fold) merged
    for w in sorted(out):
        if merged and w[0] <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], w[1])
        else:
            merged.append(w)
    return merged


def write(cat: dict, out: str | os.PathLike, schema: dict, previous=None) -> dict:
    """Write one JSON per family, ``index.json``, ``schema.json`` (``schema``: the loader's
    :data:`rotorlib.beyond.catalogue_schema.SCHEMA`) and ``members.csv`` into ``out``, with
    the ids of ``previous`` (:func:`~rotorlib.beyond.catalogue_ids.assign_ids`)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fams = sorted(
        cat["families"],
        key=lambda f: (min(m["period"] for m in f["path"]), f["seed"]["E"]),
    )
    lo, hi = cat["window"]
    assign_ids(fams, previous)
    fams.sort(key=lambda f: f["id"])
    for f in fams:
        # a point located from both directions (beside the seed) is kept once
        seen, keep = set(), []
        for p in f["special"]:
            key = (p["kind"], round(p["E"], 10), round(p["period"], 7))
            if key not in seen:
                seen.add(key)
                keep.append(p)
        f["special"] = keep
        for p in keep:  # a point the relocation did not reach: marked, not silent
            if p["kind"] in ("IS", "PD", "fold") and "location" not in p:
                p["location"] = "float64 (not located again at 30 digits)"
        f["stored"] = [
            m
            for m in f["stored"]
            if m["kind"] in ("path", "seed") or any(m is p for p in keep)
        ]
    link_families(fams)
    rows, index = [], []
    failed: list[tuple] = []
    for f in fams:
        names = sorted({o["label"] for o in f["census"] if o["label"] != "new"})
        folds = [p for p in f["special"] if p["kind"] == "fold"]  # beyond the path
        Es = [m["E"] for m in f["path"] + folds]
        members = []
        for m in f["stored"]:
            p = m["polish"]
            if "failed" in p:
                failed.append((f["id"], m["kind"], m["E"], p["failed"]))
                continue
            if "maslov_reason" not in p:  # a polish stored before they were computed
                p = {
                    **p,
                    **phase_data(p["state0_str"], p["period_str"], p["trace_str"]),
                }
            if m["kind"] in ("IS", "fold") and p["maslov"] is not None:
                # tr M = 4 there; its float64 location leaves tr M ~1e-6 from 4 beside
                # a fold (tr M - 4 ~ sqrt(E_f - E)), where phase_data's test misses it
                p = {
                    **p,
                    "maslov": None,
                    "maslov_reason": f"marginal orbit (a located {m['kind']} point, "
                    "tr M = 4): no Maslov index",
                }
            members.append(
                {
                    "kind": m["kind"],
                    "E": m["E"],
                    "E_str": p["E_str"],
                    "period": m["period"],
                    "period_str": p["period_str"],
                    "state0": m["x0"],
                    "state0_str": p["state0_str"],
                    "trace": m["trace"],
                    "trace_str": p["trace_str"],
                    "multipliers": p["multipliers"],
                    "stability": "stable" if 0 < m["trace"] < 4 else "unstable",
                    "action": p["action"],
                    "maslov": p["maslov"],
                    "maslov_reason": p["maslov_reason"],
                    "u": m["u"],
                    "pieces": m.get("pieces", []),
                    "closure": p["closure"],
                    "digits": p["digits"],
                }
            )
        rec = {
            "id": f["id"],
            "name": names[0] if names else None,
            "names": names,
            "t_max": f["t_max"],
            "window": [lo, hi],
            "symmetry": _symmetry(f),
            "E_range": [min(Es), max(Es)],
            "period_range": [
                min(m["period"] for m in f["path"] + folds),
                max(m["period"] for m in f["path"] + folds),
            ],
            "ends": [_end(f, 0, lo, hi), _end(f, 1, lo, hi)],
            "special_points": [
                {
                    k: p[k]
                    for k in ("kind", "E", "period", "trace", "index")
                    + ("E_str", "E_error", "E64", "location")
                    + (
                        ("E_end", "index_end", "crossings", "level")
                        * (p["kind"] == "marginal")
                    )
                    + ("level",) * (p["kind"] == "touch")
                    if k in p
                }
                for p in f["special"]
                if p["kind"] != "E"
            ],
            "stable_windows": _stable_windows(f),
            "parents": f["parents"],
            "daughters": f["daughters"],
            "fold_twins": f["fold_twins"],
            "census_orbits": [
                {k: o[k] for k in ("E", "period", "trace", "label")}
                for o in f["census"]
            ],
            "members": members,
            "interpolation": _interpolation(f, members),
            "branch": {
                "factor": f["factor"],
                "problem": f["problem"],
                "path": [
                    [m["E"], m["u"], m["t1"], m["trace"], *m["x0"]] for m in f["path"]
                ],
            },
        }
        write_json(out / f"{f['id']}.json", rec, rows=True)
        index.append(
            {
                k: rec[k]
                for k in ("id", "name", "E_range", "period_range", "stable_windows")
            }
            | {
                "symmetry": rec["symmetry"],
                "n_members": len(members),
                "fold_twins": [t["id"] for t in rec["fold_twins"]],
            }
        )
        for m in members:
            rows.append(
                [f["id"], rec["name"] or "", m["kind"], m["E_str"], m["period_str"]]
                + m["state0_str"]
                + [m["trace_str"], m["stability"], repr(m["action"]), m["maslov"]]
            )
    idx = {
        "version": VERSION,
        "t_max": cat["t_max"],
        "bands": cat["bands"],
        "window": [lo, hi],
        "grid": cat["grid"],
        "step": cat["step"],
        "census_energies": sorted(cat["censuses"]),
        "census_counts": [len(cat["censuses"][E]) for E in sorted(cat["censuses"])],
        "orphans": len(cat["orphans"]),
        "unpolished": [list(x) for x in failed],
        "families": index,
    }
    write_json(out / "index.json", idx)
    write_json(out / "schema.json", schema)
    with open(out / "members.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS)
        w.writerows(["" if v is None else v for v in r] for r in rows)
    write_parquet(out / "members.parquet", rows)
    return idx


#: The columns of the flat table of members (``members.csv``, ``members.parquet``):
#: decimal strings to 30 digits (``trace`` to 25), ``action`` a float64 repr,
#: ``maslov`` an integer (empty / null for a marginal orbit).
COLUMNS = ["id", "name", "kind", "E", "period", "a1", "a2", "p1", "p2"] + [
    "trace",
    "stability",
    "action",
    "maslov",
]


def write_parquet(path: str | os.PathLike, rows: list[list]) -> bool:
    """The members table (:data:`COLUMNS`, as in ``members.csv``: strings, ``maslov``
    a nullable int32) as Parquet, when pyarrow is installed (``rotorlib[parquet]``);
    returns whether it was written."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return False
    cols = list(zip(*rows)) if rows else [()] * len(COLUMNS)
    arrays = [pa.array(list(c), type=pa.string()) for c in cols[:-1]]
    arrays.append(pa.array(list(cols[-1]), type=pa.int32()))
    pq.write_table(pa.table(arrays, names=COLUMNS), path, compression="zstd")
    return True


def _interpolation(f: dict, members: list[dict]) -> dict:
    """The interpolation record: per piece its parameter, its path indices and its
    nodes (indices into ``members``, in the order of the parameter); the largest error
    of the interpolant on the path with the nodes that were polished (``max_error``), and
    the path's own accuracy measured at them (``path_accuracy``: float64 path values
    against the 30-digit re-solve, period relative, ``tr M`` relative to max(1, |tr M|);
    ``above_tolerance``: ``[E, dT, dtr]`` of the nodes where the path is less accurate
    than the tolerance, e.g. the short steps where the engine stopped); between path
    members, the largest error at a path member of the interpolant through the other
    path members, in each piece's parameter (``left_out_error``,
    :func:`~rotorlib.beyond.catalogue_members.left_out_errors`) and the number of path
    members the build added for it (``densified``: those of the final path, after its
    cuts, that :func:`~rotorlib.beyond.catalogue_members.insert_members` marked with
    their ``parent`` interval's error)."""
    info = f.get("interpolation")
    if info is None:
        return {"pieces": [], "degree": DEGREE, "tolerance": TOL, "max_error": None}
    path = f["path"]
    worst, acc_T, acc_tr, left = 0.0, 0.0, 0.0, 0.0
    pieces = []
    for k, pc in enumerate(info["pieces"]):
        a, b = pc["path"]
        key = pc["param"]
        nodes = [i for i, m in enumerate(members) if k in m["pieces"]]
        nodes.sort(key=lambda i: members[i][key])
        pieces.append({"param": key, "path": [a, b], "members": nodes})
        if len(nodes) < 1:  # every node of the piece failed to polish
            worst = max(worst, 1.0)
            continue
        seg = path[a : b + 1]
        other = "u" if key == "E" else "E"
        x = [m[key] for m in seg] + [members[i][key] for i in nodes]
        Y = [
            [m["period"], m["trace"]] + ([m[other]] if key == "u" else []) for m in seg
        ]
        Y += [
            [members[i]["period"], members[i]["trace"]]
            + ([members[i][other]] if key == "u" else [])
            for i in nodes
        ]
        n = len(seg)
        xs, Ys = np.array(x), np.array(Y)
        e = interpolation_errors(xs, Ys, list(range(n, n + len(nodes))), info["degree"])
        worst = max(worst, float(e[:n].max()))
        if n > 2:  # in the piece's parameter, as the build densified it
            lo = left_out_errors(xs[:n], Ys[:n, :2], info["degree"])
            left = max(left, float(lo.max()))
    above = []  # where the path itself is not accurate to the tolerance
    for m in members:
        if m["pieces"]:
            dT = abs(float(m["period_str"]) / m["period"] - 1)
            tr = float(m["trace_str"])
            dtr = abs(tr - m["trace"]) / max(1.0, abs(tr))
            acc_T, acc_tr = max(acc_T, dT), max(acc_tr, dtr)
            if max(dT, dtr) > info["tolerance"]:
                above.append([m["E"], dT, dtr])
    return {
        "pieces": pieces,
        "degree": info["degree"],
        "tolerance": info["tolerance"],
        "max_error": worst,
        "path_accuracy": {"period": acc_T, "trace": acc_tr, "above_tolerance": above},
        "left_out_error": left,
        "densified": sum(1 for m in path if "parent" in m),
    }
