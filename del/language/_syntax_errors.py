"""Located, hinted syntax errors for text in the formula grammar.

:func:`syntax_error` turns a lark ``UnexpectedInput`` into a
:class:`~epistemica.del_.errors.ParseError` that points at the offending character, says
in words what could have come there (``a formula``, ``an agent name``, ``')'``, ...) and
adds a hint for the common slips (a missing operand, an unclosed bracket, a group
modality without agents, ``=`` for ``->``). :func:`~epistemica.del_.language.parser.parse_formula`
uses it, and so does the spec grammar, which imports ``formula.lark``: its terminals
arrive namespaced (``formula__AND``) and are read back as the formula's own.

The expected tokens are computed exactly by feeding each candidate to a copy of the
LALR parser, since lark's merged lookahead sets are too broad.

Examples
--------
>>> from lark import Lark
>>> from lark.exceptions import UnexpectedInput
>>> from epistemica.del_.language.parser import FORMULA_GRAMMAR
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

from lark import Lark, Token
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken
from lark.parsers.lalr_interactive_parser import InteractiveParser

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
        "SAFE_BELIEF",
        "RADICAL_OPEN",
        "CONSERVATIVE_OPEN",
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
_MODAL = {"KNOW", "BELIEVE", "KNOW_WHETHER", "POSSIBLE", "SAFE_BELIEF"}
_GROUP = {"EVERYBODY", "COMMON", "DISTRIBUTED", "EVERYBODY_BELIEVES", "COMMON_BELIEF"}
_OPENERS = {"LPAR": "RPAR", "LSQB": "RSQB", "ANNOUNCE_OPEN": "RSQB", "DIAMOND_OPEN": "MORETHAN",
            "RADICAL_OPEN": "RSQB", "CONSERVATIVE_OPEN": "RSQB"}  # fmt: skip
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

# What a hint says when nothing more specific fits: the syntax itself, not a path to a page
# that an installed package does not have.
_FORMULA_SYNTAX = (
    "formulas are built from atoms with ~ & | -> <->, K[a] F, B[a] F, E[a, b] F, C[a, b] F, "
    "[!F] G and [ACTION] G; names use ASCII letters, digits and '_'"
)


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


def _accepts(parser: InteractiveParser) -> set[str]:
    """The terminals that could come next in the state of ``parser``.

    lark's LALR lookahead sets are merged across states and so too broad; feeding each
    candidate to a copy of the parser is exact. (``InteractiveParser.accepts`` would do
    this but skips namespaced terminals such as ``formula__NAME``.)
    """
    found = set()
    for name in parser.choices():
        if not _kind(name).isupper():
            continue  # a rule, not a terminal
        # A shallow copy of the values: a deep one recurses down a long formula's tree
        # (a 2,400-term law), and feeding one token never changes the values below it.
        cursor = parser.copy(deepcopy_values=False)
        try:
            cursor.feed_token(Token(name, ""))
        except Exception:  # rejected (UnexpectedToken) or a failing user callback
            continue
        found.add(name)
    return found


def _before(parser: Lark, text: str, start: str | None, token: Token) -> InteractiveParser | None:
    """A parser of ``text`` stopped just before ``token``, none of its reductions done."""
    cursor = parser.parse_interactive(text, start=start)
    try:
        for seen in cursor.iter_parse():  # yields each token before feeding it
            if seen.start_pos == token.start_pos and seen.type == token.type:
                return cursor
    except UnexpectedInput:  # pragma: no cover - fails at the same token, yielded first
        return None
    return cursor if token.type == "$END" else None


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


def syntax_error(
    exc: UnexpectedInput,
    text: str,
    filename: str,
    parser: Lark | None = None,
    start: str | None = None,
) -> ParseError:
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
    parser : lark.Lark, optional
        The parser that raised ``exc`` (and ``start``, its start rule when it has several).
        LALR reduces as far as the unexpected token allows before it fails, so after a
        complete formula (``p)``) nothing is left to expect; given the parser, the text is
        parsed again up to the unexpected token to say what could have come there.

    Returns
    -------
    ParseError
        Located at the offending character (at the end of the text for a premature end),
        saying what was expected and what was found, with a hint when one applies.
    """
    if isinstance(exc, UnexpectedCharacters):
        return _character_error(exc, text, filename)
    if not isinstance(exc, UnexpectedToken):  # pragma: no cover - LALR raises only these
        return ParseError(str(exc), source=text, filename=filename)

    token = _plain(exc.token)
    state = exc.state
    accepted = _accepts(exc.interactive_parser) if exc.interactive_parser else set(exc.expected)
    if not accepted and parser is not None:
        before = _before(parser, text, start, exc.token)
        if before is not None:
            state, accepted = before.parser_state, _accepts(before)
    stack = [_plain(t) for t in state.value_stack] if state is not None else []
    expected = {_kind(name) for name in accepted}
    previous = next((t for t in reversed(stack) if isinstance(t, Token)), None)
    inner, before_inner = _innermost_bracket(stack)
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

    kind = "agent" if in_group or in_modal else "argument" if "argument" in context else "name"
    hint = _hint(token, previous, expected, inner, before_inner, kind)
    return ParseError(message, line=line, column=column, source=text, filename=filename, hint=hint)


