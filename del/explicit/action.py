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

>>> from epistemica.del_ import KripkeModel
>>> m = KripkeModel.from_observables(["heads"], {"a": [], "b": []}, designated=["heads"])
>>> after = m.update(semi_private_sensing("heads", ["b"], ["a", "b"]))
>>> after.holds("Kw[b] heads & ~Kw[a] heads & K[a] Kw[b] heads")
True
"""

from __future__ import annotations

import functools
from collections.abc import Hashable, Iterable, Mapping, Sequence
from types import MappingProxyType

import numpy as np

from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.explicit import _product, checker
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit.row_truth import RowTruth
from epistemica.del_.language.formula import Formula, Top, canonical_atom
from epistemica.del_.language.parser import as_formula

__all__ = [
    "ActionModel",
    "applicable_in_some",
    "private_announcement",
    "product_update",
    "product_with_provenance",
    "public_announcement",
    "public_assignment",
    "semi_private_sensing",
]

Event = Hashable


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
        self.pre = tuple(as_formula(pre.get(e, Top())) for e in self.events)
        self.post = tuple(
            {canonical_atom(a): as_formula(v) for a, v in post.get(e, {}).items()}
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
        # sorted(set()), not np.unique: that loads numpy.ma, which `check` need not pay for
        self._designated = np.array(sorted(set(points)), dtype=np.int64)
        self._designated.setflags(write=False)  # shared through designated_positions

    @property
    def designated(self) -> tuple:
        """The designated events' names."""
        return tuple(self.events[i] for i in self._designated)

    @property
    def designated_positions(self) -> np.ndarray:
        """The positions in :attr:`events` of the designated events (a read-only array)."""
        return self._designated

    @property
    def edges(self) -> Mapping[str, tuple[tuple[int, int, Formula | None], ...]]:
        """Agent -> its belief edges ``(e, f, condition)`` between event positions
        (``condition`` is ``None`` for an unconditioned edge)."""
        return MappingProxyType(self._edges)

    @property
    def knowledge_edges(self) -> Mapping[str, tuple[tuple[int, int, Formula | None], ...]]:
        """Agent -> its knowledge edges; the same tuple as :attr:`edges` unless separate."""
        return MappingProxyType(self._know_edges)

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
        condition = as_formula(edge[2]) if len(edge) == 3 else None
        out.append((e, f, None if isinstance(condition, Top) else condition))
    return tuple(out)


def applicable_in_some(
    model: ExplicitModel, action: ActionModel, rows: RowTruth | None = None
) -> bool:
    """Whether a designated event's precondition holds at *some* designated world: the
    product update then has a designated world.

    A plan step asks more, executability at *every* designated world
    (:func:`~epistemica.del_.planning.planner.applicable_in_all`).

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []})   # p and ~p designated
    >>> applicable_in_some(m, public_announcement("p", ["a"]))
    True
    """
    truth = checker.evaluate if rows is None else rows
    points = model.designated_positions
    for i in action.designated_positions:
        if truth(model, action.pre[i])[points].any():
            return True
    return False


def product_with_provenance(
    model: ExplicitModel,
    action: ActionModel,
    *,
    beliefs_only: bool = False,
    rows: RowTruth | None = None,
) -> tuple[ExplicitModel, np.ndarray, np.ndarray]:
    """The full product ``model ⊗ action`` and, per product world, its world and event.

    Unlike :func:`product_update`, the product may have no designated world. With
    ``beliefs_only``, the separate knowledge relations are not computed (``K`` then reads
    the belief relation): for callers whose formulas never mention knowledge. ``rows``
    (a :class:`~epistemica.del_.explicit.row_truth.RowTruth`) evaluates the action's
    propositional conditions from values remembered per valuation row (a search passes
    one for all its updates); the product is the same.
    """
    truth = functools.partial(checker.evaluate if rows is None else rows, model)
    return _product.product_with_provenance(model, action, truth, beliefs_only=beliefs_only)


def product_update(
    model: ExplicitModel,
    action: ActionModel,
    *,
    beliefs_only: bool = False,
    rows: RowTruth | None = None,
) -> ExplicitModel:
    """The product update ``model ⊗ action``, pointed at the executable designated pairs.

    ``beliefs_only`` skips the separate knowledge relations and ``rows`` remembers
    propositional conditions per valuation row (see :func:`product_with_provenance`).

    Raises
    ------
    InvalidArgumentError
        If no designated event is executable at a designated world.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
    >>> m.update(public_announcement("p", ["a"])).holds("K[a] p")
    True
    """
    if not applicable_in_some(model, action, rows):
        raise InvalidArgumentError(
            "the action is not executable: no designated event's precondition holds at a "
            "designated world",
            hint="check model.applicable_in_some(action) before updating",
        )
    return product_with_provenance(model, action, beliefs_only=beliefs_only, rows=rows)[0]


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
    tree = as_formula(formula)
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
