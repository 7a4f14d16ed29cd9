"""Spec files (``.epi``): an initial Kripke model, actions, a goal and checked claims.

The grammar is ``spec.lark``, which imports the formula rules of ``formula.lark``; this
module compiles its parse tree into a :class:`Spec`. Every meaningful mistake (an unknown
agent or atom, a name declared twice, a law nothing satisfies, an unbound parameter, ...)
raises :class:`~epistemica.del_.errors.SpecError` pointing at the offending token of the
file, with a hint; malformed text raises :class:`~epistemica.del_.errors.ParseError`.
See ``docs/language.md``, section "Spec files", for the language.

Examples
--------
>>> spec = parse_spec('''
... agents a, b
... atoms heads
... actual {heads}
... action show: sense heads by b
... check "b learns the coin": [show] (Kw[b] heads & ~Kw[a] heads & K[a] Kw[b] heads)
... ''')
>>> spec.model.n_worlds, sorted(spec.actions)
(2, ['show'])
>>> [(c.name, c.expected, spec.holds(c.formula)) for c in spec.checks]
[('b learns the coin', True, True)]
"""

from __future__ import annotations

import difflib
import functools
import itertools
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from lark import Lark, Token, Transformer, Tree
from lark.exceptions import UnexpectedInput, VisitError
from lark.visitors import merge_transformers

