"""The planning stage of the active-inference levels: options scored by expected free
energy over nested predictions (:class:`epistemica.aif.planning.Planner`).

Where the one-step controller (:class:`epistemica.aif.Controller`) scores controls, this
stage scores *options* over a horizon: head for a goal, or wait and choose once the
teammates' moves have said more. Teammates are predicted by the same planner one order
down over the sets the robot knows they keep (the nested sets of the DEL state), so a
robot at order 3 acts on what it thinks its teammates think it will do. The robot then
drives straight for the goal it chose (or stands while it waits).

Examples
--------
>>> from epistemica.sim import Scenario, simulate
>>> from epistemica.sim.policies.active import ActiveInference
>>> scenario = Scenario.paper("rendezvous", 3, 3, seed=1)
>>> trial = simulate(scenario, ActiveInference(3, planning=True), seed=1)
>>> trial.success
True
"""

from __future__ import annotations

import weakref
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import NamedTuple

import numpy as np

from epistemica.aif.decision import Decision
from epistemica.aif.plan_context import later_claimants
from epistemica.aif.planning import (
    WAIT,
    Planner,
    filter_sightings,
    motion_evidence,
    places_in_square,
)
from epistemica.aif.teammates import (
    ON_GOAL,
    TYPE_PRIOR,
    TYPES,
    ClaimModel,
    claim_yields,
    goal_distances,
    least_cost_from_distances,
    motion_log_likelihood,
    planner_type_goals,
    typed_predictions,
    update_types,
)
from epistemica.sim.engine.navigation import roadmap_for
from epistemica.sim.engine.scenario import Scenario
from epistemica.sim.engine.sensing import Observations
from epistemica.sim.policies.hidden_places import HiddenPlaces
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.policy import steer

__all__ = ["PlanRecord", "PlanningStage", "chains_of", "recording_plans", "sighting_variance"]


class PlanRecord(NamedTuple):
    """One plan as :func:`recording_plans` keeps it.

    ``goals`` are the scenario indices of the planner's goals (its table); ``G``, ``wait``,
    ``predictions``, ``belief`` and ``focal`` are the :class:`~epistemica.aif.planning.PlanResult`'s
    (``predictions[j]`` the robot's predicted distribution of teammate ``j``'s goal, its own
    row its own); ``chosen`` the scenario index of the goal it heads for (-1: waits);
    ``positions`` where it places every robot (a placeholder for one it never saw:
    ``seen``); ``sets`` the size of each chain's set; ``types`` each robot's posterior
    over :data:`~epistemica.aif.teammates.TYPES` and ``typed`` whether it was held to a
    goal by its type (both ``None`` with ``plan_types = 0``).
    """

    step: int
    robot: int
    goals: np.ndarray
    G: np.ndarray
    wait: float
    predictions: np.ndarray
    belief: np.ndarray
    focal: int
    chosen: int
    positions: np.ndarray
    seen: np.ndarray
    sets: dict
    types: np.ndarray | None = None
    typed: np.ndarray | None = None


_RECORDER: ContextVar[list | None] = ContextVar("epistemica_plan_recorder", default=None)


@contextmanager
def recording_plans() -> Iterator[list[PlanRecord]]:
    """Keep every plan made inside the block, in order, as :class:`PlanRecord` s: what a
    robot predicted of each teammate and how it scored its options, to read a decision
    that went wrong (``benchmarks/planning_trace.py``). Trials run in this process only.

    Examples
    --------
    >>> from epistemica.sim import Scenario, simulate
    >>> from epistemica.sim.policies.active import ActiveInference
    >>> scenario = Scenario.paper("rendezvous", 3, 3, seed=1)
    >>> with recording_plans() as plans:
    ...     trial = simulate(scenario, ActiveInference(3, planning=True), seed=1)
    >>> first = plans[0]
    >>> (first.step, first.predictions.shape[0], int(first.G.argmin()) == first.chosen)
    (0, 3, True)
    """
    log: list[PlanRecord] = []
    token = _RECORDER.set(log)
    try:
        yield log
    finally:
        _RECORDER.reset(token)


