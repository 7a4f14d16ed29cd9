"""The front end of spec files: the lark grammar ``spec.lark`` and located syntax errors.

:func:`parse` turns the text of a spec (or of one formula over a spec's names) into a lark
parse tree, and reports malformed text as a
:class:`~epistemica.del_.errors.ParseError` with the file, line and column of the
offending token, the line with a caret and a hint that names the expected keyword.
The tree is compiled by :mod:`epistemica.del_.spec._compiler`.

Examples
--------
>>> tree = parse("agents a\\natoms p\\ngoal K[a] p", "<string>", start="start")
>>> [str(statement.data) for statement in tree.children]
['agents_decl', 'atoms_decl', 'goal_decl']
>>> parse("agents a\\natom p", "demo.epi", start="start")
Traceback (most recent call last):
...
epistemica.del_.errors.ParseError: demo.epi:2:1: error: expected ..., found 'atom'
    atom p
    ^
hint: did you mean 'atoms'?
"""

from __future__ import annotations

import difflib
import functools
import os
import re
from pathlib import Path

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from epistemica.del_.errors import ParseError
from epistemica.del_.language.parser import FORMULA_GRAMMAR, syntax_error
from epistemica.del_.spec._fast_syntax import fast_formula, fast_parse

__all__ = ["KEYWORDS", "SPEC_GRAMMAR", "parse", "position"]

#: Path of the grammar file of spec files.
SPEC_GRAMMAR = Path(__file__).with_name("spec.lark")

#: The keywords that start a statement.
KEYWORDS = (
    "agents", "atoms", "observes", "law", "actual", "world", "relation", "knowledge",
    "partition", "designated", "action", "goal", "check",
)  # fmt: skip

_CONTEXT_HINTS = {
    "IN": "a parameter is written 'i in {a, b}' or 'i in agents'",
    "TRUE": "write 'expect true' or 'expect false'",
    "COLON": "write 'action NAME: public F' (one line) or 'action NAME { ... }' (a block)",
    "_BECOMES": "an effect is written 'atom := formula'",
}


def parse(text: str, filename: str, start: str, fast: bool = True) -> Tree:
    """Parse ``text`` from the rule ``start`` (``"start"``: a spec; ``"fml"``: a formula).

    With ``fast``, valid formula-heavy text is read by the fast path
    (:mod:`._fast_syntax`), whose ``fml`` nodes hold finished formulas; anything it does
    not take is parsed by lark, which locates the errors.

    Raises
    ------
    ParseError
        Located at the offending token, with a hint.
    """
    if fast:
        try:
            tree = fast_parse(text, _statement) if start == "start" else fast_formula(text)
        except (UnexpectedInput, _SplitWord):
            tree = None
        if tree is not None:
            return tree
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
        error = syntax_error(exc, text, filename, parser=_lark(), start=start)
        if "_BECOMES" in (getattr(exc, "allowed", None) or ()):
            error.hint = _CONTEXT_HINTS["_BECOMES"]
        elif error.hint is None:
            error.hint = _statement_hint(exc)
        raise error from None


def _statement(padded: str) -> Tree:
    return _lark().parse(padded, start="start")


def position(item: Token | Tree) -> tuple[int | None, int | None]:
    """Line and column of a token or of a tree (its first token), if known."""
    if isinstance(item, Token):
        return item.line, item.column
    meta = item.meta
    return getattr(meta, "line", None), getattr(meta, "column", None)


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
    # Built once per process, and kept between processes in lark's cache (building takes
    # about 0.05 s, loading 0.005 s; lark rebuilds it when the grammar files change).
    return Lark.open(
        str(SPEC_GRAMMAR),
        parser="lalr",
        start=["start", "fml"],
        propagate_positions=True,
        maybe_placeholders=True,
        import_paths=[str(FORMULA_GRAMMAR.parent)],
        postlex=_WholeWords(),
        cache=_cache_file(),
    )


def _cache_file() -> str | bool:
    # In the user's own cache directory, not the shared temporary one lark would use:
    # the cache is a pickle, and loading one that someone else planted would run code.
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "epistemica"
    try:
        base.mkdir(parents=True, exist_ok=True)
    except OSError:  # read-only home: build the grammar every time
        return False
    return str(base / "spec-grammar.lark-cache")


def _keyword_hint(word: str) -> str:
    close = difflib.get_close_matches(word, KEYWORDS, n=1)
    if close:
        return f"did you mean '{close[0]}'?"
    return "each statement starts with a keyword: " + ", ".join(KEYWORDS)


def _statement_hint(exc: UnexpectedInput) -> str | None:
    expected = set(getattr(exc, "expected", ()) or ())
    token = getattr(exc, "token", None)
    if "AGENTS" in expected:  # at the start of a statement
        word = str(token or "")
        if "COMMA" in expected and not difflib.get_close_matches(word, KEYWORDS, n=1):
            return f"separate the items of a list with ',' (found '{word}' after an item)"
        return _keyword_hint(word)
    for terminal, hint in _CONTEXT_HINTS.items():
        if terminal in expected:
            return hint
    return None
