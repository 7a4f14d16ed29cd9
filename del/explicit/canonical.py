"""Canonical forms of bisimulation classes, for hashing epistemic states.

:func:`canonical_key` names the bisimulation class of a pointed Kripke model by a
hashable value, so that a planner can detect a state it has seen before with one dict
lookup instead of pairwise :func:`~epistemica.del_.explicit.bisimulation.bisimilar` tests.

The key comes from a partition refinement in which every class is named by its rank in
an order of descriptions that depends on their content only (valuation first, then per
agent and relation the set of classes reached), so the names do not depend on the order
or names of the worlds. At the fixed point the classes are the bisimulation classes and
the key spells out the quotient model. A state of more than :data:`CONTRACT_ABOVE` worlds
is contracted first (:func:`~epistemica.del_.explicit.bisimulation.bisimulation_classes`,
O(m log n)), which leaves the key unchanged: every description is a bisimulation
invariant. Refinement runs on int64 bitmasks while there are at most 62 classes, and
beyond that on 64-bit hashes of each successor set, ordered by (label, hash); sets with
equal hashes are compared exactly, and a collision falls back to Python tuples.

Examples
--------
>>> from epistemica.del_ import KripkeModel
>>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
>>> canonical_key(m.minimize()) == canonical_key(m.announce("p | ~p").minimize())
True
>>> canonical_key(m.minimize()) == canonical_key(m.announce("p").minimize())  # a learns p
False
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit._refinement import mix64, ranges
from epistemica.del_.explicit.bisimulation import bisimulation_classes, quotient, successor_sets
from epistemica.del_.explicit.relations import Partition, Relation

__all__ = ["CONTRACT_ABOVE", "canonical_classes", "canonical_key"]

# Sets of at most this many classes (and valuations of fewer atoms) are int64 bitmasks.
_MASK_BITS = 62

#: States of more worlds are contracted before their canonical refinement.
CONTRACT_ABOVE = 256


def canonical_key(state: ExplicitModel) -> tuple:
    """A canonical form of the bisimulation class of a pointed model.

    Partition refinement in which every class is named by its rank in the sorted order
    of its description (valuation first, then per agent and relation the set of classes
    reached), so the names do not depend on the order or names of the worlds. At the
    fixed point the classes are the bisimulation classes and the key spells out the
    quotient model (each class's valuation and successors, and the designated classes).
    Two models get the same key exactly when they are bisimilar, provided both are
    contracted (:meth:`~epistemica.del_.KripkeModel.minimize`); for other models
    equal keys still imply bisimilarity.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "q"], {"a": ["p"]}, designated=["p"])
    >>> canonical_key(m.minimize()) == canonical_key(m.announce("q | ~q").minimize())
    True
    >>> canonical_key(m.minimize()) == canonical_key(m.announce("~q").minimize())
    False
    """
    return canonical_classes(state)[1]


def canonical_classes(state: ExplicitModel) -> tuple[list[int], tuple]:
    """The canonical refinement's class of each world, and the canonical key.

    Returns
    -------
    labels : list of int
        Per world (in model order), its class, numbered ``0, 1, ...`` in canonical order.
    key : tuple
        :func:`canonical_key` of ``state``.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "q"], {"a": ["p"]})
    >>> labels, key = canonical_classes(m)
    >>> sorted(labels)   # four valuations, so four classes
    [0, 1, 2, 3]
    >>> key == canonical_key(m)
    True
    """
    if state.n_worlds > CONTRACT_ABOVE:
        blocks = bisimulation_classes(state)
        if int(blocks.max()) + 1 < state.n_worlds:
            labels, key = canonical_classes(quotient(state, blocks))
            return np.asarray(labels)[blocks].tolist(), key
    present = state.valuation.any(axis=0).tolist()  # one pass, not one call per atom
    atoms = sorted(a for a, used in zip(state.atoms, present, strict=True) if used)
    relations = [
        relation
        for agent in sorted(state.agents)
        for relation in (state.belief_relations[agent], state.knowledge_relations[agent])
    ]
    if len(atoms) < _MASK_BITS:
        found = _canonical_bitmasks(state, atoms, relations)
        if found is not None:
            return found
    found = _canonical_hashes(state, atoms, relations)
    if found is not None:
        return found
    return _canonical_tuples(state, atoms, relations)


def _canonical_bitmasks(
    state: ExplicitModel, atoms: list[str], relations: list[Relation]
) -> tuple[list[int], tuple] | None:
    """Vectorised canonical refinement; None when the classes outgrow a 64-bit mask.

    Whether it applies depends only on the number of bisimulation classes, so bisimilar
    states always get keys of the same kind.
    """
    columns = [state.atom_column(a) for a in atoms]
    codes = state.valuation[:, columns].astype(np.int64) @ (np.int64(1) << np.arange(len(atoms)))
    labels = np.unique(codes, return_inverse=True)[1].reshape(-1)

    def describe(labels: np.ndarray) -> np.ndarray | None:
        if int(labels.max()) + 1 > _MASK_BITS:
            return None
        masks: dict[int, np.ndarray] = {}  # a relation shared by belief and knowledge
        for r in relations:
            if id(r) not in masks:
                masks[id(r)] = _reached_mask(r, labels)
        return np.column_stack([labels] + [masks[id(r)] for r in relations])

    done = _fixed_point(labels, describe)
    if done is None:
        return None
    labels, described = done
    first = np.unique(labels, return_index=True)[1]  # one world per class, by class
    table = np.column_stack([codes, described[:, 1:]])[first]
    points = tuple(np.unique(labels[state.designated_positions]).tolist())
    return labels.tolist(), (tuple(atoms), table.tobytes(), points)


def _fixed_point(
    labels: np.ndarray, describe: Callable[[np.ndarray], np.ndarray | None]
) -> tuple[np.ndarray, np.ndarray] | None:
    """Refine ``labels`` by ranking ``describe(labels)`` (one row per world, the label
    first) until the number of classes stops growing; the labels and the last rows, or
    None as soon as ``describe`` gives up."""
    count = int(labels.max()) + 1
    while True:
        described = describe(labels)
        if described is None:
            return None
        refined = _rank_rows(described)
        new_count = int(refined.max()) + 1
        if new_count == count:
            return refined, described
        labels, count = refined, new_count


def _rank_rows(described: np.ndarray) -> np.ndarray:
    """Each row's rank among the distinct rows, in lexicographic order: names that depend
    on the rows' content only."""
    order = np.lexsort(described.T[::-1])
    ordered = described[order]
    changed = np.zeros(len(described), dtype=bool)
    changed[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    refined = np.empty(len(described), dtype=np.int64)
    refined[order] = np.cumsum(changed)
    return refined


def _reached_mask(relation: Relation, labels: np.ndarray) -> np.ndarray:
    """Per world, the set of classes of its successors as a bitmask."""
    bits = np.int64(1) << labels.astype(np.int64)
    if isinstance(relation, Partition):
        per_class = np.zeros(relation.n_labels, dtype=np.int64)
        np.bitwise_or.at(per_class, relation.labels, bits)
        return per_class[relation.labels]
    rows, cols = relation.edges()
    reached = np.zeros(len(labels), dtype=np.int64)
    np.bitwise_or.at(reached, rows, bits[cols])
    return reached


def _canonical_hashes(
    state: ExplicitModel, atoms: list[str], relations: list[Relation]
) -> tuple[list[int], tuple] | None:
    """Vectorised canonical refinement for any number of classes; None on a collision.

    A world's description is its label and, per relation, a 64-bit hash of the set of
    labels its successors have; descriptions are ranked by (label, hashes), an order that
    depends on content only. Sets with equal hashes are compared exactly within the state,
    and the key lists the sets themselves, so keys of different states never collide.
    """
    columns = [state.atoms.index(a) for a in atoms]
    rows = np.packbits(state.valuation[:, columns], axis=1)
    labels = _row_ranks(rows)
    sets = {}
    for r in relations:
        if id(r) not in sets:
            sets[id(r)] = successor_sets(r)
    found: dict[int, tuple] = {}

    def describe(labels: np.ndarray) -> np.ndarray | None:
        found.update({key: _set_hashes(parts, labels) for key, parts in sets.items()})
        if any(f is None for f in found.values()):
            return None
        return np.column_stack(
            [labels.astype(np.uint64)] + [found[id(r)][0][sets[id(r)][0]] for r in relations]
        )

    done = _fixed_point(labels, describe)
    if done is None:
        return None
    labels = done[0]
    first = np.unique(labels, return_index=True)[1]  # one world per class, by class
    parts = [rows[first].tobytes()]
    for r in relations:
        # Per class, which of the relation's distinct successor sets it has (numbered by
        # first use in class order); per such set, its sorted distinct labels and their
        # count. A set shared by many classes is listed once (one agent who considers
        # every world possible would otherwise list every class once per class).
        used, index = _first_use_order(sets[id(r)][0][first])
        starts, lengths = found[id(r)][1]
        used, index = _same_labels_once(used, index, starts, lengths, found[id(r)][2])
        parts.append(index.tobytes())
        parts.append(lengths[used].tobytes())
        parts.append(found[id(r)][2][ranges(starts[used], lengths[used])].tobytes())
    points = tuple(np.unique(labels[state.designated_positions]).tolist())
    return labels.tolist(), (tuple(atoms), tuple(parts), points)


def _first_use_order(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct values in order of first occurrence, and each value's index there.

    >>> used, index = _first_use_order(np.array([7, 3, 7, 5, 3]))
    >>> used.tolist(), index.tolist()
    ([7, 3, 5], [0, 1, 0, 2, 1])
    """
    distinct, first, inverse = np.unique(values, return_index=True, return_inverse=True)
    order = np.argsort(first)
    rank = np.empty(len(order), dtype=np.int64)
    rank[order] = np.arange(len(order))
    return distinct[order], rank[inverse.reshape(-1)]


def _same_labels_once(used, index, starts, lengths, data) -> tuple[np.ndarray, np.ndarray]:
    """``used`` and ``index`` with successor sets that meet the same labels merged: two
    sets of worlds may differ and still meet the same classes, and which of them a class's
    representative has depends on the numbering of worlds, so the key may name a set only
    by the labels it meets."""
    seen: dict[bytes, int] = {}
    keep, renumber = [], np.empty(len(used), dtype=np.int64)
    for k, u in enumerate(used.tolist()):
        content = data[starts[u] : starts[u] + lengths[u]].tobytes()
        if content not in seen:
            seen[content] = len(keep)
            keep.append(k)
        renumber[k] = seen[content]
    return used[keep], renumber[index]


def _set_hashes(parts: tuple, labels: np.ndarray) -> tuple | None:
    """Per successor set, a hash of the labels it meets (exact within the state).

    Returns ``(hashes, (starts, lengths), sorted labels)``: each set's distinct member
    labels are ``sorted labels[starts[s] : starts[s] + lengths[s]]``; ``None`` when two
    different sets share a hash.
    """
    _, n_sets, members, of_set = parts
    met = of_set.astype(np.int64) * (int(labels.max()) + 1) + labels[members]
    met = np.unique(met)
    width = int(labels.max()) + 1
    owner, label = met // width, met % width
    lengths = np.bincount(owner, minlength=n_sets)
    starts = np.zeros(n_sets, dtype=np.int64)
    starts[1:] = np.cumsum(lengths)[:-1]
    hashes = np.zeros(n_sets, dtype=np.uint64)
    hit = lengths > 0
    if len(label):
        hashes[hit] = np.add.reduceat(mix64(label), starts[hit])
    hashes ^= mix64(lengths)
    # Equal hashes must mean equal sets: compare each set with the first of its hash.
    _, first, inverse = np.unique(hashes, return_index=True, return_inverse=True)
    rep = first[inverse.reshape(-1)]
    if not np.array_equal(lengths, lengths[rep]):
        return None
    if not np.array_equal(label[ranges(starts, lengths)], label[ranges(starts[rep], lengths)]):
        return None
    return hashes, (starts, lengths), label


def _canonical_tuples(
    state: ExplicitModel, atoms: list[str], relations: list[Relation]
) -> tuple[list[int], tuple]:
    """Canonical refinement on Python tuples, for states of many classes."""
    columns = [state.atoms.index(a) for a in atoms]
    rows = [tuple(np.flatnonzero(row)) for row in state.valuation[:, columns]]
    labels = _tuple_ranks(rows)
    count = len(set(labels))
    while True:
        reached = [_reached_labels(relation, labels) for relation in relations]
        described = [(labels[w], *(r[w] for r in reached)) for w in range(state.n_worlds)]
        labels = _tuple_ranks(described)
        new_count = len(set(labels))
        if new_count == count:
            break
        count = new_count
    classes = {}
    for w, label in enumerate(labels):
        classes.setdefault(label, (rows[w], described[w][1:]))
    points = tuple(sorted({labels[i] for i in state.designated_positions}))
    return labels, (tuple(atoms), tuple(classes[k] for k in range(count)), points)


def _reached_labels(relation: Relation, labels: list[int]) -> list[tuple[int, ...]]:
    """Per world, the sorted labels of its successors."""
    if isinstance(relation, Partition):
        members: dict[int, set[int]] = {}
        for cls, label in zip(relation.labels.tolist(), labels, strict=True):
            members.setdefault(cls, set()).add(label)
        frozen = {cls: tuple(sorted(found)) for cls, found in members.items()}
        return [frozen[cls] for cls in relation.labels.tolist()]
    found: list[set[int]] = [set() for _ in labels]
    for w, v in zip(*(side.tolist() for side in relation.edges()), strict=True):
        found[w].add(labels[v])
    return [tuple(sorted(targets)) for targets in found]


def _row_ranks(rows: np.ndarray) -> np.ndarray:
    """Each distinct row's rank in the sorted order of rows (as bytes)."""
    if not rows.shape[1]:
        return np.zeros(len(rows), dtype=np.int64)
    keys = np.ascontiguousarray(rows).view(np.dtype((np.void, rows.shape[1]))).reshape(-1)
    return np.unique(keys, return_inverse=True)[1].reshape(-1).astype(np.int64)


def _tuple_ranks(items: list) -> list[int]:
    """Each distinct item's rank in sorted order: names independent of world order."""
    order = {item: rank for rank, item in enumerate(sorted(set(items)))}
    return [order[item] for item in items]
