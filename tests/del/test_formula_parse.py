"""parse_formula: each construct, precedence and associativity, aliases, error reports.

Expected trees are written out by hand from the grammar's precedence table
(unary > & > | > -> > <->, -> right-associative, <-> left-associative).
"""

from __future__ import annotations

import pytest
from lark import Lark, Transformer
from lark.exceptions import UnexpectedInput
from lark.visitors import merge_transformers

from epistemica.del_ import (
    After,
    And,
    Announce,
    AnnounceDiamond,
    Atom,
    Believe,
    Bottom,
    Common,
    CommonBelief,
    Distributed,
    EpistemicaError,
    Everybody,
    EverybodyBelieves,
    Iff,
    Implies,
    InvalidArgumentError,
    Know,
    KnowWhether,
    Not,
    Or,
    ParseError,
    SpecError,
    Top,
    parse_formula,
)
from epistemica.del_.language.parser import FORMULA_GRAMMAR, FormulaBuilder, syntax_error

p, q, r, s = Atom("p"), Atom("q"), Atom("r"), Atom("s")


# --------------------------------------------------------------------------------------
# constructs
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "tree"),
    [
        ("p", p),
        ("muddy1", Atom("muddy1")),
        ("_x", Atom("_x")),
        ("at(r1, g1)", Atom("at", ("r1", "g1"))),
        ("at( r1 ,g1 )", Atom("at", ("r1", "g1"))),
        ("cell(2, 10)", Atom("cell", ("2", "10"))),
        ("true", Top()),
        ("false", Bottom()),
        ("~p", Not(p)),
        ("p & q", And(p, q)),
        ("p | q", Or(p, q)),
        ("p -> q", Implies(p, q)),
        ("p <-> q", Iff(p, q)),
        ("(p)", p),
        ("((p))", p),
        ("K[a] p", Know("a", p)),
        ("B[a] p", Believe("a", p)),
        ("Kw[a] p", KnowWhether("a", p)),
        ("K[0] p", Know("0", p)),
        ("K[r_2] p", Know("r_2", p)),
        ("E[a,b] p", Everybody(("a", "b"), p)),
        ("C[a, b] p", Common(("a", "b"), p)),
        ("CB[a, b] p", CommonBelief(("a", "b"), p)),
        ("EB[b, a, b] p", EverybodyBelieves(("a", "b"), p)),
        ("CB[a] p & q", And(CommonBelief(("a",), p), q)),
        ("CB[a, c] EB[b] ~p", CommonBelief(("a", "c"), EverybodyBelieves(("b",), Not(p)))),
        ("D[a] p", Distributed(("a",), p)),
        ("E[b, a, b] p", Everybody(("a", "b"), p)),  # groups are sets
        ("[!p] q", Announce(p, q)),
        ("[ ! p ] q", Announce(p, q)),
        ("<!p> q", AnnounceDiamond(p, q)),
        ("< ! p > q", AnnounceDiamond(p, q)),
        ("[tick] p", After("tick", p)),
        ("[open(a)] p", After("open(a)", p)),
        ("[move( r1,g1 ,3)] p", After("move(r1, g1, 3)", p)),
        ("K[a]\n  (p &\n\tq)", Know("a", And(p, q))),
    ],
)
def test_each_construct(text, tree):
    assert parse_formula(text) == tree


@pytest.mark.parametrize(
    ("text", "tree"),
    [
        ("~p & q", And(Not(p), q)),
        ("~(p & q)", Not(And(p, q))),
        ("p & q | r", Or(And(p, q), r)),
        ("p | q & r", Or(p, And(q, r))),
        ("p & q & r", And(And(p, q), r)),
        ("p | q | r", Or(Or(p, q), r)),
        ("p -> q -> r", Implies(p, Implies(q, r))),
        ("(p -> q) -> r", Implies(Implies(p, q), r)),
        ("p <-> q <-> r", Iff(Iff(p, q), r)),
        ("p <-> (q <-> r)", Iff(p, Iff(q, r))),
        ("p | q -> r <-> s", Iff(Implies(Or(p, q), r), s)),
        ("p <-> q -> r", Iff(p, Implies(q, r))),
        ("p -> q <-> r -> s", Iff(Implies(p, q), Implies(r, s))),
        ("p & q -> r | s", Implies(And(p, q), Or(r, s))),
        ("K[a] p & q", And(Know("a", p), q)),
        ("K[a] (p & q)", Know("a", And(p, q))),
        ("~K[a] ~p", Not(Know("a", Not(p)))),
        ("K[a] K[b] p", Know("a", Know("b", p))),
        ("C[a, b] p -> E[a, b] p", Implies(Common(("a", "b"), p), Everybody(("a", "b"), p))),
        ("[!p] q -> r", Implies(Announce(p, q), r)),
        ("[!p -> q] r", Announce(Implies(p, q), r)),
        ("[!p] [!q] r", Announce(p, Announce(q, r))),
        ("[![!p] q] r", Announce(Announce(p, q), r)),
        ("<!p> K[a] p | q", Or(AnnounceDiamond(p, Know("a", p)), q)),
        ("<!p -> q> r", AnnounceDiamond(Implies(p, q), r)),
        ("<!<!p> q> r", AnnounceDiamond(AnnounceDiamond(p, q), r)),
        ("[open(a)] p & q", And(After("open(a)", p), q)),
        ("~[!p] ~q", Not(Announce(p, Not(q)))),
        ("p & ~K[a] p", And(p, Not(Know("a", p)))),
    ],
)
def test_precedence_and_associativity(text, tree):
    assert parse_formula(text) == tree


