"""Teammate models inferred online: a posterior over a small library of behaviours.

An ad hoc teammate need not reason as the team does. In the spirit of type-based ad hoc
teamwork (HBA, Albrecht & Ramamoorthy 2013; PLASTIC, Barrett et al. 2017), a robot keeps,
for each teammate ``j``, a posterior over a library of :data:`TYPES`:

- ``"team"``: the robot's own level; its goal is distributed as the team prior's marginal
  ``pi_j(g)``;
- ``"greedy"``: the goal nearest to where it is (level ``zero``);
- ``"convention"``: the configuration of least total distance over the valid set, ties
  broken the other way (level ``convention-reverse``);
- ``"stationary"``: it does not move; it stays on the goal it stands on (level
  ``stationary``, once arrived); away from every goal it says nothing of its goal.

Each type predicts a goal distribution ``P_t(g)``; a moving type predicts the next position
as one step of at most ``reach`` metres straight for the goal, the stationary type the
same position. The observed step is scored by an isotropic Gaussian of variance ``sigma²``
around each prediction (mixed over goals), and the type posterior is updated by Bayes,
then mixed with the type prior at rate ``leak`` so that it can follow a teammate that
changes its mind.

The belief over configurations uses the type mixture: with ``π`` the team prior, a
teammate ``j`` of type ``t`` takes its goal from ``P_t`` and the team coordinates around it,
``P(c) = Σ_t P(t) P_t(c_j) π(c_-j | c_j)`` (:func:`mix_configurations`). A ``"team"``
teammate commits to no goal of its own (``π`` already models it); with several teammates
the mixture is taken to first order: at most one of them holds to a goal of its own.

Examples
--------
A teammate at the origin steps one metre towards goal 0 at (10, 0), its nearest; the team
prior expected it at goal 1 at (0, -20):

>>> goals = np.array([[10.0, 0.0], [0.0, -20.0]])
>>> marginal = np.array([[0.01, 0.99]])
>>> probs = type_goal_probabilities(marginal, np.zeros((1, 2)), goals, np.array([1]))
>>> ll = motion_log_likelihood(np.zeros((1, 2)), np.array([[1.0, 0.0]]), probs, goals,
...                            np.ones(1), 0.5)
>>> post = update_types(np.log(TYPE_PRIOR)[None], ll, leak=0.0)
>>> TYPES[int(np.argmax(post[0]))]
'greedy'
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = [
    "TYPES",
    "TYPE_PRIOR",
    "ClaimModel",
    "adhoc_rows",
    "claim_yields",
    "goal_distances",
    "goal_marginals",
    "goal_probabilities_from_distances",
    "least_cost_from_distances",
    "least_cost_rows",
    "mix_configurations",
    "motion_log_likelihood",
    "planner_type_goals",
    "type_goal_probabilities",
    "typed_predictions",
    "update_types",
]

#: The behaviour library, in the order of every ``T`` axis.
TYPES = ("team", "greedy", "convention", "stationary")
#: Prior over :data:`TYPES`: a teammate is most likely one of the team.
TYPE_PRIOR = np.array([0.5, 1 / 6, 1 / 6, 1 / 6])
#: Probability a one-hot goal prediction leaves on every other goal (keeps logs finite).
GOAL_FLOOR = 1e-4
#: Metres from a goal within which a teammate stands on it.
ON_GOAL = 0.5


def goal_distances(positions: np.ndarray, goals: np.ndarray) -> np.ndarray:
    """``(..., m)`` distances from ``positions (..., 2)`` to ``goals (m, 2)``: what
    :func:`least_cost_from_distances` and :func:`goal_probabilities_from_distances` share.

    Examples
    --------
    >>> goal_distances(np.array([[0.0, 0.0]]), np.array([[3.0, 4.0], [0.0, 1.0]])).tolist()
    [[5.0, 1.0]]
    """
    delta = positions[..., None, :] - goals
    return np.sqrt((delta**2).sum(-1))


def least_cost_rows(positions: np.ndarray, goals: np.ndarray, configurations: np.ndarray
                    ) -> np.ndarray:  # fmt: skip
    """``(R, n)``: for each view ``positions[r] (n, 2)``, the valid configuration of least
    total distance, the last of equal ones (the other tie-break).

    Examples
    --------
    >>> least_cost_rows(np.array([[[0.0, 0.0], [4.0, 0.0]]]), np.array([[1.0, 0.0], [3.0, 0.0]]),
    ...                 np.array([[0, 0], [1, 1], [0, 1], [1, 0]])).tolist()
    [[0, 1]]
    """
    return least_cost_from_distances(goal_distances(positions, goals), configurations)


def least_cost_from_distances(cost: np.ndarray, configurations: np.ndarray) -> np.ndarray:
    """:func:`least_cost_rows` from the ``(R, n, m)`` robot-to-goal distances."""
    n = configurations.shape[1]
    total = cost[:, np.arange(n), configurations].sum(axis=2)  # (R, k)
    # the last of the configurations within 1e-9 of the least total
    tied = total <= total.min(axis=1, keepdims=True) + 1e-9
    k = total.shape[1]
    return configurations[k - 1 - np.argmax(tied[:, ::-1], axis=1)]


def goal_marginals(prior: np.ndarray, configurations: np.ndarray, m: int) -> np.ndarray:
    """``(R, n, m)``: each robot's goal marginal under each prior ``prior[r] (k,)``.

    Examples
    --------
    >>> goal_marginals(np.array([[0.25, 0.75]]), np.array([[0, 1], [1, 1]]), 2).tolist()
    [[[0.25, 0.75], [0.0, 1.0]]]
    """
    r, (k, n) = prior.shape[0], configurations.shape
    cell = (np.arange(r)[:, None, None] * n + np.arange(n)) * m + configurations  # (r, k, n)
    weights = np.broadcast_to(prior[:, :, None], (r, k, n))
    return np.bincount(cell.ravel(), weights.ravel(), r * n * m).reshape(r, n, m)


def type_goal_probabilities(
    marginal: np.ndarray, positions: np.ndarray, goals: np.ndarray, convention: np.ndarray
) -> np.ndarray:
    """``(n, T, m)``: each teammate's goal distribution under each type.

    Parameters
    ----------
    marginal : numpy.ndarray
        ``(n, m)`` the team prior's marginal over each robot's goal (the ``"team"`` type).
    positions : numpy.ndarray
        ``(n, 2)`` where the robots are seen.
    goals : numpy.ndarray
        ``(m, 2)`` goal positions.
    convention : numpy.ndarray
        ``(n,)`` each robot's goal in the other tie-break's convention.
    """
    return goal_probabilities_from_distances(marginal, goal_distances(positions, goals), convention)


def goal_probabilities_from_distances(
    marginal: np.ndarray, distance: np.ndarray, convention: np.ndarray
) -> np.ndarray:
    """:func:`type_goal_probabilities` from the ``(n, m)`` robot-to-goal distances."""
    n, m = marginal.shape
    team, greedy = TYPES.index("team"), TYPES.index("greedy")
    other, stationary = TYPES.index("convention"), TYPES.index("stationary")
    rows = np.arange(n)
    nearest = np.argmin(distance, axis=1)
    on_goal = distance[rows, nearest] <= ON_GOAL
    sure = 1.0 - (m - 1) * GOAL_FLOOR  # a one-hot row, floored
    out = np.full((n, len(TYPES), m), GOAL_FLOOR)
    out[:, team] = marginal
    out[rows, greedy, nearest] = sure
    out[rows, other, convention] = sure
    out[~on_goal, stationary] = 1.0 / m  # away from every goal: says nothing of its goal
    out[rows[on_goal], stationary, nearest[on_goal]] = sure
    return out


def motion_log_likelihood(
    previous: np.ndarray,
    current: np.ndarray,
    goal_probabilities: np.ndarray,
    goals: np.ndarray,
    reach: np.ndarray,
    sigma: float,
    drive: bool = False,
) -> np.ndarray:
    """``(n, T)`` log likelihood of each teammate's observed step under each type.

    ``goal_probabilities`` are the ``(n, T, m)`` predictions made at ``previous``;
    ``reach`` the ``(n,)`` metres a robot covers in a step at most. The stationary type
    stands still; with ``drive`` it is the simulator's level ``stationary``, which drives
    to a goal drawn at random and stands there: with probability 1/2 it has arrived (the
    step is still), else it steps towards a goal drawn uniformly (``plan_claim = 5``).

    Examples
    --------
    A teammate at the origin steps 1 m towards goal 0 (reach 1, sigma 0.5): standing
    still misses by 1 m (``-1 / (2 · 0.25) = -2`` nats), heading for goal 0 by nothing,
    for goal 1 by ``√2`` m (-4). Driving, the stationary type scores
    ``ln(e^-2 / 2 + (1 + e^-4) / 4) = -1.13`` nats over the Gaussian's constant:

    >>> goals = np.array([[10.0, 0.0], [0.0, -20.0]])
    >>> probs = np.full((1, len(TYPES), 2), 0.5)
    >>> args = np.zeros((1, 2)), np.array([[1.0, 0.0]]), probs, goals, np.ones(1), 0.5
    >>> norm = -np.log(2 * np.pi * 0.25)
    >>> (motion_log_likelihood(*args)[0, -1] - norm).round(2).item()
    -2.0
    >>> (motion_log_likelihood(*args, drive=True)[0, -1] - norm).round(2).item()
    -1.13
    """
    delta = goals[None] - previous[:, None]  # (n, m, 2)
    distance = np.hypot(delta[..., 0], delta[..., 1])
    scale = np.minimum(reach[:, None], distance) / np.maximum(distance, 1e-12)
    predicted = previous[:, None] + scale[..., None] * delta  # (n, m, 2)
    norm = -np.log(2 * np.pi * sigma**2)
    miss = current[:, None] - predicted
    toward = norm - (miss**2).sum(-1) / (2 * sigma**2)  # (n, m)
    with np.errstate(divide="ignore"):
        terms = np.log(goal_probabilities) + toward[:, None, :]
    top = terms.max(axis=-1, keepdims=True)
    moving = np.log(np.exp(terms - top).sum(-1)) + top[..., 0]
    still = norm - ((current - previous) ** 2).sum(-1) / (2 * sigma**2)
    if drive:  # arrived (still), or on its way to a goal drawn uniformly
        top = toward.max(axis=-1)
        uniform = np.log(np.exp(toward - top[:, None]).mean(axis=-1)) + top
        still = np.logaddexp(still, uniform) - np.log(2.0)
    moving[:, TYPES.index("stationary")] = still
    return moving


def update_types(log_types: np.ndarray, log_likelihood: np.ndarray, leak: float) -> np.ndarray:
    """``(n, T)`` log posterior: Bayes, then mixed with :data:`TYPE_PRIOR` at rate ``leak``.

    Examples
    --------
    >>> post = update_types(np.log(TYPE_PRIOR)[None], np.array([[0.0, 0.0, 0.0, -50.0]]), 0.0)
    >>> np.exp(post).round(3).tolist()
    [[0.6, 0.2, 0.2, 0.0]]
    """
    joint = log_types + log_likelihood
    top = joint.max(axis=-1, keepdims=True)
    post = np.exp(joint - np.where(np.isfinite(top), top, 0.0))
    total = post.sum(axis=-1, keepdims=True)  # 0 only where every type was ruled out
    post *= (1 - leak) / np.where(total > 0, total, 1.0)
    if leak > 0:  # no type is ever ruled out
        return np.log(post + leak * TYPE_PRIOR)
    with np.errstate(divide="ignore"):
        return np.log(post)


def mix_configurations(
    prior: np.ndarray,
    log_types: np.ndarray,
    goal_probabilities: np.ndarray,
    configurations: np.ndarray,
    teammates: np.ndarray,
    marginal: np.ndarray | None = None,
) -> np.ndarray:
    """``(R, k)`` each team prior ``prior[r] (k,)`` made the teammate-type mixture.

    ``log_types (R, n, T)`` and ``goal_probabilities (R, n, T, m)`` are what observer
    ``r`` believes of each robot, ``teammates (R, n)`` whom it mixes in (the others keep
    the team's model); ``marginal`` is :func:`goal_marginals` of ``prior`` if the caller
    has it.

    For one teammate ``j``: ``P'(c) = Σ_t P(t) P_t(c_j) π(c) / π_j(c_j)``, the configuration
    drawn with ``j``'s goal from its type and the rest of the team coordinating around it
    (``π_j`` the marginal of ``j``'s goal under the prior ``π``). The ``"team"`` type, and a
    ``"stationary"`` one away from every goal, commit to no goal of their own: their term
    is ``P(t) π(c)``. With several teammates, writing ``u_j`` for the weight of ``j``'s
    uncommitted types and ``a_j(g)`` for the committed ones' ``Σ_t P(t) P_t(g)``, the
    mixture is expanded to first order in commitment:
    ``P'(c) ∝ π(c) [Π_j u_j + Σ_j a_j(c_j) / π_j(c_j) Π_{i≠j} u_i]`` — everyone coordinating,
    or exactly one teammate holding to a goal of its own (two teammates committed to
    clashing goals leave no configuration the team can form). Exact with one teammate.

    Examples
    --------
    A rendezvous of two robots at one of two goals; the prior favours goal 0, but teammate
    1 is believed greedy for goal 1 with probability 0.75:

    >>> rows = np.array([[0, 0], [1, 1]])
    >>> probs = np.array([[[0.9, 0.1], [0.0, 1.0], [0.9, 0.1], [0.5, 0.5]]] * 2)
    >>> lt = np.log(np.array([[0.97, 0.01, 0.01, 0.01], [0.25, 0.73, 0.01, 0.01]]))
    >>> q = mix_configurations(np.array([[0.9, 0.1]]), lt[None], probs[None], rows,
    ...                        np.array([[False, True]]))
    >>> q.round(3).tolist()   # 0.9 · (0.26 + 0.01), 0.1 · (0.26 + 7.31)
    [[0.243, 0.757]]
    """
    pi = np.asarray(prior, dtype=float)
    m = goal_probabilities.shape[-1]
    weights = np.exp(log_types)  # (R, n, T)
    team, stationary = TYPES.index("team"), TYPES.index("stationary")
    # a stationary teammate away from every goal predicts the uniform row: no goal of its own
    adrift = (goal_probabilities[..., stationary, :] == 1.0 / m).all(axis=-1)  # (R, n)
    uncommitted = np.where(teammates, weights[..., team] + adrift * weights[..., stationary], 1.0)
    weights[..., team] = 0.0
    weights[..., stationary] *= ~adrift
    committed = np.einsum("rnt,rntm->rnm", weights, goal_probabilities)
    if marginal is None:
        marginal = goal_marginals(pi, configurations, m)
    ratio = np.zeros_like(committed)
    np.divide(committed, marginal, out=ratio, where=teammates[..., None] & (marginal > 0))
    n = configurations.shape[1]
    terms = ratio[:, np.arange(n), configurations]  # (R, k, n): a_j(c_j) / π_j(c_j)
    # Π_{i≠j} u_i from prefix and suffix products (a u_j of 0 stays exact)
    r = uncommitted.shape[0]
    before = np.cumprod(np.hstack([np.ones((r, 1)), uncommitted]), axis=1)  # (R, n + 1)
    after = np.cumprod(np.hstack([np.ones((r, 1)), uncommitted[:, ::-1]]), axis=1)[:, ::-1]
    others = before[:, :-1] * after[:, 1:]
    p = pi * (before[:, -1:] + (terms * others[:, None, :]).sum(axis=2))
    return p / p.sum(axis=1, keepdims=True)


def planner_type_goals(planned: np.ndarray, distance: np.ndarray, convention: np.ndarray
                       ) -> np.ndarray:  # fmt: skip
    """``(n, T, m)``: each teammate's goal distribution under each type, as the planner
    reads its teammates (:class:`epistemica.aif.planning.Planner`, ``typed``).

    As :func:`goal_probabilities_from_distances`, with two differences: the ``"team"`` row
    is ``planned``, the planner's own prediction of the teammate as a planner, and a
    ``"stationary"`` teammate holds to its nearest goal wherever it is seen (noisy
    sightings of a robot standing on a goal fall outside :data:`ON_GOAL`).

    Examples
    --------
    >>> planned = np.array([[0.0, 1.0, 0.0]])
    >>> out = planner_type_goals(planned, np.array([[0.8, 5.0, 9.0]]), np.array([2]))
    >>> out.argmax(axis=2).tolist()    # team, greedy, convention, stationary
    [[1, 0, 2, 0]]
    """
    out = goal_probabilities_from_distances(planned, distance, convention)
    out[:, TYPES.index("stationary")] = out[:, TYPES.index("greedy")]
    return out


def typed_predictions(log_types: np.ndarray, goal_probabilities: np.ndarray,
                      threshold: float, types: tuple[str, ...] = ("greedy", "stationary")
                      ) -> np.ndarray:  # fmt: skip
    """``(n, m)``: the goal distribution of each teammate whose moves fit ad hoc
    ``types``, ``nan`` rows for the others (predicted as planners).

    A teammate is typed when its posterior puts at least ``threshold`` on ``types``
    (by default those that hold to the nearest goal: a planner may head for another
    goal than predicted, but does not stay where it is predicted to leave); it is then
    predicted by their mixture, ``Σ_t P(t) P_t(g) / Σ_t P(t)`` over ``types``, with no
    weight left on the team's own behaviour. A ``threshold`` of 0 types no one.

    Examples
    --------
    Teammate 0 was seen standing still (stationary 0.95), teammate 1 moving as predicted:

    >>> probs = np.array([[[0.0, 1.0], [1.0, 0.0], [1.0, 0.0], [1.0, 0.0]]] * 2)
    >>> lt = np.log(np.array([[0.03, 0.01, 0.01, 0.95], [0.9, 0.05, 0.03, 0.02]]))
    >>> typed_predictions(lt, probs, 0.9).round(3).tolist()
    [[1.0, 0.0], [nan, nan]]
    """
    weights = np.exp(log_types)
    weights = weights / weights.sum(axis=-1, keepdims=True)
    adhoc = np.zeros_like(weights)
    counted = [TYPES.index(t) for t in types]
    adhoc[:, counted] = weights[:, counted]
    mass = adhoc.sum(axis=1)
    out = np.full(goal_probabilities.shape[::2], np.nan)
    typed = (mass >= threshold) & (threshold > 0) & (mass > 0)
    mixed = np.einsum("nt,ntm->nm", adhoc[typed], goal_probabilities[typed])
    out[typed] = mixed / mass[typed, None]
    return out


def adhoc_rows(posterior: np.ndarray, goal_probabilities: np.ndarray) -> np.ndarray:
    """``(n, m)``: each teammate's goal distribution if it is not of the team type, the
    mixture of the other types' rows of ``goal_probabilities`` (``(n, T, m)``) weighed by
    ``posterior`` (``(n, T)``, any positive scale): what a claim expects of a teammate
    that does not yield (``plan_claim = 4``).

    Examples
    --------
    Greedy and stationary both hold to goal 0, the other convention to goal 1:

    >>> probs = np.array([[[0.5, 0.5], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0]]])
    >>> adhoc_rows(np.array([[0.4, 0.3, 0.2, 0.1]]), probs).round(3).tolist()
    [[0.667, 0.333]]
    """
    weights = np.delete(posterior, TYPES.index("team"), axis=1)
    rows = np.delete(goal_probabilities, TYPES.index("team"), axis=1)
    return np.einsum("nt,ntm->nm", weights, rows) / weights.sum(axis=1, keepdims=True)


class ClaimModel(NamedTuple):
    """What a claim (``plan_claim``) assumes of each robot that finds a goal taken.

    ``yields`` ``(n,)`` in ``[0, 1]``: the probability that it is a planner and gives the
    goal up (its posterior on the team type; 2, 3). ``keeps`` ``(n, m)`` or ``None``: its
    goal weights if it does not (its ad hoc types' rows, 4, 5; a ``nan`` row, or ``None``
    for all: it keeps the plan's prediction of it). ``within``: those rows are held to
    the goals its set leaves it (6).
    """

    yields: np.ndarray
    keeps: np.ndarray | None = None
    within: bool = False


def claim_yields(log_types, goal_probabilities=None, never=None) -> ClaimModel:
    """What a claim assumes of each robot (:class:`ClaimModel`): its posterior on the
    team type (``log_types``, ``(n, T)``), a planner that yields a goal it finds taken
    (``plan_claim`` 2, 3); given the planner's ``(n, T, m)`` type rows, its goal if it
    does not yield (:func:`adhoc_rows`; 4, 5); given ``never`` (``(n,)`` booleans, 6), that
    row ``nan`` for a robot never seen (no move read, its rows from a placeholder: it keeps
    the plan's prediction), and the rows held to the goals its set leaves it.

    Examples
    --------
    >>> lt = np.log([[0.5, 0.25, 0.2, 0.05], [0.5, 0.4, 0.05, 0.05]])
    >>> probs = np.array([[[0.5, 0.5], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0]]] * 2)
    >>> claim = claim_yields(lt, probs, np.array([False, True]))
    >>> claim.yields.tolist(), claim.keeps.round(2).tolist(), claim.within
    ([0.5, 0.5], [[0.6, 0.4], [nan, nan]], True)
    >>> claim_yields(lt).keeps is None
    True
    """
    posterior = np.exp(log_types - log_types.max(axis=1, keepdims=True))
    team = posterior[:, TYPES.index("team")] / posterior.sum(axis=1)
    if goal_probabilities is None:
        return ClaimModel(team)
    rows = adhoc_rows(posterior, goal_probabilities)
    if never is None:
        return ClaimModel(team, rows)
    rows[never] = np.nan
    return ClaimModel(team, rows, True)
