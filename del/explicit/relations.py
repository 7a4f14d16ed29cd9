"""Accessibility relations of one agent over the worlds of a model, stored for speed.

Three representations share one small interface:

- :class:`Partition`: an equivalence relation given by a label per world (worlds with
  the same label are related). The box of a mask costs one scatter and one gather.
- :class:`DenseArrows`: any relation on a few thousand worlds at most, as a boolean
  matrix (planning states are small: numpy beats sparse-matrix bookkeeping there).
- :class:`Arrows`: any relation, as a sparse boolean matrix in CSR form.

A relation is stored as a partition only when it *is* an equivalence; the box over a
partition is never used as a shortcut for a relation that is not one (a classic source of
wrong answers when beliefs are false).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from epistemica.del_.explicit._sparse import connected_components, csr_matrix

if TYPE_CHECKING:
    import scipy.sparse as sp

__all__ = [
    "DENSE_LIMIT",
    "Arrows",
    "ClassArrows",
    "DenseArrows",
    "Partition",
    "Relation",
    "arrows_from_edges",
    "as_compact",
    "relation_from_pairs",
]

# Relations on at most this many worlds are kept as dense boolean matrices.
DENSE_LIMIT = 2048


class Relation:
    """Interface of an agent's relation over ``n`` worlds."""

    n: int

    def box(self, mask: np.ndarray) -> np.ndarray:
        """Worlds all of whose successors lie in ``mask``."""
        raise NotImplementedError

    def restrict(self, keep: np.ndarray) -> Relation:
        """The relation on the worlds of the boolean mask ``keep``, renumbered in order."""
        raise NotImplementedError

    def successors_of(self, mask: np.ndarray) -> np.ndarray:
        """Worlds reachable in one step from some world of ``mask``."""
        raise NotImplementedError

    def predecessors_of(self, mask: np.ndarray) -> np.ndarray:
        """Worlds with at least one successor in ``mask``."""
        raise NotImplementedError

    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        """Sources and targets of every related pair."""
        raise NotImplementedError

    def to_dense(self) -> np.ndarray:
        """The relation as an ``n x n`` boolean matrix."""
        raise NotImplementedError

    def contains(self, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
        """Whether each pair ``(sources[i], targets[i])`` is related."""
        raise NotImplementedError

    def to_csr(self) -> sp.csr_matrix:
        """The relation as a boolean CSR matrix (row: source world, column: target)."""
        rows, cols = self.edges()
        data = np.ones(len(rows), dtype=bool)
        return csr_matrix((data, (rows, cols)), shape=(self.n, self.n))

    def is_equivalence(self) -> bool:
        """Reflexive, symmetric and transitive."""
        raise NotImplementedError

    def is_kd45(self) -> bool:
        """Serial, transitive and Euclidean."""
        raise NotImplementedError


class Partition(Relation):
    """An equivalence relation given by one label per world.

    Parameters
    ----------
    labels : array of int
        ``labels[w]`` names the class of world ``w``; labels lie in ``[0, n_labels)`` but
        need not be contiguous (after a restriction some labels are unused).
    n_labels : int, optional
        An upper bound on the labels; default ``labels.max() + 1``.

    Examples
    --------
    >>> import numpy as np
    >>> r = Partition(np.array([0, 0, 1]))
    >>> r.box(np.array([True, False, True])).tolist()
    [False, False, True]
    """

    def __init__(self, labels: np.ndarray, n_labels: int | None = None) -> None:
        # Index arrays of the platform's intp type avoid a conversion on every gather.
        self.labels = np.ascontiguousarray(labels, dtype=np.intp)
        self.n = len(self.labels)
        if n_labels is None:
            n_labels = int(self.labels.max()) + 1 if self.n else 0
        self.n_labels = n_labels

    def box(self, mask: np.ndarray) -> np.ndarray:
        spoiled = np.zeros(self.n_labels, dtype=bool)
        spoiled[self.labels[~mask]] = True
        return ~spoiled[self.labels]

    def know_whether(self, mask: np.ndarray) -> np.ndarray:
        """Worlds whose class is uniform on ``mask`` (one gather instead of two boxes)."""
        has_true = np.zeros(self.n_labels, dtype=bool)
        has_true[self.labels[mask]] = True
        has_false = np.zeros(self.n_labels, dtype=bool)
        has_false[self.labels[~mask]] = True
        return ~(has_true & has_false)[self.labels]

    def restrict(self, keep: np.ndarray) -> Partition:
        return Partition(self.labels[keep], self.n_labels)

    def successors_of(self, mask: np.ndarray) -> np.ndarray:
        hit = np.zeros(self.n_labels, dtype=bool)
        hit[self.labels[mask]] = True
        return hit[self.labels]

    predecessors_of = successors_of  # symmetric

    def compact(self) -> np.ndarray:
        """The labels renumbered to ``0..k-1`` (in increasing order of the old labels)."""
        return np.unique(self.labels, return_inverse=True)[1].reshape(-1)

    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        order = np.argsort(self.labels, kind="stable")
        sorted_labels = self.labels[order]
        starts = np.flatnonzero(np.r_[True, sorted_labels[1:] != sorted_labels[:-1]])
        sizes = np.diff(np.r_[starts, self.n])
        rows, cols = [], []
        for start, size in zip(starts.tolist(), sizes.tolist(), strict=True):
            members = order[start : start + size]
            rows.append(np.repeat(members, size))
            cols.append(np.tile(members, size))
        if not rows:
            return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
        return np.concatenate(rows), np.concatenate(cols)

    def to_dense(self) -> np.ndarray:
        return self.labels[:, None] == self.labels[None, :]

    def contains(self, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
        return self.labels[sources] == self.labels[targets]

    def is_equivalence(self) -> bool:
        return True

    def is_kd45(self) -> bool:
        return True


class DenseArrows(Relation):
    """Any relation as a dense boolean matrix (for small models).

    Examples
    --------
    >>> import numpy as np
    >>> r = DenseArrows(np.array([[0, 1], [0, 1]], dtype=bool))
    >>> r.box(np.array([True, False])).tolist()
    [False, False]
    >>> r.is_kd45(), r.is_equivalence()
    (True, False)
    """

    def __init__(self, matrix: np.ndarray) -> None:
        self.matrix = np.asarray(matrix, dtype=bool)
        self.n = self.matrix.shape[0]

    def box(self, mask: np.ndarray) -> np.ndarray:
        return ~(self.matrix & ~mask).any(axis=1)

    def restrict(self, keep: np.ndarray) -> DenseArrows:
        return DenseArrows(self.matrix[np.ix_(keep, keep)])

    def successors_of(self, mask: np.ndarray) -> np.ndarray:
        return self.matrix[mask].any(axis=0)

    def predecessors_of(self, mask: np.ndarray) -> np.ndarray:
        return self.matrix[:, mask].any(axis=1)

    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        return np.nonzero(self.matrix)

    def to_dense(self) -> np.ndarray:
        return self.matrix

    def contains(self, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
        return self.matrix[sources, targets]

    def is_equivalence(self) -> bool:
        m = self.matrix
        return bool(m.diagonal().all() and (m == m.T).all() and _closed(m, _compose(m, m)))

    def is_kd45(self) -> bool:
        m = self.matrix
        serial = bool(m.any(axis=1).all())
        return serial and _closed(m, _compose(m, m)) and _closed(m, _compose(m.T, m))


def _compose(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Relational composition: i -> k when i -> j in ``first`` and j -> k in ``second``."""
    return (first.astype(np.float32) @ second.astype(np.float32)) > 0


def _closed(big: np.ndarray, small: np.ndarray) -> bool:
    return not (small & ~big).any()


class Arrows(Relation):
    """Any relation as a sparse boolean matrix (for large models).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> r = Arrows(sp.csr_matrix(np.array([[0, 1], [0, 1]], dtype=bool)))
    >>> r.box(np.array([True, False])).tolist()
    [False, False]
    >>> r.is_kd45(), r.is_equivalence()
    (True, False)
    """

    def __init__(self, matrix: sp.spmatrix) -> None:
        matrix = csr_matrix(matrix, dtype=bool)
        matrix.sum_duplicates()
        matrix.eliminate_zeros()
        self.matrix = matrix
        self.n = matrix.shape[0]
        self._rows = np.repeat(np.arange(self.n), np.diff(matrix.indptr))

    def box(self, mask: np.ndarray) -> np.ndarray:
        bad_edge = ~mask[self.matrix.indices]
        return np.bincount(self._rows[bad_edge], minlength=self.n) == 0

    def restrict(self, keep: np.ndarray) -> Arrows:
        index = np.flatnonzero(keep)
        return Arrows(self.matrix[index][:, index])

    def successors_of(self, mask: np.ndarray) -> np.ndarray:
        hit = np.zeros(self.n, dtype=bool)
        hit[self.matrix.indices[mask[self._rows]]] = True
        return hit

    def predecessors_of(self, mask: np.ndarray) -> np.ndarray:
        hit = np.zeros(self.n, dtype=bool)
        hit[self._rows[mask[self.matrix.indices]]] = True
        return hit

    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        return self._rows, self.matrix.indices

    def to_dense(self) -> np.ndarray:
        return self.matrix.toarray()

    def contains(self, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
        if not len(sources):  # scipy cannot index a matrix by empty arrays
            return np.zeros(0, dtype=bool)
        return np.asarray(self.matrix[sources, targets]).reshape(-1).astype(bool)

    def to_csr(self) -> sp.csr_matrix:
        return self.matrix

    def is_equivalence(self) -> bool:
        m = self.matrix
        reflexive = bool(m.diagonal().all())
        return reflexive and (m != m.T).nnz == 0 and _contains(m, m @ m)

    def is_kd45(self) -> bool:
        m = self.matrix
        serial = bool((np.diff(m.indptr) > 0).all())
        return serial and _contains(m, m @ m) and _contains(m, m.T @ m)


class ClassArrows(Relation):
    """A relation in which every world of a class has the same successors: class ``c``
    leads to the worlds of ``targets[c]`` (the group models of an epistemic state, whose
    copies of the worlds are related block by block). Boxes and images cost one pass per
    class, never one per edge; ``edges()`` lists them only when asked.

    Parameters
    ----------
    labels : array of int
        ``labels[w]``: the class of world ``w``.
    targets : sequence of int arrays
        ``targets[c]``: the successors of every world of class ``c``.

    Examples
    --------
    >>> import numpy as np
    >>> r = ClassArrows(np.array([0, 0, 1]), [np.array([2]), np.array([2])])
    >>> r.box(np.array([False, False, True])).tolist(), r.is_kd45(), r.is_equivalence()
    ([True, True, True], True, False)
    """

    def __init__(self, labels: np.ndarray, targets) -> None:
        self.labels = np.asarray(labels, dtype=np.intp)
        self.targets = [np.asarray(t, dtype=np.intp) for t in targets]
        self.n = self.labels.size

    def _per_class(self, mask: np.ndarray, test) -> np.ndarray:
        return np.array([test(mask[t]) for t in self.targets], dtype=bool)

    def box(self, mask: np.ndarray) -> np.ndarray:
        return self._per_class(mask, np.all)[self.labels] if self.targets else np.ones(0, bool)

    def restrict(self, keep: np.ndarray) -> ClassArrows:
        index = np.cumsum(keep) - 1
        targets = [index[t[keep[t]]] for t in self.targets]
        return ClassArrows(self.labels[keep], targets)

    def successors_of(self, mask: np.ndarray) -> np.ndarray:
        hit = np.zeros(self.n, dtype=bool)
        for c in np.unique(self.labels[mask]):
            hit[self.targets[c]] = True
        return hit

    def predecessors_of(self, mask: np.ndarray) -> np.ndarray:
        return self._per_class(mask, np.any)[self.labels]

    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        sizes = np.array([self.targets[c].size for c in self.labels], dtype=np.intp)
        sources = np.repeat(np.arange(self.n), sizes)
        if not self.n:
            return sources, np.zeros(0, dtype=np.intp)
        return sources, np.concatenate([self.targets[c] for c in self.labels])

    def to_dense(self) -> np.ndarray:
        out = np.zeros((self.n, self.n), dtype=bool)
        out[self.edges()] = True
        return out

    def contains(self, sources: np.ndarray, targets: np.ndarray) -> np.ndarray:
        return np.array(
            [
                t in set(self.targets[self.labels[s]].tolist())
                for s, t in zip(sources, targets, strict=True)
            ],
            dtype=bool,
        )

    def to_csr(self) -> sp.csr_matrix:
        sources, targets = self.edges()
        data = np.ones(sources.size, dtype=bool)
        return csr_matrix((data, (sources, targets)), shape=(self.n, self.n), dtype=bool)

    def _class_sets(self) -> list[frozenset]:
        return [frozenset(t.tolist()) for t in self.targets]

    def is_kd45(self) -> bool:
        """Serial, transitive and euclidean: every class leads to a nonempty set all of
        whose worlds lead back to exactly that set."""
        sets = self._class_sets()
        for c, here in enumerate(sets):
            if not here or any(sets[self.labels[w]] != here for w in self.targets[c]):
                return False
        return True

    def is_equivalence(self) -> bool:
        """KD45 and reflexive: every world is among its own successors."""
        sets = self._class_sets()
        return self.is_kd45() and all(w in sets[c] for w, c in enumerate(self.labels))


def _contains(big: sp.csr_matrix, small: sp.spmatrix) -> bool:
    """Whether every edge of ``small`` is an edge of ``big``."""
    small = csr_matrix(small, dtype=bool)
    return (small > big).nnz == 0


def arrows_from_edges(n: int, sources: np.ndarray, targets: np.ndarray) -> Relation:
    """A relation from edge lists: dense for small ``n``, sparse otherwise."""
    if n <= DENSE_LIMIT:
        matrix = np.zeros((n, n), dtype=bool)
        matrix[sources, targets] = True
        return DenseArrows(matrix)
    data = np.ones(len(sources), dtype=bool)
    return Arrows(csr_matrix((data, (sources, targets)), shape=(n, n), dtype=bool))


def relation_from_pairs(n: int, sources: Sequence[int], targets: Sequence[int]) -> Relation:
    """Build a relation from edge lists, as a :class:`Partition` when it is an equivalence.

    Examples
    --------
    >>> type(relation_from_pairs(2, [0, 0, 1, 1], [0, 1, 0, 1])).__name__
    'Partition'
    >>> type(relation_from_pairs(2, [0, 1], [1, 1])).__name__
    'DenseArrows'
    """
    sources = np.asarray(sources, dtype=np.intp)
    targets = np.asarray(targets, dtype=np.intp)
    return as_compact(arrows_from_edges(n, sources, targets))


def as_compact(relation: Relation) -> Relation:
    """Return ``relation`` as a partition if it is an equivalence, unchanged otherwise."""
    if isinstance(relation, Partition) or not relation.n or not relation.is_equivalence():
        return relation
    if isinstance(relation, DenseArrows):
        # In an equivalence, a world's first related world names its class.
        return Partition(relation.matrix.argmax(axis=1))
    return Partition(connected_components(relation.matrix, directed=False)[1])
