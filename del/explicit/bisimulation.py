"""Bisimulation: contraction of a model and equivalence of two models.

Two worlds are bisimilar when they agree on every atom and each agent's successors of one
can be matched by bisimilar successors of the other; bisimilar worlds satisfy the same
formulas of the language. The coarsest bisimulation is the coarsest stable refinement of
"same valuation" in a labelled graph (:mod:`~epistemica.del_.explicit._refinement`, O(m log n)):

- each world is a node;
- each relation (per agent, belief and, when separate, knowledge) has a label, and its
  worlds' successor *sets* are nodes too: a world has one edge to its set, and the set
  one edge to each member. A partition's sets are its classes, so an equivalence costs
  two edges per world instead of the square of its class sizes; arrows whose rows repeat
  (beliefs after an oblivious event) share a node per distinct row.

Two worlds then reach the same blocks exactly when their successor sets meet the same
blocks, which is the bisimulation condition.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from epistemica.del_ import budget
from epistemica.del_.errors import ModelError
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit._refinement import coarsest_partition, mix64, ranges
from epistemica.del_.explicit._sparse import breadth_first_order, coo_matrix
from epistemica.del_.explicit.relations import (
    Arrows,
    ClassArrows,
    DenseArrows,
    Partition,
    Relation,
    arrows_from_edges,
)

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = [
    "BYTES_PER_EDGE",
    "bisimilar",
    "bisimulation_classes",
    "contraction_bytes",
    "edge_count",
    "generated_submodel",
    "minimize",
    "quotient",
    "successor_sets",
]


#: Peak bytes of the refinement per edge of its graph (edge lists, cells, the records of a
#: round and their sorts; measured 90-97 on muddy children of 16-18 agents with hidden
#: atoms, 2-9 million edges: ``benchmarks/contraction_memory.py``), with a margin.
BYTES_PER_EDGE = 112


def edge_count(relation: Relation) -> int:
    """The number of edges a relation gives the refinement's graph: one per member of a
    successor set (a partition's class lists each world once), without listing them.

    >>> import numpy as np
    >>> edge_count(Partition(np.array([0, 0, 1]))), edge_count(DenseArrows(np.ones((2, 2), bool)))
    (3, 4)
    """
    if isinstance(relation, Partition):
        return relation.n
    if isinstance(relation, DenseArrows):
        return int(np.count_nonzero(relation.matrix))
    if isinstance(relation, Arrows):
        return int(relation.matrix.nnz)
    if isinstance(relation, ClassArrows):
        sizes = np.array([len(t) for t in relation.targets], dtype=np.int64)
        return int(sizes[relation.labels].sum()) if relation.n else 0
    return relation.n * relation.n


def contraction_bytes(model: ExplicitModel) -> int:
    """Estimated peak bytes of contracting ``model`` (the refinement's graph: per relation
    one edge from each world to its successor set, and the sets' edges to their members).

    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "q"], {"a": ["p"], "b": []})
    >>> contraction_bytes(m) == BYTES_PER_EDGE * 2 * (4 + 4)
    True
    """
    return BYTES_PER_EDGE * sum(model.n_worlds + edge_count(r) for r in _relations(model))


def generated_submodel(model: ExplicitModel) -> ExplicitModel:
    """The submodel of the worlds reachable from the designated ones by any relation.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel(["u", "v"], {"u": {"p"}}, {"a": [("u", "u"), ("v", "v")]}, "u")
    >>> generated_submodel(m).worlds
    ('u',)
    """
    reached = _reached(model)
    if reached.all():
        return model
    return model.restrict(reached)


# Reachability steps from the frontier only, expanding each partition class and each
# world's arrows once (O(worlds + edges) in all, a few numpy calls per step and relation);
# a model not done after this many steps (a long chain) is searched once over an
# explicit graph instead.
_STEPS = 64


# Up to this many worlds, reachability is a few boolean-matrix steps (planning states).
_SMALL = 64


def _reached(model: ExplicitModel) -> np.ndarray:
    reached = np.zeros(model.n_worlds, dtype=bool)
    reached[model.designated_positions] = True
    if model.n_worlds <= _SMALL:
        return _reached_small(model, reached)
    expanders = [_Expander(r) for r in _relations(model)]
    frontier = np.flatnonzero(reached)
    for _ in range(_STEPS):
        if not len(frontier):
            return reached
        new = np.zeros(model.n_worlds, dtype=bool)
        for e in expanders:
            new[e.successors(frontier)] = True
        new &= ~reached
        reached |= new
        frontier = np.flatnonzero(new)
    if not len(frontier):
        return reached
    return _Graph(model).reached(model.designated_positions)


def _reached_small(model: ExplicitModel, reached: np.ndarray) -> np.ndarray:
    """Reachability over the union of the relations as one small boolean matrix."""
    arrows = np.zeros((model.n_worlds, model.n_worlds), dtype=bool)
    for relation in _relations(model):
        arrows |= relation.to_dense()
    while True:
        grown = reached | arrows[reached].any(axis=0)
        if grown.sum() == reached.sum():
            return reached
        reached = grown


class _Expander:
    """One relation's successors of a set of worlds, each class or world expanded once."""

    def __init__(self, relation: Relation) -> None:
        if isinstance(relation, Partition):
            self.labels = relation.labels
            # Worlds sorted by class: class c is members[start[c]:start[c + 1]].
            index = np.int32 if relation.n < 2**31 else np.int64
            self.members = np.argsort(relation.labels, kind="stable").astype(index)
            self.start = np.zeros(relation.n_labels + 1, dtype=np.int64)
            np.cumsum(np.bincount(relation.labels, minlength=relation.n_labels), out=self.start[1:])
            self.done = np.zeros(relation.n_labels, dtype=bool)
        else:
            self.labels = None
            if isinstance(relation, Arrows):
                self.members, self.start = relation.matrix.indices, relation.matrix.indptr
            else:  # small dense matrices and class arrows: their edges (no scipy matrix)
                rows, self.members = relation.edges()
                order = np.argsort(rows, kind="stable")
                rows, self.members = rows[order], self.members[order]
                self.start = np.searchsorted(rows, np.arange(relation.n + 1))
            self.done = np.zeros(relation.n, dtype=bool)

    def successors(self, worlds: np.ndarray) -> np.ndarray:
        if self.labels is None:
            keys = worlds[~self.done[worlds]]
        else:  # the classes of `worlds` not expanded yet, each once
            fresh = np.zeros(len(self.done), dtype=bool)
            fresh[self.labels[worlds]] = True
            keys = np.flatnonzero(fresh & ~self.done)
        self.done[keys] = True
        return self.members[ranges(self.start[keys], self.start[keys + 1] - self.start[keys])]


