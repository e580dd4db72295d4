"""Write the catalogue's gallery: one MyST page per family, its figures, the T-E diagram.

For every family of the stored catalogue (``rotorlib/data/catalogue/``, or
``--catalogue DIR``) this writes into ``book/catalogue/``:

* ``<ID>.md``: the family's page (name, symmetry, energy range and ends with their
  reasons, stability windows, special points, links to its parents and daughters,
  the stored members' table) -- plain MyST Markdown, nothing executes;
* ``<ID>-branch.png``: ``T(E)`` and ``tr M(E)`` along the continuation path;
* ``<ID>-shape.png``: the orbit on the configuration torus at up to three energies,
  integrated over one period from stored 30-digit members' ``state0`` (rotorlib's
  flow, float64);

and ``gallery.md`` (the list of the families, linking to their pages),
``te_diagram.svg`` (every family's ``T(E)``, coloured by stability, each branch a link
to its page; chapter 13 includes it inline) with ``te_diagram.png`` (its raster copy
for print). Pages of families no longer in the catalogue are removed. The family pages
become the sections of ``book/catalogue/gallery`` under ``book/13_catalogue`` in
``_toc.yml`` (only that entry is rewritten).

PNGs are drawn at 200 dpi (2x the 688 px column) and stored with a 64-colour palette
(~30-70 kB each); the script prints the total size.

Usage: python scripts/catalogue_pages.py [--catalogue DIR] [--no-figures]
"""

from __future__ import annotations

import argparse
import io
import math
import re
import sys
from decimal import Decimal, localcontext
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
OUT = BOOK / "catalogue"
TOC = ROOT / "_toc.yml"
CHAPTER = "book/13_catalogue"
GALLERY = "book/catalogue/gallery"
FAMILY_PAGE = re.compile(r"^F\d{3,}$")


# ---------------------------------------------------------------- formatting helpers
def sig(x: Any, n: int) -> str:
    from rotorlib.core.rounding import sig as _sig

    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    return _sig(float(x), n)


def esc(text: Any) -> str:
    """Plain text for a Markdown table cell."""
    s = str(text)
    for c in "\\|*_$`<>[]":
        s = s.replace(c, "\\" + c)
    return s


def name_md(name: str | None) -> str:
    """A family's name as MyST: family labels typeset (``PD^r_1`` -> math)."""
    from rotorlib.core.compare import label_tex, typeset_labels

    if not name:
        return "unnamed"
    try:
        return label_tex(name)
    except ValueError:
        pass
    typeset = typeset_labels(name)
    return typeset if typeset != name else esc(name)


def table(header: list[str], rows: list[list[Any]]) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def symmetry_class(rec: dict) -> str:
    s = rec.get("symmetry") or {}
    if s.get("choreography"):
        return "choreography"
    return "rotating" if s.get("rotating") else "librating"


def period_factor(rec: dict) -> float:
    return float((rec.get("branch") or {}).get("factor", 1.0))


def path_arrays(rec: dict):
    """``E, T, tr M`` along the stored continuation path (float64)."""
    import numpy as np

    path = np.array((rec.get("branch") or {}).get("path") or [], dtype=float)
    if path.size == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    return path[:, 0], period_factor(rec) * path[:, 2], path[:, 3]


def link(fid: str, known: set[str]) -> str:
    return f"[{fid}]({fid}.md)" if fid in known else esc(fid)


def point_E(p: dict) -> str:
    """A special point's energy to the digits it was located to (``E_str`` rounded to
    the decimals of its ``E_error`` when the record has them; else 12 decimals); a
    marginal stretch's two ends."""
    if p.get("kind") == "marginal":
        return f"{float(p['E']):.12f} – {float(p['E_end']):.12f}"
    if p.get("E_str"):
        if not p.get("E_error"):
            return esc(p["E_str"])
        # the decimals its error bound warrants (a fold: ~22; an IS/PD point: ~25)
        d = max(0, math.floor(-math.log10(p["E_error"])))
        with localcontext(prec=50):
            return esc(str(Decimal(p["E_str"]).quantize(Decimal(1).scaleb(-d))))
    tail = " (float64)" if p.get("location", "").startswith("float64") else ""
    return f"{float(p['E']):.12f}{tail}"


