"""The AGM-style laws of conditional belief, safe belief and soft upgrades (Baltag and
Smets 2008; van Benthem 2007), as properties of random plausibility models."""

from __future__ import annotations

import numpy as np
from hypothesis import find, given, settings
from hypothesis import strategies as st
from plausibility_strategies import plausibility_formulas, plausibility_models

from epistemica.del_.explicit.checker import evaluate
from epistemica.del_.language.formula import Bottom, Not, Top
from epistemica.del_.language.modalities import (
    Announce,
    Believe,
    ConditionalBelief,
    ConservativeUpgrade,
    Know,
    RadicalUpgrade,
    SafeBelief,
)

formulas = plausibility_formulas(max_leaves=5)
facts = plausibility_formulas(max_leaves=4, dynamic=False).filter(lambda f: f.modal_depth() == 0)
agents = st.sampled_from(["a", "b"])


def possible(agent, f):
    return Not(Know(agent, Not(f)))


def valid(model, f):
    return bool(model.truth(f).all())


def same(model, f, g):
    return model.truth(f).tolist() == model.truth(g).tolist()


@given(plausibility_models(), agents, formulas)
def test_unconditional_is_conditional_on_true(model, a, f):
    assert same(model, Believe(a, f), ConditionalBelief(a, Top(), f))


@given(plausibility_models(), agents, formulas)
def test_plain_belief_means_what_it_means_in_kripke_models(model, a, f):
    # B[a] is KD45 over the relation to the best worlds of the cell: the existing checker
    # on the induced Kripke model gives the same truth set (for formulas it interprets).
    g = Believe(a, f)
    if not any(
        isinstance(x, (ConditionalBelief, SafeBelief, RadicalUpgrade, ConservativeUpgrade))
        for x in g.subformulas()
    ):
        assert evaluate(model.to_kripke(), g).tolist() == model.truth(g).tolist()


@given(plausibility_models(), agents, formulas)
def test_knowledge_implies_safe_belief_implies_belief(model, a, f):
    assert valid(model, Know(a, f) >> SafeBelief(a, f))
    assert valid(model, SafeBelief(a, f) >> Believe(a, f))


@given(plausibility_models(), agents, formulas, formulas)
def test_safe_belief_is_s4(model, a, f, g):
    sb = SafeBelief
    assert valid(model, sb(a, f) >> f)  # T
    assert valid(model, sb(a, f) >> sb(a, sb(a, f)))  # 4
    assert valid(model, sb(a, f >> g) >> (sb(a, f) >> sb(a, g)))  # K


@given(plausibility_models(), agents, formulas)
def test_conditional_belief_is_consistent_when_the_condition_is_possible(model, a, f):
    assert valid(model, possible(a, f) >> Not(ConditionalBelief(a, f, Bottom())))
    assert valid(model, ConditionalBelief(a, f, f))  # success of the condition


@given(plausibility_models(), agents, facts)
def test_success_of_upgrades(model, a, f):
    # A fact keeps its truth set through an upgrade: when it is possible in the cell,
    # the agent believes it afterwards (not so for epistemic f: Moore sentences).
    assert valid(model, possible(a, f) >> RadicalUpgrade(f, Believe(a, f)))
    assert valid(model, possible(a, f) >> ConservativeUpgrade(f, Believe(a, f)))


@given(plausibility_models(), formulas)
def test_radical_upgrade_puts_the_zone_first_and_keeps_the_rest(model, f):
    truth = model.truth(f)
    after = model.radical_upgrade(truth)
    for a in model.agents:
        same_cell = model.cells[a][:, None] == model.cells[a][None, :]
        before_le = model.ranks[a][:, None] <= model.ranks[a][None, :]
        after_le = after.ranks[a][:, None] <= after.ranks[a][None, :]
        zone = truth[:, None] == truth[None, :]
        assert (after_le == before_le)[same_cell & zone].all()
        # every f-world strictly before every ~f-world of its cell
        assert (after_le & ~after_le.T)[same_cell & truth[:, None] & ~truth[None, :]].all()
        assert (after.cells[a] == model.cells[a]).all()


