"""Scaling constants of the pendulum bifurcation cascade and comparison with printed values (paper §5).

* :func:`class_sequences` splits transitions into the seven classes of §5.
* :func:`log_delta_sequence`: ``log delta_n = log|E_n - 4| - log|E_{n+1} - 4|`` within a class;
  predicted limits ``sqrt(3) pi`` (libration) and ``2 sqrt(3) pi`` (rotation).
* :func:`asymptotic_distance`: the paper's asymptotic energy formulas
  ``4 - E = 64 exp(-sqrt3 tau/2)`` (libration) and ``E - 4 = 64 exp(-sqrt3 tau)`` (rotation).
* :func:`fit_convergence`: fit ``log|err_n| = a + b x_n + log|x_n|`` (error ~ ``|E-4| log|E-4|``).
* :func:`transverse_eigenstructure`: spectrum and transverse eigenvectors of M at a transition,
  robust to the parabolic (defective) 2x2 block.
* :func:`rounded_verdict`: is a printed value the correctly rounded value of ours? If not, why
  (truncation, lower precision, a typo)?

Numerics only (no matplotlib). Works with floats or mpmath numbers.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from decimal import ROUND_DOWN, ROUND_HALF_EVEN, Decimal

import numpy as np

from .bifurcations import CLASSES

__all__ = ["class_sequences", "log_delta_sequence", "asymptotic_distance", "fit_convergence",
           "TransverseEigen", "transverse_eigenstructure", "rounded_verdict", "text_table"]


def class_sequences(trs) -> dict:
    """``{class name: [transitions ordered by n]}`` for the seven classes of §5 (empty classes dropped)."""
    out = {}
    for name, (kind, phase, parity) in CLASSES.items():
        seq = sorted((t for t in trs if t.kind == kind and t.phase == phase
                      and (parity is None or t.n % 2 == parity)), key=lambda t: t.n)
        if seq:
            out[name] = seq
    return out


def log_delta_sequence(xs):
    """``log delta_n = x_n - x_{n+1}`` for a class's ``x_n = log|E_n - 4|`` (floats or mpf)."""
    return [a - b for a, b in zip(xs, xs[1:])]


def asymptotic_distance(tau, phase):
    """``|E - 4|`` predicted from the period: ``64 e^{-sqrt3 tau/2}`` (lib), ``64 e^{-sqrt3 tau}`` (rot).

    These follow from ``K(m) ~ log(4/sqrt(m1))`` (paper eqs. for tau_l and tau_r); relative error
    O(|E - 4| log|E - 4|).
    """
    if phase not in ("lib", "rot"):
        raise ValueError(f"phase must be 'lib' or 'rot', got {phase!r}")
    c = math.sqrt(3.0) / (2.0 if phase == "lib" else 1.0)
    try:
        import mpmath as mp

        if isinstance(tau, mp.mpf):
            return 64 * mp.exp(-mp.sqrt(3) / (2 if phase == "lib" else 1) * tau)
    except ImportError:       # pragma: no cover
        pass
    return 64.0 * math.exp(-c * float(tau))


def fit_convergence(xs, errs):
    """Least-squares fit of ``log|err_n| - log|x_n| = a + b x_n``.

    ``b = 1`` means ``err_n ~ C |E_n - 4| log|E_n - 4|``: the error shrinks by the
    factor ``delta`` (times ``x_{n+1}/x_n``) from one member to the next.
    Returns ``(a, b)``.
    """
    xs = np.array([float(x) for x in xs])
    y = np.log(np.abs(np.array([float(e) for e in errs]))) - np.log(np.abs(xs))
    b, a = np.polyfit(xs, y, 1)
    return float(a), float(b)


@dataclass(frozen=True)
class TransverseEigen:
    """Spectrum and eigenvectors of the monodromy M at a transition (paper §5.3).

    Attributes
    ----------
    eigenvalues : ndarray (4,)
        Multipliers of M: the two of M_perp (from its trace, stably) and (1, 1) of M_parallel.
    mu : float
        The multiplier of the transition, +1 (IS) or -1 (PD).
    singular_values : ndarray (2,)
        Of ``M_perp - mu I`` (both ~0: two transverse eigenvectors; one ~0: one).
    null_vectors : list of ndarray
        Transverse eigenvectors in the ``(delta a1, delta p1)`` plane, as 4-vectors
        ``(da1, dp1, da2, dp2)`` in the paper's block basis, normalised, sign fixed.
    longitudinal : ndarray (4,)
        The sliding eigenvector ``(0, 0, 1, 0)`` of M_parallel (checked, not assumed).
    residual : float
        ``max |(M - mu I) v|`` over the transverse eigenvectors.
    """

    eigenvalues: np.ndarray
    mu: float
    singular_values: np.ndarray
    null_vectors: list
    longitudinal: np.ndarray
    residual: float


