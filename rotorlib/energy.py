"""Energies parametrised by their distance to a separatrix.

Near the pendulum separatrix E = 4 the energy itself cannot carry the
information (4 + 1e-30 == 4 in float64); the distance ``eps = |E - 4|``, or
its logarithm, can. Every orbit in :mod:`rotorlib` is built from a
:class:`PendulumEnergy` or :class:`BreatherEnergy`, which keeps ``eps`` and
the complementary elliptic parameter ``m1`` exact to one rounding.

Accepted input (anything else raises ``ValueError`` with the reason):

* pendulum: ``E >= 0`` finite and ``E != 4``; or ``log|E - 4|`` finite with a
  phase, ``lib`` (then ``log|E - 4| <= log 4``, i.e. ``E >= 0``) or ``rot``.
  ``E = 0`` is the small-oscillation limit about G.
* breather: families ``LG`` (0 <= E < 4.5), ``LD`` (4 <= E < 4.5) and ``R``
  (E > 4.5); the distance is to the breather separatrix 4.5. ``E = 4.5``
  (heteroclinic orbit between the maxima T) is refused.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .system import BREATHER_SEPARATRIX_ENERGY, SEPARATRIX_ENERGY

__all__ = ["PendulumEnergy", "BreatherEnergy", "pendulum_energy", "breather_energy", "as_float"]

_PHASES = ("lib", "rot")
_FAMILIES = ("LG", "LD", "R")


def as_float(value, name: str) -> float:
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


@dataclass(frozen=True)
class PendulumEnergy:
    """Energy of a pendulum orbit, carried by its distance to the separatrix.

    Attributes
    ----------
    phase : {'lib', 'rot'}
        Libration (E < 4) or rotation (E > 4).
    eps : float
        ``|E - 4|`` (exact to one rounding however small).
    log_abs_dE : float
        ``log|E - 4|`` (natural log; ``-inf`` never occurs).
    E : float
        The energy in float64 (equal to 4.0 when ``eps < 1e-16``: use ``eps``).
    m, m1 : float
        Elliptic parameter of the closed form and ``1 - m``: ``m = E/4``,
        ``m1 = eps/4`` in libration; ``m = 4/E``, ``m1 = eps/E`` in rotation.
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

    def mp_values(self, dps: int) -> dict:
        """E, eps, m, m1 as mpmath numbers at ``dps`` digits, from the decimal input.

        The input is read as the decimal string the user gave (``repr`` of a
        float argument), so ``E=3.9`` means exactly 39/10 here.
        """
        import mpmath as mp

        with mp.workdps(dps):
            kind, text = self.given
            if kind == "E":
                E = mp.mpf(text)
                eps = abs(E - 4)
            else:
                eps = mp.exp(mp.mpf(text))
                E = 4 - eps if self.phase == "lib" else 4 + eps
            if self.phase == "lib":
                m1, m = eps / 4, E / 4
            else:
                m1, m = eps / E, 4 / E
            return dict(E=+E, eps=+eps, m=+m, m1=+m1)

    def decimal_E(self, digits: int = 17) -> str:
        """E as a decimal string with ``digits`` significant digits *after* the
        leading ``4.000…`` zeros, so that ``E - 4`` is visible however small."""
        import mpmath as mp

        extra = max(0, int(-self.log_abs_dE / math.log(10)) + 1)
        with mp.workdps(digits + extra + 10):
            return mp.nstr(self.mp_values(digits + extra + 10)["E"], digits + extra, strip_zeros=True)


