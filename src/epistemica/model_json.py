"""Kripke models as JSON objects, and back (``epistemica show --json``).

The object names everything as a person would read it: worlds by their labels (the
spec's world names where it has them, see :func:`world_names`), agents and atoms as
declared. Each agent's relation is given by its blocks when it is an equivalence, by its
arrows otherwise; ``knowledge`` appears only for agents whose knowledge relation differs
from their belief relation::

    {"format": "epistemica-kripke-1",
     "agents": ["a"], "atoms": ["p"],
     "worlds": [{"name": "w0", "atoms": []}, {"name": "w1", "atoms": ["p"]}],
     "designated": ["w1"],
     "relations": {"a": {"belief": {"blocks": [["w0", "w1"]]}}}}

Examples
--------
>>> from epistemica.del_ import KripkeModel
>>> m = KripkeModel.from_observables(["p"], {"a": []}, designated=["p"])
>>> data = model_to_json(m)
>>> data["worlds"], data["designated"]
([{'name': 'w0', 'atoms': []}, {'name': 'w1', 'atoms': ['p']}], ['w1'])
>>> data["relations"]
{'a': {'belief': {'blocks': [['w0', 'w1']]}}}
>>> back = model_from_json(data)
>>> back.worlds, back.designated, back.holds("~K[a] p")
(('w0', 'w1'), ('w1',), True)
"""

from __future__ import annotations

import json
from collections.abc import Hashable, Mapping, Sequence
from typing import Any

import numpy as np

from epistemica.del_ import KripkeModel
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.describe import (
    relation_blocks,
    same_relations,
    true_atoms,
    world_labels,
)
from epistemica.del_.explicit.relations import Partition

__all__ = ["FORMAT", "dumps", "model_from_json", "model_to_json", "world_names"]

FORMAT = "epistemica-kripke-1"


def world_names(model: KripkeModel) -> dict[Hashable, str]:
    """A printable, distinct name for each world, as close to the spec's names as possible.

    A world named in the spec keeps its name; after product updates a world ``(w, e)``
    is ``w.e`` (world ``w``, event ``e``) when every part has a name. Otherwise (models
    from observables, whose worlds are valuations) the names of
    :func:`~epistemica.del_.explicit.describe.world_labels`.

    Examples
    --------
    >>> from epistemica.del_ import public_announcement
    >>> m = KripkeModel(["w1", "w2"], {"w1": {"p"}}, {"a": [("w1", "w1"), ("w2", "w2")]}, "w1")
    >>> world_names(m.update(public_announcement("p", ["a"])))
    {('w1', 'announce'): 'w1.announce'}
    """
    names = {w: _joined(w) for w in model.worlds}
    if None in names.values() or len(set(names.values())) != len(names):
        return world_labels(model)
    return names


def _joined(name: Hashable) -> str | None:
    if isinstance(name, str):
        return name
    if isinstance(name, tuple) and name:
        parts = [_joined(part) for part in name]
        return None if None in parts else ".".join(parts)
    return None


def _relation(
    model: KripkeModel, agent: str, kind: str, names: Sequence[str], keep: np.ndarray | None
) -> dict[str, list]:
    """Blocks of an equivalence, else arrows; ``keep``: only these world positions."""
    relation = model.relation(agent, kind)
    blocks = relation_blocks(relation)
    if blocks is not None:
        if keep is None:
            return {"blocks": [list(map(names.__getitem__, b)) for b in blocks]}
        kept = keep.tolist()
        listed = ([names[i] for i in b if kept[i]] for b in blocks)
        return {"blocks": [b for b in listed if b]}
    rows, cols = relation.edges()
    if keep is not None:
        inside = keep[rows] & keep[cols]
        rows, cols = rows[inside], cols[inside]
    order = np.lexsort((cols, rows))
    pairs = zip(rows[order].tolist(), cols[order].tolist(), strict=True)
    return {"arrows": [[names[w], names[v]] for w, v in pairs]}


def model_to_json(
    model: KripkeModel, atoms: Sequence[str] | None = None, limit: int | None = None
) -> dict[str, Any]:
    """The model as a JSON-ready dict (see the module docstring for the layout).

    ``atoms`` gives the order of the atoms (a spec's declaration order); atoms of the
    model it omits follow, atoms it adds that the model lacks are left out. ``limit``
    keeps the designated worlds and then the first worlds up to ``limit`` worlds, with
    the relations among them, and adds ``"truncated": true`` and ``"n_worlds"`` (a
    truncated object is not read back). Linear in the worlds and arrows of the model.
    """
    order = [a for a in atoms or () if a in model.atoms]
    order += [a for a in model.atoms if a not in order]
    by_world = world_names(model)
    names = [by_world[w] for w in model.worlds]
    n = model.n_worlds
    keep = None
    if limit is not None and limit < n:
        keep = np.zeros(n, dtype=bool)
        keep[model.designated_positions[:limit]] = True
        spare = limit - int(keep.sum())
        if spare > 0:
            keep[np.flatnonzero(~keep)[:spare]] = True
    positions = np.arange(n) if keep is None else np.flatnonzero(keep)
    relations = {}
    for agent in model.agents:
        entry = {"belief": _relation(model, agent, "belief", names, keep)}
        if not same_relations(model, agent):
            entry["knowledge"] = _relation(model, agent, "knowledge", names, keep)
        relations[agent] = entry
    atoms_of = true_atoms(model, positions, order)
    data = {
        "format": FORMAT,
        "agents": list(model.agents),
        "atoms": order,
        "worlds": [
            {"name": names[i], "atoms": true}
            for i, true in zip(positions.tolist(), atoms_of, strict=True)
        ],
        "designated": [names[i] for i in model.designated_positions.tolist()],
        "relations": relations,
    }
    if keep is not None:
        data.update(truncated=True, n_worlds=n)
    return data


