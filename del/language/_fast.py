"""A fast reader for formulas and flat statement lists, for valid text only.

lark's LALR parser in pure Python reads about 50 kB of formulas a second, building a tree
with positions for every node. This module reads the same language with one regular
expression and a precedence-climbing loop (about 1 MB/s) and builds :class:`Formula`
objects directly. It accepts only what the grammar accepts and returns ``None`` at the
first thing it does not expect: the caller then parses with lark, which produces the
located error message. So every error is lark's, and valid text is read fast.
"""

from __future__ import annotations

import array
import re
from collections.abc import Iterator
from typing import Any

from epistemica.del_.language.formula import (
    RESERVED_WORDS,
    And,
    Atom,
    Bottom,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    Top,
)
from epistemica.del_.language.modalities import (
    After,
    Announce,
    AnnounceDiamond,
    Believe,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
    SafeBelief,
)

__all__ = ["Tokens", "read_formula", "tokenize"]

# Token kinds: the first group of _TOKEN that matched (lastindex).
_SPACE, _WORD, _INT, _STRING, _ANNOUNCE, _DIAMOND, _IFF, _IMPLIES, _AND, _OR, _NOT = range(1, 12)
_TOP, _BOTTOM, _PUNCT, _OTHER = 12, 13, 14, 15
# Spaces and comments before each token (group 1), and the token (group 2): findall
# returns the pairs, and offsets are their running lengths (no match object per token).
# Group 2 also matches the end of the text, so that a match never fails: a failing match
# would be retried at every position of a trailing run of blank lines (quadratic time).
_TOKEN = re.compile(
    r"((?:\s+|#[^\n]*)*)"
    r"([A-Za-z_][A-Za-z0-9_]*|[0-9]+|\"[^\"\n]*\"|\[[ \t\r\n]*!|<[ \t\r\n]*!|<->|<=>|->|=>"
    r"|&&|\|\||\S|\Z)",
)
# A token's kind from its first character; the few that need the second are below.
_FIRST = {c: _WORD for c in "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_"}
_FIRST.update({c: _INT for c in "0123456789"})
_FIRST.update({"&": _AND, "∧": _AND, "|": _OR, "∨": _OR, "~": _NOT, "!": _NOT, "¬": _NOT,
               "→": _IMPLIES, "↔": _IFF, "⊤": _TOP, "⊥": _BOTTOM})  # fmt: skip
_FIRST.update({c: _PUNCT for c in "[](),:{}<>.="})
_LONGER = {"[": _ANNOUNCE, "<": _DIAMOND, "-": _IMPLIES, "=": _IMPLIES, '"': _STRING}


def _chunks(text: str, size: int = 1 << 16) -> Iterator[tuple[int, str]]:
    """``text`` in pieces of about ``size`` characters, cut after a newline, with their
    offsets: findall's list of a piece stays small. A token split by a cut (``[`` and
    ``!`` of an announcement on two lines) only sends the text to lark."""
    start = 0
    while start < len(text):
        cut = text.find("\n", start + size)
        end = len(text) if cut < 0 else cut + 1
        yield start, text[start:end]
        start = end


def _kind(value: str) -> int:
    first = value[0]
    if len(value) > 1 and first in _LONGER:
        if first == "<" and value[1] in "-=":
            return _IFF  # <-> and <=>
        return _LONGER[first]
    kind = _FIRST.get(first, _OTHER)
    return _WORD_KIND.get(value, _WORD) if kind == _WORD else kind


_WORD_KIND = {"not": _NOT, "and": _AND, "or": _OR, "true": _TOP, "false": _BOTTOM}
_AGENT_MODALITIES = {"K": Know, "B": Believe, "Kw": KnowWhether, "Sb": SafeBelief}
_GROUP_MODALITIES = {
    "E": Everybody,
    "C": Common,
    "D": Distributed,
    "EB": EverybodyBelieves,
    "CB": CommonBelief,
}
_BINARY = {_AND: (4, And), _OR: (3, Or), _IMPLIES: (2, Implies), _IFF: (1, Iff)}


