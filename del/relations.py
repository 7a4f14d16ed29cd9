"""Accessibility relations of one agent over the worlds of a model, stored for speed.

Two representations share one small interface:

- :class:`Partition`: an equivalence relation given by a label per world (worlds with
  the same label are related). The box of a mask costs one scatter and one gather.
- :class:`Arrows`: any relation, as a sparse boolean matrix in CSR form.

A relation is stored as a partition only when it *is* an equivalence; the box over a
partition is never used as a shortcut for a relation that is not one (a classic source of
wrong answers when beliefs are false).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

__all__ = ["Arrows", "Partition", "Relation", "as_compact", "relation_from_pairs"]


class Relation:
    """Interface of an agent's relation over ``n`` worlds."""

    n: int

    def box(self, mask: np.ndarray) -> np.ndarray:
        """Worlds all of whose successors lie in ``mask``."""
        raise NotImplementedError

    def restrict(self, keep: np.ndarray) -> Relation:
        """The relation on the worlds of the boolean mask ``keep``, renumbered in order."""
        raise NotImplementedError

    def to_csr(self) -> sp.csr_matrix:
        """The relation as a boolean CSR matrix (row: source world, column: target)."""
        raise NotImplementedError

    def successors_of(self, mask: np.ndarray) -> np.ndarray:
        """Worlds reachable in one step from some world of ``mask``."""
        raise NotImplementedError

    def is_equivalence(self) -> bool:
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

    def compact(self) -> np.ndarray:
        """The labels renumbered to ``0..k-1`` (in increasing order of the old labels)."""
        return np.unique(self.labels, return_inverse=True)[1].reshape(-1)

    def to_csr(self) -> sp.csr_matrix:
        labels = self.compact()
        k = int(labels.max()) + 1 if self.n else 0
        member = sp.csr_matrix(
            (np.ones(self.n, dtype=bool), (np.arange(self.n), labels)), shape=(self.n, k)
        )
        return (member @ member.T).astype(bool).tocsr()

    def is_equivalence(self) -> bool:
        return True

    def is_kd45(self) -> bool:
        return True


class Arrows(Relation):
    """An arbitrary relation as a sparse boolean matrix.

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
        matrix = sp.csr_matrix(matrix, dtype=bool)
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
        """Worlds with at least one successor in ``mask``."""
        hit = np.zeros(self.n, dtype=bool)
        hit[self._rows[mask[self.matrix.indices]]] = True
        return hit

    def to_csr(self) -> sp.csr_matrix:
        return self.matrix

    def is_equivalence(self) -> bool:
        m = self.matrix
        reflexive = bool(m.diagonal().all())
        return reflexive and _is_symmetric(m) and _contains(m, m @ m)

    def is_kd45(self) -> bool:
        m = self.matrix
        serial = bool((np.diff(m.indptr) > 0).all())
        euclidean = _contains(m, m.T @ m)
        return serial and _contains(m, m @ m) and euclidean


def _is_symmetric(m: sp.csr_matrix) -> bool:
    return (m != m.T).nnz == 0


def _contains(big: sp.csr_matrix, small: sp.spmatrix) -> bool:
    """Whether every edge of ``small`` is an edge of ``big``."""
    small = sp.csr_matrix(small, dtype=bool)
    return (small > big).nnz == 0


def relation_from_pairs(n: int, sources: Sequence[int], targets: Sequence[int]) -> Relation:
    """Build a relation from edge lists, as a :class:`Partition` when it is an equivalence.

    Examples
    --------
    >>> type(relation_from_pairs(2, [0, 0, 1, 1], [0, 1, 0, 1])).__name__
    'Partition'
    >>> type(relation_from_pairs(2, [0, 1], [1, 1])).__name__
    'Arrows'
    """
    sources = np.asarray(sources, dtype=np.int64)
    targets = np.asarray(targets, dtype=np.int64)
    matrix = sp.csr_matrix(
        (np.ones(len(sources), dtype=bool), (sources, targets)), shape=(n, n), dtype=bool
    )
    return as_compact(Arrows(matrix))


def as_compact(relation: Relation) -> Relation:
    """Return ``relation`` as a partition if it is an equivalence, unchanged otherwise."""
    if isinstance(relation, Arrows) and relation.n and relation.is_equivalence():
        _, labels = connected_components(relation.matrix, directed=False)
        return Partition(labels.astype(np.int64))
    return relation
