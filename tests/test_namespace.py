"""``import rotorlib`` gives the front door and the result types, nothing else.

``rotorlib.__all__`` is the four calls, ``LABELS`` and the types they return; every
other public name lives in (and is imported from) its submodule.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

import rotorlib

FRONT_DOOR = ["orbit", "family", "transition", "census", "catalogue", "LABELS"]
TYPES = {
    "PeriodicOrbit": "rotorlib.orbits.periodic_orbit",
    "Branch": "rotorlib.orbits.family",
    "Member": "rotorlib.orbits.family",
    "SpecialPoint": "rotorlib.orbits.family",
    "Transition": "rotorlib.paper.bifurcations",
    "Atlas": "rotorlib.beyond.atlas",
}
# Names that were re-exported by ``import rotorlib`` before the layers, and where they live.
LOW_LEVEL = {
    "rotorlib.core.closed_forms": "BreatherOrbit PendulumOrbit breather pendulum "
    "separatrix_pendulum_state",
    "rotorlib.core.energy": "BreatherEnergy PendulumEnergy breather_energy "
    "pendulum_energy",
    "rotorlib.core.system": "BREATHER_SEPARATRIX_ENERGY SEPARATRIX_ENERGY CriticalPoint "
    "critical_points energy_alpha potential_alpha potential_phi rhs_alpha",
    "rotorlib.orbits.floquet": "Monodromy monodromy multipliers_from_trace "
    "textbook_monodromy trace_monodromy variational_monodromy",
}


def test_all_is_the_front_door_and_the_result_types():
    assert rotorlib.__all__ == FRONT_DOOR + list(TYPES)
    for name, module in TYPES.items():
        assert getattr(rotorlib, name) is getattr(importlib.import_module(module), name)
        assert getattr(rotorlib, name).__module__ == module
    for name in FRONT_DOOR:
        assert getattr(rotorlib, name) is getattr(rotorlib.api, name)
    assert isinstance(rotorlib.__version__, str)


@pytest.mark.parametrize("module", sorted(LOW_LEVEL))
def test_low_level_names_live_in_their_modules(module):
    mod = importlib.import_module(module)
    for name in LOW_LEVEL[module].split():
        assert hasattr(mod, name), (module, name)
        assert not hasattr(rotorlib, name), f"rotorlib.{name} is still top level"


def test_no_module_level_getattr():
    """The package's namespace is what ``__init__`` imports, not computed on access."""
    tree = ast.parse(Path(rotorlib.__file__).read_text(encoding="utf-8"))
    defs = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    assert "__getattr__" not in defs and not hasattr(rotorlib, "__getattr__")
