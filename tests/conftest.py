"""Shared fixtures: an independent high-precision reference for tr M.

The reference integrates the *full nonlinear flow and the 4x4 variational
equations* (the textbook route) with heyoka in multiprecision, from an initial
state and period computed with mpmath. It shares no code with the
symmetry-reduced Hill route that ``rotorlib.monodromy`` uses (different
variables, different equations, different integrator settings); its closure
after one period also checks the closed-form period.
"""
from __future__ import annotations

import functools

import mpmath as mp
import pytest

import rotorlib

requires_heyoka = pytest.mark.skipif(not rotorlib.heyoka_available(), reason="heyoka not installed")


@functools.lru_cache(maxsize=None)
def textbook_reference(kind: str, value: float, phase_or_family: str, bits: int = 256):
    """(trace as mpf, closure) of the textbook monodromy at ``bits`` of precision.

    kind: 'pendulum-E', 'pendulum-log' or 'breather'.
    """
    dps = int(bits / 3.33) + 10
    with mp.workdps(dps):
        if kind.startswith("pendulum"):
            en = (rotorlib.pendulum_energy(E=value) if kind == "pendulum-E"
                  else rotorlib.pendulum_energy(log_abs_dE=value, phase=phase_or_family))
            v = en.mp_values(dps)
            E, m = v["E"], v["m"]
            period = (4 * mp.ellipk(m) / mp.sqrt(3) if en.phase == "lib"
                      else 2 * mp.sqrt(m) * mp.ellipk(m) / mp.sqrt(3))
            state0 = [mp.mpf(0), mp.mpf(0), mp.mpf(0), mp.sqrt(4 * E / 3)]
        else:
            E = mp.mpf(repr(value))
            assert phase_or_family == "R"
            Q = mp.sqrt(E * (E - 4))
            m = (Q - E + 6) / (2 * Q)
            period = 4 * mp.ellipk(m) / mp.sqrt(Q)
            p = mp.sqrt(E)                       # phi' at G; a1 = phi/2, a2 = 3phi/2, p1 = p2 = phi'
            state0 = [mp.mpf(0), mp.mpf(0), p, p]
        res = rotorlib.variational_monodromy(state0, period, method="heyoka", precision=f"mp{bits}")
        return mp.mpf(res.trace_str), res.closure
