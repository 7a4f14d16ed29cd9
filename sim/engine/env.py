"""The simulator as a reinforcement-learning environment: PettingZoo and Gymnasium.

:class:`MissionEnv` is a PettingZoo ``ParallelEnv`` over a :class:`~epistemica.sim.Scenario`
or a mission file (anything with a ``scenario(seed)`` method, such as
:func:`epistemica.mission.load_mission`'s :class:`~epistemica.mission.Mission`: each reset
draws that seed's layout). Every robot is an agent, named as in the mission (``r1``,
``r2``, ...), except the robots given to one of our reasoning levels with ``teammates``.
:class:`RobotEnv` is the Gymnasium view of one robot among such scripted teammates.
Both need the ``env`` extra: ``pip install "epistemica[env]"``.

The environment steps the simulator's own :class:`~epistemica.sim.engine.simulate.TrialRun`
(perception, events, knowledge, dynamics, contacts), or for a collaborative mission its
:class:`~epistemica.sim.engine.joint.JointRun`: given the controls a level would choose
(:meth:`MissionEnv.level_actions`), it runs exactly the trial
:func:`~epistemica.sim.engine.simulate` runs for the same seed.

Spaces (robot ``i``, ``n`` robots, ``m`` goals, ``R`` event rules):

=================  ============================================================================
``pose``           ``(3,)`` float32: its own true pose ``x, y`` (m), heading (rad)
``teammates``      ``(n, 2)`` float32: where it places every robot (noisy, the last estimate
                   for one out of range or sight; its own row exact)
``seen``           ``MultiBinary(n)``: robot ``j`` was observed at this step
``goals``          ``(m, 2)`` float32: the goals it knows of (zeros for the others)
``known_goals``    ``MultiBinary(m)``: the goals it knows of (discovered within range, told,
                   revealed by an event)
``closed``         ``MultiBinary(m)``: goals it knows closed (tasks done, doors shut)
``events``         ``MultiBinary(R)`` (only when the mission has events): it observed an event
                   of rule ``k`` that taught it something, since its last observation
``step``           ``Discrete(max_steps + 1)``: the step
``teammates_know`` ``MultiBinary((n, m))`` (only with ``epistemic=True``): the goals it
                   takes each robot to know of (its own row: the goals it knows of)
action             ``Box`` float32 ``(speed, heading change)`` in ``[0, max_speed] x
                   [-max_turn, max_turn]`` of that robot (values outside are clipped)
=================  ============================================================================

A collaborative mission's robot observes, instead of goals, the tasks it found
(``tasks`` ``(m, 2)``, zeros for the others; ``known_tasks``), how many robots each needs
(``needs``, ``MultiDiscrete``: 0 for a task it does not know), the tasks it knows done
(``done``), where it last saw each teammate (``teammates``) and whom it sees now
(``seen``); ``teammates_know`` is the tasks it knows each robot to know of, the reward
counts tasks done, the shaping potential measures to the nearest task not done
(:mod:`epistemica.sim.engine._env_joint`). Teammates may observe where a robot heads
(``heading`` events): an agent whose action is the one :meth:`MissionEnv.level_actions`
gave it at that step heads where that level heads, any other agent explores.

Positions are bounded: observed positions are clipped into ``[-W, 2W]`` (``W`` the
workspace side), headings wrapped into ``[-pi, pi)``, so that every space is a bounded
float32 ``Box`` (``gymnasium.utils.env_checker.check_env`` passes without a warning).
``state()`` is the global state for a centralised critic (``state_space``: every true pose,
every goal, which goals are open, the step over the step limit, flattened, float32).
Importing this module registers the published protocol's Gymnasium ids
(:mod:`epistemica.sim.engine.env_registry`): ``gymnasium.make("epistemica/Rendezvous-v0")``
is a :class:`RobotEnv` drawing the layouts ``specs/rendezvous.epi`` draws; importing
:mod:`epistemica.envs` registers one id per mission file and generated family besides.

Reward (shared by the team, the same for every agent): the mission's progress made at
this step, ``Δ(held / dwell)`` (steps on which the mission held, towards the ``dwell``
that ends the trial) or, for a multitask mission, ``Δ(tasks done / tasks)``; a trial that
succeeds collects 1 in total. Plus ``shaping`` times the change of a potential, minus the
mean distance (in workspaces) from each robot to its nearest open goal beyond the success
radius (potential-based, so it does not change which policies are optimal). Every agent is
terminated when the mission succeeds, truncated at the step limit; the observation then
returned does not advance the sensors (the last one, with each robot's own pose updated),
so that the trial stays the simulator's. ``render()`` draws the trial so far with
:func:`epistemica.sim.study.figures.plot_trial` (``render_mode="rgb_array"``, matplotlib
needed).

Examples
--------
>>> from epistemica.sim import Scenario
>>> env = MissionEnv(Scenario.paper("rendezvous", 3, 3, seed=0))
>>> observations, infos = env.reset(seed=0)
>>> env.agents, observations["r1"]["teammates"].shape
(['r1', 'r2', 'r3'], (3, 2))
>>> while env.agents:  # everyone plays the convention, through the environment
...     observations, rewards, terminations, truncations, infos = env.step(
...         env.level_actions("convention"))
>>> trial = env.trial()
>>> trial.success, round(sum(env.returns.values()) / 3, 3) > 0.9
(True, True)
"""

