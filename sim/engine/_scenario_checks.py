"""The checks of a :class:`~epistemica.sim.engine.scenario.Scenario`'s fields.

Each check reads fields of the scenario being built, stores them normalised (tuples,
read-only arrays, floats) into the frozen instance, or raises a clear
:class:`~epistemica.del_.errors.InvalidArgumentError` with a hint. ``Scenario.__post_init__``
calls them in a fixed order, so that a scenario with several faults reports the same one
first every time.

Examples
--------
>>> per_robot(2.0, "max_speed", 3, 0.0, 1e6).tolist()
[2.0, 2.0, 2.0]
>>> count(3, "robots", 12)
3
>>> non_negative(-1, "dt", positive=True)
Traceback (most recent call last):
...
epistemica.del_.errors.InvalidArgumentError: dt must be a finite number > 0, got -1
hint: e.g. dt=1.0
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from epistemica.aif.evidence import SENSORS
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine.dynamics import Dynamics, Unicycle
from epistemica.sim.engine.events import EventRule
from epistemica.sim.engine.obstacles import CLEARANCE, inside, polygon, polygon_distance

if TYPE_CHECKING:
    from epistemica.sim.engine.scenario import Scenario

__all__ = [
    "MAX_STEPS",
    "as_rows",
    "check_contacts",
    "check_epistemics",
    "check_goal_knowledge",
    "check_mission",
    "check_numbers",
    "check_places",
    "count",
    "fail",
    "non_negative",
    "per_robot",
]

#: The longest trial a scenario may ask for (steps): what a mission file accepts too.
MAX_STEPS = 100_000


def fail(message: str, hint: str) -> InvalidArgumentError:
    """The error of a bad field: what is wrong, and a hint."""
    return InvalidArgumentError(message, hint=hint)


def as_rows(value, name: str, columns: Sequence[int]) -> np.ndarray:
    """``value`` as a non-empty float array of rows of one of ``columns`` lengths, finite."""
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise fail(f"{name} must be numbers, got {value!r}", "pass a list of rows") from exc
    if a.ndim != 2 or a.shape[1] not in columns or a.shape[0] == 0:
        want = " or ".join(f"(n, {c})" for c in columns)
        raise fail(f"{name} must have shape {want}, got {a.shape}", f"one row per {name[:-1]}")
    if not np.all(np.isfinite(a)):
        raise fail(f"{name} contains NaN or infinity", "every coordinate must be a number")
    return a


def per_robot(value, name: str, n: int, low: float, high: float) -> np.ndarray:
    """``value`` (one number, or one per robot) as ``n`` numbers in ``[low, high]``."""
    a = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()
    if np.any(~(a >= low)) or np.any(a > high):  # ~(a >= low) also catches NaN
        raise fail(f"{name} must lie in [{low}, {high}], got {a.tolist()}", "one value per robot")
    return a


def non_negative(value, name: str, allow_none: bool = False, positive: bool = False):
    """``value`` as a finite float >= 0 (> 0 if ``positive``; None kept if ``allow_none``)."""
    if value is None and allow_none:
        return None
    v = float(value)
    if not math.isfinite(v) or v < 0 or (positive and v == 0):
        bound = "> 0" if positive else ">= 0"
        raise fail(f"{name} must be a finite number {bound}, got {value!r}", f"e.g. {name}=1.0")
    return v


def check_places(scenario: Scenario) -> tuple[np.ndarray, np.ndarray]:
    """``(starts (n, 3), goals (m, 2))`` as arrays, and one known sensor per robot."""
    starts = as_rows(scenario.starts, "starts", (2, 3))
    if starts.shape[1] == 2:
        starts = np.column_stack([starts, np.zeros(len(starts))])
    goals = as_rows(scenario.goals, "goals", (2,))
    n = starts.shape[0]
    sensors = scenario.sensors
    sensors = (sensors,) if isinstance(sensors, str) else tuple(sensors)
    bad = [s for s in sensors if s not in SENSORS]
    if bad or len(sensors) != n:
        raise fail(
            f"sensors {list(sensors)!r} for {n} robots",
            f"one of {', '.join(SENSORS)} per robot",
        )
    object.__setattr__(scenario, "sensors", sensors)
    return starts, goals


def check_numbers(scenario: Scenario, starts: np.ndarray) -> None:
    """Noises, workspace, time step, radii and ranges, starts inside the workspace, per-robot
    speed and turn limits, step limit and dwell."""
    set_ = object.__setattr__
    n = starts.shape[0]
    for name in ("position_noise", "angle_noise", "process_noise"):
        set_(scenario, name, non_negative(getattr(scenario, name), name))
    for name in ("workspace", "dt", "success_radius"):
        set_(scenario, name, non_negative(getattr(scenario, name), name, positive=True))
    for name in ("sensing_range", "discovery_range"):
        set_(scenario, name, non_negative(getattr(scenario, name), name, allow_none=True))
    outside = np.any((starts[:, :2] < 0) | (starts[:, :2] > scenario.workspace), axis=1)
    if np.any(outside):
        raise fail(
            f"robot {int(np.argmax(outside))} starts at {starts[outside][0, :2].tolist()}, "
            f"outside the workspace [0, {scenario.workspace:g}]²",
            "move the start inside, or enlarge `workspace`",
        )
    set_(scenario, "max_speed", per_robot(scenario.max_speed, "max_speed", n, 0.0, 1e6))
    set_(scenario, "max_turn", per_robot(scenario.max_turn, "max_turn", n, 0.0, math.pi))
    for name in ("max_steps", "dwell"):
        value = getattr(scenario, name)
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise fail(f"{name} must be an integer >= 1, got {value!r}", f"e.g. {name}=5")
        if value > MAX_STEPS:  # a trial's arrays are preallocated per step
            raise fail(f"{name} must be at most {MAX_STEPS:,}, got {value!r}", "e.g. 150")
        set_(scenario, name, int(value))


def check_goal_knowledge(scenario: Scenario, n: int, m: int) -> None:
    """``known_goals``: ``(n, m)`` booleans, or None (every robot knows every goal)."""
    if scenario.known_goals is None:
        return
    known = np.array(scenario.known_goals)
    if known.shape != (n, m) or known.dtype != bool:
        raise fail(
            f"known_goals must be ({n}, {m}) booleans, got {known.shape} {known.dtype}",
            "row i marks the goals robot i knows at the start",
        )
    known.setflags(write=False)
    object.__setattr__(scenario, "known_goals", known)


def check_mission(scenario: Scenario, n: int, m: int) -> None:
    """What the kind needs: capacities, the tasking bound, a non-empty set of configurations."""
    kind = scenario.kind
    if kind.capacities:
        if scenario.capacities is None:
            raise fail("a capacity mission needs `capacities`", "one count per goal")
        object.__setattr__(scenario, "capacities", tuple(int(c) for c in scenario.capacities))
    elif scenario.capacities is not None:
        raise fail(f"`capacities` given for a {scenario.mission} mission", "drop it")
    if kind.tasks:
        tasking = scenario.tasking
        if tasking is not None and (not isinstance(tasking, int) or tasking < 1):
            raise fail(f"tasking must be an integer >= 1, got {tasking!r}", "e.g. 3")
        return
    if kind.count(n, m, scenario.capacities) == 0:
        # Building the (empty) set raises the specific error: too few goals, ...
        kind.configurations(n, m, scenario.capacities)


def check_epistemics(scenario: Scenario, n: int, m: int) -> None:
    """Names, events, closed goals, told and suggested facts, the table of valid rows."""
    set_ = object.__setattr__
    for name, size, prefix in (("robot_names", n, "r"), ("goal_names", m, "g")):
        names = getattr(scenario, name)
        names = tuple(f"{prefix}{i + 1}" for i in range(size)) if names is None else names
        if len(names) != size or len(set(names)) != size:
            raise fail(f"{name} must be {size} distinct names, got {names!r}", "one each")
        set_(scenario, name, tuple(str(x) for x in names))
    events = tuple(scenario.events)
    for rule in events:
        if not isinstance(rule, EventRule):
            raise fail(
                f"events must be EventRule objects, got {rule!r}",
                "compile them from a mission file, or use "
                "epistemica.mission.library_event('settle', 'nearby')",
            )
    set_(scenario, "events", events)
    closed = np.zeros(m, dtype=bool) if scenario.closed is None else np.array(scenario.closed)
    if closed.shape != (m,) or closed.dtype != bool:
        raise fail(f"closed must be {m} booleans, got {closed!r}", "one per goal")
    closed.setflags(write=False)
    set_(scenario, "closed", closed)
    for name in ("told", "suggested"):
        facts = []
        for observers, formula in getattr(scenario, name):
            mask = np.asarray(observers, dtype=bool)
            if mask.shape != (n,):
                raise fail(f"{name} observers must be {n} booleans", "one per robot")
            facts.append((tuple(bool(x) for x in mask), formula))
        set_(scenario, name, tuple(facts))
    if scenario.valid is None:
        return
    if scenario.kind.tasks:
        raise fail(f"`valid` is not used by a {scenario.mission} mission", "drop it")
    rows = np.array(scenario.valid)
    if rows.ndim != 2 or rows.shape[1] != n or rows.shape[0] == 0:
        raise fail(f"valid must be (k, {n}) goal indices, got {rows.shape}", "one per robot")
    if not np.issubdtype(rows.dtype, np.integer) or rows.min() < 0 or rows.max() >= m:
        raise fail(f"valid must hold goal indices 0..{m - 1}", "one row per configuration")
    rows.setflags(write=False)
    set_(scenario, "valid", rows)


def check_contacts(scenario: Scenario, starts: np.ndarray, goals: np.ndarray) -> None:
    """Dynamics, robot radii and obstacles: no start and no goal inside an obstacle."""
    set_ = object.__setattr__
    if scenario.dynamics is None:
        set_(scenario, "dynamics", Unicycle())
    elif not isinstance(scenario.dynamics, Dynamics):
        raise fail(
            f"dynamics must have a step(poses, controls, dt) method, got {scenario.dynamics!r}",
            "use epistemica.sim.engine.dynamics.Unicycle(), or an object of your own",
        )
    n = starts.shape[0]
    if scenario.robot_radius is not None:
        radius = per_robot(scenario.robot_radius, "robot_radius", n, 0.0, scenario.workspace)
        radius.setflags(write=False)
        set_(scenario, "robot_radius", radius)
    obstacles = tuple(polygon(p) for p in scenario.obstacles)
    set_(scenario, "obstacles", obstacles)
    radii = np.zeros(n) if scenario.robot_radius is None else scenario.robot_radius
    for k, poly in enumerate(obstacles):
        for i, start in enumerate(starts[:, :2]):
            if polygon_distance(start, start, poly) < max(radii[i], CLEARANCE):
                raise fail(
                    f"robot {i} starts at {start.tolist()}, in obstacle {k}",
                    "move the start (or the obstacle); a place drawn at random may fall "
                    "in an obstacle: place robots explicitly when there are obstacles",
                )
        hit = inside(goals, poly)
        if hit.any():
            g = int(np.argmax(hit))
            raise fail(
                f"goal {g} at {goals[g].tolist()} lies in obstacle {k}: no robot can reach it",
                "move the goal (or the obstacle); a place drawn at random may fall in "
                "an obstacle: place goals explicitly when there are obstacles",
            )


def count(value, name: str, limit: int) -> int:
    """A team size or goal count: an integer in ``[1, limit]``."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise fail(f"{name} must be an integer >= 1, got {value!r}", f"e.g. {name}=3")
    if value > limit:  # the levels' sets of configurations grow as goals^robots
        raise fail(f"{name} must be at most {limit}, got {value!r}", "the simulator's limit")
    return int(value)
