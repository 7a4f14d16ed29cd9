"""What each robot knows, and what it knows of its teammates' knowledge, from events.

Every fact a robot learns during a trial (a goal exists, a task is done, a teammate has
settled at a goal, a fact it was told at the start) comes from an *observation event*
with a set of observers. The observers learn the fact, and who else observed it; the
others are oblivious. In dynamic epistemic logic this is a private announcement to a group
(:func:`epistemica.del_.explicit.action.private_announcement`): after it, for a chain of robots
``(i1, ..., ik)`` ("``i1``'s model of ``i2``'s model ... of ``ik``") the fact holds in
every world the chain reaches iff *every robot of the chain* observed one event teaching
it. :class:`TeamKnowledge` keeps, per fact, the observer sets of the events that taught it
and answers chain queries with bit masks; ``tests/sim/test_knowledge.py`` checks that it
agrees with the model checker on the Kripke model after the same product updates.

Facts act on configurations (rows of goal indices, one per robot) as follows: a chain
reasons only over configurations whose goals it knows of and does not know to be done,
that give a settled robot the goal it settled at, and that satisfy the facts it was told.

Examples
--------
Robot 0 sees task 2 completed, robot 1 does not:

>>> import numpy as np
>>> k = TeamKnowledge(2, 3)
>>> k.complete(2, observers=[True, False])  # robot 0 learnt something
True
>>> rows = np.array([[0, 1], [0, 2], [2, 1]])
>>> k.possible((0,), rows).tolist()  # robot 0 prunes the rows that use task 2
[True, False, False]
>>> k.possible((0, 1), rows).tolist()  # ... and knows robot 1 has not
[True, True, True]
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence

import numpy as np

from epistemica.del_.errors import InvalidArgumentError

__all__ = ["TeamKnowledge", "initial_knowledge", "rows_satisfying"]

#: A fact told to some robots: a function from configuration rows (global goal indices)
#: to the rows where the fact holds.
RowFact = Callable[[np.ndarray], np.ndarray]


def _bits(observers, n: int) -> int:
    mask = np.asarray(observers, dtype=bool)
    if mask.shape != (n,):
        raise InvalidArgumentError(
            f"observers must be {n} booleans, got shape {mask.shape}", hint="one per robot"
        )
    return int(sum(1 << int(i) for i in np.flatnonzero(mask)))


def _add(masks: list[int], new: int) -> bool:
    """Add an observer set; keep only the maximal sets. True if anything changed."""
    if new == 0 or any(old & new == new for old in masks):
        return False
    masks[:] = [old for old in masks if old & new != old]
    masks.append(new)
    return True


class TeamKnowledge:
    """Facts learnt by groups of robots during one trial.

    Parameters
    ----------
    n_robots, n_goals : int
        Team size and number of goals (tasks).
    known_goals : array_like, optional
        ``(n, m)`` booleans: robot ``i`` knows goal ``g`` at the start. Each robot's
        initial goals count as observed by that robot alone, except goals every robot
        knows, which are common knowledge. Default: every goal, common knowledge.
    """

    def __init__(self, n_robots: int, n_goals: int, known_goals=None) -> None:
        self.n, self.m = int(n_robots), int(n_goals)
        self._everyone = (1 << self.n) - 1
        self._goal: list[list[int]] = [[] for _ in range(self.m)]
        self._done: list[list[int]] = [[] for _ in range(self.m)]
        self._settled: list[tuple[int, int, int]] = []  # (robot, goal, observers), in order
        self._told: list[tuple[RowFact, int]] = []
        known = np.ones((self.n, self.m), dtype=bool) if known_goals is None else known_goals
        known = np.asarray(known, dtype=bool)
        for g in range(self.m):
            if known[:, g].all():
                self._goal[g].append(self._everyone)
            else:
                for i in np.flatnonzero(known[:, g]):
                    _add(self._goal[g], 1 << int(i))

    # -- events ----------------------------------------------------------------------

    def discover(self, goal: int, observers) -> bool:
        """The observers learn that ``goal`` exists (and who else learnt it)."""
        return _add(self._goal[int(goal)], _bits(observers, self.n))

    def complete(self, task: int, observers) -> bool:
        """The observers see ``task`` done: no configuration needs it any more. True if
        any of them learnt something new."""
        return _add(self._done[int(task)], _bits(observers, self.n))

    def settle(self, robot: int, goal: int, observers) -> bool:
        """The observers see ``robot`` settle at ``goal``: it is its goal. True if any of
        them learnt something new."""
        bits = _bits(observers, self.n)
        seen = any(r == robot and g == goal and b & bits == bits for r, g, b in self._settled)
        if bits and not seen:
            self._settled.append((int(robot), int(goal), bits))
        return bool(bits) and not seen

    def tell(self, fact: RowFact, observers) -> None:
        """The observers are told ``fact`` (a predicate on configuration rows)."""
        self._told.append((fact, _bits(observers, self.n)))

    # -- queries ---------------------------------------------------------------------

    def _chain(self, chain: Sequence[int]) -> int:
        bits = 0
        for i in chain:
            if not 0 <= int(i) < self.n:
                raise InvalidArgumentError(
                    f"chain {tuple(chain)} names robot {i}", hint=f"robots are 0..{self.n - 1}"
                )
            bits |= 1 << int(i)
        return bits

    def constrains(self, chain: Sequence[int]) -> bool:
        """Whether a settled robot or a told fact reaches ``chain`` (else only the goals
        it knows of, and the tasks it knows done, restrict it)."""
        c = self._chain(chain)
        return any(b & c == c for *_, b in self._settled) or any(b & c == c for _, b in self._told)

    def private_goals(self, robot: int) -> bool:
        """Whether ``robot`` knows of a goal that it does not know every teammate knows."""
        own = self.knows_goals((robot,))
        return any((own & ~self.knows_goals((robot, j))).any() for j in range(self.n) if j != robot)

    def settled(self, chain: Sequence[int]) -> list[tuple[int, int]]:
        """``(robot, goal)`` of the settle events the whole chain saw, newest first."""
        c = self._chain(chain)
        return [(r, g) for r, g, b in reversed(self._settled) if b & c == c]

    def told(self, chain: Sequence[int]) -> bool:
        """Whether a told fact reaches the chain."""
        c = self._chain(chain)
        return any(b & c == c for _, b in self._told)

    def knows_goals(self, chain: Sequence[int]) -> np.ndarray:
        """``(m,)`` the goals the chain knows of."""
        c = self._chain(chain)
        return np.array([any(b & c == c for b in masks) for masks in self._goal], dtype=bool)

    def knows_done(self, chain: Sequence[int]) -> np.ndarray:
        """``(m,)`` the tasks the chain knows are done."""
        c = self._chain(chain)
        return np.array([any(b & c == c for b in masks) for masks in self._done], dtype=bool)

    def signature(self, chain: Sequence[int]) -> tuple:
        """What the chain keeps, as a hashable key: chains with equal signatures keep the
        same configurations (:meth:`possible` depends on nothing else)."""
        c = self._chain(chain)
        return (
            self.knows_goals(chain).tobytes(),
            self.knows_done(chain).tobytes(),
            tuple(i for i, (*_, b) in enumerate(self._settled) if b & c == c),
            tuple(i for i, (_, b) in enumerate(self._told) if b & c == c),
        )

    def possible_many(self, chains: Sequence[Sequence[int]], rows: np.ndarray) -> list:
        """:meth:`possible` for each chain, computed once per distinct signature.

        Examples
        --------
        >>> k = TeamKnowledge(3, 2)
        >>> a, b = k.possible_many([(0, 1), (1, 2)], np.array([[0, 0, 1]]))
        >>> a is b  # nothing was observed: one computation serves both chains
        True
        """
        memo: dict[tuple, np.ndarray] = {}
        out = []
        for chain in chains:
            key = self.signature(chain)
            if key not in memo:
                memo[key] = self.possible(chain, rows)
            out.append(memo[key])
        return out

    def possible(self, chain: Sequence[int], rows: np.ndarray) -> np.ndarray:
        """Which configurations ``rows`` (``(k, n)`` global goal indices) the chain keeps.

        A settled robot's goal, or a told fact, that would leave the chain no
        configuration at all is ignored: the chain saw contradictory events (two robots
        settled at different goals of a rendezvous, or at one goal of an allocation).
        Settle events are applied newest first, so the most recent one wins: a robot that
        settled where a stubborn teammate then settled too gives way (belief revision by
        recency, documented in docs/language.md).
        """
        rows = np.asarray(rows)
        c = self._chain(chain)
        usable = self.knows_goals(chain) & ~self.knows_done(chain)
        keep = usable[rows].all(axis=1) if rows.size else np.ones(rows.shape[0], dtype=bool)
        for robot, goal, bits in reversed(self._settled):  # the newest first
            if bits & c == c:
                narrowed = keep & (rows[:, robot] == goal)
                if narrowed.any():
                    keep = narrowed
        for fact, bits in self._told:
            if bits & c == c:
                narrowed = keep & np.asarray(fact(rows), dtype=bool)
                if narrowed.any():
                    keep = narrowed
        return keep


def rows_satisfying(formula, rows: np.ndarray, robot_names, goal_names) -> np.ndarray:
    """Which configurations ``rows`` (``(k, n)`` goal indices) satisfy ``formula``.

    ``formula`` is propositional over ``assigned(ROBOT, GOAL)`` atoms, named by
    ``robot_names`` and ``goal_names``.

    Examples
    --------
    >>> from epistemica.del_ import parse_formula
    >>> f = parse_formula("assigned(a, x) | ~assigned(b, y)")
    >>> rows_satisfying(f, np.array([[0, 1], [1, 1], [1, 0]]), ["a", "b"], ["x", "y"]).tolist()
    [True, False, True]
    """
    rows = np.asarray(rows)
    robot = {name: i for i, name in enumerate(robot_names)}
    goal = {name: g for g, name in enumerate(goal_names)}
    values: dict[int, np.ndarray] = {}
    stack = [(formula, False)]
    while stack:  # post-order with an explicit stack: no recursion limit
        node, ready = stack.pop()
        parts = _PARTS.get(type(node).__name__)
        if parts is None:
            raise InvalidArgumentError(
                f"'{node}' is not a fact about configurations",
                hint="use assigned(ROBOT, GOAL) atoms with ~, &, |, ->, <->",
            )
        children = [getattr(node, p) for p in parts]
        if not ready:
            stack.append((node, True))
            stack.extend((c, False) for c in children if id(c) not in values)
            continue
        values[id(node)] = _combine(node, [values[id(c)] for c in children], rows, robot, goal)
    return values[id(formula)]


_PARTS = {
    "Top": (),
    "Bottom": (),
    "Atom": (),
    "Not": ("operand",),
    "And": ("left", "right"),
    "Or": ("left", "right"),
    "Implies": ("left", "right"),
    "Iff": ("left", "right"),
}


def _combine(node, args: list[np.ndarray], rows, robot, goal) -> np.ndarray:
    kind = type(node).__name__
    if kind == "Top":
        return np.ones(rows.shape[0], dtype=bool)
    if kind == "Bottom":
        return np.zeros(rows.shape[0], dtype=bool)
    if kind == "Atom":
        if node.name != "assigned" or len(node.args) != 2:
            raise InvalidArgumentError(
                f"unknown atom '{node}'", hint="facts about configurations use assigned(r, g)"
            )
        r, g = (str(a) for a in node.args)
        if r not in robot or g not in goal:
            raise InvalidArgumentError(
                f"'{node}' names an unknown robot or goal",
                hint=f"robots: {', '.join(robot)}; goals: {', '.join(goal)}",
            )
        return rows[:, robot[r]] == goal[g]
    if kind == "Not":
        return ~args[0]
    if kind == "And":
        return args[0] & args[1]
    if kind == "Or":
        return args[0] | args[1]
    if kind == "Implies":
        return ~args[0] | args[1]
    return args[0] == args[1]  # Iff


def initial_knowledge(scenario) -> TeamKnowledge:
    """The team's knowledge at the start of a trial of ``scenario``: the goals each robot
    knows and the facts it was told (``Scenario.known_goals`` and ``Scenario.told``).

    Examples
    --------
    >>> from epistemica.sim import Scenario
    >>> from epistemica.del_ import parse_formula
    >>> s = Scenario("allocation", [[0, 0], [9, 9]], [[1, 1], [8, 8]], ["range"] * 2,
    ...              told=[((True, False), parse_formula("assigned(r1, g2)"))])
    >>> initial_knowledge(s).possible((0,), s.configurations()).tolist()
    [False, True]
    """
    k = TeamKnowledge(scenario.n_robots, scenario.n_goals, scenario.known_goals)
    for observers, formula in scenario.told:
        fact = functools.partial(
            rows_satisfying,
            formula,
            robot_names=scenario.robot_names,
            goal_names=scenario.goal_names,
        )
        k.tell(fact, observers)
    return k
