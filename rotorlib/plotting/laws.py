"""Figures of the laws-of-the-cascade chapter (paper Figs. 7, 8, 9 and the duality plots). Units m = g = r = 1."""

from __future__ import annotations

import re

import matplotlib.pyplot as plt
import numpy as np


def _tex(label):
    """A family label in mathtext: 'PD^r_3' -> '$\\mathrm{PD}^r_{3}$'."""
    m = re.fullmatch(r"(IS|PD)\^([lrb])_?(\w*)", label)
    if not m:
        return label
    fam, sup, n = m.groups()
    sup = r"\ell" if sup == "l" else sup
    return rf"$\mathrm{{{fam}}}^{sup}_{{{n}}}$"


def fans(panels, figsize=(15, 4.3)):
    """Paper Fig. 7: three panels of tr M(E).

    ``panels``: list of dicts with ``title`` and ``curves``: list of ``(label, E, trace)``; optional
    ``extrap``: list of ``(label, E_line, trace_line)`` drawn dashed (backward linear extrapolation),
    and ``fan``: the fan value(s) marked at E = 4.
    """
    fig, axes = plt.subplots(1, len(panels), figsize=figsize)
    for ax, p in zip(np.ravel(axes), panels):
        for i, (lab, E, tr) in enumerate(p["curves"]):
            ax.plot(E, tr, "o-", ms=3, lw=1.2, color=f"C{i}", label=f"${lab}$")
        for i, (lab, E, tr) in enumerate(p.get("extrap", [])):
            ax.plot(E, tr, "--", lw=1.0, color=f"C{i}")
        for v in np.atleast_1d(p.get("fan", [])):
            ax.plot([4.0], [v], "k*", ms=10)
        ax.axvline(4.0, color="grey", lw=0.6)
        ax.set_xlabel(r"$E$ ($m = g = r = 1$)")
        ax.set_ylabel(r"$\mathrm{tr}\,M$")
        ax.set_title(p["title"], fontsize=10)
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def shapes_fig8(t6, a1_6, a2_6, a2_pend, t_r, a2_r, a2dot_r):
    """Paper Fig. 8: (a) a1(t) of IS^l_6 at E = 4; (b) a2(t) of IS^l_6 and of the pendulum at E(IS^l_6);
    (c) a2(t) and (d) a2'(t) of IS^r_1 near its birth."""
    fig, ax = plt.subplots(2, 2, figsize=(11, 7))
    ax[0, 0].plot(t6, a1_6)
    ax[0, 0].set_title(
        r"(a) $\alpha_1(t)$ of $\mathrm{IS}^\ell_6$ at $E = 4$", fontsize=10
    )
    ax[0, 0].set_ylabel(r"$\alpha_1$ (rad)")
    ax[0, 1].plot(t6, a2_6, "-", lw=2.5, label=r"$\mathrm{IS}^\ell_6$ at $E=4$")
    ax[0, 1].plot(
        t6, a2_pend, "--", color="k", label=r"pendulum at $E(\mathrm{IS}^\ell_6)$"
    )
    ax[0, 1].set_title(r"(b) $\alpha_2(t)$", fontsize=10)
    ax[0, 1].set_ylabel(r"$\alpha_2$ (rad)")
    ax[0, 1].legend(fontsize=8)
    ax[1, 0].plot(t_r, a2_r)
    ax[1, 0].set_title(
        r"(c) $\alpha_2(t)$ of $\mathrm{IS}^r_1$ near birth", fontsize=10
    )
    ax[1, 0].set_ylabel(r"$\alpha_2$ (rad)")
    ax[1, 1].plot(t_r, a2dot_r)
    ax[1, 1].set_title(r"(d) $\dot\alpha_2(t)$ of $\mathrm{IS}^r_1$", fontsize=10)
    ax[1, 1].set_ylabel(r"$\dot\alpha_2$ (rad per unit time)")
    for a in ax.ravel():
        a.set_xlabel(r"$t$ (units of $\sqrt{r/g}$)")
    fig.tight_layout()
    return fig


