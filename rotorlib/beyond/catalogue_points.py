"""The special points of a catalogued family: their classification along the float64
path (:func:`special_points`), the IS, PD and fold points located again at 30 digits
(:func:`relocate_points`, the ``locate`` and ``fold`` tasks of
:mod:`rotorlib.beyond.catalogue_roots`) and the touches of ``tr M = 4`` that only
the Maslov index of the stored members shows (:func:`find_touches`, the ``touch`` task).
Used by :func:`rotorlib.beyond.catalogue_build.build`.

Precision: float64 locations (the engine's: ``E`` to ~1e-10 relative where ``tr M``
crosses its level steeply; folds 2e-9 to 6e-9 apart where two records share one) are
replaced by 30-digit roots with their error bound (``E_error``: ~1e-25 for IS and PD,
~1e-22 for folds); a touch is located to its final golden-section bracket (~1e-13).
"""

from __future__ import annotations

from collections.abc import Callable

from .catalogue_tasks import task_key

__all__ = ["MARGINAL", "special_points", "end_folds", "relocate_points", "find_touches"]


#: ``|tr M - level|`` below which the float64 path does not resolve the side of the
#: level (4 or 0) that ``tr M`` is on (:func:`special_points`).
MARGINAL = 1e-6


def special_points(f: dict) -> list[dict]:
    """The located special points of a followed family, classified.

    * An ``IS`` point at a fold of the same family (within 1e-6 in ``E`` and one
      member: ``tr M = 4`` at a saddle-node is generic) is the fold, not an ``IS``.
    * Crossings of one level (4 or 0) by ``tr M`` chained by members that all lie within
      :data:`MARGINAL` of it are one run. Two crossings within two members are one
      ``touch`` (the level reached without a change of stability, as
      :func:`rotorlib.beyond.choreo_family.special_points` reports the choreographies'
      touches; the engine sees a touch only as a pair of crossings at rounding level).
      Any other run is one ``marginal`` stretch, from ``E`` to ``E_end`` (path index
      ``index`` to ``index_end``), with its number of ``crossings``: ``tr M`` stays
      within 1e-6 of the level there and float64 does not resolve its side, so its
      sign changes are not bifurcations (an odd number: the stability differs on the
      two sides). Measured at ``T <= 16``: a family born at a fold at E = 4.0575 whose
      ``tr M - 4`` is below 1e-11 over 0.03 in ``E`` (its 30-digit members:
      ``4 + 2e-16`` to ``4 + 1e-5``) gave 39 float64 crossings of 4."""
    pts = [dict(p) for p in f["special"]]
    folds = [p for p in pts if p["kind"] == "fold"]
    out = []
    for p in pts:
        if p["kind"] == "IS" and any(
            abs(p["E"] - q["E"]) < 1e-6 * max(1.0, abs(q["E"]))
            and abs(p["index"] - q["index"]) <= 1
            for q in folds
        ):
            continue  # the fold's own tr M = 4
        out.append(p)
    path = f["path"]
    level = {"IS": 4.0, "PD": 0.0}

    def flat(p: dict, q: dict) -> bool:
        between = path[p["index"] + 1 : q["index"] + 1]
        return all(abs(m["trace"] - level[p["kind"]]) < MARGINAL for m in between)

    runs: list[list[dict]] = []
    for p in out:
        last = next((r for r in reversed(runs) if r[-1]["kind"] == p["kind"]), None)
        if (
            p["kind"] in level
            and last is not None
            and p["index"] >= last[-1]["index"]
            and flat(last[-1], p)
        ):
            last.append(p)
        else:
            runs.append([p])
    kept = []
    for r in runs:
        p = r[0]
        if len(r) == 1:
            kept.append(p)
        elif len(r) == 2 and r[1]["index"] - p["index"] <= 2:
            kept.append(dict(p, kind="touch", level=level[p["kind"]]))
        else:
            i, j = p["index"], r[-1]["index"]
            Es = [q["E"] for q in r] + [m["E"] for m in path[i + 1 : j + 1]]
            kept.append(
                dict(
                    p,
                    kind="marginal",
                    level=level[p["kind"]],
                    E=min(Es),
                    E_end=max(Es),
                    index_end=j,
                    crossings=len(r),
                )
            )
    return kept


