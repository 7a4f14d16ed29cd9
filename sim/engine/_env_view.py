"""What one robot of :mod:`epistemica.sim.engine.env` observes, what it may do, and the reward.

Helper of :mod:`epistemica.sim.engine.env` (gymnasium is imported by the caller and passed in as
``spaces``, so this module needs no optional dependency of its own).
"""

from __future__ import annotations

import numpy as np

from epistemica.sim.engine.missions import distances
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Observations

__all__ = ["action_space", "agent_views", "observation_space", "potential"]


def observation_space(spaces, s: Scenario):
    """The observation space of every robot of ``s`` (see :mod:`epistemica.sim.engine.env`)."""
    n, m = s.n_robots, s.n_goals
    unbounded = {"low": -np.inf, "high": np.inf, "dtype": np.float32}
    parts = {
        "pose": spaces.Box(shape=(3,), **unbounded),
        "teammates": spaces.Box(shape=(n, 2), **unbounded),
        "seen": spaces.MultiBinary(n),
        "goals": spaces.Box(shape=(m, 2), **unbounded),
        "known_goals": spaces.MultiBinary(m),
        "closed": spaces.MultiBinary(m),
        "step": spaces.Discrete(s.max_steps + 1),
    }
    if s.events:
        parts["events"] = spaces.MultiBinary(len(s.events))
    return spaces.Dict(parts)


def action_space(spaces, s: Scenario, robot: int):
    """``(speed, heading change)`` within robot ``robot``'s limits (float64, exact)."""
    speed, turn = float(s.max_speed[robot]), float(s.max_turn[robot])
    return spaces.Box(
        low=np.array([0.0, -turn]), high=np.array([speed, turn]), shape=(2,), dtype=np.float64
    )


def agent_views(
    s: Scenario, obs: Observations, step: int, new_events: list[tuple], robots
) -> dict[int, dict]:
    """Each robot's observation (robot index -> dict) from the team's ``obs``."""
    n = s.n_robots
    poses = obs.poses.astype(np.float32)
    known = obs.known_goals
    goals = np.where(known[..., None], s.goals[None], 0.0).astype(np.float32)
    known_i8, closed_i8 = known.astype(np.int8), obs.known_done.astype(np.int8)
    seen_i8 = obs.seen.astype(np.int8)
    events = None
    if s.events:
        rule = {r.name: k for k, r in enumerate(s.events)}
        events = np.zeros((n, len(s.events)), dtype=np.int8)
        for record in new_events:
            events[list(record[-1]), rule[record[1]]] = 1
    views = {}
    for i in robots:
        view = {
            "pose": poses[i, i],
            "teammates": poses[i, :, :2],
            "seen": seen_i8[i],
            "goals": goals[i],
            "known_goals": known_i8[i],
            "closed": closed_i8[i],
            "step": step,
        }
        if events is not None:
            view["events"] = events[i]
        views[i] = view
    return views


def potential(s: Scenario, poses: np.ndarray, open_goals: np.ndarray) -> float:
    """Minus the mean distance (in workspaces) from each robot to its nearest open goal
    beyond the success radius: 0 when every robot is at an open goal."""
    if not open_goals.any():
        return 0.0
    d = distances(poses, s.goals[open_goals]).min(axis=1)
    return -float(np.maximum(d - s.success_radius, 0.0).sum()) / (len(d) * s.workspace)
