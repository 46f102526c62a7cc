"""
The modules of the three Python packages import one another without a cycle (issue 15).

The graph is read from the source with ``ast``: every ``import`` of every module, those inside
functions too (an import moved into a function hides a circle from the interpreter, it does not
remove it). ``import a.b`` and ``from a.b import c`` are edges to the module ``a.b.c`` when it
exists, else to ``a.b`` (a package's ``__init__``); relative imports are resolved against the
importing module's package. Imports of other libraries are not edges. The parent packages that
Python runs before a submodule are not edges either: a package that gathers its submodules in
its ``__init__`` is the usual layout, and a submodule that needs its package's names says so
with an explicit import, which is an edge.
"""
import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / 'ros2_ws' / 'src'
PACKAGES = ('robotica_kin', 'robotica_ctrl', 'robotica_sim')


def module_files() -> dict[str, Path]:
    """Return every module of the packages by dotted name (a package by its own name)."""
    modules = {}
    for package in PACKAGES:
        root = SRC / package
        for path in sorted((root / package).rglob('*.py')):
            parts = path.relative_to(root).with_suffix('').parts
            modules['.'.join(p for p in parts if p != '__init__')] = path
    return modules


def imported_modules(name: str, path: Path, modules: set[str]) -> set[str]:
    """Return the modules of ``modules`` that the module ``name`` at ``path`` imports."""
    is_package = path.name == '__init__.py'
    targets: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding='utf-8'), str(path))):
        if isinstance(node, ast.Import):
            targets.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ''
            if node.level:
                package = name.split('.')
                anchor = package[:len(package) - node.level + (1 if is_package else 0)]
                base = '.'.join(anchor + ([base] if base else []))
            for alias in node.names:
                targets.add(f'{base}.{alias.name}' if f'{base}.{alias.name}' in modules
                            else base)
    edges = set()
    for target in targets:
        while target and target not in modules:     # a name inside a module: that module
            target = target.rpartition('.')[0]
        if target and target != name:
            edges.add(target)
    return edges


def import_graph() -> dict[str, set[str]]:
    """Return the import graph of the packages: module -> modules it imports."""
    files = module_files()
    names = set(files)
    return {name: imported_modules(name, path, names) for name, path in files.items()}


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """Return one cycle of ``graph`` as a path ``[a, b, ..., a]``, or None (depth-first)."""
    state: dict[str, int] = {}     # 1: on the current path, 2: finished
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for succ in sorted(graph.get(node, ())):
            if state.get(succ) == 1:
                return path[path.index(succ):] + [succ]
            if succ not in state:
                cycle = visit(succ)
                if cycle:
                    return cycle
        path.pop()
        state[node] = 2
        return None

    for start in sorted(graph):
        if start not in state:
            cycle = visit(start)
            if cycle:
                return cycle
    return None


def test_cycle_finder_finds_a_circle_and_accepts_a_diamond():
    assert find_cycle({'a': {'b'}, 'b': {'c'}, 'c': {'a'}}) == ['a', 'b', 'c', 'a']
    assert find_cycle({'a': {'b', 'c'}, 'b': {'d'}, 'c': {'d'}, 'd': set()}) is None


def test_graph_is_read_from_the_source():
    graph = import_graph()
    # Known edges, one of each kind: absolute, relative, and a package's re-export.
    assert 'robotica_kin.dh' in graph['robotica_kin.pinocchio_model']
    assert 'robotica_ctrl.joint_control.law' in graph[
        'robotica_ctrl.joint_control.computed_torque']
    assert 'robotica_ctrl.joint_control.computed_torque' in graph['robotica_ctrl.joint_control']
    assert len(graph) > 50


def test_module_import_graph_has_no_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, 'import cycle: ' + ' -> '.join(cycle or [])
