"""Families of atlas orbits, branch switching at their bifurcations, and the cascade.

The stable orbit at E = 5.517 (T = 9.454) lies on a saddle-centre family whose stable member
loses stability at a pitchfork (tr M = 4, not a fold) near E = 5.5158. Checks that do not
share the code under test: the saddle-centre fold and its tr M = 4 point are located
separately and must coincide; the daughter found by branch switching, followed back with the
continuation, must turn (a fold of its own family) at the energy where it was born; each
period-doubled daughter's period at birth is twice its parent's.
"""

import math

import numpy as np
import pytest

from rotorlib.beyond import atlas
from rotorlib.beyond import atlas_families as af
from rotorlib.orbits.family import Branch


@pytest.fixture(scope="module")
def orbit():
    (o,) = atlas.census(5.517, 10, name=False).stable
    return o


@pytest.fixture(scope="module")
def family(orbit):
    (f,) = af.families([orbit], (5.5150, 5.5175), step=0.002)
    return f


def _points(f, kind):
    return [
        (i, float(p.member.E)) for i, p in enumerate(f.special_points) if p.kind == kind
    ]


def test_saddle_centre_family(family, orbit):
    assert isinstance(family, Branch) and family.label == orbit.family
    assert all(p.located for p in family.special_points)
    # the orbit is a member: the backward branch ends at it, reversed
    assert min(abs(family.E - orbit.E)) == 0.0
    assert all(s in ("E range", "period") for s in family.stop.split(" / "))
    folds = [E for _, E in _points(family, "fold")]
    IS = [E for _, E in _points(family, "IS")]
    assert len(folds) == 1 and len(IS) == 2
    # tr M = 4 at the fold (located independently: Brent on E, Illinois on tr M - 4)
    assert min(abs(E - folds[0]) for E in IS) < 1e-9
    ((lo, hi),) = family.stable_windows
    assert hi == pytest.approx(folds[0], abs=1e-9) and lo == pytest.approx(min(IS))
    assert np.all(np.isfinite(family.u)) and family.problem.factor > 0


def test_branch_switching_at_the_pitchfork(family):
    ((i, E_IS),) = [(i, E) for i, E in _points(family, "IS") if E < 5.5165]
    (d,) = af.daughters(family, i)
    assert d.stable and d.E < E_IS and d.family.endswith("/IS")
    # the daughter's period at birth is the parent's: within |dT/dE| dE of it
    j = family.special_points[i].index
    T_parent = np.interp(
        E_IS, *zip(*sorted(zip(family.E[j : j + 2], family.period[j : j + 2])))
    )
    assert abs(d.period - T_parent) < 1e-2
    # followed back through its birth, the daughter's family turns there (it merges with
    # the parent): a fold at the pitchfork's energy
    (g,) = af.families([d], (5.5150, 5.5175), step=3e-5, du=0.01)
    assert isinstance(g, Branch) and g.label == d.family
    folds = [E for _, E in _points(g, "fold")]
    assert any(abs(E - E_IS) < 1e-8 for E in folds), (folds, E_IS)
    assert _points(g, "PD")  # it period-doubles below its birth


def test_saddle_centre_is_not_a_branch_point(family):
    i_fold_IS = [i for i, E in _points(family, "IS") if E > 5.5165][0]
    with pytest.raises(ValueError, match="saddle-centre"):
        af.daughters(family, i_fold_IS)


def test_cascade(family):
    ((i, E_IS),) = [(i, E) for i, E in _points(family, "IS") if E < 5.5165]
    c = af.cascade(family, i, generations=2)
    assert len(c.births) == 3 and len(c.families) == 3 and len(c.periods) == 2
    assert all(isinstance(f, Branch) for f in c.families)
    assert c.births[0] == E_IS and c.births[0] > c.births[1] > c.births[2]
    assert abs(c.periods[1] / c.periods[0] - 2) < 1e-2  # a period doubling
    # the windows shrink by about the area-preserving Feigenbaum delta (8.72)
    (r,) = c.ratios
    assert 7.5 < r < 9.5, r


def test_bad_input(family, orbit):
    with pytest.raises(ValueError, match="IS or PD"):
        af.daughters(family, 99)
    with pytest.raises(ValueError, match="dE"):
        af.daughters(family, _points(family, "IS")[0][0], dE=-1.0)
    with pytest.raises(ValueError, match="E_range"):
        af.families([orbit], (5.6, 5.7))
    with pytest.raises(ValueError, match="du"):
        af.families([orbit], (5.5, 5.6), du=0.0)
    with pytest.raises(ValueError, match="generations"):
        af.cascade(family, 0, generations=0)
    assert math.isfinite(family.E[0])


def test_stable_windows_of_a_synthetic_branch():
    """A stable run bounded by its IS points, and a stretch between two unstable members
    where tr M crosses 4 and then 0 (a window narrower than the step); none without."""
    from rotorlib.core.precision import FLOAT64
    from rotorlib.orbits.family import Member, SpecialPoint

    def m(E, trace):
        return Member(u=0.0, w=0.0, E=E, t1=1.0, r=0.0, trace=trace)

    members = tuple(m(E, t) for E, t in zip([1, 2, 3, 4, 5], [5, 3, 3, 5, -1]))
    points = [("IS", 1.5, 0), ("IS", 3.5, 2), ("IS", 4.2, 3), ("PD", 4.6, 3)]
    b = Branch(
        None,
        FLOAT64,
        members,
        tuple(SpecialPoint(k, m(E, 4.0), i) for k, E, i in points),
    )
    assert b.stable_windows == [(1.5, 3.5), (4.2, 4.6)]
    # without located points a run is bounded by its members; no stable member: none
    assert Branch(None, FLOAT64, members).stable_windows == [(2.0, 3.0)]
    assert Branch(None, FLOAT64, members[3:]).stable_windows == []
