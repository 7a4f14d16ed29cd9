"""Multi-agent Kripke models: worlds, valuations, per-agent relations, designated worlds.

A :class:`KripkeModel` is an immutable value. Internally worlds are numbered ``0..n-1``;
the valuation is a boolean matrix (worlds x atoms); each agent has a *belief* relation
(``B`` quantifies over it) and a *knowledge* relation (``K`` quantifies over it), which are
one and the same unless the model was given, or an update produced, a separate one.
Truth sets are numpy boolean masks, memoised per model and subformula.

Examples
--------
Two worlds that agent ``a`` cannot tell apart and ``b`` can:

>>> m = KripkeModel(
...     worlds=["w1", "w2"],
...     valuation={"w1": {"p"}, "w2": set()},
...     relations={"a": [("w1", "w1"), ("w1", "w2"), ("w2", "w1"), ("w2", "w2")],
...                "b": [("w1", "w1"), ("w2", "w2")]},
...     designated="w1",
... )
>>> m.holds("p & ~K[a] p & K[b] p & K[a] Kw[b] p")
True
>>> sorted(m.truth_set("K[b] p"))
['w1']
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from epistemica.del_ import checker
from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.formula import Formula, canonical_atom
from epistemica.del_.relations import Partition, Relation, relation_from_pairs

if TYPE_CHECKING:
    from epistemica.del_.action import ActionModel

__all__ = ["KripkeModel"]

# Enumerating valuations beyond this many atoms would not fit in memory.
MAX_ENUMERATED_ATOMS = 26

World = Hashable


class KripkeModel:
    """A multi-agent Kripke model, possibly multi-pointed.

    Parameters
    ----------
    worlds : sequence of hashable
        Distinct world names.
    valuation : mapping
        World -> iterable of the atoms true there (text such as ``"p"`` or
        ``"at(r1, g1)"``); unlisted atoms are false.
    relations : mapping
        Agent -> iterable of ``(w, v)`` pairs: the agent's accessibility relation.
        ``B[a]`` quantifies over it, and so does ``K[a]`` unless ``knowledge`` is given.
    designated : world or iterable of worlds
        The actual world(s); :meth:`holds` checks truth at all of them.
    knowledge : mapping, optional
        Agent -> pairs: a separate knowledge relation for ``K[a]``.

    Raises
    ------
    ModelError
        If a pair, valuation entry or designated world names an unknown world.
    """

    def __init__(
        self,
        worlds: Sequence[World],
        valuation: Mapping[World, Iterable[str]],
        relations: Mapping[str, Iterable[tuple[World, World]]],
        designated: World | Iterable[World],
        knowledge: Mapping[str, Iterable[tuple[World, World]]] | None = None,
    ) -> None:
        names = tuple(worlds)
        index = {w: i for i, w in enumerate(names)}
        if len(index) != len(names):
            raise ModelError("world names must be distinct", hint="rename the repeated world")
        atoms: dict[str, None] = {}
        for w, true_atoms in valuation.items():
            _lookup(index, w, "valuation")
            for a in true_atoms:
                atoms.setdefault(canonical_atom(str(a)))
        atom_list = tuple(atoms)
        column = {a: j for j, a in enumerate(atom_list)}
        val = np.zeros((len(names), len(atom_list)), dtype=bool)
        for w, true_atoms in valuation.items():
            for a in true_atoms:
                val[index[w], column[canonical_atom(str(a))]] = True
        agents = tuple(str(a) for a in relations)
        rel = {
            str(a): _relation(index, pairs, f"relation of {a}") for a, pairs in relations.items()
        }
        know = dict(rel)
        if knowledge is not None:
            for a, pairs in knowledge.items():
                if str(a) not in rel:
                    raise ModelError(
                        f"knowledge relation given for unknown agent {a!r}",
                        hint=f"agents with a relation: {', '.join(agents)}",
                    )
                know[str(a)] = _relation(index, pairs, f"knowledge relation of {a}")
        points = _as_world_list(designated, index)
        if not points:
            raise ModelError("a model needs at least one designated world")
        self._init(names, atom_list, val, agents, rel, know, np.array(points, dtype=np.int64))

    # -- construction -------------------------------------------------------------------

    def _init(
        self,
        names: tuple | Callable[[], tuple] | None,
        atoms: tuple[str, ...],
        val: np.ndarray,
        agents: tuple[str, ...],
        rel: dict[str, Relation],
        know: dict[str, Relation],
        designated: np.ndarray,
    ) -> None:
        self._names = names
        self._atoms = atoms
        self._column = {a: j for j, a in enumerate(atoms)}
        self._val = val
        self._agents = agents
        self._rel = rel
        self._know = know
        self._designated = np.unique(designated)
        self._memo: dict[Any, np.ndarray] = {}
        self._derived: dict[Any, Any] = {}

    @classmethod
    def _from_arrays(cls, names, atoms, val, agents, rel, know, designated) -> KripkeModel:
        model = cls.__new__(cls)
        model._init(names, atoms, val, agents, rel, know, designated)
        return model

    @classmethod
    def from_observables(
        cls,
        atoms: Sequence[str],
        observes: Mapping[str, Iterable[str]],
        law: Formula | str | None = None,
        designated: Iterable[str] | None = None,
    ) -> KripkeModel:
        """Build the S5 model in which each agent sees the truth of some atoms.

        Worlds are the valuations of ``atoms`` that satisfy the propositional formula
        ``law``; agent ``a`` cannot tell apart two worlds that agree on ``observes[a]``.
        World ``i`` is named by the integer ``i``; the first atom is the most significant
        bit, so worlds come in lexicographic order of their valuations.

        Parameters
        ----------
        atoms : sequence of str
            The atoms, at most 26.
        observes : mapping
            Agent -> the atoms whose truth the agent sees.
        law : formula or str, optional
            A propositional formula every world satisfies (default ``true``).
        designated : iterable of str, optional
            The atoms true in the actual world; ``None`` designates every world.

        Examples
        --------
        Three muddy children, each seeing the others' foreheads:

        >>> m = KripkeModel.from_observables(
        ...     ["m1", "m2", "m3"],
        ...     {"c1": ["m2", "m3"], "c2": ["m1", "m3"], "c3": ["m1", "m2"]},
        ...     designated=["m1", "m2"])
        >>> m.n_worlds
        8
        >>> m.holds("~Kw[c1] m1 & K[c3] (m1 & m2)")
        True
        """
        atom_list = tuple(canonical_atom(a) for a in atoms)
        if len(set(atom_list)) != len(atom_list):
            raise InvalidArgumentError("atoms must be distinct", hint="remove the repeated atom")
        if len(atom_list) > MAX_ENUMERATED_ATOMS:
            raise InvalidArgumentError(
                f"{len(atom_list)} atoms would give 2^{len(atom_list)} valuations to enumerate",
                hint=f"use at most {MAX_ENUMERATED_ATOMS} atoms, or build the worlds explicitly",
            )
        n_atoms = len(atom_list)
        codes = np.arange(1 << n_atoms, dtype=np.int64)
        shifts = np.arange(n_atoms - 1, -1, -1, dtype=np.int64)
        val = ((codes[:, None] >> shifts) & 1).astype(bool)
        column = {a: j for j, a in enumerate(atom_list)}
        if law is not None:
            keep = checker.propositional_mask(law, val, column)
            codes, val = codes[keep], val[keep]
            if not len(codes):
                raise InvalidArgumentError(
                    "no valuation satisfies the law", hint="the law is a contradiction"
                )
        agents = tuple(str(a) for a in observes)
        rel: dict[str, Relation] = {}
        for agent, seen in observes.items():
            mask = 0
            for a in seen:
                mask |= 1 << (n_atoms - 1 - _column_of(column, a, f"observes[{agent!r}]"))
            rel[str(agent)] = Partition(codes & mask, n_labels=1 << n_atoms)
        if designated is None:
            points = np.arange(len(codes))
        else:
            actual = np.zeros(n_atoms, dtype=bool)
            for a in designated:
                actual[_column_of(column, a, "designated")] = True
            points = np.flatnonzero((val == actual).all(axis=1))
            if not len(points):
                raise InvalidArgumentError(
                    "the designated valuation violates the law",
                    hint="choose an actual world that satisfies the law",
                )
        return cls._from_arrays(None, atom_list, val, agents, rel, dict(rel), points)

    @classmethod
    def from_partitions(
        cls,
        worlds: Sequence[World],
        valuation: Mapping[World, Iterable[str]],
        partitions: Mapping[str, Iterable[Iterable[World]]],
        designated: World | Iterable[World],
    ) -> KripkeModel:
        """Build an S5 model from each agent's partition of the worlds into blocks.

        Examples
        --------
        >>> m = KripkeModel.from_partitions(
        ...     ["h", "t"], {"h": {"heads"}}, {"a": [["h", "t"]], "b": [["h"], ["t"]]}, "h")
        >>> m.holds("Kw[b] heads & ~Kw[a] heads")
        True
        """
        relations = {}
        for agent, blocks in partitions.items():
            pairs = []
            for block in blocks:
                block = list(block)
                pairs.extend((w, v) for w in block for v in block)
            relations[agent] = pairs
        return cls(worlds, valuation, relations, designated)

    # -- inspection ---------------------------------------------------------------------

    @property
    def agents(self) -> tuple[str, ...]:
        """The agents, in declaration order."""
        return self._agents

    @property
    def atoms(self) -> tuple[str, ...]:
        """The atoms that have a column in the valuation."""
        return self._atoms

    @property
    def n_worlds(self) -> int:
        """The number of worlds."""
        return self._val.shape[0]

    @property
    def worlds(self) -> tuple:
        """The world names, in internal order."""
        if self._names is None:
            self._names = tuple(range(self.n_worlds))
        elif callable(self._names):
            self._names = self._names()
        return self._names

    @property
    def designated(self) -> tuple:
        """The designated worlds' names."""
        names = self.worlds
        return tuple(names[i] for i in self._designated)

    def valuation_of(self, world: World) -> frozenset[str]:
        """The atoms true at ``world``."""
        i = self._index_of(world)
        return frozenset(a for a, t in zip(self._atoms, self._val[i], strict=True) if t)

    def successors(self, agent: str, world: World, relation: str = "belief") -> tuple:
        """The worlds ``agent`` considers possible at ``world``."""
        mask = np.zeros(self.n_worlds, dtype=bool)
        mask[self._index_of(world)] = True
        hit = self._relation(agent, relation).successors_of(mask)
        names = self.worlds
        return tuple(names[i] for i in np.flatnonzero(hit))

    def is_s5(self, agent: str, relation: str = "belief") -> bool:
        """Whether the agent's relation is an equivalence (reflexive, symmetric, transitive)."""
        return self._relation(agent, relation).is_equivalence()

    def is_kd45(self, agent: str, relation: str = "belief") -> bool:
        """Whether the agent's relation is serial, transitive and Euclidean."""
        return self._relation(agent, relation).is_kd45()

    def has_separate_knowledge(self) -> bool:
        """Whether some agent's knowledge relation differs from its belief relation."""
        return any(self._know[a] is not self._rel[a] for a in self._agents)

    # -- model checking -----------------------------------------------------------------

    def truth_mask(
        self, formula: Formula | str, actions: Mapping[str, ActionModel] | None = None
    ) -> np.ndarray:
        """Boolean mask over :attr:`worlds` of where ``formula`` holds.

        ``actions`` maps names to action models and resolves ``[ACT] g``.
        """
        return checker.evaluate(self, formula, actions).copy()

    def truth_set(
        self, formula: Formula | str, actions: Mapping[str, ActionModel] | None = None
    ) -> frozenset:
        """The names of the worlds where ``formula`` holds."""
        names = self.worlds
        return frozenset(names[i] for i in np.flatnonzero(checker.evaluate(self, formula, actions)))

    def holds(
        self, formula: Formula | str, actions: Mapping[str, ActionModel] | None = None
    ) -> bool:
        """Whether ``formula`` holds at every designated world."""
        return bool(checker.evaluate(self, formula, actions)[self._designated].all())

    # -- updates ------------------------------------------------------------------------

    def announce(self, formula: Formula | str) -> KripkeModel:
        """The model after the truthful public announcement of ``formula``.

        Raises
        ------
        InvalidArgumentError
            If ``formula`` is false at every designated world (it cannot be announced
            truthfully).
        """
        mask = checker.evaluate(self, formula, None)
        if not mask[self._designated].any():
            raise InvalidArgumentError(
                f"cannot announce {formula}: it is false at every designated world",
                hint="only true formulas can be announced; check it with holds() first",
            )
        return self.restrict(mask)

    def restrict(self, mask: np.ndarray) -> KripkeModel:
        """The submodel on the worlds of ``mask`` (designated worlds outside are dropped)."""
        keep = np.flatnonzero(mask)
        points = np.flatnonzero(mask[self._designated])
        if not len(points):
            raise InvalidArgumentError("the restriction removes every designated world")
        new_index = np.cumsum(mask) - 1
        rel = {a: r.restrict(keep) for a, r in self._rel.items()}
        know = {a: rel[a] if k is self._rel[a] else k.restrict(keep) for a, k in self._know.items()}
        names = _pick_names(self._names, keep)
        designated = new_index[self._designated[mask[self._designated]]]
        return KripkeModel._from_arrays(
            names, self._atoms, self._val[keep], self._agents, rel, know, designated
        )

    def is_applicable(self, action: ActionModel) -> bool:
        """Whether some designated event's precondition holds at some designated world."""
        from epistemica.del_.action import is_applicable

        return is_applicable(self, action)

    def update(self, action: ActionModel) -> KripkeModel:
        """The product update of this model with ``action``.

        World names become ``(world, event)`` pairs. Raises
        :class:`~epistemica.del_.errors.InvalidArgumentError` when no designated event is
        executable at a designated world.
        """
        from epistemica.del_.action import product_update

        return product_update(self, action)

    def minimize(self) -> KripkeModel:
        """The bisimulation contraction of the submodel generated by the designated worlds."""
        from epistemica.del_.bisimulation import minimize

        return minimize(self)

    def to_networkx(self) -> Any:
        """The model as a :class:`networkx.MultiDiGraph` (see :mod:`epistemica.del_.export`)."""
        from epistemica.del_.export import to_networkx

        return to_networkx(self)

    def to_dot(self) -> str:
        """The model in Graphviz DOT (see :mod:`epistemica.del_.export`)."""
        from epistemica.del_.export import to_dot

        return to_dot(self)

    def __repr__(self) -> str:
        return (
            f"<KripkeModel: {self.n_worlds} worlds, agents {list(self._agents)}, "
            f"{len(self._designated)} designated>"
        )

    # -- internals ----------------------------------------------------------------------

    def _relation(self, agent: str, kind: str) -> Relation:
        table = {"belief": self._rel, "knowledge": self._know}.get(kind)
        if table is None:
            raise InvalidArgumentError(
                f"unknown relation kind {kind!r}", hint="use 'belief' or 'knowledge'"
            )
        if agent not in table:
            raise InvalidArgumentError(
                f"unknown agent {agent!r}", hint=f"the model's agents: {', '.join(self._agents)}"
            )
        return table[agent]

    def _index_of(self, world: World) -> int:
        index = self._derived.get("index")
        if index is None:
            index = self._derived["index"] = {w: i for i, w in enumerate(self.worlds)}
        return _lookup(index, world, "argument")

    def _atom_column(self, atom: str) -> int | None:
        return self._column.get(atom)


