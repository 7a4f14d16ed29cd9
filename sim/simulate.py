"""Run one trial: perceive, decide, move, until the mission holds or time runs out.

Examples
--------
>>> from epistemica.sim import Scenario
>>> s = Scenario.paper("rendezvous", 3, 3, seed=4)
>>> a, b = simulate(s, "zero", seed=4), simulate(s, "convention", seed=4)
>>> bool(np.array_equal(a.trajectory[0], b.trajectory[0]))  # same trial for every level
True
>>> simulate(s, "convention", seed=4, policies={0: "zero"}).policies
('zero', 'convention', 'convention')
"""

from __future__ import annotations

from collections.abc import Mapping
from time import perf_counter

import numpy as np

from epistemica.aif.motion import move
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim._streams import trial_streams
from epistemica.sim.active import LEVELS, ActiveInference
from epistemica.sim.baselines import Convention, Greedy
from epistemica.sim.knowledge import initial_knowledge
from epistemica.sim.missions import distances, mission_holds, realises
from epistemica.sim.paper import PAPER_LEVELS, PaperPolicy
from epistemica.sim.policy import Policy
from epistemica.sim.scenario import Scenario
from epistemica.sim.sensing import Sensing
from epistemica.sim.trial import Trial

__all__ = ["REASONING", "make_policy", "simulate"]

#: Names accepted for ``reasoning`` (and as values of ``policies``).
REASONING = (
    "zero",
    "convention",
    "first",
    "second",
    "third",
    "first-unpruned",
    "second-unpruned",
    "third-unpruned",
    "second-shared",
    "third-shared",
    "convention-reverse",
    "paper-first",
    "paper-higher",
    "paper-higher-fixed",
)

# A robot that moved less than this (m) in the last step, within the success radius of a
# goal, is seen to have settled there.
_SETTLED = 0.05


def make_policy(name: str) -> Policy:
    """A fresh policy for a level name.

    Examples
    --------
    >>> make_policy("third").order
    3
    """
    if isinstance(name, Policy):
        return name
    if name == "zero":
        return Greedy()
    if name == "convention":
        return Convention()
    if name == "convention-reverse":
        return Convention(tie_break="reverse")
    if name in LEVELS:
        return ActiveInference(LEVELS[name])
    if name.endswith("-unpruned") and name.removesuffix("-unpruned") in LEVELS:
        return ActiveInference(LEVELS[name.removesuffix("-unpruned")], pruning=False)
    if name.endswith("-shared") and name.removesuffix("-shared") in LEVELS:
        return ActiveInference(LEVELS[name.removesuffix("-shared")], nested=False)
    if name in PAPER_LEVELS:
        return PaperPolicy(name)
    raise InvalidArgumentError(
        f"unknown reasoning level {name!r}",
        hint=f"use one of {', '.join(REASONING)}, or pass a Policy object",
    )


def _groups(n: int, reasoning, policies: Mapping | None) -> list[tuple[Policy, np.ndarray]]:
    chosen: dict[int, object] = dict.fromkeys(range(n), reasoning)
    for robot, value in (policies or {}).items():
        if isinstance(robot, bool) or not isinstance(robot, int | np.integer) or not 0 <= robot < n:
            raise InvalidArgumentError(
                f"policies names robot {robot!r}, but the team has robots 0..{n - 1}",
                hint="keys are robot indices",
            )
        chosen[int(robot)] = value
    instances: dict[object, Policy] = {}
    members: dict[int, list[int]] = {}
    for robot in range(n):
        value = chosen[robot]
        key = id(value) if isinstance(value, Policy) else value
        if key not in instances:
            instances[key] = make_policy(value)
        members.setdefault(id(instances[key]), []).append(robot)
    by_id = {id(p): p for p in instances.values()}
    return [(by_id[k], np.array(v)) for k, v in members.items()]


