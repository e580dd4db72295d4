"""The quantum 3-rotor: the spectrum of the relative motion on the (phi1, phi2) torus.

Units g = m r^2 = 1 and one dimensionless Planck constant ``hbar`` (the physical one over
``sqrt(g m r^2)``). The relative Lagrangian of the paper (§2),
``L = (phi1'^2 + phi2'^2 + phi1' phi2')/3 - V`` has the mass matrix
``M = [[2, 1], [1, 2]]/3`` and the Hamiltonian ``H = P1^2 - P1 P2 + P2^2 + V`` with
``V = 3 - cos phi1 - cos phi2 - cos(phi1 + phi2)``. Quantized with ``P_j = -i hbar d/dphi_j``
on plane waves ``exp(i (n1 phi1 + n2 phi2))``:

    <n|H|n> = hbar^2 (n1^2 - n1 n2 + n2^2) + 3,     <n +- e|H|n> = -1/2
    for e = (1, 0), (0, 1), (1, 1).

In rotor wave numbers ``k = (n1, n2 - n1, -n2)`` (``sum k = 0``) the kinetic energy is
``hbar^2 |k|^2 / 2`` and the symmetry group S3 x Z2 (rotor permutations and the reflection
``theta -> -theta``, order 12, the point group C6v of the hexagonal lattice of ``k``) acts
by signed permutations of ``k``. Its irreducible representations:

====  =====================================  ==========================
name  S3 x Z2                                C6v characters (E C6 C3 C2 sv sd)
====  =====================================  ==========================
A1    trivial, even                          1  1  1  1  1  1
A2    sign, even                             1  1  1  1 -1 -1
B1    trivial, odd                           1 -1  1 -1  1 -1
B2    sign, odd                              1 -1  1 -1 -1  1
E1    two-dimensional, odd                   2  1 -1 -2  0  0
E2    two-dimensional, even                  2 -1 -1  2  0  0
====  =====================================  ==========================

("even/odd": under ``theta -> -theta``, i.e. C2; ``sv`` are the rotor transpositions,
``sd`` a transposition times the reflection.) Each block is the Hamiltonian on the
symmetry-adapted functions of one row of its irrep, built orbit by orbit of the lattice;
the levels of E1 and E2 are doubly degenerate in the full spectrum.

Precision: float64 throughout. The basis is every plane wave with kinetic energy
``hbar^2 |k|^2/2 <= cutoff``; the levels converge from above (nested bases, Cauchy
interlacing) and each level carries its change when the cut-off is lowered by
``cutoff_step(hbar)`` (``errors``; ``convergence`` is the largest, typically < 1e-11).
Blocks of up to ``DENSE_MAX`` functions are diagonalized by LAPACK ``dsyevr`` (both
bases); larger ones by spectrum slicing (:mod:`rotorlib.beyond.quantum_solver`: windows counted by
Sylvester inertia, shift-and-invert block Krylov, residual bounds per level). Checked
against independent diagonalizations in the rotor wave numbers (``tests/test_quantum.py``).
"""

from __future__ import annotations

import math
import os
from concurrent.futures import Executor
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..core.parallel import pmap
from ..core.precision import tier
from . import quantum_solver as qs
from .quantum_symmetry import DIMENSIONS, SECTORS, symmetry_basis

__all__ = [
    "SECTORS",
    "sector_block",
    "DIMENSIONS",
    "cutoff_step",
    "SectorSpectrum",
    "Spectrum",
    "plane_waves",
    "hamiltonian",
    "symmetry_basis",
    "sector_hamiltonian",
    "default_cutoff",
    "basis_size",
    "memory_estimate",
    "sector_spectrum",
    "spectrum",
]

#: Blocks up to this size use dense ``dsyevr``; larger ones spectrum slicing.
DENSE_MAX = 1500


