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
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from decimal import ROUND_DOWN, ROUND_HALF_EVEN, Decimal

__all__ = [
    "Claim",
    "claim",
    "check",
    "markdown",
    "records",
    "STATUSES",
    "rounded",
    "sig",
    "bound",
    "glue",
]

STATUSES = ("reproduced", "not correctly rounded", "wrong", "not evaluable")


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

    @property
    def status(self) -> str:
        """The ledger class: one of ``STATUSES``."""
        if self.verdict == "agrees":
            return "reproduced"
        if self.verdict == "not evaluable":
            return "not evaluable"
        if self.verdict == "truncated" or self.verdict.startswith("last digit"):
            return "not correctly rounded"
        return "wrong"


def _decimals(text: str) -> int:
    s = text.strip().lower()
    mant, _, ex = s.partition("e")
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
    swap = (
        len(diffs) == 2
        and diffs[1] == diffs[0] + 1
        and a[diffs[0]] == b[diffs[1]]
        and a[diffs[1]] == b[diffs[0]]
    )
    if p == o_r:
        v, cause = "agrees", "correctly rounded"
    elif p == o_t:
        v, cause = "truncated", "the paper's value is ours truncated, not rounded"
    elif abs(k) <= 3:
        v, cause = (
            f"last digit off by {k:+d}",
            "lower working precision (or an inaccurate input)",
        )
    elif swap:
        v, cause = "typo", "two adjacent digits transposed"
    else:
        v, cause = "DIFFERS", "not explained by rounding or a single typo"
        for i in (
            diffs
        ):  # one wrong digit (not the last), maybe with the last off a few units
            if i == len(a) - 1:
                continue
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
    quantity, paper: str, ours, *, section="", rel=None, tol=None, note="", shown=None
) -> Claim:
    """Check one printed value ``paper`` (a string, as printed) against ``ours``.

    ``rel`` (the paper's ``≈``: tolerance ``rel |paper|``) or ``tol`` (absolute) make it a
    tolerance comparison (an approximate claim); otherwise the printed digits are the claim. ``ours=None``: not
    evaluable. ``shown`` overrides how ours is displayed (default: rounded to the
    tolerance's digits).
    """
    paper = str(paper).strip()
    if ours is None:
        return Claim(
            section,
            quantity,
            paper,
            "-",
            math.nan,
            math.nan,
            "not evaluable",
            note or "not evaluable",
            rel is not None,
            note,
        )
    p = float(paper)
    diff = float(_dec(paper) - _dec(ours))
    if rel is None and tol is None:
        v, cause, s, t = _rounded(paper, ours)
        return Claim(
            section, quantity, paper, shown or s, diff, t, v, cause, False, note
        )
    t = abs(p) * float(rel) if rel is not None else float(tol)
    ok = math.isfinite(diff) and abs(diff) <= t
    digits = max(0, 2 - int(math.floor(math.log10(t)))) if t > 0 else 6
    s = shown or (
        f"{float(ours):.{digits}f}"
        if abs(float(ours)) >= 1e-3 or float(ours) == 0
        else f"{float(ours):.4e}"
    )
    return Claim(
        section,
        quantity,
        paper,
        s,
        diff,
        t,
        "agrees" if ok else "DIFFERS",
        "within the tolerance" if ok else "outside the tolerance",
        True,
        note,
    )


def check(diff: float, tol: float) -> str:
    """``'agrees'`` when ``|diff| <= tol`` (both finite), else ``'DIFFERS'``: the rule for our
    numbers against an independent computation."""
    return (
        "agrees"
        if math.isfinite(diff) and math.isfinite(tol) and abs(diff) <= tol
        else "DIFFERS"
    )


def _cell(x) -> str:
    """A table cell: floats (tolerances) as ``.1e``; pass other numbers as strings."""
    s = f"{x:.1e}" if isinstance(x, float) else str(x)
    return s.replace("|", "\\|").replace("nan", "-")


def _shown_difference(diff: float, tol: float) -> str:
    """``paper - ours`` as a table shows it: one significant digit when it is at least a
    tenth of the tolerance (the paper's own digits; our error is far below that), else
    the bound ``< tol/10``. What round-off moves (the last bits of ``ours``) never shows.
    """
    if not math.isfinite(diff):
        return "-"
    if not (tol > 0 and math.isfinite(tol)):
        return f"{diff:+.0e}"
    floor = 10.0 ** math.floor(math.log10(tol / 10))
    if abs(diff) < floor:
        return f"< {floor:.0e}"
    return f"{diff:+.0e}"


# --- output that does not depend on the last bits of the arithmetic -------------------
# A number the book prints or glues carries only the digits that its computation
# verified: rounded to them (`rounded`, `sig`), or, when it is zero up to round-off, a
# bound (`bound`). Printed this way, a chapter's output is the same on every CPU (the
# test command checks it in a perturbed floating-point environment too).


