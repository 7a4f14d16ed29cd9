"""Epistemic planning: search for action sequences that reach an epistemic goal.

A planning problem is the paper's ``Plan(s0, Gamma, B)``: an initial epistemic state
``s0`` (a possibly multi-pointed :class:`~epistemica.del_.KripkeModel`), named
action models, and a goal formula; a plan is a sequence of action names that is
applicable step by step and ends in a state where the goal holds at every designated
world.

Semantics (Bolander and Andersen's sequential plans):

- an action is *applicable* in a state when at **every** designated world some
  designated event's precondition holds (so a plan from a multi-pointed state works
  whichever designated world is actual);
- the successor state is the product update, contracted to its bisimulation minimum
  (:meth:`~epistemica.del_.KripkeModel.minimize`), which preserves every formula without
  distributed knowledge; a task with ``D[G]`` (whose truth a contraction can change) keeps
  its states uncontracted and finds duplicates only when identical.

Search: ``"bfs"`` (breadth-first, shortest plans), ``"greedy"`` (greedy best-first) and
``"astar"`` (A*), the last two guided by a heuristic (default: the number of top-level
conjuncts of the goal that do not hold yet, which is not admissible, so A* with it may
return a longer plan than breadth-first search; ``heuristic="blind"`` is admissible).
The engine is :func:`~epistemica.del_.planning.state_space.search_states`, which stores each state
once up to bisimulation (keyed by :func:`~epistemica.del_.explicit.canonical.canonical_key`), so
the per-model memo of truth sets is reused by every precondition and goal test on it.

The search terminates whenever finitely many states are reachable up to bisimulation
(for example with public actions only); plan existence in DEL is undecidable in general,
so ``max_depth`` or ``max_states`` bound the search otherwise. :attr:`PlanResult.complete`
tells whether ``None`` means "no plan exists" or "none within the bound".

Examples
--------
A light switch that both agents see; the goal is that ``b`` knows the light is on:

>>> from epistemica.del_ import KripkeModel, public_assignment
>>> s0 = KripkeModel.from_observables(["on"], {"a": ["on"], "b": ["on"]}, designated=[])
>>> toggle = public_assignment({"on": "~on"}, ["a", "b"])
>>> plan(s0, {"toggle": toggle}, "K[b] on")
['toggle']
>>> plan(s0, {"toggle": toggle}, "on & ~on") is None
True
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.action import ActionModel, product_update
from epistemica.del_.explicit.canonical import canonical_key
from epistemica.del_.explicit.checker import evaluate
from epistemica.del_.explicit.describe import world_labels
from epistemica.del_.explicit.row_truth import RowTruth
from epistemica.del_.language.formula import And, Formula
from epistemica.del_.language.parser import as_formula
from epistemica.del_.models import KripkeModel
from epistemica.del_.planning.relevance import (
    action_with_agents,
    forget_knowledge,
    project,
    relevant_agents,
    relevant_atoms,
    relevant_part,
    uses_distributed,
    uses_knowledge,
)
from epistemica.del_.planning.state_space import (
    SEARCHES,
    Heuristic,
    KeyedStates,
    PlanResult,
    check_problem,
    exact_state,
    search_states,
)

# SEARCHES, PlanResult (from state_space), canonical_key and the relevance functions
# (from relevance) are re-exported here.
__all__ = [
    "SEARCHES",
    "PlanResult",
    "Validation",
    "action_with_agents",
    "applicable_in_all",
    "canonical_key",
    "choose_heuristic",
    "goal_count",
    "plan",
    "plan_with_stats",
    "project",
    "relevant_agents",
    "relevant_atoms",
    "relevant_part",
    "uses_knowledge",
    "validate",
]


@dataclass(frozen=True)
class Validation:
    """The verdict of :func:`validate`; true in a boolean context when the plan works.

    Attributes
    ----------
    valid : bool
        Whether every step is applicable and the goal holds at the end.
    reason : str
        Why not (or a one-line confirmation).
    step : int or None
        0-based index of the first inapplicable action; ``len(plan)`` when only the goal
        fails; ``None`` when valid.
    states : tuple of KripkeModel
        The (contracted) states reached, starting with the initial one, on the atoms and
        agents the search sees (knowledge structures, normalised, for
        :func:`~epistemica.del_.planning.symbolic_search.validate_symbolic`).
    """

    valid: bool
    reason: str
    step: int | None
    states: tuple[KripkeModel, ...] = field(repr=False)

    def __bool__(self) -> bool:
        return self.valid


def plan(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    goal: Formula | str,
    search: str = "bfs",
    max_depth: int | None = None,
    heuristic: str | Heuristic | None = None,
    max_states: int | None = None,
) -> list[str] | None:
    """Find a plan: a list of action names whose execution makes ``goal`` hold.

    Parameters
    ----------
    initial : KripkeModel
        The initial epistemic state (its designated worlds are the actual candidates).
    actions : mapping
        Action name -> :class:`~epistemica.del_.explicit.action.ActionModel`; tried in this order.
    goal : formula or str
        Must hold at every designated world of the final state. ``[ACT] g`` in the goal
        refers to ``actions``.
    search : {"bfs", "greedy", "astar"}
        Breadth-first (shortest plans), greedy best-first or A*.
    max_depth : int, optional
        Longest plan considered.
    heuristic : {"goalcount", "blind"} or callable, optional
        For ``greedy``/``astar`` only: ``"goalcount"`` (default) counts unsatisfied
        top-level conjuncts of the goal, ``"blind"`` is 0 on goal states and 1
        elsewhere, a callable maps a state to a non-negative number.
    max_states : int, optional
        Stop after storing this many distinct states.

    Returns
    -------
    list of str or None
        A plan, or ``None`` when none exists (within the bounds).

    See Also
    --------
    plan_with_stats : the same search, returning a :class:`PlanResult`.
    """
    return plan_with_stats(initial, actions, goal, search, max_depth, heuristic, max_states).plan


def plan_with_stats(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    goal: Formula | str,
    search: str = "bfs",
    max_depth: int | None = None,
    heuristic: str | Heuristic | None = None,
    max_states: int | None = None,
) -> PlanResult:
    """Like :func:`plan`, but return the plan with search statistics.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel, public_announcement
    >>> s0 = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
    >>> result = plan_with_stats(s0, {"tell": public_announcement("p", ["a"])}, "K[a] p")
    >>> result.plan, result.expanded, result.complete
    (['tell'], 1, True)
    """
    check_problem(initial, actions)
    tree = as_formula(goal)
    table = dict(actions)
    if not callable(heuristic):  # a user's heuristic may read any atom or agent
        initial, table = relevant_part(initial, table, tree)
    # Without K, Kw, E, C or D anywhere, states that agree on beliefs are interchangeable:
    # the search then tracks belief relations only (half the relational work).
    beliefs_only = not uses_knowledge(tree, table.values())
    if beliefs_only:
        initial = forget_knowledge(initial)

    # Conditions are evaluated from values remembered per valuation row: the states of
    # one search share few distinct valuations (the plan is the same, only faster).
    rows = RowTruth()

    def successors(state: KripkeModel) -> Iterable[tuple[str, KripkeModel]]:
        for name, action in table.items():
            if _executable_at_points(state, action, rows).all():
                yield name, product_update(state, action, beliefs_only=beliefs_only, rows=rows)

    def is_goal(state: KripkeModel) -> bool:
        return state.holds(tree, actions=table)

    h = choose_heuristic(heuristic, search, tree, table)
    # D[G] reads intersections of relations, which a contraction can change: such a
    # task is searched on uncontracted states, duplicates found only when identical.
    store = KeyedStates(exact_state) if uses_distributed(tree, table.values()) else None
    return search_states(initial, successors, is_goal, search, max_depth, h, max_states, store)


def _contraction(goal: Formula, table: Mapping[str, ActionModel]):
    """How :func:`validate` normalises its states: contracted, or (``D[G]`` in the task)
    the generated submodel."""
    if uses_distributed(goal, table.values()):
        return lambda state: exact_state(state)[0]
    return lambda state: state.minimize()


def _named(state: KripkeModel, worlds) -> str:
    """The worlds as ``explain`` names them (``w6``, ``u.tell``), comma-separated."""
    labels = world_labels(state)
    return ", ".join(labels[w] for w in worlds)


def validate(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    plan: Sequence[str],
    goal: Formula | str,
) -> Validation:
    """Check a plan: every step applicable, the goal true at the end.

    Returns a :class:`Validation`, true in a boolean context when the plan is valid and
    carrying the reason otherwise. The states are those the search visits: on the atoms
    and agents that the goal or an action mentions (:func:`relevant_part`), contracted.

    Raises
    ------
    InvalidArgumentError
        If the plan names an unknown action.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel, public_announcement
    >>> s0 = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
    >>> acts = {"tell": public_announcement("p", ["a"]),
    ...         "deny": public_announcement("~p", ["a"])}
    >>> bool(validate(s0, acts, ["tell"], "K[a] p"))
    True
    >>> print(validate(s0, acts, ["deny"], "K[a] p").reason)  # doctest: +ELLIPSIS
    step 1 (deny) is not applicable: ... at designated world(s) w1
    """
    check_problem(initial, actions)
    tree = as_formula(goal)
    table = dict(actions)
    if isinstance(plan, str):
        raise InvalidArgumentError(
            "plan must be a sequence of action names, not one string",
            hint=f"write [{plan!r}]",
        )
    steps = list(plan)
    for name in steps:
        if name not in table:
            raise InvalidArgumentError(
                f"the plan names an unknown action {name!r}",
                hint=f"actions: {', '.join(table)}",
            )
    initial, table = relevant_part(initial, table, tree)
    contract = _contraction(tree, table)
    state = contract(initial)
    states = [state]
    for i, name in enumerate(steps):
        failing = inapplicable_worlds(state, table[name])
        if failing:
            return Validation(
                False,
                f"step {i + 1} ({name}) is not applicable: no designated event's precondition "
                f"holds at designated world(s) {_named(state, failing)}",
                i,
                tuple(states),
            )
        state = contract(state.update(table[name]))
        states.append(state)
    if not state.holds(tree, actions=table):
        bad = [
            w
            for w, ok in zip(state.designated, _goal_at_points(state, tree, table), strict=True)
            if not ok
        ]
        return Validation(
            False,
            f"after the plan the goal {tree} fails at designated world(s) {_named(state, bad)}",
            len(steps),
            tuple(states),
        )
    return Validation(
        True, f"the plan reaches the goal in {len(steps)} step(s)", None, tuple(states)
    )


def applicable_in_all(state: KripkeModel, action: ActionModel) -> bool:
    """Whether at every designated world some designated event is executable.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel, public_announcement
    >>> both = KripkeModel.from_observables(["p"], {"a": []})   # p and ~p designated
    >>> applicable_in_all(both, public_announcement("p", ["a"]))
    False
    """
    return bool(_executable_at_points(state, action).all())


def inapplicable_worlds(state: KripkeModel, action: ActionModel) -> list[Hashable]:
    """The designated worlds at which no designated event of ``action`` is executable."""
    ok = _executable_at_points(state, action)
    names = state.worlds
    return [names[i] for i in state.designated_positions[~ok]]


def _executable_at_points(
    state: KripkeModel, action: ActionModel, rows: RowTruth | None = None
) -> np.ndarray:
    """Per designated world, whether some designated event's precondition holds there."""
    truth = evaluate if rows is None else rows
    points = state.designated_positions
    ok = np.zeros(len(points), dtype=bool)
    for e in action.designated_positions:
        ok |= truth(state, action.pre[e])[points]
        if ok.all():
            break
    return ok