def _check(hbar, E_max=None, sector=None, digits=None):
    tier(digits)  # validates digits
    if digits is not None and digits > 15:
        raise ValueError(
            f"the spectrum is computed in float64 only (at most 15 digits), not {digits}"
        )
    try:
        hbar = float(hbar)
    except (TypeError, ValueError):
        raise ValueError(f"hbar must be a positive number, not {hbar!r}") from None
    if not (math.isfinite(hbar) and hbar > 0):
        raise ValueError(f"hbar must be a positive finite number, not {hbar}")
    if E_max is not None:
        try:
            E_max = float(E_max)
        except (TypeError, ValueError):
            raise ValueError(f"E_max must be a number, not {E_max!r}") from None
        if not (math.isfinite(E_max) and E_max > 0):
            raise ValueError(f"E_max must be a positive finite energy, not {E_max}")
    if sector is not None and sector not in SECTORS:
        raise ValueError(
            f"unknown sector {sector!r}: choose one of {', '.join(SECTORS)}"
        )
    return hbar, E_max


# ---------------------------------------------------------------- the basis
def default_cutoff(hbar: float, E_max: float) -> float:
    """Kinetic-energy cut-off of the (smaller) plane-wave basis for levels below ``E_max``.

    ``E_max + 0.5 + 40 hbar``: beyond the classical kinetic energy ``E_max`` an
    eigenfunction decays in momentum space by a fixed factor per lattice step, and a
    step is worth ``~2 hbar sqrt(E)`` of kinetic energy, so the margin grows like
    ``hbar``. Measured to converge every level to < 1e-9 for ``0.02 <= hbar <= 0.5``,
    ``E_max <= 8`` (``convergence`` states it for each run).

    Examples
    --------
    >>> round(default_cutoff(0.1, 2.0), 3)
    6.5
    """
    return float(E_max) + 0.5 + 40.0 * float(hbar)


def cutoff_step(hbar: float) -> float:
    """Raise of the cut-off between the two bases of the convergence estimate:
    ``0.5 + 6 hbar``.

    Examples
    --------
    >>> cutoff_step(0.5)
    3.5
    """
    return 0.5 + 6.0 * float(hbar)


def plane_waves(hbar: float, cutoff: float) -> np.ndarray:
    """The wave numbers ``(n1, n2)`` with ``hbar^2 (n1^2 - n1 n2 + n2^2) <= cutoff``.

    Sorted by kinetic energy (then lexicographically); shape ``(N, 2)``, integers.
    ``N ~ (2 pi/sqrt 3) cutoff / hbar^2``.

    Examples
    --------
    >>> plane_waves(1.0, 1.0).tolist()
    [[0, 0], [-1, -1], [-1, 0], [0, -1], [0, 1], [1, 0], [1, 1]]
    """
    hbar, _ = _check(hbar)
    r = int(math.floor(math.sqrt(4.0 * cutoff / 3.0) / hbar)) + 1
    a = np.arange(-r, r + 1)
    n1, n2 = np.meshgrid(a, a, indexing="ij")
    q = n1 * n1 - n1 * n2 + n2 * n2
    keep = hbar * hbar * q <= cutoff * (1 + 1e-12)
    n = np.stack([n1[keep], n2[keep]], axis=1)
    order = np.lexsort((n[:, 1], n[:, 0], q[keep]))
    return n[order]


def _keys(n, r):
    w = 2 * r + 1
    return (n[..., 0] + r) * w + (n[..., 1] + r)


