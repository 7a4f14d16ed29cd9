"""Answers to a question about a mission's model: true, false, or neither.

A mission's model is multi-pointed: one designated world per configuration the robots may
be in (who goes where), so a formula may hold in some of them and not in others. "Does
``closed(g1)`` hold?" is then neither true nor false, and ``~closed(g1)`` neither: the
answer says in how many designated configurations the formula is true
(:func:`answer`). :func:`atom_meanings` says what the mission's atoms mean (``closed(g1)``
is "no robot goes to g1", not "the door of g1 is shut").

Examples
--------
>>> from epistemica.mission import parse_mission
>>> m = parse_mission('''mission rendezvous
... robot r1..r2: range at random
... goal g1..g2 at random''')
>>> answer(m.model, "closed(g1)", m.robots)
(1, 2, 'neither: true in 1 of 2 designated configurations')
>>> answer(m.model, "closed(g1) | closed(g2)", m.robots)[2]
'true (in all 2 designated configurations)'
>>> atom_meanings("C[r1, r2] ~closed(g1)", m.robots)
['closed(g1): no robot goes to g1 (~assigned(r1, g1) & ~assigned(r2, g1))']
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from epistemica.del_ import KripkeModel, parse_formula
from epistemica.del_.explicit.plausibility import PlausibilityModel
from epistemica.del_.language.formula import Formula
from epistemica.sim.engine.events import expand
from epistemica.sim.engine.worlds import closed_fact

__all__ = ["answer", "atom_meanings", "designated_truth"]


def designated_truth(model, formula: Formula) -> tuple[int, int]:
    """``(k, n)``: ``formula`` (``closed(G)`` already expanded) holds at ``k`` of the ``n``
    designated worlds of ``model`` (a Kripke model, a plausibility model, or a knowledge
    structure, whose designated states are counted symbolically)."""
    if isinstance(model, PlausibilityModel):
        truth = np.asarray(model.truth(formula)[model.designated], dtype=bool)
    elif isinstance(model, KripkeModel):
        truth = np.asarray(model.truth_mask(formula)[model.designated_positions], dtype=bool)
    else:
        return int(model.count_designated(formula)), int(model.count_designated())
    return int(truth.sum()), int(truth.size)


def answer(model, formula: Formula | str, robots: Sequence[str]) -> tuple[int, int, str]:
    """``(true_in, designated, text)``: in how many of the designated configurations of
    ``model`` the formula holds, of how many, and the answer in words (``true``,
    ``false``, or ``neither: true in k of n designated configurations``)."""
    tree = parse_formula(formula) if isinstance(formula, str) else formula
    k, n = designated_truth(model, expand(tree, robots))
    if n and k == n:
        return k, n, f"true (in all {n} designated configurations)"
    if k == 0:
        return k, n, f"false (in all {n} designated configurations)"
    return k, n, f"neither: true in {k} of {n} designated configurations"


def atom_meanings(formula: Formula | str, robots: Sequence[str]) -> list[str]:
    """What the ``closed(G)`` atoms of ``formula`` mean on a mission, one line each."""
    tree = parse_formula(formula) if isinstance(formula, str) else formula
    out = []
    for atom in sorted(tree.atoms(), key=str):
        if atom.name == "closed" and len(atom.args) == 1:
            goal = str(atom.args[0])
            out.append(f"{atom}: no robot goes to {goal} ({closed_fact(robots, goal)})")
    return out
