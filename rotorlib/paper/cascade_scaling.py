"""Scaling constants of the pendulum bifurcation cascade and comparison with printed values (paper §5).

* :func:`class_sequences` splits transitions into the seven classes of §5.
* :func:`log_delta_sequence`: ``log delta_n = log|E_n - 4| - log|E_{n+1} - 4|`` within a class;
  predicted limits ``sqrt(3) pi`` (libration) and ``2 sqrt(3) pi`` (rotation).
* :func:`asymptotic_distance`: the paper's asymptotic energy formulas
  ``4 - E = 64 exp(-sqrt3 tau/2)`` (libration) and ``E - 4 = 64 exp(-sqrt3 tau)`` (rotation).
* :func:`fit_convergence`: fit ``log|err_n| = a + b x_n + log|x_n|`` (error ~ ``|E-4| log|E-4|``).
* :func:`transverse_eigenstructure`: spectrum and transverse eigenvectors of M at a transition,
  robust to the parabolic (defective) 2x2 block.

Numerics only (no matplotlib). Works with floats or mpmath numbers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import mpmath as mp
import numpy as np

from ..core.closed_forms import pendulum
from ..orbits.floquet import monodromy, multipliers_from_trace
from .bifurcations import CLASSES, Transition

__all__ = [
    "class_sequences",
    "log_delta_sequence",
    "asymptotic_distance",
    "fit_convergence",
    "TransverseEigen",
    "transverse_eigenstructure",
    "HarmonicFit",
    "fit_harmonic",
    "separatrix_transmission",
    "TraceAsymptotics",
    "trace_asymptotics",
]


def class_sequences(trs: Sequence[Transition]) -> dict[str, list[Transition]]:
    """``{class name: [transitions ordered by n]}`` for the seven classes of §5 (empty classes dropped)."""
    out: dict[str, list[Transition]] = {}
    for t in sorted(trs, key=lambda t: t.n):
        out.setdefault(t.cls, []).append(t)
    return {name: out[name] for name in CLASSES if name in out}


def log_delta_sequence(xs: Sequence[Any]) -> list[Any]:
    """``log delta_n = x_n - x_{n+1}`` for a class's ``x_n = log|E_n - 4|`` (floats or mpf)."""
    return [a - b for a, b in zip(xs, xs[1:])]


def asymptotic_distance(tau: Any, phase: str) -> Any:
    """``|E - 4|`` predicted from the period: ``64 e^{-sqrt3 tau/2}`` (lib), ``64 e^{-sqrt3 tau}`` (rot).

    These follow from ``K(m) ~ log(4/sqrt(m1))`` (paper eqs. for tau_l and tau_r); relative error
    O(|E - 4| log|E - 4|).
    """
    if phase not in ("lib", "rot"):
        raise ValueError(f"phase must be 'lib' or 'rot', got {phase!r}")
    if isinstance(tau, mp.mpf):
        return 64 * mp.exp(-mp.sqrt(3) / (2 if phase == "lib" else 1) * tau)
    return 64.0 * math.exp(
        -math.sqrt(3.0) / (2.0 if phase == "lib" else 1.0) * float(tau)
    )


def fit_convergence(xs: Sequence[Any], errs: Sequence[Any]) -> tuple[float, float]:
    """Least-squares fit of ``log|err_n| - log|x_n| = a + b x_n``.

    ``b = 1`` means ``err_n ~ C |E_n - 4| log|E_n - 4|``: the error shrinks by the
    factor ``delta`` (times ``x_{n+1}/x_n``) from one member to the next.
    Returns ``(a, b)``.
    """
    x = np.array([float(v) for v in xs])
    y = np.log(np.abs(np.array([float(e) for e in errs]))) - np.log(np.abs(x))
    b, a = np.polyfit(x, y, 1)
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


