"""Action models (event models) with pre- and postconditions, and product update.

An :class:`ActionModel` describes what happens and who sees it: events with a
precondition (when it can happen) and a postcondition (``atom := formula``, factual
change), and per agent an accessibility relation between events (which events the agent
cannot tell apart). An edge may carry a condition, evaluated at the world where the action
happens: the edge is present only where the condition holds, so observability can depend
on the state ("agents looking at the box see it opened").

The product update ``M ⊗ A`` has the worlds ``(w, e)`` with ``w ⊨ pre(e)``, valuation
changed by ``post(e)`` evaluated at ``w`` before the change, and
``(w, e) R_a (v, f)`` iff ``w R_a v``, ``e R_a f`` and the edge's condition holds at ``w``.

Examples
--------
A coin lands heads; ``b`` is shown the coin, ``a`` only sees that ``b`` looked:

>>> from epistemica.del_.explicit.kripke import KripkeModel
>>> m = KripkeModel.from_observables(["heads"], {"a": [], "b": []}, designated=["heads"])
>>> after = m.update(semi_private_sensing("heads", ["b"], ["a", "b"]))
>>> after.holds("Kw[b] heads & ~Kw[a] heads & K[a] Kw[b] heads")
True
"""

from __future__ import annotations

import functools
from collections.abc import Hashable, Iterable, Mapping, Sequence

import numpy as np

from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.explicit import checker
from epistemica.del_.explicit.kripke import KripkeModel
from epistemica.del_.explicit.relations import (
    DENSE_LIMIT,
    DenseArrows,
    Partition,
    Relation,
    arrows_from_edges,
    as_compact,
)
from epistemica.del_.language.formula import Formula, Top, canonical_atom

__all__ = [
    "ActionModel",
    "is_applicable",
    "private_announcement",
    "product_update",
    "product_with_provenance",
    "public_announcement",
    "public_assignment",
    "semi_private_sensing",
]

Event = Hashable
# Above this many edges, a product relation is kept as arrows rather than tested for being
# an equivalence (the test multiplies sparse matrices).
_EQUIVALENCE_TEST_LIMIT = 2_000_000


class ActionModel:
    """An event model with pre- and postconditions and optionally conditioned edges.

    Parameters
    ----------
    events : sequence of hashable
        Distinct event names.
    pre : mapping
        Event -> precondition (formula or text); missing events have ``true``.
    post : mapping
        Event -> mapping atom -> formula: the atom's new value is the formula's value
        *before* the update. Missing events change nothing.
    relations : mapping
        Agent -> iterable of ``(e, f)`` or ``(e, f, condition)`` edges: the agent's belief
        relation over events; a conditioned edge exists at worlds where the condition holds.
    designated : event or iterable of events
        The event(s) that actually happen (the one executable at the actual world is the
        actual one).
    knowledge : mapping, optional
        Agent -> edges: a separate knowledge relation (same format); defaults to
        ``relations``.

    Examples
    --------
    A private announcement of ``p`` to ``a``; ``b`` believes nothing happened:

    >>> act = ActionModel(
    ...     events=["e", "skip"], pre={"e": "p"}, post={},
    ...     relations={"a": [("e", "e"), ("skip", "skip")],
    ...                "b": [("e", "skip"), ("skip", "skip")]},
    ...     designated="e")
    >>> act.events
    ('e', 'skip')
    """

    def __init__(
        self,
        events: Sequence[Event],
        pre: Mapping[Event, Formula | str],
        post: Mapping[Event, Mapping[str, Formula | str]],
        relations: Mapping[str, Iterable[tuple]],
        designated: Event | Iterable[Event],
        knowledge: Mapping[str, Iterable[tuple]] | None = None,
    ) -> None:
        self.events = tuple(events)
        index = {e: i for i, e in enumerate(self.events)}
        if len(index) != len(self.events):
            raise ModelError("event names must be distinct", hint="rename the repeated event")
        for where, table in (("pre", pre), ("post", post)):
            for e in table:
                _event_index(index, e, where)
        self.pre = tuple(checker.as_formula(pre.get(e, Top())) for e in self.events)
        self.post = tuple(
            {canonical_atom(a): checker.as_formula(v) for a, v in post.get(e, {}).items()}
            for e in self.events
        )
        self.agents = tuple(str(a) for a in relations)
        self._edges = {str(a): _edges(index, edges, a) for a, edges in relations.items()}
        self._know_edges = dict(self._edges)
        for a, edges in (knowledge or {}).items():
            if str(a) not in self._edges:
                raise ModelError(
                    f"knowledge edges given for unknown agent {a!r}",
                    hint=f"agents with a relation: {', '.join(self.agents)}",
                )
            known = _edges(index, edges, a)
            # Equal edges share one object, so the product computes the relation once.
            self._know_edges[str(a)] = (
                self._edges[str(a)] if known == self._edges[str(a)] else known
            )
        try:
            points = [index[designated]]
        except (KeyError, TypeError):
            points = [_event_index(index, e, "designated") for e in designated]
        if not points:
            raise ModelError("an action model needs at least one designated event")
        self._designated = np.unique(np.array(points, dtype=np.int64))

    @property
    def designated(self) -> tuple:
        """The designated events' names."""
        return tuple(self.events[i] for i in self._designated)

    def __repr__(self) -> str:
        return f"<ActionModel: events {list(self.events)}, designated {list(self.designated)}>"


