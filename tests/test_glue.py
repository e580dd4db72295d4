"""Numbers in the book's prose come from the computation (myst-nb glue), and the bibliography is real.

Glue (every notebook in book/):

* every glue role or directive in a Markdown cell ({glue:text}`key:.6f`, {glue}`key`, ```{glue:figure} key)
  names a key that a code cell of the SAME notebook defines with ``glue("key", ...)`` (a literal key, an
  f-string whose pattern matches it, or ``glue(name, ...)`` with ``"key"`` quoted in the code, as in a loop
  over ``("key", value)`` pairs); a glue role in a notebook with no glue call fails;
* the stored (executed) outputs contain that key, so the notebook was re-executed after the glue call was
  added (otherwise the book build fails on an unknown key);
* a ``:format`` in a glue:text role is a valid Python format specification, and the stored value is a
  number literal (myst-nb cannot format ``np.float64(...)``: glue ``float(x)``).

A Markdown page (book/*.md) has no code cells: a glue role there must name another document's key
(``{glue:text}`01_formulation.ipynb::key:.4f```, myst-nb's cross-document form, the path relative to the page or
``/``-rooted at book/), and that notebook must glue it and store it in its outputs. The roles are parsed as myst-nb
1.4 parses them (``myst_nb/ext/glue/roles.py``): ``{glue:text}`` splits the format off at the LAST colon, so a
cross-document text role needs an explicit format (``doc::key:s``, not ``doc::key``); ``{glue:md}`` and the
directives cannot paste from another document; the stored value must format with the role's format spec
(checked with myst-nb's own ``format_plain_text``).

Bibliography (book/references.bib):

* no entry contains placeholder text ("TODO", "placeholder", "unidentified", "not verified", "identified
  from", ...), except those listed in UNRESOLVED, and that list may only shrink;
* no title or note holds raw TeX ($...$, control words other than BibTeX's accents);
* articles from 1990 on carry a DOI or an arXiv identifier;
* every key cited in the book ({cite}`a,b`) is an entry of references.bib, and every entry is cited.
"""

from __future__ import annotations

import ast
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BOOK = ROOT / "book"
NOTEBOOKS = sorted(
    p for p in BOOK.rglob("*.ipynb") if ".ipynb_checkpoints" not in p.parts
)
PAGES = sorted(p for p in BOOK.glob("*.md"))
BIB = BOOK / "references.bib"

# {glue}`key`, {glue:}`key`, {glue:text}`key:.6f`, {glue:any}`key`, {glue:md}`key`, {glue:math}`key`
GLUE_ROLE = re.compile(r"\{glue(:[a-z]*)?\}`([^`]+)`")
# ```{glue:figure} key   /  :::{glue} key   /  ```{glue:math} key
GLUE_DIRECTIVE = re.compile(r"^[`:]{3,}\{glue(?::[a-z]*)?\}\s+(\S+)", re.MULTILINE)
# glue("key", ...), glue('key', ...), glue(f"key_{i}", ...), myst_nb.glue(...)
GLUE_CALL = re.compile(r"\bglue\(\s*(f?)([\"'])(.*?)\2")


def _cells(nb_path: Path):
    return json.loads(nb_path.read_text(encoding="utf-8"))["cells"]


def _source(cell) -> str:
    src = cell.get("source", "")
    return "".join(src) if isinstance(src, list) else src


def glue_uses(markdown: str) -> list[tuple[str, str, str | None]]:
    """(role or directive, key, format spec or None) of every glue role and directive, parsed as myst-nb does.

    ``{glue:text}`` (and ``{glue:md}``) split the format at the last colon (so ``doc::key`` without a format gives the
    key ``doc:``); ``{glue}``, ``{glue:}``, ``{glue:any}`` take the whole text as the key. A key ``doc::name`` is a
    cross-document reference.
    """
    out = []
    for m in GLUE_ROLE.finditer(markdown):
        role, text = "glue" + (m.group(1) or ""), m.group(2)
        if role in ("glue:text", "glue:md") and ":" in text:
            key, fmt = text.rsplit(":", 1)
            out.append((role, key.strip(), fmt if role == "glue:text" else None))
        else:
            out.append((role, text.strip(), None))
    for m in GLUE_DIRECTIVE.finditer(markdown):
        out.append(("directive", m.group(1).strip(), None))
    return out


