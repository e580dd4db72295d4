"""Figures of the catalogue chapter (13) and of its generated family pages.

:func:`plot_te_diagram` draws every family's period against energy, thick where it is
linearly stable, with the band of global chaos shaded and the separatrix energies
marked; each family's curves carry a URL (``artist.set_url``), so that the figure saved
as SVG links every branch to its page (no JavaScript). :func:`plot_family` draws one
family's ``T(E)`` and ``tr M(E)`` with its special points, :func:`plot_shapes` its
orbit on the configuration torus at a few energies, :func:`plot_stable_fraction` the
number of families and the stable fraction against ``E``.

Inputs are plain arrays (the catalogue's float64 continuation path), so that the
figures can be drawn from the JSON files alone.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from . import COLUMN_WIDTH, family_tex, integer_ticks, panel_letters

__all__ = [
    "E_LABEL",
    "T_LABEL",
    "plot_te_diagram",
    "plot_family",
    "plot_shapes",
    "plot_stable_fraction",
    "stable_mask",
]

E_LABEL = r"energy $E$ ($g$, with $m = g = r = 1$)"
T_LABEL = r"period $T$ (units $\sqrt{m r^2/g}$)"
STABLE, UNSTABLE = "C2", "C0"


def stable_mask(trace: ArrayLike) -> np.ndarray:
    """Linear stability from the monodromy's trace: ``0 < tr M < 4``."""
    tr = np.asarray(trace, dtype=float)
    return (tr > 0) & (tr < 4)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges ``[i, j)`` of the runs of True in ``mask``."""
    out, start = [], None
    for i, v in enumerate(mask):
        if v and start is None:
            start = i
        elif not v and start is not None:
            out.append((start, i))
            start = None
    if start is not None:
        out.append((start, len(mask)))
    return out


def _marks(ax, band, separatrices, window=None):
    ax.axvspan(*band, color="0.88", lw=0, label="band of global chaos")
    for k, (name, Es) in enumerate(separatrices):
        ax.axvline(Es, color="k", lw=0.8, ls=("--", ":", "-.")[k % 3], label=name)
    if window is not None:
        for e in window:
            ax.axvline(e, color="0.55", lw=0.6, ls=(0, (1, 3)))


def plot_te_diagram(
    curves: Sequence[Mapping[str, Any]],
    band: tuple[float, float],
    separatrices: Sequence[tuple[str, float]],
    window: tuple[float, float] | None = None,
    t_max: float | Sequence[Sequence[float]] | None = None,
) -> Figure:
    """Every family's ``T(E)``: thick green where stable, thin blue where unstable.

    ``curves``: one mapping per family with arrays ``E``, ``T``, ``trace`` and optional
    ``url`` (the family's page: every artist of the family links there in SVG) and
    ``id``. ``separatrices``: ``(legend text, E)`` pairs; ``window``: the built energy
    window (dotted); ``t_max``: the census's period bound (a horizontal line), or its
    bands ``[(E_hi, T_max), ...]`` (a step: ``T_max`` up to ``E_hi``).
    """
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 5.0), layout="constrained")
    _marks(ax, band, separatrices, window)
    for c in curves:
        E, T = np.asarray(c["E"], float), np.asarray(c["T"], float)
        st = stable_mask(c["trace"])
        url = c.get("url")
        gid = c.get("id")
        # a wide transparent stroke: the family's click target in the SVG
        hit = ax.plot(E, T, color="w", alpha=0.0, lw=7, zorder=1)[0]
        thin = ax.plot(E, T, color=UNSTABLE, lw=0.8, zorder=2)[0]
        arts = [hit, thin]
        for i, j in _runs(st):
            lo, hi = max(i - 1, 0), min(j + 1, len(E))  # join the run to its ends
            arts += ax.plot(E[lo:hi], T[lo:hi], color=STABLE, lw=2.4, zorder=3)
        for a in arts:
            if url:
                a.set_url(url)
        if gid:
            thin.set_gid(f"family-{gid}")
    if isinstance(t_max, (int, float)):
        ax.axhline(t_max, color="0.4", lw=0.6, ls="-.")
    elif t_max is not None:
        e0 = window[0] if window else 0.0
        for e1, T_b in t_max:
            ax.plot([e0, e1], [T_b, T_b], color="0.4", lw=0.6, ls="-.")
            e0 = e1
    ax.plot([], [], color=STABLE, lw=2.4, label=r"stable ($0 < \mathrm{tr}\,M < 4$)")
    ax.plot([], [], color=UNSTABLE, lw=0.8, label="unstable")
    ax.set_xlabel(E_LABEL)
    ax.set_ylabel(T_LABEL)
    ax.margins(x=0.01)
    fig.legend(loc="outside upper center", fontsize=9, ncol=3)
    return fig


def _symlog(ax, y):
    """A symmetric log scale, linear in ``|y| < 4``, ticked at 0, +-4, +-10^k."""
    from matplotlib.ticker import FixedLocator, FuncFormatter

    ax.set_yscale("symlog", linthresh=4, linscale=1.5)
    top = max(float(np.nanmax(np.abs(y))), 100.0)
    ks = range(2, int(math.ceil(math.log10(top))) + 1)  # 10 would crowd 4
    ticks = [0.0, 4.0] + [10.0**k for k in ks]
    if np.nanmin(y) < -4:
        ticks += [-4.0] + [-(10.0**k) for k in ks if 10.0 ** (k - 1) < -np.nanmin(y)]
    ax.yaxis.set_major_locator(FixedLocator(sorted(ticks)))

    def fmt(v, _):
        if abs(v) < 10:
            return f"${v:g}$"
        k = round(math.log10(abs(v)))
        return ("$-" if v < 0 else "$") + f"10^{{{k}}}$"

    ax.yaxis.set_major_formatter(FuncFormatter(fmt))
    ax.yaxis.set_minor_locator(FixedLocator([]))


def plot_family(
    E: ArrayLike,
    T: ArrayLike,
    trace: ArrayLike,
    points: Sequence[Mapping[str, Any]] = (),
    band: tuple[float, float] | None = None,
    title: str = "",
) -> Figure:
    """One family's ``T(E)`` (a) and ``tr M(E)`` (b) along its continuation path.

    ``points``: special points, mappings with ``kind``, ``E``, ``period``, ``trace``.
    ``tr M`` is drawn on a symmetric log scale (linear within ``|tr M| < 4``) when it
    leaves ``[-10, 14]``; the stable strip ``0 < tr M < 4`` is shaded.
    """
    E, T, tr = (np.asarray(v, dtype=float) for v in (E, T, trace))
    fig, (a, b) = plt.subplots(1, 2, figsize=(COLUMN_WIDTH, 2.9))
    st = stable_mask(tr)
    for ax, y in ((a, T), (b, tr)):
        if band is not None:
            ax.axvspan(*band, color="0.9", lw=0)
        ax.plot(E, y, color=UNSTABLE, lw=0.9)
        for i, j in _runs(st):
            lo, hi = max(i - 1, 0), min(j + 1, len(E))
            ax.plot(E[lo:hi], y[lo:hi], color=STABLE, lw=2.2)
        ax.set_xlabel(E_LABEL)
    b.axhspan(0, 4, color=STABLE, alpha=0.12, lw=0)
    for level in (0, 4):
        b.axhline(level, color="0.5", lw=0.6, ls=":")
    style = {"fold": ("k", "s"), "IS": ("C3", "o"), "PD": ("C1", "D")}
    for kind in sorted({str(p["kind"]) for p in points}):
        color, marker = style.get(kind, ("C4", "^"))
        ps = [p for p in points if p["kind"] == kind]
        kw = dict(color=color, marker=marker, ls="none", ms=5, mfc="w", zorder=5)
        a.plot([p["E"] for p in ps], [p["period"] for p in ps], **kw)
        b.plot([p["E"] for p in ps], [p["trace"] for p in ps], label=kind, **kw)
    if np.nanmax(tr) > 14 or np.nanmin(tr) < -10:
        _symlog(b, tr)
    a.set_ylabel(T_LABEL)
    b.set_ylabel(r"$\mathrm{tr}\,M$")
    a.set_title("period")
    b.set_title(r"$\mathrm{tr}\,M$ (stable: $0 < \mathrm{tr}\,M < 4$)")
    if points:
        b.legend(fontsize=9, loc="best")
    if title:
        fig.suptitle(family_tex(title))
    panel_letters((a, b))
    fig.tight_layout()
    return fig


def _wrap(x: np.ndarray) -> np.ndarray:
    return np.mod(x + math.pi, 2 * math.pi) - math.pi


def plot_shapes(orbits: Sequence[Mapping[str, Any]]) -> Figure:
    """Orbits on the configuration torus ``(phi1, phi2)``, one panel each.

    ``orbits``: mappings with ``states`` (``(n, 4)``, pendulum variables
    ``[a1, a2, p1, p2]`` over one period), ``E`` and ``title``. ``phi1 = 2 a1``,
    ``phi2 = a2 - a1``, wrapped to ``(-pi, pi]``; the region ``V > E`` (forbidden) is
    shaded, G (the minimum) and the maxima T are marked.
    """
    from ..core.system import potential_phi

    n = len(orbits)
    if n == 0:
        raise ValueError("plot_shapes: no orbits to draw")
    fig, axes = plt.subplots(1, n, figsize=(COLUMN_WIDTH, 2.75), squeeze=False)
    g = np.linspace(-math.pi, math.pi, 181)
    P1, P2 = np.meshgrid(g, g)
    V = np.asarray(potential_phi(P1, P2))
    for ax, o in zip(axes[0], orbits):
        s = np.asarray(o["states"], dtype=float)
        x, y = _wrap(2 * s[:, 0]), _wrap(s[:, 1] - s[:, 0])
        jump = np.hypot(np.diff(x), np.diff(y)) > math.pi
        x, y = x.copy(), y.copy()
        x[1:][jump] = np.nan
        if float(o["E"]) < float(V.max()):
            ax.contourf(
                P1, P2, V, levels=[float(o["E"]), float(V.max()) + 1], colors="0.85"
            )
            ax.contour(P1, P2, V, levels=[float(o["E"])], colors="0.5", linewidths=0.6)
        ax.plot(x, y, color="C0", lw=1.1)
        ax.plot([0], [0], "ko", ms=3.5)
        t = 2 * math.pi / 3
        ax.plot([t, -t], [t, -t], "k^", ms=3.5)
        ax.set_xlim(-math.pi, math.pi)
        ax.set_ylim(-math.pi, math.pi)
        ax.set_aspect("equal")
        ax.set_xticks([-3, 0, 3])
        ax.set_yticks([-3, 0, 3])
        ax.set_xlabel(r"$\varphi_1$ (rad)")
        ax.set_ylabel(r"$\varphi_2$ (rad)")
        ax.set_title(o.get("title", ""), fontsize=9.5)
    if n > 1:
        panel_letters(axes[0])
    fig.tight_layout()
    return fig


def plot_stable_fraction(
    E: ArrayLike,
    n_exist: ArrayLike,
    n_stable: ArrayLike,
    band: tuple[float, float] | None = None,
) -> Figure:
    """(a) The number of families with a member at ``E`` and of those stable there;
    (b) the stable fraction (undefined where no family exists)."""
    E, n, s = (np.asarray(v, dtype=float) for v in (E, n_exist, n_stable))
    fig, (a, b) = plt.subplots(1, 2, figsize=(COLUMN_WIDTH, 2.8))
    for ax in (a, b):
        if band is not None:
            ax.axvspan(*band, color="0.88", lw=0)
        ax.set_xlabel(E_LABEL)
    a.step(E, n, where="mid", color=UNSTABLE, label="families")
    a.step(E, s, where="mid", color=STABLE, label="stable there")
    a.set_ylabel("number of families")
    a.legend(fontsize=9)
    integer_ticks(a.yaxis)
    frac = np.where(n > 0, s / np.where(n > 0, n, 1), np.nan)
    b.step(E, frac, where="mid", color="k")
    b.set_ylim(-0.03, 1.03)
    b.set_ylabel("stable fraction")
    a.set_title("families existing")
    b.set_title("fraction stable")
    panel_letters((a, b))
    fig.tight_layout()
    return fig
