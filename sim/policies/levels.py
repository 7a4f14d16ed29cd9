"""The reasoning levels: one registry, keyed by mission kind, from a level's name to the
policy that plays it.

Every list of levels (the command line's ``--reasoning`` and ``--levels``, a mission's
``levels`` and ``teammate`` lines, the reports, the environment) comes from
:data:`KIND_LEVELS`: for each kind of :data:`~epistemica.sim.kinds.registry.KINDS`, its table
of levels. Goal and multitask missions share :data:`LEVELS`; joint (collaborative) missions
have theirs, :data:`JOINT_LEVELS`. A level is a policy class with the settings that define
it; ``make_level(kind, name, parameters)`` builds a fresh one, the levels taking the
mission's parameters (:func:`parameters_for`:
:class:`~epistemica.sim.policies.parameters.ActiveParameters` or
:class:`~epistemica.sim.policies.collaborative_levels.CollaborativeParameters`; the
level's own settings, such as ``nested=False`` for ``third-shared``, always win).

Examples
--------
>>> make_policy("third-shared").parameters.nested, make_policy("third").parameters.planning
(False, True)
>>> make_policy("rules-third").parameters.planning
False
>>> make_policy("third", ActiveParameters(lone_wait=40)).parameters.lone_wait
40
>>> "convention-reverse" in REASONING
True
>>> level_names("collaborative")[:4]
('convention', 'rules-first', 'rules-shared', 'rules')
>>> make_level("collaborative", "oracle").shares
'everything'
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.registry import KINDS, kind_named
from epistemica.sim.policies.active import ORDERS, ActiveInference
from epistemica.sim.policies.baselines import Convention, Greedy, Stationary
from epistemica.sim.policies.collaborative_levels import (
    COLLABORATIVE_LEVELS,
    CollaborativePolicy,
)
from epistemica.sim.policies.collaborative_parameters import CollaborativeParameters
from epistemica.sim.policies.collaborative_planning import (
    PLANNING_LEVELS,
    PlanningCollaborativePolicy,
)
from epistemica.sim.policies.oracle import Oracle
from epistemica.sim.policies.paper import PAPER_LEVELS, PaperPolicy
from epistemica.sim.policies.parameters import ActiveParameters
from epistemica.sim.policies.policy import Policy

__all__ = [
    "JOINT_LEVELS",
    "KIND_LEVELS",
    "LEVELS",
    "REASONING",
    "Level",
    "level_names",
    "make_level",
    "make_policy",
    "parameters_for",
    "rules_level",
]


class Level(NamedTuple):
    """A level: what it is, and how to build its policy from the active parameters."""

    description: str
    build: Callable[[Any], Any]


def _active(order: int, **settings) -> Callable[[ActiveParameters], Policy]:
    return lambda parameters: ActiveInference(order, parameters.replace(**settings))


def _named(name: str, build: Callable[[ActiveParameters], Policy]):
    """``build`` with the policy renamed (a level defined by its settings)."""

    def named(parameters: ActiveParameters) -> Policy:
        policy = build(parameters)
        policy.name = name
        return policy

    return named


def _orders(levels: dict[str, Level], prefix: str, what: str, planning: bool) -> None:
    """Register one controller's levels: each order, and its ablations, under ``prefix``."""
    for name, order in ORDERS.items():
        levels[f"{prefix}{name}"] = Level(
            f"{what} at order {order}", _active(order, planning=planning)
        )
    for name, order in ORDERS.items():
        levels[f"{prefix}{name}-unpruned"] = Level(
            f"{what} at order {order}, ignoring observed events (ablation)",
            _active(order, planning=planning, pruning=False),
        )
    for name, order in list(ORDERS.items())[1:]:
        levels[f"{prefix}{name}-shared"] = Level(
            f"{what} at order {order}, every teammate taken to have seen what it saw (ablation)",
            _active(order, planning=planning, nested=False),
        )


