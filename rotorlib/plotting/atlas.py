"""Figures of the chapter *Periodic orbits in the band of global chaos* (book/09_atlas)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from ..paper.chaos import BAND
from . import COLUMN_WIDTH, integer_ticks, panel_letters

if TYPE_CHECKING:
    from ..beyond.atlas import Atlas
    from ..beyond.atlas_families import Cascade
    from ..orbits.family import Branch
    from ..paper.chaos import ChaoticFraction, PoincareSection

__all__ = [
    "plot_sweep",
    "plot_growth",
    "plot_family_trace",
    "plot_islands",
    "plot_cascade",
]


def plot_sweep(atlases: Sequence[Atlas], cf: ChaoticFraction | None = None) -> Figure:
    """Period against E of every orbit of each census (stable ones filled), the band
    shaded; beside it the number of stable orbits and the chaotic fraction ``cf``."""
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(COLUMN_WIDTH, 3.3))
    for a in atlases:
        T = np.array([o.period for o in a.orbits])
        s = np.array([o.stable for o in a.orbits], bool)
        ax.plot([a.E] * int((~s).sum()), T[~s], "o", mfc="none", color="0.45", ms=3)
        ax.plot([a.E] * int(s.sum()), T[s], "o", color="C3", ms=4)
    ax.plot([], [], "o", mfc="none", color="0.45", label="unstable")
    ax.plot([], [], "o", color="C3", label="linearly stable")
    for x in (ax, bx):
        x.axvspan(*BAND, color="C0", alpha=0.12, lw=0)
        x.set_xlabel(r"$E$ (units of $g$)")
    ax.set_ylabel(r"period $T$ (units of $\sqrt{m r^2/g}$)")
    ax.legend(loc="upper left")
    ax.set_title(r"symmetric periodic orbits, $T \leq T_{\max}$")
    E = [a.E for a in atlases]
    bx.step(E, [len(a.stable) for a in atlases], where="mid", color="C3")
    bx.set_ylabel("linearly stable orbits (number)", color="C3")
    integer_ticks(bx.yaxis)
    bx.set_ylim(bottom=0)
    if cf is not None:
        cx = bx.twinx()
        cx.errorbar(cf.E, cf.fraction, cf.stderr, fmt="s-", color="C0", ms=4)
        cx.set_ylabel("chaotic fraction of the shell", color="C0")
        cx.set_ylim(0, 1.05)
    bx.set_title("stable orbits and chaos")
    panel_letters([ax, bx])
    fig.tight_layout()
    return fig


def plot_growth(
    periods: ArrayLike, T_fit: tuple[float, float], slope: float, intercept: float
) -> Figure:
    """``N(T)``: the number of orbits with period ``<= T`` (log scale) and the fit."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.6))
    T = np.sort(periods)
    ax.step(T, np.arange(1, len(T) + 1), where="post", label=r"$N(T)$, census")
    t = np.linspace(*T_fit, 50)
    ax.plot(
        t, np.exp(intercept + slope * t), "--", label=rf"$\propto e^{{{slope:.2f}\,T}}$"
    )
    ax.set_yscale("log")
    ax.set_xlabel(r"period $T$ (units of $\sqrt{m r^2/g}$)")
    ax.set_ylabel(r"$N(T)$: orbits with period $\leq T$")
    ax.legend()
    fig.tight_layout()
    return fig


def plot_family_trace(fam: Branch, E_fold: float | None = None) -> Figure:
    """``tr M`` against E along one atlas family (:func:`rotorlib.beyond.atlas_families.families`),
    its special points dotted, the stable strip ``0 < tr M < 4``."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.8))
    ax.axhspan(
        0,
        4,
        color="C2",
        alpha=0.15,
        lw=0,
        label=r"linearly stable: $0 < \mathrm{tr}\,M < 4$",
    )
    ax.plot(
        fam.E, fam.trace, ".-", color="C3", label=r"$\mathrm{tr}\,M$ along the family"
    )
    for p in fam.special_points:
        ax.axvline(p.E, color="0.5", lw=0.8, ls=":")
    if E_fold is not None:
        ax.axvline(E_fold, color="k", lw=1, ls="--", label="fold of the family")
    ax.set_xlabel(r"$E$ (units of $g$)")
    ax.set_ylabel(r"$\mathrm{tr}\,M$")
    ax.legend()
    fig.tight_layout()
    return fig


def plot_islands(
    sections: Mapping[float, PoincareSection], checks: Mapping[float, Sequence[Any]]
) -> Figure:
    """One panel per energy: the Poincaré section (``sections[E]``, grey), the crossings of
    each checked orbit (``checks[E]``, stable: red, hyperbolic: black crosses) and of its
    test trajectory (coloured dots)."""
    Es = sorted(sections)
    fig, axes = plt.subplots(
        1, len(Es), figsize=(COLUMN_WIDTH, 3.6 if len(Es) > 1 else 5.0), squeeze=False
    )
    for ax, E in zip(axes[0], Es):
        sec = sections[E]
        for f, P in zip(sec.phi2, sec.P2):
            ax.plot(f, P, ",", color="0.6")
        for k, c in enumerate(checks[E]):
            st = c.orbit.stable
            ax.plot(c.test_phi2, c.test_P2, ".", ms=1.5, color=f"C{k % 10}")
            ax.plot(
                c.phi2,
                c.P2,
                "o" if st else "x",
                color="C3" if st else "k",
                ms=6,
                mfc="none" if st else None,
                label=rf"$T = {c.orbit.period:.3f}$, $\mathrm{{tr}}\,M = {c.orbit.trace:.3g}$",
            )
        ax.set_xlabel(r"$\varphi_2$ (rad) at $\varphi_1 = 0$, $\dot\varphi_1 > 0$")
        ax.set_ylabel(r"$P_2$ (units of $\sqrt{g m r^2}$)")
        ax.set_title(f"$E = {E:g}$")
        ax.legend(loc="upper right", fontsize="small")
    if len(Es) > 1:
        panel_letters(axes[0])
    fig.tight_layout()
    return fig


def plot_cascade(cas: Cascade) -> Figure:
    """``tr M`` against ``E - E_last`` (the last located birth) for each generation of a
    :class:`rotorlib.beyond.atlas_families.Cascade`, the births marked; ``E`` on a symmetric
    logarithmic axis (each generation's window is ~9 times narrower than its parent's)."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.8))
    E0 = cas.births[-1]
    ax.axhspan(
        0,
        4,
        color="C2",
        alpha=0.15,
        lw=0,
        label=r"linearly stable: $0 < \mathrm{tr}\,M < 4$",
    )
    for n, (f, T) in enumerate(zip(cas.families[1:], cas.periods), start=2):
        keep = np.abs(f.trace) < 40
        ax.plot(
            f.E[keep] - E0,
            f.trace[keep],
            ".-",
            ms=3,
            label=f"generation {n}, $T = {T:.3f}$",
        )
    for E in cas.births:
        ax.axvline(E - E0, color="0.5", lw=0.8, ls=":")
    ax.set_xscale("symlog", linthresh=1e-7)
    ax.set_ylim(-6, 10)
    ax.set_xlabel(f"$E - {E0:.10f}$ (units of $g$)")
    ax.set_ylabel(r"$\mathrm{tr}\,M$")
    ax.legend()
    fig.tight_layout()
    return fig
