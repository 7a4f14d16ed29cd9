"""Action models as knowledge (and belief) transformers: the product update, symbolically.

The product ``S ⊗ A`` of a structure and an action model (van Benthem et al. 2018,
sections 4 and 5, with factual change) adds variables and keeps every old one:

- *event bits*: the event that happened, in binary (none for a one-event action);
- for each atom a postcondition assigns, a *fresh variable for its new value*: the atom
  now names the fresh variable, and the old variable keeps the value before the update,
  so the old relations (which read old values) and the old law stay valid unchanged;
- the new law: old law, the event's precondition, and ``new <-> post`` per changed atom.

An agent's new relation is its old one together with the event edges it has:
``(s, e) R (t, f)`` iff ``s R t``, ``e R f`` and the edge's condition holds at ``s``.
When the old relation is observational and the agent's event edges form an unconditioned
equivalence, the new one stays observational: the agent also observes the event's class
(bits constrained by the law). Anything else becomes a BDD of arrows. Preconditions,
postconditions and conditions may be any formulas (they are evaluated in ``S`` first).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

from epistemica.del_.errors import ModelError
from epistemica.del_.language.formula import Formula
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic.relations import Arrows, Observes, Relation, as_arrows

if TYPE_CHECKING:
    from epistemica.del_.explicit.action import ActionModel
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = ["Product", "product"]


class Product(NamedTuple):
    """The updated structure (pointed at the executable designated pairs) and the BDD of
    the designated events over the event bits."""

    structure: Any
    designated_events: BDDFunction


def product(
    s: Any, action: ActionModel, truth: Callable[[Formula], BDDFunction] | None = None
) -> Product:
    """The product update of structure ``s`` with ``action`` (cached per action object).

    ``truth`` evaluates a formula in ``s`` (default: ``s.truth``).
    """
    key = ("after", id(action))
    cached = s.derived.get(key)
    if cached is None or cached[0] is not action:
        with _bdd.node_limit():
            cached = s.derived[key] = (action, _product(s, action, truth or s.truth))
    return cached[1]


def _bits(n: int) -> int:
    return max(0, (n - 1).bit_length())


def _product(s: Any, action: ActionModel, truth: Callable) -> Product:
    missing = set(s.agents) - set(action.agents)
    extra = set(action.agents) - set(s.agents)
    if missing or extra:
        raise ModelError(
            "the action model and the Kripke model must have the same agents",
            hint=f"missing in the action: {sorted(missing)}; unknown to the model: {sorted(extra)}",
        )
    if _is_public(action):  # the submodel of the precondition: no new variable
        pre = truth(action.pre[0])
        return Product(s.restricted(pre, s.designated_states & pre), _bdd.true())
    start = max(s.slots, default=-1) + 1
    fresh = _Allocator(start)
    n_events = len(action.events)
    event_slots = fresh.take(_bits(n_events))
    code = [_bdd.minterm(event_slots, e) for e in range(n_events)]
    law = s.law & _any(code[e] & truth(action.pre[e]) for e in range(n_events))

    atoms = dict(s.atom_slots)
    changed = list(dict.fromkeys(a for post in action.post for a in post))
    for atom in changed:
        old = _bdd.var(atoms[atom]) if atom in atoms else _bdd.false()
        new_slot = fresh.take(1)[0]
        value = _any(
            code[e] & (truth(post[atom]) if atom in post else old)
            for e, post in enumerate(action.post)
        )
        law &= _bdd.var(new_slot).equiv(value)
        atoms[atom] = new_slot

    belief: dict[str, Relation] = {}
    knowledge: dict[str, Relation] = {}
    made: dict[tuple, tuple[Relation, BDDFunction]] = {}
    for agent in s.agents:
        for table, old, edges in (
            (belief, s.belief_relations[agent], action.edges[agent]),
            (knowledge, s.knowledge_relations[agent], action.knowledge_edges[agent]),
        ):
            # Same old relation and same edges: the same new relation (one object).
            pair = (id(old), id(edges))
            if pair not in made:
                made[pair] = _relation(old, edges, code, event_slots, fresh, truth)
            table[agent], constraint = made[pair]
            law &= constraint

    designated_events = _any(code[e] for e in action.designated_positions)
    structure = type(s)(
        atoms,
        s.slots + tuple(range(start, fresh.next)),
        law,
        s.agents,
        belief,
        knowledge,
        s.designated_states & designated_events,
    )
    return Product(structure, designated_events)


def _is_public(action: ActionModel) -> bool:
    """One event, no postcondition, seen by every agent as itself: a public announcement."""
    if len(action.events) != 1 or action.post[0]:
        return False
    loop = ((0, 0, None),)
    return all(action.edges[a] == loop and action.knowledge_edges[a] == loop for a in action.agents)


class _Allocator:
    """Hands out fresh slots above every slot in use."""

    def __init__(self, start: int) -> None:
        self.next = start

    def take(self, n: int) -> list[int]:
        slots = list(range(self.next, self.next + n))
        self.next += n
        return slots


def _any(parts) -> BDDFunction:
    result = _bdd.false()
    for p in parts:
        result |= p
    return result


def _relation(
    old: Relation,
    edges: tuple,
    code: list[BDDFunction],
    event_slots: list[int],
    fresh: _Allocator,
    truth: Callable,
) -> tuple[Relation, BDDFunction]:
    """The agent's new relation and a constraint to add to the law (class bits)."""
    classes = _equivalence_classes(edges, len(code))
    if isinstance(old, Observes) and classes is not None:
        n_classes = max(classes) + 1
        if n_classes == 1:
            return old, _bdd.true()
        if n_classes == len(code):
            return Observes(old.slots | set(event_slots)), _bdd.true()
        class_slots = fresh.take(_bits(n_classes))
        constraint = _bdd.true()
        for e, c in enumerate(classes):
            constraint &= code[e].imp(_bdd.minterm(class_slots, c))
        return Observes(old.slots | set(class_slots)), constraint
    arrows = _bdd.false()
    for e, f, condition in edges:
        step = code[e] & _bdd.primed(code[f], event_slots)
        if condition is not None:
            step &= truth(condition)
        arrows |= step
    return Arrows(as_arrows(old).bdd & arrows), _bdd.true()


def _equivalence_classes(edges: tuple, n: int) -> list[int] | None:
    """Class per event if the edges are an unconditioned equivalence, else ``None``."""
    if any(c is not None for _, _, c in edges):
        return None
    pairs = {(e, f) for e, f, _ in edges}
    label = [-1] * n
    classes = 0
    for e in range(n):
        if label[e] < 0:
            members = [f for f in range(n) if (e, f) in pairs]
            for f in members:
                label[f] = classes
            classes += 1
    for e in range(n):
        for f in range(n):
            if ((e, f) in pairs) != (label[e] == label[f]):
                return None
    return label
