"""The catalogue's generated gallery (scripts/catalogue_pages.py) and its figures.

* every family of the stored catalogue has its page, and every page is in _toc.yml
  under chapter 13 (and no page of a family that left the catalogue remains);
* the stored pages are what the script writes from the stored records (so a new
  build without a re-run of the script fails here);
* every link between pages and every link of the T-E diagram reaches a page;
* the figures follow the book's style; the T-E diagram's SVG carries the links.
"""

from __future__ import annotations

import functools
import importlib.util
import io
import json
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import yaml  # noqa: E402

import rotorlib.plotting as rp  # noqa: E402
from rotorlib.beyond import catalogue as cat  # noqa: E402
from rotorlib.plotting import catalogue as pcat  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PAGES = ROOT / "book" / "catalogue"
spec = importlib.util.spec_from_file_location(
    "catalogue_pages", ROOT / "scripts" / "catalogue_pages.py"
)
cp = importlib.util.module_from_spec(spec)
spec.loader.exec_module(cp)

INDEX = json.loads((cat.DATA / "index.json").read_text())
IDS = [r["id"] for r in INDEX["families"]]


@functools.cache
def catalogue():
    return cat.load()


def _chapter_entry():
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    for ch in toc["chapters"]:
        if ch.get("file") == cp.CHAPTER:
            return ch
    raise AssertionError(f"{cp.CHAPTER} is not a chapter of _toc.yml")


def test_every_family_has_a_page_in_the_toc():
    (gallery,) = _chapter_entry()["sections"]
    assert gallery["file"] == cp.GALLERY
    listed = [s["file"] for s in gallery.get("sections", [])]
    assert listed == [f"book/catalogue/{i}" for i in IDS]
    stored = sorted(p.stem for p in PAGES.glob("F*.md"))
    assert stored == sorted(IDS), "pages of families not in index.json (or missing)"
    for i in IDS:
        assert (PAGES / f"{i}.md").is_file()


@pytest.mark.parametrize("fid", IDS)
def test_page_is_what_the_script_writes(fid):
    rec = catalogue().family(fid).record
    figs = {
        k: f"{fid}-{k}.png"
        for k in ("branch", "shape")
        if (PAGES / f"{fid}-{k}.png").is_file()
    }
    assert "branch" in figs, f"{fid}: no figure (run scripts/catalogue_pages.py)"
    assert (PAGES / f"{fid}.md").read_text() == cp.page(rec, set(IDS), figs), (
        f"book/catalogue/{fid}.md is stale: run scripts/catalogue_pages.py"
    )


def test_gallery_is_what_the_script_writes():
    C = catalogue()
    assert (PAGES / "gallery.md").read_text() == cp.gallery(
        C.index, [f.record for f in C]
    ), "book/catalogue/gallery.md is stale: run scripts/catalogue_pages.py"


def test_links_reach_pages():
    for p in [*PAGES.glob("F*.md"), PAGES / "gallery.md"]:
        for target in re.findall(r"\]\(([^)#]+)", p.read_text()):  # links, images
            assert (p.parent / target).resolve().is_file(), f"{p.name} -> {target}"
    svg = (PAGES / "te_diagram.svg").read_text()
    hrefs = set(re.findall(r'xlink:href="catalogue/(F\d+)\.html"', svg))
    assert hrefs == set(IDS), "the T-E diagram does not link every family's page"
    assert "target=" not in svg and svg.startswith("<svg ")


def test_links_both_ways_on_the_pages():
    """A daughter's page names its parent, and the parent's page names the daughter."""
    for fid in IDS:
        rec = catalogue().family(fid).record
        for d in rec["daughters"]:
            assert f"[{fid}]({fid}.md)" in (PAGES / f"{d['id']}.md").read_text()


def test_update_toc_rewrites_only_chapter_13():
    text = (
        "chapters:\n  - file: book/12_precision\n  - file: book/13_catalogue\n"
        "    sections:\n      - file: old\n  # back matter\n  - file: book/errata\n"
    )
    out = cp.update_toc(text, ["F001", "F002"])
    toc = yaml.safe_load(out)
    ch = toc["chapters"][1]
    assert [s["file"] for s in ch["sections"][0]["sections"]] == [
        "book/catalogue/F001",
        "book/catalogue/F002",
    ]
    assert toc["chapters"][2] == {"file": "book/errata"} and "# back matter" in out
    assert cp.update_toc(out, ["F001", "F002"]) == out
    with pytest.raises(ValueError, match="13_catalogue"):
        cp.update_toc("chapters:\n  - file: book/01\n", ["F001"])


def test_page_reads_fields_defensively():
    """A minimal record (fields of another build missing) still makes a page."""
    rec = {"id": "F999", "name": "PD^r_1", "members": [], "ends": []}
    text = cp.page(rec, {"F999"})
    assert text.startswith("# F999") and r"\mathrm{PD}" in text
    assert "None inside" in text and "No parent" in text


x = np.linspace(5.0, 6.0, 30)
FIGURES = {
    "te": lambda: pcat.plot_te_diagram(
        [dict(E=x, T=2 + x, trace=np.linspace(-1, 5, 30), id="F001", url="a.html")],
        (5.33, 5.6),
        [("separatrix", 4.0)],
        window=(5.3, 6.2),
        t_max=8.0,
    ),
    "family": lambda: pcat.plot_family(
        x,
        2 + x,
        np.linspace(-900, 5, 30),
        [dict(kind="PD", E=5.5, period=7.5, trace=0)],
    ),
    "shapes": lambda: pcat.plot_shapes(
        [dict(states=np.c_[x, x, x, x], E=e, title="E = 4") for e in (3.0, 5.0)]
    ),
    "fraction": lambda: pcat.plot_stable_fraction(x, x * 0 + 3, x * 0 + 1, (5.33, 5.6)),
}
PLAIN = re.compile(r"\b(IS|PD)\^|\b(IS|PD)[lr]\d|<=|>=|sqrt\(|\bT_max\b")


@pytest.mark.parametrize("name", sorted(FIGURES))
def test_figures_in_the_book_style(name):
    fig = FIGURES[name]()
    try:
        fig.set_dpi(50)
        fig.canvas.draw()
        assert fig.get_size_inches()[0] <= rp.COLUMN_WIDTH + 1e-9
        for a in fig.get_axes():
            if a.get_visible() and a.axison:
                assert a.get_xlabel().strip() and a.get_ylabel().strip()
                for t in a.get_xticklabels() + a.get_yticklabels():
                    assert not t.get_text() or t.get_fontsize() >= 10
        for t in fig.findobj(matplotlib.text.Text):
            s = re.sub(r"\$[^$]*\$", "", t.get_text())
            assert not PLAIN.search(s), s
    finally:
        plt.close(fig)


def test_te_diagram_svg_links_each_branch():
    fig = FIGURES["te"]()
    buf = io.StringIO()
    fig.savefig(buf, format="svg")
    plt.close(fig)
    assert buf.getvalue().count('xlink:href="a.html"') >= 3  # hit line, thin, stable


def test_shapes_refuse_nothing():
    with pytest.raises(ValueError, match="no orbits"):
        pcat.plot_shapes([])
