"""EPDDL formulas grounded into epistemica's: connectives, quantifiers, modalities, and the
conditions of list comprehensions.

Helper of :mod:`epistemica.del_.formats._epddl_ground` (whose :class:`Grounder` resolves
names and bindings; it is passed in as ``g``). The semantics is plank's: ``[i] f`` is
``B[i] f`` (an EPDDL agent has one relation); ``[G] f`` and ``<G> f`` quantify agent by
agent (``<G>`` is not the dual of ``[G]``); ``Kw.`` is "believes whether"; ``C.`` common
belief; ``forall``/``exists`` range over the bindings of their list comprehension; facts,
``=`` and ``/=`` are decided when grounding. Constants are folded, so that facts leave no
trace in the formulas.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from lark import Tree

from epistemica.del_.formats._epddl_syntax import Source, mangle
from epistemica.del_.language.formula import And, Bottom, Formula, Implies, Not, Or, Top
from epistemica.del_.language.modalities import Believe, CommonBelief

__all__ = ["conj", "disj", "ground_formula", "negate", "static_truth"]

_MODAL = {"box", "diamond"}


def negate(f: Formula) -> Formula:
    """``~f``, folding constants."""
    if isinstance(f, Top):
        return Bottom()
    if isinstance(f, Bottom):
        return Top()
    if isinstance(f, Not):
        return f.operand
    return Not(f)


def conj(parts: Iterable[Formula]) -> Formula:
    """The conjunction of ``parts``, folding constants (empty: ``true``)."""
    kept: dict[Formula, None] = {}  # hashed: a theory's law may have thousands of parts
    for f in parts:
        if isinstance(f, Bottom):
            return Bottom()
        if not isinstance(f, Top):
            kept[f] = None
    return _fold(list(kept), And, Top())


def disj(parts: Iterable[Formula]) -> Formula:
    """The disjunction of ``parts``, folding constants (empty: ``false``)."""
    kept: dict[Formula, None] = {}
    for f in parts:
        if isinstance(f, Top):
            return Top()
        if not isinstance(f, Bottom):
            kept[f] = None
    return _fold(list(kept), Or, Bottom())


def _fold(parts: list[Formula], op: type, empty: Formula) -> Formula:
    if not parts:
        return empty
    result = parts[0]
    for f in parts[1:]:
        result = op(result, f)
    return result


def _implies(left: Formula, right: Formula) -> Formula:
    if isinstance(left, Bottom) or isinstance(right, Top):
        return Top()
    if isinstance(left, Top):
        return right
    if isinstance(right, Bottom):
        return negate(left)
    return Implies(left, right)


def ground_formula(g: Any, tree: Tree, env: Mapping[str, str], src: Source) -> Formula:
    """The ground :class:`Formula` of a ``formula`` (or body) node under ``env``."""
    if tree.data == "formula":
        tree = tree.children[0]
    kind = tree.data
    kids = tree.children
    if kind == "top":
        return Top()
    if kind == "bottom":
        return Bottom()
    if kind == "predicate":
        return g.atom(kids[0], kids[1:], env, src)
    if kind in ("eq", "neq"):
        same = g.term(kids[0], env, src) == g.term(kids[1], env, src)
        return Top() if same == (kind == "eq") else Bottom()
    if kind == "neg":
        return negate(ground_formula(g, kids[0], env, src))
    if kind in ("conj", "disj"):
        parts = (ground_formula(g, k, env, src) for k in kids)
        return conj(parts) if kind == "conj" else disj(parts)
    if kind == "imply":
        left, right = (ground_formula(g, k, env, src) for k in kids)
        return _implies(left, right)
    if kind in ("forall", "exists"):
        comprehension, body = kids
        parts = (ground_formula(g, body, b, src) for b in g.bindings(comprehension, env, src))
        return conj(parts) if kind == "forall" else disj(parts)
    if kind in _MODAL:
        return _modal(g, tree, env, src)
    raise AssertionError(kind)  # pragma: no cover - the grammar has no other node


def _modal(g: Any, tree: Tree, env: Mapping[str, str], src: Source) -> Formula:
    modality, operand = tree.children
    name, index = modality.children
    group = [mangle(a) for a in g.agent_list(index, env, src)]
    f = ground_formula(g, operand, env, src)
    box = tree.data == "box"
    if name is None:
        if box:
            return conj(Believe(a, f) for a in group)
        return conj(negate(Believe(a, negate(f))) for a in group)
    if str(name) == "Kw.":
        if box:
            return conj(Or(Believe(a, f), Believe(a, negate(f))) for a in group)
        return conj(And(negate(Believe(a, f)), negate(Believe(a, negate(f)))) for a in group)
    if box:
        return CommonBelief(tuple(group), f)
    return negate(CommonBelief(tuple(group), negate(f)))


def static_truth(g: Any, tree: Tree, env: Mapping[str, str], src: Source, local=None) -> bool:
    """Truth of a list-comprehension condition: facts, ``=``, ``/=`` and connectives."""
    if tree.data == "formula":
        tree = tree.children[0]
    kind, kids = tree.data, tree.children
    if kind in ("top", "bottom"):
        return kind == "top"
    if kind == "predicate":
        _, is_fact, _ = g.predicate(kids[0], kids[1:], src)
        if not is_fact:
            raise src.error(
                f"'{kids[0]}' is not a fact", kids[0],
                "a list comprehension's condition may use only facts, = and /=, whose "
                "truth is known before any state",
            )  # fmt: skip
        values = g.check_args(kids[0], kids[1:], env, src, local)
        return (str(kids[0]), values) in g.facts
    if kind in ("eq", "neq"):
        same = g.term(kids[0], env, src, local) == g.term(kids[1], env, src, local)
        return same == (kind == "eq")
    if kind == "neg":
        return not static_truth(g, kids[0], env, src, local)
    if kind == "conj":
        return all(static_truth(g, k, env, src, local) for k in kids)
    if kind == "disj":
        return any(static_truth(g, k, env, src, local) for k in kids)
    if kind == "imply":
        return not static_truth(g, kids[0], env, src, local) or static_truth(
            g, kids[1], env, src, local
        )
    if kind in ("forall", "exists"):
        comprehension, body = kids
        values = (
            static_truth(g, body, b, src, local) for b in g.bindings(comprehension, env, src, local)
        )
        return all(values) if kind == "forall" else any(values)
    raise src.error(
        "a modality in a list comprehension's condition", tree,
        "conditions are evaluated before any state: use facts, = and /= only",
    )  # fmt: skip