def window_text(w) -> str:
    return f"{sig(w[0], 10)} – {sig(w[1], 10)}"


# ---------------------------------------------------------------- the page
def shown_width(png: Path) -> str:
    """The width to show a PNG at: 2 pixels per CSS pixel of the 688 px column
    (figures are drawn at 200 dpi, 6.88 in wide at most)."""
    from PIL import Image

    try:
        with Image.open(png) as img:
            px = img.size[0]
    except OSError:
        return "100%"
    return f"{min(100, round(100 * px / 1376))}%"


def page(
    rec: dict,
    known: set[str],
    figures: dict[str, str] | None = None,
    fig_dir: Path = OUT,
) -> str:
    """The Markdown page of one family record (its JSON as stored); ``figures`` names
    its PNGs (keys ``branch``, ``shape``) in ``fig_dir``."""
    fid = rec["id"]
    name = rec.get("name")
    sym = rec.get("symmetry") or {}
    title = f"{fid}: {name}" if name and "^" not in name else fid
    lines = [
        f"# {title}",
        "",
        "<!-- Generated by scripts/catalogue_pages.py from "
        f"rotorlib/data/catalogue/{fid}.json; do not edit by hand. -->",
        "",
        f"Family **{fid}** of the [catalogue](../13_catalogue.ipynb) "
        f"([all families](gallery.md)): {name_md(name)}"
        + (
            f" (also named {', '.join(name_md(n) for n in rec.get('names', [])[1:])})"
            if len(rec.get("names") or []) > 1
            else ""
        )
        + f", a {symmetry_class(rec)} family. "
        f"Its record is `rotorlib/data/catalogue/{fid}.json`; "
        f"`rotorlib catalogue --family {fid} --json` prints it and "
        f"`rotorlib catalogue --verify {fid}` re-solves its stored members.",
        "",
        "## Summary",
        "",
    ]
    wind = sym.get("winding")
    lo, hi = rec.get("E_range", [math.nan, math.nan])
    tlo, thi = rec.get("period_range", [math.nan, math.nan])
    windows = rec.get("stable_windows") or []
    rows = [
        ["energy range", f"{sig(lo, 8)} ≤ E ≤ {sig(hi, 8)}"],
        ["period range", f"{sig(tlo, 8)} ≤ T ≤ {sig(thi, 8)}"],
        ["choreography", "yes" if sym.get("choreography") else "no"],
        [
            "rotating",
            ("yes" if sym.get("rotating") else "no")
            + (
                f" (winding of a1, a2 over a period: {', '.join(sig(w, 3) for w in wind)}"
                " turns)"
                if wind
                else ""
            ),
        ],
        [
            "stable windows",
            "; ".join(window_text(w) for w in windows) or "none (unstable throughout)",
        ],
        ["stored members", len(rec.get("members") or [])],
        ["continuation path members", len((rec.get("branch") or {}).get("path") or [])],
        ["census orbits it contains", len(rec.get("census_orbits") or [])],
    ]
    for key, value in sorted(rec.items()):  # fields of later builds, shown as they are
        if "interp" not in key:
            continue
        items = value.items() if isinstance(value, dict) else [("", value)]
        for sub, v in items:
            if isinstance(v, int | float) and not isinstance(v, bool):
                shown = str(v) if isinstance(v, int) else sig(v, 2)  # counts exactly
                rows.append([esc(f"{key} {sub}".replace("_", " ").strip()), shown])
    lines += [table(["quantity", "value"], rows), ""]
    sets = sym.get("fixed_sets") or []
    if sets:
        lines += [
            "The pairs of fixed sets of reversing symmetries its census orbits meet "
            "half a period apart: "
            + "; ".join(" and ".join(esc(s) for s in pair) for pair in sets)
            + ".",
            "",
        ]
    # ends
    lines += ["## Its ends", ""]
    ends = rec.get("ends") or []
    lines += [
        table(
            ["side", "E", "T", "why the record stops"],
            [
                [
                    esc(e.get("side", "")),
                    sig(e.get("E"), 8),
                    sig(e.get("period"), 8),
                    esc(e.get("reason") or e.get("kind", "")),
                ]
                for e in ends
            ],
        )
        if ends
        else "No end is recorded.",
        "",
    ]
    # figures
    if figures:
        lines += [
            "## Period and stability along the family",
            "",
            f"```{{figure}} {figures['branch']}",
            f":alt: {fid}: period T and the trace of the monodromy tr M against "
            "energy E along the family; thick green where stable",
            f":width: {shown_width(fig_dir / figures['branch'])}",
            "",
            f"{fid}: (a) the period and (b) $\\mathrm{{tr}}\\,M$ against the energy "
            "along the continuation path (float64), thick where the family is "
            "linearly stable ($0 < \\mathrm{tr}\\,M < 4$); the band of global chaos "
            "is shaded and the special points are marked.",
            "```",
            "",
        ]
        if figures.get("shape"):
            lines += [
                "## The orbit's shape",
                "",
                f"```{{figure}} {figures['shape']}",
                f":alt: {fid}: the orbit on the configuration torus (phi1, phi2) at "
                "up to three energies of the family",
                f":width: {shown_width(fig_dir / figures['shape'])}",
                "",
                f"{fid} on the configuration torus "
                "($\\varphi_1 = \\theta_1 - \\theta_2$, "
                "$\\varphi_2 = \\theta_2 - \\theta_3$, wrapped to $(-\\pi, \\pi]$) at "
                "stored members, integrated over one period from their "
                "`state0` (float64): the minimum G (dot), the maxima T (triangles) "
                "and the region $V > E$ (grey, forbidden) where it exists.",
                "```",
                "",
            ]
    # special points
    lines += ["## Special points", ""]
    pts = rec.get("special_points") or []
    if pts:
        lines += [
            table(
                ["kind", "E", "T", "tr M"],
                [
                    [
                        esc(p.get("kind", "")),
                        point_E(p),
                        sig(p.get("period"), 10),
                        sig(p.get("trace"), 6)
                        if abs(float(p.get("trace", 0))) > 1e-9
                        else "< 1e-9 (0)",
                    ]
                    for p in sorted(pts, key=lambda p: float(p["E"]))
                ],
            ),
            "",
            "Folds are turning points of the family in E; IS: "
            "$\\mathrm{tr}\\,M = 4$ (a pair of multipliers leaves the unit circle at 1), "
            "PD: $\\mathrm{tr}\\,M = 0$ (at $-1$); touch: $\\mathrm{tr}\\,M$ reaches 4 "
            "or 0 without a change of stability; marginal: a stretch (its two ends) where "
            "$\\mathrm{tr}\\,M$ stays within $10^{-6}$ of its level and float64 does not "
            "resolve its side. IS and PD energies are their 30-digit roots, folds the "
            "30-digit extremum of E along the branch (to ~1e-22; where E(u) is "
            "ill-conditioned, the float64 one, ~1e-8, marked so), touches to their golden-section bracket "
            "(~1e-15).",
            "",
        ]
    else:
        lines += ["None inside the family's catalogued range.", ""]
    # links
    lines += ["## Parents and daughters", ""]
    links = [
        ["parent", link(x["id"], known), esc(x.get("kind", "")), sig(x.get("E"), 12)]
        for x in rec.get("parents") or []
    ] + [
        ["daughter", link(x["id"], known), esc(x.get("kind", "")), sig(x.get("E"), 12)]
        for x in rec.get("daughters") or []
    ]
    lines += [
        table(["link", "family", "bifurcation", "at E"], links)
        if links
        else "No parent or daughter in the catalogue.",
        "",
    ]
    twins = rec.get("fold_twins") or []
    if twins:
        lines += [
            "The same family's other branch, across the fold they share, is held as "
            "the record "
            + ", ".join(
                f"{link(t['id'], known)} (fold at E = {sig(t['E'], 12)})" for t in twins
            )
            + ".",
            "",
        ]
    # members
    members = sorted(rec.get("members") or [], key=lambda m: float(m["E"]))
    lines += [
        "## Stored members",
        "",
        "Each re-solved to 30 digits (period, `state0` and $\\mathrm{tr}\\,M$ to "
        "30 and 25 digits in the JSON record; rounded here); S is the action "
        "$\\oint p\\cdot dq$ and μ the Maslov index (– where not computed).",
        "",
        table(
            ["kind", "E", "T", "tr M", "S", "μ"],
            [
                [
                    esc(m.get("kind", "")),
                    sig(m.get("E_str", m.get("E")), 12),
                    sig(m.get("period_str", m.get("period")), 12),
                    sig(m.get("trace_str", m.get("trace")), 10),
                    sig(m.get("action"), 9),
                    "–" if m.get("maslov") is None else esc(m["maslov"]),
                ]
                for m in members
            ],
        ),
        "",
    ]
    return "\n".join(lines)


