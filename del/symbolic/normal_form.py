"""Normal forms of knowledge structures, and keys that tell planning states apart.

A product update never renames: it adds event bits, a fresh variable per changed atom
and class bits, and keeps every old variable (:mod:`~epistemica.del_.symbolic.transform`).
After a few steps of a plan a structure carries its history, so two action sequences
that reach the same epistemic state give structures that differ as BDDs. This module
removes what the history does not need, by steps that each preserve bisimilarity:

1. **generated part**: the law is narrowed to the states reachable from the designated
   ones by any relation (a least fixed point of relational images);
2. **unread variables**: a variable that is no atom and that no relation reads is
   quantified away (dropping it maps states onto states, a bounded morphism);
3. **determined variables**: a variable that is no atom and whose value the law fixes
   as a function ``f`` of the atoms is replaced by ``f`` everywhere (the relations that
   read it become arrows over ``f``; an agent observing an event bit that is ``p`` or
   ``~p`` observes ``p`` instead), then quantified away.

:func:`state_key` then names the result. When only atoms are left (every state is its
valuation), the generated, renamed-to-canonical-slots law, designated set and relations
are a canonical form: two such structures are bisimilar exactly when their keys are
equal (a bisimulation between generated structures whose states are distinct valuations
is the identity). A structure that keeps other variables but has few states (at most
:data:`EXPLICIT_KEY_STATES`) is keyed by the explicit canonical key of its Kripke model
(also exact). Otherwise the key is structural: equal keys mean
the same structure up to renaming, hence bisimilar; bisimilar structures may get
different keys, which costs a planner duplicates, never a wrong answer.

Examples
--------
Two public moves in either order give the same state:

>>> from epistemica.del_ import KnowledgeStructure, public_assignment
>>> s = KnowledgeStructure.from_observables(["p", "q"], {"a": ["p", "q"]}, designated=[])
>>> set_p = public_assignment({"p": "true"}, ["a"])
>>> set_q = public_assignment({"q": "true"}, ["a"])
>>> one = normalise(s.update(set_p).update(set_q))
>>> two = normalise(s.update(set_q).update(set_p))
>>> state_key(one) == state_key(two), state_key(one) == state_key(normalise(s))
(True, False)
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

from epistemica.del_.explicit.bisimulation import minimize
from epistemica.del_.explicit.canonical import canonical_key
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic.convert import to_kripke
from epistemica.del_.symbolic.relations import Arrows, Observes, Relation, as_arrows

if TYPE_CHECKING:
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = [
    "EXPLICIT_KEY_STATES",
    "image",
    "normalise",
    "reachable",
    "state_key",
    "support",
    "without_free_atoms",
]

#: Structures with at most this many states left after normalisation are keyed through
#: their Kripke model (exact); larger ones that keep non-atom variables structurally.
EXPLICIT_KEY_STATES = 64


def image(relation: Relation, law: BDDFunction, states: BDDFunction, slots: Sequence[int]):
    """The law-states that some state of ``states`` reaches by ``relation``."""
    if isinstance(relation, Observes):
        hidden = [s for s in slots if s not in relation.slots]
        return states.exists(_cube(hidden)) & law
    reached = relation.bdd.apply_exists(_bdd.AND, states, _cube(slots))
    return unprimed(reached, slots) & law


def reachable(structure: Any) -> BDDFunction:
    """The states reachable from the designated ones by any agent's relation."""
    law, slots = structure.law, structure.slots
    relations = _distinct_relations(structure)
    reached = frontier = structure.designated_states
    while True:
        step = _bdd.false()
        for relation in relations:
            step |= image(relation, law, frontier, slots)
        frontier = step & ~reached
        if not frontier.satisfiable():
            return reached
        reached |= frontier


@functools.lru_cache(maxsize=4096)
def support(f: BDDFunction) -> frozenset[int]:
    """The BDD variables ``f`` depends on (a walk over its nodes; cached per function)."""
    found: set[int] = set()
    seen: set = set()
    stack = [f]
    while stack:
        node = stack.pop()
        if node in seen:
            continue
        seen.add(node)
        children = node.cofactors()
        if children is None:
            continue
        found.add(node.node_var())
        stack.extend(children)
    return frozenset(found)


