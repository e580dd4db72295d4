"""Figures of the level statistics of chapter 11 (:mod:`rotorlib.beyond.quantum_windows`).

Units g = m r^2 = 1, dimensionless hbar. Each function returns the ``Figure`` it drew; the
numbers are computed by the caller.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from ..paper.chaos import BAND

if TYPE_CHECKING:
    from ..beyond.quantum_statistics import RegularFraction

__all__ = [
    "plot_regular_fraction",
    "plot_number_variance",
    "plot_trends",
    "plot_spacings",
]


def plot_regular_fraction(rf: RegularFraction) -> Figure:
    """``mu_reg(E)`` with its statistical and total error bars, the band shaded."""
    fig, ax = plt.subplots(figsize=(7, 3.2))
    ax.axvspan(*BAND, color="0.85", lw=0)
    ax.errorbar(rf.E, rf.mu, yerr=rf.error, fmt="o-", ms=3, capsize=2, color="C0")
    ax.set_xlabel("energy E (units g = m r² = 1)")
    ax.set_ylabel("regular fraction μ_reg")
    ax.set_ylim(-0.05, 1.05)
    fig.tight_layout()
    return fig


def plot_number_variance(
    panels: Sequence[tuple[str, np.ndarray, Mapping[float, tuple], float]],
    goe,
    berry_robnik,
) -> Figure:
    """One panel per window: ``(title, L, {hbar: (sigma2, error)}, mu)``; Poisson ``L``,
    ``goe(L)`` and ``berry_robnik(L, mu)`` (the classical prediction) drawn beside."""
    fig, axes = plt.subplots(1, len(panels), figsize=(3.4 * len(panels), 3.2))
    axes = np.atleast_1d(axes)
    for ax, (title, L, data, mu) in zip(axes, panels):
        Lf = np.linspace(0.05, float(np.max(L)), 200)
        ax.plot(Lf, Lf, "k:", lw=1, label="Poisson")
        ax.plot(Lf, goe(Lf), "k--", lw=1, label="GOE")
        ax.plot(Lf, berry_robnik(Lf, mu), "k-", lw=0.8, label="Berry–Robnik(μ_reg)")
        for i, (h, (s2, err)) in enumerate(sorted(data.items(), reverse=True)):
            ax.errorbar(
                L,
                s2,
                yerr=err,
                fmt="o-",
                ms=3,
                capsize=2,
                color=f"C{i}",
                label=f"ħ = {h:g}",
            )
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("L (mean spacings)")
        ax.set_ylim(0, max(4.0, 1.1 * max(max(v[0]) for v in data.values())))
    axes[0].set_ylabel("number variance Σ²(L)")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    return fig


def plot_trends(
    series: Mapping[str, Sequence[tuple[float, float, float, float, float, float]]],
    r_poisson: float,
    r_goe: float,
) -> Figure:
    """Per window (label -> rows ``(hbar, r, r_err, rho, rho_err, mu)``): ``<r>`` and the
    fitted Berry–Robnik fraction against ``hbar``; the predicted ``mu`` as a dashed line."""
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.6))
    for i, (lab, rows) in enumerate(series.items()):
        h, r, re, rho, rhe, mu = (np.array(x) for x in zip(*rows))
        c = f"C{i}"
        a1.errorbar(h, r, yerr=re, fmt="o-", ms=3, capsize=2, color=c, label=lab)
        a2.errorbar(h, rho, yerr=rhe, fmt="o-", ms=3, capsize=2, color=c)
        a2.plot([0, h.max()], [mu.mean()] * 2, "--", color=c, lw=0.8)
    a1.axhline(r_poisson, color="k", ls=":", lw=1)
    a1.axhline(r_goe, color="k", ls="--", lw=1)
    a1.set_ylabel("⟨r⟩ (Poisson dotted, GOE dashed)")
    a2.set_ylabel("Berry–Robnik ρ fitted (dashed: μ_reg)")
    for ax in (a1, a2):
        ax.set_xlabel("ħ (units g = m r² = 1)")
        ax.set_xlim(0, None)
    a1.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return fig


def plot_spacings(
    panels: Sequence[tuple[str, np.ndarray, float, float]], berry_robnik
) -> Figure:
    """One panel per window: ``(title, spacings, rho_fitted, mu_predicted)``; the histogram
    of the unfolded spacings with Poisson, Wigner and ``berry_robnik(s, rho)`` at the fitted
    and the predicted fraction."""
    fig, axes = plt.subplots(1, len(panels), figsize=(3.4 * len(panels), 3.0))
    axes = np.atleast_1d(axes)
    s = np.linspace(0, 4, 300)
    for ax, (title, sp, rho, mu) in zip(axes, panels):
        ax.hist(sp, bins=np.linspace(0, 4, 41), density=True, color="0.8")
        ax.plot(s, np.exp(-s), "k:", lw=1, label="Poisson")
        ax.plot(s, berry_robnik(s, 0.0), "k--", lw=1, label="Wigner")
        ax.plot(
            s, berry_robnik(s, rho), "C3-", lw=1.2, label=f"BR, ρ = {rho:.2f} (fit)"
        )
        ax.plot(s, berry_robnik(s, mu), "C0-", lw=1.2, label=f"BR, μ_reg = {mu:.2f}")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("unfolded spacing s (mean spacings)")
        ax.legend(fontsize=6)
    axes[0].set_ylabel("P(s)")
    fig.tight_layout()
    return fig
