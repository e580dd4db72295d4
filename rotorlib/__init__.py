"""rotorlib: the 3-rotor bifurcation cascade, re-derived.

A small library reproducing Krishnaswami & Yadav, "Bifurcation cascade,
self-similarity and duality in the 3-rotor problem", Chaos 33, 083101 (2023),
arXiv:2303.01057. Units m = g = r = 1 throughout.

Front door (:mod:`rotorlib.api`): ``orbit``, ``family``, ``transition``, ``census``;
``digits`` the one precision argument; every result has ``to_dict()``.

Modules, by section of the paper
--------------------------------
====================  ======  ======================================================================
module                paper   what
====================  ======  ======================================================================
system                §2      potential, energies, equations of motion, coordinates, critical points
energy                §2      energies carried by their distance to a separatrix (input validation)
elliptic              §2      K(m), E(m), Jacobi sn/cn/dn accurate as m -> 1
orbits                §2      closed-form pendula and isosceles breathers
hill                  §4      the symmetry-reduced transverse (Lamé/Hill) problem
floquet               §4      monodromy (Floquet) matrices: block form for pendula/breathers, textbook 4x4 for any orbit
bifurcations          §3, §5  stability transitions of pendula (Tables I, II)
scaling               §5      scaling constants, asymptotics of tr M, families' tr M curves
precision             --      the one ``digits`` control: float64, real128, multiprecision tiers
flow                  --      the nonlinear flow, variational equations, section events (any tier)
shooting              §6      symmetric periodic orbits as roots of one residual; the corrector
continuation          §6-7    one continuation engine: Natural / PALC, events, Branch
periodic              §6-7    the PeriodicOrbit result
search                §6      the paper's search against the symmetric shooting
newborn               §7.1-2  the families born at pendulum bifurcations (IS/PD)
laws                  §7.3-6  slope theorems, fans, self-similar scaling, duality
breather_bifurcation  §8      the breathers' transition and the daughter family PD^b
chaos                 §9      sections, Lyapunov exponents, families followed to the band
reversors             beyond  reversing symmetries of H and their fixed sets
atlas                 beyond  every symmetric periodic orbit with T <= T_max (the band, §9)
atlas_families        beyond  their families, branch switching, the period-doubling cascade (§9, §10)
compare               --      our numbers against the paper's: one rule, one record, one table
qubit                 App. A  the flux-qubit analogy
lame_functions        App. B  Lamé functions and the trace of M
parallel              --      sweeps on a process pool or a Dask cluster (pmap)
====================  ======  ======================================================================
"""

from .api import LABELS, catalogue, census, family, orbit, transition
from .core.closed_forms import (
    BreatherOrbit,
    PendulumOrbit,
    breather,
    pendulum,
    separatrix_pendulum_state,
)
from .core.energy import (
    BreatherEnergy,
    PendulumEnergy,
    breather_energy,
    pendulum_energy,
)
from .core.system import (
    BREATHER_SEPARATRIX_ENERGY,
    SEPARATRIX_ENERGY,
    CriticalPoint,
    critical_points,
    energy_alpha,
    potential_alpha,
    potential_phi,
    rhs_alpha,
)
from .orbits.floquet import (
    Monodromy,
    monodromy,
    multipliers_from_trace,
    textbook_monodromy,
    trace_monodromy,
    variational_monodromy,
)
from .orbits.hill import heyoka_available, precision_tier
from .orbits.periodic_orbit import PeriodicOrbit

__version__ = "1.0.0"

__all__ = [
    "orbit",
    "family",
    "transition",
    "census",
    "catalogue",
    "LABELS",
    "PeriodicOrbit",
    "BreatherEnergy",
    "PendulumEnergy",
    "breather_energy",
    "pendulum_energy",
    "heyoka_available",
    "precision_tier",
    "Monodromy",
    "monodromy",
    "multipliers_from_trace",
    "trace_monodromy",
    "variational_monodromy",
    "textbook_monodromy",
    "BreatherOrbit",
    "PendulumOrbit",
    "breather",
    "pendulum",
    "separatrix_pendulum_state",
    "BREATHER_SEPARATRIX_ENERGY",
    "SEPARATRIX_ENERGY",
    "CriticalPoint",
    "critical_points",
    "energy_alpha",
    "potential_alpha",
    "potential_phi",
    "rhs_alpha",
]
