"""Search over epistemic states with duplicate detection up to bisimulation.

:func:`search_states` is the search engine behind
:func:`~epistemica.del_.planning.planner.plan_with_stats` and
:func:`~epistemica.del_.planning.coordination.plan_implicitly_coordinated`: given a start state, a
successor function and a goal test, it runs ``"bfs"`` (breadth-first, shortest plans),
``"greedy"`` (greedy best-first) or ``"astar"`` (A*) and returns a :class:`PlanResult`.

Every state is contracted to its bisimulation minimum and stored once, keyed by
:func:`~epistemica.del_.explicit.canonical.canonical_key`, so a hash lookup replaces pairwise
:func:`~epistemica.del_.explicit.bisimulation.bisimilar` tests. One object is kept per distinct
state, so the engine's per-model memo of truth sets is reused by every test on that state.

Examples
--------
Toggling a light that nobody sees; the two states (on, off) are found once each:

>>> from epistemica.del_ import KripkeModel, public_assignment
>>> s0 = KripkeModel.from_observables(["on"], {"a": ["on"]}, designated=[])
>>> toggle = public_assignment({"on": "~on"}, ["a"])
>>> result = search_states(s0, lambda s: [("toggle", s.update(toggle))],
...                        lambda s: s.holds("on"))
>>> result.plan, result.distinct, result.complete
(['toggle'], 2, True)
"""

from __future__ import annotations

import heapq
import math
import time
from collections import deque
from collections.abc import Callable, Hashable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from epistemica.del_ import budget
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.action import ActionModel
from epistemica.del_.explicit.bisimulation import edge_count, generated_submodel, quotient
from epistemica.del_.explicit.canonical import canonical_classes
from epistemica.del_.models import KripkeModel
from epistemica.del_.symbolic.structure import SymbolicModel

__all__ = [
    "SEARCHES",
    "Heuristic",
    "KeyedStates",
    "PlanResult",
    "StateStore",
    "check_problem",
    "exact_state",
    "search_states",
    "state_bytes",
]

#: The search strategies that :func:`search_states` accepts.
SEARCHES = ("bfs", "greedy", "astar")

#: A heuristic maps a state to a non-negative estimate of the remaining plan length.
Heuristic = Callable[[KripkeModel], float]


@dataclass(frozen=True)
class PlanResult:
    """The outcome of a search, with statistics.

    Attributes
    ----------
    plan : list of str or None
        The action names of the plan found, or ``None``.
    expanded : int
        States whose successors were generated.
    generated : int
        Successor states produced (before duplicate detection).
    distinct : int
        Distinct states (up to bisimulation) stored.
    seconds : float
        Wall-clock time of the search.
    complete : bool
        True when the search ended without hitting ``max_depth`` or ``max_states``;
        then ``plan is None`` proves that no plan exists.
    search : str
        The strategy used.
    """

    plan: list[str] | None
    expanded: int
    generated: int
    distinct: int
    seconds: float
    complete: bool
    search: str

    @property
    def solved(self) -> bool:
        """Whether a plan was found."""
        return self.plan is not None

    @property
    def length(self) -> int | None:
        """The number of actions of the plan, or ``None``."""
        return None if self.plan is None else len(self.plan)


def search_states(
    initial: KripkeModel,
    successors: Callable[[KripkeModel], Iterable[tuple[str, KripkeModel]]],
    is_goal: Callable[[KripkeModel], bool],
    search: str = "bfs",
    max_depth: int | None = None,
    heuristic: Heuristic | None = None,
    max_states: int | None = None,
    store: StateStore | None = None,
) -> PlanResult:
    """Generic search over epistemic states with duplicate detection up to bisimulation.

    Parameters
    ----------
    initial : KripkeModel
        The start state.
    successors : callable
        ``successors(state)`` yields ``(action name, next state)`` pairs; next states are
        contracted and deduplicated here.
    is_goal : callable
        ``is_goal(state)`` tells whether the search may stop at ``state``.
    search : {"bfs", "greedy", "astar"}
        Breadth-first (shortest plans), greedy best-first or A*.
    max_depth : int, optional
        Longest plan considered.
    heuristic : callable, optional
        For ``greedy``/``astar``: a state's non-negative estimate (default 0).
    max_states : int, optional
        Stop storing new states after this many distinct ones.
    store : StateStore, optional
        Where distinct states are kept: by default Kripke models contracted and keyed by
        :func:`~epistemica.del_.explicit.canonical.canonical_key`; the symbolic planner
        passes one for knowledge structures.

    Returns
    -------
    PlanResult
        The plan (or ``None``) with statistics.

    Raises
    ------
    InvalidArgumentError
        On an unknown search, a bad bound, or a negative or NaN heuristic value.
    """
    if search not in SEARCHES:
        raise InvalidArgumentError(
            f"unknown search {search!r}", hint=f"choose one of {', '.join(SEARCHES)}"
        )
    _check_bound(max_depth, "max_depth", minimum=0)
    _check_bound(max_states, "max_states", minimum=1)
    run = _Search(initial, successors, search, max_depth, max_states, store)
    if search == "bfs":
        return run.breadth_first(is_goal)
    return run.best_first(is_goal, heuristic if heuristic is not None else (lambda s: 0.0))


