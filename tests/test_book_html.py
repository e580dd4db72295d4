"""The built book as a reader sees it, in a headless browser (Debian chromium + Playwright).

For every HTML page of _build/html, served over http on 127.0.0.1:
* it loads without console errors or uncaught exceptions;
* no request leaves 127.0.0.1 (all others are blocked and reported): the HTML
  reads offline, MathJax included;
* its math is typeset (MathJax ``mjx-container`` elements, no ``mjx-merror``)
  when it contains math;
* every ``<img>`` loaded (``naturalWidth > 0``);
* every link to a local page points to an existing file (and anchor);
* no cell shows an error traceback;
* no code block overflows horizontally: every ``pre`` of a code cell's input
  (``.cell_input pre``) and of a code block in the text (``div.highlight pre``
  outside cell outputs) has ``scrollWidth <= clientWidth + 1`` at the test's
  1280 px wide viewport; the failure names each line that does not fit
  (test_code_blocks_fit).
The page as a physicist reads it, at 1280 x 1000 (the test_reader_* tests; each
failure lists every offending element with its section, code cell and sizes):
* no table and no display equation is wider than the text column (the article's
  content box, ~688 px);
* no raw TeX ($, \\command, ^{, _{) in the text outside code and typeset math;
* no family label as plain text (IS^l_1, ISl1, PDb) outside code, and none in math
  without \\mathrm;
* every image has alt text that is not empty, a file name or a hash; every raster
  image has at least 1.5x the pixels it is shown at;
* no project-internal word ("issue", "Must show", NUMERICS.md, ../shared) on a page;
* the bibliography has no placeholder entry (test_bibliography_has_no_placeholders);
* the gallery shows a loaded thumbnail for every panel of the paper's figures, each
  linked to a chapter section (test_gallery_shows_every_panel).
Every chapter (the notebooks ``book/0*`` and ``book/appendix_*`` in _toc.yml)
shows at least one rendered table: a ``<table>`` with a header and a row in the
main content, not a monospace table printed into an output
(test_chapter_shows_table).
Screenshots of two chapters (and of a chapter's launch menu) are written to
_build/screenshots/ (kept as CI artifacts); launch buttons are present exactly when
_config.yml configures them.

Skipped, with the reason, when the book is not built or chromium/playwright is
missing -- except under CI=true, where either is a failure.
Build first: bash scripts/build_book.sh
"""

from __future__ import annotations

import functools
import http.server
import os
import re
import shutil
import tempfile
import threading
import urllib.parse
from pathlib import Path

import pytest
import yaml

# ~1-2 s per page in a real browser: the whole module is marked slow.
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
HTML = Path(
    os.environ.get("BOOK_HTML", ROOT / "_build" / "html")
)  # override for testing
SHOTS = ROOT / "_build" / "screenshots"
CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
IN_CI = os.environ.get("CI", "").lower() == "true"
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def _unavailable(reason: str):
    if IN_CI:
        pytest.fail(f"CI=true and {reason}", pytrace=False)
    pytest.skip(reason)


def _pages() -> list[str]:
    if not (HTML / "index.html").is_file():
        return []
    skip = {"_static", "_sources", "_images"}
    pages = sorted(
        str(p.relative_to(HTML))
        for p in HTML.rglob("*.html")
        if not skip & set(p.relative_to(HTML).parts)
    )
    # The catalogue's family pages are generated from one template
    # (scripts/catalogue_pages.py; their links, tables and figures are checked for
    # every family by tests/test_catalogue_pages.py): the browser visits the first
    # three and the last, not all ~100, which would add minutes to CI.
    fam = [p for p in pages if re.fullmatch(r"book/catalogue/F\d+\.html", p)]
    sample = set(fam[:3] + fam[-1:])
    return [p for p in pages if p not in fam or p in sample]


PAGES = _pages()


