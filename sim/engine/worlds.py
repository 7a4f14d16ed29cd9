"""Goal configurations as worlds: the one place where a mission meets the logic.

A configuration assigns each robot a goal (a row of goal indices, one per robot); as a
world it makes the atoms ``assigned(ROBOT, GOAL)`` of that assignment true. This module
turns configuration rows into a world table for :mod:`epistemica.del_.state`
(:class:`ConfigurationTable`), evaluates facts about configurations on rows
(:func:`fact_mask`, through the logic's one propositional evaluator), writes the facts the
simulator's events teach (:func:`assignment_atom`, :func:`closed_fact`, the atoms of a
goal) and builds the Kripke model over the configurations (:func:`configuration_model`).

Examples
--------
>>> import numpy as np
>>> from epistemica.del_ import EpistemicState, Observation
>>> rows = np.array([[0, 1], [1, 0]])
>>> model = configuration_model(["r1", "r2"], ["g1", "g2"], rows)
>>> model.n_worlds, model.holds("assigned(r1, g1) <-> assigned(r2, g2)")
(2, True)
>>> state = EpistemicState(["r1", "r2"])
>>> _ = state.observe(Observation("told", full={"r1"}, pre="assigned(r1, g1)"))
>>> after = configuration_model(["r1", "r2"], ["g1", "g2"], rows, state)
>>> after.holds("K[r1] assigned(r2, g2) & ~K[r2] assigned(r2, g2)")
True
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Sequence

import numpy as np

from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.explicit.checker import propositional_truth
from epistemica.del_.language.formula import (
    And,
    Atom,
    Formula,
    Not,
    Top,
    conjunction,
    disjunction,
)
from epistemica.del_.models import KnowledgeStructure, KripkeModel
from epistemica.del_.state import EpistemicState
from epistemica.del_.state.explicit import group_model
from epistemica.del_.state.symbolic import group_structure, world_space
from epistemica.sim.kinds.base import MissionKind
from epistemica.sim.kinds.registry import kind_named

__all__ = [
    "MAX_CONFIGURATIONS",
    "ConfigurationTable",
    "assignment_atom",
    "closed_fact",
    "configuration_atoms",
    "configuration_law",
    "configuration_model",
    "configuration_structure",
    "fact_mask",
    "goal_atoms",
]

#: Configurations beyond which an explicit model is refused.
MAX_CONFIGURATIONS = 200_000


def assignment_atom(robot: str, goal: str) -> str:
    """The atom saying that ``robot`` goes to ``goal``.

    Examples
    --------
    >>> assignment_atom("r1", "g2")
    'assigned(r1, g2)'
    """
    return f"assigned({robot}, {goal})"


def goal_atoms(robots: Sequence[str], goal: str) -> frozenset[str]:
    """Every robot's atom for ``goal``: what a robot becomes aware of when it learns that
    the goal exists."""
    return frozenset(assignment_atom(r, goal) for r in robots)


def closed_fact(robots: Sequence[str], goal: str) -> Formula:
    """No robot goes to ``goal`` (a task done, a goal closed).

    Examples
    --------
    >>> str(closed_fact(["r1", "r2"], "g3"))
    '~assigned(r1, g3) & ~assigned(r2, g3)'
    """
    out: Formula = Top()
    for r in robots:
        literal = Not(Atom("assigned", (r, goal)))
        out = literal if isinstance(out, Top) else And(out, literal)
    return out


class ConfigurationTable:
    """Configuration rows as a :class:`~epistemica.del_.state.explicit.WorldTable`.

    Parameters
    ----------
    rows : array_like
        ``(k, n)`` goal indices, one row per configuration.
    robots, goals : sequence of str
        Names; the atoms are ``assigned(ROBOT, GOAL)``.
    """

    def __init__(self, rows, robots: Sequence[str], goals: Sequence[str]) -> None:
        self.rows = np.asarray(rows)
        self.robots, self.goals = tuple(robots), tuple(goals)
        n = len(self.robots)
        if self.rows.ndim != 2 or self.rows.shape[1] != n:
            raise InvalidArgumentError(
                f"configurations must be (k, {n}) goal indices, got {self.rows.shape}",
                hint="one row per configuration, one column per robot",
            )
        self._where = {
            assignment_atom(r, g): (i, j)
            for i, r in enumerate(self.robots)
            for j, g in enumerate(self.goals)
        }
        self._masks: dict[str, np.ndarray] = {}
        self._conceivable: dict[frozenset, np.ndarray] = {}

    @property
    def n_worlds(self) -> int:
        return self.rows.shape[0]

    @functools.cached_property
    def atoms(self) -> tuple[str, ...]:
        return tuple(self._where)

    def atom_mask(self, atom: str) -> np.ndarray:
        mask = self._masks.get(atom)
        if mask is None:
            if atom not in self._where:
                raise InvalidArgumentError(
                    f"'{atom}' is not a fact about configurations",
                    hint=f"use assigned(ROBOT, GOAL) with robots {', '.join(self.robots)} "
                    f"and goals {', '.join(self.goals)}",
                )
            robot, goal = self._where[atom]
            mask = self._masks[atom] = self.rows[:, robot] == goal
        return mask

    def conceivable(self, unaware: frozenset[str]) -> np.ndarray:
        found = self._conceivable.get(unaware)
        if found is not None:
            return found
        allowed = np.ones((len(self.robots), len(self.goals)), dtype=bool)
        for atom in unaware:
            where = self._where.get(atom)
            if where is not None:
                allowed[where] = False
        if allowed.all():
            found = np.ones(self.n_worlds, dtype=bool)
        elif (allowed == allowed[0]).all():  # whole goals unknown: a lookup per goal
            found = allowed[0][self.rows].all(axis=1)
        else:
            found = allowed[np.arange(len(self.robots)), self.rows].all(axis=1)
        self._conceivable[unaware] = found
        return found

    def world_names(self) -> tuple[str, ...]:
        return tuple(" ".join(self.goals[g] for g in row) for row in self.rows.tolist())

    def valuation(self) -> np.ndarray:
        k, n, m = self.n_worlds, len(self.robots), len(self.goals)
        val = np.zeros((k, n * m), dtype=bool)
        val[np.arange(k)[:, None], np.arange(n)[None, :] * m + self.rows] = True
        return val


def fact_mask(
    formula: Formula | str, rows, robots: Sequence[str], goals: Sequence[str]
) -> np.ndarray:
    """Which configurations ``rows`` satisfy the propositional ``formula`` over
    ``assigned(ROBOT, GOAL)`` atoms.

    Examples
    --------
    >>> rows = np.array([[0, 1], [1, 1], [1, 0]])
    >>> fact_mask("assigned(a, x) | ~assigned(b, y)", rows, ["a", "b"], ["x", "y"]).tolist()
    [True, False, True]
    """
    table = ConfigurationTable(rows, robots, goals)
    return propositional_truth(formula, table.n_worlds, table.atom_mask)


def configuration_model(
    robots: Sequence[str],
    goals: Sequence[str],
    rows,
    state: EpistemicState | None = None,
) -> KripkeModel:
    """The model over the configurations ``rows`` after what ``state`` recorded (default:
    nothing; every robot then considers every configuration possible).

    Worlds are named ``"g1 g2@0"``: the goals in robot order, then the copy of the group
    semantics (``@0`` the actual one; see :func:`epistemica.del_.state.explicit.group_model`).
    """
    rows = np.asarray(rows)
    if rows.ndim == 2 and rows.shape[0] == 0:
        raise ModelError("no configuration to build a model over", hint="add goals")
    if rows.shape[0] > MAX_CONFIGURATIONS:
        raise ModelError(
            f"{rows.shape[0]} configurations exceed the explicit limit of {MAX_CONFIGURATIONS}",
            hint="fewer robots or goals, or a `valid` constraint that leaves fewer",
        )
    table = ConfigurationTable(rows, robots, goals)
    return group_model(EpistemicState(robots) if state is None else state, table)


def configuration_law(
    kind: str | MissionKind,
    robots: Sequence[str],
    goals: Sequence[str],
    capacities: Sequence[int] | None = None,
    constraints: Sequence[Formula] = (),
) -> Formula:
    """The valid configurations as a propositional law over ``assigned(ROBOT, GOAL)``
    atoms, for the symbolic backend (no configuration is listed): each robot goes to one
    goal, and the mission kind (rendezvous: all to one; allocation: no goal shared;
    capacity: goal ``g`` takes ``capacities[g]`` robots) and ``constraints`` hold.

    Examples
    --------
    >>> from epistemica.del_.state.symbolic import count, world_space
    >>> law = configuration_law("allocation", ["a", "b", "c"], ["x", "y", "z"])
    >>> space = world_space(configuration_atoms(["a", "b", "c"], ["x", "y", "z"]), law)
    >>> count(space, space.law)  # 3! allocations
    6
    """
    atom = {(r, g): Atom("assigned", (r, g)) for r in robots for g in goals}
    parts: list[Formula] = []
    for r in robots:
        parts.append(disjunction(atom[r, g] for g in goals))
        parts += [Not(And(atom[r, g], atom[r, h])) for g, h in itertools.combinations(goals, 2)]
    mission = kind_named(kind)
    if mission.gathers:
        parts.append(disjunction(conjunction(atom[r, g] for r in robots) for g in goals))
    elif mission.distinct:
        for g in goals:
            parts += [
                Not(And(atom[r, g], atom[s, g])) for r, s in itertools.combinations(robots, 2)
            ]
    elif mission.capacities:
        for g, needs in zip(goals, capacities or (), strict=True):
            parts.append(_exactly(int(needs), [atom[r, g] for r in robots]))
    else:
        raise InvalidArgumentError(
            f"no configuration law for a {mission} mission",
            hint="rendezvous, allocation or capacity",
        )
    return conjunction([*parts, *constraints])


def _exactly(count: int, literals: list[Formula]) -> Formula:
    """Exactly ``count`` of ``literals`` hold (every choice of ``count`` of them)."""
    chosen = []
    for subset in itertools.combinations(range(len(literals)), count):
        inside = set(subset)
        chosen.append(conjunction(x if i in inside else Not(x) for i, x in enumerate(literals)))
    return disjunction(chosen)


def configuration_atoms(robots: Sequence[str], goals: Sequence[str]) -> list[str]:
    """Every ``assigned(ROBOT, GOAL)`` atom, robot by robot."""
    return [assignment_atom(r, g) for r in robots for g in goals]


def configuration_structure(
    kind: str | MissionKind,
    robots: Sequence[str],
    goals: Sequence[str],
    state: EpistemicState,
    capacities: Sequence[int] | None = None,
    constraints: Sequence[Formula] = (),
) -> KnowledgeStructure:
    """The knowledge structure over the valid configurations after what ``state``
    recorded: :func:`configuration_model` on BDDs, for missions too large to list."""
    law = configuration_law(kind, robots, goals, capacities, constraints)
    return group_structure(state, world_space(configuration_atoms(robots, goals), law))
