"""Belief updates over the valid configurations.

Two rules are provided:

- :func:`bayes_update`: the paper's equation, ``q ∝ L · prior``, computed in log space so
  that products of many small likelihoods neither underflow nor lose precision;
- :func:`published_update`: the rule of the authors' released code,
  ``q = softmax(w · L + (1 - w) · prior)`` with ``w = 0.2`` (0.1 in their multi-task
  runs). It mixes *probabilities* inside a softmax, so it is not Bayesian: a likelihood
  of 1 on one configuration moves the belief only a little. It is kept to reproduce the
  published numbers.

Examples
--------
>>> bayes_update([0.5, 0.25, 0.25], [0.7367, 0.1817, 0.0816]).round(4).tolist()
[0.8484, 0.1046, 0.047]
>>> published_update([0.5, 0.5], [1.0, 0.0]).round(4).tolist()
[0.5498, 0.4502]
"""

from __future__ import annotations

import numpy as np
from scipy.special import softmax

from epistemica.aif._logspace import normalise_log
from epistemica.aif._validate import (
    as_distribution,
    as_finite,
    as_log_values,
    as_nonnegative,
    positive_int,
)
from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "PUBLISHED_WEIGHT",
    "bayes_update",
    "bayes_update_log",
    "published_update",
    "uniform_belief",
]

#: Likelihood weight of the published code's update (rendezvous and task allocation).
PUBLISHED_WEIGHT = 0.2


def uniform_belief(n_states: int) -> np.ndarray:
    """The uniform distribution over ``n_states`` configurations.

    Examples
    --------
    >>> uniform_belief(4).tolist()
    [0.25, 0.25, 0.25, 0.25]
    """
    n_states = positive_int(n_states, "n_states", "pass the number of valid configurations")
    return np.full(n_states, 1.0 / n_states)


def bayes_update_log(log_prior, log_likelihood) -> np.ndarray:
    """Log-space Bayes rule: ``ln q = ln prior + ln L - logsumexp(...)``.

    Entries may be ``-inf`` (impossible states); at least one state must stay possible.

    Examples
    --------
    >>> np.exp(bayes_update_log(np.log([0.5, 0.5]), [0.0, -np.inf])).tolist()
    [1.0, 0.0]
    """
    lp = as_log_values(log_prior, "log_prior", ndim=1)
    ll = as_log_values(log_likelihood, "log_likelihood", ndim=1, shape=lp.shape)
    return normalise_log(
        lp + ll,
        "the prior and the likelihood have disjoint supports",
        hint="every configuration the prior allows is ruled out by the observation",
    )


def bayes_update(prior, likelihood) -> np.ndarray:
    """Posterior ``q ∝ likelihood · prior`` over the same states.

    Parameters
    ----------
    prior : array_like
        Probability vector over the valid configurations.
    likelihood : array_like
        Non-negative vector ``P(o | s)`` (any positive scale: only ratios matter).

    Returns
    -------
    numpy.ndarray
        The normalised posterior.

    Examples
    --------
    >>> bayes_update([0.3, 0.7], [0.1, 0.8]).round(6).tolist()
    [0.050847, 0.949153]
    >>> bayes_update([0.25, 0.75], [1.0, 1.0]).tolist()
    [0.25, 0.75]
    """
    prior = as_distribution(prior, "prior")
    likelihood = as_nonnegative(likelihood, "likelihood", size=prior.size)
    with np.errstate(divide="ignore"):
        log_q = bayes_update_log(np.log(prior), np.log(likelihood))
    return np.exp(log_q)


def published_update(prior, likelihood, weight: float = PUBLISHED_WEIGHT) -> np.ndarray:
    """The released code's update ``softmax(w · L + (1 - w) · prior)``.

    ``likelihood`` is normalised over the states first (the paper's ``L``).

    Examples
    --------
    >>> published_update([0.25] * 4, [0.25] * 4).tolist()
    [0.25, 0.25, 0.25, 0.25]
    """
    prior = as_distribution(prior, "prior")
    likelihood = as_nonnegative(likelihood, "likelihood", size=prior.size)
    w = float(as_finite(weight, "weight"))
    if not 0.0 <= w <= 1.0:
        raise InvalidArgumentError(
            f"weight must lie in [0, 1], got {weight!r}", hint="the published runs use 0.2"
        )
    return softmax(w * likelihood / likelihood.sum() + (1.0 - w) * prior)
