"""Laws of epistemic logic hold on random models of the right class."""

from __future__ import annotations

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from epistemica.del_ import (
    Announce,
    Believe,
    Bottom,
    Common,
    CommonBelief,
    Distributed,
    Everybody,
    EverybodyBelieves,
    Iff,
    Implies,
    Know,
    KripkeModel,
    Not,
    bisimilar,
    public_announcement,
)

from epistemic_strategies import AGENTS, formulas, models

small = formulas(max_leaves=6)
agent = st.sampled_from(AGENTS)


def valid(model, formula):
    return bool(model.truth_mask(formula).all())


@settings(max_examples=80)
@given(models("s5"), small, small, agent)
def test_s5_axioms(model, f, g, a):
    K = lambda x: Know(a, x)  # noqa: E731
    assert valid(model, Implies(K(Implies(f, g)), Implies(K(f), K(g))))  # K
    assert valid(model, Implies(K(f), f))  # T
    assert valid(model, Implies(K(f), K(K(f))))  # 4
    assert valid(model, Implies(Not(K(f)), K(Not(K(f)))))  # 5
    assert model.is_s5(a)


@settings(max_examples=80)
@given(models("s5"), small, st.lists(agent, min_size=1, unique=True), agent)
def test_group_knowledge_chain(model, f, group, a):
    assert valid(model, Implies(Common(group, f), Everybody(group, f)))
    assert valid(model, Implies(Everybody(group, f), f))
    # K_a f -> D_G f for a in G (and for the group extended by a).
    assert valid(model, Implies(Know(a, f), Distributed((*group, a), f)))


groups = st.lists(agent, min_size=1, unique=True)
any_kind = st.sampled_from(["s5", "kd45", "any", "kd45-s5"]).flatmap(models)


@settings(max_examples=60)
@given(models("s5"), small, groups)
def test_common_belief_is_common_knowledge_on_s5(model, f, group):
    assert valid(model, Iff(CommonBelief(group, f), Common(group, f)))
    assert valid(model, Iff(EverybodyBelieves(group, f), Everybody(group, f)))


@settings(max_examples=60)
@given(st.sampled_from(["kd45", "kd45-s5"]).flatmap(models), small, groups)
def test_common_belief_implies_everybody_believes_on_kd45(model, f, group):
    assert valid(model, Implies(CommonBelief(group, f), EverybodyBelieves(group, f)))
    # KD45 belief is consistent: common belief in false is impossible.
    assert not model.truth_mask(CommonBelief(group, Bottom())).any()


@settings(max_examples=80)
@given(any_kind, small, groups)
def test_common_belief_fixpoint_and_induction(model, f, group):
    # Valid on every frame: CB f holds at w iff f holds at every world reachable in
    # >= 1 steps; by induction on the length of the path, EB f plus (f -> EB f) at
    # every reachable world gives f at all of them.
    EB = lambda x: EverybodyBelieves(group, x)  # noqa: E731
    CB = lambda x: CommonBelief(group, x)  # noqa: E731
    assert valid(model, Iff(CB(f), EB(f & CB(f))))
    assert valid(model, Implies(CB(Implies(f, EB(f))) & EB(f), CB(f)))


@settings(max_examples=60)
@given(models("kd45-s5"), small, groups)
def test_common_knowledge_implies_common_belief_when_belief_is_inside_knowledge(model, f, group):
    assert valid(model, Implies(Common(group, f), CommonBelief(group, f)))


@settings(max_examples=80)
@given(models("kd45"), small, small, agent)
def test_kd45_axioms_for_belief(model, f, g, a):
    B = lambda x: Believe(a, x)  # noqa: E731
    assert model.is_kd45(a)
    assert valid(model, Implies(B(Implies(f, g)), Implies(B(f), B(g))))  # K
    assert valid(model, Implies(B(f), Not(B(Not(f)))))  # D
    assert valid(model, Implies(B(f), B(B(f))))  # 4
    assert valid(model, Implies(Not(B(f)), B(Not(B(f)))))  # 5


def test_truth_axiom_fails_for_false_belief():
    m = KripkeModel(["w", "v"], {"w": {"p"}}, {"a": [("w", "v"), ("v", "v")]}, "w")
    assert m.is_kd45("a") and not m.is_s5("a")
    assert not valid(m, "B[a] ~p -> ~p")


@settings(max_examples=80)
@given(st.sampled_from(["s5", "kd45", "any"]).flatmap(models), small, small, agent)
def test_announcement_reduction_laws(model, p, q, a):
    ann = lambda x: Announce(p, x)  # noqa: E731
    assert valid(model, "[!p] q <-> (p -> q)")
    assert valid(model, Iff(ann(Know(a, q)), Implies(p, Know(a, ann(q)))))
    assert valid(model, Iff(ann(Believe(a, q)), Implies(p, Believe(a, ann(q)))))
    assert valid(model, Iff(ann(Not(q)), Implies(p, Not(ann(q)))))


@settings(max_examples=60)
@given(st.sampled_from(["s5", "kd45", "any"]).flatmap(models), formulas())
def test_truth_is_invariant_under_minimize(model, f):
    small_model = model.minimize()
    assert small_model.n_worlds <= model.n_worlds
    assert bisimilar(model, small_model)
    # D[G] reads the intersection of relations, which a contraction may enlarge: it is
    # not invariant (tests/del/test_planner_search.py has a counterexample worked by hand)
    assume(not any(isinstance(g, Distributed) for g in f.subformulas()))
    assert model.holds(f) == small_model.holds(f)


@settings(max_examples=60)
@given(st.sampled_from(["s5", "kd45", "any"]).flatmap(models), formulas(), st.randoms())
def test_truth_is_invariant_under_renaming(model, f, rnd):
    names = list(model.worlds)
    shuffled = names[:]
    rnd.shuffle(shuffled)
    rename = {w: f"x{shuffled.index(w)}" for w in names}
    order = sorted(names, key=lambda w: rename[w])  # a different internal order as well
    renamed = KripkeModel(
        [rename[w] for w in order],
        {rename[w]: model.valuation_of(w) for w in order},
        {
            a: [(rename[w], rename[v]) for w in names for v in model.successors(a, w)]
            for a in model.agents
        },
        [rename[w] for w in model.designated],
        atoms=model.atoms,
    )
    assert renamed.truth_set(f) == {rename[w] for w in model.truth_set(f)}


@settings(max_examples=60)
@given(st.sampled_from(["s5", "kd45", "any"]).flatmap(models))
def test_trivial_action_leaves_the_model_bisimilar(model):
    after = model.update(public_announcement("true", model.agents))
    assert after.n_worlds == model.n_worlds
    assert bisimilar(model, after)


@settings(max_examples=60)
@given(models("s5"), small)
def test_announcement_action_equals_restriction(model, f):
    mask = model.truth_mask(f)
    assume(mask[model.designated_positions].any())
    assert bisimilar(model.announce(f), model.update(public_announcement(f, model.agents)))
    assert np.array_equal(model.announce(f).valuation, model.valuation[mask])
