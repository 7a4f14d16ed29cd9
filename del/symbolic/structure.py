"""Knowledge structures: the symbolic counterpart of :class:`~epistemica.del_.KripkeModel`.

:class:`SymbolicModel` is the data and the algorithms of the symbolic backend; the public
class :class:`~epistemica.del_.KnowledgeStructure` (in :mod:`epistemica.del_.models`) adds
the conversions to and from Kripke models.

A knowledge structure (van Benthem, van Eijck, Gattinger and Su, "Symbolic model checking
for dynamic epistemic logic: S5 and beyond", J. Logic Comput. 2018) is a vocabulary of
Boolean variables, a *state law* (a BDD: the states are the assignments satisfying it), and
per agent a relation between states: the variables it observes (S5) or a BDD over the
variables and their primed copies (belief, or any relation). Formulas are evaluated to BDDs
by quantification and fixed points, never by listing states, so 100 muddy children
(2^100 states) are checked in seconds.

Each agent has a belief relation (``B``) and a knowledge relation (``K``), the same object
unless an action model made them differ, exactly as in a Kripke model.

Examples
--------
>>> from epistemica.del_ import KnowledgeStructure
>>> s = KnowledgeStructure.from_observables(
...     ["m1", "m2", "m3"],
...     {"c1": ["m2", "m3"], "c2": ["m1", "m3"], "c3": ["m1", "m2"]},
...     designated=["m1", "m2"])
>>> s.n_worlds
8
>>> s.holds("~Kw[c1] m1 & K[c3] (m1 & m2)")
True
>>> s.announce("m1 | m2 | m3").n_worlds
7
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._model import column_of
from epistemica.del_.language.formula import (
    And,
    Atom,
    Bottom,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    Top,
    atom_name,
)
from epistemica.del_.language.parser import as_formula
from epistemica.del_.language.walk import iter_nodes
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic.evaluate import evaluate, propositional
from epistemica.del_.symbolic.relations import Observes, Relation
from epistemica.del_.symbolic.transform import product

if TYPE_CHECKING:
    from epistemica.del_.explicit.action import ActionModel
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = ["SymbolicModel"]

_PROPOSITIONAL = (Atom, Top, Bottom, Not, And, Or, Implies, Iff)


class SymbolicModel:
    """A multi-agent knowledge (or belief) structure with designated states.

    Build one with :meth:`from_observables` or :meth:`KripkeModel.to_symbolic
    <epistemica.del_.KripkeModel.to_symbolic>`; it is an immutable value whose updates
    (:meth:`announce`, :meth:`update`) return new structures. The constructor takes the
    parts directly (for the translations and transformers of this package).

    Parameters
    ----------
    atoms : mapping
        Atom -> the slot of the state variable holding its (current) value.
    slots : sequence of int
        Every state variable (atoms, event bits, values before an update, labels).
    law : BDDFunction
        The state law over ``slots``.
    agents : sequence of str
    belief, knowledge : mapping
        Agent -> :class:`~.relations.Observes` or :class:`~.relations.Arrows`.
    designated : BDDFunction
        The designated states (intersected with the law).
    """

    def __init__(
        self,
        atoms: Mapping[str, int],
        slots: Sequence[int],
        law: BDDFunction,
        agents: Sequence[str],
        belief: Mapping[str, Relation],
        knowledge: Mapping[str, Relation],
        designated: BDDFunction,
    ) -> None:
        self._atoms = dict(atoms)
        self._slots = tuple(slots)
        _bdd.reserve(self._slots)  # the structure's variables exist before it counts
        self._law = law
        self._agents = tuple(agents)
        self._belief = dict(belief)
        self._knowledge = dict(knowledge)
        self._designated = designated & law
        self._memo: dict[Any, BDDFunction] = {}
        self._derived: dict[Any, Any] = {}

    # -- construction -------------------------------------------------------------------

    @classmethod
    def from_observables(
        cls,
        atoms: Sequence[str],
        observes: Mapping[str, Iterable[str]],
        law: Formula | str | None = None,
        designated: Iterable[str] | None = None,
    ) -> SymbolicModel:
        """The S5 structure in which each agent sees the truth of some atoms.

        The same arguments as :meth:`KripkeModel.from_observables
        <epistemica.del_.KripkeModel.from_observables>`, with no limit on the number of
        atoms: the states are the valuations satisfying the propositional ``law``; agent
        ``a`` cannot tell apart states that agree on ``observes[a]``; ``designated`` lists
        the atoms true in the actual state (``None`` designates every state).

        Examples
        --------
        >>> atoms = [f"m{i}" for i in range(1, 61)]
        >>> from epistemica.del_ import KnowledgeStructure
        >>> s = KnowledgeStructure.from_observables(
        ...     atoms, {f"c{i}": atoms[:i - 1] + atoms[i:] for i in range(1, 61)},
        ...     designated=atoms)
        >>> s.n_worlds == 2 ** 60
        True
        >>> s.holds("E[c1, c2] (m1 | m2) & ~C[c1, c2] (m1 | m2)")
        True
        """
        names = tuple(atom_name(a, "atoms") for a in atoms)
        if len(set(names)) != len(names):
            raise InvalidArgumentError("atoms must be distinct", hint="remove the repeated atom")
        slot = {a: j for j, a in enumerate(names)}
        relations: dict[str, Relation] = {}
        for agent, seen in observes.items():
            where = f"observes[{agent!r}]"
            relations[str(agent)] = Observes(frozenset(_slot_of(slot, a, where) for a in seen))
        state_law = _bdd.true()
        if law is not None:
            state_law = _propositional(as_formula(law), slot, "the law")
            if not state_law.satisfiable():
                raise InvalidArgumentError(
                    "no valuation satisfies the law", hint="the law is a contradiction"
                )
        if designated is None:
            points = state_law
        else:
            true_slots = {_slot_of(slot, a, "designated") for a in designated}
            points = _bdd.true()
            for j in range(len(names) - 1, -1, -1):
                points = (_bdd.var(j) if j in true_slots else ~_bdd.var(j)) & points
            if not (points & state_law).satisfiable():
                raise InvalidArgumentError(
                    "the designated valuation violates the law",
                    hint="choose an actual world that satisfies the law",
                )
        slots = range(len(names))
        return cls(slot, slots, state_law, tuple(relations), relations, relations, points)

    # -- inspection ---------------------------------------------------------------------

    @property
    def agents(self) -> tuple[str, ...]:
        """The agents, in declaration order."""
        return self._agents

    @property
    def atoms(self) -> tuple[str, ...]:
        """The declared atoms (including those an action's postcondition introduced)."""
        return tuple(self._atoms)

    @property
    def n_worlds(self) -> int:
        """The number of states (assignments satisfying the law)."""
        return self._count(self._law)

    @property
    def n_variables(self) -> int:
        """The number of Boolean state variables (atoms, event and bookkeeping bits)."""
        return len(self._slots)

    @property
    def atom_slots(self) -> Mapping[str, int]:
        """Atom -> the slot of the state variable holding its current value."""
        return MappingProxyType(self._atoms)

    @property
    def slots(self) -> tuple[int, ...]:
        """Every state variable's slot."""
        return self._slots

    @property
    def law(self) -> BDDFunction:
        """The state law: its satisfying assignments are the states."""
        return self._law

    @property
    def designated_states(self) -> BDDFunction:
        """The designated states (within the law)."""
        return self._designated

    @property
    def belief_relations(self) -> Mapping[str, Relation]:
        """Agent -> belief relation (read-only mapping)."""
        return MappingProxyType(self._belief)

    @property
    def knowledge_relations(self) -> Mapping[str, Relation]:
        """Agent -> knowledge relation (read-only mapping)."""
        return MappingProxyType(self._knowledge)

    @property
    def memo(self) -> dict[Any, BDDFunction]:
        """Truth sets memoised by the evaluator, by formula."""
        return self._memo

    @property
    def derived(self) -> dict[Any, Any]:
        """Structures derived and cached with this one (submodels, products)."""
        return self._derived

    def has_separate_knowledge(self) -> bool:
        """Whether some agent's knowledge relation differs from its belief relation."""
        return any(self._knowledge[a] is not self._belief[a] for a in self._agents)

    def __repr__(self) -> str:
        return (
            f"<{type(self).__name__}: {len(self._atoms)} atoms, {len(self._slots)} variables, "
            f"agents {list(self._agents)}, law of {self._law.node_count()} BDD nodes>"
        )

    # -- model checking -----------------------------------------------------------------

    def truth(
        self, formula: Formula | str, actions: Mapping[str, ActionModel] | None = None
    ) -> BDDFunction:
        """The BDD of the states where ``formula`` holds (meaningful on the law)."""
        return evaluate(self, as_formula(formula), actions)

    def holds(
        self, formula: Formula | str, actions: Mapping[str, ActionModel] | None = None
    ) -> bool:
        """Whether ``formula`` holds at every designated state.

        ``actions`` maps names to action models and resolves ``[ACT] g``, as in
        :meth:`KripkeModel.holds <epistemica.del_.KripkeModel.holds>`.

        Raises
        ------
        InvalidArgumentError
            If the formula names an atom or agent the structure does not declare.
        """
        return not (self._designated & ~self.truth(formula, actions)).satisfiable()

    def count(
        self, formula: Formula | str, actions: Mapping[str, ActionModel] | None = None
    ) -> int:
        """The number of states where ``formula`` holds."""
        return self._count(self._law & self.truth(formula, actions))

    def count_designated(
        self, formula: Formula | str | None = None, actions: Mapping[str, ActionModel] | None = None
    ) -> int:
        """The number of designated states (where ``formula`` holds, if given)."""
        points = self._designated
        if formula is not None:
            points = points & self.truth(formula, actions)
        return self._count(points)

    # -- updates ------------------------------------------------------------------------

    def announce(self, formula: Formula | str) -> SymbolicModel:
        """The structure after the truthful public announcement of ``formula``.

        Raises
        ------
        InvalidArgumentError
            If ``formula`` is false at every designated state.
        """
        tree = as_formula(formula)
        announced = self.truth(tree)
        if not (self._designated & announced).satisfiable():
            raise InvalidArgumentError(
                f"cannot announce {tree}: it is false at every designated world",
                hint="only true formulas can be announced; check it with holds() first",
            )
        return self.restricted(announced, self._designated & announced)

    def applicable_in_some(self, action: ActionModel) -> bool:
        """Whether some designated event's precondition holds at some designated state
        (whether :meth:`update` succeeds)."""
        return product(self, action).structure.designated_states.satisfiable()

    def update(self, action: ActionModel) -> SymbolicModel:
        """The product update with ``action`` (a knowledge/belief transformer).

        Raises
        ------
        InvalidArgumentError
            If no designated event is executable at a designated state.

        Examples
        --------
        >>> from epistemica.del_.explicit.action import semi_private_sensing
        >>> from epistemica.del_ import KnowledgeStructure
        >>> s = KnowledgeStructure.from_observables(
        ...     ["heads"], {"a": [], "b": []}, designated=["heads"])
        >>> after = s.update(semi_private_sensing("heads", ["b"], ["a", "b"]))
        >>> after.holds("Kw[b] heads & ~Kw[a] heads & K[a] Kw[b] heads")
        True
        """
        result = product(self, action).structure
        if not result.designated_states.satisfiable():
            raise InvalidArgumentError(
                "the action is not executable: no designated event's precondition holds at a "
                "designated world",
                hint="check applicable_in_some(action) before updating",
            )
        return result

    # -- internals ----------------------------------------------------------------------

    def _count(self, f: BDDFunction) -> int:
        return _bdd.count(f, self._slots)

    def restricted(self, keep: BDDFunction, designated: BDDFunction) -> SymbolicModel:
        """The structure with the law narrowed to ``keep`` and these designated states."""
        return type(self)(
            self._atoms,
            self._slots,
            self._law & keep,
            self._agents,
            self._belief,
            self._knowledge,
            designated,
        )

    def atom_slot(self, atom: Atom) -> int:
        """The slot holding ``atom``'s current value."""
        return _slot_of(self._atoms, atom.key, "the formula")

    def relation(self, agent: str, kind: str = "belief") -> Relation:
        """The agent's ``"belief"`` or ``"knowledge"`` relation."""
        table = self._knowledge if kind == "knowledge" else self._belief
        found = table.get(agent)
        if found is None:
            raise InvalidArgumentError(
                f"unknown agent {agent!r}", hint=f"the model's agents: {', '.join(self._agents)}"
            )
        return found


def _slot_of(slots: Mapping[str, int], atom: str, where: str) -> int:
    return column_of(slots, atom, where)


def _propositional(f: Formula, slots: Mapping[str, int], where: str) -> BDDFunction:
    if not all(isinstance(g, _PROPOSITIONAL) for g in iter_nodes(f)):
        raise InvalidArgumentError(
            f"expected a propositional formula in {where}, found {f}",
            hint="laws constrain valuations only; they cannot mention K, B, C, ...",
        )
    return propositional(f, lambda atom: _bdd.var(_slot_of(slots, atom.key, where)))