def _character_error(exc: UnexpectedCharacters, text: str, filename: str) -> ParseError:
    """A character no token starts with, with a hint for the usual ones (``&&``, ``∧``)."""
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
        hint=hint or _FORMULA_SYNTAX,
    )


def _innermost_bracket(stack: list) -> tuple:
    """The innermost bracket still open on the parser's stack, and the item before it."""
    opened = _open_brackets(stack)
    inner = opened[-1] if opened else None
    before_inner = None
    if inner is not None:
        index = next(i for i, item in enumerate(stack) if item is inner)
        before_inner = stack[index - 1] if index > 0 else None
    return inner, before_inner


def _hint(
    token: Token,
    previous: Token | None,
    expected: set[str],
    inner: Token | None,
    before_inner: object,
    kind: str,
) -> str | None:
    """The likely fix, from the unexpected token, the token before it and the open bracket.

    ``kind`` names what the innermost open bracket lists: "agent", "argument" or "name".
    """
    prev = previous.type if previous is not None else None
    opener = before_inner.type if isinstance(before_inner, Token) else None
    formula_next = _FORMULA_START <= expected
    if token.type == "RSQB" and prev == "LSQB":
        if opener in _GROUP:
            return "group modalities need at least one agent, as in C[a, b] p"
        if opener in _MODAL:
            return f"{before_inner} needs one agent, as in {before_inner}[a] p"
        return "write an action name, as in [go] p, or an announcement, as in [!p] q"
    if token.type in ("RSQB", "RPAR") and prev == "COMMA":
        return f"remove the ',' before '{token}', or write another {kind} after it"
    if token.type == "COMMA" and opener in _MODAL:
        groups = "EB[...] or CB[...]" if opener == "BELIEVE" else "E[...], C[...] or D[...]"
        return f"{before_inner} takes one agent; use {groups} for a group"
    if prev in _MODAL | _GROUP and token.type != "LSQB":
        return (
            f"write the agents in brackets, as in {previous}[a] p; "
            f"'{previous}' is a reserved word and cannot name an atom"
        )
    if token.type in _CONNECTIVES and formula_next:
        return f"'{token}' needs a formula on each side"
    if prev in _CONNECTIVES and formula_next:
        return f"'{previous}' needs a formula on its right"
    if prev == "NOT" and formula_next:
        space = " " if str(previous)[-1:].isalpha() else ""  # "not p", "~p"
        return f"'{previous}' needs a formula on its right, as in {previous}{space}p"
    if prev in ("RSQB", "MORETHAN") and formula_next:
        return "a modality, announcement or action needs a formula after it, as in K[a] p"
    if inner is not None and "COMMA" in expected and token.type in ("NAME", "INT"):
        return f"separate the {kind}s with ','"
    if inner is not None and _OPENERS[inner.type] in expected:
        shape = {"LPAR": "parenthesis", "DIAMOND_OPEN": "'<!'"}.get(inner.type, "bracket")
        closer = _READABLE[_OPENERS[inner.type]]
        return f"close the {shape} opened at {inner.line}:{inner.column} with {closer}"
    if token.type in _FORMULA_START and all(c in expected for c in _CONNECTIVES):
        return "join two formulas with a connective such as '&'"
    if token.type == "MORETHAN":
        return "did you mean '->'? ('>' only closes an announcement <!f> g)"
    if inner is None and token.type in ("RPAR", "RSQB") and token.type not in expected:
        opening = "(" if token.type == "RPAR" else "["
        return f"no '{opening}' is open here; remove this '{token}'"
    return None
