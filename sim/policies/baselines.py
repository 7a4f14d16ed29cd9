"""The simple rules every claim is measured against: greedy and a shared convention.

- :class:`Greedy` (level ``"zero"``): drive to the nearest goal the robot knows of
  (multitask: the nearest task it does not know to be done), ignoring the others.
- :class:`Stationary` (level ``"stationary"``): an ad hoc teammate that stops on one goal,
  drawn at random from those it knows at its first step, and never leaves it.
- :class:`Convention`: every step, from the robot's own observations, the configuration of
  least total distance over the valid set (rendezvous: the goal minimising the summed
  distance; allocation, multitask: an optimal assignment; capacity: an optimal assignment
  to goal slots), then drive straight to its own part. Memoryless, no belief: when all
  robots see nearly the same scene they compute nearly the same configuration.

Both drive straight (turn to face the target, then move), not on a control grid.

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> s = Scenario("allocation", [[0, 0, 0], [20, 0, 0]], [[2, 0], [18, 0]], ["range"] * 2)
>>> simulate(s, "convention", seed=0).success
True
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine.missions import distances
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.goal import ALLOCATION
from epistemica.sim.policies.policy import Decisions, Policy, steer

__all__ = ["Convention", "Greedy", "Stationary", "Straight", "open_goals"]


def open_goals(scenario, observations: Observations, robot: int) -> np.ndarray:
    """Indices of the goals ``robot`` knows of and does not know are done (closed)."""
    return np.flatnonzero(observations.known_goals[robot] & ~observations.known_done[robot])


class Straight(Policy):
    """A level that picks a configuration per robot and steers straight to its part: a
    subclass gives :meth:`configuration` (the baselines here, the oracle)."""

    def decide(self, observations: Observations, robots: np.ndarray) -> Decisions:
        s = self.scenario
        self._knowledge = observations.knowledge
        focal = np.full((len(robots), s.n_robots), -1)
        targets = np.empty((len(robots), 2))
        for row, robot in enumerate(robots):
            view = observations.poses[robot]
            goals = open_goals(s, observations, robot)
            if goals.size == 0:  # nothing known: hold position
                targets[row] = view[robot, :2]
                continue
            focal[row] = self.configuration(view, goals, robot)
            own = focal[row, robot]
            targets[row] = s.goals[own] if own >= 0 else view[robot, :2]
        poses = observations.poses[robots, robots]
        controls = steer(poses, targets, s.max_speed[robots], s.max_turn[robots], s.dt)
        return Decisions.of(controls, focal)

    def configuration(self, view: np.ndarray, goals: np.ndarray, robot: int) -> np.ndarray:
        raise NotImplementedError


class Greedy(Straight):
    """Level ``"zero"``: the nearest known goal; the others are not modelled."""

    name = "zero"

    def configuration(self, view, goals, robot):
        row = np.full(view.shape[0], -1)
        row[robot] = goals[
            np.argmin(distances(view[robot : robot + 1], self.scenario.goals[goals])[0])
        ]
        return row


class Stationary(Straight):
    """Level ``"stationary"``: one goal, drawn from the robot's policy stream among those it
    knows at its first step, driven to and never left (a teammate that stopped on a goal,
    whatever the team does).

    Examples
    --------
    >>> from epistemica.sim import Scenario, simulate
    >>> s = Scenario("rendezvous", [[0, 0, 0], [20, 0, 0]], [[2, 0], [18, 0]], ["range"] * 2)
    >>> t = simulate(s, "stationary", seed=3)
    >>> t.success == bool(t.focal[-1, 0, 0] == t.focal[-1, 1, 1])
    True
    """

    name = "stationary"

    def start(self, scenario, robots, generators) -> None:
        super().start(scenario, robots, generators)
        self._goal: dict[int, int] = {}

    def configuration(self, view, goals, robot):
        if robot not in self._goal:
            self._goal[robot] = int(goals[self.generators[robot].integers(goals.size)])
        row = np.full(view.shape[0], -1)
        row[robot] = self._goal[robot]
        return row


class Convention(Straight):
    """Least total distance over the valid configurations, from the robot's own view.

    Parameters
    ----------
    tie_break : {"index", "reverse"}
        Which of equally good configurations wins: scipy's order over goals as given, or
        over goals in reverse order (a teammate with a different convention).
    """

    name = "convention"

    def __init__(self, tie_break: str = "index") -> None:
        if tie_break not in ("index", "reverse"):
            raise InvalidArgumentError(
                f"unknown tie_break {tie_break!r}", hint="use 'index' or 'reverse'"
            )
        self.tie_break = tie_break
        if tie_break != "index":
            self.name = f"convention-{tie_break}"

    def configuration(self, view, goals, robot):
        s = self.scenario
        knowledge = getattr(self, "_knowledge", None)
        constrained = knowledge is not None and knowledge.constrains((robot,))
        pins: dict[int, int] = {}
        kind = s.kind
        if not (kind.capacities or kind.tasks) and s.valid is None and constrained:
            if not knowledge.told((robot,)):  # settles only: pin, no table to enumerate
                pins = _pins(kind, knowledge.settled((robot,)), goals)
                constrained = False
        if not kind.tasks and (s.valid is not None or constrained):
            row = self._tabled(view, goals, robot, knowledge)
            if row is not None:
                return row
        if pins:
            return self._pinned(view, goals, robot, pins)
        if self.tie_break == "reverse":
            goals = goals[::-1]
        cost = distances(view[:, :2], s.goals[goals])  # (n, m')
        # more robots than goals: the unassigned one takes its nearest
        if kind.tasks:  # multitask: the tasks chosen now, one robot each
            return ALLOCATION.cheapest(cost, goals, robot=robot)
        return kind.cheapest(cost, goals, s.capacities, robot=robot)

    def _pinned(self, view, goals, robot, pins: dict[int, int]) -> np.ndarray:
        """Least total distance with the settled robots at their goals: the others take
        the least-cost assignment to the goals left (rendezvous: the pinned goal)."""
        s = self.scenario
        row = np.full(view.shape[0], -1)
        if s.kind.gathers:
            row[:] = next(iter(pins.values()))
            return row
        for r, g in pins.items():
            row[r] = g
        free_robots = np.array([r for r in range(view.shape[0]) if r not in pins])
        free_goals = np.array([g for g in goals if g not in pins.values()])
        if free_robots.size and free_goals.size:
            if self.tie_break == "reverse":
                free_goals = free_goals[::-1]
            cost = distances(view[free_robots, :2], s.goals[free_goals])
            rs, cs = linear_sum_assignment(cost)
            row[free_robots[rs]] = free_goals[cs]
            if row[robot] < 0:
                row[robot] = free_goals[np.argmin(cost[np.flatnonzero(free_robots == robot)[0]])]
        elif row[robot] < 0 and free_goals.size == 0:
            row[robot] = goals[np.argmin(distances(view[robot : robot + 1, :2], s.goals[goals])[0])]
        return row

    def _tabled(self, view, goals, robot, knowledge) -> np.ndarray | None:
        """Least total distance over an explicit table of valid configurations, pruned by
        what the robot knows; None when nothing in it uses only goals it knows of."""
        s = self.scenario
        rows = s.configurations()
        usable = np.isin(rows, goals).all(axis=1)
        if knowledge is not None:
            usable &= knowledge.possible((robot,), rows)
        if not usable.any():
            return None
        rows = rows[usable]
        cost = distances(view[:, :2], s.goals)
        total = cost[np.arange(rows.shape[1]), rows].sum(axis=1)
        best = np.flatnonzero(total <= total.min() + 1e-9)
        return rows[best[-1] if self.tie_break == "reverse" else best[0]].copy()


def _pins(kind: MissionKind, settled: list[tuple[int, int]], goals: np.ndarray) -> dict[int, int]:
    """Settled robots and their goals, newest first, keeping what is consistent with the
    mission (as TeamKnowledge.possible revises: the newest wins)."""
    known = set(goals.tolist())
    pins: dict[int, int] = {}
    for robot, goal in settled:
        if goal not in known or robot in pins:
            continue
        if not kind.admits(pins, goal):
            continue
        pins[robot] = goal
    return pins
