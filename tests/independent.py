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
