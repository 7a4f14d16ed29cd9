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

from collections.abc import Hashable

from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit._model import ExplicitModel

__all__ = ["describe_model", "world_label", "world_labels"]


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


def _atoms(model: ExplicitModel, world: Hashable) -> str:
    true = model.valuation_of(world)
    return "{" + ", ".join(a for a in model.atoms if a in true) + "}"


def _blocks(model: ExplicitModel, agent: str, kind: str, labels: dict) -> str:
    seen: set = set()
    blocks = []
    for w in model.worlds:
        if w in seen:
            continue
        block = model.successors(agent, w, kind)
        seen.update(block)
        blocks.append("{" + ", ".join(labels[v] for v in block) + "}")
    return " ".join(blocks)


def _arrows(model: ExplicitModel, agent: str, kind: str, labels: dict) -> str:
    parts = []
    for w in model.worlds:
        targets = model.successors(agent, w, kind)
        parts.append(f"{labels[w]} -> " + (", ".join(labels[v] for v in targets) or "nothing"))
    return "; ".join(parts)


def _relation(model: ExplicitModel, agent: str, kind: str, labels: dict) -> str:
    if model.is_s5(agent, kind):
        return _blocks(model, agent, kind, labels)
    return _arrows(model, agent, kind, labels)


def _same(model: ExplicitModel, agent: str) -> bool:
    return all(
        model.successors(agent, w) == model.successors(agent, w, "knowledge") for w in model.worlds
    )


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
