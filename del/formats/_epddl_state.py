"""The initial state of an EPDDL problem: explicit worlds, or a finitary S5 theory.

Helper of :mod:`epistemica.del_.formats.epddl`, with plank's semantics:

- ``:worlds (...) :relations (...) :labels (...) :designated (...)``: the worlds named, each
  agent's relation as listed (an agent listed twice keeps its last list, an agent not
  listed relates nothing), a world's label the atoms listed for it;
- a finitary S5 theory (a list of formulas): the worlds are the valuations of the ground
  atoms that satisfy every ``[C. All] (f)`` and ``[C. All] ([i] f)``; agent ``i`` relates
  two worlds that agree on every ``f`` of a ``[C. All] ([Kw. i] f)`` (and relates every
  two worlds if it has none); the designated worlds are those that satisfy the
  propositional formulas; ``[C. All] (<Kw. i> f)`` adds no constraint.

The worlds of a theory are enumerated on a BDD (the states of the law), never as all 2^n
valuations, so a theory over 33 atoms with a handful of models is cheap.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from lark import Tree

from epistemica.del_.errors import EpistemicaError
from epistemica.del_.explicit.relations import Partition, relation_from_pairs
from epistemica.del_.formats._epddl_formulas import conj
from epistemica.del_.formats._epddl_ground import Grounder
from epistemica.del_.formats._epddl_syntax import Source, mangle
from epistemica.del_.language.formula import Bottom, Formula, Not, Or, Top
from epistemica.del_.models import KnowledgeStructure, KripkeModel
from epistemica.del_.symbolic.convert import states

__all__ = ["MAX_WORLDS", "initial_state"]

#: Bound on the worlds of an initial state.
MAX_WORLDS = 1 << 22


def initial_state(g: Grounder) -> KripkeModel:
    """The initial Kripke model of the problem of ``g``."""
    init = [i for i in g.problem.children[2:] if i.data == "init"]
    if not init:
        raise g.psrc.error("the problem has no :init", g.problem, "add (:init ...)")
    if len(init) > 1:
        raise g.psrc.error("a second :init", init[1], "keep one initial state")
    body = init[0].children[0]
    if body.data == "explicit_init":
        return _explicit(g, body)
    return _theory(g, body)


def _explicit(g: Grounder, body: Tree) -> KripkeModel:
    src = g.psrc
    first, *middle, last = body.children
    worlds: dict[str, int] = {}
    for token in first.children:
        if str(token) in worlds:
            raise src.error(f"world '{token}' declared twice", token, "rename one")
        worlds[str(token)] = len(worlds)
    local = {w: "world" for w in worlds}
    n = len(worlds)
    pairs: dict[str, list[tuple[int, int]]] = {a: [] for a in g.agents}
    for rel in (t for t in middle if t.data == "relation"):
        agent_token, edges = rel.children
        agent = g.term(agent_token, {}, src)
        if agent not in pairs:
            raise src.error(f"'{agent}' is not an agent", agent_token, ", ".join(g.agents))
        found = []
        for pair, env in g.list_items(edges, {}, src, local=local):
            x, y = (_world(g, t, env, src, worlds, local) for t in pair.children)
            found.append((x, y))
        pairs[agent] = found  # a second list for one agent replaces the first, as in plank
    column = {a: j for j, a in enumerate(g.atoms)}
    val = np.zeros((n, len(g.atoms)), dtype=bool)
    for label in (t for t in middle if t.data == "label"):
        wtoken, atoms = label.children
        if str(wtoken) not in worlds:
            raise src.error(f"unknown world '{wtoken}'", wtoken, f"worlds: {', '.join(worlds)}")
        for node, env in g.list_items(atoms, {}, src, local=local):
            atom = g.atom(node.children[0], node.children[1:], env, src)
            if not isinstance(atom, (Top, Bottom)):  # facts are constants
                val[worlds[str(wtoken)], column[atom.key]] = True
    points = []
    for token in last.children:
        if str(token) not in worlds:
            raise src.error(f"unknown world '{token}'", token, f"worlds: {', '.join(worlds)}")
        points.append(worlds[str(token)])
    rel = {}
    for agent, edges in pairs.items():
        sources = [e[0] for e in edges]
        targets = [e[1] for e in edges]
        rel[mangle(agent)] = relation_from_pairs(n, sources, targets)
    agents = tuple(mangle(a) for a in g.agents)
    return KripkeModel.from_arrays(
        tuple(worlds), tuple(g.atoms), val, agents, rel, dict(rel), np.unique(points)
    )


def _world(g, token, env, src: Source, worlds: Mapping[str, int], local) -> int:
    name = g.term(token, env, src, local)
    if name not in worlds:
        raise src.error(f"'{name}' is not a world", token, f"worlds: {', '.join(worlds)}")
    return worlds[name]


def _theory(g: Grounder, body: Tree) -> KripkeModel:
    src = g.psrc
    actual: list[Formula] = []
    law: list[Formula] = []
    whether: dict[str, list[Formula]] = {a: [] for a in g.agents}
    for node, env in g.list_items(body, {}, src):
        if node.data != "ck":
            actual.append(_propositional(g, node, env, src))
            continue
        modality, _everyone, inner = node.children
        if str(modality) != "C.":
            raise src.error(
                f"expected 'C.', found '{modality}'", modality,
                "a theory states common knowledge as [C. All] (...)",
            )  # fmt: skip
        kind = inner.data
        if kind == "ck_prop":
            law.append(_propositional(g, inner.children[0], env, src))
        elif kind == "ck_k":
            law.append(_propositional(g, inner.children[1], env, src))
        elif kind in ("ck_kw", "ck_not_kw"):
            modality, agent_token, f = inner.children
            if str(modality) != "Kw.":
                raise src.error(f"expected 'Kw.', found '{modality}'", modality, "write [Kw. i]")
            agent = g.term(agent_token, env, src)
            if g.entities.get(agent) != "agent":
                raise src.error(f"'{agent}' is not an agent", agent_token, ", ".join(g.agents))
            if kind == "ck_kw":
                whether[agent].append(_propositional(g, f, env, src))
    return _theory_model(g, body, conj(law), conj(actual), whether)


def _propositional(g: Grounder, node: Tree, env, src: Source) -> Formula:
    for sub in node.iter_subtrees():
        if sub.data in ("box", "diamond"):
            raise src.error(
                "a modality inside a formula of the theory", sub,
                "a finitary S5 theory has propositional formulas, [C. All] (f), "
                "[C. All] ([Kw. i] f) and [C. All] (<Kw. i> f)",
            )  # fmt: skip
    return g.formula(node, env, src)


def _theory_model(g: Grounder, where: Tree, law: Formula, actual: Formula, whether) -> KripkeModel:
    src = g.psrc
    atoms = tuple(g.atoms)
    # "p | ~p" for every atom: n_worlds counts over variables the BDD manager has seen
    # (a law that leaves an atom free must still declare it; see the report of issue 21).
    declared = conj([law, *(Or(g.atom_formula(a), Not(g.atom_formula(a))) for a in atoms)])
    try:
        structure = KnowledgeStructure.from_observables(atoms, {}, declared)
    except EpistemicaError as exc:  # a contradiction in the law, reported located
        message = getattr(exc, "message", str(exc))
        raise src.error(f"no world satisfies the theory: {message}", where, _law_hint()) from None
    count = structure.n_worlds
    if count > MAX_WORLDS:
        raise src.error(
            f"the theory has {count} worlds, more than {MAX_WORLDS}", where,
            "constrain the atoms with [C. All] (...) formulas",
        )  # fmt: skip
    found = states(structure.law, list(structure.slots))
    position = {s: k for k, s in enumerate(structure.slots)}
    order = [position[structure.atom_slots[a]] for a in atoms]
    val = np.array(found, dtype=bool).reshape(len(found), len(structure.slots))[:, order]
    model = KripkeModel.from_arrays(None, atoms, val, (), {}, {}, np.arange(len(found)))
    points = np.flatnonzero(model.truth_mask(actual))
    if not len(points):
        raise src.error(
            "no world of the theory satisfies its propositional formulas", where,
            "the actual world must satisfy the [C. All] formulas too",
        )  # fmt: skip
    rel = {}
    for agent, formulas in whether.items():
        columns = [model.truth_mask(f) for f in formulas]
        if columns:
            keys = np.stack(columns, axis=1)
            _, labels = np.unique(keys, axis=0, return_inverse=True)
        else:
            labels = np.zeros(len(found), dtype=np.intp)
        rel[mangle(agent)] = Partition(np.asarray(labels).reshape(-1))
    agents = tuple(mangle(a) for a in g.agents)
    return KripkeModel.from_arrays(None, atoms, val, agents, rel, dict(rel), points)


def _law_hint() -> str:
    return "the [C. All] formulas of the :init contradict each other"