def hamiltonian(hbar: float, cutoff: float) -> tuple[sp.csr_matrix, np.ndarray]:
    """The Hamiltonian in the plane-wave basis, ``(H, n)``: a sparse symmetric CSR matrix
    and the wave numbers of :func:`plane_waves`.

    Examples
    --------
    >>> H, n = hamiltonian(1.0, 1.0)
    >>> H.shape, float(H[0, 0]), float(H[0, 1])
    ((7, 7), 3.0, -0.5)
    """
    n = plane_waves(hbar, cutoff)
    N = len(n)
    r = int(np.abs(n).max()) + 2
    keys = _keys(n, r)
    order = np.argsort(keys)
    diag = hbar * hbar * (n[:, 0] ** 2 - n[:, 0] * n[:, 1] + n[:, 1] ** 2) + 3.0
    rows, cols = [np.arange(N)], [np.arange(N)]
    vals = [diag]
    for e in ((1, 0), (0, 1), (1, 1), (-1, 0), (0, -1), (-1, -1)):
        kk = _keys(n + np.array(e), r)
        pos = np.searchsorted(keys[order], kk)
        pos = np.minimum(pos, N - 1)
        hit = keys[order][pos] == kk
        rows.append(np.nonzero(hit)[0])
        cols.append(order[pos[hit]])
        vals.append(np.full(hit.sum(), -0.5))
    H = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(N, N),
    )
    return H, n


def sector_hamiltonian(
    hbar: float, sector: str, cutoff: float, row: int = 0
) -> sp.csr_matrix:
    """The block of ``sector`` (CSR, symmetric): ``B^T H B`` with ``B`` of
    :func:`symmetry_basis`.

    Examples
    --------
    >>> import numpy as np
    >>> H = sector_hamiltonian(1.0, "A1", 1.0).toarray()  # the origin and the hexagon
    >>> np.linalg.eigvalsh(H).round(6).tolist()  # 3 -/+ sqrt(6)/2
    [1.775255, 4.224745]
    """
    hbar, _ = _check(hbar, sector=sector)
    H, n = hamiltonian(hbar, cutoff)
    B = symmetry_basis(n, sector, row)
    Hs = (B.T @ H @ B).tocsr()
    Hs.data[np.abs(Hs.data) < 1e-14] = 0.0
    Hs.eliminate_zeros()
    return Hs


# ---------------------------------------------------------------- sizes and memory
def basis_size(hbar: float, cutoff: float) -> int:
    """Number of plane waves below ``cutoff``: ``(2 pi / sqrt 3) cutoff / hbar^2`` (Weyl's
    estimate, within a few per cent; nothing is allocated).

    Examples
    --------
    >>> basis_size(0.1, 10.0)
    3627
    """
    return int(2.0 * math.pi / math.sqrt(3.0) * cutoff / hbar**2)


def memory_estimate(hbar: float, E_max: float, cutoff: float | None = None) -> int:
    """Peak bytes of one sector's computation, estimated (not allocated).

    The full sparse H (7 entries per plane wave), the group images of the lattice
    (12 x 3 integers per plane wave), and the sparse factorization of the largest block
    (a row of E1 or E2, ~N/6 functions, ~100 nonzeros per row after fill-in), the two
    Krylov arrays of a window (``N/6`` x ``qs.krylov_columns(1.5 WINDOW)``), plus the
    interpreter. ``benchmarks/bench_quantum.py`` prints the measured peak against it.

    Examples
    --------
    >>> memory_estimate(0.1, 2.0) < 10**8
    True
    """
    hbar, E_max = _check(hbar, E_max)
    K = default_cutoff(hbar, E_max) + cutoff_step(hbar) if cutoff is None else cutoff
    N = basis_size(hbar, K)
    nb = N / 6.0
    krylov = 2 * 8 * nb * qs.krylov_columns(int(1.5 * qs.WINDOW))
    return int(N * (7 * 12 * 2 + 12 * 3 * 8 + 96) + nb * 100 * 12 * 3 + krylov + 5e7)


def available_memory() -> int:
    """Bytes of physical memory available now (``sysconf``); 8 GB if unknown."""
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 8 * 2**30


