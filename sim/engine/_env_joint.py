"""The environment's side of a joint (collaborative) mission: what one robot observes of
tasks it finds while exploring, the global state, the progress and the shaping potential.

Helper of :mod:`epistemica.sim.engine.env`, as :class:`~epistemica.sim.engine._env_view.GoalWorld`
is for goal and multitask missions (gymnasium's ``spaces`` is passed in). The environment
steps :class:`~epistemica.sim.engine.joint.JointRun`, the run
:func:`~epistemica.sim.engine.simulate` steps for a collaborative mission.

Examples
--------
>>> from gymnasium import spaces
>>> from epistemica.sim.kinds.collaborative import CollaborativeScenario
>>> s = CollaborativeScenario([[1.0, 1.0, 0.0], [3.0, 1.0, 0.0]], [[2.0, 2.0]], (2,))
>>> world = JointWorld(spaces, s, epistemic=False)
>>> sorted(world.observation_space.spaces)
['done', 'known_tasks', 'needs', 'pose', 'seen', 'step', 'tasks', 'teammates']
"""

from __future__ import annotations

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine._env_view import (
    event_flags,
    position_bounds,
    positions,
    robot_space,
    shortfall,
    state_space,
    state_vector,
)
from epistemica.sim.engine.joint import JointRun, JointView

__all__ = ["JointWorld"]


class JointWorld:
    """Spaces, observations, state and reward terms of a collaborative mission ``s``.

    Robot ``i`` observes its pose, where it last saw each teammate (``teammates``; its own
    row exact) and whom it sees now (``seen``), the tasks it knows of (``tasks``, zeros for
    the others; ``known_tasks``), how many robots each needs (``needs``, 0 for unknown
    tasks), the tasks it knows done (``done``), the events it observed since its last
    observation (``events``, missions with events) and the step; with ``epistemic`` also
    ``teammates_know`` (``(n, m)``: the tasks it knows each robot to know of).
    """

    def __init__(self, spaces, s, epistemic: bool) -> None:
        self.s, self.epistemic = s, epistemic
        n, m = s.n_robots, s.n_tasks
        tasks = {
            "tasks": positions(spaces, s, (m, 2)),
            "known_tasks": spaces.MultiBinary(m),
            "needs": spaces.MultiDiscrete(np.full(m, n + 1)),
            "done": spaces.MultiBinary(m),
        }
        self.observation_space = robot_space(spaces, s, m, tasks, epistemic)
        self.state_space = state_space(spaces, s, m)

    def start(self, s, streams, groups) -> JointRun:
        """The joint run of a trial of ``s`` (the scenario from now on), with what the
        scripted teammates' level shares."""
        self.s = s
        shares = {getattr(policy, "shares", "") for policy, _ in groups} or {""}
        if len(shares) > 1:
            raise InvalidArgumentError(
                "levels that share what they see and levels that do not play the same world",
                hint="give every scripted robot of a collaborative mission one level",
            )
        self._bounds = lo, hi = position_bounds(s)
        self._tasks = np.clip(s.tasks, lo, hi).astype(np.float32)[None]  # (1, m, 2)
        self._needs, self._alone = np.asarray(s.needs), np.eye(s.n_robots, dtype=bool)
        self._undone, self._near = -1, []  # how many tasks were not done, and where they are
        self._rules = {rule.name: k for k, rule in enumerate(s.events)}
        return JointRun(s, streams, shares.pop())

    def views(self, run: JointRun, view: JointView, step: int, new_events, robots) -> dict:
        """Each of ``robots``' observation (robot index -> dict) at ``step`` (the arrays of
        every robot built at once, from the trial's constants :meth:`start` keeps)."""
        # ufuncs and array methods only (no numpy function wrappers): this runs every step
        s, (lo, hi), true = self.s, self._bounds, view.poses
        poses = np.empty(true.shape, dtype=np.float32)  # as _env_view.clipped, then float32
        poses[:, :2] = np.minimum(np.maximum(true[:, :2], lo), hi)
        poses[:, 2] = (true[:, 2] + np.pi) % (2 * np.pi) - np.pi
        where = np.minimum(np.maximum(view.estimates, lo), hi).astype(np.float32)
        where[self._alone] = poses[:, :2]  # its own row: exact
        seen = ((view.last_seen == view.step) | self._alone).astype(np.int8)
        knows = view.aware.diagonal().T  # (n, m): robot i knows of task t
        tasks = np.where(knows[..., None], self._tasks, np.float32(0.0))
        needs = np.where(knows, self._needs, 0)
        known = knows.astype(np.int8)
        done = np.array([view.knowledge.knows_done((i,)) for i in robots], dtype=np.int8)
        events = event_flags(s, new_events, self._rules)
        aware = view.aware.astype(np.int8) if self.epistemic else None
        out = {}
        for row, i in enumerate(robots):
            out[i] = own = {
                "pose": poses[i],
                "teammates": where[i],
                "seen": seen[i],
                "tasks": tasks[i],
                "known_tasks": known[i],
                "needs": needs[i],
                "done": done[row],
                "step": step,
            }
            if events is not None:
                own["events"] = events[i]
            if aware is not None:
                own["teammates_know"] = aware[i]
        return out

    def declare(self, run: JointRun, targets: dict[int, int]) -> None:
        """Record, for this step, the task each of some agents heads to (robot index ->
        task): an agent that plays a level's actions (``MissionEnv.level_actions``) heads
        where the level heads, and teammates may observe it (``heading`` events); any
        other agent explores, as far as anyone can tell."""
        for robot, task in targets.items():
            run.steer_to[-1][robot] = task

    def state(self, run: JointRun, step: int) -> np.ndarray:
        """Every true pose, every task, which tasks are not done, the step over the limit."""
        return state_vector(self.s, run.poses, run.done < 0, step, self.s.tasks)

    def progress(self, run: JointRun) -> float:
        """The share of the tasks done."""
        return float(np.add.reduce(run.done >= 0)) / self.s.n_tasks

    def potential(self, run: JointRun) -> float:
        """Minus the mean distance (in workspaces) from each robot to its nearest task not
        done, beyond the completion radius (0 when every task is done)."""
        s, done = self.s, run.done.tolist()
        left = done.count(-1)
        if not left:
            return 0.0
        if left != self._undone:  # a task is done for good: the set changed
            near = [p for p, d in zip(s.tasks.tolist(), done, strict=True) if d < 0]
            self._undone, self._near = left, near
        beyond = shortfall(run.poses.tolist(), self._near, s.completion_radius)
        return -beyond / (s.n_robots * s.workspace)

    def last(self, view: JointView, run: JointRun) -> JointView:
        """The observation after the last step: the same, with the true poses now."""
        return view._replace(poses=run.poses)

    def info(self, run: JointRun) -> dict:
        """What every agent's info adds: tasks done, success."""
        done = int(np.add.reduce(run.done >= 0))
        return {"tasks_done": done, "success": run.completion is not None}
