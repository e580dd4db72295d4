"""The book's sources are complete and clean.

* every file named in _toc.yml exists, and every notebook in book/ is in the toc;
* every notebook is stored executed (outputs present, every code cell run) with
  a kernelspec, and its stored outputs contain no error, no traceback, no tqdm
  progress bar and no memory address (``0x7f...``: output that changes per run);
* book/api.md documents every module of rotorlib (scripts/make_api.py);
* book/gallery.md is what scripts/make_gallery.py generates from the chapters.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
NOTEBOOKS = sorted(
    p for p in BOOK.rglob("*.ipynb") if ".ipynb_checkpoints" not in p.parts
)

TQDM = re.compile(r"\d+%\|[^|\n]*\||\d+/\d+ \[\d+:\d+<|it/s\]|s/it\]")
# A float64 printed with all its digits: 16 or 17 significant digits, the last of them
# the machine's round-off (the output would not reproduce on another CPU). Numbers
# from an extended-precision tier carry 20 or more digits and are not matched.
DECIMAL = re.compile(r"(?<![\w.])[+-]?\d+\.\d+(?:[eE][+-]?\d+)?(?![\w.])")


def float_reprs(text: str) -> list[str]:
    """The numbers in ``text`` written with 16 or 17 significant digits."""
    out = []
    for m in DECIMAL.finditer(text):
        mantissa = re.split("[eE]", m.group(0).lstrip("+-"))[0]
        digits = mantissa.replace(".", "").lstrip("0")
        if len(digits) in (16, 17):
            out.append(m.group(0))
    return out


ADDRESS = re.compile(r"\bat 0x[0-9a-fA-F]{6,}|0x7f[0-9a-fA-F]{6,}")


def toc_entries() -> list[str]:
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    files: list[str] = []

    def walk(node):
        if isinstance(node, dict):
            for key in ("root", "file"):
                if key in node:
                    files.append(str(node[key]))
            for key in ("chapters", "sections", "parts"):
                for child in node.get(key) or []:
                    walk(child)
        elif isinstance(node, list):
            for child in node:
                walk(child)

    walk(toc)
    return files


def resolve(entry: str) -> Path | None:
    base = ROOT / entry
    for suffix in ("", ".md", ".ipynb"):
        candidate = base.with_name(base.name + suffix)
        if candidate.is_file():
            return candidate
    return None


def test_toc_is_valid_and_nonempty():
    entries = toc_entries()
    assert entries, "_toc.yml lists no files"
    assert len(entries) == len(set(entries)), f"duplicate toc entries: {entries}"


@pytest.mark.parametrize("entry", toc_entries())
def test_toc_file_exists(entry):
    assert resolve(entry) is not None, (
        f"_toc.yml names {entry!r} but neither .md nor .ipynb exists"
    )


@pytest.mark.parametrize("nb", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_in_toc(nb):
    listed = {resolve(e) for e in toc_entries()}
    assert nb in listed, (
        f"{nb.relative_to(ROOT)} is not in _toc.yml (only_build_toc_files: it would not be built)"
    )


def _outputs_text(output: dict) -> str:
    parts = []
    if "text" in output:
        parts.append(
            "".join(output["text"])
            if isinstance(output["text"], list)
            else output["text"]
        )
    for mime, value in (output.get("data") or {}).items():
        if mime.startswith("text/") or mime.endswith("json"):
            parts.append("".join(value) if isinstance(value, list) else str(value))
    return "\n".join(parts)


@pytest.mark.parametrize("nb", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_stored_clean(nb):
    data = json.loads(nb.read_text(encoding="utf-8"))
    kernelspec = data.get("metadata", {}).get("kernelspec") or {}
    assert kernelspec.get("name"), f"{nb.name}: no kernelspec in the notebook metadata"

    code = [
        c
        for c in data["cells"]
        if c["cell_type"] == "code" and "".join(c["source"]).strip()
    ]
    problems = []
    unexecuted = [i for i, c in enumerate(code) if c.get("execution_count") is None]
    if unexecuted:
        problems.append(
            f"code cells {unexecuted} were never executed (store the executed notebook)"
        )
    if code and not any(c.get("outputs") for c in code):
        problems.append("no outputs stored")
    for i, cell in enumerate(code):
        for out in cell.get("outputs", []):
            text = _outputs_text(out)
            if out.get("output_type") == "error":
                problems.append(
                    f"code cell {i}: stored error output {out.get('ename')}: {out.get('evalue')}"
                )
            if "Traceback (most recent call last)" in text:
                problems.append(f"code cell {i}: stored traceback")
            if TQDM.search(text):
                problems.append(
                    f"code cell {i}: progress bar in the output: {TQDM.search(text).group(0)!r}"
                )
            if ADDRESS.search(text):
                problems.append(
                    f"code cell {i}: memory address in the output: {ADDRESS.search(text).group(0)!r}"
                )
            src = "".join(cell["source"])
            if "NBVAL_IGNORE_OUTPUT" not in src.split("\n", 1)[0]:
                reprs = float_reprs(text)
                if reprs:
                    problems.append(
                        f"code cell {i}: float64 repr(s) in a compared output {reprs[:3]}: "
                        "print the verified digits (rotorlib.core.compare.sig/rounded) or a bound"
                    )
    assert not problems, f"{nb.name}:\n  " + "\n  ".join(problems)


@pytest.mark.parametrize("script", ["make_api.py", "make_gallery.py", "make_ledger.py"])
def test_generated_page_up_to_date(script):
    """book/api.md, gallery.md and ledger.md are what their scripts generate from the
    package and the chapters (scripts/build_book.sh runs them)."""
    proc = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / script), "--check"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert proc.returncode == 0, (
        proc.stdout
        + proc.stderr
        + f"\nrun: .venv/bin/python scripts/{script} (build_book.sh does it)"
    )


def test_ledger_counts_every_chapter_claim():
    """The ledger lists at least 90 claims, each in one row (a claim the paper makes twice
    is merged into one row) with a category and a link to a chapter that is in the toc."""
    from rotorlib.core.compare import CATEGORIES, STATUSES

    sys.path.insert(0, str(ROOT / "scripts"))
    try:
        import make_ledger as L
    finally:
        sys.path.pop(0)
    rows = [(p, "", c) for p in L.toc_notebooks() for c in L.claims_of(p)[1]]
    assert len(rows) >= 90
    assert all(c["status"] in STATUSES and c["section"] for _, _, c in rows)
    assert all(L.category_of(c) in CATEGORIES for _, _, c in rows)
    text = (ROOT / "book" / "ledger.md").read_text()
    links = re.findall(r"\]\(([^)#]+\.ipynb)(?:#[^)]*)?\)", text)
    toc = {p.name for p in L.toc_notebooks()}
    assert links and set(links) <= toc, set(links) - toc
    claim_rows = [
        line
        for line in text.splitlines()
        if line.startswith("| ") and re.search(r"\.ipynb(#[^)]*)?\)", line)
    ]
    assert len(claim_rows) == len(L.merge(rows))


def test_gallery_parser_reads_captions():
    """The caption parser itself, on the forms the chapters use."""
    sys.path.insert(0, str(ROOT / "scripts"))
    try:
        import make_gallery as g
    finally:
        sys.path.pop(0)
    assert g.panels_in("1(a) and 1(b)") == {(1, "a"), (1, "b")}
    assert g.panels_in("5(a)-(d)") == {(5, c) for c in "abcd"}
    assert g.panels_in("2(a, b)") == {(2, "a"), (2, "b")}
    assert g.panels_in("3(b), (c) and 4(a)") == {(3, "b"), (3, "c"), (4, "a")}
    assert g.panels_in("7") == {(7, c) for c in "abc"}
    assert g.panels_in("3 (b)") == {(3, "b")}
    assert g.panels_in("5 (all eight panels, (a) PD") == {(5, c) for c in "abcdefgh"}
    assert g.panels_in("10(e)") == set()  # Fig. 10 has 4 panels
    assert g.panels_in("2(a) at E = 4") == {(2, "a")}  # stops at prose
    assert sum(g.PANELS.values()) == 42
