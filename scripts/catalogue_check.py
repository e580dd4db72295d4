"""Check the stored catalogue against independent computations (outside CI; minutes).

``python scripts/catalogue_check.py [--path DIR] [--E 4.3 5.45 6.2 2.55 7.35]``
``  [--grid 400] [--closure-E V] [--skip-outside] [--out FILE]``

1. Held-back energies: an independent census at each ``--E`` (its own ``--grid``,
   ``T <=`` the catalogue's period bound there); every reference orbit must be a
   member of a family at that energy (period 1e-8 relative, tr M 1e-6), the member
   solved from the stored members (:func:`rotorlib.beyond.catalogue_checks.held_back`). An energy outside the
   built window is reported and counts as a failure unless ``--skip-outside``.
2. Every special point ``rotorlib.family`` locates on a named family is one of the
   record's (E to 1e-8); the record's points it does not locate are listed.
3. ``rotorlib catalogue --E V --digits 30 --json`` at each ``--E`` inside the window
   (or ``--closure-E``): each member's ``state0_str`` closes
   after its ``period_str`` under an independent real128 integration (heyoka, the
   rotor equations written in the tests) to < 1e-20.
4. Every family file against the schema; the links both ways.

Prints one line per check and a JSON summary last (also written to ``--out``: chapter
13 reads ``book/data/catalogue_check.json``); exits 1 if any check fails.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def closure(E: str, path: str | None) -> list[tuple[str, float, float]]:
    """``(id, period, closure)`` of each member ``catalogue --E E --digits 30`` gives."""
    sys.path.insert(0, str(ROOT / "tests"))
    # the tests' independent rotor equations (tests/independent.py)
    from independent import decimal_theta as _decimal_theta
    from independent import real128_closure as _real128_closure

    from rotorlib.cli import main

    argv = ["catalogue", "--E", E, "--digits", "30", "--json"]
    argv += ["--path", path] if path else []
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rc = main(argv)
    if rc != 0:
        raise SystemExit(f"catalogue --E {E} exited {rc}")
    out = []
    for r in json.loads(buf.getvalue()):
        if "error" in r:
            out.append((r["id"], float("nan"), float("inf")))
            continue
        th, w = _decimal_theta(r["state0_str"])
        out.append(
            (r["id"], float(r["period"]), _real128_closure(th, w, r["period_str"]))
        )
    return out


def main(argv=None) -> int:
    import rotorlib
    from rotorlib.beyond.catalogue import load
    from rotorlib.beyond.catalogue_checks import (
        held_back,
        named_special_points,
        validate,
    )

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--path", default=None, help="catalogue directory (default: stored)")
    p.add_argument("--E", nargs="+", default=["4.3", "5.45", "6.2", "2.55", "7.35"])
    p.add_argument("--grid", type=int, default=400)
    p.add_argument("--closure-E", default=None, help="default: the first --E inside")
    p.add_argument("--skip-outside", action="store_true")
    p.add_argument("--out", default=None, help="write the JSON summary here")
    a = p.parse_args(argv)
    cat = load(a.path)
    lo, hi = cat.index["window"]
    fails: list[str] = []
    summary: dict = {"window": [lo, hi], "t_max": cat.index["t_max"], "held_back": []}
    summary["bands"] = cat.index["bands"]
    inside = []
    for E in a.E:
        if not lo <= float(E) <= hi:
            print(f"E = {E}: outside the built window [{lo}, {hi}]: not checked")
            if not a.skip_outside:
                fails.append(f"E = {E} outside the window")
            continue
        inside.append(E)
        t0 = time.time()
        r = held_back(float(E), grid=a.grid, path=a.path)
        dt = time.time() - t0
        grid_note = (
            " (ON the build's census grid: not held back)" if r["on_grid"] else ""
        )
        print(
            f"E = {E}{grid_note}: {r['reference']} reference orbits (T <= {r['t_max']}), "
            f"{len(r['matched'])} matched, {len(r['unmatched'])} in no family "
            f"({dt:.0f} s)"
        )
        for T, tr in r["unmatched"]:
            print(f"   IN NO FAMILY: period {T!r}, tr M {tr!r}")
            fails.append(f"E = {E}: orbit T = {T!r} in no family")
        for fid, msg in r["errors"]:
            print(f"   {fid}: member not solved: {msg}")
        summary["held_back"].append(
            {k: r[k] for k in ("E", "on_grid", "reference", "t_max")}
            | {
                "matched": len(r["matched"]),
                "unmatched": r["unmatched"],
                "families": len({fid for _, fid in r["matched"]}),
                "grid": a.grid,
                "cpu_s": round(dt, 1),
            }
        )
    named = named_special_points(rotorlib.family, a.path)
    for r in named:
        print(
            f"{r['id']} {r['name']} (family {r['label']!r}): {r['located']} of its "
            f"{r['points']} special points located by rotorlib.family, worst |dE| "
            f"{r['worst']:.1e}; missing from the record {r['missing']}; not located by "
            f"family {r['not_located']} (it stops: {r['reason']})"
        )
        if r["missing"]:
            fails.append(f"{r['id']} special points missing: {r['missing']}")
    summary["named"] = named
    summary["closure"] = []
    for E_cl in [a.closure_E] if a.closure_E else inside or [repr((lo + hi) / 2)]:
        t0 = time.time()
        cl = closure(E_cl, a.path)
        worst = max((c for _, _, c in cl), default=0.0)
        print(
            f"catalogue --E {E_cl} --digits 30: {len(cl)} members, worst real128 "
            f"closure {worst:.1e} ({time.time() - t0:.0f} s)"
        )
        if not cl or not worst < 1e-20:
            fails.append(f"closure at E = {E_cl}: {worst:.1e}")
        summary["closure"].append({"E": E_cl, "members": len(cl), "worst": worst})
    bad = validate(a.path)
    print(f"schema and links: {len(cat)} families, {len(bad)} problems")
    for b in bad:
        print("  ", b)
    fails += bad
    summary["families"] = len(cat)
    summary["failures"] = fails
    print(json.dumps(summary, default=str))
    if a.out:
        Path(a.out).write_text(json.dumps(summary, indent=1, default=str) + "\n")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