@pytest.mark.parametrize(
    ("alias", "canonical"),
    [
        ("!p", "~p"),
        ("not p", "~p"),
        ("¬p", "~p"),
        ("p && q", "p & q"),
        ("p and q", "p & q"),
        ("p ∧ q", "p & q"),
        ("p || q", "p | q"),
        ("p or q", "p | q"),
        ("p ∨ q", "p | q"),
        ("p => q", "p -> q"),
        ("p → q", "p -> q"),
        ("p <=> q", "p <-> q"),
        ("p ↔ q", "p <-> q"),
        ("⊤ | ⊥", "true | false"),
        ("M[a] p", "~K[a] ~p"),
        ("M[a] (p | q)", "~K[a] ~(p | q)"),
        ("[!!p] q", "[!~p] q"),
        ("not not p and q", "~~p & q"),
    ],
)
def test_aliases_build_the_same_tree(alias, canonical):
    assert parse_formula(alias) == parse_formula(canonical)


def test_keyword_prefixes_are_atoms():
    # Word operators need a word boundary; longer names are ordinary atoms.
    assert parse_formula("nothing & android | order") == Or(
        And(Atom("nothing"), Atom("android")), Atom("order")
    )
    assert parse_formula("Kw2 -> truex") == Implies(Atom("Kw2"), Atom("truex"))
    assert parse_formula("Kx") == Atom("Kx")
    assert parse_formula("CBx | EB1") == Or(Atom("CBx"), Atom("EB1"))


def test_reserved_words_allowed_inside_brackets():
    # Where only a name can occur (agents, actions, arguments), keywords are names.
    assert parse_formula("K[K] p") == Know("K", p)
    assert parse_formula("C[E, and] p") == Common(("E", "and"), p)
    assert parse_formula("CB[CB, EB] p") == CommonBelief(("CB", "EB"), p)
    assert parse_formula("[not] p") == After("not", p)
    assert parse_formula("at(true, K)") == Atom("at", ("true", "K"))


@pytest.mark.parametrize(
    ("text", "printed"),
    [
        ("(p & q) & r", "p & q & r"),
        ("p & (q & r)", "p & (q & r)"),
        ("(p -> q) -> r", "(p -> q) -> r"),
        ("p -> (q -> r)", "p -> q -> r"),
        ("(p <-> q) <-> r", "p <-> q <-> r"),
        ("~(p | q)", "~(p | q)"),
        ("(~p) | q", "~p | q"),
        ("K[a] (~K[b] (p))", "K[a] ~K[b] p"),
        ("[!(p & q)] (r)", "[!p & q] r"),
        ("E[c,a] p", "E[a, c] p"),
        ("CB[c,a] (p)", "CB[a, c] p"),
        ("EB[a] (p & q)", "EB[a] (p & q)"),
        ("M[a] p", "~K[a] ~p"),
        ("not p and q => r", "~p & q -> r"),
        ("at(r1,g1)", "at(r1, g1)"),
        ("[open(a,b)] p", "[open(a, b)] p"),
    ],
)
def test_printing(text, printed):
    assert str(parse_formula(text)) == printed


# --------------------------------------------------------------------------------------
# syntax errors
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "line", "column", "message", "hint"),
    [
        ("K[a p", 1, 5, "expected ']', found 'p'", "close the bracket opened at 1:2"),
        ("p &", 1, 4, "expected a formula, found end of input", "'&' needs a formula on its"),
        ("(p | q", 1, 7, "expected ')', found end of input", "parenthesis opened at 1:1"),
        ("((p)", 1, 5, "expected ')'", "close the parenthesis opened at 1:1"),
        ("[!p q", 1, 5, "found 'q'", "close the bracket opened at 1:1 with ']'"),
        ("<!p q", 1, 5, "found 'q'", "close the '<!' opened at 1:1 with '>'"),
        ("E[] p", 1, 3, "expected an agent name, found ']'", "at least one agent"),
        ("C[a,] p", 1, 5, "expected an agent name, found ']'", None),
        ("p -> -> q", 1, 6, "expected a formula, found '->'", "formula on each side"),
        ("p q", 1, 3, "found 'q'", "connective such as '&'"),
        ("K p", 1, 3, "expected '[', found 'p'", "K[a] p"),
        ("K[a, b] p", 1, 4, "found ','", "use E[...], C[...] or D[...]"),
        ("B[a, b] p", 1, 4, "found ','", "use EB[...] or CB[...]"),
        ("CB[] p", 1, 4, "expected an agent name, found ']'", "at least one agent"),
        ("CB & p", 1, 4, "expected '['", "reserved word"),
        ("E & p", 1, 3, "expected '['", "reserved word"),
        ("p = q", 1, 3, "unexpected character '='", "'->'"),
        ("p - q", 1, 3, "unexpected character '-'", "did you mean '->'?"),
        ("p ^ q", 1, 3, "unexpected character '^'", "'&'"),
        ("p &\n  & q", 2, 3, "expected a formula, found '&'", None),
        ("K[a]\n(p | q\n", 2, 7, "found end of input", "parenthesis opened at 2:1"),
        ("at(r1,", 1, 7, "expected an argument", None),
        ("   ", 1, 1, "empty formula", None),
    ],
)
def test_syntax_error_location_message_and_hint(text, line, column, message, hint):
    with pytest.raises(ParseError) as caught:
        parse_formula(text, filename="goal.txt")
    err = caught.value
    assert (err.line, err.column) == (line, column)
    assert err.filename == "goal.txt"
    assert err.source == text
    assert message in err.message
    if hint is not None:
        assert hint in err.hint


