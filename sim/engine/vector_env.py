"""Many trials of a mission family stepped at once, as arrays: an environment for learners
that need millions of steps.

:class:`VectorMissionEnv` keeps ``num_envs`` copies of a family's trial (a
:class:`~epistemica.sim.Scenario` or anything with ``scenario(seed)``, such as
:class:`~epistemica.sim.engine.env_registry.PaperFamily` or a mission file) and steps them together
with numpy: every robot of every copy is an agent, actions are one ``(num_envs, n, 2)``
array, observations one dict of arrays with leading ``(num_envs, n)`` (the fields of
:mod:`epistemica.sim.engine.env`: ``pose``, ``teammates``, ``seen``, ``goals``, ``known_goals``,
``step``), rewards the team's, ``(num_envs,)``. A copy whose trial ends (success or the
step limit) starts the family's next seed at once; the observation returned for it is the
new trial's first (its ``terminated`` or ``truncated`` says the old one ended).

The world is the simulator's (:mod:`epistemica.sim.engine.simulate`): the same dynamics
(:func:`epistemica.aif.motion.move`), the paper sensor (positions plus ``N(0,
position_noise)``, within the sensing range), goals discovered within the discovery range
or shown by a teammate seen settled at them, process noise, the workspace bound, the
mission's success rule held for ``dwell`` steps and the reward of
:class:`~epistemica.sim.engine.env.MissionEnv` (progress plus ``shaping`` times the change of the
distance potential). The noise comes from one generator per batch, so a copy's trial is not
``simulate``'s trial of the same seed (with no noise it is: tests/sim/test_vector_env.py).
Families with observation events, obstacles, robot discs, closed goals, multitask or
collaborative missions or other sensors are refused: step them with
:class:`~epistemica.sim.engine.env.MissionEnv`.

Examples
--------
>>> from epistemica.sim.engine.env_registry import PaperFamily
>>> env = VectorMissionEnv(PaperFamily("rendezvous", 3, 3), num_envs=4)
>>> observations = env.reset(seed=0)
>>> observations["teammates"].shape
(4, 3, 3, 2)
>>> observations, rewards, terminated, truncated = env.step(np.zeros((4, 3, 2)))
>>> rewards.shape, env.seeds.tolist()
((4,), [0, 1, 2, 3])
"""

from __future__ import annotations

import numpy as np

from epistemica.aif.motion import turn_then_move
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine._env_checks import checked_count, checked_seed, checked_shaping
from epistemica.sim.engine.dynamics import PaperSensor, Unicycle
from epistemica.sim.engine.events import STILL
from epistemica.sim.engine.scenario import Scenario

__all__ = ["VectorMissionEnv"]


