"""Local Sphinx extension of the book (``sphinx.local_extensions`` in ``_config.yml``).

1. Offline HTML. Jupyter Book always loads ``sphinx_thebe``, which writes an
   inline ``THEBE_JS_URL = "https://unpkg.com/thebe@..."`` script into every
   page (used only by the "Live code" launch button, which this book does not
   enable). Its
   ``env-before-read-docs`` and ``doctree-resolved`` handlers are disconnected,
   which removes that script and the thebe configuration block. MathJax is
   served from ``_static/mathjax`` by ``sphinx-mathjax-offline``.

2. rotorlib docstrings in the API page (autodoc + numpydoc). They are written
   for ``help()`` as much as for Sphinx, so before numpydoc sees them:

   * ``|E - 4|``-style absolute values (reST would read substitution
     references) get their bars escaped, outside inline literals and tables;
   * section titles inside *module* docstrings ("Precision\\n---------") become
     rubrics, so they neither collide between modules nor enter the page's TOC;
   * family labels in the prose (``IS^l_3``, ``ISl6``, ``PD^b``) are typeset as
     ``:math:`` roles (outside literals, roles, literal blocks and doctest blocks, their
     output lines included).

   And cross-references by short name (``:class:`PeriodicOrbit```) resolve when
   exactly one documented rotorlib object has that name; a front-door name
   (``:func:`rotorlib.transition```, ``rotorlib.Branch``: ``rotorlib.__all__``) resolves
   to the module that defines it.

3. A module constant's value is shown only when ``NAME = value`` fits the 88-column
   code width; a longer one (``FAMILIES``, ``REGISTRY``, a regex) is described by its
   docstring instead.
"""

from __future__ import annotations

import re

from sphinx.application import Sphinx
from sphinx.util.nodes import make_refnode

_THEBE_HANDLERS = {"init_thebe_core", "update_thebe_context"}
_LITERAL = re.compile(r"(``.+?``|`[^`]+`)")
_UNDERLINE = re.compile(r"^\s*([-=~^\"'`#*+])\1{2,}\s*$")
_TABLE_LINE = re.compile(r"^\s*[|+]")
# the border of a reStructuredText simple table ("====  ======  ===")
_SIMPLE_TABLE_BORDER = re.compile(r"^\s*=+(\s+=+)+\s*$")


def _disconnect_thebe(app: Sphinx) -> None:
    for listeners in app.events.listeners.values():
        for listener in list(listeners):
            handler = listener.handler
            if (
                getattr(handler, "__module__", "") == "sphinx_thebe"
                and getattr(handler, "__name__", "") in _THEBE_HANDLERS
            ):
                app.disconnect(listener.id)


def _escape_bars(line: str) -> str:
    if _TABLE_LINE.match(line) or "|" not in line:
        return line
    parts = _LITERAL.split(line)
    for i in range(0, len(parts), 2):  # even = outside literals
        parts[i] = re.sub(r"(?<!\\)\|", r"\\|", parts[i])
    return "".join(parts)


_START_OK = set(" \t-:/'\"<([{")
_END_OK = set(" \t-.,:;!?\\/'\")]}>")


def _typeset_labels(line: str) -> str:
    """Family labels in docstring prose (``IS^l_3``, ``ISl6``, ``PD^b``) as :math:
    roles, outside inline literals and roles (``rotorlib.core.compare.label_tex``)."""
    from rotorlib.core.compare import LABEL_IN_TEXT_RE, label_tex

    if _TABLE_LINE.match(line) or line.lstrip().startswith((">>>", "... ")):
        return line
    parts = _LITERAL.split(line)
    for i in range(0, len(parts), 2):  # even = outside literals and roles
        text, out, pos = parts[i], [], 0
        for m in LABEL_IN_TEXT_RE.finditer(text):
            before = text[m.start() - 1] if m.start() else (" " if i == 0 else "`")
            after = text[m.end()] if m.end() < len(text) else " "
            if before == ":" or after == "`":
                continue  # part of a role or literal we did not split off
            role = f":math:`{label_tex(m.group(0), delimiters=False)}`"
            pre = "" if before in _START_OK else "\\ "
            post = "" if after in _END_OK else "\\ "
            out += [text[pos : m.start()], pre, role, post]
            pos = m.end()
        parts[i] = "".join(out) + text[pos:]
    return "".join(parts)


