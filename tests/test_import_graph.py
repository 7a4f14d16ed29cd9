"""The structure of the package: imports point one way, and no module reaches into another's
private parts.

Every module of the four folders that make up ``epistemica`` (``del/``, ``aif/``, ``sim/``,
``src/epistemica/``) is parsed with :mod:`ast` (nothing is imported), so the checks also run
on another checkout: ``EPISTEMICA_SOURCE=/path/to/checkout pytest tests/test_import_graph.py``.

- The graph of imports between project modules (``if TYPE_CHECKING:`` blocks left out, as
  they never run) has no cycle. Importing ``a.b.c`` first runs ``a/__init__.py`` and
  ``a/b/__init__.py``, so those edges are in the graph too. A module imported by name
  (``importlib.import_module``, ``__import__``) is an edge too: a name written in the
  module, or one of a table of modules it loads by name (the command-line dispatcher's
  ``COMMANDS`` in ``cli/__init__.py``, del/'s lazy exports), so that start-up stays short;
  an import by a name the test cannot read is flagged.
- Layers import only the layers before them: ``del_ <- aif <- sim <- root``.
- No ``import`` of a project module sits inside a function: a deferred import hides an
  edge of the graph (the usual way a cycle is papered over). Optional third-party
  libraries (matplotlib, distributed, ...) may be imported lazily.
- No module of ``del/`` imports names from the package ``epistemica.del_`` itself (its
  ``__init__`` only re-exports).
- No attribute ``x._name`` is read or written with ``x`` other than ``self`` or ``cls``
  (named tuples' public API, ``_replace`` and the like, excepted), no module imports a
  private name (``from m import _name``) of another module, and a private module
  (``_name.py``) is imported only by modules of its own layer.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path

import networkx as nx
import pytest

SOURCE = Path(os.environ.get("EPISTEMICA_SOURCE") or Path(__file__).resolve().parents[1])
#: Package name -> folder, in layer order: a layer imports only the layers before it.
LAYERS = (
    ("epistemica.del_", SOURCE / "del"),
    ("epistemica.aif", SOURCE / "aif"),
    ("epistemica.sim", SOURCE / "sim"),
    ("epistemica", SOURCE / "src" / "epistemica"),
)
#: Named tuples keep their public API underscore-prefixed, to keep field names free.
NAMED_TUPLE_API = {"_replace", "_asdict", "_fields", "_make", "_field_defaults"}


def _module_name(package: str, folder: Path, path: Path) -> str:
    parts = list(path.relative_to(folder).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join([package, *parts])


def _modules() -> dict[str, tuple[Path, ast.Module]]:
    found = {}
    for package, folder in LAYERS:
        for path in sorted(folder.rglob("*.py")):
            name = _module_name(package, folder, path)
            found[name] = (path, ast.parse(path.read_text(), filename=str(path)))
    return found


MODULES = _modules()


def _layer(module: str) -> int:
    """The index in LAYERS of the package a module belongs to (the longest prefix)."""
    best = -1
    for index, (package, _) in enumerate(LAYERS):
        if (module == package or module.startswith(package + ".")) and (
            best < 0 or len(package) > len(LAYERS[best][0])
        ):
            best = index
    return best


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
    """The project modules an import names, each with the names taken from it."""
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


def _registry_targets(module: str, tree: ast.Module) -> list[str]:
    """The modules named in a module-level table loaded by name: a dict literal whose string
    keys or values name project modules, absolutely (``"module:function"``: the command-line
    dispatcher's ``COMMANDS``) or relative to a package (del/'s lazy ``_SOURCES``)."""
    found = []
    for node in tree.body:
        value = node.value if isinstance(node, (ast.Assign, ast.AnnAssign)) else None
        if not isinstance(value, ast.Dict):
            continue
        for item in [*value.keys, *value.values]:
            if isinstance(item, ast.Constant) and isinstance(item.value, str):
                name = item.value.partition(":")[0]
                relative = f"{module}.{name}" if _is_package(module) else ""
                found += [m for m in (name, relative) if m in MODULES and m != module]
    return found


#: Calls that import a module by name.
DYNAMIC = ("import_module", "__import__")


def _dynamic_imports(module: str, tree: ast.Module) -> tuple[list[str], list[str]]:
    """The project modules imported by name (``importlib.import_module``, ``__import__``)
    whose name is written in the module (a literal, or a module-level string constant), and
    the call sites whose target cannot be read so. A call whose module keeps a table of
    the modules it loads (:func:`_registry_targets`) is read through the table, and a
    package may load its own submodules (``f"{__name__}.{name}"``) on attribute access."""
    constants = {
        target.id: node.value.value
        for node in tree.body
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Constant)
        for target in node.targets
        if isinstance(target, ast.Name) and isinstance(node.value.value, str)
    }
    has_table = bool(_registry_targets(module, tree))
    edges, unread = [], []
    for call in ast.walk(tree):
        if not isinstance(call, ast.Call):
            continue
        func = call.func
        name = getattr(func, "attr", None) or getattr(func, "id", None)
        if name not in DYNAMIC or not call.args:
            continue
        arg = call.args[0]
        text = arg.value if isinstance(arg, ast.Constant) else None
        if isinstance(arg, ast.Name):
            text = constants.get(arg.id)
        if isinstance(text, str):
            if text.split(".")[0] != "epistemica":
                continue  # a third-party library, loaded when first needed
            if text in MODULES:
                edges.append(text)
                continue
        own_submodule = (
            isinstance(arg, ast.JoinedStr)
            and _is_package(module)
            and "__name__" in ast.unparse(arg.values[0])
        )
        if not (own_submodule or has_table):
            unread.append(f"{module}:{call.lineno} {ast.unparse(call)}")
    return edges, unread


def _ancestors(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts)) if ".".join(parts[:i]) in MODULES]


def import_graph() -> tuple[nx.DiGraph, list[str]]:
    """The import graph of the project and the imports of names from del/'s package root."""
    graph = nx.DiGraph()
    graph.add_nodes_from(MODULES)
    from_root = []
    for module, (_, tree) in MODULES.items():
        edges = [edge for node in _runtime_imports(tree) for edge in _targets(module, node)]
        edges += [(target, []) for target in _registry_targets(module, tree)]
        edges += [(target, []) for target in _dynamic_imports(module, tree)[0]]
        for target, names in edges:
            if target == "epistemica.del_" and names and _layer(module) == 0:
                from_root.append(f"{module}: from epistemica.del_ import {', '.join(names)}")
            # importing a submodule first runs its packages' __init__ (the importer's
            # own packages have run already)
            for package in [*_ancestors(target), target]:
                if package != module and package not in _ancestors(module):
                    graph.add_edge(module, package)
    return graph, from_root


