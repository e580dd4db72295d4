"""tr M_perp of pendula from two Lamé solutions Lc, Ls (paper Appendix B).

Transverse perturbations of the pendulum obey the Lamé equation

    y''(z) + (h - n(n+1) k^2 sn^2(z, k)) y(z) = 0,   n(n+1) = 2/3,

with ``z = sqrt(3) t``, ``k^2 = E/4``, ``h = 1`` (libration, period ``4K`` in z) and
``z = sqrt(3) t / kappa``, ``k^2 = kappa^2 = 4/E``, ``h = k^2`` (rotation, period ``2K``).
If ``Lc`` and ``Ls`` are independent solutions with ``Ls(0) = 0`` and ``Lc'(0) = 0``
(normalised as one likes), the paper's formula is

    tr M_perp = [Ls(0) Lc'(w) - Ls'(0) Lc(w) - Ls'(w) Lc(0) + Ls(w) Lc'(0)] / W,

``w`` the period in ``z`` and ``W = Ls Lc' - Ls' Lc`` the (constant) Wronskian.
For small ``k^2`` the equation becomes Mathieu's ``y'' + (a - 2 q cos 2z) y = 0`` with
``a = h - n(n+1) k^2/2``, ``q = -n(n+1) k^2/4``.

These are direct integrations (scipy DOP853, rtol 1e-12, Jacobi sn from
:mod:`rotorlib.core.elliptic`), kept apart from the symmetry-reduced solver of
:mod:`rotorlib.orbits.hill` on purpose: Appendix B's formula is checked against
:func:`rotorlib.orbits.floquet.monodromy`. Accuracy ~1e-10 away from ``E = 4`` (this is the
textbook route; do not use it near the separatrix).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from ..core.elliptic import ellipk_m1, jacobi_sncndn
from ..core.energy import pendulum_energy

__all__ = [
    "LameSolutions",
    "lame_parameters",
    "lame_solutions",
    "trace_from_lame",
    "mathieu_solutions",
    "N_N1",
]

#: n(n+1) of the pendulum's Lamé equation.
N_N1 = 2.0 / 3.0


def lame_parameters(
    E: Any, phase: str | None = None
) -> tuple[float, float, float, float]:
    """``(h, k^2, 1 - k^2, w)`` of the pendulum's Lamé equation at energy ``E``; ``w`` is the period in z."""
    en = pendulum_energy(E=E, phase=phase)
    K = ellipk_m1(en.m1)
    if en.phase == "lib":
        return 1.0, en.m, en.m1, 4.0 * K
    return en.m, en.m, en.m1, 2.0 * K


@dataclass(frozen=True)
class LameSolutions:
    """Two Lamé solutions and their derivatives at ``z = 0`` and ``z = w``.

    Attributes
    ----------
    Lc0, dLc0, Ls0, dLs0 : float
        Values and z-derivatives at 0 (``dLc0 = Ls0 = 0``).
    Lcw, dLcw, Lsw, dLsw : float
        At ``z = w``.
    w : float
    """

    Lc0: float
    dLc0: float
    Ls0: float
    dLs0: float
    Lcw: float
    dLcw: float
    Lsw: float
    dLsw: float
    w: float

    @property
    def wronskian(self) -> float:
        return self.Ls0 * self.dLc0 - self.dLs0 * self.Lc0


def _solutions(coef, w, c_norm, s_norm) -> LameSolutions:
    """Integrate ``y'' = -coef(z) y`` for the cosine and sine solutions from 0 to ``w``."""
    sol = solve_ivp(
        lambda z, y: [y[1], -coef(z) * y[0], y[3], -coef(z) * y[2]],
        (0.0, w),
        [c_norm, 0.0, 0.0, s_norm],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
    )
    Lcw, dLcw, Lsw, dLsw = (float(v) for v in sol.y[:, -1])
    return LameSolutions(c_norm, 0.0, 0.0, s_norm, Lcw, dLcw, Lsw, dLsw, w)


def lame_solutions(
    h: float,
    k2: float,
    w: float,
    m1: float | None = None,
    c_norm: float = 2.0,
    s_norm: float = 3.0,
) -> LameSolutions:
    """Integrate ``Lc`` (``Lc(0) = c_norm``, ``Lc'(0) = 0``) and ``Ls`` (``Ls(0) = 0``,
    ``Ls'(0) = s_norm``) to ``w`` (scipy DOP853, rtol 1e-12: ~1e-10 in the trace).

    Examples
    --------
    >>> h, k2, m1, w = lame_parameters(3.5)
    >>> round(trace_from_lame(lame_solutions(h, k2, w, m1)), 10)
    0.4895306455
    """
    m1 = 1.0 - k2 if m1 is None else m1

    def coef(z):
        s, _, _ = jacobi_sncndn(np.array([z]), k2, m1)
        return h - N_N1 * k2 * float(s[0]) ** 2

    return _solutions(coef, w, c_norm, s_norm)


def mathieu_solutions(
    a: float, q: float, w: float, c_norm: float = 2.0, s_norm: float = 3.0
) -> LameSolutions:
    """The Mathieu cosine/sine solutions of ``y'' + (a - 2 q cos 2z) y = 0`` to ``w``
    (scipy DOP853, rtol 1e-12).

    Examples
    --------
    >>> import math
    >>> M = mathieu_solutions(1.0, 0.0, 2 * math.pi)  # q = 0: 2 cos z and 3 sin z
    >>> round(M.Lcw, 10), round(M.dLsw, 10)
    (2.0, 3.0)
    """
    return _solutions(lambda z: a - 2.0 * q * np.cos(2.0 * z), w, c_norm, s_norm)


def trace_from_lame(L: LameSolutions) -> float:
    """The paper's Appendix-B formula for ``tr M_perp``."""
    return (
        L.Ls0 * L.dLcw - L.dLs0 * L.Lcw - L.dLsw * L.Lc0 + L.Lsw * L.dLc0
    ) / L.wronskian
