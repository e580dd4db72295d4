"""Complete elliptic integrals and Jacobi functions near the separatrix.

Every routine here takes the *complementary* parameter ``m1 = 1 - m`` as an
input in its own right, so that it stays accurate when ``m`` is so close to 1
that ``1 - m`` is not representable from ``m`` (the separatrix limit
``E -> 4`` of the pendulum, where ``m1 = |E - 4| / 4`` or ``|E - 4| / E``).

Precision
---------
float64 throughout, except ``mp_ellipk_m1`` and ``mp_dK_dm`` (mpmath, at the
working precision, for the extended tiers and for depths beyond float64).
``ellipk_m1`` and ``dK_dm`` use scipy's Cephes routines (relative error ~1e-16).
``jacobi_sncndn`` reduces the argument to ``[0, K/2]`` with the quarter-period
symmetries, then for ``m < 1/2`` calls ``scipy.special.ellipj`` (the descending
arithmetic-geometric mean, Abramowitz & Stegun 16.4) and for ``m >= 1/2`` runs the
AGM itself on Jacobi's imaginary transformation, started from ``sqrt(m1)``: measured
absolute error ~1e-16 in sn, cn, dn for any ``m1`` down to 1e-300 (see
``tests/test_elliptic.py``). ``scipy.special.ellipj`` is *not* used there: for
``m >= 1 - 1e-10`` it switches to an approximation valid only for ``u < K`` (scipy
issue #8480), and ``1 - m`` would lose the digits of ``m1``.
"""

from __future__ import annotations

from typing import Any

import mpmath as mp
import numpy as np
from scipy import special

__all__ = [
    "ellipk_m1",
    "dK_dm",
    "jacobi_sncndn",
    "jacobi_am",
    "mp_ellipk_m1",
    "mp_dK_dm",
]


def ellipk_m1(m1: float) -> float:
    """Complete elliptic integral K(m) given the complementary parameter m1 = 1 - m.

    Valid for any ``m1 > 0`` (``m`` may be negative, i.e. ``m1 > 1``).
    """
    return float(special.ellipkm1(m1))


def dK_dm(m: float, m1: float) -> float:
    """Derivative dK/dm = (E - m1 K) / (2 m m1), with a series near m = 0."""
    if abs(m) < 1e-3:
        c = [19845 / 65536, 1225 / 4096, 75 / 256, 9 / 32, 1 / 4]  # m^4 ... m^0
        return float(np.pi / 2 * np.polyval(c, m))
    # E(m) from scipy's ellipe on m = 1 - m1: the rounding error of m enters only times
    # dE/dm, logarithmically small as m1 -> 0 (E = 1 + (m1/2)(log(4/sqrt m1) - 1/2)
    # + O(m1^2 log m1)): ~1e-16 |log m1|.
    E = float(special.ellipe(1.0 - m1))
    return (E - m1 * ellipk_m1(m1)) / (2.0 * m * m1)


def mp_ellipk_m1(m1: Any) -> Any:
    """K(m) in mpmath from the complementary parameter: ``pi / (2 agm(1, sqrt(m1)))``.

    Correct to the working precision for any ``m1 > 0`` (``m < 1``, negative
    ``m`` included) however small ``m1`` is: ``1 - m`` is never formed, so no
    guard digits are needed near the separatrix (``m1 = 1e-4343`` costs
    nothing extra).
    """
    return mp.pi / (2 * mp.agm(1, mp.sqrt(m1)))


def mp_dK_dm(m: Any, m1: Any) -> Any:
    """dK/dm in mpmath, correct to the working precision for any ``m < 1``.

    ``(E(m) - m1 K(m)) / (2 m m1)`` for ``|m| >= 1/2`` (near the separatrix, any
    small ``m1``, where :func:`dK_dm` overflows float64); for ``|m| < 1/2`` the
    derivative of ``K = (pi/2) 2F1(1/2, 1/2; 1; m)``, ``(pi/8) 2F1(3/2, 3/2; 2; m)``
    (mpmath's hypergeometric series: no cancellation as ``m -> 0``).

    Examples
    --------
    >>> import mpmath
    >>> mpmath.nstr(mp_dK_dm(mpmath.mpf(0), mpmath.mpf(1)), 15)  # pi/8
    '0.392699081698724'
    """
    if abs(m) >= 0.5:
        return (mp.ellipe(m) - m1 * mp_ellipk_m1(m1)) / (2 * m * m1)
    return mp.pi / 8 * mp.hyp2f1(1.5, 1.5, 2, m)


def _asinh_c_sinh(c, psi):
    """arcsinh(c * sinh(psi)) for c >= 0, psi >= 0, without overflow."""
    big = psi > 600.0
    small = np.where(big, 0.0, psi)
    direct = np.arcsinh(c * np.sinh(small))
    if c == 0.0 or not np.any(big):
        return direct
    # log y = log c + psi - log 2 ; arcsinh(y) = log y + log(1 + sqrt(1 + y**-2))
    logy = np.log(c) + np.where(big, psi, 0.0) - np.log(2.0)
    tail = np.where(
        logy > 40.0,
        np.log(2.0),
        np.log1p(np.sqrt(1.0 + np.exp(-2.0 * np.minimum(logy, 40.0)))),
    )
    viaLog = np.where(logy < -40.0, np.exp(logy), logy + tail)
    return np.where(big, viaLog, direct)


