"""Level statistics that can tell regimes apart, and the classical regular fraction.

The quantum side (levels of one symmetry sector from :mod:`rotorlib.beyond.quantum`):

* :func:`lag_correlation`, :func:`block_bootstrap` -- consecutive spacing ratios are
  correlated (they share a spacing), so the standard error of ``<r>`` is estimated by a
  circular block bootstrap over each sector's sequence (sectors are independent);
* :func:`ratio_windows` -- ``<r>`` per energy window with the iid and the block-bootstrap
  error side by side, and the lag-1 correlation;
* :func:`unfold` -- unfolding with the library's Weyl law
  (:func:`rotorlib.beyond.quantum_semiclassics.weyl_count`, with its ``hbar^0``
  correction): a sector of dimension ``d`` holds ``d/12`` of the distinct levels; within a
  window the unfolded levels are rescaled to the window's own count (this removes the
  sector's ``O(1/hbar)`` boundary terms, which shift the mean density by a few per cent);
* :func:`berry_robnik_pdf`, :func:`fit_berry_robnik` -- the spacing distribution of a
  regular part of measure ``rho`` superposed on a chaotic (GOE, Wigner surmise) part,
  fitted by maximum likelihood with a block-bootstrap error;
* :func:`number_variance`, :func:`sigma2_goe`, :func:`sigma2_berry_robnik` -- ``Sigma^2(L)``
  of an unfolded sequence against Poisson (``L``), GOE (Mehta's closed form) and
  Berry-Robnik (``rho L + Sigma^2_GOE((1 - rho) L)``).

The classical side: :func:`regular_fraction`, the Liouville measure of the regular part of
the energy shell, from finite-time Lyapunov exponents on a microcanonical sample
(:func:`rotorlib.paper.chaos.sample_energy_shell`, :func:`rotorlib.paper.chaos.ftle`), with
its binomial error and the systematic effect of the FTLE threshold and of the time.

Precision: every statistic is a float64 estimate whose error is statistical and stated
(bootstrap or binomial); the special functions are exact to float64.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar
from scipy.special import erfc, sici

from ..paper.chaos import ftle, sample_energy_shell
from .quantum import DIMENSIONS, SECTORS
from .quantum_semiclassics import spacing_ratios, weyl_count

__all__ = [
    "lag_correlation",
    "block_bootstrap",
    "RatioWindows",
    "ratio_windows",
    "unfold",
    "window_spacings",
    "berry_robnik_pdf",
    "BerryRobnikFit",
    "fit_berry_robnik",
    "number_variance",
    "sigma2_goe",
    "sigma2_berry_robnik",
    "RegularFraction",
    "regular_fraction",
    "load_regular_fraction",
]


def _sequence(x, name, n_min=2):
    x = np.asarray(x, float)
    if x.ndim != 1 or len(x) < n_min or not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be a finite 1-d sequence of >= {n_min} numbers")
    return x


def _edges(edges):
    edges = np.asarray(edges, float)
    if edges.ndim != 1 or len(edges) < 2 or np.any(np.diff(edges) <= 0):
        raise ValueError(
            "edges must be an increasing sequence of at least two energies"
        )
    return edges


def lag_correlation(x: ArrayLike, lag: int = 1) -> float:
    """Pearson correlation of ``x[n]`` and ``x[n + lag]``.

    Examples
    --------
    >>> round(lag_correlation([1.0, 2.0, 1.0, 2.0, 1.0, 2.0]), 6)
    -1.0
    """
    v = _sequence(x, "x", 3)
    if not (isinstance(lag, (int, np.integer)) and 1 <= lag < len(v) - 1):
        raise ValueError(f"lag must be an integer from 1 to len(x) - 2, not {lag!r}")
    a, b = v[:-lag], v[lag:]
    if a.std() == 0 or b.std() == 0:
        return 0.0
    return float(np.corrcoef(a, b)[0, 1])


def _block_means(seqs, block, n_boot, rng):
    """``n_boot`` bootstrap means of the pooled sequences: each sequence resampled by
    circular blocks of ``block`` (its own length kept), sums pooled."""
    total = sum(len(s) for s in seqs)
    acc = np.zeros(n_boot)
    for s in seqs:
        acc += s[_block_index(len(s), block, n_boot, rng)].sum(axis=1)
    return acc / total


def _block_index(n, block, n_boot, rng):
    """``n_boot`` circular-block resamplings of ``range(n)`` (rows of length ``n``)."""
    b = min(block, n)
    starts = rng.integers(0, n, size=(n_boot, -(-n // b)))
    return ((starts[:, :, None] + np.arange(b)) % n).reshape(n_boot, -1)[:, :n]


def block_bootstrap(
    seqs: Sequence[ArrayLike] | ArrayLike,
    block: int = 10,
    n_boot: int = 1000,
    seed: int = 0,
) -> float:
    """Standard error of the pooled mean of one or several independent sequences, from a
    circular block bootstrap (blocks of ``block`` consecutive values, within a sequence).

    ``block = 1`` is the ordinary (iid) bootstrap. The estimate converges once ``block``
    exceeds the correlation length; its own relative error is ``~ 1/sqrt(2 n_boot)``.

    Examples
    --------
    >>> x = np.random.default_rng(1).normal(size=4000)
    >>> round(block_bootstrap(x, block=10, n_boot=2000) * math.sqrt(4000), 1)
    1.0
    """
    parts = seqs if isinstance(seqs, (list, tuple)) else [seqs]
    arrays = [_sequence(s, "each sequence", 1) for s in parts]
    if not (isinstance(block, (int, np.integer)) and block >= 1):
        raise ValueError(f"block must be an integer >= 1, not {block!r}")
    if not (isinstance(n_boot, (int, np.integer)) and n_boot >= 20):
        raise ValueError(f"n_boot must be an integer >= 20, not {n_boot!r}")
    if sum(len(s) for s in arrays) < 2:
        raise ValueError("need at least two values")
    rng = np.random.default_rng(seed)
    return float(np.std(_block_means(arrays, int(block), int(n_boot), rng), ddof=1))


@dataclass(frozen=True)
class RatioWindows:
    """``<r>`` per energy window (:func:`ratio_windows`).

    Attributes
    ----------
    edges : ndarray (n + 1)
    mean, iid_error, error, lag1 : ndarray (n)
        ``<r>``; its standard error as if the ratios were independent
        (``std/sqrt(count)``); its block-bootstrap standard error; the lag-1 correlation of
        consecutive ratios (within a sector, pooled).
    count : ndarray of int (n)
    block : int
    """

    edges: np.ndarray
    mean: np.ndarray
    iid_error: np.ndarray
    error: np.ndarray
    lag1: np.ndarray
    count: np.ndarray
    block: int

    @property
    def centres(self) -> np.ndarray:
        return 0.5 * (self.edges[1:] + self.edges[:-1])


def ratio_windows(
    sectors: Sequence[ArrayLike],
    edges: ArrayLike,
    block: int = 10,
    n_boot: int = 1000,
    seed: int = 0,
) -> RatioWindows:
    """``<r>`` per window of the middle level, pooled over the given sectors (each sector's
    levels once; ratios within a sector), with iid and block-bootstrap errors.

    Examples
    --------
    >>> lev = np.cumsum(np.random.default_rng(0).exponential(size=3001))
    >>> w = ratio_windows([lev], [0.0, lev[-1]])
    >>> bool(abs(w.mean[0] - 0.3863) < 3 * w.error[0]), int(w.count[0])
    (True, 2999)
    """
    ed = _edges(edges)
    n = len(ed) - 1
    per: list[list[np.ndarray]] = [[] for _ in range(n)]
    for sec in sectors:
        lev = np.asarray(sec, float)
        if len(lev) < 3:
            continue
        e, r = spacing_ratios(lev)
        idx = np.digitize(e, ed) - 1
        for i in range(n):
            x = r[idx == i]
            if len(x):
                per[i].append(x)
    out = {k: np.full(n, np.nan) for k in ("mean", "iid", "err", "lag1")}
    count = np.zeros(n, int)
    for i, seqs in enumerate(per):
        x = np.concatenate(seqs) if seqs else np.empty(0)
        count[i] = len(x)
        if len(x) == 0:
            continue
        out["mean"][i] = x.mean()
        if len(x) < 2:
            continue
        out["iid"][i] = x.std(ddof=1) / math.sqrt(len(x))
        out["err"][i] = block_bootstrap(seqs, block, n_boot, seed + i)
        la = [s[:-1] - x.mean() for s in seqs if len(s) > 2]
        lb = [s[1:] - x.mean() for s in seqs if len(s) > 2]
        if la:
            a, b = np.concatenate(la), np.concatenate(lb)
            out["lag1"][i] = float(np.sum(a * b) / np.sum((x - x.mean()) ** 2))
    return RatioWindows(
        ed, out["mean"], out["iid"], out["err"], out["lag1"], count, int(block)
    )


def unfold(
    levels: ArrayLike, hbar: float, sector: str, n_grid: int = 400
) -> np.ndarray:
    """The levels of one sector in units of the mean spacing: ``(d/12) N_Weyl(E)``.

    ``N_Weyl`` is :func:`rotorlib.beyond.quantum_semiclassics.weyl_count` with its
    ``hbar^0`` correction, evaluated on ``n_grid`` energies and interpolated (cubic
    Hermite on the monotone staircase; error below 1e-6 levels away from the saddle energy
    4, whose logarithmic singularity of the correction is smoothed over one grid step).

    Examples
    --------
    >>> x = unfold([6.0, 7.0], 0.1, "A1")  # above max V: (2 pi/sqrt 3)(E - 3)/hbar^2/12
    >>> round(float(x[1] - x[0]), 2)
    30.23
    """
    from scipy.interpolate import PchipInterpolator

    lev = _sequence(levels, "levels", 1)
    if sector not in SECTORS:
        raise ValueError(f"unknown sector {sector!r}: choose one of {SECTORS}")
    lo, hi = max(float(lev.min()) - 0.05, 1e-3), float(lev.max()) + 0.05
    grid = np.linspace(lo, hi, n_grid)
    N = np.atleast_1d(weyl_count(grid, hbar)) * DIMENSIONS[sector] / 12.0
    return PchipInterpolator(grid, np.maximum.accumulate(N))(lev)


def window_spacings(
    levels: ArrayLike, hbar: float, sector: str, a: float, b: float
) -> tuple[np.ndarray, np.ndarray]:
    """Unfolded levels and spacings of one sector in the window ``a < E <= b``.

    The levels are unfolded by :func:`unfold` and rescaled so that the window holds its
    own count (mean spacing 1 within the window). Returns ``(x, s)``: the unfolded levels
    (starting at 0) and their ``len(x) - 1`` spacings.

    Examples
    --------
    >>> x, s = window_spacings(np.linspace(6.0, 7.0, 11), 0.1, "A1", 5.5, 7.5)
    >>> round(float(s.mean()), 12), len(s)
    (1.0, 10)
    """
    lev = np.sort(_sequence(levels, "levels", 1))
    lev = lev[(lev > a) & (lev <= b)]
    if len(lev) < 3:
        raise ValueError(f"fewer than 3 levels of {sector} in ({a}, {b}]")
    x = unfold(lev, hbar, sector)
    x = (x - x[0]) * (len(x) - 1) / (x[-1] - x[0])
    return x, np.diff(x)


def berry_robnik_pdf(s: ArrayLike, rho: float) -> np.ndarray:
    """Berry-Robnik spacing density of a regular part of measure ``rho`` and a chaotic part
    ``1 - rho`` (Wigner surmise), unit mean spacing.

    ``P(s) = [rho^2 erfc(sqrt(pi) (1 - rho) s / 2) + (2 rho (1 - rho) + pi (1 - rho)^3 s / 2)
    exp(-pi (1 - rho)^2 s^2 / 4)] exp(-rho s)``: Poisson at ``rho = 1``, Wigner at 0.

    Examples
    --------
    >>> poisson, wigner = berry_robnik_pdf(1.0, 1.0), berry_robnik_pdf(0.0, 0.0)
    >>> round(float(poisson[0]), 6), round(float(wigner[0]), 6)
    (0.367879, 0.0)
    """
    if not (0.0 <= rho <= 1.0):
        raise ValueError(f"rho must lie in [0, 1], not {rho}")
    s = np.atleast_1d(np.asarray(s, float))
    c = 1.0 - rho
    g = np.exp(-math.pi * c * c * s * s / 4.0)
    return (
        rho * rho * erfc(math.sqrt(math.pi) * c * s / 2.0)
        + (2.0 * rho * c + math.pi * c**3 * s / 2.0) * g
    ) * np.exp(-rho * s)


def _br_nll(s, rho):
    return -float(np.sum(np.log(np.maximum(berry_robnik_pdf(s, rho), 1e-300))))


def _br_mle(s):
    res = minimize_scalar(
        lambda r: _br_nll(s, r),
        bounds=(0.0, 1.0),
        method="bounded",
        options={"xatol": 1e-5},
    )
    # the bounded search never evaluates the end points themselves
    return min((float(res.x), 0.0, 1.0), key=lambda r: _br_nll(s, r))


def _br_profile(s, rho):
    """Half-width of the profile-likelihood interval ``NLL <= NLL(rho) + 1/2`` (one-sided
    at a bound of [0, 1])."""
    from scipy.optimize import brentq

    f0 = _br_nll(s, rho) + 0.5
    ends = []
    for end in (0.0, 1.0):
        if end == rho or _br_nll(s, end) <= f0:
            ends.append(end)
        else:
            ends.append(
                brentq(
                    lambda r: _br_nll(s, r) - f0,
                    min(rho, end),
                    max(rho, end),
                    xtol=1e-6,
                )
            )
    return 0.5 * (ends[1] - ends[0])


@dataclass(frozen=True)
class BerryRobnikFit:
    """Maximum-likelihood Berry-Robnik fraction of a set of spacings.

    Attributes
    ----------
    rho : float
        The fitted regular fraction.
    error : float
        Its standard error: the block-bootstrap standard deviation, or half the width of
        the profile-likelihood interval (``Delta NLL = 1/2``) when that is larger (at the
        bounds 0 and 1 the bootstrap collapses).
    count : int
        Number of spacings.
    """

    rho: float
    error: float
    count: int


def fit_berry_robnik(
    spacings: Sequence[ArrayLike] | ArrayLike,
    block: int = 10,
    n_boot: int = 100,
    seed: int = 0,
) -> BerryRobnikFit:
    """Fit ``rho`` of :func:`berry_robnik_pdf` to unit-mean spacings by maximum likelihood.

    ``spacings``: one array, or one per sector (each resampled by circular blocks of
    ``block`` spacings in the bootstrap, as in :func:`block_bootstrap`).

    Examples
    --------
    >>> s = np.random.default_rng(0).exponential(size=2000)  # Poisson: rho = 1
    >>> f = fit_berry_robnik(s, n_boot=30)
    >>> round(f.rho, 3), f.count
    (1.0, 2000)
    """
    parts = spacings if isinstance(spacings, (list, tuple)) else [spacings]
    seqs = [_sequence(s, "spacings", 1) for s in parts]
    if any(np.any(s < 0) for s in seqs):
        raise ValueError("spacings must be >= 0")
    if not (isinstance(n_boot, (int, np.integer)) and n_boot >= 20):
        raise ValueError(f"n_boot must be an integer >= 20, not {n_boot!r}")
    allx = np.concatenate(seqs)
    if len(allx) < 10:
        raise ValueError("need at least 10 spacings")
    rho = _br_mle(allx)
    rng = np.random.default_rng(seed)
    idx = [_block_index(len(s), block, int(n_boot), rng) for s in seqs]
    boots = [
        _br_mle(np.concatenate([s[ix[k]] for s, ix in zip(seqs, idx)]))
        for k in range(int(n_boot))
    ]
    err = max(float(np.std(boots, ddof=1)), _br_profile(allx, rho))
    return BerryRobnikFit(rho, err, int(len(allx)))


def number_variance(x: ArrayLike, L: ArrayLike, n_starts: int = 4000) -> np.ndarray:
    """``Sigma^2(L)``: the variance of the number of unfolded levels in ``[x0, x0 + L]``,
    ``x0`` on ``n_starts`` equally spaced points of ``[x_0, x_last - L]``, about ``L``.

    Examples
    --------
    >>> float(number_variance(np.arange(100.0), [2.5])[0])  # a picket fence: (n - L)^2
    0.25
    """
    x = np.sort(_sequence(x, "x", 3))
    L = np.atleast_1d(np.asarray(L, float))
    if np.any(L <= 0) or np.any(L >= x[-1] - x[0]):
        raise ValueError("every L must lie between 0 and the span of x")
    out = np.empty(len(L))
    for i, ell in enumerate(L):
        x0 = np.linspace(x[0], x[-1] - ell, n_starts)
        n = np.searchsorted(x, x0 + ell, "right") - np.searchsorted(x, x0, "right")
        out[i] = np.mean((n - ell) ** 2)
    return out


def sigma2_goe(L: ArrayLike) -> np.ndarray:
    """The GOE number variance (Mehta): ``2 S_GUE(L) + (Si(pi L)/pi)^2 - Si(pi L)/pi``
    with ``S_GUE = [ln(2 pi L) + gamma + 1 - cos(2 pi L) - Ci(2 pi L)]/pi^2 + L [1 - (2/pi)
    Si(2 pi L)]``. Exact (float64); ``~ (2/pi^2)(ln 2 pi L + gamma + 1 - pi^2/8)`` for large L.

    Examples
    --------
    >>> round(float(sigma2_goe(10.0)[0]), 4)
    0.9087
    """
    L = np.atleast_1d(np.asarray(L, float))
    if np.any(L <= 0):
        raise ValueError("L must be > 0")
    si2, ci2 = sici(2 * math.pi * L)
    gue = np.log(2 * math.pi * L) + np.euler_gamma + 1 - np.cos(2 * math.pi * L) - ci2
    gue = gue / math.pi**2 + L * (1 - 2 * si2 / math.pi)
    si1 = sici(math.pi * L)[0] / math.pi
    return 2 * gue + si1 * si1 - si1


def sigma2_berry_robnik(L: ArrayLike, rho: float) -> np.ndarray:
    """Number variance of independent Poisson (fraction ``rho``) and GOE sequences
    superposed: ``rho L + Sigma^2_GOE((1 - rho) L)``.

    Examples
    --------
    >>> float(sigma2_berry_robnik([3.0], 1.0)[0])
    3.0
    """
    if not (0.0 <= rho <= 1.0):
        raise ValueError(f"rho must lie in [0, 1], not {rho}")
    L = np.atleast_1d(np.asarray(L, float))
    g = sigma2_goe((1 - rho) * L) if rho < 1 else np.zeros_like(L)
    return rho * L + g


# ---------------------------------------------------------------- the classical side
@dataclass(frozen=True)
class RegularFraction:
    """Liouville measure of the regular part of the energy shell (:func:`regular_fraction`).

    Attributes
    ----------
    E, mu : ndarray
        Energies and the fraction of the shell with FTLE ``<= threshold`` at time ``T``.
    stat_error : ndarray
        Binomial standard error (posterior standard deviation with a uniform prior,
        nonzero at ``mu = 0`` or 1).
    syst_error : ndarray
        Largest change of ``mu`` when the threshold is moved to each of ``thresholds`` or
        the time to ``T_check`` (paired, on the first ``N_check`` points).
    N, N_check : int
    T, T_check, threshold : float
    thresholds : tuple of float
    mu_thresholds : ndarray (n_E, len(thresholds))
    mu_check, mu_check_T : ndarray
        On the first ``N_check`` points: the fraction at ``T`` and at ``T_check``.
    """

    E: np.ndarray
    mu: np.ndarray
    stat_error: np.ndarray
    syst_error: np.ndarray
    N: int
    N_check: int
    T: float
    T_check: float
    threshold: float
    thresholds: tuple
    mu_thresholds: np.ndarray
    mu_check: np.ndarray
    mu_check_T: np.ndarray

    @property
    def error(self) -> np.ndarray:
        """Statistical and systematic errors in quadrature."""
        return np.hypot(self.stat_error, self.syst_error)

    def at(self, E: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """``(mu, error)`` interpolated linearly in ``E`` (within the sampled range)."""
        E = np.atleast_1d(np.asarray(E, float))
        if np.any(E < self.E[0] - 1e-12) or np.any(E > self.E[-1] + 1e-12):
            raise ValueError(f"E must lie in [{self.E[0]}, {self.E[-1]}]")
        return np.interp(E, self.E, self.mu), np.interp(E, self.E, self.error)

    def to_dict(self) -> dict:
        d = asdict(self)
        return {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in d.items()}


def regular_fraction(
    energies: ArrayLike,
    N: int = 1000,
    T: float = 300.0,
    threshold: float = 0.05,
    thresholds: Sequence[float] = (0.03, 0.08),
    N_check: int = 200,
    T_check: float = 1000.0,
    seed: int = 0,
    executor: Executor | None = None,
    progress: bool = False,
) -> RegularFraction:
    """``mu_reg(E)``: the fraction of ``N`` microcanonical (Liouville) points of the shell
    ``H = E`` whose finite-time Lyapunov exponent over ``T`` is ``<= threshold``.

    A regular orbit's FTLE decays like ``log(T)/T`` (~0.02 at ``T = 300``), a chaotic one
    stays near the shell's Lyapunov exponent (0.1-0.4 in the band); sticky orbits near
    islands are counted regular at finite ``T``: the systematic error states how much
    ``mu`` moves with the threshold (``thresholds``) and with the time (``T_check`` on the
    first ``N_check`` points, compared on the same points).

    Examples
    --------
    >>> r = regular_fraction([1.0], N=20, N_check=20, T=50.0, T_check=100.0)  # doctest: +SKIP
    >>> float(r.mu[0])  # doctest: +SKIP
    1.0
    """
    E = np.atleast_1d(np.asarray(energies, float))
    if E.ndim != 1 or len(E) < 1 or np.any(~np.isfinite(E)) or np.any(E <= 0):
        raise ValueError("energies must be positive finite numbers")
    if np.any(np.diff(E) <= 0):
        raise ValueError("energies must be increasing")
    if not (isinstance(N, (int, np.integer)) and N >= 10):
        raise ValueError(f"N must be an integer >= 10, not {N!r}")
    if not (isinstance(N_check, (int, np.integer)) and 1 <= N_check <= N):
        raise ValueError(f"N_check must be an integer from 1 to N, not {N_check!r}")
    if not (0 < threshold and all(t > 0 for t in thresholds)):
        raise ValueError("thresholds must be > 0")
    if not (0 < T < T_check):
        raise ValueError("need 0 < T < T_check")
    states = [sample_energy_shell(e, N, seed=seed + 7919 * k) for k, e in enumerate(E)]
    allx = np.concatenate(states)
    lam = ftle(allx, T=T, executor=executor, progress=progress, seed=seed)
    chk = np.concatenate([s[:N_check] for s in states])
    lam2 = ftle(chk, T=T_check, executor=executor, progress=progress, seed=seed + 1)
    lam = lam.reshape(len(E), N)
    lam2 = lam2.reshape(len(E), N_check)
    k = (lam <= threshold).sum(axis=1)
    mu = k / N
    stat = np.sqrt((k + 1) * (N - k + 1) / ((N + 2) ** 2 * (N + 3)))
    mt = np.array([[np.mean(x <= t) for t in thresholds] for x in lam])
    mc = np.mean(lam[:, :N_check] <= threshold, axis=1)
    mc2 = np.mean(lam2 <= threshold, axis=1)
    syst = np.max(np.abs(np.column_stack([mt - mu[:, None], mc2 - mc])), axis=1)
    return RegularFraction(
        E,
        mu,
        stat,
        syst,
        int(N),
        int(N_check),
        float(T),
        float(T_check),
        float(threshold),
        tuple(float(t) for t in thresholds),
        mt,
        mc,
        mc2,
    )


def load_regular_fraction(path: str | Path) -> RegularFraction:
    """Read a :class:`RegularFraction` written as JSON by ``scripts/regular_fraction.py``."""
    d = json.loads(Path(path).read_text())
    try:
        rec = d["regular_fraction"]
        kw: dict = {
            k: (np.array(v) if isinstance(v, list) and k != "thresholds" else v)
            for k, v in rec.items()
        }
        kw["thresholds"] = tuple(rec["thresholds"])
        return RegularFraction(**kw)
    except (KeyError, TypeError) as e:
        raise ValueError(f"{path} is not a regular-fraction record: {e}") from None