@pytest.fixture(scope="module")
def server():
    if not (HTML / "index.html").is_file():
        _unavailable(
            f"the book is not built ({HTML / 'index.html'} missing; run bash scripts/build_book.sh)"
        )
    handler = functools.partial(_QuietHandler, directory=str(HTML))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}/"
    httpd.shutdown()
    httpd.server_close()


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def browser_context():
    if not (Path(CHROMIUM).is_file() and os.access(CHROMIUM, os.X_OK)):
        _unavailable(f"chromium not found at {CHROMIUM} (apt-get install chromium)")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _unavailable(
            "the playwright Python package is not installed (see environment.txt)"
        )
    profile = tempfile.mkdtemp(prefix="book-chromium-")
    blocked: list[str] = []
    with sync_playwright() as pw:
        context = pw.chromium.launch_persistent_context(
            profile,
            executable_path=CHROMIUM,
            headless=True,
            args=CHROMIUM_ARGS,
            viewport={"width": 1280, "height": 1000},
            service_workers="block",
        )

        def guard(route):
            url = route.request.url
            host = urllib.parse.urlsplit(url).hostname
            if url.startswith(("data:", "blob:", "about:")) or host == "127.0.0.1":
                route.continue_()
            else:
                blocked.append(url)
                route.abort()

        context.route("**/*", guard)
        context.blocked = blocked
        context.visits = {}  # page path -> _visit's result (each page is loaded once)
        yield context
        context.close()
    shutil.rmtree(profile, ignore_errors=True)


def _local_target(url: str) -> tuple[Path, str]:
    parts = urllib.parse.urlsplit(url)
    path = HTML / urllib.parse.unquote(parts.path).lstrip("/")
    if parts.path.endswith("/") or path.is_dir():
        path = path / "index.html"
    return path, urllib.parse.unquote(parts.fragment)


@functools.cache
def _ids(path: Path) -> frozenset[str]:
    text = path.read_text(encoding="utf-8", errors="replace")
    return frozenset(re.findall(r'\b(?:id|name)="([^"]+)"', text))


_PAGE_STATE_JS = """
async () => {
  // Math: wait for MathJax 3 to finish typesetting, if the page loaded it.
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    await MathJax.startup.promise;
  }
  // Images: load lazy ones too, then wait for every image to settle.
  const imgs = Array.from(document.images);
  imgs.forEach(img => { img.loading = "eager"; });
  await Promise.all(imgs.map(img => img.complete ? null : new Promise(resolve => {
    img.addEventListener("load", resolve); img.addEventListener("error", resolve);
    setTimeout(resolve, 5000);
  })));
  const article = document.querySelector("article") || document.body;
  return {
    mathSource: article.querySelectorAll(".math, span.math, div.math").length,
    mathTypeset: document.querySelectorAll("mjx-container").length,
    // mjx-merror: TeX errors; red mtext: undefined macros (MathJax "noundefined").
    mathErrors: Array.from(document.querySelectorAll(
        "mjx-merror, mjx-container [data-mjx-error], mjx-container mjx-mtext[style*='color: red']"))
      .map(e => e.getAttribute("data-mjx-error") || e.getAttribute("title")
                || (e.closest("mjx-container").querySelector("mjx-assistive-mml") || e).textContent
                || "TeX error / undefined macro").slice(0, 5),
    badImages: imgs.filter(img => !(img.complete && img.naturalWidth > 0)).map(img => img.currentSrc || img.src),
    nImages: imgs.length,
    links: Array.from(document.querySelectorAll("a[href]")).map(a => a.href),
    tracebacks: document.querySelectorAll(".output.traceback, .output.error, .cell_output .traceback").length,
    code: codeOverflow(article),
    reader: readerChecks(article),
    tables: Array.from(article.querySelectorAll("table"))
      .filter(t => !t.closest("table.highlighttable, mjx-container") && t.rows.length >= 2).length,
    // Plain-text tables printed into outputs (for the failure message only):
    // a rule line of dashes, or at least 3 lines of 3+ columns split by 2+ spaces or '|'.
    printedTables: Array.from(article.querySelectorAll(".cell_output pre")).filter(pre => {
      const lines = pre.textContent.split("\\n").filter(l => l.trim());
      const columnar = lines.filter(l => l.trim().split(/ {2,}|\\s*\\|\\s*/).length >= 3).length;
      return lines.some(l => /^[ |+:=-]*[-=]{3,}[ |+:=-]*$/.test(l)) || columnar >= 3;
    }).length,
  };
}
"""

