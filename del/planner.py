"""Epistemic planning: search for action sequences that reach an epistemic goal.

A planning problem is the paper's ``Plan(s0, Gamma, B)``: an initial epistemic state
``s0`` (a possibly multi-pointed :class:`~epistemica.del_.kripke.KripkeModel`), named
action models, and a goal formula; a plan is a sequence of action names that is
applicable step by step and ends in a state where the goal holds at every designated
world.

Semantics (Bolander and Andersen's sequential plans):

- an action is *applicable* in a state when at **every** designated world some
  designated event's precondition holds (so a plan from a multi-pointed state works
  whichever designated world is actual);
- the successor state is the product update, contracted to its bisimulation minimum
  (:meth:`~epistemica.del_.kripke.KripkeModel.minimize`), which preserves every formula.

Search: ``"bfs"`` (breadth-first, shortest plans), ``"greedy"`` (greedy best-first) and
``"astar"`` (A*), the last two guided by a heuristic (default: the number of top-level
conjuncts of the goal that do not hold yet, which is not admissible, so A* with it may
return a longer plan than breadth-first search; ``heuristic="blind"`` is admissible).
States are deduplicated up to bisimulation: each contracted state is keyed by an exact
canonical form of its bisimulation class (:func:`canonical_key`, a partition refinement
with order-independent class names), so a hash lookup replaces pairwise
:func:`~epistemica.del_.bisimulation.bisimilar` tests.
One object is kept per distinct state, so the engine's per-model memo of truth sets is
reused by every precondition and goal test on that state, and nested modalities are
evaluated once per subformula and state.

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

import heapq
import math
import time
from collections import deque
from collections.abc import Callable, Hashable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from epistemica.del_.action import ActionModel, product_update
from epistemica.del_.bisimulation import generated_submodel, quotient
from epistemica.del_.checker import as_formula, evaluate
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.formula import (
    And,
    Common,
    Distributed,
    Everybody,
    Formula,
    Know,
    KnowWhether,
)
from epistemica.del_.kripke import KripkeModel
from epistemica.del_.relations import Partition, Relation

__all__ = [
    "SEARCHES",
    "PlanResult",
    "Validation",
    "applicable",
    "canonical_key",
    "goal_count",
    "plan",
    "plan_with_stats",
    "uses_knowledge",
    "validate",
]

SEARCHES = ("bfs", "greedy", "astar")

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
        The (contracted) states reached, starting with the initial one.
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
        Action name -> :class:`~epistemica.del_.action.ActionModel`; tried in this order.
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
    _check_problem(initial, actions)
    tree = as_formula(goal)
    table = dict(actions)
    # Without K, Kw, E, C or D anywhere, states that agree on beliefs are interchangeable:
    # the search then tracks belief relations only (half the relational work).
    beliefs_only = not uses_knowledge(tree, table.values())
    if beliefs_only:
        initial = _forget_knowledge(initial)

    def successors(state: KripkeModel) -> Iterable[tuple[str, KripkeModel]]:
        for name, action in table.items():
            if applicable(state, action):
                yield name, product_update(state, action, beliefs_only=beliefs_only)

    def is_goal(state: KripkeModel) -> bool:
        return state.holds(tree, actions=table)

    h = _heuristic(heuristic, search, tree, table)
    return search_states(initial, successors, is_goal, search, max_depth, h, max_states)


def validate(
    initial: KripkeModel,
    actions: Mapping[str, ActionModel],
    plan: Sequence[str],
    goal: Formula | str,
) -> Validation:
    """Check a plan: every step applicable, the goal true at the end.

    Returns a :class:`Validation`, true in a boolean context when the plan is valid and
    carrying the reason otherwise.

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
    step 1 (deny) is not applicable: ... at designated world(s) [1]
    """
    _check_problem(initial, actions)
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
    state = initial.minimize()
    states = [state]
    for i, name in enumerate(steps):
        failing = inapplicable_worlds(state, table[name])
        if failing:
            return Validation(
                False,
                f"step {i + 1} ({name}) is not applicable: no designated event's precondition "
                f"holds at designated world(s) {failing}",
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
            f"after the plan the goal {tree} fails at designated world(s) {bad}",
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
    formulas = [goal]
    for action in actions:
        formulas.extend(action.pre)
        formulas.extend(v for changes in action.post for v in changes.values())
        for edges in (*action._edges.values(), *action._know_edges.values()):
            formulas.extend(c for _, _, c in edges if c is not None)
    return any(isinstance(g, _KNOWLEDGE_NODES) for f in formulas for g in f.subformulas())


def _forget_knowledge(state: KripkeModel) -> KripkeModel:
    """The same state with each agent's knowledge relation replaced by its belief relation."""
    if not state.has_separate_knowledge():
        return state
    rel = state._rel
    return KripkeModel._from_arrays(
        state._names, state.atoms, state._val, state.agents, rel, dict(rel), state._designated
    )


