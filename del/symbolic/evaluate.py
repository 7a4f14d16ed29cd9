"""Formulas to BDDs in a knowledge structure: quantification for the modalities, greatest
fixed points for common knowledge and belief, structure transformers for ``[!f]`` and
``[ACT]``.

The semantics is :mod:`epistemica.del_.explicit.checker`'s, state by state; only the law-states
matter, so a BDD may say anything outside the law. Truth sets are memoised per structure
and subformula.
"""

from __future__ import annotations

import gc
from collections.abc import Callable, Generator, Mapping
from typing import TYPE_CHECKING, Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language.formula import And, Atom, Bottom, Formula, Iff, Implies, Not, Or, Top
from epistemica.del_.language.modalities import (
    After,
    Announce,
    AnnounceDiamond,
    Believe,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
)
from epistemica.del_.language.walk import fold_nodes
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic.relations import box, intersection
from epistemica.del_.symbolic.transform import product

if TYPE_CHECKING:
    from epistemica.del_.explicit.action import ActionModel
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = ["evaluate", "propositional"]


def evaluate(
    structure: Any, formula: Formula, actions: Mapping[str, ActionModel] | None = None
) -> BDDFunction:
    """The BDD of the states of ``structure`` where ``formula`` holds.

    Evaluation runs on an explicit stack (no recursion), so formulas nested 10,000 deep
    or chains of 100,000 operands are fine, as on the explicit backend.

    Examples
    --------
    >>> from epistemica.del_ import KnowledgeStructure
    >>> s = KnowledgeStructure.from_observables(["p"], {"a": [], "b": ["p"]})
    >>> evaluate(s, Know("b", Atom("p"))) == s.truth("p")
    True
    """
    with _bdd.node_limit():
        return _Run(actions).value(structure, formula)


def propositional(f: Formula, atom: Callable[[Atom], BDDFunction]) -> BDDFunction:
    """The BDD of a formula without modalities, atoms given by ``atom``.

    A fold over the node objects (:func:`~epistemica.del_.language.walk.fold_nodes`):
    no recursion, a shared node computed once, each BDD freed after its last use.

    Examples
    --------
    >>> from epistemica.del_.language.parser import parse_formula
    >>> p = _bdd.var(0)
    >>> propositional(parse_formula("~~p | false"), lambda a: p) == p
    True
    """

    def combine(node: Formula, values: list[BDDFunction]) -> BDDFunction:
        kind = type(node)
        if kind is Atom:
            return atom(node)
        if kind is Top:
            return _bdd.true()
        if kind is Bottom:
            return _bdd.false()
        if kind is Not:
            return ~values[0]
        if kind in _BINARY:
            return _connective(kind, *values)
        raise InvalidArgumentError(
            f"expected a propositional formula, found {kind.__name__}",
            hint="laws constrain valuations only; they cannot mention K, B, C, ...",
        )

    return fold_nodes(f, combine)


_BINARY = (And, Or, Implies, Iff)


def _connective(kind: type, left: BDDFunction, right: BDDFunction) -> BDDFunction:
    if kind is And:
        return left & right
    if kind is Or:
        return left | right
    if kind is Implies:
        return left.imp(right)
    return left.equiv(right)


Node = Generator[tuple, "BDDFunction", "BDDFunction"]


