"""The catalogue build engine (rotorlib.beyond.catalogue_build): the wavefront's result
does not depend on timing or on the number of workers, the special points are classified
(fold, touch), coverage off the census energies, the build's cost records and the ends."""

from __future__ import annotations

import random
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from rotorlib.beyond import catalogue_tasks as ct
from rotorlib.beyond.catalogue_build import default_max_steps, wavefront
from rotorlib.beyond.catalogue_paths import covers, drop_contained, on_family
from rotorlib.beyond.catalogue_points import special_points

GRID = [4.0 + 0.1 * k for k in range(8)]
#: three synthetic families T = a + b E, tr M = c E: a follow from a seed at E0 reaches
#: only E0 - 0.25 .. E0 + 0.25 (so which seed is followed first changes the result)
LINES = [(1.0, 0.5, 0.1), (2.0, -0.3, 0.2), (3.0, 0.1, -0.1)]


def _orbit(k: int, E: float) -> dict:
    a, b, c = LINES[k]
    x0 = [E, k, 0.0, 0.0]  # a start state smooth along the path
    return {"E": E, "u": E, "period": a + b * E, "trace": c * E, "k": k, "x0": x0}


def _fake_follow(args: dict) -> dict:
    o = args["seed"]
    time.sleep(random.uniform(0.0, 0.02))  # the order of completion varies
    path = [
        dict(_orbit(o["k"], E), kind="path")
        for E in GRID
        if abs(E - o["E"]) <= 0.25 + 1e-9
    ]
    return {"seed": dict(o), "special": [], "path": path, "from": o["E"]}


def _seeds() -> list[dict]:
    out = []
    for E in GRID:
        for k in range(3):
            if k != 2 or E < 4.45:  # the third family dies inside the grid
                out.append(_orbit(k, E))
    return out


def _run(executor) -> list[tuple]:
    fams, _ = wavefront(_seeds(), lambda o: {"seed": o}, None, executor)
    return [(f["seed"]["k"], f["from"], len(f["path"])) for f in fams]


def test_wavefront_is_the_serial_rule_on_any_number_of_workers(monkeypatch):
    monkeypatch.setitem(ct.TASKS, "follow", _fake_follow)
    serial = _run(None)
    # the serial rule by hand: a seed is followed iff no earlier family covers it
    fams: list[dict] = []
    for o in _seeds():
        if not any(covers(f, o) for f in fams):
            fams.append(_fake_follow({"seed": o}))
    assert serial == [(f["seed"]["k"], f["from"], len(f["path"])) for f in fams]
    assert len(serial) > 3  # each family followed from several seeds (cut paths)
    for n in (2, 3, 5):
        for _ in range(3):
            with ThreadPoolExecutor(n) as ex:
                assert _run(ex) == serial


def test_wavefront_counts_speculative_follows_and_reads_the_cache(
    monkeypatch, tmp_path
):
    monkeypatch.setitem(ct.TASKS, "follow", _fake_follow)
    with ThreadPoolExecutor(3) as ex:
        fams, ran = wavefront(_seeds(), lambda o: {"seed": o}, tmp_path, ex)
    assert ran >= len(fams)
    again, ran2 = wavefront(_seeds(), lambda o: {"seed": o}, tmp_path, None)
    assert ran2 == 0 and [f["from"] for f in again] == [f["from"] for f in fams]


def test_on_family_interpolates_between_members():
    fam = {"seed": {}, "special": [], "path": [_orbit(0, E) for E in GRID]}
    o = dict(_orbit(0, 4.333), via=["x", "IS", 4.3])
    assert on_family(fam, o) and covers(fam, o)
    assert not on_family(fam, dict(o, period=o["period"] * (1 + 1e-4)))
    assert not on_family(fam, dict(o, trace=o["trace"] + 0.1))
    assert not on_family(fam, dict(o, E=3.9))  # outside the path


def _fam(traces, kinds):
    path = [
        {"E": 1.0 + 0.01 * i, "period": 2.0, "trace": t} for i, t in enumerate(traces)
    ]
    special = [
        {"kind": k, "E": 1.0 + 0.01 * i + 0.005, "index": i, "period": 2.0, "trace": v}
        for k, i, v in kinds
    ]
    return {"path": path, "special": special}


def test_special_points_fold_and_touch():
    # an IS beside a fold of the same family is the fold
    f = _fam([3.9, 3.99, 4.01], [("IS", 1, 4.0), ("fold", 1, 4.0)])
    f["special"][1]["E"] = f["special"][0]["E"] + 1e-9
    assert [p["kind"] for p in special_points(f)] == ["fold"]
    # tr M reaching 4 and back at rounding level: one touch
    f = _fam([3.9, 4.0 + 1e-9, 4.0 + 2e-9, 3.9], [("IS", 0, 4.0), ("IS", 2, 4.0)])
    (p,) = special_points(f)
    assert p["kind"] == "touch" and p["level"] == 4.0
    # a genuine unstable window, however short: two IS points
    f = _fam([3.9, 4.1, 4.2, 3.9], [("IS", 0, 4.0), ("IS", 2, 4.0)])
    assert [p["kind"] for p in special_points(f)] == ["IS", "IS"]
    # an IS far from the fold stays
    f = _fam([3.9, 4.1, 4.2], [("IS", 0, 4.0), ("fold", 1, 4.0)])
    assert [p["kind"] for p in special_points(f)] == ["IS", "fold"]