def bisimulation_classes(model: ExplicitModel) -> np.ndarray:
    """Label each world with its class of the coarsest bisimulation (labels ``0..k-1``).

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel(["u", "v", "w"], {"u": {"p"}, "v": {"p"}},
    ...                 {"a": [("u", "v"), ("v", "u"), ("w", "w")]}, "u")
    >>> u, v, w = bisimulation_classes(m)
    >>> bool(u == v != w)   # u and v only see each other's p-worlds; w has no p
    True
    """
    if not model.n_worlds:
        return np.zeros(0, dtype=np.intp)
    valuation = _valuation_classes(model.valuation)
    if int(valuation.max()) + 1 == model.n_worlds:  # valuations tell every world apart
        return valuation
    return _Graph(model, valuation).classes()


def minimize(model: ExplicitModel) -> ExplicitModel:
    """The bisimulation contraction of the submodel generated by the designated worlds.

    Each class is represented by its first world, whose name it keeps. The result
    satisfies exactly the same formulas at its designated worlds as ``model``.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "q"], {"a": ["p"]}, designated=["p"])
    >>> m.minimize().n_worlds   # q is irrelevant to everything a can know
    2
    """
    model = generated_submodel(model)
    return quotient(model, bisimulation_classes(model))


def quotient(model: ExplicitModel, blocks: np.ndarray) -> ExplicitModel:
    """The model whose worlds are the classes ``blocks`` (labels ``0..k-1``) of a bisimulation.

    Each class is represented by its first world, whose name it keeps. ``blocks`` must be
    a bisimulation (as from :func:`bisimulation_classes`), or the result is meaningless.
    """
    count = int(blocks.max()) + 1
    if count == model.n_worlds:
        return model
    representative = np.full(count, -1, dtype=np.int64)
    representative[blocks[::-1]] = np.arange(model.n_worlds)[::-1]
    rel, know = {}, {}
    for agent in model.agents:
        rel[agent] = _quotient(model.belief_relations[agent], blocks, count)
        shared = model.knowledge_relations[agent] is model.belief_relations[agent]
        know[agent] = (
            rel[agent] if shared else _quotient(model.knowledge_relations[agent], blocks, count)
        )
    source = model.lazy_names

    def names() -> tuple:
        worlds = source() if callable(source) else source
        if worlds is None:
            return tuple(int(i) for i in representative)
        return tuple(worlds[i] for i in representative)

    return type(model).from_arrays(
        names,
        model.atoms,
        model.valuation[representative],
        model.agents,
        rel,
        know,
        np.unique(blocks[model.designated_positions]),
    )


