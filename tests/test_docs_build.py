"""The built documentation works offline and its commands survive copy and paste.

Reads the HTML that ``sphinx-build -b html docs docs/_build/html`` wrote:

* **Offline.** No page loads anything from another host: no ``<script src>``, no ``<link
  href>`` that fetches (style sheets, icons, fonts, preloads), no ``<img src>`` or
  ``srcset``, no ``<source>``, ``<iframe>``, ``<embed>`` or ``<object>``, and no ``url(...)``
  or ``@import`` in a page's styles or in the built CSS points at ``http(s)://`` or ``//``.
  Ordinary hyperlinks are fine: an ``<a href>`` to a paper or a repository loads nothing
  until a reader follows it, and neither do a page's navigation links (``<link rel>``
  canonical, next, prev, index, search).
* **Copy and paste.** A command-line option keeps its ``--``: every code span, code block
  line or line of text in the Markdown sources that holds an option (`` --name``) appears as
  written on its built page, and so does the command of every ``docs/data/*.json`` a page
  cites (the "measured ... by ``python benchmarks/NAME.py --x``" footnotes and table credits);
  no page shows an option whose ``--`` became a dash (``–fills``).

Without a build these tests skip, unless ``DOCS_BUILD_REQUIRED=1`` (CI, after its docs
build), where a missing build fails.
"""
from __future__ import annotations

import json
import os
import re
from functools import cache
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
HTML = DOCS / "_build" / "html"
NOT_PAGES = {"_build", "data", "jupyter_execute"}
"""Folders of docs/ whose Markdown is not built into pages (conf.py's exclude_patterns)."""

OPTION = re.compile(r"(?<!\S)--[a-z]")
MANGLED_OPTION = re.compile(r"(?<!\S)[\u2013\u2014][a-z][a-z0-9]*(?:-[a-z0-9]+)*")
EXTERNAL = re.compile(r"^\s*(?:https?:)?//", re.IGNORECASE)
CSS_URL = re.compile(r"""url\(\s*['"]?([^'")]+)|@import\s+['"]([^'"]+)""", re.IGNORECASE)
NAVIGATION_RELS = {"canonical", "next", "prev", "previous", "index", "search", "author",
                   "license", "help", "copyright", "up", "first", "last", "top"}
LOADING_ATTRIBUTES = {
    "script": ("src",), "img": ("src", "srcset"), "source": ("src", "srcset"),
    "video": ("src", "poster"), "audio": ("src",), "track": ("src",), "iframe": ("src",),
    "embed": ("src",), "object": ("data",), "input": ("src",), "image": ("href", "xlink:href"),
}


# -- the build --------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def html_dir() -> Path:
    """docs/_build/html; skip (fail with DOCS_BUILD_REQUIRED=1) when it was not built."""
    if (HTML / "index.html").is_file():
        return HTML
    reason = f"no documentation build in {HTML.relative_to(ROOT)} (run sphinx-build first)"
    if os.environ.get("DOCS_BUILD_REQUIRED") == "1":
        pytest.fail(reason)
    pytest.skip(reason)