@given(plausibility_models(), formulas)
def test_conservative_upgrade_only_changes_the_top(model, f):
    truth = model.truth(f)
    after = model.conservative_upgrade(truth)
    for a in model.agents:
        best = model.best(a, truth)
        same_cell = model.cells[a][:, None] == model.cells[a][None, :]
        before_le = model.ranks[a][:, None] <= model.ranks[a][None, :]
        after_le = after.ranks[a][:, None] <= after.ranks[a][None, :]
        rest = ~best[:, None] & ~best[None, :]
        assert (after_le == before_le)[same_cell & rest].all()
        assert (after_le & ~after_le.T)[same_cell & best[:, None] & ~best[None, :]].all()
        assert (after_le & after_le.T)[same_cell & best[:, None] & best[None, :]].all()


@settings(max_examples=200)
@given(plausibility_models(), agents, formulas, formulas, formulas)
def test_recursion_axiom_for_conditional_belief_after_radical_upgrade(model, a, f, g, h):
    # van Benthem (2007): [^^f] B[a | g] h <-> (M[a] (f & [^^f] g) & B[a | f & [^^f] g] [^^f] h)
    #                                        | (~M[a] (f & [^^f] g) & B[a | [^^f] g] [^^f] h)
    up_g, up_h = RadicalUpgrade(f, g), RadicalUpgrade(f, h)
    zone = possible(a, f & up_g)
    right = (zone & ConditionalBelief(a, f & up_g, up_h)) | (
        Not(zone) & ConditionalBelief(a, up_g, up_h)
    )
    assert same(model, RadicalUpgrade(f, ConditionalBelief(a, g, h)), right)
    # and the simple ones: upgrades change no fact and no knowledge
    assert same(model, RadicalUpgrade(f, Know(a, g)), Know(a, RadicalUpgrade(f, g)))
    assert same(model, RadicalUpgrade(f, Not(g)), Not(RadicalUpgrade(f, g)))


@settings(max_examples=200)
@given(plausibility_models(), agents, formulas, formulas, formulas)
def test_recursion_axiom_for_conditional_belief_after_conservative_upgrade(model, a, f, g, h):
    # [^f] B[a | g] h <-> (B[a | f] ~[^f] g & B[a | [^f] g] [^f] h)
    #                   | (~B[a | f] ~[^f] g & B[a | f & [^f] g] [^f] h)
    up_g, up_h = ConservativeUpgrade(f, g), ConservativeUpgrade(f, h)
    miss = ConditionalBelief(a, f, Not(up_g))
    right = (miss & ConditionalBelief(a, up_g, up_h)) | (
        Not(miss) & ConditionalBelief(a, f & up_g, up_h)
    )
    assert same(model, ConservativeUpgrade(f, ConditionalBelief(a, g, h)), right)
    assert same(model, ConservativeUpgrade(f, Know(a, g)), Know(a, ConservativeUpgrade(f, g)))


@settings(max_examples=200)
@given(plausibility_models(), agents, formulas, formulas, formulas)
def test_recursion_axiom_for_conditional_belief_after_announcement(model, a, f, g, h):
    # [!f] B[a | g] h <-> (f -> B[a | f & [!f] g] [!f] h)
    left = Announce(f, ConditionalBelief(a, g, h))
    right = f >> ConditionalBelief(a, f & Announce(f, g), Announce(f, h))
    assert same(model, left, right)


@given(plausibility_models(), agents, facts, facts)
def test_upgrades_of_a_fact_already_believed_change_no_belief(model, a, f, g):
    # Preservation (AGM K*4 for conservative upgrade): if a believes f, ^f keeps B[a] g.
    believes = Believe(a, f)
    assert valid(model, believes >> (Believe(a, g) >> ConservativeUpgrade(f, Believe(a, g))))


def test_the_models_are_varied():
    # Guard against a strategy that only draws trivial models: some example must have a
    # cell with more than one rank.
    found = find(
        plausibility_models(),
        lambda m: any(len(np.unique(m.ranks[a][m.cells[a] == 0])) > 2 for a in m.agents),
    )
    assert found.n_worlds >= 3
