"""EpistemicState: the group semantics against the product update, its two backends against
each other, and the laws of soft evidence and awareness.

The reference is the engine's own product update: the observations' action models
(:meth:`Observation.action_model`) applied to a model whose every agent considers every
world possible. For chains of ``K`` (or of ``B``, without soft facts or awareness) the
state's sets must give the same verdicts as that model.
"""

from __future__ import annotations

import itertools
from functools import partial

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from epistemica.del_ import (
    And,
    Atom,
    Bottom,
    EpistemicState,
    Iff,
    Implies,
    InvalidArgumentError,
    KripkeModel,
    Not,
    Observation,
    Or,
    Top,
    as_formula,
)
from epistemica.del_.explicit.checker import propositional_truth
from epistemica.del_.state.explicit import (
    ValuationTable,
    belief_mask,
    belief_masks,
    group_model,
    knowledge_mask,
)
from epistemica.del_.state.state import REVISIONS
from epistemica.del_.state.symbolic import (
    belief_bdd,
    count,
    group_structure,
    knowledge_bdd,
    world_space,
)

from epistemic_strategies import formulas

ATOMS = ("p", "q", "r")
AGENTS = ("a", "b", "c")
facts = st.recursive(
    st.sampled_from([Atom(a) for a in ATOMS] + [Top(), Bottom()]),
    lambda inner: st.one_of(
        inner.map(Not),
        *(st.builds(kind, inner, inner) for kind in (And, Or, Implies, Iff)),
    ),
    max_leaves=5,
)
group_formulas = formulas(ATOMS, AGENTS, max_leaves=6, announcements=False)
ALL = np.array(list(itertools.product([False, True], repeat=len(ATOMS))))


def truth(fact, val=ALL):
    column = {a: i for i, a in enumerate(ATOMS)}
    return propositional_truth(fact, len(val), lambda key: val[:, column[key]])


@st.composite
def histories(draw, soft=True, awareness=True):
    """Worlds (valuations satisfying a law), the actual world, and observations that are
    true of it; soft facts may be false (evidence, not knowledge)."""
    law = draw(facts.filter(lambda f: truth(f).any()))
    worlds = ALL[truth(law)]
    actual = worlds[draw(st.integers(0, len(worlds) - 1))]
    tracked = draw(st.sets(st.sampled_from(ATOMS))) if awareness else set()
    observations = []
    for _ in range(draw(st.integers(0, 5))):
        full = draw(st.sets(st.sampled_from(AGENTS)))
        partial = draw(st.sets(st.sampled_from(AGENTS)))
        kinds = ["pre", "senses"] + (["suggests"] if soft else [])
        kinds += ["aware"] if tracked else []
        kind = draw(st.sampled_from(kinds))
        fact = draw(facts)
        if kind == "pre":
            if not truth(fact, actual[None])[0]:
                fact = ~fact
            observations.append(Observation("e", full, partial, pre=fact))
        elif kind == "senses":
            held = bool(truth(fact, actual[None])[0])
            observations.append(Observation("e", full, partial, senses=fact, outcome=held))
        elif kind == "suggests":
            observations.append(Observation("e", full, partial, suggests=fact))
        else:
            atoms = draw(st.sets(st.sampled_from(sorted(tracked)), min_size=1))
            observations.append(Observation("e", full, partial, aware=atoms))
    return law, worlds, actual, tracked, observations


def _state(tracked, observations):
    state = EpistemicState(AGENTS, tracked=tracked)
    for o in observations:
        state.observe(o)
    return state


def _reference(worlds, observations):
    """The product update of the observations' action models, every world designated."""
    val = {
        f"w{i}": [a for a, t in zip(ATOMS, row, strict=True) if t] for i, row in enumerate(worlds)
    }
    names = list(val)
    everything = [(u, v) for u in names for v in names]
    model = KripkeModel(names, val, dict.fromkeys(AGENTS, everything), names, atoms=ATOMS)
    for o in observations:
        if o.hard_fact(True) is not None:
            model = model.update(o.action_model(AGENTS))
    return model


chains = st.lists(st.sampled_from(AGENTS), min_size=1, max_size=3)


