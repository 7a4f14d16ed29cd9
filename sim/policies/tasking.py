"""Multitask upper level: which tasks the team works on now (the paper's problem 1).

The bi-level problem selects at most ``K`` tasks and assigns robots to them at least total
cost. With the cost of a task its distance to the robot assigned to it, the optimum is an
optimal assignment of the robots to the open tasks (``linear_sum_assignment``), and the
selected subset is the set of assigned tasks. Every robot solves this team-level problem
from its own observations; since the teammates see nearly the same scene they select
nearly the same subset, a common ground for the lower level. The released code instead
gave each robot the ``n`` tasks nearest to itself, subsets that differ from robot to robot
so that no configuration the robots reason about is shared.

When fewer open tasks remain than robots, the subset is cycled to ``n`` slots, so surplus
robots back up a task someone else also heads for.

Examples
--------
>>> robots = np.array([[0.0, 0.0], [10.0, 0.0]])
>>> tasks = np.array([[9.0, 0.0], [1.0, 0.0], [30.0, 30.0]])
>>> select_tasks(robots, tasks, np.array([0, 1, 2])).tolist()
[1, 0]
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from epistemica.sim.engine.missions import distances

__all__ = ["select_tasks", "task_slots"]


def select_tasks(
    positions: np.ndarray, tasks: np.ndarray, open_tasks: np.ndarray, k: int | None = None
) -> np.ndarray:
    """The tasks of an optimal assignment of the robots to the open tasks.

    Parameters
    ----------
    positions : numpy.ndarray
        ``(n, 2)`` robot positions as one robot observes them.
    tasks : numpy.ndarray
        ``(m, 2)`` all task positions.
    open_tasks : numpy.ndarray
        Indices of the tasks not known to be done.
    k : int, optional
        At most this many tasks (default ``n``); the ``k`` assigned tasks nearest to
        their robots are kept.

    Returns
    -------
    numpy.ndarray
        Task indices, the one assigned to robot ``i`` at position ``i`` when ``k >= n``.
    """
    open_tasks = np.asarray(open_tasks, dtype=int)
    if open_tasks.size == 0:
        return open_tasks
    cost = distances(positions[:, :2], tasks[open_tasks])
    robots, columns = linear_sum_assignment(cost)
    order = np.argsort(robots)
    chosen = open_tasks[columns[order]]
    if k is not None and k < chosen.size:
        nearest = np.argsort(cost[robots[order], columns[order]], kind="stable")[:k]
        chosen = chosen[np.sort(nearest)]
    return chosen


def task_slots(chosen: np.ndarray, n_robots: int) -> np.ndarray:
    """``n_robots`` slots over the chosen tasks, cycling them when there are fewer.

    Examples
    --------
    >>> task_slots(np.array([4, 7]), 3).tolist()
    [4, 7, 4]
    """
    return np.resize(chosen, n_robots) if chosen.size else chosen
