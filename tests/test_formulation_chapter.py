"""Plotting and table helpers of the chapters on paper §2 and §4 (rotorlib.plotting.formulation)."""

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from rotorlib.core.system import critical_points, potential_phi  # noqa: E402
from rotorlib.plotting import formulation as fp  # noqa: E402


def _labelled(ax):
    return bool(ax.get_xlabel().strip()) and bool(ax.get_ylabel().strip())


def test_pendulum_and_breather_lines_lie_where_the_paper_says():
    # pendulum lines: V <= 4 with equality only at the saddle; breather lines: max V = 4.5 at T
    for (x, y), vmax in [(xy, 4.0) for xy in fp.pendulum_lines().values()] + [
        (xy, 4.5) for xy in fp.breather_lines(n=3 * 2**10 + 1).values()
    ]:
        ok = np.isfinite(x)
        assert np.all(
            (x[ok] >= 0) & (x[ok] < 2 * math.pi) & (y[ok] >= 0) & (y[ok] < 2 * math.pi)
        )
        v = potential_phi(x[ok], y[ok])
        assert abs(v.max() - vmax) < 1e-12
    # the breather line phi1 + 2 phi2 = 0 really satisfies its equation mod 2 pi
    x, y = list(fp.breather_lines().values())[1]
    ok = np.isfinite(x)
    r = np.mod(x[ok] + 2 * y[ok] + math.pi, 2 * math.pi) - math.pi
    assert np.max(np.abs(r)) < 1e-12


def test_fig1_has_two_labelled_panels_with_all_critical_points():
    fig = fp.plot_fig1(critical_points(), grid=61)
    try:
        axes = fig.get_axes()
        assert len(axes) == 2 and all(_labelled(ax) for ax in axes)
        for ax in axes:
            # typeset as mathtext ($T_{1}$): compare the plain names
            names = {
                t.get_text().translate(str.maketrans("", "", "${}_")) for t in ax.texts
            }
            assert {"G", "T1", "T2", "D1", "D2", "D3"} <= names
            assert len(ax.get_legend().get_texts()) == 3
    finally:
        plt.close(fig)


def test_other_figures_are_labelled():
    t = np.linspace(0, 1, 11)
    st = np.zeros((11, 4))
    figs = [
        fp.plot_separatrix_approach([("a", t, st)], period_marks=[("T", 0.5)]),
        fp.plot_textbook_error([1e-2, 1e-4, 1e-6], [1e-8, 1e-4, 1.0]),
        fp.plot_trace_vs_energy(
            np.linspace(0, 3.9, 5), np.ones(5), np.linspace(4.1, 9, 5), np.ones(5)
        ),
    ]
    try:
        for fig in figs:
            assert all(_labelled(ax) for ax in fig.get_axes())
    finally:
        for fig in figs:
            plt.close(fig)
