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

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine._streams import trial_streams
from epistemica.sim.engine.events import STILL, World, firings, observer_indices
from epistemica.sim.engine.joint import JointRun
from epistemica.sim.engine.knowledge import assignment, initial_knowledge
from epistemica.sim.engine.missions import distances, realises
from epistemica.sim.engine.navigation import roadmap_for
from epistemica.sim.engine.obstacles import resolve_contacts
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Sensing
from epistemica.sim.engine.trial import Trial
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.collaborative import CollaborativeScenario
from epistemica.sim.policies.levels import make_level
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.policy import Policy, steer

__all__ = ["TrialRun", "policy_groups", "simulate"]


def policy_groups(
    n: int,
    reasoning,
    policies: Mapping | None,
    parameters: ActiveParameters | None,
    kind: str | MissionKind,
) -> list[tuple[Policy, np.ndarray]]:
    chosen: dict[int, object] = dict.fromkeys(range(n), reasoning)
    for robot, value in (policies or {}).items():
        if isinstance(robot, bool) or not isinstance(robot, int | np.integer) or not 0 <= robot < n:
            raise InvalidArgumentError(
                f"policies names robot {robot!r}, but the team has robots 0..{n - 1}",
                hint="keys are robot indices",
            )
        chosen[int(robot)] = value
    """The policies of a team, each with the robots it drives (``reasoning`` for every
    robot, ``policies`` overriding it per robot; one instance per distinct level of the
    levels of ``kind``)."""
    instances: dict[object, Policy] = {}
    members: dict[int, list[int]] = {}
    for robot in range(n):
        value = chosen[robot]
        key = id(value) if isinstance(value, Policy) else value
        if key not in instances:
            instances[key] = make_level(kind, value, parameters)
        members.setdefault(id(instances[key]), []).append(robot)
    by_id = {id(p): p for p in instances.values()}
    return [(by_id[k], np.array(v)) for k, v in members.items()]


def simulate(
    scenario: Scenario | CollaborativeScenario,
    reasoning="third",
    seed: int = 0,
    *,
    policies: Mapping | None = None,
    parameters: ActiveParameters | None = None,
    navigate: bool = True,
) -> Trial:
    """Simulate one trial of ``scenario``.

    Parameters
    ----------
    scenario : Scenario or CollaborativeScenario
        The world (a joint mission's is a
        :class:`~epistemica.sim.kinds.collaborative.CollaborativeScenario`).
    reasoning : str or Policy
        The level of every robot: a name of the levels of the scenario's kind
        (:func:`epistemica.sim.policies.levels.level_names`: for goal missions ``"zero"``,
        ``"convention"``, the planner's ``"first"``, ``"second"``, ``"third"``, the rules'
        ``"rules-first"`` ... ``"rules-third"``, the ablations and the ``"paper-*"``
        levels), or a :class:`~epistemica.sim.policies.policy.Policy`.
    seed : int
        Trial seed: observation and process noise, and any policy randomness. The same
        seed gives the same noise for every level.
    policies : mapping, optional
        Robot index to level name or policy, overriding ``reasoning`` for that robot.
    parameters : ActiveParameters or CollaborativeParameters, optional
        Rules and constants of the levels named (default: the kind's,
        :func:`~epistemica.sim.policies.levels.parameters_for`; a mission's ``policy`` line).
    navigate : bool, optional
        With obstacles, a robot that moves towards the goal it heads for and whose straight
        way is blocked drives round the walls (:mod:`~epistemica.sim.engine.navigation`);
        False drives every control as the policy gave it (default True).

    Returns
    -------
    Trial
    """
    if not isinstance(scenario, Scenario | CollaborativeScenario):
        raise InvalidArgumentError(
            f"expected a Scenario, got {type(scenario).__name__}",
            hint="build one with Scenario(...) or Scenario.paper(...)",
        )
    if not isinstance(navigate, bool):
        raise InvalidArgumentError(
            f"navigate must be true or false, got {navigate!r}", hint="navigate=False"
        )
    s, n = scenario, scenario.n_robots
    streams = trial_streams(seed, n)
    groups = policy_groups(n, reasoning, policies, parameters, s.kind)
    names = [""] * n
    for policy, robots in groups:
        policy.start(s, robots, [streams.policy[r] for r in robots])
        for r in robots:
            names[r] = policy.name
    run = _run(s, streams, groups, navigate)
    for step in range(s.max_steps):
        obs = run.perceive(step)
        controls = np.empty((n, 2))
        started = perf_counter()
        run.decide(step, obs, groups, controls)
        run.time[step] = perf_counter() - started
        if run.advance(step, controls):
            break
    return run.trial(tuple(names), seed)


