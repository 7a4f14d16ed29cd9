"""Withdrawn facts: an observation that withdraws a fact (an ontic change, a closed goal
reopened) voids the earlier hard evidence of it for the groups that observed it.

The reference is the product update of the history with the withdrawn evidence left out
(for a group that observed the withdrawal) or kept (for any other group).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from test_state import AGENTS, ALL, ATOMS, _reference, facts, truth

from epistemica.del_ import EpistemicState, InvalidArgumentError, Observation
from epistemica.del_.state.explicit import ValuationTable, knowledge_mask
from epistemica.del_.state.symbolic import count, knowledge_bdd, world_space

chains = st.lists(st.sampled_from(AGENTS), min_size=1, max_size=3)
groups = st.sets(st.sampled_from(AGENTS))


@st.composite
def pre_histories(draw):
    """An actual world and preconditions true there, one of them the fact to withdraw."""
    actual = ALL[draw(st.integers(0, len(ALL) - 1))]
    true_facts = facts.map(lambda f: f if truth(f, actual[None])[0] else ~f)
    withdrawn = draw(true_facts)
    observations = []
    for _ in range(draw(st.integers(0, 5))):
        fact = withdrawn if draw(st.booleans()) else draw(true_facts)
        observations.append(Observation("e", draw(groups), draw(groups), pre=fact))
    return observations, withdrawn


def _kept(observations, chain) -> np.ndarray:
    state = EpistemicState(AGENTS)
    for o in observations:
        state.observe(o)
    return knowledge_mask(state, chain, ValuationTable(ATOMS, ALL))


def _holds(model, chain, fact) -> bool:
    return model.holds("".join(f"K[{a}] " for a in chain) + f"({fact})")


@settings(max_examples=80, deadline=None)
@given(pre_histories(), groups, groups, chains, facts)
def test_a_withdrawal_voids_the_evidence_for_the_groups_that_observed_it(
    history, full, partial, chain, fact
):
    observations, withdrawn = history
    change = Observation("change", full, partial, withdraws=[withdrawn])
    kept = _kept([*observations, change], chain)
    if set(chain) <= full | partial:  # the group saw the change: the evidence is void
        reference = _reference(ALL, [o for o in observations if o.pre != withdrawn])
    else:  # some member is oblivious of it: the group keeps what it had
        reference = _reference(ALL, observations)
    for claim in (withdrawn, fact):
        assert _holds(reference, chain, claim) == bool(truth(claim)[kept].all())


@settings(max_examples=40, deadline=None)
@given(pre_histories(), chains, facts)
def test_evidence_after_the_withdrawal_binds_again(history, chain, fact):
    observations, withdrawn = history
    change = Observation("change", set(AGENTS), withdraws=[withdrawn])
    again = Observation("look", set(chain), pre=withdrawn)
    kept = _kept([*observations, change, again], chain)
    reference = _reference(ALL, [*(o for o in observations if o.pre != withdrawn), again])
    assert _holds(reference, chain, fact) == bool(truth(fact)[kept].all())
    assert bool(truth(withdrawn)[kept].all())


def test_a_repeat_after_a_withdrawal_is_news_and_before_it_is_not():
    state = EpistemicState(["a", "b"])
    seen = Observation("notice", full={"a"}, pre="~p")
    assert state.observe(seen)
    assert not state.observe(seen)  # nothing new
    assert state.observe(Observation("reopen", full={"a"}, withdraws=["~p"]))
    assert state.hard(("a",)) == ()
    assert state.observe(seen)  # closed again: news
    assert [str(f) for f in state.hard(("a",))] == ["~p"]


def test_the_symbolic_backend_reads_the_withdrawal_as_the_explicit_one():
    state = EpistemicState(["a", "b"])
    state.observe(Observation("notice", full={"a", "b"}, pre="~p & q"))
    state.observe(Observation("reopen", full={"a"}, withdraws=["~p & q"]))
    space = world_space(ATOMS)
    # a saw it reopen: all 8 valuations of p, q, r; b (and the group a, b) did not: the
    # 2 with p false and q true.
    for chain, expected in ((("a",), 8), (("b",), 2), (("a", "b"), 2)):
        assert int(knowledge_mask(state, chain, ValuationTable(ATOMS, ALL)).sum()) == expected
        assert count(space, knowledge_bdd(state, chain, space)) == expected


def test_withdraws_takes_a_sequence_of_facts():
    try:
        Observation("reopen", full={"a"}, withdraws="~p")
    except InvalidArgumentError as error:
        assert "sequence" in str(error)
    else:  # pragma: no cover - the check above must refuse it
        raise AssertionError("a bare formula was accepted")
