"""The environment's checks of what a caller passes in (:mod:`epistemica.sim.engine.env`): seeds,
the shaping weight, the actions; each a clear
:class:`~epistemica.del_.errors.InvalidArgumentError` saying what to pass.

Examples
--------
>>> checked_seed(3, "seed"), checked_shaping(0.5)
(3, 0.5)
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["checked_actions", "checked_seed", "checked_shaping"]


def checked_seed(value, what: str) -> int:
    """A seed: a whole number >= 0 (not a bool, a string or a float), or a clear error."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 0:
        raise InvalidArgumentError(
            f"{what} must be a whole number >= 0, got {value!r}",
            hint="e.g. reset(seed=0); leave it out for the next seed",
        )
    return int(value)


def checked_shaping(value) -> float:
    """A finite real weight, or a clear error."""
    try:
        weight = float(value) if not isinstance(value, bool | str) else None
    except (TypeError, ValueError):
        weight = None
    if weight is None or not np.isfinite(weight):
        raise InvalidArgumentError(
            f"shaping must be a finite number, got {value!r}",
            hint="e.g. shaping=1.0 (0: progress only)",
        )
    return weight


def checked_actions(agents: list[str], actions: Mapping) -> np.ndarray:
    """The agents' actions as ``(k, 2)`` finite floats, or an error naming the first bad one."""
    try:
        values = np.array([actions[a] for a in agents], dtype=float)
    except (TypeError, ValueError):
        values = None
    if values is not None and values.shape == (len(agents), 2) and np.isfinite(values).all():
        return values
    for agent in agents:
        value = actions[agent]
        try:
            good = np.shape(value) == (2,) and bool(np.isfinite(np.asarray(value, float)).all())
        except (TypeError, ValueError):
            good = False
        if not good:
            raise InvalidArgumentError(
                f"the action of {agent} must be two finite numbers, got {value!r}",
                hint="(speed, heading change), e.g. np.array([1.0, 0.0])",
            )
    raise AssertionError("unreachable: some action was malformed")  # pragma: no cover