def _event_index(index: Mapping[Event, int], e: Event, where: str) -> int:
    try:
        return index[e]
    except (KeyError, TypeError):
        raise ModelError(
            f"unknown event {e!r} in {where}", hint=f"events: {', '.join(map(str, index))}"
        ) from None


def _edges(index: Mapping[Event, int], edges: Iterable[tuple], agent: str) -> tuple:
    out = []
    for edge in edges:
        if len(edge) not in (2, 3):
            raise ModelError(
                f"edge {edge!r} of agent {agent!r} must be (e, f) or (e, f, condition)"
            )
        e, f = (_event_index(index, x, f"relation of {agent}") for x in edge[:2])
        condition = checker.as_formula(edge[2]) if len(edge) == 3 else None
        out.append((e, f, None if isinstance(condition, Top) else condition))
    return tuple(out)


def _check_agents(model: KripkeModel, action: ActionModel) -> None:
    missing = set(model.agents) - set(action.agents)
    extra = set(action.agents) - set(model.agents)
    if missing or extra:
        raise ModelError(
            "the action model and the Kripke model must have the same agents",
            hint=f"missing in the action: {sorted(missing)}; unknown to the model: {sorted(extra)}",
        )


def product_with_provenance(
    model: KripkeModel, action: ActionModel, *, beliefs_only: bool = False
) -> tuple[KripkeModel, np.ndarray, np.ndarray]:
    """The full product ``model ⊗ action`` and, per product world, its world and event.

    Unlike :func:`product_update`, the product may have no designated world. With
    ``beliefs_only``, the separate knowledge relations are not computed (``K`` then reads
    the belief relation): for callers whose formulas never mention knowledge.
    """
    _check_agents(model, action)
    blocks = [np.flatnonzero(checker.evaluate(model, pre)) for pre in action.pre]
    parent = np.concatenate(blocks) if blocks else np.zeros(0, dtype=np.int64)
    event = np.repeat(np.arange(len(blocks)), [len(b) for b in blocks])
    offsets = np.concatenate([[0], np.cumsum([len(b) for b in blocks])])

    atoms = list(model.atoms)
    for changes in action.post:
        atoms.extend(a for a in changes if a not in atoms)
    val = np.zeros((len(parent), len(atoms)), dtype=bool)
    val[:, : len(model.atoms)] = model._val[parent]
    column = {a: j for j, a in enumerate(atoms)}
    for j, changes in enumerate(action.post):
        rows = slice(offsets[j], offsets[j + 1])
        for atom, value in changes.items():
            val[rows, column[atom]] = checker.evaluate(model, value)[blocks[j]]

    rel: dict[str, Relation] = {}
    know: dict[str, Relation] = {}
    for agent in model.agents:
        rel[agent] = _product_relation(model, model._rel[agent], action._edges[agent], blocks)
        same_model = model._know[agent] is model._rel[agent]
        same_action = action._know_edges[agent] is action._edges[agent]
        if beliefs_only or (same_model and same_action):
            know[agent] = rel[agent]
        else:
            edges = action._know_edges[agent]
            know[agent] = _product_relation(model, model._know[agent], edges, blocks)

    is_point = np.zeros(model.n_worlds, dtype=bool)
    is_point[model._designated] = True
    is_designated_event = np.zeros(len(action.events), dtype=bool)
    is_designated_event[action._designated] = True
    designated = np.flatnonzero(is_point[parent] & is_designated_event[event])

    source, events = model._names, action.events

    def names() -> tuple:
        worlds = source() if callable(source) else source
        if worlds is None:
            return tuple((int(w), events[e]) for w, e in zip(parent, event, strict=True))
        return tuple((worlds[w], events[e]) for w, e in zip(parent, event, strict=True))

    product = KripkeModel._from_arrays(
        names, tuple(atoms), val, model.agents, rel, know, designated
    )
    return product, parent, event


