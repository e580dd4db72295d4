"""Potential, coordinates, equations of motion and critical points."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorlib.core import system as S

rng = np.random.default_rng(1)


def test_critical_points_computed():
    pts = {p.name: p for p in S.critical_points()}
    assert set(pts) == {"G", "T1", "T2", "D1", "D2", "D3"}
    assert pts["G"].kind == "minimum" and abs(pts["G"].energy) < 1e-15
    for n in ("T1", "T2"):
        assert pts[n].kind == "maximum" and abs(pts[n].energy - 4.5) < 1e-14
    for n in ("D1", "D2", "D3"):
        assert pts[n].kind == "saddle" and abs(pts[n].energy - 4.0) < 1e-14
    assert np.allclose(pts["T1"].phi, (2 * np.pi / 3, 2 * np.pi / 3))
    assert S.SEPARATRIX_ENERGY == 4.0 and S.BREATHER_SEPARATRIX_ENERGY == 4.5


def test_maps_are_inverse_and_preserve_energy():
    x = rng.normal(size=(50, 4)) * 2
    for f, g in (
        (S.alpha_to_phi, S.phi_to_alpha),
        (S.phi_to_beta, S.beta_to_phi),
        (S.alpha_to_beta, S.beta_to_alpha),
    ):
        assert np.max(np.abs(g(f(x)) - x)) < 1e-14
    Ea = S.energy_alpha(x)
    assert np.max(np.abs(S.energy_phi(S.alpha_to_phi(x)) - Ea)) < 1e-13
    assert np.max(np.abs(S.energy_beta(S.alpha_to_beta(x)) - Ea)) < 1e-13


def test_theta_round_trip_and_energy():
    th, w = rng.normal(size=(10, 3)), rng.normal(size=(10, 3))
    f0, w0, rel = S.theta_to_phi(th, w)
    th2, w2 = S.phi_to_theta(f0, w0, rel)
    assert np.max(np.abs(th2 - th)) < 1e-14 and np.max(np.abs(w2 - w)) < 1e-14
    E_tot = 0.5 * np.sum(w**2, axis=1) + S.potential_theta(*th.T)
    E_cm = 1.5 * w0**2
    assert np.max(np.abs(E_tot - E_cm - S.energy_phi(rel))) < 1e-13


def test_equations_agree_in_all_coordinates():
    x0 = np.array([0.3, -0.8, 0.5, 0.9])
    T = 3.0
    sols = {}
    for name, rhs, to, back in (
        ("alpha", S.rhs_alpha, lambda s: s, lambda s: s),
        ("phi", S.rhs_phi, S.alpha_to_phi, S.phi_to_alpha),
        ("beta", S.rhs_beta, S.alpha_to_beta, S.beta_to_alpha),
    ):
        sol = solve_ivp(rhs, (0, T), to(x0), method="DOP853", rtol=1e-12, atol=1e-12)
        sols[name] = back(sol.y[:, -1])
    assert np.max(np.abs(sols["phi"] - sols["alpha"])) < 1e-9
    assert np.max(np.abs(sols["beta"] - sols["alpha"])) < 1e-9


def test_jacobian_matches_finite_differences():
    x = np.array([0.2, 1.1, -0.4, 0.7])
    J = S.jacobian_alpha(x)
    h = 1e-6
    Jn = np.column_stack(
        [
            (S.rhs_alpha(0, x + h * e) - S.rhs_alpha(0, x - h * e)) / (2 * h)
            for e in np.eye(4)
        ]
    )
    assert np.max(np.abs(J - Jn)) < 1e-8


@pytest.mark.parametrize("bad", [float("nan")])
def test_potential_propagates_nan(bad):
    assert np.isnan(S.potential_alpha(bad, 0.0))


def test_lattice_reduce_arrays_and_tiers_agree():
    import mpmath as mp

    from rotorlib.core.precision import tier

    rng = np.random.default_rng(1)
    d = rng.uniform(-20, 20, size=(200, 4))
    r = S.lattice_reduce(d)
    assert np.all(np.abs(r[:, 0]) <= np.pi / 2 + 1e-12)
    assert np.all(np.abs(r[:, 1]) <= np.pi + 1e-12)
    assert np.array_equal(r[:, 2:], d[:, 2:])  # momenta untouched
    # the shift is a lattice vector: k1 (pi, pi) + k2 (0, 2 pi)
    k1 = (d[:, 0] - r[:, 0]) / np.pi
    k2 = (d[:, 1] - r[:, 1] - k1 * np.pi) / (2 * np.pi)
    assert np.allclose(k1, np.round(k1), atol=1e-9)
    assert np.allclose(k2, np.round(k2), atol=1e-9)
    t = tier(40)
    with t.context():
        x = [mp.mpf(3) * mp.pi + mp.mpf("1e-30"), mp.mpf(-7) * mp.pi, 0, 0]
        y = S.lattice_reduce(x, 40)
        assert abs(y[0] - mp.mpf("1e-30")) < mp.mpf(10) ** -45
        assert abs(y[1]) < mp.mpf(10) ** -45  # -7 pi - 3 pi = -10 pi
    row = S.lattice_reduce(d[0])  # one difference
    assert np.allclose(row, r[0])


def test_heyoka_equations_of_motion_are_rhs_alpha():
    from rotorlib.core.flow import flow

    x0 = np.array([0.3, -0.8, 0.5, 0.9])
    sol = solve_ivp(S.rhs_alpha, (0, 3.0), x0, method="DOP853", rtol=1e-13, atol=1e-13)
    assert np.max(np.abs(np.array(flow(x0, 3.0)) - sol.y[:, -1])) < 1e-10


def test_tier_owns_thresholds_and_tolerances():
    from rotorlib.core.precision import FLOAT64, REAL128, Tier, tier

    assert Tier.separatrix_depth == FLOAT64.separatrix_depth == 3e-8
    assert FLOAT64.r_max == 1e-8 and FLOAT64.step_tol == 4e-15
    assert REAL128.r_max == REAL128.eps ** (2 / 3)
    assert float(tier(40).step_tol) == 8 * tier(40).eps
