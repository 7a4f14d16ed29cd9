"""Knowledge structures for people: their parts as text or JSON, and states listed.

A structure is shown as SMCDEL prints one: the vocabulary, the state law and each agent's
observables, plus the counts; the law is written as a disjunction of the BDD's disjoint
cubes (at most ``limit`` of them). States are listed by the atoms true in them, at most
``limit``, without enumerating the others.

Examples
--------
>>> from epistemica.del_ import KnowledgeStructure
>>> s = KnowledgeStructure.from_observables(
...     ["p", "q"], {"a": ["p"], "b": []}, law="p | q", designated=["p"])
>>> print(describe_structure(s))
knowledge structure: 2 atoms, 2 variables, 3 states, 1 designated; agents a, b
  vocabulary: p, q
  law: ~p & q | p
  observables:
    a: p
    b: (none)
  designated: {p}
>>> list(iter_valuations(s, s.truth("~p")))
[['q']]
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic.relations import Observes

if TYPE_CHECKING:
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = [
    "cube_literals",
    "describe_structure",
    "disjoint_cubes",
    "iter_valuations",
    "law_text",
    "structure_to_json",
]

FORMAT = "epistemica-knowledge-structure-1"


def _variable_names(s: Any) -> dict[int, str]:
    names = {slot: f"v{slot}" for slot in s.slots}
    names.update({slot: atom for atom, slot in s.atom_slots.items()})
    return names


def disjoint_cubes(f: BDDFunction) -> Iterator[list]:
    """Disjoint cubes covering ``f`` (each a list over BDD variables: True, False, None)."""
    while f.satisfiable():
        yield f.pick_cube()
        f = f & ~f.pick_cube_dd()


def cube_literals(f: BDDFunction, slots, limit: int) -> Iterator[list[tuple[int, bool]]]:
    """The disjoint cubes of ``f``, each as its ``(slot, value)`` literals over ``slots``
    in their order (an empty list: the cube is every state); at most ``limit`` cubes.

    Raises
    ------
    InvalidArgumentError
        ``f`` needs more than ``limit`` cubes (a written format without shared
        subformulas would be too long).

    Examples
    --------
    >>> from epistemica.del_ import KnowledgeStructure
    >>> s = KnowledgeStructure.from_observables(["p", "q"], {}, law="p | q")
    >>> p, q = s.atom_slots["p"], s.atom_slots["q"]
    >>> sorted(len(cube) for cube in cube_literals(s.law, [p, q], 10))
    [1, 2]
    """
    for count, picked in enumerate(disjoint_cubes(f)):
        if count == limit:
            raise InvalidArgumentError(
                f"the formula needs more than {limit:,} disjoint cubes to write",
                hint="the format has no shared subformulas; export a smaller instance",
            )
        yield [
            (slot, bool(picked[2 * slot]))
            for slot in slots
            if 2 * slot < len(picked) and picked[2 * slot] is not None
        ]


def law_text(s: Any, limit: int = 16) -> str:
    """The state law as a formula: a disjunction of at most ``limit`` disjoint cubes."""
    names = _variable_names(s)
    terms = []
    for picked in itertools.islice(disjoint_cubes(s.law), limit + 1):
        literals = [
            names[slot] if picked[2 * slot] else f"~{names[slot]}"
            for slot in s.slots
            if 2 * slot < len(picked) and picked[2 * slot] is not None
        ]
        terms.append(" & ".join(literals) or "true")
    if len(terms) > limit:
        return " | ".join(terms[:limit]) + f" | ... (law of {s.law.node_count():,} BDD nodes)"
    return " | ".join(terms) or "false"


def iter_valuations(s: Any, f: BDDFunction) -> Iterator[list[str]]:
    """The distinct atom valuations of the law-states satisfying ``f`` (true atoms, in
    declaration order), one at a time: listing a few of 2^100 costs a few."""
    atoms = list(s.atom_slots.items())
    atom_slots = {slot for _, slot in atoms}
    hidden = [slot for slot in s.slots if slot not in atom_slots]
    g = (s.law & f).exists(_bdd.cube(hidden)) if hidden else s.law & f
    for picked in disjoint_cubes(g):
        values = [picked[2 * slot] if 2 * slot < len(picked) else None for _, slot in atoms]
        free = [k for k, v in enumerate(values) if v is None]
        for bits in itertools.product((False, True), repeat=len(free)):
            filled = list(values)
            for k, bit in zip(free, bits, strict=True):
                filled[k] = bit
            yield [a for (a, _), v in zip(atoms, filled, strict=True) if v]


def _observables(s: Any, agent: str, names: dict[int, str]) -> list[str] | None:
    relation = s.relation(agent, "knowledge")
    if isinstance(relation, Observes):
        return [names[slot] for slot in sorted(relation.slots)]
    return None


def structure_to_json(s: Any, limit: int = 1000) -> dict[str, Any]:
    """The structure as a JSON-ready dict: vocabulary, law, observables, counts, and the
    designated valuations (at most ``limit``)."""
    names = _variable_names(s)
    designated = list(itertools.islice(iter_valuations(s, s.designated_states), limit + 1))
    return {
        "format": FORMAT,
        "agents": list(s.agents),
        "atoms": list(s.atom_slots),
        "n_variables": s.n_variables,
        "n_states": s.n_worlds,
        "n_designated": s.count_designated(),
        "law": law_text(s, limit),
        "law_bdd_nodes": s.law.node_count(),
        "observables": {a: _observables(s, a, names) for a in s.agents},
        "separate_knowledge": s.has_separate_knowledge(),
        "designated": designated[:limit],
        "truncated": len(designated) > limit,
    }


def describe_structure(s: Any, limit: int = 16) -> str:
    """The structure as text, in the manner of SMCDEL's knowledge structures."""
    names = _variable_names(s)
    n_atoms = len(s.atom_slots)
    head = (
        f"knowledge structure: {n_atoms} atom{'s' if n_atoms != 1 else ''}, "
        f"{s.n_variables} variables, {s.n_worlds:,} state{'s' if s.n_worlds != 1 else ''}, "
        f"{s.count_designated():,} designated; agents {', '.join(s.agents)}"
    )
    vocabulary = list(s.atom_slots)
    shown = ", ".join(vocabulary[:limit]) + (", ..." if len(vocabulary) > limit else "")
    lines = [head, f"  vocabulary: {shown}"]
    extra = s.n_variables - n_atoms
    if extra:
        lines.append(f"  bookkeeping variables: {extra} (events, values before an update)")
    lines.append(f"  law: {law_text(s, limit)}")
    lines.append("  observables:")
    for agent in s.agents:
        seen = _observables(s, agent, names)
        if seen is None:
            lines.append(f"    {agent}: a relation of arrows (not observational)")
        else:
            text = ", ".join(seen[:limit]) + (", ..." if len(seen) > limit else "")
            lines.append(f"    {agent}: {text or '(none)'}")
        if s.relation(agent, "belief") is not s.relation(agent, "knowledge"):
            lines.append(f"    {agent} believes: a separate relation of arrows")
    points = list(itertools.islice(iter_valuations(s, s.designated_states), limit + 1))
    listed = "  ".join("{" + ", ".join(p) + "}" for p in points[:limit])
    more = " ..." if len(points) > limit else ""
    lines.append(f"  designated: {listed}{more}")
    return "\n".join(lines)
