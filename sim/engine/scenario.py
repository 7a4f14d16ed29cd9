"""One simulated world: mission, robots, goals, sensing and the rules of success.

A :class:`Scenario` is frozen and validated when built; every array is read-only. It holds
no randomness: the noise of a trial comes from the seed given to
:func:`~epistemica.sim.engine.simulate`, so one scenario runs identically for every reasoning level.

Examples
--------
>>> s = Scenario("rendezvous", [[0, 0], [10, 0]], [[5, 5], [20, 20]], ["range", "bearing"])
>>> s.n_robots, s.n_goals, s.starts[1].tolist()
(2, 2, [10.0, 0.0, 0.0])
>>> Scenario.paper("allocation", 3, 3, seed=7).sensors == Scenario.paper(
...     "allocation", 3, 3, seed=7).sensors
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

import numpy as np

from epistemica.sim.engine._scenario_checks import (
    MAX_STEPS,
    check_contacts,
    check_epistemics,
    check_goal_knowledge,
    check_mission,
    check_numbers,
    check_places,
    count,
    fail,
)
from epistemica.sim.engine.draws import draw_layout
from epistemica.sim.engine.dynamics import SENSOR_MODELS, Dynamics, Sensor
from epistemica.sim.engine.events import EventRule
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.registry import KINDS, PAPER_KINDS

__all__ = ["MAX_GOALS", "MAX_ROBOTS", "MAX_STEPS", "OBSERVATIONS", "SCENARIO_KINDS", "Scenario"]

#: The kinds a :class:`Scenario` holds (a joint mission's world is a
#: :class:`~epistemica.sim.kinds.collaborative.CollaborativeScenario`).
SCENARIO_KINDS = tuple(name for name, kind in KINDS.items() if not kind.joint)

#: Observation models: ``"paper"`` (noisy positions) and ``"honest"`` (what the sensor gives).
OBSERVATIONS = ("paper", "honest")
#: The largest team and goal count of the published protocol's scenarios (as mission files).
MAX_ROBOTS, MAX_GOALS = 12, 64


@dataclass(frozen=True, eq=False)
class Scenario:
    """A multi-robot mission to simulate.

    Parameters
    ----------
    mission : {"rendezvous", "allocation", "capacity", "multitask"}
        Rendezvous: every robot within ``success_radius`` of one common goal. Allocation:
        pairwise distinct goals. Capacity: goal ``g`` needs ``capacities[g]`` robots.
        Multitask: the goals are tasks; a task is done when any robot comes within
        ``success_radius``; the mission is done when every task is.
    starts : array_like
        ``(n, 2)`` positions (heading 0) or ``(n, 3)`` poses ``x, y, heading``.
    goals : array_like
        ``(m, 2)`` goal (task) positions.
    sensors : sequence of {"range", "bearing"}
        One sensor type per robot.
    workspace : float
        Side of the square workspace ``[0, workspace]²`` (m).
    bounded : bool
        Keep robots inside the workspace (positions are clipped after each move).
    observation : {"paper", "honest"} or Sensor
        ``"paper"``: every robot receives the others' positions with ``N(0,
        position_noise)`` per axis. ``"honest"``: a bearing robot measures angles only
        (``N(0, angle_noise)``); a range robot measures range (``N(0, position_noise)``)
        and angle. Or a sensor of your own (:class:`~epistemica.sim.engine.dynamics.Sensor`).
    position_noise, angle_noise : float
        Variances (m², rad²) of the observation noise.
    process_noise : float
        Variance (m²) per axis of the Gaussian noise added to every move.
    sensing_range : float, optional
        Robots beyond it are not observed (the observer knows it saw nothing); ``None``:
        everyone sees everyone.
    discovery_range : float, optional
        Distance within which a robot discovers an unknown goal, or sees that a task is
        done; default ``sensing_range``, or 10 m when sensing is unlimited.
    known_goals : array_like, optional
        ``(n, m)`` booleans: the goals each robot knows at the start (default all).
    capacities : sequence of int, optional
        Robots needed per goal, for ``"capacity"``.
    max_speed, max_turn : float or array_like
        Per-robot limits on speed (m/s) and heading change per step (rad).
    dt : float
        Time step (s).
    max_steps : int
        Step limit.
    success_radius : float
        Distance (m) at which a robot counts as at a goal.
    dwell : int
        Steps, not necessarily consecutive, on which the mission must hold to succeed
        (rendezvous, allocation, capacity).
    tasking : int, optional
        Multitask: the most tasks the team works on at once (the paper's ``K``); default
        the number of robots.
    valid : array_like, optional
        ``(k, n)`` goal indices: an explicit set of valid configurations (a subset of the
        mission's, e.g. compiled from a mission file's ``valid`` formula); the mission
        holds when the robots realise one of them.
    events : sequence of EventRule
        Observation events that update the robots' knowledge
        (:class:`~epistemica.sim.engine.events.EventRule`: when they happen, their world effects,
        what they teach and who observes them). Mission files declare them; the library
        events ``settle`` and ``complete`` come from ``epistemica.mission.library_event``.
    closed : array_like, optional
        ``(m,)`` booleans: goals closed at the start (they count for success, and are
        discovered, only once an event opens them). Default: none.
    told : sequence of (observers, formula)
        Facts over ``assigned(ROBOT, GOAL)`` atoms that the robots marked in
        ``observers`` (``n`` booleans) know at the start (and know each other to know).
    suggested : sequence of (observers, formula)
        Soft facts the robots marked in ``observers`` believe at the start (a prior, as
        ``suggests`` of an event: later evidence that contradicts one wins), oldest first.
    robot_names, goal_names : sequence of str, optional
        Names used by ``told`` formulas and in reports; default ``r1, r2, ...`` and
        ``g1, g2, ...``.
    dynamics : Dynamics, optional
        How robots move (:class:`~epistemica.sim.engine.dynamics.Dynamics`); default the
        unicycle (:class:`~epistemica.sim.engine.dynamics.Unicycle`).
    robot_radius : float or array_like, optional
        Disc robots of this radius (m, per robot) that cannot overlap
        (:mod:`epistemica.sim.engine.obstacles`); ``None``: point robots that pass through each
        other.
    obstacles : sequence of array_like
        Polygons (``(k, 2)`` corners each) that block motion and sight; no start and no
        goal may lie in one.
    """

    mission: str
    starts: np.ndarray
    goals: np.ndarray
    sensors: tuple[str, ...]
    workspace: float = 30.0
    bounded: bool = False
    observation: str = "paper"
    position_noise: float = 0.5
    angle_noise: float = 0.1
    process_noise: float = 0.0
    sensing_range: float | None = None
    discovery_range: float | None = None
    known_goals: np.ndarray | None = None
    capacities: tuple[int, ...] | None = None
    max_speed: np.ndarray = field(default=1.0)  # type: ignore[assignment]
    max_turn: np.ndarray = field(default=math.pi)  # type: ignore[assignment]
    dt: float = 1.0
    max_steps: int = 100
    success_radius: float = 5.0 / 3.0
    dwell: int = 5
    tasking: int | None = None
    valid: np.ndarray | None = None
    events: tuple[EventRule, ...] = ()
    closed: np.ndarray | None = None
    told: tuple = ()
    suggested: tuple = ()
    robot_names: tuple[str, ...] | None = None
    goal_names: tuple[str, ...] | None = None
    dynamics: Dynamics | None = None
    robot_radius: np.ndarray | None = None
    obstacles: tuple[np.ndarray, ...] = ()

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        if isinstance(self.mission, MissionKind) and not isinstance(self.mission, str):
            set_(self, "mission", self.mission.name)
        if self.mission not in SCENARIO_KINDS:
            # a joint (collaborative) mission's world is a CollaborativeScenario
            raise fail(
                f"unknown mission {self.mission!r}", f"use one of {', '.join(SCENARIO_KINDS)}"
            )
        if not isinstance(self.observation, Sensor) and self.observation not in OBSERVATIONS:
            raise fail(
                f"unknown observation model {self.observation!r}",
                f"use one of {', '.join(OBSERVATIONS)}",
            )
        starts, goals = check_places(self)
        n, m = starts.shape[0], goals.shape[0]
        check_numbers(self, starts)
        check_goal_knowledge(self, n, m)
        check_mission(self, n, m)
        check_epistemics(self, n, m)
        check_contacts(self, starts, goals)
        for name, value in (("starts", starts), ("goals", goals)):
            value.setflags(write=False)
            set_(self, name, value)
        for name in ("max_speed", "max_turn"):
            getattr(self, name).setflags(write=False)

    @property
    def sensor(self) -> Sensor:
        """The observation model as a :class:`~epistemica.sim.engine.dynamics.Sensor`."""
        if isinstance(self.observation, str):
            return SENSOR_MODELS[self.observation]
        return self.observation

    @property
    def contacts(self) -> bool:
        """Whether robots are discs or there are obstacles (moves may be cut short)."""
        return self.robot_radius is not None or bool(self.obstacles)

    @property
    def n_robots(self) -> int:
        """Number of robots."""
        return self.starts.shape[0]

    @property
    def kind(self) -> MissionKind:
        """The mission's kind (:mod:`epistemica.sim.kinds`)."""
        return KINDS[self.mission]

    @property
    def n_goals(self) -> int:
        """Number of goals (tasks)."""
        return self.goals.shape[0]

    def configurations(self) -> np.ndarray:
        """The valid goal configurations of the mission, ``(k, n)`` goal indices.

        Examples
        --------
        >>> Scenario("allocation", [[0, 0], [1, 1]], [[5, 5], [9, 9]], ["range"] * 2
        ...          ).configurations().tolist()
        [[0, 1], [1, 0]]
        """
        if self.valid is not None:
            return self.valid
        return self.kind.configurations(self.n_robots, self.n_goals, self.capacities)

    def replace(self, **changes) -> Scenario:
        """A copy with some fields changed (validated again).

        Examples
        --------
        >>> s = Scenario.paper("rendezvous", 2, 3, seed=0)
        >>> s.replace(sensing_range=10.0).sensing_range
        10.0
        """
        names = {f.name for f in fields(self)}
        unknown = sorted(set(changes) - names)
        if unknown:
            raise fail(f"Scenario has no field {unknown[0]!r}", f"fields: {', '.join(names)}")
        return replace(self, **changes)

    @classmethod
    def paper(
        cls, mission: str, robots: int, goals: int | None = None, seed: int = 0, **options
    ) -> Scenario:
        """One trial of the published protocol (``paper-results.md``), drawn from ``seed``.

        Rendezvous and allocation: goals uniform in ``[1, 29]²``, starts uniform in
        ``[0, 30]²`` with heading 0, each sensor uniform over range/bearing, step limit
        100. Multitask: starts ``(n-1, n-1) + N(0, 1)`` per axis (clipped into the
        workspace), turns of at most ``pi/4`` per step, speeds up to 1 m/s, step limit 150.

        Parameters
        ----------
        mission : str
            A kind the protocol draws (:data:`~epistemica.sim.kinds.registry.PAPER_KINDS`).
        robots : int
            Team size.
        goals : int, optional
            Goals (tasks); allocation defaults to ``robots``, multitask to 20.
        seed : int
            Trial seed: the same seed gives the same geometry and sensors.
        **options
            Other :class:`Scenario` fields (e.g. ``sensing_range=10.0``).

        Examples
        --------
        >>> s = Scenario.paper("rendezvous", 3, 4, seed=1)
        >>> s.starts.shape, s.goals.shape, s.max_steps
        ((3, 3), (4, 2), 100)
        >>> bool(np.all((s.goals >= 1) & (s.goals <= 29)))
        True
        """
        kind = KINDS.get(mission) if isinstance(mission, str) else None
        if kind is None or kind.paper is None:
            raise fail(
                f"the paper protocol has no {mission!r} mission",
                f"use {', '.join(PAPER_KINDS)}",
            )
        n = count(robots, "robots", MAX_ROBOTS)
        m = count(goals if goals is not None else kind.default_goals(n), "goals", MAX_GOALS)
        layout = draw_layout(seed, n, m, clustered=kind.tasks)
        defaults = dict(kind.paper)
        starts = np.column_stack([layout.starts, np.zeros(n)])
        task_goals, sensors = layout.goals, layout.sensors
        return cls(mission, starts, task_goals, sensors, **{**defaults, **options})
