"""Parse formulas written in the concrete syntax of ``formula.lark``.

``parse_formula`` turns text into a :class:`~epistemica.del_.language.formula.Formula` tree and
reports malformed text as a :class:`~epistemica.del_.errors.ParseError` that points at the
offending character, says what was expected and suggests a fix (the wording comes from
:mod:`~epistemica.del_.language._syntax_errors`). ``FormulaBuilder`` is the lark transformer behind
it, public so that grammars importing ``formula.lark`` (the spec files) build the same
trees.

Examples
--------
>>> f = parse_formula("[!p | q] K[a] (p -> ~q)")
>>> f
Announce(announcement=Or(left=Atom(name='p', args=()), right=Atom(name='q', args=())), \
operand=Know(agent='a', operand=Implies(left=Atom(name='p', args=()), \
right=Not(operand=Atom(name='q', args=())))))
>>> print(parse_formula("not p and q => r"))
~p & q -> r
>>> parse_formula("K[alcie] p", agents=["alice", "bob"])
Traceback (most recent call last):
...
epistemica.del_.errors.SpecError: <formula>:1:3: error: unknown agent 'alcie'
    K[alcie] p
      ^
hint: declared agents: alice, bob; did you mean 'alice'?
"""

from __future__ import annotations

import difflib
import functools
from collections.abc import Collection
from pathlib import Path
from typing import Any

from lark import Lark, Token, Transformer, Tree
from lark.exceptions import UnexpectedInput
from lark.visitors import merge_transformers

from epistemica.del_.errors import InvalidArgumentError, ParseError, SpecError
from epistemica.del_.language._fast import read_formula, tokenize
from epistemica.del_.language._syntax_errors import syntax_error
from epistemica.del_.language.formula import (
    RESERVED_WORDS,  # re-exported for the grammar users
    And,
    Atom,
    Bottom,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    Top,
)
from epistemica.del_.language.modalities import (
    After,
    Announce,
    AnnounceDiamond,
    Believe,
    Common,
    CommonBelief,
    ConditionalBelief,
    ConservativeUpgrade,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Know,
    KnowWhether,
    RadicalUpgrade,
    SafeBelief,
)
from epistemica.del_.language.walk import iter_postorder

# syntax_error is re-exported for the spec grammar, which imports formula.lark.
__all__ = [
    "FORMULA_GRAMMAR",
    "RESERVED_WORDS",
    "FormulaBuilder",
    "as_formula",
    "build_imported_formula",
    "parse_formula",
    "read_whole_formula",
    "syntax_error",
    "transform_iteratively",
]

#: Path of the grammar file, for ``import_paths`` of grammars that ``%import`` it.
FORMULA_GRAMMAR = Path(__file__).with_name("formula.lark")


def _names(tokens: list[Token]) -> tuple[str, ...]:
    return tuple(str(t) for t in tokens)


def transform_iteratively(transformer: Any, tree: Tree) -> Any:
    """Apply a lark transformer bottom-up with an explicit stack instead of recursion.

    ``lark.Transformer.transform`` recurses once per tree level, so a formula nested a
    few hundred deep (or a chain of a few hundred ``&``) exhausts Python's stack; this
    visits the same nodes in the same order in time linear in the size of the tree.

    Parameters
    ----------
    transformer : object
        Has a method per rule name, called with the list of transformed children (as
        ``lark.Transformer`` calls them; tokens are passed through unchanged), and
        ``__default__(data, children, meta)`` for the other rules.
    tree : lark.Tree

    Returns
    -------
    object
        What the method of the root rule returns.

    Notes
    -----
    Exceptions raised by the methods propagate unchanged (lark would wrap them in
    ``VisitError``).

    Examples
    --------
    >>> lark = Lark.open(str(FORMULA_GRAMMAR), parser="lalr", start="formula")
    >>> print(transform_iteratively(FormulaBuilder(), lark.parse("~~p & K[a] q")))
    ~~p & K[a] q
    """
    values: list[Any] = []
    # A Tree on the stack is still to expand; (tree, n) waits for its n subtrees' values.
    stack: list[Tree | tuple[Tree, int]] = [tree]
    while stack:
        item = stack.pop()
        if isinstance(item, Tree):
            subtrees = [c for c in item.children if isinstance(c, Tree)]
            stack.append((item, len(subtrees)))
            stack.extend(reversed(subtrees))
            continue
        node, count = item
        children = list(node.children)
        if count:  # the subtrees' values are the last `count` values, in order
            done = iter(values[-count:])
            del values[-count:]
            children = [next(done) if isinstance(c, Tree) else c for c in children]
        method = getattr(transformer, node.data, None)
        if method is None:
            values.append(transformer.__default__(node.data, children, node.meta))
        else:
            values.append(method(children))
    return values[0]


