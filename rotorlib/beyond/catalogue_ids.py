"""Record ids that stay the same across builds of the catalogue
(:func:`rotorlib.beyond.catalogue_files.write`).

A researcher cites a family by its id (``F013`` is CG), so a rebuild that finds one more
family must not renumber the others. Without an earlier catalogue the records are
numbered in order of their shortest period (then their seed's energy); with one, a
record keeps the id of the earlier record whose census orbits it holds, and a record
holding none of them takes the next id after the earlier ones.
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from pathlib import Path

__all__ = ["previous_census", "assign_ids"]


def previous_census(path: str | os.PathLike) -> dict[str, list[tuple[float, float]]]:
    """The census orbits ``(E, period)`` of each record of the catalogue in ``path``
    (its ``F*.json`` files) and its seed (a record found off the censuses has only
    that), by id; ``{}`` where there is none."""
    out = {}
    for fn in sorted(Path(path).glob("F*.json")):
        rec = json.loads(fn.read_text())
        seed = [
            m for m in rec["members"] if m["kind"] == "seed"
        ]  # off the censuses too
        out[rec["id"]] = [(o["E"], o["period"]) for o in rec["census_orbits"] + seed]
    return out


def assign_ids(
    fams: Sequence[dict], previous: dict[str, list[tuple[float, float]]] | None = None
) -> None:
    """Set ``f['id']`` on each of ``fams`` (given in the order of fresh numbering).

    With ``previous`` (:func:`previous_census` of an earlier catalogue): each earlier
    id goes to the family holding most of its census orbits and seed (the same energy
    to 1e-9 and period to 1e-7 relative; a family's own: its ``census`` and ``seed``), the families holding more claiming first; the other
    families take ``F<n>`` past the largest earlier id, in their order. An earlier id
    no family holds is not given again.

    Examples
    --------
    >>> a = {"census": [{"E": 4.3, "period": 6.0}]}
    >>> b = {"census": []}
    >>> c = {"census": [{"E": 4.4, "period": 9.0}]}
    >>> assign_ids([a, b, c], {"F001": [(4.4, 9.0)], "F002": [(4.3, 6.0)]})
    >>> a["id"], b["id"], c["id"]
    ('F002', 'F003', 'F001')
    >>> assign_ids([a, b, c])
    >>> a["id"], b["id"], c["id"]
    ('F001', 'F002', 'F003')
    """
    previous = previous or {}

    def held(f: dict, orbits: list[tuple[float, float]]) -> int:
        return sum(
            any(
                abs(o["E"] - E) < 1e-9 and abs(o["period"] / T - 1) < 1e-7
                for E, T in orbits
            )
            for o in f["census"] + ([f["seed"]] if "seed" in f else [])
        )

    claims = sorted(
        (-held(f, orbits), k, fid)
        for k, f in enumerate(fams)
        for fid, orbits in previous.items()
    )
    ids: dict[int, str] = {}
    for n, k, fid in claims:
        if n < 0 and k not in ids and fid not in ids.values():
            ids[k] = fid
    last = max((int(fid[1:]) for fid in previous), default=0)
    for k, f in enumerate(fams):
        if k not in ids:
            last += 1
            ids[k] = f"F{last:03d}"
        f["id"] = ids[k]
