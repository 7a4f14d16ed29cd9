"""The fast reader of formulas and specs agrees with lark, and leaves every error to it.

The fast path (del/language/_fast.py, del/spec/_fast_syntax.py) must accept only text that
lark accepts, build the same formulas, and return nothing on the rest, so that lark's
located messages stay the only error messages.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from lark.exceptions import UnexpectedInput

from epistemica.del_ import ParseError, SpecError, parse_formula, parse_spec
from epistemica.del_.language import _fast as fast_module
from epistemica.del_.language._fast import read_formula, tokenize
from epistemica.del_.language.parser import FormulaBuilder, _lark, read_whole_formula
from epistemica.del_.spec import _syntax as spec_syntax
from epistemica.del_.spec._syntax import parse

from epistemic_strategies import formulas

ROOT = Path(__file__).resolve().parents[2]
SPECS = sorted(p for p in ROOT.glob("specs/**/*.epi") if p.parent.name in ("puzzles", "planning"))


def _lark_formula(text):
    return FormulaBuilder().transform(_lark().parse(text))


@settings(max_examples=300, deadline=None)
@given(formulas(max_leaves=12, actions=st.sampled_from(["go", "open(door, 2)"])))
def test_printed_formulas_read_the_same_as_lark(f):
    text = str(f)
    assert read_whole_formula(text) == _lark_formula(text) == f


SPELLINGS = ["p and q", "p && q", "not p", "p || q", "p => q", "p <=> q", "¬p ∧ q", "p ∨ ⊤",
             "p → ⊥", "p ↔ q", "[ ! p] q", "< !p> q", "M[a] p", "K[7] p", "C[a,b,c] p",
             "at(r1,g2)", "((((p))))", "[go(a, 1)] p", "p -> q -> r", "p <-> q <-> r"]  # fmt: skip


@pytest.mark.parametrize("text", SPELLINGS)
def test_other_spellings_read_the_same_as_lark(text):
    assert read_whole_formula(text) == _lark_formula(text)


TOKENS = ["p", "q", "~", "&", "|", "->", "<->", "(", ")", "K[a]", "E[a, b]", "[!", "]",
          "<!", ">", "[go]", "true", "and", "K", ",", "[", "=", "9", "#", "M", "C[", "<",
          "!"]  # fmt: skip


@settings(max_examples=400, deadline=None)
@given(st.lists(st.sampled_from(TOKENS), max_size=30))
def test_token_soup_is_read_as_lark_reads_it_or_left_to_lark(tokens):
    text = " ".join(tokens)
    fast = read_whole_formula(text, comments=False)
    try:
        expected = _lark_formula(text)
    except (UnexpectedInput, ParseError):
        assert fast is None  # lark rejects it: the fast reader must not accept it
        return
    assert fast is None or fast == expected


def test_deep_nesting_needs_no_recursion():
    text = "(" * 10_000 + "~" * 10_000 + "p" + ")" * 10_000
    tokens = tokenize(text)
    f, end = read_formula(tokens, 0)
    assert tokens.kinds[end] == 0 and str(f) == "~" * 10_000 + "p"


@pytest.mark.parametrize("path", SPECS, ids=[p.name for p in SPECS])
def test_shipped_specs_compile_the_same_on_both_paths(path, monkeypatch):
    text = path.read_text(encoding="utf-8")
    if len(text) > 20_000:
        pytest.skip("a generated puzzle: its claims are checked in test_spec_puzzles.py")
    fast = parse_spec(text, str(path))
    assert parse(text, str(path), "start", fast=False).children  # lark parses it too
    monkeypatch.setattr(spec_syntax, "fast_parse", lambda *args: None)  # lark only
    slow = parse_spec(text, str(path))
    assert [(c.name, c.formula, c.expected) for c in fast.checks] == [
        (c.name, c.formula, c.expected) for c in slow.checks
    ]
    assert fast.goal == slow.goal and sorted(fast.actions) == sorted(slow.actions)


@pytest.mark.parametrize(
    ("text", "line", "column", "message"),
    [
        ("agents a\natoms p\nlaw p & zz\n", 3, 9, "unknown atom 'zz'"),
        ("agents a\natoms p\ngoal K[b] p\n", 3, 8, "unknown agent 'b'"),
        ('agents a\natoms p\ncheck "c": [go] p\n', 3, 13, "unknown action 'go'"),
        ("agents a\natoms p\ngoal p &\n", 3, 9, "expected a formula"),
        ('agents a\natoms p\naction go: public p\ncheck "c": p expect maybe\n', 4, 21, ""),
    ],
)
def test_errors_in_fast_path_statements_are_lark_located(text, line, column, message):
    with pytest.raises((ParseError, SpecError)) as caught:
        parse_spec(text, "bad.epi")
    err = caught.value
    assert (err.line, err.column) == (line, column), str(err)
    assert message in err.message


def test_an_error_at_the_end_of_a_long_law_is_located_not_a_recursion_error():
    """Found by the fuzz corpus: the expected tokens were computed on a deep copy of the
    parser's values, which recursed down a 3,000-term law."""
    law = " | ".join(f"(p{i % 3} & ~p{(i + 1) % 3})" for i in range(3_000))
    text = f"agents a\natoms p0..p2\nlaw {law} &\n"
    with pytest.raises(ParseError) as caught:
        parse_spec(text, "long.epi")
    # End of input is reported just after the last token, as for "goal p &" above.
    assert (caught.value.line, caught.value.column) == (3, len(f"law {law} &") + 1)
    assert "expected a formula" in caught.value.message


@settings(max_examples=100, deadline=None)
@given(formulas(max_leaves=8), st.integers(1, 12))
def test_text_read_in_small_pieces_reads_the_same(f, size):
    """The tokenizer reads long text in pieces cut after newlines; a token cut in two
    (the '[' and '!' of an announcement on two lines) must only send the text to lark."""
    text = str(f).replace(" ", "\n").replace("[!", "[\n!").replace("<!", "<\n!")
    original = fast_module._chunks
    fast_module._chunks = lambda t, size=size: original(t, size)
    try:
        tokens = tokenize(text)
        found = read_formula(tokens, 0)
    finally:
        fast_module._chunks = original
    assert found is None or (tokens.kinds[found[1]] == 0 and found[0] == f)
    assert read_whole_formula(text) == f


def test_long_runs_of_blank_lines_and_comments_take_linear_time():
    """Found by the fuzz corpus: a tokenizer match that could fail was retried at every
    position of a trailing run of blank lines (a 200-line run took seconds)."""
    text = "agents a\natoms p\ngoal p\n" + "\n" * 200_000 + "# the end\n" * 50_000
    start = time.perf_counter()
    tokens = tokenize(text)
    assert list(tokens.values) == ["agents", "a", "atoms", "p", "goal", "p", ""]
    assert time.perf_counter() - start < 2
    assert parse_spec(text, "blank.epi").goal == parse_formula("p")
