"""Translations between Kripke models and knowledge structures.

A Kripke model becomes a structure whose states are its worlds: world bits (the world's
index in binary), its atoms (determined by the world through the law) and, per agent whose
relation is an equivalence, label bits naming the agent's class, which the agent observes.
Any other relation becomes a BDD of arrows between world codes. The way back lists the
states, so it is refused above ``max_worlds``.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit.relations import Partition
from epistemica.del_.language.formula import atom_name
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic.relations import Arrows, Observes, Relation

if TYPE_CHECKING:
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = ["MAX_KRIPKE_WORLDS", "kripke_parts", "states", "to_kripke"]

# Listing the relations of more states than this would take minutes in Python.
MAX_KRIPKE_WORLDS = 2048


def kripke_parts(model: ExplicitModel, atoms: Iterable[str] | None = None) -> tuple:
    """The constructor arguments of the knowledge structure of ``model``, state for world.

    ``atoms`` declares atoms besides the model's own (false everywhere), such as a spec's
    atoms that no world makes true: a structure refuses atoms it does not declare.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_partitions(
    ...     ["h", "t"], {"h": {"heads"}}, {"a": [["h", "t"]], "b": [["h"], ["t"]]}, "h")
    >>> from epistemica.del_ import KnowledgeStructure
    >>> s = KnowledgeStructure(*kripke_parts(m))
    >>> s.n_worlds, s.holds("Kw[b] heads & ~Kw[a] heads")
    (2, True)
    """
    names = list(model.atoms)
    for a in atoms or ():
        key = atom_name(a, "atoms")
        if key not in names:
            names.append(key)
    n = model.n_worlds
    world_slots = list(range(len(names), len(names) + _bits(n)))
    next_slot = len(names) + len(world_slots)
    val = np.zeros((n, len(names)), dtype=bool)
    val[:, : len(model.atoms)] = model.valuation

    made: dict[int, Relation] = {}
    labels: list[tuple[list[int], np.ndarray]] = []
    codes = [_bdd.minterm(world_slots, i) for i in range(n)]
    for relation in [*model.belief_relations.values(), *model.knowledge_relations.values()]:
        if id(relation) in made:
            continue
        if isinstance(relation, Partition):
            label = np.unique(relation.labels, return_inverse=True)[1].reshape(-1)
            slots = list(range(next_slot, next_slot + _bits(int(label.max()) + 1)))
            next_slot += len(slots)
            labels.append((slots, label))
            made[id(relation)] = Observes(frozenset(slots))
        else:
            rows, cols = relation.edges()
            arrows = _bdd.false()
            for i, j in zip(rows.tolist(), cols.tolist(), strict=True):
                arrows |= codes[i] & _bdd.minterm(world_slots, j, primed_copy=True)
            made[id(relation)] = Arrows(arrows)

    law = _bdd.false()
    for i in range(n):
        world = codes[i]
        for j in range(len(names) - 1, -1, -1):
            world &= _bdd.var(j) if val[i, j] else ~_bdd.var(j)
        for slots, label in labels:
            world &= _bdd.minterm(slots, int(label[i]))
        law |= world
    designated = _bdd.false()
    for i in model.designated_positions.tolist():
        designated |= codes[i]
    agents = model.agents
    return (
        {a: j for j, a in enumerate(names)},
        range(next_slot),
        law,
        agents,
        {a: made[id(model.belief_relations[a])] for a in agents},
        {a: made[id(model.knowledge_relations[a])] for a in agents},
        designated,
    )


def to_kripke(
    structure: Any,
    max_worlds: int = MAX_KRIPKE_WORLDS,
    model_class: type[ExplicitModel] = ExplicitModel,
) -> ExplicitModel:
    """The Kripke model of ``structure``: one world per state, named ``0, 1, ...``.

    ``model_class`` is the class built (``KnowledgeStructure.to_kripke`` passes the public
    :class:`~epistemica.del_.KripkeModel`).

    Raises
    ------
    InvalidArgumentError
        If the structure has more than ``max_worlds`` states.

    Examples
    --------
    >>> from epistemica.del_ import KnowledgeStructure
    >>> s = KnowledgeStructure.from_observables(["p", "q"], {"a": ["p"]}, designated=["p"])
    >>> m = s.to_kripke()
    >>> m.n_worlds, m.holds("K[a] p & ~Kw[a] q")
    (4, True)
    """
    count = structure.n_worlds
    if count > max_worlds:
        raise InvalidArgumentError(
            f"the structure has {count} states, more than {max_worlds} worlds to list",
            hint="evaluate formulas on the KnowledgeStructure itself, or raise max_worlds",
        )
    slots = list(structure.slots)
    found = states(structure.law, slots)
    index = {state: i for i, state in enumerate(found)}
    position = {s: k for k, s in enumerate(slots)}
    valuation = {
        i: [a for a, s in structure.atom_slots.items() if state[position[s]]]
        for state, i in index.items()
    }
    points = [index[state] for state in states(structure.designated_states, slots)]
    made: dict[int, list[tuple[int, int]]] = {}

    def pairs(relation: Relation) -> list[tuple[int, int]]:
        if id(relation) not in made:
            made[id(relation)] = _pairs(relation, structure.law, slots, found, index)
        return made[id(relation)]

    agents = structure.agents
    return model_class(
        list(range(len(found))),
        valuation,
        {a: pairs(structure.belief_relations[a]) for a in agents},
        points,
        # one relation object per agent unless they differ: "separate knowledge" is
        # read off the objects, and a listed S5 structure has none
        knowledge=(
            {a: pairs(structure.knowledge_relations[a]) for a in agents}
            if structure.has_separate_knowledge()
            else None
        ),
        atoms=list(structure.atom_slots),
    )


def _pairs(
    relation: Relation, law: BDDFunction, slots: list[int], found: list, index: dict
) -> list[tuple[int, int]]:
    if isinstance(relation, Observes):
        seen = [k for k, s in enumerate(slots) if s in relation.slots]
        blocks: dict[tuple, list[int]] = {}
        for i, state in enumerate(found):
            blocks.setdefault(tuple(state[k] for k in seen), []).append(i)
        return [(w, v) for block in blocks.values() for w in block for v in block]
    out = []
    targets = _bdd.primed(law, slots)
    for i, state in enumerate(found):
        here = _bdd.minterm(slots, _as_int(state))
        successors = (relation.bdd & here).exists(_bdd.cube(slots)) & targets
        out += [(i, index[t]) for t in states(successors, slots, primed_copy=True)]
    return out


def states(f: BDDFunction, slots: Sequence[int], primed_copy: bool = False) -> list[tuple]:
    """Every assignment to ``slots`` satisfying ``f`` (whose support lies in them)."""
    out = []
    offset = 1 if primed_copy else 0
    while f.satisfiable():
        picked = f.pick_cube()
        values = [picked[2 * s + offset] if 2 * s + offset < len(picked) else None for s in slots]
        free = [k for k, v in enumerate(values) if v is None]
        for bits in itertools.product((False, True), repeat=len(free)):
            filled = list(values)
            for k, b in zip(free, bits, strict=True):
                filled[k] = b
            out.append(tuple(bool(v) for v in filled))
        f = f & ~f.pick_cube_dd()
    return sorted(out, reverse=True)


def _as_int(state: tuple) -> int:
    value = 0
    for bit in state:
        value = 2 * value + int(bit)
    return value


def _bits(n: int) -> int:
    return max(0, (n - 1).bit_length())
