"""rotorlib.plotting: one style for the book, and every figure drawn in it.

Every public plotting function is called on small synthetic data and its figure is
checked: it fits the 688 px text column (width <= COLUMN_WIDTH inches, shown at 100 px
per inch) at 200 dpi; tick labels are >= 10 pt (~14 px on the page, the body's footnote
size) and no text is below 8.5 pt; every visible panel has both axis labels; a figure
with several panels letters them (a), (b), ...; no text shows a family label or an
inequality as plain text (``IS^l_1``, ``<=``, ``sqrt(``) outside mathtext.
"""

from __future__ import annotations

import re
from types import SimpleNamespace as NS

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.text import Text  # noqa: E402

import rotorlib.plotting as rp  # noqa: E402
from rotorlib.core.system import critical_points  # noqa: E402
from rotorlib.plotting import (  # noqa: E402
    atlas,
    breathers,
    cascade,
    chaos,
    formulation,
    laws,
    newborn,
    precision,
    search,
)

x = np.linspace(0.1, 1.0, 12)
st = np.zeros((12, 4))
orb = NS(period=5.0, stable=True, trace=1.5)
cf = NS(
    E=np.array([4.0, 5.0, 6.0]),
    fraction=np.array([0.2, 1.0, 0.5]),
    stderr=np.array([0.01, 0.0, 0.02]),
    threshold=0.05,
    N=100,
    T=200.0,
    ftles=[x, x, x],
)
fam = NS(
    E=x + 4,
    trace=x,
    dE=x - 0.5,
    label="IS^l_1",
    special_points=[NS(member=NS(E=4.5), E=4.5)],
)
tr = [NS(phase="lib", period=0.5, kind="IS", n=1, label="IS^l_1")]
shape = dict(label="IS^l_1", a1=x, a2=x, E=4.0)
pair = dict(label="IS^l_2", a1=x, a2=x + 2, alpha=230.0, beta=230.0)
branch = NS(u=x, E=x + 4, dE=x, t1=x, label="IS^r_3", trace=x, fold=None)
wp = NS(
    integration_paper=x,
    integration_shooting=x,
    error_paper=x,
    error_shooting=x,
    label="PD^l_1",
    evaluations_paper=x,
    evaluations_shooting=x,
)
sec = NS(E=5.45, phi2=[x], P2=[x])
check = NS(orbit=orb, test_phi2=x, test_P2=x, phi2=[0.5], P2=[0.1])
rows = [dict(method="Hill reduction, scipy", setting="a", time=0.1, error=1e-9)]

FIGURES = {
    "atlas.plot_sweep": lambda: atlas.plot_sweep(
        [NS(E=5.0, orbits=[orb], stable=[orb])], cf
    ),
    "atlas.plot_growth": lambda: atlas.plot_growth(x * 10, (1, 9), 0.5, 0.0),
    "atlas.plot_family_trace": lambda: atlas.plot_family_trace(fam, E_fold=4.6),
    "atlas.plot_islands": lambda: atlas.plot_islands(
        {5.0: sec, 5.5: sec}, {5.0: [check], 5.5: [check]}
    ),
    "atlas.plot_cascade": lambda: atlas.plot_cascade(
        NS(births=[4.1, 4.2], families=[fam, fam, fam], periods=[5.0, 10.0])
    ),
    "cascade.plot_fig2": lambda: cascade.plot_fig2({"lib": (x, x), "rot": (x, x)}, tr),
    "cascade.plot_fig3": lambda: cascade.plot_fig3(
        [
            dict(dE=x, trace=x, title=f"({c}) IS^l_1", marks=[(0.5, 4, "IS^l_1")])
            for c in "abcde"
        ]
    ),
    "chaos.plot_band_traces": lambda: chaos.plot_band_traces({"PD^l_1": (x + 4, x)}),
    "chaos.plot_sections": lambda: chaos.plot_sections([sec, sec, sec, sec]),
    "chaos.plot_fraction": lambda: chaos.plot_fraction(cf),
    "chaos.plot_ftle_histograms": lambda: chaos.plot_ftle_histograms(cf, [4.0, 5.0]),
    "chaos.plot_rotational_branches": lambda: chaos.plot_rotational_branches([branch]),
    "laws.fans": lambda: laws.fans(
        [dict(title="IS^l odd", curves=[("IS^l_1", x + 3, x)], fan=[1.5])] * 3
    ),
    "laws.shapes_fig8": lambda: laws.shapes_fig8(x, x, x, x, x, x, x),
    "laws.self_similar": lambda: laws.self_similar([(pair, pair), (pair, pair)]),
    "laws.duality": lambda: laws.duality(
        [1, 2, 3], [1.0, 0.1, 0.01], (2.3, 0.0), dict(w=x, lib=x, rot=x)
    ),
    "laws.rotational_reach": lambda: laws.rotational_reach(
        [branch], [("E(IS^r_1)", 0.5)]
    ),
    "newborn.shapes": lambda: newborn.shapes([shape] * 8),
    "newborn.trace_vs_period": lambda: newborn.trace_vs_period(
        (x, x), {"IS^l_1": (x, x)}
    ),
    "precision.plot_work_precision": lambda: precision.plot_work_precision(rows),
    "precision.plot_locate": lambda: precision.plot_locate(
        [dict(method="Brent", error=1e-12, time=0.1, evaluations=9)]
    ),
    "precision.plot_digit_cost": lambda: precision.plot_digit_cost(
        [
            dict(orbit="ISl1", digits=d, tier="float64", time=0.1 * d, trace_err=1e-10)
            for d in (15, 30)
        ]
    ),
    "search.landscape": lambda: search.landscape(
        NS(delta=x, defect=x, residual=x, label="IS^l_2", u=0.1)
    ),
    "search.work_precision": lambda: search.work_precision([wp, wp, wp]),
    "search.amplitude_branch": lambda: search.amplitude_branch(
        branch, u_scan=x, r_scan=x, E_scan=4.3
    ),
    "breathers.plot_fig10ab": lambda: breathers.plot_fig10ab(
        x, x + 4, x, x + 4, x + 5, x, 8.97
    ),
    "breathers.plot_fig10c": lambda: breathers.plot_fig10c(x + 8, x, x, 8.97),
    "breathers.plot_fig10d": lambda: breathers.plot_fig10d(
        {"E = 8.9": np.c_[x, x, x, x]}
    ),
    "formulation.plot_fig1": lambda: formulation.plot_fig1(critical_points(), grid=41),
    "formulation.plot_separatrix_approach": lambda: (
        formulation.plot_separatrix_approach([("E = 3.9", x, st)])
    ),
    "formulation.plot_textbook_error": lambda: formulation.plot_textbook_error(
        [1e-2, 1e-4], [1e-8, 1e-4]
    ),
    "formulation.plot_trace_vs_energy": lambda: formulation.plot_trace_vs_energy(
        x, x, x + 4, x
    ),
}

