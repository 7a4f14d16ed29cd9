"""Model checking: the truth set of a formula in a Kripke model, as a boolean mask.

Semantics, at a world ``w`` of a model ``M``:

- ``K[a] f``: ``f`` holds at every world of a's *knowledge* relation from ``w``;
  ``B[a] f``: the same over a's *belief* relation (the two coincide unless the model has
  a separate knowledge relation); ``Kw[a] f`` is ``K[a] f | K[a] ~f``;
- ``E[G] f``: every agent of ``G`` knows ``f``; ``C[G] f``: ``f`` holds at every world
  reachable in one or more steps by the union of the knowledge relations of ``G``;
  ``D[G] f``: ``f`` holds at every world related to ``w`` by *all* of them (intersection);
  ``EB[G] f`` and ``CB[G] f``: as ``E`` and ``C`` over the *belief* relations (belief need
  not be reflexive, so ``CB`` uses the general reachability unless every relation of the
  group is an equivalence);
- ``[!f] g``: if ``f`` holds, ``g`` holds in the submodel of the ``f``-worlds;
  ``<!f> g``: ``f`` holds and ``g`` holds in that submodel;
- ``[ACT] g``: ``g`` holds at ``(w, e)`` in the product update with the named action, for
  every designated event ``e`` whose precondition holds at ``w``.

Every truth set is memoised per model and subformula, so shared and deeply nested
subformulas are evaluated once per model. Relations that are equivalences are evaluated
through their partition; any other relation through its arrows.

Atoms that the model does not know are false everywhere (a valuation lists true atoms
only); spec files declare their atoms, which catches misspellings.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from epistemica.del_ import cube
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.formula import (
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
from epistemica.del_.relations import Partition, Relation, arrows_from_edges

if TYPE_CHECKING:
    from epistemica.del_.action import ActionModel
    from epistemica.del_.kripke import KripkeModel

__all__ = ["as_formula", "evaluate", "propositional_mask"]

_CONNECTIVES = {
    And: np.logical_and,
    Or: np.logical_or,
    Implies: lambda x, y: ~x | y,
    Iff: np.equal,
}


@functools.lru_cache(maxsize=4096)
def _parse(text: str) -> Formula:
    from epistemica.del_.parser import parse_formula

    return parse_formula(text)


def as_formula(formula: Formula | str) -> Formula:
    """Return ``formula`` as a tree, parsing it if it is text.

    Examples
    --------
    >>> print(as_formula("K[a] (p & q)"))
    K[a] (p & q)
    """
    if isinstance(formula, Formula):
        return formula
    if isinstance(formula, str):
        return _parse(formula)
    raise InvalidArgumentError(
        f"expected a formula or its text, got {type(formula).__name__}",
        hint="pass a Formula tree or a string such as 'K[a] p'",
    )


def evaluate(
    model: KripkeModel,
    formula: Formula | str,
    actions: Mapping[str, ActionModel] | None = None,
) -> np.ndarray:
    """The truth set of ``formula`` in ``model`` as a read-only boolean mask.

    Examples
    --------
    >>> from epistemica.del_.kripke import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": [], "b": ["p"]}, designated=["p"])
    >>> evaluate(m, "Kw[b] p & ~Kw[a] p").tolist()
    [True, True]
    """
    tree = as_formula(formula)
    context = _Context(actions)
    return context.eval(model, tree)


class _Context:
    """One evaluation: the named actions in force and the memo key they imply."""

    def __init__(self, actions: Mapping[str, ActionModel] | None) -> None:
        self.actions = dict(actions or {})
        self.key = frozenset((name, id(a)) for name, a in self.actions.items())

    def eval(self, model: KripkeModel, f: Formula) -> np.ndarray:
        key = (f, self.key) if _mentions_action(f) else f
        found = model._memo.get(key)
        if found is None and model._cube is not None and cube.supported(f):
            found = model._cube.to_mask(cube.evaluate_bits(model, f))
        if found is None:
            found = self._compute(model, f)
            found.setflags(write=False)
            model._memo[key] = found
        return found

    def _compute(self, model: KripkeModel, f: Formula) -> np.ndarray:
        n = model.n_worlds
        kind = type(f)
        if kind is Atom:
            column = model._atom_column(f.key)
            return np.zeros(n, dtype=bool) if column is None else model._val[:, column]
        if kind is Top:
            return np.ones(n, dtype=bool)
        if kind is Bottom:
            return np.zeros(n, dtype=bool)
        if kind is Not:
            return ~self.eval(model, f.operand)
        if kind in _CONNECTIVES:
            return _CONNECTIVES[kind](self.eval(model, f.left), self.eval(model, f.right))
        if kind is Know:
            return _relation(model, f.agent, "knowledge").box(self.eval(model, f.operand))
        if kind is Believe:
            return _relation(model, f.agent, "belief").box(self.eval(model, f.operand))
        if kind is KnowWhether:
            relation = _relation(model, f.agent, "knowledge")
            inner = self.eval(model, f.operand)
            if isinstance(relation, Partition):
                return relation.know_whether(inner)
            return relation.box(inner) | relation.box(~inner)
        if kind is Everybody or kind is EverybodyBelieves:
            relation_kind = "knowledge" if kind is Everybody else "belief"
            inner = self.eval(model, f.operand)
            result = np.ones(n, dtype=bool)
            for agent in f.group:
                result &= _relation(model, agent, relation_kind).box(inner)
            return result
        if kind is Common:
            return _common_box(model, f.group, self.eval(model, f.operand))
        if kind is CommonBelief:
            return _common_box(model, f.group, self.eval(model, f.operand), "belief")
        if kind is Distributed:
            return _distributed(model, f.group).box(self.eval(model, f.operand))
        if kind in (Announce, AnnounceDiamond):
            return self._announcement(model, f)
        if kind is After:
            return self._after(model, f)
        raise InvalidArgumentError(f"cannot evaluate {type(f).__name__}")

    def _announcement(self, model: KripkeModel, f: Announce | AnnounceDiamond) -> np.ndarray:
        announced = self.eval(model, f.announcement)
        inside = np.zeros(model.n_worlds, dtype=bool)
        if announced.any():
            key = ("announce", f.announcement)
            sub = model._derived.get(key)
            if sub is None:
                sub = model._derived[key] = _submodel(model, announced)
            inside[announced] = self.eval(sub, f.operand)
        if isinstance(f, Announce):
            return ~announced | inside
        return inside

    def _after(self, model: KripkeModel, f: After) -> np.ndarray:
        from epistemica.del_.action import product_with_provenance

        action = self.actions.get(f.action)
        if action is None:
            known = ", ".join(sorted(self.actions)) or "none"
            raise InvalidArgumentError(
                f"unknown action {f.action!r} in {f}",
                hint=f"pass it in `actions`; known actions: {known}",
            )
        key = ("after", id(action))
        cached = model._derived.get(key)
        if cached is None or cached[0] is not action:
            product, parent, event = product_with_provenance(model, action)
            cached = model._derived[key] = (action, product, parent, event)
        _, product, parent, event = cached
        result = np.ones(model.n_worlds, dtype=bool)
        if product.n_worlds:
            designated_event = np.zeros(len(action.events), dtype=bool)
            designated_event[action._designated] = True
            violated = ~self.eval(product, f.operand) & designated_event[event]
            result[parent[violated]] = False
        return result


@functools.lru_cache(maxsize=65536)
def _mentions_action(f: Formula) -> bool:
    return any(isinstance(g, After) for g in f.subformulas())


def _relation(model: KripkeModel, agent: str, kind: str) -> Relation:
    table = model._know if kind == "knowledge" else model._rel
    relation = table.get(agent)
    if relation is None:
        raise InvalidArgumentError(
            f"unknown agent {agent!r}", hint=f"the model's agents: {', '.join(model.agents)}"
        )
    return relation


def _submodel(model: KripkeModel, mask: np.ndarray) -> KripkeModel:
    """The restriction to ``mask`` for evaluation only (designated worlds may vanish)."""
    return model._restricted(mask, np.zeros(0, dtype=np.intp))


def _group(model: KripkeModel, group: tuple[str, ...], kind: str = "knowledge") -> list[Relation]:
    return [_relation(model, agent, kind) for agent in group]


def _common_box(
    model: KripkeModel, group: tuple[str, ...], inner: np.ndarray, kind: str = "knowledge"
) -> np.ndarray:
    """``C[group]`` over the agents' ``kind`` relations ("knowledge" or "belief")."""
    relations = _group(model, group, kind)
    if all(isinstance(r, Partition) for r in relations):
        # Reflexive relations: reachable in >= 1 step is the connected component. (A
        # relation is a Partition only if it is an equivalence, belief relations included.)
        key = ("common-partition", kind, group)
        component = model._derived.get(key)
        if component is None:
            component = model._derived[key] = _component_partition(relations, model.n_worlds)
        return component.box(inner)
    # General relations: a world fails iff it reaches a ~inner world in >= 1 step.
    reached = np.zeros(model.n_worlds, dtype=bool)
    frontier = ~inner
    while frontier.any():
        predecessors = np.zeros(model.n_worlds, dtype=bool)
        for r in relations:
            predecessors |= r.predecessors_of(frontier)
        frontier = predecessors & ~reached
        reached |= frontier
    return ~reached