class _Page(HTMLParser):
    """A page's visible text and the URLs it loads."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.text: list[str] = []
        self.loads: list[str] = []
        self._skip = 0  # inside <script> or <style>
        self._style = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        values = {name: value or "" for name, value in attrs}
        for name in LOADING_ATTRIBUTES.get(tag, ()):
            if values.get(name):
                self.loads.extend(_srcset_urls(values[name]) if name == "srcset"
                                  else [values[name]])
        if tag == "link" and values.get("href"):
            rels = set(values.get("rel", "").lower().split())
            if not rels or not rels <= NAVIGATION_RELS:
                self.loads.append(values["href"])
        if values.get("style"):
            self.loads.extend(_css_urls(values["style"]))
        if tag in ("script", "style"):
            self._skip += 1
            self._style = tag == "style"

    def handle_endtag(self, tag: str) -> None:
        if tag in ("script", "style") and self._skip:
            self._skip -= 1
            self._style = False

    def handle_data(self, data: str) -> None:
        if self._style:
            self.loads.extend(_css_urls(data))
        elif not self._skip:
            self.text.append(data)


def _srcset_urls(srcset: str) -> list[str]:
    return [part.split()[0] for part in srcset.split(",") if part.strip()]


def _css_urls(css: str) -> list[str]:
    return [url or imported for url, imported in CSS_URL.findall(css)]


def _normalise(text: str) -> str:
    return " ".join(text.split())


@cache
def _read(page: Path) -> _Page:
    parser = _Page()
    parser.feed(page.read_text(encoding="utf-8"))
    parser.close()
    return parser


def _page_text(page: Path) -> str:
    return _normalise("".join(_read(page).text))


def _pages(html: Path) -> list[Path]:
    return sorted(html.rglob("*.html"))


# -- the Markdown sources --------------------------------------------------------------------

def _sources() -> list[Path]:
    return sorted(path for path in DOCS.rglob("*.md")
                  if not NOT_PAGES & set(path.relative_to(DOCS).parts))


def _tokens(tokens):
    for token in tokens:
        yield token
        if token.children:
            yield from _tokens(token.children)


def _commands(source: Path) -> list[str]:
    """What a reader copies that holds an option: code spans, code block lines, text lines."""
    from markdown_it import MarkdownIt  # the docs' own parser (myst-parser's dependency)

    found = []
    parser = MarkdownIt("commonmark").enable("table")
    for token in _tokens(parser.parse(source.read_text(encoding="utf-8"))):
        if token.type in ("fence", "code_block"):
            if token.type == "fence" and token.info.strip().startswith("{") and \
                    not token.info.strip().startswith(("{code", "{code-block")):
                continue  # a directive's options, not a shown command
            found += [_normalise(line) for line in token.content.splitlines()
                      if OPTION.search(line)]
        elif token.type in ("code_inline", "text") and OPTION.search(token.content):
            found.append(_normalise(token.content))
    return found


def _built_page(html: Path, source: Path) -> Path:
    return html / source.relative_to(DOCS).with_suffix(".html")


def _cited_commands() -> dict[str, str]:
    """{data file name: its command} for the data files whose command has an option."""
    commands = {}
    for path in sorted((DOCS / "data").glob("*.json")):
        command = json.loads(path.read_text(encoding="utf-8")).get("command")
        if isinstance(command, str) and OPTION.search(command):
            commands[path.stem] = _normalise(command)
    return commands


def _cites(source_text: str, name: str) -> bool:
    return bool(re.search(r"\{data\}`" + re.escape(name) + r":", source_text) or
                re.search(r"\{data-table\}\s+" + re.escape(name) + r"\s", source_text))


# -- the tests ---------------------------------------------------------------------------------

def test_no_page_loads_an_external_resource(html_dir):
    offenders = []
    for page in _pages(html_dir):
        offenders += [f"{page.relative_to(html_dir)}: {url}"
                      for url in _read(page).loads if EXTERNAL.match(url)]
    for sheet in sorted(html_dir.rglob("*.css")):
        offenders += [f"{sheet.relative_to(html_dir)}: {url}"
                      for url in _css_urls(sheet.read_text(encoding="utf-8", errors="replace"))
                      if EXTERNAL.match(url)]
    assert not offenders, "resources loaded from other hosts:\n" + "\n".join(offenders[:20])


def test_commands_in_the_sources_keep_their_double_dash(html_dir):
    missing, checked = [], 0
    for source in _sources():
        commands = _commands(source)
        if not commands:
            continue
        page = _built_page(html_dir, source)
        assert page.is_file(), f"{source.relative_to(ROOT)} has no built page {page.name}"
        text = _page_text(page)
        checked += len(commands)
        missing += [f"{source.relative_to(ROOT)}: {command!r}"
                    for command in commands if command not in text]
    assert checked, "no command with an option found in the Markdown sources"
    assert not missing, "commands not shown as written:\n" + "\n".join(missing[:20])


def test_cited_benchmark_commands_keep_their_double_dash(html_dir):
    commands = _cited_commands()
    missing, checked = [], 0
    for source in _sources():
        source_text = source.read_text(encoding="utf-8")
        for name, command in commands.items():
            if _cites(source_text, name):
                checked += 1
                if command not in _page_text(_built_page(html_dir, source)):
                    missing.append(f"{source.relative_to(ROOT)} ({name}.json): {command!r}")
    assert checked, "no page cites a data file whose command has an option"
    assert not missing, "benchmark commands not shown as written:\n" + "\n".join(missing[:20])


def test_no_option_turned_into_a_dash(html_dir):
    found = []
    for page in _pages(html_dir):
        found += [f"{page.relative_to(html_dir)}: {match!r}"
                  for match in MANGLED_OPTION.findall(_page_text(page))]
    assert not found, "options whose -- became a dash:\n" + "\n".join(found[:20])
