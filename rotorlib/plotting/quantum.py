"""Figures for the chapter on the quantum 3-rotor (:mod:`rotorlib.beyond.quantum`).

Units g = m r^2 = 1, dimensionless hbar. Each function returns the ``Figure`` it drew; the
numbers are computed by the caller.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from ..beyond.quantum import Spectrum
    from ..beyond.quantum_semiclassics import RatioStatistics
    from ..paper.chaos import ChaoticFraction

__all__ = ["plot_levels_vs_hbar", "plot_ratio", "plot_weyl", "plot_trace"]

BAND = (5.33, 5.6)
COLORS = {"A1": "C0", "A2": "C1", "B1": "C2", "B2": "C3", "E1": "C4", "E2": "C5"}


def plot_levels_vs_hbar(spectra: Sequence[Spectrum], E_max: float) -> Figure:
    """``spectra``: list of :class:`rotorlib.beyond.quantum.Spectrum` at several hbar; each level
    a dot coloured by its sector, with the harmonic shells ``hbar sqrt 3 (n + 1)``."""
    fig, ax = plt.subplots(figsize=(7, 4.2))
    seen = set()
    for s in spectra:
        for x in s.sectors:
            lab = x.sector if x.sector not in seen else None
            seen.add(x.sector)
            ax.plot(
                np.full(len(x.levels), s.hbar),
                x.levels,
                "_",
                ms=7,
                mew=1.4,
                color=COLORS[x.sector],
                label=lab,
            )
    h = np.linspace(0, max(s.hbar for s in spectra), 50)
    for n in range(12):
        ax.plot(h, np.sqrt(3) * h * (n + 1), color="0.6", lw=0.6, zorder=0)
    ax.set_ylim(0, E_max)
    ax.set_xlim(0, h[-1] * 1.03)
    ax.set_xlabel(r"$\hbar$ (units $g = m r^2 = 1$)")
    ax.set_ylabel(r"level $E_n$ (units of $g$)")
    ax.legend(title="sector", fontsize=8, ncol=2, loc="lower right")
    fig.tight_layout()
    return fig


def _marks(ax):
    ax.axvspan(*BAND, color="0.85", zorder=0)
    for E in (4.0, 4.5):
        ax.axvline(E, color="0.4", ls=":", lw=1)


def plot_ratio(
    stats: Mapping[float, RatioStatistics],
    chaotic: ChaoticFraction,
    r_poisson: float,
    r_goe: float,
) -> Figure:
    """``stats``: ``{hbar: RatioStatistics}``; ``chaotic``: a ChaoticFraction. Top: <r>(E)
    with error bars; bottom: the chaotic fraction; the band 5.33-5.6 shaded, E = 4 and
    4.5 dotted."""
    fig, (a1, a2) = plt.subplots(
        2, 1, figsize=(7, 5.6), sharex=True, height_ratios=[3, 2]
    )
    for i, (h, st) in enumerate(sorted(stats.items(), reverse=True)):
        off = (i - 0.5 * (len(stats) - 1)) * 0.03
        a1.errorbar(
            st.centres + off,
            st.mean,
            st.error,
            fmt="o-",
            ms=3,
            lw=1,
            capsize=2,
            label=rf"$\hbar = {h:g}$",
        )
    a1.axhline(r_poisson, color="k", ls="--", lw=0.8)
    a1.axhline(r_goe, color="k", ls="-.", lw=0.8)
    a1.text(0.1, r_poisson + 0.006, "Poisson", fontsize=8)
    a1.text(0.1, r_goe + 0.006, "GOE", fontsize=8)
    _marks(a1)
    a1.set_ylabel(r"$\langle r\rangle$ in the window")
    a1.legend(fontsize=8, loc="lower right")
    a2.errorbar(chaotic.E, chaotic.fraction, chaotic.stderr, fmt="s-", ms=3, color="C3")
    _marks(a2)
    a2.set_ylabel("chaotic fraction")
    a2.set_xlabel(r"energy $E$ (units of $g$)")
    a2.set_ylim(-0.05, 1.05)
    fig.tight_layout()
    return fig


def plot_weyl(
    E: ArrayLike, N: np.ndarray, weyl0: ArrayLike, weyl1: ArrayLike
) -> Figure:
    """The staircase minus Weyl's leading term, and the first correction."""
    fig, ax = plt.subplots(figsize=(7, 3.4))
    ax.plot(E, N - weyl0, lw=0.8, label=r"$N(E) - \bar N_0(E)$")
    ax.plot(E, weyl1, lw=1.5, color="C3", label=r"first correction $\bar N_1(E)$")
    _marks(ax)
    ax.set_xlabel(r"energy $E$ (units of $g$)")
    ax.set_ylabel("levels")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_trace(
    panels: Sequence[tuple[str, np.ndarray, np.ndarray, Sequence[tuple[float, float]]]],
) -> Figure:
    """``panels``: list of ``(title, t, A(t), orbits)`` with ``orbits`` a list of
    ``(T_p, predicted amplitude)``: the Fourier transform of the windowed level density
    and Gutzwiller's predicted peaks (stems)."""
    fig, axes = plt.subplots(len(panels), 1, figsize=(7, 2.4 * len(panels)))
    axes = np.atleast_1d(axes)
    for ax, (title, t, A, orbits) in zip(axes, panels):
        ax.plot(t, A, lw=0.9, label=r"$|\tilde\rho(t)|$ (quantum)")
        if orbits:
            T, amp = np.array(orbits).T
            ax.vlines(T, 0, amp, color="C3", lw=1.5, label="Gutzwiller, atlas orbits")
            ax.plot(T, amp, "v", color="C3", ms=4)
        ax.set_title(title, fontsize=9)
        ax.set_ylabel("amplitude")
        ax.set_xlim(t[0], t[-1])
        top = np.max(A[t > 1.5]) if np.any(t > 1.5) else np.max(A)
        ax.set_ylim(0, 1.3 * top)
    axes[-1].set_xlabel(r"time $t$ (units of $\sqrt{m r^2/g}$)")
    axes[0].legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    return fig
