"""Every kind of mistake in a spec file names FILE:LINE:COL, says what was expected, hints."""

from __future__ import annotations

import pytest

from epistemica.del_ import EpistemicaError, ParseError, SpecError, load_spec, parse_spec

HEAD = "agents a, b\natoms p, q, at(r1..r2, g1)\n"  # lines 1-2 of most cases below


def error_of(text: str, kind=SpecError) -> SpecError:
    with pytest.raises(kind) as info:
        parse_spec(text, filename="bad.epi")
    return info.value


# (text, line, column, words in the message, words in the hint). Columns are 1-based and
# counted by hand on the offending line.
SEMANTIC = [
    pytest.param(HEAD + "observes a: pp\n", 3, 13, "unknown atom 'pp'", "'p'", id="atom"),
    pytest.param(HEAD + "observes c: p\n", 3, 10, "unknown agent 'c'", "a, b", id="agent"),
    pytest.param(HEAD + "goal K[c] p\n", 3, 8, "unknown agent 'c'", "a, b", id="agent-in-formula"),
    pytest.param(HEAD + "goal K[a] qq\n", 3, 11, "unknown atom 'qq'", "'q'", id="atom-in-formula"),
    pytest.param(
        HEAD + "goal at(r1, g2)\n", 3, 6, "unknown atom 'at(r1, g2)'", "at(r1, g1)",
        id="predicate-atom",
    ),
    pytest.param(HEAD + "goal [tel] p\naction tell: public p\n", 3, 7, "unknown action 'tel'",
                 "'tell'", id="action-in-formula"),
    pytest.param(HEAD + "atoms q\n", 3, 7, "atom 'q' declared twice", "2:10", id="atom-twice"),
    pytest.param("agents a, b, a\n", 1, 14, "agent 'a' declared twice", "1:8", id="agent-twice"),
    pytest.param(HEAD + "law p & ~p\n", 3, 5, "no valuation satisfies the law", "contradiction",
                 id="law-unsatisfiable"),
    pytest.param(HEAD + "law p\nactual {q}\n", 4, 1, "actual world violates the law", "law is p",
                 id="actual-violates-law"),
    pytest.param(HEAD + "law K[a] p\n", 3, 5, "law must be propositional", "check",
                 id="modal-law"),
    pytest.param("atoms p\n", 1, 1, "no agents declared", "agents a, b", id="no-agents"),
    pytest.param(HEAD + "goal p\ngoal q\n", 4, 1, "a second goal", "&", id="two-goals"),
    pytest.param(HEAD + 'check "c": p\ncheck "c": q\n', 4, 7, 'second check named "c"',
                 "3:7", id="check-twice"),
    pytest.param(HEAD + "atoms m3..m1\n", 3, 11, "empty range", "smaller", id="empty-range"),
    pytest.param(HEAD + "atoms x1..x200000\n", 3, 11, "the range has 200000 names",
                 "bounds", id="huge-range"),
    pytest.param(HEAD + "atoms m1..x3\n", 3, 7, "cannot expand the range", "m1..m4",
                 id="bad-range"),
    pytest.param("agents a\natoms a\n", 2, 7, "names both an agent and an atom", "rename",
                 id="agent-atom-clash"),
    # actions
    pytest.param(HEAD + "action x: private p to c\n", 3, 24, "unknown agent 'c'", "a, b",
                 id="unknown-observer"),
    pytest.param(HEAD + "action x: assign p := q, p := true\n", 3, 26, "'p' assigned twice",
                 "one", id="assigned-twice"),
    pytest.param(HEAD + "action x: public p\naction x: public q\n", 4, 8,
                 "action 'x' declared twice", "3:8", id="action-twice"),
    pytest.param(HEAD + "action t { event e event e designated e relation a, b: {e} }\n",
                 3, 26, "event 'e' declared twice", "3:18", id="event-twice"),
    pytest.param(HEAD + "action t { event e relation a, b: {e} designated f }\n", 3, 50,
                 "unknown event 'f'", "declared events: e", id="unknown-event"),
    pytest.param(HEAD + "action t { event e relation a, b: {e} }\n", 3, 1,
                 "no 'designated' line", "designated e", id="no-designated-event"),
    pytest.param(HEAD + "action t { event e relation a: {e} designated e }\n", 3, 1,
                 "agent 'b' has no relation", "relation b", id="agent-without-edges"),
    pytest.param(HEAD + "action t { pre p\n event e relation a, b: {e} designated e }\n", 4, 2,
                 "mixes explicit events with observability", "not both", id="mixed-block"),
    pytest.param(HEAD + "action t { full a\n partial a }\n", 4, 10,
                 "agent 'a' is given two observabilities", "3:17", id="agent-twice-in-block"),
    pytest.param(HEAD + "action t { senses p\n announces q }\n", 4, 2, "a second 'announces'",
                 "one formula", id="senses-and-announces"),
    pytest.param(HEAD + "action t { executable p\n executable q\n full a }\n", 4, 2,
                 "a second 'executable'", "&", id="executable-twice"),
    pytest.param(HEAD + "action t { executable K[c] p }\n", 3, 25, "unknown agent 'c'",
                 "a, b", id="executable-unknown-agent"),
    pytest.param(HEAD + "action t { executable p\n event e relation a, b: {e} designated e }\n",
                 4, 2, "mixes explicit events with observability", "not both",
                 id="executable-in-event-model"),
    pytest.param(HEAD + "action t by c: public p\n", 3, 13, "unknown agent 'c'", "a, b",
                 id="unknown-owner"),
    pytest.param(HEAD + "action go(i in {r1, r2}) by i: public at(i, g1)\n", 3, 29,
                 "unknown agent 'r1'", "parameters of action 'go': i", id="owner-not-an-agent"),
    # parametrised schemas
    pytest.param(HEAD + "action go(i in {r1, r2}): public at(j, g1)\n", 3, 37,
                 "unbound parameter 'j'", "parameters of 'go': i", id="unbound-parameter"),
    pytest.param(HEAD + "action go(i in {r1, r2}): private at(i, g1) to k\n", 3, 48,
                 "unknown agent 'k'", "parameters of action 'go': i", id="unbound-agent"),
    pytest.param(HEAD + "action go(i in {r1, r9}): public at(i, g1)\n", 3, 34,
                 "unknown atom 'at(r9, g1)'", "parameters of action 'go': i",
                 id="bound-to-unknown-value"),
    pytest.param(HEAD + "action go(i in {r1}, i in {r2}): public p\n", 3, 22,
                 "parameter 'i' given twice", "rename", id="parameter-twice"),
    pytest.param(HEAD + "action go(a in {r1}): public p\n", 3, 11,
                 "parameter 'a' has the name of an agent", "rename", id="parameter-shadows"),
    # explicit models
    pytest.param(HEAD + "world w1 {p}\nobserves a: p\n", 4, 1, "cannot be mixed", "either",
                 id="mixed-model"),
    pytest.param(HEAD + "world w1 {p}\nworld w1 {}\n", 4, 7, "world 'w1' declared twice", "3:7",
                 id="world-twice"),
    pytest.param(HEAD + "world w1 {p}\nworld w2 {}\npartition a, b: {w1}\ndesignated w1\n",
                 5, 1, "partition of 'a' leaves out world 'w2'", "{w2}", id="partition-gap"),
    pytest.param(HEAD + "world w1 {p}\npartition a, b: {w1}, {w1}\ndesignated w1\n", 4, 24,
                 "'w1' is in two blocks", "overlap", id="partition-overlap"),
    pytest.param(HEAD + "world w1 {p}\npartition a, b: {w1}\ndesignated w2\n", 5, 12,
                 "unknown world 'w2'", "declared worlds: w1", id="unknown-designated-world"),
    pytest.param(HEAD + "world w1 {p}\npartition a, b: {w1}\n", 3, 7, "no designated world",
                 "designated w1", id="no-designated-world"),
    pytest.param(HEAD + "law q\nworld w1 {p}\npartition a, b: {w1}\ndesignated w1\n", 4, 7,
                 "world 'w1' violates the law", "law is q", id="world-violates-law"),
    pytest.param(HEAD + "world w1 {p}\nrelation a, b: w1 -> w1 if p\ndesignated w1\n", 4, 28,
                 "conditions on edges are allowed in event models only", "if",
                 id="condition-on-world-edge"),
]  # fmt: skip


