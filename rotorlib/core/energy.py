"""Energies parametrised by their distance to a separatrix.

Near the pendulum separatrix E = 4 the energy itself cannot carry the
information (4 + 1e-30 == 4 in float64); the distance ``eps = |E - 4|``, or
its logarithm, can. Every orbit in :mod:`rotorlib` is built from a
:class:`PendulumEnergy` or :class:`BreatherEnergy` (distance to the breather
separatrix 4.5), which keep the decimal input, ``eps`` and ``log|E - sep|``.

The input is a *decimal*: a string is read exactly as typed (``"3.99999999999999999999"``
is 4 - 1e-20, not the float64 4.0), a float as its shortest ``repr`` (``3.9``
means 39/10). ``eps`` is the exact decimal distance rounded once to float64;
``mp_values`` rebuilds ``E`` and ``eps`` in mpmath at any precision from the
same decimal, so no float64 rounding reaches the extended-precision tiers.

Accepted input (anything else raises ``ValueError`` with the reason):

* pendulum: ``E >= 0`` finite and ``E != 4`` as a decimal; or ``log|E - 4|``
  finite with a phase, ``lib`` (then ``log|E - 4| <= log 4``, i.e. ``E >= 0``)
  or ``rot``. ``E = 0`` is the equilibrium G (small-oscillation limit).
* breather: families ``LG`` (0 <= E < 4.5), ``LD`` (4 <= E < 4.5) and ``R``
  (E > 4.5); the distance is to the breather separatrix 4.5. Only an input
  that *is* the separatrix (``E`` equal to 4.5 as a decimal) is refused.

Depth: any ``log|E - sep|`` is accepted. Below ``|E - sep| = 1.8e-307``
(``log < -706.3``) ``eps`` or ``m1`` leave the normal float64 range (``eps`` is
0.0 below ``log = -745``); such energies are carried by ``log_abs_dE`` and
``mp_values`` only, and the float64 closed forms refuse them
(``require_float64``, ``ValueError`` naming the extended tiers).
"""

from __future__ import annotations

import math
import numbers
import sys
from dataclasses import dataclass
from decimal import Context, Decimal, InvalidOperation
from typing import Any

import mpmath as mp

__all__ = [
    "PendulumEnergy",
    "BreatherEnergy",
    "pendulum_energy",
    "breather_energy",
    "as_float",
    "FLOAT64_MIN_EPS",
]

#: Smallest ``|E - sep|`` the float64 closed forms accept: it keeps ``eps`` and the
#: complementary parameter ``m1`` (>= eps/4 for every family) normal floats.
FLOAT64_MIN_EPS = 8.0 * sys.float_info.min
#: Decimal inputs longer than this (digits needed for the exact ``E - sep``) are refused.
_MAX_DIGITS = 100_000


