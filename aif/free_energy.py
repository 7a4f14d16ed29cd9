"""Variational and expected free energy, policy posterior and policy selection.

Variational free energy, in the standard form used by this package and by pymdp::

    F[q] = KL[q || prior] - E_q[ln P(o | s)]            (complexity - accuracy)
         = KL[q || P(s | o)] - ln P(o)                 (so F >= -ln P(o), = at the posterior)

The paper prints ``F = H[q] + KL[q || P]``; with ``P`` a distribution over the states that
sum is the cross-entropy ``-E_q[ln P]`` (see :func:`printed_free_energy`). When ``P`` is
the exact posterior ``P(s | o)``, ``printed = F + H[q] - (-ln P(o))``: both are minimised
by the posterior only if the entropy term is dropped, so we minimise ``F``. The released
code scores a predicted belief with ``H[q] - ln max q`` (:func:`published_free_energy`).

Expected free energy of a policy whose predicted states are ``q(s)`` and whose JOINT
outcome model is ``A[o, s] = P(o | s)``, with preferred outcomes ``C = softmax(c)``::

    G = KL[Q(o) || C] + E_q[H[P(o | s)]]                 (risk + ambiguity)
      = -E_Q(o)[ln C(o)] - I_q(S; O)                     (-(pragmatic + epistemic))

Examples
--------
>>> round(variational_free_energy([0.8, 0.2], [0.5, 0.5], [0.8, 0.2]), 6)
0.693147
>>> efe = expected_free_energy([0.5, 0.5], [[0.9, 0.2], [0.1, 0.8]])
>>> round(efe.G, 6) == round(efe.risk + efe.ambiguity, 6)
True
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.special import log_softmax, xlogy

from epistemica.aif._logspace import normalise_log
from epistemica.aif._validate import (
    as_distribution,
    as_finite,
    as_likelihood_matrix,
    as_log_values,
    as_nonnegative,
)
from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "ExpectedFreeEnergy",
    "expected_free_energy",
    "joint_observation_model",
    "joint_preference",
    "policy_posterior",
    "printed_free_energy",
    "published_free_energy",
    "select_policy",
    "variational_free_energy",
]


def variational_free_energy(q, prior, likelihood) -> float:
    """``F = KL[q || prior] - E_q[ln likelihood]`` for one observed outcome.

    Parameters
    ----------
    q, prior : array_like
        Probability vectors over the states.
    likelihood : array_like
        ``P(o | s)`` of the observed ``o``, one entry per state.

    Examples
    --------
    At the exact posterior ``F`` equals the surprise ``-ln P(o)``:

    >>> round(variational_free_energy([0.8, 0.2], [0.5, 0.5], [0.8, 0.2]), 6)  # ln 2
    0.693147
    >>> round(variational_free_energy([0.5, 0.5], [0.5, 0.5], [0.8, 0.2]), 6)
    0.916291
    """
    q = as_distribution(q, "q")
    prior = as_distribution(prior, "prior", size=q.size)
    likelihood = as_nonnegative(likelihood, "likelihood", size=q.size)
    support = q > 0
    if np.any(prior[support] == 0) or np.any(likelihood[support] == 0):
        return float("inf")
    qs = q[support]
    complexity = np.sum(qs * (np.log(qs) - np.log(prior[support])))
    accuracy = np.sum(qs * np.log(likelihood[support]))
    return float(complexity - accuracy)


def printed_free_energy(q, p) -> float:
    """The paper's printed form ``H[q] + KL[q || p]`` (equal to the cross-entropy).

    Examples
    --------
    >>> round(printed_free_energy([0.5, 0.5], [0.5, 0.5]), 6)  # = H[q] when p = q
    0.693147
    """
    q = as_distribution(q, "q")
    p = as_distribution(p, "p", size=q.size)
    support = q > 0
    if np.any(p[support] == 0):
        return float("inf")
    return float(-np.sum(q[support] * np.log(p[support])))


def published_free_energy(q) -> float:
    """The released code's score of a predicted belief: ``H[q] - ln max q``.

    It equals ``H[q] + KL[onehot(argmax q) || q]``; it is zero only on a one-hot belief.

    Examples
    --------
    >>> published_free_energy([1.0, 0.0])
    0.0
    >>> round(published_free_energy([0.5, 0.5]), 6)  # 2 ln 2
    1.386294
    """
    q = as_distribution(q, "q")
    return float(max(-xlogy(q, q).sum() - np.log(q.max()), 0.0)) + 0.0  # no -0.0


class ExpectedFreeEnergy(NamedTuple):
    """Components of the expected free energy of one policy (nats)."""

    G: float
    risk: float
    ambiguity: float
    pragmatic: float
    epistemic: float


def joint_observation_model(*likelihoods) -> np.ndarray:
    """Combine conditionally independent modalities into one joint ``P(o_1, ..., o_M | s)``.

    Each argument has shape ``(n_outcomes_m, n_states)``; the result has shape
    ``(prod n_outcomes_m, n_states)`` with outcome index in C order (last modality fastest).

    Examples
    --------
    >>> joint_observation_model([[1.0, 0.0], [0.0, 1.0]], [[0.5, 1.0], [0.5, 0.0]]).tolist()
    [[0.5, 0.0], [0.5, 0.0], [0.0, 1.0], [0.0, 0.0]]
    """
    if not likelihoods:
        raise InvalidArgumentError("no modality given", hint="pass at least one P(o | s) array")
    joint = np.asarray(likelihoods[0], dtype=float)
    n_states = joint.shape[-1] if joint.ndim == 2 else None
    joint = as_likelihood_matrix(joint, n_states)
    for a in likelihoods[1:]:
        a = as_likelihood_matrix(a, n_states)
        joint = (joint[:, None, :] * a[None, :, :]).reshape(-1, n_states)
    return joint


def joint_preference(*log_preferences) -> np.ndarray:
    """Outer sum of per-modality log preferences, matching :func:`joint_observation_model`.

    Examples
    --------
    >>> joint_preference([0.0, 1.0], [2.0, 0.0]).tolist()
    [2.0, 0.0, 3.0, 1.0]
    """
    total = np.zeros(1)
    for c in log_preferences:
        c = as_finite(c, "log_preference", ndim=1)
        total = (total[:, None] + c[None, :]).ravel()
    return total


def expected_free_energy(qs, likelihood, log_preference=None) -> ExpectedFreeEnergy:
    """Expected free energy of one policy from its predicted states and outcome model.

    Parameters
    ----------
    qs : array_like
        Predicted distribution over states under the policy, shape ``(n_states,)``.
    likelihood : array_like
        Joint outcome model ``P(o | s)``, shape ``(n_outcomes, n_states)``.
    log_preference : array_like, optional
        Log preferences ``c`` over outcomes; normalised as ``ln C = log_softmax(c)`` so that
        risk is a true KL divergence. ``None`` means no preference (uniform ``C``).

    Returns
    -------
    ExpectedFreeEnergy
        ``G = risk + ambiguity = -(pragmatic + epistemic)``; the epistemic value is the
        joint mutual information ``I(S; O)``.

    Examples
    --------
    A cue that reveals the state has epistemic value ``ln 2``; an uninformative one none:

    >>> round(expected_free_energy([0.5, 0.5], [[1, 0], [0, 1]]).epistemic, 6)
    0.693147
    >>> expected_free_energy([0.5, 0.5], [[0.5, 0.5], [0.5, 0.5]]).epistemic
    0.0
    """
    qs = as_distribution(qs, "qs")
    a = as_likelihood_matrix(likelihood, qs.size)
    if log_preference is None:
        ln_c = np.full(a.shape[0], -np.log(a.shape[0]))
    else:
        c = as_finite(log_preference, "log_preference", ndim=1, shape=(a.shape[0],))
        ln_c = log_softmax(c)
    qo = a @ qs
    h_o = float(-xlogy(qo, qo).sum())
    ambiguity = float(-(xlogy(a, a).sum(axis=0) @ qs))
    pragmatic = float(qo @ ln_c)
    epistemic = max(h_o - ambiguity, 0.0)
    risk = float(-h_o - pragmatic)  # KL[Q(o) || C] = -H[Q(o)] - E_Q[ln C]
    return ExpectedFreeEnergy(
        G=-(pragmatic + epistemic),
        risk=max(risk, 0.0),
        ambiguity=max(ambiguity, 0.0),
        pragmatic=pragmatic,
        epistemic=epistemic,
    )


def policy_posterior(G, gamma: float = 1.0, log_prior=None) -> np.ndarray:
    """``q(pi) = softmax(-gamma · G + ln E)`` over policies.

    Examples
    --------
    >>> policy_posterior([1.0, 1.0]).tolist()
    [0.5, 0.5]
    >>> policy_posterior([0.0, 1.0], gamma=16).round(6).tolist()
    [1.0, 0.0]
    """
    g = as_finite(G, "G", ndim=1)
    if g.size == 0:
        raise InvalidArgumentError("G is empty", hint="pass one expected free energy per policy")
    gam = float(as_finite(gamma, "gamma"))
    if gam < 0:
        raise InvalidArgumentError(
            f"gamma must be >= 0, got {gamma!r}", hint="gamma is a precision"
        )
    # Shifting G by its minimum changes nothing after normalisation and keeps a huge
    # precision from overflowing: the best policy's logit is 0, the others <= 0 (or -inf).
    with np.errstate(over="ignore"):
        logits = -gam * (g - g.min())
    if log_prior is not None:
        logits = logits + as_log_values(log_prior, "log_prior", ndim=1, shape=g.shape)
    log_q = normalise_log(
        logits,
        "every policy has zero prior probability",
        hint="give at least one policy a finite ln E",
    )
    return np.exp(log_q)


def select_policy(q_pi, rng: np.random.Generator | None = None) -> int:
    """Index of the chosen policy: the most probable (first on ties), or a sample.

    Parameters
    ----------
    q_pi : array_like
        Policy posterior.
    rng : numpy.random.Generator, optional
        When given, sample from ``q_pi`` with it; otherwise choose deterministically.

    Examples
    --------
    >>> select_policy([0.2, 0.5, 0.3])
    1
    >>> select_policy([0.0, 1.0], np.random.default_rng(0))
    1
    """
    q = as_distribution(q_pi, "q_pi")
    if rng is None:
        return int(np.argmax(q))
    if not isinstance(rng, np.random.Generator):
        raise InvalidArgumentError(
            f"rng must be a numpy.random.Generator, got {type(rng).__name__}",
            hint="pass numpy.random.default_rng(seed)",
        )
    return int(rng.choice(q.size, p=q))
