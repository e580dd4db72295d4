"""Write book/gallery.md: a thumbnail of every regenerated panel of the paper's figures.

The chapters' Markdown cells carry captions naming what they reproduce, e.g.
"Paper Fig. 3(b)", "Paper Fig. 1(a) and 1(b)", "Paper Figs. 5(a)-(h)",
"Paper Fig. 2(a, b)" or "Paper Fig. 8" (a figure without a panel = all its
panels). This script collects those mentions from every notebook listed in
_toc.yml. The figure a caption belongs to is the image output of the code cell
just before it (or, when that image already has a caption or there is none, just
after it). Those images are copied out of the stored notebooks into
book/_gallery/ (git-ignored, rewritten on every run: scripts/build_book.sh runs
this script before the build), and the page shows, for each paper figure, the
paper's caption and a thumbnail of each regenerated image with the panels it
covers, linked to the section of the chapter that draws it. Panels no chapter
claims yet are listed as missing. The page depends only on the notebooks and
_toc.yml.

Usage: python scripts/make_gallery.py [--check]
  --check  exit 1 if book/gallery.md is not up to date (writes nothing).
"""

from __future__ import annotations

import base64
import json
import re
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
OUT = BOOK / "gallery.md"
THUMBS = BOOK / "_gallery"  # git-ignored: extracted from the stored notebooks

sys.path.insert(0, str(ROOT / "scripts"))
from make_ledger import section_at, sections_of  # noqa: E402  (MyST's anchors)