from __future__ import annotations

import io
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from epistemica.del_.errors import EpistemicaError, InvalidArgumentError
from epistemica.sim.engine._env_checks import (
    checked_actions,
    checked_keywords,
    checked_options,
    checked_robot,
    checked_seed,
    checked_shaping,
    checked_teammates,
)
from epistemica.sim.engine._env_joint import JointWorld
from epistemica.sim.engine._env_view import GoalWorld, action_space
from epistemica.sim.engine._env_view import controls as controls_of
from epistemica.sim.engine._streams import trial_streams
from epistemica.sim.engine.env_registry import register
from epistemica.sim.engine.joint import JointRun
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.simulate import TrialRun, policy_groups
from epistemica.sim.engine.trial import Trial
from epistemica.sim.kinds.collaborative import CollaborativeScenario
from epistemica.sim.policies.levels import rules_level
from epistemica.sim.study.figures import plot_trial, pyplot

try:
    import gymnasium
    from gymnasium import spaces
    from pettingzoo import ParallelEnv
except ImportError as exc:  # pragma: no cover - the env extra is missing
    raise EpistemicaError(
        "epistemica.sim.engine.env needs gymnasium and pettingzoo",
        hint='install the env extra: pip install "epistemica[env]"',
    ) from exc

__all__ = ["MissionEnv", "RobotEnv"]

#: The scenarios an environment takes as they are (a mission draws one per seed).
WORLDS = (Scenario, CollaborativeScenario)

#: The name a robot driven through the environment has in a trial's ``policies``.
EXTERNAL = "env"