def _product_relation(
    model: KripkeModel, relation: Relation, edges: tuple, blocks: list[np.ndarray]
) -> Relation:
    n = sum(len(b) for b in blocks)
    if isinstance(relation, Partition) and all(c is None for _, _, c in edges):
        classes = _event_classes(edges, len(blocks))
        if classes is not None:
            return _paired_partition(relation, classes, blocks)
    offsets = np.concatenate([[0], np.cumsum([len(b) for b in blocks])])
    if n <= DENSE_LIMIT:
        return as_compact(_dense_product(model, relation, edges, blocks, offsets, n))
    matrix = relation.to_csr()
    rows, cols = [], []
    for e, f, condition in edges:
        if not len(blocks[e]) or not len(blocks[f]):
            continue
        sub = matrix[blocks[e]][:, blocks[f]].tocoo()
        keep = np.ones(sub.nnz, dtype=bool)
        if condition is not None:
            keep = checker.evaluate(model, condition)[blocks[e]][sub.row]
        rows.append(sub.row[keep] + offsets[e])
        cols.append(sub.col[keep] + offsets[f])
    row = np.concatenate(rows) if rows else np.zeros(0, dtype=np.intp)
    col = np.concatenate(cols) if cols else np.zeros(0, dtype=np.intp)
    product = arrows_from_edges(n, row, col)
    if len(row) <= _EQUIVALENCE_TEST_LIMIT:
        return as_compact(product)
    return product


def _dense_product(
    model: KripkeModel,
    relation: Relation,
    edges: tuple,
    blocks: list[np.ndarray],
    offsets: np.ndarray,
    n: int,
) -> DenseArrows:
    """The product relation as a boolean matrix, one block per edge of the action."""
    matrix = relation.to_dense()
    out = np.zeros((n, n), dtype=bool)
    for e, f, condition in edges:
        if not len(blocks[e]) or not len(blocks[f]):
            continue
        block = matrix[np.ix_(blocks[e], blocks[f])]
        if condition is not None:
            block &= checker.evaluate(model, condition)[blocks[e]][:, None]
        out[offsets[e] : offsets[e + 1], offsets[f] : offsets[f + 1]] |= block
    return DenseArrows(out)


def _paired_partition(
    relation: Partition, classes: np.ndarray, blocks: list[np.ndarray]
) -> Partition:
    """Equivalence times equivalence: pair each world's class with its event's class."""
    width = int(classes.max()) + 1
    parts = [relation.labels[b] * width + classes[j] for j, b in enumerate(blocks)]
    labels = np.concatenate(parts).astype(np.int64)
    if len(labels) and labels.max() >= 4 * len(labels) + 64:
        labels = np.unique(labels, return_inverse=True)[1].reshape(-1)  # keep labels dense
    return Partition(labels)


@functools.lru_cache(maxsize=4096)
def _event_classes(edges: tuple, n_events: int) -> np.ndarray | None:
    """Class label per event if the unconditioned edges form an equivalence, else None.

    Cached: action models are immutable, so their edge tuples recur across updates.
    """
    if not edges:
        return None
    matrix = np.zeros((n_events, n_events), dtype=bool)
    matrix[[x for x, _, _ in edges], [y for _, y, _ in edges]] = True
    relation = as_compact(DenseArrows(matrix))
    return relation.labels if isinstance(relation, Partition) else None


