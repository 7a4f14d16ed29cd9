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
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from epistemica._mission_events import compile_event
from epistemica.del_ import FORMULA_GRAMMAR, Check, Formula, build_imported_formula, range_names
from epistemica.del_.errors import EpistemicaError, SpecError
from epistemica.del_.language.parser import syntax_error
from epistemica.sim.events import EventRule, ObserverRule, expand
from epistemica.sim.levels import REASONING
from epistemica.sim.scenario import MISSIONS, OBSERVATIONS

__all__ = ["GoalSpec", "MissionCheck", "MissionParts", "RobotSpec", "compile_text"]

MISSION_GRAMMAR = Path(__file__).with_name("mission.lark")

#: The keywords that start a statement.
KEYWORDS = (
    "mission", "valid", "workspace", "robot", "goal", "task", "sensing", "knows", "learns",
    "initially", "event", "teammate", "policy", "check", "simulate",
)  # fmt: skip
SENSOR_TYPES = ("range", "bearing", "random")
#: Largest accepted magnitude of any number in a mission file.
MAX_NUMBER = 1e6
#: Most robots, goals (tasks), steps and trials a mission file may declare.
LIMITS = {"robots": 12, "goals": 64, "steps": 100_000, "trials": 100_000}
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

    kind: str
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

    @property
    def robot_names(self) -> tuple[str, ...]:
        return tuple(r.name for r in self.robots)

    @property
    def goal_names(self) -> tuple[str, ...]:
        return tuple(g.name for g in self.goals)


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