class MissionEnv(ParallelEnv):
    """Every robot of a mission as a PettingZoo agent (see the module notes).

    Parameters
    ----------
    source : Scenario or object with ``scenario(seed)``
        The world: one fixed scenario, or a mission whose layout each reset draws.
    teammates : mapping, optional
        Robot (name or index) to reasoning level (``"third"``, ``"rules-third"``,
        ``"convention"``, ...):
        those robots are driven by the level and are not agents.
    parameters : ActiveParameters, optional
        Parameters of the active-inference levels.
    shaping : float
        Weight of the potential-based shaping term of the reward (0: progress only).
    render_mode : {"rgb_array", None}
    epistemic : bool
        Put the epistemic state in every observation (``teammates_know``).
    normalized : bool
        Actions in ``[-1, 1]²`` (mapped onto ``0 .. max_speed`` and ``-max_turn ..
        max_turn``), as RL libraries expect; default: physical ``(speed, heading change)``,
        as :meth:`level_actions` gives them.
    seed : int, optional
        Seed of the first reset without one (default: the mission's first seed, or 0);
        each later reset without a seed takes the next one.

    A mission's ``teammate`` line (an ad hoc teammate) is not applied: every robot is an
    agent unless ``teammates`` says otherwise (``teammates=mission.policies(seed)`` scripts
    the one of trial ``seed``).
    """

    metadata: ClassVar[dict] = {
        "render_modes": ["rgb_array"],
        "name": "epistemica_mission_v0",
        "render_fps": 4,
    }

    def __init__(
        self,
        source,
        teammates: Mapping | None = None,
        *,
        parameters=None,
        shaping: float = 1.0,
        render_mode: str | None = None,
        seed: int | None = None,
        epistemic: bool = False,
        normalized: bool = False,
    ) -> None:
        if not isinstance(source, WORLDS) and not callable(getattr(source, "scenario", None)):
            raise InvalidArgumentError(
                f"expected a Scenario or a mission, got {type(source).__name__}",
                hint="pass Scenario.paper(...) or epistemica.mission.load_mission(path)",
            )
        if render_mode not in (None, "rgb_array"):
            raise InvalidArgumentError(
                f"render_mode {render_mode!r} is not supported", hint='use "rgb_array" or None'
            )
        study = getattr(getattr(source, "study", None), "seed", 0)
        seed = study if seed is None else checked_seed(seed, "seed")
        self.source, self.parameters, self.render_mode = source, parameters, render_mode
        self.shaping = checked_shaping(shaping)
        self.epistemic, self.normalized = bool(epistemic), bool(normalized)
        self.scenario = self._scenario(seed)
        s = self.scenario
        self.scripted = self._scripted(checked_teammates(teammates))
        self.possible_agents = [r for i, r in enumerate(s.robot_names) if i not in self.scripted]
        if not self.possible_agents:
            raise InvalidArgumentError(
                "every robot is a scripted teammate: no agent is left",
                hint="leave at least one robot out of `teammates`",
            )
        self._index = {name: i for i, name in enumerate(s.robot_names)}
        world = JointWorld if s.kind.joint else GoalWorld
        self.world = world(spaces, s, self.epistemic)
        self._observation_space = self.world.observation_space
        self.state_space = self.world.state_space
        self._action_spaces = {
            r: action_space(spaces, s, self._index[r], self.normalized) for r in s.robot_names
        }
        self._next_seed = seed
        self.agents: list[str] = []
        self.run: TrialRun | JointRun | None = None

    # -- PettingZoo's interface ------------------------------------------------------

    def observation_space(self, agent: str):
        """The observation space (the same object for every agent, every call)."""
        return self._observation_space

    def action_space(self, agent: str):
        """The agent's action space (the same object every call)."""
        return self._action_spaces[agent]

    def reset(self, seed: int | None = None, options: dict | None = None):
        """Start trial ``seed`` (default: the next seed); returns observations and infos."""
        checked_options(options)
        self.seed_ = self._next_seed if seed is None else checked_seed(seed, "reset(seed=...)")
        self._next_seed = self.seed_ + 1
        s = self.scenario = self._scenario(self.seed_)
        self.streams = trial_streams(self.seed_, s.n_robots)
        self.groups = self._start(self.scripted)
        self.run = self.world.start(s, self.streams, self.groups)
        self._advisors: dict[str, list] = {}
        self._advice: dict[str, tuple] = {}  # level_actions' rows and targets, this step
        self.step_count, self._mark = 0, 0
        self.agents = list(self.possible_agents)
        self.returns = dict.fromkeys(self.agents, 0.0)
        self._progress, self._potential = 0.0, self._current_potential()
        self.observations = self.run.perceive(0)
        self._rows = np.array([self._index[a] for a in self.agents], dtype=int)
        speed, turn = s.max_speed[self._rows], s.max_turn[self._rows]
        self._limits = np.stack([0.0 * speed, -turn], axis=1), np.stack([speed, turn], axis=1)
        return self._views(), self._infos()

    def step(self, actions: Mapping):
        """Apply every live agent's ``(speed, heading change)``; the scripted teammates
        decide for themselves."""
        run, s, t = self._running(), self.scenario, self.step_count
        if not self.agents:
            raise InvalidArgumentError("the trial is over", hint="call reset() for another")
        if not isinstance(actions, Mapping):
            raise InvalidArgumentError(
                f"step() takes a mapping from agent to action, got {type(actions).__name__}",
                hint="e.g. {agent: np.array([speed, turn]) for agent in env.agents}",
            )
        unknown = [a for a in actions if a not in self.agents]
        if unknown:
            raise InvalidArgumentError(
                f"actions for unknown agent(s) {unknown}",
                hint=f"the live agents are {self.agents}; scripted teammates decide for themselves",
            )
        controls = np.zeros((s.n_robots, 2))
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise InvalidArgumentError(
                f"no action for agent(s) {missing}", hint="give every agent in env.agents one"
            )
        robots, (low, high) = self._rows, self._limits  # the agents' rows, every step
        given = checked_actions(self.agents, actions)
        chosen = controls_of(s, robots, given) if self.normalized else given
        controls[robots] = np.minimum(np.maximum(chosen, low), high)  # clipped as the run would
        run.decide(t, self.observations, self.groups, controls)
        self.world.declare(run, self._advised(given))
        self._advice = {}
        success = run.advance(t, controls)
        self.step_count = t + 1
        progress = self.world.progress(run)
        now = self._current_potential()
        reward = progress - self._progress + self.shaping * (now - self._potential)
        self._progress, self._potential = progress, now
        over = success or self.step_count >= s.max_steps
        if over:
            self.observations = self.world.last(self.observations, run)
        else:
            self.observations = run.perceive(self.step_count)
        agents = self.agents
        observations, infos = self._views(), self._infos()
        rewards = dict.fromkeys(agents, float(reward))
        for agent in agents:
            self.returns[agent] += float(reward)
        terminations = dict.fromkeys(agents, bool(success))
        truncations = dict.fromkeys(agents, bool(over and not success))
        if over:
            self.agents = []
        return observations, rewards, terminations, truncations, infos

    def state(self) -> np.ndarray:
        """The global state (``state_space``): every true pose, every goal, which goals are
        open and the step over the step limit, flattened (float32)."""
        return self.world.state(self._running(), self.step_count)

    def render(self):
        """The trial so far as an RGB image ``(height, width, 3)`` uint8 (or None)."""
        if self.render_mode is None:
            return None
        self._running()
        buffer = io.BytesIO()
        plot_trial(self.scenario, self.trial(), buffer)
        buffer.seek(0)
        image = pyplot().imread(buffer, format="png")
        return (np.asarray(image)[..., :3] * 255).round().astype(np.uint8)

    def close(self) -> None:
        self.run = None

    # -- beyond the interface ----------------------------------------------------------

    def level_actions(self, level: str) -> dict[str, np.ndarray]:
        """The actions ``level`` would choose for every live agent at this step.

        The level keeps its own state across steps (its beliefs, search timers): call it
        at every step from the reset on. Given these actions every step, the environment
        runs :func:`~epistemica.sim.engine.simulate`'s trial of the same seed.
        """
        self._running()
        if level not in self._advisors:
            robots = [self._index[a] for a in self.possible_agents]
            self._advisors[level] = self._start(dict.fromkeys(robots, level))
        n = self.scenario.n_robots
        controls, steer = np.zeros((n, 2)), np.full(n, -1)
        for policy, robots in self._advisors[level]:
            decisions = policy.decide(self.observations, robots)
            controls[robots] = decisions.controls
            if decisions.steer_to is not None:
                steer[robots] = decisions.steer_to
        actions = {a: controls[self._index[a]] for a in self.agents}
        self._advice = {a: (actions[a].tolist(), int(steer[self._index[a]])) for a in self.agents}
        return actions

    def trial(self) -> Trial:
        """The record of the trial so far (a :class:`~epistemica.sim.Trial`)."""
        run = self._running()
        names = [EXTERNAL] * self.scenario.n_robots
        for policy, robots in self.groups:
            for r in robots:
                names[r] = policy.name
        return run.trial(tuple(names), self.seed_)

    # -- helpers -------------------------------------------------------------------------

    def _scenario(self, seed: int) -> Scenario:
        if isinstance(self.source, WORLDS):
            return self.source
        return self.source.scenario(seed)

    def _scripted(self, teammates: Mapping) -> dict[int, str]:
        s, out = self.scenario, {}
        for robot, level in teammates.items():
            if isinstance(robot, str) and robot in s.robot_names:
                robot = s.robot_names.index(robot)
            if isinstance(robot, bool) or not isinstance(robot, int | np.integer):
                raise InvalidArgumentError(
                    f"teammates names robot {robot!r}",
                    hint=f"robots: {', '.join(s.robot_names)} (or indices 0..{s.n_robots - 1})",
                )
            if not 0 <= robot < s.n_robots:
                raise InvalidArgumentError(
                    f"teammates names robot {robot}", hint=f"indices 0..{s.n_robots - 1}"
                )
            out[int(robot)] = level
        if out:  # build the policies once now: an unknown level fails here, not at reset
            policy_groups(s.n_robots, next(iter(out.values())), out, self.parameters, s.kind)
        return out

    def _start(self, levels: Mapping[int, Any]) -> list:
        """Policy groups for ``levels`` (robot -> level), started on this trial's streams."""
        if not levels:
            return []
        s = self.scenario
        groups = policy_groups(
            s.n_robots, next(iter(levels.values())), levels, self.parameters, s.kind
        )
        policy_streams = trial_streams(self.seed_, s.n_robots).policy  # fresh, unshared
        started = []
        for policy, robots in groups:
            robots = np.array([r for r in robots if r in levels], dtype=int)
            if robots.size:
                policy.start(s, robots, [policy_streams[r] for r in robots])
                started.append((policy, robots))
        return started

    def _running(self) -> TrialRun | JointRun:
        if self.run is None:
            raise InvalidArgumentError("the environment has no trial", hint="call reset() first")
        return self.run

    def _advised(self, given: np.ndarray) -> dict[int, int]:
        """Robot -> task of the agents whose action this step (``given``, rows of
        ``self.agents``) is the one :meth:`level_actions` gave them."""
        out = {}
        for k, (agent, row) in enumerate(zip(self.agents, given.tolist(), strict=True)):
            advice = self._advice.get(agent)
            if advice is not None and row == advice[0]:
                out[int(self._rows[k])] = advice[1]
        return out

    def _views(self) -> dict[str, dict]:
        run = self._running()
        new = run.events[self._mark :]
        self._mark = len(run.events)
        robots = [self._index[a] for a in self.agents]
        views = self.world.views(run, self.observations, self.step_count, new, robots)
        return {a: views[self._index[a]] for a in self.agents}

    def _infos(self) -> dict[str, dict]:
        info = {"step": self.step_count, **self.world.info(self._running())}
        return {a: dict(info) for a in self.agents}

    def _current_potential(self) -> float:
        return self.world.potential(self._running()) if self.shaping else 0.0


