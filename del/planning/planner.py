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
  (:meth:`~epistemica.del_.KripkeModel.minimize`), which preserves every formula.

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
from epistemica.del_.explicit._cube import Cube, pack_bits
from epistemica.del_.explicit.action import ActionModel, product_update
from epistemica.del_.explicit.canonical import canonical_key
from epistemica.del_.explicit.checker import evaluate
from epistemica.del_.explicit.describe import world_labels
from epistemica.del_.language.formula import And, Formula
from epistemica.del_.language.modalities import Common, Distributed, Everybody, Know, KnowWhether
from epistemica.del_.language.parser import as_formula
from epistemica.del_.models import KripkeModel
from epistemica.del_.planning.state_space import (
    SEARCHES,
    Heuristic,
    PlanResult,
    check_problem,
    search_states,
)

# SEARCHES, PlanResult (from state_space) and canonical_key are re-exported here.
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
        initial = _forget_knowledge(initial)

    def successors(state: KripkeModel) -> Iterable[tuple[str, KripkeModel]]:
        for name, action in table.items():
            if applicable_in_all(state, action):
                yield name, product_update(state, action, beliefs_only=beliefs_only)

    def is_goal(state: KripkeModel) -> bool:
        return state.holds(tree, actions=table)

    h = choose_heuristic(heuristic, search, tree, table)
    return search_states(initial, successors, is_goal, search, max_depth, h, max_states)


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
    state = initial.minimize()
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
        state = state.update(table[name]).minimize()
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


_KNOWLEDGE_NODES = (Know, KnowWhether, Everybody, Common, Distributed)


def uses_knowledge(goal: Formula, actions: Iterable[ActionModel]) -> bool:
    """Whether a knowledge modality occurs in the goal or in any action's formulas.

    Examples
    --------
    >>> from epistemica.del_ import parse_formula, public_announcement
    >>> uses_knowledge(parse_formula("B[a] p"), [public_announcement("K[a] p", ["a"])])
    True
    >>> uses_knowledge(parse_formula("B[a] p"), [public_announcement("p", ["a"])])
    False
    """
    return any(
        isinstance(g, _KNOWLEDGE_NODES) for f in _formulas(goal, actions) for g in f.subformulas()
    )


def _formulas(goal: Formula, actions: Iterable[ActionModel]) -> list[Formula]:
    """The goal and every formula of the actions: preconditions, effects, edge conditions."""
    formulas = [goal]
    for action in actions:
        formulas.extend(action.pre)
        formulas.extend(v for changes in action.post for v in changes.values())
        for edges in (*action.edges.values(), *action.knowledge_edges.values()):
            formulas.extend(c for _, _, c in edges if c is not None)
    return formulas


def relevant_atoms(goal: Formula | str, actions: Iterable[ActionModel]) -> frozenset[str]:
    """The atoms that the goal or an action reads or assigns: all that planning can see.

    Examples
    --------
    >>> from epistemica.del_ import public_assignment
    >>> sorted(relevant_atoms("K[a] p", [public_assignment({"q": "r"}, ["a"])]))
    ['p', 'q', 'r']
    """
    actions = list(actions)
    found = {g.key for f in _formulas(as_formula(goal), actions) for g in f.atoms()}
    found.update(atom for action in actions for changes in action.post for atom in changes)
    return frozenset(found)


def relevant_agents(goal: Formula | str, actions: Iterable[ActionModel]) -> frozenset[str]:
    """The agents that a modality of the goal or of an action names.

    Examples
    --------
    >>> from epistemica.del_ import public_announcement
    >>> sorted(relevant_agents("K[a] p", [public_announcement("B[b] q", ["a", "b", "c"])]))
    ['a', 'b']
    """
    return frozenset(g for f in _formulas(as_formula(goal), actions) for g in f.agents())


def relevant_part(
    state: KripkeModel,
    actions: Mapping[str, ActionModel],
    goal: Formula | str,
    agents: Iterable[str] = (),
) -> tuple[KripkeModel, dict[str, ActionModel]]:
    """The state and actions without the atoms and agents no formula of them reads.

    An agent that no modality names changes no truth value, but its relation still
    splits states (and each action carries it); an unread atom doubles the worlds. The
    search, :func:`validate` and implicit coordination (which also keeps ``agents``, the
    owners whose perspectives it takes) all plan on this part, so they see the same
    states. Every formula over the kept atoms and agents keeps its truth.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel, public_announcement
    >>> s = KripkeModel.from_observables(["p", "junk"], {"a": [], "b": []}, designated=["p"])
    >>> small, acts = relevant_part(s, {"tell": public_announcement("p", ["a", "b"])}, "K[a] p")
    >>> small.atoms, small.agents, small.n_worlds
    (('p',), ('a',), 2)
    """
    goal = as_formula(goal)
    actions = dict(actions)
    named = relevant_agents(goal, actions.values()) | set(agents)
    keep = named & set(state.agents) or set(state.agents[:1])
    if len(keep) < len(state.agents):
        agents = tuple(a for a in state.agents if a in keep)
        state = _with_agents(state, agents)
        actions = {name: action_with_agents(a, agents) for name, a in actions.items()}
    return project(state, relevant_atoms(goal, actions.values())), actions


