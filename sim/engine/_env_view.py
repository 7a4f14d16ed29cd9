"""What one robot of :mod:`epistemica.sim.engine.env` observes, what it may do, and the reward.

Helper of :mod:`epistemica.sim.engine.env` (gymnasium is imported by the caller and passed in as
``spaces``, so this module needs no optional dependency of its own): the functions, and
:class:`GoalWorld`, the goal and multitask missions' side of the environment
(:class:`~epistemica.sim.engine._env_joint.JointWorld` is the collaborative one's).
"""

from __future__ import annotations

import math

import numpy as np

from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.engine.simulate import TrialRun

__all__ = [
    "GoalWorld",
    "action_space",
    "agent_views",
    "clipped",
    "controls",
    "event_flags",
    "observation_space",
    "position_bounds",
    "positions",
    "potential",
    "robot_space",
    "shortfall",
    "state_space",
    "state_vector",
]


def position_bounds(s: Scenario) -> tuple[float, float]:
    """The bounds of every position in an observation (m): the workspace with a margin of
    one workspace on each side (observed positions are clipped into them)."""
    return -float(s.workspace), 2.0 * float(s.workspace)


def positions(spaces, s: Scenario, shape: tuple):
    """A float32 ``Box`` of positions of ``shape`` within :func:`position_bounds`."""
    lo, hi = position_bounds(s)
    return spaces.Box(low=np.float32(lo), high=np.float32(hi), shape=shape, dtype=np.float32)


def robot_space(spaces, s, m: int, kinds: dict, epistemic: bool):
    """A robot's observation space over ``m`` goals or tasks: its pose, the teammates,
    whom it sees, the kind's own parts ``kinds``, the step, the events (a mission with
    events) and, with ``epistemic``, ``teammates_know`` ``(n, m)``."""
    n = s.n_robots
    lo, hi = position_bounds(s)
    pose = np.array([[lo, lo, -np.pi], [hi, hi, np.pi]], dtype=np.float32)
    parts = {
        "pose": spaces.Box(low=pose[0], high=pose[1], dtype=np.float32),
        "teammates": positions(spaces, s, (n, 2)),
        "seen": spaces.MultiBinary(n),
        **kinds,
        "step": spaces.Discrete(s.max_steps + 1),
    }
    if s.events:
        parts["events"] = spaces.MultiBinary(len(s.events))
    if epistemic:
        parts["teammates_know"] = spaces.MultiBinary((n, m))
    return spaces.Dict(parts)


def observation_space(spaces, s: Scenario, epistemic: bool = False):
    """The observation space of every robot of ``s`` (see :mod:`epistemica.sim.engine.env`)."""
    m = s.n_goals
    goals = {
        "goals": positions(spaces, s, (m, 2)),
        "known_goals": spaces.MultiBinary(m),
        "closed": spaces.MultiBinary(m),
    }
    return robot_space(spaces, s, m, goals, epistemic)


def action_space(spaces, s: Scenario, robot: int, normalized: bool = False):
    """``(speed, heading change)`` within robot ``robot``'s limits (float32; the
    simulator clips to the exact limits); ``normalized``: ``[-1, 1]²`` instead
    (:func:`controls`)."""
    if normalized:
        return spaces.Box(low=-1.0, high=1.0, shape=(2,), dtype=np.float32)
    speed, turn = float(s.max_speed[robot]), float(s.max_turn[robot])
    return spaces.Box(
        low=np.array([0.0, -turn], dtype=np.float32),
        high=np.array([speed, turn], dtype=np.float32),
        shape=(2,),
        dtype=np.float32,
    )


def controls(s: Scenario, robots, actions: np.ndarray) -> np.ndarray:
    """Normalised actions ``[-1, 1]²`` of ``robots`` as ``(speed, heading change)``:
    ``-1 .. 1`` maps onto ``0 .. max_speed`` and ``-max_turn .. max_turn``."""
    a = np.clip(np.asarray(actions, dtype=float), -1.0, 1.0)
    speed = (a[:, 0] + 1.0) / 2.0 * s.max_speed[robots]
    return np.stack([speed, a[:, 1] * s.max_turn[robots]], axis=1)


def state_space(spaces, s: Scenario, m: int | None = None):
    """The global state's space: every true pose ``(n, 3)``, every goal ``(m, 2)`` (or
    ``m`` tasks), which are open ``(m,)`` and the step over the step limit, flattened
    (float32)."""
    n, m = s.n_robots, s.n_goals if m is None else m
    lo, hi = position_bounds(s)
    low = np.concatenate([np.tile([lo, lo, -np.pi], n), np.full(2 * m, lo), np.zeros(m + 1)])
    high = np.concatenate([np.tile([hi, hi, np.pi], n), np.full(2 * m, hi), np.ones(m + 1)])
    return spaces.Box(low=low.astype(np.float32), high=high.astype(np.float32), dtype=np.float32)


def state_vector(
    s, poses: np.ndarray, open_goals: np.ndarray, step: int, places: np.ndarray | None = None
) -> np.ndarray:
    """The global state (:func:`state_space`) of true ``poses`` and ``open_goals`` (of
    ``places``, default the goals)."""
    lo, hi = position_bounds(s)
    places = s.goals if places is None else places
    poses = clipped(poses, lo, hi)
    parts = [poses.ravel(), np.clip(places, lo, hi).ravel(), open_goals.astype(float)]
    return np.concatenate([*parts, [step / max(s.max_steps, 1)]]).astype(np.float32)


