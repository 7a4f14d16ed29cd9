"""The structure of ``del/``: imports point one way, and no module reaches into another's
private fields.

Every module of the package is parsed with :mod:`ast` (nothing is imported), so the
checks also run on another checkout: ``EPISTEMICA_DEL_DIR=/path/to/del pytest
tests/del/test_import_graph.py``.

- The graph of imports between ``del/`` modules (relative or absolute, ``if
  TYPE_CHECKING:`` blocks left out as they never run) has no cycle. Importing
  ``epistemica.del_.a.b`` first runs ``a/__init__.py``, so that edge is in the graph too.
- No ``import`` statement sits inside a function: a deferred import hides an edge of the
  graph (the usual way a cycle is papered over).
- No module imports names from the package ``epistemica.del_`` itself (its ``__init__``
  only re-exports; modules import the submodule that defines a name).
- No attribute ``x._name`` is read or written with ``x`` other than ``self`` or ``cls``:
  models and actions are used through their documented interface.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path

import networkx as nx

import epistemica.del_

ROOT_PACKAGE = "epistemica.del_"
DEL_DIR = Path(os.environ.get("EPISTEMICA_DEL_DIR") or Path(epistemica.del_.__file__).parent)

# (module, expression, attribute) triples allowed to touch a private attribute, each with
# the reason. Add an entry only with a comment that justifies it.
ALLOWED_PRIVATE: set[tuple[str, str, str]] = {
    # NamedTuple's public API is underscore-prefixed (to keep field names free)
    ("epistemica.del_.spec._document", "parts", "_asdict"),
}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(DEL_DIR).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join([ROOT_PACKAGE, *parts])


def _modules() -> dict[str, tuple[Path, ast.Module]]:
    found = {}
    for path in sorted(DEL_DIR.rglob("*.py")):
        found[_module_name(path)] = (path, ast.parse(path.read_text(), filename=str(path)))
    return found


MODULES = _modules()


def _is_package(name: str) -> bool:
    return MODULES[name][0].name == "__init__.py"


def _type_checking_block(node: ast.AST) -> bool:
    test = getattr(node, "test", None)
    return isinstance(node, ast.If) and (
        (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING")
        or (isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")
    )


def _runtime_imports(tree: ast.Module):
    """Every import statement that runs, skipping ``if TYPE_CHECKING:`` blocks."""
    stack = list(tree.body)
    while stack:
        node = stack.pop()
        if _type_checking_block(node):
            stack.extend(node.orelse)
            continue
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        stack.extend(ast.iter_child_nodes(node))


def _absolute(module: str, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".")
    if not _is_package(module):
        base.pop()
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _targets(module: str, node: ast.Import | ast.ImportFrom) -> list[tuple[str, list[str]]]:
    """The del/ modules an import names, each with the names taken from it."""
    if isinstance(node, ast.Import):
        return [(alias.name, []) for alias in node.names if alias.name in MODULES]
    source = _absolute(module, node)
    if source not in MODULES:
        return []
    targets, names = [], []
    for alias in node.names:
        sub = f"{source}.{alias.name}"
        if sub in MODULES:
            targets.append((sub, []))
        else:
            names.append(alias.name)
    if names:
        targets.append((source, names))
    return targets


def _ancestors(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(2, len(parts))]


def import_graph() -> tuple[nx.DiGraph, list[str]]:
    """The import graph of del/ and the imports of names from the package root."""
    graph = nx.DiGraph()
    graph.add_nodes_from(MODULES)
    from_root = []
    for module, (_, tree) in MODULES.items():
        for node in _runtime_imports(tree):
            for target, names in _targets(module, node):
                if target == ROOT_PACKAGE and names:
                    from_root.append(f"{module}: from {ROOT_PACKAGE} import {', '.join(names)}")
                # importing a submodule first runs its packages' __init__ (the importer's
                # own packages have run already)
                for package in [*_ancestors(target), target]:
                    if package != module and package not in _ancestors(module):
                        graph.add_edge(module, package)
    return graph, from_root


def test_the_del_package_is_found():
    assert len(MODULES) > 20 and f"{ROOT_PACKAGE}.errors" in MODULES


def test_no_import_cycle_among_del_modules():
    graph, _ = import_graph()
    cycles = list(nx.simple_cycles(graph))
    shortest = sorted(cycles, key=len)[:5]
    assert not cycles, f"{len(cycles)} import cycles, e.g. " + "; ".join(
        " -> ".join([*c, c[0]]) for c in shortest
    )


def test_no_module_imports_from_the_package_root():
    _, from_root = import_graph()
    assert not from_root, "\n".join(from_root)


def test_no_import_inside_a_function():
    found = []
    for module, (_, tree) in MODULES.items():
        for function in ast.walk(tree):
            if isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                for node in ast.walk(function):
                    if isinstance(node, (ast.Import, ast.ImportFrom)):
                        found.append(f"{module}:{node.lineno}")
    assert not found, f"imports inside functions: {', '.join(sorted(set(found)))}"


def test_no_private_attribute_of_another_object():
    found = []
    for module, (_, tree) in MODULES.items():
        for node in ast.walk(tree):
            if not isinstance(node, ast.Attribute):
                continue
            name = node.attr
            if not name.startswith("_") or (name.startswith("__") and name.endswith("__")):
                continue
            owner = node.value
            if isinstance(owner, ast.Name) and owner.id in ("self", "cls"):
                continue
            key = (module, ast.unparse(owner), name)
            if key not in ALLOWED_PRIVATE:
                found.append(f"{module}:{node.lineno} {key[1]}.{name}")
    assert not found, f"{len(found)} private accesses:\n" + "\n".join(found)


def test_a_type_checking_block_is_not_a_runtime_import():
    guarded = ast.parse(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import a\nelse:\n    import b\n"
    )
    names = [alias.name for node in _runtime_imports(guarded) for alias in node.names]
    assert sorted(names) == ["TYPE_CHECKING", "b"]