def is_applicable(model: KripkeModel, action: ActionModel) -> bool:
    """Whether a designated event's precondition holds at a designated world.

    Examples
    --------
    >>> from epistemica.del_.explicit.kripke import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=[])
    >>> is_applicable(m, public_announcement("p", ["a"]))
    False
    """
    for i in action._designated:
        if checker.evaluate(model, action.pre[i])[model._designated].any():
            return True
    return False


def product_update(
    model: KripkeModel, action: ActionModel, *, beliefs_only: bool = False
) -> KripkeModel:
    """The product update ``model ⊗ action``, pointed at the executable designated pairs.

    ``beliefs_only`` skips the separate knowledge relations (see
    :func:`product_with_provenance`).

    Raises
    ------
    InvalidArgumentError
        If no designated event is executable at a designated world.

    Examples
    --------
    >>> from epistemica.del_.explicit.kripke import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
    >>> m.update(public_announcement("p", ["a"])).holds("K[a] p")
    True
    """
    if not is_applicable(model, action):
        raise InvalidArgumentError(
            "the action is not executable: no designated event's precondition holds at a "
            "designated world",
            hint="check model.is_applicable(action) before updating",
        )
    return product_with_provenance(model, action, beliefs_only=beliefs_only)[0]


def _reflexive(agents: Iterable[str], events: Sequence[Event]) -> dict[str, list[tuple]]:
    return {str(a): [(e, e) for e in events] for a in agents}


def public_announcement(formula: Formula | str, agents: Iterable[str]) -> ActionModel:
    """Everybody learns that ``formula`` is true (one event, precondition ``formula``).

    Examples
    --------
    >>> public_announcement("p", ["a", "b"]).pre[0]
    Atom(name='p', args=())
    """
    return ActionModel(
        ["announce"], {"announce": formula}, {}, _reflexive(agents, ["announce"]), "announce"
    )


def private_announcement(
    formula: Formula | str, observers: Iterable[str], agents: Iterable[str]
) -> ActionModel:
    """The observers learn ``formula``; the others believe nothing happened.

    The others' beliefs point to the ``skip`` event; their knowledge relates both events,
    so knowledge stays truthful while beliefs may become false.
    """
    observers = {str(o) for o in observers}
    agents = [str(a) for a in agents]
    _check_subset(observers, agents)
    events = ["announce", "skip"]
    relations, knowledge = {}, {}
    for a in agents:
        if a in observers:
            relations[a] = knowledge[a] = [("announce", "announce"), ("skip", "skip")]
        else:
            relations[a] = [("announce", "skip"), ("skip", "skip")]
            knowledge[a] = [(e, f) for e in events for f in events]
    return ActionModel(events, {"announce": formula}, {}, relations, "announce", knowledge)


def semi_private_sensing(
    formula: Formula | str, observers: Iterable[str], agents: Iterable[str]
) -> ActionModel:
    """The observers learn whether ``formula``; the others learn only that they did."""
    observers = {str(o) for o in observers}
    agents = [str(a) for a in agents]
    _check_subset(observers, agents)
    tree = checker.as_formula(formula)
    events = ["yes", "no"]
    relations = {
        a: [("yes", "yes"), ("no", "no")]
        if a in observers
        else [(e, f) for e in events for f in events]
        for a in agents
    }
    return ActionModel(events, {"yes": tree, "no": ~tree}, {}, relations, events)


def public_assignment(
    assignments: Mapping[str, Formula | str],
    agents: Iterable[str],
    pre: Formula | str = "true",
) -> ActionModel:
    """Everybody sees the atoms set to the values of the formulas (evaluated before)."""
    return ActionModel(
        ["assign"],
        {"assign": pre},
        {"assign": dict(assignments)},
        _reflexive(agents, ["assign"]),
        "assign",
    )


def _check_subset(observers: set[str], agents: list[str]) -> None:
    unknown = observers - set(agents)
    if unknown:
        raise ModelError(
            f"observers {sorted(unknown)} are not among the agents",
            hint=f"agents: {', '.join(agents)}",
        )