from epistemica.del_ import spec_actions, spec_model
from epistemica.del_.errors import ParseError, SpecError
from epistemica.del_.formula import (
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
from epistemica.del_.kripke import KripkeModel
from epistemica.del_.parser import FORMULA_GRAMMAR, FormulaBuilder, syntax_error
from epistemica.del_.spec_actions import names_hint

__all__ = ["Check", "Spec", "load_spec", "parse_spec"]

SPEC_GRAMMAR = Path(__file__).with_name("spec.lark")

# A range such as m1..m1000000 is almost certainly a typo; refuse it before it eats memory.
_MAX_RANGE = 100_000
_NUMBERED = re.compile(r"^(.*?)(\d+)$")
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


@dataclass(frozen=True, eq=False)
class Spec:
    """A compiled spec file.

    Attributes
    ----------
    model : KripkeModel
        The initial model.
    actions : dict
        Action name -> :class:`~epistemica.del_.action.ActionModel`; a parametrised schema
        contributes one entry per binding, named like ``open(a)``.
    goal : Formula or None
    checks : tuple of Check
    agents, atoms : tuple of str
        In declaration order (atoms canonical, as in ``at(r1, g1)``).
    filename : str
    source : str
        The text of the spec.
    """

    model: KripkeModel
    actions: dict[str, Any]
    goal: Formula | None
    checks: tuple[Check, ...]
    agents: tuple[str, ...]
    atoms: tuple[str, ...]
    filename: str
    source: str = field(repr=False)

    def __repr__(self) -> str:
        return (
            f"<Spec {self.filename}: {len(self.agents)} agents, {len(self.atoms)} atoms, "
            f"{self.model.n_worlds} worlds, {len(self.actions)} actions, {len(self.checks)} checks>"
        )

    def holds(self, formula: Formula | str) -> bool:
        """Whether ``formula`` holds at the designated worlds, resolving ``[ACT]`` here."""
        if isinstance(formula, str):
            formula = self.formula(formula)
        return self.model.holds(formula, actions=self.actions)

    def formula(self, text: str, filename: str = "<formula>") -> Formula:
        """Parse ``text`` as a formula over this spec's agents, atoms and actions.

        Raises
        ------
        ParseError, SpecError
            Located in ``text`` (e.g. an atom the spec does not declare).

        Examples
        --------
        >>> spec = parse_spec("agents a\\natoms p")
        >>> print(spec.formula("K[a] p | ~p"))
        K[a] p | ~p
        >>> spec.formula("K[a] q")
        Traceback (most recent call last):
        ...
        epistemica.del_.errors.SpecError: <formula>:1:6: error: unknown atom 'q'
            K[a] q
                 ^
        hint: declared atoms: p
        """
        if not text.strip():
            raise ParseError(
                "empty formula", line=1, column=1, source=text, filename=filename,
                hint="write a formula such as 'K[a] p'",
            )  # fmt: skip
        tree = _parse(text, filename, start="fml")
        names = _Names(self.agents, self.atoms, frozenset(self.actions))
        return _Compiler(text, filename, names).formula(tree, {})


def parse_spec(text: str, filename: str = "<string>") -> Spec:
    """Compile the text of a spec file.

    Parameters
    ----------
    text : str
        The spec, in the language of ``docs/language.md``.
    filename : str
        Shown in error messages.

    Raises
    ------
    ParseError
        The text does not follow the grammar.
    SpecError
        It parses but is not meaningful; the error names the offending token.

    Examples
    --------
    >>> spec = parse_spec('''
    ... agents c1, c2
    ... atoms m1..m2
    ... observes c1: m2
    ... observes c2: m1
    ... actual {m1, m2}
    ... ''')
    >>> spec.holds("~Kw[c1] m1 & K[c1] m2")
    True
    >>> parse_spec("agents a\\natoms p\\ngoal K[b] p")
    Traceback (most recent call last):
    ...
    epistemica.del_.errors.SpecError: <string>:3:8: error: unknown agent 'b'
        goal K[b] p
               ^
    hint: declared agents: a
    """
    tree = _parse(text, filename, start="start")
    return _Compiler(text, filename).compile(tree)


def load_spec(path: str | Path) -> Spec:
    """Read and compile a spec file.

    Raises
    ------
    SpecError
        The file cannot be read (no line number), or see :func:`parse_spec`.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise SpecError(
            f"cannot read the spec file: {reason}",
            filename=str(path),
            hint="check the path; spec files are UTF-8 text such as specs/puzzles/*.epi",
        ) from None
    return parse_spec(text, filename=str(path))


# --------------------------------------------------------------------------------------
# Parsing
# --------------------------------------------------------------------------------------


class _SplitWord(Exception):
    def __init__(self, keyword: Token, rest: Token) -> None:
        super().__init__(f"{keyword}{rest}")
        self.keyword, self.rest = keyword, rest


class _WholeWords:
    """Post-lexer: a keyword glued to the next word ("actions x") is a misspelling.

    String keywords are matched without a word boundary, so the contextual lexer would
    otherwise read "actions" as the keyword "action" followed by the name "s".
    """

    always_accept = ()

    def process(self, stream):
        previous = None
        for token in stream:
            if (
                previous is not None
                and previous.end_pos == token.start_pos
                and previous.value.isalpha()
                and (token.value[:1].isalnum() or token.value[:1] == "_")
            ):
                raise _SplitWord(previous, token)
            previous = token
            yield token


@functools.cache
def _lark() -> Lark:
    return Lark.open(
        str(SPEC_GRAMMAR),
        parser="lalr",
        start=["start", "fml"],
        propagate_positions=True,
        maybe_placeholders=True,
        import_paths=[str(FORMULA_GRAMMAR.parent)],
        postlex=_WholeWords(),
    )


def _parse(text: str, filename: str, start: str) -> Tree:
    try:
        return _lark().parse(text, start=start)
    except _SplitWord as exc:
        word = re.match(r"\w+", text[exc.keyword.start_pos :]).group(0)
        raise ParseError(
            f"unknown keyword '{word}'",
            line=exc.keyword.line,
            column=exc.keyword.column,
            source=text,
            filename=filename,
            hint=_keyword_hint(word),
        ) from None
    except UnexpectedInput as exc:
        error = syntax_error(exc, text, filename)
        if "_BECOMES" in (getattr(exc, "allowed", None) or ()):
            error.hint = _CONTEXT_HINTS["_BECOMES"]
        elif error.hint is None:
            error.hint = _statement_hint(exc)
        raise error from None


_KEYWORDS = (
    "agents", "atoms", "observes", "law", "actual", "world", "relation", "knowledge",
    "partition", "designated", "action", "goal", "check",
)  # fmt: skip


_CONTEXT_HINTS = {
    "IN": "a parameter is written 'i in {a, b}' or 'i in agents'",
    "TRUE": "write 'expect true' or 'expect false'",
    "COLON": "write 'action NAME: public F' (one line) or 'action NAME { ... }' (a block)",
    "_BECOMES": "an effect is written 'atom := formula'",
}


def _keyword_hint(word: str) -> str:
    close = difflib.get_close_matches(word, _KEYWORDS, n=1)
    if close:
        return f"did you mean '{close[0]}'?"
    return "each statement starts with a keyword: " + ", ".join(_KEYWORDS)


def _statement_hint(exc: UnexpectedInput) -> str | None:
    expected = set(getattr(exc, "expected", ()) or ())
    token = getattr(exc, "token", None)
    if "AGENTS" in expected:  # at the start of a statement
        word = str(token or "")
        if "COMMA" in expected and not difflib.get_close_matches(word, _KEYWORDS, n=1):
            return f"separate the items of a list with ',' (found '{word}' after an item)"
        return _keyword_hint(word)
    for terminal, hint in _CONTEXT_HINTS.items():
        if terminal in expected:
            return hint
    return None


# --------------------------------------------------------------------------------------
# Compiling
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Names:
    agents: tuple[str, ...]
    atoms: tuple[str, ...]
    actions: frozenset[str]


class _Base(Transformer):
    """Placeholder root transformer: only the merged formula methods are used."""


def _position(item: Token | Tree) -> tuple[int | None, int | None]:
    if isinstance(item, Token):
        return item.line, item.column
    meta = item.meta
    return getattr(meta, "line", None), getattr(meta, "column", None)


class _Compiler:
    """Turns the parse tree of one spec text into a :class:`Spec`."""

    def __init__(self, source: str, filename: str, names: _Names | None = None) -> None:
        # A spec is compiled in one pass over its statements by kind (declarations first),
        # so statements may come in any order.
        self.source = source
        self.filename = filename
        self.names = names or _Names((), (), frozenset())
        self.params: dict[str, str] = {}  # parameter -> value, while compiling a schema
        self.action_name = ""

    # -- errors ---------------------------------------------------------------------------

    def error(self, message: str, where: Token | Tree | None, hint: str | None = None):
        line, column = _position(where) if where is not None else (1, 1)
        return SpecError(
            message, line=line, column=column, source=self.source,
            filename=self.filename, hint=hint,
        )  # fmt: skip

    # -- names and ranges -----------------------------------------------------------------

    def expand(self, item: Tree | Token, env: Mapping[str, str]) -> list[tuple[str, Token]]:
        """Names of a ``names``/``name`` node with ranges expanded and parameters bound."""
        if isinstance(item, Token):
            return [(env.get(str(item), str(item)), item)]
        if item.data == "names" or item.data == "arguments":
            return [pair for child in item.children for pair in self.expand(child, env)]
        if item.data in ("single", "number"):
            return self.expand(item.children[0], env)
        if item.data == "indexed":
            stem, low, high = item.children
            return self._range(stem, str(stem), int(low), int(high), len(str(low)), high)
        first, last = item.children  # span: m1..m4
        head, tail = _NUMBERED.match(str(first)), _NUMBERED.match(str(last))
        if head is None or tail is None or head.group(1) != tail.group(1):
            raise self.error(
                f"cannot expand the range {first}..{last}",
                first,
                "a range joins two names that differ only in a final number, as in m1..m4",
            )
        digits = head.group(2)
        return self._range(first, head.group(1), int(digits), int(tail.group(2)), len(digits), last)

    def _range(self, at: Token, stem: str, low: int, high: int, width: int, end: Token):
        if high < low:
            raise self.error(f"empty range from {low} to {high}", end, "write the smaller first")
        if high - low >= _MAX_RANGE:
            raise self.error(
                f"the range has {high - low + 1} names, more than {_MAX_RANGE}", end,
                "check the bounds of the range",
            )  # fmt: skip
        width = width if width > 1 else 1  # m01..m10 keeps its zero padding
        return [(f"{stem}{i:0{width}d}", at) for i in range(low, high + 1)]

    def atom_items(self, node: Tree, env: Mapping[str, str]) -> list[tuple[str, Token]]:
        """Atom keys of an ``atoms`` node (predicates expanded over their argument ranges)."""
        found = []
        for child in node.children:
            if isinstance(child, Tree) and child.data == "predicate":
                stem, arguments = child.children
                options = [[n for n, _ in self.expand(a, env)] for a in arguments.children]
                for combo in itertools.product(*options):
                    found.append((f"{stem}({', '.join(combo)})", stem))
            else:
                found.extend(self.expand(child, env))
        return found

    def atom_ref(self, node: Tree, env: Mapping[str, str]) -> tuple[str, Token]:
        stem, arguments = node.children
        if arguments is None:
            return env.get(str(stem), str(stem)), stem
        args = [n for n, _ in self.expand(arguments, env)]
        return f"{stem}({', '.join(args)})", stem

    def agent(self, name: str, token: Token) -> str:
        if name not in self.names.agents:
            raise self.unknown("agent", name, token, self.names.agents)
        return name

    def atom(self, key: str, token: Token) -> str:
        if key not in self.names.atoms:
            raise self.unknown("atom", key, token, self.names.atoms)
        return key

    def unknown(self, kind: str, name: str, token: Token, declared: Iterable[str]):
        hint = names_hint(name, declared, kind)
        if self.params:
            params = ", ".join(self.params)
            hint += f"; parameters of action '{self.action_name}': {params}"
        return self.error(f"unknown {kind} '{name}'", token, hint)

    # -- formulas -------------------------------------------------------------------------

    def formula(self, fml: Tree, env: Mapping[str, str]) -> Formula:
        """Check the names of a ``fml`` node, bind parameters and build the Formula."""
        tree = fml.children[0]
        if env:
            tree = _bind(tree, env)
        for node in tree.iter_subtrees_topdown():
            kind = node.data.rsplit("__", 1)[-1]
            if kind == "atom":
                stem, args = node.children
                if args is None:
                    key = str(stem)
                else:
                    key = f"{stem}({', '.join(str(a) for a in args.children)})"
                if key not in self.names.atoms:
                    self._unbound_argument(args.children if args is not None else [])
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
        try:
            return _builder().transform(tree)
        except VisitError as exc:  # pragma: no cover - names were checked above
            raise self.error(str(exc.orig_exc), fml) from None

    def _unbound_argument(self, args: list[Token]) -> None:
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
        f = self.formula(fml, {})
        if not all(isinstance(g, _PROPOSITIONAL) for g in f.subformulas()):
            raise self.error(
                f"{what} must be propositional",
                fml,
                "it constrains valuations only; use a 'check' claim for K, B, C, ... formulas",
            )
        return f

    # -- the whole file -------------------------------------------------------------------

    def compile(self, tree: Tree) -> Spec:
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
            if key in agents:
                raise self.error(f"'{key}' names both an agent and an atom", token, "rename one")
        headers = spec_actions.headers(self, by_kind.get("action_decl", []), tuple(agents))
        self.names = _Names(tuple(agents), tuple(atoms), frozenset(headers))
        model = self.model(by_kind)
        actions = spec_actions.compile_actions(self, headers)
        goals = by_kind.get("goal_decl", [])
        if len(goals) > 1:
            raise self.error("a second goal", goals[1], "join the goals with '&'")
        goal = self.formula(goals[0].children[0], {}) if goals else None
        checks = self.checks(by_kind.get("check_decl", []))
        return Spec(
            model, actions, goal, checks, tuple(agents), tuple(atoms), self.filename, self.source
        )

    def declare(self, statements: list[Tree], kind: str, expand) -> dict[str, Token]:
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
        return seen

    def checks(self, statements: list[Tree]) -> tuple[Check, ...]:
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
            line, column = _position(stmt)
            found.append(Check(name, text, formula, expected, self.filename, line, column))
        return tuple(found)

    # -- the initial model ----------------------------------------------------------------

    def model(self, by_kind: dict[str, list[Tree]]) -> KripkeModel:
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
        law = conjunction(
            self.proposition(s.children[0], "a law") for s in by_kind.get("law_decl", [])
        )
        if explicit or by_kind.get("designated_decl"):
            return spec_model.explicit_model(self, by_kind, law)
        return spec_model.observables_model(self, by_kind, law)


def _bind(tree: Tree, env: Mapping[str, str]) -> Tree:
    """A copy of a formula tree with parameter names replaced, positions kept."""
    children = []
    for child in tree.children:
        if isinstance(child, Tree):
            children.append(_bind(child, env))
        elif isinstance(child, Token) and child.type in ("NAME", "INT") and str(child) in env:
            children.append(child.update(value=env[str(child)]))
        else:
            children.append(child)
    return Tree(tree.data, children, tree.meta)


@functools.cache
def _builder() -> Transformer:
    return merge_transformers(_Base(), formula=FormulaBuilder())
