"""Plain-text descriptions of Kripke models, for people (``epistemica plan --explain``).

Examples
--------
>>> from epistemica.del_ import KripkeModel
>>> from epistemica.del_.explicit._model import ExplicitModel
>>> m = KripkeModel.from_observables(["p", "q"], {"a": ["p"], "b": ["q"]}, designated=["p"])
>>> print(describe_model(m))
4 worlds, 1 designated; agents a, b
    w0  {}
    w1  {q}
  * w2  {p}
    w3  {p, q}
  a: {w0, w1} {w2, w3}
  b: {w0, w2} {w1, w3}
"""

from __future__ import annotations

import itertools
from collections.abc import Hashable, Sequence

import numpy as np

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._model import ExplicitModel
from epistemica.del_.explicit._sparse import connected_components
from epistemica.del_.explicit.relations import Partition, Relation

__all__ = [
    "describe_model",
    "relation_blocks",
    "same_relations",
    "true_atoms",
    "world_label",
    "world_labels",
]


def relation_blocks(relation: Relation) -> list[list[int]] | None:
    """The classes of an equivalence (lists of world positions, ordered by their first
    world), or ``None`` if the relation is not one. Linear in the worlds and arrows.

    Examples
    --------
    >>> from epistemica.del_ import KripkeModel
    >>> m = KripkeModel.from_observables(["p", "q"], {"a": ["p"]})
    >>> relation_blocks(m.relation("a"))
    [[0, 1], [2, 3]]
    """
    if isinstance(relation, Partition):
        labels = relation.labels
    elif relation.is_equivalence():
        labels = connected_components(relation.to_csr(), directed=False)[1]
    else:
        return None
    if not len(labels):
        return []
    order = np.argsort(labels, kind="stable")
    ordered = labels[order]
    bounds = [0, *(np.flatnonzero(ordered[1:] != ordered[:-1]) + 1).tolist(), len(order)]
    members = order.tolist()
    blocks = [members[a:b] for a, b in itertools.pairwise(bounds)]
    blocks.sort(key=lambda block: block[0])
    return blocks


def same_relations(model: ExplicitModel, agent: str) -> bool:
    """Whether the agent's knowledge relation relates the same pairs as its belief relation."""
    belief, knowledge = model.relation(agent, "belief"), model.relation(agent, "knowledge")
    if belief is knowledge:
        return True
    first, second = relation_blocks(belief), relation_blocks(knowledge)
    if first is not None and second is not None:
        return first == second
    if (first is None) != (second is None):
        return False
    return (belief.to_csr() != knowledge.to_csr()).nnz == 0


def true_atoms(model: ExplicitModel, positions: Sequence[int], order: Sequence[str]) -> list:
    """Per world position, the atoms true there in the order ``order`` (one matrix read)."""
    columns = [model.atom_column(a) for a in order]
    keep = [(a, c) for a, c in zip(order, columns, strict=True) if c is not None]
    if not keep or not len(positions):
        return [[] for _ in positions]
    rows = model.valuation[np.asarray(positions, dtype=np.intp)][:, [c for _, c in keep]]
    names = [a for a, _ in keep]
    worlds, columns = np.nonzero(rows)  # row-major: each world's atoms in order
    bounds = np.searchsorted(worlds, np.arange(len(rows) + 1)).tolist()
    found = list(map(names.__getitem__, columns.tolist()))
    return [found[a:b] for a, b in itertools.pairwise(bounds)]


def world_labels(model: ExplicitModel) -> dict[Hashable, str]:
    """Short printable names of the worlds, made of the names the user wrote.

    A world named by a string (an explicit world of a spec) keeps its name; a world of a
    product update, a pair ``(world, event)``, is named ``world.event`` from the names of
    its parts (so ``u.tell.skip`` after two updates of world ``u``); a world numbered by
    :meth:`KripkeModel.from_observables` (the index of its valuation) is ``w<number>``.
    Should two worlds get the same label, every world is named ``w<index>`` instead.

    Examples
    --------
    >>> from epistemica.del_.explicit.action import public_announcement
    >>> from epistemica.del_ import KripkeModel
    >>> world_labels(KripkeModel.from_observables(["p"], {"a": []}))
    {0: 'w0', 1: 'w1'}
    >>> m = KripkeModel(["u", "v"], {"u": {"p"}}, {"a": []}, ["u"])
    >>> world_labels(m.update(public_announcement("p", ["a"])))
    {('u', 'announce'): 'u.announce'}
    """
    labels = {w: _label(w) for w in model.worlds}
    if len(set(labels.values())) < len(labels):
        return {w: f"w{i}" for i, w in enumerate(model.worlds)}
    return labels


