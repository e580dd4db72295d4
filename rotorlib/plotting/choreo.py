"""Figures for the chapter on the choreographies and the orbits born at G.

Units m = g = r = 1. Every function returns the matplotlib ``Figure`` it drew; all
numbers are computed by the caller with :mod:`rotorlib`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from ..paper.chaos import BAND

__all__ = [
    "plot_family",
    "plot_all_families",
    "plot_orbits",
    "plot_birth",
    "plot_cs",
    "plot_island",
    "BAND",
]


def _band(ax):
    ax.axvspan(*BAND, color="0.85", lw=0, label="band of global chaos")


def plot_family(
    cg: Mapping[str, ArrayLike],
    ct: Mapping[str, ArrayLike],
    E_fold: float,
    marks: Sequence[tuple[float, float, str]] = (),
) -> Figure:
    """Period and ``tr DP``, ``tr M`` of CG and CT against E, the band shaded.

    ``cg``, ``ct``: dicts of arrays ``E``, ``period``, ``trp`` (``tr DP``), ``trm``
    (``tr M``); ``marks``: ``(E, tr DP, text)`` of special points.
    """
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(11, 3.6))
    for ax in (a, b, c):
        _band(ax)
        ax.axvline(E_fold, color="C3", lw=0.8, ls="--")
        ax.set_xlabel(r"energy $E$ ($g$, with $m = g = r = 1$)")
    a.plot(cg["E"], cg["period"], "C0", label="CG (stable)")
    a.plot(ct["E"], ct["period"], "C1--", label="CT (unstable)")
    a.axhline(2 * math.pi / math.sqrt(3), color="k", lw=0.6, ls=":")
    a.set_ylim(3, 30)
    a.set_yscale("log")
    a.set_ylabel(r"period $T$ (units $\sqrt{m r^2/g}$)")
    a.set_title("(a) period")
    a.legend(fontsize=8, loc="upper left")
    b.plot(cg["E"], cg["trp"], "C0")
    b.plot(ct["E"], ct["trp"], "C1--")
    for y in (0.0, 4.0):
        b.axhline(y, color="k", lw=0.6, ls=":")
    for E, y, text in marks:
        b.plot([E], [y], "k.", ms=5)
        b.annotate(
            text, (E, y), (-6, 4), textcoords="offset points", ha="right", fontsize=7
        )
    b.set_ylim(-0.5, 8)
    b.set_ylabel(r"$\mathrm{tr}\,DP$ (reduced map, $T/6$)")
    b.set_title("(b) reduced trace: the stability")
    c.plot(cg["E"], cg["trm"], "C0")  # CT: tr M > 4 (off the scale)
    for y in (0.0, 4.0):
        c.axhline(y, color="k", lw=0.6, ls=":")
    c.set_ylim(-0.5, 8)
    c.set_ylabel(r"$\mathrm{tr}\,M$ (full period)")
    c.set_title(r"(c) $\mathrm{tr}\,M = 2 + 2\cos 6\vartheta$")
    for ax in (a, b, c):
        ax.set_xlim(0, 5.8)
    fig.tight_layout()
    return fig


def plot_orbits(orbits: Sequence[tuple[str, np.ndarray]]) -> Figure:
    """The orbits on the torus ``(phi1, phi2)`` and the three rotors on the circle.

    ``orbits``: list of ``(title, theta)`` with ``theta`` an array ``(n, 3)`` of the rotor
    angles over one period (centre of mass at rest).
    """
    n = len(orbits)
    ncol = min(n, 3)
    blocks = -(-n // ncol)
    fig, axes = plt.subplots(
        2 * blocks, ncol, figsize=(2.9 * ncol, 5.6 * blocks), squeeze=False
    )
    for k in range(n, blocks * ncol):  # empty slots of the last block
        r, col = divmod(k, ncol)
        axes[2 * r, col].set_visible(False)
        axes[2 * r + 1, col].set_visible(False)
    for k, (title, th) in enumerate(orbits):
        r, col = divmod(k, ncol)
        a, b = axes[2 * r, col], axes[2 * r + 1, col]
        phi1 = th[:, 0] - th[:, 1]
        phi2 = th[:, 1] - th[:, 2]
        w1 = np.mod(phi1 + math.pi, 2 * math.pi) - math.pi
        w2 = np.mod(phi2 + math.pi, 2 * math.pi) - math.pi
        jump = np.hypot(np.diff(w1), np.diff(w2)) > math.pi
        x, y = w1.copy(), w2.copy()
        x[1:][jump] = np.nan
        a.plot(x, y, "C0", lw=1)
        for px, py, mk in ((0, 0, "o"), (2 * math.pi / 3, 2 * math.pi / 3, "^")):
            a.plot([px, -px], [py, -py], "k" + mk, ms=4)
        a.set_xlim(-math.pi, math.pi)
        a.set_ylim(-math.pi, math.pi)
        a.set_aspect("equal")
        a.set_xlabel(r"$\varphi_1$")
        a.set_ylabel(r"$\varphi_2$")
        a.set_title(title, fontsize=9)
        t = np.linspace(0, 2 * math.pi, 200)
        b.plot(np.cos(t), np.sin(t), color="0.7", lw=0.8)
        m = len(th)
        for i, color in enumerate(("C0", "C1", "C2")):
            b.plot(
                np.cos(th[:, i]) * (1 - 0.04 * i),
                np.sin(th[:, i]) * (1 - 0.04 * i),
                color,
                lw=1,
            )
            b.plot(np.cos(th[0, i]), np.sin(th[0, i]), color + "o", ms=6)
            j = m // 12
            b.plot(np.cos(th[j, i]), np.sin(th[j, i]), color + "o", ms=4, mfc="w")
        b.set_aspect("equal")
        b.set_xlim(-1.15, 1.15)
        b.set_ylim(-1.15, 1.15)
        b.set_xticks([])
        b.set_yticks([])
        b.set_xlabel("rotors on the circle")
    fig.tight_layout()
    return fig


def plot_birth(
    E: ArrayLike, ratios: Mapping[str, ArrayLike], slopes: Mapping[str, float]
) -> Figure:
    """``(T/T0 - 1)/E`` of the three families born at G against E with their first-order
    slopes (``ratios``, ``slopes``: dicts by family name)."""
    fig, ax = plt.subplots(figsize=(6.2, 3.6))
    for k, (name, r) in enumerate(ratios.items()):
        ax.plot(E, r, f"C{k}o-", ms=3, label=name)
        ax.axhline(slopes[name], color=f"C{k}", lw=0.7, ls=":")
    ax.set_xscale("log")
    ax.set_xlabel(r"energy $E$ ($g$)")
    ax.set_ylabel(r"$(T/T_0 - 1)/E$, $T_0 = 2\pi/\sqrt{3}$")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def plot_all_families(
    families: Sequence[Mapping[str, Any]],
    cg: Mapping[str, ArrayLike],
    ct: Mapping[str, ArrayLike],
    E_fold: float,
) -> Figure:
    """Period and reduced trace of every choreography family against E, the band shaded.

    ``families``: list of dicts with ``label``, ``E``, ``period``, ``trace_reduced`` (the
    families of ``scripts/choreo_census.py``); ``cg``, ``ct`` as for :func:`plot_family`.
    """
    fig, (a, b) = plt.subplots(1, 2, figsize=(10.5, 3.8))
    for ax in (a, b):
        _band(ax)
        ax.axvline(E_fold, color="C3", lw=0.8, ls="--")
        ax.set_xlabel(r"energy $E$ ($g$, with $m = g = r = 1$)")
    a.plot(cg["E"], cg["period"], "C0", label="CG")
    a.plot(ct["E"], ct["period"], "C1--", label="CT")
    b.plot(cg["E"], cg["trp"], "C0")
    b.plot(ct["E"], ct["trp"], "C1--")
    for k, f in enumerate(families):
        E = np.asarray(f["E"])
        a.plot(E, f["period"], f"C{k + 2}", lw=1.2, label=f["label"])
        b.plot(E, f["trace_reduced"], f"C{k + 2}", lw=1.2)
    for y in (0.0, 4.0):
        b.axhline(y, color="k", lw=0.6, ls=":")
    a.set_yscale("log")
    a.set_ylabel(r"period $T$ (units $\sqrt{m r^2/g}$)")
    a.set_title("(a) period")
    a.legend(fontsize=7, ncol=2)
    b.set_yscale("symlog", linthresh=4)
    b.set_ylabel(r"$\mathrm{tr}\,DP$ (reduced map)")
    b.set_title(r"(b) stable where $0 < \mathrm{tr}\,DP < 4$")
    fig.tight_layout()
    return fig


def plot_cs(
    E: ArrayLike,
    period: ArrayLike,
    trp: ArrayLike,
    marks: Sequence[tuple[float, float, float, str]] = (),
) -> Figure:
    """The family CS along the continuation: (a) period and (b) ``tr DP`` (symmetric
    log scale) against E, the band shaded, the stable part ``0 < tr DP < 4`` drawn
    thick; ``marks``: ``(E, period, tr DP, text)`` of its special points."""
    E, period, trp = (np.asarray(v, float) for v in (E, period, trp))
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.6))
    stable = (trp > 0) & (trp < 4)
    for ax, y in ((a, period), (b, trp)):
        _band(ax)
        ax.plot(E, y, "C2-", lw=1, label="CS")
        ax.plot(E, np.where(stable, y, np.nan), "C2-", lw=3, label="CS stable")
        ax.set_xlabel("E (units of g)")
    for Em, Tm, pm, text in marks:
        a.plot(Em, Tm, "ko", ms=4)
        b.plot(Em, pm, "ko", ms=4)
        b.annotate(text, (Em, pm), textcoords="offset points", xytext=(-60, 8))
    a.set_ylabel(r"period $T$ (units of $\sqrt{mr^2/g}$)")
    a.set_ylim(0, 60)
    b.set_yscale("symlog", linthresh=4)
    for lev in (0, 4):
        b.axhline(lev, color="0.5", lw=0.6, ls=":")
    b.set_ylabel(r"$\mathrm{tr}\,DP$ (reduced map over $T/6$)")
    a.legend(loc="upper right", fontsize=8)
    a.set_title("(a)", loc="left")
    b.set_title("(b)", loc="left")
    fig.tight_layout()
    return fig


def plot_island(
    dE: ArrayLike, area: ArrayLike, err: ArrayLike, fold_label: str = ""
) -> Figure:
    """The area of CG's island on the section against the distance ``E_f - E`` to the
    fold (log-log, error bars)."""
    fig, ax = plt.subplots(figsize=(5, 3.6))
    ax.errorbar(dE, area, yerr=err, fmt="o-", ms=4, capsize=2, color="C0")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(
        r"$E_f - E$ (units of g)" + (f" ({fold_label})" if fold_label else "")
    )
    ax.set_ylabel(r"island area in $(\varphi_2, P_2)$ (units of $\sqrt{m r^2 g}$)")
    fig.tight_layout()
    return fig