def used_keys(markdown: str) -> list[tuple[str, str | None]]:
    """(key, format spec or None) of every glue role and directive in a Markdown text."""
    return [(key, fmt) for _, key, fmt in glue_uses(markdown)]


def defined_patterns(code: str) -> list[re.Pattern]:
    """Regular expressions matching the keys glued by a code cell (an f-string's fields match anything)."""
    pats = []
    for m in GLUE_CALL.finditer(code):
        is_f, key = m.group(1), m.group(3)
        if is_f:
            parts = re.split(r"\{[^{}]*\}", key)
            pats.append(re.compile("^" + ".+".join(re.escape(p) for p in parts) + "$"))
        else:
            pats.append(re.compile("^" + re.escape(key) + "$"))
    return pats


# glue(name, ...) with a variable name (e.g. in a loop over ("key", value) pairs)
GLUE_DYNAMIC = re.compile(r"\bglue\(\s*[A-Za-z_]\w*\s*,")


def key_is_defined(key: str, code_cells: list[str]) -> bool:
    """A literal (or f-string) glue("key", ...) call, or a glue(name, ...) call with ``"key"`` quoted in the code."""
    if any(p.match(key) for src in code_cells for p in defined_patterns(src)):
        return True
    dynamic = any(GLUE_DYNAMIC.search(src) for src in code_cells)
    quoted = re.compile(r"([\"'])" + re.escape(key) + r"\1")
    return dynamic and any(quoted.search(src) for src in code_cells)


def stored_keys(cells) -> set[str]:
    """Keys recorded in the stored outputs (myst-nb writes them in the output metadata under 'scrapbook')."""
    keys = set()
    for cell in cells:
        for out in cell.get("outputs", []) or []:
            name = ((out.get("metadata") or {}).get("scrapbook") or {}).get("name")
            if name:
                keys.add(name)
    return keys


@pytest.mark.parametrize("nb_path", NOTEBOOKS, ids=lambda p: p.name)
def test_every_glue_key_is_defined_in_the_same_notebook(nb_path):
    cells = _cells(nb_path)
    used = [
        (k, f, i)
        for i, c in enumerate(cells)
        if c["cell_type"] == "markdown"
        for k, f in used_keys(_source(c))
    ]
    bad_cross = [
        b
        for c in cells
        if c["cell_type"] == "markdown"
        for b in check_cross_document_uses(nb_path.parent, _source(c), local_ok=True)
    ]
    assert not bad_cross, (
        f"{nb_path.name}: cross-document glue keys not defined by an executed notebook: {bad_cross}"
    )
    used = [u for u in used if "::" not in u[0]]
    code = [_source(c) for c in cells if c["cell_type"] == "code"]
    if used:
        assert any(re.search(r"\bglue\(", src) for src in code), (
            f"{nb_path.name}: glue roles {sorted({k for k, _, _ in used})} but no glue(...) call"
        )
    undefined = sorted({(k, i) for k, _, i in used if not key_is_defined(k, code)})
    assert not undefined, (
        f"{nb_path.name}: glue keys used in Markdown but never glued (key, cell): {undefined}"
    )
    stored = stored_keys(cells)
    not_stored = sorted({k for k, _, _ in used if k not in stored})
    assert not not_stored, (
        f"{nb_path.name}: glue keys not in the stored outputs (re-execute the notebook): "
        f"{not_stored}"
    )


def stored_text(cells) -> dict[str, str]:
    """The stored text/plain representation of every glued key."""
    out = {}
    for cell in cells:
        for o in cell.get("outputs", []) or []:
            meta = (o.get("metadata") or {}).get("scrapbook") or {}
            if meta.get("name"):
                data = o.get("data") or {}
                out[meta["name"]] = data.get(
                    meta.get("mime_prefix", "") + "text/plain", data.get("text/plain")
                )
    return out