def transverse_eigenstructure(t: Transition, rel_tol: float = 1e-8) -> TransverseEigen:
    """Eigen-structure of M at the transition ``t`` (a :class:`~rotorlib.paper.bifurcations.Transition`).

    At a transition the 2x2 block ``M_perp - mu I`` is nilpotent (rank 1, one
    eigenvector) or zero (PD^l: ``M_perp = -I``, two). ``numpy.linalg.eig`` is
    ill conditioned there (errors ~sqrt(1e-13)); instead the eigenvectors are
    the right singular vectors of ``M_perp - mu I`` whose singular values are
    below ``rel_tol`` times the largest entry of ``M_perp`` (float64 M, ~1e-13).
    """
    M = monodromy(pendulum(t.energy))
    mu = 1.0 if t.kind == "IS" else -1.0
    P, Mpar = M.transverse, M.longitudinal
    assert P is not None and Mpar is not None  # the block route
    _, s, Vt = np.linalg.svd(P - mu * np.eye(2))
    scale = max(1.0, float(np.max(np.abs(P))))
    unit = [v / np.linalg.norm(v) for v in Vt[s <= rel_tol * scale]]  # null vectors
    vecs = [np.array([*v * np.sign(v[np.argmax(np.abs(v))]), 0.0, 0.0]) for v in unit]
    if len(vecs) == 2:  # the whole plane: use the coordinate basis
        vecs = [np.array([1.0, 0, 0, 0]), np.array([0, 1.0, 0, 0])]
    assert np.max(np.abs((Mpar - np.eye(2)) @ np.array([1.0, 0.0]))) == 0.0
    res = max(
        [float(np.max(np.abs((M.matrix - mu * np.eye(4)) @ v))) for v in vecs]
        or [float("nan")]
    )
    return TransverseEigen(
        np.concatenate(
            [np.asarray(multipliers_from_trace(M.trace_transverse)), [1.0, 1.0]]
        ),
        mu,
        s,
        vecs,
        np.array([0.0, 0.0, 1.0, 0.0]),
        res,
    )


# --------------------------------------------------------------------------- tr M_perp asymptotics


@dataclass(frozen=True)
class HarmonicFit:
    """Least-squares fit ``y ~ c0 + c1 cos(tau) + s1 sin(tau)`` on a window of periods.

    Attributes
    ----------
    c0, c1, s1 : float
        Coefficients.
    amplitude : float
        ``sqrt(c1^2 + s1^2)``.
    phase : float
        ``phi`` in ``y ~ c0 + amplitude cos(tau + phi)`` (radians, in (-pi, pi]).
    max_residual : float
        Largest ``|y - fit|`` on the window (the model error plus the data error).
    tau_min, tau_max : float
        The window.
    n : int
        Number of samples.
    """

    c0: float
    c1: float
    s1: float
    amplitude: float
    phase: float
    max_residual: float
    tau_min: float
    tau_max: float
    n: int


def fit_harmonic(
    tau: Any, y: Any, tau_min: float = -np.inf, tau_max: float = np.inf
) -> HarmonicFit:
    """Fit ``y(tau) ~ c0 + c1 cos tau + s1 sin tau`` (angular frequency 1) on ``tau_min <= tau <= tau_max``.

    Precision: a float64 linear least-squares fit (``numpy.linalg.lstsq``); with
    ``tr M_perp`` data accurate to ~1e-13 the coefficients are limited by the
    model error (the ``O(|E - 4| log|E - 4|)`` corrections inside the window,
    reported as ``max_residual``), down to ~1e-13 on windows of a few hundred
    points.

    Raises
    ------
    ValueError
        Fewer than 3 samples in the window, arrays of different shapes, or
        non-finite data.
    """
    tau = np.asarray(tau, dtype=float)
    y = np.asarray(y, dtype=float)
    if tau.shape != y.shape or tau.ndim != 1:
        raise ValueError(
            f"tau and y must be 1-d arrays of the same shape, got {tau.shape} and {y.shape}"
        )
    sel = (tau >= tau_min) & (tau <= tau_max)
    if int(sel.sum()) < 3:
        raise ValueError(
            f"need at least 3 samples with {tau_min} <= tau <= {tau_max}, got {int(sel.sum())}"
        )
    t, v = tau[sel], y[sel]
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
        raise ValueError("tau and y must be finite in the window")
    A = np.column_stack([np.ones_like(t), np.cos(t), np.sin(t)])
    (c0, c1, s1), *_ = np.linalg.lstsq(A, v, rcond=None)
    return HarmonicFit(
        float(c0),
        float(c1),
        float(s1),
        float(math.hypot(c1, s1)),
        float(math.atan2(-s1, c1)),
        float(np.max(np.abs(A @ np.array([c0, c1, s1]) - v))),
        float(t.min()),
        float(t.max()),
        int(t.size),
    )


