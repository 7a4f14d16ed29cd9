"""Anticipating teammates: what each will do, from what the robot knows it knows.

A teammate ``j`` acts on its own belief, and its belief ranges over what it observed: the
configurations ``B_ij`` that robot ``i`` knows ``j`` keeps (the group ``{i, j}``'s ``B``
set, :mod:`epistemica.del_.state`). From the team prior (teammates are efficient) restricted
to that set, ``i`` predicts how likely ``j`` is to head for each goal:
``π_j(g) ∝ Σ_{c ∈ B_ij, c_j = g} p(c)``. At order 3, ``i`` first predicts, for ``j``, each
other robot ``k`` from ``B_ijk`` the same way, and takes ``j``'s choice to be its best
response: ``p_j(c) ∝ p(c) Π_k π_jk(c_k)`` over ``B_ij``. Robot ``i``'s own prior is then
``p_i(c) ∝ p(c) Π_j π_j(c_j)`` over its own set ``B_i``: the configurations its teammates
will actually take, given what they know and do not know.

Where every teammate keeps what ``i`` keeps this changes nothing a robot chooses, and the
simulator uses it only where the sets differ. Where they differ it decides: a robot that
knows of a goal its teammate does not know of will not meet there; a robot that saw a goal
relocated predicts where a teammate who did not see it will end up.

Examples
--------
Two robots, goals 0 and 1; robot 0 prefers goal 1 but knows robot 1 does not know of it:

>>> import numpy as np
>>> table = np.array([[0, 0], [1, 1]])          # rendezvous: both at goal 0, or at goal 1
>>> base = np.array([0.3, 0.7])                  # the team prior
>>> own = np.array([True, True])                 # robot 0 keeps both
>>> theirs = {1: np.array([True, False])}        # robot 1 conceives of goal 0 only
>>> anticipated_prior(table, base, 0, own, theirs).round(3).tolist()
[1.0, 0.0]
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

__all__ = ["anticipated_prior", "goal_distribution"]


def goal_distribution(
    table: np.ndarray, weights: np.ndarray, robot: int, n_goals: int
) -> np.ndarray:
    """``(n_goals,)`` how the mass of ``weights`` over the configurations ``table``
    (``(k, n)`` goal indices) falls on ``robot``'s goal; zeros if there is no mass."""
    mass = np.bincount(table[:, robot], weights=weights, minlength=n_goals)
    total = mass.sum()
    return mass / total if total > 0 else mass


def anticipated_prior(
    table: np.ndarray,
    base: np.ndarray,
    robot: int,
    own: np.ndarray,
    theirs: Mapping[int, np.ndarray],
    nested: Mapping[tuple[int, int], np.ndarray] | None = None,
    redecide: Callable[[int, int], np.ndarray] | None = None,
) -> np.ndarray:
    """Robot ``robot``'s prior over ``table`` when it anticipates its teammates.

    Parameters
    ----------
    table : numpy.ndarray
        ``(k, n)`` configurations (goal indices per robot).
    base : numpy.ndarray
        ``(k,)`` the team prior over them.
    robot : int
        The deciding robot ``i``.
    own : numpy.ndarray
        ``(k,)`` booleans: ``B_i``.
    theirs : mapping
        Teammate ``j`` -> ``(k,)`` booleans ``B_ij``.
    nested : mapping, optional
        ``(j, k)`` -> ``(k,)`` booleans ``B_ijk`` (order 3: ``j``'s best response to its
        predictions of ``k``).
    redecide : callable, optional
        ``redecide(j, g)``: the team prior over ``table`` once ``j`` stands at goal ``g``.
        A teammate predicted to head for a goal the robot knows it cannot use (a closed
        goal it did not see close) will see that there and choose again, from there,
        among the configurations both keep.

    Returns
    -------
    numpy.ndarray
        ``(k,)`` normalised; the team prior on ``B_i`` when no configuration of ``B_i``
        is compatible with the predictions.
    """
    n_goals = int(table.max()) + 1 if table.size else 0
    weights = np.where(own, base, 0.0)
    for j, mask in theirs.items():
        view = np.where(mask, base, 0.0)
        if nested:
            for (who, k), inner in nested.items():
                if who == j and k != j:
                    prediction = goal_distribution(table, np.where(inner, base, 0.0), k, n_goals)
                    if prediction.any():
                        view = view * prediction[table[:, k]]
        prediction = goal_distribution(table, view, j, n_goals)
        heading = int(np.argmax(prediction))
        if redecide is not None and prediction.any() and not (own & (table[:, j] == heading)).any():
            again = np.where(mask & own, redecide(j, heading), 0.0)
            prediction = goal_distribution(table, again, j, n_goals)
        if prediction.any():
            weights = weights * prediction[table[:, j]]
    total = weights.sum()
    if total > 0:
        return weights / total
    fallback = np.where(own, base, 0.0)
    return fallback / fallback.sum() if fallback.sum() > 0 else np.full(len(base), 1 / len(base))
