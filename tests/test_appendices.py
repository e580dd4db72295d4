"""Appendix A (flux qubit = 3 rotors) and Appendix B (tr M_perp from Lamé solutions)."""

import numpy as np
import pytest

from rotorlib.core.closed_forms import pendulum
from rotorlib.core.system import potential_phi
from rotorlib.orbits.floquet import monodromy
from rotorlib.paper import lame_functions as lf
from rotorlib.paper import qubit as q


def _random_states(n, seed=0):
    rng = np.random.default_rng(seed)
    return (
        rng.uniform(-10, 10, (n, 2)),
        rng.normal(0, 2, (n, 2)),
        rng.uniform(-5, 5, n),
        rng.normal(0, 1, n),
    )


def test_qubit_energies_equal_rotor_energies():
    phi, dphi, phi0, dphi0 = _random_states(500)
    for m, r, g, h in [(1.0, 1.0, 1.0, 1.0), (2.0, 1.5, 0.7, 0.3)]:
        theta, dtheta = q.theta_from_phi(phi0, phi, dphi0, dphi)
        T_rot, V_rot = q.rotor_energies(theta, dtheta, m=m, r=r, g=g)
        T_q, U_q = q.qubit_energies(phi, dphi, m=m, r=r, g=g, hbar_over_2e=h)
        assert np.max(np.abs(T_rot - T_q)) < 1e-12 * max(1, np.max(T_rot))
        assert np.max(np.abs(V_rot - U_q)) < 1e-12
        assert np.max(np.abs(V_rot / g - potential_phi(phi[:, 0], phi[:, 1]))) < 1e-12


def test_identification_fails_off_the_special_point():
    phi, dphi, phi0, dphi0 = _random_states(200, seed=1)
    theta, dtheta = q.theta_from_phi(phi0, phi, dphi0, dphi)
    T_rot, V_rot = q.rotor_energies(theta, dtheta)
    for kw in ({"alpha": 0.8}, {"f": 0.1}, {"gamma": 0.2}):
        T_q, U_q = q.qubit_energies(phi, dphi, **kw)
        assert max(np.max(np.abs(T_rot - T_q)), np.max(np.abs(V_rot - U_q))) > 1e-3
    # Mooij's own sign of phi2 gives the potential at (phi1, -phi2)
    U_m = q.josephson_energy(phi[:, 0], -phi[:, 1], mooij_sign=True)
    assert np.max(np.abs(U_m - V_rot)) < 1e-12


@pytest.mark.parametrize("E", [0.5, 2.0, 3.5, 3.9, 4.2, 5.0, 7.0, 12.0])
def test_lame_trace_formula_matches_monodromy(E):
    h, k2, m1, w = lf.lame_parameters(E)
    L = lf.lame_solutions(h, k2, w, m1, c_norm=1.7, s_norm=0.4)
    assert abs(L.Ls0) == 0 and abs(L.dLc0) == 0
    assert abs(lf.trace_from_lame(L) - monodromy(pendulum(E)).trace_transverse) < 1e-9


def test_mathieu_limit():
    diffs = []
    for k2 in (0.04, 0.02, 0.01):
        L = lf.lame_solutions(1.0, k2, 2 * np.pi)
        M = lf.mathieu_solutions(1.0 - lf.N_N1 * k2 / 2, -lf.N_N1 * k2 / 4, 2 * np.pi)
        diffs.append(max(abs(L.Lcw - M.Lcw), abs(L.dLsw - M.dLsw)))
    # the solutions differ by O(k^4): halving k^2 divides the difference by ~4
    assert 3.5 < diffs[0] / diffs[1] < 4.5 and 3.5 < diffs[1] / diffs[2] < 4.5