def _table() -> dict[str, Level]:
    levels = {
        "zero": Level("greedy: the nearest goal it knows", lambda p: Greedy()),
        "convention": Level(
            "least total distance from its own view (a shared convention)",
            lambda p: Convention(),
        ),
    }
    _orders(
        levels,
        "rules-",
        "the rules' one-step controller (expected free energy over the next control, with "
        "the search, anchoring and anticipation rules; the first/second/third of before "
        "issue 37)",
        planning=False,
    )
    _orders(
        levels,
        "",
        "the planning controller (options scored by expected free energy over teammates' "
        "choices predicted one order down, epistemica.aif.planning)",
        planning=True,
    )
    for name, order in ORDERS.items():
        levels[f"{name}-priormode"] = Level(
            f"order {order}, the same beliefs, no planning: straight to the prior's most "
            "probable configuration (ablation of expected free energy; the planner and the "
            "rules play the same trial)",
            _active(order, planning=True, free_energy=False),
        )
    levels["third-wait"] = Level(
        "the planning controller at order 3 with a waiting option over a 3-step horizon "
        "(wait, read the teammates' moves, then choose)",
        _active(3, planning=True, plan_horizon=3),
    )
    levels["convention+rules"] = Level(
        "the convention on the common view with every rule of the rules' levels (search, "
        "exploration, pruning), no inference",
        _named("convention+rules", _active(2, free_energy=False, nested=False, anticipate=False)),
    )
    levels["convention-reverse"] = Level(
        "the convention with the opposite tie-break (an ad hoc teammate)",
        lambda p: Convention(tie_break="reverse"),
    )
    levels["oracle"] = Level(
        "full communication: every pose exact, every goal and closure known, the "
        "configuration of least makespan (a reference for completion time, not a teammate)",
        lambda p: Oracle(),
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

_JOINT_DESCRIPTIONS = {
    "convention": "the sweep convention, a task done by whoever finds it with enough robots",
    "rules-first": "the rules at first order: tasks it knows of, teammates as it sees them "
    "(first before issue 37)",
    "rules-shared": "every rule of rules, every teammate taken to know what it knows "
    "(ablation; third-shared before issue 37)",
    "rules": "the rules over who knows which task, nested: fetching and waiting by what "
    "teammates know, about twenty hand-written rules (third before issue 37)",
    "oracle": "the rules' level with full communication (news and places): an upper bound",
    "oracle-events": "the rules' level with every event and sighting shared, places not",
    "recruit": "the rules' first-order choice of task, fetching any recently seen teammate "
    "to it (baseline)",
    "convention+rules": "every rule of the rules' level, no knowledge of which teammates know "
    "(baseline)",
    "first": "the planning controller at order 1 on first-order knowledge: options "
    "(go to a task, fetch a teammate, explore) scored by expected time saved "
    "(epistemica.aif.task_planning)",
    "second": "the planning controller at order 2 over who knows which task, nested",
    "third": "the planning controller at order 3: teammates predicted one order down "
    "over what it knows they know",
    "third-shared": "the planning controller at order 3, every teammate taken to know "
    "what it knows (ablation of the nested ledger)",
    "third-priormode": "the planning controller's beliefs, no planning: the nearest open "
    "task it knows of (ablation of expected free energy)",
}


def _joint(name: str) -> Level:
    description = _JOINT_DESCRIPTIONS.get(name, f"the collaborative level {name}")
    policy = PlanningCollaborativePolicy if name in PLANNING_LEVELS else CollaborativePolicy
    return Level(description, lambda p: policy(name, p))


#: The levels of joint (collaborative) missions: name -> :class:`Level` (the rules' levels,
#: then the planning controller's).
JOINT_LEVELS: dict[str, Level] = {
    name: _joint(name) for name in (*COLLABORATIVE_LEVELS, *PLANNING_LEVELS)
}
#: Mission kind name -> its levels (name -> :class:`Level`): the one registry.
KIND_LEVELS: dict[str, dict[str, Level]] = {
    name: JOINT_LEVELS if kind.joint else LEVELS for name, kind in KINDS.items()
}


def level_names(kind: str | MissionKind) -> tuple[str, ...]:
    """The names of the levels that play missions of ``kind``, in the registry's order."""
    return tuple(KIND_LEVELS[kind_named(kind).name])


def rules_level(kind: str | MissionKind) -> str:
    """The rules' highest level of ``kind`` (``rules-third``; ``rules`` on joint missions):
    the teammates of an environment by default, the level its measured results name.

    Examples
    --------
    >>> rules_level("rendezvous"), rules_level("collaborative")
    ('rules-third', 'rules')
    """
    return "rules" if kind_named(kind).joint else "rules-third"


def parameters_for(kind: str | MissionKind) -> type:
    """The parameter type of ``kind``'s levels (a mission's ``policy`` line sets one)."""
    return CollaborativeParameters if kind_named(kind).joint else ActiveParameters


def make_level(kind: str | MissionKind, name, parameters=None):
    """A fresh policy for the level ``name`` of missions of ``kind`` (a
    :class:`~epistemica.sim.policies.policy.Policy` is returned as it is: a traced
    planning level, :class:`PlanningCollaborativePolicy` with ``trace=True``).

    Examples
    --------
    >>> make_level("allocation", "third").order
    3
    """
    kind = kind_named(kind)
    if not kind.joint or isinstance(name, Policy):
        return make_policy(name, parameters)
    table = KIND_LEVELS[kind.name]
    level = table.get(name) if isinstance(name, str) else None
    if level is None:
        raise InvalidArgumentError(
            f"unknown {kind} level {name!r}", hint=f"use one of {', '.join(table)}"
        )
    return level.build(CollaborativeParameters() if parameters is None else parameters)


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
