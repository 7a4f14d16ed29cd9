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

import numpy as np

from epistemica.aif._validate import as_finite, nonnegative, positive
from epistemica.aif.likelihood import check_configurations

__all__ = ["shared_rank", "team_log_prior"]


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
        keys = g[rows].reshape(k, -1)  # (x, y) of robot 0's goal, then robot 1's, ...
        order = np.lexsort(keys.T[::-1])
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
        ``(n, 2)`` (or ``(n, 3)``) robot positions as the deciding robot observes them.
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
    x = as_finite(positions, "positions", ndim=2)[:, :2]
    g = as_finite(goals, "goals", ndim=2, shape=(None, 2))
    rows = check_configurations(configurations, x.shape[0], g.shape[0]).astype(np.intp)
    scale = positive(scale, "scale")
    tie_weight = nonnegative(tie_weight, "tie_weight")
    distance = np.hypot(*(x[:, None, :] - g[None, :, :]).transpose(2, 0, 1))  # (n, m)
    cost = distance[np.arange(x.shape[0]), rows].sum(axis=1)
    if rank is None:
        rank = shared_rank(g, rows) if tie_weight > 0 else np.zeros(rows.shape[0])
    logits = -(cost - cost.min()) / scale - tie_weight * rank
    logits -= logits.max()
    return logits - np.log(np.exp(logits).sum())
