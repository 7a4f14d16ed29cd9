"""An agent's relation in a knowledge structure: observed variables or a BDD of arrows.

``Observes(slots)``: the agent cannot tell apart two states that agree on these variables
(an equivalence: S5 knowledge, van Benthem et al. 2018, section 3). ``Arrows(bdd)``: a BDD
over the state variables and their primed copies, true of ``(s, t)`` when ``t`` is
accessible from ``s`` (any relation: KD45 belief and beyond, section 5). In both cases only
states satisfying the structure's law are ever accessible.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from epistemica.del_.symbolic import _bdd

if TYPE_CHECKING:
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = ["Arrows", "Observes", "as_arrows", "box", "intersection"]


@dataclass(frozen=True)
class Observes:
    """The agent sees exactly the variables of ``slots``."""

    slots: frozenset[int]


@dataclass(frozen=True, eq=False)
class Arrows:
    """The agent's accessibility relation as a BDD over unprimed and primed variables."""

    bdd: BDDFunction


Relation = Observes | Arrows


def as_arrows(relation: Relation) -> Arrows:
    """The relation as arrows (observing ``v`` means ``v <-> v'``)."""
    if isinstance(relation, Arrows):
        return relation
    result = _bdd.true()
    for s in sorted(relation.slots, reverse=True):
        result = _bdd.var(s).equiv(_bdd.prime(s)) & result
    return Arrows(result)


def box(
    relation: Relation, law: BDDFunction, inner: BDDFunction, state_slots: Sequence[int]
) -> BDDFunction:
    """The states all of whose accessible law-states satisfy ``inner``."""
    if isinstance(relation, Observes):
        hidden = [s for s in state_slots if s not in relation.slots]
        return law.apply_forall(_bdd.IMP, inner, _bdd.cube(hidden))
    bad = _bdd.primed(law & ~inner, state_slots)
    return ~relation.bdd.apply_exists(_bdd.AND, bad, _bdd.cube(state_slots, primed_copy=True))


def intersection(relations: Sequence[Relation]) -> Relation:
    """The intersection (distributed knowledge): observing the union, or both arrows."""
    if all(isinstance(r, Observes) for r in relations):
        return Observes(frozenset().union(*(r.slots for r in relations)))
    result = _bdd.true()
    for r in relations:
        result &= as_arrows(r).bdd
    return Arrows(result)
