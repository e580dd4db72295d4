"""Sparse spectrum slicing for the blocks of the quantum 3-rotor (:mod:`rotorlib.beyond.quantum`).

A block ``Hs`` (real symmetric, sparse: each plane wave couples to six neighbours) is
cut into energy windows ``(lo, hi]`` of about :data:`WINDOW` levels. In each window:

1. **Count.** The number of levels below ``x`` is the number of negative pivots of a
   sparse ``LDL^T``-like factorization of ``Hs - x`` (SuperLU, symmetric ordering, no
   pivoting; Sylvester's law of inertia). The count of a window is the difference of the
   counts at its ends, so no level is lost or counted twice between windows.
2. **Solve.** A block Krylov space of ``(Hs - sigma)^-1`` (shift-and-invert at the
   window's midpoint, the same factorization type, several right-hand sides at once) with
   full reorthogonalization, and Rayleigh-Ritz with ``Hs`` itself. A Ritz pair is accepted
   when its residual ``||Hs x - E x||`` is below :data:`RESIDUAL_TOL` (then an eigenvalue
   lies within the residual of ``E``, and the error of ``E`` is ~residual^2/gap); the
   window is done when exactly its count of accepted levels lies inside it, and the
   midpoint's own inertia splits them the same way. Otherwise the window is halved.
3. **Convergence in the cut-off.** Each accepted Ritz vector ``x`` gives the change of
   its level when the basis is cut back to the columns ``P`` (kinetic energy below the
   lower cut-off), by the exact identity for the Rayleigh quotient of the cut vector,
   ``RQ(x_P) - E = x_Q^T (H_QQ - E) x_Q / |x_P|^2`` (``Q`` the dropped shell; exact
   for an eigenvector, an upper estimate of the change of the level itself, which differs
   from it at the next order in ``|x_Q|^2``).

Precision: float64. Residuals are accepted below ``1e-9``; the Ritz values of the test
cases agree with dense LAPACK to ~1e-13. The cost at ``hbar = 0.01`` (A1, 28,842
functions, 15,000 levels): ~2 ms per solve of one right-hand side, ~0.1 s per
factorization; ``benchmarks/bench_quantum.py`` prints the measured figures.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

__all__ = [
    "WINDOW",
    "RESIDUAL_TOL",
    "SlicingFailed",
    "factor",
    "count_below",
    "window_levels",
    "plan_windows",
    "sliced_levels",
    "WindowLevels",
]

#: Target number of levels per window.
WINDOW = 32
#: Krylov block size (right-hand sides per solve).
BLOCK = 8
#: Largest accepted error bound of a level: ``min(r, r^2/gap)`` with ``r`` the residual
#: ``||H x - E x||`` of its unit Ritz vector and ``gap`` the distance to the nearest
#: other Ritz value (Kato-Temple).
RESIDUAL_TOL = 1e-11


def krylov_columns(count: int) -> int:
    """Largest Krylov space of a window of ``count`` levels (then it is halved)."""
    return max(6 * count + 4 * BLOCK, 128)


class SlicingFailed(RuntimeError):
    """A window's accepted levels do not match its inertia count."""


def factor(Hs: sp.spmatrix, x: float):
    """Sparse factorization of ``Hs - x`` and the number of levels below ``x``.

    SuperLU with a symmetric ordering and no pivoting: ``P (Hs - x) P^T = L U`` with
    ``U = D L^T``, so the negative diagonal entries of ``U`` count the negative
    eigenvalues of ``Hs - x`` (Sylvester's law of inertia).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.diags([1.0, 2.0, 3.0]).tocsc()
    >>> factor(A, 2.5)[1]
    2
    """
    import scipy.sparse.linalg as spla

    for k in range(4):  # x on an eigenvalue (a zero pivot): move it by 1e-12
        A = (Hs - (x + k * 1e-12) * sp.identity(Hs.shape[0], format="csc")).tocsc()
        try:
            lu = spla.splu(
                A,
                permc_spec="MMD_AT_PLUS_A",
                diag_pivot_thresh=0.0,
                options=dict(SymmetricMode=True),
            )
        except RuntimeError:
            continue
        return lu, int(np.count_nonzero(lu.U.diagonal() < 0))
    raise SlicingFailed(f"Hs - {x} could not be factorized without pivoting")


def count_below(Hs: sp.spmatrix, x: float) -> int:
    """Number of eigenvalues of ``Hs`` below ``x`` (inertia of :func:`factor`)."""
    return factor(Hs, x)[1]


class WindowLevels:
    """The levels of one window: ``levels``, ``residuals`` and ``tails`` (arrays)."""

    __slots__ = ("levels", "residuals", "tails")

    def __init__(self, levels, residuals, tails):
        self.levels, self.residuals, self.tails = levels, residuals, tails


