"""The catalogue's files: one JSON per family, the index, the schema and the flat
table of members, written from a build (:func:`rotorlib.beyond.catalogue_build.build`);
the parent/daughter links, stability windows and ends of each family.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from .catalogue_members import DEGREE, TOL, interpolation_errors, phase_data
from .catalogue_tasks import VERSION, near, write_json

__all__ = ["END_KINDS", "COLUMNS", "write", "write_parquet"]

#: Why a family's record ends, from the engine's stop code (``E range``: see ``_end``).
END_KINDS = {
    "period": "leaves T <= T_max",
    "stuck": "engine stopped (a critical point, a cusp or a sharp turn)",
    "section lost": "engine stopped (the orbit no longer reaches its section)",
    "steps": "step budget",
}


def _end(f: dict, side: int, lo: float, hi: float) -> dict:
    """The record of one end of a family: where and why it stops."""
    m = f["path"][0 if side == 0 else -1]
    e = f["ends"][side]
    stop = e["stop"]
    if stop == "E range":
        outside = m["E"] < lo or m["E"] > hi
        at_axis = (m["E"] <= 0 and lo <= 0.01) or (m["E"] >= 8 and hi >= 8)
        kind = "E = 0 or 8" if at_axis else "end of the built window"
        if not outside:
            kind = "end of the built window"
    else:
        kind = END_KINDS.get(stop, stop)
    return {
        "side": e["side"],
        "E": m["E"],
        "period": m["period"],
        "kind": kind,
        "stop": stop,
        "reason": e["reason"],
    }


def _symmetry(f: dict) -> dict:
    sets = sorted({tuple(o["fixed_sets"]) for o in f["census"]})
    return {
        "fixed_sets": [list(s) for s in sets],
        "choreography": any(o["choreography"] for o in f["census"]),
        "rotating": any(abs(w) > 1e-6 for w in f["winding"]),
        "winding": [round(w, 9) for w in f["winding"]],
    }


def _stable_windows(f: dict) -> list[list[float]]:
    """Runs of stable path members, bounded by the located IS/PD/fold points beside them."""
    path, marks = f["path"], f["special"]
    out, i = [], 0
    st = [0 < m["trace"] < 4 for m in path]
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


def _links(fams: list[dict]) -> None:
    """Parent -> daughter links: a family with a member within 1e-6 in E of a parent's
    located IS (PD) point, with the parent's period (twice it) to 1e-5, is its daughter."""
    for f in fams:
        f["parents"], f["daughters"] = [], []
    for f in fams:
        for p in f["special"]:
            if p["kind"] not in ("IS", "PD"):
                continue
            n = 2 if p["kind"] == "PD" else 1
            for g in fams:
                if g is f:
                    continue
                hits = [
                    m
                    for m in g["path"] + g["special"]
                    if abs(m["E"] - p["E"]) < 2 * 0.01
                    and near(m["period"], n * p["period"], 2e-3)
                ]
                if hits:
                    link = {"kind": p["kind"], "E": p["E"]}
                    f["daughters"].append({"id": g["id"], **link})
                    g["parents"].append({"id": f["id"], **link})


def write(cat: dict, out: str | os.PathLike, schema: dict) -> dict:
    """Write one JSON per family, ``index.json``, ``schema.json`` (``schema``: the loader's
    :data:`rotorlib.beyond.catalogue.SCHEMA`) and ``members.csv`` into ``out``; returns
    the index."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fams = sorted(
        cat["families"],
        key=lambda f: (min(m["period"] for m in f["path"]), f["seed"]["E"]),
    )
    lo, hi = cat["window"]
    for i, f in enumerate(fams):
        f["id"] = f"F{i + 1:03d}"
        # a point located from both directions (beside the seed) is kept once
        seen, keep = set(), []
        for p in f["special"]:
            key = (p["kind"], round(p["E"], 10), round(p["period"], 7))
            if key not in seen:
                seen.add(key)
                keep.append(p)
        f["special"] = keep
        f["stored"] = [
            m
            for m in f["stored"]
            if m["kind"] in ("path", "seed") or any(m is p for p in keep)
        ]
    _links(fams)
    rows, index = [], []
    failed: list[tuple] = []
    for f in fams:
        names = sorted({o["label"] for o in f["census"] if o["label"] != "new"})
        Es = [m["E"] for m in f["path"]]
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
            "t_max": cat["t_max"],
            "window": [lo, hi],
            "symmetry": _symmetry(f),
            "E_range": [min(Es), max(Es)],
            "period_range": [
                min(m["period"] for m in f["path"]),
                max(m["period"] for m in f["path"]),
            ],
            "ends": [_end(f, 0, lo, hi), _end(f, 1, lo, hi)],
            "special_points": [
                {k: p[k] for k in ("kind", "E", "period", "trace", "index")}
                for p in f["special"]
                if p["kind"] != "E"
            ],
            "stable_windows": _stable_windows(f),
            "parents": f["parents"],
            "daughters": f["daughters"],
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
        write_json(out / f"{f['id']}.json", rec)
        index.append(
            {
                k: rec[k]
                for k in ("id", "name", "E_range", "period_range", "stable_windows")
            }
            | {"symmetry": rec["symmetry"], "n_members": len(members)}
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
    than the tolerance, e.g. the short steps where the engine stopped)."""
    info = f.get("interpolation")
    if info is None:
        return {"pieces": [], "degree": DEGREE, "tolerance": TOL, "max_error": None}
    path = f["path"]
    worst, acc_T, acc_tr = 0.0, 0.0, 0.0
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
    }
