"""Write book/ledger.md: every quantitative claim of the paper the book checks, by category.

Each chapter that compares numbers with the paper glues its records under the key
``claims`` (``glue("claims", rotorlib.core.compare.records(CLAIMS, chapter), display=False)``,
a JSON list of :class:`rotorlib.core.compare.Claim`). This script reads those records from the
stored, executed notebooks listed in _toc.yml (nbval checks that they are reproduced),
merges claims that the paper makes twice (the same family, the same printed digits and
the same value of ours, up to sign), sorts them into the categories of
``rotorlib.core.compare.CATEGORIES`` (given per claim with ``claim(..., category=...)``, or
derived from the verdict), and writes the ledger: counts by category at the top, then one
table per category, each row with its cause, the meaning of its tolerance and a link to
the section of the chapter that computes it. Nothing in the ledger is typed by hand.

The section is the chapter heading above the first Markdown cell quoting the paper's
printed value (else the first code cell containing it as a string literal), unless the
claim names one (``anchor``); the link uses MyST's heading anchors
(``myst_heading_anchors`` in _config.yml), whose slugs are computed here the same way.

Usage: python scripts/make_ledger.py [--check]
  --check  exit 1 if book/ledger.md is not up to date (writes nothing).
"""

from __future__ import annotations

import ast
import json
import re
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from rotorlib.core.compare import (  # noqa: E402
    CATEGORIES,
    category_of_verdict,
    label_tex,
    typeset_labels,
)

OUT = ROOT / "book" / "ledger.md"

#: What each category means, for the reader (the ledger's legend).
MEANING = {
    "reproduced": "our value rounds to the paper's printed digits, or lies within the "
    "stated tolerance of a value the paper marks ≈",
    "misrounded": "the paper's last printed digit is off by a few units (k > 0: the "
    "paper's digit is k units above ours correctly rounded; k < 0: below), or the "
    "paper's value is ours truncated instead of rounded; the physics is unaffected",
    "typo": "the printed value differs from ours by transposed or single wrong digits, "
    "with every other digit right: a transcription slip",
    "error": "an independent error in the paper: the value or formula differs beyond "
    "rounding, and no earlier claim explains it",
    "inherited": "the paper computed the value from an earlier wrong number (linked); "
    "it is not a separate error",
    "definition": "the value depends on a definition the paper leaves open; the row "
    "states the definition under which ours is computed",
    "inequality": "the paper states a bound (≲, ≳), and our value satisfies it",
    "not evaluable": "the quantity does not exist where the paper evaluates it",
    "answer": "the paper asks an open question and the book answers it: our value is "
    "set beside the value the paper quotes, with the tolerance of its printed digits; "
    "it is not a claim of the paper and is not scored as reproduced",
}

_WORDS = {
    "tau": "τ",
    "omega0": "ω₀",
    "omega": "ω",
    "alpha": "α",
    "beta": "β",
    "delta": "δ",
    "kappa": "κ",
    "phi": "φ",
    "phi1": "φ₁",
    "phi2": "φ₂",
    "dphi1": "δφ₁",
    "dphi2": "δφ₂",
    "da1": "δα₁",
    "da2": "δα₂",
    "pi": "π",
    "sqrt": "√",
    "sqrt3": "√3",
    "mu": "μ",
    "lambda": "λ",
    "theta": "θ",
}
_SYMBOLS = [("<=", "≤"), (">=", "≥"), ("<~", "≲"), (">~", "≳"), ("!=", "≠")]


def toc_notebooks() -> list[Path]:
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    files = [c["file"] for c in toc.get("chapters", [])]
    return [ROOT / f"{f}.ipynb" for f in files if (ROOT / f"{f}.ipynb").is_file()]


# ------------------------------------------------------------------ headings, anchors


def _heading_text(inline) -> str:
    """The text MyST slugs a heading from: its text and inline-code children only."""
    return "".join(
        child.content
        for child in (inline.children or [])
        if child.type in ("text", "code_inline")
    )


def _slugify(title: str) -> str:
    # myst_parser.mdit_to_docutils.base.default_slugify (GitHub style)
    return re.sub(r"[^\w\u4e00-\u9fff\- ]", "", title.lower().replace(" ", "-"))


def sections_of(nb: dict) -> list[tuple[int, int, str, str]]:
    """``(cell index, line, heading text, anchor)`` of every heading, as MyST anchors
    them."""
    from markdown_it import MarkdownIt
    from mdit_py_plugins.dollarmath import dollarmath_plugin

    md = MarkdownIt("commonmark").enable("table").use(dollarmath_plugin)
    out, slugs = [], set()
    for i, cell in enumerate(nb["cells"]):
        if cell["cell_type"] != "markdown":
            continue
        tokens = md.parse("".join(cell["source"]))
        for k, tok in enumerate(tokens):
            if tok.type != "heading_open":
                continue
            inline = tokens[k + 1]
            slug = base = _slugify(_heading_text(inline))
            n = 1
            while slug in slugs:
                slug = f"{base}-{n}"
                n += 1
            slugs.add(slug)
            out.append((i, tok.map[0] if tok.map else 0, inline.content, slug))
    return out