def test_default_max_steps_covers_the_axis():
    n = default_max_steps(0.05, 8.0, 0.01)
    # steps of step / 8 relative to E from 0.05 to 8 number ln(160) * 800 ~ 4060
    assert n >= 2 * 4060
    assert default_max_steps(5.3, 6.2, 0.01) == 600
    with pytest.raises(ValueError):
        default_max_steps(0.0, 8.0, 0.01)


def _path(Es, Ts, trs):
    return [
        {"E": E, "period": T, "trace": tr, "u": 0.1 * i}
        for i, (E, T, tr) in enumerate(zip(Es, Ts, trs))
    ]


def _ends(stop0="E range", stop1="E range"):
    return [
        {"side": "backward", "stop": stop0, "reason": f"{stop0}: ..."},
        {"side": "forward", "stop": stop1, "reason": f"{stop1}: ..."},
    ]


def test_links_only_at_genuine_points_and_both_ways():
    from rotorlib.beyond.catalogue_links import link_families as _links

    # parent: a PD at E = 5.0 (T_b = 2); daughter: born there (a fold) with 2 T_b
    parent = {
        "id": "F001",
        "path": _path([4.9, 4.95, 5.0, 5.05], [2.0] * 4, [0.2, 0.1, 0.0, -0.1]),
        "special": [{"kind": "PD", "E": 5.0, "period": 2.0, "trace": 0.0}],
    }
    daughter = {
        "id": "F002",
        "path": _path([5.1, 5.0, 5.1], [4.01, 4.0, 3.99], [3.9, 4.0, 3.9]),
        "special": [{"kind": "fold", "E": 5.0, "period": 4.0, "trace": 4.0}],
    }
    other = {  # the period, not born there (tr M far from 4)
        "id": "F003",
        "path": _path([4.9, 5.1], [4.0, 4.0], [1.0, 1.0]),
        "special": [],
    }
    _links([parent, daughter, other])
    assert parent["daughters"] == [{"id": "F002", "kind": "PD", "E": 5.0}]
    assert daughter["parents"] == [{"id": "F001", "kind": "PD", "E": 5.0}]
    assert other["parents"] == [] and other["daughters"] == []
    parent["special"][0]["kind"] = "touch"  # not a bifurcation: no link
    _links([parent, daughter, other])
    assert parent["daughters"] == [] and daughter["parents"] == []


def test_a_family_the_engine_cannot_carry_across_an_energy_is_joined():
    from rotorlib.beyond.catalogue_files import _end
    from rotorlib.beyond.catalogue_links import link_families as _links

    x = [2.59, 7.77, -2.34, 0.78]
    a = {
        "id": "F002",
        "path": [
            {
                "E": 4.2,
                "period": 4.9,
                "trace": 1.0,
                "u": 0.0,
                "x0": [2.6, 7.9, -2.3, 0.8],
            },
            {"E": 4.5, "period": 5.1, "trace": 1.0, "u": 0.1, "x0": x},
        ],
        "special": [],
        "seed": {"E": 4.2, "u": 0.0},
        "ends": _ends("E range", "stuck"),
    }
    b = {
        "id": "F003",
        "path": [
            {"E": 4.51, "period": 5.11, "trace": 1.0, "u": 0.0, "x0": x},
            {"E": 4.5 + 1e-9, "period": 5.1, "trace": 1.0, "u": 0.1, "x0": x},
        ],
        "special": [],
        "seed": {"E": 4.51, "u": 0.0},
        "ends": _ends("E range", "stuck"),
    }
    _links([a, b])
    assert a["joins"] == [{"id": "F003", "E": 4.5, "side": 1}]
    end = _end(a, 1, 4.2, 4.6)
    assert end["kind"] == "engine stopped" and "goes on as F003" in end["reason"]


