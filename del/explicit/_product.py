"""The product update ``M ⊗ A`` as arrays, given the truth sets it needs.

``M ⊗ A`` has the worlds ``(w, e)`` with ``w ⊨ pre(e)``; the valuation changes by
``post(e)``, evaluated at ``w`` before the update; ``(w, e) R_a (v, f)`` iff ``w R_a v``,
``e R_a f`` and the edge's condition (if any) holds at ``w``. Partition × equivalence
without conditions stays a partition (pairs of labels); anything else is built as sparse
(or, for small products, dense) arrows and turned back into a partition when it is an
equivalence.

The truth sets of pre-, postconditions and edge conditions come from a ``truth`` callable,
so that the evaluator (which needs products for ``[ACT] f``) and this module do not
import each other; :func:`epistemica.del_.explicit.action.product_update` is the public
entry point.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from epistemica.del_.errors import ModelError
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit.relations import (
    DENSE_LIMIT,
    DenseArrows,
    Partition,
    Relation,
    arrows_from_edges,
    as_compact,
)
from epistemica.del_.language.formula import Formula

if TYPE_CHECKING:
    from epistemica.del_.explicit.action import ActionModel

__all__ = ["product_with_provenance"]

# Above this many edges, a product relation is kept as arrows rather than tested for being
# an equivalence (the test multiplies sparse matrices).
_EQUIVALENCE_TEST_LIMIT = 2_000_000


def _check_agents(model: ExplicitModel, action: ActionModel) -> None:
    missing = set(model.agents) - set(action.agents)
    extra = set(action.agents) - set(model.agents)
    if missing or extra:
        raise ModelError(
            "the action model and the Kripke model must have the same agents",
            hint=f"missing in the action: {sorted(missing)}; unknown to the model: {sorted(extra)}",
        )


def product_with_provenance(
    model: ExplicitModel,
    action: ActionModel,
    truth: Callable[[Formula], np.ndarray],
    *,
    beliefs_only: bool = False,
) -> tuple[ExplicitModel, np.ndarray, np.ndarray]:
    """The full product ``model ⊗ action`` and, per product world, its world and event.

    ``truth(f)`` is the truth mask of a precondition, postcondition or edge condition in
    ``model``: the evaluator passes its own, so that evaluating ``[ACT] f`` and computing
    a product never import each other. The product may have no designated world. With
    ``beliefs_only``, the separate knowledge relations are not computed (``K`` then reads
    the belief relation): for callers whose formulas never mention knowledge.
    """
    _check_agents(model, action)
    blocks = [np.flatnonzero(truth(pre)) for pre in action.pre]
    parent = np.concatenate(blocks) if blocks else np.zeros(0, dtype=np.int64)
    event = np.repeat(np.arange(len(blocks)), [len(b) for b in blocks])
    offsets = np.concatenate([[0], np.cumsum([len(b) for b in blocks])])

    atoms = list(model.atoms)
    for changes in action.post:
        atoms.extend(a for a in changes if a not in atoms)
    val = np.zeros((len(parent), len(atoms)), dtype=bool)
    val[:, : len(model.atoms)] = model.valuation[parent]
    column = {a: j for j, a in enumerate(atoms)}
    for j, changes in enumerate(action.post):
        rows = slice(offsets[j], offsets[j + 1])
        for atom, value in changes.items():
            val[rows, column[atom]] = truth(value)[blocks[j]]

    rel: dict[str, Relation] = {}
    know: dict[str, Relation] = {}
    for agent in model.agents:
        belief, knowledge = model.belief_relations[agent], model.knowledge_relations[agent]
        edges, know_edges = action.edges[agent], action.knowledge_edges[agent]
        rel[agent] = _product_relation(truth, belief, edges, blocks)
        if beliefs_only or (knowledge is belief and know_edges is edges):
            know[agent] = rel[agent]
        else:
            know[agent] = _product_relation(truth, knowledge, know_edges, blocks)

    is_point = np.zeros(model.n_worlds, dtype=bool)
    is_point[model.designated_positions] = True
    is_designated_event = np.zeros(len(action.events), dtype=bool)
    is_designated_event[action.designated_positions] = True
    designated = np.flatnonzero(is_point[parent] & is_designated_event[event])

    source, events = model.lazy_names, action.events

    def names() -> tuple:
        worlds = source() if callable(source) else source
        if worlds is None:
            return tuple((int(w), events[e]) for w, e in zip(parent, event, strict=True))
        return tuple((worlds[w], events[e]) for w, e in zip(parent, event, strict=True))

    product = type(model).from_arrays(names, tuple(atoms), val, model.agents, rel, know, designated)
    return product, parent, event


def _product_relation(
    truth: Callable[[Formula], np.ndarray],
    relation: Relation,
    edges: tuple,
    blocks: list[np.ndarray],
) -> Relation:
    n = sum(len(b) for b in blocks)
    if isinstance(relation, Partition) and all(c is None for _, _, c in edges):
        classes = _event_classes(edges, len(blocks))
        if classes is not None:
            return _paired_partition(relation, classes, blocks)
    offsets = np.concatenate([[0], np.cumsum([len(b) for b in blocks])])
    if n <= DENSE_LIMIT:
        return as_compact(_dense_product(truth, relation, edges, blocks, offsets, n))
    matrix = relation.to_csr()
    rows, cols = [], []
    for e, f, condition in edges:
        if not len(blocks[e]) or not len(blocks[f]):
            continue
        sub = matrix[blocks[e]][:, blocks[f]].tocoo()
        keep = np.ones(sub.nnz, dtype=bool)
        if condition is not None:
            keep = truth(condition)[blocks[e]][sub.row]
        rows.append(sub.row[keep] + offsets[e])
        cols.append(sub.col[keep] + offsets[f])
    row = np.concatenate(rows) if rows else np.zeros(0, dtype=np.intp)
    col = np.concatenate(cols) if cols else np.zeros(0, dtype=np.intp)
    product = arrows_from_edges(n, row, col)
    if len(row) <= _EQUIVALENCE_TEST_LIMIT:
        return as_compact(product)
    return product


def _dense_product(
    truth: Callable[[Formula], np.ndarray],
    relation: Relation,
    edges: tuple,
    blocks: list[np.ndarray],
    offsets: np.ndarray,
    n: int,
) -> DenseArrows:
    """The product relation as a boolean matrix, one block per edge of the action."""
    matrix = relation.to_dense()
    out = np.zeros((n, n), dtype=bool)
    for e, f, condition in edges:
        if not len(blocks[e]) or not len(blocks[f]):
            continue
        block = matrix[blocks[e]][:, blocks[f]]  # two takes: cheaper than np.ix_ when small
        if condition is not None:
            block &= truth(condition)[blocks[e]][:, None]
        out[offsets[e] : offsets[e + 1], offsets[f] : offsets[f + 1]] |= block
    return DenseArrows(out)


def _paired_partition(
    relation: Partition, classes: np.ndarray, blocks: list[np.ndarray]
) -> Partition:
    """Equivalence times equivalence: pair each world's class with its event's class."""
    width = int(classes.max()) + 1
    parts = [relation.labels[b] * width + classes[j] for j, b in enumerate(blocks)]
    labels = np.concatenate(parts).astype(np.int64)
    if len(labels) and labels.max() >= 4 * len(labels) + 64:
        labels = np.unique(labels, return_inverse=True)[1].reshape(-1)  # keep labels dense
    return Partition(labels)


@functools.lru_cache(maxsize=4096)
def _event_classes(edges: tuple, n_events: int) -> np.ndarray | None:
    """Class label per event if the unconditioned edges form an equivalence, else None.

    Cached: action models are immutable, so their edge tuples recur across updates.
    """
    if not edges:
        return None
    matrix = np.zeros((n_events, n_events), dtype=bool)
    matrix[[x for x, _, _ in edges], [y for _, y, _ in edges]] = True
    relation = as_compact(DenseArrows(matrix))
    return relation.labels if isinstance(relation, Partition) else None
