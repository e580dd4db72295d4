"""Independent check of the A1 spectrum at small hbar (issue 31): the lowest levels and a
window at E ~ 5.45 against a diagonalization that shares no code with rotorlib.

    .venv/bin/python scripts/quantum_independent.py [--hbar 0.01] [--low 200]
        [--window 5.45 --count 60] [--levels FILE.json] [--out PATH]

The reference: the Hamiltonian built from scratch in the rotor wave numbers
``k = (k1, k2, k3)``, ``sum k = 0`` (kinetic ``hbar^2 |k|^2 / 2``, potential
``3 - sum_{i<j} cos(theta_i - theta_j)`` shifting ``k`` by ``+-(e_i - e_j)`` with weight
-1/2), on the normalized sums over the orbits of S3 x Z2 (labelled by sorted ``k``), at
its own cut-off ``E + 1 + 45 hbar``, and solved by scipy's ARPACK (``eigsh`` with its own
pivoted LU in shift-invert mode), not by the library's windows. The levels compared: the
stored data product (``rotorlib.beyond.quantum_data``) or the JSON of
``python -m rotorlib spectrum --hbar H --sector A1 --E-max 8 --json`` (``--levels``).
Writes ``book/data/quantum/independent_check.json`` (counts, largest differences);
``tests/test_quantum_data.py`` asserts it.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "book" / "data" / "quantum" / "independent_check.json"
SHIFTS = np.array(
    [[1, -1, 0], [-1, 1, 0], [1, 0, -1], [-1, 0, 1], [0, 1, -1], [0, -1, 1]]
)


def canonical(k: np.ndarray) -> np.ndarray:
    """The label of the orbit of each row of ``k``: the larger (lexicographically) of
    sorted(k) and sorted(-k)."""
    a, b = np.sort(k, axis=1), np.sort(-k, axis=1)
    a_larger = np.zeros(len(k), dtype=bool)
    decided = np.zeros(len(k), dtype=bool)
    for j in range(3):
        gt, lt = a[:, j] > b[:, j], a[:, j] < b[:, j]
        a_larger |= ~decided & gt
        decided |= gt | lt
    a_larger |= ~decided  # equal
    return np.where(a_larger[:, None], a, b)


def a1_hamiltonian(hbar: float, cutoff: float) -> sp.csr_matrix:
    """H on the normalized A1 orbit sums of every k with hbar^2 |k|^2 / 2 <= cutoff."""
    r = int(math.sqrt(2 * cutoff) / hbar) + 1
    k1, k2 = np.meshgrid(np.arange(-r, r + 1), np.arange(-r, r + 1), indexing="ij")
    k = np.stack([k1.ravel(), k2.ravel(), -(k1 + k2).ravel()], axis=1)
    k = k[hbar * hbar * np.sum(k * k, axis=1) / 2 <= cutoff]
    lab = canonical(k)
    w = 4 * r + 3
    code = lambda x: ((x[:, 0] + 2 * r + 1) * w + x[:, 1] + 2 * r + 1) * w + x[:, 2]  # noqa: E731
    labels, size = np.unique(code(lab), return_counts=True)
    reps = np.unique(lab, axis=0)
    assert np.array_equal(np.sort(code(reps)), labels)
    reps = reps[np.argsort(code(reps))]
    M = len(reps)
    rows, cols, vals = (
        [np.arange(M)],
        [np.arange(M)],
        [3.0 + hbar * hbar * np.sum(reps * reps, axis=1) / 2],
    )
    for d in SHIFTS:
        nb = code(canonical(reps + d))
        j = np.searchsorted(labels, nb)
        j = np.minimum(j, M - 1)
        ok = labels[j] == nb
        i = np.nonzero(ok)[0]
        rows.append(i)
        cols.append(j[ok])
        vals.append(-0.5 * size[i] / np.sqrt(size[i] * size[j[ok]]))
    H = sp.coo_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), (M, M)
    ).tocsr()
    return H


def reference(hbar: float, sigma: float, count: int, E_top: float) -> np.ndarray:
    """The ``count`` A1 levels nearest ``sigma`` (ARPACK shift-invert), sorted."""
    H = a1_hamiltonian(hbar, E_top + 1.0 + 45.0 * hbar)
    w = spla.eigsh(H, k=count, sigma=sigma, which="LM", return_eigenvectors=False)
    return np.sort(w)


def direct(hbar: float, low: int, E0: float) -> np.ndarray:
    """The library's A1 levels, in the basis ``spectrum --E-max 8`` uses, from its own
    windows: every level up to just above the ``low``-th, and those in E0 +- 0.05
    (NaN between; only these are compared)."""
    from rotorlib.beyond import quantum as q
    from rotorlib.beyond import quantum_solver as qs

    K = q.default_cutoff(hbar, 8.0) + q.cutoff_step(hbar)
    Hs = q.sector_block(hbar, "A1", K, 0)[0]
    x = 0.0
    while qs.count_below(Hs, x) <= low + 2:
        x += 0.05
    w_low, _ = qs.sliced_levels(Hs, np.linspace(0.0, x, 9))
    w_win, c = qs.sliced_levels(Hs, np.linspace(E0 - 0.05, E0 + 0.05, 5))
    out = np.full(c[0] + len(w_win.levels), np.nan)
    out[: len(w_low.levels)] = w_low.levels
    out[c[0] :] = w_win.levels
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--hbar", type=float, default=0.01)
    ap.add_argument("--low", type=int, default=200)
    ap.add_argument("--window", type=float, default=5.45)
    ap.add_argument("--count", type=int, default=60)
    ap.add_argument("--levels", type=Path, default=None)
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument(
        "--direct",
        action="store_true",
        help="the library's levels from windows of the E_max = 8 basis (no stored file)",
    )
    args = ap.parse_args(argv)
    if args.direct:
        lev = direct(args.hbar, args.low, args.window)
        source = (
            f"library windows in the basis of spectrum --hbar {args.hbar:g} --sector A1 "
            "--E-max 8 (its cut-off), the lowest levels and E0 +- 0.05"
        )
    elif args.levels is not None:
        rec = json.loads(args.levels.read_text())
        lev = np.array(rec["levels"], dtype=float)
        source = f"spectrum --hbar {args.hbar:g} --sector A1 --E-max 8 --json"
    else:
        from rotorlib.beyond import quantum_data

        lev = quantum_data.stored_spectrum(args.hbar, "A1").levels
        source = f"book/data/quantum/spectrum_hbar{args.hbar:g}.npz"
    t0 = time.perf_counter()
    low = reference(args.hbar, 0.0, args.low, float(lev[args.low]))
    # the window: the `count` reference levels nearest E0; compare with the library's
    # levels between the same edges (the count must agree too)
    win = reference(args.hbar, args.window, args.count, args.window + 0.1)
    inner = win[1:-1]  # the two outermost may sit next to unlisted neighbours
    lo, hi = 0.5 * (win[0] + win[1]), 0.5 * (win[-2] + win[-1])
    mine = lev[(lev > lo) & (lev < hi)]
    if args.direct and not (lo > args.window - 0.05 and hi < args.window + 0.05):
        raise SystemExit("the reference window is wider than the library's")
    result = {
        "hbar": args.hbar,
        "sector": "A1",
        "compared": source,
        "reference": "orbit sums of sorted k, built from scratch; scipy eigsh "
        "(ARPACK, shift-invert); cut-off E + 1 + 45 hbar",
        "low_count": args.low,
        "low_max_difference": float(np.max(np.abs(lev[: args.low] - low))),
        "window_E0": args.window,
        "window_edges": [float(lo), float(hi)],
        "window_count_reference": len(inner),
        "window_count_library": len(mine),
        "window_max_difference": float(np.max(np.abs(mine - inner)))
        if len(mine) == len(inner)
        else None,
        "seconds": round(time.perf_counter() - t0, 1),
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
