"""Plausibility models, explicitly: worlds, information cells and plausibility ranks.

A :class:`PlausibilityModel` stores, per agent, the information cell of every world (a
label; ``K`` quantifies over the cell) and a *rank* (0 is the most plausible): agent ``a``
finds ``v`` at least as plausible as ``w`` when they share a cell and ``rank[v] <= rank[w]``,
a total preorder on every cell (Baltag and Smets 2008; van Benthem 2007). Ranks are kept
dense (``0, 1, 2, ...`` over the whole model), which does not change any cell's order.

The formula language is interpreted by
:func:`~epistemica.del_.language.plausibility_semantics.evaluate_plausibility`, which
calls the operations of this class; the symbolic backend
(:mod:`epistemica.del_.symbolic.plausibility`) implements the same operations on BDDs.

Examples
--------
Alice believes the coin shows tails (``~h``) but has not seen it; a radical upgrade with
``h`` makes her believe heads, a hard announcement of ``h`` makes her know it:

>>> m = PlausibilityModel.from_levels(["h"], {"alice": ["~h", "h"]}, designated=["h"])
>>> m.holds("B[alice] ~h & B[alice | h] h & ~K[alice] h")
True
>>> m.holds("[^^h] (B[alice] h & ~K[alice] h) & [!h] K[alice] h")
True
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from itertools import product
from typing import Any

import numpy as np

from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit.checker import propositional_mask
from epistemica.del_.language.formula import Atom, Formula, atom_name
from epistemica.del_.language.parser import as_formula
from epistemica.del_.language.plausibility_semantics import evaluate_plausibility

__all__ = ["PlausibilityModel", "dense_ranks"]


def dense_ranks(ranks: np.ndarray) -> np.ndarray:
    """``ranks`` renumbered ``0, 1, 2, ...`` in the same order (ties kept).

    Examples
    --------
    >>> dense_ranks(np.array([5, 2, 5, 9])).tolist()
    [1, 0, 1, 2]
    """
    return np.unique(ranks, return_inverse=True)[1].reshape(-1).astype(np.int64)


class PlausibilityModel:
    """A multi-agent plausibility model, possibly multi-pointed: an immutable value.

    Parameters
    ----------
    atoms : sequence of str
        The vocabulary (columns of ``valuation``).
    valuation : array of bool, shape (n_worlds, n_atoms)
    cells : mapping
        Agent -> integer array of length ``n_worlds``: worlds with equal labels are in the
        same information cell of the agent.
    ranks : mapping
        Agent -> integer array of length ``n_worlds``: lower is more plausible; only the
        order within a cell matters. The agents are those of ``cells``.
    designated : array of bool, optional
        The actual worlds (default: every world).
    observes : mapping, optional
        Agent -> the atoms it observes, when the cells are the classes of equal observed
        atoms (as :meth:`from_levels` makes them); the symbolic backend needs it.
    """

    def __init__(
        self,
        atoms: Sequence[str],
        valuation: np.ndarray,
        cells: Mapping[str, Any],
        ranks: Mapping[str, Any],
        designated: np.ndarray | None = None,
        observes: Mapping[str, Iterable[str]] | None = None,
    ) -> None:
        self.atoms = tuple(atom_name(a, "atoms") for a in atoms)
        self.valuation = np.asarray(valuation, dtype=bool).reshape(-1, len(self.atoms))
        n = len(self.valuation)
        if set(cells) != set(ranks):
            raise ModelError(
                "every agent needs both cells and ranks",
                hint=f"cells name {sorted(cells)}, ranks name {sorted(ranks)}",
            )
        self.agents = tuple(str(a) for a in cells)
        self.cells = {str(a): dense_ranks(_vector(cells[a], n, f"cells[{a!r}]")) for a in cells}
        self.ranks = {str(a): dense_ranks(_vector(ranks[a], n, f"ranks[{a!r}]")) for a in ranks}
        self.designated = (
            np.ones(n, dtype=bool) if designated is None else np.asarray(designated, dtype=bool)
        )
        if self.designated.shape != (n,):
            raise InvalidArgumentError(
                f"designated must be a mask of {n} worlds", hint="one boolean per world"
            )
        self.observes = None if observes is None else {a: tuple(o) for a, o in observes.items()}
        self.column = {a: j for j, a in enumerate(self.atoms)}
        self.memo: dict[Formula, np.ndarray] = {}
        self.derived: dict[tuple[str, Formula], PlausibilityModel] = {}
        self.positions_in_parent = np.arange(n)

    @classmethod
    def from_levels(
        cls,
        atoms: Sequence[str],
        levels: Mapping[str, Sequence[Formula | str]],
        observes: Mapping[str, Iterable[str]] | None = None,
        law: Formula | str | None = None,
        designated: Iterable[str] | None = None,
    ) -> PlausibilityModel:
        """The model of every valuation satisfying ``law``, ranked by propositional levels.

        Agent ``a``'s rank of a world is the index of the first formula of ``levels[a]``
        that holds there (most plausible first); a world satisfying none comes after all
        of them. Agent ``a`` cannot tell apart worlds that agree on ``observes[a]``
        (default: it observes nothing). ``designated`` lists the atoms true in the actual
        world (``None``: every world is designated).

        Examples
        --------
        >>> m = PlausibilityModel.from_levels(["p", "q"], {"a": ["p & q", "p"]})
        >>> m.ranks["a"].tolist()  # worlds: {}, {q}, {p}, {p, q}
        [2, 2, 1, 0]
        """
        names = tuple(atom_name(a, "atoms") for a in atoms)
        if len(names) > 20:
            raise InvalidArgumentError(
                f"{len(names)} atoms are too many to list every valuation",
                hint="use the symbolic backend (PlausibilityStructure.from_levels)",
            )
        column = {a: j for j, a in enumerate(names)}
        table = np.array(list(product((False, True), repeat=len(names))), dtype=bool)
        table = table.reshape(-1, len(names))
        if law is not None:
            table = table[propositional_mask(as_formula(law), table, column)]
            if not len(table):
                raise InvalidArgumentError("no valuation satisfies the law", hint="relax it")
        observed = {str(a): tuple((observes or {}).get(a, ())) for a in levels}
        cells, ranks = {}, {}
        for agent, formulas in levels.items():
            agent = str(agent)
            seen = [_column(column, a, f"observes[{agent!r}]") for a in observed[agent]]
            cells[agent] = table[:, seen] @ (1 << np.arange(len(seen), dtype=np.int64))
            rank = np.full(len(table), len(formulas), dtype=np.int64)
            for i in range(len(formulas) - 1, -1, -1):
                rank[propositional_mask(as_formula(formulas[i]), table, column)] = i
            ranks[agent] = rank
        actual = None
        if designated is not None:
            want = np.zeros(len(names), dtype=bool)
            for a in designated:
                want[_column(column, a, "designated")] = True
            actual = (table == want).all(axis=1)
            if not actual.any():
                raise InvalidArgumentError(
                    "the designated valuation violates the law", hint="choose a lawful one"
                )
        return cls(names, table, cells, ranks, actual, observed)

    # -- questions ----------------------------------------------------------------------

    @property
    def n_worlds(self) -> int:
        """The number of worlds."""
        return len(self.valuation)

    def truth(self, formula: Formula | str) -> np.ndarray:
        """The truth set of ``formula``, a boolean mask over the worlds."""
        return evaluate_plausibility(self, as_formula(formula))

    def holds(self, formula: Formula | str) -> bool:
        """Whether ``formula`` holds at every designated world."""
        return bool(self.truth(formula)[self.designated].all())

    def best(self, agent: str, condition: np.ndarray) -> np.ndarray:
        """The most plausible ``condition``-worlds of each of ``agent``'s cells."""
        cells, ranks = self._order(agent)
        lowest = np.full(self.n_worlds + 1, np.iinfo(np.int64).max)
        np.minimum.at(lowest, cells[condition], ranks[condition])
        return condition & (ranks == lowest[cells])

    def to_kripke(self) -> ExplicitModel:
        """The Kripke model of knowledge (the cells) and plain belief (each world to the
        most plausible worlds of its cell): ``B[a]`` means the same in both. A Kripke
        model needs a designated world: with none, every world is designated."""
        worlds = range(self.n_worlds)
        valuation = {
            w: [a for a, t in zip(self.atoms, self.valuation[w], strict=True) if t] for w in worlds
        }
        belief, knowledge = {}, {}
        for agent in self.agents:
            cells = self.cells[agent]
            top = self.best(agent, np.ones(self.n_worlds, dtype=bool))
            same = cells[:, None] == cells[None, :]
            belief[agent] = list(zip(*np.nonzero(same & top[None, :]), strict=True))
            knowledge[agent] = list(zip(*np.nonzero(same), strict=True))
        designated = np.flatnonzero(self.designated).tolist() or list(worlds)
        return ExplicitModel(
            list(worlds), valuation, belief, designated, knowledge, atoms=self.atoms
        )

    # -- the operations evaluate_plausibility uses --------------------------------------

    def atom(self, atom: Atom) -> np.ndarray:
        column = self.column.get(atom.key)
        if column is None:
            raise InvalidArgumentError(
                f"unknown atom {atom.key!r}", hint=f"declared atoms: {', '.join(self.atoms)}"
            )
        return self.valuation[:, column]

    def constant(self, value: bool) -> np.ndarray:
        return np.full(self.n_worlds, value, dtype=bool)

    def know(self, agent: str, truth: np.ndarray) -> np.ndarray:
        cells, _ = self._order(agent)
        return ~self._cells_with(cells, ~truth)

    def conditional_belief(
        self, agent: str, condition: np.ndarray, truth: np.ndarray
    ) -> np.ndarray:
        cells, _ = self._order(agent)
        return ~self._cells_with(cells, self.best(agent, condition) & ~truth)

    def safe_belief(self, agent: str, truth: np.ndarray) -> np.ndarray:
        # w is safe iff every world ranked <= rank(w) in its cell satisfies truth, i.e.
        # rank(w) is below the lowest rank of a counterexample in the cell.
        cells, ranks = self._order(agent)
        lowest = np.full(self.n_worlds + 1, np.iinfo(np.int64).max)
        np.minimum.at(lowest, cells[~truth], ranks[~truth])
        return ranks < lowest[cells]

    def restricted(self, truth: np.ndarray) -> PlausibilityModel:
        keep = np.asarray(truth, dtype=bool)
        sub = PlausibilityModel(
            self.atoms,
            self.valuation[keep],
            {a: c[keep] for a, c in self.cells.items()},
            {a: r[keep] for a, r in self.ranks.items()},
            self.designated[keep],
            self.observes,
        )
        sub.positions_in_parent = np.flatnonzero(keep)
        return sub

    def lifted(self, submodel: PlausibilityModel, truth: np.ndarray) -> np.ndarray:
        out = np.zeros(self.n_worlds, dtype=bool)
        out[submodel.positions_in_parent] = truth
        return out

    def radical_upgrade(self, truth: np.ndarray) -> PlausibilityModel:
        # Every truth-world below every other, order inside each zone kept: shift the
        # others past the largest rank (ranks are dense, so by n_worlds is enough).
        return self._reranked(
            {a: np.where(truth, r, r + self.n_worlds + 1) for a, r in self.ranks.items()}
        )

    def conservative_upgrade(self, truth: np.ndarray) -> PlausibilityModel:
        # The best truth-worlds of each cell go to a new top rank; the rest stay in order.
        return self._reranked(
            {a: np.where(self.best(a, truth), 0, r + 1) for a, r in self.ranks.items()}
        )

    # -- internals ----------------------------------------------------------------------

    def _order(self, agent: str) -> tuple[np.ndarray, np.ndarray]:
        if agent not in self.cells:
            raise InvalidArgumentError(
                f"unknown agent {agent!r}", hint=f"agents: {', '.join(self.agents)}"
            )
        return self.cells[agent], self.ranks[agent]

    def _cells_with(self, cells: np.ndarray, worlds: np.ndarray) -> np.ndarray:
        """Per world: whether its cell holds one of ``worlds``."""
        flagged = np.zeros(self.n_worlds + 1, dtype=bool)
        flagged[cells[worlds]] = True
        return flagged[cells]

    def _reranked(self, ranks: dict[str, np.ndarray]) -> PlausibilityModel:
        return PlausibilityModel(
            self.atoms, self.valuation, self.cells, ranks, self.designated, self.observes
        )

    def __repr__(self) -> str:
        return (
            f"<PlausibilityModel: {self.n_worlds} worlds, atoms {list(self.atoms)}, "
            f"agents {list(self.agents)}>"
        )


def _vector(values: Any, n: int, where: str) -> np.ndarray:
    array = np.asarray(values)
    if array.shape != (n,) or (n and not np.issubdtype(array.dtype, np.integer)):
        raise InvalidArgumentError(
            f"{where} must be {n} integers, one per world", hint="e.g. [0, 1, 1]"
        )
    return array.astype(np.int64)


def _column(column: Mapping[str, int], atom: str, where: str) -> int:
    name = atom_name(atom, where)
    if name not in column:
        raise InvalidArgumentError(
            f"unknown atom {name!r} in {where}", hint=f"declared atoms: {', '.join(column)}"
        )
    return column[name]
