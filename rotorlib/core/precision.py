"""Precision tiers: one ``digits`` control for every integration in rotorlib.

A :class:`Tier` is float64 (heyoka's Taylor method at machine epsilon, or scipy),
heyoka ``real128`` (quadruple precision, ~33 digits) or heyoka multiprecision
``mp<bits>`` (MPFR). :func:`tier` maps a requested number of significant digits to
a tier; :func:`precision_tier` names its heyoka tier with it, so that a
result computed with ``digits=D`` names the same tier whatever produced it.

Numbers in a tier are Python floats (float64) or ``mpmath.mpf`` evaluated at
:attr:`Tier.dps` working digits (extended tiers); a float given to an extended
tier is read as its shortest decimal representation (``4.55`` means 455/100).
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterable
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from functools import cache
from typing import Any

import mpmath as mp
import numpy as np

__all__ = [
    "Tier",
    "tier",
    "FLOAT64",
    "REAL128",
    "load_heyoka",
    "HEYOKA_CACHE_MB",
    "HeyokaMissing",
    "DIGITS_RANGE",
    "check_digits",
    "json_number",
    "requested_digits",
    "heyoka_available",
    "precision_tier",
    "integrator_tier",
]

#: The significant digits every function (``digits=``) and command (``--digits``) accepts.
DIGITS_RANGE = (1, 1000)


def check_digits(digits: Any, name: str = "digits") -> int | None:
    """``digits`` itself if it is ``None`` or an integer in :data:`DIGITS_RANGE`.

    Raises
    ------
    ValueError
        Anything else, with the one message every function and command uses.

    Examples
    --------
    >>> check_digits(30)
    30
    >>> check_digits(0, "--digits")
    Traceback (most recent call last):
    ...
    ValueError: --digits must be an integer from 1 to 1000, got 0
    """
    lo, hi = DIGITS_RANGE
    if digits is None:
        return None
    if (
        isinstance(digits, bool)
        or not isinstance(digits, (int, np.integer))
        or not lo <= digits <= hi
    ):
        raise ValueError(f"{name} must be an integer from {lo} to {hi}, got {digits!r}")
    return digits


def _same_decimal(text: str, v) -> bool:
    """Whether ``text`` is the decimal ``repr(v)`` (``1.0e-300`` is ``1e-300``)."""
    try:
        return v is not None and math.isfinite(v) and Decimal(text) == Decimal(repr(v))
    except InvalidOperation:
        return False


def json_number(key: str, value: Any, text: str | None = None, note: str = "") -> dict:
    """``key`` (and ``key_str``, ``key_note``) as the command line prints them in JSON.

    The one rule of every ``--json`` output: a quantity is a JSON number, its float64
    value, under ``key``; the digits beyond float64 (an extended tier, or an input with
    more digits than a float64 holds) are the decimal string ``text``, given as
    ``key_str`` when it says more than the number, which is then its float64 rounding. A value that float64 cannot hold
    (overflow, ``nan``) is ``null``, with ``key_note`` saying why: JSON never holds
    ``nan`` or ``inf``, as numbers or as strings.

    Examples
    --------
    >>> json_number("E", 1.0, "1.0")
    {'E': 1.0}
    >>> json_number("E", 4.0, "3.99999999999999999999")
    {'E': 4.0, 'E_str': '3.99999999999999999999'}
    >>> rec = json_number("trace", float("inf"), "2.5e+400")
    >>> rec["trace"], rec["trace_str"]
    (None, '2.5e+400')
    >>> rec["trace_note"]
    'beyond the float64 range: see trace_str'
    """
    v = None if value is None else float(value)
    if text:  # the number is the float64 rounding of every digit, when they are given
        with contextlib.suppress(InvalidOperation):  # "4 + 5.07e-435": the value stays
            v = float(Decimal(str(text)))
    out: dict = {key: v if v is not None and math.isfinite(v) else None}
    if text is not None and text != "" and not _same_decimal(str(text), v):
        out[key + "_str"] = str(text)
    if out[key] is None:
        out[key + "_note"] = note or (
            f"beyond the float64 range: see {key}_str"
            if key + "_str" in out
            else f"{key} is undefined here"
        )
    return out


#: Default bound (MiB) of heyoka's on-disk cache of compiled integrators
#: (``~/.cache/heyoka``; heyoka's own default is 20 GiB). One build of the book and one
#: run of the tests fill about 260 MB; past the bound heyoka evicts the least recently
#: used entries. Set ``ROTORLIB_HEYOKA_CACHE_MB`` to change it (``0`` turns the cache off).
HEYOKA_CACHE_MB = 512


class HeyokaMissing(ImportError):
    """heyoka is not installed: its message is the one-line refusal every command prints.

    heyoka is a required dependency where its wheels exist (Linux x86_64 and aarch64);
    elsewhere install the extra ``rotorlib[fast]`` (or conda-forge's ``heyoka.py``).
    """


@cache
def load_heyoka() -> Any:
    """heyoka, imported once, with its on-disk cache bounded.

    The bound is ``ROTORLIB_HEYOKA_CACHE_MB`` MiB if that variable is set, else
    :data:`HEYOKA_CACHE_MB`. No number depends on the cache: it only saves the
    compilation of an integrator already built once on this machine.

    Raises
    ------
    HeyokaMissing
        heyoka is not installed: the Hill integrals fall back to scipy/mpmath
        (:func:`heyoka_available`); the nonlinear flow
        (:mod:`rotorlib.core.flow`: shooting, families, the atlas) refuses with it.
    ValueError
        ``ROTORLIB_HEYOKA_CACHE_MB`` is not a non-negative integer.
    """
    try:
        import heyoka as hy
    except ImportError as exc:  # one line, naming the extra (the CLI prints it)
        raise HeyokaMissing(
            "this computation needs heyoka (the Taylor integrator of the nonlinear "
            f"flow), which is not installed here ({exc}): pip install "
            "'rotorlib[fast]' or conda install -c conda-forge heyoka.py",
            name="heyoka",
        ) from exc

    raw = os.environ.get("ROTORLIB_HEYOKA_CACHE_MB", str(HEYOKA_CACHE_MB))
    if not raw.strip().isdecimal():
        raise ValueError(
            f"ROTORLIB_HEYOKA_CACHE_MB must be a non-negative integer (MiB), got {raw!r}"
        )
    hy.llvm_state.set_diskcache_limit(int(raw) * 2**20)
    return hy


@dataclass(frozen=True)
class Tier:
    """A working precision: ``float64``, ``real128`` or ``mp<bits>``."""

    name: str

    #: float64 shooting is trusted while the distance ``|E - E_sep|`` to the separatrix
    #: exceeds this (book/numerical_notes.md: fine to ~1e-8); closer, real128.
    separatrix_depth = 3e-8

    @property
    def r_max(self) -> float:
        """The accepted shooting residual: 1e-8 in float64, ``eps^(2/3)`` extended."""
        return 1e-8 if not self.extended else self.eps ** (2 / 3)

    @property
    def step_tol(self) -> Any:
        """The relative step at which a secant stops: 4e-15 in float64, ``8 eps``
        extended (a number of the tier)."""
        return 4e-15 if not self.extended else self.num(self.eps) * 8

    def __post_init__(self) -> None:
        if self.name not in ("float64", "real128") and not (
            self.name.startswith("mp") and self.name[2:].isdigit()
        ):
            raise ValueError(
                f"precision must be float64, real128 or mp<bits>, got {self.name!r}"
            )

    @property
    def bits(self) -> int:
        """Mantissa bits (53, 113 or the MPFR precision)."""
        return {"float64": 53, "real128": 113}.get(self.name) or int(self.name[2:])

    @property
    def dps(self) -> int:
        """mpmath working digits for quantities carried between integrations."""
        return (
            17
            if self.name == "float64"
            else 40
            if self.name == "real128"
            else int(self.bits / 3.32) + 8
        )

    @property
    def eps(self) -> float:
        """Unit roundoff ``2^(1 - bits)`` (as a float; 0 below the float64 range)."""
        return 2.0 ** (1 - self.bits)

    @property
    def extended(self) -> bool:
        return self.name != "float64"

    def context(self) -> Any:
        """``mp.workdps(dps)``: arithmetic on the tier's numbers happens inside it."""
        return mp.workdps(self.dps)

    def num(self, v: Any) -> Any:
        """``v`` (float, int, decimal string or mpf) as a number of this tier."""
        if not self.extended:
            return float(v)
        if isinstance(v, (float, np.floating)):
            v = repr(float(v))
        elif isinstance(v, (int, np.integer)):
            v = int(v)
        with self.context():
            return mp.mpf(v)

    def scale(self, factor: Any, x: Any) -> Any:
        """``factor * x`` (``x`` a number of this tier). A ``factor`` that is a small
        rational (denominator ``q <= 48``, to 1e-12: a period factor, the order of
        ``R2 R1`` over 2) is applied as that rational in an extended tier: as a float,
        ``2/3`` would limit the product to ~1e-16 relative.

        >>> t = tier(30)
        >>> with t.context():
        ...     print(mp.nstr(t.scale(2 / 3, t.num(3)), 30))
        2.0
        """
        q = next(
            (q for q in range(1, 49) if abs(factor * q - round(factor * q)) < 1e-12), 1
        )
        with self.context():
            return (
                factor * x
                if q == 1 or not self.extended
                else self.num(round(factor * q)) * x / q
            )

    @property
    def m(self) -> Any:
        """The math module of the tier's numbers (``math`` or ``mpmath``)."""
        return mp if self.extended else math

    @property
    def pi(self) -> Any:
        return self.num(mp.pi) if self.extended else math.pi

    def text(self, v: Any, digits: int | None = None) -> str:
        """``v`` as a decimal string with ``digits`` significant digits (default: all)."""
        if not self.extended:
            return repr(float(v))
        with self.context():
            return mp.nstr(mp.mpf(v), digits or self.dps - 4, strip_zeros=False)

    # ---------------------------------------------------------------- heyoka types
    @property
    def hy_kwargs(self) -> dict:
        """``fp_type`` / ``prec`` keyword arguments of ``heyoka.taylor_adaptive``."""
        hy = load_heyoka()
        return (
            {}
            if self.name == "float64"
            else {"fp_type": hy.real128}
            if self.name == "real128"
            else {"fp_type": hy.real, "prec": self.bits}
        )

    def to_hy(self, v: Any) -> Any:
        """A number in heyoka's type for this tier, without losing digits."""
        if not self.extended:
            return float(v)
        hy = load_heyoka()

        if isinstance(v, (float, np.floating)):
            s = repr(float(v))
        elif isinstance(v, (int, np.integer, str)):
            s = str(v)
        else:
            with self.context():
                s = mp.nstr(mp.mpf(v), self.dps + 2)
        return hy.real128(s) if self.name == "real128" else hy.real(s, self.bits)

    def from_hy(self, v: Any) -> Any:
        """Back from heyoka's type: a float or an mpf."""
        if not self.extended:
            return float(v)
        with self.context():
            return mp.mpf(str(v))

    def hy_array(self, values: Iterable[Any]) -> np.ndarray:
        """A numpy array of heyoka numbers (the state of an integrator)."""
        vals = [self.to_hy(v) for v in values]
        if self.name == "float64":
            return np.array(vals, dtype=float)
        hy = load_heyoka()

        return np.array(vals, dtype=hy.real128 if self.name == "real128" else object)


FLOAT64 = Tier("float64")
REAL128 = Tier("real128")


@cache
def tier(digits: int | Tier | None = None, extra: float = 0) -> Tier:
    """The tier that delivers ``digits`` significant digits after losing ``extra``.

    ``digits=None`` or ``digits + extra <= 15``: float64; up to 31: real128; beyond:
    ``mp<bits>`` with ``bits = ceil((digits + extra + 8) * 3.33)``. ``extra`` is the
    number of digits the computation itself loses (e.g. ``log10(1/|E - 4|)`` for
    shooting near the separatrix). A :class:`Tier` is returned as it is: ``digits``, an
    int or a Tier, is the one precision argument of rotorlib.

    Examples
    --------
    >>> tier(None).name, tier(20).name, tier(40).name, tier(REAL128).name
    ('float64', 'real128', 'mp160', 'real128')
    """
    if isinstance(digits, Tier):
        return digits
    checked = check_digits(digits)
    if checked is None:
        return FLOAT64
    d = int(checked) + max(0, int(math.ceil(extra)))
    if d <= 15:
        return FLOAT64
    if d <= 31:
        return REAL128
    return Tier(f"mp{int(math.ceil((d + 8) * 3.33))}")


def requested_digits(digits: int | Tier | None) -> int | None:
    """The significant digits an extended tier delivers for ``digits``; ``None`` for float64.

    An integer above 15 is itself; a :class:`Tier` beyond float64 delivers ``dps - 9``
    digits; ``None``, an integer up to 15 and ``FLOAT64`` give ``None``.

    Examples
    --------
    >>> requested_digits(30), requested_digits(10), requested_digits(REAL128)
    (30, None, 31)
    """
    t = tier(digits)
    if not t.extended:
        return None
    return t.dps - 9 if isinstance(digits, Tier) else int(digits)  # type: ignore[arg-type]


def heyoka_available() -> bool:
    """True when heyoka imports (a dependency on Linux x86_64/aarch64, the extra
    ``rotorlib[fast]`` elsewhere); without it the Hill problem uses scipy/mpmath."""
    try:
        load_heyoka()  # a malformed ROTORLIB_HEYOKA_CACHE_MB raises: never hidden
    except ImportError:
        return False
    return True


def _mpmath_tier(dps: int) -> Tier:
    """The tier ``mp<bits>`` of mpmath's arithmetic at ``dps`` working digits."""
    return Tier(f"mp{mp.libmp.dps_to_prec(dps)}")


def integrator_tier(
    digits: int | Tier | None, integrator: str | None = None
) -> tuple[str, Tier]:
    """The integrator (``integrator``, else the one :func:`precision_tier` picks) and its
    tier for ``digits``: mpmath works at ``digits + 5`` digits (20 for float64).

    Examples
    --------
    >>> integrator_tier(40, "mpmath")[1].name  # 45 working digits
    'mp153'
    """
    d = requested_digits(digits)
    if integrator is None:
        integrator = (
            "heyoka" if heyoka_available() else "scipy" if d is None else "mpmath"
        )
    if integrator == "mpmath":
        return integrator, _mpmath_tier(d + 5 if d else 20)
    return integrator, tier(digits)


def precision_tier(digits: int | Tier | None = None) -> tuple[str, str]:
    """The integrator and the tier that :func:`rotorlib.orbits.floquet.monodromy` uses for ``digits``
    on this machine.

    Returns
    -------
    (str, str)
        Integrator: ``heyoka``, in the tier :func:`rotorlib.core.precision.tier` gives
        (``float64``, ``real128``, ``mp<bits>``); without heyoka ``scipy`` in float64
        and ``mpmath`` beyond, at ``digits + 5`` working digits: the tier ``mp<bits>``
        of that arithmetic. Either name is one :class:`~rotorlib.core.precision.Tier` accepts,
        and the one ``Monodromy.precision`` records.

    Examples
    --------
    >>> precision_tier(None)[1], precision_tier(20)[1], precision_tier(40)[1]
    ('float64', 'real128', 'mp160')
    """
    integrator, t = integrator_tier(digits)
    return integrator, t.name
