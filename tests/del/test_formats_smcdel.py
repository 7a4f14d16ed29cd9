"""SMCDEL's text format: reading (precedence as SMCDEL's parser, hand-worked answers), errors,
and the round trip spec -> SMCDEL -> spec on random observational models and formulas."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import epistemica.del_.formats.smcdel as smcdel
from epistemica.del_ import KripkeModel
from epistemica.del_.errors import ParseError, SpecError
from epistemica.del_.explicit.bisimulation import bisimilar
from epistemica.del_.formats.smcdel import MAX_ONEOF, parse_smcdel
from epistemica.del_.formats.smcdel_export import to_smcdel
from epistemica.del_.language.formula import And, Atom, Not
from epistemica.del_.language.modalities import Know
from epistemica.del_.planning.planner import project
from epistemica.del_.spec import MAX_CLAIMS, Check, Spec, load_spec
from epistemica.del_.spec import _source as source
from tests.epistemic_strategies import formulas

# Three children, each seeing the others' foreheads (written for this test).
CHILDREN = """-- muddy children
VARS 1,2,3
LAW  Top
OBS  alice: 2,3
     bob:   1,3
     carol: 1,2
TRUE? {1,2} bob knows that 1 & ~ bob knows whether 2
VALID? [ ! (1|2|3) ] [ ! AND (~ alice knows whether 1, ~ bob knows whether 2,
        ~ carol knows whether 3) ] [ ! AND (~ alice knows whether 1,
        ~ bob knows whether 2, ~ carol knows whether 3) ] (1 & 2 & 3)