# Horizontal overflow of code blocks. A block overflows when its scrollWidth
# exceeds its clientWidth by more than 1 px (the criterion); the lines to blame
# are found by measuring each line's right edge (a DOM Range over its text)
# against the block's content box. Cell outputs are not code and not checked.
_CODE_OVERFLOW_JS = """
function codeOverflow(article) {
  // Collapsed cells (hide-input, hide-output) are measured as a reader who opens them sees them.
  article.querySelectorAll("details").forEach(d => { d.open = true; });
  const inCell = Array.from(article.querySelectorAll(".cell_input pre"));
  const inText = Array.from(article.querySelectorAll("div.highlight pre"))
    .filter(pre => !pre.closest(".cell_output") && !pre.closest(".cell_input"));
  const cells = Array.from(article.querySelectorAll("div.cell"));
  const result = {blocks: inCell.length + inText.length, overflowing: []};
  for (const pre of inCell.concat(inText)) {
    if (pre.scrollWidth <= pre.clientWidth + 1) continue;
    const style = getComputedStyle(pre);
    const padL = parseFloat(style.paddingLeft), padR = parseFloat(style.paddingRight);
    const box = pre.getBoundingClientRect();
    const left = box.left + pre.clientLeft + padL - pre.scrollLeft;
    const avail = pre.clientWidth - padL - padR;
    // text nodes with their offsets in pre.textContent
    const nodes = [];
    const walker = document.createTreeWalker(pre, NodeFilter.SHOW_TEXT);
    let node, total = 0;
    while ((node = walker.nextNode())) { nodes.push([node, total]); total += node.data.length; }
    const at = off => {
      for (let i = nodes.length - 1; i >= 0; i--) {
        if (nodes[i][1] <= off) return [nodes[i][0], Math.min(off - nodes[i][1], nodes[i][0].data.length)];
      }
      return [pre, 0];
    };
    const text = pre.textContent.replace(/\\n$/, "");
    const lines = [];
    let start = 0, widest = null;
    text.split("\\n").forEach((line, i) => {
      if (line.length) {
        const range = document.createRange();
        range.setStart(...at(start));
        range.setEnd(...at(start + line.length));
        const right = range.getBoundingClientRect().right - left;
        const entry = {line: i + 1, chars: line.length, px: Math.round(right), text: line};
        if (right > avail + 1) lines.push(entry);
        if (!widest || right > widest.px) widest = entry;
      }
      start += line.length + 1;
    });
    const cell = pre.closest("div.cell");
    result.overflowing.push({
      where: cell ? `code cell ${cells.indexOf(cell) + 1}` : "code block in the text",
      scrollWidth: pre.scrollWidth, clientWidth: pre.clientWidth, avail: Math.round(avail),
      lines: lines.length ? lines : (widest ? [widest] : []),
    });
  }
  return result;
}
"""
# What a reader sees (the checks of test_reader_*): measured after codeOverflow has
# opened every collapsed cell. The text column is the article's content box.
_READER_JS = r"""
function readerChecks(article) {
  const colEl = document.querySelector("article.bd-article") || article;
  const cs = getComputedStyle(colEl);
  const box = colEl.getBoundingClientRect();
  const colLeft = box.left + parseFloat(cs.paddingLeft);
  const colRight = box.right - parseFloat(cs.paddingRight);
  const colWidth = Math.round(colRight - colLeft);
  const clip = (t, n) => { t = t.replace(/\s+/g, " ").trim(); return t.length > n ? t.slice(0, n - 3) + "..." : t; };
  const where = el => {
    const sec = el.closest("section[id]");
    const cell = el.closest("div.cell");
    const cells = Array.from(article.querySelectorAll("div.cell"));
    return (sec ? "section #" + sec.id : "top") + (cell ? `, code cell ${cells.indexOf(cell) + 1}` : "");
  };
  // Tables wider than the column (or scrolling inside their wrapper).
  const tables = [];
  Array.from(article.querySelectorAll("table")).forEach((t, i) => {
    if (t.closest("table.highlighttable, mjx-container, .linenodiv")) return;
    const r = t.getBoundingClientRect();
    if (!r.width) return;
    const wrap = t.parentElement;
    const scrolls = wrap && wrap.scrollWidth > wrap.clientWidth + 1 && getComputedStyle(wrap).overflowX !== "visible";
    const visibleRight = scrolls ? Math.min(colRight, wrap.getBoundingClientRect().right) : colRight;
    if (r.right <= colRight + 1 && !scrolls) return;
    const row = t.rows[0];
    const heads = row ? Array.from(row.cells).map(c => clip(c.textContent, 24)) : [];
    const cut = row ? Array.from(row.cells).filter(c => c.getBoundingClientRect().right > visibleRight + 1)
      .map(c => clip(c.textContent, 24)) : [];
    tables.push({where: where(t), index: i + 1, width: Math.round(r.width), scrollWidth: wrap ? wrap.scrollWidth : 0,
                 column: colWidth, rows: t.rows.length, header: heads, cut: cut});
  });
  // Display equations wider than the column.
  const equations = [];
  const tex = new Map();
  const mathLabels = [];
  const doc = window.MathJax && MathJax.startup && MathJax.startup.document;
  if (doc && doc.math) {
    for (const item of doc.math) {
      const root = item.typesetRoot;
      if (!root) continue;
      tex.set(root, item.math);
      if (/(?<!\\mathrm\{|\\rm\s?|\\text\{|\\operatorname\{)\b(IS|PD)\s*\^/.test(item.math)) {
        mathLabels.push({where: where(root), tex: clip(item.math, 90)});
      }
      if (!item.display || !article.contains(root)) continue;
      const inner = root.querySelector("mjx-math") || root;
      const r = inner.getBoundingClientRect();
      const scrolls = root.scrollWidth > root.clientWidth + 1;
      if (r.right > colRight + 1 || r.left < colLeft - 1 || scrolls) {
        equations.push({where: where(root), width: Math.round(r.width), column: colWidth,
                        tex: clip(item.math, 90)});
      }
    }
  }
  // Text a reader reads (not code, not typeset math): raw TeX and plain-text family labels.
  const skip = "pre, code, kbd, samp, script, style, mjx-container, .MathJax, .highlight, .cell_input, .headerlink, .sig, .linenos, svg";
  const rawTex = [], plainLabels = [];
  const walker = document.createTreeWalker(article, NodeFilter.SHOW_TEXT);
  let node;
  const RAW = /\$|\\[A-Za-z]+|[\^_]\{/g;
  const LABEL = /\b(?:IS|PD)\s*\^\s*\{?(?:l|r|ℓ|b|\\ell)(?![A-Za-z])|\b(?:IS|PD)[lr]\d+\b|\bPDb\b/g;
  while ((node = walker.nextNode())) {
    const el = node.parentElement;
    if (!el || el.closest(skip)) continue;
    const text = node.data;
    for (const [re, out] of [[RAW, rawTex], [LABEL, plainLabels]]) {
      re.lastIndex = 0;
      let m;
      while ((m = re.exec(text))) {
        out.push({where: where(el), match: m[0],
                  context: clip(text.slice(Math.max(0, m.index - 40), m.index + m[0].length + 40), 100)});
      }
    }
  }
  // Images: alt text and resolution (raster images need 1.5x the pixels shown).
  // (Sphinx's and the theme's own icons under _static/ are not figures.)
  const images = Array.from(article.querySelectorAll("img"))
    .filter(img => !/\/_static\//.test(img.currentSrc || img.src)).map(img => {
    const r = img.getBoundingClientRect();
    const src = img.currentSrc || img.src;
    return {where: where(img), src: src.startsWith("data:") ? src.slice(0, 30) + "..." : src.split("/").pop(),
            alt: img.getAttribute("alt"), natural: [img.naturalWidth, img.naturalHeight],
            shown: [Math.round(r.width), Math.round(r.height)],
            raster: !/(\.svg(\?|#|$))|^data:image\/svg/i.test(src)};
  });
  return {column: colWidth, tables, equations, rawTex, plainLabels, mathLabels, images,
          text: article.innerText};
}
"""
_PAGE_STATE_JS = _PAGE_STATE_JS.replace(
    "async () => {", "async () => {\n" + _CODE_OVERFLOW_JS + _READER_JS, 1
)


