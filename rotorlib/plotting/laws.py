"""Figures of the laws-of-the-cascade chapter (paper Figs. 7, 8, 9 and the duality plots). Units m = g = r = 1."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from . import COLUMN_WIDTH, family_tex, panel_letters

if TYPE_CHECKING:
    from ..orbits.family import Branch


def _grid(n, row_height, figsize=None):
    """``n`` panels, two per row, across the text column (or ``figsize``)."""
    ncols = min(2, n)
    nrows = (n + ncols - 1) // ncols
    fig, axes = plt.subplots(
        nrows,
        ncols,
        figsize=figsize or (COLUMN_WIDTH, row_height * nrows),
        squeeze=False,
    )
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    return fig, axes.ravel()[:n]


def fans(
    panels: Sequence[Mapping[str, Any]], figsize: tuple[float, float] | None = None
) -> Figure:
    """Paper Fig. 7: three panels of tr M(E).

    ``panels``: list of dicts with ``title`` and ``curves``: list of ``(label, E, trace)``; optional
    ``extrap``: list of ``(label, E_line, trace_line)`` drawn dashed (backward linear extrapolation),
    and ``fan``: the fan value(s) marked at E = 4.
    """
    fig, axes = _grid(len(panels), 3.2, figsize)
    for ax, p in zip(axes, panels):
        for i, (lab, E, tr) in enumerate(p["curves"]):
            ax.plot(E, tr, "o-", ms=3, lw=1.2, color=f"C{i}", label=family_tex(lab))
        for i, (lab, E, tr) in enumerate(p.get("extrap", [])):
            ax.plot(E, tr, "--", lw=1.0, color=f"C{i}")
        for v in np.atleast_1d(p.get("fan", [])):
            ax.plot([4.0], [v], "k*", ms=10)
        ax.axvline(4.0, color="grey", lw=0.6)
        ax.set_xlabel(r"$E$ (units of $g$)")
        ax.set_ylabel(r"$\mathrm{tr}\,M$")
        ax.set_title(family_tex(p["title"]))
        ax.legend(fontsize="small")
    panel_letters(axes)
    fig.tight_layout()
    return fig


def shapes_fig8(
    t6: ArrayLike,
    a1_6: ArrayLike,
    a2_6: ArrayLike,
    a2_pend: ArrayLike,
    t_r: ArrayLike,
    a2_r: ArrayLike,
    a2dot_r: ArrayLike,
) -> Figure:
    """Paper Fig. 8: (a) a1(t) of IS^l_6 at E = 4; (b) a2(t) of IS^l_6 and of the pendulum at E(IS^l_6);
    (c) a2(t) and (d) a2'(t) of IS^r_1 near its birth."""
    fig, ax = plt.subplots(2, 2, figsize=(COLUMN_WIDTH, 5.4))
    is6, isr1 = family_tex("IS^l_6"), family_tex("IS^r_1")
    ax[0, 0].plot(t6, a1_6)
    ax[0, 0].set_title(rf"(a) $\alpha_1(t)$ of {is6} at $E = 4$")
    ax[0, 0].set_ylabel(r"$\alpha_1$ (rad)")
    ax[0, 1].plot(t6, a2_6, "-", lw=2.5, label=rf"{is6} at $E=4$")
    ax[0, 1].plot(
        t6, a2_pend, "--", color="k", label=r"pendulum at $E(\mathrm{IS}^\ell_{6})$"
    )
    ax[0, 1].set_title(r"(b) $\alpha_2(t)$")
    ax[0, 1].set_ylabel(r"$\alpha_2$ (rad)")
    ax[0, 1].legend(fontsize="small")
    ax[1, 0].plot(t_r, a2_r)
    ax[1, 0].set_title(rf"(c) $\alpha_2(t)$ of {isr1} near birth")
    ax[1, 0].set_ylabel(r"$\alpha_2$ (rad)")
    ax[1, 1].plot(t_r, a2dot_r)
    ax[1, 1].set_title(rf"(d) $\dot\alpha_2(t)$ of {isr1}")
    ax[1, 1].set_ylabel(r"$\dot\alpha_2$ (units of $\sqrt{g/m r^2}$)")
    for a in ax.ravel():
        a.set_xlabel(r"$t$ (units of $\sqrt{m r^2/g}$)")
    fig.tight_layout()
    return fig


