"""What a trial draws from its seed before it starts: the layout, who knows which goal, and
which teammate is ad hoc.

One implementation for :meth:`Scenario.paper <epistemica.sim.Scenario.paper>` and mission
files (``epistemica.mission``): each draw comes from its own stream of the trial seed
(:func:`~epistemica.sim.engine._streams.trial_streams`), so a mission file that places everything
``at random`` reproduces the published protocol trial for trial.

Examples
--------
>>> a = draw_layout(3, robots=2, goals=3)
>>> a.goals.shape, a.starts.shape, len(a.sensors)
((3, 2), (2, 2), 2)
>>> bool(np.array_equal(a.goals, draw_layout(3, robots=5, goals=3).goals))  # team size
True
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from epistemica.aif.evidence import SENSORS
from epistemica.sim.engine._streams import trial_streams

__all__ = ["Layout", "draw_adhoc_teammate", "draw_goal_knowledge", "draw_layout"]


class Layout(NamedTuple):
    """Goal positions ``(m, 2)``, start positions ``(n, 2)`` and one sensor per robot."""

    goals: np.ndarray
    starts: np.ndarray
    sensors: tuple[str, ...]


def draw_layout(
    seed: int, robots: int, goals: int, *, workspace: float = 30.0, clustered: bool = False
) -> Layout:
    """The random layout of trial ``seed``.

    Goals are uniform in the workspace less 1 m borders, then starts uniform in the
    workspace (``clustered``: around ``(n-1, n-1)`` with unit variance per axis, clipped
    into the workspace, as the published multitask protocol), both from the seed's geometry
    stream; each sensor is range or bearing with probability 1/2, from its sensor stream.
    """
    streams = trial_streams(seed, robots)
    geometry = streams.geometry
    # a workspace of 2 m or less has no room for goals at random (missions place them all
    # there, and refuse otherwise); drawn anyway so that the streams stay in step
    goal_xy = geometry.uniform(1.0, max(workspace - 1.0, 1.0), size=(goals, 2))
    if clustered:
        start_xy = np.clip((robots - 1) + geometry.normal(0.0, 1.0, (robots, 2)), 0.0, workspace)
    else:
        start_xy = geometry.uniform(0.0, workspace, size=(robots, 2))
    sensors = tuple(SENSORS[i] for i in streams.sensors.integers(0, 2, size=robots))
    return Layout(goal_xy, start_xy, sensors)


def _mission_streams(seed: int, robots: int) -> list[np.random.Generator]:
    """Two independent generators of trial ``seed``: who knows which goal, who is ad hoc."""
    sequence = trial_streams(seed, robots).mission.bit_generator.seed_seq
    return [np.random.default_rng(child) for child in sequence.spawn(2)]


def draw_goal_knowledge(seed: int, robots: int, goals: int) -> np.ndarray:
    """``(n, m)``: per goal, each robot knows it with probability 1/2; a goal nobody drew
    is known to one robot drawn uniformly.

    Examples
    --------
    >>> bool(draw_goal_knowledge(0, 3, 4).any(axis=0).all())  # every goal known to someone
    True
    """
    stream = _mission_streams(seed, robots)[0]
    known = stream.random((goals, robots)) < 0.5
    nobody = ~known.any(axis=1)
    known[np.flatnonzero(nobody), stream.integers(robots, size=int(nobody.sum()))] = True
    return known.T.copy()


def draw_adhoc_teammate(seed: int, robots: int) -> int:
    """The index of the robot that follows its own rule in trial ``seed``."""
    return int(_mission_streams(seed, robots)[1].integers(robots))
