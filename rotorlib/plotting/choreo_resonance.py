"""Figures for the section on CG's resonances and the choreographies born from CG.

Units m = g = r = 1. Every function returns the matplotlib ``Figure`` it drew; all
numbers are computed by the caller with :mod:`rotorlib`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from .choreo import BAND

__all__ = ["plot_rotation", "plot_resonance_families"]


def plot_rotation(
    E: ArrayLike,
    rho: ArrayLike,
    levels: Sequence[tuple[str, float, float, bool]],
    E_fold: float,
) -> Figure:
    """CG's rotation number ``rho`` against ``E`` (left: the whole family; right: near
    the fold), the rational levels ``(text, p/q, E, choreographies born)`` marked
    (filled: choreographies are born there; open: ``3 | q``)."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    for ax, (lo, hi) in zip(axes, ((0.0, 5.45), (4.5, 5.45))):
        ax.axvspan(*BAND, color="0.85", lw=0, label="band of global chaos")
        ax.axvline(E_fold, color="C3", lw=0.8, ls="--", label="fold of CG")
        ax.plot(E, rho, "C0", label=r"CG: $\rho(E)$")
        for text, y, Er, choreo in levels:
            if not lo <= Er <= hi:
                continue
            ax.axhline(y, color="k", lw=0.5, ls=":")
            ax.plot([Er], [y], "ko" if choreo else "wo", mec="k", ms=4)
            ax.annotate(text, (Er, y), (4, 2), textcoords="offset points", fontsize=7)
        ax.set_xlim(lo, hi)
        ax.set_xlabel(r"energy $E$ ($g$, with $m = g = r = 1$)")
        ax.set_ylabel(r"rotation number $\rho$ of CG's reduced map")
    axes[0].set_ylim(0, 0.35)
    axes[1].set_ylim(0, 0.3)
    axes[0].set_title(r"(a) from G ($\rho = 1/3$) to the fold ($\rho = 0$)")
    axes[1].set_title("(b) near the fold")
    axes[0].legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    return fig


def plot_resonance_families(
    cg: Mapping[str, ArrayLike],
    families: Mapping[str, Mapping[str, Any]],
) -> Figure:
    """The period of each family born from CG against ``E`` (solid where stable,
    dotted where unstable), with ``q T_CG`` or ``q T_CG / 2`` of CG (thin) and the band
    shaded. ``cg``: ``E``, ``period`` of CG; ``families``: name -> ``E``, ``period``,
    ``stable`` (bool array), ``q``."""
    fig, ax = plt.subplots(figsize=(8, 4.2))
    ax.axvspan(*BAND, color="0.85", lw=0, label="band of global chaos")
    Ec, Tc = np.asarray(cg["E"]), np.asarray(cg["period"])
    for k, (name, f) in enumerate(families.items()):
        E, T, st = (np.asarray(f[v]) for v in ("E", "period", "stable"))
        c = f"C{k // 2}"
        ax.plot(E, np.where(st, T, np.nan), c, lw=1.6)
        ax.plot(E, np.where(st, np.nan, T), c, lw=0.9, ls=":")
        ax.plot([], [], c, ls="-" if name.endswith("a") else ":", label=name)
        q = int(f["q"])
        if name.endswith("a"):
            ax.plot(Ec, Tc * q / (1 if q % 2 else 2), c, lw=0.4)
    ax.set_ylim(20, 100)
    ax.set_xlim(3.7, 5.62)
    ax.set_xlabel(r"energy $E$ ($g$, with $m = g = r = 1$)")
    ax.set_ylabel(r"period $T$ (units $\sqrt{m r^2/g}$)")
    ax.legend(fontsize=7, ncol=2, loc="upper left")
    fig.tight_layout()
    return fig