def section_at(sections, cell: int, line: int = 0) -> str:
    """The anchor of the section that holds ``line`` of ``cell`` ("" in the chapter's
    opening, which is the page itself)."""
    above = [s for s in sections if (s[0], s[1]) <= (cell, line)]
    return above[-1][3] if len(above) > 1 else ""


def _anchor_for(nb: dict, sections, value: str) -> str:
    """The anchor of the section that states ``value`` (prose first, then code)."""
    if not value or value in ("0", "1", "2", "3", "4", "-"):
        return ""
    quoted = re.compile(r"(?<![\d.])" + re.escape(value) + r"(?![\d])")
    literal = re.compile(r"[\"']-?" + re.escape(value) + r"[\"']")
    for kind, pattern in (("markdown", quoted), ("code", literal)):
        for i, cell in enumerate(nb["cells"]):
            src = "".join(cell["source"])
            m = pattern.search(src) if cell["cell_type"] == kind else None
            if m:
                return section_at(sections, i, src.count("\n", 0, m.start()))
    return ""


def claims_of(path: Path) -> tuple[str, list[dict]]:
    """The chapter's title and its glued claims, each with ``anchor`` filled in."""
    nb = json.loads(path.read_text(encoding="utf-8"))
    title = path.stem
    for cell in nb["cells"]:
        if cell["cell_type"] == "markdown":
            for line in "".join(cell["source"]).splitlines():
                if line.startswith("# "):
                    title = line[2:].strip()
                    break
            break
    sections = sections_of(nb)
    slugs = {s[3] for s in sections}
    rows = []
    for cell in nb["cells"]:
        for out in cell.get("outputs", []):
            if out.get("metadata", {}).get("scrapbook", {}).get("name") != "claims":
                continue
            text = out["data"]["application/papermill.record/text/plain"]
            rows += json.loads(ast.literal_eval(text))
    for r in rows:
        given = r.get("anchor", "")
        r["anchor"] = (
            given
            if given in slugs
            else _anchor_for(nb, sections, r["paper"].strip().lstrip("-"))
        )
    return title, rows


# ------------------------------------------------------------------------- rendering


def pretty(text: str) -> str:
    """A record's plain text for the page: family labels typeset, Greek and ≤ in Unicode,
    ``|`` escaped for the table."""
    parts = re.split(r"(\$[^$]*\$|`[^`]*`)", typeset_labels(str(text)))
    for i in range(0, len(parts), 2):
        s = parts[i]
        for a, b in _SYMBOLS:
            s = s.replace(a, b)
        s = re.sub(
            r"(?<![\w\\])("
            + "|".join(sorted(_WORDS, key=len, reverse=True))
            + r")(?![A-Za-z0-9])",
            lambda m: _WORDS[m.group(1)],
            s,
        )
        s = re.sub(r"(?<![\w$])\*(?!\*)", "·", s)  # a bare * is a product
        parts[i] = s
    return "".join(parts).replace("|", "\\|")


def _labels(text: str) -> frozenset[str]:
    from rotorlib.core.compare import LABEL_IN_TEXT_RE

    return frozenset(label_tex(m) for m in LABEL_IN_TEXT_RE.findall(text))


def category_of(rec: dict) -> str:
    return rec.get("category") or category_of_verdict(rec["verdict"])


def _num(x) -> str:
    return f"{x:.2g}" if isinstance(x, float) else str(x)


def tolerance_text(rec: dict) -> str:
    """What the row's tolerance means."""
    tol = rec.get("tolerance")
    if tol is None:
        return ""
    if rec.get("rule") == "bound":
        return f"a bound, slack {_num(tol)}" if tol else "a bound"
    if not rec.get("approx"):
        return f"tolerance ± half a unit in the last digit ({_num(tol)})"
    try:
        paper = abs(float(rec["paper"]))
    except ValueError:
        paper = 0.0
    if paper:
        r = tol / paper
        rounded = float(f"{r:.1g}")
        if abs(r - rounded) <= 0.01 * rounded:
            return f"tolerance (≈) {rounded * 100:.1g}% of the value ({_num(tol)})"
    return f"tolerance ± {_num(tol)}"


