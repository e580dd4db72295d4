"""Orbits of the families born at the IS and PD bifurcations of pendula (paper §7.1-7.2):
:func:`newborn_orbit` (one member at an energy, any precision) and the shapes of Fig. 5
and Tables III-IV (:func:`linear_orbit`, :func:`a1_structure`,
:func:`trace_slope_at_birth`).

The families themselves (their shooting problems :class:`FamilySpec`, the seeds at birth,
:func:`family` and :func:`follow` over an energy range) live in
:mod:`rotorlib.paper.newborn_families`; this module imports the names it and the chapters
use from there, so that ``newborn.family_spec``, ``newborn.follow``, ... read as before.

Precision: one ``digits`` control. Default: float64 while ``|E_n - 4| > 3e-8``
(heyoka Taylor at machine epsilon; exported orbits close to ~1e-9 or better),
real128 beyond; members near E = 4 (``|E_n - 4| < 0.05``) are polished in real128.
``digits=D`` for ``D >= 16`` delivers ``D`` digits: the search loses
``log10(1/|E_n - 4|)`` of the tier's digits, and the tier is chosen to cover them
(:func:`rotorlib.core.precision.tier`). ``digits <= 15`` is the float64 tier as it is (to
compare with it): near E = 4 it delivers only about ``14 - log10(1/|E_n - 4|)`` digits
(``tr M`` of ``PD^r_3`` at ``E = 4.0002`` to ~2.5e-6 relative); ask for 16 digits or the
default for members near E = 4.
"""

from __future__ import annotations

import math
import time
from typing import Any, cast

import numpy as np

from ..core import flow
from ..core.precision import FLOAT64, REAL128, Tier, tier
from ..orbits.continuation import FamilyEnd, Member
from ..orbits.periodic_orbit import PeriodicOrbit, periodic_orbit
from ..orbits.shooting import solve
from .newborn_families import (
    FAMILIES,
    FAMILY_FLOAT64_DEPTH,
    FAMILY_REACH,
    FamilyRangeError,
    FamilySpec,
    birth_member,
    branch_from_birth,
    family,
    family_range,
    family_spec,
    follow,
    seed,
)

__all__ = [
    "newborn_orbit",
    "linear_orbit",
    "a1_structure",
    "trace_slope_at_birth",
    # the families' names, from rotorlib.paper.newborn_families
    "FAMILIES",
    "FAMILY_FLOAT64_DEPTH",
    "FAMILY_REACH",
    "FamilyRangeError",
    "FamilySpec",
    "birth_member",
    "branch_from_birth",
    "family",
    "family_range",
    "family_spec",
    "follow",
    "seed",
]


def _tiers(spec: FamilySpec, digits):
    """(continuation tier, result tier) for ``digits`` (see the module docstring)."""
    cont = (
        FLOAT64
        if spec.depth > Tier.separatrix_depth or (digits is not None and digits <= 15)
        else REAL128
    )
    if digits is None:
        return cont, REAL128 if spec.depth < 0.05 else cont
    if digits <= 15:
        return FLOAT64, FLOAT64
    return cont, tier(int(digits), math.log10(1 / spec.depth) + 2)


def newborn_orbit(
    label: str,
    E: float | str,
    digits: int | None = None,
) -> PeriodicOrbit:
    """The member of the family born at ``label`` with energy ``E`` (:func:`~rotorlib.paper.newborn_families.family` gives
    its members over a range).

    Parameters
    ----------
    label : str
        ``IS^l_2``, ``ISl2``, ``PD^r_3``, ``PDr3``, ...
    E : float or str
        Energy (a decimal string keeps all its digits in extended tiers).
    digits : int, optional
        Significant digits wanted (see the module docstring); ``None``: the default tiers.

    Returns
    -------
    PeriodicOrbit
        ``state0`` on the starting symmetry line; ``trace`` from the variational equations
        over one period in the result's tier (``precision``); extended tiers add
        ``state0_str``, ``period_str``, ``trace_str``.

    Raises
    ------
    ValueError
        Unknown label; :class:`FamilyRangeError` when ``E`` is outside the family's range.
    """
    spec = family_spec(label)
    lo, hi = family_range(spec)
    if not (lo <= float(E) <= hi):
        raise FamilyRangeError(spec, E)
    if float(E) == spec.E_birth:
        raise ValueError(
            f"{spec.label}: E = E_n is the bifurcation itself (the new orbit is "
            f"the pendulum there)"
        )
    t_cont, t_out = _tiers(spec, digits)
    t0 = time.perf_counter()
    try:  # continuation steps from the seed: by the distance to birth
        path = branch_from_birth(
            spec, str(E) if t_cont.extended else float(E), t_cont
        ).members
    except FamilyEnd:
        if t_cont.extended:
            raise
        b = follow(spec.label, E_range=(None, float(E) + 1e-9), energies=(float(E),))
        pts = b.points("E")
        if not pts:
            raise FamilyRangeError(spec, E) from None
        path = (cast(Member, pts[0].member),)
    u = path[-1].u
    if t_out != t_cont:
        u = solve(
            spec.problem, u, u * (1 + t_out.num("1e-9")), E=str(E), digits=t_out
        ).x
    with t_out.context():
        w = spec.problem.w_at(u, str(E) if t_out.extended else float(E), t_out)
    return periodic_orbit(
        spec.problem,
        u,
        w,
        t_out,
        extra={
            "start": spec.start,
            "section": spec.event,
            "condition": f"{spec.end} = 0",
            "phase": spec.phase,
            "steps": len(path) - 1,
            "seconds": time.perf_counter() - t0,
        },
        shown=digits if digits and digits > 15 else None,
    )