def scope_md(index: dict) -> str:
    r"""The census scope in words: ``periods T <= 8 in 0.1 <= E <= 8``, or by bands
    (``T <= 16 for 0.1 <= E <= 6.2 and T <= 8 for 6.2 < E <= 8``).

    >>> print(scope_md({"window": [0.1, 8.0], "t_max": 16, "bands": [[6.2, 16], [8, 8]]}))
    periods $T \le 16$ for $0.1 \le E \le 6.2$ and $T \le 8$ for $6.2 < E \le 8$
    """
    lo, hi = index.get("window", [math.nan, math.nan])
    bands = index.get("bands") or [[hi, index.get("t_max")]]
    g = "{:g}".format
    if len(bands) == 1:
        T = g(float(bands[0][1]))
        return f"periods $T \\le {T}$ in ${g(lo)} \\le E \\le {g(hi)}$"
    parts, e0 = [], None
    for e1, T in bands:
        left = f"{g(lo)} \\le E" if e0 is None else f"{g(e0)} < E"
        parts.append(f"$T \\le {g(T)}$ for ${left} \\le {g(e1)}$")
        e0 = e1
    return "periods " + ", ".join(parts[:-1]) + " and " + parts[-1]


def gallery(index: dict, records: list[dict], fig_dir: Path = OUT) -> str:
    """The gallery page: a summary table, then a thumbnail of each family's orbit (its
    shape figure, else its branch figure) beside its description, linked to its page."""
    lo, hi = index.get("window", [math.nan, math.nan])
    lines = [
        "# The catalogued families",
        "",
        "<!-- Generated by scripts/catalogue_pages.py; do not edit by hand. -->",
        "",
        f"The {len(records)} families of the [catalogue](../13_catalogue.ipynb) "
        f"({scope_md(index)}), one page each: its symmetry, "
        "ends, stability windows, special points, parents and daughters, the shape "
        "of its orbit and its stored members.",
        "",
        table(
            ["family", "name", "class", "E range", "T range", "stable"],
            [
                [
                    f"[{r['id']}]({r['id']}.md)",
                    name_md(r.get("name")) if r.get("name") else "–",
                    symmetry_class(r),
                    " – ".join(sig(v, 4) for v in r.get("E_range", [])),
                    " – ".join(sig(v, 4) for v in r.get("period_range", [])),
                    "yes" if r.get("stable_windows") else "no",
                ]
                for r in records
            ],
        ),
        "",
    ]
    rows = []
    for r in records:
        fid = r["id"]
        thumb = next(
            (
                f"{fid}-{k}.png"
                for k in ("shape", "branch")
                if (fig_dir / f"{fid}-{k}.png").is_file()
            ),
            None,
        )
        if thumb is None:
            continue
        what = "its orbit on the configuration torus" if "shape" in thumb else "T(E)"
        windows = r.get("stable_windows") or []
        rows += [
            f"* - ![{fid}: {what}]({thumb})",
            f"  - **[{fid}]({fid}.md)**"
            + (f" {name_md(r.get('name'))}" if r.get("name") else "")
            + f": {symmetry_class(r)}; "
            + " ≤ E ≤ ".join(sig(v, 4) for v in r.get("E_range", []))
            + "; "
            + " ≤ T ≤ ".join(sig(v, 4) for v in r.get("period_range", []))
            + "; "
            + (
                "stable in " + ", ".join(window_text(w) for w in windows)
                if windows
                else "unstable throughout"
            ),
        ]
    if rows:
        lines += [
            "## The orbits",
            "",
            "Each family's orbit on the configuration torus at up to three energies "
            "(its page shows it larger).",
            "",
            "```{list-table}",
            ":header-rows: 1",
            ":class: gallery-table",
            ":widths: 45 55",
            "",
            "* - orbit",
            "  - family",
            *rows,
            "```",
            "",
        ]
    return "\n".join(lines)


