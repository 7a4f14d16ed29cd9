"""Every syntax hint, triggered by an input and checked to point at a fix that parses.

Each case gives a wrong formula, a piece of the hint it must get, and the formula written
as the hint says; the fixed text must parse. Also: reserved words as names, world names
in descriptions and DOT, and the location of a missing goal.
"""

from __future__ import annotations

import pytest

from epistemica.del_ import InvalidArgumentError, KripkeModel, ParseError, SpecError, parse_spec
from epistemica.del_.explicit.action import public_announcement
from epistemica.del_.explicit.describe import describe_model, world_labels
from epistemica.del_.explicit.export import to_dot
from epistemica.del_.language.formula import RESERVED_WORDS, Atom
from epistemica.del_.language.parser import parse_formula

HINTS = [
    # unexpected characters
    ("p - q", "did you mean '->'?", "p -> q"),
    ("p = q", "'->' (implies) or '<->'", "p <-> q"),
    ("p < q", "did you mean '<->'", "p <-> q"),
    ("p ^ q", "write '&' for 'and'", "p & q"),
    ("p / q", "write '|' for 'or'", "p | q"),
    ("p \\ q", "'&' for 'and' and '|' for 'or'", "p & q"),
    ("'p'", "without quotes", "p"),
    ('"p"', "without quotes", "p"),
    ("p & é", "ASCII letters", "p & e"),
    ("p $ q", "formulas are built from atoms with ~ & |", "p & q"),
    # unexpected tokens
    ("p > q", "did you mean '->'?", "p -> q"),
    ("E[] p", "at least one agent", "E[a] p"),
    ("K[] p", "K needs one agent", "K[a] p"),
    ("[] p", "action name", "[go] p"),
    ("C[a,] p", "remove the ',' before ']'", "C[a] p"),
    ("at(r1,)", "remove the ',' before ')'", "at(r1)"),
    ("K[a, b] p", "use E[...], C[...] or D[...]", "E[a, b] p"),
    ("B[a, b] p", "use EB[...] or CB[...]", "EB[a, b] p"),
    ("K p", "write the agents in brackets", "K[a] p"),
    ("CB & p", "'CB' is a reserved word", "CB[a] p"),
    ("p & & q", "'&' needs a formula on each side", "p & q"),
    ("p => => q", "'=>' needs a formula on each side", "p => q"),
    ("p and", "'and' needs a formula on its right", "p and q"),
    ("~", "as in ~p", "~p"),
    ("not", "as in not p", "not p"),
    ("K[a]", "needs a formula after it", "K[a] p"),
    ("<!p>", "needs a formula after it", "<!p> q"),
    ("E[a b] p", "separate the agents with ','", "E[a, b] p"),
    ("at(r1 r2)", "separate the arguments with ','", "at(r1, r2)"),
    ("(p | q", "close the parenthesis opened at 1:1 with ')'", "(p | q)"),
    ("[!p q", "close the bracket opened at 1:1 with ']'", "[!p] q"),
    ("<!p q", "close the '<!' opened at 1:1 with '>'", "<!p> q"),
    ("p q", "join two formulas with a connective", "p & q"),
    ("p)", "no '(' is open here; remove this ')'", "p"),
    ("p & q]", "no '[' is open here; remove this ']'", "p & q"),
    ("and", "'and' joins two formulas", "p and q"),
]


@pytest.mark.parametrize(("text", "hint", "fixed"), HINTS, ids=[h[0] for h in HINTS])
def test_each_hint_is_triggered_and_its_fix_parses(text, hint, fixed):
    with pytest.raises(ParseError) as caught:
        parse_formula(text)
    assert caught.value.hint is not None and hint in caught.value.hint, caught.value.hint
    parse_formula(fixed)


def test_expected_tokens_after_a_complete_formula():
    with pytest.raises(ParseError) as caught:
        parse_formula("p & q)")
    assert caught.value.message == (
        "expected a connective ('&', '|', '->', '<->') or end of input, found ')'"
    )
    assert caught.value.column == 6


@pytest.mark.parametrize("word", sorted(RESERVED_WORDS))
def test_reserved_words_cannot_name_atoms(word):
    with pytest.raises(SpecError) as caught:
        parse_spec(f"agents a\natoms p, {word}", "r.epi")
    err = caught.value
    assert (err.line, err.column) == (2, 10)
    assert f"'{word}' is a reserved word" in err.message and f"'{word}_'" in err.hint
    with pytest.raises(InvalidArgumentError):
        Atom(word)
    with pytest.raises(SpecError):
        parse_spec(f"agents a\natoms {word}(x1..x2)")


def test_reserved_words_may_name_agents_inside_brackets():
    spec = parse_spec("agents K, and\natoms p\nobserves K: p\nactual {p}")
    assert spec.holds("K[K] p & ~K[and] p")


def test_world_labels_use_the_names_of_worlds_and_events():
    m = KripkeModel(["u", "v"], {"u": {"p"}}, {"a": [("u", "v"), ("v", "u")]}, ["u"])
    once = m.update(public_announcement("p", ["a"]))
    twice = once.update(public_announcement("true", ["a"]))
    assert list(world_labels(twice).values()) == ["u.announce.announce"]
    assert "u.announce.announce" in describe_model(twice)
    assert 'label="u.announce\\np"' in to_dot(once)


def test_world_labels_fall_back_to_indices_on_a_clash():
    m = KripkeModel(["w0", 1], {"w0": {"p"}}, {"a": []}, ["w0"])  # distinct labels
    assert world_labels(m) == {"w0": "w0", 1: "w1"}
    clash = KripkeModel(["w1", 1], {"w1": {"p"}}, {"a": []}, ["w1"])
    assert world_labels(clash) == {"w1": "w0", 1: "w1"}


def test_missing_goal_is_located():
    spec = parse_spec("agents r\natoms door\n", "noplan.epi")
    with pytest.raises(SpecError) as caught:
        spec.require_goal()
    err = caught.value
    assert (err.filename, err.line, err.column) == ("noplan.epi", 3, 1)
    assert "goal K[r] door" in err.hint
    assert parse_spec("agents a\natoms p\ngoal p").require_goal() == Atom("p")
