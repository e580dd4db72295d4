"""newborn.family: one Branch per IS/PD family over an energy range, members inside it."""

from __future__ import annotations

import json

import pytest

from rotorlib.paper.newborn import FamilyRangeError, family, family_spec, newborn_orbit


def test_members_stay_inside_the_range_and_reach_its_ends():
    b = family("IS^l_1", (3.991, 4.0))
    assert all(3.991 <= E <= 4.0 for E in b.E)
    assert (b.E[0], b.E[-1]) == (3.991, 4.0)  # located at the ends it crosses
    assert b.stop == "E range" and "14 members lie inside E_range" in b.reason
    assert len(b.members) >= 10
    E = list(b.E)
    assert E == sorted(E)


def test_range_containing_the_birth_starts_at_the_seed():
    spec = family_spec("IS^r_1")
    b = family("IS^r_1", (4.0, 4.3))
    assert b.E[0] > spec.E_birth and b.E[-1] == 4.3 and b.E.max() <= 4.3


def test_special_points_and_the_stable_window():
    """tr M = 4 located by the engine; an orbit found independently (continuation in E
    from the seed) at that energy has tr M = 4; the members below it are stable."""
    b = family("IS^l_1", (3.9, 4.1))
    (p,) = b.special_points
    assert p.kind == "IS" and p.located and 3.9 <= p.member.E <= 4.1
    assert abs(float(p.member.trace) - 4) < 1e-6
    o = newborn_orbit("IS^l_1", float(p.member.E))
    assert abs(o.trace - 4) < 1e-5
    k = p.index
    assert all(m.stable for m in b.members[1 : k + 1])
    assert all(not m.stable for m in b.members[k + 1 :])


def test_a_fold_inside_the_range_is_passed_and_located():
    b = family("PD^r_2", (4.52, 4.6))
    f = b.fold
    assert f is not None and abs(float(f.E) - 4.5516743) < 2e-7
    assert b.E.min() >= 4.52 and b.E.max() <= 4.6
    kinds = [p.kind for p in b.special_points]
    assert "fold" in kinds and "IS" in kinds  # tr M = 4 at a fold of E


def test_bad_ranges_are_refused():
    with pytest.raises(FamilyRangeError, match="got E_range = \\(3.9, 3.99\\)"):
        family("IS^l_1", (3.9, 3.99))  # below its birth at 3.9906
    with pytest.raises(FamilyRangeError):
        family("PD^r_1", (6.0, 6.5))  # above its fold at 5.9831
    with pytest.raises(ValueError, match="lo < hi"):
        family("IS^l_1", (4.0, 3.995))
    with pytest.raises(ValueError):
        family("XY^l_1", (3.9, 4.0))


def test_a_range_the_family_does_not_reach_says_so():
    b = family("IS^r_1", (5.8, 6.0))
    assert b.members == () and "no member lies inside E_range = (5.8, 6)" in b.reason


def test_members_and_branch_follow_the_result_protocol():
    b = family("IS^l_1", (3.991, 3.995))
    m = b.members[0]
    assert (m.label, m.E, m.digits, m.precision) == ("IS^l_1", 3.991, 15, "float64")
    assert m.period == 4 * m.t1 and m.state0.shape == (4,)
    assert m.E_str == "3.991" and m.stability == "stable"
    assert abs(m.multipliers[2] * m.multipliers[3] - 1) < 1e-12
    d = json.loads(json.dumps(b.to_dict(), allow_nan=False))
    assert d["label"] == "IS^l_1" and d["E_range"] == [3.991, 3.995]
    assert d["members"][0]["E"] == 3.991 and d["members"][0]["stability"] == "stable"
    assert d["stop"] == b.stop and d["reason"] == b.reason


def test_extended_members_carry_their_digits():
    b = family("IS^l_1", ("3.991", "3.9911"), digits=20)
    m = b.members[0]
    assert m.precision == "real128" and m.digits > 15
    assert m.E_str.startswith("3.99100000000000000")
    d = m.to_dict()
    assert d["E"] == 3.991 and d.get("E_str", "3.991").startswith("3.991")
    assert len(d["state0_str"]) == 4


def test_one_container_for_every_family(capsys):
    """rotorlib.family gives a Branch for a newborn family and a choreography alike, and the
    family command prints both through it (members, then special points)."""
    import rotorlib
    from rotorlib import cli
    from rotorlib.orbits.family import Branch

    for label, E_range in (("IS^l_1", (3.991, 4.0)), ("CG", (5.3, 5.4))):
        b = rotorlib.family(label, E_range)
        assert isinstance(b, Branch) and b.label == label and b.E_range == E_range
        assert all(E_range[0] <= m.E <= E_range[1] for m in b.members)
        assert cli.main(["family", label, "--E-range", *map(str, E_range)]) == 0
        out = capsys.readouterr().out.splitlines()
        assert out[0].startswith(f"{label}: {len(b.members)} members in ")
        assert "special points:" in out[len(b.members) + 2]
    (fold,) = rotorlib.family("CT", (5.3, 5.4)).points("fold")
    assert fold.index == -1 and fold.description == "fold (saddle-node)"
    assert abs(float(fold.member.E) - 5.3153239128) < 1e-10


def test_one_special_point_type_for_every_family():
    """``rotorlib.family("CG", ...)`` and ``rotorlib.family("IS^l_1", ...)`` return
    special points of one type with the same fields, a transition is one too, and each
    serialises to JSON with the same keys."""
    import dataclasses
    import math

    import rotorlib
    from rotorlib.orbits.family import SpecialPoint

    fields = {"kind", "E", "E_str", "member", "located", "description", "rotation"}
    pts = [
        *rotorlib.family("CG", (5, 5.4)).special_points,
        *rotorlib.family("IS^l_1", (3.99, 4.1)).special_points,
    ]
    assert {p.kind for p in pts} >= {"fold", "IS", "touch", "resonance"}
    assert {type(p) for p in pts} == {SpecialPoint}
    names = {f.name for f in dataclasses.fields(SpecialPoint)}
    assert fields | {"families"} <= names
    for p in pts:
        assert (
            isinstance(p.E, float) and math.isfinite(p.E) and p.E == float(p.member.E)
        )
        assert abs(float(p.E_str) - p.E) < 1e-12 and isinstance(p.located, str)
        if p.kind == "resonance":  # CG's resonances: a rotation number, families born
            assert p.rotation and p.families
        else:
            assert p.rotation is None and p.families == ()
        rec = json.loads(json.dumps(p.to_dict(), allow_nan=False))
        assert set(rec) == {*fields, "families", "branch", "index"} - {"E_str"}
        assert rec["E"] == p.E and rec["member"]["E"] == p.E
    t = rotorlib.transition("IS^l_1")
    assert (
        isinstance(t, SpecialPoint) and t.member is None and t.families == ("IS^l_1",)
    )
    assert {f.name for f in dataclasses.fields(t)} >= names
    # a point carries a rotation number and the families born there when given them
    q = SpecialPoint("resonance", pts[0].member, rotation="2/7", families=("X",))
    assert q.to_dict()["rotation"] == "2/7" and q.to_dict()["families"] == ["X"]
    assert q.E == pts[0].E  # E and E_str are the member's
    assert SpecialPoint("fold", None, located=None).to_dict()["member"] is None
