"""Package boundaries, read from the source with ``ast`` (nothing is imported).

The solver packages (structure, fluid, coupling) know nothing of each other or of the
application (fsi); coupling knows no participant at all; no production package reaches into
the model problems (cases) or the benchmark scripts. Inside fsi the modules import each other
without cycles, and so do its rooms (each subpackage, and each module at its top level); each
room says in its docstring what it holds; no function or method of fsi is longer than
MAX_FUNCTION_LINES. Inside each solver package the modules import each other without cycles.

Every ``import`` and ``from ... import`` counts, at module level or inside a function, with
relative imports resolved against the importing module.
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("structure", "fluid", "coupling", "fsi", "cases")
SOLVERS = ("structure", "fluid", "coupling")
MAX_FUNCTION_LINES = 60

RULES = {
    "solver packages do not import each other":
        (SOLVERS, SOLVERS),
    "coupling imports nothing of ours":
        (("coupling",), ("structure", "fluid", "fsi", "cases", "benchmarks")),
    "solver packages do not import fsi":
        (SOLVERS, ("fsi",)),
    "production packages do not import cases or benchmarks":
        (SOLVERS + ("fsi",), ("cases", "benchmarks")),
}
"""Rule -> (importing top-level packages, top-level packages they must not import)."""


def _module_files(package: str) -> dict[str, Path]:
    """Dotted module name -> source file of every module of ``package`` (packages as their
    ``__init__``)."""
    files = {}
    for path in sorted((ROOT / package).rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        files[".".join(parts)] = path
    return files


MODULE_FILES = {name: path for package in PACKAGES for name, path in _module_files(package).items()}


def _imports(module: str, path: Path) -> list[tuple[int, str, tuple[str, ...]]]:
    """(line, imported module, names taken from it) of every import in ``path``, relative
    imports resolved (``from . import x`` gives the names ('x',) from the package)."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name, ()) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module
            found.append((node.lineno, target, tuple(alias.name for alias in node.names)))
    return sorted(found)


def _where(module: str, line: int) -> str:
    return f"{MODULE_FILES[module].relative_to(ROOT)}:{line}"


@pytest.mark.parametrize("rule", sorted(RULES))
def test_package_boundaries(rule):
    importers, forbidden = RULES[rule]
    offences = []
    for module, path in MODULE_FILES.items():
        top = module.split(".")[0]
        if top not in importers:
            continue
        for line, target, names in _imports(module, path):
            other = target.split(".")[0]
            if other in forbidden and other != top:
                what = f"from {target} import {', '.join(names)}" if names else f"import {target}"
                offences.append(f"{module} ({_where(module, line)}): {what}")
    if offences:
        pytest.fail(f"{rule}:\n  " + "\n  ".join(offences), pytrace=False)


# ------------------------------------------------------------------ inside fsi

def _fsi_graph() -> dict[str, dict[str, int]]:
    """fsi module -> {fsi module it imports: line of the first such import}. ``from A import
    b`` imports the module A.b when there is one, else A itself (a package as its
    ``__init__``)."""
    graph = {}
    for module, path in MODULE_FILES.items():
        if module.split(".")[0] != "fsi":
            continue
        edges = graph.setdefault(module, {})
        for line, target, names in _imports(module, path):
            if target.split(".")[0] != "fsi":
                continue
            for name in names or ("",):
                sub = f"{target}.{name}"
                dest = sub if sub in MODULE_FILES else target
                if dest in MODULE_FILES and dest != module:
                    edges.setdefault(dest, line)
    return graph