def _visit(server, context, page_path: str) -> dict:
    """Load ``page_path`` once per test session; what the page showed and did.

    Returns ``{"redirect": target or None, "errors": [...], "blocked": [...],
    "state": _PAGE_STATE_JS's result or None}``; later calls reuse it.
    """
    visits = context.visits
    if page_path in visits:
        return visits[page_path]
    html = (HTML / page_path).read_text(encoding="utf-8", errors="replace")
    refresh = re.search(
        r'http-equiv="refresh"\s+content="\d+;\s*url=([^"]+)"', html, re.I
    )
    if refresh:  # a redirect page (index.html -> book/intro.html)
        visits[page_path] = {
            "redirect": refresh.group(1),
            "errors": [],
            "blocked": [],
            "state": None,
        }
        return visits[page_path]
    errors: list[str] = []
    page = context.new_page()
    page.set_default_timeout(30_000)
    page.on(
        "console",
        lambda msg: (
            errors.append(f"console {msg.type}: {msg.text}")
            if msg.type == "error"
            else None
        ),
    )
    page.on("pageerror", lambda exc: errors.append(f"uncaught exception: {exc}"))
    n_blocked = len(context.blocked)
    try:
        response = page.goto(server + page_path, wait_until="load", timeout=30_000)
        assert response is not None and response.ok, (
            f"{page_path}: HTTP {response and response.status}"
        )
        page.evaluate(
            "async () => { await document.fonts.ready; }"
        )  # code widths need the final font
        state = page.evaluate(_PAGE_STATE_JS)
        page.wait_for_timeout(100)  # late console errors
    finally:
        page.close()
    visits[page_path] = {
        "redirect": None,
        "errors": errors,
        "blocked": context.blocked[n_blocked:],
        "state": state,
    }
    return visits[page_path]


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_page(server, browser_context, page_path):
    if page_path not in PAGES:
        _unavailable("the book is not built")
    visit = _visit(server, browser_context, page_path)
    if visit[
        "redirect"
    ]:  # a redirect page (index.html -> book/intro.html): its target must exist
        target = (HTML / page_path).parent / urllib.parse.unquote(
            visit["redirect"].split("#")[0]
        )
        assert target.is_file(), f"{page_path} redirects to missing {visit['redirect']}"
        return
    state = visit["state"]
    problems = list(visit["errors"])
    blocked = visit["blocked"]
    if blocked:
        problems.append(
            f"requests leaving 127.0.0.1 (blocked): {sorted(set(blocked))[:10]}"
        )
    if state["mathSource"] and not state["mathTypeset"]:
        problems.append(
            f"{state['mathSource']} math elements but nothing typeset by MathJax"
        )
    if state["mathErrors"]:
        problems.append(f"MathJax errors: {state['mathErrors']}")
    if state["badImages"]:
        problems.append(f"images that did not load: {state['badImages']}")
    if state["tracebacks"]:
        problems.append(f"{state['tracebacks']} error/traceback outputs shown")
    for href in sorted(set(state["links"])):
        parts = urllib.parse.urlsplit(href)
        if parts.hostname != "127.0.0.1":
            continue
        target, fragment = _local_target(href)
        if not target.is_file():
            problems.append(f"broken link {href} -> {target.relative_to(HTML)} missing")
        elif fragment and target.suffix == ".html" and fragment not in _ids(target):
            problems.append(
                f"broken anchor {href} (no id {fragment!r} in {target.relative_to(HTML)})"
            )
    assert not problems, f"{page_path}:\n  " + "\n  ".join(problems)


