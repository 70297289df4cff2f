"""Measured numbers read from the benchmarks' JSON, never typed in.

Each benchmark ``benchmarks/NAME.py`` prints one JSON object; ``docs/data/NAME.json`` holds
that object plus the fields ``"commit"`` and ``"date"`` of the measurement.  Two ways to show
it, both credited with "measured at commit X on DATE by ``python benchmarks/NAME.py``":

A table (MyST)::

    ```{data-table} fluid_step
    :rows: runs
    :columns: cells=cells, seconds_per_step=s/step:.3g, ratio=ratio:.2f
    :key: grid
    :caption: Seconds per liquid step
    ```

``:rows:`` is a dotted path to a list of objects or an object of objects (``.`` for the
top-level object as one row); with an object of objects, ``:key: HEADER`` adds its keys as
the first column and ``:exclude: KEY, ...`` leaves those keys' entries out.  ``:columns:`` is
a comma-separated list of ``PATH[=HEADER][:FORMAT]`` (semicolons instead when a format groups
thousands with ``,``),
PATH dotted inside a row (``@key`` is the row's key; a trailing ``?`` makes it optional, '–'
where a row has none), FORMAT a Python format spec.

One number in running text (MyST): ``{data}`fluid_step:ratio:.2f``` renders the value at the
dotted path with the format; the first number a page takes from a file carries a footnote
naming the measurement.  ``{data}`slosh_energy:cases.*.wall_seconds:duration``` sums
seconds over every item (``*``) or over several paths (``A+B``) and writes them as "12 min".

A missing file, path or field is a Sphinx error, so ``-W`` stops a page that cites a number
no benchmark wrote.
"""
from __future__ import annotations

from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import directives
from docutils.transforms import Transform
from sphinx.application import Sphinx
from sphinx.util.docutils import SphinxDirective

from datapath import DATA_DIR, FORMAT_SPEC, DataError, _load, credit, load, lookup, render


def credit_nodes(name: str, data: dict) -> list[nodes.Node]:
    command = data.get("command") or f"python benchmarks/{name}.py"
    return [nodes.Text("Measured at commit "), nodes.literal(text=str(data["commit"])),
            nodes.Text(f" on {data['date']} by "), nodes.literal(text=command),
            nodes.Text(f"{_load(data)}.")]


def parse_columns(spec: str) -> list[tuple[str, str, str]]:
    """``PATH[=HEADER][:FORMAT], ...`` -> [(path, header, format)].

    Columns are separated by commas, or by semicolons when a format has a ``,`` (grouping).
    """
    columns = []
    for item in (part.strip() for part in spec.split(";" if ";" in spec else ",")):
        if not item:
            continue
        fmt = ""
        head, sep, tail = item.rpartition(":")
        if sep and FORMAT_SPEC.match(tail.strip()):
            item, fmt = head, tail.strip()
        path, sep, header = item.partition("=")
        path = path.strip()
        columns.append((path, header.strip() if sep else path, fmt))
    if not columns:
        raise DataError("no columns")
    return columns


class DataTable(SphinxDirective):
    """``{data-table} NAME``: a table of rows read from ``docs/data/NAME.json``."""

    required_arguments = 1
    has_content = True
    option_spec = {
        "rows": directives.unchanged_required,
        "columns": directives.unchanged_required,
        "key": directives.unchanged,
        "caption": directives.unchanged,
        "name": directives.unchanged,
        "exclude": directives.unchanged,
    }

    def run(self) -> list[nodes.Node]:
        name = self.arguments[0]
        try:
            self.env.note_dependency(str(Path(self.env.srcdir) / DATA_DIR / f"{name}.json"))
            data, path = load(self.env.srcdir, name)
            if "rows" not in self.options or "columns" not in self.options:
                raise DataError("data-table needs :rows: and :columns:")
            rows = lookup(data, self.options["rows"], f"{name}.json")
            columns = parse_columns(self.options["columns"])
            if isinstance(rows, dict) and self.options["rows"] in ("", "."):
                items = [(None, rows)]
            elif isinstance(rows, dict):
                excluded = {k.strip() for k in self.options.get("exclude", "").split(",")}
                items = [(k, v) for k, v in rows.items() if k not in excluded]
            elif isinstance(rows, list):
                items = [(None, row) for row in rows]
            else:
                raise DataError(f"{name}.json: {self.options['rows']!r} is not a list or object")
            key_header = self.options.get("key")
            headers = ([key_header] if key_header else []) + [c[1] for c in columns]
            body = []
            for index, (key, row) in enumerate(items):
                where = f"{name}.json {self.options['rows']}[{key if key is not None else index}]"
                cells = [str(key)] if key_header else []
                for path_, _, fmt in columns:
                    if path_ == "@key":
                        if key is None:
                            raise DataError(f"{where}: @key needs rows that are an object")
                        cells.append(str(key))
                    elif path_.endswith("?"):  # optional: '–' where the row has none
                        try:
                            cells.append(render(lookup(row, path_[:-1], where), fmt))
                        except DataError:
                            cells.append(render(None, fmt))
                    else:
                        cells.append(render(lookup(row, path_, where), fmt))
                body.append(cells)
        except DataError as error:
            raise self.error(f"data-table: {error}") from None

        table = nodes.table(classes=["data-table"])
        caption = self.options.get("caption") or " ".join(self.content).strip()
        if caption:
            title, _ = self.state.inline_text(caption, self.lineno)
            table += nodes.title("", "", *title)
        group = nodes.tgroup(cols=len(headers))
        table += group
        for _ in headers:
            group += nodes.colspec(colwidth=1)
        head = nodes.thead()
        group += head
        head += self._row(headers)
        tbody = nodes.tbody()
        group += tbody
        for cells in body:
            tbody += self._row(cells)
        if "name" in self.options:
            self.add_name(table)
        source = nodes.paragraph("", "", *credit_nodes(name, data), classes=["data-source"])
        container = nodes.container("", table, source, classes=["data-table-container"])
        return [container]

    @staticmethod
    def _row(cells: list[str]) -> nodes.row:
        row = nodes.row()
        for text in cells:
            entry = nodes.entry()
            entry += nodes.paragraph(text=text)
            row += entry
        return row


