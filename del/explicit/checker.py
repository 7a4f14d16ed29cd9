"""Model checking: the truth set of a formula in a Kripke model, as a boolean mask.

Semantics, at a world ``w`` of a model ``M``:

- ``K[a] f``: ``f`` holds at every world of a's *knowledge* relation from ``w``;
  ``B[a] f``: the same over a's *belief* relation (the two coincide unless the model has
  a separate knowledge relation); ``Kw[a] f`` is ``K[a] f | K[a] ~f``;
- ``E[G] f``: every agent of ``G`` knows ``f``; ``C[G] f``: ``f`` holds at every world
  reachable in one or more steps by the union of the knowledge relations of ``G``;
  ``D[G] f``: ``f`` holds at every world related to ``w`` by *all* of them (intersection);
  ``EB[G] f`` and ``CB[G] f``: as ``E`` and ``C`` over the *belief* relations (belief need
  not be reflexive, so ``CB`` uses the general reachability unless every relation of the
  group is an equivalence);
- ``[!f] g``: if ``f`` holds, ``g`` holds in the submodel of the ``f``-worlds;
  ``<!f> g``: ``f`` holds and ``g`` holds in that submodel;
- ``[ACT] g``: ``g`` holds at ``(w, e)`` in the product update with the named action, for
  every designated event ``e`` whose precondition holds at ``w``.

Evaluation runs on an explicit stack, so formulas of any depth or width are fine. Small
truth sets are memoised per model and subformula (planning states, puzzles); large ones
only for the formula asked about and for announcements, every other intermediate result
being freed once its parent has used it. Models from observables are evaluated on bitsets
(:mod:`~epistemica.del_.explicit.cube`), public-announcement actions included. Nothing larger than
the memory budget (:mod:`~epistemica.del_.budget`) is allocated without first raising
:class:`~epistemica.del_.budget.MemoryBudgetError`. Relations that are equivalences are
evaluated through their partition; any other relation through its arrows.

An atom outside the model's vocabulary (its declared atoms, by default those its valuation
names) is refused with "unknown atom", as on the symbolic backend; a declared atom that no
world makes true is false everywhere.
"""

from __future__ import annotations

import functools
import gc
from collections.abc import Generator, Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from epistemica.del_ import budget
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._model import ExplicitModel, column_of
from epistemica.del_.explicit._product import product_with_provenance
from epistemica.del_.explicit._sets import BITS, CONNECTIVES, MASKS
from epistemica.del_.explicit.propositional import (
    propositional_mask,
    propositional_truth,
    short_text,
)
from epistemica.del_.language.formula import And, Atom, Bottom, Formula, Iff, Implies, Not, Or, Top
from epistemica.del_.language.modalities import (
    After,
    Announce,
    AnnounceDiamond,
    Believe,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
)
from epistemica.del_.language.parser import as_formula

if TYPE_CHECKING:
    from epistemica.del_.explicit.action import ActionModel

# propositional_mask and propositional_truth (from propositional) are re-exported here.
__all__ = [
    "designated_truth",
    "evaluate",
    "evaluate_bits",
    "propositional_mask",
    "propositional_truth",
]

_CONNECTIVES = CONNECTIVES
_BINARY = (And, Or, Implies, Iff)
_LEAVES = frozenset((Atom, Top, Bottom))
# Results this small are memoised for every subformula (planning states, small puzzles);
# larger ones only for the formula asked about and for announcements, so a finished
# subformula's truth set is freed as soon as its parent has used it.
_MEMO_ALL_BYTES = 1 << 16


def evaluate(
    model: ExplicitModel,
    formula: Formula | str,
    actions: Mapping[str, ActionModel] | None = None,
    *,
    memory_budget: int | None = None,
) -> np.ndarray:
    """The truth set of ``formula`` in ``model`` as a read-only boolean mask.

    The evaluation uses an explicit stack, so formulas of any depth are fine; nothing is
    allocated beyond ``memory_budget`` bytes (default
    :data:`~epistemica.del_.budget.DEFAULT_MEMORY_BUDGET`) without first raising
    :class:`~epistemica.del_.budget.MemoryBudgetError`.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": [], "b": ["p"]}, designated=["p"])
    >>> evaluate(m, "Kw[b] p & ~Kw[a] p").tolist()
    [True, True]
    """
    if memory_budget is None:
        return _Run(actions).value(model, as_formula(formula), bits=False)
    with budget.budget_scope(memory_budget):
        return _Run(actions).value(model, as_formula(formula), bits=False)


