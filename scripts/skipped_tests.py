"""Which tests of one file a pytest run skipped, from its JUnit XML report.

    python scripts/skipped_tests.py _build/pytest.xml tests/test_book_html.py

Prints ``N of M tests skipped (reason)`` when the file's tests were skipped (the
reasons, one each, as pytest gave them), and nothing when none was or the file did
not run. Skips that are part of the test's design (``EXPECTED``: a redirect page of
the book has no content to check) do not count. ``scripts/run_tests.sh`` uses it to name the browser test when it did not run.
"""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from pathlib import Path

#: Skip reasons that do not mean the test did not run.
EXPECTED = ("a redirect page",)


def skipped(report: Path, test_file: str) -> str:
    """``N of M tests skipped (reasons)`` for ``test_file`` in ``report``, or ``""``."""
    module = test_file.removesuffix(".py").replace("/", ".")
    cases = [
        c
        for c in ET.parse(report).getroot().iter("testcase")
        if c.get("classname", "") == module
        or c.get("classname", "").startswith(module + ".")
    ]
    reasons = [
        s.get("message", "")
        for c in cases
        for s in c.findall("skipped")
        if not any(e in s.get("message", "") for e in EXPECTED)
    ]
    if not reasons:
        return ""
    why = "; ".join(dict.fromkeys(r.removeprefix("Skipped: ") for r in reasons))
    return f"{len(reasons)} of {len(cases)} tests skipped ({why})"


if __name__ == "__main__":
    report, test_file = Path(sys.argv[1]), sys.argv[2]
    print(skipped(report, test_file) if report.is_file() else "")