def test_every_layer_is_found():
    layers = {_layer(m) for m in MODULES}
    assert layers == set(range(len(LAYERS)))
    assert "epistemica.del_.errors" in MODULES and "epistemica.sim.engine.simulate" in MODULES


def test_no_import_cycle():
    graph, _ = import_graph()
    cycles = list(nx.simple_cycles(graph))
    shortest = sorted(cycles, key=len)[:5]
    assert not cycles, f"{len(cycles)} import cycles, e.g. " + "; ".join(
        " -> ".join([*c, c[0]]) for c in shortest
    )


def test_layers_import_only_the_layers_before_them():
    graph, _ = import_graph()
    # every import of a subpackage first runs the root's __init__ (lazy re-exports only)
    upward = [f"{a} -> {b}" for a, b in graph.edges if _layer(b) > _layer(a) and b != "epistemica"]
    assert not upward, "imports against the layers:\n" + "\n".join(sorted(upward))


def test_every_import_by_name_of_a_project_module_is_an_edge_of_the_graph():
    unread = [
        site for module, (_, tree) in MODULES.items() for site in _dynamic_imports(module, tree)[1]
    ]
    assert not unread, "imports by a name the graph cannot read:\n" + "\n".join(unread)
    graph, _ = import_graph()
    assert graph.has_edge("epistemica", "epistemica.mission")  # the root's lazy re-exports
    assert graph.has_edge("epistemica.cli", "epistemica.cli.run")  # the dispatcher's table


def test_an_import_by_a_computed_name_is_flagged():
    tree = ast.parse("import importlib\ndef load(n):\n    return importlib.import_module(n)\n")
    assert _dynamic_imports("epistemica.run", tree)[1] == [
        "epistemica.run:3 importlib.import_module(n)"
    ]
    tree = ast.parse("__import__('epistemica.mission')\n")
    assert _dynamic_imports("epistemica.run", tree) == (["epistemica.mission"], [])


