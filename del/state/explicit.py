"""The explicit backend of :class:`~epistemica.del_.state.EpistemicState`: worlds as a table.

A :class:`WorldTable` lists worlds and reads each atom's truth on all of them at once
(``atom_mask``); facts are evaluated by the package's one propositional evaluator
(:func:`~epistemica.del_.explicit.checker.propositional_truth`), and a group's ``K`` and
``B`` sets (see :mod:`~epistemica.del_.state.state`) are boolean masks over the table.
Groups that observed the same keep the same sets, so :func:`belief_masks` computes each
distinct set once.

:func:`group_model` builds the Kripke model of the group semantics: one copy of the worlds
per distinct history a chain can reach, ``K[i]`` and ``B[i]`` leading from a copy to the
``K`` and ``B`` sets of the history extended by ``i``. Any formula is then checked by the
explicit model checker.

Examples
--------
>>> import numpy as np
>>> from epistemica.del_.state import EpistemicState, Observation
>>> table = ValuationTable(["p", "q"], np.array([[0, 0], [0, 1], [1, 0], [1, 1]], bool))
>>> s = EpistemicState(["a", "b"])
>>> _ = s.observe(Observation("tell", full={"a"}, pre="p"))
>>> knowledge_mask(s, ("a",), table).tolist(), knowledge_mask(s, ("a", "b"), table).tolist()
([False, False, True, True], [True, True, True, True])
>>> group_model(s, table).holds("K[a] p & ~K[b] p & K[a] ~K[b] p")
True
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.checker import propositional_truth
from epistemica.del_.explicit.relations import ClassArrows, Partition
from epistemica.del_.language.formula import Formula
from epistemica.del_.models import KripkeModel
from epistemica.del_.state.state import Chain, EpistemicState, soft_in_order

__all__ = [
    "ValuationTable",
    "WorldTable",
    "belief_mask",
    "belief_masks",
    "group_model",
    "knowledge_mask",
]


class WorldTable(Protocol):
    """Worlds as a table: what the explicit backend needs of them."""

    @property
    def n_worlds(self) -> int:
        """How many worlds."""

    @property
    def atoms(self) -> tuple[str, ...]:
        """Every atom a world may make true (the columns of :meth:`valuation`)."""

    def atom_mask(self, atom: str) -> np.ndarray:
        """``(n_worlds,)`` booleans: where ``atom`` (canonical text) is true."""

    def conceivable(self, unaware: frozenset[str]) -> np.ndarray:
        """``(n_worlds,)`` booleans: the worlds where no atom of ``unaware`` is true."""

    def valuation(self) -> np.ndarray:
        """``(n_worlds, len(atoms))`` booleans."""

    def world_names(self) -> tuple[str, ...]:
        """A name per world."""


class ValuationTable:
    """A :class:`WorldTable` given by a valuation matrix.

    Parameters
    ----------
    atoms : sequence of str
    valuation : array_like
        ``(k, len(atoms))`` booleans, one row per world.
    """

    def __init__(self, atoms: Sequence[str], valuation) -> None:
        self._atoms = tuple(str(a) for a in atoms)
        self._val = np.asarray(valuation, dtype=bool)
        if self._val.ndim != 2 or self._val.shape[1] != len(self._atoms):
            raise InvalidArgumentError(
                f"valuation must be (k, {len(self._atoms)}) booleans, got {self._val.shape}",
                hint="one row per world, one column per atom",
            )
        self._column = {a: i for i, a in enumerate(self._atoms)}

    @property
    def n_worlds(self) -> int:
        return self._val.shape[0]

    @property
    def atoms(self) -> tuple[str, ...]:
        return self._atoms

    def atom_mask(self, atom: str) -> np.ndarray:
        if atom not in self._column:
            raise InvalidArgumentError(
                f"unknown atom {atom!r}", hint=f"atoms: {', '.join(self._atoms)}"
            )
        return self._val[:, self._column[atom]]

    def conceivable(self, unaware: frozenset[str]) -> np.ndarray:
        columns = [self._column[a] for a in unaware if a in self._column]
        return ~self._val[:, columns].any(axis=1)

    def valuation(self) -> np.ndarray:
        return self._val

    def world_names(self) -> tuple[str, ...]:
        return tuple(f"w{i}" for i in range(self.n_worlds))


class _Facts:
    """Truth masks of facts on one table, each computed once."""

    def __init__(self, table: WorldTable) -> None:
        self.table = table
        self.masks: dict[Formula, np.ndarray] = {}

    def __call__(self, fact: Formula) -> np.ndarray:
        mask = self.masks.get(fact)
        if mask is None:
            mask = self.masks[fact] = propositional_truth(
                fact, self.table.n_worlds, self.table.atom_mask
            )
        return mask


def _knowledge(state: EpistemicState, chain: Chain, facts: Callable) -> np.ndarray:
    keep = np.ones(facts.table.n_worlds, dtype=bool)
    for fact in state.hard(chain):
        keep &= facts(fact)
    return keep


def _belief(
    state: EpistemicState, chain: Chain, facts: Callable, revision: str = "recency"
) -> np.ndarray:
    keep = _knowledge(state, chain, facts)
    if state.tracked:
        keep &= facts.table.conceivable(state.tracked - state.aware(chain))
    for fact in soft_in_order(state, chain, revision):  # the first consistent one wins
        narrowed = keep & facts(fact)
        if narrowed.any():
            keep = narrowed
    return keep


def knowledge_mask(state: EpistemicState, chain: Chain, table: WorldTable) -> np.ndarray:
    """``K`` of the chain's group: the worlds its hard evidence leaves."""
    return _knowledge(state, chain, _Facts(table))