class VectorMissionEnv:
    """``num_envs`` trials of a family stepped together (see the module notes).

    Parameters
    ----------
    source : Scenario or object with ``scenario(seed)``
    num_envs : int
        Copies stepped at once.
    shaping : float
        Weight of the potential-based shaping term of the reward.
    normalized : bool
        Actions in ``[-1, 1]²`` (as :class:`~epistemica.sim.engine.env.MissionEnv` with
        ``normalized=True``); default physical ``(speed, heading change)``.
    """

    def __init__(
        self, source, num_envs: int, shaping: float = 1.0, normalized: bool = False
    ) -> None:
        num_envs = checked_count(num_envs, "num_envs")
        if not isinstance(source, Scenario) and not callable(getattr(source, "scenario", None)):
            raise InvalidArgumentError(
                f"expected a Scenario or a mission family, got {type(source).__name__}",
                hint="pass Scenario.paper(...), PaperFamily(...) or load_mission(path)",
            )
        self.source, self.num_envs = source, num_envs
        self.shaping, self.normalized = checked_shaping(shaping), bool(normalized)
        self.scenarios: list[Scenario] = []
        first = self._scenario(0)
        self.n, self.m = first.n_robots, first.n_goals

    # -- the interface -----------------------------------------------------------------

    def reset(self, seed: int = 0) -> dict[str, np.ndarray]:
        """Start copy ``k`` on the family's seed ``seed + k``; the first observations."""
        seed = checked_seed(seed, "reset(seed=...)")
        self.rng = np.random.default_rng(seed)
        self.next_seed = seed + self.num_envs
        self.seeds = np.arange(seed, seed + self.num_envs)
        self.scenarios = [self._scenario(int(k)) for k in self.seeds]
        shape = (self.num_envs, self.n)
        self.goals = np.zeros((self.num_envs, self.m, 2))
        self.poses = np.zeros((*shape, 3))
        self.estimates = np.zeros((*shape, self.n, 3))
        self.known = np.zeros((*shape, self.m), dtype=bool)
        self.seen = np.zeros((*shape, self.n), dtype=bool)
        self.limits = np.zeros((*shape, 2))
        self.steps = np.zeros(self.num_envs, dtype=int)
        self.held = np.zeros(self.num_envs, dtype=int)
        self.potentials = np.zeros(self.num_envs)
        self.settled = np.zeros(shape, dtype=bool)
        for k in range(self.num_envs):
            self._start(k)
        self._arrays()
        self._perceive()
        return self._views()

    def step(self, actions) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray]:
        """Apply ``(num_envs, n, 2)`` actions; observations, rewards, terminated, truncated."""
        if not self.scenarios:
            raise InvalidArgumentError("the environment has no trials", hint="call reset() first")
        controls = self._controls(actions)
        controls[..., 0] *= self.dt  # the distance moved this step
        before = self.poses
        moved = turn_then_move(before, controls, 1.0)
        moved[..., :2] += np.sqrt(self.process_noise)[:, None, None] * self.rng.standard_normal(
            (self.num_envs, self.n, 2)
        )
        inside = np.clip(moved[..., :2], 0.0, self.workspace[:, None, None])
        moved[..., :2] = np.where(self.bounded[:, None, None], inside, moved[..., :2])
        self.poses = moved
        d = _distances(moved, self.goals)  # (N, n, m)
        still = np.hypot(*(moved[..., :2] - before[..., :2]).transpose(2, 0, 1)) < STILL
        self.settled = still & (d <= self.radius[:, None, None]).any(axis=2)
        holds = self._holds(d)
        dwell = self.dwell
        progress = np.minimum(self.held, dwell) / dwell
        self.held += holds
        self.steps += 1
        now = _potential(d, self.radius, self.workspace)
        rewards = np.minimum(self.held, dwell) / dwell - progress
        rewards += self.shaping * (now - self.potentials)
        self.potentials = now
        terminated = self.held >= dwell
        truncated = ~terminated & (self.steps >= self.max_steps)
        ended = np.flatnonzero(terminated | truncated)
        for k in ended:
            self.scenarios[k] = self._scenario(self.next_seed)
            self.seeds[k], self.next_seed = self.next_seed, self.next_seed + 1
            self._start(int(k))
        if ended.size:
            self._arrays()
        self._perceive()
        return self._views(), rewards, terminated, truncated

    # -- helpers -------------------------------------------------------------------------

    def _scenario(self, seed: int) -> Scenario:
        s = self.source if isinstance(self.source, Scenario) else self.source.scenario(seed)
        _check_plain(s)
        if self.scenarios and (s.n_robots, s.n_goals) != (self.n, self.m):
            raise InvalidArgumentError(
                f"seed {seed} of the family has {s.n_robots} robots and {s.n_goals} goals, "
                f"the batch {self.n} and {self.m}",
                hint="a family of one team size and goal count",
            )
        return s

    def _start(self, k: int) -> None:
        """Copy ``k`` at the start of its scenario's trial."""
        s = self.scenarios[k]
        self.goals[k] = s.goals
        self.poses[k] = s.starts
        centre = np.array([s.workspace / 2, s.workspace / 2, 0.0])
        self.estimates[k] = centre
        self.known[k] = True if s.known_goals is None else s.known_goals
        self.limits[k] = np.stack([s.max_speed, s.max_turn], axis=1)
        self.steps[k], self.held[k] = 0, 0
        self.settled[k] = False
        d = _distances(self.poses[k : k + 1], s.goals[None])
        self.potentials[k] = _potential(d, np.array([s.success_radius]), np.array([s.workspace]))[0]

    def _arrays(self) -> None:
        """Per-copy parameters as arrays (rebuilt when a copy starts a new scenario)."""
        ss = self.scenarios
        self.dt = np.array([s.dt for s in ss])[:, None]
        self.process_noise = np.array([s.process_noise for s in ss])
        self.position_noise = np.array([s.position_noise for s in ss])
        self.bounded = np.array([s.bounded for s in ss])
        self.workspace = np.array([s.workspace for s in ss])
        self.radius = np.array([s.success_radius for s in ss])
        self.dwell = np.array([s.dwell for s in ss])
        self.max_steps = np.array([s.max_steps for s in ss])
        sensing = [np.inf if s.sensing_range is None else s.sensing_range for s in ss]
        self.sensing = np.array(sensing)
        discovery = [
            s.discovery_range if s.discovery_range is not None else min(r, 10.0)
            for s, r in zip(ss, sensing, strict=True)
        ]
        self.discovery = np.array(discovery)

    def _controls(self, actions) -> np.ndarray:
        try:
            a = np.asarray(actions, dtype=float)
        except (TypeError, ValueError):
            a = np.zeros(0)
        if a.shape != (self.num_envs, self.n, 2) or not np.isfinite(a).all():
            raise InvalidArgumentError(
                f"actions must be a finite ({self.num_envs}, {self.n}, 2) array, got shape "
                f"{a.shape}",
                hint="one (speed, heading change) row per robot of every copy",
            )
        if self.normalized:
            a = np.clip(a, -1.0, 1.0)
            return np.stack(
                [(a[..., 0] + 1.0) / 2.0 * self.limits[..., 0], a[..., 1] * self.limits[..., 1]],
                axis=-1,
            )
        speed = np.clip(a[..., 0], 0.0, self.limits[..., 0])
        return np.stack([speed, np.clip(a[..., 1], -self.limits[..., 1], self.limits[..., 1])], -1)

    def _perceive(self) -> None:
        """The sensors at the current poses."""
        n = self.n
        pos = self.poses[..., :2]
        gaps = np.linalg.norm(pos[:, :, None] - pos[:, None], axis=-1)  # (N, n, n)
        seen = gaps <= self.sensing[:, None, None]
        measured = np.broadcast_to(self.poses[:, None], self.estimates.shape).copy()
        noise = self.rng.standard_normal((self.num_envs, n, n, 2))
        measured[..., :2] += np.sqrt(self.position_noise)[:, None, None, None] * noise
        self.estimates = np.where(seen[..., None], measured, self.estimates)
        idx = np.arange(n)
        self.estimates[:, idx, idx] = self.poses
        d = _distances(self.poses, self.goals)
        self.known |= d <= self.discovery[:, None, None]
        shown = (d <= self.radius[:, None, None]) & self.settled[..., None]  # (N, n, m)
        self.known |= np.einsum("kij,kjg->kig", seen.astype(int), shown.astype(int)) > 0
        self.seen = seen

    def _holds(self, d: np.ndarray) -> np.ndarray:
        near = d <= self.radius[:, None, None]
        every_robot_near = near.any(axis=2).all(axis=1)
        out = np.zeros(self.num_envs, dtype=bool)
        for k in np.flatnonzero(every_robot_near):
            s = self.scenarios[k]
            if s.kind.gathers:
                out[k] = near[k].all(axis=0).any()
            else:
                out[k] = s.kind.holds(self.poses[k], s.goals, s.success_radius, s.capacities)
        return out

    def _views(self) -> dict[str, np.ndarray]:
        goals = np.where(self.known[..., None], self.goals[:, None], 0.0)
        n = self.n
        idx = np.arange(n)
        return {
            "pose": self.estimates[:, idx, idx].astype(np.float32),
            "teammates": self.estimates[..., :2].astype(np.float32),
            "seen": self.seen.astype(np.int8),
            "goals": goals.astype(np.float32),
            "known_goals": self.known.astype(np.int8),
            "step": self.steps.copy(),
        }


