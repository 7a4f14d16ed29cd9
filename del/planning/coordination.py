"""Implicit coordination (Engesser, Bolander, Mattmüller and Nebel, 2017).

Each action has an *owner*, the agent who executes it. Agents do not communicate: the
owner of the next action must itself know, from its own perspective, that the rest of
the plan still reaches the goal. The *perspective* (associated local state) of agent
``i`` on a state is the same model re-pointed at every world ``i`` cannot tell apart,
by its knowledge relation, from a designated world.

A sequential plan ``a1 ... an`` is *implicitly coordinated* from ``s0`` when, with
``Y0 = s0``, ``Xk`` the perspective of ``owner(ak)`` on ``Y(k-1)`` and
``Yk = Xk ⊗ ak``: every ``ak`` is applicable at every world of ``Xk`` and the goal holds
at every designated world of ``Yn``. Equivalently (Engesser et al.'s strong policies
restricted to sequences), the owner of every step knows that the rest of the plan,
executed by agents who in turn only act on what they know, reaches the goal in every
world it considers possible. This module is restricted to **sequential** plans; in
general implicitly coordinated policies may need to branch on what an agent observes.

:func:`check_implicit_coordination` explains a failure (which step, which agent, which
world of its perspective, and the chain of perspective shifts that brought that world
in); :func:`plan_implicitly_coordinated` searches breadth-first for the shortest
implicitly coordinated sequential plan.

Examples
--------
Robot ``r1`` knows where its task is (``t``: at ``g1``); ``r2`` does not. ``r1`` moving
first tells ``r2`` (the move is public and only goes to r1's task):

>>> from epistemica.del_ import KripkeModel, public_assignment
>>> s0 = KripkeModel.from_observables(["t"], {"r1": ["t"], "r2": []}, designated=["t"])
>>> agents = ["r1", "r2"]
>>> acts = {"r1_to_g1": public_assignment({"r1_g1": "true"}, agents, pre="t"),
...         "r2_to_g2": public_assignment({"r2_g2": "true"}, agents)}
>>> owners = {"r1_to_g1": "r1", "r2_to_g2": "r2"}
>>> goal = "r1_g1 & r2_g2 & t"
>>> bool(check_implicit_coordination(s0, acts, owners, ["r1_to_g1", "r2_to_g2"], goal))
True
>>> report = check_implicit_coordination(s0, acts, owners, ["r2_to_g2", "r1_to_g1"], goal)
>>> report.step, report.agent, report.kind
(1, 'r1', 'not-applicable')
>>> report.chain   # at step 0, r2 could not tell world 0 (~t) from the actual 1 (t)
((0, 'r2', 0, 1),)
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.explicit.bisimulation import generated_submodel
from epistemica.del_.explicit.checker import evaluate
from epistemica.del_.language.formula import Formula
from epistemica.del_.language.parser import as_formula
from epistemica.del_.models import KripkeModel
from epistemica.del_.planning.planner import (
    applicable_in_all,
    inapplicable_worlds,
    relevant_part,
)
from epistemica.del_.planning.relevance import uses_distributed
from epistemica.del_.planning.state_space import (
    KeyedStates,
    PlanResult,
    check_problem,
    exact_state,
    search_states,
)

__all__ = [
    "CoordinationReport",
    "check_implicit_coordination",
    "check_owners",
    "perspective",
    "plan_implicitly_coordinated",
    "plan_implicitly_coordinated_with_stats",
    "pointed_at",
]


@dataclass(frozen=True)
class CoordinationReport:
    """Whether a plan is implicitly coordinated, and if not, why.

    Attributes
    ----------
    coordinated : bool
    reason : str
        A sentence explaining the verdict.
    step : int or None
        0-based index of the step at which the plan breaks (the last step when only the
        goal fails).
    agent, action : str or None
        The owner and the action of that step.
    world : hashable or None
        The world of the owner's perspective where the action is not applicable, or
        from which the goal fails after the last action.
    kind : {"not-applicable", "goal"} or None
    chain : tuple of (step, agent, world, actual)
        The perspective shifts that brought ``world`` (or its ancestor) in: at ``step``,
        ``agent`` could not tell ``world`` apart from the designated world ``actual``.
        Empty when the plan fails in the designated worlds themselves.
    """

    coordinated: bool
    reason: str
    step: int | None = None
    agent: str | None = None
    action: str | None = None
    world: Hashable | None = None
    kind: str | None = None
    chain: tuple[tuple[int, str, Hashable, Hashable], ...] = ()

    def __bool__(self) -> bool:
        return self.coordinated


def perspective(state: KripkeModel, agent: str) -> KripkeModel:
    """The state re-pointed at every world ``agent`` cannot tell apart from a designated one.

    Uses the knowledge relation (which is the belief relation unless the model keeps a
    separate one), so the actual worlds stay in the perspective.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": [], "b": ["p"]}, designated=["p"])
    >>> perspective(m, "a").designated, perspective(m, "b").designated
    ((0, 1), (1,))
    """
    if agent not in state.agents:
        raise InvalidArgumentError(
            f"unknown agent {agent!r}", hint=f"the model's agents: {', '.join(state.agents)}"
        )
    mask = np.zeros(state.n_worlds, dtype=bool)
    mask[state.designated_positions] = True
    seen = state.knowledge_relations[agent].successors_of(mask)
    return pointed_at(state, np.flatnonzero(seen))


def pointed_at(state: KripkeModel, positions: Iterable[int]) -> KripkeModel:
    """The same model with the worlds at ``positions`` designated (by index)."""
    return KripkeModel.from_arrays(
        state.lazy_names,
        state.atoms,
        state.valuation,
        state.agents,
        state.belief_relations,
        state.knowledge_relations,
        np.asarray(list(positions), dtype=np.intp),
    )


def check_implicit_coordination(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    owners: Mapping[str, str],
    plan: Sequence[str],
    goal: Formula | str,
) -> CoordinationReport:
    """Check whether a sequential plan is implicitly coordinated and explain a failure.

    Parameters
    ----------
    initial : KripkeModel
    actions : mapping
        Action name -> ActionModel.
    owners : mapping
        Action name -> the agent who executes it (every action of the plan needs one).
    plan : sequence of str
    goal : formula or str

    Returns
    -------
    CoordinationReport
        True in a boolean context when the plan is implicitly coordinated.
    """
    check_problem(initial, actions)
    check_owners(initial, actions, owners)
    tree = as_formula(goal)
    initial, table = relevant_part(initial, actions, tree, set(owners.values()))
    if isinstance(plan, str):
        raise InvalidArgumentError("plan must be a sequence of action names", hint=f"[{plan!r}]")
    steps = list(plan)
    for name in steps:
        if name not in table:
            raise InvalidArgumentError(
                f"the plan names an unknown action {name!r}", hint=f"actions: {', '.join(table)}"
            )
    # Worlds keep their names (no contraction) so that a failure can be traced back.
    before: list[KripkeModel] = [initial]  # Y_{k-1}
    shifted: list[KripkeModel] = []  # X_k
    for k, name in enumerate(steps):
        owner = owners[name]
        view = perspective(before[-1], owner)
        shifted.append(view)
        failing = inapplicable_worlds(view, table[name])
        if failing:
            return _not_applicable(k, failing[0], before, shifted, steps, owners)
        before.append(generated_submodel(view.update(table[name])))
    final = before[-1]
    bad = np.flatnonzero(~evaluate(final, tree, table)[final.designated_positions])
    if len(bad):
        if not steps:
            return CoordinationReport(False, f"the goal {tree} does not hold initially")
        reached = final.worlds[final.designated_positions[bad[0]]]
        return _goal_fails(reached[0], before, shifted, steps, owners)
    return CoordinationReport(
        True, f"every owner knows the rest of the plan reaches the goal ({len(steps)} steps)"
    )


def _not_applicable(k, world, before, shifted, steps, owners) -> CoordinationReport:
    """The report of step ``k``'s owner not knowing the step applicable at ``world``."""
    name = steps[k]
    owner, view = owners[name], shifted[k]
    chain = _trace(world, k, before, shifted, steps, owners)
    return CoordinationReport(
        False,
        f"step {k + 1} ({name}): {owner} does not know that {name} is applicable: "
        f"it is not at world {world!r} {_atoms(view, world)} of {owner}'s "
        f"perspective{_story(chain, before)}",
        k,
        owner,
        name,
        world,
        "not-applicable",
        chain,
    )


