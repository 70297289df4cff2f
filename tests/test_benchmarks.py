"""Every benchmark script runs in its ``--smoke`` mode (the same code path on its smallest
configuration, seconds) and ends by printing one JSON object on its last stdout line that
holds the fields the documentation reads: the script's module-level ``DOC_FIELDS``, each
present and not null. A smoke run writes nothing into ``docs/data`` (only a full run does,
through ``benchmarks/_report.py``).

The scripts run one after the other in subprocesses from the repository root, each with one
BLAS thread (unless the environment sets another count): the suite's other workers share the
cores, and OpenBLAS threads waiting on busy cores slow some scripts several times over.
"""
from __future__ import annotations

import ast
import datetime
import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import module_constant

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = [path for path in sorted((ROOT / "benchmarks").glob("*.py"))
           if not path.name.startswith("_")]
DOCS_DATA = ROOT / "docs" / "data"
TIMEOUT = 300
"""s per smoke run: a few seconds each alone, this much on a loaded machine."""


def _docs_file_state(name: str):
    path = DOCS_DATA / f"{name}.json"
    return path.read_bytes() if path.exists() else None


def test_there_are_benchmarks():
    assert len(SCRIPTS) >= 25, [p.name for p in SCRIPTS]


def _report_module():
    spec = importlib.util.spec_from_file_location("_report", ROOT / "benchmarks" / "_report.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_emit_writes_docs_data_for_a_full_run_only(tmp_path, monkeypatch, capsys):
    report = _report_module()
    monkeypatch.setattr(report, "DOCS_DATA", tmp_path)
    record = {"value": 1.5, "nested": {"n": [1, 2]}}
    report.emit("example", record, smoke=True)
    assert json.loads(capsys.readouterr().out.splitlines()[-1]) == record
    assert not (tmp_path / "example.json").exists()
    report.emit("example", record, smoke=False)
    assert json.loads(capsys.readouterr().out.splitlines()[-1]) == record  # stdout unstamped
    written = json.loads((tmp_path / "example.json").read_text())
    assert {k: written[k] for k in record} == record
    assert written["commit"] == report.commit() and written["commit"]
    assert written["date"] == datetime.date.today().isoformat()


def run_lines(doc: str, script: str) -> list[str]:
    """The docstring's run command: the first line holding ``python benchmarks/<script>``
    and the lines that continue it (up to the next blank line)."""
    lines = doc.splitlines()
    start = next((k for k, line in enumerate(lines)
                  if f"python benchmarks/{script}" in line), None)
    if start is None:
        return []
    end = next((k for k in range(start, len(lines)) if not lines[k].strip()), len(lines))
    return lines[start:end]


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_docstring_run_line_names_smoke(script):
    doc = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8")))
    assert doc, f"{script.name} has no module docstring"
    command = run_lines(doc, script.name)
    assert command, f"{script.name}: no run line 'python benchmarks/{script.name} ...'"
    assert "--smoke" in " ".join(command), command


@pytest.mark.benchmark
@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.stem)
def test_smoke_run_prints_the_documented_fields(script):
    fields = module_constant(script, "DOC_FIELDS")
    assert fields and all(isinstance(f, str) for f in fields), \
        f"{script.name}: no module-level DOC_FIELDS = ('key', ...)"
    before = _docs_file_state(script.stem)
    env = dict(os.environ, MPLBACKEND="Agg")
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    env.setdefault("OMP_NUM_THREADS", "1")
    done = subprocess.run([sys.executable, str(script.relative_to(ROOT)), "--smoke"], cwd=ROOT,
                          env=env, capture_output=True, text=True, timeout=TIMEOUT)
    assert done.returncode == 0, f"exit {done.returncode}\n{done.stderr[-4000:]}"
    lines = done.stdout.strip().splitlines()
    assert lines, f"nothing on stdout\n{done.stderr[-2000:]}"
    record = json.loads(lines[-1])
    assert isinstance(record, dict), type(record)
    missing = [f for f in fields if f not in record]
    null = [f for f in fields if f in record and record[f] is None]
    assert not missing and not null, f"missing {missing}, null {null}"
    assert _docs_file_state(script.stem) == before, "a smoke run wrote into docs/data"