def self_similar(
    pairs: Sequence[tuple[Mapping[str, Any], Mapping[str, Any]]],
    figsize: tuple[float, float] | None = None,
) -> Figure:
    """Paper Fig. 9: each pair ``(small, big)`` of dicts with ``label``, ``a1``, ``a2``, and the big one's
    ``alpha``, ``beta``; the left panel shows the small-n orbit near a2 = pi, the right the large-n orbit
    with a1 magnified by alpha and pi - a2 by beta (the small-n orbit dashed on top)."""
    fig, axes = plt.subplots(
        len(pairs),
        2,
        figsize=figsize or (COLUMN_WIDTH, 3.1 * len(pairs)),
        squeeze=False,
    )
    letters = "abcd"
    for i, (lo, hi) in enumerate(pairs):
        a, b = axes[i]
        a.plot(lo["a2"], lo["a1"], color="C0")
        a.set_title(f"({letters[2 * i]}) {family_tex(lo['label'])} at $E = 4$")
        a.set_xlabel(r"$\alpha_2$ (rad)")
        a.set_ylabel(r"$\alpha_1$ (rad)")
        far_hi = (
            np.abs(hi["a2"]) < np.pi / 2
        )  # fold a2 -> |a2| and keep the visits near +-pi
        far_lo = np.abs(lo["a2"]) < np.pi / 2
        x = np.where(far_hi, np.nan, np.pi - hi["beta"] * (np.pi - np.abs(hi["a2"])))
        b.plot(
            x,
            hi["alpha"] * hi["a1"],
            color="C1",
            lw=2.5,
            label=f"{family_tex(hi['label'])} magnified",
        )
        b.plot(
            np.where(far_lo, np.nan, np.abs(lo["a2"])),
            lo["a1"],
            "--",
            color="k",
            lw=1,
            label=family_tex(lo["label"]),
        )
        b.set_xlim(
            np.pi - 1.5 * (np.pi - np.max(np.abs(lo["a2"]))) - 0.02, np.pi + 0.01
        )
        b.set_title(
            f"({letters[2 * i + 1]}) {family_tex(hi['label'])}: "
            + r"$\alpha_1 \times$"
            + f"{hi['alpha']:.2f}, "
            + r"$(\pi - \alpha_2) \times$"
            + f"{hi['beta']:.2f}",
        )
        b.set_xlabel(r"$|\alpha_2|$ or $\pi - \beta(\pi - |\alpha_2|)$ (rad)")
        b.set_ylabel(r"$\alpha_1$ or $\alpha \, \alpha_1$ (rad)")
        b.legend(fontsize="small")
    fig.tight_layout()
    return fig


def duality(
    ns: ArrayLike,
    diffs: ArrayLike,
    fit: tuple[float, float],
    lame: Mapping[str, ArrayLike],
    figsize: tuple[float, float] | None = None,
) -> Figure:
    """(a) log10 of log(4 - E(IS^l_n)) - log(E(dual) - 4) against n with the exponential fit;
    (b) periodic transverse solutions at IS^l_1 and IS^r_1 on the rescaled time."""
    fig, ax = plt.subplots(1, 2, figsize=figsize or (COLUMN_WIDTH, 3.3))
    ax[0].semilogy(ns, diffs, "o", label="measured")
    b, a = fit
    nn = np.asarray(ns, float)
    ax[0].semilogy(
        nn, np.exp(a - b * nn), "-", label=rf"fit: $e^{{{a:.2f} - {b:.3f}\,n}}$"
    )
    ax[0].set_xlabel(r"$n$ (of $\mathrm{IS}^\ell_n$)")
    ax[0].set_ylabel(r"$\log(4 - E_\ell) - \log(E_r - 4)$")
    ax[0].xaxis.set_major_locator(plt.MaxNLocator(integer=True))
    ax[0].legend(fontsize="small")
    ax[1].plot(
        lame["w"],
        lame["lib"],
        lw=2.5,
        label=r"$\mathrm{IS}^\ell_1$: $\alpha_1(z)$, $z = \sqrt{3}\,t$",
    )
    ax[1].plot(
        lame["w"],
        lame["rot"],
        "--",
        color="k",
        label=r"$\mathrm{IS}^r_1$: $\alpha_1(z)$, $z = \sqrt{3}\,k_r t$",
    )
    ax[1].set_xlabel(r"$z / z_{\max}$")
    ax[1].set_ylabel(r"$\alpha_1 / \alpha_1(0)$")
    ax[1].legend(fontsize="small")
    panel_letters(ax)
    fig.tight_layout()
    return fig


def rotational_reach(
    profiles: Sequence[Branch],
    levels: Sequence[tuple[str, float]],
    figsize: tuple[float, float] | None = None,
) -> Figure:
    """Rotational newborn families followed in amplitude: (a) ``E - 4`` against the amplitude ``u``,
    (b) ``E - 4`` against the time ``t1`` from the start line to ``a2 = pi`` (half or quarter period).

    ``profiles``: list of :class:`rotorlib.orbits.continuation.Branch`; ``levels``: list of ``(label, E - 4)``
    drawn as horizontal lines (energies the definition of alpha^r needs, and E = 4.5).
    """
    fig, ax = plt.subplots(1, 2, figsize=figsize or (COLUMN_WIDTH, 3.6), sharey=True)
    for i, p in enumerate(profiles):
        lab = family_tex(p.label)
        ax[0].plot(p.u, p.dE, ".-", ms=3, color=f"C{i}", label=lab)
        ax[1].plot(p.t1, p.dE, ".-", ms=3, color=f"C{i}", label=lab)
    for j, (lab, v) in enumerate(levels):
        for a in ax:
            a.axhline(
                v, color="k", lw=0.8, ls=[":", "--", "-."][j % 3], label=family_tex(lab)
            )
    ax[0].set_xscale("log")
    ax[0].set_xlabel(r"amplitude $u$: $\alpha_1(0)$ (rad) or $p_1(0)$")
    ax[1].set_xlabel(r"$t_1$, $\alpha_2 = 0 \to \pi$ (units of $\sqrt{m r^2/g}$)")
    ax[0].set_ylabel(r"$E - 4$ (units of $g$)")
    for a, t in zip(ax, ("(a)", "(b)")):
        a.set_title(t)
        a.legend(fontsize="small")
    fig.tight_layout()
    return fig