@settings(max_examples=80, deadline=None)
@given(histories(soft=False, awareness=False), chains, facts)
def test_knowledge_chains_agree_with_the_product_update(history, chain, fact):
    _, worlds, _, tracked, observations = history
    state = _state(tracked, observations)
    reference = _reference(worlds, observations)
    table = ValuationTable(ATOMS, worlds)
    kept = knowledge_mask(state, chain, table)
    expected = bool(truth(fact, worlds)[kept].all())
    prefix = "".join(f"K[{a}] " for a in chain)
    assert reference.holds(f"{prefix}({fact})") == expected
    prefix = "".join(f"B[{a}] " for a in chain)  # no soft facts: B chains see the same
    assert reference.holds(f"{prefix}({fact})") == bool(
        truth(fact, worlds)[belief_mask(state, chain, table)].all()
    )


@settings(max_examples=60, deadline=None)
@given(histories(), st.lists(chains, min_size=1, max_size=4))
def test_the_actual_world_stays_known_and_beliefs_stay_within_knowledge(history, groups):
    _, worlds, actual, tracked, observations = history
    state = _state(tracked, observations)
    table = ValuationTable(ATOMS, worlds)
    here = int(np.flatnonzero((worlds == actual).all(axis=1))[0])
    for chain in groups:
        know, believe = knowledge_mask(state, chain, table), belief_mask(state, chain, table)
        assert know[here]
        assert not (believe & ~know).any()
        conceivable = table.conceivable(frozenset(tracked) - state.aware(chain))
        assert believe.any() == (know & conceivable).any()
        assert not (believe & ~conceivable).any()


@settings(max_examples=60, deadline=None)
@given(histories(), chains)
def test_soft_evidence_is_a_lexicographic_upgrade(history, chain):
    """Success for the newest consistent fact; vacuity when all are jointly consistent."""
    _, worlds, _, tracked, observations = history
    state = _state(tracked, observations)
    table = ValuationTable(ATOMS, worlds)
    base = knowledge_mask(state, chain, table) & table.conceivable(
        frozenset(tracked) - state.aware(chain)
    )
    believe = belief_mask(state, chain, table)
    soft = state.soft(chain)
    consistent = [f for f in soft if (base & truth(f, worlds)).any()]
    if consistent:  # the newest fact consistent with the hard evidence is believed
        assert truth(consistent[0], worlds)[believe].all()
    joint = base.copy()
    for f in soft:
        joint &= truth(f, worlds)
    if joint.any():
        assert np.array_equal(believe, joint)
    if not soft:
        assert np.array_equal(believe, base)


@settings(max_examples=60, deadline=None)
@given(histories(), chains)
def test_primacy_revision_keeps_the_oldest_consistent_fact(history, chain):
    """The ablation mirrors recency: success for the oldest consistent fact, the same set
    whenever the soft facts are jointly consistent (then the order cannot matter)."""
    _, worlds, _, tracked, observations = history
    state = _state(tracked, observations)
    table = ValuationTable(ATOMS, worlds)
    base = knowledge_mask(state, chain, table) & table.conceivable(
        frozenset(tracked) - state.aware(chain)
    )
    believe = belief_mask(state, chain, table, revision="primacy")
    consistent = [f for f in state.soft(chain)[::-1] if (base & truth(f, worlds)).any()]
    if consistent:
        assert truth(consistent[0], worlds)[believe].all()
    joint = base.copy()
    for f in state.soft(chain):
        joint &= truth(f, worlds)
    if joint.any():
        assert np.array_equal(believe, belief_mask(state, chain, table))


def test_the_oldest_of_two_contradicting_suggestions_wins_under_primacy():
    table = ValuationTable(["p"], np.array([[False], [True]]))
    state = EpistemicState(["a"])
    state.observe(Observation("seen", full={"a"}, suggests="p"))
    state.observe(Observation("seen", full={"a"}, suggests="~p"))
    assert belief_mask(state, ("a",), table, revision="primacy").tolist() == [False, True]
    assert belief_mask(state, ("a",), table).tolist() == [True, False]
    with pytest.raises(InvalidArgumentError, match="unknown revision"):
        belief_mask(state, ("a",), table, revision="latest")