def test_ends_say_why():
    from rotorlib.beyond.catalogue_files import END_KINDS, _end

    # born at a parent's PD (a fold at the parent's point), window edge at the top
    f = {
        "path": _path(
            [5.1, 5.0, 5.1, 5.2], [4.01, 4.0, 3.99, 3.98], [3.9, 4.0, 3.9, 3.8]
        ),
        "seed": {"E": 5.1, "u": 0.0},
        "ends": _ends(),
        "parents": [{"id": "F001", "kind": "PD", "E": 5.0}],
    }
    low, high = _end(f, 0, 4.8, 5.2), _end(f, 1, 4.8, 5.2)
    assert low["kind"] == END_KINDS["parent"] and "F001" in low["reason"]
    assert high["kind"] == END_KINDS["window"] and high["E"] == 5.2
    f["parents"] = []
    assert _end(f, 0, 4.8, 5.2)["kind"] == "fold"
    # the engine stuck 3e-4 short of the parent's point: born there all the same
    f["path"] = f["path"][1:]
    f["path"][0]["E"] = 5.0003
    f["ends"] = _ends("stuck", "E range")
    f["parents"] = [{"id": "F001", "kind": "PD", "E": 5.0}]
    low = _end(f, 0, 4.8, 5.2)
    assert low["kind"] == END_KINDS["parent"] and "3.0e-04" in low["reason"]
    f["path"][0]["E"] = 5.003  # too far: the engine's stop
    assert _end(f, 0, 4.8, 5.2)["kind"] == "engine stopped"
    # T -> infinity at the pendulum separatrix; an engine stop away from critical points
    g = {
        "path": _path([3.97, 3.98, 3.99, 4.1, 4.2], [9.0, 8.0, 7.0, 6.0, 5.0], [1] * 5),
        "seed": {"E": 4.2, "u": 0.4},
        "ends": _ends("period", "stuck"),
    }
    low, high = _end(g, 0, 3.0, 5.0), _end(g, 1, 3.0, 5.0)
    assert low["kind"] == END_KINDS["separatrix"] and "E -> 4" in low["reason"]
    assert low["side"] == "backward"
    assert high["kind"] == "engine stopped" and "stuck" in high["reason"]
    g["path"][0]["E"] = 3.5  # far from a separatrix: leaves T <= T_max
    assert _end(g, 0, 3.0, 5.0)["kind"] == END_KINDS["period"]
    g["path"][0]["E"] = 0.02  # the engine stops at E -> 0: a critical point
    g["ends"] = _ends("stuck", "stuck")
    assert _end(g, 0, 0.01, 5.0)["kind"] == END_KINDS["critical"]
    g["path"][-1]["x0"] = [0.1, 0.2, 0.01, -0.02]  # shrinks to the saddle at E = 4
    g["path"][3]["E"], g["path"][-1]["E"] = 3.995, 4.01
    assert _end(g, 1, 0.01, 5.0)["kind"] == END_KINDS["critical"]
    g["path"][-1]["x0"] = [0.1, 0.2, 1.0, -0.02]  # stuck at 4, not an equilibrium
    assert _end(g, 1, 0.01, 5.0)["kind"] == "engine stopped"
    g["path"][-1]["E"] = 8.0  # the axis
    g["ends"] = _ends("stuck", "E range")
    assert _end(g, 1, 0.01, 8.0)["kind"] == END_KINDS["axis"]


def test_switch_finds_the_pd_daughter_on_its_side_only():
    """The pendulum's PD point at E_b = 4.4773509830 (T_b = 2.78091194; located by the
    engine): the census beside it, restricted to periods near 2 T_b, finds PD^r_2's
    member above E_b (born there with tr M = 4) and nothing below."""
    T2 = 2 * 2.7809119399520856
    below, above = 4.474371432046, 4.480330533973
    args = {"period": T2, "rel": 0.03, "t_max": 1.05 * T2, "grid": 100}
    (o,) = ct.switch_task(dict(args, energies=[below, above]))
    assert o["E"] == above
    assert abs(o["period"] / T2 - 1) < 0.01 and abs(o["trace"] - 4) < 0.05


def test_a_small_build_is_the_same_serially_and_on_2_workers(tmp_path):
    """A real build (E = 4.3, 4.4, 4.5, T <= 3.5, coarse): the same families, special
    points and paths from an empty cache serially and on a pool of 2 processes."""
    from rotorlib.beyond.catalogue_build import build
    from rotorlib.core.parallel import executor_for

    def fams(workers):
        with executor_for(workers) as ex:
            cat = build(
                [4.3, 4.4, 4.5],
                3.5,
                tmp_path / str(workers),
                grid=40,
                refine=0,
                digits=16,
                name=False,
                max_steps=15,
                executor=ex,
                switch=0,
            )
        assert not cat["orphans"]
        return [
            (f["task"], [(p["kind"], p["E"]) for p in f["special"]], f["path"])
            for f in cat["families"]
        ]

    serial = fams(1)
    # the pendulum, followed from E = 4.3 and from 4.4 (15 steps each): two records,
    # of which the one that lies on the other is dropped, in both runs
    assert len(serial) == 1 and fams(2) == serial


def _curve(task, E0, E1, n, shift=0.0, seed_E=None):
    """A family on T = 6 + (E - 5)^2, tr M = 2 + 10 (E - 5) (plus ``shift`` in T), its
    path ``n`` members from ``E0`` to ``E1``."""

    def m(E):
        return {"E": E, "period": 6 + (E - 5) ** 2 + shift, "trace": 2 + 10 * (E - 5)}

    path = [m(E0 + (E1 - E0) * k / (n - 1)) for k in range(n)]
    return {
        "task": task,
        "seed": m(seed_E if seed_E is not None else (E0 + E1) / 2),
        "path": path,
    }


def test_a_family_met_from_two_seeds_is_kept_once():
    """F006 of the 5.3-6.2 build was F004's lower branch from another seed: the engine
    stopped it early, so that its path lay on F004's. The longer is kept, whatever the
    order; a family that shares one point with another (a bifurcation), one that lies
    close but not on it (T 1e-4 apart), and one that runs past the other's end are
    kept."""
    long = _curve("long", 5.0, 6.0, 101)
    short = _curve("short", 5.3, 5.7, 37)  # other members, same curve
    assert [f["task"] for f in drop_contained([short, long])[0]] == ["long"]
    kept, dropped = drop_contained([long, short])
    assert [f["task"] for f in kept] == ["long"] and dropped == [("short", ["long"])]
    near_by = _curve("near", 5.3, 5.7, 37, shift=6e-4)
    past_end = _curve("past", 5.5, 6.3, 50)
    touching = {
        "task": "daughter",
        "seed": {"E": 5.5, "period": 6.25, "trace": 7.0},
        "path": [
            {"E": 5.5 - 0.01 * k, "period": 6.25 + 0.05 * k, "trace": 7.0 - 0.3 * k}
            for k in range(30)
        ],
    }
    kept, dropped = drop_contained([long, near_by, past_end, touching])
    assert {f["task"] for f in kept} == {"long", "near", "past", "daughter"}
    assert dropped == []


