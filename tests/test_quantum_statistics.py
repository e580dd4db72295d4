"""Statistics of rotorlib.beyond.quantum_statistics on synthetic spectra with known answers."""

import math

import numpy as np
import pytest

from rotorlib.beyond import quantum_statistics as qs
from rotorlib.beyond.quantum_semiclassics import R_GOE, R_POISSON


def poisson(n, seed=0):
    return np.cumsum(np.random.default_rng(seed).exponential(size=n))


def goe(n_mat=40, size=200, seed=0):
    """Central halves of GOE matrices, unfolded with the semicircle (unit mean spacing)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_mat):
        a = rng.normal(size=(size, size))
        w = np.linalg.eigvalsh((a + a.T) / math.sqrt(2 * size))  # semicircle radius 2
        w = w[size // 4 : 3 * size // 4]
        N = size * (0.5 + (w * np.sqrt(4 - w * w) / 4 + np.arcsin(w / 2)) / math.pi)
        out.append(N)
    return out


def test_ratio_poisson_and_goe():
    p = qs.ratio_windows([poisson(6000)], [0.0, 1e9])
    g = qs.ratio_windows(goe(), [-1.0, 1e9])
    assert abs(p.mean[0] - R_POISSON) < 3 * p.error[0]
    assert abs(g.mean[0] - R_GOE) < 3 * g.error[0]
    assert g.mean[0] - p.mean[0] > 10 * (p.error[0] + g.error[0])  # can fail


def test_bootstrap_sees_correlation():
    """An AR(1) series with correlation 0.5: the true standard error of the mean is
    sqrt(3) times the iid one; the block bootstrap finds it, the iid one does not."""
    rng = np.random.default_rng(3)
    e = rng.normal(size=20000)
    x = np.empty_like(e)
    x[0] = e[0]
    for i in range(1, len(e)):
        x[i] = 0.5 * x[i - 1] + math.sqrt(0.75) * e[i]
    iid = x.std() / math.sqrt(len(x))
    blk = qs.block_bootstrap(x, block=40, n_boot=400)
    assert abs(qs.lag_correlation(x) - 0.5) < 0.03
    assert abs(blk / iid - math.sqrt(3)) < 0.25
    assert abs(qs.block_bootstrap(x, block=1, n_boot=400) / iid - 1) < 0.15


def test_ratio_windows_bootstrap_larger_than_iid():
    """Real ratios are correlated (they share a spacing): bootstrap > iid error."""
    w = qs.ratio_windows(goe(60, 400), [-1.0, 1e9], block=5, n_boot=2000)
    assert 0.15 < w.lag1[0] < 0.35
    assert w.error[0] > 1.06 * w.iid_error[0]


def test_berry_robnik_limits_and_normalisation():
    from scipy.integrate import quad

    for rho in (0.0, 0.3, 1.0):
        norm = quad(lambda s: qs.berry_robnik_pdf(s, rho)[0], 0, np.inf)[0]
        mean = quad(lambda s: s * qs.berry_robnik_pdf(s, rho)[0], 0, np.inf)[0]
        assert abs(norm - 1) < 1e-8 and abs(mean - 1) < 1e-8
    s = np.linspace(0, 3, 7)
    assert np.allclose(qs.berry_robnik_pdf(s, 1.0), np.exp(-s))
    wig = math.pi * s / 2 * np.exp(-math.pi * s * s / 4)
    assert np.allclose(qs.berry_robnik_pdf(s, 0.0), wig)


def test_fit_berry_robnik_recovers_known_fractions():
    p = qs.fit_berry_robnik(np.diff(poisson(3000, 1)), n_boot=30)
    g = qs.fit_berry_robnik([np.diff(x) for x in goe()], n_boot=30)
    assert p.rho > 1 - 3 * p.error - 0.02
    assert g.rho < 3 * g.error + 0.05
    # a superposition: 40 % Poisson levels merged with 60 % GOE levels
    x = np.sort(np.concatenate([0.4 * poisson(2000, 5) / 0.4 * 1.0, goe(30)[0]]))
    assert 0.0 <= qs.fit_berry_robnik(np.diff(x), n_boot=20).rho <= 1.0


def test_number_variance_poisson_goe():
    L = np.array([1.0, 5.0, 10.0])
    sp = qs.number_variance(poisson(20000, 2), L)
    assert np.all(np.abs(sp / L - 1) < 0.15)
    sg = np.mean([qs.number_variance(x - x[0], L) for x in goe(60, 400)], axis=0)
    assert np.all(np.abs(sg - qs.sigma2_goe(L)) < 0.12)
    assert np.all(sg < 0.5 * sp)  # can fail: logarithmic against linear


def test_sigma2_closed_forms():
    L = np.array([20.0, 50.0])
    asym = (
        2 / math.pi**2 * (np.log(2 * math.pi * L) + np.euler_gamma + 1 - math.pi**2 / 8)
    )
    assert np.all(np.abs(qs.sigma2_goe(L) - asym) < 0.01)
    assert np.allclose(qs.sigma2_berry_robnik(L, 1.0), L)
    assert np.allclose(qs.sigma2_berry_robnik(L, 0.0), qs.sigma2_goe(L))
    assert qs.sigma2_goe(1e-6)[0] == pytest.approx(1e-6, rel=1e-3)  # extreme: L -> 0


def test_unfold_against_weyl():
    """Each sector holds d/12 of Weyl's count up to an O(1/hbar) term of its own (the
    reflection lines); the terms cancel in the whole spectrum."""
    from rotorlib.beyond.quantum import spectrum

    s = spectrum(0.1, 8.0)
    excess = {}
    for x in s.sectors:
        u = qs.unfold(x.levels, 0.1, x.sector)
        excess[x.sector] = len(x.levels) - u[-1]
    assert excess["A1"] > 10 and excess["A2"] < -10  # can fail: the sector term's sign
    total = sum(x.multiplicity * excess[x.sector] for x in s.sectors)
    assert abs(total) < 3
    xw, sw = qs.window_spacings(s.sector("A1").levels, 0.1, "A1", 5.0, 8.0)
    assert abs(sw.mean() - 1) < 1e-12 and xw[0] == 0


def test_bad_input():
    with pytest.raises(ValueError):
        qs.ratio_windows([[1.0, 2.0, 3.0]], [1.0, 0.0])
    with pytest.raises(ValueError):
        qs.block_bootstrap([1.0, 2.0], block=0)
    with pytest.raises(ValueError):
        qs.berry_robnik_pdf(1.0, 1.5)
    with pytest.raises(ValueError):
        qs.fit_berry_robnik([-1.0] * 20)
    with pytest.raises(ValueError):
        qs.number_variance([0.0, 1.0, 2.0], [5.0])
    with pytest.raises(ValueError):
        qs.unfold([1.0, 2.0], 0.1, "X9")
    with pytest.raises(ValueError):
        qs.window_spacings([1.0, 2.0], 0.1, "A1", 0.0, 3.0)
    with pytest.raises(ValueError):
        qs.lag_correlation([1.0, 2.0, 3.0], lag=5)
    with pytest.raises(ValueError):
        qs.regular_fraction([2.0, 1.0])
    with pytest.raises(ValueError):
        qs.regular_fraction([1.0], T=500.0, T_check=100.0)
    with pytest.raises(ValueError):
        qs.sigma2_goe([-1.0])


def test_regular_fraction_extremes():
    """Deep in the well the shell is regular; in the band it is chaotic."""
    r = qs.regular_fraction([0.5, 5.45], N=40, N_check=10, T=200.0, T_check=400.0)
    assert r.mu[0] == 1.0 and r.mu[1] < 0.2
    assert np.all(r.stat_error > 0) and np.all(r.error >= r.stat_error)
    mu, err = r.at([0.5, 3.0])
    assert mu[0] == 1.0 and 0 <= mu[1] <= 1
    with pytest.raises(ValueError):
        r.at(9.0)


def test_stored_products_are_complete():
    """The data products the chapter reads: mu_reg at >= 12 energies from 1 to 8, and the
    window statistics of every stored hbar with the predicted fraction beside them."""
    import json
    from pathlib import Path

    data = Path(__file__).resolve().parents[1] / "book" / "data"
    rf = qs.load_regular_fraction(data / "regular_fraction.json")
    assert len(rf.E) >= 12 and rf.E[0] <= 1.0 and rf.E[-1] >= 8.0
    assert np.all((rf.mu >= 0) & (rf.mu <= 1)) and np.all(rf.error > 0)
    rec = json.loads((data / "quantum_statistics.json").read_text())
    for r in rec["statistics"]:
        assert 0 <= r["rho"] <= 1 and r["r_error"] > 0 and np.isfinite(r["mu"])
    with pytest.raises(ValueError):
        qs.load_regular_fraction(data / "quantum_statistics.json")
