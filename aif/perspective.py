"""The beliefs a deciding robot holds or models, and their evidence after it moves.

Robot ``i`` reasoning at order ``K`` holds its own belief (the ``root`` perspective, order
``K``) and, at ``K >= 2``, models the others' beliefs: for each order-2 chain ``(i, j)``,
``j``'s belief at order ``K - 1``; at ``K = 3``, for each chain ``(i, j, k)``, ``k``'s
belief at order ``K - 2`` (chains ending at the same robot count with their multiplicity,
the perspective's ``weight``). The chains are those of
:func:`epistemica.aif.evidence.chain_counts`.

When ``i`` moves, only what its motion can change is recomputed: in its own belief its
measurements of the others (its viewpoint moves; its own row stays, since ``i`` knows its
own motion exactly), and in a modelled belief the measurements *of* ``i`` (what the others
would see of its move).

Examples
--------
>>> [(p.agent, p.order, p.weight, p.root) for p in perspectives(["range"] * 3, 0, 2)]
[(0, 2, 1.0, True), (1, 1, 1.0, False), (2, 1, 1.0, False)]
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from epistemica.aif.evidence import (
    chain_counts,
    check_order,
    check_robot,
    check_sensors,
    noise_attenuation,
    stack_evidence,
)

__all__ = ["Perspective", "perspectives", "row_weights"]


class Perspective(NamedTuple):
    """A belief the deciding robot holds (``root``) or models for another robot.

    ``agent`` holds the belief, built from evidence up to ``order``; ``weight`` is the
    number of chains that lead to it; ``counts[v]`` is how many of its evidence chains of
    order >= 1 end at viewpoint ``v`` (its evidence is ``sum_v counts[v] * measurements(v)``
    plus its own position at order 0).
    """

    agent: int
    order: int
    weight: float
    root: bool
    counts: np.ndarray


def perspectives(sensors: Sequence[str], robot: int, order: int) -> list[Perspective]:
    """The beliefs robot ``robot`` holds (first) or models, with their evidence chains.

    Parameters
    ----------
    sensors : sequence of {"range", "bearing"}
        One sensor type per robot.
    robot : int
        The deciding robot.
    order : {0, 1, 2, 3}
        Its order of reasoning.

    Examples
    --------
    A bearing robot 1 is modelled twice at order 3: directly (chain ``(0, 1)``) and as
    the range robot 2 would model it (chain ``(0, 2, 1)``):

    >>> ps = perspectives(["range", "bearing", "range"], 0, 3)
    >>> [(p.agent, p.order, p.weight) for p in ps]
    [(0, 3, 1.0), (1, 2, 1.0), (2, 2, 1.0), (1, 1, 1.0)]
    >>> ps[0].counts.tolist()  # chain ends: (0,); (0, 1), (0, 2); (0, 2, 1)
    [1.0, 2.0, 1.0]
    """
    sensors = check_sensors(sensors)
    robot = check_robot(robot, len(sensors))
    order = check_order(order)
    out = [_perspective(sensors, robot, order, 1.0, root=True)]
    if order >= 2:
        counts = chain_counts(sensors, robot, order)
        # An order-2 chain (i, j) ends at j: i's model of j's belief, one order lower.
        for j in np.flatnonzero(counts[2]):
            out.append(_perspective(sensors, int(j), order - 1, float(counts[2, j])))
        if order >= 3:
            # An order-3 chain (i, j, k): i's model of j's model of k's belief.
            for k in np.flatnonzero(counts[3]):
                out.append(_perspective(sensors, int(k), order - 2, float(counts[3, k])))
    return out


def _perspective(sensors, agent: int, order: int, weight: float, root=False) -> Perspective:
    counts = chain_counts(sensors, agent, order)
    return Perspective(agent, order, weight, root, counts[1:].sum(axis=0).astype(float))


def row_weights(views: Sequence[Perspective], n: int) -> np.ndarray:
    """How many evidence terms reach each robot's row in each perspective, ``(P, n)``.

    A row gets one term per chain whose viewpoint measures it (a viewpoint never
    measures itself) plus, for the perspective's own agent, its exact position. The
    evidence of a row is the mean of its terms: summing them would count the agent's own
    row (and rows measured by many chains) several times while others count once, and
    two robots with the same information would then each trust their own nearest goal
    more than the other's, claiming the same goal.

    Examples
    --------
    Two range robots at order 2, robot 0 deciding: in its own belief its row gets its
    position and robot 1's view of it, robot 1's row only robot 0's view of it; in its
    model of robot 1 (order 1), each row gets one term.

    >>> row_weights(perspectives(["range", "range"], 0, 2), 2).tolist()
    [[2.0, 1.0], [1.0, 1.0]]
    """
    out = np.zeros((len(views), n))
    for p, view in enumerate(views):
        out[p] = view.counts.sum() - view.counts
        out[p, view.agent] += 1.0
    return np.maximum(out, 1.0)  # a row nobody measures stays at zero evidence


# Multiply-adds per BLAS product: at most OpenBLAS's threshold for one thread (65536 · 4).
# Above it, starting threads on a busy CPU cost about 10 ms a call (measured: n = 9, third
# order, 108 ms a team step against 13 ms on one thread).
_SERIAL_PRODUCT = 262_144


def chain_sums(counts: np.ndarray, stack: np.ndarray) -> np.ndarray:
    """``tensordot(counts (P, n), stack (b, n, n, m), ([1], [1]))`` in serial-size blocks.

    Each block is the same product over fewer candidates, so every entry is computed
    exactly as in one product.
    """
    per = counts.size * int(np.prod(stack.shape[2:]))  # multiply-adds per candidate
    step = max(1, _SERIAL_PRODUCT // max(per, 1))
    if stack.shape[0] <= step:
        return np.tensordot(counts, stack, axes=([1], [1]))
    return np.concatenate(
        [
            np.tensordot(counts, stack[a : a + step], axes=([1], [1]))
            for a in range(0, stack.shape[0], step)
        ],
        axis=1,
    )


def predicted_evidence(
    views: list[Perspective],
    robot: int,
    positions: np.ndarray,
    candidates: np.ndarray,
    goals: np.ndarray,
    bearing: np.ndarray,
    eta: float,
    eta_bearing: float,
    position_noise: float = 0.0,
) -> np.ndarray:
    """Evidence ``(P, b, n, m)`` of every perspective with ``robot`` at each candidate.

    Unchecked core for the controller: ``positions (n, 2)``, ``candidates (b, 2)``,
    ``goals (m, 2)``, ``bearing`` a boolean mask of the bearing robots; ``views[0]`` is
    ``robot``'s own (root) perspective. With ``position_noise > 0`` (variance, m², of the
    observed positions of the others) each row is attenuated by
    :func:`~epistemica.aif.evidence.noise_attenuation` as ``robot`` sees the scene.

    Examples
    --------
    Robot 0 moving from x = 0 to x = 5 does not change its own row of its own evidence,
    but it does change robot 1's view of it:

    >>> views = perspectives(["range", "range"], 0, 2)
    >>> pos = np.array([[0.0, 0.0], [0.0, 10.0]])
    >>> goals = np.array([[10.0, 0.0], [-10.0, 0.0]])
    >>> e = predicted_evidence(views, 0, pos, np.array([[0.0, 0.0], [5.0, 0.0]]), goals,
    ...                         np.array([False, False]), 10.0, 1.0)
    >>> bool(np.array_equal(e[0, 0, 0], e[0, 1, 0])), bool(e[1, 1, 0, 0] > e[1, 0, 0, 0])
    (True, True)
    """
    scenes = np.repeat(positions[None], candidates.shape[0], axis=0)
    scenes[:, robot] = candidates
    stack, ranged = stack_evidence(scenes, goals, bearing, eta, eta_bearing)
    counts = np.array([p.counts for p in views])
    e = chain_sums(counts, stack)  # (P, b, n, m)
    agents = np.array([p.agent for p in views])
    # Order 0: each perspective's agent knows its own position exactly.
    e[np.arange(len(views)), :, agents] += ranged[:, agents].transpose(1, 0, 2)
    e /= row_weights(views, positions.shape[0])[:, None, :, None]
    others = np.arange(positions.shape[0]) != robot
    e[0, :, robot] = e[0, 0, robot]  # own motion is not evidence about own goal
    e[1:, :, others] = e[1:, :1, others]
    if position_noise > 0:
        factor = noise_attenuation(
            positions[None], np.array([robot]), bearing, position_noise, eta, eta_bearing
        )[0]
        e *= factor[None, None, :, None]
    return e
