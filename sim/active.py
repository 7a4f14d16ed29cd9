"""Active-inference levels ``"first"``, ``"second"`` and ``"third"`` in the simulator.

Each robot runs :class:`epistemica.aif.Controller` at its order over the valid
configurations of the goals it knows of; multitask robots first select the tasks the team
works on now (:mod:`~epistemica.sim.tasking`) and reason over allocations of those. The
control grid respects the robot's limits: four speeds up to its ``max_speed`` and headings
changes that include "straight ahead" (the full turn when allowed, else nine values in
``[-max_turn, max_turn]``).
"""

from __future__ import annotations

import weakref

import numpy as np

from epistemica.aif.configurations import (
    count_configurations,
    shared_configurations,
    valid_configurations,
)
from epistemica.aif.controller import Controller
from epistemica.aif.evidence import perspective_sets
from epistemica.aif.information import entropy
from epistemica.aif.motion import DEFAULT_HEADING_CHANGES, control_grid
from epistemica.aif.perspective import perspectives as _perspectives
from epistemica.aif.prior import plausible_configurations, shared_rank, team_log_prior
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.baselines import Convention, open_goals
from epistemica.sim.explore import Explorer
from epistemica.sim.policy import Decisions, Policy, steer
from epistemica.sim.sensing import Observations
from epistemica.sim.tasking import select_tasks, task_slots

__all__ = ["LEVELS", "ActiveInference"]

#: Order of reasoning of each active-inference level.
LEVELS = {"first": 1, "second": 2, "third": 3}


def _grid(max_speed: float, max_turn: float, headings: int = 8) -> np.ndarray:
    speeds = max_speed * np.array([0.0, 1 / 3, 2 / 3, 1.0])
    if max_turn >= np.pi and headings == len(DEFAULT_HEADING_CHANGES):
        changes = DEFAULT_HEADING_CHANGES
    elif max_turn >= np.pi:
        changes = np.linspace(-np.pi, np.pi, headings, endpoint=False)
    else:
        changes = np.linspace(-max_turn, max_turn, headings + 1)
    return control_grid(speeds, changes)


class _Pruned:
    """The plausible configurations of one robot at one step (not shared, not cached)."""

    def __init__(self, rows: np.ndarray) -> None:
        self.rows = rows

    def __call__(self) -> np.ndarray:
        return self.rows


