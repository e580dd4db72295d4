"""Spectrum slicing (rotorlib.beyond.quantum_solver) and the stored spectra
(rotorlib.beyond.quantum_data, book/data/quantum/): each data product is checked by
recomputing one window, never whole; the independent check at hbar = 0.01 is asserted
from its stored result (scripts/quantum_independent.py) and re-run here on a small case.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from rotorlib.beyond import quantum as q
from rotorlib.beyond import quantum_data as qd
from rotorlib.beyond import quantum_semiclassics as sc
from rotorlib.beyond import quantum_solver as qs

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

import quantum_independent as qi  # noqa: E402

HBARS = qd.stored_hbars()


def _random_sparse(n, seed):
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=8 / n, random_state=rng)
    return (A + A.T + sp.diags(np.linspace(0.0, 10.0, n))).tocsc()


@pytest.mark.parametrize("seed", [1, 2])
def test_windows_equal_dense_on_a_random_matrix(seed):
    """All eigenvalues in [0, 8) of a random sparse symmetric matrix, window by window,
    equal dense LAPACK to 1e-11, none lost or doubled."""
    A = _random_sparse(900, seed)
    ref = np.linalg.eigvalsh(A.toarray())
    ref = ref[(ref >= 0.0) & (ref < 8.0)]
    edges = np.linspace(0.0, 8.0, 13)
    edges[0] = 0.0
    n0 = qs.count_below(A, 0.0)
    counts = [qs.count_below(A, x) for x in edges]
    out = []
    for i in range(12):
        out.append(
            qs.window_levels(A, edges[i], edges[i + 1], counts[i], counts[i + 1])
        )
    lev = np.concatenate([w.levels for w in out])
    assert len(lev) == len(ref) == counts[-1] - n0 > 300
    assert np.max(np.abs(lev - ref)) < 1e-11
    assert max(w.residuals.max() for w in out if len(w.levels)) < qs.RESIDUAL_TOL


def test_inertia_count_and_failure():
    A = sp.diags(np.arange(1.0, 101.0) + 0.5).tocsc()
    assert qs.count_below(A, 10.0) == 9 and qs.count_below(A, 0.0) == 0
    with pytest.raises(qs.SlicingFailed):  # a wrong count cannot be matched
        qs.window_levels(A, 10.0, 20.0, 9, 20)


def test_sliced_equals_dense_and_error_estimates(monkeypatch):
    """A block forced through the slicing path: its levels equal the dense route to
    1e-11, and each level's estimated change when the cut-off is lowered is within a
    factor 3 of the measured change (median within 30%; where it exceeds round-off; a
    small cut-off, so that the changes are large)."""
    hbar, E_max, K = 0.08, 5.0, 6.0
    dense = q.sector_spectrum(hbar, "A2", E_max, cutoff=K)
    assert dense.method == "dense dsyevr"
    monkeypatch.setattr(q, "DENSE_MAX", 50)
    sliced = q.sector_spectrum(hbar, "A2", E_max, cutoff=K)
    assert sliced.method.startswith("shift-invert")
    assert len(sliced.levels) == len(dense.levels) > 60
    assert np.max(np.abs(sliced.levels - dense.levels)) < 1e-11
    meas = dense.errors  # measured: both bases dense
    sel = meas > 1e-11
    assert sel.sum() > 10
    ratio = sliced.errors[sel] / meas[sel]
    assert np.all((ratio > 0.5) & (ratio < 3.0)) and 0.9 < np.median(ratio) < 1.3
    assert np.isfinite(sliced.top_check) and sliced.top_check < 2 * dense.convergence


def test_library_refuses_a_basis_too_large():
    with pytest.raises(ValueError, match="would not fit in memory"):
        q.sector_spectrum(1e-5, "A1", 6.0)


def test_spectrum_progress_off_by_default(capsys):
    q.spectrum(0.3, 3.0, progress=True)  # not a terminal: no bar
    assert capsys.readouterr().err == ""


# ---------------------------------------------------------------- the data products
def test_every_hbar_is_stored():
    assert set(HBARS) >= {0.03, 0.02}


@pytest.mark.parametrize("hbar", HBARS)
def test_stored_spectrum_is_complete(hbar):
    """Every sector stored, sorted, each level with its error; below E = 8 the count
    with multiplicity follows Weyl's law (with its correction) to 1%."""
    s = qd.stored_spectrum(hbar)
    assert [x.sector for x in s.sectors] == list(q.SECTORS)
    for x in s.sectors:
        assert len(x.levels) == len(x.errors) == len(x.residuals) > 0
        assert np.all(np.diff(x.levels) > 0) and x.levels[-1] < x.E_max
        assert x.convergence < 1e-9 and x.residuals.max() < 1e-10
    n = len(s.levels)
    assert abs(n - sc.weyl_count(s.E_max, hbar)) < 0.01 * n


@pytest.mark.parametrize("hbar", HBARS)
def test_stored_window_recomputed(hbar):
    """One window of stored levels per hbar (A1 near E = 5.45, in the band; 50 levels,
    30 below hbar = 0.02 so that the larger blocks stay a few seconds of CPU: 7 s at
    hbar = 0.01, measured), recomputed from a fresh block: the same count, the same
    levels to 1e-8."""
    n = 50 if hbar >= 0.02 else 30
    k, d = qd.recheck(hbar, "A1", 5.45, n=n)
    assert k == n and d < 1e-8


def test_loader_refuses_bad_input():
    with pytest.raises(ValueError, match="no stored spectrum"):
        qd.stored_spectrum(0.123)
    with pytest.raises(ValueError, match="unknown sector"):
        qd.stored_spectrum(0.03, "T2")
    with pytest.raises(ValueError, match="hbar must be a number"):
        qd.stored_spectrum("x")


def test_cost_is_recorded():
    cost = qd.stored_cost()
    for h in HBARS:
        rec = cost[f"{h:g}"]
        assert rec["cpu_seconds"] > 0 and set(rec["sectors"]) == set(q.SECTORS)
        assert all(v["peak_MiB"] > 0 for v in rec["sectors"].values())


# ---------------------------------------------------------------- independent check
def test_independent_check_at_hbar_001_stored():
    """The lowest 200 A1 levels at hbar = 0.01 and those in a window at E ~ 5.45 agree
    with the independent diagonalization (scripts/quantum_independent.py) to 1e-8."""
    p = ROOT / "book" / "data" / "quantum" / "independent_check.json"
    rec = json.loads(p.read_text())
    assert rec["hbar"] == 0.01 and rec["low_count"] == 200
    assert rec["low_max_difference"] < 1e-8
    assert rec["window_count_library"] == rec["window_count_reference"] >= 40
    assert rec["window_max_difference"] < 1e-8
    assert rec["window_edges"][0] < 5.45 < rec["window_edges"][1]


def test_independent_reference_small_case():
    """The independent reference itself (small case, here): at hbar = 0.03, the 20 A1
    levels nearest 5.45 agree with the stored product to 1e-8."""
    ref = qi.reference(0.03, 5.45, 20, 5.6)
    lev = qd.stored_spectrum(0.03, "A1").levels
    mine = lev[(lev > ref[0] - 1e-9) & (lev < ref[-1] + 1e-9)]
    assert len(mine) == 20 and np.max(np.abs(mine - ref)) < 1e-8