def clipped(poses: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Positions clipped into the bounds, headings wrapped into ``[-pi, pi)``."""
    out = np.array(poses, dtype=float)
    out[..., :2] = np.minimum(np.maximum(out[..., :2], lo), hi)  # ufuncs: every step
    out[..., 2] = (out[..., 2] + np.pi) % (2 * np.pi) - np.pi
    return out


def agent_views(
    s: Scenario,
    obs: Observations,
    step: int,
    new_events: list[tuple],
    robots,
    teammates_know: np.ndarray | None = None,
) -> dict[int, dict]:
    """Each robot's observation (robot index -> dict) from the team's ``obs``
    (``teammates_know``: ``(n, n, m)``, the goals robot ``i`` takes robot ``j`` to know of,
    put in as ``teammates_know`` when given)."""
    lo, hi = position_bounds(s)
    poses = clipped(obs.poses, lo, hi).astype(np.float32)
    known = obs.known_goals
    places = np.minimum(np.maximum(s.goals, lo), hi)[None]
    goals = np.where(known[..., None], places, 0.0).astype(np.float32)
    known_i8, closed_i8 = known.astype(np.int8), obs.known_done.astype(np.int8)
    seen_i8 = obs.seen.astype(np.int8)
    events = event_flags(s, new_events)
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
        if teammates_know is not None:
            view["teammates_know"] = teammates_know[i].astype(np.int8)
        views[i] = view
    return views


def event_flags(s, new_events: list[tuple], rules: dict | None = None) -> np.ndarray | None:
    """``(n, R)``: robot ``i`` observed an event of rule ``k`` among ``new_events`` (the
    run's records: ``(step, rule, arguments, observers)``); None for a mission without
    events. ``rules``: each rule's index by name, if the caller keeps it."""
    if not s.events:
        return None
    rule = {r.name: k for k, r in enumerate(s.events)} if rules is None else rules
    events = np.zeros((s.n_robots, len(s.events)), dtype=np.int8)
    for record in new_events:
        events[list(record[-1]), rule[record[1]]] = 1
    return events


def potential(s: Scenario, poses: np.ndarray, open_goals: np.ndarray) -> float:
    """Minus the mean distance (in workspaces) from each robot to its nearest open goal
    beyond the success radius: 0 when every robot is at an open goal."""
    near = [g for g, now in zip(s.goals.tolist(), open_goals.tolist(), strict=True) if now]
    if not near:
        return 0.0
    return -shortfall(poses.tolist(), near, s.success_radius) / (len(poses) * s.workspace)


def shortfall(poses: list, places: list, radius: float) -> float:
    """The sum over robots (``poses``: ``[x, y, ...]`` lists) of the distance to the
    nearest of ``places`` (``[x, y]`` lists) beyond ``radius``: plain floats, which cost
    less than numpy calls for a few robots and places, every step.

    Examples
    --------
    >>> shortfall([[0.0, 0.0, 0.0], [10.0, 0.0, 1.0]], [[3.0, 4.0], [10.0, 1.0]], 1.0)
    4.0
    """
    total = 0.0
    for x, y, *_ in poses:
        d = min(math.hypot(x - a, y - b) for a, b in places)
        total += max(d - radius, 0.0)
    return total


class GoalWorld:
    """Spaces, observations, state and reward terms of a goal or multitask mission ``s``
    (the functions above, over :class:`~epistemica.sim.engine.simulate.TrialRun`)."""

    def __init__(self, spaces, s: Scenario, epistemic: bool) -> None:
        self.s, self.epistemic = s, epistemic
        self.observation_space = observation_space(spaces, s, epistemic)
        self.state_space = state_space(spaces, s)

    def start(self, s: Scenario, streams, groups) -> TrialRun:
        """The run of a trial of ``s`` (the scenario of the trial from now on: a mission
        draws one per seed, within the spaces of the first)."""
        self.s = s
        return TrialRun(s, streams)

    def views(self, run: TrialRun, obs: Observations, step: int, new_events, robots) -> dict:
        """Each of ``robots``' observation (robot index -> dict) at ``step``."""
        s, know = self.s, None
        if self.epistemic:
            know = np.ones((s.n_robots, s.n_robots, s.n_goals), dtype=bool)
            if run.known is not None:
                know = run.known[min(step, len(run.known) - 1)]
        return agent_views(s, obs, step, new_events, robots, teammates_know=know)

    def declare(self, run: TrialRun, targets: dict[int, int]) -> None:
        """Nothing: a goal mission's robots declare no task they head to."""

    def state(self, run: TrialRun, step: int) -> np.ndarray:
        """The global state (:func:`state_vector`)."""
        return state_vector(self.s, run.poses, run.open, step)

    def progress(self, run: TrialRun) -> float:
        """``held / dwell``, or for a multitask mission the share of the tasks done."""
        s = self.s
        if s.kind.tasks:
            return float(np.count_nonzero(run.done >= 0)) / s.n_goals
        return min(run.held, s.dwell) / s.dwell

    def potential(self, run: TrialRun) -> float:
        """:func:`potential` of the run's poses."""
        return potential(self.s, run.poses, run.open)

    def last(self, obs: Observations, run: TrialRun) -> Observations:
        """The observation after the last step: the last one, each robot's own pose now."""
        poses = obs.poses.copy()
        index = np.arange(self.s.n_robots)
        poses[index, index] = run.poses
        return obs._replace(poses=poses)

    def info(self, run: TrialRun) -> dict:
        """What every agent's info adds: steps the mission held, success."""
        return {"held": run.held, "success": bool(run.success)}