#: The keywords of :class:`MissionEnv` that :class:`RobotEnv` passes on.
_OPTIONS = ("parameters", "shaping", "render_mode", "seed", "epistemic", "normalized")


class RobotEnv(gymnasium.Env):
    """One robot of a mission as a Gymnasium environment, its teammates driven by a level.

    Parameters
    ----------
    source : Scenario or object with ``scenario(seed)``
    robot : str or int
        The robot the learner drives (default the first).
    teammates : str, optional
        The reasoning level of every other robot (default: the rules' highest level of
        the mission's kind, ``"rules-third"``, ``"rules"`` on a collaborative mission:
        the teammates the learned policy's results were measured with).
    **options
        ``parameters``, ``shaping``, ``render_mode``, ``seed``, ``epistemic``,
        ``normalized`` of :class:`MissionEnv`.

    Examples
    --------
    >>> from epistemica.sim import Scenario
    >>> env = RobotEnv(Scenario.paper("rendezvous", 2, 2, seed=1), teammates="convention")
    >>> observation, info = env.reset(seed=1)
    >>> observation["pose"].shape, env.action_space.shape
    ((3,), (2,))
    """

    metadata: ClassVar[dict] = MissionEnv.metadata

    def __init__(
        self, source, robot: str | int = 0, teammates: str | None = None, **options
    ) -> None:
        checked_keywords(options, _OPTIONS)
        first = MissionEnv(source, **{k: v for k, v in options.items() if k != "render_mode"})
        names = first.scenario.robot_names
        if teammates is None:
            teammates = rules_level(first.scenario.kind)
        robot = checked_robot(robot, names)
        others = {j: teammates for j in range(len(names)) if j != robot}
        self.multi = MissionEnv(source, others, **options)
        self.agent = names[robot]
        self.render_mode = self.multi.render_mode
        self.observation_space = self.multi.observation_space(self.agent)
        self.action_space = self.multi.action_space(self.agent)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if seed is not None:
            checked_seed(seed, "reset(seed=...)")
        super().reset(seed=seed)
        observations, infos = self.multi.reset(seed=seed, options=options)
        return observations[self.agent], infos[self.agent]

    def step(self, action):
        out = self.multi.step({self.agent: action})
        observations, rewards, terminations, truncations, infos = (x[self.agent] for x in out)
        return observations, rewards, terminations, truncations, infos

    def render(self):
        return self.multi.render()

    def trial(self) -> Trial:
        """The record of the trial so far."""
        return self.multi.trial()


register()
