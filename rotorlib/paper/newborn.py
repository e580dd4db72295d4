"""Periodic orbits born at the IS and PD bifurcations of pendula (paper §7.1-7.2).

Each family is a :class:`~rotorlib.orbits.shooting.ShootingProblem` for the one engine
(:mod:`rotorlib.orbits.shooting`, :mod:`rotorlib.orbits.continuation`). The pendulum's base point
G (``a1 = a2 = 0``, ``p1 = 0``) lies on the fixed sets of two reversing symmetries,
``{a2 = 0, p1 = 0}`` and ``{a1 = a2 = 0}``; the transverse eigenvector of the
bifurcation picks the one the newborn orbit keeps: ``(1,0,0,0)`` (``a1(0) = u``,
start ``a1``) or ``(0,1,0,0)`` (``p1(0) = u``, start ``p1``); ``p2(0) > 0`` comes
from the energy. The Lamé analysis of the transverse equation (the coefficient-map
at the half period of the coefficient is ``[[Delta/2, 2 y2 y2'], [2 y1 y1',
Delta/2]]``) fixes where and how the orbit meets the second fixed set:

* IS^l: section ``p2 = 0`` (a2 turns), condition ``p1 = 0`` or ``a1 = 0``, period
  ``4 t1`` (= tau);
* PD^l: section ``a2 = 0`` going down, condition ``a1 = 0``, period ``4 t1`` (= 2 tau);
* IS^r: section ``a2 = pi``, condition of the start's type, period ``2 t1`` (= tau);
* PD^r: section ``a2 = pi``, condition of the other type, period ``4 t1`` (= 2 tau).

For IS^l the condition is of the start's type when ``Delta = +2`` at the
bifurcation (IS^l_{1,2,5,6}) and of the other type when ``Delta = -2``
(IS^l_{3,4,7,8}). The residual ``x_k(t1) / u`` has the pendulum ``u = 0`` divided
out (``trivial = 0``: branch switching by deflation). One shot covers a quarter or
half of a pendulum period, halving the unstable stretch near the saddle.

Following a family: the first member is found at a small amplitude with the energy
adjusted (:func:`birth_member`, the paper's "adjust one quantity"), which measures
the fork law ``E - E_n ~ c u^2``; :func:`newborn_orbit` then continues in ``E``
(:class:`~rotorlib.orbits.continuation.Natural`, predictor linear in ``sqrt|E - E_n|``) and,
past folds, in pseudo-arclength (:func:`~rotorlib.paper.newborn_families.follow`), which also measured where each
family ends or folds (:data:`FAMILY_REACH`).

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

import functools
import math
import time
from dataclasses import dataclass
from typing import Any

import mpmath as mp
import numpy as np

from ..core import flow
from ..core.precision import FLOAT64, REAL128, Tier, tier
from ..orbits.continuation import (
    ContinuationOptions,
    FamilyEnd,
    Member,
    Natural,
    continuation,
    member,
    switch,
)
from ..orbits.family import Branch
from ..orbits.periodic_orbit import PeriodicOrbit, periodic_orbit
from ..orbits.shooting import ShootingProblem, StartSet, solve
from .bifurcations import parse_label, transition

__all__ = [
    "FAMILIES",
    "FAMILY_FLOAT64_DEPTH",
    "FamilySpec",
    "family_spec",
    "FAMILY_REACH",
    "FamilyRangeError",
    "family_range",
    "birth_member",
    "seed",
    "branch_from_birth",
    "newborn_orbit",
    "linear_orbit",
    "a1_structure",
    "trace_slope_at_birth",
]

#: The families this module follows (paper Fig. 4-6 and Tables III-IV).
FAMILIES = tuple(
    [f"IS^l_{n}" for n in range(1, 9)]
    + [f"PD^l_{n}" for n in range(1, 5)]
    + [f"IS^r_{n}" for n in range(1, 5)]
    + [f"PD^r_{n}" for n in range(1, 7)]
)

#: Families are followed member by member (with tr M over a whole period) in float64 only while
#: ``|E_n - 4|`` exceeds this (measured: float64 tr M of IS^l_3,4 and PD^l_2 at E = 4 within 6e-5
#: of real128; of PD^l_3 (born at 1.5e-6) 0.04 off, of IS^l_5,6 (1.7e-7, 5.8e-8) wrong by O(1)
#: to O(30)); deeper families in real128.
FAMILY_FLOAT64_DEPTH = 1e-5

_START = {"a1": StartSet("a1", a=(1.0, 0.0)), "p1": StartSet("p1", c=(1.0, 0.0))}
_SECTION = {
    "turn": flow.Section((0, 0, 0, 1), 0.0, -1),
    "a2_down": flow.Section((0, 1, 0, 0), 0.0, -1),
    "a2_up": flow.Section((0, 1, 0, 0), 1.0, 1),
}
_CONDITION = {"a1": flow.Section((1, 0, 0, 0)), "p1": flow.Section((0, 0, 1, 0))}
_OTHER = {"a1": "p1", "p1": "a1"}


@dataclass(frozen=True)
class FamilySpec:
    """A family born at a pendulum bifurcation, and how it is searched.

    Attributes
    ----------
    label, kind, phase : str
    n : int
    start : {'a1', 'p1'}
        The unknown: ``a1(0) = u`` or ``p1(0) = u``.
    event : {'turn', 'a2_down', 'a2_up'}
        Section of the second symmetric point (table of the module docstring).
    end : {'a1', 'p1'}
        The component that vanishes there.
    factor : int
        Period = ``factor * t1``.
    E_birth, log_abs_dE_birth, period_birth : float
        The bifurcation (:mod:`rotorlib.paper.bifurcations`) and the pendulum period there.
    transition : str
        Stability change of the pendulum with increasing E.
    """

    label: str
    kind: str
    phase: str
    n: int
    start: str
    event: str
    end: str
    factor: int
    E_birth: float
    log_abs_dE_birth: float
    period_birth: float
    transition: str

    @property
    def u_scale(self) -> float:
        """Rough amplitude scale: transverse energy ~ a1^2 (a1 start) or p1^2/4 (p1)."""
        return 1.0 if self.start == "a1" else 2.0

    @property
    def depth(self) -> float:
        """``|E_n - 4|`` (from ``log|E_n - 4|``: exact where ``E_n`` rounds to 4 in float64)."""
        return math.exp(self.log_abs_dE_birth)

    @property
    def problem(self) -> ShootingProblem:
        """The family as a shooting problem (energy chart ``E``)."""
        lattice = (0.0, 0.0) if self.phase == "lib" else (0.0, 2.0 * self.factor / 2)
        # a rotation that turns back (p2 = 0) before a2 = pi has failed: the shot ends there
        abort = flow.Section((0, 0, 0, 1), 0.0, -1) if self.phase == "rot" else None
        return ShootingProblem(
            self.label,
            _START[self.start],
            _SECTION[self.event],
            _CONDITION[self.end],
            1,
            self.factor,
            lattice,
            trivial=0.0,
            t_max=4 * self.period_birth + 200.0,
            abort=abort,
        )


def family_spec(label: str) -> FamilySpec:
    """The family born at ``label`` (``IS^l_2``, ``ISl2``, ``PD^r_3`` ...)."""
    return _family_spec(*parse_label(label))


@functools.cache
def _family_spec(kind, phase, n) -> FamilySpec:
    """:func:`family_spec`, cached on the parsed label (``ISl2`` and ``IS^l_2`` alike)."""
    tr = transition(f"{kind}{phase[0]}{n}")
    up = tr.transition.startswith("unstable")  # unstable -> stable with increasing E
    if phase == "lib" and kind == "IS":
        start = "p1" if up else "a1"
        plus = ((n + 1) // 2) % 2 == 1  # Delta = +2 for IS^l_{1,2,5,6}
        event, end, factor = "turn", _OTHER[start] if plus else start, 4
    elif phase == "lib":
        start, event, end, factor = "a1", "a2_down", "a1", 4
    else:
        start = "a1" if up else "p1"
        event, factor = "a2_up", 2 if kind == "IS" else 4
        end = _OTHER[start] if kind == "IS" else start
    return FamilySpec(
        tr.label,
        kind,
        phase,
        n,
        start,
        event,
        end,
        factor,
        tr.E,
        tr.log_abs_dE,
        tr.period,
        tr.transition,
    )


#: Where each family was followed to, measured by :func:`~rotorlib.paper.newborn_families.follow` (``tests/test_newborn.py``
#: re-measures some): ``label -> (E_upper, how)``. ``'fold'``: the branch turns back to lower
#: energies (no member above ``E_upper``); ``'E = 4.5'``: :func:`newborn_orbit` was checked up
#: to ``E_upper`` and the branch, followed further, runs towards E = 4.5 (the maxima of V) with a
#: growing period; ``'followed'``: checked up to there. Extended-precision families: the energies
#: at which they were checked (E = 4 for libration, ``E_n + 1000 |E_n - 4|`` for rotation).
FAMILY_REACH: dict[str, tuple[float | str, str]] = {
    "IS^l_1": (4.4999101, "E = 4.5"),
    "IS^l_2": (4.48, "E = 4.5"),
    "IS^l_3": (5.4889383, "fold"),
    "IS^l_4": (4.49, "E = 4.5"),
    "IS^l_5": (4.0016721, "followed"),
    "IS^l_6": (4.0012564, "followed"),
    "IS^l_7": (4.0, "followed"),
    "IS^l_8": (4.0, "followed"),
    "PD^l_1": (4.45, "E = 4.5"),
    "PD^l_2": (4.4870156, "E = 4.5"),
    "PD^l_3": (4.45, "E = 4.5"),
    "PD^l_4": (4.0, "followed"),
    "IS^r_1": (4.49, "E = 4.5"),
    "IS^r_2": (4.4980101, "E = 4.5"),
    "IS^r_3": (4.0034066, "followed"),
    "IS^r_4": (4.02, "followed"),
    "PD^r_1": (5.9831001, "fold"),
    "PD^r_2": (4.5516743, "fold"),
    "PD^r_3": (4.4681256, "E = 4.5"),
    "PD^r_4": (4.2, "followed"),
    "PD^r_5": ("1000", "followed"),
    "PD^r_6": ("1000", "followed"),
}


class FamilyRangeError(ValueError):
    """An energy outside the range a family exists in (or was followed to).

    Attributes
    ----------
    label : str
    E_min, E_max : float
        The family exists for ``E_min < E <= E_max``.
    how : str
        Why the range ends at ``E_max`` (a key of :data:`FAMILY_REACH`).
    E : float or (float, float)
        The energy (or the range) asked for.
    """

    def __init__(self, spec: FamilySpec, E: Any):
        lo, hi = family_range(spec)
        self.label, self.E_min, self.E_max = spec.label, lo, hi
        self.E = tuple(float(v) for v in E) if isinstance(E, tuple) else float(E)
        got = f"E_range = {self.E!r}" if isinstance(E, tuple) else f"E = {self.E!r}"
        self.how = FAMILY_REACH[spec.label][1]
        why = {
            "fold": f"at E = {hi!r} the family folds back to lower energies (no member "
            f"above it)",
            "E = 4.5": f"it was followed from birth to E = {hi!r}; continued further in "
            f"amplitude it runs towards E = 4.5 (the maxima of V) with a growing "
            f"period",
            "followed": f"it was followed from birth to E = {hi!r}",
        }[self.how]
        super().__init__(
            f"{spec.label} exists for {lo!r} < E <= {hi!r} (born at E_n = {lo!r}; "
            f"{why}); got {got}"
        )


def family_range(spec: FamilySpec) -> tuple[float, float]:
    """``(E_n, E_max)``: every family is born at ``E_n`` and exists just above it (forward
    fork); ``E_max`` from :data:`FAMILY_REACH`."""
    if spec.label not in FAMILY_REACH:
        raise ValueError(
            f"no newborn family {spec.label} is followed here "
            f"(families: {', '.join(FAMILIES)})"
        )
    top = FAMILY_REACH[spec.label][0]
    if isinstance(top, str):
        return spec.E_birth, spec.E_birth + float(top) * spec.depth
    return spec.E_birth, float(top)


# --------------------------------------------------------------------------- birth and seed


@functools.cache
def _birth(spec: FamilySpec, t: Tier):
    """``E_n`` in a tier: float64, or from the 30-digit transition (extended)."""
    if not t.extended:
        return spec.E_birth
    with t.context():
        eps = mp.exp(mp.mpf(transition(spec.label, digits=30).log_abs_dE_str))
        return 4 - eps if spec.phase == "lib" else 4 + eps


def birth_member(
    spec: FamilySpec,
    u: Any,
    digits: int | Tier | None = None,
    tol: Any = None,
) -> tuple[Any, int]:
    """Paper §6 step 3 in one unknown: fix the amplitude ``u``, adjust the energy.

    A secant on the symmetric residual in ``E`` from ``E_n`` and ``E_n + 1e-3 |E_n - 4|``
    to a relative step ``tol`` (default 1e-15 float64, 1e-32 real128), in the tier of
    ``digits`` (:func:`~rotorlib.core.precision.tier`); a simple root: ``E`` to
    ~eps / |E - 4|. Returns ``(E, iterations)``; the residual is evaluated
    ``iterations + 2`` times.

    Examples
    --------
    >>> from rotorlib.paper.newborn import birth_member, family_spec
    >>> E, it = birth_member(family_spec("IS^l_2"), 1e-3)
    >>> round(E, 9)
    3.996917247
    """
    t = tier(digits)
    with t.context():
        E0 = _birth(spec, t)
        dE = (
            1e-3 * max(spec.depth, 1e-12)
            if not t.extended
            else t.num("1e-3") * abs(E0 - 4)
        )
        tol = tol if tol is not None else (1e-15 if not t.extended else t.num("1e-32"))
        m, it = switch(spec.problem, t.num(u), E0, dE, t, tol=tol, r_max=math.inf)
        return m.E, it


def seed(label: str, digits: int | Tier | None = None) -> tuple[Member, Any]:
    """``(member, c)``: the first member, at ``u = 0.01 sqrt|E_n - 4|`` (twice that for a
    ``p1`` start), and the fork coefficient ``c`` in ``E - E_n = c u^2``, in the tier of
    ``digits`` (:func:`~rotorlib.core.precision.tier`).

    Examples
    --------
    >>> from rotorlib.paper.newborn import seed
    >>> m, c = seed("IS^l_2")
    >>> m.label, m.stability, round(c, 4)
    ('IS^l_2', 'unknown', 0.1361)
    """
    return _seed(family_spec(label), tier(digits))


@functools.lru_cache(maxsize=64)
def _seed(spec: FamilySpec, t: Tier) -> tuple[Member, Any]:
    with t.context():
        u_s = t.num(1e-2 * spec.u_scale * math.sqrt(spec.depth))
        E_s, _ = birth_member(spec, u_s, t)
        m = member(spec.problem, u_s, E_s, t)
        return m, (E_s - _birth(spec, t)) / (u_s * u_s)


def branch_from_birth(
    spec: FamilySpec,
    E_target: Any,
    digits: int | Tier | None = None,
    steps: int | None = None,
    traces: bool = False,
) -> Branch:
    """The family ``spec`` from its seed (:func:`seed`, beside the birth) to ``E_target``,
    continued in ``E`` (natural continuation, :class:`~rotorlib.orbits.continuation.Natural`)
    in the tier of ``digits``.

    The ``steps`` energies (default: 4 to 40, by the distance covered) are equally
    spaced in ``sqrt|E - E_n|``, the family's own scale near its birth, and end at
    ``E_target`` (a decimal string keeps its digits in an extended tier); ``traces``
    adds ``tr M`` of every member. Raises ValueError for an ``E_target`` on the side of
    ``E_n`` where the family does not exist, and
    :class:`~rotorlib.orbits.continuation.FamilyEnd` where the continuation stops.

    Examples
    --------
    >>> from rotorlib.paper.newborn import branch_from_birth, family_spec
    >>> b = branch_from_birth(family_spec("IS^l_1"), 4.0, steps=4)
    >>> len(b.members), float(b.members[-1].E)
    (5, 4.0)
    """
    t = tier(digits)
    m0, c = seed(spec.label, t)
    with t.context():
        E_target = t.num(E_target)
        if (c > 0) != (E_target > spec.E_birth):
            raise ValueError(
                f"{spec.label} exists only for E {'>' if c > 0 else '<'} E_n = "
                f"{spec.E_birth!r}"
            )
        En = _birth(spec, t)
        s_s, s_t = t.m.sqrt(abs(m0.E - En)), t.m.sqrt(abs(E_target - En))
        if steps is None:
            steps = int(
                min(40, max(4, math.ceil(2 * math.log(float(s_t / s_s) + 1.0) + 6)))
            )
        # values equally spaced in sqrt|E - E_n| from the seed's to the target's
        vals = [
            En + (1 if c > 0 else -1) * (s_s + (s_t - s_s) * i / steps) ** 2
            for i in range(1, steps)
        ]
        alg = Natural(
            "E", tuple(vals) + (E_target,), order=1, origin=En, origin_other=0.0
        )
        return continuation(
            spec.problem, alg, ContinuationOptions(traces=traces), [m0], t
        )


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
        from .newborn_families import follow

        b = follow(spec.label, E_range=(None, float(E) + 1e-9), energies=(float(E),))
        pts = b.points("E")
        if not pts:
            raise FamilyRangeError(spec, E) from None
        path = (pts[0].member,)
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


def __getattr__(name: str) -> Any:
    """``family`` and ``follow`` (:mod:`rotorlib.paper.newborn_families`), re-exported here; imported
    on first use, so that either module can be imported first."""
    if name in ("family", "follow"):
        from . import newborn_families

        return getattr(newborn_families, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