def _clip(text: str, n: int = 100) -> str:
    return text if len(text) <= n else text[: n - 3] + "..."


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_code_blocks_fit(server, browser_context, page_path):
    """No code block scrolls sideways: a reader sees every line of code whole."""
    if page_path not in PAGES:
        _unavailable("the book is not built")
    visit = _visit(server, browser_context, page_path)
    if visit["redirect"]:
        return
    code = visit["state"]["code"]
    if not code["overflowing"]:
        return
    n_lines = sum(len(b["lines"]) for b in code["overflowing"])
    msg = [
        f"{page_path}: {len(code['overflowing'])} of {code['blocks']} code blocks overflow "
        f"horizontally ({n_lines} lines too wide):"
    ]
    for b in code["overflowing"]:
        msg.append(
            f"  {b['where']}: scrollWidth {b['scrollWidth']} > clientWidth {b['clientWidth']} + 1 "
            f"(room for {b['avail']} px of text)"
        )
        for ln in b["lines"]:
            msg.append(
                f"    line {ln['line']} ({ln['chars']} chars, {ln['px']} px): {_clip(ln['text'])!r}"
            )
    pytest.fail("\n".join(msg), pytrace=False)


# --------------------------------------------------------------------------------------
# The page as a physicist reads it (one test per kind of fault, each failure lists every
# offending element with where it is: the page, its section, the code cell, sizes).

