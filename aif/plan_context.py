"""The memoised predictions of one plan of :class:`epistemica.aif.planning.Planner`.

A :class:`PlanContext` holds what one call of ``Planner.plan`` computes: every chain of
robots' predicted goal distribution at each order, the expected completion times behind
them, and the predictions of teammates never seen (from places they may be). Internal to
the planner.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from epistemica.aif.teammates import ClaimModel
from epistemica.del_.errors import InvalidArgumentError

if TYPE_CHECKING:  # the planner builds its contexts; only its type is named here
    from epistemica.aif.planning import Planner

__all__ = [
    "PlanContext",
    "arrivals",
    "claimed",
    "contests",
    "later_claimants",
    "places_in_square",
    "quasi_uniform",
]


class PlanContext:
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
        self.typed: dict[int, np.ndarray] = {}  # teammate -> its ad hoc type's goals
        self.held: np.ndarray | None = None  # the configurations the typed teammates allow
        self.blind = np.zeros(pos.shape[0], dtype=bool)  # robots never seen (see ``hide``)
        self.yields: np.ndarray | None = None  # P(a teammate yields a goal it finds taken)
        self.keeps: np.ndarray | None = None  # (n, m) its goal if it does not (None: pi_l)
        self.within = False  # ... only on goals pi_l leaves it (its set's)

    def hide(self, robot: int, never: np.ndarray) -> None:
        """Mark the teammates in ``never`` (``(n,)`` booleans) as never seen: the
        placeholder that places one is no evidence of its goal, and one of them, as a
        predictor, is not credited with what the robot saw of anyone."""
        never = np.asarray(never, dtype=bool)
        if never.shape != self.blind.shape:
            raise InvalidArgumentError(
                f"blind must have shape {self.blind.shape}, got {never.shape}",
                hint="one boolean per robot: never seen",
            )
        self.blind = never.copy()
        self.blind[robot] = False

    def give_way(self, robot: int, claim) -> None:
        """Set what a claim (``claimed``) assumes of each teammate: ``claim`` a
        :class:`~epistemica.aif.teammates.ClaimModel`, or its ``yields`` alone (``(n,)`` in
        ``[0, 1]``, the probability that each gives up a goal it finds taken; the robot's own
        entry is 1, a planner), every teammate then keeping its plan prediction if not."""
        if not isinstance(claim, ClaimModel):
            claim = ClaimModel(claim)
        if claim.keeps is not None:
            keeps = np.array(claim.keeps, dtype=float)  # a nan row: it keeps its prediction
            total = keeps.sum(axis=1, keepdims=True) if keeps.shape == self.times.shape else 0
            rows = ~np.isnan(keeps).all(axis=1) if np.ndim(total) else np.ones(1, bool)
            if np.any(~np.isfinite(keeps[rows])) or np.any(keeps[rows] < 0) or np.any(
                    total[rows] <= 0):  # fmt: skip
                raise InvalidArgumentError(
                    f"keeps must be {self.times.shape} non-negative goal weights",
                    hint="per robot, its ad hoc types' goal distribution (nan: its own)",
                )
            self.keeps, self.within = keeps / total, bool(claim.within)
        yields = np.array(claim.yields, dtype=float)
        if yields.shape != self.blind.shape or not np.all((yields >= 0) & (yields <= 1)):
            raise InvalidArgumentError(
                f"yields must be {self.blind.shape} numbers in [0, 1], got {yields!r}",
                hint="per robot, P(it is a planner), e.g. its type posterior on team",
            )
        yields[robot] = 1.0
        self.yields = yields

    def type_rows(self, robot: int, typed: np.ndarray) -> None:
        """Predict each teammate with a row in ``typed`` (``(n, m)``, ``nan`` rows for
        the planners) by that row in every chain that ends with it."""
        if typed.shape != self.times.shape:
            raise InvalidArgumentError(
                f"typed must have shape {self.times.shape}, got {typed.shape}",
                hint="one goal distribution per robot, nan rows for the planners",
            )
        rows = ~np.isnan(typed).any(axis=1)
        rows[robot] = False
        bad = typed[rows]
        if np.any(~np.isfinite(bad)) or np.any(bad < 0) or np.any(bad.sum(axis=1) <= 0):
            raise InvalidArgumentError(
                "typed rows must be non-negative goal weights (or all nan)",
                hint="teammates.typed_predictions gives them",
            )
        self.typed = {int(j): typed[j] / typed[j].sum() for j in np.flatnonzero(rows)}
        # A typed teammate holds to its most probable goal: every chain keeps only the
        # configurations with it there (it will not come to another goal).
        configurations = self.p.configurations
        held = np.ones(configurations.shape[0], dtype=bool)
        for j, row in self.typed.items():
            held &= configurations[:, j] == int(np.argmax(row))
        self.held = held if held.any() and not held.all() else None

    def predict_unseen(self, robot: int, places: np.ndarray) -> None:
        """Put the mean prediction of each never-seen teammate over ``places`` (its draws
        of where it may be) into the plan: as the robot predicts it, and as it predicts
        each teammate to predict it (chains of two and three robots)."""
        n = self.p.speeds.shape[0]
        if places.ndim != 3 or places.shape[1:] != (n, 2):
            raise InvalidArgumentError(
                f"unseen must have shape (P, {n}, 2), got {places.shape}",
                hint="places per draw and robot, nan for the robots seen",
            )
        hidden = np.flatnonzero(~np.isnan(places).any(axis=(0, 2)))
        hidden = hidden[hidden != robot]
        if hidden.size == 0 or self.p.order == 0 or places.shape[0] == 0:
            return
        chains = [((robot, int(j)), self.p.order - 1) for j in hidden]
        if self.p.order >= 2:
            chains += [((robot, k, int(j)), self.p.order - 2)
                       for k in range(n) if k != robot for j in hidden if j != k]  # fmt: skip
        keys = {self.key(chain, order): (chain, order) for chain, order in chains}
        total = dict.fromkeys(keys, 0.0)
        taken = []  # per draw, each hidden teammate's choice and trips (``arrivals``)
        for draw in places:
            moved = self.pos.copy()
            moved[hidden] = draw[hidden]
            there = PlanContext(self.p, moved, self.prior, self.sets, self.masks)
            there.evidence = there.evidence + self.extra
            there.typed, there.held, there.yields = self.typed, self.held, self.yields
            there.keeps, there.within = self.keeps, self.within
            for key, (chain, order) in keys.items():
                total[key] = total[key] + there.choice(chain, order)
            picks = [there.choice((robot, int(j)), self.p.order - 1) for j in hidden]
            taken.append((np.array(picks), there.times[hidden]))
        for key, value in total.items():
            self.memo[key] = value / places.shape[0]
        if self.p.arrivals:  # its trips from where it may be, not from the placeholder
            choices, trips = (np.array(part) for part in zip(*taken, strict=True))
            self.times[hidden] = arrivals(choices, trips)
            self.row_times = self.times[np.arange(n), self.p.configurations]

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
        if self.held is not None:  # the typed teammates' goals, where the set allows them
            both = self.held if found[0] is None else found[0] & self.held
            found = (both, both.tobytes()) if both.any() else found
        self.masks[chain] = found
        return found

    def key(self, chain: tuple[int, ...], order: int) -> tuple:
        if len(chain) < self.depth:  # deeper chains may have sets of their own
            return chain, order
        return self._mask(chain)[1], chain[-1], order, len(chain) > 1, self.unread(chain)

    def unread(self, chain: tuple[int, ...]) -> bool:
        """Whether the chain's last robot is predicted without the robot's evidence of it:
        it was never seen (its place is a placeholder), or the chain's predictor of it
        was (nothing says that one saw what the robot saw)."""
        if len(chain) < 2 or not self.blind.any():
            return False
        return bool(self.blind[chain[-1]] or (len(chain) > 2 and self.blind[chain[-2]]))

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
        return self.given(chain, preds)

    def given(self, chain: tuple[int, ...], preds: np.ndarray) -> np.ndarray:
        """``(m,)`` expected completion time (s) of each goal of ``chain[-1]`` with the
        other robots' goals distributed as the rows of ``preds`` (its own row unread)."""
        p, agent = self.p, chain[-1]
        n, m = p.speeds.shape[0], p.goals.shape[0]
        mask = self.mask(chain)
        rows = p.configurations if mask is None else p.configurations[mask]
        own = rows[:, agent]
        if own.size == 0:
            return np.full(m, np.inf)
        preds = preds.copy()
        preds[agent] = 1.0
        w = np.prod(preds[np.arange(n), rows], axis=1)
        finish = (self.row_times if mask is None else self.row_times[mask]).max(axis=1)
        valid = np.bincount(own, weights=w, minlength=m)
        timed = np.bincount(own, weights=w * finish, minlength=m)
        if p.claim:  # a later teammate finds the goal taken and goes elsewhere
            valid, timed = claimed(self, agent, rows, (preds, finish, valid, timed))
        expected = p.risk(valid, timed, self.times[agent])
        options = np.bincount(own, minlength=m) > 0
        return np.where(options, expected, np.inf)

    def choice(self, chain: tuple[int, ...], order: int) -> np.ndarray:
        """``(m,)`` the goal distribution of ``chain[-1]`` as ``chain[:-1]`` predicts it:
        for a typed teammate, its type's row; for another, the mixture of orders up to
        ``order`` (``hierarchy``), weighed by where it is seen."""
        if len(chain) > 1 and chain[-1] in self.typed:
            return self.typed[chain[-1]]
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
        if len(chain) > 1 and not self.unread(chain):  # weigh by where it is seen, its moves
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


