"""Numbers as the book shows them: rounded to the digits their computation verified.

A number the book prints or glues carries only the digits that its computation
verified: rounded to them (:func:`rounded`, :func:`sig`), or, when it is zero up to
round-off, a bound (:func:`bound`). Printed this way, a chapter's output is the same on
every CPU; the test command checks it with a second nbval run in a perturbed
floating-point environment. :mod:`rotorlib.core.compare` re-exports these functions.
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["rounded", "sig", "bound", "difference", "glue"]


def rounded(x: Any, digits: int, *, atol: float = 0.0) -> Any:
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


def sig(x: Any, digits: int) -> str:
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


def bound(x: Any, tol: float) -> str:
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


def difference(x: float, floor: float = 1e-15) -> str:
    """A difference of two locations or routes in words: one significant digit, or the
    bound ``'< floor'`` below ``floor`` (float64's last bits by default).

    Examples
    --------
    >>> difference(2.3e-13), difference(4e-17)
    ('2e-13', '< 1e-15')
    """
    return f"{x:.0e}" if x >= floor else f"< {floor:.0e}"


def glue(key: str, value: Any, digits: int | None = None, *, atol: float = 0.0) -> None:
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
    """Whether ``x`` (or an entry of a list, tuple or dict) is a number :func:`rounded`
    would round: not a bool, int, str or None."""
    if isinstance(x, dict):
        x = list(x.values())
    if isinstance(x, list | tuple):
        return any(_has_float(v) for v in x)
    return not (isinstance(x, bool | int | str) or x is None)
