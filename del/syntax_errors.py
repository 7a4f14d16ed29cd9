"""Located, hinted syntax errors for text in the formula grammar.

:func:`syntax_error` turns a lark ``UnexpectedInput`` into a
:class:`~epistemica.del_.errors.ParseError` that points at the offending character, says
in words what could have come there (``a formula``, ``an agent name``, ``')'``, ...) and
adds a hint for the common slips (a missing operand, an unclosed bracket, a group
modality without agents, ``=`` for ``->``). :func:`~epistemica.del_.parser.parse_formula`
uses it, and so does the spec grammar, which imports ``formula.lark``: its terminals
arrive namespaced (``formula__AND``) and are read back as the formula's own.

The expected tokens are computed exactly by feeding each candidate to a copy of the
LALR parser, since lark's merged lookahead sets are too broad.

Examples
--------
>>> from lark import Lark
>>> from lark.exceptions import UnexpectedInput
>>> from epistemica.del_.parser import FORMULA_GRAMMAR
>>> lark = Lark.open(str(FORMULA_GRAMMAR), parser="lalr", start="formula")
>>> try:
...     lark.parse("p & (q | r")
... except UnexpectedInput as exc:
...     print(syntax_error(exc, "p & (q | r", "<formula>"))
<formula>:1:11: error: expected ')', found end of input
    p & (q | r
              ^
hint: close the parenthesis opened at 1:5 with ')'
"""

from __future__ import annotations

from lark import Token
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from epistemica.del_.errors import ParseError

__all__ = ["syntax_error"]

_FORMULA_START = frozenset(
    {
        "NAME",
        "TRUE",
        "FALSE",
        "NOT",
        "KNOW",
        "BELIEVE",
        "KNOW_WHETHER",
        "POSSIBLE",
        "EVERYBODY",
        "COMMON",
        "DISTRIBUTED",
        "EVERYBODY_BELIEVES",
        "COMMON_BELIEF",
        "ANNOUNCE_OPEN",
        "DIAMOND_OPEN",
        "LSQB",
        "LPAR",
    }
)
_CONNECTIVES = ("AND", "OR", "IMPLIES", "IFF")
_READABLE = {
    "AND": "'&'",
    "OR": "'|'",
    "IMPLIES": "'->'",
    "IFF": "'<->'",
    "NOT": "'~'",
    "RPAR": "')'",
    "RSQB": "']'",
    "MORETHAN": "'>'",
    "COMMA": "','",
    "LPAR": "'('",
    "LSQB": "'['",
    "$END": "end of input",
}
_MODAL = {"KNOW", "BELIEVE", "KNOW_WHETHER", "POSSIBLE"}
_GROUP = {"EVERYBODY", "COMMON", "DISTRIBUTED", "EVERYBODY_BELIEVES", "COMMON_BELIEF"}
_OPENERS = {"LPAR": "RPAR", "LSQB": "RSQB", "ANNOUNCE_OPEN": "RSQB", "DIAMOND_OPEN": "MORETHAN"}
_CHARACTER_HINTS = {
    "-": "did you mean '->'?",
    "=": "did you mean '->' (implies) or '<->' (if and only if)?",
    "<": "did you mean '<->' or an announcement '<!f> g'?",
    ">": "did you mean '->'?",
    "^": "write '&' for 'and'",
    "/": "write '|' for 'or'",
    "\\": "write '&' for 'and' and '|' for 'or'",
    "'": "atoms are written without quotes",
    '"': "atoms are written without quotes",
}


def _position(text: str, index: int) -> tuple[int, int]:
    line = text.count("\n", 0, index) + 1
    return line, index - (text.rfind("\n", 0, index) + 1) + 1


def _open_brackets(stack: list) -> list[Token]:
    """The unclosed opening tokens on a parser's value stack, outermost first."""
    opened: list[Token] = []
    for item in stack:
        if not isinstance(item, Token):
            continue  # a reduced subtree is balanced
        if item.type in _OPENERS:
            opened.append(item)
        elif opened and item.type == _OPENERS[opened[-1].type]:
            opened.pop()
    return opened


def _kind(name: str) -> str:
    # A grammar that %imports formula.lark sees our terminals as "formula__AND" etc.
    return name.rsplit("__", 1)[-1]


def _plain(item: object) -> object:
    if isinstance(item, Token):
        return Token.new_borrow_pos(_kind(item.type), item.value, item)
    return item


def _accepts(exc: UnexpectedToken) -> set[str]:
    """The terminals that could have come instead of the unexpected one.

    lark's LALR lookahead sets are merged across states and so too broad; feeding each
    candidate to a copy of the parser is exact. (``InteractiveParser.accepts`` would do
    this but skips namespaced terminals such as ``formula__NAME``.)
    """
    parser = exc.interactive_parser
    if parser is None:  # pragma: no cover - LALR always provides one
        return set(exc.expected)
    found = set()
    for name in parser.choices():
        if not _kind(name).isupper():
            continue  # a rule, not a terminal
        cursor = parser.copy()
        try:
            cursor.feed_token(Token(name, ""))
        except Exception:  # rejected (UnexpectedToken) or a failing user callback
            continue
        found.add(name)
    return found


def _found(token: Token) -> str:
    if token.type == "$END":
        return "end of input"
    return f"'{token}'"


