"""The periodic-orbit result shared by every family, and its construction from a problem."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mpmath as mp
import numpy as np

from .flow import extrema, monodromy_matrix
from .precision import FLOAT64, Tier, json_number
from .shooting import ShootingProblem, residual

__all__ = ["PeriodicOrbit", "periodic_orbit", "orbit_from_state"]

_NO_LOG = "log|E - 4| is not defined here (E = 4 exactly, or a breather's daughter)"


@dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit found numerically.

    Attributes
    ----------
    label : str
        Family label in the paper's notation, e.g. ``IS^l_2``, ``PD^r_3``, ``PD^b``.
    E : float
        Energy (m = g = r = 1).
    period : float
        Period (for period-doubled families, the full doubled period).
    state0 : ndarray (4,)
        Initial state ``[a1, a2, p1, p2]`` (float64 rounding of the computed state).
    monodromy : ndarray (4, 4)
        Monodromy matrix in the state order ``[a1, a2, p1, p2]``.
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
        Search details (unknowns, section, ...); extended tiers add ``state0_str``,
        ``period_str``, ``trace_str`` and ``E_str`` with every verified digit.
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
    extra: dict = field(default_factory=dict)

    def to_record(self) -> dict:
        """A JSON-serialisable dict (the ``orbit`` command's ``--json`` output)."""
        rec = {
            "label": self.label,
            **json_number("E", self.E),
            **json_number("log_abs_dE", self.log_abs_dE, note=_NO_LOG),
            "period": float(self.period),
            "state0": [float(v) for v in self.state0],
            "trace": float(self.trace),
            "alpha1_max": float(self.alpha1_max),
            "alpha2_max": float(self.alpha2_max),
            "residual": float(self.residual),
            "energy_residual": float(self.energy_residual),
            "precision": self.precision,
            "monodromy": [
                [float(v) for v in row] for row in np.asarray(self.monodromy)
            ],
        }
        rec.update(
            {
                k: v
                for k, v in self.extra.items()
                if isinstance(v, (str, int, float, list))
            }
        )
        return rec


def orbit_from_state(
    label,
    x0,
    period,
    t: Tier = FLOAT64,
    lattice=(0.0, 0.0),
    E=None,
    extra=None,
    digits=None,
) -> PeriodicOrbit:
    """A :class:`PeriodicOrbit` from its initial state and period, integrated in tier ``t``:
    the monodromy from the 4x4 variational equations over one period, the closure against the
    lattice vector ``lattice`` (units of pi); extended tiers add the state, period, trace and
    energy as strings of ``digits`` significant digits (default: the tier's, less 8)."""
    from .system import energy_alpha

    with t.context():
        x0 = [t.num(v) for v in x0]
        T = t.num(period)
        M, xT, tr = monodromy_matrix(x0, T, t)
        lat = [lattice[0] * t.pi, lattice[1] * t.pi, 0, 0]
        closure = max(abs(float(a - b - c)) for a, b, c in zip(xT, x0, lat))
        if E is not None:
            E = t.num(E)
        else:
            E = (
                x0[2] ** 2 / 4
                + 3 * x0[3] ** 2 / 4
                + 3
                - t.m.cos(2 * x0[0])
                - t.m.cos(x0[1] - x0[0])
                - t.m.cos(x0[0] + x0[1])
            )
        eps = abs(E - 4)
        xf = np.array([float(v) for v in x0])
        a1m, a2m = extrema(xf, float(T), FLOAT64)
        ex = dict(extra or {})
        if t.extended:
            d = digits or t.dps - 8
            ex.update(
                state0_str=[t.text(v, d) for v in x0],
                period_str=t.text(T, d),
                trace_str=t.text(tr, d if digits else d - 7),
                E_str=t.text(E, d),
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
            float(mp.log(eps)) if eps else math.nan,
            ex,
        )


def periodic_orbit(
    problem: ShootingProblem,
    u,
    w,
    t: Tier = FLOAT64,
    label=None,
    extra=None,
    digits=None,
) -> PeriodicOrbit:
    """The :class:`PeriodicOrbit` of ``problem`` at ``(u, w)`` (:func:`orbit_from_state`)."""
    with t.context():
        s = residual(problem, u, w, t)
        ex = {"u": float(u), "t1": float(s.t1)}
        ex.update(extra or {})
        return orbit_from_state(
            label or problem.label,
            s.x0,
            problem.factor * s.t1,
            t,
            problem.lattice,
            problem.energy(u, w, t),
            ex,
            digits,
        )
