"""The constructs of the spec language, each checked on a hand-worked example."""

from __future__ import annotations

import pytest

from epistemica.del_ import (
    Atom,
    Check,
    Know,
    KripkeModel,
    Not,
    Spec,
    load_spec,
    parse_formula,
    parse_spec,
)


def worlds_where(spec: Spec, formula: str) -> set[frozenset[str]]:
    """The valuations (sets of true atoms) of the worlds where ``formula`` holds."""
    model = spec.model
    return {model.valuation_of(w) for w in model.truth_set(spec.formula(formula), spec.actions)}


# -- declarations ------------------------------------------------------------------------


def test_ranges_expand_in_declaration_order():
    spec = parse_spec("agents c1..c3, x[1..2]\natoms m01..m03, at(r1..r2, g1..g2), p")
    assert spec.agents == ("c1", "c2", "c3", "x1", "x2")
    assert spec.atoms == (
        "m01", "m02", "m03",
        "at(r1, g1)", "at(r1, g2)", "at(r2, g1)", "at(r2, g2)",
        "p",
    )  # fmt: skip


def test_predicate_atoms_are_canonical_and_usable_in_formulas():
    spec = parse_spec("agents a\natoms at(r1,g1), at( r2 , g1 )\nactual {at(r1, g1)}")
    assert spec.atoms == ("at(r1, g1)", "at(r2, g1)")
    assert spec.holds("at(r1,g1) & ~at(r2, g1)")


def test_comments_and_free_layout():
    text = """
    # a comment on its own line
    agents a, b   # a trailing comment
    atoms p,
          q       # a list may span lines
    observes a: p observes b: q   # two statements on one line
    actual {p}
    """
    spec = parse_spec(text)
    assert spec.holds("K[a] p & ~Kw[b] p & K[b] ~q")


def test_statements_may_come_in_any_order():
    spec = parse_spec(
        'check "c": [tell] K[a] p\naction tell: public p\nactual {p}\natoms p\nagents a'
    )
    assert [c.name for c in spec.checks] == ["c"]
    assert spec.holds(spec.checks[0].formula)


# -- the initial model -------------------------------------------------------------------


def test_observes_gives_the_indistinguishability_of_unseen_atoms():
    # a sees p only, b sees q only; the actual world makes p true and q false.
    spec = parse_spec("agents a, b\natoms p, q\nobserves a: p\nobserves b: q\nactual {p}")
    assert spec.model.n_worlds == 4
    assert spec.holds("K[a] p & ~Kw[a] q & K[b] ~q & ~Kw[b] p")
    # K[a] p holds exactly where p is true, whatever q is.
    assert worlds_where(spec, "K[a] p") == {frozenset({"p"}), frozenset({"p", "q"})}


def test_observes_for_several_agents_and_default_nothing():
    spec = parse_spec("agents a, b, c\natoms p\nobserves a, b: p\nactual {p}")
    assert spec.holds("K[a] p & K[b] p & ~Kw[c] p")


def test_law_restricts_the_valuations():
    spec = parse_spec("agents a\natoms p, q\nlaw p -> q\nlaw q -> p\nactual {p, q}")
    assert {spec.model.valuation_of(w) for w in spec.model.worlds} == {
        frozenset(),
        frozenset({"p", "q"}),
    }
    # a sees nothing, but the law makes p and q equivalent, common knowledge.
    assert spec.holds("~Kw[a] p & K[a] (p <-> q)")


def test_without_actual_every_world_is_designated():
    spec = parse_spec("agents a\natoms p, q")
    assert len(spec.model.designated) == spec.model.n_worlds == 4
    assert spec.holds("p | ~p") and not spec.holds("p")


def test_actual_empty_braces_make_every_atom_false():
    spec = parse_spec("agents a\natoms p, q\nactual {}")
    assert spec.holds("~p & ~q")


def test_explicit_worlds_relations_and_partitions():
    text = """
    agents a, b
    atoms p
    world w1 {p}
    world w2 {}
    relation a: {w1, w2}            # a cannot tell w1 from w2
    partition b: {w1}, {w2}         # b can
    designated w1
    """
    spec = parse_spec(text)
    assert spec.model.worlds == ("w1", "w2")
    assert spec.model.designated == ("w1",)
    assert spec.holds("p & ~K[a] p & K[b] p & K[a] Kw[b] p")


def test_arrows_and_both_ways_edges():
    # a: w1 <-> w2 plus loops on both; b: w1 -> w2 only from w1, w2 -> w2.
    text = """
    agents a, b
    atoms p
    world w1 {p}
    world w2 {}
    relation a: w1 <-> w2, w1 -> w1, w2 -> w2
    relation b: w1 -> w2, w2 -> w2
    designated w1
    """
    spec = parse_spec(text)
    assert spec.holds("p & ~K[a] p & B[b] ~p & ~K[a] ~p")
    assert spec.model.is_s5("a") and not spec.model.is_s5("b") and spec.model.is_kd45("b")


