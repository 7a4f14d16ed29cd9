"""The sweep every robot of a collaborative mission follows while it has nothing better to
do, and where a robot meets a teammate on it (:mod:`epistemica.sim.policies.collaborative_levels`).

The sweep is a convention every robot knows: lanes (a boustrophedon) at most ``factor``
sensing ranges apart, each robot starting at a lane of its own. So a robot that knows a
teammate is still sweeping (it knows of no task that teammate could be going to) can
predict where that teammate is, and where to meet it: :func:`meeting_point`.

Examples
--------
>>> lanes(40.0, 8.0, 1.6)                      # at most 12.8 m apart: four lanes
array([ 5., 15., 25., 35.])
>>> lane = Route(np.array([[5.0, 0.0], [5.0, 30.0]]))
>>> lane.at(12.0).tolist()
[5.0, 12.0]
>>> # from (15, 20), 1 m a step, to meet a teammate going up the lane from (5, 0): the
>>> # first tau with sqrt(10**2 + (20 - tau)**2) <= tau is 13 (500 <= 40 tau)
>>> meeting_point(np.array([15.0, 20.0]), 1.0, lane, 0.0, 1.0, reach=0.0, horizon=40)
(13, array([ 5., 13.]))
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Route", "lanes", "meeting_point", "sweep"]


def lanes(workspace: float, sensing_range: float, factor: float) -> np.ndarray:
    """Centres of the sweep's lanes: as few as leave them at most ``factor`` sensing
    ranges apart, evenly spaced."""
    count = max(1, math.ceil(workspace / (factor * sensing_range) - 1e-9))
    spacing = workspace / count
    return spacing / 2 + spacing * np.arange(count)


def sweep(scenario, robot: int, factor: float) -> np.ndarray:
    """Robot ``robot``'s sweep: waypoints ``(k, 2)``, lanes in turn from its own, cyclic."""
    w, r = scenario.workspace, scenario.sensing_range
    xs = lanes(w, r, factor)
    low = min(w / (2 * len(xs)), w / 2)
    count, n = len(xs), scenario.n_robots
    first = (robot * count) // n
    up = robot % 2 == 0
    points = []
    travel = scenario.max_steps * float(scenario.max_speed[robot])
    laps = 2 + int(travel // max(count * w, 1.0))
    for k in range(count * laps):
        x = xs[(first + k) % count]
        ends = [(x, low), (x, w - low)] if up else [(x, w - low), (x, low)]
        points.extend(ends)
        up = not up
    return np.array(points)


class Route:
    """A polyline with arc-length look-ups (a teammate's predicted sweep)."""

    def __init__(self, points: np.ndarray) -> None:
        self.points = points
        seg = np.diff(points, axis=0)
        self.lengths = np.hypot(seg[:, 0], seg[:, 1])
        self.cumulative = np.concatenate([[0.0], np.cumsum(self.lengths)])

    def along(self, s) -> np.ndarray:
        """``(k, 2)`` the points at arc lengths ``s`` (clipped to the route)."""
        s = np.clip(np.atleast_1d(np.asarray(s, dtype=float)), 0.0, self.cumulative[-1])
        return np.column_stack(
            [
                np.interp(s, self.cumulative, self.points[:, 0]),
                np.interp(s, self.cumulative, self.points[:, 1]),
            ]
        )

    def at(self, s: float) -> np.ndarray:
        """The point at arc length ``s``."""
        return self.along(s)[0]

    def _nearest(self, point: np.ndarray) -> tuple[int, float, float]:
        a, b = self.points[:-1], self.points[1:]
        d = b - a
        length2 = np.maximum((d**2).sum(axis=1), 1e-12)
        u = np.clip(((point - a) * d).sum(axis=1) / length2, 0.0, 1.0)
        gap = np.hypot(*(a + u[:, None] * d - point).T)
        k = int(np.argmin(gap))
        return k, float(u[k]), float(gap[k])

    def gap(self, point: np.ndarray) -> float:
        """Distance from ``point`` to the route."""
        return self._nearest(point)[2]

    def project(self, point: np.ndarray) -> float:
        """Arc length of the point of the route nearest ``point`` (first lap)."""
        k, u, _ = self._nearest(point)
        return float(self.cumulative[k] + u * self.lengths[k])


def meeting_point(
    here: np.ndarray,
    speed: float,
    route: Route,
    s_now: float,
    their_speed: float,
    reach: float,
    horizon: int,
) -> tuple[int, np.ndarray] | None:
    """Where a robot at ``here`` (moving ``speed`` m a step) first comes within ``reach``
    of a teammate that is at arc length ``s_now`` of ``route`` and moves on along it at
    ``their_speed``: ``(steps, the teammate's place then)``, the earliest step count
    ``tau <= horizon`` with ``|here - p(tau)| - reach <= tau * speed``; None if there is
    none (it cannot catch up within ``horizon`` steps).
    """
    tau = np.arange(horizon + 1)
    places = route.along(s_now + tau * their_speed)
    gap = np.hypot(*(places - here).T) - reach
    ok = np.flatnonzero(gap <= tau * speed)
    if ok.size == 0:
        return None
    return int(ok[0]), places[ok[0]]
