"""The symbolic backend of :class:`~epistemica.del_.state.EpistemicState`: worlds as a law.

The worlds are the states of a knowledge structure's law (:func:`world_space`: atoms and a
propositional law, never listed), facts are BDDs, and a group's ``K`` and ``B`` sets (see
:mod:`~epistemica.del_.state.state`) are BDDs built by the same rules as the explicit
backend's masks. :func:`group_structure` is the knowledge structure of the group semantics:
one state variable per agent marks the group a state belongs to, so the ``2^n`` copies of
the explicit group model are a law on ``n`` more variables, and any formula is checked by
the symbolic model checker.

Examples
--------
>>> from epistemica.del_.state import EpistemicState, Observation
>>> space = world_space(["p", "q"], "p | q")
>>> s = EpistemicState(["a", "b"])
>>> _ = s.observe(Observation("tell", full={"a"}, pre="p"))
>>> count(space, knowledge_bdd(s, ("a",), space)), count(space, knowledge_bdd(s, ("b",), space))
(2, 3)
>>> group_structure(s, space).holds("K[a] p & ~K[b] p & K[a] ~K[b] p")
True
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from epistemica.del_.language.formula import Formula
from epistemica.del_.language.parser import as_formula
from epistemica.del_.models import KnowledgeStructure
from epistemica.del_.state.state import Chain, EpistemicState, soft_in_order
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic.relations import Arrows

if TYPE_CHECKING:
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = [
    "belief_bdd",
    "count",
    "group_structure",
    "holds_on",
    "knowledge_bdd",
    "world_space",
]


def world_space(atoms: Sequence[str], law: Formula | str | None = None) -> KnowledgeStructure:
    """The worlds: every valuation of ``atoms`` satisfying the propositional ``law``."""
    return KnowledgeStructure.from_observables(list(atoms), {}, law)


def count(space: KnowledgeStructure, worlds: BDDFunction) -> int:
    """How many worlds of ``space`` the BDD ``worlds`` holds."""
    for slot in space.slots:  # every variable allocated before counting over them
        _bdd.var(slot)
    return space.restricted(worlds, worlds).n_worlds


def knowledge_bdd(state: EpistemicState, chain: Chain, space: KnowledgeStructure) -> BDDFunction:
    """``K`` of the chain's group, as a BDD over the space's atoms."""
    keep = space.law
    for fact in state.hard(chain):
        keep &= space.truth(fact)
    return keep


def belief_bdd(
    state: EpistemicState, chain: Chain, space: KnowledgeStructure, revision: str = "recency"
) -> BDDFunction:
    """``B`` of the chain's group, as a BDD over the space's atoms (``revision`` as in
    :func:`~epistemica.del_.state.explicit.belief_mask`)."""
    keep = knowledge_bdd(state, chain, space)
    for atom in sorted(state.tracked - state.aware(chain)):
        if atom in space.atom_slots:
            keep &= ~_bdd.var(space.atom_slots[atom])
    for fact in soft_in_order(state, chain, revision):  # the first consistent one wins
        narrowed = keep & space.truth(fact)
        if narrowed.satisfiable():
            keep = narrowed
    return keep


def _within(bits: int, group_slots: Sequence[int]) -> BDDFunction:
    """The groups (as group variables) contained in the agent set ``bits``."""
    out = _bdd.true()
    for j, slot in enumerate(group_slots):
        if not bits >> j & 1:
            out &= ~_bdd.var(slot)
    return out


def group_structure(state: EpistemicState, space: KnowledgeStructure) -> KnowledgeStructure:
    """The knowledge structure of the group semantics over ``space``.

    States are pairs (group, world): group variable ``j`` says that agent ``j`` belongs to
    the group whose picture of the world the state is. The law holds the pairs whose world
    is in the group's ``K`` set; ``B[i]`` leads from (S, w) to every (S ∪ {i}, v) with ``v``
    in ``B`` of ``S ∪ {i}``, ``K[i]`` to every (S', v) with ``v`` in ``K`` of ``S'`` for
    the groups ``S'`` whose history agrees with that of ``S`` on what ``i`` observed; the
    designated states are the empty group (the actual world) with every world its ``K``
    set allows.
    """
    atom_slots = dict(space.atom_slots)
    first = max(space.slots, default=-1) + 1
    group_slots = list(range(first, first + len(state.agents)))
    observations = state.observations
    observed = [state.bits(o.observers) for o in observations]
    full = [state.bits(o.full) for o in observations]
    know = space.law
    for o, seen, fully in zip(observations, observed, full, strict=True):
        if o.pre is not None:
            know &= _within(seen, group_slots).imp(space.truth(o.pre))
        if o.senses is not None:
            sensed = space.truth(o.senses)
            know &= _within(fully, group_slots).imp(sensed if o.outcome else ~sensed)
    believe = know
    for atom in sorted(state.tracked):
        if atom in atom_slots:
            aware = _bdd.false()
            for o, fully in zip(observations, full, strict=True):
                if atom in o.aware:
                    aware |= _within(fully, group_slots)
            believe &= _bdd.var(atom_slots[atom]).imp(aware)
    world_cube = _bdd.cube(atom_slots.values())
    for o, fully in reversed(list(zip(observations, full, strict=True))):
        if o.suggests is None:
            continue
        fact = space.truth(o.suggests)
        consistent = believe.apply_exists(_bdd.AND, fact, world_cube)  # a function of S
        believe &= (_within(fully, group_slots) & consistent).imp(fact)
    slots = [*space.slots, *group_slots]
    belief, knowledge = {}, {}
    for i, agent in enumerate(state.agents):
        step = _bdd.prime(group_slots[i])
        for j, slot in enumerate(group_slots):
            if j != i:
                step &= _bdd.var(slot).equiv(_bdd.prime(slot))
        belief[agent] = Arrows(step & _bdd.primed(believe, slots))
        same_view = _bdd.true()  # S and S' saw alike what i observed
        for masks in (observed, full):
            for bits in masks:
                if bits >> i & 1:
                    inside = _within(bits, group_slots)
                    same_view &= inside.equiv(_bdd.primed(inside, group_slots))
        knowledge[agent] = Arrows(same_view & _bdd.primed(know, slots))
    actual = know & _within(0, group_slots)
    return KnowledgeStructure(atom_slots, slots, know, state.agents, belief, knowledge, actual)


def holds_on(space: KnowledgeStructure, worlds: BDDFunction, fact: Formula | str) -> bool:
    """Whether the propositional ``fact`` holds on every world of ``worlds``."""
    return not (worlds & ~space.truth(as_formula(fact))).satisfiable()