def applicable(state: KripkeModel, action: ActionModel) -> bool:
    """Whether at every designated world some designated event is executable.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel, public_announcement
    >>> both = KripkeModel.from_observables(["p"], {"a": []})   # p and ~p designated
    >>> applicable(both, public_announcement("p", ["a"]))
    False
    """
    return bool(_executable_at_points(state, action).all())


def inapplicable_worlds(state: KripkeModel, action: ActionModel) -> list[Hashable]:
    """The designated worlds at which no designated event of ``action`` is executable."""
    ok = _executable_at_points(state, action)
    names = state.worlds
    return [names[i] for i in state._designated[~ok]]


def _executable_at_points(state: KripkeModel, action: ActionModel) -> np.ndarray:
    """Per designated world, whether some designated event's precondition holds there."""
    points = state._designated
    ok = np.zeros(len(points), dtype=bool)
    for e in action._designated:
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


def search_states(
    initial: KripkeModel,
    successors: Callable[[KripkeModel], Iterable[tuple[str, KripkeModel]]],
    is_goal: Callable[[KripkeModel], bool],
    search: str = "bfs",
    max_depth: int | None = None,
    heuristic: Heuristic | None = None,
    max_states: int | None = None,
) -> PlanResult:
    """Generic search over epistemic states with duplicate detection up to bisimulation.

    ``successors(state)`` yields ``(action name, next state)`` pairs; next states are
    contracted and deduplicated here. Used by :func:`plan_with_stats` and by the search
    for implicitly coordinated plans.
    """
    if search not in SEARCHES:
        raise InvalidArgumentError(
            f"unknown search {search!r}", hint=f"choose one of {', '.join(SEARCHES)}"
        )
    _check_bound(max_depth, "max_depth", minimum=0)
    _check_bound(max_states, "max_states", minimum=1)
    start = time.perf_counter()
    table = _StateTable()
    root = table.add(initial.minimize())[0]
    parent: dict[int, tuple[int, str] | None] = {root: None}
    depth = {root: 0}
    stats = {"expanded": 0, "generated": 0}
    truncated = False

    def result(found: int | None) -> PlanResult:
        steps = None
        if found is not None:
            steps = []
            node = found
            while parent[node] is not None:
                node, name = parent[node]  # type: ignore[misc]
                steps.append(name)
            steps.reverse()
        return PlanResult(
            steps,
            stats["expanded"],
            stats["generated"],
            len(table),
            time.perf_counter() - start,
            found is not None or not truncated,
            search,
        )

    def children(node: int):
        nonlocal truncated
        if max_depth is not None and depth[node] >= max_depth:
            truncated = True
            return
        stats["expanded"] += 1
        for name, child in successors(table.states[node]):
            stats["generated"] += 1
            if max_states is not None and len(table) >= max_states:
                truncated = True
                found = table.find(child)
                if found is None:
                    continue
                yield name, found, False
                continue
            index, new = table.add(child)
            yield name, index, new

    if search == "bfs":
        if is_goal(table.states[root]):
            return result(root)
        queue = deque([root])
        while queue:
            node = queue.popleft()
            for name, child, new in children(node):
                if not new:
                    continue
                parent[child] = (node, name)
                depth[child] = depth[node] + 1
                if is_goal(table.states[child]):
                    return result(child)
                queue.append(child)
        return result(None)

    h = heuristic if heuristic is not None else (lambda s: 0.0)
    greedy = search == "greedy"
    goal_memo: dict[int, bool] = {}

    def goal_of(node: int) -> bool:
        if node not in goal_memo:
            goal_memo[node] = bool(is_goal(table.states[node]))
        return goal_memo[node]

    def priority(node: int) -> float:
        value = float(h(table.states[node]))
        if math.isnan(value) or value < 0:
            raise InvalidArgumentError(
                f"the heuristic returned {value}", hint="return a non-negative number"
            )
        return value if greedy else depth[node] + value

    counter = 0
    heap = [(priority(root), counter, root)]
    closed: set[int] = set()
    while heap:
        _, _, node = heapq.heappop(heap)
        if node in closed:
            continue
        if goal_of(node):
            return result(node)
        closed.add(node)
        for name, child, new in children(node):
            better = not new and not greedy and depth[node] + 1 < depth[child]
            if not (new or better):
                continue
            parent[child] = (node, name)
            depth[child] = depth[node] + 1
            closed.discard(child)
            if greedy and goal_of(child):
                return result(child)
            counter += 1
            heapq.heappush(heap, (priority(child), counter, child))
    return result(None)