# ---------------------------------------------------------------- spectra
@dataclass(frozen=True)
class SectorSpectrum:
    """The levels of one symmetry sector below ``E_max``.

    Attributes
    ----------
    hbar, E_max : float
    sector : str
    row : int
        Row of the irrep (0; 1 only for the second row of E1/E2).
    levels : numpy.ndarray
        Sorted eigenvalues ``<= E_max`` (float64), from the larger basis.
    cutoff : float
        Kinetic cut-off of the larger basis (the smaller one is ``cutoff - cutoff_step(hbar)``).
    basis_size : int
        Functions in the block of the larger basis.
    plane_waves : int
        Plane waves in the larger basis.
    convergence : float
        ``max |E(cutoff) - E(cutoff - cutoff_step(hbar))|`` over the levels (a level that
        crossed ``E_max`` between the two counts as ``inf``); for sliced blocks the
        larger of the per-level estimates and the change measured in the top window.
    method : str
        The solver used.
    errors : numpy.ndarray
        Per level, its change when the cut-off is lowered by ``cutoff_step(hbar)``:
        measured for dense blocks, the eigenvector estimate of :mod:`rotorlib.beyond.quantum_solver`
        for sliced ones.
    residuals : numpy.ndarray
        Per level, the bound on its distance to an eigenvalue of the block
        (``min(r, r^2/gap)`` of the Ritz pair; ``10 eps ||H||`` for dense LAPACK).
    top_check : float
        Sliced blocks: the largest change, measured by solving the basis with the
        lowered cut-off, of the levels of the top window (NaN for dense blocks).
    """

    hbar: float
    sector: str
    row: int
    E_max: float
    levels: np.ndarray
    cutoff: float
    basis_size: int
    plane_waves: int
    convergence: float
    method: str
    errors: np.ndarray = field(default_factory=lambda: np.empty(0))
    residuals: np.ndarray = field(default_factory=lambda: np.empty(0))
    top_check: float = math.nan

    @property
    def multiplicity(self) -> int:
        """Degeneracy of each level in the full spectrum (the irrep's dimension)."""
        return DIMENSIONS[self.sector]


def sector_block(hbar, sector, cutoff, row):
    """The Hamiltonian of one row of sector ``sector`` (CSC, in the symmetry-adapted
    plane waves with ``hbar^2 |k|^2 <= cutoff``), the number of plane waves and each
    column's kinetic energy (float64, exact up to rounding)."""
    H, n = hamiltonian(hbar, cutoff)
    B = symmetry_basis(n, sector, row)
    Hs = (B.T @ H @ B).tocsc()
    Hs.data[np.abs(Hs.data) < 1e-14] = 0.0
    Hs.eliminate_zeros()
    q = (n[:, 0] ** 2 - n[:, 0] * n[:, 1] + n[:, 1] ** 2).astype(float)
    kin = hbar * hbar * q[B.indices[B.indptr[:-1]]] if B.shape[1] else np.empty(0)
    return Hs, len(n), kin


@lru_cache(maxsize=2)
def _cached_block(hbar, sector, cutoff, row):
    return sector_block(hbar, sector, cutoff, row)


def _dense(Hs, E_max):
    if Hs.shape[0] == 0:
        return np.empty(0)
    w = sla.eigh(
        Hs.toarray(), eigvals_only=True, subset_by_value=(-1.0, E_max), driver="evr"
    )
    return np.sort(w)


def _plan_task(args):
    """One sector: solved whole when dense, else its windows (sliced later)."""
    hbar, sector, E_max, cutoff, row = args
    Hs, npw, kin = _cached_block(hbar, sector, cutoff, row)
    common = dict(hbar=hbar, sector=sector, row=row, E_max=E_max, cutoff=cutoff)
    common.update(basis_size=Hs.shape[0], plane_waves=npw)
    if Hs.shape[0] > DENSE_MAX:
        return common, qs.plan_windows(Hs, E_max)
    w1 = _dense(Hs, E_max)
    # the check: the basis with the cut-off lowered by cutoff_step(hbar)
    w0 = _dense(sector_block(hbar, sector, cutoff - cutoff_step(hbar), row)[0], E_max)
    err = np.abs(w1 - w0) if len(w0) == len(w1) else np.full(len(w1), math.inf)
    eps = np.finfo(float).eps * (abs(Hs).sum(axis=0).max() if Hs.nnz else 0.0)
    conv = float(err.max()) if len(err) else 0.0
    return SectorSpectrum(
        **common,
        levels=w1,
        convergence=conv,
        method="dense dsyevr",
        errors=err,
        residuals=np.full(len(w1), 10 * eps),
    ), None