@pytest.mark.parametrize("nb_path", NOTEBOOKS, ids=lambda p: p.name)
def test_glue_formats_are_valid(nb_path):
    """A numeric format (``:.6f``) needs a stored value that myst-nb can read back as a number.

    myst-nb formats ``ast.literal_eval(text/plain)``: ``np.float64(1.5)`` is not a literal and fails the build,
    so glue ``float(x)``, not a numpy scalar.
    """
    cells = _cells(nb_path)
    texts = stored_text(cells)
    bad = []
    for c in cells:
        if c["cell_type"] != "markdown":
            continue
        for key, fmt in used_keys(_source(c)):
            if fmt is None or "::" in key:
                continue
            try:
                format(1.2345, fmt)
            except ValueError:
                bad.append((key, fmt, "invalid format"))
                continue
            if fmt[-1] in "eEfFgGn%bcdoxX" and key in texts:
                try:
                    value = ast.literal_eval(texts[key] or "")
                except (ValueError, SyntaxError):
                    value = None
                if isinstance(value, bool) or not isinstance(value, (int, float)):
                    bad.append(
                        (
                            key,
                            fmt,
                            f"stored value {texts[key]!r} is not a number literal",
                        )
                    )
    assert not bad, f"{nb_path.name}: {bad}"


def cross_document_target(base: Path, key: str) -> tuple[Path | None, str]:
    """The notebook and key named by ``doc::name`` (myst-nb splits at the first ``::``; ``doc`` is relative to base,
    or to book/ if it starts with ``/``, as Sphinx's ``relfn2path`` resolves it); (None, key) if not cross-document."""
    doc, sep, name = key.partition("::")
    if not sep:
        return None, key
    target = (BOOK / doc.lstrip("/")) if doc.startswith("/") else (base / doc)
    if target.suffix == "":
        target = target.with_suffix(".ipynb")
    return target, name


def cross_document_key_ok(base: Path, key: str) -> bool:
    """``doc::name`` names a notebook (relative to base) that glues ``name`` and stores it."""
    target, name = cross_document_target(base, key)
    if target is None or target.suffix != ".ipynb" or not target.is_file():
        return False
    cells = _cells(target)
    return key_is_defined(
        name, [_source(c) for c in cells if c["cell_type"] == "code"]
    ) and name in stored_keys(cells)


def cross_document_format_error(base: Path, key: str, fmt: str | None) -> str | None:
    """Why myst-nb would fail to paste ``{glue:text}`key:fmt``` from the notebook's stored value (None if it works)."""
    from myst_nb.core.variables import format_plain_text

    target, name = cross_document_target(base, key)
    text = stored_text(_cells(target)).get(name)
    if text is None:
        return "no text/plain stored"
    try:
        format_plain_text(text, fmt if fmt is not None else "s")
    except (ValueError, TypeError) as exc:
        return f"stored value {text!r} does not format with {fmt!r}: {exc}"
    return None


def check_cross_document_uses(base: Path, markdown: str, local_ok: bool) -> list[str]:
    """Problems with the glue roles of a Markdown text that paste from another notebook (or, for a page, locally)."""
    bad = []
    for role, key, fmt in glue_uses(markdown):
        if "::" not in key:
            if not local_ok:
                hint = (
                    " (a glue:text role doc::key needs a format: doc::key:s)"
                    if key.endswith(":")
                    else ""
                )
                bad.append(f"{key!r}: not a doc::key reference{hint}")
            continue
        if role not in ("glue", "glue:", "glue:any", "glue:text"):
            bad.append(f"{key!r}: myst-nb's {role} cannot paste from another document")
        elif not cross_document_key_ok(base, key):
            bad.append(
                f"{key!r}: not glued by, or not stored in, the named notebook (re-execute it)"
            )
        elif role == "glue:text" and (
            err := cross_document_format_error(base, key, fmt)
        ):
            bad.append(f"{key!r}: {err}")
    return bad


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_markdown_pages_glue_only_from_notebooks(page):
    bad = check_cross_document_uses(
        page.parent, page.read_text(encoding="utf-8"), local_ok=False
    )
    assert not bad, (
        f"{page.name}: glue roles that no executed notebook can fill (a page must use doc::key): {bad}"
    )


# --- the parser itself -------------------------------------------------------------------------------------