class _StateTable:
    """Distinct states up to bisimulation, keyed by :func:`canonical_key`."""

    def __init__(self) -> None:
        self.states: list[KripkeModel] = []
        self._index: dict[tuple, int] = {}

    def __len__(self) -> int:
        return len(self.states)

    def find(self, state: KripkeModel) -> int | None:
        return self._index.get(canonical_key(generated_submodel(state)))

    def add(self, state: KripkeModel) -> tuple[int, bool]:
        """Contract ``state`` and store it unless a bisimilar state is stored already."""
        state = generated_submodel(state)
        labels, key = _canonical_classes(state)
        found = self._index.get(key)
        if found is not None:
            return found, False
        self.states.append(quotient(state, np.asarray(labels, dtype=np.intp)))
        self._index[key] = len(self.states) - 1
        return len(self.states) - 1, True


def canonical_key(state: KripkeModel) -> tuple:
    """A canonical form of the bisimulation class of a pointed model.

    Partition refinement in which every class is named by its rank in the sorted order
    of its description (valuation first, then per agent and relation the set of classes
    reached), so the names do not depend on the order or names of the worlds. At the
    fixed point the classes are the bisimulation classes and the key spells out the
    quotient model (each class's valuation and successors, and the designated classes).
    Two models get the same key exactly when they are bisimilar, provided both are
    contracted (:meth:`~epistemica.del_.kripke.KripkeModel.minimize`); for other models
    equal keys still imply bisimilarity.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "q"], {"a": ["p"]}, designated=["p"])
    >>> canonical_key(m.minimize()) == canonical_key(m.announce("q | ~q").minimize())
    True
    >>> canonical_key(m.minimize()) == canonical_key(m.announce("~q").minimize())
    False
    """
    return _canonical_classes(state)[1]


def _canonical_classes(state: KripkeModel) -> tuple[list[int], tuple]:
    """The canonical refinement's class of each world, and the canonical key."""
    atoms = sorted(a for a, column in zip(state.atoms, state._val.T, strict=True) if column.any())
    relations = [
        relation
        for agent in sorted(state.agents)
        for relation in (state._rel[agent], state._know[agent])
    ]
    if len(atoms) < _MASK_BITS:
        found = _canonical_bitmasks(state, atoms, relations)
        if found is not None:
            return found
    return _canonical_tuples(state, atoms, relations)


# Sets of at most this many classes (and valuations of fewer atoms) are int64 bitmasks.
_MASK_BITS = 62


