"""The two representations of a set of worlds that the evaluator works on.

The evaluator (:mod:`.checker`) interprets every formula type once; what a modality or an
announcement does to a truth set is asked of one of two representations, with the same
operations:

- :data:`MASKS`: a boolean mask over the model's worlds (compact order). Boxes go through
  each agent's relation (:mod:`.relations`): a partition if it is an equivalence, arrows
  otherwise, so belief and knowledge may differ.
- :data:`BITS`: a bitset over all ``2^n`` valuation codes of a model from observables
  (:mod:`._cube`). Every agent has one S5 relation, "agrees on what I observe", so
  ``K[a]`` is an AND over the codes that differ in a hidden bit, belief is knowledge, and
  an announcement only clears bits.

The evaluator picks bits for a model from observables whose cube is not sparse, masks
otherwise, and converts between the two where a subformula needs the other.
"""

from __future__ import annotations

import operator
from collections.abc import Sequence

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit._sparse import connected_components, csr_matrix
from epistemica.del_.explicit.relations import Partition, Relation, arrows_from_edges
from epistemica.del_.language.formula import And, Formula, Iff, Implies, Or

__all__ = ["BITS", "CONNECTIVES", "MASKS"]

# Boolean connectives, elementwise: the same operators serve masks (bool) and bitsets
# (uint64 words).
CONNECTIVES = {
    And: operator.and_,
    Or: operator.or_,
    Implies: lambda x, y: ~x | y,
    Iff: lambda x, y: ~(x ^ y),
}


def unknown_agent(model: ExplicitModel, agent: str) -> InvalidArgumentError:
    return InvalidArgumentError(
        f"unknown agent {agent!r}", hint=f"the model's agents: {', '.join(model.agents)}"
    )


class _Masks:
    """Truth sets as boolean masks over the worlds; boxes through relations."""

    bits = False

    @staticmethod
    def relations(model: ExplicitModel, group: Sequence[str], kind: str) -> list[Relation]:
        """The ``kind`` ("belief" or "knowledge") relation of each agent of ``group``."""
        table = model.knowledge_relations if kind == "knowledge" else model.belief_relations
        found = []
        for agent in group:
            relation = table.get(agent)
            if relation is None:
                raise unknown_agent(model, agent)
            found.append(relation)
        return found

    @staticmethod
    def box(model: ExplicitModel, relation: Relation, inner: np.ndarray) -> np.ndarray:
        return relation.box(inner)

    @staticmethod
    def know_whether(model: ExplicitModel, relation: Relation, inner: np.ndarray) -> np.ndarray:
        if isinstance(relation, Partition):
            return relation.know_whether(inner)
        return relation.box(inner) | relation.box(~inner)

    @staticmethod
    def everybody(model: ExplicitModel, relations: list[Relation], inner: np.ndarray):
        result = np.ones(model.n_worlds, dtype=bool)
        for relation in relations:
            result &= relation.box(inner)
        return result

    @staticmethod
    def common(
        model: ExplicitModel,
        group: tuple[str, ...],
        kind: str,
        relations: list[Relation],
        inner: np.ndarray,
    ) -> np.ndarray:
        """``f`` at every world reachable in one or more steps of the group's relations."""
        if all(isinstance(r, Partition) for r in relations):
            # Reflexive relations: reachable in >= 1 step is the connected component. (A
            # relation is a Partition only if it is an equivalence, belief included.)
            key = ("common-partition", kind, group)
            component = model.derived.get(key)
            if component is None:
                component = _component_partition(relations, model.n_worlds)
                model.derived[key] = component
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

    @staticmethod
    def distributed(
        model: ExplicitModel,
        group: tuple[str, ...],
        relations: list[Relation],
        inner: np.ndarray,
    ) -> np.ndarray:
        """``f`` at every world related by all the group's knowledge relations."""
        key = ("distributed", group)
        found = model.derived.get(key)
        if found is None:
            found = model.derived[key] = _intersection(relations, model.n_worlds)
        return found.box(inner)

    @staticmethod
    def submodel(
        model: ExplicitModel, announcement: Formula, announced: np.ndarray
    ) -> ExplicitModel | None:
        """The submodel of the announced worlds (cached), or ``None`` if there are none."""
        if not announced.any():
            return None
        key = ("announce", announcement)
        sub = model.derived.get(key)
        if sub is None:
            # for evaluation only: designated worlds may vanish
            sub = model.derived[key] = model.restricted(announced, np.zeros(0, dtype=np.intp))
        return sub

    @staticmethod
    def after(
        model: ExplicitModel, announced: np.ndarray, inside: np.ndarray | None, box: bool
    ) -> np.ndarray:
        """``[!f] g`` (``box``) or ``<!f> g`` from ``f`` and ``g`` on the submodel."""
        full = np.zeros(model.n_worlds, dtype=bool)
        if inside is not None:
            full[announced] = inside  # the submodel's worlds are the announced ones, in order
        return ~announced | full if box else full