def evaluate_bits(
    model: ExplicitModel,
    formula: Formula | str,
    actions: Mapping[str, ActionModel] | None = None,
) -> np.ndarray:
    """The truth set of ``formula`` in a model from observables, as a bitset over codes."""
    return _Run(actions).value(model, as_formula(formula), bits=True)


def designated_truth(
    model: ExplicitModel, formula: Formula, actions: Mapping[str, ActionModel] | None = None
) -> np.ndarray:
    """The truth of ``formula`` at each designated world (in the cheaper representation)."""
    run = _Run(actions)
    if run.natural_bits(model, formula):
        bits = run.value(model, formula, bits=True)
        return model.cube.test(bits, model.designated_codes)
    return run.value(model, formula, bits=False)[model.designated_positions]


# -- formula analysis -------------------------------------------------------------------

# Per node (by identity, so that deep formulas are never compared or hashed
# recursively): (registers needed, mentions a named action, height).
_ANALYSES: dict[int, tuple[Formula, dict[int, tuple[int, bool, int]]]] = {}
_ANALYSED_NODES = 1 << 20
# Nodes in _ANALYSES' tables, counted as they are added: summing the tables on every new
# root cost a pass over every cached root (quadratic over a process's formulas).
_analysed_count = 0
# Taller subformulas are memoised by identity: comparing two equal but distinct trees
# would recurse once per level.
_STRUCTURAL_HEIGHT = 200


def _analyse(root: Formula) -> dict[int, tuple[int, bool, int]]:
    """Post-order pass over ``root``: Sethi-Ullman numbers and whether actions occur.

    Evaluating the child that needs more live results first keeps at most about
    ``log2(size)`` truth sets alive at once, whatever the shape of the tree. The pass
    also hashes every node bottom-up, so that hashing the root later (as a memo key)
    reads cached hashes instead of recursing.
    """
    found = _ANALYSES.get(id(root))
    if found is not None and found[0] is root:
        return found[1]
    table: dict[int, tuple[int, bool, int]] = {}
    stack: list[tuple[Formula, bool]] = [(root, False)]
    while stack:
        node, expanded = stack.pop()
        if id(node) in table:
            continue
        children = node.children()
        if not expanded and children:
            stack.append((node, True))
            stack.extend((c, False) for c in children if id(c) not in table)
            continue
        hash(node)
        info = [table[id(c)] for c in children]
        action = isinstance(node, After) or any(i[1] for i in info)
        if not info:
            need = 1
        elif isinstance(node, (Announce, AnnounceDiamond)):
            need = max(info[0][0], info[1][0] + 1)
        elif len(info) == 2:
            left, right = info[0][0], info[1][0]
            need = left + 1 if left == right else max(left, right)
        else:
            need = info[0][0] + isinstance(node, After)
        height = 1 + max((i[2] for i in info), default=0)
        table[id(node)] = (need, action, height)
    global _analysed_count
    if _analysed_count + len(table) > _ANALYSED_NODES:
        _ANALYSES.clear()
        _analysed_count = 0
    _analysed_count += len(table)  # a new root: a cached one returned above
    _ANALYSES[id(root)] = (root, table)
    return table


# -- the driver ---------------------------------------------------------------------------

Node = Generator[tuple, np.ndarray, np.ndarray]