def _goal_fails(world, before, shifted, steps, owners) -> CoordinationReport:
    """The report of the last step's owner not knowing that the goal will hold."""
    k = len(steps) - 1
    name, owner = steps[k], owners[steps[k]]
    chain = _trace(world, k, before, shifted, steps, owners)
    return CoordinationReport(
        False,
        f"step {k + 1} ({name}): {owner} does not know that the goal will hold: it "
        f"fails after {name} at world {world!r} {_atoms(shifted[k], world)} of "
        f"{owner}'s perspective{_story(chain, before)}",
        k,
        owner,
        name,
        world,
        "goal",
        chain,
    )


def plan_implicitly_coordinated(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    owners: Mapping[str, str],
    goal: Formula | str,
    max_depth: int | None = None,
) -> list[str] | None:
    """The shortest implicitly coordinated sequential plan, or ``None``.

    Breadth-first search over the states ``Yk`` of the definition (contracted and
    deduplicated up to bisimulation, as in :func:`~epistemica.del_.planning.planner.plan`).
    """
    return plan_implicitly_coordinated_with_stats(initial, actions, owners, goal, max_depth).plan


def plan_implicitly_coordinated_with_stats(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    owners: Mapping[str, str],
    goal: Formula | str,
    max_depth: int | None = None,
) -> PlanResult:
    """Like :func:`plan_implicitly_coordinated`, with search statistics."""
    check_problem(initial, actions)
    check_owners(initial, actions, owners)
    tree = as_formula(goal)
    initial, table = relevant_part(initial, actions, tree, set(owners.values()))

    def successors(state: KripkeModel) -> Iterable[tuple[str, KripkeModel]]:
        views: dict[str, KripkeModel] = {}
        for name, action in table.items():
            owner = owners[name]
            if owner not in views:
                views[owner] = perspective(state, owner)
            if applicable_in_all(views[owner], action):
                yield name, views[owner].update(action)

    def is_goal(state: KripkeModel) -> bool:
        return state.holds(tree, actions=table)

    store = KeyedStates(exact_state) if uses_distributed(tree, table.values()) else None
    return search_states(initial, successors, is_goal, "bfs", max_depth, store=store)


