"""Our numbers against the paper's: one record per claim, one rule, one table.

A :class:`Claim` holds the paper's value as printed, ours, the tolerance and the
verdict. The tolerance comes from the printing:

* a value printed plainly (``'230.76'``, ``'2.8611e-11'``) claims its digits: ours must
  round to it (tolerance half a unit in its last digit). If it does not, the cause is
  classified: ``truncated`` (ours truncated, not rounded), ``last digit off by k``
  (``|k| <= 3``: lower working precision), ``typo`` (two adjacent digits transposed, or
  one wrong digit with the rest correct to one unit in the last), or ``DIFFERS``;
* a value the paper marks ``≈`` (``rel=``) or states with an explicit tolerance
  (``tol=``) agrees when ``|paper - ours| <= tol``.

The ledger groups the verdicts in four classes (:attr:`Claim.status`): ``reproduced``,
``not correctly rounded`` (truncated or last digit off), ``wrong`` (typo or differs) and
``not evaluable`` (``ours`` is ``None``). :func:`check` is the same rule for our own
numbers against an independent computation.

What the disagreement *means* is the claim's ``category`` (one of
``CATEGORIES``), shown by the book's ledger: ``reproduced``, ``misrounded`` (the paper's
last digit is off by ``k`` units, or ours truncated), ``typo`` (a transcription typo),
``error`` (an error in the paper), ``inherited`` (a consequence of an earlier wrong
number, named in ``inherits``), ``definition`` (the value depends on a definition, stated
in ``cause``), ``inequality`` (the paper states a bound, ``≲`` or ``≳``, and it holds),
``not evaluable`` and ``answer`` (the paper asks, the book answers: our number set beside
the paper's quoted value, with the paper's printed digits as the tolerance, never
scored as reproduced; its status is ``answer to an open question``). By default it is
derived from the verdict (``agrees`` -> reproduced,
``truncated``/``last digit off`` -> misrounded, ``typo`` -> typo, ``DIFFERS`` -> error);
a chapter that knows better passes ``category=`` and ``cause=`` to :func:`claim`.

Family labels (``IS^l_1``, ``ISl1``, ``PD^r_{12}``, ``PDb``) are typeset by
:func:`label_tex` (LaTeX that is also valid matplotlib mathtext) and, inside running
text, by :func:`typeset_labels`.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import asdict, dataclass
from decimal import ROUND_DOWN, ROUND_HALF_EVEN, Decimal
from typing import Any

from .rounding import bound, glue, rounded, sig

__all__ = [
    "CATEGORIES",
    "Claim",
    "STATUSES",
    "category_of_verdict",
    "check",
    "claim",
    "label_tex",
    "LABEL_IN_TEXT_RE",
    "markdown",
    "records",
    "typeset_labels",
    "rounded",
    "sig",
    "bound",
    "glue",
]

STATUSES = (
    "reproduced",
    "not correctly rounded",
    "wrong",
    "not evaluable",
    "answer to an open question",
)

#: The ledger's categories: key -> what a reader is told (in this order).
CATEGORIES = {
    "reproduced": "reproduced",
    "misrounded": "misrounded in the paper",
    "typo": "transcription typo",
    "error": "error in the paper",
    "inherited": "inherited from an earlier claim",
    "definition": "depends on a definition",
    "inequality": "inequality holds",
    "not evaluable": "not evaluable",
    "answer": "answer to an open question",
}


def category_of_verdict(verdict: str) -> str:
    """The default category of a verdict (``agrees`` -> ``reproduced``, ...).

    Examples
    --------
    >>> category_of_verdict("last digit off by +1")
    'misrounded'
    """
    if verdict.startswith("last digit"):
        return "misrounded"
    return _CATEGORY_OF_VERDICT.get(verdict, "error")


_CATEGORY_OF_VERDICT = {
    "agrees": "reproduced",
    "holds": "inequality",
    "not evaluable": "not evaluable",
    "truncated": "misrounded",
    "typo": "typo",
}
#: The ledger class (``STATUSES``) of each category; the rest are ``wrong``.
_STATUS_OF_CATEGORY = {
    "reproduced": "reproduced",
    "inequality": "reproduced",
    "not evaluable": "not evaluable",
    "misrounded": "not correctly rounded",
    "answer": "answer to an open question",
}


@dataclass(frozen=True)
class Claim:
    """One quantitative claim of the paper, checked.

    Attributes
    ----------
    section : str
        Where the paper makes it (``§5``, ``Table I``, ``Fig. 10``).
    quantity : str
    paper : str
        As printed (``≈`` claims carry ``approx``).
    ours : str
        Our value, shown to the digits compared (``-`` when not evaluable).
    difference : float
        ``paper - ours``.
    tolerance : float
    verdict : str
        ``agrees``, ``truncated``, ``last digit off by k``, ``typo``, ``DIFFERS`` or
        ``not evaluable``.
    cause : str
    approx : bool
        The paper states it as approximate.
    note : str
    category : str
        What the disagreement means: a key of ``CATEGORIES``. Derived from ``verdict``
        when not given (:func:`category_of_verdict`).
    inherits : str
        For ``category='inherited'``: the earlier claim the value follows from (as the
        ledger names it, e.g. ``'Table I, PD^l_5: tau'``).
    rule : str
        The meaning of ``tolerance``: ``'digits'`` (half a unit in the last printed
        digit), ``'rel'`` (the paper's ``≈``, relative), ``'abs'`` (a stated absolute
        tolerance) or ``'bound'`` (an inequality, with that much slack).
    anchor : str
        The heading anchor of the chapter section that computes it (the ledger links
        there; default: found by ``scripts/make_ledger.py``).
    """

    section: str
    quantity: str
    paper: str
    ours: str
    difference: float
    tolerance: float
    verdict: str
    cause: str
    approx: bool = False
    note: str = ""
    category: str = ""
    inherits: str = ""
    rule: str = ""
    anchor: str = ""

    def __post_init__(self):
        if not self.category:
            object.__setattr__(self, "category", category_of_verdict(self.verdict))
        if self.category not in CATEGORIES:
            raise ValueError(
                f"unknown category {self.category!r}: one of {', '.join(CATEGORIES)}"
            )
        if not self.rule:
            object.__setattr__(self, "rule", "rel" if self.approx else "digits")

    @property
    def status(self) -> str:
        """The ledger class: one of ``STATUSES`` (from the verdict's own category; an
        answer to one of the paper's open questions is a class of its own)."""
        return _STATUS_OF_CATEGORY.get(
            "answer"
            if self.category == "answer"
            else category_of_verdict(self.verdict),
            "wrong",
        )


def _decimals(text: str) -> int:
    mant, _, ex = text.strip().lower().partition("e")
    d = len(mant.split(".")[1]) if "." in mant else 0
    return d - int(ex or 0)


def _dec(v) -> Decimal:
    import mpmath as mp

    if isinstance(v, mp.mpf):
        return Decimal(mp.nstr(v, 40, strip_zeros=False))
    return Decimal(str(v))


def _rounded(paper: str, ours):
    """Verdict and cause of a plainly printed value (see the module docstring)."""
    d = _decimals(paper)
    q = Decimal(1).scaleb(-d)
    p, o = Decimal(paper.strip()), _dec(ours)
    o_r, o_t = (
        o.quantize(q, rounding=ROUND_HALF_EVEN),
        o.quantize(q, rounding=ROUND_DOWN),
    )
    k = int((p - o_r) / q)

    def digits(x):
        return format(abs(x), f".{d}f").replace(".", "") if d >= 0 else str(abs(x))

    a, b = digits(p), digits(o_r)
    same = len(a) == len(b) and (p < 0) == (o_r < 0)
    diffs = [i for i, (x, y) in enumerate(zip(a, b)) if x != y] if same else []
    if p == o_r:
        v, cause = "agrees", "correctly rounded"
    elif p == o_t:
        v, cause = "truncated", "the paper's value is ours truncated, not rounded"
    elif abs(k) <= 3:
        v, cause = (
            f"last digit off by {k:+d}",
            "lower working precision (or an inaccurate input)",
        )
    elif len(diffs) == 2 and diffs[1] == diffs[0] + 1 and sorted(a) == sorted(b):
        v, cause = "typo", "two adjacent digits transposed"
    else:
        v, cause = "DIFFERS", "not explained by rounding or a single typo"
        # one wrong digit (not the last), maybe with the last off a unit
        for i in [i for i in diffs if i != len(a) - 1]:
            k2 = int(
                (Decimal(a[:i] + b[i] + a[i + 1 :]) * q * (-1 if p < 0 else 1) - o_r)
                / q
            )
            if abs(k2) <= 1:
                v = "typo"
                cause = f"digit {a[i]} printed for {b[i]}" + (
                    f", and last digit off by {k2:+d}" if k2 else ""
                )
                break
    if "e" in paper.lower():
        mant = len(paper.lower().split("e")[0].replace("-", "").replace(".", "")) - 1
        shown = f"{float(o_r):.{mant}e}"
    else:
        shown = str(o_r)
    return v, cause, shown, float(q) / 2


def claim(
    quantity: Any,
    paper: str,
    ours: Any,
    *,
    section: Any = "",
    rel: Any = None,
    tol: Any = None,
    note: Any = "",
    shown: Any = None,
    category: Any = None,
    cause: Any = None,
    inherits: Any = "",
    inequality: Any = None,
    anchor: Any = "",
) -> Claim:
    """Check one printed value ``paper`` (a string, as printed) against ``ours``.

    Parameters
    ----------
    quantity : str
        What is compared (family labels as ``IS^l_1``; the ledger typesets them).
    paper : str
        The paper's value as printed.
    ours : float, mpmath.mpf, Decimal or None
        Our value; ``None``: not evaluable.
    section : str
        Where the paper states it (``§5``, ``Table I``).
    rel, tol : float, optional
        The paper's ``≈``: tolerance ``rel |paper|``, or an absolute ``tol``; without
        either the printed digits are the claim (tolerance half a unit in the last).
    note : str
    shown : str, optional
        How ours is displayed (default: rounded to the tolerance's digits).
    category : str, optional
        What the result means, a key of ``CATEGORIES`` (default: derived from the
        verdict). ``'typo'``, ``'inherited'`` and ``'definition'`` need a ``cause``
        (or, for ``'inherited'``, ``inherits``).
    cause : str, optional
        The cause shown in the ledger's row (default: the rule's own explanation).
    inherits : str
        The earlier claim an ``'inherited'`` value follows from.
    inequality : {'<=', '>='}, optional
        The paper states a bound: ``ours <= paper`` or ``ours >= paper`` (``≲``,
        ``≳``), with ``rel``/``tol`` as slack. The verdict is ``holds`` (category
        ``'inequality'``) or ``fails`` (``'error'``).
    anchor : str
        The heading anchor of the section that computes the value, for the ledger's
        link (when the claim is recorded away from it, e.g. in a closing cell).

    Returns
    -------
    Claim

    Raises
    ------
    ValueError
        An unknown ``category`` or ``inequality``, or ``'inherited'`` without what it
        inherits from.

    Examples
    --------
    >>> claim("tau", "7.6341", 7.63404).verdict
    'last digit off by +1'
    >>> claim("tau", "7.6341", 7.63404).category
    'misrounded'
    >>> claim("E of the first instability", "3.9", 3.93, inequality=">=").category
    'inequality'
    """
    paper = str(paper).strip()  # an unknown category is refused by Claim
    if category == "inherited" and not (inherits or cause):
        raise ValueError("category='inherited' needs inherits= (the earlier claim)")
    if inequality not in (None, "<=", ">="):
        raise ValueError(f"inequality must be '<=' or '>=', got {inequality!r}")
    extra = dict(category=category or "", inherits=inherits, anchor=anchor)
    if ours is None:
        return Claim(
            section,
            quantity,
            paper,
            "-",
            math.nan,
            math.nan,
            "not evaluable",
            cause or note or "not evaluable",
            rel is not None,
            note,
            **extra,
        )
    p, o = float(paper), float(ours)
    diff = float(_dec(paper) - _dec(ours))
    t = abs(p) * float(rel) if rel is not None else float(tol or 0.0)
    if inequality is not None:
        ok = o <= p + t if inequality == "<=" else o >= p - t
        verdict = "holds" if ok else "fails"
        why = f"the paper's bound: ours {'≤' if inequality == '<=' else '≥'} {paper}"
        s = f"{o:.{max(_decimals(paper) + 1, 0)}f}"
        rule = "bound"
    elif rel is None and tol is None:
        verdict, why, s, t = _rounded(paper, ours)
        rule = "digits"
    else:
        ok = math.isfinite(diff) and abs(diff) <= t
        verdict = "agrees" if ok else "DIFFERS"
        why = "within the tolerance" if ok else "outside the tolerance"
        digits = max(0, 2 - int(math.floor(math.log10(t)))) if t > 0 else 6
        s = f"{o:.{digits}f}" if abs(o) >= 1e-3 or o == 0 else f"{o:.4e}"
        rule = "rel" if rel is not None else "abs"
    return Claim(
        section,
        quantity,
        paper,
        shown or s,
        diff,
        t,
        verdict,
        cause or why,
        rule != "digits",
        note,
        rule=rule,
        **extra,
    )


def check(diff: float, tol: float) -> str:
    """``'agrees'`` when ``|diff| <= tol`` (both finite), else ``'DIFFERS'``: the rule for our
    numbers against an independent computation."""
    return (
        "agrees"
        if math.isfinite(diff) and math.isfinite(tol) and abs(diff) <= tol
        else "DIFFERS"
    )


def _cell(x, tex) -> str:
    """A table cell: floats (tolerances) as ``.1e``; pass other numbers as strings; text
    through ``tex``."""
    s = f"{x:.1e}" if isinstance(x, float) else str(x)
    s = s.replace("|", "\\|").replace("nan", "-")
    return tex(s) if isinstance(x, str) else s


def _shown_difference(diff: float, tol: float) -> str:
    """``paper - ours`` as a table shows it: one significant digit when it is at least a
    tenth of the tolerance (the paper's own digits; our error is far below that), else
    the bound ``< tol/10``. What round-off moves (the last bits of ``ours``) never shows.
    """
    if not math.isfinite(diff):
        return "-"
    if tol > 0 and math.isfinite(tol):
        floor = 10.0 ** math.floor(math.log10(tol / 10))
        if abs(diff) < floor:
            return f"< {floor:.0e}"
    return f"{diff:+.0e}"


def markdown(
    rows: Any, columns: Any = None, *, typeset: Any = False, compact: Any = False
) -> str:
    r"""A Markdown (GFM) table of claims, or of any rows given with ``columns``.

    Parameters
    ----------
    rows : sequence of Claim, or sequence of sequences
    columns : list of str, optional
        Headers of ``rows`` given as sequences (default: the claims' fields).
    typeset : bool
        Typeset family labels in headers and cells (``IS^l_1`` ->
        ``$\mathrm{IS}^\ell_{1}$``, :func:`typeset_labels`).
    compact : bool
        For claims: only ``quantity``, ``paper``, ``ours`` and ``verdict``, so that the
        table fits a 688 px text column (the rest is in the ledger). Implies
        ``typeset``.

    Examples
    --------
    >>> print(markdown([claim("tau of IS^l_7", "29.0524", 29.05234)], compact=True))
    | quantity | paper | ours | verdict |
    |---|---|---|---|
    | tau of $\mathrm{IS}^\ell_{7}$ | 29.0524 | 29.0523 | last digit off by +1 |
    """
    if columns is None:
        columns = (
            ["quantity", "paper", "ours", "verdict"]
            if compact
            else [
                "section",
                "quantity",
                "paper",
                "ours",
                "difference",
                "tolerance",
                "verdict",
            ]
        )
        rows = [
            [
                _shown_difference(c.difference, c.tolerance)
                if k == "difference"
                else getattr(c, k)
                for k in columns
            ]
            for c in rows
        ]
    tex = typeset_labels if (typeset or compact) else (lambda x: x)
    out = [
        "| " + " | ".join(tex(str(c)) for c in columns) + " |",
        "|" + "---|" * len(columns),
    ]
    out += ["| " + " | ".join(_cell(v, tex) for v in r) + " |" for r in rows]
    return "\n".join(out)


def records(claims: Any, chapter: str) -> str:
    """The claims as one JSON string (a chapter glues it under ``claims``; the ledger page is
    generated from these records).

    ``category``, ``inherits`` and ``rule`` appear only when they differ from what the
    verdict implies (:func:`category_of_verdict`; rule ``digits`` or ``rel``/``abs``).
    """
    rows = []
    for c in claims:
        # The fields added for the ledger's categories are recorded only when they say
        # more than the verdict does, so that records of earlier claims are unchanged
        # (make_ledger.py derives the defaults the same way): a category that is the
        # verdict's own, an empty inherits or anchor, a rule other than ``bound``.
        implied = {
            "category": category_of_verdict(c.verdict),
            "inherits": "",
            "anchor": "",
        }
        d = {
            k: v
            for k, v in asdict(c).items()
            if (v == "bound" if k == "rule" else k not in implied or implied[k] != v)
        }
        d.update(
            status=c.status,
            chapter=chapter,
            difference=None
            if math.isnan(c.difference)
            else _shown_difference(c.difference, c.tolerance),
            tolerance=None if math.isnan(c.tolerance) else float(f"{c.tolerance:.3g}"),
        )
        rows.append(d)
    return json.dumps(rows, ensure_ascii=False, sort_keys=True)


# --------------------------------------------------------------------- family labels

_PHASE_TEX = {"l": r"\ell", "ℓ": r"\ell", r"\ell": r"\ell", "r": "r", "b": "b"}
# One family label: kind, phase (l, r, ℓ, \ell, b or a braced list such as {l,r}), and an
# optional index (digits, a letter such as n, or a braced expression such as {4n-k}).
_LABEL_TEX_RE = re.compile(
    r"^\s*(IS|PD)\s*(?:\^\s*(\{[^{}]*\}|\\ell|[lrℓb])|([lrℓb]))\s*"
    r"(?:_?\s*(\{[^{}]*\}|\d+)|_\s*([A-Za-z]))?\s*$"
)
#: An orbit label inside running text (``IS^l_2``, ``PD^{r}_{n}``, ``ISl1``: the plain
#: style only with an index, so that words and code names such as PDw8 or ISkr are left
#: alone; ``PDb`` as a whole word), as :func:`typeset_labels` finds them.
#:
#: :meta hide-value:
LABEL_IN_TEXT_RE = re.compile(
    r"(?<![\w\\^{])(?:"
    r"(?:IS|PD)\^(?:\{[^{}$]*\}|\\ell|[lrℓb])(?:_(?:\{[^{}$]*\}|\d+|[A-Za-z](?![A-Za-z])))?"
    r"|(?:IS|PD)[lr]\d+"
    r"|(?:IS|PD)b"
    r")(?![\w^])"
)


def label_tex(label: str, *, delimiters: bool = True) -> str:
    r"""A family label typeset: ``'IS^l_1'`` -> ``'$\mathrm{IS}^\ell_{1}$'``.

    Accepts every spelling of :func:`rotorlib.paper.bifurcations.parse_label` (``IS^l_3``,
    ``ISl3``, ``IS^l_{3}``, ``IS^ℓ_3``, ``PDr2``), the breather's daughters (``PD^b``,
    ``PDb``), class labels without an index (``IS^r``), a letter or braced expression as
    index (``IS^l_n``, ``IS^l_{4n-k}``, ``PD^r_{1,3,5}``) and a braced phase list
    (``IS^{l,r}_n``). The result is LaTeX for MathJax and, unchanged, matplotlib mathtext
    (``\mathrm``, ``\ell`` and braces are all mathtext).

    Parameters
    ----------
    label : str
    delimiters : bool
        Wrap in ``$...$`` (default); ``False`` gives the bare expression, to be placed
        inside a larger formula.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        Not a family label.

    Examples
    --------
    >>> label_tex("IS^l_1")
    '$\\mathrm{IS}^\\ell_{1}$'
    >>> label_tex("PDr2")
    '$\\mathrm{PD}^r_{2}$'
    >>> label_tex("PDb")
    '$\\mathrm{PD}^b$'
    >>> label_tex("IS^r_{12}", delimiters=False)
    '\\mathrm{IS}^r_{12}'
    """
    if not isinstance(label, str):
        raise ValueError(f"a family label must be a string, got {label!r}")
    m = _LABEL_TEX_RE.match(label)
    if not m:
        raise ValueError(
            f"not a family label: {label!r} (expected e.g. 'IS^l_1', 'PDr2', 'PDb')"
        )
    kind, phase = m.group(1), m.group(2) or m.group(3)
    index = m.group(4) or m.group(5)
    if index is not None and index.startswith("{"):
        index = index[1:-1].strip()
    if phase == "b" and index is not None:
        raise ValueError(f"the breather's daughter {label!r} has no index")
    if m.group(3) and index is None and phase != "b":
        raise ValueError(f"not a family label: {label!r} (an index is missing)")
    if phase.startswith("{"):  # a list of phases
        parts = [p.strip() for p in phase[1:-1].split(",")]
        phase = "{" + ",".join(_PHASE_TEX.get(p, p) for p in parts) + "}"
    else:
        phase = _PHASE_TEX[phase]
    tex = rf"\mathrm{{{kind}}}^{phase}"
    if index is not None:
        tex += "_{" + index + "}"
    return f"${tex}$" if delimiters else tex


def typeset_labels(text: str) -> str:
    r"""Every family label in running text typeset with :func:`label_tex`.

    Text already inside ``$...$`` or backticks is left alone, as are code names that
    merely start like a label (``PDw8``, ``ISkr``).

    Examples
    --------
    >>> typeset_labels("fan IS^l even, PD^r_1 and ISl6")
    'fan $\\mathrm{IS}^\\ell$ even, $\\mathrm{PD}^r_{1}$ and $\\mathrm{IS}^\\ell_{6}$'
    >>> typeset_labels("already $\\mathrm{IS}^\\ell_1$ and `ISl1`")
    'already $\\mathrm{IS}^\\ell_1$ and `ISl1`'
    """
    parts = re.split(r"(\$[^$]*\$|`[^`]*`)", text)
    for i in range(0, len(parts), 2):
        parts[i] = LABEL_IN_TEXT_RE.sub(lambda m: label_tex(m.group(0)), parts[i])
    return "".join(parts)
