"""Compiling the parse tree of a mission file into the parts of a Mission.

Helper of :mod:`epistemica.mission`. The grammar is ``mission.lark`` (which imports the
formula rules of the DEL language); every mistake raises a located
:class:`~epistemica.del_.errors.SpecError` (or :class:`ParseError` for malformed text).
"""

from __future__ import annotations

import difflib
import functools
import math
import re
from pathlib import Path
from typing import Any

import numpy as np
from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from epistemica.del_ import FORMULA_GRAMMAR, Check, Formula, build_imported_formula
from epistemica.del_.errors import EpistemicaError, SpecError
from epistemica.del_.language.parser import syntax_error
from epistemica.sim.scenario import EVENTS, MISSIONS, OBSERVATIONS, SEEN_BY

MISSION_GRAMMAR = Path(__file__).with_name("mission.lark")

#: The keywords that start a statement.
KEYWORDS = (
    "mission", "valid", "workspace", "robot", "goal", "task", "sensing", "knows", "learns",
    "initially", "event", "teammate", "check", "simulate",
)  # fmt: skip
SENSOR_TYPES = ("range", "bearing", "random")
#: Largest accepted magnitude of any number in a mission file.
MAX_NUMBER = 1e6
#: Most robots, goals (tasks), steps and trials a mission file may declare.
LIMITS = {"robots": 12, "goals": 64, "steps": 100_000, "trials": 100_000}


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
    """Walks the statements of one mission text and collects its parts (a dict)."""

    def __init__(self, source: str, filename: str) -> None:
        self.source, self.filename = source, filename
        self.robots: dict[str, dict[str, Any]] = {}
        self.goals: dict[str, dict[str, Any]] = {}
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
        self.events: dict[str, str] = {}
        self.checks: list[Check] = []
        self.formula_nodes: list[tuple[Tree, str]] = []

    # -- errors ------------------------------------------------------------------------

    def error(self, message: str, where: Token | Tree | None, hint: str | None = None):
        line = column = None
        if isinstance(where, Token):
            line, column = where.line, where.column
        elif isinstance(where, Tree):
            line, column = getattr(where.meta, "line", None), getattr(where.meta, "column", None)
        return SpecError(
            message,
            line=line,
            column=column,
            source=self.source,
            filename=self.filename,
            hint=hint,
        )

    def unknown(self, what: str, token: Token, known) -> SpecError:
        close = difflib.get_close_matches(str(token), list(known), n=1)
        hint = (
            f"did you mean '{close[0]}'?"
            if close
            else f"declared {what}s: " + (", ".join(known) or "none")
        )
        return self.error(f"unknown {what} '{token}'", token, hint)

    # -- walking -----------------------------------------------------------------------

    def compile(self, tree: Tree) -> dict[str, Any]:
        first = ("mission_decl", "robot_decl", "goal_decl", "task_decl", "workspace_decl")
        statements = sorted(tree.children, key=lambda t: t.data not in first)  # declarations
        for statement in statements:
            getattr(self, str(statement.data))(statement)
        return self.finish(tree)

    def number(self, item, low: float = -MAX_NUMBER, high: float = MAX_NUMBER) -> float:
        text = str(item)
        if len(text) > 40:
            raise self.error(f"number of {len(text)} characters", item, "write a short number")
        value = float(text)
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
        if name in KEYWORDS or name in ("and", "or", "not", "true", "false"):
            raise self.error(f"'{name}' is a reserved word", token, "choose another name")
        return name

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

    def place(self, node: Tree):
        if node.data == "random":
            return None
        x, y, heading = node.children
        point = [self.number(x), self.number(y)]
        if heading is not None:
            point.append(self.number(heading, -4 * math.pi, 4 * math.pi))
        return (point, node)

    def expand(self, node: Tree, what: str) -> list[tuple[str, Token]]:
        """The names of a ``declared`` node: one, or a range ``r1..r5``."""
        if node.data != "declared_range":
            return [(str(node.children[0]), node.children[0])]
        first, last = node.children
        a, b = re.fullmatch(r"(.*?)(\d+)", str(first)), re.fullmatch(r"(.*?)(\d+)", str(last))
        if not a or not b or a.group(1) != b.group(1) or int(a.group(2)) > int(b.group(2)):
            raise self.error(
                f"bad {what} range '{first}..{last}'", first, "write e.g. r1..r5 (same stem)"
            )
        low, high = int(a.group(2)), int(b.group(2))
        if high - low >= LIMITS["goals"] or len(a.group(2)) > 6:
            raise self.error(f"the range '{first}..{last}' is too long", first, "fewer names")
        return [(f"{a.group(1)}{i}", first) for i in range(low, high + 1)]

    def robot_decl(self, node: Tree) -> None:
        declared, sensor, place, *options = node.children
        if str(sensor) not in SENSOR_TYPES:
            raise self.unknown("sensor", sensor, SENSOR_TYPES)
        for name, token in self.expand(declared, "robot"):
            self._robot(name, token, str(sensor), place, options)

    def _robot(self, name, name_token, sensor: str, place, options) -> None:
        name = self.new_name(name, name_token, "robot")
        if len(self.robots) >= LIMITS["robots"]:
            raise self.error(
                f"more than {LIMITS['robots']} robots", name_token, "the simulator's limit"
            )
        robot = {"token": name_token, "sensor": sensor, "place": self.place(place)}
        for option in options:
            value = option.children[0]
            if option.data == "speed":
                robot["speed"] = self.number(value, 0.0)
            else:
                robot["turn"] = self.number(value, 0.0, math.pi)
        self.robots[name] = robot

    def goal_decl(self, node: Tree) -> None:
        declared, place, needs = node.children
        for name, token in self.expand(declared, "goal"):
            self._goal(name, token, place, needs, tasks=False)

    def task_decl(self, node: Tree) -> None:
        declared, place = node.children
        for name, token in self.expand(declared, "task"):
            self._goal(name, token, place, None, tasks=True)

    def _goal(self, name, name_token, place, needs, tasks: bool) -> None:
        name = self.new_name(name, name_token, "task" if tasks else "goal")
        if self.goals and tasks != self.is_tasks:
            raise self.error(
                "a mission has goals or tasks, not both", name_token, "use one kind throughout"
            )
        if len(self.goals) >= LIMITS["goals"]:
            raise self.error(f"more than {LIMITS['goals']} goals", name_token, "fewer goals")
        self.is_tasks = tasks
        self.goals[name] = {
            "token": name_token,
            "place": self.place(place),
            "needs": None if needs is None else self.count(needs, "needs"),
            "needs_token": needs,
        }

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

    def learns_decl(self, node: Tree) -> None:
        robots, fml = node.children
        names = tuple(self.robot_name(r) for r in robots.children)
        self.learns.append((names, self.fact(fml)))

    def valid_decl(self, node: Tree) -> None:
        self.valid.append(self.fact(node.children[0]))

    def initially_decl(self, node: Tree) -> None:
        self.initially.append(self.fact(node.children[0]))

    def event_decl(self, node: Tree) -> None:
        kind, seen_by = node.children
        if str(kind) not in EVENTS:
            raise self.unknown("event", kind, EVENTS)
        if str(seen_by) not in SEEN_BY:
            raise self.unknown("observer rule", seen_by, SEEN_BY)
        if str(kind) in self.events:
            raise self.error(f"event '{kind}' is declared twice", kind, "keep one")
        self.events[str(kind)] = str(seen_by)

    def check_decl(self, node: Tree) -> None:
        string, fml, verdict = node.children
        formula = self.formula(fml, epistemic=True)
        text = " ".join(self.source[fml.meta.start_pos : fml.meta.end_pos].split())
        expected = verdict is None or str(verdict.children[0]) == "true"
        self.checks.append(
            Check(
                str(string)[1:-1],
                text,
                formula,
                expected,
                self.filename,
                string.line,
                string.column,
            )
        )

    def simulate_decl(self, node: Tree) -> None:
        for option in node.children:
            key, value = str(option.data), option.children[0]
            if key == "levels":
                self.study["levels_token"] = value
                self.study["levels"] = tuple(str(t).replace("_", "-") for t in value.children)
            elif key == "success_radius":
                self.options[key] = self.number(value, 1e-6)
            elif key == "max_steps":
                self.options[key] = self.count(value, "steps")
            elif key == "dwell":
                self.options[key] = self.count(value, "steps")
            elif key == "seed":
                self.study[key] = self.count(value, "seed", low=0)
            else:
                self.study[key] = self.count(value, "trials")

    # -- names and formulas -------------------------------------------------------------

    def robot_name(self, token: Token) -> str:
        if str(token) not in self.robots:
            raise self.unknown("robot", token, self.robots)
        return str(token)

    def goal_name(self, token: Token) -> str:
        if str(token) not in self.goals:
            raise self.unknown("goal", token, self.goals)
        return str(token)

    def fact(self, fml: Tree) -> Formula:
        """A propositional formula over assigned(ROBOT, GOAL) atoms."""
        return self.formula(fml, epistemic=False)

    def formula(self, fml: Tree, epistemic: bool) -> Formula:
        tree = fml.children[0]
        for node in tree.iter_subtrees_topdown():
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
        try:
            return build_imported_formula(tree)
        except SpecError:
            raise
        except EpistemicaError as exc:  # a bound the formula builder enforces
            raise self.error(exc.message, fml, exc.hint) from None

    def atom(self, node: Tree) -> None:
        stem, args = node.children
        if str(stem) != "assigned" or args is None or len(args.children) != 2:
            raise self.error(
                f"unknown atom '{stem}'",
                stem,
                "mission formulas speak of assigned(ROBOT, GOAL)",
            )
        robot, goal = args.children
        self.robot_name(robot)
        self.goal_name(goal)

    # -- the whole ----------------------------------------------------------------------

    def finish(self, tree: Tree) -> dict[str, Any]:
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
        kind = self.kind
        if (kind == "multitask") != self.is_tasks:
            want = "task" if kind == "multitask" else "goal"
            raise self.error(
                f"a {kind} mission declares {want}s",
                self.kind_token,
                f"declare its places with '{want} NAME at (x, y)'",
            )
        needs = [g["needs"] for g in self.goals.values()]
        if kind == "capacity":
            missing = [g for g in self.goals.values() if g["needs"] is None]
            if missing:
                raise self.error(
                    "every goal of a capacity mission says how many robots it needs",
                    missing[0]["token"],
                    "write 'goal NAME at (x, y) needs 2'",
                )
        elif any(n is not None for n in needs):
            token = next(g["needs_token"] for g in self.goals.values() if g["needs"] is not None)
            raise self.error(f"'needs' in a {kind} mission", token, "use 'mission capacity'")
        if self.random_knowledge and self.knows:
            raise self.error(
                "'knows random' and 'knows ROBOTS: GOALS' exclude each other",
                end,
                "keep one way of saying who knows which goal",
            )
        known = "random" if self.random_knowledge else None
        if self.knows:
            known = np.array(
                [[g in self.knows.get(r, set()) for g in self.goals] for r in self.robots]
            )
        return {
            "kind": kind,
            "robots": tuple(self.robots),
            "goals": tuple(self.goals),
            "robot_specs": self.robots,
            "goal_specs": self.goals,
            "capacities": tuple(needs) if kind == "capacity" else None,
            "options": self.options,
            "valid": tuple(self.valid),
            "initially": tuple(self.initially),
            "learns": tuple(self.learns),
            "known_goals": known,
            "events": tuple(self.events.items()),
            "teammates": tuple(self.teammates),
            "checks": tuple(self.checks),
            "study": self.study,
        }


def compile_text(text: str, filename: str) -> dict[str, Any]:
    """The parts of the mission written in ``text``."""
    return MissionCompiler(text, filename).compile(parse_tree(text, filename))
