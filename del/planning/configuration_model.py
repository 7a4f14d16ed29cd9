"""The Kripke model of a multi-robot mission: one world per valid goal configuration.

A configuration assigns each robot a goal; the world of a configuration makes the atoms
``assigned(ROBOT, GOAL)`` of that assignment true. At the start no robot knows which
configuration the team will realise, so each robot's knowledge (and belief) relates every
world to every world, and every world is designated. What robots learn later (a teammate
settled at a goal, a fact told to some of them) is applied by product update with
:func:`~epistemica.del_.explicit.action.private_announcement` (:func:`observed`).

Examples
--------
>>> import numpy as np
>>> m = configuration_model(["r1", "r2"], ["g1", "g2"], np.array([[0, 1], [1, 0]]))
>>> m.n_worlds, m.holds("assigned(r1, g1) <-> assigned(r2, g2)")
(2, True)
>>> m.holds("K[r1] assigned(r1, g1)")
False
>>> after = m.update(observed("assigned(r1, g1)", ["r1"], ["r1", "r2"]))
>>> after.holds("K[r1] assigned(r2, g2) & ~K[r2] assigned(r2, g2)")
True
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from epistemica.del_.errors import ModelError
from epistemica.del_.explicit.action import ActionModel, private_announcement
from epistemica.del_.explicit.relations import Partition
from epistemica.del_.language.formula import Formula
from epistemica.del_.models import KripkeModel

__all__ = ["assignment_atom", "configuration_model", "observed"]

#: Configurations beyond which an explicit model is refused.
MAX_CONFIGURATIONS = 200_000


def assignment_atom(robot: str, goal: str) -> str:
    """The atom saying that ``robot`` goes to ``goal``.

    Examples
    --------
    >>> assignment_atom("r1", "g2")
    'assigned(r1, g2)'
    """
    return f"assigned({robot}, {goal})"


def configuration_model(
    robots: Sequence[str], goals: Sequence[str], rows: np.ndarray
) -> KripkeModel:
    """The model whose worlds are the configurations ``rows`` (``(k, n)`` goal indices).

    Worlds are named by the goals in robot order (``"g1 g2"``: robot 1 to ``g1``, robot
    2 to ``g2``).
    """
    rows = np.asarray(rows)
    robots, goals = [str(r) for r in robots], [str(g) for g in goals]
    if rows.ndim != 2 or rows.shape[1] != len(robots) or rows.shape[0] == 0:
        raise ModelError(
            f"configurations must be (k, {len(robots)}) goal indices, got {rows.shape}",
            hint="one row per configuration, one column per robot",
        )
    if rows.shape[0] > MAX_CONFIGURATIONS:
        raise ModelError(
            f"{rows.shape[0]} configurations exceed the explicit limit of {MAX_CONFIGURATIONS}",
            hint="fewer robots or goals, or a `valid` constraint that leaves fewer",
        )
    k, n, m = rows.shape[0], len(robots), len(goals)
    atoms = tuple(assignment_atom(r, g) for r in robots for g in goals)
    val = np.zeros((k, n * m), dtype=bool)
    val[np.arange(k)[:, None], np.arange(n)[None, :] * m + rows] = True
    names = tuple(" ".join(goals[g] for g in row) for row in rows.tolist())
    one_block = Partition(np.zeros(k, dtype=np.int64), 1)
    relations = dict.fromkeys(robots, one_block)
    designated = np.arange(k, dtype=np.int64)
    return KripkeModel.from_arrays(
        names, atoms, val, tuple(robots), relations, dict(relations), designated
    )


def observed(fact: Formula | str, observers: Sequence[str], robots: Sequence[str]) -> ActionModel:
    """The event: ``observers`` see that ``fact`` holds, the other robots are oblivious.

    The observers know who else observed it (common knowledge among them); the others
    believe nothing happened. A robot settling at a goal is ``observed("assigned(r, g)",
    ...)``; a task completed is the fact that no robot is assigned to it.
    """
    return private_announcement(fact, observers, robots)