def _spelling(name: str, terminals: dict) -> str:
    # Terminals of an importing grammar: show the literal text when there is one.
    pattern = getattr(terminals.get(name), "pattern", None)
    if pattern is not None and pattern.type == "str":
        return f"'{pattern.value}'"
    return name.lower().replace("_", " ")


def _describe(expected: set[str], context: str, terminals: dict | None = None) -> str:
    items: list[str] = []
    if _FORMULA_START <= expected:
        items.append("a formula")
        expected = expected - _FORMULA_START
    if {"NAME", "INT"} <= expected:
        items.append(context)
        expected = expected - {"NAME", "INT"}
    elif "NAME" in expected:
        items.append("an action name" if context == "an agent name" else "a name")
        expected = expected - {"NAME"}
    if all(c in expected for c in _CONNECTIVES):
        items.append("a connective ('&', '|', '->', '<->')")
        expected = expected - set(_CONNECTIVES) - {"LPAR"}  # '(' would start arguments
    for name in sorted(expected, key=lambda n: (n == "$END", n)):
        items.append(_READABLE.get(name) or _spelling(name, terminals or {}))
    if len(items) <= 1:
        return "".join(items) or "something else"
    return ", ".join(items[:-1]) + " or " + items[-1]


def syntax_error(exc: UnexpectedInput, text: str, filename: str) -> ParseError:
    """Translate a lark exception into a :class:`ParseError` with a hint.

    Public for grammars that import ``formula.lark``: their parse errors inside a formula
    read the same way.

    Parameters
    ----------
    exc : lark.exceptions.UnexpectedInput
        The exception raised by an LALR parser of ``formula.lark`` or of a grammar that
        imports it.
    text : str
        The whole text that was parsed.
    filename : str
        Where the text came from, for the ``FILE:LINE:COL`` prefix.

    Returns
    -------
    ParseError
        Located at the offending character (at the end of the text for a premature end),
        saying what was expected and what was found, with a hint when one applies.
    """
    if isinstance(exc, UnexpectedCharacters):
        char = text[exc.pos_in_stream] if exc.pos_in_stream < len(text) else ""
        hint = _CHARACTER_HINTS.get(char)
        if hint is None and char.isalpha():
            hint = "names use ASCII letters, digits and '_'"
        return ParseError(
            f"unexpected character '{char}'",
            line=exc.line,
            column=exc.column,
            source=text,
            filename=filename,
            hint=hint or "see docs/language.md for the syntax of formulas",
        )
    if not isinstance(exc, UnexpectedToken):  # pragma: no cover - LALR raises only these
        return ParseError(str(exc), source=text, filename=filename)

    token = _plain(exc.token)
    stack = [_plain(t) for t in exc.state.value_stack] if exc.state is not None else []
    expected = {_kind(name) for name in _accepts(exc)}
    previous = next((t for t in reversed(stack) if isinstance(t, Token)), None)
    opened = _open_brackets(stack)
    inner = opened[-1] if opened else None
    before_inner = None
    if inner is not None:
        index = next(i for i, item in enumerate(stack) if item is inner)
        before_inner = stack[index - 1] if index > 0 else None
    in_group = isinstance(before_inner, Token) and before_inner.type in _GROUP
    in_modal = isinstance(before_inner, Token) and before_inner.type in _MODAL
    if in_group or in_modal:
        context = "an agent name"
    elif inner is not None and inner.type == "LPAR" and isinstance(before_inner, Token):
        context = "an argument (a name or a number)"
    else:
        context = "a name"

    if token.type == "$END":
        line, column = _position(text, len(text.rstrip()))
    else:
        line, column = token.line, token.column
    terminals = {_kind(k): v for k, v in (getattr(exc, "_terminals_by_name", None) or {}).items()}
    message = f"expected {_describe(expected, context, terminals)}, found {_found(token)}"

    hint = None
    if token.type == "RSQB" and in_group and previous is not None and previous.type == "LSQB":
        hint = "group modalities need at least one agent, as in C[a, b] p"
    elif token.type == "COMMA" and in_modal:
        groups = (
            "EB[...] or CB[...]" if before_inner.type == "BELIEVE" else "E[...], C[...] or D[...]"
        )
        hint = f"{before_inner} takes one agent; use {groups} for a group"
    elif previous is not None and previous.type in _MODAL | _GROUP and token.type != "LSQB":
        hint = (
            f"write the agents in brackets, as in {previous}[a] p; "
            f"'{previous}' is a reserved word and cannot name an atom"
        )
    elif token.type in _CONNECTIVES and "NAME" in expected:
        hint = f"{_READABLE[token.type]} needs a formula on each side"
    elif previous is not None and previous.type in _CONNECTIVES and "NAME" in expected:
        hint = f"{_READABLE[previous.type]} needs a formula on its right"
    elif inner is not None and _OPENERS[inner.type] in expected:
        shape = {"LPAR": "parenthesis", "DIAMOND_OPEN": "'<!'"}.get(inner.type, "bracket")
        closer = _READABLE[_OPENERS[inner.type]]
        hint = f"close the {shape} opened at {inner.line}:{inner.column} with {closer}"
    elif token.type in _FORMULA_START and all(c in expected for c in _CONNECTIVES):
        hint = "join two formulas with a connective such as '&'"
    return ParseError(message, line=line, column=column, source=text, filename=filename, hint=hint)
