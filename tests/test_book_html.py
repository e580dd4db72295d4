"""The built book as a reader sees it, in a headless browser (Debian chromium + Playwright).

For every HTML page of _build/html, served over http on 127.0.0.1:
* it loads without console errors or uncaught exceptions;
* no request leaves 127.0.0.1 (all others are blocked and reported): the HTML
  reads offline, MathJax included;
* its math is typeset (MathJax ``mjx-container`` elements, no ``mjx-merror``)
  when it contains math;
* every ``<img>`` loaded (``naturalWidth > 0``);
* every link to a local page points to an existing file (and anchor);
* no cell shows an error traceback.
Screenshots of two chapters (and of a chapter's launch menu) are written to
_build/screenshots/ (kept as CI artifacts).

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

# ~1-2 s per page in a real browser: the whole module is marked slow.
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]
HTML = Path(os.environ.get("BOOK_HTML", ROOT / "_build" / "html"))  # override for testing
SHOTS = ROOT / "_build" / "screenshots"
CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
IN_CI = os.environ.get("CI", "").lower() == "true"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def _unavailable(reason: str):
    if IN_CI:
        pytest.fail(f"CI=true and {reason}", pytrace=False)
    pytest.skip(reason)


def _pages() -> list[str]:
    if not (HTML / "index.html").is_file():
        return []
    skip = {"_static", "_sources", "_images"}
    return sorted(str(p.relative_to(HTML)) for p in HTML.rglob("*.html") if not skip & set(p.relative_to(HTML).parts))


PAGES = _pages()


@pytest.fixture(scope="module")
def server():
    if not (HTML / "index.html").is_file():
        _unavailable(f"the book is not built ({HTML / 'index.html'} missing; run bash scripts/build_book.sh)")
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
        _unavailable("the playwright Python package is not installed (see environment.txt)")
    profile = tempfile.mkdtemp(prefix="book-chromium-")
    blocked: list[str] = []
    with sync_playwright() as pw:
        context = pw.chromium.launch_persistent_context(
            profile, executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS,
            viewport={"width": 1280, "height": 900}, service_workers="block")

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
        yield context
        context.close()
    shutil.rmtree(profile, ignore_errors=True)


def _local_target(url: str) -> tuple[Path, str]:
    parts = urllib.parse.urlsplit(url)
    path = HTML / urllib.parse.unquote(parts.path).lstrip("/")
    if parts.path.endswith("/") or path.is_dir():
        path = path / "index.html"
    return path, urllib.parse.unquote(parts.fragment)


@functools.lru_cache(maxsize=None)
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
  };
}
"""


@pytest.mark.parametrize("page_path", PAGES or ["<book not built>"])
def test_page(server, browser_context, page_path):
    if page_path not in PAGES:
        _unavailable("the book is not built")
    html = (HTML / page_path).read_text(encoding="utf-8", errors="replace")
    refresh = re.search(r'http-equiv="refresh"\s+content="\d+;\s*url=([^"]+)"', html, re.I)
    if refresh:   # a redirect page (index.html -> book/intro.html): its target must exist
        target = (HTML / page_path).parent / urllib.parse.unquote(refresh.group(1).split("#")[0])
        assert target.is_file(), f"{page_path} redirects to missing {refresh.group(1)}"
        return
    errors: list[str] = []
    page = browser_context.new_page()
    page.set_default_timeout(30_000)
    page.on("console", lambda msg: errors.append(f"console {msg.type}: {msg.text}")
            if msg.type == "error" else None)
    page.on("pageerror", lambda exc: errors.append(f"uncaught exception: {exc}"))
    n_blocked = len(browser_context.blocked)
    try:
        response = page.goto(server + page_path, wait_until="load", timeout=30_000)
        assert response is not None and response.ok, f"{page_path}: HTTP {response and response.status}"
        state = page.evaluate(_PAGE_STATE_JS)
        page.wait_for_timeout(100)   # late console errors
    finally:
        page.close()

    problems = list(errors)
    blocked = browser_context.blocked[n_blocked:]
    if blocked:
        problems.append(f"requests leaving 127.0.0.1 (blocked): {sorted(set(blocked))[:10]}")
    if state["mathSource"] and not state["mathTypeset"]:
        problems.append(f"{state['mathSource']} math elements but nothing typeset by MathJax")
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
            problems.append(f"broken anchor {href} (no id {fragment!r} in {target.relative_to(HTML)})")
    assert not problems, f"{page_path}:\n  " + "\n  ".join(problems)


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
            page.evaluate("async () => { if (window.MathJax && MathJax.startup) await MathJax.startup.promise; }")
            name = Path(chapter).stem
            page.screenshot(path=str(SHOTS / f"{name}.png"), full_page=True)
            # Download (.ipynb) and launch (Binder, Colab) links are in the page's header.
            hrefs = page.eval_on_selector_all("a[href]", "els => els.map(e => e.getAttribute('href'))")
            assert any(h.endswith(f"{name}.ipynb") for h in hrefs), f"{chapter}: no .ipynb download link"
            assert any("mybinder.org" in h for h in hrefs), f"{chapter}: no Binder launch link"
            assert any("colab.research.google.com" in h for h in hrefs), f"{chapter}: no Colab launch link"
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
