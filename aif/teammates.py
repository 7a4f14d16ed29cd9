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

import numpy as np
from scipy.special import logsumexp

from epistemica.aif._logspace import log_normalise

__all__ = [
    "TYPES",
    "TYPE_PRIOR",
    "least_cost_row",
    "mix_configurations",
    "motion_log_likelihood",
    "type_goal_probabilities",
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


def _one_hot(index: np.ndarray, m: int) -> np.ndarray:
    """``(n, m)`` rows ``1 - (m - 1) · GOAL_FLOOR`` at ``index``, ``GOAL_FLOOR`` elsewhere."""
    out = np.full((index.shape[0], m), GOAL_FLOOR)
    out[np.arange(index.shape[0]), index] = 1.0 - (m - 1) * GOAL_FLOOR
    return out


def least_cost_row(positions: np.ndarray, goals: np.ndarray, configurations: np.ndarray,
                   last: bool = True) -> np.ndarray:  # fmt: skip
    """The valid configuration of least total distance (``last``: the last of equal ones).

    Examples
    --------
    >>> least_cost_row(np.array([[0.0, 0.0], [4.0, 0.0]]), np.array([[1.0, 0.0], [3.0, 0.0]]),
    ...                np.array([[0, 0], [1, 1], [0, 1], [1, 0]])).tolist()
    [0, 1]
    """
    cost = np.hypot(*(positions[:, None, :] - goals[None]).transpose(2, 0, 1))  # (n, m)
    total = cost[np.arange(configurations.shape[1]), configurations].sum(axis=1)
    best = np.flatnonzero(total <= total.min() + 1e-9)
    return configurations[best[-1] if last else best[0]]


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
    n, m = marginal.shape
    distance = np.hypot(*(positions[:, None, :] - goals[None]).transpose(2, 0, 1))
    nearest = np.argmin(distance, axis=1)
    on_goal = distance[np.arange(n), nearest] <= ON_GOAL
    stationary = np.where(on_goal[:, None], _one_hot(nearest, m), 1.0 / m)
    return np.stack([marginal, _one_hot(nearest, m), _one_hot(convention, m), stationary], 1)


def motion_log_likelihood(
    previous: np.ndarray,
    current: np.ndarray,
    goal_probabilities: np.ndarray,
    goals: np.ndarray,
    reach: np.ndarray,
    sigma: float,
) -> np.ndarray:
    """``(n, T)`` log likelihood of each teammate's observed step under each type.

    ``goal_probabilities`` are the ``(n, T, m)`` predictions made at ``previous``;
    ``reach`` the ``(n,)`` metres a robot covers in a step at most.
    """
    delta = goals[None] - previous[:, None]  # (n, m, 2)
    distance = np.hypot(delta[..., 0], delta[..., 1])
    scale = np.minimum(reach[:, None], distance) / np.maximum(distance, 1e-12)
    predicted = previous[:, None] + scale[..., None] * delta  # (n, m, 2)
    norm = -np.log(2 * np.pi * sigma**2)
    miss = current[:, None] - predicted
    toward = norm - (miss**2).sum(-1) / (2 * sigma**2)  # (n, m)
    with np.errstate(divide="ignore"):
        moving = logsumexp(np.log(goal_probabilities) + toward[:, None, :], axis=-1)
    still = norm - ((current - previous) ** 2).sum(-1) / (2 * sigma**2)
    stationary = TYPES.index("stationary")
    moving[:, stationary] = still
    return moving


def update_types(log_types: np.ndarray, log_likelihood: np.ndarray, leak: float) -> np.ndarray:
    """``(n, T)`` log posterior: Bayes, then mixed with :data:`TYPE_PRIOR` at rate ``leak``.

    Examples
    --------
    >>> post = update_types(np.log(TYPE_PRIOR)[None], np.array([[0.0, 0.0, 0.0, -50.0]]), 0.0)
    >>> np.exp(post).round(3).tolist()
    [[0.6, 0.2, 0.2, 0.0]]
    """
    post = np.exp(log_normalise(log_types + log_likelihood, 1))
    with np.errstate(divide="ignore"):
        return np.log((1 - leak) * post + leak * TYPE_PRIOR)


def mix_configurations(
    prior: np.ndarray,
    log_types: np.ndarray,
    goal_probabilities: np.ndarray,
    configurations: np.ndarray,
    teammates: np.ndarray,
) -> np.ndarray:
    """``(k,)`` the team prior over ``configurations`` made the teammate-type mixture.

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
    >>> q = mix_configurations(np.array([0.9, 0.1]), lt, probs, rows, np.array([1]))
    >>> q.round(3).tolist()   # 0.9 · (0.26 + 0.01), 0.1 · (0.26 + 7.31)
    [0.243, 0.757]
    """
    pi = np.asarray(prior, dtype=float)
    stationary = TYPES.index("stationary")
    m = goal_probabilities.shape[2]
    uncommitted = np.zeros(len(teammates))
    terms = np.zeros((len(teammates), pi.shape[0]))  # a_j(c_j) / π_j(c_j)
    for row, j in enumerate(teammates):
        column = configurations[:, j]
        marginal = np.bincount(column, weights=pi, minlength=m)
        weights = np.exp(log_types[j])
        flat = np.zeros(weights.shape[0], dtype=bool)
        flat[TYPES.index("team")] = True
        flat[stationary] = np.all(goal_probabilities[j, stationary] == 1.0 / m)
        uncommitted[row] = weights[flat].sum()
        committed = weights[~flat] @ goal_probabilities[j, ~flat]  # (m,)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(marginal > 0, committed / marginal, 0.0)
        terms[row] = ratio[column]
    others = np.array([np.prod(np.delete(uncommitted, row)) for row in range(len(teammates))])
    p = pi * (np.prod(uncommitted) + others @ terms)
    return p / p.sum()
