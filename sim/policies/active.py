"""The active-inference levels of goal and multitask missions in the simulator: the
planner's ``"first"``, ``"second"`` and ``"third"`` (``planning=True``) and the rules'
one-step controller ``"rules-first"``, ``"rules-second"``, ``"rules-third"``
(:func:`level_name`).

Each robot runs :class:`epistemica.aif.Controller` at its order over the valid
configurations of the goals it knows of. The parts, each with one job:

- :mod:`~epistemica.sim.policies.configuration_sets`: which configurations a robot reasons over,
  and, nested, which of them it knows each teammate keeps;
- :mod:`~epistemica.sim.policies.search`: the rendezvous search for missing teammates;
- :class:`~epistemica.sim.policies.explore.Explorer`: a robot that knows too few goals sweeps the
  workspace;
- :mod:`~epistemica.sim.policies.active_stages`: the controller over a set, the team prior
  (from the common view) and the act: one team call per shared controller, the planner
  (:mod:`~epistemica.sim.policies.planning`), or the prior's mode;
- this module: the pipeline, each stage returning values (sets -> priors -> act ->
  record), and the record of each decision.

Every rule and constant is a field of :class:`~epistemica.sim.policies.parameters.ActiveParameters`.
The control grid respects the robot's limits: four speeds up to its ``max_speed`` and
heading changes that include "straight ahead" (the full turn when allowed, else nine values
in ``[-max_turn, max_turn]``).
"""

from __future__ import annotations

import numpy as np

from epistemica.aif.controller import Controller
from epistemica.aif.information import entropy
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.active_stages import ControllerStage
from epistemica.sim.policies.anticipation import anticipated_prior
from epistemica.sim.policies.baselines import Convention
from epistemica.sim.policies.common_view import CommonView
from epistemica.sim.policies.configuration_sets import (
    ConfigurationSets,
    held_to,
    known_slots,
    nested_sets,
)
from epistemica.sim.policies.explore import Explorer
from epistemica.sim.policies.joining import Joining
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.planning import chains_of
from epistemica.sim.policies.policy import Decisions, Policy, steer
from epistemica.sim.policies.search import RendezvousSearch
from epistemica.sim.policies.teammate_models import TeammateModels

__all__ = ["ORDERS", "ActiveInference", "level_name"]

#: Order of reasoning of each active-inference level.
ORDERS = {"first": 1, "second": 2, "third": 3}


def level_name(order: int, parameters: ActiveParameters) -> str:
    """The level name of the controller at ``order`` with ``parameters``: the planner's
    levels are ``first``, ``second``, ``third`` and their ablations; the one-step
    controller's carry the prefix ``rules-``; without expected free energy both play the
    prior's mode, the same trial, under one name (``third-priormode``).

    Examples
    --------
    >>> level_name(3, ActiveParameters(planning=True)), level_name(3, ActiveParameters())
    ('third', 'rules-third')
    >>> level_name(2, ActiveParameters(planning=True, plan_horizon=3, nested=False))
    'second-shared-wait'
    """
    p = parameters
    name = {v: k for k, v in ORDERS.items()}.get(int(order), f"order-{order}")
    if not p.pruning:
        name += "-unpruned"
    elif not p.nested:
        name += "-shared"
    if not p.free_energy:
        return name + "-priormode"
    if not p.planning:
        return "rules-" + name
    return name + ("-wait" if p.plan_horizon > 1 else "")


