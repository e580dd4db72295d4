"""Building the catalogue of periodic-orbit families (:mod:`rotorlib.beyond.catalogue`).

The build is a set of tasks of three kinds, each a pure function of its inputs:

* ``census``: :func:`rotorlib.beyond.atlas.census` at one energy (float64, named);
* ``follow``: one census orbit continued with the engine
  (:func:`rotorlib.orbits.continuation.continuation`, pseudo-arclength, through folds) in
  both directions until it leaves the built energy window or ``T <= T_max``, or the engine
  stops (step too small, section lost), with ``tr M`` of every member, its folds and its
  ``IS`` / ``PD`` points located, and a member located at every census energy it crosses;
* ``polish``: one stored member re-solved at ``digits = 30`` (heyoka real128): ``E``,
  period, ``state0`` and ``tr M`` as decimal strings, the multipliers, the closure.

Every task is keyed by a hash of its inputs (:func:`task_key`); its result is written,
as it finishes, to ``<cache>/<key>.json`` (a temporary file renamed: complete or absent).
:func:`run_tasks` skips the tasks whose file exists: a build killed at any point (a
worker, or the client) resumes without redoing a finished task. Tasks run serially, on
a process pool or on a Dask cluster (:func:`rotorlib.core.parallel.executor_for`).

:func:`build` runs the census round, refines the energy grid where the number of census
orbits changes between neighbours (a family born or dying between them), follows the
census orbits energy by energy (an orbit whose family is already catalogued is not
followed again: each census orbit belongs to exactly one family), polishes the stored
members, links parents and daughters, and writes the files (:func:`write`).

Precision: float64 continuation (members to residual < 1e-8; folds to ~1e-15 in ``E``,
IS/PD to ~1e-14 in the local parameter); stored members re-solved to 30 digits
(``state0_str``; ``tr M`` to 25 digits); the action ``S = oint p.dq = 2 (E T - int V dt)``
by Simpson's rule on 801 samples (~1e-9 relative). The Maslov index is not computed (its
field is ``null``).
"""

from __future__ import annotations

import csv
import hashlib
import json
import math
import os
import sys
import time
from collections.abc import Sequence
from concurrent.futures import Executor, as_completed
from dataclasses import replace
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "VERSION",
    "task_key",
    "run_tasks",
    "problem_of",
    "census_task",
    "follow_task",
    "polish_task",
    "build",
    "write",
    "END_KINDS",
]

#: The version of the task functions and of the file format (part of every task's key).
VERSION = 1

#: Why a family's record ends, from the engine's stop code (``E range``: see ``_end``).
END_KINDS = {
    "period": "leaves T <= T_max",
    "stuck": "engine stopped (a critical point, a cusp or a sharp turn)",
    "section lost": "engine stopped (the orbit no longer reaches its section)",
    "steps": "step budget",
}


def task_key(kind: str, args: dict) -> str:
    """The hash of a task's inputs (sha256 of its canonical JSON, with :data:`VERSION`).

    >>> task_key("census", {"E": 5.45, "t_max": 8.0, "grid": 300})[:12]
    'c9c757c3cccf'
    """
    text = json.dumps({"v": VERSION, "kind": kind, "args": args}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def _write_json(path: Path, obj: Any) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(obj, indent=1))
    os.replace(tmp, path)  # atomic: the file is complete or absent


def _execute(job: tuple) -> Any:
    """One task: compute, then store ``{kind, args, result, cpu_s}`` under its key
    (``cpu_s``: the task's CPU seconds in its process)."""
    kind, args, cache = job
    c0 = time.process_time()
    result = TASKS[kind](args)
    cpu = time.process_time() - c0
    if cache is not None:
        p = Path(cache) / f"{task_key(kind, args)}.json"
        _write_json(p, {"kind": kind, "args": args, "result": result, "cpu_s": cpu})
    return result


def _bar(total: int, desc: str, progress: bool):
    if not progress or os.environ.get("TQDM_DISABLE"):
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm(total=total, desc=desc, file=sys.stderr)