def _window_task(args):
    """Consecutive windows of one sector (``edges``), or with ``lower`` the top window in
    the basis with the cut-off lowered (the check of the per-level estimates)."""
    hbar, sector, cutoff, row, edges, lower = args
    step = cutoff_step(hbar)
    if lower:
        Hs = sector_block(hbar, sector, cutoff - step, row)[0]
        w, counts = qs.sliced_levels(Hs, edges, None, seed=1)
        return w.levels, w.residuals, w.tails, counts
    Hs, _, kin = _cached_block(hbar, sector, cutoff, row)
    outer = np.nonzero(kin > (cutoff - step) * (1 + 1e-12))[0]
    w, counts = qs.sliced_levels(Hs, edges, outer)
    return w.levels, w.residuals, w.tails, counts


def _assemble(common, edges, parts, check):
    """A sliced sector from its chunks of windows, checked against the inertia counts."""
    for a, b in zip(parts, parts[1:]):
        if a[3][-1] != b[3][0]:
            raise qs.SlicingFailed("inertia counts of adjacent chunks differ")
    lev = np.concatenate([p[0] for p in parts])
    if len(lev) != parts[-1][3][-1] or np.any(np.diff(lev) < 0):
        raise qs.SlicingFailed("the windows do not add up to the inertia count")
    err = np.concatenate([p[2] for p in parts])
    top = lev[lev >= edges[-2]]
    same = len(check[0]) == len(top) and check[3][-1] == len(lev)
    measured = float(np.max(np.abs(check[0] - top), initial=0.0)) if same else math.inf
    conv = max(float(err.max(initial=0.0)), measured)
    return SectorSpectrum(
        **common,
        levels=lev,
        convergence=conv,
        method="shift-invert block Krylov windows (SuperLU inertia counts)",
        errors=err,
        residuals=np.concatenate([p[1] for p in parts]),
        top_check=measured,
    )


CHUNK = 6  # windows per task


def _compute(hbar, E_max, names, cutoff, row, executor, progress):
    need, have = memory_estimate(hbar, E_max, cutoff), available_memory()
    if need > have:  # refused before anything is built
        raise ValueError(
            f"the basis would not fit in memory: {basis_size(hbar, cutoff):,} plane "
            f"waves, ~{need / 2**30:.3g} GiB needed, {have / 2**30:.3g} GiB available"
        )
    plans = pmap(
        _plan_task, [(hbar, s, E_max, cutoff, row) for s in names], executor=executor
    )
    tasks, where = [], {}
    for (common, edges), s in zip(plans, names):
        if edges is None:
            continue
        idx = []
        for i in range(0, len(edges) - 1, CHUNK):
            idx.append(len(tasks))
            tasks.append((hbar, s, cutoff, row, edges[i : i + CHUNK + 1], False))
        idx.append(len(tasks))
        tasks.append((hbar, s, cutoff, row, edges[-2:], True))
        where[s] = idx
    out = pmap(
        _window_task, tasks, executor=executor, progress=progress, desc="windows"
    )
    res = {}
    for (common, edges), s in zip(plans, names):
        if edges is None:
            res[s] = common
        else:
            parts = [out[i] for i in where[s]]
            res[s] = _assemble(common, edges, parts[:-1], parts[-1])
    return res