def _component_partition(relations: list[Partition], n: int) -> Partition:
    """Connected components of the union of equivalence relations, as a partition."""
    rows, cols, offset = [], [], n
    for r in relations:
        rows.append(np.arange(n))
        cols.append(offset + r.labels)
        offset += r.n_labels
    graph = sp.csr_matrix(
        (np.ones(len(relations) * n, dtype=bool), (np.concatenate(rows), np.concatenate(cols))),
        shape=(offset, offset),
    )
    _, labels = connected_components(graph, directed=False)
    return Partition(labels[:n].astype(np.int64))


def _distributed(model: KripkeModel, group: tuple[str, ...]) -> Relation:
    key = ("distributed", group)
    found = model._derived.get(key)
    if found is not None:
        return found
    relations = _group(model, group)
    if all(isinstance(r, Partition) for r in relations):
        stacked = np.stack([r.labels for r in relations], axis=1)
        labels = np.unique(stacked, axis=0, return_inverse=True)[1].reshape(-1)
        found = Partition(labels.astype(np.int64))
    else:
        rows, cols = relations[0].edges()
        keep = np.ones(len(rows), dtype=bool)
        for r in relations[1:]:
            keep &= r.contains(rows, cols)
        found = arrows_from_edges(model.n_worlds, rows[keep], cols[keep])
    model._derived[key] = found
    return found


