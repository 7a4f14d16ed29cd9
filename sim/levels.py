"""The reasoning levels: one table from a level's name to the policy that plays it.

Every list of levels (the command line's ``--reasoning`` and ``--levels``, a mission's
``levels`` and ``teammate`` lines, the reports) comes from :data:`LEVELS`. A level is a
policy class with the settings that define it; ``make_policy(name, parameters)`` builds a
fresh one, the active-inference levels taking the mission's
:class:`~epistemica.sim.parameters.ActiveParameters` (the level's own settings, such as
``nested=False`` for ``third-shared``, always win).

Examples
--------
>>> make_policy("third-shared").parameters.nested
False
>>> make_policy("third", ActiveParameters(lone_wait=40)).parameters.lone_wait
40
>>> "convention-reverse" in REASONING
True
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.active import ORDERS, ActiveInference
from epistemica.sim.baselines import Convention, Greedy, Stationary
from epistemica.sim.paper import PAPER_LEVELS, PaperPolicy
from epistemica.sim.parameters import ActiveParameters
from epistemica.sim.policy import Policy

__all__ = ["LEVELS", "REASONING", "Level", "make_policy"]


class Level(NamedTuple):
    """A level: what it is, and how to build its policy from the active parameters."""

    description: str
    build: Callable[[ActiveParameters], Policy]


def _active(order: int, **settings) -> Callable[[ActiveParameters], Policy]:
    return lambda parameters: ActiveInference(order, parameters.replace(**settings))


def _named(name: str, build: Callable[[ActiveParameters], Policy]):
    """``build`` with the policy renamed (a level defined by its settings)."""

    def named(parameters: ActiveParameters) -> Policy:
        policy = build(parameters)
        policy.name = name
        return policy

    return named


def _table() -> dict[str, Level]:
    levels = {
        "zero": Level("greedy: the nearest goal it knows", lambda p: Greedy()),
        "convention": Level(
            "least total distance from its own view (a shared convention)",
            lambda p: Convention(),
        ),
    }
    for name, order in ORDERS.items():
        levels[name] = Level(f"active inference at order {order}", _active(order))
    for name, order in ORDERS.items():
        levels[f"{name}-unpruned"] = Level(
            f"order {order}, ignoring observed events (ablation)", _active(order, pruning=False)
        )
    for name, order in list(ORDERS.items())[1:]:
        levels[f"{name}-shared"] = Level(
            f"order {order}, every teammate taken to have seen what it saw (ablation)",
            _active(order, nested=False),
        )
    for name, order in ORDERS.items():
        levels[f"{name}-priormode"] = Level(
            f"order {order}, straight to the prior's most probable configuration (ablation "
            "of expected free energy)",
            _active(order, free_energy=False),
        )
    levels["convention+rules"] = Level(
        "the convention on the common view with every rule of the active levels (search, "
        "exploration, pruning), no inference",
        _named("convention+rules", _active(2, free_energy=False, nested=False, anticipate=False)),
    )
    levels["convention-reverse"] = Level(
        "the convention with the opposite tie-break (an ad hoc teammate)",
        lambda p: Convention(tie_break="reverse"),
    )
    levels["stationary"] = Level(
        "stops on a goal drawn at random at its first step and never leaves it (an ad hoc "
        "teammate)",
        lambda p: Stationary(),
    )
    for name in PAPER_LEVELS:
        levels[name] = Level(
            "the authors' released algorithm", lambda p, name=name: PaperPolicy(name)
        )
    return levels


#: Level name -> :class:`Level`.
LEVELS: dict[str, Level] = _table()
#: The level names, in the order of :data:`LEVELS`.
REASONING: tuple[str, ...] = tuple(LEVELS)


def make_policy(name: str | Policy, parameters: ActiveParameters | None = None) -> Policy:
    """A fresh policy for a level name (a :class:`Policy` is returned as it is).

    Examples
    --------
    >>> make_policy("third").order
    3
    """
    if isinstance(name, Policy):
        return name
    level = LEVELS.get(name) if isinstance(name, str) else None
    if level is None:
        raise InvalidArgumentError(
            f"unknown reasoning level {name!r}",
            hint=f"use one of {', '.join(REASONING)}, or pass a Policy object",
        )
    return level.build(ActiveParameters() if parameters is None else parameters)
