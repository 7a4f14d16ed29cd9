"""Valid goal configurations: which goal each robot takes, for a given mission.

A configuration assigns one goal (an index in ``range(n_goals)``) to each of ``n_robots``
robots. The valid set is a subset of ``G**n`` stored as an integer array of shape
``(k, n_robots)``, one configuration per row, in lexicographic order.

Constrained sets are built directly, row by row, never by filtering all ``m**n``
combinations: 8 robots on 8 distinct goals gives 40,320 rows out of 16.7 million
combinations, and the construction touches only those rows (and their prefixes).

Examples
--------
>>> valid_configurations("capacity", 3, 2, capacities=[1, 2]).tolist()
[[0, 1, 1], [1, 0, 1], [1, 1, 0]]
>>> valid_configurations("allocation", 8, 8).shape
(40320, 8)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import lru_cache
from math import factorial, prod
from typing import NamedTuple

import numpy as np

from epistemica.aif._validate import positive_int
from epistemica.del_.errors import InvalidArgumentError

__all__ = [
    "FAMILIES",
    "count_configurations",
    "filter_configurations",
    "shared_configurations",
    "valid_configurations",
]


# Refuse to materialise unconstrained sets larger than this (rows).
_MAX_ROWS = 50_000_000


def _check_counts(n_robots, n_goals) -> tuple[int, int]:
    hint = "a mission needs at least one robot and one goal"
    return positive_int(n_robots, "n_robots", hint), positive_int(n_goals, "n_goals", hint)


def index_dtype(n_goals: int) -> type:
    # Small integers keep 3.6 million rows x 10 robots at 36 MB instead of 288 MB.
    return np.int8 if n_goals <= 127 else np.int32


def count_configurations(mission: str, n_robots: int, n_goals: int, capacities=None) -> int:
    """Number of valid configurations, without building them.

    Examples
    --------
    >>> count_configurations("allocation", 10, 10)
    3628800
    >>> count_configurations("capacity", 3, 2, capacities=[1, 2])
    3
    """
    n, m = _check_counts(n_robots, n_goals)
    return _family(mission).count(n, m, capacities)


def _family(mission) -> _Family:
    family = _FAMILIES.get(mission) if isinstance(mission, str) else None
    if family is None:
        raise InvalidArgumentError(
            f"unknown mission {mission!r}",
            hint=f"use one of {', '.join(repr(x) for x in FAMILIES)}",
        )
    return family


def check_capacities(capacities, n: int, m: int) -> np.ndarray:
    if capacities is None:
        raise InvalidArgumentError(
            "mission 'capacity' needs capacities",
            hint="pass capacities=[c_0, ..., c_{m-1}]: how many robots each goal needs",
        )
    caps = np.asarray(capacities)
    if caps.shape != (m,) or not np.issubdtype(caps.dtype, np.integer) or np.any(caps < 0):
        raise InvalidArgumentError(
            f"capacities must be {m} non-negative integers, got {capacities!r}",
            hint="one entry per goal: the exact number of robots that goal needs",
        )
    if int(caps.sum()) != n:
        raise InvalidArgumentError(
            f"capacities sum to {int(caps.sum())} but there are {n} robots",
            hint="every robot takes exactly one goal, so the capacities must add up to n_robots",
        )
    return caps


def _extend(rows: np.ndarray, allowed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Append every allowed goal to every row; row-major nonzero keeps lexicographic order."""
    parent, goal = np.nonzero(allowed)
    return np.column_stack([rows[parent], goal.astype(rows.dtype)]), parent


def _allocation(n: int, m: int) -> np.ndarray:
    if n > m:
        raise InvalidArgumentError(
            f"allocation needs pairwise distinct goals, but {n} robots > {m} goals",
            hint="use n_robots <= n_goals, or mission='capacity' to share goals",
        )
    _check_rows(math.perm(m, n), f"allocation of {n} robots to {m} goals")
    dtype = index_dtype(m)
    rows = np.empty((1, 0), dtype=dtype)
    used = np.zeros((1, m), dtype=bool)
    for _ in range(n):
        rows, parent = _extend(rows, ~used)
        used = used[parent]
        used[np.arange(rows.shape[0]), rows[:, -1]] = True
    return rows


def _check_rows(count: int, what: str) -> None:
    """Refuse a set of configurations too large to list (before listing any of it)."""
    if count > _MAX_ROWS:
        raise InvalidArgumentError(
            f"{what} has {count:,} configurations, too many to list (at most {_MAX_ROWS:,})",
            hint="a smaller team or fewer goals; the active-inference levels of the simulator "
            "reason over a plausible subset instead (aif: prune_from)",
        )


def _capacity(n: int, m: int, caps: np.ndarray) -> np.ndarray:
    count = math.factorial(n)
    for c in caps.tolist():
        count //= math.factorial(int(c))
    _check_rows(count, f"capacity mission of {n} robots")
    dtype = index_dtype(m)
    rows = np.empty((1, 0), dtype=dtype)
    remaining = caps[None, :].astype(np.int64)
    for _ in range(n):
        rows, parent = _extend(rows, remaining > 0)
        remaining = remaining[parent]
        remaining[np.arange(rows.shape[0]), rows[:, -1]] -= 1
    return rows


def _all(n: int, m: int) -> np.ndarray:
    if m**n > _MAX_ROWS:
        raise InvalidArgumentError(
            f"mission 'all' would materialise {m}**{n} = {m**n} rows",
            hint="use a constrained mission ('allocation', 'capacity', 'rendezvous')",
        )
    grids = np.indices((m,) * n, dtype=index_dtype(m))
    return grids.reshape(n, -1).T.copy()


