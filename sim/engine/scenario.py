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
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace

import numpy as np

from epistemica.aif.evidence import SENSORS
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine.draws import draw_layout
from epistemica.sim.engine.dynamics import SENSOR_MODELS, Dynamics, Sensor, Unicycle
from epistemica.sim.engine.events import EventRule
from epistemica.sim.engine.obstacles import CLEARANCE, inside, polygon, polygon_distance
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.registry import KINDS, PAPER_KINDS

__all__ = ["OBSERVATIONS", "SCENARIO_KINDS", "Scenario"]

#: The kinds a :class:`Scenario` holds (a joint mission's world is a
#: :class:`~epistemica.sim.kinds.collaborative.CollaborativeScenario`).
SCENARIO_KINDS = tuple(name for name, kind in KINDS.items() if not kind.joint)

#: Observation models: ``"paper"`` (noisy positions) and ``"honest"`` (what the sensor gives).
OBSERVATIONS = ("paper", "honest")
#: The longest trial a scenario may ask for (steps): what a mission file accepts too.
MAX_STEPS = 100_000
#: The largest team and goal count of the published protocol's scenarios (as mission files).
MAX_ROBOTS, MAX_GOALS = 12, 64


def _fail(message: str, hint: str) -> InvalidArgumentError:
    return InvalidArgumentError(message, hint=hint)


def _array(value, name: str, columns: Sequence[int]) -> np.ndarray:
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise _fail(f"{name} must be numbers, got {value!r}", "pass a list of rows") from exc
    if a.ndim != 2 or a.shape[1] not in columns or a.shape[0] == 0:
        want = " or ".join(f"(n, {c})" for c in columns)
        raise _fail(f"{name} must have shape {want}, got {a.shape}", f"one row per {name[:-1]}")
    if not np.all(np.isfinite(a)):
        raise _fail(f"{name} contains NaN or infinity", "every coordinate must be a number")
    return a


def _per_robot(value, name: str, n: int, low: float, high: float) -> np.ndarray:
    a = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()
    if np.any(~(a >= low)) or np.any(a > high):  # ~(a >= low) also catches NaN
        raise _fail(f"{name} must lie in [{low}, {high}], got {a.tolist()}", "one value per robot")
    return a