def test_separate_knowledge_relation():
    # a believes ~p (points to w2 only) but knows only that p or ~p (both worlds).
    text = """
    agents a
    atoms p
    world w1 {p}
    world w2 {}
    relation a: w1 -> w2, w2 -> w2
    knowledge a: {w1, w2}
    designated w1
    """
    spec = parse_spec(text)
    assert spec.holds("p & B[a] ~p & ~K[a] ~p & ~K[a] p")


def test_several_designated_worlds():
    text = "agents a\natoms p\nworld u {p}\nworld v {}\npartition a: {u, v}\ndesignated u, v"
    spec = parse_spec(text)
    assert spec.model.designated == ("u", "v")
    assert spec.holds("~Kw[a] p") and not spec.holds("p")


# -- actions -----------------------------------------------------------------------------

BASE = "agents a, b\natoms p, q\nactual {p}\n"


def test_public_announcement_one_liner():
    spec = parse_spec(BASE + "action tell: public p")
    assert spec.holds("~Kw[a] p & [tell] (K[a] p & K[b] p & C[a, b] p)")


def test_private_announcement_leaves_the_others_oblivious():
    spec = parse_spec(BASE + "action whisper: private p to a")
    # a learns p; b does not, and b believes a did not learn it either.
    assert spec.holds("[whisper] (K[a] p & ~Kw[b] p & B[b] ~K[a] p)")


def test_semi_private_sensing():
    spec = parse_spec(BASE + "action look: sense p by a")
    assert spec.holds("[look] (K[a] p & ~Kw[b] p & K[b] Kw[a] p)")
    # If p were false, a would know that instead: at the ~p worlds a knows ~p.
    assert worlds_where(spec, "[look] K[a] ~p") >= {frozenset(), frozenset({"q"})}


def test_public_assignment_with_a_precondition():
    spec = parse_spec(BASE + "action swap: assign p := q, q := p when p")
    # Values are those before the assignment, and only p-worlds survive the precondition:
    # {p} becomes {q} and {p, q} stays. So q is common knowledge, p's new value is not.
    assert spec.holds("[swap] (~p & q & C[a, b] q & ~Kw[a] p)")
    assert not spec.model.applicable_in_some(parse_spec(BASE + "action x: assign p := q when q")
                                        .actions["x"])  # fmt: skip


def test_observability_block_with_conditions():
    text = """
    agents a, b
    atoms p, looking(b)
    observes a, b: looking(b)
    actual {p}
    action peek {
        senses p
        full a
        partial b if looking(b)
    }
    action flip {
        effect p := ~p
        full a, b if looking(b)
    }
    """
    spec = parse_spec(text)
    # b is not looking, so b is oblivious to the peek and believes nothing happened.
    assert spec.holds("~Kw[a] p & [peek] (K[a] p & ~Kw[b] p & B[b] ~Kw[a] p)")
    # nor does b notice the flip; a, who saw p before, knows its new value.
    assert spec.holds("[peek][flip] (~p & K[a] ~p & ~Kw[b] p & B[b] ~Kw[a] p)")
    # Had b been looking, b would have seen that a peeked (partial observer).
    assert worlds_where(spec, "[peek] K[b] Kw[a] p") == {
        frozenset({"looking(b)"}),
        frozenset({"p", "looking(b)"}),
    }


def test_observability_block_announces_and_pre():
    text = BASE + "action say {\n pre q | p\n announces p\n full a\n partial b\n}"
    spec = parse_spec(text)
    assert spec.holds("[say] (K[a] p & ~Kw[b] p & K[b] Kw[a] p)")


# b falsely believes that a does not know p: b believes the world w2, where p holds
# but a cannot tell it from w3 (~p); actually (w1) a knows p.
FALSE_BELIEF = """
agents a, b
atoms p
world w1 {p}
world w2 {p}
world w3 {}
partition a: {w1}, {w2, w3}
relation b: w1 -> w2, w2 -> w2, w3 -> w2
knowledge b: {w1, w2, w3}
designated w1
"""


def test_executable_is_checked_at_the_actual_world_only():
    # mA*: B[a] p holds at w1 only. b sees the announcement as the event "p" (its belief
    # world w2 survives), so b comes to believe p, and that a knows it.
    text = FALSE_BELIEF + "action tell {\n announces p\n executable B[a] p\n full a, b\n}"
    spec = parse_spec(text)
    assert spec.holds("B[b] ~K[a] p & [tell] (B[b] p & B[b] K[a] p & ~B[b] false)")
    # The condition is not observed, but it is required where the action happens.
    assert spec.model.applicable_in_some(spec.actions["tell"])
    not_here = parse_spec(text.replace("designated w1", "designated w2"))
    assert not not_here.model.applicable_in_some(not_here.actions["tell"])


def test_precondition_inside_the_events_collapses_the_observers_beliefs():
    # The same condition as `pre`: every event requires B[a] p, which fails at b's only
    # belief world w2, so after the action b has no belief world and believes everything.
    text = FALSE_BELIEF + "action tell {\n pre B[a] p\n announces p\n full a, b\n}"
    assert parse_spec(text).holds("[tell] B[b] false")


