"""Where a robot of a collaborative mission expects each teammate it does not see
(:mod:`epistemica.sim.policies.collaborative_levels`).

Every robot knows the convention: a robot with nothing better to do follows its sweep
(:func:`~epistemica.sim.policies.collaborative_sweep.sweep`), from wherever it is to the waypoint
it was making for, then on along the lanes. So a teammate's place follows from three
things the robot may know:

- **never seen**: it started somewhere in the workspace (uniformly) and made for the
  start of its sweep; every step the robot did not see it rules out the starts that would
  have put it in sight (``particles``, a grid of starts);
- **seen on its sweep**: it went on along it;
- **seen off its sweep and moving** (back from a task, or on its way to the start): it
  makes for the waypoint it was heading to (the one its motion points at), then sweeps on.

It may also have found a task the robot does not know of: that is what ``fetch_memory``
and ``sweep_memory`` bound.

Examples
--------
A 40 m workspace, 10 m sight: two lanes, x = 10 and x = 30; robot 1's sweep starts at
(30, 30) and goes down. Robot 0 stands at (10, 10) and never sees robot 1 for a step:
of the 16 starts of a 4 x 4 grid, only (5, 5), (15, 5), (5, 15) and (15, 15) were in sight.

>>> from types import SimpleNamespace
>>> s = SimpleNamespace(workspace=40.0, sensing_range=10.0, n_robots=2, max_steps=100,
...                     max_speed=np.array([1.0, 1.0]))
>>> model = TeammateModel(s, lane_factor=2.0, particles=4, resume=True)
>>> model.routes[1].points[:2].tolist()
[[30.0, 30.0], [30.0, 10.0]]
>>> poses = np.array([[10.0, 10.0, 0.0], [35.0, 35.0, 0.0]])
>>> model.observe(0, poses, np.zeros((2, 2, 2)), np.array([[0, -1], [-1, 0]]))
>>> int(model.alive[0, 1].sum())
12
"""

from __future__ import annotations

import numpy as np

from epistemica.sim.policies.collaborative_sweep import Route, sweep

__all__ = ["TeammateModel"]