class _Run:
    """One evaluation: the named actions in force, and an explicit stack of nodes.

    Every node is a generator that yields requests ``(model, subformula, bits, keep)``
    and receives their truth sets (as bitsets if ``bits``, else as masks); ``keep`` asks
    for the result to stay in the model's memo. No Python recursion is involved.
    """

    def __init__(self, actions: Mapping[str, ActionModel] | None) -> None:
        self.actions = dict(actions) if actions else {}
        self._key: frozenset | None = None
        self.info: dict[int, tuple[int, bool, int]] = {}

    def value(self, model: ExplicitModel, root: Formula, bits: bool) -> np.ndarray:
        if not gc.isenabled():
            return self._value(model, root, bits)
        # A large formula means one suspended generator per pending node: the cyclic
        # garbage collector would rescan them all, over and over (quadratic time).
        # Evaluation makes no reference cycles, so it can wait until the end.
        gc.disable()
        try:
            return self._value(model, root, bits)
        finally:
            gc.enable()

    def _value(self, model: ExplicitModel, root: Formula, bits: bool) -> np.ndarray:
        self.info = _analyse(root)
        need = self.info[id(root)][0]
        cube = model.cube
        if cube is not None and not cube.sparse():
            unit = cube.space.nbytes
        else:
            unit = model.n_worlds
        budget.require(
            (need + 2) * unit, lambda: f"checking {short_text(root)} on {model.n_worlds:,} worlds"
        )
        return self._drive(model, root, bits)

    def _drive(self, model: ExplicitModel, root: Formula, bits: bool) -> np.ndarray:
        stack: list[tuple[Node, ExplicitModel, Any, Formula | None, bool]] = []
        result = self._open(stack, model, root, bits, True)
        while stack:
            node, where, key, owner, keep = stack[-1]
            try:
                request = node.send(result)
            except StopIteration as stop:
                stack.pop()
                result = stop.value
                if key is not None:
                    result.setflags(write=False)
                    if keep or result.nbytes <= _MEMO_ALL_BYTES:
                        # an identity key keeps its formula, so its id cannot be reused
                        where.memo[key] = result if owner is None else (owner, result)
                continue
            result = self._open(stack, *request)
        return result

    @property
    def key(self) -> frozenset:
        """The memo key of the actions in force (for formulas that name one)."""
        if self._key is None:
            self._key = frozenset((name, id(a)) for name, a in self.actions.items())
        return self._key

    def natural_bits(self, model: ExplicitModel, f: Formula) -> bool:
        """Whether ``f`` is best evaluated on ``model`` as a bitset."""
        cube = model.cube
        if cube is None or cube.sparse():
            return False
        return type(f) is not After or _public_announcement(self._action(f), model) is not None

    def _open(self, stack: list, model: ExplicitModel, f: Formula, bits: bool, keep: bool) -> Any:
        """The memoised result, or ``None`` after pushing the node that computes it."""
        if id(f) not in self.info:  # an action's precondition: not part of the formula
            self.info = {**self.info, **_analyse(f)}
        natural = self.natural_bits(model, f)
        if natural != bits:
            stack.append((_convert(model, f, natural, keep), model, None, None, False))
            return None
        if type(f) in _LEAVES:  # half of most formulas: no generator, no memo
            return _leaf(model, f, bits)
        _, action, height = self.info[id(f)]
        key = ("id", id(f)) if height > _STRUCTURAL_HEIGHT else f
        key = (key, self.key) if action else key
        if bits:
            key = ("bits", key)
        found = model.memo.get(key)
        if found is not None and (height <= _STRUCTURAL_HEIGHT or found[0] is f):
            return found if height <= _STRUCTURAL_HEIGHT else found[1]
        node = self._node(model, f, self._first(f), bits)
        stack.append((node, model, key, f if height > _STRUCTURAL_HEIGHT else None, keep))
        return None

    def _first(self, f: Formula) -> Formula | None:
        if isinstance(f, _BINARY) and self.info[id(f.right)][0] > self.info[id(f.left)][0]:
            return f.right
        return None

    def _action(self, f: After) -> ActionModel:
        action = self.actions.get(f.action)
        if action is None:
            known = ", ".join(sorted(self.actions)) or "none"
            raise InvalidArgumentError(
                f"unknown action {f.action!r} in {short_text(f)}",
                hint=f"pass it in `actions`; known actions: {known}",
            )
        return action

    def _node(self, model: ExplicitModel, f: Formula, first: Formula | None, bits: bool) -> Node:
        """Evaluate one node (not a leaf) of ``f``, yielding requests for its subresults.

        Each formula type is interpreted here once; the operations on truth sets come
        from the representation, bitsets or masks (:mod:`._sets`). ``first`` names the
        child of a binary node to evaluate first (the one that needs more live results).
        """
        kind = type(f)
        rep = BITS if bits else MASKS
        if kind is Not:
            return ~(yield model, f.operand, bits, False)
        if kind in _CONNECTIVES:
            if first is f.right:
                right = yield model, f.right, bits, False
                left = yield model, f.left, bits, False
            else:
                left = yield model, f.left, bits, False
                right = yield model, f.right, bits, False
            return _CONNECTIVES[kind](left, right)
        if kind is Know or kind is Believe or kind is KnowWhether:
            which = "belief" if kind is Believe else "knowledge"
            (relation,) = rep.relations(model, (f.agent,), which)
            inner = yield model, f.operand, bits, False
            if kind is KnowWhether:
                return rep.know_whether(model, relation, inner)
            return rep.box(model, relation, inner)
        if kind is Everybody or kind is EverybodyBelieves:
            which = "knowledge" if kind is Everybody else "belief"
            relations = rep.relations(model, f.group, which)
            return rep.everybody(model, relations, (yield model, f.operand, bits, False))
        if kind is Common or kind is CommonBelief:
            which = "knowledge" if kind is Common else "belief"
            relations = rep.relations(model, f.group, which)
            inner = yield model, f.operand, bits, False
            return rep.common(model, f.group, which, relations, inner)
        if kind is Distributed:
            relations = rep.relations(model, f.group, "knowledge")
            inner = yield model, f.operand, bits, False
            return rep.distributed(model, f.group, relations, inner)
        if kind is Announce or kind is AnnounceDiamond:
            box = kind is Announce
            return (yield from self._announce(model, f.announcement, f.operand, box, bits))
        if kind is After and bits:  # a public announcement (see natural_bits): [!pre] g
            pre = _public_announcement(self._action(f), model)
            return (yield from self._announce(model, pre, f.operand, True, bits))
        if kind is After:
            return (yield from self._after(model, f))
        raise InvalidArgumentError(
            f"cannot evaluate {kind.__name__}",
            hint="B[a | f], Sb[a], [^^f] and [^f] need a plausibility model: a spec with a "
            "'plausibility' line, or epistemica.del_.explicit.plausibility.PlausibilityModel",
        )

    def _announce(
        self, model: ExplicitModel, announcement: Formula, operand: Formula, box: bool, bits: bool
    ) -> Node:
        """``[!announcement] operand`` (``box``) or ``<!announcement> operand``."""
        rep = BITS if bits else MASKS
        announced = yield model, announcement, bits, True
        sub = rep.submodel(model, announcement, announced)
        inside = None if sub is None else (yield sub, operand, bits, False)
        return rep.after(model, announced, inside, box)

    def _after(self, model: ExplicitModel, f: After) -> Node:
        action = self._action(f)
        key = ("after", id(action))
        cached = model.derived.get(key)
        if cached is None or cached[0] is not action:
            model.require_arrays()  # the product lists worlds: refuse before anything
            pres = []
            for pre in action.pre:
                pres.append((yield model, pre, False, True))
            _require_product(model, action, sum(int(p.sum()) for p in pres))
            # a precondition may itself hold [ACT] (a nested announcement): same actions
            truth = functools.partial(evaluate, model, actions=self.actions)
            product, parent, event = product_with_provenance(model, action, truth)
            cached = model.derived[key] = (action, product, parent, event)
        _, product, parent, event = cached
        result = np.ones(model.n_worlds, dtype=bool)
        if product.n_worlds:
            designated_event = np.zeros(len(action.events), dtype=bool)
            designated_event[action.designated_positions] = True
            inner = yield product, f.operand, False, False
            violated = ~inner & designated_event[event]
            result[parent[violated]] = False
        return result