def _run(s, streams, groups, navigate: bool = True) -> TrialRun | JointRun:
    """The run state of the scenario's kind: a joint mission's world is the joint run's,
    with what the team's levels share (full communication: ``oracle``)."""
    if not s.kind.joint:
        return TrialRun(s, streams, navigate)
    shares = {getattr(policy, "shares", "") for policy, _ in groups}
    if len(shares) > 1:
        raise InvalidArgumentError(
            "levels that share what they see and levels that do not play the same world",
            hint="give every robot of a collaborative mission one level",
        )
    return JointRun(s, streams, shares.pop())


def _checked(controls: np.ndarray, policy: Policy, count: int) -> np.ndarray:
    controls = np.asarray(controls, dtype=float)
    if controls.shape != (count, 2) or not np.all(np.isfinite(controls)):
        raise InvalidArgumentError(
            f"policy {policy.name!r} returned controls of shape {controls.shape} "
            f"(finite: {bool(np.all(np.isfinite(controls)))}), expected ({count}, 2) finite",
            hint="decide() returns one finite (speed, heading change) row per robot",
        )
    return controls


def _record(step: int, rule, firing, s: Scenario) -> tuple:
    """``(step, name, *arguments, observers)`` of an event, robots and goals by index."""
    index = {**{r: i for i, r in enumerate(s.robot_names)},
             **{g: j for j, g in enumerate(s.goal_names)}}  # fmt: skip
    arguments = tuple(index.get(firing.binding.get(p, ""), -1) for p, _ in rule.parameters)
    return (step, rule.name, *arguments, observer_indices(firing.observation, s.robot_names))


