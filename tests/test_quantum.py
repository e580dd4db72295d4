"""The quantum 3-rotor (rotorlib.beyond.quantum, rotorlib.beyond.quantum_semiclassics, `spectrum`).

The reference diagonalizations here share no code with the library: the Hamiltonian is
built in the rotor wave numbers k = (k1, k2, k3), sum k = 0 (kinetic hbar^2 |k|^2 / 2,
V = 3 - sum_{i<j} cos(theta_i - theta_j) shifting k by +-(e_i - e_j)), either in full
(dense numpy eigvalsh) or on the totally symmetric orbit sums (A1) labelled by sorted k.
"""

from __future__ import annotations

import itertools
import json
import math
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from rotorlib.beyond import quantum as q
from rotorlib.beyond import quantum_semiclassics as sc

SHIFTS = [
    np.array(d)
    for a, b in itertools.permutations(range(3), 2)
    for d in [np.eye(3, dtype=int)[a] - np.eye(3, dtype=int)[b]]
]


def _k_lattice(hbar, cutoff):
    r = int(math.sqrt(2 * cutoff) / hbar) + 1
    out = []
    for k1 in range(-r, r + 1):
        for k2 in range(-r, r + 1):
            k = (k1, k2, -k1 - k2)
            if hbar * hbar * (k1 * k1 + k2 * k2 + k[2] ** 2) / 2 <= cutoff:
                out.append(k)
    return out


def _reference_cutoff(hbar, E_max):
    return E_max + 1.0 + 45.0 * hbar


def independent_full(hbar, E_max):
    """Every level below E_max (with multiplicities): dense eigvalsh of the full matrix."""
    ks = _k_lattice(hbar, _reference_cutoff(hbar, E_max))
    index = {k: i for i, k in enumerate(ks)}
    H = np.zeros((len(ks), len(ks)))
    for k, i in index.items():
        H[i, i] = 3.0 + hbar * hbar * sum(x * x for x in k) / 2
        for d in SHIFTS:
            j = index.get(tuple(np.array(k) + d))
            if j is not None:
                H[i, j] = -0.5
    w = np.linalg.eigvalsh(H)
    return w[w <= E_max]


def _canonical(k):
    return max(tuple(sorted(k)), tuple(sorted(-x for x in k)))


def independent_A1(hbar, E_max):
    """The A1 levels: H on the normalized sums over orbits of S3 x Z2 (sorted k)."""
    orbits = {}
    for k in _k_lattice(hbar, _reference_cutoff(hbar, E_max)):
        orbits.setdefault(_canonical(k), []).append(k)
    names = list(orbits)
    index = {c: i for i, c in enumerate(names)}
    H = np.zeros((len(names), len(names)))
    for c, i in index.items():
        size = len(orbits[c])
        H[i, i] += 3.0 + hbar * hbar * sum(x * x for x in c) / 2
        for d in SHIFTS:
            nb = _canonical(tuple(np.array(c) + d))
            j = index.get(nb)
            if j is not None:
                H[i, j] -= 0.5 * size / math.sqrt(size * len(orbits[nb]))
    w = np.linalg.eigvalsh(H)
    return w[w <= E_max]


def cli(*args):
    p = subprocess.run(
        [sys.executable, "-m", "rotorlib", "spectrum", *args],
        capture_output=True,
        text=True,
        timeout=600,
    )
    return p.returncode, p.stdout, p.stderr


CASES = [(0.5, 6.5), (0.2, 4.0), (0.1, 2.0)]


@pytest.mark.parametrize("hbar,E_max", CASES)
def test_cli_all_and_A1_against_independent(hbar, E_max):
    """`spectrum --sector all` and `--sector A1` agree with the references to 1e-9,
    with the same counts (and the references' own levels are not within 1e-9 of E_max)."""
    ref_all, ref_A1 = independent_full(hbar, E_max), independent_A1(hbar, E_max)
    for sector, ref in (("all", ref_all), ("A1", ref_A1)):
        rc, out, err = cli(
            "--hbar", str(hbar), "--sector", sector, "--E-max", str(E_max), "--json"
        )
        assert rc == 0, err
        rec = json.loads(out)
        assert rec["decimals"] >= 10 and rec["convergence"] < 1e-10
        levels = np.repeat(rec["levels"], rec["multiplicities"])
        assert rec["count"] == len(levels) == len(ref) > 0
        assert np.max(np.abs(levels - ref)) < 1e-9