class Tokens:
    """The tokens of a text: parallel lists of kinds, values and start offsets."""

    def __init__(self, text: str) -> None:
        # Compact arrays: a token costs 13 bytes, not the 80 of three lists of objects
        # (offsets fit in 32 bits: sources are at most 64 MiB).
        kinds, values, starts = bytearray(), [], array.array("i")
        known: dict[str, tuple[int, str]] = {}  # token text -> (kind, the one string kept)
        for offset, chunk in _chunks(text):
            position = offset
            for space, value in _TOKEN.findall(chunk):
                if not value:  # the end of the piece
                    break
                position += len(space)
                found = known.get(value)
                if found is None:
                    found = known[value] = (_kind(value), value)
                kinds.append(found[0])
                values.append(found[1])
                starts.append(position)
                position += len(value)
        self.kinds, self.values, self.starts = kinds, values, starts
        # Atoms and negated atoms, shared by every formula read from this text.
        self.atoms: dict[str, Atom] = {}
        self.negated: dict[int, Formula] = {}
        # Connectives by (operator, id(left), id(right)); each keeps its parts alive, so
        # an id is never reused while the table lives.
        self.made: dict[tuple, Formula] = {}
        kinds.append(0)  # end of input
        values.append("")
        starts.append(len(text))
        self.text = text


def tokenize(text: str) -> Tokens:
    """The tokens of ``text`` (whitespace and ``#`` comments dropped)."""
    return Tokens(text)


class _Miss(Exception):
    """The fast reader does not handle this text: parse it with lark."""


def read_formula(tokens: Tokens, i: int) -> tuple[Formula, int] | None:
    """The formula starting at token ``i`` and the index of the token after it, or
    ``None`` if the text there is not one the fast reader accepts."""
    try:
        return _Reader(tokens).formula(i)
    except (_Miss, IndexError):
        return None


class _Frame:
    """A formula being read: its operands and pending operators, the prefixes waiting for
    the next operand, and the token that closes it (``None`` at the top)."""

    __slots__ = ("closer", "kind", "made", "operands", "operators", "prefixes")

    def __init__(self, closer: str | None, made: dict, kind: int = 0) -> None:
        self.closer, self.kind, self.made = closer, kind, made
        self.operands: list[Formula] = []
        self.operators: list[int] = []
        self.prefixes: list[Any] = []

    def push(self, operand: Formula) -> None:
        for prefix in reversed(self.prefixes):
            operand = _apply(prefix, operand)
        self.prefixes.clear()
        self.operands.append(operand)

    def reduce(self, strength: int, kind: int) -> None:
        # Pending operators binding at least as tightly (-> is right-associative).
        operators, operands = self.operators, self.operands
        while operators and (
            _BINARY[operators[-1]][0] > strength
            or (_BINARY[operators[-1]][0] == strength and kind != _IMPLIES)
        ):
            right = operands.pop()
            left = operands[-1]
            operator = operators.pop()
            # Equal connectives of shared parts are one object: a generated spec repeats
            # the same conjunction hundreds of times.
            key = (operator, id(left), id(right))
            node = self.made.get(key)
            if node is None:  # the node keeps its parts alive: their ids stay theirs
                node = self.made[key] = _BINARY[operator][1](left, right)
            operands[-1] = node