class FormulaBuilder(Transformer):
    """Turn a parse tree of ``formula.lark`` into a :class:`Formula`.

    Parameters
    ----------
    agents, actions : collection of str, optional
        When given, an agent (or action) not in the collection raises :class:`SpecError`
        at its position. An action ``open(a)`` is accepted when either ``open(a)`` or
        ``open`` is declared.
    source : str, optional
        The parsed text, used to render error excerpts.
    filename : str
        Where the text came from, for error messages.

    Notes
    -----
    ``transform`` works with an explicit stack (:func:`transform_iteratively`), so deep
    and long formulas need no recursion, and raises the :class:`SpecError` itself (not
    wrapped in lark's ``VisitError``). To use the builder on a grammar that imports
    ``formula.lark``, merge it:
    ``lark.visitors.merge_transformers(SpecBuilder(), formula=FormulaBuilder())`` and
    apply the merged transformer with :func:`transform_iteratively`.

    Examples
    --------
    >>> from lark import Lark
    >>> lark = Lark.open(str(FORMULA_GRAMMAR), parser="lalr", start="formula")
    >>> FormulaBuilder().transform(lark.parse("M[a] p"))
    Not(operand=Know(agent='a', operand=Not(operand=Atom(name='p', args=()))))
    """

    def __init__(
        self,
        *,
        agents: Collection[str] | None = None,
        actions: Collection[str] | None = None,
        source: str | None = None,
        filename: str = "<formula>",
    ) -> None:
        super().__init__()
        self.agents = None if agents is None else frozenset(str(a) for a in agents)
        self.actions = None if actions is None else frozenset(str(a) for a in actions)
        self.source = source
        self.filename = filename

    def transform(self, tree: Tree) -> Any:
        """The :class:`Formula` of a parse tree (see :func:`transform_iteratively`)."""
        return transform_iteratively(self, tree)

    # -- names, checked against the declarations --------------------------------------
    def _unknown(self, kind: str, token: Token, text: str, declared: frozenset[str]) -> None:
        listing = ", ".join(sorted(declared)) if declared else "none"
        hint = f"declared {kind}s: {listing}"
        close = difflib.get_close_matches(text, sorted(declared), n=1)
        if close:
            hint += f"; did you mean '{close[0]}'?"
        raise SpecError(
            f"unknown {kind} '{text}'",
            line=token.line,
            column=token.column,
            source=self.source,
            filename=self.filename,
            hint=hint,
        )

    def _agent(self, token: Token) -> str:
        name = str(token)
        if self.agents is not None and name not in self.agents:
            self._unknown("agent", token, name, self.agents)
        return name

    def agent(self, children: list[Token]) -> Token:
        return children[0]

    def group(self, children: list[Token]) -> list[Token]:
        return children

    def args(self, children: list[Token]) -> tuple[str, ...]:
        return _names(children)

    def atom(self, children: list) -> Atom:
        name, args = children
        if name in RESERVED_WORDS:  # "and" where a formula starts: the lexer read a name
            raise ParseError(
                f"'{name}' is a reserved word and cannot name an atom",
                line=name.line,
                column=name.column,
                source=self.source,
                filename=self.filename,
                hint=f"'{name}' joins two formulas, as in 'p {name} q'",
            )
        return Atom(str(name), args or ())

    def action(self, children: list) -> str:
        name, args = children
        text = str(name) if args is None else f"{name}({', '.join(args)})"
        if self.actions is not None and not {text, str(name)} & self.actions:
            self._unknown("action", name, text, self.actions)
        return text

    # -- constants and connectives (operator tokens sit between the operands) --------
    def top(self, _children: list) -> Formula:
        return Top()

    def bottom(self, _children: list) -> Formula:
        return Bottom()

    def not_(self, children: list) -> Formula:
        return Not(children[1])

    def and_(self, children: list) -> Formula:
        return And(children[0], children[2])

    def or_(self, children: list) -> Formula:
        return Or(children[0], children[2])

    def implies(self, children: list) -> Formula:
        return Implies(children[0], children[2])

    def iff(self, children: list) -> Formula:
        return Iff(children[0], children[2])

    # -- modalities: [keyword, agent or group, operand] -------------------------------
    def know(self, children: list) -> Formula:
        return Know(self._agent(children[1]), children[2])

    def believe(self, children: list) -> Formula:
        return Believe(self._agent(children[1]), children[2])

    def conditional_belief(self, children: list) -> Formula:
        # [B, agent, |, condition, operand]
        return ConditionalBelief(self._agent(children[1]), children[3], children[4])

    def safe_belief(self, children: list) -> Formula:
        return SafeBelief(self._agent(children[1]), children[2])

    def know_whether(self, children: list) -> Formula:
        return KnowWhether(self._agent(children[1]), children[2])

    def possible(self, children: list) -> Formula:
        # M[a] f is sugar for ~K[a] ~f, so trees stay within the fixed node set.
        return Not(Know(self._agent(children[1]), Not(children[2])))

    def _group(self, children: list) -> tuple[str, ...]:
        return tuple(self._agent(t) for t in children[1])

    def everybody(self, children: list) -> Formula:
        return Everybody(self._group(children), children[2])

    def common(self, children: list) -> Formula:
        return Common(self._group(children), children[2])

    def distributed(self, children: list) -> Formula:
        return Distributed(self._group(children), children[2])

    def everybody_believes(self, children: list) -> Formula:
        return EverybodyBelieves(self._group(children), children[2])

    def common_belief(self, children: list) -> Formula:
        return CommonBelief(self._group(children), children[2])

    # -- dynamic operators -------------------------------------------------------------
    def announce(self, children: list) -> Formula:
        return Announce(children[1], children[2])

    def announce_diamond(self, children: list) -> Formula:
        return AnnounceDiamond(children[1], children[2])

    def radical_upgrade(self, children: list) -> Formula:
        return RadicalUpgrade(children[1], children[2])

    def conservative_upgrade(self, children: list) -> Formula:
        return ConservativeUpgrade(children[1], children[2])

    def after(self, children: list) -> Formula:
        return After(children[0], children[1])