def sector_spectrum(
    hbar: float,
    sector: str,
    E_max: float,
    cutoff: float | None = None,
    row: int = 0,
    digits: int | None = None,
) -> SectorSpectrum:
    """The levels of one sector below ``E_max``, with the convergence estimate.

    Parameters
    ----------
    hbar : float
        Dimensionless Planck constant (units g = m r^2 = 1), > 0.
    sector : str
        One of :data:`SECTORS`.
    E_max : float
        Highest energy (the minimum of V is 0, the ground state ~ hbar sqrt 3).
    cutoff : float, optional
        Kinetic cut-off of the larger basis; default ``default_cutoff + cutoff_step(hbar)``.
    row : int
        Row of a two-dimensional irrep (0 or 1).
    digits : int, optional
        At most 15 (float64 is the only tier).

    Returns
    -------
    SectorSpectrum
        Levels to ~1e-13 absolute when ``convergence`` is below that.

    Examples
    --------
    >>> s = sector_spectrum(0.1, "A1", 0.6)
    >>> [round(float(x), 6) for x in s.levels]
    [0.171947, 0.510725]
    >>> s.convergence < 1e-12
    True
    """
    hbar, E_max = _check(hbar, E_max, sector, digits)
    if cutoff is None:
        cutoff = default_cutoff(hbar, E_max) + cutoff_step(hbar)
    if cutoff - cutoff_step(hbar) <= E_max:
        raise ValueError(
            f"cutoff {cutoff} must exceed E_max + cutoff_step = "
            f"{E_max + cutoff_step(hbar)}"
        )
    return _compute(hbar, E_max, (sector,), float(cutoff), row, None, False)[sector]


@dataclass(frozen=True)
class Spectrum:
    """The spectrum of several sectors (``all``: the whole spectrum with multiplicities).

    Attributes
    ----------
    hbar, E_max : float
    sectors : tuple of SectorSpectrum
    """

    hbar: float
    E_max: float
    sectors: tuple

    @property
    def levels(self) -> np.ndarray:
        """All levels, each repeated by its multiplicity, sorted."""
        parts = [np.repeat(s.levels, s.multiplicity) for s in self.sectors]
        return np.sort(np.concatenate(parts)) if parts else np.empty(0)

    @property
    def labels(self) -> np.ndarray:
        """The sector of each distinct level, in the order of :attr:`distinct`."""
        lab = np.concatenate([[s.sector] * len(s.levels) for s in self.sectors])
        return lab[np.argsort(self._distinct_unsorted(), kind="stable")]

    def _distinct_unsorted(self):
        return np.concatenate([s.levels for s in self.sectors])

    @property
    def distinct(self) -> np.ndarray:
        """Every level once (a level of E1/E2 once), sorted."""
        return np.sort(self._distinct_unsorted(), kind="stable")

    @property
    def convergence(self) -> float:
        return max((s.convergence for s in self.sectors), default=0.0)

    def sector(self, name: str) -> SectorSpectrum:
        return next(s for s in self.sectors if s.sector == name)


def spectrum(
    hbar: float,
    E_max: float,
    sectors: str | tuple[str, ...] | list[str] = "all",
    cutoff: float | None = None,
    executor: Executor | None = None,
    digits: int | None = None,
    progress: bool = False,
) -> Spectrum:
    """The levels below ``E_max`` of the given sectors (``"all"``: the six).

    Each sector is planned in one task of :func:`rotorlib.core.parallel.pmap` (serial, a
    process pool or a Dask cluster via ``executor``), largest first; a small block is
    solved there (dense), a large one is cut into windows, solved in chunks of
    ``CHUNK`` windows, one task each (``progress``: a bar on a terminal).

    Examples
    --------
    >>> s = spectrum(0.5, 2.0)
    >>> [round(float(x), 6) for x in s.levels]
    [0.833625, 1.63238, 1.63238]
    >>> [x.sector for x in s.sectors if len(x.levels)]
    ['A1', 'E1']
    """
    names = (
        SECTORS
        if sectors == "all"
        else tuple([sectors] if isinstance(sectors, str) else sectors)
    )
    for s in names:
        hbar, E_max = _check(hbar, E_max, s, digits)
    if cutoff is None:
        cutoff = default_cutoff(hbar, E_max) + cutoff_step(hbar)
    order = tuple(sorted(names, key=lambda s: -DIMENSIONS[s]))
    by = _compute(hbar, E_max, order, float(cutoff), 0, executor, progress)
    return Spectrum(hbar=hbar, E_max=E_max, sectors=tuple(by[s] for s in names))
