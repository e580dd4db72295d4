"""Figures for the chapter on pendulum stability transitions (paper §5, Figs. 2 and 3).

Units m = g = r = 1. The caller computes every number with :mod:`rotorlib.paper.bifurcations`;
these functions only draw. Each returns the matplotlib ``Figure``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from . import COLUMN_WIDTH, family_tex

if TYPE_CHECKING:
    from ..paper.bifurcations import Transition

__all__ = ["plot_fig2", "plot_fig3"]

_COLORS = {"IS": "tab:red", "PD": "tab:blue"}


def _band(ax):
    ax.axhspan(0.0, 4.0, color="0.93", zorder=0, lw=0)
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.axhline(4.0, color="0.5", lw=0.6)


def plot_fig2(
    curves: Mapping[str, tuple[np.ndarray, np.ndarray]],
    trs: Sequence[Transition],
    label_n_max: int = 6,
    ylim: tuple[float, float] = (-1.5, 6.0),
) -> Figure:
    """tr M against the period tau, (a) libration and (b) rotation, transitions marked and labelled.

    Parameters
    ----------
    curves : dict
        ``{'lib': (tau, trM), 'rot': (tau, trM)}``.
    trs : sequence of Transition
        Marked at ``(period, 4 or 0)``; labelled when ``n <= label_n_max``.
    """
    fig, axes = plt.subplots(
        1, 2, figsize=(COLUMN_WIDTH, 3.2), sharey=True, constrained_layout=True
    )
    for ax, phase, tag in zip(
        axes, ("lib", "rot"), ("(a) libration, $E < 4$", "(b) rotation, $E > 4$")
    ):
        tau, tr = curves[phase]
        _band(ax)
        ax.plot(tau, tr, color="k", lw=0.9)
        for t in trs:
            if t.phase != phase or t.period > tau.max():
                continue
            y = 4.0 if t.kind == "IS" else 0.0
            ax.plot(t.period, y, "o", ms=4, color=_COLORS[t.kind], zorder=3)
            if t.n <= label_n_max:
                k = t.kind
                dy = 0.35 if k == "IS" else -0.55
                if k == "IS" and t.n % 2 == 0:
                    dy = 0.95
                ax.annotate(
                    _tex(t.label),
                    (t.period, y),
                    xytext=(t.period, y + dy),
                    fontsize="small",
                    ha="center",
                    color=_COLORS[k],
                )
        ax.set_ylim(*ylim)
        ax.set_xlim(0, tau.max())
        ax.set_xlabel(r"period $\tau$ (units of $\sqrt{m r^2/g}$)")
        ax.set_title(tag)
    axes[0].set_ylabel(r"$\mathrm{tr}\,M$")
    return fig


def plot_fig3(panels: Sequence[Mapping[str, Any]]) -> Figure:
    """Self-similarity of tr M(E) under magnification (five panels a-e), with the newborn families.

    Parameters
    ----------
    panels : list of dict
        Each with ``dE`` (``E - 4``, array), ``trace`` (array), ``title`` (str),
        ``marks`` (list of ``(E - 4, y, label)``), optionally ``ylim`` and
        ``families``: a list of objects with ``label``, ``dE`` and ``trace``
        (:class:`rotorlib.orbits.family.Branch`), drawn dashed (IS) or dotted (PD)
        and listed in the panel's legend; ``deeper``: more such families, drawn thin
        and grey under one legend entry ``deeper_label``; ``legend_loc``.
    """
    fig, axes = plt.subplots(3, 2, figsize=(COLUMN_WIDTH, 8.4), constrained_layout=True)
    axes = axes.ravel()
    for ax, p in zip(axes, panels):
        _band(ax)
        ax.plot(p["dE"], p["trace"], color="k", lw=0.9, label="pendulum")
        fams = p.get("families", [])
        for i, f in enumerate(fams):
            style = "--" if f.label.startswith("IS") else ":"
            ax.plot(
                f.dE,
                f.trace,
                style,
                lw=1.2,
                color=_FAMILY_COLORS[i % len(_FAMILY_COLORS)],
                label=_tex(f.label),
            )
        for i, f in enumerate(p.get("deeper", [])):
            ax.plot(
                f.dE,
                f.trace,
                "--" if f.label.startswith("IS") else ":",
                lw=0.8,
                color="0.45",
                label=p.get("deeper_label", "deeper families") if i == 0 else None,
            )
        for x, y, lab in p.get("marks", []):
            ax.plot(x, y, "o", ms=4, color=_COLORS[lab[:2]], zorder=3)
            ax.annotate(
                _tex(lab),
                (x, y),
                xytext=(3, 6 if y > 2 else -12),
                textcoords="offset points",
                fontsize="small",
                color=_COLORS[lab[:2]],
            )
        ax.set_xlim(min(p["dE"]), max(p["dE"]))
        ax.set_ylim(*p.get("ylim", (-1.0, 7.0)))
        ax.ticklabel_format(axis="x", style="sci", scilimits=(-2, 2), useMathText=True)
        ax.set_xlabel(r"$E - 4$ (units of $g$)")
        ax.set_ylabel(r"$\mathrm{tr}\,M$")
        ax.set_title(family_tex(p["title"]))
        if fams or p.get("deeper"):
            ax.legend(
                fontsize="small",
                ncol=2,
                loc=p.get("legend_loc", "best"),
                framealpha=0.85,
                handlelength=2.2,
            )
    for ax in axes[len(panels) :]:
        ax.axis("off")
    return fig


_FAMILY_COLORS = (
    "tab:red",
    "tab:orange",
    "tab:purple",
    "tab:green",
    "tab:brown",
    "tab:pink",
    "tab:olive",
    "tab:cyan",
    "tab:blue",
    "tab:gray",
)


def _tex(label):
    r"""``IS^l_3`` -> ``$\mathrm{IS}^\ell_{3}$`` (:func:`rotorlib.core.compare.label_tex`)."""
    return family_tex(label)