def _cycles(graph: dict[str, dict[str, int]]) -> list[list[str]]:
    """One cycle (first module repeated at its end) through each strongly connected component
    of more than one module (Tarjan)."""
    index, low, stack, on_stack, components = {}, {}, [], set(), []

    def visit(node):
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in sorted(graph.get(node, {})):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                components.append(set(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return [_cycle_in(graph, component) for component in components]


def _cycle_in(graph: dict[str, dict[str, int]], component: set[str]) -> list[str]:
    """Shortest cycle through the first (sorted) module of ``component`` (breadth first)."""
    start = min(component)
    paths = {start: [start]}
    frontier = [start]
    while frontier:
        following = []
        for node in frontier:
            for nxt in sorted(graph[node]):
                if nxt == start:
                    return paths[node] + [start]
                if nxt in component and nxt not in paths:
                    paths[nxt] = paths[node] + [nxt]
                    following.append(nxt)
        frontier = following
    raise AssertionError(f"no cycle through {start} in {sorted(component)}")


def test_fsi_modules_import_each_other_without_cycles():
    graph = _fsi_graph()
    reports = []
    for cycle in _cycles(graph):
        steps = [f"{a} -> {b} ({_where(a, graph[a][b])})" for a, b in zip(cycle, cycle[1:])]
        reports.append(" -> ".join(cycle) + "\n    " + "\n    ".join(steps))
    if reports:
        pytest.fail("import cycles among fsi modules:\n  " + "\n  ".join(reports), pytrace=False)


def _room(module: str) -> str:
    """The room of an fsi module: its subpackage (``fsi.sweep``) or, at fsi's top level,
    the module itself (``fsi.scene``)."""
    return ".".join(module.split(".")[:2])


def test_fsi_rooms_import_each_other_without_cycles():
    rooms: dict[str, dict[str, int]] = {}
    where: dict[tuple[str, str], str] = {}
    for module, edges in _fsi_graph().items():
        for dest, line in edges.items():
            a, b = _room(module), _room(dest)
            rooms.setdefault(b, {})
            if a != b:
                rooms.setdefault(a, {}).setdefault(b, line)
                where.setdefault((a, b), f"{module} -> {dest} ({_where(module, line)})")
    reports = [" -> ".join(cycle) + "\n    " + "\n    ".join(where[a, b] for a, b in zip(cycle, cycle[1:]))
               for cycle in _cycles(rooms)]
    if reports:
        pytest.fail("import cycles among fsi's rooms:\n  " + "\n  ".join(reports), pytrace=False)


def test_every_fsi_room_says_what_it_holds():
    silent = [name for name, path in MODULE_FILES.items()
              if name.count(".") == 1 and name.startswith("fsi.") and path.name == "__init__.py"
              and not (ast.get_docstring(ast.parse(path.read_text())) or "").strip()]
    assert not silent, f"rooms of fsi without a docstring: {silent}"


@pytest.mark.parametrize("package", SOLVERS)
def test_solver_modules_import_each_other_without_cycles(package):
    graph = {}
    for module, path in MODULE_FILES.items():
        if module.split(".")[0] != package:
            continue
        edges = graph.setdefault(module, {})
        for line, target, names in _imports(module, path):
            for name in names or ("",):
                sub = f"{target}.{name}"
                dest = sub if sub in MODULE_FILES else target
                if dest in MODULE_FILES and dest != module and dest.split(".")[0] == package \
                        and dest != package:
                    edges.setdefault(dest, line)
    cycles = _cycles(graph)
    assert not cycles, f"import cycles among {package} modules: {cycles}"


def test_fsi_functions_are_at_most_60_lines():
    offenders = []
    for module, path in MODULE_FILES.items():
        if module.split(".")[0] != "fsi":
            continue
        offenders += _long_functions(ast.parse(path.read_text(), str(path)), module)
    if offenders:
        pytest.fail(f"fsi functions longer than {MAX_FUNCTION_LINES} lines (def line to last "
                    "line of the body):\n  " + "\n  ".join(offenders), pytrace=False)


def _long_functions(tree: ast.AST, module: str, prefix: str = "") -> list[str]:
    """'file:line name is n lines' for every function or method under ``tree`` (nested ones
    included, named by their qualified name) longer than MAX_FUNCTION_LINES."""
    found = []
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            name = prefix + node.name
            if not isinstance(node, ast.ClassDef):
                length = node.end_lineno - node.lineno + 1
                if length > MAX_FUNCTION_LINES:
                    found.append(f"{_where(module, node.lineno)} {name} is {length} lines")
            found += _long_functions(node, module, name + ".")
        else:
            found += _long_functions(node, module, prefix)
    return found