def test_parser_finds_roles_directives_and_calls():
    md = "E = {glue:text}`E_pd:.6f` and {glue}`tau` and {glue:}`x`\n```{glue:figure} fig_a\n:name: f\n```\n"
    assert used_keys(md) == [
        ("E_pd", ".6f"),
        ("tau", None),
        ("x", None),
        ("fig_a", None),
    ]
    code = 'glue("E_pd", 1.0, display=False)\nglue(\'tau\', t)\nfor i in r:\n    glue(f"x_{i}_y", v, display=False)\n'
    pats = defined_patterns(code)
    assert any(p.match("E_pd") for p in pats) and any(p.match("tau") for p in pats)
    assert any(p.match("x_3_y") for p in pats) and not any(
        p.match("x_3_z") for p in pats
    )
    assert defined_patterns("print('no glue here')") == []
    loop = 'for key, val in (("a_key", 1.0), ("b_key", x)):\n    glue(key, val, display=False)\n'
    assert (
        key_is_defined("a_key", [loop])
        and key_is_defined("b_key", [loop])
        and not key_is_defined("c_key", [loop])
    )
    assert not key_is_defined("a_key", ['print("a_key")'])
    # cross-document roles, parsed as myst-nb 1.4 parses them
    md = (
        "{glue:text}`03_transitions.ipynb::err_x:.4f` {glue:text}`03_transitions.ipynb::err_v:s` "
        "{glue:text}`03_transitions.ipynb::err_v` {glue}`06_laws.ipynb::k` {glue:md}`a.ipynb::m:commonmark`"
    )
    assert glue_uses(md) == [
        ("glue:text", "03_transitions.ipynb::err_x", ".4f"),
        ("glue:text", "03_transitions.ipynb::err_v", "s"),
        ("glue:text", "03_transitions.ipynb:", "err_v"),
        ("glue", "06_laws.ipynb::k", None),
        ("glue:md", "a.ipynb::m", None),
    ]
    assert cross_document_target(BOOK, "03_transitions::k") == (
        BOOK / "03_transitions.ipynb",
        "k",
    )
    assert cross_document_target(BOOK / "sub", "/03_transitions.ipynb::k") == (
        BOOK / "03_transitions.ipynb",
        "k",
    )
    assert cross_document_target(BOOK, "plain_key") == (None, "plain_key")
    bad = check_cross_document_uses(BOOK, md, local_ok=False)
    assert any("needs a format" in b for b in bad) and any(
        "cannot paste from another document" in b for b in bad
    )
    assert any("06_laws.ipynb::k" in b and "not glued" in b for b in bad)


def test_format_check_uses_myst_nb_formatting():
    """The cross-document format check fails exactly where myst-nb's formatting fails."""
    from myst_nb.core.variables import format_plain_text

    assert (
        format_plain_text("7.634", ".4f") == "7.6340"
        and format_plain_text("-36", "d") == "-36"
    )
    assert format_plain_text("'last digit off by +1'", "s") == "last digit off by +1"
    with pytest.raises(ValueError):
        format_plain_text("np.float64(1.5)", ".4f")


# --- bibliography -------------------------------------------------------------------------------------------

PLACEHOLDER = re.compile(
    r"\b(TODO|TBD|FIXME|XXX|placeholder|unidentified|unknown|co-?workers|"
    r"not verified|details not verified|title and year not verified|to be checked|"
    r"identified from)\b|\?\?",
    re.IGNORECASE,
)
#: Entries that are still placeholders. The set may only shrink (it is empty): the test
#: fails if an entry listed here is resolved or deleted but left here, or if any other
#: entry is a placeholder.
UNRESOLVED: set[str] = set()
ENTRY = re.compile(r"^@(\w+)\s*\{\s*([^,\s]+)\s*,(.*?)^\}", re.MULTILINE | re.DOTALL)
CITE = re.compile(r"\{cite(?::[a-z]+)?\}`([^`]+)`")
#: TeX that a bibliography style prints raw: mathematics, control words other than
#: the accent and brace forms BibTeX understands.
RAW_TEX = re.compile(r"\$|\\(?![\'`\"^~=.vuHcdbtr]\{?)[A-Za-z]+")


def bib_entries() -> dict[str, tuple[str, str]]:
    return {
        m.group(2): (m.group(1).lower(), m.group(3))
        for m in ENTRY.finditer(BIB.read_text(encoding="utf-8"))
    }


