"""Write book/gallery.md: which chapter reproduces each panel of the paper's figures.

The chapters' Markdown cells carry captions naming what they reproduce, e.g.
"Paper Fig. 3(b)", "Paper Fig. 1(a) and 1(b)", "Paper Figs. 5(a)-(h)",
"Paper Fig. 2(a, b)" or "Paper Fig. 8" (a figure without a panel = all its
panels). This script collects those mentions from every notebook listed in
_toc.yml and writes a table paper figure -> panel -> chapter(s); panels no
chapter claims yet are listed as missing. It is idempotent (the output depends
only on the notebooks and _toc.yml) and is run by scripts/build_book.sh before
the build.

Usage: python scripts/make_gallery.py [--check]
  --check  exit 1 if book/gallery.md is not up to date (writes nothing).
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
OUT = BOOK / "gallery.md"

# Panels of the paper's figures (Krishnaswami & Yadav, Chaos 33, 083101 (2023)):
# counted from the subfigure environments of its LaTeX source. 42 in all.
PANELS = {1: 2, 2: 2, 3: 5, 4: 2, 5: 8, 6: 8, 7: 3, 8: 4, 9: 4, 10: 4}
TITLES = {
    1: "Equipotentials; pendula and isosceles breathers",
    2: "tr M vs period for librational and rotational pendula",
    3: "Self-similarity of tr M(E) under magnification",
    4: "tr M vs period including the newly born families",
    5: "Shapes of orbits born from librational pendula",
    6: "Shapes of orbits born from rotational pendula",
    7: "Fans of the newborn families near E = 4",
    8: "Newborn orbits as Lamé functions",
    9: "Self-similarity of newborn orbit shapes",
    10: "Breathers: stability and bifurcations",
}

LETTERS = "abcdefghijklmnopqrstuvwxyz"
# "Paper Fig." / "Paper Figs." / "Paper Figure(s)", then the reference list up to
# a colon, full stop, semicolon or line end.
MENTION = re.compile(r"Paper\s+Fig(?:ure)?s?\.?\s*([^:;.\n]*)")
TOKEN = re.compile(
    r"(?P<fig>\d+)?\s*\(\s*(?P<a>[a-z])\s*\)\s*(?:[-\u2013]|to)\s*\(\s*(?P<b>[a-z])\s*\)"  # 5(a)-(h)
    r"|(?P<fig2>\d+)?\s*\(\s*(?P<list>[a-z](?:\s*(?:,|[-\u2013]|and)\s*[a-z])*)\s*\)"  # 5(a-h), 2(a, b)
    r"|(?P<fig3>\d+)(?!\d|\s*\(\s*[a-z]\s*[-\u2013,)]|\s*\(\s*[a-z]\s+(?:and|to)\b)"  # bare 8
)


SEPARATOR = re.compile(r"\s*(?:,|&|and)?\s*")


def toc_files() -> list[str]:
    """Document paths (no suffix) listed in _toc.yml, in order."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    files: list[str] = []

    def walk(node):
        if isinstance(node, dict):
            if "file" in node:
                files.append(str(node["file"]))
            if "root" in node:
                files.append(str(node["root"]))
            for key in ("chapters", "sections", "parts"):
                for child in node.get(key, []) or []:
                    walk(child)
        elif isinstance(node, list):
            for child in node:
                walk(child)

    walk(toc)
    return files


