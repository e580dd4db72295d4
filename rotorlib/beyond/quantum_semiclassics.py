"""Semiclassical checks of the quantum 3-rotor spectrum (:mod:`rotorlib.beyond.quantum`).

* the bottom of the well: both normal modes at G have frequency sqrt 3 (a 1:1 resonance),
  so the harmonic shell ``n`` holds ``n + 1`` levels at ``hbar sqrt 3 (n + 1)``; the quartic
  term of V splits it at order ``hbar^2`` (:func:`harmonic_levels`, first-order degenerate
  perturbation theory, exact to ``O(hbar^3)``);
* Weyl's law with its first correction (:func:`weyl_count`, :func:`weyl_correction`);
* the mean ratio of consecutive spacings (:func:`ratio_statistics`);
* the windowed Fourier transform of the level density against Gutzwiller's periodic-orbit
  amplitudes (:func:`density_fourier`, :func:`gutzwiller_amplitude`, :func:`orbit_copies`).

Units g = m r^2 = 1; the inverse mass matrix of ``(phi1, phi2)`` is ``[[2, -1], [-1, 2]]``.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "R_POISSON",
    "R_GOE",
    "hbar_from_qubit",
    "zero_point_energy",
    "harmonic_levels",
    "phase_space_integral",
    "weyl_count",
    "weyl_correction",
    "spacing_ratios",
    "RatioStatistics",
    "ratio_statistics",
    "density_fourier",
    "gutzwiller_amplitude",
    "orbit_copies",
]

#: ``<r>`` of a Poisson spectrum, ``2 ln 2 - 1``.
R_POISSON = 2.0 * math.log(2.0) - 1.0
#: ``<r>`` of large GOE matrices (Atas, Bogomolny, Giraud, Roux, PRL 110, 084101 (2013)).
R_GOE = 0.5307


def _positive(x, name):
    x = float(x)
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{name} must be positive and finite, not {x}")
    return x


def hbar_from_qubit(EJ_over_EC: float) -> float:
    """The rotor's ``hbar`` of a three-junction loop with equal junctions (Appendix A).

    With ``Ej = g`` and ``m r^2 = 3 C (hbar/2e)^2``, ``E_C = e^2/2C``:
    ``hbar_rotor^2 = hbar^2/(g m r^2) = 8 E_C / (3 E_J)``. Exact.

    Examples
    --------
    >>> round(hbar_from_qubit(80.0), 6)
    0.182574
    """
    return math.sqrt(8.0 / (3.0 * _positive(EJ_over_EC, "E_J/E_C")))


def zero_point_energy(hbar: float) -> float:
    """``hbar sqrt 3 - hbar^2/8``: the ground level to ``O(hbar^3)``.

    The quartic term ``-(phi1^4 + phi2^4 + (phi1 + phi2)^4)/24`` of V averaged over the
    harmonic ground state (each of the three angles has variance ``hbar/sqrt 3``) gives
    ``-hbar^2/8``.

    Examples
    --------
    >>> round(zero_point_energy(0.01), 8)
    0.01730801
    """
    h = _positive(hbar, "hbar")
    return h * math.sqrt(3.0) - h * h / 8.0


def harmonic_levels(hbar: float, n_max: int) -> list[np.ndarray]:
    """The normal-form prediction of the lowest levels, shell by shell.

    Shell ``n`` (``n + 1`` levels): ``hbar sqrt 3 (n + 1) + hbar^2 w`` with ``w`` the
    eigenvalues of the quartic ``-(1/24) sum_a (c_a . phi)^4`` (``c_a`` = (1,0), (0,1),
    (1,1)) restricted to the shell, in units of ``hbar^2``. The error is ``O(hbar^3)``.

    Returns
    -------
    list of numpy.ndarray
        Element ``n``: the ``n + 1`` predicted levels of shell ``n``, ascending.

    Examples
    --------
    >>> [np.round(x / 0.01, 4).tolist() for x in harmonic_levels(0.01, 1)]
    [[1.7308], [3.4604, 3.4604]]
    """
    h = _positive(hbar, "hbar")
    if not (isinstance(n_max, (int, np.integer)) and 0 <= n_max <= 60):
        raise ValueError(f"n_max must be an integer from 0 to 60, not {n_max!r}")
    w = math.sqrt(3.0)
    D = n_max + 4  # quanta per mode in the truncated Fock space
    a = np.diag(np.sqrt(np.arange(1, D)), 1)
    X = a + a.T  # a + a^dagger
    one = np.eye(D)
    X1, X2 = np.kron(X, one), np.kron(one, X)
    nq = np.add.outer(np.arange(D), np.arange(D)).ravel()
    evals, evecs = np.linalg.eigh(np.array([[2.0, -1.0], [-1.0, 2.0]]))
    Ah = evecs @ np.diag(np.sqrt(evals)) @ evecs.T  # A^(1/2): phi = A^(1/2) x
    W = np.zeros_like(X1)
    for c in ((1.0, 0.0), (0.0, 1.0), (1.0, 1.0)):
        d = Ah @ np.array(c)
        u = d[0] * X1 + d[1] * X2
        u2 = u @ u
        W -= (u2 @ u2) / 24.0
    W *= (1.0 / (2.0 * w)) ** 2  # x = sqrt(hbar/2 omega) (a + a^dagger)
    out = []
    for n in range(n_max + 1):
        idx = np.nonzero(nq == n)[0]
        shift = np.linalg.eigvalsh(W[np.ix_(idx, idx)])
        out.append(h * w * (n + 1) + h * h * shift)
    return out


def _phase_space(E, what):
    """``int (E - V)_+ dphi`` (``what="volume"``) or ``area{V < E}`` over the torus.

    At fixed phi1, ``V = a - |b| cos psi`` with ``a = 3 - cos phi1``,
    ``b = 2 cos(phi1/2)``, ``psi = phi2 + phi1/2``: the psi integral is elementary and
    the phi1 integral (a periodic integrand with square-root kinks) is done by
    Gauss-Legendre quadrature between its kinks."""
    from scipy.integrate import quad

    def inner(f1):
        a, b = 3.0 - math.cos(f1), abs(2.0 * math.cos(0.5 * f1))
        if b == 0.0:
            return (
                2 * math.pi * max(E - a, 0.0)
                if what == "volume"
                else (2 * math.pi if E > a else 0.0)
            )
        x = (a - E) / b
        if x >= 1.0:
            return 0.0
        if x <= -1.0:
            return 2 * math.pi * (E - a) if what == "volume" else 2 * math.pi
        ac = math.acos(x)
        if what == "volume":
            return 2.0 * ((E - a) * ac + b * math.sqrt(1.0 - x * x))
        return 2.0 * ac

    # kinks where (a - E)/b = +-1: 3 - cos f - E = +-2 cos(f/2); with c = cos(f/2):
    # 4 - 2 c^2 - E = +-2 c
    pts = []
    for s in (1.0, -1.0):
        for c in np.roots([2.0, s * 2.0, E - 4.0]):
            if abs(c.imag) < 1e-14 and -1.0 <= c.real <= 1.0:
                f = 2.0 * math.acos(c.real)
                pts += [f, 2 * math.pi - f]
    pts = sorted(p for p in pts if 0.0 < p < 2 * math.pi)
    with warnings.catch_warnings():  # the square-root kinks are at the given points
        warnings.simplefilter("ignore")
        val, _ = quad(
            inner, 0.0, 2 * math.pi, points=pts or None, limit=400, epsabs=1e-13
        )
    return val


def phase_space_integral(E: float) -> float:
    """``int (E - V)_+ dphi1 dphi2`` over the torus (to ~1e-12).

    Examples
    --------
    >>> round(phase_space_integral(6.0) / (4 * math.pi**2), 10)  # E above max V: E - 3
    3.0
    """
    return _phase_space(float(E), "volume")


def weyl_count(
    E: ArrayLike, hbar: float, correction: bool = True
) -> float | np.ndarray:
    """Smoothed number of levels below ``E`` (the whole spectrum, with multiplicities).

    ``N(E) = (2 pi hbar)^-2 int (2 pi/sqrt 3)(E - V)_+ dphi`` (the phase-space volume: at
    each point the momenta with ``P1^2 - P1 P2 + P2^2 <= E - V`` fill an ellipse of area
    ``2 pi (E - V)/sqrt 3``), plus, with ``correction``, :func:`weyl_correction` (order
    ``hbar^0``; the next term is ``O(hbar^2)``).

    Examples
    --------
    >>> round(weyl_count(6.0, 0.1, correction=False), 6)  # (2 pi/sqrt 3) (E - 3)/hbar^2
    1088.279619
    """
    h = _positive(hbar, "hbar")
    E = np.atleast_1d(np.asarray(E, float))
    lead = np.array(
        [phase_space_integral(e) / (2.0 * math.sqrt(3.0) * math.pi * h * h) for e in E]
    )
    if correction:
        lead = lead + weyl_correction(E)
    return lead if lead.size > 1 else float(lead[0])


def weyl_correction(E: ArrayLike, dE: float = 1e-5) -> float | np.ndarray:
    """The ``hbar^0`` term of the smoothed counting function (Wigner-Kirkwood).

    For ``H = P.A.P/2 + V`` in two dimensions the first correction is
    ``-(sqrt(det A^-1)/48 pi) int tr(A Hess V) delta(E - V) dphi``; here ``A = [[2, -1],
    [-1, 2]]`` and ``tr(A Hess V) = 2 (3 - V)``, so it is
    ``-(3 - E) area'(E) / (24 sqrt 3 pi)`` with ``area(E)`` the area where ``V < E``.
    It tends to ``-1/12`` at the bottom (the isotropic oscillator's
    ``N = x^2/2 - 1/12``) and vanishes above ``max V = 4.5``. ``area'`` by a central
    difference of step ``dE`` (~1e-9 except within ``dE`` of the saddle energy 4 and 4.5).

    Examples
    --------
    >>> round(weyl_correction(1e-3), 4)
    -0.0833
    """
    E = np.atleast_1d(np.asarray(E, float))
    values = []
    for e in E:
        lo = max(e - dE, 0.0)
        d = (_phase_space(e + dE, "area") - _phase_space(lo, "area")) / (e + dE - lo)
        values.append(-(3.0 - e) * d / (24.0 * math.sqrt(3.0) * math.pi))
    out = np.array(values)
    return out if out.size > 1 else float(out[0])


def spacing_ratios(levels: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """``r_n = min(s_n, s_{n+1}) / max(s_n, s_{n+1})`` of one symmetry sector.

    Returns ``(E_n, r_n)``: the middle level of each triple and its ratio (a triple of
    coincident levels, ``0/0``, is dropped).

    Examples
    --------
    >>> spacing_ratios([0.0, 1.0, 3.0, 4.0])[1].tolist()
    [0.5, 0.5]
    """
    x = np.sort(np.asarray(levels, float))
    s = np.diff(x)
    a, b = s[:-1], s[1:]
    big = np.maximum(a, b)
    ok = big > 0
    return x[1:-1][ok], np.minimum(a, b)[ok] / big[ok]


@dataclass(frozen=True)
class RatioStatistics:
    """``<r>`` in energy windows: ``edges`` (n + 1), ``mean``, ``error`` (the standard error
    of the mean, ``std/sqrt(count)``) and ``count`` (n each)."""

    edges: np.ndarray
    mean: np.ndarray
    error: np.ndarray
    count: np.ndarray

    @property
    def centres(self) -> np.ndarray:
        return 0.5 * (self.edges[1:] + self.edges[:-1])


def ratio_statistics(sectors: Sequence[ArrayLike], edges: ArrayLike) -> RatioStatistics:
    """``<r>`` per energy window, pooling the ratios of every sector given.

    Ratios are computed within each sector (levels of different symmetry are
    uncorrelated) and assigned to the window of their middle level. No unfolding is
    needed: ``r`` is independent of the local density.

    Parameters
    ----------
    sectors : sequence of arrays
        The levels of each sector (each level once).
    edges : array
        Window edges.

    Examples
    --------
    >>> st = ratio_statistics([[0.0, 1.0, 2.0, 3.0]], [0.0, 5.0])
    >>> st.mean.tolist(), st.count.tolist()
    ([1.0], [2])
    """
    edges = np.asarray(edges, float)
    if edges.ndim != 1 or len(edges) < 2 or np.any(np.diff(edges) <= 0):
        raise ValueError(
            "edges must be an increasing sequence of at least two energies"
        )
    E_parts, r_parts = [], []
    for lev in sectors:
        e, x = spacing_ratios(lev)
        E_parts.append(e)
        r_parts.append(x)
    E, r = np.concatenate(E_parts), np.concatenate(r_parts)
    idx = np.digitize(E, edges) - 1
    n = len(edges) - 1
    mean, err, cnt = np.full(n, np.nan), np.full(n, np.nan), np.zeros(n, int)
    for i in range(n):
        x = r[idx == i]
        cnt[i] = len(x)
        if len(x):
            mean[i] = x.mean()
        if len(x) > 1:
            err[i] = x.std(ddof=1) / math.sqrt(len(x))
    return RatioStatistics(edges=edges, mean=mean, error=err, count=cnt)


def density_fourier(
    levels: ArrayLike, E0: float, sigma: float, hbar: float, t: ArrayLike
) -> np.ndarray:
    """Fourier transform of the level density in a Gaussian window, against time.

    ``A(t) = (sqrt(2 pi) hbar / sigma) |sum_n w(E_n - E0) exp(-i E_n t / hbar)|`` with
    ``w(x) = exp(-x^2 / 2 sigma^2)``. Gutzwiller's trace formula
    ``rho_osc = (1/pi hbar) sum_p A_p cos(S_p/hbar - ...)`` makes each periodic orbit of
    period ``T_p`` at ``E0`` a Gaussian peak of height ``A_p`` and width
    ``hbar/sigma`` at ``t = T_p`` (:func:`gutzwiller_amplitude`), as long as ``T_p``
    varies little across the window. ``levels`` is the whole spectrum with
    multiplicities.

    Examples
    --------
    >>> round(float(density_fourier([1.0], 1.0, 0.5, 0.1, [0.0])[0]), 6)
    0.501326
    """
    h, s = _positive(hbar, "hbar"), _positive(sigma, "sigma")
    E = np.asarray(levels, float)
    w = np.exp(-0.5 * ((E - E0) / s) ** 2)
    keep = w > 1e-17
    E, w = E[keep], w[keep]
    t = np.atleast_1d(np.asarray(t, float))
    out = np.empty(len(t))
    for i0 in range(0, len(t), 256):
        ph = np.exp(-1j * np.outer(t[i0 : i0 + 256], E - E0) / h)
        out[i0 : i0 + 256] = np.abs(ph @ w)
    return math.sqrt(2.0 * math.pi) * h / s * out


def gutzwiller_amplitude(period: float, trace: float, repetition: int = 1) -> float:
    """``T_p / sqrt|det(M_p^r - 1)|`` of the ``r``-th repetition of an isolated orbit.

    ``trace`` is the trace of the full 4x4 monodromy (two unit eigenvalues), so the
    reduced 2x2 matrix has trace ``t = trace - 2`` and ``|det(M^r - 1)| =
    |2 - 2 T_r(t/2)|`` (Chebyshev); for ``r = 1`` it is ``|4 - trace|``.

    Examples
    --------
    >>> round(gutzwiller_amplitude(2.0, 20.0), 6)
    0.5
    """
    T = _positive(period, "period")
    if not (isinstance(repetition, (int, np.integer)) and repetition >= 1):
        raise ValueError(f"repetition must be an integer >= 1, not {repetition!r}")
    x = (float(trace) - 2.0) / 2.0
    if abs(x) <= 1:
        tr_r = 2.0 * math.cos(repetition * math.acos(x))
    else:
        tr_r = (
            2.0
            * math.copysign(1.0, x) ** repetition
            * math.cosh(repetition * math.acosh(abs(x)))
        )
    d = abs(2.0 - tr_r)
    if d == 0:
        raise ValueError(
            "a marginal orbit (det(M - 1) = 0) has no Gutzwiller amplitude"
        )
    return T / math.sqrt(d)


def orbit_copies(
    state0: ArrayLike, period: float, n: int = 20001, tol: float = 0.02
) -> int:
    """Number of distinct periodic orbits among the 24 images of one (symmetry group and
    time reversal), each of which enters the trace formula with the same amplitude.

    An image ``g x0`` of the start state lies on the orbit itself when ``g`` maps the orbit
    onto itself; the count is ``24`` over the number of such ``g``. Membership is judged
    on ``n`` samples of the orbit (positions modulo the configuration lattice) within
    ``tol``; distinct images are O(1) apart.

    Examples
    --------
    >>> import json
    >>> f = json.load(open("book/data/atlas_families_E5.45_T16.json"))["families"][0]
    >>> orbit_copies([float(x) for x in f["state0_str"]], f["period"])  # doctest: +SKIP
    6
    """
    from ..core.flow import sample
    from ..orbits.reversors import images

    x0 = np.asarray(state0, float)
    pts, _ = sample(x0, period, n)
    on = 0
    for y in images(x0):
        d = pts - y
        # positions modulo the lattice generated by (pi, pi) and (0, 2 pi) in (a1, a2)
        k = np.rint(d[:, 0] / math.pi)
        d0, d1 = d[:, 0] - k * math.pi, d[:, 1] - k * math.pi
        d1 = d1 - 2 * math.pi * np.rint(d1 / (2 * math.pi))
        dist = np.sqrt(d0**2 + d1**2 + (d[:, 2:] ** 2).sum(axis=1))
        on += bool(dist.min() < tol)
    return 24 // max(on, 1)