class ActiveInference(Policy):
    """Expected-free-energy control at a given order of reasoning.

    Parameters
    ----------
    order : {1, 2, 3}
        Order of reasoning.
    prior_scale : float or None
        Metres of total distance per nat of the team prior
        (:func:`epistemica.aif.prior.team_log_prior`); ``None``: a uniform prior.
    tie_weight : float
        Nats of the shared tie-breaking preference.
    memory : float
        Exponent ``rho`` in ``[0, 1]`` of the previous posterior in the next prior,
        ``p_t ∝ team_prior_t · q_{t-1}^rho``: 0 forgets, 1 is a plain Bayes filter.
    headings : int
        Heading changes in the control grid.
    pruning : bool
        Reason only over the configurations the robot still considers possible after the
        observation events it saw (settled teammates, tasks done, facts it was told:
        :class:`~epistemica.sim.knowledge.TeamKnowledge`). ``False`` is the ablation: the
        robot ignores those events (goals it does not know of stay out).
    nested : bool
        Model each teammate over the configurations the robot knows that teammate keeps
        (who saw which event). ``False`` is the ablation (level ``third-shared``): the
        robot prunes by what it saw and takes every teammate to have seen the same.
    common_view : bool
        At order 2 and above, compute the team prior from what is common knowledge: a
        robot that does not see every teammate knows that those it cannot see cannot see
        it either, so no position is common knowledge and the prior puts every robot at
        the workspace centre (the shared default estimate); the shared tie-break then
        picks the same configuration for everyone. With everyone in sight it is the
        robot's own view. First order always uses its own view.
    **options
        Passed to :class:`epistemica.aif.Controller` (weights, horizon, ...).
    """

    #: Log-prior floor (nats below the best configuration): keeps every probability
    #: representable in float32, where the controller computes over large sets.
    LOG_PRIOR_FLOOR = -80.0
    #: From this many valid configurations on, a robot reasons over the plausible ones
    #: only: those within ``prior_scale * (n + PLAUSIBLE_MARGIN)`` of the least total
    #: distance (:func:`epistemica.aif.prior.plausible_configurations`).
    PRUNE_FROM = 2_000
    PLAUSIBLE_MARGIN = 10.0
    #: Rendezvous with a sensing range: steps a robot stands at a goal, seeing only
    #: teammates at that goal and not the whole team, before it searches for the rest
    #: (chosen on tuning seeds 1000-1039 of the stress suite).
    LONE_WAIT = 15
    #: A searcher counts a goal as looked at from this fraction of its sensing range.
    LOOK = 0.8

    def __init__(
        self,
        order: int,
        prior_scale: float | None = 1.0,
        tie_weight: float = 1.0,
        memory: float = 0.0,
        headings: int = 16,
        pruning: bool = True,
        common_view: bool = True,
        nested: bool = True,
        **options,
    ) -> None:
        if not 0.0 <= float(memory) <= 1.0:
            raise InvalidArgumentError(
                f"memory must lie in [0, 1], got {memory!r}", hint="0 forgets, 1 is a filter"
            )
        self.memory = float(memory)
        self.order = int(order)
        self.headings = int(headings)
        self.prior_scale = prior_scale
        self.tie_weight = tie_weight
        self.options = options
        self.pruning = bool(pruning)
        self.common_view = bool(common_view)
        self.nested = bool(nested)
        self.name = {v: k for k, v in LEVELS.items()}.get(self.order, f"order-{order}")
        if not self.pruning:
            self.name += "-unpruned"
        elif not self.nested:
            self.name += "-shared"

    def start(self, scenario, robots, generators) -> None:
        super().start(scenario, robots, generators)
        self._controllers: dict[tuple, Controller] = {}
        # Keyed by the controller object, weakly: per-step controllers come and go, and
        # an id() of a collected one may be reused by the next.
        self._ranks: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
        self._beliefs: dict[int, tuple[Controller, np.ndarray]] = {}  # robot -> (ctrl, q)
        # Too few goals known for any valid configuration: sweep the workspace for more,
        # then fall back to the convention on what is known.
        self._convention = Convention()
        self._convention.start(scenario, robots, generators)
        spacing = scenario.discovery_range or min(scenario.sensing_range or 10.0, 10.0)
        self._explorer = Explorer(scenario.workspace, spacing, scenario.n_robots)
        # Rendezvous: a group at a goal that has waited LONE_WAIT steps for the rest of
        # the team searches for it; _left is the goal a searcher left (-1: not searching).
        self._search = Explorer(scenario.workspace, spacing, scenario.n_robots)
        self._waiting = np.zeros(scenario.n_robots, dtype=int)
        self._left = np.full(scenario.n_robots, -1)
        self._group = np.zeros((scenario.n_robots,) * 2, dtype=bool)  # who stayed there
        self._searches = np.zeros(scenario.n_robots, dtype=int)
        self._mark = np.zeros(scenario.n_robots, dtype=int)  # settles seen when it left
        self._checked = np.zeros((scenario.n_robots, scenario.n_goals), dtype=bool)

    def _controller(self, robot: int, goals: np.ndarray, configurations) -> Controller:
        s = self.scenario
        if isinstance(configurations, _Pruned):  # a set of its own each step: no caching
            return self._build(robot, goals, configurations())
        key = (float(s.max_speed[robot]), float(s.max_turn[robot]), goals.tobytes())
        ctrl = self._controllers.get(key)
        if ctrl is None:
            ctrl = self._build(robot, goals, configurations())
            if len(self._controllers) > 64:  # multitask subsets change: bound the cache
                self._controllers.clear()
            self._controllers[key] = ctrl
        return ctrl

    def _build(self, robot: int, goals: np.ndarray, rows: np.ndarray) -> Controller:
        s = self.scenario
        options = {"position_noise": s.position_noise, **self.options}
        grid = _grid(s.max_speed[robot], s.max_turn[robot], self.headings)
        return Controller(
            s.goals[goals], s.sensors, rows, order=self.order, controls=grid, dt=s.dt, **options
        )

    def _views(self, observations: Observations, robots) -> np.ndarray:
        """``(R, n, 3)`` the poses each robot's team prior is computed from."""
        views = observations.poses[list(robots)]
        if self.order < 2 or not self.common_view:
            return views
        blind = ~observations.seen[list(robots)].all(axis=1)
        if blind.any():
            views = views.copy()
            views[blind, :, :2] = self.scenario.workspace / 2
        return views

    def _priors(self, ctrl: Controller, views: np.ndarray, robots) -> list:
        """Each robot's prior from its own view ``views[j]`` (``None``: uniform)."""
        log_prior = np.zeros((len(robots), ctrl.configurations.shape[0]))
        if self.prior_scale is not None:
            rank = self._ranks.get(ctrl)
            if rank is None:
                rank = self._ranks[ctrl] = shared_rank(ctrl.goals, ctrl.configurations)
            log_prior += team_log_prior(
                views, ctrl.goals, ctrl.configurations, self.prior_scale, self.tie_weight, rank
            )
        for j, robot in enumerate(robots):
            remembered = self._beliefs.get(robot)
            if self.memory > 0 and remembered is not None and remembered[0] is ctrl:
                with np.errstate(divide="ignore"):
                    log_prior[j] += self.memory * np.log(remembered[1])
        top = log_prior.max(axis=1, keepdims=True)
        prior = np.exp(np.maximum(log_prior - top, self.LOG_PRIOR_FLOOR))
        # Each row normalised alone: a 1-D sum rounds as the single robot's call did.
        return [p / p.sum() if lp.any() else None for p, lp in zip(prior, log_prior, strict=True)]

    def _configurations(self, observations: Observations, robot: int):
        """Goal indices the robot reasons over, and a builder of their configurations."""
        s, n = self.scenario, self.scenario.n_robots
        known = open_goals(s, observations, robot)
        if not self.pruning:  # the ablation: tasks seen done are not pruned either
            known = np.flatnonzero(observations.known_goals[robot])
        if s.mission == "multitask":
            slots = task_slots(select_tasks(observations.poses[robot], s.goals, known), n)
            # Fewer open tasks than robots: each task takes as many robots as it has slots.
            tasks, copies = np.unique(slots, return_counts=True)
            mission, caps = ("allocation", None) if len(tasks) == n else ("capacity", copies)
            if len(tasks) and count_configurations(mission, n, len(tasks), caps) >= self.PRUNE_FROM:
                return tasks, self._plausible(observations, robot, tasks, mission, caps)
            if mission == "allocation":
                return tasks, lambda: shared_configurations("allocation", n, n)
            return tasks, lambda: valid_configurations(mission, n, len(tasks), caps)
        if known.size == s.n_goals:
            if count_configurations(s.mission, n, s.n_goals, s.capacities) >= self.PRUNE_FROM:
                return known, self._plausible(observations, robot, known, s.mission, s.capacities)
            return known, s.configurations
        if s.valid is None and s.mission in ("allocation", "rendezvous"):
            # The valid configurations over the known goals, enumerated directly (the same
            # rows, in the same order, as filtering the whole set, which at 10 robots
            # holds 3.6 million rows).
            if known.size == 0 or count_configurations(s.mission, n, known.size) == 0:
                return known[:0], None  # too few goals known for any valid configuration
            if count_configurations(s.mission, n, known.size) >= self.PRUNE_FROM:
                return known, self._plausible(observations, robot, known, s.mission, None)
            return known, lambda: valid_configurations(s.mission, n, known.size)
        rows = s.configurations()
        usable = np.isin(rows, known).all(axis=1)
        if not usable.any():  # too few goals known for any valid configuration
            return known[:0], None
        remap = np.full(s.n_goals, -1)
        remap[known] = np.arange(known.size)
        return known, lambda: remap[rows[usable]]

    def _plausible(self, observations, robot, goals, mission, capacities):
        view = observations.poses[robot, :, :2]
        cost = np.hypot(*(view[:, None, :] - self.scenario.goals[goals][None]).transpose(2, 0, 1))
        scale = 1.0 if self.prior_scale is None else self.prior_scale
        within = scale * (len(view) + self.PLAUSIBLE_MARGIN)
        rows = plausible_configurations(cost, mission, capacities, within)
        return _Pruned(rows)

    def _explore(self, out: Decisions, row: int, observations: Observations, robot: int) -> None:
        """Too few goals known for any valid configuration: head for the nearest part of
        the workspace not swept yet (sim/explore.py); when all is swept, the
        convention's move on the goals it knows."""
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

    def _searchers(self, observations: Observations, robots: np.ndarray) -> np.ndarray:
        """Rendezvous with a sensing range: which robots search for the rest of the team.

        A robot that has stood at a goal for ``LONE_WAIT`` steps, seeing some teammates
        there and the others nowhere, knows the mission does not hold (it would see the
        whole team), and that no one it can see is coming: it leaves to look for the rest.
        Everyone in such a group knows the same, so the group leaves together (a teammate
        that never moves stays). A searcher stops when it sees a teammate settled where it
        was not when the searcher left: the settle it then observes is its newest, and
        wins.
        """
        s = self.scenario
        if s.mission != "rendezvous" or s.sensing_range is None:
            return np.zeros(len(robots), dtype=bool)
        rows = np.arange(len(robots))
        pose = observations.poses[robots, robots, :2]
        d = np.hypot(*(pose[:, None] - s.goals[None]).transpose(2, 0, 1))
        own = np.where(d.min(axis=1) <= s.success_radius, d.argmin(axis=1), -1)
        # Where each robot last saw each teammate settle (a noisy view of a position
        # cannot tell "at my goal" from "near it"; a settle event can).
        at = np.full((len(robots), s.n_robots), -1)
        fresh = np.zeros((len(robots), s.n_robots), dtype=bool)  # settled since it left
        count = np.zeros(len(robots), dtype=int)
        if observations.knowledge is not None:
            for row, robot in enumerate(robots):
                events = observations.knowledge.settled((robot,))  # newest first
                count[row] = len(events)
                for teammate, goal in reversed(events):
                    at[row, teammate] = goal  # oldest first: the newest wins
                for teammate, _ in events[: max(len(events) - self._mark[robot], 0)]:
                    fresh[row, teammate] = True
        seen = observations.seen[robots].copy()
        seen[rows, robots] = False
        everyone = seen.sum(axis=1) == s.n_robots - 1
        together = (~seen | (at == own[:, None])).all(axis=1)  # all in sight stand here
        left, group = self._left[robots], self._group[robots]
        # Found: a teammate settled at another goal, or one that settled at the goal the
        # searcher left after it left (a newcomer there).
        elsewhere = seen & (at >= 0) & (at != left[:, None])
        newcomer = fresh & ~group & (at == left[:, None])
        found = (elsewhere | newcomer).any(axis=1)
        searching = (left >= 0) & ~found
        waiting = (own >= 0) & ~everyone & together & ~searching
        self._waiting[robots] = np.where(waiting, self._waiting[robots] + 1, 0)
        # Each search doubles the robot's next wait: two groups that left at once and
        # crossed unseen would otherwise keep missing each other (one must stay put).
        start = self._waiting[robots] >= self.LONE_WAIT * 2 ** self._searches[robots]
        self._searches[robots] += start
        if start.any():
            self._search.visited[robots[start]] = False  # a new search sweeps anew
            self._checked[robots[start]] = False
            self._group[robots[start]] = seen[start] & (at[start] == own[start, None])
            self._mark[robots[start]] = count[start]
        self._left[robots] = np.where(start, own, np.where(searching, left, -1))
        return self._left[robots] >= 0

    def _seek(self, out: Decisions, row: int, observations: Observations, robot: int) -> bool:
        """Head first for the goals where the robot last saw a missing teammate settle,
        then for the nearest cell not yet searched; False when all are."""
        s, pose = self.scenario, observations.poses[robot, robot]
        self._search.visit(pose[None, :2], [robot])
        distance = np.hypot(*(s.goals - pose[:2]).T)
        self._checked[robot] |= distance <= self.LOOK * s.sensing_range
        clues = np.zeros(s.n_goals, dtype=bool)
        if observations.knowledge is not None:
            for teammate, goal in observations.knowledge.settled((robot,)):
                if teammate != robot and not self._group[robot, teammate]:
                    clues[goal] = True
        # The team can only be waiting at a goal: first where missing teammates were
        # seen to settle, then the other goals the robot knows, then the whole workspace.
        unchecked = ~self._checked[robot]
        for candidates in (clues & unchecked, observations.known_goals[robot] & unchecked):
            if candidates.any():
                goals = np.flatnonzero(candidates)
                target = s.goals[goals[np.argmin(distance[goals])]]
                break
        else:
            target = self._search.target(robot, pose)
        if target is None:
            return False
        self._steer(out, row, robot, pose, target)
        return True

    def _knows_more(self, observations: Observations, robot: int) -> bool:
        """Whether events, told facts or private goals make the robot's own set, or those
        of the teammates it models, differ from the unpruned one."""
        knowledge = observations.knowledge
        if not self.pruning or knowledge is None or self.scenario.mission == "multitask":
            return False
        return knowledge.constrains((robot,)) or (
            self.order >= 2 and knowledge.private_goals(robot)
        )

    def _decide_nested(self, out, row, observations, robot, goals, configurations) -> None:
        """Decide over nested configuration sets (docs/aif.md, "Nested configuration sets").

        The robot's own belief ranges over what its chain ``(i,)`` keeps; its model of
        teammate ``j`` over what ``(i, j)`` keeps, and of ``k`` as ``j`` models it over what
        some chain ``(i, j, k)`` keeps. The controller's table is their union; each
        perspective's prior is the team prior restricted to its set.
        """
        knowledge, s = observations.knowledge, self.scenario
        rows = configurations()
        table = goals[rows]
        chains = perspective_sets(s.sensors, robot, self.order)
        # Chains that saw the same events keep the same set: computed once per signature
        # (at ten robots, third order, 72 chains share a handful of signatures).
        every = [(robot,)] + [c for level in chains[2:] for c in level]
        kept = dict(zip(every, knowledge.possible_many(every, table), strict=True))
        own = kept[(robot,)]
        masks = []
        for view in _perspectives(s.sensors, robot, self.order)[1:]:
            if not self.nested:  # the ablation: every teammate is taken to have seen it all
                masks.append(own)
                continue
            level = 2 if view.order == self.order - 1 else 3
            mask = np.zeros(len(rows), dtype=bool)
            for chain in chains[level]:
                if chain[-1] == view.agent:
                    mask |= kept[chain]
            masks.append(mask)
        keep = own | np.logical_or.reduce(masks) if masks else own
        ctrl = self._controller(robot, goals, _Pruned(rows[keep]))
        view_poses = observations.poses[robot]
        base = self._priors(ctrl, self._views(observations, (robot,)), (robot,))[0]
        base = np.full(int(keep.sum()), 1.0) if base is None else base

        def restricted(mask: np.ndarray) -> np.ndarray:
            p = np.where(mask[keep], base, 0.0)
            total = p.sum()
            return p / total if total > 0 else base  # a chain with no set: no restriction

        d = ctrl.decide(
            robot,
            view_poses,
            prior=restricted(own),
            modelled_priors=[restricted(m) for m in masks] or None,
        )
        out.unpruned[row] = rows.shape[0]
        self._record(out, row, robot, ctrl, goals, d)
        out.considered[row] = int(own.sum())

    def decide(self, observations: Observations, robots: np.ndarray) -> Decisions:
        n, m = self.scenario.n_robots, self.scenario.n_goals
        out = Decisions.of(np.zeros((len(robots), 2)), np.full((len(robots), n), -1))
        out = out._replace(goal_belief=np.zeros((len(robots), m)))
        out = out._replace(unpruned=np.zeros(len(robots), dtype=int))
        # Robots that share a controller (same goals, set and limits) decide in one team
        # call, which returns what their separate decide calls would, bit for bit.
        groups: dict[int, tuple[Controller, np.ndarray, list]] = {}
        self._explorer.visit(observations.poses[robots, robots], robots)
        searching = self._searchers(observations, robots)
        for row, robot in enumerate(robots):
            if searching[row] and self._seek(out, row, observations, robot):
                continue
            goals, configurations = self._configurations(observations, robot)
            if goals.size == 0:
                self._explore(out, row, observations, robot)
                continue
            if self._knows_more(observations, robot):
                self._decide_nested(out, row, observations, robot, goals, configurations)
                continue
            out.unpruned[row] = -1
            ctrl = self._controller(robot, goals, configurations)
            groups.setdefault(id(ctrl), (ctrl, goals, []))[2].append((row, robot))
        for ctrl, goals, members in groups.values():
            rows, team = zip(*members, strict=True)
            priors = self._priors(ctrl, self._views(observations, team), team)
            decisions = ctrl.decide_team(observations.poses, team, priors)
            for row, robot, d in zip(rows, team, decisions, strict=True):
                self._record(out, row, robot, ctrl, goals, d)
        return out

    def _record(self, out: Decisions, row: int, robot: int, ctrl, goals, d) -> None:
        if self.memory > 0:
            self._beliefs[robot] = (ctrl, d.belief)
        out.controls[row] = d.control
        out.focal[row] = goals[ctrl.configurations[d.focal]]
        out.entropy[row] = entropy(d.belief)
        out.considered[row] = ctrl.configurations.shape[0]
        if out.unpruned[row] < 0:
            out.unpruned[row] = out.considered[row]
        own = goals[ctrl.configurations[:, robot]]
        m = out.goal_belief.shape[1]
        out.goal_belief[row] = np.bincount(own, weights=d.belief, minlength=m)
