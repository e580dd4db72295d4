"""The choreography census (rotorlib.beyond.choreo_census) and CG's island
(rotorlib.beyond.choreo_island): small runs checked against the families and the stored
data products."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from rotorlib.api import REGISTRY
from rotorlib.beyond.choreo import choreography_of
from rotorlib.beyond.choreo_census import agreement_period, census
from rotorlib.beyond.choreo_s import cs_orbits

DATA = Path(__file__).resolve().parents[1] / "book" / "data"


def test_census_finds_cr1_and_cs_in_the_band():
    """At E = 5.45 with T <= 17: CR1 (rotating, Z3) and CS (D6), both on their families."""
    c = census(5.45, 17.0, 200)
    assert [(o.sixth, o.rotating) for o in c] == [(False, True), (True, False)]
    cs = c[1]
    assert abs(cs.period - cs_orbits(5.45)[0].period) < 1e-9
    chor = choreography_of(cs.state0, cs.period)
    assert chor is not None and chor.sixth and not chor.rotating
    # the front door names it (CG and CT tried first; the Z3 rows, ~20 s each, are
    # skipped here by asking only the rows that serve D6 choreographies)
    assert [
        lab
        for lab in ("CG", "CT", "CS")
        if any(
            abs(T - cs.period) < 1e-7 * T
            for T in REGISTRY[lab].periods(lab, 5.45, chor)
        )
    ] == ["CS"]
    assert all(o.stability == "unstable" for o in c)


def test_agreement_period():
    a = census(5.45, 17.0, 200)
    assert agreement_period(a, a) == math.inf
    assert agreement_period(a[:1], a) == pytest.approx(a[1].period)


@pytest.mark.parametrize(
    "args", [(math.nan, 10.0, 100), (5.4, -1.0, 100), (5.4, 10, 3)]
)
def test_census_refuses_bad_input(args):
    with pytest.raises(ValueError, match="census needs"):
        census(*args)


def test_stored_census_t50():
    """The stored census: three energies, two grids, CS named at each energy with its
    family's period, and the finer grid contains the coarser one's orbits."""
    data = json.loads((DATA / "choreo_census_T50.json").read_text())
    assert [r["E"] for r in data["census"]] == [5.33, 5.45, 5.6]
    for r in data["census"]:
        n1, n4 = r["n_orbits"]
        assert n4 >= n1 and 16 < r["complete_to"] <= 50
        cs = [o for o in r["orbits"] if o["label"] == "CS"]
        assert len(cs) == 2
        for o in cs:
            assert min(abs(m.period - o["period"]) for m in cs_orbits(r["E"])) < 1e-8


def test_island_against_the_stored_value():
    """A coarser island at E = 5.2 agrees with the stored one within their uncertainties."""
    from rotorlib.beyond.choreo_island import island_area

    data = json.loads((DATA / "choreo_island.json").read_text())
    (rec,) = [r for r in data["islands"] if r["E"] == 5.2]
    r = island_area(5.2, n=15)
    assert abs(r.area - rec["area"]) < 2 * (r.area_err + rec["area_err"])
    assert r.area_err < 0.2 * r.area
    with pytest.raises(ValueError):
        island_area(5.4)  # above CG's fold