class MissionCompiler:
    """Walks the statements of one mission text and collects its parts."""

    def __init__(self, source: str, filename: str, library: dict[str, EventRule]) -> None:
        self.source, self.filename, self.library = source, filename, library
        self.robots: dict[str, RobotSpec] = {}
        self.goals: dict[str, GoalSpec] = {}
        self.kind: str | None = None
        self.kind_token: Any = None
        self.is_tasks = False
        self.options: dict[str, Any] = {}
        self.study: dict[str, Any] = {}
        self.valid: list[Formula] = []
        self.initially: list[Formula] = []
        self.learns: list[tuple[tuple[str, ...], Formula]] = []
        self.knows: dict[str, set[str]] = {}
        self.random_knowledge = False
        self.teammates: list[tuple[str, str, Token]] = []
        self.events: dict[str, EventRule] = {}
        self.policy: list[tuple[str, Any, Token]] = []
        self.checks: list[MissionCheck] = []
        self.step_triggers: list[tuple[int, Token]] = []
        self.level_tokens: list[Token] = []  # every level a line names, checked at the end

    # -- errors ------------------------------------------------------------------------

    def error(self, message: str, where: Token | Tree | None, hint: str | None = None):
        line = column = None
        if isinstance(where, Token):
            line, column = where.line, where.column
        elif isinstance(where, Tree):
            line, column = getattr(where.meta, "line", None), getattr(where.meta, "column", None)
        return SpecError(
            message, line=line, column=column, source=self.source, filename=self.filename,
            hint=hint,
        )  # fmt: skip

    def unknown(self, what: str, token: Token, known: Iterable[str]) -> SpecError:
        known = list(known)
        close = difflib.get_close_matches(str(token), known, n=1)
        hint = (
            f"did you mean '{close[0]}'?"
            if close
            else f"declared {what}s: " + (", ".join(known) or "none")
        )
        return self.error(f"unknown {what} '{token}'", token, hint)

    # -- names ---------------------------------------------------------------------------

    def is_robot(self, name: str) -> bool:
        return name in self.robots

    def is_goal(self, name: str) -> bool:
        return name in self.goals

    def is_declared(self, name: str) -> bool:
        return name in self.robots or name in self.goals

    def declared(self, kind: str) -> list[str]:
        """The declared names of a kind (``robot``, ``goal`` or ``place``: both)."""
        robots = list(self.robots) if kind in ("robot", "place") else []
        return robots + (list(self.goals) if kind in ("goal", "place") else [])

    def robot_name(self, token: Token) -> str:
        if str(token) not in self.robots:
            raise self.unknown("robot", token, self.robots)
        return str(token)

    def goal_name(self, token: Token) -> str:
        if str(token) not in self.goals:
            raise self.unknown("goal", token, self.goals)
        return str(token)

    # -- walking -----------------------------------------------------------------------

    def compile(self, tree: Tree) -> MissionParts:
        first = ("mission_decl", "robot_decl", "goal_decl", "task_decl", "workspace_decl")
        statements = sorted(tree.children, key=lambda t: t.data not in first)  # declarations
        for statement in statements:
            getattr(self, str(statement.data))(statement)
        return self.finish()

    def number(self, item, low: float = -MAX_NUMBER, high: float = MAX_NUMBER) -> float:
        text = str(item)
        if len(text) > 40:
            raise self.error(f"number of {len(text)} characters", item, "write a short number")
        try:
            value = float(text)
        except ValueError:
            raise self.error(f"expected a number, got '{text}'", item, "e.g. 5 or 2.5") from None
        if not math.isfinite(value) or not low <= value <= high:
            raise self.error(
                f"{text} is outside [{low:g}, {high:g}]", item, "use a value within the bounds"
            )
        return value

    def count(self, item, what: str, low: int = 1) -> int:
        value = self.number(item, low, LIMITS.get(what, MAX_NUMBER))
        if value != int(value):
            raise self.error(f"{what} must be a whole number, got {item}", item, "e.g. 5")
        return int(value)

    def new_name(self, name: str, token: Token, what: str) -> str:
        if name in self.robots or name in self.goals:
            raise self.error(f"{what} '{name}' is declared twice", token, "use distinct names")
        if name in KEYWORDS or name in ("and", "or", "not", "true", "false", "robots"):
            raise self.error(f"'{name}' is a reserved word", token, "choose another name")
        return name

    def expand_names(self, node: Tree) -> list[tuple[str, Token]]:
        """The names of a ``declared`` node: one, or a range ``r1..r5`` (``r01..r03``
        keeps its zeros), expanded as spec files expand them."""
        if node.data != "span":
            return [(str(node.children[0]), node.children[0])]
        return range_names(*node.children, self.error)

    def mission_decl(self, node: Tree) -> None:
        token = node.children[0]
        if self.kind is not None:
            raise self.error("the mission is declared twice", token, "keep one 'mission' line")
        if str(token) not in MISSIONS:
            raise self.unknown("mission", token, MISSIONS)
        self.kind, self.kind_token = str(token), token

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
            bounds = (0.0, MAX_NUMBER) if option.data == "speed" else (0.0, math.pi)
            limits[str(option.data)] = self.number(value, *bounds)
        for name, token in self.expand_names(declared):
            self.new_name(name, token, "robot")
            if len(self.robots) >= LIMITS["robots"]:
                raise self.error(
                    f"more than {LIMITS['robots']} robots", token, "the simulator's limit"
                )
            self.robots[name] = RobotSpec(name, token, str(sensor), self.place(place), **limits)

    def goal_decl(self, node: Tree) -> None:
        declared, place, needs, closed = node.children
        for name, token in self.expand_names(declared):
            self._goal(name, token, place, needs, closed is not None, tasks=False)

    def task_decl(self, node: Tree) -> None:
        declared, place = node.children
        for name, token in self.expand_names(declared):
            self._goal(name, token, place, None, False, tasks=True)

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

    # -- formulas ------------------------------------------------------------------------

    def fact(self, fml: Tree) -> Formula:
        """A propositional formula over assigned(ROBOT, GOAL) and closed(GOAL) atoms."""
        return self.formula(fml, epistemic=False)

    def build(self, fml: Tree) -> Formula:
        """The formula of a checked ``fml`` node (``closed(G)`` left as written)."""
        try:
            return build_imported_formula(fml.children[0])
        except SpecError:
            raise
        except EpistemicaError as exc:  # a bound the formula builder enforces
            raise self.error(exc.message, fml, exc.hint) from None

    def formula(self, fml: Tree, epistemic: bool) -> Formula:
        for node in fml.children[0].iter_subtrees_topdown():
            kind = node.data.rsplit("__", 1)[-1]
            if kind == "atom":
                self.atom(node)
            elif kind == "agent":
                token = node.children[0]
                if not epistemic:
                    raise self.error(
                        "a fact about configurations cannot speak of knowledge",
                        token,
                        "use assigned(ROBOT, GOAL) atoms with ~, &, |, ->, <->",
                    )
                self.robot_name(token)
            elif kind == "action" or (kind in ("announce", "announce_diamond") and not epistemic):
                raise self.error(
                    "actions and announcements are not part of mission formulas",
                    node,
                    "check them in an .epi spec file, or simulate the mission",
                )
        return expand(self.build(fml), tuple(self.robots))

    def atom(self, node: Tree) -> None:
        stem, args = node.children
        arguments = [] if args is None else args.children
        if str(stem) == "closed" and len(arguments) == 1:
            self.goal_name(arguments[0])
            return
        if str(stem) != "assigned" or len(arguments) != 2:
            raise self.error(
                f"unknown atom '{stem}'",
                stem,
                "mission formulas speak of assigned(ROBOT, GOAL) and closed(GOAL)",
            )
        self.robot_name(arguments[0])
        self.goal_name(arguments[1])

    # -- the whole ----------------------------------------------------------------------

    def finish(self) -> MissionParts:
        end = Token("NAME", "", line=max(1, self.source.count("\n") + 1), column=1)
        if self.kind is None:
            raise self.error(
                "the mission has no 'mission' line", end, "add e.g. 'mission rendezvous'"
            )
        if not self.robots:
            raise self.error(
                "the mission declares no robot", end, "add 'robot r1: range at (x, y)'"
            )
        if not self.goals:
            raise self.error("the mission declares no goal", end, "add 'goal g1 at (x, y)'")
        self._check_kind()
        self._check_steps()
        self._check_levels()
        return MissionParts(
            kind=self.kind,
            robots=tuple(self.robots.values()),
            goals=tuple(self.goals.values()),
            capacities=self._capacities(),
            options=self.options,
            valid=tuple(self.valid),
            initially=tuple(self.initially),
            learns=tuple(self.learns),
            known_goals=self._known(end),
            events=tuple(self.events.values()),
            teammates=tuple(self.teammates),
            policy=tuple(self.policy),
            checks=tuple(self.checks),
            trials=self.study.get("trials"),
            seed=self.study.get("seed"),
            levels=self.study.get("levels"),
        )

    def _check_kind(self) -> None:
        kind = self.kind
        if (kind == "multitask") != self.is_tasks:
            want = "task" if kind == "multitask" else "goal"
            raise self.error(
                f"a {kind} mission declares {want}s",
                self.kind_token,
                f"declare its places with '{want} NAME at (x, y)'",
            )
        needs = [g for g in self.goals.values() if g.needs is not None]
        if kind == "capacity":
            missing = [g for g in self.goals.values() if g.needs is None]
            if missing:
                raise self.error(
                    "every goal of a capacity mission says how many robots it needs",
                    missing[0].token,
                    "write 'goal NAME at (x, y) needs 2'",
                )
        elif needs:
            raise self.error(
                f"'needs' in a {kind} mission", needs[0].needs_token, "use 'mission capacity'"
            )
        workspace = self.options.get("workspace", 30.0)
        if workspace <= 2.0 and any(g.place is None for g in self.goals.values()):
            raise self.error(
                f"a workspace of {workspace:g} m leaves no room for goals at random "
                "(they keep 1 m from the borders)",
                self.kind_token,
                "enlarge 'workspace', or place the goals",
            )

    def _check_steps(self) -> None:
        limit = self.options.get("max_steps", DEFAULT_STEPS)
        for step, token in self.step_triggers:
            if step >= limit:
                raise self.error(
                    f"a trigger at step {step} never fires: trials stop after {limit} steps",
                    token,
                    f"choose a step below {limit}, or raise 'simulate steps'",
                )

    def _check_levels(self) -> None:
        seen = set()
        for token in self.level_tokens:
            name = str(token).replace("_", "-")
            if name not in REASONING:
                raise self.error(
                    f"unknown reasoning level '{token}'",
                    token,
                    "levels: " + ", ".join(r.replace("-", "_") for r in REASONING),
                )
        for name, token in self.study.get("levels", ()):
            if name in seen:
                raise self.error(f"level '{token}' is listed twice", token, "list it once")
            seen.add(name)

    def _capacities(self) -> tuple[int, ...] | None:
        if self.kind != "capacity":
            return None
        return tuple(int(g.needs) for g in self.goals.values())

    def _known(self, end: Token) -> np.ndarray | str | None:
        if self.random_knowledge and self.knows:
            raise self.error(
                "'knows random' and 'knows ROBOTS: GOALS' exclude each other",
                end,
                "keep one way of saying who knows which goal",
            )
        if self.random_knowledge:
            return "random"
        if not self.knows:
            return None
        return np.array([[g in self.knows.get(r, set()) for g in self.goals] for r in self.robots])


def everyone_observes(rule: EventRule) -> EventRule:
    """``rule`` observed in full by every robot."""
    return dataclasses.replace(rule, full=(ObserverRule("robots"),), partial=())


def compile_text(
    text: str, filename: str, library: dict[str, EventRule] | None = None
) -> MissionParts:
    """The parts of the mission written in ``text``."""
    return MissionCompiler(text, filename, library or {}).compile(parse_tree(text, filename))


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
