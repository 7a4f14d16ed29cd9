"""Goal missions: the team holds a configuration of goals for ``dwell`` steps.

Three kinds, one class, told apart by the data they carry rather than by their names:

- ``rendezvous``: every robot at the same goal;
- ``allocation``: robots at pairwise distinct goals;
- ``capacity``: goal ``g`` takes exactly ``capacities[g]`` robots.

Their configurations come from :mod:`epistemica.aif.configurations` (the family of the same
name); whether one holds is decided by matching (:mod:`epistemica.sim.engine.missions`),
never by listing every configuration.

Examples
--------
>>> goals = np.array([[0.0, 0.0], [10.0, 0.0]])
>>> ALLOCATION.holds(np.array([[0.5, 0.0], [9.0, 0.5]]), goals, 5 / 3)
True
>>> RENDEZVOUS.holds(np.array([[0.5, 0.0], [9.0, 0.5]]), goals, 5 / 3)
False
>>> CAPACITY.cheapest(np.array([[1.0, 5.0], [2.0, 1.0], [9.0, 1.0]]), np.arange(2), [1, 2]).tolist()
[0, 1, 1]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from epistemica.aif.configurations import count_configurations, valid_configurations
from epistemica.sim.engine.missions import gathered, matched, within
from epistemica.sim.kinds.base import GOAL_PANELS

__all__ = ["ALLOCATION", "CAPACITY", "RENDEZVOUS", "GoalKind"]

_STUDY_LEVELS = ("zero", "convention", "rules-third", "first", "third")


@dataclass(frozen=True)
class GoalKind:
    """A goal mission (see the module docstring): ``distinct`` says whether two robots may
    share a goal, ``gathers`` whether they must all share one, ``capacities`` whether goals
    carry a count of robots."""

    name: str
    gathers: bool = False
    distinct: bool = False
    capacities: bool = False
    paper: tuple[tuple[str, float], ...] | None = (("max_steps", 100),)
    tasks: bool = False
    joint: bool = False
    study_levels: tuple[str, ...] = _STUDY_LEVELS
    trace_kind: str | None = None
    panels: tuple[str, ...] = GOAL_PANELS

    def __str__(self) -> str:
        return self.name

    def __repr__(self) -> str:
        return f"<mission kind {self.name}>"

    def default_goals(self, robots: int) -> int:
        return robots

    def count(self, robots: int, goals: int, capacities: Sequence[int] | None = None) -> int:
        return count_configurations(self.name, robots, goals, capacities)

    def configurations(
        self, robots: int, goals: int, capacities: Sequence[int] | None = None
    ) -> np.ndarray:
        return valid_configurations(self.name, robots, goals, capacities)

    def holds(
        self,
        positions: np.ndarray,
        goals: np.ndarray,
        radius: float,
        capacities: Sequence[int] | None = None,
    ) -> bool:
        near = within(positions, goals, radius)
        if self.gathers:
            return gathered(near)
        if self.capacities:
            near = np.repeat(near, np.asarray(capacities, dtype=int), axis=1)
        return matched(near)

    def cheapest(
        self,
        cost: np.ndarray,
        goals: np.ndarray,
        capacities: Sequence[int] | None = None,
        robot: int | None = None,
    ) -> np.ndarray:
        row = np.full(cost.shape[0], -1)
        if self.gathers:
            row[:] = goals[np.argmin(cost.sum(axis=0))]
            return row
        if self.capacities:
            slots = np.repeat(np.arange(len(goals)), np.asarray(capacities)[goals])
            cost, goals = cost[:, slots], goals[slots]
        robots, columns = linear_sum_assignment(cost)
        row[robots] = goals[columns]
        if robot is not None and row[robot] < 0:
            row[robot] = goals[np.argmin(cost[robot])]
        return row

    def admits(self, pins: dict[int, int], goal: int) -> bool:
        if self.gathers:
            return not pins or goal in pins.values()
        if self.distinct:
            return goal not in pins.values()
        return True


RENDEZVOUS = GoalKind("rendezvous", gathers=True)
ALLOCATION = GoalKind("allocation", distinct=True)
CAPACITY = GoalKind("capacity", capacities=True, paper=None)
