"""A team with full communication on goal missions: the reference for completion time.

:class:`Oracle` (level ``"oracle"``) sees what no robot of the other levels sees: every
teammate's exact pose, every goal and every closure as they are (the trial loop gives a
level that ``shares`` everything the world's state, :meth:`TrialRun.everything`). Each
robot heads for its part of the configuration whose slowest robot arrives first
(:func:`least_makespan`), with ways measured round known walls. Every robot computes it
from the same facts, so the team agrees at once: what is left between a level and the
oracle is what the level pays for not knowing, the most any controller could gain over it
by reasoning better. It is a reference, not a teammate: it is never one of the levels a
claim is tuned against.

Examples
--------
Two robots, two goals: least total distance sends r0 to g0 and r1 to g1 (1 + 6), but the
last robot arrives sooner the other way round (5 and 4).

>>> cost = np.array([[1.0, 5.0], [4.0, 6.0]])
>>> least_makespan(cost, np.array([0, 1])).tolist()
[1, 0]

A rendezvous goes to the goal whose farthest robot is nearest.

>>> from epistemica.sim.kinds.goal import RENDEZVOUS
>>> least_makespan(np.array([[1.0, 4.0], [8.0, 5.0]]), np.array([0, 1]), RENDEZVOUS).tolist()
[1, 1]
>>> from epistemica.sim import Scenario, simulate
>>> s = Scenario("allocation", [[0, 0, 0], [20, 0, 0]], [[2, 0], [18, 0]], ["range"] * 2)
>>> simulate(s, "oracle", seed=0).success
True
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from epistemica.sim.engine.missions import distances
from epistemica.sim.engine.navigation import roadmap_for
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.goal import ALLOCATION
from epistemica.sim.policies.baselines import Straight

__all__ = ["Oracle", "least_makespan"]


def least_makespan(
    cost: np.ndarray,
    goals: np.ndarray,
    kind: MissionKind = ALLOCATION,
    capacities: Sequence[int] | None = None,
    table: np.ndarray | None = None,
) -> np.ndarray:
    """The configuration over ``goals`` whose longest way is shortest (ties: least total).

    Parameters
    ----------
    cost : (n, m') array
        The way from each robot to each of ``goals`` (``inf``: none).
    goals : (m',) int array
        The goals that may be used (their indices in the mission).
    kind : MissionKind
        A gathering kind sends everyone to one goal; otherwise robots take distinct goals
        (goal slots with ``capacities``), the one a robot cannot be given its nearest.
    capacities : sequence of int, optional
        Per mission goal, with a kind that has capacities.
    table : (k, n) int array, optional
        The mission's explicit valid configurations (mission goal indices): the best row
        among those that use only ``goals``.

    Returns
    -------
    numpy.ndarray
        ``(n,)``: each robot's goal (mission index).
    """
    cost, goals = np.asarray(cost, dtype=float), np.asarray(goals)
    n = cost.shape[0]
    if table is not None:
        column = {int(g): k for k, g in enumerate(goals)}
        rows = table[np.isin(table, goals).all(axis=1)]
        if len(rows):
            ways = cost[np.arange(n), np.vectorize(column.get)(rows)]
            best = np.lexsort((ways.sum(axis=1), ways.max(axis=1)))[0]
            return rows[best].copy()
    if kind.gathers:
        best = np.lexsort((cost.sum(axis=0), cost.max(axis=0)))[0]
        return np.full(n, goals[best])
    if kind.capacities and capacities is not None:
        slots = np.repeat(np.arange(len(goals)), np.asarray(capacities)[goals])
        cost, goals = cost[:, slots], goals[slots]
    robots, columns = _bottleneck(cost)
    row = np.full(n, -1)
    row[robots] = goals[columns]
    for r in np.flatnonzero(row < 0):  # more robots than goals: the nearest
        row[r] = goals[np.argmin(cost[r])]
    return row


def _bottleneck(cost: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The assignment whose largest cost is least, then whose total is least: the
    smallest threshold (bisected over the costs) under which a full assignment exists."""
    finite = np.isfinite(cost)
    values = np.unique(cost[finite])
    big = (values.max() + 1.0) * cost.size if values.size else 1.0
    need = min(cost.shape)

    def under(limit: float):
        capped = np.where(finite & (cost <= limit), cost, big)
        robots, columns = linear_sum_assignment(capped)
        return robots, columns, int((capped[robots, columns] < big).sum()) == need

    lo, hi = 0, values.size - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if under(values[mid])[2]:
            hi = mid
        else:
            lo = mid + 1
    robots, columns, _ = under(values[lo] if values.size else 0.0)
    return robots, columns


class Oracle(Straight):
    """Level ``"oracle"``: full communication, the configuration of least makespan
    (module docstring). Multitask missions: the open tasks, one robot each."""

    name = "oracle"
    shares = "everything"

    def start(self, scenario, robots, generators) -> None:
        super().start(scenario, robots, generators)
        self._roadmap = roadmap_for(scenario)
        radii = scenario.robot_radius
        self._radius = 0.0 if radii is None else float(np.max(radii))

    def decide(self, observations, robots):
        self._row = None  # every robot sees the same facts: one configuration a step
        return super().decide(observations, robots)

    def configuration(self, view, goals, robot):
        if self._row is None:
            self._row = self._least(view, goals)
        return self._row.copy()

    def _least(self, view, goals):
        s = self.scenario
        places = s.goals[goals]
        if self._roadmap is None:
            cost = distances(view[:, :2], places)
        else:
            cost = self._roadmap.lengths(view[:, :2], places, self._radius)
        if s.kind.tasks:
            return least_makespan(cost, goals)
        table = s.configurations() if s.valid is not None else None
        return least_makespan(cost, goals, s.kind, s.capacities, table)
