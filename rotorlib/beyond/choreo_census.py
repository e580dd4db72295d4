"""A census that sees choreographies: every reversible choreography up to a period.

A choreography ``x(t + T/3) = C^{+-1} x(t)`` that is reversible under a reflection
(the mirrors of the transpositions ``Fix T(12)``, ... or of the negated transpositions
``Fix T-(12)``, ...) meets a mirror at right angles at ``t = 0`` and, as the composition
of two reflections of one class is ``C^{+-1}``, the mirror of the same class 60 degrees
away at ``t = T/6``: the symmetry fixes half the unknowns and the orbit is a root of one
residual in one amplitude ``u`` at fixed ``E``. The ``D6`` rotating waves
(``x(t + T/6) = -C^2 x(t)``, such as CG, CT and CS) meet the adjacent mirror of the
other class at ``T/12``. Three shooting problems therefore cover every reversible
choreography up to a symmetry of the system (:data:`PROBLEMS`):

* ``D6``: :func:`rotorlib.beyond.choreo.cg_problem` (``Fix T(12)`` to ``Fix T-(13)``,
  ``T = 12 t1``);
* ``Z3 T-(12)`` and ``Z3 T(12)``: :func:`rotorlib.beyond.choreo_z3.z3_problem` of ``CZ1``
  and ``CZ2`` (to the mirror of the same class, ``T = 6 t1``),

each at its ``k``-th crossing, ``k = 1, 2, ...`` until ``t1`` exceeds ``T_max /
factor``. :func:`census` scans ``u`` on a uniform grid of ``n`` points over the start set,
bisects every sign change of the residual to ``|du| < 1e-14`` and keeps the roots that
close as choreographies (:func:`rotorlib.beyond.choreo.choreography_of`, tolerance
``1e-6``) with their least period (an orbit found at a later crossing, or run several
times, is reduced to its least period) and ``T <= T_max``; orbits of equal period to
``1e-7`` relative are one orbit (its images under the symmetries). Roots closer than
the grid's spacing can be missed: the census is run with ``n`` and ``4 n`` and is
complete, to the resolution tested, up to the period where the two counts agree
(:func:`agreement_period`).

The census does not name its orbits: the front door does
(:func:`rotorlib.api.name_choreography`, the families of :data:`rotorlib.api.REGISTRY`).

Scope: reversible choreographies (of the classes above); not a choreography that meets
no mirror. Precision: float64 shots, ``|r| < 1e-10`` at the roots kept (most ``1e-14``);
period to ~1e-12 relative.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..orbits.shooting import ShootingProblem, residual
from .choreo import cg_problem, choreography_of, reduced_trace
from .choreo_z3 import z3_problem

__all__ = ["PROBLEMS", "CensusChoreography", "census", "agreement_period"]


def _problems() -> dict[str, tuple[ShootingProblem, tuple[float, float]]]:
    return {
        "D6": (cg_problem(), (-math.pi, math.pi)),
        "Z3 T-(12)": (z3_problem("CZ1"), (0.0, 2 * math.pi)),
        "Z3 T(12)": (z3_problem("CZ2"), (0.0, 2 * math.pi)),
    }


#: The three shooting problems: name -> (problem, range of the amplitude ``u``).
PROBLEMS = tuple(_problems())


@dataclass(frozen=True)
class CensusChoreography:
    """One choreography of the census: where it was found (``problem``, ``crossing``,
    ``u``), its least ``period``, ``trace`` (``tr M``) and ``trace_reduced`` (``tr DP``
    over ``T/6`` for a ``D6`` rotating wave, ``T/3`` otherwise), ``stability`` of
    ``tr DP``, the symmetry (``power``, ``sixth``, ``rotating``) and ``state0``.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_census import census
    >>> c = census(5.45, 17.0, 200)
    >>> [(o.problem, round(o.period, 6), o.sixth, o.rotating) for o in c]
    [('Z3 T(12)', 13.036882, False, True), ('D6', 16.524918, True, False)]
    """

    problem: str
    crossing: int
    u: float
    E: float
    period: float
    trace: float
    trace_reduced: float
    stability: str
    power: int
    sixth: bool
    rotating: bool
    state0: tuple

    def to_dict(self) -> dict[str, Any]:
        """The record of the data file (JSON-serialisable)."""
        d = dict(vars(self))
        d["state0"] = [float(v) for v in self.state0]
        return d


def _bisect(p, a, b, fa, E):
    for _ in range(60):
        if b - a < 1e-14:
            break
        m = 0.5 * (a + b)
        try:
            fm = float(residual(p, m, E).r)
        except (ValueError, RuntimeError):
            return None
        if fa * fm <= 0:
            b = m
        else:
            a, fa = m, fm
    return a


def _least_period(x0, T):
    """The least period ``T/n`` (``n <= 12``) at which the orbit closes as a
    choreography, with its record, or ``(None, None)``."""
    for n in range(12, 0, -1):
        if T / n < 1.0:
            continue
        c = choreography_of(x0, T / n, tol=1e-6)
        if c is not None:
            return T / n, c
    return None, None


def census(E: float, t_max: float, n: int = 1200) -> tuple[CensusChoreography, ...]:
    """Every reversible choreography with period ``<= t_max`` at energy ``E`` that the
    scan of ``n`` amplitudes per problem and crossing finds (module docstring), ordered
    by period. Raises ValueError for a non-finite ``E``, ``t_max <= 0`` or ``n < 10``.

    Precision: see the module docstring; completeness: :func:`agreement_period`.
    """
    E, t_max = float(E), float(t_max)
    if not (math.isfinite(E) and math.isfinite(t_max)) or t_max <= 0 or int(n) < 10:
        raise ValueError(
            f"census needs a finite E, t_max > 0 and n >= 10, got {E}, {t_max}, {n}"
        )
    found: list[CensusChoreography] = []
    for name, (p0, (lo, hi)) in _problems().items():
        us = np.linspace(lo, hi, int(n), endpoint=False)
        for k in range(1, 200):
            p = replace(p0, crossing=k, t_max=t_max / p0.factor + 1e-9)
            rs: list[float | None] = []
            for u in us:
                try:
                    rs.append(float(residual(p, u, E).r))
                except (ValueError, RuntimeError):
                    rs.append(None)
            if all(r is None for r in rs):
                break
            for i in range(len(us) - 1):
                ra, rb = rs[i], rs[i + 1]
                if ra is None or rb is None or ra * rb > 0:
                    continue
                u = _bisect(p, float(us[i]), float(us[i + 1]), ra, E)
                if u is None:
                    continue
                s = residual(p, u, E)
                if abs(float(s.r)) > 1e-10:
                    continue  # a jump of the residual, not a root
                x0 = [float(v) for v in s.x0]
                T, c = _least_period(x0, p0.factor * float(s.t1))
                if c is None or T > t_max:
                    continue
                if any(abs(T - o.period) < 1e-7 * T for o in found):
                    continue
                order = 6 if c.sixth else 3
                trp, trm = reduced_trace(x0, T, order=order, power=c.power)
                trp = float(trp)
                stab = "stable" if 0 < trp < 4 else "unstable"
                found.append(
                    CensusChoreography(
                        name, k, float(u), E, T, float(trm), trp, stab, c.power,
                        c.sixth, c.rotating, tuple(x0),
                    )
                )  # fmt: skip
    return tuple(sorted(found, key=lambda o: o.period))


def agreement_period(
    coarse: tuple[CensusChoreography, ...], fine: tuple[CensusChoreography, ...]
) -> float:
    """The largest period up to which two censuses (of ``n`` and ``4 n`` amplitudes)
    found the same orbits (equal periods to 1e-7): below it the finer grid added
    nothing.

    Examples
    --------
    >>> from rotorlib.beyond.choreo_census import agreement_period
    >>> agreement_period((), ())
    inf
    """
    a = sorted(o.period for o in coarse)
    b = sorted(o.period for o in fine)
    for i, T in enumerate(b):
        if i >= len(a) or abs(a[i] - T) > 1e-7 * T:
            return float(T)
    return math.inf if len(a) == len(b) else float(a[len(b)])