def goal_count(goal: Formula | str) -> Heuristic:
    """The goal-counting heuristic: unsatisfied top-level conjuncts of ``goal``.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "q"], {"a": []}, designated=["p"])
    >>> goal_count("p & q & K[a] p")(m)
    2
    """
    parts = _conjuncts(as_formula(goal))

    def count(state: KripkeModel) -> int:
        return sum(not state.holds(f) for f in parts)

    return count


def _conjuncts(f: Formula) -> list[Formula]:
    if isinstance(f, And):
        return _conjuncts(f.left) + _conjuncts(f.right)
    return [f]


def _goal_at_points(state: KripkeModel, goal: Formula, actions: Mapping) -> list[bool]:
    mask = evaluate(state, goal, actions)
    return [bool(x) for x in mask[state.designated_positions]]


def choose_heuristic(
    heuristic: str | Heuristic | None, search: str, goal: Formula, actions: Mapping
) -> Heuristic | None:
    """The heuristic function for ``search`` (None for breadth-first search), checked.

    ``"goalcount"`` (the default for greedy and A*), ``"blind"`` or a callable; the
    built-in ones call ``state.holds``, so they serve both backends.
    """
    if search not in SEARCHES:
        raise InvalidArgumentError(
            f"unknown search {search!r}", hint=f"choose one of {', '.join(SEARCHES)}"
        )
    if search == "bfs":
        if heuristic is not None:
            raise InvalidArgumentError(
                "breadth-first search takes no heuristic",
                hint="use search='greedy' or search='astar', or drop the heuristic",
            )
        return None
    if heuristic is None or heuristic == "goalcount":
        return goal_count(goal)
    if heuristic == "blind":
        return lambda state: 0 if state.holds(goal, actions=actions) else 1
    if callable(heuristic):
        return heuristic
    raise InvalidArgumentError(
        f"unknown heuristic {heuristic!r}",
        hint="use 'goalcount', 'blind' or a function state -> number",
    )
