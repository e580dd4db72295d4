"""The 3-rotor system: potential, energy, equations of motion and coordinates.

Units m = g = r = 1; time is the paper's dimensionless t~ = t sqrt(g / m r^2).

Coordinates (paper §2, §4, §8):

* rotor angles ``theta = (theta1, theta2, theta3)``, ``L = sum(theta_i'^2)/2 - V``;
* centre of mass and relative angles ``phi0 = mean(theta)``,
  ``phi1 = theta1 - theta2``, ``phi2 = theta2 - theta3``;
* pendulum variables ``a1 = phi1/2``, ``a2 = phi1/2 + phi2`` with momenta
  ``p1 = 2 a1'``, ``p2 = (2/3) a2'`` (the paper's alpha_1, alpha_2, pi~_1, pi~_2):
  ``H = p1^2/4 + 3 p2^2/4 + 3 - cos 2a1 - cos(a2 - a1) - cos(a1 + a2)``;
* breather variables ``b1 = phi1 + phi2``, ``b2 = phi1 - phi2`` with momenta
  ``q1 = (P1 + P2)/2``, ``q2 = (P1 - P2)/2`` where ``P = (p~1, p~2)`` are the
  momenta conjugate to ``(phi1, phi2)`` (the paper's beta_i, pi_i):
  ``H = q1^2 + 3 q2^2 + 3 - cos((b1 + b2)/2) - cos((b1 - b2)/2) - cos b1``.

A state in pendulum variables is ordered ``[a1, a2, p1, p2]`` throughout
(the order of the book's *Numerical notes*, ``book/numerical_notes.md``); in breather variables
``[b1, b2, q1, q2]``; in relative variables ``[phi1, phi2, P1, P2]``.
All linear maps between them are exact (matrices with entries 0, ±1/2, ±1, 2),
so they introduce no error beyond one rounding.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import mpmath as mp
import numpy as np
from numpy.typing import ArrayLike

from .precision import Tier, tier

#: A float or an array of them (elementwise numpy functions).
Real = float | np.ndarray

__all__ = [
    "lattice_reduce",
    "potential_phi",
    "potential_alpha",
    "potential_beta",
    "potential_theta",
    "energy_alpha",
    "energy_phi",
    "energy_beta",
    "rhs_alpha",
    "rhs_beta",
    "rhs_phi",
    "jacobian_alpha",
    "alpha_to_phi",
    "phi_to_alpha",
    "phi_to_beta",
    "beta_to_phi",
    "alpha_to_beta",
    "beta_to_alpha",
    "theta_to_phi",
    "phi_to_theta",
    "CriticalPoint",
    "critical_points",
    "SEPARATRIX_ENERGY",
    "BREATHER_SEPARATRIX_ENERGY",
]

# Coordinate matrices: alpha = A phi, beta = B phi; momenta transform with A^{-T}, B^{-T}.
_A = np.array([[0.5, 0.0], [0.5, 1.0]])
_Ainv = np.array([[2.0, 0.0], [-1.0, 1.0]])
_B = np.array([[1.0, 1.0], [1.0, -1.0]])
_Binv = 0.5 * _B


def potential_phi(phi1: Real, phi2: Real) -> Real:
    """V(phi1, phi2) = 3 - cos phi1 - cos phi2 - cos(phi1 + phi2).

    Examples
    --------
    >>> import numpy as np
    >>> from rotorlib.core.system import potential_phi
    >>> float(potential_phi(np.pi, np.pi))  # the saddle D1: the separatrix energy
    4.0
    """
    return 3.0 - np.cos(phi1) - np.cos(phi2) - np.cos(phi1 + phi2)


def potential_theta(theta1: Real, theta2: Real, theta3: Real) -> Real:
    """V in rotor angles: 3 - cos(t1 - t2) - cos(t2 - t3) - cos(t3 - t1)."""
    return (
        3.0
        - np.cos(theta1 - theta2)
        - np.cos(theta2 - theta3)
        - np.cos(theta3 - theta1)
    )


def potential_alpha(a1: Real, a2: Real) -> Real:
    """V(a1, a2) = 3 - cos 2a1 - cos(a2 - a1) - cos(a1 + a2)."""
    return 3.0 - np.cos(2.0 * a1) - np.cos(a2 - a1) - np.cos(a1 + a2)


def potential_beta(b1: Real, b2: Real) -> Real:
    """V(b1, b2) = 3 - cos((b1 + b2)/2) - cos((b1 - b2)/2) - cos b1."""
    return 3.0 - np.cos(0.5 * (b1 + b2)) - np.cos(0.5 * (b1 - b2)) - np.cos(b1)


def energy_alpha(state: ArrayLike) -> Real:
    """Relative energy of a state ``[a1, a2, p1, p2]`` (last axis).

    Examples
    --------
    >>> from rotorlib.core.system import alpha_to_beta, alpha_to_phi, energy_alpha
    >>> from rotorlib.core.system import energy_beta, energy_phi
    >>> x = [0.3, 1.1, -0.2, 0.7]
    >>> pairs = [(energy_alpha, x), (energy_phi, alpha_to_phi(x))]
    >>> pairs.append((energy_beta, alpha_to_beta(x)))
    >>> [round(float(f(y)), 12) for f, y in pairs]
    [1.685490532843, 1.685490532843, 1.685490532843]
    """
    a1, a2, p1, p2 = np.moveaxis(np.asarray(state, dtype=float), -1, 0)
    return 0.25 * p1**2 + 0.75 * p2**2 + potential_alpha(a1, a2)


def energy_phi(state: ArrayLike) -> Real:
    """Relative energy of ``[phi1, phi2, P1, P2]``.

    The kinetic energy (phi1'^2 + phi2'^2 + phi1' phi2')/3 in momenta is P1^2 - P1 P2 + P2^2.
    """
    f1, f2, P1, P2 = np.moveaxis(np.asarray(state, dtype=float), -1, 0)
    return P1**2 - P1 * P2 + P2**2 + potential_phi(f1, f2)


def energy_beta(state: ArrayLike) -> Real:
    """Relative energy of a state ``[b1, b2, q1, q2]``."""
    b1, b2, q1, q2 = np.moveaxis(np.asarray(state, dtype=float), -1, 0)
    return q1**2 + 3.0 * q2**2 + potential_beta(b1, b2)


def rhs_alpha(t: float, state: Sequence[Any] | np.ndarray) -> np.ndarray:
    """Hamilton's equations in pendulum variables, ``d/dt [a1, a2, p1, p2]``.

    ``state`` holds float64 numbers (or arrays of them: the equations act elementwise),
    or a tier's ``mpmath.mpf`` numbers, evaluated in the current mpmath context (an
    object array of mpf then; the crossing directions and projections of
    :mod:`rotorlib.orbits.shooting`). The one statement of the equations outside heyoka's
    (:func:`rotorlib.core.flow.equations_of_motion`).

    Examples
    --------
    >>> import mpmath as mp
    >>> from rotorlib.core.system import rhs_alpha
    >>> rhs_alpha(0.0, [0.0, 0.0, 2.0, 2.0])  # at G: only the angles move
    array([ 1.,  3., -0., -0.])
    >>> with mp.workdps(30):  # dp2/dt = -2 sin 1 at a1 = 0, a2 = 1
    ...     print(mp.nstr(rhs_alpha(0.0, [0, mp.mpf(1), 0, 0])[3], 25))
    -1.682941969615793013305005
    """
    a1, a2, p1, p2 = state
    sin = mp.sin if any(isinstance(v, mp.mpf) for v in (a1, a2, p1, p2)) else np.sin
    s_m, s_p = sin(a2 - a1), sin(a1 + a2)
    # 0.5 p1 and 1.5 p2 round as p1 / 2 and 3 p2 / 2 do: a power of two scales exactly
    f = [0.5 * p1, 1.5 * p2, -(2.0 * sin(2.0 * a1) - s_m + s_p), -(s_m + s_p)]
    return np.array(f, dtype=object) if sin is mp.sin else np.array(f)


def jacobian_alpha(state: Sequence[float] | np.ndarray) -> np.ndarray:
    """Jacobian of :func:`rhs_alpha` (the variational matrix), shape (4, 4)."""
    a1, a2 = state[0], state[1]
    c_m = np.cos(a2 - a1)
    c_p = np.cos(a1 + a2)
    v11 = 4.0 * np.cos(2.0 * a1) + c_m + c_p  # d2V/da1^2
    v12 = -c_m + c_p  # d2V/da1 da2
    v22 = c_m + c_p  # d2V/da2^2
    return np.array(
        [
            [0.0, 0.0, 0.5, 0.0],
            [0.0, 0.0, 0.0, 1.5],
            [-v11, -v12, 0.0, 0.0],
            [-v12, -v22, 0.0, 0.0],
        ]
    )


def rhs_beta(t: float, state: Sequence[float] | np.ndarray) -> np.ndarray:
    """Hamilton's equations in breather variables (paper §8)."""
    b1, b2, q1, q2 = state
    sp = np.sin(0.5 * (b1 + b2))
    sm = np.sin(0.5 * (b1 - b2))
    return np.array(
        [2.0 * q1, 6.0 * q2, -0.5 * (sp + sm + 2.0 * np.sin(b1)), -0.5 * (sp - sm)]
    )


