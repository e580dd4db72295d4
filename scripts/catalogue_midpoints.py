"""The catalogue's interpolant between stored members against 30-digit re-solves
(outside CI; ~3 minutes).

``python scripts/catalogue_midpoints.py [--path DIR] [--stride 8]``
``  [--out book/data/catalogue_midpoints.json]``

At the midpoint in ``E`` of every ``stride``-th pair of neighbouring stored members on
each piece parametrised by ``E``, the interpolant (:meth:`Family.interpolate`: the
period and ``tr M``) is compared with the member re-solved there at 30 digits from the
interpolated ``u`` (:func:`rotorlib.beyond.catalogue_members.polish_task`): a float64 shot
is no reference for ``tr M`` (good to ~1e-11 tr M^2 only). Errors: the period relative,
``tr M`` relative to ``max(1, |tr M|)``. Midpoints are split into ``near`` (within 0.2
of E = 4 or 4.5, or 0.01 of a fold) and ``far``. Writes, per class, the number of
midpoints, how many exceed 1e-8 in each quantity, the largest errors and where they are;
and the re-solves that failed.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main(argv=None) -> int:
    sys.path.insert(0, str(ROOT))
    from rotorlib.beyond.catalogue import load
    from rotorlib.beyond.catalogue_members import polish_task
    from rotorlib.beyond.catalogue_tasks import write_json

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--path", default=None)
    p.add_argument("--stride", type=int, default=8)
    p.add_argument("--out", default=None)
    a = p.parse_args(argv)
    if a.stride < 1:
        p.error("--stride must be >= 1")
    rows: dict[str, list] = {"near": [], "far": []}
    failed = 0
    for f in load(a.path):
        ms, sp = f.record["members"], f.record["special_points"]
        br = f.record["branch"]
        for k, pc in enumerate(f.record["interpolation"]["pieces"]):
            if pc["param"] != "E":
                continue
            nodes = [ms[i] for i in pc["members"]]
            for lo, hi in list(zip(nodes, nodes[1:]))[:: a.stride]:
                E = 0.5 * (lo["E"] + hi["E"])
                near = min(abs(E - 4.0), abs(E - 4.5)) < 0.2 or any(
                    q["kind"] == "fold" and abs(E - q["E"]) < 0.01 for q in sp
                )
                for r in (r for r in f.interpolate(E) if r["piece"] == k):
                    args = {"problem": br["problem"], "factor": br["factor"]}
                    s = polish_task(
                        {**args, "u": r["u"], "E_str": repr(E), "digits": 30}
                    )
                    if "failed" in s:
                        failed += 1
                        continue
                    T, tr = float(s["period_str"]), float(s["trace_str"])
                    eT = abs(r["period"] / T - 1)
                    etr = abs(r["trace"] - tr) / max(1.0, abs(tr))
                    rows["near" if near else "far"].append((eT, etr, f.id, E))
    out: dict = {"stride": a.stride, "failed": failed}
    for key, rs in rows.items():
        wT, wtr = max(rs), max(rs, key=lambda r: r[1])
        out[key] = {
            "n": len(rs),
            "period_above_1e-8": sum(r[0] > 1e-8 for r in rs),
            "trace_above_1e-8": sum(r[1] > 1e-8 for r in rs),
            "period_max": wT[0],
            "period_max_at": [wT[2], wT[3]],
            "trace_max": wtr[1],
            "trace_max_at": [wtr[2], wtr[3]],
        }
    print(json.dumps(out, indent=1))
    if a.out:  # as the build writes its files (atomically)
        write_json(Path(a.out), out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