@pytest.mark.parametrize(("text", "line", "column", "message", "hint"), SEMANTIC)
def test_semantic_errors_are_located_and_hinted(text, line, column, message, hint):
    err = error_of(text)
    assert type(err) is SpecError
    assert (err.filename, err.line, err.column) == ("bad.epi", line, column), str(err)
    assert message in err.message
    assert err.hint and hint in err.hint
    rendered = str(err)
    assert rendered.startswith(f"bad.epi:{line}:{column}: error: ")
    offending = text.splitlines()[line - 1]
    assert f"    {offending}\n    {' ' * (column - 1)}^" in rendered
    assert "\nhint: " in rendered


SYNTAX = [
    pytest.param("agent a\n", 1, 1, "found 'agent'", "did you mean 'agents'?",
                 id="misspelt-keyword"),
    pytest.param(HEAD + "actions x: public p\n", 3, 1, "unknown keyword 'actions'",
                 "did you mean 'action'?", id="keyword-glued"),
    pytest.param(HEAD + "goal K[a] p &\n", 3, 14, "expected a formula", "'&'",
                 id="dangling-and"),
    pytest.param(HEAD + "goal K[a] (p\ncheck \"x\": p\n", 4, 1, "expected ')'", "3:11",
                 id="unclosed-paren"),
    pytest.param(HEAD + "goal p $ q\n", 3, 8, "unexpected character '$'", "formulas are built",
                 id="bad-character"),
    pytest.param(HEAD + "action go(r1): public p\n", 3, 13, "expected 'in'", "i in {a, b}",
                 id="parameter-without-domain"),
    pytest.param(HEAD + 'check "c": p expect maybe\n', 3, 21, "'false' or 'true'",
                 "expect true", id="bad-verdict"),
    pytest.param(HEAD + "goal K[a] p q\n", 3, 13, "expected a connective", "connective",
                 id="missing-connective"),
    pytest.param(HEAD + "action x: assign p = q\n", 3, 20, "unexpected character '='",
                 "atom := formula", id="assign-with-equals"),
    pytest.param(HEAD + "action x { effect p q }\n", 3, 21, "expected '(' or ':='",
                 "atom := formula", id="effect-without-becomes"),
    pytest.param(HEAD + "atoms p q\n", 3, 9, "found 'q'", "separate the items of a list with ','",
                 id="missing-comma"),
]  # fmt: skip