def run_tasks(
    jobs: Sequence[tuple[str, dict]],
    cache: str | os.PathLike | None,
    executor: Executor | None = None,
    progress: bool = False,
    desc: str = "tasks",
) -> tuple[list, int]:
    """``([result of each job], number of jobs run)``: the jobs ``(kind, args)`` whose
    result is not stored in ``cache`` are run (serially, or submitted all at once to
    ``executor``) and stored as each finishes; the others are read back.

    >>> run_tasks([], None)
    ([], 0)
    """
    keys = [task_key(k, a) for k, a in jobs]
    done: dict[str, Any] = {}
    if cache is not None:
        Path(cache).mkdir(parents=True, exist_ok=True)
        for key in keys:
            p = Path(cache) / f"{key}.json"
            if p.exists():
                done[key] = json.loads(p.read_text())["result"]
    todo = {key: job for key, job in zip(keys, jobs) if key not in done}
    bar = _bar(len(todo), desc, progress)
    c = None if cache is None else str(cache)
    try:
        if executor is None:
            for key, (k, a) in todo.items():
                done[key] = _execute((k, a, c))
                if bar is not None:
                    bar.update()
        else:
            futs = {
                executor.submit(_execute, (k, a, c)): key
                for key, (k, a) in todo.items()
            }
            try:
                for f in as_completed(futs):
                    key = futs[f]
                    done[key] = f.result()
                    if c is not None and not (Path(c) / f"{key}.json").exists():
                        kind, args = todo[key]  # a remote worker: store it here
                        _write_json(
                            Path(c) / f"{key}.json",
                            {"kind": kind, "args": args, "result": done[key]},
                        )
                    if bar is not None:
                        bar.update()
            except BaseException:
                for f in futs:
                    f.cancel()
                raise
    finally:
        if bar is not None:
            bar.close()
    return [done[k] for k in keys], len(todo)


# --------------------------------------------------------------------------- tasks


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


def census_task(args: dict) -> list[dict]:
    """The census at ``args['E']`` as records (float64; named after the atlas unless
    ``args['name']`` is False)."""
    from .atlas import census

    a = census(args["E"], args["t_max"], args["grid"], name=args.get("name", True))
    out = []
    for o in a.orbits:
        p = o.extra["problem"]
        out.append(
            {
                "E": float(o.E),
                "label": o.label,
                "family": o.family,
                "period": float(o.period),
                "trace": float(o.trace),
                "state0": [float(v) for v in o.state0],
                "u": float(o.extra["u"]),
                "start": p.start.name,
                "target": o.extra["fixed_sets"][1],
                "crossing": int(p.crossing),
                "t_half": float(a.t_max / 2 * 1.02),
                "action": float(o.extra["action"]),
                "fixed_sets": list(o.extra["fixed_sets"]),
                "choreography": o.extra.get("choreography") is not None,
            }
        )
    return out


def _member_rec(m, kind: str = "path") -> dict:
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


def follow_task(args: dict) -> dict:
    """One census orbit (``args['seed']``) continued both ways in ``args['E_range']``
    (steps of at most ``args['step']`` in ``E``, ``T <= args['t_max']``), with a member
    located at each of ``args['energies']``; the action of every located member."""
    from ..core.flow import states_at
    from ..orbits.continuation import PALC, ContinuationOptions, continuation, member
    from ..orbits.shooting import residual
    from .atlas import orbit_action

    o = args["seed"]
    prob = problem_of(o)
    s = residual(prob, o["u"], o["E"])
    factor = float(Fraction(o["period"] / float(s.t1)).limit_denominator(48))
    prob = replace(prob, label="catalogue", factor=factor)
    m0 = member(prob, o["u"], o["E"], traces=True)
    lo, hi = args["E_range"]
    opts = ContinuationOptions(
        max_steps=args.get("max_steps", 600),
        E_range=(lo, hi),
        t_max=args["t_max"],
        jump=0.05,
        traces=True,
        folds=True,
        energies=tuple(e for e in args["energies"] if lo <= e <= hi),
    )
    ds = args["step"] / max(hi, 1.0)
    alg = PALC(ds=ds, ds_max=ds, ds_min=1e-10, u_floor=1.0)
    back, fwd = (
        continuation(prob, replace(alg, direction=d), opts, [m0]) for d in (-1, 1)
    )
    n = len(back.members)
    path = [_member_rec(m) for m in back.members[::-1] + fwd.members[1:]]
    points = [
        (p, n - 1 - p.index - (p.kind != "fold")) for p in back.special_points
    ] + [(p, n - 1 + p.index) for p in fwd.special_points]
    special = []
    for p, idx in sorted(points, key=lambda v: v[1]):
        if not p.located:
            continue
        rec = _member_rec(p.member, p.kind)
        rec["index"] = idx
        T = rec["period"]
        rec["action"] = float(orbit_action(rec["x0"], T, rec["E"]))
        special.append(rec)
    seed = _member_rec(m0, "seed")
    seed["action"] = float(orbit_action(seed["x0"], seed["period"], seed["E"]))
    x = states_at(seed["x0"], [0.0, seed["period"]])
    winding = [float(v) / (2 * math.pi) for v in (x[1] - x[0])[:2]]
    return {
        "factor": factor,
        "problem": {k: o[k] for k in ("start", "target", "crossing", "t_half", "E")},
        "path": path,
        "special": special,
        "seed": seed,
        "winding": winding,
        "ends": [
            {"side": "backward", "stop": back.stop, "reason": back.reason},
            {"side": "forward", "stop": fwd.stop, "reason": fwd.reason},
        ],
    }