def rhs_phi(t: float, state: Sequence[float] | np.ndarray) -> np.ndarray:
    """Hamilton's equations in relative variables ``[phi1, phi2, P1, P2]``."""
    f1, f2, P1, P2 = state
    s12 = np.sin(f1 + f2)
    return np.array(
        [
            2.0 * P1 - P2,
            2.0 * P2 - P1,
            -(np.sin(f1) + s12),
            -(np.sin(f2) + s12),
        ]
    )


def lattice_reduce(
    d: np.ndarray | Sequence[Any], digits: int | Tier | None = None
) -> np.ndarray | list[Any]:
    """A difference of pendulum states (or of configurations) ``d = (da1, da2, ...)``
    reduced modulo the configuration lattice of ``(a1, a2)``, generated by ``(0, 2 pi)``
    and ``(pi, pi)`` (``book/numerical_notes.md``): ``da1`` into ``[-pi/2, pi/2]``, then
    ``da2`` into ``[-pi, pi]``; the momenta are left as they are.

    ``d`` is a float array (the last axis the state: one difference or many) or a
    sequence of tier numbers (float, real128 or mpmath: typed ``Any``), reduced in the tier
    of ``digits`` (:func:`~rotorlib.core.precision.tier`; a list is returned).

    Examples
    --------
    >>> import numpy as np
    >>> from rotorlib.core.system import lattice_reduce
    >>> lattice_reduce(np.array([np.pi + 0.1, 3 * np.pi - 0.2, 0.5, 0.0])).round(12)
    array([ 0.1, -0.2,  0.5,  0. ])
    """
    if isinstance(d, np.ndarray):
        out = np.array(d, dtype=float)
        out[..., :2] -= np.round(out[..., :1] / np.pi) * np.pi
        out[..., 1] -= 2 * np.pi * np.round(out[..., 1] / (2 * np.pi))
        return out
    t = tier(digits)
    with t.context():
        d, pi = list(d), t.pi
        k = round(float(d[0] / pi))
        d[0] -= k * pi
        d[1] -= k * pi
        d[1] -= 2 * pi * round(float(d[1] / (2 * pi)))
        return d