def arrivals(choices: np.ndarray, trips: np.ndarray) -> np.ndarray:
    """``(h, m)`` each hidden teammate's trip (s) to each goal given that it takes that
    goal, over ``D`` draws of where it is: ``sum_d q_d(g) t_d(g) / sum_d q_d(g)`` with
    ``choices`` ``q`` and ``trips`` ``t`` both ``(D, h, m)``; the mean trip where no draw
    takes ``g`` (``Planner(arrivals=True)``).

    Examples
    --------
    Two draws: 2 s from goal 0 (taken with 0.9) or 10 s (taken with 0.1); goal 1 is 8 s
    away from either, never taken:

    >>> q = np.array([[[0.9, 0.0]], [[0.1, 0.0]]])
    >>> t = np.array([[[2.0, 8.0]], [[10.0, 8.0]]])
    >>> arrivals(q, t).round(2).tolist()      # (0.9 * 2 + 0.1 * 10) / 1.0
    [[2.8, 8.0]]
    """
    weight = choices.sum(axis=0)
    timed = (choices * trips).sum(axis=0)
    return np.where(weight > 0, timed / np.where(weight > 0, weight, 1.0), trips.mean(axis=0))


def claimed(context: PlanContext, agent: int, rows: np.ndarray, sums) -> tuple:
    """``valid`` and ``timed`` of ``sums = (preds, finish, valid, timed)`` (``(m,)``: the
    weights of the configurations ``rows`` under the predictions ``preds``, and the same
    times their ``finish``, summed by ``agent``'s goal; :meth:`PlanContext.given`) with the
    teammates that reach each goal ``g`` after ``agent`` (and share it with it in no
    configuration) conditioned on finding ``agent`` settled there (``Planner.claim``).

    Teammate ``l`` yields with probability ``y_l`` (``context.yields``; 1 for all when
    unset): a planner finds ``g`` taken and goes elsewhere, ``pi_l(h) / (1 - pi_l(g))``
    for ``h != g``; one that does not keeps ``pi_l``. In the configurations with
    ``agent`` at ``g``, ``l`` is not at ``g``, so the mixture multiplies their weight
    by ``y_l / (1 - pi_l(g)) + 1 - y_l``: ``P(g)`` and ``E[T | g]``'s numerator are
    divided by ``prod_l (1 - pi_l(g)) / (1 - pi_l(g) + y_l pi_l(g))``. With ``keeps``
    (``plan_claim = 4``) one that does not yield is no planner: it goes by its ad hoc
    types' row ``a_l``, so ``l``'s row is ``y_l pi_l / (1 - pi_l(g)) + (1 - y_l) a_l``
    off ``g``, and the mass ``(1 - y_l) a_l(g)`` of it contesting ``g`` is lost.
    """
    preds, finish, valid, timed = sums
    contested = contests(context.times, agent, rows)  # (m, n)
    if not contested.any():  # no goal contested (every rendezvous goal): the sums stand
        return valid, timed
    n = rows.shape[1]
    kept = np.maximum(1.0 - preds.T, 1e-3)  # (m, n): l's mass off each goal
    if context.keeps is not None:  # the rows of g's configurations, l's row the mixture
        keeps = np.where(np.isnan(context.keeps), preds, context.keeps)
        if context.within:  # an ad hoc teammate, too, goes only where its set lets it
            keeps = keeps * (preds > 0)
            total = keeps.sum(axis=1, keepdims=True)
            keeps = np.where(total > 0, keeps / np.maximum(total, 1e-300), preds)
        own, who = rows[:, agent], np.arange(n)
        y = context.yields[None]
        plain = preds[who, rows]  # (k, n): each row's factor per teammate
        mixed = y * plain / kept[own] + (1 - y) * keeps[who, rows]
        w = np.prod(np.where(contested[own], mixed, plain), axis=1)
        m = valid.shape[0]
        goals = contested.any(axis=1)
        valid = np.where(goals, np.bincount(own, weights=w, minlength=m), valid)
        timed = np.where(goals, np.bincount(own, weights=w * finish, minlength=m), timed)
        return valid, timed
    ratio = kept
    if context.yields is not None:  # only who yields is conditioned (the mixture)
        ratio = kept / (kept + context.yields[None] * preds.T)
    share = np.prod(np.where(contested, ratio, 1.0), axis=1)
    return valid / share, timed / share


