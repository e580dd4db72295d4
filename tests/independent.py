"""Independent references for tr M: the textbook 4x4 route from a state and period built in mpmath.

Nothing here goes through rotorlib's energy objects, closed-form parameters or
the Hill reduction: the energy is ``sep -/+ exp(x)`` computed from the
decimal ``x = log|E - sep|`` in mpmath, the period is ``K(m)`` from
``mpmath.ellipk`` with ``m`` from the textbook formula (``1 - m`` *is* formed,
at enough digits that it does not matter), and the nonlinear flow plus the
4x4 variational equations are integrated by heyoka at ``bits`` of precision
(``rotorlib.orbits.floquet.variational_monodromy``, a plain integrator call). The textbook
route loses about ``2 log10(1/|E - sep|)`` digits near a separatrix, so
``bits`` must exceed ``3.33 (2 log10(1/|E - sep|) + digits wanted)``.
"""

from __future__ import annotations

import functools

import mpmath as mp
import numpy as np
import pytest

from rotorlib.core.precision import Tier
from rotorlib.orbits.floquet import variational_monodromy


def _run(state, period, bits, dps):
    with mp.workdps(dps):
        st = [mp.nstr(v, dps - 5) for v in state]
        T = mp.nstr(period, dps - 5)
    res = variational_monodromy(st, T, digits=Tier(f"mp{bits}"))
    with mp.workdps(dps):
        return mp.mpf(res.trace_str), mp.mpf(T), res.closure


@functools.cache
def textbook_pendulum(x: str, phase: str, bits: int = 512):
    """(tr M, period, closure) of the pendulum at ``log|E - 4| = x`` (decimal string)."""
    dps = int(bits / 3.33) + 30
    with mp.workdps(dps):
        eps = mp.exp(mp.mpf(x))
        E = 4 - eps if phase == "lib" else 4 + eps
        if phase == "lib":
            period = 4 * mp.ellipk(E / 4) / mp.sqrt(3)
        else:
            period = 2 * mp.sqrt(4 / E) * mp.ellipk(4 / E) / mp.sqrt(3)
        state = [0, 0, 0, mp.sqrt(4 * E / 3)]
    return _run(state, period, bits, dps)


@functools.cache
def textbook_breather_R(x: str, bits: int = 384):
    """(tr M, period, closure) of the rotational breather R at ``log|E - 4.5| = x`` (decimal string).

    State at G: ``phi = 0``, ``phi' = sqrt(E)``, i.e. ``[a1, a2, p1, p2] = [0, 0, sqrt E, sqrt E]``;
    period ``4 K(m)/sqrt(Q)``, ``Q = sqrt(E (E - 4))``, ``m = (Q - E + 6)/(2Q)`` (paper §8).
    """
    dps = int(bits / 3.33) + 30
    with mp.workdps(dps):
        E = mp.mpf(9) / 2 + mp.exp(mp.mpf(x))
        Q = mp.sqrt(E * (E - 4))
        period = 4 * mp.ellipk((Q - E + 6) / (2 * Q)) / mp.sqrt(Q)
        state = [0, 0, mp.sqrt(E), mp.sqrt(E)]
    return _run(state, period, bits, dps)


# --------------------------------------------------------------------------- the rotors in real128

#: The rotor pairs of the 3-rotor potential sum_{i<j} (1 - cos(theta_i - theta_j)).
PAIRS = ((0, 1), (1, 2), (2, 0))


def rotor_system():
    """heyoka's ODE system of the rotor equations written here: ``theta_i' = p_i``,
    ``p_i' = -sum_j sin(theta_i - theta_j)``."""
    hy = pytest.importorskip("heyoka")
    th = hy.make_vars("t1", "t2", "t3")
    ps = hy.make_vars("q1", "q2", "q3")
    f = [0, 0, 0]
    for i, j in PAIRS:
        s = hy.sin(th[i] - th[j])
        f[i], f[j] = f[i] - s, f[j] + s
    return list(zip(th, ps)) + [(ps[k], f[k]) for k in range(3)]


def real128_states(y0, times):
    """The rotor states ``(theta_1..3, p_1..3)`` at ``times`` (decimal strings or floats)
    from ``y0`` by heyoka's real128 Taylor method on the rotor equations written here
    (``theta_i' = p_i``, ``p_i' = -sum_j sin(theta_i - theta_j)``), as mpf numbers."""
    hy = pytest.importorskip("heyoka")
    R = hy.real128
    ta = hy.taylor_adaptive(
        rotor_system(), np.array([R(str(v)) for v in y0]), fp_type=R
    )
    out = []
    for t in times:
        ta.propagate_until(R(str(t)))
        out.append([mp.mpf(str(v)) for v in ta.state])
    return out


def real128_closure(x0, w0, T):
    """``max |x(T) - x(0)|`` (relative angles mod 2 pi, momenta) of the rotor state
    (``x0`` angles, ``w0`` momenta; decimal strings or floats) by :func:`real128_states`."""
    y0 = list(x0) + list(w0)
    with mp.workdps(40):
        (a,) = real128_states(y0, [T])
        b = [mp.mpf(str(v)) for v in y0]
        d = [(a[0] - a[1]) - (b[0] - b[1]), (a[1] - a[2]) - (b[1] - b[2])]
        two_pi = 2 * mp.pi
        d = [v - two_pi * mp.nint(v / two_pi) for v in d]
        d += [a[k] - b[k] for k in range(3, 6)]
        return float(max(abs(v) for v in d))


def decimal_theta(state_str):
    """The rotor state of a ``[a1, a2, p1, p2]`` given as decimal strings, at 40 digits
    (angles and momenta centred: zero total momentum), as 38-digit strings."""
    with mp.workdps(40):
        a1, a2, p1, p2 = (mp.mpf(v) for v in state_str)
        phi1, phi2 = 2 * a1, a2 - a1
        th = [mp.mpf(0), -phi1, -phi1 - phi2]
        d1, d2 = p1, 3 * p2 / 2 - p1 / 2
        w = [mp.mpf(0), -d1, -d1 - d2]
        mt, mw = sum(th) / 3, sum(w) / 3
        return [mp.nstr(v - mt, 38) for v in th], [mp.nstr(v - mw, 38) for v in w]
