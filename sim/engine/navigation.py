"""Driving around known walls: a robot whose straight way to the goal it heads for is
blocked takes the shortest way around the obstacles instead.

A policy decides *where* a robot goes (the goal of the configuration it acts on, its
``Decisions.focal``) and a control towards it; most steer straight. With polygonal
obstacles (a mission's ``obstacle`` lines, known to every robot) a straight control can
push a robot into a wall for the rest of the trial, whatever it decided. The
:class:`Roadmap` is the visibility graph of the obstacles' convex corners, each moved
out along its edges' normals by a ``margin`` (the robots' largest radius plus
:data:`MARGIN`); where a robot moves and its segment to its goal comes closer to an
obstacle than it may (:func:`clear`), :meth:`Roadmap.waypoint` gives the first corner of
the shortest way through the graph and the robot steers for it instead. Decisions are
never changed, only the control that carries them out, and only for a robot that moves:
a policy that waits still waits.

Examples
--------
A wall between a robot and its goal, from the floor up: the way round goes over its top.

>>> from epistemica.sim.engine.obstacles import polygon
>>> wall = polygon([[4, 0], [5, 0], [5, 8], [4, 8]])
>>> roadmap = Roadmap((wall,), margin=0.5, workspace=10.0)
>>> clear(np.array([2.0, 4.0]), np.array([8.0, 4.0]), (wall,), 0.0)
False
>>> roadmap.waypoint(np.array([2.0, 4.0]), np.array([8.0, 4.0])).round(2).tolist()
[3.5, 8.5]
"""

from __future__ import annotations

import numpy as np
from scipy.sparse.csgraph import shortest_path

from epistemica.sim.engine.obstacles import CLEARANCE, segment_distances

__all__ = ["MARGIN", "Roadmap", "clear", "clear_all", "roadmap_for"]

#: Distance (m) beyond a robot's radius at which the roadmap passes obstacles' corners.
MARGIN = 0.5


def clear(start: np.ndarray, end: np.ndarray, obstacles, radius: float) -> bool:
    """Whether a robot of ``radius`` may drive straight from ``start`` to ``end``: the
    segment comes no closer to any obstacle than ``radius`` (and the contacts' clearance),
    or than its ends already are (a robot pressed against a wall may drive away from it)."""
    return bool(clear_all(np.asarray(start)[None], np.asarray(end)[None], obstacles, radius)[0])


def clear_all(starts: np.ndarray, ends: np.ndarray, obstacles, radius: float) -> np.ndarray:
    """``(p,)``: :func:`clear` of each segment ``starts[i] -> ends[i]`` (``(p, 2)`` each)."""
    starts, ends = np.asarray(starts, dtype=float), np.asarray(ends, dtype=float)
    out = np.ones(len(starts), dtype=bool)
    for poly in obstacles:
        at_ends = np.minimum(
            segment_distances(starts, starts, poly), segment_distances(ends, ends, poly)
        )
        allowed = np.minimum(radius + CLEARANCE, at_ends) - 1e-9
        out &= segment_distances(starts, ends, poly) >= allowed
    return out


def _corners(poly: np.ndarray, margin: float) -> np.ndarray:
    """The convex corners of ``poly``, each moved out by ``margin`` from both its edges
    (a mitre, capped at three margins for sharp corners)."""
    area = np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1])
    orientation = 1.0 if area > 0 else -1.0  # counter-clockwise: outward is to the right
    before, after = np.roll(poly, 1, axis=0), np.roll(poly, -1, axis=0)
    out = []
    for p, a, b in zip(poly, before, after, strict=True):
        e1, e2 = p - a, b - p
        if orientation * (e1[0] * e2[1] - e1[1] * e2[0]) <= 0:
            continue  # a reflex (or straight) corner: never on a shortest way round
        n1 = orientation * np.array([e1[1], -e1[0]]) / np.hypot(*e1)
        n2 = orientation * np.array([e2[1], -e2[0]]) / np.hypot(*e2)
        mitre = (n1 + n2) / max(1.0 + float(n1 @ n2), 1.0 / 9.0)
        out.append(p + margin * mitre)
    return np.array(out).reshape(-1, 2)


