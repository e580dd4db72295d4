"""The trace formula with phases (rotorlib.beyond.quantum_trace).

The checks share no code with the module's path: the pendulum's action against its
elliptic-integral closed form, its Maslov index against the longitudinal rule (2 for a
libration, 0 for a rotation) plus the Conley-Zehnder index of Hill's transverse equation
integrated by scipy in fixed coordinates, and the frame construction against the exact
two-dimensional harmonic oscillator, whose trace formula is the Poisson sum of
``E = hbar w1 (n1 + 1/2) + hbar w2 (n2 + 1/2)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rotorlib
from rotorlib.beyond import quantum_signals as qg
from rotorlib.beyond import quantum_significance as qs
from rotorlib.beyond import quantum_trace as qt


def _hill_index(E, r_max=3):
    """CZ index of da1' = dp1/2, dp1' = -(4 + 2 cos a2) da1 along the pendulum, in the
    fixed coordinates (da1, dp1), by scipy (independent of heyoka and of the frame)."""
    o = rotorlib.orbit("pendulum", E)

    def rhs(t, y):
        a2, p2 = y[0], y[1]
        m = y[2:].reshape(2, 2)
        A = np.array([[0.0, 0.5], [-(4.0 + 2.0 * math.cos(a2)), 0.0]])
        return np.concatenate([[1.5 * p2, -2.0 * math.sin(a2)], (A @ m).ravel()])

    ts = np.linspace(0.0, o.period, 2001)
    sol = solve_ivp(
        rhs,
        (0.0, o.period),
        np.concatenate([[0.0, o.state0[3]], np.eye(2).ravel()]),
        t_eval=ts,
        rtol=1e-12,
        atol=1e-12,
    )
    mats = sol.y[2:].T.reshape(-1, 2, 2)
    return o, qt.conley_zehnder(mats, r_max)


@pytest.mark.parametrize("E", [0.3, 2.0, 3.0, 3.9, 4.3, 5.45, 7.0, 20.0])
def test_pendulum_action_and_maslov_against_closed_form(E):
    o, hill = _hill_index(E)
    S = qt.orbit_action(o.state0, o.period)
    assert abs(S - qt.pendulum_action(E)) < 1e-11 * S
    longitudinal = 2 if E < 4 else 0  # two turning points / none
    expected = tuple(h + r * longitudinal for r, h in enumerate(hill, start=1))
    assert qt.maslov_index(o.state0, o.period, 3) == expected


def test_pendulum_action_derivative_is_the_period():
    for E in (1.0, 3.5, 4.7, 9.0):
        d = 1e-5
        dS = (qt.pendulum_action(E + d) - qt.pendulum_action(E - d)) / (2 * d)
        assert abs(dS - rotorlib.orbit("pendulum", E).period) < 1e-7


def test_pendulum_small_and_large_energy_limits():
    # harmonic limit: S = 2 pi E / sqrt 3; fast rotation: S -> 2 pi sqrt(4 E/3)
    assert (
        abs(qt.pendulum_action(1e-9) / (2 * math.pi * 1e-9 / math.sqrt(3)) - 1) < 1e-8
    )
    E = 1e6
    assert abs(qt.pendulum_action(E) / (2 * math.pi * math.sqrt(4 * E / 3)) - 1) < 1e-5
    # index: near the bottom the transverse motion turns by just over 2 pi (5 = 2 + 3),
    # at high energy by less than pi (rotation: 1)
    o = rotorlib.orbit("pendulum", 0.3)
    assert qt.maslov_index(o.state0, o.period) == (5,)
    o = rotorlib.orbit("pendulum", 40.0)
    assert qt.maslov_index(o.state0, o.period, 2) == (1, 1)


@pytest.mark.parametrize("w2", [0.7, 1.3, 2.6, 3.3])
def test_harmonic_oscillator_frame_index_is_exact(w2):
    """H = (p1^2 + p2^2)/2 + (q1^2 + w2^2 q2^2)/2, the orbit along q1 (period 2 pi): the
    Poisson sum of the exact levels gives sigma_r = 2 r + 2 floor(r w2) + 1."""
    T = 2 * math.pi
    ts = np.linspace(0.0, T, 801)
    mats = []
    for t in ts:
        f = np.array([-math.sin(t), 0.0, -math.cos(t), 0.0])  # q1 = cos t, p1 = -sin t
        c, s = math.cos(w2 * t), math.sin(w2 * t)
        Phi = np.eye(4)
        Phi[np.ix_([0, 2], [0, 2])] = [
            [math.cos(t), math.sin(t)],
            [-math.sin(t), math.cos(t)],
        ]
        Phi[np.ix_([1, 3], [1, 3])] = [[c, s / w2], [-w2 * s, c]]
        mats.append(
            qt.transverse_frame(f) @ Phi @ qt.transverse_frame([0, 0, -1.0, 0]).T
        )
    got = qt.conley_zehnder(mats, 3)
    assert got == tuple(2 * r + 2 * math.floor(r * w2) + 1 for r in (1, 2, 3))


def test_hyperbolic_path_index_counts_half_turns():
    # m(t) = R(pi t) diag(e^t, e^-t): one full turn and a hyperbolic end: index 2
    mats = []
    for t in np.linspace(0.0, 2.0, 200):
        R = np.array(
            [
                [math.cos(math.pi * t), math.sin(math.pi * t)],
                [-math.sin(math.pi * t), math.cos(math.pi * t)],
            ]
        )
        mats.append(R @ np.diag([math.exp(t), math.exp(-t)]))
    assert qt.conley_zehnder(mats, 3) == (2, 4, 6)


def test_transverse_path_reduces_the_monodromy():
    o = rotorlib.orbit("R", 5.45)
    t, m, th = qt.transverse_path(o.state0, o.period)
    assert abs(np.linalg.det(m[-1]) - 1) < 1e-9
    assert abs(np.trace(m[-1]) - (o.trace - 2)) < 1e-8 * abs(o.trace)
    assert t[0] == 0 and abs(t[-1] - o.period) < 1e-12


def test_orbit_term_and_symmetry():
    o = rotorlib.orbit("pendulum", 3.0)
    tm = qt.orbit_term("pendulum", 3.0, o.period, o.state0, o.trace, 2)
    assert tm.copies == 3 and len(tm.stabiliser) == 8  # three pendula, self-retracing
    o6 = rotorlib.orbit("pendulum", 6.0)
    assert len(qt.orbit_symmetry(o6.state0, o6.period)) == 4  # rotations: 6 images
    assert tm.maslov == (5, 9)
    back = qt.OrbitTerm.from_dict(tm.to_dict())
    assert back == tm
    assert abs(tm.amplitude(1) - 3 * o.period / math.sqrt(abs(4 - o.trace))) < 1e-12


def test_signals_agree_for_one_orbit_with_its_phase():
    tm = qt.OrbitTerm("x", 2.0, 3.0, 1.234, 30.0, (3, 6), 1)
    t = np.linspace(2.0, 4.0, 401)
    s = qg.semiclassical_signal([tm], 2.0, 0.2, 0.05, t, 1)
    k = np.argmax(np.abs(s))
    assert abs(t[k] - 3.0) < 0.01
    assert (
        abs(np.angle(s[k]) - np.angle(np.exp(1j * (1.234 / 0.05 - 1.5 * math.pi))))
        < 1e-9
    )
    # the 2-d oscillator (w1 = 1, w2 = 1.37): its trace formula is exact; two orbits
    # with S = 2 pi E/w, sigma_r = 2 r + 2 floor(r w'/w) + 1, tr M = 2 + 2 cos(2 pi w'/w)
    h, w2, E0, sig = 0.01, 1.37, 2.0, 0.2
    n = np.arange(0, 700)
    levels = (h * (n[:, None] + 0.5) + h * w2 * (n[None, :] + 0.5)).ravel()
    terms = []
    for w, v in ((1.0, w2), (w2, 1.0)):
        sigma = tuple(2 * r + 2 * math.floor(r * v / w) + 1 for r in (1, 2))
        tr = 2 + 2 * math.cos(2 * math.pi * v / w)
        terms.append(
            qt.OrbitTerm("ho", E0, 2 * math.pi / w, 2 * math.pi * E0 / w, tr, sigma)
        )
    tt = np.linspace(3.5, 7.5, 201)
    q = qg.quantum_signal(levels, E0, sig, h, tt)
    sc = qg.semiclassical_signal(terms, E0, sig, h, tt, 2)
    assert np.max(np.abs(q - sc)) < 1e-6 * np.max(np.abs(q))
    wrong = [qt.OrbitTerm("ho", E0, x.period, x.action, x.trace, (0, 0)) for x in terms]
    assert np.max(np.abs(q - qg.semiclassical_signal(wrong, E0, sig, h, tt, 2))) > 0.5


def test_smoothed_density_of_the_oscillator_is_exact():
    """2-d oscillator (w1 = 1, w2 = 1.37): smoothed density minus its smooth part
    (E/hbar^2 w2 at this smoothing, exactly linear) against the two orbits' terms."""
    h, w2, gam = 0.01, 1.37, 0.004
    n = np.arange(0, 700)
    levels = (h * (n[:, None] + 0.5) + h * w2 * (n[None, :] + 0.5)).ravel()
    E = np.linspace(1.9, 2.1, 41)
    terms = []
    for w, v in ((1.0, w2), (w2, 1.0)):
        sigma = tuple(2 * r + 2 * math.floor(r * v / w) + 1 for r in range(1, 6))
        tr = 2 + 2 * math.cos(2 * math.pi * v / w)
        terms.append(
            qt.OrbitTerm("ho", 2.0, 2 * math.pi / w, 2 * math.pi * 2.0 / w, tr, sigma)
        )
    smooth = E / (h * h * w2)
    osc = qg.smoothed_density(levels, E, gam) - smooth
    pred = qg.smoothed_oscillation(terms, E, gam, h, 5)
    assert np.max(np.abs(osc - pred)) < 0.02 * np.max(np.abs(pred))
    assert qs.signal_correlation(osc, pred) > 0.999


