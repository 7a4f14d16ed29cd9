"""The common view: which poses a robot's team prior is computed from.

A robot that sees every teammate computes the team prior from its own estimates. One with a
teammate out of sight switches, at the nested levels with ``common_view``, to a view every
teammate can share: the team's poses at the last step it saw the whole team in sight of each
other (``remember_sight``), or else every robot at the centre of the workspace. The switch
follows sight only once a change has lasted ``sight_hysteresis`` steps, so a robot at the
edge of sight does not flip every step (see
:class:`~epistemica.sim.policies.parameters.ActiveParameters`).

Examples
--------
>>> from types import SimpleNamespace
>>> from epistemica.sim import ActiveParameters, Scenario
>>> s = Scenario("rendezvous", [[3.0, 3.0], [9.0, 3.0]], [[5.0, 5.0]], ["range"] * 2)
>>> view = CommonView(s, ActiveParameters(remember_sight=False), order=3)
>>> poses = np.broadcast_to(s.starts, (2, 2, 3)).copy()
>>> view.follow(SimpleNamespace(step=0, poses=poses, seen=np.eye(2, dtype=bool)), [0, 1])
>>> view.private(0), view.views(SimpleNamespace(poses=poses), [0])[0, :, :2].tolist()
(False, [[15.0, 15.0], [15.0, 15.0]])
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.parameters import ActiveParameters

__all__ = ["CommonView"]


class CommonView:
    """Each robot's common-view switch and its memory of the team last seen together."""

    def __init__(self, scenario, parameters: ActiveParameters, order: int) -> None:
        n = scenario.n_robots
        self.scenario, self.parameters, self.order = scenario, parameters, order
        # The switch of each robot (True: teammates out of sight), the steps its sight has
        # disagreed with it, and the step it was last advanced.
        self.blind = np.zeros(n, dtype=bool)
        self.unsteady = np.zeros(n, dtype=int)
        self.advanced = np.full(n, -1)
        # Each robot's estimate of the team's poses at the last step it saw the whole team
        # in sight of each other (``remember_sight``).
        self.team_sight: dict[int, np.ndarray] = {}

    def follow(self, observations: Observations, robots: Sequence[int]) -> None:
        """Advance each robot's switch by this step's sight (once per step)."""
        step, k = observations.step, self.parameters.sight_hysteresis
        for robot in robots:
            if self.advanced[robot] == step:
                continue
            blind = not observations.seen[robot].all()
            if self.advanced[robot] < 0 or blind == self.blind[robot]:
                self.blind[robot], self.unsteady[robot] = blind, 0
            else:
                self.unsteady[robot] += 1
                if self.unsteady[robot] >= k:
                    self.blind[robot], self.unsteady[robot] = blind, 0
            self.advanced[robot] = step
        p = self.parameters
        if p.remember_sight and p.common_view and self.order >= 2:  # only views() reads it
            self._remember(observations, [r for r in robots if observations.seen[r].all()])

    def _remember(self, observations: Observations, seeing: list) -> None:
        """Keep the estimates of each robot of ``seeing`` (it sees every teammate) whose
        estimates put every pair of robots within the sensing range: the whole team in
        sight of each other."""
        reach = self.scenario.sensing_range
        if not seeing or reach is None:
            return
        x = observations.poses[seeing][..., :2]  # (R, n, 2)
        gaps = x[:, :, None] - x[:, None]  # (R, n, n, 2)
        together = (np.hypot(gaps[..., 0], gaps[..., 1]) <= reach).all(axis=(1, 2))
        for robot, whole in zip(seeing, together, strict=True):
            if whole:
                self.team_sight[robot] = observations.poses[robot].copy()

    def private(self, robot: int) -> bool:
        """Whether the robot may use what it privately reads of its teammates: not while
        the team coordinates on the common view (some teammate out of its sight)."""
        return not (self.parameters.common_view and self.blind[robot])

    def views(self, observations: Observations, robots: Sequence[int]) -> np.ndarray:
        """``(R, n, 3)`` the poses each robot's team prior is computed from."""
        views = observations.poses[list(robots)]
        if self.order < 2 or not self.parameters.common_view:
            return views
        blind = self.blind[list(robots)]
        if blind.any():
            views = views.copy()
            for j in np.flatnonzero(blind):
                remembered = self.team_sight.get(int(robots[j]))
                if remembered is None:
                    views[j, :, :2] = self.scenario.workspace / 2
                else:
                    views[j] = remembered
        return views