def dumps(data: Mapping[str, Any]) -> str:
    """JSON text of a model object: one key per line, each world, block list and agent on
    a line of its own (readable, and written by the C encoder: a 65,536-world model in
    about a second, where ``indent=2`` takes tens of seconds).

    Examples
    --------
    >>> print(dumps({"format": FORMAT, "worlds": [{"name": "w0", "atoms": []}]}))
    {
      "format": "epistemica-kripke-1",
      "worlds": [
        {"name": "w0", "atoms": []}
      ]
    }
    """
    compact = json.JSONEncoder(separators=(", ", ": ")).encode
    lines = []
    for key, value in data.items():
        if isinstance(value, list) and value:
            items = ",\n".join(f"    {compact(item)}" for item in value)
            lines.append(f"  {compact(key)}: [\n{items}\n  ]")
        elif isinstance(value, dict) and value:
            items = ",\n".join(f"    {compact(k)}: {compact(v)}" for k, v in value.items())
            lines.append(f"  {compact(key)}: {{\n{items}\n  }}")
        else:
            lines.append(f"  {compact(key)}: {compact(value)}")
    return "{\n" + ",\n".join(lines) + "\n}"


def model_from_json(data: Mapping[str, Any]) -> KripkeModel:
    """The :class:`KripkeModel` of an object written by :func:`model_to_json`.

    Worlds are named by their names in ``data``; keys other than the model's are ignored
    (``epistemica show --json`` adds ``file`` and ``after``).

    Raises
    ------
    InvalidArgumentError
        ``data`` is not such an object (wrong format tag, missing key).
    """
    if not isinstance(data, Mapping) or data.get("format") != FORMAT:
        raise InvalidArgumentError(
            "not a model written by 'epistemica show --json'",
            hint=f'expected an object with "format": "{FORMAT}"',
        )
    if data.get("truncated"):
        raise InvalidArgumentError(
            "a truncated model ('epistemica show --limit') cannot be read back",
            hint="print the whole model: leave out --limit",
        )
    try:
        worlds = [w["name"] for w in data["worlds"]]
        valuation = {w["name"]: w["atoms"] for w in data["worlds"]}
        relations = data["relations"]
        # Blocks become partitions below, in time linear in the worlds, never as pairs.
        belief = {a: _arrows(r["belief"]) for a, r in relations.items()}
        knowledge = {a: _arrows(r["knowledge"]) for a, r in relations.items() if "knowledge" in r}
        designated = data["designated"]
        atoms = list(data["atoms"])
        base = KripkeModel(
            worlds, valuation, belief, designated, knowledge=knowledge or None, atoms=atoms
        )
        rel, know = {}, {}
        for agent, entry in relations.items():
            rel[agent] = _relation_from(entry["belief"], base, agent, "belief")
            know[agent] = rel[agent]
            if "knowledge" in entry:
                know[agent] = _relation_from(entry["knowledge"], base, agent, "knowledge")
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise InvalidArgumentError(
            f"malformed model object ({type(exc).__name__}: {exc})",
            hint="read back what 'epistemica show --json' printed, unchanged",
        ) from None
    return KripkeModel.from_arrays(
        base.lazy_names, base.atoms, base.valuation, base.agents, rel, know,
        base.designated_positions,
    )  # fmt: skip


def _arrows(relation: Mapping[str, list]) -> list[tuple[str, str]]:
    if "blocks" in relation:
        return []
    return [(w, v) for w, v in relation["arrows"]]


def _relation_from(entry: Mapping[str, list], base: KripkeModel, agent: str, kind: str):
    if "blocks" not in entry:
        return base.relation(agent, kind)
    index = base.world_index()
    labels = np.full(base.n_worlds, -1, dtype=np.intp)
    for k, block in enumerate(entry["blocks"]):
        for w in block:
            i = base.index_of(w)
            if labels[i] >= 0:
                raise ValueError(f"world {w!r} is in two blocks of {agent}'s {kind} relation")
            labels[i] = k
    missing = np.flatnonzero(labels < 0)
    if len(missing):
        world = list(index)[int(missing[0])]
        raise ValueError(f"world {world!r} is in no block of {agent}'s {kind} relation")
    return Partition(labels)