class TrialRun:
    """The mutable state of one trial (true poses, counters, records): :func:`simulate`
    and the environment of :mod:`epistemica.sim.engine.env` step the same one, so a trial run
    either way is the same trial.

    Each step: :meth:`perceive`, :meth:`decide` (for the robots a policy drives),
    :meth:`advance`; :meth:`trial` is the record so far.
    """

    def __init__(self, s: Scenario, streams, navigate: bool = True) -> None:
        n, steps = s.n_robots, s.max_steps
        self.s, self.streams = s, streams
        self.sensing = Sensing(s, streams.observation)
        self.settles = np.full((n, n), -1)  # who saw whom settle where, this step
        self.poses = np.array(s.starts, dtype=float)
        self.path = [self.poses.copy()]
        self.held = 0
        self.success = False
        self.completion: int | None = None
        self.done = np.full(s.n_goals if s.kind.tasks else 0, -1)
        self.focal = np.full((steps, n, n), -1)
        self.entropy = np.full((steps, n), np.nan)
        self.considered = np.zeros((steps, n), dtype=int)
        self.unpruned = np.zeros((steps, n), dtype=int)
        self.modelled = np.zeros((steps, n, n), dtype=int)
        self.knowledge = initial_knowledge(s)
        self.open = ~s.closed
        self.first_reached = np.full(s.n_goals, -1)
        self.events: list[tuple] = []
        self.goal_belief = np.zeros((steps, n, s.n_goals))
        self.teammate_types: np.ndarray | None = None  # (steps, n, n, T) once a policy keeps them
        self.estimates = np.zeros((steps, n, n, 2))
        self.time = np.zeros(steps)
        # (steps, n, n, m): the goals robot i takes robot j to know of (its own on the
        # diagonal), kept only where goals are unknown to some; (steps, m) goals closed.
        tracked = bool(self.knowledge.state.tracked)
        self.known = np.ones((steps, n, n, s.n_goals), dtype=bool) if tracked else None
        self.closed = np.zeros((steps, s.n_goals), dtype=bool)
        self.noted = -1  # the number of observations the knowledge had when last noted
        self.roadmap = roadmap_for(s) if navigate else None  # the way round known walls

    def decide(self, step: int, obs, groups, controls: np.ndarray) -> None:
        """Each group's controls at ``step`` into ``controls`` (rows of its robots), its
        decisions into the record."""
        n = self.s.n_robots
        for policy, robots in groups:
            view = self.everything(obs) if getattr(policy, "shares", "") else obs
            decisions = policy.decide(view, robots)
            controls[robots] = _checked(decisions.controls, policy, len(robots))
            if self.roadmap is not None:
                own = decisions.focal[np.arange(len(robots)), robots]
                controls[robots] = self.around_walls(robots, own, controls[robots])
            self.focal[step, robots] = decisions.focal
            self.entropy[step, robots] = decisions.entropy
            self.considered[step, robots] = decisions.considered
            unpruned = decisions.unpruned
            self.unpruned[step, robots] = decisions.considered if unpruned is None else unpruned
            modelled = decisions.modelled
            if modelled is None:
                modelled = np.repeat(np.asarray(decisions.considered)[:, None], n, axis=1)
            self.modelled[step, robots] = modelled
            self.record_goal_belief(step, robots, decisions)
            if decisions.teammate_types is not None:
                if self.teammate_types is None:
                    shape = (len(self.focal), n, *np.shape(decisions.teammate_types)[1:])
                    self.teammate_types = np.full(shape, np.nan)
                self.teammate_types[step, robots] = decisions.teammate_types

    def everything(self, obs):
        """``obs`` as a level with full communication sees it (``oracle``): every pose
        exact, every goal known, the closed ones known closed."""
        n, m = self.s.n_robots, self.s.n_goals
        return obs._replace(
            poses=np.broadcast_to(self.poses, (n, *self.poses.shape)).copy(),
            seen=np.ones((n, n), dtype=bool),
            last_seen=np.full((n, n), obs.step),
            known_goals=np.ones((n, m), dtype=bool),
            known_done=np.broadcast_to(~self.open, (n, m)).copy(),
        )

    def around_walls(self, robots: np.ndarray, goals: np.ndarray, controls: np.ndarray):
        """The controls of ``robots`` heading for ``goals`` (-1: none), each that moves
        and whose straight way to its goal is blocked turned for the roadmap's way round
        (:mod:`~epistemica.sim.engine.navigation`)."""
        s, out = self.s, controls.copy()
        for row, (robot, goal) in enumerate(zip(robots, goals, strict=True)):
            if goal < 0 or controls[row, 0] <= 0:
                continue
            pose = self.poses[robot]
            radius = 0.0 if s.robot_radius is None else float(s.robot_radius[robot])
            place = s.goals[goal]
            target = self.roadmap.waypoint(pose[:2], place, radius)
            if target is not None and target is not place:  # blocked: the way round
                limits = s.max_speed[[robot]], s.max_turn[[robot]]
                out[row] = steer(pose[None], target[None], *limits, s.dt)[0]
        return out

    def record_goal_belief(self, step: int, robots: np.ndarray, decisions) -> None:
        if decisions.goal_belief is not None:
            self.goal_belief[step, robots] = decisions.goal_belief
            return
        own = decisions.focal[np.arange(len(robots)), robots]  # certainty on the focal goal
        has = own >= 0
        self.goal_belief[step, robots[has], own[has]] = 1.0

    def perceive(self, step: int):
        """The team's observations at ``step``, after this step's observation events."""
        # The events first: a robot sees the world as this step's events left it (a goal
        # an event opens now is not seen closed, and then known closed for good).
        self._events(step, arrivals=False)
        settled = self.settled()
        before, before_closed = self.sensing.known_goals.copy(), self.sensing.known_done.copy()
        obs = self.sensing.observe(self.poses, step, settled, ~self.open)
        alone = np.eye(self.s.n_robots, dtype=bool)
        for i, g in zip(*np.nonzero(obs.known_goals & ~before), strict=True):
            self.knowledge.discover(g, alone[i])
        for i, g in zip(*np.nonzero(obs.known_done & ~before_closed), strict=True):
            self.knowledge.notice_closed(g, alone[i])
        for i, g in zip(*np.nonzero(before_closed & ~obs.known_done), strict=True):
            self.knowledge.notice_open(g, alone[i])  # only events reopen goals
        known_goals, known_done = obs.known_goals, obs.known_done
        if self.s.events:  # what the events taught: goals revealed, closed, reopened
            for i in range(self.s.n_robots):
                known_goals[i] |= self.knowledge.knows_goals((i,))
                known_done[i] = self.knowledge.knows_done((i,))
        self.estimates[step] = obs.poses[..., :2]
        self.closed[step] = ~self.open
        self._note_known(step)
        settles, self.settles = self.settles, np.full_like(self.settles, -1)
        return obs._replace(knowledge=self.knowledge, settles=settles if self.s.events else None)

    def _note_known(self, step: int) -> None:
        """Who takes whom to know of which goals at ``step`` (recomputed only when the
        knowledge took in an observation since the last step)."""
        if self.known is None:
            return
        count = len(self.knowledge.state)
        if count == self.noted:
            self.known[step] = self.known[step - 1]
            return
        self.noted, n = count, self.s.n_robots
        for i in range(n):
            for j in range(n):
                self.known[step, i, j] = self.knowledge.knows_goals((i,) if i == j else (i, j))

    def _events(self, step: int, arrivals: bool) -> None:
        """Fire the mission's event rules at ``step``: arrivals (``G is reached``) right
        after the robots move, the others when they perceive."""
        s = self.s
        if not any((rule.trigger.kind == "reached") == arrivals for rule in s.events):
            return
        world = World(
            step,
            self.poses,
            self.path[-2] if len(self.path) > 1 else None,
            s.goals,
            self.open.copy(),
            self.first_reached == step,
            self.sensing.visible(self.poses),
            self.sensing.sensing_range,
            s.success_radius,
            s.sensors,
            s.robot_names,
            s.goal_names,
        )
        for rule, firing in firings(s.events, world, arrivals):
            self.open[list(firing.closes)] = False
            self.open[list(firing.opens)] = True
            self._note_settle(firing.observation)
            if self.knowledge.observe(firing.observation):
                self.events.append(_record(step, rule, firing, s))

    def _note_settle(self, observation) -> None:
        """Who saw whom settle where (``Observations.settles``), news or not."""
        pair = assignment(observation.suggests)
        if pair is not None:
            robot, goal = pair
            watchers = [i for i, r in enumerate(self.s.robot_names) if r in observation.full]
            self.settles[watchers, self.s.robot_names.index(robot)] = self.s.goal_names.index(goal)

    def settled(self) -> np.ndarray:
        if len(self.path) < 2:
            return np.zeros(self.poses.shape[0], dtype=bool)
        still = np.hypot(*(self.path[-1][:, :2] - self.path[-2][:, :2]).T) < STILL
        near = (distances(self.poses, self.s.goals) <= self.s.success_radius).any(axis=1)
        return still & near

    def advance(self, step: int, controls: np.ndarray) -> bool:
        """Apply the controls; True when the trial is over."""
        s = self.s
        controls[:, 0] = np.clip(controls[:, 0], 0.0, s.max_speed)
        controls[:, 1] = np.clip(controls[:, 1], -s.max_turn, s.max_turn)
        poses = np.array(s.dynamics.step(self.poses, controls, s.dt), dtype=float)
        jitter = np.stack([g.standard_normal(2) for g in self.streams.process])
        poses[:, :2] += np.sqrt(s.process_noise) * jitter
        if s.bounded:
            poses[:, :2] = np.clip(poses[:, :2], 0.0, s.workspace)
        if s.contacts:
            radii = np.zeros(s.n_robots) if s.robot_radius is None else s.robot_radius
            poses = resolve_contacts(self.poses, poses, radii, s.obstacles)
        self.poses = poses
        self.path.append(poses.copy())
        near = distances(poses, s.goals) <= s.success_radius  # (n, m)
        self.first_reached[near.any(axis=0) & self.open & (self.first_reached < 0)] = step + 1
        if s.kind.tasks:
            return self._tasks(step, near)
        self._events(step + 1, arrivals=True)
        if self.open.all():
            holds = self._holds(poses, s.goals, s.capacities, s.valid)
        else:
            holds = self._holds_open(poses)
        if holds:
            self.held += 1
        self.success = self.held >= s.dwell
        return self.success

    def _holds(self, poses, goals, capacities, valid) -> bool:
        s = self.s
        if valid is not None:
            return valid.size > 0 and realises(poses, goals, s.success_radius, valid)
        return s.kind.holds(poses, goals, s.success_radius, capacities)

    def _holds_open(self, poses) -> bool:
        """Whether the mission holds over the goals still open (renumbered)."""
        s, keep = self.s, np.flatnonzero(self.open)
        if keep.size == 0:
            return False
        valid = s.valid
        if valid is not None:
            remap = np.full(s.n_goals, -1)
            remap[keep] = np.arange(keep.size)
            valid = remap[valid[np.isin(valid, keep).all(axis=1)]]
        capacities = None if s.capacities is None else np.asarray(s.capacities)[keep]
        return self._holds(poses, s.goals[keep], capacities, valid)

    def _tasks(self, step: int, near: np.ndarray) -> bool:
        for task in np.flatnonzero(near.any(axis=0) & (self.done < 0)):
            self.done[task] = step + 1
            self.open[task] = False
        self._events(step + 1, arrivals=True)
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
            modelled=self.modelled[:steps],
            estimates=self.estimates[:steps],
            goal_belief=self.goal_belief[:steps],
            decision_time=self.time[:steps],
            policies=names,
            seed=int(seed),
            events=tuple(self.events),
            knowledge=self.knowledge,
            teammate_types=None if self.teammate_types is None else self.teammate_types[:steps],
            known_goals=None if self.known is None else self.known[:steps],
            closed_goals=self.closed[:steps],
        )
