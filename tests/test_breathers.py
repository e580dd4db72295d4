"""Breathers (paper §8): the PD transition of R and its daughter family PD^b, checked independently."""

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorlib.core.closed_forms import breather
from rotorlib.core.system import energy_alpha, lattice_reduce, rhs_alpha
from rotorlib.orbits.floquet import variational_monodromy
from rotorlib.paper import breathers as B


@pytest.fixture(scope="module")
def pd30():
    return B.pd_transition(digits=30)


@pytest.fixture(scope="module")
def family():
    return B._branch_table()


def test_pd_energy_and_period_independent(pd30):
    """E_PD from the Hill route at 30 digits; independently: the period by mpmath quadrature of
    dt = dphi / phi' and tr M of the full 4x4 variational equations (heyoka real128) vanish there."""
    pd64 = B.pd_transition()
    assert (
        pd64.kind == "PD"
        and pd64.family == "R"
        and pd64.transition == "unstable->stable"
    )
    with mp.workdps(40):
        E = mp.mpf(pd30.E_str)
        T = mp.quad(
            lambda f: 1 / mp.sqrt(E - 3 + 2 * mp.cos(f) + mp.cos(2 * f)),
            [0, mp.pi / 2, mp.pi, 3 * mp.pi / 2, 2 * mp.pi],
        )
        assert abs(T - mp.mpf(pd30.period_str)) < mp.mpf("1e-20")
        s = mp.nstr(mp.sqrt(E), 40)
        v = variational_monodromy(["0", "0", s, s], mp.nstr(T, 40), digits=30)
        # tr M = 0 at E_PD; |d tr M / dE| ~ 1.6, so |tr M| < 1e-20 pins E to ~1e-20
        assert abs(mp.mpf(v.trace_str)) < mp.mpf("1e-20")
    # float64 transition agrees to 12+ digits
    assert abs(pd64.E - float(pd30.E_str)) < 1e-12 * pd64.E
    assert abs(pd64.period - float(pd30.period_str)) < 1e-12 * pd64.period
    # the paper: E ~ 8.97, period ~ 2.63
    assert abs(pd64.E - 8.97) < 0.005 and abs(pd64.period - 2.63) < 0.005


def test_pd_record_contract():
    recs = [t.to_dict() for t in B.breather_transitions()]
    assert len(recs) == 1
    r = recs[0]
    assert r["kind"] == "PD" and r["family"] == "R" and isinstance(r["E"], float)
    assert (
        abs(r["E"] - 8.968972046849596) < 1e-12 and "transition" in r and "period" in r
    )
    assert B.breather_transitions("LG") == [] and B.breather_transitions("LD") == []
    with pytest.raises(ValueError):
        B.breather_transitions("X")


def test_pd_eigenstructure():
    es = B.pd_eigenstructure()
    ev = np.sort(es.eigenvalues.real)
    assert np.allclose(
        ev, [-1, -1, 1, 1], atol=1e-6
    )  # defective: eigenvalues to ~sqrt(eps)
    assert es.geometric_multiplicity == {1: 1, -1: 1}
    assert np.allclose(
        np.abs(es.eigenvectors[1][:, 0]), [1, 0, 0, 0], atol=1e-8
    )  # sliding
    assert np.allclose(
        np.abs(es.eigenvectors[-1][:, 0]), [0, 0, 1, 0], atol=1e-8
    )  # transverse
    assert es.basis == ("b1", "q1", "b2", "q2")


@pytest.mark.parametrize("E", [8.9, 8.3, 8.2])
def test_daughter_closes_under_scipy(E):
    o = B.breather_daughter(E)
    assert o.label == "PD^b" and o.E == E
    sol = solve_ivp(
        rhs_alpha, (0.0, o.period), o.state0, method="DOP853", rtol=1e-12, atol=1e-14
    )
    xT = sol.y[:, -1]
    assert np.max(np.abs(lattice_reduce(xT - o.state0))) < 1e-7
    assert abs(energy_alpha(o.state0) - E) < 1e-9 and abs(energy_alpha(xT) - E) < 1e-9
    # not the parent: b2(0) = 3 a1 - a2 is far from 0, and the period is near twice the parent's
    assert abs(3 * o.state0[0] - o.state0[1]) > 0.5
    assert 1.9 < o.period / breather(E, "R").period < 2.4
    # independent monodromy (scipy DOP853 variational equations) agrees on the trace
    v = variational_monodromy(o.state0, o.period)
    assert abs(v.trace - o.trace) < 1e-6 * max(1.0, abs(o.trace))
    stable = 0.0 < o.trace < 4.0
    assert stable == (E > 8.2755)
    if E == 8.3:
        assert 0.0 < o.trace < 4.0
    if E == 8.2:
        assert not 0.0 < o.trace < 4.0


def test_er_minimisation_matches_shooting():
    o = B.breather_daughter(8.6)
    r = B.daughter_by_er_minimisation(o.extra["delta_b2"], o.extra["q1_0"] + 2e-3)
    assert r.extra["Er"] < 1e-7
    assert abs(r.E - 8.6) < 1e-7 and abs(r.trace - o.trace) < 1e-5


def test_backward_fork_and_slope_ratio(family):
    assert np.all(family.E < family.E_PD)  # exists below E_PD only
    assert np.all(np.diff(family.E) < 0)  # energy falls as delta grows
    assert abs(family.fit["trace_at_birth"] - 4.0) < 1e-6  # born with tr M = 4
    assert abs(family.fit["E_at_birth"] - family.E_PD) < 1e-9
    assert abs(family.slope_ratio - 8.0) < 0.01  # paper 7.99, theory 8
    assert family.unstable_crossing == "tr M = 4"
    assert abs(family.E_unstable - 8.27) < 0.01  # paper 8.27
    assert np.all(family.trace > -1e-9)  # tr M = (tr N - 2)^2 >= 0
    assert abs(family.period[0] - 2 * breather(family.E_PD, "R").period) < 1e-3


def test_daughter_range_errors(family):
    for E in (9.0, family.E_PD + 1e-6, 5.0):
        with pytest.raises(ValueError, match="exists for"):
            B.breather_daughter(E)