def panels_in(text: str) -> set[tuple[int, str]]:
    """(figure, panel) pairs named by one mention's reference list."""
    found: set[tuple[int, str]] = set()
    fig = None
    pos = SEPARATOR.match(text, 0).end()
    while True:  # consecutive references only: stop at the first other word
        m = TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            break
        pos = SEPARATOR.match(text, m.end()).end()
        if m.group("a"):
            fig = int(m.group("fig")) if m.group("fig") else fig
            if fig in PANELS:
                lo, hi = LETTERS.index(m.group("a")), LETTERS.index(m.group("b"))
                found.update((fig, LETTERS[i]) for i in range(lo, hi + 1))
        elif m.group("list"):
            fig = int(m.group("fig2")) if m.group("fig2") else fig
            if fig in PANELS:
                parts = re.split(r"\s*(,|and)\s*", m.group("list"))
                for part in parts:
                    if part in (",", "and", ""):
                        continue
                    r = re.fullmatch(r"([a-z])\s*[-\u2013]\s*([a-z])", part)
                    if r:
                        lo, hi = LETTERS.index(r.group(1)), LETTERS.index(r.group(2))
                        found.update((fig, LETTERS[i]) for i in range(lo, hi + 1))
                    else:
                        found.add((fig, part))
        elif m.group("fig3"):
            fig = int(m.group("fig3"))
            if fig in PANELS:
                found.update((fig, LETTERS[i]) for i in range(PANELS[fig]))
    return {(f, p) for f, p in found if f in PANELS and LETTERS.index(p) < PANELS[f]}


def notebook_title(cells: list[dict], fallback: str) -> str:
    for cell in cells:
        if cell.get("cell_type") == "markdown":
            for line in "".join(cell.get("source", "")).splitlines():
                if line.startswith("# "):
                    return line[2:].strip()
    return fallback


def collect() -> tuple[dict[tuple[int, str], list[str]], dict[str, str]]:
    """Map (figure, panel) -> list of chapter docnames; and docname -> title."""
    claims: dict[tuple[int, str], list[str]] = {}
    titles: dict[str, str] = {}
    for doc in toc_files():
        path = ROOT / (doc + ".ipynb")
        if not path.is_file():
            continue
        cells = json.loads(path.read_text(encoding="utf-8")).get("cells", [])
        titles[doc] = notebook_title(cells, path.stem)
        for cell in cells:
            if cell.get("cell_type") != "markdown":
                continue
            src = "".join(cell.get("source", ""))
            for m in MENTION.finditer(src):
                for key in sorted(panels_in(m.group(1))):
                    claims.setdefault(key, [])
                    if doc not in claims[key]:
                        claims[key].append(doc)
    return claims, titles


def render() -> str:
    claims, titles = collect()
    total = sum(PANELS.values())
    done = sum(
        1 for f, n in PANELS.items() for i in range(n) if (f, LETTERS[i]) in claims
    )

    def link(doc: str) -> str:
        rel = (
            Path(doc).relative_to("book")
            if doc.startswith("book/")
            else Path("/" + doc)
        )
        return f"[{titles[doc]}]({rel}.ipynb)"

    lines = [
        "# Gallery: paper figures",
        "",
        "<!-- Generated by scripts/make_gallery.py from the chapters' captions",
        '     ("Paper Fig. N(x)"); do not edit by hand. -->',
        "",
        "Each panel of the figures of the paper {cite}`krishnaswami2023cascade` and the",
        "chapter whose figure regenerates it (found from the chapters' captions, which",
        "name the paper figure and panel they reproduce).",
        f"**{done} of the paper's {total} panels** are reproduced in this book.",
        "",
    ]
    for fig, n in PANELS.items():
        lines += [
            f"## Figure {fig}: {TITLES[fig]}",
            "",
            "| panel | reproduced in |",
            "| --- | --- |",
        ]
        for i in range(n):
            docs = claims.get((fig, LETTERS[i]), [])
            where = ", ".join(link(d) for d in docs) if docs else "not yet reproduced"
            lines.append(f"| {fig}({LETTERS[i]}) | {where} |")
        lines.append("")
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    text = render()
    if "--check" in argv:
        ok = OUT.is_file() and OUT.read_text(encoding="utf-8") == text
        print(
            "make_gallery: book/gallery.md is "
            + ("up to date" if ok else "OUT OF DATE")
        )
        return 0 if ok else 1
    if not OUT.is_file() or OUT.read_text(encoding="utf-8") != text:
        OUT.write_text(text, encoding="utf-8")
        print("make_gallery: wrote book/gallery.md")
    else:
        print("make_gallery: book/gallery.md unchanged")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
