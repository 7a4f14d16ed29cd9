"""The fast path of spec parsing: valid, formula-heavy specs without lark's tree.

Generated specs are mostly formulas (a law of 2,400 disjuncts, 400 announcements of a
400-conjunct formula). :func:`fast_parse` reads the statements made of formulas (``law``,
``goal``, ``check``, ``action NAME [by AGENT]: public F``) with the fast formula reader of
:mod:`epistemica.del_.language._fast`, and each other statement (``agents``, ``atoms``,
``observes``, ``actual``, ``designated``) with lark, on that statement alone. The tree it
returns has the shape of lark's, except that a ``fml`` node holds the finished
:class:`Formula`. It returns ``None`` for anything else (a world, an action block, a
schema, a syntax error, an undeclared name met later): the caller then parses the whole
text with lark, so every error message is lark's, located as before.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable
from typing import Any

from lark import Token, Tree
from lark.tree import Meta

from epistemica.del_.language._fast import Tokens, read_formula, tokenize

__all__ = ["FastPathMiss", "fast_formula", "fast_parse"]

_SIMPLE = frozenset(("agents", "atoms", "observes", "actual", "designated"))
_FORMULA = frozenset(("law", "goal", "check", "action"))
# left to lark
_OTHER = frozenset(("world", "relation", "knowledge", "partition", "plausibility", "upgrade"))
_WORD, _STRING = 2, 4


class FastPathMiss(Exception):
    """Raised by the compiler on a fast-path tree it cannot accept: parse with lark."""


class _Positions:
    def __init__(self, text: str) -> None:
        self.starts = [0]
        self.starts += [k + 1 for k, c in enumerate(text) if c == "\n"]

    def line_column(self, offset: int) -> tuple[int, int]:
        line = bisect.bisect_right(self.starts, offset)
        return line, offset - self.starts[line - 1] + 1


def _token(kind: str, value: str, offset: int, where: _Positions) -> Token:
    line, column = where.line_column(offset)
    end_line, end_column = where.line_column(offset + len(value))
    return Token(kind, value, offset, line, column, end_line, end_column, offset + len(value))


def _meta(start: int, end: int, where: _Positions) -> Meta:
    meta = Meta()
    meta.empty = False
    meta.start_pos, meta.end_pos = start, end
    meta.line, meta.column = where.line_column(start)
    meta.end_line, meta.end_column = where.line_column(end)
    return meta


def _fml(formula: Any, start: int, end: int, where: _Positions) -> Tree:
    return Tree("fml", [formula], _meta(start, end, where))


def fast_formula(text: str) -> Tree | None:
    """The ``fml`` tree of a whole formula (comments allowed), or ``None``."""
    tokens = tokenize(text)
    found = read_formula(tokens, 0)
    if found is None or tokens.kinds[found[1]] != 0:
        return None
    return _fml(found[0], tokens.starts[0], len(text.rstrip()), _Positions(text))


def fast_parse(text: str, parse_statement: Callable[[str], Tree]) -> Tree | None:
    """The tree of a spec, or ``None`` if the fast path does not take it.

    ``parse_statement(padded)`` parses one simple statement with lark; ``padded`` puts it
    at its line and column of the file, so that its tokens are located as in the file.
    """
    tokens = tokenize(text)
    where = _Positions(text)
    kinds, values, starts = tokens.kinds, tokens.values, tokens.starts
    statements: list[Tree] = []
    i = 0
    while kinds[i] != 0:
        if kinds[i] != _WORD:
            return None
        word = values[i]
        if word in _SIMPLE:
            j = _statement_end(tokens, i + 1)
            line, column = where.line_column(starts[i])
            chunk = text[starts[i] : starts[j]]
            padded = "\n" * (line - 1) + " " * (column - 1) + chunk
            tree = parse_statement(padded)
            if len(tree.children) != 1:
                return None
            statements.append(tree.children[0])
            i = j
            continue
        if word not in _FORMULA:
            return None
        found = _formula_statement(tokens, i, where)
        if found is None:
            return None
        statement, j = found
        end = starts[j - 1] + len(values[j - 1])
        meta = _meta(starts[i], end, where)  # where errors about the statement point
        statements.append(Tree(statement.data, statement.children, meta))
        i = j
    return Tree("start", statements)


def _statement_end(tokens: Tokens, i: int) -> int:
    """The first keyword starting a statement after token ``i`` (a name list's end)."""
    kinds, values = tokens.kinds, tokens.values
    while kinds[i] != 0:
        if (
            kinds[i] == _WORD
            and (values[i] in _SIMPLE or values[i] in _FORMULA or values[i] in _OTHER)
            and values[i - 1] not in (",", ":", "{", ".")
        ):
            return i
        i += 1
    return i


def _ends_statement(tokens: Tokens, i: int, also: str = "") -> bool:
    kind, value = tokens.kinds[i], tokens.values[i]
    if kind == 0:
        return True
    return kind == _WORD and (
        value in _SIMPLE or value in _FORMULA or value in _OTHER or value == also
    )


def _read(tokens: Tokens, i: int, where: _Positions, also: str = "") -> tuple[Tree, int] | None:
    found = read_formula(tokens, i)
    if found is None or not _ends_statement(tokens, found[1], also):
        return None
    formula, j = found
    end = tokens.starts[j - 1] + len(tokens.values[j - 1])
    return _fml(formula, tokens.starts[i], end, where), j


def _formula_statement(tokens: Tokens, i: int, where: _Positions) -> tuple[Tree, int] | None:
    kinds, values, starts = tokens.kinds, tokens.values, tokens.starts
    word = values[i]
    if word in ("law", "goal"):
        found = _read(tokens, i + 1, where)
        if found is None:
            return None
        return Tree(f"{word}_decl", [found[0]]), found[1]
    if word == "check":
        if kinds[i + 1] != _STRING or values[i + 2] != ":":
            return None
        label = _token("STRING", values[i + 1], starts[i + 1], where)
        found = _read(tokens, i + 3, where, also="expect")
        if found is None:
            return None
        fml, j = found
        verdict = None
        if values[j] == "expect" and kinds[j] == _WORD:
            if values[j + 1] not in ("true", "false"):
                return None
            kind = values[j + 1].upper()
            value = _token(kind, values[j + 1], starts[j + 1], where)
            verdict = Tree("verdict", [value], _meta(value.start_pos, value.end_pos, where))
            j += 2
            if not _ends_statement(tokens, j):
                return None
        return Tree("check_decl", [label, fml, verdict]), j
    # action NAME [by AGENT]: public F
    if kinds[i + 1] != _WORD:
        return None
    name = _token("NAME", values[i + 1], starts[i + 1], where)
    j = i + 2
    owner = None
    if values[j] == "by" and kinds[j] == _WORD and kinds[j + 1] == _WORD:
        agent = _token("NAME", values[j + 1], starts[j + 1], where)
        owner = Tree("owner", [agent], _meta(starts[j], agent.end_pos, where))
        j += 2
    if values[j] != ":" or values[j + 1] != "public" or kinds[j + 1] != _WORD:
        return None
    found = _read(tokens, j + 2, where)
    if found is None:
        return None
    body = Tree("public", [found[0]], _meta(starts[j + 1], found[0].meta.end_pos, where))
    return Tree("action_decl", [name, None, owner, body]), found[1]
