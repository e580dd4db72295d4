"""Figures of the search chapter (paper §6). Units m = g = r = 1."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure, SubFigure
from numpy.typing import ArrayLike

from . import COLUMN_WIDTH, family_tex, panel_letters

if TYPE_CHECKING:
    from ..orbits.family import Branch
    from ..paper.search import DefectLandscape, WorkPrecision


def landscape(L: DefectLandscape, ax: Axes | None = None) -> Figure | SubFigure:
    """``d`` and ``|r|`` against the relative offset of ``p2(0)`` (log-log), with the minimiser's floor."""
    fig: Figure | SubFigure  # ``ax.figure``: a subfigure when ``ax`` is in one
    if ax is None:
        fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 4.0))
    else:
        fig = ax.figure
    ax.loglog(
        L.delta, L.defect, "o-", ms=3, label=r"paper: departure $d$ (full period)"
    )
    ax.loglog(
        L.delta,
        L.residual,
        "s-",
        ms=3,
        label=r"symmetric shooting: $|r|$ (quarter/half period)",
    )
    eps = np.finfo(float).eps
    ax.axvline(
        np.sqrt(eps),
        color="C3",
        ls="--",
        lw=1,
        label=r"Brent's stopping floor $\sqrt{\epsilon}$",
    )
    ax.axvline(eps, color="grey", ls=":", lw=1, label=r"$\epsilon$")
    ax.set_xlabel(r"relative offset $\delta$ of $\pi_2(0) = \pi_2^*(1+\delta)$")
    ax.set_ylabel(r"$d$ or $|r|$ (dimensionless)")
    ax.set_title(f"{family_tex(L.label)}, $u = {L.u:.3g}$")
    ax.legend(fontsize="small")
    return fig


def work_precision(wps: Sequence[WorkPrecision], cost: str = "integration") -> Figure:
    """One panel per family: error ``|E - E_ref|`` against cost for both searches.

    ``cost='integration'``: total integration time in pendulum periods; ``'evaluations'``: count.
    """
    n = len(wps)
    fig, axes = plt.subplots(
        (n + 1) // 2 if n > 2 else 1,
        min(n, 2),
        figsize=(COLUMN_WIDTH, 3.0 * ((n + 1) // 2 if n > 2 else 1)),
        sharey=True,
        squeeze=False,
    )
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    axes = axes.ravel()[:n]
    for ax, w in zip(axes, wps):
        if cost == "integration":
            xp, xs, lab = (
                w.integration_paper,
                w.integration_shooting,
                r"integration time / $\tau_n$",
            )
        else:
            xp, xs, lab = (
                w.evaluations_paper,
                w.evaluations_shooting,
                "function evaluations",
            )
        floor = 1e-17
        ax.semilogy(
            xp,
            np.maximum(w.error_paper, floor),
            "o-",
            ms=4,
            label="paper (minimise $d$)",
        )
        ax.semilogy(
            xs,
            np.maximum(w.error_shooting, floor),
            "s-",
            ms=4,
            label="symmetric shooting (root)",
        )
        ax.set_xlabel(lab)
        ax.set_title(family_tex(w.label))
        ax.set_ylabel(r"$|E - E_\mathrm{ref}|$ (units of $g$)")
    axes[0].legend(fontsize="small")
    if n > 1:
        panel_letters(axes)
    fig.tight_layout()
    return fig


def amplitude_branch(
    branch: Branch,
    u_scan: ArrayLike | None = None,
    r_scan: ArrayLike | None = None,
    E_scan: float | None = None,
) -> Figure:
    """(a) ``E`` against the amplitude ``u`` along a family (a :class:`rotorlib.orbits.continuation.Branch`)
    with its fold; (b) ``r(u)`` at ``E_scan``."""
    ncols = 1 if u_scan is None else 2
    fig, axes = plt.subplots(
        1, ncols, figsize=(COLUMN_WIDTH, 3.6 if ncols > 1 else 4.0)
    )
    axes = np.atleast_1d(axes)
    ax = axes[0]
    ax.plot(
        branch.u,
        branch.E,
        ".-",
        ms=3,
        label=f"{family_tex(branch.label)} from its birth",
    )
    if branch.fold is not None:
        f = branch.fold
        ax.plot([float(f.u)], [float(f.E)], "r^", label=f"fold, $E = {float(f.E):.7f}$")
    ax.axhline(4.5, color="grey", ls=":", lw=1, label="$E = 4.5$ (maxima of $V$)")
    if E_scan is not None:
        ax.axhline(E_scan, color="C3", ls="--", lw=1, label=f"$E = {E_scan:g}$")
    ax.set_xlabel(r"amplitude $u$: $p_1(0)$ or $\alpha_1(0)$ (rad)")
    ax.set_ylabel(r"$E$ (units of $g$)")
    ax.legend(fontsize="small")
    if u_scan is not None:
        ax = axes[1]
        ax.plot(u_scan, r_scan, "-", lw=1)
        ax.axhline(0, color="grey", lw=0.5)
        ax.set_xlabel(r"amplitude $u$ (the whole energy shell)")
        ax.set_ylabel(f"residual $r(u)$ at $E = {E_scan:g}$")
        panel_letters(axes)
    fig.tight_layout()
    return fig