class _Run:
    """One evaluation: the named actions in force, and an explicit stack of nodes.

    Every node that is not a leaf is a generator yielding requests ``(structure,
    subformula)`` and receiving their BDDs, as in the explicit checker; results are
    memoised per structure and subformula (and per actions, for formulas naming one).
    """

    def __init__(self, actions: Mapping[str, ActionModel] | None) -> None:
        self.actions = dict(actions or {})
        self.key = frozenset((name, id(a)) for name, a in self.actions.items())

    def value(self, s: Any, root: Formula) -> BDDFunction:
        if not gc.isenabled():
            return self._drive(s, root)
        # One suspended generator per pending node: the cyclic garbage collector would
        # rescan them all, over and over (quadratic time). Evaluation makes no cycles.
        gc.disable()
        try:
            return self._drive(s, root)
        finally:
            gc.enable()

    def _drive(self, s: Any, root: Formula) -> BDDFunction:
        stack: list[tuple[Node, Any, tuple]] = []
        result = self._open(stack, s, root)
        while stack:
            node, where, key = stack[-1]
            try:
                request = node.send(result)
            except StopIteration as stop:
                stack.pop()
                result = where.memo[key] = stop.value
                continue
            result = self._open(stack, *request)
        return result

    def _open(self, stack: list, s: Any, f: Formula) -> BDDFunction | None:
        """The memoised result, or ``None`` after pushing the node that computes it."""
        kind = type(f)
        if kind is Atom:
            return _bdd.var(s.atom_slot(f))
        if kind is Top:
            return _bdd.true()
        if kind is Bottom:
            return _bdd.false()
        key = (f, self.key)
        found = s.memo.get(key)
        if found is not None:
            return found
        stack.append((self._node(s, f), s, key))
        return None

    def _node(self, s: Any, f: Formula) -> Node:
        """Evaluate one node of ``f`` (not a leaf), yielding requests for its subresults."""
        kind = type(f)
        if kind is Not:
            return ~(yield s, f.operand)
        if kind in _BINARY:
            left = yield s, f.left
            return _connective(kind, left, (yield s, f.right))
        if kind is Know or kind is Believe:
            relation = s.relation(f.agent, "knowledge" if kind is Know else "belief")
            return box(relation, s.law, (yield s, f.operand), s.slots)
        if kind is KnowWhether:
            relation = s.relation(f.agent, "knowledge")
            inner = yield s, f.operand
            return box(relation, s.law, inner, s.slots) | box(relation, s.law, ~inner, s.slots)
        if kind is Everybody or kind is EverybodyBelieves:
            which = "knowledge" if kind is Everybody else "belief"
            return _everybody(s, f.group, which, (yield s, f.operand))
        if kind is Common or kind is CommonBelief:
            which = "knowledge" if kind is Common else "belief"
            return _common(s, f.group, which, (yield s, f.operand))
        if kind is Distributed:
            relation = intersection([s.relation(a, "knowledge") for a in f.group])
            return box(relation, s.law, (yield s, f.operand), s.slots)
        if kind is Announce or kind is AnnounceDiamond:
            return (yield from self._announcement(s, f))
        if kind is After:
            return (yield from self._after(s, f))
        raise InvalidArgumentError(
            f"cannot evaluate {kind.__name__}",
            hint="B[a | f], Sb[a], [^^f] and [^f] need a plausibility model: a spec with a "
            "'plausibility' line, or epistemica.del_.explicit.plausibility.PlausibilityModel",
        )

    def _announcement(self, s: Any, f: Announce | AnnounceDiamond) -> Node:
        announced = yield s, f.announcement
        key = ("announce", f.announcement, self.key)
        sub = s.derived.get(key)
        if sub is None:
            sub = s.derived[key] = s.restricted(announced, _bdd.false())
        inside = announced & (yield sub, f.operand)
        if isinstance(f, Announce):
            return ~announced | inside
        return inside

    def _after(self, s: Any, f: After) -> Node:
        action = self.actions.get(f.action)
        if action is None:
            known = ", ".join(sorted(self.actions)) or "none"
            raise InvalidArgumentError(
                f"unknown action {f.action!r} in {_short(f)}",
                hint=f"pass it in `actions`; known actions: {known}",
            )
        # Preconditions, postconditions and conditions are usually small: a run of their own.
        result = product(s, action, lambda g: self.value(s, g))
        after = result.structure
        inner = yield after, f.operand
        old = set(s.slots)
        fresh = [slot for slot in after.slots if slot not in old]
        # g at every (s, e) of the product with e designated: quantify the new variables.
        return after.law.apply_forall(
            _bdd.IMP, result.designated_events.imp(inner), _bdd.cube(fresh)
        )


def _short(f: Formula) -> str:
    """A formula's text for a message, cut short (deep formulas print long)."""
    text = str(f)
    return text if len(text) <= 60 else text[:57] + "..."


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
