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
from rotorlib.core.precision import Tier

requires_heyoka = pytest.mark.skipif(
    not rotorlib.heyoka_available(), reason="heyoka not installed"
)


@functools.cache
def textbook_reference(kind: str, value: float, phase_or_family: str, bits: int = 256):
    """(trace as mpf, closure) of the textbook monodromy at ``bits`` of precision.

    kind: 'pendulum-E', 'pendulum-log' or 'breather'.
    """
    if kind == "pendulum-E":
        orbit = rotorlib.pendulum(E=value)
    elif kind == "pendulum-log":
        orbit = rotorlib.pendulum(log_abs_dE=value, phase=phase_or_family)
    else:
        orbit = rotorlib.breather(value, phase_or_family)
    res = rotorlib.textbook_monodromy(orbit, Tier(f"mp{bits}"))
    with mp.workdps(int(bits / 3.33)):
        return mp.mpf(res.trace_str), res.closure
