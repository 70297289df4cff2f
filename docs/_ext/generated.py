"""Pages generated from the code at build time (never copied text).

On ``builder-inited`` this writes, under ``docs/_generated/``:

* ``scene_keys.md``: every scene key, its default, allowed values and meaning, from
  :func:`fsi.scene.reference_markdown` (the table ``fsi scenes --reference`` prints);
* ``outputs.md``: the datasets and attributes of ``result.h5`` with their units, from
  :func:`fsi.io.output.reference_markdown`;
* ``diaphragm_outputs.md``: the diaphragm's stress, strain, topology, envelope, events and
  cycles datasets with their shapes and units, from
  :func:`fsi.analysis.diaphragm.reference_markdown`;
* ``static_table.md``: the columns of the table a static run prints, from
  :func:`fsi.procedures.static.columns_markdown`;
* ``notebooks/*.ipynb``: copies of ``notebooks/*.ipynb``, which MyST-NB executes and renders.

It also checks that every module of the packages has an ``automodule`` on a page of
``docs/api/`` (a module moved or added without a page is a warning).

A file is rewritten only when its text changes, so an unchanged build stays incremental.
A reference that cannot be generated is a Sphinx warning (an error under ``-W``).
"""
from __future__ import annotations

import importlib
import re
import shutil
from pathlib import Path

from sphinx.application import Sphinx
from sphinx.util import logging

logger = logging.getLogger(__name__)

#: (file under docs/_generated, module, function, one-line header)
REFERENCES = (
    ("scene_keys.md", "fsi.scene", "reference_markdown",
     "Generated from `fsi.scene.reference_markdown()` (also printed by "
     "`fsi scenes --reference`)."),
    ("outputs.md", "fsi.io.output", "reference_markdown",
     "Generated from `fsi.io.output.reference_markdown()`."),
    ("diaphragm_outputs.md", "fsi.analysis.diaphragm", "reference_markdown",
     "Generated from `fsi.analysis.diaphragm.reference_markdown()`."),
    ("static_table.md", "fsi.procedures.static", "columns_markdown",
     "Generated from `fsi.procedures.static.columns_markdown()`."),
)


def escape_cell_bars(table: str) -> str:
    """Escape the ``|`` inside table cells (``|u| h / 2``), which Markdown would read as cell
    borders; a border is a bar with blanks (or the row's ends) on both sides."""
    rows = []
    for row in table.split("\n"):
        if row.lstrip().startswith("|") and not re.fullmatch(r"\s*\|([ :-]+\|)+\s*", row):
            chars = []
            for k, ch in enumerate(row):
                before = row[k - 1] if k else " "
                after = row[k + 1] if k + 1 < len(row) else " "
                border = before.isspace() and after.isspace()
                chars.append(ch if ch != "|" or border or before == "\\" else "\\|")
            row = "".join(chars)
        rows.append(row)
    return "\n".join(rows)


def _write_if_changed(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def _copy_if_changed(source: Path, target: Path) -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    if not target.exists() or target.read_bytes() != source.read_bytes():
        shutil.copyfile(source, target)


def generate(app: Sphinx) -> None:
    srcdir = Path(app.srcdir)
    out = srcdir / "_generated"
    for name, module, function, header in REFERENCES:
        try:
            table = escape_cell_bars(getattr(importlib.import_module(module), function)())
        except Exception as error:  # noqa: BLE001 - reported, the build goes on
            logger.warning("cannot generate _generated/%s from %s.%s(): %s",
                           name, module, function, error, type="generated")
            table = f"*(not generated: {module}.{function}() failed)*\n"
        text = f"<!-- {header} Do not edit: rewritten at every build. -->\n\n{table.rstrip()}\n"
        _write_if_changed(out / name, text)

    notebooks = srcdir.parent / "notebooks"
    copies = out / "notebooks"
    wanted = sorted(notebooks.glob("*.ipynb"))
    if not wanted:
        logger.warning("no notebooks found in %s", notebooks, type="generated")
    for source in wanted:
        _copy_if_changed(source, copies / source.name)
    for stale in copies.glob("*.ipynb"):
        if not (notebooks / stale.name).exists():
            stale.unlink()


#: packages whose every module must have an ``automodule`` in docs/api/
API_PACKAGES = ("structure", "fluid", "coupling", "cases", "fsi")


def check_api_pages(app: Sphinx) -> None:
    """Warn for a module of the packages that no page of docs/api/ documents (a module moved
    or added since the pages were written), and for a page naming a module that is gone."""
    import pkgutil

    documented = set()
    for page in (Path(app.srcdir) / "api").glob("*.md"):
        documented.update(re.findall(r"^\.\. automodule:: ([\w.]+)", page.read_text(encoding="utf-8"),
                                     flags=re.M))
    modules = set()
    for package in API_PACKAGES:
        try:
            root = importlib.import_module(package)
        except Exception as error:  # noqa: BLE001
            logger.warning("cannot import %s for the API pages: %s", package, error,
                           type="generated")
            continue
        modules.add(package)
        modules.update(name for _, name, _ in pkgutil.walk_packages(root.__path__, package + "."))
    for name in sorted(modules - documented):
        logger.warning("module %s has no automodule in docs/api/", name, type="generated")
    for name in sorted(documented - modules):
        logger.warning("docs/api/ documents %s, which does not exist", name, type="generated")


def setup(app: Sphinx) -> dict:
    app.connect("builder-inited", generate)
    app.connect("builder-inited", check_api_pages)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