def world_label(world: Hashable) -> str:
    """The label :func:`world_labels` gives ``world`` when labels do not clash.

    Examples
    --------
    >>> world_label(("u", "tell")), world_label(5)
    ('u.tell', 'w5')
    """
    return _label(world)


def _label(world: Hashable) -> str:
    # Iteratively: a world after n updates is a pair nested n deep.
    parts: list[str] = []
    stack = [world]
    while stack:
        item = stack.pop()
        if isinstance(item, tuple):
            stack.extend(reversed(item))
        elif isinstance(item, str):
            parts.append(item)
        elif isinstance(item, int):
            parts.append(f"w{item}")
        else:
            parts.append(str(item))
    return ".".join(parts)


def _blocks(blocks: list[list[int]], labels: list[str]) -> str:
    return " ".join("{" + ", ".join(labels[i] for i in block) + "}" for block in blocks)


def _arrows(relation: Relation, labels: list[str]) -> str:
    rows, cols = relation.edges()
    targets: list[list[int]] = [[] for _ in labels]
    for w, v in zip(rows.tolist(), cols.tolist(), strict=True):
        targets[w].append(v)
    return "; ".join(
        f"{labels[w]} -> " + (", ".join(labels[v] for v in sorted(t)) or "nothing")
        for w, t in enumerate(targets)
    )


def _relation(model: ExplicitModel, agent: str, kind: str, labels: list[str]) -> str:
    relation = model.relation(agent, kind)
    blocks = relation_blocks(relation)
    return _arrows(relation, labels) if blocks is None else _blocks(blocks, labels)


def describe_model(model: ExplicitModel, max_worlds: int = 16) -> str:
    """Describe a model: its worlds with their true atoms, and what each agent considers.

    Designated worlds are marked ``*``. For each agent the belief relation is printed as
    blocks ``{w0, w1}`` when it is an equivalence (S5), else as arrows ``w0 -> w1, w2``;
    when the agent's knowledge relation differs, it follows on a line of its own.

    Parameters
    ----------
    model : ExplicitModel
    max_worlds : int
        Larger models are summarised: the designated worlds (at most ``max_worlds``) and,
        per agent, the kind of its relations instead of the relations themselves.

    Returns
    -------
    str
        Several lines, without a trailing newline.
    """
    if not isinstance(max_worlds, int) or max_worlds < 1:
        raise InvalidArgumentError(
            f"max_worlds must be a positive integer, got {max_worlds!r}", hint="e.g. 16"
        )
    names = world_labels(model)
    labels = [names[w] for w in model.worlds] if model.n_worlds <= max_worlds else []
    n = model.n_worlds
    points = model.designated_positions
    head = (
        f"{n} world{'s' if n != 1 else ''}, {len(points)} designated; "
        f"agents {', '.join(model.agents)}"
    )
    lines = [head]
    shown = np.arange(n) if n <= max_worlds else points[:max_worlds]
    shown_names = model.worlds_at(shown)
    width = max((len(names[w]) for w in shown_names), default=0)
    marked = set(points.tolist())
    for i, w, atoms in zip(
        shown.tolist(), shown_names, true_atoms(model, shown, model.atoms), strict=True
    ):
        mark = "*" if i in marked else " "
        lines.append(f"  {mark} {names[w]:<{width}}  {{{', '.join(atoms)}}}")
    if len(shown) < n:
        lines.append(f"    ... {n - len(shown)} more worlds not shown")
    for agent in model.agents:
        if n > max_worlds:
            kinds = ["S5" if model.is_s5(agent) else "KD45" if model.is_kd45(agent) else "K"]
            if model.has_separate_knowledge():
                kinds.append("knowledge S5" if model.is_s5(agent, "knowledge") else "knowledge K")
            lines.append(f"  {agent}: {', '.join(kinds)} relation (too large to list)")
            continue
        if same_relations(model, agent):
            lines.append(f"  {agent}: {_relation(model, agent, 'belief', labels)}")
        else:
            lines.append(f"  {agent} believes: {_relation(model, agent, 'belief', labels)}")
            lines.append(f"  {agent} knows: {_relation(model, agent, 'knowledge', labels)}")
    return "\n".join(lines)
