"""Building the catalogue of periodic-orbit families (:mod:`rotorlib.beyond.catalogue`).

:func:`build` runs the census round, refines the energy grid where the number of census
orbits changes between neighbours (a family born or dying between them), then:

* **follows** the census orbits as a wavefront (:func:`wavefront`): in ``(E, index)``
  order, each orbit that no family followed from an earlier one covers is continued; the
  free workers follow the next orbits ahead while the first undecided one runs, and a
  family found twice (two seeds of one family in flight) is kept from the seed that comes
  first, so that the families do not depend on timing or on the number of workers; each
  census orbit belongs to exactly one family (the first that covers it);
* **spaces the grid by the families' speed** (:func:`by_speed`): a census between two
  grid energies wherever a followed family's period changes by more than ``speed``
  (10 %) over the interval (near the separatrices, beside folds); its orbits that lie on
  no family (:func:`on_family`, period to 2e-5) are followed as new seeds (the follows
  keep landing on the first grid, so that their cached results stay valid);
* classifies the special points (:func:`~rotorlib.beyond.catalogue_points.special_points`: a fold's own ``tr M = 4`` is the
  fold; ``tr M`` reaching 4 or 0 without a change of stability is a ``touch``; a
  stretch where float64 does not resolve the side of the level is ``marginal``);
* **walks on past zigzags** (:func:`~rotorlib.beyond.catalogue_paths.beyond_jobs`, the
  ``beyond`` task): where a path
  was cut because the engine's steps zigzagged in ``E`` (beside the fold of a very
  unstable family), the family is walked on in its shooting unknown ``u``; a seed
  found there on no family (the other branch of the fold) is followed as a new record;
* **switches branches** at every located ``IS`` (``PD``) point and every touch of ``tr M = 4``
  (of 0) of period ``T_b`` inside the
  window with ``n T_b <= T_max``, where ``T_max`` is the smaller of the family's bound and
  the census's bound at ``E_b`` (a daughter is sought in the scope where it is born):
  censuses at ``E_b -+ dE`` restricted to periods within 3 % of ``n T_b`` (the ``switch``
  task); each orbit found that no family covers (:func:`is_new_daughter`) is followed as
  a new seed, to that ``T_max``, for ``switch`` rounds (daughters of daughters). The
  class covered: daughters that are symmetric orbits (they meet two fixed sets, as the
  census finds them), existing at ``E_b - dE`` or ``E_b + dE``;
* polishes the stored members, cuts a path where its float64 members disagree with
  their 30-digit re-solves (:func:`~rotorlib.beyond.catalogue_paths.cut_untrusted`:
  the continuation loses the family close to a separatrix) and chooses its members
  again, locates its IS, PD and fold points again at 30 digits and the touches that only
  the Maslov index shows (:mod:`rotorlib.beyond.catalogue_points`), and returns the
  catalogue in memory, with the CPU seconds
  of every task kind and of every family; :func:`rotorlib.beyond.catalogue_files.write`
  links parents and daughters, records the ends and writes the files. The tasks and their
  resumable store: :mod:`rotorlib.beyond.catalogue_tasks`.

Precision: as the tasks (float64 continuation, members re-solved to 30 digits); the
action ``S = oint p.dq`` and the Maslov index of each stored member come with its
polish (:mod:`rotorlib.beyond.catalogue_members`: the action to ~1e-13 relative).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Executor, wait
from typing import Any

from .atlas import E_DOMAIN
from .catalogue_members import (
    DENSIFY_ROUNDS,
    coarse_gaps,
    insert_members,
    stored_members,
)
from .catalogue_paths import (
    bands_of,
    beyond_jobs,
    covers,
    cut_at_critical,
    cut_at_reversal,
    cut_at_switch,
    cut_beyond,
    cut_untrusted,
    drop_contained,
    holds,
    on_family,
    period_bound,
    same_orbit,
)
from .catalogue_points import (
    end_folds,
    find_touches,
    relocate_points,
    special_points,
)
from .catalogue_tasks import (
    execute_task,
    finished,
    near,
    progress_bar,
    run_tasks,
    stored,
    task_key,
)

__all__ = [
    "by_speed",
    "wavefront",
    "switch_jobs",
    "is_new_daughter",
    "build",
]


def _slots(executor: Executor | None) -> int:
    """How many tasks keep ``executor`` busy (its processes, or a Dask cluster's threads)."""
    if executor is None:
        return 1
    n = getattr(executor, "_max_workers", None)
    if n:
        return int(n)
    client = getattr(executor, "_client", None)
    if client is not None:
        return max(1, sum(client.nthreads().values()))
    return 2


def wavefront(
    seeds: Sequence[dict],
    args_of: Callable[[dict], dict],
    cache,
    executor: Executor | None = None,
    cpu: dict | None = None,
    bar=None,
    known: Sequence[dict] = (),
) -> tuple[list[dict], int]:
    """``(families, follows run)``: the seeds followed in order, each that no family
    followed from an earlier seed (or in ``known``) covers (:func:`covers`).

    The result is that of the serial rule whatever the timing or the number of workers:
    the families are the follows of the seeds that no earlier *chosen* family covers.
    While the first undecided seed runs, the free workers follow the next seeds (in
    order) that no finished follow of an earlier seed covers and that are no symmetric
    images of a seed in flight (:func:`~rotorlib.beyond.catalogue_paths.same_orbit`);
    a speculative follow whose seed turns out covered (two seeds of one family in
    flight at once) is dropped, the family of the seed that comes first being kept. Results are stored in ``cache``
    (:func:`~rotorlib.beyond.catalogue_tasks.run_tasks`' files) as each finishes.
    """
    n, slots, c = len(seeds), _slots(executor), None if cache is None else str(cache)
    args = [args_of(o) for o in seeds]
    keys = [task_key("follow", a) for a in args]
    results: dict[int, dict] = {}
    running: dict[Any, int] = {}
    checked: set[int] = set()
    # shadow[j]: a finished follow of an earlier seed covers seed j (not run ahead)
    shadow = [any(covers(f, o) for f in known) for o in seeds]
    state = {"pos": 0, "ran": 0}
    chosen: list[int] = []

    def first_undecided() -> int | None:
        """Advance the decided prefix (the serial rule; decisions there are final)."""
        while state["pos"] < n:
            i = state["pos"]
            if not (
                any(covers(f, seeds[i]) for f in known)
                or any(covers(results[j], seeds[i]) for j in chosen)
            ):
                if i not in results:
                    return i
                chosen.append(i)
            state["pos"] += 1
        return None

    def add(j: int, out: tuple[Any, float], run: bool) -> None:
        results[j] = cut_at_reversal(cut_at_critical(out[0]))
        if "t_max" in args[j]:  # how far it was followed (see covers)
            results[j]["t_max"] = args[j]["t_max"]
        if cpu is not None:
            cpu[keys[j]] = out[1]
        for k in range(j + 1, n):
            if not shadow[k] and covers(results[j], seeds[k]):
                shadow[k] = True
        if run:
            state["ran"] += 1
            if bar is not None:
                bar.update()

    try:
        while (first := first_undecided()) is not None:
            busy = set(running.values())
            free = 1 if executor is None else max(0, slots - len(running))
            todo: list[int] = []
            hit = False
            for j in range(first, n):
                if len(todo) >= free:
                    break
                if j in results or j in busy or (j != first and shadow[j]):
                    continue
                if j != first and any(same_orbit(seeds[i], seeds[j]) for i in busy):
                    continue  # a symmetric image of a seed in flight: its family
                if j not in checked:
                    checked.add(j)
                    got = stored("follow", args[j], c)
                    if got is not None:
                        add(j, got, False)
                        hit = True
                        continue
                todo.append(j)
            if hit:
                continue
            if executor is None:
                add(first, execute_task(("follow", args[first], c)), True)
                continue
            for j in todo:
                running[executor.submit(execute_task, ("follow", args[j], c))] = j
            done, _ = wait(list(running), return_when=FIRST_COMPLETED)
            for fut in done:
                j = running.pop(fut)
                out = fut.result()
                finished("follow", args[j], c, out)
                add(j, out, True)
    finally:
        for fut in running:  # speculative follows no longer needed
            fut.cancel()
    fams = []
    for i in chosen:
        f = results[i]
        f["seed_orbit"] = seeds[i]
        f["task"] = keys[i]
        fams.append(f)
    return fams, state["ran"]


def _refine(censuses: dict, depth: int) -> list[float]:
    """Midpoints of neighbouring census energies whose orbit counts differ."""
    Es = sorted(censuses)
    return [
        round((a + b) / 2, 12)
        for a, b in zip(Es, Es[1:])
        if len(censuses[a]) != len(censuses[b]) and b - a > 2.0**-depth
    ]


def by_speed(
    fams: Sequence[dict], grid_E: Sequence[float], rel: float = 0.1, split: int = 4
) -> list[float]:
    """Energies that space the census grid by the families' own speed in ``E``: each
    interval of ``grid_E`` over which a family's period changes by more than ``rel``
    (relative: ``max T / min T - 1`` over its path members in the interval, a fold's two
    branches included) is cut into ``ceil(change / rel)`` equal parts, at most ``split``.

    >>> f = {"path": [{"E": 1 + k / 100, "period": 1 + k / 20} for k in range(101)]}
    >>> by_speed([f], [1.0, 1.5, 2.0], rel=1.0)  # T: 1 to 3.5, then 3.5 to 6
    [1.166666666667, 1.333333333333]
    """
    out = []
    for a, b in zip(grid_E, grid_E[1:]):
        change = 0.0
        for f in fams:
            Ts = [m["period"] for m in f["path"] if a <= m["E"] <= b]
            if len(Ts) >= 2:
                change = max(change, max(Ts) / min(Ts) - 1)
        n = min(split, math.ceil(change / rel)) if change > rel else 1
        out += [round(a + (b - a) * k / n, 12) for k in range(1, n)]
    return out


def _switch_args(f: dict, p: dict, lo: float, hi: float, t_max: float, grid: int):
    """The ``switch`` task of a located ``IS`` / ``PD`` point or a ``touch`` ``p`` of
    family ``f``, or ``None`` (outside the window, or ``n T_b > t_max``): ``n = 2`` at a
    ``PD`` point and a touch of ``tr M = 0``, else 1."""
    n = 2 if p["kind"] == "PD" or (p["kind"] == "touch" and p["level"] == 0) else 1
    if not lo <= p["E"] <= hi or n * p["period"] > t_max:
        return None
    # dE: 0.3 of the family's local step in E (its speed), within [1e-3, 1e-2]
    k = min(max(p["index"], 0), len(f["path"]) - 2)
    step = abs(f["path"][k + 1]["E"] - f["path"][k]["E"])
    dE = min(max(0.3 * step, 1e-3), 1e-2)
    Es = [round(p["E"] + s * dE, 12) for s in (-1, 1)]
    return {
        # inside the window (a seed outside would give a stub of a family cut there)
        # and the census's domain
        "energies": [e for e in Es if max(lo, E_DOMAIN[0]) <= e <= hi],
        "period": n * p["period"],
        "rel": 0.03,
        "t_max": min(t_max, 1.05 * n * p["period"]),
        "grid": grid,
    }


def _checked_polish(m: dict, p: dict) -> dict:
    """The polish ``p`` of the path member ``m``, or a failure when the re-solve
    converged to another orbit (its period more than 1e-6 from the member's: the
    float64 member is good to ~1e-10)."""
    if "failed" in p:
        return p
    T = float(p["period_str"])
    if not near(T, m["period"], 1e-6):
        return {
            "failed": f"the re-solve converged to another orbit: period {T:.12g} "
            f"against the member's {m['period']:.12g}"
        }
    return p


def is_new_daughter(o: dict, fams: Sequence[dict]) -> bool:
    """Whether an orbit a ``switch`` task found lies on none of ``fams`` (:func:`covers`),
    not even as a parent traversed twice (three times): the seed of a new family."""
    return not any(covers(f, o) for f in fams) and not any(
        on_family(f, dict(o, period=o["period"] / r), 1e-6, math.inf)
        for f in fams
        for r in (2, 3)
    )


def switch_jobs(
    fams: Sequence[dict],
    bands: Sequence[tuple[float, float]],
    lo: float,
    hi: float,
    grid: int,
) -> tuple[list[dict], list[tuple[list, float]]]:
    """The ``switch`` tasks of the located ``IS`` / ``PD`` points and the touches of
    ``fams`` and their owners ``([family task, kind, E_b], T_max)``. ``T_max`` is the
    smaller of the family's bound and the census's bound at ``E_b``: a daughter is
    sought, and followed, in the scope where it is born. A touch (``tr M`` reaching 4 or
    0 without a change of stability) is a bifurcation too: a pair of daughters is born
    or dies there (CG's touch of 0 at E = 4.6869 gives CZ1 and CZ2); the touches
    switched at are those the float64 path shows
    (:func:`~rotorlib.beyond.catalogue_points.special_points`)."""
    jobs, owners = [], []
    for f in fams:
        for p in f["special"]:
            if p["kind"] in ("IS", "PD", "touch"):
                T = min(f["t_max"], period_bound(bands, p["E"]))
                a = _switch_args(f, p, lo, hi, T, grid)
                if a is not None and a["energies"]:
                    jobs.append(a)
                    owners.append(([f.get("task"), p["kind"], p["E"]], T))
    return jobs, owners


def build(
    energies: Sequence[float],
    t_max: float | Sequence[tuple[float, float]],
    cache: str | os.PathLike,
    grid: int = 300,
    step: float = 0.01,
    refine: int = 1,
    digits: int = 30,
    name: bool = True,
    max_steps: int | None = None,
    executor: Executor | None = None,
    progress: bool = False,
    log=None,
    switch: int = 2,
    speed: float = 0.1,
) -> dict:
    """The catalogue of the families met by censuses at ``energies`` (the build window is
    their range), ``T <= t_max``: ``{'families': [...], 'censuses': {E: [...]},
    'window': (lo, hi), 'tasks': {kind: (total, run)}, 'cpu': {kind: s}}``.

    ``t_max``: one period bound, or bands ``[(E_hi, T_max), ...]`` (:func:`bands_of`):
    the census at ``E`` seeks ``T <= period_bound(bands, E)``, and each census orbit is
    followed over the whole window until its period passes that bound (a daughter: its
    parent's). The seeds of the larger bounds are followed first, so that a family is
    recorded as far as its largest bound takes it.

    ``max_steps`` (per direction; default: enough for a family that spans the window in
    steps of ``step`` in ``E``, the engine's steps being relative to ``E``);
    ``switch``: rounds of branch switching (``0``: none); ``speed``: the relative
    period change that a census interval may hold (:func:`by_speed`; ``0``: none).
    See the module docstring."""
    energies = sorted(float(e) for e in energies)
    if not energies or energies[0] <= 0 or energies[-1] > 8:
        raise ValueError(f"energies must lie in 0 < E <= 8, got {energies!r}")
    lo, hi = energies[0], energies[-1]
    bands = bands_of(t_max, hi)
    T_top = max(t for _, t in bands)
    if max_steps is None:
        max_steps = default_max_steps(lo, hi, step)
    say = log or (lambda s: None)
    kinds = (
        "census",
        "follow",
        "switch",
        "beyond",
        "densify",
        "polish",
        "locate",
        "fold",
        "touch",
    )
    ran: dict[str, list[int]] = {k: [0, 0] for k in kinds}
    cpu: dict[str, dict[str, float]] = {k: {} for k in kinds}

    def run(kind, argss, desc):
        res, n = run_tasks(
            [(kind, a) for a in argss], cache, executor, progress, desc, cpu[kind]
        )
        ran[kind][0] += len(argss)
        ran[kind][1] += n
        return res

    def do_census(Es):
        extra = {} if name else {"name": False}
        args = [
            {"E": E, "t_max": period_bound(bands, E), "grid": grid, **extra} for E in Es
        ]
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
    follow_E = list(grid_E)  # the energies every follow lands on (its task key)

    def follow_args(o):
        return {
            "seed": {k: v for k, v in o.items() if k != "t_max"},
            "E_range": [lo, hi],
            "t_max": o["t_max"],
            "step": step,
            "energies": follow_E,
            **({} if max_steps == 600 else {"max_steps": max_steps}),
        }

    def follow(seeds, known, desc):
        bar = progress_bar(len(seeds), desc, progress)
        try:
            got, n = wavefront(
                seeds, follow_args, cache, executor, cpu["follow"], bar, known
            )
        finally:
            if bar is not None:
                bar.close()
        ran["follow"][0] += len(got)
        ran["follow"][1] += n
        return got

    def grow(fresh, desc):
        """The new families followed from ``fresh`` (known: ``fams``), classified."""
        new = follow(fresh, fams, desc) if fresh else []
        for f in new:
            f["special"] = special_points(f)
        return new

    def marked(Es):
        """The census orbits at ``Es`` as seeds, each with its census's bound, the
        larger bounds first (a stable sort: within one bound, in (E, index) order)."""
        out = [dict(o, t_max=period_bound(bands, E)) for E in Es for o in censuses[E]]
        return sorted(out, key=lambda o: -o["t_max"])

    seeds = marked(grid_E)
    fams = follow(seeds, (), "follow")
    for f in fams:
        f["special"] = special_points(f)
    say(f"{len(seeds)} census orbits, {len(fams)} families")
    if speed:  # the grid spaced by the families' speed: censuses between, new seeds
        extra = [E for E in by_speed(fams, grid_E, speed) if E not in censuses]
        got = do_census(extra)
        for E in extra:
            censuses[E] = [dict(o, via=["speed"]) for o in got[E]]
        grid_E = sorted(censuses)
        fresh = [o for o in marked(extra) if not any(covers(f, o) for f in fams)]
        new = grow(fresh, "speed")
        say(
            f"spaced by speed: census at {len(extra)} energies, {len(fresh)} orbits "
            f"on no family, {len(new)} new families"
        )
        fams += new

    def tally(log: list, what: str, n: int, unit: str, fresh: list, new: list) -> bool:
        """Log a round of new seeds and add its families; True when it found none."""
        say(f"{what}: {n} {unit}, {len(fresh)} new orbits, {len(new)} new families")
        log.append({"tasks": n, "new_orbits": len(fresh), "new_families": len(new)})
        fams.extend(new)
        return not new

    # past the zigzags (beyond_jobs): a seed on no family there (the other branch of a
    # fold the engine crossed in its zigzag) is followed, for up to 3 rounds
    new, beyond = fams, list[dict]()
    for rnd in range(3):
        jobs, owners = beyond_jobs(new, lo, hi)
        found = [
            dict(o, via=via, t_max=T)
            for (via, T), orbs in zip(owners, run("beyond", jobs, "beyond"))
            for o in orbs
        ]
        fresh = [o for o in found if is_new_daughter(o, fams)]
        new = grow(fresh, f"beyond {rnd + 1}")
        for g in new:  # the record whose zigzag end it was found beyond
            o = min(fresh, key=lambda o: abs(o["E"] - g["seed"]["E"]))
            g.update(cut_beyond(g, o["via"][2]))
            g["beyond_of"] = {"task": o["via"][0], "E": o["via"][2]}
        if tally(beyond, f"beyond {rnd + 1}", len(jobs), "zigzag ends", fresh, new):
            break
    new = fams
    rounds: list[dict] = []  # per switch round: its tasks, new orbits, new families
    for rnd in range(switch):
        jobs, owners = switch_jobs(new, bands, lo, hi, grid)
        found = []
        for (via, T), orbs in zip(owners, run("switch", jobs, f"switch {rnd + 1}")):
            # the census's section search bound for the switch's T_max (as a grid
            # seed), which the daughter is followed to
            found += [
                dict(o, via=via, t_half=float(T / 2 * 1.02), t_max=T) for o in orbs
            ]
        found.sort(key=lambda o: (o["E"], o["period"], o["trace"]))
        fresh = [o for o in found if is_new_daughter(o, fams)]
        new = grow(fresh, f"daughters {rnd + 1}")
        if tally(rounds, f"switch {rnd + 1}", len(jobs), "points", fresh, new):
            break
    # one family met from two seeds: keep the one that carries the other's whole path
    seeded = {(f["seed"]["E"], f["seed"]["period"]): f.get("task") for f in fams}
    # no record is dropped while it alone holds a census orbit (the seeds excepted:
    # a dropped follow's seed goes with its host, below)
    fams, dup = drop_contained(
        fams,
        orbits=[
            o
            for E in grid_E
            for o in censuses[E]
            if (o["E"], o["period"]) not in seeded
        ],
    )
    if dup:
        say(f"{len(dup)} families lay on another's path and were dropped")
    # a record that turned at a fold onto another's branch keeps its own side only
    for t, h, E in cut_at_switch(fams):
        say(f"a path turned onto another record's branch at E = {E:.10g}: cut there")
    host = {t: hs[0] for t, hs in dup}
    by_task = {f.get("task"): f for f in fams}
    for f in fams:
        f.pop("_by_E", None)
        f.pop("_seg", None)
    # each census orbit in exactly one family: the first that covers it
    for f in fams:
        f["census"] = []
    orphans: list[dict] = []
    for E in grid_E:
        for o in censuses[E]:
            f = next((f for f in fams if covers(f, o)), None)
            if f is None:  # its own follow was dropped, and no step lands on its E
                f = next((f for f in fams if on_family(f, o)), None)
            if f is None:  # where T(E) is too steep to interpolate: the dropped
                t = seeded.get((o["E"], o["period"]))  # follow's host holds it
                while t in host:
                    t = host[t]
                f = by_task.get(t) if t is not None else None
            (orphans if f is None else f["census"]).append(o)
    for f in fams:
        f.pop("_by_E", None)
        f.pop("_seg", None)
    owned: dict[int, set[str]] = {}  # the tasks of each family after its follow
    densified = densify(fams, run, owned)
    if densified:
        say(f"path members added where the interpolant was not shown: {densified}")
    # stored members (the special points, the seed, the path members that interpolation
    # needs), re-solved to 30 digits; where a path's float64 members disagree with their
    # re-solves it is cut (cut_untrusted) and its members are chosen again
    for f in fams:  # a fold the engine stopped at unlocated: for the fold task
        f["special"] = sorted(f["special"] + end_folds(f), key=lambda p: p["index"])
    todo, rnd, cut = list(range(len(fams))), 0, set()
    while todo:
        jobs, owner = [], []
        for i in todo:
            fams[i]["stored"] = stored_members(fams[i])
            for m in fams[i]["stored"]:
                jobs.append(
                    {
                        "problem": fams[i]["problem"],
                        "factor": fams[i]["factor"],
                        "u": m["u"],
                        "E_str": repr(m["E"]),
                        "digits": digits,
                    }
                )
                owner.append(i)
        pol = iter(run("polish", jobs, "polish"))
        for i in todo:
            for m in fams[i]["stored"]:
                m["polish"] = _checked_polish(m, next(pol))
        for a, i in zip(jobs, owner):
            owned.setdefault(i, set()).add(task_key("polish", a))
        rnd += 1
        todo = [i for i in todo if rnd < 4 and cut_untrusted(fams[i])]
        cut |= set(todo)
    for i in sorted(cut):  # census orbits past a cut: on no family now (a failure)
        f, kept = fams[i], list[dict]()
        for o in f["census"]:
            (kept if holds(f, o) else orphans).append(o)
        f["census"] = kept
        f.pop("_by_E", None)
        f.pop("_seg", None)
    if cut:
        say(f"{len(cut)} paths cut where float64 disagrees with 30 digits")
    # the IS, PD and fold points located again, and the touches the float64 path misses,
    # at `digits` digits (catalogue_points)
    for i, keys in relocate_points(fams, run, digits).items():
        owned[i] |= keys
    for i, keys in find_touches(fams, run, digits, say).items():
        owned[i] |= keys
    # the cost of each family: its follow and its 30-digit tasks, by kind
    for i, f in enumerate(fams):
        f["cpu_s"] = {
            "follow": cpu["follow"].get(f["task"], 0.0),
            **{
                k: sum(cpu[k].get(x, 0.0) for x in owned.get(i, ()))
                for k in ("densify", "polish", "locate", "fold", "touch")
            },
        }
    return {
        "families": fams,
        "censuses": censuses,
        "orphans": orphans,
        "window": (lo, hi),
        "t_max": T_top,
        "bands": [list(b) for b in bands],
        "grid": grid,
        "step": step,
        "max_steps": max_steps,
        "tasks": {k: tuple(v) for k, v in ran.items()},
        "switch_rounds": rounds,
        "beyond_rounds": beyond,
        "densify_rounds": densified,
        "cpu": {k: sum(v.values()) for k, v in cpu.items()},
        "cpu_max": {k: max(v.values(), default=0.0) for k, v in cpu.items()},
    }


def densify(fams: list[dict], run: Callable, owned: dict[int, set[str]]) -> list[int]:
    """Add float64 members to the paths of ``fams`` where the interpolant is not shown
    to hold between path members (:func:`rotorlib.beyond.catalogue_members.coarse_gaps`,
    the ``densify`` task), for at most :data:`DENSIFY_ROUNDS` rounds (each may halve
    an interval); ``run(kind, jobs, desc)`` runs the tasks, whose keys are added to
    ``owned`` (by family index). Returns the members added in each round."""
    added: list[int] = []
    for rnd in range(DENSIFY_ROUNDS):
        todo = [(i, g) for i, f in enumerate(fams) if (g := coarse_gaps(f))]
        jobs = [
            {
                "problem": fams[i]["problem"],
                "factor": fams[i]["factor"],
                **{
                    k: [x[n] for x in g] for n, k in ((1, "E"), (2, "u"), (3, "period"))
                },
                # the u pieces' intervals (absent when none: the E-only task keys)
                **({"box": [x[4] for x in g]} if any(x[4] for x in g) else {}),
            }
            for i, g in todo
        ]
        n = 0
        for (i, g), a, res in zip(
            todo, jobs, run("densify", jobs, f"densify {rnd + 1}")
        ):
            owned.setdefault(i, set()).add(task_key("densify", a))
            n += insert_members(fams[i], g, res)
        if not n:
            break
        added.append(n)
    return added


def default_max_steps(lo: float, hi: float, step: float) -> int:
    """Steps per direction for a family spanning ``[lo, hi]``: the engine's steps are
    ``step / max(hi, 1)`` relative to ``E`` (and to ``u``), so crossing ``[lo, hi]`` takes
    ``~ max(hi, 1) / step * ln(hi / lo)`` of them; twice that, plus the steps of a crossing
    at the floor ``E ~ 1`` (``(hi - lo) / step``), and at least 600.

    >>> default_max_steps(5.3, 6.2, 0.01), default_max_steps(0.05, 8.0, 0.01)
    (600, 8916)
    """
    if not (0 < lo <= hi and step > 0):
        raise ValueError(
            f"need 0 < lo <= hi and step > 0, got {lo!r}, {hi!r}, {step!r}"
        )
    s = max(hi, 1.0) / step
    return max(600, math.ceil(2 * s * math.log(hi / lo) + (hi - lo) / step))