#: Words of the workshop that must not reach a reader. "issue" is allowed only after
#: the name of another project ("scipy issue 8480").
INTERNAL = [
    re.compile(r"\bMust show\b"),
    re.compile(r"NUMERICS\.md"),
    re.compile(r"\.\./shared\b"),
    re.compile(
        r"(?<!scipy )(?<!SciPy )(?<!numpy )(?<!MyST-NB )(?<!GitHub )(?<!matplotlib )"
        r"(?<!heyoka )(?<!mpmath )(?<!Sphinx )\bissues?\b",
        re.IGNORECASE,
    ),
]
#: A file name or hash used as alt text (myst-nb's default for an output image).
HASH_ALT = re.compile(r"^([0-9a-f]{16,}|.*\.(png|svg|jpe?g|gif))$", re.IGNORECASE)
PLACEHOLDER_BIB = re.compile(
    r"Unidentified reference|Placeholder|not verified|Identified from", re.IGNORECASE
)


def _reader(server, browser_context, page_path):
    if page_path not in PAGES:
        _unavailable("the book is not built")
    visit = _visit(server, browser_context, page_path)
    if visit["redirect"]:
        pytest.skip("a redirect page")
    return visit["state"]["reader"]


def _report(page_path, what, items, fmt):
    if items:
        pytest.fail(
            f"{page_path}: {len(items)} {what}:\n  "
            + "\n  ".join(fmt(x) for x in items),
            pytrace=False,
        )


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_reader_tables_fit(server, browser_context, page_path):
    """Every table fits the text column at 1280 px: the verdict column is in view."""
    r = _reader(server, browser_context, page_path)
    _report(
        page_path,
        f"tables wider than the {r['column']} px text column",
        r["tables"],
        lambda t: (
            f"table {t['index']} ({t['where']}, {t['rows']} rows): {t['width']} px"
            f" (scrolls to {t['scrollWidth']} px); header {t['header']}; cut off: {t['cut']}"
        ),
    )


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_reader_equations_fit(server, browser_context, page_path):
    """Every display equation fits the text column (long ones are broken over lines)."""
    r = _reader(server, browser_context, page_path)
    _report(
        page_path,
        f"display equations wider than the {r['column']} px text column",
        r["equations"],
        lambda e: f"{e['where']}: {e['width']} px: {e['tex']!r}",
    )


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_reader_no_raw_tex(server, browser_context, page_path):
    """No unrendered $ or TeX (\\command, ^{, _{) in the text outside code and math."""
    r = _reader(server, browser_context, page_path)
    _report(
        page_path,
        "raw TeX fragments in the text",
        r["rawTex"],
        lambda x: f"{x['where']}: {x['match']!r} in {x['context']!r}",
    )


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_reader_family_labels_typeset(server, browser_context, page_path):
    """Family labels are typeset ($\\mathrm{IS}^\\ell_1$), never plain text (IS^l_1, ISl1)
    outside code, nor italic letters in math ($IS^l_1$)."""
    r = _reader(server, browser_context, page_path)
    items = [dict(x, kind="plain text") for x in r["plainLabels"]] + [
        dict(x, kind="math without \\mathrm", match=x["tex"], context=x["tex"])
        for x in r["mathLabels"]
    ]
    _report(
        page_path,
        "family labels not typeset",
        items,
        lambda x: f"{x['where']} ({x['kind']}): {x['match']!r} in {x['context']!r}",
    )


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_reader_image_alt_text(server, browser_context, page_path):
    """Every image has alt text that says what it shows, not a file name or hash."""
    r = _reader(server, browser_context, page_path)
    bad = [
        i
        for i in r["images"]
        if not (i["alt"] or "").strip() or HASH_ALT.match(i["alt"])
    ]
    _report(
        page_path,
        "images with empty or file-name alt text",
        bad,
        lambda i: (
            f"{i['where']}: {i['src']} alt={i['alt']!r} ({i['shown'][0]}x{i['shown'][1]} px)"
        ),
    )


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_reader_image_resolution(server, browser_context, page_path):
    """Raster images carry at least 1.5x the pixels they are shown at (SVG is exempt)."""
    r = _reader(server, browser_context, page_path)
    bad = [
        i
        for i in r["images"]
        if i["raster"] and i["shown"][0] > 0 and i["natural"][0] < 1.5 * i["shown"][0]
    ]
    _report(
        page_path,
        "raster images with fewer than 1.5x the pixels shown",
        bad,
        lambda i: (
            f"{i['where']}: {i['src']} is {i['natural'][0]}x{i['natural'][1]} px,"
            f" shown {i['shown'][0]}x{i['shown'][1]} px"
            f" ({i['natural'][0] / i['shown'][0]:.2f}x)"
        ),
    )


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_reader_no_internal_words(server, browser_context, page_path):
    """No word of the workshop ("issue", "Must show", NUMERICS.md, ../shared) on a page,
    code cells included."""
    r = _reader(server, browser_context, page_path)
    hits = []
    for n, line in enumerate(r["text"].splitlines(), 1):
        for pattern in INTERNAL:
            for m in pattern.finditer(line):
                a = max(0, m.start() - 50)
                hits.append((n, m.group(0), line[a : m.end() + 50].strip()))
    _report(
        page_path,
        "project-internal words",
        hits,
        lambda h: f"text line {h[0]}: {h[1]!r} in {h[2]!r}",
    )