def self_similar(pairs, figsize=(11, 8)):
    """Paper Fig. 9: each pair ``(small, big)`` of dicts with ``label``, ``a1``, ``a2``, and the big one's
    ``alpha``, ``beta``; the left panel shows the small-n orbit near a2 = pi, the right the large-n orbit
    with a1 magnified by alpha and pi - a2 by beta (the small-n orbit dashed on top)."""
    fig, axes = plt.subplots(len(pairs), 2, figsize=figsize)
    letters = "abcd"
    for i, (lo, hi) in enumerate(pairs):
        a, b = axes[i]
        a.plot(lo["a2"], lo["a1"], color="C0")
        a.set_title(f"({letters[2 * i]}) ${lo['label']}$ at E = 4", fontsize=10)
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
            label=f"${hi['label']}$ magnified",
        )
        b.plot(
            np.where(far_lo, np.nan, np.abs(lo["a2"])),
            lo["a1"],
            "--",
            color="k",
            lw=1,
            label=f"${lo['label']}$",
        )
        b.set_xlim(
            np.pi - 1.5 * (np.pi - np.max(np.abs(lo["a2"]))) - 0.02, np.pi + 0.01
        )
        b.set_title(
            f"({letters[2 * i + 1]}) ${hi['label']}$: "
            + r"$\alpha_1 \times$"
            + f"{hi['alpha']:.2f}, "
            + r"$(\pi - \alpha_2) \times$"
            + f"{hi['beta']:.2f}",
            fontsize=10,
        )
        b.set_xlabel(
            r"$|\alpha_2|$ (dashed), $\pi - \beta(\pi - |\alpha_2|)$ (solid) (rad)"
        )
        b.set_ylabel(r"$\alpha \, \alpha_1$ (rad)")
        b.legend(fontsize=8)
    fig.tight_layout()
    return fig


def duality(ns, diffs, fit, lame, figsize=(12, 4)):
    """(a) log10 of log(4 - E(IS^l_n)) - log(E(dual) - 4) against n with the exponential fit;
    (b) periodic transverse solutions at IS^l_1 and IS^r_1 on the rescaled time."""
    fig, ax = plt.subplots(1, 2, figsize=figsize)
    ax[0].semilogy(ns, diffs, "o", label="measured")
    b, a = fit
    nn = np.asarray(ns, float)
    ax[0].semilogy(
        nn, np.exp(a - b * nn), "-", label=f"fit: $\\exp({a:.2f} - {b:.3f}\\,n)$"
    )
    ax[0].set_xlabel(r"$n$ (of $\mathrm{IS}^\ell_n$)")
    ax[0].set_ylabel(r"$\log(4 - E_\ell) - \log(E_r - 4)$")
    ax[0].legend(fontsize=8)
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
    ax[1].set_xlabel(r"$z / z_{\max}$ (one librational period, two rotational periods)")
    ax[1].set_ylabel(r"$\alpha_1 / \alpha_1(0)$")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    return fig


def rotational_reach(profiles, levels, figsize=(12, 4.2)):
    """Rotational newborn families followed in amplitude: (a) ``E - 4`` against the amplitude ``u``,
    (b) ``E - 4`` against the time ``t1`` from the start line to ``a2 = pi`` (half or quarter period).

    ``profiles``: list of :class:`rotorlib.continuation.Branch`; ``levels``: list of ``(label, E - 4)``
    drawn as horizontal lines (energies the definition of alpha^r needs, and E = 4.5).
    """
    fig, ax = plt.subplots(1, 2, figsize=figsize)
    for i, p in enumerate(profiles):
        ax[0].plot(p.u, p.dE, ".-", ms=3, color=f"C{i}", label=_tex(p.label))
        ax[1].plot(p.t1, p.dE, ".-", ms=3, color=f"C{i}", label=_tex(p.label))
    for j, (lab, v) in enumerate(levels):
        for a in ax:
            a.axhline(v, color="k", lw=0.8, ls=[":", "--", "-."][j % 3], label=lab)
    ax[0].set_xscale("log")
    ax[0].set_xlabel(
        r"amplitude $u$ ($\alpha_1(0)$ or $p_1(0)$; rad or rad per unit time)"
    )
    ax[1].set_xlabel(
        r"$t_1$: time from $\alpha_2 = 0$ to $\alpha_2 = \pi$ (units of $\sqrt{r/g}$)"
    )
    for a, t in zip(ax, ("(a)", "(b)")):
        a.set_ylabel(r"$E - 4$ ($g$, with $m = g = r = 1$)")
        a.set_title(t, fontsize=10)
        a.legend(fontsize=7)
    fig.tight_layout()
    return fig
