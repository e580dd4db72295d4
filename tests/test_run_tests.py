"""scripts/run_tests.sh says what it did not run (the browser test, unselected parts).

The browser test (tests/test_book_html.py) skips itself without chromium or the built
book; scripts/skipped_tests.py finds those skips in pytest's JUnit report, and the
script then ends with a NOT RUN line instead of "all parts passed".
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))

from skipped_tests import skipped  # noqa: E402

REPORT = """<?xml version="1.0" encoding="utf-8"?><testsuites><testsuite name="pytest">
<testcase classname="tests.test_book_html" name="test_page[a]">{skip}</testcase>
<testcase classname="tests.test_book_html" name="test_page[b]">{skip}</testcase>
<testcase classname="tests.test_book_html" name="test_pages_listed" />
<testcase classname="tests.test_toc" name="test_toc"><skipped message="other" /></testcase>
</testsuite></testsuites>"""
SKIP = '<skipped type="pytest.skip" message="chromium not found at /x" />'


def test_skips_of_one_file_are_counted_with_their_reason(tmp_path):
    report = tmp_path / "pytest.xml"
    report.write_text(REPORT.format(skip=SKIP))
    assert skipped(report, "tests/test_book_html.py") == (
        "2 of 3 tests skipped (chromium not found at /x)"
    )
    report.write_text(REPORT.format(skip=""))
    assert skipped(report, "tests/test_book_html.py") == ""
    assert skipped(report, "tests/test_other.py") == ""


def test_script_prints_all_parts_passed_only_when_nothing_was_left_out(tmp_path):
    """With RUN_TESTS_PARTS empty nothing runs: the script must not claim a pass."""
    text = (ROOT / "scripts" / "run_tests.sh").read_text()
    assert "CHROMIUM" in text and "skipped_tests.py" in text
    # a copy without its first step (setup_env.sh), in tmp_path/scripts/ (the script
    # works in the directory above its own)
    (tmp_path / "scripts").mkdir()
    script = tmp_path / "scripts" / "run_tests.sh"
    script.write_text(text.replace("\nbash scripts/setup_env.sh\n", "\n", 1))
    res = subprocess.run(
        ["bash", str(script)],
        env={"PATH": "/usr/bin:/bin", "RUN_TESTS_PARTS": " ", "HOME": str(tmp_path)},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert res.returncode == 0, res.stderr
    last = res.stdout.strip().splitlines()[-1]
    assert "all parts passed" not in res.stdout
    assert "NOT RUN" in last and "nbval" in last and "lint" in last, last
