"""The stored members of a catalogued family: which members are stored and their
re-solve to 30 digits (the ``polish`` task of :mod:`rotorlib.beyond.catalogue_tasks`).

Precision: each stored member is re-solved at ``digits = 30`` (heyoka real128):
``state0_str`` and the period to 30 digits, ``tr M`` to 25 digits, the closure error
printed beside them.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

__all__ = ["problem_of", "polish_task", "stored_members"]


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


def stored_members(f: dict) -> list[dict]:
    """The members of a followed family ``f`` to store: its located special points and
    its seed, in path order."""
    stored = list(f["special"])
    if not any(
        abs(m["E"] - f["seed"]["E"]) <= 1e-12 * max(1.0, abs(m["E"])) for m in stored
    ):
        stored.append(f["seed"])
    return sorted(stored, key=lambda m: m.get("index", 0))
