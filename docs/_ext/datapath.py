"""Reading the benchmarks' JSON for the documentation, without Sphinx: the file, a dotted
path in it (``*`` and ``A+B`` included), a value as text and the credit line
(the `datatable` extension renders them; the tests call these directly)."""
from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

DATA_DIR = "data"
FORMAT_SPEC = re.compile(r"^[<>^=]?[+\- ]?#?0?\d*[,_]?(\.\d+)?[bcdeEfFgGnosxX%]?$")


class DataError(Exception):
    """A data file, path or field that cannot be read."""


def load(srcdir: str | Path, name: str) -> tuple[dict, Path]:
    """The JSON object of benchmark ``name`` and its path; DataError if absent or bad."""
    if not re.fullmatch(r"[A-Za-z0-9_.-]+", name):
        raise DataError(f"bad benchmark name {name!r}")
    path = Path(srcdir) / DATA_DIR / f"{name}.json"
    if not path.is_file():
        raise DataError(f"no data file {DATA_DIR}/{name}.json (run benchmarks/{name}.py)")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as error:
        raise DataError(f"{DATA_DIR}/{name}.json cannot be read: {error}") from error
    if not isinstance(data, dict):
        raise DataError(f"{DATA_DIR}/{name}.json does not hold a JSON object")
    for field in ("commit", "date"):
        if field not in data:
            raise DataError(f"{DATA_DIR}/{name}.json has no {field!r} field")
    return data, path


def lookup(value: Any, dotted: str, where: str) -> Any:
    """``value`` at the dotted path (object keys or list indices); DataError if absent.

    A ``*`` part stands for every item of a list or every value of an object (the result is
    the list of what the rest of the path finds in each); ``A+B`` is the list of both paths'
    values (for the ``duration`` format, which sums them)."""
    if "+" in dotted:
        found = []
        for part in dotted.split("+"):
            item = lookup(value, part.strip(), where)
            found.extend(item if isinstance(item, list) else [item])
        return found
    if dotted in ("", "."):
        return value
    head, _, rest = dotted.partition(".")
    if head != "*":
        return lookup(_child(value, head, dotted, where), rest, where)
    if not isinstance(value, (dict, list)) or not value:
        raise DataError(f"{where}: '*' in path {dotted!r} meets no list or object")
    found = []
    for item in (value.values() if isinstance(value, dict) else value):
        got = lookup(item, rest, where)
        found.extend(got if "*" in rest else [got])
    return found


def _child(value: Any, part: str, dotted: str, where: str) -> Any:
    """The object key or list index ``part`` of ``value``; DataError if absent."""
    if isinstance(value, dict) and part in value:
        return value[part]
    if isinstance(value, list) and re.fullmatch(r"-?\d+", part) and \
            -len(value) <= int(part) < len(value):
        return value[int(part)]
    raise DataError(f"{where}: no {part!r} in path {dotted!r}")


def duration(seconds: float) -> str:
    """A wall time as a reader says it: '0.2 s', '40 s', '2.5 min', '41 min', '1.7 h'."""
    if seconds < 10:
        return f"{seconds:.1f} s"
    if seconds < 90:
        return f"{seconds:.0f} s"
    minutes = seconds / 60
    if minutes < 10:
        return f"{minutes:.1f} min"
    if minutes < 90:
        return f"{minutes:.0f} min"
    return f"{minutes / 60:.1f} h"


def render(value: Any, spec: str) -> str:
    """A value as text: the format spec for numbers, '–' for null, yes/no for booleans;
    the spec ``duration`` writes seconds (or the sum of a list of them) as :func:`duration`."""
    if spec == "duration":
        values = value if isinstance(value, list) else [value]
        if not values or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                 for v in values):
            raise DataError(f"duration of {value!r}: expected seconds")
        return duration(float(sum(values)))
    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if spec and isinstance(value, (int, float)) and not isinstance(value, bool):
        return format(value, spec)
    if isinstance(value, float):
        return format(value, "g")
    return str(value)


def _load(data: dict) -> str:
    """'; load average a / b / c' (1, 5, 15 min, at the run's end) where the file has it: a
    timing taken beside other work reads high."""
    load = data.get("load_average")
    if not load:
        return ""
    return "; the machine's load average at its end " + " / ".join(f"{v:g}" for v in load) + \
        " (1, 5, 15 min; 2 cores)"


def credit(name: str, data: dict) -> str:
    command = data.get("command") or f"python benchmarks/{name}.py"
    return f"measured at commit {data['commit']} on {data['date']} by {command}{_load(data)}"
