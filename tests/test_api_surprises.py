"""The silent surprises of the public API: each returns what it documents, or says why not."""

from __future__ import annotations

import importlib
import math

import mpmath as mp
import pytest

from rotorlib.orbits.continuation import (
    ContinuationOptions,
    FamilyEnd,
    Natural,
    continuation,
)
from rotorlib.orbits.floquet import monodromy, trace_monodromy
from rotorlib.paper.bifurcations import transition
from rotorlib.paper.newborn import family, family_spec, seed


def test_trace_monodromy_returns_the_extended_value():
    t64 = trace_monodromy(E=3.9)
    t40 = trace_monodromy(E=3.9, digits=40)
    assert isinstance(t64, float)
    assert isinstance(t40, mp.mpf)  # not its float64 rounding
    ref = monodromy(E=3.9, digits=40).trace_str
    with mp.workdps(50):
        assert abs(t40 - mp.mpf(ref)) < mp.mpf(10) ** -40
        # it carries digits a float64 cannot: differs from its own float64 rounding
        assert abs(t40 - mp.mpf(float(t40))) > mp.mpf(10) ** -30
    assert abs(float(t40) - t64) < 1e-12


def test_monodromy_accepts_a_transition_energy():
    tr = transition("IS^l_2")
    M = monodromy(tr.energy)  # used to raise AttributeError
    assert abs(M.trace - 4) < 1e-9
    assert M.trace == monodromy(E=tr.energy).trace


@pytest.mark.parametrize("bad", [4.0, "3.9", None.__class__])
def test_monodromy_names_what_to_pass(bad):
    if bad is None.__class__:
        bad = object()
    with pytest.raises(TypeError, match="pendulum or breather orbit"):
        monodromy(bad)


def test_family_steps_counts_steps_as_documented():
    doc = family.__doc__
    assert "one per step (plus one per halved step)" in doc
    fam = family("IS^l_2", (3.99, 4.0), steps=4).members
    assert len(fam) >= 4 + 1
    assert float(fam[-1].E) == 4.0
    E = [float(o.E) for o in fam]
    assert all(a < b for a, b in zip(E, E[1:]))


def _natural(values, **opts):
    spec = family_spec("IS^l_2")
    m0, _ = seed(spec.label)
    alg = Natural("E", tuple(values), order=1, origin=spec.E_birth, origin_other=0.0)
    return continuation(spec.problem, alg, ContinuationOptions(**opts), [m0])


def test_natural_honours_the_stopping_rules():
    spec = family_spec("IS^l_2")
    En = spec.E_birth
    vals = [En + (4 - En) * k / 8 for k in range(1, 9)]
    full = _natural(vals)
    assert full.stop == "values" and len(full.members) == 9
    b = _natural(vals, max_steps=3)
    assert b.stop == "steps" and len(b.members) == 4
    b = _natural(vals, E_range=(0, vals[4]))
    assert b.stop == "E range" and len(b.members) == 7  # the first one outside
    assert "E_range" in b.reason and "7 members" in b.reason
    b = _natural(vals, t_max=float(full.period[3]) * (1 + 1e-12))
    assert b.stop == "period" and len(b.members) == 5 and "t_max" in b.reason


def test_branch_says_why_it_stopped():
    b = _natural([])
    assert b.stop == "values" and b.reason.startswith("values: ended after 1 members")
    assert issubclass(FamilyEnd, ValueError)
    assert not hasattr(importlib.import_module("rotorlib.orbits.shooting"), "FamilyEnd")
    assert math.isfinite(float(b.members[0].E))


def test_follow_says_why_it_stopped():
    from rotorlib.paper.newborn import follow

    b = follow("IS^r_1", E_range=(5.8, 6.0))
    assert b.stop == "E range" and len(b.members) == 1  # the seed only
    assert "outside E_range = (5.8, 6)" in b.reason
    assert "the first member" in b.reason  # the seed is outside the range too
    assert "dropped" in b.reason


def test_follow_members_stay_inside_the_range():
    from rotorlib.paper.newborn import follow

    b = follow("IS^r_1", E_range=(None, 4.3))
    assert b.stop == "E range" and b.E.max() <= 4.3  # it ended at 4.309
    assert all(float(p.member.E) <= 4.3 for p in b.special_points)
    out = follow("IS^r_1", E_range=(None, 4.3), clip=False)
    assert out.E.max() > 4.3 and len(out.members) == len(b.members) + 1