def test_a_record_that_bridges_two_others_is_the_one_dropped():
    """The CG family of the whole-axis build: the engine stops two records at E = 4.5
    (0.1-4.5 and 4.5-5.3), and a third, from a seed at E = 4, runs 4-5.3 across it.
    The bridge is dropped, not the shorter part (which would leave 4-4.5 twice); the
    probes near a separatrix that the interpolation misses (``share``) do not save a
    part."""
    low = _curve("low", 4.0, 5.0, 101)
    high = _curve("high", 5.0, 5.6, 31)
    bridge = _curve("bridge", 4.6, 5.5, 60)
    kept, dropped = drop_contained([low, high, bridge])
    assert [f["task"] for f in kept] == ["low", "high"]
    assert [(t, sorted(h)) for t, h in dropped] == [("bridge", ["high", "low"])]
    part = _curve("part", 4.2, 4.8, 40)
    part["path"][5] = dict(part["path"][5], period=part["path"][5]["period"] + 0.01)
    assert drop_contained([low, part])[1] == [("part", ["low"])]


def test_a_record_followed_further_is_not_dropped_for_a_shorter_bound():
    """Bands of period bounds (T <= 16 below some energy, T <= 8 above): a record
    followed to a lower bound holds no record followed further whose periods pass that
    bound (T = 6 .. 6.49 on the short record), whatever their lengths; one whose
    periods stay below it adds nothing and is dropped. A seed of a T <= 16 census is
    not covered by a family followed to T <= 8 only."""
    long = dict(_curve("long", 5.0, 6.0, 101), t_max=6.2)
    short = dict(_curve("short", 5.3, 5.7, 37), t_max=16.0)
    kept, dropped = drop_contained([long, short])
    assert {f["task"] for f in kept} == {"long", "short"} and dropped == []
    long = dict(long, t_max=6.5)
    assert drop_contained([long, short])[1] == [("short", ["long"])]
    long = dict(long, t_max=8.0)
    long16 = dict(long, t_max=16.0)
    short8 = dict(short, t_max=8.0)
    assert drop_contained([long16, short8])[1] == [("short", ["long"])]
    fam = {"seed": long["seed"], "special": [], "path": long["path"], "t_max": 8.0}
    o = dict(long["path"][50])
    assert covers(fam, o) and covers(fam, dict(o, t_max=8.0))
    assert not covers(fam, dict(o, t_max=16.0))


def test_the_bands_of_a_build_are_checked():
    from rotorlib.beyond.catalogue_paths import bands_of, period_bound

    b = bands_of([(8.0, 8), (6.2, 16)], 8.0)
    assert [period_bound(b, E) for E in (0.1, 6.2, 6.2000001, 8.0)] == [16, 16, 8, 8]
    for bad in ([(8.0, 0)], [(8.0, float("nan"))], [(6.0, 16)], []):
        with pytest.raises(ValueError):
            bands_of(bad, 8.0)


def test_a_daughter_is_sought_within_the_bound_where_it_is_born():
    """Branch switching on a family followed to T <= 16 across two bands (T <= 16 up to
    E = 4.6, T <= 8 above): an IS point of period 10 is switched below 4.6 (and its
    daughter followed to 16), not above; a PD point of period 3.5 above 4.6 is switched
    with the bound 8 (n T_b = 7); a PD point of period 9 is not (n T_b = 18 > 16)."""
    from rotorlib.beyond.catalogue_build import switch_jobs
    from rotorlib.beyond.catalogue_paths import bands_of

    path = [{"E": 4.0 + 0.01 * k, "period": 10.0, "trace": 1.0} for k in range(201)]
    pts = [
        {"kind": "IS", "E": 4.3, "period": 10.0, "index": 30},
        {"kind": "IS", "E": 5.0, "period": 10.0, "index": 100},
        {"kind": "PD", "E": 5.5, "period": 3.5, "index": 150},
        {"kind": "PD", "E": 4.2, "period": 9.0, "index": 20},
        {"kind": "fold", "E": 4.1, "period": 1.0, "index": 10},
    ]
    fam = {"task": "f", "path": path, "special": pts, "t_max": 16.0}
    bands = bands_of([(4.6, 16.0), (8.0, 8.0)], 8.0)
    jobs, owners = switch_jobs([fam], bands, 0.1, 8.0, 300)
    assert [(o[0][1], o[0][2], o[1]) for o in owners] == [
        ("IS", 4.3, 16.0),
        ("PD", 5.5, 8.0),
    ]
    assert [j["period"] for j in jobs] == [10.0, 7.0]
    assert [j["t_max"] for j in jobs] == [pytest.approx(10.5), pytest.approx(7.35)]
    # one band: the family's own bound
    one = bands_of(16.0, 8.0)
    assert len(switch_jobs([fam], one, 0.1, 8.0, 300)[0]) == 3