class _Reader:
    """Precedence climbing on an explicit stack of frames (parentheses and announcements
    open one), so that nesting depth costs no recursion."""

    def __init__(self, tokens: Tokens) -> None:
        self.kinds, self.values = tokens.kinds, tokens.values
        # Shared: a generated law repeats the same atoms thousands of times.
        self.atoms, self.negated, self.made = tokens.atoms, tokens.negated, tokens.made

    def formula(self, i: int) -> tuple[Formula, int]:
        kinds, values = self.kinds, self.values
        made = self.made
        frames = [_Frame(None, made)]
        frame = frames[0]
        while True:
            # -- an operand, after its prefixes ----------------------------------------
            kind = kinds[i]
            if kind == _NOT:
                frame.prefixes.append(Not)
                i += 1
                continue
            if kind == _WORD and kinds[i + 1] == _PUNCT and values[i + 1] == "[":
                word = values[i]
                if word in _AGENT_MODALITIES or word == "M":
                    if kinds[i + 2] not in (_WORD, _INT) or values[i + 3] != "]":
                        raise _Miss
                    frame.prefixes.append((word, values[i + 2]))
                    i += 4
                    continue
                if word in _GROUP_MODALITIES:
                    group, i = self.names(i + 2, "]")
                    frame.prefixes.append((word, group))
                    continue
                raise _Miss
            if kind == _ANNOUNCE or kind == _DIAMOND:
                frame = _Frame("]" if kind == _ANNOUNCE else ">", made, kind)
                frames.append(frame)
                i += 1
                continue
            if kind == _PUNCT and values[i] == "[":
                action, i = self.action(i + 1)
                frame.prefixes.append((After, action))
                continue
            if kind == _PUNCT and values[i] == "(":
                frame = _Frame(")", made)
                frames.append(frame)
                i += 1
                continue
            operand, i = self.primary(i)
            if frame.prefixes and frame.prefixes[-1] is Not and type(operand) is Atom:
                frame.prefixes.pop()
                negated = self.negated.get(id(operand))
                if negated is None:
                    negated = self.negated[id(operand)] = Not(operand)
                operand = negated
            frame.push(operand)
            # -- operators, and the ends of frames -------------------------------------
            while True:
                kind = kinds[i]
                found = _BINARY.get(kind)
                if found is not None:
                    frame.reduce(found[0], kind)
                    frame.operators.append(kind)
                    i += 1
                    break  # an operand follows
                frame.reduce(0, 0)
                result = frame.operands[0]
                if frame.closer is None:
                    return result, i
                if kinds[i] != _PUNCT or values[i] != frame.closer:
                    raise _Miss
                i += 1
                closed = frames.pop()
                frame = frames[-1]
                if closed.closer == ")":
                    frame.push(result)  # and read an operator of the outer frame
                    continue
                frame.prefixes.append((closed.kind, result))
                break  # the announcement's operand follows

    def names(self, i: int, closer: str) -> tuple[tuple[str, ...], int]:
        """``name, name, ...`` from token ``i`` up to ``closer``, and the index after it."""
        kinds, values = self.kinds, self.values
        names = []
        while True:
            if kinds[i] not in (_WORD, _INT):
                raise _Miss
            names.append(values[i])
            if values[i + 1] == closer:
                return tuple(names), i + 2
            if values[i + 1] != ",":
                raise _Miss
            i += 2

    def action(self, i: int) -> tuple[str, int]:
        if self.kinds[i] != _WORD:
            raise _Miss
        name = self.values[i]
        i += 1
        if self.values[i] == "(" and self.kinds[i] == _PUNCT:
            args, i = self.names(i + 1, ")")
            name = f"{name}({', '.join(args)})"
        if self.values[i] != "]":
            raise _Miss
        return name, i + 1

    def primary(self, i: int) -> tuple[Formula, int]:
        kinds, values = self.kinds, self.values
        kind = kinds[i]
        if kind == _WORD:
            name = values[i]
            if name in RESERVED_WORDS:
                raise _Miss
            if kinds[i + 1] == _PUNCT and values[i + 1] == "(":
                args, i = self.names(i + 2, ")")
                return Atom(name, args), i
            atom = self.atoms.get(name)
            if atom is None:
                atom = self.atoms[name] = Atom(name)
            return atom, i + 1
        if kind == _TOP:
            return Top(), i + 1
        if kind == _BOTTOM:
            return Bottom(), i + 1
        raise _Miss


def _apply(prefix: Any, operand: Formula) -> Formula:
    if prefix is Not:
        return Not(operand)
    head, value = prefix
    if head is After:
        return After(value, operand)
    if head == _ANNOUNCE:
        return Announce(value, operand)
    if head == _DIAMOND:
        return AnnounceDiamond(value, operand)
    if head == "M":  # M[a] f is ~K[a] ~f, as the lark builder writes it
        return Not(Know(value, Not(operand)))
    if head in _AGENT_MODALITIES:
        return _AGENT_MODALITIES[head](value, operand)
    return _GROUP_MODALITIES[head](value, operand)