# ---------------------------------------------------------------- figures
def save_png(fig, path: Path, colors: int = 64) -> int:
    """Save at the style's 200 dpi with an adaptive palette; returns the size."""
    import matplotlib.pyplot as plt
    from PIL import Image

    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    buf.seek(0)
    img = Image.open(buf).convert("RGB")
    img = img.quantize(colors=colors, method=Image.Quantize.MEDIANCUT)
    img.save(path, format="PNG", optimize=True)
    return path.stat().st_size


def shape_orbits(rec: dict, n: int = 3) -> list[dict]:
    """Up to ``n`` stored members spread in E, integrated over one period."""
    from rotorlib.core.flow import sample

    ms = sorted(rec.get("members") or [], key=lambda m: float(m["E"]))
    if not ms:
        return []
    pick = sorted({round(i * (len(ms) - 1) / max(n - 1, 1)) for i in range(n)})
    out = []
    for i in pick:
        m = ms[i]
        T = float(m["period"])
        try:
            states, _ = sample([float(v) for v in m["state0"]], T, n=700)
        except Exception as exc:  # an orbit the float64 flow cannot follow: no panel
            print(
                f"catalogue_pages: {rec['id']} at E = {m['E']}: {exc}", file=sys.stderr
            )
            continue
        out.append(
            {
                "states": states,
                "E": float(m["E"]),
                "title": f"E = {sig(m['E'], 6)}, T = {sig(T, 6)}",
            }
        )
    return out


