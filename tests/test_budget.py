"""The library's size: rotorlib without plotting/ and the modules of new science
(names containing ``choreo``, ``quantum`` or ``catalogue``) stays within its statement
budget, and no module exceeds its line limit (``scripts/statement_budget.py``)."""

import importlib.util
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "statement_budget.py"


def _budget():
    spec = importlib.util.spec_from_file_location("statement_budget", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_core_within_statement_budget():
    sb = _budget()
    core = sum(n for _, part, n, _ in sb.modules() if part == "core")
    assert core <= sb.BUDGET, f"core {core} statements > budget {sb.BUDGET}"


def test_no_module_over_the_line_limit():
    sb = _budget()
    long = [m for m, _, _, lines in sb.modules() if lines > sb.MAX_LINES]
    assert not long, long


def test_new_science_kept_apart():
    """The choreography and quantum modules are counted apart, and exist as such."""
    parts = {m: part for m, part, _, _ in _budget().modules()}
    assert parts["rotorlib/beyond/choreo_family.py"] == "new science"
    assert parts["rotorlib/beyond/quantum.py"] == "new science"
    assert parts["rotorlib/beyond/atlas.py"] == "core"


def test_new_science_by_name_wherever_it_lives():
    """A module is new science by its name (choreo, quantum, catalogue) in any folder;
    plotting by its folder; everything else is core."""
    sb = _budget()
    root = sb.ROOT
    assert sb.part(root / "beyond" / "catalogue.py") == "new science"
    assert sb.part(root / "paper" / "orbit_catalogue.py") == "new science"
    assert sb.part(root / "orbits" / "quantum_x.py") == "new science"
    assert sb.part(root / "plotting" / "choreo.py") == "plotting"
    assert sb.part(root / "beyond" / "atlas.py") == "core"
    assert sb.part(root / "api.py") == "core"
