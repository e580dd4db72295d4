"""The 3-rotor energy as the energy of a three-junction flux qubit (paper Appendix A).

Mooij et al. (Science 285, 1036 (1999), eqs. (1), (3), (4)) write the Josephson
energy of a loop with junctions 1, 2 (Josephson energy ``Ej``, capacitance ``C``) and
3 (``alpha Ej``, ``alpha C``), threaded by a flux ``f`` flux quanta, as

    U = Ej [2 + alpha - cos phi1 - cos phi2 - alpha cos(2 pi f + phi1 - phi2)]

and the charging energy (gate capacitances ``gamma C``) as

    T = (C/2) (hbar/2e)^2 phidot^T [[1 + alpha + gamma, -alpha], [-alpha, 1 + alpha + gamma]] phidot.

Reversing the sign of ``phi2`` (the paper's convention) turns ``phi1 - phi2`` into
``phi1 + phi2`` and the off-diagonal ``-alpha`` into ``+alpha``. With ``alpha = 1``,
``f = 0``, ``gamma = 0``, ``Ej = g`` and ``m r^2 / 3 = C (hbar/2e)^2`` these become the
3-rotor potential ``g V(phi1, phi2)`` and the relative kinetic energy
``(m r^2/3)(phi1'^2 + phi2'^2 + phi1' phi2')``. :func:`rotor_energies` computes the
rotor side from the rotor angles ``theta_i`` directly (``sum m r^2 theta_i'^2 / 2``
minus the centre-of-mass part), so the comparison is between two independent
formulas. Everything is exact arithmetic up to rounding (~1e-15 relative).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.system import phi_to_theta

__all__ = [
    "josephson_energy",
    "charging_energy",
    "rotor_energies",
    "qubit_energies",
    "theta_from_phi",
]


def josephson_energy(
    phi1: Any,
    phi2: Any,
    Ej: float = 1.0,
    alpha: float = 1.0,
    f: float = 0.0,
    mooij_sign: bool = False,
) -> Any:
    """Josephson energy of the three-junction loop.

    ``mooij_sign=True`` uses Mooij's ``phi2`` (``cos(2 pi f + phi1 - phi2)``); the default
    uses the paper's reversed ``phi2`` (``cos(2 pi f + phi1 + phi2)``).
    """
    s = -1.0 if mooij_sign else 1.0
    return Ej * (
        2.0
        + alpha
        - np.cos(phi1)
        - np.cos(phi2)
        - alpha * np.cos(2 * np.pi * f + phi1 + s * phi2)
    )


def charging_energy(
    dphi1: Any,
    dphi2: Any,
    C: float = 1.0,
    alpha: float = 1.0,
    gamma: float = 0.0,
    hbar_over_2e: float = 1.0,
    mooij_sign: bool = False,
) -> Any:
    """Charging energy ``(C/2)(hbar/2e)^2 phidot^T Cmat phidot`` (up to the additive constant)."""
    off = -alpha if mooij_sign else alpha
    d = 1.0 + alpha + gamma
    return (
        0.5
        * C
        * hbar_over_2e**2
        * (d * dphi1**2 + 2.0 * off * dphi1 * dphi2 + d * dphi2**2)
    )


def rotor_energies(
    theta: Any, theta_dot: Any, m: float = 1.0, r: float = 1.0, g: float = 1.0
) -> Any:
    """Relative kinetic and potential energies of three rotors from their angles.

    Returns ``(T_rel, V)`` with ``T_rel = sum(m r^2 theta_i'^2)/2 - (3 m r^2/2) phi0'^2`` and
    ``V = g sum(1 - cos(theta_i - theta_j))`` over the three pairs.
    """
    theta = np.asarray(theta, float)
    w = np.asarray(theta_dot, float)
    t1, t2, t3 = np.moveaxis(theta, -1, 0)
    T = (
        0.5 * m * r * r * np.sum(w * w, axis=-1)
        - 1.5 * m * r * r * np.mean(w, axis=-1) ** 2
    )
    V = g * (3.0 - np.cos(t1 - t2) - np.cos(t2 - t3) - np.cos(t3 - t1))
    return T, V


def qubit_energies(
    phi: Any,
    phi_dot: Any,
    m: float = 1.0,
    r: float = 1.0,
    g: float = 1.0,
    alpha: float = 1.0,
    f: float = 0.0,
    gamma: float = 0.0,
    hbar_over_2e: float = 1.0,
) -> Any:
    """``(T, U)`` of the qubit at relative angles ``phi = (phi1, phi2)`` and their rates,
    with ``Ej = g`` and ``C = m r^2 / (3 (hbar/2e)^2)`` (the paper's identification)."""
    C = m * r * r / (3.0 * hbar_over_2e**2)
    phi = np.asarray(phi, float)
    phi_dot = np.asarray(phi_dot, float)
    U = josephson_energy(phi[..., 0], phi[..., 1], Ej=g, alpha=alpha, f=f)
    T = charging_energy(
        phi_dot[..., 0],
        phi_dot[..., 1],
        C=C,
        alpha=alpha,
        gamma=gamma,
        hbar_over_2e=hbar_over_2e,
    )
    return T, U


def theta_from_phi(phi0: Any, phi: Any, phi0_dot: Any, phi_dot: Any) -> Any:
    """Rotor angles and rates from the centre of mass and relative angles (via :mod:`rotorlib.core.system`)."""
    phi = np.asarray(phi, float)
    phi_dot = np.asarray(phi_dot, float)
    # phi_to_theta takes momenta P; build them from the rates: phidot = (2P1 - P2, 2P2 - P1)
    P1 = (2.0 * phi_dot[..., 0] + phi_dot[..., 1]) / 3.0
    P2 = (phi_dot[..., 0] + 2.0 * phi_dot[..., 1]) / 3.0
    state = np.stack([phi[..., 0], phi[..., 1], P1, P2], axis=-1)
    return phi_to_theta(phi0, phi0_dot, state)