def pendulum_energy(E=None, log_abs_dE=None, phase=None) -> PendulumEnergy:
    """Build a :class:`PendulumEnergy` from ``E`` or from ``log|E - 4|`` and a phase.

    Parameters
    ----------
    E : float, optional
        Relative energy (units m = g = r = 1).
    log_abs_dE : float, optional
        Natural log of the distance to the separatrix; needs ``phase``.
    phase : {'lib', 'rot'}, optional
        Required with ``log_abs_dE``; checked against ``E`` when both given.

    Raises
    ------
    ValueError
        Negative, non-finite or unparsable input; ``E == 4`` exactly; both or
        neither of ``E`` and ``log_abs_dE``; a phase other than lib/rot; a
        librational ``log|E-4| > log 4`` (negative energy); an ``eps`` that
        underflows float64 (``log|E-4| < -745``).
    """
    sep = SEPARATRIX_ENERGY
    if phase is not None and phase not in _PHASES:
        raise ValueError(f"phase must be 'lib' or 'rot', got {phase!r}")
    if (E is None) == (log_abs_dE is None):
        raise ValueError("give exactly one of E and log|E-4|")
    if E is not None:
        E = as_float(E, "E")
        if E < 0:
            raise ValueError(f"E must be >= 0 (the minimum of V is 0), got {E!r}")
        if E == sep:
            raise ValueError("E = 4 is the separatrix (homoclinic orbit): the period diverges; "
                             "give log|E-4| and a phase instead")
        ph = "lib" if E < sep else "rot"
        if phase is not None and phase != ph:
            raise ValueError(f"E = {E!r} is in the {ph} phase, not {phase!r}")
        eps = abs(E - sep)
        x = math.log(eps)
        given = ("E", repr(E))
    else:
        x = as_float(log_abs_dE, "log|E-4|")
        if phase is None:
            raise ValueError("log|E-4| needs a phase, 'lib' or 'rot'")
        ph = phase
        if ph == "lib" and x > math.log(sep):
            raise ValueError(f"libration has E = 4 - exp(log|E-4|) >= 0, so log|E-4| <= log 4 = "
                             f"{math.log(sep):.6f}; got {x!r}")
        eps = math.exp(x)
        if eps == 0.0 or not math.isfinite(eps):
            raise ValueError(f"log|E-4| = {x!r} is outside the float64 range of |E-4| "
                             "(|E-4| = exp(log|E-4|) must lie between 1e-323 and 1.8e308)")
        E = sep - eps if ph == "lib" else sep + eps
        given = ("log_abs_dE", repr(x))
    if ph == "lib":
        m1 = eps / 4.0
        m = E / 4.0
    else:
        m1 = eps / E
        m = sep / E
    return PendulumEnergy(ph, eps, x, E, m, m1, given)


@dataclass(frozen=True)
class BreatherEnergy:
    """Energy of an isosceles breather (phi1 = phi2 = phi).

    Attributes
    ----------
    family : {'LG', 'LD', 'R'}
        Libration about G, libration about D, or rotation.
    E : float
        Energy.
    eps : float
        ``|E - 4.5|``, the distance to the breather separatrix.
    """

    family: str
    E: float
    eps: float

    @property
    def phase(self) -> str:
        return "rot" if self.family == "R" else "lib"


def breather_energy(E=None, family=None, log_abs_dE=None) -> BreatherEnergy:
    """Build a :class:`BreatherEnergy`.

    Parameters
    ----------
    E : float, optional
        Energy; the family defaults to ``LG`` below 4.5 and ``R`` above.
    family : {'LG', 'LD', 'R'}, optional
    log_abs_dE : float, optional
        ``log|E - 4.5|`` instead of ``E`` (needs ``family``).

    Raises
    ------
    ValueError
        For energies the family does not have: ``R`` needs ``E > 4.5``, ``LG``
        ``0 <= E < 4.5``, ``LD`` ``4 <= E < 4.5``; ``E = 4.5`` exactly; negative
        or non-finite input; an unknown family.
    """
    sep = BREATHER_SEPARATRIX_ENERGY
    if family is not None and family not in _FAMILIES:
        raise ValueError(f"breather family must be one of LG, LD, R; got {family!r}")
    if (E is None) == (log_abs_dE is None):
        raise ValueError("give exactly one of E and log|E-4.5|")
    if E is None:
        x = as_float(log_abs_dE, "log|E-4.5|")
        if family is None:
            raise ValueError("log|E-4.5| needs a breather family (LG, LD or R)")
        eps = math.exp(x)
        if eps == 0.0 or not math.isfinite(eps):
            raise ValueError(f"log|E-4.5| = {x!r} is outside float64 range")
        E = sep + eps if family == "R" else sep - eps
    else:
        E = as_float(E, "E")
        eps = abs(E - sep)
    if E < 0:
        raise ValueError(f"E must be >= 0, got {E!r}")
    if E == sep:
        raise ValueError("E = 4.5 is the breather separatrix (heteroclinic orbit between the maxima T): "
                         "the period diverges")
    fam = family or ("R" if E > sep else "LG")
    if fam == "R" and E < sep:
        raise ValueError(f"the rotational breather R exists only for E > 4.5; got E = {E!r}")
    if fam in ("LG", "LD") and E > sep:
        raise ValueError(f"the librational breather {fam} exists only for E < 4.5; got E = {E!r}")
    if fam == "LD" and E < SEPARATRIX_ENERGY:
        raise ValueError(f"the breather LD (libration about D) exists only for 4 <= E < 4.5; got E = {E!r}")
    return BreatherEnergy(fam, E, eps)
