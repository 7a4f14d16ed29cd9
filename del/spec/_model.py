"""Building the initial Kripke model of a spec file.

Helper of :mod:`epistemica.del_.spec._document`: the model is given either by what each agent
observes (``observes``, ``law``, ``actual``: :meth:`KripkeModel.from_observables`) or by
explicit worlds and relations (``world``, ``relation``/``knowledge``/``partition``,
``designated``). The functions take the spec compiler as their first argument and raise its
located :class:`~epistemica.del_.errors.SpecError`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from lark import Token, Tree

from epistemica.del_.errors import EpistemicaError
from epistemica.del_.explicit._model import MAX_ENUMERATED_ATOMS
from epistemica.del_.explicit.checker import propositional_mask
from epistemica.del_.language.formula import Atom, Formula
from epistemica.del_.language.walk import iter_nodes
from epistemica.del_.models import KripkeModel
from epistemica.del_.spec._actions import members, relations

__all__ = ["explicit_model", "observables_model", "observations", "satisfies"]


def observables_model(comp: Any, by_kind: dict[str, list[Tree]], law: Formula) -> Any:
    """The S5 model of ``observes``/``law``/``actual`` statements."""
    atoms = comp.names.atoms
    build = comp.observables or KripkeModel.from_observables
    if comp.observables is None and len(atoms) > MAX_ENUMERATED_ATOMS:
        stmt = by_kind["atoms_decl"][0]
        raise comp.error(
            f"{len(atoms)} atoms give 2^{len(atoms)} valuations, too many to enumerate",
            stmt,
            f"use at most {MAX_ENUMERATED_ATOMS} atoms with 'observes', explicit worlds, or "
            "the symbolic backend (epistemica check --backend symbolic)",
        )
    observes, designated = observations(comp, by_kind)
    actual = by_kind.get("actual_decl", [])
    true = set(designated or ())
    try:
        return build(atoms, observes, law=law, designated=designated)
    except EpistemicaError as exc:
        # The builder checks the actual world against the law too (on the whole model,
        # cheaply); only to locate its error is the law evaluated on that one world here.
        if actual and not satisfies(law, true):
            raise comp.error(
                "the actual world violates the law",
                actual[0],
                f"the law is {law}; the actual world makes true: "
                f"{', '.join(sorted(true)) or 'no atom'}",
            ) from None
        laws = [s.children[0] for s in by_kind.get("law_decl", [])]
        where = (laws or by_kind.get("atoms_decl") or [None])[0]
        raise comp.error(exc.message, where, exc.hint) from None


def observations(
    comp: Any, by_kind: dict[str, list[Tree]]
) -> tuple[dict[str, list[str]], list[str] | None]:
    """What each agent observes, and the atoms true in the ``actual`` world (``None``: no
    ``actual`` line, every world designated)."""
    observes: dict[str, list[str]] = {a: [] for a in comp.names.agents}
    for stmt in by_kind.get("observes_decl", []):
        who, what = stmt.children
        seen = [comp.atom(k, t) for k, t in comp.atom_items(what, {})]
        for name, token in comp.expand(who, {}):
            observes[comp.agent(name, token)].extend(seen)
    actual = by_kind.get("actual_decl", [])
    if len(actual) > 1:
        raise comp.error("a second 'actual' world", actual[1], "keep one 'actual' line")
    if not actual:
        return observes, None
    items = actual[0].children[0]
    true = {comp.atom(k, t) for k, t in comp.atom_items(items, {})} if items else set()
    return observes, sorted(true)


def explicit_model(comp: Any, by_kind: dict[str, list[Tree]], law: Formula) -> KripkeModel:
    """The model of ``world``/``relation``/``designated`` statements."""
    worlds: dict[str, Token] = {}
    valuation: dict[str, set[str]] = {}
    for stmt in by_kind.get("world_decl", []):
        name, items = stmt.children
        if str(name) in worlds:
            first = worlds[str(name)]
            raise comp.error(
                f"world '{name}' declared twice", name,
                f"first declared at {first.line}:{first.column}",
            )  # fmt: skip
        worlds[str(name)] = name
        true = {comp.atom(k, t) for k, t in comp.atom_items(items, {})} if items else set()
        if not satisfies(law, true):
            raise comp.error(f"world '{name}' violates the law", name, f"the law is {law}")
        valuation[str(name)] = true
    if not worlds:
        first = by_kind.get("relation_decl", by_kind.get("designated_decl"))[0]
        raise comp.error("relations but no worlds", first, "declare worlds: world w1 {p}")
    belief, knowledge = relations(
        comp, by_kind.get("relation_decl", []), worlds, "world", conditions=False
    )
    designated_decl = by_kind.get("designated_decl", [])
    if not designated_decl:
        first = next(iter(worlds.values()))
        raise comp.error(
            "no designated world",
            first,
            "add a line such as 'designated w1' (the actual world)",
        )
    designated = members(comp, designated_decl, worlds, "world")
    return KripkeModel(
        list(worlds), valuation, belief, designated, knowledge=knowledge, atoms=comp.names.atoms
    )


def satisfies(f: Formula, true: set[str]) -> bool:
    """Truth of a propositional formula under the valuation making ``true`` true (the
    explicit checker's propositional evaluator, on one row: linear, no recursion)."""
    names = list(dict.fromkeys([*(g.key for g in iter_nodes(f) if isinstance(g, Atom)), *true]))
    row = np.array([[name in true for name in names]], dtype=bool)
    return bool(propositional_mask(f, row, {name: j for j, name in enumerate(names)})[0])