def data_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    """``{data}`NAME:PATH[:FORMAT]``` -> the number, with a footnote naming its source."""
    parts = text.split(":", 2)
    document = inliner.document
    env = document.settings.env
    try:
        if len(parts) < 2:
            raise DataError(f"{text!r}: expected NAME:PATH[:FORMAT]")
        bench, path, fmt = parts[0], parts[1], parts[2] if len(parts) > 2 else ""
        # the page depends on the file even while it is missing: it is rebuilt when it appears
        env.note_dependency(str(Path(env.srcdir) / DATA_DIR / f"{bench}.json"))
        data, file = load(env.srcdir, bench)
        value = render(lookup(data, path, f"{bench}.json"), fmt)
    except (DataError, ValueError) as error:
        message = inliner.reporter.error(f"data: {error}", line=lineno)
        problem = inliner.problematic(rawtext, rawtext, message)
        return [problem], [message]
    label = f"data-source-{bench}"
    cited = env.temp_data.setdefault("data_cited", set())
    if label in cited:  # one footnote mark per source and page: its first number
        return [nodes.Text(value)], []
    cited.add(label)
    reference = nodes.footnote_reference("", "", auto=1, refname=label,
                                         classes=["data-source-ref"])
    reference["data_credit"] = credit(bench, data)
    reference["data_bench"] = bench
    document.note_autofootnote_ref(reference)
    document.note_footnote_ref(reference)
    return [nodes.Text(value), reference], []


class DataFootnotes(Transform):
    """One footnote per data file cited by ``{data}`` in a document, appended at its end
    (before docutils numbers the auto-numbered footnotes)."""

    default_priority = 500

    def apply(self) -> None:
        seen: dict[str, nodes.footnote_reference] = {}
        for reference in self.document.findall(nodes.footnote_reference):
            if "data_credit" in reference and reference["refname"] not in seen:
                seen[reference["refname"]] = reference
        for label, reference in seen.items():
            text = reference["data_credit"]
            footnote = nodes.footnote("", nodes.paragraph(text=text[0].upper() + text[1:] + "."),
                                      auto=1, names=[label], classes=["data-source"])
            self.document += footnote
            self.document.note_autofootnote(footnote)
            self.document.note_explicit_target(footnote, footnote)
        for reference in self.document.findall(nodes.footnote_reference):
            for attribute in ("data_credit", "data_bench"):
                if attribute in reference:
                    del reference[attribute]


def _python_or_data_role():
    """The ``data`` role: ``NAME:PATH[:FORMAT]`` (a colon, which no Python name has) is a
    measured number; anything else is the Python domain's ``py:data`` cross-reference, which
    docstrings use and which would otherwise shadow this role."""
    from sphinx.domains.python import PyXRefRole

    python_role = PyXRefRole()

    def role(name, rawtext, text, lineno, inliner, options=None, content=None):
        if ":" in text:
            return data_role(name, rawtext, text, lineno, inliner, options, content)
        return python_role(name, rawtext, text, lineno, inliner, options or {}, content or [])

    return role


def setup(app: Sphinx) -> dict:
    app.add_directive("data-table", DataTable)
    role = _python_or_data_role()
    app.add_role("data", role)
    app.add_role_to_domain("py", "data", role, override=True)
    app.add_transform(DataFootnotes)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
