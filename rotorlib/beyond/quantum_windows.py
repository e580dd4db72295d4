"""Level statistics of the quantum 3-rotor window by window, sector by sector, against hbar.

:func:`window_statistics` applies :mod:`rotorlib.beyond.quantum_statistics` to the
levels of each symmetry sector (each level once; an E1/E2 pair counted once) in windows
of energy: ``<r>`` with its iid and block-bootstrap errors and lag-1 correlation, the
Berry-Robnik fraction fitted to the unfolded spacings, the number variance
``Sigma^2(L)``, and the classical regular fraction of the window predicted from
``mu_reg(E)`` (the mean of ``mu_reg`` over the window's levels, i.e. weighted by the
density of states). :func:`extrapolate` fits a statistic linearly in ``hbar`` and states
whether the slope is significant.

Precision: as :mod:`rotorlib.beyond.quantum_statistics` (statistical errors stated).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike

from .quantum import SECTORS
from .quantum_statistics import (
    RegularFraction,
    fit_berry_robnik,
    number_variance,
    ratio_windows,
    window_spacings,
)

__all__ = ["L_GRID", "WindowStatistics", "window_statistics", "Trend", "extrapolate"]

#: Lengths (in mean spacings) at which the number variance is evaluated.
L_GRID = (0.25, 0.5, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0)


@dataclass(frozen=True)
class WindowStatistics:
    """The statistics of one energy window at one ``hbar`` (:func:`window_statistics`).

    Attributes
    ----------
    hbar, a, b : float
        ``hbar`` and the window ``a < E <= b``.
    sectors : tuple of str
        The sectors pooled (``r_sector`` etc. are per sector, in this order).
    count : int
        Levels in the window (each level once).
    r, r_error, r_iid_error, r_lag1 : float
        Pooled ``<r>``, its block-bootstrap and iid standard errors, the lag-1 correlation.
    r_sector, r_sector_error : tuple of float
        ``<r>`` and its block-bootstrap error per sector.
    rho, rho_error : float
        Berry-Robnik fraction fitted to the pooled unfolded spacings.
    mu, mu_error : float
        The classical regular fraction predicted for the window (nan without one).
    L, sigma2, sigma2_error : tuple of float
        ``Sigma^2(L)``: mean over the sectors and its standard error (spread over sectors).
    """

    hbar: float
    a: float
    b: float
    sectors: tuple
    count: int
    r: float
    r_error: float
    r_iid_error: float
    r_lag1: float
    r_sector: tuple
    r_sector_error: tuple
    rho: float
    rho_error: float
    mu: float
    mu_error: float
    L: tuple
    sigma2: tuple
    sigma2_error: tuple

    def to_dict(self) -> dict:
        return asdict(self)


def window_statistics(
    levels: Mapping[str, ArrayLike],
    hbar: float,
    edges: Sequence[tuple[float, float]],
    regular: RegularFraction | None = None,
    L: Sequence[float] = L_GRID,
    block: int = 10,
    n_boot: int = 1000,
    n_boot_fit: int = 100,
    seed: int = 0,
) -> list[WindowStatistics]:
    """The statistics of each window ``(a, b)`` of ``edges`` (pairs, may overlap).

    ``levels``: the levels of each sector (keys among ``SECTORS``), each level once.
    ``regular``: ``mu_reg(E)`` for the predicted regular fraction of each window.

    Examples
    --------
    >>> lev = {"A1": np.cumsum(np.random.default_rng(0).exponential(0.01, 800))}
    >>> w = window_statistics(lev, 0.1, [(0.5, 7.0)], L=(1.0,), n_boot=50, n_boot_fit=20)
    >>> round(w[0].rho, 1), w[0].count, bool(abs(w[0].r - 0.386) < 3 * w[0].r_error)
    (1.0, 619, True)
    """
    names = tuple(s for s in SECTORS if s in levels)
    if not names or set(levels) - set(SECTORS):
        raise ValueError(f"levels must be keyed by sectors among {SECTORS}")
    if not (math.isfinite(hbar) and hbar > 0):
        raise ValueError(f"hbar must be positive, not {hbar}")
    out = []
    for k, (a, b) in enumerate(edges):
        if not b > a:
            raise ValueError(f"window ({a}, {b}) is empty")
        lev = {s: np.sort(np.asarray(levels[s], float)) for s in names}
        inside = {s: v[(v > a) & (v <= b)] for s, v in lev.items()}
        if min(len(v) for v in inside.values()) < 12:
            raise ValueError(f"fewer than 12 levels of a sector in ({a}, {b}]")
        rw = ratio_windows([lev[s] for s in names], [a, b], block, n_boot, seed + k)
        per = [ratio_windows([lev[s]], [a, b], block, n_boot, seed + k) for s in names]
        xs = {s: window_spacings(lev[s], hbar, s, a, b)[0] for s in names}
        fit = fit_berry_robnik(
            [np.diff(x) for x in xs.values()], block, n_boot_fit, seed + k
        )
        S2 = np.array([number_variance(x, L) for x in xs.values()])
        if regular is not None:
            allE = np.concatenate(list(inside.values()))
            m, e = regular.at(np.clip(allE, regular.E[0], regular.E[-1]))
            mu, mu_err = float(m.mean()), float(e.mean())
        else:
            mu = mu_err = float("nan")
        out.append(
            WindowStatistics(
                hbar=float(hbar),
                a=float(a),
                b=float(b),
                sectors=names,
                count=int(sum(len(v) for v in inside.values())),
                r=float(rw.mean[0]),
                r_error=float(rw.error[0]),
                r_iid_error=float(rw.iid_error[0]),
                r_lag1=float(rw.lag1[0]),
                r_sector=tuple(float(p.mean[0]) for p in per),
                r_sector_error=tuple(float(p.error[0]) for p in per),
                rho=fit.rho,
                rho_error=fit.error,
                mu=mu,
                mu_error=mu_err,
                L=tuple(float(x) for x in L),
                sigma2=tuple(float(x) for x in S2.mean(axis=0)),
                sigma2_error=tuple(
                    float(x) for x in S2.std(axis=0, ddof=1) / math.sqrt(len(S2))
                )
                if len(S2) > 1
                else tuple(float("nan") for _ in L),
            )
        )
    return out


@dataclass(frozen=True)
class Trend:
    """A weighted straight line ``y = y0 + slope * hbar`` (:func:`extrapolate`).

    Attributes
    ----------
    y0, y0_error : float
        The value extrapolated to ``hbar -> 0`` and its standard error.
    slope, slope_error : float
    chi2 : float
        Chi-squared of the fit (``len - 2`` degrees of freedom).
    clear : bool
        ``|slope| > 3 slope_error`` and the line fits (``chi2 <= len - 2 + 3 sqrt(2 (len - 2))``).
    """

    y0: float
    y0_error: float
    slope: float
    slope_error: float
    chi2: float
    clear: bool


def extrapolate(hbar: ArrayLike, y: ArrayLike, error: ArrayLike) -> Trend:
    """Weighted least-squares line through ``(hbar, y)`` with standard errors ``error``.

    Examples
    --------
    >>> t = extrapolate([0.01, 0.02, 0.03], [2.0, 3.0, 4.0], [0.1, 0.1, 0.1])
    >>> round(t.y0, 9), round(t.slope, 6), t.clear
    (1.0, 100.0, True)
    """
    h, v, e = (np.asarray(x, float) for x in (hbar, y, error))
    if not (h.shape == v.shape == e.shape and h.ndim == 1 and len(h) >= 3):
        raise ValueError("need at least three (hbar, y, error) of equal length")
    if np.any(e <= 0) or not np.all(np.isfinite(np.concatenate([h, v, e]))):
        raise ValueError("errors must be positive and every value finite")
    A = np.column_stack([np.ones_like(h), h]) / e[:, None]
    cov = np.linalg.inv(A.T @ A)
    coef = cov @ (A.T @ (v / e))
    chi2 = float(np.sum(((v - coef[0] - coef[1] * h) / e) ** 2))
    dof = len(h) - 2
    s0, s1 = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
    clear = bool(abs(coef[1]) > 3 * s1 and chi2 <= dof + 3 * math.sqrt(2 * dof))
    return Trend(float(coef[0]), s0, float(coef[1]), s1, chi2, clear)
