"""The symmetry group S3 x Z2 of the quantum 3-rotor and its symmetry-adapted bases.

The group acts on the rotor wave numbers ``k = (n1, n2 - n1, -n2)`` by signed
permutations (rotor permutations and the reflection ``theta -> -theta``; the point group
C6v of the hexagonal lattice of ``k``); its six irreducible representations are the
sectors of :mod:`rotorlib.beyond.quantum` (see its table). :func:`symmetry_basis` builds, orbit by
orbit of the lattice, orthonormal functions of one row of one irrep (exact: the
coefficients are those of a 12 x 12 projector, rank decided at 1e-9).
"""

from __future__ import annotations

import itertools
from functools import cache

import numpy as np
import scipy.sparse as sp

__all__ = ["SECTORS", "DIMENSIONS", "symmetry_basis"]

#: The six irreducible representations of S3 x Z2 (C6v), in the order used throughout.
SECTORS = ("A1", "A2", "B1", "B2", "E1", "E2")
#: Their dimensions (the multiplicity of a sector's levels in the full spectrum).
DIMENSIONS = {"A1": 1, "A2": 1, "B1": 1, "B2": 1, "E1": 2, "E2": 2}


@cache
def _group():
    """The 12 signed permutation matrices acting on ``k``, their permutations and signs."""
    mats, perms, signs = [], [], []
    for p in itertools.permutations(range(3)):
        P = np.zeros((3, 3), dtype=np.int64)
        P[list(p), range(3)] = 1  # e_j -> e_{p(j)}
        for s in (1, -1):
            mats.append(s * P)
            perms.append(P)
            signs.append(s)
    mats = np.array(mats)
    n = len(mats)
    mult = np.empty((n, n), dtype=np.int64)
    for a in range(n):
        for b in range(n):
            prod = mats[a] @ mats[b]
            mult[a, b] = next(c for c in range(n) if np.array_equal(mats[c], prod))
    return mats, np.array(perms), np.array(signs), mult


@cache
def _rep(sector: str, row: int):
    """``D_{row,row}(g)`` of the irrep ``sector`` for the 12 group elements (real)."""
    mats, perms, signs, _ = _group()
    det = np.rint(np.linalg.det(perms)).astype(int)  # sign of the permutation
    if sector in ("A1", "A2", "B1", "B2"):
        if row != 0:
            raise ValueError(f"sector {sector} is one-dimensional: row must be 0")
        return {
            "A1": np.ones(12),
            "A2": det.astype(float),
            "B1": signs.astype(float),
            "B2": (signs * det).astype(float),
        }[sector]
    if row not in (0, 1):
        raise ValueError(f"row must be 0 or 1, not {row}")
    # orthonormal basis of the plane sum(x) = 0: the standard representation of S3
    U = np.array([[1.0, -1.0, 0.0], [1.0, 1.0, -2.0]]).T
    U /= np.linalg.norm(U, axis=0)
    D = np.einsum("ia,gij,jb->gab", U, perms.astype(float), U)
    d = D[:, row, row]
    return d * signs if sector == "E1" else d


@cache
def _orbit_vectors(pattern: tuple, sector: str, row: int):
    """Orthonormal symmetry-adapted vectors on one lattice orbit (by its pattern)."""
    _, _, _, mult = _group()
    D = _rep(sector, row)
    slots = sorted(set(pattern))
    where = {s: i for i, s in enumerate(slots)}
    S = np.zeros((12, len(slots)))
    for h in range(12):
        for g in range(12):
            S[h, where[pattern[mult[g, h]]]] += D[g]
    u, s, vt = np.linalg.svd(S)
    rank = int(np.sum(s > 1e-9 * max(s.max(), 1.0)))
    return slots, vt[:rank]


def symmetry_basis(n: np.ndarray, sector: str, row: int = 0) -> sp.csc_matrix:
    """Symmetry-adapted orthonormal basis of ``sector`` (row ``row`` of a 2D irrep).

    Parameters
    ----------
    n : array (N, 2)
        A basis of plane waves closed under the group (e.g. :func:`plane_waves`).
    sector : str
        One of :data:`SECTORS`.
    row : int
        0, or 1 for the second row of E1 and E2 (the same levels: a check).

    Returns
    -------
    scipy.sparse.csc_matrix, shape (N, N_sector)
        Orthonormal columns spanning the functions of that row of the irrep.

    Examples
    --------
    >>> from rotorlib.beyond.quantum import plane_waves
    >>> n = plane_waves(1.0, 1.0)
    >>> [symmetry_basis(n, s).shape[1] for s in SECTORS]
    [2, 0, 0, 1, 1, 1]
    """
    if sector not in SECTORS:
        raise ValueError(
            f"unknown sector {sector!r}: choose one of {', '.join(SECTORS)}"
        )
    mats, _, _, _ = _group()
    n = np.asarray(n)
    k = np.stack([n[:, 0], n[:, 1] - n[:, 0], -n[:, 1]], axis=1)
    img = np.einsum("gij,nj->ngi", mats, k)  # (N, 12, 3)
    r = int(np.abs(k).max()) + 1
    w = 2 * r + 1
    key = ((img[..., 0] + r) * w + (img[..., 1] + r)) * w + (img[..., 2] + r)
    canon = key.max(axis=1)
    mine = key[:, 0] == canon  # the canonical representative of each orbit
    reps = np.nonzero(mine)[0]
    kr = key[reps]  # (n_orb, 12): key of g . rep
    first = np.argmax(kr[:, :, None] == kr[:, None, :], axis=2)  # first equal slot
    lookup = np.argsort(key[:, 0])
    sorted_keys = key[lookup, 0]
    rows, cols, vals = [], [], []
    col = 0
    patterns, inverse = np.unique(first, axis=0, return_inverse=True)
    inverse = np.asarray(inverse).ravel()
    for p_idx, pat in enumerate(patterns):
        slots, vecs = _orbit_vectors(tuple(int(x) for x in pat), sector, row)
        if len(vecs) == 0:
            continue
        orbits = np.nonzero(inverse == p_idx)[0]
        pts = lookup[np.searchsorted(sorted_keys, kr[orbits][:, slots])]  # (m_o, len)
        for v in vecs:
            m = len(orbits)
            rows.append(pts.ravel())
            cols.append(np.repeat(np.arange(col, col + m), len(slots)))
            vals.append(np.tile(v, m))
            col += m
    if col == 0:
        return sp.csc_matrix((len(n), 0))
    B = sp.csc_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(len(n), col),
    )
    # order the columns by the kinetic energy of their orbit (smaller bandwidth)
    q = (n[:, 0] ** 2 - n[:, 0] * n[:, 1] + n[:, 1] ** 2).astype(float)
    first_row = B.indices[B.indptr[:-1]]
    B = B[:, np.argsort(q[first_row], kind="stable")]
    B.eliminate_zeros()
    return B
