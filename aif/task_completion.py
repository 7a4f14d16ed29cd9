"""Expected completion times of tasks that need several robots at once.

The model of :mod:`epistemica.aif.task_planning`: a task is done at the ``needs``-th
arrival among the robots that come, each coming independently with its predicted
probability; a task too few come to costs ``fail``, less a ``credit`` for each robot that
came (those still to be brought cost less). The sum over who comes is exact (a pass over
the arrivals in order that keeps the distribution of how many came).

Examples
--------
>>> completion_times([[5.0], [10.0]], [[1.0], [0.5]], [2], [100.0]).tolist()
[55.0]
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Credit", "completion_times", "sorted_completion"]


def completion_times(
    arrivals,
    presence,
    needs,
    fail,
    credit: float = 0.0,
    timed: bool = False,
    quorum: int = 1,
    brought=None,
    free=None,
) -> np.ndarray:
    """``(c,)`` the expected completion time of each column: the ``needs``-th arrival
    among the robots that come; when only ``c < needs`` come, ``fail`` less ``credit``
    of its ``1 / needs`` share for each that came (those still to be brought cost less).

    Parameters
    ----------
    arrivals : array_like
        ``(r, c)`` when each robot would arrive (``inf``: it cannot).
    presence : array_like
        ``(r, c)`` the probability that each robot comes (independently).
    needs : array_like
        ``(c,)`` robots each column needs at once (``>= 1``).
    fail : array_like
        ``(c,)`` the cost of too few coming.
    credit : float
        In ``[0, 1]``: 0, too few is as bad as none; 1, the cost falls in proportion.
    timed : bool
        A robot arriving at ``a`` earns ``1 - a / fail`` of its share (sooner is worth more).
    quorum : int
        The fewest robots that earn credit (``>= 1``; one waiting alone brings nobody).
    brought : array_like, optional
        ``(r, c)`` booleans: the robots whose coming earns credit (default: all).
    free : array_like, optional
        ``(r, c)`` the probability that each robot, not coming, is free to be brought
        later: credit then counts only when enough are (default: credit always counts).

    Examples
    --------
    One of two robots certain, the other coming with probability one half:

    >>> completion_times([[5.0], [10.0]], [[1.0], [0.5]], [2], [100.0]).tolist()
    [55.0]
    >>> completion_times([[5.0], [10.0]], [[1.0], [0.5]], [2], [100.0], credit=1.0).tolist()
    [30.0]
    >>> completion_times([[5.0], [10.0]], [[1.0], [0.5]], [2], [100.0], 1.0, timed=True).tolist()
    [31.25]
    >>> completion_times([[5.0], [10.0]], [[1.0], [0.5]], [2], [100.0], 1.0, quorum=2).tolist()
    [55.0]
    >>> completion_times([[5.0], [10.0]], [[1.0], [0.5]], [2], [100.0], 1.0,
    ...                  brought=[[False], [True]]).tolist()    # robot 0 earns nothing
    [55.0]
    """
    a = np.asarray(arrivals, dtype=float)
    p = np.where(np.isfinite(a), np.asarray(presence, dtype=float), 0.0)
    order = np.argsort(a, axis=0, kind="stable")
    cols = np.arange(a.shape[1])
    rule = Credit(credit, timed, quorum)
    worth = None if brought is None else np.asarray(brought, dtype=float)[order, cols]
    free = None if free is None else np.asarray(free, dtype=float)[order, cols]
    needs = np.asarray(needs, dtype=int)
    return sorted_completion(a[order, cols], p[order, cols], needs, fail, rule, worth, free)


class Credit(NamedTuple):
    """How a robot that came to a task too few came to counts (:func:`completion_times`).

    Examples
    --------
    >>> Credit(1.0).quorum
    1
    """

    share: float = 0.0
    timed: bool = False
    quorum: int = 1


def sorted_completion(
    a: np.ndarray, p, needs: np.ndarray, fail, rule: Credit, worth=None, free=None
) -> np.ndarray:
    """:func:`completion_times` of arrivals already sorted down each column (``p``,
    ``worth`` and ``free`` likewise), the credit rule given as a :class:`Credit`.

    Examples
    --------
    >>> rule = Credit(share=1.0)
    >>> sorted_completion(np.array([[5.0], [10.0]]), np.array([[1.0], [0.5]]), np.array([2]),
    ...                   [100.0], rule).tolist()
    [30.0]
    """
    cols = np.arange(a.shape[1])
    fail = np.broadcast_to(np.asarray(fail, dtype=float), cols.shape)
    count = np.zeros((a.shape[1], int(needs.max(initial=1)) + 1))
    count[:, 0] = 1.0  # the distribution of how many came so far, below needs
    earned = np.zeros_like(count)  # E[credit of those that came; that many came]
    expected = np.zeros(a.shape[1])
    for k in np.flatnonzero(p.any(axis=1)):  # robots that never come change nothing
        q = p[k][:, None]
        reach = count[cols, needs - 1] * q[:, 0]  # this arrival is the needs-th
        expected += reach * np.where(reach > 0, a[k], 0.0)
        w = np.clip(1.0 - a[k] / fail, 0.0, 1.0)[:, None] if rule.timed else 1.0
        w = w if worth is None else w * worth[k][:, None]
        earned[:, 1:] = earned[:, 1:] * (1 - q) + (earned[:, :-1] + count[:, :-1] * w) * q
        count[:, 1:] = count[:, 1:] * (1 - q) + count[:, :-1] * q
        count[:, 0] *= 1 - q[:, 0]
        count[cols, needs] = earned[cols, needs] = 0.0
    came = earned[:, max(int(rule.quorum), 1) :].sum(axis=1) / needs
    if free is not None and rule.share > 0:
        came = _pooled(a, p, needs, fail, rule, worth, free)
    missing = count.sum(axis=1) - rule.share * came  # each robot that came: its credit
    return expected + missing * fail


def _pooled(a: np.ndarray, p: np.ndarray, needs: np.ndarray, fail, rule: Credit, worth, free):
    """``(c,)`` the credit of :func:`sorted_completion` counted only when enough of the robots
    that do not come are free (``free``: the probability of each) to make up the rest."""
    r, c = a.shape
    cols = np.arange(c)
    top = int(needs.max(initial=1))
    joint = np.zeros((c, top + 1, r + 1))  # P(that many came, that many free)
    joint[:, 0, 0] = 1.0
    earned = np.zeros_like(joint)
    for k in range(r):
        q, f = p[k][:, None, None], np.clip(free[k], 0.0, 1.0 - p[k])[:, None, None]
        w = np.clip(1.0 - a[k] / fail, 0.0, 1.0) if rule.timed else np.ones(c)
        w = (w if worth is None else w * worth[k])[:, None]
        rest = 1.0 - q - f
        came_j, came_e = np.zeros_like(joint), np.zeros_like(joint)
        came_j[:, 1:] = joint[:, :-1] * q
        came_e[:, 1:] = (earned[:, :-1] + joint[:, :-1] * w[:, :, None]) * q
        freed_j, freed_e = np.zeros_like(joint), np.zeros_like(joint)
        freed_j[:, :, 1:], freed_e[:, :, 1:] = joint[:, :, :-1] * f, earned[:, :, :-1] * f
        joint = joint * rest + came_j + freed_j
        earned = earned * rest + came_e + freed_e
        joint[cols, needs] = earned[cols, needs] = 0.0
    came = np.arange(top + 1)[None, :, None]
    enough = (came + np.arange(r + 1)[None, None, :] >= needs[:, None, None]) & (
        came >= max(int(rule.quorum), 1)
    )
    return (earned * enough).sum(axis=(1, 2)) / needs
