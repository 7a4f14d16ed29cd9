"""Implicitly coordinated policies (Engesser, Bolander, Mattmüller and Nebel, 2017).

A sequential implicitly coordinated plan (:mod:`~epistemica.del_.planning.coordination`)
fixes every action in advance. A *policy* may branch on what the acting agent observes:
an agent that learns which world it is in picks the action for that world, and the next
agent, watching it, picks its own from what it then knows.

Semantics (perspective shifts, as in the sequential case; ``s^i`` is agent ``i``'s
perspective on ``s``, the same model pointed at every world ``i`` cannot tell apart from a
designated one by its knowledge relation). A policy is a finite tree of decisions. Each
decision names an agent ``i``, a condition ``when`` on what ``i`` knows (a conjunction of
literals), and an action ``a`` that ``i`` owns. From a state ``O`` (the initial state, or
the outcome of the previous decision) the policy continues with one agent ``i``: for every
designated world ``w`` of ``O`` where the goal does not yet hold at every world of
``(O, w)^i``, exactly one of the decisions for ``i`` has a condition that ``i`` knows in
``L = (O, w)^i``; its action must be applicable at every designated world of ``L``, and
the policy goes on from ``L ⊗ a``. A branch ends when the goal holds at every designated
world of its state. So every acting agent knows, at its decision point, that its action
is executable and, by induction, that the rest of the policy reaches the goal in every
world it considers possible: the policy is *strong* from each actor's perspective.

:func:`check_policy` verifies a policy against that definition from scratch, and also
that it is *uniform* (an agent in the same local state, up to bisimulation, at two
decision points is told the same action) and that nobody else has a decision for its own
local state where another agent is to act (so no two agents act at once).
:func:`plan_policy` searches for a policy of least depth (iterative deepening over an
AND-OR search, memoised by agent and local state), each branching's conditions being the
literals the next agent knows that tell its possible local states apart.

Examples
--------
Robot r1 knows which spot is its task, r2 does not (``specs/planning/two_robots_implicit.epi``).
From r2's perspective both worlds are possible; r1 goes to its task, whichever it is, and
r2, having watched, goes to the other spot:

>>> from epistemica.del_ import KripkeModel, public_assignment
>>> s0 = KripkeModel.from_observables(["t", "at1", "at2", "b1", "b2"], {"r1": ["t"], "r2": []},
...                                    law="~at1 & ~at2 & ~b1 & ~b2")    # t unknown to r2
>>> agents = ["r1", "r2"]
>>> acts = {"r1_g1": public_assignment({"at1": "true"}, agents, pre="t"),
...         "r1_g2": public_assignment({"at2": "true"}, agents, pre="~t"),
...         "r2_g1": public_assignment({"b1": "true"}, agents, pre="~at1"),
...         "r2_g2": public_assignment({"b2": "true"}, agents, pre="~at2")}
>>> owners = {"r1_g1": "r1", "r1_g2": "r1", "r2_g1": "r2", "r2_g2": "r2"}
>>> goal = "(t & at1 & b2) | (~t & at2 & b1)"
>>> policy = plan_policy(s0, acts, owners, goal).policy
>>> print(policy)
r1, when it knows t: r1_g1
  r2: r2_g2
r1, when it knows ~t: r1_g2
  r2: r2_g1
>>> bool(check_policy(s0, acts, owners, goal, policy))
True
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.explicit.bisimulation import generated_submodel
from epistemica.del_.explicit.canonical import canonical_key
from epistemica.del_.language.formula import And, Atom, Formula, Not, Top
from epistemica.del_.language.parser import as_formula
from epistemica.del_.models import KripkeModel
from epistemica.del_.planning.coordination import check_owners, perspective, pointed_at
from epistemica.del_.planning.planner import applicable_in_all, relevant_part
from epistemica.del_.planning.relevance import uses_distributed
from epistemica.del_.planning.state_space import check_problem, exact_state

__all__ = ["Decision", "Policy", "PolicyReport", "PolicyResult", "check_policy", "plan_policy"]


@dataclass(frozen=True)
class Decision:
    """One decision of a policy: ``agent``, when it knows ``when``, does ``action``; then
    the policy goes on with ``then`` (the next agent's decisions; empty when done)."""

    agent: str
    when: Formula
    action: str
    then: tuple[Decision, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "agent": self.agent,
            "when": str(self.when),
            "action": self.action,
            "then": [d.to_dict() for d in self.then],
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Decision:
        """A decision from :meth:`to_dict`'s form (``when`` as formula text)."""
        try:
            return cls(
                str(data["agent"]),
                as_formula(data.get("when", "true")),
                str(data["action"]),
                tuple(cls.from_dict(d) for d in data.get("then", ())),
            )
        except (KeyError, TypeError) as error:
            raise InvalidArgumentError(
                f"a policy decision needs 'agent' and 'action' ({error})",
                hint='e.g. {"agent": "r1", "when": "t", "action": "go", "then": []}',
            ) from None


@dataclass(frozen=True)
class Policy:
    """A policy: the first decisions (of one agent); empty when the goal holds already."""

    decisions: tuple[Decision, ...]

    def __str__(self) -> str:
        lines: list[str] = []
        _render(self.decisions, 0, lines)
        return "\n".join(lines) if lines else "(nothing to do: the goal holds)"

    @property
    def depth(self) -> int:
        """The most actions along a branch."""
        return _depth(self.decisions)

    @property
    def size(self) -> int:
        """The number of decisions."""
        return sum(1 + Policy(d.then).size for d in self.decisions)

    def to_dict(self) -> dict[str, Any]:
        return {"policy": [d.to_dict() for d in self.decisions]}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Policy:
        decisions = data.get("policy") if isinstance(data, Mapping) else None
        if not isinstance(decisions, list):
            raise InvalidArgumentError(
                "a policy is an object with a list 'policy' of decisions",
                hint="write it with `epistemica plan SPEC --implicit --policy --json`",
            )
        return cls(tuple(Decision.from_dict(d) for d in decisions))


@dataclass(frozen=True)
class PolicyResult:
    """The outcome of :func:`plan_policy`."""

    policy: Policy | None
    depth_searched: int
    local_states: int
    seconds: float
    complete: bool

    @property
    def solved(self) -> bool:
        return self.policy is not None


@dataclass(frozen=True)
class PolicyReport:
    """The verdict of :func:`check_policy`; true in a boolean context when it holds."""

    ok: bool
    reason: str
    path: tuple[str, ...] = field(default=())

    def __bool__(self) -> bool:
        return self.ok


def plan_policy(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    owners: Mapping[str, str],
    goal: Formula | str,
    max_depth: int = 12,
    perspective_of: str | None = None,
) -> PolicyResult:
    """A least-depth implicitly coordinated policy from ``initial`` (see the module).

    Parameters
    ----------
    initial : KripkeModel
        The initial state; the policy must work at every designated world.
    actions, owners, goal
        As for :func:`~epistemica.del_.planning.coordination.plan_implicitly_coordinated`.
    max_depth : int
        The deepest policy tried.
    perspective_of : str, optional
        Plan from this agent's perspective on ``initial`` (every world it considers
        possible designated), as that agent would.
    """
    start = time.perf_counter()
    search = _Search(initial, actions, owners, goal, perspective_of)
    if search.goal_everywhere(search.root):
        return PolicyResult(Policy(()), 0, 0, time.perf_counter() - start, True)
    for depth in range(1, max_depth + 1):
        search.cut = False
        found = search.solve_state(search.root, depth)
        if found is not None:
            elapsed = time.perf_counter() - start
            return PolicyResult(Policy(found), depth, len(search.memo), elapsed, True)
        if not search.cut:  # nothing was cut off by the bound: deeper will not help
            return PolicyResult(None, depth, len(search.memo), time.perf_counter() - start, True)
    return PolicyResult(None, max_depth, len(search.memo), time.perf_counter() - start, False)


def check_policy(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    owners: Mapping[str, str],
    goal: Formula | str,
    policy: Policy,
    perspective_of: str | None = None,
) -> PolicyReport:
    """Whether ``policy`` is an implicitly coordinated (strong, uniform) policy, and if
    not, where and why it fails (see the module for the definition)."""
    problem = _Problem(initial, actions, owners, goal, perspective_of)
    for decision in _walk(policy.decisions):
        if decision.agent not in problem.state.agents:
            return PolicyReport(False, f"unknown agent {decision.agent!r} in the policy")
        if decision.action not in problem.actions:
            return PolicyReport(False, f"unknown action {decision.action!r} in the policy")
        if problem.owners[decision.action] != decision.agent:
            return PolicyReport(
                False,
                f"{decision.agent} cannot do {decision.action}: its owner is "
                f"{problem.owners[decision.action]}",
            )
    checker = _Checker(problem)
    failure = checker.follow(problem.root, policy.decisions, ())
    if failure is not None:
        return failure
    return checker.coordinated()


# -- the search ---------------------------------------------------------------------------


class _Problem:
    """A policy problem on the part of the state that planning can see."""

    def __init__(self, initial, actions, owners, goal, perspective_of) -> None:
        check_problem(initial, actions)
        check_owners(initial, actions, owners)
        self.goal = as_formula(goal)
        self.owners = dict(owners)
        keep = set(owners.values()) | ({perspective_of} if perspective_of else set())
        state, self.actions = relevant_part(initial, actions, self.goal, keep)
        self.state = state
        if perspective_of is not None:
            state = perspective(state, perspective_of)
        self.root = generated_submodel(state)
        self.acting = [a for a in state.agents if a in set(self.owners.values())]
        # D[G] is not invariant under contraction: such views are kept whole, keyed exactly
        self.exact = uses_distributed(self.goal, self.actions.values())

    def normal(self, view: KripkeModel) -> tuple[KripkeModel, tuple]:
        """A view as it is stored: contracted with its canonical key, or whole (D[G])."""
        if self.exact:
            return exact_state(view)
        view = view.minimize()
        return view, canonical_key(view)

    def goal_everywhere(self, state: KripkeModel) -> bool:
        return state.holds(self.goal, actions=self.actions)

    def views(self, state: KripkeModel, agent: str) -> list[tuple[tuple, KripkeModel]]:
        """``agent``'s distinct perspectives on the designated worlds of ``state``
        (each contracted, with its canonical key), in a fixed order."""
        found: dict[tuple, KripkeModel] = {}
        for point in state.designated_positions.tolist():
            view = perspective(pointed_at(state, [point]), agent)
            view, key = self.normal(view)
            found.setdefault(key, view)
        return sorted(found.items(), key=lambda item: repr(item[0]))

    def outcome(self, view: KripkeModel, action: str) -> KripkeModel:
        return generated_submodel(view.update(self.actions[action]))


class _Search(_Problem):
    """AND-OR search: a state is solved by one agent's decisions covering its views."""

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.memo: dict[tuple, tuple[int, Decision | None]] = {}
        self.cut = False

    def solve_state(self, state: KripkeModel, depth: int) -> tuple[Decision, ...] | None:
        """Decisions of one agent covering every designated world of ``state``."""
        for agent in self.acting:
            views = [v for v in self.views(state, agent) if not self.goal_everywhere(v[1])]
            if not views:
                return ()
            chosen = []
            for key, view in views:
                found = self.solve_view(agent, key, view, depth)
                if found is None:
                    break
                chosen.append((view, found))
            else:
                labelled = _label(agent, chosen)
                if labelled is not None:
                    return labelled
        return None

    def solve_view(self, agent: str, key: tuple, view: KripkeModel, depth: int):
        """An action of ``agent`` and the rest of the policy, from its local state."""
        memo_key = (agent, key)
        tried, found = self.memo.get(memo_key, (-1, None))
        if found is not None and _depth((found,)) <= depth:
            return found  # the same local state, the same decision: uniform by design
        if found is None and tried >= depth:
            return None
        if depth == 0:
            self.cut = True
            return None
        for action in self.actions:
            if self.owners[action] != agent or not applicable_in_all(view, self.actions[action]):
                continue
            after = self.outcome(view, action)
            if self.goal_everywhere(after):
                rest: tuple[Decision, ...] | None = ()
            else:
                rest = self.solve_state(after, depth - 1)
            if rest is not None:
                found = Decision(agent, Top(), action, rest)
                self.memo[memo_key] = (depth, found)
                return found
        self.memo[memo_key] = (depth, None)
        return None


def _label(agent: str, chosen: list[tuple[KripkeModel, Decision]]) -> tuple[Decision, ...] | None:
    """The decisions with conditions: the literals ``agent`` knows that tell its local
    states apart (``true`` for a single one); None when literals cannot tell them apart."""
    if len(chosen) == 1:
        return (chosen[0][1],)
    known = [_known_literals(view) for view, _ in chosen]
    varying = set().union(*known) - set.intersection(*known)
    decisions = []
    for (_, decision), literals in zip(chosen, known, strict=True):
        when = [lit for lit in literals if lit in varying]
        decisions.append(
            Decision(agent, _conjunction(sorted(when)), decision.action, decision.then)
        )
    conditions = [d.when for d in decisions]
    for i, (view, _) in enumerate(chosen):
        matching = [j for j, c in enumerate(conditions) if view.holds(c)]
        if matching != [i]:
            return None
    return tuple(sorted(decisions, key=lambda d: str(d.when)))


def _known_literals(view: KripkeModel) -> set[tuple[str, bool]]:
    """The atom literals true at every designated world of ``view``."""
    points = view.designated_positions
    values = view.valuation[points]
    return {
        (atom, bool(values[0, j]))
        for j, atom in enumerate(view.atoms)
        if values[:, j].all() or not values[:, j].any()
    }


def _conjunction(literals: Iterable[tuple[str, bool]]) -> Formula:
    parts = [Atom(a) if value else Not(Atom(a)) for a, value in literals]
    if not parts:
        return Top()
    result = parts[0]
    for part in parts[1:]:
        result = And(result, part)
    return result


# -- checking -----------------------------------------------------------------------------


class _Checker:
    """Follows a policy from the root, recording who decides what in which local state."""

    def __init__(self, problem: _Problem) -> None:
        self.problem = problem
        self.decided: dict[tuple[str, tuple], tuple[str, tuple[str, ...]]] = {}
        self.turns: list[tuple[str, KripkeModel, tuple[str, ...]]] = []

    def follow(self, state: KripkeModel, decisions: tuple[Decision, ...], path: tuple):
        p = self.problem
        if p.goal_everywhere(state):
            return None
        if not decisions:
            return PolicyReport(False, f"the goal {p.goal} does not hold and nobody acts", path)
        agent = decisions[0].agent
        if any(d.agent != agent for d in decisions):
            return PolicyReport(False, "decisions of one branching belong to one agent", path)
        for key, view in p.views(state, agent):
            if p.goal_everywhere(view):
                continue
            matching = [d for d in decisions if view.holds(d.when)]
            where = (*path, f"{agent} in {_describe(view)}")
            if len(matching) != 1:
                return PolicyReport(
                    False,
                    f"{agent} cannot tell which decision is its own: "
                    f"{len(matching)} conditions hold in its local state {_describe(view)}",
                    where,
                )
            decision = matching[0]
            where = (*path, f"{agent}: {decision.action}")
            earlier = self.decided.setdefault((agent, key), (decision.action, where))
            if earlier[0] != decision.action:
                return PolicyReport(
                    False,
                    f"{agent} is told {earlier[0]} and {decision.action} in the same local state "
                    f"(not uniform): at {' / '.join(earlier[1])} and at {' / '.join(where)}",
                    where,
                )
            self.turns.append((agent, state, where))
            if not applicable_in_all(view, p.actions[decision.action]):
                return PolicyReport(
                    False,
                    f"{agent} does not know that {decision.action} is applicable: it is not "
                    f"applicable at every world of its local state {_describe(view)}",
                    where,
                )
            failure = self.follow(p.outcome(view, decision.action), decision.then, where)
            if failure is not None:
                return failure
        return None

    def coordinated(self) -> PolicyReport:
        """No agent has a decision for its local state where another agent acts."""
        p = self.problem
        acting = {(agent, key) for agent, key in self.decided}
        for agent, state, where in self.turns:
            for other in p.acting:
                if other == agent:
                    continue
                for key, _ in p.views(state, other):
                    if (other, key) in acting:
                        return PolicyReport(
                            False,
                            f"{other} also has a decision for its local state where {agent} is "
                            f"to act (at {' / '.join(where)}): both would act",
                            where,
                        )
        depth = max((len(w) for _, _, w in self.turns), default=0)
        return PolicyReport(
            True,
            f"every acting agent knows its action is applicable and that the rest of the policy "
            f"reaches the goal ({len(self.decided)} local states, depth {depth})",
        )


def _walk(decisions: tuple[Decision, ...]):
    for d in decisions:
        yield d
        yield from _walk(d.then)


def _depth(decisions: tuple[Decision, ...]) -> int:
    return max((1 + _depth(d.then) for d in decisions), default=0)


def _render(decisions: tuple[Decision, ...], indent: int, lines: list[str]) -> None:
    for d in decisions:
        condition = "" if isinstance(d.when, Top) else f", when it knows {d.when}"
        lines.append("  " * indent + f"{d.agent}{condition}: {d.action}")
        _render(d.then, indent + 1, lines)


def _describe(view: KripkeModel) -> str:
    literals = sorted(_known_literals(view))
    return "{" + ", ".join(a if v else f"~{a}" for a, v in literals) + "}"
