"""When a mission holds: the success conditions, decided by matching, not enumeration.

Rendezvous holds when one goal is within the success radius of every robot; allocation
when the robots can be matched to pairwise distinct goals each within the radius;
capacity when they can be matched to goal slots (goal ``g`` repeated ``capacities[g]``
times). Matching (``scipy.sparse.csgraph.maximum_bipartite_matching``) answers in
polynomial time what the definition states over all valid configurations.

The kinds (:mod:`epistemica.sim.kinds`) decide with these primitives.

Examples
--------
>>> goals = np.array([[0.0, 0.0], [10.0, 0.0]])
>>> near = within(np.array([[0.5, 0.0], [9.0, 0.5]]), goals, 5 / 3)
>>> matched(near), gathered(near)
(True, False)
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import maximum_bipartite_matching

__all__ = ["distances", "gathered", "matched", "realises", "within"]


def distances(positions: np.ndarray, goals: np.ndarray) -> np.ndarray:
    """Euclidean distances ``(n, m)`` from every position to every goal.

    Examples
    --------
    >>> distances(np.array([[0.0, 0.0]]), np.array([[3.0, 4.0]])).tolist()
    [[5.0]]
    """
    return np.hypot(*(positions[:, None, :2] - goals[None, :, :2]).transpose(2, 0, 1))


def within(positions: np.ndarray, goals: np.ndarray, radius: float) -> np.ndarray:
    """``(n, m)`` booleans: robot ``i`` is within ``radius`` of goal ``g``."""
    return distances(positions, goals) <= radius


def realises(positions: np.ndarray, goals: np.ndarray, radius: float, rows: np.ndarray) -> bool:
    """Whether every robot is within ``radius`` of its goal in one of ``rows`` (``(k, n)``).

    Examples
    --------
    >>> goals = np.array([[0.0, 0.0], [10.0, 0.0]])
    >>> realises(np.array([[0.0, 0.5], [9.0, 0.0]]), goals, 5 / 3, np.array([[1, 0], [0, 1]]))
    True
    """
    near = within(positions, goals, radius)
    return bool(near[np.arange(near.shape[0]), rows].all(axis=1).any())


def gathered(near: np.ndarray) -> bool:
    """Whether one goal is near every robot (``near`` ``(n, m)`` booleans).

    Examples
    --------
    >>> gathered(np.array([[True, False], [True, True]]))
    True
    """
    return bool(near.all(axis=0).any())


def matched(near: np.ndarray) -> bool:
    """Whether robots can be matched to pairwise distinct columns each near them
    (``near`` ``(n, k)`` booleans: goals, or goal slots of a capacity mission).

    Examples
    --------
    >>> matched(np.array([[True, True], [True, False]])), matched(np.array([[True], [True]]))
    (True, False)
    """
    n = near.shape[0]
    if near.shape[1] < n:
        return False
    assigned = maximum_bipartite_matching(csr_matrix(near), perm_type="column")
    return bool(np.all(assigned >= 0))