def te_curves(records: list[dict], prefix: str) -> list[dict]:
    out = []
    for r in records:
        E, T, tr = path_arrays(r)
        if len(E):
            out.append(
                {
                    "E": E,
                    "T": T,
                    "trace": tr,
                    "id": r["id"],
                    "url": f"{prefix}{r['id']}.html",
                }
            )
    return out


def separatrices() -> list[tuple[str, float]]:
    from rotorlib.core.system import BREATHER_SEPARATRIX_ENERGY, SEPARATRIX_ENERGY

    return [
        (f"pendulum separatrix (E = {sig(SEPARATRIX_ENERGY, 3)})", SEPARATRIX_ENERGY),
        (
            f"breather separatrix (E = {sig(BREATHER_SEPARATRIX_ENERGY, 3)})",
            BREATHER_SEPARATRIX_ENERGY,
        ),
    ]


def write_te_diagram(index: dict, records: list[dict], out: Path) -> int:
    """``te_diagram.svg`` (branches linked to ``catalogue/<ID>.html``, for chapter 13)
    and ``te_diagram.png``; returns their total size."""
    import matplotlib.pyplot as plt

    from rotorlib.paper.chaos import BAND
    from rotorlib.plotting import catalogue as pcat

    names = {r["id"]: r.get("name") for r in records}
    fig = pcat.plot_te_diagram(
        te_curves(records, "catalogue/"),
        BAND,
        separatrices(),
        window=tuple(index["window"]) if index.get("window") else None,
        t_max=index.get("bands") or index.get("t_max"),
    )
    plt.rcParams["svg.hashsalt"] = "rotorlib-catalogue"
    buf = io.StringIO()
    fig.savefig(buf, format="svg", metadata={"Date": None})
    svg = buf.getvalue()

    # a tooltip per link: the family's id and name
    def title(m):
        fid = m.group(2)
        tip = fid + (f": {names.get(fid)}" if names.get(fid) else "")
        return f"{m.group(0)}<title>{tip}</title>"

    svg = svg.replace(' target="_blank"', "")  # links open in the same tab
    svg = re.sub(r'<a xlink:href="(catalogue/(F\d+)\.html)">', title, svg)
    # coordinates to 0.1 pt (the file is inlined in the page: keep it small)
    svg = re.sub(r' d="[^"]*"', lambda m: re.sub(r"(\.\d)\d+", r"\1", m.group(0)), svg)
    svg = svg[svg.index("<svg") :]  # drop the XML prolog and DOCTYPE: inline HTML
    # scale to the text column (the viewBox keeps the aspect ratio)
    svg = re.sub(
        r'^<svg ([^>]*?)width="[^"]*" height="[^"]*"', r'<svg \1width="100%"', svg
    )
    svg = svg.replace(
        "<svg ",
        '<svg role="img" aria-label="The T-E diagram of the catalogued families; '
        'each branch links to its family page" ',
        1,
    )
    (out / "te_diagram.svg").write_text(svg)
    size = (out / "te_diagram.svg").stat().st_size
    return size + save_png(fig, out / "te_diagram.png")


