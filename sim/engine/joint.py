"""The world of a joint (collaborative) trial: tasks found while exploring, each done when as
many robots as it needs stand at it at once.

:class:`JointRun` is the run state :func:`~epistemica.sim.engine.simulate.simulate` steps for
a mission whose kind is joint, as :class:`~epistemica.sim.engine.simulate.TrialRun` is for
goal and multitask missions: the same loop (perceive, decide, advance) over a world whose
perception and completion are the kind's. Robots see teammates and tasks within their sensing
range and do not communicate: what a robot learns of a task or of a teammate's knowledge comes
from perception (a task within range, a task seen done) and from the mission's observation
events. Every observation goes into the team's
:class:`~epistemica.sim.engine.knowledge.TeamKnowledge` (``epistemica.del_`` state), and the
task ledger the policies read (:class:`JointView`: who knows that whom knows of which task,
since when) is computed here, where perception is, from that state.

A level that shares news (``oracle-events``) or news and places (``oracle``) makes every robot
an observer of everything (full communication, an upper bound).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import NamedTuple

import numpy as np

from epistemica.aif.motion import move
from epistemica.sim.engine.events import World, firings, observer_indices
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.engine.missions import distances
from epistemica.sim.engine.trial import Trial

__all__ = ["JointRun", "JointView"]


class JointView(NamedTuple):
    """What the robots have at one step of a joint trial (robot ``i`` reads its own rows)."""

    step: int
    poses: np.ndarray  # (n, 3) true poses (robot i reads row i only)
    estimates: np.ndarray  # (n, n, 2) where robot i last saw robot j
    last_seen: np.ndarray  # (n, n) step robot i last saw robot j (-1 never)
    knowledge: TeamKnowledge
    aware: np.ndarray  # (n, n, m) robot i knows that robot j knows of task t (j == i: it does)
    since: np.ndarray  # (n, n, m) the first step aware[i, j, t] held (-1: not yet)
    open_seen: np.ndarray  # (n, m) the last step robot i saw task t not done (-1: never)


class JointRun:
    """The mutable state of one joint trial (true poses, the task ledger, records).

    Each step: :meth:`perceive` (teammates and tasks in sight, tasks seen done, the
    mission's events; then the ledger), :meth:`decide` (for the robots a policy drives),
    :meth:`advance`; :meth:`trial` is the record so far.
    """

    def __init__(self, s, streams, shares: str = "") -> None:
        n, m = s.n_robots, s.n_tasks
        self.s, self.streams, self.n = s, streams, n
        self.news_shared = bool(shares)  # every event and task sighting reaches everyone
        self.positions_shared = shares == "everything"
        self.poses = s.starts.copy()
        self.path = [self.poses.copy()]
        self.knowledge = TeamKnowledge(s.robot_names, s.task_names, np.zeros((n, m), dtype=bool))
        self.done = np.full(m, -1)
        self.reached_now = np.zeros(m, dtype=bool)
        self.estimates = np.zeros((n, n, 2))
        self.last_seen = np.full((n, n), -1)
        self.heading = np.full(n, -1)
        # the ledger: when each robot learnt what (the knowledge keeps no time).
        # ``since[i, j, t]`` the first step robot i knew that j knows of task t (j == i: of
        # the task itself), ``open_seen[i, t]`` the last step i saw t not done
        self.aware = np.zeros((n, n, m), dtype=bool)
        self.since = np.full((n, n, m), -1)
        self.open_seen = np.full((n, m), -1)
        self.read_at = -1  # observations the knowledge held when the ledger was last read
        self.steer_to: list[np.ndarray] = []
        self.knows: list[np.ndarray] = []
        self.events: list[tuple] = []
        self.time = np.zeros(s.max_steps)
        self.completion: int | None = None

    def _observers(self, mask: np.ndarray) -> np.ndarray:
        return np.ones(self.n, dtype=bool) if self.news_shared else mask

    def visible(self) -> np.ndarray:
        return distances(self.poses, self.poses[:, :2]) <= self.s.sensing_range

    def perceive(self, step: int) -> JointView:
        """Teammates and tasks in sight, tasks seen done, the mission's events; then the
        ledger, from the team's knowledge."""
        s, k = self.s, self.knowledge
        sight = self.visible()
        # full communication: every robot knows where all are
        seen = np.ones_like(sight) if self.positions_shared else sight
        self.last_seen[seen] = step
        rows, cols = np.nonzero(seen)
        self.estimates[rows, cols] = self.poses[cols, :2]
        near = distances(self.poses, s.tasks) <= s.sensing_range  # (n, m)
        alone = np.eye(self.n, dtype=bool)
        for i, t in zip(*np.nonzero(near), strict=True):
            if self.done[t] >= 0:
                k.notice_closed(t, self._observers(alone[i]))
            else:
                k.discover(t, self._observers(alone[i]))
                self.open_seen[self._observers(alone[i]), t] = step
        self._fire(step, False, sight)
        self._ledger(step)
        return JointView(
            step, self.poses, self.estimates, self.last_seen, k, self.aware, self.since,
            self.open_seen,
        )  # fmt: skip

    def _ledger(self, step: int) -> None:
        """``aware`` (robot i knows that robot j knows of task t) and ``since``, read
        again from the knowledge only when it recorded an observation since the last step
        (otherwise nothing in it changed)."""
        k, n = self.knowledge, self.n
        recorded = len(k.state)
        if recorded == self.read_at:
            return
        self.read_at = recorded
        for i in range(n):
            for j in range(n):
                self.aware[i, j] = k.knows_goals((i,) if i == j else (i, j))
        self.since[self.aware & (self.since < 0)] = step

    def decide(self, step: int, view: JointView, groups, controls: np.ndarray) -> None:
        """Each group's controls at ``step`` into ``controls``, where it steers into the
        record."""
        steer_to = np.full(self.n, -1)
        for policy, robots in groups:
            decisions = policy.decide(view, robots)
            controls[robots] = decisions.controls
            steer_to[robots] = decisions.steer_to
        self.steer_to.append(steer_to)
        self.knows.append(np.diagonal(self.aware).T.copy())

    def _fire(self, step: int, arrivals: bool, sight: np.ndarray) -> None:
        """Fire the mission's event rules (``arrivals``: the ones triggered by reaching a
        task) with ``sight``, who sees whom now."""
        s = self.s
        world = World(
            step, self.poses, self.path[-2] if len(self.path) > 1 else None, s.tasks,
            self.done < 0, self.reached_now, sight, s.sensing_range,
            s.completion_radius, s.sensors, s.robot_names, s.task_names, self.heading,
        )  # fmt: skip
        for rule, firing in firings(s.events, world, arrivals):
            observation = firing.observation
            if self.news_shared:
                observation = replace(
                    observation, full=frozenset(s.robot_names), partial=frozenset()
                )
            if self.knowledge.observe(observation):
                observers = observer_indices(observation, s.robot_names)
                self.events.append((step, rule.name, observation.args, observers))

    def advance(self, step: int, controls: np.ndarray) -> bool:
        """Apply the controls; True when every task is done."""
        s = self.s
        poses = move(self.poses, controls, s.dt)
        jitter = np.stack([g.standard_normal(2) for g in self.streams.process])
        poses[:, :2] += math.sqrt(s.process_noise) * jitter
        poses[:, :2] = np.clip(poses[:, :2], 0.0, s.workspace)
        self.poses = poses
        self.path.append(poses.copy())
        self.heading = np.where(self.steer_to[-1] >= 0, self.steer_to[-1], -1)
        near = distances(poses, s.tasks) <= s.completion_radius  # (n, m)
        counts = near.sum(axis=0)
        self.reached_now = (counts >= np.asarray(s.needs)) & (self.done < 0)
        self.done[self.reached_now] = step + 1
        self._fire(step + 1, True, self.visible())
        if np.all(self.done >= 0):
            self.completion = step + 1
            return True
        return False

    def trial(self, names: tuple[str, ...], seed: int) -> Trial:
        steps, n, m = len(self.path) - 1, self.n, self.s.n_tasks
        return Trial(
            success=self.completion is not None,
            steps=steps,
            completion_step=self.completion,
            tasks_done=self.done.copy(),
            trajectory=np.stack(self.path),
            focal=np.full((steps, n, n), -1),
            entropy=np.full((steps, n), np.nan),
            considered=np.zeros((steps, n), dtype=int),
            unpruned=None,
            modelled=np.zeros((steps, n, n), dtype=int),
            estimates=np.zeros((steps, n, n, 2)),
            goal_belief=np.zeros((steps, n, m)),
            decision_time=self.time[:steps],
            policies=names,
            seed=int(seed),
            events=tuple(self.events),
            knowledge=self.knowledge,
            steer_to=np.array(self.steer_to, dtype=int).reshape(steps, n),
            knows=np.array(self.knows).reshape(steps, n, m),
            aware_since=self.since.copy(),
        )