def bisimilar(first: ExplicitModel, second: ExplicitModel) -> bool:
    """Whether two pointed models are bisimilar (their designated sets match up).

    Every designated world of each model must be bisimilar to some designated world of the
    other. The models must have the same agents.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
    >>> bisimilar(m, m.minimize()), bisimilar(m, m.announce("p"))
    (True, False)
    """
    if set(first.agents) != set(second.agents):
        raise ModelError(
            "bisimilarity compares models of the same agents",
            hint=f"agents {sorted(first.agents)} versus {sorted(second.agents)}",
        )
    union = _disjoint_union(first, second)
    blocks = bisimulation_classes(union)
    ours = set(blocks[first.designated_positions].tolist())
    theirs = set(blocks[second.designated_positions + first.n_worlds].tolist())
    return ours == theirs


def _relations(model: ExplicitModel) -> list[Relation]:
    found = [model.belief_relations[a] for a in model.agents]
    found += [
        model.knowledge_relations[a]
        for a in model.agents
        if model.knowledge_relations[a] is not model.belief_relations[a]
    ]
    return found


class _Graph:
    """A model as the labelled graph whose coarsest stable partition is bisimilarity.

    Nodes ``0..n-1`` are the worlds, then come the successor-set nodes of each relation.
    ``initial`` separates worlds by valuation and the set nodes of each relation from
    everything else.
    """

    def __init__(self, model: ExplicitModel, valuation: np.ndarray | None = None) -> None:
        n = model.n_worlds
        budget.require(
            contraction_bytes(model), lambda: f"contracting a model of {n:,} worlds (bisimulation)"
        )
        if valuation is None:
            valuation = _valuation_classes(model.valuation)
        n_blocks = int(valuation.max()) + 1 if n else 0
        relations = _relations(model)
        sets = [successor_sets(r) for r in relations]
        self.n_nodes = n + sum(n_sets for _, n_sets, _, _ in sets)
        index = np.int32 if self.n_nodes < 2**31 else np.int64
        # Edges in increasing order of target (the refinement then uses them as they are):
        # first each set's edges to its members (into worlds), then each world's edge to
        # its set, relation by relation (set nodes are numbered in that order).
        offsets = np.cumsum([n] + [n_sets for _, n_sets, _, _ in sets])[:-1]
        into_worlds = _into_worlds(sets, offsets, index)
        initial, sources, targets, labels, alone = [valuation], [], [], [], []
        for label, ((owner, n_sets, _, _), offset) in enumerate(zip(sets, offsets, strict=True)):
            by_set = np.argsort(owner, kind="stable")
            sources.append(by_set.astype(index))
            targets.append((owner[by_set] + offset).astype(index))
            labels.append(np.full(n, 2 * label, dtype=index))
            alone.append(np.ones(n, dtype=bool))  # one edge per world and label
            initial.append(np.full(n_sets, n_blocks + label))
        del sets
        self.initial = np.concatenate(initial)
        self.sources, self.targets, self.labels, self.alone = (
            np.concatenate([first, *rest])
            for first, rest in zip(into_worlds, (sources, targets, labels, alone), strict=True)
        )
        self.n_worlds = n

    def reached(self, points: np.ndarray) -> np.ndarray:
        """Which worlds are reachable from ``points`` (a breadth-first search, O(n + m))."""
        root = self.n_nodes  # one more node, pointing at every point
        rows = np.concatenate([self.sources, np.full(len(points), root)])
        cols = np.concatenate([self.targets, points])
        data = np.ones(len(rows), dtype=bool)
        graph = coo_matrix((data, (rows, cols)), shape=(root + 1, root + 1)).tocsr()
        found = breadth_first_order(graph, root, directed=True)
        reached = np.zeros(root + 1, dtype=bool)
        reached[found] = True
        return reached[: self.n_worlds]

    def classes(self) -> np.ndarray:
        """Each world's class of the coarsest bisimulation, labels ``0..k-1``."""
        blocks = coarsest_partition(
            self.initial, self.sources, self.targets, self.labels, self.alone
        )
        return np.unique(blocks[: self.n_worlds], return_inverse=True)[1].reshape(-1)