def test_A1_at_hbar_003_against_independent():
    """The A1 spectrum at hbar = 0.03 below E = 8 (about 1,700 levels, solved by
    spectrum slicing and stored as a data product) agrees with the dense orbit-sum
    reference to 1e-9. The stored levels are the solver's: tests/test_quantum_data.py
    re-solves a window of every stored hbar and compares (CI time: the whole A1 solve
    costs ~100 s, the reference ~10 s)."""
    from rotorlib.beyond import quantum_data as qd

    s = qd.stored_spectrum(0.03, "A1")
    ref = independent_A1(0.03, 8.0)
    assert len(s.levels) == len(ref) > 1600
    assert np.max(np.abs(s.levels - ref)) < 1e-9
    assert s.convergence < 1e-9


def test_two_dimensional_sectors_are_doubly_degenerate():
    """Both rows of E1 and E2 give the same levels, and in the full reference spectrum
    each of their levels appears twice, each A/B level once."""
    hbar, E_max = 0.2, 4.0
    ref = independent_full(hbar, E_max)
    s = q.spectrum(hbar, E_max)
    for sec in ("E1", "E2"):
        other = q.sector_spectrum(hbar, sec, E_max, row=1).levels
        assert np.max(np.abs(other - s.sector(sec).levels)) < 1e-12
    for x in s.sectors:
        for E in x.levels:
            assert np.sum(np.abs(ref - E) < 1e-9) == x.multiplicity
    assert sum(len(x.levels) * x.multiplicity for x in s.sectors) == len(ref)


def test_zero_point_energy_and_resonance_splitting():
    """Ground level hbar sqrt 3 - hbar^2/8 + O(hbar^3); the lowest harmonic shells
    (1:1 resonance) split as the normal form predicts, to O(hbar^3): shell 1 is one E1
    pair, shell 2 is A1 + an E2 pair."""
    for hbar in (0.04, 0.02):
        s = q.spectrum(hbar, 4.3 * math.sqrt(3) * hbar)
        E = s.levels
        assert abs(E[0] - sc.zero_point_energy(hbar)) < 0.02 * hbar**3
        assert abs(E[0] - math.sqrt(3) * hbar) > 0.1 * hbar**2  # the correction shows
        pred = np.sort(np.concatenate(sc.harmonic_levels(hbar, 3)))
        assert len(E) == len(pred) == 10
        assert np.max(np.abs(E - pred)) < 0.5 * hbar**3
        labels = [x.sector for x in s.sectors for _ in x.levels]
        order = np.argsort(np.concatenate([x.levels for x in s.sectors]))
        labels = [labels[i] for i in order]
        assert labels[:4] == ["A1", "E1", "A1", "E2"] or labels[:4] == [
            "A1",
            "E1",
            "E2",
            "A1",
        ]


def test_weyl_law():
    """N(E) follows Weyl's law with its first correction: at hbar = 0.1 the mean of
    N - N_Weyl over 0.5 < E < 7.9 is below one level, and N_Weyl without the
    correction misses the bottom by -1/12 (the isotropic oscillator)."""
    hbar = 0.1
    levels = q.spectrum(hbar, 8.0).levels
    E = np.linspace(0.5, 7.9, 149)
    N = np.searchsorted(levels, E, side="right")
    W = sc.weyl_count(E, hbar)
    assert abs(np.mean(N - W)) < 1.0
    assert np.max(np.abs(N - W)) < 0.02 * N.max()
    assert abs(sc.weyl_correction(1e-4) + 1 / 12) < 1e-3
    assert sc.weyl_correction(4.7) == 0.0


def test_ratio_statistic_limits():
    """<r> of Poisson levels is 2 ln 2 - 1 and of GOE matrices ~0.53."""
    rng = np.random.default_rng(1)
    pois = np.cumsum(rng.exponential(size=20000))
    st = sc.ratio_statistics([pois], [0, pois[-1] + 1])
    assert abs(st.mean[0] - sc.R_POISSON) < 4 * st.error[0]
    goe = []
    for _ in range(20):
        a = rng.normal(size=(200, 200))
        goe.append(np.linalg.eigvalsh(a + a.T)[50:150])
    st = sc.ratio_statistics(goe, [-1e9, 1e9])
    assert abs(st.mean[0] - sc.R_GOE) < 4 * st.error[0] + 0.005