def _lin(state: ArrayLike, Q: np.ndarray, Pm: np.ndarray) -> np.ndarray:
    s = np.asarray(state, dtype=float)
    return np.concatenate(
        [
            np.einsum("ij,...j->...i", Q, s[..., :2]),  # the angles
            np.einsum("ij,...j->...i", Pm, s[..., 2:]),  # the momenta
        ],
        axis=-1,
    )


def phi_to_alpha(state: ArrayLike) -> np.ndarray:
    """``[phi1, phi2, P1, P2] -> [a1, a2, p1, p2]``."""
    return _lin(state, _A, _Ainv.T)


def alpha_to_phi(state: ArrayLike) -> np.ndarray:
    """``[a1, a2, p1, p2] -> [phi1, phi2, P1, P2]``.

    Examples
    --------
    >>> from rotorlib.core.system import alpha_to_phi, phi_to_alpha
    >>> alpha_to_phi([0.3, 1.1, -0.2, 0.7])
    array([0.6 , 0.8 , 0.25, 0.7 ])
    >>> phi_to_alpha(alpha_to_phi([0.3, 1.1, -0.2, 0.7])).round(12)
    array([ 0.3,  1.1, -0.2,  0.7])
    """
    return _lin(state, _Ainv, _A.T)


def phi_to_beta(state: ArrayLike) -> np.ndarray:
    """``[phi1, phi2, P1, P2] -> [b1, b2, q1, q2]``."""
    return _lin(state, _B, _Binv.T)


