"""The families born at the IS and PD bifurcations of pendula (paper §7.1-7.2): their
shooting problems (:class:`FamilySpec`), seeds at birth, and each family over an energy
range (:func:`family`, the front door's ``rotorlib.family`` for IS/PD labels, and
:func:`follow`, the engine's view; one pseudo-arclength continuation from the seed).

Each family is a :class:`~rotorlib.orbits.shooting.ShootingProblem`. G (``a1 = a2 = 0``,
``p1 = 0``) lies on the fixed sets ``{a2 = 0, p1 = 0}`` and ``{a1 = a2 = 0}`` of two
reversing symmetries; the transverse eigenvector at the bifurcation picks the one the
newborn orbit keeps: start ``a1`` (``a1(0) = u``) or ``p1`` (``p1(0) = u``), ``p2(0) > 0``
from the energy. The Lamé analysis fixes where it meets the second fixed set: IS^l at
``p2 = 0`` (condition ``p1 = 0`` or ``a1 = 0``: of the start's type when ``Delta = +2``,
IS^l_{1,2,5,6}, else of the other), PD^l at ``a2 = 0`` going down (``a1 = 0``), IS^r and
PD^r at ``a2 = pi`` (of the start's type, of the other); period ``4 t1`` (``2 t1`` for
IS^r). The residual ``x_k(t1) / u`` has the pendulum divided out (deflation). The first
member is found at a small amplitude with the energy adjusted (:func:`birth_member`, the
paper's "adjust one quantity"), measuring the fork law ``E - E_n ~ c u^2``;
:func:`follow` measured where each family ends or folds (:data:`FAMILY_REACH`).

Precision: the continuation's tier is float64 while ``|E_n - 4|`` exceeds 3e-8
(:attr:`~rotorlib.core.precision.Tier.separatrix_depth`), real128 beyond, or the tier of
``digits``; members satisfy ``|r| < r_max`` (:attr:`~rotorlib.core.precision.Tier.r_max`;
extended: ``max(eps^(2/3), 1e4 eps / |E_n - 4|)``); special points as in the engine.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace
from typing import Any, cast

import mpmath as mp

from ..core import flow
from ..core.flow import SectionNotReached
from ..core.precision import FLOAT64, REAL128, Tier, tier
from ..orbits.continuation import (
    PALC,
    Branch,
    ContinuationOptions,
    Member,
    Natural,
    SpecialPoint,
    continuation,
    member,
    switch,
)
from ..orbits.shooting import NoConvergence, ShootingProblem, StartSet, solve
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
    "family",
    "follow",
]

#: The families this module follows (paper Fig. 4-6 and Tables III-IV).
FAMILIES = tuple(
    [f"IS^l_{n}" for n in range(1, 9)]
    + [f"PD^l_{n}" for n in range(1, 5)]
    + [f"IS^r_{n}" for n in range(1, 5)]
    + [f"PD^r_{n}" for n in range(1, 7)]
)

#: Families are followed with tr M in float64 only while ``|E_n - 4|`` exceeds this, deeper
#: ones in real128 (float64 tr M at E = 4: IS^l_3,4, PD^l_2 within 6e-5 of real128; PD^l_3,
#: born at 1.5e-6, 0.04 off; IS^l_5,6, at 1.7e-7 and 5.8e-8, wrong by O(1) to O(30)).
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
        Section of the second symmetric point (see the module docstring).
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


#: Where each family was followed to, measured by :func:`follow` (``tests/test_newborn.py``
#: re-measures some): ``label -> (E_upper, how)``. ``'fold'``: the branch turns back to
#: lower energies (no member above ``E_upper``); ``'E = 4.5'``: the member at ``E_upper``
#: was checked (:func:`~rotorlib.paper.newborn.newborn_orbit`) and the branch runs on towards
#: E = 4.5 (the maxima of V) with a growing period; ``'followed'``: checked up to there.
#: Extended-precision families: checked at E = 4 (libration), ``E_n + 1000 |E_n - 4|``.
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
    >>> from rotorlib.paper.newborn_families import birth_member, family_spec
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
    >>> from rotorlib.paper.newborn_families import seed
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
    >>> from rotorlib.paper.newborn_families import branch_from_birth, family_spec
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


def _default_tier(spec: FamilySpec, traces: bool) -> Tier:
    """float64 while ``|E_n - 4|`` exceeds the separatrix depth (with ``traces``:
    :data:`FAMILY_FLOAT64_DEPTH`, where float64 ``tr M`` is still
    right), else real128."""
    depth = FAMILY_FLOAT64_DEPTH if traces else Tier.separatrix_depth
    return FLOAT64 if spec.depth > depth else REAL128


def _branch(
    spec: FamilySpec,
    E_range: tuple[Any, Any],
    t: Tier,
    *,
    t_max: float,
    traces: bool,
    energies: tuple[Any, ...],
    chart: str,
    jump: float | None,
    ds: float,
    ds_max: float,
    max_steps: int,
    enter: bool,
    start: list[Member] | None = None,
) -> Branch:
    """The family of ``spec`` in pseudo-arclength from its seed (or from ``start``)."""
    prob = spec.problem if chart == "E" else spec.problem.chart(4.0)
    if start is None:
        m0 = seed(spec.label, t)[0]
        if chart == "K":
            m0 = member(prob, m0.u, prob.w_at(m0.u, m0.E, t), t)
        start = [m0]
    return continuation(
        prob,
        PALC(
            ds=ds,
            ds_max=ds_max,
            E_ref=spec.E_birth if chart == "E" else 4.0,
            u_floor=1e-3 * math.sqrt(spec.depth),
            w_floor=1e-3 * spec.depth,
        ),
        ContinuationOptions(
            max_steps=max_steps,
            E_range=E_range,
            t_max=t_max,
            jump=jump,
            traces=traces,
            energies=tuple(energies),
            r_max=_r_max(spec, t, chart),
            enter=enter,
        ),
        start,
        t,
    )


def _r_max(spec: FamilySpec, t: Tier, chart: str) -> float:
    """The accepted residual: the shooting amplifies round-off like 1/|E_n - 4| (the K
    chart's members sit in a channel where a2 barely passes the barrier: 1e-6 in float64,
    as measured)."""
    if t.extended:
        return max(t.r_max, 1e4 * t.eps / spec.depth)
    return 1e-6 if chart == "K" else t.r_max


def _t_max(spec: FamilySpec, t_max: float | None) -> float:
    """The largest full period ``t_max`` (default: 12 times the period at birth, beyond
    which the family runs into an orbit of infinite period)."""
    T_birth = spec.period_birth * (2 if spec.kind == "PD" else 1)
    return 12 * T_birth if t_max is None else t_max


def family(
    label: str,
    E_range: tuple[float | str, float | str],
    *,
    digits: int | Tier | None = None,
    steps: int | None = None,
    t_max: float | None = None,
    traces: bool = True,
    energies: tuple[float | str, ...] = (),
    chart: str = "E",
    jump: float | None = None,
    ds: float = 0.3,
    ds_max: float | None = None,
    max_steps: int = 2000,
) -> Branch:
    """The family born at ``label``, followed over ``E_range = (lo, hi)``.

    The family is followed in pseudo-arclength (it passes folds) from its seed near the
    birth energy ``E_n`` (:func:`seed`), through energies below ``lo`` if need be, and
    stops at the first member that leaves the range after entering it (or lands beyond
    it). The members returned all lie inside ``[lo, hi]``: the first and last are
    located exactly at ``lo`` and ``hi`` where the branch crosses them.

    Parameters
    ----------
    label : str
        ``IS^l_n``, ``PD^l_n``, ``IS^r_n``, ``PD^r_n`` (also ``ISl2``, ``PDr3``).
    E_range : (float or str, float or str)
        ``(lo, hi)`` with ``lo < hi``; it must reach above the birth energy ``E_n``.
    digits : int or Tier, optional
        Tier of the continuation (default float64 while ``|E_n - 4| > 1e-5``, where
        float64 ``tr M`` is still right, else real128; without ``traces``: 3e-8).
    steps : int, optional
        Instead of pseudo-arclength: ``steps`` energies from the seed to ``hi``, spaced
        equally in ``sqrt|E - E_n|`` (a natural continuation in ``E``, which stops at a
        fold: :class:`~rotorlib.orbits.continuation.FamilyEnd`); the members are the seed and
        one per step (plus one per halved step) in ``E_range``, the last at ``hi``
        (within :func:`family_range`).
    t_max : float, optional
        Stop once the period exceeds it (default: 12 times the period at birth; the
        family runs into an orbit of infinite period at the maxima of V, E -> 4.5).
    traces : bool
        ``tr M`` of every member and the ``IS``/``PD`` points where it crosses 4 or 0.
    energies : tuple
        Energies at which members are located exactly (``E`` points).
    chart : {'E', 'K'}
        Second unknown: ``E``, or (rotational families) ``q = K - 4`` of the ``a2``
        motion at the base point (``E - 4 = q + T(u)`` without cancellation).
    jump : float, optional
        Refuse steps that change the period by more than this fraction.
    ds, ds_max, max_steps
        First and largest pseudo-arclength step (:class:`~rotorlib.orbits.continuation.PALC`;
        default ``ds_max``: 1 up to ``lo``, then the step that spaces about 24 members
        geometrically in ``E - E_n`` across the range), and the most members followed.

    Returns
    -------
    Branch
        Members inside ``E_range``; special points (``fold``, ``IS``, ``PD``, ``E``)
        located by the engine; ``stop`` and ``reason``: why it ended.

    Raises
    ------
    FamilyRangeError
        ``E_range`` lies below the birth, or above a fold where the family ends.

    Examples
    --------
    >>> from rotorlib.paper.newborn_families import family
    >>> b = family("IS^l_1", (3.991, 4.0))
    >>> float(b.E[0]), float(b.E[-1]), len(b.members), b.stop
    (3.991, 4.0, 14, 'E range')
    >>> b.special_points, [m.stability for m in b.members][-1]
    ((), 'stable')
    >>> g = family("IS^l_2", (3.99, 4.0), steps=4)  # the seed and 4 steps
    >>> len(g.members), float(g.E[-1]), round(float(g.trace[-1]), 4)
    (5, 4.0, 7.6664)
    >>> family("IS^l_1", (3.9, 3.99))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    rotorlib.paper.newborn_families.FamilyRangeError: ... exists for 3.9905882294... < E ...
    """
    spec = family_spec(label)
    t = _default_tier(spec, traces) if digits is None else tier(digits)
    with t.context():
        lo, hi = (t.num(str(v) if t.extended else v) for v in E_range)
    if not lo < hi:
        raise ValueError(f"E_range must be (lo, hi) with lo < hi, got {E_range!r}")
    top = family_range(spec)[1]
    if hi <= spec.E_birth or (FAMILY_REACH[spec.label][1] == "fold" and lo > top):
        raise FamilyRangeError(spec, E_range)
    r_max = _r_max(spec, t, chart)
    if steps is not None:
        if float(hi) > top:
            raise FamilyRangeError(spec, E_range)
        return _inside(branch_from_birth(spec, hi, t, steps, traces), lo, hi, r_max)
    kw: dict[str, Any] = dict(
        t_max=_t_max(spec, t_max), chart=chart, jump=jump, max_steps=max_steps
    )
    start, E0 = None, seed(spec.label, t)[0].E
    if E0 < lo:  # the approach, in long steps, to the member at lo
        a = _branch(spec, (-math.inf, lo), t, traces=False, energies=(lo,), ds=ds,
                    ds_max=ds_max or 1.0, enter=False, **kw)  # fmt: skip
        pts = [p for p in a.points("E") if p.located][-1:]
        at_lo = [m for p in pts for m in _at(a, cast(Member, p.member), lo, r_max)]
        if a.stop != "E range" or not at_lo:
            return _inside(a, lo, hi, r_max)
        start = [a.members[-2], at_lo[0]]
    # the steps across the range: about 24 members spaced geometrically in E - E_n
    with t.context():
        ratio = float((hi - spec.E_birth) / (max(lo, E0) - spec.E_birth))
    fine = ds_max or min(1.0, max(0.002, ratio ** (1 / 24) - 1))
    b = _branch(spec, (lo, hi), t, traces=traces, energies=(lo, hi) + tuple(energies),
                ds=min(ds, fine), ds_max=fine, enter=True, start=start, **kw)  # fmt: skip
    return _inside(b, lo, hi, r_max)


def _at(b: Branch, m: Member, E: Any, r_max: float) -> list[Member]:
    """The member of ``b``'s family at exactly ``E``, corrected from ``m`` (none if the
    corrector fails and ``m`` lies outside)."""
    p, t, traces = b.problem, b.tier, m.trace == m.trace
    try:
        with t.context():
            u = solve(p, m.u, E=E, digits=t, r_max=r_max).x
            return [member(p, u, p.w_at(u, E, t), t, traces)]
    except (NoConvergence, SectionNotReached, ValueError):
        return [m] if m.E == E else []


def _inside(b: Branch, lo: Any, hi: Any, r_max: float) -> Branch:
    """The members of ``b`` inside ``[lo, hi]``, with the members at ``lo`` and ``hi``
    where the branch crosses them, and the special points among them."""
    ms = b.members
    keep = [k for k, m in enumerate(ms) if lo <= m.E <= hi]
    first, last = (keep[0], keep[-1]) if keep else (len(ms), len(ms) - 1)

    def end(p: SpecialPoint, k: int) -> Any:  # the range end crossed after member k
        if p.kind != "E" or not p.located or p.index != k or not 0 <= k < len(ms) - 1:
            return None
        a, c = ms[k].E, ms[k + 1].E
        return next((v for v in (lo, hi) if (a - v) * (c - v) <= 0), None)

    ends = [p for p in b.special_points if end(p, first - 1) is not None]
    head = [
        m
        for p in ends[:1]
        for m in _at(b, cast(Member, p.member), end(p, first - 1), r_max)
    ]
    tails = [p for p in b.special_points if end(p, last) is not None][-1:]
    tail = [
        m for p in tails for m in _at(b, cast(Member, p.member), end(p, last), r_max)
    ]
    ends += tails
    members = head + list(ms[first : last + 1]) + tail
    pts = [
        replace(p, index=max(0, min(len(members) - 1, p.index - first + len(head))))
        for p in b.special_points
        if first - 1 <= p.index <= last
        and lo <= cast(Member, p.member).E <= hi
        and p not in ends
    ]
    n, (flo, fhi) = len(members), (float(lo), float(hi))
    why = (
        f"; {n} members lie inside E_range = ({flo:.12g}, {fhi:.12g})"
        if n
        else f"; no member lies inside E_range = ({flo:.12g}, {fhi:.12g})"
    )
    if not n and b.stop == "E range":
        why += " (the branch passed over it between two members)"
    return replace(
        b, members=tuple(members), special_points=tuple(pts), reason=b.reason + why
    )


def follow(
    label: str,
    *,
    E_range: tuple[float | None, float | None] = (None, None),
    t_max: float | None = None,
    digits: int | Tier | None = None,
    traces: bool = False,
    energies: tuple[float | str, ...] = (),
    chart: str = "E",
    jump: float | None = None,
    ds: float = 0.3,
    ds_max: float = 1.0,
    max_steps: int = 2000,
    clip: bool = True,
) -> Branch:
    """The engine's view of :func:`family` (the chapters' and the census's): the branch
    from the seed, stopped by the first member outside ``E_range = (lo, hi)`` (``None``
    for an end: ``lo = E_n - 2|E_n - 4|``; ``hi = 4.2`` for libration, ``E_n + 6`` for
    rotation), which is dropped with ``clip``; the seed is kept even when it lies
    outside. ``t_max`` bounds the period as in :func:`family`. Prefer :func:`family`,
    whose members all lie inside its range.

    Examples
    --------
    >>> from rotorlib.paper.newborn_families import follow
    >>> b = follow("IS^r_1", E_range=(5.8, 6.0))
    >>> b.stop, len(b.members)
    ('E range', 1)
    """
    spec = family_spec(label)
    t = _default_tier(spec, False) if digits is None else tier(digits)
    lo, hi = E_range
    hi = hi if hi is not None else 4.2 if spec.phase == "lib" else spec.E_birth + 6
    lo = lo if lo is not None else spec.E_birth - 2 * spec.depth
    b = _branch(
        spec,
        (lo, hi),
        t,
        t_max=_t_max(spec, t_max),
        traces=traces,
        energies=tuple(energies),
        chart=chart,
        jump=jump,
        ds=ds,
        ds_max=ds_max,
        max_steps=max_steps,
        enter=False,
    )
    if not clip or b.stop != "E range" or len(b.members) < 2:
        return b
    keep = b.members[:-1]
    pts = [
        p
        for p in b.special_points
        if p.index < len(keep) and lo <= cast(Member, p.member).E <= hi
    ]
    return replace(
        b,
        members=keep,
        special_points=tuple(pts),
        reason=b.reason + " (dropped: the branch ends with its last member inside)",
    )
