"""The size of rotorlib: AST statements and lines per module, against the budget.

The budget (``BUDGET``) covers the library without ``plotting/`` and without the
modules of new science (names containing ``choreo``, ``quantum`` or ``catalogue``,
counted apart). A
statement is every ``ast.stmt`` node, nested ones included, except docstrings. No module
may exceed ``MAX_LINES`` lines.

    python scripts/statement_budget.py        # a table; exit status 1 over budget
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

BUDGET = 4500
MAX_LINES = 700
ROOT = Path(__file__).resolve().parents[1] / "rotorlib"


def statements(path: Path) -> int:
    """AST statements of one file, docstrings excluded."""
    n = 0
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.stmt) and not (
            isinstance(node, ast.Expr)
            and isinstance(node.value, ast.Constant)
            and isinstance(node.value.value, str)
        ):
            n += 1
    return n


def modules() -> list[tuple[str, str, int, int]]:
    """``(module, part, statements, lines)``; part is ``core``, ``new science`` or
    ``plotting``."""
    rows = []
    for p in sorted(ROOT.rglob("*.py")):
        rel = p.relative_to(ROOT.parent).as_posix()
        part = (
            "plotting"
            if "plotting" in p.parts
            else "new science"
            if any(w in p.name for w in ("choreo", "quantum", "catalogue"))
            else "core"
        )
        rows.append((rel, part, statements(p), len(p.read_text().splitlines())))
    return rows


def main() -> int:
    rows = modules()
    total = {
        k: sum(r[2] for r in rows if r[1] == k)
        for k in ("core", "new science", "plotting")
    }
    long = [r for r in rows if r[3] > MAX_LINES]
    for r in sorted(rows, key=lambda r: -r[2])[:12]:
        print(f"{r[0]:40s} {r[1]:12s} {r[2]:5d} statements {r[3]:5d} lines")
    print(
        f"core: {total['core']} statements (budget {BUDGET}); new science: "
        f"{total['new science']}; plotting: {total['plotting']} (not counted)"
    )
    print(f"modules over {MAX_LINES} lines: {[r[0] for r in long] or 'none'}")
    return 0 if total["core"] <= BUDGET and not long else 1


if __name__ == "__main__":
    sys.exit(main())
