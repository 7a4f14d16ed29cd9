"""The policy interface: how a robot (or a group of robots) chooses its controls.

A policy decides for a group of robots at once, so work shared across robots is done once
per step. The simulator calls :meth:`Policy.start` once per trial with the robots the
policy drives and their random streams, then :meth:`Policy.decide` every step with the
team's :class:`~epistemica.sim.engine.sensing.Observations`. A policy sees only what its robots
perceive (``observations.poses[i]`` for robot ``i``), never the true state.

To plug in a rule of your own, subclass :class:`Policy` and implement :meth:`decide`, or
wrap a per-robot function with :class:`FunctionPolicy`.

Examples
--------
>>> import numpy as np
>>> from epistemica.sim import Scenario, simulate
>>> def stand_still(robot, observations, scenario):
...     return 0.0, 0.0
>>> trial = simulate(Scenario.paper("rendezvous", 2, 2, seed=0), FunctionPolicy(stand_still))
>>> bool(np.all(trial.trajectory[-1] == trial.trajectory[0]))
True
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np

from epistemica.aif.motion import wrap_angle
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Observations

__all__ = ["Decisions", "FunctionPolicy", "Policy", "steer"]


class Decisions(NamedTuple):
    """A group's decisions at one step, one row per deciding robot.

    Attributes
    ----------
    controls : numpy.ndarray
        ``(r, 2)`` ``(speed, heading change)``.
    focal : numpy.ndarray
        ``(r, n)`` the configuration each robot acts on (goal index per robot, -1 where
        it has none).
    entropy : numpy.ndarray
        ``(r,)`` entropy (nats) of each robot's belief; NaN for policies without one.
    considered : numpy.ndarray
        ``(r,)`` configurations each robot considered.
    goal_belief : numpy.ndarray or None
        ``(r, m)``: each robot's belief about its own goal (the marginal of its belief over
        configurations); ``None``: certainty on its focal goal.
    modelled : numpy.ndarray or None
        ``(r, n)``: for each deciding robot, the size of the set of configurations it
        models each teammate keeping (its own set's size on its own column); ``None``: as
        ``considered`` throughout (no nested sets).
    unpruned : numpy.ndarray or None
        ``(r,)`` configurations each robot had before pruning by what it knows
        (:class:`~epistemica.sim.engine.knowledge.TeamKnowledge`); ``None``: as ``considered``.
    teammate_types : numpy.ndarray or None
        ``(r, n, T)``: each deciding robot's posterior over the behaviour library
        :data:`epistemica.aif.teammates.TYPES` of every robot (its own row unused);
        ``None``: no teammate models.
    steer_to : numpy.ndarray or None
        ``(r,)`` joint missions: the task each robot heads to (-1 exploring, -2 fetching a
        teammate, -3 waiting for helpers); ``None`` elsewhere.
    """

    controls: np.ndarray
    focal: np.ndarray
    entropy: np.ndarray
    considered: np.ndarray
    goal_belief: np.ndarray | None = None
    unpruned: np.ndarray | None = None
    modelled: np.ndarray | None = None
    teammate_types: np.ndarray | None = None
    steer_to: np.ndarray | None = None

    @classmethod
    def of(cls, controls, focal, entropy=None, considered=None) -> Decisions:
        """Decisions from controls and focal rows; entropy NaN and considered 1 by default."""
        controls = np.asarray(controls, dtype=float).reshape(-1, 2)
        r = controls.shape[0]
        return cls(
            controls,
            np.asarray(focal, dtype=int).reshape(r, -1),
            np.full(r, np.nan) if entropy is None else np.asarray(entropy, dtype=float),
            np.ones(r, dtype=int) if considered is None else np.asarray(considered, dtype=int),
        )


class Policy:
    """Base class of the simulator's policies.

    Attributes
    ----------
    name : str
        Shown in results.
    """

    name = "policy"

    def start(
        self, scenario: Scenario, robots: Sequence[int], generators: Sequence[np.random.Generator]
    ) -> None:
        """Called once per trial before the first step.

        ``robots`` are the indices this policy drives; ``generators`` their policy streams
        (for any deliberate randomness; never use the global RNG).
        """
        self.scenario = scenario
        self.robots = np.asarray(robots, dtype=int)
        self.generators = dict(zip(self.robots.tolist(), generators, strict=True))

    def decide(self, observations: Observations, robots: np.ndarray) -> Decisions:
        """The controls of ``robots`` (a subset of the started ones) at this step."""
        raise NotImplementedError("a Policy subclass implements decide()")


class FunctionPolicy(Policy):
    """A policy from a function ``f(robot, observations, scenario) -> (speed, change)``.

    Examples
    --------
    >>> FunctionPolicy(lambda robot, obs, scenario: (1.0, 0.0), name="forward").name
    'forward'
    """

    def __init__(self, function: Callable, name: str | None = None) -> None:
        if not callable(function):
            raise TypeError("FunctionPolicy needs a callable f(robot, observations, scenario)")
        self.function = function
        self.name = name or getattr(function, "__name__", "function")

    def decide(self, observations: Observations, robots: np.ndarray) -> Decisions:
        controls = [self.function(int(r), observations, self.scenario) for r in robots]
        n = self.scenario.n_robots
        return Decisions.of(controls, np.full((len(robots), n), -1))


def steer(poses: np.ndarray, targets: np.ndarray, max_speed, max_turn, dt: float) -> np.ndarray:
    """Straight-line controls ``(r, 2)`` from ``poses (r, 3)`` towards ``targets (r, 2)``.

    Turn towards the target (within ``max_turn``), then move at most ``max_speed`` and
    never past it.

    Examples
    --------
    >>> steer(np.array([[0.0, 0.0, 0.0]]), np.array([[0.0, 0.5]]), 1.0, np.pi, 1.0).round(4)
    array([[0.5   , 1.5708]])
    """
    delta = targets - poses[:, :2]
    distance = np.hypot(delta[:, 0], delta[:, 1])
    change = wrap_angle(np.arctan2(delta[:, 1], delta[:, 0]) - poses[:, 2])
    change = np.where(distance > 0, np.clip(change, -max_turn, max_turn), 0.0)
    speed = np.minimum(max_speed, distance / dt)
    return np.column_stack([speed, change])