class ActiveInference(Policy):
    """Expected-free-energy control at a given order of reasoning.

    Parameters
    ----------
    order : {1, 2, 3}
        Order of reasoning.
    parameters : ActiveParameters, optional
        Rules and constants (default :class:`ActiveParameters`).
    **changes
        Parameters to change from ``parameters`` (fields of
        :class:`~epistemica.sim.policies.parameters.ActiveParameters`, or controller arguments).

    Examples
    --------
    >>> ActiveInference(3, lone_wait=30).parameters.lone_wait
    30
    >>> ActiveInference(3, nested=False).name
    'rules-third-shared'
    >>> ActiveInference(3, planning=True, nested=False).name
    'third-shared'
    """

    def __init__(self, order: int, parameters: ActiveParameters | None = None, **changes) -> None:
        base = ActiveParameters() if parameters is None else parameters
        self.parameters = base.replace(**changes) if changes else base
        self.order = int(order)
        self.name = level_name(self.order, self.parameters)

    def start(self, scenario, robots, generators) -> None:
        super().start(scenario, robots, generators)
        p = self.parameters
        self._stage = ControllerStage(scenario, p, self.order)
        self._plans = self._stage.plans
        self._sets = ConfigurationSets(scenario, p)
        # Too few goals known for any valid configuration: sweep the workspace for more,
        # then fall back to the convention on what is known.
        self._convention = Convention()
        self._convention.start(scenario, robots, generators)
        spacing = scenario.discovery_range or min(scenario.sensing_range or 10.0, 10.0)
        self._explorer = Explorer(scenario.workspace, spacing, scenario.n_robots)
        # Knowing that a teammate does not know of one's goal is second-order knowledge:
        # only the nested levels have it.
        aware_of_others = self.order >= 2 and p.nested
        self._search = RendezvousSearch(
            scenario,
            spacing,
            p.lone_wait,
            p.look,
            p.anchor_check,
            p.unaware_wait if aware_of_others else p.lone_wait,
            meet=p.plan_meet and self._plans is not None,
            hold=p.plan_anchor and self._plans is not None,
            sighted=p.plan_sighted and self._plans is not None,
        )
        # Teammates settled at a goal the robot does not know (plan_join; the planner's).
        self._join = Joining(scenario, p.plan_join if self._plans is not None else 0)
        self._teammates = (
            TeammateModels(scenario, p.teammate_sigma, p.teammate_leak)
            if p.teammate_models and p.free_energy and self.order >= 2
            else None
        )
        self.common_view = CommonView(scenario, p, self.order)

    # -- the step ------------------------------------------------------------------------

    def decide(self, observations: Observations, robots: np.ndarray) -> Decisions:
        n, m = self.scenario.n_robots, self.scenario.n_goals
        out = Decisions.of(np.zeros((len(robots), 2)), np.full((len(robots), n), -1))
        out = out._replace(goal_belief=np.zeros((len(robots), m)))
        out = out._replace(unpruned=np.zeros(len(robots), dtype=int))
        out = out._replace(modelled=np.zeros((len(robots), n), dtype=int))
        # Robots that share a controller (same goals, set and limits) decide in one team
        # call, which returns what their separate decide calls would, bit for bit.
        groups: dict[int, tuple[Controller, np.ndarray, list]] = {}
        self.common_view.follow(observations, robots)
        self._explorer.visit(observations.poses[robots, robots], robots)
        was = self._search.left[robots] >= 0
        searching = (
            self._search.searchers(observations, robots)
            if self.parameters.search
            else np.zeros(len(robots), dtype=bool)
        )
        if self._search.meet:  # a search ended: what was read before it is stale
            for robot in robots[was & ~searching]:
                self._plans.forget(int(robot))
        for row, robot in enumerate(robots):
            if searching[row]:
                target = self._search.target(observations, robot)
                if target is not None:
                    self._steer(out, row, robot, observations.poses[robot, robot], target)
                    continue
            target = self._join.target(observations, robot)
            if target is not None:  # its goal is the one they settled at: round walls to it
                self._steer(out, row, robot, observations.poses[robot, robot], target)
                out.focal[row, robot] = self._join.goal[robot]
                continue
            choice = self._sets.choose(observations, robot)
            if choice.goals.size == 0:
                self._explore(out, row, observations, robot)
                continue
            if self._knows_more(observations, robot):
                self._decide_nested(out, row, observations, robot, choice)
                continue
            out.unpruned[row] = -1
            ctrl = self._stage.controller(robot, choice.goals, choice.rows, choice.shared)
            groups.setdefault(id(ctrl), (ctrl, choice.goals, []))[2].append((row, robot))
        for ctrl, goals, members in groups.values():
            rows, team = zip(*members, strict=True)
            priors = self._stage.priors(ctrl, self.common_view.views(observations, team), team)
            if self._teammates is not None:
                private = [self.common_view.private(robot) for robot in team]
                priors = self._teammates.mix(
                    team, observations, goals, ctrl.configurations, priors, private
                )
            decisions = self._stage.act(ctrl, goals, team, observations, priors)
            for row, robot, d in zip(rows, team, decisions, strict=True):
                self._record(out, row, robot, ctrl, goals, d)
        if self._teammates is not None:  # what each robot reads of its teammates, for the record
            types = np.stack([self._teammates.posterior(int(robot)) for robot in robots])
            out = out._replace(teammate_types=types)
        return out

    def _explore(self, out: Decisions, row: int, observations: Observations, robot: int) -> None:
        """Too few goals known for any valid configuration: head for the nearest part of
        the workspace not swept yet; when all is swept, the convention's move on the goals
        it knows."""
        pose = observations.poses[robot, robot]
        target = self._explorer.target(robot, pose)
        if target is None and observations.known_goals[robot].any():
            d = self._convention.decide(observations, np.array([robot]))
            out.controls[row], out.focal[row] = d.controls[0], d.focal[0]
            return
        if target is not None:
            self._steer(out, row, robot, pose, target)

    def _steer(self, out: Decisions, row: int, robot: int, pose, target) -> None:
        """Drive ``robot`` straight for ``target`` (exploring and searching)."""
        s = self.scenario
        out.controls[row] = steer(
            pose[None], target[None], s.max_speed[[robot]], s.max_turn[[robot]], s.dt
        )[0]

    def _knows_more(self, observations: Observations, robot: int) -> bool:
        """Whether events, told facts or private goals make the robot's own set, or those
        of the teammates it models, differ from the unpruned one."""
        knowledge = observations.knowledge
        if not self.parameters.pruning or knowledge is None:
            return False
        if self.scenario.kind.tasks:
            return False
        if self._plans is not None and self.order >= 2 and self.parameters.free_energy:
            return True  # a plan reads every chain's set, even where its own is whole
        return knowledge.constrains((robot,)) or (
            self.order >= 2 and knowledge.private_goals(robot)
        )

    def _decide_nested(self, out, row, observations, robot, choice) -> None:
        """Decide over nested configuration sets: the robot's own belief over its ``B`` set,
        its model of each teammate over the set it knows that teammate keeps; the
        controller's table is their union, each perspective's prior the team prior
        restricted to its set."""
        rows = choice.rows()
        sets = nested_sets(
            observations.knowledge,
            self.scenario.sensors,
            robot,
            self.order,
            choice.goals[rows],
            self.parameters.nested,
            self.parameters.revision,
        )
        if self._plans is not None:  # anchors outrank the newest settles (plan_settled)
            sets = held_to(sets, choice.goals[rows], self._plans.anchors(observations, robot))
            if self.parameters.plan_few and self.parameters.free_energy:  # the plan's chains
                sets = known_slots(sets, observations.knowledge, robot, choice.goals[rows],
                                   self._near(observations, robot))  # fmt: skip
        keep = sets.union
        ctrl = self._stage.controller(robot, choice.goals, lambda: rows[keep], shared=False)
        base = self._stage.priors(ctrl, self.common_view.views(observations, (robot,)), (robot,))[0]
        base = np.full(int(keep.sum()), 1.0) if base is None else base
        if self._teammates is not None:  # every perspective starts from the type mixture
            base = self._teammates.mix(
                [robot], observations, choice.goals, ctrl.configurations, [base],
                [self.common_view.private(robot)],
            )[0]  # fmt: skip

        def restricted(mask: np.ndarray) -> np.ndarray:
            p = np.where(mask[keep], base, 0.0)
            total = p.sum()
            return p / total if total > 0 else base  # a chain with no set: no restriction

        own = restricted(sets.own)
        if self._plans is not None and self.parameters.free_energy:
            chains = chains_of(robot, sets.own, sets.pairs, sets.triples, keep)
            d = self._plans.decide(ctrl, choice.goals, robot, observations, base, chains)
            self._record_nested(out, row, robot, ctrl, choice, rows, sets, d)
            return
        unaware = self._unaware(sets)
        if unaware:
            view = self.common_view.views(observations, (robot,))[0]

            def redecide(teammate: int, goal: int) -> np.ndarray:
                moved = view.copy()
                moved[teammate, :2] = ctrl.goals[goal]
                prior = self._stage.priors(ctrl, moved[None], (robot,))[0]
                return np.full(len(base), 1.0) if prior is None else prior

            own = anticipated_prior(
                ctrl.configurations,
                base / base.sum(),
                robot,
                sets.own[keep],
                {j: m[keep] for j, m in unaware.items()},
                {jk: m[keep] for jk, m in sets.triples.items()},
                redecide,
            )
        if self.parameters.free_energy:
            d = ctrl.decide(
                robot,
                observations.poses[robot],
                prior=own,
                modelled_priors=[restricted(m) for m in sets.modelled] or None,
            )
        else:
            d = self._stage.prior_mode(ctrl, robot, observations.poses[robot, robot], own)
        self._record_nested(out, row, robot, ctrl, choice, rows, sets, d)

    def _near(self, observations: Observations, robot: int) -> np.ndarray:
        """``(n, m)`` whether the robot sees each robot within discovery range of each goal
        (the sensor's range, as :class:`~epistemica.sim.engine.sensing.Sensing` sets it):
        it may have discovered it (``plan_few``)."""
        s = self.scenario
        sensing = np.inf if s.sensing_range is None else s.sensing_range
        reach = s.discovery_range if s.discovery_range is not None else min(sensing, 10.0)
        at = observations.poses[robot, :, None, :2] - s.goals[None]
        seen = observations.last_seen[robot] >= 0  # a placeholder is nowhere
        return (np.hypot(at[..., 0], at[..., 1]) <= reach) & seen[:, None]

    def _record_nested(self, out, row, robot, ctrl, choice, rows, sets, d) -> None:
        out.unpruned[row] = rows.shape[0]
        self._record(out, row, robot, ctrl, choice.goals, d)
        out.considered[row] = int(sets.own.sum())
        out.modelled[row] = out.considered[row]
        for j, mask in sets.pairs.items():
            out.modelled[row, j] = int(mask.sum())

    def _unaware(self, sets) -> dict:
        """The teammates to predict from their sets (order 2 and above, with nested sets):
        those that cannot conceive of some configuration the robot keeps."""
        if self.order < 2 or not self.parameters.anticipate or not self.parameters.nested:
            return {}
        return {j: m for j, m in sets.pairs.items() if (sets.own & ~m).any()}

    def _record(self, out: Decisions, row: int, robot: int, ctrl, goals, d) -> None:
        self._stage.remember(robot, ctrl, d.belief)
        out.controls[row] = d.control
        out.focal[row] = goals[ctrl.configurations[d.focal]]
        out.entropy[row] = entropy(d.belief)
        out.considered[row] = ctrl.configurations.shape[0]
        if out.unpruned[row] < 0:
            out.unpruned[row] = out.considered[row]
        out.modelled[row] = out.considered[row]
        own = goals[ctrl.configurations[:, robot]]
        m = out.goal_belief.shape[1]
        out.goal_belief[row] = np.bincount(own, weights=d.belief, minlength=m)
