"""Sparse gathers over the valid configurations, built once per valid set.

The controller needs, for many candidate tables at once, the row sums
``sum_r table[r, c_s[r]]`` over every valid row ``c_s`` (the log likelihood of
:func:`epistemica.aif.likelihood.row_sums`), and, per robot, which rows give it which goal.
Both are sparse products with indicator matrices built on first use: a ``k x nm`` one-hot
matrix (``n`` ones per row) and, per robot, an ``m x k`` goal indicator.

Examples
--------
>>> index = RowIndex([[0, 1], [1, 0]], 2)
>>> index.row_sums(np.array([[[1.0, 2.0], [10.0, 20.0]]])).tolist()
[[21.0], [12.0]]
>>> index.groups(0).toarray().tolist()   # row 0 gives robot 0 goal 0, row 1 goal 1
[[1.0, 0.0], [0.0, 1.0]]
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_matrix

from epistemica.aif.evidence import check_robot
from epistemica.aif.likelihood import check_configurations
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["RowIndex"]


class RowIndex:
    """Sparse row sums and goal groups over ``(k, n)`` valid configurations.

    Parameters
    ----------
    configurations : array_like
        ``(k, n)`` valid configurations.
    n_goals : int
        Number of goals ``m``.
    dtype : {numpy.float64, numpy.float32}
        Precision of the indicator matrices and of the sums.

    Examples
    --------
    >>> index = RowIndex([[0, 1, 1], [1, 0, 1], [1, 1, 0]], 2, dtype=np.float32)
    >>> index.row_sums(np.zeros((4, 3, 2))).shape, index.row_sums(np.zeros((4, 3, 2))).dtype
    ((3, 4), dtype('float32'))
    """

    def __init__(self, configurations, n_goals: int, dtype=np.float64) -> None:
        self.configurations = check_configurations(configurations, None, n_goals)
        self.n_goals = int(n_goals)
        if dtype not in (np.float64, np.float32):
            raise InvalidArgumentError(
                f"dtype must be numpy.float64 or numpy.float32, got {dtype!r}",
                hint="float32 halves the memory of large valid sets",
            )
        self.dtype = dtype
        self._onehot: csr_matrix | None = None
        self._groups: dict[int, csr_matrix] = {}
        self._stacked: csr_matrix | None = None

    def row_sums(self, tables: np.ndarray) -> np.ndarray:
        """``out[s, b] = sum_r tables[b, r, c_s[r]]`` for every valid row: ``(b, n, m) -> (k, b)``.

        Examples
        --------
        >>> index = RowIndex([[0, 1], [1, 1]], 2)
        >>> index.row_sums(np.array([[[1.0, 2.0], [10.0, 20.0]]] * 2)).tolist()
        [[21.0, 21.0], [22.0, 22.0]]
        """
        k, n = self.configurations.shape
        m = self.n_goals
        if tables.ndim != 3 or tables.shape[1:] != (n, m):
            raise InvalidArgumentError(
                f"tables must have shape (b, {n}, {m}), got {tables.shape}",
                hint="one (robots x goals) table per candidate",
            )
        if self._onehot is None:
            flat = (self.configurations + np.arange(n) * m).ravel()
            self._onehot = csr_matrix(
                (np.ones(k * n, dtype=self.dtype), flat, np.arange(0, k * n + 1, n)),
                shape=(k, n * m),
            )
        t = tables.reshape(tables.shape[0], -1).astype(self.dtype)
        return np.asarray(self._onehot @ t.T)

    def groups(self, robot: int) -> csr_matrix:
        """Sparse ``(m, k)`` indicator: ``[g, s]`` is 1 when row ``s`` gives ``robot`` goal ``g``.

        Examples
        --------
        >>> RowIndex([[0, 1], [1, 0], [1, 1]], 2).groups(1).toarray().tolist()  # goals 1, 0, 1
        [[0.0, 1.0, 0.0], [1.0, 0.0, 1.0]]
        """
        if robot not in self._groups:
            robot = check_robot(robot, self.configurations.shape[1])
            self._groups[robot] = self._indicator(self.configurations[:, robot], self.n_goals)
        return self._groups[robot]

    def stacked_groups(self) -> csr_matrix:
        """Every robot's :meth:`groups`, stacked: ``(n m, k)``, row ``r m + g``.

        Row ``r m + g`` lists the same rows in the same order as row ``g`` of
        ``groups(r)``, so its products are computed term by term alike.

        Examples
        --------
        >>> RowIndex([[0, 1], [1, 0], [1, 1]], 2).stacked_groups().toarray().tolist()
        [[1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 1.0]]
        """
        if self._stacked is None:
            n = self.configurations.shape[1]
            shifted = self.configurations + np.arange(n) * self.n_goals  # (k, n)
            self._stacked = self._indicator(shifted.T.ravel(), n * self.n_goals)
        return self._stacked

    def _indicator(self, goal: np.ndarray, rows: int) -> csr_matrix:
        # Entry (goal[j], j mod k): within a row, the valid rows in increasing order.
        k = self.configurations.shape[0]
        cols = np.arange(goal.size) % k
        return csr_matrix((np.ones(goal.size, dtype=self.dtype), (goal, cols)), shape=(rows, k))