def _canonical_bitmasks(
    state: KripkeModel, atoms: list[str], relations: list[Relation]
) -> tuple[list[int], tuple] | None:
    """Vectorised canonical refinement; None when the classes outgrow a 64-bit mask.

    Whether it applies depends only on the number of bisimulation classes, so bisimilar
    states always get keys of the same kind.
    """
    columns = [state.atoms.index(a) for a in atoms]
    codes = state._val[:, columns].astype(np.int64) @ (np.int64(1) << np.arange(len(atoms)))
    labels = np.unique(codes, return_inverse=True)[1].reshape(-1)
    count = int(labels.max()) + 1
    while True:
        if count > _MASK_BITS:
            return None
        masks: dict[int, np.ndarray] = {}  # a relation shared by belief and knowledge
        for r in relations:
            if id(r) not in masks:
                masks[id(r)] = _reached_mask(r, labels)
        described = np.column_stack([labels] + [masks[id(r)] for r in relations])
        order = np.lexsort(described.T[::-1])
        ordered = described[order]
        changed = np.zeros(len(labels), dtype=bool)
        changed[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
        refined = np.empty_like(labels)
        refined[order] = np.cumsum(changed)
        new_count = int(refined.max()) + 1
        labels = refined
        if new_count == count:
            break
        count = new_count
    first = np.unique(labels, return_index=True)[1]  # one world per class, by class
    table = np.column_stack([codes, described[:, 1:]])[first]
    points = tuple(np.unique(labels[state._designated]).tolist())
    return labels.tolist(), (tuple(atoms), table.tobytes(), points)


def _reached_mask(relation: Relation, labels: np.ndarray) -> np.ndarray:
    """Per world, the set of classes of its successors as a bitmask."""
    bits = np.int64(1) << labels.astype(np.int64)
    if isinstance(relation, Partition):
        per_class = np.zeros(relation.n_labels, dtype=np.int64)
        np.bitwise_or.at(per_class, relation.labels, bits)
        return per_class[relation.labels]
    rows, cols = relation.edges()
    reached = np.zeros(len(labels), dtype=np.int64)
    np.bitwise_or.at(reached, rows, bits[cols])
    return reached


def _canonical_tuples(
    state: KripkeModel, atoms: list[str], relations: list[Relation]
) -> tuple[list[int], tuple]:
    """Canonical refinement on Python tuples, for states of many classes."""
    columns = [state.atoms.index(a) for a in atoms]
    rows = [tuple(np.flatnonzero(row)) for row in state._val[:, columns]]
    labels = _ranks(rows)
    count = len(set(labels))
    while True:
        reached = [_reached_labels(relation, labels) for relation in relations]
        described = [(labels[w], *(r[w] for r in reached)) for w in range(state.n_worlds)]
        labels = _ranks(described)
        new_count = len(set(labels))
        if new_count == count:
            break
        count = new_count
    classes = {}
    for w, label in enumerate(labels):
        classes.setdefault(label, (rows[w], described[w][1:]))
    points = tuple(sorted({labels[i] for i in state._designated}))
    return labels, (tuple(atoms), tuple(classes[k] for k in range(count)), points)


def _reached_labels(relation: Relation, labels: list[int]) -> list[tuple[int, ...]]:
    """Per world, the sorted labels of its successors."""
    if isinstance(relation, Partition):
        members: dict[int, set[int]] = {}
        for cls, label in zip(relation.labels.tolist(), labels, strict=True):
            members.setdefault(cls, set()).add(label)
        frozen = {cls: tuple(sorted(found)) for cls, found in members.items()}
        return [frozen[cls] for cls in relation.labels.tolist()]
    found: list[set[int]] = [set() for _ in labels]
    for w, v in zip(*(side.tolist() for side in relation.edges()), strict=True):
        found[w].add(labels[v])
    return [tuple(sorted(targets)) for targets in found]


def _ranks(items: list) -> list[int]:
    order = {item: rank for rank, item in enumerate(sorted(set(items)))}
    return [order[item] for item in items]


def _conjuncts(f: Formula) -> list[Formula]:
    if isinstance(f, And):
        return _conjuncts(f.left) + _conjuncts(f.right)
    return [f]


def _goal_at_points(state: KripkeModel, goal: Formula, actions: Mapping) -> list[bool]:
    mask = evaluate(state, goal, actions)
    return [bool(x) for x in mask[state._designated]]


def _heuristic(
    heuristic: str | Heuristic | None, search: str, goal: Formula, actions: Mapping
) -> Heuristic | None:
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


def _check_bound(value: object, name: str, minimum: int) -> None:
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InvalidArgumentError(
            f"{name} must be an integer >= {minimum} or None, got {value!r}",
            hint=f"e.g. {name}=10",
        )


def _check_problem(initial: object, actions: object) -> None:
    if not isinstance(initial, KripkeModel):
        raise InvalidArgumentError(
            f"the initial state must be a KripkeModel, got {type(initial).__name__}",
            hint="build one with KripkeModel(...) or KripkeModel.from_observables(...)",
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
