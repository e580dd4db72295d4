"""Shared fixtures: an independent high-precision reference for tr M.

The reference integrates the *full nonlinear flow and the 4x4 variational
equations* (the textbook route) with heyoka in multiprecision, from an initial
state and period computed with mpmath. It shares no code with the
symmetry-reduced Hill route that ``rotorlib.orbits.floquet.monodromy`` uses (different
variables, different equations, different integrator settings); its closure
after one period also checks the closed-form period.
"""

from __future__ import annotations

import functools

import mpmath as mp
import pytest

from rotorlib.core.closed_forms import breather, pendulum
from rotorlib.core.precision import Tier, heyoka_available
from rotorlib.orbits.floquet import textbook_monodromy

requires_heyoka = pytest.mark.skipif(
    not heyoka_available(), reason="heyoka not installed"
)


@functools.cache
def textbook_reference(kind: str, value: float, phase_or_family: str, bits: int = 256):
    """(trace as mpf, closure) of the textbook monodromy at ``bits`` of precision.

    kind: 'pendulum-E', 'pendulum-log' or 'breather'.
    """
    if kind == "pendulum-E":
        orbit = pendulum(E=value)
    elif kind == "pendulum-log":
        orbit = pendulum(log_abs_dE=value, phase=phase_or_family)
    else:
        orbit = breather(value, phase_or_family)
    res = textbook_monodromy(orbit, Tier(f"mp{bits}"))
    with mp.workdps(int(bits / 3.33)):
        return mp.mpf(res.trace_str), res.closure
