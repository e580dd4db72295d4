"""The tasks of the catalogue build (:mod:`rotorlib.beyond.catalogue_build`) and their store.

Nine kinds of task, each a pure function of its inputs:

* ``census``: :func:`rotorlib.beyond.atlas.census` at one energy (float64, named);
* ``follow``: one census orbit continued with the engine
  (:func:`rotorlib.orbits.continuation.continuation`, pseudo-arclength, through folds) in
  both directions until it leaves the built energy window or ``T <= T_max``, or the engine
  stops (step too small, section lost), with ``tr M`` of every member, its folds and its
  ``IS`` / ``PD`` points located, and a member located at every census energy it crosses;
* ``switch``: the censuses beside a located ``IS`` / ``PD`` point, restricted to the
  periods of its daughters (:func:`switch_task`);
* ``beyond``: a family continued in its shooting unknown ``u`` past the end where the
  engine's steps zigzagged in ``E`` (:func:`beyond_task`), for a new seed there;
* ``polish``: one stored member re-solved at ``digits = 30``
  (:func:`rotorlib.beyond.catalogue_members.polish_task`);
* ``locate``: one IS or PD point located again at ``digits = 30``
  (:func:`rotorlib.beyond.catalogue_roots.locate_task`);
* ``touch``: where ``tr M`` comes closest to 4 between two stored members whose Maslov
  indices differ (:func:`rotorlib.beyond.catalogue_roots.touch_task`);
* ``fold``: one fold located again at ``digits = 30``, the extremum of ``E`` along the
  branch (:func:`rotorlib.beyond.catalogue_roots.fold_task`);
* ``densify``: path members shot where the interpolant between the float64 members is
  not shown (:func:`rotorlib.beyond.catalogue_members.densify_task`).

Every task is keyed by a hash of its inputs (:func:`task_key`); its result is written,
as it finishes, to ``<cache>/<key>.json`` (a temporary file renamed: complete or absent).
:func:`run_tasks` skips the tasks whose file exists: a build killed at any point (a
worker, or the client) resumes without redoing a finished task. Tasks run serially, on
a process pool or on a Dask cluster (:func:`rotorlib.core.parallel.executor_for`).

Precision: float64 continuation (members to residual < 1e-8; folds to ~1e-15 in ``E``,
IS/PD to ~1e-14 in the local parameter; both located again to 30 digits by ``fold``
and ``locate``).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import sys
import time
from collections.abc import Sequence
from concurrent.futures import Executor, as_completed
from dataclasses import replace
from fractions import Fraction
from pathlib import Path
from typing import Any

from .catalogue_members import (
    densify_task,
    member_record,
    polish_task,
    problem_of,
)
from .catalogue_roots import fold_task, locate_task, touch_task

__all__ = [
    "VERSION",
    "KIND_REVISION",
    "task_key",
    "run_tasks",
    "census_task",
    "follow_task",
    "switch_task",
    "beyond_task",
    "heyoka_ready",
    "stored",
    "finished",
    "TASKS",
    "near",
    "PERIOD_TOL",
    "TRACE_TOL",
    "TRACE_TOL_SQ",
    "matches",
    "write_json",
    "execute_task",
    "progress_bar",
]

#: The version of the task functions and of the file format (part of every task's key).
VERSION = 1
#: Revisions of single task kinds, so that a fix to one kind invalidates only its own
#: cached results (polish 2: the period factor is the exact rational, not its float).
KIND_REVISION = {"polish": 2}


def near(a: float, b: float, rel: float) -> bool:
    """Whether ``|a - b| <= rel * max(1, |b|)``.

    >>> near(1.0, 1.0 + 1e-9, 1e-8), near(1.0, 1.1, 1e-8)
    (True, False)
    """
    return abs(a - b) <= rel * max(1.0, abs(b))


#: The period tolerance of a match (relative).
PERIOD_TOL = 1e-8
#: The ``tr M`` tolerance of a match (relative to ``max(1, |tr M|)``) ...
TRACE_TOL = 1e-6
#: ... plus this times ``tr M^2``: a float64 ``tr M`` of a very unstable orbit is good to
#: about ``1e-11 tr M^2`` only (an error in the start state grows by ``|tr M|`` over the
#: period, times a factor that depends on the orbit); measured against the 30-digit
#: value: 1e-5 relative (1e-13 tr M^2) at ``tr M = -7.5e7`` (E = 4.3, T = 14.48), and
#: 0.33 and 0.79 (up to 9e-12 tr M^2) for the census's and the catalogue's float64
#: values at ``tr M = -3.03e5`` (E = 4.02, T = 12.13): a match of two float64 values
#: allows the sum, with margin. Two orbits of one period (1e-8) are still told apart
#: unless their ``tr M`` agree that closely.
TRACE_TOL_SQ = 3e-11


def matches(T: float, tr: float, T_m: float, tr_m: float) -> bool:
    """Whether a reference orbit ``(T, tr M)`` is the member ``(T_m, tr_m)``: the period
    to :data:`PERIOD_TOL` relative, ``tr M`` to :data:`TRACE_TOL` ``max(1, |tr M|)`` plus
    :data:`TRACE_TOL_SQ` ``tr M^2``.

    >>> matches(14.4767701559, -75126795.6, 14.4767701559, -75126297.0)
    True
    >>> matches(7.000834, 129139.0, 7.000834, 16.9)
    False
    """
    return (
        abs(T_m - T) <= PERIOD_TOL * T
        and abs(tr_m - tr) <= TRACE_TOL * max(1.0, abs(tr)) + TRACE_TOL_SQ * tr * tr
    )


def task_key(kind: str, args: dict) -> str:
    """The hash of a task's inputs (sha256 of its canonical JSON, with :data:`VERSION`
    and the kind's :data:`KIND_REVISION`, if it has one).

    >>> task_key("census", {"E": 5.45, "t_max": 8.0, "grid": 300})[:12]
    'c9c757c3cccf'
    """
    head: dict[str, Any] = {"v": VERSION, "kind": kind, "args": args}
    if kind in KIND_REVISION:
        head["rev"] = KIND_REVISION[kind]
    text = json.dumps(head, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


#: A JSON array of numbers, strings, booleans or nulls, as ``json.dumps(indent=1)``
#: writes it (one item per line).
_FLAT_ARRAY = re.compile(r'\[\n\s*((?:[-+\w.":, ]+,\n\s*)*[-+\w.":, ]+)\n\s*\]')


def write_json(path: Path, obj: Any, rows: bool = False) -> None:
    """Write ``obj`` as JSON to ``path`` atomically (a temporary file renamed).

    ``rows``: each array of scalars on one line (a family's path, a member's state):
    a third smaller than one item per line, and as readable.

    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "x.json"
    >>> write_json(p, {"path": [[1.5, -2e-3], [3, 4]], "name": "a, b"}, rows=True)
    >>> print(p.read_text())
    {
     "path": [
      [1.5, -0.002],
      [3, 4]
     ],
     "name": "a, b"
    }
    >>> json.loads(p.read_text())["path"][0]
    [1.5, -0.002]
    """
    text = json.dumps(obj, indent=1)
    if rows:
        text = _FLAT_ARRAY.sub(
            lambda m: "[" + re.sub(r",\n\s*", ", ", m.group(1)) + "]", text
        )
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)  # atomic: the file is complete or absent


def heyoka_ready(tries: int = 8, load=None) -> Any:
    """Load heyoka with its on-disk cache bounded (``load``: default
    :func:`rotorlib.core.precision.load_heyoka`), retrying while another process holds
    the cache's SQLite database: a fresh machine's first 2-worker build died at once
    with heyoka's "Failed to set the WAL journal mode ..." in a worker. Waits 0.05 s,
    0.1 s, ... (doubling) between ``tries`` attempts, then raises heyoka's error.

    >>> fails = [2]
    >>> def flaky():  # fails twice, as a database held by another process does
    ...     if fails[0]:
    ...         fails[0] -= 1
    ...         raise RuntimeError("Failed to set the WAL journal mode")
    >>> heyoka_ready(load=flaky)
    >>> fails
    [0]
    """
    from ..core.precision import load_heyoka

    for k in range(tries):
        try:
            return (load or load_heyoka)()
        except RuntimeError:
            if k == tries - 1:
                raise
            time.sleep(0.05 * 2**k)


def execute_task(job: tuple) -> tuple[Any, float]:
    """One task: compute, then store ``{kind, args, result, cpu_s}`` under its key
    (``cpu_s``: the task's CPU seconds in its process); returns ``(result, cpu_s)``.
    heyoka logs only errors in a task's process."""
    import heyoka

    # heyoka's warning of a zero event cooldown, printed at each integration that
    # starts at rest (a census at E = 4, at the equilibrium's energy), fills gigabytes
    # of a build's log; its errors still show
    heyoka.set_logger_level_error()
    heyoka_ready()
    kind, args, cache = job
    c0 = time.process_time()
    result = TASKS[kind](args)
    cpu = time.process_time() - c0
    if cache is not None:
        p = Path(cache) / f"{task_key(kind, args)}.json"
        write_json(p, {"kind": kind, "args": args, "result": result, "cpu_s": cpu})
    return result, cpu


def stored(kind: str, args: dict, cache) -> tuple[Any, float] | None:
    """``(result, cpu_s)`` of a task stored in ``cache``, or ``None``."""
    if cache is None:
        return None
    p = Path(cache) / f"{task_key(kind, args)}.json"
    if not p.exists():
        return None
    rec = json.loads(p.read_text())
    return rec["result"], float(rec.get("cpu_s", 0.0))


def finished(kind: str, args: dict, cache, out: tuple[Any, float]) -> None:
    """Store a task's ``(result, cpu_s)`` here if its (remote) worker did not."""
    if cache is not None:
        p = Path(cache) / f"{task_key(kind, args)}.json"
        if not p.exists():
            rec = {"kind": kind, "args": args, "result": out[0], "cpu_s": out[1]}
            write_json(p, rec)


def progress_bar(total: int, desc: str, progress: bool):
    """A tqdm progress bar on stderr (None without ``progress``, tqdm or with TQDM_DISABLE)."""
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
    cpu: dict[str, float] | None = None,
) -> tuple[list, int]:
    """``([result of each job], number of jobs run)``: the jobs ``(kind, args)`` whose
    result is not stored in ``cache`` are run (serially, or submitted all at once to
    ``executor``) and stored as each finishes; the others are read back. ``cpu``, if
    given, receives the CPU seconds of each job by its key (stored or measured).

    >>> run_tasks([], None)
    ([], 0)
    """
    keys = [task_key(k, a) for k, a in jobs]
    done: dict[str, tuple[Any, float]] = {}
    if cache is not None:
        Path(cache).mkdir(parents=True, exist_ok=True)
    for key, (k, a) in zip(keys, jobs):
        got = stored(k, a, cache)
        if got is not None:
            done[key] = got
    todo = {key: job for key, job in zip(keys, jobs) if key not in done}
    bar = progress_bar(len(todo), desc, progress)
    c = None if cache is None else str(cache)
    try:
        if executor is None:
            for key, (k, a) in todo.items():
                done[key] = execute_task((k, a, c))
                if bar is not None:
                    bar.update()
        else:
            futs = {
                executor.submit(execute_task, (k, a, c)): key
                for key, (k, a) in todo.items()
            }
            try:
                for f in as_completed(futs):
                    key = futs[f]
                    done[key] = f.result()
                    finished(*todo[key], c, done[key])  # a remote worker: store here
                    if bar is not None:
                        bar.update()
            except BaseException:
                for f in futs:
                    f.cancel()
                raise
    finally:
        if bar is not None:
            bar.close()
    if cpu is not None:
        cpu.update({k: done[k][1] for k in keys})
    return [done[k][0] for k in keys], len(todo)