@functools.cache
def _lark() -> Lark:
    # Built once per process (about 0.1 s); LALR with the contextual lexer, so that an
    # agent or action may be called "K" inside brackets.
    return Lark.open(str(FORMULA_GRAMMAR), parser="lalr", start="formula")


def parse_formula(
    text: str,
    *,
    filename: str = "<formula>",
    agents: Collection[str] | None = None,
    actions: Collection[str] | None = None,
) -> Formula:
    """Parse a formula of dynamic epistemic logic.

    Parameters
    ----------
    text : str
        The formula, e.g. ``"[!p] K[a] (p & ~K[b] q)"``; see ``docs/language.md``.
    filename : str
        Where the text came from, shown in error messages.
    agents, actions : collection of str, optional
        Declared agents and actions; a name outside them raises :class:`SpecError`.

    Returns
    -------
    Formula
        The tree; ``parse_formula(str(f)) == f`` for every formula ``f``.

    Raises
    ------
    ParseError
        The text does not follow the grammar; the error carries line, column, what was
        expected and a hint.
    SpecError
        An agent or action is not declared.

    Examples
    --------
    >>> print(parse_formula("C[b, a] (p -> q -> r) <-> E[a] p"))
    C[a, b] (p -> q -> r) <-> E[a] p
    >>> parse_formula("[open(door, 2)] at(r1, g1)").action
    'open(door, 2)'
    """
    if not isinstance(text, str):
        raise InvalidArgumentError(
            f"parse_formula expects a string, got {type(text).__name__}",
            hint="pass the formula as text, e.g. parse_formula('K[a] p')",
        )
    if not text.strip():
        raise ParseError(
            "empty formula",
            line=1,
            column=1,
            source=text,
            filename=filename,
            hint="write a formula such as 'p & K[a] q'",
        )
    fast = read_whole_formula(text, comments=False)
    if fast is not None and _declared(fast, agents, actions):
        return fast
    # Anything the fast reader does not accept (an error, an undeclared name): lark, for
    # the located message.
    try:
        tree = _lark().parse(text)
    except UnexpectedInput as exc:
        raise syntax_error(exc, text, filename, parser=_lark()) from None
    builder = FormulaBuilder(agents=agents, actions=actions, source=text, filename=filename)
    return builder.transform(tree)


