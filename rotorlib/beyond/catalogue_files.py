"""The catalogue's files: one JSON per family, the index, the schema and the flat
table of members, written from a build (:func:`rotorlib.beyond.catalogue_build.build`);
the parent/daughter links, stability windows and ends of each family.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

from .catalogue_tasks import VERSION, near, write_json

__all__ = ["END_KINDS", "write"]

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
                near = [
                    m
                    for m in g["path"] + g["special"]
                    if abs(m["E"] - p["E"]) < 2 * 0.01
                    and near(m["period"], n * p["period"], 2e-3)
                ]
                if near:
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
        f["stored"] = [m for m in f["stored"] if any(m is p for p in keep)] + [
            m for m in f["stored"] if m["kind"] == "seed"
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
                    "action": m.get("action"),
                    "maslov": None,
                    "u": m["u"],
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
                + [m["trace_str"], m["stability"], repr(m["action"])]
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
        w.writerow(
            ["id", "name", "kind", "E", "period", "a1", "a2", "p1", "p2"]
            + ["trace", "stability", "action"]
        )
        w.writerows(rows)
    return idx
