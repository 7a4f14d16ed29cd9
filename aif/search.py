"""Receding-horizon search over control sequences, with pruning of dominated branches.

Sequences of ``horizon`` controls are expanded breadth first from the poses the first
controls reach; each step costs ``step_cost`` at the pose it reaches, and a sequence costs
the first control's cost plus its steps. Under each first control, a branch that reaches
the same pose as a cheaper one is dominated (the future from a pose does not depend on
how it was reached) and pruned; then only the ``beam`` cheapest branches are expanded.
The result is, per first control, the cost of its best sequence: only the first control
is applied, and the search is run again at the next step.

Examples
--------
Two steps towards x = 2 along a line, with controls "stay" and "one metre ahead": staying
first and moving once costs 2 + 1, moving twice 1 + 0.

>>> from epistemica.aif.motion import predict_poses
>>> controls = np.array([[0.0, 0.0], [1.0, 0.0]])
>>> first = predict_poses([0.0, 0.0, 0.0], controls)
>>> cost = lambda xy: np.abs(2.0 - xy[:, 0])
>>> receding_horizon(cost, first, cost(first[:, :2]), controls, horizon=2).tolist()
[3.0, 1.0]
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from epistemica.aif._validate import as_finite, positive_int
from epistemica.aif.motion import predict_poses
from epistemica.del_.errors import InvalidArgumentError

__all__ = ["MAX_BEAM", "MAX_HORIZON", "check_search", "prune_dominated", "receding_horizon"]

#: The deepest look-ahead and widest beam accepted: a search costs about horizon x beam
#: one-step decisions, so these already cost thousands; horizon=10**6 would not return.
MAX_HORIZON, MAX_BEAM = 64, 256

# Poses equal to this many decimals are the same pose (headings compared wrapped).
_POSE_DECIMALS = 9


def check_search(horizon, beam) -> tuple[int, int]:
    """``(horizon, beam)`` checked: integers >= 1, at most :data:`MAX_HORIZON` and :data:`MAX_BEAM`.

    Examples
    --------
    >>> check_search(3, 4)
    (3, 4)
    >>> check_search(1, MAX_BEAM + 1)
    Traceback (most recent call last):
    ...
    epistemica.del_.errors.InvalidArgumentError: beam must be at most 256, got 257
    hint: a receding horizon is re-planned every step; a few steps suffice
    """
    hint = "horizon 1 is the one-step controller"
    checked = positive_int(horizon, "horizon", hint), positive_int(beam, "beam", hint)
    for name, value, most in (("horizon", horizon, MAX_HORIZON), ("beam", beam, MAX_BEAM)):
        if value > most:  # each depth costs about beam one-step decisions
            raise InvalidArgumentError(
                f"{name} must be at most {most}, got {value!r}",
                hint="a receding horizon is re-planned every step; a few steps suffice",
            )
    return checked


def prune_dominated(nodes, cost, origin, beam: int):
    """Per first control: drop branches dominated at the same pose, keep the ``beam`` cheapest.

    Parameters
    ----------
    nodes : array_like
        ``(b, 3)`` poses ``(x, y, heading)`` the branches reach.
    cost : array_like
        ``(b,)`` cost of each branch so far.
    origin : array_like
        ``(b,)`` index of each branch's first control.
    beam : int
        Branches kept per first control.

    Returns
    -------
    tuple of numpy.ndarray
        The kept ``nodes``, ``cost`` and ``origin``, sorted by origin then cost. Every first
        control keeps its cheapest branch.

    Examples
    --------
    Two branches of control 0 reach the same pose; the dearer one is dominated:

    >>> nodes = [[1.0, 0.0, 0.0], [1.0, 0.0, 2 * np.pi], [0.0, 0.0, 0.0]]
    >>> kept = prune_dominated(nodes, [2.0, 1.0, 5.0], [0, 0, 0], beam=4)
    >>> kept[1].tolist(), kept[2].tolist()
    ([1.0, 5.0], [0, 0])
    """
    nodes = as_finite(nodes, "nodes", ndim=2, shape=(None, 3))
    b = nodes.shape[0]
    cost = np.asarray(cost, dtype=float)
    origin = np.asarray(origin)
    if cost.shape != (b,) or origin.shape != (b,) or not np.issubdtype(origin.dtype, np.integer):
        raise InvalidArgumentError(
            f"cost and origin must be ({b},) like nodes; origin integer",
            hint="one cost and one first-control index per branch",
        )
    beam = positive_int(beam, "beam", "the number of branches kept per first control")
    key = np.round(nodes, _POSE_DECIMALS)
    key[:, 2] = np.round(np.angle(np.exp(1j * nodes[:, 2])), _POSE_DECIMALS)
    order = np.lexsort((cost, *key.T[::-1], origin))
    k_sorted, o_sorted = key[order], origin[order]
    new_pose = np.ones(len(order), dtype=bool)
    new_pose[1:] = np.any(k_sorted[1:] != k_sorted[:-1], axis=1) | (o_sorted[1:] != o_sorted[:-1])
    keep = order[new_pose]
    keep = keep[np.lexsort((cost[keep], origin[keep]))]
    rank = np.arange(keep.size) - np.searchsorted(origin[keep], origin[keep], side="left")
    keep = keep[rank < beam]
    return nodes[keep], cost[keep], origin[keep]


def receding_horizon(
    step_cost: Callable[[np.ndarray], np.ndarray],
    first,
    first_cost,
    controls,
    dt: float = 1.0,
    horizon: int = 2,
    beam: int = 4,
) -> np.ndarray:
    """Best cumulative cost over ``horizon`` steps for each first control.

    Parameters
    ----------
    step_cost : callable
        Maps positions ``(b, 2)`` to the cost ``(b,)`` of a step that reaches them.
    first : array_like
        ``(c0, 3)`` poses reached by the first controls.
    first_cost : array_like
        ``(c0,)`` their one-step costs.
    controls : array_like
        ``(c, 2)`` controls applied at every later step.
    dt : float
        Time step (s).
    horizon, beam : int
        Sequence length (1: the first costs are returned), and branches expanded per
        first control and depth.

    Returns
    -------
    numpy.ndarray
        ``(c0,)`` cost of the cheapest surviving sequence under each first control.

    Examples
    --------
    >>> from epistemica.aif.motion import predict_poses
    >>> controls = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, np.pi]])  # wait, ahead, turn back
    >>> first = predict_poses([0.0, 0.0, 0.0], controls)
    >>> cost = lambda xy: np.hypot(xy[:, 0] - 3.0, xy[:, 1])
    >>> receding_horizon(cost, first, cost(first[:, :2]), controls, horizon=3).round(9).tolist()
    [6.0, 3.0, 9.0]

    Waiting first costs 3 + 2 + 1, heading on 2 + 1 + 0, turning back 4 + 3 + 2.
    """
    first = as_finite(first, "first", ndim=2, shape=(None, 3))
    c0 = first.shape[0]
    cost = np.array(first_cost, dtype=float)
    if cost.shape != (c0,):
        raise InvalidArgumentError(
            f"first_cost must have shape ({c0},), got {cost.shape}",
            hint="one cost per first control",
        )
    controls = as_finite(controls, "controls", ndim=2, shape=(None, 2))
    c = controls.shape[0]
    horizon = positive_int(horizon, "horizon", "horizon 1 is the one-step controller")
    nodes, origin = first, np.arange(c0)
    for _ in range(1, horizon):
        nodes, cost, origin = prune_dominated(nodes, cost, origin, beam)
        children = predict_poses(nodes[:, None, :], controls, dt).reshape(-1, 3)
        step = step_cost(children[:, :2])
        cost = np.repeat(cost, c) + step
        origin = np.repeat(origin, c)
        nodes = children
    best = np.full(c0, np.inf)
    np.minimum.at(best, origin, cost)
    return best