def chains_of(robot: int, own, pairs, triples, keep=None) -> dict[tuple[int, ...], np.ndarray]:
    """The planner's chain -> set mapping from nested sets (restricted to ``keep``)."""

    def cut(mask: np.ndarray) -> np.ndarray:
        return mask if keep is None else mask[keep]

    chains = {(robot,): cut(own)}
    chains.update({(robot, j): cut(mask) for j, mask in pairs.items()})
    chains.update({(robot, j, k): cut(mask) for (j, k), mask in triples.items()})
    return chains


def sighting_variance(scenario: Scenario, distance) -> np.ndarray:
    """Per-axis variance (m²) of a sighting of teammates at ``distance`` (m), as the
    scenario's sensor states it (``variance``; a sensor without one: ``position_noise``).

    Examples
    --------
    >>> from epistemica.sim import Scenario
    >>> honest = Scenario.paper("allocation", 2, 2, seed=0).replace(
    ...     observation="honest", position_noise=8.0, angle_noise=0.1)
    >>> sighting_variance(honest, [0.0, 10.0]).tolist()
    [4.0, 9.0]
    """
    distance = np.asarray(distance, dtype=float)
    variance = getattr(scenario.sensor, "variance", None)  # a sensor of one's own may lack it
    if variance is None:
        return np.full(distance.shape, float(scenario.position_noise))
    return variance(distance, scenario)