class TeammateModel:
    """What every robot of a team predicts of every teammate's place.

    Parameters
    ----------
    scenario : CollaborativeScenario
        The mission's world (workspace, sensing range, speeds).
    lane_factor : float
        The sweep's lane spacing, in sensing ranges.
    particles : int
        Starts per side of the grid of a never-seen teammate's possible starts (0: it is
        taken to reach its sweep after half the workspace's side).
    resume : bool
        Whether a teammate seen off its sweep and moving is taken to make for the waypoint
        its motion points at (else it is projected onto the nearest point of its sweep).
    motion : (float, float, float)
        ``rejoin_gap``, ``still_fraction``, ``heading_slack`` of
        :class:`~epistemica.sim.policies.collaborative_levels.CollaborativeParameters`.
    """

    def __init__(
        self,
        scenario,
        lane_factor: float,
        particles: int,
        resume: bool,
        motion: tuple[float, float, float] = (1.0, 0.3, 0.01),
    ) -> None:
        s, n = scenario, scenario.n_robots
        self.s, self.resume_on = s, resume
        # what a teammate seen shows of its way back to its sweep (CollaborativeParameters:
        # rejoin_gap, still_fraction, heading_slack)
        self.rejoin_gap, self.still_fraction, self.heading_slack = motion
        self.routes = [Route(sweep(s, j, lane_factor)) for j in range(n)]
        self.resume = np.full((n, n), -1)  # waypoint i saw j make for, off its sweep
        self.prev_estimates = np.zeros((n, n, 2))
        self.prev_seen = np.full((n, n), -1)
        cells = (np.arange(particles) + 0.5) * s.workspace / max(particles, 1)
        self.starts = np.stack(np.meshgrid(cells, cells), axis=-1).reshape(-1, 2)
        self.alive = np.ones((n, n, len(self.starts)), dtype=bool)
        self.legs = [np.hypot(*(route.points[0] - self.starts).T) for route in self.routes]
        self._places: dict[tuple, np.ndarray] = {}  # (teammate, step) -> its hypotheses

    # -- hypotheses of a never-seen teammate ------------------------------------------

    def _hypotheses(self, j: int, step: float) -> np.ndarray:
        """``(g, 2)`` where teammate ``j`` is at ``step`` from each start of the grid
        (computed once per teammate and step: every robot's prediction reads it)."""
        key = (j, step)
        if key not in self._places:
            if len(self._places) > 4 * self.s.n_robots:  # only the current step is read
                self._places.clear()
            self._places[key] = self._unseen_places(j, step)
        return self._places[key]

    def _unseen_places(self, j: int, step: float) -> np.ndarray:
        travel, legs = step * self.s.max_speed[j], self.legs[j]
        route = self.routes[j]
        on_leg = travel < legs
        heading = route.points[0] - self.starts
        frac = np.where(on_leg, travel / np.maximum(legs, 1e-9), 1.0)[:, None]
        swept = route.along(np.maximum(travel - legs, 0.0))
        return np.where(on_leg[:, None], self.starts + frac * heading, swept)

    def possible(self, step: float, i: int, j: int) -> np.ndarray:
        """``(g, 2)`` where never-seen teammate ``j`` is at ``step`` from each start robot
        ``i`` has not ruled out (empty without particles, or with none left)."""
        if not len(self.starts):
            return np.zeros((0, 2))
        return self._unseen_places(j, step)[self.alive[i, j]]

    def spread(self, step: float, i: int, j: int, place) -> float:
        """The share of never-seen teammate ``j``'s starts robot ``i`` has not ruled out
        that put ``j`` in sight of ``place`` at ``step``: the chance an intercept there
        finds it, if it is on its sweep (1 with no start left: the plain guess).

        Examples
        --------
        A 40 m workspace, 10 m sight, a 2 x 2 grid of starts; at step 0 robot 1 is still
        at its start, and only (10, 10) is in sight of (12, 12):

        >>> from types import SimpleNamespace
        >>> s = SimpleNamespace(workspace=40.0, sensing_range=10.0, n_robots=2,
        ...                     max_steps=100, max_speed=np.array([1.0, 1.0]))
        >>> model = TeammateModel(s, lane_factor=2.0, particles=2, resume=True)
        >>> model.possible(0, 0, 1).tolist()
        [[10.0, 10.0], [30.0, 10.0], [10.0, 30.0], [30.0, 30.0]]
        >>> model.spread(0, 0, 1, (12.0, 12.0))
        0.25
        """
        places = self.possible(step, i, j)
        if not len(places):
            return 1.0
        gap = np.hypot(*(places - np.asarray(place, dtype=float)).T)
        return float(np.mean(gap <= self.s.sensing_range))

    def observe(self, step: int, poses: np.ndarray, estimates, last_seen) -> None:
        """Update from what each robot sees at ``step`` (its own row of ``estimates``
        and ``last_seen``; ``poses`` read for a robot's own place only)."""
        n, r = self.s.n_robots, self.s.sensing_range
        if len(self.starts):
            for j in range(n):
                unseen = last_seen[:, j] < 0
                if not unseen.any():
                    continue
                places = self._hypotheses(j, step)
                gap = np.hypot(*(places[None] - poses[:, None, :2]).transpose(2, 0, 1))
                self.alive[unseen, j] &= gap[unseen] > r
        if self.resume_on:
            for i, j in zip(*np.nonzero(last_seen == step), strict=True):
                if i != j:
                    self._note_resume(step, i, j, estimates[i, j])
        self.prev_estimates = estimates.copy()
        self.prev_seen = last_seen.copy()

    def _note_resume(self, step: int, i: int, j: int, here: np.ndarray) -> None:
        """The waypoint robot ``i`` sees teammate ``j`` make for (off its sweep, moving)."""
        route = self.routes[j]
        if route.gap(here) <= self.rejoin_gap:
            self.resume[i, j] = -1
            return
        if self.prev_seen[i, j] != step - 1:
            return
        motion = here - self.prev_estimates[i, j]
        if np.hypot(*motion) < self.still_fraction * self.s.max_speed[j]:
            return  # standing (at a task): where it goes next is not shown
        to = route.points - here
        cos = (to @ motion) / np.maximum(np.hypot(*to.T) * np.hypot(*motion), 1e-9)
        ahead = np.flatnonzero(cos >= cos.max() - self.heading_slack)  # later laps too
        expected = self._nominal(step, j)
        self.resume[i, j] = int(ahead[np.argmin(np.abs(route.cumulative[ahead] - expected))])

    def _nominal(self, step: float, j: int) -> float:
        speed = self.s.max_speed[j]
        return (step - 0.5 * self.s.workspace / speed) * speed

    # -- predictions --------------------------------------------------------------------

    def arc(self, step: int, i: int, j: int, estimate, seen: int) -> float:
        """Arc length of teammate ``j``'s sweep where robot ``i`` expects it at ``step``
        (``estimate``: where ``i`` last saw it, at step ``seen``, -1 never)."""
        speed, route = self.s.max_speed[j], self.routes[j]
        if seen < 0:
            alive = self.alive[i, j]
            if not alive.any():  # it left its sweep (a task): the plain guess
                return self._nominal(step, j)
            return float(np.median(step * speed - self.legs[j][alive]))
        k = self.resume[i, j]
        if k >= 0:  # making for waypoint k: there after the leg, then on along the sweep
            leg = np.hypot(*(route.points[k] - estimate))
            return route.cumulative[k] + (step - seen) * speed - leg
        return route.project(estimate) + (step - seen) * speed

    def place(self, step: int, i: int, j: int, estimate, seen: int) -> np.ndarray:
        """Where robot ``i`` expects teammate ``j`` at ``step``."""
        route, speed = self.routes[j], self.s.max_speed[j]
        if seen < 0 and self.alive[i, j].any():
            places = self._hypotheses(j, step)[self.alive[i, j]]
            centre = places.mean(axis=0)  # the possible place nearest the mean
            return places[np.argmin(np.hypot(*(places - centre).T))]
        k = self.resume[i, j]
        if seen >= 0 and k >= 0:
            leg = route.points[k] - estimate
            length, travel = np.hypot(*leg), (step - seen) * speed
            if travel < length:
                return estimate + leg * (travel / length)
        return route.at(self.arc(step, i, j, estimate, seen))