def cause_text(rec: dict, cat: str) -> str:
    """The cause shown in the row (the sign of an 'off by k' spelled out)."""
    verdict, cause = rec["verdict"], rec.get("cause", "")
    m = re.fullmatch(r"last digit off by ([+-]\d+)", verdict)
    if m and cat == "misrounded":
        k = int(m.group(1))
        unit = "unit" if abs(k) == 1 else "units"
        where = "above" if k > 0 else "below"
        return f"last digit {k:+d}: the paper's is {abs(k)} {unit} {where} ours rounded"
    if verdict == "truncated" and cat == "misrounded":
        return "ours truncated, not rounded"
    if cat == "reproduced" or cause == "outside the tolerance":
        return ""
    return cause


def merge(rows: list[tuple]) -> list[list[tuple]]:
    """Rows of the same claim made twice (same family labels, same printed digits and the
    same value of ours, up to sign, same category) grouped together, in first order."""
    groups: list[list[tuple]] = []
    index: dict = {}
    for row in rows:
        rec = row[2]
        labels = _labels(rec["quantity"])
        paper = rec["paper"].strip().lstrip("-")
        key = None
        if labels and "." in paper and len(paper.replace(".", "").lstrip("0")) >= 3:
            key = (labels, paper, str(rec["ours"]).lstrip("-"), category_of(rec))
        if key is not None and key in index:
            index[key].append(row)
        else:
            groups.append([row])
            if key is not None:
                index[key] = groups[-1]
    return groups


def _link(path: Path, anchor: str, text: str) -> str:
    return f"[{text}]({path.name}{'#' + anchor if anchor else ''})"


def render() -> str:
    chapters = [(p, *claims_of(p)) for p in toc_notebooks()]
    rows = [(p, title, c) for p, title, cs in chapters for c in cs]
    groups = merge(rows)
    by_name = {}
    for p, _, c in rows:
        by_name.setdefault(f"{c['section']}, {c['quantity']}", (p, c))
    cats = {k: [g for g in groups if category_of(g[0][2]) == k] for k in CATEGORIES}
    n_merged = len(rows) - len(groups)
    lines = [
        "# Ledger of claims",
        "",
        "Every quantitative claim of the paper that a chapter of this book checks, "
        "collected from the chapters' own comparison records (`rotorlib.core.compare`; the "
        "page is generated by `scripts/make_ledger.py`, nothing in it is typed). A value "
        "the paper prints plainly claims its digits: ours must round to it (tolerance "
        "half a unit in the last digit). A value the paper marks ≈ claims agreement "
        "within the stated tolerance; a bound (≲, ≳) claims an inequality. Each row "
        "links to the section of the chapter that computes it; the disagreements are "
        "discussed in the {doc}`errata`.",
        "",
        f"**{len(groups)} claims** ({len(rows)} comparisons; {n_merged} claims the "
        "paper makes twice are merged into one row).",
        "",
        "| category | claims | meaning |",
        "|---|--:|---|",
    ]
    for k, label in CATEGORIES.items():
        lines.append(f"| {label} | {len(cats[k])} | {MEANING[k]} |")
    # The disagreements first, what is reproduced last.
    order = [k for k in CATEGORIES if k != "reproduced"] + ["reproduced"]
    for k in order:
        label = CATEGORIES[k]
        if not cats[k]:
            continue
        lines += [
            "",
            f"## {label[0].upper() + label[1:]} ({len(cats[k])})",
            "",
            "| claim | paper | ours | cause; tolerance |",
            "|---|--:|--:|---|",
        ]
        for g in cats[k]:
            p, _, c = g[0]
            where = "; ".join(
                dict.fromkeys(
                    f"{pretty(cc['section'])} ({_link(pp, cc['anchor'], 'ch. ' + pp.stem[:2])})"
                    if pp.stem[:2].isdigit()
                    else f"{pretty(cc['section'])} ({_link(pp, cc['anchor'], 'appendix')})"
                    for pp, _, cc in g
                )
            )
            claim = f"{pretty(c['quantity'])} · {where}"
            cause = cause_text(c, k)
            if k == "inherited" and c.get("inherits"):
                src = by_name.get(c["inherits"])
                name = pretty(c["inherits"])
                cause = (
                    f"from {_link(src[0], src[1]['anchor'], name)}"
                    if src
                    else f"from {name}"
                ) + (f"; {cause}" if cause and cause != c["inherits"] else "")
            tol = tolerance_text(c)
            last = "; ".join(
                x for x in (pretty(cause) if k != "inherited" else cause, tol) if x
            )
            if c.get("note"):
                last += f" ({pretty(c['note'])})"
            lines.append(
                f"| {claim} | {pretty(c['paper'])} | {pretty(c['ours'])} | {last} |"
            )
    return "\n".join(lines) + "\n"


def main(argv) -> int:
    text = render()
    if "--check" in argv:
        if not OUT.is_file() or OUT.read_text(encoding="utf-8") != text:
            print("book/ledger.md is not up to date: run python scripts/make_ledger.py")
            return 1
        return 0
    OUT.write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