def read_whole_formula(text: str, comments: bool = True) -> Formula | None:
    """``text`` read as one formula by the fast reader (:mod:`._fast`), or ``None`` if it
    does not accept it (then lark parses it, and reports the error)."""
    if not comments and "#" in text:  # formula.lark has no comments; specs do
        return None
    tokens = tokenize(text)
    found = read_formula(tokens, 0)
    if found is None or tokens.kinds[found[1]] != 0:
        return None
    return found[0]


def _declared(f: Formula, agents: Collection[str] | None, actions: Collection[str] | None) -> bool:
    if agents is not None and not f.agents() <= {str(a) for a in agents}:
        return False
    if actions is not None:
        known = {str(a) for a in actions}
        for node in iter_postorder(f, unique=True):
            if type(node) is After and not {node.action, node.action.split("(")[0]} & known:
                return False
    return True


@functools.lru_cache(maxsize=4096)
def _parse(text: str) -> Formula:
    return parse_formula(text)


def as_formula(formula: Formula | str) -> Formula:
    """Return ``formula`` as a tree, parsing it if it is text (parses are cached).

    Examples
    --------
    >>> print(as_formula("K[a] (p & q)"))
    K[a] (p & q)
    """
    if isinstance(formula, Formula):
        return formula
    if isinstance(formula, str):
        return _parse(formula)
    raise InvalidArgumentError(
        f"expected a formula or its text, got {type(formula).__name__}",
        hint="pass a Formula tree or a string such as 'K[a] p'",
    )


class _Root(Transformer):
    """Placeholder root of the merged transformer: only the ``formula__`` rules are used."""


@functools.cache
def _imported_builder() -> Transformer:
    return merge_transformers(_Root(), formula=FormulaBuilder())


def build_imported_formula(tree: Tree) -> Formula:
    """The :class:`Formula` of a subtree parsed by a grammar that imports ``formula.lark``.

    A grammar that ``%import``s the formula rules (the ``.epi`` spec grammar, the mission
    grammar) names them ``formula__<rule>``; this applies :class:`FormulaBuilder`, merged
    under that namespace, with :func:`transform_iteratively` (no recursion limit). Names
    are not checked against declarations: the caller has done so, with its own locations.

    Examples
    --------
    >>> from lark import Lark
    >>> grammar = "start: formula\\n%import formula (formula)\\n%ignore /\\\\s+/"
    >>> lark = Lark(grammar, parser="lalr", import_paths=[str(FORMULA_GRAMMAR.parent)])
    >>> print(build_imported_formula(lark.parse("K[a] p & q").children[0]))
    K[a] p & q
    """
    return transform_iteratively(_imported_builder(), tree)
