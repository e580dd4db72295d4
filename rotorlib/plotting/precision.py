"""Figures and tables for the chapter "Speed against accuracy" (work-precision diagrams).

The numbers are measured by the caller (``benchmarks/bench_precision.py`` and the
chapter); these functions only draw them. Work-precision diagrams put the error on
the vertical axis and the time per evaluation on the horizontal one, both
logarithmic, with one curve per method (its points are the tolerance settings);
lower left is better. :func:`plot_digit_cost` draws the cost of one periodic orbit
against the digits requested.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure, SubFigure
from matplotlib.ticker import NullFormatter, ScalarFormatter

from . import COLUMN_WIDTH, family_tex, panel_letters

__all__ = [
    "plot_work_precision",
    "plot_locate",
    "plot_digit_cost",
    "cells",
    "table",
    "order_of_magnitude",
]

_STYLE = {
    "textbook scipy": dict(color="tab:red", marker="x", ls="-"),
    "textbook heyoka": dict(color="tab:pink", marker="X", ls="none", ms=9),
    "Hill reduction, scipy": dict(color="tab:orange", marker="s", ls="-"),
    "Hill reduction, heyoka float64": dict(color="tab:blue", marker="o", ls="-"),
    "Hill reduction, heyoka real128": dict(color="tab:green", marker="^", ls="-"),
    "Hill reduction, heyoka multiprecision": dict(
        color="tab:purple", marker="D", ls="-"
    ),
    "Hill reduction, mpmath": dict(color="tab:brown", marker="*", ls="none", ms=11),
}


def _sci(x: float) -> str:
    """``1e-11`` -> ``$10^{-11}$``, ``2.5e-07`` -> ``$2.5 \\times 10^{-7}$`` (mathtext)."""
    mant, _, ex = f"{x:.3g}".partition("e")
    if not ex:
        return f"${mant}$"
    power = f"10^{{{int(ex)}}}"
    return f"${power}$" if mant == "1" else f"${mant} \\times {power}$"


def _style(name):
    for key, st in _STYLE.items():
        if name.startswith(key):
            return st
    return dict(marker="o", ls="-")


def order_of_magnitude(x: float) -> int:
    """``floor(log10(x))`` (``x > 0``); used to state conclusions that do not depend on exact timings."""
    if not x > 0:
        raise ValueError(f"order_of_magnitude needs a positive number, got {x!r}")
    return int(math.floor(math.log10(x)))


def plot_work_precision(
    rows: Sequence[Mapping[str, Any]],
    ax: Axes | None = None,
    title: str | None = None,
    floor: float = 1e-70,
    xlabel: str | None = None,
    ylabel: str | None = None,
    target: float | None = 1e-11,
) -> Figure | SubFigure:
    """Error against time per energy (log-log), one curve per method.

    Parameters
    ----------
    rows : list of dict
        Rows of ``bench_precision.work_precision`` (keys ``method``, ``setting``,
        ``time`` in seconds, ``error``).
    ax : matplotlib Axes, optional
    title : str, optional
    floor : float
        Errors below it (an exact zero) are drawn at ``floor``.
    xlabel, ylabel : str, optional
        Axis labels (defaults: time per energy, error of tr M).
    target : float or None
        Draw a dotted line at this error (default 1e-11, the float64 target).

    Rows with a ``label`` key get that text written next to their point.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig: Figure | SubFigure  # ``ax.figure``: a subfigure when ``ax`` is in one
    if ax is None:
        fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 4.6))
    else:
        fig = ax.figure
    methods = list(dict.fromkeys(r["method"] for r in rows))
    for name in methods:
        pts = sorted(
            (r["time"], max(r["error"], floor))
            for r in rows
            if r["method"] == name and np.isfinite(r["error"])
        )
        if not pts:
            continue
        t, e = zip(*pts)
        ax.loglog(t, e, label=name, **_style(name))
    for r in rows:
        if r.get("label") and np.isfinite(r["error"]):
            ax.annotate(
                r["label"],
                (r["time"], max(r["error"], floor)),
                textcoords="offset points",
                xytext=(6, 4),
                fontsize="small",
            )
    ax.set_xlabel(xlabel or "time per energy (s), minimum over repeats")
    ax.set_ylabel(
        ylabel
        or r"error $|\mathrm{tr}\,M - \mathrm{tr}\,M_{\rm ref}|$ (max over energies)"
    )
    if target is not None:
        ax.axhline(target, color="0.5", lw=0.8, ls=":")
        ax.text(
            ax.get_xlim()[0] * 1.3,
            target * 2,
            f"target {_sci(target)}",
            color="0.4",
            fontsize="small",
        )
    ax.grid(True, which="major", alpha=0.3)
    if title:
        ax.set_title(title)
    ax.legend(fontsize="small", loc="best")
    return fig


