"""The one BDD manager of the process and its variables (oxidd).

Every structure numbers its state variables by *slots* ``0, 1, 2, ...``; slot ``s`` is the
BDD variable ``2 s`` and its primed copy (the target of a relation) is ``2 s + 1``, so each
variable sits next to its copy in the order, which keeps relations small. Slots are reused
by unrelated structures: a BDD is only ever combined with BDDs of its own structure.

oxidd is imported when the first BDD is made (or ``AND``, ``IMP``, ``BDDFunction`` are
first read), so that commands on explicit models never pay for it.
"""

from __future__ import annotations

import contextlib
import functools
from collections.abc import Iterable, Iterator, Sequence
from typing import TYPE_CHECKING, Any

from epistemica.del_.errors import EpistemicaError

if TYPE_CHECKING:
    from oxidd.bdd import BDDFunction, BDDManager

__all__ = [
    "BDDFunction",
    "count",
    "cube",
    "false",
    "minterm",
    "node_limit",
    "prime",
    "primed",
    "substitution",
    "true",
    "var",
]


def __getattr__(name: str) -> Any:
    """``AND`` and ``IMP`` (oxidd's operators) and ``BDDFunction``, importing oxidd."""
    if name in ("AND", "IMP"):
        from oxidd.util import BooleanOperator

        return getattr(BooleanOperator, name)
    if name == "BDDFunction":
        from oxidd.bdd import BDDFunction

        return BDDFunction
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# Inner-node capacity is an upper bound (memory is taken as nodes are made). oxidd does
# not collect garbage by itself here, so every evaluation starts by collecting once the
# manager holds more than _COLLECT_ABOVE nodes (those of live BDDs are kept).
_NODE_CAPACITY = 1 << 26
_CACHE_CAPACITY = 1 << 20
_COLLECT_ABOVE = 1 << 22


@functools.cache
def manager() -> BDDManager:
    """The process-wide manager (created on first use)."""
    from oxidd.bdd import BDDManager

    return BDDManager(_NODE_CAPACITY, _CACHE_CAPACITY, 1)


@contextlib.contextmanager
def node_limit() -> Iterator[None]:
    """Collect garbage if the manager is large; turn running out of nodes into an
    :class:`EpistemicaError`."""
    from oxidd.util import DDMemoryError

    if manager().approx_num_inner_nodes() > _COLLECT_ABOVE:
        manager().gc()
    try:
        yield
    except DDMemoryError:
        raise EpistemicaError(
            f"the BDDs outgrew the node limit ({_NODE_CAPACITY:,} nodes)",
            hint="the formula or action is too large for the symbolic backend; simplify it",
        ) from None


def _ensure(slot: int) -> None:
    m = manager()
    missing = 2 * (slot + 1) - m.num_vars()
    if missing > 0:
        m.add_vars(missing)


def reserve(slots: Iterable[int]) -> None:
    """Make the manager hold the variables (and primed copies) of ``slots``."""
    top = max(slots, default=-1)
    if top >= 0:
        _ensure(top)


def count(f: BDDFunction, slots: Sequence[int]) -> int:
    """The number of assignments to ``slots`` satisfying ``f`` (whose support lies in them).

    oxidd counts over the first ``n`` variables of the manager; every other variable
    doubles the count, so the count over the manager's variables is shifted back by
    their number. The slots' variables are created first, so the shift is never negative.

    Examples
    --------
    >>> count(var(3) | var(5), [3, 5, 9])
    6
    """
    reserve(slots)
    n_vars = manager().num_vars()
    return f.sat_count(n_vars) >> (n_vars - len(set(slots)))


def var(slot: int) -> BDDFunction:
    """The BDD of state variable ``slot``."""
    _ensure(slot)
    return manager().var(2 * slot)


def prime(slot: int) -> BDDFunction:
    """The BDD of the primed copy of ``slot``."""
    _ensure(slot)
    return manager().var(2 * slot + 1)


def true() -> BDDFunction:
    return manager().true()


def false() -> BDDFunction:
    return manager().false()


def cube(slots: Iterable[int], primed_copy: bool = False) -> BDDFunction:
    """The conjunction of the variables of ``slots`` (a set to quantify over)."""
    result = true()
    for s in sorted(slots, reverse=True):
        result = (prime(s) if primed_copy else var(s)) & result
    return result


def minterm(slots: Sequence[int], value: int, primed_copy: bool = False) -> BDDFunction:
    """``slots`` read as a binary number (first slot most significant) equals ``value``."""
    result = true()
    n = len(slots)
    for i, s in enumerate(slots):
        literal = prime(s) if primed_copy else var(s)
        bit = (value >> (n - 1 - i)) & 1
        result &= literal if bit else ~literal
    return result


def substitution(pairs: list[tuple[int, BDDFunction]]) -> Any:
    """oxidd's substitution of the BDD variables ``pairs[i][0]`` by ``pairs[i][1]``."""
    from oxidd.bdd import BDDFunction

    return BDDFunction.make_substitution(pairs)


@functools.lru_cache(maxsize=256)
def _renaming(slots: tuple[int, ...]):
    m = manager()
    return substitution([(2 * s, m.var(2 * s + 1)) for s in slots])


def primed(f: BDDFunction, slots: Sequence[int]) -> BDDFunction:
    """``f`` with every variable of ``slots`` replaced by its primed copy."""
    for s in slots:
        _ensure(s)
    return f.substitute(_renaming(tuple(sorted(slots))))
