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

from epistemica.del_ import budget
from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.explicit import checker
from epistemica.del_.explicit._cube import Cube
from epistemica.del_.explicit.relations import Partition, Relation, relation_from_pairs
from epistemica.del_.language.formula import Formula, canonical_atom

if TYPE_CHECKING:
    from epistemica.del_.explicit.action import ActionModel

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
        val: np.ndarray | None,
        agents: tuple[str, ...],
        rel: dict[str, Relation] | None,
        know: dict[str, Relation] | None,
        designated: np.ndarray | None,
        cube: Cube | None = None,
        designated_codes: np.ndarray | None = None,
    ) -> None:
        self._names = names
        self._atoms = atoms
        self._column = {a: j for j, a in enumerate(atoms)}
        # Models from observables keep a bitset cube and build the arrays below on demand.
        self._cube = cube
        self._designated_codes = designated_codes
        self._val_ = None if val is None else np.asfortranarray(val, dtype=bool)
        self._agents = agents
        self._rel_ = rel
        self._know_ = know
        self._designated_ = None if designated is None else np.unique(designated)
        self._memo: dict[Any, np.ndarray] = {}
        self._derived: dict[Any, Any] = {}

    @classmethod
    def _from_arrays(cls, names, atoms, val, agents, rel, know, designated) -> KripkeModel:
        model = cls.__new__(cls)
        model._init(names, atoms, val, agents, rel, know, designated)
        return model

    @classmethod
    def _from_cube(cls, cube: Cube, atoms, agents, designated_codes) -> KripkeModel:
        model = cls.__new__(cls)
        model._init(
            _code_names(cube), atoms, None, agents, None, None, None, cube, designated_codes
        )
        return model

    def _cube_submodel(self, bits: np.ndarray) -> KripkeModel:
        """The restriction to the live codes of ``bits``, for evaluation only."""
        empty = np.zeros(0, dtype=np.intp)
        return KripkeModel._from_cube(self._cube.restrict(bits), self._atoms, self._agents, empty)

    def _materialize(self) -> None:
        """Build the compact arrays of a cube model (valuation matrix, partitions)."""
        cube = self._cube
        self._require_arrays()
        codes = cube.codes
        shifts = np.arange(cube.n_bits - 1, -1, -1, dtype=np.intp)
        self._val_ = np.asfortranarray(((codes[:, None] >> shifts) & 1).astype(bool))
        everything = (1 << cube.n_bits) - 1
        # Labels are codes with the hidden bits cleared; renumbered when few codes are live,
        # so that a box scatters into an array of the live classes, not of all 2^n codes.
        compact = 4 * len(codes) < (1 << cube.n_bits)
        rel: dict[str, Relation] = {}
        for agent in self._agents:
            labels = codes & (everything ^ sum(1 << p for p in cube.hidden[agent]))
            if compact:
                rel[agent] = Partition(np.unique(labels, return_inverse=True)[1].reshape(-1))
            else:
                rel[agent] = Partition(labels, n_labels=1 << cube.n_bits)
        self._rel_, self._know_ = rel, dict(rel)
        self._designated_ = np.searchsorted(codes, self._designated_codes)

    def _arrays_bytes(self) -> int:
        """Bytes the compact arrays of a cube model would take (0 once they exist)."""
        if self._cube is None or self._val_ is not None:
            return 0
        # codes, valuation matrix, one label per world and agent, a sort's scratch
        return self._cube.count() * (8 + self._cube.n_bits + 8 * len(self._agents) + 16)

    def _require_arrays(self) -> None:
        """Refuse to build the compact arrays of a cube model beyond the memory budget."""
        needed = self._arrays_bytes()
        if needed:
            n_worlds = self._cube.count()
            budget.require(needed, f"listing the {n_worlds:,} worlds of the model")

    @property
    def _val(self) -> np.ndarray:
        if self._val_ is None:
            self._materialize()
        return self._val_

    @property
    def _rel(self) -> dict[str, Relation]:
        if self._rel_ is None:
            self._materialize()
        return self._rel_

    @property
    def _know(self) -> dict[str, Relation]:
        if self._know_ is None:
            self._materialize()
        return self._know_

    @property
    def _designated(self) -> np.ndarray:
        if self._designated_ is None:  # a cube model: positions of its designated codes
            self._designated_ = np.searchsorted(self._cube.codes, self._designated_codes)
        return self._designated_

    @property
    def designated_positions(self) -> np.ndarray:
        """The positions in :attr:`worlds` of the designated worlds (a read-only array)."""
        positions = self._designated.view()
        positions.setflags(write=False)
        return positions

    @classmethod
    def from_observables(
        cls,
        atoms: Sequence[str],
        observes: Mapping[str, Iterable[str]],
        law: Formula | str | None = None,
        designated: Iterable[str] | None = None,
        *,
        memory_budget: int | None = None,
    ) -> KripkeModel:
        """Build the S5 model in which each agent sees the truth of some atoms.

        Worlds are the valuations of ``atoms`` that satisfy the propositional formula
        ``law``; agent ``a`` cannot tell apart two worlds that agree on ``observes[a]``.
        Each world is named by its code: the integer whose binary digits are the truth
        values of the atoms, the first atom being the most significant bit. Such models are
        evaluated on bitsets over all codes (see :mod:`epistemica.del_.explicit._cube`), which makes
        public announcements on a million worlds take milliseconds.

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
        memory_budget : int, optional
            Bytes the valuation bitsets may take (default
            :data:`~epistemica.del_.budget.DEFAULT_MEMORY_BUDGET`); beyond it a
            :class:`~epistemica.del_.budget.MemoryBudgetError` is raised before allocating.

        Examples
        --------
        Three muddy children, each seeing the others' foreheads:

        >>> m = KripkeModel.from_observables(
        ...     ["m1", "m2", "m3"],
        ...     {"c1": ["m2", "m3"], "c2": ["m1", "m3"], "c3": ["m1", "m2"]},
        ...     designated=["m1", "m2"])
        >>> m.n_worlds
        8
        >>> m.designated   # m1 m2 ~m3 = binary 110
        (6,)
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
        column = {a: j for j, a in enumerate(atom_list)}
        hidden = {}
        for agent, seen in observes.items():
            visible = {_column_of(column, a, f"observes[{agent!r}]") for a in seen}
            hidden[str(agent)] = tuple(n_atoms - 1 - j for j in range(n_atoms) if j not in visible)
        with budget.budget_scope(memory_budget):
            # the live set, the law's truth set and a few atoms' bitsets
            budget.require(4 * max(8, (1 << n_atoms) // 8), f"the {2**n_atoms:,} valuations")
            cube = Cube.full(n_atoms, hidden)
        agents = tuple(hidden)
        if law is not None:
            tree = checker.as_formula(law)
            checker.propositional_mask(tree, np.zeros((0, n_atoms), dtype=bool), column)
            everything = cls._from_cube(cube, atom_list, agents, np.zeros(0, dtype=np.intp))
            cube = cube.restrict(checker.evaluate_bits(everything, tree))
            if not cube.count():
                raise InvalidArgumentError(
                    "no valuation satisfies the law", hint="the law is a contradiction"
                )
        if designated is None:
            points = cube.codes
        else:
            code = 0
            for a in designated:
                code |= 1 << (n_atoms - 1 - _column_of(column, a, "designated"))
            if not cube.test(cube.alive, np.array([code]))[0]:
                raise InvalidArgumentError(
                    "the designated valuation violates the law",
                    hint="choose an actual world that satisfies the law",
                )
            points = np.array([code], dtype=np.intp)
        return cls._from_cube(cube, atom_list, agents, points)

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
        if self._cube is not None:
            return self._cube.count()
        return self._val.shape[0]

    @property
    def worlds(self) -> tuple:
        """The world names, in internal order."""
        if self._names is None:
            self._names = tuple(range(self.n_worlds))
        elif callable(self._names):
            self._names = self._names()
        return self._names

    def worlds_at(self, indices: Iterable[int]) -> tuple:
        """The names of the worlds at these positions of :attr:`worlds`, listing no other.

        Examples
        --------
        >>> m = KripkeModel.from_observables(["p", "q"], {"a": []}).announce("p | q")
        >>> m.worlds_at([0, 2])
        (1, 3)
        """
        indices = np.asarray(list(indices), dtype=np.intp)
        if self._names_are_codes():
            return tuple(int(c) for c in self._cube.codes[indices])
        names = self.worlds
        return tuple(names[i] for i in indices)

    @property
    def designated(self) -> tuple:
        """The designated worlds' names."""
        if self._names_are_codes():  # no need to list every world
            return tuple(int(c) for c in self._designated_codes)
        names = self.worlds
        return tuple(names[i] for i in self._designated)

    def valuation_of(self, world: World) -> frozenset[str]:
        """The atoms true at ``world``."""
        if self._names_are_codes():  # a world's name is its valuation's code
            code = self._names.code_of(world)
            n = len(self._atoms)
            return frozenset(a for j, a in enumerate(self._atoms) if code >> (n - 1 - j) & 1)
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
        self,
        formula: Formula | str,
        actions: Mapping[str, ActionModel] | None = None,
        *,
        memory_budget: int | None = None,
    ) -> np.ndarray:
        """Boolean mask over :attr:`worlds` of where ``formula`` holds.

        ``actions`` maps names to action models and resolves ``[ACT] g``;
        ``memory_budget`` bounds the bytes allocated (see :mod:`epistemica.del_.budget`).
        """
        return checker.evaluate(self, formula, actions, memory_budget=memory_budget).copy()

    def truth_set(
        self,
        formula: Formula | str,
        actions: Mapping[str, ActionModel] | None = None,
        *,
        memory_budget: int | None = None,
    ) -> frozenset:
        """The names of the worlds where ``formula`` holds."""
        mask = checker.evaluate(self, formula, actions, memory_budget=memory_budget)
        if self._names_are_codes():  # names are codes: list no other world
            return frozenset(int(c) for c in self._names.cube.codes[mask])
        names = self.worlds
        return frozenset(names[i] for i in np.flatnonzero(mask))

    def holds(
        self,
        formula: Formula | str,
        actions: Mapping[str, ActionModel] | None = None,
        *,
        memory_budget: int | None = None,
    ) -> bool:
        """Whether ``formula`` holds at every designated world."""
        tree = checker.as_formula(formula)
        with budget.budget_scope(memory_budget):
            return bool(checker.designated_truth(self, tree, actions).all())

    # -- updates ------------------------------------------------------------------------

    def announce(self, formula: Formula | str, *, memory_budget: int | None = None) -> KripkeModel:
        """The model after the truthful public announcement of ``formula``.

        Raises
        ------
        InvalidArgumentError
            If ``formula`` is false at every designated world (it cannot be announced
            truthfully).
        """
        tree = checker.as_formula(formula)
        with budget.budget_scope(memory_budget):
            if self._cube is not None and not self._cube.sparse():
                bits = checker.evaluate_bits(self, tree)
                kept = self._designated_codes[self._cube.test(bits, self._designated_codes)]
                if len(kept):
                    return KripkeModel._from_cube(
                        self._cube.restrict(bits), self._atoms, self._agents, kept
                    )
            else:
                mask = checker.evaluate(self, tree, None)
                if mask[self._designated].any():
                    return self.restrict(mask)
        raise InvalidArgumentError(
            f"cannot announce {tree}: it is false at every designated world",
            hint="only true formulas can be announced; check it with holds() first",
        )

    def restrict(self, mask: np.ndarray) -> KripkeModel:
        """The submodel on the worlds of ``mask`` (designated worlds outside are dropped)."""
        mask = np.asarray(mask, dtype=bool)
        kept_points = self._designated[mask[self._designated]]
        if not len(kept_points):
            raise InvalidArgumentError("the restriction removes every designated world")
        # New index of a kept world = number of kept worlds before it.
        designated = np.cumsum(mask[: kept_points[-1] + 1])[kept_points] - 1
        return self._restricted(mask, designated)

    def _restricted(self, mask: np.ndarray, designated: np.ndarray) -> KripkeModel:
        """The submodel on ``mask`` with the given (new) designated indices, possibly none."""
        rel = {a: r.restrict(mask) for a, r in self._rel.items()}
        know = {a: rel[a] if k is self._rel[a] else k.restrict(mask) for a, k in self._know.items()}
        return KripkeModel._from_arrays(
            _pick_names(self._names, mask),
            self._atoms,
            self._val[mask],
            self._agents,
            rel,
            know,
            designated,
        )

    def repoint(self, designated: World | Iterable[World]) -> KripkeModel:
        """The same model with other designated worlds.

        The result shares this model's memoised truth sets (they do not depend on the
        designated worlds), so re-pointing for an agent's perspective is cheap.

        Examples
        --------
        >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
        >>> m.holds("p"), m.repoint(m.worlds).holds("p")
        (True, False)
        """
        points = _as_world_list(designated, self._world_index())
        if not points:
            raise InvalidArgumentError("repoint needs at least one world")
        model = KripkeModel.__new__(KripkeModel)
        model.__dict__.update(self.__dict__)
        model._designated_ = np.unique(np.array(points, dtype=np.intp))
        if self._cube is not None:
            model._designated_codes = self._cube.codes[model._designated_]
        return model

    def is_applicable(self, action: ActionModel) -> bool:
        """Whether some designated event's precondition holds at some designated world."""
        from epistemica.del_.explicit.action import is_applicable

        return is_applicable(self, action)

    def update(self, action: ActionModel) -> KripkeModel:
        """The product update of this model with ``action``.

        World names become ``(world, event)`` pairs. Raises
        :class:`~epistemica.del_.errors.InvalidArgumentError` when no designated event is
        executable at a designated world.
        """
        from epistemica.del_.explicit.action import product_update

        return product_update(self, action)

    def minimize(self) -> KripkeModel:
        """The bisimulation contraction of the submodel generated by the designated worlds."""
        from epistemica.del_.explicit.bisimulation import minimize

        return minimize(self)

    def to_symbolic(self, atoms: Iterable[str] | None = None) -> Any:
        """This model as a :class:`~epistemica.del_.symbolic.KnowledgeStructure` (BDDs).

        ``atoms`` declares further atoms, false everywhere (see
        :meth:`KnowledgeStructure.from_kripke
        <epistemica.del_.symbolic.KnowledgeStructure.from_kripke>`).

        Examples
        --------
        >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
        >>> m.to_symbolic().holds("p & ~K[a] p")
        True
        """
        from epistemica.del_.symbolic import KnowledgeStructure

        return KnowledgeStructure.from_kripke(self, atoms)

    def to_networkx(self) -> Any:
        """The model as a :class:`networkx.MultiDiGraph`

        (see :mod:`~epistemica.del_.explicit.export`)."""
        from epistemica.del_.explicit.export import to_networkx

        return to_networkx(self)

    def to_dot(self) -> str:
        """The model in Graphviz DOT (see :mod:`~epistemica.del_.explicit.export`)."""
        from epistemica.del_.explicit.export import to_dot

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

    def _world_index(self) -> dict[World, int]:
        index = self._derived.get("index")
        if index is None:
            index = self._derived["index"] = {w: i for i, w in enumerate(self.worlds)}
        return index

    def _index_of(self, world: World) -> int:
        return _lookup(self._world_index(), world, "argument")

    def _names_are_codes(self) -> bool:
        """Whether world names are the live codes of this model's cube (in order)."""
        names = self._names
        return (
            isinstance(names, _CodeNames)
            and names.cube is self._cube
            and self._designated_codes is not None
        )

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


class _CodeNames:
    """The names of a cube model's worlds (their codes), listed only when asked for."""

    def __init__(self, cube: Cube) -> None:
        self.cube = cube

    def __call__(self) -> tuple:
        return tuple(self.cube.codes.tolist())

    def code_of(self, world: World) -> int:
        """The code of a live world, checked without listing the others."""
        if isinstance(world, (int, np.integer)) and 0 <= world < 1 << self.cube.n_bits:
            if self.cube.test(self.cube.alive, np.array([world]))[0]:
                return int(world)
        raise ModelError(
            f"unknown world {world!r} in argument", hint="every world must be listed in `worlds`"
        )


def _code_names(cube: Cube) -> Callable[[], tuple]:
    return _CodeNames(cube)


def _pick_names(source: tuple | Callable[[], tuple] | None, mask: np.ndarray) -> Callable:
    """Names of a restriction, computed only when asked for (it keeps no parent model alive)."""

    def names() -> tuple:
        keep = np.flatnonzero(mask)
        if source is None:
            return tuple(int(i) for i in keep)
        full = source() if callable(source) else source
        return tuple(full[i] for i in keep)

    return names
