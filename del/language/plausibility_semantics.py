"""The semantics of the plausibility language, once for every backend.

A plausibility model (Baltag and Smets, "A qualitative theory of dynamic interactive belief
revision", 2008) gives each agent a partition of the worlds into information cells and,
inside each cell, a total preorder: which worlds the agent finds more plausible. Both
backends store the preorder as *ranks* (0 is most plausible; only the order of the ranks
within a cell matters):

- :class:`~epistemica.del_.explicit.plausibility.PlausibilityModel`: a rank per world;
- :class:`~epistemica.del_.symbolic.plausibility.PlausibilityStructure`: one BDD per rank
  level.

:func:`evaluate_plausibility` walks a formula on an explicit stack (no recursion; a
subformula is computed once per model and memoised there) and asks the backend for the
few operations below, so the two backends share every line of the semantics except the
set operations themselves. At a world ``w`` of agent ``a``'s cell ``cell(w)``:

- ``K[a] f``: ``f`` holds in all of ``cell(w)``; ``Kw[a] f`` is ``K[a] f | K[a] ~f``;
- ``B[a | c] f``: ``f`` holds at the most plausible ``c``-worlds of ``cell(w)`` (true if
  the cell has no ``c``-world); ``B[a] f`` is ``B[a | true] f``: plain belief, the KD45
  modality of the relation from each world to the most plausible worlds of its cell;
- ``Sb[a] f`` (safe belief): ``f`` holds at every world of ``cell(w)`` that is at least as
  plausible as ``w``;
- ``E[G] f`` and ``EB[G] f``: every agent of ``G`` knows (believes) ``f``;
- ``[!c] f`` and ``<!c> f``: the hard public announcement (the submodel of the
  ``c``-worlds, orders restricted);
- ``[^^c] f`` (radical upgrade ⇑c): ``f`` after every agent ranks, in every cell, all
  ``c``-worlds above all others, keeping the order inside both zones;
  ``[^c] f`` (conservative upgrade ↑c): ``f`` after the best ``c``-worlds of every cell
  (per agent) move to the top, the rest of the order kept. Upgrades change no cell and
  are always executable.

Common knowledge and belief, distributed knowledge and named actions are refused with a
message: plausibility models do not interpret them (yet).
"""

from __future__ import annotations

import gc
from collections.abc import Generator
from typing import Any, Protocol

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.language.formula import And, Atom, Bottom, Formula, Iff, Implies, Not, Or, Top
from epistemica.del_.language.modalities import (
    Announce,
    AnnounceDiamond,
    Believe,
    ConditionalBelief,
    ConservativeUpgrade,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
    RadicalUpgrade,
    SafeBelief,
)

__all__ = ["PlausibilityBackend", "evaluate_plausibility"]


class PlausibilityBackend(Protocol):
    """What :func:`evaluate_plausibility` needs of a model; truth sets support ``~ & |``."""

    memo: dict[Formula, Any]
    derived: dict[tuple[str, Formula], PlausibilityBackend]

    def atom(self, atom: Atom) -> Any: ...
    def constant(self, value: bool) -> Any: ...
    def know(self, agent: str, truth: Any) -> Any: ...
    def conditional_belief(self, agent: str, condition: Any, truth: Any) -> Any: ...
    def safe_belief(self, agent: str, truth: Any) -> Any: ...
    def restricted(self, truth: Any) -> PlausibilityBackend: ...
    def lifted(self, submodel: PlausibilityBackend, truth: Any) -> Any: ...
    def radical_upgrade(self, truth: Any) -> PlausibilityBackend: ...
    def conservative_upgrade(self, truth: Any) -> PlausibilityBackend: ...


Node = Generator[tuple, Any, Any]