def _process_docstring(app, what, name, obj, options, lines: list[str]) -> None:
    if not name.startswith("rotorlib"):
        return
    out: list[str] = []
    i = 0
    literal = None  # indentation of the paragraph that opened a literal block (::)
    borders = 0  # border lines of a simple table seen so far (inside while 1 or 2)
    last_column = 0  # where the last column of that table starts
    doctest = False  # in a doctest block (">>>" to a blank line), its output too
    while i < len(lines):
        line = lines[i]
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        indent = len(line) - len(line.lstrip())
        if literal is not None and line.strip() and indent <= literal:
            literal = None
        if line.lstrip().startswith(">>>"):
            doctest = True
        elif not line.strip():
            doctest = False
        if doctest:
            out.append(line)
            i += 1
            continue
        if _SIMPLE_TABLE_BORDER.match(line):
            borders = (borders + 1) % 3  # top, under the header, bottom
            last_column = line.rstrip().rfind(" ") + 1
        # a simple table's columns are as wide as its borders: a typeset label would
        # make a cell wider than its column ("Malformed table"), except in the last
        # column, whose text may run past the border
        if literal is None and borders and len(line) > last_column:
            line = line[:last_column] + _typeset_labels(line[last_column:])
        elif literal is None and line.strip() and not borders:
            if line.rstrip().endswith("::"):
                literal = indent
            line = _typeset_labels(line)
        if (
            what == "module"
            and line.strip()
            and _UNDERLINE.match(nxt)
            and len(nxt.strip()) >= len(line.strip())
            and not _UNDERLINE.match(line)
        ):
            indent = line[: len(line) - len(line.lstrip())]
            out += [f"{indent}.. rubric:: {_escape_bars(line.strip())}", ""]
            i += 2
            continue
        out.append(_escape_bars(line))
        i += 1
    lines[:] = out


def _resolve_short_names(app, env, node, contnode):
    if node.get("refdomain") != "py" or node.get("reftype") not in {
        "class",
        "func",
        "meth",
        "attr",
        "obj",
        "data",
        "exc",
        "mod",
        "const",
    }:
        return None
    target = node.get("reftarget", "").lstrip("~.")
    if not target:
        return None
    if target.count(".") == 1 and target.startswith("rotorlib."):
        # a name of the front door (rotorlib.__all__) is documented where it is defined
        import rotorlib

        name = target.split(".")[1]
        if name in rotorlib.__all__:
            module = getattr(getattr(rotorlib, name), "__module__", None)
            target = f"{module or 'rotorlib.api'}.{name}"
    objects = env.get_domain("py").objects
    hits = [
        full
        for full in objects
        if full.startswith("rotorlib")
        and (full == target or full.endswith("." + target))
    ]
    if len(hits) != 1:
        return None
    entry = objects[hits[0]]
    return make_refnode(
        app.builder, node["refdoc"], entry.docname, entry.node_id, contnode, hits[0]
    )


def _short_data_documenter():
    """autodoc's documenter of module constants, showing a constant's value only when
    ``NAME = value`` fits the code column (88 characters); a longer value (a table of
    families, a registry, a compiled regex) is left to the docstring, which says what
    the constant holds."""
    from sphinx.ext.autodoc import DataDocumenter
    from sphinx.util.inspect import object_description

    class ShortDataDocumenter(DataDocumenter):
        def should_suppress_value_header(self) -> bool:
            if super().should_suppress_value_header():
                return True
            try:
                value = object_description(self.object)
            except Exception:
                return False
            return len(self.objpath[-1]) + 3 + len(value) > 88

    return ShortDataDocumenter


def setup(app: Sphinx) -> dict:
    _disconnect_thebe(app)
    app.add_autodocumenter(_short_data_documenter(), override=True)
    app.connect(
        "autodoc-process-docstring", _process_docstring, priority=400
    )  # before numpydoc (500)
    app.connect("missing-reference", _resolve_short_names)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
