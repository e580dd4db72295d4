"""The periodic-orbit result shared by every family, and its construction from a problem."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import mpmath as mp
import numpy as np

from ..core.flow import extrema, monodromy_matrix
from ..core.precision import FLOAT64, Tier, json_number, tier
from .floquet import multipliers_from_trace, stability_of
from .shooting import ShootingProblem, residual

__all__ = [
    "PeriodicOrbit",
    "OrbitResult",
    "periodic_orbit",
    "orbit_from_state",
]

_NO_EXTREMA = "the extrema of a1, a2 are not computed for this orbit (a census)"
_NO_LOG = "log|E - 4| is not defined here (E = 4 exactly, or an orbit not born of the pendulum)"


class OrbitResult:
    """The result protocol shared by :class:`PeriodicOrbit`, the members of a
    :class:`~rotorlib.orbits.continuation.Branch` and a :class:`~rotorlib.paper.bifurcations.Transition`.

    Subclasses carry ``label``, ``E``, ``period``, ``trace``, ``state0`` and ``digits``
    (and ``E_str``, ``period_str``, ``trace_str``, ``state0_str``, the decimal strings
    with every verified digit); this class adds the multipliers and the stability.
    """

    trace: float
    digits: int

    @property
    def multipliers(self) -> tuple[complex, complex, complex, complex]:
        """The four Floquet multipliers ``(1, 1, mu, 1/mu)``: a periodic orbit of a
        two-degree-of-freedom Hamiltonian has the pair 1, 1 (the flow and the energy) and
        ``mu + 1/mu = tr M - 2``."""
        mu = multipliers_from_trace(float(self.trace) - 2.0)
        return (1 + 0j, 1 + 0j, complex(mu[0]), complex(mu[1]))

    @property
    def stability(self) -> str:
        """``stable``, ``unstable`` or ``marginal`` (:func:`stability_of`)."""
        return stability_of(self.trace, self.digits)

    @property
    def stable(self) -> bool:
        """``stability == 'stable'``."""
        return self.stability == "stable"


@dataclass(frozen=True)
class PeriodicOrbit(OrbitResult):
    """A periodic orbit: the one orbit result of rotorlib.

    Attributes
    ----------
    label : str
        Family label in the paper's notation, e.g. ``IS^l_2``, ``PD^r_3``, ``PD^b``, ``CG``.
    E : float
        Energy (m = g = r = 1).
    period : float
        Period (for period-doubled families, the full doubled period).
    state0 : ndarray (4,)
        Initial state ``[a1, a2, p1, p2]`` (float64 rounding of the computed state).
    monodromy : ndarray (4, 4)
        Monodromy matrix in the state order ``[a1, a2, p1, p2]`` (float64 rounding).
    trace : float
        ``tr M``.
    residual : float
        Closure ``max |x(T) - x(0) - L|`` (``L`` the lattice vector of the family), in
        the working precision.
    energy_residual : float
        ``|H(state0) - E|`` of the float64 ``state0``.
    precision : str
        The tier that found and integrated the orbit (``float64``, ``real128``, ``mp<bits>``).
    alpha1_max, alpha2_max : float
        ``max |a1(t)|`` and the largest excursion of ``a2`` over one period.
    log_abs_dE : float
        ``log|E - 4|`` (nan when not meaningful).
    extra : dict
        How it was found (unknowns ``u``, symmetric time ``t1``, section, ...).
    digits : int
        Significant digits of ``E_str``, ``period_str`` and ``state0_str`` (15: float64).
    E_str, period_str, trace_str : str
        ``E``, the period and ``tr M`` with every verified digit (``repr`` in float64).
    state0_str : tuple of str
        The initial state with every verified digit.
    family : str
        A census's family id (orbits of one family at other energies share it), else ``""``.

    The protocol (:class:`OrbitResult`) adds ``multipliers``, ``stability`` and ``stable``;
    a choreography's stability is decided by its reduced map (``extra['stability']``).

    Examples
    --------
    >>> import rotorlib
    >>> o = rotorlib.orbit("pendulum", 3.9)
    >>> o.label, o.stability, round(o.period, 9)
    ('pendulum', 'stable', 7.493684782)
    >>> sorted(o.to_dict())[:4]
    ['E', 'alpha1_max', 'alpha2_max', 'digits']
    """

    label: str
    E: float
    period: float
    state0: np.ndarray
    monodromy: np.ndarray
    trace: float
    residual: float
    energy_residual: float
    precision: str
    alpha1_max: float
    alpha2_max: float
    log_abs_dE: float = float("nan")
    extra: dict[str, Any] = field(default_factory=dict)
    digits: int = 15
    E_str: str = ""
    period_str: str = ""
    trace_str: str = ""
    state0_str: tuple[str, ...] = ()
    family: str = ""

    def __post_init__(self) -> None:
        for k in ("E", "period", "trace"):
            if not getattr(self, k + "_str"):
                object.__setattr__(self, k + "_str", repr(float(getattr(self, k))))
        if not self.state0_str:
            object.__setattr__(
                self, "state0_str", tuple(repr(float(v)) for v in self.state0)
            )

    @property
    def stability(self) -> str:
        """``stable``, ``unstable`` or ``marginal`` (a choreography: its reduced map's)."""
        return self.extra.get("stability") or stability_of(self.trace, self.digits)

    def to_dict(self) -> dict[str, Any]:
        """The JSON the ``orbit`` command prints (:func:`~rotorlib.core.precision.json_number`:
        float64 values as numbers, digits beyond float64 in ``*_str`` strings)."""
        ext = self.digits > 15
        rec: dict[str, Any] = {
            "label": self.label,
            **json_number("E", self.E, self.E_str if ext else None),
            **json_number("log_abs_dE", self.log_abs_dE, note=_NO_LOG),
            **json_number("period", self.period, self.period_str if ext else None),
            "state0": [float(v) for v in self.state0],
            **json_number("trace", self.trace, self.trace_str if ext else None),
            "multipliers": [[z.real, z.imag] for z in self.multipliers],
            "stability": self.stability,
            "digits": self.digits,
            **json_number("alpha1_max", self.alpha1_max, note=_NO_EXTREMA),
            **json_number("alpha2_max", self.alpha2_max, note=_NO_EXTREMA),
            **json_number("residual", self.residual),
            **json_number("energy_residual", self.energy_residual),
            "precision": self.precision,
            "monodromy": [
                [float(v) for v in row] for row in np.asarray(self.monodromy)
            ],
        }
        if ext:
            rec["state0_str"] = list(self.state0_str)
        if self.family:
            rec["family"] = self.family
        rec.update(
            {
                k: list(v) if isinstance(v, tuple) else v
                for k, v in self.extra.items()
                if isinstance(v, (str, int, float, list, tuple, dict, type(None)))
                and k not in rec
            }
        )
        return rec


def orbit_from_state(
    label: str,
    x0: Sequence[Any],
    period: Any,
    digits: int | Tier | None,
    lattice: tuple[float, float],
    E: Any,
    extra: dict[str, Any] | None = None,
    *,
    shown: int | None = None,
) -> PeriodicOrbit:
    """A :class:`PeriodicOrbit` from its initial state, period and energy, integrated in
    the tier of ``digits`` (:func:`~rotorlib.core.precision.tier`): the monodromy from the 4x4
    variational equations over one period, the closure against the lattice vector
    ``lattice`` (units of pi); extended tiers give the state, period, trace and energy as
    strings of ``shown`` significant digits (default: the tier's, less 8)."""
    from ..core.system import energy_alpha

    t = tier(digits)
    with t.context():
        x0 = [t.num(v) for v in x0]
        T = t.num(period)
        M, xT, tr = monodromy_matrix(x0, T, t)
        lat = [lattice[0] * t.pi, lattice[1] * t.pi, 0, 0]
        closure = max(abs(float(a - b - c)) for a, b, c in zip(xT, x0, lat))
        E = t.num(E)
        xf = np.array([float(v) for v in x0])
        a1m, a2m = extrema(xf, float(T), FLOAT64)
        d = shown or t.dps - 8
        strs: dict[str, Any] = (
            dict(
                digits=d,
                E_str=t.text(E, d),
                period_str=t.text(T, d),
                trace_str=t.text(tr, d if shown else d - 7),
                state0_str=tuple(t.text(v, d) for v in x0),
            )
            if t.extended
            else {}
        )
        return PeriodicOrbit(
            label,
            float(E),
            float(T),
            xf,
            M,
            float(tr),
            closure,
            abs(float(energy_alpha(xf)) - float(E)),
            t.name,
            a1m,
            a2m,
            float(mp.log(abs(E - 4))) if E != 4 else math.nan,
            dict(extra or {}),
            **strs,
        )


def periodic_orbit(
    problem: ShootingProblem,
    u: Any,
    w: Any,
    digits: int | Tier | None = None,
    label: str | None = None,
    extra: dict[str, Any] | None = None,
    *,
    shown: int | None = None,
) -> PeriodicOrbit:
    """The :class:`PeriodicOrbit` of ``problem`` at ``(u, w)`` (:func:`orbit_from_state`)."""
    t = tier(digits)
    with t.context():
        s = residual(problem, u, w, t)
        return orbit_from_state(
            label or problem.label,
            s.x0,
            t.scale(problem.factor, s.t1),
            t,
            problem.lattice,
            problem.energy(u, w, t),
            {"u": float(u), "t1": float(s.t1), **(extra or {})},
            shown=shown,
        )
