"""Random plausibility models and formulas, and a naive reference semantics.

The reference evaluates a formula world by world, straight from the definitions of
Baltag and Smets (2008) and van Benthem (2007), on plain Python dicts of ranks: it shares
no code with either backend, so agreement is evidence that both follow the definitions.
"""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import strategies as st

from epistemica.del_.explicit.plausibility import PlausibilityModel
from epistemica.del_.language.formula import And, Atom, Bottom, Iff, Implies, Not, Or, Top
from epistemica.del_.language.modalities import (
    Announce,
    AnnounceDiamond,
    Believe,
    ConditionalBelief,
    ConservativeUpgrade,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
    RadicalUpgrade,
    SafeBelief,
)

ATOMS = ("p", "q", "r")
AGENTS = ("a", "b")


@st.composite
def plausibility_models(draw, atoms=ATOMS, agents=AGENTS, max_rank=3):
    """A model from observables: some lawful valuations, cells by observed atoms, and a
    random rank (0..max_rank) per world and agent."""
    k = len(atoms)
    names = atoms
    table = np.array(list(itertools.product((False, True), repeat=k)), dtype=bool)
    keep = draw(st.lists(st.booleans(), min_size=len(table), max_size=len(table)))
    keep = np.array(keep)
    if not keep.any():
        keep[draw(st.integers(0, len(table) - 1))] = True
    valuation = table[keep]
    n = len(valuation)
    observes, cells, ranks = {}, {}, {}
    for agent in agents:
        seen = draw(st.lists(st.sampled_from(range(k)), unique=True, max_size=k))
        observes[agent] = [names[j] for j in seen]
        cells[agent] = valuation[:, seen] @ (1 << np.arange(len(seen), dtype=np.int64))
        ranks[agent] = np.array(draw(st.lists(st.integers(0, max_rank), min_size=n, max_size=n)))
    designated = np.array(draw(st.lists(st.booleans(), min_size=n, max_size=n)))
    return PlausibilityModel(names, valuation, cells, ranks, designated, observes)


def plausibility_formulas(atoms=ATOMS, agents=AGENTS, max_leaves=8, dynamic=True):
    """Random formulas of the plausibility language over ``atoms`` (every model has them)."""
    agent = st.sampled_from(agents)
    groups = st.lists(agent, min_size=1, max_size=len(agents), unique=True)
    leaves = st.one_of(st.sampled_from([Atom(a) for a in atoms]), st.just(Top()), st.just(Bottom()))

    def extend(children):
        options = [
            children.map(Not),
            st.builds(And, children, children),
            st.builds(Or, children, children),
            st.builds(Implies, children, children),
            st.builds(Iff, children, children),
            st.builds(Know, agent, children),
            st.builds(KnowWhether, agent, children),
            st.builds(Believe, agent, children),
            st.builds(ConditionalBelief, agent, children, children),
            st.builds(SafeBelief, agent, children),
            st.builds(Everybody, groups, children),
            st.builds(EverybodyBelieves, groups, children),
        ]
        if dynamic:
            options += [
                st.builds(Announce, children, children),
                st.builds(AnnounceDiamond, children, children),
                st.builds(RadicalUpgrade, children, children),
                st.builds(ConservativeUpgrade, children, children),
            ]
        return st.one_of(options)

    return st.recursive(leaves, extend, max_leaves=max_leaves)


# -- the reference semantics -----------------------------------------------------------


class Reference:
    """A model as dicts: worlds, valuation, and per agent a cell label and rank per world."""

    def __init__(self, worlds, valuation, cell, rank):
        self.worlds, self.valuation, self.cell, self.rank = worlds, valuation, cell, rank

    @classmethod
    def of(cls, model):
        worlds = frozenset(range(model.n_worlds))
        valuation = {
            w: {a for a, t in zip(model.atoms, model.valuation[w], strict=True) if t}
            for w in worlds
        }
        cell = {a: {w: int(model.cells[a][w]) for w in worlds} for a in model.agents}
        rank = {a: {w: int(model.ranks[a][w]) for w in worlds} for a in model.agents}
        return cls(worlds, valuation, cell, rank)

    def same_cell(self, a, w):
        return {v for v in self.worlds if self.cell[a][v] == self.cell[a][w]}

    def best(self, a, w, condition):
        """The most plausible worlds of w's cell among ``condition``."""
        candidates = self.same_cell(a, w) & condition
        if not candidates:
            return set()
        low = min(self.rank[a][v] for v in candidates)
        return {v for v in candidates if self.rank[a][v] == low}

    def truth(self, f):
        """The set of worlds where ``f`` holds."""
        kind, ws = type(f), self.worlds
        if kind is Atom:
            return {w for w in ws if f.key in self.valuation[w]}
        if kind is Top:
            return set(ws)
        if kind is Bottom:
            return set()
        if kind is Not:
            return ws - self.truth(f.operand)
        if kind in (And, Or, Implies, Iff):
            x, y = self.truth(f.left), self.truth(f.right)
            return {
                w
                for w in ws
                if {
                    And: lambda a, b: a and b,
                    Or: lambda a, b: a or b,
                    Implies: lambda a, b: (not a) or b,
                    Iff: lambda a, b: a == b,
                }[kind](w in x, w in y)
            }
        if kind is Know:
            x = self.truth(f.operand)
            return {w for w in ws if self.same_cell(f.agent, w) <= x}
        if kind is KnowWhether:
            x = self.truth(f.operand)
            return {
                w
                for w in ws
                if self.same_cell(f.agent, w) <= x or not self.same_cell(f.agent, w) & x
            }
        if kind is Believe:
            x = self.truth(f.operand)
            return {w for w in ws if self.best(f.agent, w, ws) <= x}
        if kind is ConditionalBelief:
            c, x = self.truth(f.condition), self.truth(f.operand)
            return {w for w in ws if self.best(f.agent, w, c) <= x}
        if kind is SafeBelief:
            x = self.truth(f.operand)
            return {
                w
                for w in ws
                if all(
                    v in x
                    for v in self.same_cell(f.agent, w)
                    if self.rank[f.agent][v] <= self.rank[f.agent][w]
                )
            }
        if kind in (Everybody, EverybodyBelieves):
            inner = Know if kind is Everybody else Believe
            result = set(ws)
            for a in f.group:
                result &= self.truth(inner(a, f.operand))
            return result
        if kind in (Announce, AnnounceDiamond):
            c = self.truth(f.announcement)
            sub = Reference(
                frozenset(c),
                self.valuation,
                self.cell,
                self.rank,
            )
            inside = sub.truth(f.operand)
            if kind is Announce:
                return {w for w in ws if w not in c or w in inside}
            return c & inside
        if kind is RadicalUpgrade:
            c = self.truth(f.upgrade)
            # Compare (not in c, old rank) lexicographically: c-worlds first, order kept.
            top = max((r for ranks in self.rank.values() for r in ranks.values()), default=0) + 1
            rank = {a: {w: r[w] + (0 if w in c else top) for w in ws} for a, r in self.rank.items()}
            return Reference(ws, self.valuation, self.cell, rank).truth(f.operand)
        if kind is ConservativeUpgrade:
            c = self.truth(f.upgrade)
            rank = {}
            for a, r in self.rank.items():
                rank[a] = {w: (0 if w in self.best(a, w, c) else r[w] + 1) for w in ws}
            return Reference(ws, self.valuation, self.cell, rank).truth(f.operand)
        raise TypeError(kind)
