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
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["WAIT", "PlanResult", "Planner", "motion_evidence", "places_in_square"]

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
    """

    goal: int
    G: np.ndarray
    wait: float
    predictions: np.ndarray
    belief: np.ndarray
    focal: int


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
    horizon : int
        Steps of the waiting option; 1 plans no waiting (the myopic ablation).
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
        success_weight: float = 3.0,
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
    ) -> PlanResult:
        """Robot ``robot``'s plan from the positions it observes.

        Parameters
        ----------
        robot : int
            The planning robot.
        positions : array_like
            ``(n, 2)`` (or ``(n, 3)`` poses): where it sees every robot, itself exactly.
        prior : array_like, optional
            ``(k,)`` weights of the configurations (default uniform): what order 0 reads
            a teammate's goal from.
        sets : mapping, optional
            Chain of robots ``(robot, l, ...)`` -> ``(k,)`` booleans: the configurations
            ``robot`` knows that the last robot of the chain keeps, as the chain's middle
            robots see it (a chain without an entry takes its longest prefix that has one,
            a chain whose set is empty restricts nothing; default every configuration).
        moving : array_like, optional
            ``(n,)`` in ``[0, 1]``: how much of its speed each teammate was seen to use
            (what waiting can reveal); default 1.
        evidence : array_like, optional
            ``(n, m)`` log-likelihood of each robot heading for each goal from what the
            robot saw of its moves (:func:`motion_evidence`), added to the position's
            ``-d / eta``.
        previous : int, optional
            The goal the robot headed for at its last plan: changing it costs
            ``commitment`` nats (teammates have read it from the robot's moves).
        unseen : array_like, optional
            ``(P, n, 2)`` places a teammate the robot has never seen may be (a row per
            draw), ``nan`` for the robots it has seen. Such a teammate's ``positions`` row
            is a placeholder: it is predicted as the mean of its predictions from the ``P``
            places, not from the placeholder (two unseen teammates at one placeholder
            would both be predicted at its nearest goal). Default: every robot seen.

        Examples
        --------
        Allocation of two robots to two goals; robot 1 knows only configurations that
        put it on goal 0, and robot 0 knows that:

        >>> planner = Planner([[0.0, 0.0], [10.0, 0.0]], [[0, 1], [1, 0]], [1.0, 1.0],
        ...                   order=2, horizon=1)
        >>> only = np.array([False, True])
        >>> planner.plan(0, [[1.0, 0.0], [9.0, 0.0]], sets={(0, 1): only}).goal
        1
        """
        robot = check_robot(robot, self.speeds.shape[0])
        n, k = self.speeds.shape[0], self.configurations.shape[0]
        pos = as_finite(positions, "positions", ndim=2, shape=(n, None))[:, :2]
        weights = np.ones(k) if prior is None else as_finite(prior, "prior", ndim=1, shape=(k,))
        if np.any(weights < 0):
            raise InvalidArgumentError("prior must be non-negative", hint="weights or a pmf")
        moving = np.ones(n) if moving is None else np.clip(as_finite(moving, "moving"), 0, 1)
        context = _Context(self, pos, weights, dict(sets or {}))
        if unseen is not None:
            self._predict_unseen(context, robot, np.asarray(unseen, dtype=float))
        if evidence is not None:
            context.extra = as_finite(evidence, "evidence", ndim=2, shape=context.times.shape)
            context.evidence = context.evidence + context.extra
        G = self._own_costs(context, robot, weights, previous)
        own = context.choice((robot,), self.order)
        below = max(self.order - 1, 0)
        preds = np.stack(
            [own if j == robot else context.choice((robot, j), below) for j in range(n)]
        )
        wait = np.inf
        if self.horizon > 1 and self.order >= 1 and n > 1:
            wait = context.waiting(robot, preds, moving)
        best = int(np.argmin(G))
        goal = WAIT if wait < G[best] or not np.isfinite(G[best]) else best
        belief = context.belief((robot,), preds)
        mine = self.configurations[:, robot] == goal if goal != WAIT else np.ones(len(belief))
        focal = int(np.argmax(np.where(mine, belief, -1.0)))
        return PlanResult(goal, G / self.tau, wait / self.tau, preds, belief, focal)

    def _predict_unseen(self, context, robot: int, places: np.ndarray) -> None:
        """Put the mean prediction of each never-seen teammate over ``places`` (its draws
        of where it may be) into ``context``: as the robot predicts it, and as it predicts
        each teammate to predict it (chains of two and three robots)."""
        n = self.speeds.shape[0]
        if places.ndim != 3 or places.shape[1:] != (n, 2):
            raise InvalidArgumentError(
                f"unseen must have shape (P, {n}, 2), got {places.shape}",
                hint="places per draw and robot, nan for the robots seen",
            )
        hidden = np.flatnonzero(~np.isnan(places).any(axis=(0, 2)))
        hidden = hidden[hidden != robot]
        if hidden.size == 0 or self.order == 0 or places.shape[0] == 0:
            return
        chains = [((robot, int(j)), self.order - 1) for j in hidden]
        if self.order >= 2:
            chains += [((robot, k, int(j)), self.order - 2)
                       for k in range(n) if k != robot for j in hidden if j != k]  # fmt: skip
        keys = {context.key(chain, order): (chain, order) for chain, order in chains}
        total = dict.fromkeys(keys, 0.0)
        for draw in places:
            moved = context.pos.copy()
            moved[hidden] = draw[hidden]
            there = _Context(self, moved, context.prior, context.sets, context.masks)
            there.evidence = there.evidence + context.extra
            for key, (chain, order) in keys.items():
                total[key] = total[key] + there.choice(chain, order)
        for key, value in total.items():
            context.memo[key] = value / places.shape[0]

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

    def _own_costs(self, context, robot: int, weights, previous) -> np.ndarray:
        """``(m,)`` the robot's own expected times, with the convention's tie-break and
        the cost of changing its goal."""
        G = context.costs((robot,), self.order)
        if self.convention > 0:  # the shared tie-break: symmetric standoffs resolve alike
            mass = np.bincount(self.configurations[:, robot], weights=weights,
                               minlength=G.shape[0])  # fmt: skip
            G = G + self.convention * self.tau * (1.0 - mass / mass.max())
        if previous is not None and 0 <= previous < G.shape[0] and np.isfinite(G[previous]):
            G = G + self.commitment * self.tau
            G[previous] -= self.commitment * self.tau
        return G


class _Context:
    """The memoised predictions of one plan: chain and order -> a goal distribution."""

    def __init__(self, planner: Planner, pos: np.ndarray, prior: np.ndarray, sets,
                 masks: dict | None = None) -> None:  # fmt: skip
        self.p = planner
        self.masks = {} if masks is None else masks  # chain -> (set, its bytes)
        self.pos = pos
        self.prior = prior
        self.sets = sets
        self.depth = min(max((len(c) for c in sets), default=0), max(planner.order, 1))
        delta = pos[:, None, :] - planner.goals[None, :, :]
        distance = np.hypot(delta[..., 0], delta[..., 1])
        self.times = distance / planner.speeds[:, None]  # (n, m) seconds
        self.evidence = -distance / planner.eta  # (n, m) nats
        self.extra = np.zeros_like(self.evidence)  # what the robot read from the moves
        rows = planner.configurations
        self.row_times = self.times[np.arange(rows.shape[1]), rows]  # (k, n)
        self.memo: dict = {}

    def mask(self, chain: tuple[int, ...]) -> np.ndarray | None:
        return self._mask(chain)[0]

    def _mask(self, chain: tuple[int, ...]) -> tuple[np.ndarray | None, bytes | None]:
        """The chain's set and its bytes (memoised: every prediction asks again)."""
        found = self.masks.get(chain, False)
        if found is not False:
            return found
        found = None, None
        # A robot at order k models sets down to chains of length k, no deeper.
        for length in range(min(len(chain), max(self.p.order, 1)), 0, -1):
            kept = self.sets.get(chain[:length])
            if kept is not None:
                kept = np.asarray(kept, dtype=bool)
                # A chain that keeps nothing (its facts contradict each other) restricts
                # nothing, as in the one-step controller's priors.
                found = (kept, kept.tobytes()) if kept.any() else (None, None)
                break
        self.masks[chain] = found
        return found

    def key(self, chain: tuple[int, ...], order: int) -> tuple:
        if len(chain) < self.depth:  # deeper chains may have sets of their own
            return chain, order
        return self._mask(chain)[1], chain[-1], order, len(chain) > 1

    def costs(self, chain: tuple[int, ...], order: int) -> np.ndarray:
        """``(m,)`` expected completion time (s) of each goal of ``chain[-1]`` at ``order``
        (memoised: the robot's own row is read by its plan and by its prediction)."""
        key = ("costs", *self.key(chain, order))
        if key not in self.memo:
            self.memo[key] = self._costs(chain, order)
        return self.memo[key]

    def _costs(self, chain: tuple[int, ...], order: int) -> np.ndarray:
        p, agent = self.p, chain[-1]
        n, m = p.speeds.shape[0], p.goals.shape[0]
        mask = self.mask(chain)
        rows = p.configurations if mask is None else p.configurations[mask]
        own = rows[:, agent]
        if own.size == 0:  # the chain keeps no configuration: no option
            return np.full(m, np.inf)
        if order == 0:
            weights = self.prior if mask is None else self.prior[mask]
            mass = np.bincount(own, weights=weights, minlength=m)
            if not mass.sum() > 0:  # a prior with no mass on the set: every row alike
                mass = np.bincount(own, minlength=m).astype(float)
            with np.errstate(divide="ignore"):
                return np.where(mass > 0, -np.log(mass / mass.sum()) * p.tau, np.inf)
        preds = np.stack(
            [np.ones(m) if j == agent else self.choice((*chain, j), order - 1) for j in range(n)]
        )
        w = np.prod(preds[np.arange(n), rows], axis=1)
        finish = (self.row_times if mask is None else self.row_times[mask]).max(axis=1)
        valid = np.bincount(own, weights=w, minlength=m)
        timed = np.bincount(own, weights=w * finish, minlength=m)
        expected = p.risk(valid, timed, self.times[agent])
        options = np.bincount(own, minlength=m) > 0
        return np.where(options, expected, np.inf)

    def choice(self, chain: tuple[int, ...], order: int) -> np.ndarray:
        """``(m,)`` the goal distribution of ``chain[-1]`` as ``chain[:-1]`` predicts it:
        for a teammate, the mixture of orders up to ``order`` (``hierarchy``), weighed
        by where it is seen."""
        key = self.key(chain, order)
        if key in self.memo:
            return self.memo[key]
        orders = range(max(order, 0) + 1) if len(chain) > 1 else (max(order, 0),)
        q = np.zeros(self.p.goals.shape[0])
        for level in orders:
            G = self.costs(chain, level)
            finite = np.isfinite(G)
            if not finite.any():  # a chain with an empty set predicts nothing at this order
                continue
            weights = np.where(finite, np.exp(-(G - G[finite].min()) / self.p.tau), 0.0)
            q += self.p.hierarchy ** (max(order, 0) - level) * weights / weights.sum()
        if len(chain) > 1:  # a teammate: weigh by where it is seen and how it moves
            q = q * np.exp(self.evidence[chain[-1]] - self.evidence[chain[-1]].max())
        total = q.sum()
        q = q / total if total > 0 else np.full(len(q), 1.0 / len(q))
        self.memo[key] = q
        return q

    def belief(self, chain: tuple[int, ...], preds: np.ndarray) -> np.ndarray:
        """``(k,)`` the probability of each configuration under ``preds``, zero off the set."""
        rows = self.p.configurations
        w = np.prod(preds[np.arange(rows.shape[1]), rows], axis=1)
        mask = np.ones(len(w), dtype=bool) if (m := self.mask(chain)) is None else m
        w = np.where(mask, w, 0.0)
        total = w.sum()
        return w / total if total > 0 else mask / mask.sum()

    def waiting(self, robot: int, preds: np.ndarray, moving) -> float:
        """Expected completion time (s) of waiting ``horizon`` steps, then choosing."""
        p = self.p
        n, m = preds.shape
        mask = self.mask((robot,))
        rows = p.configurations if mask is None else p.configurations[mask]
        times = self.row_times if mask is None else self.row_times[mask]
        delay = (p.horizon - 1) * p.dt
        others = np.array([j for j in range(n) if j != robot])
        # Particles of the teammates' true goals, and what waiting reveals of them.
        cumulative = np.cumsum(preds[others], axis=1)
        draws = _quasi_uniform(p.particles, others.size)[..., None]
        truth = np.minimum((draws > cumulative[None]).sum(axis=2), m - 1)  # (P, n - 1)
        gain = delay * p.speeds[others] * moving[others] / p.eta  # nats per teammate
        revised = np.log(np.maximum(preds[others], 1e-300))[None].repeat(p.particles, 0)
        np.put_along_axis(
            revised, truth[..., None],
            np.take_along_axis(revised, truth[..., None], 2) + gain[None, :, None], axis=2,
        )  # fmt: skip
        revised = np.exp(revised - revised.max(axis=2, keepdims=True))
        revised /= revised.sum(axis=2, keepdims=True)
        # Each particle's choice: least expected time under its revised predictions.
        w = np.prod(revised[:, np.arange(others.size), rows[:, others]], axis=2)  # (P, k')
        own_time = self.times[robot] + delay
        finish = np.maximum(times[:, others].max(axis=1)[None], own_time[rows[:, robot]][None])
        slot = rows[:, robot][None] + m * np.arange(p.particles)[:, None]
        valid = np.bincount(slot.ravel(), weights=w.ravel(), minlength=m * p.particles)
        timed = np.bincount(slot.ravel(), (w * finish).ravel(), minlength=m * p.particles)
        expected = p.risk(valid, timed, np.tile(own_time, p.particles)).reshape(p.particles, m)
        options = np.bincount(rows[:, robot], minlength=m) > 0
        chosen = np.argmin(np.where(options[None], expected, np.inf), axis=1)  # (P,)
        # Realised: does the chosen goal complete the particle's configuration?
        match = (rows[None, :, others] == truth[:, None, :]).all(axis=2)
        match &= rows[None, :, robot] == chosen[:, None]
        done = np.where(match, finish, np.inf).min(axis=1)
        formed = np.isfinite(done)
        share = formed.mean()
        if p.success_weight > 0:  # the same risk, estimated from the particles
            timed = done[formed].sum() if formed.any() else 0.0
            return float(p.risk(np.array([share]), np.array([timed / p.particles]),
                                np.array([own_time[chosen].mean()]))[0])  # fmt: skip
        return float(np.where(formed, done, own_time[chosen] + p.repair).mean())


def _quasi_uniform(count: int, dims: int) -> np.ndarray:
    """``(count, dims)`` points of the Weyl sequence ``frac((p + 1/2) sqrt(prime_d))``."""
    primes = np.array([2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53])
    steps = np.sqrt(primes[np.arange(dims) % primes.size] + dims // primes.size * 100)
    return np.mod((np.arange(count)[:, None] + 0.5) * steps[None], 1.0)


def places_in_square(count: int, robots: int, side: float) -> np.ndarray:
    """``(count, robots, 2)`` places spread evenly over the square ``[0, side]²``: the
    draws of where a robot never seen may be (a low-discrepancy sequence, so a plan stays
    a deterministic function of what the robot observes).

    Examples
    --------
    >>> places = places_in_square(8, 3, 30.0)
    >>> places.shape, bool((places >= 0).all() and (places <= 30).all())
    ((8, 3, 2), True)
    """
    return _quasi_uniform(count, 2 * robots).reshape(count, robots, 2) * float(side)


def motion_evidence(before, after, goals, speeds, dt: float, sigma: float) -> np.ndarray:
    """``(n, m)`` log-likelihood of one step's moves ``before -> after`` for each goal.

    A robot heading for goal ``g`` moves ``min(v dt, d)`` straight at it (and stands once
    there); the observed move is that with Gaussian error ``sigma`` (m) per axis. Summed
    over steps, this is how a teammate's goal is read from what it does, standing still
    on a goal included.

    Examples
    --------
    >>> goals = [[10.0, 0.0], [-10.0, 0.0]]
    >>> motion_evidence([[0.0, 0.0]], [[1.0, 0.0]], goals, [1.0], 1.0, 0.5).round(1).tolist()
    [[-0.0, -8.0]]
    """
    before = np.asarray(before, dtype=float)[:, :2]
    after = np.asarray(after, dtype=float)[:, :2]
    goals = np.asarray(goals, dtype=float)
    to_goal = goals[None] - before[:, None]  # (n, m, 2)
    distance = np.hypot(to_goal[..., 0], to_goal[..., 1])
    reach = np.minimum(np.asarray(speeds, dtype=float)[:, None] * dt, distance)
    unit = to_goal / np.where(distance > 0, distance, 1.0)[..., None]
    residual = (after - before)[:, None] - reach[..., None] * unit
    return -(residual**2).sum(axis=2) / (2 * sigma**2)
