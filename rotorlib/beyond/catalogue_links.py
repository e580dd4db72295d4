"""Parent and daughter links between the catalogue's records
(:func:`link_families`, called by :func:`rotorlib.beyond.catalogue_files.write`): the
daughters at each genuine IS / PD point, the families that join at an engine stop or
past a zigzag end, the two records of a saddle-node (``fold_twins``) and the daughters
born where the parent's record shows nothing (``_born_at_folds``).

Precision: the links are found on the float64 paths (linear interpolation between path
members, to the tolerances each function states) and on the 30-digit special points.
"""

from __future__ import annotations

from .catalogue_tasks import near

__all__ = ["link_families"]


def _brackets(path: list[dict], E: float, strict: bool = False):
    """``(i, period, tr M)`` at energy ``E`` on each pair of consecutive path members
    ``i, i + 1`` that bracket it (``strict``: ``E`` strictly between them), interpolated
    linearly."""
    for i, (a, b) in enumerate(zip(path, path[1:])):
        lo, hi = sorted((a["E"], b["E"]))
        if (lo < E < hi) if strict else (lo <= E <= hi and lo != hi):
            t = (E - a["E"]) / (b["E"] - a["E"])
            T = a["period"] + t * (b["period"] - a["period"])
            yield i, T, a["trace"] + t * (b["trace"] - a["trace"])


def _at(g: dict, E: float, dE: float = 1e-3) -> list[tuple[float, float]]:
    """``(period, tr M)`` of family ``g`` at energy ``E``: interpolated (linearly) on each
    pair of consecutive path members that bracket ``E``, and at its path members and
    located points within ``dE`` of ``E`` (a daughter born at a fold that the engine did
    not locate has its nearest member ``~ (du)^2`` away)."""
    out = [(T, tr) for _, T, tr in _brackets(g["path"], E)]
    out += [
        (p["period"], p["trace"])
        for p in g["path"] + g["special"]
        if abs(p["E"] - E) < dE
    ]
    return out


def _joins(fams: list[dict]) -> None:
    """``f['joins']``: the families whose path ends where one of ``f``'s ends (an engine
    stop) with the same orbit up to the symmetries (``E`` to 1e-6, the period to 1e-6
    relative, ``tr M`` to 1e-4 relative; the two records may start it on different
    fixed sets): one family that the engine could not carry across an energy (its
    shooting problem's start set changes at 4 and 4.5). Also two records that both
    stop (``stuck``) facing each other across a gap (``E`` to 1e-3, the period to 1e-3,
    ``tr M`` to 1e-2 relative), with the ``gap`` in ``E``; or found past a zigzag end."""
    for f in fams:
        f["joins"] = []
    by_task = {g.get("task"): g for g in fams}
    for g in fams:  # found past a zigzag end of f (the build's `beyond` task)
        if (b := g.get("beyond_of")) and (h := by_task.get(b["task"])) is not None:
            end = int(
                abs(h["path"][-1]["E"] - b["E"]) < abs(h["path"][0]["E"] - b["E"])
            )
            h["joins"].append({"id": g["id"], "E": b["E"], "side": end, "beyond": True})
    for f in fams:
        for side in (0, 1) if "ends" in f else ():
            if f["ends"][side]["stop"] not in ("stuck", "section lost"):
                continue
            m = f["path"][0 if side == 0 else -1]
            for g in fams:
                if g is f:
                    continue
                for gs, q in enumerate((g["path"][0], g["path"][-1])):
                    if (
                        abs(q["E"] - m["E"]) < 1e-6
                        and near(q["period"], m["period"], 1e-6)
                        and near(q["trace"], m["trace"], 1e-4)
                    ):
                        f["joins"].append({"id": g["id"], "E": m["E"], "side": side})
                    elif (  # both stopped, facing each other across a small gap
                        "ends" in g
                        and g["ends"][gs]["stop"] in ("stuck", "section lost")
                        and abs(q["E"] - m["E"]) < 1e-3
                        and near(q["period"], m["period"], 1e-3)
                        and near(q["trace"], m["trace"], 1e-2)
                    ):
                        f["joins"].append(
                            {
                                "id": g["id"],
                                "E": m["E"],
                                "side": side,
                                "gap": abs(q["E"] - m["E"]),
                            }
                        )