class _Search:
    """One run of :func:`search_states`: the stored states, each one's parent and depth,
    and the counts a :class:`PlanResult` reports."""

    def __init__(self, initial, successors, search, max_depth, max_states, store) -> None:
        self.start = time.perf_counter()
        self.successors, self.search = successors, search
        self.max_depth, self.max_states = max_depth, max_states
        self.table = KeyedStates() if store is None else store
        self.root = self.table.add(initial)[0]
        self.stored_bytes = state_bytes(self.table.states[self.root])
        self.parent: dict[int, tuple[int, str] | None] = {self.root: None}
        self.depth = {self.root: 0}
        self.expanded = self.generated = 0
        self.truncated = False

    def result(self, found: int | None) -> PlanResult:
        steps = None
        if found is not None:
            steps = []
            node = found
            while self.parent[node] is not None:
                node, name = self.parent[node]  # type: ignore[misc]
                steps.append(name)
            steps.reverse()
        return PlanResult(
            steps,
            self.expanded,
            self.generated,
            len(self.table),
            time.perf_counter() - self.start,
            found is not None or not self.truncated,
            self.search,
        )

    def children(self, node: int):
        """``(action, child index, whether new)`` for each successor of ``node``."""
        if self.max_depth is not None and self.depth[node] >= self.max_depth:
            self.truncated = True
            return
        self.expanded += 1
        for name, child in self.successors(self.table.states[node]):
            self.generated += 1
            if self.max_states is not None and len(self.table) >= self.max_states:
                self.truncated = True
                found = self.table.find(child)
                if found is None:
                    continue
                yield name, found, False
                continue
            index, new = self.table.add(child)
            if new:
                self.stored_bytes += state_bytes(self.table.states[index])
                budget.require(self.stored_bytes, self._stored_what)
            yield name, index, new

    def _stored_what(self) -> str:
        return f"storing the {len(self.table):,} distinct states of the search"

    def reach(self, node: int, child: int, name: str) -> None:
        self.parent[child] = (node, name)
        self.depth[child] = self.depth[node] + 1

    def breadth_first(self, is_goal) -> PlanResult:
        states = self.table.states
        if is_goal(states[self.root]):
            return self.result(self.root)
        queue = deque([self.root])
        while queue:
            node = queue.popleft()
            for name, child, new in self.children(node):
                if not new:
                    continue
                self.reach(node, child, name)
                if is_goal(states[child]):
                    return self.result(child)
                queue.append(child)
        return self.result(None)

    def best_first(self, is_goal, h: Heuristic) -> PlanResult:
        """Greedy best-first (priority h) or A* (depth + h), goals tested once each."""
        greedy = self.search == "greedy"
        goal_memo: dict[int, bool] = {}

        def goal_of(node: int) -> bool:
            if node not in goal_memo:
                goal_memo[node] = bool(is_goal(self.table.states[node]))
            return goal_memo[node]

        def priority(node: int) -> float:
            value = float(h(self.table.states[node]))
            if math.isnan(value) or value < 0:
                raise InvalidArgumentError(
                    f"the heuristic returned {value}", hint="return a non-negative number"
                )
            return value if greedy else self.depth[node] + value

        counter = 0
        heap = [(priority(self.root), counter, self.root)]
        closed: set[int] = set()
        while heap:
            _, _, node = heapq.heappop(heap)
            if node in closed:
                continue
            if goal_of(node):
                return self.result(node)
            closed.add(node)
            for name, child, new in self.children(node):
                better = not new and not greedy and self.depth[node] + 1 < self.depth[child]
                if not (new or better):
                    continue
                self.reach(node, child, name)
                closed.discard(child)
                if greedy and goal_of(child):
                    return self.result(child)
                counter += 1
                heapq.heappush(heap, (priority(child), counter, child))
        return self.result(None)


class StateStore(Protocol):
    """Distinct states, stored once each: what :func:`search_states` needs of a store."""

    states: list

    def __len__(self) -> int: ...

    def find(self, state: Any) -> int | None:
        """The index of a stored state equivalent to ``state``, or None."""

    def add(self, state: Any) -> tuple[int, bool]:
        """Store ``state`` (normalised) unless an equivalent one is; (index, whether new)."""


