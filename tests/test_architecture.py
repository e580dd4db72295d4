"""The house plan, checked from the source: the import graph of rotorlib has no cycle,
and no module imports one of a higher layer.

The graph is built from the AST of every module, so that every import counts: at module
level, deferred into a function, under ``if TYPE_CHECKING:``, relative (``from ..core
import x``) or absolute (``import rotorlib.core.x``). An edge ``a -> b`` means that ``a``
names ``b`` in an import; ``from .pkg import name`` is an edge to ``pkg.name`` when that
is a module, else to ``pkg``. The implicit import of a module's parent packages is not an
edge (the package ``__init__`` files of the layers hold only a docstring).

Layers, low to high: ``core`` < ``orbits`` < ``paper`` < ``beyond`` < the front door
(``api``, ``registry``, ``cli``, ``commands``, the package itself); ``plotting`` may
import any numeric module (the four layers below the front door), and no numeric module
imports ``plotting``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import rotorlib

ROOT = Path(rotorlib.__file__).resolve().parent

#: Rank of each layer (the first component below ``rotorlib``); a module may import only
#: modules of its own rank or lower.
LAYERS = {"core": 0, "orbits": 1, "paper": 2, "beyond": 3}
FRONT_DOOR = 4  # api, registry, cli, commands, __init__, __main__
NUMERIC = set(LAYERS)


def module_name(path: Path, root: Path) -> str:
    """``rotorlib.orbits.floquet`` for ``<root>/orbits/floquet.py``; a package's
    ``__init__.py`` is the package."""
    parts = [root.name, *path.relative_to(root).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph(root: Path) -> dict[str, set[str]]:
    """``{module: modules it imports}`` over the package at ``root``, every import
    statement of the AST counted (deferred ones included), only edges inside it."""
    files = {module_name(p, root): p for p in sorted(root.rglob("*.py"))}
    graph: dict[str, set[str]] = {}
    for mod, path in files.items():
        is_pkg = path.name == "__init__.py"
        pkg = mod.split(".") if is_pkg else mod.split(".")[:-1]
        targets: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names)
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    up = pkg[: len(pkg) - node.level + 1]
                    base = ".".join(up + ([node.module] if node.module else []))
                else:
                    base = node.module or ""
                for a in node.names:
                    sub = f"{base}.{a.name}"
                    targets.add(sub if sub in files else base)
        graph[mod] = {t for t in targets if t in files and t != mod}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan), each
    sorted: every import cycle lies in one of them."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def layer(mod: str) -> tuple[str, int]:
    """``(part, rank)`` of a module: its layer folder and that layer's rank."""
    parts = mod.split(".")
    part = parts[1] if len(parts) > 1 else "__init__"
    if part == "plotting":
        return part, FRONT_DOOR
    return part, LAYERS.get(part, FRONT_DOOR)


def layer_violations(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Edges ``(a, b)`` that climb: ``b`` in a higher layer than ``a``, or a numeric
    module importing ``plotting``."""
    bad = []
    for a, targets in graph.items():
        pa, ra = layer(a)
        for b in targets:
            pb, rb = layer(b)
            if rb > ra or (pa in NUMERIC and pb == "plotting"):
                bad.append((a, b))
    return sorted(bad)


def test_rotorlib_has_no_import_cycle():
    graph = import_graph(ROOT)
    assert len(graph) > 40  # every module was read
    assert cycles(graph) == []


def test_no_layer_imports_a_higher_one():
    assert layer_violations(import_graph(ROOT)) == []


def test_no_module_level_getattr():
    """No module re-exports names lazily through a module-level ``__getattr__``."""
    found = [
        str(p.relative_to(ROOT))
        for p in sorted(ROOT.rglob("*.py"))
        for node in ast.parse(p.read_text()).body
        if isinstance(node, ast.FunctionDef) and node.name == "__getattr__"
    ]
    assert found == []


def _package(tmp_path: Path, files: dict[str, str]) -> Path:
    root = tmp_path / "rotorlib"
    for name, text in files.items():
        p = root / name
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    return root


def test_a_planted_cycle_is_found(tmp_path):
    """Two tiny modules importing each other, one import deferred into a function and
    relative, the other absolute: the check reports the cycle (and the climb)."""
    root = _package(
        tmp_path,
        {
            "__init__.py": "",
            "core/__init__.py": "",
            "core/a.py": "def f():\n    from ..orbits import b\n    return b\n",
            "orbits/__init__.py": "",
            "orbits/b.py": "import rotorlib.core.a\n",
            "orbits/c.py": "from .b import something\n",
        },
    )
    graph = import_graph(root)
    assert graph["rotorlib.core.a"] == {"rotorlib.orbits.b"}
    assert graph["rotorlib.orbits.c"] == {"rotorlib.orbits.b"}
    assert cycles(graph) == [["rotorlib.core.a", "rotorlib.orbits.b"]]
    assert layer_violations(graph) == [("rotorlib.core.a", "rotorlib.orbits.b")]
    with pytest.raises(AssertionError):
        assert cycles(graph) == []


def test_a_longer_cycle_and_plotting_are_found():
    graph = {
        "rotorlib.beyond.x": {"rotorlib.beyond.y"},
        "rotorlib.beyond.y": {"rotorlib.beyond.z"},
        "rotorlib.beyond.z": {"rotorlib.beyond.x", "rotorlib.plotting.p"},
        "rotorlib.plotting.p": {"rotorlib.core.q"},
        "rotorlib.core.q": set(),
    }
    assert cycles(graph) == [
        ["rotorlib.beyond.x", "rotorlib.beyond.y", "rotorlib.beyond.z"]
    ]
    assert layer_violations(graph) == [("rotorlib.beyond.z", "rotorlib.plotting.p")]
