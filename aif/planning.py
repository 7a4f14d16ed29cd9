"""Planning by expected free energy over nested predictions of teammates' choices.

A robot chooses among *options* rather than controls: head for one of its goals (its slot
in some valid configuration), or wait a few steps and choose once its teammates' moves have
said more. Each option is scored by its expected free energy under the robot's beliefs,
with a preference over outcomes that is exponential in the team's completion time
(``ln C(T) = -T / tau``), so that ``G`` is an expected completion time in units of the
precision ``tau``:

- heading for goal ``g``, with the teammates' choices predicted as independent
  distributions ``pi_l`` over their goals::

      G(g) = [ sum_{c in S, c_i = g} w(c) T(c)  +  (1 - sum_{c in S, c_i = g} w(c)) F(g) ] / tau
      w(c) = prod_{l != i} pi_l(c_l)

  ``S`` is the set of configurations the robot keeps (what it knows), ``T(c)`` the time
  at which the last robot reaches its goal in ``c``, and ``F(g)`` the cost of a
  mismatch: its own travel time and a repair time. The first sum is the risk of the
  outcome; a mismatch is the outcome the preference rules out.
- waiting ``h`` steps (``horizon > 1``): every teammate keeps moving towards its true
  goal ``o_l`` and the robot's evidence for it grows by ``h dt v_l / eta`` nats; the robot
  then heads for the goal of least ``G`` under its revised predictions. ``G(wait)`` is the
  expected realised cost of that choice, averaged over sampled particles ``o ~ pi``: the
  risk after observing, which is the risk now less the value of the information (the
  epistemic term of expected free energy, here in its sophisticated, look-ahead form).

The predictions are where the order of reasoning enters. A robot at order ``k`` predicts
each teammate ``l`` as ``l`` choosing by the same expected free energy at order ``k - 1``,
over the set the robot knows ``l`` keeps (``S_il``, from the nested sets of the DEL state),
and ``l``'s own predictions at order ``k - 2`` over ``S_ilj``, down to order 0: a
teammate's goal from the prior over its set alone. Every prediction is then weighed by
the evidence of the teammate's observed position (``-d / eta`` nats; close to a goal is
heading for it): ``pi_l ∝ softmax(-G_l) · exp(-d_l / eta)``. Second order is what I think
you will do; third order, what I think you think I will do.

Examples
--------
Two robots must meet (rendezvous) at one of two goals; robot 1 stands on goal 1:

>>> import numpy as np
>>> goals = [[0.0, 0.0], [10.0, 0.0]]
>>> planner = Planner(goals, [[0, 0], [1, 1]], [1.0, 1.0], order=1)
>>> result = planner.plan(0, [[4.0, 0.0], [10.0, 0.0]])
>>> result.goal                                # closer to goal 0, but goes where 1 stands
1
>>> bool(result.G[1] < result.G[0])
True
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from epistemica.aif._validate import as_finite, positive, positive_int
from epistemica.aif.evidence import check_order, check_robot
from epistemica.aif.likelihood import check_configurations
from epistemica.aif.plan_context import PlanContext, places_in_square
from epistemica.aif.plan_waiting import model, wait_cost
from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "WAIT",
    "PlanResult",
    "Planner",
    "filter_sightings",
    "motion_evidence",
    "places_in_square",
]

#: :attr:`PlanResult.goal` of the waiting option.
WAIT = -1


class PlanResult(NamedTuple):
    """One robot's plan at one step.

    Attributes
    ----------
    goal : int
        The goal it heads for (an index into the planner's goals), or :data:`WAIT`.
    G : numpy.ndarray
        ``(m,)`` expected free energy (nats) of heading for each goal; ``inf`` where the
        goal is in no configuration the robot keeps.
    wait : float
        Expected free energy of waiting (``inf`` when not planned: horizon 1, order 0).
    predictions : numpy.ndarray
        ``(n, m)`` predicted goal distribution of every robot; the robot's own row is
        ``softmax(-G)``.
    belief : numpy.ndarray
        ``(k,)`` the robot's belief over the configurations: their probability under
        the predictions, zero outside its set.
    focal : int
        The most probable configuration with the robot at its chosen goal.
    planned : numpy.ndarray or None
        ``(n, m)`` every robot as the robot predicts it *as a planner*: ``predictions``
        with the rows of the teammates it predicts by their type (``typed``) replaced by
        the planner's prediction (what their moves are scored against).
    """

    goal: int
    G: np.ndarray
    wait: float
    predictions: np.ndarray
    belief: np.ndarray
    focal: int
    planned: np.ndarray | None = None


class Planner:
    """Expected-free-energy planning over goals at an order of reasoning.

    Parameters
    ----------
    goals : array_like
        ``(m, 2)`` goal positions.
    configurations : array_like
        ``(k, n)`` valid configurations (goal index per robot).
    speeds : array_like
        ``(n,)`` maximum speed of each robot (m/s).
    order : {0, 1, 2, 3}
        Order of reasoning. 0 heads for the goal the prior favours, without predicting
        anyone.
    dt : float
        Time step (s).
    temperature, evidence : float
        The precision ``tau`` and the evidence scale ``eta``, as fractions of the goals'
        typical spread ``D`` (the median distance between two goals; for ``tau``, its
        travel time at the mean speed).
    success_weight : float
        The risk's weight on the outcome "the configuration forms": ``G(g) = E[T | formed]
        / tau - success_weight * ln P(formed)`` (nats). 0 scores the expected completion
        time with a mismatch costing ``repair`` instead.
    repair : float
        The repair time of a mismatch (with ``success_weight = 0``, and in the waiting
        option's realised costs), in units of the longest trip between two goals at the
        slowest speed.
    horizon, waiting : int
        Steps of the waiting option (1 plans none: the myopic ablation); its model of the
        teammates, 0-8 (:mod:`epistemica.aif.plan_waiting`).
    particles : int
        Particles of the teammates' choices that score the waiting option: a
        low-discrepancy (Weyl) sequence through each predicted distribution, so a plan is
        a deterministic function of what the robot observes and no random stream is used.
    commitment : float
        Nats a robot pays to change the goal it headed for at its last plan.
    convention : float
        Nats a goal costs the robot as its prior marginal falls short of the most
        probable goal's: ``convention * (1 - p(g) / max p)``, a bounded tie-break (the
        team prior is sharp; as log-odds it would overrule everything) that resolves
        symmetric standoffs the same way for every robot.
    hierarchy : float
        In ``[0, 1]``: a teammate predicted at order ``k`` is the mixture of orders
        ``0..k`` with weights ``hierarchy ** (k - j)`` (a cognitive hierarchy); 0 predicts
        it at order ``k`` alone (level-k).
    shown, sigma : float
        Steps a watching teammate (``plan(watching=...)``) sees the robot head for an
        option's goal before it is scored, at order >= 2 (0: one prediction for every
        option); the watchers' motion error in steps of the mean top speed.
    claim : bool
        A goal is held by who reaches it first: teammates that would reach it later, and
        share it in no configuration, are predicted elsewhere (``PlanContext.claimed``),
        each with the probability that it yields (``plan(yields=)``; default: all do).
    arrivals : bool
        A never-seen teammate's trips are averaged over its draws (``plan(unseen=)``),
        each goal's weighed by the draws' choice of it (``plan_context.arrivals``).
    """

    def __init__(
        self,
        goals,
        configurations,
        speeds,
        *,
        order: int = 1,
        dt: float = 1.0,
        temperature: float = 0.25,
        repair: float = 1.5,
        evidence: float = 5.0,
        horizon: int = 1,
        particles: int = 32,
        commitment: float = 0.0,
        convention: float = 0.0,
        hierarchy: float = 0.0,
        success_weight: float = 1.0,
        shown: float = 0.0,
        sigma: float = 0.5,
        claim: bool = False,
        arrivals: bool = False,
        waiting: int = 0,
    ) -> None:
        self.goals = as_finite(goals, "goals", ndim=2, shape=(None, 2))
        self.speeds = as_finite(speeds, "speeds", ndim=1)
        n, m = self.speeds.shape[0], self.goals.shape[0]
        if n == 0 or m == 0 or np.any(self.speeds <= 0):
            raise InvalidArgumentError(
                "need at least one robot, one goal and positive speeds",
                hint="pass each robot's maximum speed",
            )
        self.configurations = check_configurations(configurations, n, m)
        self.order = check_order(order)
        self.dt = positive(dt, "dt")
        self.horizon = positive_int(horizon, "horizon", "1 plans no waiting")
        self.particles = positive_int(particles, "particles", "e.g. 32")
        self.commitment = float(as_finite(commitment, "commitment"))
        self.convention = float(as_finite(convention, "convention"))
        self.hierarchy = float(as_finite(hierarchy, "hierarchy"))
        self.success_weight = float(as_finite(success_weight, "success_weight"))
        self.shown = float(as_finite(shown, "shown"))
        self.claim, self.arrivals, self.waiting = bool(claim), bool(arrivals), model(waiting)
        if self.shown < 0:
            raise InvalidArgumentError("shown must be >= 0", hint="steps; 0 leaves it out")
        if self.success_weight < 0:
            raise InvalidArgumentError(
                "success_weight must be >= 0", hint="nats per nat of -ln P(success); 0: time"
            )
        if not 0.0 <= self.hierarchy <= 1.0:
            raise InvalidArgumentError(
                f"hierarchy must lie in [0, 1], got {hierarchy!r}", hint="0 is pure level-k"
            )
        if self.commitment < 0 or self.convention < 0:
            raise InvalidArgumentError(
                "commitment and convention must be >= 0", hint="nats; 0 leaves them out"
            )
        spread = self.goals[:, None, :] - self.goals[None, :, :]
        pairs = np.hypot(spread[..., 0], spread[..., 1])[np.triu_indices(m, 1)]
        scale = float(np.median(pairs)) if pairs.size and np.median(pairs) > 0 else 1.0
        travel = scale / float(self.speeds.mean())
        diameter = float(pairs.max()) if pairs.size else scale
        self.tau = positive(temperature, "temperature") * travel
        # A mismatch costs more than any trip between goals: someone has to cross them.
        self.repair = positive(repair, "repair") * max(diameter, scale) / float(self.speeds.min())
        self.eta = positive(evidence, "evidence") * scale
        self.sigma = positive(sigma, "sigma") * float(self.speeds.mean()) * self.dt

    def plan(
        self,
        robot: int,
        positions,
        prior=None,
        sets: Mapping[tuple[int, ...], np.ndarray] | None = None,
        moving=None,
        evidence=None,
        previous: int | None = None,
        unseen=None,
        typed=None,
        blind=None,
        watching=None,
        progress: float = 0.0,
        yields=None,
    ) -> PlanResult:
        """Robot ``robot``'s plan from the positions it observes.

        Parameters
        ----------
        robot : int
            The planning robot.
        positions : array_like
            ``(n, 2)`` (or ``(n, 3)`` poses): where it sees every robot, itself exactly.
        prior : array_like, optional
            ``(k,)`` configuration weights (default uniform), read by order 0.
        sets : mapping, optional
            Chain ``(robot, l, ...)`` -> ``(k,)`` booleans: what ``robot`` knows the last one
            keeps, as the middle ones see it (default: the longest prefix's; empty: all).
        moving : array_like, optional
            ``(n,)`` in ``[0, 1]``: the share of its speed each teammate was seen to use.
        evidence : array_like, optional
            ``(n, m)`` log-likelihood of each robot heading for each goal from its moves
            (:func:`motion_evidence`; beside the position's ``-d / eta``).
        previous : int, optional
            The goal it headed for at its last plan: changing it costs ``commitment``
            nats and the ``progress`` seconds it has driven towards it.
        unseen, typed : array_like, optional
            ``(P, n, 2)`` draws of where each teammate never seen may be (``nan``: seen);
            ``(n, m)`` goal distributions of ad hoc teammates (``nan`` rows: planners;
            :func:`epistemica.aif.teammates.typed_predictions`).
        blind, watching, yields : array_like, optional
            ``(n,)``. ``blind``: the teammates never seen (a placeholder is no evidence of
            one's goal, nor of others they predict); ``watching``: those that see the robot
            now (``shown``); ``yields``: P(each gives up a goal it finds taken, as a planner
            does; ``claim``; default 1), or a :class:`~epistemica.aif.teammates.ClaimModel`.

        Examples
        --------
        Allocation of two robots to two goals; robot 0 knows robot 1 keeps only goal 0:

        >>> planner = Planner([[0.0, 0.0], [10.0, 0.0]], [[0, 1], [1, 0]], [1.0, 1.0],
        ...                   order=2, horizon=1)
        >>> only = np.array([False, True])
        >>> planner.plan(0, [[1.0, 0.0], [9.0, 0.0]], sets={(0, 1): only}).goal
        1
        """
        robot = check_robot(robot, self.speeds.shape[0])
        n, k = self.speeds.shape[0], self.configurations.shape[0]
        pos = as_finite(positions, "positions", ndim=2, shape=(n, None))[:, :2]
        weights, moving, evidence, unseen = self._inputs(k, prior, moving, evidence, unseen)
        inputs = (pos, weights, sets, evidence, unseen, blind, yields)
        context = self._context(robot, *inputs, typed)
        G = self._shown(context, robot, inputs, typed, watching)
        G = self._own_costs(G, robot, weights, previous, progress)
        own = context.choice((robot,), self.order)
        below = max(self.order - 1, 0)
        preds = np.stack(
            [own if j == robot else context.choice((robot, j), below) for j in range(n)]
        )
        wait = wait_cost(context, robot, preds, moving, G, watching)  # inf: none planned
        best = int(np.argmin(G))
        goal = WAIT if wait < G[best] or not np.isfinite(G[best]) else best
        belief = context.belief((robot,), preds)
        mine = self.configurations[:, robot] == goal if goal != WAIT else np.ones(len(belief))
        focal = int(np.argmax(np.where(mine, belief, -1.0)))
        planned = self._as_planners(context, robot, preds, inputs)
        return PlanResult(goal, G / self.tau, wait / self.tau, preds, belief, focal, planned)

    def _inputs(self, k: int, prior, moving, evidence, unseen) -> tuple:
        """The plan's optional inputs checked, with their defaults."""
        n = self.speeds.shape[0]
        weights = np.ones(k) if prior is None else as_finite(prior, "prior", ndim=1, shape=(k,))
        if np.any(weights < 0):
            raise InvalidArgumentError("prior must be non-negative", hint="weights or a pmf")
        moving = np.ones(n) if moving is None else np.clip(as_finite(moving, "moving"), 0, 1)
        if evidence is not None:
            evidence = as_finite(evidence, "evidence", ndim=2, shape=(n, self.goals.shape[0]))
        return weights, moving, evidence, None if unseen is None else np.asarray(unseen, float)

    def _as_planners(self, context, robot: int, preds: np.ndarray, inputs) -> np.ndarray:
        """``preds`` with each typed teammate's row its prediction as a planner: the same
        plan's ``inputs`` (positions, prior, sets, evidence, draws, blind, yields) without
        the types."""
        planned = preds.copy()
        if context.typed:
            plain = self._context(robot, *inputs, None)
            for j in context.typed:
                planned[j] = plain.choice((robot, j), max(self.order - 1, 0))
        return planned

    def _context(self, robot: int, pos, weights, sets, evidence, unseen, blind, yields,
                 typed) -> PlanContext:  # fmt: skip
        """One plan's predictions: the moves' evidence, who was never seen and who yields
        first (every prediction below reads them), then the typed teammates and the
        unseen teammates' draws."""
        context = PlanContext(self, pos, weights, dict(sets or {}))
        if yields is not None:
            context.give_way(robot, yields)
        if blind is not None:
            context.hide(robot, blind)
        if evidence is not None:
            context.extra = evidence
            context.evidence = context.evidence + evidence
        if typed is not None:
            context.type_rows(robot, np.asarray(typed, dtype=float))
        if unseen is not None:
            context.predict_unseen(robot, unseen)
        return context

    def risk(self, formed: np.ndarray, timed: np.ndarray, alone: np.ndarray) -> np.ndarray:
        """Risk (s) of options whose configuration forms with probability ``formed``,
        ``timed`` the sum of ``P(c) T(c)`` over those configurations, ``alone`` the own
        trip: ``E[T | formed] - success_weight * tau * ln P(formed)``, or with
        ``success_weight = 0`` the expected time with a mismatch costing ``alone +
        repair``."""
        if self.success_weight > 0:
            with np.errstate(divide="ignore", invalid="ignore"):
                given = np.where(formed > 0, timed / formed, alone)
            return given - self.success_weight * self.tau * np.log(np.maximum(formed, 1e-12))
        return timed + (1.0 - formed) * (alone + self.repair)

    def _shown(self, context, robot: int, inputs, typed, watching) -> np.ndarray:
        """``(m,)`` the robot's own expected times; with ``shown`` steps, each goal's with
        the teammates watching it predicted as having seen it head there (order >= 2:
        what they think it does enters their choice)."""
        G = context.costs((robot,), self.order)
        watchers = [] if watching is None else np.flatnonzero(np.asarray(watching, bool))
        watchers = [int(j) for j in watchers if j != robot]
        if self.shown <= 0 or self.order < 2 or not watchers:
            return G
        n, m, below = self.speeds.shape[0], self.goals.shape[0], self.order - 1
        preds = np.stack([context.choice((robot, j), below) for j in range(n)])
        here = np.repeat(inputs[0][[robot]], m, axis=0)
        to_goal = self.goals - here
        distance = np.maximum(np.hypot(to_goal[:, 0], to_goal[:, 1]), 1e-9)
        step = np.minimum(self.speeds[robot] * self.dt, distance)[:, None] * to_goal
        speeds = np.full(m, self.speeds[robot])
        moves = motion_evidence(here, here + step / distance[:, None], self.goals, speeds,
                                self.dt, self.sigma)  # fmt: skip
        out = G.copy()
        for g in np.flatnonzero(np.isfinite(G)):
            seen = self._context(robot, *inputs, typed)
            seen.evidence[robot] = seen.evidence[robot] + self.shown * moves[g]
            shown = preds.copy()
            for j in watchers:
                shown[j] = seen.choice((robot, j), below)
            out[g] = seen.given((robot,), shown)[g]
        return out

    def _own_costs(self, G: np.ndarray, robot: int, weights, previous, progress=0.0
                   ) -> np.ndarray:  # fmt: skip
        """``(m,)`` the robot's own expected times ``G`` with the convention's tie-break
        and the cost of changing its goal."""
        if self.convention > 0:  # the shared tie-break: symmetric standoffs resolve alike
            mass = np.bincount(self.configurations[:, robot], weights=weights,
                               minlength=G.shape[0])  # fmt: skip
            G = G + self.convention * self.tau * (1.0 - mass / mass.max())
        if previous is not None and 0 <= previous < G.shape[0] and np.isfinite(G[previous]):
            switch = self.commitment * self.tau + max(float(progress), 0.0)
            G = G + switch
            G[previous] -= switch
        return G


def motion_evidence(before, after, goals, speeds, dt: float, sigma) -> np.ndarray:
    """``(n, m)`` log-likelihood of one step's moves ``before -> after`` for each goal.

    A robot heading for goal ``g`` moves ``min(v dt, d)`` straight at it (and stands once
    there); the observed move is that with Gaussian error ``sigma`` (m) per axis, one
    value or ``(n,)`` (a robot seen through noisier sightings moves the reading less).
    ``goals`` is ``(m, 2)``, or ``(n, m, 2)``: per robot, the point it steers for when
    heading for each goal (round a wall: the corner it drives to first).
    Summed over steps, this is how a teammate's goal is read from what it does, standing
    still on a goal included.

    Examples
    --------
    >>> goals = [[10.0, 0.0], [-10.0, 0.0]]
    >>> motion_evidence([[0.0, 0.0]], [[1.0, 0.0]], goals, [1.0], 1.0, 0.5).round(1).tolist()
    [[-0.0, -8.0]]
    """
    before = np.asarray(before, dtype=float)[:, :2]
    after = np.asarray(after, dtype=float)[:, :2]
    goals = np.asarray(goals, dtype=float)
    to_goal = (goals if goals.ndim == 3 else goals[None]) - before[:, None]  # (n, m, 2)
    distance = np.hypot(to_goal[..., 0], to_goal[..., 1])
    reach = np.minimum(np.asarray(speeds, dtype=float)[:, None] * dt, distance)
    unit = to_goal / np.where(distance > 0, distance, 1.0)[..., None]
    residual = (after - before)[:, None] - reach[..., None] * unit
    sigma = np.broadcast_to(np.asarray(sigma, dtype=float), before.shape[:1])[:, None]
    return -(residual**2).sum(axis=2) / (2 * sigma**2)


def filter_sightings(track, sighted, variance, goals, speeds, steps, sigma) -> np.ndarray:
    """``(n, m)`` log-likelihood of new sightings under each goal, read by a Kalman filter
    per robot and goal hypothesis; updates ``track`` in place.

    Under "heading for goal ``g``" a robot moves ``min(v, d)`` per step straight at it
    (random-walk error ``sigma`` m per step and axis) and is sighted with per-axis
    ``variance``. A sighting's evidence is its innovation ``-|s - x|² / 2S`` against the
    filtered position ``x`` of that hypothesis (``S``, predicted plus sighting variance,
    is the same for every goal). Two consecutive moves share a sighting; read through
    the filter, its noise counts once, not once per move.

    Parameters
    ----------
    track : tuple of numpy.ndarray
        ``(mean (n, m, 2), var (n,), last (n,))``: filtered positions, their per-axis
        variance, the step of each robot's last sighting (-1: never; a first sighting
        starts the filter and reads nothing).
    sighted : array_like
        ``(n, 2)`` this step's sightings, ``nan`` rows for robots not sighted.
    variance, speeds : array_like
        ``(n,)`` per-axis sighting variance (m²), top speed (m per step).
    goals, steps, sigma
        ``(m, 2)`` goal positions; the current step; the motion model's error (m per step).

    Examples
    --------
    >>> track = (np.zeros((1, 2, 2)), np.zeros(1), np.array([-1]))
    >>> goals, at = [[10.0, 0.0], [-10.0, 0.0]], np.array([[0.0, 0.0]])
    >>> filter_sightings(track, at, [1.0], goals, [1.0], 0, 0.5).tolist()  # starts
    [[0.0, 0.0]]
    >>> filter_sightings(track, at + [1.0, 0.0], [1.0], goals, [1.0], 1, 0.5).round(2).tolist()
    [[-0.0, -0.89]]
    """
    (mean, var, last), variance = track, np.asarray(variance, dtype=float)
    sighted, out = np.asarray(sighted, dtype=float), np.zeros(mean.shape[:2])
    new = ~np.isnan(sighted).any(axis=1)
    first = new & (last < 0)
    mean[first], var[first] = sighted[first][:, None, :], variance[first]
    rows = new & (last >= 0)
    if rows.any():
        gap = (steps - last[rows]).astype(float)
        to_goal = np.asarray(goals, dtype=float)[None] - mean[rows]  # (r, m, 2)
        distance = np.hypot(to_goal[..., 0], to_goal[..., 1])
        reach = np.minimum(np.asarray(speeds, dtype=float)[rows][:, None] * gap[:, None], distance)
        predicted = mean[rows] + reach[..., None] * to_goal / np.maximum(distance, 1e-12)[..., None]
        prior = var[rows] + sigma**2 * gap  # the same for every goal
        total, innovation = prior + variance[rows], sighted[rows][:, None, :] - predicted
        out[rows] = -(innovation**2).sum(axis=2) / (2 * total[:, None])
        gain = prior / total
        mean[rows], var[rows] = predicted + gain[:, None, None] * innovation, prior * (1 - gain)
    last[new] = steps
    return out
