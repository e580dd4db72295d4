"""Figures and tables for the chapters on the formulation (paper §2) and on
perturbations to pendula (paper §4).

Units m = g = r = 1 (time is the paper's dimensionless t~). Every function
returns the matplotlib ``Figure`` it drew (or a string, for tables); the
numbers plotted are computed by the caller with :mod:`rotorlib`, except the
potential V(phi1, phi2) on a grid, which is evaluated here with
:func:`rotorlib.core.system.potential_phi`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from ..core.system import potential_phi
from . import COLUMN_WIDTH, panel_letters

if TYPE_CHECKING:
    from ..core.system import CriticalPoint

__all__ = [
    "pendulum_lines",
    "breather_lines",
    "plot_fig1",
    "plot_separatrix_approach",
    "plot_textbook_error",
    "plot_trace_vs_energy",
]

TWO_PI = 2.0 * math.pi


# --------------------------------------------------------------------------- tables
def _wrapped(phi1, phi2):
    """Reduce a curve to the square [0, 2pi)^2, inserting NaN where it jumps across an edge."""
    x, y = np.mod(phi1, TWO_PI), np.mod(phi2, TWO_PI)
    jump = np.r_[False, (np.abs(np.diff(x)) > math.pi) | (np.abs(np.diff(y)) > math.pi)]
    idx = np.flatnonzero(jump)
    return np.insert(x, idx, np.nan), np.insert(y, idx, np.nan)


def pendulum_lines(n: int = 801) -> dict:
    """The three pendulum lines phi1 = 0, phi2 = 0, phi1 + phi2 = 0 (mod 2 pi) on the square.

    Returns ``{label: (phi1, phi2)}``; each line is the full E = 4 homoclinic
    orbit through one saddle (D3, D2, D1 respectively).
    """
    s = np.linspace(0.0, TWO_PI, n)
    z = np.zeros_like(s)
    return {
        r"$\varphi_1 = 0$ (through $D_3$)": _wrapped(z, s),
        r"$\varphi_2 = 0$ (through $D_2$)": _wrapped(s, z),
        r"$\varphi_1 + \varphi_2 = 0$ (through $D_1$)": _wrapped(s, -s),
    }


def breather_lines(n: int = 1601) -> dict:
    """The three isosceles-breather curves phi1 = phi2, phi1 + 2 phi2 = 0, 2 phi1 + phi2 = 0 (mod 2 pi).

    Each closed curve is parametrised by ``s in [0, 2 pi]`` (``(s, s)``,
    ``(-2s, s)``, ``(s, -2s)``): it passes G (s = 0), T1 (s = 2pi/3), a saddle
    D (s = pi) and T2 (s = 4pi/3), i.e. it is made of the two E = 4.5
    heteroclinic orbits between the maxima.
    """
    s = np.linspace(0.0, TWO_PI, n)
    return {
        r"$\varphi_1 = \varphi_2$ (through $D_1$)": _wrapped(s, s),
        r"$\varphi_1 + 2\varphi_2 = 0$ (through $D_3$)": _wrapped(-2 * s, s),
        r"$2\varphi_1 + \varphi_2 = 0$ (through $D_2$)": _wrapped(s, -2 * s),
    }


def _equipotentials(ax, points, levels, grid):
    g = np.linspace(0.0, TWO_PI, grid)
    X, Y = np.meshgrid(g, g, indexing="xy")
    V = potential_phi(X, Y)
    ax.contour(X, Y, V, levels=levels, colors="0.6", linewidths=0.6)
    ax.contour(X, Y, V, levels=[4.0], colors="tab:red", linewidths=0.8, alpha=0.5)
    ax.contour(X, Y, V, levels=[4.5], colors="tab:purple", linewidths=0.8, alpha=0.5)
    style = {
        "minimum": ("o", "tab:green"),
        "maximum": ("^", "tab:red"),
        "saddle": ("s", "tab:blue"),
    }
    for p in points:
        # draw every periodic copy that lies in the closed square
        for dx in (0.0, TWO_PI):
            for dy in (0.0, TWO_PI):
                x, y = p.phi[0] + dx, p.phi[1] + dy
                if x <= TWO_PI + 1e-9 and y <= TWO_PI + 1e-9:
                    mk, col = style[p.kind]
                    ax.plot(x, y, mk, color=col, ms=5, zorder=5)
        ax.annotate(
            f"${p.name[0]}_{{{p.name[1:]}}}$" if len(p.name) > 1 else f"${p.name}$",
            p.phi,
            textcoords="offset points",
            xytext=(5, 5),
            fontsize="medium",
            zorder=6,
        )
    ticks = [0, math.pi / 2, math.pi, 3 * math.pi / 2, TWO_PI]
    labels = ["0", r"$\pi/2$", r"$\pi$", r"$3\pi/2$", r"$2\pi$"]
    ax.set_xticks(ticks, labels)
    ax.set_yticks(ticks, labels)
    ax.set_xlim(-0.12, TWO_PI + 0.12)
    ax.set_ylim(-0.12, TWO_PI + 0.12)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$\varphi_1$ (rad)")
    ax.set_ylabel(r"$\varphi_2$ (rad)")


def plot_fig1(
    points: Sequence[CriticalPoint],
    levels: Sequence[float] | None = None,
    grid: int = 301,
) -> Figure:
    """Paper Fig. 1: equipotentials of V on [0, 2pi]^2 with G, T, D; (a) pendulum lines, (b) breather lines.

    Parameters
    ----------
    points : sequence of rotorlib.core.system.CriticalPoint
        From :func:`rotorlib.core.system.critical_points` (marked and labelled).
    levels : sequence of float, optional
        Equipotential levels (default 0.25, 0.5, ..., 4.25 and 4.4). E = 4 (red)
        and E = 4.5 (purple) are always drawn.
    """
    if levels is None:
        levels = list(np.arange(0.25, 4.3, 0.5)) + [4.4]
    fig, axes = plt.subplots(
        1, 2, figsize=(COLUMN_WIDTH, 4.3), sharey=True, constrained_layout=True
    )
    for ax in axes:
        _equipotentials(ax, points, levels, grid)
    for (lab, (x, y)), ls in zip(pendulum_lines().items(), (":", "--", "-")):
        axes[0].plot(x, y, ls, color="k", lw=1.8, label=lab)
        # the lines phi1 = 0 and phi2 = 0 lie on the edges: draw their copies on the opposite edges too
        axes[0].plot(
            np.where(x == 0.0, TWO_PI, x),
            np.where(y == 0.0, TWO_PI, y),
            ls,
            color="k",
            lw=1.8,
        )
    for (lab, (x, y)), ls in zip(breather_lines().items(), ("-", "--", ":")):
        axes[1].plot(x, y, ls, color="k", lw=1.6, label=lab)
    axes[0].set_title("(a) pendula, $E = 4$")
    axes[1].set_title("(b) isosceles breathers, $E = 4.5$")
    for ax in axes:
        ax.legend(
            loc="upper center",
            bbox_to_anchor=(0.5, -0.16),
            fontsize="small",
            framealpha=0.9,
        )
    return fig


# --------------------------------------------------------------------------- separatrix
def plot_separatrix_approach(
    curves: Sequence[tuple[str, np.ndarray, np.ndarray]],
    period_marks: Sequence[tuple[str, float]] | None = None,
    portrait_curves: Sequence[tuple[str, np.ndarray, np.ndarray]] | None = None,
) -> Figure:
    """Time series a2(t) and phase portrait (a2, p2) of pendula near E = 4.

    Parameters
    ----------
    curves : sequence of (label, t, state)
        ``state`` has shape ``t.shape + (4,)`` (``[a1, a2, p1, p2]``).
    period_marks : sequence of (label, period), optional
        Vertical lines on the time series.
    portrait_curves : sequence of (label, t, state), optional
        Curves for the phase portrait (default: ``curves``).
    """
    fig, (ax1, ax2) = plt.subplots(
        1, 2, figsize=(COLUMN_WIDTH, 3.3), constrained_layout=True
    )
    for lab, t, st in curves:
        ax1.plot(t, st[..., 1], label=lab)
    for lab, t, st in portrait_curves or curves:
        ax2.plot(
            np.mod(st[..., 1] + math.pi, TWO_PI) - math.pi,
            st[..., 3],
            ".",
            ms=1.5,
            label=lab,
        )
    for lab, T in period_marks or []:
        ax1.axvline(T, color="0.5", ls=":", lw=1)
    ax1.set_xlabel(r"time $\tilde t$ (units of $\sqrt{m r^2/g}$)")
    ax1.set_ylabel(r"$\alpha_2 = \varphi_2$ (rad)")
    ax1.legend(fontsize="small")
    ax2.set_xlabel(r"$\alpha_2$ mod $2\pi$ (rad)")
    ax2.set_ylabel(r"$\tilde\pi_2$ (units of $\sqrt{g m r^2}$)")
    ax2.legend(fontsize="small", markerscale=6)
    panel_letters([ax1, ax2])
    return fig


# --------------------------------------------------------------------------- chapter 2
def plot_textbook_error(
    eps: ArrayLike,
    err: ArrayLike,
    label: str | None = None,
    slope: float | None = -1.0,
) -> Figure:
    """Log-log plot of |error of tr M| against |E - 4|, with a reference line of the given slope.

    ``label`` names the curve in the legend (``None``: the textbook 4x4 route, scipy
    DOP853 at rtol 1e-12)."""
    if label is None:
        label = r"textbook $4 \times 4$ (scipy DOP853, rtol $10^{-12}$)"
    eps, err = np.asarray(eps, float), np.asarray(err, float)
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 4.0), constrained_layout=True)
    ax.loglog(eps, err, "o-", label=label)
    if slope is not None:
        i = int(np.argmax(eps))
        ref = err[i] * (eps / eps[i]) ** slope
        ax.loglog(eps, ref, "k:", label=rf"$\propto |E-4|^{{{slope:g}}}$")
    ax.set_xlabel(r"$|E - 4|$ (units of $g$)")
    ax.set_ylabel(r"$|\mathrm{tr}\,M_{\rm textbook} - \mathrm{tr}\,M_{\rm ref}|$")
    ax.invert_xaxis()
    ax.legend()
    return fig


def plot_trace_vs_energy(
    E_lib: ArrayLike,
    tr_lib: ArrayLike,
    E_rot: ArrayLike,
    tr_rot: ArrayLike,
    ylim: tuple[float, float] = (-1.0, 5.0),
) -> Figure:
    """tr M of pendula against E on both sides of the separatrix, with the band 0 < tr M < 4 shaded."""
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.9), constrained_layout=True)
    ax.axhspan(
        0.0,
        4.0,
        color="tab:green",
        alpha=0.15,
        label=r"stable: $0 < \mathrm{tr}\,M < 4$",
    )
    ax.plot(E_lib, tr_lib, color="tab:blue", label="libration ($E < 4$)")
    ax.plot(E_rot, tr_rot, color="tab:orange", label="rotation ($E > 4$)")
    ax.axvline(4.0, color="0.4", ls=":", lw=1)
    ax.set_ylim(*ylim)
    ax.set_xlabel(r"relative energy $E$ (units of $g$)")
    ax.set_ylabel(r"$\mathrm{tr}\,M$ of the pendulum $\varphi_1 = 0$")
    ax.legend(loc="upper right")
    return fig
