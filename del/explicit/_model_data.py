"""The stored arrays of an explicit model, and how a model from observables builds them.

:class:`ModelData` is the storage half of :class:`~._model.ExplicitModel`: the atoms and
agents, the valuation matrix, the belief and knowledge relations, the designated
positions and the two caches (``memo``, ``derived``), read through properties, with the
constructors that algorithms call (:meth:`ModelData.from_arrays`,
:meth:`ModelData.from_cube`). A model from observables keeps a bitset
:class:`~._cube.Cube` of its live valuations, names its worlds by their codes, and lists
its arrays only when an operation reads them (within the memory budget).
:class:`~._model.ExplicitModel` adds the worlds' names and the derived models.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import Any

import numpy as np

from epistemica.del_ import budget
from epistemica.del_.errors import InvalidArgumentError, ModelError
from epistemica.del_.explicit._cube import Cube
from epistemica.del_.explicit._model_input import World
from epistemica.del_.explicit.relations import Partition, Relation

__all__ = ["ModelData", "read_only"]


class ModelData:
    """The arrays of a multi-agent Kripke model (see the module docstring)."""

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
        self._val_ = None if val is None else read_only(np.asfortranarray(val, dtype=bool))
        self._agents = agents
        self._rel_ = rel
        self._know_ = know
        self._designated_ = None if designated is None else read_only(_sorted_unique(designated))
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
    ) -> ModelData:
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
    ) -> ModelData:
        """A model from observables: the live codes of ``cube`` are its worlds (and names)."""
        model = cls.__new__(cls)
        cls._init(
            model, _code_names(cube), atoms, None, agents, None, None, None, cube, designated_codes
        )
        return model

    def cube_submodel(self, bits: np.ndarray) -> ModelData:
        """The restriction to the live codes of ``bits``, for evaluation only."""
        empty = np.zeros(0, dtype=np.intp)
        return type(self).from_cube(self._cube.restrict(bits), self._atoms, self._agents, empty)

    def _materialize(self) -> None:
        """Build the compact arrays of a cube model (valuation matrix, partitions)."""
        cube = self._cube
        self.require_arrays()
        codes = cube.codes
        shifts = np.arange(cube.n_bits - 1, -1, -1, dtype=np.intp)
        self._val_ = read_only(np.asfortranarray(((codes[:, None] >> shifts) & 1).astype(bool)))
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
        self._designated_ = read_only(np.searchsorted(codes, self._designated_codes))

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
            self._designated_ = read_only(found)
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

    def has_separate_knowledge(self) -> bool:
        """Whether some agent's knowledge relation differs from its belief relation."""
        return any(self._know[a] is not self._rel[a] for a in self._agents)

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


def _sorted_unique(values) -> np.ndarray:
    """``np.unique(values)`` without loading ``numpy.ma`` (which ``np.unique`` imports on
    first use, about 10 ms of a ``check`` that needs nothing else from it).

    >>> _sorted_unique([3, 1, 3, 2]).tolist()
    [1, 2, 3]
    """
    array = np.sort(np.asarray(values).ravel())
    if array.size < 2:
        return array
    return array[np.concatenate(([True], array[1:] != array[:-1]))]


def read_only(array: np.ndarray) -> np.ndarray:
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


def _code_names(cube: Cube) -> Callable[[], tuple]:
    return _CodeNames(cube)
