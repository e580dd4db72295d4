"""Closed-form pendulum and isosceles-breather orbits (paper §2).

Pendulum (a1 = 0, ``a2'' = -3 sin a2``), base point G at t = 0 (a2 = 0, p2 > 0):

* libration, k^2 = m = E/4:  sin(a2/2) = k sn(sqrt(3) t | m),  period 4 K(m)/sqrt(3);
* separatrix E = 4:          sin(a2/2) = tanh(sqrt(3) t)          (not periodic);
* rotation, kappa^2 = m = 4/E:  a2 = 2 am(sqrt(3) t / kappa | m),  period 2 kappa K(m)/sqrt(3).

Isosceles breather phi1 = phi2 = phi (``phi'' = -(sin phi + sin 2 phi)``,
``E = phi'^2 + 3 - 2 cos phi - cos 2 phi``). With w = tan(phi/2) the energy
integral becomes ``(2 w')^2 = (E-4) w^4 + (2E-12) w^2 + E``, whose
factorisation gives, with ``S = sqrt(9 - 2E)`` (libration) and
``Q = sqrt(E (E - 4))`` (rotation):

* LG (libration about G, E < 4.5): ``w = A sn(nu t | m)``,
  ``A^2 = (3-S)/(1+S)``, ``m = (1-S)(3-S)/((1+S)(3+S))``,
  ``m1 = 8S/((1+S)(3+S))``, ``nu = sqrt((1+S)(3+S)/2)/2`` (m < 0 when E < 4);
* LD (libration about D, 4 <= E < 4.5): ``cot(phi/2) = D sn(nu t | m)``,
  ``D^2 = (1-S)/(3+S)``, same m and nu (so LG and LD have equal periods);
* R (rotation, E > 4.5): ``tan(phi/2) = lam tan(am(nu t | m)/2)``,
  ``lam = (E/(E-4))^(1/4)``, ``nu = sqrt(Q)``, ``m = (Q - E + 6)/(2Q)``,
  ``m1 = 4 (E - 4.5)/(Q (Q + 6 - E))``.

All periods are ``4 K(m)/nu``. Base points: G for LG and R, D for LD.

Precision: states are float64 closed forms; with :mod:`rotorlib.core.elliptic`
they keep ~1e-15 relative accuracy for any distance to the separatrix down to
``|E - sep| = 1.8e-307`` (the energy residual is checked in
``tests/test_orbits.py``). ``closed_form(digits)`` gives the parameters, K, the
period and its derivative in mpmath at ``digits`` digits from the decimal input,
at any depth; the float64 ``K``, ``period`` and ``dperiod_dE`` use it beyond
the float64 range of ``eps``.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import mpmath as mp
import numpy as np

from .elliptic import dK_dm, ellipk_m1, jacobi_am, jacobi_sncndn, mp_dK_dm, mp_ellipk_m1
from .energy import BreatherEnergy, PendulumEnergy, breather_energy, pendulum_energy
from .precision import Tier

__all__ = [
    "PendulumOrbit",
    "BreatherOrbit",
    "pendulum",
    "breather",
    "separatrix_pendulum_state",
]

SQRT3 = math.sqrt(3.0)
#: Digits used for the float64 view of K, period and d(period)/dE beyond the float64 range of eps.
_DEEP_DPS = 30


def _working_dps(digits: int | Tier | None) -> int | None:
    """mpmath working digits of the closed forms: ``digits`` itself, a Tier's ``dps``,
    ``None`` for float64."""
    if isinstance(digits, Tier):
        return digits.dps if digits.extended else None
    return None if digits is None else int(digits)


class _ClosedForm:
    """The closed form written once, for float64 and mpmath, and its float64 views."""

    energy: PendulumEnergy | BreatherEnergy
    # each orbit's formulas (float64 or mpmath: ``sqrt`` is math's or mpmath's)
    _parameters: Callable[[int | None, Any], dict]
    _period: Callable[[dict, Any], Any]
    _dperiod_dE: Callable[[dict, Any, Any], Any]

    def closed_form(
        self, digits: int | Tier | None = None, derivative: bool = False
    ) -> dict:
        """E, eps, the parameters (m, m1, ...), K, period (and with ``derivative``
        d(period)/dE) of the closed form.

        Parameters
        ----------
        digits : int or Tier, optional
            ``None``: float64 (~1e-16 relative at any ``|E - sep| >= 1.8e-307``,
            refused below with ``ValueError``). An integer: mpmath numbers correct to
            ``digits`` digits (the working precision), built from the decimal input at
            any depth; a :class:`~rotorlib.core.precision.Tier`: its working digits.
        derivative : bool
            Also return ``dperiod_dE``.

        Notes
        -----
        Pendulum: period ``4K/sqrt3`` (libration, ``m = E/4``) or ``2 kappa K/sqrt3``
        (rotation, ``m = kappa^2 = 4/E``); ``dK/dm`` by chain rule. Breather:
        ``tau = 4K(m)/nu``, ``dtau/dE = 4 (K'(m) m'(E) nu - K nu'(E)) / nu^2`` with
        ``m(E)``, ``nu(E)`` from the module docstring (it diverges at 4.5 like the
        period's log). ``K`` and ``dK/dm`` come from :mod:`rotorlib.core.elliptic` in
        float64, from ``mp_ellipk_m1``/``mp_dK_dm`` in mpmath: the float64 and the
        extended-precision values follow the same formulas.

        Examples
        --------
        >>> import mpmath
        >>> from rotorlib.core.closed_forms import pendulum
        >>> cf = pendulum(E=3.9).closed_form(30, derivative=True)
        >>> mpmath.nstr(cf["period"], 25), round(float(cf["dperiod_dE"]), 6)
        ('7.493684782180075798697786', 11.289633)
        """
        dps = _working_dps(digits)
        if dps is None:
            self.energy.require_float64()
            sqrt, ellipk, dkdm, ctx = (
                math.sqrt,
                ellipk_m1,
                dK_dm,
                contextlib.nullcontext(),
            )
        else:
            sqrt, ellipk, dkdm, ctx = mp.sqrt, mp_ellipk_m1, mp_dK_dm, mp.workdps(dps)
        with ctx:
            p = self._parameters(dps, sqrt)
            p["K"] = ellipk(p["m1"])
            p["period"] = self._period(p, sqrt)
            if derivative:
                p["dperiod_dE"] = self._dperiod_dE(p, dkdm(p["m"], p["m1"]), sqrt)
        return p

    def _view(self, key, derivative=False):
        # inside the float64 range: the float64 closed form; beyond it (eps underflows)
        # the mpmath one at _DEEP_DPS digits, converted (d(period)/dE ~ 1/eps may be inf)
        if self.energy.in_float64_range:
            return self.closed_form(derivative=derivative)[key]
        return float(self.closed_form(_DEEP_DPS, derivative=derivative)[key])

    @property
    def E(self) -> float:
        """The energy in float64 (see ``energy`` for its distance to the separatrix)."""
        return self.energy.E

    @property
    def K(self) -> float:
        """Complete elliptic integral K(m) of the closed form."""
        return self._view("K")

    @property
    def period(self) -> float:
        return self._view("period")

    @property
    def dperiod_dE(self) -> float:
        """d(period)/dE in closed form (float64; ``inf`` when it overflows, |E - sep| < ~1e-308)."""
        return self._view("dperiod_dE", derivative=True)


@dataclass(frozen=True)
class PendulumOrbit(_ClosedForm):
    """The pendulum a1 = 0 at a given energy (closed form).

    Attributes
    ----------
    energy : PendulumEnergy
        Energy with its distance to the separatrix.
    """

    energy: PendulumEnergy

    @property
    def family(self) -> str:
        return "pendulum"

    def _parameters(self, dps, sqrt):
        en = self.energy
        if dps is None:
            return dict(E=en.E, eps=en.eps, m=en.m, m1=en.m1)
        return en.mp_values(dps)

    def _period(self, p, sqrt):
        if self.energy.phase == "lib":
            return 4 * p["K"] / sqrt(3)
        return 2 * sqrt(p["m"]) * p["K"] / sqrt(3)  # 2 kappa K / sqrt3

    def _dperiod_dE(self, p, dk, sqrt):
        if self.energy.phase == "lib":  # m = E/4
            return dk / sqrt(3)
        kappa = sqrt(p["m"])  # m = 4/E
        return 2 / sqrt(3) * (dk * kappa + p["K"] / (2 * kappa)) * (-p["m"] / p["E"])

    @property
    def state0(self) -> np.ndarray:
        """Initial state at G, ``[a1, a2, p1, p2] = [0, 0, 0, sqrt(4E/3)]``."""
        return np.array([0.0, 0.0, 0.0, math.sqrt(4.0 * self.E / 3.0)])

    def state(self, t: Any) -> np.ndarray:
        """State ``[a1, a2, p1, p2]`` at times ``t`` (shape ``t.shape + (4,)``); float64 range only.

        In rotation ``a2`` is continuous (it grows by 2 pi per period).
        """
        t = np.asarray(t, dtype=float)
        en = self.energy
        en.require_float64()
        k = math.sqrt(en.m)  # k (libration) or kappa (rotation)
        if en.phase == "lib":
            s, c, d = jacobi_sncndn(SQRT3 * t, en.m, en.m1)
            a2 = 2.0 * np.arctan2(
                k * s, d
            )  # cos(a2/2) = dn: exact at the turning point
            p2 = 4.0 / SQRT3 * k * c
        else:
            u = SQRT3 * t / k
            _, _, d = jacobi_sncndn(u, en.m, en.m1)
            a2 = 2.0 * jacobi_am(u, en.m, en.m1)
            p2 = 4.0 / (SQRT3 * k) * d
        z = np.zeros_like(a2)
        return np.stack([z, a2, z, p2], axis=-1)


def separatrix_pendulum_state(t: Any) -> np.ndarray:
    """The homoclinic pendulum at E = 4: sin(a2/2) = tanh(sqrt(3) t)."""
    t = np.asarray(t, dtype=float)
    a2 = 2.0 * np.arcsin(np.tanh(SQRT3 * t))
    p2 = 4.0 / SQRT3 / np.cosh(SQRT3 * t)
    z = np.zeros_like(a2)
    return np.stack([z, a2, z, p2], axis=-1)


def pendulum(
    E: Any = None, log_abs_dE: Any = None, phase: str | None = None
) -> PendulumOrbit:
    """The pendulum orbit at ``E`` or at ``log|E-4|`` in a phase (see
    :func:`rotorlib.core.energy.pendulum_energy`): the closed form, float64 to ~1e-16
    relative at any ``|E - 4| >= 1.8e-307``, mpmath at any depth
    (``PendulumOrbit.closed_form``).

    Examples
    --------
    >>> from rotorlib.core.closed_forms import pendulum
    >>> o = pendulum(E=3.9)
    >>> o.energy.phase, round(o.period, 9), [round(float(v), 9) for v in o.state0]
    ('lib', 7.493684782, [0.0, 0.0, 0.0, 2.28035085])
    >>> pendulum(log_abs_dE=-30, phase="rot").energy.decimal_E(5)
    '4.000000000000093576'
    """
    if isinstance(E, PendulumEnergy):
        return PendulumOrbit(E)
    return PendulumOrbit(pendulum_energy(E=E, log_abs_dE=log_abs_dE, phase=phase))


def _breather_params(family, E, eps, sqrt) -> dict:
    """m, m1, nu and shape (A^2 for LG, D^2 for LD, lam^2 for R) from ``E`` and ``eps = |E - 4.5|``.

    Written without cancellation (module docstring identities
    ``1 - S = 2(E - 4)/(1 + S)``, ``3 - S = 2E/(3 + S)``, ``Q^2 - (6 - E)^2 = 8 eps``),
    so every parameter has the relative accuracy of the arithmetic (float64 or
    mpmath) at any distance to 4.5 and down to E = 0.
    """
    if family in ("LG", "LD"):
        S = sqrt(2 * eps)
        den = (1 + S) * (3 + S)
        # A^2 = (3 - S)/(1 + S) = 2E/den (LG), D^2 = (1 - S)/(3 + S) = 2(E - 4)/den (LD)
        shape = 2 * (E if family == "LG" else E - 4) / den
        return dict(
            m=4 * E * (E - 4) / (den * den),
            m1=8 * S / den,
            nu=sqrt(den / 2) / 2,
            shape=shape,
        )
    Q = sqrt(E * (E - 4))
    if E < 6:
        m, m1 = (Q - E + 6) / (2 * Q), 4 * eps / (Q * (Q + 6 - E))
    else:
        m, m1 = 4 * eps / (Q * (Q + E - 6)), (Q + E - 6) / (2 * Q)
    return dict(m=m, m1=m1, nu=sqrt(Q), shape=sqrt(E / (E - 4)))  # shape = lam^2


@dataclass(frozen=True)
class BreatherOrbit(_ClosedForm):
    """An isosceles breather phi1 = phi2 = phi (closed form).

    Attributes
    ----------
    energy : BreatherEnergy
    """

    energy: BreatherEnergy

    @property
    def family(self) -> str:
        return "breather-" + self.energy.family

    @property
    def params(self) -> dict:
        """Closed-form parameters in float64: m, m1, nu and shape (A^2, D^2 or lam^2)."""
        en = self.energy
        en.require_float64()
        return _breather_params(en.family, en.E, en.eps, math.sqrt)

    def _parameters(self, dps, sqrt):
        en = self.energy
        E, eps = (en.E, en.eps) if dps is None else en.mp_E_eps(dps + 5)
        return dict(_breather_params(en.family, E, eps, sqrt), E=E, eps=eps)

    def _period(self, p, sqrt):
        return 4 * p["K"] / p["nu"]

    def _dperiod_dE(self, p, dk, sqrt):
        m, nu, E, eps = p["m"], p["nu"], p["E"], p["eps"]
        if self.energy.family in ("LG", "LD"):
            S = sqrt(2 * eps)
            D = (1 + S) * (3 + S)
            dS = -1 / S  # S = sqrt(9 - 2E)
            dD = 2 * S + 4
            dN = 2 * S - 4  # N = (1 - S)(3 - S) = m D
            dm = (dN * D - m * D * dD) / (D * D) * dS
            dnu = dD / (8 * sqrt(D / 2)) * dS  # nu = sqrt(D/2)/2
        else:
            Q = sqrt(E * (E - 4))
            dQ = (E - 2) / Q
            dm = (-Q - (6 - E) * dQ) / (2 * Q * Q)  # m = 1/2 + (6 - E)/(2Q)
            dnu = dQ / (2 * sqrt(Q))  # nu = sqrt(Q)
        return 4 * (dk * dm * nu - p["K"] * dnu) / (nu * nu)

    def phi(self, t: Any) -> tuple[np.ndarray, np.ndarray]:
        """phi(t) and phi'(t) of the breather."""
        t = np.asarray(t, dtype=float)
        p = self.params
        u = p["nu"] * t
        fam = self.energy.family
        if fam != "R":  # w = tan(phi/2) = A sn (LG); cot(phi/2) = D sn (LD)
            a = np.sqrt(p["shape"])  # A or D
            s, c, d = jacobi_sncndn(u, p["m"], p["m1"])
            w = a * s
            f, df = 2.0 * np.arctan(w), 2.0 * a * p["nu"] * c * d / (1.0 + w * w)
            return (f, df) if fam == "LG" else (np.pi - f, -df)
        lam, K = np.sqrt(p["shape"]), self.K
        j = np.round(u / (4.0 * K))
        r = u - 4.0 * K * j  # theta = am(r) in [-pi, pi]
        far = np.abs(r) > K
        # for |r| > K use v = 2K - |r|: sn(r) = sign(r) sn(v), 1 + cn(r) = sn(v)^2 / (1 + cn(v))
        v = np.where(far, 2.0 * K - np.abs(r), r)
        s, c, d = jacobi_sncndn(v, p["m"], p["m1"])
        onep = np.where(far, s * s / (1.0 + c), 1.0 + c)  # 1 + cos(theta)
        onem = np.where(far, 1.0 + c, 1.0 - c)  # 1 - cos(theta)
        half = np.where(
            far,
            np.sign(r) * (np.pi / 2 - np.arctan2(np.abs(s), lam * (1.0 + c))),
            np.arctan2(lam * s, 1.0 + c),
        )
        dphi = 2.0 * lam * p["nu"] * d / (onep + lam * lam * onem)
        return 2.0 * np.pi * j + 2.0 * half, dphi

    @property
    def state0(self) -> np.ndarray:
        """Initial state ``[a1, a2, p1, p2]`` at the base point (G, or D for LD)."""
        return self.state(0.0)

    def state(self, t: Any) -> np.ndarray:
        """State ``[a1, a2, p1, p2] = [phi/2, 3 phi/2, phi', phi']``."""
        f, df = self.phi(t)
        return np.stack([0.5 * f, 1.5 * f, df, df], axis=-1)

    def state_beta(self, t: Any) -> np.ndarray:
        """State ``[b1, b2, q1, q2] = [2 phi, 0, phi', 0]`` (paper §8)."""
        f, df = self.phi(t)
        z = np.zeros_like(f)
        return np.stack([2.0 * f, z, df, z], axis=-1)


def breather(
    E: Any = None, family: str | None = None, log_abs_dE: Any = None
) -> BreatherOrbit:
    """The isosceles breather of ``family`` (LG, LD, R) at energy ``E`` (or at
    ``log|E - 4.5|``; see :func:`rotorlib.core.energy.breather_energy`): the closed form.

    Examples
    --------
    >>> from rotorlib.core.closed_forms import breather
    >>> b = breather(E=9.0)
    >>> b.family, round(b.period, 9), [float(v) for v in b.state0]
    ('breather-R', 2.62597978, [0.0, 0.0, 3.0, 3.0])
    >>> breather(E=2.0).family
    'breather-LG'
    """
    if isinstance(E, BreatherEnergy):
        return BreatherOrbit(E)
    return BreatherOrbit(breather_energy(E=E, family=family, log_abs_dE=log_abs_dE))
