"""What a kind of mission is: the protocol every kind implements.

A mission's kind says what the team is asked to do with the places it is given: gather at one
goal, take one goal each, fill each goal to its capacity, visit tasks, or do tasks that need
several robots at once. Everything that depends on the kind is a method or an attribute of
its object, so that no module compares a mission's name; adding a kind touches its module,
the registry (:mod:`epistemica.sim.kinds.registry`), the mission grammar and the docs.

Examples
--------
>>> from epistemica.sim.kinds.registry import kind_named
>>> allocation = kind_named("allocation")
>>> allocation.configurations(2, 2).tolist(), allocation.tasks
([[0, 1], [1, 0]], False)
>>> kind_named("multitask").tasks, kind_named("multitask").default_goals(3)
(True, 20)
>>> kind_named("collaborative").panels
('targets', 'tasks_known', 'teammates_known', 'events')
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol, runtime_checkable

import numpy as np

__all__ = ["GOAL_PANELS", "JOINT_PANELS", "MissionKind"]

#: The panels beside the map of a goal trial's figure and page (goal and multitask
#: missions): what each robot knows of (and what the focus robot takes its teammates to
#: know), each robot's belief, the configuration-set sizes, the events.
GOAL_PANELS = ("knowledge", "belief", "sets", "events")
#: The panels of a joint trial's: what each robot steers to, the tasks each robot knows of
#: (since when, how), what a chosen robot knows each teammate knows, the events.
JOINT_PANELS = ("targets", "tasks_known", "teammates_known", "events")


@runtime_checkable
class MissionKind(Protocol):
    """A kind of mission.

    Attributes
    ----------
    name : str
        The kind's name in mission files (``mission NAME``) and in results tables.
    tasks : bool
        Its places are tasks, each done once by robots reaching it (multitask,
        collaborative), rather than goals the team must hold at once.
    joint : bool
        Its tasks need several robots at once and are found while exploring
        (collaborative): its trials run in the collaborative loop, its levels are the
        collaborative ones.
    gathers : bool
        Every robot goes to the same goal (a rendezvous): a robot that waited in vain may
        go and look for the rest.
    distinct : bool
        No two robots may share a goal (an allocation).
    capacities : bool
        Its goals carry capacities (how many robots each needs).
    paper : tuple of (str, number) pairs, or None
        The :class:`~epistemica.sim.engine.scenario.Scenario` fields of the published
        protocol's trials of this kind (``Scenario.paper``); ``None``: it draws none.
    study_levels : tuple of str
        The levels a mission file of this kind studies when it names none.
    trace_kind : str or None
        The ``kind`` field of its trials' traces (``None``: goal-mission traces, which
        carry beliefs and configuration sets).
    panels : tuple of str
        The panels a picture of one of its trials draws beside the map, in order
        (:data:`GOAL_PANELS`, :data:`JOINT_PANELS`): the animation
        (:mod:`epistemica.sim.study.figures`) and the replay page (``epistemica view``)
        draw those; kinds with the same ``trace_kind`` have the same panels.
    """

    name: str
    tasks: bool
    joint: bool
    gathers: bool
    distinct: bool
    capacities: bool
    paper: tuple[tuple[str, float], ...] | None
    study_levels: tuple[str, ...]
    trace_kind: str | None
    panels: tuple[str, ...]

    def default_goals(self, robots: int) -> int:
        """How many goals (tasks) a generated trial has for ``robots`` robots."""
        ...

    def count(self, robots: int, goals: int, capacities: Sequence[int] | None = None) -> int:
        """How many valid configurations there are (0 for a task kind)."""
        ...

    def configurations(
        self, robots: int, goals: int, capacities: Sequence[int] | None = None
    ) -> np.ndarray:
        """The valid configurations, ``(k, robots)`` goal indices; an error for a kind with
        no fixed configuration set."""
        ...

    def holds(
        self,
        positions: np.ndarray,
        goals: np.ndarray,
        radius: float,
        capacities: Sequence[int] | None = None,
    ) -> bool:
        """Whether robots at ``positions`` satisfy the mission right now."""
        ...

    def cheapest(
        self,
        cost: np.ndarray,
        goals: np.ndarray,
        capacities: Sequence[int] | None = None,
        robot: int | None = None,
    ) -> np.ndarray:
        """The configuration of least total cost over ``goals`` (indices), ``cost`` being
        ``(n, len(goals))``: -1 for a robot left without a goal, except ``robot``, which
        then takes its nearest goal (slot)."""
        ...

    def admits(self, pins: dict[int, int], goal: int) -> bool:
        """Whether another robot may be pinned to ``goal`` given ``pins`` (robot -> goal)
        already known, newest first."""
        ...