# --------------------------------------------------------------------------- tasks


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


def follow_task(args: dict) -> dict:
    """One census orbit (``args['seed']``) continued both ways in ``args['E_range']``
    (steps of at most ``args['step']`` in ``E``, ``T <= args['t_max']``), with a member
    located at each of ``args['energies']`` (the action and Maslov index come with the
    polish: :func:`rotorlib.beyond.catalogue_members.polish_task`)."""
    from ..core.flow import states_at
    from ..orbits.continuation import PALC, ContinuationOptions, continuation, member
    from ..orbits.shooting import residual

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
    path = [member_record(m) for m in back.members[::-1] + fwd.members[1:]]
    points = [
        (p, n - 1 - p.index - (p.kind != "fold")) for p in back.special_points
    ] + [(p, n - 1 + p.index) for p in fwd.special_points]
    special = []
    for p, idx in sorted(points, key=lambda v: v[1]):
        if not p.located:
            continue
        rec = member_record(p.member, p.kind)
        rec["index"] = idx
        special.append(rec)
    seed = member_record(m0, "seed")
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


def switch_task(args: dict) -> list[dict]:
    """The daughters' candidates beside a located ``IS`` / ``PD`` point of period
    ``T_b``: the census (:func:`rotorlib.beyond.atlas.census`, float64, unnamed) at each of
    ``args['energies']`` (``E_b -+ dE``) to ``T <= args['t_max']`` (a little above
    ``args['period'] = n T_b``, ``n = 1`` at ``IS``, 2 at ``PD``), keeping the orbits whose
    period is within ``args['rel']`` of ``n T_b``.

    Covers the daughters that are symmetric orbits (they meet two fixed sets, as the
    census finds them) and exist at ``E_b - dE`` or ``E_b + dE``; a daughter born
    asymmetric, or one whose period differs from ``n T_b`` by more than ``rel`` at
    ``dE``, is not found here."""
    out = []
    for E in args["energies"]:
        rec = census_task(
            {"E": E, "t_max": args["t_max"], "grid": args["grid"], "name": False}
        )
        out += [o for o in rec if near(o["period"], args["period"], args["rel"])]
    return out