def plot_locate(
    rows: Sequence[Mapping[str, Any]],
    ax: Axes | None = None,
    title: str | None = None,
    floor: float = 1e-70,
) -> Figure | SubFigure:
    """Error of a located transition (in ``log|E - 4|``) against the time to locate it, one point per tier.

    Methods that fail to bracket the root (``error`` is None) are listed in the legend as failed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig: Figure | SubFigure  # ``ax.figure``: a subfigure when ``ax`` is in one
    if ax is None:
        fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 4.2))
    else:
        fig = ax.figure
    markers = "osD^v*p"
    for i, r in enumerate(rows):
        if r["error"] is None:
            ax.plot(
                [],
                [],
                "x",
                color="tab:red",
                label=f"{r['method']}: no sign change (fails)",
            )
            continue
        ax.loglog(
            [r["time"]],
            [max(r["error"], floor)],
            markers[i % len(markers)],
            ms=8,
            label=f"{r['method']} ({r['evaluations']} evaluations)",
        )
    ax.set_xlabel("time to locate the transition (s)")
    ax.set_ylabel(r"error in $\log|E - 4|$")
    ax.grid(True, which="major", alpha=0.3)
    if title:
        ax.set_title(title)
    ax.legend(fontsize="small", loc="best")
    return fig


def _cell(r, c, formats):
    v = r.get(c)
    if v is None:
        return "-"
    if c in formats:
        return format(v, formats[c])
    return f"{v:.3g}" if isinstance(v, float) else str(v)


def cells(
    rows: Iterable[Mapping[str, Any]],
    columns: Sequence[str],
    formats: Mapping[str, str] | None = None,
) -> list:
    """``rows`` (dicts) as lists of strings in the order of ``columns`` (``formats`` maps a
    column to a format specification; None is shown as ``-``), for
    ``rotorlib.core.compare.markdown(cells(...), columns)``."""
    formats = formats or {}
    return [[_cell(r, c, formats) for c in columns] for r in rows]


def table(
    rows: Iterable[Mapping[str, Any]],
    columns: Sequence[str],
    formats: Mapping[str, str] | None = None,
) -> str:
    """A plain-text table of ``rows`` (dicts) with the given columns; ``formats`` maps a column to a format."""
    body = [list(columns)] + cells(rows, columns, formats)
    w = [max(len(row[j]) for row in body) for j in range(len(columns))]
    return "\n".join(
        "  ".join(x.ljust(w[j]) for j, x in enumerate(row)).rstrip() for row in body
    )


def plot_digit_cost(
    rows: Sequence[Mapping[str, Any]], title: str | None = None
) -> Figure:
    """Wall time and error of tr M of one periodic orbit against the digits requested.

    Parameters
    ----------
    rows : list of dict
        Keys ``orbit`` (label of the curve), ``digits``, ``tier`` (name of the precision
        tier used), ``time`` (seconds, wall time of one orbit with its tr M) and
        ``trace_err`` (relative error of tr M against a reference; None for the
        reference itself, which is not drawn in the right panel).
    title : str, optional

    The left panel is log-log (seconds against digits), the right one draws the error
    with ``10^-digits`` dotted.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax_t, ax_e) = plt.subplots(1, 2, figsize=(COLUMN_WIDTH, 3.6))
    markers = "os^Dv*p"
    for i, name in enumerate(dict.fromkeys(r["orbit"] for r in rows)):
        sel = sorted((r for r in rows if r["orbit"] == name), key=lambda r: r["digits"])
        st = dict(marker=markers[i % len(markers)], color=f"C{i}")
        ax_t.loglog(
            [r["digits"] for r in sel],
            [r["time"] for r in sel],
            label=family_tex(name),
            **st,
        )
        err = [r for r in sel if r.get("trace_err") is not None]
        ax_e.semilogy(
            [r["digits"] for r in err],
            [max(r["trace_err"], 1e-300) for r in err],
            label=family_tex(name),
            **st,
        )
        if i == 0:
            for r in sel:
                ax_t.annotate(
                    r["tier"],
                    (r["digits"], r["time"]),
                    textcoords="offset points",
                    xytext=(4, -10),
                    fontsize="small",
                    color="0.3",
                )
    d = sorted({r["digits"] for r in rows})
    ax_t.set_xticks(d)
    ax_t.xaxis.set_major_formatter(ScalarFormatter())
    ax_t.xaxis.set_minor_formatter(NullFormatter())
    d_err = sorted({r["digits"] for r in rows if r.get("trace_err") is not None})
    ax_e.semilogy(
        d_err, [10.0**-k for k in d_err], "k:", lw=0.8, label=r"$10^{-\mathrm{digits}}$"
    )
    ax_t.set_xlabel("significant digits requested")
    ax_t.set_ylabel(r"wall time of an orbit and $\mathrm{tr}\,M$ (s)")
    ax_e.set_xlabel("significant digits requested")
    ax_e.set_ylabel(r"rel. error of $\mathrm{tr}\,M$ (vs. 100 digits)")
    for ax in (ax_t, ax_e):
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize="small", loc="best")
    panel_letters([ax_t, ax_e])
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig
