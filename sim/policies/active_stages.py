"""The stages of an active-inference decision, each returning values: the controller over
a robot's configuration set, the team prior over it, and the act (one-step expected free
energy, the planner, or the prior's mode), which :class:`~epistemica.sim.policies.active.
ActiveInference` chains: sets -> priors -> act -> record.
"""

from __future__ import annotations

import weakref

import numpy as np

from epistemica.aif.controller import Controller
from epistemica.aif.decision import Decision
from epistemica.aif.motion import DEFAULT_HEADING_CHANGES, control_grid
from epistemica.aif.prior import shared_rank, team_log_prior
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import PlanningStage
from epistemica.sim.policies.policy import steer

__all__ = ["ControllerStage", "control_candidates"]


def control_candidates(max_speed: float, max_turn: float, headings: int) -> np.ndarray:
    """The control grid of a robot: four speeds up to ``max_speed`` and heading changes
    that include straight ahead (the full turn when allowed, else ``headings + 1`` values
    in ``[-max_turn, max_turn]``).

    Examples
    --------
    >>> control_candidates(1.0, 0.5, 2).shape
    (12, 2)
    """
    speeds = max_speed * np.array([0.0, 1 / 3, 2 / 3, 1.0])
    if max_turn >= np.pi and headings == len(DEFAULT_HEADING_CHANGES):
        changes = DEFAULT_HEADING_CHANGES
    elif max_turn >= np.pi:
        changes = np.linspace(-np.pi, np.pi, headings, endpoint=False)
    else:
        changes = np.linspace(-max_turn, max_turn, headings + 1)
    return control_grid(speeds, changes)


class ControllerStage:
    """Controllers (cached by goals and limits), priors and acts of one trial's robots."""

    def __init__(self, scenario: Scenario, parameters: ActiveParameters, order: int) -> None:
        self.scenario, self.parameters, self.order = scenario, parameters, order
        self._controllers: dict[tuple, Controller] = {}
        # Keyed by the controller object, weakly: per-step controllers come and go, and
        # an id() of a collected one may be reused by the next.
        self._ranks: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
        self._beliefs: dict[int, tuple[Controller, np.ndarray]] = {}  # robot -> (ctrl, q)
        self.plans = PlanningStage(scenario, parameters, order) if parameters.planning else None

    def controller(self, robot: int, goals: np.ndarray, rows, shared: bool) -> Controller:
        """The controller over ``goals`` and the configurations ``rows()``."""
        s = self.scenario
        if not shared:  # a set of its own each step: no caching
            return self._build(robot, goals, rows())
        key = (float(s.max_speed[robot]), float(s.max_turn[robot]), goals.tobytes())
        ctrl = self._controllers.get(key)
        if ctrl is None:
            ctrl = self._build(robot, goals, rows())
            if len(self._controllers) > 64:  # multitask subsets change: bound the cache
                self._controllers.clear()
            self._controllers[key] = ctrl
        return ctrl

    def _build(self, robot: int, goals: np.ndarray, rows: np.ndarray) -> Controller:
        s, p = self.scenario, self.parameters
        options = {"position_noise": s.position_noise, **dict(p.controller)}
        grid = control_candidates(s.max_speed[robot], s.max_turn[robot], p.headings)
        return Controller(
            s.goals[goals], s.sensors, rows, order=self.order, controls=grid, dt=s.dt, **options
        )

    def priors(self, ctrl: Controller, views: np.ndarray, robots) -> list:
        """Each robot's prior from its own view ``views[j]`` (``None``: uniform)."""
        p = self.parameters
        log_prior = np.zeros((len(robots), ctrl.configurations.shape[0]))
        if p.prior_scale is not None:
            rank = self._ranks.get(ctrl)
            if rank is None:
                rank = self._ranks[ctrl] = shared_rank(ctrl.goals, ctrl.configurations)
            log_prior += team_log_prior(
                views, ctrl.goals, ctrl.configurations, p.prior_scale, p.tie_weight, rank
            )
        for j, robot in enumerate(robots):
            remembered = self._beliefs.get(robot)
            if p.memory > 0 and remembered is not None and remembered[0] is ctrl:
                with np.errstate(divide="ignore"):
                    log_prior[j] += p.memory * np.log(remembered[1])
        top = log_prior.max(axis=1, keepdims=True)
        prior = np.exp(np.maximum(log_prior - top, p.log_prior_floor))
        # Each row normalised alone: a 1-D sum rounds as the single robot's call did.
        return [q / q.sum() if lp.any() else None for q, lp in zip(prior, log_prior, strict=True)]

    def act(self, ctrl: Controller, goals, team, observations: Observations, priors) -> list:
        """The decisions of ``team`` (robots sharing ``ctrl``) from their priors: the
        one-step controller's team call, the planner's plans, or the prior's mode."""
        if not self.parameters.free_energy:
            return [
                self.prior_mode(ctrl, robot, observations.poses[robot, robot], prior)
                for robot, prior in zip(team, priors, strict=True)
            ]
        if self.plans is not None:
            return [
                self.plans.decide(ctrl, goals, robot, observations, prior)
                for robot, prior in zip(team, priors, strict=True)
            ]
        return ctrl.decide_team(observations.poses, team, priors)

    def remember(self, robot: int, ctrl: Controller, belief: np.ndarray) -> None:
        """Keep the robot's belief for its next prior (``memory``)."""
        if self.parameters.memory > 0:
            self._beliefs[robot] = (ctrl, belief)

    def prior_mode(self, ctrl: Controller, robot: int, pose, prior) -> Decision:
        """The ablation of expected free energy: straight for the robot's own goal in the
        prior's most probable configuration (the first on ties; uniform when ``None``)."""
        k = ctrl.configurations.shape[0]
        belief = np.full(k, 1.0 / k) if prior is None else np.asarray(prior, dtype=float)
        focal = int(np.argmax(belief))
        target = ctrl.goals[ctrl.configurations[focal, robot]]
        s = self.scenario
        control = steer(pose[None], target[None], s.max_speed[[robot]], s.max_turn[[robot]], s.dt)
        empty = np.zeros(0)
        return Decision((float(control[0, 0]), float(control[0, 1])), -1, empty, empty, belief,
                        focal)  # fmt: skip