class _Bits:
    """Truth sets as bitsets over valuation codes; boxes by pairing codes."""

    bits = True

    @staticmethod
    def relations(model: ExplicitModel, group: Sequence[str], kind: str) -> list[tuple[int, ...]]:
        """The hidden code bits of each agent (one S5 relation: belief is knowledge)."""
        hidden = model.cube.hidden
        found = []
        for agent in group:
            bits = hidden.get(agent)
            if bits is None:
                raise unknown_agent(model, agent)
            found.append(bits)
        return found

    @staticmethod
    def box(model: ExplicitModel, hidden: tuple[int, ...], inner: np.ndarray) -> np.ndarray:
        return model.cube.box(inner, hidden)

    @staticmethod
    def know_whether(model: ExplicitModel, hidden: tuple[int, ...], inner: np.ndarray):
        return model.cube.box(inner, hidden) | model.cube.box(~inner, hidden)

    @staticmethod
    def everybody(model: ExplicitModel, hiddens: list[tuple[int, ...]], inner: np.ndarray):
        result = model.cube.ones()
        for hidden in hiddens:
            result &= model.cube.box(inner, hidden)
        return result

    @staticmethod
    def common(
        model: ExplicitModel,
        group: tuple[str, ...],
        kind: str,
        hiddens: list[tuple[int, ...]],
        inner: np.ndarray,
    ) -> np.ndarray:
        return model.cube.common_box(inner, group)

    @staticmethod
    def distributed(
        model: ExplicitModel,
        group: tuple[str, ...],
        hiddens: list[tuple[int, ...]],
        inner: np.ndarray,
    ) -> np.ndarray:
        # Pooling observations: a bit stays hidden only if it is hidden from everyone.
        hidden = set(hiddens[0]).intersection(*hiddens[1:])
        return model.cube.box(inner, tuple(sorted(hidden)))

    @staticmethod
    def submodel(model: ExplicitModel, announcement: Formula, announced: np.ndarray):
        """The submodel of the announced codes (cached); it shares the model's space."""
        key = ("announce-bits", announcement)
        sub = model.derived.get(key)
        if sub is None:
            sub = model.derived[key] = model.cube_submodel(announced)
        return sub

    @staticmethod
    def after(
        model: ExplicitModel, announced: np.ndarray, inside: np.ndarray | None, box: bool
    ) -> np.ndarray:
        # the submodel keeps the bit positions of the model: nothing to scatter
        return ~announced | inside if box else announced & inside


MASKS = _Masks()
BITS = _Bits()


def _component_partition(relations: list[Partition], n: int) -> Partition:
    """Connected components of the union of equivalence relations, as a partition."""
    if n <= _SMALL_COMPONENTS:
        return Partition(_small_components(relations, n))
    rows, cols, offset = [], [], n
    for r in relations:
        rows.append(np.arange(n))
        cols.append(offset + r.labels)
        offset += r.n_labels
    graph = csr_matrix(
        (np.ones(len(relations) * n, dtype=bool), (np.concatenate(rows), np.concatenate(cols))),
        shape=(offset, offset),
    )
    _, labels = connected_components(graph, directed=False)
    return Partition(labels[:n].astype(np.int64))


def _intersection(relations: list[Relation], n: int) -> Relation:
    """The intersection of relations (distributed knowledge)."""
    if all(isinstance(r, Partition) for r in relations):
        stacked = np.stack([r.labels for r in relations], axis=1)
        labels = np.unique(stacked, axis=0, return_inverse=True)[1].reshape(-1)
        return Partition(labels.astype(np.int64))
    rows, cols = relations[0].edges()
    keep = np.ones(len(rows), dtype=bool)
    for r in relations[1:]:
        keep &= r.contains(rows, cols)
    return arrows_from_edges(n, rows[keep], cols[keep])


#: Up to this many worlds, components are found by label propagation in numpy rather than
#: by scipy's graph search (whose import costs more than a small model's whole check).
_SMALL_COMPONENTS = 2048


def _small_components(relations: list[Partition], n: int) -> np.ndarray:
    """Component labels numbered by their first world (as scipy's): each world takes the
    smallest label of its blocks until no label changes (at most a component's diameter
    rounds)."""
    label = np.arange(n)
    changed = True
    while changed:
        changed = False
        for r in relations:
            low = np.full(r.n_labels, n)
            np.minimum.at(low, r.labels, label)
            spread = low[r.labels]
            if (spread < label).any():
                label, changed = spread, True
    return np.unique(label, return_inverse=True)[1].astype(np.int64)
