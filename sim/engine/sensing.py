"""What each robot perceives: noisy teammates, goals it knows, tasks it has seen done.

Each step every robot draws the same amount of noise from its own stream whatever it
ends up seeing, so the noise of step ``t`` is the same for every reasoning level.

Observation models (``Scenario.observation``):

- ``"paper"``: robot ``i`` receives every other robot's position plus ``N(0, σ²)`` per
  axis (``σ² = position_noise``); its own pose is exact.
- ``"honest"``: a range robot measures range (``N(0, position_noise)``) and bearing
  (``N(0, angle_noise)``) and places the teammate there; a bearing robot measures the
  bearing only and keeps, along the new ray, the range of its previous estimate
  (a bearing-only tracker: the angle is what was measured, the range is a remembered
  guess, a quarter of the workspace until anything better is known).

Both are :class:`~epistemica.sim.engine.dynamics.Sensor` implementations
(:mod:`epistemica.sim.engine.dynamics`); a scenario may bring its own.

A teammate beyond ``sensing_range``, or hidden behind an obstacle, is not observed: its
estimate stays where it was last seen (the workspace centre if never), and ``seen`` says so.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.engine.missions import distances
from epistemica.sim.engine.obstacles import line_of_sight
from epistemica.sim.engine.scenario import Scenario

__all__ = ["Observations", "Sensing"]


class Observations(NamedTuple):
    """What the whole team perceives at one step; row ``i`` is robot ``i``'s view.

    Attributes
    ----------
    step : int
        The step (0 is the start).
    poses : numpy.ndarray
        ``(n, n, 3)``: robot ``i``'s estimate of every pose, its own exact.
    seen : numpy.ndarray
        ``(n, n)`` booleans: robot ``j`` was observed by ``i`` at this step.
    last_seen : numpy.ndarray
        ``(n, n)`` step at which ``i`` last observed ``j`` (-1: never).
    known_goals : numpy.ndarray
        ``(n, m)`` booleans: the goals (tasks) robot ``i`` knows of.
    known_done : numpy.ndarray
        ``(n, m)`` booleans: the goals robot ``i`` knows are closed (tasks done).
    knowledge : TeamKnowledge or None
        The facts each robot (and each chain of robots) learnt from observation events
        (:mod:`epistemica.sim.engine.knowledge`); read it, never change it. ``known_goals`` and
        ``known_done`` include what each robot learnt from events (a goal revealed, a
        task seen done by a teammate's completion).
    settles : numpy.ndarray or None
        ``(n, n)``: the goal at which robot ``i`` saw robot ``j`` settle at this step (an
        observation event suggesting ``assigned(j, g)``, such as ``settle``, that ``i``
        observed fully), whether or not it taught ``i`` anything new; -1: none. A
        repeated sighting is no news to ``knowledge``, but it says the teammate is
        still there. ``None`` without events.
    """

    step: int
    poses: np.ndarray
    seen: np.ndarray
    last_seen: np.ndarray
    known_goals: np.ndarray
    known_done: np.ndarray
    knowledge: TeamKnowledge | None = None
    settles: np.ndarray | None = None


class Sensing:
    """The perception state of a team during one trial.

    Parameters
    ----------
    scenario : Scenario
    generators : sequence of numpy.random.Generator
        One observation-noise stream per robot.
    """

    def __init__(self, scenario: Scenario, generators) -> None:
        n, m = scenario.n_robots, scenario.n_goals
        self.scenario = scenario
        self.generators = tuple(generators)
        self.sensing_range = np.inf if scenario.sensing_range is None else scenario.sensing_range
        discovery = scenario.discovery_range
        self.discovery_range = discovery if discovery is not None else min(self.sensing_range, 10.0)
        centre = np.array([scenario.workspace / 2, scenario.workspace / 2, 0.0])
        self.estimates = np.broadcast_to(centre, (n, n, 3)).copy()
        self.last_seen = np.full((n, n), -1, dtype=int)
        self.known_goals = (
            np.ones((n, m), dtype=bool)
            if scenario.known_goals is None
            else np.array(scenario.known_goals, dtype=bool)
        )
        self.known_done = np.zeros((n, m), dtype=bool)
        self.sensor = scenario.sensor

    def visible(self, poses: np.ndarray) -> np.ndarray:
        """``(n, n)`` booleans: ``j`` is within ``i``'s sensing range (``i`` sees itself)."""
        d = distances(poses[:, :2], poses[:, :2])
        if self.scenario.obstacles:
            return (d <= self.sensing_range) & line_of_sight(poses[:, :2], self.scenario.obstacles)
        return d <= self.sensing_range

    def observe(self, poses: np.ndarray, step: int, settled=None, closed=None) -> Observations:
        """Perceive the true ``poses`` at ``step``.

        ``settled`` marks robots that have stopped at a goal (teammates who see them
        learn of that goal); ``closed`` the goals closed now (tasks done, doors shut):
        robots within the discovery range of a goal see whether it is closed, and a
        closed goal is not discovered.
        """
        s, n = self.scenario, poses.shape[0]
        noise = np.stack([g.standard_normal((n, 2)) for g in self.generators])  # (n, n, 2)
        seen = self.visible(poses)
        measured = self._measure(poses, noise)
        self.estimates = np.where(seen[..., None], measured, self.estimates)
        idx = np.arange(n)
        self.estimates[idx, idx] = poses  # own pose is exact
        self.last_seen[seen] = step
        near_goal = distances(poses[:, :2], s.goals) <= self.discovery_range
        if s.obstacles:  # a goal behind an obstacle is not seen either
            near_goal &= line_of_sight(poses[:, :2], s.obstacles, s.goals)
        closed = np.zeros(s.n_goals, dtype=bool) if closed is None else np.asarray(closed)
        self.known_goals |= near_goal & ~closed[None, :]
        if settled is not None and np.any(settled):
            at = distances(poses[:, :2], s.goals) <= s.success_radius  # (n, m)
            shown = at & np.asarray(settled)[:, None]
            self.known_goals |= (seen.astype(int) @ shown.astype(int)) > 0
        # What a robot near a goal sees of it is its news: closed, or open again (an
        # event may reopen a goal, :mod:`~epistemica.sim.engine.events`).
        self.known_done = (self.known_done & ~near_goal) | (near_goal & closed[None, :])
        return Observations(
            step,
            self.estimates.copy(),
            seen,
            self.last_seen.copy(),
            self.known_goals.copy(),
            self.known_done.copy(),
        )

    def _measure(self, poses: np.ndarray, noise: np.ndarray) -> np.ndarray:
        return self.sensor.measure(poses, self.estimates, noise, self.scenario)
