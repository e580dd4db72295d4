"""Figures of the newborn-orbit chapters (paper Fig. 4, 5, 6). Units m = g = r = 1."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure, SubFigure
from numpy.typing import ArrayLike

from . import COLUMN_WIDTH, family_tex


def shapes(
    panels: Sequence[Mapping[str, Any]], title: str | None = None, ncols: int = 2
) -> Figure:
    """Eight panels of orbits in the (a2, a1) plane.

    ``panels``: list of dicts with keys ``label``, ``a1``, ``a2`` (arrays) and
    optionally ``lin_a1``, ``lin_a2`` (the linearised Lamé orbit, drawn solid
    with the nonlinear one dashed on top).
    """
    n = len(panels)
    nrows = int(np.ceil(n / ncols))
    fig, axes = plt.subplots(
        nrows, ncols, figsize=(COLUMN_WIDTH, 2.4 * nrows * 2 / ncols), squeeze=False
    )
    for ax, p in zip(np.ravel(axes), panels):
        if "lin_a1" in p:
            ax.plot(
                p["lin_a2"],
                p["lin_a1"],
                "-",
                color="C1",
                lw=2.5,
                label="linearised (Lamé)",
            )
            ax.plot(p["a2"], p["a1"], "--", color="k", lw=1.0, label="nonlinear search")
            ax.legend(fontsize="small", loc="upper right")
        else:
            ax.plot(p["a2"], p["a1"], "-", color="C0", lw=1.2)
        letter = f"({chr(ord('a') + list(panels).index(p))}) "
        ax.set_title(
            letter
            + family_tex(p["label"])
            + (f" ($E = {p['E']:.6g}$)" if "E" in p else "")
        )
        ax.set_xlabel(r"$\alpha_2$ (rad)")
        ax.set_ylabel(r"$\alpha_1$ (rad)")
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 2))
    for ax in np.ravel(axes)[n:]:
        ax.set_visible(False)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig


def trace_vs_period(
    pendulum_curves: tuple[ArrayLike, ArrayLike],
    families: Mapping[str, tuple[ArrayLike, ArrayLike]],
    ax: Axes | None = None,
    title: str | None = None,
    ylim: tuple[float, float] = (-4, 12),
) -> Figure | SubFigure:
    """tr M vs period: pendula (``(tau, trM)`` arrays, solid black) and families (``label -> (tau, trM)``)."""
    fig: Figure | SubFigure  # ``ax.figure``: a subfigure when ``ax`` is in one
    if ax is None:
        fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 4.2))
    else:
        fig = ax.figure
    tau, tr = pendulum_curves
    ax.plot(tau, tr, "k-", lw=1.2, label="pendulum")
    for i, (lab, (t, y)) in enumerate(families.items()):
        ax.plot(
            t,
            y,
            "os^"[(i // 10) % 3] + "-",
            ms=2.5,
            lw=1.0,
            color=f"C{i % 10}",
            label=family_tex(lab),
        )
    ax.axhline(0, color="grey", lw=0.5)
    ax.axhline(4, color="grey", lw=0.5)
    ax.set_ylim(*ylim)
    ax.set_xlabel(r"period $\tau$ (units of $\sqrt{m r^2/g}$)")
    ax.set_ylabel(r"$\mathrm{tr}\,M$")
    ax.legend(fontsize="small", ncol=2)
    if title:
        ax.set_title(title)
    return fig
