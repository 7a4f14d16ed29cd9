"""The one registry of mission kinds: name -> kind object.

Every list of mission kinds (the mission grammar's check, the command line, the reports)
comes from :data:`KINDS`; nothing else compares a mission's name.

Examples
--------
>>> list(KINDS)
['rendezvous', 'allocation', 'capacity', 'multitask', 'collaborative']
>>> kind_named("rendezvous").gathers
True
>>> kind_named("relay")
Traceback (most recent call last):
    ...
epistemica.del_.errors.InvalidArgumentError: unknown mission kind 'relay'
hint: use one of rendezvous, allocation, capacity, multitask, collaborative
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.goal import ALLOCATION, CAPACITY, RENDEZVOUS
from epistemica.sim.kinds.tasks import COLLABORATIVE, MULTITASK

__all__ = ["KINDS", "PAPER_KINDS", "kind_named", "kind_of_trace", "mission_holds"]

#: Mission kind name -> kind, in the order the docs list them.
KINDS: dict[str, MissionKind] = {
    kind.name: kind for kind in (RENDEZVOUS, ALLOCATION, CAPACITY, MULTITASK, COLLABORATIVE)
}
#: The kinds the published protocol draws (``Scenario.paper``).
PAPER_KINDS: tuple[str, ...] = tuple(name for name, kind in KINDS.items() if kind.paper is not None)


def kind_named(name: str | MissionKind) -> MissionKind:
    """The kind called ``name`` (a kind is returned as it is)."""
    if isinstance(name, MissionKind) and not isinstance(name, str):
        return name
    kind = KINDS.get(name) if isinstance(name, str) else None
    if kind is None:
        raise InvalidArgumentError(
            f"unknown mission kind {name!r}", hint=f"use one of {', '.join(KINDS)}"
        )
    return kind


def kind_of_trace(trace: Mapping[str, Any]) -> MissionKind:
    """The kind of the trial a trace (:mod:`epistemica.sim.study.trace`) records, as far as
    its picture goes: the first kind whose ``trace_kind`` is the trace's ``kind`` field
    (absent: a goal trial's trace; every kind writing one draws the same panels).

    Examples
    --------
    >>> kind_of_trace({"kind": "collaborative"}).joint, kind_of_trace({}).panels[0]
    (True, 'knowledge')
    >>> kind_of_trace({"kind": "relay"})
    Traceback (most recent call last):
        ...
    epistemica.del_.errors.InvalidArgumentError: a trace of an unknown kind 'relay'
    hint: traces are written by epistemica.sim.study.trace; kinds: collaborative
    """
    field = trace.get("kind")
    for kind in KINDS.values():
        if kind.trace_kind == field:
            return kind
    written = ", ".join(k.trace_kind for k in KINDS.values() if k.trace_kind is not None)
    raise InvalidArgumentError(
        f"a trace of an unknown kind {field!r:.40}",
        hint=f"traces are written by epistemica.sim.study.trace; kinds: {written}",
    )


def mission_holds(
    mission: str | MissionKind,
    positions: np.ndarray,
    goals: np.ndarray,
    radius: float,
    capacities: Sequence[int] | None = None,
) -> bool:
    """Whether robots at ``positions`` satisfy the goal mission ``mission`` right now.

    Examples
    --------
    >>> goals = np.array([[0.0, 0.0], [10.0, 0.0]])
    >>> mission_holds("capacity", np.array([[0, 0], [10, 0], [10, 1.0]]), goals, 5 / 3,
    ...               capacities=[1, 2])
    True
    """
    return kind_named(mission).holds(positions, goals, radius, capacities)