def test_executable_line_compiles_to_observability_action():
    from epistemica.del_ import observability_action

    text = BASE + "action say {\n pre q\n announces p\n executable K[a] p\n full a\n}"
    got = parse_spec(text).actions["say"]
    want = observability_action(["a", "b"], pre="q", announces="p", full=["a"],
                                name="say", executable="K[a] p")  # fmt: skip
    assert got.events == want.events and got.pre == want.pre and got.post == want.post
    assert got.designated == want.designated == ("say!",)
    assert got.edges == want.edges and got.knowledge_edges == want.knowledge_edges


def test_action_owners_by_name_and_by_parameter():
    text = """
    agents a, b
    atoms open(a), open(b), p
    actual {}
    action open(i in agents) by i: assign open(i) := true
    action tell by b { announces p  full a, b }
    action toss: assign p := ~p
    """
    spec = parse_spec(text)
    assert spec.owners == {"open(a)": "a", "open(b)": "b", "tell": "b"}
    assert parse_spec("agents a\natoms p\naction x: public p").owners == {}


def test_the_word_by_still_names_sensing_observers_and_atoms():
    text = "agents a, b\natoms by\nactual {by}\naction look by a: sense by by b"
    spec = parse_spec(text)
    assert spec.owners == {"look": "a"}
    assert spec.holds("[look] (K[b] by & ~Kw[a] by)")


def test_explicit_event_model_with_edge_conditions():
    # Two events: 'on' sets q, 'off' clears it. a tells them apart only where p holds.
    text = """
    agents a, b
    atoms p, q
    actual {p}
    action switch {
        event on { pre true post q := true }
        event off { post q := false }
        relation a: on -> on, off -> off, {on, off} if ~p
        relation b: {on, off}
        designated on
    }
    """
    spec = parse_spec(text)
    assert spec.holds("[switch] (q & K[a] q & ~Kw[b] q)")
    assert spec.actions["switch"].events == ("on", "off")


def test_parametrised_schema_expands_agents_and_atoms():
    text = """
    agents a, b
    atoms open(a), open(b)
    actual {open(a)}
    action open(i in agents): assign open(i) := true
    action tell(i in {a, b}, x in {a, b}): private open(x) to i
    """
    spec = parse_spec(text)
    assert list(spec.actions) == [
        "open(a)", "open(b)", "tell(a, a)", "tell(a, b)", "tell(b, a)", "tell(b, b)",
    ]  # fmt: skip
    assert spec.holds("[open(b)] (open(b) & C[a, b] open(b) & ~Kw[a] open(a))")
    assert spec.holds("[tell(b, a)] (K[b] open(a) & ~K[a] open(a) & ~K[a] K[b] open(a))")
    assert spec.holds("[tell(b, b)] false")  # open(b) is false: not executable


def test_parameters_bind_modal_agents_and_whole_atom_names():
    text = """
    agents a, b
    atoms p, q
    observes a: p
    actual {p, q}
    action ask(i in agents): public K[i] p
    action set(x in {p, q}): assign x := false
    """
    spec = parse_spec(text)
    assert spec.holds("[ask(a)] K[b] K[a] p")
    # K[b] p is false, so ask(b) cannot happen: every box over it is vacuous.
    assert spec.holds("[ask(b)] false")
    assert spec.holds("[set(q)] (p & ~q)") and spec.holds("[set(p)] (~p & q)")


# -- goal and checks ---------------------------------------------------------------------


def test_goal_and_checks():
    text = """
    agents a
    atoms p
    actual {p}
    goal K[a] p
    check "not yet": K[a]   p   expect false
    check "default expectation is true": ~K[a] p
    check "explicit true": p expect true
    """
    spec = parse_spec(text, filename="g.epi")
    assert spec.goal == Know("a", Atom("p"))
    assert [(c.name, c.expected) for c in spec.checks] == [
        ("not yet", False),
        ("default expectation is true", True),
        ("explicit true", True),
    ]
    first = spec.checks[0]
    assert isinstance(first, Check)
    assert first.text == "K[a] p"  # whitespace collapsed
    assert first.formula == parse_formula("K[a] p")
    assert (first.filename, first.line, first.column) == ("g.epi", 6, 5)
    assert first.location == "g.epi:6:5"
    assert spec.checks[1].formula == Not(Know("a", Atom("p")))


def test_spec_formula_resolves_actions_of_the_spec():
    spec = parse_spec(BASE + "action tell(i in agents): private p to i")
    assert spec.holds("[tell(a)] K[a] p") and not spec.holds("[tell(b)] K[a] p")


def test_load_spec_reads_a_file(tmp_path):
    path = tmp_path / "tiny.epi"
    path.write_text("agents a\natoms p\nactual {p}\n", encoding="utf-8")
    spec = load_spec(path)
    assert spec.filename == str(path)
    assert isinstance(spec.model, KripkeModel)
    assert "tiny.epi" in repr(spec)


@pytest.mark.parametrize("word", ["nothing", "observed", "actually", "designate"])
def test_names_that_start_with_a_keyword_are_names(word):
    spec = parse_spec(f"agents a\natoms {word}\nactual {{{word}}}")
    assert spec.atoms == (word,) and spec.holds(word)
