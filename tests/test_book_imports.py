"""One name per module across the book: a module imported by several chapters is bound
to the same name in each, and no name stands for two modules (CONTRIBUTING, Notebooks)."""

from __future__ import annotations

import ast
import json
from collections import defaultdict
from pathlib import Path

BOOK = Path(__file__).resolve().parents[1] / "book"


def module_bindings(source: str) -> list[tuple[str, str]]:
    """``(module, name)`` for every module bound to a name by an import in ``source``
    (``import a.b as x``, ``from a import b as x`` when ``a.b`` is a module of
    rotorlib or the repository); function imports are not module bindings."""
    import importlib.util

    def is_module(name: str) -> bool:
        try:
            return importlib.util.find_spec(name) is not None
        except (ImportError, ValueError):
            return False

    lines = [
        "pass" if line.lstrip().startswith(("%", "!")) else line
        for line in source.split("\n")
    ]
    out = []
    for node in ast.walk(ast.parse("\n".join(lines))):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("rotorlib"):
                    out.append((a.name, a.asname or a.name.split(".")[0]))
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if not node.module.startswith(("rotorlib", "benchmarks")):
                continue
            for a in node.names:
                full = f"{node.module}.{a.name}"
                if is_module(full):
                    out.append((full, a.asname or a.name))
    return out


def book_bindings() -> dict[str, dict[str, set[str]]]:
    by_module: dict[str, dict[str, set[str]]] = defaultdict(lambda: defaultdict(set))
    for nb in sorted(BOOK.glob("*.ipynb")):
        cells = json.loads(nb.read_text(encoding="utf-8"))["cells"]
        for cell in cells:
            if cell["cell_type"] == "code":
                for module, name in module_bindings("".join(cell["source"])):
                    by_module[module][name].add(nb.stem)
    return by_module


def test_one_name_per_module():
    clashes = {m: dict(v) for m, v in book_bindings().items() if len(v) > 1}
    assert not clashes, f"a module under several names: {clashes}"


def test_no_name_for_two_modules():
    names: dict[str, set[str]] = defaultdict(set)
    for module, bound in book_bindings().items():
        for name in bound:
            names[name].add(module)
    clashes = {n: sorted(m) for n, m in names.items() if len(m) > 1}
    assert not clashes, f"a name for several modules: {clashes}"


def test_the_check_sees_a_clash():
    """The scan finds a module bound to two names (the check can fail)."""
    a = module_bindings("from rotorlib.paper import chaos as ch")
    b = module_bindings(
        "from rotorlib.beyond import choreo as ch\nimport rotorlib as rl"
    )
    assert a == [("rotorlib.paper.chaos", "ch")]
    assert b == [("rotorlib.beyond.choreo", "ch"), ("rotorlib", "rl")]
    assert module_bindings("from rotorlib.orbits.floquet import monodromy") == []
