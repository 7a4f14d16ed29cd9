"""The environment's checks of what a caller passes in (:mod:`epistemica.sim.engine.env`): seeds,
the shaping weight, the teammates' levels, the robot, the keywords, reset's options, the
actions; each a clear :class:`~epistemica.del_.errors.InvalidArgumentError` saying what to
pass.

Examples
--------
>>> checked_seed(3, "seed"), checked_shaping(0.5), checked_robot("r2", ["r1", "r2"])
(3, 0.5, 1)
>>> checked_count(True, "num_envs")
Traceback (most recent call last):
...
epistemica.del_.errors.InvalidArgumentError: num_envs must be a whole number >= 1, got True
hint: e.g. 64
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.policies.policy import Policy

__all__ = [
    "checked_actions",
    "checked_count",
    "checked_keywords",
    "checked_level",
    "checked_options",
    "checked_robot",
    "checked_seed",
    "checked_shaping",
    "checked_teammates",
]


def _whole(value) -> bool:
    return not isinstance(value, bool) and isinstance(value, int | np.integer)


def checked_seed(value, what: str) -> int:
    """A seed: a whole number >= 0 (not a bool, a string or a float), or a clear error."""
    if not _whole(value) or value < 0:
        raise InvalidArgumentError(
            f"{what} must be a whole number >= 0, got {value!r}",
            hint="e.g. reset(seed=0); leave it out for the next seed",
        )
    return int(value)


def checked_count(value, what: str) -> int:
    """A count: a whole number >= 1 (numpy's integers too), or a clear error."""
    if not _whole(value) or value < 1:
        raise InvalidArgumentError(
            f"{what} must be a whole number >= 1, got {value!r}", hint="e.g. 64"
        )
    return int(value)


def checked_level(value):
    """A teammate's level: a level's name or a ``Policy``, or a clear error."""
    if not isinstance(value, str | Policy):
        raise InvalidArgumentError(
            f"a teammate's level is a level's name or a Policy, got {value!r}",
            hint='e.g. "third" or "convention"',
        )
    return value


def checked_teammates(value) -> Mapping:
    """The ``teammates`` mapping (robot name or index -> level), or a clear error."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise InvalidArgumentError(
            f"teammates must map robots to levels, got {type(value).__name__}",
            hint='e.g. {"r2": "third"} (RobotEnv takes one level: teammates="rules-third")',
        )
    for level in value.values():
        checked_level(level)
    return value


def checked_robot(value, names: list[str]) -> int:
    """A robot by name or index into ``names``, as an index, or a clear error."""
    if isinstance(value, str) and value in names:
        return names.index(value)
    if not _whole(value) or not 0 <= value < len(names):
        raise InvalidArgumentError(
            f"no robot {value!r} in this mission",
            hint=f"robots: {', '.join(names)} (or indices 0..{len(names) - 1})",
        )
    return int(value)


def checked_keywords(options: Mapping, accepted: tuple[str, ...]) -> None:
    """Refuse a keyword outside ``accepted`` (say, through ``gymnasium.make``)."""
    unknown = sorted(set(options) - set(accepted))
    if unknown:
        raise InvalidArgumentError(
            f"unknown keyword(s) {', '.join(unknown)}", hint=f"accepted: {', '.join(accepted)}"
        )


def checked_options(value) -> None:
    """``reset``'s ``options``: None or a mapping (the environment reads none of it)."""
    if value is not None and not isinstance(value, Mapping):
        raise InvalidArgumentError(
            f"reset(options=...) must be a dict or None, got {type(value).__name__}",
            hint="leave it out: the environment takes no reset options",
        )


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