def _bounds(E, res, count, lo, hi):
    """Rigorous error bounds of the ``count`` Ritz values with the smallest residuals,
    or None. If their intervals ``[E - r, E + r]`` lie in ``[lo, hi)`` and are disjoint,
    each holds at least one eigenvalue (a unit vector with residual r), and as the
    window holds exactly ``count``, one each and no other: between the neighbouring
    intervals (or the window's edges) ``a < E < b`` lies one eigenvalue, within
    ``r^2 / min(E - a, b - E)`` of ``E`` (Kato-Temple)."""
    if len(E) < count:
        return None
    pick = np.sort(np.argsort(res)[:count])
    order = np.argsort(E[pick])
    e, r = E[pick][order], res[pick][order]
    top, bottom = e + r, e - r
    if bottom[0] < lo or top[-1] >= hi or np.any(bottom[1:] <= top[:-1]):
        return None
    a = np.concatenate([[lo], top[:-1]])
    b = np.concatenate([bottom[1:], [hi]])
    gap = np.minimum(e - a, b - e)
    bound = np.minimum(r, r * r / np.maximum(gap, 1e-300))
    out = np.empty(count)
    out[order] = bound  # back to the order of pick
    return out


def _tails(Hs_QQ, outer, X, E):
    """``x_Q^T (H_QQ - E) x_Q / |x_P|^2`` for the columns of ``X`` (see the module)."""
    if outer is None or len(outer) == 0:
        return np.zeros(len(E))
    XQ = X[outer]
    nq = np.einsum("ij,ij->j", XQ, XQ)
    num = np.einsum("ij,ij->j", XQ, Hs_QQ @ XQ) - E * nq
    return np.maximum(num, 0.0) / np.maximum(1.0 - nq, 1e-300)


def window_levels(
    Hs: sp.spmatrix,
    lo: float,
    hi: float,
    n_lo: int,
    n_hi: int,
    outer: np.ndarray | None = None,
    seed: int = 0,
) -> WindowLevels:
    """The eigenvalues of ``Hs`` in ``[lo, hi)``, ``n_hi - n_lo`` of them.

    Parameters
    ----------
    Hs : sparse symmetric matrix
    lo, hi : float
        The window ``[lo, hi)``.
    n_lo, n_hi : int
        The levels below ``lo`` and below ``hi`` (:func:`count_below`).
    outer : array of int, optional
        The columns dropped when the cut-off is lowered (for the per-level change).
    seed : int
        Seed of the random start block (the result does not depend on it beyond
        round-off).

    Returns
    -------
    WindowLevels
        Sorted levels, their residuals and their change when the cut-off is lowered.

    Raises
    ------
    SlicingFailed
        If the Krylov space reaches its size limit first, or the levels found do not
        split at the midpoint as its inertia says.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.diags([np.arange(1.0, 301.0), -0.3 * np.ones(299), -0.3 * np.ones(299)],
    ...              [0, 1, -1]).tocsc()
    >>> w = window_levels(A, 100.5, 150.5, count_below(A, 100.5), count_below(A, 150.5))
    >>> ref = np.linalg.eigvalsh(A.toarray())
    >>> ref = ref[(ref >= 100.5) & (ref < 150.5)]
    >>> len(w.levels) == len(ref) and bool(np.max(np.abs(w.levels - ref)) < 1e-12)
    True
    """
    N = Hs.shape[0]
    count = n_hi - n_lo
    empty = WindowLevels(np.empty(0), np.empty(0), np.empty(0))
    if count == 0:
        return empty
    sigma = 0.5 * (lo + hi)
    lu, below_mid = factor(Hs, sigma)
    rng = np.random.default_rng(seed)
    b = min(BLOCK, N)
    m_max = min(N - b, krylov_columns(count))
    Q = np.empty((N, m_max + b))
    S = np.empty((N, m_max + b))  # (Hs - sigma)^-1 Q
    T = np.empty((m_max + b, m_max + b))  # Q^T (Hs - sigma)^-1 Q
    V = np.linalg.qr(rng.standard_normal((N, b)))[0]
    m = 0
    prev = np.empty(0)
    Hs_QQ = Hs[outer][:, outer] if outer is not None and len(outer) else None
    while True:
        nb = V.shape[1]
        W = lu.solve(V)
        Q[:, m : m + nb] = V
        S[:, m : m + nb] = W
        cols = slice(m, m + nb)
        T[: m + nb, cols] = Q[:, : m + nb].T @ W
        T[cols, :m] = T[:m, cols].T
        m += nb
        if m >= count + b:
            Tm = 0.5 * (T[:m, :m] + T[:m, :m].T)
            theta, Y = sla.eigh(Tm)
            with np.errstate(divide="ignore"):
                E_all = sigma + 1.0 / theta
            inside = np.nonzero((E_all >= lo) & (E_all < hi))[0]
            # explicit residuals only once count Ritz values inside have settled
            settled = (
                np.count_nonzero(
                    np.min(np.abs(E_all[inside][:, None] - prev[None, :]), axis=1)
                    < 1e-9
                )
                if len(prev) and len(inside)
                else 0
            )
            prev = E_all[inside]
            if settled >= count:
                Yi = Y[:, inside]
                X = Q[:, :m] @ Yi
                X /= np.linalg.norm(X, axis=0)
                HX = Hs @ X
                E = np.einsum("ij,ij->j", X, HX)  # Rayleigh quotients
                res = np.linalg.norm(HX - X * E, axis=0)
                bound = _bounds(E, res, count, lo, hi)
                if bound is not None and bound.max() < RESIDUAL_TOL:
                    good = np.sort(np.argsort(res)[:count])
                    E = E[good]
                    if np.count_nonzero(E < sigma) != below_mid - n_lo:
                        raise SlicingFailed(
                            f"window [{lo}, {hi}): the levels found do not split "
                            "at the midpoint as its inertia does"
                        )
                    order = np.argsort(E)
                    tails = _tails(Hs_QQ, outer, X[:, good], E)
                    return WindowLevels(E[order], bound[order], tails[order])
        if m + b > m_max:
            raise SlicingFailed(
                f"window [{lo}, {hi}): {count} levels not converged in {m} vectors"
            )
        # classical Gram-Schmidt, twice; the first pass's coefficients are T's column
        W -= Q[:, :m] @ T[:m, m - nb : m]
        W -= Q[:, :m] @ (Q[:, :m].T @ W)
        V, Rr = np.linalg.qr(W)
        small = np.abs(np.diag(Rr)) < 1e-10 * max(1.0, np.abs(Rr).max())
        if small.any():  # an (almost) invariant subspace: continue with random vectors
            Z = rng.standard_normal((N, int(small.sum())))
            V = np.hstack([V[:, ~small], Z])
            for _ in range(2):
                V -= Q[:, :m] @ (Q[:, :m].T @ V)
            V = np.linalg.qr(V)[0]