def test_gutzwiller_amplitude_repetitions():
    M = np.array([[3.0, 1.0], [5.0, 2.0]])  # det 1, trace 5 (full trace 7)
    for r in (1, 2, 3):
        d = abs(np.linalg.det(np.linalg.matrix_power(M, r) - np.eye(2)))
        assert abs(sc.gutzwiller_amplitude(2.0, 7.0, r) - 2.0 / math.sqrt(d)) < 1e-12
    with pytest.raises(ValueError):
        sc.gutzwiller_amplitude(2.0, 4.0)


def test_density_fourier_peak_of_a_single_orbit():
    """A synthetic density with one oscillating term of period 3 gives a peak of the
    predicted height at t = 3."""
    hbar, T, A = 0.02, 3.0, 0.7
    E = np.linspace(4.5, 6.5, 40001)
    rho = 1 + A / (math.pi * hbar) * np.cos(E * T / hbar)
    # sample the density as a weighted sum over a fine grid (levels with weights)
    t = np.linspace(2.9, 3.1, 41)
    w = np.exp(-0.5 * ((E - 5.5) / 0.2) ** 2) * rho * (E[1] - E[0])
    F = np.abs(np.exp(-1j * np.outer(t, E - 5.5) / hbar) @ w)
    F *= math.sqrt(2 * math.pi) * hbar / 0.2
    assert abs(F.max() - A) < 1e-3 and abs(t[F.argmax()] - T) < 1e-9
    one = sc.density_fourier([5.5], 5.5, 0.2, hbar, [0.0])[0]
    assert abs(one - math.sqrt(2 * math.pi) * hbar / 0.2) < 1e-15


def test_sectors_through_a_process_pool():
    with ProcessPoolExecutor(2) as ex:
        a = q.spectrum(0.2, 3.0, executor=ex)
    b = q.spectrum(0.2, 3.0)
    assert np.array_equal(a.levels, b.levels)


def test_qubit_hbar():
    assert abs(sc.hbar_from_qubit(8.0 / 3.0) - 1.0) < 1e-15


@pytest.mark.parametrize(
    "args,needle",
    [
        (("--hbar", "0", "--sector", "A1", "--E-max", "2"), "--hbar must be > 0"),
        (("--hbar", "-0.1", "--sector", "A1", "--E-max", "2"), "--hbar must be > 0"),
        (("--hbar", "0.1", "--sector", "C3", "--E-max", "2"), "unknown sector"),
        (("--hbar", "1e-5", "--sector", "all", "--E-max", "6"), "plane waves"),
        (("--hbar", "0.1", "--sector", "A1", "--E-max", "-1"), "--E-max must be > 0"),
        (("--hbar", "x", "--sector", "A1", "--E-max", "2"), "--hbar must be a number"),
    ],
)
def test_cli_refuses_bad_input(args, needle):
    rc, out, err = cli(*args)
    assert rc == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and needle in err


def test_library_refuses_bad_input():
    with pytest.raises(ValueError, match="hbar"):
        q.sector_spectrum(0.0, "A1", 1.0)
    with pytest.raises(ValueError, match="sector"):
        q.sector_spectrum(0.1, "T2", 1.0)
    with pytest.raises(ValueError, match="float64"):
        q.sector_spectrum(0.1, "A1", 1.0, digits=20)
    with pytest.raises(ValueError, match="E_max"):
        q.spectrum(0.1, float("inf"))
    with pytest.raises(ValueError, match="edges"):
        sc.ratio_statistics([[1.0, 2.0]], [1.0])


def test_extremes_large_hbar_and_tiny_window():
    """hbar = 2 (deep quantum) and a window below the ground state (no level)."""
    s = q.spectrum(2.0, 10.0)
    assert s.levels[0] > 0 and s.convergence < 1e-9
    assert len(q.spectrum(0.1, 0.1).levels) == 0