class Roadmap:
    """The visibility graph of the obstacles' corners, moved out by ``margin``.

    Parameters
    ----------
    obstacles : sequence of (k, 2) arrays
        Validated polygons (:func:`~epistemica.sim.engine.obstacles.polygon`).
    margin : float
        How far from each edge the corners lie (more than any robot's radius).
    workspace : float
        Side of the square workspace: corners outside it are left out.
    """

    def __init__(self, obstacles, margin: float, workspace: float) -> None:
        self.obstacles = tuple(obstacles)
        self.margin = float(margin)
        found = [_corners(poly, self.margin) for poly in self.obstacles]
        nodes = np.concatenate(found) if found else np.zeros((0, 2))
        inside = ((nodes >= 0) & (nodes <= workspace)).all(axis=1)
        # A corner moved out of one obstacle may land in (or next to) another: no robot
        # stands there. (``clear`` exempts a segment's own ends, so it cannot tell.)
        free = np.ones(len(nodes), dtype=bool)
        for poly in self.obstacles:
            free &= segment_distances(nodes, nodes, poly) >= self.margin * 0.99
        self.nodes = nodes[inside & free]
        k = len(self.nodes)
        graph = np.zeros((k, k))
        for i in range(k):
            for j in range(i + 1, k):
                if clear(self.nodes[i], self.nodes[j], self.obstacles, 0.0):
                    graph[i, j] = graph[j, i] = np.hypot(*(self.nodes[i] - self.nodes[j]))
        self.distance = shortest_path(graph, directed=False) if k else np.zeros((0, 0))
        self._sight: dict[tuple, np.ndarray] = {}  # the corners that see a goal

    def _seen_from(self, goal: np.ndarray, radius: float) -> np.ndarray:
        """``(k,)`` which corners a robot of ``radius`` drives straight from to ``goal``
        (goals do not move: kept)."""
        key = (float(goal[0]), float(goal[1]), float(radius))
        if key not in self._sight:
            ends = np.broadcast_to(goal, self.nodes.shape)
            self._sight[key] = clear_all(self.nodes, ends, self.obstacles, radius)
        return self._sight[key]

    def waypoint(self, start: np.ndarray, goal: np.ndarray, radius: float = 0.0):
        """Where a robot of ``radius`` at ``start`` steers for ``goal``: ``goal`` itself
        when the way is clear, else the first corner of the shortest way round (a corner
        it stands on does not count), or None when no way round is known."""
        if clear(start, goal, self.obstacles, radius):
            return goal
        return self._round(start, goal, radius, self._seen_by(start, radius))

    def _seen_by(self, start: np.ndarray, radius: float) -> np.ndarray:
        """``(k,)`` the corners a robot at ``start`` drives straight to (not one it is on)."""
        near = np.hypot(*(self.nodes - start).T) < 1e-3
        starts = np.broadcast_to(start, self.nodes.shape)
        return ~near & clear_all(starts, self.nodes, self.obstacles, radius)

    def _round(self, start: np.ndarray, goal: np.ndarray, radius: float, first: np.ndarray):
        """The first corner of the shortest way round from ``start`` (seeing the corners
        ``first``) to ``goal``, or None."""
        last = self._seen_from(goal, radius)
        if not first.any() or not last.any():
            return None
        to_node = np.where(first, np.hypot(*(self.nodes - start).T), np.inf)
        from_node = np.where(last, np.hypot(*(self.nodes - goal).T), np.inf)
        total = to_node[:, None] + self.distance + from_node[None, :]
        i, j = np.unravel_index(np.argmin(total), total.shape)
        return None if not np.isfinite(total[i, j]) else self.nodes[i]

    def lengths(self, points: np.ndarray, goals: np.ndarray, radius: float = 0.0) -> np.ndarray:
        """``(n, m)``: the length of the shortest way from each of ``points (n, 2)`` to each
        of ``goals (m, 2)`` for a robot of ``radius``: the straight distance where the way
        is clear, round the corners where not, ``inf`` where no way is known.

        Examples
        --------
        >>> from epistemica.sim.engine.obstacles import polygon
        >>> wall = polygon([[4, 0], [5, 0], [5, 8], [4, 8]])
        >>> roadmap = Roadmap((wall,), margin=0.5, workspace=10.0)
        >>> roadmap.lengths(np.array([[2.0, 4.0], [2.0, 9.0]]), np.array([[8.0, 9.0]])).round(2)
        array([[9.27],
               [6.  ]])
        """
        points, goals = np.asarray(points, dtype=float), np.asarray(goals, dtype=float)
        n, m = len(points), len(goals)
        out = np.hypot(*(points[:, None] - goals[None]).transpose(2, 0, 1))
        starts, ends = np.repeat(points, m, axis=0), np.tile(goals, (n, 1))
        straight = clear_all(starts, ends, self.obstacles, radius).reshape(n, m)
        for i in np.flatnonzero(~straight.all(axis=1)):
            first = self._seen_by(points[i], radius)
            to_node = np.where(first, np.hypot(*(self.nodes - points[i]).T), np.inf)
            via = (to_node[:, None] + self.distance).min(axis=0) if len(self.nodes) else to_node
            for g in np.flatnonzero(~straight[i]):
                last = self._seen_from(goals[g], radius)
                from_node = np.where(last, np.hypot(*(self.nodes - goals[g]).T), np.inf)
                out[i, g] = (via + from_node).min() if len(self.nodes) else np.inf
        return out

    def aims(self, points: np.ndarray, goals: np.ndarray, radius: float = 0.0) -> np.ndarray:
        """``(n, m, 2)``: where a robot at each of ``points (n, 2)`` heading for each of
        ``goals (m, 2)`` steers (:meth:`waypoint`; the goal itself where no way round is
        known). A teammate's move is read against these, not against straight lines."""
        points, goals = np.asarray(points, dtype=float), np.asarray(goals, dtype=float)
        out = np.broadcast_to(goals[None], (len(points), *goals.shape)).copy()
        n, m = len(points), len(goals)
        starts, ends = np.repeat(points, m, axis=0), np.tile(goals, (n, 1))
        straight = clear_all(starts, ends, self.obstacles, radius).reshape(n, m)
        for i in np.flatnonzero(~straight.all(axis=1)):  # the corners it sees, once
            first = self._seen_by(points[i], radius)
            for g in np.flatnonzero(~straight[i]):
                aim = self._round(points[i], goals[g], radius, first)
                if aim is not None:
                    out[i, g] = aim
        return out


def roadmap_for(scenario) -> Roadmap | None:
    """The roadmap of a scenario's obstacles, for robots of its largest radius (None
    without obstacles)."""
    if not scenario.obstacles:
        return None
    radius = 0.0 if scenario.robot_radius is None else float(np.max(scenario.robot_radius))
    return Roadmap(scenario.obstacles, radius + MARGIN, scenario.workspace)