def belief_mask(
    state: EpistemicState, chain: Chain, table: WorldTable, revision: str = "recency"
) -> np.ndarray:
    """``B`` of the chain's group: the most plausible worlds it conceives of.

    ``revision`` orders the soft facts: ``"recency"`` (the newest consistent fact wins, a
    lexicographic radical upgrade) or ``"primacy"`` (the oldest wins: the ablation).
    """
    return _belief(state, chain, _Facts(table), revision)


def belief_masks(
    state: EpistemicState,
    chains: Sequence[Chain],
    table: WorldTable,
    revision: str = "recency",
) -> list:
    """:func:`belief_mask` of each chain, computed once per distinct signature (chains
    that observed the same share one array).

    Examples
    --------
    >>> from epistemica.del_.state import EpistemicState
    >>> s = EpistemicState(["a", "b", "c"])
    >>> t = ValuationTable(["p"], np.array([[False], [True]]))
    >>> x, y = belief_masks(s, [("a", "b"), ("b", "c")], t)
    >>> x is y  # nothing observed: one computation serves both chains
    True
    """
    facts = _Facts(table)
    memo: dict[tuple, np.ndarray] = {}
    out = []
    for chain in chains:
        key = state.signature(chain)
        if key not in memo:
            memo[key] = _belief(state, chain, facts, revision)
        out.append(memo[key])
    return out


def group_model(
    state: EpistemicState, table: WorldTable, designated: np.ndarray | None = None
) -> KripkeModel:
    """The Kripke model of the group semantics over ``table``.

    One copy of the worlds per history a chain reaches (the observations its group saw):
    the actual history (every observation) and, from a copy of history ``h``, for each
    agent ``i`` the copy of ``h`` restricted to what ``i`` observed. A copy holds the worlds
    of its ``K`` set. ``B[i]`` leads from a copy to the ``B`` set of ``h`` restricted to
    what ``i`` observed (an oblivious agent believes nothing else happened); ``K[i]`` to the
    ``K`` set of every copy that agrees with ``h`` on what ``i`` observed (it cannot rule
    out that what it did not observe happened). Designated: the actual copy's worlds
    (within ``designated``, a mask over the table, when given).
    """
    agents = state.agents
    facts = _Facts(table)
    everyone = tuple(range(len(agents)))
    # A history is named by a group with that history: the empty group sees everything.
    copies: dict[tuple, tuple[int, ...]] = {state.signature(()): ()}
    queue: list[tuple[int, ...]] = [()]
    step: dict[tuple[tuple, int], tuple] = {}
    while queue:
        group = queue.pop()
        for i in everyone:
            bigger = tuple(sorted(set(group) | {i}))
            key = state.signature(bigger)
            step[(state.signature(group), i)] = key
            if key not in copies:
                copies[key] = bigger
                queue.append(bigger)
    keys = list(copies)
    know = {k: _knowledge(state, copies[k], facts) for k in keys}
    believe = {k: _belief(state, copies[k], facts) for k in keys}
    rows = {k: np.flatnonzero(know[k]) for k in keys}
    start, total = {}, 0
    for k in keys:
        start[k] = total
        total += rows[k].size
    copy_of = np.concatenate([np.full(rows[k].size, c) for c, k in enumerate(keys)])
    position = {k: c for c, k in enumerate(keys)}
    belief_rel, knowledge_rel = {}, {}
    for i, agent in enumerate(agents):
        # i's view of each copy's history: the copy of the history restricted to what i
        # observed. K[i] relates the worlds of copies with one view (an equivalence); B[i]
        # leads every world of them to the B set of that view's copy.
        view = np.array([position[step[(k, i)]] for k in keys])[copy_of]
        knowledge_rel[agent] = Partition(view, len(keys))
        believed = [
            np.flatnonzero(believe[k][rows[k]]) + start[k]
            if position[k] in set(view)
            else np.zeros(0, dtype=np.intp)
            for k in keys
        ]
        belief_rel[agent] = ClassArrows(view, believed)
    val = np.concatenate([table.valuation()[rows[k]] for k in keys])
    base = table.world_names()
    names = tuple(f"{base[w]}@{c}" for c, k in enumerate(keys) for w in rows[k].tolist())
    actual = rows[keys[0]]
    chosen = np.ones(actual.size, dtype=bool)
    if designated is not None:
        chosen = np.asarray(designated, dtype=bool)[actual]
    designated_ids = np.flatnonzero(chosen).astype(np.int64)
    if designated_ids.size == 0:
        raise InvalidArgumentError(
            "no designated world satisfies what was observed",
            hint="designate worlds where the observed facts hold",
        )
    return KripkeModel.from_arrays(
        names, tuple(table.atoms), val, agents, belief_rel, knowledge_rel, designated_ids
    )