def beyond_task(args: dict) -> list[dict]:
    """A family continued past the end where the engine's steps zigzagged in ``E`` (the
    stop ``reversal`` of :func:`rotorlib.beyond.catalogue_paths.cut_at_reversal`), in
    its shooting unknown ``u`` instead of ``E``: from the end member (``args['u']``,
    ``args['E']``) in steps of ``args['du']`` (the sign: the path's way at that end),
    the second unknown solved at each fixed ``u`` (float64, residual < 1e-8), which a
    fold does not trouble (the residual's derivative in ``E`` does not vanish there).

    The walk stops, and its last member is returned as a seed orbit (a census record
    with ``via``, the problem's fixed sets and the ``u`` of ``args['problem']``):

    * 5 steps after ``E`` turned back (a fold passed: the seed lies on the family's
      other branch), or
    * after 30 steps with no turn (the path is regular there: the zigzag was the
      engine's, not the family's);

    ``[]`` when a solve fails, the period leaves ``args['t_max']`` or ``E`` the
    window ``args['E_range']`` first, or the problem's start set does not exist at the
    seed's energy (the census's start sets change at E = 4 and 4.5). Measured on the ``T <= 16`` build: a family with
    ``tr M ~ -470`` cut at E = 4.67852 turns at a fold at E = 4.6786 two steps of
    ``6e-5`` in ``u`` later, and its other branch (``tr M ~ +800``, T = 15.07 at
    E = 4.67848) lay on no record."""
    from ..core.flow import SectionNotReached
    from ..orbits.continuation import member
    from ..orbits.shooting import NoConvergence, solve

    spec = args["problem"]
    prob = replace(problem_of(spec), label="catalogue", factor=args["factor"])
    lo, hi = args["E_range"]
    u, E, du = float(args["u"]), float(args["E"]), float(args["du"])
    w = prob.w_at(u, E)
    first, turned = None, None
    for k in range(1, 31):
        u += du
        try:
            w = solve(prob, w, w * (1 + 1e-7), u=u).x
        except (NoConvergence, SectionNotReached, ValueError):
            return []
        E_new = float(prob.energy(u, w))
        sign = math.copysign(1.0, E_new - E)
        E = E_new
        if not lo <= E <= hi:
            return []
        first = sign if first is None else first
        if turned is None and sign != first:
            turned = k
        if turned is not None and k - turned >= 5:
            break
    try:
        m = member(prob, u, w, traces=True)
        problem_of({**spec, "E": E})  # the follow's problem at the seed's energy
    except (NoConvergence, SectionNotReached, ValueError):
        return []
    if not float(m.period) <= args["t_max"]:
        return []
    return [
        {
            "E": float(m.E),
            "label": "new",
            "family": None,
            "period": float(m.period),
            "trace": float(m.trace),
            "state0": [float(v) for v in m.x0],
            "u": float(m.u),
            "start": spec["start"],
            "target": spec["target"],
            "crossing": spec["crossing"],
            "t_half": spec["t_half"],
            "fixed_sets": [spec["start"], spec["target"]],
            "choreography": False,
            "turned": turned,
        }
    ]


TASKS = {
    "census": census_task,
    "follow": follow_task,
    "switch": switch_task,
    "beyond": beyond_task,
    "polish": polish_task,
    "locate": locate_task,
    "touch": touch_task,
    "fold": fold_task,
    "densify": densify_task,
}
