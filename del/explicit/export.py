"""Export of Kripke models to networkx graphs and Graphviz DOT text.

networkx is loaded on the first export, not with this module: every
:class:`~epistemica.del_.KripkeModel` imports this module for its ``to_networkx`` and
``to_dot`` methods, and ``epistemica check`` must not pay 80 ms for a library it never
uses (``tests/test_cli_contract.py``). That is a third-party library, not an edge between
``del/`` modules, so the one-way import graph is unaffected.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit.describe import true_atoms, world_labels
from epistemica.del_.explicit.relations import Partition, Relation

if TYPE_CHECKING:
    import networkx as nx

__all__ = ["MAX_DOT_EDGES", "to_dot", "to_networkx"]


def _edges(model: ExplicitModel, agent: str, kind: str):
    relation = (
        model.belief_relations[agent] if kind == "belief" else model.knowledge_relations[agent]
    )
    rows, cols = relation.edges()
    return zip(rows.tolist(), cols.tolist(), strict=True)


def to_networkx(model: ExplicitModel) -> nx.MultiDiGraph:
    """The model as a multigraph: one node per world, one edge per related pair and agent.

    Nodes carry ``atoms`` (the true atoms, sorted) and ``designated`` (bool). Edges carry
    ``agent`` and ``relation`` (``"belief"``; ``"knowledge"`` edges are added only for
    agents whose knowledge relation differs from their belief relation).

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
    >>> g = to_networkx(m)
    >>> g.number_of_nodes(), g.number_of_edges()
    (2, 4)
    >>> g.nodes[1]
    {'atoms': ['p'], 'designated': True}
    """
    graph = importlib.import_module("networkx").MultiDiGraph()
    names = model.worlds
    designated = np.zeros(model.n_worlds, dtype=bool)
    designated[model.designated_positions] = True
    for i, name in enumerate(names):
        atoms = sorted(a for a, t in zip(model.atoms, model.valuation[i], strict=True) if t)
        graph.add_node(name, atoms=atoms, designated=bool(designated[i]))
    for agent in model.agents:
        kinds = ["belief"]
        if model.knowledge_relations[agent] is not model.belief_relations[agent]:
            kinds.append("knowledge")
        for kind in kinds:
            for w, v in _edges(model, agent, kind):
                graph.add_edge(names[w], names[v], agent=agent, relation=kind)
    return graph


#: DOT draws every related pair: an agent who sees nothing of 65,536 worlds relates 2^32.
MAX_DOT_EDGES = 5_000_000


def _n_edges(relation: Relation) -> int:
    """The number of related pairs, without listing them."""
    if isinstance(relation, Partition):
        sizes = np.bincount(relation.labels)
        return int((sizes.astype(np.int64) ** 2).sum())
    return len(relation.edges()[0])


def _quote(text: object) -> str:
    return '"' + str(text).replace('"', '\\"') + '"'


def to_dot(model: ExplicitModel) -> str:
    """The model in Graphviz DOT: designated worlds double-circled, edges labelled by agent.

    Knowledge edges (when separate from belief) are dashed. Worlds are labelled with the
    names the user wrote (:func:`~epistemica.del_.explicit.describe.world_labels`: ``u``, ``u.tell``
    after an update) and their true atoms. Linear in the worlds and related pairs (no
    graph object is built).

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
    >>> print(to_dot(m).splitlines()[0])
    digraph kripke {
    """
    edges = sum(_n_edges(r) for r in model.belief_relations.values())
    if edges > MAX_DOT_EDGES:
        raise InvalidArgumentError(
            f"the model has {edges:,} related pairs, more than {MAX_DOT_EDGES:,} to draw",
            hint="draw a part of it (epistemica show --dot F --limit N), or use --json, "
            "which writes an equivalence as its blocks",
        )
    names = world_labels(model)
    designated = np.zeros(model.n_worlds, dtype=bool)
    designated[model.designated_positions] = True
    atoms = true_atoms(model, np.arange(model.n_worlds), sorted(model.atoms))
    lines = ["digraph kripke {", "  node [shape=circle];"]
    for i, name in enumerate(model.worlds):
        label = f"{names[name]}\\n{', '.join(atoms[i])}"
        shape = "doublecircle" if designated[i] else "circle"
        lines.append(f"  w{i} [label={_quote(label)}, shape={shape}];")
    for agent in model.agents:
        kinds = ["belief"]
        if model.knowledge_relations[agent] is not model.belief_relations[agent]:
            kinds.append("knowledge")
        for kind in kinds:
            style = ", style=dashed" if kind == "knowledge" else ""
            quoted = _quote(agent)
            lines.extend(
                f"  w{w} -> w{v} [label={quoted}{style}];" for w, v in _edges(model, agent, kind)
            )
    lines.append("}")
    return "\n".join(lines)