def test_a_record_alone_holding_a_census_orbit_is_not_dropped():
    """A record four fifths of whose probes lie on another (so drop_contained would
    drop it) is kept while a census orbit lies on it and on no other record; the
    orbit's removal lets it go."""
    from rotorlib.beyond.catalogue_paths import holds

    long = dict(_curve("long", 4.0, 6.0, 201), special=[])
    # the last fifth of "part" leaves "long" (its period bends away above E = 5.8)
    part = dict(_curve("part", 5.0, 6.0, 101), special=[])
    for m in part["path"]:
        if m["E"] > 5.8:
            m["period"] += 0.5 * (m["E"] - 5.8)
    lone = dict(part["path"][95])  # on "part" only
    assert holds(part, lone) and not holds(long, lone)
    assert drop_contained([part, long])[1] == [("part", ["long"])]
    kept, dropped = drop_contained([part, long], orbits=[lone])
    assert dropped == [] and len(kept) == 2


def test_a_polish_that_lands_on_another_orbit_is_a_failure():
    from rotorlib.beyond.catalogue_build import _checked_polish

    m = {"period": 12.0256204463}
    ok = {"period_str": "12.02562044630000001"}
    assert _checked_polish(m, ok) is ok
    bad = _checked_polish(m, {"period_str": "12.0256434777051361"})
    assert "another orbit" in bad["failed"]
    assert _checked_polish(m, {"failed": "x"}) == {"failed": "x"}


def _jumping_path(n=21, jump_at=10, E0=3.9, dE=0.01):
    """A path across E = 4 whose start state jumps between members ``jump_at`` and
    ``jump_at + 1`` (E = 4.0 and 4.01)."""
    return [
        {
            "E": E0 + k * dE,
            "u": k / 100,
            "period": 6.0 + k / 100,
            "trace": 1.0,
            "x0": [k / 1000 + (k > jump_at), 3 * k / 1000, 0.0, 0.0],
        }
        for k in range(n)
    ]


def test_a_path_carried_across_a_critical_energy_onto_another_orbit_is_cut():
    """The breather LD's path at T <= 16 crossed E = 4 with its start jumping: the part
    that holds the seed is kept, the end at the cut is a critical point, special points
    beyond it go and the others are re-indexed; a smooth crossing, or a jump away from
    a critical energy, is not cut."""
    from rotorlib.beyond.catalogue_files import END_KINDS, _end
    from rotorlib.beyond.catalogue_paths import cut_at_critical

    path = _jumping_path()
    f = {
        "path": path,
        "seed": path[15],
        "special": [{"kind": "PD", "index": 3}, {"kind": "IS", "index": 17}],
        "ends": _ends("stuck", "E range"),
    }
    g = cut_at_critical(f)
    assert [m["E"] for m in g["path"]] == [m["E"] for m in path[11:]]
    assert g["special"] == [{"kind": "IS", "index": 6}]
    assert (
        g["ends"][0]["stop"] == "critical"
        and "critical energy 4" in g["ends"][0]["reason"]
    )
    assert g["ends"][1] == f["ends"][1]
    low = _end(g, 0, 0.1, 8.0)
    assert low["kind"] == END_KINDS["critical"] and abs(low["E"] - 4.01) < 1e-12
    # the seed below: the lower part is kept, its forward end is the cut
    h = cut_at_critical(dict(f, seed=path[2]))
    assert len(h["path"]) == 11 and h["ends"][1]["stop"] == "critical"
    assert h["special"] == [{"kind": "PD", "index": 3}]
    # no jump, or a jump away from 4 and 4.5: unchanged
    smooth = _jumping_path(jump_at=100)
    assert len(cut_at_critical(dict(f, path=smooth, seed=smooth[15]))["path"]) == 21
    away = _jumping_path(E0=5.0)
    assert len(cut_at_critical(dict(f, path=away, seed=away[15]))["path"]) == 21


def _polished(i, E, T, tr, T30, tr30, kind="path"):
    return {
        "kind": kind,
        "index": i,
        "E": E,
        "u": i / 100,
        "period": T,
        "trace": tr,
        "polish": {"period_str": repr(T30), "trace_str": repr(tr30)},
    }


def test_a_path_whose_float64_members_disagree_with_30_digits_is_cut():
    """IS^r_4 at T <= 16: within ~2e-5 of E = 4 its float64 tr M is off by percent and
    then by thousands (the continuation has lost the family): the path is cut at the
    last stored member that agrees with its re-solve, special points past it go, and the
    end says why. Agreement within the float64 path's own accuracy (1e-6 in tr M) is
    not cut, nor a fold (its fixed-E re-solve is ill-conditioned)."""
    from rotorlib.beyond.catalogue_files import END_KINDS, _end
    from rotorlib.beyond.catalogue_paths import cut_untrusted

    path = [
        {"E": 4.0 + 10.0 ** (-k), "u": k / 100, "period": 12 + 1 / k, "trace": -k}
        for k in range(1, 9)
    ]  # E -> 4 along the path
    stored = [
        _polished(i, m["E"], m["period"], m["trace"], m["period"], m["trace"])
        for i, m in enumerate(path)
    ]
    f = {
        "path": path,
        "seed": path[0],
        "stored": stored,
        "special": [{"kind": "PD", "index": 2}, {"kind": "IS", "index": 6}],
        "ends": _ends("E range", "stuck"),
    }
    assert not cut_untrusted(f)  # all agree
    stored[4]["polish"]["trace_str"] = repr(-5 * (1 + 5e-7))  # float64's own accuracy
    stored[3]["kind"] = "fold"
    stored[3]["polish"]["trace_str"] = "3.999"  # a fold: not tested
    assert not cut_untrusted(f)
    stored[5]["polish"]["trace_str"] = "1.69"  # lost: -6 against 1.69
    assert cut_untrusted(f)
    assert len(f["path"]) == 5 and f["special"] == [{"kind": "PD", "index": 2}]
    assert f["ends"][1]["stop"] == "untrusted" and "1.69" in f["ends"][1]["reason"]
    assert f["ends"][0]["stop"] == "E range"
    end = _end(f, 0, 3.0, 5.0)  # the low end: the cut, near E = 4
    assert end["kind"] == END_KINDS["untrusted"] and "not trusted" in end["reason"]
    # a re-solve that landed on another orbit counts too; the seed itself never cuts
    g = {**f, "path": path, "special": [], "ends": _ends()}
    g["stored"] = [dict(m) for m in stored[:5]]
    g["stored"][2] = dict(g["stored"][2], polish={"failed": "...another orbit..."})
    assert cut_untrusted(g) and len(g["path"]) == 2
    g = {**f, "path": path, "special": [], "ends": _ends(), "seed": path[5]}
    g["stored"] = stored
    assert not cut_untrusted(g)


