"""Task missions: places that are done once, rather than goals the team holds.

- ``multitask``: any robot reaching a task does it; an upper level
  (:mod:`epistemica.sim.policies.tasking`) re-chooses which tasks the team goes for;
- ``collaborative``: task ``t`` is done when ``needs[t]`` robots stand at it at once; tasks
  are found while exploring (:mod:`epistemica.sim.kinds.collaborative`).

Neither has a fixed set of configurations: asking for one is an error that says why.

Examples
--------
>>> MULTITASK.default_goals(4), COLLABORATIVE.tasks
(20, True)
>>> MULTITASK.count(3, 20)
0
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.kinds.base import GOAL_PANELS, JOINT_PANELS

__all__ = ["COLLABORATIVE", "MULTITASK", "TaskKind"]


@dataclass(frozen=True)
class TaskKind:
    """A task mission (see the module docstring)."""

    name: str
    goals: int | None
    why: str
    paper: tuple[tuple[str, float], ...] | None = None
    study_levels: tuple[str, ...] = ("zero", "convention", "rules-third", "first", "third")
    trace_kind: str | None = None
    panels: tuple[str, ...] = GOAL_PANELS
    tasks: bool = True
    joint: bool = False
    gathers: bool = False
    distinct: bool = False
    capacities: bool = False

    def __str__(self) -> str:
        return self.name

    def __repr__(self) -> str:
        return f"<mission kind {self.name}>"

    def default_goals(self, robots: int) -> int:
        return robots if self.goals is None else self.goals

    def count(self, robots: int, goals: int, capacities: Sequence[int] | None = None) -> int:
        return 0

    def configurations(
        self, robots: int, goals: int, capacities: Sequence[int] | None = None
    ) -> np.ndarray:
        raise InvalidArgumentError(
            f"a {self.name} mission has no fixed configuration set", hint=self.why
        )

    def holds(self, positions, goals, radius, capacities=None) -> bool:
        raise InvalidArgumentError(
            f"a {self.name} mission is done task by task, it does not hold at one instant",
            hint=self.why,
        )

    def cheapest(self, cost, goals, capacities=None, robot=None) -> np.ndarray:
        raise InvalidArgumentError(
            f"a {self.name} mission has no configuration of least cost", hint=self.why
        )

    def admits(self, pins: dict[int, int], goal: int) -> bool:
        return True


MULTITASK = TaskKind(
    "multitask",
    goals=20,
    paper=(("max_steps", 150), ("max_turn", math.pi / 4)),
    why="its configurations are re-chosen every step (epistemica.sim.policies.tasking)",
)
COLLABORATIVE = TaskKind(
    "collaborative",
    goals=None,
    why="its tasks are found while exploring and done by several robots at once",
    joint=True,
    study_levels=("convention", "rules-first", "rules", "first", "third", "oracle"),
    trace_kind="collaborative",
    panels=JOINT_PANELS,
)
