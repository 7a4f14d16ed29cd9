"""Entropy, Kullback-Leibler divergence and mutual information of discrete distributions.

All quantities are in nats and follow the convention ``0 ln 0 = 0``.

Examples
--------
>>> round(entropy([0.5, 0.5]), 6)
0.693147
>>> kl_divergence([0.5, 0.5], [0.5, 0.5])
0.0
"""

from __future__ import annotations

import numpy as np
from scipy.special import xlogy

from epistemica.aif._validate import as_distribution, as_finite, as_likelihood_matrix
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["entropy", "kl_divergence", "mutual_information", "total_correlation"]


def entropy(p) -> float:
    """Shannon entropy ``H[p] = -sum p ln p`` of a probability vector.

    Examples
    --------
    >>> round(entropy([0.25] * 4), 6)
    1.386294
    """
    p = as_distribution(p, "p")
    return float(max(-xlogy(p, p).sum(), 0.0)) + 0.0  # no -0.0


def kl_divergence(p, q) -> float:
    """``KL[p || q] = sum p ln(p / q)``; infinite when ``p`` puts mass where ``q`` has none.

    Examples
    --------
    >>> round(kl_divergence([0.8, 0.2], [0.5, 0.5]), 6)
    0.192745
    >>> kl_divergence([1.0, 0.0], [0.0, 1.0])
    inf
    """
    p = as_distribution(p, "p")
    q = as_distribution(q, "q", size=p.size)
    support = p > 0
    if np.any(q[support] == 0):
        return float("inf")
    value = float(np.sum(p[support] * (np.log(p[support]) - np.log(q[support]))))
    return max(value, 0.0)


def mutual_information(qs, likelihood) -> float:
    """Mutual information ``I(S; O)`` of states ``S ~ qs`` and outcomes ``O ~ P(o | s)``.

    ``likelihood`` is the JOINT observation model, shape ``(n_outcomes, n_states)``:
    when several modalities depend on the same state, combine them first with
    :func:`epistemica.aif.free_energy.joint_observation_model` (summing per-modality
    informations over-counts by the total correlation of the outcomes).

    Examples
    --------
    >>> round(mutual_information([0.5, 0.5], [[1.0, 0.0], [0.0, 1.0]]), 6)
    0.693147
    >>> mutual_information([0.5, 0.5], [[0.3, 0.3], [0.7, 0.7]])
    0.0
    """
    qs = as_distribution(qs, "qs")
    a = as_likelihood_matrix(likelihood, qs.size)
    qo = a @ qs
    h_o = -xlogy(qo, qo).sum()
    h_o_given_s = -(xlogy(a, a).sum(axis=0) @ qs)
    return float(max(h_o - h_o_given_s, 0.0))


def total_correlation(joint) -> float:
    """Total correlation ``sum_m H[O_m] - H[O_1, ..., O_M]`` of a joint outcome table.

    ``joint`` is an M-dimensional array of probabilities (one axis per modality). This is
    exactly the amount by which a per-modality sum of informations exceeds the joint one
    for conditionally independent modalities.

    Examples
    --------
    >>> total_correlation([[0.5, 0.0], [0.0, 0.5]]) == entropy([0.5, 0.5])
    True
    """
    table = as_finite(joint, "joint")
    if np.any(table < 0) or abs(table.sum() - 1.0) > 1e-6:
        raise InvalidArgumentError("joint must be a probability table", hint="normalise it")
    flat = table.ravel()
    h_joint = -xlogy(flat, flat).sum()
    h_marginals = 0.0
    for axis in range(table.ndim):
        others = tuple(i for i in range(table.ndim) if i != axis)
        marginal = table.sum(axis=others)
        h_marginals += -xlogy(marginal, marginal).sum()
    return float(max(h_marginals - h_joint, 0.0))