def test_a_path_that_zigzags_beside_a_fold_is_cut_at_the_fold():
    """F057 at T <= 16: up to its fold (index 3 here), then back down on the same
    branch and up again: a turn that no located fold explains. The path is cut at the
    fold, whose end says so; a second turn far from the fold cuts at the turn itself;
    a single turn at a located fold is kept."""
    from rotorlib.beyond.catalogue_files import END_KINDS, _end
    from rotorlib.beyond.catalogue_paths import cut_at_reversal

    Es = [4.60, 4.65, 4.67, 4.6785, 4.6766, 4.6763, 4.6783, 4.6786, 4.6771, 4.65]
    path = [
        {"E": E, "u": k, "period": 15 + k / 10, "trace": -1e3, "x0": [0.0] * 4}
        for k, E in enumerate(Es)
    ]
    fold = {"kind": "fold", "index": 3, "E": 4.6784, "period": 15.3, "trace": 4.0}
    f = {
        "path": path,
        "seed": path[0],
        "special": [fold],
        "ends": _ends("period", "E range"),
    }
    g = cut_at_reversal(f)
    assert [m["E"] for m in g["path"]] == Es[:4] and g["special"] == [fold]
    assert g["ends"][1]["stop"] == "fold" and "zigzag" in g["ends"][1]["reason"]
    assert _end(g, 1, 4.5, 8.0)["kind"] == END_KINDS["fold"]
    # no located fold: cut at the first turn
    h = cut_at_reversal(dict(f, special=[]))
    assert len(h["path"]) == 4 and h["ends"][1]["stop"] == "reversal"
    # one turn, at the located fold: a family through its fold, kept whole
    once = [dict(m) for m in path[:6]]
    k = cut_at_reversal(dict(f, path=once, seed=once[0]))
    assert len(k["path"]) == 6


def test_a_record_that_turned_onto_its_parents_branch_is_cut_and_linked():
    """The record that met IS^r_3 had come down the pendulum and turned at a fold onto
    IS^r_3: its side of the fold that lies on another record (the parent, which has no
    fold there) goes, the end is a birth at the parent's IS point; two halves of a
    saddle-node (both turn at the fold) are not cut."""
    from rotorlib.beyond.catalogue_files import END_KINDS, _end
    from rotorlib.beyond.catalogue_links import link_families as _links
    from rotorlib.beyond.catalogue_paths import cut_at_switch

    Es = [4.5 - 0.05 * k for k in range(9)]  # the parent: T = 10 - E
    parent = {
        "task": "p",
        "seed": {"E": Es[0], "u": 0.0},
        "path": [
            {"E": E, "u": 0.1 * k, "period": 10 - E, "trace": 1.0}
            for k, E in enumerate(Es)
        ],
        "special": [],
        "ends": _ends(),
    }
    down = [dict(m) for m in parent["path"]]  # down the parent, then up the daughter
    up = [
        {"E": Es[-1] + 0.05 * k, "u": 5 + k, "period": 12 + k, "trace": 9.0}
        for k in range(1, 9)
    ]
    fold = {
        "kind": "fold",
        "index": 8,
        "E": Es[-1],
        "period": 10 - Es[-1],
        "trace": 4.0,
    }
    f = {
        "task": "d",
        "seed": up[5],
        "path": down + up,
        "special": [
            fold,
            {"kind": "PD", "index": 2, "E": 4.4, "period": 5.6, "trace": 0.0},
        ],
        "ends": _ends("period", "period"),
    }
    assert cut_at_switch([parent, f]) == [("d", "p", Es[-1])]
    assert [m["E"] for m in f["path"]] == [Es[-1]] + [m["E"] for m in up]
    assert f["special"] == [] and f["ends"][0]["stop"] == "switch"
    for g, i in ((parent, "F001"), (f, "F002")):
        g["id"] = i
    _links([parent, f])
    assert f["parents"] == [{"id": "F001", "kind": "IS", "E": Es[-1]}]
    assert parent["daughters"] == [{"id": "F002", "kind": "IS", "E": Es[-1]}]
    low = _end(f, 0, 0.1, 8.0)
    assert low["kind"] == END_KINDS["parent"] and "F001" in low["reason"]
    # the parent with a fold of its own there: two halves, nothing cut
    g = {**f, "path": down + up, "special": [dict(fold)], "ends": _ends()}
    p2 = {**parent, "special": [dict(fold)]}
    assert cut_at_switch([p2, g]) == []


