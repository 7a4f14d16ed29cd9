"""The documentation's code runs as written: every ``>>>`` example of README.md and
docs/*.md (``python -m doctest FILE`` passes), and every other Python block, from the
repository's root (where the blocks' paths, ``specs/...``, point); every documented
``epistemica`` command parses (and runs: tests/test_docs_commands.py)."""

from __future__ import annotations

import doctest
import re
import shlex
from pathlib import Path

import pytest

from epistemica.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]
# results.md and architecture.md hold measured reports and diagrams, not examples.
DOCS = [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").glob("*.md"))]
BLOCK = re.compile(r"```python\n(.*?)```", re.S)


def _blocks() -> list[tuple[Path, int, str]]:
    out = []
    for path in DOCS:
        text = path.read_text(encoding="utf-8")
        for match in BLOCK.finditer(text):
            if ">>>" not in match.group(1):
                out.append((path, text[: match.start()].count("\n") + 1, match.group(1)))
    return out


@pytest.mark.parametrize("path", DOCS, ids=lambda p: p.name)
def test_doctest_examples_in_the_docs_pass(path, monkeypatch):
    monkeypatch.chdir(ROOT)
    result = doctest.testfile(str(path), module_relative=False, verbose=False)
    assert result.failed == 0, f"{path.name}: {result.failed} of {result.attempted} failed"


@pytest.mark.parametrize(
    ("path", "line", "code"), _blocks(), ids=lambda v: v.name if isinstance(v, Path) else ""
)
def test_python_blocks_in_the_docs_run(path, line, code, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    if "epistemica.sim.engine.env" in code or "epistemica.envs" in code:
        pytest.importorskip("gymnasium")
        pytest.importorskip("pettingzoo")
    exec(compile(code, f"{path.name}:{line}", "exec"), {"__name__": "__docs__"})


def documented_commands() -> list[tuple[Path, int, str]]:
    """Every ``epistemica ...`` line of the docs' bash blocks (continuations joined, the
    comment cut), except those with placeholders (``...``, ``HOST``)."""
    out = []
    for path in DOCS:
        text = path.read_text(encoding="utf-8")
        for match in re.finditer(r"```bash\n(.*?)```", text, re.S):
            first = text[: match.start()].count("\n") + 2
            joined = re.sub(r"\\\n\s*", " ", match.group(1))
            for k, line in enumerate(joined.splitlines()):
                command = line.split(" # ")[0].split("&&")[-1].strip()
                if command.startswith("epistemica ") and "..." not in command:
                    if not re.search(r"\b(HOST|FILE|SEED|PATH)\b", command):
                        out.append((path, first + k, command))
    return out


@pytest.mark.parametrize(
    ("path", "line", "command"),
    documented_commands(),
    ids=lambda v: v.name if isinstance(v, Path) else "",
)
def test_documented_commands_parse(path, line, command):
    """Each documented command's options exist as written, exactly (tests/test_docs_commands.py
    runs them all, at one trial per cell)."""
    argv = shlex.split(command)[1:]
    try:
        build_parser().parse_args(argv)
    except SystemExit as exc:
        pytest.fail(f"{path.name}:{line}: {command!r} does not parse (exit {exc.code})")
