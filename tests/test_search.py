"""The paper's §6 search against the symmetry-reduced shooting, continuation in amplitude, ranges.

The references are real128 roots of the symmetric residual (~30 digits) and, for closure, heyoka
integrations in real128 that the float64 searches do not use.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorlib.core.precision import REAL128, heyoka_available
from rotorlib.orbits.shooting import residual
from rotorlib.paper import newborn as nb
from rotorlib.paper import search as sr

pytestmark = pytest.mark.skipif(not heyoka_available(), reason="heyoka not installed")


def test_periodicity_defect_vanishes_on_a_member_and_grows_linearly():
    spec = nb.family_spec("IS^l_2")
    u = sr.default_amplitude("IS^l_2")
    E = nb.birth_member(spec, u, REAL128)[0]
    x0 = spec.problem.state(u, E, REAL128)
    d128, t = sr.periodicity_defect("IS^l_2", x0, REAL128)
    assert d128 < 1e-25
    assert (
        abs(t - spec.period_birth) < 1e-3 * spec.period_birth
    )  # one cycle of a2 ~ tau
    x1 = [float(v) for v in x0]
    x1[3] *= 1 + 1e-8
    d1 = sr.periodicity_defect("IS^l_2", x1)[0]
    x1[3] = float(x0[3]) * (1 + 1e-7)
    d2 = sr.periodicity_defect("IS^l_2", x1)[0]
    assert 9 < d2 / d1 < 11


def test_periodicity_defect_pd_integrates_two_cycles():
    spec = nb.family_spec("PD^r_1")
    u = sr.default_amplitude("PD^r_1")
    E = float(nb.birth_member(spec, u)[0])
    d, t = sr.periodicity_defect("PD^r_1", spec.problem.state(u, E))
    assert d < 1e-12
    assert abs(t - 2 * spec.period_birth) < 0.05 * spec.period_birth


@pytest.mark.parametrize("label", ["IS^l_1", "PD^l_1", "IS^r_1", "PD^r_1"])
def test_paper_search_is_sqrt_eps_limited_and_shooting_is_not(label):
    c = sr.compare_searches(label)
    assert not c.paper.at_bound
    assert c.shooting_error < 1e-14
    assert 1e-11 < c.paper_error < 1e-6
    assert c.paper_defect > 10 * c.shooting_defect
    assert c.shooting_defect < 1e-13
    # the paper integrates a full period (twice for PD), the shooting a quarter or half
    assert c.paper_span > 1.9 * c.shooting_span


def test_paper_search_tolerance_floor():
    """xatol below sqrt(eps) |p2| changes nothing: Brent's built-in relative tolerance."""
    w = sr.work_precision(
        "IS^l_2",
        tolerances_paper=[1e-9, 1e-12, 1e-16],
        tolerances_shooting=[1e-4, 1e-15],
    )
    assert np.ptp(w.error_paper) < 0.1 * w.error_paper.max()
    assert w.error_paper.min() > 1e-10
    assert w.error_shooting[-1] < 1e-14 < w.error_shooting[0]
    assert np.all(w.integration_shooting < w.integration_paper.min())


def test_paper_search_bracket_and_bad_input():
    spec = nb.family_spec("IS^l_1")
    u = sr.default_amplitude("IS^l_1")
    E = float(nb.birth_member(spec, u)[0])
    # a bracket that misses the minimum is reported, not hidden
    r = sr.paper_search("IS^l_1", u, E + 1e-3, width=1e-5)
    assert r.at_bound
    with pytest.raises(ValueError):
        sr.paper_search("IS^l_1", u, spec.E_birth)  # zero default width
    with pytest.raises(ValueError):
        sr.paper_search("IS^l_1", u, E, width=-1.0)
    with pytest.raises(ValueError):
        sr.paper_search(
            "IS^l_1", math.pi / 2, E
        )  # V(pi/2, 0) = 4 > E: outside the energy shell
    with pytest.raises(ValueError):
        sr.default_amplitude("IS^l_1", rel=0)
    with pytest.raises(ValueError):
        sr.work_precision("IS^l_1", tolerances_paper=[0.0])
    with pytest.raises(ValueError):
        sr.compare_searches("IS^l_7")  # float64 only