def polish_task(args: dict) -> dict:
    """A stored member re-solved at ``args['digits']`` digits at the energy
    ``args['E_str']`` from ``args['u']``: the decimal strings of ``E``, the period,
    ``state0`` and ``tr M`` (5 digits fewer), the multipliers, the closure error; or
    ``{'failed': reason}`` when the re-solve does not converge."""
    from ..core.flow import SectionNotReached
    from ..orbits.shooting import NoConvergence

    try:
        return _polish(args)
    except (NoConvergence, SectionNotReached, ValueError, ZeroDivisionError) as exc:
        return {"failed": f"{type(exc).__name__}: {exc}"[:300]}


def _polish(args: dict) -> dict:
    from ..core.flow import monodromy_matrix
    from ..core.precision import tier
    from ..core.system import lattice_reduce
    from ..orbits.shooting import residual, solve

    D = int(args["digits"])
    prob = problem_of(
        {**args["problem"], "label": "catalogue", "factor": args["factor"]}
    )
    t = tier(D)
    with t.context():
        u0 = t.num(repr(args["u"]))
        u1 = u0 * (1 + t.num("1e-12"))
        u = solve(prob, u0, u1, E=args["E_str"], digits=t, r_max=t.eps**0.6).x
        sh = residual(prob, u, args["E_str"], t)
        T = prob.factor * sh.t1
        M, xT, tr = monodromy_matrix(sh.x0, T, t)
        d = lattice_reduce([a - b for a, b in zip(xT, sh.x0)], D)
        mult = np.linalg.eigvals(np.array(M, dtype=float))
        return {
            "E_str": args["E_str"],
            "period_str": t.text(T, D),
            "state0_str": [t.text(v, D) for v in sh.x0],
            "trace_str": t.text(tr, D - 5),
            "u_str": t.text(u, D),
            "multipliers": [[float(z.real), float(z.imag)] for z in mult],
            "closure": max(abs(float(v)) for v in d),
            "residual": abs(float(sh.r)),
            "digits": D,
        }


TASKS = {"census": census_task, "follow": follow_task, "polish": polish_task}


# --------------------------------------------------------------------------- the build


def _near(a: float, b: float, rel: float) -> bool:
    return abs(a - b) <= rel * max(1.0, abs(b))


def covers(fam: dict, orb: dict) -> bool:
    """Whether a followed family has a member at the census orbit's energy with its
    period (1e-7 relative) and ``tr M`` (1e-5 relative, at least absolute)."""
    pts = [fam["seed"], *fam["special"], *fam["path"]]
    return any(
        _near(m["E"], orb["E"], 1e-10)
        and _near(m["period"], orb["period"], 1e-7)
        and _near(m["trace"], orb["trace"], 1e-5)
        for m in pts
    )


def _refine(censuses: dict, depth: int) -> list[float]:
    """Midpoints of neighbouring census energies whose orbit counts differ."""
    Es = sorted(censuses)
    return [
        round((a + b) / 2, 12)
        for a, b in zip(Es, Es[1:])
        if len(censuses[a]) != len(censuses[b]) and b - a > 2.0**-depth
    ]


