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

The arrays, bitsets and caches are stored by the base class
:class:`~._model_data.ModelData` (with the construction of a cube model's arrays);
this module adds the worlds' names and the models derived by restriction and re-pointing.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._arguments import column_of
from epistemica.del_.explicit._model_data import ModelData
from epistemica.del_.explicit._model_input import World, lookup_world, model_arrays, world_positions

__all__ = ["MAX_ENUMERATED_ATOMS", "ExplicitModel", "column_of"]

# Enumerating valuations beyond this many atoms would not fit in memory.
MAX_ENUMERATED_ATOMS = 26


class ExplicitModel(ModelData):
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

    def world_index(self) -> dict[World, int]:
        index = self._derived.get("index")
        if index is None:
            index = self._derived["index"] = {w: i for i, w in enumerate(self.worlds)}
        return index

    def index_of(self, world: World) -> int:
        return lookup_world(self.world_index(), world, "argument")


def _pick_names(source: tuple | Callable[[], tuple] | None, mask: np.ndarray) -> Callable:
    """Names of a restriction, computed only when asked for (it keeps no parent model alive)."""

    def names() -> tuple:
        keep = np.flatnonzero(mask)
        if source is None:
            return tuple(int(i) for i in keep)
        full = source() if callable(source) else source
        return tuple(full[i] for i in keep)

    return names