def simulate(
    scenario: Scenario,
    reasoning="third",
    seed: int = 0,
    *,
    policies: Mapping | None = None,
) -> Trial:
    """Simulate one trial of ``scenario``.

    Parameters
    ----------
    scenario : Scenario
        The world.
    reasoning : str or Policy
        The level of every robot: ``"zero"``, ``"convention"``, ``"first"``,
        ``"second"``, ``"third"`` (and the ``"paper-*"`` levels of
        :mod:`epistemica.sim.paper`), or a :class:`~epistemica.sim.policy.Policy`.
    seed : int
        Trial seed: observation and process noise, and any policy randomness. The same
        seed gives the same noise for every level.
    policies : mapping, optional
        Robot index to level name or policy, overriding ``reasoning`` for that robot.

    Returns
    -------
    Trial
    """
    if not isinstance(scenario, Scenario):
        raise InvalidArgumentError(
            f"expected a Scenario, got {type(scenario).__name__}",
            hint="build one with Scenario(...) or Scenario.paper(...)",
        )
    s, n = scenario, scenario.n_robots
    streams = trial_streams(seed, n)
    groups = _groups(n, reasoning, policies)
    names = [""] * n
    for policy, robots in groups:
        policy.start(s, robots, [streams.policy[r] for r in robots])
        for r in robots:
            names[r] = policy.name
    run = _Run(s, streams)
    for step in range(s.max_steps):
        done = run.done >= 0 if s.mission == "multitask" else None
        obs = run.perceive(step, done)
        controls = np.empty((n, 2))
        started = perf_counter()
        for policy, robots in groups:
            decisions = policy.decide(obs, robots)
            controls[robots] = _checked(decisions.controls, policy, len(robots))
            run.focal[step, robots] = decisions.focal
            run.entropy[step, robots] = decisions.entropy
            run.considered[step, robots] = decisions.considered
            unpruned = decisions.unpruned
            run.unpruned[step, robots] = decisions.considered if unpruned is None else unpruned
            run.record_goal_belief(step, robots, decisions)
        run.time[step] = perf_counter() - started
        if run.advance(step, controls):
            break
    return run.trial(tuple(names), seed)


def _checked(controls: np.ndarray, policy: Policy, count: int) -> np.ndarray:
    controls = np.asarray(controls, dtype=float)
    if controls.shape != (count, 2) or not np.all(np.isfinite(controls)):
        raise InvalidArgumentError(
            f"policy {policy.name!r} returned controls of shape {controls.shape} "
            f"(finite: {bool(np.all(np.isfinite(controls)))}), expected ({count}, 2) finite",
            hint="decide() returns one finite (speed, heading change) row per robot",
        )
    return controls


def _indices(mask: np.ndarray) -> tuple[int, ...]:
    return tuple(int(i) for i in np.flatnonzero(mask))