def test_defect_landscape_linear():
    L = sr.defect_landscape("IS^r_1", delta=[1e-12, 1e-10, 1e-8])
    assert np.all(np.diff(np.log10(L.defect)) > 1.9) and np.all(
        np.diff(np.log10(L.residual)) > 1.9
    )


def test_birth_member_tolerance():
    spec = nb.family_spec("IS^l_1")
    u = sr.default_amplitude("IS^l_1")
    ref = nb.birth_member(spec, u, REAL128)[0]
    E1, it1 = nb.birth_member(spec, u, tol=1e-4)
    E2, it2 = nb.birth_member(spec, u)
    assert it1 < it2
    assert abs(float(E2) - float(ref)) < 1e-14 < abs(float(E1) - float(ref))


def test_follow_pdr2_fold_and_end():
    b = nb.follow("PD^r_2")
    assert b.fold is not None and abs(float(b.fold.E) - 4.5516743) < 1e-6
    assert abs(b.E[-1] - 4.5) < 1e-3 and abs(b.u[-1] - math.sqrt(4.5)) < 1e-3
    assert b.period[-1] > 4 * b.period[0]
    # every member is on the family: r(u, E) = 0
    spec = nb.family_spec("PD^r_2")
    for k in (5, len(b.u) // 2):
        assert abs(residual(spec.problem, b.u[k], b.E[k]).r) < 1e-8
    assert nb.FAMILY_REACH["PD^r_2"] == (
        math.floor(float(b.fold.E) * 1e7) / 1e7,
        "fold",
    )


def test_follow_pdr1_fold():
    b = nb.follow("PD^r_1", max_steps=400)
    assert (
        b.fold is not None
        and abs(float(b.fold.E) - nb.FAMILY_REACH["PD^r_1"][0]) < 1e-6
    )


def test_follow_bad_input():
    with pytest.raises(ValueError):
        nb.follow("IS^l_1", digits=0)
    with pytest.raises(ValueError):
        nb.follow("XY^l_1")


def test_no_pdr2_member_at_4_6():
    u, r = sr.residual_scan("PD^r_2", 4.6, n=800)
    f = np.isfinite(r)
    assert f.sum() > 790
    assert np.all(np.sign(r[f]) == np.sign(r[f][0])) and np.nanmin(np.abs(r)) > 0.01
    with pytest.raises(ValueError, match="folds back"):
        nb.newborn_orbit("PDr2", 4.6)
    with pytest.raises(ValueError):
        sr.residual_scan("PD^r_2", -1.0)


def test_residual_scan_finds_a_member():
    """At an energy where the family exists the scan has a sign change at the member's u."""
    o = nb.newborn_orbit("PDr2", 4.52)
    u, r = sr.residual_scan("PD^r_2", 4.52, n=400)
    k = np.nonzero(np.isfinite(r[:-1]) & np.isfinite(r[1:]) & (r[:-1] * r[1:] < 0))[0]
    assert any(u[i] <= o.extra["u"] <= u[i + 1] for i in k)


def test_family_ranges():
    for lab in nb.FAMILIES:
        spec = nb.family_spec(lab)
        lo, hi = nb.family_range(spec)
        assert lo == spec.E_birth and hi > lo
        assert spec.label in str(nb.FamilyRangeError(spec, hi + 1))
    assert (
        nb.family_range(nb.family_spec("PD^r_1"))[1] < 6.0
    )  # folds at 5.9831, not E_n + 6
    with pytest.raises(ValueError, match="exists for"):
        nb.newborn_orbit("PD^r_1", 6.0)
    # the range's top is reachable (checked, a fold)
    o = nb.newborn_orbit("PD^r_1", 5.98)
    assert o.residual < 1e-9


def test_cli_pdr2_at_4_6_says_it_does_not_exist(capsys):
    from rotorlib.cli import main

    assert main(["orbit", "PDr2", "--E", "4.6"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert "4.5516743" in err and "folds back" in err and "no member above" in err


def test_family_steps_end_within_range():
    lo, hi = nb.family_range(nb.family_spec("IS^r_3"))
    fam = nb.family("IS^r_3", (lo, hi), steps=3)
    assert fam.E[-1] <= hi
