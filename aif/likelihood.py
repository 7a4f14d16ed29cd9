"""Likelihood of the valid configurations from per-robot goal distributions.

Per robot ``r``, ``P_r = softmax(sum_k e_r^(k))`` over the goals. A configuration ``c``
gets ``prod_r P_r(c_r)``, normalised over the VALID rows only (the paper's ``L``). We never
build the ``m**n`` product table: ``ln L`` is a gather of ``ln P_r(c_r)`` along each valid
row, a sum, and a log-sum-exp. Mass the product would put on invalid configurations
never enters, which is exactly what restricting and renormalising the full table does.

Examples
--------
The paper's three-robot, two-goal example (``paper_configs`` in the pymdp vectors):

>>> configs = [[0, 1, 1], [1, 0, 1], [1, 1, 0]]
>>> log_p = goal_log_probabilities([[1.2, 0.3], [0.4, 0.9], [0.2, 1.5]])
>>> np.exp(log_likelihood(log_p, configs)).round(4).tolist()
[0.7367, 0.1817, 0.0816]
"""

from __future__ import annotations

import numpy as np
from scipy.special import log_softmax

from epistemica.aif._logspace import normalise_log
from epistemica.aif._validate import as_finite, as_log_values
from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "check_configurations",
    "configuration_likelihood",
    "goal_log_probabilities",
    "log_likelihood",
    "row_sums",
]


def check_configurations(
    configurations, n_robots: int | None = None, n_goals: int | None = None
) -> np.ndarray:
    """Validate a ``(k, n)`` integer configuration array (eagerly, once).

    Examples
    --------
    >>> check_configurations([[0, 1]], 2, 2).shape
    (1, 2)
    """
    rows = np.asarray(configurations)
    if rows.ndim != 2 or rows.shape[0] == 0 or not np.issubdtype(rows.dtype, np.integer):
        raise InvalidArgumentError(
            f"configurations must be a non-empty 2-D integer array, got shape {rows.shape}",
            hint="build them with valid_configurations(mission, n_robots, n_goals)",
        )
    if n_robots is not None and rows.shape[1] != n_robots:
        raise InvalidArgumentError(
            f"configurations have {rows.shape[1]} columns for {n_robots} robots",
            hint="one column per robot",
        )
    if n_goals is not None and (rows.min() < 0 or rows.max() >= n_goals):
        raise InvalidArgumentError(
            f"configurations name goals outside range({n_goals})",
            hint="goal indices are 0 .. n_goals - 1",
        )
    return rows


def goal_log_probabilities(evidence) -> np.ndarray:
    """``ln softmax`` over goals of the evidence summed over orders.

    ``evidence`` is ``(n, m)`` or ``(orders, n, m)`` (summed over the first axis).

    Examples
    --------
    >>> np.exp(goal_log_probabilities([[0.0, 0.0]])).tolist()
    [[0.5, 0.5]]
    """
    e = as_finite(evidence, "evidence")
    if e.ndim == 3:
        e = e.sum(axis=0)
    if e.ndim != 2 or e.shape[1] == 0:
        raise InvalidArgumentError(
            f"evidence must be (n, m) or (orders, n, m), got shape {e.shape}",
            hint="one row per robot, one column per goal",
        )
    return log_softmax(e, axis=1)


def row_sums(table, configurations) -> np.ndarray:
    """``out[..., s] = sum_r table[..., r, c_s[r]]`` for every valid row ``c_s``.

    ``table`` has shape ``(..., n, m)``; the result ``(..., k)``. Leading axes (candidate
    controls, perspectives) are handled in one pass per robot.

    Examples
    --------
    >>> row_sums([[1.0, 2.0], [10.0, 20.0]], [[0, 1], [1, 0]]).tolist()
    [21.0, 12.0]
    """
    t = np.asarray(table, dtype=float)
    rows = np.asarray(configurations)
    out = np.zeros((*t.shape[:-2], rows.shape[0]))
    for r in range(rows.shape[1]):
        out += t[..., r, :][..., rows[:, r]]
    return out


def log_likelihood(log_p, configurations) -> np.ndarray:
    """``ln L`` over the valid rows: ``sum_r ln P_r(c_r)`` normalised by log-sum-exp.

    Parameters
    ----------
    log_p : array_like
        ``(n, m)`` log goal probabilities per robot (``-inf`` allowed for impossible goals).
    configurations : array_like
        ``(k, n)`` valid configurations.

    Examples
    --------
    >>> np.exp(log_likelihood(np.log([[0.5, 0.5], [0.9, 0.1]]), [[0, 1], [1, 0]])).round(9).tolist()
    [0.1, 0.9]
    """
    lp = as_log_values(log_p, "log_p", ndim=2)
    rows = check_configurations(configurations, lp.shape[0], lp.shape[1])
    return normalise_log(
        row_sums(lp, rows),
        "every valid configuration has probability zero",
        hint="some robot's goal distribution excludes all goals the mission allows",
    )


def configuration_likelihood(p, configurations) -> np.ndarray:
    """The normalised likelihood ``L`` from per-robot goal probabilities ``p`` (``(n, m)``).

    Examples
    --------
    >>> configuration_likelihood([[0.5, 0.5], [0.5, 0.5]], [[0, 1], [1, 0]]).tolist()
    [0.5, 0.5]
    """
    p = as_finite(p, "p", ndim=2)
    if np.any(p < 0):
        raise InvalidArgumentError("p has negative entries", hint="p holds probabilities")
    with np.errstate(divide="ignore"):
        return np.exp(log_likelihood(np.log(p), configurations))