def _agm_sncndn_imag(u, m, m1):
    """sn, cn, dn for 0 <= u <= K/2 and 1/2 <= m < 1 (near the separatrix).

    Jacobi's imaginary transformation, sn(u|m) = -i sc(iu|m1), cn(u|m) =
    nc(iu|m1), dn(u|m) = dc(iu|m1), with the AGM run on the *small* parameter
    m1 (a0 = 1, b0 = sqrt(m), c0 = sqrt(m1)). On the imaginary axis the
    amplitudes are i*psi_n with psi_{n-1} = (psi_n + arcsinh(c_n/a_n sinh psi_n))/2,
    all real and well conditioned; then sn = tanh psi_0, cn = sech psi_0,
    dn = sech(psi_1 - psi_0): relative accuracy ~1e-16 in all three.
    """
    u = np.asarray(u, dtype=float)
    umax = float(np.max(u)) if u.size else 0.0
    a = [1.0]
    c = [np.sqrt(m1)]
    b = np.sqrt(m)
    while len(a) < 40:
        an = 0.5 * (a[-1] + b)
        cn = c[-1] ** 2 / (4.0 * an)
        b = np.sqrt(a[-1] * b)
        a.append(an)
        c.append(cn)
        n = len(a) - 1
        psi_top = (2.0**n) * an * umax
        if cn == 0.0 or np.log(cn / an) + min(psi_top, 1e300) < np.log(1e-18):
            break
    psi = (2.0**n) * a[-1] * u  # n >= 1: the loop runs at least once
    for j in range(n, 0, -1):
        prev = psi
        psi = 0.5 * (psi + _asinh_c_sinh(c[j] / a[j], psi))
    return np.tanh(psi), 1.0 / np.cosh(psi), 1.0 / np.cosh(prev - psi)


def _sncndn_nonneg(u, m, m1):
    """sn, cn, dn for 0 <= m < 1 and any real u (vectorised)."""
    u = np.asarray(u, dtype=float)
    K = ellipk_m1(m1)
    sgn = np.where(u < 0, -1.0, 1.0)
    r = np.mod(np.abs(u), 4.0 * K)
    # half-period shift: sn(u + 2K) = -sn(u), cn(u + 2K) = -cn(u)
    upper = r >= 2.0 * K
    r = np.where(upper, r - 2.0 * K, r)
    # reflection about K: sn(2K - u) = sn(u), cn(2K - u) = -cn(u)
    refl = r > K
    r = np.where(refl, 2.0 * K - r, r)
    # now 0 <= r <= K; near K use v = K - r: sn = cd(v), cn = k' sd(v), dn = k' nd(v)
    near = r > 0.5 * K
    v = np.where(near, K - r, r)
    if m >= 0.5:
        s, c, d = _agm_sncndn_imag(v, m, m1)
    else:  # 1 - m is exact enough: scipy's ellipj (Cephes, the descending AGM of A&S 16.4)
        s, c, d, _ = special.ellipj(v, m)
    kp = np.sqrt(m1)
    sn = np.where(near, c / d, s)
    cn = np.where(near, kp * s / d, c)
    dn = np.where(near, kp / d, d)
    cn = np.where(
        refl != upper, -cn, cn
    )  # -cn under the reflection and under the shift
    return np.where(upper, -sgn, sgn) * sn, cn, dn


def jacobi_sncndn(
    u: Any, m: float, m1: float | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Jacobi elliptic functions sn, cn, dn of argument ``u`` and parameter ``m``.

    Parameters
    ----------
    u : float or array_like
        Argument.
    m : float
        Parameter (``m = k**2``), ``m < 1``; negative ``m`` is allowed.
    m1 : float, optional
        Complementary parameter ``1 - m``. Pass it whenever ``m`` is close to 1:
        it is the quantity that carries the distance to the separatrix.

    Returns
    -------
    sn, cn, dn : ndarray
        Absolute error ~1e-16 for every ``m1 > 0`` representable in float64.

    Raises
    ------
    ValueError
        If ``m1 <= 0`` (the separatrix ``m = 1`` is not periodic) or not finite.
    """
    if m1 is None:
        m1 = 1.0 - m
    if not (np.isfinite(m1) and m1 > 0):
        raise ValueError(f"jacobi_sncndn needs 0 < m1 = 1 - m finite, got m1 = {m1!r}")
    if m < 0:
        # A&S 16.10: reciprocal-parameter transformation to mu = -m / (1 - m) in [0, 1)
        mu = -m / m1
        mu1 = 1.0 / m1
        v = np.asarray(u, dtype=float) * np.sqrt(m1)
        s, c, d = _sncndn_nonneg(v, mu, mu1)
        return s / d / np.sqrt(m1), c / d, 1.0 / d
    return _sncndn_nonneg(u, m, m1)


def jacobi_am(u: Any, m: float, m1: float | None = None) -> np.ndarray:
    """Jacobi amplitude am(u | m), continuous in ``u`` (0 <= m < 1)."""
    if m1 is None:
        m1 = 1.0 - m
    u = np.asarray(u, dtype=float)
    K = ellipk_m1(m1)
    j = np.round(u / (2.0 * K))
    r = u - 2.0 * K * j
    s, c, _ = jacobi_sncndn(r, m, m1)
    return j * np.pi + np.arctan2(s, c)