def test_match_and_correlation_tests_can_fail():
    rng = np.random.default_rng(5)
    peaks = np.sort(rng.uniform(1, 10, 20))
    random_periods = rng.uniform(1, 10, 6)
    m = qs.match_test(peaks, random_periods, 0.05, (1.0, 10.0), 2000)
    assert m.p_value > 0.05  # random "orbits" explain no more than chance
    m = qs.match_test(peaks, peaks[:6] + 0.01, 0.05, (1.0, 10.0), 2000)
    assert m.explained == 6 and m.p_value < 0.01
    t = np.linspace(1.0, 10.0, 901)
    terms = [
        qt.OrbitTerm("x", 1.0, float(p), 0.1 * k, 30.0, (1,), 1)
        for k, p in enumerate(random_periods)
    ]
    q = qg.semiclassical_signal(terms, 1.0, 0.1, 0.02, t, 1)
    c = qs.correlation_test(q, terms, 1.0, 0.1, 0.02, t, 1, draws=200)
    assert c.value > 0.999 and c.p_value < 0.01
    decoy = [
        qt.OrbitTerm("y", 1.0, float(p), 0.0, 30.0, (1,), 1)
        for p in rng.uniform(1, 10, 6)
    ]
    c = qs.correlation_test(q, decoy, 1.0, 0.1, 0.02, t, 1, draws=200)
    assert c.p_value > 0.05


