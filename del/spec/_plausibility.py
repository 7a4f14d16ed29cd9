"""The plausibility statements of a spec file: ``plausibility`` and ``upgrade``.

Helper of :mod:`epistemica.del_.spec._document`. ``plausibility a, b: F0, F1, ...`` ranks
the worlds of the model by observation for agents ``a`` and ``b``: a world's rank is the
index of the first ``Fi`` it satisfies (most plausible first; a world satisfying none comes
last). ``upgrade NAME: radical F`` (or ``conservative F``) names a public soft
announcement, which claims use as ``[NAME] g``: it stands for ``[^^F] g`` (``[^F] g``).
A spec with a ``plausibility`` line evaluates its claims in the plausibility model
(:class:`~epistemica.del_.explicit.plausibility.PlausibilityModel`, or
:class:`~epistemica.del_.symbolic.plausibility.PlausibilityStructure` on the symbolic
backend), where ``B[a]`` is belief in the most plausible worlds of a's cell.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from lark import Tree

from epistemica.del_.errors import SpecError
from epistemica.del_.explicit.plausibility import PlausibilityModel
from epistemica.del_.language.formula import Formula, fold, with_children
from epistemica.del_.language.modalities import (
    After,
    Common,
    CommonBelief,
    ConservativeUpgrade,
    Distributed,
    RadicalUpgrade,
)
from epistemica.del_.language.walk import iter_nodes
from epistemica.del_.spec._model import observations
from epistemica.del_.symbolic.plausibility import PlausibilityStructure

__all__ = [
    "PlausibilityDeclaration",
    "compile_upgrades",
    "declared_upgrades",
    "plausibility_declaration",
    "refuse_uninterpreted",
    "resolve_upgrades",
]


@dataclass(frozen=True)
class PlausibilityDeclaration:
    """The arguments of ``from_levels`` on either backend."""

    atoms: tuple[str, ...]
    levels: dict[str, list[Formula]]
    observes: dict[str, list[str]]
    law: Formula
    designated: list[str] | None

    def build(self, symbolic: bool) -> PlausibilityModel | PlausibilityStructure:
        """The explicit model, or the symbolic structure."""
        kind = PlausibilityStructure if symbolic else PlausibilityModel
        return kind.from_levels(self.atoms, self.levels, self.observes, self.law, self.designated)


def plausibility_declaration(
    comp: Any, by_kind: dict[str, list[Tree]], law: Formula
) -> PlausibilityDeclaration | None:
    """The declaration of the spec's ``plausibility`` lines, or ``None`` without any."""
    statements = by_kind.get("plausibility_decl", [])
    if not statements:
        return None
    explicit = by_kind.get("world_decl", []) + by_kind.get("relation_decl", [])
    if explicit:
        raise comp.error(
            "'plausibility' needs the model by observation",
            statements[0],
            "describe the model with 'observes' and 'actual' lines; plausibility over "
            "explicit worlds is not supported yet",
        )
    levels: dict[str, list[Formula]] = {a: [] for a in comp.names.agents}
    ranked: dict[str, Tree] = {}
    for stmt in statements:
        who, *formulas = stmt.children
        for name, token in comp.expand(who, {}):
            agent = comp.agent(name, token)
            if agent in ranked:
                first = ranked[agent]
                raise comp.error(
                    f"a second plausibility order for agent '{agent}'",
                    token,
                    f"first given at line {first.meta.line}; list all levels in one line",
                )
            ranked[agent] = stmt
            levels[agent] = [comp.proposition(f, "a plausibility level") for f in formulas]
    observes, designated = observations(comp, by_kind)
    return PlausibilityDeclaration(comp.names.atoms, levels, observes, law, designated)


def declared_upgrades(comp: Any, statements: list[Tree], taken: set[str]) -> dict[str, Tree]:
    """The names of the ``upgrade`` statements (checked distinct from ``taken``)."""
    found: dict[str, Tree] = {}
    for stmt in statements:
        name = stmt.children[0]
        if str(name) in found or str(name) in taken:
            raise comp.error(
                f"'{name}' is declared twice (as an action or upgrade)", name, "rename one"
            )
        found[str(name)] = stmt
    return found


def compile_upgrades(comp: Any, statements: dict[str, Tree]) -> dict[str, tuple[str, Formula]]:
    """Upgrade name -> (``"radical"`` or ``"conservative"``, the upgrading formula)."""
    upgrades = {}
    for name, stmt in statements.items():
        _, kind, fml = stmt.children
        upgrades[name] = (str(kind.children[0]), comp.formula(fml, {}))
    return upgrades


def resolve_upgrades(formula: Formula, upgrades: dict[str, tuple[str, Formula]]) -> Formula:
    """``formula`` with every ``[NAME] g`` of a declared upgrade written as the upgrade."""
    if not upgrades:
        return formula

    def rebuild(node: Formula, inner: tuple[Formula, ...]) -> Formula:
        if isinstance(node, After) and node.action in upgrades:
            kind, f = upgrades[node.action]
            return (RadicalUpgrade if kind == "radical" else ConservativeUpgrade)(f, inner[0])
        return with_children(node, inner)

    return fold(formula, rebuild)


def refuse_uninterpreted(comp: Any, checks: Any, upgrades: dict[str, tuple[str, Formula]]) -> None:
    """A located error for a claim that a plausibility model does not interpret: a named
    action (not an upgrade), common or distributed knowledge, common belief."""
    for check in checks:
        for node in iter_nodes(check.formula):
            if isinstance(node, After) and node.action not in upgrades:
                what = f"the action '{node.action}'"
            elif isinstance(node, (Common, CommonBelief, Distributed)):
                what = f"{node.keyword}[...]"
            else:
                continue
            raise SpecError(
                f"claim \"{check.name}\" uses {what}, which plausibility models do not interpret",
                line=check.line, column=check.column, source=comp.source,
                filename=comp.filename,
                hint="claims of a spec with 'plausibility' use K, B, B[a | f], Sb, E, EB, "
                "announcements and upgrades",
            )  # fmt: skip