def separatrix_transmission(digits: int | None = None) -> Any:
    """``|t|^2``: transmission probability of one passage near the separatrix (Pöschl-Teller well).

    On the separatrix (``k -> 1``) the transverse Lamé equation (paper eqs. for libration and
    rotation, ``z = sqrt3 t``) becomes ``-y'' - (2/3) sech^2(z) y = (1/3) y``: free oscillation
    with wave number ``q = 1/sqrt3`` (``omega_perp = 1`` in time) near the saddle, where the orbit
    spends most of its time, and one scattering by the Pöschl-Teller well ``nu(nu+1) sech^2 z``,
    ``nu(nu+1) = 2/3``, per passage between two visits. Its transmission probability (Landau &
    Lifshitz, *Quantum Mechanics*, §25 problem 4) is

    ``|t|^2 = sinh^2(pi q) / (sinh^2(pi q) + cos^2((pi/2) sqrt(1 + 4 nu(nu+1))))``.

    ``nu`` is not an integer, so the well reflects (``|t| < 1``).

    Parameters
    ----------
    digits : int, optional
        ``None``: float64 (correctly rounded to ~1e-16). Otherwise an ``mpmath.mpf`` computed
        with ``digits`` decimal digits.
    """
    if digits is not None and (not isinstance(digits, int) or digits < 1):
        raise ValueError(f"digits must be a positive integer or None, got {digits!r}")
    with mp.workdps((digits or 16) + 10):
        q = 1 / mp.sqrt(3)
        sh2 = mp.sinh(mp.pi * q) ** 2
        c2 = mp.cos(mp.pi / 2 * mp.sqrt(1 + 4 * mp.mpf(2) / 3)) ** 2
        T = sh2 / (sh2 + c2)
        return float(T) if digits is None else +T


@dataclass(frozen=True)
class TraceAsymptotics:
    """Limit of ``tr M_perp(tau) = c0 + amplitude cos(tau + phi) + o(1)`` as ``E -> 4`` (one phase).

    Attributes
    ----------
    phase : {'lib', 'rot'}
    transmission : float
        ``|t|^2`` of one separatrix passage (:func:`separatrix_transmission`).
    c0, amplitude : float
        Rotation (one passage per period): ``0`` and ``2/|t|``. Libration (two passages, ``tr M_perp =
        Delta^2 - 2`` with ``Delta -> (2/|t|) cos(tau/2 + phi')``): ``2/|t|^2 - 2`` and ``2/|t|^2``.
    window_width : float
        Asymptotic width in ``tau`` of each unstable window (``|Delta| > 2``): ``2 arccos|t|``
        (rotation) or ``4 arccos|t|`` (libration), i.e. ``tau(IS_{2n}) - tau(IS_{2n-1})``.
    """

    phase: str
    transmission: float
    c0: float
    amplitude: float
    window_width: float


def trace_asymptotics(phase: str) -> TraceAsymptotics:
    """Asymptotic form of ``tr M_perp(tau)`` near the separatrix (float64, ~1e-16 relative).

    Between passages ``delta alpha_1`` oscillates with ``omega_perp = 1`` (paper §5.2, eq. for
    ``tr M_perp``); each passage away from the saddle scatters it with transmission amplitude
    ``|t| < 1``: in the travelling-wave basis ``e^{+-i tau}`` the transfer matrix of a passage is
    unimodular with diagonal entries ``1/t`` and its conjugate, so one free stretch and one passage
    give ``tr -> 2 Re(e^{i tau}/t) = (2/|t|) cos(tau + phi)``. The paper's ``2 cos(omega_perp tau)`` is the reflectionless case ``|t| = 1``.
    Corrections are ``O(|E - 4| log|E - 4|)``.

    Raises
    ------
    ValueError
        ``phase`` not ``'lib'`` or ``'rot'``.
    """
    if phase not in ("lib", "rot"):
        raise ValueError(f"phase must be 'lib' or 'rot', got {phase!r}")
    T = separatrix_transmission()
    t = math.sqrt(T)
    if phase == "rot":
        return TraceAsymptotics(phase, T, 0.0, 2.0 / t, 2.0 * math.acos(t))
    return TraceAsymptotics(phase, T, 2.0 / T - 2.0, 2.0 / T, 4.0 * math.acos(t))
