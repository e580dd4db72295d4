"""The results of the continuation engine: :class:`Member`, :class:`SpecialPoint`,
:class:`Branch` (one family container).

A :class:`Member` follows the result protocol of :class:`~rotorlib.orbits.periodic_orbit.OrbitResult`
(``label``, ``E``, ``period``, ``trace``, ``state0``, ``digits``, the decimal strings
``E_str``, ``period_str``, ``trace_str``, ``state0_str``, ``multipliers``,
``stability`` and ``to_dict()``), so that a branch member and a
:class:`~rotorlib.orbits.periodic_orbit.PeriodicOrbit` are read alike.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.precision import Tier, json_number
from .periodic_orbit import OrbitResult
from .shooting import ShootingProblem

__all__ = ["Member", "SpecialPoint", "Branch", "energy_range"]


@dataclass(frozen=True)
class Member(OrbitResult):
    """One periodic orbit of a family (a point of a :class:`Branch`).

    Attributes
    ----------
    u, w : tier number
        The unknowns: the amplitude on the start set and the energy chart's value.
    E : tier number
        Energy (float64, or ``mpf`` in an extended tier).
    t1 : tier number
        Time of the second symmetric point (``period = factor * t1``).
    r : tier number
        Shooting residual.
    trace : tier number
        ``tr M`` over the full period (``nan`` unless computed).
    x1 : tuple
        The state at ``t1``.
    label : str
        The family.
    factor : int
        ``period / t1``.
    x0 : tuple
        The initial state (tier numbers).
    digits : int
        Significant digits of the decimal strings: 15 in float64; in an extended tier
        the digits the residual ``r`` leaves (at most the tier's less 8).
    precision : str
        The tier's name (``float64``, ``real128``, ``mp<bits>``).

    Examples
    --------
    >>> from rotorlib.paper.newborn import family
    >>> m = family("IS^l_1", (3.991, 4.0)).members[0]
    >>> m.label, m.E, m.stability, m.state0.shape, round(m.trace, 3)
    ('IS^l_1', 3.991, 'stable', (4,), 3.869)
    >>> m.to_dict()["E"], m.to_dict()["stability"]
    (3.991, 'stable')
    """

    u: Any
    w: Any
    E: Any
    t1: Any
    r: Any
    trace: Any = math.nan
    x1: tuple[Any, ...] = ()
    label: str = ""
    factor: int = 1
    x0: tuple[Any, ...] = ()
    digits: int = 15
    precision: str = "float64"

    @property
    def stability(self) -> str:
        """``stable``, ``unstable``, ``marginal`` (:func:`~rotorlib.orbits.floquet.stability_of`),
        or ``unknown`` when ``tr M`` was not computed."""
        return super().stability if self.trace == self.trace else "unknown"

    @property
    def period(self) -> Any:
        """``factor * t1`` (a tier number)."""
        return Tier(self.precision).scale(self.factor, self.t1)

    @property
    def state0(self) -> np.ndarray:
        """The initial state ``[a1, a2, p1, p2]`` (float64 rounding)."""
        return np.array([float(v) for v in self.x0])

    def _text(self, v: Any, less: int = 0) -> str:
        t = Tier(self.precision)
        return t.text(v, max(1, self.digits - less)) if t.extended else repr(float(v))

    @property
    def E_str(self) -> str:
        return self._text(self.E)

    @property
    def period_str(self) -> str:
        return self._text(self.period)

    @property
    def trace_str(self) -> str:
        """``tr M`` (7 digits fewer than ``E_str`` in an extended tier: ``|M|`` is large)."""
        return self._text(self.trace, 7)

    @property
    def state0_str(self) -> tuple[str, ...]:
        return tuple(self._text(v) for v in self.x0)

    def to_dict(self) -> dict[str, Any]:
        """The member as JSON (the rule of :func:`~rotorlib.core.precision.json_number`)."""
        ext = Tier(self.precision).extended
        tr = float(self.trace)
        rec: dict[str, Any] = {
            "label": self.label,
            **json_number("E", self.E, self.E_str if ext else None),
            **json_number("period", self.period, self.period_str if ext else None),
            "state0": [float(v) for v in self.x0],
            **json_number("trace", tr, self.trace_str if ext else None, "not computed"),
            "multipliers": (
                [[z.real, z.imag] for z in self.multipliers] if tr == tr else None
            ),
            "stability": self.stability,
            "digits": self.digits,
            "precision": self.precision,
            "u": float(self.u),
            "t1": float(self.t1),
            "residual": float(self.r),
        }
        if ext:
            rec["state0_str"] = list(self.state0_str)
        return rec


@dataclass(frozen=True)
class SpecialPoint:
    """A special point: where something happens along a family (the one special-point
    type of rotorlib: the engine's events, a choreography's stability changes, and,
    through the subclass :class:`~rotorlib.paper.bifurcations.Transition`, the
    pendulum's and the breather's transitions).

    Attributes
    ----------
    kind : str
        ``fold`` (of ``E``), ``E`` (a requested energy), ``IS`` (``tr M`` or a reduced
        map's trace through 4), ``PD`` (through 0), ``touch`` (a trace touching 4 or 0
        without a change of stability), ``resonance``, ``pitchfork``, ...
    member : Member or None
        The member located there (the best location: the one in the tier asked for);
        ``None`` for a point that is not on a branch (a transition) or, with ``located``
        ``None``, the nearest member where the location failed.
    index : int
        The member of the branch after which the point lies (-1: before the first).
    located : str or None
        How the point was located (the method, or the agreement of two locations);
        ``None`` when the location failed (the orbit stops reaching its section there):
        ``member`` is then the nearest member of the branch.
    description : str
        What happens there, in words (``stable -> unstable (tr DP = 4)``).
    E, E_str : float, str
        The energy, and as a decimal with its verified digits: the member's (its
        ``E_str`` in an extended tier, 13 decimals in float64) when there is one.
    rotation : str or None
        A rotation number where one applies (``"2/7"`` at a resonance).
    families : tuple of str
        The families born there.
    branch : str
        The branch or branches the point lies on (``CG/CT``), where a family has several.

    Examples
    --------
    >>> from rotorlib.paper.newborn import family
    >>> (p,) = family("IS^l_1", (3.9, 4.1)).special_points
    >>> p.kind, p.E_str, p.located
    ('IS', '4.0357079207117', 'Illinois between two members (to 1e-14, float64)')
    >>> sorted(p.to_dict())[:5]
    ['E', 'branch', 'description', 'families', 'index']
    """

    kind: str
    member: Member | None = None
    index: int = -1
    located: str | None = "located"
    description: str = ""
    E: float = math.nan
    E_str: str = ""
    rotation: str | None = None
    families: tuple[str, ...] = ()
    branch: str = ""

    def __post_init__(self) -> None:
        if (m := self.member) is not None:  # E, E_str: the member's (set once, here)
            self.__dict__.update(
                E=float(m.E),
                E_str=m.E_str if Tier(m.precision).extended else f"{float(m.E):.13f}",
            )

    @property
    def position(self) -> float:
        """Where the point lies among the members: a fold at its member (``index``),
        an IS, PD or E point half-way from its member to the next."""
        return self.index + (0.0 if self.kind == "fold" else 0.5)

    def to_dict(self) -> dict[str, Any]:
        """The point as JSON: ``kind``, ``E`` (and ``E_str`` when it has more digits,
        :func:`~rotorlib.core.precision.json_number`), ``located``, ``description``,
        ``rotation``, ``families``, ``branch``, ``index`` and the ``member``'s JSON (or
        ``null``)."""
        return {
            "kind": self.kind,
            **json_number("E", self.E, self.E_str if len(self.E_str) > 17 else None),
            "located": self.located,
            "description": self.description,
            "rotation": self.rotation,
            "families": list(self.families),
            "branch": self.branch,
            "index": self.index,
            "member": None if self.member is None else self.member.to_dict(),
        }


@dataclass(frozen=True)
class Branch:
    """A family followed by :func:`~rotorlib.orbits.continuation.continuation`: the one family
    container of rotorlib.

    Attributes
    ----------
    problem : ShootingProblem
    tier : Tier
    members : tuple of Member
        In order along the branch.
    special_points : tuple of SpecialPoint
        Folds of ``E``, requested energies (``E``) and the energies where ``tr M``
        crosses 4 (``IS``) or 0 (``PD``), located between members.
    stop : str
        Why the continuation ended, as a code (see :mod:`rotorlib.orbits.continuation`).
    reason : str
        The same as one sentence, with the numbers that triggered it.
    E_range : (float, float)
        The energies the branch was asked to stay in.

    Examples
    --------
    >>> from rotorlib.paper.newborn import family
    >>> b = family("IS^l_1", (3.9, 4.1))
    >>> bool(3.9 <= b.E.min() and b.E.max() <= 4.1), b.stop
    (True, 'E range')
    >>> [(p.kind, round(float(p.member.E), 6)) for p in b.special_points]
    [('IS', 4.035708)]
    >>> stable = [m.E for m in b.members if m.stable]  # the stable window
    >>> round(min(stable), 6), round(max(stable), 4)
    (3.99059, 4.0158)
    >>> d = b.to_dict()
    >>> d["E_range"], d["special_points"][0]["kind"], len(d["members"]) == len(b.members)
    ([3.9, 4.1], 'IS', True)
    """

    problem: ShootingProblem
    tier: Tier
    members: tuple[Member, ...]
    special_points: tuple[SpecialPoint, ...] = ()
    stop: str = ""
    reason: str = ""
    E_range: tuple[float, float] = (-math.inf, math.inf)

    def _col(self, name: str) -> np.ndarray:
        return np.array([float(getattr(m, name)) for m in self.members])

    @property
    def label(self) -> str:
        return self.problem.label

    @property
    def u(self) -> np.ndarray:
        return self._col("u")

    @property
    def dE(self) -> np.ndarray:
        """``E - 4`` of the members, formed in the tier (no cancellation)."""
        with self.tier.context():
            return np.array([float(m.E - 4) for m in self.members])

    @property
    def E(self) -> np.ndarray:
        return self._col("E")

    @property
    def t1(self) -> np.ndarray:
        return self._col("t1")

    @property
    def period(self) -> np.ndarray:
        return self.problem.factor * self._col("t1")

    @property
    def trace(self) -> np.ndarray:
        return self._col("trace")

    def points(self, kind: str) -> list[SpecialPoint]:
        """The special points of one kind (``fold``, ``E``, ``IS``, ``PD``)."""
        return [p for p in self.special_points if p.kind == kind]

    @property
    def fold(self) -> Member | None:
        """The first located fold (a :class:`Member`), or ``None``."""
        return next((p.member for p in self.points("fold") if p.located), None)

    @property
    def E_max(self) -> float:
        """The largest energy on the branch (a located fold where there is one)."""
        return max([p.E for p in self.points("fold")] + list(self.E))

    @property
    def stable_windows(self) -> list[tuple[float, float]]:
        """The energies where the family is linearly stable.

        ``[(E_a, E_b)]``: each run of consecutive linearly stable members
        (``0 < tr M < 4``), bounded by the located points on either side of it and the
        folds within it (or by its end members where none was located); and each
        stretch between two members, both unstable, where ``tr M`` crosses both 4 and 0
        (bounded by those two points). The ends have the precision of the located
        points, or of the members' ``E``.

        Examples
        --------
        >>> from rotorlib.paper.newborn import family
        >>> windows = family("IS^l_1", (3.9, 4.1)).stable_windows
        >>> [(round(lo, 6), round(hi, 6)) for lo, hi in windows]
        [(3.99059, 4.035708)]
        """
        st = [0 < t < 4 for t in self.trace]
        marks = [(p.kind, p.E, p.position) for p in self.special_points]
        E, out, i = self.E, [], 0
        for stable, run in itertools.groupby(st):
            j = i + len(list(run))  # members i .. j - 1
            if stable:  # the run, the points beside it and the folds within it
                ends = [*E[i:j], *(e for _, e, x in marks if i - 1 < x < j)]
                out.append((float(min(ends)), float(max(ends))))
            i = j
        for i in range(len(st) - 1):  # tr M crossing 4 and 0 between unstable members
            inside = [
                (k, e) for k, e, x in marks if i < x < i + 1 and k in ("IS", "PD")
            ]
            if not (st[i] or st[i + 1]) and {k for k, _ in inside} == {"IS", "PD"}:
                out.append((min(e for _, e in inside), max(e for _, e in inside)))
        return sorted(out)

    def state(self, m: Member) -> list[Any]:
        """The initial state of a member (tier numbers)."""
        return self.problem.state(m.u, m.w, self.tier)

    def to_dict(self) -> dict[str, Any]:
        """The branch as JSON: ``label``, ``E_range``, ``stop``, ``reason``, ``members``
        and ``special_points`` (each with its ``kind``)."""
        return {
            "label": self.label,
            "E_range": [
                float(v) if math.isfinite(float(v)) else None for v in self.E_range
            ],
            "stop": self.stop,
            "reason": self.reason,
            "members": [m.to_dict() for m in self.members],
            "special_points": [p.to_dict() for p in self.special_points],
        }


def energy_range(E_range: Sequence[Any]) -> tuple[float, float]:
    """``E_range = (lo, hi)`` as floats, checked: two finite energies with ``lo < hi``
    (the range of every family, :func:`rotorlib.api.family`). Raises ValueError otherwise.

    Examples
    --------
    >>> from rotorlib.orbits.family import energy_range
    >>> energy_range(("5", 5.4))
    (5.0, 5.4)
    >>> energy_range((5.4, 5.0))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: E_range must be two finite energies (lo, hi) with lo < hi, got (5.4, 5.0)
    """
    lo, hi = (float(v) for v in E_range)
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(
            f"E_range must be two finite energies (lo, hi) with lo < hi, got {E_range!r}"
        )
    return lo, hi