def _distances(poses: np.ndarray, goals: np.ndarray) -> np.ndarray:
    """``(N, n, m)`` distances from every robot to every goal of its copy."""
    return np.linalg.norm(poses[..., None, :2] - goals[:, None], axis=-1)


def _potential(d: np.ndarray, radius: np.ndarray, workspace: np.ndarray) -> np.ndarray:
    """Minus the mean distance (in workspaces) from each robot to its nearest goal beyond
    the success radius (:func:`epistemica.sim.engine._env_view.potential`, per copy)."""
    beyond = np.maximum(d.min(axis=2) - radius[:, None], 0.0)
    return -beyond.sum(axis=1) / (d.shape[1] * workspace)


def _check_plain(s: Scenario) -> None:
    """Refuse what the batched world does not model (the module notes)."""
    if s.kind.joint:
        raise InvalidArgumentError(
            f"the vectorised environment does not model a {s.kind} mission",
            hint="step such missions with epistemica.sim.engine.env.MissionEnv",
        )
    why = []
    if s.events:
        why.append("observation events")
    if s.obstacles or s.robot_radius is not None:
        why.append("obstacles or robot discs")
    if s.closed is not None and np.any(s.closed):
        why.append("closed goals")
    if s.kind.tasks:
        why.append(f"a {s.kind} mission")
    if not isinstance(s.sensor, PaperSensor) or not isinstance(s.dynamics, Unicycle):
        why.append("a sensor or dynamics other than the paper's")
    if s.valid is not None:
        why.append("a valid-configurations table")
    if why:
        raise InvalidArgumentError(
            f"the vectorised environment does not model {', '.join(why)}",
            hint="step such missions with epistemica.sim.engine.env.MissionEnv",
        )