def beta_to_phi(state: ArrayLike) -> np.ndarray:
    """``[b1, b2, q1, q2] -> [phi1, phi2, P1, P2]``."""
    return _lin(state, _Binv, _B.T)


def alpha_to_beta(state: ArrayLike) -> np.ndarray:
    """``[a1, a2, p1, p2] -> [b1, b2, q1, q2]``."""
    return phi_to_beta(alpha_to_phi(state))


def beta_to_alpha(state: ArrayLike) -> np.ndarray:
    """``[b1, b2, q1, q2] -> [a1, a2, p1, p2]``."""
    return phi_to_alpha(beta_to_phi(state))


#: Rotor angles of zero mean from the relative ones: ``theta = phi0 + _C phi``.
_C = np.array([[2.0, 1.0], [-1.0, 1.0], [-1.0, -2.0]]) / 3.0
#: The kinetic metric, ``P = phi' _K``, and its inverse, ``phi' = P _K_INV``.
_K = np.array([[2.0, 1.0], [1.0, 2.0]]) / 3.0
_K_INV = np.array([[2.0, -1.0], [-1.0, 2.0]])


def theta_to_phi(
    theta: ArrayLike, theta_dot: ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rotor angles and velocities -> (``phi0``, ``phi0'``, ``[phi1, phi2, P1, P2]``).

    Examples
    --------
    >>> from rotorlib.core.system import phi_to_theta, theta_to_phi
    >>> phi0, phi0_dot, state = theta_to_phi([0.1, 0.2, 0.6], [1.0, 0.0, -1.0])
    >>> state.round(12)
    array([-0.1, -0.4,  1. ,  1. ])
    >>> phi_to_theta(phi0, phi0_dot, state)[0].round(12)
    array([0.1, 0.2, 0.6])
    """
    t, w = np.asarray(theta, dtype=float), np.asarray(theta_dot, dtype=float)
    phi, phi_dot = t[..., :2] - t[..., 1:], w[..., :2] - w[..., 1:]  # t1 - t2, t2 - t3
    return t.mean(-1), w.mean(-1), np.concatenate([phi, phi_dot @ _K], axis=-1)


def phi_to_theta(
    phi0: Real, phi0_dot: Real, state: ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`theta_to_phi`: returns ``(theta, theta_dot)``."""
    s = np.asarray(state, dtype=float)
    phi_dot = s[..., 2:] @ _K_INV  # (2 P1 - P2, 2 P2 - P1)
    return (
        np.asarray(phi0)[..., None] + s[..., :2] @ _C.T,
        np.asarray(phi0_dot)[..., None] + phi_dot @ _C.T,
    )


@dataclass(frozen=True)
class CriticalPoint:
    """A critical point of V on the (phi1, phi2) torus.

    Attributes
    ----------
    name : str
        ``G`` (minimum), ``T1``/``T2`` (maxima) or ``D1``/``D2``/``D3`` (saddles).
    phi : tuple of float
        Location (phi1, phi2) in [0, 2 pi)^2.
    energy : float
        V at the point.
    hessian_eigenvalues : tuple of float
        Eigenvalues of the Hessian of V in (phi1, phi2).
    kind : str
        ``minimum``, ``maximum`` or ``saddle``.
    """

    name: str
    phi: tuple[float, float]
    energy: float
    hessian_eigenvalues: tuple[float, ...]
    kind: str


def _grad_phi(x: np.ndarray) -> np.ndarray:
    f1, f2 = x
    s = np.sin(f1 + f2)
    return np.array([np.sin(f1) + s, np.sin(f2) + s])


def _hess_phi(x: np.ndarray) -> np.ndarray:
    f1, f2 = x
    c = np.cos(f1 + f2)
    return np.array([[np.cos(f1) + c, c], [c, np.cos(f2) + c]])


def critical_points(grid: int = 16) -> list[CriticalPoint]:
    """Locate and classify every critical point of V on the torus.

    Newton's method from a ``grid x grid`` set of starting points; duplicates
    are merged modulo 2 pi. Saddles are named D1 = (pi, pi), D2 = (pi, 0),
    D3 = (0, pi) and maxima T1, T2 by increasing phi1, as in the paper.

    Returns
    -------
    list of CriticalPoint
        Sorted by energy, then name.

    Examples
    --------
    >>> from rotorlib.core.system import critical_points
    >>> [(p.name, p.kind, round(p.energy, 12)) for p in critical_points()][::2]
    [('G', 'minimum', 0.0), ('D2', 'saddle', 4.0), ('T1', 'maximum', 4.5)]
    """
    from scipy import optimize  # (lazy: scipy.optimize is slow to import)

    found: list[np.ndarray] = []
    pts = np.linspace(0, 2 * np.pi, grid, endpoint=False) + 0.05
    for x0, y0 in itertools.product(pts, pts):
        sol = optimize.root(_grad_phi, [x0, y0], jac=_hess_phi, method="lm", tol=1e-15)
        if not sol.success or np.max(np.abs(_grad_phi(sol.x))) > 1e-12:
            continue
        x = np.mod(sol.x, 2 * np.pi)
        x = np.where(np.abs(x - 2 * np.pi) < 1e-9, 0.0, x)
        if not any(np.allclose(x, y, atol=1e-8) for y in found):
            found.append(x)
    points = []
    for x in found:
        ev = np.linalg.eigvalsh(_hess_phi(x))
        kind = "minimum" if ev.min() > 0 else ("maximum" if ev.max() < 0 else "saddle")
        at_pi = (
            bool(abs(x[0] - np.pi) < 1e-8),
            bool(abs(x[1] - np.pi) < 1e-8),
        )  # x is in [0, 2 pi)
        name = {"minimum": "G", "maximum": "T"}.get(kind) or (
            {(True, True): "D1", (True, False): "D2"}.get(at_pi, "D3")
        )
        points.append(
            CriticalPoint(
                name,
                (float(x[0]), float(x[1])),
                float(potential_phi(*x)),
                tuple(float(v) for v in ev),
                kind,
            )
        )
    maxima = sorted((p for p in points if p.kind == "maximum"), key=lambda p: p.phi[0])
    points = [
        replace(p, name=f"T{maxima.index(p) + 1}") if p in maxima else p for p in points
    ]
    return sorted(points, key=lambda p: (p.energy, p.name))


#: Energy of the saddles D (the pendulum separatrix), computed from V at (0, pi).
SEPARATRIX_ENERGY = float(potential_phi(0.0, np.pi))
#: Energy of the maxima T (the breather separatrix), computed from V at (2pi/3, 2pi/3).
BREATHER_SEPARATRIX_ENERGY = float(potential_phi(2 * np.pi / 3, 2 * np.pi / 3))