# ---------------------------------------------------------------- the table of contents
def toc_block(indent: int, ids: list[str]) -> list[str]:
    pad = " " * indent
    out = [f"{pad}  sections:", f"{pad}    - file: {GALLERY}"]
    if ids:
        out.append(f"{pad}      sections:")
        out += [f"{pad}        - file: book/catalogue/{i}" for i in ids]
    return out


def update_toc(text: str, ids: list[str]) -> str:
    """``_toc.yml`` with the entry of chapter 13 given the gallery and family pages
    as its sections (the rest of the file is left as it is)."""
    lines = text.splitlines()
    pat = re.compile(rf"^(\s*)- file: {re.escape(CHAPTER)}\s*$")
    for i, line in enumerate(lines):
        m = pat.match(line)
        if m:
            break
    else:
        raise ValueError(f"_toc.yml has no entry '- file: {CHAPTER}'")
    indent = len(m.group(1))
    j = i + 1
    while j < len(lines):
        s = lines[j]
        if s.strip() and len(s) - len(s.lstrip()) <= indent:
            break
        j += 1
    return "\n".join(lines[: i + 1] + toc_block(indent, ids) + lines[j:]) + "\n"


# ---------------------------------------------------------------- main
def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--catalogue", default=None, help="a catalogue directory")
    ap.add_argument("--out", default=str(OUT), help="where the pages go")
    ap.add_argument("--toc", default=str(TOC), help="the _toc.yml to update")
    ap.add_argument(
        "--no-figures", action="store_true", help="pages only (no PNG, no SVG)"
    )
    args = ap.parse_args(argv)

    from rotorlib.beyond import catalogue as cat

    C = cat.load(args.catalogue)
    records = [f.record for f in C]
    known = {r["id"] for r in records}
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for old in out.iterdir():  # families that left the catalogue
        stem = old.name.split("-")[0].split(".")[0]
        if FAMILY_PAGE.match(stem) and stem not in known:
            old.unlink()
    size = 0
    for r in records:
        fid = r["id"]
        figs = None
        if not args.no_figures:
            from rotorlib.paper.chaos import BAND
            from rotorlib.plotting import catalogue as pcat

            E, T, tr = path_arrays(r)
            fig = pcat.plot_family(E, T, tr, r.get("special_points") or [], BAND)
            size += save_png(fig, out / f"{fid}-branch.png")
            figs = {"branch": f"{fid}-branch.png"}
            shapes = shape_orbits(r)
            if shapes:
                size += save_png(pcat.plot_shapes(shapes), out / f"{fid}-shape.png")
                figs["shape"] = f"{fid}-shape.png"
        (out / f"{fid}.md").write_text(page(r, known, figs, out))
        print(f"catalogue_pages: {fid}", file=sys.stderr)
    (out / "gallery.md").write_text(gallery(C.index, records, out))
    if not args.no_figures:
        size += write_te_diagram(C.index, records, out)
    toc = Path(args.toc)
    toc.write_text(update_toc(toc.read_text(), [r["id"] for r in records]))
    total = sum(p.stat().st_size for p in out.iterdir() if p.is_file())
    print(
        f"catalogue_pages: {len(records)} family pages in {out}; figures written "
        f"{size / 1e6:.2f} MB, the directory {total / 1e6:.2f} MB"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
