"""Checking the arguments of a model built by hand: mappings, atom names, vocabularies.

Bad arguments raise :class:`~epistemica.del_.errors.InvalidArgumentError` naming what was
wrong and what to pass instead, rather than an ``AttributeError`` deep inside; an atom a
model does not declare is "unknown", with the closest declared one.
"""

from __future__ import annotations

import difflib
import itertools
from collections.abc import Iterable, Mapping
from typing import Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language.formula import atom_name, canonical_atom

__all__ = ["column_of", "declared_atoms", "require_mapping"]


def require_mapping(value: Any, name: str, what: str) -> None:
    if not isinstance(value, Mapping):
        raise InvalidArgumentError(
            f"{name} must be a mapping {what}, not {type(value).__name__}",
            hint=f"pass a dict of {what} (an empty dict for none)",
        )


def declared_atoms(atoms: Iterable[str]) -> dict[str, None]:
    if isinstance(atoms, (str, bytes)):
        raise InvalidArgumentError(
            "atoms must be an iterable of atom names, not a string", hint='e.g. ["p", "q"]'
        )
    declared: dict[str, None] = {}
    for a in atoms:
        key = atom_name(a, "atoms")
        if key in declared:
            raise InvalidArgumentError(f"atom {key!r} is declared twice", hint="remove the repeat")
        declared[key] = None
    return declared


def column_of(column: Mapping[str, int], atom: str, where: str) -> int:
    """The column (or slot) of ``atom``, or "unknown atom" with the closest declared one."""
    key = canonical_atom(str(atom))
    found = column.get(key)
    if found is None:
        close = difflib.get_close_matches(key, list(column)[:10_000], n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        names = list(itertools.islice(column, 20))
        listed = ", ".join(names) + (", ..." if len(column) > 20 else "")
        raise InvalidArgumentError(
            f"unknown atom {atom!r} in {where}",
            hint=f"{hint}declared atoms: {listed or 'none'}",
        )
    return found