def quasi_uniform(count: int, dims: int) -> np.ndarray:
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
    return quasi_uniform(count, 2 * robots).reshape(count, robots, 2) * float(side)


def contests(times: np.ndarray, robot: int, rows: np.ndarray) -> np.ndarray:
    """``(m, n)`` :func:`later_claimants` of every goal at once: ``[g, l]`` whether
    teammate ``l`` finds ``g`` taken if ``robot`` heads for it (``times`` ``(n, m)``
    seconds to each goal); all false for a goal no row of ``rows`` gives ``robot``.

    Examples
    --------
    >>> rows = np.array([[0, 1, 1], [1, 0, 0], [0, 1, 0]])
    >>> times = np.array([[2.0, 1.0], [5.0, 1.0], [1.0, 3.0]])
    >>> contests(times, 0, rows).astype(int).tolist()
    [[0, 1, 0], [0, 0, 1]]
    """
    own = rows[:, robot]
    shared = np.zeros((times.shape[1], rows.shape[1]), dtype=bool)
    at, who = np.nonzero(rows == own[:, None])
    shared[own[at], who] = True  # shared with robot in some row: no contest
    later = (times > times[robot][None]).T & ~shared
    later[:, robot] = False
    later &= np.bincount(own, minlength=times.shape[1])[:, None] > 0
    return later


def later_claimants(arrival: np.ndarray, robot: int, goal: int, rows: np.ndarray) -> np.ndarray:
    """``(n,)`` the teammates that find ``goal`` taken if ``robot`` heads for it: those
    that reach it later (``arrival``, ``(n,)`` seconds to it) and share it with ``robot`` in
    no configuration of ``rows`` (``(k, n)``) that puts ``robot`` there (``plan_claim``).

    Examples
    --------
    >>> rows = np.array([[0, 1, 1], [1, 0, 0], [0, 1, 0]])  # robots 1 and 2 share goal 0
    >>> later_claimants(np.array([2.0, 5.0, 1.0]), 0, 0, rows).tolist()
    [False, True, False]
    """
    mine = rows[rows[:, robot] == goal]
    later = arrival > arrival[robot]
    later &= ~(mine == goal).any(axis=0)  # shared in some configuration: no contest
    later[robot] = False
    return later