def _leaf(model: ExplicitModel, f: Atom | Top | Bottom, bits: bool) -> np.ndarray:
    """The read-only truth set of an atom, ``true`` or ``false``."""
    column = model.atom_column(f.key) if type(f) is Atom else None
    if column is None and type(f) is Atom:
        column_of(dict.fromkeys(model.atoms, 0), f.key, "the formula")  # raises: unknown
    if column is not None:  # a bitset built once per space, or a column of the valuation
        found = model.cube.atom(column) if bits else model.valuation[:, column]
    elif bits:  # true or false
        found = model.cube.ones() if type(f) is Top else model.cube.zeros()
    else:
        found = np.full(model.n_worlds, type(f) is Top, dtype=bool)
    found.setflags(write=False)
    return found


def _convert(model: ExplicitModel, f: Formula, natural_bits: bool, keep: bool) -> Node:
    """The truth set of ``f`` in its natural representation, converted to the other."""
    found = yield model, f, natural_bits, keep
    if natural_bits:
        return model.cube.to_mask(found)
    return model.cube.from_mask(found)


def _public_announcement(action: ActionModel, model: ExplicitModel) -> Formula | None:
    """The precondition of ``action`` if it is a public announcement for ``model``.

    One event, no postcondition, and every agent relates it only to itself (in belief and
    knowledge): the product update is then the submodel of the precondition.
    """
    if len(action.events) != 1 or action.post[0] or set(action.agents) != set(model.agents):
        return None
    loop = ((0, 0, None),)
    for agent in action.agents:
        if action.edges[agent] != loop or action.knowledge_edges[agent] != loop:
            return None
    return action.pre[0]


def _require_product(model: ExplicitModel, action: ActionModel, n_worlds: int) -> None:
    """Refuse a product update whose arrays (and the model's own) would not fit."""
    n_atoms = len(model.atoms) + sum(len(p) for p in action.post)
    per_world = n_atoms + 16 + 2 * 8 * len(model.agents)
    needed = model.arrays_bytes() + n_worlds * per_world
    budget.require(needed, f"the product update with {n_worlds:,} worlds")