def test_the_newest_of_two_contradicting_suggestions_wins():
    table = ValuationTable(["p"], np.array([[False], [True]]))
    state = EpistemicState(["a", "b"])
    state.observe(Observation("seen", full={"a", "b"}, suggests="p"))
    state.observe(Observation("seen", full={"a"}, suggests="~p"))
    assert belief_mask(state, ("a",), table).tolist() == [True, False]
    assert belief_mask(state, ("b",), table).tolist() == [False, True]
    assert belief_mask(state, ("a", "b"), table).tolist() == [False, True]
    assert knowledge_mask(state, ("a",), table).tolist() == [True, True]


def test_awareness_makes_a_world_conceivable_for_the_group_that_saw_it():
    table = ValuationTable(["door_closed"], np.array([[False], [True]]))
    state = EpistemicState(["a", "b"], tracked=["door_closed"])
    assert belief_mask(state, ("a",), table).tolist() == [True, False]  # by default, open
    state.observe(Observation("close", full={"a"}, pre="door_closed", aware={"door_closed"}))
    assert belief_mask(state, ("a",), table).tolist() == [False, True]
    assert belief_mask(state, ("b",), table).tolist() == [True, False]  # a false belief
    assert knowledge_mask(state, ("b",), table).tolist() == [True, True]
    model = group_model(state, table)
    assert model.holds("K[a] door_closed & B[b] ~door_closed & ~K[b] ~door_closed")
    assert model.holds("K[a] B[b] ~door_closed")


@settings(max_examples=60, deadline=None)
@given(histories(), st.lists(chains, min_size=1, max_size=4))
def test_equal_signatures_give_equal_sets(history, groups):
    _, worlds, _, tracked, observations = history
    state = _state(tracked, observations)
    table = ValuationTable(ATOMS, worlds)
    shared = belief_masks(state, groups, table)
    for chain, mask in zip(groups, shared, strict=True):
        assert np.array_equal(mask, belief_mask(state, chain, table))


def _renamed(observations):
    """The same observations under distinct names: no two have the same content, so the
    state records every one (the reference without the skipping of repeats)."""
    return [
        Observation(f"e{k}", o.full, o.observers - o.full, o.pre, o.senses, o.outcome,
                    o.suggests, o.aware)
        for k, o in enumerate(observations)
    ]  # fmt: skip


@settings(max_examples=150, deadline=None)
@given(histories(), st.data(), st.sampled_from(REVISIONS))
def test_skipping_a_repeated_observation_changes_no_belief(history, data, revision):
    """An observation repeated with the same or fewer observers, after any history (soft
    facts in between included): every group's belief is that of recording it again."""
    _, worlds, _, tracked, observations = history
    if not observations:
        return
    soft = [o for o in observations if o.suggests is not None and o.full]
    o = data.draw(st.sampled_from(soft or observations))
    fewer = data.draw(st.sets(st.sampled_from(sorted(o.full)), min_size=1)) if o.full else set()
    repeat = Observation(o.name, fewer, set(), o.pre, o.senses, o.outcome, o.suggests, o.aware)
    later = data.draw(st.lists(st.sampled_from(observations), max_size=2))
    if o.suggests is not None:  # the case that matters: contrary evidence in between
        later.append(Observation("e", data.draw(st.sets(st.sampled_from(AGENTS))), set(),
                                 suggests=Not(o.suggests)))  # fmt: skip
    sequence = [*observations, *later, repeat]
    state, reference = _state(tracked, sequence), _state(tracked, _renamed(sequence))
    table = ValuationTable(ATOMS, worlds)
    for chain in itertools.product(AGENTS, repeat=2):
        assert np.array_equal(
            belief_mask(state, chain, table, revision),
            belief_mask(reference, chain, table, revision),
        ), chain


def test_a_settle_seen_again_after_another_is_the_newest_again():
    """a sees c settle at g1, then at g2, then at g1 again: g1 is the newest evidence."""
    s = EpistemicState(["a", "c"])
    for goal in ("g1", "g2", "g1"):
        assert s.observe(Observation("settle", full={"a", "c"}, suggests=f"at_c_{goal}"))
    assert [str(f) for f in s.soft(("a",))] == ["at_c_g1", "at_c_g2", "at_c_g1"]
    assert not s.observe(Observation("settle", full={"a"}, suggests="at_c_g1"))