class _Run:
    """The mutable state of one trial (true poses, counters, records)."""

    def __init__(self, s: Scenario, streams) -> None:
        n, steps = s.n_robots, s.max_steps
        self.s, self.streams = s, streams
        self.sensing = Sensing(s, streams.observation)
        self.poses = np.array(s.starts, dtype=float)
        self.path = [self.poses.copy()]
        self.held = 0
        self.success = False
        self.completion: int | None = None
        self.done = np.full(s.n_goals if s.mission == "multitask" else 0, -1)
        self.focal = np.full((steps, n, n), -1)
        self.entropy = np.full((steps, n), np.nan)
        self.considered = np.zeros((steps, n), dtype=int)
        self.unpruned = np.zeros((steps, n), dtype=int)
        self.knowledge = initial_knowledge(s)
        self.seen_by = dict(s.events)
        self.events: list[tuple] = []
        self.goal_belief = np.zeros((steps, n, s.n_goals))
        self.time = np.zeros(steps)

    def record_goal_belief(self, step: int, robots: np.ndarray, decisions) -> None:
        if decisions.goal_belief is not None:
            self.goal_belief[step, robots] = decisions.goal_belief
            return
        own = decisions.focal[np.arange(len(robots)), robots]  # certainty on the focal goal
        has = own >= 0
        self.goal_belief[step, robots[has], own[has]] = 1.0

    def perceive(self, step: int, done):
        """The team's observations at ``step``, after this step's observation events."""
        settled = self.settled()
        before = self.sensing.known_goals.copy()
        obs = self.sensing.observe(self.poses, step, settled, done)
        for i, g in zip(*np.nonzero(obs.known_goals & ~before), strict=True):
            self.knowledge.discover(g, np.arange(self.s.n_robots) == i)
        if "settle" in self.seen_by and settled.any():
            d = distances(self.poses, self.s.goals)
            for r in np.flatnonzero(settled):
                goal, observers = int(np.argmin(d[r])), self._observers("settle", r)
                if self.knowledge.settle(r, goal, observers):
                    self.events.append((step, "settle", int(r), goal, _indices(observers)))
        return obs._replace(knowledge=self.knowledge)

    def _observers(self, kind: str, robot: int) -> np.ndarray:
        if self.seen_by[kind] == "everyone":
            return np.ones(self.s.n_robots, dtype=bool)
        return self.sensing.visible(self.poses)[:, robot]

    def settled(self) -> np.ndarray:
        if len(self.path) < 2:
            return np.zeros(self.poses.shape[0], dtype=bool)
        still = np.hypot(*(self.path[-1][:, :2] - self.path[-2][:, :2]).T) < _SETTLED
        near = (distances(self.poses, self.s.goals) <= self.s.success_radius).any(axis=1)
        return still & near

    def advance(self, step: int, controls: np.ndarray) -> bool:
        """Apply the controls; True when the trial is over."""
        s = self.s
        controls[:, 0] = np.clip(controls[:, 0], 0.0, s.max_speed)
        controls[:, 1] = np.clip(controls[:, 1], -s.max_turn, s.max_turn)
        poses = move(self.poses, controls, s.dt)
        jitter = np.stack([g.standard_normal(2) for g in self.streams.process])
        poses[:, :2] += np.sqrt(s.process_noise) * jitter
        if s.bounded:
            poses[:, :2] = np.clip(poses[:, :2], 0.0, s.workspace)
        self.poses = poses
        self.path.append(poses.copy())
        if s.mission == "multitask":
            return self._tasks(step)
        if s.valid is not None:
            holds = realises(poses, s.goals, s.success_radius, s.valid)
        else:
            holds = mission_holds(s.mission, poses, s.goals, s.success_radius, s.capacities)
        if holds:
            self.held += 1
        self.success = self.held >= s.dwell
        return self.success

    def _tasks(self, step: int) -> bool:
        near = distances(self.poses, self.s.goals) <= self.s.success_radius  # (n, m)
        for task in np.flatnonzero(near.any(axis=0) & (self.done < 0)):
            self.done[task] = step + 1
            witnesses = self.sensing.task_completed(self.poses, near[:, task], [task])
            if self.seen_by.get("complete") == "everyone":
                witnesses = np.ones_like(witnesses)
                self.sensing.known_done[:, task] = True
            if self.knowledge.complete(task, witnesses):
                done_by = int(np.flatnonzero(near[:, task])[0])
                self.events.append((step + 1, "complete", done_by, int(task), _indices(witnesses)))
        if np.all(self.done >= 0):
            self.success, self.completion = True, step + 1
        return self.success

    def trial(self, names: tuple[str, ...], seed: int) -> Trial:
        steps = len(self.path) - 1
        return Trial(
            success=self.success,
            steps=steps,
            completion_step=self.completion,
            tasks_done=self.done.copy(),
            trajectory=np.stack(self.path),
            focal=self.focal[:steps],
            entropy=self.entropy[:steps],
            considered=self.considered[:steps],
            unpruned=self.unpruned[:steps],
            goal_belief=self.goal_belief[:steps],
            decision_time=self.time[:steps],
            policies=names,
            seed=int(seed),
            events=tuple(self.events),
        )
