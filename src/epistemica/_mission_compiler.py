"""Compiling the parse tree of a mission file into its parts (:class:`MissionParts`).

Helper of :mod:`epistemica.mission`. The grammar is ``mission.lark`` (which imports the
formula rules of the DEL language); every mistake raises a located
:class:`~epistemica.del_.errors.SpecError` (or :class:`ParseError` for malformed text).
Event declarations are compiled by :mod:`epistemica._mission_events`.
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import math
from pathlib import Path
from typing import Any

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from epistemica._mission_events import compile_event
from epistemica._mission_names import KEYWORDS, LIMITS, MAX_NUMBER, MissionScope
from epistemica._mission_parts import GoalSpec, MissionCheck, MissionParts, RobotSpec, assemble
from epistemica._mission_plausibility import PlausibilityOrder, plausibility_order
from epistemica.del_ import FORMULA_GRAMMAR, Check, Formula
from epistemica.del_.language.parser import syntax_error
from epistemica.sim.engine.events import EventRule, ObserverRule
from epistemica.sim.engine.scenario import OBSERVATIONS
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.registry import KINDS

__all__ = ["compile_events", "compile_text", "everyone_observes"]

MISSION_GRAMMAR = Path(__file__).with_name("mission.lark")

SENSOR_TYPES = ("range", "bearing", "random")


@functools.cache
def _lark() -> Lark:
    return Lark.open(
        str(MISSION_GRAMMAR),
        parser="lalr",
        propagate_positions=True,
        maybe_placeholders=True,
        import_paths=[str(FORMULA_GRAMMAR.parent)],
    )


def parse_tree(text: str, filename: str) -> Tree:
    """The parse tree of a mission text; malformed text raises a located ParseError."""
    try:
        return _lark().parse(text)
    except UnexpectedInput as exc:
        error = syntax_error(exc, text, filename)
        token = getattr(exc, "token", None)
        if error.hint is None and isinstance(token, Token) and token.type == "NAME":
            close = difflib.get_close_matches(str(token), KEYWORDS, n=1)
            if close:
                error.hint = f"did you mean '{close[0]}'?"
        raise error from None


class MissionCompiler(MissionScope):
    """Walks the statements of one mission text and collects its parts."""

    def __init__(
        self, source: str, filename: str, library: dict[str, EventRule], team: int | None = None
    ) -> None:
        super().__init__(source, filename)
        self.team = team
        self.library = library
        self.kind: MissionKind | None = None
        self.kind_token: Any = None
        self.is_tasks = False
        self.options: dict[str, Any] = {}
        self.study: dict[str, Any] = {}
        self.valid: list[Formula] = []
        self.initially: list[Formula] = []
        self.learns: list[tuple[tuple[str, ...], Formula]] = []
        self.plausibility: list[PlausibilityOrder] = []
        self.knows: dict[str, set[str]] = {}
        self.random_knowledge = False
        self.teammates: list[tuple[str, str, Token]] = []
        self.events: dict[str, EventRule] = {}
        self.event_tokens: dict[str, Token] = {}
        self.policy: list[tuple[str, Any, Token]] = []
        self.checks: list[MissionCheck] = []
        self.step_triggers: list[tuple[int, Token]] = []
        self.level_tokens: list[Token] = []  # every level a line names, checked at the end
        self.obstacles: list[tuple[list[tuple[float, float]], Tree]] = []

    # -- walking -----------------------------------------------------------------------

    def compile(self, tree: Tree) -> MissionParts:
        first = ("mission_decl", "robot_decl", "goal_decl", "task_decl", "workspace_decl")
        statements = sorted(tree.children, key=lambda t: t.data not in first)  # declarations
        if self.team is None:
            self.team = self._default_team(tree)
        for statement in statements:
            getattr(self, str(statement.data))(statement)
        return self.finish()

    def _default_team(self, tree: Tree) -> int | None:
        """N of ``simulate robots N`` (the last one), the team size of spans r1..rN."""
        team = None
        for statement in tree.children:
            if statement.data == "simulate_decl":
                for option in statement.children:
                    if option.data == "team_size":
                        team = self.count(option.children[0], "robots")
        return team

    def mission_decl(self, node: Tree) -> None:
        token = node.children[0]
        if self.kind is not None:
            raise self.error("the mission is declared twice", token, "keep one 'mission' line")
        if str(token) not in KINDS:
            raise self.unknown("mission", token, tuple(KINDS))
        self.kind, self.kind_token = KINDS[str(token)], token

    def workspace_decl(self, node: Tree) -> None:
        size, bounded = node.children
        self.options["workspace"] = self.number(size, 1e-3)
        self.options["bounded"] = bounded is not None

    def place(self, node: Tree) -> tuple[float, ...] | None:
        if node.data == "random":
            return None
        x, y, heading = node.children
        point = [self.number(x), self.number(y)]
        if heading is not None:
            point.append(self.number(heading, -4 * math.pi, 4 * math.pi))
        return tuple(point)

    def robot_decl(self, node: Tree) -> None:
        declared, sensor, place, *options = node.children
        if str(sensor) not in SENSOR_TYPES:
            raise self.unknown("sensor", sensor, SENSOR_TYPES)
        limits = {"speed": 1.0, "turn": math.pi}
        for option in options:
            value = option.children[0]
            bounds = (0.0, math.pi) if option.data == "turn" else (0.0, MAX_NUMBER)
            limits[str(option.data)] = self.number(value, *bounds)
        for name, token in self.expand_names(declared):
            self.new_name(name, token, "robot")
            if len(self.robots) >= LIMITS["robots"]:
                raise self.error(
                    f"more than {LIMITS['robots']} robots", token, "the simulator's limit"
                )
            self.robots[name] = RobotSpec(name, token, str(sensor), self.place(place), **limits)

    def obstacle_decl(self, node: Tree) -> None:
        corners = [(self.number(c.children[0]), self.number(c.children[1])) for c in node.children]
        self.obstacles.append((corners, node))

    def goal_decl(self, node: Tree) -> None:
        declared, place, needs, closed = node.children
        for name, token in self.expand_names(declared):
            self._goal(name, token, place, needs, closed is not None, tasks=False)

    def task_decl(self, node: Tree) -> None:
        declared, place, needs = node.children
        for name, token in self.expand_names(declared):
            self._goal(name, token, place, needs, False, tasks=True)

    def _goal(self, name, token, place, needs, closed: bool, tasks: bool) -> None:
        self.new_name(name, token, "task" if tasks else "goal")
        if self.goals and tasks != self.is_tasks:
            raise self.error(
                "a mission has goals or tasks, not both", token, "use one kind throughout"
            )
        if len(self.goals) >= LIMITS["goals"]:
            raise self.error(f"more than {LIMITS['goals']} goals", token, "fewer goals")
        self.is_tasks = tasks
        count = None if needs is None else self.count(needs, "needs")
        self.goals[name] = GoalSpec(name, token, self.place(place), count, closed, needs)

    def sensing_decl(self, node: Tree) -> None:
        for option in node.children:
            value = option.children[0]
            key = str(option.data)
            if key == "observation":
                if str(value) not in OBSERVATIONS:
                    raise self.unknown("observation model", value, OBSERVATIONS)
                self.options[key] = str(value)
            elif key == "angle_noise":
                self.options[key] = self.number(value, 0.0, 100.0)
            else:
                self.options[key] = self.number(value, 0.0)

    def knows_decl(self, node: Tree) -> None:
        robots, goals = node.children
        for goal in goals.children:
            self.goal_name(goal)
        for robot in robots.children:
            known = self.knows.setdefault(self.robot_name(robot), set())
            known.update(str(g) for g in goals.children)

    def knows_random(self, node: Tree) -> None:
        self.random_knowledge = True

    def teammate_decl(self, node: Tree) -> None:
        robot, level = node.children
        if str(robot) != "random":
            self.robot_name(robot)
        if self.teammates:
            raise self.error("one 'teammate' line per mission", robot, "keep one")
        self.teammates.append((str(robot), str(level).replace("_", "-"), level))
        self.level_tokens.append(level)

    def learns_decl(self, node: Tree) -> None:
        robots, fml = node.children
        names = tuple(self.robot_name(r) for r in robots.children)
        self.learns.append((names, self.fact(fml)))

    def plausibility_decl(self, node: Tree) -> None:
        self.plausibility.append(plausibility_order(self, node))

    def valid_decl(self, node: Tree) -> None:
        self.valid.append(self.fact(node.children[0]))

    def initially_decl(self, node: Tree) -> None:
        self.initially.append(self.fact(node.children[0]))

    def event_library(self, node: Tree) -> None:
        name, seen_by = node.children
        if str(name) not in self.library:
            raise self.unknown("library event", name, self.library)
        if str(seen_by) not in ("nearby", "everyone"):
            raise self.unknown("observer rule", seen_by, ("nearby", "everyone"))
        self._add_event(name, self.library[str(name)], seen_by=str(seen_by))

    def event_decl(self, node: Tree) -> None:
        self._add_event(node.children[0], compile_event(self, node))

    def _add_event(self, token: Token, rule: EventRule, seen_by: str = "nearby") -> None:
        if rule.name in self.events:
            raise self.error(f"event '{rule.name}' is declared twice", token, "keep one")
        if seen_by == "everyone":
            rule = everyone_observes(rule)
        self.events[rule.name] = rule
        self.event_tokens[rule.name] = token

    def policy_decl(self, node: Tree) -> None:
        for option in node.children:
            name, value = option.children
            self.policy.append((str(name), str(value), name))

    def check_decl(self, node: Tree) -> None:
        string, when, fml, verdict = node.children
        formula = self.formula(fml, epistemic=True)
        text = " ".join(self.source[fml.meta.start_pos : fml.meta.end_pos].split())
        expected = verdict is None or str(verdict.children[0]) == "true"
        check = Check(
            str(string)[1:-1], text, formula, expected, self.filename, string.line, string.column
        )
        if when is None:
            self.checks.append(MissionCheck(check))
            return
        steps, seed, level = when.children
        self.checks.append(
            MissionCheck(
                check,
                self.count(steps, "steps", low=0),
                None if seed is None else self.count(seed, "seed", low=0),
                None if level is None else str(level).replace("_", "-"),
            )
        )
        if level is not None:
            self.level_tokens.append(level)

    def simulate_decl(self, node: Tree) -> None:
        for option in node.children:
            key, value = str(option.data), option.children[0]
            if key == "team_size":
                continue  # read before the declarations (_default_team)
            if key == "levels":
                self.study["levels"] = tuple((str(t).replace("_", "-"), t) for t in value.children)
                self.level_tokens.extend(value.children)
            elif key == "success_radius":
                self.options[key] = self.number(value, 1e-6)
            elif key in ("max_steps", "dwell"):
                self.options[key] = self.count(value, "steps")
            elif key == "seed":
                self.study[key] = self.count(value, "seed", low=0)
            else:
                self.study[key] = self.count(value, "trials")

    # -- the whole ----------------------------------------------------------------------

    def finish(self) -> MissionParts:
        """The parts, after the checks that need the whole file."""
        return assemble(self)


def everyone_observes(rule: EventRule) -> EventRule:
    """``rule`` observed in full by every robot."""
    return dataclasses.replace(rule, full=(ObserverRule("robots"),), partial=())


def compile_text(
    text: str, filename: str, library: dict[str, EventRule] | None = None, team: int | None = None
) -> MissionParts:
    """The parts of the mission written in ``text`` (``team``: N of its spans r1..rN)."""
    compiler = MissionCompiler(text, filename, library or {}, team)
    return compiler.compile(parse_tree(text, filename))


def compile_events(text: str, filename: str) -> dict[str, EventRule]:
    """The ``event`` declarations of a library text (no robots or goals: only parameters)."""
    compiler = MissionCompiler(text, filename, {})
    for statement in parse_tree(text, filename).children:
        if statement.data != "event_decl":
            raise compiler.error(
                "a library holds event declarations only", statement, "move it to a mission"
            )
        compiler.event_decl(statement)
    return compiler.events
