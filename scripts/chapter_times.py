"""Print each chapter's execution time from nbval's JUnit XML report.

scripts/run_tests.sh runs nbval with ``--junitxml``; every cell is one test case, so a
notebook's time is the sum of its cells' times (kernel start-up excluded). Usage:
``python scripts/chapter_times.py _build/nbval.xml [more reports]``.
"""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from collections import defaultdict
from pathlib import Path


def chapter_times(report: Path) -> dict[str, float]:
    """Seconds per notebook (file stem) in one JUnit XML report."""
    times: dict[str, float] = defaultdict(float)
    for case in ET.parse(report).iter("testcase"):
        # classname "book.03_transitions.ipynb" (nbval: one test case per cell)
        name = case.get("classname") or ""
        stem = name.removesuffix(".ipynb").rsplit(".", 1)[-1]
        times[stem] += float(case.get("time") or 0.0)
    return dict(times)


def main(paths: list[str]) -> int:
    for p in paths:
        path = Path(p)
        if not path.is_file():
            print(f"chapter_times: no report {p}")
            continue
        times = chapter_times(path)
        print(f"chapter_times: {path.name}")
        for stem in sorted(times):
            print(f"  {stem:<28} {times[stem]:7.1f} s")
        print(f"  {'total':<28} {sum(times.values()):7.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
