"""Checking a Kripke model given as names (worlds, valuation, relations, designated worlds)
and turning it into the arrays :class:`~epistemica.del_.explicit._model.ExplicitModel`
stores: every wrong type or unknown name is an :class:`InvalidArgumentError` naming it.
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.explicit._arguments import declared_atoms, require_mapping
from epistemica.del_.explicit.relations import Relation, relation_from_pairs
from epistemica.del_.language.formula import atom_name

__all__ = ["World", "lookup_world", "model_arrays", "world_positions"]

#: A world's name: anything hashable (a string, a number, a tuple of them).
World = Hashable


def model_arrays(
    worlds: Sequence[World],
    valuation: Mapping[World, Iterable[str]],
    relations: Mapping[str, Iterable[tuple[World, World]]],
    designated: World | Iterable[World],
    knowledge: Mapping[str, Iterable[tuple[World, World]]] | None = None,
    atoms: Iterable[str] | None = None,
) -> tuple:
    """``(names, atoms, valuation matrix, agents, relations, knowledge relations,
    designated positions)`` of a model given by names, every argument checked."""
    require_mapping(valuation, "valuation", "world -> the atoms true there")
    require_mapping(relations, "relations", "agent -> (world, world) pairs")
    if knowledge is not None:
        require_mapping(knowledge, "knowledge", "agent -> (world, world) pairs")
    if isinstance(worlds, (str, bytes)) or not isinstance(worlds, Iterable):
        raise InvalidArgumentError(
            f"worlds must be a sequence of world names, not {type(worlds).__name__}",
            hint='e.g. ["w1", "w2"]',
        )
    names = tuple(worlds)
    try:
        index = {w: i for i, w in enumerate(names)}
    except TypeError:  # an unhashable name: a list, a dict
        raise InvalidArgumentError(
            "a world name must be a string or a number, not a list or a dict",
            hint='e.g. ["w1", "w2"]',
        ) from None
    if len(index) != len(names):
        raise ModelError("world names must be distinct", hint="rename the repeated world")
    declared = None if atoms is None else declared_atoms(atoms)
    found: dict[str, None] = dict.fromkeys(declared or ())
    keys: dict[World, list[str]] = {}
    for w, true_atoms in valuation.items():
        lookup_world(index, w, "valuation")
        where = f"the valuation of {w!r}"
        if isinstance(true_atoms, (str, bytes)) or not isinstance(true_atoms, Iterable):
            raise InvalidArgumentError(
                f"{where} must be an iterable of atom names, not {true_atoms!r}",
                hint=f'e.g. {{{w!r}: ["p", "q"]}}',
            )
        keys[w] = [atom_name(a, where) for a in true_atoms]
        for key in keys[w]:
            if declared is not None and key not in declared:
                raise ModelError(
                    f"atom {key!r} in {where} is not declared",
                    hint=f"declared atoms: {', '.join(declared) or 'none'}",
                )
            found.setdefault(key)
    atom_list = tuple(found)
    column = {a: j for j, a in enumerate(atom_list)}
    val = np.zeros((len(names), len(atom_list)), dtype=bool)
    for w, true_keys in keys.items():
        for key in true_keys:
            val[index[w], column[key]] = True
    agents = tuple(str(a) for a in relations)
    rel = {str(a): _relation(index, pairs, f"relation of {a}") for a, pairs in relations.items()}
    know = dict(rel)
    if knowledge is not None:
        for a, pairs in knowledge.items():
            if str(a) not in rel:
                raise ModelError(
                    f"knowledge relation given for unknown agent {a!r}",
                    hint=f"agents with a relation: {', '.join(agents)}",
                )
            know[str(a)] = _relation(index, pairs, f"knowledge relation of {a}")
    points = world_positions(designated, index)
    if not points:
        raise ModelError("a model needs at least one designated world")
    return names, atom_list, val, agents, rel, know, np.array(points, dtype=np.int64)


def lookup_world(index: Mapping[World, int], world: World, where: str) -> int:
    try:
        return index[world]
    except (KeyError, TypeError):
        raise ModelError(
            f"unknown world {world!r} in {where}", hint="every world must be listed in `worlds`"
        ) from None


def _relation(index: Mapping[World, int], pairs: Iterable, where: str) -> Relation:
    if isinstance(pairs, (str, bytes)) or not isinstance(pairs, Iterable):
        raise InvalidArgumentError(
            f"the {where} must be an iterable of (world, world) pairs, not {pairs!r:.60}",
            hint='e.g. [("w1", "w2"), ("w2", "w2")]',
        )
    sources, targets = [], []
    for pair in pairs:
        if (
            isinstance(pair, (str, bytes))
            or not isinstance(pair, Iterable)
            or len(pair := tuple(pair)) != 2
        ):
            raise InvalidArgumentError(
                f"the {where} holds {pair!r:.60}, not a (world, world) pair",
                hint='e.g. [("w1", "w2"), ("w2", "w2")]',
            )
        w, v = pair
        sources.append(lookup_world(index, w, where))
        targets.append(lookup_world(index, v, where))
    return relation_from_pairs(len(index), sources, targets)


def world_positions(designated: Any, index: Mapping[World, int]) -> list[int]:
    try:
        if designated in index:
            return [index[designated]]
    except TypeError:
        pass
    if isinstance(designated, (str, bytes)) or not isinstance(designated, Iterable):
        return [lookup_world(index, designated, "designated")]  # one world, not a known one
    return [lookup_world(index, w, "designated") for w in designated]
