"""The public model classes of the two backends, with their convenience methods.

:class:`KripkeModel` is the explicit backend's data (:class:`~.explicit._model.ExplicitModel`)
plus methods that call the algorithms of :mod:`epistemica.del_.explicit` (checking,
announcements, product update, contraction, export) and the conversion to the symbolic
backend; :class:`KnowledgeStructure` is the symbolic backend's
(:class:`~.symbolic.structure.SymbolicModel`) plus the conversion back. The algorithms take
and return models through the data classes' interface and construct ``type(model)``, so
they never import this module: it sits above both backends, and the import graph of
``del/`` points one way (``tests/test_import_graph.py``).

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

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from epistemica.del_ import budget
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit import bisimulation, checker, export
from epistemica.del_.explicit._cube import Cube
from epistemica.del_.explicit._model import MAX_ENUMERATED_ATOMS, ExplicitModel, column_of
from epistemica.del_.explicit.action import ActionModel, applicable_in_some, product_update
from epistemica.del_.language.formula import Formula, atom_name
from epistemica.del_.language.parser import as_formula
from epistemica.del_.symbolic import convert
from epistemica.del_.symbolic.structure import SymbolicModel

if TYPE_CHECKING:
    import networkx as nx

__all__ = ["KnowledgeStructure", "KripkeModel"]


def _hidden_bits(observes: Mapping[str, Iterable[str]], column: dict[str, int]) -> dict:
    """Agent -> the bits of a world's code it does not see (the first atom is the most
    significant bit)."""
    n_atoms = len(column)
    hidden = {}
    for agent, seen in observes.items():
        visible = {column_of(column, a, f"observes[{agent!r}]") for a in seen}
        hidden[str(agent)] = tuple(n_atoms - 1 - j for j in range(n_atoms) if j not in visible)
    return hidden


def _designated_code(cube: Cube, column: dict[str, int], designated: Iterable[str]):
    """The one code whose true atoms are ``designated``, checked against the law."""
    code = 0
    for a in designated:
        code |= 1 << (len(column) - 1 - column_of(column, a, "designated"))
    if not cube.test(cube.alive, np.array([code]))[0]:
        raise InvalidArgumentError(
            "the designated valuation violates the law",
            hint="choose an actual world that satisfies the law",
        )
    return np.array([code], dtype=np.intp)


class KripkeModel(ExplicitModel):
    """A multi-agent Kripke model, possibly multi-pointed: an immutable value.

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
    atoms : iterable of str, optional
        The model's vocabulary, declared: atoms that no world makes true are false
        everywhere, and the valuation may name only these. By default the vocabulary is
        the atoms the valuation names. A formula naming an atom outside the vocabulary is
        refused (``InvalidArgumentError``: "unknown atom"), on this backend and on the
        symbolic one alike.

    Raises
    ------
    InvalidArgumentError
        If an argument has the wrong type, or an atom name is not one a formula could
        write (``"p q"``, ``""``).
    ModelError
        If a pair, valuation entry or designated world names an unknown world, or the
        valuation names an undeclared atom.
    """

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
        atom_list = tuple(atom_name(a, "atoms") for a in atoms)
        if len(set(atom_list)) != len(atom_list):
            raise InvalidArgumentError("atoms must be distinct", hint="remove the repeated atom")
        if len(atom_list) > MAX_ENUMERATED_ATOMS:
            raise InvalidArgumentError(
                f"{len(atom_list)} atoms would give 2^{len(atom_list)} valuations to enumerate",
                hint=f"use at most {MAX_ENUMERATED_ATOMS} atoms, or build the worlds explicitly",
            )
        n_atoms = len(atom_list)
        column = {a: j for j, a in enumerate(atom_list)}
        hidden = _hidden_bits(observes, column)
        with budget.budget_scope(memory_budget):
            # the live set, the law's truth set and a few atoms' bitsets
            budget.require(4 * max(8, (1 << n_atoms) // 8), f"the {2**n_atoms:,} valuations")
            cube = Cube.full(n_atoms, hidden)
        agents = tuple(hidden)
        if law is not None:
            tree = as_formula(law)
            checker.propositional_mask(tree, np.zeros((0, n_atoms), dtype=bool), column)
            everything = cls.from_cube(cube, atom_list, agents, np.zeros(0, dtype=np.intp))
            cube = cube.restrict(checker.evaluate_bits(everything, tree))
            if not cube.count():
                raise InvalidArgumentError(
                    "no valuation satisfies the law", hint="the law is a contradiction"
                )
        points = cube.codes if designated is None else _designated_code(cube, column, designated)
        return cls.from_cube(cube, atom_list, agents, points)

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
        if self.names_are_codes():  # names are codes: list no other world
            return frozenset(int(c) for c in self.cube.codes[mask])
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
        tree = as_formula(formula)
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
        tree = as_formula(formula)
        with budget.budget_scope(memory_budget):
            cube, codes = self.cube, self.designated_codes
            if cube is not None and not cube.sparse():
                bits = checker.evaluate_bits(self, tree)
                kept = codes[cube.test(bits, codes)]
                if len(kept):
                    return self.from_cube(cube.restrict(bits), self.atoms, self.agents, kept)
            else:
                mask = checker.evaluate(self, tree, None)
                if mask[self.designated_positions].any():
                    return self.restrict(mask)
        raise InvalidArgumentError(
            f"cannot announce {tree}: it is false at every designated world",
            hint="only true formulas can be announced; check it with holds() first",
        )

    def applicable_in_some(self, action: ActionModel) -> bool:
        """Whether some designated event is executable at *some* designated world, i.e.
        whether :meth:`update` succeeds. (A plan step needs more: executable at *every*
        designated world, :func:`~epistemica.del_.planning.planner.applicable_in_all`.)"""
        return applicable_in_some(self, action)

    def update(self, action: ActionModel) -> KripkeModel:
        """The product update of this model with ``action``.

        World names become ``(world, event)`` pairs. Raises
        :class:`~epistemica.del_.errors.InvalidArgumentError` when no designated event is
        executable at a designated world.
        """
        return product_update(self, action)

    def minimize(self) -> KripkeModel:
        """The bisimulation contraction of the submodel generated by the designated worlds."""
        return bisimulation.minimize(self)

    def to_symbolic(self, atoms: Iterable[str] | None = None) -> KnowledgeStructure:
        """This model as a :class:`KnowledgeStructure` (BDDs).

        ``atoms`` declares further atoms, false everywhere (see
        :meth:`KnowledgeStructure.from_kripke`).

        Examples
        --------
        >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
        >>> m.to_symbolic().holds("p & ~K[a] p")
        True
        """
        return KnowledgeStructure.from_kripke(self, atoms)

    def to_networkx(self) -> nx.MultiDiGraph:
        """The model as a :class:`networkx.MultiDiGraph` (see :func:`.export.to_networkx`)."""
        return export.to_networkx(self)

    def to_dot(self) -> str:
        """The model in Graphviz DOT (see :func:`.export.to_dot`)."""
        return export.to_dot(self)


class KnowledgeStructure(SymbolicModel):
    __doc__ = SymbolicModel.__doc__

    @classmethod
    def from_kripke(
        cls, model: ExplicitModel, atoms: Iterable[str] | None = None
    ) -> KnowledgeStructure:
        """The structure of a Kripke model, one state per world.

        ``atoms`` declares atoms besides the model's own (false everywhere), such as a
        spec's atoms that no world makes true. See :func:`.symbolic.convert.kripke_parts`.
        """
        return cls(*convert.kripke_parts(model, atoms))

    def to_kripke(self, max_worlds: int | None = None) -> KripkeModel:
        """The Kripke model of this structure (see :func:`.symbolic.convert.to_kripke`)."""
        limit = convert.MAX_KRIPKE_WORLDS if max_worlds is None else max_worlds
        return convert.to_kripke(self, limit, KripkeModel)