def as_float(value: Any, name: str) -> float:
    """Convert ``value`` to a finite float or raise a ValueError naming ``name``."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return x


# --------------------------------------------------------------------------- decimal input (shared)


def _decimal_text(value, name: str) -> str:
    """The decimal text of an input: a string as typed, a float as its ``repr``.

    Raises ``ValueError`` for booleans, unparsable or non-finite values.
    """
    if isinstance(value, bool) or value is None:
        raise ValueError(f"{name} must be a number, got {value!r}")
    if isinstance(value, str):
        text = value.strip()
    elif isinstance(value, numbers.Integral):
        text = str(int(value))
    elif isinstance(value, numbers.Real) and not isinstance(value, Decimal):
        text = repr(float(value))  # float, numpy floats: shortest round-trip decimal
    else:
        text = str(value)  # Decimal, mpmath mpf (its digits at the current dps)
    try:
        d = Decimal(text)
    except (InvalidOperation, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not d.is_finite():
        raise ValueError(f"{name} must be finite, got {value!r}")
    return text


def _exact_distance(text: str, sep: Decimal):
    """``(sign, |E - sep|)`` of the decimal ``text`` as an exact ``Decimal``."""
    d = Decimal(text)
    top = max(d.adjusted(), sep.adjusted(), 0)
    low = min(int(d.as_tuple().exponent), int(sep.as_tuple().exponent))
    prec = top - low + 3  # enough digits for the exact difference
    if prec > _MAX_DIGITS:
        raise ValueError(
            f"E = {text!r} has too many digits (its distance to {sep} needs {prec} > {_MAX_DIGITS})"
        )
    ctx = Context(prec=prec, Emax=999_999_999, Emin=-999_999_999)
    diff = ctx.subtract(d, sep)
    return (diff > 0) - (diff < 0), abs(diff)


#: The branches of each energy: their side of the separatrix (-1 below, +1 above) and
#: their lowest energy (``None``: the separatrix itself). The first on a side is the
#: default of an ``E`` on that side.
_PHASES = {"lib": (-1, Decimal(0)), "rot": (1, None)}
_FAMILIES = {"LG": (-1, Decimal(0)), "LD": (-1, Decimal(4)), "R": (1, None)}


@dataclass(frozen=True)
class _Distance:
    """Parsed input: the branch (phase or family), eps and its log, E (floats), given."""

    branch: str
    eps: float
    log_abs_dE: float
    E: float
    given: tuple


def _distance(
    sep: Decimal, E, log_abs_dE, branch, branches: dict, kind: str, what: str
) -> _Distance:
    """Parse ``E`` or ``log|E - sep|`` on ``branch`` (a key of ``branches``, a ``kind`` of
    orbit) into a :class:`_Distance`, checking the range of the branch; ``what`` names
    the separatrix. Shared by both energies."""
    name = f"log|E-{sep}|"
    if branch is not None and branch not in branches:
        raise ValueError(f"{kind} must be one of {', '.join(branches)}; got {branch!r}")
    if (E is None) == (log_abs_dE is None):
        raise ValueError(f"give exactly one of E and {name}")
    if E is None:
        if branch is None:
            raise ValueError(f"{name} needs a {kind} ({', '.join(branches)})")
        side, lowest = branches[branch]
        text = _decimal_text(log_abs_dE, name)
        x = float(Decimal(text))
        if not math.isfinite(x):
            raise ValueError(
                f"{name} = {text} is beyond the float64 range of the logarithm"
            )
        if x > 700.0:
            raise ValueError(f"{name} = {text} is too large (|E| would exceed 1e304)")
        if lowest is not None and x > math.log(sep - lowest):
            raise ValueError(
                f"the {kind} {branch} has E = {sep} - exp({name}) >= {lowest}, so {name} <= "
                f"log {sep - lowest} = {math.log(sep - lowest):.6f}; got {text}"
            )
        eps = math.exp(x)  # 0.0 or subnormal below -745 / -708: see require_float64
        return _Distance(branch, eps, x, float(sep) + side * eps, ("log_abs_dE", text))
    text = _decimal_text(E, "E")
    if Decimal(text) < 0:
        raise ValueError(f"E must be >= 0 (the minimum of V is 0), got {text}")
    side, dist = _exact_distance(text, sep)
    if side == 0:
        raise ValueError(
            f"E = {sep} is the {what}: the period diverges; give {name} and a {kind} instead"
        )
    branch = branch or next(b for b, (s, _) in branches.items() if s == side)
    s, lowest = branches[branch]
    if s != side or (lowest is not None and Decimal(text) < lowest):
        span = f"E > {sep}" if s > 0 else f"{lowest} <= E < {sep}"
        raise ValueError(f"the {kind} {branch} has {span}; got E = {text}")
    eps = float(dist)
    x = math.log(eps) if eps >= sys.float_info.min else float(dist.ln(Context(prec=25)))
    Ef = float(Decimal(text))
    if not math.isfinite(Ef):
        raise ValueError(f"E = {text} is beyond the float64 range")
    return _Distance(branch, eps, x, Ef, ("E", text))


class _SeparatrixDistance:
    """Methods shared by :class:`PendulumEnergy` and :class:`BreatherEnergy` (decimal input, mpmath values)."""

    _SEP = Decimal(4)
    _NAME = "E-4"
    # fields of the dataclasses that mix this in (BreatherEnergy derives phase)
    eps: float
    log_abs_dE: float
    given: tuple[str, str]

    @property
    def side(self) -> int:
        """-1 below the separatrix, +1 above."""
        return 1 if getattr(self, "phase") == "rot" else -1

    @property
    def in_float64_range(self) -> bool:
        """True when ``eps >= FLOAT64_MIN_EPS`` (the float64 closed forms apply)."""
        return self.eps >= FLOAT64_MIN_EPS

    def require_float64(self) -> None:
        """Raise ``ValueError`` when ``|E - sep|`` is below the float64 range of the closed forms."""
        if not self.in_float64_range:
            raise ValueError(
                f"|{self._NAME}| = exp({self.log_abs_dE:.6g}) is below the float64 range "
                f"(|{self._NAME}| >= {FLOAT64_MIN_EPS:.2g}, log >= {math.log(FLOAT64_MIN_EPS):.1f}): "
                "use the extended precision tiers (digits > 15)"
            )

    def mp_E_eps(self, digits: int) -> tuple[Any, Any]:
        """``(E, eps)`` as mpmath numbers rounded to ``digits`` digits, from the decimal input.

        Precision: for ``E`` input both are the exact decimals rounded once (so
        ``eps`` keeps ``digits`` digits however small, and ``E`` however close to 0);
        for ``log|E - sep|`` input, ``eps`` to ``digits`` digits relative (guard digits
        cover ``exp`` of a large log) and ``E = sep -/+ eps`` to ``digits`` digits of ``sep``.
        """
        kind, text = self.given
        sep = mp.mpf(str(self._SEP))
        if kind == "E":
            _, dist = _exact_distance(text, self._SEP)
            with mp.workdps(digits):
                return mp.mpf(text), mp.mpf(str(dist))
        guard = len(str(int(abs(float(text))))) + 5
        with mp.workdps(digits + guard):
            eps = mp.exp(mp.mpf(text))
            E = sep + self.side * eps
        with mp.workdps(digits):
            return +E, +eps

    def decimal_E(self, digits: int = 17) -> str:
        """E as a decimal string with ``digits`` significant digits *after* the
        leading ``4.000…`` zeros, so that ``E - sep`` is visible however small
        (the string has about ``-log10|E - sep|`` characters)."""
        extra = max(0, int(-self.log_abs_dE / math.log(10)) + 1)
        with mp.workdps(digits + extra + 10):
            E, _ = self.mp_E_eps(digits + extra + 10)
            return mp.nstr(E, digits + extra, strip_zeros=True)

    def E_text(self, digits: int = 17) -> str:
        """:meth:`decimal_E` down to ``|E - sep| = 1e-300``; deeper, ``'4 - 1.13548386531474e-4343'``
        (the exact decimal would have ``-log10|E - sep|`` characters)."""
        if self.log_abs_dE > -690.0:
            return self.decimal_E(digits)
        _, eps = self.mp_E_eps(20)
        return f"{self._SEP} {'-' if self.side < 0 else '+'} {mp.nstr(eps, 15)}"


def _pendulum_m(phase, E, eps):
    """``(m, m1)`` of the closed-form pendulum; float64 or mpmath (same formulas)."""
    if phase == "lib":
        return E / 4, eps / 4  # k^2 = E/4
    return 4 / E, eps / E  # kappa^2 = 4/E


@dataclass(frozen=True)
class PendulumEnergy(_SeparatrixDistance):
    """Energy of a pendulum orbit, carried by its distance to the separatrix.

    Attributes
    ----------
    phase : {'lib', 'rot'}
        Libration (E < 4) or rotation (E > 4).
    eps : float
        ``|E - 4|``, the exact decimal distance rounded once to float64 (0.0 or
        subnormal when it underflows, ``log|E - 4| < -706.3``: see ``log_abs_dE``).
    log_abs_dE : float
        ``log|E - 4|`` (natural log; finite at any depth).
    E : float
        The energy in float64 (equal to 4.0 when ``eps < 1e-16``: use ``eps``).
    m, m1 : float
        Elliptic parameter of the closed form and ``1 - m``: ``m = E/4``,
        ``m1 = eps/4`` in libration; ``m = 4/E``, ``m1 = eps/E`` in rotation.
    given : tuple
        ``('E', text)`` or ``('log_abs_dE', text)``: the decimal input.
    """

    phase: str
    eps: float
    log_abs_dE: float
    E: float
    m: float
    m1: float
    given: tuple = ("E", "nan")

    @property
    def modulus(self) -> float:
        """Elliptic modulus ``k = sqrt(E/4)`` (lib) or ``kappa = sqrt(4/E)`` (rot)."""
        return math.sqrt(self.m)

    def mp_values(self, digits: int) -> dict:
        """E, eps, m, m1 as mpmath numbers at ``digits`` digits, from the decimal input.

        The input is read as the decimal the user gave (``repr`` of a float
        argument), so ``E=3.9`` means exactly 39/10 here. Each value is correct
        to ``digits`` digits relative, at any depth.
        """
        E, eps = self.mp_E_eps(digits + 5)
        with mp.workdps(digits + 5):
            m, m1 = _pendulum_m(self.phase, E, eps)
        with mp.workdps(digits):
            return dict(E=+E, eps=+eps, m=+m, m1=+m1)


def pendulum_energy(
    E: Any = None, log_abs_dE: Any = None, phase: str | None = None
) -> PendulumEnergy:
    """Build a :class:`PendulumEnergy` from ``E`` or from ``log|E - 4|`` and a phase.

    Parameters
    ----------
    E : float, int or str, optional
        Relative energy (units m = g = r = 1), read as a decimal: a string
        keeps every typed digit (``"3.99999999999999999999"`` is 4 - 1e-20).
    log_abs_dE : float or str, optional
        Natural log of the distance to the separatrix; needs ``phase``. Any
        depth is accepted (below -706.3 only the extended tiers can use it).
    phase : {'lib', 'rot'}, optional
        Required with ``log_abs_dE``; checked against ``E`` when both given.

    Raises
    ------
    ValueError
        Negative, non-finite or unparsable input; ``E`` equal to 4 as a
        decimal; both or neither of ``E`` and ``log_abs_dE``; a phase other than
        lib/rot; a librational ``log|E-4| > log 4`` (negative energy).

    Examples
    --------
    >>> en = pendulum_energy(log_abs_dE=-50, phase="rot")
    >>> en.phase, f"{en.eps:.6e}", en.decimal_E(5)
    ('rot', '1.928750e-22', '4.00000000000000000000019287')
    >>> pendulum_energy(E="3.99999999999999999999").eps
    1e-20
    """
    d = _distance(
        Decimal(4),
        E,
        log_abs_dE,
        phase,
        _PHASES,
        "phase",
        "separatrix (homoclinic orbit)",
    )
    m, m1 = _pendulum_m(d.branch, d.E, d.eps)
    return PendulumEnergy(d.branch, d.eps, d.log_abs_dE, d.E, m, m1, d.given)


@dataclass(frozen=True)
class BreatherEnergy(_SeparatrixDistance):
    """Energy of an isosceles breather (phi1 = phi2 = phi), carried by its distance to E = 4.5.

    Attributes
    ----------
    family : {'LG', 'LD', 'R'}
        Libration about G, libration about D, or rotation.
    E : float
        Energy in float64 (equal to 4.5 when ``eps < 1e-16``: use ``eps``).
    eps : float
        ``|E - 4.5|``, the exact decimal distance rounded once to float64 (0.0
        or subnormal below ``log|E - 4.5| = -706.3``).
    log_abs_dE : float
        ``log|E - 4.5|`` (finite at any depth).
    given : tuple
        ``('E', text)`` or ``('log_abs_dE', text)``: the decimal input.
    """

    family: str
    E: float
    eps: float
    log_abs_dE: float
    given: tuple

    _SEP = Decimal("4.5")
    _NAME = "E-4.5"

    @property
    def phase(self) -> str:
        return "rot" if self.family == "R" else "lib"

    def mp_values(self, digits: int) -> dict:
        """E and eps = |E - 4.5| as mpmath numbers at ``digits`` digits, from the decimal input."""
        E, eps = self.mp_E_eps(digits)
        return dict(E=E, eps=eps)


def breather_energy(
    E: Any = None, family: str | None = None, log_abs_dE: Any = None
) -> BreatherEnergy:
    """Build a :class:`BreatherEnergy`.

    Parameters
    ----------
    E : float, int or str, optional
        Energy, read as a decimal (a string keeps every typed digit); the
        family defaults to ``LG`` below 4.5 and ``R`` above.
    family : {'LG', 'LD', 'R'}, optional
    log_abs_dE : float or str, optional
        ``log|E - 4.5|`` instead of ``E`` (needs ``family``); any depth.

    Raises
    ------
    ValueError
        For energies the family does not have: ``R`` needs ``E > 4.5``, ``LG``
        ``0 <= E < 4.5``, ``LD`` ``4 <= E < 4.5``; ``E`` equal to 4.5 as a
        decimal; negative or non-finite input; an unknown family.

    Examples
    --------
    >>> en = breather_energy(E="4.49999999999999999999", family="LD")
    >>> en.family, en.phase, en.eps
    ('LD', 'lib', 1e-20)
    >>> breather_energy(E=9).family
    'R'
    """
    d = _distance(
        Decimal("4.5"), E, log_abs_dE, family, _FAMILIES, "breather family",
        "breather separatrix (heteroclinic orbit between the maxima T)",
    )  # fmt: skip
    return BreatherEnergy(d.branch, d.E, d.eps, d.log_abs_dE, d.given)
