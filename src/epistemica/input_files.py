"""Which language a source file is written in, and reading it once for a command.

Spec files and mission files share the ``.epi`` extension. The rule: the first statement
decides. A file whose first statement is ``mission`` is a mission file; one whose first
statement is a keyword only the mission language has (``robot``, ``workspace``, ...) is a
mission file that lacks its ``mission`` line, refused by every command alike; anything
else is a spec file. Each command then says which kind it wants, so a spec given to
``run`` or a mission given to ``plan`` gets one sentence naming the right command instead
of a grammar error about the other language's keywords.
"""

from __future__ import annotations

import re
from pathlib import Path

from epistemica.del_.errors import SourceError
from epistemica.del_.spec import read_source

__all__ = ["MAX_MISSION_BYTES", "MAX_MISSION_TOKENS", "MISSION_ONLY", "file_kind", "read_input"]

#: Larger mission files are refused: the shipped ones are about 1 kB, and compiling costs
#: about 30 bytes of memory a byte of source (a 45 MB file of `check` lines reached
#: 1.35 GB), so this bounds a mission's compilation to some tens of MB.
MAX_MISSION_BYTES = 1 << 20
#: More tokens in a mission file are refused before it is parsed (``check_token_count``):
#: compiling a mission costs up to about 1.3 kB a token (a 1 MiB claim of a million
#: nested ``~`` peaked at 1.34 GB), so this bounds any mission near 330 MB; the shipped
#: missions hold at most a few hundred tokens.
MAX_MISSION_TOKENS = 250_000

#: Keywords that start a statement of the mission language and of no spec statement.
MISSION_ONLY = frozenset(
    ("valid", "workspace", "robot", "task", "sensing", "knows", "learns", "initially",
     "event", "teammate", "simulate")
)  # fmt: skip
_FIRST_WORD = re.compile(r"[^\s#]\S*")
_COMMENT_OR_SPACE = re.compile(r"(?:\s+|#[^\n]*)*")


def file_kind(text: str) -> tuple[str, str, int]:
    """``("mission" | "spec" | "headless", first word, its line)`` of a source text.

    ``"headless"``: a mission statement comes first, not ``mission``.

    Examples
    --------
    >>> file_kind("# a comment\\nmission rendezvous\\n")
    ('mission', 'mission', 2)
    >>> file_kind("robot r1: range at random\\n")
    ('headless', 'robot', 1)
    >>> file_kind("agents a, b\\n")[0]
    'spec'
    """
    start = _COMMENT_OR_SPACE.match(text).end()
    match = _FIRST_WORD.match(text, start)
    if match is None:
        return "spec", "", 1
    word = re.split(r"[^A-Za-z0-9_]", match.group(0))[0]
    line = text.count("\n", 0, start) + 1
    if word == "mission":
        return "mission", word, line
    if word in MISSION_ONLY:
        return "headless", word, line
    return "spec", word, line


def read_input(path: str | Path, command: str, accepts: tuple[str, ...] = ("spec",)) -> tuple:
    """``(kind, text)`` of the file at ``path``, read once, for ``command``.

    ``accepts`` lists the kinds the command reads (``"spec"``, ``"mission"``).

    Raises
    ------
    SourceError
        The file cannot be read (see :func:`~epistemica.del_.spec.read_source`),
        lacks its ``mission`` line, or is of a kind the command does not read.
    """
    what = " or ".join(f"{k} file" for k in accepts)
    text = read_source(path, what)
    kind, word, line = file_kind(text)
    where = {"line": line, "column": 1, "source": text, "filename": str(path)}
    if kind == "headless":
        raise SourceError(
            f"this looks like a mission file, but its first statement is '{word}', not 'mission'",
            hint="start a mission file with its kind, e.g. 'mission rendezvous' (rendezvous, "
            "allocation, capacity or multitask); a spec file starts with 'agents'",
            **where,
        )
    if kind != "spec" and len(text.encode("utf-8")) > MAX_MISSION_BYTES:
        raise SourceError(
            f"the mission file is larger than the limit of {MAX_MISSION_BYTES:,} bytes",
            filename=str(path),
            hint="a mission states its robots, goals and claims in a few kB; generate "
            "fewer 'check' lines",
        )
    if kind not in accepts:
        if kind == "mission":
            message, use = "this is a mission file", "use 'epistemica run' or 'epistemica check'"
        else:
            message = "this is a spec file, not a mission file (it does not start with 'mission')"
            use = "use 'epistemica check', 'plan' or 'show'"
        raise SourceError(f"{message}; '{command}' reads {what}s", hint=use, **where)
    return kind, text
