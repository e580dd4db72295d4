"""rotorlib: the 3-rotor bifurcation cascade, re-derived.

A small library reproducing Krishnaswami & Yadav, "Bifurcation cascade,
self-similarity and duality in the 3-rotor problem", Chaos 33, 083101 (2023),
arXiv:2303.01057. Units m = g = r = 1 throughout.

Front door (:mod:`rotorlib.api`): ``orbit``, ``family``, ``transition``, ``census``;
``digits`` the one precision argument; every result has ``to_dict()``. ``import
rotorlib`` gives these four calls, ``LABELS`` and the result types (``PeriodicOrbit``,
``Branch``, ``Member``, ``SpecialPoint``, ``Transition``, ``Atlas``); everything else is
imported from its module (e.g. ``from rotorlib.orbits.floquet import monodromy``).

Layers
------
Each layer imports only the layers above it in this table (core the lowest); the
numerical modules never import :mod:`rotorlib.plotting`.

==========  =============================================================================
layer       modules
==========  =============================================================================
``core``    the system and its flow: ``system`` (potential, equations of motion,
            coordinates, critical points; paper §2), ``energy`` (energies carried by
            their distance to a separatrix), ``elliptic`` (K(m), E(m), Jacobi functions
            as m -> 1), ``closed_forms`` (pendula and isosceles breathers), ``precision``
            (the ``digits`` tiers: float64, real128, multiprecision), ``flow`` (the flow,
            variational equations, section events), ``parallel`` (``pmap`` on a process
            pool or a Dask cluster), ``compare`` and ``rounding`` (our numbers against the
            paper's, rounded to their verified digits)
``orbits``  the periodic-orbit engine: ``shooting`` (symmetric orbits as roots of one
            residual; §6), ``continuation`` (one engine, natural and pseudo-arclength),
            ``floquet`` (monodromy matrices; §4), ``hill`` (the symmetry-reduced
            Lamé/Hill problem), ``reversors`` (reversing symmetries and their fixed
            sets), ``periodic_orbit`` (the ``PeriodicOrbit`` result), ``family``
            (``Branch``, ``Member``, ``SpecialPoint``)
``paper``   the paper's results: ``bifurcations`` (pendulum transitions, Tables I-II;
            §3, §5), ``cascade_scaling`` (scaling constants, asymptotics of tr M; §5),
            ``search`` (the paper's search; §6), ``newborn`` and ``newborn_families``
            (the orbits born at IS/PD points; §7.1-2), ``newborn_laws`` (slope theorems,
            fans, self-similarity, duality; §7.3-6), ``breathers`` (the breather's
            transition and PD^b; §8), ``chaos`` (the band of global chaos; §9),
            ``qubit`` (App. A), ``lame_functions`` (App. B)
``beyond``  new science: ``atlas`` and ``atlas_families`` (every symmetric periodic orbit
            with T <= T_max, their families and cascade), ``choreo``, ``choreo_family``,
            ``choreo_z3`` (choreographies), ``quantum`` and ``quantum_semiclassics`` (the
            quantum 3-rotor)
front door  ``api`` (``orbit``, ``family``, ``transition``, ``census``), ``cli`` and
            ``commands`` (``python -m rotorlib``); ``plotting`` (matplotlib, one module
            per chapter)
==========  =============================================================================
"""

from .api import LABELS, catalogue, census, family, orbit, transition
from .beyond.atlas import Atlas
from .orbits.family import Branch, Member, SpecialPoint
from .orbits.periodic_orbit import PeriodicOrbit
from .paper.bifurcations import Transition

__version__ = "1.0.0"

__all__ = [
    "orbit",
    "family",
    "transition",
    "census",
    "catalogue",
    "LABELS",
    "PeriodicOrbit",
    "Branch",
    "Member",
    "SpecialPoint",
    "Transition",
    "Atlas",
]