def valid_configurations(
    mission: str,
    n_robots: int,
    n_goals: int,
    capacities: Sequence[int] | None = None,
    *,
    where: Callable[[np.ndarray], np.ndarray] | None = None,
) -> np.ndarray:
    """Build the valid configuration set of a mission.

    Parameters
    ----------
    mission : {"rendezvous", "allocation", "capacity", "all"}
        ``"rendezvous"``: all robots at one goal; ``"allocation"``: pairwise distinct
        goals (needs ``n_robots <= n_goals``); ``"capacity"``: goal ``g`` takes exactly
        ``capacities[g]`` robots; ``"all"``: every combination (guarded against size).
    n_robots, n_goals : int
        Team size and number of goals.
    capacities : sequence of int, optional
        Required for ``"capacity"``: one non-negative count per goal, summing to
        ``n_robots``.
    where : callable, optional
        Extra filter, see :func:`filter_configurations`.

    Returns
    -------
    numpy.ndarray
        Integer array of shape ``(k, n_robots)``, rows in lexicographic order; ``int8``
        when there are fewer than 128 goals (cast before arithmetic that could overflow).

    Raises
    ------
    InvalidArgumentError
        Unknown mission, impossible constraints, or an empty result.

    Examples
    --------
    >>> valid_configurations("rendezvous", 2, 3).tolist()
    [[0, 0], [1, 1], [2, 2]]
    >>> valid_configurations("allocation", 2, 3).tolist()
    [[0, 1], [0, 2], [1, 0], [1, 2], [2, 0], [2, 1]]
    """
    n, m = _check_counts(n_robots, n_goals)
    family = _family(mission)
    rows = family.build(n, m, capacities)
    if where is not None:
        rows = filter_configurations(rows, where)
    return rows


@lru_cache(maxsize=32)
def shared_configurations(mission: str, n_robots: int, n_goals: int) -> np.ndarray:
    """:func:`valid_configurations` of a mission without capacities, computed once and
    read-only, for the many controllers that reason over the same set.

    Examples
    --------
    >>> rows = shared_configurations("allocation", 2, 3)
    >>> rows.flags.writeable, rows is shared_configurations("allocation", 2, 3)
    (False, True)
    """
    rows = valid_configurations(mission, n_robots, n_goals)
    rows.setflags(write=False)
    return rows


def filter_configurations(
    configurations: np.ndarray, predicate: Callable[[np.ndarray], np.ndarray]
) -> np.ndarray:
    """Keep the rows for which a vectorised predicate holds.

    Parameters
    ----------
    configurations : numpy.ndarray
        ``(k, n)`` integer array.
    predicate : callable
        Takes the whole ``(k, n)`` array and returns a boolean mask of length ``k``.

    Examples
    --------
    >>> rows = valid_configurations("allocation", 2, 3)
    >>> filter_configurations(rows, lambda c: c[:, 0] != 2).tolist()
    [[0, 1], [0, 2], [1, 0], [1, 2]]
    """
    rows = np.asarray(configurations)
    if rows.ndim != 2 or not np.issubdtype(rows.dtype, np.integer):
        raise InvalidArgumentError(
            f"configurations must be a 2-D integer array, got shape {rows.shape}",
            hint="build them with valid_configurations(...)",
        )
    mask = np.asarray(predicate(rows))
    if mask.shape != (rows.shape[0],) or mask.dtype != bool:
        raise InvalidArgumentError(
            f"the filter returned shape {mask.shape} ({mask.dtype}), "
            f"expected ({rows.shape[0]},) bool",
            hint="write the filter on the whole array, e.g. lambda c: c[:, 0] != c[:, 1]",
        )
    kept = rows[mask]
    if kept.shape[0] == 0:
        raise InvalidArgumentError(
            "no configuration satisfies the filter",
            hint="an empty valid set leaves nothing to believe in; relax the filter",
        )
    return kept


class _Family(NamedTuple):
    """A family of configurations: how many there are, and how to build them, for ``n``
    robots, ``m`` goals and (capacity) the capacities."""

    count: Callable[[int, int, object], int]
    build: Callable[[int, int, object], np.ndarray]


def _count_capacity(n: int, m: int, capacities) -> int:
    caps = check_capacities(capacities, n, m)
    return factorial(n) // prod(factorial(int(c)) for c in caps)


#: Family name -> how to count and build it: the one table of configuration families.
_FAMILIES: dict[str, _Family] = {
    "rendezvous": _Family(
        lambda n, m, caps: m,
        lambda n, m, caps: np.repeat(np.arange(m, dtype=index_dtype(m))[:, None], n, axis=1),
    ),
    "allocation": _Family(
        lambda n, m, caps: factorial(m) // factorial(m - n) if n <= m else 0,
        lambda n, m, caps: _allocation(n, m),
    ),
    "capacity": _Family(
        _count_capacity, lambda n, m, caps: _capacity(n, m, check_capacities(caps, n, m))
    ),
    "all": _Family(lambda n, m, caps: m**n, lambda n, m, caps: _all(n, m)),
}
#: The configuration families understood by :func:`valid_configurations` (the simulator's
#: goal-mission kinds use the first three: :mod:`epistemica.sim.kinds`).
FAMILIES: tuple[str, ...] = tuple(_FAMILIES)
