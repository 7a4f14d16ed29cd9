"""Normalisation in log space, shared by the active-inference modules (private).

Two kinds: :func:`normalise_log` is the checked form behind the public functions (it
refuses a vector with no possible state); :func:`log_normalise` and :func:`log_softmax`
are the unchecked forms for the controller's inner passes, in plain numpy because scipy's
argument checks cost more than the arithmetic on small arrays.

Examples
--------
>>> np.exp(normalise_log(np.log([1.0, 3.0]), "no state is possible", "hint")).round(9).tolist()
[0.25, 0.75]
"""

from __future__ import annotations

import numpy as np
from scipy.special import logsumexp

from epistemica.del_.errors import InvalidArgumentError

__all__: list[str] = []


def normalise_log(joint: np.ndarray, message: str, hint: str) -> np.ndarray:
    """``joint - logsumexp(joint)``; raises ``InvalidArgumentError(message)`` if all ``-inf``.

    Examples
    --------
    >>> normalise_log(np.array([0.0, -np.inf]), "empty", "hint").tolist()
    [0.0, -inf]
    >>> normalise_log(np.array([-np.inf]), "nothing is possible", "widen the prior")
    Traceback (most recent call last):
    ...
    epistemica.del_.errors.InvalidArgumentError: nothing is possible...
    """
    norm = logsumexp(joint)
    if not np.isfinite(norm):
        raise InvalidArgumentError(message, hint=hint)
    return joint - norm


def log_normalise(x: np.ndarray, axis: int) -> np.ndarray:
    """``x - logsumexp(x)`` along ``axis``, unchecked; ``-inf`` entries are allowed.

    Examples
    --------
    >>> x = np.array([[0.0, 0.0], [np.log(3.0), -np.inf]])
    >>> np.exp(log_normalise(x, 0)).round(9).tolist()
    [[0.25, 1.0], [0.75, 0.0]]

    An all ``-inf`` slice (nothing possible) stays ``-inf``, never NaN:

    >>> log_normalise(np.array([[-np.inf, -np.inf], [0.0, 0.0]]), 1).round(6).tolist()
    [[-inf, -inf], [-0.693147, -0.693147]]
    """
    top = x.max(axis=axis, keepdims=True)
    empty = ~np.isfinite(top)
    top = np.where(empty, 0.0, top)
    with np.errstate(divide="ignore"):
        norm = top + np.log(np.exp(x - top).sum(axis=axis, keepdims=True))
    return np.where(empty, -np.inf, x - np.where(empty, 0.0, norm))


def log_softmax(x: np.ndarray, axis: int) -> np.ndarray:
    """``ln softmax(x)`` along ``axis`` for FINITE ``x``, unchecked (evidence to log P_r).

    Examples
    --------
    >>> np.exp(log_softmax(np.array([[0.0, 0.0], [np.log(3.0), 0.0]]), -1)).round(6).tolist()
    [[0.5, 0.5], [0.75, 0.25]]
    """
    shifted = x - x.max(axis=axis, keepdims=True)
    return shifted - np.log(np.exp(shifted).sum(axis=axis, keepdims=True))
