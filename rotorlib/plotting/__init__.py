"""Plotting helpers (matplotlib), one module per chapter; the numerical modules never
import this package.

Importing the package applies the book's one matplotlib style, ``rotorlib.mplstyle``
(shipped next to this file; :data:`STYLE`): figures sized for the book's 688 px text
column, drawn at 200 dpi (2x the pixels shown), text no smaller than the body's
footnotes at display size, STIX fonts matching the mathtext. :func:`use_style` applies
it again (after a notebook changed rcParams), :func:`panel_letters` labels the panels of
a multi-panel figure (a), (b), ..., :func:`family_tex` typesets a family label
(``IS^l_1`` -> :math:`\\mathrm{IS}^\\ell_1`) for a legend or a title.
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import matplotlib.pyplot as plt
import matplotlib.ticker
from matplotlib.axes import Axes
from matplotlib.axis import Axis

from ..core.compare import label_tex, typeset_labels

__all__ = [
    "COLUMN_WIDTH",
    "STYLE",
    "family_tex",
    "integer_ticks",
    "panel_letters",
    "use_style",
]

#: The style file of the book's figures.
STYLE = Path(__file__).with_name("rotorlib.mplstyle")
#: Width (inches) of a figure that spans the 688 px text column.
COLUMN_WIDTH = 6.88


def use_style() -> None:
    """Apply the book's matplotlib style (:data:`STYLE`) to the global rcParams.

    Examples
    --------
    >>> use_style()
    >>> import matplotlib as mpl
    >>> mpl.rcParams["savefig.dpi"]
    200.0
    """
    plt.style.use(STYLE)


def family_tex(label: str) -> str:
    r"""A label for a legend or title: family labels typeset as mathtext.

    ``'IS^l_1'`` -> ``'$\mathrm{IS}^\ell_{1}$'``; text with labels inside
    (``'IS^l_6 at E = 4'``) has them typeset; a string that already holds ``$`` is
    returned as is; other TeX-looking text (``\alpha_1``) is wrapped in ``$...$``.

    Examples
    --------
    >>> family_tex("PD^r_2")
    '$\\mathrm{PD}^r_{2}$'
    >>> family_tex("pendulum")
    'pendulum'
    """
    s = str(label)
    if "$" in s:
        return s
    try:
        return label_tex(s)
    except ValueError:
        pass
    typeset = typeset_labels(s)
    if typeset != s:
        return typeset
    if any(c in s for c in "\\^_"):
        return f"${s}$"
    return s


def panel_letters(axes: Iterable[Axes], start: int = 0) -> None:
    """Prefix each panel's title with (a), (b), ... (row by row); titles that already
    start with a panel letter are left as they are.

    Examples
    --------
    >>> fig, axes = plt.subplots(1, 2)
    >>> axes[0].set_title("libration")
    Text(...)
    >>> panel_letters(axes)
    >>> [a.get_title() for a in axes]
    ['(a) libration', '(b)']
    >>> plt.close(fig)
    """
    import re

    flat = list(getattr(axes, "flat", axes))
    for i, ax in enumerate(flat):
        title = ax.get_title()
        if re.match(r"^\([a-z]\)", title):
            continue
        letter = f"({chr(ord('a') + start + i)})"
        ax.set_title(f"{letter} {title}".strip())


def integer_ticks(axis: Axis) -> None:
    """Ticks only at integers (for count axes): ``integer_ticks(ax.yaxis)``."""
    axis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True, min_n_ticks=1))


use_style()
