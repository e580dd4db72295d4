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

Precision: states are float64 closed forms; with :mod:`rotorlib.elliptic`
they keep ~1e-15 relative accuracy for any distance to the separatrix (the
energy residual is checked in ``tests/test_orbits.py``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .elliptic import dK_dm, ellipk_m1, jacobi_am, jacobi_sncndn
from .energy import BreatherEnergy, PendulumEnergy, breather_energy, pendulum_energy

__all__ = ["PendulumOrbit", "BreatherOrbit", "pendulum", "breather", "separatrix_pendulum_state"]

SQRT3 = math.sqrt(3.0)


@dataclass(frozen=True)
class PendulumOrbit:
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

    @property
    def E(self) -> float:
        return self.energy.E

    @property
    def K(self) -> float:
        """Complete elliptic integral K(m) of the closed form."""
        return ellipk_m1(self.energy.m1)

    @property
    def period(self) -> float:
        """Period: 4K/sqrt(3) (libration) or 2 kappa K/sqrt(3) (rotation)."""
        if self.energy.phase == "lib":
            return 4.0 * self.K / SQRT3
        return 2.0 * math.sqrt(self.energy.m) * self.K / SQRT3

    @property
    def dperiod_dE(self) -> float:
        """d(period)/dE, from dK/dm (closed form)."""
        en = self.energy
        dk = dK_dm(en.m, en.m1)
        if en.phase == "lib":
            return 4.0 / SQRT3 * dk / 4.0            # m = E/4
        kappa = math.sqrt(en.m)
        dm_dE = -en.m / en.E                         # m = 4/E
        return 2.0 / SQRT3 * (dk * kappa + self.K / (2.0 * kappa)) * dm_dE

    @property
    def state0(self) -> np.ndarray:
        """Initial state at G, ``[a1, a2, p1, p2] = [0, 0, 0, sqrt(4E/3)]``."""
        return np.array([0.0, 0.0, 0.0, math.sqrt(4.0 * self.E / 3.0)])

    def state(self, t) -> np.ndarray:
        """State ``[a1, a2, p1, p2]`` at times ``t`` (shape ``t.shape + (4,)``).

        In rotation ``a2`` is continuous (it grows by 2 pi per period).
        """
        t = np.asarray(t, dtype=float)
        en = self.energy
        if en.phase == "lib":
            k = math.sqrt(en.m)
            s, c, d = jacobi_sncndn(SQRT3 * t, en.m, en.m1)
            a2 = 2.0 * np.arctan2(k * s, d)          # cos(a2/2) = dn: exact at the turning point
            p2 = 4.0 / SQRT3 * k * c
        else:
            kappa = math.sqrt(en.m)
            u = SQRT3 * t / kappa
            _, _, d = jacobi_sncndn(u, en.m, en.m1)
            a2 = 2.0 * jacobi_am(u, en.m, en.m1)
            p2 = 4.0 / (SQRT3 * kappa) * d
        z = np.zeros_like(a2)
        return np.stack([z, a2, z, p2], axis=-1)


def separatrix_pendulum_state(t) -> np.ndarray:
    """The homoclinic pendulum at E = 4: sin(a2/2) = tanh(sqrt(3) t)."""
    t = np.asarray(t, dtype=float)
    a2 = 2.0 * np.arcsin(np.tanh(SQRT3 * t))
    p2 = 4.0 / SQRT3 / np.cosh(SQRT3 * t)
    z = np.zeros_like(a2)
    return np.stack([z, a2, z, p2], axis=-1)


def pendulum(E=None, log_abs_dE=None, phase=None) -> PendulumOrbit:
    """The pendulum orbit at ``E`` or at ``log|E-4|`` in a phase (see :func:`rotorlib.energy.pendulum_energy`)."""
    if isinstance(E, PendulumEnergy):
        return PendulumOrbit(E)
    return PendulumOrbit(pendulum_energy(E=E, log_abs_dE=log_abs_dE, phase=phase))


@dataclass(frozen=True)
class BreatherOrbit:
    """An isosceles breather phi1 = phi2 = phi (closed form).

    Attributes
    ----------
    energy : BreatherEnergy
    """

    energy: BreatherEnergy

    @property
    def E(self) -> float:
        return self.energy.E

    @property
    def family(self) -> str:
        return "breather-" + self.energy.family

    @property
    def params(self) -> dict:
        """Closed-form parameters: m, m1, nu and A (LG), D (LD) or lam (R)."""
        E, eps = self.energy.E, self.energy.eps
        if self.energy.family in ("LG", "LD"):
            S = math.sqrt(2.0 * eps)
            den = (1.0 + S) * (3.0 + S)
            p = dict(m=(1.0 - S) * (3.0 - S) / den, m1=8.0 * S / den, nu=0.5 * math.sqrt(den / 2.0))
            if self.energy.family == "LG":
                p["A"] = math.sqrt((3.0 - S) / (1.0 + S))
            else:
                p["D"] = math.sqrt(max(1.0 - S, 0.0) / (3.0 + S))
            return p
        Q = math.sqrt(E * (E - 4.0))
        if E < 6.0:
            m, m1 = (Q - E + 6.0) / (2.0 * Q), 4.0 * eps / (Q * (Q + 6.0 - E))
        else:
            m, m1 = 4.0 * eps / (Q * (Q + E - 6.0)), (Q + E - 6.0) / (2.0 * Q)
        return dict(m=m, m1=m1, nu=math.sqrt(Q), lam=(E / (E - 4.0)) ** 0.25)

    @property
    def K(self) -> float:
        return ellipk_m1(self.params["m1"])

    @property
    def period(self) -> float:
        """Period 4 K(m)/nu (phi advances by 2 pi per period in R)."""
        return 4.0 * self.K / self.params["nu"]

    @property
    def dperiod_dE(self) -> float:
        """d(period)/dE in closed form: tau = 4K(m)/nu with m(E), nu(E) as in the module docstring.

        ``dtau/dE = 4 (K'(m) m'(E) nu - K nu'(E)) / nu^2`` with ``dK/dm`` from
        :func:`rotorlib.elliptic.dK_dm`; float64 relative accuracy ~1e-15 away
        from E = 4.5 (it diverges there like the period's log).
        """
        E, eps = self.energy.E, self.energy.eps
        p = self.params
        m, m1, nu = p["m"], p["m1"], p["nu"]
        if self.energy.family in ("LG", "LD"):
            S = math.sqrt(2.0 * eps)
            N, D = (1.0 - S) * (3.0 - S), (1.0 + S) * (3.0 + S)
            dN, dD = 2.0 * S - 4.0, 2.0 * S + 4.0
            dS = -1.0 / S                                   # S = sqrt(9 - 2E)
            dm = (dN * D - N * dD) / (D * D) * dS
            dnu = dD / (8.0 * math.sqrt(D / 2.0)) * dS      # nu = sqrt(D/2)/2
        else:
            Q = math.sqrt(E * (E - 4.0))
            dQ = (E - 2.0) / Q
            dm = (-Q - (6.0 - E) * dQ) / (2.0 * Q * Q)      # m = 1/2 + (6 - E)/(2Q)
            dnu = dQ / (2.0 * math.sqrt(Q))                  # nu = sqrt(Q)
        K = ellipk_m1(m1)
        return 4.0 * (dK_dm(m, m1) * dm * nu - K * dnu) / (nu * nu)

    def phi(self, t):
        """phi(t) and phi'(t) of the breather."""
        t = np.asarray(t, dtype=float)
        p = self.params
        u = p["nu"] * t
        fam = self.energy.family
        s, c, d = jacobi_sncndn(u, p["m"], p["m1"])
        if fam == "LG":
            w = p["A"] * s
            return 2.0 * np.arctan(w), 2.0 * p["A"] * p["nu"] * c * d / (1.0 + w * w)
        if fam == "LD":
            v = p["D"] * s
            return np.pi - 2.0 * np.arctan(v), -2.0 * p["D"] * p["nu"] * c * d / (1.0 + v * v)
        lam, K = p["lam"], self.K
        j = np.round(u / (4.0 * K))
        r = u - 4.0 * K * j                          # theta = am(r) in [-pi, pi]
        far = np.abs(r) > K
        # for |r| > K use v = 2K - |r|: sn(r) = sign(r) sn(v), 1 + cn(r) = sn(v)^2 / (1 + cn(v))
        v = np.where(far, 2.0 * K - np.abs(r), r)
        s, c, d = jacobi_sncndn(v, p["m"], p["m1"])
        onep = np.where(far, s * s / (1.0 + c), 1.0 + c)     # 1 + cos(theta)
        onem = np.where(far, 1.0 + c, 1.0 - c)               # 1 - cos(theta)
        half = np.where(far, np.sign(r) * (np.pi / 2 - np.arctan2(np.abs(s), lam * (1.0 + c))),
                        np.arctan2(lam * s, 1.0 + c))
        dphi = 2.0 * lam * p["nu"] * d / (onep + lam * lam * onem)
        return 2.0 * np.pi * j + 2.0 * half, dphi

    @property
    def state0(self) -> np.ndarray:
        """Initial state ``[a1, a2, p1, p2]`` at the base point (G, or D for LD)."""
        return self.state(0.0)

    def state(self, t) -> np.ndarray:
        """State ``[a1, a2, p1, p2] = [phi/2, 3 phi/2, phi', phi']``."""
        f, df = self.phi(t)
        return np.stack([0.5 * f, 1.5 * f, df, df], axis=-1)

    def state_beta(self, t) -> np.ndarray:
        """State ``[b1, b2, q1, q2] = [2 phi, 0, phi', 0]`` (paper §8)."""
        f, df = self.phi(t)
        z = np.zeros_like(f)
        return np.stack([2.0 * f, z, df, z], axis=-1)


def breather(E=None, family=None, log_abs_dE=None) -> BreatherOrbit:
    """The isosceles breather of ``family`` (LG, LD, R) at energy ``E``."""
    if isinstance(E, BreatherEnergy):
        return BreatherOrbit(E)
    return BreatherOrbit(breather_energy(E=E, family=family, log_abs_dE=log_abs_dE))
