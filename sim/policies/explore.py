"""Searching for goals a robot does not know: the nearest unvisited cell of a grid.

A robot that knows too few goals for any valid configuration (private goals) cannot plan
a configuration; it discovers goals by coming within the discovery range of them. It
sweeps the workspace: a grid of cell centres one discovery range apart, each marked
visited once the robot has come within half that distance of it; its target is the
nearest centre it has not visited. When every centre is visited it falls back to the
convention on what it knows.

Examples
--------
>>> import numpy as np
>>> e = Explorer(workspace=30.0, spacing=10.0, n_robots=1)
>>> e.centres.shape
(9, 2)
>>> e.visit(np.array([[5.0, 5.0]]))
>>> e.target(0, np.array([5.0, 5.0])).tolist()  # (5, 5) is done: a neighbour is next
[5.0, 15.0]
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Explorer"]

#: Most cells per side of the grid.
MAX_CELLS = 32


class Explorer:
    """Per robot, the cells of the workspace it has swept.

    Parameters
    ----------
    workspace : float
        Side of the square workspace.
    spacing : float
        Distance between cell centres (the discovery range: a robot at a centre discovers
        every goal within ``spacing`` of it).
    n_robots : int
    """

    def __init__(self, workspace: float, spacing: float, n_robots: int) -> None:
        # At most MAX_CELLS per side: a huge workspace is swept coarsely, never enumerated.
        count = min(max(1, math.ceil(workspace / max(spacing, 1e-9))), MAX_CELLS)
        ticks = (np.arange(count) + 0.5) * workspace / count
        xs, ys = np.meshgrid(ticks, ticks, indexing="ij")
        self.centres = np.column_stack([xs.ravel(), ys.ravel()])
        self.radius = 0.5 * workspace / count
        self.visited = np.zeros((n_robots, len(self.centres)), dtype=bool)

    def visit(self, positions: np.ndarray, robots=None) -> None:
        """Mark the centres near the ``(r, 2)`` positions of ``robots`` (default all)."""
        robots = np.arange(self.visited.shape[0]) if robots is None else np.asarray(robots)
        d = np.hypot(*(positions[:, None, :2] - self.centres[None]).transpose(2, 0, 1))
        self.visited[robots] |= d <= self.radius

    def target(self, robot: int, position: np.ndarray) -> np.ndarray | None:
        """The nearest centre ``robot`` has not visited, or None."""
        left = np.flatnonzero(~self.visited[robot])
        if left.size == 0:
            return None
        d = np.hypot(*(self.centres[left] - position[:2]).T)
        return self.centres[left[np.argmin(d)]]