class KeyedStates:
    """A :class:`StateStore`: each state prepared (contracted, normalised) and keyed, one
    per key. ``prepare(state)`` gives ``(state to store, key)``; the default contracts a
    Kripke model and keys it by :func:`canonical_key`; :func:`exact_state` keeps it
    uncontracted (a task with ``D[G]``)."""

    def __init__(self, prepare: Callable[[Any], tuple[Any, Hashable]] | None = None) -> None:
        self.states: list[Any] = []
        self._index: dict[Hashable, int] = {}
        self._prepare = prepare or _contracted

    def __len__(self) -> int:
        return len(self.states)

    def find(self, state: Any) -> int | None:
        return self._index.get(self._prepare(state)[1])

    def add(self, state: Any) -> tuple[int, bool]:
        """Store ``state`` unless an equivalent (same key) state is stored already."""
        state, key = self._prepare(state)
        found = self._index.get(key)
        if found is not None:
            return found, False
        self.states.append(state)
        self._index[key] = len(self.states) - 1
        return len(self.states) - 1, True


def state_bytes(state: Any) -> int:
    """Estimated bytes a stored explicit state holds (its valuation matrix and about 16
    bytes per edge of its relations); 0 for other states (BDDs are bounded by the symbolic
    backend's node limit).

    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []})
    >>> state_bytes(m) == m.valuation.nbytes + 16 * 2
    True
    """
    if not isinstance(state, KripkeModel):
        return 0
    relations = {id(r): r for r in state.belief_relations.values()}
    relations.update({id(r): r for r in state.knowledge_relations.values()})
    return state.valuation.nbytes + 16 * sum(edge_count(r) for r in relations.values())


def exact_state(state: KripkeModel) -> tuple[KripkeModel, tuple]:
    """The generated submodel, keyed by its arrays (equal keys: the same model, world for
    world). For tasks with distributed knowledge, which a bisimulation contraction can
    change (:func:`~epistemica.del_.planning.relevance.uses_distributed`): duplicates are
    then found only when identical, never merged when merely bisimilar.

    >>> from epistemica.del_ import KripkeModel
    >>> def m(actual):
    ...     return KripkeModel.from_observables(["p"], {"a": []}, designated=actual)
    >>> key = exact_state(m(["p"]))[1]
    >>> key == exact_state(m(["p"]))[1], key == exact_state(m([]))[1]
    (True, False)
    """
    state = generated_submodel(state)
    relations = []
    for agent in state.agents:
        belief, knowledge = state.belief_relations[agent], state.knowledge_relations[agent]
        relations.append(np.packbits(belief.to_dense()).tobytes())
        if knowledge is not belief:
            relations.append(np.packbits(knowledge.to_dense()).tobytes())
    valuation = np.packbits(state.valuation, axis=1)
    return state, (state.valuation.shape, valuation.tobytes(),
                   np.asarray(state.designated_positions).tobytes(), *relations)  # fmt: skip


def _contracted(state: KripkeModel) -> tuple[KripkeModel, tuple]:
    """The bisimulation contraction of the generated submodel, and its canonical key."""
    state = generated_submodel(state)
    labels, key = canonical_classes(state)
    return quotient(state, np.asarray(labels, dtype=np.intp)), key


_KIND_NAMES = {KripkeModel: "KripkeModel", SymbolicModel: "KnowledgeStructure"}
_KIND_HINTS = {
    KripkeModel: "build one with KripkeModel(...) or KripkeModel.from_observables(...)",
    SymbolicModel: "build one with KnowledgeStructure.from_observables(...) or "
    "KripkeModel.to_symbolic()",
}


def _check_bound(value: object, name: str, minimum: int) -> None:
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InvalidArgumentError(
            f"{name} must be an integer >= {minimum} or None, got {value!r}",
            hint=f"e.g. {name}=10",
        )


def check_problem(initial: object, actions: object, kind: type = KripkeModel) -> None:
    """Validate a planning problem's initial state (a ``kind``) and named actions eagerly."""
    if not isinstance(initial, kind):
        raise InvalidArgumentError(
            f"the initial state must be a {_KIND_NAMES.get(kind, kind.__name__)}, "
            f"got {type(initial).__name__}",
            hint=_KIND_HINTS.get(kind, "build it with from_observables(...)"),
        )
    if not isinstance(actions, Mapping):
        raise InvalidArgumentError(
            "actions must map action names to ActionModels",
            hint="e.g. {'open': open_action, 'peek': peek_action}",
        )
    agents = set(initial.agents)
    for name, action in actions.items():
        if not isinstance(name, str) or not name:
            raise InvalidArgumentError(
                f"action names must be non-empty strings, got {name!r}", hint="e.g. 'open'"
            )
        if not isinstance(action, ActionModel):
            raise InvalidArgumentError(
                f"action {name!r} is a {type(action).__name__}, not an ActionModel",
                hint="build it with ActionModel(...) or observability_action(...)",
            )
        if set(action.agents) != agents:
            raise InvalidArgumentError(
                f"action {name!r} has agents {sorted(action.agents)}, the initial state "
                f"{sorted(agents)}",
                hint="every action must give a relation to exactly the model's agents",
            )
