"""The world of a collaborative mission: tasks found while exploring, each needing several
robots at once.

Tasks lie at places unknown at the start; task ``t`` is done the first step ``needs[t]``
robots are within the completion radius of it at once. Typical observation events
(:mod:`epistemica.sim.engine.events`): a task *found* (seen by the robots that see the
finder), a robot *waiting* at a task or *heading* to it (seen by the robots that see it), a
task *done* (seen by those that see the robots that did it). Its trials run in the one loop,
:func:`~epistemica.sim.engine.simulate.simulate`, over the joint run
(:mod:`epistemica.sim.engine.joint`: perception and the task ledger); its levels are in
:mod:`epistemica.sim.policies.collaborative_levels`.

The same seed gives the same tasks, starts and process noise for every level.

Examples
--------
>>> from epistemica.sim import simulate
>>> s = CollaborativeScenario.drawn(robots=3, needs=(2, 2), seed=1)
>>> s.n_robots, s.n_tasks, s.needs, s.kind.name
(3, 2, (2, 2), 'collaborative')
>>> simulate(s, "convention", seed=1).tasks_done.shape
(2,)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine.draws import draw_layout
from epistemica.sim.engine.events import EventRule
from epistemica.sim.kinds.tasks import COLLABORATIVE, TaskKind

__all__ = ["CollaborativeScenario"]


@dataclass(frozen=True)
class CollaborativeScenario:
    """A collaborative mission's world, validated when built.

    Parameters
    ----------
    starts : array_like
        ``(n, 2)`` or ``(n, 3)`` start poses.
    tasks : array_like
        ``(m, 2)`` task places (unknown to every robot at the start).
    needs : sequence of int
        Robots each task needs at once, each in ``1..n``.
    workspace, sensing_range, completion_radius : float
        Side of the square workspace (m); range within which a robot sees teammates and
        tasks; distance that counts as "at a task".
    max_steps : int
        Step limit.
    events : tuple of EventRule
        The mission's observation events.
    """

    starts: np.ndarray
    tasks: np.ndarray
    needs: tuple[int, ...]
    workspace: float = 40.0
    sensing_range: float = 8.0
    completion_radius: float = 1.5
    max_steps: int = 400
    max_speed: float | np.ndarray = 1.0
    max_turn: float | np.ndarray = math.pi
    process_noise: float = 0.0
    dt: float = 1.0
    events: tuple[EventRule, ...] = ()
    robot_names: tuple[str, ...] = ()
    task_names: tuple[str, ...] = ()
    sensors: tuple[str, ...] = field(default=(), repr=False)

    def __post_init__(self) -> None:
        starts = np.array(self.starts, dtype=float)
        if starts.ndim != 2 or starts.shape[1] not in (2, 3) or starts.shape[0] < 1:
            raise InvalidArgumentError(f"starts must be (n, 2) or (n, 3), got {starts.shape}")
        if starts.shape[1] == 2:
            starts = np.column_stack([starts, np.zeros(len(starts))])
        tasks = np.array(self.tasks, dtype=float).reshape(-1, 2)
        n, m = starts.shape[0], tasks.shape[0]
        speed = np.broadcast_to(np.asarray(self.max_speed, dtype=float), (n,)).copy()
        turn = np.broadcast_to(np.asarray(self.max_turn, dtype=float), (n,)).copy()
        numbers = {"workspace": self.workspace, "sensing_range": self.sensing_range,
                   "completion_radius": self.completion_radius, "dt": self.dt,
                   "max_speed": float(speed.min())}  # fmt: skip
        for name, value in numbers.items():
            if not (math.isfinite(value) and value > 0):
                raise InvalidArgumentError(f"{name} must be finite and > 0, got {value!r}")
        if not (np.isfinite(starts).all() and np.isfinite(tasks).all()) or (turn < 0).any():
            raise InvalidArgumentError("starts and tasks must be finite, turns >= 0", hint="no NaN")
        needs = tuple(int(k) for k in self.needs)
        if len(needs) != m or m == 0 or not all(1 <= k <= n for k in needs):
            raise InvalidArgumentError(
                f"needs must give, for each of the {m} tasks, 1..{n} robots; got {needs}",
                hint="a task cannot need more robots than the team has",
            )
        if int(self.max_steps) < 1:
            raise InvalidArgumentError(f"max_steps must be >= 1, got {self.max_steps}")
        object.__setattr__(self, "max_speed", speed)
        object.__setattr__(self, "max_turn", turn)
        object.__setattr__(self, "starts", starts)
        object.__setattr__(self, "tasks", tasks)
        object.__setattr__(self, "needs", needs)
        object.__setattr__(self, "max_steps", int(self.max_steps))
        if not self.robot_names:
            object.__setattr__(self, "robot_names", tuple(f"r{i + 1}" for i in range(n)))
        if not self.task_names:
            object.__setattr__(self, "task_names", tuple(f"t{j + 1}" for j in range(m)))
        if not self.sensors:
            object.__setattr__(self, "sensors", ("range",) * n)

    @property
    def n_robots(self) -> int:
        return self.starts.shape[0]

    @property
    def n_tasks(self) -> int:
        return self.tasks.shape[0]

    @property
    def kind(self) -> TaskKind:
        """The mission's kind: :data:`~epistemica.sim.kinds.tasks.COLLABORATIVE`."""
        return COLLABORATIVE

    def replace(self, **changes) -> CollaborativeScenario:
        return replace(self, **changes)

    @classmethod
    def drawn(
        cls, robots: int, needs, seed: int, workspace: float = 40.0, **options
    ) -> CollaborativeScenario:
        """Tasks and starts uniform in the workspace, drawn from ``seed``
        (:func:`~epistemica.sim.engine.draws.draw_layout`)."""
        layout = draw_layout(seed, robots, len(needs), workspace=workspace)
        return cls(layout.starts, layout.goals, tuple(needs), workspace=workspace, **options)