def test_budget_model_reproduces_its_documented_calibration():
    """The model against the CPU times its docstring records (measured once with
    ``nice -n 10``; no timing is measured here)."""
    import re

    from rotorlib.beyond.atlas import budget_seconds

    doc = " ".join(budget_seconds.__doc__.split())
    m = re.search(r"([\d.]+), ([\d.]+) and ([\d.]+) s at T = (\d+), (\d+), (\d+)", doc)
    assert m, doc
    cpu, T = [float(v) for v in m.groups()[:3]], [float(v) for v in m.groups()[3:]]
    for c, t in zip(cpu, T):
        assert abs(budget_seconds([5.45], t) / c - 1) < 0.1, (t, c)


def _private_imports(source: str) -> list[str]:
    """The private names one module of rotorlib takes from another: ``from .x import
    _y`` (or ``from rotorlib.x import _y``), and ``x._y`` of a module bound by ``from .
    import x`` or ``import rotorlib.x as x``."""
    import ast

    tree = ast.parse(source)
    found, modules = [], set()
    for node in ast.walk(tree):
        internal = isinstance(node, ast.ImportFrom) and (
            node.level > 0 or (node.module or "").split(".")[0] == "rotorlib"
        )
        if internal:
            for a in node.names:
                if a.name.startswith("_") and not a.name.startswith("__"):
                    found.append(f"{node.module}.{a.name}")
                elif not node.module:  # from . import x: x is a module
                    modules.add(a.asname or a.name)
        if isinstance(node, ast.Import):
            modules.update(
                a.asname or a.name for a in node.names if a.name.startswith("rotorlib")
            )
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id in modules
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
        ):
            found.append(f"{node.value.id}.{node.attr}")
    return found


def test_the_scan_finds_private_imports():
    assert _private_imports("from .flow import _rhs, to_section") == ["flow._rhs"]
    assert _private_imports("from rotorlib.orbits.hill import _solve_hill") == [
        "rotorlib.orbits.hill._solve_hill"
    ]
    assert _private_imports("from . import atlas\natlas._check([4.3], 7, 300)") == [
        "atlas._check"
    ]
    assert _private_imports("from .x import y\nimport argparse\nargparse._Sub") == []


def test_no_module_imports_another_modules_private_names():
    """Every name one module of rotorlib uses from another is public: documented, in
    the API reference, and kept stable."""
    from pathlib import Path

    import rotorlib

    root = Path(rotorlib.__file__).parent
    found = {
        str(f.relative_to(root)): _private_imports(f.read_text())
        for f in sorted(root.rglob("*.py"))
    }
    assert {k: v for k, v in found.items() if v} == {}


def test_family_end_lives_with_the_engine():
    assert FamilyEnd.__module__ == "rotorlib.orbits.continuation"


def test_monodromy_accepts_a_transition():
    tr = transition("PD^r_1")
    assert abs(monodromy(tr).trace) < 1e-9  # tr M = 0 at a PD transition


def test_no_module_shares_a_public_functions_name():
    """No submodule of ``rotorlib`` itself is called like a public function of the
    package: importing it would rebind ``rotorlib.<name>`` to the module. Modules of
    the layers (``rotorlib.orbits.family``, ``rotorlib.core.closed_forms``) bind
    names in their own package and cannot shadow ``rotorlib.family`` or
    ``rotorlib.orbit``."""
    import importlib.util
    import pkgutil

    import rotorlib

    modules = {m.name for m in pkgutil.iter_modules(rotorlib.__path__)}
    assert {"core", "orbits", "paper", "beyond", "api"} <= modules
    public = [n for n in dir(rotorlib) if not n.startswith("_")]
    functions = {n for n in public if callable(getattr(rotorlib, n))}
    assert {"orbit", "family", "census", "transition"} <= functions
    assert not functions & modules, functions & modules
    import rotorlib.orbits.family  # noqa: F401  (binds rotorlib.orbits.family only)

    assert callable(rotorlib.family)
    assert importlib.util.find_spec("rotorlib.orbits.floquet") is not None