def test_bad_input():
    with pytest.raises(ValueError):
        qt.orbit_action([0, 0, 0], 1.0)
    with pytest.raises(ValueError):
        qt.orbit_action([0, 0, 0, 1.0], -1.0)
    with pytest.raises(ValueError):
        qt.pendulum_action(4.0)
    with pytest.raises(ValueError):
        qt.pendulum_action(-1.0)
    with pytest.raises(ValueError):
        qt.transverse_frame([0, 0, 0, 0])
    with pytest.raises(ValueError):
        qt.conley_zehnder(np.eye(2)[None], 1)
    with pytest.raises(ValueError):
        qt.conley_zehnder([np.eye(2), np.eye(2)], 1)  # marginal end
    with pytest.raises(ValueError):
        qt.maslov_index([0, 0, 0, 1.0], 1.0, 0)
    with pytest.raises(ValueError):
        qs.match_test([1.0], [1.0], 0.1, (2.0, 1.0))
    with pytest.raises(ValueError):
        qg.quantum_signal([1.0], 1.0, 0.0, 0.1, [0.0])
    with pytest.raises(ValueError):
        qs.signal_correlation([1.0, 2.0], [1.0])
    with pytest.raises(ValueError):
        qs.correlation_test([1.0], [], 1.0, 0.1, 0.02, [1.0])
    tm = qt.OrbitTerm("x", 2.0, 3.0, 1.0, 30.0, (1,), 1)
    with pytest.raises(ValueError):
        qg.semiclassical_signal([tm], 3.0, 0.2, 0.05, [1.0])