@pytest.mark.parametrize(("text", "line", "column", "message", "hint"), SYNTAX)
def test_syntax_errors_are_located_and_hinted(text, line, column, message, hint):
    err = error_of(text, ParseError)
    assert (err.filename, err.line, err.column) == ("bad.epi", line, column), str(err)
    assert message in err.message
    assert err.hint and hint in err.hint, err.hint
    assert str(err).startswith(f"bad.epi:{line}:{column}: error: ")


def test_formula_errors_point_into_the_file_not_the_formula():
    text = HEAD + '\n\ncheck "deep":\n    [!p]\n        K[a] (q & K[zed] p)\n'
    err = error_of(text)
    # "zed" sits on line 7, column 21 of the file; the formula itself starts on line 6.
    assert (err.line, err.column) == (7, 21)
    assert err.message == "unknown agent 'zed'"


def test_errors_inside_a_schema_point_at_the_schema_text():
    text = HEAD + "action go(i in {r1, r2}) {\n    pre at(i, g1)\n    effect qq := true\n}\n"
    err = error_of(text)
    assert (err.line, err.column) == (5, 12)
    assert "unknown atom 'qq'" in err.message and "parameters of action 'go': i" in err.hint


def test_spec_formula_errors_are_located_in_the_formula_text():
    spec = parse_spec(HEAD)
    with pytest.raises(SpecError) as info:
        spec.formula("K[a] p & K[b] r")
    assert (info.value.filename, info.value.line, info.value.column) == ("<formula>", 1, 15)
    with pytest.raises(ParseError) as info:
        spec.formula("K[a] (p")
    assert info.value.filename == "<formula>"
    with pytest.raises(ParseError):
        spec.formula("   ")


def test_too_many_atoms_for_observables():
    """Explicitly refused; the default backend ('auto') takes the symbolic one instead."""
    with pytest.raises(SpecError) as caught:
        parse_spec("agents a\natoms x1..x27\n", "bad.epi", backend="explicit")
    err = caught.value
    assert (err.line, err.column) == (2, 1) and "too many" in err.message
    assert type(parse_spec("agents a\natoms x1..x27\n").model).__name__ == "KnowledgeStructure"


def test_missing_file_is_a_spec_error(tmp_path):
    with pytest.raises(SpecError) as info:
        load_spec(tmp_path / "nope.epi")
    assert "cannot read" in info.value.message and info.value.hint
    assert str(info.value).startswith(str(tmp_path / "nope.epi"))


def test_every_error_is_an_epistemica_error():
    for text in ("agents", "agents a\ngoal K[b] p"):
        with pytest.raises(EpistemicaError):
            parse_spec(text)
