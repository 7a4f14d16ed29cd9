"""Planning over knowledge structures: the symbolic backend of the planner.

The same problems as :func:`~epistemica.del_.planning.planner.plan_with_stats` (an
initial state, named action models, a goal; a plan is applicable at every designated
state, step by step, and ends where the goal holds at every designated state), searched
with the same engine (:func:`~epistemica.del_.planning.state_space.search_states`:
breadth-first, greedy or A*), but each state is a
:class:`~epistemica.del_.KnowledgeStructure`: BDDs over Boolean variables, never a list
of worlds. A model of 3^20 worlds costs a law of a few hundred BDD nodes.

Successors are product updates (knowledge/belief transformers). States are stored once
each, keyed by :func:`~epistemica.del_.symbolic.normal_form.state_key` after
:func:`~epistemica.del_.symbolic.normal_form.normalise`, which removes the history a
product update leaves behind; equal keys always mean bisimilar states, and the key is
exact when only atoms are left or the state has few states (see that module).

Before searching, atoms that no formula reads and that the law leaves independent are
dropped (a bounded morphism, so bisimilar), and agents that no modality names are left
out, as the explicit planner does.

Examples
--------
>>> from epistemica.del_ import KnowledgeStructure, public_announcement
>>> s0 = KnowledgeStructure.from_observables(["p", "q"], {"a": []}, designated=["p"])
>>> result = plan_symbolic_with_stats(s0, {"tell": public_announcement("p", ["a"])}, "K[a] p")
>>> result.plan, result.complete
(['tell'], True)
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from epistemica.del_.budget import current_budget, estimate_explicit_bytes
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._model import MAX_ENUMERATED_ATOMS
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.language.formula import Formula
from epistemica.del_.language.parser import as_formula
from epistemica.del_.planning.planner import (
    Validation,
    action_with_agents,
    choose_heuristic,
    relevant_agents,
    relevant_atoms,
)
from epistemica.del_.planning.state_space import (
    KeyedStates,
    PlanResult,
    check_problem,
    search_states,
)
from epistemica.del_.symbolic.normal_form import normalise, state_key, without_free_atoms
from epistemica.del_.symbolic.structure import SymbolicModel

__all__ = [
    "applicable_in_all_symbolic",
    "choose_backend",
    "plan_symbolic",
    "plan_symbolic_with_stats",
    "relevant_structure",
    "symbolic_states",
    "validate_symbolic",
]


def choose_backend(n_atoms: int, n_agents: int) -> str:
    """``"explicit"`` when an explicit model from ``n_atoms`` observable atoms fits the
    memory budget in force (:func:`~epistemica.del_.budget.estimate_explicit_bytes`, with
    the arrays a product update lists), else ``"symbolic"``.

    Examples
    --------
    >>> choose_backend(12, 3), choose_backend(40, 3)
    ('explicit', 'symbolic')
    """
    need = estimate_explicit_bytes(n_atoms, n_agents, materialize=True)
    fits = n_atoms <= MAX_ENUMERATED_ATOMS and need <= current_budget()
    return "explicit" if fits else "symbolic"


def plan_symbolic(
    initial: SymbolicModel,
    actions: Mapping[str, ActionModel],
    goal: Formula | str,
    search: str = "bfs",
    max_depth: int | None = None,
    heuristic: Any = None,
    max_states: int | None = None,
) -> list[str] | None:
    """A plan over knowledge structures, or None; the arguments of
    :func:`~epistemica.del_.planning.planner.plan`."""
    found = plan_symbolic_with_stats(
        initial, actions, goal, search, max_depth, heuristic, max_states
    )
    return found.plan


def plan_symbolic_with_stats(
    initial: SymbolicModel,
    actions: Mapping[str, ActionModel],
    goal: Formula | str,
    search: str = "bfs",
    max_depth: int | None = None,
    heuristic: Any = None,
    max_states: int | None = None,
) -> PlanResult:
    """Like :func:`plan_symbolic`, returning a :class:`PlanResult` with statistics."""
    check_problem(initial, actions, SymbolicModel)
    tree = as_formula(goal)
    table = dict(actions)
    if not callable(heuristic):  # a user's heuristic may read any atom or agent
        initial, table = relevant_structure(initial, table, tree)

    def successors(state: SymbolicModel) -> Iterable[tuple[str, SymbolicModel]]:
        for name, action in table.items():
            if applicable_in_all_symbolic(state, action):
                yield name, state.update(action)

    def is_goal(state: SymbolicModel) -> bool:
        return state.holds(tree, actions=table)

    h = choose_heuristic(heuristic, search, tree, table)
    return search_states(
        initial, successors, is_goal, search, max_depth, h, max_states, store=symbolic_states()
    )


def validate_symbolic(
    initial: SymbolicModel,
    actions: Mapping[str, ActionModel],
    plan: Sequence[str],
    goal: Formula | str,
) -> Validation:
    """Check a plan over knowledge structures, as
    :func:`~epistemica.del_.planning.planner.validate` does over Kripke models (the
    states of the verdict are the normalised structures)."""
    check_problem(initial, actions, SymbolicModel)
    tree = as_formula(goal)
    if isinstance(plan, str):
        raise InvalidArgumentError(
            "plan must be a sequence of action names, not one string", hint=f"write [{plan!r}]"
        )
    for name in plan:
        if name not in actions:
            raise InvalidArgumentError(
                f"the plan names an unknown action {name!r}",
                hint=f"actions: {', '.join(actions)}",
            )
    state, table = relevant_structure(initial, actions, tree)
    state = normalise(state)
    states = [state]
    for i, name in enumerate(plan):
        if not applicable_in_all_symbolic(state, table[name]):
            return Validation(
                False,
                f"step {i + 1} ({name}) is not applicable: no designated event's precondition "
                f"holds at some designated state",
                i,
                tuple(states),
            )
        state = normalise(state.update(table[name]))
        states.append(state)
    if not state.holds(tree, actions=table):
        bad = state.count_designated() - state.count_designated(tree, table)
        return Validation(
            False,
            f"after the plan the goal {tree} fails at {bad} designated state(s)",
            len(plan),
            tuple(states),
        )
    return Validation(
        True, f"the plan reaches the goal in {len(plan)} step(s)", None, tuple(states)
    )


def applicable_in_all_symbolic(state: SymbolicModel, action: ActionModel) -> bool:
    """Whether at every designated state some designated event's precondition holds.

    Examples
    --------
    >>> from epistemica.del_ import KnowledgeStructure, public_announcement
    >>> both = KnowledgeStructure.from_observables(["p"], {"a": []})
    >>> applicable_in_all_symbolic(both, public_announcement("p", ["a"]))
    False
    """
    missing = state.designated_states
    for e in action.designated_positions:
        missing = missing & ~state.truth(action.pre[e])
        if not missing.satisfiable():
            return True
    return False


def relevant_structure(
    structure: SymbolicModel,
    actions: Mapping[str, ActionModel],
    goal: Formula | str,
    agents: Iterable[str] = (),
) -> tuple[SymbolicModel, dict[str, ActionModel]]:
    """The structure and actions without what no formula of them reads.

    Agents that no modality names (besides ``agents``) are left out. An atom that no
    formula reads or assigns is dropped when the law does not constrain it and every
    relation reading it only observes it: dropping it then maps states onto states
    (a bounded morphism), so every formula over the rest keeps its truth.

    Examples
    --------
    >>> from epistemica.del_ import KnowledgeStructure, public_announcement
    >>> s = KnowledgeStructure.from_observables(["p", "junk"], {"a": ["junk"], "b": []})
    >>> small, _ = relevant_structure(s, {"tell": public_announcement("p", ["a", "b"])},
    ...                               "K[a] p")
    >>> small.atoms, small.agents
    (('p',), ('a',))
    """
    goal = as_formula(goal)
    table = dict(actions)
    named = relevant_agents(goal, table.values()) | set(agents)
    keep = tuple(a for a in structure.agents if a in named) or structure.agents[:1]
    if len(keep) < len(structure.agents):
        table = {name: action_with_agents(a, keep) for name, a in table.items()}
    needed = relevant_atoms(goal, table.values())
    smaller = without_free_atoms(structure, needed, keep)
    return smaller, table


def symbolic_states() -> KeyedStates:
    """A store of distinct knowledge structures for
    :func:`~epistemica.del_.planning.state_space.search_states`: each normalised and keyed
    by :func:`~epistemica.del_.symbolic.normal_form.state_key`."""

    def prepare(state: SymbolicModel) -> tuple[SymbolicModel, tuple]:
        state = normalise(state)
        return state, state_key(state)

    return KeyedStates(prepare)