class PlanningStage:
    """Plans of the robots of one trial, with what each saw its teammates do last step."""

    def __init__(self, scenario: Scenario, parameters: ActiveParameters, order: int) -> None:
        self.scenario, self.order = scenario, order
        p = parameters
        # Tasks: re-assigned each step, done by one arrival: no goal kept or move read; all yield.
        self.reselected = bool(scenario.kind.tasks)
        claim = min(p.plan_claim, 1) if self.reselected else p.plan_claim
        self.options = {
            "temperature": p.plan_temperature,
            "repair": p.plan_repair,
            "evidence": p.plan_evidence,
            "horizon": p.plan_horizon,
            "particles": p.plan_particles,
            "commitment": p.plan_commitment,
            "convention": p.plan_convention,
            "hierarchy": p.plan_hierarchy,
            "success_weight": p.plan_success,
            "shown": p.plan_shown,
            "sigma": p.plan_sigma,
            "claim": claim > 0,
            "arrivals": p.plan_hidden > 0,
            "waiting": p.plan_wait,
        }
        self._planners: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
        self.sigma, self.leak, self.blind = p.plan_sigma, p.plan_leak, bool(p.plan_blind)
        self.noise, self.progress = float(p.plan_noise), float(p.plan_progress)
        self.by_type, self.yielding, self.keeping, self.driving, self.unread = (  # claims
            claim >= v for v in (2, 3, 4, 5, 6))  # fmt: skip
        self.resight, self.filtering = bool(p.plan_resight), bool(p.plan_filter)
        self._roadmap = roadmap_for(scenario)  # teammates drive round walls: read them so
        self._tracks: dict[int, tuple] = {}  # robot -> its filters (filter_sightings)
        self._start: dict[int, tuple[int, float]] = {}  # robot -> (goal, distance on choosing)
        # Where a never-seen teammate may be: over the workspace, or where it can be (hidden).
        self.places = places_in_square(p.plan_unseen, scenario.n_robots, scenario.workspace)
        self.hidden = HiddenPlaces(scenario, p.plan_hidden) if p.plan_hidden > 0 else None
        # robot -> (step, what it saw, when it last saw each robot)
        self._last: dict[int, tuple[int, np.ndarray, np.ndarray]] = {}
        # robot -> (n, M) log-likelihood of each teammate heading for each goal, summed
        # over the moves it saw.
        self._read: dict[int, np.ndarray] = {}
        self._heading: dict[int, int] = {}  # robot -> the goal (scenario index) it chose last
        # Teammate types read from their moves (docs/aif.md §6g): robot -> (n, T) log
        # posterior, and what its last plan predicted each type would do.
        self.threshold = float(p.plan_types)
        self.type_sigma = float(np.sqrt(p.teammate_sigma**2 + 2 * scenario.position_noise))
        self.type_leak = float(p.teammate_leak)
        self._types: dict[int, np.ndarray] = {}
        self._typing: dict[int, tuple] = {}  # robot -> (step, goals, positions, seen, (n, T, m))
        # Anchors (plan_settled): robot -> (the goal each teammate was last seen to settle
        # at, at how many plans since, away from the robot's own goal).
        self.settled = int(p.plan_settled)
        self._settles: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def planner(self, ctrl) -> Planner:
        """The planner over a controller's goals and configurations (one per table)."""
        planner = self._planners.get(ctrl)
        if planner is None:
            s = self.scenario
            planner = Planner(ctrl.goals, ctrl.configurations, s.max_speed, order=self.order,
                              dt=s.dt, **self.options)  # fmt: skip
            self._planners[ctrl] = planner
        return planner

    def observe(self, observations: Observations, robot: int) -> np.ndarray:
        """Read the teammates' moves since the robot last planned; ``(n,)`` the fraction
        of its speed each used (1 where it could not tell).

        With ``plan_resight`` a move is read only between two sightings of the teammate,
        over the time between them; otherwise from where the robot's last plan placed it
        (a sighting of any age, or the placeholder) over the time since that plan."""
        s = self.scenario
        now = observations.poses[robot, :, :2]
        step = observations.step
        seen = observations.last_seen[robot] == step
        before = self._last.get(robot)
        self._last[robot] = (step, now.copy(), observations.last_seen[robot].copy())
        read = self._read.setdefault(robot, np.zeros((s.n_robots, s.n_goals)))
        if before is not None and before[0] >= step:
            return np.ones(s.n_robots)
        if self.filtering:
            read *= 1.0 - self.leak
            read[seen] += self._filtered(robot, now, seen, step)[seen]
        if before is None:
            return np.ones(s.n_robots)
        gap = (step - before[0]) * s.dt
        if self.resight:  # the last plan's estimate of a teammate is its sighting then
            seen = seen & (before[2] >= 0)
            gap = np.where(seen, step - before[2], step - before[0]) * s.dt
        model = self.sigma * float(s.max_speed.mean()) * gap
        # A move is the difference of two sightings: their noise adds to the model's error.
        sigma = model
        if self.noise > 0:
            noise = 2 * self.noise * sighting_variance(s, np.hypot(*(now - now[robot]).T))
            sigma = np.sqrt(model**2 + noise)
        aims = s.goals if self._roadmap is None else self._roadmap.aims(before[1], s.goals)
        if self.resight:  # per-teammate gaps: each one's reach over its own time
            moves = motion_evidence(before[1], now, aims, s.max_speed * gap, 1.0, sigma)
        else:
            moves = motion_evidence(before[1], now, aims, s.max_speed, gap, sigma)
        if not self.filtering:
            read *= 1.0 - self.leak
            read[seen] += moves[seen]
        used = np.hypot(*(now - before[1]).T) / (s.max_speed * gap)
        return np.where(seen, np.clip(used, 0.0, 1.0), 1.0)

    def _filtered(self, robot: int, now: np.ndarray, seen: np.ndarray, step: int) -> np.ndarray:
        """``(n, M)`` the evidence of this step's sightings, each robot's filtered under
        every goal hypothesis against the noise its sensor states (``plan_filter``)."""
        s = self.scenario
        n, m = s.n_robots, s.n_goals
        track = self._tracks.setdefault(robot, (np.zeros((n, m, 2)), np.zeros(n), np.full(n, -1)))
        variance = np.array(sighting_variance(s, np.hypot(*(now - now[robot]).T)), dtype=float)
        variance[robot] = 0.0  # its own pose is exact
        sighted = np.where(seen[:, None], now, np.nan)
        sigma = self.sigma * float(s.max_speed.mean()) * s.dt
        return filter_sightings(track, sighted, variance, s.goals, s.max_speed * s.dt, step, sigma)

    def _progress(self, robot: int, pose) -> float:
        """Seconds (times ``plan_progress``) the robot has driven towards the goal it
        heads for since it chose it: what turning to another goal wastes."""
        goal, start = self._start.get(robot, (-1, 0.0))
        if goal < 0 or self.progress <= 0:
            return 0.0
        s = self.scenario
        done = start - float(np.hypot(*(s.goals[goal] - pose[:2])))
        return self.progress * max(done, 0.0) / float(s.max_speed[robot])

    def forget(self, robot: int) -> None:
        """Drop what the robot read of its teammates' moves and the goal it headed for:
        its next plan starts from their positions alone (after a rendezvous search)."""
        for memory in (self._last, self._read, self._heading, self._start, self._tracks):
            memory.pop(robot, None)

    def anchors(self, observations: Observations, robot: int) -> dict[int, int]:
        """Rendezvous: the teammates the robot has seen settle at one goal, away from the
        one it heads for or stands at, at ``plan_settled`` of its plans and at no other
        goal since (teammate -> goal, scenario indices; none with ``plan_settled = 0``;
        a plan that does not see it settle counts nothing: sightings of settles come and
        go). A planner that saw where the team meets would have left; one that stays
        holds to its goal for good.

        Examples
        --------
        >>> import numpy as np
        >>> from epistemica.sim.engine.sensing import Observations
        >>> scenario = Scenario.paper("rendezvous", 2, 2, seed=0)
        >>> stage = PlanningStage(scenario, ActiveParameters(plan_settled=2), order=3)
        >>> poses = np.zeros((2, 2, 3))
        >>> poses[0, 0, :2] = scenario.goals[1]               # r1 stands at goal 1
        >>> settles = np.array([[-1, 0], [-1, -1]])           # and sees r2 settle at goal 0
        >>> seen = np.ones((2, 2), bool)
        >>> def step(k):
        ...     return Observations(k, poses, seen, np.full((2, 2), k), seen, ~seen, None, settles)
        >>> stage._heading[0] = 1                             # r1 heads for goal 1
        >>> stage.anchors(step(0), 0), stage.anchors(step(1), 0)
        ({}, {1: 0})
        """
        s = self.scenario
        if self.settled <= 0 or not s.kind.gathers or observations.settles is None:
            return {}
        n = s.n_robots
        goal, count = self._settles.setdefault(robot, (np.full(n, -1), np.zeros(n, dtype=int)))
        now = observations.settles[robot].copy()
        now[robot] = -1
        pose = observations.poses[robot, robot, :2]
        near = np.hypot(*(s.goals - pose).T)
        mine = {
            self._heading.get(robot, -1),
            int(near.argmin()) if near.min() <= s.success_radius else -1,
        }
        # A settle at the goal last seen counts on (its goal may have become the robot's
        # own since); one at another goal starts anew, unless at the robot's own goal.
        again = (now >= 0) & (now == goal)
        moved = (now >= 0) & (now != goal)
        count[:] = np.where(again & (count > 0), count + 1, count)
        count[moved] = ~np.isin(now[moved], list(mine))
        goal[moved] = now[moved]
        if count.max() < self.settled:
            return {}
        # Groups waiting at two goals in sight would each take the other for anchors: the
        # goal of the teammate seen settled there longest (the one that never left) wins.
        held = goal[int(np.argmax(count))]
        return {int(j): int(held) for j in np.flatnonzero((count >= self.settled) & (goal == held))}

    def unseen(self, observations: Observations, robot: int, goals=(), tau=1.0):
        """Draws of where never-seen teammates may be (``plan_hidden``: ``goals``, ``tau``)."""
        if self.hidden is not None:
            return self.hidden.draws(observations, robot, goals, tau)
        never = observations.last_seen[robot] < 0
        never[robot] = False
        if not never.any() or self.places.shape[0] == 0:
            return None
        return np.where(never[None, :, None], self.places, np.nan)

    def typed(self, ctrl, goals, robot: int, observations: Observations) -> np.ndarray | None:
        """Score the teammates' moves since the robot's last plan under each type, and
        return the rows of the teammates to predict by their type (``nan``: a planner),
        or ``None`` where types are off (``plan_types = 0``).

        A teammate is typed where the posterior on greedy and stationary together
        reaches ``plan_types`` and it is seen on a goal (within :data:`ON_GOAL` plus two
        standard deviations of the sightings' noise): it holds to that goal."""
        if self.threshold <= 0:
            return None
        s, step = self.scenario, observations.step
        now = observations.poses[robot, :, :2]
        seen = observations.last_seen[robot] == step
        seen[robot] = False
        log_types = self._types.setdefault(robot, np.tile(np.log(TYPE_PRIOR), (s.n_robots, 1)))
        last = self._typing.get(robot)
        if last is not None and last[0] == step - 1 and np.array_equal(last[1], goals):
            both = seen & last[3]
            if both.any():  # one step's moves under each type (the team row: the plan's)
                reach = s.max_speed[both] * s.dt
                ll = motion_log_likelihood(last[2][both], now[both], last[4][both], ctrl.goals,
                                           reach, self.type_sigma, self.driving)  # fmt: skip
                log_types[both] = update_types(log_types[both], ll, self.type_leak)
        distance = goal_distances(now, ctrl.goals)
        convention = least_cost_from_distances(distance[None], ctrl.configurations)[0]
        uniform = np.full(distance.shape, 1.0 / distance.shape[1])
        probs = planner_type_goals(uniform, distance, convention)
        self._typing[robot] = (step, np.asarray(goals).copy(), now.copy(), seen, probs)
        rows = typed_predictions(log_types, probs, self.threshold)
        # It holds to the goal it stands on: typed only where seen on one (noise allowed).
        rows[distance.min(axis=1) > ON_GOAL + 2 * np.sqrt(s.position_noise)] = np.nan
        return rows

    def yields(self, robot: int) -> ClaimModel | None:
        """A claim's :func:`claim_yields` (``None``: all yield; ``plan_claim`` 1, types off)."""
        log_types = self._types.get(robot)
        if not self.by_type or log_types is None:
            return None
        if not self.keeping:
            return claim_yields(log_types)
        never = self._last[robot][2] < 0 if self.unread else None
        return claim_yields(log_types, self._typing[robot][4], never)

    def _type_record(self, robot: int, typed) -> tuple:
        """The robot's type posteriors of every robot and which are typed, for a record."""
        log_types = self._types.get(robot)
        if typed is None or log_types is None:
            return None, None
        posterior = np.exp(log_types - log_types.max(axis=1, keepdims=True))
        return posterior / posterior.sum(axis=1, keepdims=True), ~np.isnan(typed[:, 0])

    def decide(
        self, ctrl, goals, robot: int, observations: Observations, prior, sets=None
    ) -> Decision:
        """Robot ``robot``'s decision over ``ctrl``'s table of ``goals`` (scenario
        indices): the plan's goal, or standing still to wait."""
        s = self.scenario
        pose = observations.poses[robot, robot]
        moving = self.observe(observations, robot)
        local = np.flatnonzero(goals == self._heading.get(robot, -1))
        progress = self._progress(robot, pose)
        typed = self.typed(ctrl, goals, robot, observations)
        read = self._read[robot][:, goals]
        previous = int(local[0]) if local.size else None
        if self.reselected:
            read, previous = np.zeros_like(read), None
        result = self.planner(ctrl).plan(
            robot, observations.poses[robot], prior, sets, moving, read, previous,
            self.unseen(observations, robot, goals, self.planner(ctrl).tau), typed,
            observations.last_seen[robot] < 0 if self.blind else None,
            observations.last_seen[robot] == observations.step,  # who sees it: sight is mutual
            progress, self.yields(robot),
        )  # fmt: skip
        if typed is not None:  # the team type is the planner: its moves are scored by the plan
            planned = result.planned
            if self.yielding and result.goal != WAIT:
                pl, at = self.planner(ctrl), observations.poses[robot, :, :2]
                planned = yielded(planned, result.goal, robot, at, pl.goals, pl.speeds,
                                  pl.configurations)  # fmt: skip
            self._typing[robot][4][:, TYPES.index("team")] = planned
        if result.goal != WAIT:
            chosen = int(goals[result.goal])
            if self._start.get(robot, (-1,))[0] != chosen:
                self._start[robot] = (chosen, float(np.hypot(*(s.goals[chosen] - pose[:2]))))
            self._heading[robot] = chosen
        log = _RECORDER.get()
        if log is not None:
            chosen = int(goals[result.goal]) if result.goal != WAIT else WAIT
            sizes = {chain: int(np.count_nonzero(mask)) for chain, mask in (sets or {}).items()}
            log.append(PlanRecord(observations.step, robot, np.asarray(goals).copy(), result.G,
                                  result.wait, result.predictions, result.belief, result.focal,
                                  chosen, observations.poses[robot, :, :2].copy(),
                                  observations.last_seen[robot] >= 0, sizes,
                                  *self._type_record(robot, typed)))  # fmt: skip
        if result.goal == WAIT:
            control = (0.0, 0.0)
        else:
            target = ctrl.goals[result.goal]
            c = steer(pose[None], target[None], s.max_speed[[robot]], s.max_turn[[robot]], s.dt)
            control = (float(c[0, 0]), float(c[0, 1]))
        G = np.append(result.G, result.wait)
        finite = np.isfinite(G)
        q = np.where(finite, np.exp(-(G - G[finite].min())), 0.0)
        return Decision(control, int(result.goal), G, q / q.sum(), result.belief, result.focal)