def _trace(world, k, before, shifted, steps, owners) -> tuple:
    """Perspective shifts that brought ``world`` (a world of X_k) in, latest first."""
    chain = []
    u = world
    for j in range(k, -1, -1):
        source = before[j]
        points = set(source.designated)
        if u not in points:
            agent = owners[steps[j]]
            mates = source.successors(agent, u, relation="knowledge")
            actual = next(w for w in mates if w in points)
            chain.append((j, agent, u, actual))
            u = actual
        if j > 0:
            u = u[0]  # the world before step j's update
    return tuple(chain)


def _story(chain: tuple, before: list[KripkeModel]) -> str:
    if not chain:
        return ""
    parts = [
        f"at step {j + 1} {agent} could not tell {world!r} {_atoms(before[j], world)} from "
        f"{actual!r} {_atoms(before[j], actual)}"
        for j, agent, world, actual in chain
    ]
    return " (" + "; ".join(parts) + ")"


def _atoms(model: KripkeModel, world) -> str:
    return "{" + ", ".join(sorted(model.valuation_of(world))) + "}"


def check_owners(initial: KripkeModel, actions: Mapping, owners: object) -> None:
    """Every action has an owner, an agent of the model (eagerly, with a hint)."""
    if not isinstance(owners, Mapping):
        raise InvalidArgumentError(
            "owners must map action names to agents", hint="e.g. {'go_r1_g1': 'r1'}"
        )
    for name in actions:
        if name not in owners:
            raise InvalidArgumentError(
                f"action {name!r} has no owner", hint="give every action an owner agent"
            )
        if owners[name] not in initial.agents:
            raise InvalidArgumentError(
                f"the owner {owners[name]!r} of {name!r} is not an agent",
                hint=f"agents: {', '.join(initial.agents)}",
            )
