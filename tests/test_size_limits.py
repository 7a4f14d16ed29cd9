"""Size limits of the source, checked rather than claimed (issue 35).

No module of the four folders that make up ``epistemica`` (``del/``, ``aif/``, ``sim/``,
``src/epistemica/``) is longer than :data:`MODULE_LINES` lines, no class longer than
:data:`CLASS_LINES`, no function or method longer than :data:`FUNCTION_LINES`. A class or
function counts from its ``def``/``class`` line (decorators left out) to its last line,
docstring included; a module counts every line of its file. Files are parsed with
:mod:`ast`, nothing is imported, so this also runs on another checkout:
``EPISTEMICA_SOURCE=/path/to/checkout pytest tests/test_size_limits.py``.

Run as a script, it lists every item over its limit, allowed or not::

    python tests/test_size_limits.py

:data:`ALLOWED` names the items still over, each with the reason. The test fails when an item
not in it goes over (a new one), and when an allowed item is back under its limit (so that
the list only shrinks).
"""

from __future__ import annotations

import ast
import os
from collections.abc import Iterator
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("EPISTEMICA_SOURCE") or Path(__file__).resolve().parents[1])
FOLDERS = ("del", "aif", "sim", "src/epistemica")
MODULE_LINES = 500
CLASS_LINES = 300
FUNCTION_LINES = 80

#: Items over their limit today, by the key :func:`oversized` gives them, and why (none:
#: an entry is added only with a reason, and removed when the item is back within).
ALLOWED: dict[str, str] = {}


def _limit(kind: str) -> int:
    return {"module": MODULE_LINES, "class": CLASS_LINES, "function": FUNCTION_LINES}[kind]


def measure(text: str, path: str) -> Iterator[tuple[str, str, int]]:
    """Yield ``(kind, key, lines)`` for the module in ``text`` and every class and function.

    ``key`` is ``path`` for the module and ``path::Outer.inner`` for a definition inside it.
    """
    yield "module", path, len(text.splitlines())
    tree = ast.parse(text, filename=path)
    stack: list[tuple[ast.AST, str]] = [(tree, "")]
    while stack:
        node, prefix = stack.pop()
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
                name = prefix + child.name
                kind = "class" if isinstance(child, ast.ClassDef) else "function"
                assert child.end_lineno is not None
                yield kind, f"{path}::{name}", child.end_lineno - child.lineno + 1
                stack.append((child, name + "."))
            else:
                stack.append((child, prefix))


def oversized(source: Path = SOURCE) -> dict[str, tuple[str, int]]:
    """Every module, class and function of the package over its limit: key -> (kind, lines)."""
    found = {}
    for folder in FOLDERS:
        for path in sorted((source / folder).rglob("*.py")):
            relative = path.relative_to(source).as_posix()
            for kind, key, lines in measure(path.read_text(), relative):
                if lines > _limit(kind):
                    found[key] = (kind, lines)
    return found


def test_measure_counts_definitions_from_their_first_line_to_their_last() -> None:
    text = "\n".join(
        [
            "import os",  # 1
            "class A:",  # 2
            "    @staticmethod",  # 3
            "    def f():",  # 4
            "        def g():",  # 5
            "            return 1",  # 6
            "        return g",  # 7
            "",  # 8
            "async def h():",  # 9
            "    pass",  # 10
        ]
    )
    assert sorted(measure(text, "m.py")) == [
        ("class", "m.py::A", 6),
        ("function", "m.py::A.f", 4),
        ("function", "m.py::A.f.g", 2),
        ("function", "m.py::h", 2),
        ("module", "m.py", 10),
    ]


def test_a_definition_inside_a_branch_is_measured_too() -> None:
    text = "if True:\n    def f():\n" + "        x = 1\n" * 81
    assert ("function", "m.py::f", 82) in set(measure(text, "m.py"))


@pytest.fixture(scope="module")
def over() -> dict[str, tuple[str, int]]:
    return oversized()


def test_no_new_item_goes_over_its_limit(over: dict[str, tuple[str, int]]) -> None:
    new = {key: value for key, value in over.items() if key not in ALLOWED}
    assert not new, "over the size limits, split along concepts: " + ", ".join(
        f"{key} ({kind}, {lines} lines)" for key, (kind, lines) in sorted(new.items())
    )


def test_every_allowed_item_is_still_over(over: dict[str, tuple[str, int]]) -> None:
    stale = sorted(set(ALLOWED) - set(over))
    assert not stale, "now within the limits, remove from ALLOWED: " + ", ".join(stale)


if __name__ == "__main__":
    for key, (kind, lines) in sorted(oversized().items()):
        mark = "allowed" if key in ALLOWED else "NEW"
        print(f"{lines:5d} {kind:8s} {key}  [{mark}]")
