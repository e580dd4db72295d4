"""Figures for the chapter on the band of global chaos (paper §9).

Units m = g = r = 1. Each function returns the ``Figure`` it drew; the numbers are
computed by the caller with :mod:`rotorlib`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from ..paper.chaos import BAND
from . import COLUMN_WIDTH, family_tex, integer_ticks, panel_letters

if TYPE_CHECKING:
    from ..orbits.family import Branch
    from ..paper.chaos import ChaoticFraction, PoincareSection

__all__ = [
    "plot_band_traces",
    "plot_sections",
    "plot_fraction",
    "plot_ftle_histograms",
    "plot_rotational_branches",
]


def _band(ax):
    ax.axvspan(
        *BAND, color="0.85", zorder=0, label=rf"band ${BAND[0]} \leq E \leq {BAND[1]}$"
    )


def _stable_window(ax):
    """Shade the stable window ``0 < tr M < 4`` (green) on a tr M axis."""
    ax.axhspan(
        0.0,
        4.0,
        color="C2",
        alpha=0.15,
        zorder=0,
        label=r"stable window $0 < \mathrm{tr}\,M < 4$",
    )


def plot_band_traces(curves: Mapping[str, tuple[ArrayLike, ArrayLike]]) -> Figure:
    """``curves``: ``{label: (E, trM)}``; tr M on a symmetric-log axis (linear for |tr M| < 5) with the
    stable window ``0 < tr M < 4`` shaded green and the band grey."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.9))
    _band(ax)
    _stable_window(ax)
    for lab, (E, tr) in curves.items():
        ax.plot(E, tr, label=family_tex(lab))
    ax.set_yscale("symlog", linthresh=5.0, linscale=3.0)
    ticks = [-1e4, -1e2, 0, 4, 1e2, 1e4, 1e6, 1e8]
    ax.set_yticks(
        ticks, ["$-10^4$", "$-10^2$", "0", "4", "$10^2$", "$10^4$", "$10^6$", "$10^8$"]
    )
    ax.set_xlabel(r"$E$ (units of $g$)")
    ax.set_ylabel(r"$\mathrm{tr}\,M$ (symmetric log scale)")
    ax.legend(loc="center right", fontsize="small")
    fig.tight_layout()
    return fig


def plot_sections(sections: Sequence[PoincareSection], ncols: int = 3) -> Figure:
    """Poincaré sections (``rotorlib.paper.chaos.PoincareSection``), one panel each."""
    n = len(sections)
    nrows = (n + ncols - 1) // ncols
    fig, axes = plt.subplots(
        nrows, ncols, figsize=(COLUMN_WIDTH, 2.5 * nrows), squeeze=False
    )
    for ax, s in zip(axes.ravel(), sections):
        for k, (x, y) in enumerate(zip(s.phi2, s.P2)):
            # points of 1 px at 100 dpi; rasterized, so that an SVG figure stays small
            ax.plot(
                x, y, "o", ms=0.35, mew=0, color=plt.cm.tab10(k % 10), rasterized=True
            )
        ax.set_title(
            f"$E = {s.E:g}$" + (" (band)" if BAND[0] <= s.E <= BAND[1] else "")
        )
        ax.set_xlabel(r"$\varphi_2$ (rad)")
        ax.set_ylabel(r"$\tilde p_2$ (units of $\sqrt{g m r^2}$)")
        ax.set_xlim(0, 2 * np.pi)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    if n > 1:
        panel_letters(axes.ravel()[:n])
    fig.tight_layout()
    return fig


def plot_fraction(cf: ChaoticFraction) -> Figure:
    """Chaotic fraction ``f(E)`` with binomial error bars (``rotorlib.paper.chaos.ChaoticFraction``)."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.4))
    _band(ax)
    ax.errorbar(
        cf.E,
        cf.fraction,
        yerr=cf.stderr,
        fmt="o-",
        ms=3,
        capsize=2,
        label=rf"FTLE $> {cf.threshold:g}$ ($N = {cf.N}$, $T = {cf.T:g}$)",
    )
    ax.axvline(4.0, color="C3", lw=0.6, ls="--", label=r"$E = 4$ (pendulum separatrix)")
    ax.set_ylim(-0.03, 1.03)
    ax.set_xlabel(r"$E$ (units of $g$)")
    ax.set_ylabel("chaotic fraction of the shell")
    ax.legend(loc="lower right")
    fig.tight_layout()
    return fig


def plot_ftle_histograms(
    cf: ChaoticFraction, energies: Iterable[float], threshold: float | None = None
) -> Figure:
    """Histograms of the FTLEs at a few energies of ``cf``."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.3))
    bins = np.linspace(0, max(0.8, max(np.max(x) for x in cf.ftles)), 60)
    for E in energies:
        k = int(np.argmin(np.abs(cf.E - E)))
        ax.hist(
            cf.ftles[k],
            bins=bins,  # type: ignore[arg-type]  # an array of edges is fine
            histtype="step",
            label=f"$E = {cf.E[k]:g}$",
        )

    ax.axvline(
        threshold if threshold is not None else cf.threshold,
        color="k",
        ls=":",
        label="threshold",
    )
    ax.set_xlabel(
        r"finite-time Lyapunov exponent $\lambda_T$ (units of $\sqrt{g/m r^2}$)"
    )
    ax.set_ylabel("initial conditions (count)")
    integer_ticks(ax.yaxis)
    ax.legend()
    fig.tight_layout()
    return fig


def plot_rotational_branches(
    branches: Iterable[Branch], E_max: float = 4.5, trace_cap: float = 1e12
) -> Figure:
    """tr M against E along rotational newborn families (:class:`rotorlib.orbits.continuation.Branch`
    with traces, e.g. ``FamilyInBand.branch`` of :func:`rotorlib.paper.chaos.band_families`),
    symmetric-log axis, with the band shaded and the energy ``E_max`` (where the families
    end) marked. Members with ``|tr M| > trace_cap`` (float64 traces there are only an
    order of magnitude) are not drawn."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.9))
    _band(ax)
    _stable_window(ax)
    for i, b in enumerate(branches):
        tr = np.where(np.abs(b.trace) <= trace_cap, b.trace, np.nan)
        ax.plot(
            b.E, tr, ".-", ms=2, lw=1, color=f"C{i % 10}", label=family_tex(b.label)
        )
    ax.axvline(
        E_max, color="k", ls="--", lw=0.8, label=f"$E = {E_max:g}$ (maximum of $V$)"
    )
    ax.set_yscale("symlog", linthresh=5.0, linscale=2.0)
    ax.set_ylim(-2 * trace_cap, 2 * trace_cap)
    ax.set_xlabel(r"$E$ (units of $g$)")
    ax.set_ylabel(r"$\mathrm{tr}\,M$ (symmetric log scale)")
    ax.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    return fig
