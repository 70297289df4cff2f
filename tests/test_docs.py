"""The README and the documentation stay true to the code.

- The README is a front door: at most 250 lines, and its scene table lists every bundled scene
  with the description the scene file gives and the wall time that ``benchmarks/scene_times.py``
  measured (``docs/data/scene_times.json``).
- The documentation's scene-key and output references are generated from the code at build
  time (``docs/_ext/generated.py``); the pages include them rather than copies.
- Every scene key the documentation names in running text exists in the schema, or in a sweep
  file's ``[sweep]`` table (the notes, which record studies at the commit they measured,
  excepted).
- Every dataset a run writes is in the output reference, with the units the reference gives.
- Every measured number the documentation reads from ``docs/data/NAME.json`` is one of the
  fields ``benchmarks/NAME.py`` declares in ``DOC_FIELDS``, which its ``--smoke`` run (in the
  suite, ``tests/test_benchmarks.py``) proves it still writes.
"""
from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path

import h5py
import pytest
from conftest import module_constant

from fsi.cli import main
from fsi.io.output import reference_markdown as output_reference
from fsi.scene import SCHEMA, bundled_scenes, load_scene
from fsi.sweep.file import SWEEP_KEYS

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
README = ROOT / "README.md"
README_MAX_LINES = 250
FILE_SUFFIXES = {"nc", "png", "h5", "xdmf", "toml", "json", "md", "py", "obj", "csv", "pkl",
                 "ipynb"}
"""``name.suffix`` in backticks is a file, not a scene key."""
SCENE_ROW = re.compile(r"^\| `([a-z0-9-]+)` \| (.+?) \| (.+?) \|$")


def wall_text(seconds: float) -> str:
    """How the README writes a wall time: '8 s', '2 min 05 s', '1 h 02 min'."""
    seconds = round(seconds)
    if seconds < 60:
        return f"{seconds} s"
    if seconds < 3600:
        return f"{seconds // 60} min {seconds % 60:02d} s"
    return f"{seconds // 3600} h {seconds % 3600 // 60:02d} min"


def scene_rows() -> list[str]:
    """The README's scene table rows, as the code and the measured times give them."""
    times = json.loads((DOCS / "data" / "scene_times.json").read_text())["scenes"]
    rows = []
    for name in bundled_scenes():
        run = times[name]
        status = "" if run["exit_code"] == 0 else f" (exit {run['exit_code']})"
        rows.append(f"| `{name}` | {load_scene(name)['scene']['description']} | "
                    f"{wall_text(run['wall_seconds'])}{status} |")
    return rows


def test_the_readme_is_a_front_door_of_at_most_250_lines():
    lines = README.read_text().splitlines()
    assert len(lines) <= README_MAX_LINES, f"README.md is {len(lines)} lines"


def test_the_readme_lists_every_bundled_scene_with_its_description_and_measured_time():
    rows = [line for line in README.read_text().splitlines() if SCENE_ROW.match(line)]
    assert rows == scene_rows()


def test_the_pages_include_the_references_generated_from_the_code():
    guide = DOCS / "user-guide"
    assert "{include} ../_generated/scene_keys.md" in (guide / "scenes.md").read_text()
    assert "{include} ../_generated/outputs.md" in (guide / "outputs.md").read_text()
    generator = (DOCS / "_ext" / "generated.py").read_text()
    assert '"fsi.scene", "reference_markdown"' in generator
    assert '"fsi.io.output", "reference_markdown"' in generator


def _is_module(name: str) -> bool:
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


def test_every_scene_key_the_documentation_names_exists():
    key = re.compile(r"`([a-z_]+)\.([a-z_0-9]+)(?: = [^`]*)?`")
    unknown = []
    pages = [README] + [p for p in DOCS.rglob("*.md")
                        if not {"notes", "_generated", "_build"} & set(p.relative_to(DOCS).parts)]
    for page in pages:
        for section, name in key.findall(page.read_text()):
            if section in SCHEMA and name not in SCHEMA[section] and name not in FILE_SUFFIXES \
                    and not (section == "sweep" and name in SWEEP_KEYS) \
                    and not _is_module(f"{section}.{name}"):
                unknown.append(f"{page.relative_to(ROOT)}: {section}.{name}")
    assert not unknown, "scene keys named in the documentation but not in the schema:\n" + \
        "\n".join(unknown)


def _documented_units() -> dict[str, str]:
    """Name (or name pattern) -> units, read from the generated output reference."""
    units = {}
    for line in output_reference().splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if len(cells) == 2 and cells[0].startswith("`"):
            units[cells[0].strip("`")] = cells[1]
    return units