def propositional_mask(
    formula: Formula | str, val: np.ndarray, column: Mapping[str, int]
) -> np.ndarray:
    """Truth of a propositional formula on each row of a valuation matrix.

    Raises
    ------
    InvalidArgumentError
        If the formula has a modality or names an atom without a column.

    Examples
    --------
    >>> import numpy as np
    >>> val = np.array([[True, False], [True, True]])
    >>> propositional_mask("p & ~q", val, {"p": 0, "q": 1}).tolist()
    [True, False]
    """
    tree = as_formula(formula)
    return _propositional(tree, val, column)


def _propositional(f: Formula, val: np.ndarray, column: Mapping[str, int]) -> Any:
    kind = type(f)
    if kind is Atom:
        if f.key not in column:
            raise InvalidArgumentError(
                f"unknown atom {f.key!r}", hint=f"declared atoms: {', '.join(column)}"
            )
        return val[:, column[f.key]]
    if kind is Top:
        return np.ones(len(val), dtype=bool)
    if kind is Bottom:
        return np.zeros(len(val), dtype=bool)
    if kind is Not:
        return ~_propositional(f.operand, val, column)
    if kind in _CONNECTIVES:
        left = _propositional(f.left, val, column)
        return _CONNECTIVES[kind](left, _propositional(f.right, val, column))
    raise InvalidArgumentError(
        f"expected a propositional formula, found the modality in {f}",
        hint="laws and postconditions evaluated on valuations alone cannot mention K, B, C, ...",
    )