# Panels of the paper's figures (Krishnaswami & Yadav, Chaos 33, 083101 (2023)):
# counted from the subfigure environments of its LaTeX source. 42 in all.
PANELS = {1: 2, 2: 2, 3: 5, 4: 2, 5: 8, 6: 8, 7: 3, 8: 4, 9: 4, 10: 4}
TITLES = {
    1: r"Equipotentials of $V$ with its minimum $G$, saddles $D$ and maxima $T$: "
    r"(a) the three pendula on the $E = 4$ homoclinic orbits, (b) the isosceles "
    r"breathers on the $E = 4.5$ heteroclinic orbits.",
    2: r"$\operatorname{tr} M$ against the period $\tau$ for (a) librational and (b) "
    r"rotational pendula, asymptotically periodic as $E \to 4^\mp$.",
    3: r"Self-similarity of $\operatorname{tr} M(E)$ of pendula and their newborn "
    r"families under magnification by $\delta^\ell$ ((b), (c)) and $\delta^r$ ((e)).",
    4: r"$\operatorname{tr} M$ against $\tau$ for (a) librational and (b) rotational "
    r"pendula together with the families born at their bifurcations.",
    5: r"Shapes in the $\alpha_1$–$\alpha_2$ plane of the orbits born at the "
    r"bifurcations of librational pendula, (a) $\mathrm{PD}^\ell_1$ to (h) "
    r"$\mathrm{IS}^\ell_6$.",
    6: r"Shapes of the orbits born at the bifurcations of rotational pendula, (a) "
    r"$\mathrm{PD}^r_1$ to (h) $\mathrm{IS}^r_4$.",
    7: r"Fans: the $\operatorname{tr} M(E)$ graphs of the newborn families meet near "
    r"$E = 4$ ((a) $\mathrm{IS}^\ell$, (b) $\mathrm{PD}^\ell$, (c) $\mathrm{IS}^r$, "
    r"extrapolated backward).",
    8: r"Newborn orbits at $E = 4$ as Lamé functions: (a) $\alpha_1(t)$ and (b) "
    r"$\alpha_2(t)$ of $\mathrm{IS}^\ell_6$, (c), (d) the same for "
    r"$\mathrm{PD}^\ell_3$.",
    9: r"Self-similar shapes at $E = 4$ of the orbits born at bifurcations of "
    r"librational pendula, related by the scaling constants $\alpha^\ell$, "
    r"$\beta^\ell$.",
    10: r"Breathers: (a) librational breathers are unstable, (b) rotational breathers "
    r"turn stable at $E \approx 8.97$, (c) period and $\operatorname{tr} M$ of the "
    r"daughter family, (d) daughter orbits.",
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


_IMAGE_TYPES = (("image/svg+xml", "svg"), ("image/png", "png"))


def _image_of(cell: dict):
    """``(mime, extension, bytes, alt text)`` of a code cell's first image output."""
    if cell.get("cell_type") != "code":
        return None
    for out in cell.get("outputs", []):
        data = out.get("data") or {}
        for mime, ext in _IMAGE_TYPES:
            if mime in data:
                raw = data[mime]
                raw = "".join(raw) if isinstance(raw, list) else raw
                blob = raw.encode() if ext == "svg" else base64.b64decode(raw)
                alt = "".join(data.get("text/plain", "")).strip()
                return mime, ext, blob, alt
    return None


def collect():
    """Panels and the images that regenerate them.

    Returns ``(claims, titles, figures)``: ``claims`` maps (figure, panel) to the
    chapter docnames; ``titles`` maps docname -> chapter title; ``figures`` lists, in
    book order, ``dict(doc, anchor, panels, name, blob)`` for each captioned image.
    """
    claims: dict[tuple[int, str], list[str]] = {}
    titles: dict[str, str] = {}
    figures: list[dict] = []
    for doc in toc_files():
        path = ROOT / (doc + ".ipynb")
        if not path.is_file():
            continue
        nb = json.loads(path.read_text(encoding="utf-8"))
        cells = nb.get("cells", [])
        titles[doc] = notebook_title(cells, path.stem)
        sections = sections_of(nb)
        taken: set[int] = set()
        for i, cell in enumerate(cells):
            if cell.get("cell_type") != "markdown":
                continue
            src = "".join(cell.get("source", ""))
            panels: set[tuple[int, str]] = set()
            for m in MENTION.finditer(src):
                panels |= panels_in(m.group(1))
            for key in sorted(panels):
                claims.setdefault(key, [])
                if doc not in claims[key]:
                    claims[key].append(doc)
            if not panels:
                continue
            for j in (i - 1, i + 1):
                if 0 <= j < len(cells) and j not in taken and _image_of(cells[j]):
                    taken.add(j)
                    mime, ext, blob, _ = _image_of(cells[j])
                    line = src.count("\n", 0, MENTION.search(src).start())
                    figures.append(
                        dict(
                            doc=doc,
                            anchor=section_at(sections, i, line),
                            panels=panels,
                            name=f"{path.stem}-cell{j}.{ext}",
                            blob=blob,
                        )
                    )
                    break
    return claims, titles, figures


def _panel_list(fig: int, letters: list[str]) -> str:
    """``5(a)–(h)``, ``2(a), (b)``, ``10(d)``."""
    idx = sorted(LETTERS.index(x) for x in letters)
    if len(idx) > 2 and idx == list(range(idx[0], idx[-1] + 1)):
        return f"{fig}({LETTERS[idx[0]]})–({LETTERS[idx[-1]]})"
    return f"{fig}" + ", ".join(f"({LETTERS[i]})" for i in idx)


def render() -> str:
    claims, titles, figures = collect()
    total = sum(PANELS.values())
    done = sum(
        1 for f, n in PANELS.items() for i in range(n) if (f, LETTERS[i]) in claims
    )
    shown = {p for f in figures for p in f["panels"]}

    def link(doc: str, anchor: str = "") -> str:
        rel = (
            Path(doc).relative_to("book")
            if doc.startswith("book/")
            else Path("/" + doc)
        )
        return f"[{titles[doc]}]({rel}.ipynb{'#' + anchor if anchor else ''})"

    lines = [
        "# Gallery: paper figures",
        "",
        "<!-- Generated by scripts/make_gallery.py from the chapters' captions",
        '     ("Paper Fig. N(x)"); do not edit by hand. -->',
        "",
        "Each figure of the paper {cite}`krishnaswami2023cascade`, its caption in "
        "short, and a thumbnail of every figure of this book that regenerates its "
        "panels, linked to the section of the chapter that draws it (found from the "
        "chapters' captions, which name the paper figure and panel they reproduce).",
        f"**{done} of the paper's {total} panels** are reproduced in this book, "
        f"{len(shown)} of them with a thumbnail here.",
        "",
    ]
    for fig, n in PANELS.items():
        lines += [f"## Figure {fig}", "", TITLES[fig], ""]
        rows = [f for f in figures if any(p[0] == fig for p in f["panels"])]
        missing = [LETTERS[i] for i in range(n) if (fig, LETTERS[i]) not in claims]
        if rows:
            lines += [
                "```{list-table}",
                ":header-rows: 1",
                ":class: gallery-table",
                ":widths: 45 55",
                "",
                "* - regenerated",
                "  - paper panels, chapter",
            ]
            for f in rows:
                letters = [p[1] for p in sorted(f["panels"]) if p[0] == fig]
                panels = _panel_list(fig, letters)
                alt = f"Paper Fig. {panels} regenerated"
                lines += [
                    f"* - ![{alt}](_gallery/{f['name']})",
                    f"  - **Fig. {panels}**: {link(f['doc'], f['anchor'])}",
                ]
            lines += ["```", ""]
        unthumbed = [
            LETTERS[i]
            for i in range(n)
            if (fig, LETTERS[i]) in claims and (fig, LETTERS[i]) not in shown
        ]
        if unthumbed:
            where = {d for i in unthumbed for d in claims[(fig, i)]}
            lines += [
                f"Panels {_panel_list(fig, unthumbed)} (no figure output next to the "
                "caption): " + ", ".join(link(d) for d in sorted(where)) + ".",
                "",
            ]
        if missing:
            lines += [f"Not yet reproduced: {_panel_list(fig, missing)}.", ""]
    return "\n".join(lines)


def write_thumbnails() -> int:
    """Copy the captioned images out of the stored notebooks into book/_gallery/."""
    _, _, figures = collect()
    THUMBS.mkdir(exist_ok=True)
    names = {f["name"] for f in figures}
    for old in THUMBS.iterdir():
        if old.name not in names:
            old.unlink()
    for f in figures:
        target = THUMBS / f["name"]
        if not target.is_file() or target.read_bytes() != f["blob"]:
            target.write_bytes(f["blob"])
    return len(figures)


def main(argv: list[str]) -> int:
    text = render()
    if "--check" in argv:
        ok = OUT.is_file() and OUT.read_text(encoding="utf-8") == text
        print(
            "make_gallery: book/gallery.md is "
            + ("up to date" if ok else "OUT OF DATE")
        )
        return 0 if ok else 1
    n = write_thumbnails()
    if not OUT.is_file() or OUT.read_text(encoding="utf-8") != text:
        OUT.write_text(text, encoding="utf-8")
        print(f"make_gallery: wrote book/gallery.md ({n} thumbnails in book/_gallery)")
    else:
        print(
            f"make_gallery: book/gallery.md unchanged ({n} thumbnails in book/_gallery)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