def _documented(name: str, documented: dict[str, str]) -> str | None:
    """The documented units of dataset ``name``, by its name or a name pattern."""
    if name in documented:
        return documented[name]
    for pattern, unit in documented.items():
        if pattern.endswith("*") and name.startswith(pattern[:-1]):
            return unit
        if pattern.startswith("*") and name.endswith(pattern[1:]):
            return documented.get(name[:-len(pattern) + 1], unit) if "name without" in unit \
                else unit
    return None


def test_every_dataset_a_run_writes_is_documented_with_its_units(tmp_path, tiny_sweep_scene):
    scene = tiny_sweep_scene
    out = tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out), "--no-plots"]) in (0, 3)
    documented = _documented_units()
    wrong = []
    with h5py.File(out / "result.h5") as f:
        def check(path, obj):
            if not isinstance(obj, h5py.Dataset):
                return
            group, _, name = path.rpartition("/")
            if group == "membrane":
                return  # the rest shape's own units, written beside it
            assert group in documented, f"group {group!r} is not in the output reference"
            unit = _documented(name, documented)
            if unit != obj.attrs.get("units"):
                wrong.append(f"{path}: written {obj.attrs.get('units')!r}, documented {unit!r}")
        f.visititems(check)
    assert not wrong, "\n".join(wrong)


DATA_ROLE = re.compile(r"\{data\}`([A-Za-z0-9_.-]+):([^:`]+)")
DATA_TABLE = re.compile(r"```\{data-table\} ([A-Za-z0-9_.-]+)\n:rows: ([^\n.]+)")
STAMPS = ("commit", "date", "command", "command_seconds", "load_average")
"""Fields every docs/data file carries beside its benchmark's record (benchmarks/_report.py)."""


def benchmark_script(name: str) -> Path:
    """The script that writes ``docs/data/NAME.json``: ``benchmarks/NAME.py``, or for a
    variant's file (``slosh_frequency_linear``) the script whose name it extends."""
    stem = name
    while stem:
        script = ROOT / "benchmarks" / f"{stem}.py"
        if script.is_file():
            return script
        stem = stem.rpartition("_")[0]
    raise AssertionError(f"no benchmark script writes docs/data/{name}.json")


def test_every_number_the_documentation_reads_is_a_field_its_benchmark_declares():
    read = set()
    for page in DOCS.rglob("*.md"):
        if "_build" in page.parts:
            continue
        text = page.read_text()
        read |= {(m.group(1), path.strip().split(".")[0], page.name)
                 for m in DATA_ROLE.finditer(text) for path in m.group(2).split("+")}
        read |= {(m.group(1), m.group(2).strip(), page.name) for m in DATA_TABLE.finditer(text)}
    assert read, "the documentation reads no benchmark data"
    declared = {name: tuple(module_constant(benchmark_script(name), "DOC_FIELDS")
                            or ()) + STAMPS for name, _, _ in read}
    undeclared = sorted(f"{page}: {name}.{field}" for name, field, page in read
                        if field not in declared[name])
    assert not undeclared, "read by the documentation, not in the benchmark's DOC_FIELDS: " + \
        ", ".join(undeclared)


def test_a_duration_sums_seconds_over_every_item_and_path_and_reads_as_a_reader_says_it():
    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        import datapath as datatable  # the Sphinx-free half of the {data} role
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    data = {"cases": [{"wall_seconds": 100.0}, {"wall_seconds": 50.0}],
            "runs": {"1": {"s": 3.0}, "2": {"s": 4.0}}, "extra": 30.0}
    assert datatable.lookup(data, "cases.*.wall_seconds", "x") == [100.0, 50.0]
    assert datatable.lookup(data, "runs.*.s+extra", "x") == [3.0, 4.0, 30.0]
    assert datatable.render(datatable.lookup(data, "cases.*.wall_seconds+extra", "x"),
                            "duration") == "3.0 min"
    assert [datatable.duration(s) for s in (0.24, 40.0, 150.0, 2460.0, 6000.0)] == \
        ["0.2 s", "40 s", "2.5 min", "41 min", "1.7 h"]
    with pytest.raises(datatable.DataError):
        datatable.lookup(data, "cases.*.seconds", "x")
    with pytest.raises(datatable.DataError):
        datatable.render("text", "duration")


def test_no_page_holds_control_characters():
    """A control character in a page (an escape gone wrong in an edit: BEL for \\a in
    \\alpha) renders as text and does not fail the build; none is allowed."""
    bad = []
    for page in DOCS.rglob("*.md"):
        if "_build" in page.parts:
            continue
        for number, line in enumerate(page.read_text().splitlines(), 1):
            if re.search(r"[\x00-\x08\x0b-\x1f\x7f]", line):
                bad.append(f"{page.relative_to(DOCS)}:{number}")
    assert not bad, "control characters in: " + ", ".join(bad)
