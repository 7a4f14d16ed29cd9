"""Joining teammates settled at a goal the robot does not know (``plan_join``; rendezvous).

A robot reasons over the goals it knows. In rendezvous with private goals the team can
split between goals whose knowers do not overlap: traced on tuning mission asymmetry 97
(docs/aif.md §6g), r1 knew g2 and g3 and waited at g3 while r2 and r4, who did not know
g3, waited at g4 (r3 joined them), which r1 did not know, behind a wall, to the step
limit. Nobody searched (the search is for teams with a sensing range) and no plan had an
option to go to g4. Yet r1 observed them settle there (an event's ``sees`` is the sensing
range; the sensor, which would have shown it the goal, needs the line of sight): the settle
names the goal, and the sighting places them. So a robot standing on a goal that sees more
teammates settle at one goal it does not know than itself and those it sees settle with it
(equal groups: the one with the lowest-numbered robot stays) goes, after ``patience``
steps of seeing it, to where it places them, with that goal as its focal one (the simulator
drives round walls to it); within discovery range it learns the goal, and its plan takes
over from there.
"""

from __future__ import annotations

import numpy as np

from epistemica.sim.engine.events import STILL
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Observations

__all__ = ["Joining"]


class Joining:
    """Per robot, the unknown goal it is joining teammates at (``plan_join``).

    Examples
    --------
    Three robots; r2 and r3 stand on g1, which r1 does not know, and r1 stands on g2:

    >>> from epistemica.sim import Scenario
    >>> s = Scenario.paper("rendezvous", 3, 2, seed=0)
    >>> joining = Joining(s, patience=2)
    >>> poses = np.zeros((3, 3, 3))
    >>> poses[:, 0, :2], poses[:, 1:, :2] = s.goals[1], s.goals[0]
    >>> known = np.array([[False, True], [True, True], [True, True]])
    >>> settles = np.array([[-1, 0, 0], [1, -1, 0], [1, 0, -1]])
    >>> def step(k):
    ...     seen = np.ones((3, 3), bool)
    ...     return Observations(k, poses, seen, np.full((3, 3), k), known, ~known, None, settles)
    >>> [joining.target(step(k), 0) is not None for k in range(4)]  # stands, waits, goes
    [False, False, True, True]
    >>> [joining.target(step(k), 1) is None for k in range(4)]  # it knows g2: its plan decides
    [True, True, True, True]
    """

    def __init__(self, scenario: Scenario, patience: int) -> None:
        n = scenario.n_robots
        self.scenario, self.patience = scenario, int(patience)
        self.last = np.full((n, 2), np.nan)  # each robot's own position at its last step
        self.count = np.zeros(n, dtype=int)  # steps it stood seeing such a group
        self.goal = np.full(n, -1)  # the unknown goal it heads for (-1: none)
        self.where = np.zeros((n, 2))  # where it saw the teammates there

    def target(self, observations: Observations, robot: int) -> np.ndarray | None:
        """Where ``robot`` drives to join teammates at a goal it does not know, or
        ``None`` (its plan decides)."""
        s, settles = self.scenario, observations.settles
        pose = observations.poses[robot, robot, :2]
        still = np.hypot(*(pose - self.last[robot])) < STILL
        self.last[robot] = pose
        if settles is None or self.patience <= 0 or not s.kind.gathers:
            return None
        known = observations.known_goals[robot]
        if self.goal[robot] >= 0 and known[self.goal[robot]]:
            self.goal[robot] = -1  # found it: the plan knows the goal now
        at = settles[robot].copy()
        at[robot] = -1
        unknown = (at >= 0) & ~known[np.maximum(at, 0)]
        if unknown.any():
            goal = np.bincount(at[unknown]).argmax()
            there = np.flatnonzero(at == goal)
            if self.goal[robot] == goal:  # refresh where they stand
                self.where[robot] = observations.poses[robot, there, :2].mean(axis=0)
            elif self._outnumbered(observations, robot, there, still):
                self.count[robot] += 1
                if self.count[robot] >= self.patience:
                    self.goal[robot] = goal
                    self.where[robot] = observations.poses[robot, there, :2].mean(axis=0)
            else:
                self.count[robot] = 0
        elif self.goal[robot] < 0:
            self.count[robot] = 0
        if self.goal[robot] < 0:
            return None
        if np.hypot(*(self.where[robot] - pose)) <= s.success_radius:
            self.goal[robot], self.count[robot] = -1, 0  # there, and still unknown: give up
            return None
        return self.where[robot]

    def _outnumbered(self, observations: Observations, robot: int, there, still) -> bool:
        """Whether the robot stands still on a goal and the teammates in ``there`` are
        more than it and those it sees settle with it (ties: the lower-numbered group
        stays)."""
        s, pose = self.scenario, observations.poses[robot, robot, :2]
        d = np.hypot(*(s.goals - pose).T)
        if not still or d.min() > s.success_radius:
            return False
        at = observations.settles[robot].copy()
        at[robot] = int(d.argmin())
        group = np.flatnonzero(at == at[robot])  # itself and those it sees settle with it
        if there.size != group.size:
            return there.size > group.size
        return int(there.min()) < int(group.min())
