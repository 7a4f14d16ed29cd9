"""Plain-text descriptions of Kripke models, for people (``epistemica plan --explain``).

Examples
--------
>>> from epistemica.del_.kripke import KripkeModel
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

from collections.abc import Hashable

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.kripke import KripkeModel

__all__ = ["describe_model", "world_labels"]


def world_labels(model: KripkeModel) -> dict[Hashable, str]:
    """Short printable names of the worlds.

    World names that are strings (explicit worlds of a spec) are kept; any other names
    (integers, the ``(world, event)`` pairs of product updates) become ``w<index>``.

    Examples
    --------
    >>> from epistemica.del_.kripke import KripkeModel
    >>> m = KripkeModel.from_observables(["p"], {"a": []})
    >>> world_labels(m)
    {0: 'w0', 1: 'w1'}
    """
    worlds = model.worlds
    if all(isinstance(w, str) for w in worlds):
        return {w: w for w in worlds}
    return {w: f"w{i}" for i, w in enumerate(worlds)}


def _atoms(model: KripkeModel, world: Hashable) -> str:
    true = model.valuation_of(world)
    return "{" + ", ".join(a for a in model.atoms if a in true) + "}"


def _blocks(model: KripkeModel, agent: str, kind: str, labels: dict) -> str:
    seen: set = set()
    blocks = []
    for w in model.worlds:
        if w in seen:
            continue
        block = model.successors(agent, w, kind)
        seen.update(block)
        blocks.append("{" + ", ".join(labels[v] for v in block) + "}")
    return " ".join(blocks)


def _arrows(model: KripkeModel, agent: str, kind: str, labels: dict) -> str:
    parts = []
    for w in model.worlds:
        targets = model.successors(agent, w, kind)
        parts.append(f"{labels[w]} -> " + (", ".join(labels[v] for v in targets) or "nothing"))
    return "; ".join(parts)


def _relation(model: KripkeModel, agent: str, kind: str, labels: dict) -> str:
    if model.is_s5(agent, kind):
        return _blocks(model, agent, kind, labels)
    return _arrows(model, agent, kind, labels)


def _same(model: KripkeModel, agent: str) -> bool:
    return all(
        model.successors(agent, w) == model.successors(agent, w, "knowledge") for w in model.worlds
    )


def describe_model(model: KripkeModel, max_worlds: int = 16) -> str:
    """Describe a model: its worlds with their true atoms, and what each agent considers.

    Designated worlds are marked ``*``. For each agent the belief relation is printed as
    blocks ``{w0, w1}`` when it is an equivalence (S5), else as arrows ``w0 -> w1, w2``;
    when the agent's knowledge relation differs, it follows on a line of its own.

    Parameters
    ----------
    model : KripkeModel
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
    labels = world_labels(model)
    designated = set(model.designated)
    n = model.n_worlds
    head = (
        f"{n} world{'s' if n != 1 else ''}, {len(designated)} designated; "
        f"agents {', '.join(model.agents)}"
    )
    lines = [head]
    width = max((len(labels[w]) for w in model.worlds), default=0)
    if n <= max_worlds:
        shown = list(model.worlds)
    else:
        shown = list(model.designated)[:max_worlds]
    for w in shown:
        mark = "*" if w in designated else " "
        lines.append(f"  {mark} {labels[w]:<{width}}  {_atoms(model, w)}")
    if len(shown) < n:
        lines.append(f"    ... {n - len(shown)} more worlds not shown")
    for agent in model.agents:
        if n > max_worlds:
            kinds = ["S5" if model.is_s5(agent) else "KD45" if model.is_kd45(agent) else "K"]
            if model.has_separate_knowledge():
                kinds.append("knowledge S5" if model.is_s5(agent, "knowledge") else "knowledge K")
            lines.append(f"  {agent}: {', '.join(kinds)} relation (too large to list)")
            continue
        if _same(model, agent):
            lines.append(f"  {agent}: {_relation(model, agent, 'belief', labels)}")
        else:
            lines.append(f"  {agent} believes: {_relation(model, agent, 'belief', labels)}")
            lines.append(f"  {agent} knows: {_relation(model, agent, 'knowledge', labels)}")
    return "\n".join(lines)
