"""The result object shared by every periodic-orbit search (newborn orbits, breather daughters)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["PeriodicOrbit"]


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
        Initial state ``[a1, a2, p1, p2]`` (pendulum variables of ``../shared/NUMERICS.md``).
    monodromy : ndarray (4, 4)
        Monodromy matrix in the state order ``[a1, a2, p1, p2]``.
    trace : float
        ``tr M``.
    residual : float
        Closure ``max |x(T) - x(0)|`` (modulo the configuration lattice) at the
        precision of the search.
    energy_residual : float
        ``|H(state0) - E|``.
    precision : str
        ``float64``, ``real128`` or ``mp<bits>``: what the search integrated with.
    alpha1_max, alpha2_max : float
        ``max |a1(t)|`` and ``max |a2(t)|`` over one period (a2 taken modulo the lattice
        for rotational orbits: the largest excursion of a2 from its value at the base point).
    log_abs_dE : float
        ``log|E - 4|`` (nan when not meaningful).
    extra : dict
        Anything else the search wants to report (e.g. shooting unknowns, step counts).
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
        return {
            "label": self.label,
            "E": repr(float(self.E)),
            "log_abs_dE": repr(float(self.log_abs_dE)),
            "period": float(self.period),
            "state0": [float(v) for v in self.state0],
            "trace": float(self.trace),
            "alpha1_max": float(self.alpha1_max),
            "alpha2_max": float(self.alpha2_max),
            "residual": float(self.residual),
            "energy_residual": float(self.energy_residual),
            "precision": self.precision,
            "monodromy": [[float(v) for v in row] for row in np.asarray(self.monodromy)],
        }