def test_mirror_relative_orbit_of_the_oscillator_is_exact():
    """q2 -> -q2 fixes the q1-orbit of the 2-d oscillator pointwise: the even levels
    minus the odd ones (n2 even/odd) are its relative orbit, monodromy -M, with the index
    of reflection_term."""
    h, w2, E0, sig = 0.01, 1.37, 2.0, 0.2
    n = np.arange(0, 700)
    E = h * (n[:, None] + 0.5) + h * w2 * (n[None, :] + 0.5)
    chi = 2 * math.pi * w2
    M = np.array(
        [[math.cos(chi), math.sin(chi) / w2], [-w2 * math.sin(chi), math.cos(chi)]]
    )
    sigma = tuple(2 * r + 2 * math.floor(r * w2) + 1 for r in (1,))
    amp, sig_t = qt.reflection_term(M, sigma)
    T, S = 2 * math.pi, 2 * math.pi * E0
    t = np.linspace(
        5.9, 6.6, 71
    )  # away from the q2-orbit relative ones, (m + 1/2) 4.59
    diff = qg.quantum_signal(E[:, 0::2].ravel(), E0, sig, h, t) - qg.quantum_signal(
        E[:, 1::2].ravel(), E0, sig, h, t
    )
    pred = T * amp[0] * np.exp(1j * (S / h - sig_t[0] * math.pi / 2))
    pred = pred * np.exp(-((t - T) ** 2) * sig**2 / (2 * h * h))
    assert np.max(np.abs(diff - pred)) < 1e-6 * np.max(np.abs(diff))
    assert sig_t[0] != sigma[0]  # the stationary-phase term does change here


def test_classes_and_mirrors():
    from collections import Counter

    from rotorlib.orbits.reversors import symmetry_group

    got = Counter(qt.element_class(g) for g in symmetry_group())
    assert got == {"E": 1, "C6": 2, "C3": 2, "C2": 1, "sv": 3, "sd": 3}
    for sector, chi in qt.CHARACTERS.items():  # orthogonality over the 12 elements
        for other, psi in qt.CHARACTERS.items():
            s = sum(
                chi[qt.element_class(g)] * psi[qt.element_class(g)]
                for g in symmetry_group()
            )
            assert s == (12 if sector == other else 0)
    o = rotorlib.orbit("pendulum", 5.45)
    assert qt.mirror_classes(o.state0, o.period) == ("sv",)
    o = rotorlib.orbit("R", 5.45)
    assert qt.mirror_classes(o.state0, o.period) == ("sd",)
    o = rotorlib.orbit("CG", 3.0)
    assert qt.mirror_classes(o.state0, o.period) == ()
    with pytest.raises(ValueError):
        qt.element_class([[2, 0], [0, 1]])
    with pytest.raises(ValueError):
        qt.reflection_term(np.eye(3), (1,))
    with pytest.raises(ValueError):
        qg.sector_signal([], "X", 1.0, 0.1, 0.02, [1.0])


def test_signal_on_a_uniform_grid_equals_the_direct_sum():
    """The phases advanced by multiplication on a uniform grid of times (anchored every
    64 steps) equal one exponential per term to 1e-13 of sum |w|, at the extremes: many
    levels, long times (phases ~1e5 rad), and a grid that is not uniform (direct sum)."""
    rng = np.random.default_rng(5)
    E = np.sort(rng.uniform(4.0, 7.0, 20000))
    h, E0, s = 0.01, 5.45, 0.3
    t = np.linspace(1.0, 200.0, 700)  # uniform: the fast route
    t_odd = t.copy()
    t_odd[1] += 1e-9  # not uniform: the direct route, the same times but one
    fast, direct = (qg.quantum_signal(E, E0, s, h, x) for x in (t, t_odd))
    scale = math.sqrt(2 * math.pi) * h / s * np.exp(-0.5 * ((E - E0) / s) ** 2).sum()
    keep = np.arange(len(t)) != 1
    assert np.max(np.abs(fast[keep] - direct[keep])) < 1e-13 * scale
    assert abs(fast[1] - direct[1]) > 1e-9 * abs(fast[1])  # the perturbed time differs
