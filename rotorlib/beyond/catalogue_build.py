"""Building the catalogue of periodic-orbit families (:mod:`rotorlib.beyond.catalogue`).

:func:`build` runs the census round, refines the energy grid where the number of census
orbits changes between neighbours (a family born or dying between them), follows the
census orbits energy by energy (an orbit whose family is already catalogued is not
followed again: each census orbit belongs to exactly one family), polishes the stored
members and returns the catalogue in memory; :func:`rotorlib.beyond.catalogue_files.write`
links parents and daughters and writes the files. The tasks and their resumable store:
:mod:`rotorlib.beyond.catalogue_tasks`.

Precision: as the tasks (float64 continuation, members re-solved to 30 digits); the
action ``S = oint p.dq = 2 (E T - int V dt)`` by Simpson's rule on 801 samples (~1e-9
relative). The Maslov index is not computed (its field is ``null``).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from concurrent.futures import Executor

from .catalogue_members import stored_members
from .catalogue_tasks import near, run_tasks

__all__ = ["covers", "build"]


def covers(fam: dict, orb: dict) -> bool:
    """Whether a followed family has a member at the census orbit's energy with its
    period (1e-7 relative) and ``tr M`` (1e-5 relative, at least absolute)."""
    pts = [fam["seed"], *fam["special"], *fam["path"]]
    return any(
        near(m["E"], orb["E"], 1e-10)
        and near(m["period"], orb["period"], 1e-7)
        and near(m["trace"], orb["trace"], 1e-5)
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
        f["stored"] = stored_members(f)
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
