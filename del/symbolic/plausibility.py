"""Plausibility models on BDDs: a knowledge structure with rank levels per agent.

A :class:`PlausibilityStructure` is a vocabulary of state variables, a state law (the
states are the valuations satisfying it), per agent the atoms it observes (its information
cell is the set of lawful states that agree with the actual one on them) and a list of
*rank levels*: disjoint BDDs covering the law, the most plausible first. Agent ``a`` finds
``v`` at least as plausible as ``w`` when they share a cell and ``v``'s level is not after
``w``'s. No state is ever listed, so the size of a structure is that of its BDDs.

The semantics is :mod:`~epistemica.del_.language.plausibility_semantics`, shared with the
explicit :class:`~epistemica.del_.explicit.plausibility.PlausibilityModel`; this module
gives the operations on BDDs:

- ``K[a] f``: ``forall hidden_a (law -> f)``, the hidden variables being those ``a`` does
  not observe;
- the best ``c``-states of every cell: walk the levels in order, keeping the states of the
  level where the cell has no ``c``-state at an earlier level (``exists hidden_a``);
- ``B[a | c] f`` is ``K[a] (best_a(c) -> f)``; ``Sb[a] f`` is, per level ``i``,
  ``level_i & K[a] (levels_0..i -> f)``;
- announcements conjoin the law; a radical upgrade with ``c`` splits every level into its
  ``c`` and ``~c`` parts and puts all the ``c`` parts first; a conservative upgrade puts
  ``best_a(c)`` first and removes it from the other levels. Empty levels are dropped, so
  level ``i`` is the explicit backend's dense rank ``i``.

Examples
--------
>>> s = PlausibilityStructure.from_levels(["h"], {"alice": ["~h", "h"]}, designated=["h"])
>>> s.holds("B[alice] ~h & [^^h] B[alice] h & [^h] B[alice] h")
True
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.plausibility import PlausibilityModel
from epistemica.del_.language.formula import Atom, Formula, atom_name
from epistemica.del_.language.parser import as_formula
from epistemica.del_.language.plausibility_semantics import evaluate_plausibility
from epistemica.del_.symbolic import _bdd
from epistemica.del_.symbolic.evaluate import propositional

if TYPE_CHECKING:
    from epistemica.del_.symbolic._bdd import BDDFunction

__all__ = ["PlausibilityStructure"]


class PlausibilityStructure:
    """A multi-agent plausibility structure: an immutable value.

    Parameters
    ----------
    atoms : sequence of str
        The vocabulary; atom ``j`` is the state variable of slot ``j``.
    law : BDDFunction
        The states.
    observes : mapping
        Agent -> the atoms it observes.
    levels : mapping
        Agent -> BDDs of its rank levels, most plausible first (intersected with the law;
        empty ones dropped). A lawful state in none of them is refused.
    designated : BDDFunction
        The actual states.
    """

    def __init__(
        self,
        atoms: Sequence[str],
        law: BDDFunction,
        observes: Mapping[str, Iterable[str]],
        levels: Mapping[str, Sequence[BDDFunction]],
        designated: BDDFunction,
    ) -> None:
        self.atoms = tuple(atom_name(a, "atoms") for a in atoms)
        self.slot = {a: j for j, a in enumerate(self.atoms)}
        _bdd.reserve(range(len(self.atoms)))
        self.law = law
        self.agents = tuple(str(a) for a in observes)
        self.observes = {
            str(a): tuple(atom_name(o, "observes") for o in observes[a]) for a in observes
        }
        self.levels: dict[str, tuple[BDDFunction, ...]] = {}
        for agent in self.agents:
            kept = tuple(g for level in levels[agent] if (g := level & law).satisfiable())
            covered = _bdd.false()
            for g in kept:
                covered |= g
            if covered != law:
                raise InvalidArgumentError(
                    f"the rank levels of agent {agent!r} do not cover every state",
                    hint="end the list of levels with 'true'",
                )
            self.levels[agent] = kept
        self.designated = designated & law
        self.memo: dict[Formula, BDDFunction] = {}
        self.derived: dict[tuple[str, Formula], PlausibilityStructure] = {}
        self._hidden: dict[str, BDDFunction] = {}

    @classmethod
    def from_levels(
        cls,
        atoms: Sequence[str],
        levels: Mapping[str, Sequence[Formula | str]],
        observes: Mapping[str, Iterable[str]] | None = None,
        law: Formula | str | None = None,
        designated: Iterable[str] | None = None,
    ) -> PlausibilityStructure:
        """The arguments of :meth:`PlausibilityModel.from_levels
        <epistemica.del_.explicit.plausibility.PlausibilityModel.from_levels>`, with no limit
        on the number of atoms (a world satisfying no level comes last)."""
        names = tuple(atom_name(a, "atoms") for a in atoms)
        slot = {a: j for j, a in enumerate(names)}

        def bdd(f: Formula | str) -> BDDFunction:
            return propositional(as_formula(f), lambda atom: _bdd.var(_slot(slot, atom.key)))

        state_law = _bdd.true() if law is None else bdd(law)
        if not state_law.satisfiable():
            raise InvalidArgumentError("no valuation satisfies the law", hint="relax it")
        ranked: dict[str, list[BDDFunction]] = {}
        for agent, formulas in levels.items():
            rest = _bdd.true()
            ranked[str(agent)] = []
            for f in formulas:
                ranked[str(agent)].append(rest & bdd(f))
                rest &= ~bdd(f)
            ranked[str(agent)].append(rest)
        actual = state_law
        if designated is not None:
            true_slots = {_slot(slot, a, "designated") for a in designated}
            actual = _bdd.true()
            for j in range(len(names)):
                actual &= _bdd.var(j) if j in true_slots else ~_bdd.var(j)
        observed = {a: tuple((observes or {}).get(a, ())) for a in ranked}
        for agent, seen in observed.items():
            for a in seen:
                _slot(slot, a, f"observes[{agent!r}]")
        return cls(names, state_law, observed, ranked, actual)

    @classmethod
    def from_explicit(cls, model: PlausibilityModel) -> PlausibilityStructure:
        """The structure of an explicit model whose cells come from observed atoms.

        Examples
        --------
        >>> m = PlausibilityModel.from_levels(["p", "q"], {"a": ["p", "q"]}, {"a": ["q"]})
        >>> s = PlausibilityStructure.from_explicit(m)
        >>> s.holds("B[a] p"), s.holds("Sb[a] (q -> p)"), m.holds("Sb[a] (q -> p)")
        (True, False, False)
        """
        if model.observes is None:
            raise InvalidArgumentError(
                "the model's cells do not come from observed atoms",
                hint="build it with PlausibilityModel.from_levels or pass observes=",
            )
        states = [_minterm(row) for row in model.valuation]
        law = _union(states)
        levels = {
            agent: [
                _union(states[w] for w in range(model.n_worlds) if ranks[w] == level)
                for level in range(int(ranks.max(initial=-1)) + 1)
            ]
            for agent, ranks in model.ranks.items()
        }
        designated = _union(s for s, d in zip(states, model.designated, strict=True) if d)
        return cls(model.atoms, law, model.observes, levels, designated)

    # -- questions ----------------------------------------------------------------------

    def truth(self, formula: Formula | str) -> BDDFunction:
        """The BDD of the states where ``formula`` holds (meaningful within the law)."""
        with _bdd.node_limit():
            return evaluate_plausibility(self, as_formula(formula)) & self.law

    def holds(self, formula: Formula | str) -> bool:
        """Whether ``formula`` holds at every designated state."""
        return not (self.designated & ~self.truth(formula)).satisfiable()

    def holds_at(self, formula: Formula | str, valuation: Sequence[bool]) -> bool:
        """Whether ``formula`` holds at the state with this valuation (one bool per atom)."""
        return (self.truth(formula) & _minterm(valuation)).satisfiable()

    def best(self, agent: str, condition: BDDFunction) -> BDDFunction:
        """The most plausible ``condition``-states of each of ``agent``'s cells."""
        hidden = self._hidden_cube(agent)
        best, covered = _bdd.false(), _bdd.false()
        for level in self.levels[agent]:
            here = condition & level
            best |= here & ~covered
            covered |= here.exists(hidden)
        return best

    # -- the operations evaluate_plausibility uses --------------------------------------

    def atom(self, atom: Atom) -> BDDFunction:
        return _bdd.var(_slot(self.slot, atom.key))

    def constant(self, value: bool) -> BDDFunction:
        return _bdd.true() if value else _bdd.false()

    def know(self, agent: str, truth: BDDFunction) -> BDDFunction:
        return self.law.apply_forall(_bdd.IMP, truth, self._hidden_cube(agent))

    def conditional_belief(
        self, agent: str, condition: BDDFunction, truth: BDDFunction
    ) -> BDDFunction:
        return self.know(agent, ~self.best(agent, condition) | truth)

    def safe_belief(self, agent: str, truth: BDDFunction) -> BDDFunction:
        result, prefix = _bdd.false(), _bdd.false()
        self._hidden_cube(agent)  # refuses an unknown agent
        for level in self.levels[agent]:
            prefix |= level
            result |= level & self.know(agent, ~prefix | truth)
        return result

    def restricted(self, truth: BDDFunction) -> PlausibilityStructure:
        law = self.law & truth
        return PlausibilityStructure(
            self.atoms, law, self.observes, self.levels, self.designated & truth
        )

    def lifted(self, submodel: PlausibilityStructure, truth: BDDFunction) -> BDDFunction:
        return truth  # the same variables: the states outside the sublaw do not matter

    def radical_upgrade(self, truth: BDDFunction) -> PlausibilityStructure:
        levels = {
            a: [g & truth for g in ls] + [g & ~truth for g in ls] for a, ls in self.levels.items()
        }
        return PlausibilityStructure(self.atoms, self.law, self.observes, levels, self.designated)

    def conservative_upgrade(self, truth: BDDFunction) -> PlausibilityStructure:
        levels = {}
        for agent, ls in self.levels.items():
            top = self.best(agent, truth & self.law)
            levels[agent] = [top] + [g & ~top for g in ls]
        return PlausibilityStructure(self.atoms, self.law, self.observes, levels, self.designated)

    # -- internals ----------------------------------------------------------------------

    def _hidden_cube(self, agent: str) -> BDDFunction:
        found = self._hidden.get(agent)
        if found is None:
            if agent not in self.observes:
                raise InvalidArgumentError(
                    f"unknown agent {agent!r}", hint=f"agents: {', '.join(self.agents)}"
                )
            seen = {self.slot[a] for a in self.observes[agent]}
            hidden = [j for j in range(len(self.atoms)) if j not in seen]
            found = self._hidden[agent] = _bdd.cube(hidden)
        return found

    def __repr__(self) -> str:
        return f"<PlausibilityStructure: atoms {list(self.atoms)}, agents {list(self.agents)}>"


def _slot(slot: Mapping[str, int], atom: str, where: str = "the formula") -> int:
    if atom not in slot:
        raise InvalidArgumentError(
            f"unknown atom {atom!r} in {where}", hint=f"declared atoms: {', '.join(slot)}"
        )
    return slot[atom]


def _minterm(valuation: Sequence[bool]) -> BDDFunction:
    result = _bdd.true()
    for j in range(len(valuation) - 1, -1, -1):
        result = (_bdd.var(j) if valuation[j] else ~_bdd.var(j)) & result
    return result


def _union(states: Iterable[BDDFunction]) -> BDDFunction:
    result = _bdd.false()
    for s in states:
        result |= s
    return result