def evaluate_plausibility(model: PlausibilityBackend, formula: Formula) -> Any:
    """The truth set of ``formula`` in ``model``, in the backend's representation.

    Examples
    --------
    >>> from epistemica.del_.explicit.plausibility import PlausibilityModel
    >>> from epistemica.del_.language.parser import parse_formula
    >>> m = PlausibilityModel.from_levels(["p"], {"a": ["~p", "p"]})
    >>> evaluate_plausibility(m, parse_formula("B[a] ~p & B[a | p] p")).tolist()
    [True, True]
    """
    if not gc.isenabled():
        return _drive(model, formula)
    # One suspended generator per pending node: the cyclic collector would rescan them.
    gc.disable()
    try:
        return _drive(model, formula)
    finally:
        gc.enable()


def _drive(model: PlausibilityBackend, root: Formula) -> Any:
    stack: list[tuple[Node, PlausibilityBackend, Formula]] = []
    result = _open(stack, model, root)
    while stack:
        node, where, f = stack[-1]
        try:
            request = node.send(result)
        except StopIteration as stop:
            stack.pop()
            result = where.memo[f] = stop.value
            continue
        result = _open(stack, *request)
    return result


def _open(stack: list, model: PlausibilityBackend, f: Formula) -> Any:
    """The memoised or leaf value, or ``None`` after pushing the node that computes it."""
    kind = type(f)
    if kind is Atom:
        return model.atom(f)
    if kind is Top or kind is Bottom:
        return model.constant(kind is Top)
    found = model.memo.get(f)
    if found is not None:
        return found
    stack.append((_node(model, f), model, f))
    return None


def _node(m: PlausibilityBackend, f: Any) -> Node:
    kind = type(f)
    if kind is Not:
        return ~(yield m, f.operand)
    if kind in (And, Or, Implies, Iff):
        left = yield m, f.left
        right = yield m, f.right
        if kind is And:
            return left & right
        if kind is Or:
            return left | right
        if kind is Implies:
            return ~left | right
        return (left & right) | (~left & ~right)
    if kind is Know:
        return m.know(f.agent, (yield m, f.operand))
    if kind is KnowWhether:
        inner = yield m, f.operand
        return m.know(f.agent, inner) | m.know(f.agent, ~inner)
    if kind is Believe:
        return m.conditional_belief(f.agent, m.constant(True), (yield m, f.operand))
    if kind is ConditionalBelief:
        condition = yield m, f.condition
        return m.conditional_belief(f.agent, condition, (yield m, f.operand))
    if kind is SafeBelief:
        return m.safe_belief(f.agent, (yield m, f.operand))
    if kind is Everybody or kind is EverybodyBelieves:
        inner = yield m, f.operand
        result = m.constant(True)
        for agent in f.group:
            if kind is Everybody:
                result = result & m.know(agent, inner)
            else:
                result = result & m.conditional_belief(agent, m.constant(True), inner)
        return result
    if kind is Announce or kind is AnnounceDiamond:
        announced = yield m, f.announcement
        sub = _derived(m, "announce", f.announcement, announced)
        inside = announced & m.lifted(sub, (yield sub, f.operand))
        return (~announced | inside) if kind is Announce else inside
    if kind is RadicalUpgrade or kind is ConservativeUpgrade:
        upgrade = yield m, f.upgrade
        after = _derived(m, kind.__name__, f.upgrade, upgrade)
        return (yield after, f.operand)
    raise InvalidArgumentError(
        f"plausibility models do not interpret {kind.__name__}",
        hint="use K, B, B[a | f], Sb, E, EB, Kw, M, announcements and upgrades; "
        "common and distributed knowledge and named actions need a Kripke model",
    )


def _derived(m: PlausibilityBackend, how: str, f: Formula, truth: Any) -> PlausibilityBackend:
    """The model after announcing or upgrading with ``f`` (whose truth set is ``truth``),
    made once per model: the formulas below it are then memoised in that model."""
    key = (how, f)
    found = m.derived.get(key)
    if found is None:
        if how == "announce":
            found = m.restricted(truth)
        elif how == "RadicalUpgrade":
            found = m.radical_upgrade(truth)
        else:
            found = m.conservative_upgrade(truth)
        m.derived[key] = found
    return found