def normalise(structure: Any) -> Any:
    """A bisimilar structure without the history no relation or atom needs (see above)."""
    law = structure.law & reachable(structure)
    restricted = structure.restricted(law, structure.designated_states & law)
    atom_slots = set(structure.atom_slots.values())
    history = [s for s in structure.slots if s not in atom_slots]
    free = _free_slots(restricted, history)
    if free:
        restricted = _without_slots(restricted, free, restricted.agents)
        history = [s for s in history if s not in set(free)]
    replaced = _determined(restricted.law, history)
    if not replaced:
        return restricted
    cache: dict[int, Relation] = {}
    tables = (dict(restricted.belief_relations), dict(restricted.knowledge_relations))
    for table in tables:
        for agent, relation in table.items():
            if id(relation) not in cache:
                cache[id(relation)] = _substituted(relation, replaced, restricted.slots)
            table[agent] = cache[id(relation)]
    cube = _cube(list(replaced))
    return type(structure)(
        restricted.atom_slots,
        [s for s in restricted.slots if s not in replaced],
        restricted.law.exists(cube),
        restricted.agents,
        *tables,
        restricted.designated_states.exists(cube),
    )


def _free_slots(structure: Any, candidates: Iterable[int]) -> list[int]:
    """The candidates a structure can forget: no arrows read them, and either no relation
    reads them at all or the law leaves them free (then only observing relations do)."""
    relations = _distinct_relations(structure)
    by_arrows = _read_slots(r for r in relations if not isinstance(r, Observes))
    observed = set().union(*(r.slots for r in relations if isinstance(r, Observes)))
    law = structure.law
    return [
        s
        for s in candidates
        if s not in by_arrows and (s not in observed or law.exists(_cube([s])) == law)
    ]


def _without_slots(structure: Any, gone: Sequence[int], agents: Sequence[str]) -> Any:
    """The structure on ``agents`` with the variables ``gone`` quantified away (and no
    longer observed): a bounded morphism when :func:`_free_slots` chose them."""
    gone_set = set(gone)
    cube = _cube(gone)
    made: dict[int, Relation] = {}

    def without(relation: Relation) -> Relation:
        if id(relation) not in made:
            smaller = None
            if isinstance(relation, Observes) and relation.slots & gone_set:
                smaller = Observes(relation.slots - gone_set)
            made[id(relation)] = smaller or relation
        return made[id(relation)]

    return type(structure)(
        {a: s for a, s in structure.atom_slots.items() if s not in gone_set},
        [s for s in structure.slots if s not in gone_set],
        structure.law.exists(cube),
        tuple(agents),
        {a: without(structure.belief_relations[a]) for a in agents},
        {a: without(structure.knowledge_relations[a]) for a in agents},
        structure.designated_states.exists(cube),
    )


def _determined(law: BDDFunction, history: list[int]) -> dict[int, BDDFunction]:
    """The history variables whose value the law fixes from the atoms, with that function."""
    found: dict[int, BDDFunction] = {}
    for slot in history:
        rest = _cube([s for s in history if s != slot])
        here = _cube([slot])
        when_true = (law & _bdd.var(slot)).exists(rest).exists(here)
        when_false = (law & ~_bdd.var(slot)).exists(rest).exists(here)
        if not (when_true & when_false).satisfiable():
            found[slot] = when_true
    return found


def state_key(structure: Any) -> tuple:
    """A hashable key of a normalised structure: equal keys mean bisimilar states, and
    for structures left with atoms only or with few states, bisimilar means equal keys."""
    atoms = structure.atom_slots
    extra = [s for s in structure.slots if s not in set(atoms.values())]
    if extra and structure.n_worlds <= EXPLICIT_KEY_STATES:
        model = to_kripke(structure, EXPLICIT_KEY_STATES)
        return ("explicit", tuple(structure.agents), canonical_key(minimize(model)))
    order = sorted(atoms)
    target = {atoms[a]: i for i, a in enumerate(order)}
    target.update({s: len(order) + i for i, s in enumerate(sorted(extra))})
    rename = _renaming(tuple(sorted(target.items())))
    law = structure.law
    within = law & _bdd.primed(law, structure.slots)
    relations = []
    made: dict[int, BDDFunction] = {}
    for agent in sorted(structure.agents):
        for relation in (
            structure.belief_relations[agent],
            structure.knowledge_relations[agent],
        ):
            if id(relation) not in made:
                made[id(relation)] = (as_arrows(relation).bdd & within).substitute(rename)
            relations.append(made[id(relation)])
    kind = "structure" if extra else "atoms"
    return (
        kind,
        tuple(order),
        len(extra),
        law.substitute(rename),
        structure.designated_states.substitute(rename),
        tuple(sorted(structure.agents)),
        tuple(relations),
    )


