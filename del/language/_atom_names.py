"""Atom names: their canonical spelling and which texts a formula could write.

Shared by :class:`~epistemica.del_.language.formula.Atom` and by the model classes, which
take atom names as text (valuations, observables, vocabularies).
"""

from __future__ import annotations

import re

from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "RESERVED_WORDS",
    "atom_name",
    "canonical_atom",
    "split_args",
    "split_predicate",
    "valid_atom",
]

#: Words that the lexer reads as keywords, so they cannot name an atom.
RESERVED_WORDS = frozenset(
    {"true", "false", "not", "and", "or", "K", "B", "Kw", "M", "E", "C", "D", "EB", "CB", "Sb"}
)

_ATOM_TEXT = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:\((.*)\))?\s*$")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_ARGUMENT = re.compile(r"[A-Za-z0-9_]+")


def canonical_atom(text: str) -> str:
    """Return the canonical spelling of an atom written as text.

    Predicate atoms are spelled ``name(arg1, arg2)`` with one space after each comma, so
    that ``"at(r1,g1)"`` and ``"at( r1 , g1 )"`` name the same atom.

    Examples
    --------
    >>> canonical_atom("at(r1,g1)")
    'at(r1, g1)'
    >>> canonical_atom(" p ")
    'p'
    """
    match = _ATOM_TEXT.match(text)
    if match is None:
        return text.strip()
    name, args = match.groups()
    if args is None:
        return name
    return f"{name}({', '.join(a.strip() for a in args.split(','))})"


def atom_name(text: str, where: str = "the argument") -> str:
    """The canonical spelling of an atom, refusing text that no formula could name.

    Raises
    ------
    InvalidArgumentError
        If ``text`` is not ``name`` or ``name(arg, ...)`` with names (letters, digits,
        ``_``, not starting with a digit) and arguments that are names or numbers, or if
        the name is a reserved word.

    Examples
    --------
    >>> atom_name("at(r1,g1)")
    'at(r1, g1)'
    >>> atom_name("p q")
    Traceback (most recent call last):
    ...
    epistemica.del_.errors.InvalidArgumentError: 'p q' in the argument is not an atom name
    hint: an atom is a name (letters, digits, _) or name(arg, ...), e.g. 'p' or 'at(r1, g1)'
    """
    key = canonical_atom(str(text))
    match = _ATOM_TEXT.match(key)
    if match is None or not valid_atom(match.group(1), split_args(match.group(2))):
        raise InvalidArgumentError(
            f"{text!r} in {where} is not an atom name",
            hint="an atom is a name (letters, digits, _) or name(arg, ...), e.g. 'p' or "
            "'at(r1, g1)'",
        )
    return key


def split_predicate(text: str) -> tuple[str, tuple[str, ...]] | None:
    """``("at", ("r1", "g1"))`` for ``"at(r1, g1)"``; ``None`` if ``text`` is not a
    predicate atom's text."""
    match = _ATOM_TEXT.match(text)
    if match is None or match.group(2) is None:
        return None
    return match.group(1), split_args(match.group(2))


def split_args(args: str | None) -> tuple[str, ...]:
    return () if args is None else tuple(a.strip() for a in args.split(","))


def valid_atom(name: str, args: tuple[str, ...]) -> bool:
    return (
        _NAME.fullmatch(name) is not None
        and name not in RESERVED_WORDS
        and all(_ARGUMENT.fullmatch(a) for a in args)
    )