def rounded(x, digits: int, *, atol: float = 0.0):
    """``x`` rounded to ``digits`` significant digits; ``|x| < atol`` gives ``0.0``.

    Works on Python and numpy floats, mpmath numbers (converted to float), and on
    lists, tuples and dicts of them (recursively); anything else (str, int, bool,
    None) passes unchanged.

    Examples
    --------
    >>> rounded(1.0013164193630415, 6)
    1.00132
    >>> rounded(4.440892098500626e-16, 6, atol=1e-12)
    0.0
    >>> rounded([2.0000000001, "x"], 3)
    [2.0, 'x']
    """
    if digits < 1:
        raise ValueError(f"digits must be >= 1, got {digits}")
    if isinstance(x, dict):
        return {k: rounded(v, digits, atol=atol) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return type(x)(rounded(v, digits, atol=atol) for v in x)
    if isinstance(x, bool | int | str) or x is None:
        return x
    try:
        v = float(x)
    except (TypeError, ValueError):
        return x
    if not math.isfinite(v):
        return v
    if abs(v) < atol or v == 0.0:
        return 0.0
    return float(f"{v:.{digits - 1}e}")


def sig(x, digits: int) -> str:
    """``x`` as a string with ``digits`` significant digits (``g`` style, no exponent
    between 1e-4 and 1e16).

    Examples
    --------
    >>> sig(3.893073684550241, 10)
    '3.893073685'
    >>> sig(2.86158152420e-11, 5)
    '2.8616e-11'
    """
    if digits < 1:
        raise ValueError(f"digits must be >= 1, got {digits}")
    v = float(x)
    if v == 0.0 or not math.isfinite(v):
        return str(v)
    e = math.floor(math.log10(abs(v)))
    if -4 <= e < 16:
        return f"{v:.{max(digits - 1 - e, 0)}f}"
    return f"{v:.{digits - 1}e}"


def bound(x, tol: float) -> str:
    """The bound ``'< tol'`` for a quantity that is zero up to round-off (a closure error,
    an energy drift, the difference of two routes), after checking ``|x| < tol``.

    The printed text depends only on ``tol``, so it is the same on every machine; the
    check is what can fail. Raises ``AssertionError`` when ``|x| >= tol`` (or ``x`` is not
    finite), with the value in the message.

    Examples
    --------
    >>> bound(5.1e-12, 1e-10)
    '< 1e-10'
    >>> bound(3e-9, 1e-10)
    Traceback (most recent call last):
    ...
    AssertionError: |x| = 3e-09 is not below the bound 1e-10
    """
    v = abs(float(x))
    if not (math.isfinite(v) and v < tol):
        raise AssertionError(f"|x| = {v:.1g} is not below the bound {tol:.0e}")
    return f"< {tol:.0e}"


def glue(key: str, value, digits: int | None = None, *, atol: float = 0.0) -> None:
    """Glue ``value`` under ``key`` for the book's text (myst-nb), rounded first.

    ``digits`` is the number of significant digits the computation verified; floats
    (also inside lists, tuples and dicts) are stored rounded to them, and those below
    ``atol`` as ``0.0``. ``digits=None`` is only for values that are not floats (strings,
    integers, JSON records). Nothing is displayed in the notebook.
    """
    from myst_nb import glue as _glue

    if digits is not None:
        value = rounded(value, digits, atol=atol)
    elif _has_float(value):
        raise ValueError(f"glue {key!r}: a float needs digits= (its verified digits)")
    _glue(key, value, display=False)


def _has_float(x) -> bool:
    if isinstance(x, dict):
        return any(_has_float(v) for v in x.values())
    if isinstance(x, list | tuple):
        return any(_has_float(v) for v in x)
    if isinstance(x, bool | int | str) or x is None:
        return False
    return True


def markdown(rows, columns=None) -> str:
    """A Markdown (GFM) table of claims, or of any rows given with ``columns``."""
    if columns is None:
        columns = [
            "section",
            "quantity",
            "paper",
            "ours",
            "difference",
            "tolerance",
            "verdict",
        ]
        rows = [
            [
                _shown_difference(c.difference, c.tolerance)
                if k == "difference"
                else getattr(c, k)
                for k in columns
            ]
            for c in rows
        ]
    out = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    out += ["| " + " | ".join(_cell(v) for v in r) + " |" for r in rows]
    return "\n".join(out)


def records(claims, chapter: str) -> str:
    """The claims as one JSON string (a chapter glues it under ``claims``; the ledger page is
    generated from these records)."""
    rows = []
    for c in claims:
        d = asdict(c)
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