def transverse_eigenstructure(t, rel_tol=1e-8) -> TransverseEigen:
    """Eigen-structure of M at the transition ``t`` (a :class:`~rotorlib.bifurcations.Transition`).

    At a transition the 2x2 block ``M_perp - mu I`` is nilpotent (rank 1, one
    eigenvector) or zero (PD^l: ``M_perp = -I``, two). ``numpy.linalg.eig`` is
    ill conditioned there (errors ~sqrt(1e-13)); instead the eigenvectors are
    the right singular vectors of ``M_perp - mu I`` whose singular values are
    below ``rel_tol`` times the largest entry of ``M_perp`` (float64 M, ~1e-13).
    """
    from .monodromy import monodromy
    from .orbits import pendulum

    M = monodromy(pendulum(t.energy))
    mu = 1.0 if t.kind == "IS" else -1.0
    P = M.transverse
    N = P - mu * np.eye(2)
    U, s, Vt = np.linalg.svd(N)
    scale = max(1.0, float(np.max(np.abs(P))))
    vecs = []
    for k in range(2):
        if s[k] <= rel_tol * scale:
            v = Vt[k] / np.linalg.norm(Vt[k])
            i = int(np.argmax(np.abs(v)))
            v = v * np.sign(v[i])
            vecs.append(np.array([v[0], v[1], 0.0, 0.0]))
    if len(vecs) == 2:                     # the whole plane: use the coordinate basis
        vecs = [np.array([1.0, 0, 0, 0]), np.array([0, 1.0, 0, 0])]
    L = M.longitudinal - np.eye(2)
    lon = np.array([0.0, 0.0, 1.0, 0.0])
    assert np.max(np.abs(L @ np.array([1.0, 0.0]))) == 0.0
    res = max([float(np.max(np.abs((M.matrix - mu * np.eye(4)) @ v))) for v in vecs] or [float("nan")])
    from .monodromy import multipliers_from_trace

    ev = np.concatenate([np.asarray(multipliers_from_trace(M.trace_transverse)), [1.0, 1.0]])
    return TransverseEigen(ev, mu, s, vecs, lon, res)


def _decimals(text: str) -> int:
    s = text.strip().lower()
    if "e" in s:
        mant, ex = s.split("e")
        d = len(mant.split(".")[1]) if "." in mant else 0
        return d - int(ex)
    return len(s.split(".")[1]) if "." in s else 0


def rounded_verdict(paper: str, ours, digits_ours: int = 12) -> dict:
    """Compare a printed value with ours, at the printed precision.

    Parameters
    ----------
    paper : str
        The value as printed (``'-4.6658'``, ``'2.8611e-11'``, ``'8.243'``).
    ours : float, str or mpf
        Our value (accurate to far more digits than printed).

    Returns
    -------
    dict
        ``paper``, ``ours`` (ours correctly rounded to the printed digits),
        ``difference`` (paper - ours, float), ``tolerance`` (half a unit in the
        last printed digit), ``verdict`` and ``cause``. Verdicts:
        ``agrees`` (the printed value is ours correctly rounded);
        ``truncated`` (ours truncated, not rounded); ``last digit off by k``
        (|k| <= 9: lower precision); ``typo`` (one digit other than the last
        is wrong, possibly with the last digit off by a few units, or two
        adjacent digits transposed); ``DIFFERS`` (anything else).
    """
    d = _decimals(paper)
    q = Decimal(1).scaleb(-d)
    o = Decimal(str(ours)) if not isinstance(ours, Decimal) else ours
    try:
        import mpmath as mp

        if isinstance(ours, mp.mpf):
            o = Decimal(mp.nstr(ours, 40, strip_zeros=False))
    except ImportError:       # pragma: no cover
        pass
    p = Decimal(paper.strip())
    o_r = o.quantize(q, rounding=ROUND_HALF_EVEN)
    o_t = o.quantize(q, rounding=ROUND_DOWN)
    diff = float(p - o)
    tol = float(q) / 2
    k = int((p - o_r) / q)
    a, b = _digits_of(p, d), _digits_of(o_r, d)
    same_shape = len(a) == len(b) and (p < 0) == (o_r < 0)
    diffs = [i for i, (x, y) in enumerate(zip(a, b)) if x != y] if same_shape else []
    swap = (len(diffs) == 2 and diffs[1] == diffs[0] + 1 and a[diffs[0]] == b[diffs[1]]
            and a[diffs[1]] == b[diffs[0]])
    if p == o_r:
        v, cause = "agrees", "correctly rounded"
    elif p == o_t:
        v, cause = "truncated", "ours truncated (not rounded) to the printed digits"
    elif abs(k) <= 3 or (abs(k) <= 9 and not swap):
        v, cause = f"last digit off by {k:+d}", "lower working precision (or an inaccurate input)"
    elif swap:
        v, cause = "typo", "two adjacent digits transposed"
    else:
        v, cause = "DIFFERS", "not explained by rounding or a single typo"
        for i in diffs:                  # one wrong digit (not the last), maybe with the last off by a few units
            if i == len(a) - 1:
                continue
            fixed = Decimal(a[:i] + b[i] + a[i + 1:]) * q * (-1 if p < 0 else 1)
            k2 = int((fixed - o_r) / q)
            if abs(k2) <= 9:
                v = "typo"
                cause = f"digit {a[i]} printed for {b[i]}" + (f", and last digit off by {k2:+d}" if k2 else "")
                break
    return {"paper": paper, "ours": _fmt(o_r, paper), "difference": diff, "tolerance": tol, "verdict": v,
            "cause": cause}


def _digits_of(x: Decimal, d: int) -> str:
    return format(abs(x), f".{d}f").replace(".", "") if d >= 0 else str(abs(x))


def _fmt(o_r: Decimal, paper: str) -> str:
    if "e" in paper.lower():
        mant_digits = len(paper.lower().split("e")[0].replace("-", "").replace(".", "")) - 1
        return f"{float(o_r):.{mant_digits}e}"
    return str(o_r)


def text_table(header, rows) -> str:
    """A plain-text table (columns padded) from a header and rows of values."""
    cells = [[str(c) for c in header]] + [[str(c) for c in r] for r in rows]
    widths = [max(len(r[j]) for r in cells) for j in range(len(header))]
    line = lambda r: "  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip()   # noqa: E731
    return "\n".join([line(cells[0]), "  ".join("-" * w for w in widths)] + [line(r) for r in cells[1:]])
