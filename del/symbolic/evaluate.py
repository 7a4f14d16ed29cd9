"""Formulas to BDDs in a knowledge structure: quantification for the modalities, greatest
fixed points for common knowledge and belief, structure transformers for ``[!f]`` and
``[ACT]``.

The semantics is :mod:`epistemica.del_.explicit.checker`'s, state by state; only the law-states
matter, so a BDD may say anything outside the law. Truth sets are memoised per structure
and subformula.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language.formula import (
    After,
    And,
    Announce,
    AnnounceDiamond,
    Atom,
    Believe,
    Bottom,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Formula,
    Iff,
    Implies,
    Know,
    KnowWhether,
    Not,
    Or,
    Top,
)
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic._bdd import BDDFunction
from epistemica.del_.symbolic.relations import box, intersection
from epistemica.del_.symbolic.transform import product

if TYPE_CHECKING:
    from epistemica.del_.explicit.action import ActionModel

__all__ = ["evaluate", "propositional"]


def evaluate(
    structure: Any, formula: Formula, actions: Mapping[str, ActionModel] | None = None
) -> BDDFunction:
    """The BDD of the states of ``structure`` where ``formula`` holds.

    Examples
    --------
    >>> from epistemica.del_ import KnowledgeStructure
    >>> s = KnowledgeStructure.from_observables(["p"], {"a": [], "b": ["p"]})
    >>> evaluate(s, Know("b", Atom("p"))) == s.truth("p")
    True
    """
    with _bdd.node_limit():
        return _Context(actions).eval(structure, formula)


def propositional(f: Formula, atom: Callable[[Atom], BDDFunction]) -> BDDFunction:
    """The BDD of a formula without modalities, atoms given by ``atom``."""
    kind = type(f)
    if kind is Atom:
        return atom(f)
    if kind is Top:
        return _bdd.true()
    if kind is Bottom:
        return _bdd.false()
    if kind is Not:
        return ~propositional(f.operand, atom)
    left, right = propositional(f.left, atom), propositional(f.right, atom)
    return _connective(kind, left, right)


def _connective(kind: type, left: BDDFunction, right: BDDFunction) -> BDDFunction:
    if kind is And:
        return left & right
    if kind is Or:
        return left | right
    if kind is Implies:
        return left.imp(right)
    return left.equiv(right)


class _Context:
    """One evaluation: the named actions in force."""

    def __init__(self, actions: Mapping[str, ActionModel] | None) -> None:
        self.actions = dict(actions or {})
        self.key = frozenset((name, id(a)) for name, a in self.actions.items())

    def eval(self, s: Any, f: Formula) -> BDDFunction:
        key = (f, self.key)
        found = s.memo.get(key)
        if found is None:
            found = s.memo[key] = self._compute(s, f)
        return found

    def _compute(self, s: Any, f: Formula) -> BDDFunction:
        kind = type(f)
        if kind is Atom:
            return _bdd.var(s.atom_slot(f))
        if kind is Top:
            return _bdd.true()
        if kind is Bottom:
            return _bdd.false()
        if kind is Not:
            return ~self.eval(s, f.operand)
        if kind in (And, Or, Implies, Iff):
            return _connective(kind, self.eval(s, f.left), self.eval(s, f.right))
        if kind is Know or kind is Believe:
            relation = s.relation(f.agent, "knowledge" if kind is Know else "belief")
            return box(relation, s.law, self.eval(s, f.operand), s.slots)
        if kind is KnowWhether:
            relation = s.relation(f.agent, "knowledge")
            inner = self.eval(s, f.operand)
            return box(relation, s.law, inner, s.slots) | box(relation, s.law, ~inner, s.slots)
        if kind is Everybody or kind is EverybodyBelieves:
            which = "knowledge" if kind is Everybody else "belief"
            return _everybody(s, f.group, which, self.eval(s, f.operand))
        if kind is Common or kind is CommonBelief:
            which = "knowledge" if kind is Common else "belief"
            return _common(s, f.group, which, self.eval(s, f.operand))
        if kind is Distributed:
            relation = intersection([s.relation(a, "knowledge") for a in f.group])
            return box(relation, s.law, self.eval(s, f.operand), s.slots)
        if kind is Announce or kind is AnnounceDiamond:
            return self._announcement(s, f)
        if kind is After:
            return self._after(s, f)
        raise InvalidArgumentError(f"cannot evaluate {type(f).__name__}")

    def _announcement(self, s: Any, f: Announce | AnnounceDiamond) -> BDDFunction:
        announced = self.eval(s, f.announcement)
        key = ("announce", f.announcement, self.key)
        sub = s.derived.get(key)
        if sub is None:
            sub = s.derived[key] = s.restricted(announced, _bdd.false())
        inside = announced & self.eval(sub, f.operand)
        if isinstance(f, Announce):
            return ~announced | inside
        return inside

    def _after(self, s: Any, f: After) -> BDDFunction:
        action = self.actions.get(f.action)
        if action is None:
            known = ", ".join(sorted(self.actions)) or "none"
            raise InvalidArgumentError(
                f"unknown action {f.action!r} in {f}",
                hint=f"pass it in `actions`; known actions: {known}",
            )
        result = product(s, action, lambda g: self.eval(s, g))
        after = result.structure
        inner = self.eval(after, f.operand)
        fresh = [slot for slot in after.slots if slot not in set(s.slots)]
        # g at every (s, e) of the product with e designated: quantify the new variables.
        return after.law.apply_forall(
            _bdd.IMP, result.designated_events.imp(inner), _bdd.cube(fresh)
        )


def _everybody(s: Any, group: tuple[str, ...], which: str, inner: BDDFunction) -> BDDFunction:
    result = _bdd.true()
    for agent in group:
        result &= box(s.relation(agent, which), s.law, inner, s.slots)
    return result


def _common(s: Any, group: tuple[str, ...], which: str, inner: BDDFunction) -> BDDFunction:
    """Greatest fixed point of ``X = E(inner & X)``: ``inner`` on every path of >= 1 step."""
    current = _bdd.true()
    while True:
        following = _everybody(s, group, which, inner & current) & s.law
        if following == current:
            return following
        current = following
