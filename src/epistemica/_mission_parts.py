"""The parts of a compiled mission file (:class:`MissionParts`) and the checks that need
the whole file: the mission kind against its goals, triggers against the step limit,
every level named, who knows which goal.

Helper of :mod:`epistemica._mission_compiler`: :func:`assemble` takes the compiler after
it walked every statement.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from lark import Token

from epistemica._mission_plausibility import check_orders
from epistemica.del_ import Check, Formula
from epistemica.del_.errors import InvalidArgumentError
from epistemica.sim.engine.events import EventRule
from epistemica.sim.engine.obstacles import CLEARANCE, polygon, polygon_distance
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.policies.levels import level_names

__all__ = ["DEFAULT_STEPS", "GoalSpec", "MissionCheck", "MissionParts", "RobotSpec", "assemble"]

#: Steps of a trial unless ``simulate steps N`` says otherwise.
DEFAULT_STEPS = 100


@dataclass(frozen=True)
class RobotSpec:
    """A ``robot`` line: name, sensor (or ``random``), place (None: at random), limits."""

    name: str
    token: Token
    sensor: str
    place: tuple[float, ...] | None
    speed: float = 1.0
    turn: float = math.pi
    radius: float | None = None


@dataclass(frozen=True)
class GoalSpec:
    """A ``goal`` (or ``task``) line."""

    name: str
    token: Token
    place: tuple[float, ...] | None
    needs: int | None = None
    closed: bool = False
    needs_token: Token | None = None


@dataclass(frozen=True)
class MissionCheck:
    """A claim, on the initial model or ``after`` steps of a seeded trial."""

    check: Check
    after: int | None = None
    seed: int | None = None
    level: str | None = None


@dataclass(frozen=True)
class MissionParts:
    """Everything a mission file declares, checked (see docs/language.md)."""

    kind: MissionKind
    robots: tuple[RobotSpec, ...]
    goals: tuple[GoalSpec, ...]
    capacities: tuple[int, ...] | None
    options: dict[str, Any]
    valid: tuple[Formula, ...]
    initially: tuple[Formula, ...]
    learns: tuple[tuple[tuple[str, ...], Formula], ...]
    known_goals: np.ndarray | str | None
    events: tuple[EventRule, ...]
    teammates: tuple[tuple[str, str, Token], ...]
    policy: tuple[tuple[str, Any, Token], ...]
    checks: tuple[MissionCheck, ...]
    trials: int | None
    seed: int | None
    levels: tuple[tuple[str, Token], ...] | None
    obstacles: tuple[np.ndarray, ...] = ()
    team: int | None = None  # the team size N of spans r1..rN (None: the file has none)
    plausibility: tuple = ()  # PlausibilityOrder per 'plausibility' line, in file order
    event_tokens: tuple[tuple[str, Token], ...] = ()  # each event's name, where declared

    @property
    def robot_names(self) -> tuple[str, ...]:
        return tuple(r.name for r in self.robots)

    @property
    def goal_names(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.goals)


def assemble(comp: Any) -> MissionParts:
    """The parts of a walked mission, after the checks that need the whole file."""
    end = Token("NAME", "", line=max(1, comp.source.count("\n") + 1), column=1)
    if comp.kind is None:
        raise comp.error("the mission has no 'mission' line", end, "add e.g. 'mission rendezvous'")
    if not comp.robots:
        raise comp.error("the mission declares no robot", end, "add 'robot r1: range at (x, y)'")
    if not comp.goals:
        raise comp.error("the mission declares no goal", end, "add 'goal g1 at (x, y)'")
    _check_kind(comp)
    _check_steps(comp)
    _check_levels(comp)
    check_orders(comp)
    return MissionParts(
        kind=comp.kind,
        robots=tuple(comp.robots.values()),
        goals=tuple(comp.goals.values()),
        capacities=_capacities(comp),
        options=comp.options,
        valid=tuple(comp.valid),
        initially=tuple(comp.initially),
        learns=tuple(comp.learns),
        known_goals=_known(comp, end),
        events=tuple(comp.events.values()),
        event_tokens=tuple(comp.event_tokens.items()),
        teammates=tuple(comp.teammates),
        policy=tuple(comp.policy),
        checks=tuple(comp.checks),
        trials=comp.study.get("trials"),
        seed=comp.study.get("seed"),
        levels=comp.study.get("levels"),
        obstacles=_obstacles(comp),
        team=comp.team if comp.parametric else None,
        plausibility=tuple(comp.plausibility),
    )


def _check_kind(comp: Any) -> None:
    kind = comp.kind
    if kind.tasks != comp.is_tasks:
        want = "task" if kind.tasks else "goal"
        raise comp.error(
            f"a {kind} mission declares {want}s",
            comp.kind_token,
            f"declare its places with '{want} NAME at (x, y)'",
        )
    needs = [g for g in comp.goals.values() if g.needs is not None]
    if kind.joint:
        _check_needs(comp)
    elif kind.capacities:
        missing = [g for g in comp.goals.values() if g.needs is None]
        if missing:
            raise comp.error(
                "every goal of a capacity mission says how many robots it needs",
                missing[0].token,
                "write 'goal NAME at (x, y) needs 2'",
            )
    elif needs:
        raise comp.error(
            f"'needs' in a {kind} mission", needs[0].needs_token, "use 'mission capacity'"
        )
    workspace = comp.options.get("workspace", 30.0)
    if workspace <= 2.0 and any(g.place is None for g in comp.goals.values()):
        raise comp.error(
            f"a workspace of {workspace:g} m leaves no room for goals at random "
            "(they keep 1 m from the borders)",
            comp.kind_token,
            "enlarge 'workspace', or place the goals",
        )


def _check_needs(comp: Any) -> None:
    """Every task of a collaborative mission needs 1..n robots; no claims (its model
    would be over tasks found, not over configurations)."""
    if comp.checks:
        raise comp.error(
            "a collaborative mission has no claims yet: its robots' knowledge is about "
            "tasks found, not about goal configurations",
            comp.kind_token,
            "remove the 'check' lines; inspect Trial.knowledge instead",
        )
    for task in comp.goals.values():
        if task.needs is None:
            raise comp.error(
                "every task of a collaborative mission says how many robots it needs",
                task.token,
                "write 'task NAME at random needs 2'",
            )
        if not 1 <= int(task.needs) <= len(comp.robots):
            raise comp.error(
                f"task '{task.name}' needs {int(task.needs)} robots, the team has "
                f"{len(comp.robots)}",
                task.needs_token,
                f"a number from 1 to {len(comp.robots)}",
            )


def _check_steps(comp: Any) -> None:
    limit = comp.options.get("max_steps", DEFAULT_STEPS)
    for step, token in comp.step_triggers:
        if step >= limit:
            raise comp.error(
                f"a trigger at step {step} never fires: trials stop after {limit} steps",
                token,
                f"choose a step below {limit}, or raise 'simulate steps'",
            )


def _check_levels(comp: Any) -> None:
    seen = set()
    known = level_names(comp.kind)
    for token in comp.level_tokens:
        name = str(token).replace("_", "-")
        if name not in known:
            raise comp.error(
                f"unknown reasoning level '{token}'",
                token,
                "levels: " + ", ".join(r.replace("-", "_") for r in known),
            )
    for name, token in comp.study.get("levels", ()):
        if name in seen:
            raise comp.error(f"level '{token}' is listed twice", token, "list it once")
        seen.add(name)


def _capacities(comp: Any) -> tuple[int, ...] | None:
    """Robots each goal (capacity) or task (collaborative) needs."""
    if not (comp.kind.capacities or comp.kind.joint):
        return None
    return tuple(int(g.needs) for g in comp.goals.values())


def _known(comp: Any, end: Token) -> np.ndarray | str | None:
    if comp.random_knowledge and comp.knows:
        raise comp.error(
            "'knows random' and 'knows ROBOTS: GOALS' exclude each other",
            end,
            "keep one way of saying who knows which goal",
        )
    if comp.random_knowledge:
        return "random"
    if not comp.knows:
        return None
    return np.array([[g in comp.knows.get(r, set()) for g in comp.goals] for r in comp.robots])


def _obstacles(comp: Any) -> tuple[np.ndarray, ...]:
    """The obstacles, each clear of every robot and goal placed in the file."""
    out = []
    for corners, node in comp.obstacles:
        try:
            poly = polygon(corners)
        except InvalidArgumentError as exc:
            raise comp.error(exc.message, node, exc.hint) from None
        for spec in (*comp.robots.values(), *comp.goals.values()):
            if spec.place is None:
                continue
            point = np.array(spec.place[:2], dtype=float)
            radius = getattr(spec, "radius", None) or CLEARANCE
            if polygon_distance(point, point, poly) < radius:
                raise comp.error(
                    f"'{spec.name}' at {list(spec.place[:2])} lies in this obstacle",
                    node,
                    f"move '{spec.name}' or the obstacle",
                )
        out.append(poly)
    return tuple(out)