def yielded(planned, goal: int, robot: int, positions, goals, speeds, configurations) -> np.ndarray:
    """``(n, m)`` the planner's predictions ``planned`` as a claim assumes them (``plan_claim
    = 3``): a teammate that would reach ``goal``, the robot's, after the robot (straight-line
    times, as the plan's) and shares it with it in no configuration finds it taken and
    yields, ``pi_l(h) / (1 - pi_l(goal))``; the team type's moves are scored against that.

    Examples
    --------
    Robot 0 is 1 s from goal 0, robot 1 is 3 s away and predicted there with 0.8:

    >>> planned = np.array([[1.0, 0.0, 0.0], [0.8, 0.15, 0.05]])
    >>> yielded(planned, 0, 0, np.array([[1.0, 0.0], [3.0, 0.0]]),
    ...         np.array([[0.0, 0.0], [0.0, 9.0], [9.0, 9.0]]), np.ones(2),
    ...         np.array([[0, 1], [1, 0], [0, 2], [2, 0]])).round(2).tolist()
    [[1.0, 0.0, 0.0], [0.0, 0.75, 0.25]]
    """
    times = np.hypot(*(np.asarray(positions) - goals[goal]).T) / speeds
    later = later_claimants(times, robot, goal, configurations)
    out = np.array(planned, dtype=float)
    rest = out[later].copy()
    rest[:, goal] = 0.0
    total = rest.sum(axis=1, keepdims=True)
    out[later] = np.where(total > 0, rest / np.where(total > 0, total, 1.0), out[later])
    return out
