"""Figures and tables for the breather chapter (paper §8, Fig. 10) and the appendices.

Units m = g = r = 1. Every function returns the matplotlib ``Figure`` it drew (or
a string for tables); all numbers are computed by the caller with :mod:`rotorlib`.
"""

from __future__ import annotations

from collections.abc import Mapping

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from . import COLUMN_WIDTH

__all__ = ["plot_fig10ab", "plot_fig10c", "plot_fig10d"]


def plot_fig10ab(
    E_LG: ArrayLike,
    tr_LG: ArrayLike,
    E_LD: ArrayLike,
    tr_LD: ArrayLike,
    E_R: ArrayLike,
    tr_R: ArrayLike,
    E_PD: float,
) -> Figure:
    """Paper Fig. 10(a): tr M of LG and LD; Fig. 10(b): tr M of R (log energy axis)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(COLUMN_WIDTH, 3.2))
    a.semilogy(E_LG, tr_LG, label="LG")
    a.semilogy(E_LD, tr_LD, "--", label="LD")
    a.axhline(4.0, color="k", lw=0.6, ls=":")
    a.set_xlabel(r"$E$ (units of $g$)")
    a.set_ylabel(r"$\mathrm{tr}\,M$")
    a.set_title("(a) librational breathers")
    a.legend(fontsize="small")
    b.semilogx(E_R, tr_R, label="R")
    for y in (0.0, 4.0):
        b.axhline(y, color="k", lw=0.6, ls=":")
    b.axvline(
        E_PD, color="C3", lw=0.8, ls="--", label=rf"$E_{{\mathrm{{PD}}}} = {E_PD:.4f}$"
    )
    b.set_ylim(-6, 5)
    b.set_xlabel(r"$E$ (units of $g$)")
    b.set_ylabel(r"$\mathrm{tr}\,M$")
    b.set_title("(b) rotational breather R")
    b.legend(loc="lower right", fontsize="small")
    fig.tight_layout()
    return fig


def plot_fig10c(
    E: ArrayLike,
    trace: ArrayLike,
    period: ArrayLike,
    E_PD: float,
    parent_E: ArrayLike | None = None,
    parent_trace: ArrayLike | None = None,
) -> Figure:
    """Paper Fig. 10(c): tr M and period of the daughter family against E (with the parent's tr M)."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.8))
    ax.plot(E, trace, "C0", label=r"daughter $\mathrm{tr}\,M$")
    if parent_E is not None:
        ax.plot(
            parent_E,
            parent_trace,  # type: ignore[arg-type]  # given with parent_E
            "C2--",
            label=r"parent R $\mathrm{tr}\,M$",
        )

    for y in (0.0, 4.0):
        ax.axhline(y, color="k", lw=0.6, ls=":")
    ax.axvline(E_PD, color="C3", lw=0.8, ls="--")
    ax.set_ylim(-1, 8)
    ax.set_xlabel(r"$E$ (units of $g$)")
    ax.set_ylabel(r"$\mathrm{tr}\,M$")
    ax2 = ax.twinx()
    ax2.plot(E, period, "C1", label="daughter period")
    ax2.set_ylabel(r"period $\tau$ (units of $\sqrt{m r^2/g}$)", color="C1")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, loc="upper center")
    fig.tight_layout()
    return fig


def plot_fig10d(trajectories: Mapping[str, np.ndarray]) -> Figure:
    """Paper Fig. 10(d): daughter orbits in the beta1-beta2 plane.

    ``trajectories``: ``{label: states [b1, b2, q1, q2]}``.
    """
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.4))
    for lab, x in trajectories.items():
        ax.plot(x[:, 0] / np.pi, x[:, 1], label=lab)
    ax.axhline(0.0, color="k", lw=1.5, label=r"breather R ($\beta_2 = 0$)")
    ax.set_xlabel(r"$\beta_1/\pi$")
    ax.set_ylabel(r"$\beta_2$ (rad)")
    ax.legend(loc="lower center", ncol=2, bbox_to_anchor=(0.5, 1.0))
    fig.tight_layout()
    return fig
