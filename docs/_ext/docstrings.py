"""Read the project's plain-text docstrings as reStructuredText without losing their content.

* The docstrings write absolute values and norms as ``|x|`` and ``|V a + r|``, which
  reStructuredText would read as substitution references.  Before autodoc parses a
  docstring, every ``|`` outside inline literals and interpreted text is escaped, so the bars
  print as written.  (The project's docstrings use no substitutions, line blocks or tables.)
* A module constant's or attribute's docstring is prose (``"[relaxation]: the thesis
  model's static relaxation"``); napoleon would read the text before its first colon as the
  attribute's type.  Such docstrings are kept as written.
* A constant whose value prints longer than :data:`MAX_VALUE` characters (a scene table, a
  registry) shows its type instead of its value in the signature.
"""
from __future__ import annotations

import re

from docutils import nodes
from sphinx import addnodes
from sphinx.application import Sphinx

# inline literals, interpreted text with an optional role, and hyperlink references
_PROTECTED = re.compile(r"(``.+?``|(?::[\w:+-]+:)?`[^`]+`_{0,2})")
MAX_VALUE = 80
_KEPT: dict[str, list[str]] = {}


def escape_bars(line: str) -> str:
    parts = _PROTECTED.split(line)
    for k in range(0, len(parts), 2):
        parts[k] = re.sub(r"(?<!\\)\|", r"\\|", parts[k])
    return "".join(parts)


def before_napoleon(app, what, name, obj, options, lines: list[str]) -> None:
    lines[:] = [escape_bars(line) for line in lines]
    if what in ("data", "attribute"):
        _KEPT[name] = list(lines)


def after_napoleon(app, what, name, obj, options, lines: list[str]) -> None:
    if what in ("data", "attribute") and name in _KEPT:
        lines[:] = _KEPT.pop(name)


def shorten_values(app: Sphinx, doctree: nodes.document) -> None:
    for signature in doctree.findall(addnodes.desc_signature):
        desc = signature.parent
        if desc.get("objtype") not in ("data", "attribute"):
            continue
        for annotation in list(signature.findall(addnodes.desc_annotation)):
            text = annotation.astext()
            if text.lstrip().startswith("=") and len(text) > MAX_VALUE:
                value = text.lstrip()[1:].strip()
                head = re.match(r"[\w.]+(?=\()", value)
                kind = head.group(0) if head else {"{": "dict", "[": "list", "(": "tuple"}.get(
                    value[:1], "…")
                annotation.replace_self(addnodes.desc_annotation(
                    "", "", addnodes.desc_sig_space(), addnodes.desc_sig_punctuation("", "="),
                    addnodes.desc_sig_space(), nodes.Text(f"{kind}(…)" if kind != "…" else "…")))


def setup(app: Sphinx) -> dict:
    app.connect("autodoc-process-docstring", before_napoleon, priority=400)
    app.connect("autodoc-process-docstring", after_napoleon, priority=600)
    app.connect("doctree-read", shorten_values)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