def _lookup(index: Mapping[World, int], world: World, where: str) -> int:
    try:
        return index[world]
    except (KeyError, TypeError):
        raise ModelError(
            f"unknown world {world!r} in {where}", hint="every world must be listed in `worlds`"
        ) from None


def _column_of(column: Mapping[str, int], atom: str, where: str) -> int:
    key = canonical_atom(str(atom))
    if key not in column:
        raise InvalidArgumentError(
            f"unknown atom {atom!r} in {where}", hint=f"declared atoms: {', '.join(column)}"
        )
    return column[key]


def _relation(index: Mapping[World, int], pairs: Iterable, where: str) -> Relation:
    sources, targets = [], []
    for pair in pairs:
        w, v = pair
        sources.append(_lookup(index, w, where))
        targets.append(_lookup(index, v, where))
    return relation_from_pairs(len(index), sources, targets)


def _as_world_list(designated: Any, index: Mapping[World, int]) -> list[int]:
    try:
        if designated in index:
            return [index[designated]]
    except TypeError:
        pass
    return [_lookup(index, w, "designated") for w in designated]


def _pick_names(source: tuple | Callable[[], tuple] | None, keep: np.ndarray) -> Callable:
    """Names of a restriction, computed only when asked for (it keeps no parent model alive)."""

    def names() -> tuple:
        if source is None:
            return tuple(int(i) for i in keep)
        full = source() if callable(source) else source
        return tuple(full[i] for i in keep)

    return names
