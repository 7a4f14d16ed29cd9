"""Where a teammate never seen can be (``plan_hidden``; docs/aif.md §6g).

A robot that has not seen a teammate knows three things of where it is: it started in the
workspace (outside the obstacles), it drives at most its top speed, and at every step the
robot looked it was not in the robot's sight (beyond its sensing range or behind a wall).
The mission's declared starts are the simulator's, not the robots' (the DEL state holds no
positions; the sensing gives a placeholder, the workspace centre), so none is read here.

:class:`HiddenPlaces` keeps, per robot and teammate, hypotheses ``(start, goal)``: a start
from a fixed low-discrepancy set over the workspace and the goal the teammate drives
straight for since step 0 at its top speed (or none: it stands). A hypothesis whose place
at some step fell in the robot's sight while the teammate was not seen is ruled out. The
planner's draws of the teammate's place are taken from the rest, each weighed by the
softmax of its trip to the goal over the planner's ``tau`` (a planner prefers a near
goal), so a draw's place has moved as far as the elapsed steps allow.
"""

from __future__ import annotations

import numpy as np

from epistemica.aif.plan_context import quasi_uniform
from epistemica.sim.engine.obstacles import inside, line_of_sight
from epistemica.sim.engine.scenario import Scenario

__all__ = ["STAND", "HiddenPlaces", "resample"]

STAND = 0.05  # prior weight of "it stands where it started", against 1 for its goals


def resample(weights: np.ndarray, count: int) -> np.ndarray:
    """``(count,)`` indices into ``weights`` by systematic resampling at the fixed offsets
    ``(d + 1/2) / count``: deterministic, each index about ``count * weight`` times.

    Examples
    --------
    >>> resample(np.array([0.0, 3.0, 1.0]), 4).tolist()
    [1, 1, 1, 2]
    """
    cumulative = np.cumsum(weights) / np.sum(weights)
    offsets = (np.arange(count) + 0.5) / count
    return np.minimum(np.searchsorted(cumulative, offsets), weights.size - 1)


class HiddenPlaces:
    """Hypotheses of where each teammate never seen is, per robot.

    Parameters
    ----------
    scenario : Scenario
        The workspace, obstacles, sensing range, speeds and time step (what every robot
        knows of its mission and its own sensor).
    draws : int
        Places handed to the planner per teammate (``plan_hidden``).
    starts : int or array_like
        Hypothesised starts: that many over the workspace (a Weyl sequence), or ``(P, 2)``.

    Examples
    --------
    One robot at the corner of a 30 m workspace sees 10 m; the other was never seen. At
    step 0 no draw lies within 10 m of it:

    >>> from epistemica.sim import Scenario
    >>> s = Scenario.paper("allocation", 2, 2, seed=0).replace(sensing_range=10.0)
    >>> places = HiddenPlaces(s, 16)
    >>> draws = places.sample(0, np.array([0.0, 0.0]), np.array([False, True]), 0,
    ...                      np.array([0, 1]), tau=5.0)
    >>> draws.shape, bool(np.isnan(draws[:, 0]).all())
    ((16, 2, 2), True)
    >>> bool((np.hypot(*draws[:, 1].T) > 10.0).all())
    True
    """

    def __init__(self, scenario: Scenario, draws: int, starts=256) -> None:
        s = self.scenario = scenario
        self.count = int(draws)
        points = np.asarray(starts, dtype=float)
        if points.ndim == 0:  # a count: spread evenly over the workspace
            points = quasi_uniform(int(starts), 2) * float(s.workspace)
        for poly in s.obstacles:  # no robot starts inside an obstacle
            points = points[~inside(points, np.asarray(poly, dtype=float))]
        self.starts = points
        self.speed = np.asarray(s.max_speed, dtype=float)  # (n,) m/s
        self.reach = self.speed * s.dt  # (n,) metres per step
        self.range = np.inf if s.sensing_range is None else float(s.sensing_range)
        # robot -> (n, P, M + 1) hypotheses not ruled out (last column: it stands)
        self.alive: dict[int, np.ndarray] = {}
        self.checked: dict[int, int] = {}  # robot -> the last step it looked

    def places(self, teammate: int, step: int) -> np.ndarray:
        """``(P, M + 1, 2)`` where each hypothesis puts ``teammate`` at ``step``."""
        goals = np.asarray(self.scenario.goals, dtype=float)
        delta = goals[None] - self.starts[:, None]  # (P, M, 2)
        distance = np.hypot(delta[..., 0], delta[..., 1])
        moved = np.minimum(self.reach[teammate] * step, distance)
        unit = delta / np.maximum(distance, 1e-9)[..., None]
        driving = self.starts[:, None] + moved[..., None] * unit
        return np.concatenate([driving, self.starts[:, None]], axis=1)

    def look(self, robot: int, pose: np.ndarray, never: np.ndarray, step: int) -> None:
        """Rule out what the robot, at ``pose`` (``(2,)``, exact), would see at ``step``
        of each teammate in ``never`` (``(n,)``: not seen so far)."""
        n, m = self.reach.shape[0], len(self.scenario.goals)
        alive = self.alive.setdefault(robot, np.ones((n, len(self.starts), m + 1), dtype=bool))
        if self.checked.get(robot, -1) >= step:
            return
        self.checked[robot] = step
        for j in np.flatnonzero(never):
            if j == robot:
                continue
            at = self.places(int(j), step).reshape(-1, 2)
            seen = np.hypot(*(at - pose).T) <= self.range
            if self.scenario.obstacles and seen.any():
                seen[seen] = line_of_sight(pose[None], self.scenario.obstacles, at[seen])[0]
            alive[j] &= ~seen.reshape(alive[j].shape)

    def draws(self, observations, robot: int, goals, tau: float) -> np.ndarray | None:
        """:meth:`sample` from what ``observations`` (:class:`Observations`) tell ``robot``."""
        never = observations.last_seen[robot] < 0
        at = observations.poses[robot, robot]
        return self.sample(robot, at, never, observations.step, goals, tau)

    def sample(self, robot: int, pose, never, step: int, goals, tau: float) -> np.ndarray | None:
        """``(D, n, 2)`` the planner's draws of where each teammate in ``never`` is at
        ``step`` (``nan`` for the others), after looking from ``pose``; ``goals`` are the
        scenario indices of the robot's table (a goal it does not know is no hypothesis)
        and ``tau`` the planner's precision (s). ``None`` if no teammate is hidden."""
        never = np.array(never, dtype=bool)
        never[robot] = False
        if not never.any() or self.count <= 0 or len(goals) == 0:
            return None
        self.look(robot, np.asarray(pose, dtype=float)[:2], never, step)
        n = self.reach.shape[0]
        out = np.full((self.count, n, 2), np.nan)
        goals = np.asarray(goals, dtype=int)
        columns = np.append(goals, len(self.scenario.goals))  # its goals, then standing
        for j in np.flatnonzero(never):
            trip = np.hypot(*(self.starts[:, None] - self.scenario.goals[goals][None]).T).T
            prior = np.exp(-(trip - trip.min(axis=1, keepdims=True)) / self.speed[j] / tau)
            prior = prior / prior.sum(axis=1, keepdims=True)  # per start: its goal's odds
            prior = np.concatenate([prior, np.full((len(self.starts), 1), STAND)], axis=1)
            weights = (self.alive[robot][j][:, columns] * prior).ravel()
            if not weights.sum() > 0:  # every hypothesis ruled out: the placeholder
                continue
            picked = resample(weights, self.count)
            out[:, j] = self.places(int(j), step)[:, columns].reshape(-1, 2)[picked]
        return None if np.isnan(out).all() else out
