"""The two sides of the trace formula as signals: the quantum spectrum's and the orbits'.

* :func:`quantum_signal`: the complex Fourier transform of the level density in a Gaussian
  window; :func:`smoothed_density`: the density smoothed in energy;
* :func:`semiclassical_signal`, :func:`smoothed_oscillation`: Gutzwiller's prediction of
  the same from :class:`~rotorlib.beyond.quantum_trace.OrbitTerm` records (action, Maslov
  indices, amplitudes, copies); :func:`sector_signal`: its projection on one symmetry
  sector (the identity's share and the relative orbits of mirrors).

Precision: sums of float64 exponentials (relative error ~1e-13 times the number of
terms); the prediction is exact for the two-dimensional harmonic oscillator
(``tests/test_quantum_trace.py``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from .quantum_trace import CHARACTERS, OrbitTerm, check_positive

__all__ = [
    "quantum_signal",
    "semiclassical_signal",
    "sector_signal",
    "smoothed_density",
    "smoothed_oscillation",
]


def quantum_signal(
    levels: ArrayLike, E0: float, sigma: float, hbar: float, t: ArrayLike
) -> np.ndarray:
    """``(sqrt(2 pi) hbar/sigma) sum_n w(E_n - E0) exp(-i (E_n - E0) t/hbar)``, complex.

    The modulus is :func:`rotorlib.beyond.quantum_semiclassics.density_fourier`; the
    phase is what the trace formula predicts as ``S_p/hbar - sigma_p pi/2``. ``levels``: the
    whole spectrum with multiplicities; ``w`` a Gaussian of width ``sigma``.

    Examples
    --------
    >>> z = quantum_signal([1.0], 1.0, 0.5, 0.1, [0.0, 1.0])
    >>> np.round(np.abs(z), 6).tolist()
    [0.501326, 0.501326]
    """
    h, s = check_positive(hbar, "hbar"), check_positive(sigma, "sigma")
    E = np.asarray(levels, float)
    w = np.exp(-0.5 * ((E - E0) / s) ** 2)
    keep = w > 1e-17
    E, w = E[keep] - E0, w[keep]
    t = np.atleast_1d(np.asarray(t, float))
    return math.sqrt(2.0 * math.pi) * h / s * _transform(E, w, t, h)


#: On a uniform grid of times, the phases are advanced by one multiplication per step
#: and recomputed exactly every ``_ANCHOR`` steps.
_ANCHOR = 64


def _transform(E: np.ndarray, w: np.ndarray, t: np.ndarray, h: float) -> np.ndarray:
    """``sum_n w_n exp(-i E_n t_k / h)`` for every ``t_k``.

    On a uniform grid (steps equal to 1e-12 relative) ``exp(-i E dt/h)`` advances the
    phases from an exact exponential at every ``_ANCHOR``-th point: ~20 times faster
    than an exponential per term, with a rounding error that grows by ~1e-16 per step
    (below 1e-13 relative to ``sum |w|``; ``tests/test_quantum_trace.py``).
    """
    out = np.empty(len(t), complex)
    dt = np.diff(t)
    if len(t) < 3 or np.any(np.abs(dt - dt[0]) > 1e-12 * abs(dt[0])):
        for i0 in range(0, len(t), 256):
            out[i0 : i0 + 256] = np.exp(-1j * np.outer(t[i0 : i0 + 256], E) / h) @ w
        return out
    step = np.exp(-1j * E * (dt[0] / h))
    for i0 in range(0, len(t), _ANCHOR):
        v = w * np.exp(-1j * E * (t[i0] / h))
        out[i0] = v.sum()
        for i in range(i0 + 1, min(i0 + _ANCHOR, len(t))):
            v *= step
            out[i] = v.sum()
    return out


def semiclassical_signal(
    terms: Sequence[OrbitTerm],
    E0: float,
    sigma: float,
    hbar: float,
    t: ArrayLike,
    r_max: int = 3,
    phases: bool = True,
) -> np.ndarray:
    """The trace formula's prediction for :func:`quantum_signal`.

    Each orbit and repetition gives ``A exp(i (r S/hbar - sigma_r pi/2))`` times the
    transform of the window, ``exp(-(t - r T)^2 sigma^2 / 2 hbar^2)``; with a known
    ``period_slope`` ``T'`` the quadratic term ``r T' (E - E0)^2/2`` of the action is kept
    (the Gaussian integral with complex width). ``phases=False``: the moduli only.
    Repetitions with ``det(M^r - 1) = 0`` are skipped. The orbits must be at ``E0``.

    Examples
    --------
    >>> tm = OrbitTerm("x", 1.0, 2.0, 0.0, 20.0, (0,), 1)
    >>> round(float(abs(semiclassical_signal([tm], 1.0, 0.5, 0.1, [2.0], 1)[0])), 6)
    0.5
    """
    h, s = check_positive(hbar, "hbar"), check_positive(sigma, "sigma")
    t = np.atleast_1d(np.asarray(t, float))
    out = np.zeros(len(t), complex)
    for tm in terms:
        if abs(tm.E - E0) > 1e-9 * max(1.0, abs(E0)):
            raise ValueError(f"orbit {tm.label} is at E = {tm.E}, not at E0 = {E0}")
        for r in range(1, min(r_max, len(tm.maslov)) + 1):
            try:
                A = tm.amplitude(r)
            except ValueError:
                continue
            ph = r * tm.action / h - tm.maslov[r - 1] * math.pi / 2 if phases else 0.0
            b = r * tm.period_slope if math.isfinite(tm.period_slope) else 0.0
            # int w(x) exp(i x (rT - t)/h + i b x^2/2h) dx / (sqrt(2 pi) s)
            a = 0.5 / s**2 - 0.5j * b / h
            g = np.exp(-((r * tm.period - t) ** 2) / (4 * a * h * h))
            out += A * np.exp(1j * ph) * g / (s * np.sqrt(2 * a))
    return out


def sector_signal(
    terms: Sequence[OrbitTerm],
    sector: str,
    E0: float,
    sigma: float,
    hbar: float,
    t: ArrayLike,
    r_max: int = 3,
) -> np.ndarray:
    """The trace formula's :func:`quantum_signal` of one sector's distinct levels.

    ``(1/12) sum_g chi(g) Tr(U(g) delta(E - H))``: the identity gives ``d/12`` of
    :func:`semiclassical_signal`; a reflection ``g`` that fixes ``g_p`` copies of an orbit
    pointwise adds ``(1/12) chi(g) g_p T A~_r exp(i (r S/hbar - sigma~_r pi/2))`` per
    repetition (:func:`reflection_term`). Orbits closing up to a rotation or to a
    reflection with a time shift (relative orbits of a fraction of the period) are not
    included.

    Examples
    --------
    >>> tm = OrbitTerm("x", 1.0, 2.0, 0.0, 20.0, (0,), 12)
    >>> round(float(abs(sector_signal([tm], "E1", 1.0, 0.5, 0.1, [2.0], 1)[0])), 6)
    1.0
    """
    if sector not in CHARACTERS:
        raise ValueError(f"sector must be one of {sorted(CHARACTERS)}, not {sector!r}")
    h, s = check_positive(hbar, "hbar"), check_positive(sigma, "sigma")
    chi = CHARACTERS[sector]
    t = np.atleast_1d(np.asarray(t, float))
    out = chi["E"] / 12.0 * semiclassical_signal(terms, E0, s, h, t, r_max)
    for tm in terms:
        weight = sum(chi[c] for c in tm.mirrors) * tm.copies / 12.0
        if weight == 0:
            continue
        b = tm.period_slope if math.isfinite(tm.period_slope) else 0.0
        for r in range(1, min(r_max, len(tm.mirror_maslov)) + 1):
            ph = r * tm.action / h - tm.mirror_maslov[r - 1] * math.pi / 2
            a = 0.5 / s**2 - 0.5j * r * b / h
            g = np.exp(-((r * tm.period - t) ** 2) / (4 * a * h * h)) / (
                s * np.sqrt(2 * a)
            )
            A = weight * tm.period * tm.mirror_amplitude[r - 1]
            out += A * np.exp(1j * ph) * g
    return out


def smoothed_density(levels: ArrayLike, E: ArrayLike, gamma: float) -> np.ndarray:
    """``sum_n exp(-(E - E_n)^2 / 2 gamma^2) / (sqrt(2 pi) gamma)``: the level density
    smoothed by a Gaussian of width ``gamma`` (``levels`` with multiplicities).

    Examples
    --------
    >>> round(float(smoothed_density([0.0], [0.0], 1.0)[0]), 6)
    0.398942
    """
    g = check_positive(gamma, "gamma")
    x = np.sort(np.asarray(levels, float))
    E = np.atleast_1d(np.asarray(E, float))
    out = np.empty(len(E))
    for i, e in enumerate(E):
        lo, hi = np.searchsorted(x, [e - 9 * g, e + 9 * g])
        out[i] = np.exp(-0.5 * ((e - x[lo:hi]) / g) ** 2).sum()
    return out / (math.sqrt(2 * math.pi) * g)


def smoothed_oscillation(
    terms: Sequence[OrbitTerm],
    E: ArrayLike,
    gamma: float,
    hbar: float,
    r_max: int = 3,
) -> np.ndarray:
    """The trace formula's oscillating density smoothed by a Gaussian of width ``gamma``:
    ``(1/pi hbar) sum A_r exp(-(gamma r T/hbar)^2/2) cos(r S(E)/hbar - sigma_r pi/2)``
    with ``S(E) = S + T (E - E0) + T' (E - E0)^2/2`` (``T'`` = 0 where unknown) around
    each orbit's energy ``E0``.

    Examples
    --------
    >>> tm = OrbitTerm("x", 1.0, 2.0, 0.0, 20.0, (0,), 1)
    >>> round(float(smoothed_oscillation([tm], [1.0], 0.01, 0.1, 1)[0]), 6)
    1.560035
    """
    h, g = check_positive(hbar, "hbar"), check_positive(gamma, "gamma")
    E = np.atleast_1d(np.asarray(E, float))
    out = np.zeros(len(E))
    for tm in terms:
        dE = E - tm.E
        b = tm.period_slope if math.isfinite(tm.period_slope) else 0.0
        S = tm.action + tm.period * dE + 0.5 * b * dE**2
        for r in range(1, min(r_max, len(tm.maslov)) + 1):
            try:
                A = tm.amplitude(r)
            except ValueError:
                continue
            damp = math.exp(-0.5 * (g * r * tm.period / h) ** 2)
            out += A * damp * np.cos(r * S / h - tm.maslov[r - 1] * math.pi / 2)
    return out / (math.pi * h)