def link_families(fams: list[dict]) -> None:
    """Parent -> daughter links at the genuine ``IS`` / ``PD`` points (folds and touches
    are classified before: :func:`rotorlib.beyond.catalogue_points.special_points`): a
    family that exists at the point's energy ``E_b`` (a member there, interpolated
    between the path members around it, or a member or located point within 1e-3 of it)
    with ``n T_b`` (``n = 1`` at IS, 2 at PD; to 1e-3 relative) and
    ``tr M`` within 0.05 of 4 (the daughter is born with a multiplier 1) is its daughter.
    Each link ``{id, kind, E}`` is recorded on both sides. Also records the families
    that join at an engine stop (``_joins``)."""
    _joins(fams)
    for f in fams:
        f["parents"], f["daughters"] = [], []
    folds = [(g, q) for g in fams for q in g["special"] if q["kind"] == "fold"]
    for f in fams:  # two records that turn at one fold: a family's two branches
        f["fold_twins"] = [
            {"id": g["id"], "E": q["E"]}
            for p in f["special"]
            if p["kind"] == "fold"
            for g, q in folds
            if g is not f
            and abs(q["E"] - p["E"]) < 1e-6 * max(1.0, abs(p["E"]))
            and near(q["period"], p["period"], 1e-6)
        ]
    by_task = {g.get("task"): g for g in fams}
    for f in fams:  # born where the engine turned onto the parent's branch
        sw = f.get("switch_parent")
        if sw and sw["task"] in by_task:
            g, link = by_task[sw["task"]], {"kind": "IS", "E": sw["E"]}
            f["parents"].append({"id": g["id"], **link})
            g["daughters"].append({"id": f["id"], **link})
    for f in fams:
        for p in f["special"]:
            if p["kind"] not in ("IS", "PD"):
                continue
            n = 2 if p["kind"] == "PD" else 1
            for g in fams:
                if g is f or any(
                    d["id"] == g["id"] and d["E"] == p["E"] for d in f["daughters"]
                ):
                    continue
                if any(
                    near(T, n * p["period"], 1e-3) and abs(tr - 4) < 0.05
                    for T, tr in _at(g, p["E"])
                ):
                    link = {"kind": p["kind"], "E": p["E"]}
                    f["daughters"].append({"id": g["id"], **link})
                    g["parents"].append({"id": f["id"], **link})
                    if n == 1:
                        _touch(g, p, f["id"])
    _born_at_folds(fams)


