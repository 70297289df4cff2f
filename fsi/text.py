"""Plain text for the terminal: tables whose columns line up (:func:`format_table`), a
suggestion for a mistyped name (:func:`suggestion`) and a rough duration (:func:`about`).
Nothing of fsi is imported here: every room may use it.

A table names each column and its unit in a header line; every column is as wide as its widest
cell, header included, and the columns are :data:`GAP` spaces apart, so that each column
starts (text) or ends (numbers) at the same character position on every line::

    >>> print(format_table([("tank fraction", "-"), ("load", "Pa"), ("estimate", ""),
    ...                     ("w0", "mm")],
    ...                    [(0.25, 713.9, "small", 4004.76), (0.5, 2055.7, "hencky", 37.93)],
    ...                    [".3f", ".1f", "", ".2f"]))
    tank fraction (-)  load (Pa)  estimate  w0 (mm)
                0.250      713.9  small     4004.76
                0.500     2055.7  hencky      37.93

The unit '-' marks a dimensionless number, '' a column without a unit (text). A column is
right-aligned when it holds a number, left-aligned otherwise; an empty cell is None. With no
headers (None) the table is a listing, e.g. names and descriptions, and ``width`` wraps its
last column with a hanging indent::

    >>> print(format_table(None, [("thesis-plate", "Thesis Ch. 3 flat clamped diaphragm: "
    ...                            "plate and membrane closed forms by fill"),
    ...                           ("slosh-forced-diaphragm", "forced lateral slosh")],
    ...                    ["", ""], width=64))
    thesis-plate            Thesis Ch. 3 flat clamped diaphragm:
                            plate and membrane closed forms by fill
    slosh-forced-diaphragm  forced lateral slosh
"""
from __future__ import annotations

import difflib
import numbers
import textwrap
from typing import Iterable, Optional, Sequence

GAP = 2
"""Spaces between two columns of a table."""
MIN_WRAP = 20
"""The narrowest a wrapped last column is made, whatever the width (characters)."""


def header_cell(name: str, unit: str) -> str:
    """'name (unit)', or 'name' when ``unit`` is ''."""
    return f"{name} ({unit})" if unit else name


def is_number(value) -> bool:
    """Whether ``value`` is a number (a bool is not: it prints as text)."""
    return isinstance(value, numbers.Number) and not isinstance(value, bool)


def format_cell(value, spec: str) -> str:
    """``value`` formatted by the format spec ``spec`` ('.3f', '.4g', '' for str()); None is
    an empty cell."""
    return "" if value is None else format(value, spec)


def format_table(headers: Optional[Sequence[tuple[str, str]]], rows: Sequence[Sequence],
                 formats: Sequence[str], *, width: Optional[int] = None) -> str:
    """The lines of a table, joined by newlines (no final newline, no trailing spaces).

    Parameters
    ----------
    headers
        (name, unit) of each column, printed 'name (unit)' in a header line above the rows;
        unit '-' for a dimensionless number, '' for none. None: no header line.
    rows
        A value per column in each row: a number (right-aligned), text (left-aligned) or None
        (an empty cell).
    formats
        A format spec per column, as :func:`format` takes it ('.3f', '.1f', '').
    width
        When given, the last column's text is wrapped to end within ``width`` characters (but
        is at least :data:`MIN_WRAP` wide), its further lines indented to the column's start.

    Raises
    ------
    ValueError
        When a row or the headers do not have a value per format.
    """
    count = len(formats)
    if any(len(row) != count for row in rows) or (headers is not None and len(headers) != count):
        raise ValueError(f"format_table: every row and the headers need {count} values, one "
                         f"per format")
    right = [any(is_number(row[j]) for row in rows) for j in range(count)]
    cells = [[format_cell(v, spec) for v, spec in zip(row, formats)] for row in rows]
    head = [header_cell(*h) for h in headers] if headers is not None else None
    every = cells + ([head] if head else [])
    widths = [max((len(line[j]) for line in every), default=0) for j in range(count)]
    wrap = width is not None and count > 0 and not right[-1]
    lines = [_line(head, widths, right, wrap)] if head else []
    for line in cells:
        lines += _wrapped(line, widths, right, width) if wrap else [_line(line, widths, right)]
    return "\n".join(lines)


def _line(cells: Sequence[str], widths: Sequence[int], right: Sequence[bool],
          last_free: bool = False) -> str:
    """One line of cells padded to their columns' widths, :data:`GAP` spaces apart; the last
    cell unpadded when ``last_free`` (a wrapped column)."""
    padded = [c.rjust(w) if r else c.ljust(w) for c, w, r in zip(cells, widths, right)]
    if last_free and cells:
        padded[-1] = cells[-1]
    return (" " * GAP).join(padded).rstrip()


def _wrapped(cells: Sequence[str], widths: Sequence[int], right: Sequence[bool],
             width: int) -> list[str]:
    """A row whose last (text) cell is wrapped to end within ``width``: its first line beside
    the other cells, the rest indented to the last column's start."""
    start = sum(widths[:-1]) + GAP * (len(widths) - 1)
    parts = textwrap.wrap(cells[-1], max(width - start, MIN_WRAP),
                          break_long_words=False, break_on_hyphens=False) or [""]
    first = _line([*cells[:-1], parts[0]], widths, right, last_free=True)
    return [first] + [" " * start + part for part in parts[1:]]


def closest(name: str, choices: Iterable[str]) -> Optional[str]:
    """The choice closest to ``name`` (:func:`difflib.get_close_matches`), or None when none
    is close."""
    close = difflib.get_close_matches(name, list(choices), n=1)
    return close[0] if close else None


def suggestion(name: str, choices: Iterable[str]) -> str:
    """"did you mean 'x'?" with ``x`` the choice closest to ``name``, or '' when none is
    close::

        >>> suggestion("thesis-statc", ["thesis-static", "thesis-plate", "valve-fill"])
        "did you mean 'thesis-static'?"
    """
    match = closest(name, choices)
    return f"did you mean '{match}'?" if match else ""


def unknown_name(what: str, name: str, choices: Iterable[str], listing: str) -> str:
    """The one line refusing a ``name`` that is neither a file nor one of the bundled
    ``choices``, with the closest of them when one is close::

        >>> unknown_name("scene", "thesis-statc", ["thesis-static"], "fsi scenes")
        "unknown scene 'thesis-statc'; did you mean 'thesis-static'? (fsi scenes lists them)"
        >>> unknown_name("scene", "xyz", ["thesis-static"], "fsi scenes")
        "unknown scene 'xyz': not a file, and not a bundled scene (fsi scenes lists them)"
    """
    hint = suggestion(name, choices)
    return (f"unknown {what} '{name}'" + (f"; {hint}" if hint else f": not a file, and not a "
                                          f"bundled {what}") + f" ({listing} lists them)")


def about(seconds: float) -> str:
    """A rough duration: 'under a second', 'about 20 s', 'about 3 min', 'about 2 h'."""
    if seconds < 1.0:
        return "under a second"
    if seconds < 90.0:
        return f"about {seconds:.2g} s"
    if seconds < 5400.0:
        return f"about {round(seconds / 60)} min"
    return f"about {round(seconds / 3600)} h"