PLAIN = re.compile(r"\b(IS|PD)\^|\b(IS|PD)[lr]\d|<=|>=|sqrt\(|\bT_max\b")


def _outside_math(s: str) -> str:
    return re.sub(r"\$[^$]*\$", "", s)


def test_style_is_applied_on_import():
    rc = matplotlib.rcParams
    assert rp.STYLE.is_file()
    assert float(rc["savefig.dpi"]) == 200.0
    assert rc["figure.figsize"][0] == pytest.approx(rp.COLUMN_WIDTH)
    assert (
        matplotlib.font_manager.FontProperties(
            size=rc["xtick.labelsize"]
        ).get_size_in_points()
        >= 10
    )


@pytest.mark.parametrize("name", sorted(FIGURES))
def test_figure_in_the_book_style(name):
    fig = FIGURES[name]()
    try:
        fig.set_dpi(50)  # sizes are in points: a coarse draw is enough, and fast
        fig.canvas.draw()
        problems = []
        w, h = fig.get_size_inches()
        if w > rp.COLUMN_WIDTH + 1e-9:
            problems.append(f"{w:.2f} in wide > {rp.COLUMN_WIDTH} in (688 px column)")
        axes = [a for a in fig.get_axes() if a.axison and a.get_visible()]
        main = [
            a
            for a in axes
            if not any(
                a is not b and a.bbox.bounds == b.bbox.bounds
                for b in axes[: axes.index(a)]
            )
        ]
        for a in main:
            if not a.get_xlabel().strip() or not (
                a.get_ylabel().strip() or a.get_shared_y_axes().get_siblings(a)[1:]
            ):
                problems.append(f"panel {a.get_title()!r} lacks an axis label")
            for t in a.get_xticklabels() + a.get_yticklabels():
                if t.get_text() and t.get_visible() and t.get_fontsize() < 10:
                    problems.append(
                        f"tick label {t.get_text()!r} {t.get_fontsize()} pt"
                    )
                    break
        if len(main) > 1:
            titles = [a.get_title() for a in main]
            if not all(re.match(r"^\([a-z]\)", t) for t in titles):
                problems.append(f"panels not lettered: {titles}")
        for t in fig.findobj(Text):
            s = t.get_text()
            if not s or not t.get_visible():
                continue
            if t.get_fontsize() < 8.5:
                problems.append(f"text {s!r} at {t.get_fontsize():.1f} pt < 8.5 pt")
            m = PLAIN.search(_outside_math(s))
            if m:
                problems.append(f"plain-text notation {m.group(0)!r} in {s!r}")
        assert not problems, f"{name}: " + "; ".join(sorted(set(problems)))
    finally:
        plt.close(fig)


@pytest.mark.parametrize(
    "label, tex",
    [
        ("IS^l_6", r"$\mathrm{IS}^\ell_{6}$"),
        ("IS^l_6 at E = 4", None),
        ("pendulum", None),
    ],
)
def test_family_tex(label, tex):
    out = rp.family_tex(label)
    if tex:
        assert out == tex
    assert not PLAIN.search(_outside_math(out))


@pytest.mark.parametrize(
    "name, axis_index", [("atlas.plot_sweep", 1), ("chaos.plot_ftle_histograms", 0)]
)
def test_count_axes_have_integer_ticks(name, axis_index):
    fig = FIGURES[name]()
    try:
        fig.canvas.draw()
        ax = fig.axes[axis_index]
        lo, hi = ax.get_ylim()
        ticks = [t for t in ax.get_yticks() if lo <= t <= hi]
        assert ticks and all(float(t).is_integer() for t in ticks), ticks
    finally:
        plt.close(fig)