def test_crossings_at_rounding_level_are_one_marginal_stretch():
    """A family whose tr M sits within 1e-6 of 4 over a stretch: the float64 sign
    changes there are one marginal stretch (E, E_end, crossings), in no stability
    window; two crossings within two members stay a touch."""
    from rotorlib.beyond.catalogue_files import _stable_windows

    trs = [3.0, 3.9, 4 - 1e-9, 4 + 1e-9, 4 - 1e-9, 4 + 1e-9, 4 - 1e-9, 3.8, 3.0]
    f = {
        "path": [
            {"E": 4.0 + 0.01 * k, "period": 5.0, "trace": tr}
            for k, tr in enumerate(trs)
        ],
        "special": [
            {
                "kind": "IS",
                "index": k,
                "E": 4.0 + 0.01 * k + 0.005,
                "period": 5.0,
                "trace": 4.0,
            }
            for k in (2, 3, 4, 5)
        ],
    }
    (m,) = special_points(f)
    assert m["kind"] == "marginal" and m["crossings"] == 4 and m["level"] == 4.0
    assert (m["index"], m["index_end"]) == (2, 5) and m["E"] < m["E_end"]
    f["special"] = [m]
    assert _stable_windows(f) == [[4.0, 4.01], [4.07, 4.08]]
    # two crossings within two members: a touch, as before
    f["special"] = [
        {"kind": "IS", "index": k, "E": 4.0 + 0.01 * k, "period": 5.0, "trace": 4.0}
        for k in (2, 3)
    ]
    f["path"][4]["trace"] = 3.5
    assert [p["kind"] for p in special_points(f)] == ["touch"]


def _densify_family(noise: float) -> tuple[dict, object]:
    """A path of 40 members on 4.02 <= E <= 5 with T = 1 - log(E - 4) (steep beside the
    separatrix), tr M = 2 + E, special point between members 5 and 6; and a fake
    ``run`` that solves the densify tasks analytically, with relative ``noise`` on T
    (a float64 path whose accuracy is its limit)."""
    rng = np.random.default_rng(3)

    def orbit(E):
        T = (1 - np.log(E - 4)) * (1 + noise * rng.standard_normal())
        return {"E": float(E), "u": float(E), "period": float(T), "trace": 2.0 + E}

    path = [orbit(E) for E in np.linspace(4.02, 5.0, 40)]
    Ep = 0.7 * path[5]["E"] + 0.3 * path[6]["E"]
    point = {"kind": "IS", "E": Ep, "period": 1 - np.log(Ep - 4), "index": 5}
    fam = {"path": path, "special": [point], "problem": {}, "factor": 1.0}

    def run(kind, jobs, desc):
        assert kind == "densify"
        return [[orbit(E) for E in a["E"]] for a in jobs]

    return fam, run


def test_densify_makes_the_interpolant_hold_between_path_members():
    """Smooth data: the rounds add members where a left-out member is not reproduced
    to 1e-8 until none is (the left-out error falls from ~1e-4 to below 1e-8); special
    points keep the member before them; the task keys are owned by the family."""
    from rotorlib.beyond.catalogue_build import densify
    from rotorlib.beyond.catalogue_members import coarse_gaps, left_out_errors

    fam, run = _densify_family(0.0)
    E = np.array([m["E"] for m in fam["path"]])
    Y = np.array([[m["period"], m["trace"]] for m in fam["path"]])
    before = left_out_errors(E, Y).max()
    owned: dict = {}
    added = densify([fam], run, owned)
    E = np.array([m["E"] for m in fam["path"]])
    Y = np.array([[m["period"], m["trace"]] for m in fam["path"]])
    assert before > 1e-5 and added and sum(added) == len(fam["path"]) - 40
    assert left_out_errors(E, Y).max() <= 1e-8 and not coarse_gaps(fam)
    assert np.all(np.diff(E) > 0) and len(owned[0]) == len(added)
    p = fam["special"][0]
    assert E[p["index"]] < p["E"] < E[p["index"] + 1]


