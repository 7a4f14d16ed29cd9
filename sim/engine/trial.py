"""The record of one simulated trial.

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> t = simulate(Scenario.paper("rendezvous", 2, 2, seed=0), "convention", seed=0)
>>> t.trajectory.shape[1:], t.focal.shape[1:], t.steps == t.trajectory.shape[0] - 1
((2, 3), (2, 2), True)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Trial"]


@dataclass(frozen=True, eq=False)
class Trial:
    """Outcome and per-step record of one trial.

    Attributes
    ----------
    success : bool
        The mission held on ``dwell`` steps (multitask: every task done) within the limit.
    steps : int
        Steps simulated: the step of success, or the step limit.
    completion_step : int or None
        Multitask: the step at which the last task was done (None if not all were).
    tasks_done : numpy.ndarray
        Multitask: the step at which each task was done (-1: never); empty otherwise.
    trajectory : numpy.ndarray
        ``(steps + 1, n, 3)`` true poses, the start first.
    focal : numpy.ndarray
        ``(steps, n, n)``: at each step, the configuration robot ``i`` acted on (goal index
        per robot, -1 where it had none).
    entropy : numpy.ndarray
        ``(steps, n)`` entropy (nats) of each robot's belief (NaN without one).
    considered : numpy.ndarray
        ``(steps, n)`` configurations each robot considered.
    unpruned : numpy.ndarray or None
        ``(steps, n)`` configurations each robot had before pruning by what it knows
        (equal to ``considered`` where nothing was pruned).
    modelled : numpy.ndarray
        ``(steps, n, n)``: the size of the set of configurations robot ``i`` models robot
        ``j`` keeping (``B_ij``; its own set on the diagonal): where nested knowledge
        differs, the sizes differ.
    estimates : numpy.ndarray
        ``(steps, n, n, 2)``: where robot ``i`` placed robot ``j`` when it decided (its
        own position exact).
    goal_belief : numpy.ndarray
        ``(steps, n, m)``: each robot's belief about its own goal.
    decision_time : numpy.ndarray
        ``(steps,)`` seconds the whole team spent deciding at each step.
    policies : tuple of str
        The policy name of each robot.
    seed : int
        The trial seed.
    events : tuple
        The observation events of the mission's rules, in order: ``(step, name,
        *arguments, observers)``, the arguments the rule's parameters bound (robot or goal
        indices: ``settle`` gives the robot and its goal, ``complete`` the task) and the
        robots that observed it (indices). Only events that taught someone something are
        listed.
    teammate_types : numpy.ndarray or None
        ``(steps, n, n, T)``: robot ``i``'s posterior over the behaviour library
        (:data:`epistemica.aif.teammates.TYPES`) of robot ``j`` when it decided (NaN where
        it kept none); ``None`` when no robot kept teammate models.
    known_goals : numpy.ndarray or None
        ``(steps, n, n, m)``: the goals robot ``i`` takes robot ``j`` to know of when it
        perceived (its own knowledge on the diagonal); ``None`` when every goal was common
        knowledge from the start.
    closed_goals : numpy.ndarray or None
        ``(steps, m)``: the goals closed (a task done, a door shut) when the robots
        perceived; ``None`` from code that did not record them.
    knowledge : TeamKnowledge
        The team's epistemic state at the end of the trial (every observation, goals
        discovered included): what ``epistemica check --after`` checks claims on.
    steer_to : numpy.ndarray or None
        Joint missions: ``(steps, n)`` the task each robot steered to (-1 exploring, -2
        fetching a teammate, -3 waiting for helpers).
    knows : numpy.ndarray or None
        Joint missions: ``(steps, n, m)`` the tasks each robot knew of when it decided.
    aware_since : numpy.ndarray or None
        Joint missions: ``(n, n, m)`` the first step robot ``i`` knew that robot ``j`` knows
        of task ``t`` (``j == i``: of the task; -1 never).
    """

    success: bool
    steps: int
    completion_step: int | None
    tasks_done: np.ndarray
    trajectory: np.ndarray
    focal: np.ndarray
    entropy: np.ndarray
    considered: np.ndarray
    unpruned: np.ndarray | None
    modelled: np.ndarray
    estimates: np.ndarray
    goal_belief: np.ndarray
    decision_time: np.ndarray
    policies: tuple[str, ...]
    seed: int
    events: tuple = ()
    knowledge: Any = field(default=None, repr=False)
    teammate_types: np.ndarray | None = field(default=None, repr=False)
    steer_to: np.ndarray | None = field(default=None, repr=False)
    knows: np.ndarray | None = field(default=None, repr=False)
    aware_since: np.ndarray | None = field(default=None, repr=False)
    known_goals: np.ndarray | None = field(default=None, repr=False)
    closed_goals: np.ndarray | None = field(default=None, repr=False)

    def summary(self) -> dict:
        """A JSON-ready dictionary of the outcome (no per-step arrays).

        Examples
        --------
        >>> from epistemica.sim import Scenario, simulate
        >>> sorted(simulate(Scenario.paper("allocation", 2, seed=1), "zero").summary())[:3]
        ['completion_step', 'final_positions', 'mean_decision_ms']
        """
        return {
            "success": self.success,
            "steps": self.steps,
            "completion_step": self.completion_step,
            "policies": list(self.policies),
            "seed": self.seed,
            "mean_decision_ms": float(np.mean(self.decision_time) * 1e3) if self.steps else 0.0,
            "final_positions": self.trajectory[-1, :, :2].round(3).tolist(),
        }