def without_free_atoms(structure: Any, needed: Iterable[str], agents: Sequence[str]) -> Any:
    """The structure on ``agents``, without the atoms outside ``needed`` that it leaves
    free: no arrows read them, and the law does not constrain them (or no relation reads
    them at all).

    Dropping such an atom maps each state to one without it, a bounded morphism (a
    successor of the image is the image of the successor that keeps the atom's value),
    so every formula over the other atoms and these agents keeps its truth.

    Examples
    --------
    >>> from epistemica.del_ import KnowledgeStructure
    >>> s = KnowledgeStructure.from_observables(["p", "q", "r"], {"a": ["q", "r"]},
    ...                                         law="p -> r", designated=["p", "r"])
    >>> without_free_atoms(s, ["p"], ["a"]).atoms   # q is free; the law ties r to p
    ('p', 'r')
    """
    needed = set(needed)
    on_agents = (
        _without_slots(structure, [], agents) if len(agents) < len(structure.agents) else structure
    )
    candidates = [s for a, s in structure.atom_slots.items() if a not in needed]
    free = _free_slots(on_agents, candidates)
    return _without_slots(on_agents, free, agents) if free else on_agents


def unprimed(f: BDDFunction, slots: Sequence[int]) -> BDDFunction:
    """``f`` with every primed copy of ``slots`` replaced by the variable itself."""
    return f.substitute(_unpriming(tuple(sorted(slots))))


@functools.lru_cache(maxsize=256)
def _unpriming(slots: tuple[int, ...]):
    return _bdd.substitution([(2 * s + 1, _bdd.var(s)) for s in slots])


@functools.lru_cache(maxsize=4096)
def _renaming(pairs: tuple[tuple[int, int], ...]):
    """Slot ``a`` to slot ``b`` for each pair, primed copies alike (simultaneously)."""
    found = []
    for old, new in pairs:
        _bdd.var(max(old, new))
        found += [(2 * old, _bdd.var(new)), (2 * old + 1, _bdd.prime(new))]
    return _bdd.substitution(found)


def _cube(slots: Iterable[int]) -> BDDFunction:
    return _cached_cube(tuple(sorted(slots)))


@functools.lru_cache(maxsize=4096)
def _cached_cube(slots: tuple[int, ...]) -> BDDFunction:
    return _bdd.cube(slots)


def _distinct_relations(structure: Any) -> list[Relation]:
    found: dict[int, Relation] = {}
    for table in (structure.belief_relations, structure.knowledge_relations):
        for relation in table.values():
            found.setdefault(id(relation), relation)
    return list(found.values())


def _read_slots(relations: Iterable[Relation]) -> set[int]:
    read: set[int] = set()
    done: set[int] = set()
    for relation in relations:
        if id(relation) in done:
            continue
        done.add(id(relation))
        if isinstance(relation, Observes):
            read |= set(relation.slots)
        else:
            read |= {v // 2 for v in support(relation.bdd)}
    return read


def _substituted(relation: Relation, replaced: dict[int, BDDFunction], slots: list[int]):
    """``relation`` with each slot of ``replaced`` read as its function of the atoms."""
    if isinstance(relation, Observes):
        if not relation.slots & set(replaced):
            return relation
        literal = {s: _atom_literal(f) for s, f in replaced.items() if s in relation.slots}
        if all(found is not None for found in literal.values()):
            kept = {s for s in relation.slots if s not in replaced}
            return Observes(frozenset(kept | {found for found in literal.values()}))
    bdd = as_arrows(relation).bdd
    pairs = []
    for slot, f in replaced.items():
        pairs += [(2 * slot, f), (2 * slot + 1, _bdd.primed(f, slots))]
    return Arrows(bdd.substitute(_bdd.substitution(pairs)))


def _atom_literal(f: BDDFunction) -> int | None:
    """The slot ``s`` if ``f`` is the variable ``s`` or its negation, else None."""
    children = f.cofactors()
    if children is None:
        return None
    high, low = children
    literal = (high.valid() and not low.satisfiable()) or (low.valid() and not high.satisfiable())
    return f.node_var() // 2 if literal and f.node_var() % 2 == 0 else None