def build(
    energies: Sequence[float],
    t_max: float,
    cache: str | os.PathLike,
    grid: int = 300,
    step: float = 0.01,
    refine: int = 1,
    digits: int = 30,
    name: bool = True,
    max_steps: int = 600,
    executor: Executor | None = None,
    progress: bool = False,
    log=None,
) -> dict:
    """The catalogue of the families met by censuses at ``energies`` (the build window is
    their range), ``T <= t_max``: ``{'families': [...], 'censuses': {E: [...]},
    'window': (lo, hi), 'tasks': {kind: (total, run)}}``. See the module docstring."""
    energies = sorted(float(e) for e in energies)
    if not energies or energies[0] <= 0 or energies[-1] > 8:
        raise ValueError(f"energies must lie in 0 < E <= 8, got {energies!r}")
    lo, hi = energies[0], energies[-1]
    say = log or (lambda s: None)
    ran: dict[str, list[int]] = {"census": [0, 0], "follow": [0, 0], "polish": [0, 0]}

    def run(kind, argss, desc):
        res, n = run_tasks([(kind, a) for a in argss], cache, executor, progress, desc)
        ran[kind][0] += len(argss)
        ran[kind][1] += n
        return res

    def do_census(Es):
        extra = {} if name else {"name": False}
        args = [{"E": E, "t_max": t_max, "grid": grid, **extra} for E in Es]
        res = run("census", args, "census")
        return dict(zip(Es, res))

    censuses = do_census(energies)
    for level in range(refine):
        extra = [E for E in _refine(censuses, 8) if E not in censuses]
        if not extra:
            break
        say(f"refine {level + 1}: census at {extra}")
        censuses.update(do_census(extra))
    grid_E = sorted(censuses)
    fams: list[dict] = []
    for E in grid_E:
        todo = [o for o in censuses[E] if not any(covers(f, o) for f in fams)]
        res = run(
            "follow",
            [
                {
                    "seed": o,
                    "E_range": [lo, hi],
                    "t_max": t_max,
                    "step": step,
                    "energies": grid_E,
                    **({} if max_steps == 600 else {"max_steps": max_steps}),
                }
                for o in todo
            ],
            f"follow E={E:g}",
        )
        for o, f in zip(todo, res):
            if not any(covers(g, o) for g in fams):
                fams.append(f)
        say(
            f"E = {E:g}: {len(censuses[E])} orbits, {len(todo)} followed, {len(fams)} families"
        )
    # each census orbit in exactly one family: the first that covers it
    for f in fams:
        f["census"] = []
    orphans: list[dict] = []
    for E in grid_E:
        for o in censuses[E]:
            f = next((f for f in fams if covers(f, o)), None)
            (orphans if f is None else f["census"]).append(o)
    # stored members: the located energies of the grid, the special points, the seed
    jobs = []
    for f in fams:
        f["stored"] = list(f["special"])
        if not any(_near(m["E"], f["seed"]["E"], 1e-12) for m in f["stored"]):
            f["stored"].append(f["seed"])
        f["stored"].sort(key=lambda m: m.get("index", 0))
        for m in f["stored"]:
            jobs.append(
                {
                    "problem": f["problem"],
                    "factor": f["factor"],
                    "u": m["u"],
                    "E_str": repr(
                        min(grid_E, key=lambda e: abs(e - m["E"]))
                        if m["kind"] == "E"
                        else m["E"]
                    ),
                    "digits": digits,
                }
            )
    pol = iter(run("polish", jobs, "polish"))
    for f in fams:
        for m in f["stored"]:
            m["polish"] = next(pol)
    return {
        "families": fams,
        "censuses": censuses,
        "orphans": orphans,
        "window": (lo, hi),
        "t_max": t_max,
        "grid": grid,
        "step": step,
        "tasks": {k: tuple(v) for k, v in ran.items()},
    }


# --------------------------------------------------------------------------- files


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
                    and _near(m["period"], n * p["period"], 2e-3)
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
        _write_json(out / f"{f['id']}.json", rec)
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
    _write_json(out / "index.json", idx)
    _write_json(out / "schema.json", schema)
    with open(out / "members.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            ["id", "name", "kind", "E", "period", "a1", "a2", "p1", "p2"]
            + ["trace", "stability", "action"]
        )
        w.writerows(rows)
    return idx
