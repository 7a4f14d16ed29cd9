"""Compiling the parse tree of a spec file: declarations, formulas, goal and claims.

Helper of :mod:`epistemica.del_.spec._document`. :class:`Compiler` walks the statements of one
spec by kind (declarations first, so statements may come in any order), checks every
name of every formula against the declarations and builds the parts of a
:class:`~epistemica.del_.spec.Spec`; the initial model is built by
:mod:`epistemica.del_.spec._model`, the actions by :mod:`epistemica.del_.spec._actions`
and names, ranges and schemas are expanded by :mod:`epistemica.del_.spec._names`.
Every meaningful mistake raises a :class:`~epistemica.del_.errors.SpecError` located at
the offending token.

Examples
--------
>>> from epistemica.del_.spec._syntax import parse
>>> text = "agents a, b\\natoms p\\ngoal K[a] p"
>>> parts = Compiler(text, "<string>").compile(parse(text, "<string>", start="start"))
>>> parts.agents, parts.atoms, str(parts.goal)
(('a', 'b'), ('p',), 'K[a] p')
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any, NamedTuple

from lark import Token, Tree

from epistemica.del_.errors import SpecError
from epistemica.del_.language.formula import (
    RESERVED_WORDS,
    And,
    Atom,
    Bottom,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    Top,
    conjunction,
)
from epistemica.del_.language.modalities import After
from epistemica.del_.language.parser import build_imported_formula
from epistemica.del_.language.walk import iter_nodes
from epistemica.del_.models import KripkeModel
from epistemica.del_.spec import _actions as spec_actions
from epistemica.del_.spec import _model as spec_model
from epistemica.del_.spec import _names as spec_names
from epistemica.del_.spec._fast_syntax import FastPathMiss
from epistemica.del_.spec._names import names_hint
from epistemica.del_.spec._plausibility import (
    PlausibilityDeclaration,
    compile_upgrades,
    declared_upgrades,
    plausibility_declaration,
    refuse_uninterpreted,
)
from epistemica.del_.spec._syntax import parse, position

__all__ = ["Check", "Compiled", "Compiler", "Names", "compile_formula"]

_PROPOSITIONAL = (Top, Bottom, Atom, Not, And, Or, Implies, Iff)


@dataclass(frozen=True)
class Check:
    """A claim of a spec file: ``check "name": FORMULA expect true|false``.

    Attributes
    ----------
    name : str
        The quoted name.
    text : str
        The formula as written in the file (whitespace collapsed).
    formula : Formula
        The parsed formula.
    expected : bool
        The expected truth value at the designated worlds (default ``True``).
    filename : str
    line, column : int
        Where the claim starts in the file.
    """

    name: str
    text: str
    formula: Formula
    expected: bool
    filename: str
    line: int
    column: int

    @property
    def location(self) -> str:
        """``FILE:LINE:COL`` of the claim."""
        return f"{self.filename}:{self.line}:{self.column}"


@dataclass(frozen=True)
class Names:
    """The declared names that formulas may use."""

    agents: tuple[str, ...]
    atoms: tuple[str, ...]
    actions: frozenset[str]


class Compiled(NamedTuple):
    """The parts of a compiled spec (the fields of :class:`~epistemica.del_.spec.Spec`)."""

    model: KripkeModel
    actions: dict[str, Any]
    goal: Formula | None
    checks: tuple[Check, ...]
    agents: tuple[str, ...]
    atoms: tuple[str, ...]
    owners: dict[str, str]
    plausibility: PlausibilityDeclaration | None = None
    upgrades: dict[str, tuple[str, Formula]] = {}  # noqa: RUF012 (a NamedTuple default)


def compile_formula(text: str, filename: str, names: Names) -> Formula:
    """Parse ``text`` as one formula over ``names``; errors are located in ``text``."""
    try:
        return Compiler(text, filename, names).formula(parse(text, filename, "fml"), {})
    except FastPathMiss:
        tree = parse(text, filename, "fml", fast=False)
        return Compiler(text, filename, names).formula(tree, {})


class Compiler:
    """Turns the parse tree of one spec text into its :class:`Compiled` parts.

    Parameters
    ----------
    source : str
        The text, for error excerpts.
    filename : str
    names : Names, optional
        The declared names, when compiling a formula for an already compiled spec.
    observables : callable, optional
        Builds the initial model of an ``observes`` spec from ``(atoms, observes, law=,
        designated=)`` instead of :meth:`KripkeModel.from_observables` (the symbolic backend
        passes a chooser that never enumerates 2^n valuations).
    """

    def __init__(
        self,
        source: str,
        filename: str,
        names: Names | None = None,
        observables: Callable[..., Any] | None = None,
    ) -> None:
        self.observables = observables
        self.source = source
        self.filename = filename
        self.names = names or Names((), (), frozenset())
        self.params: dict[str, str] = {}  # parameter -> value, while compiling a schema
        self.action_name = ""
        self.atom_set: frozenset[str] | None = None  # the declared atoms, for the fast path

    # -- errors ---------------------------------------------------------------------------

    def error(self, message: str, where: Token | Tree | None, hint: str | None = None):
        """A :class:`SpecError` located at ``where`` (a token or a tree; None: 1:1)."""
        line, column = position(where) if where is not None else (1, 1)
        return SpecError(
            message, line=line, column=column, source=self.source,
            filename=self.filename, hint=hint,
        )  # fmt: skip

    # -- names ----------------------------------------------------------------------------

    def expand(self, item: Tree | Token, env: Mapping[str, str]) -> list[tuple[str, Token]]:
        """See :func:`epistemica.del_.spec._names.expand`."""
        return spec_names.expand(self, item, env)

    def atom_items(self, node: Tree, env: Mapping[str, str]) -> list[tuple[str, Token]]:
        """See :func:`epistemica.del_.spec._names.atom_items`."""
        return spec_names.atom_items(self, node, env)

    def atom_ref(self, node: Tree, env: Mapping[str, str]) -> tuple[str, Token]:
        """See :func:`epistemica.del_.spec._names.atom_ref`."""
        return spec_names.atom_ref(self, node, env)

    def agent(self, name: str, token: Token) -> str:
        """``name`` if it is a declared agent, else a located error."""
        if name not in self.names.agents:
            raise self.unknown("agent", name, token, self.names.agents)
        return name

    def atom(self, key: str, token: Token) -> str:
        """``key`` if it is a declared atom, else a located error."""
        if key not in self.names.atoms:
            raise self.unknown("atom", key, token, self.names.atoms)
        return key

    def unknown(self, kind: str, name: str, token: Token, declared: Iterable[str]):
        """The error for an undeclared name, with the closest declared one."""
        hint = names_hint(name, declared, kind)
        if self.params:
            params = ", ".join(self.params)
            hint += f"; parameters of action '{self.action_name}': {params}"
        return self.error(f"unknown {kind} '{name}'", token, hint)

    # -- formulas -------------------------------------------------------------------------

    def formula(self, fml: Tree, env: Mapping[str, str]) -> Formula:
        """Check the names of a ``fml`` node, bind parameters and build the Formula."""
        tree = fml.children[0]
        if isinstance(tree, Formula):  # read by the fast path: check the names only
            return self.checked(tree)
        if env:
            tree = spec_names.bind(tree, env)
        for node in tree.iter_subtrees_topdown():
            kind = node.data.rsplit("__", 1)[-1]
            if kind == "atom":
                stem, args = node.children
                if args is None:
                    key = str(stem)
                else:
                    key = f"{stem}({', '.join(str(a) for a in args.children)})"
                if key not in self.names.atoms:
                    self.unbound_argument(args.children if args is not None else [])
                    raise self.unknown("atom", key, stem, self.names.atoms)
            elif kind == "agent":
                token = node.children[0]
                self.agent(str(token), token)
            elif kind == "action":
                stem, args = node.children
                key = str(stem)
                if args is not None:
                    key += f"({', '.join(str(a) for a in args.children)})"
                if key not in self.names.actions:
                    raise self.unknown("action", key, stem, self.names.actions)
        # Iteratively: lark's own transform recurses once per level of nesting.
        return build_imported_formula(tree)

    def checked(self, f: Formula) -> Formula:
        """``f`` if every name it uses is declared; else :class:`FastPathMiss` (the text
        is then parsed again with lark, which locates the unknown name)."""
        if self.atom_set is None:
            self.atom_set = frozenset(self.names.atoms)
        atoms, actions = self.atom_set, self.names.actions
        agents = set(self.names.agents)
        for node in iter_nodes(f):
            kind = type(node)
            if kind is Atom:
                if node.key not in atoms:
                    raise FastPathMiss
            elif kind is After:
                if node.action not in actions:
                    raise FastPathMiss
            elif hasattr(node, "agent"):
                if node.agent not in agents:
                    raise FastPathMiss
            elif hasattr(node, "group") and not agents.issuperset(node.group):
                raise FastPathMiss
        return f

    def unbound_argument(self, args: list[Token]) -> None:
        """Inside a schema, an argument that no declared atom uses is an unbound parameter."""
        if not self.params:
            return
        used = {
            a.strip() for key in self.names.atoms for a in key.partition("(")[2][:-1].split(",")
        }
        bound = set(self.params.values())
        for token in args:
            if str(token) not in used and str(token) not in bound:
                name = self.action_name
                raise self.error(
                    f"unbound parameter '{token}': neither a parameter of action '{name}' "
                    "nor an argument of a declared atom",
                    token,
                    f"parameters of '{name}': {', '.join(self.params)}; bind it in the "
                    f"header, as in action {name}(..., {token} in {{...}})",
                )

    def proposition(self, fml: Tree, what: str) -> Formula:
        """A formula that must be propositional (laws)."""
        f = self.formula(fml, {})
        if not all(isinstance(g, _PROPOSITIONAL) for g in iter_nodes(f)):
            raise self.error(
                f"{what} must be propositional",
                fml,
                "it constrains valuations only; use a 'check' claim for K, B, C, ... formulas",
            )
        return f

    # -- the whole file -------------------------------------------------------------------

    def compile(self, tree: Tree) -> Compiled:
        """Compile the ``start`` tree of a spec file."""
        by_kind: dict[str, list[Tree]] = {}
        for stmt in tree.children:
            by_kind.setdefault(stmt.data, []).append(stmt)
        agents = self.declare(by_kind.get("agents_decl", []), "agent", lambda n: self.expand(n, {}))
        atoms = self.declare(
            by_kind.get("atoms_decl", []), "atom", lambda n: self.atom_items(n, {})
        )
        if not agents:
            raise self.error("no agents declared", None, "start the spec with 'agents a, b'")
        for key, token in atoms.items():
            stem = key.partition("(")[0]
            if stem in RESERVED_WORDS:
                raise self.error(
                    f"'{stem}' is a reserved word and cannot name an atom", token,
                    f"rename it, e.g. to '{stem}_'; reserved: {' '.join(sorted(RESERVED_WORDS))}",
                )  # fmt: skip
            if key in agents:
                raise self.error(f"'{key}' names both an agent and an atom", token, "rename one")
        headers = spec_names.headers(self, by_kind.get("action_decl", []), tuple(agents))
        upgrade_decls = declared_upgrades(self, by_kind.get("upgrade_decl", []), set(headers))
        self.names = Names(tuple(agents), tuple(atoms), frozenset(headers) | set(upgrade_decls))
        self.atom_set = None
        model = self.model(by_kind)
        plausibility = plausibility_declaration(self, by_kind, self.law(by_kind))
        upgrades = compile_upgrades(self, upgrade_decls)
        if upgrades and plausibility is None:
            raise self.error(
                "an upgrade needs a plausibility order",
                by_kind["upgrade_decl"][0],
                "add a line such as 'plausibility a: p, ~p' (most plausible first)",
            )
        actions = spec_actions.compile_actions(self, headers)
        owners = spec_actions.owners(self, headers)
        goals = by_kind.get("goal_decl", [])
        if len(goals) > 1:
            raise self.error("a second goal", goals[1], "join the goals with '&'")
        goal = self.formula(goals[0].children[0], {}) if goals else None
        checks = self.checks(by_kind.get("check_decl", []))
        if plausibility is not None:
            refuse_uninterpreted(self, checks, upgrades)
        return Compiled(
            model,
            actions,
            goal,
            checks,
            tuple(agents),
            tuple(atoms),
            owners,
            plausibility,
            upgrades,
        )

    def declare(self, statements: list[Tree], kind: str, expand) -> dict[str, Token]:
        """Names declared by ``statements`` (in order), each at most once."""
        seen: dict[str, Token] = {}
        for stmt in statements:
            for name, token in expand(stmt.children[0]):
                if name in seen:
                    first = seen[name]
                    raise self.error(
                        f"{kind} '{name}' declared twice",
                        token,
                        f"first declared at {first.line}:{first.column}; remove one",
                    )
                seen[name] = token
            spec_names.check_count(self, len(seen), stmt, f"the {kind}s of the spec")
        return seen

    def checks(self, statements: list[Tree]) -> tuple[Check, ...]:
        """The claims, with distinct names."""
        found: list[Check] = []
        names: dict[str, Token] = {}
        for stmt in statements:
            label, fml, verdict = stmt.children
            name = str(label)[1:-1]
            if name in names:
                first = names[name]
                raise self.error(
                    f"a second check named \"{name}\"", label,
                    f"first at {first.line}:{first.column}; give each claim its own name",
                )  # fmt: skip
            names[name] = label
            text = " ".join(self.source[fml.meta.start_pos : fml.meta.end_pos].split())
            expected = verdict is None or str(verdict.children[0]) == "true"
            formula = self.formula(fml, {})
            line, column = position(stmt)
            found.append(Check(name, text, formula, expected, self.filename, line, column))
        return tuple(found)

    def law(self, by_kind: dict[str, list[Tree]]) -> Formula:
        """The conjunction of the ``law`` lines."""
        return conjunction(
            self.proposition(s.children[0], "a law") for s in by_kind.get("law_decl", [])
        )

    def model(self, by_kind: dict[str, list[Tree]]) -> KripkeModel:
        """The initial model, by observation or explicit worlds (not both)."""
        explicit = by_kind.get("world_decl", []) + by_kind.get("relation_decl", [])
        implicit = by_kind.get("observes_decl", []) + by_kind.get("actual_decl", [])
        if explicit and implicit:
            first = min(implicit, key=lambda t: t.meta.line)
            raise self.error(
                "'observes'/'actual' cannot be mixed with explicit worlds and relations",
                first,
                "describe the model either by what each agent observes or by 'world' and "
                "'relation' lines",
            )
        law = self.law(by_kind)
        if explicit or by_kind.get("designated_decl"):
            return spec_model.explicit_model(self, by_kind, law)
        return spec_model.observables_model(self, by_kind, law)