def _into_worlds(
    sets: list[tuple[np.ndarray, int, np.ndarray, np.ndarray]], offsets: np.ndarray, index: type
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Sources, targets, labels and loneliness of the edges from successor sets to their
    members, in increasing order of member (for partitions, one edge per world and
    relation: no sort)."""
    n = int(offsets[0]) if len(offsets) else 0
    sources, labels, alone = [], [], []
    for label, ((_, n_sets, _, of_set), offset) in enumerate(zip(sets, offsets, strict=True)):
        sources.append((of_set + offset).astype(index))
        labels.append(np.full(len(of_set), 2 * label + 1, dtype=index))
        alone.append(np.bincount(of_set, minlength=n_sets)[of_set] == 1)
    if not sets:
        empty = np.zeros(0, dtype=index)
        return empty, empty, empty, np.zeros(0, dtype=bool)
    if all(len(members) == n and (members == np.arange(n)).all() for _, _, members, _ in sets):
        # World w's edges are row w of an (n, relations) table: raveled, sorted by w.
        return (
            np.stack(sources, axis=1).ravel(),
            np.repeat(np.arange(n, dtype=index), len(sets)),
            np.stack(labels, axis=1).ravel(),
            np.stack(alone, axis=1).ravel(),
        )
    members = np.concatenate([m for _, _, m, _ in sets])
    order = np.argsort(members, kind="stable")
    return (
        np.concatenate(sources)[order],
        members[order].astype(index),
        np.concatenate(labels)[order],
        np.concatenate(alone)[order],
    )


def successor_sets(relation: Relation) -> tuple[np.ndarray, int, np.ndarray, np.ndarray]:
    """Each world's successor set: ``(set of each world, number of sets, members, and
    the set each member belongs to)``; worlds with equal successor sets share one."""
    if isinstance(relation, Partition):
        # Labels numbered 0..k-1 in their order (unused labels would be sets without
        # members, nodes that cost the refinement memory): by a sort when they are sparse.
        if relation.n_labels > 2 * relation.n:
            classes = relation.compact()
        else:
            used = np.zeros(relation.n_labels, dtype=bool)
            used[relation.labels] = True
            classes = (np.cumsum(used) - 1)[relation.labels]
        return (
            classes,
            int(classes.max()) + 1 if len(classes) else 0,
            np.arange(len(classes)),
            classes,
        )
    matrix = relation.to_csr()
    owner, n_sets = _equal_rows(matrix)
    first = np.full(n_sets, -1, dtype=np.int64)
    first[owner[::-1]] = np.arange(relation.n)[::-1]
    rows = matrix[first]
    of_set = np.repeat(np.arange(n_sets), np.diff(rows.indptr))
    return owner, n_sets, rows.indices.astype(np.int64), of_set


def _equal_rows(matrix: sp.csr_matrix) -> tuple[np.ndarray, int]:
    """A label per row of a CSR matrix, equal for rows with the same columns (exactly)."""
    matrix = matrix.tocsr()
    matrix.sort_indices()
    lengths = np.diff(matrix.indptr)
    starts = matrix.indptr[:-1]
    digest = mix64(lengths)
    nonempty = lengths > 0
    if len(matrix.indices):
        digest[nonempty] ^= np.add.reduceat(mix64(matrix.indices), starts[nonempty])
    _, first, labels = np.unique(digest, return_index=True, return_inverse=True)
    labels = labels.reshape(-1)
    # The digest groups rows; check each against its group's first row, exactly.
    check = np.flatnonzero(first[labels] != np.arange(len(labels)))
    rep = first[labels[check]]
    if np.array_equal(lengths[check], lengths[rep]):
        size = lengths[check]
        mine = matrix.indices[ranges(starts[check], size)]
        theirs = matrix.indices[ranges(starts[rep], size)]
        if np.array_equal(mine, theirs):
            return labels, len(first)
    exact: dict[tuple, int] = {}
    labels = np.array(
        [
            exact.setdefault(tuple(matrix.indices[s : s + k].tolist()), len(exact))
            for s, k in zip(starts.tolist(), lengths.tolist(), strict=True)
        ],
        dtype=np.int64,
    )
    return labels, len(exact)


def _valuation_classes(val: np.ndarray) -> np.ndarray:
    if not val.shape[1]:
        return np.zeros(len(val), dtype=np.intp)
    if val.shape[1] < 63:
        codes = val.astype(np.int64) @ (np.int64(1) << np.arange(val.shape[1], dtype=np.int64))
        return np.unique(codes, return_inverse=True)[1].reshape(-1)
    packed = np.packbits(val, axis=1)
    return np.unique(packed, axis=0, return_inverse=True)[1].reshape(-1)


def _quotient(relation: Relation, blocks: np.ndarray, count: int) -> Relation:
    if isinstance(relation, Partition):
        # Bisimilar worlds reach the same blocks, so the blocks meeting a world's class are
        # one class of the quotient: name it by its smallest block.
        smallest = np.full(relation.n_labels, count, dtype=np.intp)
        np.minimum.at(smallest, relation.labels, blocks)
        quotient = np.empty(count, dtype=np.intp)
        quotient[blocks] = smallest[relation.labels]
        return Partition(quotient)
    rows, cols = relation.edges()
    return arrows_from_edges(count, blocks[rows], blocks[cols])


def _disjoint_union(first: ExplicitModel, second: ExplicitModel) -> ExplicitModel:
    atoms = tuple(dict.fromkeys(first.atoms + second.atoms))
    column = {a: j for j, a in enumerate(atoms)}
    val = np.zeros((first.n_worlds + second.n_worlds, len(atoms)), dtype=bool)
    val[: first.n_worlds, [column[a] for a in first.atoms]] = first.valuation
    val[first.n_worlds :, [column[a] for a in second.atoms]] = second.valuation
    rel, know = {}, {}
    for agent in first.agents:
        rel[agent] = _stack(first.belief_relations[agent], second.belief_relations[agent])
        know[agent] = _stack(first.knowledge_relations[agent], second.knowledge_relations[agent])
    designated = np.concatenate(
        [first.designated_positions, second.designated_positions + first.n_worlds]
    )
    return type(first).from_arrays(None, atoms, val, first.agents, rel, know, designated)


def _stack(top: Relation, bottom: Relation) -> Relation:
    if isinstance(top, Partition) and isinstance(bottom, Partition):
        return Partition(np.concatenate([top.labels, bottom.labels + top.n_labels]))
    top_rows, top_cols = top.edges()
    rows, cols = bottom.edges()
    return arrows_from_edges(
        top.n + bottom.n, np.r_[top_rows, rows + top.n], np.r_[top_cols, cols + top.n]
    )