@settings(max_examples=40, deadline=None)
@given(histories(), chains)
def test_symbolic_sets_equal_explicit_sets(history, chain):
    law, worlds, _, tracked, observations = history
    state = _state(tracked, observations)
    table = ValuationTable(ATOMS, worlds)
    space = world_space(ATOMS, law)
    pairs = [(knowledge_mask, knowledge_bdd), (belief_mask, belief_bdd)]
    primacy = {"revision": "primacy"}
    pairs.append((partial(belief_mask, **primacy), partial(belief_bdd, **primacy)))
    for explicit, symbolic in pairs:
        mask = explicit(state, chain, table)
        bdd = symbolic(state, chain, space)
        assert count(space, bdd) == int(mask.sum())
        for row, inside in zip(worlds, mask, strict=True):
            literals = [a if v else f"~{a}" for a, v in zip(ATOMS, row, strict=True)]
            point = space.truth(" & ".join(literals))
            assert (bdd & point).satisfiable() == inside


@settings(max_examples=40, deadline=None)
@given(histories(), group_formulas)
def test_the_group_model_and_the_group_structure_agree(history, formula):
    law, worlds, _, tracked, observations = history
    state = _state(tracked, observations)
    model = group_model(state, ValuationTable(ATOMS, worlds))
    structure = group_structure(state, world_space(ATOMS, law))
    assert model.holds(formula) == structure.holds(formula)


@settings(max_examples=100, deadline=None)
@given(histories(soft=False, awareness=False), group_formulas)
def test_with_hard_evidence_the_group_model_is_the_product_update(history, formula):
    """Every modality (K, B, Kw, E, C, D, EB, CB, nested and negated): the same verdicts as
    the product update of the observations' action models."""
    _, worlds, _, tracked, observations = history
    state = _state(tracked, observations)
    reference = _reference(worlds, observations)
    assert group_model(state, ValuationTable(ATOMS, worlds)).holds(formula) == reference.holds(
        formula
    )


@settings(max_examples=40, deadline=None)
@given(histories(), chains, facts)
def test_the_group_model_reads_pure_chains_as_the_sets(history, chain, fact):
    _, worlds, _, tracked, observations = history
    state = _state(tracked, observations)
    table = ValuationTable(ATOMS, worlds)
    model = group_model(state, table)
    on = truth(fact, worlds)
    # A prefix group with an empty belief (it learnt a fact it cannot conceive of) makes
    # the nested B vacuous: the chain's set answers only where every prefix believes.
    consistent = all(belief_mask(state, chain[:j], table).any() for j in range(1, len(chain)))
    for modality, mask in (("K", knowledge_mask), ("B", belief_mask)):
        if modality == "B" and not consistent:
            continue
        prefix = "".join(f"{modality}[{a}] " for a in chain)
        assert model.holds(f"{prefix}({fact})") == bool(on[mask(state, chain, table)].all())


def test_a_fact_the_group_cannot_conceive_of_leaves_it_an_inconsistent_belief():
    # Hypothesis found it: a, a partial observer, learns p but is not aware of p, so it
    # believes nothing (every B[a] formula holds), while a and b together keep the worlds
    # without p (b observed nothing).
    table = ValuationTable(["p"], np.array([[False], [True]]))
    state = EpistemicState(["a", "b"], tracked={"p"})
    state.observe(Observation("e", set(), {"a"}, pre="p"))
    assert not belief_mask(state, ("a",), table).any()
    assert belief_mask(state, ("a", "b"), table).tolist() == [True, False]
    model = group_model(state, table)
    assert model.holds("B[a] B[b] p") and model.holds("B[a] B[b] ~p")
    assert knowledge_mask(state, ("a",), table).tolist() == [False, True]


def test_bad_observations_are_refused():
    with pytest.raises(InvalidArgumentError, match="fact about the world"):
        Observation("x", {"a"}, pre="K[a] p")
    with pytest.raises(InvalidArgumentError, match="go together"):
        Observation("x", {"a"}, senses="p")
    state = EpistemicState(["a"])
    with pytest.raises(InvalidArgumentError, match="unknown agent"):
        state.observe(Observation("x", {"z"}, pre="p"))
    with pytest.raises(InvalidArgumentError, match="distinct"):
        EpistemicState(["a", "a"])
    assert as_formula("p") == Observation("x", {"a"}, pre="p").pre