def _non_negative(value, name: str, allow_none: bool = False, positive: bool = False):
    if value is None and allow_none:
        return None
    v = float(value)
    if not math.isfinite(v) or v < 0 or (positive and v == 0):
        bound = "> 0" if positive else ">= 0"
        raise _fail(f"{name} must be a finite number {bound}, got {value!r}", f"e.g. {name}=1.0")
    return v


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
            raise _fail(
                f"unknown mission {self.mission!r}", f"use one of {', '.join(SCENARIO_KINDS)}"
            )
        if not isinstance(self.observation, Sensor) and self.observation not in OBSERVATIONS:
            raise _fail(
                f"unknown observation model {self.observation!r}",
                f"use one of {', '.join(OBSERVATIONS)}",
            )
        starts = _array(self.starts, "starts", (2, 3))
        if starts.shape[1] == 2:
            starts = np.column_stack([starts, np.zeros(len(starts))])
        goals = _array(self.goals, "goals", (2,))
        n, m = starts.shape[0], goals.shape[0]
        sensors = (self.sensors,) if isinstance(self.sensors, str) else tuple(self.sensors)
        bad = [s for s in sensors if s not in SENSORS]
        if bad or len(sensors) != n:
            raise _fail(
                f"sensors {list(sensors)!r} for {n} robots",
                f"one of {', '.join(SENSORS)} per robot",
            )
        set_(self, "sensors", sensors)
        for name in ("position_noise", "angle_noise", "process_noise"):
            set_(self, name, _non_negative(getattr(self, name), name))
        for name in ("workspace", "dt", "success_radius"):
            set_(self, name, _non_negative(getattr(self, name), name, positive=True))
        for name in ("sensing_range", "discovery_range"):
            set_(self, name, _non_negative(getattr(self, name), name, allow_none=True))
        outside = np.any((starts[:, :2] < 0) | (starts[:, :2] > self.workspace), axis=1)
        if np.any(outside):
            raise _fail(
                f"robot {int(np.argmax(outside))} starts at {starts[outside][0, :2].tolist()}, "
                f"outside the workspace [0, {self.workspace:g}]²",
                "move the start inside, or enlarge `workspace`",
            )
        set_(self, "max_speed", _per_robot(self.max_speed, "max_speed", n, 0.0, 1e6))
        set_(self, "max_turn", _per_robot(self.max_turn, "max_turn", n, 0.0, math.pi))
        for name in ("max_steps", "dwell"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
                raise _fail(f"{name} must be an integer >= 1, got {value!r}", f"e.g. {name}=5")
            if value > MAX_STEPS:  # a trial's arrays are preallocated per step
                raise _fail(f"{name} must be at most {MAX_STEPS:,}, got {value!r}", "e.g. 150")
            set_(self, name, int(value))
        self._check_goal_knowledge(n, m)
        self._check_mission(n, m)
        _check_epistemics(self, n, m)
        _check_contacts(self, starts, goals)
        for name, value in (("starts", starts), ("goals", goals)):
            value.setflags(write=False)
            set_(self, name, value)
        for name in ("max_speed", "max_turn"):
            getattr(self, name).setflags(write=False)

    def _check_goal_knowledge(self, n: int, m: int) -> None:
        if self.known_goals is None:
            return
        known = np.array(self.known_goals)
        if known.shape != (n, m) or known.dtype != bool:
            raise _fail(
                f"known_goals must be ({n}, {m}) booleans, got {known.shape} {known.dtype}",
                "row i marks the goals robot i knows at the start",
            )
        known.setflags(write=False)
        object.__setattr__(self, "known_goals", known)

    def _check_mission(self, n: int, m: int) -> None:
        kind = self.kind
        if kind.capacities:
            if self.capacities is None:
                raise _fail("a capacity mission needs `capacities`", "one count per goal")
            object.__setattr__(self, "capacities", tuple(int(c) for c in self.capacities))
        elif self.capacities is not None:
            raise _fail(f"`capacities` given for a {self.mission} mission", "drop it")
        if kind.tasks:
            if self.tasking is not None and (not isinstance(self.tasking, int) or self.tasking < 1):
                raise _fail(f"tasking must be an integer >= 1, got {self.tasking!r}", "e.g. 3")
            return
        if kind.count(n, m, self.capacities) == 0:
            # Building the (empty) set raises the specific error: too few goals, ...
            kind.configurations(n, m, self.capacities)

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
            raise _fail(f"Scenario has no field {unknown[0]!r}", f"fields: {', '.join(names)}")
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
            raise _fail(
                f"the paper protocol has no {mission!r} mission",
                f"use {', '.join(PAPER_KINDS)}",
            )
        n = _count(robots, "robots", MAX_ROBOTS)
        m = _count(goals if goals is not None else kind.default_goals(n), "goals", MAX_GOALS)
        layout = draw_layout(seed, n, m, clustered=kind.tasks)
        defaults = dict(kind.paper)
        starts = np.column_stack([layout.starts, np.zeros(n)])
        task_goals, sensors = layout.goals, layout.sensors
        return cls(mission, starts, task_goals, sensors, **{**defaults, **options})


def _check_epistemics(scenario: Scenario, n: int, m: int) -> None:
    """Names, events, closed goals, told and suggested facts, the table of valid rows."""
    set_ = object.__setattr__
    for name, count, prefix in (("robot_names", n, "r"), ("goal_names", m, "g")):
        names = getattr(scenario, name)
        names = tuple(f"{prefix}{i + 1}" for i in range(count)) if names is None else names
        if len(names) != count or len(set(names)) != count:
            raise _fail(f"{name} must be {count} distinct names, got {names!r}", "one each")
        set_(scenario, name, tuple(str(x) for x in names))
    events = tuple(scenario.events)
    for rule in events:
        if not isinstance(rule, EventRule):
            raise _fail(
                f"events must be EventRule objects, got {rule!r}",
                "compile them from a mission file, or use "
                "epistemica.mission.library_event('settle', 'nearby')",
            )
    set_(scenario, "events", events)
    closed = np.zeros(m, dtype=bool) if scenario.closed is None else np.array(scenario.closed)
    if closed.shape != (m,) or closed.dtype != bool:
        raise _fail(f"closed must be {m} booleans, got {closed!r}", "one per goal")
    closed.setflags(write=False)
    set_(scenario, "closed", closed)
    for name in ("told", "suggested"):
        facts = []
        for observers, formula in getattr(scenario, name):
            mask = np.asarray(observers, dtype=bool)
            if mask.shape != (n,):
                raise _fail(f"{name} observers must be {n} booleans", "one per robot")
            facts.append((tuple(bool(x) for x in mask), formula))
        set_(scenario, name, tuple(facts))
    if scenario.valid is None:
        return
    if scenario.kind.tasks:
        raise _fail(f"`valid` is not used by a {scenario.mission} mission", "drop it")
    rows = np.array(scenario.valid)
    if rows.ndim != 2 or rows.shape[1] != n or rows.shape[0] == 0:
        raise _fail(f"valid must be (k, {n}) goal indices, got {rows.shape}", "one per robot")
    if not np.issubdtype(rows.dtype, np.integer) or rows.min() < 0 or rows.max() >= m:
        raise _fail(f"valid must hold goal indices 0..{m - 1}", "one row per configuration")
    rows.setflags(write=False)
    set_(scenario, "valid", rows)


def _check_contacts(scenario: Scenario, starts: np.ndarray, goals: np.ndarray) -> None:
    """Dynamics, robot radii and obstacles: no start and no goal inside an obstacle."""
    set_ = object.__setattr__
    if scenario.dynamics is None:
        set_(scenario, "dynamics", Unicycle())
    elif not isinstance(scenario.dynamics, Dynamics):
        raise _fail(
            f"dynamics must have a step(poses, controls, dt) method, got {scenario.dynamics!r}",
            "use epistemica.sim.engine.dynamics.Unicycle(), or an object of your own",
        )
    n = starts.shape[0]
    if scenario.robot_radius is not None:
        radius = _per_robot(scenario.robot_radius, "robot_radius", n, 0.0, scenario.workspace)
        radius.setflags(write=False)
        set_(scenario, "robot_radius", radius)
    obstacles = tuple(polygon(p) for p in scenario.obstacles)
    set_(scenario, "obstacles", obstacles)
    radii = np.zeros(n) if scenario.robot_radius is None else scenario.robot_radius
    for k, poly in enumerate(obstacles):
        for i, start in enumerate(starts[:, :2]):
            if polygon_distance(start, start, poly) < max(radii[i], CLEARANCE):
                raise _fail(
                    f"robot {i} starts at {start.tolist()}, in obstacle {k}",
                    "move the start (or the obstacle); a place drawn at random may fall "
                    "in an obstacle: place robots explicitly when there are obstacles",
                )
        hit = inside(goals, poly)
        if hit.any():
            g = int(np.argmax(hit))
            raise _fail(
                f"goal {g} at {goals[g].tolist()} lies in obstacle {k}: no robot can reach it",
                "move the goal (or the obstacle); a place drawn at random may fall in "
                "an obstacle: place goals explicitly when there are obstacles",
            )


def _count(value, name: str, limit: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise _fail(f"{name} must be an integer >= 1, got {value!r}", f"e.g. {name}=3")
    if value > limit:  # the levels' sets of configurations grow as goals^robots
        raise _fail(f"{name} must be at most {limit}, got {value!r}", "the simulator's limit")
    return int(value)