def _born_at_folds(fams: list[dict]) -> None:
    """Daughters born at a point of a parent that the parent's record does not show: a
    fold of ``f`` (located at 30 digits: ``E_str``) where another record ``g`` (not a
    fold twin) passes through the point (its path beyond 1e-5 relative on both sides:
    the other branch of a saddle-node, with the same period and ``tr M = 4`` there,
    turns at it) with ``n T_g = T_f`` (1e-4 relative) and ``tr M`` within 1e-2 of 4
    (``n = 1``: a pitchfork where ``g``'s ``tr M`` reaches 4 without crossing it) or of
    0 (``n = 2``: a period doubling where it reaches 0). ``E(u)`` of a daughter is
    extremal at its birth (``E - E_b ~ u^2``), which the build sees as a fold; the link
    (``IS`` or ``PD``) is recorded both ways and ``g`` gets a ``touch`` of that level
    there. A record without a parent whose path ends within 1e-6 relative of such a
    point, with its period (1e-5), is born there too and linked the same way (its
    float64 path may end short of the point, with no fold located).

    Why: measured at ``T <= 16``, the records F022/F023 and CZ1/CZ2 each meet at one
    "fold" (agreeing to 1e-21 at 30 digits) where CG has ``tr M = 4.00000004`` and
    ``tr M = 1e-9`` (interpolated) with the daughters' period and half of it: CG's
    touch of 4 at E = 5.2450174718 and of 0 at E = 4.6869032814. The tolerances are
    those of ``g``'s path interpolated linearly (``_at``): 1.5e-5 in the period and
    6e-4 in ``tr M`` for CG there, where its members lie 0.023 apart in E. PD^l_1's
    record ends 1.5e-7 below its birth at the pendulum's touch of 0 (its float64
    members within 1e-9 of it have no 30-digit root at fixed E)."""
    births = []
    span = {
        g["id"]: (min(m["E"] for m in g["path"]), max(m["E"] for m in g["path"]))
        for g in fams
    }
    for f in fams:
        twins = {t["id"] for t in f["fold_twins"]}
        for p in f["special"]:
            if p["kind"] != "fold" or "E_str" not in p:
                continue
            for g in fams:
                lo, hi = span[g["id"]]
                if (
                    g is f
                    or g["id"] in twins
                    or not lo < p["E"] * (1 - 1e-5) < p["E"] * (1 + 1e-5) < hi
                ):  # a parent passes through the point; a fold twin turns there
                    continue
                for n, level, kind in ((1, 4.0, "IS"), (2, 0.0, "PD")):
                    if not any(
                        near(n * T, p["period"], 1e-4) and abs(tr - level) < 1e-2
                        for T, tr in _at(g, p["E"])
                    ):
                        continue
                    births.append((p, g, kind))
                    _link(g, f, {"kind": kind, "E": p["E"]})
                    _touch(g, dict(p, period=p["period"] / n), f["id"], level)
    for p, g, kind in births:  # records whose path ends at the point, unlinked
        for f in fams:
            if f is g or f["parents"]:
                continue
            if any(
                abs(m["E"] - p["E"]) < 1e-6 * p["E"]
                and near(m["period"], p["period"], 1e-5)
                for m in (f["path"][0], f["path"][-1])
            ):
                _link(g, f, {"kind": kind, "E": p["E"]})


def _link(g: dict, f: dict, link: dict) -> None:
    """Record ``g`` as ``f``'s parent at ``link`` (``{kind, E}``) and ``f`` as ``g``'s
    daughter, once."""
    if {"id": g["id"], **link} not in f["parents"]:
        f["parents"].append({"id": g["id"], **link})
        g["daughters"].append({"id": f["id"], **link})


def _touch(g: dict, p: dict, via: str, level: float = 4.0) -> None:
    """Record on ``g`` the ``touch`` of ``tr M = level`` (4; 0 for a period doubling,
    ``_born_at_folds``) at the point ``p`` of its link (``via``), where ``g``'s
    path passes through the point's energy without a special point of its own:
    ``tr M - level`` vanishes there to second order (at 4, a pitchfork: the symmetric
    family touches 4 while the other crosses it), so that no sign change shows it, and
    the Maslov index changes by 2 across it (the multipliers pass through 1 along the
    unit circle). Located through the crossing family's root (``E`` to ~1e-12) or the
    daughters' 30-digit birth point; ``period`` and ``tr M`` interpolated on ``g``'s
    path."""
    E = p["E"]
    if any(abs(q["E"] - E) < 1e-6 for q in g["special"]):
        return
    for i, T, tr in _brackets(g["path"], E, strict=True):
        if near(T, p["period"], 1e-3) and abs(tr - level) < 0.05:
            g["special"].append(
                {
                    "kind": "touch",
                    "E": E,
                    "period": T,
                    "trace": tr,
                    "index": i,
                    "level": level,
                    "via": via,
                }
            )
            g["special"].sort(key=lambda q: q["index"])
            return
