"""The team prior over configurations: teammates are efficient, and break ties one way.

Before any evidence about intent, a robot expects its team to take a configuration that
costs little: ``p(c) ∝ exp(-cost(c) / scale)`` with ``cost(c) = Σ_r ||x_r - g_{c_r}||`` the
total distance of the configuration from where the robots are seen. Motion evidence then
refines it (the likelihood of :mod:`~epistemica.aif.likelihood`); without that prior, the
belief starts uniform and every robot must first infer from the others' dithering what a
plain convention reads off the geometry at once.

Configurations of (nearly) equal cost are where a team deadlocks: each robot's noisy view
tips it another way. A small, shared preference breaks the symmetry legibly: the
configurations are ranked in an order every robot can compute from common knowledge
(lexicographic in the coordinates of the goals assigned to robots 0, 1, ...; or a
permutation drawn from a team-shared seed), and ``p(c)`` is multiplied by
``exp(-tie_weight · rank(c) / (k - 1))``. Each robot's bias is the same, so they tip the
same way, and each robot's motion towards the preferred configuration makes it cheaper for
everyone.

Examples
--------
Two robots, two goals, a perfectly symmetric rendezvous: the shared order prefers goal 0
(x = 10) over goal 1 (x = 20), both robots compute the same prior.

>>> goals = np.array([[10.0, 15.0], [20.0, 15.0]])
>>> rows = np.array([[0, 0], [1, 1]])
>>> a = team_log_prior(np.array([[5.0, 15.0], [25.0, 15.0]]), goals, rows)
>>> np.exp(a).round(3).tolist()
[0.731, 0.269]
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.optimize import linear_sum_assignment

from epistemica.aif._validate import as_finite, nonnegative, positive
from epistemica.aif.configurations import check_capacities, index_dtype
from epistemica.aif.likelihood import check_configurations
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["lexicographic_order", "plausible_configurations", "shared_rank", "team_log_prior"]


def shared_rank(goals, configurations, seed: int | None = None) -> np.ndarray:
    """Each configuration's rank in ``[0, 1]`` in an order every teammate computes alike.

    Parameters
    ----------
    goals : array_like
        ``(m, 2)`` goal positions (common knowledge).
    configurations : array_like
        ``(k, n)`` goal indices.
    seed : int, optional
        A team-shared seed: rank by a permutation drawn from it instead of by coordinates.

    Examples
    --------
    >>> shared_rank([[5.0, 0.0], [1.0, 0.0]], [[0], [1]]).tolist()  # goal 1 has smaller x
    [1.0, 0.0]
    """
    g = as_finite(goals, "goals", ndim=2, shape=(None, 2))
    rows = check_configurations(configurations, None, g.shape[0]).astype(np.intp)
    k = rows.shape[0]
    if seed is not None:
        order = np.random.default_rng(seed).permutation(k)
    else:
        # By (x, y) of robot 0's goal, then robot 1's, ...: the same order as sorting by
        # each goal's place among the goals' (x, y) (equal places share one), and one
        # integer per row sorts faster than 2n float keys.
        order = lexicographic_order(_place_of_goal(g)[rows])
    rank = np.empty(k)
    rank[order] = np.arange(k) / max(k - 1, 1)
    return rank


def team_log_prior(
    positions,
    goals,
    configurations,
    scale: float = 1.0,
    tie_weight: float = 1.0,
    rank: np.ndarray | None = None,
) -> np.ndarray:
    """Normalised log prior ``log p(c)`` of every configuration.

    Parameters
    ----------
    positions : array_like
        ``(n, 2)`` (or ``(n, 3)``) robot positions as the deciding robot observes them, or
        ``(R, n, 2)``: the views of ``R`` robots, one prior each (``(R, k)``).
    goals : array_like
        ``(m, 2)`` goal positions.
    configurations : array_like
        ``(k, n)`` valid configurations.
    scale : float
        Metres of total distance per nat (smaller: closer to the least-cost convention).
    tie_weight : float
        Nats between the first and last configuration of the shared order.
    rank : numpy.ndarray, optional
        Precomputed :func:`shared_rank` (it depends only on goals and configurations).

    Examples
    --------
    >>> goals = np.array([[0.0, 0.0], [10.0, 0.0]])
    >>> lp = team_log_prior([[1.0, 0.0], [9.0, 0.0]], goals, [[0, 1], [1, 0]], tie_weight=0)
    >>> float(np.exp(lp[0] - lp[1])) == float(np.exp(16.0))  # 16 m cheaper, 1 m per nat
    True
    """
    x = as_finite(positions, "positions")
    single = x.ndim == 2
    if single:
        x = x[None]
    if x.ndim != 3 or x.shape[2] < 2:
        raise InvalidArgumentError(
            f"positions must be (n, 2) or (R, n, 2), got shape {x.shape}",
            hint="one row of x, y per robot",
        )
    x = x[..., :2]
    g = as_finite(goals, "goals", ndim=2, shape=(None, 2))
    rows = check_configurations(configurations, x.shape[1], g.shape[0]).astype(np.intp)
    scale = positive(scale, "scale")
    tie_weight = nonnegative(tie_weight, "tie_weight")
    distance = np.hypot(x[..., :, None, 0] - g[:, 0], x[..., :, None, 1] - g[:, 1])  # (R, n, m)
    # Gathered in C order whatever R (the gather's layout changes the sum's rounding).
    cost = np.ascontiguousarray(distance[:, np.arange(x.shape[1]), rows]).sum(axis=-1)
    if rank is None:
        rank = shared_rank(g, rows) if tie_weight > 0 else np.zeros(rows.shape[0])
    logits = -(cost - cost.min(axis=1, keepdims=True)) / scale - tie_weight * rank
    logits -= logits.max(axis=1, keepdims=True)
    # Row by row: a 1-D sum runs pairwise, a 2-D one need not; a view's prior is then the
    # same whether it is computed alone or with the team's.
    norm = np.array([np.exp(row).sum() for row in logits])
    out = logits - np.log(norm)[:, None]
    return out[0] if single else out


def plausible_configurations(
    cost,
    mission: str,
    capacities=None,
    within: float = 30.0,
    limit: int = 20_000,
) -> np.ndarray:
    """The valid configurations whose total cost is within ``within`` of the least.

    Under :func:`team_log_prior` with ``scale`` metres per nat, a configuration ``D``
    metres costlier than the best has prior odds ``exp(-D / scale)`` against it, while
    motion evidence moves the odds by at most about one nat per robot. Configurations
    beyond ``within = scale · (margin + n)`` cannot win, so the belief need not range
    over them. They are never built: rows grow robot by robot (as in
    :func:`~epistemica.aif.valid_configurations`), and a prefix is dropped as soon as its
    cost plus the cheapest completion exceeds the bound. If more than ``limit`` rows
    survive a level, the ``limit`` most promising prefixes are kept (a beam; the least-cost
    configuration always survives).

    Parameters
    ----------
    cost : array_like
        ``(n, m)`` cost of robot ``r`` taking goal ``g`` (distances as observed).
    mission : {"rendezvous", "allocation", "capacity"}
    capacities : sequence of int, optional
        For ``"capacity"``.
    within : float
        Cost margin over the least-cost configuration.
    limit : int
        Most rows kept per level.

    Returns
    -------
    numpy.ndarray
        ``(k, n)`` configurations in lexicographic order (for a fixed cost, the same set
        and order as filtering :func:`~epistemica.aif.valid_configurations`).

    Examples
    --------
    >>> cost = np.array([[1.0, 9.0, 9.0], [9.0, 1.0, 9.0], [9.0, 9.0, 1.0]])
    >>> plausible_configurations(cost, "allocation", within=5.0).tolist()
    [[0, 1, 2]]
    >>> len(plausible_configurations(cost, "allocation", within=100.0))
    6
    """
    c = as_finite(cost, "cost", ndim=2)
    n, m = c.shape
    within = nonnegative(within, "within")
    if mission not in _SLOTS:
        raise InvalidArgumentError(
            f"no cost bound for mission {mission!r}",
            hint=f"use {', '.join(_SLOTS)}",
        )
    slots_of = _SLOTS[mission]
    if slots_of is None:  # everyone at one goal: the goals within the margin
        total = c.sum(axis=0)
        goals = np.flatnonzero(total <= total.min() + within)
        return np.repeat(goals[:, None], n, axis=1).astype(index_dtype(m))
    caps = slots_of(n, m, capacities)
    slots, state = np.repeat(c, caps, axis=1), caps[None, :].astype(np.int64)
    rows_r, cols_r = linear_sum_assignment(slots)
    bound = slots[rows_r, cols_r].sum() + within
    slot_goal = np.repeat(np.arange(m), caps)
    best = np.empty(n, dtype=np.intp)
    best[rows_r] = slot_goal[cols_r]
    return _within_bound(c, state, bound, best, limit)


def _within_bound(
    c: np.ndarray, state: np.ndarray, bound: float, best: np.ndarray, limit: int
) -> np.ndarray:
    """Every configuration of cost ``c`` (``(n, m)``) within ``bound``, goal slots left in
    ``state`` (``(1, m)``), expanding robot by robot with a beam of ``limit`` prefixes that
    always keeps ``best``'s (the least-cost configuration); in lexicographic order."""
    n, m = c.shape
    # Expand the most decided robots first (largest gap between their two cheapest goals):
    # their costly alternatives are cut at the first levels, where prefixes are few.
    ranked = np.sort(c, axis=1)
    order = np.argsort(-(ranked[:, 1] - ranked[:, 0]) if m > 1 else np.zeros(n), kind="stable")
    c_ordered = c[order]
    best_ordered = best[order]
    cheapest_rest = np.concatenate([np.cumsum(c_ordered.min(axis=1)[::-1])[::-1], [0.0]])
    # Rows are kept as one (parent, goal) pair per level and assembled at the end:
    # copying every prefix at every level cost more than scoring them.
    levels: list[tuple[np.ndarray, np.ndarray]] = []
    spent = np.zeros(1)
    on_best = np.ones(1, dtype=bool)  # which prefixes are the least-cost configuration's
    for r in range(n):
        # Every (prefix, goal) pair is scored before any row is built: at ten robots most
        # of them are cut, and building them first cost most of the time.
        step = spent[:, None] + c_ordered[r]
        promise = step + cheapest_rest[r + 1]
        keep = (state > 0) & (promise <= bound + 1e-9)
        if np.count_nonzero(keep) > limit:
            cut = np.partition(promise[keep], limit - 1)[limit - 1]
            # The beam keeps the least-cost configuration's prefix: the lower bound can
            # rank it below prefixes that later find no distinct goals, leaving none.
            best_pair = on_best[:, None] & (np.arange(m) == best_ordered[r])
            keep &= (promise <= cut) | best_pair
        parent, goal = np.nonzero(keep)  # row-major: lexicographic order is kept
        levels.append((parent, goal))
        spent = step[parent, goal]
        state = state[parent]
        state[np.arange(goal.size), goal] -= 1
        on_best = on_best[parent] & (goal == best_ordered[r])
    out = np.empty((spent.size, n), dtype=index_dtype(m))
    at = np.arange(spent.size)
    for r in range(n - 1, -1, -1):
        parent, goal = levels[r]
        out[:, order[r]] = goal[at]
        at = parent[at]
    return out[lexicographic_order(out)]