def test_error_renders_with_caret():
    with pytest.raises(ParseError) as caught:
        parse_formula("K[a p")
    assert str(caught.value).splitlines() == [
        "<formula>:1:5: error: expected ']', found 'p'",
        "    K[a p",
        "        ^",
        "hint: close the bracket opened at 1:2 with ']'",
    ]


def test_error_caret_on_second_line():
    with pytest.raises(ParseError) as caught:
        parse_formula("K[a] p &\n  -> q")
    lines = str(caught.value).splitlines()
    assert lines[0] == "<formula>:2:3: error: expected a formula, found '->'"
    assert lines[1:3] == ["      -> q", "      ^"]


def test_errors_belong_to_the_family():
    with pytest.raises(EpistemicaError):
        parse_formula("p &")
    with pytest.raises(InvalidArgumentError):
        parse_formula(42)  # type: ignore[arg-type]


# --------------------------------------------------------------------------------------
# declared names
# --------------------------------------------------------------------------------------
def test_known_agents_and_actions_pass():
    f = parse_formula("C[a, b] K[a] [open(a)] p", agents=["a", "b"], actions=["open"])
    assert f == Common(("a", "b"), Know("a", After("open(a)", p)))
    assert parse_formula("[open(a)] p", actions=["open(a)"]) == After("open(a)", p)


def test_unknown_agent_points_at_it_with_a_close_match():
    with pytest.raises(SpecError) as caught:
        parse_formula("p & K[alcie] q", agents=["alice", "bob"])
    err = caught.value
    assert (err.line, err.column) == (1, 7)
    assert err.message == "unknown agent 'alcie'"
    assert err.hint == "declared agents: alice, bob; did you mean 'alice'?"
    assert str(err).splitlines()[1:3] == ["    p & K[alcie] q", "          ^"]


def test_unknown_agent_in_group_and_without_close_match():
    with pytest.raises(SpecError) as caught:
        parse_formula("C[a,\n  zed] p", agents=["a", "b"])
    err = caught.value
    assert (err.line, err.column) == (2, 3)
    assert err.hint == "declared agents: a, b"


def test_unknown_action():
    with pytest.raises(SpecError) as caught:
        parse_formula("[opn(a)] p", actions=["open", "close"])
    err = caught.value
    assert (err.line, err.column, err.message) == (1, 2, "unknown action 'opn(a)'")
    assert "did you mean 'open'?" in err.hint


# --------------------------------------------------------------------------------------
# reuse from another grammar, as the spec files do
# --------------------------------------------------------------------------------------
_HOST = r"""
start: item*
item: "check" formula ";"                 -> check
    | "agents" NAME ("," NAME)* ";"       -> agents
NAME: /[a-z]+/
%import formula (formula, WS)
%ignore WS
"""


class _Host(Transformer):
    def check(self, children):
        return children[0]

    def agents(self, children):
        return [str(c) for c in children]


def _host() -> Lark:
    return Lark(_HOST, parser="lalr", import_paths=[str(FORMULA_GRAMMAR.parent)])


def test_importing_grammar_builds_the_same_trees():
    text = "agents a, b; check K[a] p & [!q] C[b, a] at(r1, 2); check not true;"
    tree = _host().parse(text)
    built = merge_transformers(_Host(), formula=FormulaBuilder()).transform(tree)
    assert built.children == [
        ["a", "b"],
        parse_formula("K[a] p & [!q] C[a, b] at(r1, 2)"),
        Not(Top()),
    ]


def test_importing_grammar_gets_the_same_error_messages():
    text = "check p &;"
    with pytest.raises(UnexpectedInput) as caught:
        _host().parse(text)
    err = syntax_error(caught.value, text, "x.epi")
    assert (err.line, err.column) == (1, 10)
    assert err.message == "expected a formula, found ';'"
    assert err.hint == "'&' needs a formula on its right"
