"""A robot's plausibility order over configurations: the ``plausibility`` line of a mission.

Helper of :mod:`epistemica._mission_compiler` and :mod:`epistemica.mission`.
``plausibility r1: F0, F1, ...`` ranks the configurations for ``r1``: a configuration's rank
is the index of the first ``Fi`` it satisfies (most plausible first; one satisfying none
comes last). The order has two readings, which agree on what a robot believes:

- the mission's initial model becomes a
  :class:`~epistemica.del_.explicit.plausibility.PlausibilityModel` (the worlds and
  information cells of the Kripke model, these ranks), where claims may use ``B[r | c]``,
  ``Sb[r]`` and upgrades (:func:`plausibility_model`);
- in the simulator the order is the robot's first *soft* evidence
  (:func:`initial_beliefs`): the disjoint levels ``F0``, ``F1 & ~F0``, ... suggested oldest
  last, so that the belief of :class:`~epistemica.del_.state.EpistemicState` (its soft facts
  applied newest first, each kept only if a configuration is left) is the most plausible
  configurations the hard evidence allows. An observation that rules them out revises the
  belief to the most plausible of the rest instead of emptying it; a later ``suggests``
  still wins over the order (recency).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from lark import Token, Tree

from epistemica.del_ import (
    And,
    Common,
    CommonBelief,
    ConditionalBelief,
    ConservativeUpgrade,
    Distributed,
    Formula,
    KripkeModel,
    Not,
    PlausibilityModel,
    RadicalUpgrade,
    SafeBelief,
)
from epistemica.del_.errors import SpecError
from epistemica.del_.explicit.relations import Partition
from epistemica.del_.language.walk import iter_nodes

__all__ = [
    "PlausibilityOrder",
    "check_orders",
    "disjoint_levels",
    "initial_beliefs",
    "plausibility_model",
    "plausibility_order",
]

#: Operators that only a plausibility model interprets.
_PLAUSIBILITY_ONLY = (ConditionalBelief, SafeBelief, RadicalUpgrade, ConservativeUpgrade)


@dataclass(frozen=True)
class PlausibilityOrder:
    """One ``plausibility`` line: its robots, its levels (most plausible first), where."""

    robots: tuple[str, ...]
    levels: tuple[Formula, ...]
    token: Token


def plausibility_order(comp: Any, node: Tree) -> PlausibilityOrder:
    """The order of a ``plausibility_decl`` node, its robots and levels checked."""
    robots, *formulas = node.children
    names = []
    for token in robots.children:
        name = comp.robot_name(token)
        for earlier in comp.plausibility:
            if name in earlier.robots:
                raise comp.error(
                    f"a second plausibility order for robot '{name}'",
                    token,
                    f"first given at line {earlier.token.line}; list all levels in one line",
                )
        names.append(name)
    if comp.kind.tasks:
        raise comp.error(
            f"a {comp.kind} mission has no configurations to rank",
            node,
            "plausibility orders are for rendezvous, allocation and capacity missions",
        )
    levels = tuple(comp.fact(f) for f in formulas)
    return PlausibilityOrder(tuple(names), levels, robots.children[0])


def check_orders(comp: Any) -> None:
    """The checks that need the whole file: an order and the claims, an order and
    ``knows`` (a robot unaware of a goal: not modelled by the plausibility model)."""
    if not comp.plausibility:
        return
    first = comp.plausibility[0].token
    if comp.knows or comp.random_knowledge:
        raise comp.error(
            "a plausibility order in a mission with 'knows' lines is not supported yet",
            first,
            "the plausibility model has every robot aware of every goal: drop 'knows'",
        )
    for claim in comp.checks:
        for node in iter_nodes(claim.check.formula):
            if claim.after is None and isinstance(node, (Common, CommonBelief, Distributed)):
                what, why = f"{node.keyword}[...]", "a plausibility model does not interpret it"
            elif claim.after is not None and isinstance(node, _PLAUSIBILITY_ONLY):
                what = "conditional belief, safe belief or an upgrade"
                why = "a claim 'after N steps' is checked on the Kripke model of the trial"
            else:
                continue
            raise SpecError(
                f"claim \"{claim.check.name}\" uses {what}: {why}",
                line=claim.check.line, column=claim.check.column, source=comp.source,
                filename=comp.filename,
                hint="initial claims of a mission with 'plausibility' use K, B, B[r | f], Sb, "
                "E, EB and upgrades; claims after steps use K, B, C, ...",
            )  # fmt: skip


def disjoint_levels(levels: tuple[Formula, ...]) -> tuple[Formula, ...]:
    """``F0, F1 & ~F0, F2 & ~F0 & ~F1, ...``: level ``i`` holds where ``Fi`` is the first
    level that does.

    Examples
    --------
    >>> from epistemica.del_ import parse_formula
    >>> [str(f) for f in disjoint_levels((parse_formula("p"), parse_formula("q")))]
    ['p', 'q & ~p']
    """
    out, before = [], []
    for level in levels:
        part = level
        for earlier in before:
            part = And(part, Not(earlier))
        out.append(part)
        before.append(level)
    return tuple(out)


def initial_beliefs(
    orders: tuple[PlausibilityOrder, ...], robots: tuple[str, ...]
) -> tuple[tuple[tuple[bool, ...], Formula], ...]:
    """The soft facts of the orders, oldest first, with their observers (``n`` booleans):
    per line, the disjoint levels from the least plausible to the most plausible, so that
    the most plausible is the newest (tried first)."""
    out = []
    for order in orders:
        mask = tuple(r in order.robots for r in robots)
        out.extend((mask, level) for level in reversed(disjoint_levels(order.levels)))
    return tuple(out)


def plausibility_model(
    model: KripkeModel, orders: tuple[PlausibilityOrder, ...]
) -> PlausibilityModel:
    """``model`` (the mission's initial Kripke model) with the orders: its worlds, each
    robot's information cells (its knowledge partition), designated worlds, and per robot
    the rank of its order (a robot without one finds every world of a cell as plausible)."""
    cells, ranks = {}, {}
    for robot in model.agents:
        relation = model.knowledge_relations[robot]
        if not isinstance(relation, Partition):  # group models partition: a safeguard
            raise SpecError(
                f"robot '{robot}''s knowledge does not partition the configurations",
                hint="a plausibility model needs information cells",
            )
        cells[robot] = relation.labels
        ranks[robot] = np.zeros(model.n_worlds, dtype=np.int64)
    designated = np.zeros(model.n_worlds, dtype=bool)
    designated[model.designated_positions] = True
    flat = PlausibilityModel(model.atoms, model.valuation, cells, ranks, designated)
    for order in orders:
        rank = np.full(model.n_worlds, len(order.levels), dtype=np.int64)
        for i in range(len(order.levels) - 1, -1, -1):
            rank[flat.truth(order.levels[i])] = i
        for robot in order.robots:
            ranks[robot] = rank
    return PlausibilityModel(model.atoms, model.valuation, cells, ranks, designated)
