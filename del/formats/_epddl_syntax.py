"""The front end of EPDDL files: the lark grammar ``epddl.lark`` and located syntax errors.

:func:`parse` turns the text of an EPDDL domain, problem or action-type library into a lark
tree and reports malformed text as a :class:`~epistemica.del_.errors.ParseError` naming
the file, line and column, what was expected, with the line, a caret and a hint. The
trees are compiled by :mod:`epistemica.del_.formats._epddl_ground`.

Examples
--------
>>> tree = parse("(define (domain d) (:predicates (p)))", "d.epddl")
>>> str(tree.data), str(tree.children[0]), str(tree.children[1].data)
('domain', 'd', 'predicates')
>>> parse("(define (domain d) (:predicate (p)))", "d.epddl")
Traceback (most recent call last):
...
epistemica.del_.errors.ParseError: d.epddl:1:21: error: unknown keyword ':predicate'
    (define (domain d) (:predicate (p)))
                        ^
hint: did you mean ':predicates'?
"""

from __future__ import annotations

import difflib
import functools
from dataclasses import dataclass
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from epistemica.del_.errors import ParseError, SpecError

__all__ = ["EPDDL_GRAMMAR", "Source", "mangle", "parse", "position"]

#: Path of the grammar file of EPDDL.
EPDDL_GRAMMAR = Path(__file__).with_name("epddl.lark")

# The keywords that open a section, for "did you mean" hints.
_SECTIONS = (
    ":action-type-libraries", ":requirements", ":types", ":constants", ":predicates",
    ":event", ":action", ":objects", ":agents", ":agent-groups", ":init", ":facts-init",
    ":goal", ":action-type", ":parameters", ":precondition", ":effects",
    ":observability-conditions", ":events", ":observability-types", ":relations",
    ":designated", ":conditions", ":worlds", ":labels", ":domain", ":and", ":forall",
)  # fmt: skip

_WORDS = {
    "LPAR": "'('", "RPAR": "')'", "LSQB": "'['", "RSQB": "']'", "LESSTHAN": "'<'",
    "MORETHAN": "'>'", "NAME": "a name", "VARIABLE": "a variable such as ?x",
    "MODALITY": "'C.' or 'Kw.'", "REQUIREMENT": "a requirement such as :typing",
    "EVENT_CONDITION": "an event condition such as :trivial-event", "ALL": "'All'",
    "VBAR": "'|'", "MINUS": "'-'", "EQUAL": "'='", "$END": "the end of the file",
}  # fmt: skip


@dataclass(frozen=True)
class Source:
    """One EPDDL text and where it came from (for located errors)."""

    text: str
    filename: str

    def error(self, message: str, where: Token | Tree | None, hint: str | None = None):
        """A :class:`SpecError` located at ``where`` (a token or a tree) in this text."""
        line, column = position(where) if where is not None else (None, None)
        return SpecError(
            message, line=line, column=column, source=self.text, filename=self.filename,
            hint=hint,
        )  # fmt: skip


def parse(text: str, filename: str) -> Tree:
    """Parse one EPDDL file (a domain, a problem or a library) into its lark tree.

    Raises
    ------
    ParseError
        Located at the offending character or token, with a hint.
    """
    try:
        return _lark().parse(text).children[0]
    except UnexpectedInput as exc:
        raise _syntax_error(exc, text, filename) from None


def position(item: Token | Tree) -> tuple[int | None, int | None]:
    """Line and column of a token or of a tree (its first token), if known."""
    if isinstance(item, Token):
        return item.line, item.column
    meta = item.meta
    return getattr(meta, "line", None), getattr(meta, "column", None)


def mangle(name: str) -> str:
    """An EPDDL name as an epistemica name (``-`` becomes ``_``)."""
    return name.replace("-", "_")


@functools.cache
def _lark() -> Lark:
    return Lark.open(
        str(EPDDL_GRAMMAR), parser="lalr", propagate_positions=True, maybe_placeholders=True
    )


def _syntax_error(exc: UnexpectedInput, text: str, filename: str) -> ParseError:
    where = {"source": text, "filename": filename}
    if isinstance(exc, UnexpectedCharacters):
        char = text[exc.pos_in_stream] if exc.pos_in_stream < len(text) else ""
        return ParseError(
            f"unexpected character '{char}'", line=exc.line, column=exc.column, **where,
            hint="EPDDL names use letters, digits, '_' and '-'; comments start with ';'",
        )  # fmt: skip
    if isinstance(exc, UnexpectedEOF) or (
        isinstance(exc, UnexpectedToken) and exc.token.type == "$END"
    ):
        lines = text.rstrip().splitlines() or [""]
        return ParseError(
            "unexpected end of the file", line=len(lines), column=len(lines[-1]) + 1, **where,
            hint=f"{_depth(text)} parenthes{'is is' if _depth(text) == 1 else 'es are'} "
            "left open; close every '(' with ')'",
        )  # fmt: skip
    assert isinstance(exc, UnexpectedToken)
    token = exc.token
    expected = sorted(exc.accepts or exc.expected)
    found = f"'{token}'"
    if token.type == "REQUIREMENT":
        close = difflib.get_close_matches(str(token), _SECTIONS, n=1)
        hint = f"did you mean '{close[0]}'?" if close else _expected_hint(expected)
        return ParseError(
            f"unknown keyword '{token}'", line=token.line, column=token.column, **where,
            hint=hint if close else f"expected {_describe(expected)} here",
        )  # fmt: skip
    return ParseError(
        f"expected {_describe(expected)}, found {found}",
        line=token.line, column=token.column, **where, hint=_expected_hint(expected),
    )  # fmt: skip


def _describe(expected: list[str]) -> str:
    words = []
    for name in expected:
        word = _WORDS.get(name) or _spelling(name)
        if word not in words:
            words.append(word)
    if len(words) > 6:
        return ", ".join(words[:6]) + ", ..."
    if len(words) > 1:
        return ", ".join(words[:-1]) + " or " + words[-1]
    return words[0] if words else "something else"


def _spelling(name: str) -> str:
    try:
        pattern = _lark().get_terminal(name).pattern
    except KeyError:
        return name
    return f"'{pattern.value}'" if pattern.type == "str" else name.lower()


def _expected_hint(expected: list[str]) -> str:
    if expected == ["RPAR"]:
        return "close the parenthesis here"
    return "epistemica reads the EPDDL of plank's benchmark set (PDDL-like s-expressions)"


def _depth(text: str) -> int:
    depth = 0
    for line in text.splitlines():
        line = line.split(";", 1)[0]
        depth += line.count("(") - line.count(")")
    return max(depth, 1)