def test_no_del_module_imports_from_its_package_root():
    _, from_root = import_graph()
    assert not from_root, "\n".join(from_root)


@pytest.mark.parametrize(
    "layer",
    [
        *(package for package, _ in LAYERS[:-1]),
        "epistemica",
    ],
)
def test_no_project_import_inside_a_function(layer):
    found = []
    for module, (_, tree) in MODULES.items():
        if LAYERS[_layer(module)][0] != layer:
            continue
        for function in ast.walk(tree):
            if isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                for node in ast.walk(function):
                    if isinstance(node, (ast.Import, ast.ImportFrom)):
                        if _targets(module, node) or _absolute_names(module, node):
                            found.append(f"{module}:{node.lineno}")
    assert not found, f"project imports inside functions: {', '.join(sorted(set(found)))}"


def _absolute_names(module: str, node: ast.Import | ast.ImportFrom) -> bool:
    """Whether an import names the project (``epistemica`` itself included)."""
    if isinstance(node, ast.Import):
        return any(a.name.split(".")[0] == "epistemica" for a in node.names)
    return bool(node.level) or (node.module or "").split(".")[0] == "epistemica"


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def test_no_private_attribute_of_another_object():
    found = []
    for module, (_, tree) in MODULES.items():
        for node in ast.walk(tree):
            if not isinstance(node, ast.Attribute) or not _private(node.attr):
                continue
            owner = node.value
            if isinstance(owner, ast.Name) and owner.id in ("self", "cls"):
                continue
            if node.attr in NAMED_TUPLE_API:
                continue
            found.append(f"{module}:{node.lineno} {ast.unparse(owner)}.{node.attr}")
    assert not found, f"{len(found)} private accesses:\n" + "\n".join(found)


def test_no_private_import_from_another_module():
    found = []
    for module, (_, tree) in MODULES.items():
        for node in _runtime_imports(tree):
            for target, names in _targets(module, node):
                private_module = _private(target.rsplit(".", 1)[-1])
                if private_module and _layer(target) != _layer(module):
                    found.append(f"{module}:{node.lineno} imports private module {target}")
                for name in names:
                    if _private(name):
                        found.append(f"{module}:{node.lineno} imports {target}.{name}")
    assert not found, f"{len(found)} private imports:\n" + "\n".join(found)


def test_a_type_checking_block_is_not_a_runtime_import():
    code = "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import a\nelse:\n    import b"
    names = [alias.name for node in _runtime_imports(ast.parse(code)) for alias in node.names]
    assert sorted(names) == ["TYPE_CHECKING", "b"]


#: sim/'s subpackages by rank in docs/architecture.md's drawing: each imports only ranks
#: up to its own (``kinds`` and ``engine`` read each other's modules, without a cycle).
SIM_RANK = {"kinds": 0, "engine": 0, "policies": 1, "study": 2}
#: The imports up that drawing that the map names: the one loop takes a level's name, and
#: the Gymnasium / PettingZoo adapters build levels and draw with the figures.
SIM_UPWARD = {
    ("engine.simulate", "policies.levels"),
    ("engine.simulate", "policies.parameters"),
    ("engine.simulate", "policies.policy"),
    ("engine._env_checks", "policies.policy"),
    ("engine.env", "policies.levels"),
    ("engine.env", "study.figures"),
}


def _sim_module(name: str) -> str | None:
    parts = name.split(".")
    if parts[:2] != ["epistemica", "sim"] or len(parts) < 4 or parts[2] not in SIM_RANK:
        return None
    return ".".join(parts[2:])


def test_sim_subpackages_import_down_the_drawing_but_for_the_named_adapters():
    graph, _ = import_graph()
    upward = set()
    for a, b in graph.edges:
        source, target = _sim_module(a), _sim_module(b)
        if source and target:
            if SIM_RANK[target.split(".")[0]] > SIM_RANK[source.split(".")[0]]:
                upward.add((source, target))
    assert upward == SIM_UPWARD, (
        f"new: {sorted(upward - SIM_UPWARD)}; gone (update SIM_UPWARD and the map): "
        f"{sorted(SIM_UPWARD - upward)}"
    )