# --------------------------------------------------------------------------- shapes (Fig. 5, Tables III-IV)


def linear_orbit(
    label: str, x0: Any, period: float, n: int = 801
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The linearised orbit of Fig. 5: ``a2`` the pendulum at the bifurcation, ``a1`` from the
    transverse Lamé equation ``a1'' = -(2 + cos a2) a1`` with the same initial ``(a1, p1)``.

    Returns ``(t, a1, a2)`` on ``n`` points over ``[0, period]`` (scipy DOP853, rtol 1e-11).
    """
    from scipy.integrate import solve_ivp

    from ..core.closed_forms import pendulum

    spec = family_spec(label)
    pend = pendulum(log_abs_dE=spec.log_abs_dE_birth, phase=spec.phase)
    t = np.linspace(0.0, float(period), n)

    def rhs(tt, y):
        return [0.5 * y[1], -2.0 * (2.0 + math.cos(pend.state(tt)[1])) * y[0]]

    sol = solve_ivp(
        rhs,
        (0.0, float(period)),
        [float(x0[0]), float(x0[2])],
        method="DOP853",
        rtol=1e-11,
        atol=1e-14,
        t_eval=t,
    )
    return t, sol.y[0], np.array([pend.state(tt)[1] for tt in t])


def a1_structure(
    orbit: PeriodicOrbit, spec: FamilySpec | None = None, n: int = 4000
) -> dict[str, Any]:
    """Period of ``a1`` in units of the pendulum period at birth, and its nodes per orbit period.

    ``a1`` is sampled at ``n`` mid-points of one period (float64 heyoka); its period is the
    smallest of ``tau/2, tau, 2 tau`` (tau = the orbit's pendulum period: the orbit period
    for IS, half of it for PD) over which it repeats to 1e-6 of its amplitude. ``m`` is the
    Lamé count of Tables III/IV: nodes of ``a1`` per orbit period divided by 2 (IS) or 4 (PD).
    """
    spec = spec or family_spec(orbit.label)
    tau = orbit.period / (2 if spec.kind == "PD" else 1)
    st, _ = flow.sample(orbit.state0, orbit.period, n + 1)
    mid = 0.5 * (st[1:, 0] + st[:-1, 0])
    nodes = int(
        np.sum(np.sign(mid[1:]) != np.sign(mid[:-1]))
        + (np.sign(mid[0]) != np.sign(mid[-1]))
    )
    amp, x0 = np.max(np.abs(st[:, 0])), orbit.state0

    def repeats(frac: float) -> bool:  # a1 and p1 back at their start after frac tau
        x = flow.flow(x0, frac * tau)
        return abs(x[0] - x0[0]) < 1e-6 * amp and abs(x[2] - x0[2]) < 4e-6 * amp

    per = next((frac for frac in (0.5, 1.0, 2.0) if repeats(frac)), None)
    return {
        "period_of_a1": per,
        "nodes": nodes,
        "m": nodes / (2 if spec.kind == "IS" else 4),
        "lame": ("Ec" if spec.start == "a1" else "Es"),
    }


def trace_slope_at_birth(
    label: str, rel: tuple[float, float] = (1e-3, 2e-3), digits: int | None = None
) -> tuple[float, float]:
    """``(d tr M / dE, tr M at E_n)`` of the new family at birth, from two members at
    ``E_n + r |E_n - 4|`` (linear extrapolation)."""
    spec = family_spec(label)
    Es = [spec.E_birth + r * spec.depth for r in rel]
    trs = [newborn_orbit(label, E, digits=digits).trace for E in Es]
    slope = (trs[1] - trs[0]) / (Es[1] - Es[0])
    return slope, trs[0] - slope * (Es[0] - spec.E_birth)