def end_folds(f: dict) -> list[dict]:
    """The folds the engine stopped at without locating them: at each end of ``f``
    whose stop is ``fold`` (not a zigzag's cut) with no fold point within two members
    of it, the end member as a float64 fold point, for the ``fold`` task of
    :func:`relocate_points` to locate at 30 digits (or refuse, with the reason).

    Measured at ``T <= 16``: the record of PD^l_1 ended 1.5e-7 in ``E`` from its birth
    at the pendulum's touch of ``tr M = 0``, where the engine stopped at a fold it did
    not locate, and its members there have no 30-digit root at fixed ``E``.

    >>> path = [{"E": 1.0 + k / 10, "u": k} for k in range(4)]
    >>> ends = [{"stop": "fold"}, {"stop": "period"}]
    >>> [(p["kind"], p["index"]) for p in end_folds({"path": path, "ends": ends,
    ...                                              "special": []})]
    [('fold', 0)]
    """
    out = []
    for side, e in enumerate(f["ends"]):
        j = 0 if side == 0 else len(f["path"]) - 1
        if e.get("stop") != "fold" or e.get("zigzag"):
            continue
        if not any(
            p["kind"] == "fold" and abs(p["index"] - j) <= 2 for p in f["special"]
        ):
            out.append(dict(f["path"][j], kind="fold", index=j))
    return out


def relocate_points(
    fams: list[dict], run: Callable, digits: int
) -> dict[int, set[str]]:
    """Locate the IS, PD and fold points among the stored members of ``fams`` again at
    ``digits`` digits (``run(kind, jobs, desc)`` runs the tasks: ``locate`` for IS and
    PD, a root of ``tr M - level`` in ``E``; ``fold`` for a fold, the extremum of ``E``
    in the shooting unknown ``u`` within ``u_f -+ h``, ``h`` the farthest in ``u`` of
    the path members from two before to three after it: the bracket holds the fold
    where the engine's float64 ``u_f`` is off, or the path ends at the fold). A located
    point takes the root's energy, period, ``tr M`` and ``state0`` (its float64 ``x0``
    the rounding of the 30-digit one; a fold also its ``u``). A point whose
    re-location fails, or lands more than 1e-6 away, keeps its float64 location with
    the reason (``location``), except a fold where ``E(u)`` is monotone across the
    bracket at 30 digits: that is no fold (``_not_a_fold``). Returns the task keys
    of each family (by index)."""
    keys: dict[int, set[str]] = {}
    for kind, point_kinds in (("locate", ("IS", "PD")), ("fold", ("fold",))):
        pts = [
            (i, m)
            for i in range(len(fams))
            for m in fams[i]["stored"]
            if m["kind"] in point_kinds
            and (kind == "fold" or "failed" not in m["polish"])
        ]
        jobs = []
        for i, m in pts:
            a = {"problem": fams[i]["problem"], "factor": fams[i]["factor"]}
            if kind == "fold":
                path, j = fams[i]["path"], m["index"]
                h = max(abs(q["u"] - m["u"]) for q in path[max(0, j - 2) : j + 4])
                a |= {"u": [m["u"] - h, m["u"] + h], "E": m["E"]}
            else:
                a |= {"kind": m["kind"], "u": m["u"], "E": m["E"]}
            jobs.append(a | {"digits": digits})
        for (i, m), a, r in zip(pts, jobs, run(kind, jobs, kind)):
            keys.setdefault(i, set()).add(task_key(kind, a))
            if "failed" not in r and abs(r["moved"]) > 1e-6 * max(1.0, abs(m["E"])):
                r = {"failed": f"the 30-digit root lies {r['moved']:.1e} away"}
            if "failed" in r and kind == "fold" and "no fold there" in r["failed"]:
                _not_a_fold(fams[i], m, r["failed"])
                continue
            if "failed" in r:
                m["location"] = f"float64 ({r['failed']})"
                continue
            m["E64"] = m["E"]
            m["E"], m["E_str"], m["E_error"] = (
                float(r["E_str"]),
                r["E_str"],
                r["E_error"],
            )
            m["period"], m["trace"] = float(r["period_str"]), float(r["trace_str"])
            m["x0"] = [float(v) for v in r["state0_str"]]
            if kind == "fold":  # the fold's own u (the float64 one is not on the root)
                m["u"] = float(r["u_str"])
            m["location"] = f"{digits} digits"
            m["polish"] = r
    return keys


