"""rotorlib: the 3-rotor bifurcation cascade, re-derived.

A small library reproducing Krishnaswami & Yadav, "Bifurcation cascade,
self-similarity and duality in the 3-rotor problem", Chaos 33, 083101 (2023),
arXiv:2303.01057. Units m = g = r = 1 throughout.

Modules
-------
system      potential, energies, equations of motion, coordinate maps, critical points
energy      energies carried by their distance to a separatrix (input validation)
elliptic    K(m), E(m), Jacobi sn/cn/dn accurate as m -> 1
orbits      closed-form pendula and isosceles breathers
hill        the symmetry-reduced transverse (Lamé/Hill) problem and its precision tiers
monodromy   monodromy matrices: block form for pendula/breathers, textbook 4x4 for any orbit
"""
from .energy import BreatherEnergy, PendulumEnergy, breather_energy, pendulum_energy
from .hill import heyoka_available, precision_tier
from .monodromy import (Monodromy, VariationalResult, monodromy, multipliers_from_trace, textbook_monodromy,
                        trace_monodromy, variational_monodromy)
from .orbits import BreatherOrbit, PendulumOrbit, breather, pendulum, separatrix_pendulum_state
from .system import (BREATHER_SEPARATRIX_ENERGY, SEPARATRIX_ENERGY, CriticalPoint, critical_points,
                     energy_alpha, potential_alpha, potential_phi, rhs_alpha)

__version__ = "0.1.0"

__all__ = [
    "BreatherEnergy", "PendulumEnergy", "breather_energy", "pendulum_energy", "heyoka_available",
    "precision_tier", "Monodromy", "VariationalResult", "monodromy", "multipliers_from_trace",
    "trace_monodromy", "variational_monodromy", "textbook_monodromy", "BreatherOrbit", "PendulumOrbit", "breather", "pendulum",
    "separatrix_pendulum_state", "BREATHER_SEPARATRIX_ENERGY", "SEPARATRIX_ENERGY", "CriticalPoint",
    "critical_points", "energy_alpha", "potential_alpha", "potential_phi", "rhs_alpha",
]