def _field(body: str, name: str) -> str | None:
    m = re.search(rf"^\s*{name}\s*=\s*\{{(.*)\}},?\s*$", body, re.MULTILINE)
    return m.group(1) if m else None


def cited_keys() -> set[str]:
    """Every key a page of the book cites: {cite}`a,b` in the notebooks' Markdown cells
    and in book/*.md (inline code, as in `` {cite}`key` ``, does not count)."""
    cited = set()
    texts = [
        _source(c) for p in NOTEBOOKS for c in _cells(p) if c["cell_type"] == "markdown"
    ]
    texts += [p.read_text(encoding="utf-8") for p in PAGES]
    for text in texts:
        text = re.sub(r"``.*?``", "", text)
        for m in CITE.finditer(text):
            cited |= {k.strip() for k in m.group(1).split(",")}
    return cited


def test_bibliography_has_no_placeholders():
    entries = bib_entries()
    assert len(entries) >= 5, f"only {len(entries)} entries parsed from references.bib"
    bad = {
        key: PLACEHOLDER.search(body).group(0)
        for key, (_, body) in entries.items()
        if PLACEHOLDER.search(body)
    }
    unexpected = {k: v for k, v in bad.items() if k not in UNRESOLVED}
    assert not unexpected, f"placeholder text in references.bib: {unexpected}"
    resolved = sorted(UNRESOLVED - set(bad))
    assert not resolved, (
        f"no longer placeholders, remove from UNRESOLVED in {Path(__file__).name}: {resolved}"
    )
    untitled = [
        key
        for key, (_, body) in entries.items()
        if not re.search(r"^\s*title\s*=", body, re.MULTILINE)
    ]
    assert not untitled, f"entries without a title: {untitled}"
    no_year = [
        key
        for key, (kind, body) in entries.items()
        if kind != "misc" and not re.search(r"^\s*year\s*=", body, re.MULTILINE)
    ]
    assert not no_year, f"entries without a year: {no_year}"


def test_bibliography_has_no_raw_tex():
    """Titles and notes render as text: no $...$ mathematics or TeX control words."""
    raw = {
        (key, name): _field(body, name)
        for key, (_, body) in bib_entries().items()
        for name in ("title", "note", "booktitle", "howpublished")
        if _field(body, name) and RAW_TEX.search(_field(body, name))
    }
    assert not raw, f"raw TeX in references.bib: {raw}"


def test_recent_articles_have_a_doi_or_arxiv_id():
    """Articles from 1990 on carry a DOI or an arXiv identifier."""
    missing = [
        key
        for key, (kind, body) in bib_entries().items()
        if kind == "article"
        and int(_field(body, "year") or 0) >= 1990
        and not (_field(body, "doi") or _field(body, "eprint"))
    ]
    assert not missing, f"articles without doi or eprint: {missing}"


def test_every_entry_is_cited():
    """references.bib lists what the book cites and nothing else."""
    unused = sorted(set(bib_entries()) - cited_keys())
    assert not unused, f"entries no page cites (remove them): {unused}"


def test_every_cited_key_is_in_the_bibliography():
    keys = set(bib_entries())
    cited = cited_keys()
    missing = sorted(cited - keys)
    assert not missing, f"cited but not in references.bib: {missing}"


@pytest.mark.parametrize("nb_path", NOTEBOOKS, ids=lambda p: p.name)
def test_glued_numbers_are_rounded(nb_path):
    """Glue stores values already rounded to their verified digits (rotorlib.core.compare.glue):
    no glued number carries a float64's 16-17 significant digits, whose last ones are the
    machine's round-off and would not reproduce on another CPU."""
    bad = {}
    for key, text in stored_text(_cells(nb_path)).items():
        for m in re.finditer(r"(?<![\w.])[+-]?\d+\.\d+(?:[eE][+-]?\d+)?", text or ""):
            mantissa = re.split("[eE]", m.group(0).lstrip("+-"))[0]
            # trailing zeros of a float's repr are not digits (2.9e14 is "290000000000000.0")
            digits = mantissa.replace(".", "").lstrip("0").rstrip("0")
            if len(digits) in (16, 17):
                bad[key] = text
    assert not bad, f"{nb_path.name}: glued with all float64 digits (round them): {bad}"