VALID? (alice, bob) distknow whether 1
WHERE? < ! (1|2|3) > (alice knows whether 1 | bob knows whether 2 | carol knows whether 3)
"""


def test_the_muddy_children_answers_by_hand():
    found = parse_smcdel(CHILDREN)
    spec = found.spec
    assert spec.atoms == ("p1", "p2", "p3") and spec.agents == ("alice", "bob", "carol")
    assert spec.model.n_worlds == 8 and len(spec.model.designated) == 8
    # at {1,2}: bob sees 1 and not his own 2; after the father and two rounds of "nobody
    # knows" only the state where all three are muddy survives; bob sees 1 and alice 2, so
    # together they know whether 1.
    assert [spec.holds(c.formula) for c in spec.checks] == [True, True, True]
    # someone knows after the father exactly where one child is muddy
    ((_, where),) = found.where
    mask = spec.model.truth_mask(where)
    worlds = [w for w, m in zip(spec.model.worlds, mask, strict=True) if m]
    states = sorted(tuple(sorted(spec.model.valuation_of(w))) for w in worlds)
    assert states == [("p1",), ("p2",), ("p3",)]


def test_precedence_is_smcdel_s():
    text = "VARS 1,2 LAW Top OBS a: 1 b: 2\nVALID? K a 1 & 2\nVALID? a knows that 1 & 2\n"
    first, second = (c.formula for c in parse_smcdel(text).spec.checks)
    p1, p2 = Atom("p1"), Atom("p2")
    assert first == Know("a", And(p1, p2))  # K a scopes over the rest
    assert second == And(Know("a", p1), p2)  # "knows that" binds tighter than &


def test_group_announcements_are_actions():
    spec = parse_smcdel("VARS 1,2 LAW Top OBS a: 2 b: 2\n"
                        "VALID? [ a ! 1 ] a knows that 1\n"
                        "VALID? [ a ! 1 ] ~ b knows whether 1\n"
                        "VALID? [ a ! 1 ] b knows that (a knows whether 1)\n").spec  # fmt: skip
    assert len(spec.actions) == 3
    # a learns 1; b learns only that a learned whether 1
    assert [spec.holds(c.formula) for c in spec.checks] == [True, True, True]


def test_boolean_quantifiers_in_both_spellings():
    # Forall 1: the body with 1 true and with 1 false; checked by hand at every world.
    spec = parse_smcdel("VARS 1,2 LAW Top OBS a: 1 b: 2\n"
                        "VALID? Forall 1 (1 | ~1)\n"
                        "VALID? ForAll 1,2 (1 -> 2)\n"
                        "VALID? Exists 1 (1 & 2) iff 2\n"
                        "VALID? Forall 2 (1 | 2)\n").spec  # fmt: skip
    assert [spec.holds(c.formula) for c in spec.checks] == [True, False, True, False]


@pytest.mark.parametrize("backend", ["explicit", "symbolic"])
def test_nested_group_announcements(backend):
    # [a ! 1] 1 is valid (announcing 1 changes no valuation), so the outer announcement
    # announces a truth everywhere: [a ! Top] g is g after it, here 1 (not valid) and Bot.
    spec = parse_smcdel("VARS 1,2 LAW Top OBS a: 1 b: 2\n"
                        "VALID? [ a ! 1 ] 1\n"
                        "VALID? [ a ! [ a ! 1 ] 1 ] 1\n"
                        "VALID? [ a ! [ a ! 1 ] 1 ] Bot\n"
                        "VALID? [ a ! [ a ! 1 ] 1 ] (1 | ~1)\n", backend=backend).spec  # fmt: skip
    assert [spec.holds(c.formula) for c in spec.checks] == [True, False, False, True]


def test_a_symbolic_spec_is_exported_without_listing_worlds():
    # 2^201 states: written from the structure's law, observables and claims (the export
    # of drinking_logicians_400 and sum_and_product, checked the same way, takes longer).
    spec = load_spec("specs/puzzles/dining_cryptographers_100.epi")
    text = to_smcdel(spec)
    back = parse_smcdel(text).spec
    assert back.atoms == spec.atoms and "LAW  OR (" in text
    assert [back.holds(c.formula) for c in back.checks] == [True] * len(spec.checks)


def test_errors_are_located():
    with pytest.raises(ParseError) as info:
        parse_smcdel("VARS 1,2\nLAW Top\nOBS a: 1\nVALID? (1 &", "x.smcdel")
    assert info.value.filename == "x.smcdel" and info.value.line == 4
    with pytest.raises(SpecError) as info:
        parse_smcdel("VARS 1,2\nLAW Top\nOBS a: 3\n", "x.smcdel")
    assert "atom 3 is not in VARS" in info.value.message and info.value.line == 3
    with pytest.raises(SpecError) as info:
        parse_smcdel("VARS 1\nLAW Top\nOBS a: 1\nVALID? bob knows that 1\n", "x.smcdel")
    assert "agent 'bob' is not in OBS" in info.value.message and info.value.line == 4


def test_the_shipped_muddy_children_survive_a_round_trip():
    spec = load_spec("specs/puzzles/muddy_children.epi")
    back = parse_smcdel(to_smcdel(spec)).spec
    assert back.atoms == spec.atoms
    assert [back.holds(c.formula) for c in back.checks] == [True] * len(spec.checks)


_LAWS = st.sampled_from(["true", "p | q", "~(p & q & r)", "p -> r", "q <-> ~r"])


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    observes=st.fixed_dictionaries(
        {a: st.lists(st.sampled_from(["p", "q", "r"]), unique=True) for a in ("a", "b")}
    ),
    law=_LAWS,
    actual=st.one_of(st.none(), st.lists(st.sampled_from(["p", "q", "r"]), unique=True)),
    claim=formulas(max_leaves=8),
)
def test_random_structures_and_claims_survive_a_round_trip(observes, law, actual, claim):
    model = KripkeModel.from_observables(["p", "q", "r"], observes, law)
    if actual is not None:
        chosen = [w for w in model.worlds if model.valuation_of(w) == frozenset(actual)]
        if not chosen:
            return  # the actual valuation violates the law
        model = model.repoint(chosen)
    check = Check("random", str(claim), claim, True, "<random>", 1, 1)
    spec = Spec(model=model, actions={}, goal=None, checks=(check,), agents=("a", "b"),
                atoms=("p", "q", "r"), filename="<random>", source="")  # fmt: skip
    back = parse_smcdel(to_smcdel(spec)).spec
    everywhere = back.model.repoint(back.model.worlds)
    mine = model.repoint(model.worlds)
    assert bisimilar(project(mine, ["p", "q", "r"]), project(everywhere, ["p", "q", "r"]))
    assert back.holds(back.checks[0].formula) == spec.holds(claim)


def test_chains_deeper_than_the_recursion_limit_are_read():
    # 5,001 negations are one negation; a chain 1|1|...|2 of 5,000 terms is 1|2.
    n = 5_000
    text = (f"VARS 1,2\nLAW Top\nOBS a: 1\nVALID? {'~' * (n + 1)}(1 & ~1)\n"
            f"TRUE? {{2}} {'1|' * n}2\nVALID? {'1|' * n}2 iff (1 | 2)\n")  # fmt: skip
    spec = parse_smcdel(text).spec
    first = spec.checks[0].formula
    for _ in range(n + 1):
        assert isinstance(first, Not)
        first = first.operand
    assert [spec.holds(c.formula) for c in spec.checks] == [True, True, True]


def test_quantifier_and_oneof_expansions_are_bounded_and_located(monkeypatch):
    monkeypatch.setattr(smcdel, "MAX_EXPANSION", 16)
    head = "VARS 1,2,3,4,5\nLAW Top\nOBS a: 1\n"
    # 2^4 copies of a one-node body: at the limit, read; Exists 1..4 (5) is 5
    spec = parse_smcdel(head + "VALID? (Exists 1,2,3,4 5) iff 5\n").spec
    assert spec.checks[0].formula.atoms() == {Atom("p5")} and spec.holds(spec.checks[0].formula)
    with pytest.raises(SpecError) as info:  # 2^5 copies
        parse_smcdel(head + "VALID? 1 & Forall 1,2,3,4,5 5\n")
    assert (info.value.line, info.value.column) == (4, 12)
    assert "over 5 variables" in info.value.message and "more than 16 nodes" in info.value.message
    many = ",".join("1" for _ in range(MAX_ONEOF + 1))
    with pytest.raises(SpecError) as info:
        parse_smcdel(f"VARS 1\nLAW Top\nOBS a: 1\nVALID? ONEOF({many})\n")
    assert info.value.line == 4 and f"more than {MAX_ONEOF:,}" in info.value.message
    # At the limit, read: checked at a limit of 16 (16^2 literals; 1,000 took 30 s).
    monkeypatch.setattr(smcdel, "MAX_ONEOF", 16)
    with pytest.raises(SpecError, match="ONEOF of 17 formulas: more than 16"):
        parse_smcdel(f"VARS 1\nLAW Top\nOBS a: 1\nVALID? ONEOF({many[: 2 * 17 - 1]})\n")
    spec = parse_smcdel(f"VARS 1\nLAW Top\nOBS a: 1\nVALID? ~ONEOF({many[: 2 * 16 - 1]})\n").spec
    assert spec.holds(spec.checks[0].formula)  # 16 copies of 1: never exactly one true


def test_a_file_over_the_token_limit_is_refused_before_parsing(monkeypatch):
    # tokens: VARS 1 , 2 NL (5), LAW Top NL (3), OBS a : 1 NL (5); VALID ? 1 | 2 NL (6 each)
    monkeypatch.setattr(source, "MAX_TOKENS", 13 + 6 * 5)
    text = "VARS 1,2\nLAW Top\nOBS a: 1\n" + "VALID? 1|2\n" * 5
    assert len(parse_smcdel(text).spec.checks) == 5
    with pytest.raises(SpecError) as info:
        parse_smcdel(text + "VALID? 1\n", "x.smcdel")  # token 44: 'VALID' at 9:1
    assert (info.value.filename, info.value.line, info.value.column) == ("x.smcdel", 9, 1)
    assert "more than 43 tokens" in info.value.message


def test_more_jobs_than_claims_allowed_are_refused_before_parsing():
    head = "VARS 1\nLAW Top\nOBS a: 1\n"
    jobs = "VALID? 1 | ~1\nTRUE? {1} 1\nWHERE? 1\n"
    found = parse_smcdel(head + jobs * (MAX_CLAIMS // 3) + "VALID? 1 | ~1\n")
    assert len(found.spec.checks) + len(found.where) == MAX_CLAIMS == 10_000
    with pytest.raises(SpecError) as info:
        parse_smcdel(head + jobs * (MAX_CLAIMS // 3) + "VALID? 1\n  WHERE? 1\n", "x.smcdel")
    assert (info.value.line, info.value.column) == (3 + MAX_CLAIMS + 1, 3)
    assert f"more than {MAX_CLAIMS} claims" in info.value.message