def _with_agents(state: KripkeModel, agents: tuple[str, ...]) -> KripkeModel:
    if state.cube is not None:
        return KripkeModel.from_cube(state.cube, state.atoms, agents, state.designated_codes)
    rel = {a: state.belief_relations[a] for a in agents}
    know = {a: state.knowledge_relations[a] for a in agents}
    return KripkeModel.from_arrays(
        state.lazy_names,
        state.atoms,
        state.valuation,
        agents,
        rel,
        know,
        state.designated_positions,
    )


def action_with_agents(action: ActionModel, agents: tuple[str, ...]) -> ActionModel:
    """The action model with the relations of ``agents`` only."""
    events = action.events

    def edges(table: dict, agent: str) -> list[tuple]:
        return [(events[e], events[f]) + (() if c is None else (c,)) for e, f, c in table[agent]]

    return ActionModel(
        events,
        dict(zip(events, action.pre, strict=True)),
        dict(zip(events, action.post, strict=True)),
        {a: edges(action.edges, a) for a in agents},
        list(action.designated),
        knowledge={a: edges(action.knowledge_edges, a) for a in agents},
    )


def project(state: KripkeModel, atoms: Iterable[str]) -> KripkeModel:
    """The state on ``atoms`` only, contracted: formulas over them keep their truth.

    Planning never reads an atom that no action or goal mentions, but such an atom may
    multiply the worlds (each unknown one doubles them); projecting it away first keeps
    the search the size of the relevant part.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "junk"], {"a": ["p"]}, designated=["p"])
    >>> small = project(m, ["p"])
    >>> small.n_worlds, small.atoms, small.holds("K[a] p")
    (2, ('p',), True)
    """
    keep = set(atoms)
    columns = [j for j, a in enumerate(state.atoms) if a in keep]
    if len(columns) == len(state.atoms):
        return state
    if state.cube is not None:
        found = _project_cube(state, columns)
        if found is not None:
            return found
    return KripkeModel.from_arrays(
        state.lazy_names,
        tuple(state.atoms[j] for j in columns),
        state.valuation[:, columns],
        state.agents,
        state.belief_relations,
        state.knowledge_relations,
        state.designated_positions,
    ).minimize()


def _project_cube(state: KripkeModel, columns: list[int]) -> KripkeModel | None:
    """Projection of a model from observables whose worlds are a product over the
    dropped atoms (every value of them goes with every live valuation of the others):
    the model from observables of the kept atoms, then, is bisimilar to the state.
    ``None`` when the worlds are not such a product (a law ties the dropped atoms)."""
    cube = state.cube
    n = cube.n_bits
    dropped = [n - 1 - j for j in range(n) if j not in set(columns)]
    any_dropped = cube.zeros()
    for p in dropped:
        if not cube.closed_under_flip(p):
            return None
        any_dropped |= cube.atom(n - 1 - p)
    kept = [n - 1 - j for j in columns]  # code bit positions, most significant first
    codes = cube.restrict(~any_dropped).codes
    new_codes = _compress(codes, kept)
    points = np.unique(_compress(np.asarray(state.designated_codes), kept))
    position = {p: len(kept) - 1 - i for i, p in enumerate(kept)}
    hidden = {a: tuple(position[p] for p in cube.hidden[a] if p in position) for a in state.agents}
    small = Cube.full(len(kept), hidden)
    flags = np.zeros(small.space.words * 64, dtype=bool)
    flags[new_codes] = True
    small = Cube(small.space, pack_bits(flags))
    atoms = tuple(state.atoms[j] for j in columns)
    return KripkeModel.from_cube(small, atoms, state.agents, points.astype(np.intp))


def _compress(codes: np.ndarray, kept: list[int]) -> np.ndarray:
    """Codes with only the bits at positions ``kept`` (most significant first), packed."""
    out = np.zeros(len(codes), dtype=np.intp)
    for i, p in enumerate(kept):
        out |= ((codes >> p) & 1) << (len(kept) - 1 - i)
    return out


def _forget_knowledge(state: KripkeModel) -> KripkeModel:
    """The same state with each agent's knowledge relation replaced by its belief relation."""
    if not state.has_separate_knowledge():
        return state
    rel = state.belief_relations
    return KripkeModel.from_arrays(
        state.lazy_names,
        state.atoms,
        state.valuation,
        state.agents,
        rel,
        dict(rel),
        state.designated_positions,
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


def _executable_at_points(state: KripkeModel, action: ActionModel) -> np.ndarray:
    """Per designated world, whether some designated event's precondition holds there."""
    points = state.designated_positions
    ok = np.zeros(len(points), dtype=bool)
    for e in action.designated_positions:
        ok |= evaluate(state, action.pre[e])[points]
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