def test_bibliography_has_no_placeholders(server, browser_context):
    """The rendered bibliography lists real works only."""
    page = "book/bibliography.html"
    if page not in PAGES:
        _unavailable("the book (or its bibliography page) is not built")
    text = _reader(server, browser_context, page)["text"]
    bad = [ln.strip() for ln in text.splitlines() if PLACEHOLDER_BIB.search(ln)]
    _report(page, "placeholder entries", bad, lambda ln: repr(ln[:160]))


def _gallery_panels():
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "make_gallery", ROOT / "scripts" / "make_gallery.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return {(f, mod.LETTERS[i]) for f, n in mod.PANELS.items() for i in range(n)}


_GALLERY_JS = """
() => Array.from(document.querySelectorAll("table.gallery-table tr")).map(tr => {
  const img = tr.querySelector("img");
  const link = tr.querySelector("a[href*='.html']");
  return {text: tr.innerText, img: img ? {ok: img.complete && img.naturalWidth > 0,
          w: Math.round(img.getBoundingClientRect().width), alt: img.alt} : null,
          link: link ? link.getAttribute("href") : null};
})
"""


def test_gallery_shows_every_panel(server, browser_context):
    """The gallery shows a loaded thumbnail for each of the paper's panels, beside the
    figure number, linked to the section of the chapter that draws it."""
    page = "book/gallery.html"
    if page not in PAGES:
        _unavailable("the book (or its gallery page) is not built")
    p = browser_context.new_page()
    try:
        p.goto(server + page, wait_until="load")
        rows = p.evaluate(_GALLERY_JS)
    finally:
        p.close()
    shown, problems = set(), []
    for row in rows:
        m = re.search(r"Fig\. (\d+)(\([a-z]\)(?:(?:–|, )\([a-z]\))*)", row["text"])
        if not m or row["img"] is None:
            continue
        fig, letters = int(m.group(1)), re.findall(r"\(([a-z])\)", m.group(2))
        if "–" in m.group(2):
            letters = [chr(c) for c in range(ord(letters[0]), ord(letters[-1]) + 1)]
        if not row["img"]["ok"]:
            problems.append(f"Fig. {fig}{m.group(2)}: thumbnail did not load")
            continue
        if not (row["link"] and "#" in row["link"]):
            problems.append(f"Fig. {fig}{m.group(2)}: no link to a chapter section")
        shown |= {(fig, x) for x in letters}
    missing = sorted(_gallery_panels() - shown)
    if missing:
        problems.append(
            f"{len(missing)} panels without a thumbnail: "
            + ", ".join(f"{f}({x})" for f, x in missing)
        )
    assert not problems, f"{page}:\n  " + "\n  ".join(problems)