def plan_windows(
    Hs: sp.spmatrix, E_max: float, target: int = WINDOW, coarse: int = 16
) -> np.ndarray:
    """Window edges ``0 = x_0 < x_1 < ... < x_M = E_max`` with about ``target`` levels
    between consecutive edges, placed by interpolating ``coarse`` inertia counts
    (``Hs >= 0``, so no level lies below 0).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.diags(np.arange(1.0, 201.0)).tocsc()
    >>> x = plan_windows(A, 100.0, target=25)
    >>> len(x) - 1, float(x[0]), float(x[-1])
    (4, 0.0, 100.0)
    """
    xs = np.linspace(0.0, E_max, coarse + 1)
    ns = np.array([0] + [count_below(Hs, x) for x in xs[1:]], dtype=float)
    total = int(ns[-1])
    M = max(1, int(round(total / target)))
    edges = [0.0]
    for t in total * np.arange(1, M) / M:
        j = int(np.searchsorted(ns, t, side="left"))  # ns[j-1] < t <= ns[j]
        f = (t - ns[j - 1]) / (ns[j] - ns[j - 1])
        edges.append(float(xs[j - 1] + f * (xs[j] - xs[j - 1])))
    edges.append(float(E_max))
    return np.unique(np.array(edges))


def _solve_window(Hs, lo, hi, n_lo, n_hi, outer, seed, depth=0):
    """:func:`window_levels`, halving the window when it fails (at most 6 times)."""
    try:
        return [window_levels(Hs, lo, hi, n_lo, n_hi, outer, seed)]
    except SlicingFailed:
        if depth >= 6 or hi - lo < 1e-9:
            raise
    mid = 0.5 * (lo + hi) + 1e-3 * (hi - lo) * math.sin(depth + seed)  # off-centre
    n_mid = count_below(Hs, mid)
    return _solve_window(
        Hs, lo, mid, n_lo, n_mid, outer, seed + 1, depth + 1
    ) + _solve_window(Hs, mid, hi, n_mid, n_hi, outer, seed + 2, depth + 1)


def sliced_levels(
    Hs: sp.spmatrix,
    edges: np.ndarray,
    outer: np.ndarray | None = None,
    seed: int = 0,
) -> tuple[WindowLevels, np.ndarray]:
    """Every level of ``Hs`` in ``[edges[0], edges[-1])``, window by window.

    Returns the levels (sorted, with residuals and per-level cut-off changes) and the
    inertia counts at the edges; raises :class:`SlicingFailed` if the windows do not add
    up to the counts. ``edges[0] = 0`` is taken to have count 0 (``Hs >= 0``).
    """
    edges = np.asarray(edges, dtype=float)
    counts = np.array(
        [0 if x <= 0.0 else count_below(Hs, float(x)) for x in edges], dtype=int
    )
    if np.any(np.diff(counts) < 0):
        raise SlicingFailed("inertia counts decrease with energy")
    parts = []
    for i in range(len(edges) - 1):
        parts += _solve_window(
            Hs, edges[i], edges[i + 1], counts[i], counts[i + 1], outer, seed + 7 * i
        )
    lev = np.concatenate([p.levels for p in parts]) if parts else np.empty(0)
    if len(lev) != counts[-1] - counts[0]:
        raise SlicingFailed("the windows do not add up to the inertia count")
    order = np.argsort(lev, kind="stable")
    res = np.concatenate([p.residuals for p in parts]) if parts else np.empty(0)
    tail = np.concatenate([p.tails for p in parts]) if parts else np.empty(0)
    return WindowLevels(lev[order], res[order], tail[order]), counts