def _not_a_fold(f: dict, m: dict, why: str) -> None:
    """Drop the float64 fold ``m`` of ``f`` that the 30-digit ``fold`` task finds no
    extremum of ``E`` at (``why``). Where the path was cut at it
    (:func:`~rotorlib.beyond.catalogue_paths.cut_at_reversal`: a fold past which the
    engine's steps zigzag) the end becomes that cut's ``reversal``: the engine's steps
    turned back there without a fold, and the family goes on beyond, unfollowed.

    Why: measured at ``T <= 16``, a family with ``tr M ~ -660`` at E = 4.6784 had a
    float64 fold inside the engine's zigzag; at 30 digits ``E(u)`` rises monotonically
    across it."""
    f["special"] = [p for p in f["special"] if p is not m]
    f["stored"] = [q for q in f["stored"] if q is not m]
    n = len(f["path"])
    side = 1 if m["index"] >= n - 5 else 0 if m["index"] <= 4 else None
    if side is not None and f["ends"][side].get("stop") == "fold":
        f["ends"][side] = {
            **f["ends"][side],
            "stop": "reversal",
            "reason": (
                "reversal: the path turns back in E at E = "
                f"{f['path'][-1 if side else 0]['E']:.10g}, where the engine's steps "
                f"zigzag; the float64 fold it located at E = {m['E']:.10g} is none at "
                f"30 digits ({why[:120]}): cut there, the family goes on beyond"
            ),
        }


def find_touches(
    fams: list[dict], run: Callable, digits: int, say: Callable[[str], None]
) -> dict[int, set[str]]:
    """Add to the special points of ``fams`` the touches of ``tr M = 4`` the float64
    path misses: where the Maslov index of two consecutive stored members differs, with
    ``tr M`` on one side of 4 at both and no special point between, the ``touch`` task
    finds the extremum of ``tr M`` between them; one within 1e-12 of 4 is a ``touch``
    (``location`` says how it was found), another is reported through ``say``. Returns
    the task keys of each family (by index)."""
    keys: dict[int, set[str]] = {}
    cand, jobs = [], []
    for i, f in enumerate(fams):
        ms = sorted(
            (m for m in f["stored"] if m["polish"].get("maslov") is not None),
            key=lambda m: m["index"],
        )
        for a, b in zip(ms, ms[1:]):
            ta, tb = float(a["polish"]["trace_str"]), float(b["polish"]["trace_str"])
            if (
                a["polish"]["maslov"] != b["polish"]["maslov"]
                and (ta - 4) * (tb - 4) > 0
                and a["E"] != b["E"]
                and not any(
                    p["index"] <= b["index"]
                    and p.get("index_end", p["index"]) >= a["index"]
                    for p in f["special"]
                )
            ):
                cand.append((i, a))
                jobs.append(
                    {
                        "problem": f["problem"],
                        "factor": f["factor"],
                        "E": [a["E"], b["E"]],
                        "u": [a["u"], b["u"]],
                        "level": 4,
                        "below": ta < 4,
                        "digits": digits,
                    }
                )
    for (i, a), job, r in zip(cand, jobs, run("touch", jobs, "touch")):
        keys.setdefault(i, set()).add(task_key("touch", job))
        if "failed" in r or abs(r["gap"]) > 1e-12:
            why = r.get("failed") or f"tr M - 4 = {r['gap']:.1e} at its extremum"
            say(f"a Maslov index change at E = {a['E']:.10g} not explained: {why}")
            continue
        fams[i]["special"].append(
            {
                "kind": "touch",
                "level": 4.0,
                "E": float(r["E_str"]),
                "E_str": r["E_str"],
                "E_error": r["E_error"],
                "period": float(r["period_str"]),
                "trace": float(r["trace_str"]),
                "index": a["index"],
                "location": f"{digits} digits (where the Maslov index changes)",
            }
        )
        fams[i]["special"].sort(key=lambda p: p["index"])
    return keys
