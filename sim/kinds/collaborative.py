"""Collaborative tasks found while exploring: the world and its loop.

Tasks lie at places unknown at the start; task ``t`` is done the first step ``needs[t]``
robots are within the completion radius of it at once. Robots see teammates and tasks
within their sensing range and do not communicate: what a robot learns of a task or of a
teammate's knowledge comes from perception (a task within range, a task seen done) and
from the mission's observation events (:mod:`epistemica.sim.engine.events`): typically a task
*found* (seen by the robots that see the finder), a robot *waiting* at a task or *heading*
to it (seen by the robots that see it), a task *done* (seen by those that see the robots
that did it). Every observation goes into the team's
:class:`~epistemica.sim.engine.knowledge.TeamKnowledge` with its observers, so a robot can ask
which teammates know of a task (the chain ``(i, j)`` is aware of it). The policies are in
:mod:`epistemica.sim.policies.collaborative_levels`; the ``oracle`` level shares every observation
with every robot (full communication, an upper bound).

The same seed gives the same tasks, starts and process noise for every level.

Examples
--------
>>> s = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=1)
>>> s.n_robots, s.n_tasks, s.needs
(3, 2, (2, 2))
>>> trial = simulate_collaborative(s, "convention", seed=1)
>>> trial.tasks_done.shape
(2,)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np

from epistemica.aif.motion import move
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine._streams import trial_streams
from epistemica.sim.engine.draws import draw_layout
from epistemica.sim.engine.events import EventRule, World, firings, observer_indices
from epistemica.sim.engine.knowledge import TeamKnowledge
from epistemica.sim.engine.missions import distances
from epistemica.sim.kinds.tasks import COLLABORATIVE
from epistemica.sim.policies.collaborative_levels import CollaborativeParameters, View
from epistemica.sim.policies.levels import make_level

__all__ = ["CollaborativeScenario", "CollaborativeTrial", "simulate_collaborative"]


@dataclass(frozen=True)
class CollaborativeScenario:
    """A collaborative mission's world, validated when built.

    Parameters
    ----------
    starts : array_like
        ``(n, 2)`` or ``(n, 3)`` start poses.
    tasks : array_like
        ``(m, 2)`` task places (unknown to every robot at the start).
    needs : sequence of int
        Robots each task needs at once, each in ``1..n``.
    workspace, sensing_range, completion_radius : float
        Side of the square workspace (m); range within which a robot sees teammates and
        tasks; distance that counts as "at a task".
    max_steps : int
        Step limit.
    events : tuple of EventRule
        The mission's observation events.
    """

    starts: np.ndarray
    tasks: np.ndarray
    needs: tuple[int, ...]
    workspace: float = 40.0
    sensing_range: float = 8.0
    completion_radius: float = 1.5
    max_steps: int = 400
    max_speed: float | np.ndarray = 1.0
    max_turn: float | np.ndarray = math.pi
    process_noise: float = 0.0
    dt: float = 1.0
    events: tuple[EventRule, ...] = ()
    robot_names: tuple[str, ...] = ()
    task_names: tuple[str, ...] = ()
    sensors: tuple[str, ...] = field(default=(), repr=False)

    def __post_init__(self) -> None:
        starts = np.array(self.starts, dtype=float)
        if starts.ndim != 2 or starts.shape[1] not in (2, 3) or starts.shape[0] < 1:
            raise InvalidArgumentError(f"starts must be (n, 2) or (n, 3), got {starts.shape}")
        if starts.shape[1] == 2:
            starts = np.column_stack([starts, np.zeros(len(starts))])
        tasks = np.array(self.tasks, dtype=float).reshape(-1, 2)
        n, m = starts.shape[0], tasks.shape[0]
        speed = np.broadcast_to(np.asarray(self.max_speed, dtype=float), (n,)).copy()
        turn = np.broadcast_to(np.asarray(self.max_turn, dtype=float), (n,)).copy()
        numbers = {"workspace": self.workspace, "sensing_range": self.sensing_range,
                   "completion_radius": self.completion_radius, "dt": self.dt,
                   "max_speed": float(speed.min())}  # fmt: skip
        for name, value in numbers.items():
            if not (math.isfinite(value) and value > 0):
                raise InvalidArgumentError(f"{name} must be finite and > 0, got {value!r}")
        if not (np.isfinite(starts).all() and np.isfinite(tasks).all()) or (turn < 0).any():
            raise InvalidArgumentError("starts and tasks must be finite, turns >= 0", hint="no NaN")
        needs = tuple(int(k) for k in self.needs)
        if len(needs) != m or m == 0 or not all(1 <= k <= n for k in needs):
            raise InvalidArgumentError(
                f"needs must give, for each of the {m} tasks, 1..{n} robots; got {needs}",
                hint="a task cannot need more robots than the team has",
            )
        if int(self.max_steps) < 1:
            raise InvalidArgumentError(f"max_steps must be >= 1, got {self.max_steps}")
        object.__setattr__(self, "max_speed", speed)
        object.__setattr__(self, "max_turn", turn)
        object.__setattr__(self, "starts", starts)
        object.__setattr__(self, "tasks", tasks)
        object.__setattr__(self, "needs", needs)
        object.__setattr__(self, "max_steps", int(self.max_steps))
        if not self.robot_names:
            object.__setattr__(self, "robot_names", tuple(f"r{i + 1}" for i in range(n)))
        if not self.task_names:
            object.__setattr__(self, "task_names", tuple(f"t{j + 1}" for j in range(m)))
        if not self.sensors:
            object.__setattr__(self, "sensors", ("range",) * n)

    @property
    def n_robots(self) -> int:
        return self.starts.shape[0]

    @property
    def n_tasks(self) -> int:
        return self.tasks.shape[0]

    def replace(self, **changes) -> CollaborativeScenario:
        return replace(self, **changes)

    @classmethod
    def drawn(
        cls, robots: int, needs, seed: int, workspace: float = 40.0, **options
    ) -> CollaborativeScenario:
        """Tasks and starts uniform in the workspace, drawn from ``seed``
        (:func:`~epistemica.sim.engine.draws.draw_layout`)."""
        layout = draw_layout(seed, robots, len(needs), workspace=workspace)
        return cls(layout.starts, layout.goals, tuple(needs), workspace=workspace, **options)


class CollaborativeTrial(NamedTuple):
    """The record of one collaborative trial.

    ``tasks_done[t]`` is the step task ``t`` was done (-1: never); ``completion_step`` the
    step the last one was (None on failure); ``events`` ``(step, name, arguments,
    observers)``; ``targets`` ``(T, n)`` the task each robot steered to (-1: exploring,
    -2: intercepting a teammate); ``knows`` ``(T, n, m)`` the tasks each robot knew of;
    ``aware_since`` ``(n, n, m)`` the first step robot ``i`` knew that robot ``j`` knows of
    task ``t`` (``j == i``: of the task; -1 never).
    """

    success: bool
    steps: int
    completion_step: int | None
    tasks_done: np.ndarray
    trajectory: np.ndarray
    targets: np.ndarray
    knows: np.ndarray
    events: tuple
    policy: str
    seed: int
    knowledge: TeamKnowledge
    aware_since: np.ndarray | None = None


def simulate_collaborative(
    scenario: CollaborativeScenario,
    level: str = "third",
    seed: int = 0,
    parameters: CollaborativeParameters | None = None,
) -> CollaborativeTrial:
    """Simulate one trial of ``scenario`` with every robot at ``level``
    (:func:`~epistemica.sim.policies.levels.level_names`)."""
    if not isinstance(scenario, CollaborativeScenario):
        raise InvalidArgumentError(
            f"expected a CollaborativeScenario, got {type(scenario).__name__}"
        )
    policy = make_level(COLLABORATIVE, level, parameters)
    run = _Run(scenario, trial_streams(seed, scenario.n_robots), policy.shares)
    policy.start(scenario)
    for step in range(scenario.max_steps):
        run.perceive(step)
        run.remember(step)
        view = View(step, run.poses, run.estimates, run.last_seen, run.knowledge, *run.record())
        targets, steer_to = policy.decide(view)
        run.targets.append(steer_to.copy())
        run.knows.append(np.diagonal(run.aware).T.copy())
        if run.advance(step, targets, steer_to):
            break
    return run.trial(policy.name, seed)


class _Run:
    """The mutable state of one trial."""

    def __init__(self, s: CollaborativeScenario, streams, shares: str) -> None:
        self.s, self.streams, self.n = s, streams, s.n_robots
        self.news_shared = bool(shares)  # every event and task sighting reaches everyone
        self.positions_shared = shares == "everything"
        self.poses = s.starts.copy()
        self.path = [self.poses.copy()]
        self.knowledge = TeamKnowledge(
            s.robot_names, s.task_names, np.zeros((s.n_robots, s.n_tasks), dtype=bool)
        )
        self.done = np.full(s.n_tasks, -1)
        self.reached_now = np.zeros(s.n_tasks, dtype=bool)
        self.reachers = np.zeros((s.n_robots, s.n_tasks), dtype=bool)
        self.estimates = np.zeros((s.n_robots, s.n_robots, 2))
        self.last_seen = np.full((s.n_robots, s.n_robots), -1)
        self.heading = np.full(s.n_robots, -1)
        # when each robot learnt what (kept beside the knowledge, which keeps no time):
        # ``since[i, j, t]`` the first step robot i knew that j knows of task t (j == i: of
        # the task itself), ``open_seen[i, t]`` the last step i saw t not done
        self.aware = np.zeros((s.n_robots, s.n_robots, s.n_tasks), dtype=bool)
        self.since = np.full((s.n_robots, s.n_robots, s.n_tasks), -1)
        self.open_seen = np.full((s.n_robots, s.n_tasks), -1)
        self.targets: list[np.ndarray] = []
        self.knows: list[np.ndarray] = []
        self.events: list[tuple] = []
        self.completion: int | None = None

    def _observers(self, mask: np.ndarray) -> np.ndarray:
        return np.ones(self.n, dtype=bool) if self.news_shared else mask

    def visible(self) -> np.ndarray:
        return distances(self.poses, self.poses[:, :2]) <= self.s.sensing_range

    def perceive(self, step: int) -> None:
        """Teammates and tasks in sight, tasks seen done, the mission's events."""
        s, k = self.s, self.knowledge
        seen = self.visible()
        if self.positions_shared:  # full communication: every robot knows where all are
            seen[:] = True
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
        self._fire(step, arrivals=False)

    def remember(self, step: int) -> None:
        """Update ``aware`` (robot i knows that robot j knows of task t) and ``since``."""
        k, n = self.knowledge, self.n
        for i in range(n):
            for j in range(n):
                self.aware[i, j] = k.knows_goals((i,) if i == j else (i, j))
        self.since[self.aware & (self.since < 0)] = step

    def record(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(aware, since, open_seen)`` for the policies' :class:`View`."""
        return self.aware, self.since, self.open_seen

    def _fire(self, step: int, arrivals: bool) -> None:
        s = self.s
        world = World(
            step,
            self.poses,
            self.path[-2] if len(self.path) > 1 else None,
            s.tasks,
            self.done < 0,
            self.reached_now,
            self.visible(),
            s.sensing_range,
            s.completion_radius,
            s.sensors,
            s.robot_names,
            s.task_names,
            self.heading,
        )
        for rule, firing in firings(s.events, world, arrivals):
            observation = firing.observation
            if self.news_shared:
                observation = replace(
                    observation, full=frozenset(s.robot_names), partial=frozenset()
                )
            if self.knowledge.observe(observation):
                observers = observer_indices(observation, s.robot_names)
                self.events.append((step, rule.name, observation.args, observers))

    def advance(self, step: int, targets: np.ndarray, steer_to: np.ndarray) -> bool:
        s = self.s
        delta = targets - self.poses[:, :2]
        distance = np.hypot(delta[:, 0], delta[:, 1])
        change = np.arctan2(delta[:, 1], delta[:, 0]) - self.poses[:, 2]
        change = (change + np.pi) % (2 * np.pi) - np.pi
        change = np.where(distance > 0, np.clip(change, -s.max_turn, s.max_turn), 0.0)
        speed = np.minimum(s.max_speed, distance / s.dt)
        poses = move(self.poses, np.column_stack([speed, change]), s.dt)
        jitter = np.stack([g.standard_normal(2) for g in self.streams.process])
        poses[:, :2] += math.sqrt(s.process_noise) * jitter
        poses[:, :2] = np.clip(poses[:, :2], 0.0, s.workspace)
        self.poses = poses
        self.path.append(poses.copy())
        self.heading = np.where(steer_to >= 0, steer_to, -1)
        near = distances(poses, s.tasks) <= s.completion_radius  # (n, m)
        counts = near.sum(axis=0)
        needs = np.asarray(s.needs)
        self.reached_now = (counts >= needs) & (self.done < 0)
        self.done[self.reached_now] = step + 1
        self._fire(step + 1, arrivals=True)
        if np.all(self.done >= 0):
            self.completion = step + 1
            return True
        return False

    def trial(self, name: str, seed: int) -> CollaborativeTrial:
        steps = len(self.path) - 1
        return CollaborativeTrial(
            success=self.completion is not None,
            steps=steps,
            completion_step=self.completion,
            tasks_done=self.done.copy(),
            trajectory=np.stack(self.path),
            targets=np.array(self.targets).reshape(steps, self.n),
            knows=np.array(self.knows).reshape(steps, self.n, self.s.n_tasks),
            events=tuple(self.events),
            policy=name,
            seed=int(seed),
            knowledge=self.knowledge,
            aware_since=self.since.copy(),
        )
