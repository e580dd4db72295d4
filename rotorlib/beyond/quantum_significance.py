"""Is a trace formula's match with a spectrum better than chance? Tests against random periods.

Two statistics, each with a null of the same size (:mod:`rotorlib.beyond.quantum_trace`
gives the signals):

* :func:`match_test`: how many peaks of the quantum transform have a predicted period within
  a tolerance, against as many periods drawn uniformly on the same range;
* :func:`correlation_test`: the complex correlation of the quantum and predicted signals
  (phases included) and of their moduli, against the same orbits moved to random periods
  with random phases.

p-values are ``(1 + #{null >= observed}) / (1 + draws)`` (exact for exchangeable draws),
so the smallest is ``1/(1 + draws)``; the draws are seeded (reproducible).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .quantum_signals import semiclassical_signal
from .quantum_trace import OrbitTerm, check_positive

__all__ = [
    "peak_times",
    "peak_match",
    "MatchTest",
    "match_test",
    "signal_correlation",
    "CorrelationTest",
    "correlation_test",
]


def peak_times(t: ArrayLike, signal: ArrayLike, height: float) -> np.ndarray:
    """Times of the local maxima of ``|signal|`` above ``height``.

    Examples
    --------
    >>> t = np.linspace(0.0, 4.0, 401)
    >>> peak_times(t, np.exp(-((t - 1) ** 2) * 20) + 2 * np.exp(-((t - 3) ** 2) * 20), 1.5)
    array([3.])
    """
    from scipy.signal import find_peaks

    t = np.asarray(t, float)
    a = np.abs(np.asarray(signal))
    if t.shape != a.shape or t.ndim != 1:
        raise ValueError("t and signal must be 1-d arrays of the same length")
    idx, _ = find_peaks(a, height=float(height))
    return t[idx]


def peak_match(peaks: ArrayLike, periods: ArrayLike, tol: float) -> np.ndarray:
    """For each peak, whether a period lies within ``tol`` of it (bool array).

    Examples
    --------
    >>> peak_match([1.0, 2.0, 3.0], [2.05, 5.0], 0.1).tolist()
    [False, True, False]
    """
    p = np.sort(np.asarray(periods, float))
    x = np.asarray(peaks, float)
    if len(p) == 0:
        return np.zeros(len(x), bool)
    j = (
        np.clip(np.searchsorted(p, x), 1, len(p) - 1)
        if len(p) > 1
        else np.zeros(len(x), int)
    )
    d = np.minimum(np.abs(x - p[j]), np.abs(x - p[np.maximum(j - 1, 0)]))
    return d <= tol


@dataclass(frozen=True)
class MatchTest:
    """Peaks explained by the periods, against periods drawn at random.

    ``explained``: peaks with a period within ``tol``; ``null``: the same count for each
    random draw (as many periods, uniform on ``t_range``); ``p_value``:
    ``(1 + #{null >= explained}) / (1 + draws)``.
    """

    explained: int
    peaks: int
    null: np.ndarray
    p_value: float

    @property
    def null_mean(self) -> float:
        return float(np.mean(self.null))


def match_test(
    peaks: ArrayLike,
    periods: ArrayLike,
    tol: float,
    t_range: tuple[float, float],
    draws: int = 10000,
    seed: int = 0,
) -> MatchTest:
    """How many ``peaks`` the ``periods`` explain, and how often random periods do as well.

    Examples
    --------
    >>> m = match_test([2.0, 5.0, 8.0], [2.01, 5.0, 8.02], 0.05, (1.0, 10.0), 2000)
    >>> m.explained, m.p_value < 0.01
    (3, True)
    """
    lo, hi = (float(v) for v in t_range)
    if not (hi > lo):
        raise ValueError(f"t_range must be increasing, not {t_range!r}")
    check_positive(tol, "tol")
    if not (isinstance(draws, (int, np.integer)) and draws >= 1):
        raise ValueError(f"draws must be a positive integer, not {draws!r}")
    x = np.asarray(peaks, float)
    p = np.asarray(periods, float)
    p = p[(p >= lo) & (p <= hi)]
    obs = int(peak_match(x, p, tol).sum())
    rng = np.random.default_rng(seed)
    null = np.array(
        [peak_match(x, rng.uniform(lo, hi, len(p)), tol).sum() for _ in range(draws)]
    )
    pv = (1 + int(np.sum(null >= obs))) / (1 + draws)
    return MatchTest(explained=obs, peaks=len(x), null=null, p_value=pv)


@dataclass(frozen=True)
class CorrelationTest:
    """The complex correlation of the quantum and semiclassical signals, and its null.

    ``value``: ``Re <q, s> / (|q| |s|)`` over the times given (1: the same signal, phases
    included); ``modulus``: the same for ``|q|`` and ``|s|`` after removing their means;
    ``null``, ``null_modulus``: both for the orbits moved to random periods (same
    amplitudes, actions and indices); ``p_value``, ``p_modulus``: the fraction of the
    null at least as large (with the ``+1`` of an exact test).
    """

    value: float
    modulus: float
    null: np.ndarray
    null_modulus: np.ndarray
    p_value: float
    p_modulus: float


def signal_correlation(q: ArrayLike, s: ArrayLike) -> float:
    """``Re <s, q> / (|q| |s|)``: 1 for equal signals (phases included), 0 if either is 0.

    Examples
    --------
    >>> signal_correlation([1j, 0.0], [2j, 0.0]), signal_correlation([1j], [-1j])
    (1.0, -1.0)
    """
    q, s = np.asarray(q, complex), np.asarray(s, complex)
    if q.shape != s.shape:
        raise ValueError(f"q and s differ in shape: {q.shape} and {s.shape}")
    nq, ns = np.linalg.norm(q), np.linalg.norm(s)
    return float(np.real(np.vdot(s, q)) / (nq * ns)) if nq > 0 and ns > 0 else 0.0


def correlation_test(
    q: ArrayLike,
    terms: Sequence[OrbitTerm],
    E0: float,
    sigma: float,
    hbar: float,
    t: ArrayLike,
    r_max: int = 3,
    draws: int = 1000,
    seed: int = 0,
) -> CorrelationTest:
    """Correlate the quantum signal ``q(t)`` with the trace formula, against chance.

    The null moves every orbit (each repetition with it) to a period drawn uniformly on
    the time range of ``t`` and a uniformly random phase, keeping its amplitude.

    Examples
    --------
    >>> tm = OrbitTerm("x", 1.0, 2.0, 0.3, 20.0, (1, 2), 1)
    >>> tt = np.linspace(1.0, 4.0, 301)
    >>> q = semiclassical_signal([tm], 1.0, 0.5, 0.1, tt)
    >>> c = correlation_test(q, [tm], 1.0, 0.5, 0.1, tt, draws=200)
    >>> round(c.value, 6), c.p_value < 0.05
    (1.0, True)
    """
    t = np.asarray(t, float)
    q = np.asarray(q, complex)
    if q.shape != t.shape or t.ndim != 1 or len(t) < 2:
        raise ValueError("q and t must be 1-d arrays of the same length (>= 2)")
    if not (isinstance(draws, (int, np.integer)) and draws >= 1):
        raise ValueError(f"draws must be a positive integer, not {draws!r}")
    s = semiclassical_signal(terms, E0, sigma, hbar, t, r_max)
    aq = np.abs(q) - np.abs(q).mean()
    val, mod = (
        signal_correlation(q, s),
        signal_correlation(aq, np.abs(s) - np.abs(s).mean()),
    )
    rng = np.random.default_rng(seed)
    lo, hi = float(t[0]), float(t[-1])
    null, null_m = np.empty(draws), np.empty(draws)
    for k in range(draws):
        moved = [
            OrbitTerm(
                tm.label,
                tm.E,
                float(rng.uniform(lo, hi)),
                float(rng.uniform(0, 2 * math.pi * hbar)),
                tm.trace,
                tm.maslov,
                tm.copies,
            )
            for tm in terms
        ]
        sr = semiclassical_signal(moved, E0, sigma, hbar, t, r_max)
        null[k] = signal_correlation(q, sr)
        null_m[k] = signal_correlation(aq, np.abs(sr) - np.abs(sr).mean())
    return CorrelationTest(
        value=val,
        modulus=mod,
        null=null,
        null_modulus=null_m,
        p_value=(1 + int(np.sum(null >= val))) / (1 + draws),
        p_modulus=(1 + int(np.sum(null_m >= mod))) / (1 + draws),
    )
