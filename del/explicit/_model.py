"""The data of an explicit Kripke model and the interface the algorithms use.

:class:`ExplicitModel` is an immutable value: worlds numbered ``0..n-1``, a boolean
valuation matrix (worlds x atoms), per agent a *belief* relation (``B`` quantifies over it)
and a *knowledge* relation (``K`` quantifies over it), which are one and the same object
unless the model was given, or an update produced, a separate one, and the designated
worlds. A model built from observables keeps a bitset :class:`~._cube.Cube` of its live
valuations instead, and lists its worlds only when an operation needs them.

The algorithms of the explicit backend (:mod:`.checker`, :mod:`.action`,
:mod:`.bisimulation`, :mod:`.canonical`, :mod:`.describe`, :mod:`.export`) are functions
over the read-only interface below; a function that makes a new model calls a constructor
of ``type(model)`` (:meth:`ExplicitModel.from_arrays`, :meth:`ExplicitModel.from_cube`,
:meth:`ExplicitModel.restricted`, ...), so the public subclass
:class:`~epistemica.del_.models.KripkeModel` comes back. The interface:

- names: :attr:`agents`, :attr:`atoms`, :attr:`n_worlds`, :attr:`worlds`, :attr:`designated`,
  :meth:`worlds_at`, :attr:`lazy_names`;
- arrays: :attr:`valuation`, :attr:`belief_relations`, :attr:`knowledge_relations`,
  :meth:`relation`, :attr:`designated_positions`, :meth:`atom_column`;
- bitsets (models from observables): :attr:`cube`, :attr:`designated_codes`,
  :meth:`cube_submodel`, :meth:`arrays_bytes`, :meth:`require_arrays`;
- caches that evaluation fills (they never change what the model means): :attr:`memo`,
  :attr:`derived`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from types import MappingProxyType
from typing import Any

import numpy as np

from epistemica.del_ import budget
from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.explicit._arguments import column_of
from epistemica.del_.explicit._cube import Cube
from epistemica.del_.explicit._model_input import World, lookup_world, model_arrays, world_positions
from epistemica.del_.explicit.relations import Partition, Relation

__all__ = ["MAX_ENUMERATED_ATOMS", "ExplicitModel", "column_of"]

# Enumerating valuations beyond this many atoms would not fit in memory.
MAX_ENUMERATED_ATOMS = 26


class ExplicitModel:
    """The data of a multi-agent Kripke model, possibly multi-pointed.

    The constructor's parameters are documented on the public subclass,
    :class:`~epistemica.del_.KripkeModel`; algorithms use the interface in the module
    docstring.
    """

    def __init__(
        self,
        worlds: Sequence[World],
        valuation: Mapping[World, Iterable[str]],
        relations: Mapping[str, Iterable[tuple[World, World]]],
        designated: World | Iterable[World],
        knowledge: Mapping[str, Iterable[tuple[World, World]]] | None = None,
        *,
        atoms: Iterable[str] | None = None,
    ) -> None:
        self._init(*model_arrays(worlds, valuation, relations, designated, knowledge, atoms))

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
        memo: dict[Any, np.ndarray] | None = None,
        derived: dict[Any, Any] | None = None,
    ) -> None:
        self._names = names
        self._atoms = atoms
        self._column = {a: j for j, a in enumerate(atoms)}
        # Models from observables keep a bitset cube and build the arrays below on demand.
        self._cube = cube
        self._designated_codes = designated_codes
        self._val_ = None if val is None else _read_only(np.asfortranarray(val, dtype=bool))
        self._agents = agents
        self._rel_ = rel
        self._know_ = know
        self._designated_ = None if designated is None else _read_only(np.unique(designated))
        self._memo: dict[Any, np.ndarray] = {} if memo is None else memo
        self._derived: dict[Any, Any] = {} if derived is None else derived

    @classmethod
    def from_arrays(
        cls,
        names: tuple | Callable[[], tuple] | None,
        atoms: tuple[str, ...],
        val: np.ndarray,
        agents: tuple[str, ...],
        rel: dict[str, Relation],
        know: dict[str, Relation],
        designated: np.ndarray,
    ) -> ExplicitModel:
        """A model from its arrays, unchecked (for algorithms that derive a model).

        ``names`` is what :attr:`lazy_names` gives: a tuple, a callable listing the names
        on demand, or ``None`` for ``0..n-1``. ``know[a]`` is ``rel[a]`` (the same object)
        unless agent ``a`` has a separate knowledge relation.
        """
        model = cls.__new__(cls)
        cls._init(model, names, atoms, val, agents, rel, know, designated)
        return model

    @classmethod
    def from_cube(
        cls,
        cube: Cube,
        atoms: tuple[str, ...],
        agents: tuple[str, ...],
        designated_codes: np.ndarray,
    ) -> ExplicitModel:
        """A model from observables: the live codes of ``cube`` are its worlds (and names)."""
        model = cls.__new__(cls)
        cls._init(
            model, _code_names(cube), atoms, None, agents, None, None, None, cube, designated_codes
        )
        return model

    def cube_submodel(self, bits: np.ndarray) -> ExplicitModel:
        """The restriction to the live codes of ``bits``, for evaluation only."""
        empty = np.zeros(0, dtype=np.intp)
        return type(self).from_cube(self._cube.restrict(bits), self._atoms, self._agents, empty)

    def _materialize(self) -> None:
        """Build the compact arrays of a cube model (valuation matrix, partitions)."""
        cube = self._cube
        self.require_arrays()
        codes = cube.codes
        shifts = np.arange(cube.n_bits - 1, -1, -1, dtype=np.intp)
        self._val_ = _read_only(np.asfortranarray(((codes[:, None] >> shifts) & 1).astype(bool)))
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
        self._designated_ = _read_only(np.searchsorted(codes, self._designated_codes))

    def arrays_bytes(self) -> int:
        """Bytes the compact arrays of a cube model would take (0 once they exist)."""
        if self._cube is None or self._val_ is not None:
            return 0
        # codes, valuation matrix, one label per world and agent, a sort's scratch
        return self._cube.count() * (8 + self._cube.n_bits + 8 * len(self._agents) + 16)

    def require_arrays(self) -> None:
        """Refuse to build the compact arrays of a cube model beyond the memory budget."""
        needed = self.arrays_bytes()
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
            found = np.searchsorted(self._cube.codes, self._designated_codes)
            self._designated_ = _read_only(found)
        return self._designated_

    @property
    def valuation(self) -> np.ndarray:
        """The valuation matrix, worlds x :attr:`atoms` (read-only)."""
        return self._val

    @property
    def belief_relations(self) -> Mapping[str, Relation]:
        """Agent -> belief relation (read-only mapping)."""
        return MappingProxyType(self._rel)

    @property
    def knowledge_relations(self) -> Mapping[str, Relation]:
        """Agent -> knowledge relation; the same object as the belief relation unless the
        agent has a separate one (read-only mapping)."""
        return MappingProxyType(self._know)

    @property
    def cube(self) -> Cube | None:
        """The bitset of live valuations of a model from observables, else ``None``."""
        return self._cube

    @property
    def designated_codes(self) -> np.ndarray | None:
        """The codes of the designated worlds of a model from observables, else ``None``."""
        return self._designated_codes

    @property
    def lazy_names(self) -> tuple | Callable[[], tuple] | None:
        """The world names as stored: a tuple, a callable that lists them, or ``None``
        for ``0..n-1`` (what :meth:`from_arrays` takes; nothing is listed)."""
        return self._names

    @property
    def memo(self) -> dict[Any, Any]:
        """Truth sets memoised by the evaluator, by formula (they depend on the worlds
        and relations only, so :meth:`repoint` shares them)."""
        return self._memo

    @property
    def derived(self) -> dict[Any, Any]:
        """Structures derived by algorithms and cached with the model (submodels,
        products, components), by key."""
        return self._derived

    @property
    def designated_positions(self) -> np.ndarray:
        """The positions in :attr:`worlds` of the designated worlds (a read-only array)."""
        return self._designated

    @classmethod
    def from_partitions(
        cls,
        worlds: Sequence[World],
        valuation: Mapping[World, Iterable[str]],
        partitions: Mapping[str, Iterable[Iterable[World]]],
        designated: World | Iterable[World],
    ) -> ExplicitModel:
        """Build an S5 model from each agent's partition of the worlds into blocks.

        Examples
        --------
        >>> from epistemica.del_ import KripkeModel
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
        >>> from epistemica.del_ import KripkeModel
        >>> m = KripkeModel.from_observables(["p", "q"], {"a": []}).announce("p | q")
        >>> m.worlds_at([0, 2])
        (1, 3)
        """
        indices = np.asarray(list(indices), dtype=np.intp)
        if self.names_are_codes():
            return tuple(int(c) for c in self._cube.codes[indices])
        names = self.worlds
        return tuple(names[i] for i in indices)

    @property
    def designated(self) -> tuple:
        """The designated worlds' names."""
        if self.names_are_codes():  # no need to list every world
            return tuple(int(c) for c in self._designated_codes)
        names = self.worlds
        return tuple(names[i] for i in self._designated)

    def valuation_of(self, world: World) -> frozenset[str]:
        """The atoms true at ``world``."""
        if self.names_are_codes():  # a world's name is its valuation's code
            code = self._names.code_of(world)
            n = len(self._atoms)
            return frozenset(a for j, a in enumerate(self._atoms) if code >> (n - 1 - j) & 1)
        i = self.index_of(world)
        return frozenset(a for a, t in zip(self._atoms, self._val[i], strict=True) if t)

    def successors(self, agent: str, world: World, relation: str = "belief") -> tuple:
        """The worlds ``agent`` considers possible at ``world``."""
        mask = np.zeros(self.n_worlds, dtype=bool)
        mask[self.index_of(world)] = True
        hit = self.relation(agent, relation).successors_of(mask)
        names = self.worlds
        return tuple(names[i] for i in np.flatnonzero(hit))

    def is_s5(self, agent: str, relation: str = "belief") -> bool:
        """Whether the agent's relation is an equivalence (reflexive, symmetric, transitive)."""
        return self.relation(agent, relation).is_equivalence()

    def is_kd45(self, agent: str, relation: str = "belief") -> bool:
        """Whether the agent's relation is serial, transitive and Euclidean."""
        return self.relation(agent, relation).is_kd45()

    def has_separate_knowledge(self) -> bool:
        """Whether some agent's knowledge relation differs from its belief relation."""
        return any(self._know[a] is not self._rel[a] for a in self._agents)

    def restrict(self, mask: np.ndarray) -> ExplicitModel:
        """The submodel on the worlds of ``mask`` (designated worlds outside are dropped)."""
        mask = np.asarray(mask, dtype=bool)
        kept_points = self._designated[mask[self._designated]]
        if not len(kept_points):
            raise InvalidArgumentError("the restriction removes every designated world")
        # New index of a kept world = number of kept worlds before it.
        designated = np.cumsum(mask[: kept_points[-1] + 1])[kept_points] - 1
        return self.restricted(mask, designated)

    def restricted(self, mask: np.ndarray, designated: np.ndarray) -> ExplicitModel:
        """The submodel on ``mask`` with the given (new) designated indices, possibly none."""
        rel = {a: r.restrict(mask) for a, r in self._rel.items()}
        know = {a: rel[a] if k is self._rel[a] else k.restrict(mask) for a, k in self._know.items()}
        return type(self).from_arrays(
            _pick_names(self._names, mask),
            self._atoms,
            self._val[mask],
            self._agents,
            rel,
            know,
            designated,
        )

    def repoint(self, designated: World | Iterable[World]) -> ExplicitModel:
        """The same model with other designated worlds.

        The result shares this model's memoised truth sets (they do not depend on the
        designated worlds), so re-pointing for an agent's perspective is cheap.

        Examples
        --------
        >>> from epistemica.del_ import KripkeModel
        >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
        >>> m.holds("p"), m.repoint(m.worlds).holds("p")
        (True, False)
        """
        points = world_positions(designated, self.world_index())
        if not points:
            raise InvalidArgumentError("repoint needs at least one world")
        positions = np.unique(np.array(points, dtype=np.intp))
        codes = None if self._cube is None else self._cube.codes[positions]
        cls = type(self)
        model = cls.__new__(cls)
        # the same arrays and caches: truth sets and derived structures do not depend on
        # the designated worlds
        cls._init(
            model,
            self._names,
            self._atoms,
            self._val_,
            self._agents,
            self._rel_,
            self._know_,
            positions,
            self._cube,
            codes,
            memo=self._memo,
            derived=self._derived,
        )
        return model

    def __repr__(self) -> str:
        return (
            f"<{type(self).__name__}: {self.n_worlds} worlds, agents {list(self._agents)}, "
            f"{len(self._designated)} designated>"
        )

    # -- internals ----------------------------------------------------------------------

    def relation(self, agent: str, kind: str = "belief") -> Relation:
        """The agent's ``"belief"`` or ``"knowledge"`` relation."""
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

    def world_index(self) -> dict[World, int]:
        index = self._derived.get("index")
        if index is None:
            index = self._derived["index"] = {w: i for i, w in enumerate(self.worlds)}
        return index

    def index_of(self, world: World) -> int:
        return lookup_world(self.world_index(), world, "argument")

    def names_are_codes(self) -> bool:
        """Whether world names are the live codes of this model's cube (in order)."""
        names = self._names
        return (
            isinstance(names, _CodeNames)
            and names.cube is self._cube
            and self._designated_codes is not None
        )

    def atom_column(self, atom: str) -> int | None:
        return self._column.get(atom)


def _read_only(array: np.ndarray) -> np.ndarray:
    """``array``, made read-only: models are immutable, and their arrays are shared."""
    array.setflags(write=False)
    return array


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