def test_densify_through_a_fold_in_u():
    """A piece parametrised by u (through a fold of E(u) = 5 - (u - 1)^2, with
    T = 1 / (3 - u), sharply curved beside u = 3): the rounds split intervals in u; a
    member is shot at E(u_mid), where two members exist, and kept only if it lands in
    the interval (the fake solver returns the other branch's member when asked to, which
    must be refused); the fold point keeps its neighbours in the (E, period) order."""
    from rotorlib.beyond.catalogue_build import densify
    from rotorlib.beyond.catalogue_members import coarse_gaps, left_out_errors, pieces

    def orbit(u):
        return {"E": 5 - (u - 1) ** 2, "u": u, "period": 1 / (3 - u), "trace": u}

    path = [orbit(u) for u in np.linspace(0.0, 2.9, 30)]
    k = int(np.searchsorted([m["u"] for m in path], 1.0)) - 1
    fold = {"kind": "fold", "E": 5.0, "period": 0.5, "trace": 1.0, "index": k}
    fam = {"path": path, "special": [fold], "problem": {}, "factor": 1.0}
    wrong = iter([True] * 3 + [False] * 10**4)

    def run(kind, jobs, desc):
        out = []
        for a in jobs:
            res = []
            for E, u0, box in zip(a["E"], a["u"], a.get("box", [None] * len(a["E"]))):
                # the solver lands on the member of the other side of the fold
                u = 2 - u0 if box and next(wrong) else u0
                res.append(orbit(u))
                if box and not box[0] < u < box[1]:
                    res[-1] = {"failed": "outside"}
            out.append(res)
        return out

    u = np.array([m["u"] for m in path])
    Y = np.array([[m["period"], m["trace"]] for m in path])
    before = left_out_errors(u, Y).max()
    added = densify([fam], run, {})
    u = np.array([m["u"] for m in fam["path"]])
    Y = np.array([[m["period"], m["trace"]] for m in fam["path"]])
    E = np.array([m["E"] for m in fam["path"]])
    assert any(p == "u" for *_, p in pieces(E, u))
    assert before > 1e-5 and added and np.all(np.diff(u) > 0)
    assert left_out_errors(u, Y).max() <= 1e-8 and not coarse_gaps(fam)
    i = fam["special"][0]["index"]
    assert u[i] <= 1.0 <= u[i + 1], (u[i], u[i + 1])


def test_densify_stops_where_the_path_is_noise_limited():
    """Noisy data (1e-7 relative, as a float64 tr M of a very unstable orbit): the
    left-out error cannot fall below the noise; a member whose error did not fall when
    its intervals were split is marked ``noise`` and not split again, so the rounds
    shrink (measured: 39, 34, 30, 13, 12, 4) instead of doubling the path each round
    (2^6 times 39)."""
    from rotorlib.beyond.catalogue_build import densify

    fam, run = _densify_family(1e-7)
    added = densify([fam], run, {})
    assert sum(m.get("noise", False) for m in fam["path"]) > 40
    assert added[-1] < added[0] / 4 and sum(added) < 4 * 40, added


def test_a_touch_is_switched_at_as_a_bifurcation():
    """A touch of tr M = 0 (a pair of PD daughters is born there without a change of the
    parent's stability: CG's at E = 4.6869, where CZ1 and CZ2 are born) is switched at
    with twice its period, a touch of 4 with its period; a marginal stretch is not."""
    from rotorlib.beyond.catalogue_build import switch_jobs
    from rotorlib.beyond.catalogue_paths import bands_of

    path = [{"E": 4.0 + 0.01 * k, "period": 5.0, "trace": 1.0} for k in range(201)]
    pts = [
        {"kind": "touch", "level": 0.0, "E": 4.3, "period": 5.0, "index": 30},
        {"kind": "touch", "level": 4.0, "E": 4.5, "period": 5.0, "index": 50},
        {"kind": "marginal", "level": 4.0, "E": 4.7, "period": 5.0, "index": 70},
    ]
    fam = {"task": "f", "path": path, "special": pts, "t_max": 16.0}
    jobs, owners = switch_jobs([fam], bands_of(16.0, 8.0), 0.1, 8.0, 300)
    assert [(o[0][1], o[0][2]) for o in owners] == [("touch", 4.3), ("touch", 4.5)]
    assert [j["period"] for j in jobs] == [10.0, 5.0]
    assert all(len(j["energies"]) == 2 for j in jobs)


def test_a_zigzag_end_is_walked_on_in_u():
    """``beyond_jobs``: a task at each end the path was cut at a zigzag of the engine's
    steps (``zigzag``), from its end member, in steps of 2e-5 max(1, |u|) the way the
    path went there; none at another end."""
    from rotorlib.beyond.catalogue_paths import beyond_jobs

    path = [{"E": 4.0 + 0.01 * k, "u": 3.0 - 0.1 * k} for k in range(5)]
    ends = [
        {"side": "backward", "stop": "period"},
        {"side": "forward", "stop": "reversal", "zigzag": True},
    ]
    fam = {"task": "f", "path": path, "ends": ends, "t_max": 16.0}
    fam |= {"problem": {"start": "s"}, "factor": 2.0}
    jobs, owners = beyond_jobs([fam], 0.1, 8.0)
    assert owners == [(["f", "beyond", path[-1]["E"]], 16.0)]
    (j,) = jobs
    assert j["u"] == path[-1]["u"] and j["E"] == path[-1]["E"]
    assert j["du"] == pytest.approx(-2e-5 * path[-1]["u"])
    assert j["t_max"] == 16.0 and j["E_range"] == [0.1, 8.0]
    assert beyond_jobs([dict(fam, ends=[ends[0], ends[0]])], 0.1, 8.0) == ([], [])


def test_heyoka_load_retried_then_heyokas_error():
    """A fresh machine's first parallel build: two workers opening heyoka's on-disk
    cache at once gave 'Failed to set the WAL journal mode ...'. The load is retried;
    a cache that stays unusable raises heyoka's own error after the last try."""
    from rotorlib.beyond.catalogue_tasks import heyoka_ready

    calls = []

    def locked():
        calls.append(1)
        raise RuntimeError("Failed to set the WAL journal mode")

    with pytest.raises(RuntimeError, match="WAL journal mode"):
        heyoka_ready(tries=3, load=locked)
    assert len(calls) == 3
