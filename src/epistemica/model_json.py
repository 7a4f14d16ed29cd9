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

from collections.abc import Hashable, Mapping, Sequence
from typing import Any

import numpy as np

from epistemica.del_ import KripkeModel
from epistemica.del_.errors import InvalidArgumentError
from epistemica.del_.explicit.describe import world_labels

__all__ = ["FORMAT", "model_from_json", "model_to_json", "world_names"]

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


def _relation(model: KripkeModel, agent: str, kind: str, names: Mapping) -> dict[str, list]:
    if model.is_s5(agent, kind):
        seen: set = set()
        blocks = []
        for w in model.worlds:
            if w not in seen:
                block = model.successors(agent, w, kind)
                seen.update(block)
                blocks.append([names[v] for v in block])
        return {"blocks": blocks}
    arrows = [[names[w], names[v]] for w in model.worlds for v in model.successors(agent, w, kind)]
    return {"arrows": arrows}


def model_to_json(model: KripkeModel, atoms: Sequence[str] | None = None) -> dict[str, Any]:
    """The model as a JSON-ready dict (see the module docstring for the layout).

    ``atoms`` gives the order of the atoms (a spec's declaration order); atoms of the
    model it omits follow, atoms it adds that the model lacks are left out.
    """
    order = [a for a in atoms or () if a in model.atoms]
    order += [a for a in model.atoms if a not in order]
    names = world_names(model)
    relations = {}
    for agent in model.agents:
        entry = {"belief": _relation(model, agent, "belief", names)}
        if any(
            model.successors(agent, w) != model.successors(agent, w, "knowledge")
            for w in model.worlds
        ):
            entry["knowledge"] = _relation(model, agent, "knowledge", names)
        relations[agent] = entry
    return {
        "format": FORMAT,
        "agents": list(model.agents),
        "atoms": order,
        "worlds": [
            {"name": names[w], "atoms": [a for a in order if a in model.valuation_of(w)]}
            for w in model.worlds
        ],
        "designated": [names[w] for w in model.designated],
        "relations": relations,
    }


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
    try:
        worlds = [w["name"] for w in data["worlds"]]
        valuation = {w["name"]: w["atoms"] for w in data["worlds"]}
        relations = data["relations"]
        belief = {a: _pairs(r["belief"]) for a, r in relations.items()}
        knowledge = {a: _pairs(r["knowledge"]) for a, r in relations.items() if "knowledge" in r}
        designated = data["designated"]
        atoms = list(data["atoms"])
    except (KeyError, TypeError, ValueError) as exc:
        raise InvalidArgumentError(
            f"malformed model object ({type(exc).__name__}: {exc})",
            hint="read back what 'epistemica show --json' printed, unchanged",
        ) from None
    # The constructor takes the atoms from the valuation, in order of appearance; a
    # first world where every atom is true keeps the declared order and the atoms that
    # are true nowhere. It has no arrows and is removed again at once.
    scaffold = ("scaffold", len(worlds))
    model = KripkeModel(
        [scaffold, *worlds],
        {scaffold: atoms, **valuation},
        belief,
        designated,
        knowledge=knowledge or None,
    )
    return model.restrict(np.arange(model.n_worlds) > 0)


def _pairs(relation: Mapping[str, list]) -> list[tuple[str, str]]:
    if "blocks" in relation:
        return [(w, v) for block in relation["blocks"] for w in block for v in block]
    return [(w, v) for w, v in relation["arrows"]]
