"""The memory budget of the explicit backend, and its size estimates.

The explicit backend enumerates worlds: a model built from ``n`` observable atoms is a
bitset of ``2^n`` bits per truth set, and its compact arrays (valuation matrix, one label
per world and agent) take ``2^n * (n + 8 * agents)`` bytes. Before anything that large is
allocated, :func:`require` compares the estimate with the budget in force and refuses
with a :class:`MemoryBudgetError` naming the size and the symbolic backend.

The budget in force is :data:`DEFAULT_MEMORY_BUDGET` (a module-level default, read at
every check, so assigning it changes later checks) unless a caller narrows or widens it
for a block with :func:`budget_scope` (what the ``memory_budget=`` keywords of
:func:`~epistemica.del_.evaluate` and :class:`~epistemica.del_.KripkeModel`
do).

Examples
--------
>>> with budget_scope(2**20):
...     require(2**19, "a small table")
...     try:
...         require(2**30, "a truth set")
...     except MemoryBudgetError as error:
...         print(str(error).splitlines()[0])
a truth set needs about 1.0 GiB, over the memory budget of 1.0 MiB
"""

from __future__ import annotations

import contextlib
import contextvars
import math
from collections.abc import Callable, Iterator

from epistemica.del_.errors import EpistemicaError

__all__ = [
    "DEFAULT_MEMORY_BUDGET",
    "MemoryBudgetError",
    "budget_scope",
    "current_budget",
    "estimate_explicit_bytes",
    "require",
]

# A few GiB: enough for bitsets of 2^30 worlds, refused well before a laptop swaps.
DEFAULT_MEMORY_BUDGET = 4 * 2**30

_SCOPED: contextvars.ContextVar[int | None] = contextvars.ContextVar("budget", default=None)


class MemoryBudgetError(EpistemicaError):
    """An explicit-backend computation would allocate more than the memory budget."""


def current_budget() -> int:
    """The budget in force, in bytes: the innermost :func:`budget_scope`, else the default."""
    scoped = _SCOPED.get()
    return DEFAULT_MEMORY_BUDGET if scoped is None else scoped


@contextlib.contextmanager
def budget_scope(n_bytes: int | None) -> Iterator[None]:
    """Run a block under another budget (``None`` keeps the one in force)."""
    if n_bytes is None:
        yield
        return
    if n_bytes <= 0:
        raise EpistemicaError(
            f"a memory budget must be positive, got {n_bytes}", hint="give a size in bytes"
        )
    token = _SCOPED.set(int(n_bytes))
    try:
        yield
    finally:
        _SCOPED.reset(token)


def _gib_at_least(n_bytes: float) -> str:
    """``n_bytes`` in GiB, rounded up at three significant digits: a ``--memory-budget``
    that covers it (rounding to nearest could name the budget just refused).

    >>> _gib_at_least(2**30 * 0.0010004), _gib_at_least(2**30 * 5.3), _gib_at_least(2**40)
    ('0.00101', '5.30', '1030')
    """
    gib = n_bytes / 2**30
    if gib <= 0:
        return "0"
    digits = 2 - math.floor(math.log10(gib))
    rounded = math.ceil(gib * 10**digits - 1e-9) / 10**digits
    return f"{rounded:.{max(digits, 0)}f}"


def _size(n_bytes: float) -> str:
    for unit, scale in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if n_bytes >= scale:
            return f"{n_bytes / scale:.1f} {unit}"
    return f"{int(n_bytes)} bytes"


def require(n_bytes: float, what: str | Callable[[], str]) -> None:
    """Refuse, before allocating, what would exceed the budget in force.

    ``what`` names the allocation in the message; a function giving that name is called
    only on refusal (for callers on hot paths).

    Raises
    ------
    MemoryBudgetError
        If ``n_bytes`` is more than :func:`current_budget`.
    """
    budget = current_budget()
    if n_bytes > budget:
        what = what() if callable(what) else what
        raise MemoryBudgetError(
            f"{what} needs about {_size(n_bytes)}, over the memory budget of {_size(budget)}",
            hint="use the symbolic backend (`--backend symbolic`, or "
            "KripkeModel.to_symbolic()), or raise the memory budget (`--memory-budget GIB`, "
            f"at least {_gib_at_least(n_bytes)} here)",
        )


def estimate_explicit_bytes(
    n_atoms: int, n_agents: int, *, live_sets: int = 8, materialize: bool = False
) -> int:
    """Estimated peak bytes of the explicit backend on a model from ``n_atoms`` observables.

    Checking on bitsets holds about ``live_sets`` truth sets of ``2^n / 8`` bytes at once
    (the evaluator frees what a finished subformula no longer needs); ``materialize``
    adds the compact arrays (valuation, codes, one label per world and agent), which
    listing worlds and product updates with events that are not public announcements need.

    Examples
    --------
    >>> estimate_explicit_bytes(24, 24) / 2**20
    16.0
    >>> estimate_explicit_bytes(24, 24, materialize=True) // 2**20
    3616
    """
    worlds = 1 << n_atoms
    total = live_sets * max(8, worlds // 8)
    if materialize:
        total += worlds * (n_atoms + 8 + 8 * n_agents + 1)
    return total
