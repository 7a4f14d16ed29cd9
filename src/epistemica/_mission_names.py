"""The names, numbers and formulas of a mission file, checked where they are written.

Helper of :mod:`epistemica._mission_compiler`: :class:`MissionScope` holds the robots and
goals declared so far and turns every mistake into a located
:class:`~epistemica.del_.errors.SpecError` (file:line:col, the line with a caret, a hint).
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable

from lark import Token, Tree

from epistemica._mission_parts import GoalSpec, RobotSpec
from epistemica.del_ import Formula, build_imported_formula, range_names
from epistemica.del_.errors import EpistemicaError, SpecError
from epistemica.sim.engine.events import expand

__all__ = ["KEYWORDS", "LIMITS", "MAX_NUMBER", "MissionScope"]

#: The keywords that start a statement.
KEYWORDS = (
    "mission", "valid", "workspace", "robot", "goal", "task", "sensing", "knows", "learns",
    "initially", "event", "teammate", "policy", "check", "simulate", "obstacle",
    "plausibility",
)  # fmt: skip
#: Largest accepted magnitude of any number in a mission file.
MAX_NUMBER = 1e6
#: Most robots, goals (tasks), steps and trials a mission file may declare.
LIMITS = {"robots": 12, "goals": 64, "steps": 100_000, "trials": 100_000}


#: Formula nodes that change the model: not part of a fact about configurations.
_DYNAMIC = ("announce", "announce_diamond", "radical_upgrade", "conservative_upgrade")


class MissionScope:
    """The robots and goals of a mission declared so far, and located errors."""

    def __init__(self, source: str, filename: str) -> None:
        self.source, self.filename = source, filename
        self.robots: dict[str, RobotSpec] = {}
        self.goals: dict[str, GoalSpec] = {}
        self.team: int | None = None  # the value of N in spans r1..rN
        self.parametric = False  # whether a span uses N

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
        first, last = node.children
        if str(last) == str(first).rstrip("0123456789") + "N":  # r1..rN: N robots
            if self.team is None:
                raise self.error(
                    f"{first}..{last} needs the team size N",
                    last,
                    "add 'simulate robots 3' (the default N), or sweep it: "
                    "epistemica sweep --mission FILE --robots 2..8",
                )
            self.parametric = True
            last = last.update(value=f"{str(last)[:-1]}{self.team}")
        return range_names(first, last, self.error)

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
            elif kind == "action" or (kind in _DYNAMIC and not epistemic):
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