def _toc_chapters() -> list[str]:
    """The chapter notebooks in _toc.yml: book/0* and book/appendix_* entries."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    entries = [str(c["file"]) for c in toc.get("chapters") or [] if "file" in c]
    chapters = [e for e in entries if re.fullmatch(r"book/(0[^/]*|appendix_[^/]*)", e)]
    return [e for e in chapters if (ROOT / f"{e}.ipynb").is_file()]


TOC_CHAPTERS = _toc_chapters()


def test_toc_has_chapters():
    assert len(TOC_CHAPTERS) >= 2, (
        f"_toc.yml names too few chapter notebooks: {TOC_CHAPTERS}"
    )


@pytest.mark.parametrize("chapter", TOC_CHAPTERS)
def test_chapter_shows_table(server, browser_context, chapter):
    """Results are shown as rendered tables (HTML ``<table>``), not plain text in a monospace font."""
    page_path = f"{chapter}.html"
    if not PAGES:
        _unavailable("the book is not built")
    assert page_path in PAGES, f"{chapter} is in _toc.yml but {page_path} was not built"
    state = _visit(server, browser_context, page_path)["state"]
    assert state["tables"] >= 1, (
        f"{page_path}: no rendered table (<table> with a header and a row) in the main content"
        + (
            f"; {state['printedTables']} output(s) print a plain-text table instead"
            if state["printedTables"]
            else ""
        )
    )


def _chapters() -> list[str]:
    """Built notebook chapters (book/NN_*.html), in name order."""
    return [p for p in PAGES if re.match(r"book/\d\d_.*\.html$", p)]


def test_screenshots_and_buttons(server, browser_context):
    """Full-page screenshots of two chapters; the download and launch buttons are there."""
    chapters = _chapters()
    if len(chapters) < 2:
        _unavailable(f"fewer than two chapters built ({chapters})")
    SHOTS.mkdir(parents=True, exist_ok=True)
    for old in SHOTS.glob("*.png"):
        old.unlink()
    page = browser_context.new_page()
    try:
        for chapter in chapters[:2]:
            page.goto(server + chapter, wait_until="load")
            page.evaluate(
                "async () => { if (window.MathJax && MathJax.startup) await MathJax.startup.promise; }"
            )
            name = Path(chapter).stem
            page.screenshot(path=str(SHOTS / f"{name}.png"), full_page=True)
            # Download (.ipynb) and launch (Binder, Colab) links are in the page's header.
            hrefs = page.eval_on_selector_all(
                "a[href]", "els => els.map(e => e.getAttribute('href'))"
            )
            assert any(h.endswith(f"{name}.ipynb") for h in hrefs), (
                f"{chapter}: no .ipynb download link"
            )
            # Launch links exactly when _config.yml configures them (off until the
            # repository is public): a button must not point to a missing repository.
            launch = (
                yaml.safe_load((ROOT / "_config.yml").read_text()).get("launch_buttons")
                or {}
            )
            for key, host in (
                ("binderhub_url", "mybinder.org"),
                ("colab_url", "colab.research.google.com"),
            ):
                present = any(host in h for h in hrefs)
                assert present == bool(launch.get(key)), (
                    f"{chapter}: {host} launch link {'shown' if present else 'missing'}"
                    f" but _config.yml launch_buttons.{key} is {launch.get(key)!r}"
                )
        # The launch menu opened, to show the buttons in a screenshot.
        launch = page.locator(".dropdown-launch-buttons button").first
        if launch.count():
            launch.click()
            page.wait_for_timeout(300)
        page.screenshot(path=str(SHOTS / f"{Path(chapters[1]).stem}_launch_menu.png"))
    finally:
        page.close()
    shots = sorted(p.name for p in SHOTS.glob("*.png"))
    assert len(shots) >= 2, shots
    assert all((SHOTS / s).stat().st_size > 10_000 for s in shots), shots