def lexicographic_order(rows: np.ndarray) -> np.ndarray:
    """The stable order sorting the rows of non-negative integers ``rows`` (``(k, n)``)
    lexicographically: ``np.lexsort(rows.T[::-1])``, computed as one ``argsort`` of each
    row read as a number in base ``rows.max() + 1`` when that fits in 63 bits.

    Examples
    --------
    >>> lexicographic_order(np.array([[1, 0], [0, 2], [0, 1], [1, 0]])).tolist()
    [2, 1, 0, 3]
    """
    k, n = rows.shape
    base = int(rows.max()) + 1 if rows.size else 1
    if n == 0 or base**n >= 2**63:
        return np.lexsort(rows.T[::-1])
    key = np.zeros(k, dtype=np.int64)
    for column in rows.T:
        key = key * base + column
    return np.argsort(key, kind="stable")


def _place_of_goal(g: np.ndarray) -> np.ndarray:
    """Each goal's place in the lexicographic order of the goals' (x, y); goals at equal
    coordinates share one place (as they compare equal)."""
    order = np.lexsort((g[:, 1], g[:, 0]))
    ordered = g[order]
    new = np.ones(len(g), dtype=bool)
    new[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    place = np.empty(len(g), dtype=np.int64)
    place[order] = np.cumsum(new) - 1
    return place


def _one_slot_each(n: int, m: int, capacities) -> np.ndarray:
    if n > m:
        raise InvalidArgumentError(
            f"allocation needs pairwise distinct goals, but {n} robots > {m} goals",
            hint="use n_robots <= n_goals",
        )
    return np.ones(m, dtype=np.int64)


#: Configuration family -> the robots each goal takes (``None``: all at one goal).
_SLOTS: dict[str, Callable[[int, int, object], np.ndarray] | None] = {
    "rendezvous": None,
    "allocation": _one_slot_each,
    "capacity": lambda n, m, capacities: check_capacities(capacities, n, m),
}
